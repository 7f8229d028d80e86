//! Spectral path tracing of sand terrain under sun and sky.
//!
//! Every camera sample carries all render bands at once (one geometric path, a spectrum of
//! throughput): BRDF sampling uses a band-averaged pdf and the weight f(λ)·cos/pdf per band, which
//! is unbiased for each band. At each ground hit the radiance
//!
//!   L_o(ω_o) = ∫ f(ω_i, ω_o) L_i(ω_i) cos θ_i dω_i
//!
//! is estimated, depending on the estimator, with
//! - `Mis`: one sun sample (uniform in the solar cone), one sky sample (the sky's CDF) and one
//!   BRDF sample, each light combined with the BRDF sample by multiple importance sampling
//!   (Veach & Guibas 1995; power heuristic β = 2, or the balance heuristic);
//! - `Brdf`: the BRDF sample alone (sun found only when a sample falls in its disc);
//! - `Light`: the light samples alone.
//!
//! The BRDF sample is drawn by cosine (`BrdfSampling::Cosine`, the paper's choice) or by the
//! table-following sampler. A BRDF sample that meets the terrain continues the path (multiple
//! scattering between dunes) up to `max_bounces` ground interactions; 1 gives direct lighting,
//! exact for the flat plane. Camera rays that miss the terrain see the sky and the solar disc.
//! Shadow rays test visibility of the sampled light direction against the terrain.

use crate::math::Vec3;
use crate::render::brdf::{direction_from, pair_cosines, BrdfSampling, BrdfStack, Spectrum, MAX_BANDS};
use crate::render::camera::Camera;
use crate::render::environment::Environment;
use crate::render::terrain::{Hit, MaterialMap, Terrain};
use crate::rng::Rng;
use crate::sampling::cosine_hemisphere_angles;

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Estimator {
    Mis,
    Brdf,
    Light,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Heuristic {
    Power,
    Balance,
}

#[derive(Clone, Copy, Debug)]
pub struct Settings {
    pub estimator: Estimator,
    pub sampling: BrdfSampling,
    pub heuristic: Heuristic,
    pub max_bounces: u32,
}

/// Per-thread working spectra of `Scene::sample`.
pub struct Scratch {
    tmp: Spectrum,
    f: Spectrum,
    beta: Spectrum,
}

impl Default for Scratch {
    fn default() -> Self {
        Scratch { tmp: [0.0; MAX_BANDS], f: [0.0; MAX_BANDS], beta: [0.0; MAX_BANDS] }
    }
}

/// Everything a render needs; immutable and shared by all threads.
#[derive(Clone, Debug)]
pub struct Scene {
    pub camera: Camera,
    pub environment: Environment,
    pub brdf: BrdfStack,
    pub terrain: Terrain,
    pub material: MaterialMap,
    pub settings: Settings,
}

#[inline]
fn mis_weight(h: Heuristic, a: f64, b: f64) -> f64 {
    match h {
        Heuristic::Power => {
            let (a2, b2) = (a * a, b * b);
            if a2 + b2 > 0.0 {
                a2 / (a2 + b2)
            } else {
                0.0
            }
        }
        Heuristic::Balance => {
            if a + b > 0.0 {
                a / (a + b)
            } else {
                0.0
            }
        }
    }
}

impl Scene {
    #[inline]
    fn n_bands(&self) -> usize {
        self.brdf.n_bands()
    }

    /// Δφ from its cosine, skipped for angle-independent (Lambertian) tables, which ignore it.
    #[inline]
    fn azimuth(&self, cos_dphi: f64) -> f64 {
        if self.brdf.is_flat() {
            0.0
        } else {
            cos_dphi.acos()
        }
    }

    /// Solid-angle pdf of the BRDF sampler for light direction cosine μ_i, |Δφ|, view cosine μ_o.
    #[inline]
    fn brdf_pdf(&self, s: f64, mu_o: f64, mu_i: f64, dphi: f64) -> f64 {
        if mu_i <= 0.0 {
            return 0.0;
        }
        match self.settings.sampling {
            BrdfSampling::Cosine => mu_i / std::f64::consts::PI,
            BrdfSampling::Table => self.brdf.pdf_table(s, mu_o, mu_i, dphi),
        }
    }

    /// One camera sample through pixel (px, py): adds its radiance (W m⁻² sr⁻¹ nm⁻¹ per band)
    /// into `acc` and returns whether the camera ray met the ground.
    pub fn sample(&self, px: usize, py: usize, rng: &mut Rng, acc: &mut [f64], scratch: &mut Scratch) -> bool {
        let nb = self.n_bands();
        let env = &self.environment;
        let st = self.settings;
        let use_light = st.estimator != Estimator::Brdf;
        let use_brdf = st.estimator != Estimator::Light;
        // Buffers reused across samples (zeroing three spectra per sample showed in profiles);
        // `tmp` and `f` are overwritten by every lookup before they are read.
        let Scratch { tmp, f, beta } = scratch;
        beta[..nb].iter_mut().for_each(|v| *v = 1.0);

        let d = self.camera.ray(px, py, rng.uniform(), rng.uniform());
        let Some(first) = self.terrain.intersect(self.camera.origin, d, 0.0, false) else {
            env.sky(d, tmp);
            let sun = if env.in_sun(d) { 1.0 } else { 0.0 };
            for (a, (&sky, &l_sun)) in acc[..nb].iter_mut().zip(tmp.iter().zip(env.sun_radiance())) {
                *a += sky + sun * l_sun;
            }
            return false;
        };
        let mut hit: Hit = first;
        let mut dir_in = d;
        for bounce in 0..st.max_bounces {
            let n = hit.n;
            let wo = -dir_in;
            let mu_o = wo.dot(n);
            if mu_o <= 0.0 {
                break;
            }
            let s = self.material.level(hit.p.x, hit.p.y);
            let origin = hit.p + n * self.terrain.ray_offset(hit.p);

            if use_light {
                if env.sun_on() {
                    let wi = env.sample_sun(rng.uniform(), rng.uniform());
                    let (mu_i, _, cos_dphi) = pair_cosines(n, wi, wo);
                    if mu_i > 0.0 && self.terrain.intersect(origin, wi, 0.0, hit.far).is_none() {
                        let dphi = self.azimuth(cos_dphi);
                        self.brdf.eval(s, mu_i, mu_o, dphi, f);
                        let pl = env.pdf_sun();
                        let w = if use_brdf {
                            mis_weight(st.heuristic, pl, self.brdf_pdf(s, mu_o, mu_i, dphi))
                        } else {
                            1.0
                        };
                        let k = mu_i * w / pl;
                        for b in 0..nb {
                            acc[b] += beta[b] * f[b] * env.sun_radiance()[b] * k;
                        }
                    }
                }
                // With MIS the sky technique is compensated (environment docs): BRDF sampling
                // covers the sky dimmer than average.
                let (wi, pl, theta, phi) = env.sample_sky([rng.uniform(), rng.uniform(), rng.uniform()], use_brdf);
                let (mu_i, _, cos_dphi) = pair_cosines(n, wi, wo);
                if pl > 0.0 && mu_i > 0.0 && self.terrain.intersect(origin, wi, 0.0, hit.far).is_none() {
                    let dphi = self.azimuth(cos_dphi);
                    self.brdf.eval(s, mu_i, mu_o, dphi, f);
                    env.sky_at(theta, phi, tmp);
                    let w =
                        if use_brdf { mis_weight(st.heuristic, pl, self.brdf_pdf(s, mu_o, mu_i, dphi)) } else { 1.0 };
                    let k = mu_i * w / pl;
                    for b in 0..nb {
                        acc[b] += beta[b] * f[b] * tmp[b] * k;
                    }
                }
            }

            // The BRDF sample: needed for its own estimate or to continue the path.
            let last = bounce + 1 == st.max_bounces;
            if !use_brdf && last {
                break;
            }
            let (mu_i, dphi_signed) = match st.sampling {
                BrdfSampling::Cosine => cosine_hemisphere_angles([rng.uniform(), rng.uniform()]),
                BrdfSampling::Table => self.brdf.sample_table(
                    s,
                    mu_o,
                    [rng.uniform(), rng.uniform(), rng.uniform(), rng.uniform(), rng.uniform()],
                ),
            };
            if mu_i <= 0.0 {
                break;
            }
            let wi: Vec3 = direction_from(n, wo, mu_i, dphi_signed);
            let dphi = dphi_signed.abs().min(std::f64::consts::PI);
            let pb = self.brdf_pdf(s, mu_o, mu_i, dphi);
            if pb.is_nan() || pb <= 0.0 {
                break;
            }
            self.brdf.eval(s, mu_i, mu_o, dphi, f);
            let k = mu_i / pb;
            match self.terrain.intersect(origin, wi, 0.0, hit.far) {
                None => {
                    if use_brdf {
                        let p_sky = env.sky_and_pdf(wi, tmp, use_light);
                        let w_sky = if use_light { mis_weight(st.heuristic, pb, p_sky) } else { 1.0 };
                        let w_sun = if !env.in_sun(wi) {
                            0.0
                        } else if use_light {
                            mis_weight(st.heuristic, pb, env.pdf_sun())
                        } else {
                            1.0
                        };
                        for b in 0..nb {
                            acc[b] += beta[b] * f[b] * k * (tmp[b] * w_sky + env.sun_radiance()[b] * w_sun);
                        }
                    }
                    break;
                }
                Some(next) => {
                    if last {
                        break;
                    }
                    for b in 0..nb {
                        beta[b] *= f[b] * k;
                    }
                    hit = next;
                    dir_in = wi;
                }
            }
        }
        true
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::render::terrain::Heightfield;
    use std::f64::consts::PI;

    const ESTIMATORS: [(Estimator, Heuristic); 4] = [
        (Estimator::Mis, Heuristic::Power),
        (Estimator::Mis, Heuristic::Balance),
        (Estimator::Brdf, Heuristic::Power),
        (Estimator::Light, Heuristic::Power),
    ];

    /// A table constant in Δφ with f = f(band, μ_i, μ_o) on the nodes μ ∈ {0, 1} (order μ_i, μ_o,
    /// Δφ, band), which `eval` interpolates bilinearly in (μ_i, μ_o).
    fn table(f: impl Fn(usize, f64, f64) -> f64, n_bands: usize) -> BrdfStack {
        let mut v = Vec::new();
        for mu_i in [0.0, 1.0] {
            for mu_o in [0.0, 1.0] {
                for _dphi in [0.0, PI] {
                    v.extend((0..n_bands).map(|b| f(b, mu_i, mu_o) as f32));
                }
            }
        }
        BrdfStack::new(1, vec![0.0, 1.0], vec![0.0, 1.0], vec![0.0, PI], n_bands, v).unwrap()
    }

    /// A sky of 8 × 16 cells whose radiance in band b and azimuth column j is `radiance(b, j)`;
    /// the sun is off.
    fn sky(n_bands: usize, radiance: impl Fn(usize, usize) -> f64) -> Environment {
        let (n_t, n_p) = (8, 16);
        let mut r = Vec::new();
        for _it in 0..n_t {
            for ip in 0..n_p {
                r.extend((0..n_bands).map(|b| radiance(b, ip) as f32));
            }
        }
        Environment::new(n_t, n_p, n_bands, r, [0.0, 0.6, 0.8], 6.8e-5, &vec![0.0; n_bands]).unwrap()
    }

    fn camera(origin: [f64; 3], forward: [f64; 3]) -> Camera {
        Camera::new(origin, forward, [0.3, 0.0, 0.0], [0.0, 0.2, 0.2], 4, 3).unwrap()
    }

    fn scene(environment: Environment, brdf: BrdfStack, terrain: Terrain, settings: Settings) -> Scene {
        let camera = camera([0.0, 0.0, 2.0], [0.0, 1.0, -1.0]);
        Scene { camera, environment, brdf, terrain, material: MaterialMap::constant(0.0), settings }
    }

    /// Mean and standard error per band of (sample value − `expected`) over `spp` samples of
    /// every pixel. `expected(px, py, rng)` gets the sample's generator before the sample
    /// draws from it and writes the expected value per band.
    fn residuals(sc: &Scene, spp: u64, expected: impl Fn(usize, usize, &Rng, &mut [f64])) -> Vec<(f64, f64)> {
        let nb = sc.brdf.n_bands();
        let (mut m1, mut m2) = (vec![0.0; nb], vec![0.0; nb]);
        let (mut acc, mut want) = (vec![0.0; nb], vec![0.0; nb]);
        let mut scratch = Scratch::default();
        let (w, h) = (sc.camera.width, sc.camera.height);
        for p in 0..w * h {
            let (px, py) = (p % w, p / w);
            for k in 0..spp {
                let mut rng = Rng::for_ray(11, p as u64, k);
                expected(px, py, &rng, &mut want);
                acc.iter_mut().for_each(|v| *v = 0.0);
                assert!(sc.sample(px, py, &mut rng, &mut acc, &mut scratch), "the camera sees the ground only");
                for b in 0..nb {
                    let r = acc[b] - want[b];
                    m1[b] += r;
                    m2[b] += r * r;
                }
            }
        }
        let n = (w * h) as f64 * spp as f64;
        (0..nb).map(|b| (m1[b] / n, ((m2[b] / n - (m1[b] / n).powi(2)).max(0.0) / n).sqrt())).collect()
    }

    /// |mean residual| < 4 standard errors, plus a relative 1e-6 of `scale` for the f32 tables.
    fn assert_unbiased(res: &[(f64, f64)], scale: f64, what: &str) {
        for (b, &(mean, se)) in res.iter().enumerate() {
            assert!(mean.abs() < 4.0 * se + 1e-6 * scale, "{what}, band {b}: residual {mean} ± {se}");
        }
    }

    #[test]
    fn lambertian_plane_under_an_azimuthal_sky_returns_albedo_times_mean_radiance() {
        // L_o = (a/π) ∫ L cos θ dω. With L depending on φ only (piecewise linear and periodic
        // between column centres, so that its mean over φ is the mean of the columns),
        // ∫ L cos θ dω = π·mean(L), and L_o = a·mean(L) for every view. The bright side makes the
        // compensated sky technique of MIS draw samples (environment docs).
        let albedo = [0.2, 0.55, 0.9];
        let column = |j: usize| 0.3 + 2.0 * (2.0 * PI * (j as f64 + 0.5) / 16.0).cos().max(0.0);
        let radiance = |b: usize, j: usize| (0.5 + b as f64) * column(j);
        let mean_l: Vec<f64> = (0..3).map(|b| (0..16).map(|j| radiance(b, j)).sum::<f64>() / 16.0).collect();
        for (estimator, heuristic) in ESTIMATORS {
            for sampling in [BrdfSampling::Cosine, BrdfSampling::Table] {
                let settings = Settings { estimator, sampling, heuristic, max_bounces: 1 };
                let brdf = table(|b, _, _| albedo[b] / PI, 3);
                let sc = scene(sky(3, radiance), brdf, Terrain::Plane { z: 0.0 }, settings);
                let res = residuals(&sc, 400, |_, _, _, want| (0..3).for_each(|b| want[b] = albedo[b] * mean_l[b]));
                assert_unbiased(&res, 2.5, &format!("{estimator:?} {heuristic:?} {sampling:?}"));
            }
        }
    }

    #[test]
    fn an_angle_dependent_brdf_under_a_uniform_sky_returns_its_albedo() {
        // f = c_b (1 + 2μ_i + μ_o) (table sampling then follows the table, not the cosine). Under a
        // uniform sky L, L_o(μ_o) = L·2π ∫₀¹ f μ_i dμ_i = L·2π c_b [(1 + μ_o)/2 + 2/3], μ_o from the
        // sample's camera ray (its first two uniforms).
        let c = [0.05, 0.09];
        let l = 1.7;
        for (estimator, heuristic) in ESTIMATORS {
            for sampling in [BrdfSampling::Cosine, BrdfSampling::Table] {
                let settings = Settings { estimator, sampling, heuristic, max_bounces: 1 };
                let brdf = table(|b, mu_i, mu_o| c[b] * (1.0 + 2.0 * mu_i + mu_o), 2);
                let sc = scene(sky(2, |_, _| l), brdf, Terrain::Plane { z: 0.0 }, settings);
                assert!(!sc.brdf.is_flat());
                let res = residuals(&sc, 400, |px, py, rng, want| {
                    let mut r = rng.clone();
                    let mu_o = -sc.camera.ray(px, py, r.uniform(), r.uniform()).z;
                    (0..2).for_each(|b| want[b] = l * 2.0 * PI * c[b] * ((1.0 + mu_o) / 2.0 + 2.0 / 3.0));
                });
                assert_unbiased(&res, 1.7, &format!("{estimator:?} {heuristic:?} {sampling:?}"));
            }
        }
    }

    #[test]
    fn white_dunes_in_a_white_furnace_have_the_sky_radiance() {
        // A white Lambertian terrain under a uniform sky of radiance 1 has radiance 1 everywhere,
        // however it is shaped: light between the dunes comes back through the continued paths
        // (max_bounces), shadowed light samples are made up by MIS or by those paths. The slopes
        // (≤ 17°) make more than 16 bounces so rare that truncating there is far below the noise.
        let (n, dx) = (32usize, 0.5);
        let h: Vec<f32> = (0..n * n)
            .map(|k| {
                let (i, j) = ((k % n) as f64, (k / n) as f64);
                (0.4 * (2.0 * PI * 2.0 * i / n as f64).sin() * (2.0 * PI * 3.0 * j / n as f64).cos()) as f32
            })
            .collect();
        let hf = Heightfield::new(n, n, -8.0, -8.0, dx, dx, h, true, 0.0, 1e4).unwrap();
        for (estimator, heuristic) in ESTIMATORS {
            let settings = Settings { estimator, sampling: BrdfSampling::Table, heuristic, max_bounces: 16 };
            let mut sc = scene(
                sky(1, |_, _| 1.0),
                table(|_, _, _| 1.0 / PI, 1),
                Terrain::Heightfield(Box::new(hf.clone())),
                settings,
            );
            sc.camera = camera([0.3, -0.2, 3.0], [0.0, 0.5, -1.0]);
            let res = residuals(&sc, 300, |_, _, _, want| want[0] = 1.0);
            assert_unbiased(&res, 1.0, &format!("{estimator:?} {heuristic:?}"));
        }
    }

    #[test]
    fn a_plane_adds_nothing_by_longer_paths() {
        // A BRDF sample leaving a plane never meets it again: more bounces give the same image,
        // bit for bit (the extra BRDF sample of `Light` draws from a generator used no further).
        for (estimator, heuristic) in ESTIMATORS {
            let settings = |max_bounces| Settings { estimator, sampling: BrdfSampling::Table, heuristic, max_bounces };
            let brdf = table(|_, mu_i, mu_o| 0.1 + 0.1 * mu_i * mu_o, 1);
            let one = scene(sky(1, |_, j| 1.0 + j as f64), brdf.clone(), Terrain::Plane { z: 0.0 }, settings(1));
            let four = Scene { settings: settings(4), ..one.clone() };
            let (mut a, mut b) = (vec![0.0], vec![0.0]);
            let mut scratch = Scratch::default();
            for k in 0..2000 {
                one.sample(1, 2, &mut Rng::for_ray(3, 0, k), &mut a, &mut scratch);
                four.sample(1, 2, &mut Rng::for_ray(3, 0, k), &mut b, &mut scratch);
            }
            assert_eq!(a, b, "{estimator:?}");
            assert!(a[0] > 0.0);
        }
    }

    #[test]
    fn mis_weights_of_two_techniques_sum_to_one() {
        for h in [Heuristic::Power, Heuristic::Balance] {
            for (a, b) in [(1.0, 1.0), (0.3, 7.0), (1e-300, 2.0), (5.0, 0.0)] {
                assert!((mis_weight(h, a, b) + mis_weight(h, b, a) - 1.0).abs() < 1e-15, "{h:?} {a} {b}");
            }
            // A direction neither technique can draw gets no weight.
            assert_eq!(mis_weight(h, 0.0, 0.0), 0.0);
        }
        // Power heuristic β = 2 (Veach & Guibas 1995): a²/(a² + b²).
        assert_eq!(mis_weight(Heuristic::Power, 1.0, 3.0), 0.1);
        assert_eq!(mis_weight(Heuristic::Balance, 1.0, 3.0), 0.25);
    }
}

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

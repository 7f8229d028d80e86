//! The light of the scene: a sky texture over the upper hemisphere and the sun as a small disc.
//!
//! **Sky.** Spectral radiance (W m⁻² sr⁻¹ nm⁻¹) on a latitude–longitude grid of the upper
//! hemisphere, precomputed by the caller (from `sandlight.sky.PreethamSky`): n_θ rows of equal
//! zenith-angle width over [0, π/2], n_φ columns over φ ∈ [0, 2π) with φ = atan2(y, x) (x east,
//! y north, z up), values at cell centres. Lookup is bilinear between cell centres (periodic in
//! φ, clamped in θ). Directions below the horizon never reach the sky here: the terrain continues
//! to infinity (see `terrain`), so the sky is defined on the upper hemisphere only; a query below
//! the horizon is given the horizon row.
//!
//! **Sky sampling.** One discrete distribution over all cells, weight = (band-mean radiance +
//! 10⁻³ of its mean over the sky) × cell solid angle × (cos θ_c + 0.05): the cosine of flat ground,
//! floored so that grazing directions (which tilted terrain faces see) keep some probability; the
//! radiance floor keeps the pdf positive everywhere. Within a cell, directions are uniform in
//! solid angle, so pdf(ω) = P(cell)/Ω(cell) exactly.
//!
//! **Compensated sky sampling for MIS** (Karlík et al. 2019, "MIS compensation"). Combined with
//! BRDF sampling, the sky technique only needs to find what BRDF sampling misses: sky brighter
//! than average. Its cell weights are max(0, L̄_c − ⟨L̄⟩) × Ω_c × (cos θ_c + 0.05), ⟨L̄⟩ the
//! solid-angle mean of the band-mean radiance; a uniform sky has none, and MIS then takes the
//! sky from BRDF sampling alone (the sky technique draws nothing: pdf 0). Cells dimmer than
//! average get no sky samples; BRDF sampling, whose pdf is positive wherever the BRDF is, covers
//! them alone. Without this a nearly perfect BRDF sampler loses to MIS: on saturated sand seen
//! at grazing angles the mirror peak carries most of the reflection, sky samples land in the dim
//! diffuse part and take the weight of the BRDF samples there, and the estimate becomes an
//! on/off variable. The light-only estimator keeps the full distribution, positive everywhere.
//!
//! **Sun.** A uniform disc of spectral radiance L☉(λ) and solid angle Ω☉ around the direction
//! `sun`, sampled uniformly in its cone (pdf 1/Ω☉); a zero radiance disables it.

use std::f64::consts::PI;

use crate::error::SandlightError;
use crate::math::{floor_i64, Vec3};
use crate::render::brdf::{Spectrum, MAX_BANDS};
use crate::sampling::{uniform_cone, AliasTable};

#[derive(Clone, Debug)]
pub struct Environment {
    n_theta: usize,
    n_phi: usize,
    n_bands: usize,
    /// radiance[(it·n_φ + ip)·n_bands + b]
    radiance: Vec<f32>,
    /// The sky's sampling distribution over the cells, for light sampling alone.
    full: CellDistribution,
    /// The compensated distribution, for MIS with BRDF sampling (None: nothing brighter than average).
    compensated: Option<CellDistribution>,
    /// cos θ at the n_θ + 1 row edges.
    row_cos: Vec<f64>,
    sun: Vec3,
    sun_cos_half_angle: f64,
    sun_solid_angle: f64,
    sun_radiance: Spectrum,
    sun_on: bool,
}

impl Environment {
    /// `radiance` has n_theta·n_phi·n_bands values (row-major θ, φ, band); `sun_dir` need not be
    /// normalised; `sun_solid_angle_sr` in (0, 2π).
    pub fn new(
        n_theta: usize,
        n_phi: usize,
        n_bands: usize,
        radiance: Vec<f32>,
        sun_dir: [f64; 3],
        sun_solid_angle_sr: f64,
        sun_radiance: &[f64],
    ) -> Result<Self, SandlightError> {
        if n_theta < 2 || n_phi < 4 {
            return Err(SandlightError::parameter(
                "sky grid",
                format!("{n_theta} × {n_phi}"),
                "at least 2 zenith rows and 4 azimuth columns",
            ));
        }
        if n_bands == 0 || n_bands > MAX_BANDS {
            return Err(SandlightError::parameter("n_bands", n_bands, &format!("between 1 and {MAX_BANDS}")));
        }
        if radiance.len() != n_theta * n_phi * n_bands {
            return Err(SandlightError::parameter(
                "sky radiance",
                format!("{} values", radiance.len()),
                &format!("{} values (n_theta × n_phi × bands)", n_theta * n_phi * n_bands),
            ));
        }
        if let Some(bad) = radiance.iter().find(|v| !v.is_finite() || **v < 0.0) {
            return Err(SandlightError::parameter("sky radiance", bad, "finite values ≥ 0"));
        }
        if sun_radiance.len() != n_bands || sun_radiance.iter().any(|v| !v.is_finite() || *v < 0.0) {
            return Err(SandlightError::parameter(
                "sun radiance",
                format!("{sun_radiance:?}"),
                &format!("{n_bands} finite values ≥ 0"),
            ));
        }
        if !(sun_solid_angle_sr > 0.0 && sun_solid_angle_sr < 2.0 * PI) {
            return Err(SandlightError::parameter("sun_solid_angle_sr", sun_solid_angle_sr, "in (0, 2π)"));
        }
        let s = Vec3::new(sun_dir[0], sun_dir[1], sun_dir[2]);
        if !s.is_finite() || s.norm2() < 1e-24 {
            return Err(SandlightError::parameter("sun_direction", format!("{sun_dir:?}"), "a finite non-zero vector"));
        }
        let n_cells = n_theta * n_phi;
        let dth = 0.5 * PI / n_theta as f64;
        let dph = 2.0 * PI / n_phi as f64;
        let means: Vec<f64> = (0..n_cells)
            .map(|c| radiance[c * n_bands..(c + 1) * n_bands].iter().map(|&v| v as f64).sum::<f64>() / n_bands as f64)
            .collect();
        let mut omega_total = 0.0;
        let mut mean_sky = 0.0;
        for it in 0..n_theta {
            let omega = dph * ((it as f64 * dth).cos() - ((it + 1) as f64 * dth).cos());
            for ip in 0..n_phi {
                mean_sky += means[it * n_phi + ip] * omega;
                omega_total += omega;
            }
        }
        mean_sky /= omega_total;
        let floor = 1e-3 * mean_sky.max(1e-30);
        let mut weights = vec![0.0; n_cells];
        let mut omegas = vec![0.0; n_cells];
        for it in 0..n_theta {
            let (c0, c1) = ((it as f64 * dth).cos(), ((it + 1) as f64 * dth).cos());
            let omega = dph * (c0 - c1);
            let cos_centre = ((it as f64 + 0.5) * dth).cos();
            for ip in 0..n_phi {
                let c = it * n_phi + ip;
                weights[c] = (means[c] + floor) * omega * (cos_centre + 0.05);
                omegas[c] = omega;
            }
        }
        let full = CellDistribution::new(&weights, &omegas);
        // Compensation: radiance above its solid-angle mean (relative threshold: rounding of a
        // uniform sky must not leave a few cells with all the probability).
        let mut excess = vec![0.0; n_cells];
        for it in 0..n_theta {
            let cos_centre = ((it as f64 + 0.5) * dth).cos();
            for ip in 0..n_phi {
                let c = it * n_phi + ip;
                let above = means[c] - mean_sky;
                if above > 1e-6 * mean_sky {
                    excess[c] = above * omegas[c] * (cos_centre + 0.05);
                }
            }
        }
        let compensated = (excess.iter().sum::<f64>() > 0.0).then(|| CellDistribution::new(&excess, &omegas));
        let mut sun_rad = [0.0; MAX_BANDS];
        sun_rad[..n_bands].copy_from_slice(sun_radiance);
        // Cone of solid angle Ω: 1 − cos α = Ω / 2π.
        let one_minus_cos = sun_solid_angle_sr / (2.0 * PI);
        Ok(Environment {
            n_theta,
            n_phi,
            n_bands,
            radiance,
            full,
            compensated,
            row_cos: (0..=n_theta).map(|k| (k as f64 * dth).cos()).collect(),
            sun: s.normalized(),
            sun_cos_half_angle: 1.0 - one_minus_cos,
            sun_solid_angle: sun_solid_angle_sr,
            sun_radiance: sun_rad,
            sun_on: sun_radiance.iter().any(|&v| v > 0.0),
        })
    }

    pub fn n_bands(&self) -> usize {
        self.n_bands
    }

    #[inline]
    fn angles(d: Vec3) -> (f64, f64) {
        let theta = d.z.clamp(0.0, 1.0).acos();
        let mut phi = d.y.atan2(d.x);
        if phi < 0.0 {
            phi += 2.0 * PI;
        }
        (theta, phi)
    }

    /// Sky radiance at zenith angle θ and azimuth φ (radians), written into `out[..n_bands]`.
    pub fn sky_at(&self, theta: f64, phi: f64, out: &mut Spectrum) {
        let nb = self.n_bands;
        let x = (theta / (0.5 * PI) * self.n_theta as f64 - 0.5).clamp(0.0, (self.n_theta - 1) as f64);
        let i0 = (x as usize).min(self.n_theta - 2); // x ≥ 0: truncation is the floor
        let tx = x - i0 as f64;
        let y = phi / (2.0 * PI) * self.n_phi as f64 - 0.5;
        let yf = floor_i64(y);
        let ty = y - yf as f64;
        // φ ∈ [0, 2π) puts y in [−0.5, n_φ − 0.5): only the first column wraps (no division).
        let j0 = if yf < 0 { self.n_phi - 1 } else { (yf as usize).min(self.n_phi - 1) };
        let j1 = if j0 + 1 == self.n_phi { 0 } else { j0 + 1 };
        out[..nb].iter_mut().for_each(|v| *v = 0.0);
        for (i, wi) in [(i0, 1.0 - tx), (i0 + 1, tx)] {
            for (j, wj) in [(j0, 1.0 - ty), (j1, ty)] {
                let w = wi * wj;
                let idx = (i * self.n_phi + j) * nb;
                for (acc, &v) in out[..nb].iter_mut().zip(&self.radiance[idx..idx + nb]) {
                    *acc += w * v as f64;
                }
            }
        }
    }

    /// Sky radiance in direction `d` (unit), written into `out[..n_bands]`.
    pub fn sky(&self, d: Vec3, out: &mut Spectrum) {
        let (theta, phi) = Self::angles(d);
        self.sky_at(theta, phi, out);
    }

    #[inline]
    fn distribution(&self, compensated: bool) -> Option<&CellDistribution> {
        if compensated {
            self.compensated.as_ref()
        } else {
            Some(&self.full)
        }
    }

    /// Sky radiance in direction `d` into `out`, and the pdf of `sample_sky(_, compensated)` for it.
    pub fn sky_and_pdf(&self, d: Vec3, out: &mut Spectrum, compensated: bool) -> f64 {
        let (theta, phi) = Self::angles(d);
        self.sky_at(theta, phi, out);
        if d.z <= 0.0 {
            0.0
        } else {
            self.density_at(theta, phi, compensated)
        }
    }

    #[inline]
    fn density_at(&self, theta: f64, phi: f64, compensated: bool) -> f64 {
        let it = ((theta / (0.5 * PI) * self.n_theta as f64) as usize).min(self.n_theta - 1);
        let ip = ((phi / (2.0 * PI) * self.n_phi as f64) as usize).min(self.n_phi - 1);
        self.distribution(compensated).map_or(0.0, |dist| dist.density[it * self.n_phi + ip])
    }

    /// A sky direction, its solid-angle pdf and its angles (θ, φ) for `sky_at`, from three
    /// uniforms: a cell from the alias table of the full or the compensated distribution, then a
    /// point uniform in solid angle in the cell (cos θ and φ uniform). A pdf of 0: the
    /// compensated technique draws nothing (uniform sky).
    pub fn sample_sky(&self, u: [f64; 3], compensated: bool) -> (Vec3, f64, f64, f64) {
        let Some(dist) = self.distribution(compensated) else {
            return (Vec3::new(0.0, 0.0, 1.0), 0.0, 0.0, 0.0);
        };
        let c = dist.cells.sample(u[0]);
        let (it, ip) = (c / self.n_phi, c % self.n_phi);
        let dph = 2.0 * PI / self.n_phi as f64;
        let (c0, c1) = (self.row_cos[it], self.row_cos[it + 1]);
        let cos_t = c0 + u[1] * (c1 - c0);
        let sin_t = (1.0 - cos_t * cos_t).max(0.0).sqrt();
        let phi = (ip as f64 + u[2]) * dph;
        let (sp, cp) = phi.sin_cos();
        (Vec3::new(sin_t * cp, sin_t * sp, cos_t), dist.density[c], cos_t.clamp(-1.0, 1.0).acos(), phi)
    }

    /// Solid-angle pdf of `sample_sky(_, compensated)` for direction `d` (0 below the horizon).
    pub fn pdf_sky(&self, d: Vec3, compensated: bool) -> f64 {
        if d.z <= 0.0 {
            return 0.0;
        }
        let (theta, phi) = Self::angles(d);
        self.density_at(theta, phi, compensated)
    }

    pub fn sun_on(&self) -> bool {
        self.sun_on
    }

    pub fn sun_radiance(&self) -> &Spectrum {
        &self.sun_radiance
    }

    /// Whether `d` (unit) falls inside the solar disc.
    #[inline]
    pub fn in_sun(&self, d: Vec3) -> bool {
        self.sun_on && d.dot(self.sun) >= self.sun_cos_half_angle
    }

    /// Solid-angle pdf of `sample_sun` (uniform in the cone).
    #[inline]
    pub fn pdf_sun(&self) -> f64 {
        1.0 / self.sun_solid_angle
    }

    /// A direction uniform in the solar cone, from two uniforms.
    pub fn sample_sun(&self, u1: f64, u2: f64) -> Vec3 {
        // A cone of solid angle Ω has 1 − cos α = Ω / 2π.
        uniform_cone(self.sun, self.sun_solid_angle / (2.0 * PI), [u1, u2])
    }
}

/// A discrete distribution over the sky cells, sampled with an alias table (O(1)).
#[derive(Clone, Debug)]
struct CellDistribution {
    cells: AliasTable,
    /// P(cell) / Ω(cell)
    density: Vec<f64>,
}

impl CellDistribution {
    /// From non-negative cell weights (positive sum) and the cells' solid angles.
    fn new(weights: &[f64], omegas: &[f64]) -> Self {
        let total: f64 = weights.iter().sum();
        let probabilities: Vec<f64> = weights.iter().map(|w| w / total).collect();
        let density = probabilities.iter().zip(omegas).map(|(p, o)| p / o).collect();
        CellDistribution { cells: AliasTable::new(&probabilities), density }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::rng::Rng;

    fn sky(n_t: usize, n_p: usize, f: impl Fn(f64, f64) -> f64) -> Environment {
        let mut r = Vec::new();
        for it in 0..n_t {
            let th = (it as f64 + 0.5) * 0.5 * PI / n_t as f64;
            for ip in 0..n_p {
                let ph = (ip as f64 + 0.5) * 2.0 * PI / n_p as f64;
                r.push(f(th, ph) as f32);
            }
        }
        Environment::new(n_t, n_p, 1, r, [0.3, 0.0, 0.5], 6.8e-5, &[1.0]).unwrap()
    }

    #[test]
    fn sky_sampling_pdf_is_consistent() {
        // E[g/pdf] = ∫ g dω over the support of the pdf, for g = cos θ, under a strongly
        // non-uniform sky: the whole hemisphere (π) for the full distribution, the cells brighter
        // than average for the compensated one.
        let env = sky(24, 48, |th, ph| 1.0 + 20.0 * (-(th - 1.0).powi(2) * 8.0 - (ph - 2.0).powi(2)).exp());
        for compensated in [false, true] {
            let mut rng = Rng::for_ray(1, 2, 3);
            let n = 400_000;
            let mut est = 0.0;
            for _ in 0..n {
                let (d, pdf, theta, phi) = env.sample_sky([rng.uniform(), rng.uniform(), rng.uniform()], compensated);
                assert!(pdf > 0.0 && (env.pdf_sky(d, compensated) - pdf).abs() <= 1e-9 * pdf);
                assert!((theta - d.z.acos()).abs() < 1e-9 && (phi - d.y.atan2(d.x).rem_euclid(2.0 * PI)).abs() < 1e-9);
                est += d.z / pdf;
            }
            est /= n as f64;
            let (m, k) = (480, 960);
            let (mut quad, mut support) = (0.0, 0.0);
            for a in 0..m {
                let th = (a as f64 + 0.5) * 0.5 * PI / m as f64;
                for b in 0..k {
                    let ph = (b as f64 + 0.5) * 2.0 * PI / k as f64;
                    let d = Vec3::new(th.sin() * ph.cos(), th.sin() * ph.sin(), th.cos());
                    let domega = th.sin() * (0.5 * PI / m as f64) * (2.0 * PI / k as f64);
                    if env.pdf_sky(d, compensated) > 0.0 {
                        quad += d.z * domega;
                        support += domega;
                    }
                }
            }
            assert!((est - quad).abs() < 0.01 * quad, "compensated {compensated}: {est} vs {quad}");
            if compensated {
                // Only the bright spot and the cells near the zenith are left (weights ∝ cos θ + 0.05).
                assert!(support < 0.6 * 2.0 * PI, "{support}");
            } else {
                assert!((quad - PI).abs() < 1e-3);
            }
        }
    }

    #[test]
    fn a_uniform_sky_leaves_mis_to_brdf_sampling() {
        // Nothing is brighter than average: the compensated technique draws nothing (pdf 0
        // everywhere), while the full distribution stays positive for light-only sampling.
        let env = sky(8, 16, |_, _| 2.5);
        let (_, pdf, _, _) = env.sample_sky([0.3, 0.6, 0.2], true);
        assert_eq!(pdf, 0.0);
        assert_eq!(env.pdf_sky(Vec3::new(0.2, 0.1, 0.9).normalized(), true), 0.0);
        assert!(env.pdf_sky(Vec3::new(0.2, 0.1, 0.9).normalized(), false) > 0.0);
    }

    #[test]
    fn bilinear_lookup_reproduces_a_constant_and_cell_centres() {
        let env = sky(8, 16, |th, _| th);
        let mut out = [0.0; MAX_BANDS];
        let th = 2.5 * 0.5 * PI / 8.0;
        let ph = 3.5 * 2.0 * PI / 16.0;
        env.sky(Vec3::new(th.sin() * ph.cos(), th.sin() * ph.sin(), th.cos()), &mut out);
        assert!((out[0] - th).abs() < 1e-6);
    }

    #[test]
    fn sun_samples_stay_in_the_cone() {
        let env = sky(4, 8, |_, _| 1.0);
        let mut rng = Rng::for_ray(0, 0, 0);
        for _ in 0..1000 {
            let d = env.sample_sun(rng.uniform(), rng.uniform());
            assert!(env.in_sun(d) || (d.dot(env.sun) - env.sun_cos_half_angle).abs() < 1e-12);
        }
    }
}

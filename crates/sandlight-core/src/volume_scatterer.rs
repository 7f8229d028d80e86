//! A population of wave-optics particles (Lorenz–Mie) traced as volume scatterers in the pore
//! space, with a majorant cross-section (docs/model.md §2.4 item 8, docs/transport.md "Fine
//! particles as volume scatterers").
//!
//! A particle type of a `Particulate` may be a volume scatterer. The tracers still meet it at the
//! geometric rate of its projected area πD²/4 (§2.1–2.2) times a wavelength-independent majorant
//! Q_max ≥ Q̄_ext at every wavelength, so the free-path law and the type choice do not depend on
//! the wavelength. At such a meeting the ray has a real collision with probability
//! Q̄_ext/Q_max (else a null collision: it goes straight on), and a real collision scatters with
//! probability ω = Q̄_sca/Q̄_ext, in a direction from the population's phase function, or absorbs.
//! This is delta tracking (Woodcock et al. 1965): the real collisions occur at the Mie rate
//! n C̄_ext = n Q̄_ext πD²/4 exactly. The Mie quantities (size-averaged over the population's
//! sizes, relative to air or to the water of a water-filled pore) come from Python
//! (`sandlight.physics.fine_particles`).

use crate::error::{check_range, SandlightError};
use crate::math::Vec3;
use crate::phase_table::PhaseTable;

/// What a ray does at a meeting with a volume scatterer.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum VolumeFate {
    /// Null collision: the ray goes on unchanged.
    Null,
    Scatter,
    Absorb,
}

/// A volume-scattering population's optics in one pore medium at one wavelength.
#[derive(Clone, Debug)]
pub struct VolumeOptics {
    /// Probability of a real collision at a meeting, Q̄_ext/Q_max, in [0, 1].
    pub extinction: f64,
    /// Single-scattering albedo ω = Q̄_sca/Q̄_ext, in [0, 1].
    pub albedo: f64,
    /// The (size-averaged) phase function, sampled exactly as tabulated.
    pub phase: PhaseTable,
}

impl VolumeOptics {
    pub fn new(extinction: f64, albedo: f64, phase: PhaseTable) -> Result<VolumeOptics, SandlightError> {
        check_range("extinction", extinction, 0.0, 1.0)?;
        check_range("albedo", albedo, 0.0, 1.0)?;
        Ok(VolumeOptics { extinction, albedo, phase })
    }

    /// The fate for a uniform `u` in [0, 1): scatter below a·ω, absorb below a, null above.
    #[inline]
    pub fn fate(&self, u: f64) -> VolumeFate {
        if u >= self.extinction {
            VolumeFate::Null
        } else if u < self.extinction * self.albedo {
            VolumeFate::Scatter
        } else {
            VolumeFate::Absorb
        }
    }

    /// Probability of `fate` at a meeting.
    #[inline]
    pub fn probability(&self, fate: VolumeFate) -> f64 {
        match fate {
            VolumeFate::Null => 1.0 - self.extinction,
            VolumeFate::Scatter => self.extinction * self.albedo,
            VolumeFate::Absorb => self.extinction * (1.0 - self.albedo),
        }
    }
}

/// A particle type traced as a volume scatterer: its majorant efficiency and its optics relative
/// to air and, when pores can be water-filled, to water.
#[derive(Clone, Debug)]
pub struct VolumeScatterer {
    /// Q_max: the type meets rays at its geometric rate times this (≥ Q̄_ext at every wavelength
    /// of a run; the same for all of them).
    pub majorant: f64,
    pub air: VolumeOptics,
    /// None when no pore is water-filled.
    pub water: Option<VolumeOptics>,
}

impl VolumeScatterer {
    pub fn new(majorant: f64, air: VolumeOptics, water: Option<VolumeOptics>) -> Result<Self, SandlightError> {
        check_range("majorant", majorant, 1e-9, 1e6)?;
        Ok(VolumeScatterer { majorant, air, water })
    }

    /// The optics in the pore the ray is in (water-filled or not; a medium with water-filled
    /// pores has the water optics: `Particulate::with_volume_scatterers` checks it).
    #[inline]
    pub fn optics(&self, water: bool) -> &VolumeOptics {
        match (water, &self.water) {
            (true, Some(w)) => w,
            _ => &self.air,
        }
    }
}

/// The direction `d` (unit) turned by the scattering angle of cosine `mu`, at azimuth 2πu
/// about `d`.
#[inline]
pub fn scattered(d: Vec3, mu: f64, u: f64) -> Vec3 {
    let sin = (1.0 - mu * mu).max(0.0).sqrt();
    let (sphi, cphi) = (2.0 * std::f64::consts::PI * u).sin_cos();
    let (a, b) = d.orthonormal_basis();
    (a * (sin * cphi) + b * (sin * sphi) + d * mu).renormalized()
}

/// Volume scatterers for the tests of the tracers.
#[cfg(test)]
pub(crate) mod testing {
    use super::*;

    /// Optics of extinction probability `extinction`, albedo `albedo` and a Henyey–Greenstein
    /// phase function of asymmetry `g` (0: isotropic), tabulated at 401 nodes.
    pub(crate) fn henyey_greenstein(extinction: f64, albedo: f64, g: f64) -> VolumeOptics {
        let mu: Vec<f64> = (0..=400).map(|i| -1.0 + i as f64 / 200.0).collect();
        let p = mu.iter().map(|m| (1.0 - g * g) / (1.0 + g * g - 2.0 * g * m).powf(1.5)).collect();
        VolumeOptics::new(extinction, albedo, PhaseTable::new(mu, p).unwrap()).unwrap()
    }

    /// A scatterer of majorant `majorant` with the same optics in air and water.
    pub(crate) fn scatterer(majorant: f64, optics: VolumeOptics) -> VolumeScatterer {
        VolumeScatterer::new(majorant, optics.clone(), Some(optics)).unwrap()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::rng::Rng;

    fn isotropic() -> PhaseTable {
        PhaseTable::new(vec![-1.0, 1.0], vec![1.0, 1.0]).unwrap()
    }

    #[test]
    fn fates_have_their_probabilities() {
        let o = VolumeOptics::new(0.6, 0.25, isotropic()).unwrap();
        let n = 200_000;
        let mut rng = Rng::for_ray(1, 0, 0);
        let mut counts = [0usize; 3];
        for _ in 0..n {
            counts[o.fate(rng.uniform()) as usize] += 1;
        }
        for (fate, c) in [VolumeFate::Null, VolumeFate::Scatter, VolumeFate::Absorb].into_iter().zip(counts) {
            let p = o.probability(fate);
            let se = (p * (1.0 - p) / n as f64).sqrt();
            assert!((c as f64 / n as f64 - p).abs() < 4.0 * se, "{fate:?}: {c} vs {p}");
        }
        let sum: f64 =
            [VolumeFate::Null, VolumeFate::Scatter, VolumeFate::Absorb].map(|f| o.probability(f)).iter().sum();
        assert!((sum - 1.0).abs() < 1e-15);
    }

    #[test]
    fn scattered_directions_have_the_cosine_and_a_uniform_azimuth() {
        let d = Vec3::new(0.3, -0.4, -(1.0f64 - 0.25).sqrt());
        let (a, _) = d.orthonormal_basis();
        let n = 100_000;
        let mut rng = Rng::for_ray(2, 0, 0);
        let mut mean_cos_phi = 0.0;
        for _ in 0..n {
            let mu = 2.0 * rng.uniform() - 1.0;
            let out = scattered(d, mu, rng.uniform());
            assert!((out.norm2() - 1.0).abs() < 1e-12);
            assert!((out.dot(d) - mu).abs() < 1e-12);
            let sin = (1.0 - mu * mu).sqrt();
            if sin > 1e-3 {
                mean_cos_phi += out.dot(a) / sin;
            }
        }
        // E[cos φ] = 0, standard deviation 1/√2 per draw.
        assert!((mean_cos_phi / n as f64).abs() < 4.0 * (0.5 / n as f64).sqrt());
    }

    #[test]
    fn out_of_range_values_are_refused_by_name() {
        assert!(VolumeOptics::new(1.2, 0.5, isotropic()).unwrap_err().to_string().contains("extinction"));
        assert!(VolumeOptics::new(0.5, -0.1, isotropic()).unwrap_err().to_string().contains("albedo"));
        let air = VolumeOptics::new(0.5, 0.5, isotropic()).unwrap();
        assert!(VolumeScatterer::new(0.0, air, None).unwrap_err().to_string().contains("majorant"));
    }
}

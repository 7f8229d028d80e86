//! The media a ray can be traced through: sand (particles generated on the fly), and two
//! reference media with exact answers used to verify the transport (isotropic point scatterers,
//! a Lambertian surface).

use crate::error::{check_range, SandlightError};
use crate::particle::{Coating, ParticleOptics, PoreOptics, Stacks};
use crate::sampling::pick_cumulative;
use crate::sizes::QuantileTable;
use crate::volume_scatterer::VolumeScatterer;

/// One kind of particle in a sand sample.
#[derive(Clone, Debug)]
pub struct ParticleType {
    /// Probability that the next particle a ray meets is of this type (surface-area weighted,
    /// docs/model.md §2.2). Normalised by `Particulate::new`.
    pub probability: f64,
    /// Sizes (volume-equivalent diameter, mm) of the particles of this type that a ray meets.
    pub sizes: QuantileTable,
    /// Prolate spheroid aspect ratio ε = c/a ≥ 1.
    pub aspect_ratio: f64,
    pub optics: ParticleOptics,
}

impl ParticleType {
    /// Equatorial semi-axis over diameter, a/d (precomputed by `Particulate::new`).
    #[inline]
    pub fn a_over_d(&self) -> f64 {
        crate::spheroid::equatorial_ratio(self.aspect_ratio)
    }
}

/// Sand: a half-space (or slab) of randomly packed particles, generated on the fly.
///
/// Per-type tables (cumulative probabilities, a/d, layer stacks) are derived from `types` and
/// `pore` by `new`; treat the public fields as read-only afterwards.
#[derive(Clone, Debug)]
pub struct Particulate {
    pub types: Vec<ParticleType>,
    cumulative: Vec<f64>,
    a_over_d: Vec<f64>,
    stacks: Vec<Stacks>,
    /// Mean free path in the pore space (mm), docs/model.md §2.1: between geometric meetings,
    /// what the path memories' tables describe.
    pub mean_free_path_mm: f64,
    /// Mean flight between candidate meetings (mm): `mean_free_path_mm`, shortened by the
    /// majorants of volume scatterers (`with_volume_scatterers`).
    pub flight_mean_free_path_mm: f64,
    pub pore: PoreOptics,
    /// Sample thickness (mm); infinite for a semi-infinite sample.
    pub depth_mm: f64,
    /// Per type, its volume-scatterer optics; empty when no type is one.
    volume: Vec<Option<VolumeScatterer>>,
}

impl Particulate {
    pub fn new(
        types: Vec<ParticleType>,
        mean_free_path_mm: f64,
        pore: PoreOptics,
        depth_mm: f64,
    ) -> Result<Particulate, SandlightError> {
        if types.is_empty() {
            return Err(SandlightError::parameter("particle_types", 0, "at least one particle type"));
        }
        check_range("mean_free_path_mm", mean_free_path_mm, 1e-9, 1e9)?;
        check_range("water_n", pore.water_n, 1.0, 10.0)?;
        check_range("water_alpha_per_mm", pore.water_alpha_per_mm, 0.0, 1e12)?;
        check_range("film_thickness_mm", pore.film_thickness_mm, 0.0, 10.0)?;
        check_range("film_coverage", pore.film_coverage, 0.0, 1.0)?;
        check_range("water_filled_probability", pore.water_filled_probability, 0.0, 1.0)?;
        if depth_mm.is_nan() || depth_mm <= 0.0 {
            return Err(SandlightError::parameter(
                "depth_mm",
                depth_mm,
                "must be > 0 (inf for a semi-infinite sample)",
            ));
        }
        let mut total = 0.0;
        for (i, t) in types.iter().enumerate() {
            let name = |s: &str| format!("particle_types[{i}].{s}");
            check_range(&name("probability"), t.probability, 0.0, 1e12)?;
            check_range(&name("aspect_ratio"), t.aspect_ratio, 1.0, 20.0)?;
            check_range(&name("core_n"), t.optics.core_n, 1.0, 10.0)?;
            check_range(&name("core_k"), t.optics.core_k, 0.0, 100.0)?;
            check_range(&name("core_alpha_per_mm"), t.optics.core_alpha_per_mm, 0.0, 1e12)?;
            if let Some(Coating { n, alpha_per_mm, thickness_mm, scattering_per_mm, asymmetry, coverage }) =
                t.optics.coating
            {
                check_range(&name("coating_n"), n, 1.0, 10.0)?;
                check_range(&name("coating_alpha_per_mm"), alpha_per_mm, 0.0, 1e12)?;
                check_range(&name("coating_thickness_mm"), thickness_mm, 0.0, 10.0)?;
                check_range(&name("coating_scattering_per_mm"), scattering_per_mm, 0.0, 1e12)?;
                check_range(&name("coating_asymmetry"), asymmetry, -0.99, 0.99)?;
                check_range(&name("coating_coverage"), coverage, 0.0, 1.0)?;
            }
            total += t.probability;
        }
        if total.is_nan() || total <= 0.0 {
            return Err(SandlightError::parameter(
                "particle_types.probability",
                total,
                "probabilities must sum to > 0",
            ));
        }
        let mut acc = 0.0;
        let cumulative = types
            .iter()
            .map(|t| {
                acc += t.probability / total;
                acc
            })
            .collect();
        let a_over_d = types.iter().map(ParticleType::a_over_d).collect();
        let stacks = types.iter().map(|t| Stacks::tabulated(&t.optics, &pore)).collect();
        Ok(Particulate {
            types,
            cumulative,
            a_over_d,
            stacks,
            mean_free_path_mm,
            flight_mean_free_path_mm: mean_free_path_mm,
            pore,
            depth_mm,
            volume: Vec::new(),
        })
    }

    /// This medium with the types given a `Some` traced as volume scatterers (docs/transport.md,
    /// "Fine particles as volume scatterers"): type i is met at its geometric rate times its
    /// majorant Q_max, so the flights shorten to ℓ Σ Pᵢ / Σ Pᵢ fᵢ (fᵢ = Q_max of a volume
    /// scatterer, 1 otherwise) and the type is drawn with probability ∝ Pᵢ fᵢ; at a meeting the
    /// scatterer decides null, scatter or absorb (`VolumeScatterer`). One entry per type.
    pub fn with_volume_scatterers(mut self, volume: Vec<Option<VolumeScatterer>>) -> Result<Self, SandlightError> {
        if volume.len() != self.types.len() {
            return Err(SandlightError::parameter(
                "volume_scatterers",
                format!("length {}", volume.len()),
                &format!("one entry per particle type ({})", self.types.len()),
            ));
        }
        if self.pore.water_filled_probability > 0.0 && volume.iter().flatten().any(|v| v.water.is_none()) {
            return Err(SandlightError::parameter(
                "volume_scatterers",
                "no optics relative to water",
                "optics relative to water when pores can be water-filled",
            ));
        }
        let factor = |i: usize| volume[i].as_ref().map_or(1.0, |v| v.majorant);
        let total: f64 = self.types.iter().map(|t| t.probability).sum();
        let weighted: f64 = self.types.iter().enumerate().map(|(i, t)| t.probability * factor(i)).sum();
        let mut acc = 0.0;
        self.cumulative = (0..self.types.len())
            .map(|i| {
                acc += self.types[i].probability * factor(i) / weighted;
                acc
            })
            .collect();
        self.flight_mean_free_path_mm = self.mean_free_path_mm * total / weighted;
        self.volume = volume;
        Ok(self)
    }

    /// The volume-scatterer optics of type `i`; None for a particle traced in geometric optics.
    #[inline]
    pub fn volume_scatterer(&self, i: usize) -> Option<&VolumeScatterer> {
        self.volume.get(i).and_then(Option::as_ref)
    }

    /// Whether any type is a volume scatterer.
    pub fn has_volume_scatterers(&self) -> bool {
        self.volume.iter().any(Option::is_some)
    }

    /// Index of the type of the next particle, for a uniform `u` in [0, 1).
    #[inline]
    pub fn pick_index(&self, u: f64) -> usize {
        pick_cumulative(&self.cumulative, u)
    }

    /// a/d and layer stacks of type `i` (as returned by `pick_index`).
    #[inline]
    pub fn type_tables(&self, i: usize) -> (f64, &Stacks) {
        (self.a_over_d[i], &self.stacks[i])
    }
}

/// Isotropic point scatterers of single-scattering albedo ω with exponential free paths of unit
/// mean, under a transparent plane boundary: Chandrasekhar's half-space (docs/model.md §2.7).
#[derive(Clone, Copy, Debug)]
pub struct IsotropicScatterers {
    pub albedo: f64,
    /// Optical thickness of the slab; infinite for a half-space.
    pub depth: f64,
}

impl IsotropicScatterers {
    pub fn new(albedo: f64, depth: f64) -> Result<Self, SandlightError> {
        check_range("albedo", albedo, 0.0, 1.0)?;
        if depth.is_nan() || depth <= 0.0 {
            return Err(SandlightError::parameter("depth", depth, "must be > 0 (inf for a half-space)"));
        }
        Ok(IsotropicScatterers { albedo, depth })
    }
}

/// An ideal diffuse (Lambertian) surface of albedo a: f = a/π. A test object for tallies.
#[derive(Clone, Copy, Debug)]
pub struct LambertianSurface {
    pub albedo: f64,
}

impl LambertianSurface {
    pub fn new(albedo: f64) -> Result<Self, SandlightError> {
        check_range("albedo", albedo, 0.0, 1.0)?;
        Ok(LambertianSurface { albedo })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::rng::Rng;

    #[test]
    fn pick_index_is_the_first_cumulative_above_u() {
        // Including a type of zero probability and u exactly on a boundary.
        let t = |p: f64| ParticleType {
            probability: p,
            sizes: QuantileTable::constant(0.1),
            aspect_ratio: 1.0,
            optics: ParticleOptics::clear(1.5),
        };
        let m = Particulate::new(vec![t(0.25), t(0.0), t(0.5), t(0.25)], 0.1, PoreOptics::DRY, f64::INFINITY).unwrap();
        let mut rng = Rng::for_ray(1, 0, 0);
        let mut counts = [0usize; 4];
        for u in (0..100_000).map(|_| rng.uniform()).chain([0.0, 0.25, 0.75, f64::from_bits(1.0f64.to_bits() - 1)]) {
            let i = m.pick_index(u);
            let expect = m.cumulative.iter().position(|&c| u < c).unwrap_or(3);
            assert_eq!(i, expect, "u {u}");
            counts[i] += 1;
        }
        assert_eq!(counts[1], 0);
        assert_eq!(m.pick_index(0.25), 2);
    }
}

//! The grain populations of a sand sample as they fill its volume, derived from how the rays
//! meet them: what the explicit packing (`packing`) packs and what the cut-plane surface layer
//! of path memory (`surface_layer`) thins (docs/geometry.md).
//!
//! The populations of a `Particulate` are given as the rays meet them (encounter
//! probabilities Pᵢ ∝ vᵢ⟨S⟩ᵢ/⟨V⟩ᵢ and area-weighted size tables p_enc ∝ p_n D²,
//! docs/model.md §2.2). Inverting those relations gives what fills the volume:
//! number fractions Nᵢ ∝ Pᵢ E_enc,ᵢ[D⁻²]/f(εᵢ), number size distributions p_n ∝ p_enc D⁻²,
//! volume fractions vᵢ ∝ Pᵢ E_enc,ᵢ[D]/f(εᵢ), and the specific surface of the solids
//! S/V = 6 / Σᵢ Pᵢ E_enc,ᵢ[D]/f(εᵢ), where f(ε) is the spheroid's surface over that of the
//! sphere of equal volume (`spheroid::surface_factor`). The sample's porosity follows from its
//! mean free path, ℓ = 4φ/[(1 − φ) S/V] (§2.1), so a packing of these populations is that of
//! the very medium the on-the-fly engine traces.
//!
//! Fines. Populations whose area-weighted median size is below `fines_below_mm` (silt, clay,
//! pigment particles) are not packed: a clay particle of 1 µm among 0.25 mm grains would need
//! ~10¹⁰ particles per mm³. They stay on the fly inside the pores of the packed grains
//! (`explicit`); the packed grains fill (1 − φ)·v_coarse of the volume.

use crate::medium::Particulate;
use crate::rng::Rng;
use crate::sampling::pick_cumulative;
use crate::spheroid::surface_factor;

/// Populations whose area-weighted median size (mm) is below this are fines, not packed.
pub const FINES_BELOW_MM: f64 = 0.05;

/// Levels used to integrate over a size table (stratified, u = (k + ½)/M).
const SIZE_LEVELS: usize = 4096;

/// What the volume holds, per particle type, derived from a `Particulate` (module docs).
#[derive(Clone, Debug)]
pub struct Populations {
    /// Sample porosity φ implied by the mean free path.
    pub porosity: f64,
    /// Volume fraction of the solids per type (sums to 1).
    pub volume_fraction: Vec<f64>,
    /// Whether the type is packed (false: fines, kept on the fly).
    pub packed: Vec<bool>,
    /// Number-weighted size table per type: sizes at stratified levels with cumulative weights.
    number_sizes: Vec<(Vec<f64>, Vec<f64>)>,
    /// Indices of the packed types and the cumulative distribution of their numbers,
    /// Nᵢ ∝ vᵢ/⟨V⟩ₙ,ᵢ.
    packed_types: Vec<usize>,
    number_cumulative: Vec<f64>,
}

impl Populations {
    pub fn of(medium: &Particulate, fines_below_mm: f64) -> Populations {
        let total_p: f64 = medium.types.iter().map(|t| t.probability).sum();
        let mut volume = Vec::new();
        let mut number_sizes: Vec<(Vec<f64>, Vec<f64>)> = Vec::new();
        let mut packed = Vec::new();
        for t in &medium.types {
            let p = t.probability / total_p;
            let sizes: Vec<f64> =
                (0..SIZE_LEVELS).map(|k| t.sizes.quantile((k as f64 + 0.5) / SIZE_LEVELS as f64)).collect();
            let mean_d = sizes.iter().sum::<f64>() / SIZE_LEVELS as f64;
            // p_n ∝ p_enc D⁻²: cumulative number weights over the stratified encounter sizes.
            let mut acc = 0.0;
            let cum: Vec<f64> = sizes
                .iter()
                .map(|d| {
                    acc += 1.0 / (d * d);
                    acc
                })
                .collect();
            let cum = cum.iter().map(|c| c / acc).collect();
            volume.push(p * mean_d / surface_factor(t.aspect_ratio));
            packed.push(t.sizes.quantile(0.5) >= fines_below_mm);
            number_sizes.push((sizes, cum));
        }
        let sum_v: f64 = volume.iter().sum();
        // S/V = 6 / Σ Pᵢ E_enc[D]/f; φ/(1 − φ) = ℓ (S/V)/4.
        let x = medium.mean_free_path_mm * (6.0 / sum_v) / 4.0;
        let volume_fraction: Vec<f64> = volume.iter().map(|v| v / sum_v).collect();
        // Number fractions of the packed types: Nᵢ ∝ vᵢ/⟨V⟩ₙ,ᵢ.
        let mean_volume = |i: usize| {
            let (sizes, cum) = &number_sizes[i];
            let mut prev = 0.0;
            sizes
                .iter()
                .zip(cum)
                .map(|(d, c)| {
                    let w = c - prev;
                    prev = *c;
                    w * d * d * d
                })
                .sum::<f64>()
                * std::f64::consts::PI
                / 6.0
        };
        let packed_types: Vec<usize> = (0..packed.len()).filter(|&i| packed[i]).collect();
        let weights: Vec<f64> = packed_types.iter().map(|&i| volume_fraction[i] / mean_volume(i)).collect();
        let wsum: f64 = weights.iter().sum();
        let mut acc = 0.0;
        let number_cumulative = weights
            .iter()
            .map(|w| {
                acc += w / wsum;
                acc
            })
            .collect();
        Populations { porosity: x / (1.0 + x), volume_fraction, packed, number_sizes, packed_types, number_cumulative }
    }

    /// Fraction of the total volume filled by the packed types: (1 − φ) Σ_packed vᵢ.
    pub fn packed_fraction(&self) -> f64 {
        (1.0 - self.porosity)
            * self.volume_fraction.iter().zip(&self.packed).filter(|(_, &p)| p).map(|(v, _)| v).sum::<f64>()
    }

    /// A size drawn from the number distribution of type `i`.
    fn sample_number_size(&self, i: usize, u: f64) -> f64 {
        let (sizes, cum) = &self.number_sizes[i];
        sizes[cum.partition_point(|&c| c <= u).min(sizes.len() - 1)]
    }

    /// A packed grain drawn by number: its type index (Nᵢ) and volume-equivalent diameter (mm)
    /// from the number distribution of the type. Needs at least one packed type.
    pub fn draw_by_number(&self, rng: &mut Rng) -> (usize, f64) {
        let i = self.packed_types[pick_cumulative(&self.number_cumulative, rng.uniform())];
        (i, self.sample_number_size(i, rng.uniform()))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::medium::ParticleType;
    use crate::particle::{ParticleOptics, PoreOptics};
    use crate::sizes::QuantileTable;

    fn sand(types: &[(f64, QuantileTable, f64)], ell_mm: f64) -> Particulate {
        let optics = ParticleOptics::clear(1.544);
        let types = types
            .iter()
            .map(|(p, sizes, eps)| ParticleType { probability: *p, sizes: sizes.clone(), aspect_ratio: *eps, optics })
            .collect();
        Particulate::new(types, ell_mm, PoreOptics::DRY, f64::INFINITY).unwrap()
    }

    #[test]
    fn populations_recover_porosity() {
        for (eps, phi) in [(1.0, 0.4), (1.4, 0.35)] {
            // ℓ = 4φ/[(1 − φ) 6 f(ε)/d] (docs/model.md §2.1).
            let ell = 4.0 * phi / ((1.0 - phi) * 6.0 * surface_factor(eps) / 0.25);
            let p = Populations::of(&sand(&[(1.0, QuantileTable::constant(0.25), eps)], ell), 0.05);
            assert!((p.porosity - phi).abs() < 1e-12);
            assert!((p.packed_fraction() - (1.0 - phi)).abs() < 1e-12);
        }
    }

    #[test]
    fn grains_are_drawn_in_their_number_fractions() {
        // Two packed sphere types met equally often (P = ½ each), of constant sizes d₁ = 0.2 and
        // d₂ = 0.4 mm, and clay fines. Encounters go as N d², so by number N₁/N₂ = (d₂/d₁)² = 4;
        // by volume v₁/v₂ = N₁d₁³/(N₂d₂³) = ½; the fines are never drawn.
        let m = sand(
            &[
                (0.4, QuantileTable::constant(0.2), 1.0),
                (0.4, QuantileTable::constant(0.4), 1.0),
                (0.2, QuantileTable::constant(0.002), 1.0),
            ],
            0.1,
        );
        let p = Populations::of(&m, FINES_BELOW_MM);
        assert_eq!(p.packed, [true, true, false]);
        assert!((p.volume_fraction[0] / p.volume_fraction[1] - 0.5).abs() < 1e-12);
        let mut rng = Rng::for_ray(3, 0, 0);
        let n = 100_000;
        let mut counts = [0usize; 3];
        for _ in 0..n {
            let (i, d) = p.draw_by_number(&mut rng);
            assert_eq!(d, [0.2, 0.4, 0.002][i]);
            counts[i] += 1;
        }
        assert_eq!(counts[2], 0);
        let p1 = 0.8;
        let se = (p1 * (1.0 - p1) / n as f64).sqrt();
        assert!((counts[0] as f64 / n as f64 - p1).abs() < 4.0 * se, "{counts:?}");
    }
}

//! The top layer of a sample cut through a plane of grain centres, for the on-the-fly engine's
//! `Memory::Cut` (docs/geometry.md, "Near-surface path memory").
//!
//! With centres uniform below z = 0, a packed grain of radius r met at height z exists only if
//! its centre is below the plane; its solids fill the fraction F(z) = w²(3 − 2w),
//! w = (r − z)/(2r) ∈ [0, 1], of their bulk share at height z (the volume of a sphere above
//! z − c, averaged over centres c < 0). The space not taken by packed grains is then
//! φ_c(z) = 1 − η_c F̄(z) (η_c their bulk packing fraction, F̄ averaged by volume over the packed
//! sizes), and the rate of meeting grains per unit length of that space scales as
//! φ_c,bulk/φ_c(z) ≤ 1 besides the centre rule. Fines (types not packed) fill the pores below the
//! plane only.
//!
//! Above the plane most grains the bulk rate would offer cannot reach down to it: a grain whose
//! largest semi-axis b is below the height z has its centre above the plane wherever it is hit.
//! Flights there are drawn against a majorant that leaves those out, constant over each of
//! `BINS` slices of height (the rate falls with z, so its value at a slice's floor bounds the
//! slice), and candidates are thinned to the rate at their own height.

use crate::medium::{ParticleType, Particulate};
use crate::populations::{Populations, FINES_BELOW_MM};
use crate::rng::Rng;
use crate::sampling::pick_cumulative;

#[derive(Clone, Debug)]
pub struct SurfaceLayer {
    /// Height where rays start and escape: the top of the largest packed grain (mm).
    pub top_mm: f64,
    /// Whether each type is packed (the others are fines).
    pub packed: Vec<bool>,
    /// η_c, the bulk volume fraction of the packed grains.
    pub packed_fraction: f64,
    /// φ_c,bulk/φ_c(z) at z = −top + 2 top·j/(N − 1).
    keep: Vec<f64>,
    /// The slices of height above the plane, bottom first.
    slices: Vec<Slice>,
    /// Λ at the slice floors and the top: Σ of rate × slice height below (per mm of height).
    hazard: Vec<f64>,
    /// For Λ = Λ_top·m/LOOKUP, the slice it falls in: where the search for a Λ starts.
    lookup: Vec<usize>,
}

/// The majorant of the rate of packed grains that can reach below the plane, at the floor z_j
/// of one slice of height above it.
#[derive(Clone, Debug)]
struct Slice {
    /// (1/ℓ) φ_c,bulk/φ_c(z_j) Σᵢ Pᵢ Gᵢ(z_j) per mm of path, Gᵢ(z) = P(bᵢ(D) > z) over the sizes
    /// a ray meets.
    rate_per_mm: f64,
    /// φ_c,bulk/φ_c(z_j).
    keep: f64,
    /// Cumulative probabilities of the types, ∝ Pᵢ Gᵢ(z_j) (fines: no increment).
    cumulative: Vec<f64>,
    /// Per type, the level of the size table below which b(D) ≤ z_j.
    level: Vec<f64>,
}

impl SurfaceLayer {
    const N: usize = 513;
    const BINS: usize = 64;
    const LOOKUP: usize = 256;

    pub fn of(m: &Particulate) -> SurfaceLayer {
        let pops = Populations::of(m, FINES_BELOW_MM);
        let eta = pops.packed_fraction();
        // Volume-weighted radii of the packed types (within a type p_vol ∝ p_enc D), at
        // stratified levels of the encounter size table.
        let levels = 256;
        let mut radii = Vec::new();
        let mut top = 0.0f64;
        for (i, t) in m.types.iter().enumerate().filter(|(i, _)| pops.packed[*i]) {
            let ds: Vec<f64> = (0..levels).map(|k| t.sizes.quantile((k as f64 + 0.5) / levels as f64)).collect();
            let sum_d: f64 = ds.iter().sum();
            for d in ds {
                radii.push((0.5 * d, pops.volume_fraction[i] * d / sum_d));
            }
            top = top.max(0.5 * t.sizes.quantile(0.999) * t.aspect_ratio.powf(2.0 / 3.0));
        }
        let wsum: f64 = radii.iter().map(|r| r.1).sum();
        let keep = (0..Self::N)
            .map(|j| {
                let z = -top + 2.0 * top * j as f64 / (Self::N - 1) as f64;
                let f: f64 = radii
                    .iter()
                    .map(|&(r, w)| {
                        let u = ((r - z) / (2.0 * r)).clamp(0.0, 1.0);
                        w * u * u * (3.0 - 2.0 * u)
                    })
                    .sum::<f64>()
                    / wsum;
                (1.0 - eta) / (1.0 - eta * f)
            })
            .collect();
        let mut layer = SurfaceLayer {
            top_mm: top,
            packed: pops.packed,
            packed_fraction: eta,
            keep,
            slices: Vec::new(),
            hazard: Vec::new(),
            lookup: Vec::new(),
        };
        layer.slices = (0..Self::BINS).map(|j| layer.slice(m, j as f64 * top / Self::BINS as f64)).collect();
        let h = top / Self::BINS as f64;
        layer.hazard = std::iter::once(0.0)
            .chain(layer.slices.iter().scan(0.0, |acc, s| {
                *acc += s.rate_per_mm * h;
                Some(*acc)
            }))
            .collect();
        let total = layer.hazard[Self::BINS];
        layer.lookup = (0..Self::LOOKUP)
            .map(|m| layer.hazard.partition_point(|&v| v <= total * m as f64 / Self::LOOKUP as f64).max(1) - 1)
            .collect();
        layer
    }

    fn slice(&self, m: &Particulate, z: f64) -> Slice {
        let total: f64 = m.types.iter().map(|t| t.probability).sum();
        let level: Vec<f64> = m
            .types
            .iter()
            .zip(&self.packed)
            .map(|(t, &p)| {
                // b(D) = max(a, c) = (a/d)·max(1, ε)·D: the largest semi-axis, ≥ the half height.
                if p {
                    t.sizes.level(z / (t.a_over_d() * t.aspect_ratio.max(1.0)))
                } else {
                    1.0
                }
            })
            .collect();
        let mut acc = 0.0;
        let mut cumulative: Vec<f64> = m
            .types
            .iter()
            .zip(&level)
            .map(|(t, l)| {
                acc += t.probability / total * (1.0 - l);
                acc
            })
            .collect();
        cumulative.iter_mut().for_each(|c| *c /= acc);
        let keep = self.keep(z);
        Slice { rate_per_mm: keep * acc / m.mean_free_path_mm, keep, cumulative, level }
    }

    /// φ_c,bulk/φ_c(z): 1 below the layer, linear interpolation in the table.
    #[inline]
    pub fn keep(&self, z: f64) -> f64 {
        let x = (z + self.top_mm) / (2.0 * self.top_mm) * (Self::N - 1) as f64;
        if x <= 0.0 {
            return 1.0;
        }
        let j = (x as usize).min(Self::N - 2);
        let f = (x - j as f64).min(1.0);
        self.keep[j] + f * (self.keep[j + 1] - self.keep[j])
    }

    #[inline]
    fn slice_index(&self, z: f64) -> usize {
        ((z / self.top_mm * Self::BINS as f64) as usize).min(Self::BINS - 1)
    }

    /// A flight from height `z` in (0, top] with vertical direction cosine `dz`, for the
    /// exponential variate `e`: the path length to the next candidate. Going down past the
    /// plane the flight goes on at the bulk rate 1/ℓ (`ell_mm`); going up past the top, the
    /// length is infinite.
    ///
    /// Exact for the piecewise-constant rate: with Λ(z) = ∫₀ᶻ rate dz′ (tabulated at the slice
    /// floors), a flight of vertical extent from z to z′ uses up the hazard |Λ(z′) − Λ(z)|/|dz|.
    pub fn flight(&self, z: f64, dz: f64, e: f64, ell_mm: f64) -> f64 {
        let j = self.slice_index(z);
        if dz == 0.0 {
            return e / self.slices[j].rate_per_mm;
        }
        let h = self.top_mm / Self::BINS as f64;
        let here = self.hazard[j] + self.slices[j].rate_per_mm * (z - j as f64 * h);
        let target = here + e * dz;
        if target <= 0.0 {
            // Through the plane, then at the bulk rate with the hazard left over.
            return z / -dz + (e + here / dz) * ell_mm;
        }
        if target >= self.hazard[Self::BINS] {
            return f64::INFINITY;
        }
        // The slice where Λ reaches the target: Λ(floor) ≤ target < Λ(ceiling), so its rate is > 0.
        let total = self.hazard[Self::BINS];
        let mut k = self.lookup[((target / total * Self::LOOKUP as f64) as usize).min(Self::LOOKUP - 1)];
        while self.hazard[k + 1] <= target {
            k += 1;
        }
        let z_end = k as f64 * h + (target - self.hazard[k]) / self.slices[k].rate_per_mm;
        (z_end - z) / dz
    }

    /// A candidate grain met at height `z` > 0 on a flight from `flight`: its type and
    /// volume-equivalent diameter, or None if thinning discards it. The caller still applies
    /// the centre rule with the grain's own shape and hit point.
    pub fn candidate_above_plane(&self, types: &[ParticleType], z: f64, rng: &mut Rng) -> Option<(usize, f64)> {
        let slice = &self.slices[self.slice_index(z)];
        if rng.uniform() >= self.keep(z) / slice.keep {
            return None;
        }
        let i = pick_cumulative(&slice.cumulative, rng.uniform());
        // Grains that cannot reach the slice floor are left out of the majorant: draw the
        // size from the rest of the table.
        let lo = slice.level[i];
        Some((i, types[i].sizes.quantile(lo + rng.uniform() * (1.0 - lo))))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::particle::{ParticleOptics, PoreOptics};
    use crate::sizes::QuantileTable;

    fn sand_with_fines() -> Particulate {
        let optics = ParticleOptics::clear(1.544);
        let sand = ParticleType {
            probability: 0.4,
            sizes: QuantileTable::new((0..65).map(|j| 0.15 + 0.3 * j as f64 / 64.0).collect()).unwrap(),
            aspect_ratio: 1.4,
            optics,
        };
        let clay = ParticleType { probability: 0.6, sizes: QuantileTable::constant(0.002), aspect_ratio: 1.0, optics };
        Particulate::new(vec![sand, clay], 0.05, PoreOptics::DRY, f64::INFINITY).unwrap()
    }

    #[test]
    fn majorant_bounds_the_rate_and_falls_with_height() {
        let m = sand_with_fines();
        let layer = SurfaceLayer::of(&m);
        let packed_rate = 0.4 / m.mean_free_path_mm;
        for (j, s) in layer.slices.iter().enumerate() {
            assert!(s.rate_per_mm <= packed_rate * (1.0 + 1e-12) && s.rate_per_mm > 0.0);
            assert_eq!(*s.cumulative.last().unwrap(), 1.0);
            assert_eq!(s.cumulative[0], 1.0, "fines are never drawn above the plane");
            if j > 0 {
                assert!(s.rate_per_mm <= layer.slices[j - 1].rate_per_mm);
            }
            // Thinning probability keep(z)/keep(z_j) ≤ 1 over the whole slice.
            let h = layer.top_mm / SurfaceLayer::BINS as f64;
            for k in 0..=10 {
                assert!(layer.keep((j as f64 + k as f64 / 10.0) * h) <= s.keep * (1.0 + 1e-12));
            }
        }
    }

    #[test]
    fn flights_have_the_piecewise_constant_hazard() {
        // Going down from the top, the probability of passing the plane without a candidate is
        // exp(−Σ rate_j h/|dz|), and below it the flight goes on at the bulk rate: the
        // probability of passing a depth δ below the plane too is that times exp(−δ/(ℓ|dz|)).
        let m = sand_with_fines();
        let layer = SurfaceLayer::of(&m);
        let ell = m.mean_free_path_mm;
        let h = layer.top_mm / SurfaceLayer::BINS as f64;
        let (dz, delta) = (-0.6, 0.02);
        let hazard: f64 = layer.slices.iter().map(|s| s.rate_per_mm * h / -dz).sum();
        let mut rng = Rng::for_ray(5, 0, 0);
        let n = 200_000;
        let to_plane = layer.top_mm / -dz;
        let (mut past_plane, mut past_delta) = (0usize, 0usize);
        for _ in 0..n {
            let s = layer.flight(layer.top_mm, dz, rng.exponential(), ell);
            assert!(s >= 0.0 && s.is_finite());
            past_plane += (s > to_plane) as usize;
            past_delta += (s > to_plane + delta / -dz) as usize;
        }
        for (count, p) in [(past_plane, (-hazard).exp()), (past_delta, (-hazard - delta / (ell * -dz)).exp())] {
            let se = (p * (1.0 - p) / n as f64).sqrt();
            assert!((count as f64 / n as f64 - p).abs() < 4.0 * se, "{count} vs {p}");
        }
        // Going up from just above the plane, the flight leaves at the top with probability
        // exp(−Σ rate_j h/dz), and otherwise ends inside the layer.
        let up = 0.5;
        let mut left = 0usize;
        for _ in 0..n {
            let s = layer.flight(1e-12, up, rng.exponential(), ell);
            left += s.is_infinite() as usize;
            assert!(s.is_infinite() || (s >= 0.0 && 1e-12 + s * up <= layer.top_mm * (1.0 + 1e-12)));
        }
        let p = (-hazard * -dz / up).exp();
        let se = (p * (1.0 - p) / n as f64).sqrt();
        assert!((left as f64 / n as f64 - p).abs() < 4.0 * se, "{left} vs {p}");
    }
}

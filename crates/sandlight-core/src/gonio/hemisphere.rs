//! Collector hemisphere with patches of equal solid angle (paper §3.2.1; docs/model.md §3).
//!
//! With `stacks` polar stacks and `slices` azimuthal slices the hemisphere holds
//! r = 1 + (stacks − 1)·slices patches of solid angle 2π/r each. Because dΩ = dz dφ with
//! z = cos θ, equal solid angle means equal area in the (z, φ) rectangle [0, 1] × [0, 2π):
//!
//! - patch 0 is the top cap, z ∈ [1 − 1/r, 1], undivided in azimuth;
//! - band k = 1, …, stacks − 1 (from the top down) spans z ∈ [(stacks − k − 1)·slices/r,
//!   (stacks − k)·slices/r], a height of slices/r;
//! - each band is cut into `slices` equal azimuth slices φ ∈ [2πs/slices, 2π(s + 1)/slices),
//!   s = 0, …, slices − 1, and patch 1 + (k − 1)·slices + s is slice s of band k.
//!
//! Intervals are half-open at the top in z and at the end in φ: a direction exactly on an edge
//! belongs to the patch above it in z and to the slice that starts at its azimuth.
//! The paper's 31 stacks × 30 slices give r = 901.

use std::f64::consts::PI;

use crate::error::SandlightError;

/// Largest admissible number of stacks (keeps r below 10⁸ and the band height far above the
/// f64 resolution of cos θ).
pub const MAX_STACKS: usize = 10_000;
/// Largest admissible number of slices.
pub const MAX_SLICES: usize = 10_000;

/// The edges of one patch in the equal-area coordinates (z = cos θ, φ).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PatchBounds {
    /// Lower edge in cos θ.
    pub z0: f64,
    /// Upper edge in cos θ (1 for the cap).
    pub z1: f64,
    /// Start azimuth φ0 in radians, in [0, 2π).
    pub phi0: f64,
    /// End azimuth φ1 in radians, in (0, 2π]; the patch holds φ0 ≤ φ < φ1.
    pub phi1: f64,
}

/// A hemisphere of directions (z ≥ 0) divided into patches of equal solid angle.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct CollectorHemisphere {
    stacks: usize,
    slices: usize,
}

impl CollectorHemisphere {
    /// A hemisphere of `stacks` polar stacks (the top one is the undivided cap) and `slices`
    /// azimuthal slices per band.
    ///
    /// # Errors
    /// `SandlightError::Parameter` unless 2 ≤ stacks ≤ [`MAX_STACKS`] and
    /// 1 ≤ slices ≤ [`MAX_SLICES`].
    pub fn new(stacks: usize, slices: usize) -> Result<Self, SandlightError> {
        if !(2..=MAX_STACKS).contains(&stacks) {
            return Err(SandlightError::parameter(
                "stacks",
                stacks,
                &format!("must be an integer in [2, {MAX_STACKS}] (the top stack is the undivided cap)"),
            ));
        }
        if !(1..=MAX_SLICES).contains(&slices) {
            return Err(SandlightError::parameter(
                "slices",
                slices,
                &format!("must be an integer in [1, {MAX_SLICES}]"),
            ));
        }
        Ok(CollectorHemisphere { stacks, slices })
    }

    /// The paper's hemisphere: 31 stacks × 30 slices, 901 patches.
    pub fn paper() -> Self {
        CollectorHemisphere { stacks: 31, slices: 30 }
    }

    pub fn stacks(&self) -> usize {
        self.stacks
    }

    pub fn slices(&self) -> usize {
        self.slices
    }

    /// Number of bands below the cap, stacks − 1.
    pub fn n_bands(&self) -> usize {
        self.stacks - 1
    }

    /// Number of patches r = 1 + (stacks − 1)·slices.
    pub fn n_patches(&self) -> usize {
        1 + (self.stacks - 1) * self.slices
    }

    /// Band and slice of patch `i`: (0, 0) for the cap, else (k, s) with band k in
    /// 1..=stacks − 1 counted from the top and slice s in 0..slices.
    ///
    /// # Panics
    /// If `i >= n_patches()` (a caller bug, like an out-of-range slice index).
    pub fn band_slice(&self, i: usize) -> (usize, usize) {
        assert!(i < self.n_patches(), "patch index {i} out of range 0..{}", self.n_patches());
        if i == 0 {
            (0, 0)
        } else {
            (1 + (i - 1) / self.slices, (i - 1) % self.slices)
        }
    }

    /// Patch index of slice `slice` of band `band` (band 0 is the cap, whose only slice is 0).
    ///
    /// # Panics
    /// If band > stacks − 1, or slice ≥ slices, or band = 0 with slice ≠ 0 (caller bugs).
    pub fn patch_of(&self, band: usize, slice: usize) -> usize {
        assert!(band < self.stacks, "band {band} out of range 0..{}", self.stacks);
        if band == 0 {
            assert!(slice == 0, "the cap has only slice 0, got {slice}");
            0
        } else {
            assert!(slice < self.slices, "slice {slice} out of range 0..{}", self.slices);
            1 + (band - 1) * self.slices + slice
        }
    }

    /// cos θ of the lower edge of the band with index `j` counted from the horizon
    /// (j = 0 is the lowest band, j = stacks − 1 is the cap): z = j·slices/r.
    /// Integer numerator and one division, so every edge is the correctly rounded value and the
    /// same expression serves `bounds` and `patch_index`.
    fn z_edge(&self, j: usize) -> f64 {
        (j * self.slices) as f64 / self.n_patches() as f64
    }

    /// Azimuth of the start of slice `s`, 2πs/slices.
    fn phi_edge(&self, s: usize) -> f64 {
        2.0 * PI * s as f64 / self.slices as f64
    }

    /// Edges of patch `i` in (cos θ, φ).
    ///
    /// # Panics
    /// If `i >= n_patches()`.
    pub fn bounds(&self, i: usize) -> PatchBounds {
        let (band, slice) = self.band_slice(i);
        if band == 0 {
            PatchBounds { z0: self.z_edge(self.stacks - 1), z1: 1.0, phi0: 0.0, phi1: 2.0 * PI }
        } else {
            let j = self.stacks - 1 - band; // band index counted from the horizon
            PatchBounds {
                z0: self.z_edge(j),
                z1: self.z_edge(j + 1),
                phi0: self.phi_edge(slice),
                phi1: self.phi_edge(slice + 1),
            }
        }
    }

    /// Index of the patch holding direction `dir` (need not be normalised).
    ///
    /// Meant for directions with z ≥ 0. Numerical edge cases never panic and always give a valid
    /// patch: z < 0 (rounding below the horizon) is treated as z = 0, i.e. the lowest band at the
    /// same azimuth; an azimuth that rounds to 2π belongs to slice 0; a zero, infinite or NaN
    /// vector gives patch 0 (the transport never produces one; callers that can must check).
    pub fn patch_index(&self, dir: [f64; 3]) -> usize {
        let [x, y, z] = dir;
        // Scale by the largest component first so that squaring cannot overflow or underflow.
        // (f64::max ignores NaN, hence the explicit finiteness test.)
        let scale = x.abs().max(y.abs()).max(z.abs());
        if !(x.is_finite() && y.is_finite() && z.is_finite() && scale > 0.0) {
            return 0;
        }
        let (x, y, z) = (x / scale, y / scale, z / scale);
        let norm = (x * x + y * y + z * z).sqrt();
        let mu = (z / norm).clamp(0.0, 1.0);

        let cap = self.stacks - 1;
        if mu >= self.z_edge(cap) {
            return 0;
        }
        // Band counted from the horizon: z_edge(j) ≤ μ < z_edge(j + 1). The floor is the answer up
        // to one rounding step; the two loops make it agree exactly with the edges of `bounds`.
        let mut j = ((mu * self.n_patches() as f64 / self.slices as f64).floor() as usize).min(cap - 1);
        while j > 0 && mu < self.z_edge(j) {
            j -= 1;
        }
        while j + 1 < cap && mu >= self.z_edge(j + 1) {
            j += 1;
        }
        let band = cap - j;

        // φ in [0, 2π); atan2 returns (−π, π], and −tiny + 2π can round to 2π, which is φ = 0.
        let mut phi = y.atan2(x);
        if phi < 0.0 {
            phi += 2.0 * PI;
        }
        if phi >= 2.0 * PI {
            phi = 0.0;
        }
        let mut s = ((phi * self.slices as f64 / (2.0 * PI)).floor() as usize).min(self.slices - 1);
        while s > 0 && phi < self.phi_edge(s) {
            s -= 1;
        }
        while s + 1 < self.slices && phi >= self.phi_edge(s + 1) {
            s += 1;
        }
        1 + (band - 1) * self.slices + s
    }

    /// Unit direction of the centroid of patch `i`.
    ///
    /// Definition: the centre of the patch in the equal-area coordinates (z = cos θ, φ), where
    /// solid angle is plain area, i.e. z_c = (z0 + z1)/2 (the solid-angle mean of cos θ over the
    /// patch) and φ_c = (φ0 + φ1)/2; for the cap, the pole (0, 0, 1), its mean direction by
    /// symmetry. This point always lies inside its patch, so the centroid maps back to its own
    /// patch for any stacks and slices, and all patches of a band share one cos θ, which the
    /// continuous BRDF uses as its interpolation node. The normalised mean direction ∫ω dΩ / |∫ω dΩ|
    /// has the same azimuth but leans towards the pole; it would leave its patch for slices ≤ 2
    /// (for slices = 1 it is the pole). For 31 × 30 the two differ by 0.52° in the top band (which
    /// spans 2.7°–15.1° in zenith) and by less than 0.12° below it.
    ///
    /// # Panics
    /// If `i >= n_patches()`.
    pub fn centroid(&self, i: usize) -> [f64; 3] {
        if i == 0 {
            return [0.0, 0.0, 1.0];
        }
        let b = self.bounds(i);
        let z = 0.5 * (b.z0 + b.z1);
        let phi = 0.5 * (b.phi0 + b.phi1);
        let sin_theta = (1.0 - z * z).max(0.0).sqrt();
        [sin_theta * phi.cos(), sin_theta * phi.sin(), z]
    }

    /// Solid angle of patch `i` in sr, (z1 − z0)(φ1 − φ0) = 2π/r up to rounding.
    ///
    /// # Panics
    /// If `i >= n_patches()`.
    pub fn solid_angle(&self, i: usize) -> f64 {
        let b = self.bounds(i);
        (b.z1 - b.z0) * (b.phi1 - b.phi0)
    }

    /// Projected solid angle ω_p = ∫ cos θ dΩ of patch `i` in sr (docs/model.md §3):
    /// band patch π(z1² − z0²)/slices, cap π t(2 − t) with t = 1/r. They sum to π.
    ///
    /// # Panics
    /// If `i >= n_patches()`.
    pub fn projected_solid_angle(&self, i: usize) -> f64 {
        let b = self.bounds(i);
        if i == 0 {
            let t = 1.0 / self.n_patches() as f64;
            PI * t * (2.0 - t)
        } else {
            PI * (b.z1 * b.z1 - b.z0 * b.z0) / self.slices as f64
        }
    }

    /// A direction distributed uniformly (in solid angle) over patch `i`, from two uniform
    /// numbers u1, u2 ∈ [0, 1): z = z0 + u1 (z1 − z0), φ = φ0 + u2 (φ1 − φ0), uniform in solid
    /// angle because dΩ = dz dφ. Values of u outside [0, 1) are clamped to the patch.
    ///
    /// # Panics
    /// If `i >= n_patches()`.
    pub fn sample_uniform(&self, i: usize, u1: f64, u2: f64) -> [f64; 3] {
        let b = self.bounds(i);
        let z = (b.z0 + u1 * (b.z1 - b.z0)).clamp(b.z0, b.z1);
        let phi = (b.phi0 + u2 * (b.phi1 - b.phi0)).clamp(b.phi0, b.phi1);
        let sin_theta = (1.0 - z * z).max(0.0).sqrt();
        [sin_theta * phi.cos(), sin_theta * phi.sin(), z]
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// splitmix64: a tiny deterministic generator so that the tests need no extra crate.
    struct SplitMix(u64);
    impl SplitMix {
        fn next_f64(&mut self) -> f64 {
            self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
            let mut z = self.0;
            z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
            z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
            z ^= z >> 31;
            (z >> 11) as f64 / (1u64 << 53) as f64
        }
        /// Uniform direction on the upper hemisphere (z uniform in [0, 1), φ uniform).
        fn hemisphere(&mut self) -> [f64; 3] {
            let z = self.next_f64();
            let phi = 2.0 * PI * self.next_f64();
            let s = (1.0 - z * z).sqrt();
            [s * phi.cos(), s * phi.sin(), z]
        }
    }

    fn contains(b: &PatchBounds, d: [f64; 3]) -> bool {
        let mut phi = d[1].atan2(d[0]);
        if phi < 0.0 {
            phi += 2.0 * PI;
        }
        let z = d[2];
        // A 1e-12 margin absorbs the rounding of atan2 and of the normalisation; azimuth is
        // periodic, so φ ≈ 2π also lies at the start of slice 0.
        let in_phi = |p: f64| p >= b.phi0 - 1e-12 && p <= b.phi1 + 1e-12;
        z >= b.z0 - 1e-12 && z <= b.z1 + 1e-12 && (in_phi(phi) || in_phi(phi - 2.0 * PI))
    }

    #[test]
    fn paper_hemisphere_has_901_patches() {
        let h = CollectorHemisphere::new(31, 30).unwrap();
        assert_eq!(h.n_patches(), 901);
        assert_eq!(h, CollectorHemisphere::paper());
        assert_eq!(h.bounds(0).z0, 900.0 / 901.0);
        assert_eq!(h.bounds(900).z0, 0.0);
    }

    #[test]
    fn invalid_sizes_are_parameter_errors() {
        for (stacks, slices, name) in [(1, 30, "stacks"), (0, 30, "stacks"), (31, 0, "slices"), (10_001, 3, "stacks")] {
            match CollectorHemisphere::new(stacks, slices) {
                Err(SandlightError::Parameter { name: n, .. }) => assert_eq!(n, name),
                other => panic!("expected a parameter error for ({stacks}, {slices}), got {other:?}"),
            }
        }
        assert!(CollectorHemisphere::new(2, 1).is_ok());
    }

    #[test]
    fn solid_angles_are_equal_and_sum_to_2pi_projected_to_pi() {
        for (stacks, slices) in [(31, 30), (2, 1), (5, 7), (12, 4)] {
            let h = CollectorHemisphere::new(stacks, slices).unwrap();
            let r = h.n_patches();
            let expected = 2.0 * PI / r as f64;
            let mut sum = 0.0;
            let mut sum_p = 0.0;
            for i in 0..r {
                let w = h.solid_angle(i);
                assert!((w / expected - 1.0).abs() < 1e-12, "patch {i}: {w} vs {expected}");
                sum += w;
                let b = h.bounds(i);
                let wp = h.projected_solid_angle(i);
                // ∫ z dz dφ over the patch.
                let wp_direct = 0.5 * (b.z1 * b.z1 - b.z0 * b.z0) * (b.phi1 - b.phi0);
                assert!((wp - wp_direct).abs() < 1e-14, "patch {i}: {wp} vs {wp_direct}");
                sum_p += wp;
            }
            assert!((sum - 2.0 * PI).abs() < 1e-12, "{sum}");
            assert!((sum_p - PI).abs() < 1e-12, "{sum_p}");
        }
    }

    #[test]
    fn random_directions_map_to_the_patch_that_contains_them() {
        let mut rng = SplitMix(42);
        for (stacks, slices) in [(31, 30), (2, 1), (4, 3), (7, 16)] {
            let h = CollectorHemisphere::new(stacks, slices).unwrap();
            let mut hits = vec![0usize; h.n_patches()];
            for _ in 0..200_000 {
                let d = rng.hemisphere();
                let i = h.patch_index(d);
                assert!(contains(&h.bounds(i), d), "{d:?} -> {i} {:?}", h.bounds(i));
                hits[i] += 1;
            }
            // Equal solid angles and uniform directions: every patch is hit.
            assert!(hits.iter().all(|&n| n > 0));
        }
    }

    #[test]
    fn samples_and_centroids_map_to_their_own_patch() {
        let mut rng = SplitMix(7);
        for (stacks, slices) in [(31, 30), (2, 1), (3, 2), (5, 7)] {
            let h = CollectorHemisphere::new(stacks, slices).unwrap();
            for i in 0..h.n_patches() {
                let c = h.centroid(i);
                assert!((c[0] * c[0] + c[1] * c[1] + c[2] * c[2] - 1.0).abs() < 1e-14);
                assert_eq!(h.patch_index(c), i, "centroid of {i}");
                for _ in 0..20 {
                    let d = h.sample_uniform(i, rng.next_f64(), rng.next_f64());
                    assert_eq!(h.patch_index(d), i, "sample {d:?} of {i}");
                }
            }
        }
    }

    #[test]
    fn sample_uniform_is_uniform_in_cos_theta() {
        // The mean of z over a band patch is (z0 + z1)/2 for a uniform-in-solid-angle sampler.
        let h = CollectorHemisphere::paper();
        let mut rng = SplitMix(3);
        let i = h.patch_of(15, 4);
        let b = h.bounds(i);
        let n = 100_000;
        let mean: f64 = (0..n).map(|_| h.sample_uniform(i, rng.next_f64(), rng.next_f64())[2]).sum::<f64>() / n as f64;
        // Standard error of the mean of a uniform on [z0, z1]: (z1 − z0)/√(12 n).
        let se = (b.z1 - b.z0) / (12.0 * n as f64).sqrt();
        assert!((mean - 0.5 * (b.z0 + b.z1)).abs() < 4.0 * se, "{mean}");
    }

    #[test]
    fn edge_directions_give_valid_patches() {
        let h = CollectorHemisphere::paper();
        let r = h.n_patches();
        // Horizon: lowest band; slightly below: still the lowest band at that azimuth.
        assert_eq!(h.band_slice(h.patch_index([1.0, 0.0, 0.0])), (30, 0));
        assert_eq!(h.band_slice(h.patch_index([1.0, 0.0, -1e-17])), (30, 0));
        assert_eq!(h.band_slice(h.patch_index([0.0, -1.0, 0.0])), (30, 22)); // φ = 3π/2
                                                                             // φ just below 2π (atan2 of −0.0 and of a tiny negative y).
        assert_eq!(h.band_slice(h.patch_index([1.0, -0.0, 0.5])).1, 0);
        assert_eq!(h.band_slice(h.patch_index([1.0, -1e-300, 0.5])).1, 0);
        assert_eq!(h.band_slice(h.patch_index([1.0, -1e-9, 0.5])).1, 29);
        // Pole; directions on every patch edge land in a patch whose (closed) bounds hold them.
        assert_eq!(h.patch_index([0.0, 0.0, 1.0]), 0);
        for i in 0..r {
            let b = h.bounds(i);
            for (z, phi) in [(b.z0, b.phi0), (b.z0, b.phi1), (b.z1, b.phi0)] {
                let s = (1.0 - z * z).sqrt();
                let d = [s * phi.cos(), s * phi.sin(), z];
                let j = h.patch_index(d);
                assert!(contains(&h.bounds(j), d), "edge of {i}: {d:?} -> {j}");
            }
        }
        // Degenerate vectors never panic; huge and tiny vectors are normalised correctly.
        assert_eq!(h.patch_index([0.0, 0.0, 0.0]), 0);
        assert_eq!(h.patch_index([f64::NAN, 0.0, 1.0]), 0);
        assert_eq!(h.patch_index([f64::INFINITY, 0.0, 1.0]), 0);
        assert_eq!(h.patch_index([1e300, 0.0, 1e300]), h.patch_index([1.0, 0.0, 1.0]));
        assert_eq!(h.patch_index([1e-300, 0.0, 1e-300]), h.patch_index([1.0, 0.0, 1.0]));
    }

    #[test]
    fn patch_numbering_runs_top_down_then_by_azimuth() {
        let h = CollectorHemisphere::new(4, 3).unwrap();
        assert_eq!(h.n_patches(), 10);
        for i in 0..h.n_patches() {
            let (band, slice) = h.band_slice(i);
            assert_eq!(h.patch_of(band, slice), i);
        }
        // Bands go down, slices go round.
        assert!(h.bounds(1).z0 > h.bounds(4).z0 && h.bounds(4).z0 > h.bounds(7).z0);
        assert!(h.bounds(1).phi0 < h.bounds(2).phi0 && h.bounds(2).phi0 < h.bounds(3).phi0);
    }
}

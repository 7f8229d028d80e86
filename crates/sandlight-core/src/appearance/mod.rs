//! Fast evaluation of the explicit BRDF of sand (paper §3.2.4 and §3.3).
//!
//! The spatial component is the continuous BRDF of the virtual goniophotometer: a trilinear
//! interpolant on the band-centroid grid F[b_i, b_o, k] (incoming band, outgoing band, slice
//! difference), piecewise linear in μ_i = cos θ_i and μ_o = cos θ_o and periodic piecewise linear
//! in Δφ = φ_o − φ_i. Its definition, and the reference implementation this module must agree with
//! to rounding, are in `python/sandlight/gonio/brdf.py` (`interpolate_band_grid`, `band_grid_f`).
//! The spectral BRDF combines two wavelength-independent parts with per-wavelength weights,
//! f(ω_i, ω_o, λ) = a(λ)·F(ω_i, ω_o) + b(λ)·P(μ_i)·P(μ_o), where P is a profile on the same μ
//! nodes (piecewise linear, held below the lowest node): the paper's §3.3 product is b = 0 and
//! a = the directional-hemispherical reflectance at normal incidence; `sandlight.appearance`
//! documents the energy-conserving term b. One spatial evaluation serves every wavelength.
//!
//! A grid may hold K *layers* (shapes) on the same nodes, F_l and P_l, blended per wavelength:
//! f(λ) = Σ_l a_l(λ)·F_l + b_l(λ)·P_l(μ_i)·P_l(μ_o) (`sandlight.appearance.shapes`: the shape at
//! the sand's reflectance at each wavelength). The interpolation weights of a direction pair are
//! computed once for all layers.

use crate::error::SandlightError;

/// The continuous BRDF's node values on the band grid (one or more layers), with the node cosines.
#[derive(Debug, Clone)]
pub struct BandGrid {
    stacks: usize,
    slices: usize,
    /// K, the layers (shapes) on these nodes.
    layers: usize,
    /// μ of the nodes in ascending order: band stacks − 1 (lowest) first, the cap (μ = 1) last.
    ascending: Vec<f64>,
    /// F[l][b_i][b_o][k] row-major, band 0 = cap (the Python layout).
    values: Vec<f64>,
    /// P[l] at the nodes, band order (cap first).
    profile: Vec<f64>,
    /// For each of `LOOKUP` equal cells of μ ∈ [asc[0], 1], the last node ≤ the cell's start:
    /// the bracket search starts there and steps up at most a few nodes (no binary search).
    start: Vec<u16>,
}

/// Cells of the bracket lookup table.
const LOOKUP: usize = 256;

/// The interpolation weights of one direction pair on the grid, shared by its layers.
#[derive(Debug, Clone, Copy)]
pub struct Stencil {
    /// Incoming nodes and weight: (1 − ti)·[i0] + ti·[i1].
    i0: usize,
    i1: usize,
    ti: f64,
    /// Outgoing nodes and weight.
    o0: usize,
    o1: usize,
    to: f64,
    /// Azimuth slices and weight.
    k0: usize,
    k1: usize,
    tk: f64,
}

/// What a direction pair asks of the grid.
#[derive(Debug, Clone, Copy)]
pub enum Pair {
    /// A NaN component: NaN out.
    Nan,
    /// On or below the horizon: 0 out.
    Below,
    /// Inside: interpolate with these weights.
    At(Stencil),
}
impl BandGrid {
    /// Builds the grid.
    ///
    /// `band_cos_theta` are the μ of the nodes in band order (cap first, decreasing), `values`
    /// is F[l, b_i, b_o, k] row-major with shape (K, stacks, stacks, slices), `profile` P[l] at
    /// the nodes in band order with shape (K, stacks) (zeros for the plain product); K ≥ 1 is
    /// the profile's length over `stacks`.
    pub fn new(
        stacks: usize,
        slices: usize,
        band_cos_theta: &[f64],
        values: Vec<f64>,
        profile: Vec<f64>,
    ) -> Result<Self, SandlightError> {
        if stacks < 2 || slices < 1 {
            return Err(SandlightError::parameter(
                "stacks, slices",
                format!("{stacks}, {slices}"),
                "must be at least 2 and 1",
            ));
        }
        if band_cos_theta.len() != stacks {
            return Err(SandlightError::parameter(
                "band_cos_theta",
                format!("length {}", band_cos_theta.len()),
                &format!("must have one entry per stack ({stacks})"),
            ));
        }
        // Non-finite values first: the order test below would let NaN through.
        if band_cos_theta.iter().any(|m| !m.is_finite()) || band_cos_theta.windows(2).any(|w| w[0] <= w[1]) {
            return Err(SandlightError::parameter(
                "band_cos_theta",
                format!("{band_cos_theta:?}"),
                "must be finite and strictly decreasing",
            ));
        }
        if profile.is_empty() || profile.len() % stacks != 0 || profile.iter().any(|v| !v.is_finite()) {
            return Err(SandlightError::parameter(
                "profile",
                format!("{} values", profile.len()),
                &format!("must hold K ≥ 1 rows of {stacks} finite values, one per node"),
            ));
        }
        let layers = profile.len() / stacks;
        if values.len() != layers * stacks * stacks * slices {
            return Err(SandlightError::parameter(
                "grid",
                format!("{} values", values.len()),
                &format!("must hold layers × stacks × stacks × slices = {} values", layers * stacks * stacks * slices),
            ));
        }
        if stacks > u16::MAX as usize {
            return Err(SandlightError::parameter("stacks", stacks, "must be at most 65535"));
        }
        if values.iter().any(|v| !v.is_finite()) {
            return Err(SandlightError::parameter("grid", "a non-finite value", "must hold finite values"));
        }
        let ascending: Vec<f64> = band_cos_theta.iter().rev().copied().collect();
        let (lo, hi) = (ascending[0], ascending[stacks - 1]);
        let start = (0..LOOKUP)
            .map(|c| {
                let m = lo + (hi - lo) * c as f64 / LOOKUP as f64;
                (ascending.partition_point(|&a| a <= m).saturating_sub(1).min(stacks - 2)) as u16
            })
            .collect();
        Ok(BandGrid { stacks, slices, layers, ascending, values, profile, start })
    }

    /// K, the layers.
    pub fn layers(&self) -> usize {
        self.layers
    }

    /// Linear weights of μ on the nodes: (band a, band b, t) with value (1 − t)·F[a] + t·F[b].
    /// μ below the lowest node is held at it, μ above the cap at the cap (`mu_bracket` in Python).
    #[inline]
    fn bracket(&self, mu: f64) -> (usize, usize, f64) {
        let n = self.stacks;
        let asc = &self.ascending;
        let (lo, hi) = (asc[0], asc[n - 1]);
        let m = mu.max(lo).min(hi);
        // j: the last node ≤ μ, clipped to [0, n − 2] (asc[j] ≤ μ < asc[j + 1]); the table gives
        // a node at or below it, then step up.
        let cell = (((m - lo) / (hi - lo)) * LOOKUP as f64) as usize;
        let mut j = self.start[cell.min(LOOKUP - 1)] as usize;
        while j + 2 < n && asc[j + 1] <= m {
            j += 1;
        }
        let t = (m - asc[j]) / (asc[j + 1] - asc[j]);
        (n - 1 - j, n - 2 - j, t)
    }

    /// The interpolation weights at (μ_i, μ_o, Δφ), Δφ in radians (any real, periodic). No
    /// horizon test.
    #[inline]
    pub fn stencil(&self, mu_i: f64, mu_o: f64, dphi: f64) -> Stencil {
        let (i0, i1, ti) = self.bracket(mu_i);
        let (o0, o1, to) = self.bracket(mu_o);
        let l = self.slices;
        let x = (dphi * (l as f64 / std::f64::consts::TAU)).rem_euclid(l as f64);
        let k0f = x.floor();
        let k0 = (k0f as usize) % l; // x can round up to exactly `slices`
        Stencil { i0, i1, ti, o0, o1, to, k0, k1: (k0 + 1) % l, tk: x - k0f }
    }

    /// (F_l, P_l(μ_i)·P_l(μ_o)) of layer `l` with the weights `s`.
    #[inline]
    pub fn layer(&self, s: &Stencil, l: usize) -> (f64, f64) {
        let n = self.stacks;
        let v = &self.values[l * n * n * self.slices..(l + 1) * n * n * self.slices];
        let at = |bi: usize, bo: usize| -> f64 {
            let row = (bi * n + bo) * self.slices;
            (1.0 - s.tk) * v[row + s.k0] + s.tk * v[row + s.k1]
        };
        let (ti, to) = (s.ti, s.to);
        let f = (1.0 - ti) * ((1.0 - to) * at(s.i0, s.o0) + to * at(s.i0, s.o1))
            + ti * ((1.0 - to) * at(s.i1, s.o0) + to * at(s.i1, s.o1));
        let p = &self.profile[l * n..(l + 1) * n];
        let pi = (1.0 - ti) * p[s.i0] + ti * p[s.i1];
        let po = (1.0 - to) * p[s.o0] + to * p[s.o1];
        (f, pi * po)
    }

    /// What the pair of directions towards the light `wi` and the viewer `wo` (local frame,
    /// z = the normal, any positive length) asks: NaN if either has a NaN component, 0 if either
    /// is on or below the horizon, else the stencil. Err for a zero or infinite vector.
    #[inline]
    pub fn pair(&self, wi: [f64; 3], wo: [f64; 3]) -> Result<Pair, &'static str> {
        if wi.iter().chain(wo.iter()).any(|c| c.is_nan()) {
            return Ok(Pair::Nan);
        }
        let ni = (wi[0] * wi[0] + wi[1] * wi[1] + wi[2] * wi[2]).sqrt();
        let no = (wo[0] * wo[0] + wo[1] * wo[1] + wo[2] * wo[2]).sqrt();
        if !(ni > 0.0 && ni.is_finite()) {
            return Err("wi");
        }
        if !(no > 0.0 && no.is_finite()) {
            return Err("wo");
        }
        if !(wi[2] > 0.0 && wo[2] > 0.0) {
            return Ok(Pair::Below);
        }
        // φ_o − φ_i from one atan2: sin and cos of the difference times |wi_xy||wo_xy|.
        let dphi = (wi[0] * wo[1] - wi[1] * wo[0]).atan2(wi[0] * wo[0] + wi[1] * wo[1]);
        Ok(Pair::At(self.stencil(wi[2] / ni, wo[2] / no, dphi)))
    }
}

/// Spectral BRDF of `n` direction pairs: `out[p·W + w] = Σ_l F_l(wi_p, wo_p)·a[w·K + l] +
/// P_l(μ_i)P_l(μ_o)·b[w·K + l]` (K the grid's layers, W = a.len()/K = b.len()/K; for K = 1,
/// F·a[w] + P P·b[w]). `wi`, `wo` are row-major (n, 3). Layers whose weights are all zero are
/// not evaluated.
///
/// Returns Err((name, row)) for the first zero or infinite direction.
pub fn spectral_brdf(
    grid: &BandGrid,
    wi: &[f64],
    wo: &[f64],
    a: &[f64],
    b: &[f64],
    out: &mut [f64],
) -> Result<(), (&'static str, usize)> {
    let k = grid.layers;
    let w = a.len() / k;
    debug_assert!(a.len() == w * k && b.len() == w * k);
    let active: Vec<usize> = (0..k).filter(|&l| (0..w).any(|j| a[j * k + l] != 0.0 || b[j * k + l] != 0.0)).collect();
    let (mut f, mut pp) = (vec![0.0; k], vec![0.0; k]);
    for (p, ((x, y), o)) in wi.chunks_exact(3).zip(wo.chunks_exact(3)).zip(out.chunks_exact_mut(w.max(1))).enumerate() {
        match grid.pair([x[0], x[1], x[2]], [y[0], y[1], y[2]]).map_err(|name| (name, p))? {
            Pair::Nan => o.fill(f64::NAN),
            Pair::Below => o.fill(0.0),
            Pair::At(s) => {
                for &l in &active {
                    (f[l], pp[l]) = grid.layer(&s, l);
                }
                for (j, dst) in o.iter_mut().enumerate() {
                    let (aj, bj) = (&a[j * k..(j + 1) * k], &b[j * k..(j + 1) * k]);
                    *dst = active.iter().fold(0.0, |v, &l| v + (f[l] * aj[l] + pp[l] * bj[l]));
                }
            }
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    /// One-layer evaluations, for the tests (the evaluator goes through `pair`, `stencil` and
    /// `layer` for every layer at once).
    impl BandGrid {
        /// (F, P(μ_i)·P(μ_o)) of the first layer at (μ_i, μ_o, Δφ). No horizon test.
        fn eval_mu(&self, mu_i: f64, mu_o: f64, dphi: f64) -> (f64, f64) {
            self.layer(&self.stencil(mu_i, mu_o, dphi), 0)
        }

        /// (F, P·P) of the first layer for directions `wi`, `wo`: 0 on or below the horizon,
        /// NaN for a NaN component, Err for a zero or infinite vector.
        fn eval_dirs(&self, wi: [f64; 3], wo: [f64; 3]) -> Result<(f64, f64), &'static str> {
            Ok(match self.pair(wi, wo)? {
                Pair::Nan => (f64::NAN, f64::NAN),
                Pair::Below => (0.0, 0.0),
                Pair::At(s) => self.layer(&s, 0),
            })
        }
    }

    /// A small grid with distinct values: F = 1 + b_i + 10 b_o + 100 k (not reciprocal; the
    /// interpolation arithmetic does not need it).
    fn grid(stacks: usize, slices: usize) -> BandGrid {
        let nodes: Vec<f64> =
            (0..stacks).map(|b| if b == 0 { 1.0 } else { 1.0 - (b as f64 - 0.5) / stacks as f64 }).collect();
        let mut v = Vec::new();
        for bi in 0..stacks {
            for bo in 0..stacks {
                for k in 0..slices {
                    v.push(1.0 + bi as f64 + 10.0 * bo as f64 + 100.0 * k as f64);
                }
            }
        }
        let profile: Vec<f64> = (0..stacks).map(|b| 1.0 - 0.1 * b as f64).collect();
        BandGrid::new(stacks, slices, &nodes, v, profile).unwrap()
    }

    #[test]
    fn exact_at_nodes() {
        let g = grid(4, 6);
        let nodes: Vec<f64> = g.ascending.iter().rev().copied().collect();
        for bi in 0..4 {
            for bo in 0..4 {
                for k in 0..6 {
                    let dphi = std::f64::consts::TAU * k as f64 / 6.0;
                    let want = 1.0 + bi as f64 + 10.0 * bo as f64 + 100.0 * k as f64;
                    let (f, pp) = g.eval_mu(nodes[bi], nodes[bo], dphi);
                    assert!((f - want).abs() < 1e-9 * want);
                    let want_p = (1.0 - 0.1 * bi as f64) * (1.0 - 0.1 * bo as f64);
                    assert!((pp - want_p).abs() < 1e-12);
                }
            }
        }
    }

    #[test]
    fn linear_between_nodes_and_held_below() {
        let g = grid(4, 6);
        let lowest = g.ascending[0];
        // Below the lowest node (band 3) the value is held.
        assert_eq!(g.eval_mu(0.0, 1.0, 0.0), g.eval_mu(lowest, 1.0, 0.0));
        // Half-way in Δφ between slices 0 and 1: the mean of the two.
        let half = std::f64::consts::TAU / 12.0;
        let v = g.eval_mu(1.0, 1.0, half).0;
        assert!((v - 51.0).abs() < 1e-9, "{v}");
        // The profile is linear in μ between nodes: half-way between the cap and band 1.
        let mid = 0.5 * (g.ascending[3] + g.ascending[2]);
        assert!((g.eval_mu(mid, 1.0, 0.0).1 - 0.95).abs() < 1e-12);
        // Periodic: Δφ and Δφ + 2π agree.
        assert!((g.eval_mu(0.5, 0.7, 1.0).0 - g.eval_mu(0.5, 0.7, 1.0 + std::f64::consts::TAU).0).abs() < 1e-9);
    }

    #[test]
    fn directions() {
        let g = grid(4, 6);
        assert_eq!(g.eval_dirs([0.0, 0.0, 1.0], [1.0, 0.0, -0.1]).unwrap(), (0.0, 0.0));
        assert!(g.eval_dirs([f64::NAN, 0.0, 1.0], [0.0, 0.0, 1.0]).unwrap().0.is_nan());
        assert_eq!(g.eval_dirs([0.0, 0.0, 0.0], [0.0, 0.0, 1.0]), Err("wi"));
        // Scaling a direction does not change the value.
        let a = g.eval_dirs([0.3, 0.2, 0.5], [-0.1, 0.4, 0.2]).unwrap().0;
        let b = g.eval_dirs([3.0, 2.0, 5.0], [-0.1, 0.4, 0.2]).unwrap().0;
        assert!((a - b).abs() < 1e-12 * a);
        // Rotating both directions about the normal does not change the value.
        let (s, c) = 0.7f64.sin_cos();
        let rot = |w: [f64; 3]| [c * w[0] - s * w[1], s * w[0] + c * w[1], w[2]];
        let r = g.eval_dirs(rot([0.3, 0.2, 0.5]), rot([-0.1, 0.4, 0.2])).unwrap().0;
        assert!((a - r).abs() < 1e-9 * a);
    }

    #[test]
    fn spectral_product() {
        let g = grid(3, 4);
        let wi = [0.1, 0.2, 0.9, 0.0, 0.0, 1.0];
        let wo = [0.3, -0.2, 0.5, 0.5, 0.5, 0.1];
        let (a, b) = ([0.5, 2.0], [0.25, 0.0]);
        let mut out = [0.0; 4];
        spectral_brdf(&g, &wi, &wo, &a, &b, &mut out).unwrap();
        let (f0, p0) = g.eval_dirs([0.1, 0.2, 0.9], [0.3, -0.2, 0.5]).unwrap();
        assert_eq!(out[0], f0 * 0.5 + p0 * 0.25);
        assert_eq!(out[1], f0 * 2.0);
        let bad = [0.0; 6];
        assert_eq!(spectral_brdf(&g, &wi, &bad, &a, &b, &mut out), Err(("wo", 0)));
    }

    #[test]
    fn layers_share_the_stencil_and_blend_per_wavelength() {
        let (stacks, slices) = (4, 6);
        let one = grid(stacks, slices);
        // Layer 1 = 2 × layer 0 + 5, profile halved.
        let n = stacks * stacks * slices;
        let values: Vec<f64> = one.values.iter().copied().chain(one.values.iter().map(|v| 2.0 * v + 5.0)).collect();
        let profile: Vec<f64> = one.profile.iter().copied().chain(one.profile.iter().map(|p| 0.5 * p)).collect();
        let nodes: Vec<f64> = one.ascending.iter().rev().copied().collect();
        let two = BandGrid::new(stacks, slices, &nodes, values, profile).unwrap();
        assert_eq!((two.layers(), two.values.len()), (2, 2 * n));
        let (wi, wo) = ([0.3, 0.2, 0.5], [-0.1, 0.4, 0.2]);
        let (f0, p0) = one.eval_dirs(wi, wo).unwrap();
        // Wavelength 0 takes layer 0 alone, wavelength 1 a blend, wavelength 2 layer 1 alone.
        let a = [0.7, 0.0, 0.3, 0.3, 0.0, 1.0];
        let b = [0.1, 0.0, 0.2, 0.2, 0.0, 0.4];
        let mut out = [0.0; 3];
        spectral_brdf(&two, &wi, &wo, &a, &b, &mut out).unwrap();
        let (f1, p1) = (2.0 * f0 + 5.0, 0.25 * p0);
        let want = [0.7 * f0 + 0.1 * p0, 0.3 * f0 + 0.2 * p0 + 0.3 * f1 + 0.2 * p1, f1 + 0.4 * p1];
        for (o, w) in out.iter().zip(want) {
            assert!((o - w).abs() < 1e-12 * w.abs(), "{out:?} vs {want:?}");
        }
        // Below the horizon and NaN as for one layer.
        spectral_brdf(&two, &[0.0, 0.0, 1.0], &[1.0, 0.0, -0.1], &a, &b, &mut out).unwrap();
        assert_eq!(out, [0.0; 3]);
        spectral_brdf(&two, &[f64::NAN, 0.0, 1.0], &wo, &a, &b, &mut out).unwrap();
        assert!(out.iter().all(|v| v.is_nan()));
    }

    #[test]
    fn rejects_bad_grids() {
        let p = || vec![0.0; 3];
        assert!(BandGrid::new(3, 4, &[1.0, 0.5, 0.6], vec![0.0; 36], p()).is_err());
        assert!(BandGrid::new(3, 4, &[1.0, 0.5, 0.1], vec![0.0; 35], p()).is_err());
        assert!(BandGrid::new(3, 4, &[1.0, 0.5, 0.1], vec![f64::NAN; 36], p()).is_err());
        assert!(BandGrid::new(3, 4, &[1.0, 0.5, 0.1], vec![0.0; 36], vec![0.0; 2]).is_err());
        // Two layers of profile want two layers of values.
        assert!(BandGrid::new(3, 4, &[1.0, 0.5, 0.1], vec![0.0; 36], vec![0.0; 6]).is_err());
        assert!(BandGrid::new(3, 4, &[1.0, 0.5, 0.1], vec![0.0; 72], vec![0.0; 6]).is_ok());
    }
}

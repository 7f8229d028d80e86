//! Tabulated isotropic spectral BRDFs, a stack of them for texture maps, and their sampling.
//!
//! A table holds f(λ_b, μ_i, μ_o, Δφ) in sr⁻¹ on a rectilinear grid: μ = cos θ on ascending axes
//! that include 0 and 1, Δφ = φ_o − φ_i folded into [0, π] (0: the viewer on the light's side,
//! backscatter), one value per render band. A *stack* is a list of such tables on the same grid,
//! the levels of a one-parameter family (16 saturations for the beach): a point with level
//! coordinate s ∈ [0, L−1] takes the linear blend of levels ⌊s⌋ and ⌊s⌋+1 (the brief's "interpolate
//! linearly between levels per point"). Within a level, lookup is trilinear in (μ_i, μ_o, Δφ).
//!
//! Sampling follows the table: for every (level, μ_i node) a discrete distribution over the
//! (μ_o, Δφ) cells, with cell weight = band-mean of f at the four cell corners × the cell's
//! projected solid angle; within a cell μ_o² and Δφ are uniform (cosine-weighted in the cell), the
//! sign of Δφ is a fair coin. A direction between nodes draws from the mixture of the ≤ 4
//! neighbouring (level, μ_i) distributions with the interpolation weights, so the pdf is exact and
//! positive wherever the interpolated f is. A defensive cosine component (weight
//! `DEFENSIVE_COSINE`) keeps the pdf positive where a noisy, slightly non-reciprocal table has f > 0
//! but the sampled (transposed) row has none, and bounds the weight f cos/pdf.

use std::f64::consts::PI;

use crate::error::SandlightError;
use crate::math::Vec3;

/// Largest number of spectral bands a render may use (e.g. 31 for 400–700 nm every 10 nm).
pub const MAX_BANDS: usize = 32;

/// Spectrum of one path (only the first `n_bands` entries are meaningful).
pub type Spectrum = [f64; MAX_BANDS];

/// Share of cosine sampling in the table-following sampler (defensive mixture, Hesterberg 1995).
pub const DEFENSIVE_COSINE: f64 = 0.1;

/// How outgoing directions are drawn from the BRDF side.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum BrdfSampling {
    /// pdf = cos θ / π (the paper's §4.2.1 choice).
    Cosine,
    /// Follows the tabulated BRDF (plus the defensive cosine share).
    Table,
}

/// A stack of BRDF tables on one grid.
#[derive(Clone, Debug)]
pub struct BrdfStack {
    n_levels: usize,
    mu_i: Vec<f64>,
    mu_o: Vec<f64>,
    dphi: Vec<f64>,
    n_bands: usize,
    /// f[((((l·n_i + i)·n_o + o)·n_p + p)·n_bands + b] in sr⁻¹.
    f: Vec<f32>,
    /// Inclusive cumulative cell probabilities, per (level, μ_i node): n_levels·n_i·n_cells.
    cell_cdf: Vec<f64>,
    /// P(cell) / (projected solid angle of the cell, both signs of Δφ), per (level, μ_i node).
    cell_density: Vec<f64>,
    /// f[level·n_bands + b] when no level depends on the angles (Lambertian tables): lookups
    /// then skip the trilinear interpolation.
    flat: Option<Vec<f32>>,
}

fn check_axis(name: &str, axis: &[f64], lo: f64, hi: f64, must_span: bool) -> Result<(), SandlightError> {
    if axis.len() < 2 {
        return Err(SandlightError::parameter(name, format!("{} nodes", axis.len()), "at least 2 nodes"));
    }
    if axis.iter().any(|v| !v.is_finite() || *v < lo - 1e-12 || *v > hi + 1e-12) {
        return Err(SandlightError::parameter(name, format!("{axis:?}"), &format!("values in [{lo}, {hi}]")));
    }
    if axis.windows(2).any(|w| w[1] <= w[0]) {
        return Err(SandlightError::parameter(name, format!("{axis:?}"), "strictly ascending values"));
    }
    if must_span && ((axis[0] - lo).abs() > 1e-9 || (axis[axis.len() - 1] - hi).abs() > 1e-9) {
        return Err(SandlightError::parameter(name, format!("{axis:?}"), &format!("an axis from {lo} to {hi} inclusive")));
    }
    Ok(())
}

/// Index k and weight t with x ≈ (1−t)·axis[k] + t·axis[k+1]; x is clamped to the axis range.
#[inline]
fn bracket(axis: &[f64], x: f64) -> (usize, f64) {
    let n = axis.len();
    if x.is_nan() || x <= axis[0] {
        // NaN: a caller never passes it, but it must not turn into an index underflow.
        return (0, 0.0);
    }
    if x >= axis[n - 1] {
        return (n - 2, 1.0);
    }
    // First node greater than x, minus one: axis[k] ≤ x < axis[k+1].
    let k = axis.partition_point(|&a| a <= x) - 1;
    let k = k.min(n - 2);
    (k, (x - axis[k]) / (axis[k + 1] - axis[k]))
}

/// Index of the cell of `axis` containing x (clamped).
#[inline]
fn cell_of(axis: &[f64], x: f64) -> usize {
    bracket(axis, x).0
}

impl BrdfStack {
    /// Builds a stack from its axes and values `f` (length n_levels·n_i·n_o·n_p·n_bands, order
    /// level, μ_i, μ_o, Δφ, band). Values must be finite and ≥ 0.
    pub fn new(n_levels: usize, mu_i: Vec<f64>, mu_o: Vec<f64>, dphi: Vec<f64>, n_bands: usize, f: Vec<f32>) -> Result<Self, SandlightError> {
        if n_levels == 0 {
            return Err(SandlightError::parameter("n_levels", n_levels, "at least one BRDF table"));
        }
        if n_bands == 0 || n_bands > MAX_BANDS {
            return Err(SandlightError::parameter("n_bands", n_bands, &format!("between 1 and {MAX_BANDS}")));
        }
        check_axis("mu_i", &mu_i, 0.0, 1.0, true)?;
        check_axis("mu_o", &mu_o, 0.0, 1.0, true)?;
        check_axis("dphi", &dphi, 0.0, PI, true)?;
        let (ni, no, np) = (mu_i.len(), mu_o.len(), dphi.len());
        let expected = n_levels * ni * no * np * n_bands;
        if f.len() != expected {
            return Err(SandlightError::parameter("f", format!("{} values", f.len()), &format!("{expected} values (levels × mu_i × mu_o × dphi × bands)")));
        }
        if let Some(bad) = f.iter().find(|v| !v.is_finite() || **v < 0.0) {
            return Err(SandlightError::parameter("f", bad, "finite BRDF values ≥ 0 sr⁻¹"));
        }
        let n_cells = (no - 1) * (np - 1);
        let mut cell_cdf = vec![0.0; n_levels * ni * n_cells];
        let mut cell_density = vec![0.0; n_levels * ni * n_cells];
        let per_level = ni * no * np * n_bands;
        let is_flat = (0..n_levels).all(|l| {
            let block = &f[l * per_level..(l + 1) * per_level];
            block.chunks_exact(n_bands).all(|c| c == &block[..n_bands])
        });
        let flat = is_flat.then(|| (0..n_levels).flat_map(|l| f[l * per_level..l * per_level + n_bands].to_vec()).collect());
        let mut stack = BrdfStack { n_levels, mu_i, mu_o, dphi, n_bands, f, cell_cdf: Vec::new(), cell_density: Vec::new(), flat };
        for l in 0..n_levels {
            for i in 0..ni {
                let base = (l * ni + i) * n_cells;
                let mut weights = vec![0.0; n_cells];
                let mut areas = vec![0.0; n_cells];
                for o in 0..no - 1 {
                    for p in 0..np - 1 {
                        let (m0, m1) = (stack.mu_o[o], stack.mu_o[o + 1]);
                        // Projected solid angle ∫ μ dω of the cell, Δφ of both signs.
                        let area = (m1 * m1 - m0 * m0) * (stack.dphi[p + 1] - stack.dphi[p]);
                        let mut mean = 0.0;
                        for (oo, pp) in [(o, p), (o + 1, p), (o, p + 1), (o + 1, p + 1)] {
                            let idx = stack.index(l, i, oo, pp);
                            mean += stack.f[idx..idx + n_bands].iter().map(|&v| v as f64).sum::<f64>();
                        }
                        mean /= 4.0 * n_bands as f64;
                        weights[o * (np - 1) + p] = mean * area;
                        areas[o * (np - 1) + p] = area;
                    }
                }
                let mut total: f64 = weights.iter().sum();
                if total <= 0.0 {
                    // A black row: sample by projected solid angle (cosine) instead.
                    weights.clone_from(&areas);
                    total = weights.iter().sum();
                }
                let mut acc = 0.0;
                for c in 0..n_cells {
                    let p = weights[c] / total;
                    acc += p;
                    cell_cdf[base + c] = acc;
                    cell_density[base + c] = if areas[c] > 0.0 { p / areas[c] } else { 0.0 };
                }
                cell_cdf[base + n_cells - 1] = 1.0;
            }
        }
        stack.cell_cdf = cell_cdf;
        stack.cell_density = cell_density;
        Ok(stack)
    }

    pub fn n_levels(&self) -> usize {
        self.n_levels
    }

    pub fn n_bands(&self) -> usize {
        self.n_bands
    }

    /// Whether no level depends on the angles (then Δφ is irrelevant and sampling is cosine).
    pub fn is_flat(&self) -> bool {
        self.flat.is_some()
    }

    #[inline]
    fn index(&self, l: usize, i: usize, o: usize, p: usize) -> usize {
        (((l * self.mu_i.len() + i) * self.mu_o.len() + o) * self.dphi.len() + p) * self.n_bands
    }

    /// The (≤ 2) levels and weights of level coordinate `s` (clamped to [0, L−1]).
    #[inline]
    fn levels(&self, s: f64) -> [(usize, f64); 2] {
        if self.n_levels == 1 || s.is_nan() || s <= 0.0 {
            return [(0, 1.0), (0, 0.0)];
        }
        let top = (self.n_levels - 1) as f64;
        if s >= top {
            return [(self.n_levels - 1, 1.0), (0, 0.0)];
        }
        let l = s as usize; // s > 0 here: truncation is the floor
        let t = s - l as f64;
        [(l, 1.0 - t), (l + 1, t)]
    }

    /// Adds f(μ_i, μ_o, Δφ) at level coordinate `s` into `out[..n_bands]` (which it overwrites).
    /// μ in [0, 1] (clamped), Δφ in [0, π].
    pub fn eval(&self, s: f64, mu_i: f64, mu_o: f64, dphi: f64, out: &mut Spectrum) {
        let nb = self.n_bands;
        out[..nb].iter_mut().for_each(|v| *v = 0.0);
        if let Some(flat) = &self.flat {
            for (l, wl) in self.levels(s) {
                if wl != 0.0 {
                    for (acc, &v) in out[..nb].iter_mut().zip(&flat[l * nb..(l + 1) * nb]) {
                        *acc += wl * v as f64;
                    }
                }
            }
            return;
        }
        let (i0, ti) = bracket(&self.mu_i, mu_i);
        let (o0, to) = bracket(&self.mu_o, mu_o);
        let (p0, tp) = bracket(&self.dphi, dphi);
        for (l, wl) in self.levels(s) {
            if wl == 0.0 {
                continue;
            }
            for (i, wi) in [(i0, 1.0 - ti), (i0 + 1, ti)] {
                if wi == 0.0 {
                    continue;
                }
                for (o, wo) in [(o0, 1.0 - to), (o0 + 1, to)] {
                    if wo == 0.0 {
                        continue;
                    }
                    for (p, wp) in [(p0, 1.0 - tp), (p0 + 1, tp)] {
                        let w = wl * wi * wo * wp;
                        if w == 0.0 {
                            continue;
                        }
                        let idx = self.index(l, i, o, p);
                        for (acc, &v) in out[..nb].iter_mut().zip(&self.f[idx..idx + nb]) {
                            *acc += w * v as f64;
                        }
                    }
                }
            }
        }
    }

    /// Mixture components (level, μ_i node, weight) of level coordinate s and cosine μ.
    #[inline]
    fn components(&self, s: f64, mu: f64) -> [(usize, usize, f64); 4] {
        let (i0, ti) = bracket(&self.mu_i, mu);
        let [(l0, w0), (l1, w1)] = self.levels(s);
        [(l0, i0, w0 * (1.0 - ti)), (l0, i0 + 1, w0 * ti), (l1, i0, w1 * (1.0 - ti)), (l1, i0 + 1, w1 * ti)]
    }

    /// Samples (μ, |Δφ|, sign) of a direction given the other direction's cosine `mu_given`,
    /// following the table. `u` are five uniforms in [0, 1). Returns (μ, signed Δφ).
    pub fn sample_table(&self, s: f64, mu_given: f64, u: [f64; 5]) -> (f64, f64) {
        // A flat table's cells weigh their projected solid angle: the mixture is cosine sampling.
        if u[0] < DEFENSIVE_COSINE || self.flat.is_some() {
            return sample_cosine(u[1], u[2]);
        }
        // Reuse u[0] to pick the mixture component (rescaled to [0, 1)).
        let mut pick = (u[0] - DEFENSIVE_COSINE) / (1.0 - DEFENSIVE_COSINE);
        let comps = self.components(s, mu_given);
        let mut chosen = comps[0];
        for c in comps {
            if c.2 <= 0.0 {
                continue;
            }
            chosen = c;
            if pick < c.2 {
                break;
            }
            pick -= c.2;
        }
        let (l, i, _) = chosen;
        let np1 = self.dphi.len() - 1;
        let n_cells = (self.mu_o.len() - 1) * np1;
        let base = (l * self.mu_i.len() + i) * n_cells;
        let cdf = &self.cell_cdf[base..base + n_cells];
        let c = cdf.partition_point(|&v| v <= u[1]).min(n_cells - 1);
        let (o, p) = (c / np1, c % np1);
        let (m0, m1) = (self.mu_o[o], self.mu_o[o + 1]);
        // Uniform in μ² (cosine-weighted within the cell), uniform in Δφ.
        let mu = (m0 * m0 + u[2] * (m1 * m1 - m0 * m0)).sqrt();
        let phi = self.dphi[p] + u[3] * (self.dphi[p + 1] - self.dphi[p]);
        (mu, if u[4] < 0.5 { phi } else { -phi })
    }

    /// Solid-angle pdf of the table-following sampler for a direction (μ, |Δφ|) given `mu_given`.
    pub fn pdf_table(&self, s: f64, mu_given: f64, mu: f64, dphi: f64) -> f64 {
        if mu <= 0.0 {
            return 0.0;
        }
        if self.flat.is_some() {
            return mu / PI; // as `sample_table`: cosine
        }
        let np1 = self.dphi.len() - 1;
        let n_cells = (self.mu_o.len() - 1) * np1;
        let c = cell_of(&self.mu_o, mu) * np1 + cell_of(&self.dphi, dphi);
        let mut table = 0.0;
        for (l, i, w) in self.components(s, mu_given) {
            if w > 0.0 {
                table += w * self.cell_density[(l * self.mu_i.len() + i) * n_cells + c];
            }
        }
        DEFENSIVE_COSINE * mu / PI + (1.0 - DEFENSIVE_COSINE) * table * mu
    }
}

/// Cosine-weighted direction: (μ, Δφ) with pdf μ/π.
#[inline]
pub fn sample_cosine(u1: f64, u2: f64) -> (f64, f64) {
    let mu = u1.sqrt();
    (mu, 2.0 * PI * u2 - PI)
}

/// Local geometry of a direction pair at a surface with unit normal `n`: (μ_a, μ_b, cos Δφ).
/// A direction along the normal has no azimuth: cos Δφ = 1 then.
#[inline]
pub fn pair_cosines(n: Vec3, a: Vec3, b: Vec3) -> (f64, f64, f64) {
    let ma = a.dot(n);
    let mb = b.dot(n);
    let ta = a - n * ma;
    let tb = b - n * mb;
    let la = ta.norm2();
    let lb = tb.norm2();
    let c = if la < 1e-24 || lb < 1e-24 { 1.0 } else { (ta.dot(tb) / (la * lb).sqrt()).clamp(-1.0, 1.0) };
    (ma, mb, c)
}


/// World direction with cosine μ to `n` and azimuth Δφ from the tangent projection of `given`.
#[inline]
pub fn direction_from(n: Vec3, given: Vec3, mu: f64, dphi: f64) -> Vec3 {
    let t = given - n * given.dot(n);
    let t1 = if t.norm2() > 1e-20 { t.normalized() } else { n.orthonormal_basis().0 };
    let t2 = n.cross(t1);
    let sin = (1.0 - mu * mu).max(0.0).sqrt();
    (t1 * (sin * dphi.cos()) + t2 * (sin * dphi.sin()) + n * mu).normalized()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::rng::Rng;

    fn axis(n: usize, hi: f64) -> Vec<f64> {
        (0..n).map(|k| hi * k as f64 / (n - 1) as f64).collect()
    }

    /// An anisotropic reciprocal test BRDF with a backscatter lobe (2 bands).
    fn test_stack() -> BrdfStack {
        let (mi, mo, dp) = (axis(9, 1.0), axis(9, 1.0), axis(13, PI));
        let mut f = Vec::new();
        for &a in &mi {
            for &b in &mo {
                for &p in &dp {
                    let lobe = 1.0 + 2.0 * (-(p * p) / 0.5).exp() * (1.0 - a * b);
                    f.push((0.3 / PI * lobe) as f32);
                    f.push((0.6 / PI * lobe) as f32);
                }
            }
        }
        BrdfStack::new(1, mi, mo, dp, 2, f).unwrap()
    }

    #[test]
    fn eval_is_exact_at_nodes_and_linear_between_levels() {
        let (mi, mo, dp) = (axis(3, 1.0), axis(3, 1.0), axis(3, PI));
        let mut f = vec![0.0f32; 2 * 27];
        for v in f[27..].iter_mut() {
            *v = 1.0;
        }
        f[3 * 3 + 3 + 1] = 0.25; // level 0, μ_i = 0.5, μ_o = 0.5, Δφ = π/2
        let s = BrdfStack::new(2, mi, mo, dp, 1, f).unwrap();
        let mut out = [0.0; MAX_BANDS];
        s.eval(0.0, 0.5, 0.5, PI / 2.0, &mut out);
        assert!((out[0] - 0.25).abs() < 1e-7);
        s.eval(0.5, 0.5, 0.5, PI / 2.0, &mut out);
        assert!((out[0] - 0.625).abs() < 1e-7);
        s.eval(1.0, 0.3, 0.9, 1.0, &mut out);
        assert!((out[0] - 1.0).abs() < 1e-7);
    }

    #[test]
    fn table_sampler_is_unbiased_for_albedo() {
        // E[f cos / pdf] over sampled directions equals the albedo by quadrature.
        let s = test_stack();
        let mu_given = 0.6;
        let n = 200_000;
        let mut rng = Rng::for_ray(3, 0, 0);
        let mut est = 0.0;
        let mut out = [0.0; MAX_BANDS];
        for _ in 0..n {
            let u = [rng.uniform(), rng.uniform(), rng.uniform(), rng.uniform(), rng.uniform()];
            let (mu, dphi) = s.sample_table(0.0, mu_given, u);
            let pdf = s.pdf_table(0.0, mu_given, mu, dphi.abs());
            s.eval(0.0, mu_given, mu, dphi.abs(), &mut out);
            est += out[0] * mu / pdf;
        }
        est /= n as f64;
        // Quadrature of ∫ f μ dω on a fine grid (midpoint in μ and Δφ).
        let (m, k) = (400, 400);
        let mut quad = 0.0;
        for a in 0..m {
            let mu = (a as f64 + 0.5) / m as f64;
            for b in 0..k {
                let p = PI * (b as f64 + 0.5) / k as f64;
                s.eval(0.0, mu_given, mu, p, &mut out);
                quad += out[0] * mu * (1.0 / m as f64) * (2.0 * PI / k as f64);
            }
        }
        assert!((est - quad).abs() < 0.01 * quad, "{est} vs {quad}");
    }

    #[test]
    fn table_pdf_integrates_to_one() {
        let s = test_stack();
        let (m, k) = (300, 300);
        let mut total = 0.0;
        for a in 0..m {
            let mu = (a as f64 + 0.5) / m as f64;
            for b in 0..k {
                let p = PI * (b as f64 + 0.5) / k as f64;
                total += s.pdf_table(0.4, 0.35, mu, p) * (1.0 / m as f64) * (2.0 * PI / k as f64);
            }
        }
        assert!((total - 1.0).abs() < 2e-3, "{total}");
    }

    #[test]
    fn table_sampler_passes_a_chi_square_test_against_its_pdf() {
        // Histogram of sampled (μ, |Δφ|) on a 10 × 12 grid against the pdf integrated over each
        // bin (midpoint rule on a 20 × 20 sub-grid); bins with fewer than 5 expected are pooled.
        let s = test_stack();
        let (level, mu_given, n) = (0.0, 0.45, 200_000usize);
        let (bm, bp) = (10usize, 12usize);
        let mut counts = vec![0.0; bm * bp];
        let mut rng = Rng::for_ray(17, 1, 2);
        for _ in 0..n {
            let u = [rng.uniform(), rng.uniform(), rng.uniform(), rng.uniform(), rng.uniform()];
            let (mu, dphi) = s.sample_table(level, mu_given, u);
            let a = ((mu * bm as f64) as usize).min(bm - 1);
            let b = ((dphi.abs() / PI * bp as f64) as usize).min(bp - 1);
            counts[a * bp + b] += 1.0;
        }
        let sub = 20;
        let (mut chi2, mut dof, mut pool_obs, mut pool_exp) = (0.0, 0i32, 0.0, 0.0);
        for a in 0..bm {
            for b in 0..bp {
                let mut p = 0.0;
                for i in 0..sub {
                    for j in 0..sub {
                        let mu = (a as f64 + (i as f64 + 0.5) / sub as f64) / bm as f64;
                        let ph = PI * (b as f64 + (j as f64 + 0.5) / sub as f64) / bp as f64;
                        // dω = dμ dφ, both signs of Δφ.
                        p += s.pdf_table(level, mu_given, mu, ph) * 2.0 * (1.0 / (bm * sub) as f64) * (PI / (bp * sub) as f64);
                    }
                }
                let expected = p * n as f64;
                if expected < 5.0 {
                    pool_obs += counts[a * bp + b];
                    pool_exp += expected;
                } else {
                    chi2 += (counts[a * bp + b] - expected).powi(2) / expected;
                    dof += 1;
                }
            }
        }
        if pool_exp > 0.0 {
            chi2 += (pool_obs - pool_exp).powi(2) / pool_exp.max(1e-12);
            dof += 1;
        }
        dof -= 1;
        // Wilson–Hilferty: the 99.9 % point of χ²(k) is about k (1 − 2/(9k) + 3.09 √(2/(9k)))³.
        let k = dof as f64;
        let limit = k * (1.0 - 2.0 / (9.0 * k) + 3.09 * (2.0 / (9.0 * k)).sqrt()).powi(3);
        assert!(chi2 < limit, "χ² = {chi2} with {dof} degrees of freedom (limit {limit})");
    }

    #[test]
    fn pair_cosines_round_trip() {
        let n = Vec3::new(0.2, -0.1, 1.0).normalized();
        let given = Vec3::new(0.5, 0.3, 0.6).normalized();
        let w = direction_from(n, given, 0.4, -2.0);
        let (ma, mb, cos_dphi) = pair_cosines(n, given, w);
        assert!((mb - 0.4).abs() < 1e-12 && (cos_dphi - 2.0f64.cos()).abs() < 1e-9 && (ma - given.dot(n)).abs() < 1e-12);
    }

    #[test]
    fn flat_tables_take_the_fast_path_with_the_same_values() {
        let mi = axis(3, 1.0);
        let mut f = vec![0.25f32; 27 * 2];
        for v in f[27..].iter_mut() {
            *v = 0.75;
        }
        let s = BrdfStack::new(2, mi.clone(), mi.clone(), axis(3, PI), 1, f.clone()).unwrap();
        assert!(s.flat.is_some());
        f[5] = 0.3;
        let t = BrdfStack::new(2, mi.clone(), mi, axis(3, PI), 1, f).unwrap();
        assert!(t.flat.is_none());
        let (mut a, mut b) = ([0.0; MAX_BANDS], [0.0; MAX_BANDS]);
        s.eval(0.4, 0.9, 0.9, 3.0, &mut a);
        t.eval(0.4, 0.9, 0.9, 3.0, &mut b);
        assert!((a[0] - 0.45).abs() < 1e-7 && (b[0] - 0.45).abs() < 1e-7);
    }

    #[test]
    fn rejects_bad_tables() {
        assert!(BrdfStack::new(1, vec![0.0, 1.0], vec![0.0, 0.9], vec![0.0, PI], 1, vec![0.0; 8]).is_err());
        assert!(BrdfStack::new(1, vec![0.0, 1.0], vec![0.0, 1.0], vec![0.0, PI], 1, vec![-1.0; 8]).is_err());
        assert!(BrdfStack::new(1, vec![0.0, 1.0], vec![0.0, 1.0], vec![0.0, PI], 1, vec![0.0; 7]).is_err());
    }
}

//! Tabulated isotropic spectral BRDFs, a stack of them for texture maps, and their sampling.
//!
//! A table holds f(λ_b, μ_i, μ_o, Δφ) in sr⁻¹ on a rectilinear grid: μ = cos θ on ascending axes
//! that include 0 and 1, Δφ = φ_o − φ_i folded into [0, π] (0: the viewer on the light's side,
//! backscatter), one value per render band. A *stack* is a list of such tables on the same grid,
//! the levels of a one-parameter family (16 saturations for the beach): a point with level
//! coordinate s ∈ [0, L−1] takes the linear blend of levels ⌊s⌋ and ⌊s⌋+1 (the brief's "interpolate
//! linearly between levels per point"). Within a level, lookup is trilinear in (μ_i, μ_o, Δφ).
//!
//! Sampling follows the table, exactly. The renderer draws the light direction ω_i given the view
//! direction ω_o. With ḡ the band mean of f, the trilinear lookup at (s, μ_o) is a blend
//! ḡ = Σ_c w_c ḡ_c of ≤ 4 *rows* c = (level, μ_o node), each ḡ_c bilinear in (μ_i, Δφ). The sampler
//! picks row c with probability w_c and draws ω_i with density ḡ_c(μ_i, Δφ) μ_i / A_c, A_c =
//! ∫ ḡ_c μ_i dω_i: a cell of the (μ_i, Δφ) grid by its exact integral, then Δφ from the cell's
//! linear marginal and μ_i from the quadratic conditional (bilinear ḡ × μ_i), the sign of Δφ a
//! fair coin. The pdf Σ_c w_c ḡ_c μ_i / A_c is then exact, and the band-mean weight
//! ḡ μ_i / pdf lies between the smallest and largest A_c: a narrow peak (the mirror reflection of
//! wet sand at grazing angles, 10³–10⁴ sr⁻¹ in one cell) is sampled in proportion to the
//! interpolated BRDF itself, not to a cell-constant stand-in for it, so it gives no fireflies.
//! The pdf is positive wherever some band of f is (ḡ > 0 there), so no defensive mixture is
//! needed; one would cost much here: with a share ε of cosine sampling, samples in the dim
//! diffuse part of a peaked BRDF get weights ≈ π ḡ/ε ≪ A, and the weight becomes two-valued
//! (relative sd 0.2 per sample on saturated sand at grazing view with ε = 0.1). A black row
//! (A_c = 0) is sampled by cosine.

use std::f64::consts::PI;

use crate::error::SandlightError;
use crate::math::Vec3;
use crate::sampling::cosine_hemisphere_angles;

/// Largest number of spectral bands a render may use (e.g. 31 for 400–700 nm every 10 nm).
pub const MAX_BANDS: usize = 32;

/// Spectrum of one path (only the first `n_bands` entries are meaningful).
pub type Spectrum = [f64; MAX_BANDS];

/// How outgoing directions are drawn from the BRDF side.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum BrdfSampling {
    /// pdf = cos θ / π (the paper's §4.2.1 choice).
    Cosine,
    /// Follows the tabulated BRDF exactly (module docs).
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
    /// Band-mean f, ordered (level, μ_o node, μ_i node, Δφ node): the sampling rows.
    mean_f: Vec<f64>,
    /// Inclusive cumulative probabilities of the (μ_i, Δφ) cells, per row (level, μ_o node).
    cell_cdf: Vec<f64>,
    /// A_c = ∫ ḡ_c μ_i dω_i of each row (both signs of Δφ); 0 for a black row (sampled by cosine).
    row_albedo: Vec<f64>,
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
        return Err(SandlightError::parameter(
            name,
            format!("{axis:?}"),
            &format!("an axis from {lo} to {hi} inclusive"),
        ));
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

impl BrdfStack {
    /// Builds a stack from its axes and values `f` (length n_levels·n_i·n_o·n_p·n_bands, order
    /// level, μ_i, μ_o, Δφ, band). Values must be finite and ≥ 0.
    pub fn new(
        n_levels: usize,
        mu_i: Vec<f64>,
        mu_o: Vec<f64>,
        dphi: Vec<f64>,
        n_bands: usize,
        f: Vec<f32>,
    ) -> Result<Self, SandlightError> {
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
            return Err(SandlightError::parameter(
                "f",
                format!("{} values", f.len()),
                &format!("{expected} values (levels × mu_i × mu_o × dphi × bands)"),
            ));
        }
        if let Some(bad) = f.iter().find(|v| !v.is_finite() || **v < 0.0) {
            return Err(SandlightError::parameter("f", bad, "finite BRDF values ≥ 0 sr⁻¹"));
        }
        let per_level = ni * no * np * n_bands;
        let is_flat = (0..n_levels).all(|l| {
            let block = &f[l * per_level..(l + 1) * per_level];
            block.chunks_exact(n_bands).all(|c| c == &block[..n_bands])
        });
        let flat =
            is_flat.then(|| (0..n_levels).flat_map(|l| f[l * per_level..l * per_level + n_bands].to_vec()).collect());
        let mut stack = BrdfStack {
            n_levels,
            mu_i,
            mu_o,
            dphi,
            n_bands,
            f,
            mean_f: Vec::new(),
            cell_cdf: Vec::new(),
            row_albedo: Vec::new(),
            flat,
        };
        // Band means in row order (level, μ_o node, μ_i node, Δφ node).
        let mut mean_f = vec![0.0; n_levels * no * ni * np];
        for l in 0..n_levels {
            for o in 0..no {
                for i in 0..ni {
                    for p in 0..np {
                        let idx = stack.index(l, i, o, p);
                        let sum: f64 = stack.f[idx..idx + n_bands].iter().map(|&v| v as f64).sum();
                        mean_f[((l * no + o) * ni + i) * np + p] = sum / n_bands as f64;
                    }
                }
            }
        }
        stack.mean_f = mean_f;
        let n_cells = (ni - 1) * (np - 1);
        let mut cell_cdf = vec![0.0; n_levels * no * n_cells];
        let mut row_albedo = vec![0.0; n_levels * no];
        let mut weights = vec![0.0; n_cells];
        for row in 0..n_levels * no {
            for i in 0..ni - 1 {
                for p in 0..np - 1 {
                    let (h0, h1) = stack.cell_marginal(row, i, p);
                    // ∫∫ ḡ μ dμ dΔφ over the cell = Δμ ΔΔφ (H0 + H1)/2; ×2 for both signs of Δφ.
                    weights[i * (np - 1) + p] =
                        (stack.mu_i[i + 1] - stack.mu_i[i]) * (stack.dphi[p + 1] - stack.dphi[p]) * (h0 + h1);
                }
            }
            let total: f64 = weights.iter().sum();
            row_albedo[row] = total;
            let cdf = &mut cell_cdf[row * n_cells..(row + 1) * n_cells];
            let mut acc = 0.0;
            for (c, w) in cdf.iter_mut().zip(&weights) {
                acc += if total > 0.0 { w / total } else { 0.0 };
                *c = acc;
            }
            // From the last cell of positive weight on, 1: rounding never sends u < 1 past it.
            let last = weights.iter().rposition(|&w| w > 0.0).unwrap_or(n_cells - 1);
            cdf[last..].iter_mut().for_each(|c| *c = 1.0);
        }
        stack.cell_cdf = cell_cdf;
        stack.row_albedo = row_albedo;
        Ok(stack)
    }

    /// Band-mean corner values of cell (i, p) of sampling row `row`: [ḡ(i,p), ḡ(i+1,p), ḡ(i,p+1), ḡ(i+1,p+1)].
    #[inline]
    fn cell_corners(&self, row: usize, i: usize, p: usize) -> [f64; 4] {
        let (ni, np) = (self.mu_i.len(), self.dphi.len());
        let at = |ii: usize, pp: usize| self.mean_f[(row * ni + ii) * np + pp];
        [at(i, p), at(i + 1, p), at(i, p + 1), at(i + 1, p + 1)]
    }

    /// H0, H1 with ∫ ḡ(μ, Δφ) μ dμ = Δμ ((1 − y) H0 + y H1) at the fraction y of the cell's Δφ
    /// range (ḡ bilinear, exact): H = ḡ(μ0)(2μ0 + μ1)/6 + ḡ(μ1)(μ0 + 2μ1)/6 at each Δφ edge.
    #[inline]
    fn cell_marginal(&self, row: usize, i: usize, p: usize) -> (f64, f64) {
        let [g00, g10, g01, g11] = self.cell_corners(row, i, p);
        let (m0, m1) = (self.mu_i[i], self.mu_i[i + 1]);
        let (c0, c1) = ((2.0 * m0 + m1) / 6.0, (m0 + 2.0 * m1) / 6.0);
        (g00 * c0 + g10 * c1, g01 * c0 + g11 * c1)
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

    /// Sampling rows (level·n_o + μ_o node) and weights of level coordinate s and view cosine μ_o:
    /// the weights of the trilinear lookup, so that ḡ(·, μ_o, ·) = Σ w ḡ_row.
    #[inline]
    fn rows(&self, s: f64, mu_o: f64) -> [(usize, f64); 4] {
        let no = self.mu_o.len();
        let (o0, to) = bracket(&self.mu_o, mu_o);
        let [(l0, w0), (l1, w1)] = self.levels(s);
        [
            (l0 * no + o0, w0 * (1.0 - to)),
            (l0 * no + o0 + 1, w0 * to),
            (l1 * no + o0, w1 * (1.0 - to)),
            (l1 * no + o0 + 1, w1 * to),
        ]
    }

    /// Samples the light direction (μ_i, signed Δφ) for the view cosine `mu_o`, following the
    /// table (module docs). `u` are five uniforms in [0, 1).
    pub fn sample_table(&self, s: f64, mu_o: f64, u: [f64; 5]) -> (f64, f64) {
        // A flat table's rows are constant: its exact sampler is cosine sampling.
        if self.flat.is_some() {
            return cosine_hemisphere_angles([u[1], u[2]]);
        }
        let mut pick = u[0];
        let rows = self.rows(s, mu_o);
        let mut chosen = rows[0].0;
        for (row, w) in rows {
            if w <= 0.0 {
                continue;
            }
            chosen = row;
            if pick < w {
                break;
            }
            pick -= w;
        }
        if self.row_albedo[chosen] <= 0.0 {
            return cosine_hemisphere_angles([u[1], u[2]]);
        }
        let np1 = self.dphi.len() - 1;
        let n_cells = (self.mu_i.len() - 1) * np1;
        let cdf = &self.cell_cdf[chosen * n_cells..(chosen + 1) * n_cells];
        let c = cdf.partition_point(|&v| v <= u[1]).min(n_cells - 1);
        let (i, p) = (c / np1, c % np1);
        // Δφ: the cell's marginal is linear in y ∈ [0, 1], (1 − y) H0 + y H1; inverse CDF in the
        // cancellation-free form y = (H0 + H1) u / (H0 + √(H0² + (H1² − H0²) u)).
        let (h0, h1) = self.cell_marginal(chosen, i, p);
        let y = if h0 + h1 > 0.0 {
            ((h0 + h1) * u[3] / (h0 + (h0 * h0 + (h1 * h1 - h0 * h0) * u[3]).max(0.0).sqrt())).clamp(0.0, 1.0)
        } else {
            u[3]
        };
        // μ given Δφ: density ∝ ḡ(μ, y) μ with ḡ linear in μ, a quadratic in x = (μ − μ0)/Δμ.
        let [g00, g10, g01, g11] = self.cell_corners(chosen, i, p);
        let (c0, c1) = ((1.0 - y) * g00 + y * g01, (1.0 - y) * g10 + y * g11);
        let (m0, m1) = (self.mu_i[i], self.mu_i[i + 1]);
        let x = invert_linear_times_ramp(c0, c1, m0, m1 - m0, u[2]);
        let mu = (m0 + x * (m1 - m0)).clamp(m0, m1);
        let phi = self.dphi[p] + y * (self.dphi[p + 1] - self.dphi[p]);
        (mu, if u[4] < 0.5 { phi } else { -phi })
    }

    /// Solid-angle pdf of `sample_table` for the light direction (μ_i, |Δφ|) given `mu_o`.
    pub fn pdf_table(&self, s: f64, mu_o: f64, mu_i: f64, dphi: f64) -> f64 {
        if mu_i <= 0.0 {
            return 0.0;
        }
        let cosine = mu_i / PI;
        if self.flat.is_some() {
            return cosine; // as `sample_table`: cosine
        }
        let (i0, ti) = bracket(&self.mu_i, mu_i);
        let (p0, tp) = bracket(&self.dphi, dphi);
        let mut table = 0.0;
        for (row, w) in self.rows(s, mu_o) {
            if w <= 0.0 {
                continue;
            }
            let a = self.row_albedo[row];
            table += w * if a > 0.0 {
                let [g00, g10, g01, g11] = self.cell_corners(row, i0, p0);
                let g = (1.0 - tp) * ((1.0 - ti) * g00 + ti * g10) + tp * ((1.0 - ti) * g01 + ti * g11);
                g * mu_i / a
            } else {
                cosine
            };
        }
        table
    }
}

/// x ∈ [0, 1] with F(x) = u F(1) for the density q(x) = ((1 − x) c0 + x c1)(m0 + x d) ≥ 0
/// (a linear function times the ramp μ = m0 + x d): F is a cubic, solved by Newton's method
/// safeguarded by bisection (to 10⁻¹³, a dozen steps at most in practice).
#[inline]
fn invert_linear_times_ramp(c0: f64, c1: f64, m0: f64, d: f64, u: f64) -> f64 {
    // q(x) = a0 + a1 x + a2 x², F(x) = a0 x + a1 x²/2 + a2 x³/3.
    let b = c1 - c0;
    let (a0, a1, a2) = (c0 * m0, c0 * d + b * m0, b * d);
    let cdf = |x: f64| x * (a0 + x * (a1 / 2.0 + x * a2 / 3.0));
    let total = cdf(1.0);
    if total.is_nan() || total <= 0.0 {
        return u;
    }
    let target = u * total;
    // Start from the cosine-weighted solution (c0 = c1), μ² uniform in the cell.
    let mut x =
        if d > 0.0 { (((m0 * m0 + u * ((m0 + d) * (m0 + d) - m0 * m0)).sqrt() - m0) / d).clamp(0.0, 1.0) } else { u };
    let (mut lo, mut hi) = (0.0, 1.0);
    for _ in 0..60 {
        let r = cdf(x) - target;
        if r > 0.0 {
            hi = x
        } else {
            lo = x
        }
        let q = a0 + x * (a1 + x * a2);
        let mut next = if q > 0.0 { x - r / q } else { 0.5 * (lo + hi) };
        if !(next > lo && next < hi) {
            next = 0.5 * (lo + hi);
        }
        if (next - x).abs() < 1e-13 || hi - lo < 1e-13 {
            return next;
        }
        x = next;
    }
    x
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

    /// A test BRDF with a backscatter lobe (2 bands); `reciprocal = false` makes f depend on μ_i
    /// and μ_o differently, so that sampling the wrong axis would show.
    fn test_stack_with(reciprocal: bool) -> BrdfStack {
        let (mi, mo, dp) = (axis(9, 1.0), axis(7, 1.0), axis(13, PI));
        let mut f = Vec::new();
        for &a in &mi {
            for &b in &mo {
                for &p in &dp {
                    let tilt = if reciprocal { 1.0 } else { 0.2 + 2.0 * a * a };
                    let lobe = tilt * (1.0 + 2.0 * (-(p * p) / 0.5).exp() * (1.0 - a * b));
                    f.push((0.3 / PI * lobe) as f32);
                    f.push((0.6 / PI * lobe) as f32);
                }
            }
        }
        BrdfStack::new(1, mi, mo, dp, 2, f).unwrap()
    }

    fn test_stack() -> BrdfStack {
        test_stack_with(true)
    }

    /// Wet sand in caricature: a dim diffuse part and a mirror peak at μ_i = μ_o, Δφ = π that
    /// grows towards grazing as 1/μ² (10⁴ sr⁻¹ at the grazing node), on a grid dense near 0.
    fn peaked_stack() -> BrdfStack {
        let mu: Vec<f64> = vec![0.0, 0.02, 0.05, 0.1, 0.2, 0.35, 0.5, 0.7, 0.85, 1.0];
        let dp = axis(16, PI);
        let mut f = Vec::new();
        for (i, &a) in mu.iter().enumerate() {
            for o in 0..mu.len() {
                for p in 0..dp.len() {
                    let peak = if i == o && p == dp.len() - 1 { 4.0 / a.max(0.02).powi(2) } else { 0.0 };
                    f.push((0.05 / PI + peak) as f32);
                    f.push((0.2 / PI + 0.9 * peak) as f32);
                }
            }
        }
        BrdfStack::new(1, mu.clone(), mu, dp, 2, f).unwrap()
    }

    /// ∫ f(μ_i, mu_o, Δφ) μ_i dω_i of `band` by the midpoint rule on a fine grid.
    fn albedo_by_quadrature(s: &BrdfStack, level: f64, mu_o: f64, band: usize) -> f64 {
        let (m, k) = (2000, 600);
        let mut out = [0.0; MAX_BANDS];
        let mut quad = 0.0;
        for a in 0..m {
            let mu = (a as f64 + 0.5) / m as f64;
            for b in 0..k {
                let p = PI * (b as f64 + 0.5) / k as f64;
                s.eval(level, mu, mu_o, p, &mut out);
                quad += out[band] * mu * (1.0 / m as f64) * (2.0 * PI / k as f64);
            }
        }
        quad
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
        // E[f cos θ_i / pdf] over sampled light directions equals ∫ f μ_i dω_i by quadrature,
        // also for a non-reciprocal table (the sampler follows the light-direction axis).
        for reciprocal in [true, false] {
            let s = test_stack_with(reciprocal);
            let mu_o = 0.6;
            let n = 200_000;
            let mut rng = Rng::for_ray(3, 0, 0);
            let mut est = 0.0;
            let mut out = [0.0; MAX_BANDS];
            for _ in 0..n {
                let u = [rng.uniform(), rng.uniform(), rng.uniform(), rng.uniform(), rng.uniform()];
                let (mu, dphi) = s.sample_table(0.0, mu_o, u);
                let pdf = s.pdf_table(0.0, mu_o, mu, dphi.abs());
                s.eval(0.0, mu, mu_o, dphi.abs(), &mut out);
                est += out[0] * mu / pdf;
            }
            est /= n as f64;
            let quad = albedo_by_quadrature(&s, 0.0, mu_o, 0);
            assert!((est - quad).abs() < 0.005 * quad, "reciprocal {reciprocal}: {est} vs {quad}");
        }
    }

    #[test]
    fn a_mirror_peak_is_sampled_in_proportion_to_the_interpolated_brdf() {
        // The weights f cos θ_i / pdf of the band mean lie between the albedos of the rows blended
        // at μ_o: no fireflies from a peak of 10⁴ sr⁻¹ (on a node the weight is constant); their
        // mean is the albedo.
        let s = peaked_stack();
        for mu_o in [0.02, 0.035, 0.3] {
            let rows = s.rows(0.0, mu_o);
            let albedos = rows.iter().filter(|r| r.1 > 0.0).map(|r| s.row_albedo[r.0]);
            let (low, high) = albedos.fold((f64::INFINITY, 0.0f64), |(lo, hi), a| (lo.min(a), hi.max(a)));
            let mut rng = Rng::for_ray(11, 0, 0);
            let (n, mut sum, mut sum2, mut max, mut min) = (100_000, 0.0, 0.0, 0.0f64, f64::INFINITY);
            let mut out = [0.0; MAX_BANDS];
            for _ in 0..n {
                let u = [rng.uniform(), rng.uniform(), rng.uniform(), rng.uniform(), rng.uniform()];
                let (mu, dphi) = s.sample_table(0.0, mu_o, u);
                s.eval(0.0, mu, mu_o, dphi.abs(), &mut out);
                let w = 0.5 * (out[0] + out[1]) * mu / s.pdf_table(0.0, mu_o, mu, dphi.abs());
                sum += w;
                sum2 += w * w;
                max = max.max(w);
                min = min.min(w);
            }
            let mean = sum / n as f64;
            let rel_sd = (sum2 / n as f64 - mean * mean).max(0.0).sqrt() / mean;
            assert!(
                max <= high * (1.0 + 1e-9) && min >= low * (1.0 - 1e-9),
                "μ_o = {mu_o}: weights in [{min}, {max}], not in [{low}, {high}]"
            );
            if mu_o == 0.02 {
                assert!(rel_sd < 1e-6, "on a node: relative sd of the weights {rel_sd}");
            }
            let albedo = 0.5 * (albedo_by_quadrature(&s, 0.0, mu_o, 0) + albedo_by_quadrature(&s, 0.0, mu_o, 1));
            assert!((mean - albedo).abs() < 0.01 * albedo, "μ_o = {mu_o}: {mean} vs {albedo}");
        }
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
                        p += s.pdf_table(level, mu_given, mu, ph)
                            * 2.0
                            * (1.0 / (bm * sub) as f64)
                            * (PI / (bp * sub) as f64);
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
        assert!(
            (mb - 0.4).abs() < 1e-12 && (cos_dphi - 2.0f64.cos()).abs() < 1e-9 && (ma - given.dot(n)).abs() < 1e-12
        );
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

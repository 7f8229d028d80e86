//! A phase function tabulated at scattering-angle cosines, and exact sampling of its
//! piecewise-linear interpolant.
//!
//! The table holds nodes −1 = μ_0 < μ_1 < … < μ_N = 1 and values p_i ≥ 0; between nodes the
//! phase function is taken linear in μ, normalised so that 2π ∫ p dμ = 1 (sr⁻¹). `sample`
//! inverts the cumulative distribution of that interpolant exactly (a quadratic on each
//! interval), so the only departure of sampled directions from the true phase function is the
//! interpolation error of the table, which the builder documents
//! (`mie::PHASE_TABLE_INTERVALS_PER_TERM`).

use crate::error::SandlightError;
use std::f64::consts::PI;

#[derive(Clone, Debug)]
pub struct PhaseTable {
    mu: Vec<f64>,
    /// Normalised node values (sr⁻¹).
    p: Vec<f64>,
    /// P(cos θ ≤ μ_i) of the interpolant: 0 at μ_0, exactly 1 at μ_N.
    cdf: Vec<f64>,
}

impl PhaseTable {
    /// A table from nodes `mu` (strictly increasing, from exactly −1 to exactly 1) and
    /// non-negative finite values `p` of any normalisation (rescaled to 2π ∫ p dμ = 1).
    pub fn new(mu: Vec<f64>, p: Vec<f64>) -> Result<PhaseTable, SandlightError> {
        let n = mu.len();
        if n < 2 || p.len() != n {
            return Err(SandlightError::parameter(
                "mu",
                format!("{n} nodes and {} values", p.len()),
                "at least 2 nodes and one value per node",
            ));
        }
        if mu[0] != -1.0
            || mu[n - 1] != 1.0
            || mu.windows(2).any(|w| w[1].partial_cmp(&w[0]) != Some(std::cmp::Ordering::Greater))
        {
            return Err(SandlightError::parameter("mu", "the nodes given", "strictly increasing from -1 to 1"));
        }
        if p.iter().any(|v| !(v.is_finite() && *v >= 0.0)) {
            return Err(SandlightError::parameter("p", "the values given", "finite values >= 0"));
        }
        let mut cdf = Vec::with_capacity(n);
        cdf.push(0.0);
        for i in 0..n - 1 {
            // Trapezoid: exact for the linear interpolant.
            cdf.push(cdf[i] + 0.5 * (mu[i + 1] - mu[i]) * (p[i] + p[i + 1]));
        }
        let total = cdf[n - 1];
        if !(total > 0.0 && total.is_finite()) {
            return Err(SandlightError::parameter("p", total, "a phase function with a positive, finite integral"));
        }
        cdf.iter_mut().for_each(|c| *c /= total);
        cdf[n - 1] = 1.0;
        let scale = 1.0 / (2.0 * PI * total);
        let p = p.iter().map(|v| v * scale).collect();
        Ok(PhaseTable { mu, p, cdf })
    }

    pub fn nodes(&self) -> &[f64] {
        &self.mu
    }

    /// The normalised node values (sr⁻¹).
    pub fn values(&self) -> &[f64] {
        &self.p
    }

    /// P(cos θ ≤ μ_i) at the nodes.
    pub fn cumulative(&self) -> &[f64] {
        &self.cdf
    }

    /// The interval j with μ_j ≤ μ ≤ μ_{j+1}.
    fn interval(&self, mu: f64) -> usize {
        self.mu.partition_point(|&m| m <= mu).clamp(1, self.mu.len() - 1) - 1
    }

    /// The interpolated phase function at μ in [−1, 1] (sr⁻¹).
    pub fn pdf(&self, mu: f64) -> f64 {
        let j = self.interval(mu);
        let t = (mu - self.mu[j]) / (self.mu[j + 1] - self.mu[j]);
        self.p[j] + t * (self.p[j + 1] - self.p[j])
    }

    /// ⟨cos θ⟩ of the interpolant, exactly: on each interval ∫ μ f dμ with f = 2πp linear is
    /// h [μ_j f_j + μ_j Δf/2 + h f_j/2 + h Δf/3], h = μ_{j+1} − μ_j, Δf = f_{j+1} − f_j.
    pub fn mean_cosine(&self) -> f64 {
        let mut sum = 0.0;
        for j in 0..self.mu.len() - 1 {
            let (h, f0, df) = (self.mu[j + 1] - self.mu[j], self.p[j], self.p[j + 1] - self.p[j]);
            sum += h * (self.mu[j] * (f0 + 0.5 * df) + h * (0.5 * f0 + df / 3.0));
        }
        2.0 * PI * sum
    }

    /// The cosine μ of a scattering angle with P(cos θ ≤ μ) = `u` under the interpolant, for `u`
    /// in [0, 1]. On the interval j with cdf_j ≤ u < cdf_{j+1} the cumulative probability is
    /// cdf_j + h(f_j t + Δf t²/2) at μ_j + th (f = 2πp); its root is taken in the form
    /// t = 2r/(f_j + √(f_j² + 2Δf r)), r = (u − cdf_j)/h, which has no cancellation for either
    /// sign of Δf. Intervals of zero probability are never chosen.
    #[inline]
    pub fn sample(&self, u: f64) -> f64 {
        let last = self.mu.len() - 2;
        let j = self.cdf.partition_point(|&c| c <= u).clamp(1, last + 1) - 1;
        let h = self.mu[j + 1] - self.mu[j];
        let f0 = 2.0 * PI * self.p[j];
        let df = 2.0 * PI * (self.p[j + 1] - self.p[j]);
        let r = (u - self.cdf[j]).max(0.0) / h;
        let root = (f0 * f0 + 2.0 * df * r).max(0.0).sqrt();
        let t = if f0 + root > 0.0 { (2.0 * r / (f0 + root)).min(1.0) } else { 0.0 };
        self.mu[j] + t * h
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mie::MieSolution;
    use crate::rng::Rng;
    use num_complex::Complex64;

    fn table(m: (f64, f64), x: f64) -> (MieSolution, PhaseTable) {
        let s = MieSolution::new(Complex64::new(m.0, m.1), x).unwrap();
        let t = s.phase_table().unwrap();
        (s, t)
    }

    #[test]
    fn sample_inverts_the_cumulative_distribution() {
        // At the nodes exactly (except either end of the flat interval, where any μ in it is an
        // inverse), and within each interval the cumulative probability of the sampled μ
        // (integrated in closed form) gives back u.
        let t = PhaseTable::new(vec![-1.0, -0.2, 0.0, 0.5, 1.0], vec![0.3, 0.0, 0.0, 2.0, 5.0]).unwrap();
        for i in [0, 3, 4] {
            assert!((t.sample(t.cumulative()[i]) - t.nodes()[i]).abs() < 1e-15, "node {i}");
        }
        for k in 0..=1000 {
            let u = k as f64 / 1000.0;
            let mu = t.sample(u);
            let j = t.interval(mu);
            let (m0, p0) = (t.nodes()[j], t.values()[j]);
            let slope = (t.values()[j + 1] - p0) / (t.nodes()[j + 1] - m0);
            let d = mu - m0;
            let cdf = t.cumulative()[j] + 2.0 * PI * (p0 * d + 0.5 * slope * d * d);
            assert!((cdf - u).abs() < 1e-14, "u = {u}: μ = {mu}, F(μ) = {cdf}");
            // Never inside the flat (zero) interval (−0.2, 0).
            assert!(!(mu > -0.2 && mu < 0.0), "u = {u}: μ = {mu}");
        }
    }

    #[test]
    fn rejects_bad_tables() {
        assert!(PhaseTable::new(vec![-1.0, 1.0], vec![1.0]).is_err());
        assert!(PhaseTable::new(vec![-0.9, 1.0], vec![1.0, 1.0]).is_err());
        assert!(PhaseTable::new(vec![-1.0, 0.5, 0.5, 1.0], vec![1.0; 4]).is_err());
        assert!(PhaseTable::new(vec![-1.0, 1.0], vec![1.0, -1.0]).is_err());
        assert!(PhaseTable::new(vec![-1.0, 1.0], vec![0.0, 0.0]).is_err());
        assert!(PhaseTable::new(vec![-1.0, 1.0], vec![f64::NAN, 1.0]).is_err());
    }

    #[test]
    fn mie_table_accuracy() {
        // Total-variation distance ½∫|p_table − p| dΩ (Simpson's rule on each table interval) and
        // the error of the table's g, against the exact series: the figures documented at
        // PHASE_TABLE_INTERVALS_PER_TERM (hematite at x = 1000 is left out for the run time of
        // debug builds; it measured TV 5.4·10⁻⁵, |Δg| 7.5·10⁻⁶).
        let cases = [(1.54, 1e-8, 1.0), (1.54, 1e-8, 10.0), (1.54, 1e-8, 100.0), (1.54, 1e-8, 1000.0)];
        let cases = cases.into_iter().chain([1.0, 10.0, 100.0].map(|x| (3.0, 0.5, x)));
        for (n, k, x) in cases {
            let (s, t) = table((n, k), x);
            let mu = t.nodes();
            // The node values are the exact ones times the table's normalisation constant.
            let scale = t.values()[0] / s.phase_function(-1.0);
            let mut tv = 0.0;
            for j in 0..mu.len() - 1 {
                let mid = 0.5 * (mu[j] + mu[j + 1]);
                let mid = (t.pdf(mid) - s.phase_function(mid)).abs();
                let ends = (t.values()[j] + t.values()[j + 1]) * (1.0 - 1.0 / scale).abs();
                tv += (mu[j + 1] - mu[j]) / 6.0 * (ends + 4.0 * mid);
            }
            tv *= PI; // ½ · 2π
            let dg = (t.mean_cosine() - s.efficiencies().g).abs();
            assert!(tv < 2e-4 && dg < 1e-5, "m = {n}+{k}i, x = {x}: TV = {tv:.2e}, |Δg| = {dg:.2e}");
        }
    }

    #[test]
    fn sampled_mean_cosine_is_g() {
        // Mean of 10⁶ sampled cos θ against the exact g, within 4 standard errors.
        for (m, x) in [((3.0, 0.5), 3.0), ((1.54, 1e-8), 20.0), ((2.4, 0.6), 200.0), ((1.56, 1e-4), 0.5)] {
            let (s, t) = table(m, x);
            let mut rng = Rng::for_ray(17, 0, 0);
            let n = 1_000_000;
            let (mut sum, mut sum2) = (0.0, 0.0);
            for _ in 0..n {
                let mu = t.sample(rng.uniform());
                sum += mu;
                sum2 += mu * mu;
            }
            let mean = sum / n as f64;
            let se = ((sum2 / n as f64 - mean * mean) / n as f64).sqrt();
            let g = s.efficiencies().g;
            assert!((mean - g).abs() < 4.0 * se, "m = {m:?}, x = {x}: mean {mean}, g {g}, se {se:.1e}");
        }
    }

    #[test]
    fn samples_follow_the_interpolant() {
        // Pearson's chi-square over bins whose edges are table nodes, chosen near equal
        // probability, with expected counts from the trapezoid cumulative (independent of
        // `sample`). A correct sampler gives χ²(bins − 1); the bound is its 0.9999 quantile.
        let (_, t) = table((2.6, 0.05), 30.0);
        let cdf = t.cumulative();
        let mut edges: Vec<usize> = (0..=64).map(|i| cdf.partition_point(|&c| c < i as f64 / 64.0)).collect();
        edges.dedup();
        let bins = edges.len() - 1;
        let mut counts = vec![0u64; bins];
        let mut rng = Rng::for_ray(3, 1, 0);
        let n = 640_000;
        let nodes = t.nodes();
        for _ in 0..n {
            let mu = t.sample(rng.uniform());
            let i = edges.partition_point(|&e| nodes[e] <= mu).clamp(1, bins) - 1;
            counts[i] += 1;
        }
        let chi2: f64 = (0..bins)
            .map(|i| {
                let e = n as f64 * (cdf[edges[i + 1]] - cdf[edges[i]]);
                (counts[i] as f64 - e).powi(2) / e
            })
            .sum();
        let dof = (bins - 1) as f64;
        // Wilson–Hilferty: the 0.9999 quantile of χ²(ν) is ν(1 − 2/(9ν) + 3.719 √(2/(9ν)))³.
        let q = dof * (1.0 - 2.0 / (9.0 * dof) + 3.719 * (2.0 / (9.0 * dof)).sqrt()).powi(3);
        assert!(bins > 50 && chi2 < q, "χ² = {chi2} over {bins} bins (bound {q})");
    }
}

//! Lorenz–Mie scattering of a plane wave by a homogeneous sphere in a non-absorbing host.
//!
//! Conventions of Bohren & Huffman (1983, *Absorption and Scattering of Light by Small
//! Particles*, Wiley; "BH" below): time dependence e^(−iωt), so the relative index of an
//! absorbing sphere is m = n + ik with k ≥ 0, m = (particle index)/(host index); size parameter
//! x = 2πa n_host/λ = π d n_host/λ (λ in vacuum, a the radius, d the diameter). Efficiencies are
//! cross sections over the geometric cross section πa².
//!
//! Algorithm: BHMIE (BH Appendix A) with three changes for accuracy over 10⁻⁶ ≤ x ≤ 2·10⁴ and
//! large |m|x:
//! - the series is summed to n_max = ⌊x + 6 x^(1/3) + 3⌋ terms: Wiscombe's (1980) criterion
//!   x + 4.05 x^(1/3) + 2 (BH use x + 4x^(1/3) + 2) converges Q_sca and g to round-off, but the
//!   absorption and extinction series, whose terms fall as |a_n| rather than |a_n|², only to
//!   ~2·10⁻¹⁰ (measured, hematite at x = 50); 2x^(1/3) + 1 more terms bring them below 10⁻¹³;
//! - the logarithmic derivative D_n(mx) is computed by BH's downward recurrence (BH eq. 4.89)
//!   started at n_max from its exact value, the continued fraction of Lentz (1976) evaluated by
//!   the modified Lentz method (Thompson & Barnett 1986), as in Wiscombe's MIEV0. BH start at
//!   max(n_max, |mx|) + 15 with D = 0 instead, which is not enough for large real mx: the
//!   starting error is damped only beyond the turning point n ≈ |mx|, whose width grows as
//!   |mx|^(1/3) (measured: relative errors in D_n up to 10⁻² at mx = 100, median 7·10⁻² at
//!   mx = 1330);
//! - ψ_n(x) is computed from the same ratios, ψ_n = ψ_{n−1}/(ψ_{n−1}/ψ_n), instead of BH's
//!   upward recurrence, whose relative error grows as ε χ_n/ψ_n for n > x (and which at small x
//!   cancels already in ψ_1 = sin x/x − cos x). χ_n(x), the dominant solution, keeps BH's
//!   upward recurrence.
//!
//! Q_abs is summed term by term from an exact identity (derived below, `solve`) rather than as
//! Q_ext − Q_sca, and Q_ext = Q_sca + Q_abs: both are sums of non-negative terms, so neither
//! suffers the cancellation of Re(a_n) − |a_n|² in weakly absorbing or very small spheres. The
//! optical theorem, Q_ext = (2/x²) Σ (2n+1) Re(a_n + b_n) (BH eq. 4.62), is then an independent
//! check (tests).
//!
//! References: Lentz, W. J. (1976), Appl. Opt. 15, 668–671. Thompson, I. J. & Barnett, A. R.
//! (1986), J. Comput. Phys. 64, 490–509. Wiscombe, W. J. (1980), Appl. Opt. 19, 1505–1509.

use num_complex::Complex64;

use crate::error::{check_range, SandlightError};
use crate::phase_table::PhaseTable;

/// Domain of the size parameter x (tested at both ends).
pub const X_MIN: f64 = 1e-6;
pub const X_MAX: f64 = 2e4;
/// Domain of the relative index m = n + ik (tested at its corners against miepython).
pub const N_MIN: f64 = 0.5;
pub const N_MAX: f64 = 10.0;
pub const K_MAX: f64 = 10.0;
/// Smallest |m − 1|: the coefficients lose about ε/|m − 1| of their relative accuracy to the
/// cancellation in BH's numerators as the sphere's index approaches the host's (10⁻¹⁰ here).
pub const MIN_CONTRAST: f64 = 1e-6;

/// θ intervals per series term in `MieSolution::phase_table`. The phase function is a
/// polynomial of degree 2 n_max in μ, so its finest angular structure has period ≈ π/n_max:
/// 32 intervals per term put 32 nodes in each such period. The diffraction peak, which holds
/// about half the scattered light of a large sphere within θ ≈ 4/x (first Airy zero 3.83/x),
/// is tabulated `PHASE_TABLE_FORWARD_REFINEMENT` times finer out to θ =
/// `PHASE_TABLE_FORWARD_WIDTH`/x (1.5 % more nodes at x = 1000). Linear interpolation errors
/// fall as the square of the spacing; measured (test `phase_table::tests::mie_table_accuracy`,
/// quartz and hematite, 1 ≤ x ≤ 1000): total-variation distance between the tabulated and the
/// exact phase function below 2·10⁻⁴ (so any expectation of a function bounded by 1 is off by
/// less than 2·10⁻⁴) and |g_table − g| below 10⁻⁵.
pub const PHASE_TABLE_INTERVALS_PER_TERM: usize = 32;
pub const PHASE_TABLE_FORWARD_REFINEMENT: usize = 4;
pub const PHASE_TABLE_FORWARD_WIDTH: f64 = 16.0;
/// Fewest θ intervals of a phase-function table (small spheres, n_max of a few terms).
pub const PHASE_TABLE_MIN_INTERVALS: usize = 512;

/// Efficiencies and integral properties of one sphere.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Efficiencies {
    /// Extinction efficiency Q_ext = C_ext/(πa²).
    pub q_ext: f64,
    /// Scattering efficiency Q_sca.
    pub q_sca: f64,
    /// Absorption efficiency Q_abs = Q_ext − Q_sca (exactly 0 for k = 0).
    pub q_abs: f64,
    /// Asymmetry parameter g = ⟨cos θ⟩ of the phase function.
    pub g: f64,
    /// Single-scattering albedo ω = Q_sca/Q_ext.
    pub albedo: f64,
}

/// The Mie series of one sphere: coefficients a_n, b_n and the efficiencies derived from them.
#[derive(Clone, Debug)]
pub struct MieSolution {
    x: f64,
    a: Vec<Complex64>,
    b: Vec<Complex64>,
    /// (2n+1)/(n(n+1)) (a_n ± b_n): S1 ± S2 = Σ (2n+1)/(n(n+1)) (a_n ± b_n)(π_n ± τ_n) (BH eq.
    /// 4.74), half the products of S1 and S2 summed separately.
    s_plus: Vec<Complex64>,
    s_minus: Vec<Complex64>,
    /// ((2n+1)/n, (n+1)/n): the π_n recurrence without a division per term.
    pi_recurrence: Vec<(f64, f64)>,
    efficiencies: Efficiencies,
}

/// Number of series terms, ⌊x + 6 x^(1/3) + 3⌋ (Wiscombe's 1980 count plus 2x^(1/3) + 1, see
/// the module notes).
pub fn series_terms(x: f64) -> usize {
    (x + 6.0 * x.cbrt() + 3.0).floor() as usize
}

/// Ratios r_n(z) = ψ_{n−1}(z)/ψ_n(z), n = 1..=n_terms (entry n − 1), of the Riccati–Bessel
/// function ψ_n(z) = z j_n(z). They obey r_n = (2n+1)/z − 1/r_{n+1} (from ψ_{n+1} + ψ_{n−1} =
/// (2n+1)ψ_n/z), stable downwards; the log derivative is D_n = r_n − n/z (BH eq. 4.89 is the
/// same recurrence written for D_n). r_{n_terms} starts it from the continued fraction
/// r_N = b_0 − 1/(b_1 − 1/(b_2 − …)), b_j = (2N + 2j + 1)/z (Lentz 1976), which converges for
/// every z ≠ 0 because ψ_n is the minimal solution of the recurrence as n → ∞.
fn psi_ratios(z: Complex64, n_terms: usize) -> Vec<Complex64> {
    let mut r = vec![Complex64::new(0.0, 0.0); n_terms];
    r[n_terms - 1] = lentz_ratio(z, n_terms);
    let inv_z = 1.0 / z;
    for n in (1..n_terms).rev() {
        r[n - 1] = (2.0 * n as f64 + 1.0) * inv_z - 1.0 / r[n];
    }
    r
}

/// r_N(z) by the modified Lentz method (Thompson & Barnett 1986, §3; Numerical Recipes §5.2)
/// for f = b_0 + a_1/(b_1 + a_2/(b_2 + …)) with a_j = −1. The tail converges once 2(N + j) ≳ 2|z|
/// (past the turning point), so it takes about max(0, |z| − N) + O(|z|^(1/3)) steps; the cap is a
/// safety net far above that.
fn lentz_ratio(z: Complex64, n: usize) -> Complex64 {
    // Replaces an exactly vanishing partial denominator (possible for real z) so that the
    // recursion continues; Thompson & Barnett's prescription.
    const TINY: f64 = 1e-300;
    const EPS: f64 = 1e-16;
    let inv_z = 1.0 / z;
    let b = |j: usize| (2.0 * (n + j) as f64 + 1.0) * inv_z;
    let guard = |v: Complex64| if v == Complex64::new(0.0, 0.0) { Complex64::new(TINY, 0.0) } else { v };
    let mut f = guard(b(0));
    let (mut c, mut d) = (f, Complex64::new(0.0, 0.0));
    let cap = 2 * (z.norm() as usize + n) + 1000;
    for j in 1..cap {
        d = guard(b(j) - d).inv();
        c = guard(b(j) - 1.0 / c);
        let delta = c * d;
        f *= delta;
        if (delta - 1.0).norm() < EPS {
            break;
        }
    }
    f
}

impl MieSolution {
    /// Solves the sphere of relative index `m` = n + ik (k ≥ 0) and size parameter `x`.
    pub fn new(m: Complex64, x: f64) -> Result<MieSolution, SandlightError> {
        check_range("x", x, X_MIN, X_MAX)?;
        check_range("m.real", m.re, N_MIN, N_MAX)?;
        if !(m.im.is_finite() && (0.0..=K_MAX).contains(&m.im)) {
            return Err(SandlightError::parameter(
                "m.imag",
                m.im,
                &format!("must be in [0, {K_MAX}]: m = n + ik with k >= 0 for an absorbing sphere"),
            ));
        }
        if (m - 1.0).norm() < MIN_CONTRAST {
            return Err(SandlightError::parameter(
                "m",
                m,
                &format!("|m - 1| must be at least {MIN_CONTRAST} (a sphere matching its host scatters nothing)"),
            ));
        }
        Ok(Self::solve(m, x, series_terms(x)))
    }

    /// The series with `n_terms` terms (`new` uses `series_terms`; tests use more to measure the
    /// truncation error).
    fn solve(m: Complex64, x: f64, n_terms: usize) -> MieSolution {
        let r_mx = psi_ratios(m * x, n_terms);
        let r_x = psi_ratios(Complex64::new(x, 0.0), n_terms);
        let (sin_x, cos_x) = x.sin_cos();
        // ψ_0 = sin x; χ_{−1} = −sin x, χ_0 = cos x (BH Appendix A; χ_n = −x y_n(x), ξ_n = ψ_n − iχ_n).
        // ψ_n comes from the upward recurrence ψ_n = (2n − 1)ψ_{n−1}/x − ψ_{n−2} while n ≤ x, where
        // ψ oscillates and the recurrence is stable, and from the ratios beyond, where ψ_n decays
        // without zeros. ψ_{n−1}/r_n alone fails near a zero of ψ_{n−1}: at x = 5π (2.5 µm at
        // 500 nm in air) sin x ≈ 6e-16 left r_1 without a correct digit and Q_ext 26.6 for 2.29.
        let mut psi = sin_x;
        let mut psi_before = cos_x; // ψ_{−1} = cos x
        let (mut chi_prev, mut chi) = (-sin_x, cos_x);
        let mut a = Vec::with_capacity(n_terms);
        let mut b = Vec::with_capacity(n_terms);
        let (mut sum_sca, mut sum_abs) = (0.0, 0.0);
        for n in 1..=n_terms {
            let nf = n as f64;
            let psi_prev = psi;
            psi = if nf <= x { (2.0 * nf - 1.0) / x * psi_prev - psi_before } else { psi_prev / r_x[n - 1].re };
            psi_before = psi_prev;
            (chi_prev, chi) = (chi, (2.0 * nf - 1.0) / x * chi - chi_prev);
            let xi = Complex64::new(psi, -chi);
            let xi_prev = Complex64::new(psi_prev, -chi_prev);
            let d = r_mx[n - 1] - nf / (m * x);
            // BH eq. 4.88 with ψ_n'(mx)/ψ_n(mx) = D_n: a_n = (T_a ψ_n − ψ_{n−1})/(T_a ξ_n − ξ_{n−1}),
            // T_a = D_n/m + n/x, and b_n likewise with T_b = m D_n + n/x.
            let t_a = d / m + nf / x;
            let t_b = m * d + nf / x;
            let den_a = t_a * xi - xi_prev;
            let den_b = t_b * xi - xi_prev;
            let an = (t_a * psi - psi_prev) / den_a;
            let bn = (t_b * psi - psi_prev) / den_b;
            let w = 2.0 * nf + 1.0;
            sum_sca += w * (an.norm_sqr() + bn.norm_sqr());
            // Absorption per term. With N = Tψ_n − ψ_{n−1}, M = Tχ_n − χ_{n−1}, a = N/(N − iM):
            // Re a − |a|² = −Im(N M*)/|N − iM|², and Im(N M*) = Im(T)(ψ_{n−1}χ_n − ψ_nχ_{n−1}) =
            // Im(T), the Casoratian of the recurrence being constant and equal to its n = 0 value
            // cos²x + sin²x = 1. So Re a − |a|² = −Im(T)/|den|² ≥ 0 without cancellation.
            sum_abs += w * (-t_a.im / den_a.norm_sqr() - t_b.im / den_b.norm_sqr());
            a.push(an);
            b.push(bn);
        }
        let scale = 2.0 / (x * x);
        let q_sca = scale * sum_sca;
        let q_abs = scale * sum_abs;
        let q_ext = q_sca + q_abs;
        // BH eq. 4.74: Q_sca g = (4/x²) Σ [n(n+2)/(n+1) Re(a_n a*_{n+1} + b_n b*_{n+1})
        //                                   + (2n+1)/(n(n+1)) Re(a_n b*_n)].
        let mut sum_g = 0.0;
        for i in 0..n_terms {
            let nf = (i + 1) as f64;
            if i + 1 < n_terms {
                sum_g += nf * (nf + 2.0) / (nf + 1.0) * (a[i] * a[i + 1].conj() + b[i] * b[i + 1].conj()).re;
            }
            sum_g += (2.0 * nf + 1.0) / (nf * (nf + 1.0)) * (a[i] * b[i].conj()).re;
        }
        let g = 2.0 * scale * sum_g / q_sca;
        let order = |i: usize| (i + 1) as f64;
        let weight = |i: usize| (2.0 * order(i) + 1.0) / (order(i) * (order(i) + 1.0));
        let s_plus = (0..n_terms).map(|i| (a[i] + b[i]) * weight(i)).collect();
        let s_minus = (0..n_terms).map(|i| (a[i] - b[i]) * weight(i)).collect();
        let pi_recurrence =
            (0..n_terms).map(|i| ((2.0 * order(i) + 1.0) / order(i), (order(i) + 1.0) / order(i))).collect();
        let efficiencies = Efficiencies { q_ext, q_sca, q_abs, g, albedo: q_sca / q_ext };
        MieSolution { x, a, b, s_plus, s_minus, pi_recurrence, efficiencies }
    }

    pub fn x(&self) -> f64 {
        self.x
    }

    pub fn efficiencies(&self) -> Efficiencies {
        self.efficiencies
    }

    /// The coefficients a_n, n = 1..=n_max (entry n − 1), BH eq. 4.53/4.88.
    pub fn a(&self) -> &[Complex64] {
        &self.a
    }

    /// The coefficients b_n, n = 1..=n_max (entry n − 1).
    pub fn b(&self) -> &[Complex64] {
        &self.b
    }

    /// Scattering amplitudes (S1, S2) at scattering-angle cosine `mu` (BH eq. 4.74):
    /// S1 = Σ (2n+1)/(n(n+1)) (a_n π_n + b_n τ_n), S2 = Σ (2n+1)/(n(n+1)) (a_n τ_n + b_n π_n), with
    /// π_n, τ_n from BH eq. 4.47: π_0 = 0, π_1 = 1, π_{n+1} = ((2n+1) μ π_n − (n+1) π_{n−1})/n,
    /// τ_n = n μ π_n − (n+1) π_{n−1}. Dimensionless; dC_sca/dΩ = (|S1|² + |S2|²)/(2k²) for
    /// unpolarised light, k the wavenumber in the host.
    pub fn amplitudes(&self, mu: f64) -> (Complex64, Complex64) {
        let (plus, minus) = self.amplitude_sum_and_difference(mu);
        ((plus + minus) * 0.5, (plus - minus) * 0.5)
    }

    /// (S1 + S2, S1 − S2) at `mu`.
    #[inline]
    fn amplitude_sum_and_difference(&self, mu: f64) -> (Complex64, Complex64) {
        let (mut plus, mut minus) = (Complex64::new(0.0, 0.0), Complex64::new(0.0, 0.0));
        let (mut pi_prev, mut pi) = (0.0, 1.0);
        let terms = self.s_plus.iter().zip(&self.s_minus).zip(&self.pi_recurrence);
        for (i, ((sp, sm), &(c1, c2))) in terms.enumerate() {
            let nf = (i + 1) as f64;
            let tau = nf * mu * pi - (nf + 1.0) * pi_prev;
            plus += sp * (pi + tau);
            minus += sm * (pi - tau);
            (pi_prev, pi) = (pi, c1 * mu * pi - c2 * pi_prev);
        }
        (plus, minus)
    }

    /// Phase function p(μ) in sr⁻¹ for unpolarised light, normalised to ∫ p dΩ = 1:
    /// p = (|S1|² + |S2|²)/(2π x² Q_sca), since C_sca = Q_sca πa² and x = ka.
    pub fn phase_function(&self, mu: f64) -> f64 {
        // |S1|² + |S2|² = (|S1 + S2|² + |S1 − S2|²)/2.
        let (plus, minus) = self.amplitude_sum_and_difference(mu);
        (plus.norm_sqr() + minus.norm_sqr()) / (4.0 * std::f64::consts::PI * self.x * self.x * self.efficiencies.q_sca)
    }

    /// The phase function tabulated for sampling scattering angles (`PhaseTable`): nodes equally
    /// spaced in θ with step h = π/N, N = max(`PHASE_TABLE_MIN_INTERVALS`,
    /// `PHASE_TABLE_INTERVALS_PER_TERM` · n_max), and step h/`PHASE_TABLE_FORWARD_REFINEMENT`
    /// for θ < `PHASE_TABLE_FORWARD_WIDTH`/x (accuracy at `PHASE_TABLE_INTERVALS_PER_TERM`).
    pub fn phase_table(&self) -> Result<PhaseTable, SandlightError> {
        use std::f64::consts::PI;
        let n = PHASE_TABLE_MIN_INTERVALS.max(PHASE_TABLE_INTERVALS_PER_TERM * self.a.len());
        let h = PI / n as f64;
        // Coarse intervals covered by the refined forward region.
        let k_f = ((PHASE_TABLE_FORWARD_WIDTH / self.x / h).ceil() as usize).min(n);
        let r = PHASE_TABLE_FORWARD_REFINEMENT;
        // θ descending from π to 0, so μ = cos θ ascends from exactly −1 to exactly 1.
        let mut theta: Vec<f64> = (0..n - k_f).map(|i| PI - i as f64 * h).collect();
        theta.extend((0..=k_f * r).map(|j| (k_f * r - j) as f64 * h / r as f64));
        let mu: Vec<f64> = theta.iter().map(|t| t.cos()).collect();
        let p = mu.iter().map(|&m| self.phase_function(m)).collect();
        PhaseTable::new(mu, p)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::f64::consts::PI;

    fn solve(m: (f64, f64), x: f64) -> MieSolution {
        MieSolution::new(Complex64::new(m.0, m.1), x).unwrap()
    }

    fn rel(a: f64, b: f64) -> f64 {
        (a - b).abs() / b.abs()
    }

    /// Indices of the brief: quartz, kaolinite, hematite (two), magnetite; quartz and hematite
    /// in water (relative to n = 1.333); a bubble in water; Wiscombe's strongly absorbing case.
    const INDICES: [(f64, f64); 10] = [
        (1.54, 1e-8),
        (1.56, 1e-4),
        (3.0, 0.5),
        (2.6, 0.05),
        (2.4, 0.6),
        (1.54 / 1.333, 1e-8 / 1.333),
        (3.0 / 1.333, 0.5 / 1.333),
        (0.75, 0.0),
        (1.5, 0.0),
        (10.0, 10.0),
    ];

    /// Gauss–Legendre nodes and weights on [−1, 1] (Newton on P_n from Tricomi's initial guesses):
    /// exact for polynomials of degree ≤ 2n − 1.
    fn gauss_legendre(n: usize) -> Vec<(f64, f64)> {
        (0..n)
            .map(|i| {
                let mut t = (PI * (i as f64 + 0.75) / (n as f64 + 0.5)).cos();
                let mut dp = 0.0;
                for _ in 0..100 {
                    let (mut p0, mut p1) = (1.0, t);
                    for k in 2..=n {
                        let kf = k as f64;
                        (p0, p1) = (p1, ((2.0 * kf - 1.0) * t * p1 - (kf - 1.0) * p0) / kf);
                    }
                    dp = n as f64 * (t * p1 - p0) / (t * t - 1.0);
                    let step = p1 / dp;
                    t -= step;
                    if step.abs() < 1e-16 {
                        break;
                    }
                }
                (t, 2.0 / ((1.0 - t * t) * dp * dp))
            })
            .collect()
    }

    #[test]
    fn rayleigh_limit() {
        // BH eqs. 5.8 and 5.11: Q_sca = (8/3) x⁴ |L|², Q_abs = 4x Im L, L = (m² − 1)/(m² + 2), with
        // relative corrections O(x²); p(μ) → 3(1 + μ²)/(16π) (BH eq. 5.14 normalised) and g → 0.
        for &(n, k) in &INDICES[..9] {
            let m = Complex64::new(n, k);
            let l = (m * m - 1.0) / (m * m + 2.0);
            for x in [1e-6, 1e-4, 1e-3] {
                let e = solve((n, k), x).efficiencies();
                let tol = 10.0 * x * x;
                assert!(rel(e.q_sca, 8.0 / 3.0 * x.powi(4) * l.norm_sqr()) < tol, "m = {m}, x = {x}: {e:?}");
                if k > 0.0 {
                    assert!(rel(e.q_abs, 4.0 * x * l.im) < tol, "m = {m}, x = {x}: {e:?}");
                }
                assert!(e.g.abs() < tol, "m = {m}, x = {x}: {e:?}");
                let s = solve((n, k), x);
                for mu in [-1.0, -0.3, 0.0, 0.6, 1.0] {
                    assert!(rel(s.phase_function(mu), 3.0 * (1.0 + mu * mu) / (16.0 * PI)) < tol);
                }
            }
        }
    }

    #[test]
    fn non_absorbing_sphere_absorbs_nothing_and_obeys_the_optical_theorem() {
        // Q_abs is identically zero for k = 0; the optical theorem (BH eq. 4.62) is an independent
        // sum, equal to Q_sca = Q_ext up to round-off. That round-off is ε Σ (2n+1)|a_n| relative
        // to Re a_n ≈ |a_n|² (Re a_n ≪ |a_n| for small spheres), hence the bound.
        for &(n, _) in &INDICES {
            for x in [1e-3, 0.1, 1.0, 10.0, 100.0, 1000.0] {
                let s = solve((n, 0.0), x);
                let e = s.efficiencies();
                assert_eq!(e.q_abs, 0.0);
                assert_eq!(e.albedo, 1.0);
                let w = |i: usize| 2.0 * (i + 1) as f64 + 1.0;
                let theorem: f64 = s.a().iter().zip(s.b()).enumerate().map(|(i, (a, b))| w(i) * (a + b).re).sum();
                let bound: f64 =
                    s.a().iter().zip(s.b()).enumerate().map(|(i, (a, b))| w(i) * (a.norm() + b.norm())).sum();
                let theorem = theorem * 2.0 / (x * x);
                let bound = 1e-14 * bound * 2.0 / (x * x) + 1e-13 * e.q_sca;
                assert!((theorem - e.q_ext).abs() < bound, "n = {n}, x = {x}: {theorem} vs {e:?}");
            }
        }
    }

    #[test]
    fn absorbing_sphere_obeys_the_optical_theorem() {
        for &(n, k) in INDICES.iter().filter(|m| m.1 > 0.0) {
            for x in [0.01, 0.3, 3.0, 30.0, 300.0, 2000.0] {
                let s = solve((n, k), x);
                let e = s.efficiencies();
                assert!(e.q_abs > 0.0 && e.albedo < 1.0);
                let theorem: f64 =
                    s.a().iter().zip(s.b()).enumerate().map(|(i, (a, b))| (2.0 * i as f64 + 3.0) * (a + b).re).sum();
                let theorem = theorem * 2.0 / (x * x);
                assert!(rel(theorem, e.q_ext) < 1e-11, "m = {n}+{k}i, x = {x}: {theorem} vs {e:?}");
            }
        }
    }

    #[test]
    fn efficiencies_are_continuous_across_the_zeros_of_sin_x() {
        // At x = jπ, ψ_0 = sin x ≈ 1e-16: the efficiencies and the optical theorem there agree
        // with those a relative 1e-7 away on either side (a build that divided by the ratio
        // ψ_0/ψ_1 gave Q_ext 26.6 for 2.29 at hematite's index and x = 5π).
        for &(n, k) in &INDICES {
            for j in 1..=12 {
                let x = j as f64 * std::f64::consts::PI;
                let q = |x: f64| solve((n, k), x).efficiencies();
                let (at, below, above) = (q(x), q(x * (1.0 - 1e-7)), q(x * (1.0 + 1e-7)));
                let mean = 0.5 * (below.q_ext + above.q_ext);
                assert!(rel(at.q_ext, mean) < 1e-5, "m = {n}+{k}i, x = {j}π: {at:?} vs {mean}");
                assert!(rel(at.q_sca, 0.5 * (below.q_sca + above.q_sca)) < 1e-5, "m = {n}+{k}i, x = {j}π");
            }
        }
    }

    #[test]
    fn extinction_paradox() {
        // Q_ext → 2 as x → ∞ (BH §4.4.3), approached as x^(−2/3).
        for &(n, k) in &INDICES {
            let q = |x: f64| solve((n, k), x).efficiencies().q_ext;
            let (q200, q2000, q20000) = (q(200.0), q(2000.0), q(20000.0));
            assert!((q2000 - 2.0).abs() < 0.03, "m = {n}+{k}i: Q_ext(2000) = {q2000}");
            assert!((q20000 - 2.0).abs() < 0.01, "m = {n}+{k}i: Q_ext(20000) = {q20000}");
            assert!((q20000 - 2.0).abs() < (q200 - 2.0).abs(), "m = {n}+{k}i: {q200} {q20000}");
        }
    }

    #[test]
    fn series_truncation_error_is_negligible() {
        // n_max against 40 more terms: efficiencies, and amplitudes relative to S(0) (with
        // Wiscombe's count they differ by up to 2·10⁻⁹ of S(0) at large x).
        for &(n, k) in &INDICES {
            for x in [0.05, 1.0, 8.5, 50.0, 500.0, 2000.0] {
                let m = Complex64::new(n, k);
                let s = MieSolution::solve(m, x, series_terms(x));
                let t = MieSolution::solve(m, x, series_terms(x) + 40);
                let (e, f) = (s.efficiencies(), t.efficiencies());
                assert!(rel(e.q_ext, f.q_ext) < 1e-12 && rel(e.q_sca, f.q_sca) < 1e-12, "m = {m}, x = {x}");
                assert!((e.g - f.g).abs() < 1e-12, "m = {m}, x = {x}");
                let s0 = t.amplitudes(1.0).0.norm();
                for i in 0..=180 {
                    let mu = (PI * i as f64 / 180.0).cos();
                    let ((a1, a2), (b1, b2)) = (s.amplitudes(mu), t.amplitudes(mu));
                    assert!((a1 - b1).norm().max((a2 - b2).norm()) < 1e-13 * s0, "m = {m}, x = {x}, μ = {mu}");
                }
            }
        }
    }

    #[test]
    fn continued_fraction_start_matches_a_deep_downward_recurrence() {
        // BH's recurrence for D_n from D = 0 far above the turning point |z| converges to the
        // exact D_n; the Lentz start at n_max must give the same values.
        for z in [
            Complex64::new(1540.0, 0.0),
            Complex64::new(6000.0, 1000.0),
            Complex64::new(4800.0, 1200.0),
            Complex64::new(3.0, 0.5),
        ] {
            let n_terms = 1042;
            let r = psi_ratios(z, n_terms);
            let start = ((z.norm() + 8.0 * z.norm().cbrt()) as usize).max(n_terms) + 200;
            let mut d = Complex64::new(0.0, 0.0);
            let mut deep = vec![Complex64::new(0.0, 0.0); n_terms];
            for n in (1..=start).rev() {
                let nz = n as f64 / z;
                d = nz - 1.0 / (d + nz);
                if n <= n_terms {
                    deep[n - 1] = d;
                }
            }
            // deep[n − 1] now holds D_{n−1}; compare D_n = r_n − n/z for n = 1..n_terms − 1.
            for n in 1..n_terms {
                let dn = r[n - 1] - n as f64 / z;
                // Near a pole of D_n (real z) an absolute error δ in 1/D becomes δ|D|².
                let tol = 1e-13 * (1.0 + deep[n].norm()).powi(2);
                assert!((dn - deep[n]).norm() <= tol, "z = {z}, n = {n}: {dn} vs {}", deep[n]);
            }
        }
    }

    #[test]
    fn phase_function_is_normalised_and_gives_back_g() {
        // |S1|² + |S2|² is a polynomial of degree 2 n_max in μ: Gauss–Legendre with n_max + 1 nodes
        // integrates it, and μ times it, exactly. The g of BH eq. 4.74 is an independent sum.
        for &(n, k) in &INDICES {
            for x in [0.01, 1.0, 10.0, 100.0, 1000.0] {
                let s = solve((n, k), x);
                let nodes = gauss_legendre(s.a().len() + 1);
                let (mut norm, mut mean) = (0.0, 0.0);
                for &(mu, w) in &nodes {
                    let p = s.phase_function(mu);
                    norm += 2.0 * PI * w * p;
                    mean += 2.0 * PI * w * mu * p;
                }
                assert!((norm - 1.0).abs() < 1e-11, "m = {n}+{k}i, x = {x}: {norm}");
                assert!((mean - s.efficiencies().g).abs() < 1e-11, "m = {n}+{k}i, x = {x}: {mean}");
            }
        }
    }

    #[test]
    fn published_values() {
        // Wiscombe's MIEV0 test cases (NCAR/TN-140+STR, 1979, revised 1996), as printed to six or
        // seven digits in miepython's test suite (tests/test_nojit.py). Wiscombe writes m = n − ik;
        // here m = n + ik. Columns: m, x, Q_sca, g, Q_ext (NaN: not printed).
        let nan = f64::NAN;
        let cases = [
            ((0.75, 0.0), 10.0, 2.232265, 0.896473, nan),
            ((0.75, 0.0), 1000.0, 1.997908, 0.844944, nan),
            ((1.33, 1e-5), 1.0, 0.093923, 0.184517, nan),
            ((1.33, 1e-5), 100.0, 2.096594, 0.868959, nan),
            ((1.33, 1e-5), 10000.0, 1.723857, 0.907840, nan),
            ((1.5, 1.0), 1.0, 0.6634538, 0.192136, nan),
            ((1.5, 1.0), 10000.0, 1.236575, 0.846309, 2.004368),
            ((10.0, 10.0), 1.0, 2.049405, -0.110664, nan),
            ((10.0, 10.0), 100.0, 1.836785, 0.556215, nan),
            ((10.0, 10.0), 10000.0, 1.795393, 0.548194, nan),
        ];
        for (m, x, q_sca, g, q_ext) in cases {
            let e = solve(m, x).efficiencies();
            assert!((e.q_sca - q_sca).abs() < 1e-6, "m = {m:?}, x = {x}: {e:?}");
            assert!((e.g - g).abs() < 1e-6, "m = {m:?}, x = {x}: {e:?}");
            if q_ext.is_finite() {
                assert!((e.q_ext - q_ext).abs() < 1e-6, "m = {m:?}, x = {x}: {e:?}");
            }
        }
        // Wiscombe's case 12/13 (m = 1.5 − i, x = 0.055 and 0.056): Q_ext 0.101491, 0.103347.
        assert!((solve((1.5, 1.0), 0.055).efficiencies().q_ext - 0.101491).abs() < 1e-6);
        assert!((solve((1.5, 1.0), 0.056).efficiencies().q_ext - 0.103347).abs() < 1e-6);
        // BH Appendix A sample output: m = 1.55, a = 0.525 µm, λ = 0.6328 µm: Q_sca = Q_ext = 3.10543.
        let e = solve((1.55, 0.0), 2.0 * PI * 0.525 / 0.6328).efficiencies();
        assert!((e.q_sca - 3.10543).abs() < 1e-5 && (e.q_ext - 3.10543).abs() < 1e-5, "{e:?}");
        // Wiscombe's case 14 amplitudes (m = 1.5 − i, x = 1) at θ = 0°, 30°, …, 180°: his S are the
        // complex conjugates of BH's (opposite time convention).
        let s1 = [
            (0.584080, 0.190515),
            (0.565702, 0.187200),
            (0.517525, 0.178443),
            (0.456340, 0.167167),
            (0.400212, 0.156643),
            (0.362157, 0.149391),
            (0.348844, 0.146829),
        ];
        let s2 = [
            (0.584080, 0.190515),
            (0.500161, 0.145611),
            (0.287964, 0.041054),
            (0.0362285, -0.0618265),
            (-0.174875, -0.122959),
            (-0.305682, -0.143846),
            (-0.348844, -0.146829),
        ];
        let s = solve((1.5, 1.0), 1.0);
        for i in 0..7 {
            let (a1, a2) = s.amplitudes((PI * i as f64 / 6.0).cos());
            let (w1, w2) = (Complex64::new(s1[i].0, s1[i].1).conj(), Complex64::new(s2[i].0, s2[i].1).conj());
            assert!((a1 - w1).norm() < 2e-6 && (a2 - w2).norm() < 2e-6, "θ = {}°: {a1} {a2}", 30 * i);
        }
    }

    #[test]
    fn rejects_bad_input() {
        let bad = [
            (Complex64::new(1.5, 0.0), 0.0, "x"),
            (Complex64::new(1.5, 0.0), f64::NAN, "x"),
            (Complex64::new(1.5, 0.0), 3e4, "x"),
            (Complex64::new(0.4, 0.0), 1.0, "m.real"),
            (Complex64::new(f64::NAN, 0.0), 1.0, "m.real"),
            (Complex64::new(1.5, -0.01), 1.0, "m.imag"),
            (Complex64::new(1.5, f64::INFINITY), 1.0, "m.imag"),
            (Complex64::new(1.0, 0.0), 1.0, "m"),
        ];
        for (m, x, name) in bad {
            match MieSolution::new(m, x) {
                Err(SandlightError::Parameter { name: got, .. }) => assert_eq!(got, name, "m = {m}, x = {x}"),
                other => panic!("m = {m}, x = {x}: {other:?}"),
            }
        }
    }
}

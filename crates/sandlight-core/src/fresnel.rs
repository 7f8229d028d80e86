//! Unpolarised Fresnel reflectance of a plane interface.

/// Reflectance between two non-absorbing media, light coming from index `n1` into `n2`, with
/// incidence cosine `cos_i` in (0, 1]. Returns 1 on total internal reflection.
/// R = (|r_s|² + |r_p|²)/2 with r_s = (n₁cosθᵢ − n₂cosθₜ)/(n₁cosθᵢ + n₂cosθₜ),
/// r_p = (n₂cosθᵢ − n₁cosθₜ)/(n₂cosθᵢ + n₁cosθₜ) (Born & Wolf §1.5).
#[inline]
pub fn dielectric(n1: f64, n2: f64, cos_i: f64) -> f64 {
    let cos_i = cos_i.clamp(0.0, 1.0);
    let eta = n1 / n2;
    let sin2_t = eta * eta * (1.0 - cos_i * cos_i);
    if sin2_t >= 1.0 {
        return 1.0;
    }
    dielectric_cos(n1, n2, cos_i, (1.0 - sin2_t).sqrt())
}

/// `dielectric` when the transmitted cosine `cos_t` is already known (e.g. from the invariant
/// n sin θ in a layer stack), saving its square root. Requires cos_t > 0 (no TIR).
/// r_s = A/B and r_p = C/D are combined over one division: R = (A²D² + C²B²)/(2B²D²).
#[inline]
pub fn dielectric_cos(n1: f64, n2: f64, cos_i: f64, cos_t: f64) -> f64 {
    let (a, b) = (n1 * cos_i - n2 * cos_t, n1 * cos_i + n2 * cos_t);
    let (c, d) = (n2 * cos_i - n1 * cos_t, n2 * cos_i + n1 * cos_t);
    let (ad, cb, bd) = (a * d, c * b, b * d);
    (ad * ad + cb * cb) / (2.0 * bd * bd)
}

/// Reflectance from a non-absorbing medium `n1` into an absorbing one ñ₂ = `n2 + i k2`.
/// cos θₜ = √(1 − (n₁ sin θᵢ / ñ₂)²) is complex (docs/model.md §2.4); the principal branch has
/// Re ≥ 0, the physical (decaying) wave for k₂ ≥ 0.
///
/// Evaluated in real arithmetic through w = ñ₂ cos θₜ = √(ñ₂² − n₁² sin² θᵢ) (principal root:
/// ñ₂ and cos θₜ both lie in the first quadrant, so their product is the root with Re, Im ≥ 0):
/// r_s = (n₁cos θᵢ − w)/(n₁cos θᵢ + w) and, multiplying r_p's numerator and denominator by ñ₂,
/// r_p = (ñ₂² cos θᵢ − n₁ w)/(ñ₂² cos θᵢ + n₁ w). With z = ñ₂² − n₁² sin² θᵢ = x + iy (y ≥ 0),
/// the stable algebraic root has w_r² = (|z| + x)/2 (x ≥ 0) or w_i² = (|z| − x)/2 (x < 0), and
/// w_r w_i = y/2. Multiplying |r_s|² and |r_p|² top and bottom by w_r² (or w_i²) removes the
/// division y/(2w_r), and the two ratios share one division: two square roots, one division,
/// no cancellation beyond that of the differences themselves.
#[inline]
pub fn conductor(n1: f64, n2: f64, k2: f64, cos_i: f64) -> f64 {
    if k2 <= 0.0 {
        return dielectric(n1, n2, cos_i);
    }
    let c = cos_i.clamp(0.0, 1.0);
    // ñ₂² = (n² − k²) + i 2nk.
    let (m2r, m2i) = (n2 * n2 - k2 * k2, 2.0 * n2 * k2);
    let x = m2r - n1 * n1 * (1.0 - c * c);
    let modulus = (x * x + m2i * m2i).sqrt();
    let a = n1 * c;
    let (pr, pi) = (m2r * c, m2i * c);
    let h = 0.5 * m2i; // w_r w_i
                       // |r_s|² = [(a − w_r)² + w_i²]/[(a + w_r)² + w_i²]; |r_p|² = [(p_r − n₁w_r)² + (p_i − n₁w_i)²]/[…+…].
    let (ns, ds, np, dp) = if x >= 0.0 {
        let wr2 = 0.5 * (modulus + x);
        let wr = wr2.sqrt();
        // × w_r²: w_i² w_r² = h², (p_i − n₁w_i) w_r = p_i w_r − n₁h.
        let (sm, sp) = (a - wr, a + wr);
        let (pm, pp) = (pr - n1 * wr, pr + n1 * wr);
        let (qm, qp) = (pi * wr - n1 * h, pi * wr + n1 * h);
        (wr2 * sm * sm + h * h, wr2 * sp * sp + h * h, wr2 * pm * pm + qm * qm, wr2 * pp * pp + qp * qp)
    } else {
        let wi2 = 0.5 * (modulus - x);
        let wi = wi2.sqrt();
        // × w_i²: (a − w_r) w_i = a w_i − h, (p_r − n₁w_r) w_i = p_r w_i − n₁h.
        let (sm, sp) = (a * wi - h, a * wi + h);
        let (pm, pp) = (pr * wi - n1 * h, pr * wi + n1 * h);
        let (qm, qp) = (pi - n1 * wi, pi + n1 * wi);
        (sm * sm + wi2 * wi2, sp * sp + wi2 * wi2, pm * pm + wi2 * qm * qm, pp * pp + wi2 * qp * qp)
    };
    0.5 * (ns * dp + np * ds) / (ds * dp)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn normal_incidence() {
        // ((n1 − n2)/(n1 + n2))²
        assert!((dielectric(1.0, 1.5, 1.0) - 0.04).abs() < 1e-12);
        let (n, k) = (2.9, 1.3);
        let expect = ((n - 1.0f64).powi(2) + k * k) / ((n + 1.0f64).powi(2) + k * k);
        assert!((conductor(1.0, n, k, 1.0) - expect).abs() < 1e-12);
    }

    #[test]
    fn conductor_reduces_to_dielectric() {
        for c in [0.05, 0.3, 0.7, 1.0] {
            assert!((conductor(1.33, 1.54, 1e-12, c) - dielectric(1.33, 1.54, c)).abs() < 1e-9);
        }
    }

    /// The complex-number form of the same formula (polar complex square root), as reference.
    fn conductor_complex(n1: f64, n2: f64, k2: f64, cos_i: f64) -> f64 {
        use num_complex::Complex64;
        let m = Complex64::new(n2, k2);
        let sin_i = (1.0 - cos_i * cos_i).max(0.0).sqrt();
        let s = Complex64::new(n1 * sin_i, 0.0) / m;
        let cos_t = (Complex64::new(1.0, 0.0) - s * s).sqrt();
        let a = Complex64::new(n1 * cos_i, 0.0);
        let rs = (a - m * cos_t) / (a + m * cos_t);
        let rp = (m * cos_i - n1 * cos_t) / (m * cos_i + n1 * cos_t);
        0.5 * (rs.norm_sqr() + rp.norm_sqr())
    }

    #[test]
    fn conductor_matches_complex_form() {
        // Weak (quartz), strong (hematite, magnetite) and metal-like (k > n) absorbers, from air
        // and from water, including indices below n₁ sin θ (x < 0 branch of the root).
        for &(n1, n2, k2) in &[
            (1.0, 1.549, 4.4e-7),
            (1.333, 1.56, 1.2e-5),
            (1.0, 2.9, 1.3),
            (1.333, 2.34, 0.105),
            (1.0, 0.3, 3.0),
            (1.333, 1.1, 0.01),
        ] {
            for j in 0..=200 {
                let c = j as f64 / 200.0;
                let (fast, reference) = (conductor(n1, n2, k2, c), conductor_complex(n1, n2, k2, c));
                assert!(
                    (fast - reference).abs() <= 1e-12 * reference,
                    "n1 {n1} n2 {n2} k2 {k2} cos {c}: {fast} vs {reference}"
                );
            }
        }
    }

    #[test]
    fn grazing_and_tir() {
        assert!((dielectric(1.0, 1.5, 0.0) - 1.0).abs() < 1e-12);
        assert_eq!(dielectric(1.5, 1.0, 0.5), 1.0); // sin θ = 0.866 > 1/1.5
        assert!(dielectric(1.5, 1.0, 0.9) < 1.0);
    }

    #[test]
    fn reciprocity_of_dielectric_reflectance() {
        // R is the same from both sides at corresponding angles (Stokes relations).
        let (n1, n2, ci) = (1.0, 1.54, 0.6);
        let st = (1.0f64 - ci * ci).sqrt() * n1 / n2;
        let ct = (1.0 - st * st).sqrt();
        assert!((dielectric(n1, n2, ci) - dielectric(n2, n1, ct)).abs() < 1e-12);
    }
}

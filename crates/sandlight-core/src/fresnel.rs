//! Unpolarised Fresnel reflectance of a plane interface.

use num_complex::Complex64;

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
    let cos_t = (1.0 - sin2_t).sqrt();
    let rs = (n1 * cos_i - n2 * cos_t) / (n1 * cos_i + n2 * cos_t);
    let rp = (n2 * cos_i - n1 * cos_t) / (n2 * cos_i + n1 * cos_t);
    0.5 * (rs * rs + rp * rp)
}

/// Reflectance from a non-absorbing medium `n1` into an absorbing one ñ₂ = `n2 + i k2`.
/// cos θₜ = √(1 − (n₁ sin θᵢ / ñ₂)²) is complex (splits-model.md §2.4); the principal branch has
/// Re ≥ 0, the physical (decaying) wave for k₂ ≥ 0.
#[inline]
pub fn conductor(n1: f64, n2: f64, k2: f64, cos_i: f64) -> f64 {
    if k2 <= 0.0 {
        return dielectric(n1, n2, cos_i);
    }
    let cos_i = cos_i.clamp(0.0, 1.0);
    let m = Complex64::new(n2, k2);
    let sin_i = (1.0 - cos_i * cos_i).max(0.0).sqrt();
    let s = Complex64::new(n1 * sin_i, 0.0) / m;
    let cos_t = (Complex64::new(1.0, 0.0) - s * s).sqrt();
    let a = Complex64::new(n1 * cos_i, 0.0);
    let rs = (a - m * cos_t) / (a + m * cos_t);
    let rp = (m * cos_i - n1 * cos_t) / (m * cos_i + n1 * cos_t);
    0.5 * (rs.norm_sqr() + rp.norm_sqr())
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
        let st = (1.0 - ci * ci as f64).sqrt() * n1 / n2;
        let ct = (1.0 - st * st).sqrt();
        assert!((dielectric(n1, n2, ci) - dielectric(n2, n1, ct)).abs() < 1e-12);
    }
}

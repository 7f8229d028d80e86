//! Prolate spheroid grains: semi-axes (a, a, c), c = ε a ≥ a, symmetry axis `u`
//! (splits-model.md §2.3). Coordinates are relative to the centre, in the sample frame.

use crate::math::{sin_cos_turns, Vec3};
use crate::rng::Rng;

/// a/d = ε^(−1/3)/2 for a prolate spheroid of volume-equivalent diameter d and aspect ratio ε.
pub fn equatorial_ratio(eps: f64) -> f64 {
    0.5 * eps.powf(-1.0 / 3.0)
}

#[derive(Clone, Copy, Debug)]
pub struct Spheroid {
    /// Unit symmetry axis.
    pub u: Vec3,
    /// Equatorial semi-axis a (mm).
    pub a: f64,
    /// Polar semi-axis c = ε a (mm).
    pub c: f64,
    inv_a2: f64,
    /// k = 1/c² − 1/a² (≤ 0): the implicit surface is |x|²/a² + k (x·u)² = 1.
    k: f64,
}

/// The surface point a ray hits, with the outward normal there.
#[derive(Clone, Copy, Debug)]
pub struct Hit {
    pub point: Vec3,
    pub normal: Vec3,
}

impl Spheroid {
    /// Spheroid of volume-equivalent diameter `d` (mm) and aspect ratio `eps` ≥ 1:
    /// a = (d/2) ε^(−1/3), c = ε a (splits-model.md §2.3).
    pub fn new(d: f64, eps: f64, u: Vec3) -> Spheroid {
        Spheroid::with_semi_axis_ratio(d, equatorial_ratio(eps), eps, u)
    }

    /// Same as `new` with a = d·`a_over_d` precomputed (avoids a `powf` per particle).
    #[inline]
    pub fn with_semi_axis_ratio(d: f64, a_over_d: f64, eps: f64, u: Vec3) -> Spheroid {
        let a = d * a_over_d;
        let c = eps * a;
        Spheroid { u, a, c, inv_a2: 1.0 / (a * a), k: 1.0 / (c * c) - 1.0 / (a * a) }
    }

    /// Random orientation, uniform on the sphere.
    #[inline]
    pub fn random_axis(rng: &mut Rng) -> Vec3 {
        let z = 1.0 - 2.0 * rng.uniform();
        let r = (1.0 - z * z).max(0.0).sqrt();
        let (sin_phi, cos_phi) = sin_cos_turns(rng.uniform());
        Vec3::new(r * cos_phi, r * sin_phi, z)
    }

    #[inline]
    pub fn normal_at(&self, x: Vec3) -> Vec3 {
        // ∇(|x|²/a² + k (x·u)²)/2
        (x * self.inv_a2 + self.u * (self.k * x.dot(self.u))).normalized()
    }

    /// Quadratic coefficients (A, B/2) of |p + t d|²/a² + k((p + t d)·u)² − 1 in t.
    #[inline]
    fn quad(&self, p: Vec3, d: Vec3) -> (f64, f64, f64) {
        let du = d.dot(self.u);
        let pu = p.dot(self.u);
        let a = self.inv_a2 + self.k * du * du;
        let half_b = p.dot(d) * self.inv_a2 + self.k * pu * du;
        let c = p.norm2() * self.inv_a2 + self.k * pu * pu - 1.0;
        (a, half_b, c)
    }

    /// First intersection of the line `p + t d` (unit `d`) with the surface, if any.
    #[inline]
    pub fn intersect_from_outside(&self, p: Vec3, d: Vec3) -> Option<Hit> {
        let (a, hb, c) = self.quad(p, d);
        let disc = hb * hb - a * c;
        if disc <= 0.0 {
            return None;
        }
        let t = (-hb - disc.sqrt()) / a;
        let point = p + d * t;
        Some(Hit { point, normal: self.normal_at(point) })
    }

    /// Chord from the surface point `x0` along the inward direction `d` to the far surface.
    /// x0 is on the surface, so one root of the quadratic is 0 and the other is −B/A exactly;
    /// using it avoids the cancellation of the general formula.
    #[inline]
    pub fn chord_from_surface(&self, x0: Vec3, d: Vec3) -> (f64, Vec3) {
        let (a, hb, _) = self.quad(x0, d);
        let t = (-2.0 * hb / a).max(0.0);
        (t, x0 + d * t)
    }

    /// Area-weighted hit point for a ray with direction `d` meeting this particle
    /// (splits-model.md §2.3): a point uniform in the disc of the bounding sphere's radius c,
    /// perpendicular to the ray; on a miss, draw again. Returns None only if `max_tries` misses
    /// in a row (impossible in practice: the acceptance, shadow area over πc², is ≥ 1/ε²).
    ///
    /// Each try works in the frame (e₁, e₂, d): for p = x e₁ + y e₂ − 2c d the quadratic of
    /// `quad` needs only p·u = x u₁ + y u₂ − 2c u_d, p·d = −2c and |p|² = x² + y² + 4c², so a
    /// miss costs a few multiplications; the 3-D point and normal are formed for the hit only.
    #[inline]
    pub fn sample_hit(&self, d: Vec3, rng: &mut Rng, max_tries: u32) -> Option<Hit> {
        let (e1, e2) = d.orthonormal_basis();
        let (u1, u2, ud) = (self.u.dot(e1), self.u.dot(e2), self.u.dot(d));
        let (k, inv_a2) = (self.k, self.inv_a2);
        let two_c = 2.0 * self.c;
        // A and the constant parts of B/2 and C (see `quad`).
        let qa = inv_a2 + k * ud * ud;
        let pu0 = -two_c * ud;
        for _ in 0..max_tries {
            let r = self.c * rng.uniform().sqrt();
            let (s, co) = sin_cos_turns(rng.uniform());
            let (x, y) = (r * co, r * s);
            let pu = x * u1 + y * u2 + pu0;
            let half_b = -two_c * inv_a2 + k * pu * ud;
            let cc = (x * x + y * y + two_c * two_c) * inv_a2 + k * pu * pu - 1.0;
            let disc = half_b * half_b - qa * cc;
            if disc <= 0.0 {
                continue;
            }
            let t = (-half_b - disc.sqrt()) / qa;
            let point = e1 * x + e2 * y + d * (t - two_c);
            return Some(Hit { point, normal: self.normal_at(point) });
        }
        None
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn volume_equivalent_axes() {
        let s = Spheroid::new(0.3, 2.0, Vec3::new(0.0, 0.0, 1.0));
        // (4/3)π a² c = (π/6) d³
        assert!((s.a * s.a * s.c - 0.3f64.powi(3) / 8.0).abs() < 1e-15);
        assert!((s.c / s.a - 2.0).abs() < 1e-12);
    }

    #[test]
    fn hits_lie_on_surface_and_chords_end_on_surface() {
        let mut rng = Rng::for_ray(3, 0, 0);
        for _ in 0..1000 {
            let u = Spheroid::random_axis(&mut rng);
            let s = Spheroid::new(0.25, 1.7, u);
            let d = Spheroid::random_axis(&mut rng);
            let h = s.sample_hit(d, &mut rng, 1000).unwrap();
            let f = |x: Vec3| x.norm2() / (s.a * s.a) + s.k * x.dot(s.u).powi(2);
            assert!((f(h.point) - 1.0).abs() < 1e-9);
            assert!(h.normal.dot(d) < 0.0);
            let (l, x1) = s.chord_from_surface(h.point, d);
            assert!(l > 0.0 && l <= 2.0 * s.c + 1e-12);
            assert!((f(x1) - 1.0).abs() < 1e-9);
        }
    }

    #[test]
    fn sphere_impact_parameter_is_area_weighted() {
        // For a sphere, cos of the incidence angle is distributed as 2μ dμ: mean 2/3.
        let mut rng = Rng::for_ray(5, 0, 0);
        let s = Spheroid::new(1.0, 1.0, Vec3::new(0.0, 0.0, 1.0));
        let d = Vec3::new(0.0, 0.0, -1.0);
        let n = 100_000;
        let mean: f64 = (0..n).map(|_| -s.sample_hit(d, &mut rng, 100).unwrap().normal.dot(d)).sum::<f64>() / n as f64;
        assert!((mean - 2.0 / 3.0).abs() < 4.0 * (1.0f64 / 18.0).sqrt() / (n as f64).sqrt());
    }
}

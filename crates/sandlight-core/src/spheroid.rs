//! Prolate spheroid grains: semi-axes (a, a, c), c = ε a ≥ a, symmetry axis `u`
//! (docs/model.md §2.3). Coordinates are relative to the centre, in the sample frame.

use crate::math::{sin_cos_turns, Vec3};
use crate::rng::Rng;
use crate::sampling::uniform_sphere;

/// a/d = ε^(−1/3)/2 for a prolate spheroid of volume-equivalent diameter d and aspect ratio ε.
pub fn equatorial_ratio(eps: f64) -> f64 {
    0.5 * eps.powf(-1.0 / 3.0)
}

/// Surface of a prolate spheroid of aspect ratio ε over that of the sphere of equal volume:
/// S = 2πa²[1 + (c/(a e)) arcsin e], e² = 1 − 1/ε² (docs/model.md §2.3).
pub fn surface_factor(eps: f64) -> f64 {
    if eps <= 1.0 + 1e-12 {
        return 1.0;
    }
    let a = equatorial_ratio(eps);
    let c = eps * a;
    let e = (1.0 - 1.0 / (eps * eps)).sqrt();
    2.0 * a * a * (1.0 + c / (a * e) * e.asin())
}

#[derive(Clone, Copy, Debug, Default)]
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
    /// a = (d/2) ε^(−1/3), c = ε a (docs/model.md §2.3).
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
        uniform_sphere([rng.uniform(), rng.uniform()])
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
        // 1/A alongside the square root rather than after it.
        let inv_a = 1.0 / a;
        let t = (-hb - disc.sqrt()) * inv_a;
        let point = p + d * t;
        Some(Hit { point, normal: self.normal_at(point) })
    }

    /// Half the grain's extent along z (its support function in z): √(a² + (c² − a²)u_z²).
    #[inline]
    pub fn half_height(&self) -> f64 {
        self.half_height2().sqrt()
    }

    #[inline]
    fn half_height2(&self) -> f64 {
        self.a * self.a + (self.c * self.c - self.a * self.a) * self.u.z * self.u.z
    }

    /// The highest point (largest z, relative to the centre) where a ray along the unit
    /// direction `d` can enter: the top of the particle, or for a rising ray (d_z > 0) the top
    /// of its lit side, whose rim is the shadow terminator (n·d = 0). With x·Mx = 1 the
    /// surface, max z over x·Md = 0 is √(h² − d_z²ρ_d²): h the half height, ρ_d the radius
    /// along d (d·Md = 1/ρ_d²).
    #[inline]
    pub fn highest_entry(&self, d: Vec3) -> f64 {
        if d.z <= 0.0 {
            return self.half_height();
        }
        // 1/ρ_d² = |d|²/a² + k (d·u)².
        let inv_rho2 = d.norm2() * self.inv_a2 + self.k * d.dot(self.u).powi(2);
        (self.half_height2() - d.z * d.z / inv_rho2).max(0.0).sqrt()
    }

    /// Whether the point `x` (relative to the centre) lies strictly inside.
    #[inline]
    pub fn contains(&self, x: Vec3) -> bool {
        x.norm2() * self.inv_a2 + self.k * x.dot(self.u).powi(2) < 1.0
    }

    /// Distance t > 0 along the unit direction `d` from the point `p` outside the particle to
    /// where the ray enters it, if it does. A ray starting inside or on the surface gets None
    /// (a ray leaving a convex particle cannot meet it again). The root is taken in the form
    /// C/(−B/2 + √disc), free of cancellation for distant particles.
    #[inline]
    pub fn entry_distance(&self, p: Vec3, d: Vec3) -> Option<f64> {
        let (a, hb, c) = self.quad(p, d);
        if c <= 0.0 || hb >= 0.0 {
            return None;
        }
        let disc = hb * hb - a * c;
        if disc <= 0.0 {
            return None;
        }
        Some(c / (-hb + disc.sqrt()))
    }

    /// Whether the segment from `p0` to `p1` (relative to the centre) meets the particle:
    /// f(t) = |x|²/a² + k(x·u)² − 1 along it is a convex quadratic, so the segment meets the
    /// solid iff f ≤ 0 at an end or at the interior minimum.
    #[inline]
    pub fn intersects_segment(&self, p0: Vec3, p1: Vec3) -> bool {
        let v = p1 - p0;
        let len = v.norm2().sqrt();
        if len == 0.0 {
            return self.contains(p0);
        }
        // `quad` takes a unit direction: f(t) = A t² + 2 hb t + c for t ∈ [0, len].
        let (a, hb, c) = self.quad(p0, v * (1.0 / len));
        if c <= 0.0 || (a * len + 2.0 * hb) * len + c <= 0.0 {
            return true;
        }
        // Minimum at t* = −hb/A, inside the segment when 0 < t* < len.
        -hb > 0.0 && -hb < a * len && hb * hb > a * c
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

    /// Chord from the interior point `x0` (an internal scattering event) along the unit
    /// direction `d` to the surface: the positive root of f(t) = A t² + 2 hb t + c with c < 0,
    /// taken as −c/(hb + √disc) when hb > 0 (an exit close ahead) to avoid cancellation.
    #[inline]
    pub fn chord_from_inside(&self, x0: Vec3, d: Vec3) -> (f64, Vec3) {
        let (a, hb, c) = self.quad(x0, d);
        let root = (hb * hb - a * c).max(0.0).sqrt();
        let t = if hb > 0.0 { (-c / (hb + root)).max(0.0) } else { (-hb + root) / a };
        (t, x0 + d * t)
    }

    /// Area-weighted hit point for a ray with direction `d` meeting this particle
    /// (docs/model.md §2.3): a point uniform in the particle's shadow on the plane
    /// perpendicular to the ray, then the first intersection of the ray through it.
    ///
    /// The shadow of the spheroid |x|²/a² + k(x·u)² = 1 along d is an ellipse whose support
    /// function is the spheroid's, h(n)² = nᵀ(a² I + (c² − a²) u uᵀ) n, for n ⊥ d: semi-axis
    /// a along e⊥ = d × e∥, and b = √(a² + (c² − a²) sin²γ) along e∥, the unit projection of u
    /// on the plane (sin γ = |u − (u·d) d|). A point uniform in the unit disc (polar map, two
    /// uniforms) scaled by (a, b) is uniform in the shadow: the hit is weighted exactly by
    /// projected area with no misses to redraw (drawing in the bounding disc of radius c and
    /// redrawing on a miss gives the same law at 1/acceptance ≈ 1.6 times the cost for ε = 1.4,
    /// and unpredictable branches). A point on the very rim can still miss by rounding and is
    /// drawn again; None only after `max_tries` such misses in a row (never seen).
    #[inline(always)]
    pub fn sample_hit(&self, d: Vec3, rng: &mut Rng, max_tries: u32) -> Option<Hit> {
        let cos_g = self.u.dot(d);
        let v = self.u - d * cos_g;
        let sin2_g = v.norm2();
        // For u ∥ d the shadow is a circle of radius a and any perpendicular axis will do.
        let e_par = if sin2_g > 1e-24 { v * (1.0 / sin2_g.sqrt()) } else { d.orthonormal_basis().0 };
        let e_perp = d.cross(e_par);
        let a = self.a;
        let b = (a * a + (self.c * self.c - a * a) * sin2_g).sqrt();
        for _ in 0..max_tries {
            let r = rng.uniform().sqrt();
            let (s, co) = sin_cos_turns(rng.uniform());
            let p = e_perp * (a * r * co) + e_par * (b * r * s) - d * (2.0 * self.c);
            if let Some(h) = self.intersect_from_outside(p, d) {
                return Some(h);
            }
        }
        None
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn surface_factor_matches_known_values() {
        assert_eq!(surface_factor(1.0), 1.0);
        // ε = 2: e = √3/2, arcsin e = π/3, a² = 2^(−2/3)/4: S/π = 2a²(1 + (2/e)(π/3)) = 1.076728.
        assert!((surface_factor(2.0) - 1.076728).abs() < 1e-6, "{}", surface_factor(2.0));
    }

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
            // Every surface point lies within the half height, and the extreme one reaches it;
            // an entry point lies no higher than the top of the lit side.
            assert!(h.point.z.abs() <= s.half_height() * (1.0 + 1e-12));
            assert!(h.point.z <= s.highest_entry(d) + 1e-12 * s.c);
            assert!(x1.z.abs() <= s.half_height() * (1.0 + 1e-12));
            let z = Vec3::new(0.0, 0.0, 1.0);
            let top = (s.u * (s.c * s.c * s.u.z) + (z - s.u * s.u.z) * (s.a * s.a)) * (1.0 / s.half_height());
            assert!((f(top) - 1.0).abs() < 1e-9 && (top.z - s.half_height()).abs() < 1e-12);
        }
    }

    #[test]
    fn chords_from_inside_end_on_the_surface_ahead() {
        let mut rng = Rng::for_ray(5, 0, 0);
        let f = |s: &Spheroid, x: Vec3| x.norm2() / (s.a * s.a) + s.k * x.dot(s.u).powi(2);
        for _ in 0..1000 {
            let s = Spheroid::new(0.25, 1.7, Spheroid::random_axis(&mut rng));
            // A point inside: a surface point pulled towards the centre, also very close to it.
            let h = s.sample_hit(Spheroid::random_axis(&mut rng), &mut rng, 1000).unwrap();
            let x0 = h.point * [rng.uniform(), 1.0 - 1e-9][(rng.uniform() < 0.1) as usize];
            let d = Spheroid::random_axis(&mut rng);
            let (l, x1) = s.chord_from_inside(x0, d);
            assert!(l >= 0.0 && l <= 2.0 * s.c + 1e-12, "{l}");
            assert!((f(&s, x1) - 1.0).abs() < 1e-9, "{}", f(&s, x1));
            assert!((x1 - x0 - d * l).norm2() < 1e-24);
        }
        // From the centre of a sphere every chord is the radius.
        let ball = Spheroid::new(0.4, 1.0, Vec3::new(0.0, 0.0, 1.0));
        let (l, _) = ball.chord_from_inside(Vec3::new(0.0, 0.0, 0.0), Spheroid::random_axis(&mut rng));
        assert!((l - 0.2).abs() < 1e-12, "{l}");
    }

    #[test]
    fn highest_entry_is_reached_by_rising_rays() {
        let mut rng = Rng::for_ray(9, 0, 0);
        for _ in 0..20 {
            let s = Spheroid::new(0.25, 1.6, Spheroid::random_axis(&mut rng));
            let mut d = Spheroid::random_axis(&mut rng);
            d.z = d.z.abs().max(0.2);
            let d = d.normalized();
            let bound = s.highest_entry(d);
            let top = (0..20_000).map(|_| s.sample_hit(d, &mut rng, 1000).unwrap().point.z).fold(f64::MIN, f64::max);
            // Safe (no entry above it) and tight (sampled entries come close: the rim is thin).
            assert!(top <= bound + 1e-12 && top >= bound - 0.05 * s.c, "{top} vs {bound}");
        }
    }

    #[test]
    fn shadow_sampling_matches_bounding_disc_rejection() {
        // Reference: a point uniform in the disc of radius c ⊥ d, redrawn on a miss, which is
        // area-weighted by construction. Compare the means of μ = −n·d, (x·u)²/c² and (x·e)²/c²
        // for an axis e ⊥ d, at several tilts γ of the symmetry axis (4 sd bounds).
        let d = Vec3::new(0.0, 0.0, -1.0);
        let n = 60_000;
        for (j, gamma_deg) in [0.0f64, 25.0, 60.0, 90.0].into_iter().enumerate() {
            let g = gamma_deg.to_radians();
            let s = Spheroid::new(0.3, 2.5, Vec3::new(g.sin(), 0.0, g.cos()));
            let stats = |h: Hit| [-h.normal.dot(d), (h.point.dot(s.u) / s.c).powi(2), (h.point.y / s.c).powi(2)];
            let mut rng = Rng::for_ray(13, j as u64, 0);
            let fast: Vec<[f64; 3]> = (0..n).map(|_| stats(s.sample_hit(d, &mut rng, 100).unwrap())).collect();
            let (e1, e2) = d.orthonormal_basis();
            let reference: Vec<[f64; 3]> = (0..n)
                .map(|_| loop {
                    let r = s.c * rng.uniform().sqrt();
                    let phi = 2.0 * std::f64::consts::PI * rng.uniform();
                    let p = e1 * (r * phi.cos()) + e2 * (r * phi.sin()) - d * (2.0 * s.c);
                    if let Some(h) = s.intersect_from_outside(p, d) {
                        break stats(h);
                    }
                })
                .collect();
            for k in 0..3 {
                let mean = |v: &[[f64; 3]]| v.iter().map(|x| x[k]).sum::<f64>() / n as f64;
                let var = |v: &[[f64; 3]], m: f64| v.iter().map(|x| (x[k] - m).powi(2)).sum::<f64>() / n as f64;
                let (mf, mr) = (mean(&fast), mean(&reference));
                let se = ((var(&fast, mf) + var(&reference, mr)) / n as f64).sqrt();
                assert!((mf - mr).abs() < 4.0 * se, "γ {gamma_deg}°, statistic {k}: {mf} vs {mr} (se {se})");
            }
        }
    }

    #[test]
    fn segment_test_agrees_with_dense_point_sampling() {
        let mut rng = Rng::for_ray(8, 0, 0);
        for _ in 0..2000 {
            let s = Spheroid::new(0.3, 1.6, Spheroid::random_axis(&mut rng));
            let p = |rng: &mut Rng| Vec3::new(rng.uniform() - 0.5, rng.uniform() - 0.5, rng.uniform() - 0.5) * 0.8;
            let (p0, p1) = (p(&mut rng), p(&mut rng));
            let sampled = (0..=4000).any(|i| s.contains(p0 + (p1 - p0) * (i as f64 / 4000.0)));
            let exact = s.intersects_segment(p0, p1);
            // Dense sampling can only miss a grazing intersection.
            assert!(exact || !sampled, "{p0:?} {p1:?}");
            if exact && !sampled {
                let grazing = (0..=4000).any(|i| {
                    let x = p0 + (p1 - p0) * (i as f64 / 4000.0);
                    x.norm2() / (s.a * s.a) + s.k * x.dot(s.u).powi(2) < 1.0 + 1e-3
                });
                assert!(grazing, "{p0:?} {p1:?}");
            }
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

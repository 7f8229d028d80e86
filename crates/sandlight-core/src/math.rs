//! Small 3-vector maths used by the transport (z is the outward surface normal of the sample).

use std::ops::{Add, Mul, Neg, Sub};

#[derive(Clone, Copy, Debug, PartialEq, Default)]
pub struct Vec3 {
    pub x: f64,
    pub y: f64,
    pub z: f64,
}

impl Vec3 {
    #[inline]
    pub const fn new(x: f64, y: f64, z: f64) -> Self {
        Vec3 { x, y, z }
    }
    #[inline]
    pub fn dot(self, o: Vec3) -> f64 {
        self.x * o.x + self.y * o.y + self.z * o.z
    }
    #[inline]
    pub fn cross(self, o: Vec3) -> Vec3 {
        Vec3::new(self.y * o.z - self.z * o.y, self.z * o.x - self.x * o.z, self.x * o.y - self.y * o.x)
    }
    #[inline]
    pub fn norm2(self) -> f64 {
        self.dot(self)
    }
    #[inline]
    pub fn normalized(self) -> Vec3 {
        self * (1.0 / self.norm2().sqrt())
    }
    /// `normalized` for a vector that is unit up to rounding (|v|² = 1 + δ, |δ| ≤ 1e-9), e.g. a
    /// direction computed from unit vectors: one Newton step for 1/√(1 + δ), v (3 − |v|²)/2,
    /// leaves an error O(δ²) without a square root or division. Falls back to `normalized`
    /// for anything further from unit length.
    #[inline]
    pub fn renormalized(self) -> Vec3 {
        let e = self.norm2();
        if (e - 1.0).abs() <= 1e-9 {
            self * (1.5 - 0.5 * e)
        } else {
            self.normalized()
        }
    }
    /// Two unit vectors completing `self` (unit) to a right-handed orthonormal basis
    /// (Duff et al. 2017, "Building an orthonormal basis, revisited": branchless and robust).
    #[inline]
    pub fn orthonormal_basis(self) -> (Vec3, Vec3) {
        let sign = 1.0_f64.copysign(self.z);
        let a = -1.0 / (sign + self.z);
        let b = self.x * self.y * a;
        (
            Vec3::new(1.0 + sign * self.x * self.x * a, sign * b, -sign * self.x),
            Vec3::new(b, sign + self.y * self.y * a, -self.y),
        )
    }
    /// Mirror reflection of direction `self` about the plane with unit normal `n`.
    #[inline]
    pub fn reflect(self, n: Vec3) -> Vec3 {
        self - n * (2.0 * self.dot(n))
    }
    #[inline]
    pub fn is_finite(self) -> bool {
        self.x.is_finite() && self.y.is_finite() && self.z.is_finite()
    }
}

impl Add for Vec3 {
    type Output = Vec3;
    #[inline]
    fn add(self, o: Vec3) -> Vec3 {
        Vec3::new(self.x + o.x, self.y + o.y, self.z + o.z)
    }
}
impl Sub for Vec3 {
    type Output = Vec3;
    #[inline]
    fn sub(self, o: Vec3) -> Vec3 {
        Vec3::new(self.x - o.x, self.y - o.y, self.z - o.z)
    }
}
impl Mul<f64> for Vec3 {
    type Output = Vec3;
    #[inline]
    fn mul(self, s: f64) -> Vec3 {
        Vec3::new(self.x * s, self.y * s, self.z * s)
    }
}
impl Neg for Vec3 {
    type Output = Vec3;
    #[inline]
    fn neg(self) -> Vec3 {
        Vec3::new(-self.x, -self.y, -self.z)
    }
}

/// (sin 2πt, cos 2πt) for a fraction of a turn t in [0, 2⁵⁰), e.g. a uniform random azimuth.
///
/// Cheaper than `f64::sin_cos(2π t)` (no general argument reduction: the quadrant comes exactly
/// from 4t) and as accurate (≲ 1 ulp): t = q/4 + r exactly with |r| ≤ 1/8, x = 2πr ∈ [−π/4, π/4],
/// then the fdlibm kernels `__kernel_sin`/`__kernel_cos` (Sun Microsystems 1993, freely
/// redistributable; minimax on [−π/4, π/4], error < 2⁻⁵⁸) in the form musl uses, and the
/// quadrant rotation sin(x + qπ/2), cos(x + qπ/2).
#[inline]
#[allow(clippy::excessive_precision)] // the kernel coefficients as fdlibm publishes them
pub fn sin_cos_turns(t: f64) -> (f64, f64) {
    const S1: f64 = -1.66666666666666324348e-01;
    const S2: f64 = 8.33333333332248946124e-03;
    const S3: f64 = -1.98412698298579493134e-04;
    const S4: f64 = 2.75573137070700676789e-06;
    const S5: f64 = -2.50507602534068634195e-08;
    const S6: f64 = 1.58969099521155010221e-10;
    const C1: f64 = 4.16666666666666019037e-02;
    const C2: f64 = -1.38888888888741095749e-03;
    const C3: f64 = 2.48015872894767294178e-05;
    const C4: f64 = -2.75573143513906633035e-07;
    const C5: f64 = 2.08757232129817482790e-09;
    const C6: f64 = -1.13596475577881948265e-11;
    debug_assert!((0.0..1.1259e15).contains(&t));
    // Nearest quarter turn (t ≥ 0, so truncation of 4t + ½ rounds; `f64::round` would be a
    // library call without SSE4.1). t − q/4 is exact.
    let q = (4.0 * t + 0.5) as i64;
    let x = (t - 0.25 * q as f64) * std::f64::consts::TAU;
    let z = x * x;
    let w = z * z;
    let rs = S2 + z * (S3 + z * S4) + z * w * (S5 + z * S6);
    let sin = x + z * x * (S1 + z * rs);
    let rc = z * (C1 + z * (C2 + z * C3)) + w * w * (C4 + z * (C5 + z * C6));
    let hz = 0.5 * z;
    let one_minus = 1.0 - hz;
    let cos = one_minus + (((1.0 - one_minus) - hz) + z * rc);
    rotate_quadrant(sin, cos, q)
}

/// (sin, cos) of x + qπ/2 from those of x: (sin, cos), (cos, −sin), (−sin, −cos), (−cos, sin).
/// The quadrant of a random azimuth is random, so as branches these choices were mispredicted
/// about half the time (valgrind's branch simulation: 0.75 per call); they are made on the bits
/// instead, a swap under a mask and a sign flip (exactly −x, as the product by −1 it replaces).
#[inline(always)]
fn rotate_quadrant(sin: f64, cos: f64, q: i64) -> (f64, f64) {
    const SIGN: u64 = 1 << 63;
    let swap = ((q & 1) as u64).wrapping_neg();
    let flip = ((q as u64) & 2) << 62;
    let (s, c) = (sin.to_bits(), cos.to_bits());
    let a = (s & !swap) | (c & swap);
    let b = (c & !swap) | ((s ^ SIGN) & swap);
    (f64::from_bits(a ^ flip), f64::from_bits(b ^ flip))
}

/// ⌊x⌋ as an integer without a libm call (baseline x86-64 has no rounding instruction).
#[inline(always)]
pub fn floor_i64(x: f64) -> i64 {
    let i = x as i64;
    if (i as f64) > x {
        i - 1
    } else {
        i
    }
}

/// Refraction by Snell's law. `d` is the unit incident direction, `n` the unit normal on the
/// incident side (`d·n < 0`), `eta = n_incident / n_transmitted`. Returns `None` on total
/// internal reflection. (pbrt-v4 `Refract`, Snell: n₁ sin θ₁ = n₂ sin θ₂.)
#[inline]
pub fn refract(d: Vec3, n: Vec3, eta: f64) -> Option<Vec3> {
    let cos_i = -d.dot(n);
    let sin2_t = eta * eta * (1.0 - cos_i * cos_i).max(0.0);
    if sin2_t >= 1.0 {
        return None;
    }
    let cos_t = (1.0 - sin2_t).sqrt();
    Some((d * eta + n * (eta * cos_i - cos_t)).renormalized())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn basis_is_orthonormal() {
        for v in
            [Vec3::new(0.0, 0.0, 1.0), Vec3::new(0.0, 0.0, -1.0), Vec3::new(0.6, 0.0, 0.8), Vec3::new(0.36, 0.48, -0.8)]
        {
            let (a, b) = v.orthonormal_basis();
            assert!((a.norm2() - 1.0).abs() < 1e-12 && (b.norm2() - 1.0).abs() < 1e-12);
            assert!(a.dot(b).abs() < 1e-12 && a.dot(v).abs() < 1e-12 && b.dot(v).abs() < 1e-12);
        }
    }

    #[test]
    fn sin_cos_turns_matches_libm() {
        // Dense in [0, 1) including the quadrant boundaries and their neighbours.
        let mut ts: Vec<f64> = (0..=100_000).map(|i| i as f64 / 100_000.0).collect();
        for q in 0..=4 {
            let b = q as f64 / 8.0;
            // Neighbouring doubles (positive b: ±1 in the bit pattern; f64::next_up needs Rust 1.86).
            ts.extend([
                b,
                b - 1e-17,
                b + 1e-17,
                f64::from_bits(b.to_bits() + 1),
                f64::from_bits(b.to_bits().saturating_sub(1)),
            ]);
        }
        ts.push(f64::from_bits(1.0f64.to_bits() - 1));
        for t in ts.into_iter().filter(|t| (0.0..1.0).contains(t)) {
            let (s, c) = sin_cos_turns(t);
            // The kernels against libm on the same reduced argument: within an ulp or so.
            let q = (4.0 * t).round();
            let (sr, cr) = ((t - 0.25 * q) * std::f64::consts::TAU).sin_cos();
            let (s1, c1) = [(sr, cr), (cr, -sr), (-sr, -cr), (-cr, sr)][(q as usize) & 3];
            assert!((s - s1).abs() <= 2.3e-16 && (c - c1).abs() <= 2.3e-16, "t {t}: ({s}, {c}) vs ({s1}, {c1})");
            // And against the naive form, whose argument 2πt carries its own rounding.
            let (s0, c0) = (std::f64::consts::TAU * t).sin_cos();
            assert!((s - s0).abs() < 1e-15 && (c - c0).abs() < 1e-15, "t {t}: ({s}, {c}) vs ({s0}, {c0})");
        }
    }

    #[test]
    fn the_quadrant_rotation_is_bit_for_bit_the_branchy_one() {
        // The engine's results depend on it: the same bits as the selection and the product by
        // ±1 it replaced, for every quadrant (also beyond 3) and signed zeros.
        let mut rng = crate::rng::Rng::for_ray(9, 0, 0);
        let mut values = vec![0.0, -0.0, 1.0, -1.0, 1e-300, -5e-324];
        values.extend((0..2000).map(|_| 2.0 * rng.uniform() - 1.0));
        for (k, &sin) in values.iter().enumerate() {
            let cos = values[(7 * k + 3) % values.len()];
            for q in 0..11i64 {
                let (a, b) = if q & 1 == 0 { (sin, cos) } else { (cos, -sin) };
                let sign = if q & 2 == 0 { 1.0 } else { -1.0 };
                let (s, c) = rotate_quadrant(sin, cos, q);
                assert_eq!((s.to_bits(), c.to_bits()), ((a * sign).to_bits(), (b * sign).to_bits()), "{sin} {cos} {q}");
            }
        }
    }

    #[test]
    fn renormalized_is_unit() {
        let v = Vec3::new(0.36, 0.48, -0.8);
        for scale in [1.0, 1.0 + 3e-16, 1.0 - 5e-13, 1.0 + 4e-7, 1.5, 0.01] {
            let w = (v * scale).renormalized();
            assert!((w.norm2() - 1.0).abs() < 4e-16, "scale {scale}: |w|² = {}", w.norm2());
            assert!((w.x / w.z - v.x / v.z).abs() < 1e-15);
        }
    }

    #[test]
    fn snell_holds() {
        let n = Vec3::new(0.0, 0.0, 1.0);
        let d = Vec3::new(0.5, 0.0, -(0.75f64).sqrt());
        let t = refract(d, n, 1.0 / 1.5).unwrap();
        // n1 sin θ1 = n2 sin θ2
        assert!((1.0 * 0.5 - 1.5 * t.x).abs() < 1e-12);
        assert!(t.z < 0.0);
        // Total internal reflection from glass at 60°.
        let d = Vec3::new((0.75f64).sqrt(), 0.0, -0.5);
        assert!(refract(d, n, 1.5).is_none());
    }
}

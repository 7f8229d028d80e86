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
    Some((d * eta + n * (eta * cos_i - cos_t)).normalized())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn basis_is_orthonormal() {
        for v in [Vec3::new(0.0, 0.0, 1.0), Vec3::new(0.0, 0.0, -1.0), Vec3::new(0.6, 0.0, 0.8), Vec3::new(0.36, 0.48, -0.8)] {
            let (a, b) = v.orthonormal_basis();
            assert!((a.norm2() - 1.0).abs() < 1e-12 && (b.norm2() - 1.0).abs() < 1e-12);
            assert!(a.dot(b).abs() < 1e-12 && a.dot(v).abs() < 1e-12 && b.dot(v).abs() < 1e-12);
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

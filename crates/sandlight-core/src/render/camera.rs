//! Pinhole camera.

use crate::error::SandlightError;
use crate::math::Vec3;

/// A pinhole camera: `right` and `up` span the image plane at unit distance along `forward`,
/// already scaled to its half-width and half-height (tan of the half field of view), so the
/// pixel (px, py) + jitter maps to forward + x·right + y·up with x, y ∈ [−1, 1].
#[derive(Clone, Copy, Debug)]
pub struct Camera {
    pub origin: Vec3,
    forward: Vec3,
    right: Vec3,
    up: Vec3,
    pub width: usize,
    pub height: usize,
}

impl Camera {
    pub fn new(
        origin: [f64; 3],
        forward: [f64; 3],
        right: [f64; 3],
        up: [f64; 3],
        width: usize,
        height: usize,
    ) -> Result<Self, SandlightError> {
        let v = |a: [f64; 3]| Vec3::new(a[0], a[1], a[2]);
        let (o, f, r, u) = (v(origin), v(forward), v(right), v(up));
        if !(o.is_finite() && f.is_finite() && r.is_finite() && u.is_finite())
            || f.norm2() < 1e-24
            || r.norm2() < 1e-24
            || u.norm2() < 1e-24
        {
            return Err(SandlightError::parameter(
                "camera",
                format!("origin {origin:?}, forward {forward:?}"),
                "finite, non-degenerate camera vectors",
            ));
        }
        if width == 0 || height == 0 {
            return Err(SandlightError::parameter(
                "resolution",
                format!("{width} × {height}"),
                "at least 1 × 1 pixels",
            ));
        }
        Ok(Camera { origin: o, forward: f, right: r, up: u, width, height })
    }

    /// Unit direction through pixel (px, py) (py = 0 at the top) at sub-pixel offset (jx, jy) ∈ [0, 1)².
    #[inline]
    pub fn ray(&self, px: usize, py: usize, jx: f64, jy: f64) -> Vec3 {
        let x = 2.0 * (px as f64 + jx) / self.width as f64 - 1.0;
        let y = 1.0 - 2.0 * (py as f64 + jy) / self.height as f64;
        (self.forward + self.right * x + self.up * y).normalized()
    }
}

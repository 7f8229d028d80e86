//! Particle sizes drawn by inverse transform from a quantile table computed in Python (so any
//! size distribution can be used; the Python side documents which one and how it is weighted).

use crate::error::SandlightError;
use crate::rng::Rng;

/// Equally spaced quantiles q_j = F⁻¹(j/(M−1)), j = 0..M−1, of the size (mm) of the particles a
/// ray meets (projected-area weighted). Sampling interpolates linearly between them.
#[derive(Clone, Debug, PartialEq)]
pub struct QuantileTable {
    q: Vec<f64>,
}

impl QuantileTable {
    pub fn new(q: Vec<f64>) -> Result<QuantileTable, SandlightError> {
        if q.is_empty() {
            return Err(SandlightError::parameter("size_quantiles_mm", "[]", "at least one quantile"));
        }
        if q.iter().any(|v| !(v.is_finite() && *v > 0.0)) {
            return Err(SandlightError::parameter("size_quantiles_mm", format!("{q:?}"), "finite sizes > 0 mm"));
        }
        if q.windows(2).any(|w| w[1] < w[0]) {
            return Err(SandlightError::parameter("size_quantiles_mm", format!("{q:?}"), "non-decreasing"));
        }
        Ok(QuantileTable { q })
    }

    pub fn constant(d: f64) -> QuantileTable {
        QuantileTable { q: vec![d] }
    }

    pub fn max(&self) -> f64 {
        *self.q.last().unwrap()
    }

    /// The size at level `u` in [0, 1): the same linear interpolation `sample` uses.
    #[inline]
    pub fn quantile(&self, u: f64) -> f64 {
        let m = self.q.len();
        if m == 1 {
            return self.q[0];
        }
        let x = u * (m - 1) as f64;
        let j = (x as usize).min(m - 2);
        let f = x - j as f64;
        self.q[j] + f * (self.q[j + 1] - self.q[j])
    }

    /// The level u in [0, 1] at which `quantile(u)` reaches `d` (its inverse; 0 below the
    /// table, 1 above it).
    pub fn level(&self, d: f64) -> f64 {
        let m = self.q.len();
        let j = self.q.partition_point(|&v| v <= d);
        if j == 0 {
            return 0.0;
        }
        if j == m {
            return 1.0;
        }
        let f = (d - self.q[j - 1]) / (self.q[j] - self.q[j - 1]);
        ((j - 1) as f64 + f) / (m - 1) as f64
    }

    #[inline]
    pub fn sample(&self, rng: &mut Rng) -> f64 {
        let m = self.q.len();
        if m == 1 {
            return self.q[0];
        }
        let x = rng.uniform() * (m - 1) as f64;
        let j = (x as usize).min(m - 2);
        let f = x - j as f64;
        self.q[j] + f * (self.q[j + 1] - self.q[j])
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn level_inverts_quantile() {
        let t = QuantileTable::new(vec![0.1, 0.2, 0.2, 0.5, 0.9]).unwrap();
        for k in 0..1000 {
            let u = k as f64 / 1000.0;
            let d = t.quantile(u);
            assert!((t.quantile(t.level(d)) - d).abs() < 1e-12, "u = {u}");
        }
        assert_eq!(t.level(0.05), 0.0);
        assert_eq!(t.level(0.95), 1.0);
        assert!((t.level(0.35) - 2.5 / 4.0).abs() < 1e-12);
        let c = QuantileTable::constant(0.25);
        assert_eq!((c.level(0.2), c.level(0.3)), (0.0, 1.0));
    }
}

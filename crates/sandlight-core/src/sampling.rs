//! Generic sampling routines (as pbrt-v4's `util/sampling.h`): discrete distributions and
//! directions on the sphere, the hemisphere and a cone, each from given uniforms in [0, 1) so
//! that a caller's use of its random numbers is explicit.

use std::f64::consts::PI;

use crate::math::{sin_cos_turns, Vec3};

/// The first i with u < cumulative[i] (the last index if none), for non-decreasing cumulative
/// probabilities: counted without branches, it is the number of them ≤ u (an entry equal to
/// its predecessor, an outcome of zero probability, is never picked).
#[inline]
pub fn pick_cumulative(cumulative: &[f64], u: f64) -> usize {
    let n = cumulative.len();
    cumulative[..n - 1].iter().map(|&c| (u >= c) as usize).sum()
}

/// A discrete distribution as an alias table (Walker 1977; built as Vose 1991): slot s is kept
/// with probability `keep[s]`, else replaced by `other[s]`, so sampling is O(1).
#[derive(Clone, Debug)]
pub struct AliasTable {
    keep: Vec<f64>,
    other: Vec<u32>,
}

impl AliasTable {
    /// From probabilities `p` (non-negative, summing to 1 up to rounding).
    pub fn new(p: &[f64]) -> AliasTable {
        let n = p.len();
        let mut keep: Vec<f64> = p.iter().map(|&q| q * n as f64).collect();
        let mut other: Vec<u32> = (0..n as u32).collect();
        let (mut small, mut large): (Vec<usize>, Vec<usize>) = (0..n).partition(|&i| keep[i] < 1.0);
        while let (Some(s), Some(&l)) = (small.pop(), large.last()) {
            other[s] = l as u32;
            keep[l] -= 1.0 - keep[s];
            if keep[l] < 1.0 {
                large.pop();
                small.push(l);
            }
        }
        // Leftovers differ from 1 only by rounding.
        for i in small.into_iter().chain(large) {
            keep[i] = 1.0;
        }
        AliasTable { keep, other }
    }

    /// An outcome for one uniform `u`: its integer part over the slots picks a slot, its
    /// fractional part keeps the slot or takes its alias.
    #[inline]
    pub fn sample(&self, u: f64) -> usize {
        let n = self.keep.len();
        let x = u * n as f64;
        let slot = (x as usize).min(n - 1);
        if x - (slot as f64) < self.keep[slot] {
            slot
        } else {
            self.other[slot] as usize
        }
    }
}

/// A direction uniform on the unit sphere (pdf 1/4π): z = 1 − 2u₀, φ = 2π u₁.
#[inline]
pub fn uniform_sphere(u: [f64; 2]) -> Vec3 {
    let z = 1.0 - 2.0 * u[0];
    let r = (1.0 - z * z).max(0.0).sqrt();
    let (sin_phi, cos_phi) = sin_cos_turns(u[1]);
    Vec3::new(r * cos_phi, r * sin_phi, z)
}

/// A direction uniform on the upper hemisphere (pdf 1/2π): cos θ = u₀, φ = 2π u₁ (equal solid
/// angle, so every equal-solid-angle patch is hit equally often).
#[inline]
pub fn uniform_hemisphere(u: [f64; 2]) -> Vec3 {
    let z = u[0];
    let r = (1.0 - z * z).max(0.0).sqrt();
    let phi = 2.0 * PI * u[1];
    Vec3::new(r * phi.cos(), r * phi.sin(), z)
}

/// A cosine-weighted direction on the upper hemisphere (pdf cos θ/π), by Malley's method: a
/// point uniform on the unit disc (radius √u₀, φ = 2π u₁) lifted to the hemisphere.
#[inline]
pub fn cosine_hemisphere(u: [f64; 2]) -> Vec3 {
    let r = u[0].sqrt();
    let (sin_phi, cos_phi) = sin_cos_turns(u[1]);
    let z = (1.0 - r * r).max(0.0).sqrt();
    Vec3::new(r * cos_phi, r * sin_phi, z)
}

/// The cosine-weighted density of `cosine_hemisphere` as local angles (μ = cos θ, signed
/// Δφ ∈ [−π, π)): μ² = u₀ uniform, Δφ = 2π u₁ − π. The renderer samples in these coordinates
/// (relative to the view azimuth), so it keeps this mapping rather than a direction.
#[inline]
pub fn cosine_hemisphere_angles(u: [f64; 2]) -> (f64, f64) {
    let mu = u[0].sqrt();
    (mu, 2.0 * PI * u[1] - PI)
}

/// A direction uniform in the cone around unit `axis` with 1 − cos α = `one_minus_cos_max`
/// (pdf 1/[2π(1 − cos α)]).
#[inline]
pub fn uniform_cone(axis: Vec3, one_minus_cos_max: f64, u: [f64; 2]) -> Vec3 {
    // cos θ uniform in [cos α, 1]; written as 1 − u·(1 − cos α) to keep precision.
    let om = u[0] * one_minus_cos_max;
    let cos_t = 1.0 - om;
    let sin_t = (om * (2.0 - om)).max(0.0).sqrt();
    let phi = 2.0 * PI * u[1];
    let (a, b) = axis.orthonormal_basis();
    (a * (sin_t * phi.cos()) + b * (sin_t * phi.sin()) + axis * cos_t).normalized()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::rng::Rng;

    fn uniforms(rng: &mut Rng) -> [f64; 2] {
        [rng.uniform(), rng.uniform()]
    }

    #[test]
    fn pick_cumulative_is_the_first_entry_above_u() {
        let c = [0.25, 0.25, 0.75, 1.0];
        assert_eq!([0.0, 0.2, 0.25, 0.5, 0.75, 0.99].map(|u| pick_cumulative(&c, u)), [0, 0, 2, 2, 3, 3]);
        // Rounding can leave the last entry below 1: u above it still picks the last outcome.
        assert_eq!(pick_cumulative(&[0.5, 0.999999], 0.9999995), 1);
    }

    #[test]
    fn alias_table_reproduces_the_distribution() {
        let p = [0.05, 0.4, 0.0, 0.15, 0.3, 0.1];
        let t = AliasTable::new(&p);
        // Exactly, from the table: slot s is met with probability 1/n.
        let mut q = [0.0; 6];
        for slot in 0..6 {
            q[slot] += t.keep[slot] / 6.0;
            q[t.other[slot] as usize] += (1.0 - t.keep[slot]) / 6.0;
        }
        for (a, b) in p.iter().zip(q) {
            assert!((a - b).abs() < 1e-12);
        }
        // And by sampling on a fine grid of u, which `sample` maps as the table says.
        let n = 600_000;
        let mut counts = [0usize; 6];
        for k in 0..n {
            counts[t.sample((k as f64 + 0.5) / n as f64)] += 1;
        }
        for (a, c) in p.iter().zip(counts) {
            assert!((c as f64 / n as f64 - a).abs() < 1e-5, "{c} vs {a}");
        }
    }

    /// Mean of f over n directions from `sample`, with its standard error.
    fn mean(n: usize, seed: u64, sample: impl Fn([f64; 2]) -> Vec3, f: impl Fn(Vec3) -> f64) -> (f64, f64) {
        let mut rng = Rng::for_ray(seed, 0, 0);
        let (mut m1, mut m2) = (0.0, 0.0);
        for _ in 0..n {
            let d = sample(uniforms(&mut rng));
            assert!((d.norm2() - 1.0).abs() < 1e-12);
            let v = f(d);
            m1 += v;
            m2 += v * v;
        }
        let m = m1 / n as f64;
        (m, ((m2 / n as f64 - m * m) / n as f64).sqrt())
    }

    #[test]
    fn direction_samplers_have_their_densities() {
        // Moments of cos θ and of x against their integrals under each pdf: uniform sphere
        // E[z] = 0, E[z²] = 1/3; uniform hemisphere E[z] = 1/2, E[z²] = 1/3; cosine-weighted
        // E[z] = 2/3, E[z²] = 1/2; E[x] = 0 for all (no preferred azimuth).
        let n = 200_000;
        type Sampler = fn([f64; 2]) -> Vec3;
        let cases: [(Sampler, [f64; 3]); 3] = [
            (uniform_sphere, [0.0, 1.0 / 3.0, 0.0]),
            (uniform_hemisphere, [0.5, 1.0 / 3.0, 0.0]),
            (cosine_hemisphere, [2.0 / 3.0, 0.5, 0.0]),
        ];
        let moments: [fn(Vec3) -> f64; 3] = [|d| d.z, |d| d.z * d.z, |d| d.x];
        for (k, (sample, expected)) in cases.iter().enumerate() {
            for (f, e) in moments.iter().zip(expected) {
                let (m, se) = mean(n, k as u64, sample, f);
                assert!((m - e).abs() < 4.0 * se, "sampler {k}: {m} vs {e} (se {se})");
            }
        }
        // The angle form: μ the same law as cosine_hemisphere's z, Δφ uniform in [−π, π).
        let mut rng = Rng::for_ray(9, 0, 0);
        let (mut m1, mut m2, mut phi) = (0.0, 0.0, 0.0);
        for _ in 0..n {
            let (mu, dphi) = cosine_hemisphere_angles(uniforms(&mut rng));
            assert!((0.0..=1.0).contains(&mu) && (-PI..PI).contains(&dphi));
            (m1, m2, phi) = (m1 + mu, m2 + mu * mu, phi + dphi);
        }
        let nf = n as f64;
        assert!((m1 / nf - 2.0 / 3.0).abs() < 4.0 * (0.5f64 - 4.0 / 9.0).sqrt() / nf.sqrt());
        assert!((m2 / nf - 0.5).abs() < 4.0 * (1.0f64 / 12.0).sqrt() / nf.sqrt());
        assert!((phi / nf).abs() < 4.0 * PI / (3.0 * nf).sqrt());
    }

    #[test]
    fn cone_samples_fill_the_cone_uniformly() {
        // 1 − cos θ is uniform on [0, 1 − cos α]: its mean is half of that.
        let axis = Vec3::new(0.3, -0.4, 0.5).normalized();
        let w = 0.01;
        let (m, se) = mean(100_000, 4, |u| uniform_cone(axis, w, u), |d| 1.0 - d.dot(axis));
        assert!((m - 0.5 * w).abs() < 4.0 * se, "{m}");
        let mut rng = Rng::for_ray(5, 0, 0);
        for _ in 0..10_000 {
            assert!(1.0 - uniform_cone(axis, w, uniforms(&mut rng)).dot(axis) <= w * (1.0 + 1e-9));
        }
    }
}

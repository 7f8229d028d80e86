//! Spectral renderer of sandy terrain under the Preetham sky and the sun (paper §4.2).
//!
//! `camera` (pinhole), `environment` (sky texture + sun disc, their sampling), `brdf` (stacks of
//! tabulated spectral BRDFs, lookup and importance sampling), `terrain` (plane, heightfield of
//! bilinear patches with a maximum-height hierarchy, material map) → `integrator` (path tracing
//! with multiple importance sampling) → `render_rows` (pixels in parallel).
//!
//! Determinism: sample k of pixel p draws from `Rng::for_ray(seed', p, k)` with seed' derived
//! from (seed, frame), so an image does not depend on the thread count or on how the rows are
//! split between calls, and rendering more samples extends the same sequence.

pub mod brdf;
pub mod camera;
pub mod environment;
pub mod integrator;
pub mod terrain;

use rayon::prelude::*;

use crate::rng::Rng;
pub use integrator::{Estimator, Heuristic, Scene, Scratch, Settings};

/// Seed of a frame: frames of one animation get decorrelated streams.
#[inline]
pub fn frame_seed(seed: u64, frame: u64) -> u64 {
    seed ^ frame.wrapping_mul(0x9E37_79B9_7F4A_7C15).rotate_left(17)
}

/// Renders rows `row0 .. row0 + n_rows` with `spp` samples per pixel.
///
/// Returns (radiance, coverage): radiance is row-major (row, column, band) mean spectral
/// radiance in W m⁻² sr⁻¹ nm⁻¹, coverage the fraction of a pixel's samples whose camera ray met the
/// ground (for masks in post-processing). Runs on the current rayon pool.
pub fn render_rows(scene: &Scene, row0: usize, n_rows: usize, spp: u32, seed: u64, frame: u64) -> (Vec<f32>, Vec<f32>) {
    let w = scene.camera.width;
    let nb = scene.brdf.n_bands();
    let seed = frame_seed(seed, frame);
    let mut radiance = vec![0.0f32; n_rows * w * nb];
    let mut coverage = vec![0.0f32; n_rows * w];
    radiance.par_chunks_mut(w * nb).zip(coverage.par_chunks_mut(w)).enumerate().for_each(|(r, (row, cov))| {
        let py = row0 + r;
        let mut acc = vec![0.0f64; nb];
        let mut scratch = Scratch::default();
        for px in 0..w {
            acc.iter_mut().for_each(|v| *v = 0.0);
            let pixel = (py * w + px) as u64;
            let mut ground = 0u32;
            for k in 0..spp {
                let mut rng = Rng::for_ray(seed, pixel, k as u64);
                ground += scene.sample(px, py, &mut rng, &mut acc, &mut scratch) as u32;
            }
            let inv = 1.0 / spp.max(1) as f64;
            for b in 0..nb {
                row[px * nb + b] = (acc[b] * inv) as f32;
            }
            cov[px] = ground as f32 * inv as f32;
        }
    });
    (radiance, coverage)
}

#[cfg(test)]
mod tests {
    use super::brdf::BrdfStack;
    use super::camera::Camera;
    use super::environment::Environment;
    use super::terrain::{MaterialMap, Terrain};
    use super::*;
    use std::f64::consts::PI;

    fn lambert(albedo: f64) -> BrdfStack {
        BrdfStack::new(1, vec![0.0, 1.0], vec![0.0, 1.0], vec![0.0, PI], 1, vec![(albedo / PI) as f32; 8]).unwrap()
    }

    fn scene(sky: f32, sun: f64, estimator: Estimator, sampling: brdf::BrdfSampling) -> Scene {
        let env = Environment::new(8, 16, 1, vec![sky; 8 * 16], [0.0, 0.6, 0.8], 6.8e-5, &[sun]).unwrap();
        let camera = Camera::new([0.0, 0.0, 2.0], [0.0, 1.0, -1.0], [0.3, 0.0, 0.0], [0.0, 0.2, 0.2], 4, 3).unwrap();
        Scene {
            camera,
            environment: env,
            brdf: lambert(1.0),
            terrain: Terrain::Plane { z: 0.0 },
            material: MaterialMap::constant(0.0),
            settings: Settings { estimator, sampling, heuristic: Heuristic::Power, max_bounces: 1 },
        }
    }

    #[test]
    fn white_lambertian_plane_under_unit_sky_has_unit_radiance() {
        for est in [Estimator::Mis, Estimator::Brdf, Estimator::Light] {
            for sampling in [brdf::BrdfSampling::Cosine, brdf::BrdfSampling::Table] {
                let (rad, cov) = render_rows(&scene(1.0, 0.0, est, sampling), 0, 3, 4000, 7, 0);
                assert!(cov.iter().all(|&c| c == 1.0));
                let mean = rad.iter().map(|&v| v as f64).sum::<f64>() / rad.len() as f64;
                assert!((mean - 1.0).abs() < 0.01, "{est:?} {sampling:?}: {mean}");
            }
        }
    }

    #[test]
    fn sun_only_plane_follows_lambert() {
        // L = E a/π cos θs, E = L☉ Ω☉; sun elevation: cos θs = 0.8. The disc's finite size makes
        // cos θ vary by ±0.35 % between samples (≈ 3·10⁻⁴ noise at 64 samples).
        let (rad, _) = render_rows(&scene(0.0, 1.0e4, Estimator::Mis, brdf::BrdfSampling::Table), 0, 3, 64, 1, 0);
        let expected = 1.0e4 * 6.8e-5 / PI * 0.8;
        for v in rad {
            assert!((v as f64 - expected).abs() < 1.5e-3 * expected, "{v} vs {expected}");
        }
    }

    #[test]
    fn images_do_not_depend_on_the_row_split() {
        let sc = scene(1.0, 1.0e4, Estimator::Mis, brdf::BrdfSampling::Table);
        let (all, _) = render_rows(&sc, 0, 3, 16, 5, 2);
        let (a, _) = render_rows(&sc, 0, 1, 16, 5, 2);
        let (b, _) = render_rows(&sc, 1, 2, 16, 5, 2);
        assert_eq!(all, [a, b].concat());
    }
}

//! Running many rays in parallel with results independent of the thread count.
//!
//! Ray `i` draws its random numbers from `Rng::for_ray(seed, stream, i)`, and tallies are integer
//! counts merged by addition (associative and commutative), so any split of the rays over
//! threads gives bit-identical totals.

use rayon::prelude::*;

use crate::math::Vec3;
use crate::rng::Rng;
use crate::transport::{Fate, Limits, Medium};

/// Runs `body(tally, ray_index)` for rays `first .. first + n` on the current rayon pool, in
/// `blocks_per_thread` contiguous blocks per thread with one tally each, and merges the tallies.
/// More blocks balance load better; fewer keep large tallies (a BRDF's) cheap in memory.
pub fn for_rays<T, I, B, M>(first: u64, n: u64, blocks_per_thread: u64, init: I, body: B, merge: M) -> T
where
    T: Send,
    I: Fn() -> T + Sync + Send,
    B: Fn(&mut T, u64) + Sync + Send,
    M: Fn(T, T) -> T + Sync + Send,
{
    let blocks = (rayon::current_num_threads() as u64 * blocks_per_thread.max(1)).clamp(1, n.max(1));
    let per = n.div_ceil(blocks);
    (0..blocks)
        .into_par_iter()
        .map(|b| {
            let mut t = init();
            let lo = first + b * per;
            let hi = (lo + per).min(first + n);
            for i in lo..hi {
                body(&mut t, i);
            }
            t
        })
        .reduce(&init, &merge)
}

/// The rays of a run: rays `first .. first + n` of stream `stream` (e.g. the wavelength index)
/// under `seed`. Ray i draws its random numbers from `rng(i)` alone.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Rays {
    pub seed: u64,
    pub stream: u64,
    pub first: u64,
    pub n: u64,
}

impl Rays {
    /// The random stream of ray `i`.
    #[inline]
    pub fn rng(&self, i: u64) -> Rng {
        Rng::for_ray(self.seed, self.stream, i)
    }
}

/// Counts of a directional-hemispherical reflectance run.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct DhrCounts {
    pub launched: u64,
    pub escaped: u64,
    pub absorbed: u64,
    pub transmitted: u64,
    pub capped: u64,
    /// Sum over rays of particle events.
    pub events: u64,
}

impl DhrCounts {
    pub fn merge(mut self, o: DhrCounts) -> DhrCounts {
        self.launched += o.launched;
        self.escaped += o.escaped;
        self.absorbed += o.absorbed;
        self.transmitted += o.transmitted;
        self.capped += o.capped;
        self.events += o.events;
        self
    }
}

/// Incident direction (pointing into the sample) at zenith angle `theta_rad` in the x–z plane.
pub fn incident_direction(theta_rad: f64) -> Vec3 {
    Vec3::new(theta_rad.sin(), 0.0, -theta_rad.cos())
}

/// Directional-hemispherical reflectance counts for `rays` at incidence direction `dir_in`
/// (docs/model.md §2.6: ρ = escaped / launched).
pub fn directional_hemispherical<Md: Medium>(medium: &Md, dir_in: Vec3, rays: Rays, limits: &Limits) -> DhrCounts {
    for_rays(
        rays.first,
        rays.n,
        16,
        DhrCounts::default,
        |c, i| {
            let mut rng = rays.rng(i);
            let out = medium.trace(dir_in, &mut rng, limits);
            c.launched += 1;
            c.events += out.events;
            match out.fate {
                Fate::Escaped(_) => c.escaped += 1,
                Fate::Absorbed => c.absorbed += 1,
                Fate::Transmitted => c.transmitted += 1,
                Fate::Capped => c.capped += 1,
            }
        },
        DhrCounts::merge,
    )
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::medium::IsotropicScatterers;

    fn rays(seed: u64, stream: u64, first: u64, n: u64) -> Rays {
        Rays { seed, stream, first, n }
    }

    fn on_threads<T: Send>(threads: usize, f: impl FnOnce() -> T + Send) -> T {
        rayon::ThreadPoolBuilder::new().num_threads(threads).build().unwrap().install(f)
    }

    #[test]
    fn for_rays_visits_every_ray_once() {
        for threads in [1, 2, 3] {
            for (first, n) in [(0, 0), (5, 1), (17, 7), (1000, 1001)] {
                for blocks in [0, 1, 16] {
                    let mut seen = on_threads(threads, || {
                        for_rays(
                            first,
                            n,
                            blocks,
                            Vec::new,
                            |v: &mut Vec<u64>, i| v.push(i),
                            |mut a, b| {
                                a.extend(b);
                                a
                            },
                        )
                    });
                    seen.sort_unstable();
                    assert_eq!(seen, (first..first + n).collect::<Vec<_>>(), "{threads} threads, n {n}");
                }
            }
        }
    }

    /// Isotropic scatterers in a slab with a small event cap: all four fates occur.
    fn every_fate() -> (IsotropicScatterers, Limits) {
        (IsotropicScatterers::new(0.97, 3.0).unwrap(), Limits { max_events: 12, max_internal: 10 })
    }

    #[test]
    fn counts_add_up_to_the_rays_launched() {
        let (medium, limits) = every_fate();
        let c = directional_hemispherical(&medium, incident_direction(0.4), rays(9, 1, 0, 20_000), &limits);
        assert_eq!(c.launched, 20_000);
        assert_eq!(c.escaped + c.absorbed + c.transmitted + c.capped, c.launched);
        assert!(c.escaped > 0 && c.absorbed > 0 && c.transmitted > 0 && c.capped > 0, "{c:?}");
        // An absorbed ray has met at least one scatterer; a capped one stops at max_events + 1.
        assert!(c.events >= c.absorbed + c.capped * (limits.max_events + 1));
    }

    #[test]
    fn counts_do_not_depend_on_threads_or_batches() {
        // Ray i draws from Rng::for_ray(seed, stream, i) alone: a serial loop, any thread count
        // and any split into batches give the same integers.
        let (medium, limits) = every_fate();
        let dir = incident_direction(0.9);
        let run = |first, n| directional_hemispherical(&medium, dir, rays(5, 2, first, n), &limits);
        let mut serial = DhrCounts::default();
        for i in 0..3000 {
            let out = medium.trace(dir, &mut Rng::for_ray(5, 2, i), &limits);
            serial.launched += 1;
            serial.events += out.events;
            match out.fate {
                Fate::Escaped(_) => serial.escaped += 1,
                Fate::Absorbed => serial.absorbed += 1,
                Fate::Transmitted => serial.transmitted += 1,
                Fate::Capped => serial.capped += 1,
            }
        }
        for threads in [1, 2, 4] {
            assert_eq!(on_threads(threads, || run(0, 3000)), serial, "{threads} threads");
        }
        let batches = on_threads(2, || run(0, 1000).merge(run(1000, 1)).merge(run(1001, 1999)));
        assert_eq!(batches, serial);
        // Another stream is another sample of rays.
        assert_ne!(directional_hemispherical(&medium, dir, rays(5, 3, 0, 3000), &limits), serial);
    }

    #[test]
    fn incident_direction_points_into_the_sample_at_its_zenith_angle() {
        for theta in [0.0, 0.3, 1.2, 1.5] {
            let d = incident_direction(theta);
            assert!((d.norm2() - 1.0).abs() < 1e-15);
            assert!((d.z + theta.cos()).abs() < 1e-15 && d.y == 0.0 && d.x >= 0.0);
        }
    }
}

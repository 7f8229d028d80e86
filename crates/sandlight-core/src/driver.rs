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

/// Directional-hemispherical reflectance counts for rays `first .. first + n` at incidence
/// direction `dir_in` (splits-model.md §2.6: ρ = escaped / launched).
pub fn directional_hemispherical<Md: Medium>(
    medium: &Md,
    dir_in: Vec3,
    seed: u64,
    stream: u64,
    first: u64,
    n: u64,
    limits: &Limits,
) -> DhrCounts {
    for_rays(
        first,
        n,
        16,
        DhrCounts::default,
        |c, i| {
            let mut rng = Rng::for_ray(seed, stream, i);
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

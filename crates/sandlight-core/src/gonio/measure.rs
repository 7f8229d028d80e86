//! Filling the goniophotometer's tallies by tracing trials through a medium (paper §3.2.1).

use crate::driver::{for_rays, Rays};
use crate::gonio::{BrdfTally, CollectorHemisphere, FixedIncidenceTally};
use crate::math::Vec3;
use crate::sampling::uniform_hemisphere;
use crate::transport::{Fate, Limits, Medium};

/// Uniform-incidence measurement of the trials `rays`: each trial draws its incident
/// direction over the hemisphere and is tallied under (incoming patch, outgoing patch), or as
/// absorbed, or as lost (event cap, or through the bottom of a finite sample).
pub fn measure_brdf<Md: Medium>(
    medium: &Md,
    hemisphere: &CollectorHemisphere,
    rays: Rays,
    limits: &Limits,
) -> BrdfTally {
    let r = hemisphere.n_patches();
    for_rays(
        rays.first,
        rays.n,
        2,
        || BrdfTally::new(r).expect("patch count validated by CollectorHemisphere"),
        |t, i| {
            let mut rng = rays.rng(i);
            // Uniform in solid angle: every equal-solid-angle patch is lit equally often.
            let toward_light = uniform_hemisphere([rng.uniform(), rng.uniform()]);
            let i_in = hemisphere.patch_index([toward_light.x, toward_light.y, toward_light.z]);
            match medium.trace(-toward_light, &mut rng, limits).fate {
                Fate::Escaped(d) => t.record_escape(i_in, hemisphere.patch_index([d.x, d.y, d.z])),
                Fate::Absorbed => t.record_absorbed(i_in),
                Fate::Transmitted | Fate::Capped => t.record_lost(i_in),
            }
        },
        |mut a, b| {
            a.merge(&b).expect("tallies of one hemisphere have equal sizes");
            a
        },
    )
}

/// The classic goniophotometer: every trial comes from `toward_light` (unit, z > 0).
pub fn measure_fixed_incidence<Md: Medium>(
    medium: &Md,
    hemisphere: &CollectorHemisphere,
    toward_light: Vec3,
    rays: Rays,
    limits: &Limits,
) -> FixedIncidenceTally {
    for_rays(
        rays.first,
        rays.n,
        16,
        || FixedIncidenceTally::for_hemisphere(hemisphere),
        |t, i| {
            let mut rng = rays.rng(i);
            match medium.trace(-toward_light, &mut rng, limits).fate {
                Fate::Escaped(d) => t.record_escape(hemisphere.patch_index([d.x, d.y, d.z])),
                Fate::Absorbed => t.record_absorbed(),
                Fate::Transmitted | Fate::Capped => t.record_lost(),
            }
        },
        |mut a, b| {
            a.merge(&b).expect("tallies of one hemisphere have equal sizes");
            a
        },
    )
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::medium::LambertianSurface;

    #[test]
    fn lambertian_counts_add_up_and_are_thread_independent() {
        let h = CollectorHemisphere::new(5, 4).unwrap();
        let m = LambertianSurface::new(0.7).unwrap();
        let lim = Limits::default();
        let one = rayon::ThreadPoolBuilder::new()
            .num_threads(1)
            .build()
            .unwrap()
            .install(|| measure_brdf(&m, &h, Rays { seed: 3, stream: 0, first: 0, n: 20_000 }, &lim));
        let two = rayon::ThreadPoolBuilder::new()
            .num_threads(2)
            .build()
            .unwrap()
            .install(|| measure_brdf(&m, &h, Rays { seed: 3, stream: 0, first: 0, n: 20_000 }, &lim));
        assert_eq!(one.counts, two.counts);
        assert_eq!(one.total_launched(), 20_000);
        let escaped: u64 = one.counts.iter().sum();
        let absorbed: u64 = one.absorbed.iter().sum();
        assert_eq!(escaped + absorbed, 20_000);
    }
}

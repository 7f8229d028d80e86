//! Filling the goniophotometer's tallies by tracing trials through a medium (paper §3.2.1).

use rayon::prelude::*;

use crate::driver::{for_rays, Rays};
use crate::error::SandlightError;
use crate::gonio::spectral_sums::{Outcome, SpectralBrdfSums};
use crate::gonio::{BrdfTally, CollectorHemisphere, FixedIncidenceTally};
use crate::hero::{fixed_point_estimates, HeroGroup};
use crate::math::Vec3;
use crate::rng::Rng;
use crate::sampling::uniform_hemisphere;
use crate::spectral::SpectralWeights;
use crate::transport::{Fate, Limits, Medium};

/// A uniform-incidence trial's incident direction: uniform in solid angle, so every
/// equal-solid-angle patch is lit equally often. Returns (incoming patch, direction toward the
/// light).
#[inline]
fn draw_incidence(hemisphere: &CollectorHemisphere, rng: &mut Rng) -> (usize, Vec3) {
    let toward_light = uniform_hemisphere([rng.uniform(), rng.uniform()]);
    (hemisphere.patch_index([toward_light.x, toward_light.y, toward_light.z]), toward_light)
}

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
            let (i_in, toward_light) = draw_incidence(hemisphere, &mut rng);
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

/// Trials of a shared measurement traced in parallel before they are added, in ray order, to
/// the sums (the scratch holds their fixed-point estimates: 8 MB for 16 wavelengths).
const SHARED_CHUNK: u64 = 65_536;

/// Uniform-incidence measurement of the trials `rays` over the wavelengths of `group`, with
/// spectral path sharing: each trial draws its incident direction as [`measure_brdf`] does,
/// then its hero and path (`HeroGroup::trace`), and is added to `sums` with its fixed-point
/// estimates (`hero::fixed_point_estimates`, the reflectance tallies' own). One set of sums
/// whatever the number of threads: trials are traced in parallel in chunks and added serially,
/// so the integer sums do not depend on the thread count.
///
/// # Errors
/// `SandlightError::Parameter` if `sums` are not sized for `hemisphere` (r incoming and r
/// outgoing patches) and `group`, or a sum would overflow (`SpectralBrdfSums::record`; the
/// trials before it are kept).
pub fn measure_brdf_shared(
    group: &HeroGroup,
    hemisphere: &CollectorHemisphere,
    rays: Rays,
    limits: &Limits,
    sums: &mut SpectralBrdfSums<'_>,
) -> Result<(), SandlightError> {
    let incidence = |rng: &mut Rng| draw_incidence(hemisphere, rng);
    measure_shared(group, hemisphere, hemisphere.n_patches(), incidence, rays, limits, sums)
}

/// The classic goniophotometer with spectral path sharing: [`measure_brdf_shared`] with every
/// trial from `toward_light` (unit, z > 0), as [`measure_fixed_incidence`]; the sums have one
/// incoming patch (incoming index 0).
///
/// # Errors
/// As [`measure_brdf_shared`], with sums sized for one incoming patch.
pub fn measure_fixed_incidence_shared(
    group: &HeroGroup,
    hemisphere: &CollectorHemisphere,
    toward_light: Vec3,
    rays: Rays,
    limits: &Limits,
    sums: &mut SpectralBrdfSums<'_>,
) -> Result<(), SandlightError> {
    measure_shared(group, hemisphere, 1, |_: &mut Rng| (0, toward_light), rays, limits, sums)
}

/// The shared measurement of both instruments: trial i draws (incoming patch, direction
/// toward the light) with `incidence` from its own random stream, then its hero and path.
fn measure_shared(
    group: &HeroGroup,
    hemisphere: &CollectorHemisphere,
    n_incoming: usize,
    incidence: impl Fn(&mut Rng) -> (usize, Vec3) + Sync,
    rays: Rays,
    limits: &Limits,
    sums: &mut SpectralBrdfSums<'_>,
) -> Result<(), SandlightError> {
    let w = group.len();
    sums.check(n_incoming, hemisphere.n_patches(), w)?;
    let mut q = vec![0u64; SHARED_CHUNK.min(rays.n) as usize * w];
    let end = rays.first + rays.n;
    for lo in (rays.first..end).step_by(SHARED_CHUNK as usize) {
        let hi = (lo + SHARED_CHUNK).min(end);
        let outcomes: Vec<(usize, Outcome)> = q[..(hi - lo) as usize * w]
            .par_chunks_mut(w)
            .enumerate()
            .map_init(
                || (SpectralWeights::new(w, 0), vec![0.0; w]),
                |(weights, estimates), (k, q)| {
                    let mut rng = rays.rng(lo + k as u64);
                    let (i_in, toward_light) = incidence(&mut rng);
                    let (fate, _) = group.trace(-toward_light, &mut rng, limits, weights);
                    let outcome = match fate {
                        Fate::Escaped(d) => Outcome::Escaped(hemisphere.patch_index([d.x, d.y, d.z])),
                        Fate::Transmitted => Outcome::Transmitted,
                        Fate::Absorbed => return (i_in, Outcome::Absorbed),
                        Fate::Capped => return (i_in, Outcome::Capped),
                    };
                    fixed_point_estimates(weights, estimates, q);
                    (i_in, outcome)
                },
            )
            .collect();
        for (&(i_in, outcome), q) in outcomes.iter().zip(q.chunks(w)) {
            sums.record(i_in, outcome, q)?;
        }
    }
    Ok(())
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
    use crate::gonio::spectral_sums::SQUARE_ONE;
    use crate::hero::testing::{packed_sand, sand};
    use crate::hero::FIXED_ONE;
    use crate::medium::LambertianSurface;
    use crate::memory::Memory;

    fn on_threads<T: Send>(threads: usize, f: impl FnOnce() -> T + Send) -> T {
        rayon::ThreadPoolBuilder::new().num_threads(threads).build().unwrap().install(f)
    }

    /// The arrays of a shared run (escaped, squares, transmitted, launched, capped).
    type Arrays = [Vec<u64>; 5];

    /// Zeroed arrays for n incoming patches, r outgoing patches and w wavelengths.
    fn zeroed(n: usize, r: usize, w: usize) -> Arrays {
        [n * r * w, 2 * n * r * w, n * w, n, n].map(|n| vec![0u64; n])
    }

    /// The sum of squares at `cell` as a float (the u128 of its two words over 2⁶⁴).
    fn square(s: &[u64], cell: usize) -> f64 {
        (u128::from(s[2 * cell]) << 64 | u128::from(s[2 * cell + 1])) as f64 / SQUARE_ONE
    }

    /// The arrays as the sums a measurement adds to.
    fn as_sums(a: &mut Arrays) -> SpectralBrdfSums<'_> {
        let [escaped, squares, transmitted, launched, capped] = a;
        SpectralBrdfSums { escaped, squares, transmitted, launched, capped }
    }

    /// Shared sums of `group` over the rays of each batch `(first, n)` of seed 7, added in turn:
    /// uniform incidence, or every trial from `fixed` (one incoming patch).
    fn shared(group: &HeroGroup, h: &CollectorHemisphere, fixed: Option<Vec3>, batches: &[(u64, u64)]) -> Arrays {
        let (r, w) = (h.n_patches(), group.len());
        let mut arrays = zeroed(if fixed.is_some() { 1 } else { r }, r, w);
        let mut sums = as_sums(&mut arrays);
        for &(first, n) in batches {
            let (rays, limits) = (Rays { seed: 7, stream: 1, first, n }, Limits::default());
            match fixed {
                Some(toward_light) => measure_fixed_incidence_shared(group, h, toward_light, rays, &limits, &mut sums),
                None => measure_brdf_shared(group, h, rays, &limits, &mut sums),
            }
            .unwrap();
        }
        arrays
    }

    /// Light from 40° off the normal, azimuth 0.
    fn from_40_degrees() -> Vec3 {
        let t = 40f64.to_radians();
        Vec3::new(t.sin(), 0.0, t.cos())
    }

    #[test]
    fn shared_sums_do_not_depend_on_threads_or_batches() {
        let h = CollectorHemisphere::new(3, 4).unwrap();
        let media = vec![packed_sand(0.5, 0.0), packed_sand(2.0, 0.01), packed_sand(4.0, 0.02)];
        for (memory, fixed) in [(Memory::None, None), (Memory::Packed, None), (Memory::Packed, Some(from_40_degrees()))]
        {
            let g = HeroGroup::new(media.clone(), memory).unwrap();
            let one = on_threads(1, || shared(&g, &h, fixed, &[(0, 4000)]));
            for threads in [2, 3] {
                let other = on_threads(threads, || shared(&g, &h, fixed, &[(0, 4000)]));
                assert_eq!(other, one, "{memory:?}, {fixed:?}, {threads} threads");
            }
            let batches = on_threads(2, || shared(&g, &h, fixed, &[(0, 1000), (1000, 1), (1001, 2999)]));
            assert_eq!(batches, one, "{memory:?}, {fixed:?}");
            assert_eq!(one[3].iter().sum::<u64>(), 4000);
            assert!(one[0].iter().filter(|&&e| e > 0).count() > if fixed.is_some() { 20 } else { 100 });
        }
    }

    #[test]
    fn a_group_of_one_tallies_counts() {
        // One wavelength: every escaped trial weighs F = 1, so the sums are counts times 2³²
        // (and the squares the same counts: F² = 1).
        let h = CollectorHemisphere::new(3, 4).unwrap();
        let g = HeroGroup::new(vec![sand(1.0, 0.0)], Memory::None).unwrap();
        let [e, s, ..] = shared(&g, &h, None, &[(0, 3000)]);
        let one = FIXED_ONE as u64;
        assert!(e.iter().enumerate().all(|(c, &e)| e % one == 0 && (e / one) as f64 == square(&s, c)));
        assert!(e.iter().sum::<u64>() > 0);
    }

    /// Asserts that a shared estimate Σ F / N, with Σ F a fixed-point sum `e` and Σ F² = `s`
    /// over N trials, and an independent one n / N' agree within 4 standard errors (the shared
    /// one's Var = (Σ F²/N − (Σ F/N)²)/N; the independent one's binomial).
    fn assert_agree((e, s, n): (u64, f64, u64), (count, own_n): (u64, u64), what: &str) {
        let n = n as f64;
        let rho = e as f64 / FIXED_ONE / n;
        let var_shared = (s / n - rho * rho) / n;
        let mono = count as f64 / own_n as f64;
        let se = (var_shared + mono * (1.0 - mono) / own_n as f64).sqrt();
        assert!((rho - mono).abs() < 4.0 * se, "{what}: {rho} vs {mono} ± {se}");
    }

    #[test]
    fn shared_estimates_agree_with_independent_measurements() {
        // Two wavelengths that differ only in absorption (×6), against their own runs (stream
        // 0): uniform incidence per incoming patch i (escaped weight Σ_j over row i), and light
        // from 40° per outgoing patch j.
        let absorb = [0.5, 3.0];
        let g = HeroGroup::new(absorb.iter().map(|&a| sand(a, 0.0)).collect(), Memory::None).unwrap();
        let (w, n) = (absorb.len(), 40_000);
        let own = Rays { seed: 7, stream: 0, first: 0, n };
        let h = CollectorHemisphere::new(2, 4).unwrap();
        let r = h.n_patches();
        let [e, s, _, l, _] = shared(&g, &h, None, &[(0, n)]);
        for (k, &a) in absorb.iter().enumerate() {
            let t = measure_brdf(&sand(a, 0.0), &h, own, &Limits::default());
            for i in 0..r {
                let e_row = (0..r).map(|j| e[(i * r + j) * w + k]).sum::<u64>();
                let s_row = (0..r).map(|j| square(&s, (i * r + j) * w + k)).sum::<f64>();
                assert_agree((e_row, s_row, l[i]), (t.escaped(i), t.launched[i]), &format!("×{a}, in {i}"));
            }
        }
        let h = CollectorHemisphere::new(3, 4).unwrap();
        let [e, s, _, l, c] = shared(&g, &h, Some(from_40_degrees()), &[(0, n)]);
        assert_eq!((&l, c), (&vec![n], vec![0]));
        for (k, &a) in absorb.iter().enumerate() {
            let t = measure_fixed_incidence(&sand(a, 0.0), &h, from_40_degrees(), own, &Limits::default());
            for j in 0..h.n_patches() {
                let (e, s) = (e[j * w + k], square(&s, j * w + k));
                assert_agree((e, s, l[0]), (t.counts[j], t.launched), &format!("×{a}, out {j}"));
            }
        }
    }

    #[test]
    fn fixed_incidence_sums_must_have_one_incoming_patch() {
        let h = CollectorHemisphere::new(3, 4).unwrap();
        let g = HeroGroup::new(vec![sand(1.0, 0.0), sand(2.0, 0.0)], Memory::None).unwrap();
        // Sums sized for uniform incidence (r incoming patches).
        let mut arrays = zeroed(h.n_patches(), h.n_patches(), g.len());
        let rays = Rays { seed: 7, stream: 1, first: 0, n: 10 };
        let err = measure_fixed_incidence_shared(
            &g,
            &h,
            from_40_degrees(),
            rays,
            &Limits::default(),
            &mut as_sums(&mut arrays),
        );
        assert!(matches!(err, Err(SandlightError::Parameter { ref name, .. }) if name == "escaped"), "{err:?}");
        assert!(arrays[3].iter().all(|&l| l == 0));
    }

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

//! Tracing one ray through a medium below the plane z = 0 (docs/model.md §2.6): free paths in
//! the pore space, particles generated on the fly, the boundary, and the ray's fate.

use crate::fresnel;
use crate::math::{refract, Vec3};
use crate::medium::{IsotropicScatterers, LambertianSurface, Particulate};
use crate::particle::{interact_with_stacks, Absorber, Interaction, Mono, PathChoices};
use crate::rng::Rng;
use crate::sampling::{cosine_hemisphere, uniform_sphere};
use crate::spheroid::Spheroid;
use crate::volume_scatterer::{scattered, VolumeFate};

/// How a ray ended.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Fate {
    /// Left through the top boundary with this direction (z > 0).
    Escaped(Vec3),
    Absorbed,
    /// Left through the bottom of a finite sample.
    Transmitted,
    /// Stopped by an event cap; counted and reported, never silently dropped.
    Capped,
}

#[derive(Clone, Copy, Debug)]
pub struct RayOutcome {
    pub fate: Fate,
    /// Particle (or scatterer) events along the path.
    pub events: u64,
}

/// Caps that stop a ray that would otherwise run (almost) forever.
#[derive(Clone, Copy, Debug)]
pub struct Limits {
    /// Particle events per ray.
    pub max_events: u64,
    /// Internal reflections inside one particle.
    pub max_internal: u32,
}

impl Default for Limits {
    fn default() -> Self {
        Limits { max_events: 10_000_000, max_internal: 10_000 }
    }
}

/// Anything a ray can be traced through. `dir_in` points into the sample (z < 0).
pub trait Medium: Sync {
    fn trace(&self, dir_in: Vec3, rng: &mut Rng, limits: &Limits) -> RayOutcome;
}

/// The outward normal of the sample's top boundary.
pub(crate) const UP: Vec3 = Vec3::new(0.0, 0.0, 1.0);

/// A ray with direction `d` (into the sample) entering a water-filled surface pore, which
/// presents a flat water surface (our assumption, docs/transport.md): Fresnel air → water, then
/// Snell. The direction in the water, or None if the water surface reflects it (to
/// `d.reflect(UP)`). The tracers draw the pore themselves: an entry function that also drew it
/// and returned an enum made the loop of the memory tracer 3–5 % longer (valgrind).
#[inline]
pub(crate) fn enter_water_surface(
    water_n: f64,
    d: Vec3,
    rng: &mut Rng,
    choices: &mut impl PathChoices,
) -> Option<Vec3> {
    let reflected = rng.uniform() < fresnel::dielectric(1.0, water_n, -d.z);
    choices.water_surface(true, -d.z, reflected);
    if reflected {
        return None;
    }
    // Air → water never reflects totally; `d` is kept only as a guard.
    Some(refract(d, UP, 1.0 / water_n).unwrap_or(d))
}

/// A ray going up (`d.z > 0`) through a water-filled surface pore at its flat water surface:
/// Fresnel water → air, then Snell. The direction it escapes in, or None if it is reflected
/// (by Fresnel or totally), back down with d.z negated.
#[inline]
pub(crate) fn leave_water_surface(
    water_n: f64,
    d: Vec3,
    rng: &mut Rng,
    choices: &mut impl PathChoices,
) -> Option<Vec3> {
    let reflected = rng.uniform() < fresnel::dielectric(water_n, 1.0, d.z);
    choices.water_surface(false, d.z, reflected);
    if reflected {
        return None;
    }
    refract(d, -UP, water_n)
}

/// A meeting with type `i` of `m`, a volume scatterer, in a pore (water-filled if `water`) by a
/// ray along `d`: its fate and the direction after it (`d` unless it scattered). Shared by the
/// classic and the memory tracer.
#[inline]
pub(crate) fn meet_volume_scatterer(
    m: &Particulate,
    i: usize,
    water: bool,
    d: Vec3,
    rng: &mut Rng,
    choices: &mut impl PathChoices,
) -> (VolumeFate, Vec3) {
    let optics = m.volume_scatterer(i).expect("a volume-scatterer type").optics(water);
    let fate = choices.volume_fate(i, water, optics, rng.uniform());
    if fate != VolumeFate::Scatter {
        return (fate, d);
    }
    let mu = optics.phase.sample(rng.uniform());
    choices.volume_scattered(i, water, optics, mu);
    (fate, scattered(d, mu, rng.uniform()))
}

/// Sand traced on the fly without memory: every free path and every particle independent of
/// the past (docs/model.md §2.6). The path memory variants (`memory`) are a separate
/// tracer, so that this one's code, random numbers and speed stay those of the engine before
/// path memory existed.
impl Medium for Particulate {
    #[inline] // into `WithMemory::trace`, whose memory 'none' is this tracer
    fn trace(&self, dir_in: Vec3, rng: &mut Rng, limits: &Limits) -> RayOutcome {
        trace_classic(self, dir_in, rng, limits, &mut Mono)
    }
}

/// The classic tracer, its wavelength-dependent choices made through `choices` (`Mono`: this
/// medium's wavelength alone; `hero::Companions`: spectral path sharing).
// Always inlined, also into `WithMemory::trace`: a call per ray there cost 1 % of the
// instructions of a classic run (valgrind).
#[inline(always)]
pub(crate) fn trace_classic(
    m: &Particulate,
    dir_in: Vec3,
    rng: &mut Rng,
    limits: &Limits,
    choices: &mut impl PathChoices,
) -> RayOutcome {
    let pore = &m.pore;
    // Candidate meetings, volume scatterers at their majorant rate (`with_volume_scatterers`).
    let ell = m.flight_mean_free_path_mm;
    let mut z = 0.0f64;
    let mut events = 0u64;
    let done = |fate, events| RayOutcome { fate, events };
    // The pore at the surface where the ray enters, water-filled or not.
    let mut d = dir_in;
    let mut water = pore.draw_water(rng);
    if water {
        match enter_water_surface(pore.water_n, d, rng, choices) {
            Some(dir) => d = dir,
            None => return done(Fate::Escaped(d.reflect(UP)), 0),
        }
    }
    loop {
        let s = ell * rng.exponential();
        if d.z > 0.0 && z + s * d.z >= 0.0 {
            if !water {
                return done(Fate::Escaped(d), events);
            }
            // Through water to the water surface, then water → air.
            let to_surface = -z / d.z;
            if !choices.survives(Absorber::Water, pore.water_alpha_per_mm, to_surface, rng) {
                return done(Fate::Absorbed, events);
            }
            match leave_water_surface(pore.water_n, d, rng, choices) {
                Some(out) => return done(Fate::Escaped(out), events),
                None => {
                    d.z = -d.z;
                    z = 0.0;
                    continue;
                }
            }
        }
        if d.z < 0.0 && z + s * d.z <= -m.depth_mm {
            return done(Fate::Transmitted, events);
        }
        if water && !choices.survives(Absorber::Water, pore.water_alpha_per_mm, s, rng) {
            return done(Fate::Absorbed, events);
        }
        z += s * d.z;
        // The type is drawn before the event is counted: a null collision is no event (a
        // capped ray ends, so its remaining random numbers do not matter).
        let i = m.pick_index(rng.uniform());
        let volume = m.volume_scatterer(i).is_some().then(|| meet_volume_scatterer(m, i, water, d, rng, choices));
        if let Some((VolumeFate::Null, _)) = volume {
            continue;
        }
        events += 1;
        if events > limits.max_events {
            return done(Fate::Capped, events);
        }
        match volume {
            Some((VolumeFate::Absorb, _)) => return done(Fate::Absorbed, events),
            // Scattered in place: the ray stays in its pore.
            Some((_, dir)) => {
                d = dir;
                continue;
            }
            None => {}
        }
        choices.particle(i);
        let ptype = &m.types[i];
        let (a_over_d, stacks) = m.type_tables(i);
        let diameter = ptype.sizes.sample(rng);
        let shape = Spheroid::with_semi_axis_ratio(diameter, a_over_d, ptype.aspect_ratio, Spheroid::random_axis(rng));
        let Some(hit) = shape.sample_hit(d, rng, 10_000) else {
            return done(Fate::Capped, events);
        };
        match interact_with_stacks(
            &ptype.optics,
            stacks,
            pore,
            &shape,
            hit,
            d,
            water,
            rng,
            limits.max_internal,
            choices,
        ) {
            Interaction::Reflected { dir } => d = dir,
            Interaction::Transmitted { dir, exit_point, water: w } => {
                // The particle's extent along z: the ray leaves from the far side.
                z = (z + (exit_point.z - hit.point.z)).min(0.0);
                d = dir;
                water = w;
            }
            Interaction::Absorbed => return done(Fate::Absorbed, events),
            Interaction::Capped => return done(Fate::Capped, events),
        }
    }
}

impl Medium for IsotropicScatterers {
    fn trace(&self, dir_in: Vec3, rng: &mut Rng, limits: &Limits) -> RayOutcome {
        let mut d = dir_in;
        let mut z = 0.0f64;
        let mut events = 0u64;
        loop {
            let s = rng.exponential();
            if d.z > 0.0 && z + s * d.z >= 0.0 {
                return RayOutcome { fate: Fate::Escaped(d), events };
            }
            if d.z < 0.0 && z + s * d.z <= -self.depth {
                return RayOutcome { fate: Fate::Transmitted, events };
            }
            z += s * d.z;
            events += 1;
            if events > limits.max_events {
                return RayOutcome { fate: Fate::Capped, events };
            }
            if rng.uniform() >= self.albedo {
                return RayOutcome { fate: Fate::Absorbed, events };
            }
            d = uniform_sphere([rng.uniform(), rng.uniform()]);
        }
    }
}

impl Medium for LambertianSurface {
    fn trace(&self, _dir_in: Vec3, rng: &mut Rng, _limits: &Limits) -> RayOutcome {
        let fate = if rng.uniform() < self.albedo {
            Fate::Escaped(cosine_hemisphere([rng.uniform(), rng.uniform()]))
        } else {
            Fate::Absorbed
        };
        RayOutcome { fate, events: 1 }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::medium::ParticleType;
    use crate::particle::{ParticleOptics, PoreOptics};
    use crate::sizes::QuantileTable;
    use crate::volume_scatterer::testing::{henyey_greenstein, scatterer};
    use crate::volume_scatterer::VolumeScatterer;

    const N_WATER: f64 = 1.333;

    /// Clear quartz-like spheroids (no absorption anywhere) in a slab `depth_mm` thick.
    fn clear_sand(pore: PoreOptics, depth_mm: f64) -> Particulate {
        let optics = ParticleOptics::clear(1.544);
        let sizes = QuantileTable::new((0..17).map(|j| 0.15 + 0.2 * j as f64 / 16.0).collect()).unwrap();
        let t = ParticleType { probability: 1.0, sizes, aspect_ratio: 1.4, optics };
        Particulate::new(vec![t], 0.1, pore, depth_mm).unwrap()
    }

    fn wet_pores() -> PoreOptics {
        PoreOptics {
            water_n: N_WATER,
            water_alpha_per_mm: 0.0,
            film_thickness_mm: 0.01,
            film_coverage: 1.0,
            water_filled_probability: 0.5,
        }
    }

    /// Fates of rays 0..n at incidence `dir_in`: [escaped, absorbed, transmitted, capped].
    fn fates(medium: &impl Medium, dir_in: Vec3, n: u64, limits: &Limits) -> [u64; 4] {
        let mut c = [0u64; 4];
        for i in 0..n {
            let out = medium.trace(dir_in, &mut Rng::for_ray(3, 0, i), limits);
            let k = match out.fate {
                Fate::Escaped(d) => {
                    assert!(d.z > 0.0 && (d.norm2() - 1.0).abs() < 1e-9, "escaped downwards or not unit: {d:?}");
                    0
                }
                Fate::Absorbed => 1,
                Fate::Transmitted => 2,
                Fate::Capped => 3,
            };
            c[k] += 1;
        }
        c
    }

    fn oblique(theta_deg: f64) -> Vec3 {
        let t = theta_deg.to_radians();
        Vec3::new(t.sin(), 0.0, -t.cos())
    }

    #[test]
    fn a_clear_slab_absorbs_nothing() {
        // No absorption in grains, films or water: every ray leaves by the top or the bottom,
        // dry and with water-filled pores (through the flat water surface both ways).
        for pore in [PoreOptics::DRY, wet_pores()] {
            let c = fates(&clear_sand(pore, 1.0), oblique(40.0), 2000, &Limits::default());
            assert_eq!(c[0] + c[2], 2000, "{pore:?}: {c:?}");
            assert!(c[0] > 0 && c[2] > 0, "{c:?}");
        }
    }

    #[test]
    fn a_clear_half_space_returns_every_ray_or_caps_it() {
        // The semi-infinite sample has no bottom: a ray comes back or meets the event cap (the
        // return time of a 3D random walk has a heavy tail, so a small cap is met now and then).
        let limits = Limits { max_events: 2000, max_internal: 10_000 };
        let c = fates(&clear_sand(wet_pores(), f64::INFINITY), oblique(0.0), 1000, &limits);
        assert_eq!((c[1], c[2]), (0, 0), "{c:?}");
        assert_eq!(c[0] + c[3], 1000);
        assert!(c[3] < 100, "{c:?}");
    }

    /// Chandrasekhar's H function of isotropic scattering, iterating
    /// 1/H(μ) = √(1 − ω) + (ω/2) ∫₀¹ μ′ H(μ′)/(μ + μ′) dμ′ (Chandrasekhar 1960, eq. IV.(40))
    /// on a midpoint rule in μ′ (within 1e-7 of Gauss–Legendre solutions, far below the Monte Carlo
    /// error here).
    fn chandrasekhar_h(albedo: f64, mu: f64) -> f64 {
        let m = 800;
        let nodes: Vec<f64> = (0..m).map(|k| (k as f64 + 0.5) / m as f64).collect();
        let one_over_h = |h: &[f64], x: f64| {
            let integral: f64 = nodes.iter().zip(h).map(|(&y, &hy)| y * hy / (x + y)).sum::<f64>() / m as f64;
            (1.0 - albedo).sqrt() + 0.5 * albedo * integral
        };
        let mut h = vec![1.0; m];
        for _ in 0..200 {
            h = nodes.iter().map(|&x| 1.0 / one_over_h(&h, x)).collect();
        }
        1.0 / one_over_h(&h, mu)
    }

    #[test]
    fn isotropic_half_space_matches_chandrasekhar() {
        // Directional-hemispherical reflectance 1 − H(μ₀)√(1 − ω) of the half-space
        // (docs/model.md §2.7), within 4 binomial standard errors.
        let n = 100_000;
        for (albedo, theta_deg) in [(0.8, 0.0), (0.8, 60.0), (0.99, 30.0)] {
            assert_chandrasekhar(&IsotropicScatterers::new(albedo, f64::INFINITY).unwrap(), albedo, theta_deg, n);
        }
    }

    /// Directional-hemispherical reflectance of `medium` at `theta_deg` over `n` rays is
    /// Chandrasekhar's 1 − H(μ₀)√(1 − ω) within 4 binomial standard errors, no ray lost.
    fn assert_chandrasekhar(medium: &impl Medium, albedo: f64, theta_deg: f64, n: u64) {
        let dir = oblique(theta_deg);
        let c = fates(medium, dir, n, &Limits::default());
        assert_eq!((c[2], c[3]), (0, 0));
        assert_eq!(c[0] + c[1], n);
        let expected = 1.0 - chandrasekhar_h(albedo, -dir.z) * (1.0 - albedo).sqrt();
        let se = (expected * (1.0 - expected) / n as f64).sqrt();
        let got = c[0] as f64 / n as f64;
        assert!((got - expected).abs() < 4.0 * se, "ω {albedo}, θ {theta_deg}°: {got} vs {expected} ± {se}");
    }

    #[test]
    fn volume_scatterers_with_null_collisions_match_chandrasekhar() {
        // A medium of volume scatterers only, isotropic, met at twice the rate of their real
        // collisions (majorant 2, extinction 1/2): the real collisions are isotropic point
        // scatterers of mean free path ℓ, Chandrasekhar's half-space, within 4 standard errors.
        let n = 60_000;
        let albedo = 0.8;
        let grains = clear_sand(PoreOptics::DRY, f64::INFINITY);
        let medium =
            grains.with_volume_scatterers(vec![Some(scatterer(2.0, henyey_greenstein(0.5, albedo, 0.0)))]).unwrap();
        assert_eq!(medium.flight_mean_free_path_mm, 0.05);
        assert_chandrasekhar(&medium, albedo, 30.0, n);
    }

    #[test]
    fn a_lossless_half_space_with_volume_scatterers_returns_every_ray_or_caps_it() {
        // Clear grains and forward-scattering, non-absorbing volume scatterers (ω = 1), dry and
        // with water-filled pores: no ray is absorbed.
        let limits = Limits { max_events: 5000, max_internal: 10_000 };
        for pore in [PoreOptics::DRY, wet_pores()] {
            let grains = clear_sand(pore, f64::INFINITY);
            let fine = ParticleType { probability: 2.0, ..grains.types[0].clone() };
            let m = Particulate::new(vec![grains.types[0].clone(), fine], 0.1, pore, f64::INFINITY)
                .unwrap()
                .with_volume_scatterers(vec![None, Some(scatterer(3.0, henyey_greenstein(0.7, 1.0, 0.8)))])
                .unwrap();
            let c = fates(&m, oblique(20.0), 1000, &limits);
            assert_eq!((c[1], c[2]), (0, 0), "{pore:?}: {c:?}");
            assert!(c[3] < 100, "{c:?}");
        }
    }

    #[test]
    fn volume_scatterers_without_water_optics_are_refused_for_wet_pores() {
        let grains = clear_sand(wet_pores(), f64::INFINITY);
        let air_only = VolumeScatterer::new(2.0, henyey_greenstein(0.5, 0.5, 0.0), None).unwrap();
        let e = grains.with_volume_scatterers(vec![Some(air_only)]).unwrap_err();
        assert!(e.to_string().contains("volume_scatterers"), "{e}");
    }

    #[test]
    fn conservative_isotropic_slab_reflects_or_transmits_everything() {
        let c = fates(&IsotropicScatterers::new(1.0, 2.0).unwrap(), oblique(20.0), 20_000, &Limits::default());
        assert_eq!((c[1], c[3]), (0, 0));
        assert_eq!(c[0] + c[2], 20_000);
        assert!(c[0] > 0 && c[2] > 0);
    }

    #[test]
    fn lambertian_surface_reflects_its_albedo_by_the_cosine_law() {
        let n = 100_000;
        let m = LambertianSurface::new(0.7).unwrap();
        let (mut escaped, mut sum_mu) = (0u64, 0.0);
        for i in 0..n {
            if let Fate::Escaped(d) = m.trace(oblique(50.0), &mut Rng::for_ray(1, 0, i), &Limits::default()).fate {
                escaped += 1;
                sum_mu += d.z;
            }
        }
        let se = (0.7f64 * 0.3 / n as f64).sqrt();
        assert!((escaped as f64 / n as f64 - 0.7).abs() < 4.0 * se);
        // E[cos θ] = 2/3 under pdf cos θ/π, standard deviation √(1/2 − 4/9).
        let se_mu = (0.5f64 - 4.0 / 9.0).sqrt() / (escaped as f64).sqrt();
        assert!((sum_mu / escaped as f64 - 2.0 / 3.0).abs() < 4.0 * se_mu);
    }

    #[test]
    fn a_water_surface_reflects_by_fresnel_and_refracts_by_snell() {
        let n = 200_000;
        for theta_deg in [0.0, 60.0] {
            let d = oblique(theta_deg);
            let r = fresnel::dielectric(1.0, N_WATER, -d.z);
            let mut reflected = 0;
            for i in 0..n {
                match enter_water_surface(N_WATER, d, &mut Rng::for_ray(2, 0, i), &mut Mono) {
                    None => reflected += 1,
                    // sin θ_air = n sin θ_water, in the plane of incidence.
                    Some(dir) => assert!((d.x - N_WATER * dir.x).abs() < 1e-12 && dir.y == 0.0 && dir.z < 0.0),
                }
            }
            let se = (r * (1.0 - r) / n as f64).sqrt();
            assert!((reflected as f64 / n as f64 - r).abs() < 4.0 * se, "θ {theta_deg}°: {reflected} vs R = {r}");
        }
        // Normal incidence: R = ((n − 1)/(n + 1))².
        assert!((fresnel::dielectric(1.0, N_WATER, 1.0) - ((N_WATER - 1.0) / (N_WATER + 1.0)).powi(2)).abs() < 1e-12);
        // The reflected direction the tracers report is the mirror image in the surface.
        assert_eq!(oblique(60.0).reflect(UP), Vec3::new(oblique(60.0).x, 0.0, -oblique(60.0).z));
    }

    #[test]
    fn a_dry_surface_takes_no_random_numbers() {
        // Dry pores draw nothing at the surface, so dry runs keep the random sequence they had
        // before water existed; a wet pore draws one number.
        let mut rng = Rng::for_ray(4, 0, 0);
        assert!(!PoreOptics::DRY.draw_water(&mut rng));
        assert_eq!(rng.next_u64(), Rng::for_ray(4, 0, 0).next_u64());
        let mut rng = Rng::for_ray(4, 0, 0);
        wet_pores().draw_water(&mut rng);
        let mut fresh = Rng::for_ray(4, 0, 0);
        fresh.next_u64();
        assert_eq!(rng.next_u64(), fresh.next_u64());
    }

    #[test]
    fn water_to_air_escapes_by_snell_and_reflects_totally_past_the_critical_angle() {
        let n = 100_000;
        let sin_critical = 1.0 / N_WATER;
        for sin_w in [0.0, 0.5, sin_critical + 1e-6, 0.9] {
            let d = Vec3::new(sin_w, 0.0, (1.0 - sin_w * sin_w).sqrt());
            let r = if sin_w > sin_critical { 1.0 } else { fresnel::dielectric(N_WATER, 1.0, d.z) };
            let mut kept = 0;
            for i in 0..n {
                match leave_water_surface(N_WATER, d, &mut Rng::for_ray(6, 0, i), &mut Mono) {
                    Some(out) => assert!((out.x - N_WATER * sin_w).abs() < 1e-12 && out.z > 0.0),
                    None => kept += 1,
                }
            }
            if r == 1.0 {
                assert_eq!(kept, n);
            } else {
                let se = (r * (1.0 - r) / n as f64).sqrt();
                assert!((kept as f64 / n as f64 - r).abs() < 4.0 * se + 1e-12, "sin {sin_w}: {kept} vs {r}");
            }
        }
    }
}

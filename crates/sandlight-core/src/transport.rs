//! Tracing one ray through a medium below the plane z = 0 (splits-model.md §2.6): free paths in
//! the pore space, particles generated on the fly, the boundary, and the ray's fate.

use crate::fresnel;
use crate::math::{refract, Vec3};
use crate::medium::{IsotropicScatterers, LambertianSurface, Particulate};
use crate::particle::{interact_with_stacks, survives, Interaction, PoreOptics};
use crate::rng::Rng;
use crate::sampling::{cosine_hemisphere, uniform_sphere};
use crate::spheroid::Spheroid;

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
const UP: Vec3 = Vec3::new(0.0, 0.0, 1.0);

/// What becomes of a ray from the air at the sample's top boundary (`enter_surface`).
pub(crate) enum SurfaceEntry {
    /// Turned back by the water surface of a water-filled surface pore, in this direction.
    Reflected(Vec3),
    /// In the sample with direction `dir`, in a water-filled pore or not.
    Entered { dir: Vec3, water: bool },
}

/// A ray with direction `d` (into the sample) at the top boundary. The pore at the surface where
/// it enters is drawn water-filled or not; a water-filled surface pore presents a flat water
/// surface (our assumption, docs/transport.md): Fresnel air → water, then Snell.
#[inline]
pub(crate) fn enter_surface(pore: &PoreOptics, d: Vec3, rng: &mut Rng) -> SurfaceEntry {
    if !pore.draw_water(rng) {
        return SurfaceEntry::Entered { dir: d, water: false };
    }
    if rng.uniform() < fresnel::dielectric(1.0, pore.water_n, -d.z) {
        return SurfaceEntry::Reflected(d.reflect(UP));
    }
    // Air → water never reflects totally; `d` is kept only as a guard.
    SurfaceEntry::Entered { dir: refract(d, UP, 1.0 / pore.water_n).unwrap_or(d), water: true }
}

/// A ray going up (`d.z > 0`) through a water-filled surface pore at its flat water surface:
/// Fresnel water → air, then Snell. The direction it escapes in, or None if it is reflected
/// (by Fresnel or totally), back down with d.z negated.
#[inline]
pub(crate) fn leave_water_surface(water_n: f64, d: Vec3, rng: &mut Rng) -> Option<Vec3> {
    if rng.uniform() < fresnel::dielectric(water_n, 1.0, d.z) {
        return None;
    }
    refract(d, -UP, water_n)
}

/// Sand traced on the fly without memory: every free path and every particle independent of
/// the past (splits-model.md §2.6). The path memory variants (`memory`) are a separate
/// tracer, so that this one's code, random numbers and speed stay those of the engine before
/// path memory existed.
impl Medium for Particulate {
    fn trace(&self, dir_in: Vec3, rng: &mut Rng, limits: &Limits) -> RayOutcome {
        trace_classic(self, dir_in, rng, limits)
    }
}

fn trace_classic(m: &Particulate, dir_in: Vec3, rng: &mut Rng, limits: &Limits) -> RayOutcome {
    let pore = &m.pore;
    let ell = m.mean_free_path_mm;
    let mut z = 0.0f64;
    let mut events = 0u64;
    let done = |fate, events| RayOutcome { fate, events };
    let (mut d, mut water) = match enter_surface(pore, dir_in, rng) {
        SurfaceEntry::Reflected(out) => return done(Fate::Escaped(out), 0),
        SurfaceEntry::Entered { dir, water } => (dir, water),
    };
    loop {
        let s = ell * rng.exponential();
        if d.z > 0.0 && z + s * d.z >= 0.0 {
            if !water {
                return done(Fate::Escaped(d), events);
            }
            // Through water to the water surface, then water → air.
            let to_surface = -z / d.z;
            if !survives(rng.uniform(), pore.water_alpha_per_mm * to_surface) {
                return done(Fate::Absorbed, events);
            }
            match leave_water_surface(pore.water_n, d, rng) {
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
        if water && pore.water_alpha_per_mm > 0.0 && !survives(rng.uniform(), pore.water_alpha_per_mm * s) {
            return done(Fate::Absorbed, events);
        }
        z += s * d.z;
        events += 1;
        if events > limits.max_events {
            return done(Fate::Capped, events);
        }
        let i = m.pick_index(rng.uniform());
        let ptype = &m.types[i];
        let (a_over_d, stacks) = m.type_tables(i);
        let diameter = ptype.sizes.sample(rng);
        let shape = Spheroid::with_semi_axis_ratio(diameter, a_over_d, ptype.aspect_ratio, Spheroid::random_axis(rng));
        let Some(hit) = shape.sample_hit(d, rng, 10_000) else {
            return done(Fate::Capped, events);
        };
        match interact_with_stacks(&ptype.optics, stacks, pore, &shape, hit, d, water, rng, limits.max_internal) {
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

//! One particle's interaction with a ray: the function shared by the on-the-fly transport and
//! any explicit-geometry tracer, so that differences between the two come from geometry alone.
//!
//! Physics (splits-model.md §2.4): Fresnel reflection or Snell refraction at the outer surface
//! through an optional water film and an optional coating (thin incoherent layers, see
//! `layers`), a straight chord through the absorbing core (Beer–Lambert, exp(−α L)), Fresnel
//! from inside with total internal reflection, repeated until the ray leaves or is absorbed.

use crate::layers::{stack_rt, Slab, MAX_MEDIA};
use crate::math::{refract, Vec3};
use crate::rng::Rng;
use crate::spheroid::{Hit, Spheroid};

/// A thin layer on the particle surface: real index, absorption coefficient (mm⁻¹), thickness (mm).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Coating {
    pub n: f64,
    pub alpha_per_mm: f64,
    pub thickness_mm: f64,
}

/// Optical description of one particle type at one wavelength.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ParticleOptics {
    /// Real index of the core.
    pub core_n: f64,
    /// Imaginary index of the core, used in the Fresnel reflectance at entry.
    pub core_k: f64,
    /// Absorption coefficient of the core (mm⁻¹), 4πk/λ of the (effective) core material.
    pub core_alpha_per_mm: f64,
    pub coating: Option<Coating>,
    /// Whether pore-water films wet this particle (all do; kept explicit for test scenes).
    pub wets: bool,
}

/// The pore space: water optics, film thickness and the chance that a pore is water-filled.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PoreOptics {
    pub water_n: f64,
    pub water_alpha_per_mm: f64,
    /// Thickness (mm) of the water film on every particle facing an air-filled pore.
    pub film_thickness_mm: f64,
    /// Probability that a pore the ray enters is filled with water (bulk water).
    pub water_filled_probability: f64,
}

impl PoreOptics {
    pub const DRY: PoreOptics = PoreOptics { water_n: 1.333, water_alpha_per_mm: 0.0, film_thickness_mm: 0.0, water_filled_probability: 0.0 };

    #[inline]
    pub fn index(&self, water: bool) -> f64 {
        if water { self.water_n } else { 1.0 }
    }
    /// Draws whether a newly entered pore is water-filled.
    #[inline]
    pub fn draw_water(&self, rng: &mut Rng) -> bool {
        self.water_filled_probability > 0.0 && rng.uniform() < self.water_filled_probability
    }
}

/// What became of the ray at one particle.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Interaction {
    /// Reflected at the outer surface; the ray stays in the pore it came from.
    Reflected { dir: Vec3 },
    /// Went through the particle and left at `exit_point` (relative to the particle centre) into
    /// a new pore, water-filled or not.
    Transmitted { dir: Vec3, exit_point: Vec3, water: bool },
    Absorbed,
    /// Stopped by the internal-reflection cap (counted and reported by the caller).
    Capped,
}

/// Media from the pore (index 0) to the core (last), with the film only facing an air pore.
fn entry_stack(p: &ParticleOptics, pore: &PoreOptics, water: bool) -> Stack {
    let mut out = Stack { media: [Slab::semi_infinite(1.0); MAX_MEDIA], len: 0 };
    let mut push = |s: Slab| {
        out.media[out.len] = s;
        out.len += 1;
    };
    push(Slab::semi_infinite(pore.index(water)));
    if !water && p.wets && pore.film_thickness_mm > 0.0 {
        push(Slab { n: pore.water_n, alpha_per_mm: pore.water_alpha_per_mm, thickness_mm: pore.film_thickness_mm, k_fresnel: 0.0 });
    }
    if let Some(c) = p.coating {
        push(Slab { n: c.n, alpha_per_mm: c.alpha_per_mm, thickness_mm: c.thickness_mm, k_fresnel: 0.0 });
    }
    push(Slab { n: p.core_n, alpha_per_mm: 0.0, thickness_mm: 0.0, k_fresnel: p.core_k });
    out
}

/// The same media in reverse order (core first); Fresnel from inside uses the real core index.
fn exit_stack(p: &ParticleOptics, pore: &PoreOptics, water: bool) -> Stack {
    let mut out = entry_stack(p, pore, water);
    out.media[..out.len].reverse();
    out.media[0].k_fresnel = 0.0;
    out
}

/// A stack of media (see `layers`), stored inline.
#[derive(Clone, Copy, Debug, PartialEq)]
struct Stack {
    media: [Slab; MAX_MEDIA],
    len: usize,
}

impl Stack {
    #[inline]
    fn rt(&self, cos_0: f64) -> (f64, f64) {
        stack_rt(&self.media[..self.len], cos_0)
    }
}

/// The layer stacks of one particle type in one pore space: into the particle and out of it,
/// each for an air- and a water-filled pore. They depend only on the optics, so a medium builds
/// them once (`Particulate::new`) rather than at every interaction.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Stacks {
    /// Indexed by `water as usize`.
    entry: [Stack; 2],
    exit: [Stack; 2],
}

impl Stacks {
    pub fn new(p: &ParticleOptics, pore: &PoreOptics) -> Stacks {
        Stacks {
            entry: [entry_stack(p, pore, false), entry_stack(p, pore, true)],
            exit: [exit_stack(p, pore, false), exit_stack(p, pore, true)],
        }
    }
}

/// Survival of Beer–Lambert attenuation over optical depth `x` = α L ≥ 0 for a uniform `u` in
/// [0, 1): u < exp(−x). Since exp(−x) ≥ 1 − x, u < 1 − x already decides survival, and the
/// exponential is evaluated only in the remaining fraction x of cases (rare for the thin,
/// weakly absorbing paths that dominate).
#[inline]
pub fn survives(u: f64, x: f64) -> bool {
    u < 1.0 - x || u < (-x).exp()
}

/// Traces a ray arriving along `d` at `hit` on particle `shape` from a pore (water-filled if
/// `water`). `max_internal` caps internal reflections.
#[inline]
pub fn interact(p: &ParticleOptics, pore: &PoreOptics, shape: &Spheroid, hit: Hit, d: Vec3, water: bool, rng: &mut Rng, max_internal: u32) -> Interaction {
    interact_with_stacks(p, &Stacks::new(p, pore), pore, shape, hit, d, water, rng, max_internal)
}

/// `interact` with the particle type's layer stacks built beforehand (`Stacks::new(p, pore)`).
#[inline]
#[allow(clippy::too_many_arguments)]
pub fn interact_with_stacks(p: &ParticleOptics, stacks: &Stacks, pore: &PoreOptics, shape: &Spheroid, hit: Hit, d: Vec3, water: bool, rng: &mut Rng, max_internal: u32) -> Interaction {
    let cos_i = (-d.dot(hit.normal)).clamp(0.0, 1.0);
    let (r, t) = stacks.entry[water as usize].rt(cos_i);
    let u = rng.uniform();
    if u < r {
        return Interaction::Reflected { dir: d.reflect(hit.normal) };
    }
    if u >= r + t {
        return Interaction::Absorbed;
    }
    let n_out = pore.index(water);
    let mut dir = match refract(d, hit.normal, n_out / p.core_n) {
        Some(t) => t,
        None => return Interaction::Reflected { dir: d.reflect(hit.normal) },
    };
    let mut x = hit.point;
    for _ in 0..max_internal {
        let (len, x1) = shape.chord_from_surface(x, dir);
        // Beer–Lambert along the chord.
        if p.core_alpha_per_mm > 0.0 && !survives(rng.uniform(), p.core_alpha_per_mm * len) {
            return Interaction::Absorbed;
        }
        let n1 = shape.normal_at(x1);
        let cos_in = dir.dot(n1).clamp(0.0, 1.0);
        // The pore beyond this point of the surface.
        let water_beyond = pore.draw_water(rng);
        let (r, t) = stacks.exit[water_beyond as usize].rt(cos_in);
        let u = rng.uniform();
        if u < r {
            dir = dir.reflect(n1);
            x = x1;
            continue;
        }
        if u >= r + t {
            return Interaction::Absorbed;
        }
        match refract(dir, -n1, p.core_n / pore.index(water_beyond)) {
            Some(out) => return Interaction::Transmitted { dir: out, exit_point: x1, water: water_beyond },
            None => {
                // At the critical angle to rounding: T was ~0; treat as internal reflection.
                dir = dir.reflect(n1);
                x = x1;
            }
        }
    }
    Interaction::Capped
}

#[cfg(test)]
mod tests {
    use super::*;

    fn glass(n: f64) -> ParticleOptics {
        ParticleOptics { core_n: n, core_k: 0.0, core_alpha_per_mm: 0.0, coating: None, wets: true }
    }

    #[test]
    fn survival_shortcut_is_the_beer_lambert_test() {
        let mut rng = Rng::for_ray(2, 0, 0);
        for &x in &[0.0, 1e-9, 1e-4, 0.003, 0.1, 0.5, 1.0, 3.0, 40.0] {
            for _ in 0..20_000 {
                let u = rng.uniform();
                assert_eq!(survives(u, x), u < (-x).exp(), "u {u} x {x}");
            }
        }
    }

    #[test]
    fn transparent_sphere_never_absorbs_and_directions_are_unit() {
        let mut rng = Rng::for_ray(11, 0, 0);
        let s = Spheroid::new(0.25, 1.0, Vec3::new(0.0, 0.0, 1.0));
        let d = Vec3::new(0.0, 0.0, -1.0);
        for _ in 0..10_000 {
            let hit = s.sample_hit(d, &mut rng, 100).unwrap();
            match interact(&glass(1.5), &PoreOptics::DRY, &s, hit, d, false, &mut rng, 10_000) {
                Interaction::Reflected { dir } | Interaction::Transmitted { dir, .. } => assert!((dir.norm2() - 1.0).abs() < 1e-9),
                other => panic!("unexpected {other:?}"),
            }
        }
    }
}

//! Near-surface path memory of the on-the-fly engine (docs/geometry.md, "Near-surface path
//! memory"): a sand medium (`Particulate`) wrapped with the memory its rays keep of the pore
//! they are in, the cut-plane surface layer (`surface_layer`) and the pair correlation of the
//! packed grains (`pair_correlation`), and the tracer that uses them, its wavelength-dependent
//! choices made through `PathChoices` (one wavelength, or a spectral group's hero with its
//! companions, `hero`).

use std::sync::OnceLock;

use crate::math::Vec3;
use crate::medium::Particulate;
use crate::pair_correlation::PairCorrelation;
use crate::particle::{interact_with_stacks, Absorber, Interaction, Mono, PathChoices};
use crate::rng::Rng;
use crate::spheroid::{Hit, Spheroid};
use crate::surface_layer::SurfaceLayer;
use crate::transport::{
    enter_water_surface, leave_water_surface, meet_volume_scatterer, Fate, Limits, Medium, RayOutcome, UP,
};
use crate::volume_scatterer::VolumeFate;

/// What a ray remembers near the surface.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum Memory {
    /// The classic model: every free path and every particle independent of the past.
    #[default]
    None,
    /// One-segment channel memory: a particle drawn on the fly must not lie across the pore
    /// segment the ray has just travelled (when the ray is still in that pore); a candidate
    /// that would is discarded and the flight goes on (thinning). For the first segment this
    /// is the entry channel from the surface, which a ray turned back along it can leave by.
    Channel,
    /// `Channel` plus the surface of the explicit reference: the sample is cut through a plane
    /// of grain centres (z = 0), so grains whose centre would lie above it are discarded and the
    /// pore space not taken by packed grains widens towards the top (`SurfaceLayer`); and the
    /// ray remembers the packed grains that bound the pore it is in (its walls) until it goes
    /// through one of them.
    Cut,
    /// `Cut` plus the packing's pair correlation: a packed sphere met after leaving a packed
    /// sphere is hit where the pair correlation g of packed grains puts it relative to the one
    /// left (no overlap, contacts), instead of uniformly over its shadow (`PairCorrelation`).
    Packed,
}

/// A sand medium traced with near-surface path memory `memory`; `Memory::None` traces it as
/// the `Particulate` itself does.
#[derive(Clone, Debug)]
pub struct WithMemory {
    pub medium: Particulate,
    pub memory: Memory,
    /// What the memory tracer keeps beside the medium (None for `Memory::None`), built by the
    /// first ray traced: a medium given to a spectral group is never traced on its own (the
    /// group builds one `PathMemory` for all its media), so it never pays for one. It depends
    /// on the medium alone, so when and on which thread it is built changes no path.
    paths: OnceLock<Option<PathMemory>>,
}

impl WithMemory {
    pub fn new(medium: Particulate, memory: Memory) -> WithMemory {
        WithMemory { medium, memory, paths: OnceLock::new() }
    }

    /// The path memory of the medium (None for `Memory::None`), built on first use.
    fn paths(&self) -> Option<&PathMemory> {
        self.paths.get_or_init(|| PathMemory::new(&self.medium, self.memory)).as_ref()
    }
}

impl Medium for WithMemory {
    fn trace(&self, dir_in: Vec3, rng: &mut Rng, limits: &Limits) -> RayOutcome {
        match self.paths() {
            None => self.medium.trace(dir_in, rng, limits),
            Some(paths) => trace_with_memory(paths, &self.medium, dir_in, rng, limits, &mut Mono),
        }
    }
}

/// The path memory `Channel`, `Cut` or `Packed` of a sand medium: the cut-plane top layer and
/// the pair correlation of its packed grains. Both depend on the medium's geometry alone
/// (particle types, sizes, shapes, free path), so the media of a spectral group, which share
/// it, share one (`hero::HeroGroup`).
#[derive(Clone, Debug)]
pub struct PathMemory {
    /// The cut-plane top layer, for `Memory::Cut` and `Memory::Packed`.
    surface: Option<SurfaceLayer>,
    /// The pair correlation of the packed grains, for `Memory::Packed`.
    neighbours: Option<PairCorrelation>,
}

impl PathMemory {
    /// The memory `memory` of `medium`; None for `Memory::None` (the classic tracer).
    pub fn new(medium: &Particulate, memory: Memory) -> Option<PathMemory> {
        if memory == Memory::None {
            return None;
        }
        let surface = matches!(memory, Memory::Cut | Memory::Packed).then(|| SurfaceLayer::of(medium));
        let mut p = PathMemory { surface, neighbours: None };
        // Only spheres have a pair correlation here (docs/geometry.md): none packed, none needed.
        let packed_spheres = (0..medium.types.len()).any(|i| p.is_packed_sphere(medium, i));
        p.neighbours = p
            .surface
            .as_ref()
            .filter(|_| memory == Memory::Packed && packed_spheres)
            .map(|s| PairCorrelation::at_packing_fraction(s.packed_fraction));
        Some(p)
    }

    /// Whether type `i` of `m` is a packed grain of the cut-plane model (not a fine particle)
    /// and a sphere: the grains the pair correlation of `Memory::Packed` describes.
    #[inline]
    fn is_packed_sphere(&self, m: &Particulate, i: usize) -> bool {
        self.surface.as_ref().is_some_and(|s| s.packed[i]) && m.types[i].aspect_ratio == 1.0
    }
}

/// A grain the memory keeps: its shape, centre (sample frame) and type.
#[derive(Clone, Copy, Default)]
struct Grain {
    shape: Spheroid,
    centre: Vec3,
    type_index: usize,
}

/// The packed grains that bound the pore a ray is in (`Memory::Cut`): the grain it left to
/// enter the pore and those it was turned back by since, the latest `N`. Fine particles live
/// inside pores and do not change it.
///
/// Slots fill in order and are then overwritten round the ring, so the walls are always the
/// first `len` slots, in slot order.
#[derive(Clone, Copy, Default)]
struct PoreWalls {
    grains: [Grain; PoreWalls::N],
    len: usize,
    next: usize,
}

impl PoreWalls {
    const N: usize = 4;

    /// Forgets every wall (a new pore).
    #[inline]
    fn clear(&mut self) {
        (self.len, self.next) = (0, 0);
    }

    fn add(&mut self, g: Grain) {
        if self.grains().any(|w| w.centre == g.centre) {
            return;
        }
        self.grains[self.next] = g;
        self.next = (self.next + 1) % Self::N;
        self.len = (self.len + 1).min(Self::N);
    }

    #[inline]
    fn grains(&self) -> std::slice::Iter<'_, Grain> {
        self.grains[..self.len].iter()
    }

    fn contain(&self, p: Vec3) -> bool {
        self.grains().any(|g| g.shape.contains(p - g.centre))
    }
}

/// Which remembered grain a flight meets first (`nearest_remembered`): `BEHIND`, or the wall in
/// that slot of `PoreWalls`. An index rather than a copy of the grain: `behind` and the walls do
/// not change between the search and the flight that uses it.
const BEHIND: usize = PoreWalls::N;

/// The nearest of the remembered grains (`behind` and the `walls`) that a flight from `from`
/// along `d` enters, and the distance to it (infinite and None if it enters none).
fn nearest_remembered(behind: &Option<Grain>, walls: &PoreWalls, from: Vec3, d: Vec3) -> (f64, Option<usize>) {
    let (mut to_ahead, mut ahead) = (f64::INFINITY, None);
    // A packed grain behind is also a wall: measured once.
    if let Some(b) = behind.as_ref().filter(|b| !walls.grains().any(|w| w.centre == b.centre)) {
        if let Some(t) = b.shape.entry_distance(from - b.centre, d) {
            if t < to_ahead {
                (to_ahead, ahead) = (t, Some(BEHIND));
            }
        }
    }
    for (k, g) in walls.grains().enumerate() {
        if let Some(t) = g.shape.entry_distance(from - g.centre, d) {
            if t < to_ahead {
                (to_ahead, ahead) = (t, Some(k));
            }
        }
    }
    (to_ahead, ahead)
}

/// The on-the-fly transport through `m` with path memory `paths`, its wavelength-dependent
/// choices made through `choices` (`Mono`: `m`'s wavelength alone; the memory adds no kind of
/// choice to the classic tracer's). The ray also keeps its position in x and y and remembers the pore it is in (docs/geometry.md, "Near-surface path memory"): while it is still in the pore it reached its last grain
/// through (after a reflection, or leaving that grain on its lit side), it knows
/// - the segment it travelled through that pore (`channel`): a grain drawn on the fly whose
///   body would lie across it is discarded, since the ray passed there. Discarding candidates
///   drawn at the full rate 1/ℓ is thinning: the free path then has the conditional hazard
///   (1/ℓ)·P(a grain met there would not cross the segment), exact for a Boolean model of the
///   grains given the segment. For the first flight the segment is the entry channel from the
///   surface, which a ray turned back along it can leave by (shadow hiding);
/// - the grain at the segment's far end (`behind`, the grain the ray left to enter the pore):
///   a ray heading back meets it again where its surface is, not at a random distance.
///
/// With `Memory::Cut` the surface is the cut plane of `SurfaceLayer`: rays start and escape at
/// its top, and candidates are also thinned by the centre rule and the widening pore space of
/// the top layer. The ray also keeps the packed grains that bound its pore (`PoreWalls`) until
/// it goes through one into another pore: light scattered many times by fines inside a pore
/// meets the same walls again, where memoryless sampling would give each wall encounter a
/// fresh grain at a fresh distance (the failure of chord-length sampling for binary mixtures
/// whose chunks are optically thick; docs/geometry.md). With `Memory::Packed` a packed sphere met
/// after leaving a packed sphere is hit where the packing's pair correlation puts it relative to
/// the one left (`PairCorrelation`).
pub(crate) fn trace_with_memory(
    paths: &PathMemory,
    m: &Particulate,
    dir_in: Vec3,
    rng: &mut Rng,
    limits: &Limits,
    choices: &mut impl PathChoices,
) -> RayOutcome {
    let pore = &m.pore;
    // Candidate meetings below the plane, volume scatterers at their majorant rate (the cut
    // layer's own rates are of packed grains: `SurfaceLayer` uses the geometric ℓ).
    let ell = m.flight_mean_free_path_mm;
    let surface = paths.surface.as_ref();
    // Height of the boundary plane: 0, or the top of the cut-plane layer.
    let top = surface.map_or(0.0, |s| s.top_mm);
    let mut z = top;
    // Lateral position, start of the current flight, distance flown since, the remembered
    // segment and grains (`prev`: the grain the flight started from).
    let (mut x, mut y) = (0.0f64, 0.0f64);
    let mut flight_start = Vec3::new(0.0, 0.0, top);
    let mut flown = 0.0f64;
    let mut channel: Option<(Vec3, Vec3)> = None;
    let mut behind: Option<Grain> = None;
    let mut prev: Option<Grain> = None;
    let mut walls = PoreWalls::default();
    // The nearest remembered grain ahead (`BEHIND` or a wall's slot) and the distance to it.
    let mut ahead: Option<usize> = None;
    let mut to_ahead = f64::INFINITY;
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
        // With the cut layer, above the plane only packed grains that can reach below it
        // exist: flights there are drawn against the layer's majorant, and go on at the bulk
        // rate once below the plane.
        let layer = surface.filter(|_| z > 0.0);
        let mut s = match layer {
            Some(sf) => sf.flight(z, d.z, rng.exponential(), ell),
            None => ell * rng.exponential(),
        };
        // The remembered grain comes first if it is nearer than the candidate.
        let rehit = to_ahead - flown <= s;
        if rehit {
            s = to_ahead - flown;
        }
        if d.z > 0.0 && z + s * d.z >= top {
            if !water {
                return done(Fate::Escaped(d), events);
            }
            // Through water to the water surface, then water → air.
            let to_surface = (top - z) / d.z;
            // This tracer draws the survival number here also for clear water (as it did before
            // its choices went through `PathChoices`, whose `survives` draws only for α > 0).
            if pore.water_alpha_per_mm <= 0.0 {
                rng.uniform();
            }
            if !choices.survives(Absorber::Water, pore.water_alpha_per_mm, to_surface, rng) {
                return done(Fate::Absorbed, events);
            }
            // Reflected at the water surface: a new flight from there, no memory.
            x += to_surface * d.x;
            y += to_surface * d.y;
            flight_start = Vec3::new(x, y, top);
            (channel, prev, ahead, flown, to_ahead) = (None, None, None, 0.0, f64::INFINITY);
            walls.clear();
            match leave_water_surface(pore.water_n, d, rng, choices) {
                Some(out) => return done(Fate::Escaped(out), events),
                None => {
                    d.z = -d.z;
                    z = top;
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
        x += s * d.x;
        y += s * d.y;
        flown += s;
        let here = Vec3::new(x, y, z);
        let (grain, hit) = if rehit {
            let g = match ahead.expect("a finite distance to the remembered grain") {
                BEHIND => behind.expect("the grain behind"),
                k => walls.grains[k],
            };
            let rel = here - g.centre;
            (g, Hit { point: rel, normal: g.shape.normal_at(rel) })
        } else {
            // The cut plane: fines only below it; packed grains only with centres below it, in
            // a top layer of widening pore space. A candidate comes from a flight drawn against
            // the layer's majorant (still above the plane) or at the bulk rate (thinned where
            // the layer has fewer grains); the tests that need no hit point come first (drawing
            // a hit is the dear part).
            let (i, diameter) = match layer.filter(|_| z > 0.0) {
                Some(sf) => match sf.candidate_above_plane(&m.types, z, rng) {
                    Some(c) => c,
                    None => continue,
                },
                None => {
                    let i = m.pick_index(rng.uniform());
                    let discarded = surface.is_some_and(|sf| {
                        if sf.packed[i] {
                            z >= -sf.top_mm && rng.uniform() >= sf.keep(z)
                        } else {
                            z >= 0.0
                        }
                    });
                    if discarded {
                        continue;
                    }
                    if m.volume_scatterer(i).is_some() {
                        let (fate, dir) = meet_volume_scatterer(m, i, water, d, rng, choices);
                        if fate == VolumeFate::Null {
                            continue;
                        }
                        events += 1;
                        if events > limits.max_events {
                            return done(Fate::Capped, events);
                        }
                        if fate == VolumeFate::Absorb {
                            return done(Fate::Absorbed, events);
                        }
                        // Scattered in place, in the pore it is in: the segment just travelled
                        // is remembered as after a reflection; the particle itself is no pore
                        // wall, no neighbour and nothing to meet again.
                        channel = Some((flight_start, here));
                        behind = prev;
                        prev = None;
                        flight_start = here;
                        d = dir;
                        flown = 0.0;
                        (to_ahead, ahead) = nearest_remembered(&behind, &walls, flight_start, d);
                        continue;
                    }
                    (i, m.types[i].sizes.sample(rng))
                }
            };
            let cut_packed = surface.is_some_and(|sf| sf.packed[i]);
            let ptype = &m.types[i];
            let (a_over_d, _) = m.type_tables(i);
            let shape =
                Spheroid::with_semi_axis_ratio(diameter, a_over_d, ptype.aspect_ratio, Spheroid::random_axis(rng));
            // Centre height = z − (hit height) ≥ z − (highest point a ray along d can enter):
            // above the plane whatever the hit point if that bound is.
            if cut_packed && z >= shape.highest_entry(d) {
                continue;
            }
            // `Packed`: a packed sphere met after leaving one lies where the packing's pair
            // correlation puts it (the flight length keeps its law).
            let neighbour = paths
                .neighbours
                .as_ref()
                .zip(prev)
                .filter(|(_, a)| paths.is_packed_sphere(m, i) && paths.is_packed_sphere(m, a.type_index));
            let hit = match neighbour {
                Some((g, a)) => {
                    let n = g.sample_normal(here - a.centre, d, shape.a, shape.a + a.shape.a, rng);
                    Hit { point: n * shape.a, normal: n }
                }
                None => match shape.sample_hit(d, rng, 10_000) {
                    Some(hit) => hit,
                    None => return done(Fate::Capped, events),
                },
            };
            let centre = here - hit.point;
            if cut_packed && centre.z >= 0.0 {
                continue;
            }
            if let Some((a, b)) = channel {
                if shape.intersects_segment(a - centre, b - centre) {
                    continue;
                }
            }
            (Grain { shape, centre, type_index: i }, hit)
        };
        events += 1;
        if events > limits.max_events {
            return done(Fate::Capped, events);
        }
        let i = grain.type_index;
        // A packed grain of the cut-plane model (not a fine particle): it bounds the pore.
        let packed = surface.is_some_and(|sf| sf.packed[i]);
        let (_, stacks) = m.type_tables(i);
        choices.particle(i);
        match interact_with_stacks(
            &m.types[i].optics,
            stacks,
            pore,
            &grain.shape,
            hit,
            d,
            water,
            rng,
            limits.max_internal,
            choices,
        ) {
            Interaction::Reflected { dir } => {
                // Back into the pore it came from: remember the segment just travelled and the
                // grain at its far end.
                channel = Some((flight_start, here));
                behind = prev;
                flight_start = here;
                d = dir;
            }
            Interaction::Transmitted { dir, exit_point, water: w } => {
                // The particle's extent: the ray leaves from the far side (a fine particle in a
                // pore whose walls are remembered: unless that is inside a wall, then it leaves
                // where it hit, as in the explicit reference).
                let moved = Vec3::new(
                    x + exit_point.x - hit.point.x,
                    y + exit_point.y - hit.point.y,
                    (z + (exit_point.z - hit.point.z)).min(top),
                );
                if packed || !walls.contain(moved) {
                    (x, y, z) = (moved.x, moved.y, moved.z);
                }
                // Out on the lit side (the half facing where the ray came from) it is back in
                // the pore it came from; out on the far side, in a new one.
                if exit_point.dot(d) < 0.0 {
                    channel = Some((flight_start, here));
                    behind = prev;
                } else {
                    (channel, behind) = (None, None);
                    if packed {
                        walls.clear();
                    }
                }
                flight_start = Vec3::new(x, y, z);
                d = dir;
                water = w;
            }
            Interaction::Absorbed => return done(Fate::Absorbed, events),
            Interaction::Capped => return done(Fate::Capped, events),
        }
        if packed {
            walls.add(grain);
        }
        prev = Some(grain);
        flown = 0.0;
        (to_ahead, ahead) = nearest_remembered(&behind, &walls, flight_start, d);
    }
}

/// Test media and a tracer's signature, shared by the tests of the memory and explicit tracers.
#[cfg(test)]
pub(crate) mod testing {
    use crate::math::Vec3;
    use crate::medium::{ParticleType, Particulate};
    use crate::particle::{Coating, ParticleOptics, PoreOptics};
    use crate::rng::Rng;
    use crate::sizes::QuantileTable;
    use crate::transport::{Fate, Limits, Medium};

    /// An absorbing sand for every choice of the memory and explicit tracers: packed spheres and
    /// spheroids with a partial coating and clay fines, films, water-filled pores of absorbing
    /// water.
    pub(crate) fn absorbing_sand() -> Particulate {
        let coating = Coating { coverage: 0.7, ..Coating::uniform(1.9, 60.0, 5e-4) };
        let optics = ParticleOptics {
            core_n: 1.55,
            core_k: 1e-6,
            core_alpha_per_mm: 0.3,
            core_scattering_per_mm: 0.0,
            coating: Some(coating),
            wets: true,
        };
        let pore = PoreOptics {
            water_n: 1.333,
            water_alpha_per_mm: 0.4,
            film_thickness_mm: 2e-3,
            film_coverage: 0.6,
            water_filled_probability: 0.4,
        };
        let types = grains_and_clay(optics, [(0.45, 1.0), (0.35, 1.3)]);
        Particulate::new(types, 0.1, pore, f64::INFINITY).unwrap()
    }

    /// Two types of grain (each its encounter probability and aspect ratio, sizes 0.15–0.35 mm)
    /// and clay fines (0.002 mm spheres, probability 0.2), all of `optics`.
    pub(crate) fn grains_and_clay(optics: ParticleOptics, grains: [(f64, f64); 2]) -> Vec<ParticleType> {
        let sizes = QuantileTable::new((0..17).map(|j| 0.15 + 0.2 * j as f64 / 16.0).collect()).unwrap();
        let t = |probability, sizes: &QuantileTable, aspect_ratio| ParticleType {
            probability,
            sizes: sizes.clone(),
            aspect_ratio,
            optics,
        };
        let [(p0, e0), (p1, e1)] = grains;
        vec![t(p0, &sizes, e0), t(p1, &sizes, e1), t(0.2, &QuantileTable::constant(0.002), 1.0)]
    }

    /// [escaped, absorbed, transmitted, capped, events, XOR of each ray's next random number after
    /// it ended] of rays 0..n: equal only if every ray made the same draws and decisions.
    pub(crate) fn signature(m: &impl Medium, n: u64) -> [u64; 6] {
        let d = Vec3::new(0.3, 0.4, -(0.75f64).sqrt());
        let mut s = [0u64; 6];
        for i in 0..n {
            let mut rng = Rng::for_ray(7, 0, i);
            let out = m.trace(d, &mut rng, &Limits::default());
            let k = match out.fate {
                Fate::Escaped(_) => 0,
                Fate::Absorbed => 1,
                Fate::Transmitted => 2,
                Fate::Capped => 3,
            };
            s[k] += 1;
            s[4] += out.events;
            s[5] ^= rng.next_u64();
        }
        s
    }
}

#[cfg(test)]
mod tests {
    use super::testing::{absorbing_sand, grains_and_clay, signature};
    use super::*;
    use crate::particle::{ParticleOptics, PoreOptics};
    use crate::volume_scatterer::testing::{henyey_greenstein, scatterer};

    /// Clear grains (no absorption anywhere): packed spheres and spheroids and clay fines, in
    /// water-filled pores half of the time, in a slab `depth_mm` thick.
    fn clear_sand(depth_mm: f64) -> Particulate {
        let pore = PoreOptics {
            water_n: 1.333,
            water_alpha_per_mm: 0.0,
            film_thickness_mm: 0.01,
            film_coverage: 1.0,
            water_filled_probability: 0.5,
        };
        let types = grains_and_clay(ParticleOptics::clear(1.544), [(0.4, 1.0), (0.4, 1.4)]);
        Particulate::new(types, 0.08, pore, depth_mm).unwrap()
    }

    #[test]
    fn the_memory_tracers_make_the_decisions_they_made_before_spectral_sharing() {
        // Recorded from the memory tracer before it made its choices through `PathChoices`
        // (commit dcf805a): one wavelength (`Mono`) traces the same paths from the same random
        // numbers, through absorbing and through clear water.
        let recorded = [
            (
                Memory::Channel,
                [600, 2400, 0, 0, 18290, 2002021303810730696],
                [587, 0, 413, 0, 22343, 13067235179718805289],
            ),
            (Memory::Cut, [546, 2454, 0, 0, 17241, 7575568002502509659], [547, 0, 453, 0, 23688, 14143824943896848622]),
            (Memory::Packed, [551, 2449, 0, 0, 17114, 70481133893985764], [548, 0, 452, 0, 25018, 3451610481167410303]),
        ];
        for (memory, absorbing, clear) in recorded {
            assert_eq!(signature(&WithMemory::new(absorbing_sand(), memory), 3000), absorbing, "{memory:?}");
            assert_eq!(signature(&WithMemory::new(clear_sand(2.0), memory), 1000), clear, "{memory:?}");
        }
    }

    #[test]
    fn no_memory_traces_as_the_particulate_does() {
        let m = clear_sand(f64::INFINITY);
        let wm = WithMemory::new(m.clone(), Memory::None);
        let d = Vec3::new(0.5, 0.0, -(0.75f64).sqrt());
        for i in 0..500 {
            let (mut r1, mut r2) = (Rng::for_ray(1, 0, i), Rng::for_ray(1, 0, i));
            let (a, b) = (m.trace(d, &mut r1, &Limits::default()), wm.trace(d, &mut r2, &Limits::default()));
            assert_eq!((a.fate, a.events), (b.fate, b.events));
            assert_eq!(r1.next_u64(), r2.next_u64());
        }
    }

    #[test]
    fn every_memory_keeps_energy_in_a_clear_slab() {
        // Memory changes where grains are met, not what they do: without absorption every ray
        // leaves by the top or the bottom, also through the water surface and the cut layer.
        for memory in [Memory::Channel, Memory::Cut, Memory::Packed] {
            let wm = WithMemory::new(clear_sand(1.0), memory);
            let paths = wm.paths().unwrap();
            assert_eq!(paths.surface.is_some(), memory != Memory::Channel);
            assert_eq!(paths.neighbours.is_some(), memory == Memory::Packed);
            let d = Vec3::new(0.3, 0.4, -(0.75f64).sqrt());
            let (mut up, mut down) = (0, 0);
            for i in 0..1500 {
                match wm.trace(d, &mut Rng::for_ray(2, 0, i), &Limits::default()).fate {
                    Fate::Escaped(out) => {
                        assert!(out.z > 0.0);
                        up += 1;
                    }
                    Fate::Transmitted => down += 1,
                    other => panic!("{memory:?}: ray {i} {other:?}"),
                }
            }
            assert!(up > 0 && down > 0 && up + down == 1500);
        }
    }

    #[test]
    fn the_packed_memory_keeps_energy_with_lossless_volume_scatterers() {
        // The clay fines of `clear_sand` as non-absorbing, forward-scattering volume scatterers
        // (half of the meetings null): every ray leaves by the top or the bottom of the slab,
        // and some meet a scatterer (the packed memory's events exceed those without them).
        let fines = scatterer(2.0, henyey_greenstein(0.5, 1.0, 0.7));
        let volume = clear_sand(1.0).with_volume_scatterers(vec![None, None, Some(fines)]).unwrap();
        let (with, without) =
            (WithMemory::new(volume, Memory::Packed), WithMemory::new(clear_sand(1.0), Memory::Packed));
        let d = Vec3::new(0.3, 0.4, -(0.75f64).sqrt());
        let (mut left, mut events, mut events_without) = (0, 0, 0);
        for i in 0..1500 {
            let out = with.trace(d, &mut Rng::for_ray(2, 0, i), &Limits::default());
            events += out.events;
            events_without += without.trace(d, &mut Rng::for_ray(2, 0, i), &Limits::default()).events;
            match out.fate {
                Fate::Escaped(_) | Fate::Transmitted => left += 1,
                other => panic!("ray {i} {other:?}"),
            }
        }
        assert_eq!(left, 1500);
        assert!(events != events_without, "{events} {events_without}");
    }
}

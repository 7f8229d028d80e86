//! The explicit-geometry reference: rays traced through a stored random packing (`packing`)
//! with the same per-particle interaction as the on-the-fly engine
//! (`particle::interact_with_stacks`, with the medium's own layer-stack tables), so that any
//! difference between the two comes from the geometry alone (docs/geometry.md).
//!
//! Scene. The packing is periodic in x, y and z with periods (L, L, H). The sample is every
//! periodic image whose centre lies below the cut plane z = H ("a cut through a plane of
//! particle centres": the grains whose centres are above it are removed, those below keep
//! their full shape and stick out of the plane). Downwards the packing repeats with period H,
//! so the sample is semi-infinite; `bottom_mm` (finite samples, or to measure how deep light
//! goes) turns rays that get deeper than that below the cut into `Transmitted`. Rays enter at a
//! uniformly random (x, y) on the plane z = H + c_max above the highest grain and escape when
//! they cross it upwards.
//!
//! Settled surface (`deposition`): grains deposited on the cut are part of the sample where
//! they lie, periodic in x and y only: they exist in the top period block and not in its
//! images below, and rays start and escape above the highest of them.
//!
//! Acceleration: a uniform grid over one period with cells about one mean grain across; each
//! grain is listed in every cell its bounding cube touches, with the period block it was
//! listed from, and rays walk the unbounded periodic grid cell by cell (Amanatides & Woo 1987).
//!
//! Fines (types not packed) stay on the fly inside the pores: free paths between them are
//! exponential with mean ℓ/P_fines (ℓ the sample's mean free path, P_fines their total
//! encounter probability), the same rate per unit pore length as in the on-the-fly medium;
//! a fine particle is drawn, hit and traced exactly as there, and a ray through it is moved by
//! its extent (unless that would put it inside a packed grain, then it leaves where it hit).
//! Fines fill the pores below the cut plane only, also under a settled layer (whose pores have
//! none).
//!
//! Pore water follows the on-the-fly rules (each pore entered is water-filled with the pore's
//! probability, a water-filled surface pore presents a flat water surface).

use std::sync::Arc;

use crate::error::SandlightError;
use crate::math::Vec3;
use crate::medium::Particulate;
use crate::packing::{PackedParticle, Packing};
use crate::particle::{interact_with_stacks, Absorber, Interaction, Mono, PathChoices};
use crate::rng::Rng;
use crate::spheroid::{Hit, Spheroid};
use crate::transport::{enter_water_surface, leave_water_surface, Fate, Limits, Medium, RayOutcome, UP};

/// Grid cells a ray may cross in one free flight before it is capped (a ray skimming a
/// channel of the periodic packing forever).
const MAX_CELLS_PER_FLIGHT: u64 = 10_000_000;

#[derive(Clone, Copy, Debug)]
struct Entry {
    particle: u32,
    /// Period block (−1, 0, 1 per axis) of the cell the grain was listed from.
    block: [i8; 3],
}

/// The packing with its grain shapes and grid: wavelength independent, shared by the media of
/// all wavelengths.
#[derive(Debug)]
pub struct Scene {
    pub packing: Packing,
    /// Grains settled on the cut surface (empty for the cut): periodic in x and y, not in z.
    pub deposit: Vec<PackedParticle>,
    /// Shapes of the packed grains, then of the deposited ones (index `packing.particles.len()`
    /// and up).
    shapes: Vec<Spheroid>,
    n: [usize; 3],
    h: Vec3,
    start: Vec<u32>,
    entries: Vec<Entry>,
    /// Height of the plane where rays start and escape (mm).
    pub top_mm: f64,
}

impl Scene {
    /// The cut surface (module docs).
    pub fn new(packing: Packing) -> Scene {
        Scene::with_deposit(packing, Vec::new())
    }

    /// The cut surface with the grains `deposit` settled on it (`deposition::deposit`).
    pub fn with_deposit(packing: Packing, deposit: Vec<PackedParticle>) -> Scene {
        let per = packing.period;
        let mut shapes: Vec<Spheroid> = (0..packing.particles.len()).map(|k| packing.shape(k)).collect();
        shapes
            .extend(deposit.iter().map(|g| Spheroid::new(g.diameter_mm, packing.aspect_ratios[g.type_index], g.axis)));
        let mean_d = packing.particles.iter().map(|p| p.diameter_mm).sum::<f64>() / packing.particles.len() as f64;
        let n = [per.x, per.y, per.z].map(|l| ((l / mean_d).floor() as usize).max(1));
        let h = Vec3::new(per.x / n[0] as f64, per.y / n[1] as f64, per.z / n[2] as f64);
        let mut lists: Vec<Vec<Entry>> = vec![Vec::new(); n[0] * n[1] * n[2]];
        for (k, (p, s)) in packing.particles.iter().chain(&deposit).zip(&shapes).enumerate() {
            let c = [p.centre.x, p.centre.y, p.centre.z];
            let hh = [h.x, h.y, h.z];
            let range = |ax: usize| ((c[ax] - s.c) / hh[ax]).floor() as i64..=((c[ax] + s.c) / hh[ax]).floor() as i64;
            for iz in range(2) {
                for iy in range(1) {
                    for ix in range(0) {
                        let i = [ix, iy, iz];
                        let w: [usize; 3] = std::array::from_fn(|a| i[a].rem_euclid(n[a] as i64) as usize);
                        let block: [i8; 3] = std::array::from_fn(|a| i[a].div_euclid(n[a] as i64) as i8);
                        lists[(w[2] * n[1] + w[1]) * n[0] + w[0]].push(Entry { particle: k as u32, block });
                    }
                }
            }
        }
        let mut start = Vec::with_capacity(lists.len() + 1);
        let mut entries = Vec::new();
        start.push(0);
        for l in lists {
            entries.extend(l);
            start.push(entries.len() as u32);
        }
        let deposit_top = deposit
            .iter()
            .zip(&shapes[packing.particles.len()..])
            .map(|(g, s)| g.centre.z + s.c)
            .fold(f64::NEG_INFINITY, f64::max);
        let top_mm = (per.z + packing.max_extent_mm()).max(deposit_top);
        Scene { packing, deposit, shapes, n, h, start, entries, top_mm }
    }

    /// Grain `k`: packed for k below the number of packed grains, deposited above.
    #[inline]
    fn grain(&self, k: usize) -> &PackedParticle {
        let n_packed = self.packing.particles.len();
        if k < n_packed {
            &self.packing.particles[k]
        } else {
            &self.deposit[k - n_packed]
        }
    }

    /// The images of the grains listed in grid cell `cell` (unbounded indices) seen from that
    /// cell: (grain, centre of the image, whether it was deposited). A deposited grain has no
    /// images in other period blocks in z.
    #[inline]
    fn images(&self, cell: [i64; 3]) -> impl Iterator<Item = (usize, Vec3, bool)> + '_ {
        let per = self.packing.period;
        let pa = [per.x, per.y, per.z];
        let n_packed = self.packing.particles.len();
        let w: [usize; 3] = std::array::from_fn(|a| cell[a].rem_euclid(self.n[a] as i64) as usize);
        let b: [i64; 3] = std::array::from_fn(|a| cell[a].div_euclid(self.n[a] as i64));
        let ci = (w[2] * self.n[1] + w[1]) * self.n[0] + w[0];
        self.entries[self.start[ci] as usize..self.start[ci + 1] as usize].iter().filter_map(move |e| {
            let k = e.particle as usize;
            let deposited = k >= n_packed;
            if deposited && b[2] != e.block[2] as i64 {
                return None;
            }
            let p0 = self.grain(k).centre;
            let shift: [f64; 3] = std::array::from_fn(|a| (b[a] - e.block[a] as i64) as f64 * pa[a]);
            Some((k, Vec3::new(p0.x + shift[0], p0.y + shift[1], p0.z + shift[2]), deposited))
        })
    }

    /// The nearest grain the ray from `o` along unit `d` enters within distance `max_t`:
    /// (distance, particle, centre of the image hit). Packed grains count with centres in
    /// [`bottom_z`, `top_z`), deposited ones (if `with_deposit`) above `bottom_z`. Err(()) if
    /// the ray crossed too many cells.
    fn nearest(
        &self,
        o: Vec3,
        d: Vec3,
        max_t: f64,
        bottom_z: f64,
        top_z: f64,
        with_deposit: bool,
    ) -> Result<Option<(f64, usize, Vec3)>, ()> {
        let oa = [o.x, o.y, o.z];
        let da = [d.x, d.y, d.z];
        let ha = [self.h.x, self.h.y, self.h.z];
        let mut cell: [i64; 3] = std::array::from_fn(|a| (oa[a] / ha[a]).floor() as i64);
        let step: [i64; 3] = std::array::from_fn(|a| if da[a] > 0.0 { 1 } else { -1 });
        let mut t_max: [f64; 3] = std::array::from_fn(|a| {
            if da[a] == 0.0 {
                f64::INFINITY
            } else {
                let edge = (cell[a] + (step[a] > 0) as i64) as f64 * ha[a];
                (edge - oa[a]) / da[a]
            }
        });
        let t_delta: [f64; 3] = std::array::from_fn(|a| if da[a] == 0.0 { f64::INFINITY } else { ha[a] / da[a].abs() });
        let mut t_enter = 0.0;
        for _ in 0..MAX_CELLS_PER_FLIGHT {
            if t_enter > max_t {
                return Ok(None);
            }
            let t_exit = t_max[0].min(t_max[1]).min(t_max[2]);
            let mut best: Option<(f64, usize, Vec3)> = None;
            for (k, c, deposited) in self.images(cell) {
                // The cut: only packed grains with centres below the top; a deposit on it.
                if (if deposited { !with_deposit } else { c.z >= top_z }) || c.z < bottom_z {
                    continue;
                }
                if let Some(t) = self.shapes[k].entry_distance(o - c, d) {
                    if best.is_none_or(|(tb, _, _)| t < tb) {
                        best = Some((t, k, c));
                    }
                }
            }
            if let Some(hit) = best {
                if hit.0 <= t_exit && hit.0 <= max_t {
                    return Ok(Some(hit));
                }
            }
            let a = if t_max[0] <= t_max[1] && t_max[0] <= t_max[2] {
                0
            } else if t_max[1] <= t_max[2] {
                1
            } else {
                2
            };
            cell[a] += step[a];
            t_enter = t_max[a];
            t_max[a] += t_delta[a];
        }
        Err(())
    }

    /// The grid cell (unbounded indices) holding `x`.
    #[inline]
    fn cell_of(&self, x: Vec3) -> [i64; 3] {
        let xa = [x.x, x.y, x.z];
        let ha = [self.h.x, self.h.y, self.h.z];
        std::array::from_fn(|a| (xa[a] / ha[a]).floor() as i64)
    }

    /// Whether `x` lies inside a packed grain (any image, cut and bottom ignored) or a
    /// deposited one.
    fn inside_packed(&self, x: Vec3) -> bool {
        self.images(self.cell_of(x)).any(|(k, c, _)| self.shapes[k].contains(x - c))
    }

    /// How many grains of the sample (packed ones below the cut plane, deposited ones) hold `x`.
    fn grains_holding(&self, x: Vec3) -> usize {
        let cut = self.packing.period.z;
        self.images(self.cell_of(x))
            .filter(|&(k, c, deposited)| (deposited || c.z < cut) && self.shapes[k].contains(x - c))
            .count()
    }

    /// Solid profile by point sampling: for each height (mm), the fractions of `n_points`
    /// uniformly random points of that plane inside no grain of the sample (its porosity there)
    /// and inside two or more (true overlap of spheroids).
    pub fn porosity_profile(&self, heights: &[f64], n_points: usize, seed: u64) -> Vec<(f64, f64)> {
        let per = self.packing.period;
        heights
            .iter()
            .enumerate()
            .map(|(j, &z)| {
                let mut rng = Rng::for_ray(seed, 0x9ac5, j as u64);
                let (mut empty, mut multiple) = (0usize, 0usize);
                for _ in 0..n_points {
                    let held = self.grains_holding(Vec3::new(rng.uniform() * per.x, rng.uniform() * per.y, z));
                    empty += (held == 0) as usize;
                    multiple += (held >= 2) as usize;
                }
                (empty as f64 / n_points as f64, multiple as f64 / n_points as f64)
            })
            .collect()
    }

    /// Heights (mm) of the sample's surface along `n_points` vertical lines at uniformly random
    /// (x, y): where a line from above first enters a grain. NaN where it enters none within
    /// the cell limit (a vertical channel through the periodic packing).
    pub fn surface_heights(&self, n_points: usize, seed: u64) -> Vec<f64> {
        let per = self.packing.period;
        let mut rng = Rng::for_ray(seed, 0x9ac6, 0);
        (0..n_points)
            .map(|_| {
                let o = Vec3::new(rng.uniform() * per.x, rng.uniform() * per.y, self.top_mm);
                match self.nearest(o, -UP, f64::INFINITY, f64::NEG_INFINITY, per.z, true) {
                    Ok(Some((t, _, _))) => self.top_mm - t,
                    _ => f64::NAN,
                }
            })
            .collect()
    }

    /// Pore chords of the packed grains (mm): along `n_lines` random lines (uniform start,
    /// isotropic direction) through the unbounded periodic packing, the lengths between leaving
    /// one grain and entering the next, `per_line` of them per line (the first, partial, pore
    /// segment of each line is dropped). For isotropic uniform lines their mean is 4φ/S_v.
    pub fn pore_chords(&self, n_lines: usize, per_line: usize, seed: u64) -> Vec<f64> {
        let per = self.packing.period;
        let mut out = Vec::with_capacity(n_lines * per_line);
        for line in 0..n_lines {
            let mut rng = Rng::for_ray(seed, 0x9ac3, line as u64);
            let mut o = Vec3::new(rng.uniform() * per.x, rng.uniform() * per.y, rng.uniform() * per.z);
            let d = Spheroid::random_axis(&mut rng);
            let mut first = true;
            let mut got = 0;
            while got < per_line {
                let Ok(Some((t, k, c))) = self.nearest(o, d, f64::INFINITY, f64::NEG_INFINITY, f64::INFINITY, false)
                else {
                    break;
                };
                if !first {
                    out.push(t);
                    got += 1;
                }
                first = false;
                let (len, _) = self.shapes[k].chord_from_surface(o + d * t - c, d);
                o = o + d * (t + len);
                o = Vec3::new(o.x.rem_euclid(per.x), o.y.rem_euclid(per.y), o.z.rem_euclid(per.z));
            }
        }
        out
    }

    /// Bytes held by the scene (particles, shapes, grid).
    pub fn memory_bytes(&self) -> usize {
        self.shapes.len() * (std::mem::size_of::<PackedParticle>() + std::mem::size_of::<Spheroid>())
            + self.start.len() * 4
            + self.entries.len() * std::mem::size_of::<Entry>()
    }
}

/// A sample at one wavelength traced through an explicit packing.
#[derive(Clone, Debug)]
pub struct Explicit {
    pub medium: Particulate,
    pub geometry: ExplicitGeometry,
}

/// What an explicit sample is apart from its optics: the scene, the bottom and the fines'
/// free path and draw, the same for the media of every wavelength (a spectral group traces
/// them with its hero's medium, `hero::HeroGroup::explicit`).
#[derive(Clone, Debug)]
pub struct ExplicitGeometry {
    pub scene: Arc<Scene>,
    /// Depth below the cut plane beyond which a ray counts as transmitted (mm); infinite for
    /// a semi-infinite sample.
    pub bottom_mm: f64,
    /// Mean free path between fines (mm), infinite without fines.
    fines_free_path_mm: f64,
    /// Cumulative encounter probabilities of the fine types, and their indices.
    fines: Vec<(f64, usize)>,
}

impl Explicit {
    /// `medium` must have the populations the packing was generated from (same types and
    /// aspect ratios; its optics may be those of another wavelength).
    pub fn new(medium: Particulate, scene: Arc<Scene>, bottom_mm: f64) -> Result<Explicit, SandlightError> {
        let pk = &scene.packing;
        if medium.types.len() != pk.aspect_ratios.len()
            || medium.types.iter().zip(&pk.aspect_ratios).any(|(t, &e)| t.aspect_ratio != e)
        {
            return Err(SandlightError::parameter(
                "packing",
                format!("{} particle types", pk.aspect_ratios.len()),
                "must be generated from a medium with the same particle types and aspect ratios",
            ));
        }
        if medium.has_volume_scatterers() {
            return Err(SandlightError::parameter(
                "volume_scatterers",
                "a medium with volume scatterers",
                "none: Mie volume scatterers are traced only by the on-the-fly tracers",
            ));
        }
        if bottom_mm.is_nan() || bottom_mm <= 0.0 {
            return Err(SandlightError::parameter(
                "bottom_mm",
                bottom_mm,
                "must be > 0 (inf for a semi-infinite sample)",
            ));
        }
        let total: f64 = medium.types.iter().map(|t| t.probability).sum();
        let mut acc = 0.0;
        let mut fines = Vec::new();
        for (i, t) in medium.types.iter().enumerate() {
            if !pk.populations.packed[i] {
                acc += t.probability / total;
                fines.push((acc, i));
            }
        }
        let fines_free_path_mm = if acc > 0.0 { medium.mean_free_path_mm / acc } else { f64::INFINITY };
        for f in fines.iter_mut() {
            f.0 /= acc;
        }
        Ok(Explicit { medium, geometry: ExplicitGeometry { scene, bottom_mm, fines_free_path_mm, fines } })
    }
}

impl ExplicitGeometry {
    /// The interaction with packed grain `k` at `hit` (relative to its centre): the on-the-fly
    /// engine's function with `medium`'s tables for the grain's type, its wavelength-dependent
    /// choices made through `choices`.
    #[inline]
    #[allow(clippy::too_many_arguments)] // `interact_with_stacks`' ray and generator, the grain by index
    pub fn interact_packed(
        &self,
        medium: &Particulate,
        k: usize,
        hit: Hit,
        d: Vec3,
        water: bool,
        rng: &mut Rng,
        max_internal: u32,
        choices: &mut impl PathChoices,
    ) -> Interaction {
        let i = self.scene.grain(k).type_index;
        choices.particle(i);
        let (_, stacks) = medium.type_tables(i);
        interact_with_stacks(
            &medium.types[i].optics,
            stacks,
            &medium.pore,
            &self.scene.shapes[k],
            hit,
            d,
            water,
            rng,
            max_internal,
            choices,
        )
    }

    /// Traces a ray arriving along `dir_in` through `medium` (one wavelength's optics, or the
    /// hero's) at a uniformly random point of the plane above the sample, its
    /// wavelength-dependent choices made through `choices` (`Mono` for one wavelength).
    pub fn trace(
        &self,
        medium: &Particulate,
        dir_in: Vec3,
        rng: &mut Rng,
        limits: &Limits,
        choices: &mut impl PathChoices,
    ) -> RayOutcome {
        let per = self.scene.packing.period;
        let mut o = Vec3::new(rng.uniform() * per.x, rng.uniform() * per.y, self.scene.top_mm);
        let pore = &medium.pore;
        let mut d = dir_in;
        let mut water = pore.draw_water(rng);
        if water {
            match enter_water_surface(pore.water_n, d, rng, choices) {
                Some(dir) => d = dir,
                None => return RayOutcome { fate: Fate::Escaped(d.reflect(UP)), events: 0 },
            }
        }
        let scene = &*self.scene;
        let bottom_z = per.z - self.bottom_mm;
        let mut events = 0u64;
        let done = |fate, events| RayOutcome { fate, events };
        loop {
            // Translational symmetry: keep x, y in the first period.
            o.x = o.x.rem_euclid(per.x);
            o.y = o.y.rem_euclid(per.y);
            let s_fines = self.fines_free_path_mm * rng.exponential();
            let t_top = if d.z > 0.0 { (scene.top_mm - o.z) / d.z } else { f64::INFINITY };
            let t_bottom = if d.z < 0.0 && self.bottom_mm.is_finite() {
                (bottom_z - scene.packing.max_extent_mm() - o.z) / d.z
            } else {
                f64::INFINITY
            };
            let reach = s_fines.min(t_top).min(t_bottom);
            let hit = match scene.nearest(
                o,
                d,
                reach,
                if self.bottom_mm.is_finite() { bottom_z } else { f64::NEG_INFINITY },
                per.z,
                true,
            ) {
                Ok(h) => h,
                Err(()) => return done(Fate::Capped, events),
            };
            let flight = hit.map_or(reach, |h| h.0);
            if water && !choices.survives(Absorber::Water, pore.water_alpha_per_mm, flight.min(t_top), rng) {
                return done(Fate::Absorbed, events);
            }
            if hit.is_none() && t_top <= s_fines && t_top <= t_bottom {
                if !water {
                    return done(Fate::Escaped(d), events);
                }
                // A water-filled surface pore: water → air at a flat surface (as on the fly).
                match leave_water_surface(pore.water_n, d, rng, choices) {
                    Some(out) => return done(Fate::Escaped(out), events),
                    None => {
                        o = o + d * t_top;
                        d.z = -d.z;
                        continue;
                    }
                }
            }
            if hit.is_none() && t_bottom <= s_fines {
                return done(Fate::Transmitted, events);
            }
            events += 1;
            if events > limits.max_events {
                return done(Fate::Capped, events);
            }
            match hit {
                Some((t, k, c)) => {
                    let x = o + d * t;
                    let rel = x - c;
                    let h = Hit { point: rel, normal: scene.shapes[k].normal_at(rel) };
                    match self.interact_packed(medium, k, h, d, water, rng, limits.max_internal, choices) {
                        Interaction::Reflected { dir } => {
                            o = x;
                            d = dir;
                        }
                        Interaction::Transmitted { dir, exit_point, water: w } => {
                            o = c + exit_point;
                            d = dir;
                            water = w;
                        }
                        Interaction::Absorbed => return done(Fate::Absorbed, events),
                        Interaction::Capped => return done(Fate::Capped, events),
                    }
                }
                None => {
                    // A fine particle in the pore, drawn as the on-the-fly engine draws one.
                    // Fines fill the pores below the cut plane only (thinning: no event above).
                    let x = o + d * s_fines;
                    if x.z >= per.z {
                        events -= 1;
                        o = x;
                        continue;
                    }
                    let u = rng.uniform();
                    let i = self.fines.iter().find(|f| u < f.0).map_or(self.fines[self.fines.len() - 1].1, |f| f.1);
                    let ptype = &medium.types[i];
                    let (a_over_d, stacks) = medium.type_tables(i);
                    let diameter = ptype.sizes.sample(rng);
                    let shape = Spheroid::with_semi_axis_ratio(
                        diameter,
                        a_over_d,
                        ptype.aspect_ratio,
                        Spheroid::random_axis(rng),
                    );
                    let Some(h) = shape.sample_hit(d, rng, 10_000) else {
                        return done(Fate::Capped, events);
                    };
                    o = x;
                    choices.particle(i);
                    match interact_with_stacks(
                        &ptype.optics,
                        stacks,
                        pore,
                        &shape,
                        h,
                        d,
                        water,
                        rng,
                        limits.max_internal,
                        choices,
                    ) {
                        Interaction::Reflected { dir } => d = dir,
                        Interaction::Transmitted { dir, exit_point, water: w } => {
                            let moved = x + (exit_point - h.point);
                            if !scene.inside_packed(moved) {
                                o = moved;
                            }
                            d = dir;
                            water = w;
                        }
                        Interaction::Absorbed => return done(Fate::Absorbed, events),
                        Interaction::Capped => return done(Fate::Capped, events),
                    }
                }
            }
        }
    }
}

impl Medium for Explicit {
    fn trace(&self, dir_in: Vec3, rng: &mut Rng, limits: &Limits) -> RayOutcome {
        self.geometry.trace(&self.medium, dir_in, rng, limits, &mut Mono)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::medium::ParticleType;
    use crate::memory::testing::{absorbing_sand, signature};
    use crate::packing::{PackedParticle, PackingParams};
    use crate::particle::{ParticleOptics, PoreOptics};
    use crate::populations::Populations;
    use crate::sizes::QuantileTable;

    fn grains(alpha_per_mm: f64) -> Particulate {
        let optics = ParticleOptics { core_alpha_per_mm: alpha_per_mm, ..ParticleOptics::clear(1.544) };
        let t = ParticleType { probability: 1.0, sizes: QuantileTable::constant(0.25), aspect_ratio: 1.0, optics };
        // φ = 0.4: ℓ = (2/3) d φ/(1 − φ).
        Particulate::new(vec![t], 2.0 / 3.0 * 0.25 * 0.4 / 0.6, PoreOptics::DRY, f64::INFINITY).unwrap()
    }

    #[test]
    fn single_grain_scene_shares_the_interaction() {
        // One sphere in a wide box. For hits drawn as the on-the-fly engine draws them, the
        // grid finds the same surface point and the explicit interaction gives the same
        // outcome, bit for bit, from the same random numbers.
        let m = grains(5.0);
        let pops = Populations::of(&m, 0.05);
        let per = Vec3::new(5.0, 5.0, 5.0);
        let pk = Packing {
            particles: vec![PackedParticle {
                centre: Vec3::new(2.5, 2.5, 2.5),
                axis: UP,
                diameter_mm: 0.25,
                type_index: 0,
            }],
            aspect_ratios: vec![1.0],
            period: per,
            populations: pops,
            packing_fraction: 0.0,
            max_overlap: 0.0,
            sweeps: 0,
        };
        let ex = Explicit::new(m.clone(), Arc::new(Scene::new(pk)), f64::INFINITY).unwrap();
        let mut rng = Rng::for_ray(21, 0, 0);
        let shape = Spheroid::new(0.25, 1.0, UP);
        let mut outcomes = [0usize; 3];
        for _ in 0..20_000 {
            let d = Spheroid::random_axis(&mut rng);
            let h = shape.sample_hit(d, &mut rng, 100).unwrap();
            let centre = Vec3::new(2.5, 2.5, 2.5);
            let o = centre + h.point - d * 0.4;
            let (t, k, c) = ex
                .geometry
                .scene
                .nearest(o, d, 1.0, f64::NEG_INFINITY, f64::INFINITY, false)
                .unwrap()
                .expect("the ray aims at the grain");
            let rel = o + d * t - c;
            assert!((rel - h.point).norm2() < 1e-20, "hit {rel:?} vs {:?}", h.point);
            let (mut r1, mut r2) = (rng.clone(), rng.clone());
            let hit = Hit { point: rel, normal: shape.normal_at(rel) };
            let explicit = ex.geometry.interact_packed(&ex.medium, k, hit, d, false, &mut r1, 10_000, &mut Mono);
            let (_, stacks) = m.type_tables(0);
            let on_the_fly = interact_with_stacks(
                &m.types[0].optics,
                stacks,
                &m.pore,
                &shape,
                h,
                d,
                false,
                &mut r2,
                10_000,
                &mut Mono,
            );
            match (explicit, on_the_fly) {
                (Interaction::Reflected { dir: a }, Interaction::Reflected { dir: b }) => {
                    assert!((a - b).norm2() < 1e-20);
                    outcomes[0] += 1
                }
                (
                    Interaction::Transmitted { dir: a, exit_point: e, .. },
                    Interaction::Transmitted { dir: b, exit_point: f, .. },
                ) => {
                    assert!((a - b).norm2() < 1e-20 && (e - f).norm2() < 1e-20);
                    outcomes[1] += 1
                }
                (Interaction::Absorbed, Interaction::Absorbed) => outcomes[2] += 1,
                (a, b) => panic!("explicit {a:?} vs on the fly {b:?}"),
            }
            rng = r1;
        }
        assert!(outcomes.iter().all(|&n| n > 100), "{outcomes:?}");
    }

    #[test]
    fn one_wavelength_makes_the_decisions_it_made_before_spectral_sharing() {
        // Recorded from the explicit tracer before it made its choices through any
        // `PathChoices` but `Mono` (commit 4696da1): the same paths from the same random
        // numbers, through coated grains, fines, films and water-filled pores of absorbing
        // water, semi-infinite and as a slab 1 mm deep.
        let m = absorbing_sand();
        let params = PackingParams { lateral_mm: 1.5, depth_mm: 1.5, seed: 3, ..Default::default() };
        let scene = Arc::new(Scene::new(Packing::generate(&m, &params).unwrap()));
        let semi = Explicit::new(m.clone(), scene.clone(), f64::INFINITY).unwrap();
        assert_eq!(signature(&semi, 2000), [364, 1636, 0, 0, 11628, 1286168667432159318]);
        let slab = Explicit::new(m, scene, 1.0).unwrap();
        assert_eq!(signature(&slab, 2000), [349, 1308, 343, 0, 9318, 13791052080783838233]);
    }

    #[test]
    fn deposited_grains_lie_in_the_top_block_only() {
        let params = PackingParams { lateral_mm: 1.5, depth_mm: 1.5, seed: 2, ..Default::default() };
        let pk = Packing::generate(&grains(0.0), &params).unwrap();
        let deposit = crate::deposition::deposit(&pk, 0.5, 2).unwrap();
        let lowest = deposit.iter().map(|g| g.centre.z - 0.5 * g.diameter_mm).fold(f64::INFINITY, f64::min);
        let highest = deposit.iter().map(|g| g.centre.z + 0.5 * g.diameter_mm).fold(f64::NEG_INFINITY, f64::max);
        let cut = Scene::new(pk.clone());
        let settled = Scene::with_deposit(pk, deposit.clone());
        let h = cut.packing.period.z;
        assert!(settled.top_mm >= highest && cut.top_mm == h + cut.packing.max_extent_mm());
        // Below the deposit (and where its images one period down would be) the two samples
        // are the same grains.
        let below: Vec<f64> = (0..12).map(|i| lowest - 0.05 - 0.2 * i as f64).collect();
        assert_eq!(cut.porosity_profile(&below, 2000, 3), settled.porosity_profile(&below, 2000, 3));
        // Every deposited grain is where it was put, and only there.
        for g in &deposit {
            assert!(settled.grains_holding(g.centre) == 1 && cut.grains_holding(g.centre) == 0);
            assert_eq!(settled.grains_holding(g.centre - UP * h), cut.grains_holding(g.centre - UP * h));
        }
        // The settled sample's surface is higher, and no vertical line misses it.
        let hs = settled.surface_heights(2000, 4);
        assert!(hs.iter().all(|z| z.is_finite()));
        let mean = |v: &[f64]| v.iter().sum::<f64>() / v.len() as f64;
        let (mc, ms) = (mean(&cut.surface_heights(2000, 4)), mean(&hs));
        assert!(ms > mc + 0.3, "settled {ms} vs cut {mc}");
    }

    #[test]
    fn transparent_packing_conserves_energy_and_absorbing_one_is_darker() {
        let params = PackingParams { lateral_mm: 1.5, depth_mm: 1.5, seed: 1, ..Default::default() };
        let pk = Packing::generate(&grains(0.0), &params).unwrap();
        let scene = Arc::new(Scene::new(pk));
        let limits = Limits::default();
        let run = |alpha: f64, bottom: f64| {
            let ex = Explicit::new(grains(alpha), scene.clone(), bottom).unwrap();
            let mut c = [0usize; 4];
            for i in 0..4000 {
                let mut rng = Rng::for_ray(5, 0, i);
                match ex.trace(Vec3::new(0.0, 0.0, -1.0), &mut rng, &limits).fate {
                    Fate::Escaped(d) => {
                        assert!(d.z > 0.0);
                        c[0] += 1
                    }
                    Fate::Absorbed => c[1] += 1,
                    Fate::Transmitted => c[2] += 1,
                    Fate::Capped => c[3] += 1,
                }
            }
            c
        };
        // Transparent grains and a slab of 2 mm: everything escapes or goes through.
        let c = run(0.0, 2.0);
        assert_eq!(c[1] + c[3], 0, "{c:?}");
        assert!(c[2] > 0 && c[0] > c[2], "{c:?}");
        // Strongly absorbing grains, semi-infinite: nothing is transmitted, little escapes.
        let c = run(50.0, f64::INFINITY);
        assert_eq!(c[2] + c[3], 0, "{c:?}");
        assert!((c[0] as f64 / 4000.0) < 0.1, "{c:?}");
    }
}

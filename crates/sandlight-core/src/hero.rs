//! Spectral path sharing (docs/transport.md, "Spectral path sharing"): the sand media of a group
//! of wavelengths traced together, one path per ray at a hero wavelength chosen uniformly in the
//! group, with a weight per wavelength (`spectral::SpectralWeights`) and balance-heuristic
//! estimates; and the deterministic fixed-point tallies of such runs.
//!
//! The media of a group share their geometry (particle types, sizes, shapes, free path, pore
//! filling, film thickness, depth); their optics differ. The wavelength-dependent choices are
//! the layer stacks at every particle (reflect / transmit / absorb), absorption along chords
//! through cores and paths through pore water, and the flat water surface of a filled surface
//! pore. The paths are those of the classic tracer, of a path memory (`memory`) or of an
//! explicit packing (`explicit`), whose geometry the group shares. Directions come from the hero's refractive indices (dispersion: docs/transport.md says
//! how groups are formed and what this costs).
//!
//! The stacks' probabilities are read from tables of R and R + T over the incidence cosine,
//! linearly interpolated (`STACK_CELLS` cells), for the hero's decision and the companions'
//! ratios alike; cells where interpolation could be off by more than `TABLE_TOLERANCE` (near
//! critical angles, steep grazing features) are evaluated exactly instead. The shared
//! estimator is exact for these stacks, which differ from the exact ones by < 1e-6 in any
//! probability (tested below; docs/transport.md). A cell is built when a decision first falls
//! in it (`StackTable`).

use std::sync::atomic::{AtomicU64, AtomicU8, Ordering};
use std::sync::{Arc, OnceLock};

use crate::driver::{for_rays, Rays};
use crate::error::SandlightError;
use crate::explicit::{Explicit, ExplicitGeometry};
use crate::fresnel;
use crate::math::Vec3;
use crate::medium::Particulate;
use crate::memory::{trace_with_memory, Memory, PathMemory};
use crate::particle::{survives, Absorber, PathChoices, StackFate, StackKind, Stacks};
use crate::rng::Rng;
use crate::spectral::SpectralWeights;
use crate::transport::{trace_classic, Fate, Limits, RayOutcome};
use crate::volume_scatterer::{VolumeFate, VolumeOptics};

/// Cells of the stack tables over the incidence cosine μ ∈ [0, 1].
pub const STACK_CELLS: usize = 2048;

/// Largest interpolation error of R or R + T allowed in a table cell, checked at interior
/// points of each cell (a cell that fails is evaluated exactly).
pub const TABLE_TOLERANCE: f64 = 5e-7;

/// Most wavelengths in one group (the fixed-point products of `SpectralCounts` assume an
/// estimate ≤ N ≤ 2¹⁶; 256 keeps the per-ray work of the products bounded).
pub const MAX_GROUP: usize = 256;

/// Fixed-point scale of the tallies: an estimate F ∈ [0, N] is counted as round(F · 2³²).
pub const FIXED_ONE: f64 = 4_294_967_296.0;

/// The sand media of a group of wavelengths, traced together.
#[derive(Debug)]
pub struct HeroGroup {
    media: Vec<Particulate>,
    /// Per particle type and `StackKind` (index `12 t + kind.index()`).
    tables: Vec<StackTable>,
    /// Core absorption coefficients (mm⁻¹) per type, per wavelength; None where all are equal.
    core_alpha: Vec<Option<Vec<f64>>>,
    water_alpha: Option<Vec<f64>>,
    water_n: Option<Vec<f64>>,
    /// Core real indices per type, per wavelength; None where all are equal.
    core_n: Vec<Option<Vec<f64>>>,
    /// The tracer of the group's paths.
    paths: Paths,
}

/// The tracer a group's paths take: the geometry they share (the media differ in their
/// optics only).
#[derive(Clone, Debug)]
enum Paths {
    Classic,
    /// A path memory (`memory`), built once for the group.
    Memory(PathMemory),
    /// An explicit packing (`explicit`), the same scene and bottom for every medium.
    Explicit(ExplicitGeometry),
}

/// One stack's table over the incidence cosine, every wavelength of the group, built a cell at
/// a time when a decision first falls in the cell (`HeroGroup::cell`). Each cell costs its two
/// nodes and three interior checks at every wavelength of the group, and a short run (a
/// training sample of 1000 rays) meets a small part of the cells.
///
/// A cell depends on the media alone, so when and on which thread it is built changes no
/// decision: its builder writes the nodes, then publishes the cell's state (release); a reader
/// that sees the state (acquire) sees the nodes. Two threads that build a cell (or the node two
/// cells share) at the same time write the same bits. The values are atomics for that, read
/// with relaxed loads (plain loads on x86-64 and AArch64), in the layout of a table built at
/// once (nodes in order, the wavelengths of a node side by side).
#[derive(Debug)]
struct StackTable {
    /// Whether the stack can be met (`Stacks::occurs`: bare surface only with a partial
    /// coating); a table of a stack that cannot is never read.
    occurs: bool,
    /// Allocated when a decision first reads the table: never for stacks the rays do not meet
    /// (those of water-filled pores in a dry sand).
    data: OnceLock<TableData>,
}

/// The cells and nodes of a `StackTable`.
#[derive(Debug)]
struct TableData {
    /// Per cell: `UNBUILT`, `INTERPOLATED` or `EXACT`.
    state: Box<[AtomicU8]>,
    /// [R, R + T] (bits of the f64) at node μ = i / STACK_CELLS for every wavelength, at
    /// `i * n + j`; set for the nodes of the interpolated cells built.
    nodes: Box<[[AtomicU64; 2]]>,
}

/// A cell's state: not built yet, interpolated, or evaluated exactly (interpolation not within
/// `TABLE_TOLERANCE` at some wavelength).
const UNBUILT: u8 = 0;
const INTERPOLATED: u8 = 1;
const EXACT: u8 = 2;

impl TableData {
    fn new(n: usize) -> TableData {
        TableData {
            state: (0..STACK_CELLS).map(|_| AtomicU8::new(UNBUILT)).collect(),
            nodes: (0..(STACK_CELLS + 1) * n).map(|_| [AtomicU64::new(0), AtomicU64::new(0)]).collect(),
        }
    }

    /// [R, R + T] at node `k` (index `i * n + j`), as stored.
    #[inline(always)]
    fn node(&self, k: usize) -> [f64; 2] {
        self.nodes[k].each_ref().map(|v| f64::from_bits(v.load(Ordering::Relaxed)))
    }
}

/// A built cell of a `StackTable` (`HeroGroup::cell`): where its nodes are, and whether it is
/// evaluated exactly.
#[derive(Clone, Copy)]
struct Cell<'a> {
    data: &'a TableData,
    /// Index of its floor node at wavelength 0 (`i * n`).
    floor: usize,
    exact: bool,
}

fn varies(v: Vec<f64>) -> Option<Vec<f64>> {
    v.iter().any(|&x| x != v[0]).then_some(v)
}

/// Checks that `media` (one per wavelength, 1 to `MAX_GROUP`) differ only in their optics.
fn check_geometry(media: &[Particulate]) -> Result<(), SandlightError> {
    if media.is_empty() || media.len() > MAX_GROUP {
        return Err(SandlightError::parameter(
            "media",
            format!("{} media", media.len()),
            &format!("1 to {MAX_GROUP} media, one per wavelength"),
        ));
    }
    let first = &media[0];
    for (j, m) in media.iter().enumerate() {
        let same_types = m.types.len() == first.types.len()
            && m.types.iter().zip(&first.types).all(|(a, b)| {
                a.probability == b.probability
                    && a.sizes == b.sizes
                    && a.aspect_ratio == b.aspect_ratio
                    && a.optics.wets == b.optics.wets
                    && a.optics.core_scattering_per_mm == b.optics.core_scattering_per_mm
                    && a.optics.coating.map(|c| (c.thickness_mm, c.coverage))
                        == b.optics.coating.map(|c| (c.thickness_mm, c.coverage))
            });
        let same_pore = m.pore.film_thickness_mm == first.pore.film_thickness_mm
            && m.pore.film_coverage == first.pore.film_coverage
            && m.pore.water_filled_probability == first.pore.water_filled_probability;
        let majorants =
            |m: &Particulate| (0..m.types.len()).map(|i| m.volume_scatterer(i).map(|v| v.majorant)).collect::<Vec<_>>();
        if !same_types
            || !same_pore
            || majorants(m) != majorants(first)
            || m.mean_free_path_mm != first.mean_free_path_mm
            || m.depth_mm != first.depth_mm
        {
            return Err(SandlightError::parameter(
                &format!("media[{j}]"),
                "a medium of other geometry",
                "the media of a spectral group differ only in their optics (same particle types, sizes, shapes, \
                 inclusions, free path, pore filling, film thickness and coverage, coating thickness and coverage, volume \
                 scatterers and their majorants, and depth)",
            ));
        }
    }
    Ok(())
}

impl HeroGroup {
    /// The group of `media` (one per wavelength, at most `MAX_GROUP`), which must share their
    /// geometry, traced with path memory `memory`.
    pub fn new(media: Vec<Particulate>, memory: Memory) -> Result<HeroGroup, SandlightError> {
        check_geometry(&media)?;
        // The memory's geometry is that of every medium of the group (checked equal above).
        let paths = PathMemory::new(&media[0], memory).map_or(Paths::Classic, Paths::Memory);
        Ok(HeroGroup::with_paths(media, paths))
    }

    /// The group of the explicit samples `samples` (one per wavelength, at most `MAX_GROUP`),
    /// which must share their geometry and be traced through the same scene (one `Arc<Scene>`)
    /// with the same bottom.
    pub fn explicit(samples: Vec<Explicit>) -> Result<HeroGroup, SandlightError> {
        let (media, geometries): (Vec<Particulate>, Vec<ExplicitGeometry>) =
            samples.into_iter().map(|e| (e.medium, e.geometry)).unzip();
        check_geometry(&media)?;
        let first = &geometries[0];
        for (j, g) in geometries.iter().enumerate() {
            if !Arc::ptr_eq(&g.scene, &first.scene) || g.bottom_mm != first.bottom_mm {
                return Err(SandlightError::parameter(
                    &format!("media[{j}]"),
                    "an explicit sample of another scene or bottom",
                    "the explicit samples of a spectral group are traced through one packing (the same scene) \
                     with the same bottom",
                ));
            }
        }
        // The fines' free path and draw of `first` are those of every medium (checked equal).
        Ok(HeroGroup::with_paths(media, Paths::Explicit(first.clone())))
    }

    /// The group of `media` (checked by `check_geometry`) whose paths `paths` trace.
    fn with_paths(media: Vec<Particulate>, paths: Paths) -> HeroGroup {
        let types = media[0].types.len();
        // Every medium meets the same stacks (`occurs` depends on the coating's coverage, the
        // same for all: `check_geometry`).
        let tables = (0..types)
            .flat_map(|t| StackKind::ALL.map(|kind| (t, kind)))
            .map(|(t, kind)| StackTable { occurs: media[0].type_tables(t).1.occurs(kind), data: OnceLock::new() })
            .collect();
        let core_alpha =
            (0..types).map(|t| varies(media.iter().map(|m| m.types[t].optics.core_alpha_per_mm).collect())).collect();
        let water_alpha = varies(media.iter().map(|m| m.pore.water_alpha_per_mm).collect());
        let water_n = varies(media.iter().map(|m| m.pore.water_n).collect());
        let core_n = (0..types).map(|t| varies(media.iter().map(|m| m.types[t].optics.core_n).collect())).collect();
        HeroGroup { media, tables, core_alpha, water_alpha, water_n, core_n, paths }
    }

    /// Wavelengths in the group.
    pub fn len(&self) -> usize {
        self.media.len()
    }

    pub fn is_empty(&self) -> bool {
        self.media.is_empty()
    }

    /// The medium at wavelength `j`.
    pub fn medium(&self, j: usize) -> &Particulate {
        &self.media[j]
    }

    /// The indices of the medium a stack `kind` of type `t` is entered from (per wavelength),
    /// None where they are all equal (air, or no dispersion in the group).
    #[inline]
    fn incident_indices(&self, t: usize, kind: StackKind) -> Option<&[f64]> {
        match (kind.exit, kind.water) {
            (true, _) => self.core_n[t].as_deref(),
            (false, true) => self.water_n.as_deref(),
            (false, false) => None,
        }
    }

    /// [R, R + T] of stack `kind` of type `t` for wavelength `j` at cosine `cos` (in [0, 1]).
    #[inline]
    fn rt_exact_or_table(&self, t: usize, kind: StackKind, cos: f64, j: usize) -> [f64; 2] {
        let x = cos * STACK_CELLS as f64;
        let cell = (x as usize).min(STACK_CELLS - 1);
        self.rt_at(t, kind, cos, cell, x - cell as f64, j)
    }

    /// Cell `i` of the table of stack `kind` of type `t`, built now if no decision fell in it
    /// before (`StackTable`).
    #[inline(always)]
    fn cell(&self, t: usize, kind: StackKind, i: usize) -> Cell<'_> {
        let tab = &self.tables[StackKind::ALL.len() * t + kind.index()];
        let data = tab.data.get_or_init(|| TableData::new(self.media.len()));
        let mut state = data.state[i].load(Ordering::Acquire);
        if state == UNBUILT {
            state = self.build_cell(data, t, kind, i);
        }
        Cell { data, floor: i * self.media.len(), exact: state == EXACT }
    }

    /// Builds cell `i` of `data`, the table of stack `kind` of type `t` (see `cell`), and
    /// returns its state. The interpolation is checked at 3 interior points, every wavelength
    /// (7 points marked the same 19.8 % of the cells for the default sample at 400–700 nm); an
    /// exact cell needs no nodes, so the first wavelength that fails ends the build.
    #[cold]
    #[inline(never)]
    fn build_cell(&self, data: &TableData, t: usize, kind: StackKind, i: usize) -> u8 {
        // [R, R + T] of medium `m` at μ = x / STACK_CELLS: node x = i and i + 1, interior
        // points x = i + frac.
        let at = |m: &Particulate, x: f64| {
            let (r, t) = m.type_tables(t).1.rt(kind, x / STACK_CELLS as f64);
            [r, r + t]
        };
        let n = self.media.len();
        let mut state = INTERPOLATED;
        for (j, m) in self.media.iter().enumerate() {
            let (a, b) = (at(m, i as f64), at(m, (i + 1) as f64));
            let off = [0.25, 0.5, 0.75].into_iter().any(|frac| {
                let v = at(m, i as f64 + frac);
                (0..2).any(|k| (a[k] + frac * (b[k] - a[k]) - v[k]).abs() > TABLE_TOLERANCE)
            });
            if off {
                state = EXACT;
                break;
            }
            for (node, v) in [(i * n + j, a), ((i + 1) * n + j, b)] {
                data.nodes[node].iter().zip(v).for_each(|(x, v)| x.store(v.to_bits(), Ordering::Relaxed));
            }
        }
        data.state[i].store(state, Ordering::Release);
        state
    }

    /// [R, R + T] of stack `kind` of type `t` for wavelength `j` at cosine `cos` (in [0, 1]),
    /// interpolated in cell `i` at `frac`, or exact where the cell is marked so.
    // Always inlined: a call per stack decision cost ~10 % of a one-wavelength run (valgrind).
    #[inline(always)]
    fn rt_at(&self, t: usize, kind: StackKind, cos: f64, i: usize, frac: f64, j: usize) -> [f64; 2] {
        self.rt_in(self.cell(t, kind, i), t, kind, cos, frac, j)
    }

    /// `rt_at` with the cell already looked up (`cell`).
    #[inline(always)]
    fn rt_in(&self, cell: Cell<'_>, t: usize, kind: StackKind, cos: f64, frac: f64, j: usize) -> [f64; 2] {
        if cell.exact {
            let (r, t) = self.media[j].type_tables(t).1.rt(kind, cos);
            return [r, r + t];
        }
        let (a, b) = (cell.data.node(cell.floor + j), cell.data.node(cell.floor + self.media.len() + j));
        [a[0] + frac * (b[0] - a[0]), a[1] + frac * (b[1] - a[1])]
    }

    /// Fraction of table cells evaluated exactly (over all types and stacks), every cell built.
    pub fn exact_fraction(&self) -> f64 {
        let (mut exact, mut cells) = (0, 0);
        for (k, _) in self.tables.iter().enumerate().filter(|(_, tab)| tab.occurs) {
            let (t, kind) = (k / StackKind::ALL.len(), StackKind::ALL[k % StackKind::ALL.len()]);
            cells += STACK_CELLS;
            exact += (0..STACK_CELLS).filter(|&i| self.cell(t, kind, i).exact).count();
        }
        exact as f64 / cells as f64
    }

    /// Traces one ray: the hero drawn from the ray's generator, then the path with the
    /// companions' weights. Returns the fate and events; `weights` holds the path's weights.
    pub fn trace(&self, dir_in: Vec3, rng: &mut Rng, limits: &Limits, weights: &mut SpectralWeights) -> (Fate, u64) {
        let n = self.media.len();
        let hero = ((rng.uniform() * n as f64) as usize).min(n - 1);
        weights.reset(hero);
        let out = if n == 1 {
            // One wavelength: every ratio is the hero's own, so the weights stay 1 and only the
            // decisions are made (`Single`, the same decisions from the same numbers).
            self.trace_path(hero, dir_in, rng, limits, &mut Single { group: self, particle: 0 })
        } else {
            self.trace_path(hero, dir_in, rng, limits, &mut Companions { group: self, weights, particle: 0 })
        };
        (out.fate, out.events)
    }

    /// One path through the medium of wavelength `hero` by the group's tracer, its choices
    /// made by `choices`.
    #[inline]
    fn trace_path(
        &self,
        hero: usize,
        dir_in: Vec3,
        rng: &mut Rng,
        limits: &Limits,
        choices: &mut impl PathChoices,
    ) -> RayOutcome {
        let medium = &self.media[hero];
        match &self.paths {
            Paths::Classic => trace_classic(medium, dir_in, rng, limits, choices),
            Paths::Memory(paths) => trace_with_memory(paths, medium, dir_in, rng, limits, choices),
            Paths::Explicit(geometry) => geometry.trace(medium, dir_in, rng, limits, choices),
        }
    }

    /// The hero's decision at stack `kind` of type `t` for a uniform `u` at incidence cosine
    /// `cos` (clamped to [0, 1]), with the clamped cosine, the table cell and the fraction of
    /// it, and the hero's [R, R + T] there.
    #[inline(always)]
    fn hero_fate(&self, t: usize, kind: StackKind, cos: f64, u: f64, hero: usize) -> HeroFate<'_> {
        let cos = cos.clamp(0.0, 1.0);
        let x = cos * STACK_CELLS as f64;
        let i = (x as usize).min(STACK_CELLS - 1);
        let frac = x - i as f64;
        let cell = self.cell(t, kind, i);
        let rt = self.rt_in(cell, t, kind, cos, frac, hero);
        let fate = if u < rt[0] {
            StackFate::Reflect
        } else if u >= rt[1] {
            StackFate::Absorb
        } else {
            StackFate::Transmit
        };
        HeroFate { fate, cos, cell, frac, rt }
    }
}

/// A stack decision of the hero and where it was read (`HeroGroup::hero_fate`): the table cell
/// (`HeroGroup::cell`) and the fraction of it.
struct HeroFate<'a> {
    fate: StackFate,
    cos: f64,
    cell: Cell<'a>,
    frac: f64,
    rt: [f64; 2],
}

/// The choices of a group of one wavelength: the decisions of `Companions` (the stacks read
/// from the group's tables), with no weights to keep, since every ratio would be the hero's own
/// (1) and the path's estimate is 1.
pub struct Single<'a> {
    group: &'a HeroGroup,
    particle: usize,
}

impl PathChoices for Single<'_> {
    #[inline(always)]
    fn particle(&mut self, type_index: usize) {
        self.particle = type_index;
    }

    #[inline(always)]
    fn stack_fate(&mut self, _stacks: &Stacks, kind: StackKind, cos: f64, u: f64) -> StackFate {
        self.group.hero_fate(self.particle, kind, cos, u, 0).fate
    }
}

/// The choices of a hero-wavelength path: the hero decides, every wavelength's weight takes
/// the ratio of its probability of the outcome to the hero's.
pub struct Companions<'a> {
    group: &'a HeroGroup,
    weights: &'a mut SpectralWeights,
    particle: usize,
}

impl PathChoices for Companions<'_> {
    #[inline]
    fn particle(&mut self, type_index: usize) {
        self.particle = type_index;
    }

    #[inline]
    fn stack_fate(&mut self, _stacks: &Stacks, kind: StackKind, cos: f64, u: f64) -> StackFate {
        let (g, t, hero) = (self.group, self.particle, self.weights.hero());
        let HeroFate { fate, cos, cell, frac, rt: [r, rt] } = g.hero_fate(t, kind, cos, u, hero);
        if fate == StackFate::Absorb {
            // The path ends with no light for any wavelength: no weight to update.
            return fate;
        }
        let p = |[r, rt]: [f64; 2]| if fate == StackFate::Reflect { r } else { rt - r };
        let p_hero = p([r, rt]);
        match g.incident_indices(t, kind) {
            None => {
                self.weights.scale(|j| if j == hero { 1.0 } else { p(g.rt_in(cell, t, kind, cos, frac, j)) / p_hero })
            }
            Some(n) => {
                // Dispersion: wavelength j meets the interface with the hero's tangential
                // invariant s = n_h sin θ_h (the hero's direction outside), at its own cosine.
                let s2 = n[hero] * n[hero] * (1.0 - cos * cos);
                self.weights.scale(|j| {
                    if j == hero {
                        return 1.0;
                    }
                    let cos_j = (1.0 - s2 / (n[j] * n[j])).max(0.0).sqrt();
                    p(g.rt_exact_or_table(t, kind, cos_j, j)) / p_hero
                })
            }
        }
        fate
    }

    #[inline]
    fn survives(&mut self, absorber: Absorber, alpha_per_mm: f64, len: f64, rng: &mut Rng) -> bool {
        if alpha_per_mm > 0.0 && !survives(rng.uniform(), alpha_per_mm * len) {
            return false;
        }
        let alphas = match absorber {
            Absorber::Core => &self.group.core_alpha[self.particle],
            Absorber::Water => &self.group.water_alpha,
        };
        if let Some(a) = alphas {
            let a_hero = a[self.weights.hero()];
            self.weights.attenuate(|j| a[j] - a_hero, len);
        }
        true
    }

    #[inline]
    fn diffuse(&mut self, stacks: &Stacks, kind: StackKind, cos: f64, reflected: bool, u: f64) -> bool {
        // The hero decides with its exact probability; each wavelength's weight takes the ratio
        // of its own (exact, at its own cosine under dispersion) to the hero's.
        let p_hero = stacks.diffuse_probability(kind, cos, reflected);
        let diffuse = u < p_hero;
        let p = |q: f64| if diffuse { q } else { 1.0 - q };
        let (g, t, hero) = (self.group, self.particle, self.weights.hero());
        let p_h = p(p_hero);
        let s2 = g.incident_indices(t, kind).map(|n| (n, n[hero] * n[hero] * (1.0 - cos * cos)));
        self.weights.scale(|j| {
            if j == hero {
                return 1.0;
            }
            let cos_j = match &s2 {
                None => cos,
                Some((n, s2)) => (1.0 - s2 / (n[j] * n[j])).max(0.0).sqrt(),
            };
            p(g.media[j].type_tables(t).1.diffuse_probability(kind, cos_j, reflected)) / p_h
        });
        diffuse
    }

    #[inline]
    fn volume_fate(&mut self, type_index: usize, water: bool, hero: &VolumeOptics, u: f64) -> VolumeFate {
        let fate = hero.fate(u);
        // Absorption ends the path with no light for any wavelength: no weight to update.
        if fate != VolumeFate::Absorb {
            let (g, h) = (self.group, self.weights.hero());
            let p_hero = hero.probability(fate);
            self.weights.scale(|j| {
                if j == h {
                    return 1.0;
                }
                g.media[j].volume_scatterer(type_index).map_or(0.0, |v| v.optics(water).probability(fate)) / p_hero
            });
        }
        fate
    }

    #[inline]
    fn volume_scattered(&mut self, type_index: usize, water: bool, hero: &VolumeOptics, mu: f64) {
        // The direction's density at each wavelength over the hero's (both the sampled
        // interpolants of the tables).
        let (g, h) = (self.group, self.weights.hero());
        let p_hero = hero.phase.pdf(mu);
        self.weights.scale(|j| {
            if j == h {
                return 1.0;
            }
            g.media[j].volume_scatterer(type_index).map_or(0.0, |v| v.optics(water).phase.pdf(mu)) / p_hero
        });
    }

    #[inline]
    fn water_surface(&mut self, from_air: bool, cos: f64, reflected: bool) {
        let Some(n) = &self.group.water_n else { return };
        let hero = self.weights.hero();
        // From the water, at each wavelength's own cosine for the hero's invariant n_h sin θ_h.
        let s2 = n[hero] * n[hero] * (1.0 - cos * cos);
        let r = |n: f64| {
            if from_air {
                fresnel::dielectric(1.0, n, cos)
            } else {
                fresnel::dielectric(n, 1.0, (1.0 - s2 / (n * n)).max(0.0).sqrt())
            }
        };
        let p = |n: f64| if reflected { r(n) } else { 1.0 - r(n) };
        let p_hero = p(n[hero]);
        self.weights.scale(|j| if j == hero { 1.0 } else { p(n[j]) / p_hero });
    }
}

/// Fixed-point tallies of a shared run: integer sums, so that any split of the rays over
/// threads and batches gives bit-identical totals (docs/transport.md). Estimates F_j ∈ [0, N]
/// enter as q_j = round(F_j · 2³²).
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct SpectralCounts {
    pub launched: u64,
    pub capped: u64,
    /// Particle events summed over rays (shared by the group's wavelengths).
    pub events: u64,
    /// Σ q_j over escaped rays.
    pub escaped: Vec<u128>,
    /// Σ q_j over rays transmitted through the bottom.
    pub transmitted: Vec<u128>,
    /// Σ q_i q_j over escaped rays, i ≤ j, row by row (the diagonal is Σ q_j²).
    pub products: Vec<u128>,
}

impl SpectralCounts {
    pub fn zeros(n: usize) -> SpectralCounts {
        SpectralCounts {
            escaped: vec![0; n],
            transmitted: vec![0; n],
            products: vec![0; n * (n + 1) / 2],
            ..Default::default()
        }
    }

    pub fn merge(mut self, o: SpectralCounts) -> SpectralCounts {
        self.launched += o.launched;
        self.capped += o.capped;
        self.events += o.events;
        let add = |a: &mut Vec<u128>, b: &[u128]| a.iter_mut().zip(b).for_each(|(x, y)| *x += y);
        add(&mut self.escaped, &o.escaped);
        add(&mut self.transmitted, &o.transmitted);
        add(&mut self.products, &o.products);
        self
    }
}

/// The path's estimates as tallied: q_j = round(F_j · 2³²) into `q`, with `estimates` as scratch
/// (both of the group's length).
#[inline]
pub fn fixed_point_estimates(weights: &SpectralWeights, estimates: &mut [f64], q: &mut [u64]) {
    if estimates.len() == 1 {
        // `Single` leaves the weights at 1: the estimate N W / Σ W is 1.
        estimates[0] = 1.0;
    } else {
        weights.estimates(estimates);
    }
    for (q, &f) in q.iter_mut().zip(estimates.iter()) {
        *q = (f * FIXED_ONE).round() as u64;
    }
}

/// A block's tally with the scratch space of its rays.
struct Block {
    counts: SpectralCounts,
    weights: SpectralWeights,
    estimates: Vec<f64>,
    q: Vec<u64>,
}

/// Directional-hemispherical reflectance tallies of a shared run over `group` (docs/model.md
/// §2.6 with the estimates of `spectral`): ρ_j = Σ F_j / launched over escaped rays.
pub fn spectral_directional_hemispherical(
    group: &HeroGroup,
    dir_in: Vec3,
    rays: Rays,
    limits: &Limits,
) -> SpectralCounts {
    let n = group.len();
    let init = || Block {
        counts: SpectralCounts::zeros(n),
        weights: SpectralWeights::new(n, 0),
        estimates: vec![0.0; n],
        q: vec![0; n],
    };
    let body = |b: &mut Block, i: u64| {
        let (fate, events) = group.trace(dir_in, &mut rays.rng(i), limits, &mut b.weights);
        let c = &mut b.counts;
        c.launched += 1;
        c.events += events;
        let escaped = match fate {
            Fate::Escaped(_) => true,
            Fate::Transmitted => false,
            Fate::Capped => {
                c.capped += 1;
                return;
            }
            Fate::Absorbed => return,
        };
        fixed_point_estimates(&b.weights, &mut b.estimates, &mut b.q);
        if !escaped {
            c.transmitted.iter_mut().zip(&b.q).for_each(|(s, &q)| *s += q as u128);
            return;
        }
        c.escaped.iter_mut().zip(&b.q).for_each(|(s, &q)| *s += q as u128);
        let mut k = 0;
        for (a, &qa) in b.q.iter().enumerate() {
            for (p, &qb) in c.products[k..k + n - a].iter_mut().zip(&b.q[a..]) {
                *p += qa as u128 * qb as u128;
            }
            k += n - a;
        }
    };
    let merge = |mut a: Block, b: Block| {
        a.counts = a.counts.merge(b.counts);
        a
    };
    for_rays(rays.first, rays.n, 16, init, body, merge).counts
}

/// Sand media for the tests of the shared tracers.
#[cfg(test)]
pub(crate) mod testing {
    use std::sync::Arc;

    use crate::explicit::{Explicit, Scene};
    use crate::medium::{ParticleType, Particulate};
    use crate::packing::{Packing, PackingParams};
    use crate::particle::{Coating, ParticleOptics, PoreOptics};
    use crate::sizes::QuantileTable;

    /// A quartz-like sand with a weakly absorbing coating over 70 % of the surface and wet
    /// pores, whose absorption
    /// (core, coating, water) is scaled by `absorb` and whose indices are shifted by `dn`.
    pub(crate) fn sand(absorb: f64, dn: f64) -> Particulate {
        sand_with(absorb, dn, Coating { coverage: 0.7, ..Coating::uniform(1.9 + dn, 40.0 * absorb, 5e-4) })
    }

    pub(crate) fn sand_with(absorb: f64, dn: f64, coating: Coating) -> Particulate {
        let sizes = QuantileTable::new((0..17).map(|j| 0.15 + 0.2 * j as f64 / 16.0).collect()).unwrap();
        let optics = ParticleOptics {
            core_n: 1.55 + dn,
            core_k: 1e-6 * absorb,
            core_alpha_per_mm: 0.2 * absorb,
            core_scattering_per_mm: 0.0,
            coating: Some(coating),
            wets: true,
        };
        let t = ParticleType { probability: 1.0, sizes, aspect_ratio: 1.3, optics };
        let pore = PoreOptics {
            water_n: 1.333 + dn,
            water_alpha_per_mm: 0.5 * absorb,
            film_thickness_mm: 2e-3,
            film_coverage: 0.6,
            water_filled_probability: 0.3,
        };
        Particulate::new(vec![t], 0.12, pore, f64::INFINITY).unwrap()
    }

    /// `packed_sand(absorb, dn)` through the explicit packing `scene` (semi-infinite).
    pub(crate) fn explicit_sand(scene: &Arc<Scene>, absorb: f64, dn: f64) -> Explicit {
        Explicit::new(packed_sand(absorb, dn), scene.clone(), f64::INFINITY).unwrap()
    }

    /// A packing of the grains of `packed_sand` (a 1.5 mm box; its clay stays on the fly).
    pub(crate) fn packed_scene(seed: u64) -> Arc<Scene> {
        let params = PackingParams { lateral_mm: 1.5, depth_mm: 1.5, seed, ..Default::default() };
        Arc::new(Scene::new(Packing::generate(&packed_sand(1.0, 0.0), &params).unwrap()))
    }

    /// For the path memories: packed spheres (the pair correlation of `Memory::Packed`) and
    /// clay fines, the coating, films and wet pores of `sand`, absorption scaled by `absorb`,
    /// indices shifted by `dn`.
    pub(crate) fn packed_sand(absorb: f64, dn: f64) -> Particulate {
        let m = sand(absorb, dn);
        let grain = ParticleType { probability: 0.8, aspect_ratio: 1.0, ..m.types[0].clone() };
        let fine = ParticleType { probability: 0.2, sizes: QuantileTable::constant(0.002), ..grain.clone() };
        Particulate::new(vec![grain, fine], m.mean_free_path_mm, m.pore, m.depth_mm).unwrap()
    }
}

#[cfg(test)]
mod tests {
    use super::testing::{explicit_sand, packed_sand, packed_scene, sand, sand_with};
    use super::*;
    use crate::driver::{directional_hemispherical, incident_direction};
    use crate::memory::WithMemory;
    use crate::particle::Coating;
    use crate::transport::Medium;
    use crate::volume_scatterer::testing::{henyey_greenstein, scatterer};

    /// ρ and its standard error of wavelength `j` of a shared run's tallies over `n` rays.
    fn shared_estimate(c: &SpectralCounts, j: usize, n: u64) -> (f64, f64) {
        let w = c.escaped.len();
        let s1 = c.escaped[j] as f64 / FIXED_ONE;
        let k = j * w - j * (j.saturating_sub(1)) / 2;
        let s2 = c.products[k] as f64 / (FIXED_ONE * FIXED_ONE);
        let rho = s1 / n as f64;
        (rho, ((s2 / n as f64 - rho * rho) / (n - 1) as f64).sqrt())
    }

    /// Asserts that each shared estimate of `g` over `rays` (stream 1) lies within 4 standard
    /// errors of its own wavelength's independent run, `own[j]` over the same rays in stream 0.
    fn assert_agrees_with_own_runs(g: &HeroGroup, own: &[impl Medium], dir: Vec3, rays: Rays, label: &str) {
        let c = spectral_directional_hemispherical(g, dir, rays, &Limits::default());
        for (j, m) in own.iter().enumerate() {
            let (rho, se_shared) = shared_estimate(&c, j, rays.n);
            let mono = directional_hemispherical(m, dir, Rays { stream: 0, ..rays }, &Limits::default());
            let mono = mono.escaped as f64 / rays.n as f64;
            let se = (se_shared.powi(2) + mono * (1.0 - mono) / rays.n as f64).sqrt();
            assert!((rho - mono).abs() < 4.0 * se, "{label}, case {j}: shared {rho} vs {mono} ± {se}");
        }
    }

    /// Asserts that a group of one wavelength traces the paths `own` traces, choice for choice:
    /// the hero draw takes one number, then every ray has the same fate, events and next number
    /// (every weight 1; the stacks decide from their tables, within 5e-7 of the exact
    /// probabilities, which no decision of these rays falls between).
    fn assert_traces_as(g: &HeroGroup, own: &impl Medium, dir: Vec3, label: &str) {
        let mut weights = SpectralWeights::new(1, 0);
        for i in 0..300 {
            let mut a = Rng::for_ray(3, 1, i);
            let (fate, events) = g.trace(dir, &mut a, &Limits::default(), &mut weights);
            let mut b = Rng::for_ray(3, 1, i);
            b.uniform();
            let out = own.trace(dir, &mut b, &Limits::default());
            assert_eq!((fate, events), (out.fate, out.events), "{label}, ray {i}");
            assert_eq!(a.next_u64(), b.next_u64(), "{label}, ray {i}");
        }
    }

    fn on_threads<T: Send>(threads: usize, f: impl FnOnce() -> T + Send) -> T {
        rayon::ThreadPoolBuilder::new().num_threads(threads).build().unwrap().install(f)
    }

    #[test]
    fn a_group_of_one_traces_as_companions_would() {
        // `Single` (a group of one wavelength) makes the decisions `Companions` makes, from the
        // same random numbers, and leaves the weights at 1: classic and packed memory, films,
        // wet pores, a partial coating.
        for (memory, medium) in [(Memory::None, sand(1.0, 0.0)), (Memory::Packed, packed_sand(1.0, 0.0))] {
            let g = HeroGroup::new(vec![medium], memory).unwrap();
            let dir = incident_direction(0.5);
            let mut weights = SpectralWeights::new(1, 0);
            for i in 0..3000 {
                let mut r1 = Rng::for_ray(6, 0, i);
                let (fate, events) = g.trace(dir, &mut r1, &Limits::default(), &mut weights);
                assert_eq!(weights, SpectralWeights::new(1, 0));
                let mut r2 = Rng::for_ray(6, 0, i);
                r2.uniform(); // the hero's draw
                let mut w2 = SpectralWeights::new(1, 0);
                let mut companions = Companions { group: &g, weights: &mut w2, particle: 0 };
                let out = g.trace_path(0, dir, &mut r2, &Limits::default(), &mut companions);
                assert_eq!((fate, events), (out.fate, out.events), "{memory:?} ray {i}");
                assert_eq!(r1.next_u64(), r2.next_u64(), "{memory:?} ray {i}");
                let mut e = [0.0];
                w2.estimates(&mut e);
                assert_eq!(e, [1.0]);
            }
        }
    }

    #[test]
    fn stack_tables_are_close_to_the_exact_stacks() {
        // Interpolated or exact by cell: within 1e-6 of the exact R and R + T at 40 001
        // cosines, every stack, including the square-root edges at critical cosines; most cells
        // are interpolated.
        let g = HeroGroup::new(vec![sand(1.0, 0.0), sand(3.0, 0.02)], Memory::None).unwrap();
        let mut worst = 0.0f64;
        for j in 0..2 {
            let (_, stacks) = g.medium(j).type_tables(0);
            for kind in StackKind::ALL.into_iter().filter(|&k| stacks.occurs(k)) {
                for i in 0..=40_000 {
                    let mu = i as f64 / 40_000.0;
                    let x = mu * STACK_CELLS as f64;
                    let cell = (x as usize).min(STACK_CELLS - 1);
                    let [r, rt] = g.rt_at(0, kind, mu, cell, x - cell as f64, j);
                    let (re, te) = stacks.rt(kind, mu);
                    worst = worst.max((r - re).abs()).max((rt - re - te).abs());
                }
            }
        }
        assert!(worst < 1e-6, "worst interpolation error {worst}");
        assert!(g.exact_fraction() < 0.3, "{}", g.exact_fraction());
    }

    /// A digest of every sum of `c` (equal only if every sum is).
    fn digest(c: &SpectralCounts) -> u128 {
        let sums = [c.launched, c.capped, c.events].map(u128::from);
        sums.iter()
            .chain(&c.escaped)
            .chain(&c.transmitted)
            .chain(&c.products)
            .fold(0, |h, &v| h.wrapping_mul(0x0000_0000_0100_0000_0000_0000_0000_013b).wrapping_add(v))
    }

    #[test]
    fn shared_tallies_are_those_recorded_before() {
        // Recorded from the build of commit ad8b41e (every stack table built with its group):
        // 24 wavelengths (absorption ×0.2–3.65, indices +0–0.0115: the companions' own cosines)
        // classic and packed, and one wavelength (`Single`), 2000 rays each. The cells are built
        // as the rays meet them, or every one before the first ray (`exact_fraction`): the same.
        let recorded = [
            (Memory::None, 24, 12640, 251813085416347861666106311106190493714),
            (Memory::Packed, 24, 12615, 109891111923202867562303561234114083356),
            (Memory::None, 1, 41807, 67089939280058249064918315105650415261),
        ];
        let dir = incident_direction(0.6);
        let rays = Rays { seed: 12, stream: 1, first: 0, n: 2000 };
        for (memory, n, events, sums) in recorded {
            let media: Vec<_> = (0..n).map(|j| packed_sand(0.2 + 0.15 * j as f64, 0.0005 * j as f64)).collect();
            let (lazy, built) =
                (HeroGroup::new(media.clone(), memory).unwrap(), HeroGroup::new(media, memory).unwrap());
            built.exact_fraction();
            for g in [lazy, built] {
                let c = spectral_directional_hemispherical(&g, dir, rays, &Limits::default());
                assert_eq!((c.events, digest(&c)), (events, sums), "{memory:?}, {n} wavelengths");
            }
        }
    }

    #[test]
    fn a_group_of_one_wavelength_agrees_with_the_classic_tracer() {
        // One wavelength: every weight is 1, the estimate the indicator of escape; the tallies
        // count escapes exactly as the classic tracer does (different random streams).
        let m = sand(1.0, 0.0);
        let g = HeroGroup::new(vec![m.clone()], Memory::None).unwrap();
        let dir = incident_direction(0.5);
        let n = 40_000;
        let c =
            spectral_directional_hemispherical(&g, dir, Rays { seed: 1, stream: 1, first: 0, n }, &Limits::default());
        assert_eq!(c.escaped[0] % FIXED_ONE as u128, 0);
        let shared = c.escaped[0] as f64 / FIXED_ONE / n as f64;
        let classic = directional_hemispherical(&m, dir, Rays { seed: 1, stream: 0, first: 0, n }, &Limits::default());
        let mono = classic.escaped as f64 / n as f64;
        let se = (2.0 * mono * (1.0 - mono) / n as f64).sqrt();
        assert!((shared - mono).abs() < 4.0 * se, "{shared} vs {mono} ± {se}");
    }

    #[test]
    fn shared_estimates_agree_with_independent_runs() {
        // Five wavelengths whose absorption differs (core, coating, film and bulk water by a
        // factor 12): each shared estimate within 4 standard errors of its own classic run.
        let absorb = [0.25, 0.5, 1.0, 2.0, 3.0];
        let g = HeroGroup::new(absorb.iter().map(|&a| sand(a, 0.0)).collect(), Memory::None).unwrap();
        let dir = incident_direction(0.3);
        let n = 60_000;
        let c =
            spectral_directional_hemispherical(&g, dir, Rays { seed: 4, stream: 1, first: 0, n }, &Limits::default());
        for (j, &a) in absorb.iter().enumerate() {
            let s1 = c.escaped[j] as f64 / FIXED_ONE;
            let k = j * absorb.len() - j * (j.saturating_sub(1)) / 2;
            let s2 = c.products[k] as f64 / (FIXED_ONE * FIXED_ONE);
            let (rho, var) = (s1 / n as f64, (s2 / n as f64 - (s1 / n as f64).powi(2)) / (n - 1) as f64);
            let classic = directional_hemispherical(
                &sand(a, 0.0),
                dir,
                Rays { seed: 4, stream: 0, first: 0, n },
                &Limits::default(),
            );
            let mono = classic.escaped as f64 / n as f64;
            let se = (var + mono * (1.0 - mono) / n as f64).sqrt();
            assert!((rho - mono).abs() < 4.0 * se, "absorption ×{a}: shared {rho} vs {mono} ± {se}");
        }
    }

    #[test]
    fn shared_estimates_agree_with_independent_runs_through_a_scattering_coating() {
        // A pigmented coating (optical depth ~1–10, diffuse reflection and transmission) whose
        // absorption, scattering, asymmetry and indices differ by wavelength: the diffuse
        // choices' weights are exact, so each shared estimate agrees with its own classic run.
        let coating = |a: f64, s: f64, g: f64, dn: f64| Coating {
            n: 1.56 + dn,
            alpha_per_mm: 2e3 * a,
            thickness_mm: 5e-4,
            scattering_per_mm: 1e4 * s,
            asymmetry: g,
            coverage: 0.5,
        };
        let cases = [(0.2, 2.0, 0.3, 0.0), (1.0, 1.0, 0.5, 0.01), (3.0, 0.3, 0.7, 0.02)];
        let media: Vec<_> = cases.iter().map(|&(a, s, g, dn)| sand_with(1.0, dn, coating(a, s, g, dn))).collect();
        let g = HeroGroup::new(media.clone(), Memory::None).unwrap();
        let dir = incident_direction(0.6);
        let n = 30_000;
        let c =
            spectral_directional_hemispherical(&g, dir, Rays { seed: 6, stream: 1, first: 0, n }, &Limits::default());
        for (j, m) in media.iter().enumerate() {
            let s1 = c.escaped[j] as f64 / FIXED_ONE;
            let k = j * media.len() - j * (j.saturating_sub(1)) / 2;
            let s2 = c.products[k] as f64 / (FIXED_ONE * FIXED_ONE);
            let (rho, var) = (s1 / n as f64, (s2 / n as f64 - (s1 / n as f64).powi(2)) / (n - 1) as f64);
            let classic =
                directional_hemispherical(m, dir, Rays { seed: 6, stream: 0, first: 0, n }, &Limits::default());
            let mono = classic.escaped as f64 / n as f64;
            let se = (var + mono * (1.0 - mono) / n as f64).sqrt();
            assert!((rho - mono).abs() < 4.0 * se, "case {j}: shared {rho} vs {mono} ± {se}");
        }
    }

    #[test]
    fn shared_estimates_agree_with_independent_runs_through_volume_scatterers() {
        // The fines of `packed_sand` as volume scatterers whose extinction, albedo and phase
        // function differ by wavelength (null, scatter and absorb weights and the phase ratio
        // f_j(μ)/f_h(μ)): each shared estimate within 4 standard errors of its own run, with
        // the classic and the packed tracer.
        let cases = [(0.9, 0.95, 0.2), (0.5, 0.7, 0.6), (0.2, 0.4, 0.85)];
        let media: Vec<_> = cases
            .iter()
            .map(|&(ext, albedo, g)| {
                let fines = scatterer(3.0, henyey_greenstein(ext, albedo, g));
                packed_sand(1.0, 0.0).with_volume_scatterers(vec![None, Some(fines)]).unwrap()
            })
            .collect();
        let dir = incident_direction(0.4);
        for memory in [Memory::None, Memory::Packed] {
            let g = HeroGroup::new(media.clone(), memory).unwrap();
            let own: Vec<_> = media.iter().map(|m| WithMemory::new(m.clone(), memory)).collect();
            assert_agrees_with_own_runs(
                &g,
                &own,
                dir,
                Rays { seed: 9, stream: 1, first: 0, n: 20_000 },
                &format!("{memory:?}"),
            );
        }
        // Media whose volume scatterers differ in their majorant are no group.
        let other = packed_sand(1.0, 0.0)
            .with_volume_scatterers(vec![None, Some(scatterer(2.0, henyey_greenstein(0.5, 0.5, 0.5)))])
            .unwrap();
        assert!(HeroGroup::new(vec![media[0].clone(), other], Memory::None).is_err());
    }

    #[test]
    fn shared_estimates_agree_with_independent_runs_through_every_path_memory() {
        // The memory tracers make the same kinds of choice through `Companions` (water surfaces,
        // survivals in water and cores, stacks): each shared estimate within 4 standard errors
        // of its own run of the memory tracer, with absorption differing by a factor 12 and
        // indices by 0.02.
        let cases = [(0.25, 0.0), (1.0, 0.01), (3.0, 0.02)];
        let dir = incident_direction(0.4);
        let rays = Rays { seed: 8, stream: 1, first: 0, n: 20_000 };
        for memory in [Memory::Channel, Memory::Cut, Memory::Packed] {
            let media: Vec<_> = cases.iter().map(|&(a, dn)| packed_sand(a, dn)).collect();
            let g = HeroGroup::new(media.clone(), memory).unwrap();
            let own: Vec<_> = media.into_iter().map(|m| WithMemory::new(m, memory)).collect();
            assert_agrees_with_own_runs(&g, &own, dir, rays, &format!("{memory:?}"));
        }
    }

    #[test]
    fn shared_estimates_agree_with_independent_runs_through_an_explicit_packing() {
        // The explicit tracer makes the choices of the memory tracers through `Companions`
        // (water surfaces, survivals in water and cores, stacks of packed grains and of fines):
        // each shared estimate within 4 standard errors of its own explicit run, absorption
        // differing by a factor 12 and indices by 0.02, through one packing.
        let scene = packed_scene(1);
        let own: Vec<_> = [(0.25, 0.0), (1.0, 0.01), (3.0, 0.02)].map(|(a, dn)| explicit_sand(&scene, a, dn)).into();
        let g = HeroGroup::explicit(own.clone()).unwrap();
        assert_agrees_with_own_runs(
            &g,
            &own,
            incident_direction(0.4),
            Rays { seed: 8, stream: 1, first: 0, n: 10_000 },
            "explicit",
        );
    }

    #[test]
    fn a_group_of_one_wavelength_traces_the_paths_of_its_memory_or_packing() {
        let m = packed_sand(1.0, 0.0);
        let dir = incident_direction(0.5);
        for memory in [Memory::Channel, Memory::Cut, Memory::Packed] {
            let g = HeroGroup::new(vec![m.clone()], memory).unwrap();
            assert_traces_as(&g, &WithMemory::new(m.clone(), memory), dir, &format!("{memory:?}"));
        }
        let own = explicit_sand(&packed_scene(1), 1.0, 0.0);
        assert_traces_as(&HeroGroup::explicit(vec![own.clone()]).unwrap(), &own, dir, "explicit");
    }

    #[test]
    fn shared_tallies_do_not_depend_on_threads_or_batches() {
        let cases = [(0.5, 0.0), (2.0, 0.01), (4.0, 0.02)];
        let media = cases.map(|(a, dn)| packed_sand(a, dn));
        let scene = packed_scene(1);
        let groups = [
            ("classic", HeroGroup::new(media.to_vec(), Memory::None).unwrap()),
            ("packed", HeroGroup::new(media.to_vec(), Memory::Packed).unwrap()),
            ("explicit", HeroGroup::explicit(cases.map(|(a, dn)| explicit_sand(&scene, a, dn)).into()).unwrap()),
        ];
        for (label, g) in groups {
            let dir = incident_direction(0.7);
            let run = |first, n| {
                spectral_directional_hemispherical(&g, dir, Rays { seed: 9, stream: 2, first, n }, &Limits::default())
            };
            let one = on_threads(1, || run(0, 3000));
            for threads in [2, 3] {
                assert_eq!(on_threads(threads, || run(0, 3000)), one, "{label}, {threads} threads");
            }
            let batches = on_threads(2, || run(0, 1000).merge(run(1000, 1)).merge(run(1001, 1999)));
            assert_eq!(batches, one, "{label}");
            assert!(one.escaped.iter().all(|&e| e > 0));
        }
    }

    #[test]
    fn media_of_other_geometry_are_refused() {
        let mut other = sand(1.0, 0.0);
        other.depth_mm = 3.0;
        assert!(HeroGroup::new(vec![sand(1.0, 0.0), other], Memory::None).is_err());
        assert!(HeroGroup::new(vec![], Memory::None).is_err());
        // Explicit samples: through one scene (the same `Arc`) with one bottom only.
        let (scene, again) = (packed_scene(1), packed_scene(1));
        let sample = explicit_sand(&scene, 1.0, 0.0);
        let slab = Explicit::new(packed_sand(2.0, 0.0), scene.clone(), 2.0).unwrap();
        assert!(HeroGroup::explicit(vec![sample.clone(), explicit_sand(&scene, 2.0, 0.0)]).is_ok());
        assert!(HeroGroup::explicit(vec![sample.clone(), explicit_sand(&again, 2.0, 0.0)]).is_err());
        assert!(HeroGroup::explicit(vec![sample, slab]).is_err());
        assert!(HeroGroup::explicit(vec![]).is_err());
    }
}

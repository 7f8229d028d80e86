//! Random dense packings of a sample's own particles: the geometry of the explicit reference
//! tracer (`explicit`, docs/geometry.md).
//!
//! What is packed: the populations of the sample as they fill its volume (`populations`),
//! fines left on the fly.
//!
//! Algorithm: collective rearrangement at fixed size (a gradient descent on the harmonic
//! overlap energy Σ max(0, σᵢⱼ − rᵢⱼ)², O'Hern et al. 2003, "Jamming at zero temperature and
//! zero applied stress"). Particles of the final sizes start at uniformly random positions in
//! a box periodic in x, y and z at the target packing fraction η; each sweep moves every
//! overlapping pair apart along its centre line by a share of the overlap (the lighter particle
//! moving more), until the largest overlap is below `overlap_tolerance` × the smaller diameter.
//! Below the jamming fraction of such quenches (η_J ≈ 0.64 for monodisperse spheres, higher
//! for polydisperse ones and for spheroids of ε ≈ 1.4, Donev et al. 2004) the energy reaches
//! zero, so η = 0.60 is reached exactly; random sequential addition stalls near 0.38.
//!
//! Spheroids: the contact distance of a pair is the sum of the two radial distances along
//! the centre line, σᵢⱼ = ρᵢ(n) + ρⱼ(n), ρ(n) = 1/√(1/a² + (1/c² − 1/a²)(n·u)²). This is
//! exact for spheres and necessary (not sufficient) for spheroids: two spheroids can still
//! overlap off the centre line. That residual overlap is measured by `overlap_volume_fraction`
//! (point sampling) and reported; for ε = 1.4 it is of order 1 % of the solid volume.

use crate::error::SandlightError;
use crate::math::Vec3;
use crate::medium::Particulate;
use crate::populations::{Populations, FINES_BELOW_MM};
use crate::rng::Rng;
use crate::spheroid::{equatorial_ratio, Spheroid};

/// One packed particle: a prolate spheroid (a sphere for ε = 1).
#[derive(Clone, Copy, Debug)]
pub struct PackedParticle {
    /// Centre (mm), inside the periodic box.
    pub centre: Vec3,
    /// Unit symmetry axis.
    pub axis: Vec3,
    /// Volume-equivalent diameter (mm).
    pub diameter_mm: f64,
    /// Index of the particle type in the `Particulate`.
    pub type_index: usize,
}

impl PackedParticle {
    /// A grain drawn by number from `populations` (`Populations::draw_by_number`) with a
    /// uniformly random orientation; the centre is left at the origin.
    pub fn draw(populations: &Populations, rng: &mut Rng) -> PackedParticle {
        let (type_index, diameter_mm) = populations.draw_by_number(rng);
        PackedParticle { centre: Vec3::default(), axis: Spheroid::random_axis(rng), diameter_mm, type_index }
    }
}

/// How to build a packing.
#[derive(Clone, Copy, Debug)]
pub struct PackingParams {
    /// Side of the box in x and y (mm).
    pub lateral_mm: f64,
    /// Height of the periodic box (mm): the period of the packing in z.
    pub depth_mm: f64,
    /// Types whose area-weighted median size is below this (mm) stay on the fly.
    pub fines_below_mm: f64,
    pub seed: u64,
    /// Refuse boxes that would hold more packed particles than this.
    pub max_particles: usize,
    pub max_sweeps: usize,
    /// Largest accepted overlap along a centre line, as a fraction of the smaller diameter.
    pub overlap_tolerance: f64,
}

impl Default for PackingParams {
    fn default() -> Self {
        PackingParams {
            lateral_mm: 3.0,
            depth_mm: 10.0,
            fines_below_mm: FINES_BELOW_MM,
            seed: 0,
            max_particles: 400_000,
            max_sweeps: 20_000,
            overlap_tolerance: 1e-3,
        }
    }
}

/// Radial distance from the centre to the surface of spheroid (a, c, axis u) along unit n.
#[inline]
pub fn radial_distance(a: f64, c: f64, u: Vec3, n: Vec3) -> f64 {
    let mu = n.dot(u);
    1.0 / (1.0 / (a * a) + (1.0 / (c * c) - 1.0 / (a * a)) * mu * mu).sqrt()
}

/// A periodic random dense packing (module docs).
#[derive(Clone, Debug)]
pub struct Packing {
    pub particles: Vec<PackedParticle>,
    /// Aspect ratio per type (for the shapes).
    pub aspect_ratios: Vec<f64>,
    /// Box periods (L, L, H) in mm.
    pub period: Vec3,
    pub populations: Populations,
    /// Σ particle volumes / box volume (the packed types only).
    pub packing_fraction: f64,
    /// Largest overlap along a centre line after relaxation, over the smaller diameter.
    pub max_overlap: f64,
    pub sweeps: usize,
}

impl Packing {
    /// The spheroid of particle `k` (centred at the origin).
    #[inline]
    pub fn shape(&self, k: usize) -> Spheroid {
        let p = &self.particles[k];
        Spheroid::new(p.diameter_mm, self.aspect_ratios[p.type_index], p.axis)
    }

    /// Largest half-extent (polar semi-axis c) over all particles (mm).
    pub fn max_extent_mm(&self) -> f64 {
        self.particles
            .iter()
            .map(|p| 0.5 * p.diameter_mm * self.aspect_ratios[p.type_index].powf(2.0 / 3.0))
            .fold(0.0, f64::max)
    }

    /// Packs the non-fine particles of `medium` at their share of the volume (module docs).
    pub fn generate(medium: &Particulate, params: &PackingParams) -> Result<Packing, SandlightError> {
        let pops = Populations::of(medium, params.fines_below_mm);
        if !pops.packed.iter().any(|&p| p) {
            return Err(SandlightError::parameter(
                "fines_below_mm",
                params.fines_below_mm,
                "must leave at least one particle type to pack (a median size at or above it)",
            ));
        }
        let eta = pops.packed_fraction();
        if !(0.05..=0.66).contains(&eta) {
            return Err(SandlightError::parameter(
                "porosity",
                pops.porosity,
                "packed solids must fill 5 %–66 % of the volume for the packing generator",
            ));
        }
        let aspect: Vec<f64> = medium.types.iter().map(|t| t.aspect_ratio).collect();
        let mut rng = Rng::for_ray(params.seed, 0x9ac1_u64, 0);
        let box_volume = params.lateral_mm * params.lateral_mm * params.depth_mm;
        let target = eta * box_volume;
        let mut particles = Vec::new();
        let mut solid = 0.0;
        // Draw particles until their volume reaches η V; the box height is then rescaled so that
        // the packing fraction is η exactly (a change of < one particle volume / L²).
        while solid < target {
            if particles.len() >= params.max_particles {
                return Err(SandlightError::parameter(
                    "max_particles",
                    params.max_particles,
                    &format!(
                        "the box needs more packed particles; use a smaller box (lateral_mm {}, depth_mm {})",
                        params.lateral_mm, params.depth_mm
                    ),
                ));
            }
            let grain = PackedParticle::draw(&pops, &mut rng);
            let d = grain.diameter_mm;
            solid += std::f64::consts::PI / 6.0 * d * d * d;
            particles.push(grain);
        }
        // The box must hold at least three of the largest grains drawn across.
        let max_c =
            particles.iter().map(|p| 0.5 * p.diameter_mm * aspect[p.type_index].powf(2.0 / 3.0)).fold(0.0, f64::max);
        if !(params.lateral_mm >= 6.0 * max_c && params.depth_mm >= 6.0 * max_c) {
            return Err(SandlightError::parameter(
                "lateral_mm/depth_mm",
                format!("{}/{}", params.lateral_mm, params.depth_mm),
                &format!("both must be at least three of the largest grains drawn across ({:.4} mm)", 6.0 * max_c),
            ));
        }
        let depth = solid / (eta * params.lateral_mm * params.lateral_mm);
        let period = Vec3::new(params.lateral_mm, params.lateral_mm, depth);
        for p in particles.iter_mut() {
            p.centre = Vec3::new(rng.uniform() * period.x, rng.uniform() * period.y, rng.uniform() * period.z);
        }
        let mut packing = Packing {
            particles,
            aspect_ratios: aspect,
            period,
            populations: pops,
            packing_fraction: solid / (period.x * period.y * period.z),
            max_overlap: f64::INFINITY,
            sweeps: 0,
        };
        packing.relax(params.max_sweeps, params.overlap_tolerance);
        if packing.max_overlap > params.overlap_tolerance {
            return Err(SandlightError::parameter("porosity", packing.populations.porosity, &format!("overlaps did not relax below {} within {} sweeps (largest {:.3e}); the packing fraction {:.3} may be beyond jamming", params.overlap_tolerance, params.max_sweeps, packing.max_overlap, packing.packing_fraction)));
        }
        Ok(packing)
    }

    /// Minimum-image separation b − a in the periodic box.
    #[inline]
    pub fn min_image(&self, a: Vec3, b: Vec3) -> Vec3 {
        let w = |d: f64, l: f64| d - l * (d / l).round();
        Vec3::new(w(b.x - a.x, self.period.x), w(b.y - a.y, self.period.y), w(b.z - a.z, self.period.z))
    }

    /// Collective rearrangement sweeps (module docs) until the largest relative overlap is
    /// below `tolerance`.
    fn relax(&mut self, max_sweeps: usize, tolerance: f64) {
        let n = self.particles.len();
        let semi: Vec<(f64, f64)> = self
            .particles
            .iter()
            .map(|p| {
                let eps = self.aspect_ratios[p.type_index];
                let a = p.diameter_mm * equatorial_ratio(eps);
                (a, eps * a)
            })
            .collect();
        let mean_d = self.particles.iter().map(|p| p.diameter_mm).sum::<f64>() / n as f64;
        let reach: Vec<f64> = semi.iter().map(|s| s.1).collect();
        let mut disp = vec![Vec3::default(); n];
        let mut list = CellList::new(self.period, mean_d, n);
        let mut centres: Vec<Vec3> = self.particles.iter().map(|p| p.centre).collect();
        for sweep in 0..max_sweeps {
            list.fill(centres.iter().copied());
            disp.iter_mut().for_each(|d| *d = Vec3::default());
            let mut worst = 0.0f64;
            list.for_each_pair(&centres, &reach, |i, j| {
                let (pi, pj) = (&self.particles[i], &self.particles[j]);
                let r = self.min_image(pi.centre, pj.centre);
                let dist2 = r.norm2();
                let reach = semi[i].1 + semi[j].1;
                if dist2 >= reach * reach {
                    return;
                }
                let dist = dist2.sqrt().max(1e-12);
                let nrm = r * (1.0 / dist);
                let sigma = radial_distance(semi[i].0, semi[i].1, pi.axis, nrm)
                    + radial_distance(semi[j].0, semi[j].1, pj.axis, nrm);
                let ov = sigma - dist;
                if ov <= 0.0 {
                    return;
                }
                worst = worst.max(ov / pi.diameter_mm.min(pj.diameter_mm));
                // Volume-weighted: the smaller particle moves more. Half of the overlap per
                // sweep and pair keeps the simultaneous (Jacobi) update from overshooting when
                // a particle has several contacts; a 5 % excess makes overlaps vanish rather
                // than decay geometrically.
                let (vi, vj) = (pi.diameter_mm.powi(3), pj.diameter_mm.powi(3));
                let step = 0.8 * ov / (vi + vj);
                disp[i] = disp[i] - nrm * (step * vj);
                disp[j] = disp[j] + nrm * (step * vi);
            });
            self.max_overlap = worst;
            self.sweeps = sweep;
            if worst <= tolerance {
                return;
            }
            let per = self.period;
            let wrap = |v: f64, l: f64| {
                let w = v.rem_euclid(l);
                if w >= l {
                    0.0
                } else {
                    w
                }
            };
            for ((p, d), c) in self.particles.iter_mut().zip(&disp).zip(centres.iter_mut()) {
                let x = p.centre + *d;
                p.centre = Vec3::new(wrap(x.x, per.x), wrap(x.y, per.y), wrap(x.z, per.z));
                *c = p.centre;
            }
        }
    }

    /// Fraction of `n_points` random points inside no particle (the porosity of the packed
    /// grains alone) and inside two or more (overlap), by exact point-in-spheroid tests.
    pub fn point_statistics(&self, n_points: usize, seed: u64) -> (f64, f64) {
        let max_c = self.max_extent_mm();
        let mean_d = self.particles.iter().map(|p| p.diameter_mm).sum::<f64>() / self.particles.len() as f64;
        let mut list = CellList::new(self.period, mean_d, self.particles.len());
        list.fill(self.particles.iter().map(|p| p.centre));
        let shapes: Vec<Spheroid> = (0..self.particles.len()).map(|k| self.shape(k)).collect();
        let mut rng = Rng::for_ray(seed, 0x9ac2, 0);
        let (mut empty, mut multiple) = (0usize, 0usize);
        for _ in 0..n_points {
            let x =
                Vec3::new(rng.uniform() * self.period.x, rng.uniform() * self.period.y, rng.uniform() * self.period.z);
            let mut inside = 0;
            list.for_each_near(x, max_c, |k| {
                let r = self.min_image(self.particles[k].centre, x);
                if shapes[k].contains(r) {
                    inside += 1;
                }
            });
            empty += (inside == 0) as usize;
            multiple += (inside >= 2) as usize;
        }
        (empty as f64 / n_points as f64, multiple as f64 / n_points as f64)
    }
}

/// A periodic cell list; pairs and neighbourhoods are searched over as many cells as a
/// particle's reach needs, so cells can be about one typical grain wide even when a few grains
/// are much larger.
struct CellList {
    n: [usize; 3],
    h: [f64; 3],
    start: Vec<usize>,
    items: Vec<usize>,
    cell_of: Vec<usize>,
}

impl CellList {
    fn new(period: Vec3, cell: f64, particles: usize) -> CellList {
        let l = [period.x, period.y, period.z];
        let n = l.map(|l| ((l / cell).floor() as usize).max(1));
        let h = std::array::from_fn(|a| l[a] / n[a] as f64);
        CellList {
            n,
            h,
            start: vec![0; n[0] * n[1] * n[2] + 1],
            items: vec![0; particles],
            cell_of: vec![0; particles],
        }
    }

    #[inline]
    fn coords(&self, x: Vec3) -> [usize; 3] {
        let xa = [x.x, x.y, x.z];
        std::array::from_fn(|a| ((xa[a] / self.h[a]) as usize).min(self.n[a] - 1))
    }

    #[inline]
    fn index(&self, c: [usize; 3]) -> usize {
        (c[2] * self.n[1] + c[1]) * self.n[0] + c[0]
    }

    /// Counting sort of the particles (centres inside the box) into cells.
    fn fill(&mut self, centres: impl Iterator<Item = Vec3>) {
        self.start.iter_mut().for_each(|s| *s = 0);
        for (k, x) in centres.enumerate() {
            let c = self.index(self.coords(x));
            self.cell_of[k] = c;
            self.start[c + 1] += 1;
        }
        for i in 1..self.start.len() {
            self.start[i] += self.start[i - 1];
        }
        let mut next = self.start.clone();
        for (k, &c) in self.cell_of.iter().enumerate() {
            self.items[next[c]] = k;
            next[c] += 1;
        }
    }

    /// Calls `f(k)` for every particle in the cells within `reach` of the cell of `x`
    /// (each cell once, also when the reach wraps around the box).
    fn for_each_near(&self, x: Vec3, reach: f64, mut f: impl FnMut(usize)) {
        let xa = [x.x, x.y, x.z];
        // Unwrapped index ranges of the cells meeting [x − reach, x + reach] per axis.
        let range = |a: usize| -> std::ops::RangeInclusive<i64> {
            let lo = ((xa[a] - reach) / self.h[a]).floor() as i64;
            let hi = ((xa[a] + reach) / self.h[a]).floor() as i64;
            if hi - lo + 1 >= self.n[a] as i64 {
                0..=self.n[a] as i64 - 1
            } else {
                lo..=hi
            }
        };
        for cz in range(2) {
            for cy in range(1) {
                for cx in range(0) {
                    let c = [cx, cy, cz];
                    let w: [usize; 3] = std::array::from_fn(|a| c[a].rem_euclid(self.n[a] as i64) as usize);
                    let o = self.index(w);
                    self.items[self.start[o]..self.start[o + 1]].iter().for_each(|&k| f(k));
                }
            }
        }
    }

    /// Calls `f(i, j)` once for every pair whose centres may lie within `reach[i] + reach[j]`:
    /// from the particle of larger reach (ties by index), searching 2·its reach.
    fn for_each_pair(&self, centres: &[Vec3], reach: &[f64], mut f: impl FnMut(usize, usize)) {
        for (i, &x) in centres.iter().enumerate() {
            let ri = reach[i];
            self.for_each_near(x, 2.0 * ri, |j| {
                if reach[j] < ri || (reach[j] == ri && j < i) {
                    f(i, j);
                }
            });
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::medium::ParticleType;
    use crate::particle::{ParticleOptics, PoreOptics};
    use crate::sizes::QuantileTable;
    use crate::spheroid::surface_factor;

    fn spheres(d: f64, porosity: f64, eps: f64) -> Particulate {
        let optics = ParticleOptics::clear(1.544);
        let t = ParticleType { probability: 1.0, sizes: QuantileTable::constant(d), aspect_ratio: eps, optics };
        // ℓ = 4φ/[(1 − φ) 6 f(ε)/d] (docs/model.md §2.1).
        let ell = 4.0 * porosity / ((1.0 - porosity) * 6.0 * surface_factor(eps) / d);
        Particulate::new(vec![t], ell, PoreOptics::DRY, f64::INFINITY).unwrap()
    }

    #[test]
    fn monodisperse_spheres_reach_0_60_without_overlap() {
        let m = spheres(0.25, 0.40, 1.0);
        let params = PackingParams { lateral_mm: 1.5, depth_mm: 1.5, ..Default::default() };
        let pk = Packing::generate(&m, &params).unwrap();
        assert!((pk.packing_fraction - 0.60).abs() < 1e-9);
        // Exact overlap check over all pairs (spheres).
        let mut worst = 0.0f64;
        for i in 0..pk.particles.len() {
            for j in i + 1..pk.particles.len() {
                let r = pk.min_image(pk.particles[i].centre, pk.particles[j].centre).norm2().sqrt();
                worst = worst.max((0.25 - r) / 0.25);
            }
        }
        assert!(worst <= params.overlap_tolerance, "overlap {worst}");
        let (empty, _) = pk.point_statistics(200_000, 1);
        assert!((empty - 0.40).abs() < 0.01, "point porosity {empty}");
    }

    #[test]
    fn spheroids_of_aspect_1_4_pack_at_0_60_with_small_true_overlap() {
        let m = spheres(0.25, 0.40, 1.4);
        let params = PackingParams { lateral_mm: 1.5, depth_mm: 1.5, seed: 3, ..Default::default() };
        let pk = Packing::generate(&m, &params).unwrap();
        let (empty, multiple) = pk.point_statistics(200_000, 2);
        eprintln!("spheroids: sweeps {} empty {empty} multiple {multiple}", pk.sweeps);
        assert!((empty - 0.40).abs() < 0.01, "point porosity {empty}");
        assert!(multiple < 0.01, "overlap volume fraction {multiple}");
    }
}

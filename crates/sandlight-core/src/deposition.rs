//! The gravity-settled surface of the explicit reference (docs/geometry.md): grains of the
//! packing's own populations deposited one at a time on its cut surface.
//!
//! Algorithm: Visscher & Bolsterli 1972, "Random packing of equal and unequal spheres in two
//! and three dimensions", Nature 239, 504. Each grain is dropped at a uniformly random (x, y)
//! above the surface, falls vertically until it touches a grain, rolls down on it keeping the
//! contact until it touches a second, rolls in the groove of the two keeping both until it
//! touches a third, and rests there if the vertical through its centre passes inside the
//! triangle of the three contacts; otherwise it rolls on over the edge of that triangle, and
//! every further contact is judged the same way.
//!
//! Here all of these steps are one rule: the quasi-static motion of a frictionless grain under
//! gravity with one-sided contacts. Its velocity is the projection of −ẑ onto the directions
//! that enter no contact, v = −ẑ + Σ_B fᵢ nᵢ with forces fᵢ ≥ 0 and v·nᵢ = 0 on the contacts B
//! that carry load and v·nⱼ ≥ 0 on the others (nᵢ the unit normal from contact i towards the
//! grain's centre). With no loaded contact the grain falls; with one it rolls down the meridian
//! of that grain; with two along the circle of centres that keeps both (the groove), until one
//! of the two forces vanishes; with three v = 0 and it rests, gravity balanced by non-negative
//! forces — for contacts below the centre exactly the triangle rule. A grain can also come to
//! rest on two contacts, at the lowest point of a groove whose forces stay positive (wedged
//! under an overhanging grain). Every path is a line or a circle, so the next contact is the
//! root of a quadratic or of C₀ + A cos φ + B sin φ = 0: grains move exactly from event to
//! event, with no time step.
//!
//! Obstacles: the cut surface (every grain of the periodic packing whose centre lies below the
//! cut plane z = H, with its images in x and y) and the grains deposited before, periodic in x
//! and y. Grains are drawn as the packing generator draws them (`PackedParticle::draw`).
//! Spheroids move and touch as their volume-equivalent spheres, the bulk ones included; their
//! true shapes then overlap their neighbours or leave gaps on the scale of c − a, which is
//! measured by point sampling (`explicit::Scene::porosity_profile`) and reported.
//!
//! Grains are added until their volume reaches the bulk packing fraction times L² times the
//! requested thickness (the solid of that many millimetres of bulk packing).

use std::f64::consts::{PI, TAU};

use crate::error::SandlightError;
use crate::math::Vec3;
use crate::packing::{PackedParticle, Packing};
use crate::rng::Rng;

const UP: Vec3 = Vec3::new(0.0, 0.0, 1.0);

/// Gaps below this fraction of the moving grain's radius are contacts.
const CONTACT_GAP: f64 = 1e-9;
/// Tolerance on contact forces and on v·n (dimensionless) when the motion is chosen: rounding
/// of ~1e-16 must not turn a grazing contact into a blocking one.
const FORCE_TOL: f64 = 1e-10;
/// |v| below this is rest (a groove within 1e-9 rad of level).
const REST_SPEED: f64 = 1e-9;
/// Moves (falls, rolls on one grain, rolls in a groove) after which a grain counts as stuck.
const MAX_MOVES: usize = 10_000;

/// An obstacle image near the moving grain: which grain and image, its centre, and the
/// contact distance (sum of the radii).
#[derive(Clone, Copy, Debug)]
struct Contact {
    id: (usize, i64, i64),
    c: Vec3,
    s: f64,
}

/// The grains a falling grain can touch, listed by column (x, y cells), periodic in x and y
/// and unbounded in z.
struct Heap {
    n: [usize; 2],
    h: [f64; 2],
    l: [f64; 2],
    cells: Vec<Vec<usize>>,
    centres: Vec<Vec3>,
    radii: Vec<f64>,
    max_radius: f64,
    /// Highest grain top (mm).
    top: f64,
}

impl Heap {
    fn new(lx: f64, ly: f64, cell: f64) -> Heap {
        let l = [lx, ly];
        let n = l.map(|l| ((l / cell).floor() as usize).max(1));
        let h = std::array::from_fn(|a| l[a] / n[a] as f64);
        Heap {
            n,
            h,
            l,
            cells: vec![Vec::new(); n[0] * n[1]],
            centres: Vec::new(),
            radii: Vec::new(),
            max_radius: 0.0,
            top: f64::NEG_INFINITY,
        }
    }

    /// Adds a grain (centre with x, y inside the period).
    fn push(&mut self, c: Vec3, r: f64) {
        let ix = ((c.x / self.h[0]) as usize).min(self.n[0] - 1);
        let iy = ((c.y / self.h[1]) as usize).min(self.n[1] - 1);
        self.cells[iy * self.n[0] + ix].push(self.centres.len());
        self.centres.push(c);
        self.radii.push(r);
        self.max_radius = self.max_radius.max(r);
        self.top = self.top.max(c.z + r);
    }

    /// Every image of a grain whose centre lies within horizontal distance `reach` of `x` and
    /// at a height in [`zlo`, `zhi`], as seen by a moving grain of radius `r`.
    fn near(&self, x: Vec3, reach: f64, zlo: f64, zhi: f64, r: f64) -> Vec<Contact> {
        let mut out = Vec::new();
        let xa = [x.x, x.y];
        let range =
            |a: usize| ((xa[a] - reach) / self.h[a]).floor() as i64..=((xa[a] + reach) / self.h[a]).floor() as i64;
        for cy in range(1) {
            for cx in range(0) {
                let (wx, bx) = (cx.rem_euclid(self.n[0] as i64) as usize, cx.div_euclid(self.n[0] as i64));
                let (wy, by) = (cy.rem_euclid(self.n[1] as i64) as usize, cy.div_euclid(self.n[1] as i64));
                for &k in &self.cells[wy * self.n[0] + wx] {
                    let c0 = self.centres[k];
                    let c = Vec3::new(c0.x + bx as f64 * self.l[0], c0.y + by as f64 * self.l[1], c0.z);
                    let (dx, dy) = (c.x - x.x, c.y - x.y);
                    if c.z >= zlo && c.z <= zhi && dx * dx + dy * dy <= reach * reach {
                        out.push(Contact { id: (k, bx, by), c, s: r + self.radii[k] });
                    }
                }
            }
        }
        out
    }

    /// The grains touching a grain of radius `r` at `x`.
    fn touching(&self, x: Vec3, r: f64) -> Vec<Contact> {
        let reach = r + self.max_radius;
        let gap = CONTACT_GAP * r;
        let mut t = self.near(x, reach + gap, x.z - reach - gap, x.z + reach + gap, r);
        t.retain(|k| (x - k.c).norm2().sqrt() - k.s <= gap);
        t
    }

    /// Where a grain of radius `r` dropped above (x0, y0) comes to rest (module docs).
    fn settle(&self, x0: f64, y0: f64, r: f64, rng: &mut Rng) -> Result<Vec3, SandlightError> {
        let mut x = Vec3::new(x0, y0, self.top + 2.0 * r);
        for _ in 0..MAX_MOVES {
            let touching = self.touching(x, r);
            let (path, loaded) = match motion(x, &touching) {
                Some(Motion::Rest) => return Ok(x),
                Some(Motion::Fall) => (Path::Line { x0: x }, vec![]),
                Some(Motion::Roll(j)) => (roll_on(x, j, rng), vec![j.id]),
                Some(Motion::Groove(i, j)) => (groove(x, i, j), vec![i.id, j.id]),
                None => return Err(stuck("no consistent motion at a contact")),
            };
            // The first grain the path enters; grains touched now but left behind only count
            // if the path meets them again further on.
            let min_step = CONTACT_GAP * r / path.scale();
            let mut step = path.length();
            for k in self.near_path(&path, r) {
                if loaded.contains(&k.id) {
                    continue;
                }
                let touched = touching.iter().any(|t| t.id == k.id);
                if let Some(e) = path.entry(&k) {
                    if e < step && (!touched || e > min_step) {
                        step = e;
                    }
                }
            }
            if !step.is_finite() {
                return Err(stuck("a grain fell through the pores of the packing"));
            }
            x = path.at(step);
            // Only the top period block of the packing is stored: the grain must stay clear of
            // the images beneath it (centres below z = 0, reaching up to the largest radius).
            if x.z - r < self.max_radius {
                return Err(stuck("a grain sank through the pores to the bottom of the packed box"));
            }
        }
        Err(stuck(&format!("a grain did not come to rest within {MAX_MOVES} moves")))
    }

    /// The grains a grain of radius `r` can meet along `path`.
    fn near_path(&self, path: &Path, r: f64) -> Vec<Contact> {
        let reach = r + self.max_radius;
        match *path {
            Path::Line { x0 } => self.near(x0, reach, f64::NEG_INFINITY, x0.z + reach, r),
            Path::Circle { q, radius, .. } => {
                self.near(q, radius + reach, q.z - radius - reach, q.z + radius + reach, r)
            }
        }
    }
}

fn stuck(what: &str) -> SandlightError {
    SandlightError::parameter(
        "surface",
        "settled",
        &format!("deposition failed: {what}; use a deeper box (depth_mm) or the cut surface"),
    )
}

/// What a grain does next (module docs).
#[derive(Clone, Copy, Debug)]
enum Motion {
    Fall,
    Roll(Contact),
    Groove(Contact, Contact),
    Rest,
}

/// The quasi-static motion of a grain at `x` with the contacts `touching` (module docs): the
/// first set B of loaded contacts, by size, with non-negative forces that leaves every other
/// contact (v·nⱼ ≥ 0). None only if rounding leaves no consistent set.
fn motion(x: Vec3, touching: &[Contact]) -> Option<Motion> {
    let n: Vec<Vec3> = touching.iter().map(|t| (x - t.c).normalized()).collect();
    let leaves_others =
        |v: Vec3, loaded: &[usize]| n.iter().enumerate().all(|(m, nm)| loaded.contains(&m) || v.dot(*nm) >= -FORCE_TOL);
    if leaves_others(-UP, &[]) {
        return Some(Motion::Fall);
    }
    for i in 0..n.len() {
        // One contact: f = nᵢ·ẑ, v = −ẑ + f nᵢ.
        let f = n[i].z;
        if f > FORCE_TOL && leaves_others(n[i] * f - UP, &[i]) {
            return Some(Motion::Roll(touching[i]));
        }
    }
    for i in 0..n.len() {
        for j in i + 1..n.len() {
            // Two contacts: v·nᵢ = v·nⱼ = 0 gives fᵢ + c fⱼ = nᵢ,z and c fᵢ + fⱼ = nⱼ,z, c = nᵢ·nⱼ.
            let c = n[i].dot(n[j]);
            let det = 1.0 - c * c;
            if det < 1e-12 {
                continue;
            }
            let fi = (n[i].z - c * n[j].z) / det;
            let fj = (n[j].z - c * n[i].z) / det;
            let v = n[i] * fi + n[j] * fj - UP;
            if fi >= -FORCE_TOL && fj >= -FORCE_TOL && leaves_others(v, &[i, j]) {
                return Some(if v.norm2() < REST_SPEED * REST_SPEED {
                    Motion::Rest
                } else {
                    Motion::Groove(touching[i], touching[j])
                });
            }
        }
    }
    for i in 0..n.len() {
        for j in i + 1..n.len() {
            for k in j + 1..n.len() {
                // Three contacts: v = 0, ẑ = Σ f n, by Cramer's rule.
                let det = n[i].dot(n[j].cross(n[k]));
                if det.abs() < 1e-12 {
                    continue;
                }
                let f =
                    [UP.dot(n[j].cross(n[k])) / det, UP.dot(n[k].cross(n[i])) / det, UP.dot(n[i].cross(n[j])) / det];
                if f.iter().all(|&f| f >= -FORCE_TOL) {
                    return Some(Motion::Rest);
                }
            }
        }
    }
    None
}

/// A path of the grain's centre: a vertical fall, or an arc φ ∈ [φ_end, φ₀] of the circle
/// q + radius (e₁ cos φ + e₂ sin φ) travelled with decreasing φ. Positions along it are
/// given by the step from the start: a distance for the line, φ₀ − φ for the circle.
#[derive(Clone, Copy, Debug)]
enum Path {
    Line { x0: Vec3 },
    Circle { q: Vec3, radius: f64, e1: Vec3, e2: Vec3, phi0: f64, phi_end: f64 },
}

impl Path {
    fn at(&self, step: f64) -> Vec3 {
        match *self {
            Path::Line { x0 } => x0 - UP * step,
            Path::Circle { q, radius, e1, e2, phi0, .. } => {
                let phi = phi0 - step;
                q + (e1 * phi.cos() + e2 * phi.sin()) * radius
            }
        }
    }

    /// Length of the step unit (mm per unit step).
    fn scale(&self) -> f64 {
        match *self {
            Path::Line { .. } => 1.0,
            Path::Circle { radius, .. } => radius,
        }
    }

    /// The whole step to the end of the path (infinite for a fall).
    fn length(&self) -> f64 {
        match *self {
            Path::Line { .. } => f64::INFINITY,
            Path::Circle { phi0, phi_end, .. } => phi0 - phi_end,
        }
    }

    /// Step at which the grain's centre enters the contact sphere of `k` (|x − c| = s), if
    /// it does ahead of the start.
    fn entry(&self, k: &Contact) -> Option<f64> {
        match *self {
            Path::Line { x0 } => {
                // |p − t ẑ|² = s²: t = p_z ∓ √(s² − p_h²), the smaller root is the entry.
                let p = x0 - k.c;
                let ph2 = p.x * p.x + p.y * p.y;
                if ph2 >= k.s * k.s {
                    return None;
                }
                let t = p.z - (k.s * k.s - ph2).sqrt();
                (t >= 0.0).then_some(t)
            }
            Path::Circle { q, radius, e1, e2, phi0, .. } => {
                // g(φ) = |q − c + radius(e₁ cos φ + e₂ sin φ)|² − s² = C₀ + A cos φ + B sin φ
                // = C₀ + M cos(φ − φₘ). Entering with decreasing φ means dg/dφ > 0: the root
                // φₘ − δ, δ = arccos(−C₀/M), at its largest representative not above φ₀.
                let p = q - k.c;
                let c0 = p.norm2() + radius * radius - k.s * k.s;
                let (a, b) = (2.0 * radius * p.dot(e1), 2.0 * radius * p.dot(e2));
                let m = a.hypot(b);
                if m <= c0.abs() {
                    return None;
                }
                let root = b.atan2(a) - (-c0 / m).acos();
                let phi = root + TAU * ((phi0 - root) / TAU).floor();
                Some(phi0 - phi)
            }
        }
    }
}

/// Rolling down the meridian of contact `j`: the vertical plane through its centre and the
/// grain's, from the grain's elevation angle down to the equator, where it falls free.
fn roll_on(x: Vec3, j: Contact, rng: &mut Rng) -> Path {
    let rel = x - j.c;
    let horizontal = Vec3::new(rel.x, rel.y, 0.0);
    let h = horizontal.norm2().sqrt();
    // Exactly on top (never seen) the grain may roll off in any direction.
    let e1 = if h > 0.0 {
        horizontal * (1.0 / h)
    } else {
        let a = TAU * rng.uniform();
        Vec3::new(a.cos(), a.sin(), 0.0)
    };
    Path::Circle { q: j.c, radius: rel.norm2().sqrt(), e1, e2: UP, phi0: rel.z.atan2(h), phi_end: 0.0 }
}

/// Rolling in the groove of contacts `i` and `j`: the circle of centres at distance sᵢ from cᵢ
/// and sⱼ from cⱼ, around the axis a = (cⱼ − cᵢ)/D, towards its lowest point, or to where one
/// of the two forces vanishes.
///
/// With the circle's centre q, radius R, its lowest direction w (e₁) and r̂ the unit radius at
/// the grain, the plane of a and r̂ holds both normals, nᵢ = (βᵢ a + R r̂)/sᵢ with
/// βᵢ = (q − cᵢ)·a, and gravity's part in it, ẑ·a a + u r̂ with u = ẑ·r̂ = w_z cos φ. Balancing
/// gives the forces fᵢ/sᵢ = (a_z − βⱼ u/R)/D and fⱼ/sⱼ = (βᵢ u/R − a_z)/D: linear in u, which
/// falls monotonically from the start to w_z at the bottom (φ = 0).
fn groove(x: Vec3, i: Contact, j: Contact) -> Path {
    let axis = j.c - i.c;
    let d = axis.norm2().sqrt();
    let a = axis * (1.0 / d);
    let beta_i = (x - i.c).dot(a);
    let q = i.c + a * beta_i;
    let rel = x - q;
    let radius = rel.norm2().sqrt();
    // `motion` only rolls on a groove whose tangent is not level, so a is not vertical.
    let w = (a * a.z - UP).normalized();
    let mut e2 = a.cross(w);
    let mut phi0 = rel.dot(e2).atan2(rel.dot(w));
    if phi0 < 0.0 {
        e2 = -e2;
        phi0 = -phi0;
    }
    let beta_j = beta_i - d;
    let u0 = w.z * phi0.cos();
    let mut phi_end = 0.0f64;
    // A force p + q u that decreases with u reaches zero at u* = −p/q.
    for (p, slope) in [(a.z, -beta_j / radius), (-a.z, beta_i / radius)] {
        if slope > 0.0 {
            let u_star = -p / slope;
            if u_star > w.z && u_star < u0 {
                phi_end = phi_end.max((u_star / w.z).clamp(-1.0, 1.0).acos());
            }
        }
    }
    Path::Circle { q, radius, e1: w, e2, phi0, phi_end }
}

/// Deposits grains of `packing`'s populations on its cut surface (module docs) until their
/// volume is the packing fraction × L² × `thickness_mm`. Returns them with centres at their
/// rest positions (x, y inside the period; z absolute, mostly above the cut plane z = H).
pub fn deposit(packing: &Packing, thickness_mm: f64, seed: u64) -> Result<Vec<PackedParticle>, SandlightError> {
    let per = packing.period;
    if !(thickness_mm > 0.0 && thickness_mm <= per.z) {
        return Err(SandlightError::parameter(
            "settled_thickness_mm",
            thickness_mm,
            &format!("must be > 0 and at most the box height {:.4} mm", per.z),
        ));
    }
    let max_d = packing.particles.iter().map(|p| p.diameter_mm).fold(0.0, f64::max);
    let mut heap = Heap::new(per.x, per.y, max_d);
    for p in &packing.particles {
        heap.push(p.centre, 0.5 * p.diameter_mm);
    }
    let target = packing.packing_fraction * per.x * per.y * thickness_mm;
    let mut rng = Rng::for_ray(seed, 0x9ac4, 0);
    let mut solid = 0.0;
    let mut out = Vec::new();
    while solid < target {
        let mut grain = PackedParticle::draw(&packing.populations, &mut rng);
        let r = 0.5 * grain.diameter_mm;
        let (x0, y0) = (rng.uniform() * per.x, rng.uniform() * per.y);
        let x = heap.settle(x0, y0, r, &mut rng)?;
        // rem_euclid of a tiny negative number rounds to the period itself.
        let wrap = |v: f64, l: f64| {
            let w = v.rem_euclid(l);
            if w >= l {
                0.0
            } else {
                w
            }
        };
        grain.centre = Vec3::new(wrap(x.x, per.x), wrap(x.y, per.y), x.z);
        heap.push(grain.centre, r);
        solid += PI / 6.0 * grain.diameter_mm.powi(3);
        out.push(grain);
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::medium::{ParticleType, Particulate};
    use crate::packing::PackingParams;
    use crate::particle::{ParticleOptics, PoreOptics};
    use crate::sizes::QuantileTable;
    use crate::spheroid::surface_factor;

    fn grains(quantiles: Vec<f64>, eps: f64) -> Particulate {
        let optics = ParticleOptics::clear(1.544);
        let mean_d = quantiles.iter().sum::<f64>() / quantiles.len() as f64;
        let t =
            ParticleType { probability: 1.0, sizes: QuantileTable::new(quantiles).unwrap(), aspect_ratio: eps, optics };
        // φ = 0.4: ℓ = 4φ/[(1 − φ) 6 f(ε)/E[D]].
        Particulate::new(
            vec![t],
            4.0 * 0.4 / (0.6 * 6.0 * surface_factor(eps) / mean_d),
            PoreOptics::DRY,
            f64::INFINITY,
        )
        .unwrap()
    }

    #[test]
    fn sphere_on_a_triangle_of_spheres_rests_at_the_tetrahedron_apex() {
        // Three touching unit spheres; a unit sphere dropped off-centre falls on one, rolls
        // into a groove and stops on all three at height 2√(2/3) above their centres.
        let mut heap = Heap::new(20.0, 20.0, 2.0);
        let z0 = 10.0;
        let centres = [Vec3::new(10.0, 10.0, z0), Vec3::new(12.0, 10.0, z0), Vec3::new(11.0, 10.0 + 3f64.sqrt(), z0)];
        centres.iter().for_each(|&c| heap.push(c, 1.0));
        let centroid = (centres[0] + centres[1] + centres[2]) * (1.0 / 3.0);
        let mut rng = Rng::for_ray(1, 0, 0);
        for (dx, dy) in [(0.3, 0.1), (-0.2, 0.25), (0.05, -0.4)] {
            let x = heap.settle(centroid.x + dx, centroid.y + dy, 1.0, &mut rng).unwrap();
            let apex = centroid + UP * (2.0 * (2.0f64 / 3.0).sqrt());
            assert!((x - apex).norm2().sqrt() < 1e-9, "{x:?} vs {apex:?}");
        }
    }

    #[test]
    fn sphere_dropped_on_a_raised_grain_rolls_off_it() {
        // Dropped over the edge of a single sphere on a wide floor of spheres, the grain must
        // not stop on the sphere: it rolls off and rests lower, on the floor.
        let mut heap = Heap::new(12.0, 12.0, 2.0);
        for i in 0..6 {
            for j in 0..6 {
                heap.push(Vec3::new(1.0 + 2.0 * i as f64, 1.0 + 2.0 * j as f64, 10.0), 1.0);
            }
        }
        heap.push(Vec3::new(6.0, 6.0, 10.0 + 2f64.sqrt()), 1.0);
        let mut rng = Rng::for_ray(2, 0, 0);
        let x = heap.settle(6.3, 6.2, 1.0, &mut rng).unwrap();
        // On the square floor a unit sphere rests in a hollow at 10 + √2 (four contacts) or
        // against the extra sphere, never on top of it (centre above 10 + √2 + 1).
        assert!(x.z < 10.0 + 2f64.sqrt() + 1.0, "{x:?}");
        let touching = heap.touching(x, 1.0);
        assert!(touching.len() >= 3, "{touching:?}");
    }

    #[test]
    fn a_groove_ends_where_a_contact_force_vanishes() {
        // Forces along the groove from the 2 × 2 balance of `motion`, at the end of the path.
        let forces = |x: Vec3, ci: Vec3, cj: Vec3| {
            let (ni, nj) = ((x - ci).normalized(), (x - cj).normalized());
            let c = ni.dot(nj);
            ((ni.z - c * nj.z) / (1.0 - c * c), (nj.z - c * ni.z) / (1.0 - c * c))
        };
        let contact = |c: Vec3| Contact { id: (0, 0, 0), c, s: 2.0 };
        // Level pair: both forces vanish together when the centre is level with the axis.
        let (ci, cj) = (Vec3::new(0.0, 0.0, 0.0), Vec3::new(2.0, 0.0, 0.0));
        let x = Vec3::new(1.0, 0.3, (4.0f64 - 1.0 - 0.09).sqrt());
        let p = groove(x, contact(ci), contact(cj));
        let end = p.at(p.length());
        assert!(end.z.abs() < 1e-12 && ((end - ci).norm2() - 4.0).abs() < 1e-12, "{end:?}");
        // Tilted pair: the path stops where one force is zero and the other positive.
        let cj = Vec3::new(2.0, 0.0, 0.8);
        let axis = (cj - ci).normalized();
        let q = ci + axis * 1.1;
        let radius = (4.0f64 - 1.21).sqrt();
        // Near the top of the groove circle: 0.4 rad from its highest direction −w.
        let w = (axis * axis.z - UP).normalized();
        let x = q + (w * -0.4f64.cos() + axis.cross(w) * 0.4f64.sin()) * radius;
        let p = groove(x, contact(ci), contact(cj));
        let (fi, fj) = forces(x, ci, cj);
        assert!(fi > 0.0 && fj > 0.0, "{fi} {fj}");
        let end = p.at(p.length());
        let (fi, fj) = forces(end, ci, cj);
        assert!(fi.min(fj).abs() < 1e-12 && fi.max(fj) > 0.0 && end.z < x.z, "{fi} {fj} {end:?}");
    }

    /// Deposits on a small packing and checks every deposited sphere: no overlap with any
    /// image of the cut surface or of another deposited grain beyond 1e-6 d, and at rest.
    fn check_settled(quantiles: Vec<f64>, seed: u64) -> (usize, usize) {
        let m = grains(quantiles, 1.0);
        let pk = Packing::generate(&m, &PackingParams { lateral_mm: 1.5, depth_mm: 1.5, seed, ..Default::default() })
            .unwrap();
        let thickness = 0.5;
        let dep = deposit(&pk, thickness, seed).unwrap();
        let per = pk.period;
        let solid: f64 = dep.iter().map(|g| PI / 6.0 * g.diameter_mm.powi(3)).sum();
        let target = pk.packing_fraction * per.x * per.y * thickness;
        let last = PI / 6.0 * dep.last().unwrap().diameter_mm.powi(3);
        assert!(solid >= target && solid - last < target, "{solid} vs {target}");
        let mut all: Vec<(Vec3, f64)> = pk.particles.iter().map(|p| (p.centre, 0.5 * p.diameter_mm)).collect();
        all.extend(dep.iter().map(|g| (g.centre, 0.5 * g.diameter_mm)));
        let n_bulk = pk.particles.len();
        let mut on_two = 0;
        for (k, g) in dep.iter().enumerate() {
            let r = 0.5 * g.diameter_mm;
            let mut touching = Vec::new();
            for (j, &(c, rj)) in all.iter().enumerate() {
                if j == n_bulk + k {
                    continue;
                }
                for bx in -1..=1 {
                    for by in -1..=1 {
                        let c = c + Vec3::new(bx as f64 * per.x, by as f64 * per.y, 0.0);
                        let gap = (g.centre - c).norm2().sqrt() - (r + rj);
                        let d = g.diameter_mm.min(2.0 * rj);
                        assert!(gap >= -1e-6 * d, "grain {k} overlaps {j} by {:.3e} d", -gap / d);
                        if gap <= 1e-6 * d {
                            touching.push(Contact { id: (j, bx, by), c, s: r + rj });
                        }
                    }
                }
            }
            assert!(matches!(motion(g.centre, &touching), Some(Motion::Rest)), "grain {k} not at rest: {touching:?}");
            on_two += (touching.len() == 2) as usize;
        }
        (dep.len(), on_two)
    }

    #[test]
    fn settled_monodisperse_spheres_do_not_overlap_and_rest() {
        let (n, on_two) = check_settled(vec![0.25], 1);
        eprintln!("monodisperse: {n} deposited, {on_two} on two contacts");
        assert!(n > 50);
    }

    #[test]
    fn settled_polydisperse_spheres_do_not_overlap_and_rest() {
        let q: Vec<f64> = (0..9).map(|k| 0.18 + 0.02 * k as f64).collect();
        let (n, on_two) = check_settled(q, 2);
        eprintln!("polydisperse: {n} deposited, {on_two} on two contacts");
        assert!(n > 50);
    }
}

//! Terrain geometry: the paper's flat plane and heightfields of bilinear patches; the texture map
//! that gives each ground point its BRDF level.
//!
//! **Heightfield.** Node heights h[j·n_x + i] at (x₀ + i·dx, y₀ + j·dy) (metres, z up). The cell
//! (i, j) is the bilinear patch of its four corner nodes, so the surface is continuous and a ray
//! meets a patch where a quadratic in the ray parameter changes sign (solved exactly, no marching
//! error). Outside the grid the terrain either repeats (`wrap`, period n_x·dx by n_y·dy: the
//! procedural dune fields are periodic) or continues as the plane z = `outside` (nodes beyond the
//! edge take that height, so the border cells ramp down to it without a gap).
//!
//! **Traversal.** A 2-D grid walk (Amanatides & Woo 1987) over a hierarchy of maximum-height grids:
//! a block of 4ˡ × 4ˡ cells stores the largest node height it touches; a ray segment that stays
//! above a block's maximum skips it whole, otherwise the walk descends into its 4 × 4 children,
//! down to the patches, and climbs back up when it steps out of a block (the "maximum mipmap" of
//! Tevs, Ihrke & Seidel 2008).
//!
//! **Far field.** Beyond a horizontal distance `far_m` from a ray's origin the terrain is taken to
//! be the plane z = `far_z` (the mean height for a periodic field, `outside` otherwise): distant
//! dunes are below a pixel, and every ray that heads below the horizon still meets the ground, so
//! the sky is never seen below the horizon. Hits in the far field are flagged: rays leaving them
//! see only that plane.

use crate::error::SandlightError;
use crate::math::{floor_i64, Vec3};

/// Branching factor of the maximum-height hierarchy.
const BRANCH: i64 = 4;

/// A ray–terrain intersection.
#[derive(Clone, Copy, Debug)]
pub struct Hit {
    pub t: f64,
    pub p: Vec3,
    /// Unit geometric normal (z > 0).
    pub n: Vec3,
    /// Whether the hit lies on the far-field plane.
    pub far: bool,
}

#[derive(Clone, Debug)]
struct MaxLevel {
    scale: i64,
    /// Block index offset (non-periodic grids start at block −1) and counts.
    off: i64,
    nbx: i64,
    nby: i64,
    /// nbx − 1, nby − 1 for periodic power-of-two counts (wrap by masking, no division), else −1.
    mask_x: i64,
    mask_y: i64,
    max: Vec<f32>,
}

#[derive(Clone, Debug)]
pub struct Heightfield {
    nx: i64,
    ny: i64,
    x0: f64,
    y0: f64,
    dx: f64,
    dy: f64,
    h: Vec<f32>,
    wrap: bool,
    outside: f64,
    far_m: f64,
    far_z: f64,
    zmin: f64,
    zmax: f64,
    levels: Vec<MaxLevel>,
    /// n − 1 when a periodic grid has a power-of-two size (index wrap by masking), else −1.
    mask_x: i64,
    mask_y: i64,
    inv_dx: f64,
    inv_dy: f64,
    /// Cell width and depth (m) at each hierarchy level (0: the patches).
    cell_w: Vec<f64>,
    cell_h: Vec<f64>,
    /// Lipschitz constant of the surface: the largest |∇h| of any patch (at its corners, where
    /// the norm of a bilinear patch's gradient, convex along the cell, peaks).
    lipschitz: f64,
}

/// A ray with the reciprocals of its horizontal direction components (divisions are slow).
#[derive(Clone, Copy)]
struct Ray {
    o: Vec3,
    d: Vec3,
    inv_x: f64,
    inv_y: f64,
    /// 1 when the ray moves towards +x (+y), else 0: the far face of a cell is at index + ahead.
    ahead_x: f64,
    ahead_y: f64,
}

#[derive(Clone, Debug)]
pub enum Terrain {
    Plane { z: f64 },
    Heightfield(Box<Heightfield>),
}

impl Heightfield {
    /// `h` holds ny·nx node heights in metres (row j = y index). `outside` is the height of the
    /// plane around a non-periodic grid (ignored when `wrap`); `far_m` > 0 the far-field distance.
    #[allow(clippy::too_many_arguments)] // a regular grid as the scene file gives it
    pub fn new(
        nx: usize,
        ny: usize,
        x0: f64,
        y0: f64,
        dx: f64,
        dy: f64,
        h: Vec<f32>,
        wrap: bool,
        outside: f64,
        far_m: f64,
    ) -> Result<Self, SandlightError> {
        if nx < 2 || ny < 2 {
            return Err(SandlightError::parameter("heightfield", format!("{nx} × {ny} nodes"), "at least 2 × 2 nodes"));
        }
        if h.len() != nx * ny {
            return Err(SandlightError::parameter(
                "heights",
                format!("{} values", h.len()),
                &format!("{} values (ny × nx)", nx * ny),
            ));
        }
        if !(dx > 0.0 && dx.is_finite() && dy > 0.0 && dy.is_finite()) {
            return Err(SandlightError::parameter("cell size", format!("({dx}, {dy})"), "finite spacings > 0 m"));
        }
        if !(x0.is_finite() && y0.is_finite()) {
            return Err(SandlightError::parameter("origin", format!("({x0}, {y0})"), "finite coordinates"));
        }
        if let Some(bad) = h.iter().find(|v| !v.is_finite()) {
            return Err(SandlightError::parameter("heights", bad, "finite heights in metres"));
        }
        if !wrap && !outside.is_finite() {
            return Err(SandlightError::parameter("outside", outside, "a finite height in metres"));
        }
        if far_m.is_nan() || far_m <= 0.0 {
            return Err(SandlightError::parameter("far_m", far_m, "a distance > 0 m"));
        }
        let mut zmin = h.iter().fold(f64::INFINITY, |a, &b| a.min(b as f64));
        let mut zmax = h.iter().fold(f64::NEG_INFINITY, |a, &b| a.max(b as f64));
        let far_z = if wrap { h.iter().map(|&v| v as f64).sum::<f64>() / h.len() as f64 } else { outside };
        if !wrap {
            zmin = zmin.min(outside);
            zmax = zmax.max(outside);
        }
        let mask = |n: usize| if wrap && n.is_power_of_two() { n as i64 - 1 } else { -1 };
        let (mask_x, mask_y) = (mask(nx), mask(ny));
        let mut hf = Heightfield {
            nx: nx as i64,
            ny: ny as i64,
            x0,
            y0,
            dx,
            dy,
            h,
            wrap,
            outside,
            far_m,
            far_z,
            zmin,
            zmax,
            levels: Vec::new(),
            mask_x,
            mask_y,
            inv_dx: 1.0 / dx,
            inv_dy: 1.0 / dy,
            cell_w: Vec::new(),
            cell_h: Vec::new(),
            lipschitz: 0.0,
        };
        hf.build_levels();
        hf.cell_w = (0..=hf.levels.len()).map(|k| dx * hf.scale(k) as f64).collect();
        hf.cell_h = (0..=hf.levels.len()).map(|k| dy * hf.scale(k) as f64).collect();
        hf.lipschitz = hf.max_gradient();
        Ok(hf)
    }

    fn max_gradient(&self) -> f64 {
        // Periodic: cells 0..n; bounded: cells −1..n−1 including the ramps to the outside plane.
        let (lo, hx, hy) = if self.wrap { (0, self.nx, self.ny) } else { (-1, self.nx, self.ny) };
        let mut g2: f64 = 0.0;
        for j in lo..hy {
            for i in lo..hx {
                let (h00, h10, h01, h11) =
                    (self.node(i, j), self.node(i + 1, j), self.node(i, j + 1), self.node(i + 1, j + 1));
                for (sx, sy) in
                    [(h10 - h00, h01 - h00), (h11 - h01, h01 - h00), (h10 - h00, h11 - h10), (h11 - h01, h11 - h10)]
                {
                    let (gx, gy) = (sx * self.inv_dx, sy * self.inv_dy);
                    g2 = g2.max(gx * gx + gy * gy);
                }
            }
        }
        g2.sqrt()
    }

    /// Height of the surface at (x, y).
    fn height(&self, x: f64, y: f64) -> f64 {
        let fx = (x - self.x0) * self.inv_dx;
        let fy = (y - self.y0) * self.inv_dy;
        let (i, j) = (floor_i64(fx), floor_i64(fy));
        let (u, v) = (fx - i as f64, fy - j as f64);
        (1.0 - v) * ((1.0 - u) * self.node(i, j) + u * self.node(i + 1, j))
            + v * ((1.0 - u) * self.node(i, j + 1) + u * self.node(i + 1, j + 1))
    }

    fn build_levels(&mut self) {
        let extent = self.nx.max(self.ny);
        let mut scale = BRANCH;
        while scale * 2 <= extent && self.levels.len() < 8 {
            if self.wrap && (self.nx % scale != 0 || self.ny % scale != 0) {
                break;
            }
            // Periodic: blocks 0 .. n/scale (indices wrap). Otherwise the cells touching data run
            // from −1 to n−1, hence blocks ⌊−1/s⌋ = −1 .. ⌊(n−1)/s⌋.
            let (off, nbx, nby) = if self.wrap {
                (0, self.nx / scale, self.ny / scale)
            } else {
                (1, (self.nx - 1).div_euclid(scale) + 2, (self.ny - 1).div_euclid(scale) + 2)
            };
            let mut max = vec![f32::NEG_INFINITY; (nbx * nby) as usize];
            for bj in 0..nby {
                for bi in 0..nbx {
                    let (ci, cj) = ((bi - off) * scale, (bj - off) * scale);
                    let mut m = f64::NEG_INFINITY;
                    for j in cj..=cj + scale {
                        for i in ci..=ci + scale {
                            m = m.max(self.node(i, j));
                        }
                    }
                    max[(bj * nbx + bi) as usize] = m as f32;
                }
            }
            let mask = |n: i64| if self.wrap && n > 0 && (n & (n - 1)) == 0 { n - 1 } else { -1 };
            self.levels.push(MaxLevel { scale, off, nbx, nby, mask_x: mask(nbx), mask_y: mask(nby), max });
            scale *= BRANCH;
        }
    }

    #[inline(always)]
    fn node(&self, i: i64, j: i64) -> f64 {
        if self.mask_x >= 0 && self.mask_y >= 0 {
            self.h[((j & self.mask_y) * self.nx + (i & self.mask_x)) as usize] as f64
        } else if self.wrap {
            self.h[(j.rem_euclid(self.ny) * self.nx + i.rem_euclid(self.nx)) as usize] as f64
        } else if i >= 0 && i < self.nx && j >= 0 && j < self.ny {
            self.h[(j * self.nx + i) as usize] as f64
        } else {
            self.outside
        }
    }

    #[inline]
    fn scale(&self, k: usize) -> i64 {
        if k == 0 {
            1
        } else {
            self.levels[k - 1].scale
        }
    }

    #[inline]
    fn block_max(&self, k: usize, i: i64, j: i64) -> f64 {
        let lv = &self.levels[k - 1];
        let (bi, bj) = if lv.mask_x >= 0 && lv.mask_y >= 0 {
            (i & lv.mask_x, j & lv.mask_y)
        } else if self.wrap {
            (i.rem_euclid(lv.nbx), j.rem_euclid(lv.nby))
        } else {
            (i + lv.off, j + lv.off)
        };
        if bi < 0 || bj < 0 || bi >= lv.nbx || bj >= lv.nby {
            self.outside
        } else {
            lv.max[(bj * lv.nbx + bi) as usize] as f64
        }
    }

    /// First crossing of the ray with the bilinear patch of cell (i, j) for t in [ta, tb].
    #[inline]
    fn patch(&self, r: &Ray, i: i64, j: i64, ta: f64, tb: f64, zlo: f64) -> Option<Hit> {
        let (o, d) = (r.o, r.d);
        let (h00, h10, h01, h11) = (self.node(i, j), self.node(i + 1, j), self.node(i, j + 1), self.node(i + 1, j + 1));
        if zlo > h00.max(h10).max(h01).max(h11) {
            return None;
        }
        // S(u, v) = a + b u + c v + e u v on the unit cell.
        let (a, b, c, e) = (h00, h10 - h00, h01 - h00, h00 - h10 - h01 + h11);
        let pa = o + d * ta;
        let u0 = (pa.x - (self.x0 + i as f64 * self.dx)) * self.inv_dx;
        let v0 = (pa.y - (self.y0 + j as f64 * self.dy)) * self.inv_dy;
        let (du, dv) = (d.x * self.inv_dx, d.y * self.inv_dy);
        // g(s) = z(s) − S(u(s), v(s)) = C0 + C1 s + C2 s², s = t − ta.
        let c0 = pa.z - (a + b * u0 + c * v0 + e * u0 * v0);
        let c1 = d.z - (b * du + c * dv + e * (u0 * dv + v0 * du));
        let c2 = -e * du * dv;
        let len = tb - ta;
        let s = if c0 <= 0.0 { 0.0 } else { first_root(c0, c1, c2, len)? };
        let u = (u0 + s * du).clamp(0.0, 1.0);
        let v = (v0 + s * dv).clamp(0.0, 1.0);
        // ∂S/∂x, ∂S/∂y → normal (−S_x, −S_y, 1).
        let sx = (b + e * v) * self.inv_dx;
        let sy = (c + e * u) * self.inv_dy;
        let t = ta + s;
        Some(Hit { t, p: o + d * t, n: Vec3::new(-sx, -sy, 1.0).normalized(), far: false })
    }

    /// Exit parameter of cell (i, j) at hierarchy level k: (t across x, t across y).
    #[inline(always)]
    fn cell_exit(&self, r: &Ray, k: usize, i: i64, j: i64) -> (f64, f64) {
        // The far face of the cell along each axis: index + 1 going forwards, index going back.
        let tx = if r.d.x != 0.0 {
            (self.x0 + (i as f64 + r.ahead_x) * self.cell_w[k] - r.o.x) * r.inv_x
        } else {
            f64::INFINITY
        };
        let ty = if r.d.y != 0.0 {
            (self.y0 + (j as f64 + r.ahead_y) * self.cell_h[k] - r.o.y) * r.inv_y
        } else {
            f64::INFINITY
        };
        (tx, ty)
    }

    /// Cell index at level k of the point at parameter t, restricted to the children of block
    /// (bi, bj) of level k + 1 when given (a point on the block's border may round outside).
    #[inline(always)]
    fn cell_at(&self, r: &Ray, k: usize, t: f64, parent: Option<(i64, i64)>) -> (i64, i64) {
        let s = self.scale(k) as f64;
        let p = r.o + r.d * t;
        let i = floor_i64((p.x - self.x0) * self.inv_dx / s);
        let j = floor_i64((p.y - self.y0) * self.inv_dy / s);
        match parent {
            Some((bi, bj)) => {
                (i.clamp(bi * BRANCH, bi * BRANCH + BRANCH - 1), j.clamp(bj * BRANCH, bj * BRANCH + BRANCH - 1))
            }
            None => (i, j),
        }
    }

    /// First hit for t in [t0, t1]: a walk over the maximum-height hierarchy that descends into a
    /// block when the ray segment inside it dips to the block's maximum, steps to the next cell
    /// otherwise, and climbs back up whenever a step leaves the parent block (Tevs et al. 2008).
    fn traverse(&self, r: &Ray, t0: f64, t1: f64) -> Option<Hit> {
        let top = self.levels.len();
        let (step_i, step_j) = (if r.d.x > 0.0 { 1 } else { -1 }, if r.d.y > 0.0 { 1 } else { -1 });
        let mut t = t0;
        // A ray leaving the ground (shadow and reflected rays) starts in the finest block around
        // its origin, which it could only have reached from the top by descending through every
        // level; a ray from above (the camera's) starts at the top.
        let mut k = top;
        let (mut i, mut j) = self.cell_at(r, k, t, None);
        if top > 0 {
            let (bi, bj) = self.cell_at(r, 1, t, None);
            if r.o.z + r.d.z * t <= self.block_max(1, bi, bj) {
                (k, i, j) = (1, bi, bj);
            }
        }
        loop {
            let (tx, ty) = self.cell_exit(r, k, i, j);
            let tb = tx.min(ty).min(t1);
            if tb >= t {
                let zlo = (r.o.z + r.d.z * t).min(r.o.z + r.d.z * tb);
                if k == 0 {
                    if let Some(h) = self.patch(r, i, j, t, tb, zlo) {
                        return Some(h);
                    }
                } else if zlo <= self.block_max(k, i, j) {
                    let (ci, cj) = self.cell_at(r, k - 1, t, Some((i, j)));
                    k -= 1;
                    i = ci;
                    j = cj;
                    continue;
                }
            }
            if tb >= t1 {
                return None;
            }
            if r.d.z >= 0.0 && r.o.z + r.d.z * tb > self.zmax {
                return None;
            }
            // Step to the neighbouring cell of this level ...
            let (oi, oj) = (i, j);
            if tx < ty {
                i += step_i;
                t = tx;
            } else {
                j += step_j;
                t = ty;
            }
            // ... and climb while the step crossed the border of the parent block.
            let (mut pi, mut pj) = (oi, oj);
            while k < top {
                let (ni, nj) = (i.div_euclid(BRANCH), j.div_euclid(BRANCH));
                let (qi, qj) = (pi.div_euclid(BRANCH), pj.div_euclid(BRANCH));
                if ni == qi && nj == qj {
                    break;
                }
                k += 1;
                i = ni;
                j = nj;
                pi = qi;
                pj = qj;
            }
        }
    }

    fn intersect(&self, o: Vec3, d: Vec3, t_min: f64) -> Option<Hit> {
        let up = Vec3::new(0.0, 0.0, 1.0);
        let dh = (d.x * d.x + d.y * d.y).sqrt();
        let t_far = if dh > 1e-12 { self.far_m / dh } else { f64::INFINITY };
        let mut t_end = t_far;
        if d.z > 0.0 {
            if o.z >= self.zmax {
                return None;
            }
            // A ray from on or above the surface that rises faster than the surface can (its
            // Lipschitz constant) never meets it: h(p) ≤ h(o) + L·|p − o| < z of the ray.
            if d.z > self.lipschitz * dh * (1.0 + 1e-9) && o.z >= self.height(o.x, o.y) {
                return None;
            }
            t_end = t_end.min((self.zmax - o.z) / d.z);
        } else if d.z < 0.0 {
            if o.z < self.zmin {
                return Some(Hit { t: t_min, p: o + d * t_min, n: up, far: false });
            }
            t_end = t_end.min((self.zmin - o.z) / d.z);
        }
        let ray = Ray {
            o,
            d,
            inv_x: 1.0 / d.x,
            inv_y: 1.0 / d.y,
            ahead_x: (d.x > 0.0) as u8 as f64,
            ahead_y: (d.y > 0.0) as u8 as f64,
        };
        if let Some(h) = self.traverse(&ray, t_min, t_end) {
            return Some(h);
        }
        if t_end < t_far {
            // Below the lowest node without a recorded crossing (rounding): ground there.
            return if d.z < 0.0 { Some(Hit { t: t_end, p: o + d * t_end, n: up, far: false }) } else { None };
        }
        let pf = o + d * t_far;
        if pf.z < self.far_z {
            Some(Hit { t: t_far, p: Vec3::new(pf.x, pf.y, self.far_z), n: up, far: true })
        } else if d.z < 0.0 {
            let t = t_far + (pf.z - self.far_z) / -d.z;
            let p = o + d * t;
            Some(Hit { t, p: Vec3::new(p.x, p.y, self.far_z), n: up, far: true })
        } else {
            None
        }
    }

    pub fn far_z(&self) -> f64 {
        self.far_z
    }

    pub fn min_spacing(&self) -> f64 {
        self.dx.min(self.dy)
    }
}

/// Smallest s in [0, len] where C0 + C1 s + C2 s² (with C0 > 0) reaches 0.
#[inline]
fn first_root(c0: f64, c1: f64, c2: f64, len: f64) -> Option<f64> {
    let lin = |c0: f64, c1: f64| {
        if c1 < 0.0 {
            let s = -c0 / c1;
            (s <= len).then_some(s)
        } else {
            None
        }
    };
    if c2.abs() <= 1e-12 * (c1.abs() + c0.abs() / len.max(1e-300)) {
        return lin(c0, c1);
    }
    let disc = c1 * c1 - 4.0 * c2 * c0;
    if disc < 0.0 {
        return None;
    }
    // Numerically stable roots (Press et al., Numerical Recipes §5.6).
    let q = -0.5 * (c1 + c1.signum() * disc.sqrt());
    let (r1, r2) = (q / c2, if q != 0.0 { c0 / q } else { f64::INFINITY });
    let (lo, hi) = if r1 < r2 { (r1, r2) } else { (r2, r1) };
    [lo, hi].into_iter().find(|&s| (0.0..=len).contains(&s))
}

impl Terrain {
    /// First hit for t > t_min; `from_far`: the ray leaves a far-field point, which sees only the
    /// far plane.
    pub fn intersect(&self, o: Vec3, d: Vec3, t_min: f64, from_far: bool) -> Option<Hit> {
        if !(o.is_finite() && d.is_finite()) {
            // A non-finite ray would never leave the grid walk; it meets nothing.
            return None;
        }
        let up = Vec3::new(0.0, 0.0, 1.0);
        let plane = |z: f64| -> Option<Hit> {
            if d.z < 0.0 {
                let t = ((z - o.z) / d.z).max(t_min);
                let p = o + d * t;
                Some(Hit { t, p: Vec3::new(p.x, p.y, z), n: up, far: false })
            } else {
                None
            }
        };
        match self {
            Terrain::Plane { z } => plane(*z),
            Terrain::Heightfield(hf) => {
                if from_far {
                    plane(hf.far_z).map(|h| Hit { far: true, ..h })
                } else {
                    hf.intersect(o, d, t_min)
                }
            }
        }
    }

    /// Offset (m) along the normal for rays leaving a surface point, against self-intersection.
    pub fn ray_offset(&self, p: Vec3) -> f64 {
        match self {
            Terrain::Plane { .. } => 1e-7 * (1.0 + p.x.abs().max(p.y.abs()).max(p.z.abs())),
            Terrain::Heightfield(hf) => (1e-4 * hf.min_spacing()).max(1e-7 * (1.0 + p.x.abs().max(p.y.abs()))),
        }
    }
}

/// Per-point BRDF level coordinate s ∈ [0, L−1] over the ground (a saturation or mineralogy map
/// already mapped to levels): nodes at (x₀ + i·dx, y₀ + j·dy), bilinear between, clamped to the
/// border (or periodic when `wrap`).
#[derive(Clone, Debug)]
pub struct MaterialMap {
    nx: i64,
    ny: i64,
    x0: f64,
    y0: f64,
    dx: f64,
    dy: f64,
    values: Vec<f32>,
    wrap: bool,
}

impl MaterialMap {
    pub fn constant(level: f64) -> Self {
        MaterialMap { nx: 1, ny: 1, x0: 0.0, y0: 0.0, dx: 1.0, dy: 1.0, values: vec![level as f32], wrap: false }
    }

    #[allow(clippy::too_many_arguments)] // a regular grid as the scene file gives it
    pub fn new(
        nx: usize,
        ny: usize,
        x0: f64,
        y0: f64,
        dx: f64,
        dy: f64,
        values: Vec<f32>,
        wrap: bool,
        n_levels: usize,
    ) -> Result<Self, SandlightError> {
        if nx == 0 || ny == 0 || values.len() != nx * ny {
            return Err(SandlightError::parameter(
                "material map",
                format!("{} values for {nx} × {ny}", values.len()),
                "ny × nx values, nx, ny ≥ 1",
            ));
        }
        if !(dx > 0.0 && dy > 0.0 && dx.is_finite() && dy.is_finite() && x0.is_finite() && y0.is_finite()) {
            return Err(SandlightError::parameter(
                "material map extent",
                format!("origin ({x0}, {y0}), spacing ({dx}, {dy})"),
                "finite origin and spacings > 0 m",
            ));
        }
        let top = (n_levels.max(1) - 1) as f32;
        if let Some(bad) = values.iter().find(|v| !v.is_finite() || **v < 0.0 || **v > top) {
            return Err(SandlightError::parameter("material map", bad, &format!("level coordinates in [0, {top}]")));
        }
        Ok(MaterialMap { nx: nx as i64, ny: ny as i64, x0, y0, dx, dy, values, wrap })
    }

    #[inline]
    fn at(&self, i: i64, j: i64) -> f64 {
        let (i, j) = if self.wrap {
            (i.rem_euclid(self.nx), j.rem_euclid(self.ny))
        } else {
            (i.clamp(0, self.nx - 1), j.clamp(0, self.ny - 1))
        };
        self.values[(j * self.nx + i) as usize] as f64
    }

    /// Level coordinate at ground point (x, y).
    pub fn level(&self, x: f64, y: f64) -> f64 {
        if self.values.len() == 1 {
            return self.values[0] as f64;
        }
        let fx = (x - self.x0) / self.dx;
        let fy = (y - self.y0) / self.dy;
        let (fx, fy) = if self.wrap {
            (fx, fy)
        } else {
            (fx.clamp(0.0, (self.nx - 1) as f64), fy.clamp(0.0, (self.ny - 1) as f64))
        };
        let (i, j) = (floor_i64(fx), floor_i64(fy));
        let (tx, ty) = (fx - i as f64, fy - j as f64);
        (1.0 - ty) * ((1.0 - tx) * self.at(i, j) + tx * self.at(i + 1, j))
            + ty * ((1.0 - tx) * self.at(i, j + 1) + tx * self.at(i + 1, j + 1))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::rng::Rng;

    fn bumpy(nx: usize, ny: usize, wrap: bool) -> Heightfield {
        let mut h = Vec::new();
        for j in 0..ny {
            for i in 0..nx {
                let (x, y) = (i as f64 * 0.5, j as f64 * 0.5);
                h.push((1.5 * (x * 0.7).sin() * (y * 0.45).cos() + 0.3 * (x * 2.3 + y).sin()) as f32);
            }
        }
        Heightfield::new(nx, ny, -3.0, -5.0, 0.5, 0.5, h, wrap, 0.0, 1e4).unwrap()
    }

    /// Surface height of the bilinear interpolant at (x, y), for brute-force checks.
    fn height(hf: &Heightfield, x: f64, y: f64) -> f64 {
        let fx = (x - hf.x0) / hf.dx;
        let fy = (y - hf.y0) / hf.dy;
        let (i, j) = (fx.floor() as i64, fy.floor() as i64);
        let (u, v) = (fx - i as f64, fy - j as f64);
        (1.0 - v) * ((1.0 - u) * hf.node(i, j) + u * hf.node(i + 1, j))
            + v * ((1.0 - u) * hf.node(i, j + 1) + u * hf.node(i + 1, j + 1))
    }

    fn march(hf: &Heightfield, o: Vec3, d: Vec3, t_max: f64) -> Option<f64> {
        let n = 200_000;
        let mut prev = o.z - height(hf, o.x, o.y);
        for k in 1..=n {
            let t = t_max * k as f64 / n as f64;
            let p = o + d * t;
            let g = p.z - height(hf, p.x, p.y);
            if prev > 0.0 && g <= 0.0 {
                return Some(t);
            }
            prev = g;
        }
        None
    }

    #[test]
    fn traversal_hits_match_brute_force_marching() {
        for (nx, ny, wrap) in [(64, 48, false), (64, 48, true), (256, 256, true), (300, 200, false)] {
            let hf = bumpy(nx, ny, wrap);
            assert!(!hf.levels.is_empty());
            let mut rng = Rng::for_ray(9, wrap as u64, 0);
            let mut hits = 0;
            for _ in 0..200 {
                let o = Vec3::new(rng.uniform() * 30.0 - 5.0, rng.uniform() * 20.0 - 5.0, 2.5 + rng.uniform() * 3.0);
                let phi = rng.uniform() * std::f64::consts::TAU;
                let dz = -0.05 - 0.5 * rng.uniform();
                let d = Vec3::new(phi.cos(), phi.sin(), dz).normalized();
                let reference = march(&hf, o, d, 80.0);
                let got = hf.intersect(o, d, 0.0).filter(|h| !h.far).map(|h| h.t);
                match (reference, got) {
                    (Some(a), Some(b)) => {
                        hits += 1;
                        assert!((a - b).abs() < 2e-3, "{nx}×{ny} wrap {wrap}: march {a} vs traversal {b}");
                    }
                    (None, None) => {}
                    (a, b) => panic!("{nx}×{ny} wrap {wrap}: march {a:?} vs traversal {b:?}"),
                }
            }
            assert!(hits > 150);
        }
    }

    #[test]
    fn shadow_rays_from_the_surface_match_brute_force_marching() {
        for (nx, ny, wrap) in [(64, 48, false), (256, 256, true)] {
            let hf = bumpy(nx, ny, wrap);
            let mut rng = Rng::for_ray(4, nx as u64, 1);
            let (mut blocked, mut n) = (0, 0);
            for _ in 0..300 {
                let (x, y) = (rng.uniform() * 20.0, rng.uniform() * 15.0);
                let o = Vec3::new(x, y, height(&hf, x, y) + 1e-3);
                let phi = rng.uniform() * std::f64::consts::TAU;
                let el: f64 = 0.02 + 0.6 * rng.uniform();
                let d = Vec3::new(el.cos() * phi.cos(), el.cos() * phi.sin(), el.sin());
                let reference = march(&hf, o, d, 60.0).is_some();
                let got = hf.intersect(o, d, 0.0).is_some();
                // Starting 1 mm above the surface, the marcher may see the start patch on steep
                // slopes where the exact test does not; count disagreements instead of failing at once.
                n += (reference != got) as u32;
                blocked += got as u32;
            }
            assert!(n <= 3, "{nx}×{ny}: {n} disagreements");
            assert!(blocked > 30 && blocked < 270, "{blocked}");
        }
    }

    #[test]
    fn lipschitz_bound_holds_and_steep_rays_escape() {
        let hf = bumpy(64, 48, false);
        let mut rng = Rng::for_ray(2, 0, 0);
        let mut steepest: f64 = 0.0;
        for _ in 0..20000 {
            let (x, y) = (rng.uniform() * 40.0 - 8.0, rng.uniform() * 30.0 - 8.0);
            let a = rng.uniform() * std::f64::consts::TAU;
            let (x2, y2) = (x + 1e-3 * a.cos(), y + 1e-3 * a.sin());
            steepest = steepest.max((height(&hf, x2, y2) - height(&hf, x, y)).abs() / 1e-3);
        }
        assert!(
            steepest <= hf.lipschitz * (1.0 + 1e-6) && steepest > 0.8 * hf.lipschitz,
            "{steepest} vs {}",
            hf.lipschitz
        );
        // Rays just steeper than the bound escape without a walk, and marching agrees.
        let el = hf.lipschitz.atan() + 0.01;
        for k in 0..50 {
            let (x, y) = (k as f64 * 0.37, 3.0 + k as f64 * 0.21);
            let o = Vec3::new(x, y, height(&hf, x, y) + 1e-6);
            let d = Vec3::new(el.cos() * (k as f64).cos(), el.cos() * (k as f64).sin(), el.sin());
            assert!(hf.intersect(o, d, 0.0).is_none() && march(&hf, o, d, 30.0).is_none());
        }
    }

    #[test]
    fn upward_rays_above_the_terrain_escape_and_downward_rays_always_land() {
        let hf = bumpy(32, 32, true);
        assert!(hf.intersect(Vec3::new(0.0, 0.0, 5.0), Vec3::new(0.1, 0.2, 0.3).normalized(), 0.0).is_none());
        let h = hf.intersect(Vec3::new(0.0, 0.0, 5.0), Vec3::new(1.0, 0.0, -1e-4).normalized(), 0.0).unwrap();
        assert!(h.n.z > 0.0);
    }

    #[test]
    fn material_map_interpolates_and_clamps() {
        let m = MaterialMap::new(2, 1, 0.0, 0.0, 10.0, 1.0, vec![0.0, 3.0], false, 4).unwrap();
        assert!((m.level(5.0, 0.0) - 1.5).abs() < 1e-6);
        assert!((m.level(-4.0, 7.0) - 0.0).abs() < 1e-6);
        assert!((m.level(40.0, 0.0) - 3.0).abs() < 1e-6);
        assert!(MaterialMap::new(2, 1, 0.0, 0.0, 1.0, 1.0, vec![0.0, 5.0], false, 4).is_err());
    }
}

//! Where the next grain lies relative to the grain a ray left, in a packing: the pair
//! correlation function g of packed spheres, for the on-the-fly engine's neighbour memory
//! (`Memory::Packed`, docs/geometry.md "Neighbour memory").
//!
//! In a Boolean model the grain met after a flight is hit at a point uniform over its shadow,
//! independently of the grain the flight started from. In a packing the two are correlated:
//! they cannot overlap, and about 5 of a grain's neighbours touch it at η = 0.60 (the contact
//! peak of g).
//! The flight length keeps its exponential law (it holds in the packing); only where the grain
//! met is hit changes: the uniform law is weighted by g(|c_B − c_A|/σ), c_A and c_B the two
//! centres and σ their contact distance.
//!
//! Table: `data/pair_correlation.txt`, written by `scripts/data/build_pair_correlation.py` from
//! sandlight's own packings of monodisperse spheres: per packing fraction η, the contacts per
//! grain z (a delta peak at x = 1) and g(x) beyond contact on a grid, x = r/σ.

use crate::math::{sin_cos_turns, Vec3};
use crate::rng::Rng;

const TABLE: &str = include_str!("../data/pair_correlation.txt");

/// g of one packing fraction: a delta peak at contact plus a smooth part on a grid (g = 0 below
/// contact, 1 beyond the grid).
#[derive(Clone, Debug)]
pub struct PairCorrelation {
    /// The packing fraction η (clamped to the table).
    eta: f64,
    /// Weight of the contact peak, ∫ g x² dx over it (with `CONTACT_BAND`): contacts per grain
    /// over 24η, since 4πρσ³ = 24η for spheres of diameter σ at number density ρ = 6η/(πσ³).
    contact: f64,
    x0: f64,
    dx: f64,
    smooth: Vec<f64>,
    /// Range maxima of `smooth`: level j holds the maximum over bins [k, k + 2ʲ).
    range_max: Vec<Vec<f64>>,
}

/// Pairs closer than this fraction of the contact distance beyond contact count as touching:
/// their share of g moves into the contact peak. A gap of 2 % of a grain diameter changes
/// nothing a ray does at the scale of the grain, and the steep rise of g just beyond contact
/// would otherwise set the rejection envelope (docs/geometry.md).
pub const CONTACT_BAND: f64 = 0.02;

/// One packing fraction of the table.
struct Row {
    eta: f64,
    /// Contacts per grain.
    z: f64,
    /// g beyond contact on the grid.
    g: Vec<f64>,
}

/// The table, parsed once: grid (x0, dx) and its rows.
fn table() -> &'static (f64, f64, Vec<Row>) {
    static PARSED: std::sync::OnceLock<(f64, f64, Vec<Row>)> = std::sync::OnceLock::new();
    PARSED.get_or_init(parse)
}

/// The table's text parsed: grid (x0, dx) and its rows.
fn parse() -> (f64, f64, Vec<Row>) {
    let mut grid = None;
    let mut rows = Vec::new();
    for line in TABLE.lines().map(str::trim).filter(|l| !l.is_empty() && !l.starts_with('#')) {
        let mut words = line.split_whitespace();
        if line.starts_with("grid") {
            let v: Vec<f64> = words.skip(1).map(|w| w.parse().expect("pair_correlation.txt: grid")).collect();
            grid = Some((v[0], v[1], v[2] as usize));
            continue;
        }
        let v: Vec<f64> = words.by_ref().map(|w| w.parse().expect("pair_correlation.txt: a number")).collect();
        rows.push(Row { eta: v[0], z: v[1], g: v[2..].to_vec() });
    }
    let (x0, dx, bins) = grid.expect("pair_correlation.txt: a grid line");
    assert!(!rows.is_empty() && rows.iter().all(|r| r.g.len() == bins), "pair_correlation.txt: rows of {bins} values");
    assert!(rows.windows(2).all(|w| w[0].eta < w[1].eta), "pair_correlation.txt: increasing η");
    (x0, dx, rows)
}

impl PairCorrelation {
    /// g at packing fraction `eta`: linear interpolation between the tabulated fractions,
    /// clamped to the table's range (0.40–0.62).
    pub fn at_packing_fraction(eta: f64) -> PairCorrelation {
        let (x0, dx, rows) = table();
        let (x0, dx) = (*x0, *dx);
        let e = eta.clamp(rows[0].eta, rows[rows.len() - 1].eta);
        // Rows with η ≤ e: at least the first (e is clamped), all of them at the top end.
        let k = rows.partition_point(|r| r.eta <= e);
        let (lo, hi) = (&rows[k - 1], &rows[k.min(rows.len() - 1)]);
        let w = if hi.eta > lo.eta { (e - lo.eta) / (hi.eta - lo.eta) } else { 0.0 };
        let mix = |a: f64, b: f64| a + w * (b - a);
        // Contact peak weight ∫ g x² dx (pairs per grain / 24η), with the band just beyond it.
        let mut contact = mix(lo.z, hi.z) / (24.0 * e);
        let mut smooth: Vec<f64> = lo.g.iter().zip(&hi.g).map(|(&a, &b)| mix(a, b)).collect();
        for (k, g) in smooth.iter_mut().enumerate() {
            let x = x0 + dx * (k as f64 + 0.5);
            if x0 + dx * (k + 1) as f64 <= 1.0 + CONTACT_BAND + 1e-9 {
                contact += *g * x * x * dx;
                *g = 0.0;
            }
        }
        let mut range_max = vec![smooth.clone()];
        while 1usize << range_max.len() <= smooth.len() {
            let (prev, half) = (range_max.last().unwrap(), 1usize << (range_max.len() - 1));
            let level = (0..smooth.len()).map(|k| prev[k].max(*prev.get(k + half).unwrap_or(&prev[k]))).collect();
            range_max.push(level);
        }
        PairCorrelation { eta: e, contact, x0, dx, smooth, range_max }
    }

    /// Contacts per grain, those within `CONTACT_BAND` included.
    pub fn contacts_per_grain(&self) -> f64 {
        self.contact * 24.0 * self.eta
    }

    /// The smooth part of g at x = r/σ (the contact peak excluded).
    #[inline]
    pub fn smooth(&self, x: f64) -> f64 {
        if x < self.x0 {
            return 0.0;
        }
        self.smooth.get(((x - self.x0) / self.dx) as usize).copied().unwrap_or(1.0)
    }

    /// An upper bound of the smooth part over [x_lo, x_hi] (0 if it lies below contact).
    #[inline]
    fn envelope(&self, x_lo: f64, x_hi: f64) -> f64 {
        if x_hi < self.x0 {
            return 0.0;
        }
        let n = self.smooth.len();
        let lo = ((x_lo - self.x0).max(0.0) / self.dx) as usize;
        let hi = ((x_hi - self.x0) / self.dx) as usize;
        let beyond = if hi >= n { 1.0 } else { 0.0 };
        if lo >= n {
            return beyond;
        }
        let hi = hi.min(n - 1);
        let j = (usize::BITS - 1 - (hi - lo + 1).leading_zeros()) as usize;
        let level = &self.range_max[j];
        level[lo].max(level[hi + 1 - (1 << j)]).max(beyond)
    }

    /// The outward normal n at which a sphere of radius `r_b` is hit by a ray along `d`, the
    /// hit point lying at `v` from the centre of the grain the ray left (contact distance
    /// `sigma`): the uniform-shadow law, density (−n·d)₊/π over directions, weighted by
    /// g(|v − r_b n|/σ). The centre of the sphere met is then at v − r_b n from that grain's.
    ///
    /// Exact composition–rejection: the target is W_c·(law on the contact circle) + (uniform
    /// law)·g_smooth, W_c = G_c I(t_c) σ²/(π r_b |v|) (the contact peak's weight, I the
    /// shadow weight of the circle n·v̂ = t_c on which |v − r_b n| = σ); propose the contact
    /// circle with weight W_c or the uniform law with weight M ≥ g_smooth over the range of
    /// distances reachable, and accept the latter with probability g_smooth/M.
    pub fn sample_normal(&self, v: Vec3, d: Vec3, r_b: f64, sigma: f64, rng: &mut Rng) -> Vec3 {
        let big_v = v.norm2().sqrt();
        let x_lo = (big_v - r_b).abs() / sigma;
        if x_lo >= self.x0 + self.dx * self.smooth.len() as f64 || big_v == 0.0 {
            return uniform_shadow_normal(d, rng);
        }
        let v_hat = v * (1.0 / big_v);
        let cvd = v_hat.dot(d).clamp(-1.0, 1.0);
        let svd = (1.0 - cvd * cvd).sqrt();
        // |v − r_b n|² = V² + r_b² − 2 r_b V (n·v̂): contact on the circle n·v̂ = t_c.
        let t_c = (big_v * big_v + r_b * r_b - sigma * sigma) / (2.0 * r_b * big_v);
        let circle = ContactCircle::new(t_c, cvd, svd);
        let w_c = if t_c.abs() < 1.0 {
            self.contact * circle.shadow_weight() * sigma * sigma / (std::f64::consts::PI * r_b * big_v)
        } else {
            0.0
        };
        let m = self.envelope(x_lo, (big_v + r_b) / sigma);
        if w_c + m <= 0.0 {
            // Nowhere to put a grain without overlap (a flight ending inside the grain left,
            // not met by the engine): the uniform law.
            return uniform_shadow_normal(d, rng);
        }
        let basis = d.orthonormal_basis();
        let (a2, b2) = ((big_v * big_v + r_b * r_b) / (sigma * sigma), 2.0 * r_b * big_v / (sigma * sigma));
        for _ in 0..10_000 {
            if rng.uniform() * (w_c + m) < w_c {
                return circle.sample(v_hat, d, cvd, svd, rng);
            }
            let n = shadow_normal_in(d, basis, rng);
            let x = (a2 - b2 * n.dot(v_hat)).max(0.0).sqrt();
            if rng.uniform() * m < self.smooth(x) {
                return n;
            }
        }
        uniform_shadow_normal(d, rng)
    }
}

/// The outward normal at a hit on a sphere, impact uniform over its shadow (the Boolean law).
#[inline]
pub fn uniform_shadow_normal(d: Vec3, rng: &mut Rng) -> Vec3 {
    shadow_normal_in(d, d.orthonormal_basis(), rng)
}

/// `uniform_shadow_normal` with the basis across `d` given.
#[inline]
fn shadow_normal_in(d: Vec3, (e1, e2): (Vec3, Vec3), rng: &mut Rng) -> Vec3 {
    let rho2 = rng.uniform();
    let (s, c) = sin_cos_turns(rng.uniform());
    let rho = rho2.sqrt();
    e1 * (rho * c) + e2 * (rho * s) - d * (1.0 - rho2).max(0.0).sqrt()
}

/// The circle of normals n = t v̂ + √(1 − t²)(cos φ e₁ + sin φ e₂), e₁ the unit vector of d's
/// part across v̂, on which the grain met touches the grain left. Along it
/// −n·d = c − b cos φ with c = −t (v̂·d), b = √(1 − t²)|d × v̂|, positive for φ in (φ₀, 2π − φ₀),
/// cos φ₀ = c/b (φ₀ = 0 if c ≥ b: the whole circle faces the ray).
struct ContactCircle {
    t: f64,
    c: f64,
    b: f64,
    phi0: f64,
}

impl ContactCircle {
    fn new(t: f64, cvd: f64, svd: f64) -> ContactCircle {
        let c = -t * cvd;
        let b = (1.0 - t * t).max(0.0).sqrt() * svd;
        let phi0 = if c < b && c > -b { (c / b).acos() } else { 0.0 };
        ContactCircle { t, c, b, phi0 }
    }

    /// I(t) = ∫₀^{2π} (−n·d)₊ dφ: 2c(π − φ₀) + 2b sin φ₀ (2πc if c ≥ b, 0 if c ≤ −b).
    fn shadow_weight(&self) -> f64 {
        let (c, b) = (self.c, self.b);
        if c >= b {
            return 2.0 * std::f64::consts::PI * c;
        }
        if c <= -b {
            return 0.0;
        }
        2.0 * c * (std::f64::consts::PI - self.phi0) + 2.0 * b * self.phi0.sin()
    }

    /// A normal on the circle with density ∝ (−n·d)₊ (rejection over the arc where it is
    /// positive; the bound c + b is the weight at φ = π).
    fn sample(&self, v_hat: Vec3, d: Vec3, cvd: f64, svd: f64, rng: &mut Rng) -> Vec3 {
        let (e1, e2) = if svd > 1e-12 {
            let e1 = (d - v_hat * cvd) * (1.0 / svd);
            (e1, v_hat.cross(e1))
        } else {
            v_hat.orthonormal_basis()
        };
        let (t, c, b) = (self.t, self.c, self.b);
        let sin_t = (1.0 - t * t).max(0.0).sqrt();
        // φ over (φ₀, 2π − φ₀), in turns φ/2π.
        let turn0 = self.phi0 / (2.0 * std::f64::consts::PI);
        for _ in 0..10_000 {
            let (s, co) = sin_cos_turns(turn0 + rng.uniform() * (1.0 - 2.0 * turn0));
            if rng.uniform() * (c + b) <= c - b * co {
                return v_hat * t + (e1 * co + e2 * s) * sin_t;
            }
        }
        v_hat * t + e1 * (-sin_t)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn sphere_pair() -> (Vec3, Vec3, f64, f64) {
        // A ray that left the top of a grain of radius 0.125 obliquely and flew 0.03 mm.
        let d = Vec3::new(0.6, -0.2, 0.5).normalized();
        let start = Vec3::new(0.0, 0.0, 0.125);
        (start + d * 0.03, d, 0.125, 0.25)
    }

    #[test]
    fn table_parses_and_interpolates() {
        let (x0, dx, rows) = parse();
        assert!(x0 > 1.0 && x0 < 1.01 && dx > 0.0 && rows.len() >= 2);
        for Row { eta, z, g } in &rows {
            assert!(*eta > 0.3 && *eta < 0.7 && *z > 1.0 && *z < 8.0, "η {eta}, z {z}");
            // g → 1 at the end of the grid (no long-range order), positive near contact.
            assert!((g[g.len() - 1] - 1.0).abs() < 0.1 && g[0] > 1.0);
        }
        // The contact peak: the tabulated contacts plus the band folded into them.
        let peak = |z: f64, eta: f64, g: &[f64]| {
            z / (24.0 * eta)
                + g.iter()
                    .enumerate()
                    .take_while(|(k, _)| x0 + dx * (*k + 1) as f64 <= 1.0 + CONTACT_BAND + 1e-9)
                    .map(|(k, v)| {
                        let x = x0 + dx * (k as f64 + 0.5);
                        v * x * x * dx
                    })
                    .sum::<f64>()
        };
        let (e0, z0, g0) = (rows[0].eta, rows[0].z, &rows[0].g);
        let at = PairCorrelation::at_packing_fraction(e0);
        assert!((at.contact - peak(z0, e0, g0)).abs() < 1e-12 && at.contacts_per_grain() > z0);
        assert_eq!(at.smooth(1.0 + 0.5 * CONTACT_BAND), 0.0, "the band is in the peak");
        assert!(at.smooth(1.0 + 1.5 * CONTACT_BAND) > 1.0);
        // Clamped below the table, interpolated inside it.
        assert_eq!(PairCorrelation::at_packing_fraction(0.1).contact, at.contact);
        let (e1, z1, g1) = (rows[1].eta, rows[1].z, &rows[1].g);
        let e = 0.5 * (e0 + e1);
        let g_mid: Vec<f64> = g0.iter().zip(g1).map(|(a, b)| 0.5 * (a + b)).collect();
        assert!((PairCorrelation::at_packing_fraction(e).contact - peak(0.5 * (z0 + z1), e, &g_mid)).abs() < 1e-12);
        assert_eq!(at.smooth(0.99), 0.0);
        assert_eq!(at.smooth(10.0), 1.0);
    }

    #[test]
    fn envelope_bounds_g_over_any_range() {
        let g = PairCorrelation::at_packing_fraction(0.6);
        let mut rng = Rng::for_ray(2, 0, 0);
        for _ in 0..2000 {
            let a = 0.9 + 2.5 * rng.uniform();
            let b = a + 0.6 * rng.uniform();
            let m = g.envelope(a, b);
            let brute = (0..=400).map(|k| g.smooth(a + (b - a) * k as f64 / 400.0)).fold(0.0, f64::max);
            assert!(m >= brute, "[{a}, {b}]: {m} < {brute}");
            // Tight: the maximum over the bins touched, not over everything beyond.
            let k_lo = ((a - g.x0).max(0.0) / g.dx) as usize;
            let k_hi = ((b - g.x0) / g.dx) as usize;
            if b >= g.x0 && k_hi < g.smooth.len() {
                assert_eq!(m, g.smooth[k_lo..=k_hi].iter().cloned().fold(0.0, f64::max));
            }
        }
    }

    #[test]
    fn shadow_weight_integrates_the_uniform_law() {
        // ∫ I(t) dt over [−1, 1] = ∫ (−n·d)₊ dΩ = π, for any angle between v̂ and d.
        for cvd in [-1.0, -0.6, 0.0, 0.3, 0.95] {
            let svd: f64 = (1.0f64 - cvd * cvd).sqrt();
            let n = 20_000;
            let sum: f64 = (0..n)
                .map(|k| ContactCircle::new(-1.0 + 2.0 * (k as f64 + 0.5) / n as f64, cvd, svd).shadow_weight())
                .sum::<f64>()
                * 2.0
                / n as f64;
            assert!((sum - std::f64::consts::PI).abs() < 1e-3, "cvd {cvd}: {sum}");
        }
    }

    #[test]
    fn sampled_normals_follow_the_weighted_law() {
        let (v, d, r_b, sigma) = sphere_pair();
        let g = PairCorrelation::at_packing_fraction(0.6);
        let mut rng = Rng::for_ray(11, 0, 0);
        // The target by brute force: uniform-shadow normals weighted by g_smooth; the contact
        // share W_c/(W_c + W_s) with W_s the mean of g_smooth under the uniform law.
        let n_draws = 400_000;
        let (mut w_s, mut mean_x_s) = (0.0, 0.0);
        for _ in 0..n_draws {
            let n = uniform_shadow_normal(d, &mut rng);
            let x = (v - n * r_b).norm2().sqrt() / sigma;
            w_s += g.smooth(x);
            mean_x_s += g.smooth(x) * x;
        }
        mean_x_s /= w_s;
        w_s /= n_draws as f64;
        let big_v = v.norm2().sqrt();
        let v_hat = v * (1.0 / big_v);
        let cvd = v_hat.dot(d);
        let t_c = (big_v * big_v + r_b * r_b - sigma * sigma) / (2.0 * r_b * big_v);
        let w_c = g.contact * ContactCircle::new(t_c, cvd, (1.0 - cvd * cvd).sqrt()).shadow_weight() * sigma * sigma
            / (std::f64::consts::PI * r_b * big_v);
        let expected_contact = w_c / (w_c + w_s);
        let (mut contacts, mut sum_x_s, mut others) = (0usize, 0.0, 0usize);
        for _ in 0..n_draws {
            let n = g.sample_normal(v, d, r_b, sigma, &mut rng);
            assert!((n.norm2() - 1.0).abs() < 1e-9 && n.dot(d) <= 1e-12, "an outward normal facing the ray");
            let x = (v - n * r_b).norm2().sqrt() / sigma;
            if (x - 1.0).abs() < 1e-9 {
                contacts += 1;
            } else {
                assert!(x >= g.x0, "no overlap with the grain left: x = {x}");
                sum_x_s += x;
                others += 1;
            }
        }
        let share = contacts as f64 / n_draws as f64;
        let se = (expected_contact * (1.0 - expected_contact) / n_draws as f64).sqrt();
        assert!(expected_contact > 0.05, "the configuration reaches contact ({expected_contact})");
        assert!((share - expected_contact).abs() < 5.0 * se + 0.005, "contact share {share} vs {expected_contact}");
        assert!((sum_x_s / others as f64 - mean_x_s).abs() < 2e-3, "{} vs {mean_x_s}", sum_x_s / others as f64);
    }

    #[test]
    fn far_from_the_grain_left_the_law_is_uniform() {
        let g = PairCorrelation::at_packing_fraction(0.6);
        let d = Vec3::new(0.0, 0.0, -1.0);
        let (mut a, mut b) = (Rng::for_ray(5, 0, 0), Rng::for_ray(5, 0, 0));
        for _ in 0..100 {
            let n = g.sample_normal(Vec3::new(0.0, 0.0, -2.0), d, 0.125, 0.25, &mut a);
            assert_eq!(n, uniform_shadow_normal(d, &mut b));
        }
    }
}

//! Thin plane-parallel layers on a particle surface (a water film, an iron-oxide coating),
//! combined incoherently with the interfaces around them.
//!
//! A layer is thin compared with the particle (t ≪ D, docs/model.md §2.4 item 2), so locally a
//! plane slab, traced without interference: coatings are thinner than daylight's coherence
//! length, but rough on the scale of their thickness (docs/model.md §2.4 item 2, "Coherence",
//! measures what a smooth coherent film would change).
//! Across parallel planes the tangential invariant s = n sin θ is conserved (Snell), hence the
//! ray that finally enters the far medium has the direction Snell's law gives between the two
//! outer media directly, and a reflected ray leaves along the mirror direction. Only the
//! probabilities need the layers: the standard incoherent recursion for a slab between two
//! interfaces with single-pass transmittance τ = exp(−α t / cos θ):
//!
//!   R = R_a + T_a² τ² R_b / (1 − R_a R_b τ²),   T = T_a τ T_b / (1 − R_a R_b τ²)
//!
//! (e.g. Born & Wolf §1.6 for the incoherent limit; Yeh, *Optical Waves in Layered Media*, §5).
//! Interface reflectances use real indices; the absorption of a layer enters through τ. The one
//! exception is the entry into an absorbing particle core, where the complex-index Fresnel
//! formula is used because a metal-like reflectance (magnetite, iron-oxide particles) matters.

use crate::fresnel;

/// A homogeneous medium in a stack: real index, absorption coefficient (mm⁻¹), thickness (mm;
/// ignored for the two outer media) and the imaginary index used for Fresnel (non-zero only
/// for an absorbing particle core entered from outside).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Slab {
    pub n: f64,
    pub alpha_per_mm: f64,
    pub thickness_mm: f64,
    pub k_fresnel: f64,
}

impl Slab {
    pub const fn semi_infinite(n: f64) -> Slab {
        Slab { n, alpha_per_mm: 0.0, thickness_mm: 0.0, k_fresnel: 0.0 }
    }
}

/// Reflectance and transmittance of a stack `media[0] | media[1] | … | media[last]` for light
/// incident from `media[0]` with incidence cosine `cos_0` (in (0, 1]). Layers are
/// `media[1..last]`; at most `MAX_MEDIA` media. Absorptance is 1 − R − T.
#[inline]
pub fn stack_rt(media: &[Slab], cos_0: f64) -> (f64, f64) {
    let m = media.len();
    debug_assert!((2..=MAX_MEDIA).contains(&m));
    let cos_0 = cos_0.clamp(0.0, 1.0);
    let s2 = media[0].n * media[0].n * (1.0 - cos_0 * cos_0); // (n₀ sin θ₀)²
    if m == 2 {
        // A bare interface (no film, no coating): R from Fresnel, T = 1 − R.
        let r = interface(media[0], media[1], cos_0, s2);
        return (r, 1.0 - r);
    }
    // cos θ in each medium from the invariant; TIR where (s/n)² ≥ 1.
    let mut cos = [0.0f64; MAX_MEDIA];
    cos[0] = cos_0;
    for i in 1..m {
        let c2 = 1.0 - s2 / (media[i].n * media[i].n);
        cos[i] = if c2 > 0.0 { c2.sqrt() } else { 0.0 };
    }
    // Interface between media i and i+1, seen from medium i; the transmitted cosine is known.
    let between = |i: usize| -> f64 {
        let (a, b) = (media[i], media[i + 1]);
        if cos[i + 1] <= 0.0 {
            1.0
        } else if b.k_fresnel > 0.0 {
            fresnel::conductor(a.n, b.n, b.k_fresnel, cos[i])
        } else {
            fresnel::dielectric_cos(a.n, b.n, cos[i], cos[i + 1])
        }
    };
    // Recursion from the innermost interface outwards: (r, t) describe everything beyond
    // medium i as seen from inside medium i.
    let mut r = between(m - 2);
    let mut t = 1.0 - r;
    for i in (1..m - 1).rev() {
        let ra = between(i - 1);
        let ta = 1.0 - ra;
        let tau = if cos[i] > 0.0 { (-media[i].alpha_per_mm * media[i].thickness_mm / cos[i]).exp() } else { 0.0 };
        let denom = 1.0 - ra * r * tau * tau;
        if denom > 0.0 {
            let new_r = ra + ta * ta * tau * tau * r / denom;
            let new_t = ta * tau * t / denom;
            r = new_r;
            t = new_t;
        } else {
            // R_a = R_b = τ = 1 (grazing incidence on a lossless layer with total reflection
            // beyond it): 0/0 in the formula, whose limit is total reflection.
            r = 1.0;
            t = 0.0;
        }
    }
    let r = r.clamp(0.0, 1.0);
    (r, t.clamp(0.0, 1.0 - r))
}

/// Reflectance of the single interface a | b for incidence cosine `cos_a` in a, with
/// s2 = (n_a sin θ_a)²: 1 beyond the critical angle, complex-index Fresnel into an absorbing
/// core, real Fresnel otherwise.
#[inline]
pub(crate) fn interface(a: Slab, b: Slab, cos_a: f64, s2: f64) -> f64 {
    if s2 >= b.n * b.n {
        1.0
    } else if b.k_fresnel > 0.0 {
        fresnel::conductor(a.n, b.n, b.k_fresnel, cos_a)
    } else {
        fresnel::dielectric(a.n, b.n, cos_a)
    }
}

/// Pore medium, optional water film, optional coating, core: four media at most.
pub const MAX_MEDIA: usize = 4;

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn single_interface_is_fresnel() {
        let st = [Slab::semi_infinite(1.0), Slab::semi_infinite(1.5)];
        let (r, t) = stack_rt(&st, 0.8);
        assert!((r - fresnel::dielectric(1.0, 1.5, 0.8)).abs() < 1e-14);
        assert!((r + t - 1.0).abs() < 1e-14);
    }

    #[test]
    fn index_matched_layer_only_absorbs() {
        let layer = Slab { n: 1.5, alpha_per_mm: 10.0, thickness_mm: 0.01, k_fresnel: 0.0 };
        let st = [Slab::semi_infinite(1.5), layer, Slab::semi_infinite(1.5)];
        let (r, t) = stack_rt(&st, 0.5);
        assert!(r.abs() < 1e-14);
        assert!((t - (-10.0f64 * 0.01 / 0.5).exp()).abs() < 1e-12);
    }

    #[test]
    fn transparent_stack_conserves_energy_and_is_reciprocal() {
        let w = Slab { n: 1.33, alpha_per_mm: 0.0, thickness_mm: 0.001, k_fresnel: 0.0 };
        let c = Slab { n: 1.8, alpha_per_mm: 0.0, thickness_mm: 0.0005, k_fresnel: 0.0 };
        let fwd = [Slab::semi_infinite(1.0), w, c, Slab::semi_infinite(1.54)];
        let back = [Slab::semi_infinite(1.54), c, w, Slab::semi_infinite(1.0)];
        for &c0 in &[0.2, 0.5, 0.9, 1.0] {
            let (r, t) = stack_rt(&fwd, c0);
            assert!((r + t - 1.0).abs() < 1e-12);
            // The same ray seen from the core side: cos in the core from the invariant.
            let s = (1.0 - c0 * c0).sqrt() / 1.54;
            let (rb, tb) = stack_rt(&back, (1.0 - s * s).sqrt());
            assert!((t - tb).abs() < 1e-12 && (r - rb).abs() < 1e-12);
        }
    }

    #[test]
    fn grazing_on_a_lossless_film_over_total_reflection_is_total_reflection() {
        // R_a = 1 at μ = 0, τ = 1, R_b = 1 (TIR at the film/air interface): R = 1, not 0/0.
        let w = Slab { n: 1.33, alpha_per_mm: 0.0, thickness_mm: 0.001, k_fresnel: 0.0 };
        let c = Slab { n: 1.9, alpha_per_mm: 0.0, thickness_mm: 0.0005, k_fresnel: 0.0 };
        for st in [
            vec![Slab::semi_infinite(1.54), w, Slab::semi_infinite(1.0)],
            vec![Slab::semi_infinite(1.54), c, w, Slab::semi_infinite(1.0)],
        ] {
            assert_eq!(stack_rt(&st, 0.0), (1.0, 0.0));
        }
    }

    #[test]
    fn tir_through_a_film() {
        // From quartz through a water film to air beyond the air critical angle: total reflection.
        let w = Slab { n: 1.33, alpha_per_mm: 0.0, thickness_mm: 0.001, k_fresnel: 0.0 };
        let st = [Slab::semi_infinite(1.54), w, Slab::semi_infinite(1.0)];
        let (r, t) = stack_rt(&st, 0.5); // sin θ = 0.866, n sin θ = 1.33 > 1
        assert_eq!(t, 0.0);
        assert!((r - 1.0).abs() < 1e-12);
    }
}

//! Per-wavelength path weights of hero-wavelength spectral sampling (docs/transport.md,
//! "Spectral path sharing"; Wilkie et al. 2014, "Hero wavelength spectral sampling").
//!
//! One path is traced at a hero wavelength h chosen uniformly among the N wavelengths of a
//! group. Every random choice whose probability depends on the wavelength is made by the hero;
//! each wavelength j keeps the product P_j of the probabilities its own optics give to the
//! choices made, relative to the hero's: W_j = P_j / P_h · c (c a common scale). With the
//! balance heuristic over the N hero choices, the path's estimate for wavelength j is
//!
//!   F_j = f_j / ((1/N) Σᵢ pᵢ) = N P_j / Σᵢ Pᵢ = N W_j / Σᵢ Wᵢ   (≤ N: bounded weights),
//!
//! times the path's indicator (escaped, transmitted). An event type plugs in with one call:
//! a discrete choice with probability p_j(outcome) calls `scale(|j| p_j / p_h)`; survival of an
//! attenuation exp(−α_j L) (the hero drew it with α_h) calls `attenuate(|j| α_j − α_h, L)`,
//! which defers the exponentials to the end of the path.

/// Above this a rescale of all weights keeps the products finite (the estimate N W_j / Σ Wᵢ
/// does not depend on a common factor).
const RESCALE_ABOVE: f64 = 1e100;

/// The weights of one path over the N wavelengths of a group.
#[derive(Clone, Debug, PartialEq)]
pub struct SpectralWeights {
    hero: usize,
    /// W_j: products of probability ratios (common scale arbitrary).
    w: Vec<f64>,
    /// D_j = Σ (α_j − α_h) L: optical-depth differences of the survived attenuations.
    depth: Vec<f64>,
    rescaled: bool,
}

impl SpectralWeights {
    /// Weights 1 for `n` wavelengths with hero `hero` (< n).
    pub fn new(n: usize, hero: usize) -> SpectralWeights {
        assert!(hero < n, "hero {hero} of {n} wavelengths");
        SpectralWeights { hero, w: vec![1.0; n], depth: vec![0.0; n], rescaled: false }
    }

    /// Starts a new path with hero `hero`, keeping the allocation.
    #[inline]
    pub fn reset(&mut self, hero: usize) {
        debug_assert!(hero < self.w.len());
        self.hero = hero;
        self.w.fill(1.0);
        self.depth.fill(0.0);
        self.rescaled = false;
    }

    #[inline]
    pub fn hero(&self) -> usize {
        self.hero
    }

    #[inline]
    pub fn len(&self) -> usize {
        self.w.len()
    }

    #[inline]
    pub fn is_empty(&self) -> bool {
        self.w.is_empty()
    }

    /// A discrete choice made by the hero: W_j ← W_j · ratio(j), with ratio(j) = p_j / p_h the
    /// probability wavelength j gives the outcome over the hero's (1 for the hero).
    #[inline]
    pub fn scale(&mut self, mut ratio: impl FnMut(usize) -> f64) {
        let mut max = 0.0f64;
        for (j, w) in self.w.iter_mut().enumerate() {
            *w *= ratio(j);
            max = max.max(*w);
        }
        if max > RESCALE_ABOVE {
            self.w.iter_mut().for_each(|w| *w /= max);
            self.rescaled = true;
        }
    }

    /// Survival of an attenuation over length `len` (mm) that the hero drew with its own
    /// coefficient: the ratio exp(−(α_j − α_h) L), with `excess(j)` = α_j − α_h (mm⁻¹),
    /// accumulated as optical depth and applied in `estimates`.
    #[inline]
    pub fn attenuate(&mut self, mut excess: impl FnMut(usize) -> f64, len: f64) {
        for (j, d) in self.depth.iter_mut().enumerate() {
            *d += excess(j) * len;
        }
    }

    /// The path's balance-heuristic estimates F_j = N W_j e^{−D_j} / Σᵢ Wᵢ e^{−Dᵢ} (each in
    /// [0, N]) into `out`.
    pub fn estimates(&self, out: &mut [f64]) {
        let n = self.w.len() as f64;
        let d_min = self.depth.iter().copied().fold(f64::INFINITY, f64::min);
        if !self.rescaled && d_min > -200.0 {
            // W ≤ 1e100 and e^{−D} ≤ e^{200}: no overflow; the hero's term (W_h e^{0} = 1
            // times ratios of one) keeps the sum positive.
            for ((o, &w), &d) in out.iter_mut().zip(&self.w).zip(&self.depth) {
                *o = w * (-d).exp();
            }
        } else {
            // In logarithms, relative to the largest term.
            for ((o, &w), &d) in out.iter_mut().zip(&self.w).zip(&self.depth) {
                *o = w.ln() - d;
            }
            let top = out.iter().copied().fold(f64::NEG_INFINITY, f64::max);
            out.iter_mut().for_each(|o| *o = (*o - top).exp());
        }
        let sum: f64 = out.iter().sum();
        out.iter_mut().for_each(|o| *o *= n / sum);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn equal_probabilities_give_every_wavelength_the_weight_one() {
        let mut w = SpectralWeights::new(4, 2);
        w.scale(|_| 1.0);
        w.attenuate(|_| 0.0, 3.0);
        let mut out = [0.0; 4];
        w.estimates(&mut out);
        assert_eq!(out, [1.0; 4]);
    }

    #[test]
    fn estimates_are_the_balance_heuristic_of_the_path_probabilities() {
        // Two choices with probabilities p_j and a survival exp(−α_j L): P_j = p_j q_j e^{−α_j L};
        // F_j = N P_j / Σ P_i whatever the hero.
        let p = [0.2, 0.5, 0.9];
        let q = [0.7, 0.1, 0.4];
        let alpha = [0.0f64, 2.0, 0.5];
        let len = 0.8;
        let big_p: Vec<f64> = (0..3).map(|j| p[j] * q[j] * (-alpha[j] * len).exp()).collect();
        let total: f64 = big_p.iter().sum();
        for hero in 0..3 {
            let mut w = SpectralWeights::new(3, hero);
            w.scale(|j| p[j] / p[hero]);
            w.scale(|j| q[j] / q[hero]);
            w.attenuate(|j| alpha[j] - alpha[hero], len);
            let mut out = [0.0; 3];
            w.estimates(&mut out);
            for j in 0..3 {
                assert!((out[j] - 3.0 * big_p[j] / total).abs() < 1e-14, "hero {hero}: {out:?}");
            }
        }
    }

    #[test]
    fn extreme_ratios_stay_finite_and_bounded() {
        // 400 choices at which the companion is 10× likelier than the hero, and an attenuation
        // far below the hero's: products beyond f64 range, estimates still in [0, N].
        let mut w = SpectralWeights::new(2, 0);
        for _ in 0..400 {
            w.scale(|j| if j == 1 { 10.0 } else { 1.0 });
        }
        w.attenuate(|j| if j == 1 { -1e4 } else { 0.0 }, 1.0);
        let mut out = [0.0; 2];
        w.estimates(&mut out);
        assert_eq!(out, [0.0, 2.0]);
        w.reset(1);
        w.attenuate(|j| if j == 0 { 1e6 } else { 0.0 }, 1.0);
        w.estimates(&mut out);
        assert_eq!(out, [0.0, 2.0]);
    }
}

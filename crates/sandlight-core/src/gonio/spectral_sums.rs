//! Fixed-point sums of a goniophotometer run whose trials share their paths over a group of
//! wavelengths (docs/transport.md, "Spectral path sharing"; paper §3.2.1).
//!
//! A trial's estimate for wavelength k is F_k ∈ [0, N] (`spectral`, the balance heuristic of
//! hero-wavelength sampling); an independent trial's would be its indicator, 0 or 1. The BRDF
//! estimate is f_k[i, j] = Σ F_k / (ω_p(j) N_i) over the trials of incoming patch i that escaped
//! into patch j, and its variance needs Σ F_k² there too (for indicators Σ F² = Σ F, the count).
//! Both enter as integers, so sums are exact and the same for any thread count or batching: F_k
//! as q = round(F_k · 2³²) (`hero::FIXED_ONE`, as in the reflectance tallies), summed in u64 (a
//! cell holds up to 2³² trial weights of F ≤ 1: 4.3·10⁹, far above any run's trials per cell;
//! 2²⁴ at the largest F of a 16-wavelength group), and F_k² as q² = F_k² · 2⁶⁴ exactly, summed
//! in u128 held as two u64 words (high, low). Exactness matters for the squares: a dark companion
//! behind bright heroes has weights of 10⁻³ and less in the cells only long paths reach, and a
//! rounded square at 2¹⁶ (until 2026-12-07), then 2³², added 0 for every weight below 2^−8.5,
//! then 2^−16.5, so those cells' standard errors collapsed (docs/transport.md). An addition that
//! would overflow is an error, never a wrap.
//!
//! The caller owns the arrays (the Python package keeps them across batches and checkpoints),
//! so a run keeps one set whatever the number of threads: 24 bytes per (incoming patch,
//! outgoing patch, wavelength), 19 MB per wavelength at the paper's 901 patches. Uniform
//! incidence has as many incoming patches as outgoing ones; the classic (fixed-incidence)
//! instrument has one, its incident direction.

use crate::error::SandlightError;

/// Fixed-point scale of the squares: F² counts as q² = F² · 2⁶⁴ exactly (q = round(F · 2³²)),
/// summed in u128; ≤ 2⁷² per trial for F ≤ N = 16.
pub const SQUARE_ONE: f64 = 18_446_744_073_709_551_616.0;

/// How a trial ended, as the goniophotometer tallies it.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Outcome {
    /// Escaped into this outgoing patch.
    Escaped(usize),
    Absorbed,
    /// Transmitted through the bottom of a finite sample.
    Transmitted,
    /// Stopped by the event cap.
    Capped,
}

/// The sums of a shared run over n incoming patches, r outgoing patches and w wavelengths,
/// borrowed from their owner (row-major; n = r for uniform incidence, 1 for a fixed incident
/// direction; [`SpectralBrdfSums::check`] tests the sizes).
#[derive(Debug)]
pub struct SpectralBrdfSums<'a> {
    /// Σ round(F_k · 2³²) over trials of incoming patch i escaped into patch j, at (i r + j) w + k.
    pub escaped: &'a mut [u64],
    /// Σ q_k² (q_k = round(F_k · 2³²)) as a u128 in two u64 words, high then low, at
    /// 2((i r + j) w + k) and the next.
    pub squares: &'a mut [u64],
    /// Σ round(F_k · 2³²) over trials of incoming patch i transmitted through the bottom, at i w + k.
    pub transmitted: &'a mut [u64],
    /// All trials of incoming patch i (shared by the wavelengths).
    pub launched: &'a mut [u64],
    /// Trials of incoming patch i stopped by the event cap (no estimate).
    pub capped: &'a mut [u64],
}

impl SpectralBrdfSums<'_> {
    /// Ok if the arrays are sized for `n_incoming` incoming patches, `n_patches` outgoing
    /// patches and `n_wavelengths` wavelengths.
    ///
    /// # Errors
    /// `SandlightError::Parameter` naming the first array of the wrong length.
    pub fn check(&self, n_incoming: usize, n_patches: usize, n_wavelengths: usize) -> Result<(), SandlightError> {
        let (n, r, w) = (n_incoming, n_patches, n_wavelengths);
        let cells = "incoming × outgoing × wavelength";
        for (name, got, want, layout) in [
            ("escaped", self.escaped.len(), n * r * w, cells),
            ("squares", self.squares.len(), 2 * n * r * w, "incoming × outgoing × wavelength × (high, low)"),
            ("transmitted", self.transmitted.len(), n * w, "incoming × wavelength"),
            ("launched", self.launched.len(), n, "one per incoming patch"),
            ("capped", self.capped.len(), n, "one per incoming patch"),
        ] {
            if got != want {
                return Err(SandlightError::parameter(
                    name,
                    format!("{got} entries"),
                    &format!("{want} entries ({layout}; {n} incoming, {r} outgoing patches, {w} wavelengths)"),
                ));
            }
        }
        Ok(())
    }

    /// Adds a trial of incoming patch `i_in` with `outcome` and fixed-point estimates `q`
    /// (round(F_k · 2³²), one per wavelength of the sums; read only for an escape or a
    /// transmission). The sums must have passed [`SpectralBrdfSums::check`].
    ///
    /// # Errors
    /// `SandlightError::Parameter` ("escaped", "squares" or "transmitted") if a sum would exceed
    /// 2⁶⁴ − 1 (2¹²⁸ − 1 for the squares); nothing is added then.
    ///
    /// # Panics
    /// If a patch index is out of range (≥ n incoming, ≥ r outgoing: a caller bug).
    pub fn record(&mut self, i_in: usize, outcome: Outcome, q: &[u64]) -> Result<(), SandlightError> {
        let (n, w) = (self.launched.len(), q.len());
        assert!(i_in < n, "incoming patch {i_in} out of range 0..{n}");
        let r = self.escaped.len().checked_div(n * w).unwrap_or(0);
        match outcome {
            Outcome::Escaped(j) => {
                assert!(j < r, "outgoing patch {j} out of range 0..{r}");
                let cell = (i_in * r + j) * w..(i_in * r + j + 1) * w;
                let sq = &mut self.squares[2 * cell.start..2 * cell.end];
                let squared: Vec<u128> = sq
                    .chunks_exact(2)
                    .zip(q)
                    .map(|(s, &q)| {
                        (u128::from(s[0]) << 64 | u128::from(s[1])).checked_add(u128::from(q) * u128::from(q))
                    })
                    .collect::<Option<_>>()
                    .ok_or_else(|| overflow("squares", "2^128 - 1"))?;
                let escaped = &mut self.escaped[cell];
                fits("escaped", escaped, q.iter().copied())?;
                add(escaped, q.iter().copied());
                for (s, v) in sq.chunks_exact_mut(2).zip(squared) {
                    (s[0], s[1]) = ((v >> 64) as u64, v as u64);
                }
            }
            Outcome::Transmitted => {
                let sums = &mut self.transmitted[i_in * w..(i_in + 1) * w];
                fits("transmitted", sums, q.iter().copied())?;
                add(sums, q.iter().copied());
            }
            Outcome::Capped => self.capped[i_in] += 1,
            Outcome::Absorbed => {}
        }
        self.launched[i_in] += 1;
        Ok(())
    }
}

/// Ok if sums[k] + add[k] ≤ 2⁶⁴ − 1 for every k, else an error naming `name`.
fn fits(name: &str, sums: &[u64], add: impl Iterator<Item = u64>) -> Result<(), SandlightError> {
    if sums.iter().zip(add).all(|(s, a)| s.checked_add(a).is_some()) {
        Ok(())
    } else {
        Err(overflow(name, "2^64 - 1"))
    }
}

/// The error of a sum `name` that would exceed `limit`.
fn overflow(name: &str, limit: &str) -> SandlightError {
    SandlightError::parameter(
        name,
        format!("a sum beyond {limit}"),
        "at most 2^32 trial weights per cell: split the run into several measurements",
    )
}

fn add(sums: &mut [u64], add: impl Iterator<Item = u64>) {
    sums.iter_mut().zip(add).for_each(|(s, a)| *s += a);
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::hero::FIXED_ONE;

    struct Arrays {
        escaped: Vec<u64>,
        squares: Vec<u64>,
        transmitted: Vec<u64>,
        launched: Vec<u64>,
        capped: Vec<u64>,
    }

    impl Arrays {
        fn new(r: usize, w: usize) -> Arrays {
            Arrays {
                escaped: vec![0; r * r * w],
                squares: vec![0; 2 * r * r * w],
                transmitted: vec![0; r * w],
                launched: vec![0; r],
                capped: vec![0; r],
            }
        }

        fn sums(&mut self) -> SpectralBrdfSums<'_> {
            SpectralBrdfSums {
                escaped: &mut self.escaped,
                squares: &mut self.squares,
                transmitted: &mut self.transmitted,
                launched: &mut self.launched,
                capped: &mut self.capped,
            }
        }
    }

    #[test]
    fn records_land_in_their_cells_with_their_squares() {
        let (r, w) = (3, 2);
        let mut a = Arrays::new(r, w);
        let half = (0.5 * FIXED_ONE) as u64;
        let mut s = a.sums();
        s.check(r, r, w).unwrap();
        s.record(1, Outcome::Escaped(2), &[half, 3 * half]).unwrap();
        s.record(1, Outcome::Escaped(2), &[half, 0]).unwrap();
        s.record(0, Outcome::Transmitted, &[2 * half, half]).unwrap();
        s.record(2, Outcome::Capped, &[7, 7]).unwrap();
        s.record(2, Outcome::Absorbed, &[7, 7]).unwrap();
        let cell = (r + 2) * w;
        assert_eq!(a.escaped[cell..cell + 2], [2 * half, 3 * half]);
        // F = 0.5, 0.5 → Σ F² = 0.5; F = 1.5, 0 → 2.25 (times 2⁶⁴: high words 0 and 2, low 2⁶³ and 2⁶²).
        assert_eq!(a.squares[2 * cell..2 * cell + 4], [0, 1 << 63, 2, 1 << 62]);
        assert_eq!(2.25 * SQUARE_ONE, (2u128 << 64 | 1 << 62) as f64);
        assert_eq!(a.transmitted[..2], [2 * half, half]);
        assert_eq!((a.launched.as_slice(), a.capped.as_slice()), ([1, 2, 2].as_slice(), [0, 0, 1].as_slice()));
        assert_eq!(a.escaped.iter().filter(|&&e| e > 0).count(), 2);
    }

    #[test]
    fn wrong_lengths_and_overflow_are_errors_naming_the_array() {
        let mut a = Arrays::new(2, 2);
        for (r, w) in [(2, 3), (3, 2)] {
            let err = a.sums().check(r, r, w).unwrap_err();
            assert!(matches!(err, SandlightError::Parameter { ref name, .. } if name == "escaped"), "{err:?}");
        }
        // One incoming patch (fixed incidence) wants 2 × 2 escaped sums and one launched.
        let err = a.sums().check(1, 4, 2).unwrap_err();
        assert!(matches!(err, SandlightError::Parameter { ref name, .. } if name == "transmitted"), "{err:?}");
        a.sums().check(2, 2, 2).unwrap();
        a.escaped[0] = u64::MAX - 1;
        let mut s = a.sums();
        let err = s.record(0, Outcome::Escaped(0), &[2, 2]).unwrap_err();
        assert!(matches!(err, SandlightError::Parameter { ref name, .. } if name == "escaped"), "{err:?}");
        assert_eq!((a.escaped[0], a.escaped[1], a.launched[0]), (u64::MAX - 1, 0, 0));
        // A sum of squares beyond 2¹²⁸ − 1: refused, nothing added.
        a.escaped[0] = 0;
        (a.squares[0], a.squares[1]) = (u64::MAX, u64::MAX);
        let err = a.sums().record(0, Outcome::Escaped(0), &[1, 0]).unwrap_err();
        assert!(matches!(err, SandlightError::Parameter { ref name, .. } if name == "squares"), "{err:?}");
        assert_eq!((a.escaped[0], a.squares[0], a.squares[1], a.launched[0]), (0, u64::MAX, u64::MAX, 0));
    }

    #[test]
    fn squares_are_exact_for_the_smallest_weights_and_carry_into_the_high_word() {
        let mut a = Arrays::new(1, 1);
        let mut s = a.sums();
        // F = 2⁻³² (q = 1): F² = 2⁻⁶⁴, which any rounded scale below 2⁶⁴ would add as 0.
        for _ in 0..3 {
            s.record(0, Outcome::Escaped(0), &[1]).unwrap();
        }
        assert_eq!(a.squares[..2], [0, 3]);
        // q = 2³²·1.5 (F = 1.5): q² = 2.25·2⁶⁴ carries into the high word, also on top of a low word.
        let q = 3u64 << 31;
        a.sums().record(0, Outcome::Escaped(0), &[q]).unwrap();
        assert_eq!(a.squares[..2], [2, (1 << 62) + 3]);
        (a.squares[0], a.squares[1]) = (0, u64::MAX);
        a.sums().record(0, Outcome::Escaped(0), &[1]).unwrap();
        assert_eq!(a.squares[..2], [1, 0]);
    }
}

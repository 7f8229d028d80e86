//! Fixed-point sums of a goniophotometer run whose trials share their paths over a group of
//! wavelengths (docs/transport.md, "Spectral path sharing"; paper §3.2.1).
//!
//! A trial's estimate for wavelength k is F_k ∈ [0, N] (`spectral`, the balance heuristic of
//! hero-wavelength sampling); an independent trial's would be its indicator, 0 or 1. The BRDF
//! estimate is f_k[i, j] = Σ F_k / (ω_p(j) N_i) over the trials of incoming patch i that escaped
//! into patch j, and its variance needs Σ F_k² there too (for indicators Σ F² = Σ F, the count).
//! Both enter as integers (F_k as round(F_k · 2³²), `hero::FIXED_ONE`, as in the reflectance
//! tallies; F_k² as round(F_k² · 2³²)), so sums are exact and the same for any thread count or
//! batching. The squares need the weight sums' resolution: a dark companion behind bright heroes
//! has weights of 10⁻³ and less in the cells only long paths reach, and at the earlier scale 2¹⁶
//! every weight below 2^−8.5 added 0 to the squares, so those cells' standard errors collapsed
//! (docs/transport.md); at 2³² weights below 2^−16.5 (1.1·10⁻⁵) still do — exact squares would
//! need u128 sums. The sums are u64: a cell holds up to 2³² trial weights of F ≤ 1 (4.3·10⁹, far
//! above any run's trials per cell; 2²⁴ at the largest F of a 16-wavelength group), and an
//! addition that would overflow is an error, never a wrap.
//!
//! The caller owns the arrays (the Python package keeps them across batches and checkpoints),
//! so a run keeps one set whatever the number of threads: 16 bytes per (incoming patch,
//! outgoing patch, wavelength), 13 MB per wavelength at the paper's 901 patches. Uniform
//! incidence has as many incoming patches as outgoing ones; the classic (fixed-incidence)
//! instrument has one, its incident direction.

use crate::error::SandlightError;
use crate::hero::FIXED_ONE;

/// Fixed-point scale of the squares: F² ∈ [0, N²] counts as round(F² · 2³²) (≤ 2⁴⁰ for N ≤ 16).
pub const SQUARE_ONE: f64 = 4_294_967_296.0;

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
    /// Σ round(F_k² · 2³²), same layout.
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
            ("squares", self.squares.len(), n * r * w, cells),
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
    /// `SandlightError::Parameter` ("escaped" or "transmitted") if a sum would exceed 2⁶⁴ − 1;
    /// nothing is added then.
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
                let squares = q.iter().map(|&q| {
                    let f = q as f64 / FIXED_ONE;
                    (f * f * SQUARE_ONE).round() as u64
                });
                let (escaped, sq) = (&mut self.escaped[cell.clone()], &mut self.squares[cell]);
                fits("escaped", escaped, q.iter().copied())?;
                fits("squares", sq, squares.clone())?;
                add(escaped, q.iter().copied());
                add(sq, squares);
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
        Err(SandlightError::parameter(
            name,
            "a sum beyond 2^64 - 1",
            "at most 2^32 trial weights per cell: split the run into several measurements",
        ))
    }
}

fn add(sums: &mut [u64], add: impl Iterator<Item = u64>) {
    sums.iter_mut().zip(add).for_each(|(s, a)| *s += a);
}

#[cfg(test)]
mod tests {
    use super::*;

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
                squares: vec![0; r * r * w],
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
        // F = 0.5, 0.5 → Σ F² = 0.5; F = 1.5, 0 → 2.25.
        assert_eq!(a.squares[cell..cell + 2], [(0.5 * SQUARE_ONE) as u64, (2.25 * SQUARE_ONE) as u64]);
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
    }
}

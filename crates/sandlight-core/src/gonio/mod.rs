//! The virtual goniophotometer of paper §3.2.1: a collector hemisphere divided into patches of
//! equal solid angle, and the counters a transport driver fills while it traces trials.
//!
//! - [`CollectorHemisphere`]: patch geometry (index ↔ direction, centroid, bounds, solid angle,
//!   projected solid angle, uniform sampling inside a patch).
//! - [`BrdfTally`]: r × r counters n[i, j] for incoming patch i and outgoing patch j, plus absorbed,
//!   lost and launched counters per incoming patch (incidence drawn uniformly over the
//!   hemisphere).
//! - [`FixedIncidenceTally`]: the classic goniophotometer, one incident direction.
//! - [`SpectralBrdfSums`]: fixed-point sums per (incoming patch, outgoing patch, wavelength) of
//!   a run whose trials share their paths over a group of wavelengths.
//!
//! Tallies are per thread; the driver merges them at the end, so the result does not depend on
//! the number of threads as long as each trial's random stream does not.

pub mod hemisphere;
pub mod measure;
pub mod spectral_sums;
pub mod tally;

pub use hemisphere::{CollectorHemisphere, PatchBounds};
pub use spectral_sums::SpectralBrdfSums;
pub use tally::{BrdfTally, FixedIncidenceTally};

//! Counters of the virtual goniophotometer (paper §3.2.1).
//!
//! A transport driver keeps one tally per thread, ends every trial with exactly one `record_*`
//! call (which also counts the trial as launched), and merges the tallies when the threads are
//! done. Counts are integers, so the merged result is the same whatever the number of threads
//! or the merge order.
//!
//! The BRDF estimate from these counts is f[i, j] = n[i, j] / (ω_p(j) N_i), with N_i =
//! `launched[i]` (escaped + absorbed + lost); the reduction lives in the Python package.

use crate::error::SandlightError;
use crate::gonio::hemisphere::CollectorHemisphere;

/// Largest number of patches a [`BrdfTally`] accepts: its r × r u64 counters take 8·r² bytes per
/// thread, 537 MB at this limit (6.5 MB for the paper's 901 patches).
pub const MAX_TALLY_PATCHES: usize = 8_192;

/// Counters for the full BRDF: incidence drawn uniformly over the hemisphere, one row per
/// incoming patch.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct BrdfTally {
    /// Number of patches r of the collector hemisphere (incoming and outgoing).
    pub n_patches: usize,
    /// n[i, j]: trials with incidence in patch i that escaped into patch j; row-major, index
    /// i·r + j, length r².
    pub counts: Vec<u64>,
    /// Trials with incidence in patch i that ended absorbed.
    pub absorbed: Vec<u64>,
    /// All trials with incidence in patch i: escaped + absorbed + lost.
    pub launched: Vec<u64>,
    /// Trials with incidence in patch i that were neither tallied nor absorbed: stopped by the
    /// event cap, or transmitted through the bottom of a finite sample.
    pub lost: Vec<u64>,
}

impl BrdfTally {
    /// Zeroed counters for `n_patches` patches.
    ///
    /// # Errors
    /// `SandlightError::Parameter` unless 1 ≤ n_patches ≤ [`MAX_TALLY_PATCHES`].
    pub fn new(n_patches: usize) -> Result<Self, SandlightError> {
        if !(1..=MAX_TALLY_PATCHES).contains(&n_patches) {
            return Err(SandlightError::parameter(
                "n_patches",
                n_patches,
                &format!("must be an integer in [1, {MAX_TALLY_PATCHES}] (the counters take 8·r² bytes per thread)"),
            ));
        }
        Ok(BrdfTally {
            n_patches,
            counts: vec![0; n_patches * n_patches],
            absorbed: vec![0; n_patches],
            launched: vec![0; n_patches],
            lost: vec![0; n_patches],
        })
    }

    /// Zeroed counters sized for `hemisphere`.
    ///
    /// # Errors
    /// As [`BrdfTally::new`] when the hemisphere has more than [`MAX_TALLY_PATCHES`] patches.
    pub fn for_hemisphere(hemisphere: &CollectorHemisphere) -> Result<Self, SandlightError> {
        Self::new(hemisphere.n_patches())
    }

    /// A trial with incidence in patch `i_in` escaped into patch `j_out`.
    ///
    /// # Panics
    /// If an index is ≥ n_patches (a caller bug).
    #[inline]
    pub fn record_escape(&mut self, i_in: usize, j_out: usize) {
        assert!(j_out < self.n_patches, "outgoing patch {j_out} out of range 0..{}", self.n_patches);
        self.counts[i_in * self.n_patches + j_out] += 1;
        self.launched[i_in] += 1;
    }

    /// A trial with incidence in patch `i_in` was absorbed.
    ///
    /// # Panics
    /// If `i_in` ≥ n_patches.
    #[inline]
    pub fn record_absorbed(&mut self, i_in: usize) {
        self.absorbed[i_in] += 1;
        self.launched[i_in] += 1;
    }

    /// A trial with incidence in patch `i_in` was lost (event cap reached, or transmitted through
    /// the bottom of the sample).
    ///
    /// # Panics
    /// If `i_in` ≥ n_patches.
    #[inline]
    pub fn record_lost(&mut self, i_in: usize) {
        self.lost[i_in] += 1;
        self.launched[i_in] += 1;
    }

    /// n[i, j].
    pub fn count(&self, i_in: usize, j_out: usize) -> u64 {
        assert!(j_out < self.n_patches, "outgoing patch {j_out} out of range 0..{}", self.n_patches);
        self.counts[i_in * self.n_patches + j_out]
    }

    /// Trials with incidence in patch `i_in` that escaped, Σ_j n[i, j].
    pub fn escaped(&self, i_in: usize) -> u64 {
        self.counts[i_in * self.n_patches..(i_in + 1) * self.n_patches].iter().sum()
    }

    /// All trials recorded, Σ_i N_i.
    pub fn total_launched(&self) -> u64 {
        self.launched.iter().sum()
    }

    /// Bytes held by the counters.
    pub fn memory_bytes(&self) -> usize {
        8 * (self.counts.len() + self.absorbed.len() + self.launched.len() + self.lost.len())
    }

    /// Adds the counters of `other` (another thread's tally) to these.
    ///
    /// # Errors
    /// `SandlightError::Parameter` if the two tallies have different numbers of patches.
    pub fn merge(&mut self, other: &BrdfTally) -> Result<(), SandlightError> {
        same_patches(self.n_patches, other.n_patches)?;
        add_into(&mut self.counts, &other.counts);
        add_into(&mut self.absorbed, &other.absorbed);
        add_into(&mut self.launched, &other.launched);
        add_into(&mut self.lost, &other.lost);
        Ok(())
    }
}

/// Counters of the classic goniophotometer: one fixed incident direction, a counter per outgoing
/// patch. f_j = n_j / (ω_p(j) N) with N = `launched`.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct FixedIncidenceTally {
    /// Number of outgoing patches r.
    pub n_patches: usize,
    /// n_j: trials that escaped into patch j.
    pub counts: Vec<u64>,
    /// Trials absorbed.
    pub absorbed: u64,
    /// All trials: escaped + absorbed + lost.
    pub launched: u64,
    /// Trials stopped by the event cap or transmitted through the bottom.
    pub lost: u64,
}

impl FixedIncidenceTally {
    /// Zeroed counters for `n_patches` outgoing patches.
    ///
    /// # Errors
    /// `SandlightError::Parameter` unless n_patches ≥ 1.
    pub fn new(n_patches: usize) -> Result<Self, SandlightError> {
        if n_patches == 0 {
            return Err(SandlightError::parameter("n_patches", n_patches, "must be an integer ≥ 1"));
        }
        Ok(FixedIncidenceTally { n_patches, counts: vec![0; n_patches], absorbed: 0, launched: 0, lost: 0 })
    }

    /// Zeroed counters sized for `hemisphere`.
    pub fn for_hemisphere(hemisphere: &CollectorHemisphere) -> Self {
        FixedIncidenceTally {
            n_patches: hemisphere.n_patches(),
            counts: vec![0; hemisphere.n_patches()],
            absorbed: 0,
            launched: 0,
            lost: 0,
        }
    }

    /// A trial escaped into patch `j_out`.
    ///
    /// # Panics
    /// If `j_out` ≥ n_patches.
    #[inline]
    pub fn record_escape(&mut self, j_out: usize) {
        self.counts[j_out] += 1;
        self.launched += 1;
    }

    /// A trial was absorbed.
    #[inline]
    pub fn record_absorbed(&mut self) {
        self.absorbed += 1;
        self.launched += 1;
    }

    /// A trial was lost (event cap, or transmitted through the bottom).
    #[inline]
    pub fn record_lost(&mut self) {
        self.lost += 1;
        self.launched += 1;
    }

    /// Adds the counters of `other` to these.
    ///
    /// # Errors
    /// `SandlightError::Parameter` if the two tallies have different numbers of patches.
    pub fn merge(&mut self, other: &FixedIncidenceTally) -> Result<(), SandlightError> {
        same_patches(self.n_patches, other.n_patches)?;
        add_into(&mut self.counts, &other.counts);
        self.absorbed += other.absorbed;
        self.launched += other.launched;
        self.lost += other.lost;
        Ok(())
    }
}

/// Refuses to merge a tally of `other` patches into one of `own`.
fn same_patches(own: usize, other: usize) -> Result<(), SandlightError> {
    if other == own {
        Ok(())
    } else {
        Err(SandlightError::parameter(
            "other.n_patches",
            other,
            &format!("must equal the n_patches of the tally merged into ({own})"),
        ))
    }
}

fn add_into(acc: &mut [u64], other: &[u64]) {
    for (a, b) in acc.iter_mut().zip(other) {
        *a += *b;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A deterministic stream of trial outcomes: (incoming, outcome) where outcome < r is an
    /// escape, r is absorption and r + 1 is loss.
    fn outcomes(n: usize, r: usize, seed: u64) -> Vec<(usize, usize)> {
        let mut state = seed;
        (0..n)
            .map(|_| {
                state = state.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
                let a = (state >> 33) as usize;
                (a % r, (a / r) % (r + 2))
            })
            .collect()
    }

    fn record(t: &mut BrdfTally, (i, o): (usize, usize)) {
        let r = t.n_patches;
        match o {
            o if o < r => t.record_escape(i, o),
            o if o == r => t.record_absorbed(i),
            _ => t.record_lost(i),
        }
    }

    #[test]
    fn paper_tally_memory_is_6_5_mb() {
        let t = BrdfTally::for_hemisphere(&CollectorHemisphere::paper()).unwrap();
        assert_eq!(t.counts.len(), 901 * 901);
        assert_eq!(t.memory_bytes(), 8 * (901 * 901 + 3 * 901));
        assert!(t.memory_bytes() < 6_600_000);
    }

    #[test]
    fn launched_counts_every_outcome() {
        let r = 10;
        let mut t = BrdfTally::new(r).unwrap();
        for o in outcomes(10_000, r, 1) {
            record(&mut t, o);
        }
        assert_eq!(t.total_launched(), 10_000);
        for i in 0..r {
            assert_eq!(t.launched[i], t.escaped(i) + t.absorbed[i] + t.lost[i]);
        }
    }

    #[test]
    fn merging_split_streams_equals_one_stream_in_any_order() {
        let r = 7;
        let stream = outcomes(20_000, r, 9);
        let mut whole = BrdfTally::new(r).unwrap();
        stream.iter().for_each(|&o| record(&mut whole, o));
        // Four "threads" with uneven shares, merged in reverse order.
        let cuts = [0, 3_000, 3_001, 12_000, 20_000];
        let parts: Vec<BrdfTally> = cuts
            .windows(2)
            .map(|w| {
                let mut t = BrdfTally::new(r).unwrap();
                stream[w[0]..w[1]].iter().for_each(|&o| record(&mut t, o));
                t
            })
            .collect();
        let mut merged = BrdfTally::new(r).unwrap();
        for p in parts.iter().rev() {
            merged.merge(p).unwrap();
        }
        assert_eq!(merged, whole);
        assert!(whole.counts.iter().all(|&n| n > 0));
    }

    #[test]
    fn merging_different_sizes_is_an_error() {
        let mut a = BrdfTally::new(3).unwrap();
        let b = BrdfTally::new(4).unwrap();
        assert!(matches!(a.merge(&b), Err(SandlightError::Parameter { .. })));
        let mut c = FixedIncidenceTally::new(3).unwrap();
        assert!(matches!(c.merge(&FixedIncidenceTally::new(5).unwrap()), Err(SandlightError::Parameter { .. })));
        assert!(BrdfTally::new(0).is_err());
        assert!(BrdfTally::new(MAX_TALLY_PATCHES + 1).is_err());
        assert!(FixedIncidenceTally::new(0).is_err());
    }

    #[test]
    fn fixed_incidence_merge_adds_counts() {
        let r = 5;
        let stream = outcomes(5_000, r, 4);
        let mut whole = FixedIncidenceTally::new(r).unwrap();
        let mut a = FixedIncidenceTally::new(r).unwrap();
        let mut b = FixedIncidenceTally::new(r).unwrap();
        for (k, &(_, o)) in stream.iter().enumerate() {
            for t in [&mut whole, if k % 3 == 0 { &mut a } else { &mut b }] {
                match o {
                    o if o < r => t.record_escape(o),
                    o if o == r => t.record_absorbed(),
                    _ => t.record_lost(),
                }
            }
        }
        a.merge(&b).unwrap();
        assert_eq!(a, whole);
        assert_eq!(whole.launched, 5_000);
        assert_eq!(whole.launched, whole.counts.iter().sum::<u64>() + whole.absorbed + whole.lost);
        assert!(whole.absorbed > 0 && whole.lost > 0);
    }
}

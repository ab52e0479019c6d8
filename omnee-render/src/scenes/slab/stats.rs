//! Counters of the work a slab render or probe did and skipped (reported
//! by `omnee render --json` and `omnee probe`).

/// Counters of the work done and skipped, summed over a run.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct SlabStats {
    /// Once-more connections set up (an `x0` chosen).
    pub connections: u64,
    /// Connections not sampled: the θ < θmax region cannot reach the slab.
    pub skipped_unreachable: u64,
    /// Technique draws whose own vertex was missing (no `x1` from its numbers).
    pub no_vertex: u64,
    /// Contributions below the Russian roulette threshold that were dropped.
    pub roulette_dropped: u64,
    /// Contributions below the threshold that survived (and were boosted).
    pub roulette_kept: u64,
    /// Occluder (visibility) tests done.
    pub visibility_tests: u64,
}

impl crate::render::Counters for SlabStats {
    fn add(&mut self, o: &SlabStats) {
        self.connections += o.connections;
        self.skipped_unreachable += o.skipped_unreachable;
        self.no_vertex += o.no_vertex;
        self.roulette_dropped += o.roulette_dropped;
        self.roulette_kept += o.roulette_kept;
        self.visibility_tests += o.visibility_tests;
    }
}

//! When a render stops: after a number of samples per pixel, or before a
//! pass that would not fit a time budget.

/// When to stop.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum RenderBudget {
    /// This many samples per pixel.
    Spp(u32),
    /// As many whole passes as fit in this many seconds (at least one).
    Seconds(f64),
}

/// The most samples per pixel (passes) of a render, `2²⁴`, also with a
/// time budget.
pub const MAX_SPP: u32 = 1 << 24;

/// The most samples of a render, `2⁴⁰` (the window's pixels times the
/// passes; days of a core, like an estimate's [`crate::point::estimate::MAX_SAMPLES`]).
pub const MAX_RENDER_SAMPLES: u64 = 1 << 40;

/// The longest time budget, a week (604 800 s).
pub const MAX_SECONDS: f64 = 604_800.0;

impl RenderBudget {
    /// Whether to stop after `passes` passes (≥ 1) that took `elapsed`
    /// seconds: a time budget stops when one more pass of the mean length
    /// so far would not fit, or after [`MAX_SPP`] passes.
    pub fn done(self, passes: u32, elapsed: f64) -> bool {
        match self {
            RenderBudget::Spp(n) => passes >= n,
            RenderBudget::Seconds(s) => passes >= MAX_SPP || elapsed + elapsed / passes as f64 > s,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn budgets_stop_after_their_passes_or_before_overrunning() {
        assert!(!RenderBudget::Spp(3).done(2, 100.0));
        assert!(RenderBudget::Spp(3).done(3, 0.0));
        // Two passes of 1 s each: a third would end at 3 s.
        assert!(!RenderBudget::Seconds(3.0).done(2, 2.0));
        assert!(RenderBudget::Seconds(2.9).done(2, 2.0));
        assert!(!RenderBudget::Seconds(1e5).done(MAX_SPP - 1, 1.0));
        assert!(RenderBudget::Seconds(1e5).done(MAX_SPP, 1.0));
    }
}

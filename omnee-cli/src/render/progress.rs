//! The render's progress bar on stderr (indicatif): rows of the current
//! pass for a sample budget, elapsed seconds for a time budget.

use super::budget::Budget;
use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};

/// A progress bar for one render.
pub struct Progress {
    bar: ProgressBar,
    budget: Budget,
    rows_per_pass: u64,
}

impl Progress {
    /// A bar for `budget`, with `rows_per_pass` rows in each pass; drawn on
    /// stderr when it is a terminal (indicatif hides it otherwise).
    pub fn start(budget: Budget, rows_per_pass: u64) -> Self {
        let rows_per_pass = rows_per_pass.max(1);
        let (length, template) = match budget {
            Budget::Spp(n) => (
                u64::from(n) * rows_per_pass,
                "[{bar:30}] {percent:>3}% {msg} spp, {elapsed_precise}, ETA {eta}",
            ),
            // Milliseconds of the budget.
            Budget::Seconds(s) => (
                (s * 1e3).ceil() as u64,
                "[{bar:30}] {percent:>3}% {msg} spp, {elapsed_precise} of the budget",
            ),
        };
        let bar = ProgressBar::with_draw_target(Some(length), ProgressDrawTarget::stderr());
        if let Ok(style) = ProgressStyle::with_template(template) {
            bar.set_style(style.progress_chars("#>-"));
        }
        let progress = Self {
            bar,
            budget,
            rows_per_pass,
        };
        progress.pass(0);
        progress
    }

    /// `rows` rows are done in total, over all passes.
    pub fn rows(&self, rows: u64) {
        match self.budget {
            Budget::Spp(_) => self.bar.set_position(rows),
            Budget::Seconds(_) => self.bar.set_position(self.bar.elapsed().as_millis() as u64),
        }
    }

    /// `passes` whole passes are done.
    pub fn pass(&self, passes: u32) {
        let total = match self.budget {
            Budget::Spp(n) => format!("/{n}"),
            Budget::Seconds(_) => String::new(),
        };
        self.bar.set_message(format!("{passes}{total}"));
        if let Budget::Spp(_) = self.budget {
            self.bar
                .set_position(u64::from(passes) * self.rows_per_pass);
        }
    }

    /// Draws the final state and leaves it on screen.
    pub fn finish(self) {
        if let Budget::Seconds(_) = self.budget {
            self.bar.set_position(self.bar.length().unwrap_or(0));
        }
        self.bar.finish();
        if !self.bar.is_hidden() {
            eprintln!();
        }
    }
}

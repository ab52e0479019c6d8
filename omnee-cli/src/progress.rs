//! The render's progress bar on stderr (indicatif), fed by the render
//! loop's reports: work items of the passes for a sample budget, elapsed
//! seconds for a time budget.

use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};
use omnee_render::render::Progress;
use omnee_render::render::budget::RenderBudget;

/// A progress bar for one render.
pub struct Bar {
    bar: ProgressBar,
    budget: RenderBudget,
}

impl Bar {
    /// A bar for `budget`, drawn on stderr when it is a terminal (indicatif
    /// hides it otherwise).
    pub fn start(budget: RenderBudget) -> Self {
        let template = match budget {
            RenderBudget::Spp(_) => {
                "[{bar:30}] {percent:>3}% {msg} spp, {elapsed_precise}, ETA {eta}"
            }
            RenderBudget::Seconds(_) => {
                "[{bar:30}] {percent:>3}% {msg} spp, {elapsed_precise} of the budget"
            }
        };
        let bar = ProgressBar::with_draw_target(None, ProgressDrawTarget::stderr());
        if let Ok(style) = ProgressStyle::with_template(template) {
            bar.set_style(style.progress_chars("#>-"));
        }
        Self { bar, budget }
    }

    /// Shows the render's state `p`.
    pub fn report(&self, p: Progress) {
        let total = match self.budget {
            RenderBudget::Spp(n) => {
                self.bar.set_length(u64::from(n) * p.items_per_pass.max(1));
                self.bar.set_position(p.items);
                format!("/{n}")
            }
            RenderBudget::Seconds(s) => {
                self.bar.set_length((s * 1e3).ceil() as u64);
                self.bar.set_position((p.seconds * 1e3) as u64);
                String::new()
            }
        };
        self.bar.set_message(format!("{}{total}", p.passes));
    }

    /// Draws the final state and leaves it on screen.
    pub fn finish(self) {
        if let RenderBudget::Seconds(_) = self.budget {
            self.bar.set_position(self.bar.length().unwrap_or(0));
        }
        self.bar.finish();
        if !self.bar.is_hidden() {
            eprintln!();
        }
    }
}

//! A progress bar on stderr: a row counter that a render's threads bump and
//! a line redrawn at most ten times a second.

use crate::render::Budget;
use std::io::Write;
use std::sync::Mutex;
use std::time::Instant;

/// The state of the bar.
pub struct Progress {
    budget: Budget,
    rows_per_pass: u64,
    start: Instant,
    state: Mutex<State>,
}

struct State {
    last_draw: f64,
    passes: u32,
    rows: u64,
}

impl Progress {
    /// A bar for `budget`, with `rows_per_pass` rows in each pass.
    pub fn start(budget: Budget, rows_per_pass: u64) -> Self {
        Progress {
            budget,
            rows_per_pass: rows_per_pass.max(1),
            start: Instant::now(),
            state: Mutex::new(State {
                last_draw: -1.0,
                passes: 0,
                rows: 0,
            }),
        }
    }

    /// `rows` rows are done in total (all passes).
    pub fn rows(&self, rows: u64) {
        if let Ok(mut s) = self.state.lock() {
            s.rows = s.rows.max(rows);
            self.draw(&mut s, false);
        }
    }

    /// `passes` whole passes are done.
    pub fn pass(&self, passes: u32) {
        if let Ok(mut s) = self.state.lock() {
            s.passes = passes;
            self.draw(&mut s, false);
        }
    }

    /// Draws the final state and ends the line.
    pub fn finish(self) {
        if let Ok(mut s) = self.state.lock() {
            self.draw(&mut s, true);
        }
        eprintln!();
    }

    fn draw(&self, s: &mut State, force: bool) {
        let t = self.start.elapsed().as_secs_f64();
        if !force && t - s.last_draw < 0.1 {
            return;
        }
        s.last_draw = t;
        let passes_f = s.rows as f64 / self.rows_per_pass as f64;
        let (fraction, tail) = match self.budget {
            Budget::Spp(n) => {
                let f = passes_f / n as f64;
                let eta = if f > 0.0 { t / f - t } else { 0.0 };
                (f, format!("{}/{n} spp, {t:.1} s, ETA {eta:.1} s", s.passes))
            }
            Budget::Seconds(b) => (t / b, format!("{} spp, {t:.1}/{b:.1} s", s.passes)),
        };
        let width = 30;
        let filled = ((fraction.clamp(0.0, 1.0)) * width as f64).round() as usize;
        let mut err = std::io::stderr().lock();
        let _ = write!(
            err,
            "\r[{}{}] {:3.0}% {tail}   ",
            "#".repeat(filled),
            "-".repeat(width - filled),
            100.0 * fraction.clamp(0.0, 1.0)
        );
        let _ = err.flush();
    }
}

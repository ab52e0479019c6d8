//! A technique's measured run time against error: one point per sample
//! count (samples per estimate, or samples per pixel), and what the tables
//! read off it, the efficiency and the error at a given time.
//!
//! Both readings stay inside what was measured: a budget outside the
//! measured times or an efficiency without a point to take it from is
//! `None` (printed `–`), never a NaN and never an extrapolation.

/// One measurement: `count` samples (per estimate or per pixel), the CPU
/// and wall seconds they took, and the relative mean squared error of the
/// result.
#[derive(Clone, Copy, Debug)]
pub struct Point {
    pub count: u64,
    pub cpu_seconds: f64,
    pub wall_seconds: f64,
    pub rel_mse: f64,
}

/// The points of one technique, in increasing `count`, and the CPU clock's
/// resolution: times below it are read as it (the slab bench's child CPU
/// time comes in 10 ms ticks).
#[derive(Clone, Debug, Default)]
pub struct Curve {
    pub points: Vec<Point>,
    pub resolution: f64,
}

impl Curve {
    /// An empty curve for a clock of `resolution` seconds.
    pub fn new(resolution: f64) -> Self {
        Self {
            points: Vec::new(),
            resolution,
        }
    }

    /// The CPU time of `p` as the readings use it, at least the resolution.
    pub fn seconds(&self, p: &Point) -> f64 {
        p.cpu_seconds.max(self.resolution)
    }

    /// `(seconds, relMSE)` of every point, for the figures.
    pub fn time_error(&self) -> Vec<(f64, f64)> {
        self.points
            .iter()
            .map(|p| (self.seconds(p), p.rel_mse))
            .collect()
    }

    /// The efficiency `1/(relMSE · seconds)`, the median over the points
    /// with `count ≥ min_count` (small counts are dominated by timer
    /// resolution and fixed costs); `None` without such a point.
    pub fn efficiency(&self, min_count: u64) -> Option<f64> {
        let mut e: Vec<f64> = self
            .points
            .iter()
            .filter(|p| p.count >= min_count)
            .map(|p| 1.0 / (p.rel_mse * self.seconds(p)))
            .collect();
        (!e.is_empty()).then(|| super::median(&mut e))
    }

    /// The relMSE at `budget` CPU seconds, interpolated between the two
    /// measured points around it, linearly in (log seconds, log relMSE)
    /// (relMSE ∝ 1/time is a straight line there), linearly in relMSE where
    /// one of them is 0. `None` if the budget lies outside the measured
    /// times.
    pub fn at_time(&self, budget: f64) -> Option<f64> {
        self.points.windows(2).find_map(|w| {
            let (t0, t1) = (self.seconds(&w[0]), self.seconds(&w[1]));
            let (r0, r1) = (w[0].rel_mse, w[1].rel_mse);
            if !(t0 <= budget && budget <= t1) {
                return None;
            }
            if t1 == t0 {
                return Some(r0.max(r1));
            }
            let f = (budget / t0).ln() / (t1 / t0).ln();
            Some(if r0 > 0.0 && r1 > 0.0 {
                (r0.ln() + f * (r1 / r0).ln()).exp()
            } else {
                r0 + f * (r1 - r0)
            })
        })
    }

    /// CPU seconds per sample at the largest count (its time at least the
    /// clock's resolution).
    pub fn seconds_per_sample(&self) -> f64 {
        let p = self.points.last().expect("a measured curve");
        self.seconds(p) / p.count as f64
    }

    /// The points as JSON objects, the count under the key `count_key`.
    pub fn points_json(&self, count_key: &str) -> Vec<serde_json::Value> {
        self.points
            .iter()
            .map(|p| {
                serde_json::json!({
                    count_key: p.count,
                    "cpu_seconds": p.cpu_seconds,
                    "wall_seconds": p.wall_seconds,
                    "rel_mse": p.rel_mse,
                })
            })
            .collect()
    }
}

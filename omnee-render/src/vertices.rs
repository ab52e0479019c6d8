//! How many scattering vertices a bridge between `x0` and `x2` has
//! (docs/math.md §14): a fixed number `K`, or a number drawn per connection
//! from the core's [`VertexCount`] on `lowest ..= K_max` ([`VertexNumber`],
//! [`Orders`]). The point-to-point estimate (`omnee estimate --vertices`)
//! starts at one vertex, the slab scene's `multiple` term at two.

use crate::error::{RenderError, Result, Spelling};
use omnee_core::Real;
use omnee_core::bridge::{MAX_VERTICES, VertexCount};
use std::fmt;

/// The largest number of vertices `--vertices auto` draws unless told
/// otherwise (`--max-vertices`, the scene's `render.max_vertices`).
pub const DEFAULT_MAX_VERTICES: usize = 8;

/// The number of vertices of every bridge.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum VertexNumber {
    /// `k` vertices, always: the estimate of `I_k` alone.
    Fixed(usize),
    /// `k` drawn per connection with the probability `P(k)` of the core's
    /// [`VertexCount`] on `lowest ..= max`, the bridge's estimate divided by
    /// `P(k)`: an unbiased estimate of `Σ_{k=lowest}^{max} I_k`.
    Auto {
        /// The largest `k`, `K_max ≤` [`MAX_VERTICES`].
        max: usize,
    },
}

impl Default for VertexNumber {
    /// One vertex: the once-more integral.
    fn default() -> Self {
        VertexNumber::Fixed(1)
    }
}

impl fmt::Display for VertexNumber {
    /// `K`, or `auto` (its `max` is a separate setting).
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            VertexNumber::Fixed(k) => write!(f, "{k}"),
            VertexNumber::Auto { .. } => f.write_str("auto"),
        }
    }
}

impl VertexNumber {
    /// `auto` (with `max`) or an integer `K` as written in an option or a
    /// scene file; the message says what is allowed (the caller adds the
    /// field's name). Integers are range-checked by [`check`](Self::check).
    pub fn parse(text: &str, max: usize) -> std::result::Result<Self, String> {
        match text.trim() {
            "auto" => Ok(VertexNumber::Auto { max }),
            t => t.parse::<usize>().map(VertexNumber::Fixed).map_err(|_| {
                format!("\"{text}\" is not a number of vertices; allowed: auto or an integer K in [1, {MAX_VERTICES}]")
            }),
        }
    }

    /// Checks `k` (field `vertices`) or `max` (field `max_vertices`) against
    /// `lowest ..= MAX_VERTICES`, naming the field by `spelling`.
    pub fn check(self, spelling: Spelling, lowest: usize) -> Result<Self> {
        let (field, value) = match self {
            VertexNumber::Fixed(k) => ("vertices", k),
            VertexNumber::Auto { max } => ("max_vertices", max),
        };
        if (lowest..=MAX_VERTICES).contains(&value) {
            Ok(self)
        } else {
            Err(RenderError::range(
                &spelling.of(field),
                value,
                format!("[{lowest}, {MAX_VERTICES}]"),
            ))
        }
    }

    /// The smallest and the largest `k` the bridges take, starting at
    /// `lowest` when drawn.
    pub fn range(self, lowest: usize) -> (usize, usize) {
        match self {
            VertexNumber::Fixed(k) => (k, k),
            VertexNumber::Auto { max } => (lowest, max),
        }
    }
}

/// The number of vertices for one connection: fixed, or drawn from the
/// core's [`VertexCount`] conditioned on `k ≥ lowest`,
/// `P(k | k ≥ lowest) = P(k)/(1 − P(K < lowest))`, drawn by inversion of the
/// same table from `u' = P(K < lowest) + u (1 − P(K < lowest))`.
#[derive(Clone, Copy, Debug)]
pub enum Orders<F> {
    /// Always `k`, with probability 1.
    Fixed(usize),
    /// Drawn: the distribution, `lowest` and `P(K < lowest)`.
    Drawn(VertexCount<F>, usize, F),
}

impl<F: Real> Orders<F> {
    /// The orders of `vertices` (checked) for a connection of length `s` in
    /// a medium with σs, σt and a phase function of mean cosine `g`
    /// (the heuristic of [`VertexCount::new`]); `lowest ≤ max`.
    pub fn new(vertices: VertexNumber, lowest: usize, s: F, sigma_s: F, sigma_t: F, g: F) -> Self {
        match vertices {
            VertexNumber::Fixed(k) => Orders::Fixed(k),
            VertexNumber::Auto { max } => {
                // Out-of-range inputs (a checked problem has none): the
                // uniform law on 1 ..= max, which cannot fail.
                let count = VertexCount::new(max, s, sigma_s, sigma_t, g)
                    .or_else(|_| VertexCount::with_mean(max, F::ZERO, F::ONE))
                    .expect("1 <= max <= MAX_VERTICES");
                Orders::Drawn(count, lowest, count.cdf(lowest - 1))
            }
        }
    }

    /// Whether drawing `k` takes a uniform number.
    #[inline]
    pub fn is_drawn(&self) -> bool {
        matches!(self, Orders::Drawn(..))
    }

    /// `k` and its probability from `u ∈ [0, 1)` (ignored when fixed).
    #[inline]
    pub fn draw(&self, u: F) -> (usize, F) {
        match *self {
            Orders::Fixed(k) => (k, F::ONE),
            Orders::Drawn(count, _, below) => {
                let rest = F::ONE - below;
                let (k, p) = count.sample(below + u * rest);
                (k, p / rest)
            }
        }
    }

    /// The Poisson mean μ of the drawn distribution (`None` when fixed).
    pub fn mean(&self) -> Option<F> {
        match self {
            Orders::Fixed(_) => None,
            Orders::Drawn(count, ..) => Some(count.mean()),
        }
    }

    /// `P(k)` as [`draw`](Self::draw) returns it (0 outside the range).
    pub fn probability(&self, k: usize) -> F {
        match *self {
            Orders::Fixed(j) => {
                if j == k {
                    F::ONE
                } else {
                    F::ZERO
                }
            }
            Orders::Drawn(count, lowest, below) => {
                if k < lowest {
                    F::ZERO
                } else {
                    count.pmf(k) / (F::ONE - below)
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn vertices_parse_check_and_print() {
        assert_eq!(
            VertexNumber::parse("auto", 8),
            Ok(VertexNumber::Auto { max: 8 })
        );
        assert_eq!(VertexNumber::parse(" 3", 8), Ok(VertexNumber::Fixed(3)));
        assert!(
            VertexNumber::parse("three", 8)
                .unwrap_err()
                .contains("auto or an integer")
        );
        let e = VertexNumber::Fixed(33)
            .check(Spelling::Options, 1)
            .unwrap_err();
        assert!(e.to_string().starts_with("--vertices = 33"), "{e}");
        let e = VertexNumber::Auto { max: 1 }
            .check(Spelling::Fields, 2)
            .unwrap_err();
        assert!(e.to_string().starts_with("max_vertices = 1"), "{e}");
        assert!(VertexNumber::Fixed(0).check(Spelling::Fields, 1).is_err());
        assert_eq!(VertexNumber::Fixed(32).to_string(), "32");
        assert_eq!(VertexNumber::Auto { max: 4 }.to_string(), "auto");
        assert_eq!(VertexNumber::Auto { max: 5 }.range(2), (2, 5));
    }

    #[test]
    fn drawn_orders_start_at_the_lowest_and_sum_to_one() {
        for lowest in [1, 2, 3] {
            let o = Orders::<f64>::new(VertexNumber::Auto { max: 6 }, lowest, 1.0, 0.5, 0.55, 0.9);
            let total: f64 = (1..=6).map(|k| o.probability(k)).sum();
            assert!((total - 1.0).abs() < 1e-12, "{total}");
            for k in 1..lowest {
                assert_eq!(o.probability(k), 0.0);
            }
            // Every number maps to an order in range with the probability of
            // its interval.
            for i in 0..1000 {
                let (k, p) = o.draw(i as f64 / 1000.0);
                assert!((lowest..=6).contains(&k), "{k}");
                assert_eq!(p, o.probability(k));
            }
        }
        let fixed = Orders::<f32>::new(VertexNumber::Fixed(3), 1, 1.0, 0.5, 0.55, 0.0);
        assert_eq!((fixed.draw(0.7), fixed.is_drawn()), ((3, 1.0), false));
    }
}

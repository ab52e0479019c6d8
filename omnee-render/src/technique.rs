//! The technique of a once-more term as asked for and as used: front ends
//! name one of the core's [`Choice`]s, `auto` included, and report which
//! method drew the vertices and why.

use omnee_core::method::{AutoReason, Choice};

/// The technique as asked for and as used.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Resolved {
    /// What was asked for.
    pub requested: Choice,
    /// What draws the vertices: a [`Method`](omnee_core::method::Method),
    /// or with a lobe at `x0` a [`LobeMethod`](omnee_core::method::LobeMethod).
    pub used: Choice,
    /// For `auto` without a lobe: why it picked [`Resolved::used`].
    pub reason: Option<AutoReason>,
}

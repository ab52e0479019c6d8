//! The light transport terms: the parts of a pixel's (or a point's) value
//! that a renderer estimates separately, each with its own technique and its
//! own image layer.
//!
//! A term is a set of light paths, `x_light → … → x_receiver`, told apart by
//! how many scattering vertices they have in the medium and where they start.
//! The slab scene has `direct`, `once-more` (one vertex `x1` between the
//! light and a surface point: the once-more integral, docs/math.md §1),
//! `view` (single scattering along camera rays) and `multiple` (k = 2 … K
//! vertices between the light and a surface point, docs/math.md §14.9);
//! the underwater scene,
//! traced from the sun, has `caustics`, `caustics-once-more`, `shafts` and
//! `shafts-once-more` (docs/math.md §13).

use crate::names::Named;

/// A light transport term. The declaration order is the order in which a
/// renderer evaluates the terms (and draws their random numbers) and the
/// order of the image layers.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub enum Term {
    /// Light → surface (and the light seen directly), attenuated.
    Direct,
    /// Light → `x1` in the medium → surface: the once-more term.
    OnceMore,
    /// Light → a point on the camera ray → eye: single scattering.
    View,
    /// Light → `x_1 … x_k` in the medium → surface, `k = 2 … K`: light
    /// scattered more than once on its way to the surface point.
    Multiple,
    /// Under water: sun → surface → floor point `x0` → eye (light traced).
    Caustics,
    /// Under water: sun → surface → `x0` → `x1` in the water → eye: the blur
    /// with depth.
    CausticsOnceMore,
    /// Under water: sun → surface → a point on the refracted ray → eye: the
    /// god rays.
    Shafts,
    /// Under water: sun → surface → `x0` on the refracted ray → `x1` → eye:
    /// the god rays' blur (a lobe at `x0`).
    ShaftsOnceMore,
}

impl Named for Term {
    const ALL: &'static [Self] = &[
        Term::Direct,
        Term::OnceMore,
        Term::View,
        Term::Multiple,
        Term::Caustics,
        Term::CausticsOnceMore,
        Term::Shafts,
        Term::ShaftsOnceMore,
    ];

    fn name(self) -> &'static str {
        match self {
            Term::Direct => "direct",
            Term::OnceMore => "once-more",
            Term::View => "view",
            Term::Multiple => "multiple",
            Term::Caustics => "caustics",
            Term::CausticsOnceMore => "caustics-once-more",
            Term::Shafts => "shafts",
            Term::ShaftsOnceMore => "shafts-once-more",
        }
    }

    fn help(self) -> &'static str {
        match self {
            Term::Direct => "light -> surface (and the light seen directly), attenuated",
            Term::OnceMore => "light -> x1 in the medium -> surface: the once-more (OMNEE) term",
            Term::View => "light -> a point on the camera ray -> eye: single scattering",
            Term::Multiple => {
                "light -> x1 ... xk in the medium -> surface, k = 2 ... K: multiple scattering (bridges or path tracing)"
            }
            Term::Caustics => "underwater: sun -> surface -> floor point x0 -> eye (light traced)",
            Term::CausticsOnceMore => {
                "underwater: sun -> surface -> x0 -> x1 in the water -> eye: the blur with depth"
            }
            Term::Shafts => {
                "underwater: sun -> surface -> a point on the refracted ray -> eye: the god rays"
            }
            Term::ShaftsOnceMore => {
                "underwater: sun -> surface -> x0 on the refracted ray -> x1 -> eye: the god rays' blur (the lobe at x0)"
            }
        }
    }
}

crate::display_by_name!(Term);

impl Term {
    /// The position of this term in `terms` (a scene's list: its layer).
    pub fn index_in(self, terms: &[Term]) -> Option<usize> {
        terms.iter().position(|t| *t == self)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_are_the_documented_ones_in_order() {
        assert_eq!(
            std::format!("{}", Term::allowed()),
            "direct, once-more, view, multiple, caustics, caustics-once-more, shafts, \
             shafts-once-more"
        );
        assert_eq!(Term::from_name("once-more"), Some(Term::OnceMore));
        assert_eq!(Term::from_name("Once-More"), None);
        assert!(Term::ALL.windows(2).all(|w| w[0] < w[1]));
        let underwater = [Term::Caustics, Term::CausticsOnceMore, Term::Shafts];
        assert_eq!(Term::Shafts.index_in(&underwater), Some(2));
        assert_eq!(Term::View.index_in(&underwater), None);
    }
}

//! The light transport terms: each is a layer of `omnee render`'s image
//! (`--terms`, the scene's `render.terms`) and `direct` and `once-more` are
//! the parts of `omnee probe`'s irradiance. The slab scene has `direct`,
//! `once-more` and `view`; the underwater scene `caustics`,
//! `caustics-once-more`, `shafts` and `shafts-once-more`.

use crate::error::{CliError, Result};
use clap::ValueEnum;

/// A light transport term. The declaration order is the order the terms are
/// evaluated in (and draw their random numbers in) and the order of the
/// image layers.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash, ValueEnum)]
pub enum Term {
    /// light -> surface (and the light seen directly), attenuated
    Direct,
    /// light -> x1 in the medium -> surface: the once-more (OMNEE) term
    OnceMore,
    /// light -> a point on the camera ray -> eye: single scattering
    View,
    /// underwater: sun -> surface -> floor point x0 -> eye (light traced)
    Caustics,
    /// underwater: sun -> surface -> x0 -> x1 in the water -> eye: the blur with depth
    CausticsOnceMore,
    /// underwater: sun -> surface -> a point on the refracted ray -> eye: the god rays
    Shafts,
    /// underwater: sun -> surface -> x0 on the refracted ray -> x1 -> eye: the god rays' blur (the lobe at x0)
    ShaftsOnceMore,
}

crate::names::display_by_name!(Term);

/// The terms of the slab scene.
pub const SLAB: [Term; 3] = [Term::Direct, Term::OnceMore, Term::View];

/// The terms of the underwater scene, in the order of its layers.
pub const UNDERWATER: [Term; 4] = [
    Term::Caustics,
    Term::CausticsOnceMore,
    Term::Shafts,
    Term::ShaftsOnceMore,
];

impl Term {
    /// The position of this term in `terms` (a scene's list: its layer).
    pub fn index_in(self, terms: &[Term]) -> Option<usize> {
        terms.iter().position(|t| *t == self)
    }
}

/// Checks that every term of `terms` (given as `field`) is one of
/// `allowed`, the terms of `scene`.
pub fn check(field: &str, terms: &[Term], allowed: &[Term], scene: &str) -> Result<()> {
    match terms.iter().find(|t| !allowed.contains(t)) {
        None => Ok(()),
        Some(t) => Err(CliError::Input(format!(
            "{field} = {t} is not a term of the {scene} scene; allowed: {}",
            allowed
                .iter()
                .map(Term::to_string)
                .collect::<Vec<_>>()
                .join(", ")
        ))),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::names;

    #[test]
    fn names_are_the_documented_ones_in_order() {
        assert_eq!(
            names::allowed::<Term>(),
            "direct, once-more, view, caustics, caustics-once-more, shafts, shafts-once-more"
        );
        assert_eq!(names::parse::<Term>("once-more"), Some(Term::OnceMore));
        assert_eq!(names::parse::<Term>("Once-More"), None);
        assert_eq!(Term::View.to_string(), "view");
        assert!(Term::Direct < Term::OnceMore && Term::OnceMore < Term::View);
        assert_eq!(Term::Shafts.index_in(&UNDERWATER), Some(2));
        assert_eq!(Term::View.index_in(&UNDERWATER), None);
    }
}

//! The light transport terms: each is a layer of `omnee render`'s image
//! (`--terms`, the scene's `render.terms`) and `direct` and `once-more` are
//! the parts of `omnee probe`'s irradiance.

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
}

crate::names::display_by_name!(Term);

#[cfg(test)]
mod tests {
    use super::*;
    use crate::names;

    #[test]
    fn names_are_the_documented_ones_in_order() {
        assert_eq!(names::allowed::<Term>(), "direct, once-more, view");
        assert_eq!(names::parse::<Term>("once-more"), Some(Term::OnceMore));
        assert_eq!(names::parse::<Term>("Once-More"), None);
        assert_eq!(Term::View.to_string(), "view");
        assert!(Term::Direct < Term::OnceMore && Term::OnceMore < Term::View);
    }
}

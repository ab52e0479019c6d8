//! Closed sets of names.
//!
//! Everything a front end offers by name — the techniques
//! ([`method::Choice`](crate::method::Choice)), the light transport terms
//! ([`term::Term`](crate::term::Term)), the scenes' patterns and settings —
//! is an enum implementing [`Named`]: each name is spelled once, next to a
//! line of help, and parsing, printing, help texts and the list of allowed
//! names in an error message all come from it. The command line, the scene
//! files, the bindings and the browser demo read the same sets.

use core::fmt;

/// A closed set of names: every value, its name and a line of help.
///
/// Names are lower case, words joined by `-` (`once-more`); parsing is exact
/// (no case folding, no trimming): `Term::from_name("once-more")`.
pub trait Named: Copy + PartialEq + 'static {
    /// Every value, in the order help texts and error messages list them.
    const ALL: &'static [Self];

    /// The value's name.
    fn name(self) -> &'static str;

    /// What the value means, in one line (for `--help`).
    fn help(self) -> &'static str;

    /// The value called exactly `name`, if there is one.
    fn from_name(name: &str) -> Option<Self> {
        Self::ALL.iter().copied().find(|v| v.name() == name)
    }

    /// The names of [`Named::ALL`], comma-separated when displayed: the
    /// `allowed` part of an error message (no allocation).
    fn allowed() -> List<'static, Self> {
        List(Self::ALL)
    }
}

/// Values of a [`Named`] set, displayed by name as `a, b, c`: the allowed
/// part of an error message, a subset of the set included.
#[derive(Clone, Copy, Debug)]
pub struct List<'a, T>(pub &'a [T]);

impl<T: Named> fmt::Display for List<'_, T> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        for (i, v) in self.0.iter().enumerate() {
            if i > 0 {
                f.write_str(", ")?;
            }
            f.write_str(v.name())?;
        }
        Ok(())
    }
}

/// Implements [`Display`](core::fmt::Display) through [`Named::name`] for
/// enums implementing [`Named`].
#[macro_export]
macro_rules! display_by_name {
    ($($t:ty),* $(,)?) => {$(
        impl ::core::fmt::Display for $t {
            fn fmt(&self, f: &mut ::core::fmt::Formatter<'_>) -> ::core::fmt::Result {
                f.write_str($crate::names::Named::name(*self))
            }
        }
    )*};
}

#[cfg(test)]
mod tests {
    use super::*;

    #[derive(Clone, Copy, Debug, PartialEq)]
    enum Two {
        One,
        OtherOne,
    }

    impl Named for Two {
        const ALL: &'static [Self] = &[Two::One, Two::OtherOne];
        fn name(self) -> &'static str {
            match self {
                Two::One => "one",
                Two::OtherOne => "other-one",
            }
        }
        fn help(self) -> &'static str {
            "a value"
        }
    }

    crate::display_by_name!(Two);

    #[test]
    fn names_parse_exactly_and_list_in_order() {
        assert_eq!(Two::from_name("other-one"), Some(Two::OtherOne));
        for bad in ["", "One", " one", "other_one"] {
            assert_eq!(Two::from_name(bad), None, "{bad:?}");
        }
        assert_eq!(std::format!("{}", Two::allowed()), "one, other-one");
        assert_eq!(std::format!("{}", List(&[Two::OtherOne])), "other-one");
        assert_eq!(std::format!("{}", Two::OtherOne), "other-one");
    }
}

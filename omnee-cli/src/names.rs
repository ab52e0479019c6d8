//! Closed sets of names (techniques, terms, patterns, formats, built-in
//! scenes) are enums deriving clap's [`ValueEnum`]: clap parses them from
//! the command line and lists them in `--help`, the scene parser reads them
//! through [`parse`], and messages print them with [`name`] and [`allowed`].
//! Each name is spelled once, in its enum.

use clap::ValueEnum;

/// The name of `value` (kebab-case of its variant unless the enum says
/// otherwise): `Term::OnceMore` → `once-more`.
pub fn name<E: ValueEnum>(value: &E) -> String {
    value
        .to_possible_value()
        .map(|v| v.get_name().to_string())
        .unwrap_or_default()
}

/// The value called `text` (exact match), if there is one.
pub fn parse<E: ValueEnum>(text: &str) -> Option<E> {
    E::from_str(text, false).ok()
}

/// Every name of `E` in declaration order, comma-separated: the `allowed`
/// part of an error message.
pub fn allowed<E: ValueEnum>() -> String {
    E::value_variants()
        .iter()
        .map(name)
        .collect::<Vec<_>>()
        .join(", ")
}

/// Implements `Display` through [`name`] for enums deriving `ValueEnum`.
macro_rules! display_by_name {
    ($($t:ty),* $(,)?) => {$(
        impl std::fmt::Display for $t {
            fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
                f.write_str(&$crate::names::name(self))
            }
        }
    )*};
}
pub(crate) use display_by_name;

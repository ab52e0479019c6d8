//! Closed sets of names on the command line: clap parses and lists every
//! [`Named`] set of the core and the library (techniques, terms, scenes,
//! patterns) through [`closed`], with each value's line of help, so no name
//! is spelled here.

use clap::builder::{PossibleValue, TypedValueParser};
use clap::error::ErrorKind;
use omnee_core::names::Named;
use std::ffi::OsStr;
use std::marker::PhantomData;

/// clap's value parser for the set `T`: [`closed`].
#[derive(Clone, Copy, Debug)]
pub struct Closed<T>(PhantomData<T>);

/// The value parser of a `Named` set: `value_parser = closed::<Term>()`.
pub fn closed<T>() -> Closed<T> {
    Closed(PhantomData)
}

impl<T: Named + Send + Sync> TypedValueParser for Closed<T> {
    type Value = T;

    fn parse_ref(
        &self,
        cmd: &clap::Command,
        arg: Option<&clap::Arg>,
        value: &OsStr,
    ) -> Result<T, clap::Error> {
        let text = value.to_string_lossy();
        T::from_name(&text).ok_or_else(|| {
            let names: Vec<String> = T::ALL.iter().map(|v| v.name().to_string()).collect();
            let arg = arg.map_or_else(|| "...".to_string(), ToString::to_string);
            let mut e = clap::Error::new(ErrorKind::InvalidValue).with_cmd(cmd);
            use clap::error::{ContextKind, ContextValue};
            e.insert(ContextKind::InvalidArg, ContextValue::String(arg));
            e.insert(ContextKind::InvalidValue, ContextValue::String(text.into()));
            e.insert(ContextKind::ValidValue, ContextValue::Strings(names));
            e
        })
    }

    fn possible_values(&self) -> Option<Box<dyn Iterator<Item = PossibleValue> + '_>> {
        Some(Box::new(
            T::ALL
                .iter()
                .map(|v| PossibleValue::new(v.name()).help(v.help())),
        ))
    }
}

//! One `[section]` of a scene file, read key by key: each reader checks the
//! value's type and range and names `section.key` in its error; keys never
//! read are reported as unknown by `Section::finish`.

use crate::error::{RenderError, Result};
use crate::range::Range;
use omnee_core::names::{List, Named};
use std::collections::BTreeSet;

/// One table of the TOML document, with the keys read so far.
pub(crate) struct Section<'a> {
    name: String,
    table: Option<&'a toml::Table>,
    used: BTreeSet<&'static str>,
}

impl<'a> Section<'a> {
    /// The section `[name]`; a missing one reads as empty (every key takes
    /// its default, a required key is reported missing).
    pub fn required(root: &'a toml::Table, name: &'static str) -> Result<Self> {
        Ok(Self::optional(root, name)?.unwrap_or(Self {
            name: name.to_string(),
            table: None,
            used: BTreeSet::new(),
        }))
    }

    /// The section `[name]`, or `None` when the file leaves it out.
    pub fn optional(root: &'a toml::Table, name: &'static str) -> Result<Option<Self>> {
        match root.get(name) {
            None => Ok(None),
            Some(toml::Value::Table(t)) => Ok(Some(Self::of(t, name.to_string()))),
            Some(v) => Err(RenderError::Input(format!(
                "{name} = {v} is not a table; allowed: a [{name}] section"
            ))),
        }
    }

    /// The table `table`, named `name` in messages (an item of an array of
    /// tables: `surface.waves[2]`).
    pub fn of(table: &'a toml::Table, name: String) -> Self {
        Self {
            name,
            table: Some(table),
            used: BTreeSet::new(),
        }
    }

    /// `section.key`, as error messages name it.
    pub fn field(&self, key: &str) -> String {
        format!("{}.{key}", self.name)
    }

    /// Whether the file gives `key` (without reading it).
    pub fn has(&self, key: &str) -> bool {
        self.table.is_some_and(|t| t.contains_key(key))
    }

    /// Marks `key` as a known field without reading it.
    pub fn known(&mut self, key: &'static str) {
        self.used.insert(key);
    }

    /// The raw value of `key`, marking it as read.
    pub fn get(&mut self, key: &'static str) -> Option<&'a toml::Value> {
        self.used.insert(key);
        self.table.and_then(|t| t.get(key))
    }

    /// A number in `range`; `default` when the key is left out (`None`:
    /// required).
    pub fn number(&mut self, key: &'static str, default: Option<f64>, range: Range) -> Result<f64> {
        let field = self.field(key);
        let x = match self.get(key) {
            None => default.ok_or_else(|| {
                RenderError::Input(format!("{field} is missing; allowed: {range}"))
            })?,
            Some(toml::Value::Float(x)) => *x,
            Some(toml::Value::Integer(i)) => *i as f64,
            Some(v) => {
                return Err(RenderError::Input(format!(
                    "{field} = {v} is not a number; allowed: {range}"
                )));
            }
        };
        range.check(&field, x)
    }

    /// An integer in `[lo, hi]`, `default` when left out.
    pub fn integer(&mut self, key: &'static str, default: i64, lo: i64, hi: i64) -> Result<i64> {
        let field = self.field(key);
        match self.get(key) {
            None => Ok(default),
            Some(toml::Value::Integer(i)) if (lo..=hi).contains(i) => Ok(*i),
            Some(v) => Err(RenderError::Input(format!(
                "{field} = {v} is out of range; allowed: an integer in [{lo}, {hi}]"
            ))),
        }
    }

    /// An array of `N` numbers, each in `range`.
    pub fn vector<const N: usize>(
        &mut self,
        key: &'static str,
        default: Option<[f64; N]>,
        range: Range,
    ) -> Result<[f64; N]> {
        let field = self.field(key);
        let allowed = format!("an array of {N} numbers, each {range}");
        let v = match self.get(key) {
            None => {
                return default.ok_or_else(|| {
                    RenderError::Input(format!("{field} is missing; allowed: {allowed}"))
                });
            }
            Some(v) => v,
        };
        let bad =
            || RenderError::Input(format!("{field} = {v} is out of range; allowed: {allowed}"));
        let toml::Value::Array(items) = v else {
            return Err(bad());
        };
        if items.len() != N {
            return Err(bad());
        }
        let mut out = [0.0; N];
        for (slot, item) in out.iter_mut().zip(items) {
            *slot = match item {
                toml::Value::Float(x) => *x,
                toml::Value::Integer(i) => *i as f64,
                _ => return Err(bad()),
            };
            if !range.contains(*slot) {
                return Err(bad());
            }
        }
        Ok(out)
    }

    /// An RGB value: an array of 3 numbers (R, G, B), or one number for all
    /// three, each in `range`.
    pub fn rgb(
        &mut self,
        key: &'static str,
        default: Option<[f64; 3]>,
        range: Range,
    ) -> Result<[f64; 3]> {
        let field = self.field(key);
        let allowed = format!("a number or an array of 3 numbers (R, G, B), each {range}");
        let x = match self.get(key) {
            None => None,
            Some(toml::Value::Float(x)) => Some(*x),
            Some(toml::Value::Integer(i)) => Some(*i as f64),
            Some(_) => {
                return self
                    .vector(key, default, range)
                    .map_err(|_| self.rgb_error(key, &allowed));
            }
        };
        match x {
            None => default.ok_or_else(|| {
                RenderError::Input(format!("{field} is missing; allowed: {allowed}"))
            }),
            Some(x) if range.contains(x) => Ok([x; 3]),
            Some(_) => Err(self.rgb_error(key, &allowed)),
        }
    }

    /// `key`'s value out of range for [`Self::rgb`].
    fn rgb_error(&self, key: &str, allowed: &str) -> RenderError {
        let v = self.table.and_then(|t| t.get(key));
        let shown = v.map(|v| v.to_string()).unwrap_or_default();
        RenderError::Input(format!(
            "{} = {shown} is out of range; allowed: {allowed}",
            self.field(key)
        ))
    }

    /// A string, `default` when left out (`allowed` describes it in errors).
    pub fn string(&mut self, key: &'static str, default: &str, allowed: &str) -> Result<String> {
        let field = self.field(key);
        match self.get(key) {
            None => Ok(default.to_string()),
            Some(toml::Value::String(s)) => Ok(s.clone()),
            Some(v) => Err(RenderError::Input(format!(
                "{field} = {v} is not a string; allowed: {allowed}"
            ))),
        }
    }

    /// One of the names of `allowed`, a subset of `E` (a `noun` such as
    /// "technique" in messages), `default` when left out.
    pub fn choice<E: Named>(
        &mut self,
        key: &'static str,
        default: E,
        allowed: &[E],
        noun: &str,
    ) -> Result<E> {
        match self.get(key) {
            None => Ok(default),
            Some(v) => self.name_of(key, v, allowed, noun),
        }
    }

    /// A non-empty list of names of `allowed`, a subset of `E`, `default`
    /// when left out.
    pub fn choices<E: Named>(
        &mut self,
        key: &'static str,
        default: &[E],
        allowed: &[E],
        noun: &str,
    ) -> Result<Vec<E>> {
        let field = self.field(key);
        let items = match self.get(key) {
            None => return Ok(default.to_vec()),
            Some(toml::Value::Array(items)) => items,
            Some(v) => {
                return Err(RenderError::Input(format!(
                    "{field} = {v} is not a list of strings; allowed: a list of {}",
                    List(allowed)
                )));
            }
        };
        if items.is_empty() {
            return Err(RenderError::Input(format!(
                "{field} is empty; allowed: one or more of {}",
                List(allowed)
            )));
        }
        items
            .iter()
            .map(|v| self.name_of(key, v, allowed, noun))
            .collect()
    }

    /// `v` as one of the names of `allowed`.
    fn name_of<E: Named>(
        &self,
        key: &str,
        v: &toml::Value,
        allowed: &[E],
        noun: &str,
    ) -> Result<E> {
        let field = self.field(key);
        let toml::Value::String(s) = v else {
            return Err(RenderError::Input(format!(
                "{field} = {v} is not a string; allowed: {}",
                List(allowed)
            )));
        };
        E::from_name(s)
            .filter(|e| allowed.contains(e))
            .ok_or_else(|| {
                RenderError::Input(format!(
                    "{field} = \"{s}\" is not a {noun}; allowed: {}",
                    List(allowed)
                ))
            })
    }

    /// Fails on the first key that was never read.
    pub fn finish(self) -> Result<()> {
        if let Some(t) = self.table {
            for (k, v) in t {
                if !self.used.contains(k.as_str()) {
                    return Err(RenderError::Input(format!(
                        "{}.{k} = {v} is not a known field; allowed: {}",
                        self.name,
                        self.used.iter().copied().collect::<Vec<_>>().join(", ")
                    )));
                }
            }
        }
        Ok(())
    }
}

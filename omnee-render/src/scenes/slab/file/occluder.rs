//! `[occluder]`: an opaque plate with openings between the light and the
//! floor (optional).

use super::floor::FloorSection;
use super::light::LightSection;
use crate::error::{RenderError, Result};
use crate::range::Range;
use crate::section::Section;
use omnee_core::names::Named;

/// The occluder's pattern of openings.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Pattern {
    /// No openings.
    Solid,
    /// Slits parallel to the y axis, repeating along x.
    Bars,
    /// Round holes on a square lattice.
    Holes,
}

impl Named for Pattern {
    const ALL: &'static [Self] = &[Pattern::Solid, Pattern::Bars, Pattern::Holes];
    fn name(self) -> &'static str {
        match self {
            Pattern::Solid => "solid",
            Pattern::Bars => "bars",
            Pattern::Holes => "holes",
        }
    }
    fn help(self) -> &'static str {
        match self {
            Pattern::Solid => "no openings",
            Pattern::Bars => "slits parallel to the y axis, repeating along x",
            Pattern::Holes => "round holes on a square lattice",
        }
    }
}

omnee_core::display_by_name!(Pattern);

/// An opaque horizontal plate with openings.
#[derive(Clone, Debug)]
pub struct Occluder {
    /// Centre of the plate (its z is the plate's height).
    pub center: [f64; 3],
    /// Extent along x and y (m).
    pub size: [f64; 2],
    /// The openings.
    pub pattern: Pattern,
    /// The pattern's period (m).
    pub period: f64,
    /// Open fraction: slit width / period, or hole diameter / period.
    pub opening: f64,
    /// RGB albedo of the plate (diffuse, both sides).
    pub albedo: [f64; 3],
}

impl Occluder {
    /// Reads `[occluder]`, if the file has one: a plate above the `floor`
    /// that does not cut the `light`.
    pub(in crate::scenes::slab) fn parse(
        root: &toml::Table,
        floor: &FloorSection,
        light: &LightSection,
    ) -> Result<Option<Self>> {
        let Some(mut o) = Section::optional(root, "occluder")? else {
            return Ok(None);
        };
        let center = o.vector("center", None, Range::FINITE)?;
        let size = o.vector("size", None, Range::POSITIVE)?;
        let pattern = o.choice("pattern", Pattern::Bars, Pattern::ALL, "pattern")?;
        let period = o.number("period", Some(0.1), Range::POSITIVE)?;
        let opening = o.number("opening", Some(0.5), Range::open(0.0, 1.0))?;
        let albedo = o.vector("albedo", Some([0.0; 3]), Range::UNIT)?;
        o.finish()?;
        if center[2] <= floor.z {
            return Err(RenderError::range(
                "occluder.center[2]",
                center[2],
                format!("(floor.z, inf) = ({}, inf)", floor.z),
            ));
        }
        if (center[2] - light.center[2]).abs() <= light.radius {
            return Err(RenderError::range(
                "occluder.center[2]",
                center[2],
                format!(
                    "|z - light.center[2]| > light.radius = {} (the plate may not cut the light)",
                    light.radius
                ),
            ));
        }
        Ok(Some(Occluder {
            center,
            size,
            pattern,
            period,
            opening,
            albedo,
        }))
    }
}

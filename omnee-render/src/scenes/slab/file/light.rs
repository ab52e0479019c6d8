//! `[light]`: a spherical area light or a point light.

use super::floor::FloorSection;
use crate::error::{RenderError, Result};
use crate::range::Range;
use crate::section::Section;

/// A spherical area light of uniform radiance, or a point light.
#[derive(Clone, Debug)]
pub struct LightSection {
    /// Centre of the sphere (m).
    pub center: [f64; 3],
    /// Radius (m); 0 for a point light.
    pub radius: f64,
    /// Radiance of the sphere's surface (W/(m²·sr)); 0 for a point light.
    pub radiance: f64,
    /// Radiant intensity (W/sr): given for a point light, `radiance·π r²`
    /// for a sphere (its intensity in every direction).
    pub intensity: f64,
}

impl LightSection {
    /// A sphere of `radius > 0` and surface `radiance`; its intensity in
    /// every direction is `radiance·π r²`.
    pub fn sphere(center: [f64; 3], radius: f64, radiance: f64) -> Self {
        Self {
            center,
            radius,
            radiance,
            intensity: radiance * std::f64::consts::PI * radius * radius,
        }
    }

    /// A point light of `intensity` (W/sr).
    pub fn point(center: [f64; 3], intensity: f64) -> Self {
        Self {
            center,
            radius: 0.0,
            radiance: 0.0,
            intensity,
        }
    }

    /// Reads `[light]`: `radiance` for a sphere, `intensity` for a point
    /// light, above the `floor`.
    pub(in crate::scenes::slab) fn parse(root: &toml::Table, floor: &FloorSection) -> Result<Self> {
        let mut l = Section::required(root, "light")?;
        let center = l.vector("center", None, Range::FINITE)?;
        let radius = l.number("radius", Some(0.0), Range::NON_NEGATIVE)?;
        let light = if radius > 0.0 {
            let radiance = l.number("radiance", None, Range::EMISSION)?;
            if l.has("intensity") {
                return Err(RenderError::Input(
                    "light.intensity is only for a point light (radius = 0); allowed: radiance for a sphere".into(),
                ));
            }
            LightSection::sphere(center, radius, radiance)
        } else {
            if l.has("radiance") {
                return Err(RenderError::Input(
                    "light.radiance needs a sphere (radius > 0); allowed: intensity for a point light".into(),
                ));
            }
            LightSection::point(center, l.number("intensity", None, Range::EMISSION)?)
        };
        l.known("radiance");
        l.known("intensity");
        l.finish()?;
        if center[2] - radius <= floor.z {
            return Err(RenderError::range(
                "light.center[2]",
                center[2],
                format!(
                    "(floor.z + light.radius, inf) = ({}, inf)",
                    floor.z + radius
                ),
            ));
        }
        Ok(light)
    }
}

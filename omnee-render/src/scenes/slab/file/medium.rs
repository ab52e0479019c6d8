//! `[medium]`: the homogeneous slab and its phase function.

use crate::error::Result;
use crate::phase::PhaseSpec;
use crate::range::Range;
use crate::section::Section;

/// The scattering medium: a homogeneous slab `z_min ≤ z ≤ z_max`.
#[derive(Clone, Debug)]
pub struct Medium {
    /// Scattering coefficient σs (1/m).
    pub sigma_s: f64,
    /// Absorption coefficient σa (1/m).
    pub sigma_a: f64,
    /// The phase function.
    pub phase: PhaseSpec,
    /// The slab's lower plane.
    pub z_min: f64,
    /// The slab's upper plane.
    pub z_max: f64,
}

impl Medium {
    /// σt = σs + σa.
    pub fn sigma_t(&self) -> f64 {
        self.sigma_s + self.sigma_a
    }

    /// Reads `[medium]`.
    pub(in crate::scenes::slab) fn parse(root: &toml::Table) -> Result<Self> {
        let mut m = Section::required(root, "medium")?;
        let sigma_s = m.number("sigma_s", None, Range::NON_NEGATIVE)?;
        let sigma_a = m.number("sigma_a", Some(0.0), Range::NON_NEGATIVE)?;
        let phase_text = m.string("phase", "iso", "a phase spec such as iso or hg:0.9")?;
        let phase = PhaseSpec::parse(&phase_text).map_err(|e| e.context("medium.phase"))?;
        let z_min = m.number("z_min", Some(0.0), Range::FINITE)?;
        let z_max = m.number("z_max", Some(1.0), Range::open(z_min, f64::INFINITY))?;
        m.finish()?;
        Ok(Medium {
            sigma_s,
            sigma_a,
            phase,
            z_min,
            z_max,
        })
    }
}

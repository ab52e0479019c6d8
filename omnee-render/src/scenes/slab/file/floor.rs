//! `[floor]`: the diffuse checkered plane under the slab.

use crate::error::Result;
use crate::range::Range;
use crate::section::Section;

/// A diffuse floor plane `z = const` with a checker albedo.
#[derive(Clone, Debug)]
pub struct FloorSection {
    /// Height of the plane.
    pub z: f64,
    /// Edge length of one checker square (m).
    pub checker_size: f64,
    /// RGB albedo of the squares with even `floor(x/size) + floor(y/size)`.
    pub albedo_a: [f64; 3],
    /// RGB albedo of the other squares.
    pub albedo_b: [f64; 3],
}

impl FloorSection {
    /// The largest albedo of any channel and square.
    pub fn albedo_max(&self) -> f64 {
        self.albedo_a
            .iter()
            .chain(&self.albedo_b)
            .fold(0.0f64, |m, &x| m.max(x))
    }

    /// Reads `[floor]`.
    pub(in crate::scenes::slab) fn parse(root: &toml::Table) -> Result<Self> {
        let mut f = Section::required(root, "floor")?;
        let floor = FloorSection {
            z: f.number("z", Some(0.0), Range::FINITE)?,
            checker_size: f.number("checker_size", Some(0.25), Range::POSITIVE)?,
            albedo_a: f.vector("albedo_a", Some([0.8; 3]), Range::UNIT)?,
            albedo_b: f.vector("albedo_b", Some([0.2; 3]), Range::UNIT)?,
        };
        f.finish()?;
        Ok(floor)
    }
}

//! `[camera]`: the pinhole camera and the image size.

use super::light::LightSection;
use crate::camera::Pinhole;
use crate::error::{RenderError, Result};
use crate::range::Range;
use crate::section::Section;
use glam::{DVec3, Vec3};

/// A pinhole camera.
#[derive(Clone, Debug)]
pub struct CameraSection {
    /// Eye position.
    pub position: [f64; 3],
    /// The point the camera looks at.
    pub look_at: [f64; 3],
    /// The up direction (not parallel to the view direction).
    pub up: [f64; 3],
    /// Vertical field of view in degrees.
    pub fov_deg: f64,
    /// Image width in pixels.
    pub width: u32,
    /// Image height in pixels.
    pub height: u32,
}

impl CameraSection {
    /// The pinhole camera for an image of `width × height` pixels (the
    /// field of view is vertical; the aspect ratio follows the image).
    pub fn pinhole(&self, width: u32, height: u32) -> Pinhole {
        let v = |a: [f64; 3]| Vec3::new(a[0] as f32, a[1] as f32, a[2] as f32);
        let tan_half = (0.5 * self.fov_deg.to_radians()).tan() as f32;
        Pinhole::with_tan_half(
            v(self.position),
            v(self.look_at),
            v(self.up),
            tan_half,
            width,
            height,
        )
    }

    /// Reads `[camera]`: a view direction, an up direction not parallel to
    /// it, and an eye outside the `light`.
    pub(in crate::scenes::slab) fn parse(root: &toml::Table, light: &LightSection) -> Result<Self> {
        let mut c = Section::required(root, "camera")?;
        let camera = CameraSection {
            position: c.vector("position", None, Range::FINITE)?,
            look_at: c.vector("look_at", Some([0.0; 3]), Range::FINITE)?,
            up: c.vector("up", Some([0.0, 1.0, 0.0]), Range::FINITE)?,
            fov_deg: c.number("fov", Some(40.0), Range::open(0.0, 180.0))?,
            width: c.integer("width", 480, 1, 16384)? as u32,
            height: c.integer("height", 360, 1, 16384)? as u32,
        };
        c.finish()?;
        let eye = DVec3::from(camera.position);
        let view = DVec3::from(camera.look_at) - eye;
        let up = DVec3::from(camera.up);
        if view.length() == 0.0 {
            return Err(RenderError::Input(format!(
                "camera.look_at = {:?} equals camera.position; allowed: any other point",
                camera.look_at
            )));
        }
        if view.cross(up).length() <= 1e-9 * view.length() * up.length() {
            return Err(RenderError::Input(format!(
                "camera.up = {:?} is parallel to the view direction; allowed: any direction not parallel to look_at - position",
                camera.up
            )));
        }
        if light.radius > 0.0 && (eye - DVec3::from(light.center)).length() <= light.radius {
            return Err(RenderError::Input(format!(
                "camera.position = {:?} is inside the light; allowed: outside the sphere of radius {} about {:?}",
                camera.position, light.radius, light.center
            )));
        }
        Ok(camera)
    }
}

//! The pinhole camera in f32: a ray through every image point.

use crate::scene;
use glam::Vec3;

/// A pinhole camera for an image of `width × height` pixels.
#[derive(Clone, Copy, Debug)]
pub struct Pinhole {
    /// The eye: every ray's origin.
    pub eye: Vec3,
    forward: Vec3,
    right: Vec3,
    up: Vec3,
    /// `tan(fov/2)`, the vertical half-extent of the image plane at
    /// distance 1.
    tan_half: f32,
    width: f32,
    height: f32,
}

impl Pinhole {
    /// The scene's camera for an image of `width × height` pixels (the
    /// field of view is vertical; the aspect ratio follows the image).
    pub fn new(camera: &scene::Camera, width: u32, height: u32) -> Self {
        let v = |a: [f64; 3]| Vec3::new(a[0] as f32, a[1] as f32, a[2] as f32);
        let eye = v(camera.position);
        let forward = (v(camera.look_at) - eye).normalize();
        let right = forward.cross(v(camera.up)).normalize();
        let up = right.cross(forward);
        Pinhole {
            eye,
            forward,
            right,
            up,
            tan_half: (0.5 * camera.fov_deg.to_radians()).tan() as f32,
            width: width as f32,
            height: height as f32,
        }
    }

    /// The unit ray direction through the image point `(x, y)` in pixels
    /// (`(0, 0)` the top left corner).
    pub fn ray(&self, x: f32, y: f32) -> Vec3 {
        let aspect = self.width / self.height;
        let sx = (2.0 * x / self.width - 1.0) * self.tan_half * aspect;
        let sy = (1.0 - 2.0 * y / self.height) * self.tan_half;
        (self.forward + self.right * sx + self.up * sy).normalize()
    }
}

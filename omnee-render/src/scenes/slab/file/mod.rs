//! The slab scene's file: one reader per section (`[medium]`, `[floor]`,
//! `[light]`, `[occluder]`, `[camera]`, `[render]`), each checked against
//! the sections before it.

mod camera;
mod floor;
mod light;
mod medium;
mod occluder;
mod settings;

pub use camera::CameraSection;
pub use floor::FloorSection;
pub use light::LightSection;
pub use medium::Medium;
pub use occluder::{Occluder, Pattern};
pub use settings::{SLAB_DEFAULT_TERMS, SLAB_TECHNIQUES, SLAB_TERMS, SlabSettings};

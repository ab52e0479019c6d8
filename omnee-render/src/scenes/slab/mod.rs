//! The slab scene: a sphere (or point) light in a slab of homogeneous
//! medium over a diffuse floor, an optional occluder plate between them,
//! seen by a pinhole camera and rendered by gathering (camera rays), each
//! transport term (`direct`, `once-more`, `view`) in its own layer.
//!
//! - [`file`](mod@file): the scene file (TOML), one reader per section; every error
//!   names the field (`section.key`), its value and the allowed range. The
//!   built-in [`DEFAULT_SCENE`] documents every field.
//! - [`world`]: the scene in the renderer's f32 and its transport terms, one
//!   file each, and [`render::SlabRender`], what the render loop runs.
//! - [`probe`]: the irradiance at a point, per term, as mean and standard
//!   error; [`stats`]: the work counters.

pub mod file;
pub mod probe;
pub mod render;
pub mod stats;
pub mod world;

pub use file::{
    CameraSection, FloorSection, LightSection, Medium, Occluder, Pattern, SLAB_DEFAULT_TERMS,
    SLAB_TECHNIQUES, SLAB_TERMS, SlabSettings,
};
pub use render::{SlabRender, render};
pub use stats::SlabStats;
pub use world::SlabWorld;

use crate::error::{RenderError, Result};

/// The default scene, as shipped in `omnee-render/scenes/default.toml`.
pub const DEFAULT_SCENE: &str = include_str!("../../../scenes/default.toml");

/// The sections of a scene file.
const SECTIONS: [&str; 6] = ["medium", "floor", "light", "occluder", "camera", "render"];

/// The slab scene as its file describes it (f64, every field checked).
#[derive(Clone, Debug)]
pub struct SlabScene {
    /// The slab medium.
    pub medium: Medium,
    /// The floor.
    pub floor: FloorSection,
    /// The light.
    pub light: LightSection,
    /// The occluder, if any.
    pub occluder: Option<Occluder>,
    /// The camera.
    pub camera: CameraSection,
    /// Render settings.
    pub render: SlabSettings,
}

impl SlabScene {
    /// The embedded default scene.
    pub fn default_scene() -> Self {
        Self::parse(DEFAULT_SCENE).expect("the embedded default scene is valid")
    }

    /// Parses and validates a scene from TOML text: the sections in the
    /// order medium, floor, light, occluder, camera, render (a later one is
    /// checked against the earlier ones).
    pub fn parse(text: &str) -> Result<Self> {
        let root: toml::Table = text
            .parse()
            .map_err(|e: toml::de::Error| RenderError::Input(format!("not valid TOML: {e}")))?;
        if let Some(key) = root.keys().find(|k| !SECTIONS.contains(&k.as_str())) {
            return Err(RenderError::Input(format!(
                "[{key}] is not a known section; allowed: {}",
                SECTIONS.join(", ")
            )));
        }
        let medium = Medium::parse(&root)?;
        let floor = FloorSection::parse(&root)?;
        let light = LightSection::parse(&root, &floor)?;
        let occluder = Occluder::parse(&root, &floor, &light)?;
        let camera = CameraSection::parse(&root, &light)?;
        let render = SlabSettings::parse(&root)?;
        Ok(SlabScene {
            medium,
            floor,
            light,
            occluder,
            camera,
            render,
        })
    }

    /// The reference radiance `L_ref` (W/(m²·sr)) that scales the Russian
    /// roulette threshold: the brightest floor albedo straight under the
    /// light, unattenuated and unoccluded, `albedo_max/π · I/h²` with `h`
    /// the height of the light's lowest point above the floor.
    pub fn reference_radiance(&self) -> f64 {
        let h = (self.light.center[2] - self.floor.z - self.light.radius).max(1e-6);
        self.floor.albedo_max() / std::f64::consts::PI * self.light.intensity / (h * h)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The default scene with `from` replaced by `to` (which must occur).
    fn edited(from: &str, to: &str) -> String {
        assert!(
            DEFAULT_SCENE.contains(from),
            "{from:?} not in the default scene"
        );
        DEFAULT_SCENE.replacen(from, to, 1)
    }

    #[test]
    fn the_default_scene_parses() {
        let s = SlabScene::default_scene();
        assert_eq!(s.medium.sigma_s, 0.5);
        assert_eq!(s.medium.sigma_a, 0.05);
        assert!(s.occluder.is_some());
        assert_eq!(s.render.terms, SLAB_DEFAULT_TERMS);
    }

    #[test]
    fn errors_name_field_value_and_range() {
        let bad = edited("sigma_s = 0.5", "sigma_s = -2");
        let e = SlabScene::parse(&bad).unwrap_err().to_string();
        assert!(e.contains("medium.sigma_s = -2"), "{e}");
        assert!(e.contains("[0, inf)"), "{e}");
        let bad = edited("sigma_s = 0.5", "sigma_s = 0.5\nsigma_x = 1");
        let e = SlabScene::parse(&bad).unwrap_err().to_string();
        assert!(e.contains("medium.sigma_x"), "{e}");
    }

    #[test]
    fn names_in_the_scene_are_checked_against_their_enums() {
        let bad = edited("terms = [\"direct\",", "terms = [\"glow\",");
        let e = SlabScene::parse(&bad).unwrap_err().to_string();
        assert!(
            e.contains(
                "render.terms = \"glow\" is not a term; allowed: direct, once-more, view, multiple"
            ),
            "{e}"
        );
        let bad = edited("pattern = \"holes\"", "pattern = \"stars\"");
        let e = SlabScene::parse(&bad).unwrap_err().to_string();
        assert!(e.contains("allowed: solid, bars, holes"), "{e}");
        let bad = edited(
            "terms = [\"direct\", \"once-more\", \"view\"]",
            "terms = []",
        );
        let e = SlabScene::parse(&bad).unwrap_err().to_string();
        assert!(e.contains("render.terms is empty"), "{e}");
    }

    #[test]
    fn the_multiple_terms_settings_are_read_and_checked() {
        use crate::vertices::VertexNumber;
        use omnee_core::method::MultipleMethod;
        let s = SlabScene::default_scene().render;
        assert_eq!(s.multiple, MultipleMethod::Bridge);
        assert_eq!(s.vertices, VertexNumber::Auto { max: 8 });
        let with = |text: &str| {
            SlabScene::parse(&edited("max_vertices = 8 ", text)).map(|s| s.render.vertices)
        };
        assert_eq!(
            with("max_vertices = 3 ").unwrap(),
            VertexNumber::Auto { max: 3 }
        );
        let e = |text: &str| with(text).unwrap_err().to_string();
        assert!(e("max_vertices = 1 ").contains("render.max_vertices = 1"));
        assert!(e("max_vertices = 33 ").contains("render.max_vertices = 33"));
        let fixed = |k: &str| SlabScene::parse(&edited("vertices = \"auto\"", k));
        let e = fixed("vertices = 1").unwrap_err().to_string();
        assert!(e.contains("render.vertices = 1 is out of range"), "{e}");
        assert!(fixed("vertices = \"many\"").is_err());
        // A fixed order with max_vertices given: the file's max_vertices
        // line is there, so the fixed k refuses it.
        let e = fixed("vertices = 3").unwrap_err().to_string();
        assert!(
            e.contains("render.max_vertices = 8 applies to render.vertices"),
            "{e}"
        );
        let text =
            edited("vertices = \"auto\"", "vertices = 3").replacen("max_vertices = 8 ", "", 1);
        assert_eq!(
            SlabScene::parse(&text).unwrap().render.vertices,
            VertexNumber::Fixed(3)
        );
        let e = SlabScene::parse(&edited("multiple = \"bridge\"", "multiple = \"photons\""))
            .unwrap_err()
            .to_string();
        assert!(e.contains("allowed: bridge, path-tracing"), "{e}");
    }

    #[test]
    fn the_default_scenes_comments_name_every_term_and_technique() {
        let line = |key: &str| {
            DEFAULT_SCENE
                .lines()
                .find(|l| l.starts_with(key))
                .unwrap_or_else(|| panic!("no {key} line"))
        };
        for t in SLAB_TERMS {
            assert!(line("terms =").contains(&format!("\"{t}\"")), "{t}");
        }
        for t in SLAB_TECHNIQUES {
            assert!(line("technique =").contains(&t.to_string()), "{t}");
        }
    }

    #[test]
    fn the_reference_radiance_is_the_brightest_floor_under_the_light() {
        let s = SlabScene::default_scene();
        // albedo 0.8, I = 1e4·π·0.01² W/sr, h = 0.95 − 0.01 m.
        let want =
            0.8 / std::f64::consts::PI * (1e4 * std::f64::consts::PI * 1e-4) / 0.94f64.powi(2);
        assert!((s.reference_radiance() / want - 1.0).abs() < 1e-12);
    }
}

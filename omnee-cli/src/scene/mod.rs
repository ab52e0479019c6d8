//! Scene files: TOML with every parameter of the slab scene, validated field
//! by field, one reader per section. Every error names the field
//! (`section.key`), its value and the allowed range. The built-in scenes are
//! embedded in the binary and document every field; `--scene` takes a
//! built-in name or a file.

mod camera;
mod floor;
mod light;
mod medium;
mod occluder;
mod section;
mod settings;

pub use camera::Camera;
pub use floor::Floor;
pub use light::Light;
pub use medium::Medium;
pub use occluder::{Occluder, Pattern};
pub(crate) use section::Section;
pub use settings::{RenderSettings, TERMS};

use crate::error::{CliError, Result};
use crate::names;
use clap::ValueEnum;
use std::path::{Path, PathBuf};

/// The default scene, as shipped in `omnee-cli/scenes/default.toml`.
pub const DEFAULT_SCENE: &str = include_str!("../../scenes/default.toml");

/// The sections of a scene file.
const SECTIONS: [&str; 6] = ["medium", "floor", "light", "occluder", "camera", "render"];

/// A scene built into the binary (`--scene NAME`, `omnee default-scene NAME`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum Builtin {
    /// the slab scene: a small sphere light in a water-like slab over a checkered floor, a perforated plate between them
    Default,
    /// the talk's scene: the sun through a wavy water surface, caustics on the sand, blurred with depth
    Underwater,
}

crate::names::display_by_name!(Builtin);

impl Builtin {
    /// The scene file's text, every field documented.
    pub fn text(self) -> &'static str {
        match self {
            Builtin::Default => DEFAULT_SCENE,
            Builtin::Underwater => crate::underwater::scene::UNDERWATER_SCENE,
        }
    }
}

/// Where a scene comes from: `--scene NAME` or `--scene FILE`.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Source {
    /// A built-in scene.
    Builtin(Builtin),
    /// A scene file (TOML).
    File(PathBuf),
}

impl Source {
    /// A built-in scene's name, else a file's path (`./default` names a
    /// file called `default`). For clap's `value_parser`.
    pub fn parse(text: &str) -> std::result::Result<Self, String> {
        Ok(match names::parse::<Builtin>(text) {
            Some(b) => Source::Builtin(b),
            None => Source::File(PathBuf::from(text)),
        })
    }
}

/// A whole scene.
#[derive(Clone, Debug)]
pub struct Scene {
    /// The slab medium.
    pub medium: Medium,
    /// The floor.
    pub floor: Floor,
    /// The light.
    pub light: Light,
    /// The occluder, if any.
    pub occluder: Option<Occluder>,
    /// The camera.
    pub camera: Camera,
    /// Render settings.
    pub render: RenderSettings,
}

impl Scene {
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
            .map_err(|e: toml::de::Error| CliError::Input(format!("not valid TOML: {e}")))?;
        if let Some(key) = root.keys().find(|k| !SECTIONS.contains(&k.as_str())) {
            return Err(CliError::Input(format!(
                "[{key}] is not a known section; allowed: {}",
                SECTIONS.join(", ")
            )));
        }
        let medium = Medium::parse(&root)?;
        let floor = Floor::parse(&root)?;
        let light = Light::parse(&root, &floor)?;
        let occluder = Occluder::parse(&root, &floor, &light)?;
        let camera = Camera::parse(&root, &light)?;
        let render = RenderSettings::parse(&root)?;
        Ok(Scene {
            medium,
            floor,
            light,
            occluder,
            camera,
            render,
        })
    }

    /// Reads and parses a scene file; errors are prefixed with the path.
    pub fn load(path: &Path) -> Result<Self> {
        let text = std::fs::read_to_string(path).map_err(|e| {
            CliError::Input(format!("--scene = {}: cannot read: {e}", path.display()))
        })?;
        Self::parse(&text).map_err(|e| e.context(&path.display().to_string()))
    }

    /// The built-in scene or the file `source` names.
    pub fn from_source(source: &Source) -> Result<Self> {
        match source {
            Source::Builtin(b) => Self::parse(b.text()),
            Source::File(path) => Self::load(path),
        }
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
        let s = Scene::default_scene();
        assert_eq!(s.medium.sigma_s, 0.5);
        assert_eq!(s.medium.sigma_a, 0.05);
        assert!(s.occluder.is_some());
        assert_eq!(s.render.terms, TERMS);
    }

    #[test]
    fn errors_name_field_value_and_range() {
        let bad = edited("sigma_s = 0.5", "sigma_s = -2");
        let e = Scene::parse(&bad).unwrap_err().to_string();
        assert!(e.contains("medium.sigma_s = -2"), "{e}");
        assert!(e.contains("[0, inf)"), "{e}");
        let bad = edited("sigma_s = 0.5", "sigma_s = 0.5\nsigma_x = 1");
        let e = Scene::parse(&bad).unwrap_err().to_string();
        assert!(e.contains("medium.sigma_x"), "{e}");
    }

    #[test]
    fn names_in_the_scene_are_checked_against_their_enums() {
        let bad = edited("terms = [\"direct\",", "terms = [\"glow\",");
        let e = Scene::parse(&bad).unwrap_err().to_string();
        assert!(
            e.contains("render.terms = \"glow\" is not a term; allowed: direct, once-more, view"),
            "{e}"
        );
        let bad = edited("pattern = \"holes\"", "pattern = \"stars\"");
        let e = Scene::parse(&bad).unwrap_err().to_string();
        assert!(e.contains("allowed: solid, bars, holes"), "{e}");
        let bad = edited(
            "terms = [\"direct\", \"once-more\", \"view\"]",
            "terms = []",
        );
        let e = Scene::parse(&bad).unwrap_err().to_string();
        assert!(e.contains("render.terms is empty"), "{e}");
    }

    #[test]
    fn the_default_scenes_comments_name_every_term_and_technique() {
        let line = |key: &str| {
            DEFAULT_SCENE
                .lines()
                .find(|l| l.starts_with(key))
                .unwrap_or_else(|| panic!("no {key} line"))
        };
        for t in TERMS {
            assert!(line("terms =").contains(&format!("\"{t}\"")), "{t}");
        }
        for t in <crate::technique::Technique as ValueEnum>::value_variants() {
            assert!(line("technique =").contains(&t.to_string()), "{t}");
        }
    }

    #[test]
    fn a_scene_source_is_a_builtin_name_or_a_file() {
        assert_eq!(
            Source::parse("default"),
            Ok(Source::Builtin(Builtin::Default))
        );
        assert_eq!(
            Source::parse("./default"),
            Ok(Source::File(PathBuf::from("./default")))
        );
        let s = Scene::from_source(&Source::Builtin(Builtin::Default)).unwrap();
        assert_eq!(s.camera.width, Scene::default_scene().camera.width);
    }

    #[test]
    fn the_reference_radiance_is_the_brightest_floor_under_the_light() {
        let s = Scene::default_scene();
        // albedo 0.8, I = 1e4·π·0.01² W/sr, h = 0.95 − 0.01 m.
        let want =
            0.8 / std::f64::consts::PI * (1e4 * std::f64::consts::PI * 1e-4) / 0.94f64.powi(2);
        assert!((s.reference_radiance() / want - 1.0).abs() < 1e-12);
    }
}

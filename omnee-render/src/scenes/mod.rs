//! The scenes, sibling modules behind one enum ([`Scene`]): [`slab`] (a
//! light in a slab of fog over a floor, gathered by camera rays) and
//! [`underwater`] (the sun through a wavy surface, light traced). Both are
//! read from a TOML file or a built-in one ([`Source`], [`Builtin`]) and
//! render through the one loop, [`crate::render::render`]; [`floor`] is
//! their common floor.

pub mod floor;
pub mod settings;
pub mod slab;
pub mod underwater;

pub use settings::{RenderReport, RenderSettings};

use crate::error::{RenderError, Result, Spelling};
use crate::render::{Options, Progress, Rendered};
use omnee_core::names::Named;
use slab::{SlabScene, SlabStats};
use std::path::{Path, PathBuf};
use std::sync::atomic::AtomicBool;
use underwater::{UnderwaterScene, UnderwaterStats};

/// A scene built into the library (`--scene NAME`, `omnee default-scene NAME`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Builtin {
    /// The slab scene.
    Default,
    /// The talk's underwater scene.
    Underwater,
}

impl Named for Builtin {
    const ALL: &'static [Self] = &[Builtin::Default, Builtin::Underwater];
    fn name(self) -> &'static str {
        match self {
            Builtin::Default => "default",
            Builtin::Underwater => "underwater",
        }
    }
    fn help(self) -> &'static str {
        match self {
            Builtin::Default => {
                "the slab scene: a small sphere light in a water-like slab over a checkered floor, a perforated plate between them"
            }
            Builtin::Underwater => {
                "the talk's scene: the sun through a wavy water surface, caustics on the sand, blurred with depth"
            }
        }
    }
}

omnee_core::display_by_name!(Builtin);

impl Builtin {
    /// The scene file's text, every field documented.
    pub fn text(self) -> &'static str {
        match self {
            Builtin::Default => slab::DEFAULT_SCENE,
            Builtin::Underwater => underwater::UNDERWATER_SCENE,
        }
    }
}

/// Where a scene comes from: a built-in name or a scene file.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Source {
    /// A built-in scene.
    Builtin(Builtin),
    /// A scene file (TOML).
    File(PathBuf),
}

impl Source {
    /// A built-in scene's name, else a file's path (`./default` names a
    /// file called `default`).
    pub fn parse(text: &str) -> Self {
        match Builtin::from_name(text) {
            Some(b) => Source::Builtin(b),
            None => Source::File(PathBuf::from(text)),
        }
    }
}

/// A scene of either kind, as its file describes it.
#[derive(Clone, Debug)]
pub enum Scene {
    /// The slab scene.
    Slab(SlabScene),
    /// The underwater scene.
    Underwater(UnderwaterScene),
}

impl Scene {
    /// Parses a scene file's text: an underwater scene if it has a `[sun]`
    /// section, else a slab scene.
    pub fn parse(text: &str) -> Result<Self> {
        let is_underwater = text
            .parse::<toml::Table>()
            .is_ok_and(|root| root.contains_key("sun"));
        if is_underwater {
            UnderwaterScene::parse(text).map(Scene::Underwater)
        } else {
            SlabScene::parse(text).map(Scene::Slab)
        }
    }

    /// Reads and parses a scene file (`field` names the option or argument
    /// it came from); errors are prefixed with the path.
    pub fn load(field: &str, path: &Path) -> Result<Self> {
        let text = std::fs::read_to_string(path).map_err(|e| {
            RenderError::Input(format!("{field} = {}: cannot read: {e}", path.display()))
        })?;
        Self::parse(&text).map_err(|e| e.context(&path.display().to_string()))
    }

    /// The built-in scene or the file `source` names (`field`: the option
    /// that named it).
    pub fn from_source(field: &str, source: &Source) -> Result<Self> {
        match source {
            Source::Builtin(b) => Self::parse(b.text()),
            Source::File(path) => Self::load(field, path),
        }
    }
}

/// The work counters of a render, by scene.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum SceneStats {
    /// The slab scene's.
    Slab(SlabStats),
    /// The underwater scene's.
    Underwater(UnderwaterStats),
}

impl Scene {
    /// The scene's render settings: its `[render]` and `[camera]` values.
    pub fn settings(&self) -> RenderSettings {
        match self {
            Scene::Slab(s) => s.settings(),
            Scene::Underwater(s) => s.settings(),
        }
    }

    /// Renders the scene with `settings` (checked first, fields named by
    /// `spelling`) on the current rayon pool; `progress` and `cancel` as
    /// [`crate::render::render`] takes them.
    pub fn render(
        &self,
        settings: &RenderSettings,
        spelling: Spelling,
        progress: &(dyn Fn(Progress) + Sync),
        cancel: &AtomicBool,
    ) -> Result<(Rendered<SceneStats>, RenderReport)> {
        let options = |crop| Options {
            budget: settings.budget,
            seed: settings.seed,
            crop,
        };
        match self {
            Scene::Slab(scene) => {
                settings.check(spelling, "slab", &slab::SLAB_TERMS, &slab::SLAB_TECHNIQUES)?;
                let crop = settings.window(spelling)?;
                let (r, report) = slab::render(scene, settings, &options(crop), progress, cancel)?;
                Ok((r.map_stats(SceneStats::Slab), report))
            }
            Scene::Underwater(scene) => {
                settings.check(
                    spelling,
                    "underwater",
                    &underwater::UNDERWATER_TERMS,
                    &underwater::UNDERWATER_TECHNIQUES,
                )?;
                let crop = settings.window(spelling)?;
                let (r, report) =
                    underwater::render(scene, settings, &options(crop), progress, cancel)?;
                Ok((r.map_stats(SceneStats::Underwater), report))
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_scene_source_is_a_builtin_name_or_a_file() {
        assert_eq!(Source::parse("default"), Source::Builtin(Builtin::Default));
        assert_eq!(
            Source::parse("./default"),
            Source::File(PathBuf::from("./default"))
        );
        assert!(matches!(
            Scene::from_source("--scene", &Source::Builtin(Builtin::Default)),
            Ok(Scene::Slab(_))
        ));
        assert!(matches!(
            Scene::from_source("--scene", &Source::Builtin(Builtin::Underwater)),
            Ok(Scene::Underwater(_))
        ));
    }
}

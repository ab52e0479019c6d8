//! `omnee_cli`: the slab-medium renderer and the measurements behind the
//! `omnee` command, the front end of omnee, a reference implementation of
//! once-more scattered next event estimation (Hanika, Weidlich, Droske,
//! EGSR 2022). The binary is [`cli::run`]; the library is there so that the
//! benchmarks and other programs can drive the same scene and estimators.
//!
//! Where things are:
//! - [`cli`]: parsing and dispatch; [`commands`]: one file per subcommand
//!   (`render`, `probe`, `estimate`, `samples`, `merge`, `default-scene`),
//!   each with its options and its `run`.
//! - [`scene`]: the scene file, one reader per section, and the built-in
//!   scenes; [`phase`]: phase function specs and tables.
//! - [`world`]: the scene in f32 and its transport terms, one file each;
//!   [`technique`]: the once-more techniques and `auto`; [`camera`]: the
//!   pinhole camera.
//! - [`render`]: the render loop (passes, budget, progress, layers), which
//!   does not know what a pixel sample computes.
//! - [`underwater`]: the underwater scene (sun, waves, chromatic water, sand
//!   floor), light traced and splatted, with its own scene file and loop.
//! - Shared helpers: [`names`] (closed sets of names), [`term`], [`range`]
//!   (range checks), [`parallel`] (threads, chunks), [`moments`], [`stats`],
//!   [`rng`], [`image`] (EXR, PNG), [`output`] (output paths, atomic
//!   writes), [`error`].

pub mod camera;
pub mod cli;
pub mod commands;
pub mod error;
pub mod image;
pub mod moments;
pub mod names;
pub mod output;
pub mod parallel;
pub mod phase;
pub mod range;
pub mod render;
pub mod rng;
pub mod scene;
pub mod stats;
pub mod technique;
pub mod term;
pub mod underwater;
pub mod world;

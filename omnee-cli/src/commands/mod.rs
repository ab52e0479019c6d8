//! The subcommands, one file each with its options (`Args`) and its `run`:
//! [`render`], [`probe`], [`estimate`], [`samples`], [`merge`],
//! [`default_scene`]; [`problem`] is the point-to-point problem that
//! `estimate` and `samples` share, [`args`] the option parsers and checks
//! several subcommands use, [`summary`] the printed result of `probe` and
//! `estimate`. A new subcommand is a new file here and a variant of
//! `Command` in `cli.rs`, which parses and dispatches.

pub mod args;
pub mod default_scene;
pub mod estimate;
pub mod merge;
pub mod probe;
pub mod problem;
pub mod render;
pub mod render_underwater;
pub mod samples;
pub mod summary;

//! The subcommands, one file each with its options (`Args`) and its `run`,
//! which translates them for the library, calls it, and prints: [`render`],
//! [`probe`], [`estimate`], [`samples`], [`merge`], [`default_scene`];
//! [`args`] holds the option parsers and the options `estimate` and
//! `samples` share, [`summary`] the printed result of `probe` and
//! `estimate`. A new subcommand is a new file here and a variant of
//! `Command` in `cli.rs`, which parses and dispatches.

pub mod args;
pub mod default_scene;
pub mod estimate;
pub mod merge;
pub mod probe;
pub mod render;
pub mod samples;
pub mod summary;

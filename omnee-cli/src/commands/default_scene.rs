//! `omnee default-scene`: prints a built-in scene's file, every field
//! documented with its default and allowed range.

use crate::error::Result;
use crate::scene::Builtin;
use clap::Args;

/// The options of `omnee default-scene`.
#[derive(Args, Debug)]
pub struct DefaultSceneArgs {
    /// Which built-in scene.
    #[arg(value_enum, default_value_t = Builtin::Default)]
    pub scene: Builtin,
}

/// `omnee default-scene`.
pub fn run(a: DefaultSceneArgs) -> Result<()> {
    print!("{}", a.scene.text());
    Ok(())
}

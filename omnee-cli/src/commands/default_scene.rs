//! `omnee default-scene`: prints a built-in scene's file, every field
//! documented with its default and allowed range.

use crate::named::closed;
use clap::Args;
use omnee_render::Result;
use omnee_render::scenes::Builtin;

/// The options of `omnee default-scene`.
#[derive(Args, Debug)]
pub struct DefaultSceneArgs {
    /// Which built-in scene.
    #[arg(value_parser = closed::<Builtin>(), default_value = "default")]
    pub scene: Builtin,
}

/// `omnee default-scene`.
pub fn run(a: DefaultSceneArgs) -> Result<()> {
    print!("{}", a.scene.text());
    Ok(())
}

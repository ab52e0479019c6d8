//! `omnee merge`: sums EXR files rendered with disjoint `--crop` windows of
//! one image into the full image.

use clap::Args;
use omnee_render::files::{check_output, read_exr, with_ext, write_exr, write_png};
use omnee_render::image::{Layers, tone_map};
use omnee_render::range::Range;
use omnee_render::{RenderError, Result};
use std::path::PathBuf;

/// The options of `omnee merge`.
#[derive(Args, Debug)]
pub struct MergeArgs {
    /// EXR files rendered with disjoint crop windows of the same image.
    #[arg(required = true)]
    pub inputs: Vec<PathBuf>,
    /// Output base name: writes BASE.exr and BASE.png.
    #[arg(short, long, default_value = "merged")]
    pub output: PathBuf,
    /// PNG exposure in stops (default: automatic).
    #[arg(long, allow_negative_numbers = true)]
    pub exposure: Option<f64>,
}

/// `omnee merge`.
pub fn run(a: MergeArgs) -> Result<()> {
    let exr_path = with_ext(&a.output, "exr");
    let png_path = with_ext(&a.output, "png");
    check_output("--output", &exr_path)?;
    let exposure = a
        .exposure
        .map(|e| Range::EXPOSURE.check("--exposure", e))
        .transpose()?;
    let mut total: Option<Layers> = None;
    for p in &a.inputs {
        let img = read_exr(p)?;
        match &mut total {
            None => total = Some(img),
            Some(t) if t.same_shape(&img) => t.add(&img),
            Some(t) => {
                return Err(RenderError::Input(format!(
                    "{}: {}x{} with layers [{}] does not match the first input's {}x{} with [{}]; allowed: crops of one render",
                    p.display(),
                    img.width,
                    img.height,
                    img.names(),
                    t.width,
                    t.height,
                    t.names()
                )));
            }
        }
    }
    let Some(total) = total else {
        return Err(RenderError::Input(
            "no input files; allowed: one or more EXR files".into(),
        ));
    };
    let (srgb, ev) = tone_map(total.get("").unwrap_or(&[]), exposure);
    write_exr(&exr_path, &total)?;
    write_png(&png_path, total.width, total.height, &srgb)?;
    println!(
        "wrote {} and {} (exposure {ev:+.2} stops)",
        exr_path.display(),
        png_path.display()
    );
    Ok(())
}

//! Files (the `files` feature): images as OpenEXR (every layer, read and
//! written) and PNG, output paths (`BASE.exr`, `BASE.TERM.png`), the check
//! that their folder exists before any work is done, and the
//! write-to-a-temporary-then-rename that keeps an existing output whole if
//! anything fails.

use crate::error::{RenderError, Result};
use crate::image::Layers;
use std::fs::File;
use std::io::{BufWriter, Write};
use std::path::{Path, PathBuf};

/// `base` with the extension `ext` appended (`out` → `out.exr`, `a.b` → `a.b.exr`).
pub fn with_ext(base: &Path, ext: &str) -> PathBuf {
    let mut s = base.as_os_str().to_owned();
    s.push(".");
    s.push(ext);
    PathBuf::from(s)
}

/// Checks that `path`'s folder exists and `path` is not a folder, naming
/// the option `field` otherwise.
pub fn check_output(field: &str, path: &Path) -> Result<()> {
    let dir = parent(path);
    if !dir.is_dir() {
        return Err(RenderError::Input(format!(
            "{field} = {}: the folder {} does not exist; allowed: a path in an existing folder",
            path.display(),
            dir.display()
        )));
    }
    if path.is_dir() {
        return Err(RenderError::Input(format!(
            "{field} = {} is a folder; allowed: a file path",
            path.display()
        )));
    }
    Ok(())
}

/// The folder of `path` (`.` for a bare file name).
fn parent(path: &Path) -> PathBuf {
    match path.parent() {
        Some(p) if !p.as_os_str().is_empty() => p.to_path_buf(),
        _ => PathBuf::from("."),
    }
}

/// Writes `path` through a temporary file in the same folder (`tempfile`),
/// renamed over `path` only once `write` has succeeded and the data is
/// flushed and synced: an existing `path` is either left as it was or
/// replaced whole, and a failed write leaves no temporary file behind.
///
/// The file gets the mode a newly created file gets from the user's umask
/// (`0o666 & !umask`, as `File::create` gives), not the temporary file's
/// private `0o600`.
pub fn write_atomic(
    path: &Path,
    write: impl FnOnce(&mut BufWriter<File>) -> std::io::Result<()>,
) -> Result<()> {
    let io = |e: std::io::Error| RenderError::Io(format!("cannot write {}: {e}", path.display()));
    let mut builder = tempfile::Builder::new();
    builder.prefix(".omnee-").suffix(".tmp");
    #[cfg(unix)]
    {
        use std::os::unix::fs::PermissionsExt;
        // The kernel applies the umask to the mode given to open(2).
        builder.permissions(std::fs::Permissions::from_mode(0o666));
    }
    let tmp = builder.tempfile_in(parent(path)).map_err(io)?;
    let (file, tmp_path) = tmp.into_parts();
    let mut w = BufWriter::new(file);
    write(&mut w).map_err(io)?;
    w.flush().map_err(io)?;
    w.get_ref().sync_all().map_err(io)?;
    drop(w);
    tmp_path.persist(path).map_err(|e| io(e.error))
}

/// Writes the layers as a single-part OpenEXR file with 32-bit float
/// channels `R, G, B` (the main layer) and `<layer>.R, .G, .B` for the
/// others (the layer convention Nuke, Blender and OpenEXR's tools read).
pub fn write_exr(path: &Path, img: &Layers) -> Result<()> {
    use exr::prelude::*;
    let (w, h) = (img.width, img.height);
    let mut channels: Vec<AnyChannel<FlatSamples>> = Vec::new();
    for (name, data) in &img.layers {
        for (k, c) in ["R", "G", "B"].iter().enumerate() {
            let full = if name.is_empty() {
                c.to_string()
            } else {
                format!("{name}.{c}")
            };
            let plane: Vec<f32> = data.iter().skip(k).step_by(3).copied().collect();
            channels.push(AnyChannel::new(full.as_str(), FlatSamples::F32(plane)));
        }
    }
    let layer = Layer::new(
        (w, h),
        LayerAttributes::default(),
        Encoding::SMALL_LOSSLESS,
        AnyChannels::sort(channels.into()),
    );
    let image = Image::from_layer(layer);
    write_atomic(path, |out| {
        image
            .write()
            .to_buffered(out)
            .map_err(|e| std::io::Error::other(e.to_string()))
    })
}

/// Reads a file written by [`write_exr`] back into layers.
pub fn read_exr(path: &Path) -> Result<Layers> {
    use exr::prelude::*;
    let bad = |e: exr::error::Error| {
        RenderError::Input(format!("{}: cannot read as OpenEXR: {e}", path.display()))
    };
    let image = read()
        .no_deep_data()
        .largest_resolution_level()
        .all_channels()
        .first_valid_layer()
        .all_attributes()
        .from_file(path)
        .map_err(bad)?;
    let layer = &image.layer_data;
    let (w, h) = (layer.size.width(), layer.size.height());
    let mut names: Vec<String> = Vec::new();
    for ch in &layer.channel_data.list {
        let full = ch.name.to_string();
        let base = match full.rsplit_once('.') {
            Some((b, _)) => b.to_string(),
            None => String::new(),
        };
        if !names.contains(&base) {
            names.push(base);
        }
    }
    // The main layer first, as written.
    names.sort_by_key(|n| !n.is_empty());
    let mut layers = Vec::new();
    for name in names {
        let mut data = vec![0.0f32; w * h * 3];
        for (k, c) in ["R", "G", "B"].iter().enumerate() {
            let full = if name.is_empty() {
                c.to_string()
            } else {
                format!("{name}.{c}")
            };
            let ch = layer
                .channel_data
                .list
                .iter()
                .find(|ch| ch.name.to_string() == full)
                .ok_or_else(|| {
                    RenderError::Input(format!("{}: channel {full} is missing", path.display()))
                })?;
            for (i, v) in ch.sample_data.values_as_f32().enumerate() {
                data[3 * i + k] = v;
            }
        }
        layers.push((name, data));
    }
    // `crate::image::Layers`: the prelude of `exr` has a `Layers` too.
    Ok(crate::image::Layers {
        width: w,
        height: h,
        layers,
    })
}

/// Writes an 8-bit sRGB PNG.
pub fn write_png(path: &Path, width: usize, height: usize, srgb: &[u8]) -> Result<()> {
    write_atomic(path, |out| {
        let mut enc = png::Encoder::new(out, width as u32, height as u32);
        enc.set_color(png::ColorType::Rgb);
        enc.set_depth(png::BitDepth::Eight);
        enc.set_source_srgb(png::SrgbRenderingIntent::Perceptual);
        let mut w = enc.write_header().map_err(std::io::Error::other)?;
        w.write_image_data(srgb).map_err(std::io::Error::other)?;
        w.finish().map_err(std::io::Error::other)
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_failed_write_leaves_the_old_file_whole() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("keep.png");
        std::fs::write(&path, b"old").unwrap();
        let r = write_atomic(&path, |w| {
            w.write_all(b"half")?;
            Err(std::io::Error::other("disk full"))
        });
        assert!(r.is_err());
        assert_eq!(std::fs::read(&path).unwrap(), b"old");
        assert_eq!(std::fs::read_dir(dir.path()).unwrap().count(), 1);
    }

    #[test]
    fn exr_round_trips_every_layer() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("a.exr");
        let img = Layers {
            width: 3,
            height: 2,
            layers: vec![
                (String::new(), (0..18).map(|i| i as f32).collect()),
                (
                    "direct".into(),
                    (0..18).map(|i| -(i as f32) * 0.5).collect(),
                ),
            ],
        };
        write_exr(&path, &img).unwrap();
        assert_eq!(read_exr(&path).unwrap(), img);
    }

    #[test]
    fn extensions_are_appended() {
        assert_eq!(with_ext(Path::new("a.b"), "exr"), PathBuf::from("a.b.exr"));
        assert_eq!(
            with_ext(Path::new("dir/out"), "once-more.png"),
            PathBuf::from("dir/out.once-more.png")
        );
    }
}

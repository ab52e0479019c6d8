//! Images: layers of linear RGB (one per transport term), OpenEXR in and
//! out, and the tone-mapped PNG; both written through
//! [`write_atomic`].

use crate::error::{CliError, Result};
use crate::output::write_atomic;
use std::path::Path;

/// An RGB float image with named layers; `""` is the main layer (the sum).
#[derive(Clone, Debug, PartialEq)]
pub struct Layers {
    /// Width in pixels.
    pub width: usize,
    /// Height in pixels.
    pub height: usize,
    /// `(name, interleaved RGB rows top to bottom)`.
    pub layers: Vec<(String, Vec<f32>)>,
}

impl Layers {
    /// The layer called `name`.
    pub fn get(&self, name: &str) -> Option<&[f32]> {
        self.layers
            .iter()
            .find(|(n, _)| n == name)
            .map(|(_, d)| d.as_slice())
    }

    /// The layers' names as messages list them: `RGB (sum), direct, ...`.
    pub fn names(&self) -> String {
        self.layers
            .iter()
            .map(|(n, _)| {
                if n.is_empty() {
                    "RGB (sum)".to_string()
                } else {
                    n.clone()
                }
            })
            .collect::<Vec<_>>()
            .join(", ")
    }

    /// Whether `other` has the same size and the same layers in the same
    /// order (e.g. another crop of the same render).
    pub fn same_shape(&self, other: &Layers) -> bool {
        (self.width, self.height) == (other.width, other.height)
            && self.layers.len() == other.layers.len()
            && self
                .layers
                .iter()
                .zip(&other.layers)
                .all(|(a, b)| a.0 == b.0)
    }

    /// Adds `other`'s pixels, layer by layer (see [`Self::same_shape`]).
    pub fn add(&mut self, other: &Layers) {
        for ((_, dst), (_, src)) in self.layers.iter_mut().zip(&other.layers) {
            for (d, s) in dst.iter_mut().zip(src) {
                *d += s;
            }
        }
    }
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
pub fn read_exr(path: &Path) -> Result<crate::image::Layers> {
    use exr::prelude::*;
    let bad = |e: exr::error::Error| {
        CliError::Input(format!("{}: cannot read as OpenEXR: {e}", path.display()))
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
                    CliError::Input(format!("{}: channel {full} is missing", path.display()))
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

/// Tone-maps linear RGB to 8-bit sRGB: multiply by `2^exposure`, then the
/// curve `x / (1 + x)` per channel (Reinhard), then the sRGB transfer
/// function. With `exposure = None` the log-average luminance is mapped to
/// 0.18 (Reinhard et al. 2002), ignoring the brightest 0.5 % (the light).
pub fn tone_map(rgb: &[f32], exposure: Option<f64>) -> (Vec<u8>, f64) {
    let ev = exposure.unwrap_or_else(|| auto_exposure(rgb));
    let scale = ev.exp2() as f32;
    let encode = |x: f32| {
        let x = x * scale;
        let y = if x > 0.0 { x / (1.0 + x) } else { 0.0 };
        let s = if y <= 0.003_130_8 {
            12.92 * y
        } else {
            1.055 * y.powf(1.0 / 2.4) - 0.055
        };
        (s * 255.0 + 0.5).clamp(0.0, 255.0) as u8
    };
    (rgb.iter().map(|&x| encode(x)).collect(), ev)
}

/// The exposure (stops) that maps the log-average luminance to 0.18.
pub fn auto_exposure(rgb: &[f32]) -> f64 {
    let mut lum: Vec<f64> = rgb
        .chunks_exact(3)
        .map(|p| 0.2126 * p[0] as f64 + 0.7152 * p[1] as f64 + 0.0722 * p[2] as f64)
        .filter(|l| *l > 0.0 && l.is_finite())
        .collect();
    if lum.is_empty() {
        return 0.0;
    }
    lum.sort_by(|a, b| a.total_cmp(b));
    let keep = &lum[..(lum.len() as f64 * 0.995).ceil() as usize];
    let log_avg = (keep.iter().map(|l| l.ln()).sum::<f64>() / keep.len() as f64).exp();
    (0.18 / log_avg).log2()
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
}

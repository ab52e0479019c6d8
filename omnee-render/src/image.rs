//! Images: layers of linear RGB (one per transport term) and their
//! tone-mapped 8-bit sRGB. Reading and writing them as OpenEXR and PNG is
//! `crate::files` (the `files` feature).

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

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn tone_mapping_is_monotone_and_exposure_maps_the_log_average() {
        let rgb = [0.0, 0.0, 0.0, 0.5, 0.5, 0.5, 2.0, 2.0, 2.0];
        let (srgb, ev) = tone_map(&rgb, None);
        assert!(srgb[0] < srgb[3] && srgb[3] < srgb[6], "{srgb:?}");
        assert!((ev - auto_exposure(&rgb)).abs() < 1e-15);
        assert_eq!(tone_map(&rgb, Some(1.0)).1, 1.0);
    }
}

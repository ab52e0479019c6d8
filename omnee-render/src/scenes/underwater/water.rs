//! Chromatic water: σs and σa per RGB channel, one phase function for all
//! channels, per-channel transmittance, and distance sampling along a ray
//! that is unbiased for every channel (docs/math.md §13).

use glam::Vec3;

/// The water's coefficients per RGB channel (1/m).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Water {
    /// Scattering coefficient σs per channel.
    pub sigma_s: Vec3,
    /// Extinction coefficient σt = σs + σa per channel.
    pub sigma_t: Vec3,
}

impl Water {
    /// Water with `σs` and `σa` per channel (each finite and ≥ 0, checked by
    /// the scene parser).
    pub fn new(sigma_s: Vec3, sigma_a: Vec3) -> Self {
        Self {
            sigma_s,
            sigma_t: sigma_s + sigma_a,
        }
    }

    /// Whether any channel scatters.
    pub fn scatters(&self) -> bool {
        self.sigma_s.max_element() > 0.0
    }

    /// Per-channel transmittance over a distance `d`: `exp(−σt d)`.
    #[inline]
    pub fn transmittance(&self, d: f32) -> Vec3 {
        Vec3::new(
            (-self.sigma_t.x * d).exp(),
            (-self.sigma_t.y * d).exp(),
            (-self.sigma_t.z * d).exp(),
        )
    }

    /// A free-flight distance on `[0, len]` from the channel mixture: a
    /// channel `c` uniformly (by `u[0]`), then `t` from the exponential of
    /// `σt_c` truncated to the segment (by `u[1]`). Its density is the
    /// mixture's, [`Self::free_flight_pdf`], so the estimate of every
    /// channel stays unbiased whichever channel drew `t` (a channel with
    /// σt_c = 0 contributes the uniform density `1/len`).
    #[inline]
    pub fn free_flight(&self, len: f32, u: [f32; 2]) -> f32 {
        let c = ((u[0] * 3.0) as usize).min(2);
        let s = self.sigma_t[c];
        let t = if s > 0.0 {
            let mass = -(-s * len).exp_m1();
            -(-u[1] * mass).ln_1p() / s
        } else {
            u[1] * len
        };
        t.clamp(0.0, len)
    }

    /// The density of [`Self::free_flight`] at `t ∈ [0, len]`:
    /// `(1/3) Σ_c σt_c e^{−σt_c t} / (1 − e^{−σt_c len})`.
    #[inline]
    pub fn free_flight_pdf(&self, len: f32, t: f32) -> f32 {
        let mut p = 0.0;
        for c in 0..3 {
            let s = self.sigma_t[c];
            p += if s > 0.0 {
                s * (-s * t).exp() / -(-s * len).exp_m1()
            } else {
                1.0 / len
            };
        }
        p / 3.0
    }
}

/// Equiangular sampling (Kulla & Fajardo 2012) of the distance `t ∈ [0, len]`
/// along the ray `o + t d` (unit `d`) towards the point `c`, with density
/// `pdf(t) = D / ((θb − θa)(D² + (t − Δ)²))`, `Δ = (c − o)·d`,
/// `D = |(c − o) × d|`, `θ = atan((t − Δ)/D)`. `None` when `c` is on the
/// ray's line (the density would be a delta).
#[derive(Clone, Copy, Debug)]
pub struct EquiangularLine {
    delta: f32,
    dist: f32,
    theta_a: f32,
    theta_b: f32,
}

impl EquiangularLine {
    /// The sampler for the ray `o + t d`, `t ∈ [0, len]`, about `c`.
    pub fn new(o: Vec3, d: Vec3, len: f32, c: Vec3) -> Option<Self> {
        let to_c = c - o;
        let delta = to_c.dot(d);
        let dist = to_c.cross(d).length();
        if !(dist > 1e-6 * (1.0 + delta.abs()) && len > 0.0) {
            return None;
        }
        Some(Self {
            delta,
            dist,
            theta_a: (-delta).atan2(dist),
            theta_b: (len - delta).atan2(dist),
        })
    }

    /// The angle `θb − θa` the segment subtends at `c`.
    pub fn angle(&self) -> f32 {
        self.theta_b - self.theta_a
    }

    /// `t = Δ + D tan(θa + u (θb − θa))`.
    #[inline]
    pub fn sample(&self, u: f32) -> f32 {
        let theta = self.theta_a + u * (self.theta_b - self.theta_a);
        self.delta + self.dist * theta.tan()
    }

    /// The `u` with `sample(u) = t`: `(atan2(t − Δ, D) − θa) / (θb − θa)`.
    #[inline]
    pub fn invert(&self, t: f32) -> f32 {
        (((t - self.delta).atan2(self.dist) - self.theta_a) / (self.theta_b - self.theta_a))
            .clamp(0.0, 1.0)
    }

    /// `D / ((θb − θa)(D² + (t − Δ)²))`.
    #[inline]
    pub fn pdf(&self, t: f32) -> f32 {
        let v = t - self.delta;
        self.dist / ((self.theta_b - self.theta_a) * (self.dist * self.dist + v * v))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// `∫ pdf = 1` and the sample's histogram against the pdf on 20 bins.
    fn check(sample: impl Fn(f32) -> f32, pdf: impl Fn(f32) -> f32, len: f32) {
        let n = 100_000;
        let h = len as f64 / n as f64;
        let mass: f64 = (0..n)
            .map(|i| pdf(((i as f64 + 0.5) * h) as f32) as f64 * h)
            .sum();
        assert!((mass - 1.0).abs() < 1e-3, "{mass}");
        let bins = 20;
        let mut counts = vec![0u32; bins];
        let m = 200_000;
        for i in 0..m {
            let t = sample((i as f32 + 0.5) / m as f32);
            assert!((0.0..=len).contains(&t));
            counts[((t / len * bins as f32) as usize).min(bins - 1)] += 1;
        }
        for (b, &c) in counts.iter().enumerate() {
            let (lo, hi) = (
                b as f64 * len as f64 / 20.0,
                (b + 1) as f64 * len as f64 / 20.0,
            );
            let k = 1000;
            let want: f64 = (0..k)
                .map(|i| pdf((lo + (i as f64 + 0.5) * (hi - lo) / k as f64) as f32) as f64)
                .sum::<f64>()
                * (hi - lo)
                / k as f64;
            // Stratified u: the counts follow the cdf to within a count or two.
            assert!(
                (c as f64 / m as f64 - want).abs() < 2e-4,
                "bin {b}: {c} vs {want}"
            );
        }
    }

    #[test]
    fn the_channel_mixture_samples_its_density() {
        let w = Water::new(Vec3::new(0.2, 0.2, 0.1), Vec3::new(0.8, 0.05, 0.0));
        for u0 in [0.1f32, 0.5, 0.9] {
            // One channel at a time: u0 picks it; the mixture check below.
            let c = (u0 * 3.0) as usize;
            let s = w.sigma_t[c];
            let len = 7.0;
            let single = |t: f32| s * (-s * t).exp() / -(-s * len).exp_m1();
            check(|u| w.free_flight(len, [u0, u]), single, len);
        }
        // The mixture: u0 over thirds.
        let len = 7.0;
        check(
            |u| {
                let u0 = (u * 3.0).floor() / 3.0 + 1e-3;
                w.free_flight(len, [u0, (u * 3.0).fract()])
            },
            |t| w.free_flight_pdf(len, t),
            len,
        );
    }

    #[test]
    fn equiangular_line_samples_its_density() {
        let line =
            EquiangularLine::new(Vec3::ZERO, Vec3::X, 5.0, Vec3::new(1.5, 0.3, 0.0)).unwrap();
        check(|u| line.sample(u), |t| line.pdf(t), 5.0);
        for u in [0.01f32, 0.3, 0.77, 0.99] {
            assert!((line.invert(line.sample(u)) - u).abs() < 1e-5);
        }
    }
}

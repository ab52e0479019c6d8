// The fixed point-to-point problem, shared by the firmware and build.rs
// (which includes this file to compute the reference on the host).

/// The light-side point x0 (m).
pub const X0: [f32; 3] = [0.0, 0.0, 1.0];
/// The receiver-side point x2 (m).
pub const X2: [f32; 3] = [0.0, 0.0, 0.0];
/// θmax = π/2 (forward scattering), rounded to f32.
pub const THETA_MAX: f32 = core::f32::consts::FRAC_PI_2;
/// σs (1/m).
pub const SIGMA_S: f32 = 0.5;
/// σa (1/m).
pub const SIGMA_A: f32 = 0.05;
/// Henyey–Greenstein's g.
pub const G: f32 = 0.9;
/// Samples of the estimate.
pub const SAMPLES: u32 = 1 << 17;
/// The generator's seed.
pub const SEED: u64 = 2024;

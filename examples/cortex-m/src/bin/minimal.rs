//! (a) The minimal firmware: OMNEE with Henyey–Greenstein in f32 on the fixed
//! point-to-point problem, against the quadrature reference that the host
//! computed at build time. Prints its results over semihosting and exits
//! with success when the estimate lies within 4.5 standard errors of the
//! reference. Nothing but OMNEE, HG and f32 arithmetic is linked.
#![no_std]
#![no_main]

#[cfg(target_arch = "arm")]
use cortex_m_rt::entry;
use glam::Vec3;
use omnee_core::medium::Homogeneous;
use omnee_core::phase::HenyeyGreenstein;
use omnee_core::reference::PointToPoint;
use omnee_core::sampling::{Connection, Omnee, Technique};
use omnee_cortex_m::report::Line;
use omnee_cortex_m::scene::{G, SAMPLES, SEED, SIGMA_A, SIGMA_S, THETA_MAX, X0, X2};
use omnee_cortex_m::{Mean, REFERENCE_BITS, SplitMix64, stack, uniform};
#[cfg(target_arch = "riscv32")]
use riscv_rt::entry;

/// The estimate's running mean over `SAMPLES` samples.
fn estimate() -> Result<Mean<f32>, omnee_core::Error> {
    let connection = Connection::new(Vec3::from_array(X0), Vec3::from_array(X2), THETA_MAX)?;
    let problem = PointToPoint::new(connection, Homogeneous::new(SIGMA_S, SIGMA_A)?, None)?;
    let omnee = Omnee::new(connection, HenyeyGreenstein::new(G)?);
    let mut rng = SplitMix64::new(SEED);
    let mut mean = Mean::default();
    for _ in 0..SAMPLES {
        let u = [uniform(&mut rng), uniform(&mut rng), uniform(&mut rng)];
        // No sample (θ ≥ θmax) contributes 0.
        mean.add(omnee.sample(u).map_or(0.0, |s| problem.estimate(&s)));
    }
    Ok(mean)
}

#[entry]
fn main() -> ! {
    let painted = stack::paint();
    let result = estimate();
    let stack_bytes = stack::peak(&painted);
    let Ok(mean) = result else {
        Line::new("error constructor refused the scene").send();
        omnee_cortex_m::exit(false);
    };
    let reference = f64::from_bits(REFERENCE_BITS) as f32;
    let agrees = mean.agrees(reference, 4.5);
    Line::new("machine mps2-an386").send();
    Line::new("phase hg").send();
    Line::new("samples").u32(SAMPLES).send();
    Line::new("estimate").f32(mean.mean()).send();
    Line::new("stderr").f32(mean.std_error()).send();
    Line::new("reference").f64_bits(REFERENCE_BITS).send();
    Line::new("stack_bytes").u32(stack_bytes as u32).send();
    Line::new("agrees").u32(agrees.into()).send();
    omnee_cortex_m::exit(agrees)
}

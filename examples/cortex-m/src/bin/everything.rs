//! (b) The firmware that links everything: every phase function (from spec
//! strings, and a table), every technique (OMNEE, equiangular, distance,
//! one-sample MIS with the power heuristic, the recommended OMNEE MIS, the
//! f32 batch), in f32 and in f64, and the quadrature reference computed on
//! the device. Its footprint is the upper bound of what omnee costs on a
//! microcontroller. Checks: the MIS estimates with Henyey–Greenstein (f32
//! and f64) lie within 4.5 standard errors of the host's reference, and the
//! device's f64 quadrature equals the host's to 1e-12.
#![no_std]
#![no_main]

#[cfg(target_arch = "arm")]
use cortex_m_rt::entry;
use omnee_core::medium::{Homogeneous, Region};
use omnee_core::mis::{Heuristic, OmneeMis, OneSample};
use omnee_core::phase::{Deflection, HenyeyGreenstein, Phase, PhaseFunction, Spec, Tabulated};
use omnee_core::real::{Real, Vector};
use omnee_core::reference::PointToPoint;
use omnee_core::sampling::{
    Connection, Directions, Distance, Equiangular, Omnee, Technique, Uniforms, Vertices,
};
use omnee_cortex_m::report::Line;
use omnee_cortex_m::scene::{G, SEED, SIGMA_A, SIGMA_S, THETA_MAX, X0, X2};
use omnee_cortex_m::{Mean, REFERENCE_BITS, SplitMix64, stack, uniform};
#[cfg(target_arch = "riscv32")]
use riscv_rt::entry;

const SPECS: [&str; 9] = [
    "iso",
    "hg:0.9",
    "tthg:0.99,-0.44,0.96",
    "ff:0.0183,1.1",
    "draine:0.5557,22",
    "mie:10",
    "rayleigh",
    "table",
    "hg:-0.6",
];
/// MIS draws per phase function and precision.
const DRAWS: u32 = 4096;

/// The scene in precision `F`, with a few more checks than its estimate.
fn run<F: Real>(rng: &mut SplitMix64, ok: &mut bool) -> Result<(), omnee_core::Error> {
    let f = F::from_f32;
    let v = |p: [f32; 3]| F::Vec3::new(f(p[0]), f(p[1]), f(p[2]));
    let connection = Connection::new(v(X0), v(X2), f(THETA_MAX))?;
    let medium = Homogeneous::new(f(SIGMA_S), f(SIGMA_A))?;
    let problem = PointToPoint::new(connection, medium, None)?;
    let directions = Directions::cosine(v([0.0, 0.2, 1.0]))?;
    let region = Region::slab(f(-4.0), f(4.0))?;
    let theta = [F::ZERO, f(0.5), f(1.5), F::PI];
    let values = [f(4.0), f(2.0), f(1.0)];
    let mut cdf = [F::ZERO; 4];
    let table = Tabulated::new(&theta, &values, &mut cdf)?;
    let name = if F::EPSILON.to_f64() < 1e-10 {
        "f64 "
    } else {
        "f32 "
    };
    let reference = F::from_f64(f64::from_bits(REFERENCE_BITS));
    let mut u = || F::from_f32(uniform(rng));
    for spec in SPECS {
        let phase: Phase<'_, F> = match Spec::<F>::parse(spec) {
            Ok(Spec::Analytic(p)) => p,
            _ => Phase::Tabulated(table),
        };
        let omnee = Omnee::new(connection, &phase);
        let equiangular = Equiangular::new(connection, &phase, Directions::Sphere, region);
        let distance = Distance::new(connection, &phase, directions, region, medium.sigma_t())?;
        let one_sample = OneSample::new(
            [&omnee, &equiangular, &distance],
            [f(0.8), f(0.1), f(0.1)],
            Heuristic::Power,
        )?;
        let mis = OmneeMis::recommended(omnee, &equiangular);
        let mut mean = Mean::<F>::default();
        let mut checksum = F::ZERO;
        for _ in 0..DRAWS {
            let draw = mis.sample([u(), u(), u(), u(), u(), u()]);
            mean.add(
                draw.iter()
                    .flatten()
                    .map(|s| problem.estimate(s))
                    .fold(F::ZERO, |a, b| a + b),
            );
            // Every other technique's trio once per draw, summed so that it
            // is not optimised away.
            let us = [u(), u(), u()];
            for technique in [&equiangular as &dyn Technique<F>, &distance, &one_sample] {
                if let Some(s) = technique.sample(us) {
                    checksum += s.weight.min(F::ONE) + technique.pdf(s.x1).min(F::ONE);
                    if let Some([a, b, c]) = technique.invert(s.x1) {
                        checksum += a + b + c;
                    }
                }
            }
            let d = Deflection::from_theta(u() * F::PI);
            checksum += phase.eval(d) + phase.cdf(d) + phase.invert(d).unwrap_or(F::ZERO);
        }
        Line::new(name)
            .text(spec)
            .u32(DRAWS)
            .f32(mean.mean().to_f32())
            .f32(mean.std_error().to_f32())
            .f32(checksum.to_f32())
            .send();
        if spec == "hg:0.9" && !mean.agrees(reference, f(4.5)) {
            Line::new("disagrees").text(name).text(spec).send();
            *ok = false;
        }
    }
    Ok(())
}

/// The f32 batch of OMNEE with Henyey–Greenstein.
fn batch(rng: &mut SplitMix64) -> Result<f32, omnee_core::Error> {
    const N: usize = 64;
    let v = glam::Vec3::from_array;
    let connection = Connection::new(v(X0), v(X2), THETA_MAX)?;
    let omnee = Omnee::new(connection, HenyeyGreenstein::new(G)?);
    let (mut u0, mut u1, mut u2) = ([0.0f32; N], [0.0f32; N], [0.0f32; N]);
    for i in 0..N {
        (u0[i], u1[i], u2[i]) = (uniform(rng), uniform(rng), uniform(rng));
    }
    let (mut x, mut y, mut z, mut pdf, mut weight) =
        ([0.0; N], [0.0; N], [0.0; N], [0.0; N], [0.0; N]);
    let count = omnee.sample_batch(
        Uniforms {
            u0: &u0,
            u1: &u1,
            u2: &u2,
        },
        Vertices {
            x: &mut x,
            y: &mut y,
            z: &mut z,
            pdf: &mut pdf,
            weight: &mut weight,
        },
    )?;
    Ok(count as f32 + weight.iter().sum::<f32>())
}

/// The scene's integral by quadrature on the device (f64 in software).
fn quadrature() -> Result<f64, omnee_core::Error> {
    let v = |p: [f32; 3]| glam::DVec3::new(p[0].into(), p[1].into(), p[2].into());
    let connection = Connection::<f64>::new(v(X0), v(X2), THETA_MAX.into())?;
    let medium = Homogeneous::<f64>::new(SIGMA_S.into(), SIGMA_A.into())?;
    let problem = PointToPoint::new(connection, medium, None)?;
    Ok(problem.integral(&HenyeyGreenstein::<f64>::new(G.into())?))
}

#[entry]
fn main() -> ! {
    let painted = stack::paint();
    let mut rng = SplitMix64::new(SEED);
    let mut ok = true;
    let result = (|| {
        run::<f32>(&mut rng, &mut ok)?;
        run::<f64>(&mut rng, &mut ok)?;
        let batch = batch(&mut rng)?;
        Ok::<_, omnee_core::Error>((batch, quadrature()?))
    })();
    let stack_bytes = stack::peak(&painted);
    match result {
        Ok((batch, device)) => {
            let host = f64::from_bits(REFERENCE_BITS);
            let close = (device - host).abs() <= 1e-12 * host;
            Line::new("batch").f32(batch).send();
            Line::new("quadrature device")
                .f64_bits(device.to_bits())
                .text(" host")
                .f64_bits(REFERENCE_BITS)
                .text(" equal")
                .u32((device == host).into())
                .send();
            ok &= close;
        }
        Err(_) => {
            Line::new("error a constructor refused the scene").send();
            ok = false;
        }
    }
    Line::new("stack_bytes").u32(stack_bytes as u32).send();
    Line::new("agrees").u32(ok.into()).send();
    omnee_cortex_m::exit(ok)
}

//! The Rust API's results on the fixed inputs of `tests/bits.c`, as IEEE bit
//! patterns in the same lines: `omnee-ffi/ci.sh` runs both and requires
//! identical output, so the C ABI is checked bit for bit against the Rust API
//! it wraps (`cargo run -p omnee-ffi --example expected`).

use glam::Vec3;
use omnee_core::bridge::{Bridge, REFERENCE_BUDGET, VertexCount, isotropic_transfer};
use omnee_core::medium::{Homogeneous, Region};
use omnee_core::mis::OmneeMis;
use omnee_core::phase::{Deflection, HenyeyGreenstein, Phase, PhaseFunction, Spec, Tabulated};
use omnee_core::real::{Real, Vector};
use omnee_core::reference::PointToPoint;
use omnee_core::sampling::{
    Connection, Directions, Distance, Equiangular, Omnee, Sample, Technique, Uniforms, Vertices,
};
use std::fmt::Write;

/// A precision whose numbers print as hex bit patterns, as `tests/bits.c` does.
trait Bits: Real {
    /// ` xxxxxxxx` (f32) or ` xxxxxxxxxxxxxxxx` (f64).
    fn bits(self) -> String;
    /// "f32" or "f64".
    const NAME: &'static str;
}

impl Bits for f32 {
    fn bits(self) -> String {
        format!(" {:08x}", self.to_bits())
    }
    const NAME: &'static str = "f32";
}

impl Bits for f64 {
    fn bits(self) -> String {
        format!(" {:016x}", self.to_bits())
    }
    const NAME: &'static str = "f64";
}

/// The C status of an `Option`: 0 (OMNEE_OK) or 1 (OMNEE_NONE).
fn status<T>(x: &Option<T>) -> &'static str {
    if x.is_some() { " s0" } else { " s1" }
}

fn v<F: Real>(x: f64, y: f64, z: f64) -> F::Vec3 {
    F::Vec3::new(F::from_f64(x), F::from_f64(y), F::from_f64(z))
}

fn sample_bits<F: Bits>(s: &Sample<F>) -> String {
    let [x, y, z] = s.x1.to_array();
    [x, y, z, s.pdf, s.weight].map(F::bits).concat()
}

/// The zero sample that the C API writes for "no sample".
fn zero<F: Real>() -> Sample<F> {
    Sample {
        x1: F::Vec3::new(F::ZERO, F::ZERO, F::ZERO),
        pdf: F::ZERO,
        weight: F::ZERO,
    }
}

fn run<F: Bits>() -> Result<String, omnee_core::Error> {
    let mut out = String::new();
    let p = F::NAME;
    let f = F::from_f64;
    let specs = [
        "iso",
        "hg:0.9",
        "hg:-0.6",
        "tthg:0.99,-0.44,0.96",
        "ff:0.0183,1.1",
        "draine:0.5557,22",
        "mie:10",
        "rayleigh",
        "table",
    ];
    let u3 = [
        [0.1, 0.2, 0.3],
        [0.5, 0.5, 0.5],
        [0.9, 0.05, 0.77],
        [0.999, 0.6, 0.1],
    ];
    let u6 = [
        [0.1, 0.2, 0.3, 0.01, 0.4, 0.6],
        [0.7, 0.5, 0.2, 0.5, 0.1, 0.1],
        [0.995, 0.3, 0.8, 0.02, 0.9, 0.3],
    ];
    let table_theta = [f(0.0), f(0.5), f(1.5), F::PI];
    let table_values = [f(4.0), f(2.0), f(1.0)];
    let mut table_cdf = [F::ZERO; 4];
    let c = Connection::new(v::<F>(0.3, -0.2, 1.1), v::<F>(-0.1, 0.4, 0.2), f(2.8))?;
    let problem = PointToPoint::new(
        c,
        Homogeneous::new(f(0.5), f(0.05))?,
        Some(v::<F>(0.2, 0.1, 1.0)),
    )?;
    let directions = Directions::cosine(v::<F>(0.0, 0.3, 1.0))?;
    let region = Region::slab(f(-1.0), f(2.0))?;
    let sigma = f(0.7);
    let d = Deflection::from_theta(f(0.7));
    writeln!(
        out,
        "{p} deflection{}",
        [d.theta, d.one_minus_cos, d.one_plus_cos]
            .map(F::bits)
            .concat()
    )
    .unwrap();

    let table = Tabulated::new(&table_theta, &table_values, &mut table_cdf)?;
    for spec in specs {
        let phase: Phase<'_, F> = match spec {
            "table" => Phase::Tabulated(table),
            _ => match Spec::<F>::parse(spec)? {
                Spec::Analytic(phase) => phase,
                Spec::Table { .. } => unreachable!("no table spec here"),
            },
        };
        let inverse = phase.invert(d);
        let sampled = phase.sample(f(0.3));
        writeln!(
            out,
            "{p} {spec}{}{}{}{}{}{}",
            phase.eval(d).bits(),
            phase.cdf(d).bits(),
            status(&inverse),
            inverse.unwrap_or(F::ZERO).bits(),
            [sampled.theta, sampled.one_minus_cos, sampled.one_plus_cos]
                .map(F::bits)
                .concat(),
            phase.mean_cosine().bits(),
        )
        .unwrap();

        let omnee = Omnee::new(c, &phase);
        let equiangular = Equiangular::new(c, &phase, directions, region);
        let distance = Distance::new(c, &phase, directions, region, sigma)?;
        let techniques: [&dyn Technique<F>; 3] = [&omnee, &equiangular, &distance];
        for (i, u) in u3.iter().enumerate() {
            let u = u.map(f);
            for (k, technique) in techniques.iter().enumerate() {
                let s = technique.sample(u);
                let sample = s.unwrap_or(zero());
                let inverse = technique.invert(sample.x1);
                writeln!(
                    out,
                    "{p} {spec} technique {k} u {i}{}{}{}{}{}{}{}",
                    status(&s),
                    sample_bits(&sample),
                    technique.pdf(sample.x1).bits(),
                    status(&inverse),
                    inverse.unwrap_or([F::ZERO; 3]).map(F::bits).concat(),
                    problem.f_c(sample.x1).bits(),
                    problem.estimate(&sample).bits(),
                )
                .unwrap();
            }
        }

        let mis = OmneeMis::recommended(omnee, &equiangular);
        for (i, u) in u6.iter().enumerate() {
            let vertices = mis.sample(u.map(f));
            let present = vertices
                .iter()
                .enumerate()
                .map(|(k, s)| u32::from(s.is_some()) << k)
                .sum::<u32>();
            let status = if present != 0 { " s0" } else { " s1" };
            write!(out, "{p} {spec} mis u {i}{status} {present:08x}").unwrap();
            for (k, vertex) in vertices.iter().enumerate() {
                let sample = vertex.unwrap_or(zero());
                write!(out, "{}", sample_bits(&sample)).unwrap();
                if vertex.is_some() {
                    // The C API's inverse: OMNEE's numbers with the companion
                    // undrawn, or the companion's scaled into u[3] < c; kept
                    // when the MIS draws that vertex again from them.
                    let z = F::ZERO;
                    let u = if k == 0 {
                        omnee
                            .invert(sample.x1)
                            .map(|[a, b, c]| [a, b, c, F::ONE_MINUS_EPSILON, z, z])
                    } else {
                        equiangular
                            .invert(sample.x1)
                            .map(|[a, b, c]| [z, z, z, a * mis.rate(), b, c])
                    };
                    let u = u.filter(|u| mis.sample(*u)[k].is_some());
                    write!(
                        out,
                        "{}{}{}",
                        mis.pdf(sample.x1).bits(),
                        if u.is_some() { " s0" } else { " s1" },
                        u.unwrap_or([z; 6]).map(F::bits).concat()
                    )
                    .unwrap();
                }
            }
            writeln!(out).unwrap();
        }
    }

    let reference = problem.integral(&HenyeyGreenstein::new(0.9)?);
    writeln!(out, "{p} reference hg:0.9{}", reference.bits()).unwrap();
    bridges::<F>(&mut out, u3)?;
    Ok(out)
}

/// The bridge lines of `tests/bits_body.inc`: bridges of 1, 2 and 5
/// vertices (hg:0.9), their densities and estimates, the number of
/// vertices drawn, and the isotropic closed form.
fn bridges<F: Bits>(out: &mut String, u3: [[f64; 3]; 4]) -> Result<(), omnee_core::Error> {
    let p = F::NAME;
    let (x0, x2) = (v::<F>(0.3, -0.2, 1.1), v::<F>(-0.1, 0.4, 0.2));
    let hg = HenyeyGreenstein::new(F::from_f64(0.9))?;
    let bridge = Bridge::new(x0, x2, hg)?;
    let medium = Homogeneous::new(F::from_f64(0.5), F::from_f64(0.05))?;
    for k in [1usize, 2, 5] {
        let mut u = [[F::ZERO; 3]; 5];
        for j in 0..3 * k {
            u[j / 3][j % 3] = F::from_f64(u3[j % 4][j % 3]) * F::from_f64(0.999);
        }
        let mut x = [x0; 5];
        let b = bridge.sample(&u[..k], &mut x[..k]);
        let drawn = status(&b);
        let b = b.expect("these numbers give a bridge");
        write!(out, "{p} bridge k {k}{drawn} {:08x}", b.k).unwrap();
        for f in [b.length, b.pdf, b.phase_ratio, b.weight] {
            write!(out, "{}", f.bits()).unwrap();
        }
        for xi in &x[..k] {
            write!(out, "{}", xi.to_array().map(F::bits).concat()).unwrap();
        }
        let estimate = bridge.estimate(&b, &medium);
        write!(out, "{}{}", bridge.pdf(&x[..k]).bits(), estimate.bits()).unwrap();
        let mut inverse = [[F::ZERO; 3]; 5];
        let found = bridge.invert(&x[..k], &mut inverse[..k]);
        write!(out, "{}", status(&found)).unwrap();
        for ui in &inverse[..k] {
            write!(out, "{}", ui.map(F::bits).concat()).unwrap();
        }
        writeln!(out).unwrap();
    }
    let count = VertexCount::new(
        8,
        bridge.axis.s,
        medium.sigma_s(),
        medium.sigma_t(),
        hg.mean_cosine(),
    )?;
    write!(out, "{p} vertex count").unwrap();
    for u in &u3 {
        let (k, probability) = count.sample(F::from_f64(u[0]));
        write!(out, " {k:08x}{}", probability.bits()).unwrap();
    }
    writeln!(out).unwrap();
    let (s, sigma_s, sigma_t) = (
        bridge.axis.s.to_f64(),
        medium.sigma_s().to_f64(),
        medium.sigma_t().to_f64(),
    );
    let reference = isotropic_transfer(3, s, sigma_s, sigma_t, REFERENCE_BUDGET)?;
    writeln!(out, "{p} bridge reference k 3{}", reference.bits()).unwrap();
    Ok(())
}

/// The batch of `tests/bits.c`.
fn batch() -> Result<String, omnee_core::Error> {
    const N: usize = 16;
    let mut out = String::new();
    let u0: Vec<f32> = (0..N).map(|i| (i as f32 + 0.5) / 16.0).collect();
    let u1: Vec<f32> = (0..N)
        .map(|i| (((i * 7) % N) as f32 + 0.25) / 16.0)
        .collect();
    let u2: Vec<f32> = (0..N)
        .map(|i| (((i * 11) % N) as f32 + 0.75) / 16.0)
        .collect();
    let (mut x, mut y, mut z) = ([0.0f32; N], [0.0f32; N], [0.0f32; N]);
    let (mut pdf, mut weight) = ([0.0f32; N], [0.0f32; N]);
    let c = Connection::new(Vec3::new(0.3, -0.2, 1.1), Vec3::new(-0.1, 0.4, 0.2), 2.8)?;
    let omnee = Omnee::new(c, HenyeyGreenstein::new(0.9f32)?);
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
    writeln!(out, "f32 batch count {count}").unwrap();
    for i in 0..N {
        let row = [x[i], y[i], z[i], pdf[i], weight[i]]
            .map(f32::bits)
            .concat();
        writeln!(out, "f32 batch {i}{row}").unwrap();
    }
    Ok(out)
}

fn main() -> Result<(), omnee_core::Error> {
    print!("{}{}{}", run::<f32>()?, run::<f64>()?, batch()?);
    Ok(())
}

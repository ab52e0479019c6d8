//! Extreme scales (docs/math.md §15): every technique's estimate of the
//! point-to-point transfer at end points from 1e-30 to 3e38 apart in f32 and
//! from 1e-300 to 1.6e308 apart in f64, against the quadrature reference of
//! the same problem at unit scale.
//!
//! The problem: `x0 = λ (1, 0, 0)`, `x2 = λ (0, 1, 0)` (s = √2 λ), σs = 0.4/λ,
//! σa = 0.1/λ, Henyey–Greenstein g = 0.5 at `x1`, θmax = π (π/2 where the
//! vertices behind the Thales ball lie beyond the largest number); for the
//! lobe techniques HG 0.8 at `x0` about +z, perpendicular to the axis; the
//! cosine rays' receiver normal (0.3, −0.2, 1). Moving the end points by λ
//! and σ by 1/λ divides `f_c` and every weight by λ and the transfer by λ²
//! (docs/math.md §15.3), and at these scales the transfer λ⁻² I itself is
//! outside the precision's range (1e60 at s = 1e-30 in f32), so each draw's
//! estimate is taken factor by factor, `(f_c λ)(weight λ)`, in f64.
//!
//! Per precision, scale and technique, over `--samples N` draws (default
//! 2^18, the same uniform numbers at every scale): the estimate's ratio to
//! the unit problem's reference with its standard error, its ratio to the
//! same draws at λ = 1 (the scale invariance; 1 up to the rounding of the
//! scaled end points), the draws with a vertex, and the counts of refused
//! constructors and of non-finite or negative numbers (target: none). The
//! ray techniques (equiangular, distance) have infinite variance on this
//! problem (their weight grows as 1/d1 next to `x0`), so their standard
//! errors understate their error; their invariance column is what this
//! table shows of them.
//!
//! Bridges of k = 1, 2, 3 vertices (docs/math.md §14) follow in a table of
//! their own: isotropic scattering, so that the unit problem's `I_k` is the
//! closed form; each draw's estimate in f64 (`Bridge::estimate_f64`) times
//! λ². Where `λ⁻² I_k` itself leaves f64 (λ = 1e-200 and below, 1e200 and
//! above) the row says so instead. At `s = 0.6 max` a bridge's vertices
//! reach beyond the largest number (D > s, in every direction), so the
//! paths through them are not representable and the estimate is that of
//! the representable part of `I_k`, less than 1 (the column of draws with a
//! path says how much is missing).
//!
//! Run: `cargo bench --bench scale` (a minute), optional `-- --samples N`.
//! Writes `docs/results/scale.md`.

mod common;

use common::{arg, docs_path};
use glam::DVec3;
use omnee::bridge::{Bridge, MAX_VERTICES, REFERENCE_BUDGET, isotropic_transfer};
use omnee::lobe::{LobeMis, LobeRay, LobeToPoint, PhaseLobe, WithLobe};
use omnee::medium::{Homogeneous, Region};
use omnee::mis::OmneeMis;
use omnee::phase::{HenyeyGreenstein, Isotropic};
use omnee::reference::PointToPoint;
use omnee::rng::SplitMix64;
use omnee::sampling::{
    Connection, Directions, Distance, Equiangular, Omnee, Sample, Technique, uniform,
};
use omnee::{Error, Real, Vector};
use std::fmt::Write as _;

const TECHNIQUES: [&str; 8] = [
    "omnee",
    "equiangular",
    "equiangular, cosine rays",
    "distance",
    "omnee MIS (recommended)",
    "omnee with the lobe",
    "lobe ray",
    "lobe MIS (recommended)",
];

/// The problem at scale λ in precision F.
struct Problem<F: Real> {
    connection: Connection<F>,
    point: PointToPoint<F>,
    cosine: PointToPoint<F>,
    lobe: PhaseLobe<F, HenyeyGreenstein<F>>,
    hg: HenyeyGreenstein<F>,
    sigma_t: F,
    normal: F::Vec3,
}

impl<F: Real> Problem<F> {
    fn new(lambda: f64, theta_max: F) -> Result<Self, Error> {
        let v =
            |x: f64, y: f64, z: f64| F::Vec3::new(F::from_f64(x), F::from_f64(y), F::from_f64(z));
        let connection = Connection::new(v(lambda, 0.0, 0.0), v(0.0, lambda, 0.0), theta_max)?;
        let (sigma_s, sigma_a) = (F::from_f64(0.4 / lambda), F::from_f64(0.1 / lambda));
        let medium = Homogeneous::new(sigma_s, sigma_a)?;
        let normal = v(0.3, -0.2, 1.0);
        Ok(Self {
            connection,
            point: PointToPoint::new(connection, medium, None)?,
            cosine: PointToPoint::new(connection, medium, Some(normal))?,
            lobe: PhaseLobe::new(HenyeyGreenstein::new(F::from_f64(0.8))?, v(0.0, 0.0, 1.0))?,
            hg: HenyeyGreenstein::new(F::from_f64(0.5))?,
            sigma_t: sigma_s + sigma_a,
            normal,
        })
    }

    /// Technique `k`'s vertices from six uniform numbers, with the `f_c` of
    /// the problem it estimates.
    fn draw(&self, k: usize, u: [F; 6]) -> Result<Vec<(Sample<F>, F)>, Error> {
        let (c, hg) = (self.connection, self.hg);
        let u3 = [u[0], u[1], u[2]];
        let eq = Equiangular::new(c, hg, Directions::Sphere, Region::Everywhere);
        let samples: Vec<Sample<F>> = match k {
            0 => Omnee::new(c, hg).sample(u3).into_iter().collect(),
            1 => eq.sample(u3).into_iter().collect(),
            2 => Equiangular::new(c, hg, Directions::cosine(self.normal)?, Region::Everywhere)
                .sample(u3)
                .into_iter()
                .collect(),
            3 => Distance::new(c, hg, Directions::Sphere, Region::Everywhere, self.sigma_t)?
                .sample(u3)
                .into_iter()
                .collect(),
            4 => OmneeMis::recommended(Omnee::new(c, hg), &eq)
                .sample(u)
                .into_iter()
                .flatten()
                .collect(),
            5 => WithLobe::new(Omnee::new(c, hg), self.lobe, c.axis.x0)
                .sample(u3)
                .into_iter()
                .collect(),
            6 => LobeRay::new(c, self.lobe, hg)
                .sample(u3)
                .into_iter()
                .collect(),
            _ => LobeMis::recommended(c, self.lobe, hg)
                .sample(u3)
                .into_iter()
                .collect(),
        };
        let problem = if k == 2 { &self.cosine } else { &self.point };
        Ok(samples
            .into_iter()
            .map(|s| (s, problem.f_c(s.x1)))
            .collect())
    }
}

/// One row: the estimate at λ over `n` draws and at λ = 1 with the same
/// numbers.
struct Row {
    mean: f64,
    se: f64,
    unit_mean: f64,
    drawn: usize,
    refused: usize,
    bad: usize,
}

fn run<F: Real>(k: usize, lambda: f64, theta_max: F, n: usize) -> Row {
    let (scaled, unit) = (
        Problem::<F>::new(lambda, theta_max),
        Problem::<F>::new(1.0, theta_max),
    );
    let mut row = Row {
        mean: 0.0,
        se: 0.0,
        unit_mean: 0.0,
        drawn: 0,
        refused: 0,
        bad: 0,
    };
    let (Ok(scaled), Ok(unit)) = (scaled, unit) else {
        row.refused += 1;
        return row;
    };
    let mut rng = SplitMix64::new(0x5ca1e + k as u64);
    let (mut sum, mut sum2, mut unit_sum) = (0.0, 0.0, 0.0);
    for _ in 0..n {
        let u: [F; 6] = core::array::from_fn(|_| uniform(&mut rng));
        let (Ok(a), Ok(b)) = (scaled.draw(k, u), unit.draw(k, u)) else {
            row.refused += 1;
            continue;
        };
        let mut e = 0.0;
        for (s, f_c) in &a {
            let ok = |x: F| x.is_finite() && x >= F::ZERO;
            if !(s.x1.is_finite() && ok(s.pdf) && ok(s.weight) && ok(*f_c)) {
                row.bad += 1;
                continue;
            }
            e += (f_c.to_f64() * lambda) * (s.weight.to_f64() * lambda);
        }
        row.drawn += usize::from(!a.is_empty());
        sum += e;
        sum2 += e * e;
        unit_sum += b
            .iter()
            .map(|(s, f_c)| f_c.to_f64() * s.weight.to_f64())
            .sum::<f64>();
    }
    row.mean = sum / n as f64;
    row.se = ((sum2 / n as f64 - row.mean * row.mean).max(0.0) / n as f64).sqrt();
    row.unit_mean = unit_sum / n as f64;
    row
}

/// The unit problem's references in f64: without the lobe, with it, and
/// with the receiver's cosine.
fn references(theta_max: f64) -> [f64; 3] {
    let c = Connection::new(DVec3::X, DVec3::Y, theta_max).unwrap();
    let medium = Homogeneous::new(0.4, 0.1).unwrap();
    let point = PointToPoint::new(c, medium, None).unwrap();
    let hg = HenyeyGreenstein::new(0.5).unwrap();
    let lobe = PhaseLobe::new(HenyeyGreenstein::new(0.8).unwrap(), DVec3::Z).unwrap();
    let normal = DVec3::new(0.3, -0.2, 1.0);
    [
        point.try_integral(&hg).unwrap(),
        LobeToPoint::new(point, Some(lobe))
            .unwrap()
            .try_integral(&hg)
            .unwrap(),
        PointToPoint::new(c, medium, Some(normal))
            .unwrap()
            .try_integral(&hg)
            .unwrap(),
    ]
}

fn table<F: Real>(out: &mut String, name: &str, scales: &[f64], n: usize) {
    let max = F::MAX.to_f64();
    let refs_pi = references(core::f64::consts::PI);
    let refs_half = references(core::f64::consts::FRAC_PI_2);
    writeln!(out, "\n### {name}\n").unwrap();
    writeln!(
        out,
        "| s = √2 λ | θmax | technique | estimate ÷ reference | ± (1 se) | ÷ same draws at λ = 1 | draws with a vertex | refused | non-finite or negative |"
    )
    .unwrap();
    writeln!(out, "|---|---|---|---|---|---|---|---|---|").unwrap();
    for &lambda in scales {
        let thales = lambda * 2f64.sqrt() > 1e-4 * max;
        let (theta_max, refs) = if thales {
            (F::FRAC_PI_2, refs_half)
        } else {
            (F::PI, refs_pi)
        };
        for (k, technique) in TECHNIQUES.iter().enumerate() {
            let reference = match k {
                2 => refs[2],
                5..=7 => refs[1],
                _ => refs[0],
            };
            let row = run::<F>(k, lambda, theta_max, n);
            writeln!(
                out,
                "| {:.2e} | {} | {technique} | {:.4} | {:.4} | {:.9} | {:.1} % | {} | {} |",
                lambda * 2f64.sqrt(),
                if thales { "π/2" } else { "π" },
                row.mean / reference,
                row.se / reference,
                row.mean / row.unit_mean,
                100.0 * row.drawn as f64 / n as f64,
                row.refused,
                row.bad
            )
            .unwrap();
        }
    }
}

/// The bridges of `k` vertices at scale λ in precision `F` over `n` draws:
/// the mean and standard error of `λ² · estimate` (f64), the draws with a
/// path, and the non-finite or negative estimates; `None` if the scaled
/// problem was refused.
fn bridge_row<F: Real>(k: usize, lambda: f64, n: usize) -> Option<Row> {
    let v = |x: f64, y: f64| F::Vec3::new(F::from_f64(x), F::from_f64(y), F::ZERO);
    let bridge = Bridge::new(v(lambda, 0.0), v(0.0, lambda), Isotropic).ok()?;
    let medium =
        Homogeneous::from_extinction(F::from_f64(0.4 / lambda), F::from_f64(0.5 / lambda)).ok()?;
    let mut rng = SplitMix64::new(0xb1d6e + k as u64);
    let mut x = [bridge.axis.x0; MAX_VERTICES];
    let mut u = [[F::ZERO; 3]; MAX_VERTICES];
    let (mut sum, mut sum2) = (0.0, 0.0);
    let mut row = Row {
        mean: 0.0,
        se: 0.0,
        unit_mean: f64::NAN,
        drawn: 0,
        refused: 0,
        bad: 0,
    };
    for _ in 0..n {
        for ui in u[..k].iter_mut() {
            *ui = core::array::from_fn(|_| uniform(&mut rng));
        }
        let Some(b) = bridge.sample(&u[..k], &mut x[..k]) else {
            continue;
        };
        row.drawn += 1;
        let e = bridge.estimate_f64(&b, &medium) * lambda * lambda;
        if !(e.is_finite() && e >= 0.0) {
            row.bad += 1;
            continue;
        }
        sum += e;
        sum2 += e * e;
    }
    row.mean = sum / n as f64;
    row.se = ((sum2 / n as f64 - row.mean * row.mean).max(0.0) / n as f64).sqrt();
    Some(row)
}

/// The bridge table of precision `F`: k = 1, 2, 3 at every scale.
fn bridge_table<F: Real>(out: &mut String, name: &str, scales: &[f64], n: usize) {
    writeln!(out, "\n### Bridges, {name}\n").unwrap();
    writeln!(
        out,
        "| s = √2 λ | k | λ² · estimate ÷ closed form | ± (1 se) | draws with a path | refused | non-finite or negative |"
    )
    .unwrap();
    writeln!(out, "|---|---|---|---|---|---|---|").unwrap();
    for &lambda in scales {
        for k in 1..=3 {
            let unit = isotropic_transfer(k, 2f64.sqrt(), 0.4, 0.5, REFERENCE_BUDGET).unwrap();
            let scaled = unit / lambda / lambda;
            let s = lambda * 2f64.sqrt();
            if !(scaled.is_normal() && scaled < f64::MAX) {
                writeln!(
                    out,
                    "| {s:.2e} | {k} | λ⁻² I_k ≈ 1e{:.0} is beyond f64 | | | | |",
                    unit.log10() - 2.0 * lambda.log10()
                )
                .unwrap();
                continue;
            }
            match bridge_row::<F>(k, lambda, n) {
                Some(row) => writeln!(
                    out,
                    "| {s:.2e} | {k} | {:.4} | {:.4} | {:.1} % | 0 | {} |",
                    row.mean / unit,
                    row.se / unit,
                    100.0 * row.drawn as f64 / n as f64,
                    row.bad
                )
                .unwrap(),
                None => writeln!(out, "| {s:.2e} | {k} | | | | 1 | |").unwrap(),
            }
        }
    }
}

fn main() {
    let n: usize = arg("--samples", 1 << 18);
    let start = std::time::Instant::now();
    let mut out = format!(
        "<!-- generated by `cargo bench --bench scale -- --samples {n}`; do not edit -->\n\n\
         Estimates of the point-to-point transfer at extreme scales (benches/scale.rs):\n\
         `x0 = λ (1, 0, 0)`, `x2 = λ (0, 1, 0)`, σs = 0.4/λ, σa = 0.1/λ, HG 0.5, {n} draws per row,\n\
         each draw's estimate `(f_c λ)(weight λ)` in f64 (the transfer λ⁻² I itself\n\
         leaves the range), against the f64 quadrature reference of the unit problem.\n\
         The last scale of each precision is `(0.6 max, 0, 0)` to `(0, 0.6 max, 0)`;\n\
         there a bridge's paths reach beyond the largest number, and only the\n\
         representable ones are estimated (the bridge tables' last rows).\n"
    );
    let f32_max = f32::MAX as f64;
    table::<f32>(
        &mut out,
        "f32",
        &[
            1e-30 / 2f64.sqrt(),
            1e-20,
            1e-10,
            1.0,
            1e10,
            1e20,
            1e30 / 2f64.sqrt(),
            1e38 / 2f64.sqrt(),
            3e38 / 2f64.sqrt(),
            0.6 * f32_max,
        ],
        n,
    );
    table::<f64>(
        &mut out,
        "f64",
        &[
            1e-300 / 2f64.sqrt(),
            1e-200,
            1e-100,
            1.0,
            1e100,
            1e200,
            1e300 / 2f64.sqrt(),
            1.6e308 / 2f64.sqrt(),
            0.6 * f64::MAX,
        ],
        n,
    );
    let bridge_scales = [1e-30, 1e-20, 1.0, 1e20, 1e30, 0.6 * f32_max];
    bridge_table::<f32>(&mut out, "f32", &bridge_scales.map(|s| s / 2f64.sqrt()), n);
    let bridge_scales = [1e-300, 1e-200, 1e-100, 1.0, 1e100, 1e200, 0.6 * f64::MAX];
    bridge_table::<f64>(&mut out, "f64", &bridge_scales.map(|s| s / 2f64.sqrt()), n);
    writeln!(
        out,
        "\n{:.0} s on the shared 2-core machine.",
        start.elapsed().as_secs_f64()
    )
    .unwrap();
    let path = docs_path("results/scale.md");
    std::fs::write(&path, &out).expect("write docs/results/scale.md");
    print!("{out}");
    eprintln!("wrote {}", path.display());
}

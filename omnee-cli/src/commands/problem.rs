//! The point-to-point problem of `omnee estimate` and `omnee samples`: a
//! unit-intensity point light `x0`, a point receiver `x2` (with a cosine
//! about an optional normal), an infinite homogeneous medium, and the
//! once-more integrand restricted to θ < θmax.

use super::args::{parse_vec3, unit_normal};
use crate::error::{CliError, Result, core_error};
use crate::phase::{PhaseSpec, TableStorage};
use crate::range::Range;
use crate::rng::Rng;
use crate::technique::{self, Choice, Technique};
use clap::{Args, ValueEnum};
use omnee_core::medium::{Homogeneous, Region};
use omnee_core::method::{Method, Setup};
use omnee_core::phase::{Phase, PhaseFunction};
use omnee_core::reference::PointToPoint;
use omnee_core::sampling::{Connection, Directions, Draw, Sample};
use omnee_core::{Real, Vector};

/// Arithmetic precision of the techniques.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum Precision {
    /// f32, as the renderer
    F32,
    /// f64
    F64,
}

crate::names::display_by_name!(Precision);

/// The options that state the problem.
#[derive(Args, Debug)]
pub struct ProblemArgs {
    /// The unit-intensity point light x0 = X,Y,Z.
    #[arg(long, value_parser = parse_vec3, allow_hyphen_values = true)]
    pub x0: [f64; 3],
    /// The point receiver x2 = X,Y,Z.
    #[arg(long, value_parser = parse_vec3, allow_hyphen_values = true)]
    pub x2: [f64; 3],
    /// Phase function spec (see below).
    #[arg(long, default_value = "iso")]
    pub phase: String,
    /// Scattering coefficient (1/m).
    #[arg(long, allow_hyphen_values = true)]
    pub sigma_s: f64,
    /// Extinction coefficient (1/m), at least sigma-s.
    #[arg(long, allow_hyphen_values = true)]
    pub sigma_t: f64,
    /// The integrand is restricted to theta < THETA_MAX (radians, (0, pi]).
    #[arg(long, allow_hyphen_values = true, default_value_t = std::f64::consts::PI)]
    pub theta_max: f64,
    /// A receiver cosine max(0, n . (x1 - x2)/d2) about this normal.
    #[arg(long, value_parser = parse_vec3, allow_hyphen_values = true)]
    pub receiver_normal: Option<[f64; 3]>,
    /// Technique for x1.
    #[arg(long, value_enum, default_value_t = Technique::Auto)]
    pub technique: Technique,
    /// Random seed.
    #[arg(long, default_value_t = 1)]
    pub seed: u64,
    /// Arithmetic precision of the techniques.
    #[arg(long, value_enum, default_value_t = Precision::F32)]
    pub precision: Precision,
}

/// How messages name the problem's fields: as the command's options
/// (`--sigma-s`), or as the fields of [`ProblemArgs`] and
/// [`EstimateArgs`](super::estimate::EstimateArgs) (`sigma_s`) for a program
/// that fills those structs itself (the Python bindings name their keyword
/// arguments after them).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Names {
    /// `--sigma-s`, `--receiver-normal`: the command line's.
    #[default]
    Options,
    /// `sigma_s`, `receiver_normal`: the structs' own.
    Fields,
}

impl Names {
    /// `field` (a field of the options' structs, in snake case) as messages
    /// name it.
    pub fn of(self, field: &str) -> String {
        match self {
            Names::Options => format!("--{}", field.replace('_', "-")),
            Names::Fields => field.to_string(),
        }
    }

    /// Several fields named by [`Names::of`], joined by `/` (the fields a
    /// core constructor's parameters came from).
    pub fn list(self, fields: &[&str]) -> String {
        let names: Vec<String> = fields.iter().map(|f| self.of(f)).collect();
        names.join("/")
    }
}

/// The checked problem in f64.
pub struct Problem {
    /// The phase function.
    pub phase: PhaseSpec,
    /// The receiver's unit normal, if it has a cosine.
    pub normal: Option<[f64; 3]>,
    /// The phase function's mean cosine.
    pub g: f64,
    /// The optical thickness `σt·|x2 − x0|`.
    pub tau: f64,
    /// The technique.
    pub choice: Choice,
    /// How messages name the fields.
    pub names: Names,
}

impl Problem {
    /// Checks the options, naming the first bad one as the command line
    /// does ([`Names::Options`]).
    pub fn new(a: &ProblemArgs) -> Result<Self> {
        Self::named(a, Names::Options)
    }

    /// Checks the fields, naming the first bad one by `names`.
    pub fn named(a: &ProblemArgs, names: Names) -> Result<Self> {
        let phase = PhaseSpec::parse(&a.phase).map_err(|e| e.context(&names.of("phase")))?;
        let (x0, x2) = (point(names, "x0", a.x0)?, point(names, "x2", a.x2)?);
        Range::NON_NEGATIVE.check(&names.of("sigma_s"), a.sigma_s)?;
        if !(a.sigma_t.is_finite() && a.sigma_t >= a.sigma_s) {
            return Err(CliError::range(
                &names.of("sigma_t"),
                a.sigma_t,
                format!("[sigma_s, inf) = [{}, inf)", a.sigma_s),
            ));
        }
        Range::THETA_MAX.check(&names.of("theta_max"), a.theta_max)?;
        let field = names.of("receiver_normal");
        let normal = a
            .receiver_normal
            .map(|n| unit_normal(&field, point(names, "receiver_normal", n)?))
            .transpose()?;
        let d = [0, 1, 2].map(|i| x2[i] - x0[i]);
        let s = (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt();
        if !(s > 0.0) {
            return Err(CliError::Input(format!(
                "{} = {},{},{} equals {}; allowed: any other point",
                names.of("x2"),
                x2[0],
                x2[1],
                x2[2],
                names.of("x0")
            )));
        }
        let mut st = TableStorage::<f64>::default();
        let g = phase.instantiate::<f64>(&mut st)?.mean_cosine();
        let tau = a.sigma_t * s;
        let choice = technique::choose(a.technique, g, tau);
        Ok(Problem {
            phase,
            normal,
            g,
            tau,
            choice,
            names,
        })
    }
}

/// `v` if its three components are finite (the command line's parser
/// guarantees it; a program filling [`ProblemArgs`] may not).
fn point(names: Names, field: &str, v: [f64; 3]) -> Result<[f64; 3]> {
    if v.iter().all(|x| x.is_finite()) {
        Ok(v)
    } else {
        Err(CliError::Input(format!(
            "{} = {},{},{} is not a point; allowed: three finite numbers",
            names.of(field),
            v[0],
            v[1],
            v[2]
        )))
    }
}

/// The problem in precision `F`, ready to draw.
pub struct Sampler<'p, F: Real> {
    setup: Setup<F, &'p Phase<'p, F>>,
    connection: Connection<F>,
    method: Method,
    /// The integrand and its quadrature.
    pub problem: PointToPoint<F>,
}

impl<F: Real> Sampler<'_, F> {
    /// One draw of the method (three uniform numbers, six for `mis`).
    pub fn draw(&self, rng: &mut Rng) -> Draw<F> {
        self.setup
            .draw(self.method, self.connection, || rng.uniform())
    }

    /// A vertex's contribution `f_c(x1) · weight`.
    pub fn estimate(&self, s: &Sample<F>) -> f64 {
        self.problem.estimate(s).to_f64()
    }
}

fn vec3<F: Real>(a: [f64; 3]) -> F::Vec3 {
    F::Vec3::new(F::from_f64(a[0]), F::from_f64(a[1]), F::from_f64(a[2]))
}

/// Runs `f` with a sampler for the problem in precision `F`.
pub fn with_sampler<F: Real, T>(
    a: &ProblemArgs,
    p: &Problem,
    f: impl FnOnce(&Sampler<'_, F>) -> T,
) -> Result<T> {
    let name = |fields: &[&str]| p.names.list(fields);
    let connection =
        Connection::<F>::new(vec3::<F>(a.x0), vec3::<F>(a.x2), F::from_f64(a.theta_max))
            .map_err(|e| core_error(&name(&["x0", "x2", "theta_max"]), e))?;
    let medium = Homogeneous::new(F::from_f64(a.sigma_s), F::from_f64(a.sigma_t - a.sigma_s))
        .map_err(|e| core_error(&name(&["sigma_s", "sigma_t"]), e))?;
    let problem = PointToPoint::new(connection, medium, p.normal.map(vec3::<F>))
        .map_err(|e| core_error(&name(&["receiver_normal"]), e))?;
    let mut storage = TableStorage::<F>::default();
    let phase = p.phase.instantiate::<F>(&mut storage)?;
    let directions = match p.normal {
        Some(n) => Directions::cosine(vec3::<F>(n))
            .map_err(|e| core_error(&name(&["receiver_normal"]), e))?,
        None => Directions::Sphere,
    };
    let setup = Setup::new(
        &phase,
        directions,
        Region::Everywhere,
        F::from_f64(a.sigma_t),
    )
    .map_err(|e| core_error(&name(&["sigma_t"]), e))?;
    Ok(f(&Sampler {
        setup,
        connection,
        method: p.choice.method,
        problem,
    }))
}

/// `x1` of a sample in f64.
pub fn x1_f64<F: Real>(s: &Sample<F>) -> [f64; 3] {
    s.x1.to_array().map(|x| x.to_f64())
}

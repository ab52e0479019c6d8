//! The point-to-point problem: a unit-intensity point light `x0`, a point
//! receiver `x2` (with a cosine about an optional normal), an infinite
//! homogeneous medium, the once-more integrand restricted to θ < θmax, and
//! optionally a lobe at `x0` (docs/math.md §1, §12), or instead of one
//! vertex a bridge of several (docs/math.md §14, [`super::bridge`]).
//! [`Problem`] is what a caller states; [`Problem::check`] gives the [`Prepared`] problem, every
//! field checked and the technique resolved, which the engines draw from.

use crate::error::{RenderError, Result, Spelling, core_error};
use crate::phase::{PhaseSpec, TableStorage};
use crate::range::Range;
use crate::rng::Rng;
use crate::technique::Resolved;
use crate::vertices::VertexNumber;
use omnee_core::lobe::PhaseLobe;
use omnee_core::medium::{Homogeneous, Region};
use omnee_core::method::{Choice, LobeMethod, LobeTechnique, Method, Setup};
use omnee_core::names::Named;
use omnee_core::phase::{Phase, PhaseFunction};
use omnee_core::reference::PointToPoint;
use omnee_core::sampling::{Connection, Directions, Draw, Sample};
use omnee_core::{Real, Vector};

/// Arithmetic precision of the techniques.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Precision {
    /// f32, as a renderer uses it.
    F32,
    /// f64.
    F64,
}

impl Named for Precision {
    const ALL: &'static [Self] = &[Precision::F32, Precision::F64];
    fn name(self) -> &'static str {
        match self {
            Precision::F32 => "f32",
            Precision::F64 => "f64",
        }
    }
    fn help(self) -> &'static str {
        match self {
            Precision::F32 => "f32, as the renderer",
            Precision::F64 => "f64",
        }
    }
}

omnee_core::display_by_name!(Precision);

/// The problem as a caller states it (plain data; nothing checked yet).
#[derive(Clone, Debug, PartialEq)]
pub struct Problem {
    /// The unit-intensity point light `x0`.
    pub x0: [f64; 3],
    /// The point receiver `x2`.
    pub x2: [f64; 3],
    /// The phase function at `x1`, a spec such as `hg:0.9`.
    pub phase: String,
    /// Scattering coefficient σs (1/m).
    pub sigma_s: f64,
    /// Extinction coefficient σt ≥ σs (1/m).
    pub sigma_t: f64,
    /// The integrand is restricted to θ < θmax (radians, (0, π]).
    pub theta_max: f64,
    /// A receiver cosine `max(0, n · (x1 − x2)/d2)` about this normal (any
    /// non-zero length).
    pub receiver_normal: Option<[f64; 3]>,
    /// The technique for `x1`.
    pub technique: Choice,
    /// Random seed.
    pub seed: u64,
    /// Arithmetic precision of the techniques.
    pub precision: Precision,
    /// The phase function at `x0`, if `x0` is a scattering vertex whose
    /// light leaves it with a lobe about `x0_incoming` (both or neither).
    pub x0_phase: Option<String>,
    /// The propagation direction of the light arriving at `x0`.
    pub x0_incoming: Option<[f64; 3]>,
    /// The number of scattering vertices between `x0` and `x2`: one (the
    /// once-more integral, drawn by `technique`), or bridges of `K`
    /// vertices or of a drawn number (docs/math.md §14), which take
    /// θmax = π, no receiver cosine, no lobe and `technique = auto`.
    pub vertices: VertexNumber,
}

impl Default for Problem {
    /// `x0 = (0, 0, 1)`, `x2 = 0`, isotropic, σs = 0.5, σt = 0.55, θmax = π,
    /// `auto`, seed 1, f64, no lobe, one vertex.
    fn default() -> Self {
        Self {
            x0: [0.0, 0.0, 1.0],
            x2: [0.0; 3],
            phase: "iso".into(),
            sigma_s: 0.5,
            sigma_t: 0.55,
            theta_max: std::f64::consts::PI,
            receiver_normal: None,
            technique: Choice::Auto,
            seed: 1,
            precision: Precision::F64,
            x0_phase: None,
            x0_incoming: None,
            vertices: VertexNumber::Fixed(1),
        }
    }
}

/// The lobe at `x0`, checked.
#[derive(Clone, Debug)]
pub struct X0Lobe {
    /// The phase function at `x0`.
    pub phase: PhaseSpec,
    /// The unit propagation direction of the arriving light.
    pub incoming: [f64; 3],
}

/// The problem checked: its fields, the phase functions parsed, the
/// technique resolved.
#[derive(Clone, Debug)]
pub struct Prepared {
    /// The problem as stated.
    pub problem: Problem,
    /// The phase function at `x1`.
    pub phase: PhaseSpec,
    /// The receiver's unit normal, if it has a cosine.
    pub normal: Option<[f64; 3]>,
    /// The lobe at `x0`, if there is one.
    pub lobe: Option<X0Lobe>,
    /// The phase function's mean cosine `g`.
    pub g: f64,
    /// The optical thickness `τ = σt · |x2 − x0|`.
    pub tau: f64,
    /// The technique (of one vertex; bridges are drawn by
    /// [`super::bridge`] whatever it says).
    pub technique: Resolved,
    /// The number of vertices, checked.
    pub vertices: VertexNumber,
    /// How messages spell the fields.
    pub spelling: Spelling,
}

impl Problem {
    /// Checks every field, naming the first bad one by `spelling`, and
    /// resolves the technique (`auto` from the phase function's mean cosine
    /// and the optical thickness, [`omnee_core::method::auto`]).
    pub fn check(&self, spelling: Spelling) -> Result<Prepared> {
        let name = |f: &str| spelling.of(f);
        let phase = PhaseSpec::parse(&self.phase).map_err(|e| e.context(&name("phase")))?;
        let (x0, x2) = (
            point(spelling, "x0", self.x0)?,
            point(spelling, "x2", self.x2)?,
        );
        Range::NON_NEGATIVE.check(&name("sigma_s"), self.sigma_s)?;
        if !(self.sigma_t.is_finite() && self.sigma_t >= self.sigma_s) {
            return Err(RenderError::range(
                &name("sigma_t"),
                self.sigma_t,
                format!("[sigma_s, inf) = [{}, inf)", self.sigma_s),
            ));
        }
        Range::THETA_MAX.check(&name("theta_max"), self.theta_max)?;
        let normal = self
            .receiver_normal
            .map(|n| {
                unit_vector(
                    &name("receiver_normal"),
                    point(spelling, "receiver_normal", n)?,
                )
            })
            .transpose()?;
        let d = [0, 1, 2].map(|i| x2[i] - x0[i]);
        let s = (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt();
        if !(s > 0.0) {
            return Err(RenderError::Input(format!(
                "{} = {},{},{} equals {}; allowed: any other point",
                name("x2"),
                x2[0],
                x2[1],
                x2[2],
                name("x0")
            )));
        }
        let lobe = self.lobe(spelling)?;
        let mut st = TableStorage::<f64>::default();
        let g = phase.instantiate::<f64>(&mut st)?.mean_cosine();
        let tau = self.sigma_t * s;
        let technique = self.resolve(lobe.is_some(), g, tau, spelling)?;
        let vertices = self.check_vertices(spelling)?;
        Ok(Prepared {
            problem: self.clone(),
            phase,
            normal,
            lobe,
            g,
            tau,
            technique,
            vertices,
            spelling,
        })
    }

    /// The number of vertices in range; with bridges, the fields that only
    /// one vertex has left at their defaults.
    fn check_vertices(&self, spelling: Spelling) -> Result<VertexNumber> {
        let vertices = self.vertices.check(spelling, 1)?;
        if vertices == VertexNumber::Fixed(1) {
            return Ok(vertices);
        }
        let only_one = |field: &str, value: String, allowed: &str| {
            Err(RenderError::Input(format!(
                "{} = {value} applies to {} = 1 only (with {} = {vertices} every draw is a bridge, \
                 docs/math.md §14); allowed: {allowed}",
                spelling.of(field),
                spelling.of("vertices"),
                spelling.of("vertices"),
            )))
        };
        if self.theta_max != std::f64::consts::PI {
            return only_one(
                "theta_max",
                self.theta_max.to_string(),
                "pi (no restriction)",
            );
        }
        if let Some(n) = self.receiver_normal {
            return only_one(
                "receiver_normal",
                format!("{},{},{}", n[0], n[1], n[2]),
                "none",
            );
        }
        if let Some(p) = &self.x0_phase {
            return only_one("x0_phase", p.clone(), "none");
        }
        if self.technique != Choice::Auto {
            return only_one("technique", self.technique.to_string(), "auto");
        }
        Ok(vertices)
    }

    /// The lobe at `x0`: `x0_phase` and `x0_incoming`, both or neither.
    fn lobe(&self, spelling: Spelling) -> Result<Option<X0Lobe>> {
        let (phase, incoming) = (spelling.of("x0_phase"), spelling.of("x0_incoming"));
        match (&self.x0_phase, self.x0_incoming) {
            (None, None) => Ok(None),
            (Some(_), None) => Err(RenderError::Input(format!(
                "{phase} needs {incoming} X,Y,Z (the propagation direction of the light \
                 arriving at x0)"
            ))),
            (None, Some(_)) => Err(RenderError::Input(format!(
                "{incoming} needs {phase} SPEC (the phase function at x0)"
            ))),
            (Some(spec), Some(w)) => Ok(Some(X0Lobe {
                phase: PhaseSpec::parse(spec).map_err(|e| e.context(&phase))?,
                incoming: unit_vector(&incoming, point(spelling, "x0_incoming", w)?)?,
            })),
        }
    }

    /// The technique used for the requested one: a [`Method`] (`auto`
    /// resolved), or with a lobe at `x0` a [`LobeMethod`].
    fn resolve(&self, lobe: bool, g: f64, tau: f64, spelling: Spelling) -> Result<Resolved> {
        let requested = self.technique;
        let resolved = if lobe {
            requested.lobe_method().map(|m| (Choice::from(m), None))
        } else {
            requested
                .resolve(g, tau)
                .map(|(m, reason)| (Choice::from(m), reason))
        };
        let Some((used, reason)) = resolved else {
            let x0_phase = spelling.of("x0_phase");
            let allowed = if lobe {
                format!("omnee, mis, lobe-mis or auto with {x0_phase}")
            } else {
                format!("omnee, equiangular, distance, mis or auto without {x0_phase}")
            };
            return Err(RenderError::range(
                &spelling.of("technique"),
                requested,
                allowed,
            ));
        };
        Ok(Resolved {
            requested,
            used,
            reason,
        })
    }
}

/// `v` if its three components are finite (the command line's parser
/// guarantees it; a program filling [`Problem`] may not).
fn point(spelling: Spelling, field: &str, v: [f64; 3]) -> Result<[f64; 3]> {
    if v.iter().all(|x| x.is_finite()) {
        Ok(v)
    } else {
        Err(RenderError::Input(format!(
            "{} = {},{},{} is not a point; allowed: three finite numbers",
            spelling.of(field),
            v[0],
            v[1],
            v[2]
        )))
    }
}

/// `n / |n|`, naming `field` when `n` is zero.
pub fn unit_vector(field: &str, n: [f64; 3]) -> Result<[f64; 3]> {
    let len = (n[0] * n[0] + n[1] * n[1] + n[2] * n[2]).sqrt();
    if !(len > 0.0) {
        return Err(RenderError::Input(format!(
            "{field} = {},{},{} has zero length; allowed: any non-zero vector",
            n[0], n[1], n[2]
        )));
    }
    Ok([n[0] / len, n[1] / len, n[2] / len])
}

/// `a` in precision `F`.
pub(crate) fn vec3<F: Real>(a: [f64; 3]) -> F::Vec3 {
    F::Vec3::new(F::from_f64(a[0]), F::from_f64(a[1]), F::from_f64(a[2]))
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

impl Prepared {
    /// The connection, the medium and the point-to-point integrand in
    /// precision `F`.
    fn integrand<F: Real>(&self) -> Result<(Connection<F>, PointToPoint<F>)> {
        let (p, name) = (&self.problem, |fields: &[&str]| self.spelling.list(fields));
        let connection =
            Connection::<F>::new(vec3::<F>(p.x0), vec3::<F>(p.x2), F::from_f64(p.theta_max))
                .map_err(|e| core_error(&name(&["x0", "x2", "theta_max"]), e))?;
        let medium = Homogeneous::new(F::from_f64(p.sigma_s), F::from_f64(p.sigma_t - p.sigma_s))
            .map_err(|e| core_error(&name(&["sigma_s", "sigma_t"]), e))?;
        let problem = PointToPoint::new(connection, medium, self.normal.map(vec3::<F>))
            .map_err(|e| core_error(&name(&["receiver_normal"]), e))?;
        Ok((connection, problem))
    }

    /// Runs `f` with a sampler for the problem without a lobe, in precision
    /// `F`.
    pub fn with_sampler<F: Real, T>(&self, f: impl FnOnce(&Sampler<'_, F>) -> T) -> Result<T> {
        let name = |fields: &[&str]| self.spelling.list(fields);
        let (connection, problem) = self.integrand::<F>()?;
        let mut storage = TableStorage::<F>::default();
        let phase = self.phase.instantiate::<F>(&mut storage)?;
        let directions = match self.normal {
            Some(n) => Directions::cosine(vec3::<F>(n))
                .map_err(|e| core_error(&name(&["receiver_normal"]), e))?,
            None => Directions::Sphere,
        };
        let setup = Setup::new(
            &phase,
            directions,
            Region::Everywhere,
            F::from_f64(self.problem.sigma_t),
        )
        .map_err(|e| core_error(&name(&["sigma_t"]), e))?;
        let method = self.technique.used.method().unwrap_or(Method::Omnee);
        Ok(f(&Sampler {
            setup,
            connection,
            method,
            problem,
        }))
    }

    /// Runs `f` with the technique and the integrand of the problem with its
    /// lobe at `x0`, in precision `F` (an error without a lobe).
    pub fn with_lobe<F: Real, T>(
        &self,
        f: impl FnOnce(
            &LobeSampler<'_, F>,
            &omnee_core::lobe::LobeToPoint<F, PhaseAt<'_, F>>,
        ) -> Result<T>,
    ) -> Result<T> {
        let spelling = self.spelling;
        let lobe = self
            .lobe
            .as_ref()
            .ok_or_else(|| RenderError::Input(format!("{} is missing", spelling.of("x0_phase"))))?;
        let (connection, point) = self.integrand::<F>()?;
        let (mut s1, mut s0) = (TableStorage::<F>::default(), TableStorage::<F>::default());
        let p1 = self.phase.instantiate::<F>(&mut s1)?;
        let p0 = lobe.phase.instantiate::<F>(&mut s0)?;
        let l = PhaseLobe::new(&p0, vec3::<F>(lobe.incoming))
            .map_err(|e| core_error(&spelling.of("x0_incoming"), e))?;
        let problem = omnee_core::lobe::LobeToPoint::new(point, Some(l))
            .map_err(|e| core_error(&spelling.of("receiver_normal"), e))?;
        let method = self
            .technique
            .used
            .lobe_method()
            .unwrap_or(LobeMethod::LobeMis);
        f(&method.technique(connection, l, &p1), &problem)
    }
}

/// A phase function's lobe at `x0`, borrowing the phase function.
pub type PhaseAt<'p, F> = PhaseLobe<F, &'p Phase<'p, F>>;

/// The technique with a lobe at `x0`.
pub type LobeSampler<'p, F> = LobeTechnique<F, PhaseAt<'p, F>, &'p Phase<'p, F>>;

/// `x1` of a sample in f64.
pub fn x1_f64<F: Real>(s: &Sample<F>) -> [f64; 3] {
    s.x1.to_array().map(|x| x.to_f64())
}

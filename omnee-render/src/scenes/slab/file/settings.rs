//! `[render]`: defaults for `omnee render` that its options override.

use crate::error::{RenderError, Result};
use crate::range::Range;
use crate::section::Section;
use crate::vertices::{DEFAULT_MAX_VERTICES, VertexNumber};
use omnee_core::bridge::MAX_VERTICES;
use omnee_core::method::{Choice, MultipleMethod};
use omnee_core::names::Named;
use omnee_core::term::Term;

/// The transport terms of the slab scene.
pub const SLAB_TERMS: [Term; 4] = [Term::Direct, Term::OnceMore, Term::View, Term::Multiple];

/// The terms rendered when the scene does not list them: all but
/// `multiple`.
pub const SLAB_DEFAULT_TERMS: [Term; 3] = [Term::Direct, Term::OnceMore, Term::View];

/// The techniques of the slab scene's once-more term: the point-to-point
/// methods and `auto` (its light has no lobe).
pub const SLAB_TECHNIQUES: [Choice; 5] = [
    Choice::Omnee,
    Choice::Equiangular,
    Choice::Distance,
    Choice::Mis,
    Choice::Auto,
];

/// Render settings stored in the scene (command-line options override them).
#[derive(Clone, Debug)]
pub struct SlabSettings {
    /// Samples per pixel.
    pub spp: u32,
    /// Random seed.
    pub seed: u64,
    /// Transport terms to evaluate.
    pub terms: Vec<Term>,
    /// Technique for the once-more term.
    pub technique: Choice,
    /// How the multiple term is estimated.
    pub multiple: MultipleMethod,
    /// The multiple term's orders (`vertices` and `max_vertices`).
    pub vertices: VertexNumber,
    /// The once-more integrand's restriction θ < θmax (radians).
    pub theta_max: f64,
    /// Russian roulette threshold as a fraction of the reference radiance.
    pub russian_roulette: f64,
    /// Exposure in stops for the PNG; `None` picks it from the image.
    pub exposure: Option<f64>,
}

impl SlabSettings {
    /// The settings when the scene has no `[render]` section.
    pub fn defaults() -> Self {
        Self {
            spp: 16,
            seed: 1,
            terms: SLAB_DEFAULT_TERMS.to_vec(),
            technique: Choice::Auto,
            multiple: MultipleMethod::Bridge,
            vertices: VertexNumber::Auto {
                max: DEFAULT_MAX_VERTICES,
            },
            theta_max: std::f64::consts::PI,
            russian_roulette: 1e-3,
            exposure: None,
        }
    }

    /// Reads `[render]`, or the defaults when there is none.
    pub(in crate::scenes::slab) fn parse(root: &toml::Table) -> Result<Self> {
        let d = Self::defaults();
        let Some(mut r) = Section::optional(root, "render")? else {
            return Ok(d);
        };
        let settings = SlabSettings {
            spp: r.integer("spp", d.spp as i64, 1, 1 << 24)? as u32,
            seed: r.integer("seed", d.seed as i64, 0, i64::MAX)? as u64,
            terms: r.choices("terms", &d.terms, &SLAB_TERMS, "term")?,
            technique: r.choice("technique", d.technique, &SLAB_TECHNIQUES, "technique")?,
            multiple: r.choice(
                "multiple",
                d.multiple,
                MultipleMethod::ALL,
                "multiple-scattering method",
            )?,
            vertices: vertices(&mut r)?,
            theta_max: r.number("theta_max", Some(d.theta_max), Range::THETA_MAX)?,
            russian_roulette: r.number(
                "russian_roulette",
                Some(d.russian_roulette),
                Range::UNIT,
            )?,
            exposure: match r.get("exposure") {
                None => None,
                Some(toml::Value::String(s)) if s == "auto" => None,
                Some(_) => Some(r.number("exposure", None, Range::EXPOSURE)?),
            },
        };
        r.finish()?;
        Ok(settings)
    }
}

/// `render.vertices` (`"auto"` or an integer in `[2, 32]`, default auto)
/// with `render.max_vertices` (`[2, 32]`, default 8, for auto only).
fn vertices(r: &mut Section<'_>) -> Result<VertexNumber> {
    let max = r.integer(
        "max_vertices",
        DEFAULT_MAX_VERTICES as i64,
        2,
        MAX_VERTICES as i64,
    )?;
    let allowed = format!("\"auto\" or an integer in [2, {MAX_VERTICES}]");
    match r.get("vertices") {
        None => Ok(VertexNumber::Auto { max: max as usize }),
        Some(toml::Value::String(s)) if s == "auto" => Ok(VertexNumber::Auto { max: max as usize }),
        Some(toml::Value::Integer(k)) if (2..=MAX_VERTICES as i64).contains(k) => {
            if r.has("max_vertices") {
                return Err(RenderError::Input(format!(
                    "{} = {max} applies to {} = \"auto\" only; allowed: leave it out",
                    r.field("max_vertices"),
                    r.field("vertices")
                )));
            }
            Ok(VertexNumber::Fixed(*k as usize))
        }
        Some(v) => Err(RenderError::Input(format!(
            "{} = {v} is out of range; allowed: {allowed}",
            r.field("vertices")
        ))),
    }
}

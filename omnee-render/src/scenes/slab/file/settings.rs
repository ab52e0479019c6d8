//! `[render]`: defaults for `omnee render` that its options override.

use crate::error::Result;
use crate::range::Range;
use crate::section::Section;
use omnee_core::method::Choice;
use omnee_core::term::Term;

/// The transport terms of the slab scene, all rendered by default.
pub const SLAB_TERMS: [Term; 3] = [Term::Direct, Term::OnceMore, Term::View];

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
            terms: SLAB_TERMS.to_vec(),
            technique: Choice::Auto,
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

//! How to render a scene, and what the render chose: the settings a caller
//! starts from (the scene's `[render]` and `[camera]` values) and may
//! change, their checks, and the report of the technique used and the work
//! skipped.

use crate::error::{RenderError, Result, Spelling};
use crate::phase::PhaseSampling;
use crate::range::Range;
use crate::render::budget::{MAX_RENDER_SAMPLES, MAX_SECONDS, MAX_SPP, RenderBudget};
use crate::technique::Resolved;
use crate::vertices::VertexNumber;
use omnee_core::method::{Choice, MultipleMethod};
use omnee_core::names::List;
use omnee_core::term::Term;

/// How to render a scene: the scene's `[render]` and `[camera]` values
/// ([`Scene::settings`](super::Scene::settings)), which a caller may
/// change before [`Scene::render`](super::Scene::render) checks them.
#[derive(Clone, Debug, PartialEq)]
pub struct RenderSettings {
    /// Samples (passes) per pixel, or a time budget.
    pub budget: RenderBudget,
    /// Random seed.
    pub seed: u64,
    /// Image width in pixels.
    pub width: u32,
    /// Image height in pixels.
    pub height: u32,
    /// Render only the pixels `[x0, x1) × [y0, y1)` (`None`: all).
    pub crop: Option<[u32; 4]>,
    /// The terms, one layer each (repeats and order do not matter).
    pub terms: Vec<Term>,
    /// The once-more technique.
    pub technique: Choice,
    /// The once-more integrand's restriction θ < θmax (radians, (0, π]).
    pub theta_max: f64,
    /// How the slab scene's `multiple` term is estimated.
    pub multiple: MultipleMethod,
    /// The orders of the `multiple` term: `2 ..= max` (drawn per
    /// connection by bridges) or one fixed `k ≥ 2`.
    pub vertices: VertexNumber,
    /// Russian roulette threshold as a fraction of the scene's reference
    /// radiance (0: off; the slab scene's only).
    pub russian_roulette: f64,
    /// How the slab scene's scattering terms draw deflections.
    pub phase_sampling: PhaseSampling,
    /// PNG exposure in stops (`None`: automatic).
    pub exposure: Option<f64>,
}

impl RenderSettings {
    /// The crop window, checked: inside the image, not empty.
    pub fn window(&self, spelling: Spelling) -> Result<[u32; 4]> {
        let (w, h) = (self.width, self.height);
        for (field, v) in [("width", w), ("height", h)] {
            if !(1..=16384).contains(&v) {
                return Err(RenderError::range(&spelling.of(field), v, "[1, 16384]"));
            }
        }
        let c = self.crop.unwrap_or([0, 0, w, h]);
        if c[0] < c[2] && c[1] < c[3] && c[2] <= w && c[3] <= h {
            Ok(c)
        } else {
            Err(RenderError::range(
                &spelling.of("crop"),
                format!("{},{},{},{}", c[0], c[1], c[2], c[3]),
                format!("X0 < X1 <= {w}, Y0 < Y1 <= {h}"),
            ))
        }
    }

    /// Checks every number against its range, naming it by `spelling`,
    /// and the terms and the technique against the scene's (`kind`, its
    /// `terms` and `techniques`).
    pub(crate) fn check(
        &self,
        spelling: Spelling,
        kind: &str,
        terms: &[Term],
        techniques: &[Choice],
    ) -> Result<()> {
        let window = self.window(spelling)?;
        match self.budget {
            RenderBudget::Spp(n) => {
                // At most 2²⁴ passes and 2⁴⁰ samples over the window.
                let pixels = u64::from(window[2] - window[0]) * u64::from(window[3] - window[1]);
                let most = (MAX_RENDER_SAMPLES / pixels.max(1)).clamp(1, u64::from(MAX_SPP));
                if !(1..=most).contains(&u64::from(n)) {
                    return Err(RenderError::range(
                        &spelling.of("spp"),
                        n,
                        format!(
                            "[1, {most}] (at most 2^24 passes and 2^40 samples: {pixels} pixels \
                             rendered)"
                        ),
                    ));
                }
            }
            RenderBudget::Seconds(t) => {
                Range::open_closed(0.0, MAX_SECONDS).check(&spelling.of("time"), t)?;
            }
        }
        Range::THETA_MAX.check(&spelling.of("theta_max"), self.theta_max)?;
        self.vertices.check(spelling, 2)?;
        Range::UNIT.check(&spelling.of("russian_roulette"), self.russian_roulette)?;
        if let Some(e) = self.exposure {
            Range::EXPOSURE.check(&spelling.of("exposure"), e)?;
        }
        let refuse = |field: &str, value: &dyn std::fmt::Display, noun: &str, allowed: String| {
            Err(RenderError::Input(format!(
                "{} = {value} is not a {noun} of the {kind} scene; allowed: {allowed}",
                spelling.of(field)
            )))
        };
        if self.terms.is_empty() {
            return Err(RenderError::Input(format!(
                "{} is empty; allowed: one or more of {}",
                spelling.of("terms"),
                List(terms)
            )));
        }
        if let Some(t) = self.terms.iter().find(|t| !terms.contains(t)) {
            return refuse("terms", t, "term", List(terms).to_string());
        }
        if !techniques.contains(&self.technique) {
            return refuse(
                "technique",
                &self.technique,
                "technique",
                List(techniques).to_string(),
            );
        }
        Ok(())
    }
}

/// What a render chose and skipped, for its report.
#[derive(Clone, Debug, PartialEq)]
pub struct RenderReport {
    /// The once-more technique as asked for and as used.
    pub technique: Resolved,
    /// Whether the scattering terms drew deflections from a table.
    pub tabulated: bool,
    /// What the scene does not need and was skipped, as sentences.
    pub skipped: Vec<String>,
    /// Whether the once-more term was rendered (the technique matters).
    pub once_more: bool,
}

//! The JavaScript interface: thin wrappers over [`crate::demo`] that turn every
//! invalid input into a thrown `Error` (never a trap).

use crate::demo::{self, Problem};
use wasm_bindgen::prelude::*;

#[wasm_bindgen(inline_js = "
export function error(a, b, value, c, d) {
  return new Error(a + b + (value === undefined ? '' : String(value)) + c + d);
}
export function estimate(count, mean, stdError, reference) {
  const relativeError = reference > 0 ? Math.abs(mean - reference) / reference : NaN;
  return { count, mean, stdError, relativeError };
}
export function f32s(a) { return a.slice(); }
export function f64s(a) { return a.slice(); }
export function triangle(x1x, x1y, theta, alpha, beta, xi, t, s, d1, d2, radius, cx, cy) {
  return { x1x, x1y, theta, alpha, beta, xi, t, s, d1, d2, radius, cx, cy };
}")]
extern "C" {
    /// `new Error(a + b + String(value) + c + d)` (no number for `None`):
    /// JavaScript formats the number and joins the message, which keeps
    /// Rust's float formatting and string building out of the module.
    fn error(a: &str, b: &str, value: Option<f64>, c: &str, d: &str) -> JsValue;

    /// A copy of `a` as a `Float32Array` (the module's memory only viewed).
    fn f32s(a: &[f32]) -> JsValue;

    /// A copy of `a` as a `Float64Array`.
    fn f64s(a: &[f64]) -> JsValue;

    /// An `Estimate` object (see `RESULTS`), with the relative error
    /// `|mean − reference| / reference` (NaN unless `reference > 0`).
    fn estimate(count: f64, mean: f64, std_error: f64, reference: f64) -> JsValue;

    /// A `Waterlevel` object (see `RESULTS`).
    #[allow(clippy::too_many_arguments)]
    fn triangle(
        x1x: f64,
        x1y: f64,
        theta: f64,
        alpha: f64,
        beta: f64,
        xi: f64,
        t: f64,
        s: f64,
        d1: f64,
        d2: f64,
        radius: f64,
        cx: f64,
        cy: f64,
    ) -> JsValue;
}

// The results with several numbers are plain JavaScript objects made by the
// functions above, not wasm-bindgen classes: a class exports a getter and a
// destructor per field from the module (1.5 KiB for these two). Arrays are
// copied into typed arrays by `f32s`/`f64s` rather than returned as a `Vec`,
// which wasm-bindgen hands over as a boxed slice (shrinking the allocation).
#[wasm_bindgen(typescript_custom_section)]
const RESULTS: &str = r#"
/** A running Monte Carlo estimate of the integral (`Demo.estimate`). */
export interface Estimate {
  /** Number of samples so far. */
  readonly count: number;
  /** The mean of the one-sample estimates. */
  readonly mean: number;
  /** Its standard error. */
  readonly stdError: number;
  /** `|mean − reference| / reference` (NaN for a zero reference). */
  readonly relativeError: number;
}

/** The talk's "waterlevel" triangle x0, x1, x2 (`waterlevel`). */
export interface Waterlevel {
  /** The vertex x1. */
  readonly x1x: number;
  readonly x1y: number;
  /** The deflection θ = α + β at x1. */
  readonly theta: number;
  /** The angle α at x0. */
  readonly alpha: number;
  /** The angle β at x2. */
  readonly beta: number;
  /** β/θ, the talk's ξ. */
  readonly xi: number;
  /** The talk's fractional distance t = sin β cos(θ − β) / sin θ. */
  readonly t: number;
  /** s = |x2 − x0|. */
  readonly s: number;
  /** d1 = |x1 − x0|. */
  readonly d1: number;
  /** d2 = |x2 − x1|. */
  readonly d2: number;
  /** The circumradius s / (2 sin θ). */
  readonly radius: number;
  /** The circumcircle's centre. */
  readonly cx: number;
  readonly cy: number;
}
"#;

/// The core's error as a JavaScript `Error` with the message of its `Display`
/// (`g = 1.5 is out of range; allowed: (-1, 1)`), the number formatted by
/// JavaScript (`Infinity` where Rust writes `inf`).
fn js(e: omnee_core::Error) -> JsValue {
    use omnee_core::Error::*;
    match e {
        OutOfRange {
            field,
            value,
            allowed,
        } => error(
            field,
            " = ",
            Some(value),
            " is out of range; allowed: ",
            allowed,
        ),
        NotFinite { field, reason } => error(field, " ", None, reason, ""),
        Degenerate { field, reason } | Arrays { field, reason } => {
            error(field, ": ", None, reason, "")
        }
        Table { field, reason } => error("table ", field, None, ": ", reason),
        Syntax { field, reason } => error("syntax error in ", field, None, ": ", reason),
        NotConverged { field, evaluations } => error(
            field,
            ": the quadrature did not converge within its budget of ",
            Some(evaluations as f64),
            " evaluations",
            "",
        ),
    }
}

pub use technique::Technique;

/// The string enum on its own: wasm-bindgen adds an undocumented variant
/// for strings that are none of the names, and an undocumented
/// `from_js_value`, which only this module excuses from `missing_docs`.
#[allow(missing_docs)]
mod technique {
    use crate::demo;
    use wasm_bindgen::prelude::*;

    /// A technique the demo runs, by name ([`demo::Technique::name`]): in
    /// JavaScript the strings `"omnee"`, `"equiangular"`, `"mis"`, `"lobe"`
    /// and `"lobe-mis"` (TypeScript: `type Technique = "omnee" |
    /// "equiangular" | "mis" | "lobe" | "lobe-mis"`; the last two with a
    /// lobe at `x0` only). Any other string is refused with an `Error` that
    /// lists these.
    #[wasm_bindgen]
    #[derive(Clone, Copy, Debug, PartialEq, Eq)]
    pub enum Technique {
        /// [`demo::Technique::Omnee`].
        Omnee = "omnee",
        /// [`demo::Technique::Equiangular`].
        Equiangular = "equiangular",
        /// [`demo::Technique::Mis`].
        Mis = "mis",
        /// [`demo::Technique::Lobe`].
        Lobe = "lobe",
        /// [`demo::Technique::LobeMis`].
        LobeMis = "lobe-mis",
    }

    impl Technique {
        /// The demo's technique of this name (an unknown string from
        /// JavaScript is an error listing the allowed names).
        pub fn technique(self) -> Result<demo::Technique, omnee_core::Error> {
            // The enum's variants in the order of `demo::TECHNIQUES`, then
            // wasm-bindgen's variant for any other string.
            demo::TECHNIQUES
                .get(self as usize)
                .copied()
                .ok_or(omnee_core::Error::Syntax {
                    field: "technique",
                    reason: "unknown name; allowed: omnee, equiangular, mis, lobe, lobe-mis",
                })
        }
    }
}

/// The point-to-point integral in the demo plane, optionally with a lobe at
/// `x0`, and its running estimates by OMNEE, equiangular sampling and MIS of
/// both, and with a lobe also by the lobe technique and the recommended
/// combination of it with OMNEE ([`Technique`]).
#[wasm_bindgen]
pub struct Demo {
    inner: Problem,
}

#[wasm_bindgen]
impl Demo {
    /// The problem for the phase function `phase` (a spec string such as
    /// `"hg:0.9"`) between the unit point light `x0 = (x0x, x0y)` and the
    /// point receiver `x2 = (x2x, x2y)` in an infinite medium with
    /// coefficients `sigmaS`, `sigmaA`, restricted to θ < `thetaMax` ∈ (0, π].
    /// With `tilt` (radians in [0, π]; `undefined`: no lobe) a lobe at
    /// `x0`: the same phase function for light arriving along the axis
    /// `x0 → x2` turned by `tilt` in the plane. Computes the quadrature
    /// reference without a lobe (with one, see `reference`). Throws on
    /// invalid input.
    #[wasm_bindgen(constructor)]
    #[allow(clippy::too_many_arguments)]
    pub fn new(
        phase: &str,
        x0x: f64,
        x0y: f64,
        x2x: f64,
        x2y: f64,
        #[wasm_bindgen(js_name = sigmaS)] sigma_s: f64,
        #[wasm_bindgen(js_name = sigmaA)] sigma_a: f64,
        #[wasm_bindgen(js_name = thetaMax)] theta_max: f64,
        seed: f64,
        tilt: Option<f64>,
    ) -> Result<Demo, JsValue> {
        Problem::new(
            phase,
            [x0x, x0y],
            [x2x, x2y],
            sigma_s,
            sigma_a,
            theta_max,
            tilt,
            seed,
        )
        .map(|inner| Demo { inner })
        .map_err(js)
    }

    /// The quadrature reference value of the integral; NaN with a lobe at
    /// `x0`, whose three-dimensional quadrature takes seconds natively and
    /// is not in the module (the page reads it from
    /// `lobe-references.js`, computed natively, where it has one).
    #[wasm_bindgen(getter)]
    pub fn reference(&self) -> f64 {
        self.inner.reference()
    }

    /// With a lobe at `x0`, the probability with which `"lobe-mis"` draws
    /// the lobe technique (0: OMNEE alone); NaN without a lobe.
    #[wasm_bindgen(getter, js_name = lobeProbability)]
    pub fn lobe_probability(&self) -> f64 {
        self.inner.lobe_probability().unwrap_or(f64::NAN)
    }

    /// Draws `n` (an integer in 1 ..= 2²⁴) more samples with each technique
    /// and updates the running estimates.
    pub fn run(&mut self, n: f64) -> Result<(), JsValue> {
        self.inner.run(n).map_err(js)
    }

    /// The running estimate of `technique` (`"omnee"`, `"equiangular"`,
    /// `"mis"`, and with a lobe at `x0` `"lobe"`, `"lobe-mis"`), an
    /// `Estimate` object (`count`, `mean`, `stdError`, `relativeError`; the
    /// last NaN with a lobe, whose reference the module does not compute).
    #[wasm_bindgen(unchecked_return_type = "Estimate")]
    pub fn estimate(&self, technique: Technique) -> Result<JsValue, JsValue> {
        let stats = technique
            .technique()
            .and_then(|t| self.inner.stats(t))
            .map_err(js)?;
        Ok(estimate(
            stats.count() as f64,
            stats.mean(),
            stats.std_error(),
            self.inner.reference(),
        ))
    }

    /// `n` (an integer in 1 ..= 2²⁰) samples of `technique` drawn from
    /// generator `seed` (an integer in 0 ..= 2³² − 1), rotated into the plane
    /// about the axis: `[x, y, estimate, …]`.
    #[wasm_bindgen(unchecked_return_type = "Float32Array")]
    pub fn cloud(&self, technique: Technique, n: f64, seed: f64) -> Result<JsValue, JsValue> {
        let technique = technique.technique().map_err(js)?;
        Ok(f32s(&self.inner.cloud(technique, n, seed).map_err(js)?))
    }

    /// Forgets the estimates and restarts the generators from the seed.
    pub fn reset(&mut self) {
        self.inner.reset();
    }
}

/// The triangle with `x1` on the arc of constant `theta` ∈ (0, π) at
/// `β/θ = xi` ∈ [0, 1], on the left of the axis from `x0` to `x2`: a
/// `Waterlevel` object (`x1x`, `x1y`, `theta`, `alpha`, `beta`, `xi`, `t`,
/// `s`, `d1`, `d2`, `radius`, `cx`, `cy`: the fields of `demo::Waterlevel`).
#[wasm_bindgen(unchecked_return_type = "Waterlevel")]
pub fn waterlevel(
    x0x: f64,
    x0y: f64,
    x2x: f64,
    x2y: f64,
    theta: f64,
    xi: f64,
) -> Result<JsValue, JsValue> {
    let w = demo::waterlevel([x0x, x0y], [x2x, x2y], theta, xi).map_err(js)?;
    Ok(triangle(
        w.x1[0],
        w.x1[1],
        w.theta,
        w.alpha,
        w.beta,
        w.xi,
        w.t,
        w.s,
        w.d1,
        w.d2,
        w.radius,
        w.centre[0],
        w.centre[1],
    ))
}

/// The arc of constant `theta` through `x0` and `x2` on both sides of the
/// axis: `segments + 1` points per side (`segments` an integer in
/// 1 ..= 4096), `[x, y, …]`.
#[wasm_bindgen(unchecked_return_type = "Float64Array")]
pub fn arc(
    x0x: f64,
    x0y: f64,
    x2x: f64,
    x2y: f64,
    theta: f64,
    segments: f64,
) -> Result<JsValue, JsValue> {
    Ok(f64s(
        &demo::arc([x0x, x0y], [x2x, x2y], theta, segments).map_err(js)?,
    ))
}

/// A histogram of `n` (an integer in 1 ..= 2²⁴) deflections sampled from
/// generator `seed` over `bins` (an integer in 1 ..= 4096) bins of
/// `[0, thetaHi]`: `bins` sampled densities, then `bins` exact ones.
#[wasm_bindgen(unchecked_return_type = "Float64Array")]
pub fn histogram(
    phase: &str,
    n: f64,
    bins: f64,
    #[wasm_bindgen(js_name = thetaHi)] theta_hi: f64,
    seed: f64,
) -> Result<JsValue, JsValue> {
    Ok(f64s(
        &demo::histogram(phase, n, bins, theta_hi, seed).map_err(js)?,
    ))
}

/// The deflection θ below which a fraction `u` of the scattering goes.
#[wasm_bindgen]
pub fn quantile(phase: &str, u: f64) -> Result<f64, JsValue> {
    demo::quantile(phase, u).map_err(js)
}

/// The mean cosine of the phase function `phase`.
#[wasm_bindgen(js_name = meanCosine)]
pub fn mean_cosine(phase: &str) -> Result<f64, JsValue> {
    demo::mean_cosine(phase).map_err(js)
}

/// The crate version, for the page footer.
#[wasm_bindgen(unchecked_return_type = "string")]
pub fn version() -> JsValue {
    JsValue::from_str(env!("CARGO_PKG_VERSION"))
}

//! `omnee_phase_*`: phase functions from parameters, spec strings or
//! caller-owned tables, and their evaluation; `omnee_deflection_*`: angles in
//! cancellation-free form.
//!
//! The file is long by the ABI's shape: every constructor and evaluation
//! exists as a documented `extern "C"` function in f32 and in f64 (the
//! header carries their doc comments), each a few lines over one generic body.

use crate::args::{finite, object, required};
use crate::boundary::{c_str, slice, slice_mut};
use crate::status::{ErrorOut, Failure, finish, omnee_error, omnee_status};
use crate::types::{
    Object, Precision, omnee_deflection, omnee_phase_f32, omnee_phase_f64, omnee_span, omnee_vec3,
};
use core::ffi::c_char;
use core::mem::MaybeUninit;
use omnee_core::Error;
use omnee_core::phase::{
    Deflection, Draine, FournierForand, HenyeyGreenstein, Isotropic, Mie, Mixture, Phase,
    PhaseFunction, Rayleigh, Spec, Tabulated,
};
use omnee_core::real::Real;
use omnee_core::sampling::unit_normal;

/// The phase-function output parameter.
type PhaseOut<'a, F> = Option<&'a mut MaybeUninit<<F as Precision>::Phase>>;

/// Stores a constructor's result.
fn make<F: Precision>(
    out: PhaseOut<'_, F>,
    error: ErrorOut<'_>,
    phase: Result<Phase<'static, F>, Error>,
) -> omnee_status {
    let result = phase.map(|p| Some(F::Phase::new(p))).map_err(Failure::from);
    finish(out, "phase", error, result)
}

/// Isotropic scattering, p = 1/(4π).
#[unsafe(no_mangle)]
pub extern "C" fn omnee_phase_iso_f32(
    phase: Option<&mut MaybeUninit<omnee_phase_f32>>,
    error: Option<&mut MaybeUninit<omnee_error>>,
) -> omnee_status {
    make::<f32>(phase, error, Ok(Phase::Isotropic(Isotropic)))
}

/// `omnee_phase_iso_f32` in double precision.
#[unsafe(no_mangle)]
pub extern "C" fn omnee_phase_iso_f64(
    phase: Option<&mut MaybeUninit<omnee_phase_f64>>,
    error: Option<&mut MaybeUninit<omnee_error>>,
) -> omnee_status {
    make::<f64>(phase, error, Ok(Phase::Isotropic(Isotropic)))
}

/// Henyey–Greenstein, p = (1 − g²)/(4π (1 + g² − 2g cos θ)^{3/2}),
/// g ∈ (−1, 1) (`hg:G`).
#[unsafe(no_mangle)]
pub extern "C" fn omnee_phase_hg_f32(
    phase: Option<&mut MaybeUninit<omnee_phase_f32>>,
    g: f32,
    error: Option<&mut MaybeUninit<omnee_error>>,
) -> omnee_status {
    make::<f32>(
        phase,
        error,
        HenyeyGreenstein::new(g).map(Phase::HenyeyGreenstein),
    )
}

/// `omnee_phase_hg_f32` in double precision.
#[unsafe(no_mangle)]
pub extern "C" fn omnee_phase_hg_f64(
    phase: Option<&mut MaybeUninit<omnee_phase_f64>>,
    g: f64,
    error: Option<&mut MaybeUninit<omnee_error>>,
) -> omnee_status {
    make::<f64>(
        phase,
        error,
        HenyeyGreenstein::new(g).map(Phase::HenyeyGreenstein),
    )
}

/// Two-term Henyey–Greenstein, w·HG(g1) + (1 − w)·HG(g2), g1, g2 ∈ (−1, 1),
/// w ∈ [0, 1] (`tthg:G1,G2,W`).
#[unsafe(no_mangle)]
pub extern "C" fn omnee_phase_tthg_f32(
    phase: Option<&mut MaybeUninit<omnee_phase_f32>>,
    g1: f32,
    g2: f32,
    w: f32,
    error: Option<&mut MaybeUninit<omnee_error>>,
) -> omnee_status {
    make::<f32>(
        phase,
        error,
        Mixture::two_term(g1, g2, w).map(Phase::TwoTermHg),
    )
}

/// `omnee_phase_tthg_f32` in double precision.
#[unsafe(no_mangle)]
pub extern "C" fn omnee_phase_tthg_f64(
    phase: Option<&mut MaybeUninit<omnee_phase_f64>>,
    g1: f64,
    g2: f64,
    w: f64,
    error: Option<&mut MaybeUninit<omnee_error>>,
) -> omnee_status {
    make::<f64>(
        phase,
        error,
        Mixture::two_term(g1, g2, w).map(Phase::TwoTermHg),
    )
}

/// Fournier–Forand with backscatter fraction ∈ (0, 0.5) and refractive
/// index n ∈ [1.001, 1.5] (`ff:B,N`).
#[unsafe(no_mangle)]
pub extern "C" fn omnee_phase_ff_f32(
    phase: Option<&mut MaybeUninit<omnee_phase_f32>>,
    backscatter: f32,
    n: f32,
    error: Option<&mut MaybeUninit<omnee_error>>,
) -> omnee_status {
    let p = FournierForand::new(backscatter, n).map(Phase::FournierForand);
    make::<f32>(phase, error, p)
}

/// `omnee_phase_ff_f32` in double precision.
#[unsafe(no_mangle)]
pub extern "C" fn omnee_phase_ff_f64(
    phase: Option<&mut MaybeUninit<omnee_phase_f64>>,
    backscatter: f64,
    n: f64,
    error: Option<&mut MaybeUninit<omnee_error>>,
) -> omnee_status {
    let p = FournierForand::new(backscatter, n).map(Phase::FournierForand);
    make::<f64>(phase, error, p)
}

/// Draine: HG times (1 + α cos²θ), normalised, g ∈ (−1, 1),
/// alpha ∈ [0, 1000] (`draine:G,ALPHA`).
#[unsafe(no_mangle)]
pub extern "C" fn omnee_phase_draine_f32(
    phase: Option<&mut MaybeUninit<omnee_phase_f32>>,
    g: f32,
    alpha: f32,
    error: Option<&mut MaybeUninit<omnee_error>>,
) -> omnee_status {
    make::<f32>(phase, error, Draine::new(g, alpha).map(Phase::Draine))
}

/// `omnee_phase_draine_f32` in double precision.
#[unsafe(no_mangle)]
pub extern "C" fn omnee_phase_draine_f64(
    phase: Option<&mut MaybeUninit<omnee_phase_f64>>,
    g: f64,
    alpha: f64,
    error: Option<&mut MaybeUninit<omnee_error>>,
) -> omnee_status {
    make::<f64>(phase, error, Draine::new(g, alpha).map(Phase::Draine))
}

/// Approximate Mie for water droplets of diameter_um ∈ (0, 50] micrometres
/// (`mie:DIAMETER_UM`).
#[unsafe(no_mangle)]
pub extern "C" fn omnee_phase_mie_f32(
    phase: Option<&mut MaybeUninit<omnee_phase_f32>>,
    diameter_um: f32,
    error: Option<&mut MaybeUninit<omnee_error>>,
) -> omnee_status {
    make::<f32>(phase, error, Mie::new(diameter_um).map(Phase::Mie))
}

/// `omnee_phase_mie_f32` in double precision.
#[unsafe(no_mangle)]
pub extern "C" fn omnee_phase_mie_f64(
    phase: Option<&mut MaybeUninit<omnee_phase_f64>>,
    diameter_um: f64,
    error: Option<&mut MaybeUninit<omnee_error>>,
) -> omnee_status {
    make::<f64>(phase, error, Mie::new(diameter_um).map(Phase::Mie))
}

/// Rayleigh, p = 3/(16π) (1 + cos²θ) (`rayleigh`).
#[unsafe(no_mangle)]
pub extern "C" fn omnee_phase_rayleigh_f32(
    phase: Option<&mut MaybeUninit<omnee_phase_f32>>,
    error: Option<&mut MaybeUninit<omnee_error>>,
) -> omnee_status {
    make::<f32>(phase, error, Ok(Phase::Rayleigh(Rayleigh)))
}

/// `omnee_phase_rayleigh_f32` in double precision.
#[unsafe(no_mangle)]
pub extern "C" fn omnee_phase_rayleigh_f64(
    phase: Option<&mut MaybeUninit<omnee_phase_f64>>,
    error: Option<&mut MaybeUninit<omnee_error>>,
) -> omnee_status {
    make::<f64>(phase, error, Ok(Phase::Rayleigh(Rayleigh)))
}

/// A tabulated phase function over n ≥ 1 bins: `theta` holds the n + 1 bin
/// edges (0 = θ_0 < … < θ_n = π), `values` the n unnormalised values
/// (finite, ≥ 0, not all 0; constant per solid angle in each bin), and `cdf`
/// receives the n + 1 entries of the cumulative distribution.
///
/// The phase function refers to the three arrays: they must outlive it (and
/// its copies) and stay unmodified. Lengths that disagree, misplaced edges,
/// values all 0 or overlapping arrays: `OMNEE_ERROR_TABLE`. A NaN or
/// infinite edge or value, or finite values whose sum weighted by their
/// bins' solid angles is not finite in double precision (values near
/// `DBL_MAX`): `OMNEE_ERROR_NOT_FINITE`, field "theta" or "values". A
/// negative value: `OMNEE_ERROR_OUT_OF_RANGE`, field "values", with that
/// value.
///
/// # Safety
/// Each array pointer is NULL (allowed with length 0) or points to as many
/// elements as its length says.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn omnee_phase_table_f32(
    phase: Option<&mut MaybeUninit<omnee_phase_f32>>,
    theta: *const f32,
    theta_len: usize,
    values: *const f32,
    values_len: usize,
    cdf: *mut f32,
    cdf_len: usize,
    error: Option<&mut MaybeUninit<omnee_error>>,
) -> omnee_status {
    // SAFETY: the arrays are as long as their lengths and outlive the phase
    // function (this function's contract); `table` checks that `cdf`, the
    // only one written, overlaps neither of the others before it borrows.
    unsafe {
        table::<f32>(
            phase,
            (theta, theta_len),
            (values, values_len),
            (cdf, cdf_len),
            error,
        )
    }
}

/// `omnee_phase_table_f32` in double precision.
///
/// # Safety
/// As `omnee_phase_table_f32`.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn omnee_phase_table_f64(
    phase: Option<&mut MaybeUninit<omnee_phase_f64>>,
    theta: *const f64,
    theta_len: usize,
    values: *const f64,
    values_len: usize,
    cdf: *mut f64,
    cdf_len: usize,
    error: Option<&mut MaybeUninit<omnee_error>>,
) -> omnee_status {
    // SAFETY: forwarded contract (see omnee_phase_table_f32).
    unsafe {
        table::<f64>(
            phase,
            (theta, theta_len),
            (values, values_len),
            (cdf, cdf_len),
            error,
        )
    }
}

/// # Safety
/// Each `(pointer, length)` is NULL with length 0 or `length` elements that
/// live for the rest of the program's use of the phase function.
unsafe fn table<F: Precision>(
    out: PhaseOut<'_, F>,
    theta: (*const F, usize),
    values: (*const F, usize),
    cdf: (*mut F, usize),
    error: ErrorOut<'_>,
) -> omnee_status {
    let table_error = |field, reason| Failure::Core(Error::Table { field, reason });
    let result = (|| {
        if crate::boundary::overlap(cdf.0, cdf.1, theta.0, theta.1)
            || crate::boundary::overlap(cdf.0, cdf.1, values.0, values.1)
        {
            return Err(table_error("cdf", "overlaps theta or values"));
        }
        // SAFETY: the caller's contract; `cdf` is disjoint from both (above).
        let theta = unsafe { slice(theta.0, theta.1) }.ok_or(Failure::Null("theta"))?;
        // SAFETY: as above.
        let values = unsafe { slice(values.0, values.1) }.ok_or(Failure::Null("values"))?;
        // SAFETY: as above; only this slice writes `cdf`, then shares it.
        let cdf = unsafe { slice_mut(cdf.0, cdf.1) }.ok_or(Failure::Null("cdf"))?;
        let table = Tabulated::new(theta, values, cdf)?;
        Ok(Some(F::Phase::new(Phase::Tabulated(table))))
    })();
    finish(out, "phase", error, result)
}

/// A phase function (docs/math.md §7) from its spec string (NUL-terminated; surrounding
/// whitespace ignored): `iso`, `hg:G`, `tthg:G1,G2,W`, `ff:B,N`,
/// `draine:G,ALPHA`, `mie:DIAMETER_UM`, `rayleigh`, or `table:PATH`.
///
/// For `table:PATH` the library, which does no I/O, returns
/// `OMNEE_TABLE_SPEC` and, if `table_path` is not NULL, where PATH lies in
/// `spec` (the phase function is not written); the caller reads the file and
/// calls `omnee_phase_table_f32`. On every other outcome `*table_path` (if
/// not NULL) is zeroed, `{0, 0}`.
/// Errors: `OMNEE_ERROR_SYNTAX` (unknown name, wrong parameter count, not a
/// number, not UTF-8), `OMNEE_ERROR_OUT_OF_RANGE` (a parameter).
///
/// # Safety
/// `spec` is NULL or a NUL-terminated string.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn omnee_phase_parse_f32(
    phase: Option<&mut MaybeUninit<omnee_phase_f32>>,
    spec: *const c_char,
    table_path: Option<&mut MaybeUninit<omnee_span>>,
    error: Option<&mut MaybeUninit<omnee_error>>,
) -> omnee_status {
    // SAFETY: spec is NULL or NUL-terminated (this function's contract).
    parse::<f32>(phase, unsafe { c_str(spec) }, table_path, error)
}

/// `omnee_phase_parse_f32` in double precision.
///
/// # Safety
/// As `omnee_phase_parse_f32`.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn omnee_phase_parse_f64(
    phase: Option<&mut MaybeUninit<omnee_phase_f64>>,
    spec: *const c_char,
    table_path: Option<&mut MaybeUninit<omnee_span>>,
    error: Option<&mut MaybeUninit<omnee_error>>,
) -> omnee_status {
    // SAFETY: spec is NULL or NUL-terminated (this function's contract).
    parse::<f64>(phase, unsafe { c_str(spec) }, table_path, error)
}

fn parse<F: Precision>(
    out: PhaseOut<'_, F>,
    spec: Option<&core::ffi::CStr>,
    table_path: Option<&mut MaybeUninit<omnee_span>>,
    error: ErrorOut<'_>,
) -> omnee_status {
    let parsed = (|| {
        let text = spec.ok_or(Failure::Null("spec"))?.to_str().map_err(|_| {
            Failure::Core(Error::Syntax {
                field: "spec",
                reason: "not valid UTF-8",
            })
        })?;
        Ok((text, Spec::<F>::parse(text)?))
    })();
    let span = match parsed {
        Ok((text, Spec::Table { path })) => omnee_span {
            offset: path.as_ptr() as usize - text.as_ptr() as usize,
            length: path.len(),
        },
        _ => omnee_span::default(),
    };
    if let Some(out) = table_path {
        out.write(span);
    }
    match parsed {
        Ok((_, Spec::Table { .. })) => omnee_status::OMNEE_TABLE_SPEC,
        Ok((_, Spec::Analytic(phase))) => {
            finish(out, "phase", error, Ok(Some(F::Phase::new(phase))))
        }
        Err(failure) => finish(out, "phase", error, Err(failure)),
    }
}

/// A deflection (docs/math.md §4) from θ ∈ [0, π] (clamped; NaN and ±∞ are errors): 1 ∓ cos θ from
/// 2 sin²(θ/2) and 2 cos²(θ/2), accurate at both ends.
#[unsafe(no_mangle)]
pub extern "C" fn omnee_deflection_from_theta_f32(
    theta: f32,
    deflection: Option<&mut MaybeUninit<omnee_deflection<f32>>>,
    error: Option<&mut MaybeUninit<omnee_error>>,
) -> omnee_status {
    from_theta(theta, deflection, error)
}

/// `omnee_deflection_from_theta_f32` in double precision.
#[unsafe(no_mangle)]
pub extern "C" fn omnee_deflection_from_theta_f64(
    theta: f64,
    deflection: Option<&mut MaybeUninit<omnee_deflection<f64>>>,
    error: Option<&mut MaybeUninit<omnee_error>>,
) -> omnee_status {
    from_theta(theta, deflection, error)
}

fn from_theta<F: Real>(
    theta: F,
    out: Option<&mut MaybeUninit<omnee_deflection<F>>>,
    error: ErrorOut<'_>,
) -> omnee_status {
    let result = (|| {
        if !theta.is_finite() {
            return Err(Error::OutOfRange {
                field: "theta",
                value: theta.to_f64(),
                allowed: "[0, pi]",
            }
            .into());
        }
        Ok(Some(omnee_deflection::from_core(Deflection::from_theta(
            theta,
        ))))
    })();
    finish(out, "deflection", error, result)
}

/// A deflection from cos θ ∈ [−1, 1] (clamped; NaN and ±∞ are errors). Loses the
/// digits of 1 ∓ cos θ near θ = 0 and π: prefer `omnee_deflection_between_*`
/// when the directions are at hand.
#[unsafe(no_mangle)]
pub extern "C" fn omnee_deflection_from_cos_f32(
    cos_theta: f32,
    deflection: Option<&mut MaybeUninit<omnee_deflection<f32>>>,
    error: Option<&mut MaybeUninit<omnee_error>>,
) -> omnee_status {
    from_cos(cos_theta, deflection, error)
}

/// `omnee_deflection_from_cos_f32` in double precision.
#[unsafe(no_mangle)]
pub extern "C" fn omnee_deflection_from_cos_f64(
    cos_theta: f64,
    deflection: Option<&mut MaybeUninit<omnee_deflection<f64>>>,
    error: Option<&mut MaybeUninit<omnee_error>>,
) -> omnee_status {
    from_cos(cos_theta, deflection, error)
}

fn from_cos<F: Real>(
    cos_theta: F,
    out: Option<&mut MaybeUninit<omnee_deflection<F>>>,
    error: ErrorOut<'_>,
) -> omnee_status {
    let result = (|| {
        if !cos_theta.is_finite() {
            return Err(Error::OutOfRange {
                field: "cos_theta",
                value: cos_theta.to_f64(),
                allowed: "[-1, 1]",
            }
            .into());
        }
        Ok(Some(omnee_deflection::from_core(Deflection::from_cos(
            cos_theta,
        ))))
    })();
    finish(out, "deflection", error, result)
}

/// The deflection between two propagation directions ω1 (into the vertex)
/// and ω2 (out of it), cos θ = ω1·ω2, from |ω1 − ω2| and |ω1 + ω2| (exact
/// where 1 − ω1·ω2 is not). The directions are normalised here: any finite,
/// non-zero length. Errors: `OMNEE_ERROR_NOT_FINITE` for a NaN or infinite
/// component, `OMNEE_ERROR_DEGENERATE` for a zero direction (each naming
/// "omega1" or "omega2").
#[unsafe(no_mangle)]
pub extern "C" fn omnee_deflection_between_f32(
    omega1: omnee_vec3<f32>,
    omega2: omnee_vec3<f32>,
    deflection: Option<&mut MaybeUninit<omnee_deflection<f32>>>,
    error: Option<&mut MaybeUninit<omnee_error>>,
) -> omnee_status {
    between(omega1, omega2, deflection, error)
}

/// `omnee_deflection_between_f32` in double precision.
#[unsafe(no_mangle)]
pub extern "C" fn omnee_deflection_between_f64(
    omega1: omnee_vec3<f64>,
    omega2: omnee_vec3<f64>,
    deflection: Option<&mut MaybeUninit<omnee_deflection<f64>>>,
    error: Option<&mut MaybeUninit<omnee_error>>,
) -> omnee_status {
    between(omega1, omega2, deflection, error)
}

fn between<F: Real>(
    omega1: omnee_vec3<F>,
    omega2: omnee_vec3<F>,
    out: Option<&mut MaybeUninit<omnee_deflection<F>>>,
    error: ErrorOut<'_>,
) -> omnee_status {
    let result = (|| {
        let w1 = unit_normal::<F>(omega1.get(), "omega1")?;
        let w2 = unit_normal::<F>(omega2.get(), "omega2")?;
        let d = Deflection::between(w1, w2);
        Ok(Some(omnee_deflection::from_core(d)))
    })();
    finish(out, "deflection", error, result)
}

/// A deflection given by the caller, checked: finite, θ ∈ [0, π] and
/// 1 ∓ cos θ ∈ [0, 2].
fn deflection<F: Real>(d: Option<&omnee_deflection<F>>) -> Result<Deflection<F>, Failure> {
    let d = required(d, "deflection")?;
    let pi = F::PI.to_f64().max(core::f64::consts::PI);
    let check = |field, value: F, hi: f64, allowed| {
        let v = value.to_f64();
        if v >= 0.0 && v <= hi {
            Ok(())
        } else {
            Err(Failure::Core(Error::OutOfRange {
                field,
                value: v,
                allowed,
            }))
        }
    };
    check("theta", d.theta, pi, "[0, pi]")?;
    check("one_minus_cos", d.one_minus_cos, 2.0, "[0, 2]")?;
    check("one_plus_cos", d.one_plus_cos, 2.0, "[0, 2]")?;
    Ok(d.get())
}

/// Evaluates one of the phase function's scalar maps of a deflection.
fn of_deflection<F: Precision>(
    phase: Option<&F::Phase>,
    d: Option<&omnee_deflection<F>>,
    out: Option<&mut MaybeUninit<F>>,
    name: &'static str,
    error: ErrorOut<'_>,
    map: impl FnOnce(&Phase<'static, F>, Deflection<F>) -> Option<F>,
) -> omnee_status {
    let result = (|| {
        let phase = object(phase)?;
        let d = deflection(d)?;
        map(phase, d).map(|v| finite(v, name)).transpose()
    })();
    finish(out, name, error, result)
}

/// p(θ) per steradian (∫ p dω = 1); also the sampling density of
/// `omnee_phase_sample_f32` per solid angle.
#[unsafe(no_mangle)]
pub extern "C" fn omnee_phase_eval_f32(
    phase: Option<&omnee_phase_f32>,
    deflection: Option<&omnee_deflection<f32>>,
    value: Option<&mut MaybeUninit<f32>>,
    error: Option<&mut MaybeUninit<omnee_error>>,
) -> omnee_status {
    of_deflection::<f32>(phase, deflection, value, "value", error, |p, d| {
        Some(p.eval(d))
    })
}

/// `omnee_phase_eval_f32` in double precision.
#[unsafe(no_mangle)]
pub extern "C" fn omnee_phase_eval_f64(
    phase: Option<&omnee_phase_f64>,
    deflection: Option<&omnee_deflection<f64>>,
    value: Option<&mut MaybeUninit<f64>>,
    error: Option<&mut MaybeUninit<omnee_error>>,
) -> omnee_status {
    of_deflection::<f64>(phase, deflection, value, "value", error, |p, d| {
        Some(p.eval(d))
    })
}

/// P(Θ ≤ θ) = 2π ∫₀^θ p sin θ' dθ'.
#[unsafe(no_mangle)]
pub extern "C" fn omnee_phase_cdf_f32(
    phase: Option<&omnee_phase_f32>,
    deflection: Option<&omnee_deflection<f32>>,
    cdf: Option<&mut MaybeUninit<f32>>,
    error: Option<&mut MaybeUninit<omnee_error>>,
) -> omnee_status {
    of_deflection::<f32>(phase, deflection, cdf, "cdf", error, |p, d| Some(p.cdf(d)))
}

/// `omnee_phase_cdf_f32` in double precision.
#[unsafe(no_mangle)]
pub extern "C" fn omnee_phase_cdf_f64(
    phase: Option<&omnee_phase_f64>,
    deflection: Option<&omnee_deflection<f64>>,
    cdf: Option<&mut MaybeUninit<f64>>,
    error: Option<&mut MaybeUninit<omnee_error>>,
) -> omnee_status {
    of_deflection::<f64>(phase, deflection, cdf, "cdf", error, |p, d| Some(p.cdf(d)))
}

/// The uniform number u with `omnee_phase_sample_f32(u)` = the deflection
/// (the CDF for inverse-CDF samplers); `OMNEE_NONE` for the mixtures (tthg,
/// mie), whose sampler picks a lobe with u.
#[unsafe(no_mangle)]
pub extern "C" fn omnee_phase_invert_f32(
    phase: Option<&omnee_phase_f32>,
    deflection: Option<&omnee_deflection<f32>>,
    u: Option<&mut MaybeUninit<f32>>,
    error: Option<&mut MaybeUninit<omnee_error>>,
) -> omnee_status {
    of_deflection::<f32>(phase, deflection, u, "u", error, |p, d| p.invert(d))
}

/// `omnee_phase_invert_f32` in double precision.
#[unsafe(no_mangle)]
pub extern "C" fn omnee_phase_invert_f64(
    phase: Option<&omnee_phase_f64>,
    deflection: Option<&omnee_deflection<f64>>,
    u: Option<&mut MaybeUninit<f64>>,
    error: Option<&mut MaybeUninit<omnee_error>>,
) -> omnee_status {
    of_deflection::<f64>(phase, deflection, u, "u", error, |p, d| p.invert(d))
}

/// A deflection with solid-angle density `omnee_phase_eval_f32`, from a
/// uniform number u (finite, clamped into [0, 1]; NaN and ±∞ are
/// `OMNEE_ERROR_OUT_OF_RANGE`, as for the deflection constructors).
#[unsafe(no_mangle)]
pub extern "C" fn omnee_phase_sample_f32(
    phase: Option<&omnee_phase_f32>,
    u: f32,
    deflection: Option<&mut MaybeUninit<omnee_deflection<f32>>>,
    error: Option<&mut MaybeUninit<omnee_error>>,
) -> omnee_status {
    sample(phase, u, deflection, error)
}

/// `omnee_phase_sample_f32` in double precision.
#[unsafe(no_mangle)]
pub extern "C" fn omnee_phase_sample_f64(
    phase: Option<&omnee_phase_f64>,
    u: f64,
    deflection: Option<&mut MaybeUninit<omnee_deflection<f64>>>,
    error: Option<&mut MaybeUninit<omnee_error>>,
) -> omnee_status {
    sample(phase, u, deflection, error)
}

fn sample<F: Precision>(
    phase: Option<&F::Phase>,
    u: F,
    out: Option<&mut MaybeUninit<omnee_deflection<F>>>,
    error: ErrorOut<'_>,
) -> omnee_status {
    let result = (|| {
        let phase = object(phase)?;
        if !u.is_finite() {
            return Err(Error::OutOfRange {
                field: "u",
                value: u.to_f64(),
                allowed: "finite, clamped to [0, 1]",
            }
            .into());
        }
        let d = phase.sample(u);
        if !d.is_finite() {
            return Err(Error::not_finite("deflection").into());
        }
        Ok(Some(omnee_deflection::from_core(d)))
    })();
    finish(out, "deflection", error, result)
}

/// The mean cosine ⟨cos θ⟩ (the "g" of the phase function).
#[unsafe(no_mangle)]
pub extern "C" fn omnee_phase_mean_cosine_f32(
    phase: Option<&omnee_phase_f32>,
    mean_cosine: Option<&mut MaybeUninit<f32>>,
    error: Option<&mut MaybeUninit<omnee_error>>,
) -> omnee_status {
    mean_cos(phase, mean_cosine, error)
}

/// `omnee_phase_mean_cosine_f32` in double precision.
#[unsafe(no_mangle)]
pub extern "C" fn omnee_phase_mean_cosine_f64(
    phase: Option<&omnee_phase_f64>,
    mean_cosine: Option<&mut MaybeUninit<f64>>,
    error: Option<&mut MaybeUninit<omnee_error>>,
) -> omnee_status {
    mean_cos(phase, mean_cosine, error)
}

fn mean_cos<F: Precision>(
    phase: Option<&F::Phase>,
    out: Option<&mut MaybeUninit<F>>,
    error: ErrorOut<'_>,
) -> omnee_status {
    let result = (|| {
        let g = object(phase)?.mean_cosine();
        finite(g, "mean_cosine").map(Some)
    })();
    finish(out, "mean_cosine", error, result)
}

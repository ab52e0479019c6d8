//! `omnee_omnee_sample_connections_*` and `omnee_mis_sample_connections_*`:
//! the core's batch over connections (`Connections`), one connection per
//! lane, in structure-of-arrays form (`omnee_connections_*`,
//! `omnee_lane_uniforms_*`, `omnee_samples_*`), f32 and f64.
//!
//! Lane `i` equals the single-connection calls on the same numbers, bit for
//! bit: `omnee_connection_init_*` of its end points and θmax, then
//! `omnee_omnee_sample_*` (or `omnee_mis_sample_*`) of its uniform numbers.
//! Where those return an error (end points the connection refuses, a NaN or
//! infinite number) or `OMNEE_NONE`, the lane has `valid = 0` and zeros:
//! one bad lane does not fail the batch.

use crate::args::{object, rays};
use crate::boundary::{overlap, slice, slice_mut};
use crate::status::{ErrorOut, Failure, fail, finish, omnee_error, omnee_status};
use crate::types::{Precision, omnee_phase_f32, omnee_phase_f64, omnee_rays};
use core::mem::{MaybeUninit, size_of};
use omnee_core::Error;
use omnee_core::method::Setup;
use omnee_core::sampling::{Connections, Points, PointsMut, SampleArrays, Uniforms};

/// Points by coordinate: point `i` is `(x[i], y[i], z[i])`.
#[repr(C)]
#[derive(Clone, Copy, Debug)]
pub struct omnee_points<F> {
    /// x coordinates.
    pub x: *const F,
    /// y coordinates.
    pub y: *const F,
    /// z coordinates.
    pub z: *const F,
}

/// A batch of connections: lane `i` runs from `x0` point `i` (light side)
/// to `x2` point `i` (receiver side), all restricted to θ < `theta_max`
/// ∈ (0, π]. Every array holds `len` numbers.
#[repr(C)]
#[derive(Clone, Copy, Debug)]
pub struct omnee_connections<F> {
    /// The light-side end points.
    pub x0: omnee_points<F>,
    /// The receiver-side end points.
    pub x2: omnee_points<F>,
    /// The restriction θ < θmax of every lane.
    pub theta_max: F,
    /// The number of lanes.
    pub len: usize,
}

/// The uniform numbers of a batch over connections, one array per
/// coordinate, each `len` long: lane `i` takes `(u0[i], u1[i], u2[i])`.
#[repr(C)]
#[derive(Clone, Copy, Debug)]
pub struct omnee_lane_uniforms<F> {
    /// u0 (θ for OMNEE; the companion's decision for MIS's second set).
    pub u0: *const F,
    /// u1.
    pub u1: *const F,
    /// u2.
    pub u2: *const F,
    /// The number of lanes.
    pub len: usize,
}

/// The samples of a batch over connections, each array `len` long: lane
/// `i`'s vertex x1 = `(x[i], y[i], z[i])`, its pdf and weight (as in
/// `omnee_sample_*`), and `valid[i]` = 1 where the lane has a vertex, 0
/// (with all its numbers 0) where not.
#[repr(C)]
#[derive(Clone, Copy, Debug)]
pub struct omnee_samples<F> {
    /// x coordinates of x1.
    pub x: *mut F,
    /// y coordinates of x1.
    pub y: *mut F,
    /// z coordinates of x1.
    pub z: *mut F,
    /// Volume densities (1/m³).
    pub pdf: *mut F,
    /// Weights k/pdf without f_c (1/m).
    pub weight: *mut F,
    /// 1 where the lane has a vertex, else 0.
    pub valid: *mut u8,
    /// The number of lanes.
    pub len: usize,
}

/// OMNEE for a batch of connections: for every lane `i`,
/// `omnee_connection_init_f32` of `connections` point `i` and `theta_max`,
/// then `omnee_omnee_sample_f32` with `phase` and `(u0[i], u1[i], u2[i])`,
/// bit for bit; a lane where either returns an error or `OMNEE_NONE` gets
/// `valid = 0` and zeros. `count` receives the number of lanes with a
/// vertex. Every phase function works (Henyey–Greenstein is vectorised,
/// tables through their own sampler).
///
/// Errors, checked before anything is written (the arrays are then left as
/// they were, `count` is 0): `OMNEE_ERROR_NULL` (`phase`, `count`, or an
/// array of a batch with `len` > 0, named like "x0.y", "u1", "valid"),
/// `OMNEE_ERROR_UNINITIALISED` (`phase`), `OMNEE_ERROR_TABLE` (the three
/// `len`s differ, or an output array overlaps another array),
/// `OMNEE_ERROR_OUT_OF_RANGE` (`theta_max`). NaN or infinite end points or
/// numbers are not errors: their lanes have no vertex.
///
/// # Safety
/// Each pointer in `connections`, `uniforms` and `samples` is NULL (allowed
/// with `len` 0) or points to as many elements as its struct's `len`.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn omnee_omnee_sample_connections_f32(
    phase: Option<&omnee_phase_f32>,
    connections: omnee_connections<f32>,
    uniforms: omnee_lane_uniforms<f32>,
    samples: omnee_samples<f32>,
    count: Option<&mut MaybeUninit<usize>>,
    error: Option<&mut MaybeUninit<omnee_error>>,
) -> omnee_status {
    // SAFETY: the arrays are NULL or as long as their structs' `len` (this
    // function's contract), which is what `omnee_sample` asks.
    unsafe { omnee_sample(phase, connections, uniforms, samples, count, error) }
}

/// `omnee_omnee_sample_connections_f32` in double precision.
///
/// # Safety
/// As for `omnee_omnee_sample_connections_f32`.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn omnee_omnee_sample_connections_f64(
    phase: Option<&omnee_phase_f64>,
    connections: omnee_connections<f64>,
    uniforms: omnee_lane_uniforms<f64>,
    samples: omnee_samples<f64>,
    count: Option<&mut MaybeUninit<usize>>,
    error: Option<&mut MaybeUninit<omnee_error>>,
) -> omnee_status {
    // SAFETY: as in the f32 function (this function's contract).
    unsafe { omnee_sample(phase, connections, uniforms, samples, count, error) }
}

/// The recommended MIS for a batch of connections: for every lane `i`,
/// `omnee_connection_init_f32` of its end points, then `omnee_mis_sample_f32`
/// with `phase`, `rays` and the six numbers `(u0[i], u1[i], u2[i])` of
/// `uniforms` and `(u0[i], u1[i], u2[i])` of `companion_uniforms`, bit for
/// bit: OMNEE's vertex into `samples`, the companion's into
/// `companion_samples` (its `valid` is 1 only where it was drawn and lies
/// behind the cone). `count` receives the number of vertices in both.
///
/// Errors as for `omnee_omnee_sample_connections_f32`, and `rays`' own
/// (`OMNEE_ERROR_NULL`, `OMNEE_ERROR_OUT_OF_RANGE`, `OMNEE_ERROR_DEGENERATE`
/// as in `omnee_mis_sample_f32`); all five `len`s must agree.
///
/// # Safety
/// Each pointer in `connections`, `uniforms`, `companion_uniforms`,
/// `samples` and `companion_samples` is NULL (allowed with `len` 0) or
/// points to as many elements as its struct's `len`.
#[unsafe(no_mangle)]
#[allow(clippy::too_many_arguments)]
pub unsafe extern "C" fn omnee_mis_sample_connections_f32(
    phase: Option<&omnee_phase_f32>,
    rays: Option<&omnee_rays<f32>>,
    connections: omnee_connections<f32>,
    uniforms: omnee_lane_uniforms<f32>,
    companion_uniforms: omnee_lane_uniforms<f32>,
    samples: omnee_samples<f32>,
    companion_samples: omnee_samples<f32>,
    count: Option<&mut MaybeUninit<usize>>,
    error: Option<&mut MaybeUninit<omnee_error>>,
) -> omnee_status {
    let u = [uniforms, companion_uniforms];
    let out = [samples, companion_samples];
    // SAFETY: the arrays are NULL or as long as their structs' `len` (this
    // function's contract), which is what `mis_sample` asks.
    unsafe { mis_sample(phase, rays, connections, u, out, count, error) }
}

/// `omnee_mis_sample_connections_f32` in double precision.
///
/// # Safety
/// As for `omnee_mis_sample_connections_f32`.
#[unsafe(no_mangle)]
#[allow(clippy::too_many_arguments)]
pub unsafe extern "C" fn omnee_mis_sample_connections_f64(
    phase: Option<&omnee_phase_f64>,
    rays: Option<&omnee_rays<f64>>,
    connections: omnee_connections<f64>,
    uniforms: omnee_lane_uniforms<f64>,
    companion_uniforms: omnee_lane_uniforms<f64>,
    samples: omnee_samples<f64>,
    companion_samples: omnee_samples<f64>,
    count: Option<&mut MaybeUninit<usize>>,
    error: Option<&mut MaybeUninit<omnee_error>>,
) -> omnee_status {
    let u = [uniforms, companion_uniforms];
    let out = [samples, companion_samples];
    // SAFETY: as in the f32 function (this function's contract).
    unsafe { mis_sample(phase, rays, connections, u, out, count, error) }
}

/// Lanes per call of the core: its `valid` mask is `bool`, the C one
/// `uint8_t`, so each block's mask passes through a local array.
const BLOCK: usize = 256;

/// One input array: its name, start and length in bytes.
type Span = (&'static str, usize, usize);

/// The input arrays of a batch (end points, then each set of uniforms).
fn input_spans<F>(c: &omnee_connections<F>, u: &[omnee_lane_uniforms<F>]) -> [Option<Span>; 12] {
    let span = |name, p: *const F, len: usize| Some((name, p as usize, len * size_of::<F>()));
    let mut spans = [None; 12];
    let (a, b) = (&c.x0, &c.x2);
    let points = [
        ("x0.x", a.x),
        ("x0.y", a.y),
        ("x0.z", a.z),
        ("x2.x", b.x),
        ("x2.y", b.y),
        ("x2.z", b.z),
    ];
    for (slot, (name, p)) in spans.iter_mut().zip(points) {
        *slot = span(name, p, c.len);
    }
    let names = [
        ["u0", "u1", "u2"],
        ["companion.u0", "companion.u1", "companion.u2"],
    ];
    for (k, u) in u.iter().enumerate() {
        for (j, p) in [u.u0, u.u1, u.u2].into_iter().enumerate() {
            spans[6 + 3 * k + j] = span(names[k][j], p, u.len);
        }
    }
    spans
}

/// The output arrays of the sample sets.
fn output_spans<F>(out: &[omnee_samples<F>]) -> [Option<Span>; 12] {
    let mut spans = [None; 12];
    let names = [
        ["x", "y", "z", "pdf", "weight", "valid"],
        [
            "companion.x",
            "companion.y",
            "companion.z",
            "companion.pdf",
            "companion.weight",
            "companion.valid",
        ],
    ];
    for (k, o) in out.iter().enumerate() {
        let len = o.len;
        let floats = [o.x, o.y, o.z, o.pdf, o.weight];
        for (j, p) in floats.into_iter().enumerate() {
            spans[6 * k + j] = Some((names[k][j], p as usize, len * size_of::<F>()));
        }
        spans[6 * k + 5] = Some((names[k][5], o.valid as usize, len));
    }
    spans
}

/// The checks that need no memory access: every length equal to the
/// connections', no NULL array of a non-empty batch, no output array that
/// shares a byte with another array.
fn check_arrays<F>(
    c: &omnee_connections<F>,
    u: &[omnee_lane_uniforms<F>],
    out: &[omnee_samples<F>],
) -> Result<(), Failure> {
    let n = c.len;
    if u.iter().any(|u| u.len != n) || out.iter().any(|o| o.len != n) {
        return Err(Error::Arrays {
            field: "connections",
            reason: "the arrays of connections, uniforms and samples differ in length",
        }
        .into());
    }
    let (inputs, outputs) = (input_spans(c, u), output_spans(out));
    let all = || inputs.iter().chain(&outputs).flatten();
    if let Some(&(name, _, _)) = all().find(|&&(_, p, bytes)| p == 0 && bytes > 0) {
        return Err(Failure::Null(name));
    }
    let bytes = |&(_, p, len): &Span| (p as *const u8, len);
    for (i, a) in outputs.iter().flatten().enumerate() {
        let (pa, la) = bytes(a);
        let clash = inputs.iter().flatten().any(|b| {
            let (pb, lb) = bytes(b);
            overlap(pa, la, pb, lb)
        }) || outputs.iter().flatten().skip(i + 1).any(|b| {
            let (pb, lb) = bytes(b);
            overlap(pa, la, pb, lb)
        });
        if clash {
            return Err(Error::Arrays {
                field: "connections",
                reason: "arrays overlap",
            }
            .into());
        }
    }
    Ok(())
}

/// The batch's input arrays as slices.
///
/// # Safety
/// Every array is NULL with `len` 0 or as long as its struct's `len`, and
/// no output array overlaps it ([`check_arrays`]) while the slices live.
unsafe fn points<'a, F>(p: &omnee_points<F>, len: usize) -> Points<'a, F> {
    // SAFETY: non-NULL (checked) and `len` long (the contract); nothing
    // writes them while the slices live (no output overlaps them).
    let [x, y, z] = [p.x, p.y, p.z].map(|q| unsafe { slice(q, len) }.unwrap_or(&[]));
    Points { x, y, z }
}

/// The uniform numbers as slices.
///
/// # Safety
/// As for [`points`].
unsafe fn lane_uniforms<'a, F>(u: &omnee_lane_uniforms<F>) -> Uniforms<'a, F> {
    // SAFETY: as in `points`.
    let [u0, u1, u2] = [u.u0, u.u1, u.u2].map(|q| unsafe { slice(q, u.len) }.unwrap_or(&[]));
    Uniforms { u0, u1, u2 }
}

/// A sample set's arrays as slices: the numbers and the C mask.
///
/// # Safety
/// Every array is NULL with `len` 0 or as long as `len`, overlaps no other
/// array ([`check_arrays`]), and nothing else accesses it while the slices
/// live.
unsafe fn samples<'a, F>(o: &omnee_samples<F>) -> ([&'a mut [F]; 5], &'a mut [u8]) {
    let n = o.len;
    // SAFETY: non-NULL (checked), `len` long (the contract), and each array
    // borrowed once, overlapping no other (checked).
    let floats = [o.x, o.y, o.z, o.pdf, o.weight].map(|p| unsafe { slice_mut(p, n) });
    // SAFETY: as above.
    let valid = unsafe { slice_mut(o.valid, n) };
    (
        floats.map(|s| s.unwrap_or(&mut [])),
        valid.unwrap_or(&mut []),
    )
}

/// The core's sample set for lanes `range` of `floats`, its mask in `mask`.
fn block<'a, F>(
    floats: &'a mut [&mut [F]; 5],
    range: core::ops::Range<usize>,
    mask: &'a mut [bool],
) -> SampleArrays<'a, F> {
    let [x, y, z, pdf, weight] = floats;
    SampleArrays {
        x1: PointsMut {
            x: &mut x[range.clone()],
            y: &mut y[range.clone()],
            z: &mut z[range.clone()],
        },
        pdf: &mut pdf[range.clone()],
        weight: &mut weight[range],
        valid: mask,
    }
}

/// θmax as the core checks it (on no lanes), before any lane is written.
fn check_theta_max<F: Precision>(theta_max: F) -> Result<(), Error> {
    let none = Points {
        x: &[],
        y: &[],
        z: &[],
    };
    Connections::new(none, none, theta_max).map(|_| ())
}

/// The core's connections for lanes `range`.
fn lanes<'a, F: Precision>(
    x0: &Points<'a, F>,
    x2: &Points<'a, F>,
    theta_max: F,
    range: core::ops::Range<usize>,
) -> Result<Connections<'a, F>, Error> {
    let cut = |p: &Points<'a, F>| Points {
        x: &p.x[range.clone()],
        y: &p.y[range.clone()],
        z: &p.z[range.clone()],
    };
    Connections::new(cut(x0), cut(x2), theta_max)
}

/// The uniform numbers of lanes `range`.
fn cut<'a, F>(u: &Uniforms<'a, F>, range: core::ops::Range<usize>) -> Uniforms<'a, F> {
    Uniforms {
        u0: &u.u0[range.clone()],
        u1: &u.u1[range.clone()],
        u2: &u.u2[range],
    }
}

/// `omnee_omnee_sample_connections_*`.
///
/// # Safety
/// Every array is NULL (with `len` 0) or as long as its struct's `len`.
unsafe fn omnee_sample<F: Precision>(
    phase: Option<&F::Phase>,
    c: omnee_connections<F>,
    u: omnee_lane_uniforms<F>,
    out: omnee_samples<F>,
    count: Option<&mut MaybeUninit<usize>>,
    error: ErrorOut<'_>,
) -> omnee_status {
    if count.is_none() {
        return fail(error, Failure::Null("count"));
    }
    let result = (|| {
        let phase = object(phase)?;
        check_arrays(&c, &[u], &[out])?;
        check_theta_max(c.theta_max)?;
        // SAFETY: the arrays are NULL only with len 0 and as long as their
        // len (this function's contract), and no output array overlaps
        // another array (`check_arrays`); the same for the next four.
        let x0 = unsafe { points(&c.x0, c.len) };
        // SAFETY: as above.
        let x2 = unsafe { points(&c.x2, c.len) };
        // SAFETY: as above.
        let u = unsafe { lane_uniforms(&u) };
        // SAFETY: as above; the output arrays are borrowed once.
        let (mut floats, valid) = unsafe { samples(&out) };
        let mut total = 0;
        for start in (0..c.len).step_by(BLOCK) {
            let range = start..c.len.min(start + BLOCK);
            let mut mask = [false; BLOCK];
            let mask = &mut mask[..range.len()];
            let batch = lanes(&x0, &x2, c.theta_max, range.clone())?;
            let set = block(&mut floats, range.clone(), mask);
            total += batch.sample_omnee(phase, cut(&u, range.clone()), set)?;
            for (v, &m) in valid[range].iter_mut().zip(mask.iter()) {
                *v = u8::from(m);
            }
        }
        Ok(Some(total))
    })();
    finish(count, "count", error, result)
}

/// `omnee_mis_sample_connections_*`.
///
/// # Safety
/// Every array is NULL (with `len` 0) or as long as its struct's `len`.
unsafe fn mis_sample<F: Precision>(
    phase: Option<&F::Phase>,
    ray: Option<&omnee_rays<F>>,
    c: omnee_connections<F>,
    u: [omnee_lane_uniforms<F>; 2],
    out: [omnee_samples<F>; 2],
    count: Option<&mut MaybeUninit<usize>>,
    error: ErrorOut<'_>,
) -> omnee_status {
    if count.is_none() {
        return fail(error, Failure::Null("count"));
    }
    let result = (|| {
        let phase = object(phase)?;
        let (directions, region) = rays(ray)?;
        let setup = Setup::new(phase, directions, region, F::ZERO)?;
        check_arrays(&c, &u, &out)?;
        check_theta_max(c.theta_max)?;
        // SAFETY: the arrays are NULL only with len 0 and as long as their
        // len (this function's contract), and no output array overlaps
        // another array, the two sample sets included (`check_arrays`);
        // the same for the next five.
        let x0 = unsafe { points(&c.x0, c.len) };
        // SAFETY: as above.
        let x2 = unsafe { points(&c.x2, c.len) };
        // SAFETY: as above.
        let u0 = unsafe { lane_uniforms(&u[0]) };
        // SAFETY: as above.
        let v = unsafe { lane_uniforms(&u[1]) };
        // SAFETY: as above; the output arrays are borrowed once.
        let (mut floats, valid) = unsafe { samples(&out[0]) };
        // SAFETY: as above.
        let (mut floats2, valid2) = unsafe { samples(&out[1]) };
        let mut total = 0;
        for start in (0..c.len).step_by(BLOCK) {
            let range = start..c.len.min(start + BLOCK);
            let (mut mask, mut mask2) = ([false; BLOCK], [false; BLOCK]);
            let (mask, mask2) = (&mut mask[..range.len()], &mut mask2[..range.len()]);
            let batch = lanes(&x0, &x2, c.theta_max, range.clone())?;
            total += batch.sample_mis(
                &setup,
                cut(&u0, range.clone()),
                cut(&v, range.clone()),
                block(&mut floats, range.clone(), mask),
                block(&mut floats2, range.clone(), mask2),
            )?;
            for (v, &m) in valid[range.clone()].iter_mut().zip(mask.iter()) {
                *v = u8::from(m);
            }
            for (v, &m) in valid2[range].iter_mut().zip(mask2.iter()) {
                *v = u8::from(m);
            }
        }
        Ok(Some(total))
    })();
    finish(count, "count", error, result)
}

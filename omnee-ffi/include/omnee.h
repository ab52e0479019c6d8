/*
 * omnee.h: the C API of omnee, once-more scattered next event estimation
 * (OMNEE) for volume rendering. C99 and C++ (extern "C").
 *
 * Build and link (from the repository root):
 *   cargo build --release -p omnee-ffi
 *   cc -std=c99 -Iomnee-ffi/include app.c target/release/libomnee_ffi.a -lm -lpthread -ldl
 * (or link target/release/libomnee_ffi.so). Firmware: build the staticlib for
 * the target, e.g. --target thumbv7em-none-eabihf.
 *
 * NAMES. Every name starts with omnee_ (types, functions) or OMNEE_
 * (constants). Functions are omnee_<object>_<operation>_<precision>:
 *   objects:    connection, phase, deflection, problem, the techniques
 *               omnee (OMNEE itself), equiangular, distance, mis, and
 *               bridge (k scattering vertices between x0 and x2) with
 *               vertex_count (the number k drawn per connection);
 *   operations: init / a phase function's name / parse / table (make an
 *               object), sample, pdf, invert (the technique trio, as in
 *               pbrt-v4 and Mitsuba 3's warps), sample_batch, eval, cdf,
 *               mean_cosine, f_c, estimate, reference;
 *   precision:  _f32 (renderers) or _f64 (references); types that hold
 *               numbers carry the same suffix.
 * Arguments come in the order: objects read, numbers in, outputs, error.
 *
 * STATUS. Every function returns an omnee_status: OMNEE_OK (0); OMNEE_NONE
 * (1, success without a result: uniform numbers that map to no contributing
 * vertex, a point without preimage); OMNEE_TABLE_SPEC (2); or a negative
 * OMNEE_ERROR_*. On any status but OMNEE_OK the outputs are zeroed (opaque
 * objects then fail every later use with OMNEE_ERROR_UNINITIALISED), except
 * where a function says otherwise (omnee_phase_parse_* leaves the phase
 * function unwritten on OMNEE_TABLE_SPEC; omnee_omnee_sample_batch_f32
 * leaves its vertex arrays as they were on an error, and so do
 * omnee_bridge_sample_* and omnee_bridge_invert_* with the caller's
 * vertex and number arrays); no output is written
 * before every check of the call has passed. The last argument, omnee_error *error, may be NULL; when it is not and the call
 * fails, it receives the status, the offending field's name, its value
 * (out-of-range numbers) and the message, for the core's errors exactly the
 * Rust API's text: "g = 1 is out of range; allowed: (-1, 1)". NULL pointers,
 * NaN and infinite numbers, x0 == x2, out-of-range parameters and lengths
 * that disagree are statuses, never undefined behaviour; no output is ever
 * NaN or infinite.
 *
 * MEMORY AND THREADS. The library allocates nothing and has no global
 * state: the caller owns every object (declare them on the stack or embed
 * them), and any number of threads may call any function at once on objects
 * they do not write concurrently. Opaque objects (omnee_connection_*,
 * omnee_phase_*, omnee_problem_*) are made by their constructors, may be
 * copied with = or memcpy, and need no destructor; their size is a constant
 * of the library's version (the OMNEE_*_WORDS constants). An object's tag
 * holds a checksum of its storage, checked on every use before the storage
 * is read: zeroed, garbage or altered memory (even under a tag copied from a
 * valid object) is OMNEE_ERROR_UNINITIALISED, never dereferenced (a random
 * change passes with probability 2^-64). A table's phase function refers to
 * the caller's arrays, which must outlive it unmodified (the checksum covers
 * the object, not the arrays).
 *
 * POINTERS. Every pointer argument is NULL (a status, never dereferenced) or
 * points to valid memory of its type and documented extent, and outputs do
 * not overlap inputs (the batch and the table check their arrays).
 *
 * PANICS. The library is written not to panic; should it, it aborts (hosted)
 * or traps (bare metal) and never unwinds into C.
 *
 * UNITS. Lengths in metres, coefficients in 1/m, densities per m^3 (volume
 * measure) or per steradian (phase functions), angles in radians. The
 * deflection theta is the angle between the propagation directions before
 * and after scattering (theta = 0: straight on).
 *
 * SCALE. Every finite geometry is accepted: end points with any finite
 * coordinates whose distance s is not zero and at most the precision's
 * largest number (from 1e-45 to 3.4e38 apart in f32, 4.9e-324 to 1.8e308 in
 * f64; a larger distance is OMNEE_ERROR_NOT_FINITE, field "x2 - x0"),
 * normals and directions of any finite non-zero length, theta_max in
 * (0, pi] down to the smallest subnormal. Lengths and densities are
 * computed in a power-of-two unit near s, so every result is right
 * wherever it is representable, and scaling a problem by a power of two
 * scales every result exactly (docs/math.md section 15). Where a value
 * itself leaves the range it saturates: a density below the smallest
 * subnormal is 0, above the largest number the largest number. The
 * once-scattered transfer falls as 1/s^2 (sigma scaled as 1/s): at s = 1e30
 * in f32 f_c and weight are each about 1e-30 but their product 1e-60 is 0 in
 * f32; multiply them in double, or with the light's intensity first.
 */


#ifndef OMNEE_H
#define OMNEE_H

/* Generated by cbindgen from omnee-ffi/src; do not edit (see omnee-ffi/cbindgen.toml). */

#include <stddef.h>
#include <stdint.h>

// The largest number of inner vertices of a bridge (the core's
// `MAX_VERTICES`); a vertex array of this capacity fits every bridge.
#define OMNEE_MAX_VERTICES 32

// The default evaluation budget of `omnee_bridge_reference_*` (the core's
// `REFERENCE_BUDGET`): tens of milliseconds at most.
#define OMNEE_REFERENCE_BUDGET 1000000

// Bytes in `omnee_error.field`, with the terminating NUL.
#define OMNEE_ERROR_FIELD_CAPACITY 32

// Bytes in `omnee_error.message`, with the terminating NUL: every message
// the library writes fits.
#define OMNEE_ERROR_MESSAGE_CAPACITY 512

// `omnee_rays.directions`: uniform on the sphere, pdf 1/(4π).
#define OMNEE_DIRECTIONS_SPHERE 0

// `omnee_rays.directions`: cosine-weighted about `omnee_rays.normal`.
#define OMNEE_DIRECTIONS_COSINE 1

// `omnee_rays.region`: the medium fills all of space.
#define OMNEE_REGION_EVERYWHERE 0

// `omnee_rays.region`: the medium fills the slab `z_min ≤ z ≤ z_max`.
#define OMNEE_REGION_SLAB 1

// 64-bit words of storage in `omnee_connection_f32`.
#define OMNEE_CONNECTION_F32_WORDS 11

// 64-bit words of storage in `omnee_connection_f64`.
#define OMNEE_CONNECTION_F64_WORDS 21

// 64-bit words of storage in `omnee_phase_f32`.
#define OMNEE_PHASE_F32_WORDS 8

// 64-bit words of storage in `omnee_phase_f64`.
#define OMNEE_PHASE_F64_WORDS 10

// 64-bit words of storage in `omnee_problem_f32`.
#define OMNEE_PROBLEM_F32_WORDS 14

// 64-bit words of storage in `omnee_problem_f64`.
#define OMNEE_PROBLEM_F64_WORDS 27

// 64-bit words of storage in `omnee_vertex_count_f32`.
#define OMNEE_VERTEX_COUNT_F32_WORDS 18

// 64-bit words of storage in `omnee_vertex_count_f64`.
#define OMNEE_VERTEX_COUNT_F64_WORDS 34

// What a function did. Zero and positive: success (an output may still be
// "nothing", as Rust's `None`); negative: an error, described in the
// `omnee_error` record when the caller passed one.
enum omnee_status
#if defined(__cplusplus) || __STDC_VERSION__ >= 202311L
  : int32_t
#endif // defined(__cplusplus) || __STDC_VERSION__ >= 202311L
 {
  // Success: every output is written.
  OMNEE_OK = 0,
  // Success without a result (Rust's `None`): the uniform numbers map to
  // no vertex that contributes, the point has no preimage, or the phase
  // function's sampler is not invertible (mixtures). Outputs are zero.
  OMNEE_NONE = 1,
  // `omnee_phase_parse_*` read `table:PATH`: the caller loads the file and
  // calls `omnee_phase_table_*`. The phase function is not written.
  OMNEE_TABLE_SPEC = 2,
  // A parameter is NaN, infinite or outside its range (the record names
  // it, its value and the allowed range).
  OMNEE_ERROR_OUT_OF_RANGE = -1,
  // A vector parameter has a NaN or infinite component, finite values
  // have a sum that is not finite (a table's values near the largest
  // number), or a result would not be finite.
  OMNEE_ERROR_NOT_FINITE = -2,
  // Two points that must differ coincide (x0 == x2), or a direction is zero.
  OMNEE_ERROR_DEGENERATE = -3,
  // A table or array has the wrong shape: lengths that disagree,
  // unordered or misplaced edges, overlapping arrays.
  OMNEE_ERROR_TABLE = -4,
  // A phase-function spec string is malformed.
  OMNEE_ERROR_SYNTAX = -5,
  // A required pointer is NULL.
  OMNEE_ERROR_NULL = -6,
  // An opaque object was not made by its constructor, or its storage
  // changed since: zeroed or garbage memory, a failed constructor's
  // output, the other precision's type, or a valid tag over altered
  // storage (the tag carries a checksum of the storage, checked on every
  // use before the storage is read; a random change goes undetected with
  // probability 2^-64).
  OMNEE_ERROR_UNINITIALISED = -7,
  // The operation does not exist for these arguments (the batch needs
  // Henyey–Greenstein).
  OMNEE_ERROR_UNSUPPORTED = -8,
  // A quadrature reference spent its evaluation budget before meeting
  // its tolerance (`omnee_problem_reference_*`): no value is returned.
  // It takes at most a few seconds, never longer.
  OMNEE_ERROR_NOT_CONVERGED = -9,
};
#ifndef __cplusplus
#if __STDC_VERSION__ >= 202311L
typedef enum omnee_status omnee_status;
#else
typedef int32_t omnee_status;
#endif // __STDC_VERSION__ >= 202311L
#endif // __cplusplus

// The end points x0, x2 and the restriction θ < θmax (opaque; make it with
// `omnee_connection_init_f32`; copy it freely).
typedef struct omnee_connection_f32 {
  uint64_t tag;
  uint64_t storage[OMNEE_CONNECTION_F32_WORDS];
} omnee_connection_f32;

// A phase function (opaque; make it with an `omnee_phase_*_f32`
// constructor; copy it freely). A table's phase function refers to the
// caller's arrays.
typedef struct omnee_phase_f32 {
  uint64_t tag;
  uint64_t storage[OMNEE_PHASE_F32_WORDS];
} omnee_phase_f32;

// A point or direction `(x, y, z)`.
typedef struct omnee_vec3_f32 {
  // x.
  float x;
  // y.
  float y;
  // z.
  float z;
} omnee_vec3_f32;

// One bridge drawn by `omnee_bridge_sample_*` (the core's `BridgeSample`); its
// `k` inner vertices are in the caller's array.
typedef struct omnee_bridge_f32 {
  // The number of inner vertices k, in [1, OMNEE_MAX_VERTICES].
  size_t k;
  // The path's total length D = d_1 + … + d_{k+1} (m).
  float length;
  // The density in the product of volume measures (1/m^{3k}),
  // s³ k! Π q(θ_i) / (Π d_j² D^{k+1}); finite (saturating).
  float pdf;
  // Π p(θ_i)/q(θ_i): 1 for phase functions that sample exactly.
  float phase_ratio;
  // The kernel Π p(θ_i) / Π d_j² over pdf, (p/q) D^{k+1}/(s³ k!);
  // finite and ≥ 0 (saturating). `omnee_bridge_estimate_*` multiplies in
  // σs^k e^{−σt D} without forming the huge factors alone.
  float weight;
} omnee_bridge_f32;

// An error, written by a function that fails (status < 0) when the caller
// passes a non-NULL `omnee_error *`; untouched on success. Caller-owned,
// so errors need no global state and threads never share one.
typedef struct omnee_error {
  // The status the function returned (an `omnee_status`).
  int32_t status;
  // For `OMNEE_ERROR_OUT_OF_RANGE`: the value that was given; else 0.
  double value;
  // The offending parameter's name, NUL-terminated (e.g. "g", "x2",
  // "theta_max").
  char field[OMNEE_ERROR_FIELD_CAPACITY];
  // The message, NUL-terminated UTF-8: for the core's errors exactly the
  // Rust API's `Display` text, e.g. `g = 1 is out of range; allowed: (-1, 1)`.
  char message[OMNEE_ERROR_MESSAGE_CAPACITY];
} omnee_error;

// The end points x0, x2 and the restriction θ < θmax (opaque; make it with
// `omnee_connection_init_f64`; copy it freely).
typedef struct omnee_connection_f64 {
  uint64_t tag;
  uint64_t storage[OMNEE_CONNECTION_F64_WORDS];
} omnee_connection_f64;

// A phase function (opaque; make it with an `omnee_phase_*_f64`
// constructor; copy it freely). A table's phase function refers to the
// caller's arrays.
typedef struct omnee_phase_f64 {
  uint64_t tag;
  uint64_t storage[OMNEE_PHASE_F64_WORDS];
} omnee_phase_f64;

// A point or direction `(x, y, z)`.
typedef struct omnee_vec3_f64 {
  // x.
  double x;
  // y.
  double y;
  // z.
  double z;
} omnee_vec3_f64;

// One bridge drawn by `omnee_bridge_sample_*` (the core's `BridgeSample`); its
// `k` inner vertices are in the caller's array.
typedef struct omnee_bridge_f64 {
  // The number of inner vertices k, in [1, OMNEE_MAX_VERTICES].
  size_t k;
  // The path's total length D = d_1 + … + d_{k+1} (m).
  double length;
  // The density in the product of volume measures (1/m^{3k}),
  // s³ k! Π q(θ_i) / (Π d_j² D^{k+1}); finite (saturating).
  double pdf;
  // Π p(θ_i)/q(θ_i): 1 for phase functions that sample exactly.
  double phase_ratio;
  // The kernel Π p(θ_i) / Π d_j² over pdf, (p/q) D^{k+1}/(s³ k!);
  // finite and ≥ 0 (saturating). `omnee_bridge_estimate_*` multiplies in
  // σs^k e^{−σt D} without forming the huge factors alone.
  double weight;
} omnee_bridge_f64;

// The point-to-point problem: a connection in a homogeneous medium, with
// an optional receiver cosine (opaque; make it with
// `omnee_problem_init_f32`; copy it freely).
typedef struct omnee_problem_f32 {
  uint64_t tag;
  uint64_t storage[OMNEE_PROBLEM_F32_WORDS];
} omnee_problem_f32;

// The point-to-point problem: a connection in a homogeneous medium, with
// an optional receiver cosine (opaque; make it with
// `omnee_problem_init_f64`; copy it freely).
typedef struct omnee_problem_f64 {
  uint64_t tag;
  uint64_t storage[OMNEE_PROBLEM_F64_WORDS];
} omnee_problem_f64;

// The distribution of the number of bridge vertices k ∈ [1, k_max]
// (opaque; make it with `omnee_vertex_count_init_f32`; copy it freely).
typedef struct omnee_vertex_count_f32 {
  uint64_t tag;
  uint64_t storage[OMNEE_VERTEX_COUNT_F32_WORDS];
} omnee_vertex_count_f32;

// The distribution of the number of bridge vertices k ∈ [1, k_max]
// (opaque; make it with `omnee_vertex_count_init_f64`; copy it freely).
typedef struct omnee_vertex_count_f64 {
  uint64_t tag;
  uint64_t storage[OMNEE_VERTEX_COUNT_F64_WORDS];
} omnee_vertex_count_f64;

// A number of bridge vertices drawn by `omnee_vertex_count_sample_*`: `k`
// and the probability P(k) with which it was drawn.
typedef struct omnee_vertex_draw_f32 {
  // The number of inner vertices k.
  size_t k;
  // P(k), in (0, 1].
  float probability;
} omnee_vertex_draw_f32;

// A number of bridge vertices drawn by `omnee_vertex_count_sample_*`: `k`
// and the probability P(k) with which it was drawn.
typedef struct omnee_vertex_draw_f64 {
  // The number of inner vertices k.
  size_t k;
  // P(k), in (0, 1].
  double probability;
} omnee_vertex_draw_f64;

// Points by coordinate: point `i` is `(x[i], y[i], z[i])`.
typedef struct omnee_points_f32 {
  // x coordinates.
  const float *x;
  // y coordinates.
  const float *y;
  // z coordinates.
  const float *z;
} omnee_points_f32;

// A batch of connections: lane `i` runs from `x0` point `i` (light side)
// to `x2` point `i` (receiver side), all restricted to θ < `theta_max`
// ∈ (0, π]. Every array holds `len` numbers.
typedef struct omnee_connections_f32 {
  // The light-side end points.
  struct omnee_points_f32 x0;
  // The receiver-side end points.
  struct omnee_points_f32 x2;
  // The restriction θ < θmax of every lane.
  float theta_max;
  // The number of lanes.
  size_t len;
} omnee_connections_f32;

// The uniform numbers of a batch over connections, one array per
// coordinate, each `len` long: lane `i` takes `(u0[i], u1[i], u2[i])`.
typedef struct omnee_lane_uniforms_f32 {
  // u0 (θ for OMNEE; the companion's decision for MIS's second set).
  const float *u0;
  // u1.
  const float *u1;
  // u2.
  const float *u2;
  // The number of lanes.
  size_t len;
} omnee_lane_uniforms_f32;

// The samples of a batch over connections, each array `len` long: lane
// `i`'s vertex x1 = `(x[i], y[i], z[i])`, its pdf and weight (as in
// `omnee_sample_*`), and `valid[i]` = 1 where the lane has a vertex, 0
// (with all its numbers 0) where not.
typedef struct omnee_samples_f32 {
  // x coordinates of x1.
  float *x;
  // y coordinates of x1.
  float *y;
  // z coordinates of x1.
  float *z;
  // Volume densities (1/m³).
  float *pdf;
  // Weights k/pdf without f_c (1/m).
  float *weight;
  // 1 where the lane has a vertex, else 0.
  uint8_t *valid;
  // The number of lanes.
  size_t len;
} omnee_samples_f32;

// Points by coordinate: point `i` is `(x[i], y[i], z[i])`.
typedef struct omnee_points_f64 {
  // x coordinates.
  const double *x;
  // y coordinates.
  const double *y;
  // z coordinates.
  const double *z;
} omnee_points_f64;

// A batch of connections: lane `i` runs from `x0` point `i` (light side)
// to `x2` point `i` (receiver side), all restricted to θ < `theta_max`
// ∈ (0, π]. Every array holds `len` numbers.
typedef struct omnee_connections_f64 {
  // The light-side end points.
  struct omnee_points_f64 x0;
  // The receiver-side end points.
  struct omnee_points_f64 x2;
  // The restriction θ < θmax of every lane.
  double theta_max;
  // The number of lanes.
  size_t len;
} omnee_connections_f64;

// The uniform numbers of a batch over connections, one array per
// coordinate, each `len` long: lane `i` takes `(u0[i], u1[i], u2[i])`.
typedef struct omnee_lane_uniforms_f64 {
  // u0 (θ for OMNEE; the companion's decision for MIS's second set).
  const double *u0;
  // u1.
  const double *u1;
  // u2.
  const double *u2;
  // The number of lanes.
  size_t len;
} omnee_lane_uniforms_f64;

// The samples of a batch over connections, each array `len` long: lane
// `i`'s vertex x1 = `(x[i], y[i], z[i])`, its pdf and weight (as in
// `omnee_sample_*`), and `valid[i]` = 1 where the lane has a vertex, 0
// (with all its numbers 0) where not.
typedef struct omnee_samples_f64 {
  // x coordinates of x1.
  double *x;
  // y coordinates of x1.
  double *y;
  // z coordinates of x1.
  double *z;
  // Volume densities (1/m³).
  double *pdf;
  // Weights k/pdf without f_c (1/m).
  double *weight;
  // 1 where the lane has a vertex, else 0.
  uint8_t *valid;
  // The number of lanes.
  size_t len;
} omnee_samples_f64;

// How the ray techniques (equiangular, distance, and the MIS companion)
// draw a ray from x2, and where the medium is along it. All zero (the
// default): uniform directions, medium everywhere.
typedef struct omnee_rays_f32 {
  // `OMNEE_DIRECTIONS_SPHERE` or `OMNEE_DIRECTIONS_COSINE`.
  uint32_t directions;
  // The cosine's normal at x2, normalised by the library: any finite,
  // non-zero length (`OMNEE_ERROR_NOT_FINITE` for a NaN or infinite
  // component, `OMNEE_ERROR_DEGENERATE` for zero); ignored for the
  // sphere.
  struct omnee_vec3_f32 normal;
  // `OMNEE_REGION_EVERYWHERE` or `OMNEE_REGION_SLAB`.
  uint32_t region;
  // The slab's lower plane (finite); ignored for everywhere.
  float z_min;
  // The slab's upper plane (finite, > z_min); ignored for everywhere.
  float z_max;
} omnee_rays_f32;

// How the ray techniques (equiangular, distance, and the MIS companion)
// draw a ray from x2, and where the medium is along it. All zero (the
// default): uniform directions, medium everywhere.
typedef struct omnee_rays_f64 {
  // `OMNEE_DIRECTIONS_SPHERE` or `OMNEE_DIRECTIONS_COSINE`.
  uint32_t directions;
  // The cosine's normal at x2, normalised by the library: any finite,
  // non-zero length (`OMNEE_ERROR_NOT_FINITE` for a NaN or infinite
  // component, `OMNEE_ERROR_DEGENERATE` for zero); ignored for the
  // sphere.
  struct omnee_vec3_f64 normal;
  // `OMNEE_REGION_EVERYWHERE` or `OMNEE_REGION_SLAB`.
  uint32_t region;
  // The slab's lower plane (finite); ignored for everywhere.
  double z_min;
  // The slab's upper plane (finite, > z_min); ignored for everywhere.
  double z_max;
} omnee_rays_f64;

// A part of a string: `length` bytes from byte `offset`.
typedef struct omnee_span {
  // Offset of the first byte.
  size_t offset;
  // Number of bytes.
  size_t length;
} omnee_span;

// A deflection angle θ ∈ [0, π] in cancellation-free form (the core's
// `Deflection`): `one_minus_cos = 1 − cos θ`, `one_plus_cos = 1 + cos θ`,
// each accurate where it is small. Make one with `omnee_deflection_*`.
typedef struct omnee_deflection_f32 {
  // θ in radians, in [0, π].
  float theta;
  // 1 − cos θ, in [0, 2].
  float one_minus_cos;
  // 1 + cos θ, in [0, 2].
  float one_plus_cos;
} omnee_deflection_f32;

// A deflection angle θ ∈ [0, π] in cancellation-free form (the core's
// `Deflection`): `one_minus_cos = 1 − cos θ`, `one_plus_cos = 1 + cos θ`,
// each accurate where it is small. Make one with `omnee_deflection_*`.
typedef struct omnee_deflection_f64 {
  // θ in radians, in [0, π].
  double theta;
  // 1 − cos θ, in [0, 2].
  double one_minus_cos;
  // 1 + cos θ, in [0, 2].
  double one_plus_cos;
} omnee_deflection_f64;

// A sampled scattering vertex (the core's `Sample`).
typedef struct omnee_sample_f32 {
  // The vertex x1.
  struct omnee_vec3_f32 x1;
  // Its density in the volume measure (1/m³), finite, saturating at the
  // precision's largest number (and 0 where it underflows, e.g. s > 1e13
  // in f32).
  float pdf;
  // The estimator k(x1)/pdf(x1) without f_c (1/m), finite and ≥ 0;
  // multiply by f_c (`omnee_problem_f_c_*`) for one estimate.
  float weight;
} omnee_sample_f32;

// A sampled scattering vertex (the core's `Sample`).
typedef struct omnee_sample_f64 {
  // The vertex x1.
  struct omnee_vec3_f64 x1;
  // Its density in the volume measure (1/m³), finite, saturating at the
  // precision's largest number (and 0 where it underflows, e.g. s > 1e13
  // in f32).
  double pdf;
  // The estimator k(x1)/pdf(x1) without f_c (1/m), finite and ≥ 0;
  // multiply by f_c (`omnee_problem_f_c_*`) for one estimate.
  double weight;
} omnee_sample_f64;

// The vertices of one MIS estimate (`omnee_mis_sample_*`): OMNEE's, and
// now and then the companion's. Sum `f_c · weight` over the present ones.
typedef struct omnee_draw_f32 {
  // `vertices[0]` is OMNEE's vertex, `vertices[1]` the companion's; an
  // absent vertex is all zero.
  struct omnee_sample_f32 vertices[2];
  // Bit `k` is set when `vertices[k]` is present.
  uint32_t present;
} omnee_draw_f32;

// The vertices of one MIS estimate (`omnee_mis_sample_*`): OMNEE's, and
// now and then the companion's. Sum `f_c · weight` over the present ones.
typedef struct omnee_draw_f64 {
  // `vertices[0]` is OMNEE's vertex, `vertices[1]` the companion's; an
  // absent vertex is all zero.
  struct omnee_sample_f64 vertices[2];
  // Bit `k` is set when `vertices[k]` is present.
  uint32_t present;
} omnee_draw_f64;

// The uniform numbers of a batch (`omnee_omnee_sample_batch_f32`), one
// array per coordinate, each `len` long.
typedef struct omnee_uniforms_f32 {
  // u0, which draws θ.
  const float *u0;
  // u1 = β/θ.
  const float *u1;
  // u2 = φ/2π.
  const float *u2;
  // The number of entries in each array.
  size_t len;
} omnee_uniforms_f32;

// The vertices of a batch: x1 by coordinate, its pdf and weight (0 where
// there is no sample), each array `len` long.
typedef struct omnee_vertices_f32 {
  // x coordinates of x1.
  float *x;
  // y coordinates of x1.
  float *y;
  // z coordinates of x1.
  float *z;
  // Volume densities.
  float *pdf;
  // Weights θ/(s sin θ).
  float *weight;
  // The number of entries in each array.
  size_t len;
} omnee_vertices_f32;

#ifdef __cplusplus
extern "C" {
#endif // __cplusplus

// Draws a bridge of `k` inner vertices x_1 … x_k from x0 to x2 of
// `connection` (whose θmax must be π, else `OMNEE_ERROR_OUT_OF_RANGE`,
// field "theta_max"), with `phase` at every vertex (docs/math.md §14): a
// chain of k + 1 edges with deflections from the phase function and edge
// proportions uniform on the simplex, turned and scaled about x0 until it
// ends at x2. `u` points to 3k numbers in [0, 1], three per vertex
// (u_θ, u_φ, u_t); `vertices` to `capacity` ≥ k points, of which the first
// k receive the vertices. `*sample_out` gets k, the length D, the density
// pdf = s³ k! Π q(θ_i) / (Π d_j² D^{k+1}) in the product of volume
// measures and the weight (p/q) D^{k+1}/(s³ k!).
//
// `OMNEE_NONE` when the numbers map to no contributing path (an edge of
// length 0, or a vertex beyond the largest number, which end points near
// it can ask for): the sample and `vertices[0..k)` are zero. On an error
// (k = 0 or > OMNEE_MAX_VERTICES and u or vertices NULL:
// `OMNEE_ERROR_OUT_OF_RANGE`/`_NULL`; capacity < k: `OMNEE_ERROR_OUT_OF_RANGE`,
// field "capacity"; a NaN or infinite u: `OMNEE_ERROR_NOT_FINITE`; u outside
// [0, 1]: `OMNEE_ERROR_OUT_OF_RANGE`; `vertices` overlapping `u`:
// `OMNEE_ERROR_TABLE`) the sample is zeroed and `vertices` is left as it was.
//
// # Safety
// `u` is NULL or points to 3k floats; `vertices` is NULL or points to
// `capacity` writable points.
omnee_status omnee_bridge_sample_f32(const struct omnee_connection_f32 *connection,
                                     const struct omnee_phase_f32 *phase,
                                     size_t k,
                                     const float *u,
                                     struct omnee_vec3_f32 *vertices,
                                     size_t capacity,
                                     struct omnee_bridge_f32 *sample_out,
                                     struct omnee_error *error);

// `omnee_bridge_sample_f32` in double precision.
//
// # Safety
// `u` is NULL or points to 3k doubles; `vertices` is NULL or points to
// `capacity` writable points.
omnee_status omnee_bridge_sample_f64(const struct omnee_connection_f64 *connection,
                                     const struct omnee_phase_f64 *phase,
                                     size_t k,
                                     const double *u,
                                     struct omnee_vec3_f64 *vertices,
                                     size_t capacity,
                                     struct omnee_bridge_f64 *sample_out,
                                     struct omnee_error *error);

// The density of `omnee_bridge_sample_*` at the path x0, `vertices[0..k)`,
// x2 of `connection` (θmax = π) with `phase`:
// s³ k! Π q(θ_i) / (Π d_j² D^{k+1}) (docs/math.md §14.4), 0 where two
// consecutive points coincide. k ∈ [1, OMNEE_MAX_VERTICES]; `vertices`
// points to k finite points (`OMNEE_ERROR_NOT_FINITE`, field "vertices").
//
// # Safety
// `vertices` is NULL or points to k points.
omnee_status omnee_bridge_pdf_f32(const struct omnee_connection_f32 *connection,
                                  const struct omnee_phase_f32 *phase,
                                  size_t k,
                                  const struct omnee_vec3_f32 *vertices,
                                  float *pdf,
                                  struct omnee_error *error);

// `omnee_bridge_pdf_f32` in double precision.
//
// # Safety
// `vertices` is NULL or points to k points.
omnee_status omnee_bridge_pdf_f64(const struct omnee_connection_f64 *connection,
                                  const struct omnee_phase_f64 *phase,
                                  size_t k,
                                  const struct omnee_vec3_f64 *vertices,
                                  double *pdf,
                                  struct omnee_error *error);

// The uniform numbers that `omnee_bridge_sample_*` maps to the path x0,
// `vertices[0..k)`, x2 of `connection` (θmax = π) with `phase`, written to
// `u[0..3k)` (three per vertex, as `omnee_bridge_sample_*` reads them);
// `capacity` is u's length, at least 3k. `OMNEE_NONE` (u[0..3k) zero) where
// the map has no inverse: coincident points, a first deflection of 0 or π,
// or a phase function whose sampler is not invertible (mixtures). On an
// error (k out of range, capacity < 3k, NULL, a NaN vertex, u overlapping
// the vertices) u is left as it was.
//
// # Safety
// `vertices` is NULL or points to k points; `u` is NULL or points to
// `capacity` writable numbers.
omnee_status omnee_bridge_invert_f32(const struct omnee_connection_f32 *connection,
                                     const struct omnee_phase_f32 *phase,
                                     size_t k,
                                     const struct omnee_vec3_f32 *vertices,
                                     float *u,
                                     size_t capacity,
                                     struct omnee_error *error);

// `omnee_bridge_invert_f32` in double precision.
//
// # Safety
// `vertices` is NULL or points to k points; `u` is NULL or points to
// `capacity` writable numbers.
omnee_status omnee_bridge_invert_f64(const struct omnee_connection_f64 *connection,
                                     const struct omnee_phase_f64 *phase,
                                     size_t k,
                                     const struct omnee_vec3_f64 *vertices,
                                     double *u,
                                     size_t capacity,
                                     struct omnee_error *error);

// One estimate of I_k = ∫…∫ Π σs p(θ_i) e^{−σt D} / (d_1² ⋯ d_{k+1}²) dx_1 ⋯ dx_k
// for the problem's medium (σs, σt; θmax = π and no receiver cosine, else
// `OMNEE_ERROR_OUT_OF_RANGE` / `OMNEE_ERROR_UNSUPPORTED`) from a bridge of
// `omnee_bridge_sample_*` drawn for the problem's connection:
// σs^k e^{−σt D} · weight, evaluated without forming D^{k+1} or e^{−σt D}
// alone (docs/math.md §14.5); finite and ≥ 0 (0 where it underflows).
// `sample` must hold k ∈ [0, OMNEE_MAX_VERTICES] and finite, non-negative
// numbers (`OMNEE_ERROR_OUT_OF_RANGE`, field "sample.k" or "sample"); the
// zero sample of `OMNEE_NONE` (k = 0) estimates 0.
omnee_status omnee_bridge_estimate_f32(const struct omnee_problem_f32 *problem,
                                       const struct omnee_bridge_f32 *sample,
                                       float *estimate,
                                       struct omnee_error *error);

// `omnee_bridge_estimate_f32` in double precision.
omnee_status omnee_bridge_estimate_f64(const struct omnee_problem_f64 *problem,
                                       const struct omnee_bridge_f64 *sample,
                                       double *estimate,
                                       struct omnee_error *error);

// The exact I_k for isotropic scattering in the problem's medium (θmax = π,
// no receiver cosine) between its end points, s = |x2 − x0|, by adaptive
// quadrature of the 1-D integral of docs/math.md §14.6 (relative accuracy
// about 1e-10), in double precision whatever the problem's. k ∈
// [1, OMNEE_MAX_VERTICES]; σt > 0 for k ≥ 2 (`OMNEE_ERROR_OUT_OF_RANGE`,
// field "sigma_t": without extinction the integral diverges). Its cost is
// bounded by `budget` evaluations of the integrand
// (`OMNEE_REFERENCE_BUDGET` is the default, tens of milliseconds at most):
// a quadrature that spends it returns `OMNEE_ERROR_NOT_CONVERGED` (field
// "reference") and `*reference` = 0. Of its two integrals (docs/math.md
// §14.6) it takes the one whose signs cancel little; where both would leave
// fewer than ten digits (dense media: none for σt s up to 20, k = 17 … 28
// at 30) it returns `OMNEE_ERROR_OUT_OF_RANGE` (field "k") and
// `*reference` = 0, never a wrong value.
omnee_status omnee_bridge_reference_f32(const struct omnee_problem_f32 *problem,
                                        size_t k,
                                        size_t budget,
                                        double *reference,
                                        struct omnee_error *error);

// `omnee_bridge_reference_f32` for a double-precision problem.
omnee_status omnee_bridge_reference_f64(const struct omnee_problem_f64 *problem,
                                        size_t k,
                                        size_t budget,
                                        double *reference,
                                        struct omnee_error *error);

// The distribution of the number of bridge vertices k ∈ [1, `k_max`]
// (`k_max` ≤ OMNEE_MAX_VERTICES) for the problem's connection and medium and
// `phase`'s mean cosine g (docs/math.md §14.7): a Poisson distribution of
// mean μ = σs s (1 + (1 − |g|) σt s / 2) truncated to [1, k_max], mixed with
// the uniform one for the share 0.2. Drawing k, then a bridge of k
// vertices, and dividing its estimate by P(k) estimates Σ_{k=1}^{k_max} I_k
// without bias. The problem's θmax and receiver cosine are not used.
omnee_status omnee_vertex_count_init_f32(struct omnee_vertex_count_f32 *count,
                                         const struct omnee_problem_f32 *problem,
                                         const struct omnee_phase_f32 *phase,
                                         size_t k_max,
                                         struct omnee_error *error);

// `omnee_vertex_count_init_f32` in double precision.
omnee_status omnee_vertex_count_init_f64(struct omnee_vertex_count_f64 *count,
                                         const struct omnee_problem_f64 *problem,
                                         const struct omnee_phase_f64 *phase,
                                         size_t k_max,
                                         struct omnee_error *error);

// Draws k by inversion of the distribution's table from `u` ∈ [0, 1)
// (`u` = 1 gives k_max; NaN: `OMNEE_ERROR_NOT_FINITE`, outside [0, 1]:
// `OMNEE_ERROR_OUT_OF_RANGE`), with its probability P(k).
omnee_status omnee_vertex_count_sample_f32(const struct omnee_vertex_count_f32 *count,
                                           float u,
                                           struct omnee_vertex_draw_f32 *draw,
                                           struct omnee_error *error);

// `omnee_vertex_count_sample_f32` in double precision.
omnee_status omnee_vertex_count_sample_f64(const struct omnee_vertex_count_f64 *count,
                                           double u,
                                           struct omnee_vertex_draw_f64 *draw,
                                           struct omnee_error *error);

// P(k) of the distribution: 0 for k outside [1, k_max].
omnee_status omnee_vertex_count_pmf_f32(const struct omnee_vertex_count_f32 *count,
                                        size_t k,
                                        float *probability,
                                        struct omnee_error *error);

// `omnee_vertex_count_pmf_f32` in double precision.
omnee_status omnee_vertex_count_pmf_f64(const struct omnee_vertex_count_f64 *count,
                                        size_t k,
                                        double *probability,
                                        struct omnee_error *error);

// Makes the connection from `x0` (light side) to `x2` (receiver side),
// restricted to deflections θ < `theta_max` ∈ (0, π] (π/2: forward
// scattering only, the ball with diameter x0x2; the smallest subnormal is
// allowed). Any finite, distinct end points are accepted whose distance is
// at most the precision's largest number (see SCALE above): s and the axis
// are computed in a power-of-two unit, so neither s² nor 1/s overflows.
//
// Errors: `OMNEE_ERROR_NOT_FINITE` (x0, x2, or a distance above the
// largest number: "x2 - x0"), `OMNEE_ERROR_DEGENERATE` (x0 == x2),
// `OMNEE_ERROR_OUT_OF_RANGE` (theta_max), `OMNEE_ERROR_NULL` (connection).
omnee_status omnee_connection_init_f32(struct omnee_connection_f32 *connection,
                                       struct omnee_vec3_f32 x0,
                                       struct omnee_vec3_f32 x2,
                                       float theta_max,
                                       struct omnee_error *error);

// `omnee_connection_init_f32` in double precision.
omnee_status omnee_connection_init_f64(struct omnee_connection_f64 *connection,
                                       struct omnee_vec3_f64 x0,
                                       struct omnee_vec3_f64 x2,
                                       double theta_max,
                                       struct omnee_error *error);

// OMNEE for a batch of connections: for every lane `i`,
// `omnee_connection_init_f32` of `connections` point `i` and `theta_max`,
// then `omnee_omnee_sample_f32` with `phase` and `(u0[i], u1[i], u2[i])`,
// bit for bit; a lane where either returns an error or `OMNEE_NONE` gets
// `valid = 0` and zeros. `count` receives the number of lanes with a
// vertex. Every phase function works (Henyey–Greenstein is vectorised,
// tables through their own sampler).
//
// Errors, checked before anything is written (the arrays are then left as
// they were, `count` is 0): `OMNEE_ERROR_NULL` (`phase`, `count`, or an
// array of a batch with `len` > 0, named like "x0.y", "u1", "valid"),
// `OMNEE_ERROR_UNINITIALISED` (`phase`), `OMNEE_ERROR_TABLE` (the three
// `len`s differ, or an output array overlaps another array),
// `OMNEE_ERROR_OUT_OF_RANGE` (`theta_max`). NaN or infinite end points or
// numbers are not errors: their lanes have no vertex.
//
// # Safety
// Each pointer in `connections`, `uniforms` and `samples` is NULL (allowed
// with `len` 0) or points to as many elements as its struct's `len`.
omnee_status omnee_omnee_sample_connections_f32(const struct omnee_phase_f32 *phase,
                                                struct omnee_connections_f32 connections,
                                                struct omnee_lane_uniforms_f32 uniforms,
                                                struct omnee_samples_f32 samples,
                                                size_t *count,
                                                struct omnee_error *error);

// `omnee_omnee_sample_connections_f32` in double precision.
//
// # Safety
// As for `omnee_omnee_sample_connections_f32`.
omnee_status omnee_omnee_sample_connections_f64(const struct omnee_phase_f64 *phase,
                                                struct omnee_connections_f64 connections,
                                                struct omnee_lane_uniforms_f64 uniforms,
                                                struct omnee_samples_f64 samples,
                                                size_t *count,
                                                struct omnee_error *error);

// The recommended MIS for a batch of connections: for every lane `i`,
// `omnee_connection_init_f32` of its end points, then `omnee_mis_sample_f32`
// with `phase`, `rays` and the six numbers `(u0[i], u1[i], u2[i])` of
// `uniforms` and `(u0[i], u1[i], u2[i])` of `companion_uniforms`, bit for
// bit: OMNEE's vertex into `samples`, the companion's into
// `companion_samples` (its `valid` is 1 only where it was drawn and lies
// behind the cone). `count` receives the number of vertices in both.
//
// Errors as for `omnee_omnee_sample_connections_f32`, and `rays`' own
// (`OMNEE_ERROR_NULL`, `OMNEE_ERROR_OUT_OF_RANGE`, `OMNEE_ERROR_DEGENERATE`
// as in `omnee_mis_sample_f32`); all five `len`s must agree.
//
// # Safety
// Each pointer in `connections`, `uniforms`, `companion_uniforms`,
// `samples` and `companion_samples` is NULL (allowed with `len` 0) or
// points to as many elements as its struct's `len`.
omnee_status omnee_mis_sample_connections_f32(const struct omnee_phase_f32 *phase,
                                              const struct omnee_rays_f32 *rays,
                                              struct omnee_connections_f32 connections,
                                              struct omnee_lane_uniforms_f32 uniforms,
                                              struct omnee_lane_uniforms_f32 companion_uniforms,
                                              struct omnee_samples_f32 samples,
                                              struct omnee_samples_f32 companion_samples,
                                              size_t *count,
                                              struct omnee_error *error);

// `omnee_mis_sample_connections_f32` in double precision.
//
// # Safety
// As for `omnee_mis_sample_connections_f32`.
omnee_status omnee_mis_sample_connections_f64(const struct omnee_phase_f64 *phase,
                                              const struct omnee_rays_f64 *rays,
                                              struct omnee_connections_f64 connections,
                                              struct omnee_lane_uniforms_f64 uniforms,
                                              struct omnee_lane_uniforms_f64 companion_uniforms,
                                              struct omnee_samples_f64 samples,
                                              struct omnee_samples_f64 companion_samples,
                                              size_t *count,
                                              struct omnee_error *error);

// Isotropic scattering, p = 1/(4π).
omnee_status omnee_phase_iso_f32(struct omnee_phase_f32 *phase,
                                 struct omnee_error *error);

// `omnee_phase_iso_f32` in double precision.
omnee_status omnee_phase_iso_f64(struct omnee_phase_f64 *phase,
                                 struct omnee_error *error);

// Henyey–Greenstein, p = (1 − g²)/(4π (1 + g² − 2g cos θ)^{3/2}),
// g ∈ (−1, 1) (`hg:G`).
omnee_status omnee_phase_hg_f32(struct omnee_phase_f32 *phase,
                                float g,
                                struct omnee_error *error);

// `omnee_phase_hg_f32` in double precision.
omnee_status omnee_phase_hg_f64(struct omnee_phase_f64 *phase,
                                double g,
                                struct omnee_error *error);

// Two-term Henyey–Greenstein, w·HG(g1) + (1 − w)·HG(g2), g1, g2 ∈ (−1, 1),
// w ∈ [0, 1] (`tthg:G1,G2,W`).
omnee_status omnee_phase_tthg_f32(struct omnee_phase_f32 *phase,
                                  float g1,
                                  float g2,
                                  float w,
                                  struct omnee_error *error);

// `omnee_phase_tthg_f32` in double precision.
omnee_status omnee_phase_tthg_f64(struct omnee_phase_f64 *phase,
                                  double g1,
                                  double g2,
                                  double w,
                                  struct omnee_error *error);

// Fournier–Forand with backscatter fraction ∈ (0, 0.5) and refractive
// index n ∈ [1.001, 1.5] (`ff:B,N`).
omnee_status omnee_phase_ff_f32(struct omnee_phase_f32 *phase,
                                float backscatter,
                                float n,
                                struct omnee_error *error);

// `omnee_phase_ff_f32` in double precision.
omnee_status omnee_phase_ff_f64(struct omnee_phase_f64 *phase,
                                double backscatter,
                                double n,
                                struct omnee_error *error);

// Draine: HG times (1 + α cos²θ), normalised, g ∈ (−1, 1),
// alpha ∈ [0, 1000] (`draine:G,ALPHA`).
omnee_status omnee_phase_draine_f32(struct omnee_phase_f32 *phase,
                                    float g,
                                    float alpha,
                                    struct omnee_error *error);

// `omnee_phase_draine_f32` in double precision.
omnee_status omnee_phase_draine_f64(struct omnee_phase_f64 *phase,
                                    double g,
                                    double alpha,
                                    struct omnee_error *error);

// Approximate Mie for water droplets of diameter_um ∈ (0, 50] micrometres
// (`mie:DIAMETER_UM`).
omnee_status omnee_phase_mie_f32(struct omnee_phase_f32 *phase,
                                 float diameter_um,
                                 struct omnee_error *error);

// `omnee_phase_mie_f32` in double precision.
omnee_status omnee_phase_mie_f64(struct omnee_phase_f64 *phase,
                                 double diameter_um,
                                 struct omnee_error *error);

// Rayleigh, p = 3/(16π) (1 + cos²θ) (`rayleigh`).
omnee_status omnee_phase_rayleigh_f32(struct omnee_phase_f32 *phase,
                                      struct omnee_error *error);

// `omnee_phase_rayleigh_f32` in double precision.
omnee_status omnee_phase_rayleigh_f64(struct omnee_phase_f64 *phase,
                                      struct omnee_error *error);

// A tabulated phase function over n ≥ 1 bins: `theta` holds the n + 1 bin
// edges (0 = θ_0 < … < θ_n = π), `values` the n unnormalised values
// (finite, ≥ 0, not all 0; constant per solid angle in each bin), and `cdf`
// receives the n + 1 entries of the cumulative distribution.
//
// The phase function refers to the three arrays: they must outlive it (and
// its copies) and stay unmodified. Lengths that disagree, misplaced edges,
// values all 0 or overlapping arrays: `OMNEE_ERROR_TABLE`. A NaN or
// infinite edge or value, or finite values whose sum weighted by their
// bins' solid angles is not finite in double precision (values near
// `DBL_MAX`): `OMNEE_ERROR_NOT_FINITE`, field "theta" or "values". A
// negative value: `OMNEE_ERROR_OUT_OF_RANGE`, field "values", with that
// value.
//
// # Safety
// Each array pointer is NULL (allowed with length 0) or points to as many
// elements as its length says.
omnee_status omnee_phase_table_f32(struct omnee_phase_f32 *phase,
                                   const float *theta,
                                   size_t theta_len,
                                   const float *values,
                                   size_t values_len,
                                   float *cdf,
                                   size_t cdf_len,
                                   struct omnee_error *error);

// `omnee_phase_table_f32` in double precision.
//
// # Safety
// As `omnee_phase_table_f32`.
omnee_status omnee_phase_table_f64(struct omnee_phase_f64 *phase,
                                   const double *theta,
                                   size_t theta_len,
                                   const double *values,
                                   size_t values_len,
                                   double *cdf,
                                   size_t cdf_len,
                                   struct omnee_error *error);

// A phase function (docs/math.md §7) from its spec string (NUL-terminated; surrounding
// whitespace ignored): `iso`, `hg:G`, `tthg:G1,G2,W`, `ff:B,N`,
// `draine:G,ALPHA`, `mie:DIAMETER_UM`, `rayleigh`, or `table:PATH`.
//
// For `table:PATH` the library, which does no I/O, returns
// `OMNEE_TABLE_SPEC` and, if `table_path` is not NULL, where PATH lies in
// `spec` (the phase function is not written); the caller reads the file and
// calls `omnee_phase_table_f32`. On every other outcome `*table_path` (if
// not NULL) is zeroed, `{0, 0}`.
// Errors: `OMNEE_ERROR_SYNTAX` (unknown name, wrong parameter count, not a
// number, not UTF-8), `OMNEE_ERROR_OUT_OF_RANGE` (a parameter).
//
// # Safety
// `spec` is NULL or a NUL-terminated string.
omnee_status omnee_phase_parse_f32(struct omnee_phase_f32 *phase,
                                   const char *spec,
                                   struct omnee_span *table_path,
                                   struct omnee_error *error);

// `omnee_phase_parse_f32` in double precision.
//
// # Safety
// As `omnee_phase_parse_f32`.
omnee_status omnee_phase_parse_f64(struct omnee_phase_f64 *phase,
                                   const char *spec,
                                   struct omnee_span *table_path,
                                   struct omnee_error *error);

// A deflection (docs/math.md §4) from θ ∈ [0, π] (clamped; NaN and ±∞ are errors): 1 ∓ cos θ from
// 2 sin²(θ/2) and 2 cos²(θ/2), accurate at both ends.
omnee_status omnee_deflection_from_theta_f32(float theta,
                                             struct omnee_deflection_f32 *deflection,
                                             struct omnee_error *error);

// `omnee_deflection_from_theta_f32` in double precision.
omnee_status omnee_deflection_from_theta_f64(double theta,
                                             struct omnee_deflection_f64 *deflection,
                                             struct omnee_error *error);

// A deflection from cos θ ∈ [−1, 1] (clamped; NaN and ±∞ are errors). Loses the
// digits of 1 ∓ cos θ near θ = 0 and π: prefer `omnee_deflection_between_*`
// when the directions are at hand.
omnee_status omnee_deflection_from_cos_f32(float cos_theta,
                                           struct omnee_deflection_f32 *deflection,
                                           struct omnee_error *error);

// `omnee_deflection_from_cos_f32` in double precision.
omnee_status omnee_deflection_from_cos_f64(double cos_theta,
                                           struct omnee_deflection_f64 *deflection,
                                           struct omnee_error *error);

// The deflection between two propagation directions ω1 (into the vertex)
// and ω2 (out of it), cos θ = ω1·ω2, from |ω1 − ω2| and |ω1 + ω2| (exact
// where 1 − ω1·ω2 is not). The directions are normalised here: any finite,
// non-zero length. Errors: `OMNEE_ERROR_NOT_FINITE` for a NaN or infinite
// component, `OMNEE_ERROR_DEGENERATE` for a zero direction (each naming
// "omega1" or "omega2").
omnee_status omnee_deflection_between_f32(struct omnee_vec3_f32 omega1,
                                          struct omnee_vec3_f32 omega2,
                                          struct omnee_deflection_f32 *deflection,
                                          struct omnee_error *error);

// `omnee_deflection_between_f32` in double precision.
omnee_status omnee_deflection_between_f64(struct omnee_vec3_f64 omega1,
                                          struct omnee_vec3_f64 omega2,
                                          struct omnee_deflection_f64 *deflection,
                                          struct omnee_error *error);

// p(θ) per steradian (∫ p dω = 1); also the sampling density of
// `omnee_phase_sample_f32` per solid angle.
omnee_status omnee_phase_eval_f32(const struct omnee_phase_f32 *phase,
                                  const struct omnee_deflection_f32 *deflection,
                                  float *value,
                                  struct omnee_error *error);

// `omnee_phase_eval_f32` in double precision.
omnee_status omnee_phase_eval_f64(const struct omnee_phase_f64 *phase,
                                  const struct omnee_deflection_f64 *deflection,
                                  double *value,
                                  struct omnee_error *error);

// P(Θ ≤ θ) = 2π ∫₀^θ p sin θ' dθ'.
omnee_status omnee_phase_cdf_f32(const struct omnee_phase_f32 *phase,
                                 const struct omnee_deflection_f32 *deflection,
                                 float *cdf,
                                 struct omnee_error *error);

// `omnee_phase_cdf_f32` in double precision.
omnee_status omnee_phase_cdf_f64(const struct omnee_phase_f64 *phase,
                                 const struct omnee_deflection_f64 *deflection,
                                 double *cdf,
                                 struct omnee_error *error);

// The uniform number u with `omnee_phase_sample_f32(u)` = the deflection
// (the CDF for inverse-CDF samplers); `OMNEE_NONE` for the mixtures (tthg,
// mie), whose sampler picks a lobe with u.
omnee_status omnee_phase_invert_f32(const struct omnee_phase_f32 *phase,
                                    const struct omnee_deflection_f32 *deflection,
                                    float *u,
                                    struct omnee_error *error);

// `omnee_phase_invert_f32` in double precision.
omnee_status omnee_phase_invert_f64(const struct omnee_phase_f64 *phase,
                                    const struct omnee_deflection_f64 *deflection,
                                    double *u,
                                    struct omnee_error *error);

// A deflection with solid-angle density `omnee_phase_eval_f32`, from a
// uniform number u (finite, clamped into [0, 1]; NaN and ±∞ are
// `OMNEE_ERROR_OUT_OF_RANGE`, as for the deflection constructors).
omnee_status omnee_phase_sample_f32(const struct omnee_phase_f32 *phase,
                                    float u,
                                    struct omnee_deflection_f32 *deflection,
                                    struct omnee_error *error);

// `omnee_phase_sample_f32` in double precision.
omnee_status omnee_phase_sample_f64(const struct omnee_phase_f64 *phase,
                                    double u,
                                    struct omnee_deflection_f64 *deflection,
                                    struct omnee_error *error);

// The mean cosine ⟨cos θ⟩ (the "g" of the phase function).
omnee_status omnee_phase_mean_cosine_f32(const struct omnee_phase_f32 *phase,
                                         float *mean_cosine,
                                         struct omnee_error *error);

// `omnee_phase_mean_cosine_f32` in double precision.
omnee_status omnee_phase_mean_cosine_f64(const struct omnee_phase_f64 *phase,
                                         double *mean_cosine,
                                         struct omnee_error *error);

// The point-to-point problem (docs/math.md §1, §5): a unit-intensity point
// light at x0, a point receiver at x2, an infinite homogeneous medium with
// σs = `sigma_s` ≥ 0 and σa = `sigma_a` ≥ 0 (1/m), the integrand restricted
// to θ < θmax of `connection`:
// I = ∫ σs p(θ) e^{−σt (d1 + d2)} [cos θ2] / (d1² d2²) dx1.
// `receiver_normal` (NULL: none) adds the one-sided receiver cosine
// cos θ2 = max(0, n·(x1 − x2)/d2) about that normal, normalised here: any
// finite, non-zero length (components from 1e-45 or 4.9e-324 up to the
// largest number); `OMNEE_ERROR_NOT_FINITE` for a NaN or infinite
// component, `OMNEE_ERROR_DEGENERATE` for the zero vector.
omnee_status omnee_problem_init_f32(struct omnee_problem_f32 *problem,
                                    const struct omnee_connection_f32 *connection,
                                    float sigma_s,
                                    float sigma_a,
                                    const struct omnee_vec3_f32 *receiver_normal,
                                    struct omnee_error *error);

// `omnee_problem_init_f32` in double precision.
omnee_status omnee_problem_init_f64(struct omnee_problem_f64 *problem,
                                    const struct omnee_connection_f64 *connection,
                                    double sigma_s,
                                    double sigma_a,
                                    const struct omnee_vec3_f64 *receiver_normal,
                                    struct omnee_error *error);

// The factors no technique samples:
// f_c(x1) = σs e^{−σt (d1 + d2)} [max(0, n·(x1 − x2)/d2)].
omnee_status omnee_problem_f_c_f32(const struct omnee_problem_f32 *problem,
                                   struct omnee_vec3_f32 x1,
                                   float *f_c,
                                   struct omnee_error *error);

// `omnee_problem_f_c_f32` in double precision.
omnee_status omnee_problem_f_c_f64(const struct omnee_problem_f64 *problem,
                                   struct omnee_vec3_f64 x1,
                                   double *f_c,
                                   struct omnee_error *error);

// One estimate of the problem's integral from a sample of any technique:
// f_c(x1) · weight (0 for weight 0), rounded to the precision (0 where the
// product underflows: see SCALE above).
omnee_status omnee_problem_estimate_f32(const struct omnee_problem_f32 *problem,
                                        const struct omnee_sample_f32 *sample,
                                        float *estimate,
                                        struct omnee_error *error);

// `omnee_problem_estimate_f32` in double precision.
omnee_status omnee_problem_estimate_f64(const struct omnee_problem_f64 *problem,
                                        const struct omnee_sample_f64 *sample,
                                        double *estimate,
                                        struct omnee_error *error);

// The problem's integral I by adaptive Gauss–Kronrod quadrature in double
// precision (relative accuracy about 1e-9 for smooth phase functions), with
// the phase function `phase` (double precision, whatever the problem's).
// Takes milliseconds, at most 0.2 s for a receiver normal and θmax = π: a
// reference, not a per-sample call. Its cost is bounded: a quadrature that
// spends its budget of evaluations (about a second; a normal at right
// angles to x2 − x0, where the receiver's horizon passes through the axis,
// is the known case) before meeting its tolerance returns
// `OMNEE_ERROR_NOT_CONVERGED` (field "reference") and `*reference` = 0.
// The quadrature runs in the connection's unit (see SCALE above): at any
// distance s, subnormal included, the problem scaled by a power of two λ
// (σ over λ) has the reference over λ², rounded once; an I beyond
// double's range (at s = 1e-320, σs = 0.5 and θmax = π it is about
// 1e320) is `OMNEE_ERROR_NOT_FINITE` (field "reference"), one below it 0.
omnee_status omnee_problem_reference_f32(const struct omnee_problem_f32 *problem,
                                         const struct omnee_phase_f64 *phase,
                                         double *reference,
                                         struct omnee_error *error);

// `omnee_problem_reference_f32` for a double-precision problem.
omnee_status omnee_problem_reference_f64(const struct omnee_problem_f64 *problem,
                                         const struct omnee_phase_f64 *phase,
                                         double *reference,
                                         struct omnee_error *error);

// Copies an error record's message into `buffer` (`capacity` bytes, at
// least 1) as a NUL-terminated string, cut at a character boundary if it does
// not fit, and stores the message's full length in `*length` (if not NULL),
// as `snprintf` does. A record never written by a failing call (all zero)
// has the empty message.
//
// Returns `OMNEE_OK`, `OMNEE_ERROR_NULL` for a NULL `error` or `buffer`, or
// `OMNEE_ERROR_TABLE` for `capacity` 0.
//
// # Safety
// `buffer` is NULL or points to `capacity` writable bytes that do not
// overlap `*error` or `*length`.
omnee_status omnee_error_message(const struct omnee_error *error,
                                 char *buffer,
                                 size_t capacity,
                                 size_t *length);

// OMNEE (docs/math.md §3): θ from the phase function by `u[0]` (no sample if θ ≥ θmax),
// β/θ = `u[1]`, φ = 2π `u[2]`; x1 on the circumcircle arc of constant θ through
// x0 and x2. weight = θ/(s sin θ) (s = |x2 − x0|), pdf =
// p(θ) (sin θ/θ) s/(d1² d2²). `u` points to 3 finite numbers (clamped into
// [0, 1]). `OMNEE_NONE` when they map to no vertex that contributes.
//
// # Safety
// `u` is NULL or points to 3 floats.
omnee_status omnee_omnee_sample_f32(const struct omnee_connection_f32 *connection,
                                    const struct omnee_phase_f32 *phase,
                                    const float *u,
                                    struct omnee_sample_f32 *sample_out,
                                    struct omnee_error *error);

// `omnee_omnee_sample_f32` in double precision.
//
// # Safety
// `u` is NULL or points to 3 doubles.
omnee_status omnee_omnee_sample_f64(const struct omnee_connection_f64 *connection,
                                    const struct omnee_phase_f64 *phase,
                                    const double *u,
                                    struct omnee_sample_f64 *sample_out,
                                    struct omnee_error *error);

// The volume density (1/m³) with which `omnee_omnee_sample_f32` places x1:
// p(θ) (sin θ/θ) s/(d1² d2²), 0 for θ ≥ θmax and at the end points.
omnee_status omnee_omnee_pdf_f32(const struct omnee_connection_f32 *connection,
                                 const struct omnee_phase_f32 *phase,
                                 struct omnee_vec3_f32 x1,
                                 float *pdf_out,
                                 struct omnee_error *error);

// `omnee_omnee_pdf_f32` in double precision.
omnee_status omnee_omnee_pdf_f64(const struct omnee_connection_f64 *connection,
                                 const struct omnee_phase_f64 *phase,
                                 struct omnee_vec3_f64 x1,
                                 double *pdf_out,
                                 struct omnee_error *error);

// The 3 uniform numbers that `omnee_omnee_sample_f32` maps to x1:
// (cdf(θ), β/θ, φ/2π). `OMNEE_NONE` for θ ≥ θmax or a mixture phase
// function (not invertible).
//
// # Safety
// `u` is NULL or points to 3 writable floats.
omnee_status omnee_omnee_invert_f32(const struct omnee_connection_f32 *connection,
                                    const struct omnee_phase_f32 *phase,
                                    struct omnee_vec3_f32 x1,
                                    float *u,
                                    struct omnee_error *error);

// `omnee_omnee_invert_f32` in double precision.
//
// # Safety
// `u` is NULL or points to 3 writable doubles.
omnee_status omnee_omnee_invert_f64(const struct omnee_connection_f64 *connection,
                                    const struct omnee_phase_f64 *phase,
                                    struct omnee_vec3_f64 x1,
                                    double *u,
                                    struct omnee_error *error);

// Equiangular sampling (Kulla & Fajardo 2012; docs/math.md §8): a ray direction from x2 by
// `u[0]`, `u[1]` (`rays`), then the distance along it inside the medium with
// density ∝ 1/d1². weight = p(θ)/(pdf_ω · c) (0 for θ ≥ θmax).
//
// # Safety
// `u` is NULL or points to 3 floats.
omnee_status omnee_equiangular_sample_f32(const struct omnee_connection_f32 *connection,
                                          const struct omnee_phase_f32 *phase,
                                          const struct omnee_rays_f32 *rays,
                                          const float *u,
                                          struct omnee_sample_f32 *sample_out,
                                          struct omnee_error *error);

// `omnee_equiangular_sample_f32` in double precision.
//
// # Safety
// `u` is NULL or points to 3 doubles.
omnee_status omnee_equiangular_sample_f64(const struct omnee_connection_f64 *connection,
                                          const struct omnee_phase_f64 *phase,
                                          const struct omnee_rays_f64 *rays,
                                          const double *u,
                                          struct omnee_sample_f64 *sample_out,
                                          struct omnee_error *error);

// The volume density of `omnee_equiangular_sample_f32` at x1:
// pdf_ω(ω) · c/(d1² d2²) inside the medium segment, else 0.
omnee_status omnee_equiangular_pdf_f32(const struct omnee_connection_f32 *connection,
                                       const struct omnee_phase_f32 *phase,
                                       const struct omnee_rays_f32 *rays,
                                       struct omnee_vec3_f32 x1,
                                       float *pdf_out,
                                       struct omnee_error *error);

// `omnee_equiangular_pdf_f32` in double precision.
omnee_status omnee_equiangular_pdf_f64(const struct omnee_connection_f64 *connection,
                                       const struct omnee_phase_f64 *phase,
                                       const struct omnee_rays_f64 *rays,
                                       struct omnee_vec3_f64 x1,
                                       double *pdf_out,
                                       struct omnee_error *error);

// The 3 uniform numbers that `omnee_equiangular_sample_f32` maps to x1
// (`OMNEE_NONE` below a cosine's horizon or off the medium).
//
// # Safety
// `u` is NULL or points to 3 writable floats.
omnee_status omnee_equiangular_invert_f32(const struct omnee_connection_f32 *connection,
                                          const struct omnee_phase_f32 *phase,
                                          const struct omnee_rays_f32 *rays,
                                          struct omnee_vec3_f32 x1,
                                          float *u,
                                          struct omnee_error *error);

// `omnee_equiangular_invert_f32` in double precision.
//
// # Safety
// `u` is NULL or points to 3 writable doubles.
omnee_status omnee_equiangular_invert_f64(const struct omnee_connection_f64 *connection,
                                          const struct omnee_phase_f64 *phase,
                                          const struct omnee_rays_f64 *rays,
                                          struct omnee_vec3_f64 x1,
                                          double *u,
                                          struct omnee_error *error);

// Distance sampling (docs/math.md §9): a ray direction from x2 by `u[0]`, `u[1]`, then the
// free-flight distance with density ∝ σ e^{−σt} (σ = `sigma` ≥ 0, usually
// the medium's σt), truncated to the medium segment.
//
// # Safety
// `u` is NULL or points to 3 floats.
omnee_status omnee_distance_sample_f32(const struct omnee_connection_f32 *connection,
                                       const struct omnee_phase_f32 *phase,
                                       const struct omnee_rays_f32 *rays,
                                       float sigma,
                                       const float *u,
                                       struct omnee_sample_f32 *sample_out,
                                       struct omnee_error *error);

// `omnee_distance_sample_f32` in double precision.
//
// # Safety
// `u` is NULL or points to 3 doubles.
omnee_status omnee_distance_sample_f64(const struct omnee_connection_f64 *connection,
                                       const struct omnee_phase_f64 *phase,
                                       const struct omnee_rays_f64 *rays,
                                       double sigma,
                                       const double *u,
                                       struct omnee_sample_f64 *sample_out,
                                       struct omnee_error *error);

// The volume density of `omnee_distance_sample_f32` at x1.
omnee_status omnee_distance_pdf_f32(const struct omnee_connection_f32 *connection,
                                    const struct omnee_phase_f32 *phase,
                                    const struct omnee_rays_f32 *rays,
                                    float sigma,
                                    struct omnee_vec3_f32 x1,
                                    float *pdf_out,
                                    struct omnee_error *error);

// `omnee_distance_pdf_f32` in double precision.
omnee_status omnee_distance_pdf_f64(const struct omnee_connection_f64 *connection,
                                    const struct omnee_phase_f64 *phase,
                                    const struct omnee_rays_f64 *rays,
                                    double sigma,
                                    struct omnee_vec3_f64 x1,
                                    double *pdf_out,
                                    struct omnee_error *error);

// The 3 uniform numbers that `omnee_distance_sample_f32` maps to x1.
//
// # Safety
// `u` is NULL or points to 3 writable floats.
omnee_status omnee_distance_invert_f32(const struct omnee_connection_f32 *connection,
                                       const struct omnee_phase_f32 *phase,
                                       const struct omnee_rays_f32 *rays,
                                       float sigma,
                                       struct omnee_vec3_f32 x1,
                                       float *u,
                                       struct omnee_error *error);

// `omnee_distance_invert_f32` in double precision.
//
// # Safety
// `u` is NULL or points to 3 writable doubles.
omnee_status omnee_distance_invert_f64(const struct omnee_connection_f64 *connection,
                                       const struct omnee_phase_f64 *phase,
                                       const struct omnee_rays_f64 *rays,
                                       double sigma,
                                       struct omnee_vec3_f64 x1,
                                       double *u,
                                       struct omnee_error *error);

// The recommended MIS of the core (`OmneeMis::recommended`, docs/math.md §10): OMNEE's vertex
// always (from `u[0..3]`) and, when `u[3]` < c (c = 0.05), the equiangular
// companion's (from `u[3]/c`, `u[4]`, `u[5]`) if it lies behind the cone
// θ ≥ 3π/4; balance heuristic behind the cone, OMNEE alone in front of
// it. `u` points to 6 finite numbers. Sum f_c · weight over the present
// vertices for one estimate. `OMNEE_NONE` when neither is present.
//
// # Safety
// `u` is NULL or points to 6 floats.
omnee_status omnee_mis_sample_f32(const struct omnee_connection_f32 *connection,
                                  const struct omnee_phase_f32 *phase,
                                  const struct omnee_rays_f32 *rays,
                                  const float *u,
                                  struct omnee_draw_f32 *draw,
                                  struct omnee_error *error);

// `omnee_mis_sample_f32` in double precision.
//
// # Safety
// `u` is NULL or points to 6 doubles.
omnee_status omnee_mis_sample_f64(const struct omnee_connection_f64 *connection,
                                  const struct omnee_phase_f64 *phase,
                                  const struct omnee_rays_f64 *rays,
                                  const double *u,
                                  struct omnee_draw_f64 *draw,
                                  struct omnee_error *error);

// The combined density of the MIS vertices at x1: p_OMNEE + c p_companion
// behind the cone, p_OMNEE in front of it.
omnee_status omnee_mis_pdf_f32(const struct omnee_connection_f32 *connection,
                               const struct omnee_phase_f32 *phase,
                               const struct omnee_rays_f32 *rays,
                               struct omnee_vec3_f32 x1,
                               float *pdf_out,
                               struct omnee_error *error);

// `omnee_mis_pdf_f32` in double precision.
omnee_status omnee_mis_pdf_f64(const struct omnee_connection_f64 *connection,
                               const struct omnee_phase_f64 *phase,
                               const struct omnee_rays_f64 *rays,
                               struct omnee_vec3_f64 x1,
                               double *pdf_out,
                               struct omnee_error *error);

// 6 uniform numbers with which `omnee_mis_sample_f32` returns x1 (up to
// rounding) as `vertices[vertex]`: vertex 0 (OMNEE's) takes OMNEE's inverse
// and leaves the companion undrawn; vertex 1 (the companion's) takes the
// equiangular inverse scaled into `u[3]` < c. `OMNEE_NONE` when x1 cannot be
// that vertex (outside θmax, a mixture phase function, a companion vertex
// in front of the cone).
//
// # Safety
// `u` is NULL or points to 6 writable floats.
omnee_status omnee_mis_invert_f32(const struct omnee_connection_f32 *connection,
                                  const struct omnee_phase_f32 *phase,
                                  const struct omnee_rays_f32 *rays,
                                  uint32_t vertex,
                                  struct omnee_vec3_f32 x1,
                                  float *u,
                                  struct omnee_error *error);

// `omnee_mis_invert_f32` in double precision.
//
// # Safety
// `u` is NULL or points to 6 writable doubles.
omnee_status omnee_mis_invert_f64(const struct omnee_connection_f64 *connection,
                                  const struct omnee_phase_f64 *phase,
                                  const struct omnee_rays_f64 *rays,
                                  uint32_t vertex,
                                  struct omnee_vec3_f64 x1,
                                  double *u,
                                  struct omnee_error *error);

// OMNEE for every entry i of a batch: x1_i, its pdf and weight from
// (u0_i, u1_i, u2_i), by the scalar sampler's formulas written
// branch-free with polynomial sin, cos and atan (results agree with
// `omnee_omnee_sample_f32` to a few ulps; the library's tests measure it).
// An entry without a sample gets pdf = weight = 0 and x1 = x0.
// `count` receives the number of entries with a sample.
//
// The phase function must be Henyey–Greenstein (else
// `OMNEE_ERROR_UNSUPPORTED`); `uniforms.len` must equal `vertices.len`
// (else `OMNEE_ERROR_TABLE`), the uniform numbers must be finite (else
// `OMNEE_ERROR_NOT_FINITE`, naming the array), no two of the eight arrays
// may overlap, inputs included (else `OMNEE_ERROR_TABLE`), and `count`
// must not be NULL (else `OMNEE_ERROR_NULL`). Every check comes before the
// first write: on an error the vertex arrays are left as they were (and
// `*count`, if `count` is not NULL, is 0).
//
// # Safety
// Each pointer in `uniforms` and `vertices` is NULL (allowed with length
// 0) or points to as many floats as the struct's `len`.
omnee_status omnee_omnee_sample_batch_f32(const struct omnee_connection_f32 *connection,
                                          const struct omnee_phase_f32 *phase,
                                          struct omnee_uniforms_f32 uniforms,
                                          struct omnee_vertices_f32 vertices,
                                          size_t *count,
                                          struct omnee_error *error);

#ifdef __cplusplus
}  // extern "C"
#endif  // __cplusplus

#endif  /* OMNEE_H */

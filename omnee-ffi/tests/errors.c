/* The C API's error paths: NULL pointers, NaN and infinities, x0 == x2,
 * out-of-range parameters, lengths that disagree, overlapping arrays, objects
 * that no constructor made. Each must give its status, name the field, carry
 * the Rust API's message text, zero the outputs, and never crash (CI runs
 * this under AddressSanitizer and UndefinedBehaviorSanitizer). Prints
 * "errors: N passed, M failed" and exits non-zero on a failure. */
#include "omnee.h"

#include <float.h>
#include <math.h>
#include <stdio.h>
#include <string.h>

static int passed, failed;

static void check(int ok, const char *what, int line) {
  if (ok) {
    passed++;
  } else {
    failed++;
    printf("FAIL line %d: %s\n", line, what);
  }
}

#define CHECK(cond) check((cond) != 0, #cond, __LINE__)

/* The call returned `want`, and the record names `field` with `message`. */
static void expect_error(omnee_status got, omnee_status want, const omnee_error *e,
                         const char *field, const char *message, int line) {
  int ok = got == want && e->status == (int32_t)want && strcmp(e->field, field) == 0 &&
           strcmp(e->message, message) == 0;
  check(ok, message, line);
  if (!ok) {
    printf("  got status %d (record %d), field \"%s\", message \"%s\"\n", (int)got,
           (int)e->status, e->field, e->message);
  }
}

#define EXPECT(call, want, field, message)                    \
  do {                                                        \
    memset(&e, 0, sizeof e);                                  \
    expect_error((call), (want), &e, (field), (message), __LINE__); \
  } while (0)

static int zero_sample(const omnee_sample_f32 *s) {
  return s->x1.x == 0.0f && s->x1.y == 0.0f && s->x1.z == 0.0f && s->pdf == 0.0f &&
         s->weight == 0.0f;
}

int main(void) {
  omnee_error e;
  omnee_connection_f32 c, bad_c;
  omnee_connection_f64 c64;
  omnee_phase_f32 hg, mix, zeroed_phase, failed_phase;
  omnee_phase_f64 hg64;
  omnee_problem_f32 problem, still_problem;
  omnee_sample_f32 s;
  omnee_deflection_f32 d;
  omnee_rays_f32 rays;
  omnee_span span;
  float value, u[3] = {0.5f, 0.5f, 0.5f}, u6[6] = {0.5f, 0.5f, 0.5f, 0.01f, 0.5f, 0.5f};
  float inv[6];
  const omnee_vec3_f32 x0 = {0.0f, 0.0f, 1.0f}, x2 = {0.0f, 0.0f, 0.0f};
  const omnee_vec3_f32 nan3 = {NAN, 0.0f, 0.0f}, inf3 = {0.0f, INFINITY, 0.0f};
  const omnee_vec3_f64 a64 = {1.0, 2.0, 3.0};
  char buffer[8];
  size_t length;

  /* Connections: x0 == x2, NaN, infinity, theta_max, NULL. */
  EXPECT(omnee_connection_init_f32(&bad_c, x0, x0, 1.0f, &e), OMNEE_ERROR_DEGENERATE, "x2",
         "x2: coincides with x0 (s = 0)");
  EXPECT(omnee_connection_init_f32(&bad_c, nan3, x2, 1.0f, &e), OMNEE_ERROR_NOT_FINITE, "x0",
         "x0 has a non-finite component");
  EXPECT(omnee_connection_init_f32(&bad_c, x0, inf3, 1.0f, &e), OMNEE_ERROR_NOT_FINITE, "x2",
         "x2 has a non-finite component");
  EXPECT(omnee_connection_init_f32(&bad_c, x0, x2, 0.0f, &e), OMNEE_ERROR_OUT_OF_RANGE,
         "theta_max", "theta_max = 0 is out of range; allowed: (0, pi]");
  CHECK(e.value == 0.0);
  EXPECT(omnee_connection_init_f32(&bad_c, x0, x2, NAN, &e), OMNEE_ERROR_OUT_OF_RANGE,
         "theta_max", "theta_max = NaN is out of range; allowed: (0, pi]");
  EXPECT(omnee_connection_init_f32(&bad_c, x0, x2, 4.0f, &e), OMNEE_ERROR_OUT_OF_RANGE,
         "theta_max", "theta_max = 4 is out of range; allowed: (0, pi]");
  CHECK(e.value == 4.0);
  EXPECT(omnee_connection_init_f32(NULL, x0, x2, 1.0f, &e), OMNEE_ERROR_NULL, "connection",
         "connection: null pointer");
  EXPECT(omnee_connection_init_f64(&c64, a64, a64, 1.0, &e), OMNEE_ERROR_DEGENERATE, "x2",
         "x2: coincides with x0 (s = 0)");
  /* The error record is optional. */
  CHECK(omnee_connection_init_f32(&bad_c, x0, x0, 1.0f, NULL) == OMNEE_ERROR_DEGENERATE);
  CHECK(omnee_connection_init_f32(&c, x0, x2, 1.5707964f, &e) == OMNEE_OK);

  /* Phase functions out of range, by parameters and by spec. */
  EXPECT(omnee_phase_hg_f32(&failed_phase, 1.0f, &e), OMNEE_ERROR_OUT_OF_RANGE, "g",
         "g = 1 is out of range; allowed: (-1, 1)");
  CHECK(e.value == 1.0);
  EXPECT(omnee_phase_hg_f32(&failed_phase, -INFINITY, &e), OMNEE_ERROR_OUT_OF_RANGE, "g",
         "g = -inf is out of range; allowed: (-1, 1)");
  EXPECT(omnee_phase_hg_f64(&hg64, -1.0, &e), OMNEE_ERROR_OUT_OF_RANGE, "g",
         "g = -1 is out of range; allowed: (-1, 1)");
  EXPECT(omnee_phase_tthg_f32(&failed_phase, 0.5f, 0.25f, 2.0f, &e), OMNEE_ERROR_OUT_OF_RANGE,
         "w", "w = 2 is out of range; allowed: [0, 1]");
  EXPECT(omnee_phase_ff_f64(&hg64, 0.6, 1.1, &e), OMNEE_ERROR_OUT_OF_RANGE, "backscatter",
         "backscatter = 0.6 is out of range; allowed: (0, 0.5)");
  EXPECT(omnee_phase_draine_f32(&failed_phase, 0.5f, -1.0f, &e), OMNEE_ERROR_OUT_OF_RANGE,
         "alpha", "alpha = -1 is out of range; allowed: [0, 1000]");
  EXPECT(omnee_phase_mie_f32(&failed_phase, 60.0f, &e), OMNEE_ERROR_OUT_OF_RANGE,
         "diameter_um", "diameter_um = 60 is out of range; allowed: (0, 50]");
  EXPECT(omnee_phase_iso_f32(NULL, &e), OMNEE_ERROR_NULL, "phase", "phase: null pointer");
  EXPECT(omnee_phase_parse_f32(&failed_phase, "henyey:0.5", NULL, &e), OMNEE_ERROR_SYNTAX,
         "phase",
         "syntax error in phase: unknown phase function; expected iso, hg, tthg, ff, draine, "
         "mie, rayleigh or table");
  EXPECT(omnee_phase_parse_f32(&failed_phase, "hg:abc", NULL, &e), OMNEE_ERROR_SYNTAX, "g",
         "syntax error in g: not a number");
  EXPECT(omnee_phase_parse_f32(&failed_phase, "tthg:0.9,0.1", NULL, &e), OMNEE_ERROR_SYNTAX,
         "tthg", "syntax error in tthg: expected tthg:G1,G2,W");
  EXPECT(omnee_phase_parse_f32(&failed_phase, "hg:1.5", NULL, &e), OMNEE_ERROR_OUT_OF_RANGE,
         "g", "g = 1.5 is out of range; allowed: (-1, 1)");
  EXPECT(omnee_phase_parse_f32(&failed_phase, "\xff\xfe", NULL, &e), OMNEE_ERROR_SYNTAX, "spec",
         "syntax error in spec: not valid UTF-8");
  EXPECT(omnee_phase_parse_f32(&failed_phase, NULL, NULL, &e), OMNEE_ERROR_NULL, "spec",
         "spec: null pointer");
  {
    const char *spec = " table: data/petzold.csv ";
    CHECK(omnee_phase_parse_f32(&failed_phase, spec, &span, &e) == OMNEE_TABLE_SPEC);
    CHECK(span.length == strlen("data/petzold.csv") &&
          strncmp(spec + span.offset, "data/petzold.csv", span.length) == 0);
  }

  /* Tables: lengths that disagree, NULL arrays, misplaced edges, overlap. */
  {
    float theta[4] = {0.0f, 0.5f, 1.5f, 3.14159265f}, values[3] = {4.0f, 2.0f, 1.0f};
    float cdf[4], short_cdf[3], shared[7] = {0.0f, 0.5f, 1.5f, 3.14159265f, 0.0f, 0.0f, 0.0f};
    float nan_values[3] = {1.0f, NAN, 1.0f}, bad_theta[4] = {0.0f, 0.5f, 1.5f, 3.0f};
    omnee_phase_f32 table;
    EXPECT(omnee_phase_table_f32(&table, theta, 4, values, 2, cdf, 4, &e), OMNEE_ERROR_TABLE,
           "theta", "table theta: needs exactly values.len() + 1 bin edges");
    EXPECT(omnee_phase_table_f32(&table, theta, 4, values, 3, short_cdf, 3, &e),
           OMNEE_ERROR_TABLE, "cdf", "table cdf: buffer needs exactly values.len() + 1 entries");
    EXPECT(omnee_phase_table_f32(&table, theta, 4, NULL, 3, cdf, 4, &e), OMNEE_ERROR_NULL,
           "values", "values: null pointer");
    EXPECT(omnee_phase_table_f32(&table, theta, 1, NULL, 0, cdf, 1, &e), OMNEE_ERROR_TABLE,
           "values", "table values: needs at least one bin");
    EXPECT(omnee_phase_table_f32(&table, bad_theta, 4, values, 3, cdf, 4, &e),
           OMNEE_ERROR_TABLE, "theta", "table theta: last edge must be pi");
    EXPECT(omnee_phase_table_f32(&table, theta, 4, nan_values, 3, cdf, 4, &e),
           OMNEE_ERROR_NOT_FINITE, "values", "values has a non-finite component");
    EXPECT(omnee_phase_table_f32(&table, shared, 4, values, 3, shared + 3, 4, &e),
           OMNEE_ERROR_TABLE, "cdf", "table cdf: overlaps theta or values");
    CHECK(omnee_phase_table_f32(&table, theta, 4, values, 3, cdf, 4, &e) == OMNEE_OK);
    CHECK(cdf[0] == 0.0f && cdf[3] == 1.0f);
  }
  /* Tables: non-finite input is not a shape error. Finite values whose
     weighted sum overflows double precision are not finite in sum; in
     single precision the sum is taken in double and the table is fine. A
     negative value is out of range, with its value. */
  {
    double theta[3] = {0.0, 1.0, 3.14159265358979323846}, huge[2] = {DBL_MAX, DBL_MAX};
    double inf_theta[3] = {0.0, INFINITY, 3.14159265358979323846}, negative[2] = {1.0, -2.0};
    double cdf[3];
    float theta32[3] = {0.0f, 1.0f, 3.14159265f}, huge32[2] = {FLT_MAX, FLT_MAX}, cdf32[3];
    omnee_phase_f64 table;
    omnee_phase_f32 table32;
    EXPECT(omnee_phase_table_f64(&table, theta, 3, huge, 2, cdf, 3, &e), OMNEE_ERROR_NOT_FINITE,
           "values",
           "values have a sum, weighted by their bins' solid angles, that is not finite");
    EXPECT(omnee_phase_table_f64(&table, inf_theta, 3, negative, 2, cdf, 3, &e),
           OMNEE_ERROR_NOT_FINITE, "theta", "theta has a non-finite component");
    EXPECT(omnee_phase_table_f64(&table, theta, 3, negative, 2, cdf, 3, &e),
           OMNEE_ERROR_OUT_OF_RANGE, "values", "values = -2 is out of range; allowed: [0, inf)");
    CHECK(e.value == -2.0);
    CHECK(omnee_phase_table_f32(&table32, theta32, 3, huge32, 2, cdf32, 3, &e) == OMNEE_OK);
    CHECK(cdf32[0] == 0.0f && cdf32[2] == 1.0f);
  }

  /* Objects that no constructor made: zeroed, failed, the other precision. */
  CHECK(omnee_phase_hg_f32(&hg, 0.875f, &e) == OMNEE_OK);
  CHECK(omnee_phase_tthg_f32(&mix, 0.875f, -0.5f, 0.75f, &e) == OMNEE_OK);
  CHECK(omnee_phase_hg_f64(&hg64, 0.875, &e) == OMNEE_OK);
  CHECK(omnee_deflection_from_theta_f32(0.5f, &d, &e) == OMNEE_OK);
  memset(&zeroed_phase, 0, sizeof zeroed_phase);
  EXPECT(omnee_phase_eval_f32(&zeroed_phase, &d, &value, &e), OMNEE_ERROR_UNINITIALISED, "phase",
         "phase: not made by its constructor (zeroed, failed, the other precision, or changed "
         "since)");
  CHECK(omnee_phase_hg_f32(&failed_phase, 2.0f, NULL) == OMNEE_ERROR_OUT_OF_RANGE);
  CHECK(omnee_phase_eval_f32(&failed_phase, &d, &value, NULL) == OMNEE_ERROR_UNINITIALISED);
  CHECK(omnee_phase_eval_f32((const omnee_phase_f32 *)(const void *)&hg64, &d, &value, NULL) ==
        OMNEE_ERROR_UNINITIALISED);
  CHECK(omnee_omnee_sample_f32((const omnee_connection_f32 *)(const void *)&hg, &hg, u, &s,
                               NULL) == OMNEE_ERROR_UNINITIALISED);
  /* A copy is as good as the original. */
  {
    omnee_phase_f32 copy = hg;
    CHECK(omnee_phase_eval_f32(&copy, &d, &value, &e) == OMNEE_OK && value > 0.0f);
  }

  /* Deflections and phase evaluation. */
  EXPECT(omnee_deflection_from_theta_f32(NAN, &d, &e), OMNEE_ERROR_OUT_OF_RANGE, "theta",
         "theta = NaN is out of range; allowed: [0, pi]");
  EXPECT(omnee_deflection_from_cos_f32(INFINITY, &d, &e), OMNEE_ERROR_OUT_OF_RANGE, "cos_theta",
         "cos_theta = inf is out of range; allowed: [-1, 1]");
  {
    omnee_deflection_f32 bad = {4.0f, 1.0f, 1.0f};
    EXPECT(omnee_phase_eval_f32(&hg, &bad, &value, &e), OMNEE_ERROR_OUT_OF_RANGE, "theta",
           "theta = 4 is out of range; allowed: [0, pi]");
    CHECK(value == 0.0f);
  }
  EXPECT(omnee_phase_eval_f32(&hg, NULL, &value, &e), OMNEE_ERROR_NULL, "deflection",
         "deflection: null pointer");
  EXPECT(omnee_phase_sample_f32(&hg, NAN, &d, &e), OMNEE_ERROR_OUT_OF_RANGE, "u",
         "u = NaN is out of range; allowed: finite, clamped to [0, 1]");
  CHECK(omnee_deflection_from_theta_f32(0.5f, &d, &e) == OMNEE_OK);
  CHECK(omnee_phase_invert_f32(&mix, &d, &value, &e) == OMNEE_NONE && value == 0.0f);

  /* Sampling: NULL, NaN, infinities, no sample; outputs zeroed. */
  EXPECT(omnee_omnee_sample_f32(&c, &hg, NULL, &s, &e), OMNEE_ERROR_NULL, "u",
         "u: null pointer");
  EXPECT(omnee_omnee_sample_f32(NULL, &hg, u, &s, &e), OMNEE_ERROR_NULL, "connection",
         "connection: null pointer");
  EXPECT(omnee_omnee_sample_f32(&c, &hg, u, NULL, &e), OMNEE_ERROR_NULL, "sample",
         "sample: null pointer");
  {
    float bad_u[3] = {0.5f, NAN, 0.5f};
    memset(&s, 0x7f, sizeof s);
    EXPECT(omnee_omnee_sample_f32(&c, &hg, bad_u, &s, &e), OMNEE_ERROR_NOT_FINITE, "u",
           "u has a non-finite component");
    CHECK(zero_sample(&s));
    memset(&rays, 0, sizeof rays); /* all zero: sphere, everywhere */
    bad_u[1] = -INFINITY;
    EXPECT(omnee_equiangular_sample_f32(&c, &hg, &rays, bad_u, &s, &e), OMNEE_ERROR_NOT_FINITE,
           "u", "u has a non-finite component");
    EXPECT(omnee_equiangular_sample_f32(&c, &hg, NULL, u, &s, &e), OMNEE_ERROR_NULL, "rays",
           "rays: null pointer");
  }
  {
    /* θ ≥ θmax = π/2: backward scattering with g = -0.5 at u0 near 1. */
    omnee_phase_f32 back;
    float far[3] = {0.999f, 0.5f, 0.5f};
    CHECK(omnee_phase_hg_f32(&back, -0.5f, &e) == OMNEE_OK);
    memset(&s, 0x7f, sizeof s);
    CHECK(omnee_omnee_sample_f32(&c, &back, far, &s, &e) == OMNEE_NONE && zero_sample(&s));
    CHECK(omnee_omnee_invert_f32(&c, &mix, x2, inv, &e) == OMNEE_NONE);
  }
  EXPECT(omnee_omnee_pdf_f32(&c, &hg, nan3, &value, &e), OMNEE_ERROR_NOT_FINITE, "x1",
         "x1 has a non-finite component");
  EXPECT(omnee_omnee_invert_f32(&c, &hg, inf3, inv, &e), OMNEE_ERROR_NOT_FINITE, "x1",
         "x1 has a non-finite component");
  EXPECT(omnee_omnee_invert_f32(&c, &hg, x0, NULL, &e), OMNEE_ERROR_NULL, "u",
         "u: null pointer");

  /* Ray techniques: the rays' kinds and geometry, sigma. */
  rays.directions = 7;
  EXPECT(omnee_equiangular_sample_f32(&c, &hg, &rays, u, &s, &e), OMNEE_ERROR_OUT_OF_RANGE,
         "directions", "directions = 7 is out of range; allowed: 0 (sphere) or 1 (cosine)");
  rays.directions = OMNEE_DIRECTIONS_COSINE; /* normal (0, 0, 0) */
  EXPECT(omnee_equiangular_pdf_f32(&c, &hg, &rays, x0, &value, &e), OMNEE_ERROR_DEGENERATE,
         "normal", "normal: must be finite and non-zero");
  rays.directions = OMNEE_DIRECTIONS_SPHERE;
  rays.region = OMNEE_REGION_SLAB;
  rays.z_min = 1.0f, rays.z_max = 1.0f;
  EXPECT(omnee_distance_sample_f32(&c, &hg, &rays, 1.0f, u, &s, &e), OMNEE_ERROR_DEGENERATE,
         "z_max", "z_max: equals z_min (empty slab)");
  rays.z_max = 0.5f;
  EXPECT(omnee_distance_sample_f32(&c, &hg, &rays, 1.0f, u, &s, &e), OMNEE_ERROR_OUT_OF_RANGE,
         "z_max", "z_max = 0.5 is out of range; allowed: (z_min, inf)");
  rays.region = 9;
  EXPECT(omnee_mis_sample_f32(&c, &hg, &rays, u6, NULL, &e), OMNEE_ERROR_NULL, "draw",
         "draw: null pointer");
  {
    omnee_draw_f32 draw;
    EXPECT(omnee_mis_sample_f32(&c, &hg, &rays, u6, &draw, &e), OMNEE_ERROR_OUT_OF_RANGE,
           "region", "region = 9 is out of range; allowed: 0 (everywhere) or 1 (slab)");
    CHECK(draw.present == 0);
  }
  rays.region = OMNEE_REGION_EVERYWHERE;
  EXPECT(omnee_distance_sample_f32(&c, &hg, &rays, -1.0f, u, &s, &e), OMNEE_ERROR_OUT_OF_RANGE,
         "sigma", "sigma = -1 is out of range; allowed: [0, inf)");
  EXPECT(omnee_distance_pdf_f32(&c, &hg, &rays, NAN, x0, &value, &e), OMNEE_ERROR_OUT_OF_RANGE,
         "sigma", "sigma = NaN is out of range; allowed: [0, inf)");
  EXPECT(omnee_mis_invert_f32(&c, &hg, &rays, 2, x0, inv, &e), OMNEE_ERROR_OUT_OF_RANGE,
         "vertex", "vertex = 2 is out of range; allowed: 0 (OMNEE) or 1 (companion)");
  {
    float bad_u6[6] = {0.5f, 0.5f, 0.5f, 0.5f, 0.5f, INFINITY};
    omnee_draw_f32 draw;
    EXPECT(omnee_mis_sample_f32(&c, &hg, &rays, bad_u6, &draw, &e), OMNEE_ERROR_NOT_FINITE, "u",
           "u has a non-finite component");
  }

  /* The batch: lengths that disagree, NULL, NaN, overlap, the wrong phase. */
  {
    enum { N = 8 };
    float a[N], b[N], cc[N], x[N], y[N], z[N], p[N], w[N];
    omnee_uniforms_f32 uu;
    omnee_vertices_f32 vv;
    size_t count = 99, i;
    for (i = 0; i < N; i++) a[i] = b[i] = cc[i] = ((float)i + 0.5f) / (float)N;
    uu.u0 = a, uu.u1 = b, uu.u2 = cc, uu.len = N;
    vv.x = x, vv.y = y, vv.z = z, vv.pdf = p, vv.weight = w, vv.len = N - 1;
    EXPECT(omnee_omnee_sample_batch_f32(&c, &hg, uu, vv, &count, &e), OMNEE_ERROR_TABLE, "batch",
           "batch: uniform and output slices differ in length");
    CHECK(count == 0);
    vv.len = N;
    EXPECT(omnee_omnee_sample_batch_f32(&c, &mix, uu, vv, &count, &e), OMNEE_ERROR_UNSUPPORTED,
           "phase", "phase: the batch needs Henyey-Greenstein (hg)");
    vv.y = x;
    EXPECT(omnee_omnee_sample_batch_f32(&c, &hg, uu, vv, &count, &e), OMNEE_ERROR_TABLE, "batch",
           "batch: arrays overlap");
    vv.y = y, vv.pdf = (float *)b;
    EXPECT(omnee_omnee_sample_batch_f32(&c, &hg, uu, vv, &count, &e), OMNEE_ERROR_TABLE, "batch",
           "batch: arrays overlap");
    vv.pdf = p, uu.u0 = NULL;
    EXPECT(omnee_omnee_sample_batch_f32(&c, &hg, uu, vv, &count, &e), OMNEE_ERROR_NULL, "u0",
           "u0: null pointer");
    uu.u0 = a, b[3] = NAN;
    EXPECT(omnee_omnee_sample_batch_f32(&c, &hg, uu, vv, &count, &e), OMNEE_ERROR_NOT_FINITE,
           "u1", "u1 has a non-finite component");
    b[3] = 0.5f;
    CHECK(omnee_omnee_sample_batch_f32(&c, &hg, uu, vv, &count, &e) == OMNEE_OK && count > 0);
    uu.len = vv.len = 0, uu.u0 = NULL, vv.x = NULL;
    CHECK(omnee_omnee_sample_batch_f32(&c, &hg, uu, vv, &count, &e) == OMNEE_OK && count == 0);
  }

  /* The problem: coefficients, receiver normal, a non-finite f_c. */
  {
    const omnee_vec3_f32 zero3 = {0.0f, 0.0f, 0.0f};
    const omnee_vec3_f32 huge = {3e38f, 3e38f, 3e38f};
    EXPECT(omnee_problem_init_f32(&problem, &c, -1.0f, 0.0f, NULL, &e), OMNEE_ERROR_OUT_OF_RANGE,
           "sigma_s", "sigma_s = -1 is out of range; allowed: [0, inf)");
    EXPECT(omnee_problem_init_f32(&problem, &c, 0.5f, INFINITY, NULL, &e),
           OMNEE_ERROR_OUT_OF_RANGE, "sigma_a", "sigma_a = inf is out of range; allowed: [0, inf)");
    EXPECT(omnee_problem_init_f32(&problem, &c, 0.5f, 0.0f, &zero3, &e), OMNEE_ERROR_DEGENERATE,
           "receiver_normal", "receiver_normal: must be finite and non-zero");
    EXPECT(omnee_problem_init_f32(&problem, NULL, 0.5f, 0.0f, NULL, &e), OMNEE_ERROR_NULL,
           "connection", "connection: null pointer");
    /* With no extinction, exp(-0 · ∞) would be NaN: the transmittance is 1 at
       any distance, so f_c at a point whose distances overflow is σs · 1 = 0. */
    CHECK(omnee_problem_init_f32(&still_problem, &c, 0.0f, 0.0f, NULL, &e) == OMNEE_OK);
    value = 1.0f;
    CHECK(omnee_problem_f_c_f32(&still_problem, huge, &value, &e) == OMNEE_OK && value == 0.0f);
    CHECK(omnee_problem_init_f32(&problem, &c, 0.5f, 0.0f, NULL, &e) == OMNEE_OK);
    s.x1 = x0, s.pdf = 1.0f, s.weight = NAN;
    EXPECT(omnee_problem_estimate_f32(&problem, &s, &value, &e), OMNEE_ERROR_NOT_FINITE, "sample",
           "sample has a non-finite component");
    EXPECT(omnee_problem_reference_f32(&problem, NULL, NULL, &e), OMNEE_ERROR_NULL, "reference",
           "reference: null pointer");
    {
      double reference;
      EXPECT(omnee_problem_reference_f32(&problem, NULL, &reference, &e), OMNEE_ERROR_NULL,
             "phase", "phase: null pointer");
    }
  }

  /* The message accessor: truncation, the full length, NULL, empty records. */
  CHECK(omnee_phase_hg_f32(&failed_phase, 1.0f, &e) == OMNEE_ERROR_OUT_OF_RANGE);
  CHECK(omnee_error_message(&e, buffer, sizeof buffer, &length) == OMNEE_OK);
  CHECK(strcmp(buffer, "g = 1 i") == 0 && length == strlen(e.message));
  CHECK(omnee_error_message(&e, buffer, 0, &length) == OMNEE_ERROR_TABLE);
  CHECK(omnee_error_message(NULL, buffer, sizeof buffer, &length) == OMNEE_ERROR_NULL);
  CHECK(omnee_error_message(&e, NULL, sizeof buffer, &length) == OMNEE_ERROR_NULL);
  memset(&e, 0, sizeof e);
  CHECK(omnee_error_message(&e, buffer, sizeof buffer, NULL) == OMNEE_OK && buffer[0] == '\0');

  printf("errors: %d passed, %d failed\n", passed, failed);
  return failed == 0 ? 0 : 1;
}

/* Bridges of k vertices through the C API (omnee_bridge_*,
 * omnee_vertex_count_*):
 *  - every bad input gives its status and field, zeroes the sample and
 *    leaves the vertex array as it was;
 *  - the density at the sampled vertices is the sample's;
 *  - the estimate of I_K (K = 1, 2, 3, 5, f32 and f64) and of the sum over
 *    K = 1 ... 4 with K drawn per sample agree with the isotropic closed form
 *    within 4.5 standard errors (fixed seeds);
 *  - the closed form's budget ends in OMNEE_ERROR_NOT_CONVERGED.
 * Prints "bridges: N passed, M failed" and exits non-zero on a failure. CI
 * runs it under AddressSanitizer and UndefinedBehaviorSanitizer. */
#include "omnee.h"

#include <math.h>
#include <stdint.h>
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
#define CAT_(a, b) a##b
#define CAT(a, b) CAT_(a, b)
#define STR_(x) #x
#define STR(x) STR_(x)

/* SplitMix64: uniform doubles in [0, 1) from a fixed seed. */
static uint64_t state;
static double uniform(void) {
  uint64_t z = (state += 0x9e3779b97f4a7c15ull);
  z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
  z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
  z ^= z >> 31;
  return (double)(z >> 11) * (1.0 / 9007199254740992.0);
}

/* The sample and the vertex array after a failed call: the sample zero, the
 * vertices as they were (-7). */
static int untouched(const omnee_vec3_f64 *v, size_t n, const omnee_bridge_f64 *b) {
  size_t i;
  int ok = b->k == 0 && b->length == 0.0 && b->pdf == 0.0 && b->weight == 0.0;
  for (i = 0; i < n; i++) ok &= v[i].x == -7.0 && v[i].y == -7.0 && v[i].z == -7.0;
  return ok;
}

#define EXPECT(call, want, field_name)                                                  \
  do {                                                                                  \
    omnee_status got_;                                                                  \
    memset(&e, 0, sizeof e);                                                            \
    got_ = (call);                                                                      \
    check(got_ == (want) && e.status == (int32_t)(want) && strcmp(e.field, field_name) == 0, \
          #call, __LINE__);                                                             \
    if (got_ != (want)) printf("  got %d, field \"%s\": %s\n", (int)got_, e.field, e.message); \
  } while (0)

static void bad_input(void) {
  omnee_connection_f64 c, narrow;
  omnee_phase_f64 hg;
  omnee_problem_f64 problem, cosine;
  omnee_vertex_count_f64 count;
  omnee_bridge_f64 b;
  omnee_vertex_draw_f64 draw;
  omnee_vec3_f64 v[4];
  omnee_error e;
  const omnee_vec3_f64 x0 = {0.0, 0.0, 1.0}, x2 = {0.0, 0.0, 0.0}, n = {0.0, 0.0, 1.0};
  double u[3 * 33], value;
  size_t i;
#define SENTINEL() for (i = 0; i < 4; i++) v[i].x = v[i].y = v[i].z = -7.0
  for (i = 0; i < 3 * 33; i++) u[i] = 0.25 + 0.005 * (double)i;
  CHECK(omnee_connection_init_f64(&c, x0, x2, 3.14159265358979323846, NULL) == OMNEE_OK);
  CHECK(omnee_connection_init_f64(&narrow, x0, x2, 3.0, NULL) == OMNEE_OK);
  CHECK(omnee_phase_hg_f64(&hg, 0.5, NULL) == OMNEE_OK);
  CHECK(omnee_problem_init_f64(&problem, &c, 0.5, 0.05, NULL, NULL) == OMNEE_OK);
  CHECK(omnee_problem_init_f64(&cosine, &c, 0.5, 0.05, &n, NULL) == OMNEE_OK);

  /* k = 0, k > OMNEE_MAX_VERTICES, capacity < k. */
  SENTINEL();
  EXPECT(omnee_bridge_sample_f64(&c, &hg, 0, u, v, 4, &b, &e), OMNEE_ERROR_OUT_OF_RANGE, "k");
  CHECK(untouched(v, 4, &b) && e.value == 0.0);
  EXPECT(omnee_bridge_sample_f64(&c, &hg, OMNEE_MAX_VERTICES + 1, u, v, 4, &b, &e),
         OMNEE_ERROR_OUT_OF_RANGE, "k");
  CHECK(untouched(v, 4, &b) && e.value == 33.0);
  EXPECT(omnee_bridge_sample_f64(&c, &hg, 5, u, v, 4, &b, &e), OMNEE_ERROR_OUT_OF_RANGE,
         "capacity");
  CHECK(untouched(v, 4, &b));
  /* NULL u, vertices, sample (no write before the check), connection. */
  EXPECT(omnee_bridge_sample_f64(&c, &hg, 2, NULL, v, 4, &b, &e), OMNEE_ERROR_NULL, "u");
  CHECK(untouched(v, 4, &b));
  EXPECT(omnee_bridge_sample_f64(&c, &hg, 2, u, NULL, 4, &b, &e), OMNEE_ERROR_NULL, "vertices");
  EXPECT(omnee_bridge_sample_f64(&c, &hg, 2, u, v, 4, NULL, &e), OMNEE_ERROR_NULL, "sample");
  CHECK(untouched(v, 4, &b));
  EXPECT(omnee_bridge_sample_f64(NULL, &hg, 2, u, v, 4, &b, &e), OMNEE_ERROR_NULL, "connection");
  /* NaN, infinite, out-of-range uniform numbers. */
  u[4] = NAN;
  EXPECT(omnee_bridge_sample_f64(&c, &hg, 2, u, v, 4, &b, &e), OMNEE_ERROR_NOT_FINITE, "u");
  u[4] = INFINITY;
  EXPECT(omnee_bridge_sample_f64(&c, &hg, 2, u, v, 4, &b, &e), OMNEE_ERROR_NOT_FINITE, "u");
  u[4] = 1.5;
  EXPECT(omnee_bridge_sample_f64(&c, &hg, 2, u, v, 4, &b, &e), OMNEE_ERROR_OUT_OF_RANGE, "u");
  CHECK(e.value == 1.5);
  u[4] = -0.1;
  EXPECT(omnee_bridge_sample_f64(&c, &hg, 2, u, v, 4, &b, &e), OMNEE_ERROR_OUT_OF_RANGE, "u");
  CHECK(untouched(v, 4, &b));
  u[4] = 0.27;
  /* The vertices over the numbers. */
  EXPECT(omnee_bridge_sample_f64(&c, &hg, 2, u, (omnee_vec3_f64 *)(void *)u, 2, &b, &e),
         OMNEE_ERROR_TABLE, "vertices");
  /* theta_max < pi; garbage and zeroed objects; the other precision's. */
  EXPECT(omnee_bridge_sample_f64(&narrow, &hg, 2, u, v, 4, &b, &e), OMNEE_ERROR_OUT_OF_RANGE,
         "theta_max");
  CHECK(untouched(v, 4, &b));
  {
    omnee_connection_f64 bad = c;
    omnee_phase_f64 zero;
    bad.storage[2] ^= 0x4;
    memset(&zero, 0, sizeof zero);
    EXPECT(omnee_bridge_sample_f64(&bad, &hg, 2, u, v, 4, &b, &e), OMNEE_ERROR_UNINITIALISED,
           "connection");
    EXPECT(omnee_bridge_sample_f64(&c, &zero, 2, u, v, 4, &b, &e), OMNEE_ERROR_UNINITIALISED,
           "phase");
    CHECK(untouched(v, 4, &b));
  }
  /* All 32 vertices; then u = 1 everywhere: the stick leaves nothing for
     the last edge, OMNEE_NONE, zeros in the first k entries only. */
  {
    omnee_vec3_f64 all[OMNEE_MAX_VERTICES];
    CHECK(omnee_bridge_sample_f64(&c, &hg, OMNEE_MAX_VERTICES, u, all, OMNEE_MAX_VERTICES, &b,
                                  &e) == OMNEE_OK);
    CHECK(b.k == OMNEE_MAX_VERTICES && b.pdf > 0.0 && isfinite(b.weight));
  }
  for (i = 0; i < 6; i++) u[i] = 1.0;
  SENTINEL();
  CHECK(omnee_bridge_sample_f64(&c, &hg, 2, u, v, 4, &b, &e) == OMNEE_NONE);
  CHECK(b.k == 0 && v[0].x == 0.0 && v[1].z == 0.0 && v[2].x == -7.0);

  /* pdf: k, NULL and NaN vertices, theta_max. */
  SENTINEL();
  value = 9.0;
  EXPECT(omnee_bridge_pdf_f64(&c, &hg, 0, v, &value, &e), OMNEE_ERROR_OUT_OF_RANGE, "k");
  CHECK(value == 0.0);
  EXPECT(omnee_bridge_pdf_f64(&c, &hg, 2, NULL, &value, &e), OMNEE_ERROR_NULL, "vertices");
  v[1].y = NAN;
  EXPECT(omnee_bridge_pdf_f64(&c, &hg, 2, v, &value, &e), OMNEE_ERROR_NOT_FINITE, "vertices");
  EXPECT(omnee_bridge_pdf_f64(&narrow, &hg, 1, v, &value, &e), OMNEE_ERROR_OUT_OF_RANGE,
         "theta_max");
  /* Coincident points: density 0. */
  v[0] = x0;
  CHECK(omnee_bridge_pdf_f64(&c, &hg, 1, v, &value, &e) == OMNEE_OK && value == 0.0);

  /* invert: k, capacity < 3k, NULL, NaN vertices, u over the vertices; u
     left as it was on an error. */
  {
    double back[6] = {-7, -7, -7, -7, -7, -7};
    omnee_vec3_f64 w[2] = {{0.1, 0.2, 0.5}, {-0.1, 0.1, 0.3}};
    EXPECT(omnee_bridge_invert_f64(&c, &hg, 0, w, back, 6, &e), OMNEE_ERROR_OUT_OF_RANGE, "k");
    EXPECT(omnee_bridge_invert_f64(&c, &hg, 2, w, back, 5, &e), OMNEE_ERROR_OUT_OF_RANGE,
           "capacity");
    EXPECT(omnee_bridge_invert_f64(&c, &hg, 2, NULL, back, 6, &e), OMNEE_ERROR_NULL, "vertices");
    EXPECT(omnee_bridge_invert_f64(&c, &hg, 2, w, NULL, 6, &e), OMNEE_ERROR_NULL, "u");
    EXPECT(omnee_bridge_invert_f64(&narrow, &hg, 2, w, back, 6, &e), OMNEE_ERROR_OUT_OF_RANGE,
           "theta_max");
    EXPECT(omnee_bridge_invert_f64(&c, &hg, 2, w, (double *)(void *)w, 6, &e), OMNEE_ERROR_TABLE,
           "u");
    w[1].z = NAN;
    EXPECT(omnee_bridge_invert_f64(&c, &hg, 2, w, back, 6, &e), OMNEE_ERROR_NOT_FINITE, "vertices");
    CHECK(back[0] == -7.0 && back[5] == -7.0);
    /* A vertex on x0: no inverse, zeros. */
    w[1].z = 0.3, w[0] = x0;
    CHECK(omnee_bridge_invert_f64(&c, &hg, 2, w, back, 6, &e) == OMNEE_NONE);
    CHECK(back[0] == 0.0 && back[5] == 0.0);
  }

  /* estimate: a problem with a receiver cosine, a bad sample; the zero
     sample estimates 0. */
  memset(&b, 0, sizeof b);
  value = 9.0;
  CHECK(omnee_bridge_estimate_f64(&problem, &b, &value, &e) == OMNEE_OK && value == 0.0);
  b.k = 2, b.length = 3.0, b.pdf = 1.0, b.phase_ratio = 1.0, b.weight = 2.0;
  EXPECT(omnee_bridge_estimate_f64(&cosine, &b, &value, &e), OMNEE_ERROR_UNSUPPORTED,
         "receiver_normal");
  CHECK(value == 0.0);
  b.weight = NAN;
  EXPECT(omnee_bridge_estimate_f64(&problem, &b, &value, &e), OMNEE_ERROR_OUT_OF_RANGE, "sample");
  b.weight = 2.0, b.k = 40;
  EXPECT(omnee_bridge_estimate_f64(&problem, &b, &value, &e), OMNEE_ERROR_OUT_OF_RANGE,
         "sample.k");
  EXPECT(omnee_bridge_estimate_f64(&problem, NULL, &value, &e), OMNEE_ERROR_NULL, "sample");

  /* reference: k, sigma_t = 0 with k >= 2, the budget spent. */
  EXPECT(omnee_bridge_reference_f64(&problem, 0, OMNEE_REFERENCE_BUDGET, &value, &e),
         OMNEE_ERROR_OUT_OF_RANGE, "k");
  {
    omnee_problem_f64 vacuum;
    CHECK(omnee_problem_init_f64(&vacuum, &c, 0.0, 0.0, NULL, NULL) == OMNEE_OK);
    EXPECT(omnee_bridge_reference_f64(&vacuum, 2, OMNEE_REFERENCE_BUDGET, &value, &e),
           OMNEE_ERROR_OUT_OF_RANGE, "sigma_t");
  }
  value = 9.0;
  EXPECT(omnee_bridge_reference_f64(&problem, 3, 20, &value, &e), OMNEE_ERROR_NOT_CONVERGED,
         "reference");
  CHECK(value == 0.0);
  EXPECT(omnee_bridge_reference_f64(&cosine, 3, OMNEE_REFERENCE_BUDGET, &value, &e),
         OMNEE_ERROR_UNSUPPORTED, "receiver_normal");

  /* vertex count: k_max, u, garbage objects. */
  EXPECT(omnee_vertex_count_init_f64(&count, &problem, &hg, 0, &e), OMNEE_ERROR_OUT_OF_RANGE,
         "k_max");
  EXPECT(omnee_vertex_count_sample_f64(&count, 0.5, &draw, &e), OMNEE_ERROR_UNINITIALISED, "count");
  CHECK(draw.k == 0 && draw.probability == 0.0);
  EXPECT(omnee_vertex_count_init_f64(&count, &problem, &hg, 33, &e), OMNEE_ERROR_OUT_OF_RANGE,
         "k_max");
  CHECK(omnee_vertex_count_init_f64(&count, &problem, &hg, 6, &e) == OMNEE_OK);
  EXPECT(omnee_vertex_count_sample_f64(&count, NAN, &draw, &e), OMNEE_ERROR_NOT_FINITE, "u");
  EXPECT(omnee_vertex_count_sample_f64(&count, 1.5, &draw, &e), OMNEE_ERROR_OUT_OF_RANGE, "u");
  CHECK(draw.k == 0);
  CHECK(omnee_vertex_count_sample_f64(&count, 1.0, &draw, &e) == OMNEE_OK && draw.k == 6);
  {
    double total = 0.0, p;
    size_t k;
    for (k = 0; k <= 7; k++) {
      CHECK(omnee_vertex_count_pmf_f64(&count, k, &p, &e) == OMNEE_OK);
      CHECK((k >= 1 && k <= 6) ? p > 0.0 : p == 0.0);
      total += p;
    }
    CHECK(fabs(total - 1.0) < 1e-12);
    count.storage[5] ^= 1;
    EXPECT(omnee_vertex_count_pmf_f64(&count, 2, &p, &e), OMNEE_ERROR_UNINITIALISED, "count");
  }
#undef SENTINEL
}

#define T float
#define P f32
#include "bridges_body.inc"
#undef P
#undef T

#define T double
#define P f64
#include "bridges_body.inc"
#undef P
#undef T

int main(void) {
  bad_input();
  estimates_f32();
  estimates_f64();
  scales_f32();
  scales_f64();
  printf("bridges: %d passed, %d failed\n", passed, failed);
  return failed == 0 ? 0 : 1;
}

/* The header's promises at the boundaries, each by a check (CI runs this
 * under AddressSanitizer and UndefinedBehaviorSanitizer):
 *  - corrupted objects (a valid tag over garbage or altered storage) are
 *    OMNEE_ERROR_UNINITIALISED in every function that reads them, never a
 *    crash, never a number;
 *  - normals and directions of any finite non-zero length are accepted with
 *    the answers of the unit vector; NaN in them is OMNEE_ERROR_NOT_FINITE,
 *    zero OMNEE_ERROR_DEGENERATE;
 *  - end points 1e-30 to 3e38 apart (f32), 1e-300 to 1.6e308 (f64), and
 *    (0.6 max, 0, 0) to (0, 0.6 max, 0) are accepted, and every technique's
 *    vertex, weight, density, inverse and f_c are the unit problem's,
 *    scaled; theta_max takes the smallest subnormal;
 *  - the documented status and outputs of deflection_between,
 *    phase_sample, phase_parse and the batch (no write before a failed
 *    check);
 *  - the reference with a receiver normal and theta_max = pi returns in
 *    well under a second;
 *  - the reference obeys the scale law (a problem scaled by a power of two
 *    lambda, sigma over lambda, has the reference over lambda^2, rounded
 *    once) at normal scales, 2^+-100 (f32), 2^+-500 and 2^+-1000 (f64) and
 *    for end points a subnormal distance apart; at 1e-320 apart its value
 *    is right where it is representable and OMNEE_ERROR_NOT_FINITE where it
 *    is beyond double's range.
 * Prints "promises: N passed, M failed" and exits non-zero on a failure. */
#include "omnee.h"

#include <float.h>
#include <math.h>
#include <stdio.h>
#include <string.h>
#include <time.h>

static int passed, failed;

static void check(int ok, const char *what, const char *file, int line) {
  if (ok) {
    passed++;
  } else {
    failed++;
    printf("FAIL %s:%d: %s\n", file, line, what);
  }
}

#define CHECK(cond) check((cond) != 0, #cond, __FILE__, __LINE__)

#define CAT_(a, b) a##b
#define CAT(a, b) CAT_(a, b)

/* |a - b| <= tol |b| (and both finite). */
static int close_to(double a, double b, double tol) {
  return isfinite(a) && isfinite(b) && fabs(a - b) <= tol * fabs(b);
}

/* An LCG for garbage bytes. */
static unsigned long long lcg_state = 0x2545f4914f6cdd1dULL;
static unsigned long long lcg(void) {
  lcg_state = lcg_state * 6364136223846793005ULL + 1442695040888963407ULL;
  return lcg_state;
}

/* Fills `words` 64-bit words with one of the garbage patterns: 0xAB bytes,
 * random bits, the valid contents with one bit flipped, all ones. */
static void garble(uint64_t *words, size_t n, int pattern, size_t flip) {
  size_t i;
  switch (pattern) {
    case 0:
      memset(words, 0xAB, n * sizeof *words);
      break;
    case 1:
      for (i = 0; i < n; i++) words[i] = lcg();
      break;
    case 2:
      words[flip % n] ^= 1ULL << (flip % 64);
      break;
    default:
      memset(words, 0xFF, n * sizeof *words);
      break;
  }
}

#define T float
#define P f32
#define T_MAX FLT_MAX
#define T_EPS FLT_EPSILON
#define T_SUB 1.40129846e-45f
#define SCALES {1e-30, 1e30, 1e38, 3e38}
/* {base, shift, sigma, sigma at theta_max 1e-30}: see reference_scales_. */
#define REFERENCE_SCALES \
  {{0, 20, 0, 0}, {0, -20, 0, 0}, {0, 100, 0, 0}, {0, -100, 0, 0}, {-120, -20, 100, 100}}
#include "promises_body.inc"
#undef SCALES
#undef REFERENCE_SCALES
#undef T_SUB
#undef T_EPS
#undef T_MAX
#undef P
#undef T

#define T double
#define P f64
#define T_MAX DBL_MAX
#define T_EPS DBL_EPSILON
#define T_SUB 4.9406564584124654e-324
#define SCALES {1e-300, 1e300, 1e308, 1.6e308}
#define REFERENCE_SCALES                                                                  \
  {{0, 20, 0, 0},         {0, -20, 0, 0},     {0, 500, 0, 0},         {0, 1000, 0, 0}, \
   {0, -500, -500, -500}, {0, -1000, -1000, -800}, {-1000, -70, -200, -200}}
#include "promises_body.inc"
#undef SCALES
#undef REFERENCE_SCALES
#undef T_SUB
#undef T_EPS
#undef T_MAX
#undef P
#undef T

/* phase_parse: *table_path is the span on OMNEE_TABLE_SPEC and zeroed on
 * every other outcome. */
static void parse(void) {
  omnee_phase_f32 phase;
  omnee_span span;
  const char *spec = "table:a.csv";
  span.offset = 7, span.length = 7;
  CHECK(omnee_phase_parse_f32(&phase, "hg:2", &span, NULL) == OMNEE_ERROR_OUT_OF_RANGE);
  CHECK(span.offset == 0 && span.length == 0);
  span.offset = 7, span.length = 7;
  CHECK(omnee_phase_parse_f32(&phase, "nonsense", &span, NULL) == OMNEE_ERROR_SYNTAX);
  CHECK(span.offset == 0 && span.length == 0);
  span.offset = 7, span.length = 7;
  CHECK(omnee_phase_parse_f32(&phase, NULL, &span, NULL) == OMNEE_ERROR_NULL);
  CHECK(span.offset == 0 && span.length == 0);
  span.offset = 7, span.length = 7;
  CHECK(omnee_phase_parse_f32(&phase, "hg:0.5", &span, NULL) == OMNEE_OK);
  CHECK(span.offset == 0 && span.length == 0);
  CHECK(omnee_phase_parse_f32(&phase, spec, &span, NULL) == OMNEE_TABLE_SPEC);
  CHECK(span.offset == 6 && span.length == 5);
}

/* The batch: every check before the first write. */
static void batch(void) {
  enum { N = 8 };
  float a[N], b[N], cc[N], x[N], y[N], z[N], p[N], w[N];
  omnee_connection_f32 c;
  omnee_phase_f32 hg;
  omnee_uniforms_f32 uu;
  omnee_vertices_f32 vv;
  omnee_error e;
  const omnee_vec3_f32 x0 = {0.0f, 0.0f, 1.0f}, x2 = {0.0f, 0.0f, 0.0f};
  size_t count, i;
  int untouched;
  CHECK(omnee_connection_init_f32(&c, x0, x2, 3.0f, NULL) == OMNEE_OK);
  CHECK(omnee_phase_hg_f32(&hg, 0.5f, NULL) == OMNEE_OK);
  for (i = 0; i < N; i++) a[i] = b[i] = cc[i] = ((float)i + 0.5f) / (float)N;
#define SENTINEL()                                                  \
  for (i = 0; i < N; i++) x[i] = y[i] = z[i] = p[i] = w[i] = -7.0f
  uu.u0 = a, uu.u1 = b, uu.u2 = cc, uu.len = N;
  vv.x = x, vv.y = y, vv.z = z, vv.pdf = p, vv.weight = w, vv.len = N;

  /* count = NULL: OMNEE_ERROR_NULL, nothing written. */
  SENTINEL();
  memset(&e, 0, sizeof e);
  CHECK(omnee_omnee_sample_batch_f32(&c, &hg, uu, vv, NULL, &e) == OMNEE_ERROR_NULL);
  CHECK(strcmp(e.field, "count") == 0);
  untouched = 1;
  for (i = 0; i < N; i++) untouched &= x[i] == -7.0f && y[i] == -7.0f && z[i] == -7.0f &&
                                       p[i] == -7.0f && w[i] == -7.0f;
  CHECK(untouched);

  /* u1 aliasing u0 (and u2 overlapping u1): OMNEE_ERROR_TABLE, nothing
     written, count 0. */
  SENTINEL();
  count = 99;
  uu.u1 = a;
  CHECK(omnee_omnee_sample_batch_f32(&c, &hg, uu, vv, &count, &e) == OMNEE_ERROR_TABLE);
  CHECK(count == 0 && strcmp(e.message, "batch: arrays overlap") == 0);
  uu.u1 = b, uu.u2 = b + 1, uu.len = vv.len = N - 1;
  CHECK(omnee_omnee_sample_batch_f32(&c, &hg, uu, vv, &count, &e) == OMNEE_ERROR_TABLE);
  uu.u2 = cc, uu.len = vv.len = N;
  /* An output on an input, a NaN input: nothing written. */
  vv.weight = cc;
  CHECK(omnee_omnee_sample_batch_f32(&c, &hg, uu, vv, &count, &e) == OMNEE_ERROR_TABLE);
  vv.weight = w, b[5] = NAN;
  CHECK(omnee_omnee_sample_batch_f32(&c, &hg, uu, vv, &count, &e) == OMNEE_ERROR_NOT_FINITE);
  b[5] = 0.5f;
  untouched = 1;
  for (i = 0; i < N; i++) untouched &= x[i] == -7.0f && y[i] == -7.0f && z[i] == -7.0f &&
                                       p[i] == -7.0f && w[i] == -7.0f;
  CHECK(untouched && cc[0] == 0.5f / (float)N);
  /* A garbage connection under a valid tag: UNINITIALISED, nothing written. */
  {
    omnee_connection_f32 bad = c;
    bad.storage[3] ^= 0x10;
    CHECK(omnee_omnee_sample_batch_f32(&bad, &hg, uu, vv, &count, &e) ==
          OMNEE_ERROR_UNINITIALISED);
    CHECK(x[0] == -7.0f && count == 0);
  }
  CHECK(omnee_omnee_sample_batch_f32(&c, &hg, uu, vv, &count, &e) == OMNEE_OK && count > 0);
#undef SENTINEL
}

/* End points 1e-320 apart (HG 0.9, sigma_s 0.5, sigma_a 0.25, no receiver
 * normal): for theta_max = 1e-30 the reference is about 2e261, the problem
 * scaled by 2^64 times 2^128; for pi and pi/2 it is beyond double's range:
 * OMNEE_ERROR_NOT_FINITE (field "reference", *reference = 0), never
 * OMNEE_ERROR_NOT_CONVERGED. */
static void subnormal_reference(void) {
  const double pi = 3.14159265358979323846, theta_max[3] = {1e-30, pi / 2, pi};
  const double lambda = ldexp(1.0, 64);
  omnee_phase_f64 hg;
  omnee_error e;
  int i, k;
  CHECK(omnee_phase_hg_f64(&hg, 0.9, NULL) == OMNEE_OK);
  for (i = 0; i < 3; i++) {
    double reference[2];
    omnee_status status[2];
    /* The scaled problem first, so that e holds the subnormal one's error. */
    for (k = 1; k >= 0; k--) {
      const double l = k == 0 ? 1.0 : lambda;
      const omnee_vec3_f64 x0 = {0.0, 0.0, 0.0}, x2 = {1e-320 * l, 0.0, 0.0};
      omnee_connection_f64 c;
      omnee_problem_f64 p;
      CHECK(omnee_connection_init_f64(&c, x0, x2, theta_max[i], NULL) == OMNEE_OK);
      CHECK(omnee_problem_init_f64(&p, &c, 0.5 / l, 0.25 / l, NULL, NULL) == OMNEE_OK);
      memset(&e, 0, sizeof e);
      status[k] = omnee_problem_reference_f64(&p, &hg, &reference[k], &e);
    }
    CHECK(status[1] == OMNEE_OK && reference[1] > 0.0);
    if (i == 0) {
      CHECK(status[0] == OMNEE_OK && reference[0] == reference[1] * lambda * lambda &&
            reference[0] > 1e261);
    } else {
      CHECK(status[0] == OMNEE_ERROR_NOT_FINITE && reference[0] == 0.0 &&
            strcmp(e.field, "reference") == 0 && isinf(reference[1] * lambda * lambda));
    }
  }
}

int main(void) {
  run_f32();
  run_f64();
  subnormal_reference();
  parse();
  batch();
  printf("promises: %d passed, %d failed\n", passed, failed);
  return failed == 0 ? 0 : 1;
}

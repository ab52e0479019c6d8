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
 *    well under a second.
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
#include "promises_body.inc"
#undef SCALES
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
#include "promises_body.inc"
#undef SCALES
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

int main(void) {
  run_f32();
  run_f64();
  parse();
  batch();
  printf("promises: %d passed, %d failed\n", passed, failed);
  return failed == 0 ? 0 : 1;
}

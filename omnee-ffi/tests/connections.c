/* The batch over connections, omnee_omnee_sample_connections_* and
 * omnee_mis_sample_connections_*: every lane must equal the single-connection
 * calls on its numbers bit for bit (omnee_connection_init_* of its end
 * points, then omnee_omnee_sample_* or omnee_mis_sample_*; a lane where
 * those fail or return OMNEE_NONE has valid = 0 and zeros), across phase
 * functions, both precisions, lanes with coincident, NaN, infinite and far
 * apart end points, NaN, infinite and out-of-range uniform numbers, and
 * batch lengths across the library's blocks; and every bad input must give
 * its status with nothing written (NULL arrays, lengths, overlap, theta_max,
 * objects). CI runs this under AddressSanitizer and
 * UndefinedBehaviorSanitizer. Prints "connections: N passed, M failed" and
 * exits non-zero on a failure. */
#include "omnee.h"

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

/* The call returned `want` and the record names `field`. */
static void expect(omnee_status got, omnee_status want, const omnee_error *e, const char *field,
                   int line) {
  int ok = got == want && e->status == (int32_t)want && strcmp(e->field, field) == 0;
  check(ok, field, line);
  if (!ok) {
    printf("  got status %d (record %d), field \"%s\", message \"%s\"\n", (int)got,
           (int)e->status, e->field, e->message);
  }
}

#define EXPECT(call, want, field)                      \
  do {                                                 \
    memset(&e, 0, sizeof e);                           \
    expect((call), (want), &e, (field), __LINE__);     \
  } while (0)

/* A fixed pseudo-random stream in [0, 1). */
static unsigned long long state = 0x5eedULL;
static double next(void) {
  state = state * 6364136223846793005ULL + 1442695040888963407ULL;
  return (double)(state >> 11) / 9007199254740992.0;
}

#define CAT_(a, b) a##b
#define CAT(a, b) CAT_(a, b)
#define STR_(x) #x
#define STR(x) STR_(x)

#define T float
#define P f32
#include "connections_body.inc"
#undef P
#undef T

#define T double
#define P f64
#include "connections_body.inc"
#undef P
#undef T

int main(void) {
  run_f32();
  run_f64();
  printf("connections: %d passed, %d failed\n", passed, failed);
  return failed == 0 ? 0 : 1;
}

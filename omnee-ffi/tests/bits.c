/* Prints the C API's results on a fixed set of inputs as IEEE bit patterns,
 * one labelled line per group; examples/expected.rs prints the Rust API's on
 * the same inputs, and omnee-ffi/ci.sh checks that the two outputs are
 * identical. */
#include "omnee.h"

#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define CAT_(a, b) a##b
#define CAT(a, b) CAT_(a, b)
#define STR_(x) #x
#define STR(x) STR_(x)

/* Stops on a status that should not happen with these inputs. */
#define CHECK(call)                                                              \
  do {                                                                           \
    omnee_status check_status_ = (call);                                         \
    if (check_status_ != OMNEE_OK) {                                             \
      fprintf(stderr, "%s:%d: %s -> %d\n", __FILE__, __LINE__, #call,            \
              (int)check_status_);                                               \
      exit(2);                                                                   \
    }                                                                            \
  } while (0)

static void line(const char *format, ...) {
  va_list args;
  va_start(args, format);
  vprintf(format, args);
  va_end(args);
}

static void end(void) { putchar('\n'); }
static void status(omnee_status s) { printf(" s%d", (int)s); }
static void bits_u32(uint32_t x) { printf(" %08lx", (unsigned long)x); }

static void bits_f32(float x) {
  uint32_t u;
  memcpy(&u, &x, sizeof u);
  bits_u32(u);
}

static void bits_f64(double x) {
  uint64_t u;
  memcpy(&u, &x, sizeof u);
  printf(" %016llx", (unsigned long long)u);
}

#define T float
#define P f32
#define bits bits_f32
#include "bits_body.inc"
#undef bits
#undef P
#undef T

#define T double
#define P f64
#define bits bits_f64
#include "bits_body.inc"
#undef bits
#undef P
#undef T

/* The structure-of-arrays batch (f32, Henyey-Greenstein). */
static void run_batch(void) {
  enum { N = 16 };
  float u0[N], u1[N], u2[N], x[N], y[N], z[N], pdf[N], weight[N];
  omnee_connection_f32 c;
  omnee_phase_f32 hg;
  omnee_vec3_f32 x0 = {0.3f, -0.2f, 1.1f}, x2 = {-0.1f, 0.4f, 0.2f};
  omnee_uniforms_f32 u;
  omnee_vertices_f32 v;
  size_t i, count;
  for (i = 0; i < N; i++) {
    u0[i] = ((float)i + 0.5f) / 16.0f;
    u1[i] = ((float)((i * 7) % N) + 0.25f) / 16.0f;
    u2[i] = ((float)((i * 11) % N) + 0.75f) / 16.0f;
  }
  u.u0 = u0, u.u1 = u1, u.u2 = u2, u.len = N;
  v.x = x, v.y = y, v.z = z, v.pdf = pdf, v.weight = weight, v.len = N;
  CHECK(omnee_connection_init_f32(&c, x0, x2, 2.8f, NULL));
  CHECK(omnee_phase_hg_f32(&hg, 0.9f, NULL));
  CHECK(omnee_omnee_sample_batch_f32(&c, &hg, u, v, &count, NULL));
  printf("f32 batch count %u\n", (unsigned)count);
  for (i = 0; i < N; i++) {
    printf("f32 batch %u", (unsigned)i);
    bits_f32(x[i]), bits_f32(y[i]), bits_f32(z[i]), bits_f32(pdf[i]), bits_f32(weight[i]);
    end();
  }
}

int main(void) {
  run_f32();
  run_f64();
  run_batch();
  return 0;
}

/* Estimates the once-scattered transfer between a point light and a point
 * receiver in fog with OMNEE through the C API, and checks it against the
 * library's quadrature reference: exits 1 when they differ by more than 4.5
 * standard errors (2 on an API error).
 *
 *   cargo build --release -p omnee-ffi
 *   cc -std=c99 -Iomnee-ffi/include omnee-ffi/examples/estimate.c \
 *      target/release/libomnee_ffi.a -lm -lpthread -ldl -o estimate && ./estimate
 */
#include "omnee.h"

#include <math.h>
#include <stdint.h>
#include <stdio.h>

/* SplitMix64 (Steele, Lea, Flood 2014): a small, well-mixed generator. */
static uint64_t next_u64(uint64_t *state) {
  uint64_t z = (*state += 0x9e3779b97f4a7c15u);
  z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9u;
  z = (z ^ (z >> 27)) * 0x94d049bb133111ebu;
  return z ^ (z >> 31);
}

/* A uniform float in [0, 1): the top 24 bits, scaled by 2^-24. */
static float uniform(uint64_t *state) { return (float)(next_u64(state) >> 40) * 0x1p-24f; }

/* Prints the error record and returns 2 when a call failed. */
static int failed(omnee_status status, const omnee_error *error) {
  if (status >= 0) return 0;
  fprintf(stderr, "omnee error %d (%s): %s\n", (int)status, error->field, error->message);
  return 2;
}

int main(void) {
  const omnee_vec3_f32 x0 = {0.0f, 0.0f, 1.0f}, x2 = {0.0f, 0.0f, 0.0f};
  const float theta_max = 1.57079637f; /* π/2: forward scattering */
  const float sigma_s = 0.5f, sigma_a = 0.05f, g = 0.9f;
  const long n = 1000000;
  omnee_connection_f32 connection;
  omnee_phase_f32 phase;
  omnee_problem_f32 problem;
  omnee_connection_f64 connection64;
  omnee_phase_f64 phase64;
  omnee_problem_f64 problem64;
  omnee_error error;
  uint64_t state = 2024;
  double sum = 0.0, sum_sq = 0.0, mean, std_error, reference;
  const omnee_vec3_f64 x0_64 = {x0.x, x0.y, x0.z}, x2_64 = {x2.x, x2.y, x2.z};
  long i;

  if (failed(omnee_connection_init_f32(&connection, x0, x2, theta_max, &error), &error) ||
      failed(omnee_phase_hg_f32(&phase, g, &error), &error) ||
      failed(omnee_problem_init_f32(&problem, &connection, sigma_s, sigma_a, NULL, &error),
             &error))
    return 2;

  for (i = 0; i < n; i++) {
    const float u[3] = {uniform(&state), uniform(&state), uniform(&state)};
    omnee_sample_f32 sample;
    float estimate = 0.0f;
    /* OMNEE_NONE (θ ≥ θmax) contributes 0. */
    omnee_status status = omnee_omnee_sample_f32(&connection, &phase, u, &sample, &error);
    if (failed(status, &error)) return 2;
    if (status == OMNEE_OK &&
        failed(omnee_problem_estimate_f32(&problem, &sample, &estimate, &error), &error))
      return 2;
    sum += estimate;
    sum_sq += (double)estimate * estimate;
  }
  mean = sum / (double)n;
  std_error = sqrt((sum_sq / (double)n - mean * mean) / (double)(n - 1));

  /* The same problem in double precision (the f32 inputs widened exactly),
   * integrated by quadrature. */
  if (failed(omnee_connection_init_f64(&connection64, x0_64, x2_64, theta_max, &error), &error) ||
      failed(omnee_phase_hg_f64(&phase64, g, &error), &error) ||
      failed(omnee_problem_init_f64(&problem64, &connection64, sigma_s, sigma_a, NULL, &error),
             &error) ||
      failed(omnee_problem_reference_f64(&problem64, &phase64, &reference, &error), &error))
    return 2;

  printf("samples    %ld\n", n);
  printf("estimate   %.9g\n", mean);
  printf("std_error  %.3g\n", std_error);
  printf("reference  %.9g\n", reference);
  printf("deviation  %.2f standard errors\n", (mean - reference) / std_error);
  if (!(fabs(mean - reference) <= 4.5 * std_error)) {
    printf("FAIL: more than 4.5 standard errors from the reference\n");
    return 1;
  }
  printf("ok: within 4.5 standard errors\n");
  return 0;
}

/* timing.c - stage timing accumulators (one writer thread each). */
#include "roadscan/util/timing.h"

#include <stdlib.h>
#include <string.h>
#include <time.h>

int64_t rs_now_ns(void) {
  struct timespec ts;
  clock_gettime(CLOCK_MONOTONIC, &ts);
  return (int64_t)ts.tv_sec * 1000000000LL + ts.tv_nsec;
}

void rs_timing_init(rs_timing_t *t, const char *name) {
  memset(t, 0, sizeof *t);
  t->name = name;
}

void rs_timing_add(rs_timing_t *t, int64_t ns) {
  t->win[t->n % RS_TIMING_WINDOW] = ns;
  t->n++;
  t->sum_ns += ns;
  if (ns > t->max_ns) t->max_ns = ns;
}

static int cmp64(const void *a, const void *b) {
  int64_t x = *(const int64_t *)a, y = *(const int64_t *)b;
  return (x > y) - (x < y);
}

double rs_timing_pct_us(const rs_timing_t *t, double pct) {
  size_t n = t->n < RS_TIMING_WINDOW ? (size_t)t->n : RS_TIMING_WINDOW;
  if (n == 0) return 0.0;
  static int64_t copy[RS_TIMING_WINDOW]; /* summary time only, single caller */
  memcpy(copy, t->win, n * sizeof copy[0]);
  qsort(copy, n, sizeof copy[0], cmp64);
  size_t i = (size_t)(pct / 100.0 * (double)(n - 1) + 0.5);
  if (i >= n) i = n - 1;
  return (double)copy[i] / 1000.0;
}

void rs_timing_print(const rs_timing_t *t, FILE *out) {
  if (t->n == 0) {
    fprintf(out, "  %-22s n=0\n", t->name);
    return;
  }
  fprintf(out, "  %-22s n=%llu median=%.1fus p99=%.1fus max=%.1fus mean=%.1fus\n", t->name, (unsigned long long)t->n,
          rs_timing_pct_us(t, 50), rs_timing_pct_us(t, 99), (double)t->max_ns / 1000.0,
          (double)t->sum_ns / 1000.0 / (double)t->n);
}

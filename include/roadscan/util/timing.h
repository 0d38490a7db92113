/* timing.h - CLOCK_MONOTONIC stage timings: count, max, mean and a fixed
 * window of the latest samples for median/p99 at summary time. Each
 * rs_timing_t is written by one thread only; read after it is joined. */
#ifndef ROADSCAN_TIMING_H
#define ROADSCAN_TIMING_H

#include <stdint.h>
#include <stdio.h>

#define RS_TIMING_WINDOW 8192

typedef struct {
  const char *name;
  uint64_t n;
  int64_t sum_ns, max_ns;
  int64_t win[RS_TIMING_WINDOW];
} rs_timing_t;

int64_t rs_now_ns(void);
void rs_timing_init(rs_timing_t *t, const char *name);
void rs_timing_add(rs_timing_t *t, int64_t ns);
/* Percentile (0..100) of the window; sorts a copy (summary time only). */
double rs_timing_pct_us(const rs_timing_t *t, double pct);
/* "name: n=.. median=..us p99=..us max=..us mean=..us" */
void rs_timing_print(const rs_timing_t *t, FILE *out);

#endif

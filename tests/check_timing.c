/* check_timing - stage timings: count, mean, max, percentiles of the window
 * on known samples, the window's wrap, the monotonic clock, the printed line. */
#include "roadscan/util/timing.h"
#include "testutil.h"

#include <stdlib.h>
#include <string.h>

static rs_timing_t t;

START_TEST(t_known_samples) {
  rs_timing_init(&t, "stage/frame");
  ck_assert_double_eq(rs_timing_pct_us(&t, 50), 0.0); /* empty */
  for (int i = 1; i <= 100; i++) rs_timing_add(&t, (int64_t)i * 1000); /* 1..100 us */
  ck_assert_uint_eq(t.n, 100);
  ck_assert_int_eq(t.max_ns, 100000);
  ck_assert_int_eq(t.sum_ns, 5050 * 1000);
  const double med = rs_timing_pct_us(&t, 50), p99 = rs_timing_pct_us(&t, 99);
  ck_assert(med >= 50.0 && med <= 51.0);
  ck_assert(p99 >= 99.0 && p99 <= 100.0);
  ck_assert_double_eq(rs_timing_pct_us(&t, 100), 100.0);
  ck_assert_double_eq(rs_timing_pct_us(&t, 0), 1.0);
  char *buf = NULL;
  size_t len = 0;
  FILE *f = open_memstream(&buf, &len);
  rs_timing_print(&t, f);
  fclose(f);
  ck_assert_ptr_nonnull(strstr(buf, "stage/frame"));
  ck_assert_ptr_nonnull(strstr(buf, "n=100"));
  ck_assert_ptr_nonnull(strstr(buf, "max=100.0us"));
  ck_assert_ptr_nonnull(strstr(buf, "mean=50.5us"));
  free(buf);
}
END_TEST

/* the window keeps the latest samples; the count, sum and max keep all */
START_TEST(t_window_wraps) {
  rs_timing_init(&t, "x");
  for (int i = 0; i < RS_TIMING_WINDOW; i++) rs_timing_add(&t, 1000000); /* 1 ms */
  for (int i = 0; i < RS_TIMING_WINDOW; i++) rs_timing_add(&t, 2000);    /* then 2 us */
  ck_assert_uint_eq(t.n, 2 * RS_TIMING_WINDOW);
  ck_assert_int_eq(t.max_ns, 1000000);
  ck_assert_double_eq(rs_timing_pct_us(&t, 99), 2.0);
}
END_TEST

START_TEST(t_monotonic) {
  int64_t a = rs_now_ns();
  for (int i = 0; i < 1000; i++) {
    int64_t b = rs_now_ns();
    ck_assert_int_ge(b, a);
    a = b;
  }
  ck_assert_int_gt(a, 0);
}
END_TEST

int main(void) {
  Suite *s = suite_create("timing");
  TCase *tc = tcase_create("core");
  tcase_add_test(tc, t_known_samples);
  tcase_add_test(tc, t_window_wraps);
  tcase_add_test(tc, t_monotonic);
  suite_add_tcase(s, tc);
  return tu_run(s);
}

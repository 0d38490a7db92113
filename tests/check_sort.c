/* check_sort - the processing thread's heapsort against glibc's qsort. */
#include "roadscan/util/sort.h"
#include "testutil.h"

#include <stdint.h>
#include <stdlib.h>
#include <string.h>

typedef struct {
  float x, y;
} pt_t;

static int cmp_pt(const void *a, const void *b) {
  const pt_t *p = a, *q = b;
  if (p->x != q->x) return p->x < q->x ? -1 : 1;
  return (p->y > q->y) - (p->y < q->y);
}

static int cmp_u64(const void *a, const void *b) {
  uint64_t x = *(const uint64_t *)a, y = *(const uint64_t *)b;
  return (x > y) - (x < y);
}

START_TEST(t_matches_qsort) {
  static pt_t a[5000], b[5000];
  static uint64_t u[3001], v[3001];
  srand(7);
  const size_t sizes[] = {0, 1, 2, 3, 17, 1000, 5000};
  for (size_t t = 0; t < sizeof sizes / sizeof sizes[0]; t++) {
    size_t n = sizes[t];
    for (size_t i = 0; i < n; i++) {
      a[i].x = (float)(rand() % 50); /* many equal keys */
      a[i].y = (float)(rand() % 1000) * 0.5f;
    }
    memcpy(b, a, n * sizeof a[0]);
    rs_sort(a, n, sizeof a[0], cmp_pt);
    qsort(b, n, sizeof b[0], cmp_pt);
    ck_assert_int_eq(memcmp(a, b, n * sizeof a[0]), 0);
  }
  /* sorted, reversed and constant inputs */
  for (int kind = 0; kind < 3; kind++) {
    for (size_t i = 0; i < 3001; i++) u[i] = kind == 0 ? i : kind == 1 ? 3001 - i : 42;
    memcpy(v, u, sizeof u);
    rs_sort(u, 3001, sizeof u[0], cmp_u64);
    qsort(v, 3001, sizeof v[0], cmp_u64);
    ck_assert_int_eq(memcmp(u, v, sizeof u), 0);
  }
}
END_TEST

int main(void) {
  Suite *s = suite_create("sort");
  TCase *tc = tcase_create("core");
  tcase_add_test(tc, t_matches_qsort);
  suite_add_tcase(s, tc);
  return tu_run(s);
}

/* check_sort - the processing thread's heapsort against glibc's qsort. */
#include "roadscan/util/assign.h"
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

/* the optimal assignment against every permutation, on random 6 x 6 matrices */
static double best_by_brute_force(const double *c, int n, int row, unsigned used, double acc) {
  if (row == n) return acc;
  double best = 1e300;
  for (int j = 0; j < n; j++) {
    if (used & (1u << j)) continue;
    const double v = best_by_brute_force(c, n, row + 1, used | (1u << j), acc + c[row * n + j]);
    if (v < best) best = v;
  }
  return best;
}

START_TEST(t_assignment_is_optimal) {
  uint64_t rng = 12345;
  for (int trial = 0; trial < 200; trial++) {
    const int n = 1 + trial % 6;
    double c[36];
    for (int i = 0; i < n * n; i++) {
      rng = rng * 6364136223846793005ull + 1442695040888963407ull;
      c[i] = (double)((rng >> 33) % 1000) - (trial % 2 ? 500.0 : 0.0);
    }
    int a[6], iw[14];
    double w[21];
    unsigned char used[7];
    rs_assign_min(c, n, (size_t)n, a, w, iw, used);
    double sum = 0;
    unsigned cols = 0;
    for (int i = 0; i < n; i++) {
      ck_assert(a[i] >= 0 && a[i] < n);
      ck_assert(!(cols & (1u << a[i]))); /* a permutation */
      cols |= 1u << a[i];
      sum += c[i * n + a[i]];
    }
    ck_assert_double_eq(sum, best_by_brute_force(c, n, 0, 0, 0.0));
  }
}
END_TEST

int main(void) {
  Suite *s = suite_create("sort");
  TCase *tc = tcase_create("core");
  tcase_add_test(tc, t_matches_qsort);
  tcase_add_test(tc, t_assignment_is_optimal);
  suite_add_tcase(s, tc);
  return tu_run(s);
}

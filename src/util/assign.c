/* assign.c - the Hungarian algorithm (assign.h). Rows and columns are
 * numbered from 1 inside, 0 being the virtual start column. */
#include "roadscan/util/assign.h"

#include <math.h>

void rs_assign_min(const double *cost, int n, size_t stride, int *row_to_col, double *work, int *iwork,
                   unsigned char *used) {
  double *u = work, *v = work + n + 1, *minv = work + 2 * (n + 1);
  int *p = iwork, *way = iwork + n + 1;
  for (int j = 0; j <= n; j++) u[j] = v[j] = 0, p[j] = 0, way[j] = 0;
  for (int i = 1; i <= n; i++) {
    p[0] = i;
    int j0 = 0;
    for (int j = 0; j <= n; j++) minv[j] = INFINITY, used[j] = 0;
    for (int guard = 0; guard <= n + 1; guard++) { /* at most n + 1 steps */
      used[j0] = 1;
      const int i0 = p[j0];
      int j1 = 0;
      double delta = INFINITY;
      for (int j = 1; j <= n; j++) {
        if (used[j]) continue;
        const double cur = cost[(size_t)(i0 - 1) * stride + (size_t)(j - 1)] - u[i0] - v[j];
        if (cur < minv[j]) minv[j] = cur, way[j] = j0;
        if (minv[j] < delta) delta = minv[j], j1 = j;
      }
      for (int j = 0; j <= n; j++) {
        if (used[j]) u[p[j]] += delta, v[j] -= delta;
        else minv[j] -= delta;
      }
      j0 = j1;
      if (p[j0] == 0) break;
    }
    for (int guard = 0; guard <= n && j0; guard++) {
      const int j1 = way[j0];
      p[j0] = p[j1];
      j0 = j1;
    }
  }
  for (int i = 0; i < n; i++) row_to_col[i] = -1;
  for (int j = 1; j <= n; j++)
    if (p[j] > 0) row_to_col[p[j] - 1] = j - 1;
}

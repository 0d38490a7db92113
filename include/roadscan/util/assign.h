/* assign.h - the optimal assignment (Hungarian algorithm: shortest
 * augmenting paths with potentials) of an n x n cost matrix. Used by the
 * tracker (processing thread, n <= RS_TRACK_GROUP_MAX, work on the stack of
 * its caller's static sizes) and the evaluator (IDF1's pairing). No
 * allocation; O(n^3); every loop bounded by n. */
#ifndef ROADSCAN_ASSIGN_H
#define ROADSCAN_ASSIGN_H

#include <stddef.h>

/* Minimises the sum of cost[i * stride + row_to_col[i]]; row_to_col[i] is the
 * column of row i. work: 3 (n + 1) doubles; iwork: 2 (n + 1) ints; used: n + 1
 * bytes. */
void rs_assign_min(const double *cost, int n, size_t stride, int *row_to_col, double *work, int *iwork,
                   unsigned char *used);

#endif

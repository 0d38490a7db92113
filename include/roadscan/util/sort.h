/* sort.h - an in-place heapsort for the processing thread.
 *
 * glibc's qsort is a merge sort that mallocs a buffer for arrays over a
 * few hundred bytes: not allowed after start-up. This one allocates
 * nothing, needs no recursion, and takes O(n log n) whatever the input.
 * Not stable. Elements up to RS_SORT_MAX_ELEM bytes. */
#ifndef ROADSCAN_SORT_H
#define ROADSCAN_SORT_H

#include <stddef.h>

#define RS_SORT_MAX_ELEM 64

void rs_sort(void *base, size_t n, size_t size, int (*cmp)(const void *, const void *));

#endif

/* rand.h - a small pseudo-random sequence for the pipeline's own draws
 * (reservoir sampling of frames, the ground plane's RANSAC): xorshift64, no
 * state but the caller's 64-bit word (never 0), the same sequence on every
 * machine. Any thread; no allocation. */
#ifndef ROADSCAN_RAND_H
#define ROADSCAN_RAND_H

#include <stdint.h>

static inline uint64_t rs_xorshift64(uint64_t *s) {
  *s ^= *s << 13;
  *s ^= *s >> 7;
  *s ^= *s << 17;
  return *s;
}

#endif

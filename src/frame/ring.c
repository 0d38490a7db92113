/* ring.c - lock-free SPSC hand-off of frame slots with drop-oldest. */
#include "roadscan/frame/ring.h"

#include "roadscan/util/error.h"

#include <errno.h>
#include <time.h>

int rs_ring_init(rs_ring_t *r, int nslots, bool lossless, bool newest) {
  if (nslots < 3 || nslots > RS_RING_MAX_SLOTS) return RS_E_INVAL;
  r->nslots = nslots;
  r->lossless = lossless;
  r->newest = newest;
  for (int i = 0; i < RS_RING_MAX_SLOTS; i++) {
    atomic_init(&r->state[i], RS_SLOT_FREE);
    atomic_init(&r->queue[i], -1);
  }
  atomic_init(&r->head, 0);
  atomic_init(&r->tail, 0);
  atomic_init(&r->dropped, 0);
  atomic_init(&r->published, 0);
  if (sem_init(&r->ready, 0, 0) != 0) return RS_E_THREAD;
  if (sem_init(&r->freed, 0, 0) != 0) {
    sem_destroy(&r->ready);
    return RS_E_THREAD;
  }
  return RS_OK;
}

void rs_ring_deinit(rs_ring_t *r) {
  sem_destroy(&r->ready);
  sem_destroy(&r->freed);
}

static int claim_free(rs_ring_t *r) {
  for (int i = 0; i < r->nslots; i++) {
    int expect = RS_SLOT_FREE;
    if (atomic_compare_exchange_strong(&r->state[i], &expect, RS_SLOT_FILLING)) return i;
  }
  return -1;
}

/* Takes the oldest queued index off the tail; -1 if the queue is empty. */
static int pop_tail(rs_ring_t *r) {
  for (int tries = 0; tries < 2 * RS_RING_MAX_SLOTS + 2; tries++) {
    uint64_t t = atomic_load_explicit(&r->tail, memory_order_acquire);
    uint64_t h = atomic_load_explicit(&r->head, memory_order_acquire);
    if (t == h) return -1;
    int idx = atomic_load_explicit(&r->queue[t % (uint64_t)r->nslots], memory_order_relaxed);
    if (atomic_compare_exchange_strong(&r->tail, &t, t + 1)) return idx;
  }
  return -1; /* lost every race: the other side is taking frames */
}

static void timespec_in(struct timespec *ts, int ms) {
  clock_gettime(CLOCK_REALTIME, ts); /* sem_timedwait uses CLOCK_REALTIME */
  ts->tv_sec += ms / 1000;
  ts->tv_nsec += (long)(ms % 1000) * 1000000L;
  if (ts->tv_nsec >= 1000000000L) {
    ts->tv_sec++;
    ts->tv_nsec -= 1000000000L;
  }
}

int rs_ring_acquire(rs_ring_t *r, const _Atomic bool *stop) {
  if (r->lossless) {
    /* analysis mode: wait for the consumer (bounded by the stop request) */
    for (;;) {
      int i = claim_free(r);
      if (i >= 0) return i;
      if (stop != NULL && atomic_load(stop)) return -1;
      struct timespec ts;
      timespec_in(&ts, 50);
      while (sem_timedwait(&r->freed, &ts) != 0 && errno == EINTR) {
      }
    }
  }
  /* real time: never wait. With N >= 3 slots, the producer holding none and
   * the consumer at most one, a slot is free or a frame is queued; each try
   * either claims one or loses a race to the consumer, which then frees one. */
  for (int tries = 0; tries < 4 * RS_RING_MAX_SLOTS; tries++) {
    int i = claim_free(r);
    if (i >= 0) return i;
    int old = pop_tail(r);
    if (old >= 0) {
      atomic_fetch_add(&r->dropped, 1);
      atomic_store_explicit(&r->state[old], RS_SLOT_FILLING, memory_order_release);
      return old;
    }
  }
  return -1;
}

void rs_ring_publish(rs_ring_t *r, int slot) {
  atomic_store_explicit(&r->state[slot], RS_SLOT_QUEUED, memory_order_release);
  uint64_t h = atomic_load_explicit(&r->head, memory_order_relaxed);
  atomic_store_explicit(&r->queue[h % (uint64_t)r->nslots], slot, memory_order_relaxed);
  atomic_store_explicit(&r->head, h + 1, memory_order_release);
  atomic_fetch_add(&r->published, 1);
  sem_post(&r->ready);
}

void rs_ring_discard(rs_ring_t *r, int slot) {
  atomic_store_explicit(&r->state[slot], RS_SLOT_FREE, memory_order_release);
  sem_post(&r->freed);
}

static int take_queued(rs_ring_t *r) {
  int idx = pop_tail(r);
  if (idx < 0) return -1;
  if (r->newest) {
    int newer;
    while ((newer = pop_tail(r)) >= 0) { /* bounded by the queue length */
      atomic_fetch_add(&r->dropped, 1);
      rs_ring_release(r, idx);
      idx = newer;
    }
  }
  atomic_store_explicit(&r->state[idx], RS_SLOT_PROCESSING, memory_order_release);
  return idx;
}

int rs_ring_take(rs_ring_t *r, int timeout_ms) {
  int idx = take_queued(r);
  if (idx >= 0 || timeout_ms <= 0) return idx;
  struct timespec ts;
  timespec_in(&ts, timeout_ms);
  while (sem_timedwait(&r->ready, &ts) != 0 && errno == EINTR) {
  }
  return take_queued(r);
}

void rs_ring_release(rs_ring_t *r, int slot) {
  atomic_store_explicit(&r->state[slot], RS_SLOT_FREE, memory_order_release);
  sem_post(&r->freed);
}

uint64_t rs_ring_dropped(const rs_ring_t *r) { return atomic_load(&r->dropped); }

int rs_ring_queued(const rs_ring_t *r) {
  return (int)(atomic_load(&r->head) - atomic_load(&r->tail));
}

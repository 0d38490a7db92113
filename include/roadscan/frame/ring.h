/* ring.h - hand-off of frame slots from the packet thread (producer) to the
 * processing thread (consumer).
 *
 * N preallocated slots. The producer always owns one slot (the frame being
 * filled); the consumer owns at most one (the frame being processed); the
 * others are free or queued. The queue is a ring of slot indices with a
 * monotonically increasing head (written by the producer only) and tail
 * (advanced by CAS by the consumer when it takes a frame, and by the
 * producer when it drops the oldest queued frame because no slot is free).
 * No locks; the producer never waits unless the ring is in lossless mode
 * (offline analysis), where it waits for the consumer to free a slot.
 * The consumer sleeps on a semaphore posted on every publish. */
#ifndef ROADSCAN_RING_H
#define ROADSCAN_RING_H

#include <semaphore.h>
#include <stdatomic.h>
#include <stdbool.h>
#include <stdint.h>

#define RS_RING_MAX_SLOTS 8

typedef enum { RS_SLOT_FREE = 0, RS_SLOT_FILLING, RS_SLOT_QUEUED, RS_SLOT_PROCESSING } rs_slot_state_t;

typedef struct {
  int nslots;
  bool lossless;                      /* producer waits instead of dropping */
  bool newest;                        /* consumer skips to the newest queued frame */
  _Atomic int state[RS_RING_MAX_SLOTS];
  _Atomic int queue[RS_RING_MAX_SLOTS]; /* a stale read loses its CAS on tail */
  _Atomic uint64_t head, tail;
  _Atomic uint64_t dropped;           /* frames dropped (queue full or skipped as stale) */
  _Atomic uint64_t published;
  sem_t ready;                        /* posted per published frame */
  sem_t freed;                        /* posted per freed slot (lossless mode) */
} rs_ring_t;

/* nslots: 3..RS_RING_MAX_SLOTS. */
int rs_ring_init(rs_ring_t *r, int nslots, bool lossless, bool newest);
void rs_ring_deinit(rs_ring_t *r);

/* Producer: a slot to fill (FILLING). Never blocks unless lossless; then it
 * waits until a slot is freed or *stop becomes true (-1). Drops the oldest
 * queued frame when nothing is free. -1 in real-time mode only if the ring
 * is misused (the producer already holds every slot). */
int rs_ring_acquire(rs_ring_t *r, const _Atomic bool *stop);
/* Producer: queues a filled slot for the consumer. */
void rs_ring_publish(rs_ring_t *r, int slot);
/* Producer: gives back a slot it will not publish. */
void rs_ring_discard(rs_ring_t *r, int slot);

/* Consumer: takes a queued frame (PROCESSING); waits up to timeout_ms once
 * (a wake-up may come early). Returns the slot index, or -1 when none. In `newest` mode older queued
 * frames are freed and counted as dropped. */
int rs_ring_take(rs_ring_t *r, int timeout_ms);
/* Consumer: done with a slot. */
void rs_ring_release(rs_ring_t *r, int slot);

uint64_t rs_ring_dropped(const rs_ring_t *r);
/* Frames queued and not yet taken. */
int rs_ring_queued(const rs_ring_t *r);

#endif

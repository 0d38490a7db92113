/* framer.h - from a capture file to complete frames, for tools.
 *
 * The stream (parse, detect, decode) feeding the frame assembler, with the
 * slot swap at every roll-over and the measured rotation rate handed back
 * to the decoder: the loop every offline tool needs, written once. The
 * caller owns the framer and its two slots (static in the programs: a slot
 * is several MB) and gets each finished frame, partial ones included (their
 * meta.partial says so), in a callback; the slot is only valid during it.
 * Single-threaded (a tool's main loop); the daemon's packet thread does the
 * same through the ring (pipeline.c). */
#ifndef ROADSCAN_FRAMER_H
#define ROADSCAN_FRAMER_H

#include "roadscan/frame/frame.h"
#include "roadscan/capture/stream.h"

#include <stdbool.h>

typedef void (*rs_framer_fn)(void *user, rs_slot_t *slot);
/* Optional: every packet once the assembler has taken it, with the frame each of its blocks went to
 * (block_seq[b], RS_ASM_DROPPED for none): a tool that needs the decoded points themselves (not the
 * map) frames them exactly as the daemon does. */
typedef void (*rs_framer_packet_fn)(void *user, const rs_packet_t *pkt, uint32_t index, const uint64_t *block_seq);

typedef struct {
  rs_stream_t stream;
  rs_asm_t as;
  rs_asm_cfg_t acfg;
  bool ready;          /* the assembler is set up (the model is known) */
  bool flush_last;     /* hand the last, partial frame over at the end of input */
  rs_slot_t *slots;    /* [2], the caller's */
  int cur;
  rs_framer_fn fn;         /* may be NULL (the packet hook alone) */
  rs_framer_packet_fn on_packet;
  void *user;
  bool stop;           /* set by the callback (or anyone) to end the replay early */
  int rc;              /* first assembler error */
} rs_framer_t;

/* slots: two caller-owned slots. RS_OK, or an error with f->stream.err set. */
int rs_framer_init(rs_framer_t *f, const rs_stream_cfg_t *scfg, const rs_asm_cfg_t *acfg, rs_slot_t *slots,
                   rs_framer_fn fn, void *user);
/* For a caller that decodes packets itself (the bench times decoding apart): the assembler set up
 * for the sensor s at once, no stream; then rs_framer_feed for every decoded packet. */
int rs_framer_start(rs_framer_t *f, const rs_asm_cfg_t *acfg, const rs_sensor_t *s, rs_slot_t *slots, rs_framer_fn fn,
                    void *user);
/* One decoded packet: fed until consumed, fn at every finished frame, the slots swapped, the measured
 * rate kept for the decoder (f->as.rate; the stream's rate hint). */
void rs_framer_feed(rs_framer_t *f, const rs_packet_t *pkt, uint32_t index, double ts);
/* Replays a capture flat out through fn. Returns rs_stream_replay_file's
 * status (err names the problem), or the assembler's error. */
int rs_framer_replay_file(rs_framer_t *f, const char *path, char *err, size_t n);

#endif

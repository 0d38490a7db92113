/* framer.c - stream -> assembler -> frame callback, for tools (one thread). */
#include "roadscan/frame/framer.h"

#include "roadscan/util/error.h"

#include <stdio.h>
#include <string.h>

static void setup(rs_framer_t *f, const rs_asm_cfg_t *acfg, rs_slot_t *slots, rs_framer_fn fn, void *user) {
  memset(f, 0, sizeof *f);
  f->acfg = *acfg;
  if (f->acfg.default_hz <= 0) f->acfg.default_hz = 10.0;
  f->slots = slots;
  f->fn = fn;
  f->user = user;
}

int rs_framer_init(rs_framer_t *f, const rs_stream_cfg_t *scfg, const rs_asm_cfg_t *acfg, rs_slot_t *slots,
                   rs_framer_fn fn, void *user) {
  setup(f, acfg, slots, fn, user);
  return rs_stream_init(&f->stream, scfg);
}

int rs_framer_start(rs_framer_t *f, const rs_asm_cfg_t *acfg, const rs_sensor_t *s, rs_slot_t *slots, rs_framer_fn fn,
                    void *user) {
  setup(f, acfg, slots, fn, user);
  f->rc = rs_asm_init(&f->as, &f->acfg, s);
  f->ready = f->rc == RS_OK;
  return f->rc;
}

void rs_framer_feed(rs_framer_t *f, const rs_packet_t *pkt, uint32_t index, double ts) {
  /* bounded: every FRAME_DONE resumes at least one block further */
  for (int i = 0; i <= RS_BLOCKS; i++) {
    if (rs_asm_feed(&f->as, &f->slots[f->cur], pkt, index, ts) == RS_ASM_CONSUMED) break;
    if (f->fn) f->fn(f->user, &f->slots[f->cur]);
    f->cur ^= 1;
  }
  f->stream.rate_hint = f->as.rate;
  if (f->on_packet) f->on_packet(f->user, pkt, index, f->as.block_seq);
}

static void on_packet(void *user, const rs_packet_t *pkt, uint32_t index, double ts) {
  rs_framer_t *f = user;
  if (f->rc != RS_OK || f->stop) return;
  if (!f->ready) {
    f->rc = rs_asm_init(&f->as, &f->acfg, &f->stream.sensor);
    if (f->rc != RS_OK) return;
    f->ready = true;
  }
  rs_framer_feed(f, pkt, index, ts);
}

int rs_framer_replay_file(rs_framer_t *f, const char *path, char *err, size_t n) {
  int rc = rs_stream_replay_file(&f->stream, path, on_packet, f, &f->stop, err, n);
  if (f->rc != RS_OK) {
    snprintf(err, n, "frame assembly: %s", rs_strerror(f->rc));
    return f->rc;
  }
  if (f->ready && f->flush_last && !f->stop && rs_asm_flush(&f->as, &f->slots[f->cur]) && f->fn)
    f->fn(f->user, &f->slots[f->cur]);
  return rc;
}

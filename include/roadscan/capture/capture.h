/* capture.h - libpcap sources: live interface or capture file (pcap/pcapng).
 *
 * Owned by the packet thread. Opening happens at start-up (may allocate,
 * inside libpcap); reading returns pointers into libpcap's buffer, valid
 * until the next read. Replay pacing (original timing x speed) is done here
 * with CLOCK_MONOTONIC absolute sleeps, so the packet thread stays simple. */
#ifndef ROADSCAN_CAPTURE_H
#define ROADSCAN_CAPTURE_H

#include <stdatomic.h>
#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>
#include <time.h>

#include "roadscan/util/error.h"

typedef struct pcap pcap_t;

typedef struct {
  uint16_t data_port;       /* BPF and classification: UDP destination port */
  const char *source_addr;  /* optional sensor address filter (live BPF + checked per packet) */
  double speed;             /* replay: 1.0 = original timing; 0 = flat out */
  bool loop;                /* replay: start again at the end */
  int snaplen;
} rs_capture_cfg_t;

/* Paced replay waits for the capture's timing, but never for a jump in it:
 * a record more than this many seconds after (or before) the previous one
 * is sent right after it, and the jump is counted. */
#define RS_CAPTURE_MAX_GAP_S 1.0

typedef struct {
  pcap_t *p;
  bool live;
  int linktype;
  rs_capture_cfg_t cfg;
  char path[512];
  /* pacing */
  bool have_t0;
  double t0_cap;            /* capture time of the first packet (s) */
  struct timespec t0_mono;
  double loop_offset;       /* added to capture times after a loop */
  double last_ts;
  uint64_t loops;
  uint64_t jumps;           /* paced replay: timestamp jumps not waited for (> RS_CAPTURE_MAX_GAP_S) */
  double jump_max;          /* the largest, s (either way) */
  char err[RS_ERRMSG_SIZE];
} rs_capture_t;

typedef struct {
  const uint8_t *data;
  uint32_t caplen, wirelen;
  double ts;                /* capture time (s), loop offset included */
} rs_frame_in_t;

int rs_capture_open_file(rs_capture_t *c, const char *path, const rs_capture_cfg_t *cfg);
int rs_capture_open_live(rs_capture_t *c, const char *iface, const rs_capture_cfg_t *cfg);
void rs_capture_close(rs_capture_t *c);

/* 1: a frame; 0: nothing within the poll interval (live) or stop requested;
 * RS_E_IO/RS_E_TRUNCATED with c->err set: read error (a truncated file ends
 * here); RS_CAPTURE_EOF: end of file (and no loop). Paces replay. */
#define RS_CAPTURE_EOF 2
int rs_capture_next(rs_capture_t *c, rs_frame_in_t *out, const _Atomic bool *stop);

/* "udp dst port N [and src host A]" */
void rs_capture_filter(const rs_capture_cfg_t *cfg, char *buf, size_t n);

#endif

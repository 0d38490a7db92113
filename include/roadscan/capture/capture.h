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
  int buffer_bytes;         /* live: the kernel's capture buffer (0: RS_CAPTURE_BUFFER_DEFAULT) */
} rs_capture_cfg_t;

/* The kernel's buffer between the interface and the packet thread (live):
 * what a stall of the packet thread can absorb before the kernel drops. */
#define RS_CAPTURE_BUFFER_DEFAULT (16 * 1024 * 1024)
#define RS_CAPTURE_BUFFER_MIN (64 * 1024)
#define RS_CAPTURE_BUFFER_MAX (1024 * 1024 * 1024)

/* What the kernel counted for a live capture (pcap_stats): packets that
 * passed the filter, packets it dropped because the buffer was full, and
 * packets the interface dropped. */
typedef struct {
  uint64_t received, dropped, if_dropped;
} rs_capture_kstats_t;

/* Paced replay waits for the capture's timing, but never for a jump in it:
 * a record more than this many seconds after (or before) the previous one
 * is sent right after it, and the jump is counted. */
#define RS_CAPTURE_MAX_GAP_S 1.0

typedef struct {
  pcap_t *p;
  bool live;
  int linktype;
  double ts_unit;           /* seconds per unit of a record's sub-second field (1e-9 or 1e-6) */
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
  int buffer_bytes;         /* live: the buffer asked for */
  rs_capture_kstats_t kstats; /* live: the latest rs_capture_kstats */
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

/* Live: refreshes c->kstats from the kernel (packet thread: libpcap's
 * handle is not shared). Returns false for a file or when the kernel says
 * nothing. Cheap (one getsockopt): call it once per frame. */
bool rs_capture_kstats(rs_capture_t *c);

/* "udp dst port N [and src host A]" */
void rs_capture_filter(const rs_capture_cfg_t *cfg, char *buf, size_t n);

#endif

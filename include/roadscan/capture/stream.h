/* stream.h - from captured frames to decoded data packets.
 *
 * Owned by the packet thread (or a tool's main loop). Per captured frame:
 * link/IP/UDP parsing, classification (data port, position port, other),
 * optional source address filter, data-packet indexing (the address space of
 * specs/point-labels.md), model detection, decoding, and error counting by
 * kind. While the model is undecided, data packets wait in a bounded
 * pre-buffer (RS_DETECT_MAX_PACKETS) and are decoded, in order, once it is
 * decided: nothing is lost to detection. The first error of each kind is
 * logged with its packet number; later ones are only counted.
 *
 * A data packet of another model than the stream's (its product byte) is
 * counted and dropped: a second sensor on the same port (give --source). When
 * RS_STREAM_SWITCH_PACKETS such packets come in a row, none of the stream's
 * own between them, the sensor was switched: the stream stops with
 * RS_E_SENSOR_CHANGED (the map, calibration and background were the old
 * sensor's; a restart identifies the new one). */
#ifndef ROADSCAN_STREAM_H
#define ROADSCAN_STREAM_H

#include "roadscan/sensor/calib.h"
#include "roadscan/capture/capture.h"
#include "roadscan/util/error.h"
#include "roadscan/sensor/packet.h"

#include <stdbool.h>
#include <stdint.h>
#include <stdio.h>

typedef struct {
  uint16_t data_port;          /* default 2368 */
  uint16_t position_port;      /* default 8308 */
  rs_model_t force_model;      /* RS_MODEL_UNKNOWN = detect */
  const rs_calib_t *calib;     /* optional, applied when the model is known */
  const char *source_addr;     /* optional IPv4/IPv6 address the sensor sends from */
  double default_hz;           /* rotation rate assumed until measured */
  FILE *log;                   /* first-of-a-kind messages (NULL: silent) */
} rs_stream_cfg_t;

/* Consecutive data packets of one other known model that end a stream: about
 * 0.3 s of the slowest model's packets, far more than any interleaving. */
#define RS_STREAM_SWITCH_PACKETS 500

typedef void (*rs_stream_emit_fn)(void *user, const rs_packet_t *pkt, uint32_t index, double ts);

typedef struct {
  uint64_t frames;             /* captured frames seen */
  uint64_t data_packets;       /* 1206-byte payloads to the data port (indexed) */
  uint64_t decoded;            /* data packets decoded and emitted */
  uint64_t position_packets;
  uint64_t other_packets;      /* not UDP to our ports, or another source */
  uint64_t errors[RS_ERR_COUNT];
} rs_stream_counters_t;

typedef struct {
  rs_stream_cfg_t cfg;
  rs_detect_t det;
  rs_sensor_t sensor;
  bool sensor_ready;
  bool failed;                 /* the stream cannot go on: fail_code, err */
  int fail_code;               /* RS_E_CALIB (calibration mismatch) or RS_E_SENSOR_CHANGED */
  bool have_src;
  uint8_t src_ver;
  uint8_t src_addr[16];
  float rate_hint;             /* degrees/µs, kept up to date by the caller */
  uint32_t next_index;
  int npre;
  uint8_t pre[RS_DETECT_MAX_PACKETS][RS_PAYLOAD_SIZE];
  uint32_t pre_index[RS_DETECT_MAX_PACKETS];
  double pre_ts[RS_DETECT_MAX_PACKETS];
  rs_packet_t pkt;             /* decode buffer */
  uint32_t foreign_run;        /* data packets of another model in a row */
  uint32_t foreign_first;      /* index of the first of them */
  rs_stream_counters_t n;
  char err[RS_ERRMSG_SIZE];               /* last fatal message */
} rs_stream_t;

int rs_stream_init(rs_stream_t *st, const rs_stream_cfg_t *cfg);
/* One captured frame. Returns RS_OK (also when the frame was counted as an
 * error or ignored), or when the stream cannot go on (st->err) RS_E_CALIB
 * (the calibration does not fit the sensor) or RS_E_SENSOR_CHANGED. */
int rs_stream_frame(rs_stream_t *st, int linktype, const rs_frame_in_t *f, rs_stream_emit_fn emit, void *user);
/* One UDP payload already taken off the wire (the same path after parsing). */
int rs_stream_payload(rs_stream_t *st, const uint8_t *payload, uint32_t len, uint16_t dst_port, double ts,
                      rs_stream_emit_fn emit, void *user);
/* End of input: decides the model with what was seen and drains the pre-buffer. */
int rs_stream_finish(rs_stream_t *st, rs_stream_emit_fn emit, void *user);
/* Replays a capture file flat out: every captured frame through the stream
 * (emit per decoded packet), then rs_stream_finish. Stops early when *stop
 * (optional) becomes true. RS_OK; a read error with err set (a truncated
 * file after everything before the cut was emitted); RS_E_CALIB or
 * RS_E_SENSOR_CHANGED with err set. */
int rs_stream_replay_file(rs_stream_t *st, const char *path, rs_stream_emit_fn emit, void *user, const bool *stop,
                          char *err, size_t n);
/* Counts an error of a kind (and logs the first one). */
void rs_stream_count(rs_stream_t *st, int code, const char *detail);
/* Prints "key=count" pairs of non-zero error counters. */
void rs_stream_print_errors(const rs_stream_counters_t *n, FILE *out);
uint64_t rs_stream_error_total(const rs_stream_counters_t *n);

#endif

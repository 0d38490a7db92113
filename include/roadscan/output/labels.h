/* labels.h - point-label files (../shared/specs/point-labels.md): a header
 * "packet,block,channel,label", optional leading '#' comments, then one
 * line per point with label >= 2, sorted by address, each address once.
 *
 * The reader validates every line and names the file and line of the first
 * problem. The writer refuses (and counts) lines out of order. Used by the
 * simulator, the evaluator and the daemon's --labels-out (processing thread;
 * writing is buffered stdio, no allocation after open). */
#ifndef ROADSCAN_LABELS_H
#define ROADSCAN_LABELS_H

#include "roadscan/util/error.h"
#include "roadscan/frame/frame.h" /* the label values: RS_LABEL_* */

#include <stdbool.h>
#include <stdint.h>
#include <stdio.h>

typedef struct {
  uint32_t packet;
  uint8_t block, channel;
  uint32_t label;
} rs_label_t;

static inline uint64_t rs_label_key(uint32_t packet, int block, int channel) {
  return (uint64_t)packet * 384u + (uint64_t)block * 32u + (uint64_t)channel;
}

typedef struct {
  FILE *f;
  char path[512];
  long line;
  uint32_t max_packets;   /* addresses must be below this packet count */
  bool any;
  uint64_t last_key;
  char err[RS_ERRMSG_SIZE];
} rs_labels_reader_t;

/* max_packets: number of data packets in the capture (UINT32_MAX: no check). */
int rs_labels_open(rs_labels_reader_t *r, const char *path, uint32_t max_packets);
/* 1 and *out, 0 at the end, RS_E_FORMAT with r->err naming path:line. */
int rs_labels_next(rs_labels_reader_t *r, rs_label_t *out);
void rs_labels_close(rs_labels_reader_t *r);

typedef struct {
  FILE *f;
  bool any;
  uint64_t last_key;
  uint64_t written, rejected;
} rs_labels_writer_t;

/* Writes the header, after `comment` lines (each prefixed with "# "), if any. */
int rs_labels_create(rs_labels_writer_t *w, const char *path, const char *comment);
/* RS_OK, or RS_E_INVAL (counted, not written) for label < 2 or an address
 * not after the previous one. */
int rs_labels_write(rs_labels_writer_t *w, uint32_t packet, int block, int channel, uint32_t label);
int rs_labels_finish(rs_labels_writer_t *w);

/* A frame's labelled returns (>= 2), sorted by address with heapsort (no
 * allocation) in buf, caller-owned: RS_LABELS_FRAME_MAX entries. */
typedef struct {
  uint64_t key;
  uint32_t label;
} rs_label_entry_t;
#define RS_LABELS_FRAME_MAX (RS_LAYERS * RS_MAX_CELLS)
/* Returns labelled one by one: cell[j] (ascending) gets value[j] + offset
 * (value 0: noise, 2), whatever its cluster's map says. */
typedef struct {
  const uint32_t *cell, *value;
  uint32_t n, offset;
} rs_labels_cells_t;
/* map: NULL, or the label written for cluster label 3 + k (map[k], k < nmap;
 * 0 = noise, 2); labels beyond nmap are written as 2. cells: NULL, or the
 * returns labelled one by one (with a map). */
void rs_labels_write_frame(rs_labels_writer_t *w, const rs_slot_t *s, rs_label_entry_t *buf, const uint32_t *map,
                           uint32_t nmap, const rs_labels_cells_t *cells);

#endif

/* frame.h - frame slots and frame assembly on azimuth roll-over.
 *
 * A frame slot is a statically allocated spherical map (rows = lasers by
 * elevation, columns = azimuth bins of 360/cols degrees, two layers for dual
 * return) plus the frame's metadata. The assembler is a pure state machine
 * owned by the packet thread: it writes decoded points into the slot it is
 * given and says "frame done" when a block's azimuth rolls over the cut
 * azimuth. The packet that straddles the cut is carried: the caller hands
 * in a fresh slot and feeds the same packet again; the assembler resumes at
 * the first block of the new frame, so no point is lost or counted twice.
 *
 * Columns: with no fixed count configured, the partial frame 0 uses the
 * rate of the first packet; at the first roll-over the count is set from
 * the rate measured over frame 0 and stays constant for the run.
 *
 * Cell (row r, column c) of layer l is at index l * RS_MAX_CELLS + r * cols + c.
 * Column 0 and column cols-1 are neighbours (the map wraps). */
#ifndef ROADSCAN_FRAME_H
#define ROADSCAN_FRAME_H

#include "roadscan/sensor/packet.h"

#include <stdbool.h>
#include <stdint.h>

#define RS_MAX_ROWS RS_MAX_LASERS
#define RS_MAX_COLS 4400 /* HDL-32E at 5 Hz: 4341 firings per turn */
#define RS_MIN_COLS 90
#define RS_MAX_CELLS (RS_MAX_ROWS * RS_MAX_COLS)
#define RS_LAYERS 2
#define RS_DUP_HISTORY 512   /* packets remembered to recognise a duplicate (a VLP-16 turn is 76) */
#define RS_DUP_NEAR 8        /* without sensor timestamps, duplicates are looked for this far back only */

_Static_assert(RS_MAX_COLS <= UINT16_MAX, "columns fit in uint16_t");
_Static_assert((uint64_t)RS_MAX_CELLS * RS_LAYERS < UINT32_MAX, "cell index fits in uint32_t");

/* Labels of the label map (and of the point-label files): */
#define RS_LABEL_NONE 0         /* no return, or not labelled yet */
#define RS_LABEL_STATIC 1       /* the static scene (background) */
#define RS_LABEL_BACKGROUND RS_LABEL_STATIC
#define RS_LABEL_NOISE 2        /* foreground left out of every cluster (truth: foliage, rain, dust) */
#define RS_LABEL_FIRST_OBJECT 3 /* 3 + cluster number (truth: object id) */

typedef struct {
  uint32_t packet;  /* data packet index in the capture */
  uint8_t block;
  uint8_t channel;
} rs_addr_t;

typedef struct {
  uint64_t seq;             /* frame number; 0 = the partial frame before the first roll-over */
  rs_model_t model;
  uint8_t mode_byte;
  bool partial;             /* did not start (frame 0) or end (end of input) on a roll-over */
  uint16_t rows, cols;
  float rate_hz;            /* rotation rate measured over the frame */
  double t_first, t_last;   /* capture time (s) of the first and last packet */
  uint32_t first_packet, last_packet;
  uint16_t first_azimuth;   /* azimuth field of the frame's first block (0.01 degree): where the firings fell this turn */
  uint32_t packets;         /* packets that contributed blocks (a straddling one counts in both) */
  uint32_t points;          /* returns written to the map (both layers) */
  uint32_t columns;         /* columns holding at least one return */
  uint32_t missing_packets; /* judged from azimuth gaps */
  uint32_t out_of_order;    /* packets behind the previous one, kept */
  uint32_t late_points;     /* returns of packets that belong to an earlier frame, dropped */
  uint32_t duplicates;      /* packets seen twice, dropped */
  uint32_t shifted;         /* returns moved to the free neighbour column of an occupied cell */
  uint32_t collisions;      /* returns landing on an occupied cell with no free neighbour (nearer kept) */
  uint64_t dropped_frames;  /* frames dropped by the ring so far (set by the pipeline) */
  int64_t assembled_ns;     /* CLOCK_MONOTONIC when the frame was complete */
  int64_t last_packet_ns;   /* CLOCK_MONOTONIC when its last packet was read (set by the pipeline) */
} rs_frame_meta_t;

typedef struct {
  rs_frame_meta_t meta;
  uint8_t colmask[RS_MAX_COLS];
  /* 1: no firing of this turn fell in the column, taken by block azimuth (a lost packet's blocks, or the
   * partial frame's columns before its first packet or after its last); a firing lands in the map's
   * column of its block azimuth plus its laser's azimuth offset. Set by the assembler; a map made by
   * hand leaves it 0 (every column seen) */
  uint8_t gap[RS_MAX_COLS];
  float range[RS_LAYERS * RS_MAX_CELLS];    /* metres, 0 = no return */
  uint8_t intensity[RS_LAYERS * RS_MAX_CELLS];
  rs_addr_t addr[RS_LAYERS * RS_MAX_CELLS]; /* which record filled the cell */
  uint16_t label[RS_LAYERS * RS_MAX_CELLS]; /* 0 none, 1 background, 2 noise, 3+ object */
} rs_slot_t;

static inline uint32_t rs_cell(const rs_slot_t *s, int layer, int row, int col) {
  return (uint32_t)layer * RS_MAX_CELLS + (uint32_t)row * s->meta.cols + (uint32_t)col;
}

typedef struct {
  int columns;          /* 0 = from the measured rotation rate */
  double cut_deg;       /* frame boundary azimuth, default 0 */
  double default_hz;    /* rate assumed before one is measured (600 rpm) */
} rs_asm_cfg_t;

typedef enum { RS_ASM_CONSUMED = 0, RS_ASM_FRAME_DONE = 1 } rs_asm_result_t;

typedef struct {
  rs_asm_cfg_t cfg;
  const rs_sensor_t *sensor;
  int cols;                 /* 0 until the first packet */
  bool cols_fixed;          /* set at the first roll-over, constant afterwards */
  int cut_cd;               /* cut azimuth in 0.01 degree */
  float rate;               /* degrees per µs, running estimate */
  bool rate_known;
  int32_t last_rel;         /* last block azimuth relative to the cut, -1 = none */
  uint64_t next_seq;
  bool slot_open;           /* the current slot has been initialised */
  int resume_block;         /* first block of the carried packet still to write, -1 none */
  bool counted_packet;      /* the carried packet was counted in the current frame */
  int late_streak;          /* consecutive late packets */
  uint32_t pending_missing; /* missing packets before the packet being written */
  struct { uint32_t ts; uint16_t az; } recent[RS_DUP_HISTORY];
  int recent_n, recent_i;
  bool have_newest;         /* the newest sensor timestamp seen (duplicates are never newer) */
  uint32_t newest_ts;
  bool have_last_ts;        /* the sensor timestamp of the last packet taken in order */
  uint32_t last_ts;
  /* totals over the run */
  uint64_t frames, missing_packets, out_of_order, duplicates, late_points, collisions;
  /* per block of the packet being fed: the frame (seq) that took its returns, or RS_ASM_DROPPED (a
   * duplicate, a late packet, no such block); final once the packet is consumed */
  uint64_t block_seq[RS_BLOCKS];
} rs_asm_t;

#define RS_ASM_DROPPED UINT64_MAX

/* Columns for a rotation rate: enough bins for every firing (rounded up to
 * a multiple of 10), within RS_MIN_COLS..RS_MAX_COLS. */
int rs_frame_columns_for(const rs_model_info_t *mi, double hz);

int rs_asm_init(rs_asm_t *a, const rs_asm_cfg_t *cfg, const rs_sensor_t *s);

/* Feeds one decoded packet (index = its data-packet index, cap_ts = capture
 * time in s). RS_ASM_FRAME_DONE: `slot` holds a complete frame; call again
 * with a fresh slot and the same packet. RS_ASM_CONSUMED: packet used up. */
rs_asm_result_t rs_asm_feed(rs_asm_t *a, rs_slot_t *slot, const rs_packet_t *pkt, uint32_t index,
                            double cap_ts);

/* End of input: closes the open frame. Returns true when `slot` holds a
 * (partial) frame worth publishing. */
bool rs_asm_flush(rs_asm_t *a, rs_slot_t *slot);

/* Frame cutting alone, for tools that work on points rather than maps:
 * true when block azimuth `az_cd` starts a new frame after `*last_rel`. */
bool rs_frame_rollover(int cut_cd, int32_t *last_rel, uint16_t az_cd);

#endif

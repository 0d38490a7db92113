/* scenestats.h - what a capture of a static scene says about the sensor:
 * the statistics that matter to learning a background, measured the same
 * way on real captures and on the simulator's, so the two can be put side
 * by side (docs/simulator.md, roadscan-scenestats).
 *
 * Consecutive complete frames are kept (range and intensity of layer
 * 0 per cell, the frame's time, rotation rate and first block azimuth);
 * then, per cell:
 *  - steady cells return in at least half of the frames; the rest are sky,
 *    far or rarely hit;
 *  - surfaces: the cell's ranges sorted and split where consecutive ones
 *    are more than max(0.3 m, 3 % of the range) apart, counting the groups
 *    holding at least 10 % of the cell's returns; a steady cell with two or
 *    more is an edge (or foliage): the share of such cells, the spread of
 *    their ranges (max - min), and how long the cell stays on one surface
 *    (mean run in frames), next to the run it would have if it chose its
 *    surface independently every frame with the same shares;
 *  - mixed returns: in cells of two or more surfaces, the share of returns
 *    lying between the nearest and the farthest surface (more than 10 cm
 *    from every surface): what a beam split across a depth edge returns;
 *  - noise: in single-surface steady cells, the robust spread (1.4826 x
 *    median absolute deviation) per cell, and the pooled deviations from
 *    each cell's median (99th percentile, share beyond 10 cm), by range band;
 *    the same robust spread on flat cells only (the medians of the cells on
 *    either side in the row within 0.3 % of this one's: a surface facing the
 *    sensor, so the spread is the sensor's, not the scene's);
 *  - dropouts: the share of frames without a return in steady cells, by
 *    range band and by row;
 *  - intensity by range band (median), and the firings: rotation rate
 *    jitter (sd of the per-frame rate, % of the mean) and how far the first
 *    block's azimuth moves from one turn to the next, as a share of the
 *    azimuth step between blocks (0 = the firings fall in the same places
 *    every turn, 0.5 = as far apart as they can be).
 * Offline (tools, tests): allocates. */
#ifndef ROADSCAN_SCENESTATS_H
#define ROADSCAN_SCENESTATS_H

#include "roadscan/frame/frame.h"

#include <stdbool.h>
#include <stdint.h>

#define RS_SSTATS_BANDS 5 /* 0-5, 5-15, 15-40, 40-80, 80+ m */

typedef struct {
  rs_model_t model;
  int rows, cols, max_frames, nframes;
  float *range;      /* [cell][max_frames] range in m, 0 = no return */
  uint8_t *inten;    /* [cell][max_frames] */
  double *t;         /* [max_frames] */
  float *rate_hz;    /* [max_frames] */
  uint16_t *first_az;/* [max_frames] */
} rs_sstats_frames_t;

typedef struct {
  int frames, rows, cols;
  double hz;
  double steady;                  /* share of cells that are steady */
  double multi;                   /* share of steady cells with 2+ surfaces */
  double edge_spread_med, edge_spread_p90; /* m */
  double dwell, dwell_indep;      /* mean run on one surface (frames), and if independent */
  double mixed;                   /* share of returns of multi-surface cells between their surfaces */
  double flat_sd[RS_SSTATS_BANDS];    /* m, median robust spread of flat cells */
  uint32_t flat_cells[RS_SSTATS_BANDS];
  double noise_sd[RS_SSTATS_BANDS];   /* m, median over the band's single-surface cells */
  double dev_p99[RS_SSTATS_BANDS];    /* m */
  double dev_10cm[RS_SSTATS_BANDS];   /* share of returns beyond 10 cm of the cell's median */
  double dropout[RS_SSTATS_BANDS];
  uint32_t band_cells[RS_SSTATS_BANDS];
  double drop_row_min, drop_row_med, drop_row_max;
  double intensity_med[RS_SSTATS_BANDS];
  double rate_jitter;             /* % */
  double phase_step;              /* share of the block step, mean |turn-to-turn change| */
} rs_sstats_t;

extern const double rs_sstats_band_lo[RS_SSTATS_BANDS];

int rs_sstats_init(rs_sstats_frames_t *f, rs_model_t model, int rows, int cols, int max_frames);
void rs_sstats_free(rs_sstats_frames_t *f);
/* Keeps a complete frame; false when full, or when the frame's geometry differs. */
bool rs_sstats_add(rs_sstats_frames_t *f, const rs_slot_t *s);
int rs_sstats_compute(const rs_sstats_frames_t *f, rs_sstats_t *out);

#endif

/* cluster.h - clustering the foreground of a frame: FSPC (fast spherical-
 * projection clustering), its density-adaptive variant, and two baselines
 * (3-D Euclidean DBSCAN on a voxel hash grid; connected components on the
 * range image).
 *
 * Input: layer 0 of a frame slot, returns labelled 1 are background, every
 * other return is foreground. Output: labels 3 + cluster number, 2 for
 * noise; layer-1 (dual) returns take the label of the layer-0 return of the
 * same cell when their ranges agree within the method's eps (the adaptive
 * eps of the cell's row and range), else 2. members[] lists the clustered
 * cells (layer 0 then 1, row-major): the object stage reads only those.
 *
 * FSPC (Chen et al. 2022): the neighbours of a cell are the foreground cells
 * of an h x w window centred on it (columns wrap, rows are clipped) whose
 * range differs from the centre's by less than eps; the centre counts. Core
 * cells have at least minPts neighbours; clusters are the connected
 * components of core cells plus the border cells within a core cell's
 * window; the rest is noise. Work per frame: at most 2 x cells x h x w
 * window reads, whatever the scene.
 *
 * Adaptive FSPC: per laser row and 1 m range bin, the window shrinks to what
 * an obj_w x obj_h object would cover (at least min_half_w columns either
 * side), minPts to share of the cells it would fill (at least min_pts, or
 * sparse_min_pts where it fills fewer than sparse_cells, at most
 * max_min_pts; the fields of rs_fspc_adaptive_cfg_t), and eps to
 * max(0.025, the median row spacing in radians) x range (0.5 to 2.5 m): a
 * car roof seen by one laser near the pole and a pedestrian at 150 m are
 * found; cars queued 2 m apart and people walking 1.5 m apart stay apart.
 * Cells where the static scene has several surfaces (the sensor sees
 * through foliage, or past an edge, to what is behind) give intermittent
 * returns that the background cannot learn; with the model's surface
 * counts (bg_surfaces) their returns join clusters but do not seed them.
 * A cell that is not a core joins a cluster within border_eps x eps
 * of one of its core cells (core cells link within eps, so clusters do not
 * merge through it): the side of a car seen almost along the line of sight
 * at 150 m spreads over metres of range from one column to the next.
 * The same bounded cost.
 * A file of people one behind the other (waiting at a crossing, seen along
 * the file) differ in range by about a metre: within a far eps, so the
 * window joins them. A split pass sorts each cluster's returns by range
 * (heapsort) and cuts it at every gap of at least split_gap where no part
 * is wider than split_width across the line of sight nor smaller than
 * split_min returns: a vehicle (wider) seen through a gap stays whole.
 * A cluster whose ranges leave no empty bin of half split_gap (a
 * vehicle's continuous ranges), or span more than 64 of them, is not
 * sorted: O(n) for those, O(n log n) for the few that are.
 *
 * No allocation: the caller owns rs_cluster_t
 * (about 28 MB; static in the programs). Processing thread only. */
#ifndef ROADSCAN_CLUSTER_H
#define ROADSCAN_CLUSTER_H

#include "roadscan/frame/frame.h"

#include <stdbool.h>
#include <stdint.h>

#define RS_MAX_CLUSTERS 4000
#define RS_MAX_WIN_H 15
#define RS_MAX_WIN_W 31
#define RS_ADAPT_BINS 256 /* 1 m range bins */
#define RS_GRID_BUCKETS (1 << 16)
#define RS_SPLIT_MAX_PARTS 8  /* a cluster is cut into at most this many people */
#define RS_SPLIT_MAX_RUNS 32  /* ... from at most this many runs between range gaps */
#define RS_ROW_WORDS ((RS_MAX_COLS + 63) / 64)

_Static_assert(RS_MAX_CLUSTERS + 3 < UINT16_MAX, "cluster labels fit in uint16_t");

typedef enum { RS_CLUSTER_NONE = 0, RS_CLUSTER_FSPC, RS_CLUSTER_FSPC_ADAPTIVE, RS_CLUSTER_DBSCAN, RS_CLUSTER_CCL } rs_cluster_method_t;

/* The paper's FSPC (also CCL's window of 3 x 3). */
typedef struct {
  int win_h, win_w;      /* odd; defaults 5 x 11 */
  float eps;             /* m, range difference; default 1.8 */
  int min_pts;           /* default 15 (the centre counts) */
} rs_fspc_cfg_t;

/* Density-adaptive FSPC (see above). */
typedef struct {
  int win_h, win_w;      /* the largest window (odd; default 5 x 11) */
  int max_min_pts;       /* the largest minPts (default 15) */
  float obj_w, obj_h;    /* the smallest object to find (m), default 0.5 x 0.8 */
  float share;           /* minPts = share x expected cells, default 0.2 */
  int min_pts;           /* lowest minPts, default 3 */
  float sparse_cells;    /* where the smallest object would cover fewer cells than this */
  int sparse_min_pts;    /*   (default 3), the lowest minPts is this instead (default 2: a pair) */
  int min_half_w;        /* the window reaches at least this many columns either side (default
                            2: returns go missing beyond 120 m, a neighbour may be two columns away) */
  float eps_share;       /* eps = clamp(max(share, eps_rows x the sensor's median row spacing in */
  float eps_rows;        /*   radians) x range, eps_min, eps_max): 0.025, 1.0, 0.5 m, 2.5 m */
  float eps_min;
  float eps_max;
  float border_eps;      /* a cell that is not a core joins a core cell's cluster within this many
                            times the core's eps (core to core: eps); default 2 */
  int seed_surfaces;     /* with bg_surfaces: a return in a cell of at least this many static
                            surfaces (foliage and edges the sensor sees through) seeds no cluster
                            but may join one; default 3, 0 = off */
  float split_gap;       /* a cluster whose returns, sorted by range, leave gaps of at least this
                            (m) is split there when every part is narrow (below); default 0.5, 0 = off */
  float split_width;     /* ... no part wider than this across the line of sight (m), default 1.2 */
  float split_depth;     /* ... nor deeper than this in range (m), default 0.5 */
  int split_min;         /* ... and no part of fewer returns than this, default 5 */
} rs_fspc_adaptive_cfg_t;

/* 3-D Euclidean DBSCAN. */
typedef struct {
  float eps;             /* m, default 1.2 */
  int min_pts;           /* default 15 */
} rs_dbscan_cfg_t;

/* Connected components of the range image (8-neighbours). */
typedef struct {
  float eps;             /* m, range difference joining neighbours, default 1.0 */
} rs_ccl_cfg_t;

/* The method and each method's own parameters. */
#define RS_CLUSTER_BRIDGE_MAX 128 /* bridge_gap's largest value (columns) */
typedef struct {
  rs_cluster_method_t method;
  int bridge_gap;        /* FSPC (all three kinds): a window's half-width counts the measured columns of its
                            row, reaching across at most this many a lost packet left unmeasured
                            (rs_slot_t.gap; 0 = off: the columns as they are; default 32) */
  rs_fspc_cfg_t fspc;
  rs_fspc_adaptive_cfg_t adaptive;
  rs_dbscan_cfg_t dbscan;
  rs_ccl_cfg_t ccl;
} rs_cluster_cfg_t;

typedef struct {
  uint32_t foreground;   /* layer-0 foreground returns */
  uint32_t clustered, noise;
  uint32_t clusters;
  uint32_t overflow;     /* clusters beyond RS_MAX_CLUSTERS (left as noise, or a split left undone) */
  uint32_t splits;       /* clusters split at range gaps (adaptive) */
} rs_cluster_stats_t;

typedef struct {
  float range;
  uint32_t rc;           /* row << 16 | column */
} rs_cluster_ret_t;

typedef struct {
  rs_cluster_cfg_t cfg;
  const rs_sensor_t *sensor;
  const uint8_t *bg_surfaces; /* optional (adaptive): static surfaces per cell, the background model's n */
  int cols;              /* geometry the tables were built for */
  uint64_t overflow_total;
  float rr[RS_MAX_CELLS];            /* foreground range, or a large negative */
  uint8_t core[RS_MAX_CELLS];
  uint32_t fg[RS_MAX_CELLS];         /* foreground cell indices */
  uint32_t fgrc[RS_MAX_CELLS];       /* the same as row << 16 | column (no division in the loops) */
  uint32_t queue[RS_MAX_CELLS];      /* FSPC: row << 16 | column; DBSCAN: point numbers */
  uint64_t open[RS_MAX_ROWS * RS_ROW_WORDS];    /* foreground cells not in a cluster yet, per row */
  uint8_t half_w[RS_MAX_ROWS][RS_ADAPT_BINS];   /* adaptive window half-width */
  uint8_t half_h[RS_MAX_ROWS][RS_ADAPT_BINS];   /* adaptive window half-height */
  uint8_t min_pts[RS_MAX_ROWS][RS_ADAPT_BINS];  /* adaptive minPts */
  float eps_tab[RS_MAX_ROWS][RS_ADAPT_BINS];    /* adaptive eps by row and range (rows share it today) */
  float px[RS_MAX_CELLS], py[RS_MAX_CELLS], pz[RS_MAX_CELLS];
  int32_t next[RS_MAX_CELLS];
  int32_t heads[RS_GRID_BUCKETS];
  uint32_t start[RS_MAX_CLUSTERS + 1];  /* split pass: each cluster's first entry in byrange */
  float rmin[RS_MAX_CLUSTERS];          /* split pass: each cluster's nearest range */
  uint64_t occ[RS_MAX_CLUSTERS];        /* split pass: its range bins (half the gap) with returns */
  rs_cluster_ret_t byrange[RS_MAX_CELLS]; /* split pass: clustered cells grouped by cluster, by range */
  /* the window across a lost packet's columns (rs_slot_t.gap), FSPC: per row its laser's azimuth offset
   * in columns; per block column the number of measured ones before it, and the measured ones in order */
  bool bridge;                          /* this frame has columns no firing fell in */
  int16_t row_shift[RS_MAX_ROWS];
  uint16_t rank[RS_MAX_COLS + 1];       /* (rank[cols]: how many are measured) */
  uint16_t measured[RS_MAX_COLS];
  uint8_t near_gap[RS_MAX_COLS];        /* map columns some row's widest window about which may reach one */
  uint32_t members[RS_LAYERS * RS_MAX_CELLS]; /* clustered cells of the last run, layer 0 then 1, row-major */
  uint32_t nmembers;
} rs_cluster_t;

void rs_cluster_cfg_default(rs_cluster_cfg_t *c);
/* What --eps, --min-pts and --window set: the chosen method's eps (the largest with fspc-adaptive),
 * minPts (the largest with fspc-adaptive) and window (the largest). false when the method has no
 * such parameter (CCL has no minPts, neither DBSCAN nor CCL a window; none has nothing). */
bool rs_cluster_cfg_set_eps(rs_cluster_cfg_t *c, float eps);
bool rs_cluster_cfg_set_min_pts(rs_cluster_cfg_t *c, int min_pts);
bool rs_cluster_cfg_set_window(rs_cluster_cfg_t *c, int h, int w);
const char *rs_cluster_method_name(rs_cluster_method_t m);
/* "fspc", "fspc-adaptive", "dbscan", "ccl", "none"; -1 if unknown */
int rs_cluster_method_from_name(const char *s);

/* RS_E_INVAL for a bad window (even, too large) or parameter. */
int rs_cluster_init(rs_cluster_t *c, const rs_cluster_cfg_t *cfg, const rs_sensor_t *s);
void rs_cluster_run(rs_cluster_t *c, rs_slot_t *slot, rs_cluster_stats_t *st);

#endif

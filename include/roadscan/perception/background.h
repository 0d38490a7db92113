/* background.h - the static scene: learning it from frames, the model file,
 * and subtracting it.
 *
 * Learning (start-up or tool; allocates): range samples of every cell of
 * the spherical map from many frames, clustered per cell with DBSCAN on the
 * ranges (eps chosen from 0.08 to 0.40 m in 0.01 m steps: highest
 * silhouette when several clusters, smallest intra-cluster distance when
 * one; minPts = max(floor, 1 % of the samples)). Which clusters are static:
 *  - the farthest cluster is the cell's static surface (a vehicle standing
 *    in the cell only ever occludes it), unless "no return" is itself a
 *    persistent state of the cell (sky behind), then no cluster is farthest;
 *  - a nearer cluster is background only when it flickers (whether the next
 *    frame returns it hardly depends on whether this one did: leaves in the
 *    wind) and is present throughout the capture (most time windows). A
 *    vehicle, queued or passing, stays in a cell for several frames; sparse
 *    traffic is also absent from most windows.
 * Subtraction (processing thread, no allocation): a return is background
 * when its range lies in a static surface of its cell. O(1) per return.
 * In a cell the sensor sees through (see_through or more static surfaces:
 * foliage, edges) a return is also background when its range lies in a
 * static surface of the cell on its left or right in the same row: leaves
 * sway across the beam by more than a column. (Looking beside every cell
 * saved 0.03-0.24 % of static returns at edges but lost 0.1-0.75 % of
 * object returns; only in see-through cells it loses at most 0.01 %.)
 * A displaced sensor (knocked, a pole swaying, a tripod nudged): the whole
 * scene moves against the model by centimetres, near surfaces by degrees of
 * azimuth, and every edge turns foreground. Evidence, counted per frame:
 * returns beyond their cell's farthest surface (a far side of an edge where
 * the near side was learned) that lie within shift_tol (3D) of a surface of
 * a cell nearby in the row. When they reach shift_gate of the frame's
 * returns, the frame is displaced, and a foreground return within shift_tol
 * (or the range x tan(shift_deg) when more) of a surface nearby in its row
 * is background. A still sensor with traffic
 * shows 0.02-0.07 % of such evidence on every simulated preset, the real
 * VLP-16 that moves 0.2-8 cm 0.2-3.2 % (docs/background.md); the rule is not
 * applied to a still sensor, where it would cost 0.2-0.9 % of the object
 * returns (feet and wheels by the road). A displaced frame also shows what
 * near objects hid while the model was learned (shift_behind): a return
 * past the model within the parallax band atan(shift_tol / r_o) of the edge
 * of an object at r_o, no nearer than the surface beside that edge, is
 * background (the real VLP-16's last second: 1.55 -> 0.15 clusters per
 * frame). */
#ifndef ROADSCAN_BACKGROUND_H
#define ROADSCAN_BACKGROUND_H

#include "roadscan/util/error.h"
#include "roadscan/frame/frame.h"

#include <stdbool.h>
#include <stdint.h>

#define RS_BG_SURFACES 4
#define RS_BG_BEYOND 65535u /* hi of a surface with no far end (the percentile method's): everything beyond lo */
#define RS_BG_SEE_THROUGH 2
#define RS_BG_MAGIC "RSBGMDL1"
#define RS_BG_VERSION 2
#define RS_BG_SOLID_PCT 80      /* a farthest surface seen in this % of frames or more is solid */
#define RS_BG_SHIFT_TOL 0.15    /* m: how far a surface seen from a displaced sensor may lie */
#define RS_BG_SHIFT_DEG 0.3     /* ... or the range x tan(this): the sensor turned */
#define RS_BG_SHIFT_GATE 0.0015 /* share of a frame's returns that are evidence of displacement */
#define RS_BG_SHIFT_COLS 48     /* columns looked at on either side, at most (bounded work) */
#define RS_BG_BEHIND_JUMP 0.3   /* m: a depth edge, seen behind a near object from a displaced sensor */
#define RS_BG_BEHIND_JUMP_SHARE 0.05 /* ... or this share of the range when more */
#define RS_BG_INTERMITTENT 0.6 /* a cluster back in the next frame less often than this is intermittent */
#define RS_BG_HIDDEN_SUPPORT 1.5 /* a cluster hidden by traffic as occluded_* says, but spread up to this
                                    many times occluded_spread: the cells beside may support it */
#define RS_BG_CLEAR_BEHIND 0.02 /* "nothing steady behind": returns beyond a cluster (but the intermittent
                                  far side of an edge) at most this share of those in front */
#define RS_BG_CLEAR_SPREAD 2.5  /* ... then a hidden cluster may spread this many times occluded_spread */
#define RS_BG_JUDGE_FRAMES 10 /* fewer frames: every cluster seen is the scene */

typedef enum { RS_BG_DBSCAN = 0, RS_BG_PERCENTILE = 1 } rs_bg_method_t;

typedef struct {
  rs_bg_method_t method;
  int min_pts_floor;      /* default 10 (the paper's 100 suits far more samples per cell) */
  double min_pts_share;   /* default 0.01 */
  double eps_min, eps_max, eps_step; /* metres: 0.08, 0.40, 0.01 */
  double persist_max;     /* "no return" persisting at least this often is sky (default 0.8) */
  double flicker_lift;    /* a nearer cluster flickers when P(next in it | in it) - P(next in it)
                             is below this (default 0.25) */
  double coverage_min;    /* ... and is present in this share of windows (default 0.8) */
  double coverage_open;   /* ... counted over the windows it was open in (a sample of the cell not in
                             front of it: no return, or at its range or beyond), at least this share
                             of all windows: a canopy behind a lane where queues stand for whole
                             windows; default 0.5, 0 = over all windows; not stored in the model file */
  double sparse_cover;    /* ... or, within max(occluded_spread, 1 % of the range), in this share
                             of the windows a cluster returning at random at its own rate would
                             be seen in, and coming and going on its own in its row (for each cell
                             beside it, P(it returns near the cluster's range | the cluster is seen)
                             - P(it does) below flicker_lift; a vehicle covers several cells at
                             once): a far surface whose returns drop out (ground at a grazing
                             angle, returning in 5 % of the frames, is in fewer than 80 % of the
                             windows); default 0.8, 0 = off; not stored in the model file */
  double leaves_range;    /* ... or, over the frames it could be seen in (not hidden by a return in front
                             of it), it comes and goes at random both ways (P(next in | in) - P(in) and
                             P(in) - P(next in | out) below flicker_lift) and its range changes from one
                             frame to the next by at least this share of the mean difference between
                             two of its samples: leaves of a dense canopy behind a lane, whose
                             presence traffic in front makes look steady; default 0.7, 0 = off; not
                             stored in the model file */
  double window_s;        /* coverage window, default 5 s */
  double pair_gap_s;      /* samples closer than this count as consecutive, default 1 s */
  double margin_min;      /* a surface interval is the cluster's [min, max] widened by */
  double margin_share;    /* max(margin_min, margin_share * range): default 0.05 m, 0.006 */
  double margin_samples;  /* ... plus the cluster's spread x min(1, margin_samples / its samples):
                             what few samples do not show (default 4) */
  double merge_gap_min;   /* background clusters closer than max(merge_gap_min, */
  double merge_gap_share; /* merge_gap_share * range) merge: default 0.5 m, 0.02 */
  double chain_gap;       /* clusters of a cell less than this apart (m) are one for the decision
                             (a surface at a grazing angle comes in clumps); default 0.20, 0 = off;
                             not stored in the model file */
  double occluded_max;    /* a nearer cluster is a surface hidden by traffic (background) when, in
                             the frames it is not seen, at most this share of the returns lie behind
                             it (the rest in front: what hides it; returns of a cluster behind it
                             that is intermittent, RS_BG_INTERMITTENT, the far side of an edge, are
                             not counted); default 0.2, 0 = off; and it is */
  double occluded_seen;   /* seen in this share of the frames (0.1), */
  double occluded_windows;/* in this share of the 5 s windows (0.5), */
  double occluded_spread; /* within max(this, 1 % of the range) (0.15 m). Not stored in the model file */
  double occluded_clear;  /* with nothing steady behind it (RS_BG_CLEAR_BEHIND; the cell returns nothing
                             less often than it is seen): in this share of the windows (0.2) and within
                             RS_BG_CLEAR_SPREAD times that spread; 0 = off; not stored in the model file */
  bool support;           /* a nearer cluster within support_tol of a background cluster that the
                             cell beside it in the row sees in half its frames or more is background
                             too, unless it stays for several frames (edges) and is not hidden by
                             traffic (the occluded_* tests, spread up to RS_BG_HIDDEN_SUPPORT times
                             occluded_spread); default on; not stored in the model file */
  double support_tol_min, support_tol_share; /* max(0.3 m, 3 % of the range) */
  double connect_min;     /* a surface interval reaches half-way to the nearest interval of the
                             cell on either side in the row when they are less than */
  double connect_share;   /* max(connect_min, connect_share x range) apart: 0.5 m, 0.05; 0 = off */
  double void_stay;       /* the farthest cluster is no surface (judged as a nearer one) when the
                             cell returns nothing more often than it and, once seen, it is back in
                             the next frame at least this often (a vehicle standing where nothing
                             behind it returns: a road too dark or too far at that angle; a far
                             surface whose returns drop out is back only as often as it is
                             detected); default 0.6, 0 = off; not stored in the model file */
  double wide_min;        /* a cluster spread over more than max(wide_min, wide_share x range) is */
  double wide_share;      /* no surface (a queue creeping through the cell): 2 m, 0.15 */
  double percentile;      /* percentile method: background range percentile, default 50 */
  double percentile_tol;  /* ... minus this (m), default 0.3 */
} rs_bg_params_t;

void rs_bg_params_default(rs_bg_params_t *p);

/* The model: per cell up to RS_BG_SURFACES [lo, hi] range intervals (cm,
 * margins included), nearest first. hi = 65535 means "and beyond". */
typedef struct {
  rs_model_t model;
  uint16_t rows, cols;
  float rate_hz;
  rs_bg_params_t params;
  uint32_t frames;        /* frames learned from */
  uint64_t created;       /* unix time */
  uint8_t *n;             /* [cells] */
  uint8_t *far_seen;      /* [cells]: % of the frames learned from in which the farthest surface is
                             seen (RS_BG_SOLID_PCT or more: solid, nothing is seen through it) */
  uint16_t *lo, *hi;      /* [cells * RS_BG_SURFACES] */
} rs_bg_model_t;

/* How the subtraction reads a model: run-time settings (the daemon's options), not part of the
 * model, so the model is only ever read. */
typedef struct {
  int see_through;        /* cells of this many static surfaces or more (or none) also match the
                             surfaces of the cells beside them (0 = off; default RS_BG_SEE_THROUGH) */
  bool beyond_static;     /* returns beyond a solid farthest surface, or just beyond one seen
                             through (max(0.3 m, 3 %)), are background (default true) */
  double shift_tol;       /* a displaced sensor: m, default RS_BG_SHIFT_TOL; 0 = off */
  double shift_deg;       /* ... or the range x tan(shift_deg) when more (default RS_BG_SHIFT_DEG) */
  double shift_gate;      /* share of the frame's returns that must be evidence (RS_BG_SHIFT_GATE);
                             0: no gate, every frame is judged displaced */
  bool shift_behind;      /* in a displaced frame, a return past the model that the sensor sees behind a
                             near object (within the parallax band of the object's edge, no nearer than
                             the surface beside the edge) is background (default on) */
} rs_bg_rules_t;

void rs_bg_rules_default(rs_bg_rules_t *r);

int rs_bg_model_alloc(rs_bg_model_t *m, rs_model_t model, int rows, int cols);
void rs_bg_model_free(rs_bg_model_t *m);
/* Writes the model atomically: PATH.tmp-PID beside it, flushed to the disk
 * (fsync), renamed over PATH. A crash or a full disk leaves the previous model
 * or none, never part of one. */
int rs_bg_save(const rs_bg_model_t *m, const char *path, char *err, size_t n);
/* Checks magic, version, sizes, CRC and every interval; the message names the problem. */
int rs_bg_load(rs_bg_model_t *m, const char *path, char *err, size_t n);

/* Is a return of range r (m) in cell (row, col) in a surface of the cell? */
bool rs_bg_is_static(const rs_bg_model_t *m, int row, int col, float r);
/* Is it background by every rule of the subtraction (surfaces beside a
 * see-through or empty cell, behind a solid surface)? *beyond (optional):
 * it lies beyond the cell's farthest surface. */
bool rs_bg_return_static(const rs_bg_model_t *m, const rs_bg_rules_t *rules, int row, int col, float r, bool *beyond);
/* A copy (allocated here). */
int rs_bg_model_copy(rs_bg_model_t *dst, const rs_bg_model_t *src);

typedef struct {
  uint64_t background, foreground;
  uint64_t beyond;          /* returns beyond their cell's farthest surface (background by default) */
  uint32_t *beyond_cells;   /* optional, caller's [rows x cols]: the same per cell */
  uint64_t displaced_frames; /* frames judged taken by a displaced sensor */
  uint64_t shifted;         /* foreground returns of those frames made background by the shift rule */
  uint64_t behind;          /* ... and as what it sees behind a near object (in the parallax band of its edge) */
  bool displaced;           /* the last frame was */
  uint32_t evidence;        /* the last frame's evidence, returns (gathered up to what the gate needs) */
} rs_bg_counts_t;

/* Labels every return of the slot: 1 background, 2 foreground (until the
 * clustering stage relabels it). The model is only read. Bounded work: two
 * passes over the map; the shift rule looks at RS_BG_SHIFT_COLS cells at most
 * on either side, and the evidence stops being gathered once it suffices. */
void rs_bg_subtract(const rs_bg_model_t *m, const rs_bg_rules_t *rules, rs_slot_t *s, rs_bg_counts_t *c);

/* ---- learning ---- */

typedef struct {
  rs_model_t model;
  int rows, cols, max_frames, nframes;
  uint64_t seen;          /* frames offered (reservoir sampling) */
  uint16_t *samples;      /* [cell][max_frames] range in cm, 0 = no return */
  double *t;              /* [max_frames] capture time of each stored frame */
  uint64_t rng;
} rs_bg_learner_t;

/* Memory needed for the samples (bytes). */
size_t rs_bg_learner_bytes(int rows, int cols, int max_frames);
int rs_bg_learner_init(rs_bg_learner_t *l, rs_model_t model, int rows, int cols, int max_frames, uint64_t seed);
void rs_bg_learner_free(rs_bg_learner_t *l);
/* Writes a frame into stored frame f (0..max_frames-1; a ring kept by the caller). */
void rs_bg_learner_set(rs_bg_learner_t *l, int f, const rs_slot_t *s);
/* Offers a frame; kept with reservoir sampling (uniform over all frames offered). */
void rs_bg_learner_add(rs_bg_learner_t *l, const rs_slot_t *s);
/* minPts for a capture of n frames: max(floor, share x n); a short capture
 * brings the floor down to a tenth of its frames, never below 2 (1 below 6
 * frames). */
int rs_bg_min_pts(const rs_bg_params_t *p, int nframes);
/* Clusters every cell into the model (allocated here). */
int rs_bg_learn(const rs_bg_learner_t *l, const rs_bg_params_t *p, float rate_hz, rs_bg_model_t *out);

/* Exposed for tests: DBSCAN on sorted unique values v[] with counts c[]
 * (u of them), eps and minPts in the same units; writes cluster ids per
 * value (-1 noise) and returns the number of clusters. */
int rs_bg_dbscan1d(const int32_t *v, const uint32_t *c, int u, int32_t eps, uint32_t min_pts, int16_t *label);
/* Mean silhouette of the clustered values (noise excluded); NaN if < 2 clusters. */
double rs_bg_silhouette1d(const int32_t *v, const uint32_t *c, int u, const int16_t *label, int k);

#endif

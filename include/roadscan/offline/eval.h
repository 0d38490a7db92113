/* eval.h - point-label metrics of ../shared/specs/point-labels.md (the FSPC
 * paper's Table 3): target / non-target precision, recall, IoU; matched
 * instances (IoU > 0.5, true instances of at least 10 points); background
 * subtraction shares; target recall by range band.
 *
 * Feed every return of a frame with rs_eval_point, then rs_eval_end_frame.
 * Tool code: rs_eval_init allocates its per-frame tables once. */
#ifndef ROADSCAN_EVAL_H
#define ROADSCAN_EVAL_H

#include <stdbool.h>
#include <stdint.h>
#include <jansson.h>
#include <stdio.h>

#define RS_EVAL_BANDS 4
#define RS_EVAL_MIN_INSTANCE 10

typedef struct {
  uint64_t frames, points;
  uint64_t t_tp, t_fp, t_fn;                /* target class (label >= 3) */
  uint64_t n_tp, n_fp, n_fn;                /* non-target class (labels 1 and 2) */
  uint64_t static_true, static_kept;        /* true 1, predicted 1 */
  uint64_t target_true, target_kept;        /* true >= 3, predicted other than 1 */
  uint64_t foliage_true, foliage_background;/* true 2, predicted 1 */
  uint64_t band_true[RS_EVAL_BANDS], band_hit[RS_EVAL_BANDS];
  uint64_t instances, matched;
  uint64_t merged, split, missed;           /* instances not matched: over half of it in one cluster that
                                               holds as much else (merged); no cluster holds over half of it
                                               (split); no return of it in a cluster (missed) */
} rs_eval_result_t;

typedef struct {
  uint64_t key;   /* (truth << 32) | pred, 0 = empty */
  uint32_t count;
} rs_eval_pair_t;

struct rs_mot;
typedef struct {
  rs_eval_result_t r;
  struct rs_mot *mot;     /* optional tracking metrics */
  uint64_t frame_no;      /* frames ended so far */
  rs_eval_pair_t *pairs;  /* open addressing */
  uint32_t cap;           /* power of two */
  uint32_t *used;         /* slots used this frame */
  uint32_t nused;
  bool overflow;
} rs_eval_t;

/* Tracking (multi-object) metrics, CLEAR MOT and identity ones, with the
 * matching of the point-label metrics: in each frame a true instance (>= 10
 * returns) and a predicted one (a track's label) match when their returns
 * overlap with IoU > 0.5 (so each has at most one partner). Predicted
 * instances: track labels with >= 10 returns in the frame, or matched.
 * MOTA = 1 - (misses + false positives + id switches) / true instances;
 * MOTP: the mean IoU of matches (py-motmetrics reports 1 - it);
 * id switch: a true instance matched to another track than the last time
 * it was matched; fragmentation: its track coverage interrupted and taken
 * up again; mostly tracked / lost: matched in >= 80 % / < 20 % of its frames;
 * IDF1 = 2 IDTP / (true + predicted instances), IDTP the matched frames of
 * the best one-to-one pairing of true objects and tracks over the whole run
 * (optimal assignment per connected group). The same as py-motmetrics'
 * figures on the same matches (tests/crosscheck_motmetrics.py). */
typedef struct {
  uint64_t frames, gt, hyp, matches, misses, false_pos, switches, fragmentations;
  double iou_sum;
  uint64_t objects, mostly_tracked, partly_tracked, mostly_lost; /* true objects */
  uint64_t tracks;                                              /* predicted ids */
  uint64_t idtp;
  /* the false positives by what their returns are: overlapping a true instance (a part of one, a
   * second track on it, two merged); else mostly (over half) returns of road users each seen with
   * fewer than RS_EVAL_MIN_INSTANCE returns in the frame (a real object too sparse to be an
   * instance); else the scene's (static, foliage, noise) */
  uint64_t fp_instance, fp_small, fp_scene;
  double mota, motp_iou, idf1, idp, idr;
} rs_mot_result_t;

typedef struct rs_mot rs_mot_t;
/* NULL when out of memory. dump: optional CSV of every frame's instances and
 * overlaps (frame,truth,pred,iou; a 0 id marks presence alone). */
rs_mot_t *rs_mot_new(FILE *dump);
void rs_mot_free(rs_mot_t *m);
/* Called for every true instance of every frame: the track label it matched, or 0. */
typedef void (*rs_mot_instance_fn)(void *user, uint64_t frame, uint32_t truth, uint32_t pred);
void rs_mot_on_instance(rs_mot_t *m, rs_mot_instance_fn fn, void *user);
/* the tracking figures of the eval's frames from now on (rs_eval_end_frame feeds it) */
void rs_eval_track(rs_eval_t *e, rs_mot_t *m);
/* RS_OK, or RS_E_NOMEM */
int rs_mot_finish(rs_mot_t *m, rs_mot_result_t *out);
void rs_mot_print(const rs_mot_result_t *r, FILE *out);
void rs_mot_print_json(const rs_mot_result_t *r, FILE *out);
/* The same as a JSON object (jansson; undefined ratios are null); the caller owns it. */
json_t *rs_mot_json(const rs_mot_result_t *r);

extern const double rs_eval_band_edges[RS_EVAL_BANDS + 1]; /* 0 20 50 100 200 */

int rs_eval_init(rs_eval_t *e);
void rs_eval_deinit(rs_eval_t *e);
/* One return of the current frame; `counted` false for frame 0. */
void rs_eval_point(rs_eval_t *e, uint32_t truth, uint32_t pred, float range, bool counted);
void rs_eval_end_frame(rs_eval_t *e, bool counted);

/* Whether a confirmation `frames` frames after an object's first frame as an instance, on a
 * capture whose frames are `period` s apart, is within `limit` s. A delay is a whole number of
 * frames, and a sensor set to 600 rpm turns a little slower or faster than that (the simulator's
 * captures: 0.10000-0.10031 s a frame), so three frames of it are 0.3 s give or take a
 * millisecond: the limit is allowed RS_EVAL_RATE_TOL of itself for the rotation rate (three frames
 * count as within 0.3 s down to 594 rpm). */
#define RS_EVAL_RATE_TOL 0.01
bool rs_eval_within(uint32_t frames, double period, double limit);

/* ratio or NaN when the denominator is 0 */
double rs_eval_ratio(uint64_t num, uint64_t den);
void rs_eval_print(const rs_eval_result_t *r, FILE *out);
void rs_eval_print_json(const rs_eval_result_t *r, FILE *out);
json_t *rs_eval_json(const rs_eval_result_t *r);
/* json_dumps flags of the reports: one line, "key": value, 6 significant digits */
#define RS_EVAL_JSON_FLAGS (JSON_INDENT(0) | JSON_REAL_PRECISION(6))

#endif

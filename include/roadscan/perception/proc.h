/* proc.h - the processing stages of one frame, in order, over a frame slot.
 *
 *   background (the static scene: rs_bgu_t keeps it current) -> clustering
 *   -> objects -> tracks -> counting lines -> the frame's census (cells, ranges)
 *
 * Each stage is a function over the slot with its own state (owned by the
 * caller and handed in configured, or, for the background, made at init)
 * and its own counters and timing (CLOCK_MONOTONIC). rs_proc_frame runs
 * them and fills a per-frame report; what leaves the process (LCM, the
 * frames CSV, point labels, statistics) is a sink that reads the report and
 * the slot: no stage knows about LCM, CSV or the command line.
 *
 * Threads: rs_proc_init and rs_proc_deinit on the main thread; everything
 * else on the processing thread (the daemon's, or the tool's only thread).
 * rs_proc_init allocates what the stages need (the cells' counters); after
 * it nothing allocates. The background learner is its own thread
 * (bgupdate.h); its models are taken over at a frame boundary. */
#ifndef ROADSCAN_PROC_H
#define ROADSCAN_PROC_H

#include "roadscan/perception/background.h"
#include "roadscan/perception/bgupdate.h"
#include "roadscan/perception/cluster.h"
#include "roadscan/perception/count.h"
#include "roadscan/perception/ground.h"
#include "roadscan/frame/frame.h"
#include "roadscan/perception/objects.h"
#include "roadscan/sensor/sensor.h"
#include "roadscan/util/timing.h"
#include "roadscan/perception/track.h"

#include <stdbool.h>
#include <stdint.h>

typedef struct {
  const rs_bg_model_t *background; /* optional: a model to start from (copied) */
  double learn_seconds;        /* > 0 and no model: learn from the first seconds, then subtract */
  const char *learn_out;       /* where the learned model is saved (by the learner thread) */
  double update_window_s;      /* > 0: keep the model current from the last window (bgupdate.h) */
  double update_every_s;       /* relearn every (0: the updater's default) */
  bool lossless;               /* every frame matters: a relearn is waited for (replays, tools) */
  int see_through;             /* 0: the model's own (RS_BG_SEE_THROUGH); N > 0: N; < 0: off */
  bool beyond_foreground;      /* returns beyond the farthest surface are foreground */
  bool no_behind;            /* displaced frames: surfaces are not continued past near objects */
  bool no_ground;             /* no ground is built from the model: objects' tops are not known above it
                                  (top_agl 0) and the class rule reads their returns' heights alone */
  double shift_tol;            /* a displaced sensor (background.h): 0 = RS_BG_SHIFT_TOL, < 0 = off */
  double shift_gate;           /* 0 = RS_BG_SHIFT_GATE, < 0 = no gate (every frame) */
  double shift_deg;            /* 0 = RS_BG_SHIFT_DEG, < 0 = none */
  rs_cluster_t *cluster;       /* optional: configured clustering work area */
  rs_objects_t *objects;       /* optional with cluster: rs_objects_init done */
  rs_object_list_t *object_list; /* required with objects */
  rs_tracker_t *tracker;       /* optional with objects: rs_track_init done */
  rs_counter_t *counter;       /* optional with tracker: rs_count_init done */
} rs_proc_cfg_t;

#define RS_PROC_DIVIDED_MAX 32768 /* returns of clusters divided between tracks, per frame */
#define RS_PROC_FINISH_LEARN_S 8.0 /* s of wall time rs_proc_finish waits for a first model being learned: below the
                                      service's WatchdogSec (10 s), not fed meanwhile; a model not ready by then is
                                      still saved (--learn-out) as the learner is joined, only not used */
_Static_assert(RS_PROC_DIVIDED_MAX <= RS_LAYERS * RS_MAX_CELLS, "no more than a frame's cells");

enum { RS_STAGE_BACKGROUND, RS_STAGE_CLUSTER, RS_STAGE_OBJECTS, RS_STAGE_TRACKS, RS_STAGE_COUNTING, RS_STAGES };

typedef struct {
  bool ran[RS_STAGES];          /* which stages ran on this frame */
  int64_t stage_ns[RS_STAGES];
  int64_t total_ns;                  /* every stage and the census (the sinks come after) */
  uint32_t foreground;               /* returns left by the background (both layers) */
  bool displaced;                    /* the background judged the sensor displaced (background.h) */
  uint32_t shift_evidence;           /* the returns that told it (up to what its gate needs) */
  rs_cluster_stats_t cluster;
  const rs_object_list_t *objects;   /* never NULL: an empty list when no stage made one */
  const rs_track_list_t *tracks;     /* NULL without a tracker (or before the first clustering) */
  const rs_count_interval_t *counts; /* a counting interval that closed with this frame, else NULL */
  const rs_count_event_t *crossings; /* the crossings tallied with this frame (count.h), ncrossings of them */
  uint32_t ncrossings;
  bool model_changed;                /* another background model was taken over before this frame */
  uint32_t filled[RS_LAYERS];        /* cells with a return, per layer */
  float min_range, max_range;        /* of the frame's returns (0 when none) */
  /* the returns of clusters divided between held tracks (track.h): cell (ascending) and the id of the
   * track it belongs to (rs_track_owner); the other returns of a cluster go with objects' track */
  uint32_t divided;
  const uint32_t *divided_cell, *divided_track;
} rs_proc_report_t;

typedef struct {
  uint64_t frames, partial_frames, missing_packets, points;
  uint64_t cells_filled[RS_LAYERS];
  double min_range, max_range;
  uint64_t clusters, clustered, noise, objects;
  uint64_t splits;          /* clusters cut at range gaps (people in file; adaptive) */
  uint64_t divided, divided_overflow; /* returns of divided clusters; beyond RS_PROC_DIVIDED_MAX in a frame */
} rs_proc_counters_t;

typedef struct {
  rs_proc_cfg_t cfg;
  rs_proc_counters_t n;
  rs_timing_t t_stage[RS_STAGES];
  rs_timing_t t_frame;
  rs_bg_counts_t bg;                 /* background / foreground returns */
  uint32_t *beyond_cells;            /* returns beyond each cell's farthest surface (allocated at init) */
  rs_bgu_t bgu;                      /* the static scene in use */
  bool bgu_on;
  bool rate_checked, few_warned;
  const rs_sensor_t *sensor;         /* of the frames seen so far */
  double last_t;                     /* capture time of the last tracked frame */
  uint32_t divided_cell[RS_PROC_DIVIDED_MAX], divided_track[RS_PROC_DIVIDED_MAX];
  /* the ground under the objects (ground.h), built from the model in use when it comes (in the
   * background stage's time) and handed to the object stage */
  rs_ground_t ground;
  const rs_bg_model_t *ground_model; /* the model and sensor it was built from */
  const rs_sensor_t *ground_sensor;
  uint32_t ground_builds;
  int64_t ground_ns;                 /* how long the last build took (CLOCK_MONOTONIC) */
} rs_proc_t;

/* RS_OK, or a negative code with err set (nothing left allocated). */
int rs_proc_init(rs_proc_t *p, const rs_proc_cfg_t *cfg, char *err, size_t errlen);
void rs_proc_deinit(rs_proc_t *p);
/* The ground built from the model in use (NULL before the first model, and with no_ground; not valid
 * when none was found). */
const rs_ground_t *rs_proc_ground(const rs_proc_t *p);
/* Runs every configured stage on s (whose frames come from sensor) and
 * fills r. Frames whose geometry is not the model's are not subtracted;
 * with a background being learned nothing is clustered until it exists. */
void rs_proc_frame(rs_proc_t *p, rs_slot_t *s, const rs_sensor_t *sensor, rs_proc_report_t *r);
/* The model in use (NULL while the first one is learned, or without a background). */
const rs_bg_model_t *rs_proc_model(const rs_proc_t *p);
const char *rs_proc_stage_name(int stage);
/* The end of the run: closes the open counting interval (r->counts, else NULL),
 * and waits for a first background model being learned (rs_bgu_finish, at most
 * RS_PROC_FINISH_LEARN_S): a replay that ends as its model is learned keeps it. */
void rs_proc_finish(rs_proc_t *p, rs_proc_report_t *r);

#endif

/* bgupdate.h - learning the static scene while running: the first model of
 * a site (learn the first N seconds), and keeping it current afterwards (a
 * parked car leaves, scaffolding goes up, leaves fall).
 *
 * Threads and ownership:
 *  - the processing thread calls rs_bgu_frame() once per frame: it copies
 *    a sample of the frame into the sample store while the updater collects,
 *    starts a relearn when one is due, and takes a new model over at the
 *    frame boundary once the learner has one (rs_bgu_model() is then the
 *    model to subtract). It never allocates and never waits, except in
 *    lossless (--fast) replays, where it waits for the learner so that a
 *    replay gives the same labels whatever the machine's speed, and at the
 *    end of input for a first model under way (rs_bgu_finish);
 *  - a learner thread (low priority: SCHED_IDLE from its first learning on;
 *    the store's reservation at the first frame comes before, at the normal
 *    priority) runs rs_bg_learn on the
 *    samples, checks the candidate against the model in use on the same
 *    samples, and hands it over, or rejects it (counted, with the reason);
 *  - the two hand the work back and forth through one atomic state:
 *    COLLECTING (the processing thread owns the samples) -> LEARNING (the
 *    learner owns them and the spare model) -> READY -> COLLECTING; and once,
 *    ALLOCATING (the learner reserves the store for the first frame's map).
 * Memory: the sample store (rows x cols x frames ranges, within a budget)
 * is reserved at start when a model is given, else by the learner thread
 * at the first frame; the models and the learner's work arrays are
 * allocated on the learner thread. The processing thread never allocates.
 *
 * Sampling: the first model from every complete frame of the first
 * learn_seconds (up to the store); afterwards one frame in k, so that the
 * store spans the last window_s seconds, in bursts of RS_BGU_BURST
 * consecutive frames (the learner reads frame-to-frame changes). A relearn
 * is due every every_s seconds of sensor time (capture time) once the
 * samples span at least min(window_s, 120 s) and either span 90 % of
 * window_s or outnumber the frames the model in use was learned from. The candidate
 * replaces the model in use when the samples' returns it calls background
 * are not fewer than the model in use's by more than 0.1 % of them, and it
 * keeps at least 90 % of the cells with a surface. */
#ifndef ROADSCAN_BGUPDATE_H
#define ROADSCAN_BGUPDATE_H

#include "roadscan/perception/background.h"

#include <pthread.h>
#include <semaphore.h>
#include <stdatomic.h>
#include <stdbool.h>
#include <stdint.h>

#define RS_BGU_BUDGET (128ull * 1024 * 1024) /* sample store */
#define RS_BGU_BURST 10 /* relearn samples: this many consecutive frames at a time */
#define RS_BG_SITE_SECONDS 120.0 /* a site with traffic needs this much to tell what stops from the scene */
_Static_assert(RS_BGU_BURST >= 1 && RS_BGU_BURST <= 100, "a burst is a few consecutive frames");

typedef struct {
  double learn_seconds;   /* > 0 with no initial model: learn the first model from this many seconds */
  const char *learn_out;  /* optional: where the first model learned is saved (by the learner thread) */
  double window_s;        /* > 0: keep the model current from the last window_s seconds (default 600) */
  double every_s;         /* relearn every (default 60 s of sensor time) */
  int frames;             /* samples kept (default 600; fewer within RS_BGU_BUDGET) */
  bool sync;              /* lossless replay: wait for the learner (deterministic) */
  rs_bg_params_t params;
  rs_bg_rules_t rules;    /* how a candidate model is scored (the pipeline's subtraction rules) */
} rs_bgu_cfg_t;

void rs_bgu_cfg_default(rs_bgu_cfg_t *c);

enum { RS_BGU_COLLECTING = 0, RS_BGU_LEARNING = 1, RS_BGU_READY = 2, RS_BGU_ALLOCATING = 3 };

typedef struct {
  rs_bgu_cfg_t cfg;
  rs_bg_learner_t store;       /* the samples (a ring over the window after the first model) */
  struct {                     /* the map the store is for */
    rs_model_t model;
    int rows, cols;
    double hz;
  } geo;
  bool ready;                  /* store allocated (at the first frame: the map's size) */
  int k, skip;                 /* one frame in k is sampled, RS_BGU_BURST in a row; skip: the phase */
  int ring;                    /* next slot once the store is full */
  double t_first;              /* sensor time of the oldest sample */
  double t_last_learn;         /* sensor time of the last relearn started */
  float rate_hz;
  rs_bg_model_t models[2];     /* the one in use and the spare */
  bool have[2];
  int active;                  /* index in use, -1 none */
  _Atomic int state;
  sem_t go;                    /* processing -> learner: a relearn is due, or stop */
  sem_t done;                  /* learner -> processing: finished (sync mode) */
  pthread_t thread;
  bool thread_started, sems;
  _Atomic bool quit;
  _Atomic bool finishing; /* rs_bgu_finish waits: the learner keeps (or takes back) the normal priority */
  /* learner results (written by the learner before it releases the state) */
  int last_rc;
  bool saved, save_failed;     /* the first model was saved to learn_out; saving it failed (said in the log) */
  int store_rc;                /* why the sample store could not be reserved (RS_OK: it was, or not yet) */
  char reason[160];            /* why the last candidate was rejected */
  double learn_s;              /* how long the last learning took */
  /* counters (processing thread) */
  int kept;                    /* frames kept for the first model when the input ended (rs_bgu_finish) */
  uint64_t updates, rejected, failed;
  double changed_at;           /* sensor time the model in use was taken over (0: never) */
  int64_t changed_wall;        /* unix time of that */
  uint32_t initial_frames;     /* frames the first model learned from */
} rs_bgu_t;

/* initial: a model to start from (copied; NULL: learn the first one). */
int rs_bgu_init(rs_bgu_t *u, const rs_bgu_cfg_t *cfg, const rs_bg_model_t *initial);
void rs_bgu_deinit(rs_bgu_t *u);
/* The model to subtract now (NULL while the first one is being learned). */
const rs_bg_model_t *rs_bgu_model(const rs_bgu_t *u);
/* Processing thread, once per complete frame (before subtraction): samples,
 * starts a relearn, takes a finished model over. Returns true when the model
 * in use changed with this frame. */
bool rs_bgu_frame(rs_bgu_t *u, const rs_slot_t *s);
/* End of input (the processing thread, after its last frame; or whoever owns
 * the updater once it has joined): when the first model is being learned, its
 * learning is waited for (at most timeout_s of wall time, the learner's
 * priority raised to normal, best effort) and the model taken over, at sensor
 * time t_last; the learner has saved it (learn_out) by then. A replay that
 * ends while its first model is learned keeps it, however loaded the machine
 * (the learner is SCHED_IDLE), unless the learning outlasts timeout_s.
 * Returns true when a model was taken over. */
bool rs_bgu_finish(rs_bgu_t *u, double t_last, double timeout_s);
/* Share of the sampled returns a model calls background (0..1; the check). */
double rs_bgu_explained(const rs_bg_model_t *m, const rs_bg_rules_t *rules, const rs_bg_learner_t *l);
/* Whether a model of `frames` frames at hz (<= 0: 10 Hz assumed) was learned from less than half of the
 * RS_BG_SITE_SECONDS a site with traffic needs (the learner's and the daemon's warning; the updater's
 * first-model rule) */
bool rs_bgu_few_frames(uint32_t frames, double hz);

#endif

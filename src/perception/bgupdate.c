/* bgupdate.c - the static scene learned and kept current while running.
 *
 * Ownership (see bgupdate.h): the processing thread owns the sample store
 * and both models while the state is COLLECTING or READY; the learner
 * thread owns the store and the spare model while it is LEARNING. The
 * state is the only shared variable: release on hand-over, acquire on
 * take-over. */
#define _GNU_SOURCE /* SCHED_IDLE */
#include "roadscan/perception/bgupdate.h"

#include "roadscan/util/error.h"
#include "roadscan/util/log.h"
#include "roadscan/util/timing.h"

#include <math.h>
#include <sched.h>
#include <stdio.h>
#include <string.h>
#include <time.h>

void rs_bgu_cfg_default(rs_bgu_cfg_t *c) {
  memset(c, 0, sizeof *c);
  c->window_s = 600.0;
  c->every_s = 60.0;
  c->frames = 600;
  rs_bg_params_default(&c->params);
  rs_bg_rules_default(&c->rules);
}

double rs_bgu_explained(const rs_bg_model_t *m, const rs_bg_rules_t *rules, const rs_bg_learner_t *l) {
  if (m->rows != l->rows || m->cols != l->cols) return 0.0;
  uint64_t all = 0, bg = 0;
  for (int r = 0; r < l->rows; r++)
    for (int c = 0; c < l->cols; c++) {
      const uint16_t *x = l->samples + ((size_t)r * (size_t)l->cols + (size_t)c) * (size_t)l->max_frames;
      for (int f = 0; f < l->nframes; f++) {
        if (x[f] == 0) continue;
        all++;
        bg += rs_bg_return_static(m, rules, r, c, (float)x[f] / 100.0f, NULL);
      }
    }
  return all ? (double)bg / (double)all : 1.0;
}

static size_t cells_with_surfaces(const rs_bg_model_t *m) {
  size_t n = 0, cells = (size_t)m->rows * m->cols;
  for (size_t c = 0; c < cells; c++) n += m->n[c] > 0;
  return n;
}

/* The learner's work: learn into the spare model, check it against the one
 * in use (if any) on the same samples. Learner thread (or the processing
 * thread in sync mode, which then waits anyway). */
static void learn_once(rs_bgu_t *u) {
  const int spare = u->active < 0 ? 0 : 1 - u->active;
  if (u->have[spare]) rs_bg_model_free(&u->models[spare]);
  u->have[spare] = false;
  u->reason[0] = '\0';
  const int64_t t0 = rs_now_ns();
  u->last_rc = rs_bg_learn(&u->store, &u->cfg.params, u->rate_hz, &u->models[spare]);
  u->learn_s = (double)(rs_now_ns() - t0) * 1e-9;
  if (u->last_rc != RS_OK) {
    snprintf(u->reason, sizeof u->reason, "learning failed: %s", rs_strerror(u->last_rc));
    rs_bg_model_free(&u->models[spare]);
    return;
  }
  u->have[spare] = true;
  if (u->active < 0) {
    /* the first model: saved here, off the processing thread */
    char err[RS_ERRMSG_SIZE];
    if (u->cfg.learn_out && rs_bg_save(&u->models[spare], u->cfg.learn_out, err, sizeof err) != RS_OK) {
      u->save_failed = true;
      rs_log(RS_LOG_ERR, "%s", err);
    } else if (u->cfg.learn_out) {
      u->saved = true;
      rs_log(RS_LOG_INFO, "background model saved to %s", u->cfg.learn_out);
    }
    return;
  }
  const rs_bg_model_t *cur = &u->models[u->active], *cand = &u->models[spare];
  /* a first model of fewer frames than a site with traffic needs (a few seconds' --learn-seconds) took
   * whatever stood then for the scene and so "explains" more than any model of more evidence: a
   * candidate of more frames is not held to that comparison, only to the surfaces (a rush capture
   * learned from 1.5 s: every candidate was refused for 5 minutes; docs/background.md) */
  const bool few = u->updates == 0 && rs_bgu_few_frames(cur->frames, cur->rate_hz) && cand->frames > cur->frames;
  const double e_cur = rs_bgu_explained(cur, &u->cfg.rules, &u->store),
               e_cand = rs_bgu_explained(cand, &u->cfg.rules, &u->store);
  const size_t s_cur = cells_with_surfaces(cur), s_cand = cells_with_surfaces(cand);
  if (!few && e_cand < e_cur - 0.001)
    snprintf(u->reason, sizeof u->reason, "it explains %.2f %% of the recent returns, the model in use %.2f %%",
             100.0 * e_cand, 100.0 * e_cur);
  else if (s_cand * 10 < s_cur * 9)
    snprintf(u->reason, sizeof u->reason, "it has a surface in %zu cells, the model in use in %zu", s_cand, s_cur);
}

/* The sample store, for the geometry in u->geo: as many frames as the
 * budget allows. Allocates: the learner thread (for the first frame's
 * geometry) or rs_bgu_init (an initial model's), never the processing
 * thread. On failure the updater stops sampling (said in the log). */
static void make_store(rs_bgu_t *u) {
  const double hz = u->geo.hz > 0 ? u->geo.hz : 10.0;
  int frames = u->cfg.frames;
  if (u->active < 0 && u->cfg.learn_seconds > 0) {
    int need = (int)ceil(u->cfg.learn_seconds * hz) + 1;
    if (need > frames) frames = need;
  }
  while (frames > 2 && rs_bg_learner_bytes(u->geo.rows, u->geo.cols, frames) > RS_BGU_BUDGET) frames--;
  const int rc = rs_bg_learner_init(&u->store, u->geo.model, u->geo.rows, u->geo.cols, frames, 1);
  if (rc != RS_OK) {
    u->store_rc = rc;
    rs_log(RS_LOG_ERR, "background: cannot reserve %d frames of samples (%s); the model stays as it is", frames,
           rs_strerror(rc));
    u->cfg.window_s = 0;
    u->cfg.learn_seconds = 0;
    return;
  }
  u->ready = true;
  /* after the first model: one frame in k spans the window */
  u->k = u->cfg.window_s > 0 ? (int)fmax(1.0, floor(u->cfg.window_s * hz / frames)) : 1;
}

/* The learner runs at SCHED_IDLE once it learns: a relearn takes what the
 * processing thread leaves. Reserving the store at the first frame is short
 * and comes first, at the normal priority: at idle priority on a busy box the
 * frames of a first model's window would go by before there was a store. */
static void *learner_main(void *arg) {
  rs_bgu_t *u = arg;
  bool idle = false;
  for (;;) {
    sem_wait(&u->go);
    if (atomic_load_explicit(&u->quit, memory_order_acquire)) break;
    const int st = atomic_load_explicit(&u->state, memory_order_acquire);
    if (st == RS_BGU_ALLOCATING) {
      make_store(u);
      atomic_store_explicit(&u->state, RS_BGU_COLLECTING, memory_order_release);
    } else if (st == RS_BGU_LEARNING) {
      if (!idle) {
        struct sched_param sp = {0};
        pthread_setschedparam(pthread_self(), SCHED_IDLE, &sp); /* best effort: not allowed everywhere */
        idle = true;
        /* rs_bgu_finish raises it after setting `finishing`: either it raised it after this, or this
         * sees the flag (sequentially consistent) and takes the normal priority back itself */
        if (atomic_load(&u->finishing)) pthread_setschedparam(pthread_self(), SCHED_OTHER, &sp);
      }
      learn_once(u);
      atomic_store_explicit(&u->state, RS_BGU_READY, memory_order_release);
    } else {
      continue;
    }
    if (u->cfg.sync) sem_post(&u->done);
  }
  return NULL;
}

int rs_bgu_init(rs_bgu_t *u, const rs_bgu_cfg_t *cfg, const rs_bg_model_t *initial) {
  memset(u, 0, sizeof *u);
  u->cfg = *cfg;
  u->active = -1;
  atomic_init(&u->state, RS_BGU_COLLECTING);
  atomic_init(&u->quit, false);
  atomic_init(&u->finishing, false);
  if (initial) {
    int rc = rs_bg_model_copy(&u->models[0], initial);
    if (rc != RS_OK) return rc;
    u->have[0] = true;
    u->active = 0;
    u->initial_frames = initial->frames;
    if (u->cfg.window_s > 0) {
      /* start-up: the store for the model's map */
      u->geo.model = initial->model;
      u->geo.rows = initial->rows;
      u->geo.cols = initial->cols;
      u->geo.hz = initial->rate_hz;
      make_store(u);
    }
  }
  if (sem_init(&u->go, 0, 0) != 0) return RS_E_THREAD;
  if (sem_init(&u->done, 0, 0) != 0) {
    sem_destroy(&u->go);
    return RS_E_THREAD;
  }
  u->sems = true;
  if (pthread_create(&u->thread, NULL, learner_main, u) != 0) return RS_E_THREAD;
  u->thread_started = true;
  return RS_OK;
}

void rs_bgu_deinit(rs_bgu_t *u) {
  if (u->thread_started) {
    atomic_store_explicit(&u->quit, true, memory_order_release);
    sem_post(&u->go);
    pthread_join(u->thread, NULL);
    u->thread_started = false;
  }
  if (u->sems) {
    sem_destroy(&u->go);
    sem_destroy(&u->done);
  }
  u->sems = false;
  for (int i = 0; i < 2; i++)
    if (u->have[i]) rs_bg_model_free(&u->models[i]);
  u->have[0] = u->have[1] = false;
  if (u->ready) rs_bg_learner_free(&u->store);
  u->ready = false;
}

const rs_bg_model_t *rs_bgu_model(const rs_bgu_t *u) { return u->active >= 0 ? &u->models[u->active] : NULL; }

/* takes a finished candidate over (or not) at sensor time t; processing thread */
static bool take_over_at(rs_bgu_t *u, double t) {
  const int spare = u->active < 0 ? 0 : 1 - u->active;
  bool changed = false;
  if (u->last_rc != RS_OK) {
    u->failed++;
    rs_log(RS_LOG_ERR, "background: %s", u->reason);
  } else if (u->reason[0]) {
    u->rejected++;
    rs_log(RS_LOG_WARN, "background: a relearned model was not taken: %s", u->reason);
  } else {
    const bool first = u->active < 0;
    u->active = spare;
    u->changed_at = t;
    u->changed_wall = (int64_t)time(NULL);
    changed = true;
    if (first) {
      u->initial_frames = u->models[spare].frames;
      /* from now on the store keeps the last window */
      u->store.nframes = u->store.nframes < u->store.max_frames ? u->store.nframes : u->store.max_frames;
      u->ring = u->store.nframes % u->store.max_frames;
    } else {
      u->updates++;
    }
    rs_log(RS_LOG_INFO, "background: %s model learned from %u frames in %.1f s", first ? "the" : "an updated",
           u->models[spare].frames, u->learn_s);
  }
  atomic_store_explicit(&u->state, RS_BGU_COLLECTING, memory_order_release);
  return changed;
}

static bool take_over(rs_bgu_t *u, const rs_slot_t *s) { return take_over_at(u, s->meta.t_first); }

/* hands work to the learner thread; lossless replays wait for it */
static void hand_over(rs_bgu_t *u, int state) {
  atomic_store_explicit(&u->state, state, memory_order_release);
  sem_post(&u->go);
  if (u->cfg.sync) {
    while (sem_wait(&u->done) != 0) {
    }
  }
}

static void start_learning(rs_bgu_t *u, const rs_slot_t *s) {
  u->rate_hz = s->meta.rate_hz;
  u->t_last_learn = s->meta.t_first;
  hand_over(u, RS_BGU_LEARNING);
}

bool rs_bgu_few_frames(uint32_t frames, double hz) {
  return frames < RS_BG_SITE_SECONDS * (hz > 0 ? hz : 10.0) * 0.5;
}

/* Whether the samples are enough for a relearn: they span 90 % of the
 * window, or outnumber the frames the model in use was learned from (a first
 * model of a few seconds is bettered early, from the store filled with every
 * frame). The learner needs many samples to tell a queue's cars from the
 * scene: learned from 120 frames of the first two minutes of a rush capture,
 * a model takes 5 % of the road users' returns for background, from 600
 * frames 0.7 % (docs/background.md). */
static bool enough_samples(const rs_bgu_t *u, double span) {
  return span >= 0.9 * u->cfg.window_s || (uint32_t)u->store.nframes > u->models[u->active].frames;
}

bool rs_bgu_frame(rs_bgu_t *u, const rs_slot_t *s) {
  if (s->meta.partial) return false;
  const int st = atomic_load_explicit(&u->state, memory_order_acquire);
  if (st == RS_BGU_READY) return take_over(u, s);
  if (st != RS_BGU_COLLECTING) return false;
  const bool initial = u->active < 0;
  if (initial ? u->cfg.learn_seconds <= 0 : u->cfg.window_s <= 0) return false;
  if (!u->ready) {
    /* the first frame gives the map's size: the learner thread reserves the store */
    u->geo.model = s->meta.model;
    u->geo.rows = s->meta.rows;
    u->geo.cols = s->meta.cols;
    u->geo.hz = s->meta.rate_hz;
    hand_over(u, RS_BGU_ALLOCATING);
    return false;
  }
  if (s->meta.rows != u->store.rows || s->meta.cols != u->store.cols) return false;
  if (initial) {
    /* the first model: every frame of the first learn_seconds */
    if (u->store.nframes == 0) u->t_first = s->meta.t_first;
    if (s->meta.t_first - u->t_first < u->cfg.learn_seconds && u->store.nframes < u->store.max_frames) {
      rs_bg_learner_set(&u->store, u->store.nframes, s);
      return false;
    }
    if (u->store.nframes < 2) return false;
    start_learning(u, s);
    return atomic_load_explicit(&u->state, memory_order_acquire) == RS_BGU_READY && take_over(u, s);
  }
  /* keeping it current: every frame into the store until it is full, then
   * one frame in k into the ring, in bursts of RS_BGU_BURST consecutive
   * frames (the learner's rules read what a cell returns from one frame to
   * the next), so that the ring comes to span the window */
  const int burst = u->k > 1 ? RS_BGU_BURST : 1;
  const int phase = u->skip;
  u->skip = (u->skip + 1) % (u->k * burst);
  if (phase < burst || u->store.nframes < u->store.max_frames) { /* every frame until the store is full */
    if (u->store.nframes == 0) u->t_first = s->meta.t_first;
    rs_bg_learner_set(&u->store, u->ring, s);
    u->ring = (u->ring + 1) % u->store.max_frames;
    if (u->t_last_learn == 0) u->t_last_learn = s->meta.t_first;
  }
  /* the oldest sample: the ring's next slot once full */
  const double oldest = u->store.nframes < u->store.max_frames ? u->t_first : u->store.t[u->ring];
  const double span = s->meta.t_first - oldest;
  if (u->store.nframes >= 2 && span >= 0.9 * fmin(u->cfg.window_s, RS_BG_SITE_SECONDS) && enough_samples(u, span) &&
      s->meta.t_first - u->t_last_learn >= u->cfg.every_s) {
    start_learning(u, s);
    return atomic_load_explicit(&u->state, memory_order_acquire) == RS_BGU_READY && take_over(u, s);
  }
  return false;
}

bool rs_bgu_finish(rs_bgu_t *u, double t_last, double timeout_s) {
  int st = atomic_load_explicit(&u->state, memory_order_acquire);
  u->kept = st != RS_BGU_ALLOCATING && u->ready ? u->store.nframes : 0; /* the store is the learner's while ALLOCATING */
  if (!u->thread_started || u->active >= 0) return false;
  if (st != RS_BGU_LEARNING && st != RS_BGU_READY) return false;
  /* the input is over: nothing left to yield to (best effort, as SCHED_IDLE was) */
  atomic_store(&u->finishing, true);
  struct sched_param sp = {0};
  pthread_setschedparam(u->thread, SCHED_OTHER, &sp);
  const long polls = (long)(fmax(0.0, timeout_s) * 100.0) + 1; /* 10 ms each */
  for (long k = 0; k < polls && st != RS_BGU_READY; k++) {
    const struct timespec d = {0, 10000000L};
    nanosleep(&d, NULL);
    st = atomic_load_explicit(&u->state, memory_order_acquire);
  }
  if (st != RS_BGU_READY) {
    rs_log(RS_LOG_WARN,
           "background: the first model was still being learned %.0f s after the input ended: not used (it is saved "
           "when it is done, with --learn-out)",
           timeout_s);
    return false;
  }
  return take_over_at(u, t_last);
}

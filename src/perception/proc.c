/* proc.c - the processing stages of a frame (processing thread).
 *
 * rs_proc_frame: background -> clustering -> objects -> (tracks), then the
 * census of the map; each stage timed on its own. State: the caller's
 * cluster, object and track areas, the background updater made here. */
#include "roadscan/perception/proc.h"

#include "roadscan/util/error.h"
#include "roadscan/util/log.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static const char *const stage_names[RS_STAGES] = {"background/frame", "cluster/frame", "objects/frame",
                                                   "tracks/frame", "counting/frame"};

const char *rs_proc_stage_name(int stage) {
  return stage >= 0 && stage < RS_STAGES ? stage_names[stage] : "?";
}

static const rs_object_list_t no_objects;

int rs_proc_init(rs_proc_t *p, const rs_proc_cfg_t *cfg, char *err, size_t errlen) {
  memset(p, 0, sizeof *p);
  p->cfg = *cfg;
  for (int k = 0; k < RS_STAGES; k++) rs_timing_init(&p->t_stage[k], stage_names[k]);
  rs_timing_init(&p->t_frame, "processing/frame");
  p->n.min_range = 1e30;
  if (cfg->objects && (cfg->cluster == NULL || cfg->object_list == NULL)) {
    snprintf(err, errlen, "the object stage needs clustering and an object list");
    return RS_E_INVAL;
  }
  if (cfg->tracker && cfg->objects == NULL) {
    snprintf(err, errlen, "the track stage needs the object stage");
    return RS_E_INVAL;
  }
  if (cfg->counter && cfg->tracker == NULL) {
    snprintf(err, errlen, "counting needs the track stage");
    return RS_E_INVAL;
  }
  if (cfg->background == NULL && cfg->learn_seconds <= 0) return RS_OK;
  p->beyond_cells = calloc((size_t)RS_MAX_ROWS * RS_MAX_COLS, sizeof *p->beyond_cells);
  if (p->beyond_cells == NULL) {
    snprintf(err, errlen, "out of memory");
    return RS_E_OOM;
  }
  /* the static scene: learned first (learn_seconds) or loaded, kept current
   * (update_window_s) by the updater's learner thread */
  rs_bgu_cfg_t bc;
  rs_bgu_cfg_default(&bc);
  bc.learn_seconds = cfg->background ? 0 : cfg->learn_seconds;
  bc.learn_out = cfg->learn_out;
  bc.window_s = cfg->update_window_s;
  if (cfg->update_every_s > 0) bc.every_s = cfg->update_every_s;
  bc.sync = cfg->lossless;
  bc.rules.see_through = cfg->see_through == 0 ? RS_BG_SEE_THROUGH : (cfg->see_through < 0 ? 0 : cfg->see_through);
  bc.rules.beyond_static = !cfg->beyond_foreground;
  bc.rules.shift_behind = !cfg->no_behind;
  if (cfg->shift_tol != 0) bc.rules.shift_tol = cfg->shift_tol < 0 ? 0.0 : cfg->shift_tol;
  if (cfg->shift_gate != 0) bc.rules.shift_gate = cfg->shift_gate < 0 ? 0.0 : cfg->shift_gate;
  if (cfg->shift_deg != 0) bc.rules.shift_deg = cfg->shift_deg < 0 ? 0.0 : cfg->shift_deg;
  int rc = rs_bgu_init(&p->bgu, &bc, cfg->background);
  if (rc != RS_OK) {
    snprintf(err, errlen, "background updater: %s", rs_strerror(rc));
    rs_bgu_deinit(&p->bgu);
    free(p->beyond_cells);
    p->beyond_cells = NULL;
    return rc;
  }
  p->bgu_on = true;
  return RS_OK;
}

void rs_proc_deinit(rs_proc_t *p) {
  if (p->bgu_on) rs_bgu_deinit(&p->bgu);
  p->bgu_on = false;
  free(p->beyond_cells);
  p->beyond_cells = NULL;
}

const rs_ground_t *rs_proc_ground(const rs_proc_t *p) { return p->ground_builds > 0 ? &p->ground : NULL; }

const rs_bg_model_t *rs_proc_model(const rs_proc_t *p) { return p->bgu_on ? rs_bgu_model(&p->bgu) : NULL; }

/* Says once when the model in use was learned at another rate, or from less
 * than a site with traffic needs (it is used all the same, and kept current).
 * Only of the first model: an updated one learned from samples one frame in
 * k, whose count says nothing of the seconds they span. */
static void check_model(rs_proc_t *p, const rs_bg_model_t *m, const rs_slot_t *s) {
  if (m == NULL || s->meta.partial) return;
  if (!p->rate_checked && m->rate_hz > 0) {
    p->rate_checked = true;
    double want = m->rate_hz, got = s->meta.rate_hz;
    if (fabs(got - want) > 0.05 * want)
      rs_log(RS_LOG_WARN, "the sensor turns at %.2f Hz, the background model was learned at %.2f Hz: relearn it", got,
             want);
  }
  const double hz = m->rate_hz > 0 ? m->rate_hz : (s->meta.rate_hz > 0 ? s->meta.rate_hz : 10.0);
  if (!p->few_warned && (!p->bgu_on || p->bgu.updates == 0) && rs_bgu_few_frames(m->frames, hz)) {
    p->few_warned = true;
    rs_log(RS_LOG_WARN,
           "the background model was learned from %u frames (%.1f s at %.1f Hz): a site with traffic needs %.0f s "
           "of it for vehicles that stop to be told from the scene (a scene without traffic needs about 1 s); it is "
           "used, and kept current from what the sensor sees%s",
           m->frames, m->frames / hz, hz, RS_BG_SITE_SECONDS, p->cfg.update_window_s > 0 ? "" : " (not: --update-minutes 0)");
  }
}

/* cells with a return per layer, nearest and farthest return */
static void census(const rs_slot_t *s, rs_proc_report_t *r) {
  const uint32_t cells = (uint32_t)s->meta.rows * s->meta.cols;
  float lo = 0.0f, hi = 0.0f;
  uint32_t filled[RS_LAYERS] = {0, 0};
  for (int l = 0; l < RS_LAYERS; l++) {
    const float *rg = s->range + (size_t)l * RS_MAX_CELLS;
    for (uint32_t i = 0; i < cells; i++) {
      float v = rg[i];
      if (v == 0.0f) continue;
      if (filled[0] + filled[1] == 0 || v < lo) lo = v;
      if (v > hi) hi = v;
      filled[l]++;
    }
  }
  for (int l = 0; l < RS_LAYERS; l++) r->filled[l] = filled[l];
  r->min_range = lo;
  r->max_range = hi;
}

static int64_t stage_end(rs_proc_t *p, rs_proc_report_t *r, int k, int64_t t0) {
  const int64_t t1 = rs_now_ns();
  r->ran[k] = true;
  r->stage_ns[k] = t1 - t0;
  rs_timing_add(&p->t_stage[k], t1 - t0);
  return t1;
}

/* the returns of clusters over held tracks, each to the track it belongs to
 * (part of the track stage) */
static void divide_shared(rs_proc_t *p, const rs_slot_t *s, const rs_sensor_t *sensor, rs_proc_report_t *r) {
  const rs_tracker_t *tr = p->cfg.tracker;
  const rs_cluster_t *cl = p->cfg.cluster;
  const uint32_t nobj = p->cfg.object_list->count;
  bool any = false;
  for (uint32_t k = 0; k < nobj && !any; k++) any = rs_track_divided(tr, k);
  if (!any) return;
  const uint32_t limit = RS_LAYERS * RS_MAX_CELLS, rowcells = (uint32_t)s->meta.rows * s->meta.cols;
  uint32_t n = 0;
  for (uint32_t j = 0; j < cl->nmembers && j < limit; j++) {
    const uint32_t c = cl->members[j];
    if (c >= limit || c % RS_MAX_CELLS >= rowcells || s->range[c] == 0.0f) continue;
    const uint32_t lab = s->label[c];
    if (lab < RS_LABEL_FIRST_OBJECT || !rs_track_divided(tr, lab - RS_LABEL_FIRST_OBJECT)) continue;
    if (n == RS_PROC_DIVIDED_MAX) {
      p->n.divided_overflow++; /* the rest go with the object's track */
      continue;
    }
    float xy[2];
    rs_objects_xy(p->cfg.objects, s, sensor, c, xy);
    p->divided_cell[n] = c;
    p->divided_track[n] = rs_track_owner(tr, lab - RS_LABEL_FIRST_OBJECT, xy[0], xy[1]);
    n++;
  }
  r->divided = n;
  p->n.divided += n;
}

void rs_proc_frame(rs_proc_t *p, rs_slot_t *s, const rs_sensor_t *sensor, rs_proc_report_t *r) {
  memset(r, 0, sizeof *r);
  r->objects = &no_objects;
  r->divided_cell = p->divided_cell;
  r->divided_track = p->divided_track;
  const rs_bg_model_t *bgm = NULL;
  if (p->bgu_on) {
    /* outside the frame's time: it waits for the learner only in lossless runs */
    if (rs_bgu_frame(&p->bgu, s)) { /* another model: the cells' counts of returns beyond start again */
      r->model_changed = true;
      memset(p->beyond_cells, 0, sizeof(uint32_t) * (size_t)s->meta.rows * s->meta.cols);
    }
    bgm = rs_bgu_model(&p->bgu);
    check_model(p, bgm, s);
  }
  if (sensor != p->sensor) {
    p->sensor = sensor;
    if (p->cfg.cluster) {
      p->cfg.cluster->sensor = sensor;
      p->cfg.cluster->cols = 0; /* tables made again for this sensor */
    }
  }
  const int64_t t0 = rs_now_ns();
  int64_t t = t0;
  const bool geo = bgm && s->meta.cols == bgm->cols && s->meta.rows == bgm->rows;
  if (geo) {
    if (!p->cfg.no_ground && (r->model_changed || bgm != p->ground_model || sensor != p->ground_sensor)) {
      const int64_t g0 = rs_now_ns();
      rs_ground_build(&p->ground, bgm, sensor);
      p->ground_ns = rs_now_ns() - g0;
      p->ground_model = bgm;
      p->ground_sensor = sensor;
      p->ground_builds++;
    }
    const uint64_t fg0 = p->bg.foreground;
    p->bg.beyond_cells = p->beyond_cells;
    rs_bg_subtract(bgm, &p->bgu.cfg.rules, s, &p->bg);
    r->foreground = (uint32_t)(p->bg.foreground - fg0);
    r->displaced = p->bg.displaced;
    r->shift_evidence = p->bg.evidence;
    t = stage_end(p, r, RS_STAGE_BACKGROUND, t);
  }
  rs_cluster_t *cl = p->cfg.cluster;
  if (cl && cl->cfg.method != RS_CLUSTER_NONE && (bgm || !p->bgu_on)) {
    cl->bg_surfaces = geo ? bgm->n : NULL;
    rs_cluster_run(cl, s, &r->cluster);
    t = stage_end(p, r, RS_STAGE_CLUSTER, t);
    p->n.clusters += r->cluster.clusters;
    p->n.clustered += r->cluster.clustered;
    p->n.noise += r->cluster.noise;
    p->n.splits += r->cluster.splits;
    if (p->cfg.objects) {
      p->cfg.objects->ground = geo && !p->cfg.no_ground && p->ground.valid ? &p->ground : NULL;
      rs_objects_extract_cells(p->cfg.objects, s, sensor, cl->members, cl->nmembers, p->cfg.object_list);
      t = stage_end(p, r, RS_STAGE_OBJECTS, t);
      r->objects = p->cfg.object_list;
      p->n.objects += p->cfg.object_list->count;
      if (p->cfg.tracker) {
        /* the frame's time is its last packet's: capture time, never the wall clock */
        rs_track_frame(p->cfg.tracker, p->cfg.object_list, s->meta.t_last);
        divide_shared(p, s, sensor, r);
        t = stage_end(p, r, RS_STAGE_TRACKS, t);
        r->tracks = &p->cfg.tracker->list;
        p->last_t = s->meta.t_last;
        if (p->cfg.counter) {
          if (rs_count_frame(p->cfg.counter, r->tracks, s->meta.t_last)) r->counts = &p->cfg.counter->closed;
          r->crossings = p->cfg.counter->events;
          r->ncrossings = p->cfg.counter->nevents;
          t = stage_end(p, r, RS_STAGE_COUNTING, t);
        }
      }
    }
  }
  census(s, r);
  const rs_frame_meta_t *m = &s->meta;
  p->n.frames++;
  if (m->partial) p->n.partial_frames++;
  p->n.missing_packets += m->missing_packets;
  p->n.points += m->points;
  for (int l = 0; l < RS_LAYERS; l++) p->n.cells_filled[l] += r->filled[l];
  if (r->filled[0] + r->filled[1] > 0) {
    if (r->min_range < p->n.min_range) p->n.min_range = r->min_range;
    if (r->max_range > p->n.max_range) p->n.max_range = r->max_range;
  }
  r->total_ns = rs_now_ns() - t0;
  rs_timing_add(&p->t_frame, r->total_ns);
}

void rs_proc_finish(rs_proc_t *p, rs_proc_report_t *r) {
  memset(r, 0, sizeof *r);
  r->objects = &no_objects;
  r->divided_cell = p->divided_cell;
  r->divided_track = p->divided_track;
  if (p->cfg.counter && rs_count_flush(p->cfg.counter, p->last_t)) r->counts = &p->cfg.counter->closed;
  if (p->cfg.counter) {
    r->crossings = p->cfg.counter->events;
    r->ncrossings = p->cfg.counter->nevents;
  }
  if (p->bgu_on) rs_bgu_finish(&p->bgu, p->last_t, RS_PROC_FINISH_LEARN_S); /* a first model under way */
}

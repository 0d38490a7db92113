/* background.c - static-scene learning, model file, subtraction.
 *
 * Learning runs at start-up or in the learning tool and allocates; the
 * subtraction runs in the processing thread on the preallocated model. */
#include "roadscan/perception/background.h"
#include "roadscan/util/rand.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <errno.h>
#include <string.h>
#include <unistd.h>
#include <time.h>


void rs_bg_params_default(rs_bg_params_t *p) {
  memset(p, 0, sizeof *p);
  p->method = RS_BG_DBSCAN;
  p->min_pts_floor = 10;
  p->min_pts_share = 0.01;
  p->eps_min = 0.08;
  p->eps_max = 0.40;
  p->eps_step = 0.01;
  p->persist_max = 0.8;
  p->void_stay = 0.6;
  p->flicker_lift = 0.25;
  p->coverage_min = 0.8;
  p->coverage_open = 0.5;
  p->sparse_cover = 0.8;
  p->leaves_range = 0.7;
  p->window_s = 5.0;
  p->pair_gap_s = 1.0;
  p->margin_min = 0.05;
  p->margin_share = 0.006;
  p->merge_gap_min = 0.5;
  p->merge_gap_share = 0.02;
  p->chain_gap = 0.20;
  p->occluded_max = 0.2;
  p->occluded_seen = 0.1;
  p->occluded_windows = 0.5;
  p->occluded_spread = 0.15;
  p->occluded_clear = 0.2;
  p->support = true;
  p->support_tol_min = 0.3;
  p->support_tol_share = 0.03;
  p->connect_min = 0.5;
  p->margin_samples = 4.0;
  p->wide_min = 2.0;
  p->wide_share = 0.15;
  p->connect_share = 0.05;
  p->percentile = 50.0;
  p->percentile_tol = 0.3;
}

int rs_bg_model_alloc(rs_bg_model_t *m, rs_model_t model, int rows, int cols) {
  memset(m, 0, sizeof *m);
  if (rows < 1 || rows > RS_MAX_ROWS || cols < RS_MIN_COLS || cols > RS_MAX_COLS) return RS_E_INVAL;
  size_t cells = (size_t)rows * (size_t)cols;
  m->model = model;
  m->rows = (uint16_t)rows;
  m->cols = (uint16_t)cols;
  m->n = calloc(cells, 1);
  m->far_seen = calloc(cells, 1);
  m->lo = calloc(cells * RS_BG_SURFACES, sizeof(uint16_t));
  m->hi = calloc(cells * RS_BG_SURFACES, sizeof(uint16_t));
  if (!m->n || !m->far_seen || !m->lo || !m->hi) {
    rs_bg_model_free(m);
    return RS_E_OOM;
  }
  rs_bg_params_default(&m->params);
  return RS_OK;
}

void rs_bg_rules_default(rs_bg_rules_t *r) {
  *r = (rs_bg_rules_t){.see_through = RS_BG_SEE_THROUGH,
                       .beyond_static = true,
                       .shift_tol = RS_BG_SHIFT_TOL,
                       .shift_gate = RS_BG_SHIFT_GATE,
                       .shift_deg = RS_BG_SHIFT_DEG,
                       .shift_behind = true};
}

void rs_bg_model_free(rs_bg_model_t *m) {
  free(m->n);
  free(m->far_seen);
  m->far_seen = NULL;
  free(m->lo);
  free(m->hi);
  m->n = NULL;
  m->lo = m->hi = NULL;
}

/* ---- subtraction ---- */

static int match(const rs_bg_model_t *m, uint32_t cell, uint32_t cm) {
  const uint32_t base = cell * RS_BG_SURFACES;
  for (int k = 0; k < m->n[cell]; k++)
    if (cm >= m->lo[base + k] && cm <= m->hi[base + k]) return 1;
  return 0;
}

static inline uint32_t to_cm(float r) { return r >= 655.0f ? 65534u : (uint32_t)(r * 100.0f + 0.5f); }

bool rs_bg_is_static(const rs_bg_model_t *m, int row, int col, float r) {
  return match(m, (uint32_t)row * m->cols + (uint32_t)col, to_cm(r));
}

/* a see-through cell: does the range match a surface of the cell on either side? */
/* a return matches a surface of the cell on either side in the row, of a
 * cell whose farthest surface is seen in at least min_seen % of frames */
static bool match_beside(const rs_bg_model_t *m, int row, int col, uint32_t cm, int min_seen) {
  const uint32_t cols = m->cols, base = (uint32_t)row * cols;
  const uint32_t left = base + (col > 0 ? (uint32_t)col - 1 : cols - 1);
  const uint32_t right = base + ((uint32_t)col + 1 < cols ? (uint32_t)col + 1 : 0);
  return (m->far_seen[left] >= min_seen && match(m, left, cm)) || (m->far_seen[right] >= min_seen && match(m, right, cm));
}

/* one return: background? (*beyond: it lies beyond the cell's farthest surface) */
static bool classify(const rs_bg_model_t *m, const rs_bg_rules_t *rules, int r, int col, uint32_t cell, uint32_t cm,
                     bool *beyond) {
  *beyond = false;
  /* a cell the sensor sees through matches the surfaces beside it; a cell
   * with none learned (too few returns) those of a cell beside it whose
   * farthest surface is seen in half the frames or more (not a queue taken
   * for the scene where the road is out of reach) */
  const int see = rules->see_through;
  if (match(m, cell, cm) ||
      (see > 0 && (m->n[cell] >= see || m->n[cell] == 0) && match_beside(m, r, col, cm, m->n[cell] == 0 ? 50 : 0)))
    return true;
  /* beyond the farthest surface: a surface has gone, or the sensor moved
   * (counted). Behind a solid surface (seen in most frames) nothing moves:
   * background. Behind one the sensor sees through (a canopy) only just
   * behind it (max(0.3 m, 3 %): the surface seen from a slightly different
   * place); farther, it can be a vehicle. */
  const uint32_t nk = m->n[cell];
  if (nk == 0) return false;
  const uint32_t far = m->hi[cell * RS_BG_SURFACES + nk - 1];
  if (far == RS_BG_BEYOND || cm <= far) return false;
  *beyond = true;
  return rules->beyond_static && (m->far_seen[cell] >= RS_BG_SOLID_PCT || cm - far <= (far < 1000u ? 30u : far * 3u / 100u));
}

bool rs_bg_return_static(const rs_bg_model_t *m, const rs_bg_rules_t *rules, int row, int col, float r, bool *beyond) {
  bool b;
  bool st = classify(m, rules, row, col, (uint32_t)row * m->cols + (uint32_t)col, to_cm(r), &b);
  if (beyond) *beyond = b;
  return st;
}

/* A displaced sensor. A return anywhere in its column and a surface anywhere
 * in a column k away are (|k| - 1/2) column widths apart at least, in the
 * row (the elevation is the same). cosk[k]: the cosine of that angle. */
typedef struct {
  double cosk[RS_BG_SHIFT_COLS + 1];
  double w, tol, share;
} shift_t;

static void shift_init(shift_t *sh, const rs_bg_model_t *m, double tol, double deg) {
  sh->w = 2.0 * M_PI / m->cols;
  sh->tol = tol;
  sh->share = tan(deg * M_PI / 180.0);
  for (int k = 0; k <= RS_BG_SHIFT_COLS; k++) sh->cosk[k] = cos(fmax(0.0, (k - 0.5) * sh->w));
}

/* is a return of cm in (row, col) within tol (3D) of a surface of a cell
 * nearby in the row? The distance from the return to the segment of a
 * surface's ranges along the other column's direction. */
static bool match_shifted(const rs_bg_model_t *m, const shift_t *sh, int row, int col, uint32_t cm) {
  const double r = cm / 100.0, tol = fmax(sh->tol, r * sh->share);
  if (r <= 0.0) return false;
  int kmax = (int)ceil(asin(fmin(1.0, tol / r)) / sh->w + 0.5);
  if (kmax > RS_BG_SHIFT_COLS) kmax = RS_BG_SHIFT_COLS;
  const int cols = m->cols;
  if (kmax > cols / 2) kmax = cols / 2;
  const uint32_t base = (uint32_t)row * (uint32_t)cols;
  for (int k = -kmax; k <= kmax; k++) {
    if (k == 0) continue;
    const double ca = sh->cosk[k < 0 ? -k : k];
    const int c = ((col + k) % cols + cols) % cols;
    const uint32_t cell = base + (uint32_t)c, b = cell * RS_BG_SURFACES;
    for (int j = 0; j < m->n[cell]; j++) {
      const double lo = m->lo[b + j] / 100.0, hi = m->hi[b + j] == RS_BG_BEYOND ? 655.35 : m->hi[b + j] / 100.0;
      const double t = fmin(hi, fmax(lo, r * ca));
      if (r * r + t * t - 2.0 * r * t * ca <= tol * tol) return true;
    }
  }
  return false;
}

/* A displaced sensor also sees past a near object onto what the object hid
 * while the model was learned: cells that learned only the object, or
 * nothing, now return a wall behind it. A sensor displaced by up to the
 * tolerance D sees past an object at range r_o by at most atan(D / r_o) of
 * azimuth: the parallax band beside the object's edges (8 cm beside an
 * object 1.3 m away: 3.5 degrees). Is a return of cm in (row, col) in that
 * band of a depth edge: a cell nearby in the row whose farthest surface is
 * nearer than the return (the object) and, within the same band, a cell
 * whose farthest surface lies behind the object but no farther than the
 * return (plus D)? What was hidden continues the far side of the edge, away
 * from the sensor; a vehicle behind the object is nearer than the far side
 * (a wall, the road beyond). Only past the model, only in displaced frames.
 * Work: 2 x RS_BG_SHIFT_COLS + 1 cells, each looked at twice. */
static bool match_behind(const rs_bg_model_t *m, const shift_t *sh, int row, int col, uint32_t cm) {
  const double r = cm / 100.0;
  const int cols = m->cols, kmax = RS_BG_SHIFT_COLS < cols / 2 ? RS_BG_SHIFT_COLS : cols / 2;
  const uint32_t base = (uint32_t)row * (uint32_t)cols;
  /* far[k + kmax]: the farthest surface of the cell k columns away (-1: none);
   * reach[d]: the farthest of those within d columns that lie no farther
   * than the return plus D (the far side of an edge it may continue) */
  double far[2 * RS_BG_SHIFT_COLS + 1], reach[RS_BG_SHIFT_COLS + 1];
  for (int k = -kmax; k <= kmax; k++) {
    const uint32_t cell = base + (uint32_t)(((col + k) % cols + cols) % cols);
    const int nk = m->n[cell];
    const uint32_t b = cell * RS_BG_SURFACES + (uint32_t)nk - 1;
    far[k + kmax] = nk == 0 || m->hi[b] == RS_BG_BEYOND ? -1.0 : (m->lo[b] + m->hi[b]) / 200.0;
  }
  for (int d = 0; d <= kmax; d++) {
    reach[d] = d > 0 ? reach[d - 1] : -1.0;
    for (int q = -1; q <= 1; q += 2) {
      const double f = far[q * d + kmax];
      if (f <= r + sh->tol && f > reach[d]) reach[d] = f;
    }
  }
  for (int k = -kmax; k <= kmax; k++) {
    const double ro = far[k + kmax];
    if (ro <= 0.0 || r - ro <= fmax(RS_BG_BEHIND_JUMP, RS_BG_BEHIND_JUMP_SHARE * r)) continue; /* not in front */
    int band = (int)(atan(sh->tol / ro) / sh->w + 0.5);
    if (band > kmax) band = kmax;
    if ((k < 0 ? -k : k) > band) continue;
    /* the farthest surface in the band is the best far side: the jump grows slower than the range */
    const double f = reach[band];
    if (f - ro > fmax(RS_BG_BEHIND_JUMP, RS_BG_BEHIND_JUMP_SHARE * f)) return true;
  }
  return false;
}

/* the return lies beyond its cell's farthest surface, or the cell learned none */
static bool past_model(const rs_bg_model_t *m, uint32_t cell, uint32_t cm) {
  const uint32_t nk = m->n[cell];
  return nk == 0 || (m->hi[cell * RS_BG_SURFACES + nk - 1] != RS_BG_BEYOND && cm > m->hi[cell * RS_BG_SURFACES + nk - 1]);
}

void rs_bg_subtract(const rs_bg_model_t *m, const rs_bg_rules_t *rules, rs_slot_t *s, rs_bg_counts_t *c) {
  const int rows = s->meta.rows, cols = s->meta.cols;
  const bool shift_on = rules->shift_tol > 0.0, gated = rules->shift_gate > 0.0;
  shift_t sh;
  if (shift_on) shift_init(&sh, m, rules->shift_tol, rules->shift_deg);
  /* evidence of displacement: enough of it, and it is no longer gathered */
  const uint64_t need = shift_on && gated ? (uint64_t)ceil(rules->shift_gate * (double)(s->meta.points ? s->meta.points : 1)) : 0;
  uint64_t evidence = 0, fg = 0;
  for (int l = 0; l < RS_LAYERS; l++)
    for (int r = 0; r < rows; r++) {
      const uint32_t base = (uint32_t)l * RS_MAX_CELLS + (uint32_t)r * (uint32_t)cols;
      for (int col = 0; col < cols; col++) {
        const float range = s->range[base + (uint32_t)col];
        if (range == 0.0f) continue;
        const uint32_t cell = (uint32_t)r * (uint32_t)cols + (uint32_t)col, cm = to_cm(range);
        bool beyond;
        const bool st = classify(m, rules, r, col, cell, cm, &beyond);
        if (beyond) {
          if (c->beyond_cells) c->beyond_cells[cell]++;
          c->beyond++;
          if (evidence < need && match_shifted(m, &sh, r, col, cm)) evidence++;
        }
        s->label[base + (uint32_t)col] = st ? RS_LABEL_BACKGROUND : RS_LABEL_NOISE;
        if (st) c->background++;
        else fg++;
      }
    }
  c->evidence = (uint32_t)evidence;
  c->displaced = shift_on && evidence >= need; /* ungated (shift_gate 0): every frame */
  if (c->displaced) {
    c->displaced_frames++;
    for (int l = 0; l < RS_LAYERS && fg > 0; l++)
      for (int r = 0; r < rows; r++) {
        const uint32_t base = (uint32_t)l * RS_MAX_CELLS + (uint32_t)r * (uint32_t)cols;
        for (int col = 0; col < cols; col++) {
          const uint32_t i = base + (uint32_t)col;
          if (s->label[i] != RS_LABEL_NOISE) continue;
          const uint32_t cm = to_cm(s->range[i]), cell = (uint32_t)r * (uint32_t)cols + (uint32_t)col;
          if (match_shifted(m, &sh, r, col, cm)) c->shifted++;
          else if (rules->shift_behind && past_model(m, cell, cm) &&
                   match_behind(m, &sh, r, col, cm))
            c->behind++;
          else continue;
          s->label[i] = RS_LABEL_BACKGROUND;
          c->background++;
          fg--;
        }
      }
  }
  c->foreground += fg;
}

int rs_bg_model_copy(rs_bg_model_t *dst, const rs_bg_model_t *src) {
  int rc = rs_bg_model_alloc(dst, src->model, src->rows, src->cols);
  if (rc != RS_OK) return rc;
  const size_t cells = (size_t)src->rows * src->cols;
  dst->rate_hz = src->rate_hz;
  dst->params = src->params;
  dst->frames = src->frames;
  dst->created = src->created;
  memcpy(dst->n, src->n, cells);
  memcpy(dst->far_seen, src->far_seen, cells);
  memcpy(dst->lo, src->lo, cells * RS_BG_SURFACES * sizeof *dst->lo);
  memcpy(dst->hi, src->hi, cells * RS_BG_SURFACES * sizeof *dst->hi);
  return RS_OK;
}

/* ---- 1-D DBSCAN on sorted unique values with counts ---- */

int rs_bg_dbscan1d(const int32_t *v, const uint32_t *c, int u, int32_t eps, uint32_t min_pts, int16_t *label) {
  /* core values (positive labels): the count within eps reaches min_pts */
  int lo = 0, hi = 0;
  uint64_t win = 0;
  for (int i = 0; i < u; i++) {
    while (hi < u && v[hi] - v[i] <= eps) win += c[hi++];
    while (v[i] - v[lo] > eps) win -= c[lo++];
    label[i] = win >= min_pts ? 1 : 0;
  }
  /* clusters: runs of core values no more than eps apart, numbered from 1 */
  int k = 0, last_core = -1;
  for (int i = 0; i < u; i++) {
    if (label[i] <= 0) continue;
    if (last_core < 0 || v[i] - v[last_core] > eps) k++;
    label[i] = (int16_t)k;
    last_core = i;
  }
  /* border values (negative labels) join the nearest core value within eps */
  int prev_core = -1;
  for (int i = 0; i < u; i++) {
    if (label[i] > 0) {
      prev_core = i;
      continue;
    }
    int next_core = -1;
    for (int j = i + 1; j < u && v[j] - v[i] <= eps; j++)
      if (label[j] > 0) {
        next_core = j;
        break;
      }
    int32_t dp = prev_core >= 0 ? v[i] - v[prev_core] : INT32_MAX;
    int32_t dn = next_core >= 0 ? v[next_core] - v[i] : INT32_MAX;
    if (dp <= eps && dp <= dn) label[i] = (int16_t)-label[prev_core];
    else if (dn <= eps) label[i] = (int16_t)-label[next_core];
  }
  for (int i = 0; i < u; i++) label[i] = (int16_t)(label[i] > 0 ? label[i] - 1 : (label[i] < 0 ? -label[i] - 1 : -1));
  return k;
}

double rs_bg_silhouette1d(const int32_t *v, const uint32_t *c, int u, const int16_t *label, int k) {
  if (k < 2) return NAN;
  /* per cluster: weighted count and sum; clusters are intervals in 1-D */
  double n[RS_BG_SURFACES * 8] = {0}, sum[RS_BG_SURFACES * 8] = {0};
  if (k > RS_BG_SURFACES * 8) return NAN;
  for (int i = 0; i < u; i++)
    if (label[i] >= 0) {
      n[label[i]] += c[i];
      sum[label[i]] += (double)c[i] * v[i];
    }
  /* mean distance of x to a cluster: exact with prefix sums inside the own
   * cluster; other clusters lie wholly on one side except at ties */
  double total = 0, weight = 0;
  double run_n = 0, run_s = 0;
  int cur = -1;
  for (int i = 0; i < u; i++) {
    int a = label[i];
    if (a < 0) continue;
    if (a != cur) {
      cur = a;
      run_n = 0;
      run_s = 0;
    }
    double x = v[i];
    /* values of own cluster below x: run_n, run_s; above: the rest minus this value's copies */
    double below_n = run_n, below_s = run_s;
    double above_n = n[a] - run_n - c[i], above_s = sum[a] - run_s - (double)c[i] * x;
    double own = n[a] - 1; /* other members (ties at distance 0 included) */
    double ai = own > 0 ? (x * below_n - below_s + above_s - x * above_n) / own : 0.0;
    double bi = INFINITY;
    for (int b = 0; b < k; b++) {
      if (b == a || n[b] == 0) continue;
      double mb = fabs(sum[b] / n[b] - x);
      if (mb < bi) bi = mb;
    }
    double si = (own <= 0 || !isfinite(bi)) ? 0.0 : (bi - ai) / fmax(ai, bi);
    total += si * c[i];
    weight += c[i];
    run_n += c[i];
    run_s += (double)c[i] * x;
  }
  return weight > 0 ? total / weight : NAN;
}

/* weighted mean pairwise distance inside cluster 0 of a one-cluster labelling */
static double intra1d(const int32_t *v, const uint32_t *c, int u, const int16_t *label) {
  double run_n = 0, run_s = 0, pairs = 0, dist = 0;
  for (int i = 0; i < u; i++) {
    if (label[i] < 0) continue;
    dist += (double)c[i] * ((double)v[i] * run_n - run_s);
    pairs += (double)c[i] * run_n + (double)c[i] * (c[i] - 1) / 2.0;
    run_n += c[i];
    run_s += (double)c[i] * v[i];
  }
  return pairs > 0 ? dist / pairs : 0.0; /* one value: no spread */
}

/* ---- learning ---- */

size_t rs_bg_learner_bytes(int rows, int cols, int max_frames) {
  return (size_t)rows * (size_t)cols * (size_t)max_frames * sizeof(uint16_t);
}

int rs_bg_learner_init(rs_bg_learner_t *l, rs_model_t model, int rows, int cols, int max_frames, uint64_t seed) {
  memset(l, 0, sizeof *l);
  if (rows < 1 || rows > RS_MAX_ROWS || cols < RS_MIN_COLS || cols > RS_MAX_COLS || max_frames < 2) return RS_E_INVAL;
  l->model = model;
  l->rows = rows;
  l->cols = cols;
  l->max_frames = max_frames;
  l->samples = malloc(rs_bg_learner_bytes(rows, cols, max_frames));
  l->t = calloc((size_t)max_frames, sizeof(double));
  l->rng = seed * 0x9E3779B97F4A7C15ull + 1;
  if (l->samples == NULL || l->t == NULL) {
    rs_bg_learner_free(l);
    return RS_E_OOM;
  }
  return RS_OK;
}

void rs_bg_learner_free(rs_bg_learner_t *l) {
  free(l->samples);
  free(l->t);
  l->samples = NULL;
  l->t = NULL;
}

void rs_bg_learner_set(rs_bg_learner_t *l, int f, const rs_slot_t *s) {
  if (f < 0 || f >= l->max_frames || s->meta.rows != l->rows || s->meta.cols != l->cols) return;
  if (f >= l->nframes) l->nframes = f + 1;
  l->t[f] = s->meta.t_first;
  const size_t cells = (size_t)l->rows * (size_t)l->cols;
  for (size_t i = 0; i < cells; i++) {
    float r = s->range[i];
    l->samples[i * (size_t)l->max_frames + (size_t)f] = r <= 0.0f ? 0 : (r >= 655.0f ? 65534 : (uint16_t)(r * 100.0f + 0.5f));
  }
}

void rs_bg_learner_add(rs_bg_learner_t *l, const rs_slot_t *s) {
  if (s->meta.rows != l->rows || s->meta.cols != l->cols) return;
  int f;
  if (l->nframes < l->max_frames) {
    f = l->nframes++;
  } else {
    uint64_t j = rs_xorshift64(&l->rng) % (l->seen + 1);
    if (j >= (uint64_t)l->max_frames) {
      l->seen++;
      return;
    }
    f = (int)j;
  }
  l->seen++;
  l->t[f] = s->meta.t_first;
  const size_t cells = (size_t)l->rows * (size_t)l->cols;
  for (size_t i = 0; i < cells; i++) {
    float r = s->range[i];
    l->samples[i * (size_t)l->max_frames + (size_t)f] = r <= 0.0f ? 0 : (r >= 655.0f ? 65534 : (uint16_t)(r * 100.0f + 0.5f));
  }
}

static int cmp_i32(const void *a, const void *b) {
  int32_t x = *(const int32_t *)a, y = *(const int32_t *)b;
  return (x > y) - (x < y);
}

#define MAXK 32

typedef struct {
  int32_t lo, hi;
  uint32_t count;
  uint32_t pairs, stay;  /* consecutive-sample pairs starting in the cluster, and staying */
  uint32_t second;       /* pairs (of any start) whose second sample is in the cluster */
  uint32_t windows;      /* time windows in which it appears */
  uint32_t front, behind; /* returns nearer than it, farther than it */
  uint32_t open;          /* time windows with a sample not in front of it (no return, or at its range or farther) */
  /* the frames it could be seen in (not hidden by a return in front of it), as the leaves rule reads them */
  uint32_t open_frames, open_seen; /* such frames, and those it is seen in */
  uint32_t open_in, open_stay;     /* pairs of such frames starting in it, and staying */
  uint32_t open_out, open_back;    /* pairs of such frames starting out of it, and coming back */
  double step;                     /* sum over the pairs that stay of the change of range (cm) */
  double spread_mean;              /* mean difference of range between two of its samples (cm) */
} clus_t;

/* Chooses eps and clusters one cell; returns the number of clusters. */
static int cluster_cell(const rs_bg_params_t *p, int32_t *vals, int nz, uint32_t min_pts, int32_t *v, uint32_t *c,
                        int16_t *label, int *u_out, int32_t *eps_out) {
  qsort(vals, (size_t)nz, sizeof vals[0], cmp_i32);
  int u = 0;
  for (int i = 0; i < nz; i++) {
    if (u > 0 && v[u - 1] == vals[i]) c[u - 1]++;
    else {
      v[u] = vals[i];
      c[u] = 1;
      u++;
    }
  }
  *u_out = u;
  const int32_t e0 = (int32_t)lround(p->eps_min * 100), e1 = (int32_t)lround(p->eps_max * 100);
  const int32_t es = (int32_t)fmax(1, lround(p->eps_step * 100));
  double best_sil = -INFINITY, best_intra = INFINITY;
  int32_t eps_multi = -1, eps_single = -1;
  for (int32_t eps = e0; eps <= e1; eps += es) {
    int k = rs_bg_dbscan1d(v, c, u, eps, min_pts, label);
    if (k >= 2 && k <= MAXK) {
      double s = rs_bg_silhouette1d(v, c, u, label, k);
      if (s > best_sil) {
        best_sil = s;
        eps_multi = eps;
      }
    } else if (k == 1) {
      double in = intra1d(v, c, u, label);
      if (in < best_intra) {
        best_intra = in;
        eps_single = eps;
      }
    }
  }
  int32_t eps = eps_multi >= 0 ? eps_multi : eps_single;
  if (eps < 0) return 0;
  *eps_out = eps;
  return rs_bg_dbscan1d(v, c, u, eps, min_pts, label);
}

static int find_value(const int32_t *v, int u, int32_t x) {
  int a = 0, b = u - 1;
  while (a <= b) {
    int m = (a + b) / 2;
    if (v[m] == x) return m;
    if (v[m] < x) a = m + 1;
    else b = m - 1;
  }
  return -1;
}

/* Flickering clusters of one cell less than gap apart become one (ids
 * renumbered from 0 in range order); returns the new count. A surface seen
 * at a grazing angle is sampled at the 0.01 degree steps of the azimuth
 * field: its ranges come in clumps (0.17 m apart for a facade at 190 m seen
 * 6 degrees off its plane), each flickering but too sparse to be present in
 * most windows, yet the surface is. A vehicle does not flicker: its cluster
 * is never joined to one beside it. */
static int chain_clusters(const int32_t *v, int u, int16_t *label, int32_t gap, const bool *flicker) {
  int16_t grp[MAXK];
  int g = -1, last = -1;
  int32_t prev = 0;
  for (int i = 0; i < u; i++) {
    if (label[i] < 0) continue;
    if (label[i] != last) {
      if (g < 0 || v[i] - prev > gap || !flicker[label[i]] || !flicker[last]) g++;
      grp[label[i]] = (int16_t)g;
      last = label[i];
    }
    prev = v[i];
  }
  for (int i = 0; i < u; i++)
    if (label[i] >= 0) label[i] = grp[label[i]];
  return g + 1;
}

/* whether a sample x (cm, 0 = no return) of a cell could show a cluster
 * starting at lo: nothing returned in front of it */
static bool shows(uint16_t x, int32_t lo) { return x == 0 || (int32_t)x >= lo; }

/* one cell's samples, for the cluster statistics */
typedef struct {
  const int32_t *v;
  const uint32_t *cnt;
  int u;
  const uint16_t *smp; /* [stored frame] range in cm, 0 = no return */
  const int *order;    /* stored frames in time order */
  const int *win;      /* time window of each, in that order */
  int nf, nz;
  const double *t;
  double pair_gap_s;
} cell_in_t;

static bool flickers(const clus_t *q, uint32_t npairs, double lift) {
  /* whether the next sample is in the cluster hardly depends on whether
   * this one was (leaves); a vehicle stays for several frames. (A cluster
   * present in more than 1 - lift of the frames always passes: it is
   * present, flickering or not. Normalising the lift by 1 - base was tried:
   * it loses the main return of surfaces that come in two, rush static
   * 99.76 -> 99.39 %, the real capture 0.26 -> 0.37 % foreground.) */
  double stay = q->pairs ? (double)q->stay / q->pairs : 1.0;
  double base = npairs ? (double)q->second / npairs : 0.0;
  return q->pairs >= 10 && stay - base < lift;
}

/* leaves: over the frames that could show it (the cell returned nothing, or
 * something at its range or beyond), whether it is seen in the next one
 * hardly depends on whether it is seen in this one, both ways (P(next in | in)
 * - P(in) and P(in) - P(next in | out) below lift), and from one frame to the
 * next its range changes by at least range_share of the mean difference
 * between two of its samples: a dense canopy behind a lane. Its leaves return
 * in most frames, so whether they return next frame depends on whether
 * traffic in front hides them, which the flicker test over all frames takes
 * for a vehicle staying; but when the cell could see them, each frame draws
 * anew whether a leaf is hit, and at which depth of the canopy. A vehicle
 * stays (once in, in next frame), once gone stays gone, and moves smoothly
 * through its range; a queue's cars stop at about the same place and each
 * stands still. A wall behind the traffic passes too, as it should. */
static bool leaves(const clus_t *q, double lift, double range_share) {
  if (range_share <= 0 || q->open_in < 10 || q->open_out < 10 || q->stay < 10 || q->spread_mean <= 0) return false;
  const double base = (double)q->open_seen / q->open_frames;
  return (double)q->open_stay / q->open_in - base < lift && base - (double)q->open_back / q->open_out < lift &&
         q->step / q->stay >= range_share * q->spread_mean;
}

/* whether a cluster [lo, hi] (cm) of a cell comes and goes independently of
 * what the cells beside it in the row return at about its range: a surface
 * whose returns drop out at random drops out in each cell on its own, a
 * vehicle passing covers several cells at once. For each neighbour, P(it
 * returns within max(0.5 m, 2 %) of [lo, hi] | the cluster is seen) minus
 * P(it does) is below lift. */
static bool alone_in_row(const rs_bg_learner_t *l, size_t cell, int nf, int32_t lo, int32_t hi, double lift) {
  const size_t col = cell % (size_t)l->cols, base = cell - col;
  const int32_t tol = (int32_t)lround(fmax(50.0, 0.02 * lo));
  const uint16_t *smp = l->samples + cell * (size_t)l->max_frames;
  for (int side = 0; side < 2; side++) {
    const size_t nc = base + (side ? (col + 1 < (size_t)l->cols ? col + 1 : 0) : (col > 0 ? col - 1 : (size_t)l->cols - 1));
    const uint16_t *nb = l->samples + nc * (size_t)l->max_frames;
    uint32_t in = 0, both = 0, near = 0;
    for (int f = 0; f < nf; f++) {
      const bool n_in = nb[f] && nb[f] >= lo - tol && nb[f] <= hi + tol;
      near += n_in;
      if (smp[f] && smp[f] >= lo && smp[f] <= hi) {
        in++;
        both += n_in;
      }
    }
    if (in == 0 || (double)both / in - (double)near / nf >= lift) return false;
  }
  return true;
}

/* the windows (wn[w] frames sampled in window w) a cluster returning in each
 * frame at random with probability r is expected to be seen in */
static double random_windows(const int *wn, int nwin, double r) {
  double e = 0.0;
  for (int w = 0; w < nwin; w++) e += 1.0 - pow(1.0 - r, wn[w]);
  return e;
}

/* extent, count, time windows and consecutive pairs of every cluster and of
 * "no return" (cl[k]); memb = cluster of every stored frame in time order.
 * Returns the number of consecutive pairs. */
static uint32_t cell_stats(const cell_in_t *in, const int16_t *label, int k, clus_t *cl, int16_t *memb) {
  memset(cl, 0, sizeof(clus_t) * (size_t)(k + 1));
  for (int j = 0; j < k; j++) {
    cl[j].lo = INT32_MAX;
    cl[j].hi = INT32_MIN;
  }
  for (int i = 0; i < in->u; i++) {
    if (label[i] < 0) continue;
    clus_t *q = &cl[label[i]];
    if (in->v[i] < q->lo) q->lo = in->v[i];
    if (in->v[i] > q->hi) q->hi = in->v[i];
    q->count += in->cnt[i];
  }
  for (int i = 0; i < in->nf; i++) {
    uint16_t x = in->smp[in->order[i]];
    if (x == 0) memb[i] = (int16_t)k;
    else {
      int at = find_value(in->v, in->u, x);
      memb[i] = (int16_t)(at < 0 ? -1 : label[at]);
    }
  }
  cl[k].count = (uint32_t)(in->nf - in->nz);
  for (int j = 0; j < k; j++) { /* mean difference: the values in order, each against those below it */
    double n = 0, below = 0, sum = 0;
    for (int i = 0; i < in->u; i++)
      if (label[i] == j) {
        sum += in->cnt[i] * (n * in->v[i] - below);
        n += in->cnt[i];
        below += (double)in->cnt[i] * in->v[i];
      }
    cl[j].spread_mean = n > 1 ? sum / (n * (n - 1) / 2) : 0;
  }
  for (int i = 0; i < in->u; i++) /* the returns nearer and farther than each cluster */
    for (int j = 0; j < k; j++) {
      if (in->v[i] < cl[j].lo) cl[j].front += in->cnt[i];
      else if (in->v[i] > cl[j].hi) cl[j].behind += in->cnt[i];
    }
  bool seen_in_win[MAXK + 1] = {false}, open_in_win[MAXK] = {false};
  uint32_t npairs = 0;
  for (int i = 0; i < in->nf; i++) {
    if (i > 0 && in->win[i] != in->win[i - 1]) {
      memset(seen_in_win, 0, sizeof seen_in_win);
      memset(open_in_win, 0, sizeof open_in_win);
    }
    const uint16_t x = in->smp[in->order[i]];
    for (int j = 0; j < k; j++)
      if (!open_in_win[j] && shows(x, cl[j].lo)) {
        open_in_win[j] = true;
        cl[j].open++;
      }
    int m = memb[i];
    if (m >= 0 && !seen_in_win[m]) {
      seen_in_win[m] = true;
      cl[m].windows++;
    }
    for (int j = 0; j < k; j++)
      if (shows(x, cl[j].lo)) {
        cl[j].open_frames++;
        cl[j].open_seen += m == j;
      }
    if (i + 1 < in->nf && in->t[in->order[i + 1]] - in->t[in->order[i]] <= in->pair_gap_s) {
      const uint16_t y = in->smp[in->order[i + 1]];
      npairs++;
      if (memb[i + 1] >= 0) cl[memb[i + 1]].second++;
      if (m >= 0) {
        cl[m].pairs++;
        if (memb[i + 1] == m) {
          cl[m].stay++;
          cl[m].step += abs((int)y - (int)x);
        }
      }
      for (int j = 0; j < k; j++) /* both frames could show it */
        if (shows(x, cl[j].lo) && shows(y, cl[j].lo)) {
          if (m == j) {
            cl[j].open_in++;
            cl[j].open_stay += memb[i + 1] == j;
          } else {
            cl[j].open_out++;
            cl[j].open_back += memb[i + 1] == j;
          }
        }
    }
  }
  return npairs;
}

/* frames in time order */
typedef struct {
  double t;
  int i;
} tidx_t;
static int cmp_tidx(const void *a, const void *b) {
  const tidx_t *x = a, *y = b;
  return (x->t > y->t) - (x->t < y->t) + (x->t == y->t) * ((x->i > y->i) - (x->i < y->i));
}

int rs_bg_min_pts(const rs_bg_params_t *p, int nframes) {
  /* 1 % of the samples, at least the floor; a short capture brings the
   * floor down to a tenth of its frames, never below 2 (below 6 frames, a
   * single return makes a surface: there is nothing else to go by) */
  int floor_ = p->min_pts_floor;
  if (floor_ > nframes / 10) floor_ = nframes / 10;
  if (floor_ < 2) floor_ = nframes < 6 ? 1 : 2;
  return (int)fmax(floor_, ceil(p->min_pts_share * nframes));
}

/* A cell's clusters after the first pass (at most CAND per cell, the
 * farthest ones): range extent (cm), the share of frames in which it is
 * seen, and whether it is background so far. */
#define CAND 12
_Static_assert(CAND <= 16, "the support pass keeps a 16-bit mask per cell");
typedef struct {
  int32_t lo, hi;
  uint16_t seen;    /* share of frames, x 10000 */
  uint8_t bg;       /* 1 background, 0 not (yet) */
  uint8_t farthest; /* the cell's static surface by the first rule */
  uint8_t stays;    /* seen to stay for several frames (enough pairs, no flicker), not hidden by traffic: something standing */
  uint8_t wide;     /* spread too wide for a surface */
} cand_t;

/* support from a neighbour: one of its background clusters, seen in at least
 * half of the frames, holds the middle of [lo, hi] within tol */
static bool supported(const cand_t *c, const uint8_t *nc, size_t cell, int32_t lo, int32_t hi, int32_t tol) {
  const int32_t mid = lo + (hi - lo) / 2;
  for (int k = 0; k < nc[cell]; k++) {
    const cand_t *q = &c[cell * CAND + (size_t)k];
    if (q->bg && q->seen >= 5000 && mid >= q->lo - tol && mid <= q->hi + tol) return true;
  }
  return false;
}

int rs_bg_learn(const rs_bg_learner_t *l, const rs_bg_params_t *p, float rate_hz, rs_bg_model_t *out) {
  int rc = rs_bg_model_alloc(out, l->model, l->rows, l->cols);
  if (rc != RS_OK) return rc;
  out->params = *p;
  out->rate_hz = rate_hz;
  out->frames = (uint32_t)l->nframes;
  out->created = (uint64_t)time(NULL);
  const int nf = l->nframes;
  if (nf < 2) return RS_OK;
  const size_t cells = (size_t)l->rows * (size_t)l->cols;
  tidx_t *ti = malloc(sizeof(tidx_t) * (size_t)nf);
  int *order = malloc(sizeof(int) * (size_t)nf);
  int *win = malloc(sizeof(int) * (size_t)nf);
  int *wn = malloc(sizeof(int) * (size_t)nf);
  int32_t *vals = malloc(sizeof(int32_t) * (size_t)nf), *v = malloc(sizeof(int32_t) * (size_t)nf);
  uint32_t *cnt = malloc(sizeof(uint32_t) * (size_t)nf);
  int16_t *label = malloc(sizeof(int16_t) * (size_t)nf);
  int16_t *memb = malloc(sizeof(int16_t) * (size_t)nf);
  cand_t *cand = p->method == RS_BG_PERCENTILE ? NULL : calloc(cells * CAND, sizeof(cand_t));
  uint8_t *ncand = calloc(cells, 1);
  uint16_t *ilo = malloc(cells * RS_BG_SURFACES * sizeof(uint16_t)), *ihi = malloc(cells * RS_BG_SURFACES * sizeof(uint16_t));
  if (!ti || !order || !win || !wn || !vals || !v || !cnt || !label || !memb || (!cand && p->method != RS_BG_PERCENTILE) ||
      !ncand || !ilo || !ihi) {
    rc = RS_E_OOM;
    goto done;
  }
  for (int i = 0; i < nf; i++) ti[i] = (tidx_t){l->t[i], i};
  qsort(ti, (size_t)nf, sizeof ti[0], cmp_tidx);
  for (int i = 0; i < nf; i++) order[i] = ti[i].i;
  const double t0 = l->t[order[0]];
  for (int i = 0; i < nf; i++) win[i] = (int)floor((l->t[order[i]] - t0) / p->window_s);
  /* the windows that have sampled frames, and how many each (in time order) */
  int nwin = 0;
  for (int i = 0; i < nf; i++) {
    if (i == 0 || win[i] != win[i - 1]) wn[nwin++] = 0;
    wn[nwin - 1]++;
  }
  const uint32_t min_pts = (uint32_t)rs_bg_min_pts(p, nf);

  /* pass 1: every cell's clusters, decided by the cell's own samples */
  for (size_t cell = 0; cell < cells; cell++) {
    const uint16_t *smp = l->samples + cell * (size_t)l->max_frames;
    int nz = 0;
    for (int f = 0; f < nf; f++)
      if (smp[f]) vals[nz++] = smp[f];
    if ((uint32_t)nz < min_pts) continue;
    if (p->method == RS_BG_PERCENTILE) {
      uint16_t *lo = out->lo + cell * RS_BG_SURFACES, *hi = out->hi + cell * RS_BG_SURFACES;
      qsort(vals, (size_t)nz, sizeof vals[0], cmp_i32);
      int idx = (int)floor(p->percentile / 100.0 * (nz - 1));
      int32_t b = vals[idx] - (int32_t)lround(p->percentile_tol * 100);
      lo[0] = (uint16_t)(b < 0 ? 0 : b);
      hi[0] = RS_BG_BEYOND;
      out->n[cell] = 1;
      continue;
    }
    int u = 0;
    int32_t eps = 0;
    int k = cluster_cell(p, vals, nz, min_pts, v, cnt, label, &u, &eps);
    if (k <= 0 || k > MAXK) continue;
    clus_t cl[MAXK + 1]; /* cl[k] = "no return" */
    const cell_in_t in = {v, cnt, u, smp, order, win, nf, nz, l->t, p->pair_gap_s};
    uint32_t npairs = cell_stats(&in, label, k, cl, memb);
    if (p->chain_gap > 0) {
      bool fl[MAXK];
      for (int j = 0; j < k; j++) fl[j] = flickers(&cl[j], npairs, p->flicker_lift);
      int k2 = chain_clusters(v, u, label, (int32_t)lround(p->chain_gap * 100.0), fl);
      if (k2 != k) {
        k = k2;
        npairs = cell_stats(&in, label, k, cl, memb);
      }
    }
    /* "no return" as a persistent state of the cell: sky behind */
    const bool sky = cl[k].count >= min_pts && cl[k].pairs >= 10 && (double)cl[k].stay / cl[k].pairs >= p->persist_max;
    /* decide every cluster, nearest first: the farthest is the static
     * surface (unless sky or void_far); a nearer one is background when it flickers and
     * is present throughout the capture (most windows). Consecutive
     * background clusters close together are one entry (leaves of a canopy
     * come out as many clusters); the farthest CAND entries are kept. */
    cand_t cc[MAXK];
    bool bg[MAXK], fl[MAXK], wide[MAXK], hidden[MAXK];
    /* a cluster spread over more than max(2 m, 15 %) of range in one cell is
     * no surface: a queue creeping through the cell, traffic in front of
     * nothing the sensor can see (a dark road too far to return) */
    for (int j = 0; j < k; j++)
      wide[j] = cl[j].hi - cl[j].lo > (int32_t)lround(fmax(p->wide_min * 100.0, p->wide_share * cl[j].lo));
    for (int j = 0; j < k; j++) fl[j] = flickers(&cl[j], npairs, p->flicker_lift);
    /* a vehicle standing where nothing behind it returns (a queue's last car
     * in front of a road out of reach): the farthest cluster, but the cell
     * returns nothing more often than it, and it stays (a far wall seen
     * between the cars of a queue also returns less often than nothing when
     * its returns drop out, but then at random: back in the next frame only
     * as often as it is detected) */
    const bool void_far = p->void_stay > 0 && k >= 1 && cl[k - 1].pairs >= 10 && !fl[k - 1] &&
                          cl[k].count > cl[k - 1].count && (double)cl[k - 1].stay >= p->void_stay * cl[k - 1].pairs;
    const bool far_surface = !sky && !void_far; /* the farthest cluster is the cell's static surface */
    for (int j = 0; j < k; j++) {
      /* the returns behind it that come from a cluster seen only now and
       * then (back in the next frame less than RS_BG_INTERMITTENT of the
       * time): the far side of an edge, seen when drifting firings miss the
       * near side; not the road a stopped vehicle hid, which returns in long
       * runs once it has left */
      uint32_t behind_edge = 0;
      for (int m = j + 1; m < k; m++)
        if (cl[m].pairs > 0 && cl[m].stay < RS_BG_INTERMITTENT * cl[m].pairs) behind_edge += cl[m].count;
      const double behind = (double)cl[j].behind - behind_edge;
      /* present throughout: in most of the windows it could be seen in (not
       * hidden all along by something standing in front of it), and those at
       * least coverage_open of all */
      const double open = p->coverage_open > 0 ? fmax((double)cl[j].open, p->coverage_open * nwin) : (double)nwin;
      bg[j] = !wide[j] && ((j == k - 1 && far_surface) || (fl[j] && (double)cl[j].windows / open >= p->coverage_min));
      /* a surface whose returns drop out at random (ground far off at a
       * grazing angle, seen in a few % of the frames, the cell returning
       * nothing the rest: sky by the test above) is in fewer windows than
       * coverage_min, but in about as many as random returns at its rate
       * would be; traffic passing now and then comes in bursts */
      if (!bg[j] && !wide[j] && fl[j] && p->sparse_cover > 0 && nf >= RS_BG_JUDGE_FRAMES &&
          cl[j].hi - cl[j].lo <= (int32_t)lround(fmax(p->occluded_spread * 100.0, 0.01 * cl[j].lo)) &&
          cl[j].windows >= p->sparse_cover * random_windows(wn, nwin, (double)cl[j].count / nf) &&
          alone_in_row(l, cell, nf, cl[j].lo, cl[j].hi, p->flicker_lift))
        bg[j] = true;
      /* hidden, not gone: a nearer cluster seen in a good share of the frames,
       * throughout the capture, at one range, and when it is not seen the
       * cell mostly returns something nearer (traffic in front of it; not
       * nothing: a truck against the sky), hardly ever something farther:
       * a surface behind a lane, occluded by queues in runs of frames (so it
       * does not flicker). A vehicle that stops in the cell leaves what it
       * hides (the road behind it) to be seen when it is not there. */
      /* Nothing steady behind it (occluded_clear): beyond it, when it is not
       * seen, only the intermittent far side of an edge (at most
       * RS_BG_CLEAR_BEHIND of the returns in front), and the cell returns
       * nothing less often than it is seen: a post behind queues that stand
       * in front of it for most of the capture, its cluster spread by the
       * mixed returns of its edge. Then a smaller share of the windows and a
       * wider spread do. A vehicle that stops leaves what it hid to be seen;
       * one in front of nothing leaves nothing (void_stay above). */
      const bool clear = p->occluded_clear > 0 && behind <= RS_BG_CLEAR_BEHIND * cl[j].front && cl[k].count <= cl[j].count;
      const double spread_max = fmax(p->occluded_spread * 100.0, 0.01 * cl[j].lo);
      const double windows_min = clear ? fmin(p->occluded_windows, p->occluded_clear) : p->occluded_windows;
      const bool hid = !wide[j] && p->occluded_max > 0 && nf >= RS_BG_JUDGE_FRAMES &&
                       cl[j].count >= p->occluded_seen * nf && (double)cl[j].windows / nwin >= windows_min &&
                       cl[j].front >= 0.5 * (double)(nf - (int)cl[j].count) &&
                       behind <= p->occluded_max * ((double)cl[j].front + behind);
      const double spread_bg = clear ? RS_BG_CLEAR_SPREAD * spread_max : spread_max;
      if (!bg[j] && hid && cl[j].hi - cl[j].lo <= (int32_t)lround(spread_bg)) bg[j] = true;
      /* the same, spread a little more (a slanted post's edge, where the
       * firings fall on either side): not decided here, but no vehicle stood
       * in it (what it hid hardly showed), so the support pass may take it */
      hidden[j] = hid && cl[j].hi - cl[j].lo <= (int32_t)lround(RS_BG_HIDDEN_SUPPORT * spread_max);
      /* leaves of a dense canopy, present throughout as the flicker rule asks
       * (the windows it could be seen in) */
      if (!bg[j] && !wide[j] && (double)cl[j].windows / open >= p->coverage_min &&
          leaves(&cl[j], p->flicker_lift, p->leaves_range))
        bg[j] = true;
      /* under RS_BG_JUDGE_FRAMES frames nothing tells what stays from what
       * flickers: everything seen is the scene */
      if (nf < RS_BG_JUDGE_FRAMES) bg[j] = !wide[j];
    }
    /* a flickering cluster just in front of a background one is the same
     * surface, sampled two ways from turn to turn (a grazing surface whose
     * footprint splits into a near and a far return of about the same
     * strength): background, present in most windows or not (traffic may
     * hide it) */
    /* likewise a cluster just in front of a farthest one that flickers and
     * returns less often: the farther return is the occasional one of the
     * two (a vehicle standing in front of the road leaves the road to return
     * steadily, not at random) */
    for (int j = k - 2; j >= 0; j--) {
      const int32_t gap_max = (int32_t)lround(100.0 * fmax(p->merge_gap_min, p->merge_gap_share * cl[j].lo / 100.0));
      const bool weak_far = j == k - 2 && fl[j + 1] && cl[j + 1].count < cl[j].count;
      if (!bg[j] && !wide[j] && (fl[j] || weak_far) && bg[j + 1] && cl[j + 1].lo - cl[j].hi <= gap_max)
        bg[j] = true;
    }
    int ne = 0;
    for (int j = 0; j < k; j++) {
      cand_t c = {cl[j].lo, cl[j].hi, (uint16_t)lround(10000.0 * cl[j].count / nf), 0, 0, 0, 0};
      c.farthest = j == k - 1 && far_surface && !wide[j];
      c.wide = wide[j];
      c.bg = bg[j];
      c.stays = cl[j].pairs >= 10 && !fl[j] && !hidden[j];
      const int32_t gap_max = (int32_t)lround(100.0 * fmax(p->merge_gap_min, p->merge_gap_share * c.lo / 100.0));
      /* consecutive clusters decided alike and close together: one entry */
      if (ne > 0 && c.bg == cc[ne - 1].bg && !c.farthest && !c.wide && !cc[ne - 1].wide && c.lo - cc[ne - 1].hi <= gap_max) {
        cand_t *e = &cc[ne - 1];
        e->hi = c.hi;
        e->seen = (uint16_t)(e->seen + c.seen > 10000 ? 10000 : e->seen + c.seen);
        e->stays |= c.stays; /* a vehicle that stayed is in it: no support from the cells beside */
        continue;
      }
      cc[ne++] = c;
    }
    const int first = ne > CAND ? ne - CAND : 0;
    memcpy(&cand[cell * CAND], &cc[first], sizeof(cand_t) * (size_t)(ne - first));
    ncand[cell] = (uint8_t)(ne - first);
  }
  if (p->method == RS_BG_PERCENTILE) goto done;

  /* pass 2: a nearer cluster that a cell beside it in the row sees as part
   * of its static scene in most frames is static here too, unless it was
   * seen to stay for several frames (a vehicle): the edge of a pole or a
   * facade, where the firings fall on one side or the other from turn to
   * turn. This needs no long capture (the flicker and presence rules do).
   * Only the row: the rows above and below look at other ranges of the
   * ground, which a passing vehicle matches. Decided from the first pass
   * only, so the order of the cells does not matter. */
  if (p->support) {
    uint16_t *add = calloc(cells, sizeof *add);
    if (add == NULL) {
      rc = RS_E_OOM;
      goto done;
    }
    const int rows = l->rows, cols = l->cols;
    for (size_t cell = 0; cell < cells; cell++) {
      const int r = (int)(cell / (size_t)cols), col = (int)(cell % (size_t)cols);
      const size_t base = cell - (size_t)col;
      const size_t nb[4] = {base + (size_t)(col > 0 ? col - 1 : cols - 1), base + (size_t)(col + 1 < cols ? col + 1 : 0),
                            r > 0 ? cell - (size_t)cols : SIZE_MAX, r + 1 < rows ? cell + (size_t)cols : SIZE_MAX};
      for (int k = 0; k < ncand[cell]; k++) {
        cand_t *c = &cand[cell * CAND + (size_t)k];
        if (c->bg || c->stays || c->wide) continue;
        int32_t tol = (int32_t)lround(fmax(p->support_tol_min * 100.0, p->support_tol_share * c->lo));
        int32_t tol_v = (int32_t)lround(fmax(10.0, 0.005 * c->lo));
        for (int q = 0; q < 4 && !(add[cell] & (1u << k)); q++)
          if (nb[q] != SIZE_MAX && supported(cand, ncand, nb[q], c->lo, c->hi, q < 2 ? tol : tol_v))
            add[cell] |= (uint16_t)(1u << k);
      }
    }
    for (size_t cell = 0; cell < cells; cell++)
      for (int k = 0; k < ncand[cell]; k++)
        if (add[cell] & (1u << k)) cand[cell * CAND + (size_t)k].bg = 1;
    free(add);
  }

  /* pass 3: background intervals with margins; a surface seen at a grazing
   * angle spreads over a metre or more inside one cell and comes out as
   * several clusters: neighbours with a small gap and no foreground cluster
   * between them are one surface */
  for (size_t cell = 0; cell < cells; cell++) {
    int32_t jlo[CAND], jhi[CAND];
    int ni = 0;
    bool fg_since = false;
    for (int j = 0; j < ncand[cell]; j++) {
      const cand_t *c = &cand[cell * CAND + (size_t)j];
      if (!c->bg) {
        fg_since = true;
        continue;
      }
      /* the margin: the noise floor, plus what a few samples of a spread
       * surface do not show (n samples leave about spread / n uncovered on
       * either side, 1/(n+1) of the draws each) */
      const double spread_cm = (double)(c->hi - c->lo), ns = fmax(1.0, c->seen * nf / 10000.0);
      int32_t mg = (int32_t)lround(100.0 * fmax(p->margin_min, p->margin_share * c->lo / 100.0) +
                                   spread_cm * fmin(1.0, p->margin_samples / ns));
      int32_t a = c->lo - mg, b = c->hi + mg;
      int32_t gap_max = (int32_t)lround(100.0 * fmax(p->merge_gap_min, p->merge_gap_share * c->lo / 100.0));
      if (ni > 0 && !fg_since && a - jhi[ni - 1] <= gap_max) {
        jhi[ni - 1] = b;
      } else {
        jlo[ni] = a;
        jhi[ni] = b;
        ni++;
      }
      fg_since = false;
    }
    /* keep the farthest RS_BG_SURFACES, nearest first */
    uint16_t *lo = out->lo + cell * RS_BG_SURFACES, *hi = out->hi + cell * RS_BG_SURFACES;
    int first = ni > RS_BG_SURFACES ? ni - RS_BG_SURFACES : 0, m = 0;
    for (int i = first; i < ni; i++) {
      int32_t a = jlo[i] < 0 ? 0 : jlo[i], b = jhi[i] > 65534 ? 65534 : jhi[i];
      if (m > 0 && a <= hi[m - 1]) {
        if (b > hi[m - 1]) hi[m - 1] = (uint16_t)b;
        continue;
      }
      lo[m] = (uint16_t)a;
      hi[m] = (uint16_t)b;
      m++;
    }
    out->n[cell] = (uint8_t)m;
    /* how often the farthest surface is seen: solid (a wall, the road) or seen through */
    if (m > 0 && ncand[cell] > 0) {
      const cand_t *far = &cand[cell * CAND + (size_t)(ncand[cell] - 1)];
      out->far_seen[cell] = far->bg ? (uint8_t)lround(far->seen / 100.0) : 0;
    }
  }

  /* pass 4: a surface continues into the cells beside it in the row: the
   * firings of a turn fall anywhere across a column, so a return may come
   * from anywhere between the ranges the neighbours see. An interval reaches
   * half-way to the nearest interval of the cell on either side when the two
   * are close (a connected surface, not an edge). From the pass-3 intervals,
   * so the order of the cells does not matter. */
  if (p->connect_min > 0) {
    memcpy(ilo, out->lo, cells * RS_BG_SURFACES * sizeof(uint16_t));
    memcpy(ihi, out->hi, cells * RS_BG_SURFACES * sizeof(uint16_t));
    const int cols = l->cols;
    for (size_t cell = 0; cell < cells; cell++) {
      const int col = (int)(cell % (size_t)cols);
      const size_t base = cell - (size_t)col;
      const size_t side[2] = {base + (size_t)(col > 0 ? col - 1 : cols - 1), base + (size_t)(col + 1 < cols ? col + 1 : 0)};
      for (int k = 0; k < out->n[cell]; k++) {
        const size_t i = cell * RS_BG_SURFACES + (size_t)k;
        int32_t a = ilo[i], b = ihi[i];
        const int32_t reach = (int32_t)lround(fmax(p->connect_min * 100.0, p->connect_share * a));
        for (int q = 0; q < 2; q++)
          for (int j = 0; j < out->n[side[q]]; j++) {
            const size_t o = side[q] * RS_BG_SURFACES + (size_t)j;
            if (ilo[o] > ihi[i] && ilo[o] - ihi[i] <= reach) b = (int32_t)fmax(b, (ihi[i] + ilo[o]) / 2);
            if (ihi[o] < ilo[i] && ilo[i] - ihi[o] <= reach) a = (int32_t)fmin(a, (ihi[o] + ilo[i]) / 2);
          }
        /* never into the next interval of the same cell */
        if (k > 0 && a <= out->hi[i - 1]) a = out->hi[i - 1] + 1;
        if (k + 1 < out->n[cell] && b >= ilo[i + 1]) b = ilo[i + 1] - 1;
        out->lo[i] = (uint16_t)a;
        out->hi[i] = (uint16_t)b;
      }
    }
  }
done:
  free(ti);
  free(order);
  free(win);
  free(wn);
  free(vals);
  free(v);
  free(cnt);
  free(label);
  free(memb);
  free(cand);
  free(ncand);
  free(ilo);
  free(ihi);
  return rc;
}

/* ---- the model file ---- */

static uint32_t crc32_update(uint32_t crc, const uint8_t *p, size_t n) {
  crc = ~crc;
  for (size_t i = 0; i < n; i++) {
    crc ^= p[i];
    for (int k = 0; k < 8; k++) crc = (crc >> 1) ^ (0xEDB88320u & (0u - (crc & 1u)));
  }
  return ~crc;
}

#define HDR_SIZE 116

static void put16(uint8_t *p, uint32_t v) {
  p[0] = (uint8_t)v;
  p[1] = (uint8_t)(v >> 8);
}
static void put32(uint8_t *p, uint32_t v) {
  for (int i = 0; i < 4; i++) p[i] = (uint8_t)(v >> (8 * i));
}
static void put64(uint8_t *p, uint64_t v) {
  for (int i = 0; i < 8; i++) p[i] = (uint8_t)(v >> (8 * i));
}
static uint32_t get16(const uint8_t *p) { return (uint32_t)p[0] | ((uint32_t)p[1] << 8); }
static uint32_t get32(const uint8_t *p) {
  return (uint32_t)p[0] | ((uint32_t)p[1] << 8) | ((uint32_t)p[2] << 16) | ((uint32_t)p[3] << 24);
}
static uint64_t get64(const uint8_t *p) { return (uint64_t)get32(p) | ((uint64_t)get32(p + 4) << 32); }
static void putf(uint8_t *p, double v) { put32(p, (uint32_t)(int32_t)lround(v * 1000.0)); }
static double getf(const uint8_t *p) { return (double)(int32_t)get32(p) / 1000.0; }

/* header (little-endian): magic[8] version u32 header_size u32 sensor u32 rows u32 cols u32
 * rate_mhz u32 method u32 frames u32 created u64 min_pts_floor u32 then milli-units of
 * min_pts_share eps_min eps_max eps_step persist_max coverage_min window_s pair_gap_s
 * percentile percentile_tol (i32 each), surfaces per cell u32, margin_min margin_share
 * merge_gap_min merge_gap_share flicker_lift (milli-units); then per cell a byte: the number of surfaces n (bits 0-6) and
 * the percentage of frames in which its farthest surface is seen (u8), then
 * lo/hi u16 pairs [cells][RS_BG_SURFACES]; then CRC-32 of everything before it. */
int rs_bg_save(const rs_bg_model_t *m, const char *path, char *err, size_t n) {
  const size_t cells = (size_t)m->rows * m->cols;
  const size_t size = HDR_SIZE + 2 * cells + cells * RS_BG_SURFACES * 4 + 4;
  uint8_t *b = calloc(size, 1);
  if (b == NULL) {
    snprintf(err, n, "%s: out of memory", path);
    return RS_E_OOM;
  }
  memcpy(b, RS_BG_MAGIC, 8);
  put32(b + 8, RS_BG_VERSION);
  put32(b + 12, HDR_SIZE);
  put32(b + 16, (uint32_t)m->model);
  put32(b + 20, m->rows);
  put32(b + 24, m->cols);
  put32(b + 28, (uint32_t)lround(m->rate_hz * 1000.0));
  put32(b + 32, (uint32_t)m->params.method);
  put32(b + 36, m->frames);
  put64(b + 40, m->created);
  put32(b + 48, (uint32_t)m->params.min_pts_floor);
  const double f[10] = {m->params.min_pts_share, m->params.eps_min, m->params.eps_max, m->params.eps_step,
                        m->params.persist_max, m->params.coverage_min, m->params.window_s, m->params.pair_gap_s,
                        m->params.percentile, m->params.percentile_tol};
  for (int i = 0; i < 10; i++) putf(b + 52 + 4 * i, f[i]);
  put32(b + 92, RS_BG_SURFACES);
  const double g[4] = {m->params.margin_min, m->params.margin_share, m->params.merge_gap_min, m->params.merge_gap_share};
  for (int i = 0; i < 4; i++) putf(b + 96 + 4 * i, g[i]);
  putf(b + 112, m->params.flicker_lift);
  for (size_t c = 0; c < cells; c++) {
    b[HDR_SIZE + 2 * c] = m->n[c];
    b[HDR_SIZE + 2 * c + 1] = m->far_seen[c];
  }
  uint8_t *s = b + HDR_SIZE + 2 * cells;
  for (size_t i = 0; i < cells * RS_BG_SURFACES; i++) {
    put16(s + 4 * i, m->lo[i]);
    put16(s + 4 * i + 2, m->hi[i]);
  }
  put32(b + size - 4, crc32_update(0, b, size - 4));
  /* atomically: a temporary file beside it, flushed to the disk, then renamed
   * over the path; a crash or a full disk leaves the old model (or none),
   * never half a model */
  char tmp[4096];
  if ((size_t)snprintf(tmp, sizeof tmp, "%s.tmp-%ld", path, (long)getpid()) >= sizeof tmp) {
    free(b);
    snprintf(err, n, "%s: path too long", path);
    return RS_E_INVAL;
  }
  FILE *fp = fopen(tmp, "wb");
  int rc = RS_OK;
  const char *why = NULL;
  if (fp == NULL) why = strerror(errno);
  else if (fwrite(b, 1, size, fp) != size || fflush(fp) != 0) why = strerror(errno ? errno : EIO);
  else if (fsync(fileno(fp)) != 0) why = strerror(errno);
  if (fp && fclose(fp) != 0 && why == NULL) why = strerror(errno);
  if (why == NULL && rename(tmp, path) != 0) why = strerror(errno);
  if (why) {
    snprintf(err, n, "%s: cannot write the model: %s", path, why);
    if (fp) remove(tmp);
    rc = RS_E_IO;
  }
  free(b);
  return rc;
}

int rs_bg_load(rs_bg_model_t *m, const char *path, char *err, size_t n) {
  memset(m, 0, sizeof *m);
  FILE *fp = fopen(path, "rb");
  if (fp == NULL) {
    snprintf(err, n, "%s: cannot open the background model", path);
    return RS_E_NOENT;
  }
  fseek(fp, 0, SEEK_END);
  long size = ftell(fp);
  fseek(fp, 0, SEEK_SET);
  if (size < HDR_SIZE + 4 || size > 256L * 1024 * 1024) {
    fclose(fp);
    snprintf(err, n, "%s: not a background model (%ld bytes)", path, size);
    return RS_E_FORMAT;
  }
  uint8_t *b = malloc((size_t)size);
  if (b == NULL) {
    fclose(fp);
    snprintf(err, n, "%s: out of memory for %ld bytes", path, size);
    return RS_E_OOM;
  }
  if (fread(b, 1, (size_t)size, fp) != (size_t)size) {
    fclose(fp);
    free(b);
    snprintf(err, n, "%s: cannot read", path);
    return RS_E_IO;
  }
  fclose(fp);
  int rc = RS_E_FORMAT;
  if (memcmp(b, RS_BG_MAGIC, 6) != 0) {
    snprintf(err, n, "%s: not a roadscan background model (bad magic)", path);
    goto out;
  }
  if (memcmp(b, RS_BG_MAGIC, 8) != 0 || get32(b + 8) != RS_BG_VERSION) {
    snprintf(err, n, "%s: model format version %u, this program reads version %d: relearn the model", path,
             get32(b + 8), RS_BG_VERSION);
    goto out;
  }
  uint32_t rows = get32(b + 20), cols = get32(b + 24), model = get32(b + 16), k = get32(b + 92);
  if (get32(b + 12) != HDR_SIZE || k != RS_BG_SURFACES || rows < 1 || rows > RS_MAX_ROWS || cols < RS_MIN_COLS ||
      cols > RS_MAX_COLS || model == RS_MODEL_UNKNOWN || model >= RS_MODEL_COUNT) {
    snprintf(err, n, "%s: corrupt header (sensor %u, %u x %u cells)", path, model, rows, cols);
    goto out;
  }
  if (rows != rs_model_info((rs_model_t)model)->lasers) {
    snprintf(err, n, "%s: corrupt header: %u rows, a %s has %u lasers", path, rows, rs_model_name((rs_model_t)model),
             rs_model_info((rs_model_t)model)->lasers);
    goto out;
  }
  size_t cells = (size_t)rows * cols, want = HDR_SIZE + 2 * cells + cells * RS_BG_SURFACES * 4 + 4;
  if ((size_t)size != want) {
    snprintf(err, n, "%s: truncated or padded: %ld bytes, a %u x %u model has %zu", path, size, rows, cols, want);
    goto out;
  }
  if (crc32_update(0, b, want - 4) != get32(b + want - 4)) {
    snprintf(err, n, "%s: checksum mismatch: the file is corrupted", path);
    goto out;
  }
  if (rs_bg_model_alloc(m, (rs_model_t)model, (int)rows, (int)cols) != RS_OK) {
    snprintf(err, n, "%s: out of memory", path);
    rc = RS_E_OOM;
    goto out;
  }
  m->rate_hz = (float)get32(b + 28) / 1000.0f;
  m->params.method = (rs_bg_method_t)get32(b + 32);
  m->frames = get32(b + 36);
  m->created = get64(b + 40);
  m->params.min_pts_floor = (int)get32(b + 48);
  double *f[10] = {&m->params.min_pts_share, &m->params.eps_min, &m->params.eps_max, &m->params.eps_step,
                   &m->params.persist_max, &m->params.coverage_min, &m->params.window_s, &m->params.pair_gap_s,
                   &m->params.percentile, &m->params.percentile_tol};
  for (int i = 0; i < 10; i++) *f[i] = getf(b + 52 + 4 * i);
  double *g[4] = {&m->params.margin_min, &m->params.margin_share, &m->params.merge_gap_min, &m->params.merge_gap_share};
  for (int i = 0; i < 4; i++) *g[i] = getf(b + 96 + 4 * i);
  m->params.flicker_lift = getf(b + 112);
  for (size_t c = 0; c < cells; c++) {
    m->n[c] = b[HDR_SIZE + 2 * c];
    m->far_seen[c] = b[HDR_SIZE + 2 * c + 1];
  }
  const uint8_t *s = b + HDR_SIZE + 2 * cells;
  for (size_t i = 0; i < cells * RS_BG_SURFACES; i++) {
    m->lo[i] = (uint16_t)get16(s + 4 * i);
    m->hi[i] = (uint16_t)get16(s + 4 * i + 2);
  }
  for (size_t c = 0; c < cells; c++) {
    if (m->n[c] > RS_BG_SURFACES) {
      snprintf(err, n, "%s: cell %zu has %u surfaces (at most %d)", path, c, m->n[c], RS_BG_SURFACES);
      rs_bg_model_free(m);
      goto out;
    }
    for (int j = 0; j < m->n[c]; j++) {
      size_t i = c * RS_BG_SURFACES + (size_t)j;
      if (m->lo[i] > m->hi[i] || (j > 0 && m->lo[i] <= m->hi[i - 1])) {
        snprintf(err, n, "%s: cell %zu: surfaces not ordered", path, c);
        rs_bg_model_free(m);
        goto out;
      }
    }
  }
  rc = RS_OK;
out:
  free(b);
  return rc;
}

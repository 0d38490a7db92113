/* eval.c - point-label metrics (tools only). */
#include "roadscan/offline/eval.h"

#include "roadscan/util/assign.h"
#include "roadscan/util/error.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

const double rs_eval_band_edges[RS_EVAL_BANDS + 1] = {0, 20, 50, 100, 200};

#define PAIR_CAP (1u << 20)

bool rs_eval_within(uint32_t frames, double period, double limit) {
  return (double)frames * period <= limit * (1.0 + RS_EVAL_RATE_TOL);
}

int rs_eval_init(rs_eval_t *e) {
  memset(e, 0, sizeof *e);
  e->cap = PAIR_CAP;
  e->pairs = calloc(e->cap, sizeof *e->pairs);
  e->used = calloc(e->cap, sizeof *e->used);
  if (e->pairs == NULL || e->used == NULL) {
    rs_eval_deinit(e);
    return RS_E_OOM;
  }
  return RS_OK;
}

void rs_eval_deinit(rs_eval_t *e) {
  free(e->pairs);
  free(e->used);
  e->pairs = NULL;
  e->used = NULL;
}

static uint32_t hash64(uint64_t k) {
  k ^= k >> 33;
  k *= 0xff51afd7ed558ccdull;
  k ^= k >> 33;
  return (uint32_t)k;
}

/* counts one (truth, pred) co-occurrence; pred 0 marks a truth size entry,
 * truth 0 a pred size entry */
static void count(rs_eval_t *e, uint32_t truth, uint32_t pred) {
  uint64_t key = ((uint64_t)truth << 32) | pred;
  uint32_t mask = e->cap - 1, i = hash64(key) & mask;
  for (uint32_t probe = 0; probe < e->cap; probe++, i = (i + 1) & mask) {
    if (e->pairs[i].key == key) {
      e->pairs[i].count++;
      return;
    }
    if (e->pairs[i].key == 0) {
      if (e->nused >= e->cap / 2) {
        e->overflow = true;
        return;
      }
      e->pairs[i].key = key;
      e->pairs[i].count = 1;
      e->used[e->nused++] = i;
      return;
    }
  }
}

static uint32_t lookup(const rs_eval_t *e, uint32_t truth, uint32_t pred) {
  uint64_t key = ((uint64_t)truth << 32) | pred;
  uint32_t mask = e->cap - 1, i = hash64(key) & mask;
  for (uint32_t probe = 0; probe < e->cap; probe++, i = (i + 1) & mask) {
    if (e->pairs[i].key == key) return e->pairs[i].count;
    if (e->pairs[i].key == 0) return 0;
  }
  return 0;
}

void rs_eval_point(rs_eval_t *e, uint32_t truth, uint32_t pred, float range, bool counted) {
  if (!counted) return;
  rs_eval_result_t *r = &e->r;
  const bool tt = truth >= 3, pt = pred >= 3;
  r->points++;
  if (tt && pt) r->t_tp++;
  else if (pt) r->t_fp++;
  else if (tt) r->t_fn++;
  const bool tn = truth == 1 || truth == 2, pn = pred == 1 || pred == 2;
  if (tn && pn) r->n_tp++;
  else if (pn) r->n_fp++;
  else if (tn) r->n_fn++;
  if (truth == 1) {
    r->static_true++;
    r->static_kept += pred == 1;
  } else if (truth == 2) {
    r->foliage_true++;
    r->foliage_background += pred == 1;
  } else if (tt) {
    r->target_true++;
    r->target_kept += pred != 1;
    int b = 0;
    while (b < RS_EVAL_BANDS - 1 && range >= rs_eval_band_edges[b + 1]) b++;
    r->band_true[b]++;
    r->band_hit[b] += pt;
  }
  if (tt) count(e, truth, 0);
  if (pt) count(e, 0, pred);
  if (tt && pt) count(e, truth, pred);
}

static int cmp_u64(const void *a, const void *b) {
  uint64_t x = *(const uint64_t *)a, y = *(const uint64_t *)b;
  return (x > y) - (x < y);
}

static void mot_frame(rs_eval_t *e, struct rs_mot *m);

void rs_eval_end_frame(rs_eval_t *e, bool counted) {
  if (counted && e->mot) mot_frame(e, e->mot);
  e->frame_no++;
  if (counted) {
    e->r.frames++;
    /* every true instance of at least 10 points: matched when a predicted
     * cluster overlaps it with IoU > 0.5 */
    for (uint32_t u = 0; u < e->nused; u++) {
      const rs_eval_pair_t *p = &e->pairs[e->used[u]];
      uint32_t t = (uint32_t)(p->key >> 32), pr = (uint32_t)p->key;
      if (t == 0 || pr != 0 || p->count < RS_EVAL_MIN_INSTANCE) continue;
      e->r.instances++;
      bool matched = false;
      uint32_t best = 0; /* the instance's returns in its largest piece */
      for (uint32_t v = 0; v < e->nused && !matched; v++) {
        const rs_eval_pair_t *q = &e->pairs[e->used[v]];
        if ((uint32_t)(q->key >> 32) != t || (uint32_t)q->key == 0) continue;
        uint32_t inter = q->count, psize = lookup(e, 0, (uint32_t)q->key);
        if (inter > best) best = inter;
        matched = (double)inter / (double)(p->count + psize - inter) > 0.5;
      }
      if (matched) e->r.matched++;
      else if (best == 0) e->r.missed++;
      else if (2 * (uint64_t)best > p->count) e->r.merged++;
      else e->r.split++;
    }
  }
  for (uint32_t u = 0; u < e->nused; u++) e->pairs[e->used[u]].key = 0;
  e->nused = 0;
}

double rs_eval_ratio(uint64_t num, uint64_t den) { return den ? (double)num / (double)den : NAN; }

static void pct(FILE *out, double v) {
  if (isnan(v)) fprintf(out, "    n/a");
  else fprintf(out, "%6.2f%%", v * 100.0);
}

void rs_eval_print(const rs_eval_result_t *r, FILE *out) {
  fprintf(out, "frames evaluated: %llu (frame 0 skipped), returns: %llu\n", (unsigned long long)r->frames,
          (unsigned long long)r->points);
  fprintf(out, "class        precision  recall     IoU\n");
  fprintf(out, "target      ");
  pct(out, rs_eval_ratio(r->t_tp, r->t_tp + r->t_fp));
  fprintf(out, "   ");
  pct(out, rs_eval_ratio(r->t_tp, r->t_tp + r->t_fn));
  fprintf(out, " ");
  pct(out, rs_eval_ratio(r->t_tp, r->t_tp + r->t_fp + r->t_fn));
  fprintf(out, "\nnon-target  ");
  pct(out, rs_eval_ratio(r->n_tp, r->n_tp + r->n_fp));
  fprintf(out, "   ");
  pct(out, rs_eval_ratio(r->n_tp, r->n_tp + r->n_fn));
  fprintf(out, " ");
  pct(out, rs_eval_ratio(r->n_tp, r->n_tp + r->n_fp + r->n_fn));
  fprintf(out, "\nmatched instances (IoU > 0.5, >= %d points): %llu / %llu (", RS_EVAL_MIN_INSTANCE,
          (unsigned long long)r->matched, (unsigned long long)r->instances);
  pct(out, rs_eval_ratio(r->matched, r->instances));
  fprintf(out, "); not matched: merged %llu, split %llu, missed %llu", (unsigned long long)r->merged,
          (unsigned long long)r->split, (unsigned long long)r->missed);
  fprintf(out, "\nbackground: static returns labelled background ");
  pct(out, rs_eval_ratio(r->static_kept, r->static_true));
  fprintf(out, ", target returns kept (not background) ");
  pct(out, rs_eval_ratio(r->target_kept, r->target_true));
  fprintf(out, ", foliage/noise labelled background ");
  pct(out, rs_eval_ratio(r->foliage_background, r->foliage_true));
  fprintf(out, "\ntarget recall by range:");
  for (int b = 0; b < RS_EVAL_BANDS; b++) {
    fprintf(out, "  %g-%g m ", rs_eval_band_edges[b], rs_eval_band_edges[b + 1]);
    pct(out, rs_eval_ratio(r->band_hit[b], r->band_true[b]));
    fprintf(out, " (%llu)", (unsigned long long)r->band_true[b]);
  }
  fprintf(out, "\n");
}

/* a ratio: null when undefined (NaN), else the number */
static json_t *jnum(double v) { return isnan(v) || isinf(v) ? json_null() : json_real(v); }

static void dump(json_t *j, FILE *out) {
  char *t = j ? json_dumps(j, RS_EVAL_JSON_FLAGS) : NULL;
  if (t) fprintf(out, "%s\n", t);
  free(t);
  json_decref(j);
}

json_t *rs_eval_json(const rs_eval_result_t *r) {
  json_t *bands = json_object();
  for (int b = 0; b < RS_EVAL_BANDS; b++) {
    char k[32];
    snprintf(k, sizeof k, "%g-%g", rs_eval_band_edges[b], rs_eval_band_edges[b + 1]);
    json_object_set_new(bands, k, jnum(rs_eval_ratio(r->band_hit[b], r->band_true[b])));
  }
  return json_pack(
      "{s:I, s:I, s:{s:o, s:o, s:o, s:I, s:I, s:I}, s:{s:o, s:o, s:o}, s:I, s:I, s:I, s:I, s:I, s:{s:o, s:o, s:o}, "
      "s:o}",
      "frames", (json_int_t)r->frames, "points", (json_int_t)r->points, "target", "precision",
      jnum(rs_eval_ratio(r->t_tp, r->t_tp + r->t_fp)), "recall", jnum(rs_eval_ratio(r->t_tp, r->t_tp + r->t_fn)), "iou",
      jnum(rs_eval_ratio(r->t_tp, r->t_tp + r->t_fp + r->t_fn)), "tp", (json_int_t)r->t_tp, "fp", (json_int_t)r->t_fp,
      "fn", (json_int_t)r->t_fn, "non_target", "precision", jnum(rs_eval_ratio(r->n_tp, r->n_tp + r->n_fp)), "recall",
      jnum(rs_eval_ratio(r->n_tp, r->n_tp + r->n_fn)), "iou", jnum(rs_eval_ratio(r->n_tp, r->n_tp + r->n_fp + r->n_fn)),
      "matched", (json_int_t)r->matched, "instances", (json_int_t)r->instances, "merged", (json_int_t)r->merged,
      "split", (json_int_t)r->split, "missed", (json_int_t)r->missed, "background", "static_kept",
      jnum(rs_eval_ratio(r->static_kept, r->static_true)), "targets_kept",
      jnum(rs_eval_ratio(r->target_kept, r->target_true)), "foliage_background",
      jnum(rs_eval_ratio(r->foliage_background, r->foliage_true)), "recall_by_range", bands);
}

void rs_eval_print_json(const rs_eval_result_t *r, FILE *out) { dump(rs_eval_json(r), out); }

/* ---- tracking metrics ---------------------------------------------------- */

typedef struct { /* growable open-addressing map: key (never UINT64_MAX) -> index */
  uint64_t *keys;
  uint32_t *vals;
  uint32_t cap, n;
} map_t;

static bool map_grow(map_t *m) {
  uint32_t nc = m->cap ? m->cap * 2 : 1024;
  uint64_t *k = malloc(sizeof *k * nc);
  uint32_t *v = malloc(sizeof *v * nc);
  if (!k || !v) {
    free(k);
    free(v);
    return false;
  }
  memset(k, 0xff, sizeof *k * nc);
  for (uint32_t i = 0; i < m->cap; i++) {
    if (m->keys[i] == UINT64_MAX) continue;
    uint32_t j = hash64(m->keys[i]) & (nc - 1);
    while (k[j] != UINT64_MAX) j = (j + 1) & (nc - 1);
    k[j] = m->keys[i];
    v[j] = m->vals[i];
  }
  free(m->keys);
  free(m->vals);
  m->keys = k;
  m->vals = v;
  m->cap = nc;
  return true;
}

/* the index of key, inserting next_val when absent (*fresh set); UINT32_MAX when out of memory */
static uint32_t map_get(map_t *m, uint64_t key, uint32_t next_val, bool *fresh) {
  if ((m->n + 1) * 2 > m->cap && !map_grow(m)) return UINT32_MAX;
  uint32_t j = hash64(key) & (m->cap - 1);
  while (m->keys[j] != UINT64_MAX) {
    if (m->keys[j] == key) {
      *fresh = false;
      return m->vals[j];
    }
    j = (j + 1) & (m->cap - 1);
  }
  m->keys[j] = key;
  m->vals[j] = next_val;
  m->n++;
  *fresh = true;
  return next_val;
}

typedef struct {
  uint32_t frames, matched, last_h; /* last_h: index + 1 of the track it was last matched to */
  bool pending;                     /* matched before, missed since */
} mot_gt_t;

typedef struct {
  uint32_t g, h, n;
} mot_co_t;

struct rs_mot {
  FILE *dump;
  rs_mot_instance_fn on_instance;
  void *user;
  rs_mot_result_t r;
  map_t gmap, hmap, cmap;
  mot_gt_t *gt;
  uint32_t ngt, gcap;
  uint32_t nh;
  mot_co_t *co;
  uint32_t nco, cocap;
  bool oom;
};

rs_mot_t *rs_mot_new(FILE *dump) {
  rs_mot_t *m = calloc(1, sizeof *m);
  if (m) m->dump = dump;
  if (m && dump) fprintf(dump, "frame,truth,pred,iou\n");
  return m;
}

void rs_mot_free(rs_mot_t *m) {
  if (!m) return;
  free(m->gmap.keys);
  free(m->gmap.vals);
  free(m->hmap.keys);
  free(m->hmap.vals);
  free(m->cmap.keys);
  free(m->cmap.vals);
  free(m->gt);
  free(m->co);
  free(m);
}

void rs_eval_track(rs_eval_t *e, rs_mot_t *m) { e->mot = m; }

void rs_mot_on_instance(rs_mot_t *m, rs_mot_instance_fn fn, void *user) {
  m->on_instance = fn;
  m->user = user;
}

static uint32_t gt_index(rs_mot_t *m, uint32_t id) {
  bool fresh;
  uint32_t i = map_get(&m->gmap, id, m->ngt, &fresh);
  if (i == UINT32_MAX) return i;
  if (fresh) {
    if (m->ngt == m->gcap) {
      uint32_t nc = m->gcap ? 2 * m->gcap : 1024;
      mot_gt_t *ng = realloc(m->gt, sizeof *ng * nc);
      if (!ng) return UINT32_MAX;
      m->gt = ng;
      m->gcap = nc;
    }
    memset(&m->gt[m->ngt], 0, sizeof m->gt[0]);
    m->ngt++;
  }
  return i;
}

static uint32_t hyp_index(rs_mot_t *m, uint32_t id) {
  bool fresh;
  uint32_t i = map_get(&m->hmap, id, m->nh, &fresh);
  if (i != UINT32_MAX && fresh) m->nh++;
  return i;
}

static void co_add(rs_mot_t *m, uint32_t g, uint32_t h) {
  bool fresh;
  uint32_t i = map_get(&m->cmap, (uint64_t)g << 32 | h, m->nco, &fresh);
  if (i == UINT32_MAX) {
    m->oom = true;
    return;
  }
  if (fresh) {
    if (m->nco == m->cocap) {
      uint32_t nc = m->cocap ? 2 * m->cocap : 1024;
      mot_co_t *n = realloc(m->co, sizeof *n * nc);
      if (!n) {
        m->oom = true;
        return;
      }
      m->co = n;
      m->cocap = nc;
    }
    m->co[m->nco++] = (mot_co_t){g, h, 0};
  }
  m->co[i].n++;
}

/* one frame of the eval: its instances and overlaps are in e->pairs */
static void mot_frame(rs_eval_t *e, rs_mot_t *m) {
  m->r.frames++;
  const uint64_t fno = e->frame_no;
  /* true instances, their matches */
  for (uint32_t u = 0; u < e->nused; u++) {
    const rs_eval_pair_t *p = &e->pairs[e->used[u]];
    const uint32_t t = (uint32_t)(p->key >> 32), pr = (uint32_t)p->key;
    if (t == 0 || pr != 0 || p->count < RS_EVAL_MIN_INSTANCE) continue;
    const uint32_t g = gt_index(m, t);
    if (g == UINT32_MAX) {
      m->oom = true;
      return;
    }
    m->r.gt++;
    m->gt[g].frames++;
    if (m->dump) fprintf(m->dump, "%llu,%u,0,0\n", (unsigned long long)fno, t);
    uint32_t match = 0;
    double miou = 0;
    for (uint32_t v = 0; v < e->nused; v++) {
      const rs_eval_pair_t *q = &e->pairs[e->used[v]];
      if ((uint32_t)(q->key >> 32) != t || (uint32_t)q->key == 0) continue;
      const uint32_t inter = q->count, psize = lookup(e, 0, (uint32_t)q->key);
      const double iou = (double)inter / (double)(p->count + psize - inter);
      if (m->dump) fprintf(m->dump, "%llu,%u,%u,%.6f\n", (unsigned long long)fno, t, (uint32_t)q->key, iou);
      if (iou > 0.5) {
        match = (uint32_t)q->key;
        miou = iou;
      }
    }
    mot_gt_t *G = &m->gt[g];
    if (m->on_instance) m->on_instance(m->user, fno, t, match);
    if (!match) {
      m->r.misses++;
      if (G->matched) G->pending = true;
      continue;
    }
    const uint32_t h = hyp_index(m, match);
    if (h == UINT32_MAX) {
      m->oom = true;
      return;
    }
    m->r.matches++;
    m->r.iou_sum += miou;
    if (G->last_h && G->last_h != h + 1) m->r.switches++;
    if (G->pending) m->r.fragmentations++;
    G->pending = false;
    G->last_h = h + 1;
    G->matched++;
    co_add(m, g, h);
  }
  /* predicted instances: >= 10 returns, or matched */
  for (uint32_t u = 0; u < e->nused; u++) {
    const rs_eval_pair_t *p = &e->pairs[e->used[u]];
    const uint32_t t = (uint32_t)(p->key >> 32), pr = (uint32_t)p->key;
    if (t != 0 || pr == 0) continue;
    bool matched = false, on_instance = false;
    uint32_t on_objects = 0; /* its returns of road users (true ids 3+), instances or not */
    for (uint32_t v = 0; v < e->nused && !matched; v++) {
      const rs_eval_pair_t *q = &e->pairs[e->used[v]];
      const uint32_t qt = (uint32_t)(q->key >> 32);
      if ((uint32_t)q->key != pr || qt == 0) continue;
      if (qt >= 3) on_objects += q->count;
      const uint32_t tsize = lookup(e, qt, 0);
      if (tsize < RS_EVAL_MIN_INSTANCE) continue;
      on_instance |= qt >= 3;
      matched = (double)q->count / (double)(tsize + p->count - q->count) > 0.5;
    }
    if (!matched && p->count < RS_EVAL_MIN_INSTANCE) continue;
    m->r.hyp++;
    if (!matched) {
      m->r.false_pos++;
      if (on_instance) m->r.fp_instance++;
      else if (2 * (uint64_t)on_objects > p->count) m->r.fp_small++;
      else m->r.fp_scene++;
    }
    if (hyp_index(m, pr) == UINT32_MAX) m->oom = true;
    if (m->dump) fprintf(m->dump, "%llu,0,%u,0\n", (unsigned long long)fno, pr);
  }
}

static uint32_t uf_find(uint32_t *c, uint32_t i) {
  while (c[i] != i) {
    c[i] = c[c[i]];
    i = c[i];
  }
  return i;
}

/* IDTP: the best one-to-one pairing of true objects and tracks, per connected group */
static int idtp(rs_mot_t *m, uint64_t *out) {
  const uint32_t N = m->ngt + m->nh;
  *out = 0;
  if (m->nco == 0) return RS_OK;
  uint32_t *c = malloc(sizeof *c * N), *loc = malloc(sizeof *loc * N);
  int rc = RS_OK;
  if (!c || !loc) {
    rc = RS_E_OOM;
    goto done;
  }
  for (uint32_t i = 0; i < N; i++) c[i] = i;
  for (uint32_t k = 0; k < m->nco; k++) {
    uint32_t a = uf_find(c, m->co[k].g), b = uf_find(c, m->ngt + m->co[k].h);
    if (a != b) c[a > b ? a : b] = a < b ? a : b;
  }
  /* co-occurrences grouped by root: sort (root << 32 | k) */
  uint64_t *keys = malloc(sizeof *keys * m->nco);
  if (!keys) {
    rc = RS_E_OOM;
    goto done;
  }
  for (uint32_t k = 0; k < m->nco; k++) keys[k] = (uint64_t)uf_find(c, m->co[k].g) << 32 | k;
  qsort(keys, m->nco, sizeof *keys, cmp_u64);
  for (uint32_t a = 0, b; a < m->nco; a = b) {
    const uint32_t root = (uint32_t)(keys[a] >> 32);
    for (b = a; b < m->nco && (uint32_t)(keys[b] >> 32) == root; b++) {
    }
    /* local numbering of the group's rows (true) and columns (tracks) */
    uint32_t nr = 0, nc = 0;
    for (uint32_t k = a; k < b; k++) {
      const mot_co_t *q = &m->co[(uint32_t)keys[k]];
      loc[q->g] = UINT32_MAX;
      loc[m->ngt + q->h] = UINT32_MAX;
    }
    for (uint32_t k = a; k < b; k++) {
      const mot_co_t *q = &m->co[(uint32_t)keys[k]];
      if (loc[q->g] == UINT32_MAX) loc[q->g] = nr++;
      if (loc[m->ngt + q->h] == UINT32_MAX) loc[m->ngt + q->h] = nc++;
    }
    const int n = (int)(nr > nc ? nr : nc);
    if (n == 1) {
      *out += m->co[(uint32_t)keys[a]].n;
      continue;
    }
    double *cost = calloc((size_t)n * n, sizeof *cost), *w = malloc(sizeof *w * 3 * ((size_t)n + 1));
    int *as = malloc(sizeof *as * 3 * ((size_t)n + 1));
    char *used = malloc((size_t)n + 1);
    if (!cost || !w || !as || !used) {
      free(cost);
      free(w);
      free(as);
      free(used);
      free(keys);
      rc = RS_E_OOM;
      goto done;
    }
    for (uint32_t k = a; k < b; k++) { /* maximise co-occurrence = minimise its negative */
      const mot_co_t *q = &m->co[(uint32_t)keys[k]];
      cost[(size_t)loc[q->g] * n + loc[m->ngt + q->h]] = -(double)q->n;
    }
    int *asg = as;
    rs_assign_min(cost, n, (size_t)n, asg, w, as + n + 1, (unsigned char *)used);
    for (int i = 0; i < n; i++)
      if (asg[i] >= 0) *out += (uint64_t)llround(-cost[(size_t)i * n + asg[i]]);
    free(cost);
    free(w);
    free(as);
    free(used);
  }
  free(keys);
done:
  free(c);
  free(loc);
  return rc;
}

int rs_mot_finish(rs_mot_t *m, rs_mot_result_t *out) {
  rs_mot_result_t *r = &m->r;
  if (m->oom) return RS_E_OOM;
  r->objects = m->ngt;
  r->tracks = m->nh;
  r->mostly_tracked = r->partly_tracked = r->mostly_lost = 0;
  for (uint32_t g = 0; g < m->ngt; g++) {
    const double ratio = m->gt[g].frames ? (double)m->gt[g].matched / m->gt[g].frames : 0.0;
    if (ratio >= 0.8) r->mostly_tracked++;
    else if (ratio < 0.2) r->mostly_lost++;
    else r->partly_tracked++;
  }
  if (idtp(m, &r->idtp) != RS_OK) return RS_E_OOM;
  r->mota = r->gt ? 1.0 - (double)(r->misses + r->false_pos + r->switches) / (double)r->gt : NAN;
  r->motp_iou = r->matches ? r->iou_sum / (double)r->matches : NAN;
  r->idf1 = r->gt + r->hyp ? 2.0 * (double)r->idtp / (double)(r->gt + r->hyp) : NAN;
  r->idp = r->hyp ? (double)r->idtp / (double)r->hyp : NAN;
  r->idr = r->gt ? (double)r->idtp / (double)r->gt : NAN;
  *out = *r;
  return RS_OK;
}

void rs_mot_print(const rs_mot_result_t *r, FILE *out) {
  fprintf(out, "tracking (frames 1+, %llu frames): true instances %llu, predicted %llu, matched %llu\n",
          (unsigned long long)r->frames, (unsigned long long)r->gt, (unsigned long long)r->hyp,
          (unsigned long long)r->matches);
  fprintf(out, "  MOTA ");
  pct(out, r->mota);
  fprintf(out, "  MOTP (mean IoU) ");
  pct(out, r->motp_iou);
  fprintf(out, "  IDF1 ");
  pct(out, r->idf1);
  fprintf(out, " (IDP ");
  pct(out, r->idp);
  fprintf(out, ", IDR ");
  pct(out, r->idr);
  fprintf(out, ")\n  misses %llu, false positives %llu, id switches %llu, fragmentations %llu\n",
          (unsigned long long)r->misses, (unsigned long long)r->false_pos, (unsigned long long)r->switches,
          (unsigned long long)r->fragmentations);
  fprintf(out,
          "  false positives overlapping a true instance %llu, mostly returns of road users seen with fewer than %d "
          "returns %llu, of the scene (static, foliage, noise) %llu\n",
          (unsigned long long)r->fp_instance, RS_EVAL_MIN_INSTANCE, (unsigned long long)r->fp_small,
          (unsigned long long)r->fp_scene);
  fprintf(out, "  true objects %llu: mostly tracked %llu, partly %llu, mostly lost %llu; tracks %llu\n",
          (unsigned long long)r->objects, (unsigned long long)r->mostly_tracked, (unsigned long long)r->partly_tracked,
          (unsigned long long)r->mostly_lost, (unsigned long long)r->tracks);
}

json_t *rs_mot_json(const rs_mot_result_t *r) {
  return json_pack("{s:I, s:I, s:I, s:I, s:I, s:I, s:I, s:I, s:I, s:I, s:I, s:I, s:I, s:I, s:I, s:I, s:I, s:o, s:o, s:o, "
                   "s:o, s:o}",
                   "frames", (json_int_t)r->frames, "gt", (json_int_t)r->gt, "hyp", (json_int_t)r->hyp, "matches",
                   (json_int_t)r->matches, "misses", (json_int_t)r->misses, "false_positives", (json_int_t)r->false_pos,
                   "false_positives_on_instances", (json_int_t)r->fp_instance, "false_positives_on_small_objects",
                   (json_int_t)r->fp_small, "false_positives_on_scene", (json_int_t)r->fp_scene, "id_switches",
                   (json_int_t)r->switches, "fragmentations", (json_int_t)r->fragmentations, "objects",
                   (json_int_t)r->objects, "mostly_tracked", (json_int_t)r->mostly_tracked, "partly_tracked",
                   (json_int_t)r->partly_tracked, "mostly_lost", (json_int_t)r->mostly_lost, "tracks",
                   (json_int_t)r->tracks, "idtp", (json_int_t)r->idtp, "mota", jnum(r->mota), "motp_iou",
                   jnum(r->motp_iou), "idf1", jnum(r->idf1), "idp", jnum(r->idp), "idr", jnum(r->idr));
}

void rs_mot_print_json(const rs_mot_result_t *r, FILE *out) { dump(rs_mot_json(r), out); }

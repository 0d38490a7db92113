/* eval.c - point-label metrics (tools only). */
#include "roadscan/eval.h"

#include "roadscan/error.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

const double rs_eval_band_edges[RS_EVAL_BANDS + 1] = {0, 20, 50, 100, 200};

#define PAIR_CAP (1u << 20)

int rs_eval_init(rs_eval_t *e) {
  memset(e, 0, sizeof *e);
  e->cap = PAIR_CAP;
  e->pairs = calloc(e->cap, sizeof *e->pairs);
  e->used = calloc(e->cap, sizeof *e->used);
  if (e->pairs == NULL || e->used == NULL) {
    rs_eval_deinit(e);
    return RS_E_NOMEM;
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

void rs_eval_end_frame(rs_eval_t *e, bool counted) {
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

static void jnum(FILE *out, double v) {
  if (isnan(v)) fprintf(out, "null");
  else fprintf(out, "%.6f", v);
}

void rs_eval_print_json(const rs_eval_result_t *r, FILE *out) {
  fprintf(out, "{\"frames\": %llu, \"points\": %llu, \"target\": {\"precision\": ", (unsigned long long)r->frames,
          (unsigned long long)r->points);
  jnum(out, rs_eval_ratio(r->t_tp, r->t_tp + r->t_fp));
  fprintf(out, ", \"recall\": ");
  jnum(out, rs_eval_ratio(r->t_tp, r->t_tp + r->t_fn));
  fprintf(out, ", \"iou\": ");
  jnum(out, rs_eval_ratio(r->t_tp, r->t_tp + r->t_fp + r->t_fn));
  fprintf(out, ", \"tp\": %llu, \"fp\": %llu, \"fn\": %llu}, \"non_target\": {\"precision\": ",
          (unsigned long long)r->t_tp, (unsigned long long)r->t_fp, (unsigned long long)r->t_fn);
  jnum(out, rs_eval_ratio(r->n_tp, r->n_tp + r->n_fp));
  fprintf(out, ", \"recall\": ");
  jnum(out, rs_eval_ratio(r->n_tp, r->n_tp + r->n_fn));
  fprintf(out, ", \"iou\": ");
  jnum(out, rs_eval_ratio(r->n_tp, r->n_tp + r->n_fp + r->n_fn));
  fprintf(out,
          "}, \"matched\": %llu, \"instances\": %llu, \"merged\": %llu, \"split\": %llu, \"missed\": %llu, "
          "\"background\": {\"static_kept\": ",
          (unsigned long long)r->matched, (unsigned long long)r->instances, (unsigned long long)r->merged,
          (unsigned long long)r->split, (unsigned long long)r->missed);
  jnum(out, rs_eval_ratio(r->static_kept, r->static_true));
  fprintf(out, ", \"targets_kept\": ");
  jnum(out, rs_eval_ratio(r->target_kept, r->target_true));
  fprintf(out, ", \"foliage_background\": ");
  jnum(out, rs_eval_ratio(r->foliage_background, r->foliage_true));
  fprintf(out, "}, \"recall_by_range\": {");
  for (int b = 0; b < RS_EVAL_BANDS; b++) {
    fprintf(out, "%s\"%g-%g\": ", b ? ", " : "", rs_eval_band_edges[b], rs_eval_band_edges[b + 1]);
    jnum(out, rs_eval_ratio(r->band_hit[b], r->band_true[b]));
  }
  fprintf(out, "}}\n");
}

/* scenestats.c - static-scene statistics of a capture (offline; allocates). */
#include "roadscan/offline/scenestats.h"

#include "roadscan/util/error.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

const double rs_sstats_band_lo[RS_SSTATS_BANDS] = {0.0, 5.0, 15.0, 40.0, 80.0};

static int band_of(double r) {
  int b = 0;
  while (b + 1 < RS_SSTATS_BANDS && r >= rs_sstats_band_lo[b + 1]) b++;
  return b;
}

int rs_sstats_init(rs_sstats_frames_t *f, rs_model_t model, int rows, int cols, int max_frames) {
  memset(f, 0, sizeof *f);
  if (rows < 1 || rows > RS_MAX_ROWS || cols < RS_MIN_COLS || cols > RS_MAX_COLS || max_frames < 2) return RS_E_INVAL;
  f->model = model;
  f->rows = rows;
  f->cols = cols;
  f->max_frames = max_frames;
  const size_t n = (size_t)rows * (size_t)cols * (size_t)max_frames;
  f->range = malloc(n * sizeof *f->range);
  f->inten = malloc(n);
  f->t = calloc((size_t)max_frames, sizeof *f->t);
  f->rate_hz = calloc((size_t)max_frames, sizeof *f->rate_hz);
  f->first_az = calloc((size_t)max_frames, sizeof *f->first_az);
  if (!f->range || !f->inten || !f->t || !f->rate_hz || !f->first_az) {
    rs_sstats_free(f);
    return RS_E_OOM;
  }
  return RS_OK;
}

void rs_sstats_free(rs_sstats_frames_t *f) {
  free(f->range);
  free(f->inten);
  free(f->t);
  free(f->rate_hz);
  free(f->first_az);
  memset(f, 0, sizeof *f);
}

bool rs_sstats_add(rs_sstats_frames_t *f, const rs_slot_t *s) {
  if (f->nframes >= f->max_frames || s->meta.rows != f->rows || s->meta.cols != f->cols) return false;
  const int k = f->nframes++;
  const size_t cells = (size_t)f->rows * (size_t)f->cols;
  for (size_t c = 0; c < cells; c++) {
    f->range[c * (size_t)f->max_frames + (size_t)k] = s->range[c];
    f->inten[c * (size_t)f->max_frames + (size_t)k] = s->intensity[c];
  }
  f->t[k] = s->meta.t_first;
  f->rate_hz[k] = s->meta.rate_hz;
  f->first_az[k] = s->meta.first_azimuth;
  return true;
}

static int cmp_flt(const void *a, const void *b) {
  float x = *(const float *)a, y = *(const float *)b;
  return (x > y) - (x < y);
}
static int cmp_dbl(const void *a, const void *b) {
  double x = *(const double *)a, y = *(const double *)b;
  return (x > y) - (x < y);
}
static void sort_vec(double *v, size_t n) {
  if (n > 1) qsort(v, n, sizeof *v, cmp_dbl); /* v is NULL when empty */
}

/* the q-quantile of n sorted doubles */
static double quant(const double *v, size_t n, double q) {
  if (n == 0) return NAN;
  size_t i = (size_t)floor(q * (double)(n - 1) + 0.5);
  return v[i];
}

/* growable double arrays for pooled values */
typedef struct {
  double *v;
  size_t n, cap;
} vec_t;
static int push(vec_t *a, double x) {
  if (a->n == a->cap) {
    size_t nc = a->cap ? a->cap * 2 : 1024;
    double *nv = realloc(a->v, nc * sizeof *nv);
    if (nv == NULL) return RS_E_OOM;
    a->v = nv;
    a->cap = nc;
  }
  a->v[a->n++] = x;
  return RS_OK;
}

#define MAX_SURF 16
#define DEV_BINS 1001 /* |deviation| in cm, the last bin: 10 m and more */

/* the q-quantile of a histogram, as the bin index */
static double hist_quant(const uint64_t *h, int bins, double q) {
  uint64_t tot = 0, acc = 0;
  for (int i = 0; i < bins; i++) tot += h[i];
  if (tot == 0) return NAN;
  uint64_t want = (uint64_t)ceil(q * (double)tot);
  for (int i = 0; i < bins; i++) {
    acc += h[i];
    if (acc >= want) return i;
  }
  return bins - 1;
}

int rs_sstats_compute(const rs_sstats_frames_t *f, rs_sstats_t *o) {
  memset(o, 0, sizeof *o);
  o->frames = f->nframes;
  o->rows = f->rows;
  o->cols = f->cols;
  const int nf = f->nframes;
  if (nf < 2) return RS_E_INVAL;
  const size_t cells = (size_t)f->rows * (size_t)f->cols;
  float *sorted = malloc(sizeof(float) * (size_t)nf);
  vec_t spread = {0}, sd[RS_SSTATS_BANDS] = {{0}};
  uint64_t(*dev)[DEV_BINS] = calloc(RS_SSTATS_BANDS, sizeof *dev);
  uint64_t(*inten)[256] = calloc(RS_SSTATS_BANDS, sizeof *inten);
  double drop_sum[RS_SSTATS_BANDS] = {0}, row_ret[RS_MAX_ROWS] = {0}, row_n[RS_MAX_ROWS] = {0};
  double runs = 0, run_frames = 0, indep_w = 0, indep_sum = 0, mixed = 0, multi_returns = 0;
  vec_t flat[RS_SSTATS_BANDS] = {{0}};
  /* every cell's median range (0: fewer than half the frames return) */
  float *med_map = calloc(cells, sizeof *med_map);
  for (size_t c = 0; c < cells && sorted && med_map; c++) {
    const float *x = f->range + c * (size_t)f->max_frames;
    int n = 0;
    for (int k = 0; k < nf; k++)
      if (x[k] > 0.0f) sorted[n++] = x[k];
    if (2 * n < nf) continue;
    qsort(sorted, (size_t)n, sizeof sorted[0], cmp_flt);
    med_map[c] = sorted[n / 2];
  }
  uint64_t steady = 0, multi = 0;
  int rc = sorted && dev && inten && med_map ? RS_OK : RS_E_OOM;
  for (size_t c = 0; c < cells && rc == RS_OK; c++) {
    const float *x = f->range + c * (size_t)f->max_frames;
    const uint8_t *in = f->inten + c * (size_t)f->max_frames;
    int n = 0;
    for (int k = 0; k < nf; k++)
      if (x[k]) sorted[n++] = x[k];
    if (2 * n < nf) continue;
    steady++;
    qsort(sorted, (size_t)n, sizeof sorted[0], cmp_flt);
    /* surfaces: split at gaps over max(30 cm, 3 %) */
    float lo[MAX_SURF], hi[MAX_SURF];
    int cnt[MAX_SURF], ns = 0, start = 0;
    for (int i = 1; i <= n && ns < MAX_SURF; i++) {
      if (i < n) {
        double gap = fmax(0.30, 0.03 * sorted[i - 1]);
        if (sorted[i] - sorted[i - 1] <= gap) continue;
      }
      if ((i - start) * 10 >= n) {
        lo[ns] = sorted[start];
        hi[ns] = sorted[i - 1];
        cnt[ns] = i - start;
        ns++;
      }
      start = i;
    }
    const double med = sorted[n / 2];
    const int b = band_of(med);
    o->band_cells[b]++;
    drop_sum[b] += 1.0 - (double)n / nf;
    const int row = (int)(c / (size_t)f->cols);
    row_ret[row] += (double)n / nf;
    row_n[row] += 1;
    for (int k = 0; k < nf; k++)
      if (x[k]) inten[b][in[k]]++;
    if (ns >= 2) {
      multi++;
      if ((rc = push(&spread, sorted[n - 1] - sorted[0])) != RS_OK) break;
      /* runs on one surface, frames in time order (no return and between surfaces: skipped) */
      int last = -1, run = 0;
      double tot = 0, p2 = 0;
      for (int s = 0; s < ns; s++) tot += cnt[s];
      for (int s = 0; s < ns; s++) p2 += (cnt[s] / tot) * (cnt[s] / tot);
      for (int k = 0; k < nf; k++) {
        int m = -1;
        for (int s = 0; s < ns && x[k]; s++)
          if (x[k] >= lo[s] && x[k] <= hi[s]) m = s;
        if (m < 0) continue;
        if (m == last) {
          run++;
        } else {
          if (run) {
            runs++;
            run_frames += run;
          }
          run = 1;
          last = m;
        }
      }
      if (run) {
        runs++;
        run_frames += run;
      }
      /* returns between the surfaces, 10 cm or more from every one of them */
      for (int i = 0; i < n; i++) {
        bool near_one = false;
        for (int q = 0; q < ns && !near_one; q++) near_one = sorted[i] >= lo[q] - 0.10f && sorted[i] <= hi[q] + 0.10f;
        mixed += !near_one && sorted[i] > lo[0] && sorted[i] < hi[ns - 1];
      }
      multi_returns += n;
      if (p2 < 1.0) {
        indep_sum += tot / (1.0 - p2); /* expected run 1/(1-sum p^2), weighted by returns */
        indep_w += tot;
      }
    } else if (ns == 1) {
      /* noise: robust spread of this cell, pooled deviations from its median */
      double m = sorted[n / 2];
      double *ad = malloc(sizeof(double) * (size_t)n);
      if (ad == NULL) {
        rc = RS_E_OOM;
        break;
      }
      for (int i = 0; i < n; i++) {
        ad[i] = fabs(sorted[i] - m);
        dev[b][(int)fmin(ad[i] * 100.0 + 0.5, DEV_BINS - 1)]++;
      }
      qsort(ad, (size_t)n, sizeof ad[0], cmp_dbl);
      rc = push(&sd[b], 1.4826 * ad[n / 2]);
      /* a flat cell: the cells either side in the row agree within 0.3 % */
      const size_t cols = (size_t)f->cols, col = c % cols, base = c - col;
      const float l = med_map[base + (col + cols - 1) % cols], r = med_map[base + (col + 1) % cols];
      if (rc == RS_OK && l > 0.0f && r > 0.0f && fabs(l - med) < 0.003 * med && fabs(r - med) < 0.003 * med)
        rc = push(&flat[b], 1.4826 * ad[n / 2]);
      free(ad);
    }
  }
  if (rc == RS_OK) {
    o->steady = (double)steady / (double)cells;
    o->multi = steady ? (double)multi / (double)steady : 0.0;
    sort_vec(spread.v, spread.n);
    o->edge_spread_med = quant(spread.v, spread.n, 0.5);
    o->edge_spread_p90 = quant(spread.v, spread.n, 0.9);
    o->dwell = runs > 0 ? run_frames / runs : NAN;
    o->dwell_indep = indep_w > 0 ? indep_sum / indep_w : NAN;
    o->mixed = multi_returns > 0 ? mixed / multi_returns : NAN;
    for (int b = 0; b < RS_SSTATS_BANDS; b++) {
      sort_vec(sd[b].v, sd[b].n);
      o->noise_sd[b] = quant(sd[b].v, sd[b].n, 0.5);
      sort_vec(flat[b].v, flat[b].n);
      o->flat_sd[b] = quant(flat[b].v, flat[b].n, 0.5);
      o->flat_cells[b] = (uint32_t)flat[b].n;
      o->dev_p99[b] = hist_quant(dev[b], DEV_BINS, 0.99) / 100.0;
      uint64_t far = 0, all = 0;
      for (int i = 0; i < DEV_BINS; i++) {
        all += dev[b][i];
        far += i > 10 ? dev[b][i] : 0;
      }
      o->dev_10cm[b] = all ? (double)far / (double)all : NAN;
      o->dropout[b] = o->band_cells[b] ? drop_sum[b] / o->band_cells[b] : NAN;
      o->intensity_med[b] = hist_quant(inten[b], 256, 0.5);
    }
    double rows_drop[RS_MAX_ROWS];
    int nr = 0;
    for (int r = 0; r < f->rows; r++)
      if (row_n[r] > 0) rows_drop[nr++] = 1.0 - row_ret[r] / row_n[r];
    qsort(rows_drop, (size_t)nr, sizeof(double), cmp_dbl);
    o->drop_row_min = nr ? rows_drop[0] : NAN;
    o->drop_row_med = quant(rows_drop, (size_t)nr, 0.5);
    o->drop_row_max = nr ? rows_drop[nr - 1] : NAN;
    /* the firings: rate jitter and the turn-to-turn move of the first block */
    double sum = 0, sum2 = 0, ph = 0;
    int nph = 0;
    for (int k = 0; k < nf; k++) {
      sum += f->rate_hz[k];
      sum2 += (double)f->rate_hz[k] * f->rate_hz[k];
    }
    o->hz = sum / nf;
    o->rate_jitter = o->hz > 0 ? 100.0 * sqrt(fmax(0.0, sum2 / nf - o->hz * o->hz)) / o->hz : NAN;
    const double group_us = rs_model_group_us(rs_model_info(f->model));
    for (int k = 1; k < nf; k++) {
      double step = f->rate_hz[k] * 360.0 / 1e6 * group_us * 100.0; /* 0.01 deg per block group */
      if (step <= 0 || f->t[k] - f->t[k - 1] > 1.5 / f->rate_hz[k]) continue; /* a frame missing between */
      double d = ((double)f->first_az[k] - (double)f->first_az[k - 1]) / step;
      d -= floor(d);
      ph += fmin(d, 1.0 - d);
      nph++;
    }
    o->phase_step = nph ? ph / nph : NAN;
  }
  free(sorted);
  free(spread.v);
  for (int b = 0; b < RS_SSTATS_BANDS; b++) {
    free(sd[b].v);
    free(flat[b].v);
  }
  free(med_map);
  free(dev);
  free(inten);
  return rc;
}

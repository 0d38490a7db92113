/* cluster.c - FSPC, adaptive FSPC, DBSCAN and CCL on a frame slot
 * (processing thread; no allocation, bounded loops). */
#include "roadscan/perception/cluster.h"

#include "roadscan/util/error.h"
#include "roadscan/util/sort.h"

#include <math.h>
#include <string.h>

#define NEG (-1.0e9f)
#define D2R (3.14159265358979323846 / 180.0)

void rs_cluster_cfg_default(rs_cluster_cfg_t *c) {
  memset(c, 0, sizeof *c);
  c->method = RS_CLUSTER_FSPC;
  c->bridge_gap = 32;
  c->fspc = (rs_fspc_cfg_t){.win_h = 5, .win_w = 11, .eps = 1.8f, .min_pts = 15};
  c->adaptive = (rs_fspc_adaptive_cfg_t){.win_h = 5,
                                         .win_w = 11,
                                         .max_min_pts = 15,
                                         .obj_w = 0.5f,
                                         .obj_h = 0.8f,
                                         .share = 0.2f,
                                         .min_pts = 3,
                                         .sparse_cells = 3.0f,
                                         .sparse_min_pts = 2,
                                         .min_half_w = 2,
                                         .eps_share = 0.025f,
                                         .eps_rows = 1.0f,
                                         .eps_min = 0.5f,
                                         .eps_max = 2.5f,
                                         .border_eps = 2.0f,
                                         .seed_surfaces = 3,
                                         .split_gap = 0.5f,
                                         .split_width = 1.2f,
                                         .split_depth = 0.5f,
                                         .split_min = 5};
  c->dbscan = (rs_dbscan_cfg_t){.eps = 1.2f, .min_pts = 15};
  c->ccl = (rs_ccl_cfg_t){.eps = 1.0f};
}

bool rs_cluster_cfg_set_eps(rs_cluster_cfg_t *c, float eps) {
  switch (c->method) {
  case RS_CLUSTER_FSPC: c->fspc.eps = eps; return true;
  case RS_CLUSTER_FSPC_ADAPTIVE: c->adaptive.eps_max = eps; return true;
  case RS_CLUSTER_DBSCAN: c->dbscan.eps = eps; return true;
  case RS_CLUSTER_CCL: c->ccl.eps = eps; return true;
  default: return false;
  }
}

bool rs_cluster_cfg_set_min_pts(rs_cluster_cfg_t *c, int min_pts) {
  switch (c->method) {
  case RS_CLUSTER_FSPC: c->fspc.min_pts = min_pts; return true;
  case RS_CLUSTER_FSPC_ADAPTIVE: c->adaptive.max_min_pts = min_pts; return true;
  case RS_CLUSTER_DBSCAN: c->dbscan.min_pts = min_pts; return true;
  default: return false;
  }
}

bool rs_cluster_cfg_set_window(rs_cluster_cfg_t *c, int h, int w) {
  switch (c->method) {
  case RS_CLUSTER_FSPC: c->fspc.win_h = h, c->fspc.win_w = w; return true;
  case RS_CLUSTER_FSPC_ADAPTIVE: c->adaptive.win_h = h, c->adaptive.win_w = w; return true;
  default: return false;
  }
}

static bool window_ok(int h, int w) {
  return h >= 1 && h <= RS_MAX_WIN_H && h % 2 == 1 && w >= 1 && w <= RS_MAX_WIN_W && w % 2 == 1;
}

const char *rs_cluster_method_name(rs_cluster_method_t m) {
  switch (m) {
  case RS_CLUSTER_FSPC: return "fspc";
  case RS_CLUSTER_FSPC_ADAPTIVE: return "fspc-adaptive";
  case RS_CLUSTER_DBSCAN: return "dbscan";
  case RS_CLUSTER_CCL: return "ccl";
  default: return "none";
  }
}

int rs_cluster_method_from_name(const char *s) {
  for (int m = RS_CLUSTER_NONE; m <= RS_CLUSTER_CCL; m++)
    if (strcmp(s, rs_cluster_method_name((rs_cluster_method_t)m)) == 0) return m;
  return -1;
}

int rs_cluster_init(rs_cluster_t *c, const rs_cluster_cfg_t *cfg, const rs_sensor_t *s) {
  const rs_fspc_cfg_t *f = &cfg->fspc;
  const rs_fspc_adaptive_cfg_t *a = &cfg->adaptive;
  if (!window_ok(f->win_h, f->win_w) || !(f->eps > 0) || f->min_pts < 1) return RS_E_INVAL;
  if (!window_ok(a->win_h, a->win_w) || a->max_min_pts < 1 || !(a->eps_min > 0) || !(a->eps_max >= a->eps_min) ||
      !(a->border_eps >= 1.0f) || a->min_pts < 1 || a->sparse_min_pts < 1 || !(a->sparse_cells >= 0.0f) ||
      a->min_half_w < 0 || !(a->obj_w > 0) || !(a->obj_h > 0) || !(a->share > 0) || a->seed_surfaces < 0 ||
      !(a->split_gap >= 0) || !(a->split_width > 0) || !(a->split_depth >= 0) || a->split_min < 1)
    return RS_E_INVAL;
  if (!(cfg->dbscan.eps > 0) || cfg->dbscan.min_pts < 1 || !(cfg->ccl.eps > 0)) return RS_E_INVAL;
  if (cfg->bridge_gap < 0 || cfg->bridge_gap > RS_CLUSTER_BRIDGE_MAX) return RS_E_INVAL;
  c->cfg = *cfg;
  c->sensor = s;
  c->bg_surfaces = NULL;
  c->cols = 0;
  c->overflow_total = 0;
  return RS_OK;
}

/* adaptive tables for a column count: per row and 1 m range bin, the window
 * and minPts an object of obj_w x obj_h would fill */
static void build_adaptive(rs_cluster_t *c, int cols) {
  const rs_sensor_t *s = c->sensor;
  const double daz = 2.0 * 3.14159265358979323846 / cols;
  /* the sensor's median spacing between adjacent rows (radians): adjacent
   * rows on one surface differ in range in proportion to it */
  double gaps[RS_MAX_ROWS];
  int ng = 0;
  for (int r = 1; r < s->lasers; r++)
    gaps[ng++] = (s->elevation_deg[s->laser_of_row[r]] - s->elevation_deg[s->laser_of_row[r - 1]]) * D2R;
  for (int i = 1; i < ng; i++) /* insertion sort, at most 127 values, once per geometry */
    for (int j = i; j > 0 && gaps[j - 1] > gaps[j]; j--) {
      double t = gaps[j];
      gaps[j] = gaps[j - 1];
      gaps[j - 1] = t;
    }
  const double eps_share = fmax(c->cfg.adaptive.eps_share, c->cfg.adaptive.eps_rows * (ng ? gaps[ng / 2] : 0.0));
  for (int r = 0; r < s->lasers; r++) {
    double el = s->elevation_deg[s->laser_of_row[r]];
    double lo = r > 0 ? el - s->elevation_deg[s->laser_of_row[r - 1]] : 1e9;
    double hi = r + 1 < s->lasers ? s->elevation_deg[s->laser_of_row[r + 1]] - el : 1e9;
    double del = fmin(lo, hi) < 1e8 ? fmin(lo, hi) * D2R : 2.0 * D2R;
    if (del < 0.05 * D2R) del = 0.05 * D2R;
    for (int b = 0; b < RS_ADAPT_BINS; b++) {
      double range = b + 0.5;
      double ncol = c->cfg.adaptive.obj_w / (range * daz), nrow = c->cfg.adaptive.obj_h / (range * del);
      int hw = (int)fmin(c->cfg.adaptive.win_w / 2, fmax(c->cfg.adaptive.min_half_w, ceil(ncol / 2.0)));
      int hh = (int)fmin(c->cfg.adaptive.win_h / 2, fmax(1.0, ceil(nrow / 2.0)));
      double cells = fmin(2 * hw + 1, fmax(1.0, ncol)) * fmin(2 * hh + 1, fmax(1.0, nrow));
      int mp = (int)lround(c->cfg.adaptive.share * cells);
      if (mp > c->cfg.adaptive.max_min_pts) mp = c->cfg.adaptive.max_min_pts;
      /* where the smallest object covers only a few cells, a pair of returns side by side is one */
      const int floor_mp = cells < c->cfg.adaptive.sparse_cells ? c->cfg.adaptive.sparse_min_pts : c->cfg.adaptive.min_pts;
      if (mp < floor_mp) mp = floor_mp;
      c->half_w[r][b] = (uint8_t)hw;
      c->half_h[r][b] = (uint8_t)hh;
      c->min_pts[r][b] = (uint8_t)mp;
      double e = eps_share * range;
      c->eps_tab[r][b] = (float)fmin(c->cfg.adaptive.eps_max, fmax(c->cfg.adaptive.eps_min, e));
    }
  }
  c->cols = cols;
}

static inline int bin_of(float r) {
  int b = (int)r;
  return b < 0 ? 0 : (b >= RS_ADAPT_BINS ? RS_ADAPT_BINS - 1 : b);
}

/* ---- the window across a lost packet (bridge_gap) ---------------------------
 * A lost packet leaves 2.4 (VLP-32C) or 4.8 degrees (VLP-16) of a turn
 * unmeasured (rs_slot_t.gap, by block azimuth: a row's returns lie at its
 * laser's azimuth offset from it). A vehicle across it was two clusters, each
 * a box cut where the gap is. Where a frame has such columns, a window's
 * half-width counts measured columns of its row: it reaches across up to
 * bridge_gap unmeasured ones (a gap wider, the partial frame's missing part,
 * is not reached across). Without gaps the windows are the plain ones. The
 * tables are made once a frame (a pass over the columns), only read after. */
/* measured block columns in [a, a + span) around the turn (rank: how many lie before each column) */
static int measured_in(const rs_cluster_t *c, int cols, int a, int span) {
  const int m = c->rank[cols];
  if (span >= cols) return m;
  a = (a % cols + cols) % cols;
  const int b = a + span;
  return b <= cols ? c->rank[b] - c->rank[a] : (m - c->rank[a]) + c->rank[b - cols];
}
static void bridge_prepare(rs_cluster_t *c, const rs_slot_t *s) {
  const int cols = s->meta.cols, rows = s->meta.rows;
  c->bridge = false;
  if (c->cfg.bridge_gap <= 0) return;
  int m = 0;
  for (int k = 0; k < cols; k++) {
    c->rank[k] = (uint16_t)m;
    if (!s->gap[k]) c->measured[m++] = (uint16_t)k;
  }
  c->rank[cols] = (uint16_t)m;
  c->bridge = m < cols && m > 0;
  if (!c->bridge) return;
  int lo = 0, hi = 0;
  for (int r = 0; r < rows && r < RS_MAX_ROWS; r++) {
    c->row_shift[r] = r < c->sensor->lasers
                          ? (int16_t)lround(c->sensor->azimuth_offset_deg[c->sensor->laser_of_row[r]] * cols / 360.0)
                          : 0;
    if (c->row_shift[r] < lo) lo = c->row_shift[r];
    if (c->row_shift[r] > hi) hi = c->row_shift[r];
  }
  /* the map columns whose windows (any row's offset, the method's widest window) may hold an
   * unmeasured column: block columns [col - hi - R, col - lo + R] */
  const rs_cluster_method_t me = c->cfg.method;
  const int R = me == RS_CLUSTER_CCL ? 1 : (me == RS_CLUSTER_FSPC_ADAPTIVE ? c->cfg.adaptive.win_w : c->cfg.fspc.win_w) / 2;
  const int span = hi - lo + 2 * R + 1;
  for (int col = 0; col < cols; col++)
    c->near_gap[col] = measured_in(c, cols, col - hi - R, span) < (span < cols ? span : cols);
}
/* row y's window columns about map column col, half-width hw in measured columns: its first column *a
 * (within [0, cols)) and how many, at most 2 hw + 1 + bridge_gap (else the plain window) */
static void bridge_span(const rs_cluster_t *c, int cols, int y, int col, int hw, int *a, int *n) {
  *a = ((col - hw) % cols + cols) % cols;
  *n = 2 * hw + 1;
  const int m = c->rank[cols];
  if (!c->bridge || 2 * hw + 1 >= m) return;
  const int sh = c->row_shift[y];
  int b = col - sh;
  if (b < 0) b += cols;
  else if (b >= cols) b -= cols;
  const int k = c->rank[b];
  if (measured_in(c, cols, b - hw, 2 * hw + 1) == 2 * hw + 1) return; /* most windows: the plain one */
  const int lo = c->measured[((k - hw) % m + m) % m], hi = c->measured[((k + hw - (c->measured[k % m] != b)) % m + m) % m];
  const int len = ((hi - lo) % cols + cols) % cols + 1;
  if (len > 2 * hw + 1 + c->cfg.bridge_gap || len < 2 * hw + 1) return;
  *a = ((lo + sh) % cols + cols) % cols;
  *n = len;
}

/* columns [a, a + len) around the turn (a > -cols) as at most two segments: the whole turn when len
 * reaches cols; one before column 0 (a < 0) is the second; returns how many */
static int segments(int cols, int a, int len, int seg_a[2], int seg_n[2]) {
  if (len >= cols) {
    seg_a[0] = 0, seg_n[0] = cols;
    return 1;
  }
  if (a < 0) {
    seg_a[0] = 0, seg_n[0] = a + len, seg_a[1] = cols + a, seg_n[1] = -a;
    return 2;
  }
  if (a + len > cols) {
    seg_a[0] = a, seg_n[0] = cols - a, seg_a[1] = 0, seg_n[1] = a + len - cols;
    return 2;
  }
  seg_a[0] = a, seg_n[0] = len;
  return 1;
}

/* neighbours of cell (r, col) in a (2hh+1) x (2hw+1) window, counted until
 * `enough` (a core needs no more): rows nearest the centre first */
static uint32_t count_window(const rs_cluster_t *c, const float *rr, int rows, int cols, int r, int col, int hh, int hw,
                             float eps, uint32_t enough) {
  const float x = rr[r * cols + col];
  uint32_t n = 0;
  for (int step = 0; step <= 2 * hh; step++) {
    int y = r + (step % 2 ? (step + 1) / 2 : -(step / 2)); /* r, r-1, r+1, r-2, r+2, ... */
    if (y < 0 || y >= rows) continue;
    const float *row = rr + (size_t)y * (size_t)cols;
    int a = col - hw, len = 2 * hw + 1;
    if (c->bridge && c->near_gap[col]) bridge_span(c, cols, y, col, hw, &a, &len);
    if (len != 2 * hw + 1) { /* across a gap: a (from bridge_span) within [0, cols) */
      for (int d = 0; d < len; d++) {
        const int k = a + d < cols ? a + d : a + d - cols;
        n += fabsf(row[k] - x) < eps;
      }
    } else if (col - hw >= 0 && col + hw < cols) {
      for (int k = col - hw; k <= col + hw; k++) n += fabsf(row[k] - x) < eps;
    } else {
      for (int d = -hw; d <= hw; d++) {
        int k = col + d;
        if (k < 0) k += cols;
        else if (k >= cols) k -= cols;
        n += fabsf(row[k] - x) < eps;
      }
    }
    if (n >= enough) break;
  }
  return n;
}

/* up to 64 bits of a row's bitset from column a on */
static inline uint64_t row_bits(const uint64_t *w, int a, int n) {
  const int wi = a >> 6, off = a & 63;
  uint64_t v = w[wi] >> off;
  if (off + n > 64) v |= w[wi + 1] << (64 - off);
  return n >= 64 ? v : v & ((1ull << n) - 1);
}

static void prepare(rs_cluster_t *c, rs_slot_t *s, uint32_t *nfg) {
  const uint32_t rows = s->meta.rows, cols = s->meta.cols;
  uint32_t n = 0;
  for (uint32_t y = 0, i = 0; y < rows; y++)
    for (uint32_t x = 0; x < cols; x++, i++) {
      const float r = s->range[i];
      const bool fg = r > 0.0f && s->label[i] != 1;
      c->rr[i] = fg ? r : NEG;
      c->core[i] = 0;
      if (fg) {
        c->fg[n] = i;
        c->fgrc[n++] = y << 16 | x;
        s->label[i] = 2;
      }
    }
  *nfg = n;
}

/* The FSPC expansion with a given window, eps and minPts (or the adaptive
 * tables). CCL is the same with a 3 x 3 window and minPts 1: every
 * foreground cell is a core, 8-neighbours within eps join. */
static void fspc(rs_cluster_t *c, rs_slot_t *s, uint32_t nfg, bool adaptive, int hh0, int hw0, float eps, int min_pts,
                 rs_cluster_stats_t *st) {
  const int rows = s->meta.rows, cols = s->meta.cols;
  if (adaptive && c->cols != cols) build_adaptive(c, cols);
  const int seed_surf = adaptive && c->bg_surfaces ? c->cfg.adaptive.seed_surfaces : 0;
  bridge_prepare(c, s);
  /* core cells */
  for (uint32_t k = 0; k < nfg; k++) {
    const uint32_t i = c->fg[k];
    const int r = (int)(c->fgrc[k] >> 16), col = (int)(c->fgrc[k] & 0xffff);
    int hh = hh0, hw = hw0;
    uint32_t mp = (uint32_t)min_pts;
    float e = eps;
    if (adaptive) {
      int b = bin_of(c->rr[i]);
      hh = c->half_h[r][b];
      hw = c->half_w[r][b];
      mp = c->min_pts[r][b];
      e = c->eps_tab[r][b];
    }
    c->core[i] = count_window(c, c->rr, rows, cols, r, col, hh, hw, e, mp) >= mp;
    /* a cell the sensor sees through (several static surfaces) seeds no cluster */
    if (seed_surf > 0 && c->bg_surfaces[i] >= seed_surf) c->core[i] = 0;
  }
  /* clusters: breadth-first over core cells; every cell enters the queue
   * once. The window scan visits only the cells still open (foreground, no
   * cluster yet), from a per-row bitset: in a dense cluster most are taken. */
  const int wpr = (cols + 63) / 64;
  memset(c->open, 0, sizeof(uint64_t) * (size_t)rows * (size_t)wpr);
  for (uint32_t k = 0; k < nfg; k++) {
    const uint32_t r = c->fgrc[k] >> 16, col = c->fgrc[k] & 0xffff;
    c->open[r * (uint32_t)wpr + (col >> 6)] |= 1ull << (col & 63);
  }
  uint32_t ncl = 0;
  for (uint32_t k = 0; k < nfg; k++) {
    uint32_t seed = c->fg[k];
    if (!c->core[seed] || s->label[seed] != 2) continue;
    if (ncl >= RS_MAX_CLUSTERS) {
      st->overflow++;
      continue;
    }
    const uint16_t id = (uint16_t)(3 + ncl++);
    /* the split pass's counts: each cluster's size and nearest range */
    uint32_t *size = &c->start[ncl];
    float *rmin = &c->rmin[ncl - 1];
    *size = 1;
    *rmin = c->rr[seed];
    uint32_t head = 0, tail = 0;
    c->queue[tail++] = c->fgrc[k];
    s->label[seed] = id;
    {
      const uint32_t sr = c->fgrc[k] >> 16, sc = c->fgrc[k] & 0xffff;
      c->open[sr * (uint32_t)wpr + (sc >> 6)] &= ~(1ull << (sc & 63));
    }
    while (head < tail) {
      const int r = (int)(c->queue[head] >> 16), col = (int)(c->queue[head] & 0xffff);
      head++;
      const uint32_t i = (uint32_t)r * (uint32_t)cols + (uint32_t)col;
      int hh = hh0, hw = hw0;
      float e = eps;
      if (adaptive) {
        int b = bin_of(c->rr[i]);
        hh = c->half_h[r][b];
        hw = c->half_w[r][b];
        e = c->eps_tab[r][b];
      }
      const float x = c->rr[i];
      const float eb = adaptive ? e * c->cfg.adaptive.border_eps : e; /* reach of a cell that is not a core */
      /* the window's columns as at most two segments (it may wrap) */
      int seg_a[2], seg_n[2];
      int nseg = segments(cols, col - hw, 2 * hw + 1, seg_a, seg_n);
      int r0 = r - hh < 0 ? 0 : r - hh, r1 = r + hh >= rows ? rows - 1 : r + hh;
      for (int y = r0; y <= r1; y++) {
        uint64_t *w = c->open + (size_t)y * (size_t)wpr;
        const uint32_t base = (uint32_t)y * (uint32_t)cols;
        if (c->bridge && c->near_gap[col]) { /* this row's window across a gap: its segments again */
          int a, len;
          bridge_span(c, cols, y, col, hw, &a, &len);
          nseg = segments(cols, a, len, seg_a, seg_n);
        }
        for (int g = 0; g < nseg; g++) {
          /* a segment longer than 64 columns (a huge window) is read in pieces */
          for (int a = seg_a[g], left = seg_n[g]; left > 0; a += 64, left -= 64) {
            int n = left < 64 ? left : 64;
            uint64_t m = row_bits(w, a, n);
            while (m) {
              int bit = __builtin_ctzll(m);
              m &= m - 1;
              const int cc = a + bit;
              const uint32_t j = base + (uint32_t)cc;
              const float d = fabsf(c->rr[j] - x);
              if (d >= e && (d >= eb || c->core[j])) continue;
              s->label[j] = id;
              ++*size;
              if (c->rr[j] < *rmin) *rmin = c->rr[j];
              w[cc >> 6] &= ~(1ull << (cc & 63));
              if (c->core[j]) c->queue[tail++] = (uint32_t)y << 16 | (uint32_t)cc;
            }
          }
        }
      }
    }
  }
  st->clusters = ncl;
}

/* ---- the split pass (adaptive): clusters cut at gaps in range ---- */

static int cmp_range(const void *a, const void *b) {
  const float x = ((const rs_cluster_ret_t *)a)->range, y = ((const rs_cluster_ret_t *)b)->range;
  return (x > y) - (x < y);
}

/* the columns n returns span (wrapping, from the first one's) and how wide
 * that is across the line of sight (m) */
static float part_width(const rs_cluster_ret_t *v, uint32_t n, int cols, int *span) {
  const int c0 = (int)(v[0].rc & 0xffff);
  float lo = 0.0f, hi = 0.0f;
  int dlo = 0, dhi = 0;
  for (uint32_t i = 1; i < n; i++) {
    int d = (int)(v[i].rc & 0xffff) - c0;
    if (d > cols / 2) d -= cols;
    else if (d < -cols / 2) d += cols;
    const float x = (float)d * v[i].range;
    if (x < lo) lo = x;
    if (x > hi) hi = x;
    if (d < dlo) dlo = d;
    if (d > dhi) dhi = d;
  }
  *span = dhi - dlo + 1;
  return (hi - lo) * (float)(2.0 * 3.14159265358979323846 / cols);
}

/* the rows n returns span */
static void part_rows(const rs_cluster_ret_t *v, uint32_t n, uint32_t *lo, uint32_t *hi) {
  *lo = UINT32_MAX;
  *hi = 0;
  for (uint32_t i = 0; i < n; i++) {
    const uint32_t r = v[i].rc >> 16;
    if (r < *lo) *lo = r;
    if (r > *hi) *hi = r;
  }
}

/* Where to cut a cluster sorted by range (v, n): the runs between gaps of
 * at least split_gap. A run of fewer than split_min returns or in one
 * column (mixed ranges at an edge between two people) stays with the run
 * before it (the first with the next). The parts are kept only when each
 * is at most split_depth deep (its runs of substance) and split_width wide,
 * and shares a row with the part before it: people one behind the other
 * stand side by side in the image; a bumper and a roof do not. The start
 * of each part after the first goes to cut[]; returns the number of cuts
 * (0: the cluster stays whole). */
static uint32_t cuts_of(const rs_cluster_ret_t *v, uint32_t n, const rs_fspc_adaptive_cfg_t *a, int cols,
                        uint32_t cut[RS_SPLIT_MAX_PARTS]) {
  uint32_t run_a[RS_SPLIT_MAX_RUNS], run_b[RS_SPLIT_MAX_RUNS];
  bool solid[RS_SPLIT_MAX_RUNS];
  uint32_t nrun = 0, from = 0, nsolid = 0;
  for (uint32_t i = 1; i <= n; i++) {
    if (i < n && v[i].range - v[i - 1].range < a->split_gap) continue;
    if (nrun == RS_SPLIT_MAX_RUNS) return 0; /* shattered: not a file of people */
    int span;
    part_width(v + from, i - from, cols, &span);
    run_a[nrun] = from;
    run_b[nrun] = i;
    solid[nrun] = i - from >= (uint32_t)a->split_min && span >= 2;
    nsolid += solid[nrun++];
    from = i;
  }
  if (nsolid < 2 || nsolid > RS_SPLIT_MAX_PARTS) return 0;
  /* parts: each solid run with the thin runs after it (before the first solid one: with it) */
  uint32_t ncut = 0, plo = 0, phi = 0, k = 0;
  while (!solid[k]) k++;
  for (bool first = true; k < nrun; first = false) {
    const uint32_t core_a = run_a[k], core_b = run_b[k];
    uint32_t end = k + 1;
    while (end < nrun && !solid[end]) end++;
    const uint32_t pa = first ? 0 : core_a, pb = run_b[end - 1];
    int span;
    if (v[core_b - 1].range - v[core_a].range > a->split_depth || part_width(v + pa, pb - pa, cols, &span) > a->split_width)
      return 0;
    uint32_t lo, hi;
    part_rows(v + core_a, core_b - core_a, &lo, &hi);
    if (!first && (lo > phi || hi < plo)) return 0;
    if (!first) cut[ncut++] = pa;
    plo = lo;
    phi = hi;
    k = end;
  }
  return ncut;
}

static void split(rs_cluster_t *c, rs_slot_t *s, uint32_t nfg, rs_cluster_stats_t *st) {
  const rs_fspc_adaptive_cfg_t *a = &c->cfg.adaptive;
  const uint32_t ncl = st->clusters, cols = s->meta.cols;
  if (!(a->split_gap > 0) || ncl == 0) return;
  /* clustered cells grouped by cluster (a counting sort on the sizes the
   * expansion counted): start[q] ends cluster q's run once placed,
   * start[q - 1] begins it */
  c->start[0] = 0; /* start[q + 1] holds cluster q's size, rmin[q] its nearest range (from the expansion) */
  for (uint32_t q = 0; q < ncl; q++) c->start[q + 1] += c->start[q];
  /* which bins of half the gap, from the cluster's nearest return on, hold
   * returns: a gap of split_gap leaves a bin empty, so a cluster with none
   * (a vehicle's continuous ranges) or deeper than 64 bins is not sorted */
  memset(c->occ, 0, sizeof c->occ[0] * ncl);
  const float inv_bin = 2.0f / a->split_gap;
  for (uint32_t k = 0; k < nfg; k++) {
    const uint32_t i = c->fg[k];
    const uint16_t l = s->label[i];
    if (l < RS_LABEL_FIRST_OBJECT) continue;
    const uint32_t q = l - RS_LABEL_FIRST_OBJECT;
    const float bin = (c->rr[i] - c->rmin[q]) * inv_bin;
    c->occ[q] |= bin < 64.0f ? 1ull << (int)bin : UINT64_MAX;
    c->byrange[c->start[q]++] = (rs_cluster_ret_t){.range = c->rr[i], .rc = c->fgrc[k]};
  }
  uint32_t next = ncl;
  for (uint32_t q = 0; q < ncl; q++) {
    const uint32_t b = q ? c->start[q - 1] : 0, n = c->start[q] - b;
    if (n < 2u * (uint32_t)a->split_min) continue;
    const uint64_t occ = c->occ[q], span = occ >> 63 ? UINT64_MAX : (2ull << (63 - __builtin_clzll(occ))) - 1;
    if ((occ & span) == span) continue; /* no gap */
    rs_cluster_ret_t *v = c->byrange + b;
    rs_sort(v, n, sizeof *v, cmp_range);
    uint32_t cut[RS_SPLIT_MAX_PARTS];
    const uint32_t ncut = cuts_of(v, n, a, (int)cols, cut);
    if (ncut == 0) continue;
    if (next + ncut > RS_MAX_CLUSTERS) {
      st->overflow++;
      continue;
    }
    st->splits++;
    /* the nearest part keeps the label; each farther one takes a new one */
    for (uint32_t p = 0; p < ncut; p++) {
      const uint16_t id = (uint16_t)(RS_LABEL_FIRST_OBJECT + next++);
      const uint32_t end = p + 1 < ncut ? cut[p + 1] : n;
      for (uint32_t i = cut[p]; i < end; i++) s->label[(v[i].rc >> 16) * cols + (v[i].rc & 0xffff)] = id;
    }
  }
  st->clusters = next;
}

/* ---- DBSCAN in 3-D on a voxel hash grid ---- */

static inline uint32_t voxel_hash(int x, int y, int z) {
  uint32_t h = (uint32_t)x * 73856093u ^ (uint32_t)y * 19349663u ^ (uint32_t)z * 83492791u;
  return h & (RS_GRID_BUCKETS - 1);
}

/* points within eps of point k (itself included) */
static uint32_t region_count(const rs_cluster_t *c, uint32_t k, float eps) {
  const float x = c->px[k], y = c->py[k], z = c->pz[k], e2 = eps * eps;
  const int ix = (int)floorf(x / eps), iy = (int)floorf(y / eps), iz = (int)floorf(z / eps);
  uint32_t n = 0;
  for (int dx = -1; dx <= 1; dx++)
    for (int dy = -1; dy <= 1; dy++)
      for (int dz = -1; dz <= 1; dz++)
        for (int32_t j = c->heads[voxel_hash(ix + dx, iy + dy, iz + dz)]; j >= 0; j = c->next[j]) {
          float ax = c->px[j] - x, ay = c->py[j] - y, az = c->pz[j] - z;
          if (ax * ax + ay * ay + az * az > e2) continue;
          n++;
        }
  return n;
}

static void dbscan(rs_cluster_t *c, rs_slot_t *s, uint32_t nfg, rs_cluster_stats_t *st) {
  const int cols = s->meta.cols;
  const rs_sensor_t *sen = c->sensor;
  const float eps = c->cfg.dbscan.eps;
  for (int b = 0; b < RS_GRID_BUCKETS; b++) c->heads[b] = -1;
  for (uint32_t k = 0; k < nfg; k++) {
    const uint32_t i = c->fg[k];
    const int r = (int)(c->fgrc[k] >> 16), col = (int)(c->fgrc[k] & 0xffff);
    int laser = sen->laser_of_row[r];
    float range = c->rr[i], az = (float)((col + 0.5) * 2.0 * 3.14159265358979323846 / cols);
    float xy = range * sen->cos_el[laser];
    c->px[k] = xy * sinf(az);
    c->py[k] = xy * cosf(az);
    c->pz[k] = range * sen->sin_el[laser];
    uint32_t h = voxel_hash((int)floorf(c->px[k] / eps), (int)floorf(c->py[k] / eps), (int)floorf(c->pz[k] / eps));
    c->next[k] = c->heads[h];
    c->heads[h] = (int32_t)k;
  }
  for (uint32_t k = 0; k < nfg; k++) c->core[k] = region_count(c, k, eps) >= (uint32_t)c->cfg.dbscan.min_pts;
  /* labels by point index in queue order; cluster ids written to the slot */
  uint32_t ncl = 0;
  for (uint32_t k = 0; k < nfg; k++) {
    if (!c->core[k] || s->label[c->fg[k]] != 2) continue;
    if (ncl >= RS_MAX_CLUSTERS) {
      st->overflow++;
      continue;
    }
    const uint16_t id = (uint16_t)(3 + ncl++);
    uint32_t head = 0, tail = 0;
    c->queue[tail++] = k;
    s->label[c->fg[k]] = id;
    while (head < tail) {
      uint32_t q = c->queue[head++];
      const float x = c->px[q], y = c->py[q], z = c->pz[q], e2 = eps * eps;
      const int ix = (int)floorf(x / eps), iy = (int)floorf(y / eps), iz = (int)floorf(z / eps);
      for (int dx = -1; dx <= 1; dx++)
        for (int dy = -1; dy <= 1; dy++)
          for (int dz = -1; dz <= 1; dz++)
            for (int32_t j = c->heads[voxel_hash(ix + dx, iy + dy, iz + dz)]; j >= 0; j = c->next[j]) {
              float ax = c->px[j] - x, ay = c->py[j] - y, az = c->pz[j] - z;
              if (ax * ax + ay * ay + az * az > e2 || s->label[c->fg[j]] != 2) continue;
              s->label[c->fg[j]] = id;
              if (c->core[j]) c->queue[tail++] = (uint32_t)j;
            }
    }
  }
  st->clusters = ncl;
}

void rs_cluster_run(rs_cluster_t *c, rs_slot_t *s, rs_cluster_stats_t *st) {
  memset(st, 0, sizeof *st);
  uint32_t nfg;
  prepare(c, s, &nfg);
  st->foreground = nfg;
  switch (c->cfg.method) {
  case RS_CLUSTER_FSPC:
  case RS_CLUSTER_FSPC_ADAPTIVE:
    /* the adaptive run takes window, eps and minPts per row and range from its tables */
    fspc(c, s, nfg, c->cfg.method == RS_CLUSTER_FSPC_ADAPTIVE, c->cfg.fspc.win_h / 2, c->cfg.fspc.win_w / 2,
         c->cfg.fspc.eps, c->cfg.fspc.min_pts, st);
    if (c->cfg.method == RS_CLUSTER_FSPC_ADAPTIVE) split(c, s, nfg, st);
    break;
  case RS_CLUSTER_DBSCAN: dbscan(c, s, nfg, st); break;
  case RS_CLUSTER_CCL: fspc(c, s, nfg, false, 1, 1, c->cfg.ccl.eps, 1, st); break;
  default: break;
  }
  for (uint32_t k = 0; k < nfg; k++) {
    if (s->label[c->fg[k]] >= 3) st->clustered++;
    else st->noise++;
  }
  c->overflow_total += st->overflow;
  /* dual return: the second layer follows the first where the ranges agree
   * within the method's own eps (the adaptive one by row and range); then
   * every clustered cell, layer by layer, row-major, for the object stage */
  const uint32_t cols = s->meta.cols, cells = (uint32_t)s->meta.rows * cols;
  const rs_cluster_method_t m = c->cfg.method;
  const float eps = m == RS_CLUSTER_DBSCAN ? c->cfg.dbscan.eps : (m == RS_CLUSTER_CCL ? c->cfg.ccl.eps : c->cfg.fspc.eps);
  uint32_t nm = 0;
  for (uint32_t k = 0; k < nfg; k++)
    if (s->label[c->fg[k]] >= RS_LABEL_FIRST_OBJECT) c->members[nm++] = c->fg[k];
  for (uint32_t i = 0; i < cells; i++) {
    uint32_t j = RS_MAX_CELLS + i;
    float r = s->range[j];
    if (r <= 0.0f || s->label[j] == RS_LABEL_STATIC) continue;
    uint16_t l0 = s->label[i];
    float e = eps;
    if (m == RS_CLUSTER_FSPC_ADAPTIVE && l0 >= RS_LABEL_FIRST_OBJECT) e = c->eps_tab[i / cols][bin_of(s->range[i])];
    s->label[j] = (uint16_t)((l0 >= RS_LABEL_FIRST_OBJECT && fabsf(s->range[i] - r) < e) ? l0 : RS_LABEL_NOISE);
    if (s->label[j] >= RS_LABEL_FIRST_OBJECT) c->members[nm++] = j;
  }
  c->nmembers = nm;
}

/* objects.c - cluster attributes (processing thread; no allocation).
 *
 * One column-major pass over the map: per object, sums and extremes in the
 * sensor frame (and the site frame with a pose), and per (object, column)
 * the nearest and farthest ground-plane point from the sensor, which become
 * hull candidates. A counting sort groups candidates by object; each
 * object's hull (monotone chain) gives the orientations its rectangle may take. */
#include "roadscan/perception/objects.h"

#include "roadscan/output/labels.h"
#include "roadscan/util/sort.h"

#include <math.h>
#include <string.h>

#define PI 3.14159265358979323846

void rs_pose_rotation(const rs_pose_t *pose, double r[9]) {
  const double cr = cos(pose->roll), sr = sin(pose->roll), cp = cos(pose->pitch), sp = sin(pose->pitch);
  const double cy = cos(pose->yaw), sy = sin(pose->yaw);
  const double m[9] = {cy * cp, cy * sp * sr - sy * cr, cy * sp * cr + sy * sr,
                       sy * cp, sy * sp * sr + cy * cr, sy * sp * cr - cy * sr,
                       -sp,     cp * sr,                cp * cr};
  memcpy(r, m, sizeof m);
}

void rs_objects_init(rs_objects_t *o, const rs_pose_t *pose) {
  memset(o->stamp, 0xff, sizeof o->stamp);
  o->trig_cols = 0;
  o->ground = NULL;
  o->have_pose = pose != NULL;
  if (!pose) return;
  double r[9];
  rs_pose_rotation(pose, r);
  for (int i = 0; i < 9; i++) o->rot[i] = (float)r[i];
  o->trans[0] = (float)pose->x;
  o->trans[1] = (float)pose->y;
  o->trans[2] = (float)pose->z;
}

/* min and max without NaN handling: no NaN reaches them, and fminf is a call */
static inline float mn(float a, float b) { return a < b ? a : b; }
static inline float mx(float a, float b) { return a > b ? a : b; }

static int cmp_xy(const void *a, const void *b) {
  const float *p = a, *q = b;
  if (p[0] != q[0]) return p[0] < q[0] ? -1 : 1;
  return (p[1] > q[1]) - (p[1] < q[1]);
}

static float cross(const float *o, const float *a, const float *b) {
  return (a[0] - o[0]) * (b[1] - o[1]) - (a[1] - o[1]) * (b[0] - o[0]);
}

/* Convex hull (Andrew's monotone chain) of n sorted points, counter-clockwise,
 * into h; returns the vertex count. */
static uint32_t hull_of(float (*pts)[2], uint32_t n, float (*h)[2]) {
  if (n < 3) {
    for (uint32_t i = 0; i < n; i++) memcpy(h[i], pts[i], sizeof h[i]);
    return n;
  }
  uint32_t k = 0;
  for (uint32_t i = 0; i < n; i++) {
    while (k >= 2 && cross(h[k - 2], h[k - 1], pts[i]) <= 0) k--;
    memcpy(h[k++], pts[i], sizeof h[0]);
  }
  for (uint32_t i = n - 1, t = k + 1; i-- > 0;) {
    while (k >= t && cross(h[k - 2], h[k - 1], pts[i]) <= 0) k--;
    memcpy(h[k++], pts[i], sizeof h[0]);
  }
  return k - 1;
}

/* Bounds of pts along u = (ux, uy) and v = (-uy, ux). */
static void bounds(float (*pts)[2], uint32_t n, float ux, float uy, float b[4]) {
  b[0] = b[2] = INFINITY;
  b[1] = b[3] = -INFINITY;
  for (uint32_t j = 0; j < n; j++) {
    float pu = pts[j][0] * ux + pts[j][1] * uy, pv = -pts[j][0] * uy + pts[j][1] * ux;
    b[0] = mn(b[0], pu);
    b[1] = mx(b[1], pu);
    b[2] = mn(b[2], pv);
    b[3] = mx(b[3], pv);
  }
}

/* The rectangle around the object: its orientation is one of the hull's
 * edge directions, the one whose rectangle the points hug closest (mean
 * distance to the nearest side; a minimum-area criterion cannot tell an
 * L-shaped view of a car from its diagonal), then the smaller area. Returns
 * true when edges were skipped. */
static bool fit_rect(float (*h)[2], uint32_t nh, float (*pts)[2], uint32_t n, rs_obj_geom_t *g) {
  g->obb_center[0] = h[0][0];
  g->obb_center[1] = h[0][1];
  g->obb_length = g->obb_width = g->obb_heading = 0.0f;
  if (nh < 2) return false;
  uint32_t step = nh > RS_OBJ_HULL_EDGES ? (nh + RS_OBJ_HULL_EDGES - 1) / RS_OBJ_HULL_EDGES : 1;
  float best = INFINITY, best_area = INFINITY;
  for (uint32_t i = 0; i < nh; i += step) {
    const float *a = h[i], *b = h[(i + 1) % nh];
    float ux = b[0] - a[0], uy = b[1] - a[1], len = sqrtf(ux * ux + uy * uy);
    if (len <= 0.0f) continue;
    ux /= len;
    uy /= len;
    float bd[4];
    bounds(h, nh, ux, uy, bd);
    float close = 0.0f;
    for (uint32_t j = 0; j < n; j++) {
      float pu = pts[j][0] * ux + pts[j][1] * uy, pv = -pts[j][0] * uy + pts[j][1] * ux;
      close += mn(mn(pu - bd[0], bd[1] - pu), mn(pv - bd[2], bd[3] - pv));
    }
    close /= (float)n;
    float area = (bd[1] - bd[0]) * (bd[3] - bd[2]);
    if (close < best - 1e-3f || (close < best + 1e-3f && area < best_area)) {
      best = fminf(best, close);
      best_area = area;
      float cu = 0.5f * (bd[0] + bd[1]), cv = 0.5f * (bd[2] + bd[3]);
      g->obb_center[0] = cu * ux - cv * uy;
      g->obb_center[1] = cu * uy + cv * ux;
      float du = bd[1] - bd[0], dv = bd[3] - bd[2];
      float head = du >= dv ? atan2f(uy, ux) : atan2f(ux, -uy);
      g->obb_length = fmaxf(du, dv);
      g->obb_width = fminf(du, dv);
      if (head > (float)(PI / 2)) head -= (float)PI;
      if (head <= (float)(-PI / 2)) head += (float)PI;
      g->obb_heading = head;
    }
  }
  return step > 1;
}

static void add_point(rs_objects_t *o, int f, uint32_t k, const float p[3], float ox, float oy, rs_obj_geom_t *g,
                      bool first, uint32_t col) {
  for (int a = 0; a < 3; a++) {
    o->sum[f][k][a] += p[a];
    if (first || p[a] < g->box_min[a]) g->box_min[a] = p[a];
    if (first || p[a] > g->box_max[a]) g->box_max[a] = p[a];
  }
  float dx = p[0] - ox, dy = p[1] - oy, d = dx * dx + dy * dy;
  if (o->stamp[k] != col || d < o->dmin[f][k]) {
    o->dmin[f][k] = d;
    o->pmin[f][k][0] = p[0];
    o->pmin[f][k][1] = p[1];
  }
  if (o->stamp[k] != col || d > o->dmax[f][k]) {
    o->dmax[f][k] = d;
    o->pmax[f][k][0] = p[0];
    o->pmax[f][k][1] = p[1];
  }
}

/* Is object k (label k + 3) hidden beside its edge column ce, looking
 * dir (-1: before, +1: after)? Per row with a return of it in ce, the
 * nearest return of anything else in the two columns beyond (either layer,
 * the seam wrapped); RS_OBJ_HIDDEN_ROWS such rows nearer by RS_OBJ_HIDDEN_M
 * (or every row, when fewer were compared) make it so. Bounded by the
 * object's rows. */
static bool hidden_beside(const rs_slot_t *s, const rs_object_t *ob, uint32_t k, int ce, int dir) {
  const int cols = s->meta.cols;
  const uint16_t lab = (uint16_t)(k + 3u);
  int compared = 0, nearer = 0;
  for (int r = ob->row_min; r <= ob->row_max; r++) {
    float ro = INFINITY, rn = INFINITY;
    for (int l = 0; l < RS_LAYERS; l++) {
      const uint32_t i = rs_cell(s, l, r, ce);
      if (s->label[i] == lab && s->range[i] != 0.0f) ro = mn(ro, s->range[i]);
      for (int d = 1; d <= 2; d++) {
        const int c = ((ce + dir * d) % cols + cols) % cols;
        const uint32_t j = rs_cell(s, l, r, c);
        if (s->label[j] != lab && s->range[j] != 0.0f) rn = mn(rn, s->range[j]);
      }
    }
    if (ro == INFINITY) continue;
    compared++;
    if (rn < ro - RS_OBJ_HIDDEN_M) nearer++;
  }
  return nearer >= RS_OBJ_HIDDEN_ROWS || (nearer > 0 && nearer == compared);
}

static void push_cand(rs_objects_t *o, int f, uint16_t k, const float *p, bool *lost) {
  if (o->ncand[f] >= RS_OBJ_CANDIDATES) {
    lost[k] = true;
    return;
  }
  o->cand[f][o->ncand[f]].x = p[0];
  o->cand[f][o->ncand[f]].y = p[1];
  o->cand[f][o->ncand[f]].obj = k;
  o->ncand[f]++;
}

/* Groups frame f's candidates by object (counting sort) and fits each box. */
static void fit_boxes(rs_objects_t *o, int f, rs_object_list_t *out, uint32_t nobj) {
  memset(o->start, 0, sizeof(uint32_t) * (nobj + 1));
  for (uint32_t i = 0; i < o->ncand[f]; i++) o->start[o->cand[f][i].obj + 1]++;
  for (uint32_t k = 0; k < nobj; k++) o->start[k + 1] += o->start[k];
  for (uint32_t i = 0; i < o->ncand[f]; i++) {
    uint32_t at = o->start[o->cand[f][i].obj]++;
    o->sorted[at][0] = o->cand[f][i].x;
    o->sorted[at][1] = o->cand[f][i].y;
  }
  /* start[k] is now the end of object k */
  for (uint32_t k = 0, begin = 0; k < nobj; begin = o->start[k], k++) {
    uint32_t n = o->start[k] - begin;
    if (out->obj[k].points == 0 || n == 0) continue;
    rs_sort(o->sorted + begin, n, sizeof o->sorted[0], cmp_xy);
    uint32_t h = hull_of(o->sorted + begin, n, o->hull);
    rs_obj_geom_t *g = f == 0 ? &out->obj[k].sensor : &out->obj[k].site;
    if (fit_rect(o->hull, h, o->sorted + begin, n, g)) out->approx_boxes++;
  }
}

/* The map's object cells (labels 3+ with a return), layer 0 then 1, row-major. */
static uint32_t object_cells(const rs_slot_t *s, uint32_t *cells) {
  const int rows = s->meta.rows, cols = s->meta.cols;
  uint32_t n = 0;
  for (int l = 0; l < RS_LAYERS; l++)
    for (int r = 0; r < rows; r++) {
      const uint32_t row0 = rs_cell(s, l, r, 0);
      for (int c = 0; c < cols; c++)
        if (s->label[row0 + (uint32_t)c] >= RS_LABEL_FIRST_OBJECT && s->range[row0 + (uint32_t)c] != 0.0f)
          cells[n++] = row0 + (uint32_t)c;
    }
  return n;
}

/* o->unmeasured: the map columns more than half the rows did not measure (rs_object_list_t.gap): row r's
 * return in map column c is of block column c - its laser's azimuth offset. The rows are grouped by
 * offset (one group for a VLP-16 or an HDL-32E, four for a VLP-32C, eight for a VLS-128): one pass over
 * the block columns when the frame has none unmeasured, else one read per column and group */
static void unmeasured_columns(rs_objects_t *o, const rs_slot_t *s, const rs_sensor_t *sen) {
  const int rows = s->meta.rows < RS_MAX_ROWS ? s->meta.rows : RS_MAX_ROWS, cols = s->meta.cols;
  bool any = false;
  for (int c = 0; c < cols && !any; c++) any = s->gap[c] != 0;
  memset(o->unmeasured, 0, (size_t)cols);
  if (!any || rows <= 0) return;
  int shift[RS_MAX_ROWS], count[RS_MAX_ROWS], ng = 0; /* the groups: their offset in columns, their rows */
  for (int r = 0; r < rows; r++) {
    const int sh = r < sen->lasers ? (int)lround(sen->azimuth_offset_deg[sen->laser_of_row[r]] * cols / 360.0) : 0;
    int g = 0;
    while (g < ng && shift[g] != sh) g++;
    if (g == ng) {
      shift[ng] = sh;
      count[ng++] = 0;
    }
    count[g]++;
  }
  for (int c = 0; c < cols; c++) {
    int n = 0;
    for (int g = 0; g < ng; g++) n += s->gap[((c - shift[g]) % cols + cols) % cols] != 0 ? count[g] : 0;
    o->unmeasured[c] = 2 * n > rows;
  }
}

bool rs_objects_unmeasured_at(const rs_object_list_t *l, double x, double y) {
  if (l->ngaps == 0 || l->gap_cols == 0) return false;
  double az = atan2(x, y);
  if (!isfinite(az)) return false; /* (a NaN cast to a column is undefined) */
  if (az < 0) az += 2.0 * PI;
  int c = (int)(az * l->gap_cols / (2.0 * PI));
  if (c >= l->gap_cols) c = l->gap_cols - 1; /* (az rounded up to 2 pi) */
  for (uint32_t k = 0; k < l->ngaps && k < RS_OBJ_GAPS_MAX; k++)
    if (c >= l->gap[k][0] && c <= l->gap[k][1]) return true;
  return false;
}

void rs_objects_extract(rs_objects_t *o, const rs_slot_t *s, const rs_sensor_t *sen, rs_object_list_t *out) {
  uint32_t n = object_cells(s, o->cells);
  rs_objects_extract_cells(o, s, sen, o->cells, n, out);
}

void rs_objects_extract_cells(rs_objects_t *o, const rs_slot_t *s, const rs_sensor_t *sen, const uint32_t *list,
                              uint32_t nlist, rs_object_list_t *out) {
  const int rows = s->meta.rows, cols = s->meta.cols;
  const int nf = o->have_pose ? 2 : 1;
  out->site_valid = o->have_pose;
  out->candidates_overflow = out->approx_boxes = 0;
  out->lowest_beam_deg = sen->lasers > 0 ? sen->elevation_deg[sen->laser_of_row[0]] : 0.0f; /* row 0: the lowest */
  out->gap_cols = (uint16_t)cols;
  out->ngaps = 0;
  out->gaps_dropped = 0;
  unmeasured_columns(o, s, sen);
  const uint8_t *un = o->unmeasured;
  for (int c = 0; c < cols; c++) { /* their runs, one pass */
    if (!un[c]) continue;
    const int first = c;
    while (c + 1 < cols && un[c + 1]) c++;
    if (out->ngaps < RS_OBJ_GAPS_MAX) {
      out->gap[out->ngaps][0] = (uint16_t)first;
      out->gap[out->ngaps][1] = (uint16_t)c;
      out->ngaps++;
    } else {
      out->gaps_dropped++;
    }
  }
  if (o->trig_cols != cols) {
    for (int c = 0; c < cols; c++) {
      double az = (c + 0.5) * 2.0 * PI / cols;
      o->col_sin[c] = (float)sin(az);
      o->col_cos[c] = (float)cos(az);
    }
    o->trig_cols = cols;
  }
  /* pass 1 over the listed cells: the number of objects, the cells per column */
  uint32_t nobj = 0, ncells = 0;
  memset(o->col_start_idx, 0, sizeof(uint32_t) * ((size_t)cols + 1));
  const uint32_t limit = RS_LAYERS * RS_MAX_CELLS, rowcells = (uint32_t)rows * (uint32_t)cols;
  for (uint32_t j = 0; j < nlist && j < limit; j++) {
    const uint32_t i = list[j];
    if (i >= limit || i % RS_MAX_CELLS >= rowcells) continue;
    const uint16_t lab = s->label[i];
    if (lab < RS_LABEL_FIRST_OBJECT || s->range[i] == 0.0f || lab - 3u >= RS_OBJ_MAX) continue;
    if (lab - 2u > nobj) nobj = lab - 2u;
    o->cells[ncells++] = i; /* ncells <= j: a list that is o->cells is compacted in place */
    o->col_start_idx[(i % RS_MAX_CELLS) % (uint32_t)cols + 1]++;
  }
  for (int c = 0; c < cols; c++) o->col_start_idx[c + 1] += o->col_start_idx[c];
  for (uint32_t j = 0; j < ncells; j++) {
    uint32_t i = o->cells[j], c = (i % RS_MAX_CELLS) % (uint32_t)cols;
    o->bycol[o->col_start_idx[c]++] = i;
  }
  /* col_start_idx[c] is now the end of column c */
  out->count = nobj;
  memset(out->obj, 0, sizeof(rs_object_t) * nobj);
  memset(o->sum, 0, sizeof(o->sum[0][0]) * nobj);
  memset(o->sum[1], 0, sizeof(o->sum[1][0]) * nobj);
  for (uint32_t k = 0; k < nobj; k++) {
    o->stamp[k] = UINT32_MAX;
    o->isum[k] = 0.0;
    out->obj[k].id = k + 1;
  }
  o->ncand[0] = o->ncand[1] = 0;
  bool lost[RS_OBJ_MAX];
  memset(lost, 0, sizeof(bool) * nobj);
  const float ox[2] = {0.0f, o->trans[0]}, oy[2] = {0.0f, o->trans[1]};
  const uint32_t half = (uint32_t)cols / 2u;
  /* pass 2, column by column over the object cells only */
  for (int c = 0, begin = 0; c < cols; begin = (int)o->col_start_idx[c], c++) {
    int nt = 0;
    for (uint32_t j = (uint32_t)begin; j < o->col_start_idx[c]; j++) {
      const uint32_t i = o->bycol[j];
      const int r = (int)((i % RS_MAX_CELLS) / (uint32_t)cols);
      const uint32_t k = s->label[i] - 3u;
      rs_object_t *ob = &out->obj[k];
      bool first = ob->points == 0;
      float p[2][3] = {{0}};
      const int laser = sen->laser_of_row[r];
      rs_objects_xy(o, s, sen, i, p[0]);
      const float range = s->range[i];
      p[0][2] = range * sen->sin_el[laser] + sen->vert_offset_m[laser];
      if (nf == 2) {
        for (int a = 0; a < 3; a++)
          p[1][a] = o->rot[3 * a] * p[0][0] + o->rot[3 * a + 1] * p[0][1] + o->rot[3 * a + 2] * p[0][2] + o->trans[a];
      }
      add_point(o, 0, k, p[0], ox[0], oy[0], &ob->sensor, first, (uint32_t)c);
      if (nf == 2) add_point(o, 1, k, p[1], ox[1], oy[1], &ob->site, first, (uint32_t)c);
      if (o->stamp[k] != (uint32_t)c) {
        o->stamp[k] = (uint32_t)c;
        o->touched[nt++] = (uint16_t)k;
      }
      o->isum[k] += s->intensity[i];
      uint32_t pk = s->addr[i].packet;
      if (first || range < ob->range_min) ob->range_min = range;
      if (first || pk < o->first_pkt[k]) o->first_pkt[k] = pk;
      if (first || pk > o->last_pkt[k]) o->last_pkt[k] = pk;
      if (first || r < ob->row_min) ob->row_min = (uint16_t)r;
      if (first || r > ob->row_max) ob->row_max = (uint16_t)r;
      uint16_t *cl = o->col_lo_hi[k];
      if (first) {
        cl[0] = (uint16_t)c;
        cl[2] = UINT16_MAX;
        cl[3] = 0;
      }
      cl[1] = (uint16_t)c; /* columns come in order */
      if ((uint32_t)c >= half && cl[2] == UINT16_MAX) cl[2] = (uint16_t)c;
      if ((uint32_t)c < half) cl[3] = (uint16_t)c;
      ob->points++;
    }
    for (int t = 0; t < nt; t++) {
      uint16_t k = o->touched[t];
      for (int f = 0; f < nf; f++) {
        push_cand(o, f, k, o->pmin[f][k], lost);
        if (o->dmax[f][k] > o->dmin[f][k]) push_cand(o, f, k, o->pmax[f][k], lost);
      }
    }
  }
  const double t0 = s->meta.t_first, t1 = s->meta.t_last;
  const double p0 = s->meta.first_packet, dp = (double)s->meta.last_packet - p0;
  for (uint32_t k = 0; k < nobj; k++) {
    rs_object_t *ob = &out->obj[k];
    if (ob->points == 0) continue;
    if (lost[k]) out->candidates_overflow++;
    for (int f = 0; f < nf; f++) {
      rs_obj_geom_t *g = f == 0 ? &ob->sensor : &ob->site;
      for (int a = 0; a < 3; a++) g->centroid[a] = (float)(o->sum[f][k][a] / ob->points);
    }
    ob->intensity_mean = (float)(o->isum[k] / ob->points);
    float gz;
    ob->top_agl = rs_ground_at(o->ground, ob->sensor.centroid[0], ob->sensor.centroid[1], &gz)
                      ? fmaxf(ob->sensor.box_max[2] - gz, 0.0f)
                      : 0.0f;
    /* a sparse sensor at range passes over a head and under a bumper: the
     * rows next to the object's bound how much of it they missed */
    {
      const int top = ob->row_max, bot = ob->row_min;
      const double rr = ob->range_min;
      double gap = 0.0;
      ob->top_gap = -1.0f;
      if (top + 1 < (int)sen->lasers) {
        gap += rr * (tan(sen->elevation_deg[sen->laser_of_row[top + 1]] * (PI / 180.0)) -
                     tan(sen->elevation_deg[sen->laser_of_row[top]] * (PI / 180.0)));
        ob->top_gap = (float)fmax(gap, 0.0);
      }
      if (bot > 0)
        gap += rr * (tan(sen->elevation_deg[sen->laser_of_row[bot]] * (PI / 180.0)) -
                     tan(sen->elevation_deg[sen->laser_of_row[bot - 1]] * (PI / 180.0)));
      ob->height_gap = (float)(gap > 0 ? gap : 0.0);
    }
    ob->t_first = dp > 0 ? t0 + ((double)o->first_pkt[k] - p0) / dp * (t1 - t0) : t0;
    ob->t_last = dp > 0 ? t0 + ((double)o->last_pkt[k] - p0) / dp * (t1 - t0) : t1;
    const uint16_t *cl = o->col_lo_hi[k];
    if (cl[1] - cl[0] > (int)half && cl[2] != UINT16_MAX) {
      /* across the seam: from the first column of the upper half to the last of the lower */
      ob->col_start = cl[2];
      ob->col_end = cl[3];
    } else {
      ob->col_start = cl[0];
      ob->col_end = cl[1];
    }
    if (hidden_beside(s, ob, k, ob->col_start, -1)) ob->occluded |= RS_OBJ_HIDDEN_START;
    if (hidden_beside(s, ob, k, ob->col_end, +1)) ob->occluded |= RS_OBJ_HIDDEN_END;
    ob->az_start = (float)(ob->col_start * 360.0 / cols);
    ob->az_end = (float)((ob->col_end + 1) * 360.0 / cols);
    if (ob->az_end >= 360.0f) ob->az_end -= 360.0f;
  }
  for (int f = 0; f < nf; f++) fit_boxes(o, f, out, nobj);
}

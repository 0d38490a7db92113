/* ground.c - the ground's height under a place, from a background model
 * (processing thread; no allocation; the design is in ground.h). */
#include "roadscan/perception/ground.h"

#include "roadscan/util/rand.h"
#include "roadscan/util/sort.h"

#include <math.h>
#include <stdio.h>
#include <string.h>

#define PI 3.14159265358979323846

static int cell_of(double x, double y) {
  const double fx = floor(x / RS_GROUND_CELL_M) + RS_GROUND_HALF, fy = floor(y / RS_GROUND_CELL_M) + RS_GROUND_HALF;
  if (!(fx >= 0 && fx < RS_GROUND_N && fy >= 0 && fy < RS_GROUND_N)) return -1;
  return (int)fy * RS_GROUND_N + (int)fx;
}

static void add_point(rs_ground_t *g, int c, float z) {
  const int k = g->n[c] < RS_GROUND_KTH ? g->n[c] : RS_GROUND_KTH;
  if (k == RS_GROUND_KTH && z >= g->low[c][k - 1]) {
    if (g->n[c] < UINT16_MAX) g->n[c]++;
    return;
  }
  int j = k == RS_GROUND_KTH ? k - 1 : k; /* insertion into the ascending k lowest */
  while (j > 0 && g->low[c][j - 1] > z) {
    g->low[c][j] = g->low[c][j - 1];
    j--;
  }
  g->low[c][j] = z;
  if (g->n[c] < UINT16_MAX) g->n[c]++;
}

static int cmp_float(const void *a, const void *b) {
  const float x = *(const float *)a, y = *(const float *)b;
  return (x > y) - (x < y);
}

/* the cells of the 3 x 3 window about cell c (c included) whose ground is known, into at; how many */
static int known_around(const float *z, int c, int at[9]) {
  const int cx = c % RS_GROUND_N, cy = c / RS_GROUND_N;
  int n = 0;
  for (int dy = -1; dy <= 1; dy++)
    for (int dx = -1; dx <= 1; dx++) {
      const int x = cx + dx, y = cy + dy;
      if (x >= 0 && y >= 0 && x < RS_GROUND_N && y < RS_GROUND_N && !isnan(z[y * RS_GROUND_N + x]))
        at[n++] = y * RS_GROUND_N + x;
    }
  return n;
}

static double cell_x(int c) { return ((c % RS_GROUND_N) - RS_GROUND_HALF + 0.5) * RS_GROUND_CELL_M; }
static double cell_y(int c) { return ((c / RS_GROUND_N) - RS_GROUND_HALF + 0.5) * RS_GROUND_CELL_M; }

static double plane_of(const double p[3], int c) { return p[0] + p[1] * cell_x(c) + p[2] * cell_y(c); }
static double plane_at(const rs_ground_t *g, int c) { return plane_of(g->plane, c); }
/* within RS_GROUND_NEAR_M of the sensor: the cells the plane is drawn from and judged by */
static bool near_cell(int c) { return hypot(cell_x(c), cell_y(c)) <= RS_GROUND_NEAR_M; }
/* every cell not known */
static void forget(rs_ground_t *g) {
  for (int c = 0; c < RS_GROUND_N * RS_GROUND_N; c++) g->z[c] = NAN;
}

/* the plane z = q0 + q1 x + q2 y through three cells' ground; false when they are (nearly) on a line */
static bool plane_through(const rs_ground_t *g, const int c[3], double q[3]) {
  const double x0 = cell_x(c[0]), y0 = cell_y(c[0]), z0 = g->z[c[0]];
  const double ax = cell_x(c[1]) - x0, ay = cell_y(c[1]) - y0, az = g->z[c[1]] - z0;
  const double bx = cell_x(c[2]) - x0, by = cell_y(c[2]) - y0, bz = g->z[c[2]] - z0;
  const double det = ax * by - ay * bx;
  if (fabs(det) < 4.0 * RS_GROUND_CELL_M * RS_GROUND_CELL_M) return false;
  q[1] = (az * by - ay * bz) / det;
  q[2] = (ax * bz - az * bx) / det;
  q[0] = z0 - q[1] * x0 - q[2] * y0;
  return true;
}

/* least squares z = a + b x + c y over the known cells (within tol of plane p when p is given) */
static bool fit_plane(const rs_ground_t *g, const double *p, double tol, double out[3]) {
  double s[3][3] = {{0}}, r[3] = {0};
  uint32_t n = 0;
  for (int c = 0; c < RS_GROUND_N * RS_GROUND_N; c++) {
    if (isnan(g->z[c])) continue;
    const double x = cell_x(c), y = cell_y(c), z = g->z[c];
    if (p && fabs(z - plane_of(p, c)) > tol) continue;
    const double v[3] = {1.0, x, y};
    for (int i = 0; i < 3; i++) {
      for (int j = 0; j < 3; j++) s[i][j] += v[i] * v[j];
      r[i] += v[i] * z;
    }
    n++;
  }
  if (n < RS_GROUND_MIN_CELLS) return false;
  /* Gaussian elimination with partial pivoting on the 3 x 3 normal equations */
  double a[3][4];
  for (int i = 0; i < 3; i++) {
    for (int j = 0; j < 3; j++) a[i][j] = s[i][j];
    a[i][3] = r[i];
  }
  for (int col = 0; col < 3; col++) {
    int piv = col;
    for (int i = col + 1; i < 3; i++)
      if (fabs(a[i][col]) > fabs(a[piv][col])) piv = i;
    if (fabs(a[piv][col]) < 1e-9) return false; /* the cells on a line: no plane */
    if (piv != col)
      for (int j = 0; j < 4; j++) {
        const double t = a[col][j];
        a[col][j] = a[piv][j];
        a[piv][j] = t;
      }
    for (int i = 0; i < 3; i++) {
      if (i == col) continue;
      const double f = a[i][col] / a[col][col];
      for (int j = col; j < 4; j++) a[i][j] -= f * a[col][j];
    }
  }
  for (int i = 0; i < 3; i++) out[i] = a[i][3] / a[i][i];
  return true;
}

void rs_ground_build(rs_ground_t *g, const rs_bg_model_t *m, const rs_sensor_t *sen) {
  const int ncell = RS_GROUND_N * RS_GROUND_N;
  g->valid = false;
  g->on_plane = 0.0;
  memset(g->plane, 0, sizeof g->plane);
  g->cells_kept = g->cells_filled = g->cells_plane = 0;
  memset(g->n, 0, sizeof g->n);
  forget(g);
  if (m == NULL || sen == NULL || m->n == NULL || m->rows != sen->lasers || m->rows == 0 || m->cols == 0) return;
  /* every static surface of every map cell: a point */
  for (int col = 0; col < m->cols; col++) {
    const double az = (col + 0.5) * 2.0 * PI / m->cols, sa = sin(az), ca = cos(az);
    for (int row = 0; row < m->rows; row++) {
      const int laser = sen->laser_of_row[row];
      const double ce = sen->cos_el[laser], se = sen->sin_el[laser], vo = sen->vert_offset_m[laser];
      const uint32_t cell = (uint32_t)row * m->cols + (uint32_t)col, b = cell * RS_BG_SURFACES;
      for (int k = 0; k < m->n[cell] && k < RS_BG_SURFACES; k++) {
        if (m->hi[b + k] == RS_BG_BEYOND) continue;
        const double r = (m->lo[b + k] + m->hi[b + k]) / 200.0;
        const int gc = cell_of(r * ce * sa, r * ce * ca);
        if (gc >= 0) add_point(g, gc, (float)(r * se + vo));
      }
    }
  }
  for (int c = 0; c < ncell; c++)
    if (g->n[c] >= RS_GROUND_KTH) g->z[c] = g->low[c][RS_GROUND_KTH - 1];
  /* the 3 x 3 median of the kept cells */
  for (int c = 0; c < ncell; c++) {
    g->tmp[c] = g->z[c];
    if (isnan(g->z[c])) continue;
    int at[9];
    float v[9];
    const int nv = known_around(g->z, c, at);
    for (int i = 0; i < nv; i++) v[i] = g->z[at[i]];
    if (nv < 3) continue;
    rs_sort(v, (size_t)nv, sizeof v[0], cmp_float);
    g->tmp[c] = nv % 2 ? v[nv / 2] : 0.5f * (v[nv / 2 - 1] + v[nv / 2]);
  }
  memcpy(g->z, g->tmp, sizeof g->z);
  for (int c = 0; c < ncell; c++) g->cells_kept += !isnan(g->z[c]);
  if (g->cells_kept < RS_GROUND_MIN_CELLS) {
    forget(g);
    return;
  }
  /* the plane: the one through three near cells below the sensor that most near cells lie on (RANSAC, a fixed
   * sequence of draws: the same model gives the same ground), no steeper than RS_GROUND_STEEP_DEG and at least
   * RS_GROUND_BELOW_M below the sensor; then least squares over the cells near it, the band narrowing to
   * RS_GROUND_PLANE_TOL (walls, trees, roofs stay out; a tilted sensor's or a sloping road's ground is a plane
   * like a level one) */
  const double steep = tan(RS_GROUND_STEEP_DEG * PI / 180.0);
  bool have_plane = false;
  {
    uint32_t nn = 0;
    for (int c = 0; c < ncell; c++)
      if (!isnan(g->z[c]) && g->z[c] <= -RS_GROUND_BELOW_M && near_cell(c)) g->near[nn++] = (uint16_t)c;
    uint64_t rng = 0x9e3779b97f4a7c15ull;
    uint32_t best_on = 0;
    double p[3] = {0.0, 0.0, 0.0};
    for (int it = 0; it < RS_GROUND_DRAWS && nn >= 3; it++) {
      int c3[3];
      for (int k = 0; k < 3; k++) c3[k] = g->near[rs_xorshift64(&rng) % nn];
      double q[3];
      if (!plane_through(g, c3, q) || hypot(q[1], q[2]) > steep || -q[0] < RS_GROUND_BELOW_M) continue;
      uint32_t on = 0;
      for (uint32_t i = 0; i < nn; i++) on += fabs(g->z[g->near[i]] - plane_of(q, g->near[i])) <= RS_GROUND_PLANE_TOL;
      if (on > best_on) {
        best_on = on;
        memcpy(p, q, sizeof p);
      }
    }
    static const double tol[] = {4 * RS_GROUND_PLANE_TOL, 2 * RS_GROUND_PLANE_TOL, RS_GROUND_PLANE_TOL};
    have_plane = best_on > 0;
    for (size_t i = 0; i < sizeof tol / sizeof tol[0] && have_plane; i++) have_plane = fit_plane(g, p, tol[i], p);
    memcpy(g->plane, p, sizeof p);
  }
  /* a plausible ground: below the sensor, not steep, and most of the cells near the sensor on it (a sensor
   * on its side, in a small room, or a model no plane fits has none) */
  uint32_t near = 0, on = 0;
  for (int c = 0; c < ncell && have_plane; c++) {
    if (isnan(g->z[c]) || !near_cell(c)) continue;
    near++;
    on += fabs(g->z[c] - plane_at(g, c)) <= 2 * RS_GROUND_PLANE_TOL;
  }
  g->on_plane = near > 0 ? (double)on / near : 0.0;
  if (!have_plane || -g->plane[0] < RS_GROUND_BELOW_M || hypot(g->plane[1], g->plane[2]) > steep ||
      g->on_plane < RS_GROUND_ON_PLANE) {
    forget(g);
    return;
  }
  /* cells without ground: the plane there, off it as much as their known neighbours are on average,
   * RS_GROUND_FILL rings out (on a slope a neighbour's own height would be a step off) */
  for (int pass = 0; pass < RS_GROUND_FILL; pass++) {
    memcpy(g->tmp, g->z, sizeof g->z);
    for (int c = 0; c < ncell; c++) {
      if (!isnan(g->z[c])) continue;
      int at[9];
      const int nv = known_around(g->z, c, at);
      double sum = 0.0;
      for (int i = 0; i < nv; i++) sum += g->z[at[i]] - plane_at(g, at[i]);
      if (nv > 0) {
        g->tmp[c] = (float)(plane_at(g, c) + sum / nv);
        g->cells_filled++;
      }
    }
    memcpy(g->z, g->tmp, sizeof g->z);
  }
  for (int c = 0; c < ncell; c++)
    if (isnan(g->z[c])) {
      g->z[c] = (float)plane_at(g, c);
      g->cells_plane++;
    }
  g->valid = true;
}

bool rs_ground_at(const rs_ground_t *g, double x, double y, float *z) {
  if (!g || !g->valid) return false;
  const int c = cell_of(x, y);
  if (c < 0 || isnan(g->z[c])) return false;
  *z = g->z[c];
  return true;
}

void rs_ground_describe(const rs_ground_t *g, char *buf, size_t n) {
  const double up = atan(hypot(g->plane[1], g->plane[2])) * 180.0 / PI;
  if (g->valid) {
    double toward = atan2(g->plane[1], g->plane[2]) * 180.0 / PI; /* clockwise from +Y */
    if (toward < 0) toward += 360.0;
    snprintf(buf, n,
             "ground (from the model): the sensor %.2f m above it; it rises %.2f deg towards azimuth %.0f deg in the "
             "sensor's frame (a tilted sensor or a sloping road); %u of its %.0f m cells from the scene, %u filled from "
             "neighbours, %u from the plane; %.0f %% of those within %.0f m on it",
             -g->plane[0], up, toward, g->cells_kept, (double)RS_GROUND_CELL_M, g->cells_filled, g->cells_plane,
             100.0 * g->on_plane, RS_GROUND_NEAR_M);
  } else {
    snprintf(buf, n,
             "ground: not found in the model (%u of its %.0f m cells with static returns, fewer than %d, or their plane "
             "%.2f m below the sensor, %.1f deg steep, holding %.0f %% of those within %.0f m): heights from returns "
             "alone",
             g->cells_kept, (double)RS_GROUND_CELL_M, RS_GROUND_MIN_CELLS, -g->plane[0], up, 100.0 * g->on_plane,
             RS_GROUND_NEAR_M);
  }
}

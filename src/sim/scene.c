/* scene.c - the simulated intersection: world building, traffic, ray casting.
 *
 * Single-threaded, owned by the simulator. Start-up builds the static
 * geometry and a static range table (first static surface and first canopy
 * per laser and 0.01-degree azimuth step, found with 1-degree azimuth
 * buckets of primitives); per packet, traffic advances and the objects
 * whose azimuth span meets the packet's are collected, so a ray tests the
 * table plus a handful of objects. */
#include "roadscan/sim/scene.h"

#include "roadscan/util/error.h"
#include "roadscan/util/opts.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define PI 3.14159265358979323846
#define D2R (PI / 180.0)
#define AZ_STEPS 36000
#define ROAD_HALF 7.0
#define WALK_OUTER 12.0
#define KERB 0.15
#define STOP_DIST 12.0
#define STEP_S 0.05
#define MAX_AGENTS 2048
#define MAX_CAND 512
#define CAND_BUCKETS 64
#define CAND_BUCKET_ITEMS 8192
#define MAX_PRIMS 4096
#define ROUTES 16
#define AMBER_S 3.0
#define RS_SCENE_LEAF 2 /* truth label of leaves, rain and dust */
#define ALLRED_S 2.0

/* ---- random numbers (xoroshiro128+) ---- */

static uint64_t splitmix(uint64_t *x) {
  uint64_t z = (*x += 0x9E3779B97F4A7C15ull);
  z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
  z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
  return z ^ (z >> 31);
}
void rs_rng_seed(rs_rng_t *r, uint64_t seed) {
  r->s[0] = splitmix(&seed);
  r->s[1] = splitmix(&seed);
}
static uint64_t rotl(uint64_t x, int k) { return (x << k) | (x >> (64 - k)); }
uint64_t rs_rng_next(rs_rng_t *r) {
  uint64_t s0 = r->s[0], s1 = r->s[1], res = s0 + s1;
  s1 ^= s0;
  r->s[0] = rotl(s0, 24) ^ s1 ^ (s1 << 16);
  r->s[1] = rotl(s1, 37);
  return res;
}
double rs_rng_uniform(rs_rng_t *r) { return (double)(rs_rng_next(r) >> 11) * (1.0 / 9007199254740992.0); }
double rs_rng_normal(rs_rng_t *r) {
  /* Irwin-Hall: four 16-bit uniforms from one draw, scaled to unit variance
   * (tails end at 3.46 sigma, which suits range noise) */
  uint64_t x = rs_rng_next(r);
  double sum = (double)(x & 0xFFFF) + (double)((x >> 16) & 0xFFFF) + (double)((x >> 32) & 0xFFFF) +
               (double)(x >> 48);
  return (sum / 65536.0 - 2.0) * 1.7320508075688772;
}

/* ---- configuration ---- */

static void defaults(rs_scene_cfg_t *c) {
  memset(c, 0, sizeof *c);
  c->pole_height = 5.0;
  c->pole_x = -11.5;
  c->pole_y = -11.5;
  c->leg_length = 250.0;
  c->trees_per_leg = 6;
  c->site_seed = 1;
  c->foliage_hit = 0.55;
  c->vehicles_per_min = 8.0;
  c->pedestrians_per_min = 1.0;
  c->cyclist_share = 0.05;
  c->green_s = 25.0;
  c->warmup_s = 60.0;
  c->walker_space = 0.8;
  c->range_noise = 0.012;
  c->noise_tail = 0.005;
  c->dropout = 0.012;
  c->spurious = 0.0002;
  c->beam_samples = 9;
  c->mix_depth = 0.6;
  c->rpm_offset = -0.0005;
  c->rpm_jitter = 0.0005;
  c->sway_period = 4.0;
}

double rs_scene_yaw(const rs_scene_cfg_t *c, double t) {
  double y = c->sway_deg * sin(2.0 * M_PI * t / c->sway_period);
  if (c->knock_deg != 0.0 && t > c->knock_at) y += c->knock_deg * fmin(1.0, (t - c->knock_at) / 0.5);
  return y;
}

bool rs_scene_preset(const char *name, rs_scene_cfg_t *c) {
  defaults(c);
  if (strcmp(name, "light") == 0) {
    c->vehicles_per_min = 4.0;
    c->pedestrians_per_min = 0.6;
  } else if (strcmp(name, "rush") == 0) {
    /* peak demand near capacity (v/c about 0.93): long queues that clear in
     * most cycles; the sensor on a 3 m pole (a signal-cabinet mount) */
    c->vehicles_per_min = 24.0;
    c->pedestrians_per_min = 6.0;
    c->cyclist_share = 0.08;
    c->green_s = 30.0;
    c->warmup_s = 180.0;
    c->pole_height = 3.0;
  } else if (strcmp(name, "turns") == 0) {
    /* ordinary traffic of which a quarter turns (right from the outer lanes, left from the
     * inner ones, across the oncoming traffic) */
    c->turn_share = 0.25;
  } else if (strcmp(name, "far") == 0) {
    c->vehicles_per_min = 14.0;
    c->pedestrians_per_min = 0.0;
    c->objects_min_range = 100.0;
    c->objects_max_range = 200.0;
  } else if (strcmp(name, "storm") == 0) {
    c->vehicles_per_min = 10.0;
    c->pedestrians_per_min = 1.0;
    c->range_noise = 0.05;
    c->dropout = 0.03;
    c->spurious = 0.01;
    c->attenuation = 5.0;
    c->packet_loss = 0.05;
    c->foliage_hit = 0.45;
  } else {
    return false;
  }
  return true;
}

/* the scene knobs by name, with their ranges (rs_scene_set; roadscan-sim --set and --scenario-file) */
#define KNOB(f, l, u) {.type = RS_OPT_DOUBLE, .name = #f, .arg = "X", .off = offsetof(rs_scene_cfg_t, f), .lo = l, .hi = u}
#define KNOB_INT(f, l, u) {.type = RS_OPT_INT, .name = #f, .arg = "N", .off = offsetof(rs_scene_cfg_t, f), .lo = l, .hi = u}
static const rs_opt_t knobs[] = {
    KNOB_INT(site_seed, 0, 2147483647.0), KNOB(pole_height, 1.0, 30.0),   KNOB(pole_x, -14.0, -8.0),
    KNOB(pole_y, -14.0, -8.0),            KNOB(leg_length, 50.0, 400.0),  KNOB_INT(trees_per_leg, 0, 40),
    KNOB(foliage_hit, 0.0, 1.0),          KNOB(vehicles_per_min, 0.0, 120.0),
    KNOB(pedestrians_per_min, 0.0, 60.0), KNOB(cyclist_share, 0.0, 1.0),
    KNOB(green_s, 5.0, 120.0),            KNOB(objects_min_range, 0.0, 400.0),
    KNOB(objects_max_range, 0.0, 400.0),  KNOB(warmup_s, 0.0, 600.0),       KNOB(walker_space, 0.0, 2.0),
    KNOB(turn_share, 0.0, 1.0),
    KNOB(range_noise, 0.0, 1.0),          KNOB(noise_tail, 0.0, 0.5),     KNOB(dropout, 0.0, 1.0),
    KNOB(spurious, 0.0, 0.5),             KNOB(attenuation, 0.0, 100.0),  KNOB(packet_loss, 0.0, 0.9),
    KNOB(max_range, 0.0, 400.0),          KNOB(beam_div_h, 0.0, 20.0),    KNOB(beam_div_v, 0.0, 20.0),
    KNOB_INT(beam_samples, 1, 9),         KNOB(mix_depth, 0.0, 5.0),
    KNOB(rpm_offset, -0.05, 0.05),        KNOB(rpm_jitter, 0.0, 0.01),
    KNOB(sway_deg, 0.0, 2.0),             KNOB(sway_period, 0.5, 60.0),
    KNOB(knock_deg, -5.0, 5.0),           KNOB(knock_at, 0.0, 7200.0),
    KNOB(tilt_deg, 0.0, 10.0),            KNOB(tilt_toward, 0.0, 360.0),
};
#define NKNOBS ((int)(sizeof knobs / sizeof knobs[0]))

const rs_opt_t *rs_scene_knobs(int *n) {
  *n = NKNOBS;
  return knobs;
}

int rs_scene_set(rs_scene_cfg_t *cfg, const char *key, const char *value, char *err, size_t n) {
  return rs_opt_set(knobs, NKNOBS, cfg, "scene key", key, value, err, n);
}

/* ---- geometry ---- */

enum { P_BOX, P_CYL, P_SPHERE };

typedef struct {
  uint8_t kind;
  uint8_t intensity;
  uint16_t label;
  float a[6]; /* box: x0 y0 z0 x1 y1 z1; cyl: x y r z0 z1; sphere: x y z r */
} prim_t;

typedef struct {
  double x0, y0, dx, dy; /* start and unit direction */
  double length;         /* despawn after */
  double stop_s;         /* front stops here on red */
  int phase;             /* 0 east-west, 1 north-south */
  bool pedestrian;
  int agents[MAX_AGENTS / 8];
  int n;                 /* agents on the route, front first */
  double next_spawn;
} route_t;

enum { T_CAR, T_VAN, T_TRUCK, T_BUS, T_CYCLIST, T_PED };

typedef struct {
  bool active;
  uint16_t id;
  uint8_t type, intensity;
  int route;
  double s, v, v0, l, w, h;
  double clear;        /* body above the road (ground clearance) */
  double span0, spanw; /* azimuth span over the current traffic step, widened */
  double lat, vlat;    /* a walker's step aside from its path (m, to its left) and its rate (m/s) */
  double vlat_next;
  bool yield;          /* a walker slowing down for another it would bump into */
  /* a turning vehicle (turn_share): its path leaves the route's line at path length p1 (m from
   * the route's start) on a quarter circle of radius R, and goes on along the road it turned
   * into (turn_dir()); vturn is the speed it takes the arc at */
  uint8_t turn;        /* TURN_NONE, TURN_RIGHT, TURN_LEFT */
  double p1, R, vturn;
} agent_t;

enum { TURN_NONE, TURN_RIGHT, TURN_LEFT };

typedef struct {
  uint16_t id;
  uint8_t intensity;
  bool cyl;
  double cx, cy, c, s; /* centre, cos/sin of heading */
  double hl, hw, h;    /* half length, half width, height */
  double z0;           /* bottom of the body (ground clearance) */
  double az0, aw;      /* azimuth span from the sensor (deg) */
  double dmin;         /* no part is nearer than this */
} cand_t;

/* the static scene along one firing direction, footprint included: the
 * nearer and the farther return (r2 = 0: one), with their intensities */
typedef struct {
  float r1, r2;     /* 0 = none */
  float fol;        /* first canopy entry when nearer than r1, else 0 */
  uint8_t i1, i2;
  uint8_t fol_p;    /* leaf chance, 0..255 */
} st_cell_t;

struct rs_scene {
  rs_scene_cfg_t cfg;
  const rs_sensor_t *sensor;
  double ox, oy, oz;
  double tilt[3][3]; /* sensor frame -> site, when cfg.tilt_deg > 0 */
  prim_t *prims;
  int nprims;
  int *bucket_start, *bucket_items; /* 360 buckets */
  /* static table, [0.01-degree azimuth step][laser]: the lasers of one
   * firing sit side by side in memory */
  st_cell_t *st;
  int slots;          /* record slots per row: 32, or 128 (VLS-128) */
  double deg_per_us;  /* rotation rate the table was cast for */
  /* traffic */
  rs_rng_t rng;
  route_t routes[ROUTES];
  int nroutes;
  agent_t agents[MAX_AGENTS];
  uint16_t next_id;
  double t; /* traffic time (s since capture start; negative during warm-up) */
  cand_t cand[MAX_CAND];
  int ncand;
  /* candidates by whole degree of azimuth inside the packet window */
  double win0;
  int nwin;
  uint16_t bstart[CAND_BUCKETS + 1];
  uint16_t bitems[CAND_BUCKET_ITEMS];
  int agent_hwm; /* agents[agent_hwm..] have never been used */
  double wind;
};

static void add_prim(rs_scene_t *sc, int kind, uint16_t label, uint8_t intensity, const float *a, int na) {
  if (sc->nprims >= MAX_PRIMS) return;
  prim_t *p = &sc->prims[sc->nprims++];
  p->kind = (uint8_t)kind;
  p->label = label;
  p->intensity = intensity;
  memset(p->a, 0, sizeof p->a);
  memcpy(p->a, a, sizeof(float) * (size_t)na);
}

static void box(rs_scene_t *sc, double x0, double y0, double z0, double x1, double y1, double z1, uint8_t inten) {
  float a[6] = {(float)fmin(x0, x1), (float)fmin(y0, y1), (float)z0, (float)fmax(x0, x1), (float)fmax(y0, y1), (float)z1};
  add_prim(sc, P_BOX, 1, inten, a, 6);
}
static void cyl(rs_scene_t *sc, double x, double y, double r, double z0, double z1, uint8_t inten) {
  float a[5] = {(float)x, (float)y, (float)r, (float)z0, (float)z1};
  add_prim(sc, P_CYL, 1, inten, a, 5);
}
static void sphere(rs_scene_t *sc, double x, double y, double z, double r, double leaf_p, uint8_t inten) {
  float a[5] = {(float)x, (float)y, (float)z, (float)r, (float)leaf_p};
  add_prim(sc, P_SPHERE, 2, inten, a, 5);
}

/* a leg's side: direction (ux, uy) from the centre, side normal (nx, ny) */
static void build_leg(rs_scene_t *sc, double ux, double uy, double nx, double ny, rs_rng_t *r) {
  const double L = sc->cfg.leg_length;
  /* buildings on both sides, with gaps for side streets */
  for (int side = -1; side <= 1; side += 2) {
    double s = 16.0 + 6.0 * rs_rng_uniform(r);
    while (s < L) {
      double len = 18.0 + 40.0 * rs_rng_uniform(r);
      double h = 6.0 + 18.0 * rs_rng_uniform(r);
      double near = 15.0 + 3.0 * rs_rng_uniform(r), depth = 12.0 + 10.0 * rs_rng_uniform(r);
      double e = fmin(s + len, L);
      double ax = ux * s + side * nx * near, ay = uy * s + side * ny * near;
      double bx = ux * e + side * nx * (near + depth), by = uy * e + side * ny * (near + depth);
      box(sc, ax, ay, 0.0, bx, by, h, (uint8_t)(30 + rs_rng_uniform(r) * 50));
      s = e + (rs_rng_uniform(r) < 0.25 ? 12.0 + 8.0 * rs_rng_uniform(r) : 1.0);
    }
    /* street lights */
    for (double p = 20.0; p < fmin(L, 200.0); p += 35.0)
      cyl(sc, ux * p + side * nx * 11.6, uy * p + side * ny * 11.6, 0.12, 0.0, 8.0, 70);
    /* trees (canopy = foliage, trunk = static) and bushes */
    for (int i = 0; i < sc->cfg.trees_per_leg; i++) {
      double p = 25.0 + rs_rng_uniform(r) * fmin(L - 30.0, 150.0);
      double cx = ux * p + side * nx * 13.0, cy = uy * p + side * ny * 13.0;
      double rad = 2.0 + 1.2 * rs_rng_uniform(r), cz = 3.5 + rad;
      cyl(sc, cx, cy, 0.18, 0.0, cz - rad * 0.6, 35);
      sphere(sc, cx, cy, cz, rad, sc->cfg.foliage_hit, (uint8_t)(25 + 20 * rs_rng_uniform(r)));
      if (rs_rng_uniform(r) < 0.5)
        sphere(sc, cx + ux * 4.0, cy + uy * 4.0, 0.7, 0.9, fmin(1.0, sc->cfg.foliage_hit + 0.3), 30);
    }
    /* a sign */
    double sp = 30.0 + 20.0 * rs_rng_uniform(r);
    double sx = ux * sp + side * nx * 10.5, sy = uy * sp + side * ny * 10.5;
    cyl(sc, sx, sy, 0.04, 0.0, 2.2, 60);
    box(sc, sx - 0.4 * fabs(uy) - 0.03 * fabs(ux), sy - 0.4 * fabs(ux) - 0.03 * fabs(uy), 2.2,
        sx + 0.4 * fabs(uy) + 0.03 * fabs(ux), sy + 0.4 * fabs(ux) + 0.03 * fabs(uy), 3.0, 200);
  }
  /* a low wall along part of the leg */
  double w0 = 60.0 + 40.0 * rs_rng_uniform(r);
  box(sc, ux * w0 + nx * 12.4, uy * w0 + ny * 12.4, 0.0, ux * (w0 + 25) + nx * 12.8, uy * (w0 + 25) + ny * 12.8, 1.2, 45);
}

static void add_route(rs_scene_t *sc, double x0, double y0, double dx, double dy, double length, double stop_s,
                      int phase, bool ped) {
  route_t *rt = &sc->routes[sc->nroutes++];
  memset(rt, 0, sizeof *rt);
  rt->x0 = x0;
  rt->y0 = y0;
  rt->dx = dx;
  rt->dy = dy;
  rt->length = length;
  rt->stop_s = stop_s;
  rt->phase = phase;
  rt->pedestrian = ped;
}

static void build_routes(rs_scene_t *sc) {
  const double L = sc->cfg.leg_length, Lp = fmin(L, 150.0);
  static const double lanes[2] = {1.75, 5.25};
  for (int i = 0; i < 2; i++) {
    double o = lanes[i];
    add_route(sc, -L, -o, 1, 0, 2 * L, L - STOP_DIST, 0, false); /* eastbound */
    add_route(sc, L, o, -1, 0, 2 * L, L - STOP_DIST, 0, false);  /* westbound */
    add_route(sc, o, -L, 0, 1, 2 * L, L - STOP_DIST, 1, false);  /* northbound */
    add_route(sc, -o, L, 0, -1, 2 * L, L - STOP_DIST, 1, false); /* southbound */
  }
  /* pedestrians along the sidewalks, crossing with the parallel traffic */
  add_route(sc, -Lp, -9.5, 1, 0, 2 * Lp, Lp - 8.0, 0, true);
  add_route(sc, Lp, 9.5, -1, 0, 2 * Lp, Lp - 8.0, 0, true);
  add_route(sc, 9.5, -Lp, 0, 1, 2 * Lp, Lp - 8.0, 1, true);
  add_route(sc, -9.5, Lp, 0, -1, 2 * Lp, Lp - 8.0, 1, true);
  add_route(sc, Lp, -10.5, -1, 0, 2 * Lp, Lp - 8.0, 0, true);
  add_route(sc, -Lp, 10.5, 1, 0, 2 * Lp, Lp - 8.0, 0, true);
  add_route(sc, 10.5, Lp, 0, -1, 2 * Lp, Lp - 8.0, 1, true);
  add_route(sc, -10.5, -Lp, 0, 1, 2 * Lp, Lp - 8.0, 1, true);
}

/* ---- ray tests (origin o, direction d; return t > 0 or INFINITY) ---- */

static double hit_cyl(double cx, double cy, double r, double z0, double z1, const double *o, const double *d) {
  double px = o[0] - cx, py = o[1] - cy;
  double A = d[0] * d[0] + d[1] * d[1];
  if (A < 1e-12) return INFINITY;
  double B = 2 * (px * d[0] + py * d[1]), C = px * px + py * py - r * r;
  double disc = B * B - 4 * A * C;
  if (disc < 0) return INFINITY;
  double t = (-B - sqrt(disc)) / (2 * A);
  if (t <= 1e-6) return INFINITY;
  double z = o[2] + t * d[2];
  if (z < z0 || z > z1) {
    /* top cap */
    if (d[2] < 0 && o[2] > z1) {
      double tc = (z1 - o[2]) / d[2];
      double qx = px + tc * d[0], qy = py + tc * d[1];
      if (qx * qx + qy * qy <= r * r) return tc;
    }
    return INFINITY;
  }
  return t;
}

static double hit_sphere(const float *a, const double *o, const double *d, double *exit) {
  double px = o[0] - a[0], py = o[1] - a[1], pz = o[2] - a[2];
  double B = px * d[0] + py * d[1] + pz * d[2];
  double C = px * px + py * py + pz * pz - (double)a[3] * a[3];
  double disc = B * B - C;
  if (disc < 0) return INFINITY;
  double q = sqrt(disc), t = -B - q;
  *exit = -B + q;
  if (*exit <= 1e-6) return INFINITY;
  return t > 1e-6 ? t : 1e-6;
}

/* azimuth (degrees, [0,360)) of a world point from the sensor */
static double az_of(const rs_scene_t *sc, double x, double y) {
  double a = atan2(x - sc->ox, y - sc->oy) / D2R;
  return a < 0 ? a + 360.0 : a;
}

/* azimuth span of a set of xy points: start and width (deg); full circle
 * when the sensor is inside the hull (approximated by the box) */
static void az_span(const rs_scene_t *sc, const double *xs, const double *ys, int n, double *start, double *width) {
  double ref = az_of(sc, xs[0], ys[0]), lo = 0, hi = 0;
  for (int i = 1; i < n; i++) {
    double d = az_of(sc, xs[i], ys[i]) - ref;
    if (d > 180) d -= 360;
    if (d < -180) d += 360;
    if (d < lo) lo = d;
    if (d > hi) hi = d;
  }
  *start = fmod(ref + lo + 360.0, 360.0);
  *width = hi - lo;
}

static void prim_span(const rs_scene_t *sc, const prim_t *p, double *start, double *width) {
  double x0, y0, x1, y1;
  if (p->kind == P_BOX) {
    x0 = p->a[0]; y0 = p->a[1]; x1 = p->a[3]; y1 = p->a[4];
  } else {
    double r = p->a[p->kind == P_CYL ? 2 : 3];
    x0 = p->a[0] - r; y0 = p->a[1] - r; x1 = p->a[0] + r; y1 = p->a[1] + r;
  }
  if (sc->ox >= x0 - 0.5 && sc->ox <= x1 + 0.5 && sc->oy >= y0 - 0.5 && sc->oy <= y1 + 0.5) {
    *start = 0;
    *width = 360;
    return;
  }
  double xs[4] = {x0, x1, x0, x1}, ys[4] = {y0, y0, y1, y1};
  az_span(sc, xs, ys, 4, start, width);
}

static void build_buckets(rs_scene_t *sc) {
  int counts[360] = {0};
  double st[MAX_PRIMS], wd[MAX_PRIMS];
  for (int i = 0; i < sc->nprims; i++) {
    prim_span(sc, &sc->prims[i], &st[i], &wd[i]);
    for (int b = 0; b <= (int)wd[i] + 1 && b < 360; b++) counts[((int)st[i] + b) % 360]++;
  }
  sc->bucket_start = calloc(361, sizeof(int));
  int total = 0;
  for (int b = 0; b < 360; b++) {
    sc->bucket_start[b] = total;
    total += counts[b];
  }
  sc->bucket_start[360] = total;
  sc->bucket_items = calloc((size_t)total + 1, sizeof(int));
  int fill[360] = {0};
  for (int i = 0; i < sc->nprims; i++)
    for (int b = 0; b <= (int)wd[i] + 1 && b < 360; b++) {
      int k = ((int)st[i] + b) % 360;
      sc->bucket_items[sc->bucket_start[k] + fill[k]++] = i;
    }
}

static void dir_el(double el_deg, double az_deg, double *d) {
  double a = az_deg * D2R, e = el_deg * D2R, ce = cos(e);
  d[0] = ce * sin(a);
  d[1] = ce * cos(a);
  d[2] = sin(e);
}

/* a sensor-frame direction turned into the site's by the sensor's tilt (tilt_deg) */
static bool tilted(const rs_scene_t *sc) { return sc->cfg.tilt_deg > 0.0; }
static void tilt_dir(const rs_scene_t *sc, double *d) {
  if (!tilted(sc)) return;
  double r[3];
  for (int i = 0; i < 3; i++) r[i] = sc->tilt[i][0] * d[0] + sc->tilt[i][1] * d[1] + sc->tilt[i][2] * d[2];
  memcpy(d, r, sizeof r);
}
/* the site azimuth (degrees, [0, 360)) of direction d */
static double dir_az(const double *d) {
  const double a = atan2(d[0], d[1]) / D2R;
  return a < 0.0 ? a + 360.0 : a;
}

static void dir_of(const rs_scene_t *sc, int laser, double az, double *d) {
  double a = az * D2R, ce = sc->sensor->cos_el[laser];
  d[0] = ce * sin(a);
  d[1] = ce * cos(a);
  d[2] = sc->sensor->sin_el[laser];
  tilt_dir(sc, d);
}

/* a box face hit: which axis the entry face is normal to */
static double hit_box_axis(const float *a, const double *o, const double *d, int *axis) {
  double tmin = 1e-6, tmax = INFINITY;
  *axis = 2;
  for (int k = 0; k < 3; k++) {
    double lo = a[k], hi = a[k + 3];
    if (fabs(d[k]) < 1e-12) {
      if (o[k] < lo || o[k] > hi) return INFINITY;
      continue;
    }
    double t1 = (lo - o[k]) / d[k], t2 = (hi - o[k]) / d[k];
    if (t1 > t2) {
      double t = t1;
      t1 = t2;
      t2 = t;
    }
    if (t1 > tmin) {
      tmin = t1;
      *axis = k;
    }
    if (t2 < tmax) tmax = t2;
    if (tmin > tmax) return INFINITY;
  }
  return tmin;
}

/* one ray against the static scene: the first surface (range, reflectivity,
 * cosine of the incidence angle) and the first canopy */
typedef struct {
  double t, cosi, fol;
  uint8_t refl, fol_p;
} st_hit_t;

static void static_hit(const rs_scene_t *sc, const double *d, double az, st_hit_t *h) {
  const double o[3] = {sc->ox, sc->oy, sc->oz};
  double best = INFINITY, fbest = INFINITY, cosi = 1.0;
  uint8_t bint = 0, fp = 0;
  if (d[2] < 0) {
    best = -o[2] / d[2];
    bint = 12;
    cosi = -d[2];
  }
  int b = (int)az % 360;
  for (int k = sc->bucket_start[b]; k < sc->bucket_start[b + 1]; k++) {
    const prim_t *p = &sc->prims[sc->bucket_items[k]];
    double t, ex, c = 1.0;
    int axis;
    switch (p->kind) {
    case P_BOX:
      t = hit_box_axis(p->a, o, d, &axis);
      c = fabs(d[axis]);
      break;
    case P_CYL: {
      t = hit_cyl(p->a[0], p->a[1], p->a[2], p->a[3], p->a[4], o, d);
      double px = o[0] + t * d[0] - p->a[0], py = o[1] + t * d[1] - p->a[1], n = hypot(px, py);
      c = n > 1e-9 ? fabs(px * d[0] + py * d[1]) / n : 1.0;
      break;
    }
    default:
      t = hit_sphere(p->a, o, d, &ex);
      if (t < fbest) {
        fbest = t;
        fp = (uint8_t)(p->a[4] * 255.0f);
      }
      continue;
    }
    if (t < best) {
      best = t;
      bint = p->intensity;
      cosi = c;
    }
  }
  h->t = isfinite(best) ? best : 0.0;
  h->refl = bint;
  h->cosi = cosi;
  h->fol = (isfinite(fbest) && fbest < best) ? fbest : 0.0;
  h->fol_p = h->fol > 0 ? fp : 0;
}

/* ---- the beam: footprint and returns ----
 * A firing lights a footprint beam_div_h x beam_div_v wide, sampled by up to
 * 3 x 3 rays (weights of a Gaussian profile). The surfaces it meets form
 * returns: hits closer in range than mix_depth are one return at their
 * energy-weighted range (the mixed range of a beam split across a small
 * depth step), farther apart they are separate returns. A return's
 * intensity is the reflectivity its part of the footprint sends back
 * (reflectivity x (0.3 + 0.7 cos incidence) x the share of the footprint):
 * the strongest return is the brightest, the last the farthest. */
typedef struct {
  double r, w, refl, cosi;
  uint16_t label;
} sub_hit_t;

typedef struct {
  double r, inten;
  uint16_t label;
} beam_ret_t;

static const double sub_off[3] = {-0.3, 0.0, 0.3};    /* of the divergence */
static const double sub_w[3] = {0.27, 0.46, 0.27};   /* Gaussian profile, normalised */

/* groups sub-hits (sorted by range here) into returns; out[0] nearer, out[1]
 * farther (the brightest and the last when there are more); returns count */
static int form_returns(sub_hit_t *h, int n, double mix_depth, beam_ret_t out[2]) {
  for (int i = 1; i < n; i++)
    for (int j = i; j > 0 && h[j].r < h[j - 1].r; j--) {
      sub_hit_t t = h[j];
      h[j] = h[j - 1];
      h[j - 1] = t;
    }
  beam_ret_t g[9];
  int ng = 0;
  for (int i = 0; i < n;) {
    double sw = 0, swr = 0, si = 0, best_w = -1;
    uint16_t label = h[i].label;
    int j = i;
    for (; j < n && h[j].r - h[i].r <= mix_depth; j++) {
      double e = h[j].w * h[j].refl * (0.3 + 0.7 * h[j].cosi);
      sw += h[j].w;
      swr += h[j].w * h[j].r;
      si += e;
      if (h[j].w > best_w) {
        best_w = h[j].w;
        label = h[j].label;
      }
    }
    g[ng].r = swr / sw;
    g[ng].inten = si;
    g[ng].label = label;
    ng++;
    i = j;
  }
  if (ng == 0) return 0;
  int strongest = 0;
  for (int k = 1; k < ng; k++)
    if (g[k].inten > g[strongest].inten) strongest = k;
  out[0] = g[strongest];
  if (strongest == ng - 1) {
    /* the last is the strongest: the second return is the brightest other one */
    if (ng == 1) return 1;
    int second = 0;
    for (int k = 1; k < ng - 1; k++)
      if (g[k].inten > g[second].inten) second = k;
    out[0] = g[second];
    out[1] = g[ng - 1];
    return 2;
  }
  out[1] = g[ng - 1];
  return 2;
}

static int beam_grid(const rs_scene_t *sc, int *nh, int *nv) {
  *nh = sc->cfg.beam_samples >= 3 ? 3 : 1;
  *nv = sc->cfg.beam_samples >= 9 ? 3 : 1;
  return *nh * *nv;
}

static uint8_t clamp_u8(double v) { return (uint8_t)(v < 1 ? 1 : (v > 255 ? 255 : lround(v))); }

/* the static returns of a firing of `laser` at azimuth az */
static void beam_static(const rs_scene_t *sc, int laser, double az, st_cell_t *c) {
  int nh, nv;
  beam_grid(sc, &nh, &nv);
  const double el = sc->sensor->elevation_deg[laser];
  const double dh = sc->cfg.beam_div_h * 1e-3 / D2R, dv = sc->cfg.beam_div_v * 1e-3 / D2R; /* degrees */
  sub_hit_t h[9];
  int n = 0;
  double wsum = 0, fol = 0;
  uint8_t fol_p = 0;
  for (int i = 0; i < nh; i++)
    for (int j = 0; j < nv; j++) {
      const double u = nh == 1 ? 0 : sub_off[i], v = nv == 1 ? 0 : sub_off[j];
      const double w = (nh == 1 ? 1 : sub_w[i]) * (nv == 1 ? 1 : sub_w[j]);
      const double a = az + u * dh;
      double d[3];
      dir_el(el + v * dv, a, d);
      tilt_dir(sc, d);
      st_hit_t sh;
      static_hit(sc, d, tilted(sc) ? dir_az(d) : fmod(a + 360.0, 360.0), &sh);
      wsum += w;
      if (u == 0 && v == 0) {
        fol = sh.fol;
        fol_p = sh.fol_p;
      }
      if (sh.t <= 0) continue;
      h[n++] = (sub_hit_t){sh.t, w, sh.refl, sh.cosi, 1};
    }
  beam_ret_t r[2];
  int nr = form_returns(h, n, sc->cfg.mix_depth, r);
  memset(c, 0, sizeof *c);
  if (nr >= 1) {
    c->r1 = (float)r[0].r;
    c->i1 = clamp_u8(r[0].inten / wsum);
  }
  if (nr >= 2) {
    c->r2 = (float)r[1].r;
    c->i2 = clamp_u8(r[1].inten / wsum);
  }
  c->fol = (c->r1 == 0 || fol < c->r1) ? (float)fol : 0.0f;
  c->fol_p = c->fol > 0 ? fol_p : 0;
}

/* Row k: a block whose azimuth field reads k (0.01 degree); column: the
 * record slot (bank * 32 + record), cast at that record's true azimuth at
 * the scene's rotation rate. */
static void build_table(rs_scene_t *sc) {
  const rs_sensor_t *s = sc->sensor;
  const int n = s->info->blocks_per_cycle > 1 ? 128 : RS_RECORDS;
  sc->slots = n;
  sc->st = malloc((size_t)n * AZ_STEPS * sizeof(st_cell_t));
  if (sc->st == NULL) return;
  for (int k = 0; k < AZ_STEPS; k++)
    for (int slot = 0; slot < n; slot++) {
      int laser;
      float t;
      rs_sensor_record(s, slot / RS_RECORDS, slot % RS_RECORDS, &laser, &t);
      double az = fmod(k * 0.01 + s->azimuth_offset_deg[laser] + sc->deg_per_us * t + 720.0, 360.0);
      beam_static(sc, laser, az, &sc->st[(size_t)k * (size_t)n + (size_t)slot]);
    }
}

static double default_max_range(rs_model_t m) {
  switch (m) {
  case RS_MODEL_VLP32C: return 200.0;
  case RS_MODEL_VLS128: return 245.0;
  default: return 100.0;
  }
}

static rs_scene_t *alloc_scene(const rs_scene_cfg_t *cfg, const rs_sensor_t *s) {
  rs_scene_t *sc = calloc(1, sizeof *sc);
  if (sc == NULL) return NULL;
  sc->cfg = *cfg;
  if (sc->cfg.max_range <= 0) sc->cfg.max_range = default_max_range(s->info->model);
  /* the VLS-128 manual's figures (Table F-1); the other models' manuals give
   * none as detailed, and their optics are of the same family */
  if (sc->cfg.beam_div_h <= 0) sc->cfg.beam_div_h = 3.0;
  if (sc->cfg.beam_div_v <= 0) sc->cfg.beam_div_v = 1.5;
  if (sc->cfg.beam_samples < 1) sc->cfg.beam_samples = 1;
  sc->sensor = s;
  sc->ox = cfg->pole_x;
  sc->oy = cfg->pole_y;
  sc->oz = cfg->pole_height;
  if (cfg->tilt_deg > 0.0) { /* about the level axis k across the lean (Rodrigues): the vertical goes to cos t z + sin t u */
    const double t = cfg->tilt_deg * D2R, T = cfg->tilt_toward * D2R, k[3] = {-cos(T), sin(T), 0.0};
    const double c = cos(t), sn = sin(t), K[3][3] = {{0, -k[2], k[1]}, {k[2], 0, -k[0]}, {-k[1], k[0], 0}};
    for (int i = 0; i < 3; i++)
      for (int j = 0; j < 3; j++) sc->tilt[i][j] = (i == j ? c : 0.0) + sn * K[i][j] + (1.0 - c) * k[i] * k[j];
  }
  sc->prims = calloc(MAX_PRIMS, sizeof(prim_t));
  sc->wind = 1.0;
  return sc;
}

static void build_ground(rs_scene_t *sc) {
  const double L = sc->cfg.leg_length;
  /* sidewalks (kerb) in the four corners, L-shaped as two slabs each */
  for (int sx = -1; sx <= 1; sx += 2)
    for (int sy = -1; sy <= 1; sy += 2) {
      box(sc, sx * ROAD_HALF, sy * ROAD_HALF, 0, sx * L, sy * WALK_OUTER, KERB, 25);
      box(sc, sx * ROAD_HALF, sy * ROAD_HALF, 0, sx * WALK_OUTER, sy * L, KERB, 25);
    }
}

rs_scene_t *rs_scene_create_empty(const rs_scene_cfg_t *cfg, const rs_sensor_t *s) {
  rs_scene_t *sc = alloc_scene(cfg, s);
  if (sc == NULL) return NULL;
  rs_rng_seed(&sc->rng, 1);
  return sc;
}

void rs_scene_add_box(rs_scene_t *sc, double cx, double cy, double z0, double l, double w, double h, double yaw,
                      uint16_t label) {
  /* as a traffic object that never moves: one route-less agent */
  for (int i = 0; i < MAX_AGENTS; i++) {
    agent_t *a = &sc->agents[i];
    if (a->active) continue;
    a->active = true;
    a->id = label;
    a->type = T_CAR;
    a->route = -1;
    a->l = l;
    a->w = w;
    a->h = h + z0;
    a->intensity = 80;
    if (i >= sc->agent_hwm) sc->agent_hwm = i + 1;
    a->s = cx;
    a->v = cy;   /* route-less: s, v hold the centre */
    a->v0 = yaw; /* and v0 the heading (radians, from +x) */
    return;
  }
}

void rs_scene_set_intensity(rs_scene_t *sc, uint16_t label, uint8_t intensity) {
  for (int i = 0; i < sc->agent_hwm; i++)
    if (sc->agents[i].active && sc->agents[i].id == label) sc->agents[i].intensity = intensity;
}

rs_scene_t *rs_scene_create(const rs_scene_cfg_t *cfg, const rs_sensor_t *s, double hz, uint64_t seed) {
  rs_scene_t *sc = alloc_scene(cfg, s);
  if (sc == NULL) return NULL;
  sc->deg_per_us = hz * 360.0 / 1e6;
  rs_rng_t world; /* the site: the same for every --seed */
  rs_rng_seed(&world, (uint64_t)cfg->site_seed ^ 0x5EED5EEDull);
  rs_rng_seed(&sc->rng, seed);
  build_ground(sc);
  /* legs: east, west, north, south (direction, side normal) */
  build_leg(sc, 1, 0, 0, 1, &world);
  build_leg(sc, -1, 0, 0, 1, &world);
  build_leg(sc, 0, 1, 1, 0, &world);
  build_leg(sc, 0, -1, 1, 0, &world);
  /* signal poles with mast arms at the corners */
  for (int sx = -1; sx <= 1; sx += 2)
    for (int sy = -1; sy <= 1; sy += 2) {
      double px = sx * 9.0, py = sy * 8.5;
      if (sx < 0 && sy < 0) continue; /* the sensor pole stands here */
      cyl(sc, px, py, 0.2, 0.0, 6.0, 80);
      box(sc, px - (sx > 0 ? 6.0 : -0.0), py - 0.1, 5.6, px + (sx < 0 ? 6.0 : 0.0), py + 0.1, 5.8, 80);
    }
  build_buckets(sc);
  build_table(sc);
  build_routes(sc);
  for (int i = 0; i < sc->nroutes; i++) sc->routes[i].next_spawn = -sc->cfg.warmup_s;
  sc->t = -sc->cfg.warmup_s;
  sc->next_id = 3;
  return sc;
}

void rs_scene_destroy(rs_scene_t *sc) {
  if (sc == NULL) return;
  free(sc->prims);
  free(sc->bucket_start);
  free(sc->bucket_items);
  free(sc->st);
  free(sc);
}

void rs_scene_origin(const rs_scene_t *sc, double *x, double *y, double *z) {
  *x = sc->ox;
  *y = sc->oy;
  *z = sc->oz;
}

/* ---- traffic ---- */

static bool green(const rs_scene_t *sc, int phase, double t, bool amber_counts) {
  double g = sc->cfg.green_s, half = g + AMBER_S + ALLRED_S;
  double m = fmod(t, 2 * half);
  if (m < 0) m += 2 * half;
  double start = phase == 0 ? 0.0 : half;
  double in = m - start;
  return in >= 0 && (in < g || (amber_counts && in < g + AMBER_S));
}

/* Turning vehicles (turn_share). A road's outer lane turns right into the outer lane of the
 * road to its right, on a quarter circle of TURN_R_RIGHT; its inner lane turns left into the
 * inner lane of the road to its left, on TURN_R_LEFT, across the oncoming lanes. Each arc is
 * tangent to both lanes' lines. A driver takes the arc at the speed of its lateral acceleration
 * (2.5-3.5 m/s^2): right turns at 3.9-4.6 m/s, left turns at 5.1-6.1 m/s. The kerb corners are
 * square (7 m from the centre lines), so a right-turner's body crosses up to 0.9 m over the
 * corner of the sidewalk, where a real kerb is rounded. Trucks and buses go straight (their
 * long bodies would sweep over the corners). A left-turner waits where its arc starts, its front
 * just past the stop line, for a gap of TURN_GAP_S in the oncoming traffic; one still waiting
 * when its green ends goes in the amber and all-red if the oncoming have stopped, else waits
 * for its next green. Vehicles yield to turners and walkers in their path (path_obstacle()). */
#define TURN_R_RIGHT 6.0
#define TURN_R_LEFT 10.5
#define TURN_GAP_S 4.5 /* a left-turner goes when no oncoming vehicle reaches its path within this */
static void turn_setup(const route_t *rt, agent_t *a, double lat_acc) {
  const double o = rt->x0 * rt->dy - rt->y0 * rt->dx; /* the lane's offset right of the centre line */
  const double lc = -(rt->x0 * rt->dx + rt->y0 * rt->dy); /* path length to the centre */
  const bool right = o > ROAD_HALF / 2;
  a->turn = right ? TURN_RIGHT : TURN_LEFT;
  a->R = right ? TURN_R_RIGHT : TURN_R_LEFT;
  a->p1 = right ? lc - o - a->R : lc + o - a->R;
  a->vturn = sqrt(lat_acc * a->R);
}

/* the direction of the road a turner turns into */
static void turn_dir(const route_t *rt, const agent_t *a, double *ex, double *ey) {
  *ex = a->turn == TURN_RIGHT ? rt->dy : -rt->dy;
  *ey = a->turn == TURN_RIGHT ? -rt->dx : rt->dx;
}

/* the point of a vehicle's path p metres from its route's start, and the unit heading there */
static void path_at(const rs_scene_t *sc, const agent_t *a, double p, double *x, double *y, double *hx,
                    double *hy) {
  const route_t *rt = &sc->routes[a->route];
  const double arc = 0.5 * PI * a->R;
  if (a->turn == TURN_NONE || p <= a->p1) {
    *x = rt->x0 + rt->dx * p;
    *y = rt->y0 + rt->dy * p;
    *hx = rt->dx;
    *hy = rt->dy;
    return;
  }
  double ex, ey;
  turn_dir(rt, a, &ex, &ey);
  const double t1x = rt->x0 + rt->dx * a->p1, t1y = rt->y0 + rt->dy * a->p1; /* where the arc starts */
  if (p < a->p1 + arc) {
    const double f = (p - a->p1) / a->R, c = cos(f), sn = sin(f);
    *x = t1x + a->R * (ex * (1.0 - c) + rt->dx * sn);
    *y = t1y + a->R * (ey * (1.0 - c) + rt->dy * sn);
    *hx = rt->dx * c + ex * sn;
    *hy = rt->dy * c + ey * sn;
  } else {
    const double q = p - a->p1 - arc + a->R;
    *x = t1x + a->R * rt->dx + q * ex;
    *y = t1y + a->R * rt->dy + q * ey;
    *hx = ex;
    *hy = ey;
  }
}

static void spawn(rs_scene_t *sc, int ri) {
  route_t *rt = &sc->routes[ri];
  if (rt->n >= (int)(sizeof rt->agents / sizeof rt->agents[0])) return;
  if (rt->n > 0) {
    const agent_t *last = &sc->agents[rt->agents[rt->n - 1]];
    if (last->s - last->l < 8.0) return; /* queue reaches the end of the leg */
  }
  int slot = -1;
  for (int i = 0; i < MAX_AGENTS; i++)
    if (!sc->agents[i].active) {
      slot = i;
      break;
    }
  if (slot < 0) return;
  if (slot >= sc->agent_hwm) sc->agent_hwm = slot + 1;
  agent_t *a = &sc->agents[slot];
  memset(a, 0, sizeof *a);
  a->active = true;
  a->route = ri;
  a->id = sc->next_id++;
  if (sc->next_id == 0) sc->next_id = 3;
  rs_rng_t *r = &sc->rng;
  if (rt->pedestrian) {
    a->type = T_PED;
    a->l = a->w = 0.5;
    a->h = 1.55 + 0.35 * rs_rng_uniform(r);
    a->v0 = 1.1 + 0.5 * rs_rng_uniform(r);
    a->intensity = (uint8_t)(10 + 30 * rs_rng_uniform(r));
  } else {
    double u = rs_rng_uniform(r);
    /* length, width, height, desired speed, ground clearance */
    static const double dims[5][5] = {{4.5, 1.8, 1.5, 13.9, 0.18}, {5.2, 2.0, 2.2, 13.0, 0.22},
                                      {9.0, 2.5, 3.5, 11.0, 0.35},  {12.0, 2.55, 3.2, 11.0, 0.32},
                                      {1.8, 0.6, 1.7, 5.5, 0.0}};
    int t = u < sc->cfg.cyclist_share ? T_CYCLIST : (u < 0.75 ? T_CAR : (u < 0.87 ? T_VAN : (u < 0.95 ? T_TRUCK : T_BUS)));
    a->type = (uint8_t)t;
    a->l = dims[t][0] * (0.92 + 0.16 * rs_rng_uniform(r));
    a->w = dims[t][1];
    a->h = dims[t][2] * (0.95 + 0.1 * rs_rng_uniform(r));
    a->v0 = dims[t][3] * (0.85 + 0.3 * rs_rng_uniform(r));
    a->clear = dims[t][4];
    a->intensity = (uint8_t)(20 + 100 * rs_rng_uniform(r));
  }
  if (!rt->pedestrian && sc->cfg.turn_share > 0 && rs_rng_uniform(r) < sc->cfg.turn_share &&
      a->type != T_TRUCK && a->type != T_BUS) /* (their bodies would sweep over the corners) */
    turn_setup(rt, a, 2.5 + rs_rng_uniform(r));
  a->v = a->v0 * 0.9;
  if (rt->n > 0) {
    const agent_t *last = &sc->agents[rt->agents[rt->n - 1]];
    if (a->v > last->v) a->v = last->v;
  }
  rt->agents[rt->n++] = slot;
}

/* Walkers keep out of each other's way (walker_space > 0). Each step, every
 * walker tries three ways on: on along its path (stepping back to it when
 * off it), stepping aside to its right, and to its left (at WALK_SIDE_V, up
 * to WALK_LAT_M off its path), and for each works out how near it would
 * come, over the next WALK_LOOK_S, to every other walker within WALK_NEAR_M
 * moving as it moves now. It keeps on when that leaves walker_space between
 * centres, else takes the side that leaves the most (the right on a tie).
 * When keeping on, and the side it takes, would both bring it nearer than
 * WALK_BODY_M within WALK_YIELD_S to one ahead of it, it also slows down,
 * unless the other one waits for it (of two walking, the younger waits). Standing walkers (a queue at the kerb) make
 * room the same way. The rates are worked out for all walkers from the same
 * positions, then applied: the order of the agents does not matter. Walkers
 * on the same path do not step aside for each other: they queue and follow
 * by the path's rule (step()), and do not overtake. */
#define WALK_LOOK_S 2.0
#define WALK_NEAR_M 5.0
#define WALK_SIDE_V 0.7
#define WALK_BACK_V 0.3
#define WALK_LAT_M 1.25
#define WALK_YIELD_S 1.0
#define WALK_BODY_M 0.6
static void walker_move(const rs_scene_t *sc, const agent_t *a, double *px, double *py, double *vx, double *vy) {
  const route_t *rt = &sc->routes[a->route];
  const double s = a->s - a->l / 2;
  *px = rt->x0 + rt->dx * s - rt->dy * a->lat;
  *py = rt->y0 + rt->dy * s + rt->dx * a->lat;
  *vx = rt->dx * a->v - rt->dy * a->vlat;
  *vy = rt->dy * a->v + rt->dx * a->vlat;
}

/* how near walker a, stepping aside at vlat, comes to the others over WALK_LOOK_S (m; INFINITY: none
 * near); *yield: nearer than WALK_BODY_M within WALK_YIELD_S to one ahead that does not wait for it */
static double walker_clear(const rs_scene_t *sc, const agent_t *a, double vlat, bool *yield) {
  const route_t *rt = &sc->routes[a->route];
  double ax, ay, unused_x, unused_y;
  walker_move(sc, a, &ax, &ay, &unused_x, &unused_y);
  /* (over the look ahead, as far as there is room) */
  vlat = fmax((-WALK_LAT_M - a->lat) / WALK_LOOK_S, fmin((WALK_LAT_M - a->lat) / WALK_LOOK_S, vlat));
  const double avx = rt->dx * a->v - rt->dy * vlat, avy = rt->dy * a->v + rt->dx * vlat;
  double nearest = INFINITY;
  *yield = false;
  for (int j = 0; j < sc->agent_hwm; j++) {
    const agent_t *b = &sc->agents[j];
    if (b == a || !b->active || b->type != T_PED || b->route < 0 || b->route == a->route) continue;
    double bx, by, bvx, bvy;
    walker_move(sc, b, &bx, &by, &bvx, &bvy);
    const double dx = bx - ax, dy = by - ay;
    if (dx * dx + dy * dy > WALK_NEAR_M * WALK_NEAR_M) continue;
    const double wx = bvx - avx, wy = bvy - avy, w2 = wx * wx + wy * wy;
    double tc = w2 > 1e-9 ? -(dx * wx + dy * wy) / w2 : 0.0;
    tc = tc < 0 ? 0 : tc > WALK_LOOK_S ? WALK_LOOK_S : tc;
    const double d = hypot(dx + wx * tc, dy + wy * tc);
    if (d < nearest) nearest = d;
    if (tc < WALK_YIELD_S && d < WALK_BODY_M && dx * rt->dx + dy * rt->dy > 0 &&
        (b->v < 0.1 || a->id > b->id || bvx * dx + bvy * dy > 0))
      *yield = true;
  }
  return nearest;
}

static void walkers_avoid(rs_scene_t *sc, double dt) {
  const double space = sc->cfg.walker_space;
  if (!(space > 0)) return;
  for (int i = 0; i < sc->agent_hwm; i++) {
    agent_t *a = &sc->agents[i];
    if (!a->active || a->type != T_PED || a->route < 0) continue;
    /* on: back towards its path */
    double v = -copysign(fmin(WALK_BACK_V, fabs(a->lat) / dt), a->lat);
    bool yield;
    double best = walker_clear(sc, a, v, &yield);
    if (best < space) {
      const double sides[2] = {-WALK_SIDE_V, WALK_SIDE_V}; /* right, then left */
      double vbest = v;
      for (int k = 0; k < 2; k++) {
        if ((sides[k] > 0 ? a->lat : -a->lat) >= WALK_LAT_M - 1e-6) continue; /* no room that side */
        bool y;
        const double d = walker_clear(sc, a, sides[k], &y);
        if (d > best + 1e-9) best = d, vbest = sides[k], yield = y;
      }
      v = vbest;
    }
    if (a->lat + v * dt > WALK_LAT_M) v = (WALK_LAT_M - a->lat) / dt;
    if (a->lat + v * dt < -WALK_LAT_M) v = (-WALK_LAT_M - a->lat) / dt;
    a->vlat_next = v;
    a->yield = yield;
  }
  for (int i = 0; i < sc->agent_hwm; i++) {
    agent_t *a = &sc->agents[i];
    if (a->active && a->type == T_PED && a->route >= 0) a->vlat = a->vlat_next;
  }
}

static void pose(const rs_scene_t *sc, const agent_t *a, double t, double *cx, double *cy, double *hd);

/* point (px, py) in the frame of a box centred at (bx, by) whose axis has cosine c and sine sn */
static void box_local(double bx, double by, double c, double sn, double px, double py, double *lx, double *ly) {
  *lx = (px - bx) * c + (py - by) * sn;
  *ly = -(px - bx) * sn + (py - by) * c;
}

/* the leader of a vehicle on its route has left its line (a turner gone into another road), or the
 * vehicle has: they no longer follow each other */
static bool diverged(const agent_t *lead, const agent_t *a) {
  if (lead->turn == a->turn) return false;
  return (lead->turn != TURN_NONE && lead->s - lead->l > lead->p1) || (a->turn != TURN_NONE && a->s > a->p1);
}

/* What stands in a vehicle's path ahead, off its own line of followers: for a turner, any road
 * user; for a vehicle going straight, a walker, or a turner from another route (or one that has
 * left its own). The path ahead of its front is sampled every 0.5 m up to 6 m + 3 s of its speed; the
 * first sample that comes within half its width + 0.3 m of another's box (of a walker: the
 * ground it covers in the next WALK_AHEAD_S) gives the gap and the other's speed along the path
 * there (0 when crossing it). */
#define PATH_LOOK_MAX 40.0
#define WALK_AHEAD_S 3.0
static void path_obstacle(const rs_scene_t *sc, const agent_t *a, double *gap, double *vlead) {
  const double look = fmin(PATH_LOOK_MAX, 6.0 + 3.0 * a->v), reach = a->w / 2 + 0.3;
  double fx, fy, hx, hy;
  path_at(sc, a, a->s, &fx, &fy, &hx, &hy);
  for (int j = 0; j < sc->agent_hwm; j++) {
    const agent_t *b = &sc->agents[j];
    if (b == a || !b->active || b->route < 0) continue;
    if (a->turn == TURN_NONE && b->type != T_PED &&
        (b->turn == TURN_NONE || (b->route == a->route && b->s - b->l <= b->p1)))
      continue;
    double bx, by, bvx, bvy, bh, bl = b->l;
    if (b->type == T_PED) { /* where it is and where it walks in the next WALK_AHEAD_S */
      walker_move(sc, b, &bx, &by, &bvx, &bvy);
      bh = atan2(bvy, bvx);
      const double ahead = hypot(bvx, bvy) * WALK_AHEAD_S;
      bl += ahead;
      bx += 0.5 * ahead * cos(bh);
      by += 0.5 * ahead * sin(bh);
    } else {
      pose(sc, b, sc->t, &bx, &by, &bh);
      bvx = b->v * cos(bh);
      bvy = b->v * sin(bh);
    }
    if (hypot(bx - fx, by - fy) > look + hypot(bl, b->w) / 2 + reach) continue;
    const double c = cos(bh), sn = sin(bh);
    for (int k = 1; k <= (int)(2 * PATH_LOOK_MAX) && 0.5 * k <= look; k++) {
      if (0.5 * k - 0.5 >= *gap) break;
      double px, py, tx, ty;
      path_at(sc, a, a->s + 0.5 * k, &px, &py, &tx, &ty);
      double lx, ly;
      box_local(bx, by, c, sn, px, py, &lx, &ly);
      const double ox = fmax(fabs(lx) - bl / 2, 0.0), oy = fmax(fabs(ly) - b->w / 2, 0.0);
      if (ox * ox + oy * oy < reach * reach) {
        /* a turner on its arc has the right of way over vehicles crossing its path: they stop for it */
        if (a->turn != TURN_NONE && a->s > a->p1 && b->type != T_PED && c * tx + sn * ty < 0.5) break;
        *gap = fmax(0.5 * k - 0.5, 0.01);
        *vlead = fmax(0.0, bvx * tx + bvy * ty);
        break;
      }
    }
  }
}

/* an oncoming vehicle going straight reaches a left-turner's path within TURN_GAP_S (at 1.5
 * m/s^2 from its speed now), or is on it; not one stopped on red, nor one held up behind an
 * oncoming turner waiting (two left-turners facing each other both go; a right-turner leaves
 * the oncoming lane before the left-turner's path) */
static bool oncoming(const rs_scene_t *sc, const route_t *rt) {
  for (int ri = 0; ri < sc->nroutes; ri++) {
    const route_t *ro = &sc->routes[ri];
    if (ro->pedestrian || ro->dx != -rt->dx || ro->dy != -rt->dy) continue;
    const double lc = -(ro->x0 * ro->dx + ro->y0 * ro->dy);
    for (int k = 0; k < ro->n; k++) {
      const agent_t *b = &sc->agents[ro->agents[k]];
      if (b->turn != TURN_NONE) { /* (a right-turner leaves before the left-turner's path) */
        if (b->v < 0.5 && b->s < b->p1 + 0.5 * PI * b->R) break; /* one waiting to turn: those behind it wait too */
        continue;
      }
      if (b->s < ro->stop_s + 0.5 && !green(sc, ro->phase, sc->t, true)) continue; /* stops on red */
      const double u = b->s - lc; /* its front, from the centre along its way */
      if (u - b->l > 3.0) continue; /* past */
      if (u > -5.0) return true;
      const double d = -5.0 - u, t = (-b->v + sqrt(b->v * b->v + 3.0 * d)) / 1.5;
      if (t < TURN_GAP_S) return true;
    }
  }
  return false;
}

/* a left-turner not yet on its arc, within 30 m of it, waits where it starts (nothing nearer in its
 * way): for a gap in the oncoming traffic, and, after its phase's all-red, for its next green */
static bool left_waits(const rs_scene_t *sc, const route_t *rt, const agent_t *a, double gap) {
  const double to_arc = a->p1 - a->s;
  if (a->turn != TURN_LEFT || to_arc <= 0.3 || to_arc >= 30.0 || to_arc >= gap) return false;
  return oncoming(sc, rt) || !(green(sc, rt->phase, sc->t, true) || green(sc, rt->phase, sc->t - ALLRED_S, true));
}

/* a walker would walk into a vehicle's body within WALK_BLOCK_M: it waits (a turning truck
 * standing across the crosswalk). A vehicle whose front is within 1.5 m of the walker stands
 * for the walker (path_obstacle()): the walker goes on. */
#define WALK_BLOCK_M 1.0
static bool walker_blocked(const rs_scene_t *sc, const agent_t *a) {
  double px, py, vx, vy;
  walker_move(sc, a, &px, &py, &vx, &vy);
  const double sp = hypot(vx, vy);
  if (sp < 0.05) return false;
  for (int j = 0; j < sc->agent_hwm; j++) {
    const agent_t *b = &sc->agents[j];
    if (!b->active || b->type == T_PED || b->route < 0) continue;
    double bx, by, bh;
    pose(sc, b, sc->t, &bx, &by, &bh);
    if (hypot(bx - px, by - py) > hypot(b->l, b->w) / 2 + WALK_BLOCK_M + 0.5) continue;
    const double c = cos(bh), sn = sin(bh);
    const double fx = bx + c * b->l / 2, fy = by + sn * b->l / 2;
    if (hypot(fx - px, fy - py) < 1.5) continue;
    for (int k = 1; k <= 4; k++) {
      double lx, ly;
      box_local(bx, by, c, sn, px + vx / sp * 0.25 * k * WALK_BLOCK_M, py + vy / sp * 0.25 * k * WALK_BLOCK_M, &lx, &ly);
      if (fabs(lx) < b->l / 2 + a->w / 2 && fabs(ly) < b->w / 2 + a->w / 2) return true;
    }
  }
  return false;
}

static void step(rs_scene_t *sc, double dt) {
  const double amax = 1.5, bcomf = 2.5, s0 = 2.0, T = 1.2;
  walkers_avoid(sc, dt);
  bool any_turn = false; /* (none when turn_share is 0: the traffic of before, to the bit) */
  for (int i = 0; i < sc->agent_hwm && !any_turn; i++) any_turn = sc->agents[i].active && sc->agents[i].turn;
  for (int ri = 0; ri < sc->nroutes; ri++) {
    route_t *rt = &sc->routes[ri];
    double rate = (rt->pedestrian ? sc->cfg.pedestrians_per_min : sc->cfg.vehicles_per_min / 2.0) / 60.0;
    for (int guard = 0; guard < 4 && rate > 0 && sc->t >= rt->next_spawn; guard++) {
      spawn(sc, ri);
      rt->next_spawn += -log(1.0 - rs_rng_uniform(&sc->rng)) / rate;
    }
    if (rate <= 0) rt->next_spawn = INFINITY;
    for (int k = 0; k < rt->n; k++) {
      agent_t *a = &sc->agents[rt->agents[k]];
      double gap = INFINITY, vlead = 0;
      for (int j = k - 1; j >= 0; j--) {
        const agent_t *lead = &sc->agents[rt->agents[j]];
        if (!rt->pedestrian && diverged(lead, a)) continue;
        gap = lead->s - lead->l - a->s;
        vlead = lead->v;
        break;
      }
      if (!rt->pedestrian && any_turn) {
        double g = INFINITY, vl = 0;
        path_obstacle(sc, a, &g, &vl);
        if (g < gap) gap = g, vlead = vl;
        if (left_waits(sc, rt, a, gap)) gap = fmax(a->p1 - a->s - 0.6, 0.01), vlead = 0; /* its front past the line */
      }
      double to_stop = rt->stop_s - a->s;
      if (to_stop > -0.5 && !green(sc, rt->phase, sc->t, !rt->pedestrian)) {
        /* amber: go when it cannot stop comfortably */
        bool committed = green(sc, rt->phase, sc->t, true) && to_stop < a->v * a->v / (2 * bcomf);
        if (!committed && to_stop < gap) {
          gap = fmax(to_stop, 0.01);
          vlead = 0;
        }
      }
      double acc;
      if (rt->pedestrian) {
        if (any_turn && walker_blocked(sc, a)) gap = 0.0;
        acc = gap < 1.0 ? -a->v / dt : a->yield ? -a->v / 0.5 : (a->v0 - a->v) / 0.5;
      } else {
        double v0 = a->v0;
        if (a->turn != TURN_NONE && a->s > a->p1 && a->s - a->l < a->p1 + 0.5 * PI * a->R)
          v0 = fmin(v0, a->vturn); /* on the arc */
        double sstar = s0 + fmax(0.0, a->v * T + a->v * (a->v - vlead) / (2 * sqrt(amax * bcomf)));
        double free = 1.0 - pow(a->v / v0, 4);
        acc = amax * (free - (isfinite(gap) ? (sstar / fmax(gap, 0.01)) * (sstar / fmax(gap, 0.01)) : 0.0));
        if (a->turn != TURN_NONE && a->s < a->p1 && a->v > a->vturn) {
          /* slowing down for the arc: at the rate that reaches its speed where it starts, once that
           * is 1.5 m/s^2 */
          const double need = (a->v * a->v - a->vturn * a->vturn) / (2.0 * fmax(a->p1 - a->s, 0.5));
          if (need > 1.5 && -need < acc) acc = -need;
        }
        if (acc < -9.0) acc = -9.0;
      }
      a->v = fmax(0.0, a->v + acc * dt);
      a->s += a->v * dt;
      a->lat += a->vlat * dt;
    }
    /* despawn at the end of the route (a turner in front may be behind one that went straight) */
    for (int k = 0; k < rt->n;) {
      agent_t *a = &sc->agents[rt->agents[k]];
      if (a->s - a->l > rt->length) {
        a->active = false;
        memmove(rt->agents + k, rt->agents + k + 1, sizeof rt->agents[0] * (size_t)(rt->n - 1 - k));
        rt->n--;
      } else {
        k++;
      }
    }
  }
  sc->t += dt;
}

int rs_scene_object_count(const rs_scene_t *sc) {
  int n = 0;
  for (int i = 0; i < MAX_AGENTS; i++) n += sc->agents[i].active;
  return n;
}

void rs_scene_new_turn(rs_scene_t *sc) { sc->wind = 0.8 + 0.4 * rs_rng_uniform(&sc->rng); }

static double wrap360(double a) {
  while (a >= 360.0) a -= 360.0;
  while (a < 0.0) a += 360.0;
  return a;
}

static bool az_overlap(double s1, double w1, double s2, double w2) {
  if (w1 >= 360 || w2 >= 360) return true;
  if (wrap360(s2 - s1) <= w1) return true;
  return wrap360(s1 - s2) <= w2;
}

/* centre and heading of an agent at time t */
static void pose(const rs_scene_t *sc, const agent_t *a, double t, double *cx, double *cy, double *hd) {
  if (a->route < 0) {
    *cx = a->s;
    *cy = a->v;
    *hd = a->v0;
    return;
  }
  const route_t *rt = &sc->routes[a->route];
  double s = a->s + a->v * (t - sc->t) - a->l / 2, lat = a->lat + a->vlat * (t - sc->t);
  if (a->turn != TURN_NONE) {
    double hx, hy;
    path_at(sc, a, s, cx, cy, &hx, &hy);
    *hd = atan2(hy, hx);
    return;
  }
  *cx = rt->x0 + rt->dx * s - rt->dy * lat;
  *cy = rt->y0 + rt->dy * s + rt->dx * lat;
  *hd = atan2(rt->dy, rt->dx);
}

int rs_scene_states(const rs_scene_t *sc, double t, rs_agent_state_t *out, int max) {
  static const char *const names[] = {"car", "van", "truck", "bus", "cyclist", "pedestrian"};
  int n = 0;
  for (int i = 0; i < sc->agent_hwm && n < max; i++) {
    const agent_t *a = &sc->agents[i];
    if (!a->active) continue;
    double cx, cy, hd;
    pose(sc, a, t, &cx, &cy, &hd);
    rs_agent_state_t *o = &out[n++];
    o->id = a->id;
    o->cls = a->type < 6 ? names[a->type] : "?";
    o->x = cx - sc->ox;
    o->y = cy - sc->oy;
    const double v = a->route < 0 ? 0.0 : a->v, vl = a->route < 0 ? 0.0 : a->vlat;
    o->vx = v * cos(hd) - vl * sin(hd);
    o->vy = v * sin(hd) + vl * cos(hd);
    o->heading = hd;
    o->length = a->l;
    o->width = a->w;
    o->height = a->h;
  }
  return n;
}

/* azimuth span of an agent over the next traffic step (cheap culling) */
static void coarse_span(rs_scene_t *sc, agent_t *a) {
  double cx, cy, hd;
  pose(sc, a, sc->t, &cx, &cy, &hd);
  double r = hypot(a->l, a->w) / 2 + a->v * STEP_S + 0.5;
  double dist = hypot(cx - sc->ox, cy - sc->oy);
  if (dist <= r + 0.1) {
    a->span0 = 0;
    a->spanw = 360;
    return;
  }
  double half = asin(r / dist) / D2R;
  a->span0 = fmod(az_of(sc, cx, cy) - half + 360.0, 360.0);
  a->spanw = 2 * half;
}

void rs_scene_prepare(rs_scene_t *sc, double t, double az_from, double az_to) {
  for (int i = 0; i < 100000 && sc->t + STEP_S <= t; i++) {
    step(sc, STEP_S);
    for (int k = 0; k < sc->agent_hwm; k++)
      if (sc->agents[k].active) coarse_span(sc, &sc->agents[k]);
  }
  double span_w = fmod(az_to - az_from + 360.0, 360.0);
  if (tilted(sc)) { /* a tilted ray's site azimuth is off its own by up to about tilt x tan(elevation) */
    az_from = fmod(az_from - sc->cfg.tilt_deg + 360.0, 360.0);
    span_w = fmin(359.0, span_w + 2.0 * sc->cfg.tilt_deg);
  }
  sc->ncand = 0;
  for (int i = 0; i < sc->agent_hwm && sc->ncand < MAX_CAND; i++) {
    agent_t *a = &sc->agents[i];
    if (!a->active) continue;
    if (a->spanw == 0) coarse_span(sc, a); /* new since the last step */
    if (!az_overlap(a->span0, a->spanw, az_from, span_w)) continue;
    double cx, cy, hd;
    pose(sc, a, t, &cx, &cy, &hd);
    if (sc->cfg.objects_max_range > 0) {
      double dist = hypot(cx, cy);
      if (dist < sc->cfg.objects_min_range || dist > sc->cfg.objects_max_range) continue;
    }
    cand_t *c = &sc->cand[sc->ncand];
    c->id = a->id;
    c->intensity = a->intensity;
    c->cyl = a->type == T_PED;
    c->cx = cx;
    c->cy = cy;
    c->c = cos(hd);
    c->s = sin(hd);
    c->hl = a->l / 2;
    c->hw = a->w / 2;
    c->h = a->h;
    c->z0 = a->clear;
    double xs[4], ys[4];
    for (int k = 0; k < 4; k++) {
      double lx = (k & 1 ? 1 : -1) * c->hl, ly = (k & 2 ? 1 : -1) * c->hw;
      xs[k] = cx + lx * c->c - ly * c->s;
      ys[k] = cy + lx * c->s + ly * c->c;
    }
    double st, wd;
    az_span(sc, xs, ys, 4, &st, &wd);
    c->az0 = fmod(st - 0.05 + 360.0, 360.0);
    c->aw = wd + 0.1;
    c->dmin = hypot(cx - sc->ox, cy - sc->oy) - hypot(c->hl, c->hw) - 0.1;
    if (az_overlap(st - 0.5, wd + 1.0, az_from, span_w)) sc->ncand++;
  }
  /* bucket them by degree from az_from (a ray looks only at its bucket) */
  sc->win0 = floor(az_from);
  sc->nwin = (int)ceil(span_w + (az_from - sc->win0)) + 1;
  if (sc->nwin > CAND_BUCKETS) sc->nwin = 0; /* window too wide: every ray scans all */
  if (sc->nwin > 0) {
    uint16_t counts[CAND_BUCKETS] = {0};
    for (int pass = 0; pass < 2; pass++) {
      if (pass == 1) {
        int total = 0;
        for (int b = 0; b < sc->nwin; b++) {
          sc->bstart[b] = (uint16_t)total;
          total += counts[b];
          counts[b] = 0;
        }
        sc->bstart[sc->nwin] = (uint16_t)total;
        if (total > CAND_BUCKET_ITEMS) {
          sc->nwin = 0;
          return;
        }
      }
      for (int k = 0; k < sc->ncand; k++) {
        const cand_t *c = &sc->cand[k];
        double lo = wrap360(c->az0 - sc->win0), hi = lo + c->aw;
        for (int b = 0; b < sc->nwin; b++) {
          /* bucket b covers [b, b+1) degrees after win0 */
          bool in = (hi >= b && lo < b + 1) || (c->aw >= 360) || (hi >= 360.0 + b && lo < 360.0 + b + 1);
          if (!in) continue;
          if (pass == 0) counts[b]++;
          else sc->bitems[sc->bstart[b] + counts[b]++] = (uint16_t)k;
        }
      }
    }
  }
}

/* an object along a ray: distance and the cosine of the incidence angle */
static double hit_cand(const cand_t *c, const double *o, const double *d, double *cosi) {
  if (c->cyl) {
    double t = hit_cyl(c->cx, c->cy, c->hw, 0.0, c->h, o, d);
    double px = o[0] + t * d[0] - c->cx, py = o[1] + t * d[1] - c->cy, n = hypot(px, py);
    *cosi = isfinite(t) && n > 1e-9 ? fabs(px * d[0] + py * d[1]) / n : 1.0;
    return t;
  }
  /* into the box frame */
  double px = o[0] - c->cx, py = o[1] - c->cy;
  double lo[3] = {px * c->c + py * c->s, -px * c->s + py * c->c, o[2]};
  double ld[3] = {d[0] * c->c + d[1] * c->s, -d[0] * c->s + d[1] * c->c, d[2]};
  float a[6] = {(float)-c->hl, (float)-c->hw, (float)c->z0, (float)c->hl, (float)c->hw, (float)c->h};
  int axis;
  double t = hit_box_axis(a, lo, ld, &axis);
  *cosi = fabs(ld[axis]);
  return t;
}

/* the nearest candidate object on a ray (INFINITY: none) */
static double nearest_object(rs_scene_t *sc, int k0, int k1, bool bucketed, double az, const double *o,
                             const double *d, double limit, const cand_t **hit, double *cosi) {
  double best = INFINITY;
  for (int kk = k0; kk < k1; kk++) {
    const cand_t *ck = &sc->cand[bucketed ? sc->bitems[kk] : kk];
    double da = az - ck->az0;
    if (da < 0) da += 360.0;
    if (da > ck->aw || ck->dmin > best || ck->dmin > limit) continue;
    double c, t = hit_cand(ck, o, d, &c);
    if (t < best) {
      best = t;
      *hit = ck;
      *cosi = c;
    }
  }
  return best;
}

/* detection, noise and intensity of one return; false: lost */
static bool sense(const rs_scene_t *sc, rs_hit_t *h, rs_rng_t *rng) {
  const double r = h->range, mr = sc->cfg.max_range;
  /* the range a surface of this intensity is seen to half the time: the
   * model's maximum for intensity 15, shorter for darker surfaces (returned
   * power ~ intensity / r^2), at most 10 % beyond it for brighter ones, less
   * in rain or dust; nothing beyond the maximum */
  double reach = mr * fmin(1.1, sqrt(fmax(h->intensity, 1) / 15.0));
  if (sc->cfg.attenuation > 0) reach *= exp(-0.5 * sc->cfg.attenuation * 1e-3 * r);
  double p = r > mr ? 0.0 : 1.0 / (1.0 + exp((r - reach) / (0.06 * reach)));
  if (rs_rng_uniform(rng) >= p * (1.0 - sc->cfg.dropout)) return false;
  double sd = sc->cfg.range_noise * (0.5 + r / 40.0) * (0.85 + 2.0 / fmax(h->intensity, 5));
  if (sc->cfg.noise_tail > 0 && rs_rng_uniform(rng) < sc->cfg.noise_tail) sd *= 5.0;
  double v = r + sd * rs_rng_normal(rng);
  h->range = (float)(v < 0.5 ? 0.5 : v);
  h->intensity = clamp_u8(h->intensity + rs_rng_normal(rng) * 3.0);
  return true;
}

void rs_scene_cast(rs_scene_t *sc, int slot, int block_az, int laser, double az, rs_rng_t *rng, rs_ray_t *out) {
  while (az >= 360.0) az -= 360.0;
  while (az < 0.0) az += 360.0;
  const double o[3] = {sc->ox, sc->oy, sc->oz};
  double d[3];
  dir_of(sc, laser, az, d);
  const bool table = sc->st != NULL && block_az >= 0 && block_az < AZ_STEPS && slot >= 0 && slot < sc->slots;
  /* the static scene along this firing (footprint included) */
  st_cell_t stc;
  if (table) {
    stc = sc->st[(size_t)block_az * (size_t)sc->slots + (size_t)slot];
  } else {
    memset(&stc, 0, sizeof stc);
    if (d[2] < 0) {
      stc.r1 = (float)(-o[2] / d[2]);
      stc.i1 = clamp_u8(12 * (0.3 + 0.7 * -d[2]));
    }
  }
  rs_hit_t ret[2] = {{stc.r1, stc.i1, (uint16_t)(stc.r1 > 0)}, {stc.r2, stc.i2, (uint16_t)(stc.r2 > 0)}};
  /* objects occlude what is behind them; across the footprint (three rays
   * side by side) an object's edge mixes with what is behind it */
  int k0 = 0, k1 = sc->ncand;
  bool bucketed = false;
  const double saz = tilted(sc) ? dir_az(d) : az; /* the ray's site azimuth */
  if (sc->nwin > 0) {
    int b = (int)wrap360(saz - sc->win0);
    if (b < sc->nwin) {
      k0 = sc->bstart[b];
      k1 = sc->bstart[b + 1];
      bucketed = true;
    }
  }
  if (k1 > k0) {
    const double limit = stc.r1 > 0 ? fmax(stc.r1, stc.r2) : INFINITY;
    const int nh = sc->cfg.beam_samples >= 3 ? 3 : 1;
    const double dh = sc->cfg.beam_div_h * 1e-3 / D2R;
    sub_hit_t h[3];
    int n = 0, objects = 0;
    for (int i = 0; i < nh; i++) {
      const double u = nh == 1 ? 0 : sub_off[i], w = nh == 1 ? 1 : sub_w[i];
      double ds[3];
      if (u == 0) memcpy(ds, d, sizeof ds);
      else dir_of(sc, laser, az + u * dh, ds);
      const cand_t *c = NULL;
      double cosi = 1.0, t = nearest_object(sc, k0, k1, bucketed, tilted(sc) ? dir_az(ds) : az, o, ds, limit, &c, &cosi);
      if (c && (stc.r1 == 0 || t < stc.r1)) {
        h[n++] = (sub_hit_t){t, w, c->intensity, cosi, c->id};
        objects++;
      } else if (stc.r1 > 0) {
        /* the static scene's brighter return stands for this part of the footprint */
        bool two = stc.r2 > 0 && stc.i2 > stc.i1;
        h[n++] = (sub_hit_t){two ? stc.r2 : stc.r1, w, 2.0 * (two ? stc.i2 : stc.i1), 1.0, 1};
      }
    }
    if (objects > 0) {
      beam_ret_t r[2];
      int nr = form_returns(h, n, sc->cfg.mix_depth, r);
      memset(ret, 0, sizeof ret);
      for (int k = 0; k < nr; k++)
        ret[k] = (rs_hit_t){(float)r[k].r, clamp_u8(r[k].inten), r[k].label};
    }
  }
  /* leaves: a ray through a canopy returns a leaf in its first metre with
   * probability fol_p x wind; what is behind is the second return */
  if (stc.fol > 0 && rs_rng_uniform(rng) * 255.0 < stc.fol_p * sc->wind) {
    float lr = stc.fol + (float)rs_rng_uniform(rng);
    if (ret[0].range == 0 || lr < ret[0].range - 0.3f) {
      ret[1] = ret[0];
      ret[0] = (rs_hit_t){lr, 30, RS_SCENE_LEAF};
    }
  }
  /* sensor effects: detection, noise, intensity */
  for (int k = 0; k < 2; k++)
    if (ret[k].range > 0 && !sense(sc, &ret[k], rng)) ret[k].range = 0;
  if (ret[0].range == 0 && ret[1].range != 0) {
    ret[0] = ret[1];
    ret[1].range = 0;
  }
  if (sc->cfg.spurious > 0 && rs_rng_uniform(rng) < sc->cfg.spurious) {
    /* rain or dust in front of whatever the beam would have hit: drops and
     * dust near the sensor return most (exponential, mean 8 m), up to 30 m */
    double far = ret[0].range > 0 ? fmin(30.0, ret[0].range - 0.5) : 30.0;
    /* inverse CDF of the exponential truncated to [1, far] */
    double r = 1.0 - 8.0 * log(1.0 - rs_rng_uniform(rng) * (1.0 - exp(-(far - 1.0) / 8.0)));
    if (far > 1.0) {
      ret[1] = ret[0];
      ret[0] = (rs_hit_t){(float)r, (uint8_t)(2 + 10 * rs_rng_uniform(rng)), RS_SCENE_LEAF};
    }
  }
  if (ret[1].range == 0) ret[1].label = 0;
  if (ret[0].range == 0) ret[0].label = 0;
  out->first = ret[0];
  out->second = ret[1];
}

/* check_scene - ray casting against hand-computed ranges (ground, a box
 * at a known place, occlusion), the beam's physics (footprint, mixed and
 * separate returns at depth edges, noise growing with range, detection
 * falling with intensity and range), scene knobs, presets, determinism. */
#include "roadscan/util/error.h"
#include "roadscan/sim/scene.h"
#include "testutil.h"

#include <math.h>
#include <stdbool.h>
#include <string.h>

#define D2R (3.14159265358979323846 / 180.0)

static rs_scene_cfg_t quiet_cfg(void) {
  rs_scene_cfg_t c;
  rs_scene_preset("light", &c);
  c.range_noise = 0;
  c.noise_tail = 0;
  c.dropout = 0;
  c.spurious = 0;
  c.pole_x = -11.5;
  c.pole_y = -11.5;
  c.pole_height = 5.0;
  return c;
}

START_TEST(t_ground_and_box) {
  static rs_sensor_t s;
  rs_sensor_init(&s, RS_MODEL_VLP32C);
  rs_scene_cfg_t c = quiet_cfg();
  rs_scene_t *sc = rs_scene_create_empty(&c, &s);
  rs_rng_t rng;
  rs_rng_seed(&rng, 3);
  rs_ray_t r;
  /* laser 0 points 25 degrees down: the ground is 5 / sin 25 away */
  rs_scene_prepare(sc, 0.0, 0.0, 359.9);
  rs_scene_cast(sc, -1, -1, 0, 45.0, &rng, &r);
  ck_assert_float_eq_tol(r.first.range, 5.0 / sin(25 * D2R), 1e-4);
  ck_assert_int_eq(r.first.label, 1);
  /* laser 5 is level: nothing to hit */
  rs_scene_cast(sc, -1, -1, 5, 45.0, &rng, &r);
  ck_assert_float_eq_tol(r.first.range, 0.0, 1e-9);
  /* a 4 x 2 x 6 m box 20 m north of the sensor, long side east-west: its
   * south face is at y = 8.5 - 1 = 7.5, 19 m from the pole at y = -11.5 */
  rs_scene_add_box(sc, -11.5, 8.5, 0.0, 4.0, 2.0, 6.0, 0.0, 42);
  rs_scene_prepare(sc, 0.0, 355.0, 5.0);
  rs_scene_cast(sc, -1, -1, 5, 0.0, &rng, &r);
  ck_assert_float_eq_tol(r.first.range, 19.0, 1e-4);
  ck_assert_int_eq(r.first.label, 42);
  /* 5 degrees to the side: x offset 19 tan 5 = 1.66 m, within the 2 m half length */
  rs_scene_cast(sc, -1, -1, 5, 5.0, &rng, &r);
  ck_assert_float_eq_tol(r.first.range, 19.0 / cos(5 * D2R), 1e-3);
  /* 7 degrees: 2.33 m, past the corner: misses */
  rs_scene_prepare(sc, 0.0, 350.0, 10.0);
  rs_scene_cast(sc, -1, -1, 5, 7.0, &rng, &r);
  ck_assert_float_eq_tol(r.first.range, 0.0, 1e-9);
  /* the box hides the ground behind it: laser 15 (-4 deg) meets the ground
   * at 5 / tan 4 = 71.5 m horizontally, but the box is at 19 m */
  rs_scene_cast(sc, -1, -1, 15, 0.0, &rng, &r);
  ck_assert_float_eq_tol(r.first.range, 19.0 / cos(4 * D2R), 1e-3);
  ck_assert_int_eq(r.first.label, 42);
  /* a box turned 90 degrees: now 2 m along x, its south face at 8.5 - 2 = 6.5 */
  rs_scene_t *sc2 = rs_scene_create_empty(&c, &s);
  rs_scene_add_box(sc2, -11.5, 8.5, 0.0, 4.0, 2.0, 6.0, 3.14159265358979 / 2, 43);
  rs_scene_prepare(sc2, 0.0, 350.0, 10.0);
  rs_scene_cast(sc2, -1, -1, 5, 0.0, &rng, &r);
  ck_assert_float_eq_tol(r.first.range, 18.0, 1e-4);
  rs_scene_destroy(sc2);
  rs_scene_destroy(sc);
}
END_TEST

START_TEST(t_effects) {
  static rs_sensor_t s;
  rs_sensor_init(&s, RS_MODEL_VLP32C);
  rs_scene_cfg_t c = quiet_cfg();
  c.range_noise = 0.05;
  rs_scene_t *sc = rs_scene_create_empty(&c, &s);
  rs_rng_t rng;
  rs_rng_seed(&rng, 9);
  rs_scene_prepare(sc, 0.0, 0.0, 359.9);
  double sum = 0, sum2 = 0, truth = 5.0 / sin(25 * D2R);
  const int N = 20000;
  for (int i = 0; i < N; i++) {
    rs_ray_t r;
    rs_scene_cast(sc, -1, -1, 0, 100.0, &rng, &r);
    double d = r.first.range - truth;
    sum += d;
    sum2 += d * d;
  }
  /* sd = range_noise x (0.5 + r / 40) x (0.85 + 2 / intensity); the ground
   * (reflectivity 12) seen 25 degrees down returns 12 x (0.3 + 0.7 sin 25) = 7 */
  const double want = 0.05 * (0.5 + truth / 40.0) * (0.85 + 2.0 / 7.0);
  ck_assert_double_eq_tol(sum / N, 0.0, 0.002);
  ck_assert_double_eq_tol(sqrt(sum2 / N), want, 0.04 * want);
  rs_scene_destroy(sc);
  /* farther, noisier: laser 15 (-4 deg) meets the ground 71.7 m away */
  sc = rs_scene_create_empty(&c, &s);
  rs_scene_prepare(sc, 0.0, 0.0, 359.9);
  double far2 = 0, far_truth = 5.0 / sin(4 * D2R);
  int nfar = 0;
  for (int i = 0; i < N; i++) {
    rs_ray_t r;
    rs_scene_cast(sc, -1, -1, 15, 100.0, &rng, &r);
    if (r.first.range == 0) continue;
    far2 += (r.first.range - far_truth) * (r.first.range - far_truth);
    nfar++;
  }
  ck_assert_int_gt(nfar, N / 4);
  ck_assert_double_gt(sqrt(far2 / nfar), 1.8 * want);
  rs_scene_destroy(sc);
  /* dropouts and spurious returns at their rates */
  c = quiet_cfg();
  c.dropout = 0.1;
  c.spurious = 0.05;
  sc = rs_scene_create_empty(&c, &s);
  rs_scene_prepare(sc, 0.0, 0.0, 359.9);
  int lost = 0, spur = 0;
  for (int i = 0; i < N; i++) {
    rs_ray_t r;
    rs_scene_cast(sc, -1, -1, 0, 100.0, &rng, &r);
    if (r.first.label == 2) spur++;
    else if (r.first.range == 0) lost++;
  }
  ck_assert_int_ge(lost, N * 0.1 * 0.9);
  ck_assert_int_le(lost, N * 0.1 * 1.1);
  ck_assert_int_ge(spur, N * 0.05 * 0.8);
  ck_assert_int_le(spur, N * 0.05 * 1.2);
  rs_scene_destroy(sc);
}
END_TEST

/* The beam has a footprint (3 x 1.5 mrad): at a depth edge the return
 * depends on how much of it each surface fills. */
START_TEST(t_beam) {
  static rs_sensor_t s;
  rs_sensor_init(&s, RS_MODEL_VLP32C);
  rs_scene_cfg_t c = quiet_cfg();
  rs_rng_t rng;
  rs_rng_seed(&rng, 5);
  rs_ray_t r;
  /* a box whose south face is 19 m north of the sensor, its west edge at
   * x = -11.5 (straight north of the sensor): level laser 5 at azimuths
   * around 0 sweeps across that edge, with nothing behind */
  rs_scene_t *sc = rs_scene_create_empty(&c, &s);
  rs_scene_add_box(sc, -9.5, 8.5, 0.0, 4.0, 2.0, 6.0, 0.0, 42);
  rs_scene_prepare(sc, 0.0, 350.0, 10.0);
  double div = 3.0e-3 / D2R; /* degrees */
  rs_scene_cast(sc, -1, -1, 5, 1.0, &rng, &r); /* well inside */
  ck_assert_float_eq_tol(r.first.range, 19.0 / cos(1.0 * D2R), 1e-3);
  const int inside = r.first.intensity;
  /* the centre ray misses by a fifth of the divergence, a side ray hits:
   * the box is seen, dimmer (part of the footprint) */
  rs_scene_cast(sc, -1, -1, 5, 360.0 - 0.2 * div, &rng, &r);
  ck_assert_int_eq(r.first.label, 42);
  ck_assert_int_lt(r.first.intensity, inside);
  /* the same direction gives the same return (the edge repeats) */
  rs_ray_t r2;
  rs_scene_cast(sc, -1, -1, 5, 360.0 - 0.2 * div, &rng, &r2);
  ck_assert_float_eq(r.first.range, r2.first.range);
  /* well outside the footprint: nothing */
  rs_scene_cast(sc, -1, -1, 5, 360.0 - div, &rng, &r);
  ck_assert_float_eq_tol(r.first.range, 0.0, 1e-9);
  rs_scene_destroy(sc);
  /* two boxes side by side, faces 0.4 m apart in depth (less than the
   * mixing depth): across the seam the range lies between the two */
  sc = rs_scene_create_empty(&c, &s);
  rs_scene_add_box(sc, -13.5, 8.5, 0.0, 4.0, 2.0, 6.0, 0.0, 42);  /* face y = 7.5: 19 m */
  rs_scene_add_box(sc, -9.5, 8.9, 0.0, 4.0, 2.0, 6.0, 0.0, 43);   /* face y = 7.9: 19.4 m */
  rs_scene_prepare(sc, 0.0, 350.0, 10.0);
  int mixed = 0;
  for (double a = -div; a <= div; a += div / 20) {
    rs_scene_cast(sc, -1, -1, 5, fmod(a + 360.0, 360.0), &rng, &r);
    double flat = r.first.range * cos(a * D2R);
    if (flat > 19.02 && flat < 19.38) mixed++;
    ck_assert_float_eq_tol(r.second.range, 0.0, 1e-9); /* one return */
  }
  ck_assert_int_gt(mixed, 2);
  rs_scene_destroy(sc);
  /* 6 m apart: two returns at the edge, the brighter one strongest */
  sc = rs_scene_create_empty(&c, &s);
  rs_scene_add_box(sc, -13.5, 8.5, 0.0, 4.0, 2.0, 6.0, 0.0, 42);  /* 19 m */
  rs_scene_add_box(sc, -9.5, 14.5, 0.0, 4.0, 2.0, 6.0, 0.0, 43);  /* 25 m */
  rs_scene_prepare(sc, 0.0, 350.0, 10.0);
  rs_scene_cast(sc, -1, -1, 5, 360.0 - 0.2 * div, &rng, &r); /* mostly on the near box */
  ck_assert_float_eq_tol(r.first.range, 19.0, 0.01);
  ck_assert_float_eq_tol(r.second.range, 25.0, 0.01);
  ck_assert_int_gt(r.first.intensity, r.second.intensity);
  rs_scene_cast(sc, -1, -1, 5, 0.2 * div, &rng, &r); /* mostly on the far one */
  ck_assert_float_eq_tol(r.first.range, 19.0, 0.01);
  ck_assert_float_eq_tol(r.second.range, 25.0, 0.01);
  ck_assert_int_lt(r.first.intensity, r.second.intensity);
  rs_scene_destroy(sc);
  /* detection falls with range and intensity: a bright and a dark box at
   * 90 m (VLP-16: 100 m for intensity 15 and brighter) */
  static rs_sensor_t s16;
  rs_sensor_init(&s16, RS_MODEL_VLP16);
  int seen[2] = {0, 0};
  for (int k = 0; k < 2; k++) {
    sc = rs_scene_create_empty(&c, &s16);
    rs_scene_add_box(sc, -11.5, 79.5, 0.0, 4.0, 2.0, 8.0, 0.0, 42); /* face y = 78.5: 90 m */
    rs_scene_set_intensity(sc, 42, k == 0 ? 100 : 3);
    rs_scene_prepare(sc, 0.0, 350.0, 10.0);
    for (int i = 0; i < 2000; i++) {
      rs_scene_cast(sc, -1, -1, 1, 0.0, &rng, &r); /* laser 1: +1 degree */
      seen[k] += r.first.label == 42;
    }
    rs_scene_destroy(sc);
  }
  ck_assert_int_gt(seen[0], 1800);
  ck_assert_int_lt(seen[1], 100);
}
END_TEST

START_TEST(t_knobs) {
  rs_scene_cfg_t c;
  ck_assert(rs_scene_preset("rush", &c));
  ck_assert(rs_scene_preset("far", &c));
  ck_assert_double_eq(c.objects_min_range, 100.0);
  ck_assert(rs_scene_preset("storm", &c));
  ck_assert_double_eq(c.packet_loss, 0.05);
  ck_assert(!rs_scene_preset("blizzard", &c));
  char err[256];
  ck_assert_int_eq(rs_scene_set(&c, "pole_height", "6.5", err, sizeof err), RS_OK);
  ck_assert_double_eq(c.pole_height, 6.5);
  ck_assert_int_eq(rs_scene_set(&c, "trees_per_leg", "3", err, sizeof err), RS_OK);
  ck_assert_int_eq(c.trees_per_leg, 3);
  ck_assert_int_eq(rs_scene_set(&c, "trees_per_leg", "2.5", err, sizeof err), RS_E_INVAL);
  ck_assert_int_eq(rs_scene_set(&c, "pole_height", "high", err, sizeof err), RS_E_INVAL);
  ck_assert_ptr_nonnull(strstr(err, "pole_height: 'high' is not a number"));
  ck_assert_int_eq(rs_scene_set(&c, "pole_height", "100", err, sizeof err), RS_E_INVAL);
  ck_assert_ptr_nonnull(strstr(err, "out of range"));
  ck_assert_int_eq(rs_scene_set(&c, "colour", "red", err, sizeof err), RS_E_INVAL);
  ck_assert_ptr_nonnull(strstr(err, "no scene key 'colour'; there are: site_seed pole_height"));
}
END_TEST

START_TEST(t_traffic_queues) {
  /* vehicles stop at the line on red and stand there for tens of seconds */
  static rs_sensor_t s;
  rs_sensor_init(&s, RS_MODEL_VLP16);
  rs_scene_cfg_t c = quiet_cfg();
  c.vehicles_per_min = 20;
  c.warmup_s = 0;
  rs_scene_t *sc = rs_scene_create(&c, &s, 10.0, 5);
  rs_rng_t rng;
  rs_rng_seed(&rng, 1);
  /* a level ray along the eastbound lanes just before the stop line, seen
   * from the sensor: count how long something stands there during one cycle */
  int seen = 0, runs = 0, longest = 0;
  for (double t = 0; t < 120.0; t += 0.5) {
    rs_scene_prepare(sc, t, 0, 359.99);
    rs_ray_t r;
    /* toward (-16, -1.75) from (-11.5, -11.5): azimuth of the first queued car */
    double az = atan2(-16.0 + 11.5, -1.75 + 11.5) / D2R + 360.0;
    rs_scene_cast(sc, -1, -1, 0, az, &rng, &r);
    int lvl = 0;
    for (int l = 0; l < s.lasers; l++) {
      rs_scene_cast(sc, -1, -1, l, az, &rng, &r);
      if (r.first.label >= 3) lvl = 1;
    }
    if (lvl) {
      seen++;
      runs++;
      if (runs > longest) longest = runs;
    } else {
      runs = 0;
    }
  }
  ck_assert_int_gt(seen, 0);
  ck_assert_int_ge(longest, 20); /* at least 10 s standing at the line */
  ck_assert_int_gt(rs_scene_object_count(sc), 5);
  rs_scene_destroy(sc);
}
END_TEST

/* walker_space's walkers over 60 s of the rush preset, sampled every 0.1 s: how many
 * pairs come within 0.45 m (bodies are 0.5 m wide), the longest any pair stays within 0.6 m (s),
 * and the largest mean gap between a walker's reported velocity and its moves (m/s) */
static void walkers_run(double space, int *pairs, double *longest, double *vel_err) {
  static rs_sensor_t s;
  rs_sensor_init(&s, RS_MODEL_VLP16);
  rs_scene_cfg_t c;
  ck_assert(rs_scene_preset("rush", &c));
  c.walker_space = space;
  rs_scene_t *sc = rs_scene_create(&c, &s, 10.0, 7);
  ck_assert_ptr_nonnull(sc);
  enum { MAXW = 256 };
  static rs_agent_state_t st[MAXW], prev[MAXW];
  static uint16_t near_a[4096], near_b[4096];
  static int near_n[4096];
  int np = 0, nprev = 0, close = 0, run_max = 0;
  double err_sum = 0;
  long err_n = 0;
  for (int k = 0; k < 600; k++) {
    const double t = 0.1 * k;
    rs_scene_prepare(sc, t, 0, 359.99);
    int n = 0, all = rs_scene_states(sc, t, st, MAXW);
    ck_assert_int_lt(all, MAXW);
    for (int i = 0; i < all; i++) /* the walkers */
      if (strcmp(st[i].cls, "pedestrian") == 0) st[n++] = st[i];
    for (int i = 0; i < n; i++) {
      for (int j = 0; j < nprev; j++) /* the move since the last sample against the velocity reported */
        if (prev[j].id == st[i].id) {
          err_sum += hypot((st[i].x - prev[j].x) / 0.1 - 0.5 * (st[i].vx + prev[j].vx),
                           (st[i].y - prev[j].y) / 0.1 - 0.5 * (st[i].vy + prev[j].vy));
          err_n++;
        }
      for (int j = i + 1; j < n; j++) {
        const double d = hypot(st[i].x - st[j].x, st[i].y - st[j].y);
        if (d >= 0.6) continue;
        const uint16_t a = st[i].id < st[j].id ? st[i].id : st[j].id, b = st[i].id ^ st[j].id ^ a;
        int q = 0;
        while (q < np && !(near_a[q] == a && near_b[q] == b)) q++;
        if (q == np && np < 4096) near_a[np] = a, near_b[np] = b, near_n[np] = 0, np++;
        if (q < np) {
          if (d < 0.45 && near_n[q] >= 0) close++, near_n[q] = -1000000; /* counted once */
          near_n[q]++;
          if (near_n[q] > run_max) run_max = near_n[q];
        }
      }
    }
    memcpy(prev, st, sizeof st[0] * (size_t)n);
    nprev = n;
  }
  rs_scene_destroy(sc);
  *pairs = close;
  *longest = 0.1 * run_max;
  *vel_err = err_n ? err_sum / (double)err_n : 0.0;
}

START_TEST(t_walkers_keep_apart) {
  int pairs;
  double longest, vel_err;
  walkers_run(0.0, &pairs, &longest, &vel_err); /* as before: they walk through each other */
  ck_assert_int_ge(pairs, 10);
  walkers_run(0.8, &pairs, &longest, &vel_err); /* the default */
  ck_assert_int_le(pairs, 2);
  ck_assert_double_lt(longest, 5.0); /* no two stuck against each other */
  ck_assert_double_lt(vel_err, 0.1);  /* the states' velocity is the step aside's too */
  rs_scene_cfg_t c;
  ck_assert(rs_scene_preset("light", &c));
  ck_assert_double_eq(c.walker_space, 0.8);
}
END_TEST

/* do two road users' boxes overlap, each shrunk by 0.05 m (separating axes) */
static bool boxes_overlap(const rs_agent_state_t *a, const rs_agent_state_t *b) {
  const rs_agent_state_t *ab[2] = {a, b};
  double cx[2][4], cy[2][4];
  for (int i = 0; i < 2; i++) {
    const double c = cos(ab[i]->heading), s = sin(ab[i]->heading);
    const double hl = ab[i]->length / 2 - 0.05, hw = ab[i]->width / 2 - 0.05;
    for (int k = 0; k < 4; k++) {
      const double lx = (k == 0 || k == 3) ? hl : -hl, ly = k < 2 ? hw : -hw;
      cx[i][k] = ab[i]->x + lx * c - ly * s;
      cy[i][k] = ab[i]->y + lx * s + ly * c;
    }
  }
  for (int i = 0; i < 2; i++)
    for (int k = 0; k < 2; k++) { /* the two axes of each box */
      const double nx = cx[i][k + 1] - cx[i][k], ny = cy[i][k + 1] - cy[i][k];
      double lo[2] = {INFINITY, INFINITY}, hi[2] = {-INFINITY, -INFINITY};
      for (int j = 0; j < 2; j++)
        for (int q = 0; q < 4; q++) {
          const double p = cx[j][q] * nx + cy[j][q] * ny;
          lo[j] = fmin(lo[j], p);
          hi[j] = fmax(hi[j], p);
        }
      if (hi[0] < lo[1] || hi[1] < lo[0]) return false;
    }
  return true;
}

/* turn_share: 90 s of a preset's traffic sampled every 0.1 s. Vehicles whose heading turns by a
 * quarter, right and left; the fastest any takes its arc (m/s); how many leave on the wrong lane
 * (right-turners on the outer lane's line, 5.25 m right of the road's centre line, left-turners on
 * the inner one's, 1.75 m), trucks or buses that turn, pairs of boxes that overlap (vehicles with
 * vehicles or walkers), and the largest mean gap between a turner's reported velocity and its move */
typedef struct {
  int right, left, wrong_lane, long_turned, overlaps;
  double fastest_right, fastest_left, vel_err;
} turns_t;
static turns_t turns_run(const char *preset, double share) {
  static rs_sensor_t s;
  rs_sensor_init(&s, RS_MODEL_VLP16);
  rs_scene_cfg_t c;
  ck_assert(rs_scene_preset(preset, &c));
  if (share >= 0) c.turn_share = share;
  rs_scene_t *sc = rs_scene_create(&c, &s, 10.0, 9);
  ck_assert_ptr_nonnull(sc);
  double ox, oy, oz;
  rs_scene_origin(sc, &ox, &oy, &oz);
  enum { MAXA = 512, MAXID = 65536 };
  static rs_agent_state_t st[MAXA], prev[MAXA];
  static float first_heading[MAXID];
  static uint8_t seen[MAXID], done[MAXID];
  memset(seen, 0, sizeof seen);
  memset(done, 0, sizeof done);
  turns_t r = {0};
  int nprev = 0;
  double err_sum = 0;
  long err_n = 0;
  for (int k = 0; k < 900; k++) {
    const double t = 0.1 * k;
    rs_scene_prepare(sc, t, 0, 359.99);
    const int n = rs_scene_states(sc, t, st, MAXA);
    ck_assert_int_lt(n, MAXA);
    for (int i = 0; i < n; i++) {
      const rs_agent_state_t *a = &st[i];
      const bool ped = strcmp(a->cls, "pedestrian") == 0;
      for (int j = i + 1; j < n; j++) {
        const bool ped2 = strcmp(st[j].cls, "pedestrian") == 0;
        if ((ped && ped2) || hypot(a->x - st[j].x, a->y - st[j].y) > 15.0) continue;
        r.overlaps += boxes_overlap(a, &st[j]);
      }
      if (ped) continue;
      if (!seen[a->id]) seen[a->id] = 1, first_heading[a->id] = (float)a->heading;
      const double turned = remainder(a->heading - first_heading[a->id], 2 * M_PI);
      for (int j = 0; j < nprev; j++) /* a turner's move since the last sample against its velocity */
        if (prev[j].id == a->id && fabs(remainder(a->heading - prev[j].heading, 2 * M_PI)) > 1e-6) {
          err_sum += hypot((a->x - prev[j].x) / 0.1 - 0.5 * (a->vx + prev[j].vx),
                           (a->y - prev[j].y) / 0.1 - 0.5 * (a->vy + prev[j].vy));
          err_n++;
          const double v = hypot(a->vx, a->vy);
          if (turned < 0) r.fastest_right = fmax(r.fastest_right, v);
          else r.fastest_left = fmax(r.fastest_left, v);
        }
      if (fabs(fabs(turned) - M_PI / 2) < 1e-3 && !done[a->id]) {
        done[a->id] = 1;
        if (turned < 0) r.right++;
        else r.left++;
        if (strcmp(a->cls, "truck") == 0 || strcmp(a->cls, "bus") == 0) r.long_turned++;
        /* its offset right of the centre line of the road it is on now */
        const double wx = a->x + ox, wy = a->y + oy, off = wx * sin(a->heading) - wy * cos(a->heading);
        if (fabs(off - (turned < 0 ? 5.25 : 1.75)) > 0.01) r.wrong_lane++;
      }
    }
    memcpy(prev, st, sizeof st[0] * (size_t)n);
    nprev = n;
  }
  rs_scene_destroy(sc);
  r.vel_err = err_n ? err_sum / (double)err_n : 0.0;
  return r;
}

START_TEST(t_vehicles_turn) {
  turns_t r = turns_run("turns", -1);
  ck_assert_int_ge(r.right, 3);
  ck_assert_int_ge(r.left, 2);
  ck_assert_int_eq(r.wrong_lane, 0);
  ck_assert_int_eq(r.long_turned, 0);
  ck_assert_int_eq(r.overlaps, 0); /* they yield to each other and to walkers */
  ck_assert_double_gt(r.fastest_right, 2.0); /* the arcs at a driver's lateral acceleration */
  ck_assert_double_le(r.fastest_right, sqrt(3.5 * 6.0) + 0.01);
  ck_assert_double_gt(r.fastest_left, 2.0);
  ck_assert_double_le(r.fastest_left, sqrt(3.5 * 10.5) + 0.01);
  ck_assert_double_lt(r.vel_err, 0.1); /* the states' velocity follows the arc */
  /* every vehicle turns: still nothing overlapping, nobody on a wrong lane */
  r = turns_run("turns", 1.0);
  ck_assert_int_ge(r.right + r.left, 10);
  ck_assert_int_eq(r.wrong_lane, 0);
  ck_assert_int_eq(r.long_turned, 0);
  ck_assert_int_eq(r.overlaps, 0);
  /* the other presets: nobody turns */
  r = turns_run("light", -1);
  ck_assert_int_eq(r.right + r.left, 0);
  rs_scene_cfg_t c;
  ck_assert(rs_scene_preset("rush", &c));
  ck_assert_double_eq(c.turn_share, 0.0);
  ck_assert(rs_scene_preset("turns", &c));
  ck_assert_double_eq(c.turn_share, 0.25);
  char err[256];
  ck_assert_int_eq(rs_scene_set(&c, "turn_share", "1.5", err, sizeof err), RS_E_INVAL);
  ck_assert_ptr_nonnull(strstr(err, "turn_share"));
}
END_TEST

int main(void) {
  Suite *s = suite_create("scene");
  TCase *tc = tcase_create("core");
  tcase_set_timeout(tc, 120);
  tcase_add_test(tc, t_ground_and_box);
  tcase_add_test(tc, t_effects);
  tcase_add_test(tc, t_beam);
  tcase_add_test(tc, t_knobs);
  tcase_add_test(tc, t_traffic_queues);
  tcase_add_test(tc, t_walkers_keep_apart);
  tcase_add_test(tc, t_vehicles_turn);
  suite_add_tcase(s, tc);
  return tu_run(s);
}

/* check_ground - the ground under a place from hand-built background models:
 * every map cell's static surface is where its beam meets a made-up scene
 * (a road, a tilted sensor's road, walls, a roof, stray returns below the
 * road); then the scenes with no ground (a small room, a sensor on its side,
 * a model of another sensor), and the object stage's top above the ground. */
#include "roadscan/util/error.h"
#include "roadscan/perception/ground.h"
#include "roadscan/perception/objects.h"
#include "testutil.h"

#include <math.h>
#include <string.h>

#define PI 3.14159265358979323846
#define COLS 1800
#define FAR_RISE_M 140.0

static rs_sensor_t sensor;
static rs_bg_model_t model;
static rs_ground_t ground;
static rs_slot_t slot;
static rs_objects_t objs;
static rs_object_list_t list;

typedef struct {
  double h;          /* sensor above the road (m) */
  double gx, gy;     /* the road's slope in the sensor frame: z = -h + gx x + gy y */
  bool wall;         /* a wall x = 25 m, |y| <= 30 m, up to 3 m above the sensor */
  bool roof;         /* a roof 3 m above the road over -50 <= x <= -20, -50 <= y <= -20 */
  bool stray;        /* two returns 1 m below the road at (15.5, 15.5) */
  bool room;         /* everything 1.5 m away */
  bool on_side;      /* the "road" is the plane x = -h: the sensor lies on its side */
  bool far_rise;     /* the road 1 m higher from 140 m out (a step's face at 140 m), seen out to 200 m */
} scene_t;

/* the range of the first thing the beam (elevation el, azimuth az clockwise from +Y) meets; 0: none */
static double cast(const scene_t *sc, int row, int col, double *z_out) {
  const int laser = sensor.laser_of_row[row];
  const double ce = sensor.cos_el[laser], se = sensor.sin_el[laser];
  const double az = (col + 0.5) * 2.0 * PI / COLS, dx = ce * sin(az), dy = ce * cos(az), dz = se;
  if (sc->room) return 1.5;
  double best = 0.0;
  if (sc->on_side) {
    if (dx < -1e-6) best = -sc->h / dx;
  } else {
    const double den = dz - sc->gx * dx - sc->gy * dy; /* t (dz - gx dx - gy dy) = -h */
    if (den < -1e-6) best = -sc->h / den;
    if (sc->far_rise && dz < -1e-6) {
      const double up = (1.0 - sc->h) / dz, face = FAR_RISE_M / ce; /* the raised road's range; the face's */
      if (up * ce >= FAR_RISE_M) best = up;                            /* on the raised road */
      else if (best * ce > FAR_RISE_M) best = face;                    /* met its face first */
    }
  }
  if (sc->wall && dx > 1e-6) {
    const double t = 25.0 / dx, y = t * dy, z = t * dz;
    if (fabs(y) <= 30.0 && z <= 3.0 && z >= -sc->h && (best == 0.0 || t < best)) best = t;
  }
  if (sc->roof && dz < -1e-6) {
    const double t = (3.0 - sc->h) / dz, x = t * dx, y = t * dy;
    if (t > 0 && x >= -50 && x <= -20 && y >= -50 && y <= -20 && (best == 0.0 || t < best)) best = t;
  }
  if (best > (sc->far_rise ? 200.0 : 120.0)) best = 0.0;
  *z_out = best * dz;
  return best;
}

static void make_model(const scene_t *sc, rs_model_t m) {
  ck_assert_int_eq(rs_sensor_init(&sensor, m), RS_OK);
  rs_bg_model_free(&model);
  ck_assert_int_eq(rs_bg_model_alloc(&model, m, sensor.lasers, COLS), RS_OK);
  for (int row = 0; row < sensor.lasers; row++)
    for (int col = 0; col < COLS; col++) {
      const uint32_t cell = (uint32_t)row * COLS + (uint32_t)col;
      double z;
      const double r = cast(sc, row, col, &z);
      model.n[cell] = 0;
      if (r <= 0) continue;
      const uint16_t cm = (uint16_t)lround(r * 100.0);
      model.n[cell] = 1;
      model.lo[cell * RS_BG_SURFACES] = (uint16_t)(cm - 5);
      model.hi[cell * RS_BG_SURFACES] = (uint16_t)(cm + 5);
    }
  if (sc->stray) { /* two cells whose surface lies below the road at (15.5, 15.5) (its beams' ranges there) */
    const double az = atan2(15.5, 15.5), gr = hypot(15.5, 15.5);
    const int col = (int)(az / (2.0 * PI) * COLS);
    int strays = 0;
    for (int row = 0; row < 2; row++) {
      const int laser = sensor.laser_of_row[row];
      const double r = gr / sensor.cos_el[laser]; /* the beam's range above that place */
      if (r * sensor.sin_el[laser] > -sc->h - 1.0) continue; /* would not be 1 m below the road or more */
      const uint32_t cell = (uint32_t)row * COLS + (uint32_t)col;
      model.n[cell] = 1;
      model.lo[cell * RS_BG_SURFACES] = model.hi[cell * RS_BG_SURFACES] = (uint16_t)lround(r * 100.0);
      strays++;
    }
    ck_assert_int_eq(strays, 2); /* both are there to be outvoted */
  }
}

static double ground_at(double x, double y) {
  float z;
  ck_assert_msg(rs_ground_at(&ground, x, y, &z), "ground at (%.1f, %.1f) not known", x, y);
  return z;
}

/* a level road under a VLP-32C 4.5 m up: the plane and every place on it */
START_TEST(t_level) {
  const scene_t sc = {.h = 4.5};
  make_model(&sc, RS_MODEL_VLP32C);
  rs_ground_build(&ground, &model, &sensor);
  ck_assert(ground.valid);
  ck_assert_msg(fabs(-ground.plane[0] - 4.5) < 0.05, "height %.3f", -ground.plane[0]);
  ck_assert(hypot(ground.plane[1], ground.plane[2]) < 0.002);
  ck_assert_uint_gt(ground.cells_kept, 500);
  ck_assert_uint_gt(ground.cells_plane, 0); /* far off, between the sparse rings, and under the pole */
  const double at[][2] = {{0, 0}, {10, 10}, {-30, 5}, {60, -40}, {0, 3}, {-100, 90}};
  for (size_t i = 0; i < sizeof at / sizeof at[0]; i++) ck_assert_double_eq_tol(ground_at(at[i][0], at[i][1]), -4.5, 0.06);
  float z;
  ck_assert_double_eq_tol(ground_at(150.0, -190.0), -4.5, 0.06); /* beyond the scene: the plane */
  ck_assert_double_eq_tol(ground_at(0.0, 250.0), -4.5, 0.06);
  ck_assert(!rs_ground_at(&ground, 257.0, 0.0, &z)); /* off the grid (256 m each way) */
  ck_assert(!rs_ground_at(&ground, 0.0, -257.0, &z));
}
END_TEST

/* a VLP-32C reaches 200 m (a VLS-128 245 m): a road 1 m higher from 140 m out, met by its beam of -1.333
 * degrees at 150 m all round, is found there (a grid ending at 128 m said not known; the plane says 1 m lower) */
START_TEST(t_far) {
  const scene_t sc = {.h = 4.5, .far_rise = true};
  make_model(&sc, RS_MODEL_VLP32C);
  rs_ground_build(&ground, &model, &sensor);
  ck_assert(ground.valid);
  ck_assert_double_eq_tol(-ground.plane[0], 4.5, 0.05);
  for (int k = 0; k < 8; k++) {
    const double a = k * PI / 4 + 0.1, r = 3.5 / tan(1.333 * PI / 180.0);
    ck_assert_double_eq_tol(ground_at(r * cos(a), r * sin(a)), -3.5, 0.1);
  }
  ck_assert_double_eq_tol(ground_at(0.0, 60.0), -4.5, 0.06); /* nearer, the road below */
}
END_TEST

/* the sensor tilted (or the road sloping) 2 degrees along x and 1 across: followed by the plane */
START_TEST(t_tilted) {
  const scene_t sc = {.h = 5.0, .gx = 0.035, .gy = -0.017};
  make_model(&sc, RS_MODEL_VLP32C);
  rs_ground_build(&ground, &model, &sensor);
  ck_assert(ground.valid);
  ck_assert_double_eq_tol(ground.plane[1], 0.035, 0.003);
  ck_assert_double_eq_tol(ground.plane[2], -0.017, 0.003);
  ck_assert_double_eq_tol(-ground.plane[0], 5.0, 0.1);
  ck_assert_double_eq_tol(ground_at(40.0, 0.0), -5.0 + 0.035 * 41.0, 0.15);
  ck_assert_double_eq_tol(ground_at(-60.0, 30.0), -5.0 - 0.035 * 59.0 - 0.017 * 31.0, 0.2);
  /* the same on a VLP-16 3 m up: its rings far apart */
  const scene_t s16 = {.h = 3.0, .gx = 0.035, .gy = -0.017};
  make_model(&s16, RS_MODEL_VLP16);
  rs_ground_build(&ground, &model, &sensor);
  ck_assert(ground.valid);
  ck_assert_double_eq_tol(ground.plane[1], 0.035, 0.005);
  ck_assert_double_eq_tol(ground_at(-20.0, -20.0), -3.0 - 0.035 * 19.0 + 0.017 * 19.0, 0.2);
}
END_TEST

/* a wall, a roof and two stray returns below the road: the plane stays the road's; beside the wall, at the stray
 * returns and under the roof (the lower beams pass under it, the higher ones meet it) the ground is the road */
START_TEST(t_walls_roof_stray) {
  const scene_t sc = {.h = 4.0, .wall = true, .roof = true, .stray = true};
  make_model(&sc, RS_MODEL_VLP32C);
  rs_ground_build(&ground, &model, &sensor);
  ck_assert(ground.valid);
  ck_assert_double_eq_tol(-ground.plane[0], 4.0, 0.05);
  ck_assert(hypot(ground.plane[1], ground.plane[2]) < 0.003);
  ck_assert_double_eq_tol(ground_at(15.5, 15.5), -4.0, 0.06);
  /* beside the wall the beams pass over the road and meet the wall's foot 0.11 m up: within 0.1 */
  ck_assert_double_eq_tol(ground_at(23.0, 0.0), -4.0, 0.1);
  ck_assert_double_eq_tol(ground_at(-10.0, -10.0), -4.0, 0.06);
  ck_assert_double_eq_tol(ground_at(-30.0, -30.0), -4.0, 0.06); /* the lower beams pass under the roof */
}
END_TEST

/* no ground: a small room, a sensor on its side, a model of another sensor, no model */
START_TEST(t_none) {
  const scene_t room = {.h = 1.0, .room = true};
  make_model(&room, RS_MODEL_VLP16);
  rs_ground_build(&ground, &model, &sensor);
  ck_assert(!ground.valid);
  float z;
  ck_assert(!rs_ground_at(&ground, 0.5, 0.5, &z));
  ck_assert(!rs_ground_at(NULL, 0.5, 0.5, &z));

  const scene_t side = {.h = 1.5, .on_side = true};
  make_model(&side, RS_MODEL_VLP32C);
  rs_ground_build(&ground, &model, &sensor);
  ck_assert(!ground.valid);
  ck_assert(!rs_ground_at(&ground, -1.5, 10.0, &z));

  const scene_t road = {.h = 4.0};
  make_model(&road, RS_MODEL_VLP32C);
  rs_sensor_t other;
  ck_assert_int_eq(rs_sensor_init(&other, RS_MODEL_VLP16), RS_OK);
  rs_ground_build(&ground, &model, &other);
  ck_assert(!ground.valid);
  rs_ground_build(&ground, NULL, &sensor);
  ck_assert(!ground.valid);
  rs_ground_build(&ground, &model, &sensor); /* and once more with the right sensor: found */
  ck_assert(ground.valid);
}
END_TEST

/* the object stage: an object whose returns' top is 2.1 m above a road 4 m below the sensor, its bottom hidden
 * (returns from 1.1 m up): its top above the ground 2.1 m with the ground, 0 (not known) without */
START_TEST(t_object_top) {
  const scene_t road = {.h = 4.0};
  make_model(&road, RS_MODEL_VLP32C);
  rs_ground_build(&ground, &model, &sensor);
  ck_assert(ground.valid);
  memset(&slot.meta, 0, sizeof slot.meta);
  slot.meta.rows = (uint16_t)sensor.lasers;
  slot.meta.cols = COLS;
  memset(slot.range, 0, sizeof slot.range);
  memset(slot.label, 0, sizeof slot.label);
  /* returns at 30 m ahead (+Y), on the beams whose height there is between 1.1 and 2.1 m above the road */
  int n = 0;
  for (int row = 0; row < sensor.lasers; row++) {
    const int laser = sensor.laser_of_row[row];
    const double r = 30.0 / sensor.cos_el[laser], z = r * sensor.sin_el[laser] + 4.0;
    if (z < 1.1 || z > 2.1) continue;
    for (int col = 0; col < 4; col++) {
      const uint32_t i = rs_cell(&slot, 0, row, col);
      slot.range[i] = (float)r;
      slot.label[i] = 3;
      n++;
    }
  }
  ck_assert_int_gt(n, 4);
  for (int with = 0; with < 2; with++) {
    rs_objects_init(&objs, NULL);
    objs.ground = with ? &ground : NULL;
    rs_objects_extract(&objs, &slot, &sensor, &list);
    ck_assert_uint_eq(list.count, 1);
    const rs_object_t *o = &list.obj[0];
    if (with) {
      ck_assert_double_eq_tol(o->top_agl, o->sensor.box_max[2] + 4.0, 0.07);
      ck_assert(o->top_agl > 1.8f && o->top_agl <= 2.11f);
      ck_assert(o->sensor.box_max[2] - o->sensor.box_min[2] < 1.01f); /* what the returns alone say */
    } else {
      ck_assert_float_eq(o->top_agl, 0.0f);
    }
  }
}
END_TEST

int main(void) {
  Suite *s = suite_create("ground");
  TCase *tc = tcase_create("core");
  tcase_set_timeout(tc, 120);
  tcase_add_test(tc, t_level);
  tcase_add_test(tc, t_far);
  tcase_add_test(tc, t_tilted);
  tcase_add_test(tc, t_walls_roof_stray);
  tcase_add_test(tc, t_none);
  tcase_add_test(tc, t_object_top);
  suite_add_tcase(s, tc);
  const int rc = tu_run(s);
  rs_bg_model_free(&model);
  return rc;
}

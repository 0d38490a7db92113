/* check_track - the tracker on hand-built object sequences with known
 * answers: ids kept through crossings, stops, occlusion, merged and split
 * clusters; foliage never confirmed; dt from timestamps; capacity. */
#include "roadscan/util/error.h"
#include "roadscan/perception/track.h"
#include "testutil.h"

#include <math.h>
#include <stdio.h>
#include <string.h>

static rs_tracker_t tr;
static rs_object_list_t objs;

static void clear(void) { memset(&objs, 0, sizeof objs); }

/* an object of a frame at time t: box centre, length, width, heading, height, returns */
static void put(double t, double x, double y, double len, double wid, double head, double h, uint32_t points) {
  rs_object_t *o = &objs.obj[objs.count];
  memset(o, 0, sizeof *o);
  o->id = objs.count + 1;
  o->points = points;
  o->sensor.obb_center[0] = (float)x;
  o->sensor.obb_center[1] = (float)y;
  o->sensor.obb_length = (float)len;
  o->sensor.obb_width = (float)wid;
  o->sensor.obb_heading = (float)head;
  o->sensor.centroid[0] = (float)x;
  o->sensor.centroid[1] = (float)y;
  o->sensor.box_min[2] = -1.8f;
  o->sensor.box_max[2] = (float)(-1.8 + h);
  o->t_first = t - 0.01;
  o->t_last = t + 0.01;
  objs.count++;
}

static void car(double t, double x, double y, double head) { put(t, x, y, 4.5, 1.8, head, 1.5, 120); }

static void init_default(void) {
  rs_track_cfg_t c;
  rs_track_cfg_default(&c);
  ck_assert_int_eq(rs_track_init(&tr, &c), RS_OK);
}

/* the defaults but n parameters, set by name as roadscand --track-set does (so the names and the
 * values' ranges are checked too) */
static void init_named(int n, const char *const names[], const double values[]) {
  rs_track_cfg_t c;
  rs_track_cfg_default(&c);
  char text[32], err[256];
  for (int k = 0; k < n; k++) {
    snprintf(text, sizeof text, "%.17g", values[k]);
    ck_assert_msg(rs_track_cfg_set(&c, names[k], text, err, sizeof err) == RS_OK, "%s", err);
  }
  ck_assert_int_eq(rs_track_init(&tr, &c), RS_OK);
}

/* the defaults but one parameter, by name */
static void init_knob(const char *name, double value) { init_named(1, (const char *const[]){name}, (const double[]){value}); }

/* the defaults but two parameters, by name */
static void init_knobs(const char *a, double va, const char *b, double vb) {
  init_named(2, (const char *const[]){a, b}, (const double[]){va, vb});
}

/* the default parameters */
static rs_track_cfg_t defaults(void) {
  rs_track_cfg_t c;
  rs_track_cfg_default(&c);
  return c;
}

/* value refused for the parameter name, by a message that names it */
static void knob_refused(const char *name, const char *value) {
  rs_track_cfg_t c;
  rs_track_cfg_default(&c);
  char err[256];
  ck_assert_int_eq(rs_track_cfg_set(&c, name, value, err, sizeof err), RS_E_INVAL);
  ck_assert_ptr_nonnull(strstr(err, name));
}

static const rs_track_t *find_id(uint32_t id) {
  for (uint32_t i = 0; i < tr.list.count; i++)
    if (tr.list.track[i].id == id) return &tr.list.track[i];
  return NULL;
}

/* whether track id (if still listed) has been updated since *hits was noted; notes its hits */
static int updated_since(uint32_t id, uint32_t *hits) {
  const rs_track_t *a = id ? find_id(id) : NULL;
  const int up = a != NULL && a->hits > *hits;
  if (a != NULL) *hits = a->hits;
  return up;
}

static int confirmed_count(void) {
  int n = 0;
  for (uint32_t i = 0; i < tr.list.count; i++) n += tr.list.track[i].state != RS_TRACK_TENTATIVE;
  return n;
}

/* a frame of a sequence of one road user, at time t: the tracker run on objs, one track listed; its
 * speed's error against v (m/s) */
static double lone_speed_error(double t, double v) {
  rs_track_frame(&tr, &objs, t + 0.05);
  ck_assert_uint_eq(tr.list.count, 1);
  return fabs(tr.list.track[0].speed - v);
}

/* ... and at its end: one track born in all, confirmed if asked */
static void lone_track_ended(bool confirmed) {
  ck_assert_uint_eq(tr.n.born, 1);
  if (confirmed) ck_assert_uint_eq(tr.list.track[0].state, RS_TRACK_CONFIRMED);
}

START_TEST(t_constant_velocity) {
  init_default();
  uint32_t id = 0;
  for (int f = 0; f < 40; f++) {
    double t = 100.0 + 0.1 * f;
    clear();
    car(t, -20.0 + 10.0 * 0.1 * f, 8.0, 0.0);
    rs_track_frame(&tr, &objs, t + 0.05);
    ck_assert_uint_eq(tr.list.count, 1);
    const rs_track_t *k = &tr.list.track[0];
    if (f == 0) id = k->id;
    ck_assert_uint_eq(k->id, id);
    ck_assert_uint_eq(tr.list.object_track[0], id);
    if (f >= 2) ck_assert_int_eq(k->state, RS_TRACK_CONFIRMED); /* the third hit confirms: 0.2 s */
  }
  const rs_track_t *k = &tr.list.track[0];
  ck_assert_double_eq_tol(k->speed, 10.0, 0.2);
  ck_assert_double_eq_tol(k->x[2], 10.0, 0.2);
  ck_assert_double_eq_tol(k->x[3], 0.0, 0.2);
  ck_assert_double_eq_tol(k->heading, 0.0, 0.05);
  ck_assert_int_eq(k->cls, RS_CLASS_CAR);
  ck_assert_uint_eq(tr.n.born, 1);
  ck_assert_str_eq(rs_class_name(k->cls), "car");
  ck_assert_str_eq(rs_track_state_name(k->state), "confirmed");
}
END_TEST

/* two cars on crossing paths pass the crossing one second apart; ids stay
 * with their cars */
START_TEST(t_crossing_paths) {
  init_default();
  uint32_t ida = 0, idb = 0;
  for (int f = 0; f < 60; f++) {
    double t = 0.1 * f;
    clear();
    double ax = -20 + 10 * t, by = -30 + 10 * t; /* A at the crossing at t = 2, B at t = 3 */
    car(t, ax, 0.0, 0.0);
    car(t, 0.0, by, M_PI / 2);
    rs_track_frame(&tr, &objs, t + 0.05);
    if (f == 3) {
      ida = tr.list.object_track[0];
      idb = tr.list.object_track[1];
      ck_assert_uint_ne(ida, idb);
    }
    if (f > 3) {
      ck_assert_uint_eq(tr.list.object_track[0], ida);
      ck_assert_uint_eq(tr.list.object_track[1], idb);
    }
  }
  ck_assert_uint_eq(tr.n.born, 2);
  ck_assert_double_eq_tol(find_id(idb)->heading, M_PI / 2, 0.05);
}
END_TEST

/* a car brakes to a stop at the line, waits 30 s, drives off: one id, speed 0 while it waits */
START_TEST(t_stop_and_go) {
  init_default();
  double x = -40, v = 12;
  uint32_t id = 0;
  int zero_frames = 0, stopped_frames = 0;
  for (int f = 0; f < 500; f++) {
    double t = 0.1 * f;
    if (t < 3.0) {
    } else if (v > 0 && t < 10) {
      v = fmax(0.0, v - 4.0 * 0.1);
    } else if (t >= 40) {
      v = fmin(12.0, v + 2.0 * 0.1);
    }
    x += v * 0.1;
    clear();
    car(t, x, 5.0, 0.0);
    rs_track_frame(&tr, &objs, t + 0.05);
    ck_assert_uint_eq(tr.list.count, 1);
    if (f == 0) id = tr.list.track[0].id;
    ck_assert_uint_eq(tr.list.track[0].id, id);
    if (t > 12 && t < 40) {
      stopped_frames++;
      zero_frames += tr.list.track[0].speed == 0.0f;
    }
  }
  ck_assert_int_eq(zero_frames, stopped_frames);
  ck_assert_double_eq_tol(tr.list.track[0].speed, v, 0.5);
  ck_assert_uint_eq(tr.n.born, 1);
}
END_TEST

/* hidden behind a bus for 0.8 s, then seen again: the same id */
START_TEST(t_occlusion) {
  init_default();
  uint32_t id = 0;
  for (int f = 0; f < 50; f++) {
    double t = 0.1 * f;
    clear();
    if (f < 20 || f >= 28) car(t, -25 + 9 * t, 12.0, 0.0);
    rs_track_frame(&tr, &objs, t + 0.05);
    if (f == 5) id = tr.list.track[0].id;
    if (f >= 20 && f < 28) {
      ck_assert_uint_eq(tr.list.count, 1);
      ck_assert_int_eq(tr.list.track[0].state, RS_TRACK_COASTING);
    }
    if (f >= 28) ck_assert_uint_eq(tr.list.object_track[0], id);
  }
  ck_assert_uint_eq(tr.n.born, 1);
  ck_assert_uint_eq(tr.list.ended, 0);
  /* a car gone for good coasts 1 s, is lost (kept, not published) 2 s more, then ends with an event */
  int ended_at = -1;
  for (int f = 50; f < 100 && ended_at < 0; f++) {
    clear();
    rs_track_frame(&tr, &objs, 0.1 * f + 0.05);
    if (f == 55) ck_assert_int_eq(tr.list.track[0].state, RS_TRACK_COASTING);
    if (f == 65) ck_assert_int_eq(tr.list.track[0].state, RS_TRACK_LOST);
    if (tr.list.ended) ended_at = f;
  }
  ck_assert_int_ge(ended_at, 79);
  ck_assert_int_le(ended_at, 81);
  ck_assert_uint_eq(tr.list.end[0].id, id);
  ck_assert_int_eq(tr.list.end[0].cls, RS_CLASS_CAR);
  ck_assert_double_eq_tol(tr.list.end[0].max_speed, 9.0, 0.5);
  ck_assert_double_eq_tol(tr.list.end[0].distance, 9.0 * 4.9, 3.0);
  ck_assert_double_eq_tol(tr.list.end[0].t_end, 4.9, 0.05);
  ck_assert_uint_eq(tr.list.count, 0);
}
END_TEST

/* a pedestrian hidden for 2 s (longer than the coasting time) is taken up again */
START_TEST(t_reacquired_after_long_occlusion) {
  init_default();
  uint32_t id = 0;
  for (int f = 0; f < 60; f++) {
    double t = 0.1 * f;
    clear();
    if (f < 20 || f >= 40) put(t, 3.0, 25 - 1.2 * t, 0.5, 0.4, 0.0, 1.7, 40);
    rs_track_frame(&tr, &objs, t + 0.05);
    if (f == 15) id = tr.list.track[0].id;
    if (f >= 40) ck_assert_uint_eq(tr.list.object_track[0], id);
  }
  ck_assert_uint_eq(tr.n.born, 1);
  ck_assert_int_eq(tr.list.track[0].cls, RS_CLASS_PEDESTRIAN);
}
END_TEST

/* A road user walking (1.2 m/s) or driving (8 m/s) along x, hidden for
 * 3.6 s (behind a bus passing, then the queue behind it), seen again where
 * its prediction is: does it keep its id? */
static bool kept_after_hiding(double lost_walker_s, bool vehicle) {
  init_knob("lost_walker_s", lost_walker_s);
  const double v = vehicle ? 8.0 : 1.2;
  uint32_t id = 0;
  bool kept = true;
  for (int f = 0; f < 80; f++) {
    const double t = 0.1 * f;
    clear();
    if (f < 20 || f >= 56) {
      if (vehicle) car(t, -20 + v * t, 12.0, 0.0);
      else put(t, -20 + v * t, 12.0, 0.5, 0.4, 0.0, 1.7, 40);
    }
    rs_track_frame(&tr, &objs, t + 0.05);
    if (f == 15) id = tr.list.object_track[0];
    if (f >= 60) kept = kept && tr.list.object_track[0] == id;
  }
  ck_assert_uint_ne(id, 0);
  return kept;
}

START_TEST(t_walker_hidden_longer) {
  ck_assert(kept_after_hiding(4.0, false));
  ck_assert_int_eq(tr.list.track[0].cls, RS_CLASS_PEDESTRIAN);
  ck_assert(!kept_after_hiding(0.0, false)); /* lost_s alone: a new id */
  ck_assert(!kept_after_hiding(4.0, true));  /* a vehicle: lost_s */
}
END_TEST

/* a pedestrian at 30 m seen by a sparse sensor: its returns span 0.4 m of
 * its height (one or two rows), the rows beside them 1 m more: a
 * pedestrian, not unknown; with no such gap (a dense sensor that saw all
 * of it), a 0.4 m tall walker-sized object stays unknown */
START_TEST(t_sparse_pedestrian) {
  for (int gap = 0; gap < 2; gap++) {
    init_default();
    for (int f = 0; f < 40; f++) {
      double t = 0.1 * f;
      clear();
      put(t, 3.0, 30 - 1.3 * t, 0.5, 0.4, 0.0, 0.4, 12);
      objs.obj[0].height_gap = gap ? 1.0f : 0.0f;
      rs_track_frame(&tr, &objs, t + 0.05);
    }
    ck_assert_uint_eq(tr.n.born, 1);
    ck_assert_int_eq(tr.list.track[0].state, RS_TRACK_CONFIRMED);
    ck_assert_int_eq(tr.list.track[0].cls, gap ? RS_CLASS_PEDESTRIAN : RS_CLASS_UNKNOWN);
  }
}
END_TEST

/* the class rules, one road user at a time driving 4 s along x at 20 m:
 * bus, van, car, a car seen edge-on (narrow, 13 m/s: a car, not a
 * cyclist), a cyclist (5.5 m/s) and a walker; a short van and an SUV */
START_TEST(t_classes) {
  static const struct {
    double len, wid, h, v, head; /* head: the box's length axis against the motion */
    rs_class_t want;
  } u[] = {
      {12.0, 2.5, 3.2, 11.0, 0.0, RS_CLASS_BUS},      {5.8, 2.0, 2.2, 12.0, 0.0, RS_CLASS_VAN_TRUCK},
      {4.5, 1.8, 1.5, 13.0, 0.0, RS_CLASS_CAR},       {2.5, 0.8, 0.4, 13.0, 0.0, RS_CLASS_CAR},
      {1.8, 0.6, 1.6, 5.5, 0.0, RS_CLASS_CYCLIST},    {0.5, 0.4, 1.7, 1.3, 0.0, RS_CLASS_PEDESTRIAN},
      /* a slow car seen head-on: its front, 1.8 m across its motion, 0.5 m deep */
      {1.8, 0.5, 1.4, 5.5, 1.5707963, RS_CLASS_CAR},
      /* two walkers side by side, 1.6 m across, walking 1.4 m/s */
      {1.6, 0.5, 1.7, 1.4, 1.5707963, RS_CLASS_UNKNOWN},
      /* a van 2.1 m tall, its returns 1.9 m from lowest to highest; an SUV's 1.6 m */
      {5.0, 2.0, 1.9, 9.0, 0.0, RS_CLASS_VAN_TRUCK},
      {4.7, 1.9, 1.6, 9.0, 0.0, RS_CLASS_CAR},
  };
  for (size_t k = 0; k < sizeof u / sizeof u[0]; k++) {
    init_default();
    for (int f = 0; f < 40; f++) {
      double t = 0.1 * f;
      clear();
      const double x = -20.0 + u[k].v * t;
      put(t, x, 20.0, u[k].len, u[k].wid, u[k].head, u[k].h, 200);
      rs_track_frame(&tr, &objs, t + 0.05);
    }
    ck_assert_uint_eq(tr.n.born, 1);
    ck_assert_msg(tr.list.track[0].cls == u[k].want, "user %zu: class %s, not %s", k, rs_class_name(tr.list.track[0].cls),
                  rs_class_name(u[k].want));
  }
}
END_TEST

/* A car (4.5 x 1.8 m) centred at (x, y0) heading along +X, of which only the
 * part outside the circle of radius rb round the sensor returns: that part
 * is the frame's object (its box on a 5 cm grid, returns by its area, from
 * z0 to z1, the row above top_gap higher; length >= width, as the objects
 * stage); none while fewer than 20 of its grid's points show. */
static void put_seen_part(double t, double x, double y0, double rb, float z0, float z1, float top_gap) {
  double umin = 1e9, umax = -1e9, vmin = 1e9, vmax = -1e9;
  int n = 0;
  for (double u = -2.25; u <= 2.25 + 1e-9; u += 0.05)
    for (double v = -0.9; v <= 0.9 + 1e-9; v += 0.05) {
      if (hypot(x + u, y0 + v) < rb) continue;
      n++;
      umin = fmin(umin, u), umax = fmax(umax, u), vmin = fmin(vmin, v), vmax = fmax(vmax, v);
    }
  if (n <= 20) return;
  put(t, x + 0.5 * (umin + umax), y0 + 0.5 * (vmin + vmax), umax - umin, vmax - vmin, 0.0, 1.3, (uint32_t)(n / 4));
  rs_object_t *o = &objs.obj[objs.count - 1];
  o->sensor.box_min[2] = z0;
  o->sensor.box_max[2] = z1;
  o->top_gap = top_gap;
  if (o->sensor.obb_length < o->sensor.obb_width) {
    const float w = o->sensor.obb_length;
    o->sensor.obb_length = o->sensor.obb_width;
    o->sensor.obb_width = w;
    o->sensor.obb_heading = (float)(M_PI / 2);
  }
}

/* Below the lowest beam. A sensor 5.5 m up whose lowest beam points 25
 * degrees down sees a car's roof (1.5 m high) only from 8.6 m on: a car
 * driving past at 8 m/s, 6 m from the sensor at its nearest, shows only the
 * part of it beyond that circle, its middle vanishing as it passes. The
 * objects here are that part (its box, returns by its area); near the sensor
 * none. With below_beam its track measures the part where it should be: the
 * speed stays within 1 m/s of 8 while the car is in view from 10 m before to
 * 10 m after; without, the box's sliding centre pulls it further off. */
static double below_beam_error(int below) {
  init_knob("below_beam", below);
  const double rb = (5.5 - 1.5) / tan(25.0 * M_PI / 180.0), y0 = 7.0;
  double worst = 0;
  for (int f = 0; f < 90; f++) {
    const double t = 0.1 * f, x = -36.0 + 8.0 * t;
    clear();
    objs.lowest_beam_deg = -25.0f;
    /* the car from 0.2 m to its roof, 1.5 m: -4.0 in the sensor frame */
    put_seen_part(t, x, y0, rb, -5.3f, -4.0f, 0.0f);
    rs_track_frame(&tr, &objs, t + 0.05);
    if (fabs(x) <= 10.0 && tr.list.count > 0 && tr.list.track[0].state == RS_TRACK_CONFIRMED)
      worst = fmax(worst, fabs(tr.list.track[0].speed - 8.0));
  }
  ck_assert_uint_eq(tr.n.born, 1);
  return worst;
}

START_TEST(t_below_beam) {
  const double with = below_beam_error(1), without = below_beam_error(0);
  ck_assert_msg(with < 1.0, "speed off by %.2f m/s", with);
  ck_assert_msg(without > with + 0.5, "without: %.2f, with: %.2f", without, with);
}
END_TEST

/* The top the reach is taken at. A sensor whose lowest beam points 15
 * degrees down, a car whose roof is 3.0 m below it: the roof is seen from
 * 11.2 m on, and a car stopping across the line of sight 13.5 m away is seen
 * whole. Sparse rows hit only its lower half (returns up to 3.8 m below the
 * sensor), the row above passes 1.6 m higher. Taken at the returns' top the
 * reach would be 14.2 m, the car's near half "below the beam" and its track
 * moved away from where the whole car is; midway to the row above (3.0 m)
 * nothing is hidden and the track stays on the car. top_gap 0 (the row above
 * at the returns' top) is the old rule: the track is moved off the car and
 * the car starts a second one. */
static double below_beam_top_error(float top_gap) {
  init_default();
  double err = 0;
  for (int f = 0; f < 80; f++) {
    const double t = 0.1 * f, y = f < 50 ? -40.0 + 8.0 * t : 0.0;
    clear();
    objs.lowest_beam_deg = -15.0f;
    put(t, 13.5, y, 4.5, 1.8, M_PI / 2, 0.5, 120);
    objs.obj[0].sensor.box_min[2] = -4.3f;
    objs.obj[0].sensor.box_max[2] = -3.8f;
    objs.obj[0].top_gap = top_gap;
    rs_track_frame(&tr, &objs, t + 0.05);
    if (f >= 60) err = fmax(err, hypot(tr.list.track[0].x[0] - 13.5, tr.list.track[0].x[1]));
  }
  return tr.n.born == 1 ? err : 1e3; /* a second track: the first was moved off the car */
}

START_TEST(t_below_beam_top) {
  const double mid = below_beam_top_error(1.6f), low = below_beam_top_error(0.0f);
  ck_assert_msg(mid < 0.1, "off by %.2f m (1e3: a second track)", mid);
  ck_assert_msg(low > mid + 0.2, "returns' top: %.2f m, midway: %.2f m", low, mid);
}
END_TEST

/* The blind circle. A sensor whose lowest beam points 15 degrees down sees
 * a car's roof, 3.0 m below it, only from 11.2 m on. A car waits 3 s at a
 * line 13 m west of the sensor's foot, 6 m off it (seen whole), then pulls
 * away east at 2.5 m/s^2, through the circle (the part of it outside the
 * circle is what the objects show; nothing while under 20 of its grid's
 * cells are), and comes out at the other side 2 s later at 10 m/s. With
 * blind_s the track that comes out is the waiting car's (one id from start
 * to end); with 0 it is a new one. */
static uint32_t blind_ids(double blind_s) {
  init_knob("blind_s", blind_s);
  const double rb = 3.0 / tan(15.0 * M_PI / 180.0), y0 = 6.0;
  uint32_t first = 0, last = 0;
  for (int f = 0; f < 100; f++) {
    const double t = 0.1 * f, x = t < 3.0 ? -13.0 : -13.0 + 1.25 * (t - 3.0) * (t - 3.0);
    clear();
    objs.lowest_beam_deg = -15.0f;
    put_seen_part(t, x, y0, rb, -4.3f, -3.0f, 0.4f); /* the car from 0.2 m to its roof, 1.5 m, the sensor 4.5 m up */
    rs_track_frame(&tr, &objs, t + 0.05);
    for (uint32_t i = 0; i < tr.list.count; i++) {
      if (tr.list.track[i].state != RS_TRACK_CONFIRMED || tr.list.track[i].object < 0) continue;
      if (first == 0) first = tr.list.track[i].id;
      last = tr.list.track[i].id;
    }
  }
  ck_assert_msg(first != 0 && last != 0, "no confirmed track");
  return first == last ? 1u : 2u;
}

START_TEST(t_blind_circle) {
  ck_assert_uint_eq(blind_ids(8.0), 1);
  ck_assert_uint_eq(tr.n.blind_linked, 1);
  ck_assert_uint_eq(blind_ids(0.0), 2);
}
END_TEST

/* a walker of a frame at time t: 0.5 m wide, 1.7 m tall, standing on the ground `up` m below the sensor */
static void put_walker(double t, double x, double y, double head, double up) {
  put(t, x, y, 0.5, 0.5, head, 1.7, 30);
  objs.obj[objs.count - 1].sensor.box_min[2] = (float)-up;
  objs.obj[objs.count - 1].sensor.box_max[2] = (float)(1.7 - up);
}

/* after a frame whose objects 0..n-1 are walkers who[]: the first and the last id of a confirmed track
 * on each walker */
static void note_walkers(const int *who, int n, uint32_t *first, uint32_t *last) {
  for (uint32_t i = 0; i < tr.list.count; i++) {
    const rs_track_t *k = &tr.list.track[i];
    if (k->state != RS_TRACK_CONFIRMED || k->object < 0 || k->object >= n) continue;
    const int w = who[k->object];
    if (first[w] == 0) first[w] = k->id;
    last[w] = k->id;
  }
}

/* blind_walker. A sensor 3 m up whose lowest beam points 15 degrees down
 * sees a walker's head (1.7 m) only beyond 4.85 m. Walkers A and B walk in
 * a line 4.8 m apart (4 s) along y = 2 towards +x at 1.2 m/s, under the
 * sensor, unseen for 7.4 s each; walker C walks along y = 2.5 towards -x
 * and goes into the circle 0.3 s before A comes out of it, 0.6 m beside
 * where C went in. Without the rule C's track, predicted on into the
 * circle, takes A; B's, unseen for less time than A's, is stitched to the
 * young track of whoever comes out next by its prediction. With it C's
 * track takes nothing before the middle of its way, no walker's track gone
 * in is stitched by its prediction, and each takes the young track whose
 * time out fits its pace (A's A, B's B, C's C). Returns how many of the
 * three keep one id from start to end; *links: the links made. (Each of the
 * rule's three parts left out, at least one walker loses its id.) */
static int walkers_under_sensor(int on, uint32_t *links) {
  init_knob("blind_walker", on);
  const double rb = 1.3 / tan(15.0 * M_PI / 180.0), v = 1.2;
  const double wx[3] = {-15.0, -19.8, 23.24}, wy[3] = {2.0, 2.0, 2.5}, dir[3] = {1, 1, -1};
  uint32_t first[3] = {0, 0, 0}, last[3] = {0, 0, 0};
  for (int f = 0; f < 300; f++) {
    const double t = 0.1 * f;
    clear();
    objs.lowest_beam_deg = -15.0f;
    int who[3], n = 0;
    for (int w = 0; w < 3; w++) {
      const double x = wx[w] + dir[w] * v * t;
      if (hypot(x, wy[w]) <= rb + 0.1) continue; /* its head below the lowest beam */
      put_walker(t, x, wy[w], dir[w] > 0 ? 0.0 : M_PI, 3.0);
      who[n++] = w;
    }
    rs_track_frame(&tr, &objs, t + 0.05);
    note_walkers(who, n, first, last);
  }
  int kept = 0;
  for (int w = 0; w < 3; w++) {
    ck_assert_msg(first[w] != 0, "walker %d never confirmed", w);
    kept += first[w] == last[w];
  }
  ck_assert_uint_ne(first[0], first[1]);
  ck_assert_uint_ne(first[0], first[2]);
  ck_assert_uint_ne(first[1], first[2]);
  *links = tr.n.blind_linked;
  return kept;
}

/* blind_walker_s: one walker of walkers_under_sensor, at 0.9 m/s along y = 2, is unseen for 9.8 s
 * under the sensor; returns whether its track keeps one id */
static bool slow_walker_kept(double keep_s) {
  init_knobs("blind_walker_s", keep_s, "blind_walker_cross", 0.0);
  const double rb = 1.3 / tan(15.0 * M_PI / 180.0);
  uint32_t first = 0, last = 0;
  for (int f = 0; f < 300; f++) {
    const double t = 0.1 * f, x = -10.0 + 0.9 * t;
    clear();
    objs.lowest_beam_deg = -15.0f;
    if (hypot(x, 2.0) > rb + 0.1) put_walker(t, x, 2.0, 0.0, 3.0);
    rs_track_frame(&tr, &objs, t + 0.05);
    for (uint32_t i = 0; i < tr.list.count; i++) {
      const rs_track_t *k = &tr.list.track[i];
      if (k->state != RS_TRACK_CONFIRMED || k->object < 0) continue;
      if (first == 0) first = k->id;
      last = k->id;
    }
  }
  ck_assert_uint_ne(first, 0);
  return first == last;
}

START_TEST(t_blind_walker) {
  uint32_t links_on, links_off;
  ck_assert_int_eq(walkers_under_sensor(1, &links_on), 3);
  ck_assert_uint_eq(links_on, 3);
  ck_assert_int_le(walkers_under_sensor(0, &links_off), 1);
  ck_assert_uint_eq(links_off, 0);
  rs_track_cfg_t c;
  rs_track_cfg_default(&c);
  ck_assert_int_eq(c.blind_walker, 1);
  knob_refused("blind_walker", "2");
  ck_assert(slow_walker_kept(12.0)); /* the default: kept 12 s */
  ck_assert(!slow_walker_kept(8.0)); /* (blind_walker_cross 0 there: blind_walker_s alone) */
  ck_assert_double_eq(c.blind_walker_s, 12.0);
  knob_refused("blind_walker_s", "61");
}
END_TEST

/* blind_walker_cross and blind_walker_alone. Under a VLP-16 4.9 m up (the lowest beam 15 degrees down: a
 * 1.7 m head is unseen within 11.9 m), walkers walk east along a sidewalk 1.5 m off the pole at 1.2 m/s,
 * unseen for 23.7 m of it, 19.8 s (a 12-minute VLP-16 capture at site 33: walkers unseen 15-22 s there,
 * each came out as a new track). Walker A alone, or, with `wait`, A and B 4 s behind it, A waiting 12 s
 * at the corner under the pole (x = 0) while B walks on: B comes out first, 19.8 s after it went in, 23.8
 * s after A, and both tracks' times fit it. Fills first[] and last[] (the first and the last id of a
 * confirmed track on each). */
static void long_unseen_walkers(bool wait, uint32_t first[2], uint32_t last[2]) {
  const double rb = 3.2 / tan(15.0 * M_PI / 180.0), v = 1.2, stop = 12.0;
  first[0] = first[1] = last[0] = last[1] = 0;
  for (int f = 0; f < 600; f++) {
    const double t = 0.1 * f;
    clear();
    objs.lowest_beam_deg = -15.0f;
    int who[2], n = 0;
    for (int w = 0; w < (wait ? 2 : 1); w++) {
      const double x0 = w == 0 ? -20.0 : -24.8, at0 = (0.0 - x0) / v; /* when it is under the pole */
      double x = x0 + v * t;
      if (w == 0 && wait && t > at0) x = t < at0 + stop ? 0.0 : v * (t - at0 - stop);
      if (hypot(x, 1.5) <= rb + 0.1) continue; /* its head below the lowest beam */
      put_walker(t, x, 1.5, 0.0, 4.9);
      who[n++] = w;
    }
    rs_track_frame(&tr, &objs, t + 0.05);
    note_walkers(who, n, first, last);
  }
}

START_TEST(t_blind_walker_cross) {
  uint32_t first[2], last[2];
  init_default();
  long_unseen_walkers(false, first, last);
  ck_assert_uint_ne(first[0], 0);
  ck_assert_uint_eq(first[0], last[0]); /* kept: the circle's 2 x (11.9 + 3) m at 1 m/s is 29.9 s */
  ck_assert_uint_eq(tr.n.blind_linked, 1);
  init_knob("blind_walker_cross", 0.0); /* blind_walker_s alone: 12 s */
  long_unseen_walkers(false, first, last);
  ck_assert_uint_ne(first[0], last[0]);
  ck_assert_uint_eq(tr.n.blind_linked, 0);
  /* the wait: by the order, A's track (gone in first) takes B when it comes out; alone, neither does */
  init_default();
  long_unseen_walkers(true, first, last);
  ck_assert(first[0] != 0 && first[1] != 0 && first[0] != first[1]);
  ck_assert_uint_ne(last[1], first[0]);
  init_knob("blind_walker_alone", 0);
  long_unseen_walkers(true, first, last);
  ck_assert(first[0] != 0 && first[1] != 0 && first[0] != first[1]);
  ck_assert_uint_eq(last[1], first[0]);
  rs_track_cfg_t c = defaults();
  ck_assert_double_eq(c.blind_walker_cross, 1.0);
  ck_assert_int_eq(c.blind_walker_alone, 1);
  knob_refused("blind_walker_cross", "-1");
  knob_refused("blind_walker_cross", "11");
  knob_refused("blind_walker_alone", "2");
}
END_TEST

/* blind_walker_pace_s. A sensor 4.9 m up whose lowest beam points 15 degrees
 * down sees a 1.7 m walker only beyond 11.9 m. A walker walks along y = 1.5
 * towards +x at 1.2 m/s; in the 1.5 s before the circle's edge it slows to
 * 0.6 m/s (the walker ahead), then walks through the circle (23.6 m) at 1.2
 * m/s again, unseen 19.7 s. At its speed at the edge the way takes 39 s, too
 * far from 19.7 for the time fit; at its pace over the seconds before (about
 * 1 m/s), it fits. Returns the first and the last id of a confirmed track on
 * it. */
static void slowed_at_edge(double pace_s, uint32_t *first, uint32_t *last) {
  init_knob("blind_walker_pace_s", pace_s);
  const double rb = 3.2 / tan(15.0 * M_PI / 180.0), x0 = -24.0, x1 = -12.7, x2 = -11.8;
  const double t1 = (x1 - x0) / 1.2, t2 = t1 + (x2 - x1) / 0.6; /* the slow stretch: x1 to x2 */
  *first = *last = 0;
  for (int f = 0; f < 380; f++) {
    const double t = 0.1 * f;
    clear();
    objs.lowest_beam_deg = -15.0f;
    const double x = t < t1 ? x0 + 1.2 * t : t < t2 ? x1 + 0.6 * (t - t1) : x2 + 1.2 * (t - t2);
    int who[1] = {0}, n = 0;
    if (hypot(x, 1.5) > rb + 0.1) { /* its head above the lowest beam */
      put_walker(t, x, 1.5, 0.0, 4.9);
      n = 1;
    }
    rs_track_frame(&tr, &objs, t + 0.05);
    uint32_t a[1] = {0}, b[1] = {0};
    note_walkers(who, n, a, b);
    if (a[0] != 0 && *first == 0) *first = a[0];
    if (b[0] != 0) *last = b[0];
  }
}

START_TEST(t_blind_walker_pace) {
  uint32_t first, last;
  slowed_at_edge(3.0, &first, &last);
  ck_assert_uint_ne(first, 0);
  ck_assert_uint_eq(last, first);
  ck_assert_uint_eq(tr.n.blind_linked, 1);
  slowed_at_edge(0.0, &first, &last); /* at its speed at the edge: no link, a new track */
  ck_assert(first != 0 && last != 0);
  ck_assert_uint_ne(last, first);
  ck_assert_uint_eq(tr.n.blind_linked, 0);
  ck_assert_double_eq(defaults().blind_walker_pace_s, 3.0);
  knob_refused("blind_walker_pace_s", "-1");
  knob_refused("blind_walker_pace_s", "61");
}
END_TEST

/* blind_walker_fifo. Walkers A and B walk in a line towards +x along a
 * sidewalk y off a pole `up` m high whose lowest beam points 15 degrees down
 * (a 1.7 m head is unseen within (up - 1.7) / tan 15), at ve[w] m/s before
 * the circle's edge (reached at t_edge + lag[w]) and at vi inside; both come
 * out, in the order they went in. Returns how many of the two keep one id
 * from start to end. */
static int walkers_in_order(int fifo, double up, double y, const double ve[2], const double lag[2], double vi,
                            double t_edge) {
  init_knob("blind_walker_fifo", fifo);
  const double rb = (up - 1.7) / tan(15.0 * M_PI / 180.0), edge = -sqrt((rb + 0.1) * (rb + 0.1) - y * y);
  uint32_t first[2] = {0, 0}, last[2] = {0, 0};
  for (int f = 0; f < 400; f++) {
    const double t = 0.1 * f;
    clear();
    objs.lowest_beam_deg = -15.0f;
    int who[2], n = 0;
    for (int w = 0; w < 2; w++) {
      const double te = t_edge + lag[w]; /* at the circle's edge */
      const double x = t < te ? edge - ve[w] * (te - t) : edge + vi * (t - te);
      if (hypot(x, y) <= rb + 0.1) continue; /* its head below the lowest beam */
      put_walker(t, x, y, 0.0, up);
      who[n++] = w;
    }
    rs_track_frame(&tr, &objs, t + 0.05);
    note_walkers(who, n, first, last);
  }
  ck_assert_msg(first[0] != 0 && first[1] != 0 && first[0] != first[1], "two walkers, two tracks");
  return (first[0] == last[0]) + (first[1] == last[1]);
}

/* The link: a VLP-16 5 m up, the sidewalk 10 m from the pole (unseen for
 * 14.6 m of it). A slowed to 0.9 m/s at the edge, B 1.1 s behind it to 1.0,
 * both at 1.3 inside: they come out 11.2 s later, 4 m or more ahead of their
 * tracks' predictions (out of the gates). By the time each track's pace
 * gives, A's young track fits B's track better (B went in later and walks
 * faster); the first gone in is A's. The gate: a 2.5 m pole (a cabinet
 * mount), the sidewalk 1.5 m off, unseen for 5.4 m of it, 4.5 s: the tracks
 * are still open to the gate. A walks at 0.75 m/s, B 1.2 s behind it at
 * 1.2, both 1.2 inside: when A comes out B's track is predicted 1.4 m
 * behind it, A's 2 m; without the rule B's track takes A by the gate, and
 * A's takes B when it comes out; with it A's takes A. */
START_TEST(t_blind_walker_fifo) {
  const double link_ve[2] = {0.9, 1.0}, link_lag[2] = {0.0, 1.1};
  ck_assert_int_eq(walkers_in_order(1, 5.0, 10.0, link_ve, link_lag, 1.3, 20.0), 2);
  ck_assert_uint_eq(tr.n.blind_linked, 2);
  ck_assert_int_eq(walkers_in_order(0, 5.0, 10.0, link_ve, link_lag, 1.3, 20.0), 0);
  const double gate_ve[2] = {0.75, 1.2}, gate_lag[2] = {0.0, 1.2};
  ck_assert_int_eq(walkers_in_order(1, 2.5, 1.5, gate_ve, gate_lag, 1.2, 8.0), 2);
  ck_assert_int_eq(walkers_in_order(0, 2.5, 1.5, gate_ve, gate_lag, 1.2, 8.0), 0);
  rs_track_cfg_t c = defaults();
  ck_assert_int_eq(c.blind_walker_fifo, 1);
  knob_refused("blind_walker_fifo", "2");
}
END_TEST

/* blind_walker_line. Under the sensor of walkers_under_sensor (3 m up, the circle 4.85 m): walker E
 * walks east along y = 2 at 1.2 m/s; walker N walks north-east at 1.2 m/s along a crossing, goes into
 * the circle 1 s before E, 5 m south-west of the pole, and stops inside (it never comes out). When E
 * comes out on the far side both tracks' times fit it, and so does the way: from where N went in to
 * where E came out it runs 23 degrees off N's heading and 22 off E's (the link allows 40). By the
 * order alone N's track, gone in first,
 * takes E (as VLP-16 rush at site 33, a walker come out along the sidewalk given the id of one gone
 * in along the crossing); with the line rule N's line passes 3.9 m from where E came out and E's own
 * 0.0 m: E's track takes E. With N not there, a walker who turned inside (E coming out 20 degrees
 * off its line) is still linked: the rule only ranks. Returns whether E keeps one id from start to
 * end; *linked: the links made. */
static bool crossing_walker_kept(double line_m, bool with_n, double e_turn, uint32_t *linked) {
  init_knob("blind_walker_line", line_m);
  const double rb = 1.3 / tan(15.0 * M_PI / 180.0), c45 = cos(0.25 * M_PI);
  uint32_t first = 0, last = 0;
  bool n_in = false;
  for (int f = 0; f < 300; f++) {
    const double t = 0.1 * f, xe = -15.0 + 1.2 * t, sn = 1.2 * t;
    clear();
    objs.lowest_beam_deg = -15.0f;
    double ex = xe, ey = 2.0; /* E: along y = 2, or, past the pole with e_turn, bent e_turn radians off */
    if (e_turn != 0 && xe > 0) ex = xe * cos(e_turn), ey = 2.0 + xe * sin(e_turn);
    if (hypot(ex, ey) > rb + 0.1) put_walker(t, ex, ey, xe > 0 ? e_turn : 0.0, 3.0);
    const int e = objs.count == 1 ? 0 : -1;
    const double nx = -11.23 + c45 * sn, ny = -8.23 + c45 * sn; /* N: in at 7.7 s, then inside */
    n_in = n_in || hypot(nx, ny) <= rb + 0.1;
    if (with_n && !n_in) put_walker(t, nx, ny, 0.25 * M_PI, 3.0);
    rs_track_frame(&tr, &objs, t + 0.05);
    for (uint32_t i = 0; i < tr.list.count && e == 0; i++) {
      const rs_track_t *k = &tr.list.track[i];
      if (k->state != RS_TRACK_CONFIRMED || k->object != 0) continue;
      if (first == 0) first = k->id;
      last = k->id;
    }
  }
  ck_assert_uint_ne(first, 0);
  *linked = tr.n.blind_linked;
  return first == last;
}

START_TEST(t_blind_walker_line) {
  uint32_t linked;
  ck_assert(crossing_walker_kept(1.5, true, 0.0, &linked)); /* the default */
  ck_assert_uint_eq(linked, 1);
  ck_assert(!crossing_walker_kept(0.0, true, 0.0, &linked)); /* the order alone: N's track took E */
  ck_assert_uint_eq(linked, 1);
  ck_assert(crossing_walker_kept(1.5, false, 0.35, &linked)); /* E alone, out 20 degrees off its line */
  ck_assert_uint_eq(linked, 1);
  rs_track_cfg_t c = defaults();
  ck_assert_double_eq(c.blind_walker_line, 1.5);
  knob_refused("blind_walker_line", "21");
  knob_refused("blind_walker_line", "-1");
}
END_TEST

/* Not any car that comes out: the waiting car of t_blind_circle pulls
 * into the circle and turns off unseen; 2 s later a car on the crossing
 * road comes out of the circle north of the pole, driving north, across
 * the way the first one went: it is a track of its own. */
START_TEST(t_blind_circle_crossing) {
  init_default();
  const double rb = 3.0 / tan(15.0 * M_PI / 180.0);
  for (int f = 0; f < 90; f++) {
    const double t = 0.1 * f;
    clear();
    objs.lowest_beam_deg = -15.0f;
    const double x = t < 3.0 ? -13.0 : -13.0 + 1.25 * (t - 3.0) * (t - 3.0);
    if (x + 2.25 < 0 && hypot(x + 2.25, 6.0) > rb + 0.5) put(t, x, 6.0, 4.5, 1.8, 0.0, 1.3, 120); /* until its front nears the circle */
    if (t >= 6.0) put(t, 3.0, rb + 1.0 + 8.0 * (t - 6.0), 4.5, 1.8, M_PI / 2, 1.3, 120); /* north, from the circle's edge */
    for (uint32_t k = 0; k < objs.count; k++) {
      objs.obj[k].sensor.box_min[2] = -4.3f;
      objs.obj[k].sensor.box_max[2] = -3.0f;
      objs.obj[k].top_gap = 0.4f;
    }
    rs_track_frame(&tr, &objs, t + 0.05);
  }
  ck_assert_uint_eq(tr.n.blind_linked, 0);
  ck_assert_uint_eq(tr.n.born, 2);
}
END_TEST

/* A car turning at the sensor's corner, unseen in the circle: it drives
 * east at 5 m/s along a lane 6 m from a sensor 4.5 m up (the circle 11.2 m),
 * turns right around the pole on a 6 m quarter circle and drives off south.
 * It is seen whole while its box is 0.5 m clear of the circle, so unseen for
 * about 4.6 s, and comes out 90 degrees from the way it went in: with
 * blind_turn the track it comes out as is linked (one id), without it is a
 * second. A car of the oncoming lane (9.5 m off the pole, westbound) that
 * comes out where the first went in is not linked by either rule. Returns
 * the id of the track that follows the car driving off at the end. */
static uint32_t turn_last_id(int blind_turn, bool oncoming) {
  init_knob("blind_turn", blind_turn);
  const double rb = 3.0 / tan(15.0 * M_PI / 180.0), v = 5.0, arc = 0.5 * M_PI * 6.0;
  for (int f = 0; f < 150; f++) {
    const double t = 0.1 * f, s = -40.0 + v * t; /* the distance driven from x = 0 on the lane */
    double x, y, h;
    if (s < 0) x = s, y = 6.0, h = 0.0;
    else if (s < arc) h = -s / 6.0, x = 6.0 * sin(s / 6.0), y = 6.0 * cos(s / 6.0);
    else x = 6.0, y = -(s - arc), h = -0.5 * M_PI;
    clear();
    objs.lowest_beam_deg = -15.0f;
    if (hypot(x, y) - hypot(2.25, 0.9) > rb && !(oncoming && s >= 0)) put(t, x, y, 4.5, 1.8, h, 1.3, 120);
    const double xo = 2.0 - v * (t - 8.0); /* the oncoming car, from the circle's far side */
    if (oncoming && t >= 8.0 && hypot(xo, 9.5) - hypot(2.25, 0.9) > rb && xo < 0) put(t, xo, 9.5, 4.5, 1.8, M_PI, 1.3, 120);
    for (uint32_t k = 0; k < objs.count; k++) {
      objs.obj[k].sensor.box_min[2] = -4.3f;
      objs.obj[k].sensor.box_max[2] = -3.0f;
      objs.obj[k].top_gap = 0.4f;
    }
    rs_track_frame(&tr, &objs, t + 0.05);
  }
  ck_assert_uint_eq(objs.count, 1);
  ck_assert_int_ge(tr.list.object_track[0], 1);
  return (uint32_t)tr.list.object_track[0];
}

START_TEST(t_blind_circle_turn) {
  ck_assert_uint_eq(turn_last_id(1, false), 1);
  ck_assert_uint_eq(tr.n.blind_linked, 1);
  ck_assert_uint_eq(turn_last_id(0, false), 2);
  ck_assert_uint_eq(tr.n.blind_linked, 0);
  ck_assert_uint_eq(turn_last_id(1, true), 2);
  ck_assert_uint_eq(tr.n.blind_linked, 0);
  rs_track_cfg_t c; /* on by default, and out of range refused */
  rs_track_cfg_default(&c);
  ck_assert_int_eq(c.blind_turn, 1);
  knob_refused("blind_turn", "2");
}
END_TEST

/* The class is the one most returns were seen as. A van passes near the
 * sensor at 6 m/s, seen whole (5.8 m long, 300 returns) for 2 s, then drives
 * off seen end-on (1.8 m across, 0.4 m deep, 25 returns) for 4 s: the box
 * shrinks and the rule's class for it (shape_cls) is no longer van/truck, its
 * track still is. Seen end-on first (4 s far off) and then whole for 2 s, it
 * is van/truck once the near views outweigh the far ones. */
static void van_views(bool near_first) {
  init_default();
  for (int f = 0; f < 60; f++) {
    const double t = 0.1 * f, x = -6.0 + 6.0 * t;
    clear();
    if (near_first ? f < 20 : f >= 40) put(t, x, 5.0, 5.8, 2.0, 0.0, 2.0, 300);
    else put(t, x - 2.7, 5.0, 1.8, 0.4, 1.5707963, 1.2, 25);
    rs_track_frame(&tr, &objs, t + 0.05);
  }
  ck_assert_uint_eq(tr.n.born, 1);
}

START_TEST(t_class_votes) {
  van_views(true);
  ck_assert_int_eq(tr.list.track[0].cls, RS_CLASS_VAN_TRUCK);
  ck_assert_int_ne(tr.list.track[0].shape_cls, RS_CLASS_VAN_TRUCK);
  van_views(false);
  ck_assert_int_eq(tr.list.track[0].cls, RS_CLASS_VAN_TRUCK);
}
END_TEST

/* The top above the ground (objects.h top_agl). A van 2.2 m tall 45 m off behind a queue: its returns span only
 * its upper metre (the box's height 1.0 m), their top 2.1 m above the ground. With the ground known it is a
 * van/truck; without (top_agl 0) a car, as the returns alone say. A car whose returns span 1.0 m and top 1.5 m
 * above the ground stays a car: the ground makes nothing taller than its top. */
static rs_class_t hidden_bottom(double len, double top_agl) {
  init_default();
  for (int f = 0; f < 40; f++) {
    const double t = 0.1 * f;
    clear();
    put(t, 45.0 - 8.0 * t, 12.0, len, 2.0, 0.0, 1.0, 150);
    objs.obj[0].top_agl = (float)top_agl;
    rs_track_frame(&tr, &objs, t + 0.05);
  }
  ck_assert_uint_eq(tr.n.born, 1);
  return tr.list.track[0].cls;
}

START_TEST(t_class_top_above_ground) {
  ck_assert_int_eq(hidden_bottom(5.2, 2.1), RS_CLASS_VAN_TRUCK);
  ck_assert_int_eq(hidden_bottom(5.2, 0.0), RS_CLASS_CAR);
  ck_assert_int_eq(hidden_bottom(4.5, 1.5), RS_CLASS_CAR);
}
END_TEST

/* A car speeds up from 4 to 14 m/s at 1.5 m/s^2, seen whole; every third
 * frame only its near half (a partial view: the box 2.3 m long, its centre
 * 1.1 m nearer the sensor). From 1 s into the speeding up, the speed is
 * never more than 0.5 m/s off (0.42 here), the partial views do not pull
 * it; the noise of meas_sd alone (meas_sd_fit 0) is off by twice that at
 * least (1.19 here). */
static double accel_lag(double fit) {
  init_knob("meas_sd_fit", fit);
  double x = -60, v = 4, worst = 0;
  for (int f = 0; f < 100; f++) {
    const double t = 0.1 * f;
    if (t >= 2.0 && v < 14.0) v = fmin(14.0, v + 1.5 * 0.1);
    x += v * 0.1;
    clear();
    /* the sensor is at the origin, the car drives along y = 8 toward +x: its near half is the rear one while
     * x < 0, the front one after */
    if (f % 3 == 2) put(t, x + (x < 0 ? -1.1 : 1.1), 8.0, 2.3, 1.8, 0.0, 1.5, 60);
    else car(t, x, 8.0, 0.0);
    const double e = lone_speed_error(t, v);
    if (t >= 3.0) worst = fmax(worst, e);
  }
  lone_track_ended(false);
  return worst;
}

/* A car at 8 m/s along y = 8 toward +x drives behind a van parked nearer
 * the sensor: everything of it with x > -10 is hidden (the van's edge), so
 * for 0.56 s its box shrinks from the front, its last column beside the
 * van's nearer returns (RS_OBJ_HIDDEN_END: the larger azimuth is the larger
 * x here). The car is still coming towards the sensor's side (x < 0), so
 * "the missing part is the far one" puts the centre behind the visible
 * rear; with hidden_anchor the centre is placed from the visible rear,
 * towards the van, by the track's length. Returns the largest speed error
 * while at least 1 m of the car shows: 0.01 m/s anchored, 0.64 without. */
static double hiding_error(int anchor) {
  init_knob("hidden_anchor", anchor);
  const double v = 8.0, edge = -10.0;
  double worst = 0;
  for (int f = 0; f < 45; f++) {
    const double t = 0.1 * f, front = -40.0 + v * t, rear = front - 4.5;
    const double hi = fmin(front, edge), len = hi - rear;
    if (len < 1.0) break;
    clear();
    put(t, 0.5 * (rear + hi), 8.0, fmax(len, 1.8), fmin(len, 1.8), len >= 1.8 ? 0.0 : 1.5707963, 1.5, (uint32_t)(25 * len));
    if (front > edge) objs.obj[0].occluded = RS_OBJ_HIDDEN_END;
    const double e = lone_speed_error(t, v);
    if (front > edge) worst = fmax(worst, e);
  }
  lone_track_ended(true);
  return worst;
}

START_TEST(t_hidden_end) {
  const double anchored = hiding_error(1), centred = hiding_error(0);
  ck_assert_msg(anchored <= 0.2, "going behind a van: speed %.2f m/s off", anchored);
  ck_assert_msg(centred >= 0.4 && centred >= 4.0 * anchored, "the far part missing: %.2f m/s off, anchored at the visible end %.2f", centred, anchored);
}
END_TEST

static double coming_into_view_error(const char *knob, double value, int hidden_first, double length, int frames);

/* The seen end (end_ref). A car at 5 m/s along y = 8 toward +x comes out
 * from behind a van parked nearer the sensor: everything of it with
 * x < -10 is hidden (the van's edge). First seen as its front 2 m, for 0.5 s
 * its box grows at its rear, its first column beside the van's nearer
 * returns (RS_OBJ_HIDDEN_START: the smaller azimuth is the smaller x here),
 * while its front moves at 5 m/s and its centre at half that. Returns the
 * largest speed error of its track from its fourth update to its fifteenth:
 * 0.02 m/s following the seen end, 2.5 following the centre. */
static void coming_out(double t) {
  const double edge = -10.0, front = edge + 2.0 + 5.0 * t, rear = fmax(edge, front - 4.5), len = front - rear;
  put(t, 0.5 * (rear + front), 8.0, len, 1.8, 0.0, 1.5, (uint32_t)(25 * len));
  if (rear <= edge) objs.obj[0].occluded = RS_OBJ_HIDDEN_START;
}
/* the same car's boxes growing the same way, marked with plain_marks (at neither end, or at both) */
static unsigned plain_marks;
static void coming_out_plain(double t) {
  const double len = fmin(4.5, 2.0 + 5.0 * t);
  put(t, -8.0 + 5.0 * t - 0.5 * len, 8.0, len, 1.8, 0.0, 1.5, (uint32_t)(25 * len));
  objs.obj[0].occluded = plain_marks;
}
/* the largest speed error of the lone track of one vehicle at v m/s, whose object at time t scene
 * puts, from its update `from` (0: the first) over `frames` frames; the track confirmed at the end */
static double lone_error_over(void (*scene)(double t), int frames, int from, double v) {
  double worst = 0;
  for (int f = 0; f < frames; f++) {
    const double t = 0.1 * f;
    clear();
    scene(t);
    const double e = lone_speed_error(t, v);
    if (f >= from) worst = fmax(worst, e);
  }
  lone_track_ended(true);
  return worst;
}
static double coming_out_error(int end_ref) {
  init_knob("end_ref", end_ref);
  return lone_error_over(coming_out, 15, 3, 5.0);
}

START_TEST(t_seen_end) {
  const double seen = coming_out_error(1), centred = coming_out_error(0);
  ck_assert_msg(seen <= 0.3, "coming out from behind a van: speed %.2f m/s off following the seen end", seen);
  ck_assert_msg(centred >= 2.0 && centred >= 4.0 * seen, "coming out: %.2f m/s off following the centre, %.2f the seen end", centred, seen);
  /* a box marked hidden at neither end, or at both, is followed by its centre: the rule does nothing */
  for (int both = 0; both <= 1; both++) {
    plain_marks = both ? RS_OBJ_HIDDEN_START | RS_OBJ_HIDDEN_END : 0u;
    double worst[2];
    for (int on = 0; on <= 1; on++) {
      init_knob("end_ref", on);
      worst[on] = lone_error_over(coming_out_plain, 15, 0, 5.0);
    }
    ck_assert_double_eq_tol(worst[0], worst[1], 1e-12);
  }
  knob_refused("end_ref", "2");
}
END_TEST

/* A car at 10 m/s comes straight towards the sensor along y = 3 from x =
 * 60, first seen as its front face: its box lies across the road (1.8 m
 * along y, 0.3 m deep, growing by 0.6 m a frame to its 4.5 m), marked hidden
 * at its end of smaller y (something nearer beside it: RS_OBJ_HIDDEN_END,
 * the larger azimuth here) while it is under 1.8 m deep. That end is beside
 * the front, not at it. Returns the largest speed error of the track from
 * its fourth update to its tenth: 0.03 m/s following the near side, 3.0
 * following the centre. */
static void face_on(double t) {
  const double front = 60.0 - 10.0 * t, seen = fmin(4.5, 0.3 + 6.0 * t);
  put(t, front + 0.5 * seen, 3.0, fmax(seen, 1.8), fmin(seen, 1.8), seen >= 1.8 ? 0.0 : 1.5707963, 1.5, (uint32_t)(10 + 8 * seen));
  if (seen < 1.8) objs.obj[0].occluded = RS_OBJ_HIDDEN_END;
}
static double face_on_error(int across) {
  init_knob("near_across", across);
  return lone_error_over(face_on, 10, 3, 10.0);
}

START_TEST(t_near_across) {
  const double across = face_on_error(1), centred = face_on_error(0);
  ck_assert_msg(across <= 0.3, "face on: speed %.2f m/s off following the near side", across);
  ck_assert_msg(centred >= 2.0 && centred >= 4.0 * across, "face on: %.2f m/s off following the centre, %.2f the near side", centred, across);
  /* a box along the line of sight marked hidden at its front is still measured by its centre
   * (car_into_view_error's first two boxes): the same with the rule or without */
  const double along_off = coming_into_view_error("near_across", 0, 2, 4.5, 10);
  ck_assert_double_eq_tol(coming_into_view_error("near_across", 1, 2, 4.5, 10), along_off, 1e-12);
  knob_refused("near_across", "2");
}
END_TEST

/* A car at 10 m/s comes towards the sensor along y = 3 from x = 60: its
 * front shows first, rows reach the rest of it in the 0.6 s after, so its
 * box grows from 1 m to its 4.5 m away from the sensor and the box's centre
 * moves at 4 m/s while it grows. With near_ref_m the speed estimator follows
 * the side nearest the sensor (the front). Its first hidden_first boxes are
 * marked hidden at the front (something nearer beside it): those are measured
 * by their centre. Returns the largest speed error of the track from its
 * fourth update to its tenth (its estimator starts at 0 m/s): 0.6 m/s with,
 * 3.4 without, 2.8 with the first two boxes hidden. A 12 m bus (length) grows
 * for 1.8 s, past the 5 updates after which its track's size counts as known:
 * with frames 20, its error from the fourth update to the twentieth. The
 * tracker is set up with the parameter knob at value. */
static double coming_into_view_error(const char *knob, double value, int hidden_first, double length, int frames) {
  init_knob(knob, value);
  const double v = 10.0;
  double worst = 0;
  for (int f = 0; f < frames; f++) {
    const double t = 0.1 * f, front = 60.0 - v * t, seen = fmin(length, 1.0 + 6.0 * t);
    clear();
    put(t, front + 0.5 * seen, 3.0, seen, 1.8, 0.0, 1.5, (uint32_t)(8 * seen));
    if (f < hidden_first) objs.obj[0].occluded = RS_OBJ_HIDDEN_START; /* its front, the smaller azimuth */
    const double e = lone_speed_error(t, v);
    if (f >= 3) worst = fmax(worst, e);
  }
  lone_track_ended(true);
  return worst;
}
static double car_into_view_error(double near_ref_m, int hidden_first) {
  return coming_into_view_error("near_ref_m", near_ref_m, hidden_first, 4.5, 10);
}

/* A truck stands 8.6 m long along y = 15, x 35.7-44.3; a van passing
 * between it and the sensor uncovers it from its far end: its box grows
 * towards the sensor, the end beside the van (its first column,
 * RS_OBJ_HIDDEN_START) the nearer one. The near side moves while the truck
 * stands: near_ref_m must not follow it. Returns the largest speed it
 * reports in its first second. */
static double uncovered_speed(double near_ref_m) {
  init_knob("near_ref_m", near_ref_m);
  double worst = 0;
  for (int f = 0; f < 10; f++) {
    const double t = 0.1 * f, seen = fmin(8.6, 2.0 + 2.2 * f), far = 44.3;
    clear();
    put(t, far - 0.5 * seen, 15.0, seen, seen < 2.5 ? 0.2 : 2.5, 0.0, 3.0, (uint32_t)(40 * seen));
    if (seen < 8.6) objs.obj[0].occluded = RS_OBJ_HIDDEN_START;
    rs_track_frame(&tr, &objs, t + 0.05);
    ck_assert_uint_eq(tr.list.count, 1);
    if (tr.list.track[0].state == RS_TRACK_CONFIRMED) worst = fmax(worst, tr.list.track[0].speed);
  }
  ck_assert_uint_eq(tr.n.born, 1);
  return worst;
}

START_TEST(t_near_side) {
  const double near = car_into_view_error(25.0, 0), centred = car_into_view_error(0.0, 0);
  ck_assert_msg(near <= 0.8, "coming into view: speed %.2f m/s off following the near side", near);
  ck_assert_msg(centred >= 2.5 && centred >= 3.0 * near, "coming into view: %.2f m/s off following the centre, %.2f the near side", centred, near);
  /* only beyond near_ref_m: the same car with the near side at 58-50 m, the rule from 70 m, is followed by its centre */
  ck_assert_double_eq_tol(car_into_view_error(70.0, 0), centred, 1e-9);
  /* its first two boxes marked hidden at the front: the centre for those, the front from the third */
  const double late = car_into_view_error(25.0, 2);
  ck_assert_msg(late <= centred - 0.3, "the front followed from the third box: %.2f m/s off, the centre %.2f", late, centred);
  /* a box growing towards the sensor from behind something: the near side is not followed */
  const double uncovered = uncovered_speed(25.0), uncovered_off = uncovered_speed(0.0);
  ck_assert_double_eq_tol(uncovered, uncovered_off, 1e-9);
  /* a bus: its box grows for 1.8 s, the near side is followed for near_ref_s (2 s by default); stopping
   * at 1 s (or, as before, once its size counted as known after 5 updates) follows its centre while it
   * still grows */
  const double bus = coming_into_view_error("near_ref_s", 2.0, 0, 12.0, 20), bus_1s = coming_into_view_error("near_ref_s", 1.0, 0, 12.0, 20);
  ck_assert_msg(bus <= 0.8, "a bus coming into view: speed %.2f m/s off following the near side for 2 s", bus);
  ck_assert_msg(bus_1s >= 1.5 && bus_1s >= 2.0 * bus, "a bus coming into view: %.2f m/s off with the near side for 1 s, %.2f for 2 s", bus_1s, bus);
  ck_assert_double_eq_tol(coming_into_view_error("near_ref_s", 0.0, 0, 12.0, 20), coming_into_view_error("near_ref_m", 0.0, 0, 12.0, 20), 1e-9);
  knob_refused("near_ref_m", "-1");
  knob_refused("near_ref_s", "-1");
}
END_TEST

/* Out of the circle (circle_whole). A VLP-16 4.5 m up, its lowest beam 15
 * degrees down, its next 13: a car's roof (1.5 m high, 3 m below it) is
 * seen from 11.2 m by the lowest beam, on one circle only (its returns there
 * within 0.05 m of it), and from 13.0 m on by every beam. A car pulls away
 * east along y = 9.7 from beside the pole (x = -1) at v m/s: its objects are
 * the returns of its roof on a 5 cm grid, their box the smallest of those
 * turned by whole degrees (length >= width, as the objects stage), nothing
 * while under 20 returns. Its first boxes are the arc of the lowest beam over
 * its roof (0.1 m wide, at 20 degrees to its way), then its roof's part
 * beyond: their centre moves at half its speed, and the track's velocity
 * with it. Returns the RMS speed error of its track over the second that
 * starts 0.3 s after its first whole box (3 m by 1.2 m or more). in: a car
 * first seen at x = 8, its box already cut by the circle, driving west at v
 * into it instead (not out): the sum of its tracks' speeds over 1.5 s, until
 * before it comes out at the other side (and 100 a frame for each the rule
 * acted on). */
static double out_of_circle(int on, double v, bool in) {
  init_knobs("circle_whole", on, "misfit_own", 0); /* misfit_own mends part of the same lag */
  const double r1 = 3.0 / tan(15.0 * M_PI / 180.0), r2 = 3.0 / tan(13.0 * M_PI / 180.0), y0 = 9.7;
  static double px[3500], py[3500];
  double whole = -1, sq = 0, sum = 0;
  int nsq = 0;
  for (int f = 0; f < (in ? 15 : 40); f++) {
    const double t = 0.1 * f, x0 = in ? 8.0 - v * t : -1.0 + v * t;
    int n = 0;
    for (double u = -2.25; u <= 2.25 + 1e-9; u += 0.05)
      for (double w = -0.9; w <= 0.9 + 1e-9; w += 0.05) {
        const double x = x0 + u, y = y0 + w, r = hypot(x, y);
        if (fabs(r - r1) >= 0.05 && r < r2) continue;
        ck_assert_int_lt(n, 3500);
        px[n] = x, py[n] = y, n++;
      }
    clear();
    objs.lowest_beam_deg = -15.0f;
    if (n >= 20) {
      double best = INFINITY, bh = 0, b[4] = {0, 0, 0, 0};
      for (int d = 0; d < 180; d++) {
        const double h = d * M_PI / 180.0, c = cos(h), s = sin(h);
        double e[4] = {INFINITY, -INFINITY, INFINITY, -INFINITY};
        for (int k = 0; k < n; k++) {
          const double pu = px[k] * c + py[k] * s, pv = -px[k] * s + py[k] * c;
          e[0] = fmin(e[0], pu), e[1] = fmax(e[1], pu), e[2] = fmin(e[2], pv), e[3] = fmax(e[3], pv);
        }
        if ((e[1] - e[0]) * (e[3] - e[2]) < best - 1e-9) best = (e[1] - e[0]) * (e[3] - e[2]), bh = h, memcpy(b, e, sizeof b);
      }
      double len = b[1] - b[0], wid = b[3] - b[2];
      const double cu = 0.5 * (b[0] + b[1]), cv = 0.5 * (b[2] + b[3]);
      const double cx = cu * cos(bh) - cv * sin(bh), cy = cu * sin(bh) + cv * cos(bh);
      if (len < wid) {
        const double l = len;
        len = wid, wid = l, bh += M_PI / 2;
      }
      put(t, cx, cy, len, wid, bh, 1.3, (uint32_t)(n / 4));
      objs.obj[0].sensor.box_min[2] = -4.3f;
      objs.obj[0].sensor.box_max[2] = -3.0f;
      if (whole < 0 && len >= 3.0 && wid >= 1.2) whole = t;
    }
    rs_track_frame(&tr, &objs, t + 0.05);
    for (uint32_t i = 0; i < tr.list.count; i++) sum += tr.list.track[i].speed + 100.0 * tr.list.track[i].made_whole;
    if (in) continue;
    ck_assert_uint_le(tr.list.count, 1);
    if (tr.list.count == 0) continue;
    if (whole >= 0 && t >= whole + 0.3 - 1e-9 && t < whole + 1.3 - 1e-9) {
      sq += (tr.list.track[0].speed - v) * (tr.list.track[0].speed - v);
      nsq++;
    }
  }
  if (in) return sum;
  ck_assert_uint_eq(tr.n.born, 1);
  ck_assert_uint_eq(tr.list.track[0].made_whole, on);
  ck_assert_int_eq(nsq, 10);
  return sqrt(sq / nsq);
}

START_TEST(t_circle_whole) {
  for (double v = 5.0; v <= 9.0 + 1e-9; v += 2.0) {
    const double on = out_of_circle(1, v, false), off = out_of_circle(0, v, false);
    ck_assert_msg(on <= 0.6, "%.0f m/s: %.2f m/s off with circle_whole", v, on);
    ck_assert_msg(off >= 1.0 && off >= 2.0 * on, "%.0f m/s: %.2f m/s off without, %.2f with", v, off, on);
    /* a car driving into the circle is not touched */
    ck_assert_double_eq_tol(out_of_circle(1, v, true), out_of_circle(0, v, true), 1e-9);
  }
  knob_refused("circle_whole", "2");
}
END_TEST

/* Uncovered (uncover_restart). A van 4.8 m long and 2 m wide, its centre
 * 40.6 m east and 13.2 m north of the sensor, heading east at v m/s (0:
 * standing), is first seen for one frame as its 1.6 m rear beside something
 * nearer (the box marked hidden at its front when `hidden`), then whole:
 * the box's centre jumps 1.6 m forward. Returns the largest error of the
 * speed its track reports from its fourth update to the fifteenth. */
static double uncovered_error(int on, double v, bool hidden) {
  init_knob("uncover_restart", on);
  double worst = 0;
  for (int f = 0; f < 15; f++) {
    const double t = 0.1 * f, x = 40.6 + v * t;
    clear();
    if (f == 0) {
      put(t, x - 2.4 + 0.8, 13.2, 1.6, 2.0, 0.0, 2.2, 60);
      if (hidden) objs.obj[0].occluded = RS_OBJ_HIDDEN_END;
    } else {
      put(t, x, 13.2, 4.8, 2.0, 0.0, 2.2, 150);
    }
    const double e = lone_speed_error(t, v);
    if (f >= 3) worst = fmax(worst, e);
  }
  lone_track_ended(false);
  return worst;
}

START_TEST(t_uncovered) {
  /* standing: 0 m/s with the rule, 1.8 without (its track took the jump for speed) */
  const double still_on = uncovered_error(1, 0.0, true), still_off = uncovered_error(0, 0.0, true);
  ck_assert_msg(still_on <= 0.3 && still_off >= 1.0, "standing van: %.2f m/s with, %.2f without", still_on, still_off);
  for (double v = 5.0; v <= 10.0 + 1e-9; v += 5.0) { /* moving: 0.15 / 0.31 m/s off with, 0.33 / 0.52 without */
    const double on = uncovered_error(1, v, true), off = uncovered_error(0, v, true);
    ck_assert_msg(on <= 0.7 * off, "%.0f m/s: %.2f m/s off with, %.2f without", v, on, off);
  }
  /* a first box not marked hidden: the rule does nothing */
  for (double v = 0.0; v <= 10.0 + 1e-9; v += 5.0)
    ck_assert_double_eq_tol(uncovered_error(1, v, false), uncovered_error(0, v, false), 1e-12);
  /* restarting at the velocity before (2, the default): a van at 10 m/s seen as its rear for two
   * frames, then whole, reports about its speed at that update, not 0 */
  for (int mode = 1; mode <= 2; mode++) {
    init_knob("uncover_restart", mode);
    double at_restart = -1;
    for (int f = 0; f < 3; f++) {
      const double t = 0.1 * f, x = 40.6 + 10.0 * t;
      clear();
      if (f < 2) {
        put(t, x - 2.4 + 0.8, 13.2, 1.6, 2.0, 0.0, 2.2, 60);
        objs.obj[0].occluded = RS_OBJ_HIDDEN_END;
      } else {
        put(t, x, 13.2, 4.8, 2.0, 0.0, 2.2, 150);
      }
      at_restart = 10.0 - lone_speed_error(t, 10.0);
    }
    if (mode == 1) ck_assert_msg(at_restart < 1.0, "restarted at 0 m/s: reports %.2f", at_restart);
    else ck_assert_msg(fabs(at_restart - 10.0) <= 1.5, "restarted at its velocity before: reports %.2f m/s for 10", at_restart);
  }
  knob_refused("uncover_restart", "3");
}
END_TEST

/* A car at 8 m/s along y = 8 is hidden for 2.2 s (behind a bus); 1.8 s
 * in, a car in the next lane (y = 11.5, 3.5 m over) comes into view right
 * beside where the first is predicted, at its speed. The first car's track
 * must not take it (reacq_across_m): the second car gets a new id, and the
 * first one's id goes on with it when it shows again. Returns the id the
 * first car has at the end, and the second car's through *other. */
static uint32_t next_lane(double across, uint32_t *other) {
  init_knob("reacq_across_m", across);
  uint32_t id_a = 0, id_b = 0;
  for (int f = 0; f < 60; f++) {
    const double t = 0.1 * f, x = -30.0 + 8.0 * t;
    clear();
    const bool a_seen = t < 2.0 || t >= 4.2, b_seen = t >= 3.8;
    if (a_seen) car(t, x, 8.0, 0.0);
    if (b_seen) car(t, x + 0.5, 11.5, 0.0);
    rs_track_frame(&tr, &objs, t + 0.05);
    if (a_seen) id_a = tr.list.object_track[0];
    if (b_seen) id_b = tr.list.object_track[a_seen ? 1 : 0];
  }
  *other = id_b;
  return id_a;
}

START_TEST(t_next_lane_not_taken) {
  uint32_t b = 0;
  const uint32_t a = next_lane(1.0, &b);
  ck_assert_uint_eq(a, 1);
  ck_assert_uint_ne(b, 1);
  ck_assert_uint_ne(b, 0);
  /* without the rule the hidden car's track takes the other lane's car */
  const uint32_t a0 = next_lane(0.0, &b);
  ck_assert_uint_eq(b, 1);
  ck_assert_uint_ne(a0, 1);
}
END_TEST

/* kin_accel. A car at v0 m/s along y = 10 (a queue moving off), seen for 3 s, hidden for 2.5 s behind
 * something nearer while it speeds up at `accel` m/s^2 (from 3 m/s at 2 m/s^2: 6.25 m ahead of its
 * track's straight-on prediction, out of the gate's 5 m), then seen again, `across` m over from its
 * lane, at the speed it got to (at least v0). Returns the id on it in the last frame; *before*: the
 * id it had before it was hidden. */
static uint32_t kin_return(double kin_accel, double v0, double accel, double across, uint32_t *before) {
  init_knob("kin_accel", kin_accel);
  const double hid = 2.5, v1 = fmax(v0, v0 + accel * hid);
  for (int f = 0; f < 80; f++) {
    const double t = 0.1 * f;
    clear();
    if (t < 3.0 - 1e-9) car(t, -30.0 + v0 * t, 10.0, 0.0);
    else if (t >= 3.0 + hid - 1e-9)
      car(t, -30.0 + v0 * 3.0 + v0 * hid + 0.5 * accel * hid * hid + v1 * (t - 3.0 - hid), 10.0 + across, 0.0);
    rs_track_frame(&tr, &objs, t + 0.05);
    if (f == 25) *before = tr.list.object_track[0];
  }
  ck_assert_uint_ne(*before, 0);
  return tr.list.object_track[0];
}

/* kin_accel's lane direction. A car's boxes lie along x (width `wid`), but their centres also drift
 * across it at 0.9 m/s while it drives at 2 m/s (its parts come and go: a slow vehicle's velocity
 * points 24 degrees off its lane); hidden 2.5 s while it speeds up at 2 m/s^2 along x, it comes back
 * 6.25 m ahead in its lane. Its track's velocity would put the lane 3-4 m to the side of where it
 * comes back; the axis of its side views puts it there. Returns whether it kept its id. */
static bool kin_drift(double wid) {
  init_default();
  uint32_t before = 0;
  const double v0 = 2.0, drift = 0.9, hid = 2.5, a = 2.0;
  for (int f = 0; f < 80; f++) {
    const double t = 0.1 * f;
    clear();
    if (t < 3.0 - 1e-9) put(t, -30.0 + v0 * t, 10.0 + drift * t, 4.5, wid, 0.0, 1.5, 120);
    else if (t >= 3.0 + hid - 1e-9)
      put(t, -30.0 + v0 * (3.0 + hid) + 0.5 * a * hid * hid + (v0 + a * hid) * (t - 3.0 - hid), 10.0 + drift * 2.9, 4.5,
          wid, 0.0, 1.5, 120);
    rs_track_frame(&tr, &objs, t + 0.05);
    if (f == 25) before = tr.list.object_track[0];
  }
  ck_assert_uint_ne(before, 0);
  return tr.list.object_track[0] == before;
}

/* kin_accel behind the prediction. A vehicle `len` m long at 6 m/s along y = 10, seen for 3 s, hidden
 * for 1.3 s while it brakes at 2.5 m/s^2 (2.1 m behind its straight-on prediction), then seen again
 * by its rear 1.3 m alone for three frames, and more of it each frame after as it comes out from
 * behind what hid it, at the speed it got to; or (follower) it stays hidden and a car 2 m behind it
 * shows whole. Returns whether the id it had is on that object in the last frame. */
static bool kin_behind(double len, bool follower) {
  init_default();
  const double v0 = 6.0, hid = 1.3, a = -2.5, v1 = v0 + a * hid, x3 = -30.0 + v0 * 3.0;
  uint32_t before = 0;
  for (int f = 0; f < 60; f++) {
    const double t = 0.1 * f;
    clear();
    if (t < 3.0 - 1e-9) {
      put(t, -30.0 + v0 * t, 10.0, len, 2.5, 0.0, 3.0, 300);
    } else if (t >= 3.0 + hid - 1e-9) {
      const double x = x3 + v0 * hid + 0.5 * a * hid * hid + v1 * (t - 3.0 - hid); /* its centre */
      if (follower) put(t, x - 0.5 * len - 2.0 - 2.25, 10.0, 4.5, 1.8, 0.0, 1.5, 120);
      else { /* its rear 1.3 m for three frames, then more of it each frame as it comes out */
        const int k = (int)lround((t - 3.0 - hid) / 0.1);
        const double seen = fmin(len, 1.3 + 2.5 * (k > 2 ? k - 2 : 0));
        put(t, x - 0.5 * len + 0.5 * seen, 10.0, seen, 2.5, 0.0, 3.0, (uint32_t)(60 + 20 * seen));
      }
    }
    rs_track_frame(&tr, &objs, t + 0.05);
    if (f == 25) before = tr.list.object_track[0];
  }
  ck_assert_uint_ne(before, 0);
  return tr.list.object_track[0] == before;
}

START_TEST(t_kin_reacq) {
  uint32_t before = 0;
  /* sped up while hidden: taken up again, by its own id */
  ck_assert_uint_eq(kin_return(2.5, 3.0, 2.0, 0.0, &before), before);
  ck_assert_uint_eq(tr.n.kin_stitched, 1);
  ck_assert_uint_eq(tr.n.born, 2); /* its young track, stitched at its third hit */
  /* off: a new track */
  ck_assert_uint_ne(kin_return(0.0, 3.0, 2.0, 0.0, &before), before);
  ck_assert_uint_eq(tr.n.kin_stitched, 0);
  /* 6.25 m behind the prediction (the next car in the lane, or this one braked): not taken */
  ck_assert_uint_ne(kin_return(2.5, 3.0, -2.0, 0.0, &before), before);
  ck_assert_uint_eq(tr.n.kin_stitched, 0);
  /* ahead but in the next lane, 3.5 m over: not taken */
  ck_assert_uint_ne(kin_return(2.5, 3.0, 2.0, 3.5, &before), before);
  ck_assert_uint_eq(tr.n.kin_stitched, 0);
  /* farther ahead than 2.5 m/s^2 takes it: at 4 m/s^2, at the young track's third hit (2.7 s unseen)
   * 14.5 m ahead, the bound 9.1 m plus 2.1 m: not taken */
  ck_assert_uint_ne(kin_return(2.5, 3.0, 4.0, 0.0, &before), before);
  ck_assert_uint_eq(tr.n.kin_stitched, 0);
  /* the lane from the axis of its side views, not from a slow vehicle's velocity: kept; boxes too
   * square for an axis (4.5 x 3 m), the velocity's direction: not */
  ck_assert(kin_drift(1.8));
  ck_assert(!kin_drift(3.0));
  /* a bus that braked while hidden, seen again by its rear 8 m behind the prediction: kept (taken up
   * at the rear's third hit); a car following the bus, seen whole: not given the bus's id */
  ck_assert(kin_behind(11.5, false));
  ck_assert_uint_eq(tr.n.kin_stitched, 1);
  ck_assert(!kin_behind(11.5, true));
  ck_assert_uint_eq(tr.n.kin_stitched, 0);
  /* standing when hidden (its axis might point either way): not taken */
  ck_assert_uint_ne(kin_return(2.5, 0.0, 2.0, 0.0, &before), before);
  ck_assert_uint_eq(tr.n.kin_stitched, 0);
  rs_track_cfg_t c;
  rs_track_cfg_default(&c);
  ck_assert_double_eq(c.kin_accel, 2.5);
  knob_refused("kin_accel", "-1");
  knob_refused("kin_accel", "11");
}
END_TEST

/* seen_across_m. A car at 8 m/s along y = 8, seen every frame for 2 s; then
 * for 0.5 s it is hidden and, 2.6 m over in the next lane beside where it is
 * predicted, a long cluster shows (8 m x 2 m: a van and the car behind it,
 * merged) moving alike. Its box misses the car's size by metres, so its
 * update noise is large and the Mahalanobis gate would let the car's track
 * take it; it does not (it gets a track of its own), with seen_across_m 0 it
 * does, and beyond 80 m from the sensor it does too (a box there is a few
 * rows). Returns the updates of the car's track while it is hidden. */
static int next_lane_cluster(double seen_across, double x0) {
  init_knob("seen_across_m", seen_across);
  uint32_t id = 0, hits = 0;
  int took = 0;
  for (int f = 0; f < 25; f++) {
    const double t = 0.1 * f, x = x0 + 8.0 * t;
    clear();
    if (f < 20) car(t, x, 8.0, 0.0);
    else put(t, x - 1.0, 10.6, 8.0, 2.0, 0.0, 2.2, 200);
    rs_track_frame(&tr, &objs, t + 0.05);
    if (f == 19) {
      id = tr.list.object_track[0];
      ck_assert_int_eq(find_id(id)->state, RS_TRACK_CONFIRMED);
    }
    const int up = updated_since(id, &hits);
    if (f >= 20) took += up;
  }
  return took;
}

/* still_lane. Two vans wait side by side in two lanes running along y (x = 6.2 and 9.7 m, 28 m
 * out), seen every frame for 3 s (their side views give the lanes' axis), then both hidden for 2.3 s
 * (a bus passing in front). The one at x = 6.2 comes back first, split in two (its front and its
 * rear, 2.2 m each); the other comes back 0.3 s later, whole. With the rule the second van's track
 * keeps its id (the first van's front is a split part of the first); without it, that track takes
 * the first van's front, 3.5 m across its lane, and the second van gets a new id. `along`: the second van comes back that far along
 * its lane (it pulled away while hidden). Returns whether the second van kept its id. */
static bool vans_uncovered(int still_lane, double along) {
  init_knob("still_lane", still_lane);
  const double h = M_PI / 2; /* the lanes' axis */
  uint32_t a = 0, b = 0;
  for (int f = 0; f < 60; f++) {
    const double t = 0.1 * f;
    clear();
    if (f < 30) {
      put(t, 6.2, 28.0, 4.9, 2.0, h, 1.9, 280);
      put(t, 9.7, 28.0, 4.9, 2.0, h, 1.9, 280);
    } else if (f >= 53) {
      put(t, 6.2, 29.3, 2.2, 2.0, h, 1.9, 130);
      put(t, 6.2, 26.7, 2.2, 2.0, h, 1.9, 130);
      if (f >= 56) put(t, 9.7, 28.0 + along, 4.9, 2.0, h, 1.9, 280);
    }
    rs_track_frame(&tr, &objs, t + 0.05);
    if (f == 29) {
      a = tr.list.object_track[0];
      b = tr.list.object_track[1];
      ck_assert(a != 0 && b != 0 && a != b);
      ck_assert_int_eq(find_id(b)->state, RS_TRACK_CONFIRMED);
      ck_assert_uint_ge(find_id(b)->axis_n, 3);
    }
  }
  ck_assert_uint_eq(tr.list.object_track[1], a); /* the first van's rear keeps its id either way */
  return tr.list.object_track[2] == b;
}

START_TEST(t_still_lane) {
  ck_assert(vans_uncovered(1, 0.0));
  ck_assert(!vans_uncovered(0, 0.0));
  /* pulled away along its lane while hidden, 3 m: still its own */
  ck_assert(vans_uncovered(1, 3.0));
  ck_assert_int_eq(defaults().still_lane, 1);
  knob_refused("still_lane", "2");
}
END_TEST

/* the track of object k this frame, checked confirmed and reporting no speed */
static uint32_t confirmed_standing(uint32_t k) {
  const uint32_t id = tr.list.object_track[k];
  ck_assert_int_eq(find_id(id)->state, RS_TRACK_CONFIRMED);
  ck_assert_float_eq(find_id(id)->speed, 0.0f);
  return id;
}

/* still_coast. A van waits at x = 6.2 m, 28 m out, in a lane along y, seen whole for 3 s (its side
 * views give the lane's axis); then a bus passing in front eats its box from the sensor's side over
 * 0.3 s (the box narrows to 1.64 m, its centre sliding 0.18 m across the lane: its filter's velocity
 * 0.6 m/s across, the speed it reports still 0), and hides it 2.2 s. A second van stops in the next lane (x = 9.7 m) while both are hidden
 * and is seen first, 0.3 s before the first comes back where it stood. Returns whether the first
 * van kept its id; *drift: how far across its last prediction had gone from where it stood. `first`:
 * the frame the first van is first seen (0: from the start). */
static bool stood_hidden(int still_coast, int first, double *drift) {
  init_knob("still_coast", still_coast);
  const double h = M_PI / 2;
  uint32_t a = 0;
  for (int f = 0; f < 62; f++) {
    const double t = 0.1 * f;
    clear();
    if (f < first)
      ;
    else if (f < 30)
      put(t, 6.2, 28.0, 4.9, 2.0, h, 1.9, 280);
    else if (f < 33) /* eaten from one side */
      put(t, 6.2 + 0.06 * (f - 29), 28.0, 4.9, 2.0 - 0.12 * (f - 29), h, 1.9, (uint32_t)(280 - 30 * (f - 29)));
    if (f >= 55) put(t, 9.7, 28.0, 4.9, 2.0, h, 1.9, 280);
    if (f >= 58) put(t, 6.2, 28.0, 4.9, 2.0, h, 1.9, 280);
    rs_track_frame(&tr, &objs, t + 0.05);
    if (f == 29) a = confirmed_standing(0);
    if (f == 54) *drift = find_id(a) ? find_id(a)->x[0] - 6.2 : 99.0;
  }
  return tr.list.object_track[1] == a;
}

START_TEST(t_still_coast) {
  double off = 0, on = 0, young = 0;
  ck_assert(stood_hidden(1, 0, &on));
  ck_assert(!stood_hidden(0, 0, &off));
  ck_assert_double_lt(fabs(on), 0.5);
  ck_assert_double_gt(off, 1.0);
  /* first seen 0.7 s before it is hidden (under STILL_COAST_S since its birth): not yet standing, it
   * is predicted on at its velocity */
  stood_hidden(1, 25, &young);
  ck_assert_double_gt(young, 1.0);
  ck_assert_int_eq(defaults().still_coast, 1);
  knob_refused("still_coast", "2");
}
END_TEST

/* still_reverse. A car drives in along its lane towards the sensor (heading -90 degrees, x = 6.2) at
 * 5 m/s and stops at y = 28, seen standing 2 s; then traffic passing in front cuts its box at its
 * near end over six frames (4.5 -> 2.1 m long, the centre 1.2 m back along its lane): its filter's
 * velocity turns back against the way it came, and it reports a speed again (so still_coast does not
 * hold it). Hidden 1 s; a second car standing in the next lane (x = 9.7) is seen first, in part (its
 * half nearer the first car's lane, traffic still in front of the rest), 0.3 s before the first comes
 * back where it stood. Returns whether the first car kept its id; *back: how far back along its lane
 * (+y) its prediction went from where it was last seen; *next_took: the second car took its id. */
static bool backed_hidden(int still_reverse, bool sharp, double *back, bool *next_took) {
  init_knob("still_reverse", still_reverse);
  const double h = -M_PI / 2;
  uint32_t a = 0;
  double last = 0.0;
  for (int f = 0; f < 70; f++) {
    const double t = 0.1 * f;
    clear();
    if (f < 24)
      put(t, 6.2, 40.0 - 5.0 * t, 4.5, 1.8, h, 1.5, 200);
    else if (f < 44)
      put(t, 6.2, 28.0, 4.5, 1.8, h, 1.5, 200);
    else if (f < 50) { /* cut at its near end (sharp: faster at the last two frames) */
      const double yc = 28.0 + (sharp ? 0.45 : 0.2) * (f - 43);
      put(t, 6.2, yc, 4.5 - 0.4 * (f - 43), 1.8, h, 1.5, 30);
    }
    if (f >= 60 && f < 63) put(t, 9.2, 28.0, 4.5, 0.8, h, 1.5, 80); /* the next car's near half */
    if (f >= 63) put(t, 9.7, 28.0, 4.5, 1.8, h, 1.5, 200);
    if (f >= 63) put(t, 6.2, 28.0, 4.5, 1.8, h, 1.5, 200);
    rs_track_frame(&tr, &objs, t + 0.05);
    if (f == 43) a = confirmed_standing(0);
    if (f == 49) { /* its velocity back against the way it came, a speed reported */
      const rs_track_t *k = find_id(a);
      ck_assert_double_gt(k->x[3], 0.5);
      ck_assert_float_gt(k->speed, 0.5f);
      last = k->x[1];
    }
    if (f == 59) {
      const rs_track_t *k = find_id(a);
      *back = k ? k->x[1] - last : 99.0;
      if (still_reverse) ck_assert_float_eq(k->speed, 0.0f); /* it reports standing */
    }
  }
  *next_took = tr.list.object_track[0] == a;
  return tr.list.object_track[1] == a;
}

START_TEST(t_still_reverse) {
  double on = 0, off = 0;
  bool took = true;
  ck_assert(backed_hidden(1, false, &on, &took));
  ck_assert(!took);
  ck_assert_double_lt(fabs(on), 0.1);
  ck_assert(!backed_hidden(0, false, &off, &took));
  ck_assert(took); /* predicted on backwards, 1.4 m, its track took the car in the next lane */
  ck_assert_double_gt(off, 1.0);
  /* cut faster: 2.2 m/s backwards at its last update, over the 2 m/s at which the way it moves is
   * learned, for one update only: the way it came holds */
  ck_assert(backed_hidden(1, true, &on, &took));
  ck_assert_double_lt(fabs(on), 0.1);
  backed_hidden(0, true, &off, &took);
  ck_assert_double_gt(off, 2.0);
  ck_assert_int_eq(defaults().still_reverse, 1);
  knob_refused("still_reverse", "2");
}
END_TEST

/* queue_coast. A car (the leader) stands in the lane y = 8 at x = 27, seen throughout. A second car
 * drives up behind it along the lane at 8 m/s and is hidden from t = 2 s (at x = 16, a bus in the near
 * lane), while it brakes to a stop 1.5 m behind the leader (x = 21, at t = 3.25 s); seen again standing
 * there from t = 4.5 s. Predicted on at 8 m/s, its track would be 15 m past where it stands, through
 * the leader (ended there as the leader's duplicate). `other`: the car seen ahead is instead 0 an oncoming car (driving -x
 * at 8 m/s, 0.5 m across the lane's line, passing the hidden one), 1 a car standing in the next lane
 * (y = 11.5), 2 the leader as above, 3 the leader standing, hidden with the second car (a bus passing
 * in front of both; its track held where it stands, still_coast, and coasting while the second
 * reaches it) and seen again with it, 4 a car ahead in the lane driving on at 4 m/s, hidden with it,
 * 5 the front part of the same long vehicle (a bus seen in two: 0.5 m between the parts' boxes, at
 * 8 m/s), seen on while the rear part is hidden and stops (a stand-in: its stop is not what is looked
 * at). Returns whether the second car kept its id
 * (and, for 3, the leader its own); *front: the farthest its prediction's front went while hidden,
 * past the leader's rear as it stands (m, negative: behind it). */
static bool queued_hidden(int queue_coast, int other, double *front) {
  init_knob("queue_coast", queue_coast);
  uint32_t id = 0, lead = 0;
  *front = -HUGE_VAL;
  for (int f = 0; f < 47; f++) {
    const double t = 0.1 * f;
    clear();
    const bool hidden = f >= 20 && f < 45;
    if (other == 0) car(t, 60.0 - 8.0 * t, 8.5, M_PI);
    else if (other == 4 && !hidden) car(t, 27.0 + 4.0 * t, 8.0, 0.0);
    else if (other == 5) car(t, 5.0 + 8.0 * t, 8.0, 0.0);
    else if (other < 3 || (other == 3 && !hidden)) car(t, 27.0, other == 1 ? 11.5 : 8.0, 0.0);
    if (f < 20) car(t, 8.0 * t, 8.0, 0.0);
    else if (f >= 45) car(t, 21.0, 8.0, 0.0);
    rs_track_frame(&tr, &objs, t + 0.05);
    if (f == 19) {
      lead = tr.list.object_track[0];
      id = tr.list.object_track[1];
      ck_assert_int_eq(find_id(id)->state, RS_TRACK_CONFIRMED);
    }
    if (f >= 20 && f < 45) {
      const rs_track_t *k = find_id(id);
      if (k) *front = fmax(*front, k->x[0] + 0.5 * k->full_length - 24.75);
    }
  }
  return tr.list.object_track[1] == id && (other != 3 || tr.list.object_track[0] == lead);
}

START_TEST(t_queue_coast) {
  double front = 0;
  ck_assert(queued_hidden(1, 2, &front));
  ck_assert_uint_gt(tr.n.queued, 0);
  ck_assert_double_le(front, -1.0 + 1e-9); /* its front kept 1 m behind the leader's rear */
  ck_assert(!queued_hidden(0, 2, &front)); /* driven on into the leader (and ended there as its duplicate) */
  ck_assert_double_gt(front, 0.5);
  ck_assert_uint_eq(tr.n.queued, 0);
  /* hidden with it, the leader's track is held where it stands: the second car stops behind that */
  ck_assert(queued_hidden(1, 3, &front));
  ck_assert_uint_gt(tr.n.queued, 0);
  ck_assert_double_le(front, -1.0 + 1e-9);
  ck_assert(!queued_hidden(0, 3, &front));
  /* an oncoming car in the lane's line, a car standing in the next lane, a car ahead hidden while it
   * drives on (its prediction is no vehicle seen, nor one standing), a part of the same vehicle 0.5 m
   * ahead (nearer than the 1 m a follower keeps): none is its leader */
  for (int other = 0; other < 6; other += other == 1 ? 3 : 1) {
    queued_hidden(1, other, &front);
    ck_assert_uint_eq(tr.n.queued, 0);
    ck_assert_double_gt(front, 0.5);
  }
  ck_assert_int_eq(defaults().queue_coast, 1);
  knob_refused("queue_coast", "2");
}
END_TEST

/* brake_coast. A car at 8 m/s along y = 8 brakes at 2.5 m/s^2 from t = 1 s; from t = 2 s (at 5.5
 * m/s) it is hidden (a bus in the near lane) and stops 6.05 m on, at t = 4.2 s; seen again standing
 * from t = 4.6 s. Predicted on at 5.5 m/s it would be 14 m on, 8 m past it, out of the gate; a car
 * waiting ahead in the lane (`ahead`: 7 m past where it stops, seen from the start, hidden with it)
 * is where that prediction lands (queue_coast: 0 off, 1 on). Returns whether the braking car kept its id. */
static bool braked_hidden(int brake_coast, bool ahead, int queue_coast) {
  init_knobs("brake_coast", brake_coast, "queue_coast", queue_coast);
  const double stop = 8.0 + 6.05 + 0.5 * (8.0 + 5.5); /* where it stops: 1 s at 8, 1 s braking, then to a stop */
  uint32_t id = 0, ahead_id = 0;
  for (int f = 0; f < 56; f++) {
    const double t = 0.1 * f;
    const double x = t <= 1.0 ? 8.0 * t : t <= 4.2 ? 8.0 + 8.0 * (t - 1.0) - 1.25 * (t - 1.0) * (t - 1.0) : stop;
    clear();
    if (t < 2.0 - 1e-9 || t > 4.6 - 1e-9) car(t, x, 8.0, 0.0);
    if (ahead && (t < 2.0 - 1e-9 || t > 4.6 - 1e-9)) car(t, stop + 7.0, 8.0, 0.0);
    rs_track_frame(&tr, &objs, t + 0.05);
    if (f == 19) {
      id = tr.list.object_track[0];
      ahead_id = ahead ? tr.list.object_track[1] : 0;
      ck_assert_int_eq(find_id(id)->state, RS_TRACK_CONFIRMED);
      if (brake_coast) ck_assert_float_gt(find_id(id)->brake, 1.0f); /* it learned that it brakes (the estimator: 1.5 of 2.5) */
    }
  }
  if (ahead) ck_assert_uint_ne(tr.list.object_track[1], id); /* the waiting car is not given its id */
  if (ahead && brake_coast) ck_assert_uint_eq(tr.list.object_track[1], ahead_id); /* and keeps its own */
  return tr.list.object_track[0] == id;
}

START_TEST(t_brake_coast) {
  ck_assert(braked_hidden(1, false, 1));
  ck_assert(!braked_hidden(0, false, 1));
  ck_assert(braked_hidden(1, true, 1));
  ck_assert(!braked_hidden(0, true, 0));
  /* without it, the car waiting ahead (its track held where it stands) stops the prediction behind it
   * (queue_coast): the id is kept that way too */
  ck_assert(braked_hidden(0, true, 1));
  ck_assert_int_eq(defaults().brake_coast, 1);
  knob_refused("brake_coast", "-1");
}
END_TEST

/* ... not at the blind circle's edge. A sensor whose lowest beam points 15 degrees down sees a car's
 * roof, 3.0 m below it, only from 11.2 m on. A car at 8 m/s along y = 6 brakes at 2 m/s^2 from t =
 * 1.5 s: at t = 4.0 s (3 m/s) its box is still 13 m from the sensor, at t = 4.5 s (2 m/s) within a
 * metre of the circle. Returns how hard its track brakes at `at` s (0: its prediction goes straight). */
static float brake_near_circle(double at) {
  init_default();
  const double rb = 3.0 / tan(15.0 * M_PI / 180.0);
  float brake = -1.0f;
  for (int f = 0; f <= (int)lround(10.0 * at); f++) {
    const double t = 0.1 * f, tb = fmax(0.0, t - 1.5);
    const double x = t < 1.5 ? -40.0 + 8.0 * t : -28.0 + 8.0 * tb - tb * tb;
    clear();
    objs.lowest_beam_deg = -15.0f;
    put_seen_part(t, x, 6.0, rb, -4.3f, -3.0f, 0.4f);
    rs_track_frame(&tr, &objs, t + 0.05);
    ck_assert_uint_eq(tr.list.count, 1);
    brake = tr.list.track[0].brake;
  }
  return brake;
}

START_TEST(t_brake_not_at_circle) {
  ck_assert_float_gt(brake_near_circle(4.0), 1.0f);
  ck_assert_float_eq(brake_near_circle(4.5), 0.0f);
}
END_TEST

START_TEST(t_seen_across) {
  ck_assert_int_eq(next_lane_cluster(2.0, -10.0), 0);
  ck_assert_uint_ne(tr.list.object_track[0], 0); /* the cluster has a track of its own */
  ck_assert_int_ge(next_lane_cluster(0.0, -10.0), 3); /* off: the car's track takes it */
  ck_assert_int_ge(next_lane_cluster(2.0, 85.0), 3); /* far: no lane rule */
  rs_track_cfg_t c;
  rs_track_cfg_default(&c);
  ck_assert_double_eq(c.seen_across_m, 2.0);
  knob_refused("seen_across_m", "-0.5");
}
END_TEST

START_TEST(t_speed_follows) {
  const double lag = accel_lag(0.05), old = accel_lag(0.0);
  ck_assert_msg(lag <= 0.5, "speed %.2f m/s off while speeding up", lag);
  ck_assert_msg(old >= 2.0 * lag, "meas_sd alone: %.2f m/s off, the fitted noise %.2f", old, lag);
}
END_TEST

/* a fixed sequence of measurement noise: the sum of four uniforms, about normal, sd 0.05 m */
static double noise_005(uint32_t *seed) {
  double u = 0;
  for (int q = 0; q < 4; q++) {
    *seed = *seed * 1664525u + 1013904223u;
    u += (double)(*seed >> 8) / 16777216.0 - 0.5;
  }
  return 0.0866 * u;
}

/* A car waits at the line, speeds up at 1.5 m/s^2 for 6 s, drives at 9 m/s,
 * brakes at 2.5 m/s^2 to a stop, along y = 12; its box centre measured with
 * 0.05 m of noise along and across (a fixed sequence: a whole box). Returns
 * the speed RMSE from 3 s on while it speeds up or brakes and in the second
 * after (*steady: the rest at 9 m/s). The constant-velocity filter lags:
 * 0.30 m/s; the mixed CV / CA estimator 0.16 (steady 0.13 and 0.10). */
static double manoeuvre_rmse(int imm, double *steady) {
  init_knob("speed_imm", imm);
  double x = -30, v = 0, se = 0, ses = 0;
  int n = 0, ns = 0;
  uint32_t seed = 12345;
  for (int f = 0; f < 200; f++) {
    const double t = 0.1 * f;
    const double a = t < 2 ? 0 : t < 8 ? 1.5 : t < 12 ? 0 : -2.5;
    v = fmax(0.0, v + a * 0.1);
    x += v * 0.1;
    const double noise[2] = {noise_005(&seed), noise_005(&seed)};
    clear();
    car(t, x + noise[0], 12.0 + noise[1], 0.0);
    rs_track_frame(&tr, &objs, t + 0.05);
    ck_assert_uint_eq(tr.list.count, 1);
    const rs_track_t *k = &tr.list.track[0];
    if (k->speed > 0) ck_assert_double_eq_tol(hypot(k->vel[0], k->vel[1]), k->speed, 1e-4);
    const double e = k->speed - v;
    if (t >= 3.0 && (a != 0 || (t >= 8 && t < 9))) se += e * e, n++;
    else if (t >= 9.0 && t < 12.0) ses += e * e, ns++;
  }
  ck_assert_uint_eq(tr.n.born, 1);
  *steady = sqrt(ses / ns);
  return sqrt(se / n);
}

START_TEST(t_speed_imm) {
  double steady_imm, steady_cv;
  const double imm = manoeuvre_rmse(1, &steady_imm), cv = manoeuvre_rmse(0, &steady_cv);
  ck_assert_msg(imm <= 0.6 * cv, "speeding up and braking: %.2f m/s off mixed, %.2f constant velocity", imm, cv);
  ck_assert_msg(steady_imm <= 0.15, "steady: %.2f m/s off mixed (%.2f constant velocity)", steady_imm, steady_cv);
  /* a walker's track reports the filter's velocity */
  init_default();
  for (int f = 0; f < 20; f++) {
    clear();
    put(0.1 * f, 5.0 + 0.14 * f, 3.0, 0.5, 0.5, 0.0, 1.7, 30);
    rs_track_frame(&tr, &objs, 0.1 * f + 0.05);
  }
  const rs_track_t *w = &tr.list.track[0];
  ck_assert_double_eq(w->vel[0], w->x[2]);
  ck_assert_double_eq(w->vel[1], w->x[3]);
  /* a car speeding up at 1.5 m/s^2, unseen for 0.7 s (over 0.5 s): the estimator, apart from the filter
   * before, starts again from the filter's state when the car is seen again (same track, coasting) */
  init_default();
  double x = -30, v = 4;
  for (int f = 0; f < 28; f++) {
    v += 0.15;
    x += 0.1 * v;
    clear();
    if (f < 20 || f >= 27) car(0.1 * f, x, 12.0, 0.0);
    rs_track_frame(&tr, &objs, 0.1 * f + 0.05);
    ck_assert_uint_eq(tr.n.born, 1);
    const rs_track_t *k = &tr.list.track[0];
    if (f == 19) ck_assert_msg(fabs(k->vel[0] - k->x[2]) > 0.01, "estimator %.3f, filter %.3f", k->vel[0], k->x[2]);
    if (f == 27) {
      ck_assert_double_eq(k->vel[0], k->x[2]);
      ck_assert_double_eq(k->vel[1], k->x[3]);
    }
  }
}
END_TEST

/* imm_birth_wide. A car drives away from the sensor at 12 m/s along y = 2, 40 m off, seen end-on: its
 * boxes are its rear and roof, 1.8 m across and 1.2 m along it (under 2 m: the filter's velocity
 * starts as uncertain as init_small_speed_sd, a walker's first pairing staying near). Returns the
 * largest speed error of its rows at hits 2-6 (*mean: their mean error) and *filter_vx the filter's
 * velocity along x at the end (the knob must not touch it). Started as uncertain as init_speed_sd,
 * the speed estimator is 0.31 m/s off at most (11.69 m/s at its second hit); started as the filter's,
 * anchored at 0 m/s, it reports 7.27 there and 11.65 at its fifth. */
static double born_short_error(int wide, double *mean, double *filter_vx) {
  init_knob("imm_birth_wide", wide);
  double worst = 0, sum = 0;
  for (int f = 0; f < 12; f++) {
    const double t = 0.1 * f, x = 40.0 + 12.0 * t;
    clear();
    put(t, x, 2.0, 1.8, 1.2, M_PI / 2, 1.4, 40);
    rs_track_frame(&tr, &objs, t + 0.05);
    ck_assert_uint_eq(tr.list.count, 1);
    const rs_track_t *k = &tr.list.track[0];
    if (f >= 1 && f < 6) {
      worst = fmax(worst, fabs(k->speed - 12.0));
      sum += k->speed - 12.0;
    }
    *filter_vx = k->x[2];
  }
  ck_assert_uint_eq(tr.n.born, 1);
  *mean = sum / 5.0;
  return worst;
}

START_TEST(t_imm_birth_wide) {
  double mean_on, mean_off, vx_on, vx_off;
  const double on = born_short_error(1, &mean_on, &vx_on), off = born_short_error(0, &mean_off, &vx_off);
  ck_assert_msg(on <= 0.5, "born on a short box: %.2f m/s off at most (mean %+.2f)", on, mean_on);
  ck_assert_msg(off >= 3.0 && mean_off < -1.0,
                "as the filter: %.2f m/s off at most (mean %+.2f), against %.2f", off, mean_off, on);
  ck_assert_double_eq(vx_on, vx_off);
  knob_refused("imm_birth_wide", "2");
}
END_TEST

/* misfit_own. A van's track learned a velocity off its axis: 5 m/s at 140
 * degrees, its boxes on that heading for 0.6 s (on a simulated capture,
 * boxes merged with a bus's gave a track 16 m/s). Then the van's whole box
 * stands still, its axis along y, 50 degrees off the track's heading. On the
 * track's axes the box misfits its 4.7 x 2.1 m by about 3 m, and the speed
 * estimator's noise from that keeps the wrong speed for a second or more; on
 * the box's own axes it fits. Returns the largest speed the track reports
 * from 0.5 s after the van stopped to 2 s; *filter_vx: the filter's velocity
 * along x then (the knob must not touch it). */
static double rotated_stop_speed(int on, double *filter_vx) {
  init_knob("misfit_own", on);
  const double v = 5.0, h = 140.0 * M_PI / 180.0, c = cos(h), s = sin(h);
  double worst = 0, x = 10.0, y = 26.0;
  for (int f = 0; f < 26; f++) {
    const double t = 0.1 * f;
    clear();
    if (f < 6) {
      x = 10.0 + v * t * c;
      y = 26.0 + v * t * s;
      put(t, x, y, 4.7, 2.07, h, 2.5, 200);
    } else {
      put(t, x, y, 4.7, 2.07, -M_PI / 2, 2.5, 200);
    }
    rs_track_frame(&tr, &objs, t + 0.05);
    ck_assert_uint_eq(tr.list.count, 1);
    if (f >= 11) worst = fmax(worst, tr.list.track[0].speed);
    *filter_vx = tr.list.track[0].x[2];
  }
  lone_track_ended(true);
  return worst;
}

/* ... and a car driving straight at 9 m/s, its box on its way, its centre
 * 0.05 m noisy: the track's heading jitters by a degree or two, within the
 * rule's 8, so each speed it reports is the same with the rule and without.
 * Returns the sum of the speeds over 4 s. */
static double straight_speeds(int on) {
  init_knob("misfit_own", on);
  uint32_t seed = 7;
  double sum = 0;
  for (int f = 0; f < 40; f++) {
    const double t = 0.1 * f, noise[2] = {noise_005(&seed), noise_005(&seed)};
    clear();
    put(t, -20.0 + 9.0 * t + noise[0], 8.0 + noise[1], 4.5, 1.8, 0.0, 1.5, 120);
    rs_track_frame(&tr, &objs, t + 0.05);
    ck_assert_uint_eq(tr.list.count, 1);
    sum += tr.list.track[0].speed;
  }
  lone_track_ended(true);
  return sum;
}

START_TEST(t_misfit_own) {
  ck_assert_double_eq(straight_speeds(1), straight_speeds(0));
  double vx_on, vx_off;
  const double on = rotated_stop_speed(1, &vx_on), off = rotated_stop_speed(0, &vx_off);
  ck_assert_msg(on <= 0.5, "a van standing, its track's heading 50 degrees off its box: %.2f m/s reported (%.2f by the track's axes)", on, off);
  ck_assert_msg(off >= 2.0, "by the track's axes %.2f m/s reported, by the box's own %.2f", off, on);
  ck_assert_double_eq(vx_on, vx_off); /* only what the track reports: the filter is the same */
  ck_assert_int_eq(defaults().misfit_own, 1);
  knob_refused("misfit_own", "2");
}
END_TEST

/* speed_full_length. A van 7 m long drives at 8 m/s along y = 10 towards
 * the sensor's side (-x) from x = 60, seen whole for 3 s, then for 2 s only
 * its front 3 m (the part nearer the sensor; no end marked hidden: say its
 * rear rows fall between two beams). Measured by the smoothed length, which
 * shrinks towards the 3 m seen by 5 % of the gap an update, the centre of
 * the partial view is moved back by less and less: it slides towards the
 * sensor, 1 m/s faster than the van at first. Measured by the full length
 * (falling 0.05 m an update) it slides 0.25 m/s: 0.37 m/s off at most, 1.03
 * by the smoothed length. Returns the largest speed
 * error from 0.5 s into the partial view to its end; *filter_vx: the
 * filter's velocity along x at the end (the knob must not touch it). */
static double partial_van_error(int on, double *filter_vx) {
  init_knob("speed_full_length", on);
  const double v = 8.0;
  double worst = 0;
  for (int f = 0; f < 50; f++) {
    const double t = 0.1 * f, xc = 60.0 - v * t, front = xc - 3.5;
    clear();
    if (f < 30) put(t, xc, 10.0, 7.0, 2.2, 3.14159265, 2.6, 300);
    else put(t, front + 1.5, 10.0, 3.0, 2.2, 3.14159265, 2.6, 130);
    const double e = lone_speed_error(t, v);
    if (f >= 35) worst = fmax(worst, e);
  }
  lone_track_ended(true);
  *filter_vx = tr.list.track[0].x[2];
  return worst;
}

START_TEST(t_speed_full_length) {
  double vx_on, vx_off;
  const double full = partial_van_error(1, &vx_on), smoothed = partial_van_error(0, &vx_off);
  ck_assert_msg(full <= 0.45, "a van seen by its front 3 m: speed %.2f m/s off by its full length (%.2f by the smoothed)", full, smoothed);
  ck_assert_msg(smoothed >= 2.0 * full, "by the smoothed length %.2f m/s off, by the full length %.2f", smoothed, full);
  ck_assert_double_eq(vx_on, vx_off); /* only what the track reports: the filter is the same */
  rs_track_cfg_t c;
  rs_track_cfg_default(&c);
  ck_assert_int_eq(c.speed_full_length, 1);
  knob_refused("speed_full_length", "2");
  knob_refused("speed_full_length", "-1");
}
END_TEST

/* A car at 6 m/s: 3 s straight on, a quarter circle of 8 m (0.75 rad/s clockwise, 2.1 s), then
 * straight on again, seen in every frame but for 0.4 s in the middle of the turn (box centres with
 * noise of sd 0.05 m). Over the turn and the 1 s after it, from 0.5 s into the turn: the RMSE of
 * the track's heading against the car's (deg) and of its position (m, the filter's state); the
 * largest turn rate measured on the first straight (rad/s), the mean over the second half of the
 * turn; the tracks born. */
typedef struct {
  double heading, pos, omega_straight, omega_turn;
  uint32_t born;
} turn_run_t;
static turn_run_t turn_run(double turn_rate) {
  /* seen_across_m off: with the turn-rate prediction on, the car seen again after 0.4 s hidden in this
   * tight turn (8 m, 0.75 rad/s) is 2.8 m across the heading of a track whose measured turn rate still
   * lags at 0.03 rad/s, and gets a new track (docs/tracking.md, Association) */
  init_knobs("turn_rate", turn_rate, "seen_across_m", 0);
  const double v = 6.0, R = 8.0, w = v / R, t_arc = 0.5 * M_PI / w;
  uint32_t seed = 777;
  turn_run_t r = {0};
  double se_h = 0, se_p = 0, om = 0;
  int n = 0, nom = 0;
  for (int f = 0; f < 80; f++) {
    const double t = 0.1 * f;
    double x, y, h; /* eastbound at y = 30, turning right (south) round (20, 22) */
    if (t < 3.0) {
      x = 20.0 - v * (3.0 - t), y = 30.0, h = 0.0;
    } else if (t < 3.0 + t_arc) {
      const double a = w * (t - 3.0);
      x = 20.0 + R * sin(a), y = 22.0 + R * cos(a), h = -a;
    } else {
      x = 28.0, y = 22.0 - v * (t - 3.0 - t_arc), h = -0.5 * M_PI;
    }
    const double noise[2] = {noise_005(&seed), noise_005(&seed)};
    clear();
    const bool hidden = t >= 3.8 && t < 4.2;
    if (!hidden) car(t, x + noise[0], y + noise[1], h);
    rs_track_frame(&tr, &objs, t + 0.05);
    if (tr.list.count == 0) continue;
    const rs_track_t *k = &tr.list.track[0];
    if (t >= 1.0 && t < 3.0) r.omega_straight = fmax(r.omega_straight, fabs(rs_track_turn_rate(k)));
    if (t >= 3.0 + 0.5 * t_arc && t < 3.0 + t_arc && !hidden) om += rs_track_turn_rate(k), nom++;
    if (t >= 3.5 && t < 4.0 + t_arc && !hidden) {
      const double dh = remainder((double)k->heading - h, 2 * M_PI) * 180.0 / M_PI;
      se_h += dh * dh;
      se_p += (k->x[0] - x) * (k->x[0] - x) + (k->x[1] - y) * (k->x[1] - y);
      n++;
    }
  }
  r.heading = sqrt(se_h / n);
  r.pos = sqrt(se_p / n);
  r.omega_turn = om / nom;
  r.born = tr.n.born;
  return r;
}

START_TEST(t_turn_rate) {
  const turn_run_t on = turn_run(0.1), off = turn_run(0.0);
  ck_assert_uint_eq(on.born, 1); /* one track through the turn and the 0.4 s unseen in it */
  ck_assert_uint_eq(off.born, 1);
  ck_assert_msg(on.omega_straight < 0.1, "straight on: %.3f rad/s", on.omega_straight);
  /* the rate measured lags the turn's (0.75 rad/s, clockwise) but has its sign */
  ck_assert_msg(on.omega_turn < -0.2 && on.omega_turn > -1.0, "turning at -0.75: %.3f rad/s", on.omega_turn);
  ck_assert_msg(on.heading < 0.85 * off.heading, "heading %.1f deg off turning, %.1f straight on", on.heading, off.heading);
  ck_assert_msg(on.pos < 0.9 * off.pos, "position %.2f m off turning, %.2f straight on", on.pos, off.pos);
  /* off by default, and out of range refused */
  rs_track_cfg_t c;
  rs_track_cfg_default(&c);
  ck_assert_double_eq(c.turn_rate, 0.0);
  knob_refused("turn_rate", "3");
}
END_TEST

/* A far car seen as its roof only (4.5 x 1.2 m, the track's width learns
 * 1.2 m), then for 1 s also its near side as a thin cluster of its own
 * 1.25 m nearer the sensor: outside the track's box grown by the margin,
 * but the two fit the track's size together. No track is born for the
 * side; its returns carry the car's id. */
/* dup_box. A van 5 m long at 8 m/s seen for 1 s as two clusters, its
 * front 3.2 m and its rear 2.6 m (their boxes overlap by 0.8 m: its roof and
 * its side), then as its front alone: the rear's track, unseen and predicted
 * inside the box of the front's (the older: its cluster comes first), is a
 * part of the same van, ended at once with no end event; with dup_box 0 it
 * coasts on (and would take the rear back when it shows again). Not ended:
 * a car in the next lane (3.5 m over) at the same speed, unseen for two
 * frames; and the second of two cars standing side by side 3.2 m apart whose
 * boxes lie across the lanes (a box axis of a still car says little), unseen
 * for two frames. Returns whether the second track is listed at frame 10
 * (`kind` 0 the halves, 1 the next lane, 2 standing). twin_s is off here: it
 * would end the rear's track while both are seen (t_twin). */
static bool dup_box_second_listed(int on, int kind) {
  init_knobs("dup_box", on, "twin_s", 0);
  bool listed = false;
  uint32_t second = 0;
  for (int f = 0; f < 12; f++) {
    const double t = 40.0 + 0.1 * f, v = kind == 2 ? 0.0 : 8.0, xc = 10.0 + v * 0.1 * f;
    clear();
    if (kind == 0) {
      put(t, xc + 0.9, 5.0, 3.2, 1.9, 0.0, 1.9, 70);
      if (f < 10) put(t, xc - 1.2, 5.0, 2.6, 1.9, 0.0, 1.2, 50);
    } else if (kind == 1) {
      car(t, xc, 5.0, 0.0);
      if (f < 10) car(t, xc, 8.5, 0.0);
    } else {
      put(t, xc, 5.0, 4.5, 1.8, 1.5708, 1.5, 120);
      if (f < 10) put(t, xc, 8.2, 4.5, 1.8, 1.5708, 1.5, 120);
    }
    rs_track_frame(&tr, &objs, t + 0.05);
    if (f == 0) {
      ck_assert_uint_eq(tr.list.count, 2);
      second = tr.list.track[1].id;
    }
    if (f == 9) ck_assert_int_eq(find_id(second)->state, RS_TRACK_CONFIRMED);
    if (f == 10) listed = find_id(second) != NULL;
    for (uint32_t e = 0; e < tr.list.ended; e++) ck_assert_uint_ne(tr.list.end[e].id, second);
  }
  return listed;
}

START_TEST(t_dup_box) {
  ck_assert(!dup_box_second_listed(1, 0));
  ck_assert_uint_eq(tr.n.duplicates, 1);
  ck_assert(dup_box_second_listed(0, 0));
  ck_assert(dup_box_second_listed(1, 1));
  ck_assert(dup_box_second_listed(1, 2));
  rs_track_cfg_t c; /* on by default, and out of range refused */
  rs_track_cfg_default(&c);
  ck_assert_int_eq(c.dup_box, 1);
  knob_refused("dup_box", "2");
}
END_TEST

/* twin_s. The van of t_dup_box, 5 m long at 8 m/s, seen for 3 s as its front
 * (3.2 m) and its rear (2.6 m), two clusters whose boxes overlap by 0.8 m,
 * both every frame: two tracks are born and confirmed, then the rear's (the
 * younger) ends as a duplicate, with no end event, and the rear's returns
 * carry the front's id; with twin_s 0 both go on. Not ended: two cars queued
 * in one lane 6 m apart at the same speed (their boxes 1.5 m apart), a car in
 * the next lane 3.5 m over, and the two halves 60 m off (beyond 50 m a box of
 * a few rows is no measure of an overlap). `kind` 0 the halves, 1 the queue,
 * 2 the next lane, 3 the far halves; returns whether the second track is
 * listed at the end, and the first's id and the id its last frame gave the
 * second object */
static bool twin_second_listed(double twin_s, int kind, uint32_t *first, uint32_t *second_label) {
  init_knob("twin_s", twin_s);
  uint32_t second = 0;
  for (int f = 0; f < 30; f++) {
    const double t = 10.0 + 0.1 * f, xc = (kind == 3 ? 60.0 : 10.0) + 8.0 * 0.1 * f;
    clear();
    if (kind == 0 || kind == 3) {
      put(t, xc + 0.9, 5.0, 3.2, 1.9, 0.0, 1.9, 70);
      put(t, xc - 1.2, 5.0, 2.6, 1.9, 0.0, 1.2, 50);
    } else {
      car(t, xc, 5.0, 0.0);
      car(t, kind == 1 ? xc - 6.0 : xc, kind == 1 ? 5.0 : 8.5, 0.0);
    }
    rs_track_frame(&tr, &objs, t + 0.05);
    if (f == 0) {
      ck_assert_uint_eq(tr.list.count, 2);
      *first = tr.list.track[0].id;
      second = tr.list.track[1].id;
    }
    if (f == 5) ck_assert_int_eq(find_id(second)->state, RS_TRACK_CONFIRMED);
    for (uint32_t e = 0; e < tr.list.ended; e++) ck_assert_uint_ne(tr.list.end[e].id, second);
    *second_label = tr.list.object_track[1];
  }
  ck_assert_ptr_nonnull(find_id(*first));
  return find_id(second) != NULL;
}

START_TEST(t_twin) {
  uint32_t first = 0, label = 0;
  ck_assert(!twin_second_listed(0.3, 0, &first, &label));
  ck_assert_uint_eq(label, first); /* the rear's returns: the van's id */
  ck_assert_uint_eq(tr.n.duplicates, 1);
  ck_assert(twin_second_listed(0, 0, &first, &label)); /* off: two tracks on one van */
  ck_assert_uint_ne(label, first);
  ck_assert(twin_second_listed(0.3, 1, &first, &label)); /* queued */
  ck_assert(twin_second_listed(0.3, 2, &first, &label)); /* the next lane */
  ck_assert(twin_second_listed(0.3, 3, &first, &label)); /* far */
  rs_track_cfg_t c;
  rs_track_cfg_default(&c);
  ck_assert_double_eq(c.twin_s, 0.3);
  knob_refused("twin_s", "-1");
}
END_TEST

START_TEST(t_split_side) {
  init_default();
  uint32_t id = 0;
  for (int f = 0; f < 40; f++) {
    const double t = 0.1 * f, x = 40 + 10 * t;
    clear();
    put(t, x, 10.3, 4.5, 1.2, 0.0, 1.5, 40);
    if (f >= 20 && f < 30) put(t, x - 0.2, 9.05, 4.1, 0.08, 0.0, 1.0, 12);
    rs_track_frame(&tr, &objs, t + 0.05);
    if (f == 5) id = tr.list.object_track[0];
    if (f >= 20 && f < 30) {
      ck_assert_uint_eq(tr.list.object_track[0], id);
      ck_assert_uint_eq(tr.list.object_track[1], id);
    }
  }
  ck_assert_uint_ne(id, 0);
  ck_assert_uint_eq(tr.n.born, 1);
  ck_assert_uint_ge(tr.n.absorbed, 10);
}
END_TEST

/* A car driving east, seen whole for `whole` frames, then for 0.4 s
 * driving turn_deg off east and seen as two parts of it, its rear (from its
 * back end, rear_len long) and its front (front_len long, at its front end):
 * with the parameter `knob` at `on`, are both parts given the car's id?
 * Returns the tracks born. With `beam`, the objects are those of a sensor
 * 4.5 m up (lowest beam 15 degrees down; the reach at a car's top 10.4 m). */
typedef struct {
  const char *knob;
  double x, y, step, turn_deg, rear_len, front_len;
  int whole;
  bool beam;
} parts_seq_t;
static uint32_t parts_born(const parts_seq_t *q, int on) { /* on -1: the defaults */
  if (on < 0) init_default();
  else init_knob(q->knob, on);
  uint32_t id = 0;
  double x = q->x, y = q->y;
  for (int f = 0; f < q->whole + 4; f++) {
    const double t = 0.1 * f, h = f < q->whole ? 0.0 : q->turn_deg * M_PI / 180.0, c = cos(h), s = sin(h);
    x += q->step * c, y += q->step * s;
    clear();
    if (q->beam) objs.lowest_beam_deg = -15.0f;
    if (f < q->whole) {
      put(t, x, y, 4.5, 1.8, h, 1.3, 120);
    } else {
      const double ur = -2.25 + 0.5 * q->rear_len, uf = 2.25 - 0.5 * q->front_len;
      put(t, x + ur * c, y + ur * s, q->rear_len, 1.8, h, 1.3, 60);
      put(t, x + uf * c, y + uf * s, q->front_len, 1.8, h, 1.3, 30);
    }
    for (uint32_t k = 0; k < objs.count && q->beam; k++) {
      objs.obj[k].sensor.box_min[2] = -4.3f;
      objs.obj[k].sensor.box_max[2] = -3.0f;
      objs.obj[k].top_gap = 0.4f;
    }
    rs_track_frame(&tr, &objs, t + 0.05);
    if (f == q->whole - 1) id = tr.list.object_track[0];
    if (f >= q->whole && on) {
      ck_assert_uint_eq(tr.list.object_track[0], id);
      ck_assert_uint_eq(tr.list.object_track[1], id);
    }
  }
  ck_assert_uint_ne(id, 0);
  return tr.n.born;
}

/* the rule of q->knob: on, one track; off, a second one; on by default; `bad` refused */
static void parts_rule(const parts_seq_t *q, const char *bad) {
  ck_assert_uint_eq(parts_born(q, 1), 1);
  ck_assert_uint_ge(tr.n.absorbed, 4);
  ck_assert_uint_eq(parts_born(q, 0), 2);
  ck_assert_uint_eq(parts_born(q, -1), 1);
  knob_refused(q->knob, bad);
}

/* A car turning, seen as two parts while its track's heading (the
 * velocity's) is still behind the turn: 3 s east at 8 m/s seen whole, then
 * driving at 45 degrees, its rear 3.4 m and its front 0.9 m seen as two
 * clusters 0.2 m apart (a post between). The front part lies outside the
 * track's box grown by the margin, and the two do not fit the track's size on
 * its axes (the rear part's box spans 3.5 m across them), but they do on the
 * rear part's own axis: no track is born for the front, its returns carry
 * the car's id. With split_object_axis 0 it becomes a track of its own. */
START_TEST(t_split_turned) {
  const parts_seq_t q = {.knob = "split_object_axis", .x = 0, .y = 10, .step = 0.8, .turn_deg = 45, .rear_len = 3.4,
                         .front_len = 0.9, .whole = 30, .beam = false};
  parts_rule(&q, "-1");
}
END_TEST

/* A car turning near the circle its top is below the lowest beam in, seen
 * as its two ends: 2 s east at 5 m/s along a lane 12 m off the pole, seen
 * whole, then 70 degrees into a right turn, only its rear 1.2 m and its front
 * 1.0 m seen. The two fit the car on its own axis but neither on the track's
 * (across it they span 4.8 m; the track's heading is its velocity's, still
 * east) nor on a part's (too short to give one): with split_near_circle no
 * track is born for the other end, with 0 one is. */
START_TEST(t_split_near_circle) {
  const parts_seq_t q = {.knob = "split_near_circle", .x = -16, .y = 12, .step = 0.5, .turn_deg = -70, .rear_len = 1.2,
                         .front_len = 1.0, .whole = 20, .beam = true};
  parts_rule(&q, "2");
}
END_TEST

/* A bus (12 x 2.5 m) 110 m off drives towards the sensor at 9 m/s along a
 * lane 9.75 m to its side, seen whole for 3 s, then as what a grazing view
 * leaves of it: the rear 4 m of its near side (0.2 m wide) and its front
 * face (2.5 x 0.1 m), two clusters. Its track takes the side piece, nearer
 * its prediction; measured by it alone (a third of its length, moved by
 * at most 3 m towards where the rest should be, the wrong way here) its box
 * slides back along the bus. With merge_parts it is updated by the two
 * together and stays on the bus. A car 0.5 m ahead of it in the lane, with
 * a track of its own, is seen the same way as its near side and its rear
 * face; the rear face fits with the bus's parts in the bus's size, but lies
 * in the car's predicted box: the bus's track is not measured with it (one
 * part a frame, the front face). (It still carries the bus's id: the
 * split-part rule gives a free part to the first track, in id order, whose
 * box holds it.) */
static double merge_seq(int on) {
  if (on < 0) init_default();
  else init_knob("merge_parts", on);
  double err = 0.0;
  for (int f = 0; f < 55; f++) {
    const double t = 0.1 * f, yc = 110.0 - 9.0 * t, cc = yc - 8.75;
    clear();
    if (f < 30) {
      put(t, 9.75, yc, 12.0, 2.5, -0.5 * M_PI, 3.0, 200);
      put(t, 9.75, cc, 4.5, 1.8, -0.5 * M_PI, 1.5, 120);
    } else {
      put(t, 8.6, yc + 4.0, 4.0, 0.2, 0.5 * M_PI, 3.0, 30);
      put(t, 9.75, yc - 6.0, 2.5, 0.1, 0.0, 3.0, 60);
      put(t, 8.95, cc + 0.5, 3.5, 0.2, 0.5 * M_PI, 1.5, 40);
      put(t, 9.75, cc + 2.25, 1.8, 0.1, 0.0, 1.5, 30);
    }
    rs_track_frame(&tr, &objs, t + 0.05);
    const uint32_t bus = tr.list.object_track[0];
    ck_assert_uint_ne(bus, 0);
    if (f >= 30) err = fabs(find_id(bus)->x[1] - yc);
  }
  return err;
}

START_TEST(t_merge_parts) {
  const double on = merge_seq(1);
  ck_assert_msg(on < 1.0, "merged: the track %.2f m off the bus's centre", on);
  ck_assert_uint_eq(tr.n.born, 2);    /* the bus and the car */
  ck_assert_uint_eq(tr.n.merged, 25); /* the front face, never the car's rear face */
  const double off = merge_seq(0);
  ck_assert_msg(off > 3.0, "not merged: the track %.2f m off the bus's centre", off);
  ck_assert_uint_eq(tr.n.merged, 0);
  ck_assert_uint_gt(tr.n.born, 2); /* and a part of the bus became a track of its own */
  ck_assert_double_eq_tol(merge_seq(-1), on, 1e-9);
  knob_refused("merge_parts", "2");
}
END_TEST

/* A truck (9.5 x 2.5 m) drives east at 6 m/s along y = 6.25, 6 m beside the
 * pole: seen whole for 2 s, then, nearer, as its near side alone (a box 9.5
 * x 0.1 m at y = 5). From 4.5 s, for 1.2 s, a walker nobody tracked (out of
 * the circle below the lowest beam) stands at (4, 2.5), between the truck
 * and the sensor, within the truck's length: a thin part that fits with the
 * side in the truck's size. With merge_front_m it is never merged with the
 * truck's object: the truck's track is the same as with no walker there;
 * off, the walker is merged and pulls the truck's track toward itself.
 * Fills y[20] with the truck's track's y from 4 s on; returns the parts
 * merged. (The walker's returns still carry the truck's id: the split-part
 * rule, docs/tracking.md.) */
static uint32_t truck_walker(double gap, bool walker, double y[20]) {
  init_knob("merge_front_m", gap);
  uint32_t truck = 0;
  for (int f = 0; f < 60; f++) {
    const double t = 0.1 * f, x = -25.0 + 6.0 * t;
    clear();
    if (f < 20) put(t, x, 6.25, 9.5, 2.5, 0.0, 3.0, 1500);
    else put(t, x, 5.0, 9.5, 0.1, 0.0, 3.0, 3000);
    if (walker && f >= 45 && f < 57) put(t, 4.0, 2.5, 0.45, 0.3, 0.0, 1.7, 50);
    rs_track_frame(&tr, &objs, t + 0.05);
    if (f == 20) truck = tr.list.object_track[0];
    if (f > 20) ck_assert_uint_eq(tr.list.object_track[0], truck);
    if (f >= 40) {
      const rs_track_t *k = find_id(truck);
      ck_assert_ptr_nonnull(k);
      y[f - 40] = k->x[1];
    }
  }
  ck_assert_uint_ne(truck, 0);
  return tr.n.merged;
}

START_TEST(t_merge_front) {
  double alone[20], on[20], off[20];
  ck_assert_uint_eq(truck_walker(1.0, false, alone), 0);
  ck_assert_uint_eq(truck_walker(1.0, true, on), 0);
  double d_on = 0.0, d_off = 0.0;
  for (int f = 0; f < 20; f++) d_on = fmax(d_on, fabs(on[f] - alone[f]));
  ck_assert_double_eq_tol(d_on, 0.0, 1e-9); /* the truck's track as with no walker */
  ck_assert_uint_eq(truck_walker(0.0, true, off), 12); /* off: merged in each of its 12 frames */
  for (int f = 0; f < 20; f++) d_off = fmax(d_off, fabs(off[f] - alone[f]));
  ck_assert_msg(d_off > 0.5, "off: the walker moved the truck's track by %.2f m at most", d_off);
  rs_track_cfg_t c;
  rs_track_cfg_default(&c);
  ck_assert_double_eq(c.merge_front_m, 1.0);
  knob_refused("merge_front_m", "-1");
  knob_refused("merge_front_m", "21");
}
END_TEST

/* tent_claim_m. Walker W walks east at 1.2 m/s along y = 1.5, 22 m out;
 * at 7.5 s walker S appears standing at the kerb at (21.5, 2.3), shifting
 * by 0.12 m each frame (never still enough, nor walking, to confirm within
 * a second: its track stays tentative); at 8.2 s, just past S, W is hidden
 * (behind the crowd) and its confirmed track coasts on. Returns the frames
 * from then to 9 s in which S's object was given to W's track. */
static int standing_taken(double claim) {
  init_knobs("tent_claim_m", claim, "confirm_pace", 0); /* confirm_pace would confirm S before W could take it */
  uint32_t w = 0;
  int taken = 0;
  for (int f = 0; f < 90; f++) {
    const double t = 0.1 * f;
    clear();
    int s_at = -1;
    if (t < 8.2) put(t, 12.0 + 1.2 * t, 1.5, 0.45, 0.35, 0.0, 1.7, 14);
    if (t >= 7.5) {
      s_at = (int)objs.count;
      put(t, 21.5 + (f % 2 ? 0.06 : -0.06), 2.3, 0.4, 0.3, 0.0, 1.7, 12);
    }
    rs_track_frame(&tr, &objs, t + 0.05);
    if (f == 60) {
      w = tr.list.object_track[0];
      ck_assert_uint_ne(w, 0);
      ck_assert_int_eq(find_id(w)->state, RS_TRACK_CONFIRMED);
    }
    if (t >= 8.2 && s_at >= 0 && tr.list.object_track[s_at] == w) taken++;
  }
  return taken;
}

START_TEST(t_tent_claim) {
  ck_assert_int_eq(standing_taken(0.5), 0);
  ck_assert_int_gt(standing_taken(0.0), 0); /* off: W's track, predicted on past S, takes it */
  ck_assert_int_gt(standing_taken(1.0), 0); /* W's track 0.95 m from S, S's own 0.1-0.3 m */
  rs_track_cfg_t c;
  rs_track_cfg_default(&c);
  ck_assert_double_eq(c.tent_claim_m, 0.5);
  knob_refused("tent_claim_m", "-1");
  knob_refused("tent_claim_m", "21");
}
END_TEST

/* A pedestrian walks 4 s toward the road, then stands hidden behind a
 * parked van; a car comes out from behind the van 1.8 m before where it
 * was last seen, seen side-on (4.5 x 1.8 m) or end-on (2 x 1.8 m). The pedestrian's track does not
 * take the car: the car gets a track of its own, the pedestrian keeps its
 * id and is taken up again when it steps out. */
START_TEST(t_pedestrian_not_vehicle) {
  static const double shape[2][2] = {{4.5, 1.8}, {2.0, 1.8}};
  for (int v = 0; v < 2; v++) {
    init_default();
    uint32_t ped = 0, carid = 0;
    for (int f = 0; f < 70; f++) {
      const double t = 0.1 * f;
      clear();
      const double py = t < 4.0 ? 18.0 - 1.3 * t : 12.8;
      if (t < 4.0 || t >= 6.0) put(t, 10.0, py, 0.5, 0.4, 0.0, 1.7, 30);
      if (t >= 4.75 && t < 5.6) /* out from behind the van at 4.8 s, 1.8 m before (10, 12.8) */
        put(t, 10.0 + 12.0 * (t - 4.9), 12.4, shape[v][0], shape[v][1], 0.0, 1.5, 120);
      rs_track_frame(&tr, &objs, t + 0.05);
      if (f == 39) {
        ped = tr.list.object_track[0];
        ck_assert_uint_ne(ped, 0);
        ck_assert_int_eq(find_id(ped)->cls, RS_CLASS_PEDESTRIAN);
      }
      if (t >= 4.75 && t < 5.6) {
        const uint32_t k = tr.list.object_track[0];
        ck_assert_msg(k != ped, "shape %d: the pedestrian's track took the car at %.1f s", v, t);
        if (k != 0 && carid == 0) carid = k;
        if (k != 0) ck_assert_uint_eq(k, carid);
      }
      if (f == 69) ck_assert_uint_eq(tr.list.object_track[0], ped);
    }
    ck_assert_uint_ne(carid, 0);
  }
}
END_TEST

/* A walker walks 2 s along x at 1.4 m/s (its track confirmed, walked), then
 * is seen for 0.5 s as a 1.4 m part (beside a pole: its box grows, its shape
 * is no longer a pedestrian's), then is hidden while a car drives through
 * where it is predicted, at 8 m/s, for 1 s. Returns how many of the car's
 * frames updated the walker's track; *speed: the walker's track's speed at
 * the end (m/s). */
static int walked_then_car(int walked_hits, double *speed) {
  init_knob("walked_hits", walked_hits);
  uint32_t walker = 0, hits = 0;
  int took = 0;
  for (int f = 0; f < 35; f++) {
    const double t = 0.1 * f, x = 5.0 + 1.4 * t;
    clear();
    if (f < 20) put(t, x, 12.0, 0.5, 0.4, 0.0, 1.7, 30);
    else if (f < 25) put(t, x + 0.45, 12.0, 1.4, 0.4, 0.0, 1.7, 40);
    else put(t, 5.0 + 1.4 * 2.5 + 0.5 + 8.0 * (t - 2.5), 12.2, 4.5, 1.8, 0.0, 1.5, 120);
    rs_track_frame(&tr, &objs, t + 0.05);
    if (f == 19) {
      walker = tr.list.object_track[0];
      ck_assert_uint_ne(walker, 0);
      ck_assert_int_eq(find_id(walker)->shape_cls, RS_CLASS_PEDESTRIAN);
      ck_assert_uint_ge(find_id(walker)->walked, (unsigned)walked_hits);
    }
    const rs_track_t *w = find_id(walker);
    if (f == 24) ck_assert_int_ne(w->shape_cls, RS_CLASS_PEDESTRIAN); /* its box grew */
    if (f >= 25 && w != NULL && w->hits > hits) took++;
    if (w != NULL) hits = w->hits, *speed = w->speed;
  }
  return took;
}

START_TEST(t_walked_not_vehicle) {
  double speed = -1;
  ck_assert_int_eq(walked_then_car(10, &speed), 0); /* the car never updates the walker's track */
  ck_assert_double_lt(speed, 3.0);
  ck_assert_int_ge(walked_then_car(0, &speed), 5); /* off: it takes the car, and its speed */
  ck_assert_double_gt(speed, 4.0);
  rs_track_cfg_t c;
  rs_track_cfg_default(&c);
  ck_assert_int_eq(c.walked_hits, 10);
  char err[160];
  ck_assert_int_eq(rs_track_cfg_set(&c, "walked_hits", "-1", err, sizeof err), RS_E_INVAL);
}
END_TEST

/* walker_reacq_s. A walker seen only to the knees (0.4 m tall: not a
 * pedestrian's shape, so the walked rule does not hold) walks 3 s at 1.2 m/s
 * towards the sensor's pole and goes out of sight for 1 s (the circle below
 * the lowest beam); then a car's part comes out of the circle beside where
 * the walker was predicted: 3 m x 1.6 m, 300 returns against the walker's
 * 25, moving at 3 m/s. The walker's track does not take it (a track of its
 * own is born); with walker_reacq_s 0 it does, and becomes a car's. Returns
 * the updates of the walker's track after it went out of sight. */
static int walker_then_car_part(double reacq_s, uint32_t *walker_id) {
  init_knob("walker_reacq_s", reacq_s);
  uint32_t walker = 0, hits = 0;
  int took = 0;
  for (int f = 0; f < 50; f++) {
    const double t = 0.1 * f;
    clear();
    if (f < 30) put(t, -7.0 + 1.2 * t, 2.0, 0.5, 0.4, 0.0, 0.4, 25);
    else if (f >= 40) put(t, -2.6 + 3.0 * (t - 4.0), 3.8, 3.0, 1.6, 0.0, 1.2, 300);
    rs_track_frame(&tr, &objs, t + 0.05);
    if (f == 29) {
      walker = tr.list.object_track[0];
      ck_assert_uint_ne(walker, 0);
      ck_assert_int_ne(find_id(walker)->shape_cls, RS_CLASS_PEDESTRIAN);
      ck_assert_uint_eq(find_id(walker)->walked, 0);
    }
    const int up = updated_since(walker, &hits);
    if (f >= 40) took += up;
  }
  *walker_id = walker;
  return took;
}

START_TEST(t_walker_reacq) {
  uint32_t walker = 0;
  ck_assert_int_eq(walker_then_car_part(0.3, &walker), 0);
  ck_assert_uint_ne(tr.list.object_track[0], walker); /* the car part has a track of its own */
  ck_assert_uint_ne(tr.list.object_track[0], 0);
  ck_assert_int_ge(walker_then_car_part(0, &walker), 5); /* off: the walker's track takes the car */
  ck_assert_uint_eq(tr.list.object_track[0], walker);
  rs_track_cfg_t c;
  rs_track_cfg_default(&c);
  ck_assert_double_eq(c.walker_reacq_s, 0.3);
  knob_refused("walker_reacq_s", "61");
}
END_TEST

/* walker_part. A walker (0.5 m x 0.4 m, 1.7 m tall) walks at 1.2 m/s along
 * y = 2 and is hidden from 2 s to 3.5 s (behind a van at the kerb); a car
 * drives past at 10 m/s along y = 3.8 (its near side at 2.9 m), seen whole
 * but, from 2.9 s to 3.5 s, as its body and a piece of its near side split
 * off by the beams (0.6 m x 0.3 m, 8 returns, 1.5 m behind its centre):
 * inside the car's box, a metre or two from where the walker is predicted.
 * Returns the updates of the walker's track while the piece is there, and
 * whether its id is the walker's again at the end. */
static int walker_and_car_piece(int on, bool *walker_kept) {
  init_knob("walker_part", on);
  uint32_t walker = 0, hits = 0;
  int took = 0;
  *walker_kept = true;
  for (int f = 0; f < 50; f++) {
    const double t = 0.1 * f, cx = -30.0 + 10.0 * t;
    clear();
    const bool walker_seen = f < 20 || f >= 35;
    if (walker_seen) put(t, -2.0 + 1.2 * t, 2.0, 0.5, 0.4, 0.0, 1.7, 40);
    if (f >= 29 && f < 35) {
      put(t, cx + 0.45, 3.8, 3.6, 1.8, 0.0, 1.5, 110);
      put(t, cx - 1.5, 3.05, 0.6, 0.3, 0.0, 0.8, 8);
    } else {
      car(t, cx, 3.8, 0.0);
    }
    rs_track_frame(&tr, &objs, t + 0.05);
    if (f == 19) {
      walker = tr.list.object_track[0];
      ck_assert_uint_ne(walker, 0);
      ck_assert_int_eq(find_id(walker)->shape_cls, RS_CLASS_PEDESTRIAN);
    }
    const int up = updated_since(walker, &hits);
    if (f >= 29 && f < 35) took += up;
    if (f >= 40) *walker_kept = *walker_kept && tr.list.object_track[0] == walker;
  }
  return took;
}

/* walker_part's bounds. A walker walks at 1.2 m/s along y = wy past a car
 * 4.5 m x 1.8 m whose near side is at y = 2.9, the car standing or driving
 * at car_v from x0. Returns the frames (after the first 5) its track was not
 * updated in; *kept: the walker's object has its track's id at the end. */
static int walker_beside_car(double car_v, double x0, double wy, bool *kept) {
  init_default();
  uint32_t walker = 0, hits = 0;
  int missed = 0;
  for (int f = 0; f < 40; f++) {
    const double t = 0.1 * f;
    clear();
    put(t, -4.0 + 1.2 * t, wy, 0.5, 0.4, 0.0, 1.7, 40);
    car(t, x0 + car_v * t, 3.8, 0.0);
    rs_track_frame(&tr, &objs, t + 0.05);
    if (f == 5) walker = tr.list.object_track[0];
    const int up = updated_since(walker, &hits);
    if (f > 5) missed += !up;
  }
  ck_assert_uint_ne(walker, 0);
  *kept = tr.list.object_track[0] == walker;
  return missed;
}

START_TEST(t_walker_part) {
  bool kept = false;
  ck_assert_int_eq(walker_and_car_piece(1, &kept), 0);
  ck_assert(kept); /* the walker comes back to its own track */
  ck_assert_int_ge(walker_and_car_piece(0, &kept), 1); /* off: the walker's track takes the car's piece */
  /* 0.3 m beside a standing car, or one creeping at 1 m/s (under 2 m/s): inside its grown box, tracked */
  ck_assert_int_eq(walker_beside_car(0.0, -2.0, 2.6, &kept), 0);
  ck_assert_int_eq(walker_beside_car(1.0, -2.0, 2.6, &kept), 0);
  /* 0.9 m beside a car passing at 10 m/s (0.4 m outside its box grown by 0.5 m): tracked */
  ck_assert_int_eq(walker_beside_car(10.0, -30.0, 2.0, &kept), 0);
  /* 0.3 m beside it (a body 0.05 m from the car: the rule's price): not updated while the car passes,
   * the track coasts and takes the walker again after, with its id */
  const int missed = walker_beside_car(10.0, -30.0, 2.6, &kept);
  ck_assert_int_gt(missed, 0);
  ck_assert_int_le(missed, 8);
  ck_assert(kept);
  rs_track_cfg_t c;
  rs_track_cfg_default(&c);
  ck_assert_int_eq(c.walker_part, 1);
  knob_refused("walker_part", "2");
}
END_TEST

/* miss_cost: the run's first two frames of VLP-32C rush at the held-out site 21 (`--objects-out`,
 * rounded): a van waiting 11 m off, and beside it two slivers of returns, each a track of its own at
 * the first frame. At the second, every track tentative, the van's track is the only one whose gate
 * holds a sliver (1.9 m from its centre). Pairing as many tracks as the group allows gave the van's
 * object to the first sliver's track (2.8 m away: its box and its speed from that jump) and the van's
 * track a sliver; when leaving a track without an object costs 24, the van keeps its id. */
static uint32_t van_and_slivers(double miss_cost, uint32_t *van_first, uint64_t *left) {
  init_knob("miss_cost", miss_cost);
  clear();
  put(0.0, -5.249, 9.718, 5.60, 1.98, 0.0, 2.2, 1155);
  put(0.0, -7.845, 10.603, 0.46, 0.03, 0.0, 0.6, 11);
  put(0.0, -5.747, 10.376, 1.56, 0.04, 0.0, 0.6, 39);
  rs_track_frame(&tr, &objs, 0.0);
  *van_first = tr.list.object_track[0];
  clear();
  put(0.1, -5.219, 9.714, 5.64, 1.99, 0.0, 2.2, 1160);
  put(0.1, -3.438, 10.222, 0.41, 0.04, 0.0, 0.6, 12);
  put(0.1, -5.444, 10.550, 0.86, 0.03, 0.0, 0.6, 22);
  rs_track_frame(&tr, &objs, 0.1);
  *left = tr.n.miss_left;
  return tr.list.object_track[0];
}
START_TEST(t_miss_cost) {
  uint32_t first = 0;
  uint64_t left_with = 0, left_without = 0;
  const uint32_t with = van_and_slivers(24.0, &first, &left_with);
  ck_assert_uint_ne(first, 0);
  ck_assert_uint_eq(with, first); /* the van keeps its track */
  const uint32_t without = van_and_slivers(0.0, &first, &left_without);
  ck_assert_uint_ne(without, first); /* off: a sliver's track takes the van */
  ck_assert_uint_gt(left_with, left_without); /* the sliver's track went without, and was counted */
  rs_track_cfg_t c;
  rs_track_cfg_default(&c);
  ck_assert(c.miss_cost == 24.0);
  knob_refused("miss_cost", "-1");
}
END_TEST

/* A group of one track and one object (most of them) is settled without the solver: the pair when it
 * costs less than leaving the track without an object, else the track goes without and is counted.
 * A car at 10 m/s along x, 200 returns, seen 8 frames (its pairs cost -2 to 4); at the ninth its
 * object lies 1.2 m across its prediction with 4 returns (a pair of 7.9): taken at the default
 * miss_cost (24), left at 6. */
static void lone_pair(double miss_cost, uint32_t *car, uint32_t *ninth, uint64_t *left) {
  init_knob("miss_cost", miss_cost);
  uint64_t before = 0;
  for (int f = 0; f < 9; f++) {
    clear();
    put(0.1 * f, 20.0 + f, 10.0 + (f == 8 ? 1.2 : 0.0), 4.5, 1.8, 0.0, 1.5, f == 8 ? 4 : 200);
    if (f == 8) before = tr.n.miss_left;
    rs_track_frame(&tr, &objs, 0.1 * f);
    if (f == 7) *car = tr.list.track[0].id;
  }
  *ninth = tr.list.track[0].object >= 0 ? tr.list.track[0].id : 0;
  *left = tr.n.miss_left - before;
}
START_TEST(t_lone_pair) {
  uint32_t car = 0, ninth = 0;
  uint64_t left = 0;
  lone_pair(24.0, &car, &ninth, &left);
  ck_assert_uint_eq(car, 1); /* one track throughout */
  ck_assert_uint_eq(ninth, car); /* cheaper than a miss: taken */
  ck_assert_uint_eq(left, 0);
  lone_pair(6.0, &car, &ninth, &left);
  ck_assert_uint_eq(car, 1);
  ck_assert_uint_eq(ninth, 0); /* dearer: the track goes without */
  ck_assert_uint_eq(left, 1);
}
END_TEST

/* Two walkers pass each other in opposite directions, 0.4-0.9 m apart
 * across; their clusters merge while they are within 1-3 m of each other
 * along (up to 2.3 s), one cluster of both, then come apart: each keeps
 * its id. */
START_TEST(t_walkers_pass) {
  static const double sep[3] = {0.4, 0.6, 0.9}, merge[3] = {1.0, 2.0, 3.0};
  for (int i = 0; i < 3; i++)
    for (int j = 0; j < 3; j++) {
      init_default();
      uint32_t a = 0, b = 0;
      int divided = 0;
      for (int f = 0; f < 120; f++) {
        const double t = 0.1 * f, xa = -8 + 1.4 * t, xb = 8 - 1.2 * t; /* they meet at 6.15 s */
        const double ja = 0.08 * sin(7.3 * t), jb = 0.08 * cos(5.1 * t);  /* the boxes wobble */
        clear();
        if (fabs(xa - xb) < merge[j]) {
          const double l = fabs(xa - xb) + 0.5, w = sep[i] + 0.5;
          put(t, 0.5 * (xa + xb), 0.5 * sep[i], fmax(l, w), fmin(l, w), l >= w ? 0.0 : M_PI / 2, 1.7, 50);
        } else {
          put(t, xa + ja, jb, 0.5, 0.4, 0.0, 1.7, 25);
          put(t, xb + jb, sep[i] + ja, 0.5, 0.4, 0.0, 1.7, 25);
        }
        rs_track_frame(&tr, &objs, t + 0.05);
        if (f == 30) a = tr.list.object_track[0], b = tr.list.object_track[1];
        if (f > 30 && objs.count == 2)
          ck_assert_msg(tr.list.object_track[0] == a && tr.list.object_track[1] == b,
                        "%.1f m apart, merged within %.0f m: at %.1f s ids %u %u, not %u %u", sep[i], merge[j], t,
                        tr.list.object_track[0], tr.list.object_track[1], a, b);
        /* merged and apart by more than a walker's width: each one's returns go to its own track */
        if (f > 30 && objs.count == 1 && rs_track_divided(&tr, 0) && fabs(xa - xb) > 0.6) {
          divided++;
          ck_assert_uint_eq(rs_track_owner(&tr, 0, xa, 0.0), a);
          ck_assert_uint_eq(rs_track_owner(&tr, 0, xb, sep[i]), b);
        }
      }
      ck_assert_uint_ne(a, b);
      ck_assert_uint_eq(tr.n.born, 2);
      ck_assert_msg(divided > 0, "%.1f m apart, merged within %.0f m: never divided", sep[i], merge[j]);
    }
}
END_TEST

/* two cars queued at the line, their clusters merged into one for 1 s:
 * both keep their ids, no new track */
START_TEST(t_queued_merge) {
  init_default();
  uint32_t a = 0, b = 0;
  for (int f = 0; f < 80; f++) {
    double t = 0.1 * f;
    /* both drive in, stop at x = 0 and x = -6.5 */
    double xa = t < 2 ? -20 + 10 * t : 0.0, xb = t < 2 ? -26.5 + 10 * t : -6.5;
    clear();
    if (f >= 40 && f < 50) {
      put(t, 0.5 * (xa + xb), 0.0, 11.0, 1.8, 0.0, 1.5, 240); /* one cluster over both */
    } else {
      car(t, xa, 0.0, 0.0);
      car(t, xb, 0.0, 0.0);
    }
    rs_track_frame(&tr, &objs, t + 0.05);
    if (f == 10) {
      a = tr.list.object_track[0];
      b = tr.list.object_track[1];
    }
    if (f > 10 && (f < 40 || f >= 50)) {
      ck_assert_uint_eq(tr.list.object_track[0], a);
      ck_assert_uint_eq(tr.list.object_track[1], b);
    }
    if (f >= 40 && f < 50) {
      ck_assert_uint_eq(tr.list.count, 2);
      ck_assert(rs_track_held(&tr.list.track[0]) && rs_track_held(&tr.list.track[1]));
      ck_assert_uint_eq(tr.list.object_track[0], a); /* the lower id carries the cluster */
      /* its returns are divided: each car's own to its track, wherever in the car */
      ck_assert(rs_track_divided(&tr, 0));
      for (double u = -2.2; u <= 2.2; u += 0.4)
        for (double v = -0.8; v <= 0.8; v += 0.4) {
          ck_assert_uint_eq(rs_track_owner(&tr, 0, xa + u, v), a);
          ck_assert_uint_eq(rs_track_owner(&tr, 0, xb + u, v), b);
        }
    } else {
      ck_assert(!rs_track_divided(&tr, 0) && !rs_track_divided(&tr, 1));
      ck_assert_uint_eq(rs_track_owner(&tr, 1, xb, 0.0), tr.list.object_track[1]); /* not divided: the object's */
    }
    ck_assert_uint_eq(rs_track_owner(&tr, objs.count, 0.0, 0.0), 0); /* no such object */
  }
  ck_assert_uint_eq(tr.n.born, 2);
  ck_assert_float_eq(find_id(a)->speed, 0.0f);
}
END_TEST

/* a car hidden at 2 s (its track coasting, then lost, predicted on at
 * 2 m/s) while another drives through its predicted position the other way
 * at 8 m/s: the passing car keeps its id (the older, unseen track is not the
 * same object: they do not move alike) */
START_TEST(t_passing_not_stitched) {
  init_default();
  uint32_t a = 0, b = 0;
  for (int f = 0; f < 60; f++) {
    const double t = 0.1 * f;
    clear();
    if (t < 2.0) car(t, -10 + 2 * t, 0.0, 0.0);
    car(t, 30 - 8 * t, 0.5, M_PI);
    rs_track_frame(&tr, &objs, t + 0.05);
    if (f == 10) a = tr.list.object_track[0], b = tr.list.object_track[1];
    if (f > 10) ck_assert_msg(tr.list.object_track[objs.count - 1] == b, "at %.1f s the passing car is %u, not %u", t,
                              tr.list.object_track[objs.count - 1], b);
  }
  ck_assert_uint_ne(a, b);
  ck_assert_uint_eq(tr.n.stitched, 0);
}
END_TEST

/* stitch_alike. Car A stands at (0, 15) and is not seen after 3 s (it went on unseen: below the
 * beams, behind a van). Car B, in the same lane behind it, seen in the same frames as A, drives up at
 * 3.5 m/s and through where A stood 2 s after A was last seen. They were seen together, so B's track
 * is A's only if they move alike; A's velocity is 0 but its uncertainty grew while unseen. Returns
 * whether B's returns carried A's id in any frame. */
static bool standing_car_taken(int stitch_alike) {
  init_knob("stitch_alike", stitch_alike);
  uint32_t a = 0, b = 0;
  bool taken = false;
  for (int f = 0; f < 70; f++) {
    const double t = 0.1 * f;
    clear();
    if (t < 3.0) car(t, 0.0, 15.0, 0.0);
    car(t, -17.5 + 3.5 * t, 15.0, 0.0);
    rs_track_frame(&tr, &objs, t + 0.05);
    if (f == 20) a = tr.list.object_track[0], b = tr.list.object_track[1];
    if (t >= 3.0) taken |= tr.list.object_track[0] == a;
  }
  ck_assert_uint_ne(a, 0);
  ck_assert_uint_ne(b, 0);
  ck_assert_uint_ne(a, b);
  return taken;
}
START_TEST(t_standing_not_stitched) {
  ck_assert_msg(!standing_car_taken(1), "the passing car took the standing car's id");
  ck_assert_msg(standing_car_taken(0), "without stitch_alike the case is not made");
}
END_TEST

/* stitch_kin. Car A drives at 3 m/s along y = 15 for 3 s and is not seen again (it turned off,
 * or stays hidden). Car B, a faster one in the same lane, comes into view at 3.6 s 6.7 m behind
 * where A was last seen and drives on at 12 m/s, through the place A's track is predicted at:
 * had it been A, A would have had to speed up from 3 to 12 m/s in a second or two, and yet
 * be behind where it would have been at 3 m/s. Returns whether B's returns carried A's id in
 * any frame. */
static bool passing_taken(int stitch_kin) {
  init_knob("stitch_kin", stitch_kin);
  uint32_t a = 0;
  bool taken = false;
  for (int f = 0; f < 70; f++) {
    const double t = 0.1 * f;
    clear();
    if (t < 3.0) car(t, 3.0 * t, 15.0, 0.0);
    if (t >= 3.6) car(t, 2.0 + 12.0 * (t - 3.6), 15.0, 0.0);
    rs_track_frame(&tr, &objs, t + 0.05);
    if (f == 10) a = tr.list.object_track[0];
    if (t >= 3.6) taken |= tr.list.object_track[0] == a;
  }
  ck_assert_uint_ne(a, 0);
  return taken;
}

START_TEST(t_stitch_kin) {
  ck_assert(!passing_taken(1));
  ck_assert(passing_taken(0)); /* without it A's track takes B over (at 4.2 s) */
  knob_refused("stitch_kin", "2");
}
END_TEST

/* six walkers abreast, 1 m apart, merged into one cluster for 0.5 s: the
 * cluster's returns are divided between the first RS_TRACK_HOLD_MAX held
 * tracks, the others counted */
START_TEST(t_crowd_divided) {
  init_default();
  uint32_t id[6] = {0};
  for (int f = 0; f < 40; f++) {
    const double t = 0.1 * f, y = 1.2 * t;
    clear();
    if (f < 35) {
      for (int w = 0; w < 6; w++) put(t, w * 1.0, y, 0.5, 0.4, 0.0, 1.7, 25);
    } else {
      put(t, 2.5, y, 5.5, 0.5, 0.0, 1.7, 200);
    }
    rs_track_frame(&tr, &objs, t + 0.05);
    if (f == 34)
      for (int w = 0; w < 6; w++) id[w] = tr.list.object_track[w];
    if (f >= 35) {
      ck_assert(rs_track_divided(&tr, 0));
      ck_assert_uint_eq(tr.hold_n[0], RS_TRACK_HOLD_MAX);
      for (int w = 0; w < RS_TRACK_HOLD_MAX; w++) ck_assert_uint_eq(rs_track_owner(&tr, 0, w * 1.0, y), id[w]);
    }
  }
  ck_assert_uint_eq(tr.n.hold_overflow, 5 * (6 - RS_TRACK_HOLD_MAX));
  ck_assert_uint_eq(tr.n.born, 6);
}
END_TEST

/* a car seen as two clusters (front and rear) for 0.5 s: no new track */
START_TEST(t_split) {
  init_default();
  uint32_t id = 0;
  for (int f = 0; f < 40; f++) {
    double t = 0.1 * f, x = -30 + 8 * t;
    clear();
    if (f >= 20 && f < 25) {
      put(t, x + 1.3, 10.0, 1.8, 1.8, 0.0, 1.5, 50);
      put(t, x - 1.3, 10.0, 1.6, 1.8, 0.0, 1.5, 40);
    } else {
      car(t, x, 10.0, 0.0);
    }
    rs_track_frame(&tr, &objs, t + 0.05);
    if (f == 5) id = tr.list.track[0].id;
    if (f > 5) {
      ck_assert_int_eq(confirmed_count(), 1);
      ck_assert_uint_eq(tr.list.object_track[0], id);
      if (f >= 20 && f < 25) ck_assert_uint_eq(tr.list.object_track[1], id);
    }
  }
  ck_assert_uint_eq(tr.n.born, 1);
  ck_assert_uint_ge(tr.n.absorbed, 4);
}
END_TEST

/* A car (4.5 x 1.8 m, 6 m/s along y = 10) whose visible part shrinks to the
 * far half of its rear for 2 s while its near side shows again ahead of it,
 * as a second cluster: the rear part's box shrinks, and so does the track's smoothed box,
 * but the side part still fits with it in the car's full size. Returns the
 * number of tracks confirmed in the run; *part_id: the id the side part's
 * returns carry in the last frame of the split (0 none), *id the car's.
 * full, car_m: split_full_size and split_car_m. */
static uint64_t shrinking_split(int full, double car_m, uint32_t *id, uint32_t *part_id) {
  init_knobs("split_full_size", full, "split_car_m", car_m);
  *id = *part_id = 0;
  for (int f = 0; f < 50; f++) {
    const double t = 0.1 * f, front = 12.0 + 6.0 * t, rear = front - 4.5;
    clear();
    if (f >= 20 && f < 40) {
      /* the rear part: 4.5 m down to 0.6 m long, its far half only (0.8 m wide) */
      const double vis = fmax(0.6, 4.5 - 0.4 * (f - 20)), w = fmax(0.8, 1.8 - 0.1 * (f - 20));
      put(t, rear + 0.5 * vis, 10.0 + 0.5 * (1.8 - w), vis, w, 0.0, 1.5, (uint32_t)(8 + 25 * vis));
      if (f >= 28) {
        const double side = fmin(3.0, 0.5 + 0.25 * (f - 28)); /* the near side's front end, growing */
        put(t, front - 0.5 * side, 9.1, side, 0.08, 0.0, 1.2, (uint32_t)(6 + 6 * side));
      }
    } else {
      car(t, rear + 2.25, 10.0, 0.0);
    }
    rs_track_frame(&tr, &objs, t + 0.05);
    if (f == 10) *id = tr.list.object_track[0];
    if (f == 39) *part_id = tr.list.object_track[1];
  }
  return tr.n.confirmed;
}

START_TEST(t_split_shrinking) {
  uint32_t id, part;
  const uint64_t on = shrinking_split(1, 0.0, &id, &part);
  ck_assert_uint_ne(id, 0);
  ck_assert_uint_eq(on, 1);
  ck_assert_uint_eq(part, id);
  const uint64_t off = shrinking_split(0, 0.0, &id, &part);
  ck_assert_uint_ge(off, 2); /* the side part as a track of its own */
  ck_assert_uint_ne(part, id);
  /* split_car_m alone keeps it too: the side part and the rear span the car's 4.5 m */
  ck_assert_uint_eq(shrinking_split(0, 5.0, &id, &part), 1);
  ck_assert_uint_eq(part, id);
}
END_TEST

/* split_car_m. A car (4.5 m) at v m/s along y = 15 seen for 2 s only by its rear 2.4 m (the car beside
 * it hides the rest), then for 1 s as two parts: its rear 2 m and, 1.7 m ahead, its front 0.8 m.
 * The two parts span 4.5 m: more than the track ever saw (2.4 m and the margin) but a car's
 * length. Returns the tracks born; *part_id: the id the front part's returns carry in the last
 * frame of the split, *id the car's. gap: how far behind the car's rear the front part is put
 * instead (a following car's front: 0 for the car's own); wid: the boxes' width (a face seen:
 * less than the car's); across: how far the front part lies across from the rear. */
static uint64_t car_split(double split_car_m, double v, double gap, double wid, double across, uint32_t *id,
                          uint32_t *part_id) {
  init_knob("split_car_m", split_car_m);
  *id = *part_id = 0;
  for (int f = 0; f < 30; f++) {
    const double t = 0.1 * f, rear = -40.0 + v * t;
    clear();
    if (f < 20) {
      put(t, rear + 1.2, 15.0, 2.4, wid, 0.0, 1.5, 80);
    } else {
      put(t, rear + 1.0, 15.0, 2.0, wid, 0.0, 1.5, 70);
      const double front = gap > 0 ? rear - gap - 0.4 : rear + 4.1;
      put(t, front, 15.0 + across, 0.8, wid, 0.0, 1.5, 30);
    }
    rs_track_frame(&tr, &objs, t + 0.05);
    if (f == 10) *id = tr.list.object_track[0];
    if (f == 29) *part_id = tr.list.object_track[1];
  }
  return tr.n.born;
}

START_TEST(t_split_car) {
  uint32_t id, part;
  ck_assert_uint_eq(car_split(5.0, 10.0, 0.0, 1.8, 0.0, &id, &part), 1);
  ck_assert_uint_ne(id, 0);
  ck_assert_uint_eq(part, id); /* the front part carries the car's id */
  ck_assert_uint_ge(car_split(0.0, 10.0, 0.0, 1.8, 0.0, &id, &part), 2); /* off: the front part a track of its own */
  ck_assert_uint_ne(part, id);
  ck_assert_uint_ge(car_split(5.0, 2.0, 0.0, 1.8, 0.0, &id, &part), 2); /* a car at 2 m/s: not a moving one's */
  ck_assert_uint_ne(part, id);
  /* the front of a car following 2.5 m behind: the two span 5.3 m, more than a car */
  ck_assert_uint_ge(car_split(5.0, 10.0, 2.5, 1.8, 0.0, &id, &part), 2);
  ck_assert_uint_ne(part, id);
  /* seen as faces 0.5 m wide, the front 1.2 m across from the rear (1.7 m across in all, more than the
   * track's width and the margin, less than a car's 2.5 m): one track */
  ck_assert_uint_eq(car_split(5.0, 10.0, 0.0, 0.5, 1.2, &id, &part), 1);
  ck_assert_uint_eq(part, id);
  /* ... the front 3 m across (3.5 m in all: the next lane's) a track of its own */
  ck_assert_uint_ge(car_split(5.0, 10.0, 0.0, 0.5, 3.0, &id, &part), 2);
  ck_assert_uint_ne(part, id);
  knob_refused("split_car_m", "-1");
  knob_refused("split_car_m", "21");
}
END_TEST

/* the frame at which a track on the +x side (at[0]) and on the -x side (at[1]) was first confirmed */
static void note_confirmed(int at[2], int f) {
  for (uint32_t i = 0; i < tr.list.count; i++) {
    const rs_track_t *k = &tr.list.track[i];
    const int which = k->x[0] > 0 ? 0 : 1;
    if (k->state != RS_TRACK_TENTATIVE && at[which] < 0) at[which] = f;
  }
}

/* A car waiting at the line from the first frame (its centre within 3 cm)
 * confirms at its third hit, 0.2 s; a small cluster as still (12 returns, one
 * row thin: a part the beams cut off a car) only after 1.5 s; a car whose centre wanders by 0.4 m, or missed once (a
 * miss also bars the 1.5 s rule: it confirms by moving), not at its third
 * hit either; with confirm_still_spread 0, the car too waits 1.5 s. */
START_TEST(t_still_vehicle_confirms_fast) {
  for (int variant = 0; variant < 4; variant++) {
    if (variant == 3) init_knob("confirm_still_spread", 0);
    else init_default();
    int confirmed_at[2] = {-1, -1};
    for (int f = 0; f < 20; f++) {
      const double t = 50.0 + 0.1 * f, j = 0.03 * ((f % 3) - 1);
      clear();
      const double wander = variant == 1 ? (f % 2 ? 0.4 : 0.0) : 0.0;
      if (!(variant == 2 && f == 1)) car(t, 20.0 + j + wander, 5.0 - j, 0.0);
      put(t, -12.0 + j, 9.0, 0.6, 0.5, 0.0, 0.02, 12);
      rs_track_frame(&tr, &objs, t + 0.05);
      note_confirmed(confirmed_at, f);
    }
    ck_assert_int_eq(tr.n.born, 2);
    if (variant == 0) ck_assert_int_eq(confirmed_at[0], 2);
    else if (variant == 3) ck_assert_int_ge(confirmed_at[0], 14); /* after 1.5 s of hits */
    else ck_assert(confirmed_at[0] < 0 || confirmed_at[0] >= 14); /* not at its third hit */
    ck_assert_int_ge(confirmed_at[1], 14);
  }
}
END_TEST

/* The same far off: a car waiting 50 m away, hit by 15 returns (a VLP-16's
 * share there), confirms at its third hit too (the returns needed fall with
 * the square of the range beyond confirm_still_range, 20 m: 30 -> 8 here);
 * a still cluster of 15 returns 15 m away (a part of a near car split off by
 * the beams: one row thin) waits 1.5 s; with confirm_still_range 0 the far car waits too. */
static int far_still_confirmed(double range_m, uint32_t returns, uint32_t *near_at) {
  init_knob("confirm_still_range", range_m);
  int at[2] = {-1, -1};
  for (int f = 0; f < 20; f++) {
    const double t = 50.0 + 0.1 * f, j = 0.03 * ((f % 3) - 1);
    clear();
    put(t, 48.0 + j, 14.0 - j, 4.5, 1.8, 0.0, 1.2, returns);
    put(t, -10.0 + j, -11.0, 1.2, 0.8, 0.0, 0.05, 15);
    rs_track_frame(&tr, &objs, t + 0.05);
    note_confirmed(at, f);
  }
  ck_assert_uint_eq(tr.n.born, 2);
  *near_at = (uint32_t)at[1];
  return at[0];
}

/* The still rule's window (confirm_still_window): a car waiting 48 m away whose
 * first box lay 0.5 m beside the rest of its views (a partial first view),
 * then within 3 cm, confirms at its fourth hit, when its last three
 * measurements lie within the spread; with the window off it waits 1.5 s. The
 * same car seen as two still pieces 2.5 m apart (both first views off), each
 * beside the other, waits too: neither is confirmed by the window while
 * another track lies beside it. So does a cluster whose returns come and go
 * about the bar (9 and 6 in turn, the bar 8 there: leaves far off). A window
 * of 1 is off. Returns
 * the frame of the first confirmation (x > 0), -1 none. */
static int window_confirmed(int window, bool parts, bool sparse) {
  init_knob("confirm_still_window", window);
  int at[2] = {-1, -1};
  for (int f = 0; f < 20; f++) {
    const double t = 70.0 + 0.1 * f, j = 0.03 * ((f % 3) - 1), off = f == 0 ? 0.5 : 0.0;
    const uint32_t returns = sparse ? (f % 2 ? 6u : 9u) : 15u;
    clear();
    if (parts) {
      put(t, 47.0 + j + off, 14.0 - j, 2.0, 1.8, 0.0, 1.2, returns);
      put(t, 49.5 + j - off, 14.0 - j, 2.0, 1.8, 0.0, 1.2, returns);
    } else {
      put(t, 48.0 + j + off, 14.0 - j, 4.5, 1.8, 0.0, 1.2, returns);
    }
    rs_track_frame(&tr, &objs, t + 0.05);
    note_confirmed(at, f);
  }
  ck_assert_uint_eq(tr.n.born, parts ? 2u : 1u);
  return at[0];
}

START_TEST(t_still_window) {
  ck_assert_int_eq(defaults().confirm_still_window, 3);
  ck_assert_int_eq(window_confirmed(3, false, false), 3);
  ck_assert_int_ge(window_confirmed(0, false, false), 14); /* after 1.5 s of hits */
  ck_assert_int_eq(window_confirmed(2, false, false), 2);  /* two measurements: at the third hit */
  ck_assert_int_eq(window_confirmed(4, false, false), 4);
  ck_assert_int_ge(window_confirmed(3, true, false), 14);
  ck_assert_int_ge(window_confirmed(3, false, true), 14);
  ck_assert_int_ge(window_confirmed(1, false, false), 14); /* one measurement is still within itself: off */
  knob_refused("confirm_still_window", "5");
  knob_refused("confirm_still_window", "-1");
}
END_TEST

/* The steady rule (confirm_steady): a truck setting off 15 m away at 1.5 m/s,
 * 9.6 m long, 300 returns a frame, moves 0.15 m a frame: farther than the
 * still spread there (0.23 m) in two frames, so neither the still rule nor its
 * window confirms it. It confirms at its fourth hit, when its last three
 * measurements lie on one way at one pace; with the rule off it waits for
 * confirm_move_m (0.8 m) to its seventh. The same truck's cluster jumping
 * 0.3 m ahead in every other frame (two pieces taking turns, leaves in the
 * wind before it) is not steady: the rule confirms it no sooner than without
 * it. (A walker as
 * steady is confirmed as soon by walking, confirm_walk_m.) Returns the frame
 * of the first confirmation, -1 none. */
static int steady_confirmed(int on, bool jumps) {
  init_knob("confirm_steady", on);
  int at = -1;
  for (int f = 0; f < 20 && at < 0; f++) {
    const double t = 90.0 + 0.1 * f;
    clear();
    put(t, -15.0 + 0.15 * f + (jumps && f % 2 ? 0.3 : 0.0), 2.0, 9.6, 2.5, 0.0, 3.2, 300);
    rs_track_frame(&tr, &objs, t + 0.05);
    ck_assert_uint_eq(tr.list.count, 1);
    if (tr.list.track[0].state != RS_TRACK_TENTATIVE) at = f;
  }
  ck_assert_uint_eq(tr.n.born, 1);
  return at;
}

/* Who keeps the fast rules from a track (window_clear; clear_beside,
 * clear_part_share, clear_longer): a car setting off 15 m away at 1.5 m/s,
 * 150 returns, passes the steady rule at its fourth hit (t_steady), with
 * - NEXT: a truck waiting in the next lane, 3.5 m across (the centres 3.5 m
 *   apart, nearer than half their lengths and 1 m: 8 m). The car's box, on
 *   the truck's axes, is 1.35 m from the truck's: no part of it. The car
 *   confirms at its fourth hit with clear_beside, at its seventh (0.8 m moved)
 *   without;
 * - AHEAD: the same truck standing 0.5 m ahead of the car's front in its lane
 *   (a piece of one vehicle could lie there): it waits either way;
 * - PIECE: a piece of 6 returns 1.9 m beside its side, 0.4 m long (the car's
 *   150: under clear_part_share of them; the car longer than it by over 0.5
 *   m): no claim on it with the share or clear_longer, a claim with neither;
 * - LONGER: the car standing 0.5 m ahead of a truck setting off (the truck's
 *   the track looked at): a truck is no piece of a car (clear_longer).
 * Returns the frame of the confirmation of the track that sets off (the
 * first born), -1 none. */
enum { NEXT, AHEAD, PIECE, LONGER };
static int beside_confirmed(int kind, int beside, double share, int longer) {
  init_named(3, (const char *const[]){"clear_beside", "clear_part_share", "clear_longer"},
             (const double[]){beside, share, longer});
  int at = -1;
  for (int f = 0; f < 20 && at < 0; f++) {
    const double t = 95.0 + 0.1 * f, x = -15.0 + 0.15 * f;
    clear();
    if (kind == LONGER) {
      put(t, x, 2.0, 9.6, 2.5, 0.0, 3.2, 300);
      put(t, -15.0 + 4.8 + 0.5 + 2.25, 2.0, 4.5, 1.8, 0.0, 1.5, 150);
    } else {
      put(t, x, 2.0, 4.5, 1.8, 0.0, 1.5, 150);
    }
    if (kind == NEXT) put(t, -15.0, 5.5, 9.6, 2.5, 0.0, 3.2, 300);
    if (kind == AHEAD) put(t, x + 2.25 + 0.5 + 4.8, 2.0, 9.6, 2.5, 0.0, 3.2, 300);
    if (kind == PIECE) put(t, -15.0, 3.9, 0.4, 0.3, 0.0, 0.5, 6);
    rs_track_frame(&tr, &objs, t + 0.05);
    ck_assert_uint_eq(tr.n.born, 2);
    const rs_track_t *k = find_id(1);
    ck_assert_ptr_nonnull(k);
    ck_assert_float_eq_tol(k->length, kind == LONGER ? 9.6f : 4.5f, 0.01f); /* its own object throughout */
    if (k->state != RS_TRACK_TENTATIVE) at = f;
  }
  return at;
}

START_TEST(t_window_clear) {
  const rs_track_cfg_t d = defaults();
  ck_assert_int_eq(d.clear_beside, 1);
  ck_assert_double_eq(d.clear_part_share, 0.25);
  ck_assert_int_eq(d.clear_longer, 1);
  ck_assert_int_eq(beside_confirmed(NEXT, 1, 0.25, 1), 3);
  ck_assert_int_eq(beside_confirmed(NEXT, 0, 0.25, 1), 6);
  ck_assert_int_eq(beside_confirmed(AHEAD, 1, 0.25, 1), 6);
  ck_assert_int_eq(beside_confirmed(PIECE, 1, 0.25, 1), 3);
  ck_assert_int_eq(beside_confirmed(PIECE, 1, 0.25, 0), 3); /* the share alone */
  ck_assert_int_eq(beside_confirmed(PIECE, 1, 0.0, 0), 6);
  ck_assert_int_eq(beside_confirmed(PIECE, 1, 0.0, 1), 3); /* the length alone: 0.4 m long */
  ck_assert_int_eq(beside_confirmed(LONGER, 1, 0.25, 1), 3);
  ck_assert_int_eq(beside_confirmed(LONGER, 1, 0.25, 0), 6);
  knob_refused("clear_beside", "2");
  knob_refused("clear_longer", "-1");
  knob_refused("clear_part_share", "1.5");
  knob_refused("clear_part_share", "-0.1");
}
END_TEST

START_TEST(t_steady) {
  ck_assert_int_eq(defaults().confirm_steady, 1);
  ck_assert_int_eq(steady_confirmed(1, false), 3);
  ck_assert_int_eq(steady_confirmed(0, false), 6);
  const int jumping = steady_confirmed(1, true);
  ck_assert_int_gt(jumping, 3);
  ck_assert_int_eq(jumping, steady_confirmed(0, true));
  knob_refused("confirm_steady", "2");
  knob_refused("confirm_steady", "-1");
}
END_TEST

START_TEST(t_far_still_confirms_fast) {
  uint32_t near_at;
  ck_assert_int_eq(far_still_confirmed(20.0, 15, &near_at), 2);
  ck_assert_uint_ge(near_at, 14);
  ck_assert_int_ge(far_still_confirmed(0.0, 15, &near_at), 14);
  /* the bar never falls below RS_TRACK_STILL_POINTS_MIN (8): 9 returns there are enough, 7 are not */
  ck_assert_int_eq(far_still_confirmed(20.0, 9, &near_at), 2);
  ck_assert_int_ge(far_still_confirmed(20.0, 7, &near_at), 14);
}
END_TEST

/* A walker standing (or just setting off: 0.1 m/s) 10 m away, hit by 22
 * returns in every frame, confirms at its fourth hit (confirm_walker_points,
 * 20), not after 1.5 s as a vehicle-sized still cluster of 22 returns (a
 * part of a near car) does; with confirm_walker_points 0, or with 16
 * returns, the walker waits 1.5 s too (confirm_upright_points off here:
 * t_walker_upright_confirms_fast). The returns at 0, 1, 2: the walker's
 * frame, the car part's. The walker at (x, y), `height` tall. */
static void walker_still_at(int walker_points, int upright_points, int pace, double x, double y, double height,
                            uint32_t returns, double step, double jitter, int at[2]) {
  rs_track_cfg_t c;
  rs_track_cfg_default(&c);
  c.confirm_walker_points = walker_points;
  c.confirm_upright_points = upright_points;
  c.confirm_pace = pace;
  ck_assert_int_eq(rs_track_init(&tr, &c), RS_OK);
  at[0] = at[1] = -1;
  for (int f = 0; f < 20; f++) {
    const double t = 30.0 + 0.1 * f, j = jitter * ((f % 3) - 1);
    clear();
    put(t, x + step * f + j, y - j, 0.5, 0.4, 0.0, height, returns);
    put(t, -8.0 + j, -6.0, 2.2, 1.6, 0.0, 1.2, 22);
    rs_track_frame(&tr, &objs, t + 0.05);
    note_confirmed(at, f);
  }
  ck_assert_uint_eq(tr.n.born, 2);
}
static void walker_still_confirmed(int walker_points, uint32_t returns, int at[2]) {
  walker_still_at(walker_points, 0, 1, 8.0, 6.0, 1.7, returns, 0.01, 0.03, at);
}

START_TEST(t_walker_still_confirms_fast) {
  int at[2];
  walker_still_confirmed(20, 22, at);
  ck_assert_int_eq(at[0], 3);
  ck_assert_int_ge(at[1], 14);
  walker_still_confirmed(0, 22, at);
  ck_assert_int_ge(at[0], 14);
  walker_still_confirmed(20, 16, at);
  ck_assert_int_ge(at[0], 14);
}
END_TEST

/* a person at the kerb 22 m from a VLP-16 (the walkers' bar 20, scaled there to 17), as walker_still_at
 * runs it with the upright bar, confirm_pace, its height, returns, step a frame and jitter: confirmed at its
 * fourth hit (frame 3) when fast, else not before frame wait; the car part beside it waits 1.5 s */
typedef struct {
  int upright, pace;
  double height;
  uint32_t returns;
  double step, jitter;
  bool fast;
  int wait;
} kerb_case_t;
static void kerb_cases(const kerb_case_t *cs, size_t n) {
  for (size_t i = 0; i < n; i++) {
    int at[2];
    walker_still_at(20, cs[i].upright, cs[i].pace, 18.0, 12.6, cs[i].height, cs[i].returns, cs[i].step, cs[i].jitter, at);
    if (cs[i].fast)
      ck_assert_msg(at[0] == 3, "case %zu: confirmed at frame %d, not at its fourth hit", i, at[0]);
    else
      ck_assert_msg(at[0] >= cs[i].wait, "case %zu: confirmed at frame %d, before frame %d", i, at[0], cs[i].wait);
    ck_assert_int_ge(at[1], 14);
  }
}

/* A person waiting at the kerb 22 m from a VLP-16, two rows tall (0.75 m of
 * returns), swaying by 2 cm, hit by 12 returns: confirms at its fourth hit
 * with confirm_upright_points (8), after 1.5 s with it off (the walkers' bar,
 * 20 scaled to 22 m, is 17). Waiting 1.5 s either way: a sliver of the same
 * size and returns one row thin (0.02 m: what the beams cut off a car), the
 * person with 7 returns, and a bush of its size swaying by 0.12 m. */
START_TEST(t_walker_upright_confirms_fast) {
  static const kerb_case_t cs[] = {
      {8, 1, 0.75, 12, 0.0, 0.02, true, 0},   /* the person */
      {0, 1, 0.75, 12, 0.0, 0.02, false, 14}, /* the rule off */
      {8, 1, 0.02, 12, 0.0, 0.02, false, 14}, /* a one-row sliver */
      {8, 1, 0.75, 7, 0.0, 0.02, false, 14},  /* 7 returns */
      {8, 1, 1.2, 12, 0.0, 0.06, false, 14},  /* a bush swaying 0.12 m */
  };
  kerb_cases(cs, sizeof cs / sizeof cs[0]);
  rs_track_cfg_t c; /* on by default, and out of range refused */
  rs_track_cfg_default(&c);
  ck_assert_int_eq(c.confirm_upright_points, 8);
  knob_refused("confirm_upright_points", "-1");
}
END_TEST

/* confirm_pace. A person slowing into the crowd waiting at a kerb 22 m from
 * a VLP-16 (two rows tall, 12 returns), still walking at 0.3 m/s: it moves
 * 0.09 m in its first four frames and 0.12 m with its sway of 2 cm, more
 * than the 0.1 m the upright rule allows a standing person, and too slowly
 * for the walking rules. Its first four measurements lie along one line at
 * one pace: with confirm_pace it confirms at its fourth hit, without it once
 * it has walked 0.3 m (confirm_walk_m: its tenth frame or later). Waiting as
 * long either way: the same walker with 7 returns, and one whose four
 * measurements zigzag by 0.12 m (a bush swaying). */
START_TEST(t_walker_pace_confirms_fast) {
  static const kerb_case_t cs[] = {
      {8, 1, 0.75, 12, 0.03, 0.02, true, 0}, /* the person walking at 0.3 m/s */
      {8, 0, 0.75, 12, 0.03, 0.02, false, 9}, /* the rule off: once it has walked 0.3 m */
      {8, 1, 0.75, 7, 0.03, 0.02, false, 9},  /* 7 returns */
      {8, 1, 1.2, 12, 0.03, 0.06, false, 9},  /* zigzagging by 0.12 m */
  };
  kerb_cases(cs, sizeof cs / sizeof cs[0]);
  ck_assert_int_eq(defaults().confirm_pace, 1);
  knob_refused("confirm_pace", "2");
}
END_TEST

/* birth_far_points. A person on the sidewalk beyond a lane of cars, 30-40 m
 * from a VLP-16, shows its head and shoulders over the cars: one row, 4
 * returns. It walks at 1.3 m/s along the sidewalk (+x from x0, at y). With
 * with_car 1 a car drives beside it at the same pace 1.1 m nearer (its box 0.2 m
 * from the person's centre: a piece the beams split off the car), seen in
 * every frame; with 2 the car is seen in frames 0-4 only (then hidden,
 * its track coasting beside the piece) and the piece from frame 5 on (the
 * car's track takes it, or the clearance from its box keeps it from starting
 * one). The walker's track: born (and confirmed by walking, as any walker)
 * only from 4 returns in the window of 25 to 50 m and clear of the car. Returns the frame it was confirmed at, -1 never; *born: tracks
 * started. */
static int far_walker(int far_points, double x0, double y, uint32_t returns, int with_car, uint32_t *born) {
  rs_track_cfg_t c;
  rs_track_cfg_default(&c);
  c.birth_far_points = far_points;
  ck_assert_int_eq(rs_track_init(&tr, &c), RS_OK);
  int at = -1;
  for (int f = 0; f < 20; f++) {
    const double t = 40.0 + 0.1 * f, x = x0 + 0.13 * f, j = 0.02 * ((f % 3) - 1);
    clear();
    if (with_car != 2 || f >= 5) {
      put(t, x + j, y - j, 0.35, 0.2, 0.0, 0.05, returns);
      objs.obj[objs.count - 1].range_min = (float)(sqrt(x * x + y * y) - 0.2);
    }
    if (with_car == 1 || (with_car == 2 && f < 5)) {
      car(t, x, y - 1.1, 0.0);
      objs.obj[objs.count - 1].range_min = (float)(sqrt(x * x + (y - 1.1) * (y - 1.1)) - 2.0);
    }
    rs_track_frame(&tr, &objs, t + 0.05);
    for (uint32_t i = 0; i < tr.list.count; i++) {
      const rs_track_t *k = &tr.list.track[i];
      if (k->state != RS_TRACK_TENTATIVE && k->full_length < 1.0f && at < 0) at = f;
    }
  }
  *born = (uint32_t)tr.n.born;
  return at;
}

START_TEST(t_far_walker_born) {
  uint32_t born;
  ck_assert_int_le(far_walker(4, 28.0, 21.0, 4, 0, &born), 4); /* 35-37 m: born, confirmed walking */
  ck_assert_uint_eq(born, 1);
  const rs_track_t *w = &tr.list.track[0];
  ck_assert_double_eq_tol(hypot(w->x[2], w->x[3]), 1.3, 0.3);
  ck_assert_int_eq(far_walker(0, 28.0, 21.0, 4, 0, &born), -1); /* the rule off: 5 returns needed */
  ck_assert_uint_eq(born, 0);
  ck_assert_int_le(far_walker(0, 28.0, 21.0, 5, 0, &born), 4); /* (with 5, as always) */
  ck_assert_int_eq(far_walker(4, 28.0, 21.0, 3, 0, &born), -1); /* 3 returns */
  ck_assert_uint_eq(born, 0);
  ck_assert_int_eq(far_walker(4, 28.0, 45.0, 4, 0, &born), -1); /* 53-55 m: the ends of far vehicles */
  ck_assert_uint_eq(born, 0);
  ck_assert_int_eq(far_walker(4, 12.0, 15.0, 4, 0, &born), -1); /* 19-21 m: a near walker has more */
  ck_assert_uint_eq(born, 0);
  ck_assert_int_eq(far_walker(4, 28.0, 21.0, 4, 1, &born), -1); /* beside the car: a piece of it */
  ck_assert_uint_eq(born, 1);
  ck_assert_int_eq(far_walker(4, 28.0, 21.0, 4, 2, &born), -1); /* beside the hidden car's coasting track */
  ck_assert_uint_eq(born, 1);
  /* a frame of 40 such objects (far rain, leaves): RS_TRACK_FAR_BIRTHS_MAX looked at, the rest counted */
  init_default();
  clear();
  for (int k = 0; k < 40; k++) {
    put(50.0, 30.0 + 1.5 * (k % 8), 20.0 + 1.5 * (k / 8), 0.3, 0.2, 0.0, 0.05, 4);
    objs.obj[objs.count - 1].range_min = 40.0f;
  }
  rs_track_frame(&tr, &objs, 50.05);
  ck_assert_uint_eq(tr.n.born, RS_TRACK_FAR_BIRTHS_MAX);
  ck_assert_uint_eq(tr.n.far_born, RS_TRACK_FAR_BIRTHS_MAX);
  ck_assert_uint_eq(tr.n.far_dropped, 40 - RS_TRACK_FAR_BIRTHS_MAX);
  ck_assert_int_eq(defaults().birth_far_points, 4);
  knob_refused("birth_far_points", "-1");
  knob_refused("birth_far_to_m", "nan");
  /* a range that holds nothing is refused while far births are on, not taken as off */
  rs_track_cfg_t c = defaults();
  c.birth_far_from_m = 50.0;
  ck_assert_int_eq(rs_track_init(&tr, &c), RS_E_INVAL);
  c.birth_far_points = 0;
  ck_assert_int_eq(rs_track_init(&tr, &c), RS_OK);
}
END_TEST

/* walker_across_m. A walker goes east along a sidewalk at 1.3 m/s (12
 * returns, 22 m off) for 2 s, is hidden for 1.5 s, then an object of a
 * walker's size shows (across, along) from where its track predicts it:
 * returns whether the walker's track took it. */
static bool walker_takes(double across_m, double across, double along) {
  rs_track_cfg_t c;
  rs_track_cfg_default(&c);
  c.walker_across_m = across_m;
  ck_assert_int_eq(rs_track_init(&tr, &c), RS_OK);
  uint32_t id = 0;
  for (int f = 0; f < 36; f++) {
    const double t = 60.0 + 0.1 * f, x = 12.0 + 0.13 * f, j = 0.02 * ((f % 3) - 1);
    clear();
    if (f < 20) put(t, x + j, 20.0 - j, 0.5, 0.4, 0.0, 1.6, 12);
    else if (f == 35) put(t, x + along, 20.0 + across, 0.5, 0.4, 0.0, 1.6, 12);
    rs_track_frame(&tr, &objs, t + 0.05);
    if (f == 19) {
      ck_assert_uint_eq(tr.list.count, 1);
      ck_assert_int_eq(tr.list.track[0].state, RS_TRACK_CONFIRMED);
      id = tr.list.track[0].id;
    }
  }
  return tr.list.object_track[0] == id;
}

START_TEST(t_walker_across) {
  ck_assert(!walker_takes(1.5, -3.0, 0.0)); /* 3 m across its way, after 1.5 s: something else */
  ck_assert(walker_takes(0.0, -3.0, 0.0));  /* the rule off: taken */
  ck_assert(walker_takes(1.5, -0.5, 0.4));  /* on its way: taken */
  ck_assert(walker_takes(1.5, 0.0, -1.5));  /* slower than it was, on its way: taken */
  ck_assert_double_eq(defaults().walker_across_m, 1.5);
  knob_refused("walker_across_m", "-1");
}
END_TEST

/* foliage: a cluster at one place, there in half the frames, its centre
 * jittering by 0.3 m, for 20 s: never confirmed */
START_TEST(t_foliage_never_confirms) {
  init_default();
  uint64_t rng = 12345;
  for (int f = 0; f < 200; f++) {
    double t = 0.1 * f;
    clear();
    rng = rng * 6364136223846793005ull + 1442695040888963407ull;
    bool there = (rng >> 33) % 2;
    double jx = ((double)((rng >> 20) % 1000) / 1000.0 - 0.5) * 0.6, jy = ((double)((rng >> 40) % 1000) / 1000.0 - 0.5) * 0.6;
    if (there) put(t, 15 + jx, -7 + jy, 1.5, 1.0, 0.3, 1.2, 12);
    rs_track_frame(&tr, &objs, t + 0.05);
    ck_assert_int_eq(confirmed_count(), 0);
  }
  ck_assert_uint_ge(tr.n.born, 10);
  ck_assert_uint_eq(tr.n.confirmed, 0);
}
END_TEST

/* across column 0 (+Y, azimuth 0): one track */
/* A walker at 1.4 m/s is confirmed by its fourth frame (0.3 s: four hits,
 * its filtered position 0.3 m on, confirm_walk_m), not after the 0.8 m of
 * confirm_move_m (0.6 s and more) as with the rule off (and the steady rule
 * off: with 40 returns it is as steady as a still object's bar asks); the foliage of
 * t_foliage_never_confirms at a walker's size (0.6 x 0.5 m, jittering
 * 0.3 m, there in half the frames, 40 s) still never confirms (it did with
 * three hits and the path half as straight as long). */
static int walker_confirmed_frame(double walk_m) {
  init_knobs("confirm_walk_m", walk_m, "confirm_steady", walk_m > 0 ? 1 : 0); /* (as steady as it walks: t_steady) */
  for (int f = 0; f < 20; f++) {
    const double t = 0.1 * f;
    clear();
    put(t, 12.0 + 1.4 * t, 6.0, 0.6, 0.5, 0.0, 1.7, 40);
    rs_track_frame(&tr, &objs, t + 0.05);
    if (tr.list.track[0].state == RS_TRACK_CONFIRMED) return f;
  }
  return -1;
}

/* A walker coming out from under a VLP-16 (lowest beam 15 degrees down) is first seen as that beam's
 * arc across it: one row (2 cm of returns), 0.45 m long across its way, 15 returns, at the circle
 * where the beam passes its top (1.78 m below the sensor: 6.64 m out), the arc's centre moving out at
 * 0.7 m/s while the walker goes at 1.4. From x0 (m); jitter > 0: the arc's centre jumps by up to
 * +-jitter m each frame instead (a bush under the sensor swaying), for 1.2 s (under confirm_still_s).
 * Returns the frame its track is confirmed at, -1 none. */
static int arc_confirmed_frame(double cut_m, double x0, double jitter) {
  init_knob("confirm_cut_walk_m", cut_m);
  uint64_t rng = 4242;
  for (int f = 0; f < (jitter > 0 ? 12 : 20); f++) {
    const double t = 0.1 * f;
    rng = rng * 6364136223846793005ull + 1442695040888963407ull;
    const double jx = ((double)((rng >> 20) % 1000) / 1000.0 - 0.5) * 2.0 * jitter;
    const double jy = ((double)((rng >> 40) % 1000) / 1000.0 - 0.5) * 2.0 * jitter;
    clear();
    objs.lowest_beam_deg = -15.0f;
    put(t, jitter > 0 ? x0 + jx : x0 + 0.7 * t, 0.5 + jy, 0.45, 0.03, M_PI / 2, 0.02, 15);
    rs_track_frame(&tr, &objs, t + 0.05);
    ck_assert_uint_eq(tr.list.count, 1);
    if (tr.list.track[0].state == RS_TRACK_CONFIRMED) return f;
  }
  return -1;
}

START_TEST(t_walker_arc_confirms_fast) {
  /* at the fourth hit, 0.3 s after the first; with the rule off (confirm_walk_m's 0.3 m), two frames later */
  ck_assert_int_eq(arc_confirmed_frame(0.15, 6.7, 0.0), 3);
  ck_assert_int_ge(arc_confirmed_frame(0.0, 6.7, 0.0), 5);
  /* away from the circle the walkers' 0.3 m holds: the same arc 12 m out */
  ck_assert_int_ge(arc_confirmed_frame(0.15, 12.0, 0.0), 5);
  /* swaying in place, it is not confirmed in 1.2 s */
  ck_assert_int_eq(arc_confirmed_frame(0.15, 6.7, 0.15), -1);
  knob_refused("confirm_cut_walk_m", "-0.1");
}
END_TEST

START_TEST(t_walker_confirms_fast) {
  ck_assert_int_le(walker_confirmed_frame(0.3), 3);
  ck_assert_int_ge(walker_confirmed_frame(0.0), 5);
  init_default();
  uint64_t rng = 777;
  for (int f = 0; f < 400; f++) {
    const double t = 0.1 * f;
    clear();
    rng = rng * 6364136223846793005ull + 1442695040888963407ull;
    const bool there = (rng >> 33) % 2;
    const double jx = ((double)((rng >> 20) % 1000) / 1000.0 - 0.5) * 0.6, jy = ((double)((rng >> 40) % 1000) / 1000.0 - 0.5) * 0.6;
    if (there) put(t, 15 + jx, -7 + jy, 0.6, 0.5, 0.3, 1.2, 12);
    rs_track_frame(&tr, &objs, t + 0.05);
    ck_assert_int_eq(confirmed_count(), 0);
  }
  ck_assert_uint_ge(tr.n.born, 20);
}
END_TEST

/* A walker at 1.4 m/s, 12 m out, is not in its second frame (f = 1): that frame did not measure
 * the columns it stands in (a lost packet; the list's gap runs, here columns 310-326 of 1800, about
 * 62-65 degrees). With gap_unseen that frame is no miss: the walking rule confirms it at its fourth hit
 * (f = 4). Off, or with the frame's gap elsewhere (the other side of the sensor), it is a miss, the
 * rules that ask for a hit in every frame are barred and it waits for confirm_move_m's 0.8 m (f >= 6). */
static int gap_walker_confirmed(int on, bool gap_here, uint32_t *misses) {
  init_knob("gap_unseen", on);
  int at = -1;
  for (int f = 0; f < 12 && at < 0; f++) {
    const double t = 0.1 * f;
    clear();
    if (f == 1) {
      objs.gap_cols = 1800;
      objs.ngaps = 1;
      objs.gaps_dropped = 2; /* (runs beyond the list's room: counted) */
      objs.gap[0][0] = gap_here ? 310 : 1210;
      objs.gap[0][1] = gap_here ? 326 : 1226;
    } else {
      put(t, 12.0 + 1.4 * t, 6.0, 0.6, 0.5, 0.0, 1.7, 40);
    }
    rs_track_frame(&tr, &objs, t + 0.05);
    ck_assert_uint_eq(tr.list.count, 1);
    if (tr.list.track[0].state == RS_TRACK_CONFIRMED) at = f;
  }
  *misses = tr.list.track[0].misses;
  return at;
}

START_TEST(t_gap_unseen) {
  uint32_t misses;
  ck_assert_int_eq(defaults().gap_unseen, 1);
  ck_assert_int_eq(gap_walker_confirmed(1, true, &misses), 4);
  ck_assert_uint_eq(misses, 0);
  ck_assert_uint_eq(tr.n.gap_unseen, 1);
  ck_assert_uint_eq(tr.n.gap_runs_dropped, 2);
  ck_assert_int_ge(gap_walker_confirmed(0, true, &misses), 6);
  ck_assert_uint_eq(misses, 1);
  ck_assert_int_ge(gap_walker_confirmed(1, false, &misses), 6);
  ck_assert_uint_eq(misses, 1);
  ck_assert_uint_eq(tr.n.gap_unseen, 0);
  knob_refused("gap_unseen", "2");
  knob_refused("gap_unseen", "-1");
}
END_TEST

START_TEST(t_across_column_zero) {
  init_default();
  for (int f = 0; f < 40; f++) {
    double t = 0.1 * f;
    clear();
    car(t, -15 + 8 * t, 6.0, 0.0);
    rs_track_frame(&tr, &objs, t + 0.05);
  }
  ck_assert_uint_eq(tr.n.born, 1);
  ck_assert_double_eq_tol(tr.list.track[0].x[0], -15 + 8 * 3.9, 0.3);
}
END_TEST

/* a lost frame: the time step comes from the timestamps, the speed stays */
START_TEST(t_lost_frame_dt) {
  init_default();
  for (int f = 0; f < 40; f++) {
    if (f == 20 || f == 21 || f == 30) continue; /* frames lost in the network */
    double t = 0.1 * f;
    clear();
    car(t, 12 * t, -20.0, 0.0);
    rs_track_frame(&tr, &objs, t + 0.05);
    ck_assert_uint_eq(tr.list.count, 1);
    if (f > 10) ck_assert_double_eq_tol(tr.list.track[0].speed, 12.0, 0.4);
  }
  ck_assert_uint_eq(tr.n.born, 1);
  /* a timestamp that runs back is not a negative step */
  clear();
  car(1.0, 12 * 3.9, -20.0, 0.0);
  rs_track_frame(&tr, &objs, 1.05);
  ck_assert_uint_eq(tr.list.count, 1);
  ck_assert(isfinite(tr.list.track[0].x[0]));
}
END_TEST

/* more objects than tracks: RS_TRACK_MAX tracks, the rest counted */
START_TEST(t_capacity) {
  init_default();
  clear();
  for (int k = 0; k < RS_TRACK_MAX + 88; k++) put(0.0, (k % 30) * 10.0, (k / 30) * 10.0, 0.5, 0.5, 0.0, 1.7, 20);
  rs_track_frame(&tr, &objs, 0.05);
  ck_assert_uint_eq(tr.list.count, RS_TRACK_MAX);
  ck_assert_uint_eq(tr.n.overflow, 88);
  ck_assert_uint_eq(tr.list.track[RS_TRACK_MAX - 1].id, RS_TRACK_MAX);
  /* ids are never reused */
  clear();
  for (int f = 1; f < 15; f++) rs_track_frame(&tr, &objs, 0.1 * f + 0.05);
  ck_assert_uint_eq(tr.list.count, 0);
  put(2.0, 0, 0, 0.5, 0.5, 0.0, 1.7, 20);
  rs_track_frame(&tr, &objs, 2.05);
  ck_assert_uint_eq(tr.list.track[0].id, RS_TRACK_MAX + 1);
}
END_TEST

/* The two lookup grids (objects and tracks by position) are cleared each frame by the buckets they
 * were filled in, not wholesale: after every frame a bucket holds this frame's entries only. A bucket
 * left over would hand a later frame an object or a track that is gone. Twelve cars drive through,
 * then vanish; their tracks end. */
static void grids_live(uint32_t nobj) {
  uint32_t heads = 0, theads = 0;
  for (int b = 0; b < RS_TRACK_GRID_BUCKETS; b++) {
    if (tr.grid_head[b] >= 0) {
      heads++;
      ck_assert_int_lt(tr.grid_head[b], (int32_t)nobj);
    }
    if (tr.tgrid_head[b] >= 0) {
      theads++;
      ck_assert_int_lt(tr.tgrid_head[b], (int32_t)tr.tgrid_n);
    }
  }
  ck_assert_uint_le(heads, nobj);
  ck_assert_uint_le(theads, tr.tgrid_n);
}
START_TEST(t_grids_live) {
  init_default();
  int f = 0;
  for (; f < 20; f++) {
    clear();
    for (int k = 0; k < 12; k++) put(0.1 * f, -30.0 + f, 5.0 * k, 4.5, 1.8, 0.0, 1.5, 60);
    rs_track_frame(&tr, &objs, 0.1 * f + 0.05);
    grids_live(objs.count);
  }
  ck_assert_uint_eq(tr.list.count, 12);
  for (; f < 80 && tr.list.count > 0; f++) {
    clear();
    rs_track_frame(&tr, &objs, 0.1 * f + 0.05);
    grids_live(0);
  }
  ck_assert_uint_eq(tr.list.count, 0);
  clear(); /* the next frame's grid holds only its own car */
  put(0.1 * f, 0.0, 20.0, 4.5, 1.8, 0.0, 1.5, 60);
  rs_track_frame(&tr, &objs, 0.1 * f + 0.05);
  grids_live(1);
}
END_TEST

/* many objects in one crowded spot: a large group is assigned greedily, boundedly */
START_TEST(t_crowd_and_config) {
  init_default();
  for (int f = 0; f < 5; f++) {
    clear();
    for (int k = 0; k < 120; k++) put(0.1 * f, (k % 12) * 0.6, (k / 12) * 0.6, 0.5, 0.5, 0.0, 1.7, 10);
    rs_track_frame(&tr, &objs, 0.1 * f + 0.05);
  }
  ck_assert_uint_eq(tr.n.born, 120);
  ck_assert_uint_ge(tr.n.greedy_groups, 1);
  /* rs_track_init refuses a value out of range in the struct */
#define INIT_REFUSED(field, value)                                                         \
  do {                                                                                     \
    rs_track_cfg_t bad;                                                                    \
    rs_track_cfg_default(&bad);                                                            \
    bad.field = value;                                                                     \
    ck_assert_msg(rs_track_init(&tr, &bad) == RS_E_INVAL, #field " = " #value " accepted"); \
  } while (0)
  INIT_REFUSED(coast_s, 0);
  INIT_REFUSED(gate_m, NAN);
  INIT_REFUSED(q_small, 0);
  INIT_REFUSED(meas_sd_fit, -0.1);
  INIT_REFUSED(meas_sd_misfit, NAN);
  INIT_REFUSED(confirm_walk_m, NAN);
  INIT_REFUSED(hidden_anchor, 3);
  INIT_REFUSED(reacq_across_m, 21);
  INIT_REFUSED(split_full_size, -1);
  INIT_REFUSED(lost_walker_s, NAN);
  INIT_REFUSED(below_beam, 2);
  INIT_REFUSED(blind_s, -1);
  INIT_REFUSED(speed_imm, 2);
  INIT_REFUSED(q_jerk, 0);
  INIT_REFUSED(confirm_walker_points, -1);
  INIT_REFUSED(miss_cost, NAN);
  INIT_REFUSED(miss_cost, 1001);
#undef INIT_REFUSED
  /* set by name: in range taken, out of range refused with the parameter's name */
  rs_track_cfg_t c;
  rs_track_cfg_default(&c);
  char err[512];
  ck_assert_int_eq(rs_track_cfg_set(&c, "q_small", "0.5", err, sizeof err), RS_OK);
  ck_assert_double_eq(c.q_small, 0.5);
  ck_assert_int_eq(rs_track_cfg_set(&c, "meas_sd_fit", "0", err, sizeof err), RS_OK);
  ck_assert_double_eq(c.meas_sd_fit, 0.0);
  ck_assert_int_eq(rs_track_cfg_set(&c, "hidden_anchor", "0", err, sizeof err), RS_OK);
  ck_assert_int_eq(c.hidden_anchor, 0);
  ck_assert_int_eq(rs_track_cfg_set(&c, "confirm_walk_m", "0", err, sizeof err), RS_OK);
  ck_assert_double_eq(c.confirm_walk_m, 0.0);
  ck_assert_int_eq(rs_track_init(&tr, &c), RS_OK);
  static const char *const refused[][2] = {{"meas_sd_misfit", "11"}, {"hidden_anchor", "2"}, {"reacq_across_m", "-1"},
                                           {"split_full_size", "2"},  {"lost_walker_s", "61"},   {"below_beam", "-1"},
                                           {"blind_s", "x"},          {"speed_imm", "-1"},       {"q_jerk", "101"},
                                           {"confirm_walker_points", "-2"}};
  for (size_t k = 0; k < sizeof refused / sizeof refused[0]; k++) {
    ck_assert_int_eq(rs_track_cfg_set(&c, refused[k][0], refused[k][1], err, sizeof err), RS_E_INVAL);
    ck_assert_msg(strstr(err, refused[k][0]) != NULL, "%s", err);
  }
}
END_TEST

/* with a pose, every track also has its site-frame state */
START_TEST(t_site_frame) {
  init_default();
  rs_pose_t pose = {.x = 100.0, .y = 50.0, .z = 5.0, .yaw = M_PI / 2}; /* the sensor's +X is the site's +Y */
  rs_track_set_pose(&tr, &pose);
  for (int f = 0; f < 30; f++) {
    double t = 0.1 * f;
    clear();
    car(t, -20 + 10 * t, 8.0, 0.0); /* sensor frame: along +X at 10 m/s */
    rs_track_frame(&tr, &objs, t + 0.05);
  }
  ck_assert(tr.list.site_valid);
  const rs_track_t *k = &tr.list.track[0];
  ck_assert_double_eq_tol(k->site[0], 100.0 - k->x[1], 1e-3); /* site = Rz(90) p + t */
  ck_assert_double_eq_tol(k->site[1], 50.0 + k->x[0], 1e-3);
  ck_assert_double_eq_tol(k->site[2], 5.0 + k->z_min, 1e-3);
  ck_assert_double_eq_tol(k->site_v[0], 0.0, 0.2);
  ck_assert_double_eq_tol(k->site_v[1], 10.0, 0.2);
  ck_assert_double_eq_tol(k->site_heading, M_PI / 2, 0.05);
  rs_track_set_pose(&tr, NULL);
  ck_assert(!tr.list.site_valid);
}
END_TEST

/* the same input gives the same tracks, bit for bit */
START_TEST(t_deterministic) {
  static rs_track_list_t first;
  for (int run = 0; run < 2; run++) {
    init_default();
    for (int f = 0; f < 30; f++) {
      double t = 0.1 * f;
      clear();
      for (int k = 0; k < 20; k++) car(t, -30 + 10 * t + k * 0.3, k * 4.0, 0.0);
      rs_track_frame(&tr, &objs, t + 0.05);
    }
    if (run == 0) first = tr.list;
  }
  ck_assert_uint_eq(first.count, tr.list.count);
  ck_assert_int_eq(memcmp(first.track, tr.list.track, sizeof first.track[0] * first.count), 0);
}
END_TEST

int main(void) {
  Suite *s = suite_create("track");
  TCase *tc = tcase_create("sequences");
  tcase_set_timeout(tc, 60);
  tcase_add_test(tc, t_constant_velocity);
  tcase_add_test(tc, t_crossing_paths);
  tcase_add_test(tc, t_stop_and_go);
  tcase_add_test(tc, t_occlusion);
  tcase_add_test(tc, t_reacquired_after_long_occlusion);
  tcase_add_test(tc, t_sparse_pedestrian);
  tcase_add_test(tc, t_classes);
  tcase_add_test(tc, t_class_votes);
  tcase_add_test(tc, t_class_top_above_ground);
  tcase_add_test(tc, t_below_beam);
  tcase_add_test(tc, t_below_beam_top);
  tcase_add_test(tc, t_blind_circle);
  tcase_add_test(tc, t_blind_walker);
  tcase_add_test(tc, t_blind_walker_line);
  tcase_add_test(tc, t_blind_walker_fifo);
  tcase_add_test(tc, t_blind_walker_cross);
  tcase_add_test(tc, t_blind_walker_pace);
  tcase_add_test(tc, t_blind_circle_crossing);
  tcase_add_test(tc, t_blind_circle_turn);
  tcase_add_test(tc, t_queued_merge);
  tcase_add_test(tc, t_passing_not_stitched);
  tcase_add_test(tc, t_standing_not_stitched);
  tcase_add_test(tc, t_stitch_kin);
  tcase_add_test(tc, t_crowd_divided);
  tcase_add_test(tc, t_split);
  tcase_add_test(tc, t_split_shrinking);
  tcase_add_test(tc, t_split_car);
  tcase_add_test(tc, t_walker_hidden_longer);
  tcase_add_test(tc, t_split_side);
  tcase_add_test(tc, t_split_turned);
  tcase_add_test(tc, t_split_near_circle);
  tcase_add_test(tc, t_merge_parts);
  tcase_add_test(tc, t_merge_front);
  tcase_add_test(tc, t_tent_claim);
  tcase_add_test(tc, t_speed_follows);
  tcase_add_test(tc, t_speed_imm);
  tcase_add_test(tc, t_imm_birth_wide);
  tcase_add_test(tc, t_speed_full_length);
  tcase_add_test(tc, t_misfit_own);
  tcase_add_test(tc, t_turn_rate);
  tcase_add_test(tc, t_hidden_end);
  tcase_add_test(tc, t_seen_end);
  tcase_add_test(tc, t_near_across);
  tcase_add_test(tc, t_near_side);
  tcase_add_test(tc, t_circle_whole);
  tcase_add_test(tc, t_uncovered);
  tcase_add_test(tc, t_next_lane_not_taken);
  tcase_add_test(tc, t_pedestrian_not_vehicle);
  tcase_add_test(tc, t_walked_not_vehicle);
  tcase_add_test(tc, t_walker_reacq);
  tcase_add_test(tc, t_walker_part);
  tcase_add_test(tc, t_miss_cost);
  tcase_add_test(tc, t_lone_pair);
  tcase_add_test(tc, t_walkers_pass);
  tcase_add_test(tc, t_foliage_never_confirms);
  tcase_add_test(tc, t_walker_confirms_fast);
  tcase_add_test(tc, t_gap_unseen);
  tcase_add_test(tc, t_walker_arc_confirms_fast);
  tcase_add_test(tc, t_still_vehicle_confirms_fast);
  tcase_add_test(tc, t_far_still_confirms_fast);
  tcase_add_test(tc, t_still_window);
  tcase_add_test(tc, t_steady);
  tcase_add_test(tc, t_window_clear);
  tcase_add_test(tc, t_walker_still_confirms_fast);
  tcase_add_test(tc, t_walker_upright_confirms_fast);
  tcase_add_test(tc, t_walker_pace_confirms_fast);
  tcase_add_test(tc, t_far_walker_born);
  tcase_add_test(tc, t_walker_across);
  tcase_add_test(tc, t_dup_box);
  tcase_add_test(tc, t_seen_across);
  tcase_add_test(tc, t_kin_reacq);
  tcase_add_test(tc, t_twin);
  tcase_add_test(tc, t_across_column_zero);
  tcase_add_test(tc, t_lost_frame_dt);
  tcase_add_test(tc, t_capacity);
  tcase_add_test(tc, t_grids_live);
  tcase_add_test(tc, t_still_lane);
  tcase_add_test(tc, t_still_coast);
  tcase_add_test(tc, t_still_reverse);
  tcase_add_test(tc, t_queue_coast);
  tcase_add_test(tc, t_brake_coast);
  tcase_add_test(tc, t_brake_not_at_circle);
  tcase_add_test(tc, t_crowd_and_config);
  tcase_add_test(tc, t_deterministic);
  tcase_add_test(tc, t_site_frame);
  suite_add_tcase(s, tc);
  return tu_run(s);
}

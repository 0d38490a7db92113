/* check_count - counting lines on hand-built track lists with known answers:
 * direction, once per track and line, crossings made while tentative,
 * coasting tracks not counted, intervals on multiples of the interval,
 * tracks forgotten, the site frame of a pose, bad lines; zones: entries,
 * exits, occupancy, a track first seen inside, tentative and coasting
 * tracks, bad zones; hidden crossings (a track first seen past a line;
 * placed in its lane, not where a partial first box's path met the line;
 * none against the track's own velocity; one taken back, its track standing,
 * leaves the line to be crossed);
 * the class delay (a crossing tallied under the class its track settles on);
 * a lost track taken up again past a line; unseen crossings (a track
 * followed on its prediction, held until it is seen again or ends; past the
 * line for the band then); the band (a car standing on a line, a track
 * running on over it as its car stops);
 * a walker crossing back (counted each way once, also back before its first
 * crossing was tallied; a car's track once); walkers in a file (one's
 * crossing on its prediction not taken for the one's ahead); the
 * crossing events (time, place, class, how, the spot speed around the
 * crossing; none for a crossing taken back; a full pool counted). */
#include "roadscan/perception/count.h"
#include "roadscan/util/error.h"
#include "testutil.h"

#include <math.h>
#include <stdio.h>
#include <string.h>

static rs_counter_t cnt;
static rs_track_list_t tl;

static void one(uint32_t id, rs_track_state_t st, rs_class_t cls, double x, double y) {
  rs_track_t *t = &tl.track[tl.count++];
  memset(t, 0, sizeof *t);
  t->id = id;
  t->state = st;
  t->cls = cls;
  t->x[0] = x;
  t->x[1] = y;
}

/* the last track added is this long (its full length: RS_COUNT_VEHICLE_M or more is a vehicle's) */
static void sized(float full_length) { tl.track[tl.count - 1].full_length = full_length; }

static void setup(const char *const *texts, int n, const rs_pose_t *pose, double interval) {
  rs_count_line_t lines[RS_COUNT_LINES];
  char err[RS_ERRMSG_SIZE];
  for (int i = 0; i < n; i++) ck_assert_int_eq(rs_count_parse_line(texts[i], &lines[i], err, sizeof err), RS_OK);
  ck_assert_int_eq(rs_count_init(&cnt, lines, n, pose, interval, err, sizeof err), RS_OK);
  cnt.class_delay_s = 0; /* tallied when found: t_class_delay tests the delay */
}

static uint32_t sum(const uint32_t *v) {
  uint32_t s = 0;
  for (int k = 0; k < RS_CLASS_COUNT; k++) s += v[k];
  return s;
}

START_TEST(t_directions_and_once) {
  static const char *const l[] = {"gate 0 -5 0 5"}; /* along +y: its left is -x */
  setup(l, 1, NULL, 60);
  /* car 1 drives -x (right to left of the line: forward), car 2 +x (backward); car 1 turns
   * back and crosses again: counted once (a vehicle's track crossing back is another vehicle's it
   * took, or its centre wandering; t_walker_back has the walkers') */
  for (int f = 0; f < 40; f++) {
    double t = 100.0 + 0.1 * f;
    tl.count = 0;
    const double x1 = f < 20 ? 10.0 - f : -10.0 + (f - 20);
    one(1, RS_TRACK_CONFIRMED, RS_CLASS_CAR, x1, 1.0);
    sized(4.5f);
    one(2, RS_TRACK_CONFIRMED, RS_CLASS_BUS, -10.0 + f, -2.0);
    one(3, RS_TRACK_CONFIRMED, RS_CLASS_CAR, -10.0 + f, 8.0); /* beyond the line's end */
    rs_count_frame(&cnt, &tl, t);
  }
  ck_assert_uint_eq(cnt.total[0].forward[RS_CLASS_CAR], 1);
  ck_assert_uint_eq(sum(cnt.total[0].forward), 1);
  ck_assert_uint_eq(cnt.total[0].backward[RS_CLASS_BUS], 1);
  ck_assert_uint_eq(sum(cnt.total[0].backward), 1);
  ck_assert_uint_eq(cnt.crossings, 2);
}
END_TEST

/* a track that crossed while tentative is counted when it is confirmed; a
 * coasting one (a prediction) is not counted until it is seen again */
START_TEST(t_tentative_and_coasting) {
  static const char *const l[] = {"a 0 -5 0 5"};
  setup(l, 1, NULL, 60);
  const rs_track_state_t st[6] = {RS_TRACK_TENTATIVE, RS_TRACK_TENTATIVE, RS_TRACK_TENTATIVE, RS_TRACK_CONFIRMED,
                                  RS_TRACK_CONFIRMED, RS_TRACK_CONFIRMED};
  for (int f = 0; f < 6; f++) {
    tl.count = 0;
    one(7, st[f], RS_CLASS_PEDESTRIAN, -1.0 + 0.5 * f, 0.0); /* crosses x = 0 at the third frame */
    rs_count_frame(&cnt, &tl, 10.0 + 0.1 * f);
    ck_assert_uint_eq(cnt.crossings, f < 3 ? 0u : 1u);
  }
  ck_assert_uint_eq(cnt.total[0].backward[RS_CLASS_PEDESTRIAN], 1);
  /* coasting across the line: not counted; seen again beyond it: counted then */
  setup(l, 1, NULL, 60);
  const rs_track_state_t st2[5] = {RS_TRACK_CONFIRMED, RS_TRACK_COASTING, RS_TRACK_COASTING, RS_TRACK_COASTING,
                                   RS_TRACK_CONFIRMED};
  for (int f = 0; f < 5; f++) {
    tl.count = 0;
    one(8, st2[f], RS_CLASS_CAR, 2.0 - f, 0.0);
    rs_count_frame(&cnt, &tl, 10.0 + 0.1 * f);
    ck_assert_uint_eq(cnt.crossings, f < 4 ? 0u : 1u);
  }
  ck_assert_uint_eq(cnt.total[0].forward[RS_CLASS_CAR], 1);
}
END_TEST

/* intervals close on multiples of the interval; a track gone is forgotten
 * (its id, seen again later, is a new track: counted again) */
START_TEST(t_intervals_and_forgetting) {
  static const char *const l[] = {"a 0 -5 0 5", "b 5 -5 5 5"};
  setup(l, 2, NULL, 10);
  int closed = 0;
  double last_end = 0;
  for (int f = 0; f < 250; f++) { /* 25 s from t = 1003 */
    const double t = 1003.0 + 0.1 * f;
    tl.count = 0;
    if (f < 110) one(1, RS_TRACK_CONFIRMED, RS_CLASS_CAR, -5.0 + 0.1 * f, 0.0); /* crosses a at 1008, b at 1013 */
    if (f >= 150) one(1, RS_TRACK_CONFIRMED, RS_CLASS_CAR, -5.0 + 0.1 * (f - 150), 0.0); /* the id again: a at 1023 */
    if (rs_count_frame(&cnt, &tl, t)) {
      closed++;
      ck_assert_double_eq_tol(fmod(cnt.closed.t_end, 10.0), 0.0, 1e-6);
      if (closed == 1) {
        ck_assert_double_eq_tol(cnt.closed.t_start, 1003.0, 1e-6);
        ck_assert_uint_eq(sum(cnt.closed.line[0].backward), 1);
        ck_assert_uint_eq(sum(cnt.closed.line[1].backward), 0);
      }
      if (closed == 2) ck_assert_uint_eq(sum(cnt.closed.line[1].backward), 1);
      last_end = cnt.closed.t_end;
    }
  }
  ck_assert_int_eq(closed, 2);
  ck_assert_double_eq_tol(last_end, 1020.0, 1e-6);
  ck_assert(rs_count_flush(&cnt, 1027.9));
  ck_assert_uint_eq(sum(cnt.closed.line[0].backward), 1); /* the new track 1 */
  ck_assert_uint_eq(sum(cnt.total[0].backward), 2);
  ck_assert_uint_eq(cnt.intervals, 3);
  for (uint32_t i = 0; i < RS_COUNT_SLOTS; i++) ck_assert(cnt.slot[i].id == 0 || cnt.slot[i].id == 1);
}
END_TEST

/* many tracks at once, appearing and leaving: the table stays consistent */
START_TEST(t_many_tracks) {
  static const char *const l[] = {"a 0 -1000 0 1000"};
  setup(l, 1, NULL, 60);
  for (int f = 0; f < 60; f++) {
    tl.count = 0;
    for (uint32_t k = 0; k < RS_TRACK_MAX; k++) {
      const uint32_t id = 1 + k + (uint32_t)(f / 20) * 1000; /* a new set of ids every 2 s */
      one(id, RS_TRACK_CONFIRMED, RS_CLASS_CAR, -1.0 + 0.1 * (f % 20), (double)k);
    }
    rs_count_frame(&cnt, &tl, 0.1 * f);
  }
  ck_assert_uint_eq(cnt.crossings, 3 * RS_TRACK_MAX);
  ck_assert_uint_eq(cnt.forgotten_full, 0);
}
END_TEST

/* with a pose, lines are in the site frame */
START_TEST(t_site_frame) {
  static const char *const l[] = {"a 100 -5 100 5"};
  rs_pose_t pose = {.x = 100.0, .y = 0.0, .z = 5.0, .yaw = M_PI / 2}; /* the sensor's +X is the site's +Y */
  setup(l, 1, &pose, 60);
  for (int f = 0; f < 10; f++) {
    tl.count = 0;
    one(1, RS_TRACK_CONFIRMED, RS_CLASS_CAR, 0.0, 5.0 - f); /* site x = 100 - y: crosses site x = 100 */
    rs_count_frame(&cnt, &tl, 0.1 * f);
  }
  ck_assert_uint_eq(cnt.crossings, 1);
}
END_TEST

/* A square zone 10 m wide around the origin: car 1 drives through it (entered, exited), pedestrian 2
 * is first seen inside and walks out (exited only), car 3 enters while tentative (counted entered when
 * confirmed), car 4 coasts out (not exited until seen outside); occupancy counts the confirmed inside. */
START_TEST(t_zones) {
  static const char *const l[] = {"gate 100 0 100 10"};
  setup(l, 1, NULL, 60);
  rs_count_zone_t z[2];
  char err[RS_ERRMSG_SIZE];
  ck_assert_int_eq(rs_count_parse_zone("box -5 -5 5 -5 5 5 -5 5", &z[0], err, sizeof err), RS_OK);
  ck_assert_int_eq(rs_count_parse_zone("tri 20 0 30 0 25 8", &z[1], err, sizeof err), RS_OK);
  ck_assert_int_eq(rs_count_add_zones(&cnt, z, 2, err, sizeof err), RS_OK);
  ck_assert(rs_count_inside(&z[0], 0, 0) && !rs_count_inside(&z[0], 6, 0) && rs_count_inside(&z[1], 25, 3));
  ck_assert(!rs_count_inside(&z[1], 21, 7));
  uint32_t occ_max = 0;
  for (int f = 0; f < 30; f++) {
    tl.count = 0;
    one(1, RS_TRACK_CONFIRMED, RS_CLASS_CAR, -10.0 + f, 0.0);                     /* in at x = -5, out at 5 */
    one(2, RS_TRACK_CONFIRMED, RS_CLASS_PEDESTRIAN, 0.0, 0.5 * f);                /* out at y = 5 */
    one(3, f < 8 ? RS_TRACK_TENTATIVE : RS_TRACK_CONFIRMED, RS_CLASS_CAR, 0.0, -12.0 + f); /* in at y = -5 (f 7) */
    one(4, f >= 2 && f < 9 ? RS_TRACK_COASTING : RS_TRACK_CONFIRMED, RS_CLASS_VAN_TRUCK, 3.0 + f, 2.0); /* out at x = 5 */
    rs_count_frame(&cnt, &tl, 10.0 + 0.1 * f);
    if (cnt.cur.zone[0].occupancy > occ_max) occ_max = cnt.cur.zone[0].occupancy;
    if (f == 0) ck_assert_uint_eq(cnt.cur.zone[0].occupancy, 2); /* 2 and 4: 3 tentative, 1 outside */
    if (f == 3) ck_assert_uint_eq(sum(cnt.zone_total[0].exited), 0);   /* 4 coasts out: not yet */
    if (f == 9) ck_assert_uint_eq(cnt.zone_total[0].exited[RS_CLASS_VAN_TRUCK], 1); /* seen again outside */
  }
  const rs_zone_tally_t *t = &cnt.zone_total[0];
  ck_assert_uint_eq(t->entered[RS_CLASS_CAR], 2); /* 1, and 3 once confirmed */
  ck_assert_uint_eq(sum(t->entered), 2);          /* 2 was first seen inside, 4 too */
  ck_assert_uint_eq(t->exited[RS_CLASS_CAR], 2);  /* 1 at x = 5, 3 at y = 5 */
  ck_assert_uint_eq(t->exited[RS_CLASS_PEDESTRIAN], 1);
  ck_assert_uint_eq(t->exited[RS_CLASS_VAN_TRUCK], 1);
  ck_assert_uint_eq(sum(t->exited), 4);
  ck_assert_uint_eq(t->occupancy, 0);
  ck_assert_uint_eq(t->occupancy_max, occ_max);
  ck_assert_uint_ge(occ_max, 3); /* 1, 2 and 3 inside together */
  /* the van drives on through the triangle (y = 2: from x = 21.25 to 28.75) */
  ck_assert_uint_eq(cnt.zone_total[1].entered[RS_CLASS_VAN_TRUCK], 1);
  ck_assert_uint_eq(cnt.zone_total[1].exited[RS_CLASS_VAN_TRUCK], 1);
  ck_assert_uint_eq(sum(cnt.zone_total[1].entered) + sum(cnt.zone_total[1].exited), 2);
  ck_assert_uint_eq(cnt.zone_events, 8);
  /* intervals carry the zone tallies */
  ck_assert(rs_count_flush(&cnt, 20.0));
  ck_assert_uint_eq(sum(cnt.closed.zone[0].entered), 2);
  ck_assert_uint_eq(cnt.closed.zone[0].occupancy_max, occ_max);
  /* bad zones, each named */
  static const struct {
    const char *text, *why;
  } bad[] = {{"z 0 0 1 1", "3 to 16 corners"},
             {"z 0 0 1 1 2", "3 to 16 corners"},
             {"z 0 0 1 1 2 2", "no area"},
             {"z 0 0 4 4 4 0 0 6", "its edges cross"},
             {"z 0 0 1 0 x 1", "pairs of numbers"},
             {"z 0 0 1 0 1 1 0 1 0 2 1 2 0 3 1 3 0 4 1 4 0 5 1 5 0 6 1 6 0 7 1 7 0 8", "more than 16 corners"},
             {"a-name-much-longer-than-thirty-one 0 0 1 0 0 1", "longer than 31"}};
  for (size_t i = 0; i < sizeof bad / sizeof bad[0]; i++) {
    ck_assert_int_eq(rs_count_parse_zone(bad[i].text, &z[0], err, sizeof err), RS_E_INVAL);
    ck_assert_msg(strstr(err, bad[i].why) != NULL, "%s: %s", bad[i].text, err);
  }
  ck_assert_int_eq(rs_count_parse_zone("box -5 -5 5 -5 5 5 -5 5", &z[0], err, sizeof err), RS_OK);
  ck_assert_int_eq(rs_count_add_zones(&cnt, z, 1, err, sizeof err), RS_E_INVAL); /* the name is taken */
  ck_assert_ptr_nonnull(strstr(err, "two zones of that name"));
}
END_TEST

/* the run starts at t = 50 with an empty frame */
static void run_start(void) {
  tl.count = 0;
  rs_count_frame(&cnt, &tl, 50.0);
}

/* A far-lane car hidden by the near lanes' traffic until it is past the line:
 * first seen 6 m past it, moving away at 8 m/s, it is counted once, in its
 * direction, at its first confirmed frame. Not counted: the same when its
 * earlier track was counted crossing there (the vehicle seen before it was
 * hidden), one first seen in the run's first frame (it may have crossed
 * before the run), one moving slower than 1 m/s, one first seen farther
 * than hidden_s of its motion from the line, and any with hidden_s = 0. */
static void drive(uint32_t id, double t0, double x0, double vx, int frames, int tentative) {
  for (int f = 0; f < frames; f++) {
    tl.count = 0;
    one(id, f < tentative ? RS_TRACK_TENTATIVE : RS_TRACK_CONFIRMED, RS_CLASS_CAR, x0 + vx * 0.1 * f, 3.0);
    rs_count_frame(&cnt, &tl, t0 + 0.1 * f);
  }
}

START_TEST(t_hidden_crossings) {
  static const char *const l[] = {"gate 0 -5 0 5"}; /* forward: towards -x */
  setup(l, 1, NULL, 60);
  run_start();
  drive(1, 52.0, -6.0, -8.0, 6, 3);
  ck_assert_uint_eq(cnt.crossings, 1);
  ck_assert_uint_eq(cnt.hidden, 1);
  ck_assert_uint_eq(cnt.total[0].forward[RS_CLASS_CAR], 1);
  ck_assert_uint_eq(sum(cnt.total[0].backward), 0);
  /* the other way: backward */
  drive(2, 53.0, 5.0, 6.0, 6, 3);
  ck_assert_uint_eq(cnt.hidden, 2);
  ck_assert_uint_eq(sum(cnt.total[0].backward), 1);
  /* off: nothing inferred */
  setup(l, 1, NULL, 60);
  cnt.hidden_s = 0;
  run_start();
  drive(1, 52.0, -6.0, -8.0, 6, 3);
  ck_assert_uint_eq(cnt.crossings, 0);

  /* seen crossing by track 3 (x 4 -> -4 at 8 m/s, crossing at t = 60.5), lost at
   * -4 m, taken up by track 4 first seen at -8 m at t = 61.0: the same car */
  setup(l, 1, NULL, 60);
  run_start();
  drive(3, 60.0, 4.0, -8.0, 11, 0);
  ck_assert_uint_eq(cnt.crossings, 1);
  drive(4, 61.0, -8.0, -8.0, 6, 3);
  ck_assert_uint_eq(cnt.crossings, 1);
  ck_assert_uint_eq(cnt.hidden, 0);
  ck_assert_uint_eq(cnt.hidden_dup, 1);
  /* a car in the next lane at the same time is another car: counted */
  for (int f = 0; f < 6; f++) {
    tl.count = 0;
    one(5, f < 3 ? RS_TRACK_TENTATIVE : RS_TRACK_CONFIRMED, RS_CLASS_CAR, -8.0 - 0.8 * f, -0.5);
    rs_count_frame(&cnt, &tl, 61.0 + 0.1 * f);
  }
  ck_assert_uint_eq(cnt.hidden, 1);
  ck_assert_uint_eq(cnt.crossings, 2);

  /* first seen in the run's first frame: not counted */
  setup(l, 1, NULL, 60);
  drive(6, 70.0, -2.0, -8.0, 6, 3);
  ck_assert_uint_eq(cnt.crossings, 0);
  /* slower than 1 m/s (a queue creeping): not counted */
  drive(7, 71.0, -1.0, -0.5, 10, 3);
  ck_assert_uint_eq(cnt.crossings, 0);
  /* first seen 30 m past the line at 8 m/s: more than 3 s of its motion away */
  drive(8, 72.0, -30.0, -8.0, 6, 3);
  ck_assert_uint_eq(cnt.crossings, 0);
  /* moving towards the line from past it: it crosses it (backward), seen */
  drive(9, 73.0, -6.0, 8.0, 12, 3);
  ck_assert_uint_eq(cnt.crossings, 1);
  ck_assert_uint_eq(sum(cnt.total[0].backward), 1);
  ck_assert_uint_eq(cnt.hidden, 0);
}
END_TEST

/* Where a hidden crossing is placed along the line. Car A (track 3, lane y =
 * -2) is seen crossing at t = 60.5, 3 m along the line. Car B (track 4), in
 * the next lane (y = 1.5, 3.5 m over), comes out from behind others past the
 * line at t = 61.0: its first box is a part of it, its centre at y = -0.5,
 * settling on its lane 0.5 m a frame. At its first confirmed frame its mean
 * velocity points across (8 m/s along, 5 m/s across), and its path run back
 * meets the line 2 m along it at t = 60.5: within 1.5 s and 2.5 m of car A's
 * crossing. Placed where the track is along the line (hidden_at_track, the
 * default: 6 m), it is another car, counted; placed where its path met the
 * line, it is taken for car A's new track and not counted. */
static void next_lane(bool at_track) {
  static const char *const l[] = {"gate 0 -5 0 5"}; /* forward: towards -x */
  setup(l, 1, NULL, 60);
  cnt.hidden_at_track = at_track;
  run_start();
  for (int f = 0; f < 11; f++) { /* car A: x 4 -> -4 at 8 m/s in lane y = -2 */
    tl.count = 0;
    one(3, RS_TRACK_CONFIRMED, RS_CLASS_CAR, 4.0 - 0.8 * f, -2.0);
    rs_count_frame(&cnt, &tl, 60.0 + 0.1 * f);
  }
  ck_assert_uint_eq(cnt.crossings, 1);
  for (int f = 0; f < 8; f++) { /* car B: first seen at (-4, -0.5), tentative for 3 frames */
    tl.count = 0;
    one(4, f < 3 ? RS_TRACK_TENTATIVE : RS_TRACK_CONFIRMED, RS_CLASS_CAR, -4.0 - 0.8 * f, -0.5 + 0.5 * (f < 4 ? f : 4));
    rs_count_frame(&cnt, &tl, 61.0 + 0.1 * f);
  }
}

START_TEST(t_hidden_place) {
  next_lane(true);
  ck_assert_uint_eq(cnt.crossings, 2);
  ck_assert_uint_eq(cnt.hidden, 1);
  ck_assert_uint_eq(cnt.hidden_dup, 0);
  ck_assert_uint_eq(cnt.total[0].forward[RS_CLASS_CAR], 2);
  next_lane(false);
  ck_assert_uint_eq(cnt.crossings, 1);
  ck_assert_uint_eq(cnt.hidden, 0);
  ck_assert_uint_eq(cnt.hidden_dup, 1);
}
END_TEST

/* Beside the line, not across it. A sidewalk's short line "walk 0 -2 0 2"; a car first seen at (-1,
 * 1.5), its boxes growing across towards its lane for 3 frames while it drives off along -x at 8 m/s: its
 * path run back meets the line within it (1.5 - 0.125 s of its mean velocity across). Its lane at y = 3,
 * 1 m beyond the line's end: counted, placed 5 m along; at y = 7.5, 5.5 m beyond: not counted (its
 * lane is not on the line). */
static uint64_t beside(double lane) {
  static const char *const l[] = {"walk 0 -2 0 2"};
  setup(l, 1, NULL, 60);
  run_start();
  for (int f = 0; f < 8; f++) {
    tl.count = 0;
    one(1, f < 3 ? RS_TRACK_TENTATIVE : RS_TRACK_CONFIRMED, RS_CLASS_CAR, -1.0 - 0.8 * f,
        1.5 + (lane - 1.5) * (f < 3 ? f : 3) / 3.0);
    rs_count_frame(&cnt, &tl, 52.0 + 0.1 * f);
  }
  return cnt.crossings;
}

START_TEST(t_hidden_beside) {
  ck_assert_uint_eq(beside(3.0), 1);
  ck_assert_uint_eq(cnt.hidden, 1);
  ck_assert_uint_eq(beside(7.5), 0);
  ck_assert_uint_eq(cnt.hidden, 0);
}
END_TEST

/* Unseen crossings. A car (20 hits) drives towards the line at x = 0 at
 * -8 m/s (forward), seen until x = 2.4 (t = 100.7), then listed coasting
 * and lost on its prediction, which crosses the line at t = 101.0. The
 * crossing is held while the car is unseen and tallied when its track
 * leaves the list (a vehicle hidden by the one behind it); seen again past
 * the line it is counted once; seen again before it (it had stopped behind
 * a bus) it is taken back, and its later crossing, seen, is counted. Not
 * followed: an unseen track whose prediction crosses more than unseen_s
 * after its last update (with unseen_s 4 it is), one of 3 hits (a flicker
 * that confirmed), one slower than 1 m/s, any with unseen_s = 0.
 * hidden_car: from x0 at vx, seen in frames 0 .. seen_until and from
 * again_from on (then from again_x at vx; -1: never), listed until
 * listed_until; unseen, its prediction is listed (coasting for 1 s, then
 * lost). Then one empty frame: the track has left the list. The vehicle's
 * new track counting the crossing first: the prediction's is not counted. */
/* a car's track at (x, 1) moving vx along x, appended to the list */
static void car_row(uint32_t id, uint32_t hits, rs_track_state_t st, double x, double vx, double t_update) {
  one(id, st, RS_CLASS_CAR, x, 1.0);
  rs_track_t *k = &tl.track[tl.count - 1];
  k->hits = hits;
  k->x[2] = vx;
  k->t_update = t_update;
}

static void hidden_car(uint32_t id, uint32_t hits, double x0, double vx, int seen_until, int listed_until,
                       int again_from, double again_x) {
  int f = 0;
  for (; f <= listed_until; f++) {
    const double t = 100.0 + 0.1 * f;
    const bool again = again_from >= 0 && f >= again_from, seen = f <= seen_until || again;
    tl.count = 0;
    car_row(id, hits, seen ? RS_TRACK_CONFIRMED : (f - seen_until <= 10 ? RS_TRACK_COASTING : RS_TRACK_LOST),
            again ? again_x + vx * 0.1 * (f - again_from) : x0 + vx * 0.1 * f, vx, seen ? t : 100.0 + 0.1 * seen_until);
    rs_count_frame(&cnt, &tl, t);
  }
  tl.count = 0;
  rs_count_frame(&cnt, &tl, 100.0 + 0.1 * f);
}

/* hidden_car (never seen again) on a fresh counter of line l with unseen_s (< 0: the default):
 * the crossings tallied */
static uint32_t hidden_crossings(double unseen_s, uint32_t hits, double x0, double vx, int seen_until, int listed_until) {
  static const char *const l[] = {"gate 0 -5 0 5"};
  setup(l, 1, NULL, 60);
  if (unseen_s >= 0) cnt.unseen_s = unseen_s;
  hidden_car(1, hits, x0, vx, seen_until, listed_until, -1, 0);
  return cnt.crossings;
}

START_TEST(t_unseen_crossings) {
  static const char *const l[] = {"gate 0 -5 0 5"}; /* forward: towards -x */
  /* hidden from x = 2.4 on, never seen again: held while listed, tallied when it leaves the list */
  setup(l, 1, NULL, 60);
  hidden_car(1, 20, 8.0, -8.0, 7, 24, -1, 0);
  ck_assert_uint_eq(cnt.crossings, 1);
  ck_assert_uint_eq(cnt.total[0].forward[RS_CLASS_CAR], 1);
  ck_assert_uint_eq(cnt.unseen, 1);
  ck_assert_uint_eq(cnt.pending, 0);
  /* held while unseen: the same car listed (lost) for a frame more, nothing tallied yet */
  setup(l, 1, NULL, 60);
  for (int f = 0; f <= 20; f++) {
    tl.count = 0;
    car_row(7, 20, f <= 7 ? RS_TRACK_CONFIRMED : RS_TRACK_COASTING, 8.0 - 0.8 * f, -8.0, 100.0 + 0.1 * (f <= 7 ? f : 7));
    rs_count_frame(&cnt, &tl, 100.0 + 0.1 * f);
  }
  ck_assert_uint_eq(cnt.crossings, 0);
  ck_assert_uint_eq(cnt.pending, 1);
  /* seen again past the line (x = -5 at t = 101.3): counted once, when seen */
  setup(l, 1, NULL, 60);
  hidden_car(2, 20, 8.0, -8.0, 7, 20, 13, -5.0);
  ck_assert_uint_eq(cnt.crossings, 1);
  ck_assert_uint_eq(cnt.total[0].forward[RS_CLASS_CAR], 1);
  ck_assert_uint_eq(cnt.unseen, 1);
  /* seen again before it (stopped at x = 2 behind a bus, seen at t = 101.4): taken back ... */
  setup(l, 1, NULL, 60);
  for (int f = 0; f <= 30; f++) {
    const bool seen = f <= 7 || f >= 14;
    /* seen, coming; its prediction, over the line; seen again, waiting before it; then driving across, seen */
    const double x = f <= 7 ? 8.0 - 0.8 * f : f < 14 ? 2.4 - 0.8 * (f - 7) : f < 20 ? 2.0 : 2.0 - 0.8 * (f - 19);
    tl.count = 0;
    car_row(3, 20, seen ? RS_TRACK_CONFIRMED : RS_TRACK_COASTING, x, f >= 14 && f < 20 ? 0.0 : -8.0,
            100.0 + 0.1 * (seen ? f : 7));
    rs_count_frame(&cnt, &tl, 100.0 + 0.1 * f);
    if (f == 19) {
      ck_assert_uint_eq(cnt.unseen_undone, 1);
      ck_assert_uint_eq(cnt.pending + cnt.crossings, 0);
    }
  }
  ck_assert_uint_eq(cnt.crossings, 1); /* ... and counted once when it crosses, seen */
  ck_assert_uint_eq(cnt.total[0].forward[RS_CLASS_CAR], 1);
  ck_assert_uint_eq(sum(cnt.total[0].backward), 0);
  ck_assert_uint_eq(cnt.unseen, 0);
  /* the prediction crosses 3 s after the last update (at 2 m/s, unseen from x = 6): not followed;
   * with unseen_s 4 it is */
  ck_assert_uint_eq(hidden_crossings(-1, 20, 8.0, -2.0, 10, 45), 0);
  ck_assert_uint_eq(hidden_crossings(4.0, 20, 8.0, -2.0, 10, 45), 1);
  /* 3 hits; slower than 1 m/s (0.8 m/s from x = 1, crossing 0.75 s after it was last seen); off */
  ck_assert_uint_eq(hidden_crossings(-1, 3, 8.0, -8.0, 7, 24), 0);
  ck_assert_uint_eq(hidden_crossings(-1, 20, 1.0, -0.8, 5, 20), 0);
  ck_assert_uint_eq(hidden_crossings(0, 20, 8.0, -8.0, 7, 24), 0);
  ck_assert_uint_eq(cnt.unseen, 0);
  /* the vehicle's new track (8) seen crossing at t = 100.9, 0.1 s before its old track's (9)
   * prediction does, in the same place: the prediction's crossing is the same vehicle's */
  setup(l, 1, NULL, 60);
  for (int f = 0; f <= 15; f++) {
    tl.count = 0;
    car_row(9, 20, f <= 5 ? RS_TRACK_CONFIRMED : RS_TRACK_COASTING, 8.0 - 0.8 * f, -8.0, 100.0 + 0.1 * (f <= 5 ? f : 5));
    if (f >= 6) car_row(8, 20, RS_TRACK_CONFIRMED, 7.2 - 0.8 * f, -8.0, 100.0 + 0.1 * f);
    rs_count_frame(&cnt, &tl, 100.0 + 0.1 * f);
  }
  ck_assert_uint_eq(cnt.crossings, 1);
  ck_assert_uint_eq(cnt.unseen_dup, 1);
  ck_assert_uint_eq(cnt.unseen + cnt.pending, 0);
}
END_TEST

/* A car comes into view 6 m past the line at 8 m/s, its box growing away
 * from the sensor for its first 0.5 s: its centre creeps 0.05 m a frame the
 * other way, so at its first confirmed frame (the third) its path run back
 * meets nothing. hidden_window_s: the check is repeated until 2 s after it
 * was first seen, with its mean velocity since then: counted once, at 1 s;
 * with the window 0, not. A track first listed confirmed 6 m past the line
 * (taken up again before the counter knew it) was not born there: not counted. */
static uint64_t growing(double window, uint32_t *when) {
  static const char *const l[] = {"gate 0 -5 0 5"};
  setup(l, 1, NULL, 60);
  cnt.hidden_window_s = window;
  run_start();
  *when = 0;
  double x = -6.0;
  for (uint32_t f = 0; f < 30; f++) {
    x += f < 5 ? 0.05 : -0.8;
    tl.count = 0;
    one(1, f < 2 ? RS_TRACK_TENTATIVE : RS_TRACK_CONFIRMED, RS_CLASS_CAR, x, 3.0);
    rs_count_frame(&cnt, &tl, 53.0 + 0.1 * f);
    if (cnt.crossings == 1 && *when == 0) *when = f;
  }
  return cnt.crossings;
}

START_TEST(t_hidden_window) {
  uint32_t when;
  ck_assert_uint_eq(growing(2.0, &when), 1);
  ck_assert_uint_eq(cnt.hidden, 1);
  ck_assert_uint_eq(cnt.total[0].forward[RS_CLASS_CAR], 1);
  ck_assert_uint_ge(when, 5);
  ck_assert_uint_le(when, 20);
  ck_assert_uint_eq(growing(0.0, &when), 0);
  /* taken up again past the line: confirmed when first listed */
  growing(2.0, &when);
  for (int f = 0; f < 15; f++) {
    tl.count = 0;
    one(2, RS_TRACK_CONFIRMED, RS_CLASS_CAR, -6.0 - 0.8 * f, -2.0);
    rs_count_frame(&cnt, &tl, 62.0 + 0.1 * f);
  }
  ck_assert_uint_eq(cnt.crossings, 1);
}
END_TEST

/* The run's start. The run starts at t = 50 (an empty frame); a car first seen
 * at 50.5, 3.2 m past the line, confirmed at 8 m/s: its path run back meets
 * the line at 50.1, after the run's start, but with that time stretched by
 * 1.5 (it may have been slower before: pulling away from the line) at 49.9,
 * before it: not counted. The same car first seen at 51.0: stretched, 50.4:
 * counted. */
static uint64_t seen_from(double t0) {
  static const char *const l[] = {"gate 0 -5 0 5"};
  setup(l, 1, NULL, 60);
  run_start();
  drive(1, t0, -3.2, -8.0, 8, 3);
  ck_assert_uint_eq(cnt.hidden, cnt.crossings);
  return cnt.crossings;
}

START_TEST(t_hidden_start) {
  ck_assert_uint_eq(seen_from(50.5), 0);
  ck_assert_uint_eq(seen_from(51.0), 1);
  ck_assert_uint_eq(cnt.total[0].forward[RS_CLASS_CAR], 1);
}
END_TEST

/* A standing van uncovered past the line: first seen at 52.0, 2 m past it,
 * its box's centre moving 0.5 m a frame away from the line for 4 frames as
 * more of it comes into view (a hidden crossing found at its first confirmed
 * frame), then still. Its track reports speed 0 when the crossing is due (2 s
 * later): taken back, no event. Reporting 4 m/s then: counted, one event.
 * Tallied at once (class delay 0), there is no later look: counted. With
 * drive_back, after 4 s it drives back over the line (+x at 4 m/s), seen. */
/* one line across x = 0 (forward: towards -x), a minute's intervals, the class delay given; the run
 * started at 50 s */
static void gate_run(double delay) {
  static const char *const l[] = {"gate 0 -5 0 5"};
  setup(l, 1, NULL, 60);
  cnt.class_delay_s = delay;
  run_start();
}

static uint64_t uncovered_van(double delay, float speed, uint32_t *events, bool drive_back) {
  gate_run(delay);
  *events = 0;
  for (int f = 0; f < (drive_back ? 70 : 40); f++) {
    tl.count = 0;
    const double x = f < 40 ? -2.0 - 0.5 * (f < 4 ? f : 4) : -4.0 + 0.4 * (f - 39);
    one(1, f < 2 ? RS_TRACK_TENTATIVE : RS_TRACK_CONFIRMED, RS_CLASS_VAN_TRUCK, x, 3.0);
    sized(6.0f);
    tl.track[0].speed = f < 4 ? 0.0f : f < 40 ? speed : 4.0f;
    rs_count_frame(&cnt, &tl, 52.0 + 0.1 * f);
    *events += cnt.nevents;
  }
  rs_count_flush(&cnt, drive_back ? 59.0 : 56.0);
  *events += cnt.nevents;
  return cnt.crossings;
}

START_TEST(t_hidden_still) {
  uint32_t events;
  ck_assert_uint_eq(uncovered_van(2.0, 0.0f, &events, false), 0);
  ck_assert_uint_eq(cnt.hidden, 0);
  ck_assert_uint_eq(cnt.hidden_still, 1);
  ck_assert_uint_eq(cnt.pending, 0);
  ck_assert_uint_eq(sum(cnt.total[0].forward), 0);
  ck_assert_uint_eq(events, 0);
  /* taken back, it never crossed: driving back over the line, seen, it is counted that way */
  ck_assert_uint_eq(uncovered_van(2.0, 0.0f, &events, true), 1);
  ck_assert_uint_eq(cnt.hidden_still, 1);
  ck_assert_uint_eq(cnt.total[0].backward[RS_CLASS_VAN_TRUCK], 1);
  ck_assert_uint_eq(sum(cnt.total[0].forward), 0);
  ck_assert_uint_eq(events, 1);
  ck_assert_uint_eq(uncovered_van(2.0, 4.0f, &events, false), 1);
  ck_assert_uint_eq(cnt.hidden, 1);
  ck_assert_uint_eq(cnt.hidden_still, 0);
  ck_assert_uint_eq(cnt.total[0].forward[RS_CLASS_VAN_TRUCK], 1);
  ck_assert_uint_eq(events, 1);
  ck_assert_uint_eq(uncovered_van(0.0, 0.0f, &events, false), 1);
  ck_assert_uint_eq(cnt.hidden_still, 0);
  ck_assert_uint_eq(events, 1);
}
END_TEST

/* A car out from behind another, 3 m before the line, coming towards it (-x) at 8 m/s: its box grows
 * away from the line as more of it comes into view, its centre moving 0.6 m a frame the other way for
 * 3 frames, while its track reports its velocity as vx (the speed estimator follows the box's near
 * side), then it drives over the line, seen. Returns the forward crossings. */
static uint32_t grows_away(double vx) {
  gate_run(2.0);
  for (int f = 0; f < 20; f++) {
    tl.count = 0;
    one(1, f < 2 ? RS_TRACK_TENTATIVE : RS_TRACK_CONFIRMED, RS_CLASS_CAR, f < 3 ? 3.0 + 0.6 * f : 4.2 - 0.8 * (f - 2), 3.0);
    sized(4.5f);
    tl.track[0].vel[0] = vx;
    rs_count_frame(&cnt, &tl, 52.0 + 0.1 * f);
  }
  rs_count_flush(&cnt, 54.0);
  ck_assert_uint_eq(sum(cnt.total[0].backward), 0);
  return sum(cnt.total[0].forward);
}

START_TEST(t_hidden_against) {
  /* its centre's path run back meets the line, but against the way the track reports it going: no hidden
   * crossing; counted once as it drives over */
  ck_assert_uint_eq(grows_away(-8.0), 1);
  ck_assert_uint_eq(cnt.hidden, 0);
  ck_assert_uint_eq(cnt.back_undone, 0);
  /* with no velocity reported, the path's crossing (backward, 1.5 s before) is held, and the drive over takes
   * it back (the band): the car is not counted */
  ck_assert_uint_eq(grows_away(0.0), 0);
  ck_assert_uint_eq(cnt.back_undone, 1);
}
END_TEST

/* A car first seen 3 m past the line (+x; forward is towards -x), its first boxes growing away from
 * the line (0.5 m a frame for 4 frames) while its track reports +5 m/s: its path run back crosses the
 * line backward 0.6 s before, a hidden crossing, pending for the class delay (2 s). Then it drives
 * towards the line at 2 m/s (reported -2 m/s, or +2 with `away`: it goes on away from the line) and,
 * towards it, over it, seen, 2.5 s after it was first seen. Returns the crossings tallied. */
static uint64_t grew_wrong_way(bool away) {
  gate_run(2.0);
  for (int f = 0; f < 40; f++) {
    tl.count = 0;
    const double x = f < 4 ? 3.0 + 0.5 * f : 4.5 + (away ? 0.2 : -0.2) * (f - 3);
    one(1, f < 2 ? RS_TRACK_TENTATIVE : RS_TRACK_CONFIRMED, RS_CLASS_CAR, x, 3.0);
    sized(4.5f);
    tl.track[0].vel[0] = f < 4 ? 5.0 : away ? 2.0 : -2.0;
    tl.track[0].speed = f < 4 ? 5.0f : 2.0f;
    rs_count_frame(&cnt, &tl, 52.0 + 0.1 * f);
  }
  rs_count_flush(&cnt, 57.0);
  return cnt.crossings;
}

START_TEST(t_hidden_reversed) {
  /* going the other way when it is tallied: the hidden crossing is taken back, and its drive over the
   * line, seen, counts (forward) */
  ck_assert_uint_eq(grew_wrong_way(false), 1);
  ck_assert_uint_eq(cnt.hidden_reversed, 1);
  ck_assert_uint_eq(cnt.hidden, 0);
  ck_assert_uint_eq(cnt.total[0].forward[RS_CLASS_CAR], 1);
  ck_assert_uint_eq(sum(cnt.total[0].backward), 0);
  /* going on away from the line: the hidden crossing stands (backward) */
  ck_assert_uint_eq(grew_wrong_way(true), 1);
  ck_assert_uint_eq(cnt.hidden_reversed, 0);
  ck_assert_uint_eq(cnt.hidden, 1);
  ck_assert_uint_eq(cnt.total[0].backward[RS_CLASS_CAR], 1);
  ck_assert_uint_eq(sum(cnt.total[0].forward), 0);
}
END_TEST

/* A car seen as a cyclist when it crosses (head-on at range), a car from
 * 0.7 s later: with the delay (2 s) it is tallied as a car, 2 s after it
 * crossed and not before; at once (0) as a cyclist. A van whose track leaves
 * the list 0.6 s after its crossing is tallied then, as a van; a crossing
 * 0.5 s before the end of the run is tallied by rs_count_flush. Crossings at
 * 9.5 s land in the interval open when they are tallied (10-20 s). */
static void class_run(double delay) {
  static const char *const l[] = {"gate 0 -5 0 5"};
  setup(l, 1, NULL, 10);
  cnt.class_delay_s = delay;
  for (int f = 0; f <= 105; f++) {
    const double t = 9.2 + 0.1 * f;
    tl.count = 0;
    one(20, RS_TRACK_CONFIRMED, f < 10 ? RS_CLASS_CYCLIST : RS_CLASS_CAR, 2.5 - f, 0.0); /* found at 9.5 */
    if (f <= 8) one(21, RS_TRACK_CONFIRMED, RS_CLASS_VAN_TRUCK, 2.5 - f, 2.0);
    one(22, RS_TRACK_CONFIRMED, RS_CLASS_BUS, -100.5 + f, -2.0); /* found at 19.3 */
    if (rs_count_frame(&cnt, &tl, t)) ck_assert_uint_eq(sum(cnt.closed.line[0].forward), delay > 0 ? 0u : 2u);
    if (delay > 0 && f == 3) ck_assert_uint_eq(cnt.pending, 2);
    if (delay > 0 && f == 9) ck_assert_uint_eq(cnt.total[0].forward[RS_CLASS_VAN_TRUCK], 1); /* 21 left at f 9 */
    if (delay > 0 && f == 22) ck_assert_uint_eq(cnt.crossings, 1);                        /* 20 at 11.4: not yet */
    if (delay > 0 && f == 24) ck_assert_uint_eq(cnt.total[0].forward[RS_CLASS_CAR], 1);   /* 11.6: tallied */
  }
  ck_assert(rs_count_flush(&cnt, 19.8));
  ck_assert_uint_eq(cnt.pending, 0);
  ck_assert_uint_eq(cnt.crossings, 3);
  ck_assert_uint_eq(cnt.total[0].backward[RS_CLASS_BUS], 1);
}

START_TEST(t_class_delay) {
  class_run(2.0);
  ck_assert_uint_eq(cnt.total[0].forward[RS_CLASS_CAR], 1);
  ck_assert_uint_eq(cnt.total[0].forward[RS_CLASS_CYCLIST], 0);
  ck_assert_uint_eq(sum(cnt.closed.line[0].forward), 2); /* both in the last interval */
  class_run(0.0);
  ck_assert_uint_eq(cnt.total[0].forward[RS_CLASS_CAR], 0);
  ck_assert_uint_eq(cnt.total[0].forward[RS_CLASS_CYCLIST], 1);
}
END_TEST

/* A track lost (unpublished, kept for re-acquisition) while it crosses the
 * line and taken up again past it crossed it: counted once, forward. One
 * first listed lost (a counter started mid-run) is not. */
START_TEST(t_lost_taken_up) {
  static const char *const l[] = {"gate 0 -5 0 5"};
  setup(l, 1, NULL, 60);
  for (int f = 0; f < 12; f++) {
    tl.count = 0;
    one(30, f < 3 || f >= 9 ? RS_TRACK_CONFIRMED : f < 5 ? RS_TRACK_COASTING : RS_TRACK_LOST, RS_CLASS_CAR,
        3.0 - f, 0.0); /* crosses x = 0 at the fourth frame, while coasting; seen again at x = -6 */
    one(31, f < 6 ? RS_TRACK_LOST : RS_TRACK_CONFIRMED, RS_CLASS_CAR, 2.0 - f, 3.0);
    rs_count_frame(&cnt, &tl, 10.0 + 0.1 * f);
    ck_assert_uint_eq(cnt.crossings, f < 9 ? 0u : 1u);
  }
  ck_assert_uint_eq(cnt.total[0].forward[RS_CLASS_CAR], 1);
}
END_TEST

/* Second tracks: two vehicle-sized tracks crossing the gate within same_s
 * (1.5 s) and 2.5 m along it, in one direction, are one vehicle (a split-off
 * part, or a new track taking over): counted once. Counted twice: the same
 * with same_s 0; two cars side by side in lanes 3.5 m apart; a car 1.8 s
 * behind another in its lane; two walkers crossing side by side; the two
 * tracks going opposite ways. Track b follows a by lag s at offset dy across
 * the gate; both at v m/s towards -x, full lengths la and lb. */
static uint64_t pair_crossings(double same_s, double lag, double dy, double v, double la, double lb, int dir_b) {
  static const char *const l[] = {"gate 0 -5 0 5"};
  setup(l, 1, NULL, 60);
  cnt.same_s = same_s;
  for (int f = 0; f < 80; f++) {
    const double t = 20.0 + 0.1 * f;
    tl.count = 0;
    one(1, RS_TRACK_CONFIRMED, RS_CLASS_CAR, 3.0 * v - v * (t - 20.0), -0.5);
    tl.track[tl.count - 1].full_length = (float)la;
    const double xb = dir_b > 0 ? 3.0 * v - v * (t - 20.0 - lag) : -3.0 * v + v * (t - 20.0 - lag);
    one(2, RS_TRACK_CONFIRMED, RS_CLASS_CAR, xb, -0.5 + dy);
    tl.track[tl.count - 1].full_length = (float)lb;
    rs_count_frame(&cnt, &tl, t);
  }
  return cnt.crossings;
}

START_TEST(t_second_tracks) {
  ck_assert_uint_eq(pair_crossings(1.5, 0.4, 0.6, 10.0, 4.5, 2.6, 1), 1);
  ck_assert_uint_eq(cnt.same_dup, 1);
  ck_assert_uint_eq(pair_crossings(1.5, 0.0, 1.0, 10.0, 2.6, 2.6, 1), 1);
  ck_assert_uint_eq(pair_crossings(0.0, 0.4, 0.6, 10.0, 4.5, 2.6, 1), 2);
  ck_assert_uint_eq(pair_crossings(1.5, 0.0, 3.5, 10.0, 4.5, 4.5, 1), 2); /* the next lane */
  ck_assert_uint_eq(pair_crossings(1.5, 1.8, 0.0, 10.0, 4.5, 4.5, 1), 2); /* following */
  ck_assert_uint_eq(pair_crossings(1.5, 0.0, 0.6, 1.4, 0.6, 0.6, 1), 2); /* walkers */
  ck_assert_uint_eq(pair_crossings(1.5, 0.0, 0.6, 10.0, 4.5, 4.5, -1), 2); /* the other way */
  ck_assert_uint_eq(cnt.same_dup, 0);
}
END_TEST

/* Second tracks are told by when they crossed, not when the crossing was found. A car (1), tentative
 * from its birth 2 m before "gate 0 -5 0 5" at 10 m/s towards -x, crosses it at t = 20.2 and is confirmed
 * at 20.8, when its crossing is found; the car behind it in its lane (2), confirmed, crosses at 21.9: 1.7 s
 * after the first (over same_s, 1.5), 1.1 s after the first was found: both counted (by the times the
 * crossings were found, once). The second crossing 1.3 s after the first: its second track, once; the
 * first confirmed from its birth: both. Returns the forward crossings. */
static uint32_t found_late(double confirm_at, double second_at) {
  static const char *const l[] = {"gate 0 -5 0 5"};
  setup(l, 1, NULL, 60);
  for (int f = 0; f <= 60; f++) {
    const double t = 20.0 + 0.1 * f;
    tl.count = 0;
    one(1, t < confirm_at - 1e-9 ? RS_TRACK_TENTATIVE : RS_TRACK_CONFIRMED, RS_CLASS_CAR, 2.0 - 10.0 * (t - 20.0), 0.5);
    sized(4.5f);
    one(2, RS_TRACK_CONFIRMED, RS_CLASS_CAR, 10.0 * (second_at - t), 0.5);
    sized(4.5f);
    rs_count_frame(&cnt, &tl, t);
  }
  return sum(cnt.total[0].forward);
}

START_TEST(t_second_track_time) {
  ck_assert_uint_eq(found_late(20.8, 21.9), 2);
  ck_assert_uint_eq(cnt.same_dup, 0);
  ck_assert_uint_eq(found_late(20.8, 21.5), 1); /* 1.3 s behind: the first's second track */
  ck_assert_uint_eq(cnt.same_dup, 1);
  ck_assert_uint_eq(found_late(20.0, 21.9), 2);
}
END_TEST

/* A held crossing gives way to a seen one (unseen_yield). A bus's track (9), 12 m long, moving -x at
 * 5 m/s along y = 0 of "gate 0 -5 0 5" (5 m along it), is seen until x = 3 (t = 100.5), then lost: its
 * prediction runs on over the line at t = 101.1 (the bus itself had slowed behind something). At
 * t = 102.0 two cars seen in the next lanes, at y = -1.4 and y = 2 (3.6 and 7 m along: each within 2.5 m
 * of the prediction's crossing, 3.4 m from each other), cross it at 8 m/s. Counted: the two cars, the
 * prediction's crossing taken back; without the rule, both cars are taken for the bus's second track and
 * only the prediction's crossing counts. And a car's own new track (8) seen crossing 0.3 s after its old
 * track's (7) prediction did, where it did: counted once either way. Returns the forward crossings. */
static uint32_t lost_bus(bool yield, bool own) {
  static const char *const l[] = {"gate 0 -5 0 5"};
  setup(l, 1, NULL, 60);
  cnt.unseen_yield = yield;
  for (int f = 0; f <= 40; f++) {
    const double t = 100.0 + 0.1 * f;
    tl.count = 0;
    if (!own) {
      car_row(9, 40, f <= 5 ? RS_TRACK_CONFIRMED : f <= 15 ? RS_TRACK_COASTING : RS_TRACK_LOST, 5.5 - 0.5 * f, -5.0,
              100.0 + 0.1 * (f <= 5 ? f : 5));
      tl.track[tl.count - 1].x[1] = 0.0;
      sized(12.0f);
      for (int k = 0; k < 2; k++) {
        car_row(20 + (uint32_t)k, 20, RS_TRACK_CONFIRMED, 16.0 - 0.8 * f, -8.0, t);
        tl.track[tl.count - 1].x[1] = k == 0 ? -1.4 : 2.0;
        sized(4.5f);
      }
    } else {
      car_row(7, 20, f <= 5 ? RS_TRACK_CONFIRMED : RS_TRACK_COASTING, 4.8 - 0.8 * f, -8.0, 100.0 + 0.1 * (f <= 5 ? f : 5));
      sized(4.5f);
      if (f >= 7) {
        car_row(8, 5, RS_TRACK_CONFIRMED, 4.8 - 0.8 * (f - 3), -8.0, t);
        sized(4.5f);
      }
    }
    rs_count_frame(&cnt, &tl, t);
  }
  tl.count = 0;
  rs_count_frame(&cnt, &tl, 104.2);
  ck_assert_uint_eq(cnt.pending, 0);
  return sum(cnt.total[0].forward);
}

START_TEST(t_unseen_yield) {
  ck_assert_uint_eq(lost_bus(true, false), 2);
  ck_assert_uint_eq(cnt.unseen_yielded, 1);
  ck_assert_uint_eq(cnt.same_dup, 0);
  ck_assert_uint_eq(cnt.unseen, 0);
  ck_assert_uint_eq(lost_bus(false, false), 1);
  ck_assert_uint_eq(cnt.same_dup, 2);
  ck_assert_uint_eq(cnt.unseen, 1);
  ck_assert_uint_eq(lost_bus(true, true), 1);
  ck_assert_uint_eq(cnt.unseen_yielded, 1);
  ck_assert_uint_eq(lost_bus(false, true), 1);
  ck_assert_uint_eq(cnt.same_dup, 1);
  rs_count_line_t line;
  char err[RS_ERRMSG_SIZE];
  ck_assert_int_eq(rs_count_parse_line("gate 0 -5 0 5", &line, err, sizeof err), RS_OK);
  ck_assert_int_eq(rs_count_init(&cnt, &line, 1, NULL, 60, err, sizeof err), RS_OK);
  ck_assert(cnt.unseen_yield); /* the default */
}
END_TEST

/* The band (band_m). A car stops with its centre 0.1 m before the line "stop 0 -5 0 5" (x = 0), driving
 * -x (forward), its centre wandering +-0.25 m for 10 s (stepping over the line every other second); then
 * either drives on (drive_on) or the run ends. band: band_m; crossings tallied when found. Returns the
 * forward crossings tallied. */
static uint32_t stop_on_line(double band, int drive_on) {
  static const char *const l[] = {"stop 0 -5 0 5"};
  setup(l, 1, NULL, 60); /* (tallied when found: nothing to take back, the band alone) */
  cnt.band_m = band;
  double t = 50.0;
  for (int f = 0; f < 30; f++, t += 0.1) { /* from 3.1 m to 0.1 m before it */
    tl.count = 0;
    one(1, RS_TRACK_CONFIRMED, RS_CLASS_CAR, 3.1 - 0.1 * f, 1.0); sized(4.5f);
    rs_count_frame(&cnt, &tl, t);
  }
  for (int f = 0; f < 100; f++, t += 0.1) { /* standing: 0.1 m before it, +-0.25 m */
    tl.count = 0;
    one(1, RS_TRACK_CONFIRMED, RS_CLASS_CAR, 0.1 + 0.25 * sin(f * M_PI / 10.0), 1.0); sized(4.5f);
    rs_count_frame(&cnt, &tl, t);
  }
  for (int f = 0; f < 30 && drive_on; f++, t += 0.1) {
    tl.count = 0;
    one(1, RS_TRACK_CONFIRMED, RS_CLASS_CAR, 0.1 - 0.2 * f, 1.0); sized(4.5f);
    rs_count_frame(&cnt, &tl, t);
  }
  rs_count_flush(&cnt, t);
  ck_assert_uint_eq(sum(cnt.total[0].backward), 0);
  return sum(cnt.total[0].forward);
}

/* A track runs 1.4 m past the line as its car stops 0.6 m short of it (the filter's overshoot, coasting),
 * then is seen where the car stands, 1 s later; 5 s on, the car drives over. back_s: how long after its
 * crossing it is seen back. Returns the forward crossings; *undone: back_undone. */
static uint32_t overshoot(double band, double back_s, uint64_t *undone) {
  static const char *const l[] = {"stop 0 -5 0 5"};
  setup(l, 1, NULL, 60);
  cnt.band_m = band;
  cnt.class_delay_s = 2.0;
  double t = 80.0;
  int f = 0;
  for (; f <= 36; f++, t += 0.1) { /* 2.2 m before, at 0.1 m a frame, to 1.4 m past (frame 22 crosses) */
    tl.count = 0;
    one(2, RS_TRACK_CONFIRMED, RS_CLASS_CAR, 2.2 - 0.1 * f, -2.0); sized(4.5f);
    rs_count_frame(&cnt, &tl, t);
  }
  for (int g = 0; g < 80; g++, t += 0.1) { /* then where the car stands, 0.6 m before it, from back_s */
    tl.count = 0;
    one(2, RS_TRACK_CONFIRMED, RS_CLASS_CAR, 0.1 * g < back_s - 1.4 ? -1.4 : 0.6, -2.0); sized(4.5f);
    rs_count_frame(&cnt, &tl, t);
  }
  for (int g = 0; g < 20; g++, t += 0.1) { /* it drives over */
    tl.count = 0;
    one(2, RS_TRACK_CONFIRMED, RS_CLASS_CAR, 0.6 - 0.2 * g, -2.0); sized(4.5f);
    rs_count_frame(&cnt, &tl, t);
  }
  rs_count_flush(&cnt, t);
  *undone = cnt.back_undone;
  ck_assert_uint_eq(sum(cnt.total[0].backward), 0);
  return sum(cnt.total[0].forward);
}

START_TEST(t_band) {
  /* standing on the line: counted once when it drives on, either way; never when it does not drive on,
   * but at the line (band 0) its centre's first step over counts */
  ck_assert_uint_eq(stop_on_line(RS_COUNT_BAND_M, 1), 1);
  ck_assert_uint_eq(stop_on_line(0.0, 1), 1);
  ck_assert_uint_eq(stop_on_line(RS_COUNT_BAND_M, 0), 0);
  ck_assert_uint_eq(stop_on_line(0.0, 0), 1);
  /* the overshoot: taken back when seen back before its crossing is tallied, then counted once as it
   * drives over; at the line (band 0) counted once, at the overshoot, and not taken back */
  uint64_t undone = 0;
  ck_assert_uint_eq(overshoot(RS_COUNT_BAND_M, 1.0, &undone), 1);
  ck_assert_uint_eq(undone, 1);
  ck_assert_uint_eq(overshoot(0.0, 1.0, &undone), 1);
  ck_assert_uint_eq(undone, 0);
  /* seen back only after the class delay: the crossing was tallied, it stands (and the drive over is
   * the same line: not counted again) */
  ck_assert_uint_eq(overshoot(RS_COUNT_BAND_M, 3.0, &undone), 1);
  ck_assert_uint_eq(undone, 0);
  /* a track crossing past the segment's end within the band's reach is not counted: a step from 0.2 m
   * before to 0.5 m past at y = 5.05, just beyond the end (0, 5) */
  static const char *const l[] = {"stop 0 -5 0 5"};
  setup(l, 1, NULL, 60);
  const double xs[] = {2.0, 1.0, 0.2, -0.5, -1.5};
  for (int f = 0; f < 5; f++) {
    tl.count = 0;
    one(3, RS_TRACK_CONFIRMED, RS_CLASS_CAR, xs[f], 5.05);
    rs_count_frame(&cnt, &tl, 90.0 + 0.1 * f);
  }
  ck_assert_uint_eq(cnt.crossings, 0);
}
END_TEST

/* A walker's track crossing back is counted that way too, once: a walker goes out over "walk 0 -2 0 2"
 * (x = 0) at 1 m/s, turns back back_after_s past the line (3 s: its forward crossing tallied after the
 * class delay; 0.6 s: before), crosses back, turns again again_after_s past the line and goes out for
 * 6 s, crossing forward once more. With 3 s and 4 s, and with 0.6 s and 4 s: one forward, one backward
 * (two walkers meeting on the line leave with each other's tracks, each over and back: the class delay
 * does not decide whether both count). The same path by a car-long track: one forward; back before its
 * crossing is tallied, that crossing is taken back (t_band). A walker's crossing back, seen back over
 * the line before it is tallied, is taken back: the first stands. */
static void walk_back(float full_length, rs_class_t cls, double back_after_s, double again_after_s) {
  static const char *const l[] = {"walk 0 -2 0 2"};
  setup(l, 1, NULL, 60);
  cnt.class_delay_s = 2.0;
  double t = 200.0, x = 2.0;
  const int out = (int)(back_after_s / 0.1 + 0.5), in = (int)(again_after_s / 0.1 + 0.5);
  for (int f = 0; f < 20 + out + out + in + 60; f++, t += 0.1) {
    /* -x to back_after_s past the line, +x to again_after_s past it, -x for 6 s */
    x += f < 20 + out ? -0.1 : f < 20 + out + out + in ? 0.1 : -0.1;
    tl.count = 0;
    one(9, RS_TRACK_CONFIRMED, cls, x, 0.5);
    sized(full_length);
    rs_count_frame(&cnt, &tl, t);
  }
  rs_count_flush(&cnt, t);
}

START_TEST(t_walker_back) {
  walk_back(0.6f, RS_CLASS_PEDESTRIAN, 3.0, 4.0);
  ck_assert_uint_eq(cnt.total[0].forward[RS_CLASS_PEDESTRIAN], 1);
  ck_assert_uint_eq(cnt.total[0].backward[RS_CLASS_PEDESTRIAN], 1);
  ck_assert_uint_eq(cnt.crossings, 2);
  ck_assert_uint_eq(cnt.walked_back, 1);
  walk_back(4.5f, RS_CLASS_CAR, 3.0, 4.0);
  ck_assert_uint_eq(sum(cnt.total[0].forward), 1);
  ck_assert_uint_eq(sum(cnt.total[0].backward), 0);
  ck_assert_uint_eq(cnt.crossings, 1);
  ck_assert_uint_eq(cnt.walked_back, 0);
  /* back 0.6 s past the line, before the tally: that crossing tallied then, the crossing back counted too;
   * out again 4 s on: not counted again */
  walk_back(0.6f, RS_CLASS_PEDESTRIAN, 0.6, 4.0);
  ck_assert_uint_eq(cnt.back_undone, 0);
  ck_assert_uint_eq(cnt.walked_early, 1);
  ck_assert_uint_eq(cnt.walked_back, 1);
  ck_assert_uint_eq(cnt.total[0].forward[RS_CLASS_PEDESTRIAN], 1);
  ck_assert_uint_eq(cnt.total[0].backward[RS_CLASS_PEDESTRIAN], 1);
  ck_assert_uint_eq(cnt.crossings, 2);
  /* a car's track the same way: its crossing taken back, then counted once as it goes out again */
  walk_back(4.5f, RS_CLASS_CAR, 0.6, 4.0);
  ck_assert_uint_eq(cnt.back_undone, 1);
  ck_assert_uint_eq(cnt.walked_early, 0);
  ck_assert_uint_eq(sum(cnt.total[0].forward), 1);
  ck_assert_uint_eq(sum(cnt.total[0].backward), 0);
  /* out (tallied), back 0.6 s past the line and out again: the crossing back taken back, the first
   * stands: one forward */
  walk_back(0.6f, RS_CLASS_PEDESTRIAN, 3.0, 0.6);
  ck_assert_uint_eq(cnt.back_undone, 1);
  ck_assert_uint_eq(sum(cnt.total[0].forward), 1);
  ck_assert_uint_eq(sum(cnt.total[0].backward), 0);
  ck_assert_uint_eq(cnt.walked_back, 0);
}
END_TEST

/* Walkers in a file over "walk 0 -2 0 2" (x = 0), going -x at pace m/s 1 m apart (y = 0.5): the first
 * (track 11) seen throughout; the second (track 12, first seen with it) unseen from 1 m before the line
 * and followed on its prediction over it, 0.8 s after the first crossed (at 1.25 m/s); seen again 1.5 s
 * after it was last seen, past the line, or, with renewed, never again: a track first seen 0.5 m ahead
 * of its prediction once it is unseen (13: the same walker's new one) crosses first. Returns the crossings; *dup:
 * unseen_dup. */
static void walker_row(uint32_t id, rs_track_state_t st, double x, double pace, double t_birth, double t_update) {
  one(id, st, RS_CLASS_PEDESTRIAN, x, 0.5);
  sized(0.6f);
  rs_track_t *k = &tl.track[tl.count - 1];
  k->x[2] = -pace;
  k->hits = 20;
  k->t_birth = t_birth;
  k->t_update = t_update;
}

static uint32_t walker_file(double pace, bool renewed, uint64_t *dup) {
  static const char *const l[] = {"walk 0 -2 0 2"};
  setup(l, 1, NULL, 60);
  const double x0 = 3.0, t0 = 300.0, step = pace * 0.1;
  const int unseen_from = (int)((x0 + 1.0 - 1.0) / step + 0.5), again = unseen_from + 15;
  for (int f = 0; f <= again + 20; f++) {
    const double t = t0 + 0.1 * f, x2 = x0 + 1.0 - step * f;
    tl.count = 0;
    walker_row(11, RS_TRACK_CONFIRMED, x0 - step * f, pace, t0, t);
    const bool seen = f < unseen_from || (!renewed && f >= again);
    walker_row(12, seen ? RS_TRACK_CONFIRMED : RS_TRACK_COASTING, x2, pace, t0, seen ? t : t0 + 0.1 * (unseen_from - 1));
    if (renewed && f >= unseen_from)
      walker_row(13, f >= unseen_from + 2 ? RS_TRACK_CONFIRMED : RS_TRACK_TENTATIVE, x2 - 0.5, pace, t0 + 0.1 * unseen_from, t);
    rs_count_frame(&cnt, &tl, t);
  }
  rs_count_flush(&cnt, t0 + 0.1 * (again + 21));
  *dup = cnt.unseen_dup;
  ck_assert_uint_eq(sum(cnt.total[0].backward), 0);
  return sum(cnt.total[0].forward);
}

/* A walker (track 21) going -x at 1 m/s over "walk 0 -2 0 2" (x = 0), unseen from 1 m before it, its
 * prediction crossing it; seen again at again_x 1.5 s later (within the band when 0.2 m either side),
 * standing 2 s, then walking at 1 m/s the way `on` (+1: -x, on over the line; -1: +x, back). A car's track the same
 * (car). Returns the crossings; forward and backward in *fwd, *bwd. */
static uint32_t seen_in_band(bool car, double again_x, int on, uint32_t *fwd, uint32_t *bwd) {
  static const char *const l[] = {"walk 0 -2 0 2"};
  setup(l, 1, NULL, 60);
  cnt.class_delay_s = 2.0;
  const double t0 = 400.0;
  double x = 3.0;
  for (int f = 0; f < 110; f++) {
    const double t = t0 + 0.1 * f;
    const bool unseen = f >= 20 && f < 35;
    if (f < 35) x = 3.0 - 0.1 * f; /* its prediction, on at 1 m/s to 0.4 m past the line */
    else if (f == 35) x = again_x;
    else if (f >= 55) x += on > 0 ? -0.1 : 0.1;
    tl.count = 0;
    one(21, unseen ? RS_TRACK_COASTING : RS_TRACK_CONFIRMED, car ? RS_CLASS_CAR : RS_CLASS_PEDESTRIAN, x, 0.5);
    sized(car ? 4.5f : 0.6f);
    rs_track_t *k = &tl.track[0];
    k->x[2] = f < 35 || f >= 55 ? (on > 0 || f < 35 ? -1.0 : 1.0) : 0.0;
    k->hits = 20;
    k->t_update = unseen ? t0 + 1.9 : t;
    rs_count_frame(&cnt, &tl, t);
  }
  rs_count_flush(&cnt, t0 + 11.0);
  *fwd = sum(cnt.total[0].forward);
  *bwd = sum(cnt.total[0].backward);
  return cnt.crossings;
}

START_TEST(t_unseen_band) {
  uint32_t fwd, bwd;
  /* a walker whose prediction crossed, seen again 0.2 m past the line (within the band), then walking
   * back over it: one forward (on its prediction), one backward (walked_back) */
  ck_assert_uint_eq(seen_in_band(false, -0.2, -1, &fwd, &bwd), 2);
  ck_assert_uint_eq(fwd, 1);
  ck_assert_uint_eq(bwd, 1);
  ck_assert_uint_eq(cnt.walked_back, 1);
  /* the same, walking on: one forward */
  ck_assert_uint_eq(seen_in_band(false, -0.2, 1, &fwd, &bwd), 1);
  ck_assert_uint_eq(fwd, 1);
  /* a car whose prediction crossed, seen again 0.2 m before the line (it stopped short): taken back; then
   * driving over it, seen: one forward */
  ck_assert_uint_eq(seen_in_band(true, 0.2, 1, &fwd, &bwd), 1);
  ck_assert_uint_eq(cnt.unseen_undone, 1);
  ck_assert_uint_eq(fwd, 1);
  ck_assert_uint_eq(bwd, 0);
}
END_TEST

START_TEST(t_unseen_walkers) {
  uint64_t dup = 0;
  /* the second walker's crossing on its prediction, 0.8 s after the first's and beside it: both counted */
  ck_assert_uint_eq(walker_file(1.25, false, &dup), 2);
  ck_assert_uint_eq(dup, 0);
  ck_assert_uint_eq(cnt.unseen, 1);
  /* its own new track crossed first: the same walker, counted once */
  ck_assert_uint_eq(walker_file(1.25, true, &dup), 2);
  ck_assert_uint_eq(dup, 1);
  ck_assert_uint_eq(cnt.unseen, 0);
  /* as fast as a cyclist (4 m/s, 0.25 s apart), the file is taken for one road user's tracks, as vehicles' are */
  ck_assert_uint_eq(walker_file(4.0, false, &dup), 1);
  ck_assert_uint_eq(dup, 1);
}
END_TEST

/* ---- crossing events (count.h) ---- */
static rs_count_event_t evs[512];
static uint32_t nevs;
static void take_events(void) {
  for (uint32_t k = 0; k < cnt.nevents && nevs < 512; k++) evs[nevs++] = cnt.events[k];
}
static void frame(double t) {
  rs_count_frame(&cnt, &tl, t);
  take_events();
}

/* on a fresh counter of lines l (tallied when found), track id from x0 towards -x at 8 m/s for
 * frames at 10 Hz from t0: the events */
static uint32_t straight(const char *const *l, uint32_t id, double x0, int frames, double t0) {
  setup(l, 1, NULL, 60);
  nevs = 0;
  for (int f = 0; f < frames; f++) {
    tl.count = 0;
    one(id, RS_TRACK_CONFIRMED, RS_CLASS_CAR, x0 - 0.8 * f, 1.0);
    frame(t0 + 0.1 * f);
  }
  return nevs;
}

/* A car speeding up at 1.5 m/s^2 from 2 m/s towards -x crosses "gate 0 -5 0 5" 1 m along -y of
 * its middle (y = 1: 6 m from A), its track reporting a speed 1 m/s behind (a filter's lag): the
 * event comes when the crossing is tallied (the class delay, 2 s), with the time it crossed, the
 * place along the line, its class, and the speed over the 2 s around the crossing: the true speed
 * there within 0.1 m/s (the window is centred on the crossing within a frame), not the track's. */
START_TEST(t_crossing_events) {
  static const char *const l[] = {"gate 0 -5 0 5"}; /* forward: towards -x */
  setup(l, 1, NULL, 60);
  cnt.class_delay_s = 2.0;
  nevs = 0;
  const double x0 = 12.0, v0 = 2.0, a = 1.5; /* x = x0 - v0 t - a t^2 / 2: at 0 when t = 2.4 s */
  const double tc = (-v0 + sqrt(v0 * v0 + 2.0 * a * x0)) / a, vc = v0 + a * tc;
  for (int f = 0; f < 60; f++) {
    const double t = 0.1 * f;
    tl.count = 0;
    one(4, RS_TRACK_CONFIRMED, RS_CLASS_CAR, x0 - v0 * t - 0.5 * a * t * t, 1.0);
    sized(4.5f);
    tl.track[0].speed = (float)(v0 + a * t - 1.0);
    frame(200.0 + t);
    if (200.0 + t < 200.0 + tc + 1.9) ck_assert_uint_eq(nevs, 0); /* not before it is tallied */
  }
  ck_assert_uint_eq(cnt.crossings, 1);
  ck_assert_uint_eq(nevs, 1);
  ck_assert_uint_eq(evs[0].track, 4);
  ck_assert_int_eq(evs[0].line, 0);
  ck_assert_int_eq(evs[0].dir, 1);
  ck_assert_int_eq(evs[0].cls, RS_CLASS_CAR);
  ck_assert_int_eq(evs[0].how, RS_CROSS_SEEN);
  ck_assert_double_eq_tol(evs[0].t, 200.0 + tc, 0.01);
  ck_assert_double_eq_tol(evs[0].at, 6.0, 0.01);
  ck_assert_double_eq_tol(evs[0].speed, vc, 0.1);
  ck_assert_str_eq(rs_count_how_name(RS_CROSS_SEEN), "seen");

  /* tallied sooner (the class delay 0): the window ends at the crossing's frame, the speed over
   * the second before it; with under 0.3 s of it (a track first seen at the line), unknown */
  ck_assert_uint_eq(straight(l, 5, 10.0, 30, 300.0), 1);
  ck_assert_double_eq_tol(evs[0].speed, 8.0, 0.01);
  ck_assert_uint_eq(straight(l, 6, 0.9, 5, 400.0), 1);
  ck_assert_float_eq(evs[0].speed, -1.0f);

  /* a hidden crossing (first seen 6 m past the line, 8 m/s): the time its path was run back to, and
   * the speed its track reports when it is tallied */
  setup(l, 1, NULL, 60);
  nevs = 0;
  tl.count = 0;
  frame(50.0);
  for (int f = 0; f < 6; f++) {
    tl.count = 0;
    one(7, f < 3 ? RS_TRACK_TENTATIVE : RS_TRACK_CONFIRMED, RS_CLASS_CAR, -6.0 - 0.8 * f, 3.0);
    tl.track[0].speed = 7.5f;
    frame(52.0 + 0.1 * f);
  }
  ck_assert_uint_eq(nevs, 1);
  ck_assert_int_eq(evs[0].how, RS_CROSS_HIDDEN);
  ck_assert_double_eq_tol(evs[0].t, 51.25, 0.01);
  ck_assert_float_eq(evs[0].speed, 7.5f);

  /* on a prediction (seen until x = 2.4, predicted over the line at t = 101.0, never seen again):
   * tallied when it leaves the list, the positions on its prediction giving the speed */
  setup(l, 1, NULL, 60);
  hidden_car(1, 20, 8.0, -8.0, 7, 24, -1, 0);
  ck_assert_uint_eq(cnt.nevents, 1);
  ck_assert_int_eq(cnt.events[0].how, RS_CROSS_UNSEEN);
  ck_assert_double_eq_tol(cnt.events[0].t, 101.0, 0.01);
  ck_assert_double_eq_tol(cnt.events[0].speed, 8.0, 0.01);

  /* taken back (the band: a track over the line, seen back before its crossing is tallied): no
   * event for it; the drive over later is one */
  setup(l, 1, NULL, 60);
  cnt.class_delay_s = 2.0;
  nevs = 0;
  double t = 80.0;
  for (int f = 0; f <= 36; f++, t += 0.1) {
    tl.count = 0;
    one(8, RS_TRACK_CONFIRMED, RS_CLASS_CAR, 2.2 - 0.1 * f, -2.0);
    sized(4.5f);
    frame(t);
  }
  for (int g = 0; g < 80; g++, t += 0.1) {
    tl.count = 0;
    one(8, RS_TRACK_CONFIRMED, RS_CLASS_CAR, 0.6, -2.0);
    sized(4.5f);
    frame(t);
  }
  const double t_over = t;
  for (int g = 0; g < 40; g++, t += 0.1) {
    tl.count = 0;
    one(8, RS_TRACK_CONFIRMED, RS_CLASS_CAR, 0.6 - 0.2 * g, -2.0);
    sized(4.5f);
    frame(t);
  }
  ck_assert_uint_eq(cnt.back_undone, 1);
  ck_assert_uint_eq(cnt.crossings, 1);
  ck_assert_uint_eq(nevs, 1);
  ck_assert_double_gt(evs[0].t, t_over);
  ck_assert_uint_eq(cnt.nopen, 0);

  /* 300 tracks crossing in one frame: all counted; the waiting pool holds RS_COUNT_OPEN_MAX, the rest's
   * events are lost and counted */
  static const char *const wide[] = {"wide 0 -500 0 500"};
  setup(wide, 1, NULL, 60);
  cnt.class_delay_s = 2.0;
  nevs = 0;
  for (int f = 0; f < 30; f++) {
    tl.count = 0;
    for (int k = 0; k < 300; k++) one((uint32_t)k + 1, RS_TRACK_CONFIRMED, RS_CLASS_CAR, f == 0 ? 1.0 : -1.0 - 0.1 * f, k);
    frame(500.0 + 0.1 * f);
  }
  ck_assert_uint_eq(cnt.crossings, 300);
  ck_assert_uint_eq(nevs, RS_COUNT_OPEN_MAX);
  ck_assert_uint_eq(cnt.events_lost, 300 - RS_COUNT_OPEN_MAX);
  ck_assert_uint_eq(cnt.nopen, 0);
}
END_TEST

START_TEST(t_bad_lines) {
  rs_count_line_t line;
  char err[RS_ERRMSG_SIZE];
  ck_assert_int_eq(rs_count_parse_line("x 1 2 3", &line, err, sizeof err), RS_E_INVAL);
  ck_assert_ptr_nonnull(strstr(err, "not NAME X1 Y1 X2 Y2"));
  ck_assert_int_eq(rs_count_parse_line("x 1 2 1 2", &line, err, sizeof err), RS_E_INVAL);
  ck_assert_ptr_nonnull(strstr(err, "less than 0.1 m apart"));
  ck_assert_int_eq(rs_count_parse_line("x 1 2 3 4 5", &line, err, sizeof err), RS_E_INVAL);
  ck_assert_int_eq(rs_count_parse_line("x nan 2 3 4", &line, err, sizeof err), RS_E_INVAL);
  ck_assert_int_eq(rs_count_parse_line("a-name-far-too-long-for-a-counting-line 1 2 3 4", &line, err, sizeof err),
                   RS_E_INVAL);
  ck_assert_int_eq(rs_count_parse_line("ok 1 2 3 4", &line, err, sizeof err), RS_OK);
  rs_count_line_t two[2] = {line, line};
  ck_assert_int_eq(rs_count_init(&cnt, two, 2, NULL, 60, err, sizeof err), RS_E_INVAL);
  ck_assert_ptr_nonnull(strstr(err, "two lines of that name"));
  ck_assert_int_eq(rs_count_init(&cnt, two, 1, NULL, 0.5, err, sizeof err), RS_E_INVAL);
  /* the option callbacks: a bad line or zone adds nothing; the 17th line, the 9th zone are refused by name */
  static rs_count_lines_t ls;
  static rs_count_zones_t zs;
  memset(&ls, 0, sizeof ls);
  memset(&zs, 0, sizeof zs);
  ck_assert_int_eq(rs_count_opt_line(&ls, "--count-line", "x 1 2 3", err, sizeof err), RS_E_INVAL);
  ck_assert_int_eq(ls.n, 0);
  for (int i = 0; i < RS_COUNT_LINES; i++) {
    char t[64];
    snprintf(t, sizeof t, "l%d 0 %d 5 %d", i, i, i);
    ck_assert_int_eq(rs_count_opt_line(&ls, "--count-line", t, err, sizeof err), RS_OK);
  }
  ck_assert_int_eq(ls.n, RS_COUNT_LINES);
  ck_assert_str_eq(ls.line[3].name, "l3");
  ck_assert_int_eq(rs_count_opt_line(&ls, "--count-line", "z 0 0 5 5", err, sizeof err), RS_E_INVAL);
  ck_assert_ptr_nonnull(strstr(err, "--count-line: at most 16 lines"));
  ck_assert_int_eq(rs_count_opt_zone(&zs, "--count-zone", "z 0 0 1", err, sizeof err), RS_E_INVAL);
  ck_assert_int_eq(zs.n, 0);
  for (int i = 0; i < RS_COUNT_ZONES; i++) {
    char t[64];
    snprintf(t, sizeof t, "z%d 0 0 4 0 4 4", i);
    ck_assert_int_eq(rs_count_opt_zone(&zs, "--count-zone", t, err, sizeof err), RS_OK);
  }
  ck_assert_int_eq(rs_count_opt_zone(&zs, "--count-zone", "y 0 0 4 0 4 4", err, sizeof err), RS_E_INVAL);
  ck_assert_ptr_nonnull(strstr(err, "--count-zone: at most"));
  ck_assert_int_eq(zs.n, RS_COUNT_ZONES);
}
END_TEST

int main(void) {
  Suite *s = suite_create("count");
  TCase *tc = tcase_create("lines");
  tcase_add_test(tc, t_directions_and_once);
  tcase_add_test(tc, t_tentative_and_coasting);
  tcase_add_test(tc, t_intervals_and_forgetting);
  tcase_add_test(tc, t_many_tracks);
  tcase_add_test(tc, t_site_frame);
  tcase_add_test(tc, t_bad_lines);
  tcase_add_test(tc, t_zones);
  tcase_add_test(tc, t_hidden_crossings);
  tcase_add_test(tc, t_hidden_window);
  tcase_add_test(tc, t_hidden_start);
  tcase_add_test(tc, t_hidden_still);
  tcase_add_test(tc, t_hidden_reversed);
  tcase_add_test(tc, t_hidden_against);
  tcase_add_test(tc, t_hidden_beside);
  tcase_add_test(tc, t_hidden_place);
  tcase_add_test(tc, t_class_delay);
  tcase_add_test(tc, t_lost_taken_up);
  tcase_add_test(tc, t_second_tracks);
  tcase_add_test(tc, t_unseen_yield);
  tcase_add_test(tc, t_second_track_time);
  tcase_add_test(tc, t_unseen_crossings);
  tcase_add_test(tc, t_band);
  tcase_add_test(tc, t_walker_back);
  tcase_add_test(tc, t_unseen_walkers);
  tcase_add_test(tc, t_unseen_band);
  tcase_add_test(tc, t_crossing_events);
  suite_add_tcase(s, tc);
  return tu_run(s);
}

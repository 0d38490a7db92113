/* check_background - 1-D DBSCAN and silhouette on known values; learning on
 * hand-built frames for each hard case (a wall, leaves in front of a wall,
 * a vehicle queued half of every cycle, passing traffic, a truck against
 * the sky, a grazing surface); the model file and its corruptions; the
 * subtraction with its beyond count. */
#include "roadscan/perception/background.h"
#include "testutil.h"

#include <dirent.h>
#include <math.h>
#include <signal.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

/* the subtraction's run-time rules: the defaults (main), changed by a test where it says so */
static rs_bg_rules_t rules;

START_TEST(t_dbscan1d) {
  /* two dense groups and a stray value */
  const int32_t v[] = {100, 101, 102, 103, 150, 300, 301, 302};
  const uint32_t c[] = {5, 5, 5, 5, 1, 4, 4, 4};
  int16_t lab[8];
  int k = rs_bg_dbscan1d(v, c, 8, 2, 10, lab);
  ck_assert_int_eq(k, 2);
  for (int i = 0; i < 4; i++) ck_assert_int_eq(lab[i], 0);
  ck_assert_int_eq(lab[4], -1);
  for (int i = 5; i < 8; i++) ck_assert_int_eq(lab[i], 1);
  /* a border value: 104 has only 5 within 1 but is within 1 of the core 103 */
  const int32_t w[] = {100, 101, 102, 103, 104};
  const uint32_t d[] = {10, 10, 10, 10, 1};
  k = rs_bg_dbscan1d(w, d, 5, 1, 15, lab);
  ck_assert_int_eq(k, 1);
  ck_assert_int_eq(lab[4], 0);
  /* minPts too high: nothing */
  ck_assert_int_eq(rs_bg_dbscan1d(v, c, 8, 2, 100, lab), 0);
  ck_assert_int_eq(lab[0], -1);
  /* silhouette of two tight, far apart groups is close to 1; of two touching ones lower */
  k = rs_bg_dbscan1d(v, c, 8, 2, 10, lab);
  double s = rs_bg_silhouette1d(v, c, 8, lab, k);
  ck_assert_double_gt(s, 0.98);
  const int32_t x[] = {100, 110, 120, 130};
  const uint32_t e[] = {10, 10, 10, 10};
  const int16_t two[] = {0, 0, 1, 1};
  /* hand computed: points 100 and 130: a = 10, b = 25 -> 0.6; 110 and 120: a = 10, b = 15 -> 1/3,
   * with ties at distance 0 inside a value: a over 19 others = 10*10/19 */
  double a_out = 100.0 / 19.0, a_in = 100.0 / 19.0;
  double s_out = (25.0 - a_out) / 25.0, s_in = (15.0 - a_in) / 15.0;
  ck_assert_double_eq_tol(rs_bg_silhouette1d(x, e, 4, two, 2), (s_out + s_in) / 2.0, 1e-9);
  ck_assert(isnan(rs_bg_silhouette1d(x, e, 4, two, 1)));
}
END_TEST

static rs_slot_t slot;

/* frames of a 4-row map: row 0 wall at 20 m; row 1 leaves at 8-9 m with
 * probability 0.5 independently per frame, else the wall at 20 m; row 2
 * ground at 12 m with a car at 9 m for 30 s out of every 60 s; row 3 sky
 * with a truck at 15 m for 30 s out of every 60 s; row 4 ground at 14 m
 * with cars passing at 10 m for 3 frames every 2 s; row 5 a grazing wall
 * whose range depends on the firing's position in the cell (40-42 m); row 6
 * a facade at 186-190 m seen at a grazing angle through an azimuth field of
 * 0.01 degree steps: its ranges come in clumps 0.17 m apart, half of the
 * firings lost at that range; row 7 the same at 20-21 m with a car standing
 * 0.8 m in front of it for 30 s out of every 60 s; row 8 a kerb at 25 m
 * across a lane where a queue stands 25 s out of every 60 s (its vehicles at
 * 12-16 m, another range every cycle), an edge behind it returning 27 m in
 * 3 % of the frames; row 9 a car at the stop line at 18 m for 30 s out of
 * every 60 s, and when it is not there a queue in the near lane (11 m) for
 * half of the time, the road at 25 m otherwise; row 10 the kerb of row 8
 * at the edge of a wall at 30 m: when the queue does not hide it, the
 * firings miss it and find the wall in 30 % of the frames, at random */
/* row 11: in even columns a car standing at 11.5 m for 30 s of every 60 s,
 * a stray return at 11.95 m in 3 % of the frames at random, the road at
 * 13.3 m otherwise; in odd columns a wall at 11.6 m (what the cells beside
 * the car see as static) */
/* row 12: the slanted post of a sign behind the queue of row 8: in odd
 * columns its middle at 25.0-25.1 m, in even ones its edge, spread over
 * 25.0-25.33 m (more than the occluded rule allows there, 0.25 m), with a
 * wall at 30 m seen past it in 30 % of the frames */
/* row 13: a lane where nothing behind returns (a dark road out of reach):
 * the queue's last car stands at 40 m for 10 s of every 60 s, then the
 * queue moves up (its cars at 33-35 m, another range every cycle) for 15 s;
 * then traffic in the near lane (20 m) 2 frames of every 5, nothing between
 * (so "no return" is no persistent state: not sky). Row 14: a wall at 80 m
 * behind a queue that stands at 30-34 m for 40 s of every 60 s; the wall's
 * returns drop out at random in 60 % of the frames: it too returns less
 * often than nothing, but at random. Row 15: a post at 40 m behind a queue
 * (its cars at 20-24 m, another range every cycle) that leaves it in view
 * 10 s of every 60 s, in a quarter of the 5 s windows; its returns spread
 * over 0.6 m (the mixed returns of its edge), the far side of the edge
 * (49 m) in a quarter of those frames, at random */
/* row 1 also holds, in columns 30-39, a canopy behind a lane where a queue
 * stands (its cars at 12-16 m, another range every cycle) for whole 5 s
 * windows: 25 s of every 60 s in columns 30-34 (the canopy in view in 7 of
 * every 12 windows), 40 s in columns 36-39 (4 of 12); in view, leaves at
 * 30-30.15 m in 30 % of the frames at random, a wall at 40 m otherwise */
/* row 1 also holds, in columns 40-49, a lane whose traffic hides what is
 * behind it in runs of 1.5 s (a vehicle at 12-16 m), every 3 s; in view, in
 * columns 40-44 a dense canopy: leaves anywhere in 30-31 m in 85 % of the
 * frames at random, a wall at 40 m otherwise; in columns 45-49 a far lane
 * whose vehicles (their sides at 30 m) pass in front of that wall 0.5 s of
 * every second; in columns 50-54 a far lane of dense traffic, vehicles seen
 * for four frames each, the next one coming at random (70 % of the time at
 * once), each at its own range in 30-31 m: in view it comes and goes about
 * at random (it is there in 90 % of those frames), but its range stays for
 * the frames of a vehicle */
/* row 3 also holds, in columns 60-69, the ground far off at a grazing angle:
 * 86 m, returned in 4 % of the frames at random in each cell on its own,
 * nothing otherwise (no return is a persistent state there: sky); and in
 * columns 80-89 traffic in front of nothing: a vehicle at 30 m in 2 % of the
 * frames, at random, seen in the ten cells at once, for one frame */
/* the far lane of row 1, columns 50-54: 0 no vehicle in frame f, else the
 * vehicle's number (1, 2, ...); a vehicle stays 4 frames, and a frame
 * without a vehicle or a vehicle's last frame is followed by a new vehicle
 * with probability 0.7 (the same draw for the five cells) */
#define LANE_FRAMES 1800
static int far_lane(int f) {
  static int veh[LANE_FRAMES];
  static bool made;
  if (!made) {
    int n = 0, left = 0;
    for (int i = 0; i < LANE_FRAMES; i++) {
      uint64_t z = (uint64_t)i * 0x9E3779B97F4A7C15ull; /* splitmix64's finaliser */
      z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
      z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
      const bool draw = (z ^ (z >> 31)) % 10u < 7u;
      if (left > 0) {
        veh[i] = n; /* the vehicle's next frame */
        left--;
      } else if (draw) {
        veh[i] = ++n;
        left = 3;
      } else
        veh[i] = 0;
    }
    made = true;
  }
  return f >= 0 && f < LANE_FRAMES ? veh[f] : 0;
}

#define ROWS 16 /* a VLP-16's */
#define COLS 100
static float truth_range(int row, int col, int frame, uint64_t *rng) {
  double t = frame * 0.1;
  *rng ^= *rng << 13;
  *rng ^= *rng >> 7;
  *rng ^= *rng << 17;
  double u = (double)(*rng % 10000) / 10000.0;
  double noise = ((double)((*rng >> 20) % 100) / 100.0 - 0.5) * 0.03;
  switch (row) {
  case 0: return (float)(20.0 + noise);
  case 1:
    if (col >= 30 && col < 40 && col != 35) {
      if (fmod(t, 60.0) < (col < 35 ? 25.0 : 40.0)) return (float)(12.0 + fmod(floor(t / 60.0) * 1.37, 4.0) + noise);
      return (float)(u < 0.3 ? 30.0 + 0.5 * u + noise : 40.0 + noise);
    }
    if (col >= 40 && col < 55) {
      if (fmod(t, 3.0) < 1.5) return (float)(12.0 + fmod(floor(t / 3.0) * 1.37, 4.0) + noise);
      if (col < 45) return (float)(u < 0.85 ? 30.0 + u / 0.85 + noise : 40.0 + noise);
      if (col >= 50) {
        const int v = far_lane(frame);
        return (float)(v ? 30.0 + fmod(v * 0.618, 1.0) + noise : 40.0 + noise);
      }
      return (float)(fmod(t + 0.25, 1.0) < 0.5 ? 30.0 + noise : 40.0 + noise);
    }
    return (float)(u < 0.5 ? 8.0 + u + noise : 20.0 + noise);
  case 2: return (float)(fmod(t, 60.0) < 30.0 ? 9.0 + noise : 12.0 + noise);
  case 3:
    if (col >= 60 && col < 70) return u < 0.04 ? (float)(86.0 + noise) : 0.0f;
    if (col >= 80 && col < 90) /* one draw per frame, the same for the ten cells */
      return ((uint32_t)frame * 2654435761u) % 10000u < 200u ? (float)(30.0 + noise) : 0.0f;
    return fmod(t, 60.0) < 30.0 ? (float)(15.0 + noise) : 0.0f;
  case 4: return (float)(fmod(t, 2.0) < 0.3 ? 10.0 + noise : 14.0 + noise);
  case 5: return (float)(40.0 + 2.0 * fmod(frame * 0.843, 1.0) + noise);
  case 6: return u < 0.5 ? 0.0f : (float)(186.0 + 0.17 * (double)((*rng >> 40) % 24) + noise);
  case 8:
    if (fmod(t, 60.0) < 25.0) return (float)(12.0 + fmod(floor(t / 60.0) * 1.37, 4.0) + noise);
    return (float)(u < 0.03 ? 27.0 + noise : 25.0 + noise);
  case 11:
    if (col % 2) return (float)(11.6 + noise);
    if (fmod(t, 60.0) < 30.0) return (float)(11.5 + noise);
    return (float)(u < 0.03 ? 11.95 + noise : 13.3 + noise);
  case 10:
    if (fmod(t, 60.0) < 25.0) return (float)(12.0 + fmod(floor(t / 60.0) * 1.37, 4.0) + noise);
    return (float)(u < 0.3 ? 30.0 + noise : 25.0 + noise);
  case 12:
    if (fmod(t, 60.0) < 25.0) return (float)(12.0 + fmod(floor(t / 60.0) * 1.37, 4.0) + noise);
    if (col % 2) return (float)(25.05 + noise);
    return (float)(u < 0.3 ? 30.0 + noise : 25.0 + 0.3 * ((double)((*rng >> 40) % 1000) / 1000.0) + noise);
  case 13:
    if (fmod(t, 60.0) < 10.0) return (float)(40.0 + noise);
    if (fmod(t, 60.0) < 25.0) return (float)(33.0 + fmod(floor(t / 60.0) * 0.77, 2.0) + noise);
    return fmod(t + 0.05, 0.5) < 0.2 ? (float)(20.0 + noise) : 0.0f;
  case 14:
    if (fmod(t, 60.0) < 40.0) return (float)(30.0 + fmod(floor(t / 60.0) * 1.37, 4.0) + noise);
    return u < 0.6 ? 0.0f : (float)(80.0 + noise);
  case 15:
    if (fmod(t, 60.0) < 2.5 || fmod(t, 60.0) >= 12.5) return (float)(20.0 + fmod(floor(t / 60.0) * 1.37, 4.0) + noise);
    return (float)(u < 0.25 ? 49.0 + noise : 40.0 + 0.6 * ((double)((*rng >> 40) % 1000) / 1000.0) + noise);
  case 9:
    if (fmod(t, 60.0) < 30.0) return (float)(18.0 + noise);
    return (float)(fmod(t, 60.0) < 45.0 ? 11.0 + noise : 25.0 + noise);
  default:
    return fmod(t, 60.0) < 30.0 ? (float)(19.2 + noise) : (float)(20.0 + 0.17 * (double)((*rng >> 40) % 6) + noise);
  }
}

static void make_frame(int f, uint64_t *rng) {
  memset(&slot.meta, 0, sizeof slot.meta);
  slot.meta.rows = ROWS;
  slot.meta.cols = COLS;
  slot.meta.model = RS_MODEL_VLP16;
  slot.meta.t_first = 1000.0 + f * 0.1;
  for (int r = 0; r < ROWS; r++)
    for (int c = 0; c < COLS; c++) slot.range[r * COLS + c] = truth_range(r, c, f, rng);
}

static rs_bg_model_t model;

/* the model of the map above, learned with p */
static void learn_model_params(const rs_bg_params_t *p) {
  rs_bg_learner_t l;
  ck_assert_int_eq(rs_bg_learner_init(&l, RS_MODEL_VLP16, ROWS, COLS, 1200, 5), RS_OK);
  uint64_t rng = 88172645463325252ull;
  for (int f = 0; f < 1800; f++) { /* three minutes at 10 Hz, three signal cycles */
    make_frame(f, &rng);
    rs_bg_learner_add(&l, &slot);
  }
  ck_assert_int_eq(l.nframes, 1200);
  ck_assert_uint_eq(l.seen, 1800);
  ck_assert_int_eq(rs_bg_learn(&l, p, 10.0f, &model), RS_OK);
  rs_bg_learner_free(&l);
}

static void learn_model_with(double chain_gap, bool support) {
  rs_bg_params_t p;
  rs_bg_params_default(&p);
  if (chain_gap >= 0) p.chain_gap = chain_gap;
  p.support = support;
  learn_model_params(&p);
}

static void learn_model_gap(double chain_gap) { learn_model_with(chain_gap, true); }
static void learn_model(void) { learn_model_gap(-1.0); }

START_TEST(t_learn_hard_cases) {
  learn_model();
  /* wall */
  ck_assert(rs_bg_is_static(&model, 0, 5, 20.0f));
  ck_assert(!rs_bg_is_static(&model, 0, 5, 19.0f));
  /* leaves and the wall behind them are both background */
  ck_assert(rs_bg_is_static(&model, 1, 5, 20.0f));
  ck_assert(rs_bg_is_static(&model, 1, 5, 8.5f));
  ck_assert(!rs_bg_is_static(&model, 1, 5, 14.0f));
  /* the canopy behind the queue, in view in 7 of every 12 windows, is in
   * nearly all of those: background; the queue is not. In view in 4 of 12
   * (under coverage_open of the windows) it cannot be told from something
   * that comes and goes: foreground */
  for (int c = 30; c < 35; c++) {
    ck_assert_msg(rs_bg_is_static(&model, 1, c, 30.1f), "canopy behind the queue, column %d", c);
    ck_assert(rs_bg_is_static(&model, 1, c, 40.0f));
    ck_assert(!rs_bg_is_static(&model, 1, c, 13.0f));
  }
  for (int c = 36; c < 40; c++) ck_assert_msg(!rs_bg_is_static(&model, 1, c, 30.1f), "canopy hidden 40 s, column %d", c);
  /* the dense canopy behind the lane: back in the next frame far more often
   * than it is seen (the traffic in front hides it in runs), so it does not
   * flicker; over the frames it could be seen in it comes and goes at random,
   * at any depth: leaves. The far lane's vehicles, at one range too, stay
   * once there and stay away once gone: foreground */
  for (int c = 40; c < 45; c++) {
    ck_assert_msg(rs_bg_is_static(&model, 1, c, 30.2f), "dense canopy, column %d", c);
    ck_assert(rs_bg_is_static(&model, 1, c, 30.9f));
    ck_assert(rs_bg_is_static(&model, 1, c, 40.0f));
    ck_assert(!rs_bg_is_static(&model, 1, c, 13.0f));
  }
  for (int c = 45; c < 50; c++) {
    ck_assert_msg(!rs_bg_is_static(&model, 1, c, 30.0f), "far lane, column %d", c);
    ck_assert(rs_bg_is_static(&model, 1, c, 40.0f));
  }
  /* the far lane's dense traffic comes and goes about at random, but its
   * range stays from one frame to the next as leaves' does not */
  for (int c = 50; c < 55; c++) {
    for (int v = 1; v < 20; v++)
      ck_assert_msg(!rs_bg_is_static(&model, 1, c, (float)(30.0 + fmod(v * 0.618, 1.0))), "dense far lane, column %d", c);
    ck_assert(rs_bg_is_static(&model, 1, c, 40.0f));
  }
  /* the queued car is foreground, the ground it stands on background */
  ck_assert(rs_bg_is_static(&model, 2, 5, 12.0f));
  ck_assert(!rs_bg_is_static(&model, 2, 5, 9.0f));
  /* a truck against the sky is never background */
  ck_assert(!rs_bg_is_static(&model, 3, 5, 15.0f));
  ck_assert_int_eq(model.n[3 * COLS + 5], 0);
  /* the far ground whose returns drop out at random, cell by cell, is
   * background; traffic in front of nothing, now and then, in the ten cells
   * at once, is not */
  for (int c = 60; c < 70; c++) {
    ck_assert_msg(rs_bg_is_static(&model, 3, c, 86.0f), "sparse ground, column %d", c);
    ck_assert(!rs_bg_is_static(&model, 3, c, 84.0f));
  }
  for (int c = 80; c < 90; c++) ck_assert_msg(!rs_bg_is_static(&model, 3, c, 30.0f), "passing traffic, column %d", c);
  /* passing traffic is foreground */
  ck_assert(rs_bg_is_static(&model, 4, 5, 14.0f));
  ck_assert(!rs_bg_is_static(&model, 4, 5, 10.0f));
  /* a grazing surface spreads over 2 m but stays one surface */
  ck_assert(rs_bg_is_static(&model, 5, 5, 40.3f));
  ck_assert(rs_bg_is_static(&model, 5, 5, 41.9f));
  ck_assert(!rs_bg_is_static(&model, 5, 5, 38.0f));
  ck_assert_int_eq(model.n[5 * COLS + 5], 1);
  /* the clumps of the far facade are one surface, nearest to farthest */
  ck_assert(rs_bg_is_static(&model, 6, 5, 186.0f));
  ck_assert(rs_bg_is_static(&model, 6, 5, 188.0f));
  ck_assert(rs_bg_is_static(&model, 6, 5, 189.9f));
  ck_assert(!rs_bg_is_static(&model, 6, 5, 180.0f));
  /* the near facade too, and the car standing 0.8 m in front of it is not */
  ck_assert(rs_bg_is_static(&model, 7, 5, 20.0f));
  ck_assert(rs_bg_is_static(&model, 7, 5, 20.85f));
  ck_assert(!rs_bg_is_static(&model, 7, 5, 19.2f));
  /* the kerb hidden by a queue most of the time is background (it does not
   * flicker, and is not the farthest: the edge behind it is); the queue is not */
  ck_assert(rs_bg_is_static(&model, 8, 5, 25.0f));
  ck_assert(rs_bg_is_static(&model, 8, 5, 27.0f));
  ck_assert(!rs_bg_is_static(&model, 8, 5, 13.0f));
  /* the car at the stop line leaves the road behind it to be seen: foreground */
  ck_assert(!rs_bg_is_static(&model, 9, 5, 18.0f));
  ck_assert(!rs_bg_is_static(&model, 9, 5, 11.0f));
  ck_assert(rs_bg_is_static(&model, 9, 5, 25.0f));
  /* the kerb at the wall's edge: the wall behind it, seen now and then, is
   * the far side of the edge, not what a stopped vehicle hid */
  ck_assert(rs_bg_is_static(&model, 10, 5, 25.0f));
  ck_assert(rs_bg_is_static(&model, 10, 5, 30.0f));
  ck_assert(!rs_bg_is_static(&model, 10, 5, 13.0f));
  /* the car beside the wall is not made static by the wall (its cluster and
   * the stray returns just behind it, judged together, stayed) */
  ck_assert(!rs_bg_is_static(&model, 11, 10, 11.5f));
  ck_assert(rs_bg_is_static(&model, 11, 10, 13.3f));
  ck_assert(rs_bg_is_static(&model, 11, 11, 11.6f));
  /* the post's edge, hidden by the queue: too spread for the occluded rule, taken from the cells beside */
  for (int c = 20; c <= 21; c++) {
    ck_assert(rs_bg_is_static(&model, 12, c, 25.05f));
    ck_assert(!rs_bg_is_static(&model, 12, c, 13.0f));
  }
  ck_assert(rs_bg_is_static(&model, 12, 20, 25.3f));
  ck_assert(rs_bg_is_static(&model, 12, 20, 30.0f));
  /* the queue's last car in front of nothing is not the scene; the far wall
   * whose returns drop out is, and not the queue in front of it */
  ck_assert(!rs_bg_is_static(&model, 13, 5, 40.0f));
  ck_assert(!rs_bg_is_static(&model, 13, 5, 33.5f));
  ck_assert(rs_bg_is_static(&model, 14, 5, 80.0f));
  ck_assert(!rs_bg_is_static(&model, 14, 5, 31.0f));
  /* the post seen in a quarter of the windows, nothing steady behind it: background; the queue not */
  ck_assert(rs_bg_is_static(&model, 15, 5, 40.1f));
  ck_assert(rs_bg_is_static(&model, 15, 5, 40.5f));
  ck_assert(!rs_bg_is_static(&model, 15, 5, 21.0f));
  rs_bg_model_free(&model);
  /* each rule off in turn (its share set to 0), relearned: what it decided */
  static const struct {
    size_t off;  /* the rule's share in rs_bg_params_t */
    size_t off2; /* another rule off with it (0: none) */
    int row, col;
    float range;
    bool is_static;
  } off[] = {
      /* without void_stay the queue's last car is the cell's static surface; the far wall stays */
      {offsetof(rs_bg_params_t, void_stay), 0, 13, 5, 40.0f, true},
      {offsetof(rs_bg_params_t, void_stay), 0, 14, 5, 80.0f, true},
      /* without occluded_clear the post needs half the windows: foreground */
      {offsetof(rs_bg_params_t, occluded_clear), 0, 15, 5, 40.1f, false},
      {offsetof(rs_bg_params_t, occluded_clear), 0, 14, 5, 80.0f, true},
      /* with the windows counted over all of the capture, the canopy behind the queue is foreground */
      {offsetof(rs_bg_params_t, coverage_open), 0, 1, 30, 30.1f, false},
      /* without the leaves rule the dense canopy is foreground */
      {offsetof(rs_bg_params_t, leaves_range), 0, 1, 42, 30.2f, false},
      {offsetof(rs_bg_params_t, leaves_range), 0, 1, 42, 40.0f, true},
      /* the kerbs hidden by the queue come and go at random when in view,
       * at one range: the leaves rule takes them too; without both, and
       * only then, they are foreground */
      {offsetof(rs_bg_params_t, occluded_max), 0, 8, 5, 25.0f, true},
      {offsetof(rs_bg_params_t, occluded_max), 0, 10, 5, 25.0f, true},
      {offsetof(rs_bg_params_t, occluded_max), offsetof(rs_bg_params_t, leaves_range), 8, 5, 25.0f, false},
      {offsetof(rs_bg_params_t, occluded_max), offsetof(rs_bg_params_t, leaves_range), 10, 5, 25.0f, false},
  };
  for (size_t i = 0; i < sizeof off / sizeof off[0]; i++) {
    if (i == 0 || off[i].off != off[i - 1].off || off[i].off2 != off[i - 1].off2) {
      if (i > 0) rs_bg_model_free(&model);
      rs_bg_params_t p;
      rs_bg_params_default(&p);
      *(double *)((char *)&p + off[i].off) = 0.0;
      if (off[i].off2) *(double *)((char *)&p + off[i].off2) = 0.0;
      learn_model_params(&p);
    }
    ck_assert_msg(rs_bg_is_static(&model, off[i].row, off[i].col, off[i].range) == off[i].is_static,
                  "rule %zu off: row %d column %d at %.1f m static %d", i, off[i].row, off[i].col, (double)off[i].range,
                  !off[i].is_static);
  }
  rs_bg_model_free(&model);
  /* without sparse_cover the far ground is background only in the cells whose
   * few returns happened to fall in 80 % of the windows */
  rs_bg_params_t p;
  rs_bg_params_default(&p);
  p.sparse_cover = 0.0;
  learn_model_params(&p);
  int ground = 0;
  for (int c = 60; c < 70; c++) ground += rs_bg_is_static(&model, 3, c, 86.0f);
  ck_assert_int_le(ground, 3);
  rs_bg_model_free(&model);
}
END_TEST

/* The sparse clumps of the far facade are one surface whichever rule joins
 * them: the chain gap (clumps that both flicker), a flickering cluster just
 * in front of a background one, or the cells beside that see the same
 * facade. The car standing 0.8 m in front of the near facade is joined by
 * none of them: it does not flicker, and stays for several frames. */
START_TEST(t_learn_chain_gap) {
  for (int i = 0; i < 4; i++) {
    learn_model_with(i & 1 ? 1.0 : 0.0, i & 2);
    ck_assert(rs_bg_is_static(&model, 6, 5, 186.0f));
    ck_assert(rs_bg_is_static(&model, 6, 5, 189.9f));
    ck_assert(rs_bg_is_static(&model, 7, 5, 20.0f));
    ck_assert(!rs_bg_is_static(&model, 7, 5, 19.2f));
    rs_bg_model_free(&model);
  }
}
END_TEST

/* A short capture (40 frames, 2 s at 20 Hz), the way a site is often first
 * learned: row 0 a pole (10 m) in columns 0-9 and a wall (30 m) beyond,
 * column 10 the pole's edge, on the pole in 20 % of the frames at random
 * (too few to judge its flicker);
 * row 1 the same edge with a car standing at the pole's range in front of
 * column 20 for 15 frames; row 2 a wall seen at a grazing angle, 0.3 m
 * farther in each column; row 3 a queue in column 10, its vehicles
 * anywhere from 14 to 17 m, with nothing behind it in reach; row 4 a surface seen in 45 %
 * of the frames in column 30 (through a canopy), nothing in column 31 */
static float short_range(int row, int col, int f, uint64_t *rng) {
  *rng ^= *rng << 13;
  *rng ^= *rng >> 7;
  *rng ^= *rng << 17;
  const double u = (double)(*rng % 10000) / 10000.0, noise = ((double)((*rng >> 20) % 100) / 100.0 - 0.5) * 0.02;
  switch (row) {
  case 0: return (float)((col < 10 || (col == 10 && u < 0.2) ? 10.0 : 30.0) + noise);
  case 1:
    if (col == 20 && f >= 10 && f < 25) return (float)(10.0 + noise);
    return (float)((col < 10 || (col == 10 && u < 0.2) || col == 19 ? 10.0 : 30.0) + noise);
  case 2: return (float)(30.0 + 1.0 * col + noise);
  case 3: return col == 10 ? (float)(14.0 + 3.0 * u + noise) : 0.0f;
  case 4: return col == 30 && u < 0.45 ? (float)(25.0 + noise) : 0.0f;
  default: return 0.0f;
  }
}

START_TEST(t_learn_short) {
  rs_bg_learner_t l;
  ck_assert_int_eq(rs_bg_learner_init(&l, RS_MODEL_VLP16, ROWS, COLS, 40, 5), RS_OK);
  uint64_t rng = 0x9E3779B97F4A7C15ull;
  for (int f = 0; f < 40; f++) {
    memset(&slot, 0, sizeof slot);
    slot.meta.rows = ROWS;
    slot.meta.cols = COLS;
    slot.meta.model = RS_MODEL_VLP16;
    slot.meta.t_first = 1000.0 + f * 0.05;
    for (int r = 0; r < ROWS; r++)
      for (int c = 0; c < COLS; c++) slot.range[r * COLS + c] = short_range(r, c, f, &rng);
    rs_bg_learner_add(&l, &slot);
  }
  rs_bg_params_t p;
  rs_bg_params_default(&p);
  ck_assert_int_eq(rs_bg_min_pts(&p, 40), 4); /* a tenth of the frames, not the floor of 10 */
  ck_assert_int_eq(rs_bg_learn(&l, &p, 20.0f, &model), RS_OK);
  /* the pole's edge: both surfaces, from the cell beside it */
  ck_assert(rs_bg_is_static(&model, 0, 10, 10.0f));
  ck_assert(rs_bg_is_static(&model, 0, 10, 30.0f));
  ck_assert(!rs_bg_is_static(&model, 0, 10, 20.0f));
  /* without that support, the edge is foreground half the time */
  rs_bg_model_free(&model);
  p.support = false;
  ck_assert_int_eq(rs_bg_learn(&l, &p, 20.0f, &model), RS_OK);
  ck_assert(!rs_bg_is_static(&model, 0, 10, 10.0f));
  rs_bg_model_free(&model);
  p.support = true;
  ck_assert_int_eq(rs_bg_learn(&l, &p, 20.0f, &model), RS_OK);
  /* a car standing 15 frames at the pole's range beside it is not background */
  ck_assert(!rs_bg_is_static(&model, 1, 20, 10.0f));
  ck_assert(rs_bg_is_static(&model, 1, 20, 30.0f));
  /* the grazing wall: a column's interval reaches half-way to its neighbours' */
  ck_assert(rs_bg_is_static(&model, 2, 10, 39.6f));
  ck_assert(rs_bg_is_static(&model, 2, 10, 40.4f));
  ck_assert(!rs_bg_is_static(&model, 2, 10, 39.0f));
  rs_bg_model_free(&model);
  p.connect_min = 0;
  ck_assert_int_eq(rs_bg_learn(&l, &p, 20.0f, &model), RS_OK);
  ck_assert(!rs_bg_is_static(&model, 2, 10, 39.6f));
  rs_bg_model_free(&model);
  rs_bg_params_default(&p);
  ck_assert_int_eq(rs_bg_learn(&l, &p, 20.0f, &model), RS_OK);
  /* the queue: with eps fixed at 0.4 m DBSCAN keeps it one cluster, spread
   * over 3 m in one cell: no surface (narrower, it would be one) */
  rs_bg_model_free(&model);
  p.eps_min = p.eps_max = 0.40;
  ck_assert_int_eq(rs_bg_learn(&l, &p, 20.0f, &model), RS_OK);
  ck_assert_int_eq(model.n[3 * COLS + 10], 0);
  ck_assert(!rs_bg_is_static(&model, 3, 10, 15.0f));
  rs_bg_model_free(&model);
  p.wide_min = 5.0;
  ck_assert_int_eq(rs_bg_learn(&l, &p, 20.0f, &model), RS_OK);
  ck_assert_int_eq(model.n[3 * COLS + 10], 1);
  rs_bg_model_free(&model);
  rs_bg_params_default(&p);
  ck_assert_int_eq(rs_bg_learn(&l, &p, 20.0f, &model), RS_OK);
  /* how often the farthest surface is seen */
  ck_assert_int_eq(model.far_seen[0 * COLS + 50], 100);
  ck_assert_int_le(model.far_seen[4 * COLS + 30], 60);
  ck_assert_int_ge(model.far_seen[4 * COLS + 30], 30);
  /* subtraction: behind a solid surface, background (counted); far behind
   * one seen through, foreground; just behind it, background; an empty cell
   * takes the surfaces of a cell beside it seen in half the frames or more */
  memset(&slot, 0, sizeof slot);
  slot.meta.rows = ROWS;
  slot.meta.cols = COLS;
  slot.range[0 * COLS + 50] = 45.0f;
  slot.range[4 * COLS + 30] = 40.0f;
  slot.range[4 * COLS + 29] = 25.1f;
  slot.range[0 * COLS + 60] = 25.0f; /* in front of the wall: foreground */
  rs_bg_counts_t c = {0};
  rs_bg_subtract(&model, &rules, &slot, &c);
  ck_assert_int_eq(slot.label[0 * COLS + 50], RS_LABEL_BACKGROUND);
  ck_assert_int_eq(slot.label[4 * COLS + 30], RS_LABEL_NOISE);
  ck_assert_uint_eq(c.beyond, 2);
  /* column 29 learned nothing; column 30's surface is seen in under half the frames */
  ck_assert_int_eq(model.n[4 * COLS + 29], 0);
  ck_assert_int_eq(slot.label[4 * COLS + 29], RS_LABEL_NOISE);
  ck_assert_int_eq(slot.label[0 * COLS + 60], RS_LABEL_NOISE);
  slot.range[4 * COLS + 30] = 25.4f; /* 0.4 m behind it, under 0.3 m + margins: background */
  rs_bg_subtract(&model, &rules, &slot, &c);
  ck_assert_int_eq(slot.label[4 * COLS + 30], RS_LABEL_BACKGROUND);
  model.far_seen[4 * COLS + 30] = 60; /* seen more often: the empty cell beside it takes its surface */
  rs_bg_subtract(&model, &rules, &slot, &c);
  ck_assert_int_eq(slot.label[4 * COLS + 29], RS_LABEL_BACKGROUND);
  rs_bg_model_free(&model);
  /* three frames: a cell that returned once has a surface */
  rs_bg_learner_free(&l);
  ck_assert_int_eq(rs_bg_learner_init(&l, RS_MODEL_VLP16, ROWS, COLS, 3, 5), RS_OK);
  for (int f = 0; f < 3; f++) {
    memset(&slot, 0, sizeof slot);
    slot.meta.rows = ROWS;
    slot.meta.cols = COLS;
    slot.meta.t_first = f * 0.1;
    slot.range[5 * COLS + 7] = f == 1 ? 12.0f : 0.0f;
    slot.range[5 * COLS + 8] = 12.0f;
    rs_bg_learner_add(&l, &slot);
  }
  ck_assert_int_eq(rs_bg_min_pts(&p, 3), 1);
  ck_assert_int_eq(rs_bg_learn(&l, &p, 10.0f, &model), RS_OK);
  ck_assert(rs_bg_is_static(&model, 5, 7, 12.0f));
  ck_assert(rs_bg_is_static(&model, 5, 8, 12.0f));
  rs_bg_model_free(&model);
  rs_bg_learner_free(&l);
}
END_TEST

START_TEST(t_subtract) {
  learn_model();
  memset(&slot, 0, sizeof slot);
  slot.meta.rows = ROWS;
  slot.meta.cols = COLS;
  slot.range[0 * COLS + 3] = 20.0f;          /* wall: background */
  slot.range[2 * COLS + 3] = 9.0f;           /* queued car: foreground */
  slot.range[0 * COLS + 4] = 35.0f;          /* beyond the wall: background (nothing moves behind it), counted */
  slot.range[RS_MAX_CELLS + 1 * COLS + 3] = 20.0f; /* layer 1 (dual): the wall */
  static uint32_t beyond[ROWS * COLS];
  rs_bg_counts_t c = {.beyond_cells = beyond};
  rs_bg_subtract(&model, &rules, &slot, &c);
  ck_assert_uint_eq(c.background, 3);
  ck_assert_uint_eq(c.foreground, 1);
  ck_assert_uint_eq(c.beyond, 1);
  ck_assert_int_eq(slot.label[0 * COLS + 3], 1);
  ck_assert_int_eq(slot.label[2 * COLS + 3], 2);
  ck_assert_int_eq(slot.label[0 * COLS + 4], 1);
  ck_assert_int_eq(slot.label[RS_MAX_CELLS + 1 * COLS + 3], 1);
  ck_assert_int_eq(slot.label[0 * COLS + 5], 0); /* no return: untouched */
  ck_assert_uint_eq(beyond[4], 1);
  /* with beyond_static off, it is foreground (still counted) */
  rules.beyond_static = false;
  memset(&c, 0, sizeof c);
  rs_bg_subtract(&model, &rules, &slot, &c);
  ck_assert_int_eq(slot.label[0 * COLS + 4], 2);
  ck_assert_uint_eq(c.beyond, 1);
  rs_bg_model_free(&model);
}
END_TEST

static void set_cell(rs_bg_model_t *m, int row, int col, int n, const uint16_t *lohi) {
  const size_t cell = (size_t)row * m->cols + (size_t)col;
  m->n[cell] = (uint8_t)n;
  for (int k = 0; k < n; k++) {
    m->lo[cell * RS_BG_SURFACES + (size_t)k] = lohi[2 * k];
    m->hi[cell * RS_BG_SURFACES + (size_t)k] = lohi[2 * k + 1];
  }
}

/* labels of a return of 15 m in each of the probe cells, with a given see_through */
static void see_through_probe(const rs_bg_model_t *m, int see, uint16_t out[4]) {
  static const int probe[4][2] = {{0, 5}, {1, 5}, {2, 0}, {3, 5}};
  rules.see_through = see;
  memset(&slot, 0, sizeof slot);
  slot.meta.rows = ROWS;
  slot.meta.cols = COLS;
  for (int i = 0; i < 4; i++) slot.range[probe[i][0] * COLS + probe[i][1]] = 15.0f;
  rs_bg_counts_t c = {0};
  rs_bg_subtract(m, &rules, &slot, &c);
  ck_assert_uint_eq(c.background + c.foreground, 4);
  for (int i = 0; i < 4; i++) out[i] = slot.label[probe[i][0] * COLS + probe[i][1]];
}

/* one row of a wall at 10 m (columns 500-599) in front of one at 30 m
 * (400-499, 600-699), 0.2 degree columns, seen turned by `shift` columns;
 * `obj` (m, 0 = none) a return in column 650 */
#define SCOLS 1800
static void displaced_frame(int shift, float obj) {
  memset(&slot, 0, sizeof slot);
  slot.meta.rows = ROWS;
  slot.meta.cols = SCOLS;
  for (int c = 400; c < 700; c++) {
    const int w = c - shift; /* where the firing of column c falls in the learned scene */
    slot.range[3 * SCOLS + c] = w >= 500 && w < 600 ? 10.02f : 30.02f;
  }
  if (obj > 0) slot.range[3 * SCOLS + 650] = obj;
  slot.meta.points = 300;
}

/* The shift rule (background.h): a frame whose edges show their far side
 * where the near side was learned is displaced, and returns within the
 * tolerance of a surface nearby in the row are background; a still frame
 * is labelled as without the rule; an object away from every surface stays
 * foreground either way. */
START_TEST(t_subtract_displaced) {
  rs_bg_model_t m;
  ck_assert_int_eq(rs_bg_model_alloc(&m, RS_MODEL_VLP16, ROWS, SCOLS), RS_OK);
  const uint16_t near[2] = {995, 1010}, far[2] = {2995, 3010};
  for (int c = 400; c < 700; c++) {
    set_cell(&m, 3, c, 1, c >= 500 && c < 600 ? near : far);
    m.far_seen[3 * SCOLS + c] = 100;
  }
  rs_bg_rules_t r;
  rs_bg_rules_default(&r);
  ck_assert_double_eq(r.shift_tol, RS_BG_SHIFT_TOL);
  rs_bg_counts_t c = {0};
  /* still: all background but the object at 20 m */
  displaced_frame(0, 20.0f);
  rs_bg_subtract(&m, &r, &slot, &c);
  ck_assert(!c.displaced);
  ck_assert_uint_eq(c.evidence, 0);
  ck_assert_uint_eq(c.foreground, 1);
  ck_assert_int_eq(slot.label[3 * SCOLS + 650], RS_LABEL_NOISE);
  /* no gate (shift_gate 0): every frame is judged displaced; the still object by the far wall goes */
  rs_bg_rules_t ungated = r;
  ungated.shift_gate = 0;
  displaced_frame(0, 29.95f);
  rs_bg_subtract(&m, &ungated, &slot, &c);
  ck_assert(c.displaced);
  ck_assert_int_eq(slot.label[3 * SCOLS + 650], RS_LABEL_BACKGROUND);
  /* turned by 3 columns (0.6 degree): columns 500-502 see the far wall behind
   * the near one (evidence), 600-602 the near wall in front of the far one */
  memset(&c, 0, sizeof c);
  displaced_frame(3, 20.0f);
  rs_bg_subtract(&m, &r, &slot, &c);
  ck_assert(c.displaced);
  ck_assert_uint_eq(c.evidence, 1); /* gathered up to what the gate needs: 0.15 % of 300 returns */
  ck_assert_uint_eq(c.displaced_frames, 1);
  ck_assert_uint_eq(c.shifted, 3);
  for (int k = 600; k < 603; k++) ck_assert_int_eq(slot.label[3 * SCOLS + k], RS_LABEL_BACKGROUND);
  ck_assert_int_eq(slot.label[3 * SCOLS + 650], RS_LABEL_NOISE); /* the object stays */
  ck_assert_uint_eq(c.foreground, 1);
  /* an object within the tolerance of the far wall is taken for it (the rule's cost) */
  displaced_frame(3, 29.95f);
  rs_bg_subtract(&m, &r, &slot, &c);
  ck_assert_int_eq(slot.label[3 * SCOLS + 650], RS_LABEL_BACKGROUND);
  /* off: the edge is foreground */
  rs_bg_rules_t off = r;
  off.shift_tol = 0;
  memset(&c, 0, sizeof c);
  displaced_frame(3, 0);
  rs_bg_subtract(&m, &off, &slot, &c);
  ck_assert(!c.displaced);
  ck_assert_uint_eq(c.foreground, 3);
  /* not enough evidence (a gate of half the returns): not displaced */
  off = r;
  off.shift_gate = 0.5;
  memset(&c, 0, sizeof c);
  rs_bg_subtract(&m, &off, &slot, &c);
  ck_assert(!c.displaced);
  ck_assert_uint_eq(c.foreground, 3);
  /* turned by 12 columns (2.4 degrees): of the 12 columns of the near wall in front of
   * the far one, the 4 within 0.15 m of column 599 (at most 0.7 degree: 0.12 m at 10 m)
   * are background, the other 8 are not */
  memset(&c, 0, sizeof c);
  displaced_frame(12, 0);
  rs_bg_subtract(&m, &r, &slot, &c);
  ck_assert(c.displaced);
  ck_assert_uint_eq(c.foreground, 8);
  for (int k = 600; k < 612; k++) ck_assert_int_eq(slot.label[3 * SCOLS + k], k < 604 ? RS_LABEL_BACKGROUND : RS_LABEL_NOISE);
  rs_bg_model_free(&m);
}
END_TEST

/* What a displaced sensor sees behind a near object (background.h): an
 * object 1.3 m away (columns 500-599, seen in 40 % of the learning frames)
 * in front of a wall at 8 m. Moved, the sensor sees past the object's edge
 * onto what it hid, set back at 8.6 m: background within the object's
 * parallax band (atan(0.15 / 1.3): 33 columns of 0.2 degree); the same
 * range deep behind the object, or a vehicle behind it nearer than the wall,
 * stays foreground, as everything does in a still frame or with the rule off. */
static void behind_frame(void) {
  memset(&slot, 0, sizeof slot);
  slot.meta.rows = ROWS;
  slot.meta.cols = SCOLS;
  for (int c = 400; c < 700; c++) slot.range[3 * SCOLS + c] = c >= 510 && c < 600 ? 1.30f : 8.05f;
  for (int c = 500; c < 510; c++) slot.range[3 * SCOLS + c] = 8.6f; /* seen past the edge */
  slot.range[3 * SCOLS + 520] = 5.0f;                               /* a vehicle behind the object */
  slot.range[3 * SCOLS + 560] = 8.6f;                               /* deep behind it */
  slot.meta.points = 300;
}

START_TEST(t_subtract_behind) {
  rs_bg_model_t m;
  ck_assert_int_eq(rs_bg_model_alloc(&m, RS_MODEL_VLP16, ROWS, SCOLS), RS_OK);
  const uint16_t obj[2] = {128, 132}, wall[2] = {800, 810};
  for (int c = 400; c < 700; c++) {
    const bool o = c >= 500 && c < 600;
    set_cell(&m, 3, c, 1, o ? obj : wall);
    m.far_seen[3 * SCOLS + c] = o ? 40 : 100;
  }
  rs_bg_rules_t r;
  rs_bg_rules_default(&r);
  ck_assert(r.shift_behind);
  r.shift_gate = 0; /* judged displaced: the gate has its own test */
  rs_bg_counts_t c = {0};
  behind_frame();
  rs_bg_subtract(&m, &r, &slot, &c);
  ck_assert(c.displaced);
  ck_assert_uint_eq(c.behind, 10);
  for (int k = 500; k < 510; k++) ck_assert_int_eq(slot.label[3 * SCOLS + k], RS_LABEL_BACKGROUND);
  ck_assert_int_eq(slot.label[3 * SCOLS + 520], RS_LABEL_NOISE);
  ck_assert_int_eq(slot.label[3 * SCOLS + 560], RS_LABEL_NOISE);
  ck_assert_uint_eq(c.foreground, 2);
  /* off */
  rs_bg_rules_t off = r;
  off.shift_behind = false;
  memset(&c, 0, sizeof c);
  rs_bg_subtract(&m, &off, &slot, &c);
  ck_assert(c.displaced);
  ck_assert_uint_eq(c.behind, 0);
  ck_assert_uint_eq(c.foreground, 12);
  /* a still sensor (the default gate; no evidence): the same returns are foreground */
  rs_bg_rules_default(&r);
  memset(&c, 0, sizeof c);
  rs_bg_subtract(&m, &r, &slot, &c);
  ck_assert(!c.displaced);
  ck_assert_uint_eq(c.foreground, 12);
  /* a wall farther away: the object's band is narrower (atan(0.15 / 5.3): 8 columns) */
  const uint16_t obj5[2] = {528, 532};
  for (int c2 = 500; c2 < 600; c2++) set_cell(&m, 3, c2, 1, obj5);
  behind_frame();
  for (int k = 510; k < 600; k++) slot.range[3 * SCOLS + k] = 5.3f;
  slot.range[3 * SCOLS + 520] = 0.0f;
  rs_bg_rules_default(&r);
  r.shift_gate = 0;
  memset(&c, 0, sizeof c);
  rs_bg_subtract(&m, &r, &slot, &c);
  for (int k = 500; k < 510; k++) ck_assert_int_eq(slot.label[3 * SCOLS + k], k < 508 ? RS_LABEL_BACKGROUND : RS_LABEL_NOISE);
  rs_bg_model_free(&m);
}
END_TEST

/* Leaves at 15 m learned in the cell beside: background in a cell the sensor
 * sees through (two surfaces), not in a cell of one surface, not from the
 * rows above and below; the row wraps at column 0. */
START_TEST(t_subtract_see_through) {
  rs_bg_model_t m;
  ck_assert_int_eq(rs_bg_model_alloc(&m, RS_MODEL_VLP16, ROWS, COLS), RS_OK);
  rs_bg_rules_t dr;
  rs_bg_rules_default(&dr);
  ck_assert_int_eq(dr.see_through, RS_BG_SEE_THROUGH);
  const uint16_t two[4] = {900, 1000, 2000, 2100}, one[2] = {2000, 2100}, leaf[2] = {1490, 1510};
  set_cell(&m, 0, 5, 2, two);
  set_cell(&m, 0, 4, 1, leaf);
  set_cell(&m, 1, 5, 1, one);
  set_cell(&m, 1, 6, 1, leaf);
  set_cell(&m, 2, 0, 2, two);
  set_cell(&m, 2, COLS - 1, 1, leaf);
  set_cell(&m, 3, 5, 2, two);
  set_cell(&m, 2, 5, 1, leaf);
  set_cell(&m, 4, 5, 1, leaf);
  uint16_t l[4];
  see_through_probe(&m, 2, l);
  ck_assert_int_eq(l[0], 1);
  ck_assert_int_eq(l[1], 2);
  ck_assert_int_eq(l[2], 1);
  ck_assert_int_eq(l[3], 2);
  see_through_probe(&m, 3, l);
  ck_assert_int_eq(l[0], 2);
  ck_assert_int_eq(l[2], 2);
  see_through_probe(&m, 0, l);
  ck_assert_int_eq(l[0], 2);
  see_through_probe(&m, 1, l);
  ck_assert_int_eq(l[1], 1);
  rs_bg_model_free(&m);
}
END_TEST

static long fsize(const char *p) {
  FILE *f = fopen(p, "rb");
  fseek(f, 0, SEEK_END);
  long n = ftell(f);
  fclose(f);
  return n;
}

static void flip_byte(const char *p, long off) {
  FILE *f = fopen(p, "r+b");
  fseek(f, off, SEEK_SET);
  int c = fgetc(f);
  fseek(f, off, SEEK_SET);
  fputc(c ^ 0x40, f);
  fclose(f);
}

START_TEST(t_model_file) {
  learn_model();
  char err[RS_ERRMSG_SIZE];
  const char *p = tu_tmp("m.bg");
  ck_assert_int_eq(rs_bg_save(&model, p, err, sizeof err), RS_OK);
  rs_bg_model_t back;
  ck_assert_int_eq(rs_bg_load(&back, p, err, sizeof err), RS_OK);
  ck_assert_int_eq(back.rows, ROWS);
  ck_assert_int_eq(back.cols, COLS);
  ck_assert_int_eq(back.model, RS_MODEL_VLP16);
  ck_assert_uint_eq(back.frames, 1200);
  ck_assert_double_eq_tol(back.params.eps_max, 0.40, 1e-9);
  ck_assert_mem_eq(back.n, model.n, ROWS * COLS);
  ck_assert_mem_eq(back.lo, model.lo, ROWS * COLS * RS_BG_SURFACES * 2);
  ck_assert_mem_eq(back.hi, model.hi, ROWS * COLS * RS_BG_SURFACES * 2);
  rs_bg_model_free(&back);
  long size = fsize(p);
  char cmd[1200];
  /* truncated */
  const char *t = tu_tmp("t.bg");
  snprintf(cmd, sizeof cmd, "head -c %ld %s > %s", size - 10, p, t);
  ck_assert_int_eq(system(cmd), 0);
  ck_assert_int_eq(rs_bg_load(&back, t, err, sizeof err), RS_E_FORMAT);
  ck_assert_ptr_nonnull(strstr(err, "truncated"));
  /* a flipped bit in the surfaces */
  snprintf(cmd, sizeof cmd, "cp %s %s", p, t);
  ck_assert_int_eq(system(cmd), 0);
  flip_byte(t, size / 2);
  ck_assert_int_eq(rs_bg_load(&back, t, err, sizeof err), RS_E_FORMAT);
  ck_assert_ptr_nonnull(strstr(err, "checksum"));
  /* another version */
  ck_assert_int_eq(system(cmd), 0);
  flip_byte(t, 8);
  ck_assert_int_eq(rs_bg_load(&back, t, err, sizeof err), RS_E_FORMAT);
  ck_assert_ptr_nonnull(strstr(err, "version"));
  /* not a model */
  ck_assert_int_eq(system(cmd), 0);
  flip_byte(t, 0);
  ck_assert_int_eq(rs_bg_load(&back, t, err, sizeof err), RS_E_FORMAT);
  ck_assert_ptr_nonnull(strstr(err, "bad magic"));
  ck_assert_int_eq(rs_bg_load(&back, tu_tmp("absent.bg"), err, sizeof err), RS_E_NOENT);
  rs_bg_model_free(&model);
  /* a header whose rows do not fit its sensor (the CRC is recomputed: no
   * protection) is refused by name, before anything reads the cells */
  rs_bg_model_t odd;
  ck_assert_int_eq(rs_bg_model_alloc(&odd, RS_MODEL_VLP16, 8, COLS), RS_OK);
  ck_assert_int_eq(rs_bg_save(&odd, t, err, sizeof err), RS_OK);
  rs_bg_model_free(&odd);
  ck_assert_int_eq(rs_bg_load(&back, t, err, sizeof err), RS_E_FORMAT);
  ck_assert_msg(strstr(err, "8 rows, a VLP-16 has 16 lasers") != NULL, "%s", err);
}
END_TEST

/* A save is atomic: one that fails in the middle (the file-size limit reached, as a full disk)
 * leaves the model that was there whole and no temporary file; one into a missing directory
 * says why. */
START_TEST(t_model_save_is_atomic) {
  learn_model();
  char err[RS_ERRMSG_SIZE];
  const char *p = tu_tmp("atomic.bg");
  ck_assert_int_eq(rs_bg_save(&model, p, err, sizeof err), RS_OK);
  const long size = fsize(p);
  ck_assert_int_gt(size, 4096);
  rs_bg_model_t other;
  ck_assert_int_eq(rs_bg_model_alloc(&other, RS_MODEL_VLP16, ROWS, COLS), RS_OK);
  pid_t pid = fork();
  ck_assert_int_ge(pid, 0);
  if (pid == 0) { /* a disk that fills up after 4 kB */
    signal(SIGXFSZ, SIG_IGN);
    struct rlimit rl = {4096, 4096};
    setrlimit(RLIMIT_FSIZE, &rl);
    const int rc = rs_bg_save(&other, p, err, sizeof err);
    _exit(rc == RS_E_IO && strstr(err, "cannot write the model") ? 0 : 1);
  }
  int st;
  waitpid(pid, &st, 0);
  ck_assert_msg(WIFEXITED(st) && WEXITSTATUS(st) == 0, "the limited save did not fail as it should");
  rs_bg_model_free(&other);
  rs_bg_model_t back;
  ck_assert_int_eq(rs_bg_load(&back, p, err, sizeof err), RS_OK); /* the old model, whole */
  ck_assert_int_eq(fsize(p), size);
  ck_assert_mem_eq(back.lo, model.lo, ROWS * COLS * RS_BG_SURFACES * 2);
  rs_bg_model_free(&back);
  /* no temporary file left beside it */
  DIR *d = opendir(RS_TMP_DIR);
  ck_assert_ptr_nonnull(d);
  struct dirent *e;
  while ((e = readdir(d)) != NULL) ck_assert_msg(strncmp(e->d_name, "atomic.bg.tmp", 13) != 0, "%s left", e->d_name);
  closedir(d);
  ck_assert_int_eq(rs_bg_save(&model, tu_tmp("no-such-dir/m.bg"), err, sizeof err), RS_E_IO);
  ck_assert_msg(strstr(err, "no-such-dir/m.bg: cannot write the model: No such file or directory") != NULL, "%s", err);
  rs_bg_model_free(&model);
}
END_TEST

START_TEST(t_percentile_and_reservoir) {
  rs_bg_learner_t l;
  ck_assert_int_eq(rs_bg_learner_init(&l, RS_MODEL_VLP16, ROWS, COLS, 100, 9), RS_OK);
  uint64_t rng = 1;
  int kept_late = 0;
  for (int f = 0; f < 1000; f++) {
    make_frame(f, &rng);
    rs_bg_learner_add(&l, &slot);
  }
  /* reservoir sampling: frames from the whole capture, not only the first 100 */
  for (int i = 0; i < l.nframes; i++) kept_late += l.t[i] > 1000.0 + 50.0;
  ck_assert_int_gt(kept_late, 30);
  rs_bg_params_t p;
  rs_bg_params_default(&p);
  p.method = RS_BG_PERCENTILE;
  p.percentile = 50;
  p.percentile_tol = 0.3;
  ck_assert_int_eq(rs_bg_learn(&l, &p, 10.0f, &model), RS_OK);
  /* the median of row 2 is the car half the time, the ground the other half:
   * a percentile model takes either; the wall row is background from 19.7 m on */
  ck_assert(rs_bg_is_static(&model, 0, 1, 19.8f));
  ck_assert(rs_bg_is_static(&model, 0, 1, 300.0f));
  ck_assert(!rs_bg_is_static(&model, 0, 1, 19.0f));
  rs_bg_model_free(&model);
  rs_bg_learner_free(&l);
  ck_assert_int_eq(rs_bg_learner_init(&l, RS_MODEL_VLP16, 0, COLS, 10, 1), RS_E_INVAL);
}
END_TEST

int main(void) {
  rs_bg_rules_default(&rules);
  Suite *s = suite_create("background");
  TCase *tc = tcase_create("core");
  tcase_set_timeout(tc, 120);
  tcase_add_test(tc, t_dbscan1d);
  tcase_add_test(tc, t_learn_hard_cases);
  tcase_add_test(tc, t_learn_chain_gap);
  tcase_add_test(tc, t_learn_short);
  tcase_add_test(tc, t_subtract);
  tcase_add_test(tc, t_subtract_see_through);
  tcase_add_test(tc, t_subtract_displaced);
  tcase_add_test(tc, t_subtract_behind);
  tcase_add_test(tc, t_model_file);
  tcase_add_test(tc, t_model_save_is_atomic);
  tcase_add_test(tc, t_percentile_and_reservoir);
  suite_add_tcase(s, tc);
  return tu_run(s);
}

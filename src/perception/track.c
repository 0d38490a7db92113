/* track.c - the tracker stage (processing thread; no allocation).
 *
 * Per frame: predict every track to each object's time, gate (grid lookup
 * around the prediction, then Mahalanobis, Euclidean and implied speed),
 * mark clusters that hold two confirmed tracks, assign (confirmed tracks,
 * then tentative ones: Hungarian per connected group, a track left without
 * an object at miss_cost, greedy beyond RS_TRACK_GROUP_MAX), update, absorb
 * split parts, give birth, confirm, end.
 * Every loop is bounded by RS_TRACK_MAX, RS_OBJ_MAX or the edge capacity. */
#include "roadscan/perception/track.h"

#include "roadscan/util/assign.h"
#include "roadscan/util/error.h"
#include "roadscan/util/opts.h"
#include "roadscan/util/sort.h"

#include <math.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define PI 3.14159265358979323846
#define BIG 1e12
#define GRID 4.0          /* m, cells of the object lookup grid */
#define WALKER_M 1.3f     /* m, a box shorter and narrower than this is a walker's size (q_small, the class rule) */
#define DUP_BOX_M 3.0f    /* m: dup_box's older track at least this long (a vehicle's) ... */
#define DUP_BOX_V 2.0     /* m/s: ... and moving this fast (two queues side by side stand still) */
#define SEEN_ACROSS_RANGE_M 80.0 /* m: seen_across_m within this range (farther, a box of a few rows is no measure) */
#define SEEN_ACROSS_TURN 0.1      /* rad/s: ... for a track turning slower than this */
#define TWIN_OVERLAP_M 0.5 /* m: twin_s's overlap of two boxes along their heading */
#define TWIN_COS 0.966     /* ... whose velocities are at most 15 degrees apart */
#define TWIN_DV 2.0        /* m/s: ... and speeds at most this far apart */
#define TWIN_RANGE_M 50.0  /* m: ... within this range (farther, boxes of a few rows are no measure of overlap) */
#define TWIN_SEEN_S 0.25   /* s: ... both seen this recently (a vehicle's coasting track predicted on is not a twin) */
#define UPRIGHT_M 0.5f    /* m, a walker-sized track at least this tall stands upright (confirm_upright_points) */
#define GRID_BUCKETS RS_TRACK_GRID_BUCKETS
#define EDGES_PER_TRACK RS_TRACK_EDGES_PER_TRACK

void rs_track_cfg_default(rs_track_cfg_t *c) {
  c->q_accel = 1.0;
  c->q_long = 1.0;
  c->q_small = 0.25;
  c->meas_sd = 0.15;
  c->meas_sd_per_m = 0.1;
  c->meas_sd_fit = 0.05;
  c->meas_sd_misfit = 0.5;
  c->gate_chi2 = 13.8;
  c->gate_m = 4.0;
  c->max_speed = 50.0;
  c->init_speed_sd = 25.0;
  c->init_small_speed_sd = 5.0;
  c->birth_points = 5;
  c->birth_far_points = 4;
  c->birth_far_from_m = 25.0;
  c->birth_far_to_m = 50.0;
  c->walker_across_m = 1.5;
  c->confirm_hits = 3;
  c->confirm_move_m = 0.8;
  c->confirm_still_s = 1.5;
  c->tentative_miss_s = 0.25;
  c->coast_s = 1.0;
  c->lost_s = 2.0;
  c->still_speed = 0.3;
  c->size_weight = 2.0;
  c->confirm_still_spread = 0.15;
  c->confirm_still_window = 3;
  c->confirm_steady = 1;
  c->clear_part_share = 0.25;
  c->clear_beside = 1;
  c->clear_longer = 1;
  c->confirm_still_points = 30;
  c->confirm_still_range = 20.0;
  c->confirm_walker_points = 20;
  c->confirm_upright_points = 8;
  c->hidden_anchor = 1;
  c->reacq_across_m = 1.0;
  c->confirm_walk_m = 0.3;
  c->confirm_cut_walk_m = 0.15;
  c->split_full_size = 1;
  c->blind_turn = 1;
  c->split_object_axis = 1;
  c->split_near_circle = 1;
  c->dup_box = 1;
  c->lost_walker_s = 4.0;
  c->below_beam = 1;
  c->still_lane = 1;
  c->brake_coast = 1;
  c->still_coast = 1;
  c->still_reverse = 1;
  c->queue_coast = 1;
  c->walked_hits = 10;
  c->blind_s = 8.0;
  c->speed_imm = 1;
  c->imm_birth_wide = 1;
  c->misfit_own = 1;
  c->confirm_pace = 1;
  c->q_jerk = 1.0;
  c->turn_rate = 0.0;
  c->near_ref_m = 25.0;
  c->near_ref_s = 2.0;
  c->end_ref = 1;
  c->near_across = 1;
  c->twin_s = 0.3;
  c->seen_across_m = 2.0;
  c->walker_reacq_s = 0.3;
  c->circle_whole = 1;
  c->uncover_restart = 2;
  c->merge_parts = 1;
  c->merge_front_m = 1.0;
  c->tent_claim_m = 0.5;
  c->kin_accel = 2.5;
  c->walker_part = 1;
  c->blind_walker = 1;
  c->blind_walker_s = 12.0;
  c->blind_walker_cross = 1.0;
  c->blind_walker_alone = 1;
  c->blind_walker_fifo = 1;
  c->blind_walker_line = 1.5;
  c->speed_full_length = 1;
  c->split_car_m = 5.0;
  c->stitch_kin = 1;
  c->stitch_alike = 1;
  c->gap_unseen = 1;
  c->miss_cost = 24.0;
  c->blind_walker_pace_s = 3.0;
}

int rs_track_init(rs_tracker_t *tr, const rs_track_cfg_t *cfg) {
  if (!(cfg->q_accel > 0 && cfg->q_accel < 1000) || !(cfg->q_long > 0 && cfg->q_long < 1000) || !(cfg->q_small > 0 && cfg->q_small < 1000) || !(cfg->meas_sd > 0 && cfg->meas_sd < 10) ||
      !(cfg->meas_sd_per_m >= 0 && cfg->meas_sd_per_m < 10) || !(cfg->meas_sd_fit >= 0 && cfg->meas_sd_fit <= 5) ||
      !(cfg->meas_sd_misfit >= 0 && cfg->meas_sd_misfit <= 10) || !(cfg->gate_chi2 > 0) || !(cfg->gate_m > 0 && cfg->gate_m <= 20) ||
      !(cfg->max_speed > 0 && cfg->max_speed <= 100) || !(cfg->init_speed_sd > 0) || !(cfg->init_small_speed_sd > 0) || cfg->birth_points < 1 ||
      cfg->birth_far_points < 0 || cfg->birth_far_points > 10000 || !(cfg->birth_far_from_m >= 0 && cfg->birth_far_from_m <= 1000) ||
      !(cfg->birth_far_to_m >= 0 && cfg->birth_far_to_m <= 1000) || (cfg->birth_far_points > 0 && !(cfg->birth_far_from_m < cfg->birth_far_to_m)) || !(cfg->walker_across_m >= 0 && cfg->walker_across_m <= 20) ||
      cfg->confirm_hits < 1 || !(cfg->confirm_move_m >= 0) || !(cfg->confirm_still_s >= 0) ||
      !(cfg->tentative_miss_s > 0) || !(cfg->coast_s > 0 && cfg->coast_s <= 60) || !(cfg->lost_s >= 0 && cfg->lost_s <= 60) || !(cfg->still_speed >= 0) || !(cfg->size_weight >= 0 && cfg->size_weight <= 100) ||
      !(cfg->confirm_still_spread >= 0 && cfg->confirm_still_spread <= 5) || cfg->confirm_still_points < 1 ||
      cfg->confirm_still_window < 0 || cfg->confirm_still_window > RS_TRACK_STILL_WINDOW ||
      cfg->confirm_steady < 0 || cfg->confirm_steady > 1 || !(cfg->clear_part_share >= 0 && cfg->clear_part_share <= 1) ||
      cfg->clear_beside < 0 || cfg->clear_beside > 1 || cfg->clear_longer < 0 || cfg->clear_longer > 1 ||
      cfg->confirm_walker_points < 0 || cfg->confirm_walker_points > 100000 ||
      cfg->confirm_upright_points < 0 || cfg->confirm_upright_points > 100000 ||
      !(cfg->confirm_still_range >= 0 && cfg->confirm_still_range <= 1000) ||
      cfg->hidden_anchor < 0 || cfg->hidden_anchor > 1 || !(cfg->reacq_across_m >= 0 && cfg->reacq_across_m <= 20) ||
      !(cfg->confirm_walk_m >= 0 && cfg->confirm_walk_m <= 20) ||
      !(cfg->confirm_cut_walk_m >= 0 && cfg->confirm_cut_walk_m <= 20) || cfg->split_full_size < 0 || cfg->split_full_size > 1 ||
      cfg->blind_turn < 0 || cfg->blind_turn > 1 || cfg->split_object_axis < 0 || cfg->split_object_axis > 1 ||
      cfg->split_near_circle < 0 || cfg->split_near_circle > 1 || cfg->dup_box < 0 || cfg->dup_box > 1 ||
      !(cfg->lost_walker_s >= 0 && cfg->lost_walker_s <= 60) || cfg->below_beam < 0 || cfg->below_beam > 1 ||
      cfg->still_lane < 0 || cfg->still_lane > 1 || cfg->brake_coast < 0 || cfg->brake_coast > 1 || cfg->still_coast < 0 || cfg->still_coast > 1 ||
      cfg->still_reverse < 0 || cfg->still_reverse > 1 || cfg->queue_coast < 0 || cfg->queue_coast > 1 ||
      !(cfg->blind_s >= 0 && cfg->blind_s <= 60) || cfg->walked_hits < 0 || cfg->walked_hits > 1000 ||
      cfg->speed_imm < 0 || cfg->speed_imm > 1 || cfg->imm_birth_wide < 0 || cfg->imm_birth_wide > 1 ||
      cfg->misfit_own < 0 || cfg->misfit_own > 1 || cfg->confirm_pace < 0 || cfg->confirm_pace > 1 ||
      !(cfg->q_jerk > 0 && cfg->q_jerk <= 100) || !(cfg->turn_rate >= 0 && cfg->turn_rate <= 2) ||
      !(cfg->near_ref_m >= 0 && cfg->near_ref_m <= 1000) || !(cfg->near_ref_s >= 0 && cfg->near_ref_s <= 60) || cfg->end_ref < 0 || cfg->end_ref > 1 || cfg->near_across < 0 || cfg->near_across > 1 ||
      !(cfg->twin_s >= 0 && cfg->twin_s <= 60) || !(cfg->walker_reacq_s >= 0 && cfg->walker_reacq_s <= 60) ||
      !(cfg->seen_across_m >= 0 && cfg->seen_across_m <= 20) ||
      cfg->circle_whole < 0 || cfg->circle_whole > 1 || cfg->uncover_restart < 0 || cfg->uncover_restart > 2 ||
      cfg->merge_parts < 0 || cfg->merge_parts > 1 || !(cfg->merge_front_m >= 0 && cfg->merge_front_m <= 20) || !(cfg->tent_claim_m >= 0 && cfg->tent_claim_m <= 20) || !(cfg->kin_accel >= 0 && cfg->kin_accel <= 10) ||
      cfg->walker_part < 0 || cfg->walker_part > 1 || cfg->speed_full_length < 0 || cfg->speed_full_length > 1 ||
      cfg->blind_walker < 0 || cfg->blind_walker > 1 || !(cfg->blind_walker_s >= 0 && cfg->blind_walker_s <= RS_TRACK_WALKER_KEEP_MAX) ||
      !(cfg->blind_walker_cross >= 0 && cfg->blind_walker_cross <= 10) || cfg->blind_walker_alone < 0 || cfg->blind_walker_alone > 1 ||
      cfg->blind_walker_fifo < 0 || cfg->blind_walker_fifo > 1 || !(cfg->blind_walker_line >= 0 && cfg->blind_walker_line <= 20) || !(cfg->split_car_m >= 0 && cfg->split_car_m <= 20) ||
      cfg->stitch_kin < 0 || cfg->stitch_kin > 1 || cfg->stitch_alike < 0 || cfg->stitch_alike > 1 || cfg->gap_unseen < 0 || cfg->gap_unseen > 1 ||
      !(cfg->miss_cost >= 0 && cfg->miss_cost <= 1000) || !(cfg->blind_walker_pace_s >= 0 && cfg->blind_walker_pace_s <= 60))
    return RS_E_INVAL;
  memset(&tr->list, 0, sizeof tr->list);
  memset(&tr->n, 0, sizeof tr->n);
  for (int b = 0; b < GRID_BUCKETS; b++) tr->lead_head[b] = tr->grid_head[b] = tr->tgrid_head[b] = -1;
  tr->nlead = 0;
  tr->grid_nused = 0;
  tr->tgrid_n = 0;
  tr->hold_objects = 0;
  tr->obj_base = NULL;
  tr->obj_n = 0;
  tr->have_pose = false;
  tr->cfg = *cfg;
  tr->next_id = 1;
  tr->last_t = 0;
  return RS_OK;
}

/* the parameters by name, with their ranges (rs_track_cfg_set; roadscand --track-set) */
#define KNOB(f, l, u) {.type = RS_OPT_DOUBLE, .name = #f, .arg = "X", .off = offsetof(rs_track_cfg_t, f), .lo = l, .hi = u}
#define KNOB_INT(f, l, u) {.type = RS_OPT_INT, .name = #f, .arg = "N", .off = offsetof(rs_track_cfg_t, f), .lo = l, .hi = u}
static const rs_opt_t knobs[] = {
    KNOB(q_accel, 0.01, 100.0),       KNOB(q_long, 0.01, 100.0),       KNOB(q_small, 0.01, 100.0),       KNOB(meas_sd, 0.01, 5.0),         KNOB(meas_sd_per_m, 0.0, 2.0),
    KNOB(meas_sd_fit, 0.0, 5.0),      KNOB(meas_sd_misfit, 0.0, 10.0),
    KNOB(gate_chi2, 1.0, 100.0),      KNOB(gate_m, 0.5, 20.0),          KNOB(max_speed, 1.0, 100.0),
    KNOB(init_speed_sd, 0.1, 100.0),  KNOB(init_small_speed_sd, 0.1, 100.0),
    KNOB_INT(birth_points, 1, 10000), KNOB_INT(birth_far_points, 0, 10000),
    KNOB(birth_far_from_m, 0.0, 1000.0), KNOB(birth_far_to_m, 0.0, 1000.0), KNOB(walker_across_m, 0.0, 20.0), KNOB_INT(confirm_hits, 1, 100),
    KNOB(confirm_move_m, 0.0, 20.0),  KNOB(confirm_still_s, 0.0, 60.0), KNOB(tentative_miss_s, 0.01, 10.0),
    KNOB(coast_s, 0.01, 60.0),        KNOB(lost_s, 0.0, 60.0),          KNOB(still_speed, 0.0, 5.0),
    KNOB(size_weight, 0.0, 100.0),    KNOB(confirm_still_spread, 0.0, 5.0), KNOB_INT(confirm_still_points, 1, 100000),
    KNOB_INT(confirm_walker_points, 0, 100000), KNOB_INT(confirm_upright_points, 0, 100000),
    KNOB(confirm_still_range, 0.0, 1000.0),
    KNOB_INT(hidden_anchor, 0, 1),   KNOB(reacq_across_m, 0.0, 20.0),    KNOB(confirm_walk_m, 0.0, 20.0),
    KNOB(confirm_cut_walk_m, 0.0, 20.0), KNOB_INT(confirm_still_window, 0, RS_TRACK_STILL_WINDOW), KNOB_INT(confirm_steady, 0, 1),
    KNOB_INT(split_full_size, 0, 1),  KNOB(lost_walker_s, 0.0, 60.0),   KNOB_INT(below_beam, 0, 1),
    KNOB(blind_s, 0.0, 60.0),         KNOB_INT(speed_imm, 0, 1),       KNOB_INT(imm_birth_wide, 0, 1),  KNOB_INT(misfit_own, 0, 1), KNOB_INT(confirm_pace, 0, 1),
    KNOB(q_jerk, 0.01, 100.0),
    KNOB_INT(walked_hits, 0, 1000),   KNOB(turn_rate, 0.0, 2.0),       KNOB_INT(blind_turn, 0, 1),
    KNOB_INT(split_object_axis, 0, 1), KNOB_INT(split_near_circle, 0, 1), KNOB_INT(dup_box, 0, 1),
    KNOB(near_ref_m, 0.0, 1000.0),    KNOB(near_ref_s, 0.0, 60.0),      KNOB_INT(end_ref, 0, 1), KNOB_INT(near_across, 0, 1),      KNOB(twin_s, 0.0, 60.0),
    KNOB(walker_reacq_s, 0.0, 60.0),  KNOB(seen_across_m, 0.0, 20.0), KNOB_INT(circle_whole, 0, 1),
    KNOB_INT(uncover_restart, 0, 2), KNOB_INT(merge_parts, 0, 1), KNOB(merge_front_m, 0.0, 20.0), KNOB(tent_claim_m, 0.0, 20.0), KNOB(kin_accel, 0.0, 10.0),
    KNOB_INT(walker_part, 0, 1), KNOB_INT(speed_full_length, 0, 1), KNOB_INT(blind_walker, 0, 1), KNOB(blind_walker_s, 0.0, RS_TRACK_WALKER_KEEP_MAX), KNOB(blind_walker_cross, 0.0, 10.0), KNOB_INT(blind_walker_alone, 0, 1),
    KNOB_INT(blind_walker_fifo, 0, 1), KNOB(blind_walker_line, 0.0, 20.0), KNOB(split_car_m, 0.0, 20.0), KNOB_INT(stitch_kin, 0, 1), KNOB_INT(stitch_alike, 0, 1), KNOB_INT(gap_unseen, 0, 1), KNOB(miss_cost, 0.0, 1000.0),
    KNOB_INT(still_lane, 0, 1), KNOB_INT(brake_coast, 0, 1), KNOB_INT(still_coast, 0, 1), KNOB(blind_walker_pace_s, 0.0, 60.0),
    KNOB_INT(still_reverse, 0, 1), KNOB_INT(queue_coast, 0, 1),
    KNOB(clear_part_share, 0.0, 1.0), KNOB_INT(clear_beside, 0, 1), KNOB_INT(clear_longer, 0, 1),
};

int rs_track_cfg_set(rs_track_cfg_t *c, const char *name, const char *value, char *err, size_t n) {
  return rs_opt_set(knobs, (int)(sizeof knobs / sizeof knobs[0]), c, "tracking parameter", name, value, err, n);
}

void rs_track_cfg_names(char *buf, size_t size) { rs_opt_names(knobs, (int)(sizeof knobs / sizeof knobs[0]), buf, size); }

void rs_track_set_pose(rs_tracker_t *tr, const rs_pose_t *pose) {
  tr->have_pose = pose != NULL;
  tr->list.site_valid = tr->have_pose;
  if (!pose) return;
  rs_pose_rotation(pose, tr->rot);
  tr->trans[0] = pose->x;
  tr->trans[1] = pose->y;
  tr->trans[2] = pose->z;
}

/* the site-frame state of every track (positions with the box's bottom as z; velocities and headings
 * turned by the rotation, on the site's ground plane) */
static void site_states(rs_tracker_t *tr) {
  for (uint32_t i = 0; i < tr->list.count; i++) {
    rs_track_t *t = &tr->list.track[i];
    const double p[3] = {t->x[0], t->x[1], t->z_min};
    for (int a = 0; a < 3; a++)
      t->site[a] = (float)(tr->rot[3 * a] * p[0] + tr->rot[3 * a + 1] * p[1] + tr->rot[3 * a + 2] * p[2] + tr->trans[a]);
    const double vx = tr->rot[0] * t->vel[0] + tr->rot[1] * t->vel[1], vy = tr->rot[3] * t->vel[0] + tr->rot[4] * t->vel[1];
    t->site_v[0] = (float)vx;
    t->site_v[1] = (float)vy;
    const double hx = tr->rot[0] * t->hcos + tr->rot[1] * t->hsin, hy = tr->rot[3] * t->hcos + tr->rot[4] * t->hsin;
    t->site_heading = (float)atan2(hy, hx);
  }
}

const char *rs_track_state_name(rs_track_state_t s) {
  switch (s) {
  case RS_TRACK_TENTATIVE: return "tentative";
  case RS_TRACK_CONFIRMED: return "confirmed";
  case RS_TRACK_COASTING: return "coasting";
  case RS_TRACK_LOST: return "lost";
  }
  return "?";
}

const char *rs_class_name(rs_class_t c) {
  static const char *const names[RS_CLASS_COUNT] = {"unknown", "pedestrian", "cyclist", "car", "van/truck", "bus"};
  return (unsigned)c < RS_CLASS_COUNT ? names[c] : "?";
}

/* the length of (x, y): libm's hypot guards against overflow and rounds more
 * carefully, at about twenty times the cost; the tracker's numbers are metres
 * and metres per second, far from overflow */
static inline double norm2(double x, double y) { return sqrt(x * x + y * y); }

/* fmin and fmax as glibc gives them on x86-64 (an out-of-line call each, in
 * the tracker's hottest loops): the same result for every input, a NaN on
 * either side and zeros of either sign included (the second operand when
 * they compare equal) */
static inline double min_d(double a, double b) { return a < b ? a : (b != b ? a : b); }
static inline double max_d(double a, double b) { return a > b ? a : (b != b ? a : b); }
static inline float min_f(float a, float b) { return a < b ? a : (b != b ? a : b); }
static inline float max_f(float a, float b) { return a > b ? a : (b != b ? a : b); }

/* object k's measurement: box centre, noise sd */
static void meas(const rs_tracker_t *tr, const rs_object_t *o, double *z, double *sd) {
  z[0] = o->sensor.obb_center[0];
  z[1] = o->sensor.obb_center[1];
  *sd = tr->cfg.meas_sd + tr->cfg.meas_sd_per_m * o->sensor.obb_length;
}

#define MAX_SHIFT 3.0 /* m, the most a partial view's centre is moved */

/* a box no pedestrian's track takes: a vehicle's length, or its width seen end-on */
static bool vehicle_sized(float length, float width) {
  return length > RS_TRACK_PED_MAX_LENGTH || width > RS_TRACK_PED_MAX_WIDTH;
}

/* track t's smoothed box is a walker's size (q_small, the speed estimator, the walker's confirmation) */
static bool walker_sized(const rs_track_t *t) { return t->length < WALKER_M && t->width < WALKER_M; }
/* ... and so was its largest box (the blind circle's walkers: a walker's box shrinks as it goes under the beam) */
static bool walker_full_sized(const rs_track_t *t) { return t->full_length < WALKER_M && t->full_width < WALKER_M; }

/* how far a walker-sized tentative track must move to confirm: confirm_walk_m, or confirm_cut_walk_m when
 * it was born at the lowest beam's circle (a walker coming out from under the sensor is that beam's arc
 * across it, whose centre moves at about half its speed) */
static double walk_m(const rs_track_cfg_t *cf, const rs_track_t *t) {
  return t->cut && cf->confirm_cut_walk_m > 0 ? cf->confirm_cut_walk_m : cf->confirm_walk_m;
}

/* track t knows the size of what it follows: confirmed, 5 hits, a vehicle's length */
static bool size_known(const rs_track_t *t) { return t->state != RS_TRACK_TENTATIVE && t->hits >= 5 && t->length >= 1.5f; }

/* object o's oriented box on track t's axes (u along its heading, v across):
 * min u, max u, min v, max v */
/* (cd, sd: |cos| and |sin| of the angle between the box's heading and the axes) */
static void box_on_cs(const rs_object_t *o, double cd, double sd, double c, double s, double e[4]) {
  const double a = 0.5 * o->sensor.obb_length, b = 0.5 * o->sensor.obb_width;
  const double du = a * cd + b * sd, dv = a * sd + b * cd;
  const double cu = o->sensor.obb_center[0] * c + o->sensor.obb_center[1] * s;
  const double cv = -o->sensor.obb_center[0] * s + o->sensor.obb_center[1] * c;
  e[0] = cu - du, e[1] = cu + du, e[2] = cv - dv, e[3] = cv + dv;
}
static void box_on(const rs_object_t *o, double h, double c, double s, double e[4]) {
  const double dh = (double)o->sensor.obb_heading - h;
  box_on_cs(o, fabs(cos(dh)), fabs(sin(dh)), c, s, e);
}
/* the cosine and sine of object o's box heading computed once a frame (obj_cs); NULL when o is not
 * one of the frame's objects */
static const double *obj_cs_of(const rs_tracker_t *tr, const rs_object_t *o) {
  const uintptr_t at = (uintptr_t)o, base = (uintptr_t)tr->obj_base;
  if (tr->obj_base == NULL || at < base || at >= base + tr->obj_n * sizeof *o) return NULL;
  return tr->obj_cs[(at - base) / sizeof *o];
}
/* box_on on track t's axes: the cosine and sine of the angle between the two
 * headings from the track's (hcd, hsd) and the object's (obj_cs, once a frame) */
static void box_on_axes(const rs_tracker_t *tr, const rs_track_t *t, const rs_object_t *o, double e[4]) {
  const double *cs = obj_cs_of(tr, o);
  if (cs == NULL) {
    box_on(o, t->heading, t->hcos, t->hsin, e);
    return;
  }
  box_on_cs(o, fabs(cs[0] * t->hcd + cs[1] * t->hsd), fabs(cs[1] * t->hcd - cs[0] * t->hsd), t->hcos, t->hsin, e);
}

/* the point at u along axes (c, s) on the centre line of a box whose extents on them are e (box_on) */
static void end_point(double c, double s, const double e[4], double u, double p[2]) {
  const double cv = 0.5 * (e[2] + e[3]);
  p[0] = u * c - cv * s;
  p[1] = u * s + cv * c;
}
/* Which end of object o's box along axes (c, s) (e: its extents on them)
 * lies beside something nearer that may hide the rest of it
 * (rs_object_t.occluded): +1 the end of larger u, -1 the smaller, 0 neither
 * or both (or the two ends within asin(sin_min) of one line of sight). The
 * map's columns run clockwise (azimuth from +y towards +x): of the two ends
 * on the box's centre line, the one counter-clockwise of the other lies at
 * the object's first column. hidden_end: on track t's axes. */
static int hidden_end_on(double c, double s, const rs_object_t *o, const double e[4], double sin_min) {
  const unsigned h = o->occluded & (RS_OBJ_HIDDEN_START | RS_OBJ_HIDDEN_END);
  if (h == 0 || h == (RS_OBJ_HIDDEN_START | RS_OBJ_HIDDEN_END)) return 0;
  double pa[2], pb[2];
  end_point(c, s, e, e[0], pa); /* the end of smaller u */
  end_point(c, s, e, e[1], pb); /* of larger u */
  const double cross = pa[0] * pb[1] - pa[1] * pb[0], norm = norm2(pa[0], pa[1]) * norm2(pb[0], pb[1]);
  if (!(norm > 0) || !(fabs(cross) > sin_min * norm)) return 0; /* ends within asin(sin_min) of one line of sight */
  const bool larger_first = cross > 0; /* counter-clockwise: the smaller azimuth */
  return (h == RS_OBJ_HIDDEN_START) == larger_first ? 1 : -1;
}
static int hidden_end(const rs_track_t *t, const rs_object_t *o, const double e[4]) {
  return hidden_end_on(t->hcos, t->hsin, o, e, 0.02); /* ends within about a degree of one line of sight: 0 */
}

/* how near the sensor the lowest beam reaches a top at sensor z = top (m; 0: everywhere, or not known) */
static double reach_at(const rs_tracker_t *tr, double top) {
  return tr->low_tan > 0 && top < -0.05 ? -top / tr->low_tan : 0.0;
}

/* how near the sensor the nearest corner of a box len x wid centred at (x, y) can be (m) */
static double near_edge(double x, double y, double len, double wid) { return norm2(x, y) - 0.5 * norm2(len, wid); }

/* how near the sensor the lowest beam reaches track t's top (m; 0: everywhere, or not known). The
 * top is midway between its objects' returns' top and the row above them (top), not the returns' top
 * alone: one or two sparse rows on a car's side put that half a metre or more below its roof, and
 * the reach by it too far out */
static double beam_reach(const rs_tracker_t *tr, const rs_track_t *t) { return t->top_n > 0 ? reach_at(tr, t->top) : 0.0; }

/* The blind circle. A vehicle waiting at a line beside the sensor pulls
 * away through the circle its top is below the lowest beam in (a VLP-16
 * 4.5 m up: about 11 m for a car; a lane 6 m from the pole crosses 18 m of
 * it) and comes out at the other side seconds later, faster than its track
 * last knew (it was still, or seen in part). Its track, last seen at the
 * circle's edge, is kept for blind_s; a young moving track born at the
 * circle's other side in its lane, moving away along its axis, is it
 * (blind_link) and gives it its object and state. The reach is taken at
 * its returns' top, not beam_reach's: the farther of the two, as a test of
 * where it may have gone unseen should be (the rows above a car waiting
 * 12 m from a VLP-32C 5 m up, between its two lowest rows, never bound its
 * top). */
#define BLIND_EDGE_M 1.0  /* m: last seen this near the reach (its box's nearest corner) */
#define BLIND_BIRTH_M 3.0 /* m: the young track born this near it (its first box's centre) */
#define BLIND_WAY_M 2.0   /* m: the way between them passes this near it, or inside */
#define BLIND_COS 0.766   /* cos 40 degrees: the young track's velocity (and a moving old one's) off the way */
#define BLIND_TURN_SIN 0.7071 /* sin 45 degrees: the least turn of a turn way (and 135 the most) */
/* how near the sensor the segment a -> b passes */
static double seg_near(double ax, double ay, double bx, double by) {
  const double dx = bx - ax, dy = by - ay, d2 = dx * dx + dy * dy;
  double u = d2 > 0 ? -(ax * dx + ay * dy) / d2 : 0.0;
  u = u < 0 ? 0 : u > 1 ? 1 : u;
  return norm2(ax + u * dx, ay + u * dy);
}
static double blind_reach(const rs_tracker_t *tr, const rs_track_t *t) { return reach_at(tr, (double)t->z_min + (double)t->height); }

static bool at_blind_edge(const rs_tracker_t *tr, const rs_track_t *t) {
  if (!(tr->cfg.blind_s > 0) || t->hits == 0) return false;
  const double rb = blind_reach(tr, t);
  return rb > 0 && near_edge(t->last_z[0], t->last_z[1], t->length, t->width) <= rb + BLIND_EDGE_M;
}

/* young track y is track o come out of the blind circle: born within
 * blind_s after o was last seen at its edge, y's first centre near the
 * circle, at least 2 m from where o was and no farther than half max_speed
 * could take it, the straight way between the two passing inside the
 * circle grown by BLIND_WAY_M (a top a few decimetres off moves the reach
 * by a metre), y moving that way (within 40 degrees; a young track's velocity
 * is a growing box's, it comes right within a second, y is tried each
 * frame until 1.5 s old), and so was o when it moved (over 2 m/s; a waiting
 * car's box axis says nothing). Returns 1 - the cosine of y's angle off the
 * way (the least wins), or -1. With blind_turn, when that straight way
 * fails, y may have come out along a turn off o's way (a car turning at the
 * sensor's own corner): o moving, y's velocity 45-135 degrees off o's, o's
 * line ahead and y's behind meeting at p ahead of both, the way a -> p -> b
 * passing near the circle; then it returns 1 + how far the time unseen is
 * from that way's length at o's speed (after every straight way; of two
 * cars turning one behind the other, the first in is the first out). */
static double blind_link(const rs_tracker_t *tr, const rs_track_t *o, const rs_track_t *y) {
  const rs_track_cfg_t *cf = &tr->cfg;
  const double dt = y->t_birth - o->t_update;
  if (!(dt > 0) || dt > cf->blind_s || !at_blind_edge(tr, o)) return -1.0;
  const double rb = blind_reach(tr, o);
  if (norm2(y->px0, y->py0) > rb + BLIND_BIRTH_M) return -1.0;
  const double ax = o->last_z[0], ay = o->last_z[1], dx = y->px0 - ax, dy = y->py0 - ay, d = norm2(dx, dy);
  if (d < 2.0 || d > 0.5 * cf->max_speed * dt + 5.0) return -1.0;
  const double vx = y->x[2], vy = y->x[3], v = norm2(vx, vy);
  if (v < 1.0) return -1.0;
  const double cosv = (vx * dx + vy * dy) / (v * d);
  const double vo = norm2(o->x[2], o->x[3]);
  if (cosv >= BLIND_COS && !(vo > 2.0 && o->x[2] * dx + o->x[3] * dy < BLIND_COS * vo * d))
    return seg_near(ax, ay, y->px0, y->py0) < rb + BLIND_WAY_M ? 1.0 - cosv : -1.0;
  /* the turn: s along o's line and r back along y's to p */
  if (!cf->blind_turn || !(vo > 2.0)) return -1.0;
  const double hox = o->x[2] / vo, hoy = o->x[3] / vo, hyx = vx / v, hyy = vy / v;
  const double cr = hox * hyy - hoy * hyx;
  if (fabs(cr) < BLIND_TURN_SIN || hox * hyx + hoy * hyy < -BLIND_TURN_SIN) return -1.0;
  const double sa = (dx * hyy - dy * hyx) / cr, ra = (hox * dy - hoy * dx) / cr;
  if (sa < 0.0 || ra < 0.0 || sa + ra > 0.5 * cf->max_speed * dt + 5.0) return -1.0;
  const double qx = ax + sa * hox, qy = ay + sa * hoy;
  if (min_d(seg_near(ax, ay, qx, qy), seg_near(qx, qy, y->px0, y->py0)) >= rb + BLIND_WAY_M) return -1.0;
  return 1.0 + fabs((sa + ra) / vo - dt);
}

/* blind_walker: young walker's track y is walker o come out of the blind
 * circle under the sensor (a sidewalk beside the pole: a walker's head is
 * below the lowest beam within a few metres, and crossing that takes 5-8 s).
 * o last seen at the circle's edge walking (WBLIND_MIN_V or faster), y born
 * near it, at least 2 m on, both walking along the straight way between them
 * (within 40 degrees), that way passing near the circle, and the time between
 * within WBLIND_TIME_SHARE (+ WBLIND_TIME_S) of the way's length at o's
 * speed, within walker_keep. Returns, the least winning: with blind_walker_fifo,
 * how long before the longest wait (RS_TRACK_WALKER_KEEP_MAX) o went in (of walkers in a line whose
 * times fit, the first in is the first out: their paces at the edge, slowed
 * by the walker ahead, tell less than their order); without it, how far the
 * time is from that; or -1. With blind_walker_line, a walker whose line (its
 * heading through where it was last seen) passes farther than that from
 * where y was born comes after every walker whose line passes nearer: one
 * who walked in along another way (a crossing) and stopped inside, or
 * turned, is not the first choice for one coming out along this one. */
#define WBLIND_MIN_V 0.5      /* m/s */
#define WBLIND_TIME_SHARE 0.3 /* of the time expected */
#define WBLIND_TIME_S 1.0     /* s */
/* blind_walk_link's rank added for a walker off the way's line (blind_walker_line): over every rank on
 * it, which is at most RS_TRACK_WALKER_KEEP_MAX or the time's fit (under it) */
#define WBLIND_OFF_LINE 1000.0
_Static_assert((int)WBLIND_OFF_LINE > RS_TRACK_WALKER_KEEP_MAX, "a rank off the line comes after every rank on it");
/* blind_walker: how long walker's track o, gone in, is kept for the link: blind_walker_s, or the time
 * the circle's width at its top takes at blind_walker_cross when that is longer (at most
 * RS_TRACK_WALKER_KEEP_MAX) */
static double walker_keep(const rs_tracker_t *tr, const rs_track_t *o) {
  const rs_track_cfg_t *cf = &tr->cfg;
  if (!(cf->blind_walker_cross > 0)) return cf->blind_walker_s;
  const double cross = 2.0 * (blind_reach(tr, o) + BLIND_BIRTH_M) / cf->blind_walker_cross;
  return min_d(RS_TRACK_WALKER_KEEP_MAX, max_d(cf->blind_walker_s, cross));
}
/* the part of blind_walk_link that asks of o alone: might walker o, gone in, come out at (px, py) at time
 * t? how far the time is from its way's length at its pace, or -1 */
static double out_fit(const rs_tracker_t *tr, const rs_track_t *o, double px, double py, double t) {
  const double dt = t - o->t_update;
  if (!(dt > 0) || dt > walker_keep(tr, o) || !at_blind_edge(tr, o)) return -1.0;
  const double rb = blind_reach(tr, o);
  if (norm2(px, py) > rb + BLIND_BIRTH_M) return -1.0;
  const double ax = o->last_z[0], ay = o->last_z[1], dx = px - ax, dy = py - ay, d = norm2(dx, dy);
  const double vo = norm2(o->x[2], o->x[3]);
  if (d < 2.0 || !(vo >= WBLIND_MIN_V) || o->x[2] * dx + o->x[3] * dy < BLIND_COS * vo * d) return -1.0;
  if (seg_near(ax, ay, px, py) >= rb + BLIND_WAY_M) return -1.0;
  const double expect = d / vo, off = fabs(dt - expect);
  return off <= WBLIND_TIME_SHARE * expect + WBLIND_TIME_S ? off : -1.0;
}
static double blind_walk_link(const rs_tracker_t *tr, const rs_track_t *o, const rs_track_t *y) {
  if (!walker_full_sized(y)) return -1.0;
  const double dx = y->px0 - o->last_z[0], dy = y->py0 - o->last_z[1], d = norm2(dx, dy);
  const double vy = norm2(y->x[2], y->x[3]);
  if (!(vy >= WBLIND_MIN_V) || y->x[2] * dx + y->x[3] * dy < BLIND_COS * vy * d) return -1.0;
  const double off = out_fit(tr, o, y->px0, y->py0, y->t_birth);
  if (off < 0) return -1.0;
  const double rank = tr->cfg.blind_walker_fifo ? RS_TRACK_WALKER_KEEP_MAX - (y->t_birth - o->t_update) : off;
  /* blind_walker_line: y born off o's line (its heading through where it was last seen) by more than that:
   * after every walker on whose line it came out (the ranks above stay below WBLIND_OFF_LINE) */
  const double h = o->heading;
  return tr->cfg.blind_walker_line > 0 && fabs(dx * sin(h) - dy * cos(h)) > tr->cfg.blind_walker_line ? rank + WBLIND_OFF_LINE
                                                                                                         : rank;
}

/* blind_walker: walker's track t was last seen at the blind circle's edge walking into it (towards the
 * sensor) */
static bool gone_in(const rs_tracker_t *tr, const rs_track_t *t) {
  if (!walker_full_sized(t) || !at_blind_edge(tr, t)) return false;
  const double vx = t->x[2], vy = t->x[3], v = norm2(vx, vy);
  return v >= WBLIND_MIN_V && t->last_z[0] * vx + t->last_z[1] * vy < 0.0;
}
/* ... and z lies before the point of its way (from where it was last seen, along its velocity, which
 * gone_in found non-zero) nearest the sensor */
static bool before_nearest(const rs_track_t *t, const double z[2]) {
  const double vx = t->x[2], vy = t->x[3], v = norm2(vx, vy);
  const double ux = vx / v, uy = vy / v;
  const double s_near = -(t->last_z[0] * ux + t->last_z[1] * uy); /* along the way, from last_z */
  return (z[0] - t->last_z[0]) * ux + (z[1] - t->last_z[1]) * uy < s_near;
}

/* coasting or lost, not held, not taken this frame */
static bool unseen(const rs_track_t *o) {
  return o->id != 0 && o->object < 0 && !rs_track_held(o) && (o->state == RS_TRACK_COASTING || o->state == RS_TRACK_LOST);
}

/* blind_walker_fifo: another walker's track gone in before t, unseen, walking t's way (within 40
 * degrees), might come out at z now (out_fit): then z is not t's to take by the gate (walkers in a
 * line come out in the order they went in; the link gives it to the first) */
static bool earlier_out(const rs_tracker_t *tr, const rs_track_t *t, const double z[2], double tk) {
  const double vt = norm2(t->x[2], t->x[3]);
  for (uint32_t j = 0; j < tr->list.count; j++) {
    const rs_track_t *o = &tr->list.track[j];
    if (o == t || !unseen(o) || !(o->t_update < t->t_update) || !gone_in(tr, o)) continue;
    const double vo = norm2(o->x[2], o->x[3]);
    if (o->x[2] * t->x[2] + o->x[3] * t->x[3] < BLIND_COS * vo * vt) continue;
    if (out_fit(tr, o, z[0], z[1], tk) >= 0) return true;
  }
  return false;
}

/* Below the lowest beam. A point of height z (sensor frame, below the
 * sensor) is returned only from beyond |z| / tan(depression of the lowest
 * beam); an object's top is seen the nearest, from rb. A track of known size
 * whose box, predicted to the object's time, reaches inside rb is seen only
 * outside it: its returns' box is that part's (a car passing a sensor 5.5 m
 * up within 8.6 m shows its ends, or its far half). The part is found on a
 * grid over the track's box at its top (BB_NU x BB_NV points); the
 * measurement is moved by the part's offset from the full box's centre, and
 * its misfit is against the part's extents. false (nothing done) when all of
 * the box is seen or none of it, or when the track was never updated with all
 * of its box beyond rb (one waiting inside from the start has learned the
 * size of its seen part). */
#define BB_NU 17
#define BB_NV 5
#define BB_SD 0.3 /* m added to the update noise: the grid, the smoothed top, a beam's width */
static bool below_beam_view(const rs_tracker_t *tr, const rs_track_t *t, const rs_object_t *o, const double e[4],
                            double *z, double *sd, double *misfit) {
  const double rb = beam_reach(tr, t);
  if (!(rb > 0) || !t->seen_whole) return false; /* a size learned inside rb is the seen part's */
  const double dt = max_d(0.0, rs_object_time(o, t->t_state) - t->t_state);
  const double pcx = t->x[0] + t->x[2] * dt, pcy = t->x[1] + t->x[3] * dt;
  const double len = t->length, wid = t->width, c = t->hcos, s = t->hsin;
  if (near_edge(pcx, pcy, len, wid) > rb) return false; /* all of it beyond rb */
  double umin = INFINITY, umax = -INFINITY, vmin = INFINITY, vmax = -INFINITY;
  int seen = 0;
  for (int i = 0; i < BB_NU; i++)
    for (int j = 0; j < BB_NV; j++) {
      const double u = len * ((double)i / (BB_NU - 1) - 0.5), v = wid * ((double)j / (BB_NV - 1) - 0.5);
      if (norm2(pcx + u * c - v * s, pcy + u * s + v * c) < rb) continue;
      seen++;
      umin = min_d(umin, u);
      umax = max_d(umax, u);
      vmin = min_d(vmin, v);
      vmax = max_d(vmax, v);
    }
  if (seen == 0 || seen == BB_NU * BB_NV) return false;
  const double cu = 0.5 * (umin + umax), cv = 0.5 * (vmin + vmax);
  z[0] -= cu * c - cv * s;
  z[1] -= cu * s + cv * c;
  *misfit = fabs((e[1] - e[0]) - (umax - umin)) + fabs((e[3] - e[2]) - (vmax - vmin));
  *sd += BB_SD;
  return true;
}

/* meas(), as track t sees it: the sensor sees the faces of an object that
 * face it, so a box shorter (narrower) than the track's along its axes is
 * its near part; its centre is moved away from the sensor by half what is
 * missing (at most MAX_SHIFT), on each of the track's axes. Only for
 * tracks whose size is known. Along the track's axis, an end beside
 * something nearer (hidden_end) is where the rest may be: with hidden_anchor,
 * the centre is moved towards that end instead, for any track seen before
 * (the visible end is where the object is; the track's length says how far
 * behind its centre lies). With below_beam, a box partly nearer than the
 * lowest beam reaches is measured by its seen part instead (below_beam_view).
 * *misfit: how far the box's extents are from the track's size (m, both
 * axes; -1 when the size is not known). zs (NULL: not wanted): the speed
 * estimator's measurement, z with the centre moved along the track's axis by
 * what the box misses of its full length instead (speed_full_length). */
static void meas_on(const rs_tracker_t *tr, const rs_track_t *t, const rs_object_t *o, double *z, double *sd, double *misfit,
                    double *sf) {
  meas(tr, o, z, sd);
  *misfit = -1.0;
  *sf = 0.0;
  if (t == NULL || t->hits == 0) return;
  const double c = t->hcos, s = t->hsin;
  double e[4];
  box_on_axes(tr, t, o, e);
  const double ext_u = e[1] - e[0], ext_v = e[3] - e[2];
  const int hidden = tr->cfg.hidden_anchor ? hidden_end(t, o, e) : 0;
  const double miss_u = min_d(MAX_SHIFT, max_d(0.0, 0.5 * ((double)t->length - ext_u)));
  const double pu = z[0] * c + z[1] * s, pv = -z[0] * s + z[1] * c; /* the centre on the track's axes */
  if (!size_known(t)) {
    if (hidden == 0) return;
    const double su = hidden * miss_u;
    z[0] += su * c;
    z[1] += su * s;
    *sd += 0.5 * miss_u;
    return;
  }
  if (tr->cfg.below_beam && hidden == 0 && below_beam_view(tr, t, o, e, z, sd, misfit)) return;
  *misfit = fabs((double)t->length - ext_u) + fabs((double)t->width - ext_v);
  const double miss_v = min_d(MAX_SHIFT, max_d(0.0, 0.5 * ((double)t->width - ext_v)));
  const double su = hidden ? hidden * miss_u : pu >= 0 ? miss_u : -miss_u, sv = pv >= 0 ? miss_v : -miss_v;
  z[0] += su * c - sv * s;
  z[1] += su * s + sv * c;
  *sd += 0.5 * (miss_u + miss_v); /* the move is a guess: less sure the more it moves */
  if (!tr->cfg.speed_full_length || !(t->full_length > t->length)) return;
  const double miss_f = min_d(MAX_SHIFT, max_d(0.0, 0.5 * ((double)t->full_length - ext_u)));
  *sf = (hidden ? hidden * miss_f : pu >= 0 ? miss_f : -miss_f) - su;
}
static void meas_for(const rs_tracker_t *tr, const rs_track_t *t, const rs_object_t *o, double *z, double *sd, double *misfit,
                     double *zs) {
  double sf;
  meas_on(tr, t, o, z, sd, misfit, &sf);
  if (zs == NULL) return;
  zs[0] = z[0] + sf * t->hcos;
  zs[1] = z[1] + sf * t->hsin;
}

/* the axis of track t's whole side views (take: AXIS_*) as the lane's: known once LANE_AXIS_VIEWS of
 * them agree (their mean vector LANE_AXIS_AGREE long or more: one axis, not a turn); (c, s) a unit
 * vector along it, either way; false when not known (kin_dir, still_lane) */
#define LANE_AXIS_VIEWS 3   /* side views before the axis is the lane's */
#define LANE_AXIS_AGREE 0.8 /* their mean vector's length at least (1: all one axis) */
static bool lane_axis(const rs_track_t *t, double *c, double *s) {
  if (t->axis_n < LANE_AXIS_VIEWS || norm2(t->axis_c2, t->axis_s2) < LANE_AXIS_AGREE) return false;
  const double a = 0.5 * atan2(t->axis_s2, t->axis_c2);
  *c = cos(a);
  *s = sin(a);
  return true;
}

/* still_lane: a standing vehicle's track (size known, STILL_LANE_LEN_M long or more, its velocity
 * under STILL_LANE_V) unseen for more than 0.5 s, whose side views give its lane's axis (lane_axis),
 * leaves along that axis if at all: an object farther across it than reacq_across_m plus half its
 * width (plus a tenth of how far along, the axis's error) is another vehicle (the one waiting in the
 * next lane, uncovered in the same frame when a bus passing in front of both has gone: its track
 * took a part of this one's, 3.4 m across, and was ended as its duplicate; docs/tracking.md) */
#define STILL_LANE_LEN_M 2.5
#define STILL_LANE_V 0.5 /* m/s: standing */
static bool off_still_lane(const rs_track_cfg_t *cf, const rs_track_t *t, double dx, double dy, double unseen) {
  if (!cf->still_lane || !(cf->reacq_across_m > 0) || unseen <= 0.5 || !size_known(t) || t->full_length < STILL_LANE_LEN_M)
    return false;
  double c, s;
  if (!lane_axis(t, &c, &s)) return false;
  const double along = dx * c + dy * s, across = fabs(-dx * s + dy * c);
  return across > cf->reacq_across_m + 0.5 * t->width + 0.1 * fabs(along);
}
/* walker_across_m: a walker-sized confirmed track moving at WALK_ACROSS_V or more, unseen for more than
 * 0.5 s, seen again (dx, dy) from its prediction: a walker keeps to its way (a sidewalk, a crossing), so
 * across its heading it is at most walker_across_m plus half its width away, growing by 0.5 m a second
 * unseen; farther is something else (VLP-16 rush at site 25: a walker's track on the far sidewalk,
 * unseen 1.9 s, took a sliver of a car 3.9 m across its way, in the road, then grew with the car's
 * returns into a car's box). The track's heading is its motion's, so a walker who turns while hidden
 * (onto a crossing) comes back across it: that is the rule's risk (docs/tracking.md). */
#define WALK_ACROSS_V 0.5 /* m/s: a walker standing has no way */
static bool off_walk(const rs_track_cfg_t *cf, const rs_track_t *t, double dx, double dy, double unseen) {
  if (!(cf->walker_across_m > 0) || t->state == RS_TRACK_TENTATIVE || unseen <= 0.5 ||
      norm2(t->x[2], t->x[3]) < WALK_ACROSS_V)
    return false;
  const double across = fabs(-dx * t->hsin + dy * t->hcos);
  return across > cf->walker_across_m + 0.5 * t->width + 0.5 * (unseen - 0.5);
}
/* A moving vehicle's track t, unseen for `unseen` s, seen again (dx, dy)
 * from its prediction: it stays in its lane, so across its heading it is at
 * most reacq_across_m plus half its width away, growing by 0.5 m a second
 * unseen; farther is another vehicle (the car in the next lane, 3.5 m over,
 * coming out from behind the same bus). Seen within the last 0.5 s, within
 * SEEN_ACROSS_RANGE_M of the sensor and not turning (its speed estimator's
 * turn rate under SEEN_ACROSS_TURN): at most seen_across_m (a cluster of the
 * next lane's vehicle, or of it and this one together, is not this one). A
 * standing one: off_still_lane */
static bool off_lane(const rs_track_cfg_t *cf, const rs_track_t *t, double dx, double dy, double unseen) {
  if (walker_sized(t)) return off_walk(cf, t, dx, dy, unseen);
  if (!size_known(t)) return false;
  const double v = norm2(t->x[2], t->x[3]);
  if (v <= STILL_LANE_V) return off_still_lane(cf, t, dx, dy, unseen);
  if (v <= 2.0) return false;
  const double across = fabs(-dx * t->hsin + dy * t->hcos);
  if (unseen <= 0.5)
    return cf->seen_across_m > 0 && across > cf->seen_across_m && norm2(t->x[0], t->x[1]) < SEEN_ACROSS_RANGE_M &&
           fabs(rs_track_turn_rate(t)) < SEEN_ACROSS_TURN;
  return cf->reacq_across_m > 0 && across > cf->reacq_across_m + 0.5 * t->width + 0.5 * (unseen - 0.5);
}

/* misfit_own: the speed estimator's update noise when a track's heading is
 * off its box's axis. The misfit (meas_on) is measured on the track's axes,
 * its heading from its motion; a whole view of a vehicle on a heading that is
 * wrong (a velocity learned from boxes merged with a neighbour's, or from a
 * partial view growing) misfits by metres there, and the noise that gives
 * (update_sd) keeps the wrong velocity for seconds: a standing van taken by a
 * track at 16 m/s reported moving for 2 s (VLP-32C rush at site 29). When the
 * box is elongated (its axis known) and its axis is more than OWN_OFF_SIN off
 * the track's heading, the estimator is given the lesser of that misfit and
 * the box's misfit on its own axes (its length and width against the
 * track's). Within that angle nothing changes: a heading a few degrees off
 * inflates the misfit by a few tenths of a metre, which keeps the estimate of
 * a steady vehicle smooth. The filter, its gates and the association keep
 * the misfit on the track's axes; ids move only where still_coast,
 * brake_coast or the class rule read the estimator (t_misfit_own). */
#define OWN_OFF_SIN 0.14 /* sin(8 degrees) */
#define OWN_ASPECT 1.5f  /* a box this many times longer than wide has a known axis */
static bool off_axis(const rs_tracker_t *tr, const rs_track_t *t, const rs_object_t *o) {
  if (!(o->sensor.obb_length >= OWN_ASPECT * o->sensor.obb_width)) return false;
  const double *cs = obj_cs_of(tr, o);
  const double h = o->sensor.obb_heading, oc = cs ? cs[0] : cos(h), os = cs ? cs[1] : sin(h);
  return fabs(t->hcos * os - t->hsin * oc) > OWN_OFF_SIN;
}
static double own_misfit(const rs_track_t *t, const rs_object_t *o) {
  return fabs((double)t->length - o->sensor.obb_length) + fabs((double)t->width - o->sensor.obb_width);
}

/* the noise of an update by an object whose box misses its track's size by
 * misfit (meas_for; sd: meas_for's, used while the size is not known): the
 * box of a whole view is good to a few centimetres, a partial one (a
 * vehicle coming into view, half hidden, split) is not */
static double update_sd(const rs_tracker_t *tr, double sd, double misfit) {
  if (misfit < 0 || tr->cfg.meas_sd_fit <= 0) return sd;
  return tr->cfg.meas_sd_fit + tr->cfg.meas_sd_misfit * misfit;
}

/* The acceleration spectral density of track t on the ground plane (xx, xy,
 * yy): q_long along its motion and q_accel across it when it moves faster
 * than 1 m/s (vehicles speed up and brake along their heading far more than
 * they swerve), q_accel both ways otherwise; q_small both ways for a track
 * of a walker's size after 3 hits. */
static void accel_density(const rs_tracker_t *tr, const rs_track_t *t, double q[3]) {
  const double vx = t->x[2], vy = t->x[3], v2 = vx * vx + vy * vy;
  double ql = tr->cfg.q_long, qc = tr->cfg.q_accel;
  if (t->hits >= 3 && walker_sized(t)) ql = qc = tr->cfg.q_small; /* a walker's size */
  if (v2 < 1.0 || ql == qc) {
    q[0] = q[2] = qc;
    q[1] = 0.0;
    return;
  }
  const double cx = vx * vx / v2, cy = vy * vy / v2, cxy = vx * vy / v2;
  q[0] = ql * cx + qc * cy;
  q[1] = (ql - qc) * cxy;
  q[2] = ql * cy + qc * cx;
}

/* The turn rate (turn_rate): a vehicle's velocity turning at rate w is predicted
 * along a circle (a coordinated turn of known rate): the transition is linear in
 * the state for a given w, so the filter stays a Kalman filter. w is
 * rs_track_turn_rate(); below turn_rate and for a track unseen over
 * OMEGA_UNSEEN_S, the constant-velocity transition. */
#define OMEGA_MAX 1.5     /* rad/s: a car on a 6 m circle at 9 m/s */
#define OMEGA_SPEED 2.0   /* m/s: slower, the direction says little */
#define OMEGA_UNSEEN_S 1.0 /* s: a track unseen longer is predicted straight on (its turn may have ended) */
/* The rate: the speed estimator's constant-acceleration model's acceleration
 * across its velocity over its speed ((v x a) / |v|^2); 0 for walkers (who turn
 * at will), below OMEGA_SPEED and before 3 hits. The estimator's models do not
 * turn, so the rate does not feed on the turn predicted (the Kalman filter's
 * velocity, mostly its own prediction, would: a turn once predicted would go on;
 * a filter of the velocity's direction and its rate was no better). It lags: on a
 * 0.75 rad/s turn it reaches about 0.3 rad/s within a second (check_track
 * t_turn_rate); on the straight before it, it stays under 0.1 rad/s. */
double rs_track_turn_rate(const rs_track_t *t) {
  const rs_track_imm_t *m = &t->imm;
  const double vx = m->x[1][0][1], vy = m->x[1][1][1], ax = m->x[1][0][2], ay = m->x[1][1][2];
  const double v2 = vx * vx + vy * vy;
  if (t->hits < 3 || walker_sized(t) || v2 < OMEGA_SPEED * OMEGA_SPEED) return 0.0;
  return max_d(-OMEGA_MAX, min_d(OMEGA_MAX, (vx * ay - vy * ax) / v2));
}

static double turn_of(const rs_tracker_t *tr, const rs_track_t *t) {
  if (!(tr->cfg.turn_rate > 0) || t->t_state - t->t_update > OMEGA_UNSEEN_S) return 0.0;
  const double w = rs_track_turn_rate(t);
  return fabs(w) < tr->cfg.turn_rate ? 0.0 : w;
}

/* the transition over dt at turn rate w (0: constant velocity): F = [[1, 0, a, -b], [0, 1, b, a],
 * [0, 0, c, -s], [0, 0, s, c]], f = {a, b, c, s} */
static void transition(double dt, double w, double f[4]) {
  double a = dt, b = 0.0, c = 1.0, s = 0.0; /* sin(w dt)/w, (1 - cos(w dt))/w, cos, sin */
  if (w != 0.0) {
    s = sin(w * dt);
    c = cos(w * dt);
    a = s / w;
    b = (1.0 - c) / w;
  }
  f[0] = a;
  f[1] = b;
  f[2] = c;
  f[3] = s;
}

/* the position of track t's state moved by the transition f (transition()) */
static void moved_pos(const rs_track_t *t, const double f[4], double p[2]) {
  p[0] = t->x[0] + f[0] * t->x[2] + -f[1] * t->x[3];
  p[1] = t->x[1] + f[1] * t->x[2] + f[0] * t->x[3];
}

/* track t's transition from its state to time tk (never back: dt at least 0); returns dt */
static double transition_to(const rs_tracker_t *tr, const rs_track_t *t, double tk, double f[4]) {
  const double dt = tk - t->t_state < 0 ? 0.0 : tk - t->t_state;
  transition(dt, turn_of(tr, t), f);
  return dt;
}

/* predicted position of track t at time tk (predict_pos's, without the covariance) */
static void predict_xy(const rs_tracker_t *tr, const rs_track_t *t, double tk, double p[2]) {
  double f[4];
  transition_to(tr, t, tk, f);
  moved_pos(t, f, p);
}

/* predicted position and its covariance (2 x 2) of track t at time tk */
static void predict_pos(const rs_tracker_t *tr, const rs_track_t *t, double tk, double p[2], double S[3]) {
  double f[4];
  const double dt = transition_to(tr, t, tk, f);
  double q[3];
  accel_density(tr, t, q);
  const double d3 = dt * dt * dt / 3.0;
  const double fa = f[0], fb = f[1];
  moved_pos(t, f, p);
  /* S = H F P F' H' + H Q H' (xx, xy, yy) from the rows of F for the position, written out without
   * the zero and unit terms and the one product S does not read (the sums in the order of the full
   * products: the same numbers) */
  const double(*P)[4] = t->P;
  const double fp00 = P[0][0] + fa * P[2][0] + -fb * P[3][0], fp01 = P[0][1] + fa * P[2][1] + -fb * P[3][1];
  const double fp02 = P[0][2] + fa * P[2][2] + -fb * P[3][2], fp03 = P[0][3] + fa * P[2][3] + -fb * P[3][3];
  const double fp11 = P[1][1] + fb * P[2][1] + fa * P[3][1], fp12 = P[1][2] + fb * P[2][2] + fa * P[3][2];
  const double fp13 = P[1][3] + fb * P[2][3] + fa * P[3][3];
  S[0] = fp00 + fp02 * fa + fp03 * -fb + q[0] * d3;
  S[1] = fp01 + fp02 * fb + fp03 * fa + q[1] * d3;
  S[2] = fp11 + fp12 * fb + fp13 * fa + q[2] * d3;
}

/* x, P to time tk (constant velocity, or a turn at the track's rate; full white-noise-acceleration Q) */
static void predict(const rs_tracker_t *tr, rs_track_t *t, double tk) {
  double dt = tk - t->t_state;
  if (dt <= 0) return;
  double q[3];
  accel_density(tr, t, q);
  double f[4];
  transition(dt, turn_of(tr, t), f);
  /* F P F' written out without F's zero and unit terms (the sums in the order of the full products:
   * the same numbers) */
  const double fa = f[0], fb = f[1], fc = f[2], fs = f[3];
  double FP[4][4], P[4][4];
  for (int j = 0; j < 4; j++) {
    FP[0][j] = t->P[0][j] + fa * t->P[2][j] + -fb * t->P[3][j];
    FP[1][j] = t->P[1][j] + fb * t->P[2][j] + fa * t->P[3][j];
    FP[2][j] = fc * t->P[2][j] + -fs * t->P[3][j];
    FP[3][j] = fs * t->P[2][j] + fc * t->P[3][j];
  }
  for (int i = 0; i < 4; i++) {
    P[i][0] = FP[i][0] + FP[i][2] * fa + FP[i][3] * -fb;
    P[i][1] = FP[i][1] + FP[i][2] * fb + FP[i][3] * fa;
    P[i][2] = FP[i][2] * fc + FP[i][3] * -fs;
    P[i][3] = FP[i][2] * fs + FP[i][3] * fc;
  }
  /* Q = [S dt^3/3, S dt^2/2; S dt^2/2, S dt], S the 2 x 2 density */
  const double a = dt * dt * dt / 3.0, b = dt * dt / 2.0, c = dt;
  const int pos[2] = {0, 1}, vel[2] = {2, 3};
  for (int i = 0; i < 2; i++)
    for (int j = 0; j < 2; j++) {
      const double sij = i == j ? q[2 * i] : q[1];
      P[pos[i]][pos[j]] += sij * a;
      P[pos[i]][vel[j]] += sij * b;
      P[vel[i]][pos[j]] += sij * b;
      P[vel[i]][vel[j]] += sij * c;
    }
  for (int i = 0; i < 4; i++)
    for (int j = 0; j < 4; j++) t->P[i][j] = P[i][j];
  const double x[4] = {t->x[0] + fa * t->x[2] + -fb * t->x[3], t->x[1] + fb * t->x[2] + fa * t->x[3],
                       fc * t->x[2] + -fs * t->x[3], fs * t->x[2] + fc * t->x[3]};
  memcpy(t->x, x, sizeof x);
  t->t_state = tk;
}

/* Kalman update with a position measurement z of noise sd */
static void update(rs_track_t *t, const double z[2], double sd) {
  const double r = sd * sd;
  const double s00 = t->P[0][0] + r, s01 = t->P[0][1], s11 = t->P[1][1] + r;
  const double det = s00 * s11 - s01 * s01;
  if (!(det > 0)) return;
  const double i00 = s11 / det, i01 = -s01 / det, i11 = s00 / det;
  double K[4][2];
  for (int i = 0; i < 4; i++) {
    K[i][0] = t->P[i][0] * i00 + t->P[i][1] * i01;
    K[i][1] = t->P[i][0] * i01 + t->P[i][1] * i11;
  }
  const double y0 = z[0] - t->x[0], y1 = z[1] - t->x[1];
  for (int i = 0; i < 4; i++) t->x[i] += K[i][0] * y0 + K[i][1] * y1;
  double P[4][4];
  for (int i = 0; i < 4; i++)
    for (int j = 0; j < 4; j++) P[i][j] = t->P[i][j] - K[i][0] * t->P[0][j] - K[i][1] * t->P[1][j];
  for (int i = 0; i < 4; i++) /* symmetric */
    for (int j = 0; j < i; j++) P[i][j] = P[j][i] = 0.5 * (P[i][j] + P[j][i]);
  for (int i = 0; i < 4; i++)
    for (int j = 0; j < 4; j++) t->P[i][j] = P[i][j];
}

/* ---- the speed estimator (rs_track_imm_t, speed_imm) ----
 * Per axis, CV and CA states in one 3-vector (CV's acceleration 0). A step at
 * a measurement: mix the two states by the probability that the model switched
 * since the last one (at dt / IMM_SWITCH_S), predict each by its model, update
 * each with the measurement and the Kalman filter's noise, weigh the models by
 * their likelihoods; the reported velocity is the weighted mean. Both axes'
 * likelihoods weigh the models together. About 700 flops, one exp and one log:
 * a few hundred nanoseconds a track update. */
#define IMM_SWITCH_S 2.0  /* s, the mean time between switches of model */
#define IMM_ACCEL_SD 2.0  /* m/s^2, the CA model's acceleration uncertainty at start */
#define IMM_RESTART_S 0.5 /* s unseen after which it starts again from the filter's state */
static const int SYM[3][3] = {{0, 1, 2}, {1, 3, 4}, {2, 4, 5}};

/* the speed estimator's velocity along axis a: the models' velocities, weighed */
static double imm_velocity(const rs_track_t *t, int a) { return t->imm.mu[0] * t->imm.x[0][a][1] + t->imm.mu[1] * t->imm.x[1][a][1]; }

/* both models from the Kalman filter's state (acceleration 0, of sd IMM_ACCEL_SD in CA) */
static void imm_start(rs_track_t *t) {
  rs_track_imm_t *m = &t->imm;
  for (int j = 0; j < 2; j++)
    for (int a = 0; a < 2; a++) {
      double *x = m->x[j][a], *P = m->P[j][a];
      x[0] = t->x[a];
      x[1] = t->x[2 + a];
      x[2] = 0.0;
      P[0] = t->P[a][a];
      P[1] = t->P[a][2 + a];
      P[3] = t->P[2 + a][2 + a];
      P[2] = P[4] = 0.0;
      P[5] = j == 1 ? IMM_ACCEL_SD * IMM_ACCEL_SD : 0.0;
    }
  m->mu[0] = 0.9;
  m->mu[1] = 0.1;
  m->t = t->t_state;
}

/* one step with the measurement z (variance r) at time tk; q: the CV model's
 * acceleration density along x and y (the filter's), jerk: the CA model's */
static void imm_step(rs_track_t *t, const double z[2], double r, double tk, const double q[2], double jerk) {
  rs_track_imm_t *m = &t->imm;
  const double dt = tk - m->t;
  if (!(dt >= 0.0) || dt > IMM_RESTART_S) {
    imm_start(t);
    return;
  }
  const double ps = min_d(0.5, dt / IMM_SWITCH_S);
  const double d2 = dt * dt, d3 = d2 * dt;
  double c[2], nis[2] = {0, 0}, det[2] = {1, 1};
  for (int j = 0; j < 2; j++) c[j] = (1.0 - ps) * m->mu[j] + ps * m->mu[1 - j];
  double x0[2][2][3], P0[2][2][3][3];
  for (int j = 0; j < 2; j++) { /* mixing: model j's start from both */
    const double w[2] = {(j == 0 ? 1.0 - ps : ps) * m->mu[0] / c[j], (j == 1 ? 1.0 - ps : ps) * m->mu[1] / c[j]};
    for (int a = 0; a < 2; a++)
      for (int u = 0; u < (j == 0 ? 2 : 3); u++) { /* (CV's prediction reads no acceleration: 0 below) */
        x0[j][a][u] = w[0] * m->x[0][a][u] + w[1] * m->x[1][a][u];
        for (int v = 0; v <= u; v++) {
          double s = 0;
          for (int i = 0; i < 2; i++)
            s += w[i] * (m->P[i][a][SYM[u][v]] + (m->x[i][a][u] - x0[j][a][u]) * (m->x[i][a][v] - x0[j][a][v]));
          P0[j][a][u][v] = P0[j][a][v][u] = s;
        }
      }
  }
  for (int a = 0; a < 2; a++) { /* CV's start: no acceleration (not computed above) */
    x0[0][a][2] = 0.0;
    for (int u = 0; u < 3; u++) P0[0][a][u][2] = P0[0][a][2][u] = 0.0;
  }
  /* the models' transitions: CV [[1, dt, 0], [0, 1, 0], [0, 0, 0]], CA [[1, dt, dt^2/2], [0, 1, dt], [0, 0, 1]];
   * x = F x0, P = F P0 F' + Q written out without their zero and unit terms (the sums in the order of the
   * full products: the same numbers) */
  const double h2 = 0.5 * d2;
  for (int j = 0; j < 2; j++) {
    for (int a = 0; a < 2; a++) {
      const double *x0a = x0[j][a];
      double(*A)[3] = P0[j][a]; /* (read only) */
      double x[3], P[3][3];
      if (j == 0) { /* CV: the acceleration is 0; Q the white-noise acceleration's */
        const double qa = q[a];
        x[0] = x0a[0] + dt * x0a[1];
        x[1] = x0a[1];
        x[2] = 0.0;
        const double fp00 = A[0][0] + dt * A[1][0], fp01 = A[0][1] + dt * A[1][1];
        P[0][0] = qa * d3 / 3 + fp00 + fp01 * dt;
        P[0][1] = qa * d2 / 2 + fp01;
        P[1][1] = qa * dt + A[1][1];
        P[0][2] = P[1][2] = P[2][2] = 0.0;
      } else { /* CA: Q the white-noise jerk's */
        const double d4 = d3 * dt, d5 = d4 * dt;
        x[0] = x0a[0] + dt * x0a[1] + h2 * x0a[2];
        x[1] = x0a[1] + dt * x0a[2];
        x[2] = x0a[2];
        double FP[3][3];
        for (int v = 0; v < 3; v++) {
          FP[0][v] = A[0][v] + dt * A[1][v] + h2 * A[2][v];
          FP[1][v] = A[1][v] + dt * A[2][v];
          FP[2][v] = A[2][v];
        }
        P[0][0] = jerk * (d5 / 20) + FP[0][0] + FP[0][1] * dt + FP[0][2] * h2;
        P[0][1] = jerk * (d4 / 8) + FP[0][1] + FP[0][2] * dt;
        P[0][2] = jerk * (d3 / 6) + FP[0][2];
        P[1][1] = jerk * (d3 / 3) + FP[1][1] + FP[1][2] * dt;
        P[1][2] = jerk * (d2 / 2) + FP[1][2];
        P[2][2] = jerk * dt + FP[2][2];
      }
      const double S = P[0][0] + r, y = z[a] - x[0];
      const double K[3] = {P[0][0] / S, P[0][1] / S, P[0][2] / S};
      for (int u = 0; u < 3; u++) {
        m->x[j][a][u] = x[u] + K[u] * y;
        for (int v = u; v < 3; v++) m->P[j][a][SYM[u][v]] = P[u][v] - K[u] * P[0][v];
      }
      nis[j] += y * y / S;
      det[j] *= S;
    }
  }
  /* mu_j ~ c_j N(y_j; 0, S_j): the ratio CA / CV (bounded, a model never dies out) */
  const double lr = max_d(-30.0, min_d(30.0, -0.5 * (nis[1] - nis[0]) - 0.5 * log(det[1] / det[0])));
  const double ratio = c[1] / c[0] * exp(lr);
  m->mu[1] = min_d(0.999, max_d(0.001, ratio / (1.0 + ratio)));
  m->mu[0] = 1.0 - m->mu[1];
  m->t = tk;
}

static void set_heading(rs_track_t *t, float h) {
  t->heading = h;
  t->hcd = cos((double)h);
  t->hsd = sin((double)h);
  t->hcos = (float)t->hcd;
  t->hsin = (float)t->hsd;
}

/* is (px, py) within half-extents hl along and hw across the axis (c, s) of the rectangle centred at (cx, cy)? */
static bool in_rect(double px, double py, double cx, double cy, double c, double s, double hl, double hw) {
  const double dx = px - cx, dy = py - cy;
  return fabs(dx * c + dy * s) <= hl && fabs(-dx * s + dy * c) <= hw;
}
/* is (px, py) inside object o's oriented box (heading cosine c, sine s) grown by m? */
static bool in_box(const rs_object_t *o, double c, double s, double px, double py, double m) {
  return in_rect(px, py, o->sensor.obb_center[0], o->sensor.obb_center[1], c, s, 0.5 * o->sensor.obb_length + m,
                 0.5 * o->sensor.obb_width + m);
}

/* the size split parts are measured by: a track of known size's full size
 * (split_full_size; never below its smoothed box, take() keeps it so),
 * else its smoothed box */
static void split_size(const rs_tracker_t *tr, const rs_track_t *t, double *len, double *wid) {
  const bool full = tr->cfg.split_full_size && size_known(t);
  *len = full ? t->full_length : t->length;
  *wid = full ? t->full_width : t->width;
}

/* inside track t's box (at its current state, split_size) grown by
 * RS_TRACK_SPLIT_MARGIN (at most half its length) along its length and half
 * that across */
static bool in_track_box(const rs_tracker_t *tr, const rs_track_t *t, double px, double py) {
  double len, wid;
  split_size(tr, t, &len, &wid);
  const double m = min_d(RS_TRACK_SPLIT_MARGIN, 0.5 * len); /* a walker's box is not grown by a stride */
  return in_rect(px, py, t->x[0], t->x[1], t->hcos, t->hsin, 0.5 * len + m, 0.5 * wid + 0.5 * m);
}

/* tracks a and b move alike, as two tracks of one object do: their
 * velocities differ by at most 3 m/s or two standard deviations of the
 * difference (a vehicle passing where a lost track is predicted does not) */
static bool move_alike(const rs_track_t *a, const rs_track_t *b) {
  const double dvx = a->x[2] - b->x[2], dvy = a->x[3] - b->x[3], d2 = dvx * dvx + dvy * dvy;
  return d2 <= 9.0 || d2 <= 4.0 * (a->P[2][2] + a->P[3][3] + b->P[2][2] + b->P[3][3]);
}

/* stitch_alike: were unseen track o and younger track y two objects when o was last seen? y's place
 * then, run back at its velocity from where it is, more than the longer of the two plus
 * STITCH_APART_M from o's last measurement. (A track's velocity uncertainty grows while it is unseen,
 * so after 2 s any vehicle passing where a hidden one stood moves "alike": a car's track, last seen
 * standing at the line, took the car that had been behind it all along.) */
#define STITCH_APART_M 1.0
static bool apart_when_seen(const rs_track_t *o, const rs_track_t *y) {
  const double back = max_d(0.0, y->t_state - o->t_update);
  const double dx = y->x[0] - y->x[2] * back - o->last_z[0], dy = y->x[1] - y->x[3] * back - o->last_z[1];
  return norm2(dx, dy) > max_d(o->length, y->length) + STITCH_APART_M;
}
static bool walker_like(const rs_track_cfg_t *cf, const rs_track_t *t);
/* objects a and b fit together in len x wid, grown by RS_TRACK_SPLIT_MARGIN both ways, on the axes (c, s) */
static bool fits_in(const rs_object_t *a, const rs_object_t *b, double h, double c, double s, double len, double wid) {
  double ea[4], eb[4];
  box_on(a, h, c, s, ea);
  box_on(b, h, c, s, eb);
  return max_d(ea[1], eb[1]) - min_d(ea[0], eb[0]) <= len + RS_TRACK_SPLIT_MARGIN &&
         max_d(ea[3], eb[3]) - min_d(ea[2], eb[2]) <= wid + RS_TRACK_SPLIT_MARGIN;
}
/* objects a (taken by track t this frame) and b fit together in t's known
 * size (split_size) on the axes (c, s): parts of one vehicle */
static bool fits_on(const rs_tracker_t *tr, const rs_track_t *t, const rs_object_t *a, const rs_object_t *b, double h,
                    double c, double s) {
  double len, wid;
  split_size(tr, t, &len, &wid);
  return fits_in(a, b, h, c, s, len, wid);
}
/* split_car_m: a moving vehicle's track never seen as long as a car: a and b fit in a car's length on its
 * axes, and across in its width and the margin or a car's width (a face seen, its heading a little off) */
#define SPLIT_CAR_V 3.0 /* m/s along its heading */
#define SPLIT_CAR_W 1.5 /* m: the least width taken (with the margin, 2.5 m across) */
static bool fits_car(const rs_tracker_t *tr, const rs_track_t *t, const rs_object_t *a, const rs_object_t *b) {
  const rs_track_cfg_t *cf = &tr->cfg;
  if (!(cf->split_car_m > 0) || t->state != RS_TRACK_CONFIRMED || !((double)t->full_length < cf->split_car_m) ||
      walker_sized(t) || walker_like(cf, t) || t->x[2] * t->hcd + t->x[3] * t->hsd < SPLIT_CAR_V)
    return false;
  double len, wid;
  split_size(tr, t, &len, &wid);
  return fits_in(a, b, t->heading, t->hcos, t->hsin, cf->split_car_m - RS_TRACK_SPLIT_MARGIN, max_d(wid, SPLIT_CAR_W));
}

/* on t's axes (a far car's near side and its roof, apart by a row's gap), or
 * on a's own when a is a vehicle's length and 1.8 times as long as wide
 * (split_object_axis: a turning car seen as two parts, its track's heading,
 * the velocity's, behind the turn), or, when t's box reaches within
 * NEAR_CIRCLE_M of the lowest beam's reach, on any axis (split_near_circle,
 * tried every 180 / FIT_AXES degrees: a car turning around the pole is seen
 * as its two ends, or as its far side and an end, and its track's box drifts
 * with the part it follows). A track of known size is a vehicle's (at least
 * 1.5 m long), not a walker's. */
#define NEAR_CIRCLE_M 3.0
#define FIT_AXES 36
static bool fits_with(const rs_tracker_t *tr, const rs_track_t *t, const rs_object_t *a, const rs_object_t *b) {
  if (!size_known(t)) return false;
  if (fits_on(tr, t, a, b, t->heading, t->hcos, t->hsin) || fits_car(tr, t, a, b)) return true;
  const double ha = a->sensor.obb_heading;
  if (tr->cfg.split_object_axis && a->sensor.obb_length >= 2.0f && a->sensor.obb_length >= 1.8f * a->sensor.obb_width &&
      fits_on(tr, t, a, b, ha, cos(ha), sin(ha)))
    return true;
  if (!tr->cfg.split_near_circle || near_edge(t->x[0], t->x[1], t->length, t->width) >= beam_reach(tr, t) + NEAR_CIRCLE_M)
    return false;
  for (int k = 0; k < FIT_AXES; k++) {
    const double h = k * M_PI / FIT_AXES;
    if (fits_on(tr, t, a, b, h, cos(h), sin(h))) return true;
  }
  return false;
}

/* ---- object lookup grid (hash of 4 m cells) ----------------------------- */
static uint32_t bucket(long gx, long gy) {
  return (uint32_t)(((unsigned long)gx * 73856093ul) ^ ((unsigned long)gy * 19349663ul)) & (GRID_BUCKETS - 1);
}

/* ---- track lookup grid: tracks by their position (4 m cells, hashed) ---- */
static void track_grid(rs_tracker_t *tr, double t_frame) {
  for (uint32_t i = 0; i < tr->tgrid_n; i++) tr->tgrid_head[bucket(tr->tcell[i][0], tr->tcell[i][1])] = -1;
  tr->tgrid_n = tr->list.count;
  tr->vmax = 0.0;
  for (uint32_t i = 0; i < tr->list.count; i++) {
    const rs_track_t *t = &tr->list.track[i];
    double dt = t_frame - t->t_state;
    if (dt < 0) dt = 0;
    tr->tpos[i][0] = t->x[0] + t->x[2] * dt;
    tr->tpos[i][1] = t->x[1] + t->x[3] * dt;
    const double v = sqrt(t->x[2] * t->x[2] + t->x[3] * t->x[3]);
    if (v > tr->vmax) tr->vmax = v;
    tr->tcell[i][0] = (long)floor(tr->tpos[i][0] / GRID);
    tr->tcell[i][1] = (long)floor(tr->tpos[i][1] / GRID);
    const uint32_t bk = bucket(tr->tcell[i][0], tr->tcell[i][1]);
    tr->tgrid_next[i] = tr->tgrid_head[bk];
    tr->tgrid_head[bk] = (int32_t)i;
  }
}

/* the tracks whose grid position lies within r (at most 30 m) of (x, y), in
 * index order (so in id order), into tr->near; returns how many */
static uint32_t tracks_near(rs_tracker_t *tr, double x, double y, double r) {
  if (r > 30.0) r = 30.0;
  uint32_t n = 0;
  const long g0x = (long)floor((x - r) / GRID), g1x = (long)floor((x + r) / GRID);
  const long g0y = (long)floor((y - r) / GRID), g1y = (long)floor((y + r) / GRID);
  for (long gx = g0x; gx <= g1x; gx++)
    for (long gy = g0y; gy <= g1y; gy++)
      for (int32_t i = tr->tgrid_head[bucket(gx, gy)], guard = 0; i >= 0 && guard < RS_TRACK_MAX;
           i = tr->tgrid_next[i], guard++) {
        if (tr->tcell[i][0] != gx || tr->tcell[i][1] != gy) continue;
        const double dx = tr->tpos[i][0] - x, dy = tr->tpos[i][1] - y;
        if (dx * dx + dy * dy <= r * r) tr->near[n++] = (uint16_t)i;
      }
  /* index order: insertion sort (n is small) */
  for (uint32_t a = 1; a < n; a++) {
    uint16_t v = tr->near[a];
    uint32_t b = a;
    while (b > 0 && tr->near[b - 1] > v) {
      tr->near[b] = tr->near[b - 1];
      b--;
    }
    tr->near[b] = v;
  }
  return n;
}

/* The objects of the grid cells within r of (x, y) (at most 16 x 16 cells),
 * cell by cell (x outer), each cell's in its bucket's order: for (k =
 * objs_near_first(..); k >= 0; k = objs_near_next(..)). Bounded: RS_OBJ_MAX
 * steps of a bucket's chain a cell. */
typedef struct {
  long g0x, g1x, g0y, g1y, gx, gy;
  int32_t k;
  uint32_t guard;
} objs_near_t;
static int32_t objs_near_next(const rs_tracker_t *tr, objs_near_t *it) {
  for (;;) {
    while (it->k >= 0 && it->guard < RS_OBJ_MAX) {
      const int32_t k = it->k;
      it->k = tr->grid_next[k];
      it->guard++;
      if (tr->obj_cell[k][0] == it->gx && tr->obj_cell[k][1] == it->gy) return k; /* not another cell, same bucket */
    }
    if (++it->gy > it->g1y || it->gy - it->g0y >= 16) {
      it->gy = it->g0y;
      if (++it->gx > it->g1x || it->gx - it->g0x >= 16) return -1;
    }
    it->k = tr->grid_head[bucket(it->gx, it->gy)];
    it->guard = 0;
  }
}
static int32_t objs_near_first(const rs_tracker_t *tr, double x, double y, double r, objs_near_t *it) {
  it->g0x = it->gx = (long)floor((x - r) / GRID);
  it->g1x = (long)floor((x + r) / GRID);
  it->g0y = it->gy = (long)floor((y - r) / GRID);
  it->g1y = (long)floor((y + r) / GRID);
  it->k = tr->grid_head[bucket(it->gx, it->gy)];
  it->guard = 0;
  return objs_near_next(tr, it);
}

/* ---- assignment ------------------------------------------------------------ */
static int cmp_edge(const void *x, const void *y) {
  const rs_track_edge_t *p = x, *q = y;
  if (p->c != q->c) return p->c < q->c ? -1 : 1;
  if (p->t != q->t) return p->t < q->t ? -1 : 1; /* then track, then object */
  return (p->o > q->o) - (p->o < q->o);
}

static uint16_t find(uint16_t *c, uint16_t i) {
  for (int guard = 0; guard < RS_TRACK_MAX + RS_OBJ_MAX && c[i] != i; guard++) {
    c[i] = c[c[i]];
    i = c[i];
  }
  return i;
}

/* one association round over the edges: tracks and objects of each connected
 * group assigned optimally (or greedily when the group is too large) */
static void assign(rs_tracker_t *tr, uint32_t nobj) {
  const rs_track_cfg_t *cf = &tr->cfg;
  const uint32_t nt = tr->list.count, ne = tr->edges;
  if (ne == 0) return;
  uint16_t *c = tr->comp; /* tracks 0..nt-1, objects RS_TRACK_MAX + k */
  for (uint32_t i = 0; i < nt; i++) c[i] = (uint16_t)i;
  for (uint32_t k = 0; k < nobj; k++) c[RS_TRACK_MAX + k] = (uint16_t)(RS_TRACK_MAX + k);
  for (uint32_t e = 0; e < ne; e++) {
    uint16_t a = find(c, tr->edge[e].t), b = find(c, (uint16_t)(RS_TRACK_MAX + tr->edge[e].o));
    if (a != b) c[a > b ? a : b] = a < b ? a : b;
  }
  /* edges grouped by their group's root (a stable counting sort: within a
   * group, edges keep their order, by track and then cost) */
  uint32_t *start = tr->root_start; /* a group's root is its lowest index: a track's, below nt */
  memset(start, 0, sizeof(uint32_t) * (nt + 1));
  for (uint32_t e = 0; e < ne; e++) {
    tr->eroot[e] = find(c, tr->edge[e].t);
    start[tr->eroot[e] + 1]++;
  }
  for (uint32_t r = 0; r < nt; r++) start[r + 1] += start[r];
  for (uint32_t e = 0; e < ne; e++) tr->gedge[start[tr->eroot[e]]++] = tr->edge[e];
  /* start[r] is now the end of group r's edges */
  for (uint32_t e0 = 0, e1; e0 < ne; e0 = e1) {
    const uint16_t root = find(c, tr->gedge[e0].t);
    e1 = start[root];
    int ntg = 0, nog = 0;
    bool greedy = false;
    /* the group's tracks and objects, in order of first appearance */
    for (uint32_t e = e0; e < e1 && !greedy; e++) {
      int a = -1, b = -1;
      for (int i = 0; i < ntg; i++)
        if (tr->gt[i] == tr->gedge[e].t) a = i;
      for (int i = 0; i < nog; i++)
        if (tr->go[i] == tr->gedge[e].o) b = i;
      if (a < 0) {
        if (ntg == RS_TRACK_GROUP_MAX) greedy = true;
        else tr->gt[ntg++] = tr->gedge[e].t;
      }
      if (b < 0 && !greedy) {
        if (nog == RS_TRACK_GROUP_MAX) greedy = true;
        else tr->go[nog++] = tr->gedge[e].o;
      }
    }
    if (greedy) {
      tr->n.greedy_groups++;
      /* cheapest first (ties: track, then object) */
      rs_sort(tr->gedge + e0, e1 - e0, sizeof tr->gedge[0], cmp_edge);
      for (uint32_t e = e0; e < e1; e++) {
        rs_track_t *t = &tr->list.track[tr->gedge[e].t];
        if (t->object >= 0 || tr->taken_by[tr->gedge[e].o] >= 0) continue;
        if (cf->miss_cost > 0 && tr->gedge[e].c > cf->miss_cost) continue; /* as the exact solution would */
        t->object = tr->gedge[e].o;
        tr->taken_by[tr->gedge[e].o] = tr->gedge[e].t;
      }
      continue;
    }
    /* miss_cost: columns nog.. are each track's "no object" (at miss_cost, its own only); rows ntg.. take
     * what the tracks leave, at no cost. Off: as many pairs as the group allows, then the cheapest */
    const bool miss = cf->miss_cost > 0;
    if (ntg == 1 && nog == 1 && (!miss || (double)tr->gedge[e0].c != cf->miss_cost)) {
      /* one track and one object (most groups; one edge, gate() pairs them once): the solver's answer
       * without it, the pair when cheaper than the track's miss (a tie is left to the solver) */
      if (miss && (double)tr->gedge[e0].c > cf->miss_cost) {
        tr->n.miss_left++;
      } else {
        tr->list.track[tr->gedge[e0].t].object = tr->gedge[e0].o;
        tr->taken_by[tr->gedge[e0].o] = tr->gedge[e0].t;
      }
      continue;
    }
    const int n = miss ? ntg + nog : (ntg > nog ? ntg : nog);
    for (int i = 0; i < n; i++)
      for (int j = 0; j < n; j++) tr->cost[i][j] = miss && i >= ntg ? 0.0 : BIG;
    for (int i = 0; miss && i < ntg; i++) tr->cost[i][nog + i] = cf->miss_cost;
    for (uint32_t e = e0; e < e1; e++) {
      int a = 0, b = 0;
      while (tr->gt[a] != tr->gedge[e].t) a++;
      while (tr->go[b] != tr->gedge[e].o) b++;
      tr->cost[a][b] = tr->gedge[e].c;
    }
    int as[RS_TRACK_ASSIGN_MAX], iwork[2 * (RS_TRACK_ASSIGN_MAX + 1)];
    double work[3 * (RS_TRACK_ASSIGN_MAX + 1)];
    unsigned char used[RS_TRACK_ASSIGN_MAX + 1];
    rs_assign_min(&tr->cost[0][0], n, RS_TRACK_ASSIGN_MAX, as, work, iwork, used);
    for (int i = 0; i < ntg; i++) {
      if (as[i] < 0 || as[i] >= nog || tr->cost[i][as[i]] >= BIG) {
        tr->n.miss_left++;
        continue;
      }
      rs_track_t *t = &tr->list.track[tr->gt[i]];
      t->object = tr->go[as[i]];
      tr->taken_by[tr->go[as[i]]] = tr->gt[i];
    }
  }
}

/* Walked. A walker's track whose walker is hidden (behind a queue, a bus)
 * is kept for lost_walker_s and takes what comes where it is predicted: a
 * walker's part of 1.4 m beside a pole grows its box, its shape is no longer
 * a pedestrian's, and the next frame it takes a passing car's cluster and
 * gives the car its id (VLP-16 rush at site 5: a walker's track left at the
 * kerb takes a car passing at 9 m/s, still called a pedestrian). A track that in
 * walked_hits updates looked like a walker (its shape a pedestrian's, a box
 * at most WALKED_LEN_M long and WALKED_WID_M wide or more: a person from any
 * side, not the edge of a car coming into view, which is as thin as 0.04 m)
 * and moved like one (WALKED_V0 to WALKED_V1) takes no object of a
 * vehicle's size from then on, and no young track of a vehicle's size is
 * stitched to it. */
#define WALKED_LEN_M 1.0f
#define WALKED_WID_M 0.1f
#define WALKER_BODY_WID_M 0.2f
#define WALKER_REACQ_POINTS 4u /* walker_reacq_s: "many times its returns" */
#define WALKED_V0 0.5f
#define WALKED_V1 3.0f
static bool walks(const rs_track_t *t) {
  return t->shape_cls == RS_CLASS_PEDESTRIAN && t->speed >= WALKED_V0 && t->speed <= WALKED_V1 &&
         t->length <= WALKED_LEN_M && t->width >= WALKED_WID_M;
}
/* track t has only ever been seen as a walker's body: its full box at most WALKED_LEN_M long and
 * WALKER_BODY_WID_M wide or more (not a sliver of something far), over 10 hits */
static bool walker_body(const rs_track_t *t) {
  return t->hits >= 10 && t->full_length <= WALKED_LEN_M && t->full_width >= WALKER_BODY_WID_M;
}
/* walker_reacq_s: track t, seen only as a walker's body and unseen for `unseen` s, may not take up
 * what is len x wid m and has `points` returns (a vehicle's size, many times its returns) */
static bool walker_reacq(const rs_track_cfg_t *cf, const rs_track_t *t, double unseen, float len, float wid,
                         uint32_t points) {
  return cf->walker_reacq_s > 0 && unseen > cf->walker_reacq_s && walker_body(t) && vehicle_sized(len, wid) &&
         points > WALKER_REACQ_POINTS * t->points;
}
/* track t is a pedestrian by its shape, or has walked like one */
static bool walker_like(const rs_track_cfg_t *cf, const rs_track_t *t) {
  return t->shape_cls == RS_CLASS_PEDESTRIAN || (cf->walked_hits > 0 && t->walked >= (uint16_t)cf->walked_hits);
}

/* walker_part: object k (o, measured at tk) lies in the box of a moving vehicle's track (not a
 * walker's; confirmed or coasting, WALKER_PART_LEN_M long or more, WALKER_PART_V or faster, seen within
 * WALKER_PART_SEEN_S), predicted to tk, its split size grown by WALKER_PART_M each way: a part of that
 * vehicle split off by the beams, not a walker (whose body cannot be inside a moving car). Asked only
 * of gated pairs, answered once a frame per object (obj_part): at most objects x RS_TRACK_MAX tests */
#define WALKER_PART_M 0.5
#define WALKER_PART_LEN_M 3.0f
#define WALKER_PART_V 2.0
#define WALKER_PART_SEEN_S 0.3
#define WALKER_PART_NEAR_M 12.0 /* m: the tracks looked at (a bus's half length, and a frame's move) */
static bool part_of_moving_vehicle(rs_tracker_t *tr, uint32_t k, const rs_object_t *o, double tk) {
  if (tr->obj_part[k] != 0) return tr->obj_part[k] == 2;
  const rs_track_cfg_t *cf = &tr->cfg;
  const double ox = o->sensor.obb_center[0], oy = o->sensor.obb_center[1];
  const uint32_t nn = tracks_near(tr, ox, oy, WALKER_PART_NEAR_M);
  bool part = false;
  for (uint32_t q = 0; q < nn && !part; q++) {
    const rs_track_t *v = &tr->list.track[tr->near[q]];
    if (v->id == 0 || (v->state != RS_TRACK_CONFIRMED && v->state != RS_TRACK_COASTING)) continue;
    if (walker_like(cf, v) || walker_sized(v) || v->full_length < WALKER_PART_LEN_M ||
        tk - v->t_update > WALKER_PART_SEEN_S || norm2(v->x[2], v->x[3]) < WALKER_PART_V)
      continue;
    double p[2], len, wid;
    predict_xy(tr, v, tk, p);
    split_size(tr, v, &len, &wid);
    const double dx = ox - p[0], dy = oy - p[1];
    const double u = dx * v->hcd + dy * v->hsd, w = -dx * v->hsd + dy * v->hcd;
    part = fabs(u) <= 0.5 * len + WALKER_PART_M && fabs(w) <= 0.5 * wid + WALKER_PART_M;
  }
  tr->obj_part[k] = part ? 2 : 1;
  return part;
}

/* tent_claim_m: a tentative walker's track hit in the last frame
 * (TENT_CLAIM_SEEN_S), TENT_CLAIM_HITS times or more, holds the walker-sized
 * objects within TENT_CLAIM_NEAR_M of its prediction: in the confirmed round
 * no track predicted more than tent_claim_m farther from one takes it.
 * Confirmed tracks choose first so that a young track on a piece of a
 * tracked object does not take it; but at site 33 a walker's track that
 * walked on past a walker standing at the kerb (its own lost among the
 * crowd there) took the standing one, 1.2-2.5 m behind its prediction,
 * from the tentative track that had held it within 0.1 m for a second. */
#define TENT_CLAIM_HITS 3
#define TENT_CLAIM_SEEN_S 0.25 /* s: hit in the last frame */
#define TENT_CLAIM_NEAR_M 0.3  /* m */
#define TENT_CLAIM_REACH_M 1.0 /* m: the objects looked at, around the track's last state (a walker's step and the margin) */
/* gated pairs of the tracks selected by `want` and the free objects */
static void gate(rs_tracker_t *tr, const rs_object_list_t *objs, bool confirmed_round) {
  tr->edges = 0;
  const rs_track_cfg_t *cf = &tr->cfg;
  for (uint32_t i = 0; i < tr->list.count; i++) {
    rs_track_t *t = &tr->list.track[i];
    if (rs_track_held(t) || t->object >= 0 || t->blind_kept) continue;
    if ((t->state != RS_TRACK_TENTATIVE) != confirmed_round) continue;
    const double sp = norm2(t->x[2], t->x[3]);
    const double radius = cf->gate_m + sp * 0.15 + MAX_SHIFT;
    struct { uint16_t o; float c; } best[EDGES_PER_TRACK];
    int nb = 0;
    objs_near_t it;
    for (int32_t k = objs_near_first(tr, t->x[0], t->x[1], radius, &it); k >= 0; k = objs_near_next(tr, &it)) {
      const rs_object_t *o = &objs->obj[k];
      if (tr->taken_by[k] >= 0 || tr->shared[k]) continue;
      double z[2], sd, p[2], S[3], misfit;
      meas_for(tr, t, o, z, &sd, &misfit, NULL);
      const double tk = tr->obj_t[k];
      predict_pos(tr, t, tk, p, S);
      const double dx = z[0] - p[0], dy = z[1] - p[1], d = sqrt(dx * dx + dy * dy);
      const double unseen = tk - t->t_update; /* the gate grows while a track is not seen */
      /* tent_claim_m: a walker's object a steady tentative track holds is not a confirmed track's from farther */
      if (confirmed_round && d > (double)tr->tent_d[k] + cf->tent_claim_m) continue;
      if (d > (unseen > 0.5 ? min_d(2.0 * cf->gate_m, cf->gate_m + 0.5 * (unseen - 0.5)) : cf->gate_m)) continue;
      if (off_lane(cf, t, dx, dy, unseen)) continue;
      const double dtu = tk - t->t_z; /* the speed the pairing implies, from the last measurement */
      if (dtu > 0.02 && norm2(z[0] - t->last_z[0], z[1] - t->last_z[1]) / dtu > cf->max_speed) continue;
      const double s00 = S[0] + sd * sd, s01 = S[1], s11 = S[2] + sd * sd, det = s00 * s11 - s01 * s01;
      if (!(det > 0)) continue;
      const double m2 = (dx * dx * s11 - 2 * dx * dy * s01 + dy * dy * s00) / det;
      if (m2 > cf->gate_chi2) continue;
      /* a pedestrian does not turn into a vehicle (one passing where it walked, or was last seen), nor
       * does a track that walked like one, once its box has grown on a part of something else */
      if (walker_like(cf, t) && vehicle_sized(o->sensor.obb_length, o->sensor.obb_width)) continue;
      /* nor is a walker's track, re-acquired, taken up by a vehicle: one seen only as a walker's body
       * (walker_body) does not take a vehicle-sized object of many times its returns after walker_reacq_s
       * unseen (a car coming out of the circle below the lowest beam where a walker went in) */
      if (walker_reacq(cf, t, unseen, o->sensor.obb_length, o->sensor.obb_width, o->points)) continue;
      /* nor a part of a moving vehicle (walker_part): a walker's track, lost among the traffic, took the
       * piece of a passing car or truck split off by the beams, followed it at the vehicle's speed, and
       * counted it */
      if (cf->walker_part && walker_like(cf, t) && part_of_moving_vehicle(tr, (uint32_t)k, o, tk)) continue;
      /* nor, with blind_walker, does a walker's track gone into the blind circle take anything before the
       * point of its way nearest the sensor (a walker coming out towards it the other way) or farther from
       * its prediction than gate_m (its gate grows while unseen; the next walker in a line comes out in it):
       * it comes out by blind_walk_link */
      if (cf->blind_walker && unseen > 0.2 && gone_in(tr, t) && (before_nearest(t, z) || d > cf->gate_m)) continue;
      /* nor, with blind_walker_fifo, anything an earlier one gone in on its way may be coming out as */
      if (cf->blind_walker && cf->blind_walker_fifo && unseen > 0.2 && gone_in(tr, t) && earlier_out(tr, t, z, tk)) continue;
      /* and how unlike the track's last object it is: a track keeps its object, not a fragment beside it */
      /* (beyond what counting noise explains: 3 sd of the smaller count) */
      const double lo = o->points < t->points ? o->points : t->points, hi = o->points < t->points ? t->points : o->points;
      const double ratio = lo > 0 ? hi / lo / (1.0 + 3.0 / sqrt(lo)) : 1.0; /* (one log, none when alike) */
      const double unlike = ratio > 1.0 ? log(ratio) : 0.0;
      const float cost = (float)(m2 + log(det) + cf->size_weight * min_d(unlike, 4.0));
      /* keep the best EDGES_PER_TRACK, by cost then object order */
      int at = nb;
      while (at > 0 && (best[at - 1].c > cost || (best[at - 1].c == cost && best[at - 1].o > k))) at--;
      if (at >= EDGES_PER_TRACK) continue;
      int last = nb < EDGES_PER_TRACK ? nb : EDGES_PER_TRACK - 1;
      for (int m = last; m > at; m--) best[m] = best[m - 1];
      best[at].o = (uint16_t)k;
      best[at].c = cost;
      if (nb < EDGES_PER_TRACK) nb++;
    }
    for (int b = 0; b < nb; b++) {
      tr->edge[tr->edges].t = (uint16_t)i;
      tr->edge[tr->edges].o = best[b].o;
      tr->edge[tr->edges].c = best[b].c;
      tr->edges++;
    }
  }
}

/* The fast confirmation of a still track (confirm_still_spread): hit in
 * every frame, every measurement within confirm_still_spread (plus 0.5 % of
 * the range) of the first, and its object has enough returns. A car has
 * fewer of them the farther it is (about the square of the range), so beyond
 * confirm_still_range the bar falls the same way, never below
 * RS_TRACK_STILL_POINTS_MIN. A fragment of a near car (a part split off by
 * the beams, 12-17 returns at 15 m) still waits like foliage: a walker-sized
 * track needs confirm_walker_points. Such fragments are one row thin (at most
 * 0.12 m of returns on the simulator's captures); a person standing at the
 * kerb is two rows or more (UPRIGHT_M) and, when it stands within
 * UPRIGHT_SPREAD_M of where it was first seen (a bush swaying in the wind
 * wanders farther), needs only confirm_upright_points. */
#define UPRIGHT_SPREAD_M 0.1
/* The still rule's window (confirm_still_window): a still track whose first
 * measurement was off (its first box a partial view, the capture's first and
 * partial frame, a car at 50 m whose first box was 0.4 m beside the rest)
 * never passes the spread from where it was born and waited
 * confirm_still_s. Its last confirm_still_window measurements (take() keeps
 * them and their objects' returns in win_z and win_points, slot hits %
 * RS_TRACK_STILL_WINDOW) within the same spread of the first of them, each
 * object with the returns the rule asks (leaves far off come and go, 3-8
 * returns at 50 m), do instead, once it has more hits than the window (the
 * first window is the rule's own spread), when no other track may claim it
 * (window_clear). A window of 0 or 1 is off (one measurement is still within
 * itself). */
_Static_assert(RS_TRACK_STILL_WINDOW >= 2 && RS_TRACK_STILL_WINDOW <= 8, "the still window: 2 to 8 measurements");
static bool window_still(const rs_track_cfg_t *cf, const rs_track_t *t, uint32_t bar, double spread) {
  const uint32_t n = (uint32_t)cf->confirm_still_window;
  if (n < 2 || t->hits <= n) return false;
  const uint32_t first = (t->hits - n) % RS_TRACK_STILL_WINDOW;
  if (t->win_points[first] < bar) return false;
  for (uint32_t k = 1; k < n; k++) {
    const uint32_t j = (first + k) % RS_TRACK_STILL_WINDOW;
    if (t->win_points[j] < bar ||
        norm2(t->win_z[j][0] - t->win_z[first][0], t->win_z[j][1] - t->win_z[first][1]) > spread)
      return false;
  }
  return true;
}
/* whether no other track may claim tentative track t, index i of the list
 * being compacted in rs_track_frame (those kept so far are at [0, w), those
 * not yet visited after i): no unseen one within gate_m (the stitching takes
 * t as its object seen again, while t is tentative), and no other of which t
 * may be a part (the duplicate rule ends a tentative part inside a confirmed
 * track's box, and a new object split in two is two tentative tracks side by
 * side; queued cars stand farther apart): one whose box comes within
 * WINDOW_GAP_M of t's on its axes (clear_beside; 0: whose centre lies within
 * half their lengths and WINDOW_GAP_M of t's, a car in the next lane too).
 * Not a part's: a tentative one with clear_part_share of t's returns or fewer,
 * or one shorter, as long as it has been seen, than t by CLEAR_LONGER_M
 * (clear_longer). A bounded scan of the list, made only for a track that
 * passed the window. */
#define WINDOW_GAP_M 1.0
#define CLEAR_LONGER_M 0.5 /* m: clear_longer's margin (two halves of one car are about as long) */
/* track t's box within WINDOW_GAP_M of track u's (u's axes, length ul, width uw): t's extents along and
 * across u's axis from both headings (clear_beside) */
static bool beside_box(const rs_track_t *t, const rs_track_t *u, double ul, double uw) {
  const double c = u->hcos, s = u->hsin, dx = t->x[0] - u->x[0], dy = t->x[1] - u->x[1];
  const double ca = fabs((double)t->hcos * c + (double)t->hsin * s), sa = fabs((double)t->hsin * c - (double)t->hcos * s);
  const double tl = t->length * ca + t->width * sa, tw = t->length * sa + t->width * ca;
  return fabs(dx * c + dy * s) < 0.5 * (ul + tl) + WINDOW_GAP_M && fabs(dy * c - dx * s) < 0.5 * (uw + tw) + WINDOW_GAP_M;
}
static bool window_clear(const rs_tracker_t *tr, const rs_track_t *t, uint32_t w, uint32_t i) {
  const rs_track_list_t *L = &tr->list;
  for (uint32_t j = 0; j < L->count; j++) {
    if (j >= w && j <= i) continue;
    const rs_track_t *u = &L->track[j];
    if (u->id == 0) continue;
    const double d = norm2(u->x[0] - t->x[0], u->x[1] - t->x[1]);
    /* unseen this frame (not unseen(): the tracks after i still have last frame's state) */
    const bool gone = u->state != RS_TRACK_TENTATIVE && u->object < 0 && !rs_track_held(u);
    if (gone) {
      if (d < tr->cfg.gate_m) return false;
      continue;
    }
    if (u->state == RS_TRACK_TENTATIVE && (double)u->points <= tr->cfg.clear_part_share * (double)t->points)
      continue; /* a part of t's object (clear_part_share), not t of its */
    const double ul = max_d(u->full_length, u->length);
    if (tr->cfg.clear_longer && t->length > ul + CLEAR_LONGER_M) continue; /* longer than all of it: no piece of it */
    if (!tr->cfg.clear_beside) {
      if (d < 0.5 * (ul + t->length) + WINDOW_GAP_M) return false;
      continue;
    }
    if (beside_box(t, u, ul, max_d(u->full_width, u->width))) return false;
  }
  return true;
}
/* the returns the still rules ask (need within confirm_still_range), at range r: falling with its square
 * beyond, never below RS_TRACK_STILL_POINTS_MIN (nor above need) */
static uint32_t range_bar(const rs_track_cfg_t *cf, int need, double r) {
  const double r0 = cf->confirm_still_range;
  if (!(r0 > 0) || !(r > r0)) return (uint32_t)need;
  return (uint32_t)min_d(max_d(RS_TRACK_STILL_POINTS_MIN, ceil(need * (r0 / r) * (r0 / r))), need);
}
/* track t's n measurements from the still window's slot first on: each within tol of the point at its
 * share of the way from the first of them to the last (evenly in time: one a frame), and each of bar
 * returns or more (bar 0: any) */
static bool at_one_pace(const rs_track_t *t, uint32_t first, uint32_t n, double tol, uint32_t bar) {
  const double *a = t->win_z[first], *b = t->win_z[(first + n - 1) % RS_TRACK_STILL_WINDOW];
  for (uint32_t k = 0; k < n; k++) {
    const uint32_t j = (first + k) % RS_TRACK_STILL_WINDOW;
    const double f = (double)k / (double)(n - 1);
    if (t->win_points[j] < bar ||
        norm2(t->win_z[j][0] - (a[0] + f * (b[0] - a[0])), t->win_z[j][1] - (a[1] + f * (b[1] - a[1]))) > tol)
      return false;
  }
  return true;
}
/* The steady rule (confirm_steady): the fast confirmation of a still
 * object's returns, for one that moves at one pace along one way. A truck
 * setting off from the line at 1.5 m/s, 1000 returns in every frame, moves
 * 0.15 m a frame: not still, and 0.5 s from confirm_move_m (0.8 m). Its last
 * confirm_still_window measurements (the window's ring, as window_still: the
 * first measurement, often a partial view, is not among them once it has
 * more hits than the window) each lie within the still spread of the point
 * at its share of the way from the first of them to the last (evenly
 * spaced: hit in every frame), that way is longer than the spread (a still
 * one is the still rule's), and each object has the returns the still rule
 * asks of a track of its size and range; the standing walker's lower bar
 * (confirm_upright_points) is not taken: a bush swaying in the wind may
 * wander one way for a few frames. Leaves' centres jump about: their steps
 * are not one pace on one way. And, as for the window, no other track may
 * claim it (window_clear). */
static bool window_steady(const rs_track_cfg_t *cf, const rs_track_t *t, uint32_t bar, double spread) {
  const uint32_t n = (uint32_t)cf->confirm_still_window;
  if (!cf->confirm_steady || n < 3 || t->hits <= n) return false;
  const uint32_t first = (t->hits - n) % RS_TRACK_STILL_WINDOW, last = (t->hits - 1) % RS_TRACK_STILL_WINDOW;
  const double *a = t->win_z[first], *b = t->win_z[last];
  if (!(norm2(b[0] - a[0], b[1] - a[1]) > spread)) return false;
  return at_one_pace(t, first, n, spread, bar);
}
/* confirm_pace: a person still walking slowly into the crowd at a kerb
 * (0.2-0.9 m/s) moves more than UPRIGHT_SPREAD_M in its first frames, so the
 * upright rule does not hold it for standing, and too little for the walking
 * rules (confirm_walk_m: 0.3 m); 20-23 m from a VLP-16, with 10-16 returns,
 * it waited confirm_still_s. Its first RS_TRACK_STILL_WINDOW measurements lie
 * along one line at one pace: an upright walker-sized track hit in every
 * frame whose measurements so far (it has no more than that) each lie within
 * UPRIGHT_SPREAD_M of the point at its share of the way from the first to the
 * last, within the still spread of where it was born, needs only
 * confirm_upright_points. Once per track, at that hit: a bush swaying steadily
 * for 0.4 s may pass, but one seen in every frame is confirmed after
 * confirm_still_s anyway; flicker (a miss) never passes (t_walker_pace_confirms_fast). */
static bool first_at_pace(const rs_track_t *t) {
  return t->hits == RS_TRACK_STILL_WINDOW && at_one_pace(t, 0, RS_TRACK_STILL_WINDOW, UPRIGHT_SPREAD_M, 0);
}
static bool still_fast(const rs_tracker_t *tr, const rs_track_t *t, uint32_t w, uint32_t i) {
  const rs_track_cfg_t *cf = &tr->cfg;
  if (t->misses != 0 || !(cf->confirm_still_spread > 0)) return false;
  const double spread = cf->confirm_still_spread + 0.005 * norm2(t->px0, t->py0);
  int need = cf->confirm_still_points;
  const bool walker = walker_sized(t) && t->hits >= (uint32_t)cf->confirm_hits + 1;
  if (walker && cf->confirm_walker_points > 0 && cf->confirm_walker_points < need) need = cf->confirm_walker_points;
  const int moving_need = need;
  if (walker && cf->confirm_upright_points > 0 && cf->confirm_upright_points < need && t->height >= UPRIGHT_M &&
      (t->spread <= min_d(spread, UPRIGHT_SPREAD_M) || (cf->confirm_pace && t->spread <= spread && first_at_pace(t))))
    need = cf->confirm_upright_points;
  const double r = norm2(t->x[0], t->x[1]);
  const uint32_t bar = range_bar(cf, need, r);
  if (t->points >= bar && (t->spread <= spread || (window_still(cf, t, bar, spread) && window_clear(tr, t, w, i))))
    return true;
  const uint32_t steady_bar = range_bar(cf, moving_need, r); /* not the standing walker's */
  return t->points >= steady_bar && window_steady(cf, t, steady_bar, spread) && window_clear(tr, t, w, i);
}

static rs_class_t classify(const rs_track_t *t) {
  const float L = t->length, W = t->width, H = t->height, V = t->max_speed, Hmax = t->height_max;
  if (t->state == RS_TRACK_TENTATIVE) return RS_CLASS_UNKNOWN;
  if (L >= 10.0f) return RS_CLASS_BUS;
  const float Ht = t->top_agl_n > 0 ? max_f(H, t->top_agl) : H; /* the top above the ground: a hidden bottom */
  if (L >= 5.6f || (L >= 4.0f && Ht >= 1.8f)) return RS_CLASS_VAN_TRUCK;
  if (L >= 3.0f && W >= 1.3f) return RS_CLASS_CAR;
  if (L >= 1.2f && V >= 9.0f) return RS_CLASS_CAR;
  if (t->across >= 1.3f && L >= 1.5f && V >= 3.5f) return RS_CLASS_CAR; /* as wide as a car across its motion */
  if (L >= 1.2f && W < 1.2f && V >= 2.0f) return RS_CLASS_CYCLIST;
  if (L < WALKER_M && W < WALKER_M && Hmax >= 0.9f && H <= 2.3f && V < 4.0f) return RS_CLASS_PEDESTRIAN;
  return RS_CLASS_UNKNOWN;
}

/* The class a track reports: the one most of its returns were seen as. Each
 * confirmed update adds its object's returns to the vote of the rule's class
 * for the box at that moment; unknown does not vote. A car seen head-on at
 * range is cyclist-sized for a while and a car once it is near: the near views
 * have the returns. Ties go to the lower class index; no vote yet: the rule's. */
static rs_class_t voted_class(rs_track_t *t, bool updated) {
  if (updated && t->state != RS_TRACK_TENTATIVE && t->shape_cls != RS_CLASS_UNKNOWN)
    t->class_votes[t->shape_cls] += (float)t->points;
  int best = 0;
  for (int c = 1; c < RS_CLASS_COUNT; c++)
    if (t->class_votes[c] > t->class_votes[best]) best = c;
  return t->class_votes[best] > 0.0f ? (rs_class_t)best : t->shape_cls;
}

static float smooth(float cur, float obs, bool first) {
  if (first) return obs;
  return cur + (obs > cur ? 0.5f : 0.05f) * (obs - cur);
}

/* ---- the near side (near_ref_m, near_ref_s) ---------------------------------
 * A vehicle coming into view far off shows its side facing the sensor first;
 * rows reach the rest of it in the frames after, so its box grows away from
 * the sensor and the box's centre moves slower than the vehicle (or the other
 * way). The side facing the sensor moves with it. While a track is younger
 * than near_ref_s (its smoothed size, known after a few updates, still lags
 * the boxes: they keep growing for a second or two), the speed estimator is
 * fed the point of each box farthest towards the sensor along the direction
 * fixed at its birth (on the box's centre line across it); after, the box's
 * centre, its states moved by the offset between the two points of the same
 * box (no jump in speed). Near the sensor the side facing it is where the
 * lowest beam cuts the vehicle: only beyond near_ref_m. Nor where that side
 * may be a hidden end (a box growing there as something nearer moves off
 * it): such a box is measured by its centre, and the next clean one by its
 * near side again. A box lying across the line of sight (its axis over 45
 * degrees off the direction to the sensor: a vehicle coming straight in,
 * first seen as its front face, or a box cut across by a row) has its ends
 * beside the near side, not at it: a hidden end there does not move the near
 * side, which is followed (near_across; before, such boxes were measured by
 * their centres, which moved at half the speed as the rows reached the rest
 * of the vehicle). */
#define NEAR_ACROSS_COS 0.70710678 /* cos 45 degrees */
static void near_side(const rs_track_t *t, const rs_object_t *o, double p[2]) {
  const double c = t->ref_dir[0], s = t->ref_dir[1];
  double e[4];
  box_on(o, atan2(s, c), c, s, e);
  end_point(c, s, e, e[1], p);
}
/* whether the end of object o's box along its own axis that lies towards dir (the sensor) may be
 * hidden (hidden_end_on): the box may grow there as something nearer moves off it. Marked at both
 * ends, or at one of two ends on one line of sight, it may be either. Nearly end-on boxes are told
 * apart however small the angle (with hidden_end's degree of tolerance, those counted as either:
 * measured worse on the held-out sites, docs/tracking.md). With across (near_across), a box lying
 * across dir is never so. */
static bool near_hidden(const rs_object_t *o, const double dir[2], bool across) {
  if ((o->occluded & (RS_OBJ_HIDDEN_START | RS_OBJ_HIDDEN_END)) == 0) return false;
  const double h = o->sensor.obb_heading, c = cos(h), s = sin(h);
  if (across && fabs(c * dir[0] + s * dir[1]) < NEAR_ACROSS_COS) return false; /* its ends are beside the near side */
  double e[4];
  box_on(o, h, c, s, e);
  const int hid = hidden_end_on(c, s, o, e, 0.0);
  return hid == 0 || hid * (c * dir[0] + s * dir[1]) > 0;
}
/* The seen end (end_ref): a vehicle coming out from behind something nearer
 * (a car in the near lane, a queue's gap opening) shows the part beside it
 * first; its box grows at the end marked hidden (rs_object_t.occluded) while
 * the other end moves with the vehicle, and the centre at half its speed or
 * less. While a young track's box has one end marked hidden (along the box's
 * own axis, hidden_end_on) and near_ref_m does not apply, the speed estimator
 * is fed the other end (on the box's centre line), kept as a direction while
 * the next boxes' seen end lies within 60 degrees of it; a box hidden at both
 * ends, or at neither, by its centre. Switching moves the estimator's positions by the
 * offset between the two points of the same box, as for the near side. */
enum { REF_CENTRE, REF_NEAR, REF_END }; /* rs_track_t.ref_mode */
#define END_SAME_COS 0.5 /* a seen end within 60 degrees of the one followed is it */
/* the direction from the centre of object o's box to its end not marked hidden when the other is (along
 * the box's own axis: a young track's heading is not yet known), in d; false when there is none such */
static bool seen_end(const rs_object_t *o, double d[2]) {
  const unsigned f = o->occluded & (RS_OBJ_HIDDEN_START | RS_OBJ_HIDDEN_END);
  if (f == 0 || f == (RS_OBJ_HIDDEN_START | RS_OBJ_HIDDEN_END) || !isfinite(o->sensor.obb_heading)) return false;
  const double h = o->sensor.obb_heading, c = cos(h), s = sin(h);
  double e[4];
  box_on(o, h, c, s, e);
  const int hid = hidden_end_on(c, s, o, e, 0.02); /* (hidden_end's tolerance) */
  d[0] = -hid * c;
  d[1] = -hid * s;
  return hid != 0;
}
/* the point of object o mode names (z: the filter's measurement, the centre's; d: the end's direction:
 * the point of its box farthest along d, on its centre line) */
static void ref_point(const rs_track_t *t, const rs_object_t *o, const double z[2], int mode, const double d[2], double p[2]) {
  if (mode == REF_NEAR) {
    near_side(t, o, p);
  } else if (mode == REF_END) {
    double e[4];
    box_on(o, atan2(d[1], d[0]), d[0], d[1], e);
    end_point(d[0], d[1], e, e[1], p);
  } else {
    p[0] = z[0];
    p[1] = z[1];
  }
}
/* the speed estimator's measurement zi of object o, given the filter's z (at tk): while the track is
 * young, the near side when that is clean, else the seen end when one end is marked hidden, the centre
 * otherwise; switching moves the estimator's positions by the offset between the two points of o's
 * box. Returns whether zi is the same end of the box as at the last update (a box grown at its
 * hidden end is then no jump: uncover_restart) */
static bool ref_meas(const rs_tracker_t *tr, rs_track_t *t, const rs_object_t *o, const double z[2], double tk,
                     bool first, double zi[2]) {
  zi[0] = z[0];
  zi[1] = z[1];
  if (first) {
    const double r = norm2(o->sensor.obb_center[0], o->sensor.obb_center[1]);
    t->ref_mode = REF_CENTRE;
    t->ref_old = false;
    t->ref_dir[0] = t->ref_dir[1] = 0.0;
    if (tr->cfg.near_ref_m > 0 && r > 0) {
      t->ref_dir[0] = -o->sensor.obb_center[0] / r;
      t->ref_dir[1] = -o->sensor.obb_center[1] / r;
    }
  }
  const bool has_dir = t->ref_dir[0] != 0.0 || t->ref_dir[1] != 0.0;
  if (t->ref_old || (!has_dir && !tr->cfg.end_ref)) return false; /* off, or no longer young */
  const bool young = tk - t->t_birth < tr->cfg.near_ref_s && (first || tk - t->imm.t <= IMM_RESTART_S);
  int mode = REF_CENTRE;
  double p[2] = {z[0], z[1]}, d[2] = {0.0, 0.0};
  if (young && has_dir) {
    near_side(t, o, p);
    if (norm2(p[0], p[1]) > tr->cfg.near_ref_m && !near_hidden(o, t->ref_dir, tr->cfg.near_across)) mode = REF_NEAR;
  }
  if (young && mode == REF_CENTRE && tr->cfg.end_ref && seen_end(o, d)) mode = REF_END;
  const int was = t->ref_mode;
  const bool same = mode == was && (mode != REF_END || d[0] * t->ref_end[0] + d[1] * t->ref_end[1] > END_SAME_COS);
  if (same && mode == REF_END) { /* the same end: its direction as first taken (a box's axis wobbles) */
    d[0] = t->ref_end[0];
    d[1] = t->ref_end[1];
  }
  if (mode != REF_CENTRE) ref_point(t, o, z, mode, d, p);
  if (!first && !same) { /* the estimator's positions are the other point's: moved by the offset */
    double q[2];
    ref_point(t, o, z, was, t->ref_end, q);
    for (int j = 0; j < 2; j++)
      for (int a = 0; a < 2; a++) t->imm.x[j][a][0] += mode == REF_CENTRE ? z[a] - q[a] : p[a] - q[a];
  }
  t->ref_mode = (uint8_t)mode;
  t->ref_end[0] = d[0];
  t->ref_end[1] = d[1];
  if (!young) t->ref_old = true;
  if (mode != REF_CENTRE) {
    zi[0] = p[0];
    zi[1] = p[1];
  }
  return !first && mode == REF_END && same;
}

/* ---- out of the circle (circle_whole) -----------------------------------------
 * A car waiting beside the pole pulls away out of the circle inside which
 * the lowest beam passes over its roof. While it comes out, its returns are
 * that beam's arc over the roof (a VLP-16 4.5 m up: 0.02-0.1 m wide, growing
 * along the circle), then the roof's part beyond it: boxes whose centre moves
 * at half the car's speed or less and at 40 degrees to its way. The filter's
 * velocity learned on them is slow and off the car's heading, and the track's
 * axes with it; the first whole box then misfits those axes by metres, and
 * the large update noise that gives makes the velocity catch up over a
 * second or more (VLP-16 light: 3.5 m/s reported for a car at 7). A track born
 * with its box cut by the circle (within WHOLE_CUT_M of it), the first time it
 * moves out (over 1 m/s, away from the sensor: one driving in is not coming
 * out) with a whole vehicle's box (WHOLE_LEN_M by WHOLE_WID_M) whose axis is
 * within WHOLE_MAX of its velocity, takes that axis as its heading: its
 * velocity is turned onto it, its position and velocity are as uncertain as
 * at birth and not correlated (WHOLE_POS_SD, init_speed_sd; set after the
 * prediction, so the jump from the cut box's centre to the whole one's is not
 * taken for speed), and its speed estimator starts again there. Once per
 * track. */
#define WHOLE_LEN_M 3.0f
#define WHOLE_WID_M 1.2f
#define WHOLE_MAX 1.05 /* rad, 60 degrees */
#define WHOLE_POS_SD 2.0 /* m */
#define WHOLE_CUT_M 0.5  /* m: a box's nearest point within the circle grown by this is cut by it */
/* object o's box reaches within the circle the lowest beam passes over its top inside (+ WHOLE_CUT_M) */
static bool circle_cut(const rs_tracker_t *tr, const rs_object_t *o) {
  const double rb = reach_at(tr, o->sensor.box_max[2]);
  if (!(rb > 0)) return false;
  const double h = o->sensor.obb_heading;
  double e[4]; /* the box on its own axes: the sensor's distance to it */
  box_on(o, h, cos(h), sin(h), e);
  return norm2(max_d(0.0, max_d(e[0], -e[1])), max_d(0.0, max_d(e[2], -e[3]))) <= rb + WHOLE_CUT_M;
}
/* circle_whole: track t, born cut by the circle, takes o, the whole box of it moving out: turned onto its axis */
static bool made_whole(const rs_tracker_t *tr, rs_track_t *t, const rs_object_t *o) {
  if (t->hits == 0) t->cut = circle_cut(tr, o); /* born at the circle */
  if (!tr->cfg.circle_whole || !t->cut || t->made_whole || t->hits < 2 || o->sensor.obb_length < WHOLE_LEN_M ||
      o->sensor.obb_width < WHOLE_WID_M)
    return false;
  const double v = norm2(t->x[2], t->x[3]);
  if (!(v > 1.0) || t->x[0] * t->x[2] + t->x[1] * t->x[3] <= 0.0) return false; /* moving out, away from the sensor */
  double c = cos(o->sensor.obb_heading), s = sin(o->sensor.obb_heading), vu = (t->x[2] * c + t->x[3] * s) / v;
  if (vu < 0) c = -c, s = -s, vu = -vu; /* the axis's way the track moves */
  if (vu < cos(WHOLE_MAX)) return false;
  t->made_whole = true;
  t->x[2] = v * vu * c; /* the velocity along the axis */
  t->x[3] = v * vu * s;
  set_heading(t, (float)atan2(s, c));
  return true;
}
/* ... and its position and velocity as uncertain as at its birth, not correlated (after the prediction:
 * the jump from the cut box's centre to the whole one's is no speed) */
static void whole_again(const rs_tracker_t *tr, rs_track_t *t) {
  memset(t->P, 0, sizeof t->P);
  t->P[0][0] = t->P[1][1] = WHOLE_POS_SD * WHOLE_POS_SD;
  t->P[2][2] = t->P[3][3] = tr->cfg.init_speed_sd * tr->cfg.init_speed_sd;
}

/* ---- uncovered (uncover_restart) --------------------------------------------
 * A vehicle standing or moving behind something nearer is first seen in
 * part: a box marked hidden at an end (rs_object_t.occluded: something
 * nearer beside it), its centre where that part is. As the nearer thing moves
 * off, the next box is the whole vehicle, metres longer, its centre metres
 * away: a young track (born with a velocity as uncertain as init_speed_sd)
 * takes that jump for speed (a van standing 43 m off, uncovered in one
 * frame, reported 9.9 m/s and took a second to come down). When a track's
 * second or third object (UNCOVER_HITS) is over UNCOVER_GROW_M longer than
 * its last one and that one was marked hidden, its speed estimator starts
 * again at this object, with the velocity's uncertainty at birth: its next
 * updates learn the speed. It starts at the velocity it had before this
 * object (uncover_restart 2; 1: at 0 m/s, which a track confirmed at that
 * update reported for a car at 10 m/s). Not when the estimator follows the
 * same seen end of the box as at the last update (end_ref): the growth at the
 * hidden end is then no jump. Only the reported velocity: the filter, the
 * gates and the ids are untouched (the filter too: measured worse, in
 * docs/tracking.md). */
#define UNCOVER_HITS 2u
#define UNCOVER_GROW_M 1.0f
static bool uncovered(const rs_tracker_t *tr, rs_track_t *t, const rs_object_t *o) {
  const bool grown = tr->cfg.uncover_restart && t->hits >= 1 && t->hits <= UNCOVER_HITS && t->last_hidden &&
                     o->sensor.obb_length > t->last_len + UNCOVER_GROW_M;
  t->last_hidden = (o->occluded & (RS_OBJ_HIDDEN_START | RS_OBJ_HIDDEN_END)) != 0;
  t->last_len = o->sensor.obb_length;
  return grown;
}

/* The axis of a vehicle's long side, from its objects whose box is as long as AXIS_VIEW_SHARE of its
 * full length (and AXIS_VIEW_M) and AXIS_ASPECT times as long as wide: a whole side, or the face of
 * one seen edge-on. A fitted box's axis is good to a few degrees; a slow vehicle's velocity, from
 * box centres that move as parts of it come and go, is not (on the rush captures 24-33 degrees off
 * at 1.7-2.6 m/s). Averaged as twice the angle (the axis has no sign), weight AXIS_WEIGHT. Read by
 * the kinematic re-acquisition (kin_dir). */
#define AXIS_VIEW_M 2.5f
#define AXIS_VIEW_SHARE 0.8f
#define AXIS_ASPECT 1.8f
#define AXIS_WEIGHT 0.2f

/* ---- braking while unseen (brake_coast) --------------------------------------
 * A vehicle hidden while it brakes (a queue slowing down behind a bus in the
 * near lane, a car stopping at the line behind another) does not go on at its
 * last speed: its prediction overshot it by metres (VLP-32C rush at site 25, a
 * car last reported at 8 m/s stopped while hidden 2.6 s, came back 19 m behind
 * its prediction, and the tracks of a queue taking the car ahead each). At
 * each update a vehicle's track (not of a walker's size, the speed estimator
 * on, moving at BRAKE_MOVING or more, BRAKE_HITS hits) notes how hard it
 * brakes: the estimator's acceleration (the CA model's, by its weight) along
 * the filter's velocity, when that is BRAKE_MIN or more against it (at most
 * BRAKE_MAX), and it is not at the blind circle's edge (a vehicle gone in
 * comes out by the circle's link, on its way: predicted to a stop in the
 * junction, its track took the car following it); while it is unseen (not
 * held) its prediction brakes at that rate, to a stop (the position and the
 * velocity; the covariance grows as before). The state at its last update is
 * kept (x_seen): what reads where it was last seen and how fast (the
 * kinematic re-acquisition) reads that. docs/tracking.md */
#define BRAKE_MOVING 1.0 /* m/s */
#define BRAKE_HITS 5
#define BRAKE_MIN 0.5    /* m/s^2: less is the estimator's noise */
#define BRAKE_MAX 4.0    /* m/s^2: a hard stop */
static void note_brake(const rs_tracker_t *tr, rs_track_t *t) {
  memcpy(t->x_seen, t->x, sizeof t->x_seen);
  t->brake = 0.0f;
  const double v = norm2(t->x[2], t->x[3]);
  if (!tr->cfg.brake_coast || !tr->cfg.speed_imm || walker_sized(t) || t->hits + 1 < BRAKE_HITS || v < BRAKE_MOVING) return;
  const rs_track_imm_t *m = &t->imm;
  const double along = m->mu[1] * (m->x[1][0][2] * t->x[2] + m->x[1][1][2] * t->x[3]) / v;
  if (-along >= BRAKE_MIN && !at_blind_edge(tr, t)) t->brake = (float)min_d(-along, BRAKE_MAX);
}
/* unseen track t, just predicted (constant velocity) from t0 to its t_state: braked instead at
 * t->brake over that step, to a stop */
static void brake_step(rs_track_t *t, double t0) {
  const double dt = t->t_state - t0;
  const double v = norm2(t->x[2], t->x[3]), b = t->brake;
  if (!(b > 0) || !(v > 0) || !(dt > 0)) return;
  const double ux = t->x[2] / v, uy = t->x[3] / v;
  const double go = v <= b * dt ? 0.5 * v * v / b : v * dt - 0.5 * b * dt * dt; /* how far, braking */
  const double v1 = max_d(0.0, v - b * dt), back = v * dt - go;
  t->x[0] -= back * ux;
  t->x[1] -= back * uy;
  t->x[2] = v1 * ux;
  t->x[3] = v1 * uy;
}
/* still_coast: a standing vehicle hidden stays where it stands. A car waiting
 * at the line is seen in views that come and go (a bus passing in front eats
 * one side of its box, then the other), and its filter keeps the velocity
 * their centres wandered at: 0.6-0.9 m/s, across its lane as often as along
 * it, while the speed it reports is 0 (within the estimator's uncertainty).
 * Predicted on at that velocity while hidden, its track drifts, and above
 * STILL_LANE_V the lane rule for standing vehicles does not hold it: it took
 * the car waiting in the next lane, 3.5 m across (VLP-16 rush at the
 * held-out site 33: three cars standing side by side and one behind, their
 * ids passed among five tracks; a truck's track at site 21 drifted 2.5 m
 * across in 2.7 s). So a vehicle's track (size known, STILL_LANE_LEN_M long or more)
 * that has reported no speed at any update for STILL_COAST_S, when it is
 * first unseen (not held), has its velocity set to 0: its prediction stays
 * where it was last seen (the covariance grows as before, so the gate does),
 * and the lane rule for standing vehicles (still_lane, under STILL_LANE_V)
 * applies to it. A car that creeps (1-2 m/s, leaving a queue) reports a speed
 * now and then, within the second: it is predicted on. */
#define STILL_COAST_S 1.0
static bool stands(const rs_tracker_t *tr, const rs_track_t *t) {
  return tr->cfg.still_coast && t->misses == 0 && !rs_track_held(t) && t->speed == 0.0f && size_known(t) &&
         t->full_length >= STILL_LANE_LEN_M && t->t_update - t->t_moving >= STILL_COAST_S;
}
/* still_reverse: a vehicle does not back up in traffic. A car that had driven up to the line and stood
 * there for seconds, seen in part as passing traffic cut its box, had its box's centre step back 0.4 m
 * in two frames; its filter's velocity turned to 0.96 m/s backwards, and hidden the next frame, its track
 * coasted back along its lane, then took the car standing in the next lane, 2.1 m across (VLP-16 rush at
 * the held-out site 33: two cars standing side by side in the north queue passed among nine tracks). So a
 * vehicle's track (size known, STILL_LANE_LEN_M long or more) that has moved faster than 2 m/s, first
 * unseen (not held) with its velocity against the way it last moved so (way_c, way_s: kept apart from
 * the heading, which turns with a velocity over 1 m/s, a cut box's too), is predicted where it was last
 * seen: its velocity set to 0, the speed estimator's too, so that it reports standing (the covariance
 * grows as before), and the lane rule for standing vehicles applies. The way turns with the track's
 * motion over 2 m/s, but back against itself only after WAY_FLIP_UPDATES such updates in a row: a box
 * cut hard gives more than 2 m/s backwards for an update or two (check_track t_still_reverse, 2.2 m/s),
 * and the way it came holds; a track whose first way was wrong (learned from a box growing) turns to
 * the right one within three updates (never turning back: rush IDF1 over the 36 captures 93.43 ->
 * 93.01 %, such tracks held wherever they were hidden). As still_coast, it acts the first time the
 * track goes unseen (misses 0; at every unseen spell: vehicle speed 0.5676 -> 0.5746 m/s). */
#define WAY_FLIP_UPDATES 3 /* updates in a row moving against the way before it turns back */
static bool backs_up(const rs_tracker_t *tr, const rs_track_t *t) {
  return tr->cfg.still_reverse && t->misses == 0 && !rs_track_held(t) && size_known(t) &&
         t->full_length >= STILL_LANE_LEN_M && t->x[2] * t->way_c + t->x[3] * t->way_s < 0.0; /* (0, 0): not moved so */
}
static void stand_still(rs_track_t *t) {
  t->x[2] = t->x[3] = 0.0;
  for (int j = 0; j < 2; j++) /* the speed estimator's models: what it reports, unseen too */
    for (int a = 0; a < 2; a++) t->imm.x[j][a][1] = t->imm.x[j][a][2] = 0.0;
  t->vel[0] = t->vel[1] = 0.0;
  t->speed = 0.0f;
}

/* queue_coast: a hidden vehicle does not drive through the vehicle ahead of it. A van hidden behind the
 * near lane's traffic while it stopped behind a standing car was predicted on at its last speed, 6.2
 * m/s, past where it stood: it came back as a new track and its old one coasted into the standing car
 * (VLP-16 rush at the held-out site 5; a car slowing into a queue at site 33 the same). While a
 * vehicle's track (size known, STILL_LANE_LEN_M long or more, QUEUE_AGE_S old at its last update; not
 * held) is unseen and predicted faster than QUEUE_V, its prediction's front stays QUEUE_GAP_M behind
 * the rear of the nearest vehicle ahead of it in its lane (queue_leaders' list: within QUEUE_ACROSS_M
 * across its way from where it was last seen, its heading within 25 degrees of that way, not driving
 * towards it, QUEUE_GAP_M ahead or more when the hidden one was last seen: nearer is a piece of the
 * same vehicle, a bus seen in two), and its velocity is no faster than that vehicle's along its way.
 * The covariance grows as before. docs/tracking.md */
#define QUEUE_V 1.0      /* m/s: a track slower than this is not moved */
#define QUEUE_AGE_S 1.0  /* s: a younger track's velocity may be its first boxes growing (a part of a standing car) */
#define QUEUE_GAP_M 1.0  /* m kept between its front and the rear of the vehicle ahead */
#define QUEUE_COS 0.9    /* the two headings within 25 degrees: one lane's */
#define QUEUE_ACROSS_M 1.2 /* m between their centres across t's way at most: one lane's */
/* this frame's vehicles a hidden one may stop behind, in tr->lead: the tracks of vehicles (size known,
 * STILL_LANE_LEN_M long or more; not tentative) seen this frame, or standing (QUEUE_V or slower) and
 * unseen for coast_s at most; taken before any track's state moves on, so that no track's place in
 * the list changes what another sees. Hashed by position (QUEUE_CELL_M cells) for follow_leader. */
#define QUEUE_CELL_M 8.0
#define QUEUE_CELLS_MAX 64 /* cells follow_leader looks in; a longer way: every leader */
static void queue_leaders(rs_tracker_t *tr, double t_frame) {
  for (uint32_t j = 0; j < tr->nlead; j++) tr->lead_head[bucket(tr->lead_cell[j][0], tr->lead_cell[j][1])] = -1;
  tr->nlead = 0;
  tr->lead_maxlen = 0.0;
  const rs_track_list_t *L = &tr->list;
  for (uint32_t j = 0; j < L->count && tr->nlead < RS_TRACK_MAX; j++) {
    const rs_track_t *l = &L->track[j];
    if (l->id == 0 || l->state == RS_TRACK_TENTATIVE || !size_known(l) || l->full_length < STILL_LANE_LEN_M) continue;
    const bool seen = l->object >= 0 || rs_track_held(l), standing = norm2(l->x[2], l->x[3]) <= QUEUE_V;
    if (!seen && !(standing && t_frame - l->t_update <= tr->cfg.coast_s)) continue;
    const double dt = max_d(0.0, t_frame - l->t_state);
    const uint32_t n = tr->nlead++;
    tr->lead[n].x = l->x[0] + l->x[2] * dt;
    tr->lead[n].y = l->x[1] + l->x[3] * dt;
    tr->lead[n].vx = l->x[2];
    tr->lead[n].vy = l->x[3];
    tr->lead[n].hc = l->hcd;
    tr->lead[n].hs = l->hsd;
    tr->lead[n].len = l->full_length;
    tr->lead[n].id = l->id;
    tr->lead_maxlen = max_d(tr->lead_maxlen, l->full_length);
    tr->lead_cell[n][0] = (long)floor(tr->lead[n].x / QUEUE_CELL_M);
    tr->lead_cell[n][1] = (long)floor(tr->lead[n].y / QUEUE_CELL_M);
    const uint32_t bk = bucket(tr->lead_cell[n][0], tr->lead_cell[n][1]);
    tr->lead_next[n] = tr->lead_head[bk];
    tr->lead_head[bk] = (int32_t)n;
  }
}
/* leader j for hidden track t (on its way ux, uy from where it was last seen): how far on
 * t may go, into *best (and the leader's speed along the way into *vl) when less than *best */
static void leader_room(const rs_tracker_t *tr, const rs_track_t *t, uint32_t j, double t_frame, double ux, double uy,
                        double *best, double *vl) {
  const double lx = tr->lead[j].x - t->x_seen[0], ly = tr->lead[j].y - t->x_seen[1];
  const double along = lx * ux + ly * uy, across = fabs(-lx * uy + ly * ux);
  if (across >= QUEUE_ACROSS_M || along <= 0.0 || tr->lead[j].id == t->id) return; /* another lane; behind */
  const double lv = tr->lead[j].vx * ux + tr->lead[j].vy * uy; /* its speed along t's way */
  if (fabs(tr->lead[j].hc * ux + tr->lead[j].hs * uy) < QUEUE_COS || (norm2(tr->lead[j].vx, tr->lead[j].vy) > QUEUE_V && lv < 0.0))
    return; /* across t's way; oncoming */
  const double room = along - 0.5 * (t->full_length + tr->lead[j].len) - QUEUE_GAP_M; /* how far on t may go */
  const double gap_seen = room + QUEUE_GAP_M - lv * max_d(0.0, t_frame - t->t_update); /* between them when t was last seen */
  if (gap_seen < QUEUE_GAP_M || room >= *best) return; /* nearer then: parts of one vehicle (a bus seen in two) */
  *best = max_d(0.0, room);
  *vl = max_d(0.0, lv);
}
static void follow_leader(rs_tracker_t *tr, rs_track_t *t, double t_frame) {
  if (tr->nlead == 0 || !size_known(t) || t->full_length < STILL_LANE_LEN_M || t->state == RS_TRACK_TENTATIVE ||
      t->t_update - t->t_birth < QUEUE_AGE_S)
    return;
  const double v = norm2(t->x[2], t->x[3]);
  if (!(v > QUEUE_V)) return;
  const double ux = t->x[2] / v, uy = t->x[3] / v;
  const double at = (t->x[0] - t->x_seen[0]) * ux + (t->x[1] - t->x_seen[1]) * uy; /* how far on since last seen */
  if (!(at > 0.0)) return;
  double best = at, vl = 0.0;
  /* the cells around its way from where it was seen as far as a leader's centre may lie */
  const double reach = at + 0.5 * (t->full_length + tr->lead_maxlen) + QUEUE_GAP_M;
  const double x0 = t->x_seen[0], y0 = t->x_seen[1], x1 = x0 + ux * reach, y1 = y0 + uy * reach;
  const long g0x = (long)floor((min_d(x0, x1) - QUEUE_ACROSS_M) / QUEUE_CELL_M), g1x = (long)floor((max_d(x0, x1) + QUEUE_ACROSS_M) / QUEUE_CELL_M);
  const long g0y = (long)floor((min_d(y0, y1) - QUEUE_ACROSS_M) / QUEUE_CELL_M), g1y = (long)floor((max_d(y0, y1) + QUEUE_ACROSS_M) / QUEUE_CELL_M);
  if ((g1x - g0x + 1) * (g1y - g0y + 1) > QUEUE_CELLS_MAX) {
    for (uint32_t j = 0; j < tr->nlead; j++) leader_room(tr, t, j, t_frame, ux, uy, &best, &vl);
  } else {
    for (long gx = g0x; gx <= g1x; gx++)
      for (long gy = g0y; gy <= g1y; gy++)
        for (int32_t j = tr->lead_head[bucket(gx, gy)], guard = 0; j >= 0 && guard < RS_TRACK_MAX; j = tr->lead_next[j], guard++)
          if (tr->lead_cell[j][0] == gx && tr->lead_cell[j][1] == gy) leader_room(tr, t, (uint32_t)j, t_frame, ux, uy, &best, &vl);
  }
  if (!(best < at)) return;
  t->x[0] -= (at - best) * ux;
  t->x[1] -= (at - best) * uy;
  const double vn = min_d(v, vl);
  t->x[2] = vn * ux;
  t->x[3] = vn * uy;
  t->brake = 0.0f;
  tr->n.queued++;
}

/* ---- a walker's pace into the blind circle (blind_walker_pace_s) ----------------
 * blind_walk_link fits the time a walker gone into the blind circle takes to
 * come out to its pace: the way's length over its speed. Its speed at the
 * edge is one moment's: walkers in file go stop-and-go (the one behind slows
 * when it comes near the one ahead, then walks on), and the filter's velocity
 * follows that, so one gone in just after it slowed was expected out seconds
 * late, later than the time fit allows, and came out as a new track; its
 * prediction lagged it too. A track keeps two anchors, the filter's position
 * at an update and its time: the newer moves on to an update once it is
 * blind_walker_pace_s old, the older taking its place, so the older is
 * blind_walker_pace_s to twice that back. When a walker's track gone into the
 * circle (gone_in, confirmed) is first unseen, and its mean velocity from the
 * older anchor to its last update (spanning PACE_MIN_S or more) is faster than
 * the filter's (moving at PACE_MIN_V or more) and within PACE_MAX_DEG of it,
 * its velocity is scaled up to that speed along its own direction: the link
 * and its prediction go at its pace. Only faster, and not turned: the mean's
 * direction lags a turn at a corner. Its covariance is left as it was.
 * (Every walker's track unseen, not only those gone in: no better,
 * docs/tracking.md.) */
#define PACE_MIN_V 0.5    /* m/s */
#define PACE_MIN_S 1.0    /* s */
#define PACE_MAX_DEG 45.0 /* degrees */
static void pace_note(const rs_tracker_t *tr, rs_track_t *t, double tk, bool first) {
  if (!(tr->cfg.blind_walker_pace_s > 0)) return;
  if (first) {
    for (int k = 0; k < 2; k++) {
      t->pace_t[k] = tk;
      t->pace_p[k][0] = t->x[0];
      t->pace_p[k][1] = t->x[1];
    }
  } else if (tk - t->pace_t[1] >= tr->cfg.blind_walker_pace_s) {
    t->pace_t[0] = t->pace_t[1];
    t->pace_p[0][0] = t->pace_p[1][0];
    t->pace_p[0][1] = t->pace_p[1][1];
    t->pace_t[1] = tk;
    t->pace_p[1][0] = t->x[0];
    t->pace_p[1][1] = t->x[1];
  }
}
/* track t, just unseen (its state still that of its last update): a walker gone into the blind circle
 * walks on at its pace */
static void walk_on_at_pace(const rs_tracker_t *tr, rs_track_t *t) {
  const rs_track_cfg_t *cf = &tr->cfg;
  if (!(cf->blind_walker_pace_s > 0) || !cf->blind_walker || t->state == RS_TRACK_TENTATIVE || !gone_in(tr, t)) return;
  const double span = t->t_update - t->pace_t[0], v = norm2(t->x[2], t->x[3]);
  if (!(span >= PACE_MIN_S) || !(v >= PACE_MIN_V)) return;
  const double mx = (t->x[0] - t->pace_p[0][0]) / span, my = (t->x[1] - t->pace_p[0][1]) / span, m = norm2(mx, my);
  if (!(m > v) || mx * t->x[2] + my * t->x[3] < cos(PACE_MAX_DEG * PI / 180.0) * m * v) return;
  t->x[2] *= m / v;
  t->x[3] *= m / v;
}

/* whether track t's state has been predicted braking since its last update (brake_step) */
static bool braked(const rs_track_t *t) { return t->brake > 0.0f && t->t_state > t->t_update; }

/* track t took object o (measured at tk) */
static void take(rs_tracker_t *tr, rs_track_t *t, const rs_object_t *o, double tk) {
  double z[2], sd, misfit;
  const bool whole = made_whole(tr, t, o); /* on the box's axes: meas_for's misfit is against them */
  bool grown = uncovered(tr, t, o);
  double zs[2]; /* the speed estimator's */
  meas_for(tr, t, o, z, &sd, &misfit, zs);
  t->last_z[0] = z[0];
  t->last_z[1] = z[1];
  t->t_z = tk;
  if (t->hits > 0) t->spread = max_d(t->spread, norm2(z[0] - t->px0, z[1] - t->py0));
  const uint32_t slot = t->hits % RS_TRACK_STILL_WINDOW; /* the still window's ring */
  t->win_z[slot][0] = z[0];
  t->win_z[slot][1] = z[1];
  t->win_points[slot] = o->points;
  predict(tr, t, tk);
  if (whole) whole_again(tr, t);
  const double sdu = update_sd(tr, sd, misfit);
  update(t, z, sdu);
  const double sdi = /* the speed estimator's (misfit_own) */
      tr->cfg.misfit_own && misfit > 0 && off_axis(tr, t, o) ? update_sd(tr, sd, min_d(misfit, own_misfit(t, o))) : sdu;
  const bool first = t->hits == 0;
  double zi[2];
  if (ref_meas(tr, t, o, zs, tk, first, zi)) grown = false; /* grown at the hidden end, the seen one followed */
  const double vprev[2] = {imm_velocity(t, 0), imm_velocity(t, 1)}; /* before this object (uncover_restart 2 keeps it) */
  if (first || whole || grown) {
    imm_start(t);
    for (int j = 0; j < 2; j++)
      for (int a = 0; a < 2; a++) {
        t->imm.x[j][a][0] = zi[a];
        if (first && tr->cfg.imm_birth_wide) /* a vehicle may be born on a short box: its speed as unknown as any */
          t->imm.P[j][a][SYM[1][1]] = max_d(t->imm.P[j][a][SYM[1][1]], tr->cfg.init_speed_sd * tr->cfg.init_speed_sd);
        if (grown && !whole) { /* at its velocity before (or 0 m/s), as uncertain as at birth, not correlated */
          t->imm.x[j][a][1] = tr->cfg.uncover_restart == 2 ? vprev[a] : 0.0;
          t->imm.P[j][a][0] = sdu * sdu;
          t->imm.P[j][a][1] = 0.0;
          t->imm.P[j][a][3] = tr->cfg.init_speed_sd * tr->cfg.init_speed_sd;
        }
      }
  } else {
    double q[3];
    accel_density(tr, t, q);
    imm_step(t, zi, sdi * sdi, tk, (const double[2]){q[0], q[2]}, tr->cfg.q_jerk);
  }
  note_brake(tr, t);
  t->length = smooth(t->length, o->sensor.obb_length, first);
  t->width = smooth(t->width, o->sensor.obb_width, first);
  t->height = smooth(t->height, o->sensor.box_max[2] - o->sensor.box_min[2], first);
  t->height_max = smooth(t->height_max, o->sensor.box_max[2] - o->sensor.box_min[2] + o->height_gap, first);
  if (o->top_agl > 0.0f) {
    t->top_agl = smooth(t->top_agl, o->top_agl, t->top_agl_n == 0);
    t->top_agl_n++;
  }
  t->z_min = first ? o->sensor.box_min[2] : 0.9f * t->z_min + 0.1f * o->sensor.box_min[2];
  if (o->top_gap >= 0.0f && o->top_gap <= RS_TRACK_TOP_GAP) { /* its top is between its returns' and the row above */
    const float top = o->sensor.box_max[2] + 0.5f * o->top_gap;
    t->top = t->top_n == 0 ? top : t->top + 0.2f * (top - t->top);
    t->top_n++;
  }
  t->full_length = max_f(t->length, t->full_length - 0.05f);
  if (o->sensor.obb_length >= max_f(AXIS_VIEW_M, AXIS_VIEW_SHARE * t->full_length) &&
      o->sensor.obb_length >= AXIS_ASPECT * o->sensor.obb_width &&
      isfinite(o->sensor.obb_heading)) { /* a side seen whole: its axis (a NaN would stay in the mean) */
    const float c2 = cosf(2.0f * o->sensor.obb_heading), s2 = sinf(2.0f * o->sensor.obb_heading);
    const float w = t->axis_n == 0 ? 1.0f : AXIS_WEIGHT;
    t->axis_c2 += w * (c2 - t->axis_c2);
    t->axis_s2 += w * (s2 - t->axis_s2);
    if (t->axis_n < UINT16_MAX) t->axis_n++;
  }
  if (!t->seen_whole && near_edge(t->x[0], t->x[1], t->length, t->width) > beam_reach(tr, t)) t->seen_whole = true;
  t->full_width = max_f(t->width, t->full_width - 0.02f);
  t->hits++;
  t->t_update = tk;
  t->points = o->points;
  pace_note(tr, t, tk, first);
  const double sp = norm2(t->x[2], t->x[3]);
  if (sp > 1.0 && t->hits >= 2) {
    set_heading(t, (float)atan2(t->x[3], t->x[2]));
  } else if (first) {
    set_heading(t, o->sensor.obb_heading);
  }
  if (sp > 2.0 && t->hits >= 3) { /* the heading is the motion's: how wide it is across it */
    const bool flip = t->hcos * t->way_c + t->hsin * t->way_s < 0.0f; /* (0, 0) before: no flip */
    t->way_flips = flip ? (uint8_t)(t->way_flips + 1) : 0;
    if (!flip || t->way_flips >= WAY_FLIP_UPDATES) { /* still_reverse: a way turned back holds when it lasts */
      t->way_c = t->hcos;
      t->way_s = t->hsin;
      t->way_flips = 0;
    }
    double e[4];
    box_on_axes(tr, t, o, e);
    t->across = t->across == 0.0f ? (float)(e[3] - e[2]) : t->across + 0.2f * ((float)(e[3] - e[2]) - t->across);
  }
}

/* the velocity and speed track t reports: the speed estimator's for a track
 * not of a walker's size (speed_imm), the filter's otherwise; 0 when still */
static void report_speed(const rs_tracker_t *tr, rs_track_t *t) {
  const bool imm = tr->cfg.speed_imm && !walker_sized(t);
  for (int a = 0; a < 2; a++) t->vel[a] = imm ? imm_velocity(t, a) : t->x[2 + a];
  const double sp = norm2(t->vel[0], t->vel[1]), sdv = sqrt(0.5 * (t->P[2][2] + t->P[3][3]));
  const double floor_v = max_d(tr->cfg.still_speed, min_d(sdv, 1.0)); /* within one sd of 0 (at most 1 m/s) */
  t->speed = (float)(sp < floor_v ? 0.0 : sp);
}

static void end_track(rs_tracker_t *tr, const rs_track_t *t, double t_end) {
  tr->n.ended++;
  if (t->state == RS_TRACK_TENTATIVE) return; /* never confirmed: no event */
  if (tr->list.ended >= RS_TRACK_ENDED_MAX) {
    tr->n.ends_dropped++;
    return;
  }
  rs_track_end_t *e = &tr->list.end[tr->list.ended++];
  e->id = t->id;
  e->cls = t->cls;
  e->confirmed = true;
  e->t_birth = t->t_birth;
  e->t_end = t_end;
  e->distance = t->distance_seen; /* to where it was last seen */
  e->mean_speed = t->speed_n ? t->sum_speed / t->speed_n : 0.0;
  e->max_speed = t->max_speed;
}

/* the returns this frame gave track id `from` carry id `to` (a track ended into another) */
static void relabel(rs_track_list_t *L, uint32_t nobj, uint32_t from, uint32_t to) {
  for (uint32_t k = 0; k < nobj; k++)
    if (L->object_track[k] == from) L->object_track[k] = to;
}

/* track y's object is unseen track oi's (stitching, the blind-circle link):
 * oi takes it over and its id continues; y ends without an event. copy: oi
 * takes y's state (y has seen more, or oi's is seconds old), else a Kalman
 * update of oi's own (its velocity, learned over many frames, is kept) */
static void stitch(rs_tracker_t *tr, const rs_object_list_t *objs, uint32_t nobj, uint32_t oi, rs_track_t *y, bool copy) {
  rs_track_list_t *L = &tr->list;
  rs_track_t *o = &L->track[oi];
  const uint32_t yid = y->id;
  const int32_t k = y->object;
  if (copy) {
    predict(tr, o, y->t_state);
    o->distance += norm2(y->x[0] - o->prev[0], y->x[1] - o->prev[1]);
    memcpy(o->x, y->x, sizeof o->x);
    o->imm = y->imm;
    for (int a = 0; a < 4; a++)
      for (int b = 0; b < 4; b++) o->P[a][b] = y->P[a][b];
    o->t_state = y->t_state;
    o->t_update = y->t_update;
    o->last_z[0] = y->last_z[0];
    o->last_z[1] = y->last_z[1];
    o->t_z = y->t_z;
    o->points = y->points;
    memcpy(o->x_seen, y->x_seen, sizeof o->x_seen);
    o->brake = y->brake;
    o->hits += y->hits;
    if (norm2(o->x[2], o->x[3]) > 1.0) set_heading(o, y->heading);
  } else {
    const double ox = o->x[0], oy = o->x[1];
    take(tr, o, &objs->obj[k], tr->obj_t[k]);
    o->distance += norm2(o->x[0] - ox, o->x[1] - oy);
    o->hits += y->hits - 1;
  }
  for (int c = 0; c < RS_CLASS_COUNT; c++) o->class_votes[c] += y->class_votes[c]; /* what y saw of it */
  o->prev[0] = o->x[0];
  o->prev[1] = o->x[1];
  o->object = k;
  o->state = RS_TRACK_CONFIRMED;
  tr->taken_by[k] = (int32_t)oi;
  relabel(L, nobj, yid, o->id);
  y->object = -1;
  y->id = 0; /* removed below */
}

/* twin_s: the list index of an older track, confirmed or coasting, whose box
 * overlaps track t's at the frame's time by more than TWIN_OVERLAP_M along
 * the older one's heading and across it, both moving at DUP_BOX_V or more,
 * alike; -1 none. Two vehicles' boxes never overlap: the two follow one
 * vehicle (each took a part of it, or one coasts on beside the other) */
static int twin_of(rs_tracker_t *tr, const rs_track_t *t, double t_frame) {
  const rs_track_list_t *L = &tr->list;
  if (t->state != RS_TRACK_CONFIRMED && t->state != RS_TRACK_COASTING) return -1;
  const double vt = norm2(t->x[2], t->x[3]);
  if (vt < DUP_BOX_V || t_frame - t->t_update > TWIN_SEEN_S || norm2(t->x[0], t->x[1]) > TWIN_RANGE_M) return -1;
  const double dtt = max_d(0.0, t_frame - t->t_state);
  const double tx = t->x[0] + t->x[2] * dtt, ty = t->x[1] + t->x[3] * dtt;
  const uint32_t nn = tracks_near(tr, tx, ty, 12.0); /* half a bus each */
  for (uint32_t q = 0; q < nn; q++) {
    const uint32_t j = tr->near[q];
    const rs_track_t *o = &L->track[j];
    if (o == t || o->id == 0 || o->id > t->id) continue;
    if ((o->state != RS_TRACK_CONFIRMED && o->state != RS_TRACK_COASTING) || t_frame - o->t_update > TWIN_SEEN_S) continue;
    const double vo = norm2(o->x[2], o->x[3]);
    if (vo < DUP_BOX_V || norm2(o->x[2] - t->x[2], o->x[3] - t->x[3]) > TWIN_DV ||
        o->x[2] * t->x[2] + o->x[3] * t->x[3] < TWIN_COS * vo * vt)
      continue;
    const double dto = max_d(0.0, t_frame - o->t_state);
    const double dx = tx - (o->x[0] + o->x[2] * dto), dy = ty - (o->x[1] + o->x[3] * dto);
    const double u = fabs(dx * o->hcos + dy * o->hsin), v = fabs(-dx * o->hsin + dy * o->hcos);
    if (u < 0.5 * (o->length + t->length) - TWIN_OVERLAP_M && v < 0.5 * max_d(o->width, t->width))
      return (int)j;
  }
  return -1;
}

/* twin_s: track y follows the same vehicle as the older track oi; y ends
 * without an event and oi goes on: with y's object and state when oi is
 * unseen this frame, else y's object's returns carry oi's id. False (y kept
 * this frame) when y shares a cluster oi is not held in */
static bool end_twin(rs_tracker_t *tr, const rs_object_list_t *objs, uint32_t nobj, uint32_t oi, rs_track_t *y) {
  rs_track_list_t *L = &tr->list;
  rs_track_t *o = &L->track[oi];
  if (rs_track_held(y) && o->held_object != y->held_object) return false;
  if (y->object >= 0 && o->object < 0 && !rs_track_held(o)) {
    stitch(tr, objs, nobj, oi, y, true);
    return true;
  }
  relabel(L, nobj, y->id, o->id);
  if (rs_track_held(y) && L->object_track[y->held_object] == 0) L->object_track[y->held_object] = o->id;
  y->object = -1;
  y->id = 0;
  return true;
}

/* ---- kinematic re-acquisition (kin_accel) ----
 * A vehicle hidden for a second or more in slow traffic (behind a bus in the
 * near lane, in a queue pulling away at a green light) does not go on at the
 * speed it was last seen at. Its track's velocity lags one speeding up (the
 * box grows as it pulls away), and it goes on speeding up while hidden: it
 * comes back metres ahead of its prediction, out of the gate, as a new track.
 * A young track is that vehicle when:
 * - it has KIN_HITS hits (its direction known), is still tentative (a
 *   confirmed one is an object of its own to the counter and the outputs),
 *   was born after the vehicle's track was last seen, is no larger than that
 *   track's full size plus a metre and does not move against it;
 * - it lies in the vehicle's lane: across the lane's direction (kin_dir: the
 *   axis of the vehicle's side views, its heading when those are not known)
 *   within reacq_across_m, half its width and KIN_LANE_M;
 * - along the lane, between the prediction and where the vehicle would be
 *   had it sped up at kin_accel since it was last seen, each end widened by
 *   KIN_MARGIN_M and a quarter of its full length (the young box may be a
 *   part). Not behind the prediction: a young track there is as often the
 *   next vehicle in the lane as this one slowed down (on the rush captures,
 *   four of five such were the next one); but a long vehicle's (KIN_LONG_M)
 *   rear part, within its full length placed where it may be had it braked
 *   (kin_rear), is (a bus seen again by its rear after passing the pole).
 * The vehicle's track: moving at KIN_MOVING or more when last seen (a
 * standing one's axis may point either way; on the rush captures such a
 * car's track took a walker passing beside it), unseen for KIN_MIN_S or more.
 * Only for young tracks the ordinary stitching and the blind-circle link gave
 * to none; of several vehicles, the one whose prediction is nearest. */
#define KIN_MIN_S 1.0    /* s unseen */
#define KIN_HITS 3       /* the young track's hits (its direction known) */
#define KIN_MARGIN_M 1.0 /* m, each end */
#define KIN_LANE_M 0.5   /* m, across, beyond reacq_across_m and half the width */
#define KIN_LEN_M 2.5    /* m: the full length of a vehicle's track */
#define KIN_MOVING 1.0   /* m/s along its heading when last seen */
#define KIN_LONG_M 8.0   /* m: a bus's or a truck's full length (kin_rear) */
#define KIN_BRAKE 4.0    /* m/s^2: the hardest it may have braked (kin_rear) */
#define KIN_AXIS_DEG 45.0    /* its axis within this of its heading */
static bool kin_vehicle(const rs_track_cfg_t *cf, const rs_track_t *t) {
  return cf->kin_accel > 0 && t->state != RS_TRACK_TENTATIVE && size_known(t) && t->full_length >= KIN_LEN_M &&
         t->shape_cls != RS_CLASS_PEDESTRIAN && !walker_like(cf, t);
}
/* the direction vehicle track o's lane runs in (unit vector, the way it goes): its side's axis
 * (lane_axis) when known, and within KIN_AXIS_DEG of its heading; its heading otherwise */
static void kin_dir(const rs_track_t *o, double *c, double *s) {
  *c = o->hcd;
  *s = o->hsd;
  double ca, sa;
  if (!lane_axis(o, &ca, &sa)) return;
  if (ca * *c + sa * *s < 0) ca = -ca, sa = -sa;
  if (ca * *c + sa * *s < cos(KIN_AXIS_DEG * PI / 180.0)) return;
  *c = ca;
  *s = sa;
}
/* behind the prediction (off < 0 along the lane, off from it), is young track y's box within the
 * full length of long vehicle o (KIN_MARGIN_M each end) placed somewhere between where it would be
 * had it braked at KIN_BRAKE since it was last seen (at v, dt ago) and `ahead` of the prediction?
 * A bus seen again by its rear after passing behind something is its rear part; a car following it,
 * seen whole, reaches out of the bus's box */
static bool kin_rear(const rs_track_t *o, const rs_track_t *y, double off, double v, double dt, double ahead) {
  const double braked_m = min_d(v * dt, 0.5 * KIN_BRAKE * dt * dt), half = 0.5 * o->full_length + KIN_MARGIN_M;
  const double front = off + 0.5 * y->length, rear = off - 0.5 * y->length;
  return max_d(-braked_m, front - half) <= min_d(ahead, rear + half);
}
/* how far young track y lies from unseen vehicle track o's prediction along o's lane (kin_dir)
 * when it lies where o may be (the bounds above), -1 when it does not */
static double kin_fit(const rs_tracker_t *tr, const rs_track_t *o, const rs_track_t *y) {
  const rs_track_cfg_t *cf = &tr->cfg;
  const double dt = y->t_state - o->t_update;
  if (dt < KIN_MIN_S || y->hits < KIN_HITS || y->t_birth <= o->t_update || !kin_vehicle(cf, o)) return -1.0;
  if (y->length > o->full_length + 1.0f || y->width > o->full_width + 1.0f) return -1.0;
  /* where o was last seen: its state is predicted straight on from there while unseen, or braking
   * (brake_coast: then its state when last updated) */
  const double back = o->t_state - o->t_update;
  const bool b = braked(o);
  const double lx = b ? o->x_seen[0] : o->x[0] - o->x[2] * back;
  const double ly = b ? o->x_seen[1] : o->x[1] - o->x[3] * back;
  double c, s;
  kin_dir(o, &c, &s);
  const double dx = y->x[0] - lx, dy = y->x[1] - ly;
  const double along = dx * c + dy * s, across = -dx * s + dy * c;
  if (fabs(across) > cf->reacq_across_m + 0.5 * o->width + KIN_LANE_M) return -1.0;
  const double *vs = b ? &o->x_seen[2] : &o->x[2];
  const double v = vs[0] * c + vs[1] * s; /* its speed along the lane when last seen */
  if (v < KIN_MOVING) return -1.0;
  const double ahead = 0.5 * cf->kin_accel * dt * dt, m = KIN_MARGIN_M + 0.25 * o->full_length;
  const double off = along - v * dt; /* from the prediction */
  if (off > ahead + m) return -1.0;
  if (off < -m) { /* behind: only a long vehicle's rear part, it having braked (kin_rear) */
    if (o->full_length < KIN_LONG_M || !kin_rear(o, y, off, v, dt, ahead)) return -1.0;
  }
  if (y->x[2] * c + y->x[3] * s < -1.0) return -1.0; /* coming the other way */
  return fabs(off);
}

/* stitch_kin: could the vehicle of unseen track o, last seen (x_seen) moving v0 along its lane (kin_dir),
 * have come to young track y's position moving y's v1 along it, in the time between, speeding up at
 * most FEAS_UP and braking at most FEAS_DN, never backwards? Each speed is given FEAS_V of slack (y's
 * also 2 sd of its velocity) and the distance FEAS_M (boxes seen in part). The least distance is that
 * of braking first, then speeding up (or standing between), from the lowest speeds; the most, of
 * speeding up first, then braking, from the highest. Only for y hit in every frame since its birth,
 * FEAS_HITS times or more (a younger track's velocity is a growing box's; one that missed may have
 * followed something else before), and o a vehicle's track of known size (kin_vehicle) */
#define FEAS_UP 3.0  /* m/s^2 */
#define FEAS_DN 8.0  /* m/s^2 */
#define FEAS_V 1.0   /* m/s */
#define FEAS_M 3.0   /* m */
#define FEAS_HITS 5
static bool stitch_feasible(const rs_tracker_t *tr, const rs_track_t *o, const rs_track_t *y) {
  const double dt = y->t_state - o->t_update;
  if (!tr->cfg.stitch_kin || y->hits < FEAS_HITS || y->misses != 0 || !(dt > 0) || !kin_vehicle(&tr->cfg, o) ||
      walker_sized(y))
    return true;
  double c, s;
  kin_dir(o, &c, &s);
  const double v0 = o->x_seen[2] * c + o->x_seen[3] * s, v1 = y->x[2] * c + y->x[3] * s;
  const double d = (y->x[0] - o->x_seen[0]) * c + (y->x[1] - o->x_seen[1]) * s;
  const double sv = FEAS_V + 2.0 * sqrt(0.5 * (y->P[2][2] + y->P[3][3]));
  double a0 = max_d(0.0, v0 - FEAS_V), b0 = max_d(0.0, v0 + FEAS_V);
  double a1 = max_d(0.0, v1 - sv), b1 = max_d(0.0, v1 + sv);
  if (a1 > b0 + FEAS_UP * dt || a0 - FEAS_DN * dt > b1) return false; /* its speed could not have changed so */
  /* the speeds within reach of each other in dt (each pair's path then fits in dt) */
  a0 = max_d(a0, a1 - FEAS_UP * dt);
  a1 = max_d(a1, a0 - FEAS_DN * dt);
  b0 = min_d(b0, b1 + FEAS_DN * dt);
  b1 = min_d(b1, b0 + FEAS_UP * dt);
  const double t1 = (a0 + FEAS_UP * dt - a1) / (FEAS_DN + FEAS_UP), vm = a0 - FEAS_DN * t1;
  const double dmin = vm >= 0.0 ? 0.5 * (a0 + vm) * t1 + 0.5 * (vm + a1) * (dt - t1)
                                : a0 * a0 / (2.0 * FEAS_DN) + a1 * a1 / (2.0 * FEAS_UP);
  const double t2 = (b1 - b0 + FEAS_DN * dt) / (FEAS_UP + FEAS_DN), vx = b0 + FEAS_UP * t2;
  const double dmax = 0.5 * (b0 + vx) * t2 + 0.5 * (vx + b1) * (dt - t2);
  return d >= dmin - FEAS_M && d <= dmax + FEAS_M;
}

/* Of the candidates tr->near[q0..n) (list indices) still unseen (a link made earlier in the same pass
 * takes one up) and other than track i (y), the one whose fit to y is least (fit: a distance, < 0
 * when it does not fit; the first in index order of equals); -1 none. *nfit (unless NULL): how many fit
 * (blind_walker_alone). The blind-circle link and the kinematic re-acquisition */
typedef double (*link_fit_t)(const rs_tracker_t *tr, const rs_track_t *o, const rs_track_t *y);
static int nearest_unseen(const rs_tracker_t *tr, uint32_t i, uint32_t q0, uint32_t n, link_fit_t fit, uint32_t *nfit) {
  const rs_track_t *y = &tr->list.track[i];
  int best = -1;
  double best_fit = INFINITY;
  uint32_t fits = 0;
  for (uint32_t q = q0; q < n; q++) {
    const uint32_t j = tr->near[q];
    const rs_track_t *o = &tr->list.track[j];
    if (j == i || !unseen(o)) continue;
    const double f = fit(tr, o, y);
    fits += f >= 0;
    if (f >= 0 && f < best_fit) {
      best_fit = f;
      best = (int)j;
    }
  }
  if (nfit) *nfit = fits;
  return best;
}

/* merge_front_m: part b stands beside object a (its centre within a's
 * length), on the sensor's side of it and more than `gap` out from its near
 * face. The sensor sees a vehicle's near side and ends and its roof, never
 * through it: nothing of the vehicle lies nearer than a face of it (a walker
 * on the kerb between a truck passing the pole and the sensor does). On a's
 * own axes when it is long and thin (FRONT_AXIS_*: a side, whose face the
 * returns give, when the track's heading may be off), else on track t's (a
 * box near square has no axis of its own: a truck's cab 60 m off, 2.3 x 1.7
 * m, its front corner ahead). A part beyond a's ends (the rest of a bus's
 * side, a face) is not judged. */
#define FRONT_AXIS_LEN_M 2.0 /* m */
#define FRONT_AXIS_RATIO 2.0 /* length over width */
static bool in_front(double gap, const rs_track_t *t, const rs_object_t *a, const rs_object_t *b) {
  if (!(gap > 0)) return false;
  const bool own = a->sensor.obb_length >= FRONT_AXIS_LEN_M && a->sensor.obb_length >= FRONT_AXIS_RATIO * a->sensor.obb_width;
  const double h = own ? a->sensor.obb_heading : t->heading, c = own ? cos(h) : t->hcos, s = own ? sin(h) : t->hsin;
  double ea[4], eb[4];
  box_on(a, h, c, s, ea);
  box_on(b, h, c, s, eb);
  const double u = 0.5 * (eb[0] + eb[1]);
  if (u < ea[0] || u > ea[1]) return false;
  if (ea[2] > 0) return eb[3] < ea[2] - gap; /* the sensor (u = v = 0) below a's band across */
  if (ea[3] < 0) return eb[2] > ea[3] + gap; /* above it */
  return false;                              /* within it: a lies ahead of or behind the sensor */
}

/* merge_parts: track i (t, of a long vehicle) took object o; the free thin
 * parts that fit with it in t's size on t's axes (fits_on, each tried against
 * the box grown so far) and lie in no other confirmed or coasting track's
 * predicted box (within half its length and 1 m of its predicted centre) are
 * taken too, and *m is the box of them all on t's axes (no end marked
 * hidden: the ends inside it hid each other). A bus 80 m off at a grazing
 * angle comes as its front face and pieces of its side; following one
 * piece, its track's box slid back along it and the face became a track of
 * its own. Bounded as objs_near_first. Returns whether any part was
 * taken. */
static bool merge_parts(rs_tracker_t *tr, uint32_t i, const rs_object_list_t *objs, const rs_object_t *o, rs_object_t *m) {
  rs_track_list_t *L = &tr->list;
  const rs_track_t *t = &L->track[i];
  if (!tr->cfg.merge_parts || !size_known(t) || t->full_length < RS_TRACK_MERGE_LEN_M) return false;
  bool any = false;
  *m = *o;
  const double r = t->full_length + RS_TRACK_SPLIT_MARGIN; /* a part's centre, from the object's: within the length */
  objs_near_t it;
  for (int32_t k = objs_near_first(tr, o->sensor.obb_center[0], o->sensor.obb_center[1], r, &it); k >= 0;
       k = objs_near_next(tr, &it)) {
    const rs_object_t *b = &objs->obj[k];
    if (k == t->object || tr->taken_by[k] >= 0 || tr->shared[k] || b->points == 0) continue;
    if (b->sensor.obb_width > RS_TRACK_MERGE_PART_WID_M || !fits_on(tr, t, m, b, t->heading, t->hcos, t->hsin)) continue;
    if (in_front(tr->cfg.merge_front_m, t, o, b)) continue;
    const double bx = b->sensor.obb_center[0], by = b->sensor.obb_center[1];
    const uint32_t nn = tracks_near(tr, bx, by, 10.0);
    bool other = false;
    for (uint32_t q = 0; q < nn && !other; q++) {
      const rs_track_t *u = &L->track[tr->near[q]];
      if (u == t || u->state == RS_TRACK_TENTATIVE || u->state == RS_TRACK_LOST) continue;
      double p[2];
      predict_xy(tr, u, tr->obj_t[k], p);
      other = norm2(p[0] - bx, p[1] - by) < 0.5 * u->length + 1.0;
    }
    if (other) continue;
    double ea[4], eb[4];
    box_on(m, t->heading, t->hcos, t->hsin, ea);
    box_on(b, t->heading, t->hcos, t->hsin, eb);
    const double u0 = min_d(ea[0], eb[0]), u1 = max_d(ea[1], eb[1]), v0 = min_d(ea[2], eb[2]), v1 = max_d(ea[3], eb[3]);
    const double cu = 0.5 * (u0 + u1), cv = 0.5 * (v0 + v1), lu = u1 - u0, lv = v1 - v0;
    m->sensor.obb_center[0] = (float)(cu * t->hcos - cv * t->hsin);
    m->sensor.obb_center[1] = (float)(cu * t->hsin + cv * t->hcos);
    m->sensor.obb_heading = (float)(lu >= lv ? t->heading : t->heading + 0.5 * PI);
    m->sensor.obb_length = (float)max_d(lu, lv);
    m->sensor.obb_width = (float)min_d(lu, lv);
    for (int d = 0; d < 3; d++) {
      m->sensor.box_min[d] = min_f(m->sensor.box_min[d], b->sensor.box_min[d]);
      m->sensor.box_max[d] = max_f(m->sensor.box_max[d], b->sensor.box_max[d]);
    }
    m->points += b->points;
    m->range_min = min_f(m->range_min, b->range_min);
    m->occluded = 0;
    tr->taken_by[k] = (int32_t)i;
    L->object_track[k] = t->id;
    tr->n.absorbed++;
    tr->n.merged++;
    any = true;
  }
  return any;
}

/* birth_far_points: an object under birth_points starts a track when it is a walker's size, between
 * birth_far_from_m and birth_far_to_m away, has birth_far_points returns or more, and lies clear of the
 * box of every vehicle-sized track and object (grown by BIRTH_CLEAR_M on each side). Far from a VLP-16 a
 * person on a sidewalk behind a lane of traffic shows only its head and shoulders over the cars: one row,
 * 3-4 returns at 30-40 m. Nearer, a walker has more returns; farther, 4 returns are mostly the ends of
 * vehicles. A piece split off a vehicle would start a second track beside it, hence the clearance. A
 * track so born confirms by the rules of any track (a vehicle coming into view far off may be first seen
 * by 4 returns). The tracks are this frame's (after the updates); objs' first nobj objects, their box
 * cosines and sines cached in tr->obj_cs, this frame's. */
#define BIRTH_CLEAR_M 1.5
_Static_assert(RS_TRACK_FAR_BIRTHS_MAX >= 1 && RS_TRACK_FAR_BIRTHS_MAX <= RS_OBJ_MAX, "far births looked at: 1 to the objects");
#define BIRTH_VEHICLE_M 2.5f /* a track this long (its largest box) is a vehicle's */
static bool far_walker_birth(rs_tracker_t *tr, const rs_object_list_t *objs, uint32_t nobj, const rs_object_t *o,
                             uint32_t *looked) {
  const rs_track_cfg_t *cf = &tr->cfg;
  const rs_track_list_t *L = &tr->list;
  if (cf->birth_far_points <= 0 || o->points < (uint32_t)cf->birth_far_points || o->range_min < cf->birth_far_from_m ||
      o->range_min > cf->birth_far_to_m || o->sensor.obb_length >= WALKER_M)
    return false;
  if (*looked >= RS_TRACK_FAR_BIRTHS_MAX) {
    tr->n.far_dropped++;
    return false;
  }
  (*looked)++;
  const double ox = o->sensor.obb_center[0], oy = o->sensor.obb_center[1];
  /* few objects get here (far, walker-sized, 4 returns), at most RS_TRACK_FAR_BIRTHS_MAX a frame */
  for (uint32_t i = 0; i < L->count; i++) {
    const rs_track_t *t = &L->track[i];
    if (t->full_length >= BIRTH_VEHICLE_M && in_rect(ox, oy, t->x[0], t->x[1], t->hcos, t->hsin,
                                                      0.5 * t->full_length + BIRTH_CLEAR_M, 0.5 * t->full_width + BIRTH_CLEAR_M))
      return false;
  }
  for (uint32_t k = 0; k < nobj; k++) /* a vehicle first seen in this frame, its track born after */
    if (objs->obj[k].sensor.obb_length >= BIRTH_VEHICLE_M && in_box(&objs->obj[k], tr->obj_cs[k][0], tr->obj_cs[k][1], ox, oy, BIRTH_CLEAR_M))
      return false;
  return true;
}

void rs_track_frame(rs_tracker_t *tr, const rs_object_list_t *objs, double t_frame) {
  rs_track_list_t *L = &tr->list;
  const rs_track_cfg_t *cf = &tr->cfg;
  const uint32_t nobj = objs->count < RS_OBJ_MAX ? objs->count : RS_OBJ_MAX;
  tr->n.gap_runs_dropped += objs->gaps_dropped;
  tr->n.frames++;
  tr->low_tan = objs->lowest_beam_deg < -1.0f ? tan(-objs->lowest_beam_deg * PI / 180.0) : 0.0;
  L->t = t_frame;
  L->ended = 0;
  if (t_frame < tr->last_t) t_frame = tr->last_t; /* time never runs back */
  tr->last_t = t_frame;
  for (uint32_t j = 0; j < tr->grid_nused; j++) tr->grid_head[tr->grid_used[j]] = -1;
  tr->grid_nused = 0;
  tr->obj_base = objs->obj;
  tr->obj_n = nobj;
  for (uint32_t k = 0; k < nobj; k++) {
    const rs_object_t *o = &objs->obj[k];
    tr->taken_by[k] = -1;
    tr->shared[k] = 0;
    tr->obj_part[k] = 0;
    L->object_track[k] = 0;
    tr->obj_t[k] = rs_object_time(o, t_frame);
    if (tr->obj_t[k] < t_frame - 1.0 || tr->obj_t[k] > t_frame + 1.0) tr->obj_t[k] = t_frame;
    tr->obj_cs[k][0] = cos(o->sensor.obb_heading);
    tr->obj_cs[k][1] = sin(o->sensor.obb_heading);
    if (o->points == 0) continue;
    tr->obj_cell[k][0] = (long)floor(o->sensor.obb_center[0] / GRID);
    tr->obj_cell[k][1] = (long)floor(o->sensor.obb_center[1] / GRID);
    const uint32_t bk = bucket(tr->obj_cell[k][0], tr->obj_cell[k][1]);
    if (tr->grid_head[bk] < 0) tr->grid_used[tr->grid_nused++] = (uint16_t)bk;
    tr->grid_next[k] = tr->grid_head[bk];
    tr->grid_head[bk] = (int32_t)k;
  }
  for (uint32_t i = 0; i < L->count; i++) {
    L->track[i].object = -1;
    L->track[i].was_held = rs_track_held(&L->track[i]);
    L->track[i].held_object = -1;
  }
  /* clusters over two confirmed tracks whose predictions are apart: held */
  track_grid(tr, t_frame);
  for (uint32_t k = 0; k < nobj; k++) {
    const rs_object_t *o = &objs->obj[k];
    if (o->points == 0 || o->sensor.obb_length < 0.8f) continue;
    const double oc = tr->obj_cs[k][0], os = tr->obj_cs[k][1];
    int in = 0;
    double first[2] = {0, 0};
    float first_len = 0.0f;
    uint32_t most_points = 0;
    bool apart = false;
    int was_held = 0;
    /* (a track moves at most max_speed x 1 s between its grid position and the object's time) */
    const uint32_t nn = tracks_near(tr, o->sensor.obb_center[0], o->sensor.obb_center[1],
                                    0.5 * (o->sensor.obb_length + o->sensor.obb_width) + 0.3 + 0.1 * tr->vmax);
    for (uint32_t q = 0; q < nn; q++) {
      const uint32_t i = tr->near[q];
      const rs_track_t *t = &L->track[i];
      if (t->state == RS_TRACK_TENTATIVE || t->state == RS_TRACK_LOST) continue;
      double p[2];
      predict_xy(tr, t, tr->obj_t[k], p);
      if (!in_box(o, oc, os, p[0], p[1], 0.3)) continue;
      /* apart: two objects side by side (pedestrians 0.7 m, cars in a queue 6 m) */
      if (in == 0) first[0] = p[0], first[1] = p[1], first_len = t->length;
      else if (norm2(p[0] - first[0], p[1] - first[1]) >= 0.25 * (first_len + t->length) + 0.4) apart = true;
      if (t->points > most_points) most_points = t->points;
      was_held += t->was_held;
      in++;
    }
    /* (tracks held the frame before stay held while they pass each other: their predictions cross) */
    if (was_held >= 2) apart = true;
    /* and the cluster holds more than either track's last object did */
    if (in < 2 || !apart || 5 * (uint64_t)o->points < 6 * (uint64_t)most_points) continue;
    tr->shared[k] = 1;
    for (uint32_t q = 0; q < nn; q++) {
      rs_track_t *t = &L->track[tr->near[q]];
      if (t->state == RS_TRACK_TENTATIVE || t->state == RS_TRACK_LOST || rs_track_held(t)) continue;
      double p[2];
      predict_xy(tr, t, tr->obj_t[k], p);
      if (!in_box(o, oc, os, p[0], p[1], 0.3)) continue;
      t->held_object = (int32_t)k;
      tr->n.held++;
      if (L->object_track[k] == 0) L->object_track[k] = t->id;
    }
  }
  /* tent_claim_m: the walker-sized objects a steady tentative walker's track holds (tent_d) */
  for (uint32_t k = 0; k < nobj; k++) tr->tent_d[k] = INFINITY;
  for (uint32_t i = 0; i < L->count && cf->tent_claim_m > 0; i++) {
    const rs_track_t *t = &L->track[i];
    if (t->state != RS_TRACK_TENTATIVE || t->hits < TENT_CLAIM_HITS || !walker_sized(t) || rs_track_held(t) ||
        t_frame - t->t_update > TENT_CLAIM_SEEN_S)
      continue;
    objs_near_t it;
    for (int32_t k = objs_near_first(tr, t->x[0], t->x[1], TENT_CLAIM_REACH_M, &it); k >= 0; k = objs_near_next(tr, &it)) {
      const rs_object_t *o = &objs->obj[k];
      if (o->sensor.obb_length >= WALKER_M || o->sensor.obb_width >= WALKER_M) continue;
      double p[2];
      predict_xy(tr, t, tr->obj_t[k], p);
      const double d = norm2(o->sensor.obb_center[0] - p[0], o->sensor.obb_center[1] - p[1]);
      if (d <= TENT_CLAIM_NEAR_M && d < tr->tent_d[k]) tr->tent_d[k] = (float)d;
    }
  }
  /* confirmed (and coasting) tracks first, then tentative ones */
  gate(tr, objs, true);
  assign(tr, nobj);
  gate(tr, objs, false);
  assign(tr, nobj);
  /* updates (a long vehicle's with its thin parts, merge_parts) */
  for (uint32_t i = 0; i < L->count; i++) {
    rs_track_t *t = &L->track[i];
    if (t->object < 0) continue;
    const rs_object_t *o = &objs->obj[t->object];
    rs_object_t merged;
    take(tr, t, merge_parts(tr, i, objs, o, &merged) ? &merged : o, tr->obj_t[t->object]);
    L->object_track[t->object] = t->id;
  }
  /* split parts: a free object inside the box of a track that took one this
   * frame, or of a confirmed one (predicted), starts no track: its returns
   * carry that track's id */
  for (uint32_t k = 0; k < nobj; k++) {
    if (tr->taken_by[k] >= 0 || tr->shared[k] || objs->obj[k].points == 0) continue;
    const double zx = objs->obj[k].sensor.obb_center[0], zy = objs->obj[k].sensor.obb_center[1];
    const uint32_t nn = tracks_near(tr, zx, zy, 10.0); /* half a bus, the margin and an update's step */
    for (uint32_t q = 0; q < nn; q++) {
      const uint32_t i = tr->near[q];
      const rs_track_t *t = &L->track[i];
      if (t->object < 0 && (t->state == RS_TRACK_TENTATIVE || t->state == RS_TRACK_LOST)) continue;
      if (!in_track_box(tr, t, zx, zy) && !(t->object >= 0 && fits_with(tr, t, &objs->obj[t->object], &objs->obj[k]))) continue;
      tr->taken_by[k] = (int32_t)i;
      L->object_track[k] = t->id;
      tr->n.absorbed++;
      break;
    }
  }
  /* stitching: a track that took an object and was born after a coasting or
   * lost track was last seen, in that track's gate, is that object seen
   * again; an older confirmed track, unseen this frame, predicted right where
   * a younger one of its size is, follows the same object (a duplicate). The
   * older track takes the object over (its id continues), the younger one
   * ends without an event */
  const double gr = 2.0 * cf->gate_m + 0.15 * cf->max_speed;
  uint32_t nunseen = 0; /* the coasting and lost tracks not held, in index order (not a walker's gone into the
                          * blind circle, with blind_walker: it comes out by blind_walk_link alone) */
  for (uint32_t j = 0; j < L->count; j++) {
    const rs_track_t *o = &L->track[j];
    if (unseen(o) && !o->blind_kept && !(cf->blind_walker && gone_in(tr, o))) {
      tr->near_pos[nunseen][0] = tr->tpos[j][0];
      tr->near_pos[nunseen][1] = tr->tpos[j][1];
      tr->near[nunseen++] = (uint16_t)j;
    }
  }
  const double gr2 = gr * gr;
  for (uint32_t i = 0; i < L->count && nunseen > 0; i++) {
    rs_track_t *y = &L->track[i];
    if (y->object < 0 || y->id == 0) continue;
    int best = -1;
    double best_m2 = cf->gate_chi2;
    for (uint32_t q = 0; q < nunseen; q++) {
      /* far from its position at the frame's time: out of every gate below (at most 2 gate_m from its
       * prediction at y's time, which is within 0.15 s x max_speed of it); tested first, on the
       * candidates' positions side by side (near_pos), before any track is read */
      const double gx = y->x[0] - tr->near_pos[q][0], gy = y->x[1] - tr->near_pos[q][1];
      if (gx * gx + gy * gy > gr2) continue;
      const uint32_t j = tr->near[q];
      const rs_track_t *o = &L->track[j];
      if (j == i || o->id == 0 || o->object >= 0) continue; /* (stitched this frame) */
      if (walker_like(cf, o) && vehicle_sized(y->length, y->width)) continue; /* a walker is not a vehicle */
      if (walker_reacq(cf, o, y->t_state - o->t_update, y->length, y->width, y->points)) continue;
      double p[2], S[3];
      predict_pos(tr, o, y->t_state, p, S);
      const double dx = y->x[0] - p[0], dy = y->x[1] - p[1];
      if (o->t_update >= y->t_birth) {
        /* they were seen together: the same object only when the older one, unseen, is predicted where the
         * younger one is (within a third of its length) and they are of a size */
        const double lmax = max_d(o->length, y->length), lmin = min_d(o->length, y->length);
        if (o->id > y->id || sqrt(dx * dx + dy * dy) > max_d(0.5, 0.35 * y->length) || lmin < 0.5 * lmax - 0.5 ||
            !move_alike(o, y) || (cf->stitch_alike && apart_when_seen(o, y)))
          continue;
      } else if (sqrt(dx * dx + dy * dy) > min_d(2.0 * cf->gate_m, cf->gate_m + 0.5 * (y->t_state - o->t_update)) ||
                 off_lane(cf, o, dx, dy, y->t_state - o->t_update) || !stitch_feasible(tr, o, y)) {
        continue;
      }
      const double s00 = S[0] + y->P[0][0], s01 = S[1] + y->P[0][1], s11 = S[2] + y->P[1][1];
      const double det = s00 * s11 - s01 * s01;
      if (!(det > 0)) continue;
      const double m2 = (dx * dx * s11 - 2 * dx * dy * s01 + dy * dy * s00) / det;
      if (m2 <= best_m2) {
        best_m2 = m2;
        best = (int)j;
      }
    }
    if (best < 0) continue;
    stitch(tr, objs, nobj, (uint32_t)best, y, y->hits > L->track[best].hits);
    tr->n.stitched++;
  }
  /* the blind-circle link: a young moving track, born at the circle's other
   * side of an unseen track last seen at its edge, is that track (the few
   * tracks under 1.5 s old against the candidates, each test a few
   * products). The candidates, in index order: unseen tracks not of a
   * walker's size (the sidewalks pass the pole and walkers cross them in
   * groups, slowly, seconds in the circle; a young walker's track is no
   * better sign of which one came out than a still one's of which one went
   * in: held-out site 13, VLP-16 rush, three walkers' ids given to others);
   * with blind_walker the walkers' tracks after them, by their own test
   * (blind_walk_link: the time unseen must fit the way at the walker's pace).
   * A link only takes tracks out of that set (the linked one is seen, the
   * young one ends), so each is checked again when tried */
  uint32_t ncand = 0;
  for (uint32_t j = 0; j < L->count && tr->cfg.blind_s > 0; j++) {
    const rs_track_t *o = &L->track[j];
    if (unseen(o) && !walker_full_sized(o)) tr->near[ncand++] = (uint16_t)j;
  }
  uint32_t nwalk = 0; /* blind_walker: the walkers' candidates, after the vehicles' in the same scratch */
  for (uint32_t j = 0; j < L->count && tr->cfg.blind_s > 0 && tr->cfg.blind_walker; j++) {
    const rs_track_t *o = &L->track[j];
    if (unseen(o) && walker_full_sized(o)) tr->near[ncand + nwalk++] = (uint16_t)j;
  }
  for (uint32_t i = 0; i < L->count && ncand + nwalk > 0; i++) {
    rs_track_t *y = &L->track[i];
    if (y->object < 0 || y->id == 0 || y->hits < 3 || y->t_update - y->t_birth > 1.5) continue;
    int best = nearest_unseen(tr, i, 0, ncand, blind_link, NULL);
    if (best < 0) {
      uint32_t fits;
      best = nearest_unseen(tr, i, ncand, ncand + nwalk, blind_walk_link, &fits);
      /* blind_walker_alone: unseen longer than blind_walker_s, o takes y only if no other gone-in walker's
       * track fits it */
      if (best >= 0 && cf->blind_walker_alone && fits > 1 && y->t_birth - L->track[best].t_update > cf->blind_walker_s)
        best = -1;
    }
    if (best < 0) continue;
    stitch(tr, objs, nobj, (uint32_t)best, y, true); /* its state is y's: o's is seconds old */
    L->track[best].blind_kept = false;
    tr->n.blind_linked++;
  }
  /* the kinematic re-acquisition (kin_accel): a young track the stitching and the link above gave to
   * none, against the vehicles' tracks unseen for KIN_MIN_S or more, in index order */
  uint32_t nkin = 0;
  double kin_first = INFINITY; /* the earliest of their last updates: a young track born before it has none */
  for (uint32_t j = 0; j < L->count && cf->kin_accel > 0; j++) {
    const rs_track_t *o = &L->track[j];
    if (unseen(o) && !o->blind_kept && kin_vehicle(cf, o) && t_frame - o->t_update >= KIN_MIN_S) {
      tr->near[nkin++] = (uint16_t)j;
      kin_first = min_d(kin_first, o->t_update);
    }
  }
  for (uint32_t i = 0; i < L->count && nkin > 0; i++) {
    rs_track_t *y = &L->track[i];
    if (y->object < 0 || y->id == 0 || y->state != RS_TRACK_TENTATIVE || y->hits < KIN_HITS || y->t_birth <= kin_first)
      continue;
    const int best = nearest_unseen(tr, i, 0, nkin, kin_fit, NULL);
    if (best < 0) continue;
    stitch(tr, objs, nobj, (uint32_t)best, y, y->hits > L->track[best].hits);
    tr->n.stitched++;
    tr->n.kin_stitched++;
  }
  /* duplicates, ended without an event: a tentative track inside the box of
   * a confirmed one at least its size (a fragment of its object); a
   * confirmed one unseen this frame, predicted where an older track of its
   * size was seen (the older one follows the object); with dup_box, one
   * unseen this frame and predicted inside the box of an older vehicle's
   * track seen this frame (DUP_BOX_M long or more, moving at DUP_BOX_V or
   * more) that moves alike: a part of that vehicle that had a track of its
   * own (the two took its front and its rear in turn, or both at once as two
   * clusters, each one's box a part of the vehicle's, never both its centre) */
  for (uint32_t i = 0; i < L->count; i++) {
    rs_track_t *t = &L->track[i];
    if (t->id == 0) continue;
    const bool tentative = t->state == RS_TRACK_TENTATIVE;
    if (!tentative && cf->twin_s > 0) {
      const int j = twin_of(tr, t, t_frame);
      if (j < 0) {
        t->twin = 0;
      } else if (t->twin != L->track[j].id) {
        t->twin = L->track[j].id;
        t->twin_t = t_frame;
      } else if (t_frame - t->twin_t >= cf->twin_s - 1e-6 && end_twin(tr, objs, nobj, (uint32_t)j, t)) {
        tr->n.duplicates++;
        continue;
      }
    }
    if (!tentative && (t->object >= 0 || rs_track_held(t))) continue;
    double px = t->x[0], py = t->x[1];
    if (!tentative) {
      double dt = t_frame - t->t_state;
      if (dt < 0) dt = 0;
      px += t->x[2] * dt;
      py += t->x[3] * dt;
    }
    const uint32_t nn = tracks_near(tr, px, py, tentative ? 8.0 : 5.0);
    bool dup = false;
    const rs_track_t *o = NULL;
    for (uint32_t q = 0; q < nn && !dup; q++) {
      o = &L->track[tr->near[q]];
      if (o == t || o->id == 0) continue;
      if (tentative) {
        dup = (o->state == RS_TRACK_CONFIRMED || o->state == RS_TRACK_COASTING) && o->length >= t->length &&
              in_track_box(tr, o, t->x[0], t->x[1]);
      } else if (o->id < t->id && o->object >= 0) {
        const double lmax = max_d(o->length, t->length), lmin = min_d(o->length, t->length);
        const double dx = o->x[0] - px, dy = o->x[1] - py, r = max_d(0.5, 0.35 * o->length);
        dup = dx * dx + dy * dy <= r * r && lmin >= 0.5 * lmax - 0.5;
        if (!dup && cf->dup_box && o->length >= DUP_BOX_M && norm2(o->x[2], o->x[3]) >= DUP_BOX_V && move_alike(o, t))
          dup = in_track_box(tr, o, px, py);
      }
    }
    if (!dup) continue;
    if (t->object >= 0) relabel(L, nobj, t->id, o->id); /* its fragment's returns go to the track it is part of */
    t->id = 0;
    tr->n.duplicates++;
  }
  if (cf->queue_coast) queue_leaders(tr, t_frame);
  /* states, confirmation, ends (compacting the list, id order kept) */
  uint32_t w = 0;
  for (uint32_t i = 0; i < L->count; i++) {
    rs_track_t *t = &L->track[i];
    if (t->id == 0) continue; /* stitched into an older track */
    const bool updated = t->object >= 0;
    if (!updated) {
      const double t0 = t->t_state;
      if (stands(tr, t)) t->x[2] = t->x[3] = 0.0; /* still_coast */
      else if (backs_up(tr, t)) stand_still(t); /* still_reverse */
      else if (t->t_state == t->t_update && !rs_track_held(t)) walk_on_at_pace(tr, t); /* first unseen */
      predict(tr, t, t_frame);
      if (cf->brake_coast && !rs_track_held(t)) brake_step(t, t0);
      if (cf->queue_coast && !rs_track_held(t)) follow_leader(tr, t, t_frame);
      if (rs_track_held(t)) t->t_update = t_frame; /* seen, inside a shared cluster */
      else if (cf->gap_unseen && rs_objects_unmeasured_at(objs, t->x[0], t->x[1])) tr->n.gap_unseen++;
      else t->misses++;
    }
    const double since = t_frame - t->t_update;
    bool ends = false;
    if (t->state == RS_TRACK_TENTATIVE) {
      const double moved = norm2(t->x[0] - t->px0, t->x[1] - t->py0);
      if (!updated && since > cf->tentative_miss_s) {
        ends = true;
      } else if (updated && t->hits >= (uint32_t)cf->confirm_hits &&
                 ((moved >= cf->confirm_move_m && moved >= 0.5 * t->distance) ||
                  (cf->confirm_walk_m > 0 && t->misses == 0 && walker_sized(t) &&
                   t->hits >= (uint32_t)cf->confirm_hits + 1 && moved >= walk_m(cf, t) && moved >= 0.8 * t->distance) ||
                  (t->misses == 0 && t->t_update - t->t_birth >= cf->confirm_still_s) ||
                  still_fast(tr, t, w, i))) {
        t->state = RS_TRACK_CONFIRMED;
        tr->n.confirmed++;
      }
    } else {
      const double lost = t->shape_cls == RS_CLASS_PEDESTRIAN ? max_d(cf->lost_s, cf->lost_walker_s) : cf->lost_s;
      t->blind_kept = !updated && since > cf->coast_s + lost &&
                      since <= (cf->blind_walker && walker_full_sized(t) ? walker_keep(tr, t) : cf->blind_s) &&
                      at_blind_edge(tr, t);
      if (since > cf->coast_s + lost && !t->blind_kept) ends = true;
      else if (updated || rs_track_held(t)) t->state = RS_TRACK_CONFIRMED;
      else t->state = since > cf->coast_s ? RS_TRACK_LOST : RS_TRACK_COASTING;
    }
    if (ends) {
      end_track(tr, t, t->t_update);
      continue;
    }
    report_speed(tr, t);
    t->distance += norm2(t->x[0] - t->prev[0], t->x[1] - t->prev[1]); /* path, coasting included */
    t->prev[0] = t->x[0];
    t->prev[1] = t->x[1];
    if (updated || rs_track_held(t)) t->distance_seen = t->distance;
    if (updated && t->speed > 0.0f) t->t_moving = t->t_update;
    if (t->state != RS_TRACK_TENTATIVE && updated) {
      if (t->speed > t->max_speed) t->max_speed = t->speed;
      t->sum_speed += t->speed;
      t->speed_n++;
    }
    t->shape_cls = classify(t);
    if (updated && t->walked < (uint16_t)cf->walked_hits && walks(t)) t->walked++;
    t->cls = voted_class(t, updated);
    if (w != i) L->track[w] = *t; /* taken_by[] keeps old indices: only its sign is read below */
    w++;
  }
  L->count = w;
  /* births, in object order */
  uint32_t far_looked = 0;
  for (uint32_t k = 0; k < nobj; k++) {
    const rs_object_t *o = &objs->obj[k];
    if (tr->taken_by[k] >= 0 || tr->shared[k] || (o->points < (uint32_t)cf->birth_points && !far_walker_birth(tr, objs, nobj, o, &far_looked)))
      continue;
    if (L->count >= RS_TRACK_MAX) {
      tr->n.overflow++;
      continue;
    }
    rs_track_t *t = &L->track[L->count++];
    memset(t, 0, sizeof *t);
    t->id = tr->next_id++;
    if (tr->next_id == 0) tr->next_id = 1; /* after 4e9 tracks */
    double z[2], sd;
    meas(tr, o, z, &sd);
    t->x[0] = z[0];
    t->x[1] = z[1];
    t->P[0][0] = t->P[1][1] = sd * sd;
    /* a small object (pedestrian, cyclist) is slow: its first pairing stays near */
    const double vsd = o->sensor.obb_length < 2.0f ? cf->init_small_speed_sd : cf->init_speed_sd;
    t->P[2][2] = t->P[3][3] = vsd * vsd;
    t->t_state = t->t_birth = t->t_moving = tr->obj_t[k];
    t->px0 = t->prev[0] = z[0];
    t->py0 = t->prev[1] = z[1];
    t->state = RS_TRACK_TENTATIVE;
    t->object = (int32_t)k;
    t->held_object = -1;
    take(tr, t, o, tr->obj_t[k]);
    t->cls = t->shape_cls = RS_CLASS_UNKNOWN;
    report_speed(tr, t);
    L->object_track[k] = t->id;
    tr->n.born++;
    if (o->points < (uint32_t)cf->birth_points) tr->n.far_born++;
  }
  /* the held tracks each shared object's returns are divided between (indices are final now) */
  memset(tr->hold_n, 0, nobj);
  tr->hold_objects = nobj;
  for (uint32_t i = 0; i < L->count; i++) {
    const rs_track_t *t = &L->track[i];
    if (!rs_track_held(t) || t->held_object < 0 || (uint32_t)t->held_object >= nobj) continue;
    const uint32_t k = (uint32_t)t->held_object;
    if (tr->hold_n[k] < RS_TRACK_HOLD_MAX) tr->hold_idx[k][tr->hold_n[k]++] = (uint16_t)i;
    else tr->n.hold_overflow++;
  }
  if (tr->have_pose) site_states(tr);
  tr->obj_base = NULL; /* (the caller's list: not kept past the frame) */
  tr->obj_n = 0;
}

uint32_t rs_track_owner(const rs_tracker_t *tr, uint32_t k, double x, double y) {
  if (k >= tr->hold_objects) return 0;
  if (tr->hold_n[k] < 2) return tr->list.object_track[k];
  uint32_t best = 0;
  double best_score = HUGE_VAL;
  for (uint32_t j = 0; j < tr->hold_n[k]; j++) { /* in index order: id order, the lower id wins a tie */
    const rs_track_t *t = &tr->list.track[tr->hold_idx[k][j]];
    const double dt = tr->obj_t[k] - t->t_state;
    const double dx = x - (t->x[0] + t->x[2] * dt), dy = y - (t->x[1] + t->x[3] * dt);
    const double u = dx * t->hcos + dy * t->hsin, v = -dx * t->hsin + dy * t->hcos;
    const double score = max_d(fabs(u) / max_d(0.25, 0.5 * t->length), fabs(v) / max_d(0.25, 0.5 * t->width));
    if (score < best_score) {
      best_score = score;
      best = t->id;
    }
  }
  return best;
}

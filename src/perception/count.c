/* count.c - counting lines and zones (processing thread; no allocation).
 *
 * Per frame: every track of the list is looked up in the slot table (by id,
 * linear probing); a confirmed one whose path since its last position (or,
 * at its first confirmed frame, since where it was first seen) crosses a
 * line it was not counted on is counted; an unseen one is followed on its
 * prediction for unseen_s (count.h); slots of tracks no longer listed are
 * freed (backward-shift deletion keeps the probing chains whole). */
#include "roadscan/perception/count.h"

#include "roadscan/util/error.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

int rs_count_parse_line(const char *text, rs_count_line_t *out, char *err, size_t n) {
  char name[RS_COUNT_NAME + 1];
  double v[4];
  int used = 0;
  memset(out, 0, sizeof *out);
  if (sscanf(text, "%32s %lf %lf %lf %lf %n", name, &v[0], &v[1], &v[2], &v[3], &used) != 5 || text[used] != '\0') {
    snprintf(err, n, "count line '%s': not NAME X1 Y1 X2 Y2 (metres)", text);
    return RS_E_INVAL;
  }
  if (strlen(name) >= RS_COUNT_NAME) {
    snprintf(err, n, "count line '%s': the name is longer than %d characters", text, RS_COUNT_NAME - 1);
    return RS_E_INVAL;
  }
  for (int k = 0; k < 4; k++)
    if (!isfinite(v[k]) || fabs(v[k]) > 10000.0) {
      snprintf(err, n, "count line '%s': coordinates are metres within 10 km", text);
      return RS_E_INVAL;
    }
  if (hypot(v[2] - v[0], v[3] - v[1]) < 0.1) {
    snprintf(err, n, "count line '%s': its ends are less than 0.1 m apart", text);
    return RS_E_INVAL;
  }
  memcpy(out->name, name, strlen(name) + 1); /* shorter than RS_COUNT_NAME: checked above */
  out->ax = v[0];
  out->ay = v[1];
  out->bx = v[2];
  out->by = v[3];
  return RS_OK;
}

/* do segments P1P2 and P3P4 cross (properly)? */
static bool segments_cross(double x1, double y1, double x2, double y2, double x3, double y3, double x4, double y4) {
  const double d1 = (x2 - x1) * (y3 - y1) - (y2 - y1) * (x3 - x1), d2 = (x2 - x1) * (y4 - y1) - (y2 - y1) * (x4 - x1);
  const double d3 = (x4 - x3) * (y1 - y3) - (y4 - y3) * (x1 - x3), d4 = (x4 - x3) * (y2 - y3) - (y4 - y3) * (x2 - x3);
  return ((d1 > 0) != (d2 > 0)) && ((d3 > 0) != (d4 > 0)) && d1 != 0 && d2 != 0 && d3 != 0 && d4 != 0;
}

int rs_count_parse_zone(const char *text, rs_count_zone_t *out, char *err, size_t n) {
  memset(out, 0, sizeof *out);
  char name[RS_COUNT_NAME + 1];
  int used = 0;
  if (sscanf(text, "%32s %n", name, &used) != 1) {
    snprintf(err, n, "count zone '%s': not NAME X1 Y1 X2 Y2 X3 Y3 ... (metres)", text);
    return RS_E_INVAL;
  }
  if (strlen(name) >= RS_COUNT_NAME) {
    snprintf(err, n, "count zone '%s': the name is longer than %d characters", text, RS_COUNT_NAME - 1);
    return RS_E_INVAL;
  }
  const char *p = text + used;
  double v[2 * RS_COUNT_ZONE_VERTICES + 1];
  int k = 0;
  while (*p) {
    if (k == 2 * RS_COUNT_ZONE_VERTICES) {
      snprintf(err, n, "count zone '%s': more than %d corners", text, RS_COUNT_ZONE_VERTICES);
      return RS_E_INVAL;
    }
    char *end;
    v[k] = strtod(p, &end);
    if (end == p || !isfinite(v[k]) || fabs(v[k]) > 10000.0) {
      snprintf(err, n, "count zone '%s': corners are pairs of numbers, metres within 10 km", text);
      return RS_E_INVAL;
    }
    k++;
    p = end;
    while (*p == ' ' || *p == '\t') p++;
  }
  if (k % 2 != 0 || k < 6) {
    snprintf(err, n, "count zone '%s': not NAME and 3 to %d corners X Y", text, RS_COUNT_ZONE_VERTICES);
    return RS_E_INVAL;
  }
  out->n = k / 2;
  for (int i = 0; i < out->n; i++) {
    out->x[i] = v[2 * i];
    out->y[i] = v[2 * i + 1];
  }
  double area = 0;
  for (int i = 0; i < out->n; i++) {
    const int j = (i + 1) % out->n;
    area += out->x[i] * out->y[j] - out->x[j] * out->y[i];
  }
  if (fabs(area) / 2 < 0.01) {
    snprintf(err, n, "count zone '%s': no area (corners on one line, or repeated)", text);
    return RS_E_INVAL;
  }
  for (int i = 0; i < out->n; i++) /* edges that do not touch must not cross */
    for (int j = i + 2; j < out->n; j++) {
      if (i == 0 && j == out->n - 1) continue;
      const int i2 = (i + 1) % out->n, j2 = (j + 1) % out->n;
      if (segments_cross(out->x[i], out->y[i], out->x[i2], out->y[i2], out->x[j], out->y[j], out->x[j2], out->y[j2])) {
        snprintf(err, n, "count zone '%s': its edges cross (give the corners in order around it)", text);
        return RS_E_INVAL;
      }
    }
  memcpy(out->name, name, strlen(name) + 1);
  return RS_OK;
}

int rs_count_opt_line(void *lines, const char *key, const char *text, char *err, size_t n) {
  rs_count_lines_t *l = lines;
  if (l->n == RS_COUNT_LINES) {
    snprintf(err, n, "%s: at most %d lines", key, RS_COUNT_LINES);
    return RS_E_INVAL;
  }
  if (rs_count_parse_line(text, &l->line[l->n], err, n) != RS_OK) return RS_E_INVAL;
  l->n++;
  return RS_OK;
}

int rs_count_opt_zone(void *zones, const char *key, const char *text, char *err, size_t n) {
  rs_count_zones_t *z = zones;
  if (z->n == RS_COUNT_ZONES) {
    snprintf(err, n, "%s: at most %d zones", key, RS_COUNT_ZONES);
    return RS_E_INVAL;
  }
  if (rs_count_parse_zone(text, &z->zone[z->n], err, n) != RS_OK) return RS_E_INVAL;
  z->n++;
  return RS_OK;
}

bool rs_count_inside(const rs_count_zone_t *z, double x, double y) {
  bool in = false;
  for (int i = 0, j = z->n - 1; i < z->n; j = i++) {
    if ((z->y[i] > y) != (z->y[j] > y) &&
        x < (z->x[j] - z->x[i]) * (y - z->y[i]) / (z->y[j] - z->y[i]) + z->x[i])
      in = !in;
  }
  return in;
}

int rs_count_add_zones(rs_counter_t *c, const rs_count_zone_t *zones, int nzones, char *err, size_t n) {
  if (nzones < 0 || c->nzones + nzones > RS_COUNT_ZONES) {
    snprintf(err, n, "at most %d count zones", RS_COUNT_ZONES);
    return RS_E_INVAL;
  }
  for (int i = 0; i < nzones; i++) {
    if (zones[i].n < 3 || zones[i].n > RS_COUNT_ZONE_VERTICES) {
      snprintf(err, n, "count zone %s: %d corners", zones[i].name, zones[i].n);
      return RS_E_INVAL;
    }
    for (int j = 0; j < c->nzones; j++)
      if (strcmp(zones[i].name, c->zones[j].name) == 0) {
        snprintf(err, n, "count zone %s: two zones of that name", zones[i].name);
        return RS_E_INVAL;
      }
    c->zones[c->nzones++] = zones[i];
  }
  return RS_OK;
}

static double line_len(const rs_count_line_t *l) { return hypot(l->bx - l->ax, l->by - l->ay); }

int rs_count_init(rs_counter_t *c, const rs_count_line_t *lines, int nlines, const rs_pose_t *pose, double interval_s,
                  char *err, size_t n) {
  memset(c, 0, sizeof *c);
  if (nlines < 0 || nlines > RS_COUNT_LINES) {
    snprintf(err, n, "at most %d count lines", RS_COUNT_LINES);
    return RS_E_INVAL;
  }
  if (!(interval_s >= 1.0 && interval_s <= 86400.0)) {
    snprintf(err, n, "count interval: %g s is not from 1 s to a day", interval_s);
    return RS_E_INVAL;
  }
  for (int i = 0; i < nlines; i++) {
    if (line_len(&lines[i]) < 0.1) {
      snprintf(err, n, "count line %s: its ends are less than 0.1 m apart", lines[i].name);
      return RS_E_INVAL;
    }
    for (int j = 0; j < i; j++)
      if (strcmp(lines[i].name, lines[j].name) == 0) {
        snprintf(err, n, "count line %s: two lines of that name", lines[i].name);
        return RS_E_INVAL;
      }
    c->lines[i] = lines[i];
  }
  c->nlines = nlines;
  c->interval_s = interval_s;
  c->hidden_s = RS_COUNT_HIDDEN_S;
  c->hidden_window_s = RS_COUNT_HIDDEN_WINDOW_S;
  c->class_delay_s = RS_COUNT_CLASS_DELAY_S;
  c->unseen_s = RS_COUNT_UNSEEN_S;
  c->same_s = RS_COUNT_SAME_S;
  c->unseen_yield = true;
  c->band_m = RS_COUNT_BAND_M;
  c->hidden_at_track = true;
  c->t_first = -1.0;
  c->cur.t_start = c->cur.t_end = -1.0;
  if (pose) {
    /* the ground-plane part of site = R p + t */
    double r[9];
    rs_pose_rotation(pose, r);
    c->rot[0] = r[0];
    c->rot[1] = r[1];
    c->rot[2] = r[3];
    c->rot[3] = r[4];
    c->trans[0] = pose->x;
    c->trans[1] = pose->y;
    c->have_pose = true;
  }
  return RS_OK;
}

static double cross(double ax, double ay, double bx, double by, double px, double py) {
  return (bx - ax) * (py - ay) - (by - ay) * (px - ax);
}

/* does P0 -> P1 cross line l? 1 forward (to the left of A -> B), -1 backward, 0 no */
static int crosses(const rs_count_line_t *l, double x0, double y0, double x1, double y1) {
  const double d0 = cross(l->ax, l->ay, l->bx, l->by, x0, y0), d1 = cross(l->ax, l->ay, l->bx, l->by, x1, y1);
  if ((d0 > 0) == (d1 > 0)) return 0; /* same side (on the line counts as its right) */
  const double e0 = cross(x0, y0, x1, y1, l->ax, l->ay), e1 = cross(x0, y0, x1, y1, l->bx, l->by);
  if ((e0 > 0) == (e1 > 0) && e0 != 0.0 && e1 != 0.0) return 0; /* beyond the segment's ends */
  return d1 > 0 ? 1 : -1;
}

int rs_count_crosses(const rs_count_line_t *l, double x0, double y0, double x1, double y1) {
  return crosses(l, x0, y0, x1, y1);
}

/* the distance from A along line l of (x, y)'s foot on it */
static double along(const rs_count_line_t *l, double x, double y) {
  return ((x - l->ax) * (l->bx - l->ax) + (y - l->ay) * (l->by - l->ay)) / line_len(l);
}

/* where P0 -> P1 meets line l's support: the share u along P0 -> P1 and the
 * distance s from A along the line (for steps that cross it) */
static void meet(const rs_count_line_t *l, double x0, double y0, double x1, double y1, double *u, double *s) {
  const double d0 = cross(l->ax, l->ay, l->bx, l->by, x0, y0), d1 = cross(l->ax, l->ay, l->bx, l->by, x1, y1);
  *u = d0 != d1 ? d0 / (d0 - d1) : 0.0;
  *s = along(l, x0 + *u * (x1 - x0), y0 + *u * (y1 - y0));
}

/* line l's side of (x, y) beyond band_m: 1 left (forward's), -1 right, 0 within the band */
static int side_of(const rs_counter_t *c, int l, double x, double y) {
  const rs_count_line_t *ln = &c->lines[l];
  const double d = cross(ln->ax, ln->ay, ln->bx, ln->by, x, y) / line_len(ln);
  return d > c->band_m ? 1 : d < -c->band_m ? -1 : 0;
}

/* slot i seen clear of line l on side (side_of, not 0) */
static void note_side(rs_counter_t *c, uint32_t i, int l, int side) {
  const uint16_t bit = (uint16_t)(1u << l);
  c->slot[i].side_known |= bit;
  if (side > 0) c->slot[i].side_left |= bit;
  else c->slot[i].side_left &= (uint16_t)~bit;
}

/* the seen track of slot i at (x, y): its sides of the lines updated; the
 * direction it crossed line l in (it is past the band on the side other than
 * the one it was last seen clear on, along the line's segment), or 0 */
static int band_cross(rs_counter_t *c, uint32_t i, int l, double x, double y, double *s) {
  const uint16_t bit = (uint16_t)(1u << l);
  const int side = side_of(c, l, x, y);
  if (side == 0) return 0;
  const bool known = (c->slot[i].side_known & bit) != 0, was_left = (c->slot[i].side_left & bit) != 0;
  note_side(c, i, l, side);
  if (!known || (side > 0) == was_left) return 0;
  /* where: the last step's meeting with the line when it met it, else the track's place along it */
  const rs_count_line_t *ln = &c->lines[l];
  double u;
  if (crosses(ln, c->slot[i].x, c->slot[i].y, x, y) != 0) meet(ln, c->slot[i].x, c->slot[i].y, x, y, &u, s);
  else *s = along(ln, x, y);
  return *s >= 0.0 && *s <= line_len(ln) ? side : 0;
}

/* slot i, whose crossing of line (bit) is counted, crossing it in direction dir: a second crossing,
 * the way back, counted once for a track not vehicle-sized, its first tallied (not pending) */
static bool counts_back(const rs_counter_t *c, uint32_t i, uint16_t bit, int dir, bool vehicle) {
  if (vehicle || dir == 0 || (c->slot[i].pending & bit) || (c->slot[i].counted_both & bit)) return false;
  return (dir > 0) != ((c->slot[i].counted_fwd & bit) != 0);
}

/* line bit counted for slot i in direction dir (its first direction kept) */
static void mark_counted(rs_counter_t *c, uint32_t i, uint16_t bit, int dir) {
  if (!(c->slot[i].counted & bit)) {
    if (dir > 0) c->slot[i].counted_fwd |= bit;
    else c->slot[i].counted_fwd &= (uint16_t)~bit;
  }
  c->slot[i].counted |= bit;
}

static void remember(rs_counter_t *c, int l, double t, double s, int dir, const rs_track_t *tr, bool vehicle) {
  const uint32_t k = c->recent_n[l]++ % RS_COUNT_RECENT;
  c->recent[l][k].t = t;
  c->recent[l][k].s = s;
  c->recent[l][k].dir = dir;
  c->recent[l][k].id = tr->id;
  c->recent[l][k].vehicle = vehicle;
  c->recent[l][k].born = tr->t_birth;
}

/* track id's remembered crossing of line l, taken back */
static void unremember(rs_counter_t *c, int l, uint32_t id) {
  const uint32_t n = c->recent_n[l] < RS_COUNT_RECENT ? c->recent_n[l] : RS_COUNT_RECENT;
  for (uint32_t k = 0; k < n; k++)
    if (c->recent[l][k].id == id) c->recent[l][k].dir = 0;
}

#define HIDDEN_DT 1.5 /* s: a counted crossing this close in time ... */
#define HIDDEN_DS 2.5 /* m: ... and along the line is the same vehicle's */
#define HIDDEN_MIN_SPEED 1.0
#define NEWER_SLACK_S 0.05 /* s: a track first seen this soon before another's last update is newer (frames' times) */
/* A track first seen soon after the run started, past a line its path run back
 * crosses, may have crossed it before the run: the vehicle was slower then (it
 * was pulling away from the stop line; the speed its first boxes give is also
 * too high while more of it comes into view). Its hidden crossing counts only
 * if it falls within the run with the time run back stretched by this much
 * (docs/tracking.md, counting: 1, 1.5, 2 and 3 measured). */
#define HIDDEN_STRETCH 1.5

/* which earlier crossings counted_near looks for */
typedef enum {
  NEAR_ANY,           /* by any track */
  NEAR_OTHER_VEHICLE, /* by a vehicle-sized track other than id (second tracks, count.h) */
  NEAR_NEWER          /* by a track other than id first seen at `since` or later (a walker's new track) */
} near_t;

/* a crossing of line l in direction dir counted within dt of t and HIDDEN_DS of s, by a track of kind: its
 * index in recent[l], -1 none */
static int near_crossing(const rs_counter_t *c, int l, double t, double s, int dir, double dt, near_t kind, uint32_t id,
                         double since) {
  const uint32_t n = c->recent_n[l] < RS_COUNT_RECENT ? c->recent_n[l] : RS_COUNT_RECENT;
  for (uint32_t k = 0; k < n; k++) {
    const bool other = c->recent[l][k].id != id;
    const bool by = kind == NEAR_ANY || (kind == NEAR_OTHER_VEHICLE && other && c->recent[l][k].vehicle) ||
                    (kind == NEAR_NEWER && other && c->recent[l][k].born >= since);
    if (by && c->recent[l][k].dir == dir && fabs(c->recent[l][k].t - t) <= dt && fabs(c->recent[l][k].s - s) <= HIDDEN_DS)
      return (int)k;
  }
  return -1;
}
static bool counted_near(const rs_counter_t *c, int l, double t, double s, int dir, double dt, near_t kind, uint32_t id,
                         double since) {
  return near_crossing(c, l, t, s, dir, dt, kind, id, since) >= 0;
}

/* a track of a vehicle's length (second tracks, count.h) */
static bool vehicle_sized(const rs_track_t *tr) { return tr->full_length >= RS_COUNT_VEHICLE_M; }

/* a track not of a vehicle's length moving at a walker's pace (unseen crossings, count.h) */
static bool walker_paced(const rs_track_t *tr) {
  return !vehicle_sized(tr) && hypot(tr->x[2], tr->x[3]) < RS_COUNT_WALKER_PACE;
}

static void tally(rs_counter_t *c, int l, int dir, unsigned cls) {
  if (dir > 0) {
    c->cur.line[l].forward[cls]++;
    c->total[l].forward[cls]++;
  } else {
    c->cur.line[l].backward[cls]++;
    c->total[l].backward[cls]++;
  }
  c->crossings++;
}

/* Line l for a track at its first confirmed frame (t, x, y) that was first
 * seen at (x0, y0) at time t0 and did not cross it since, reporting velocity
 * vel: did it cross it unseen just before (the header's hidden crossings)?
 * The direction, or 0;
 * when and where along the line (hidden_at_track: where (x, y) is along it,
 * the track's lane, not where a partial first box's path met it). */
static int hidden_crossing(rs_counter_t *c, int l, double t0, double x0, double y0, double t, double x, double y,
                           const double vel[2], double *t_cross, double *s_cross) {
  if (!(c->hidden_s > 0) || !(t > t0)) return 0;
  const double vx = (x - x0) / (t - t0), vy = (y - y0) / (t - t0);
  if (hypot(vx, vy) < HIDDEN_MIN_SPEED) return 0;
  /* its centre moved against the way the track reports it going: its box grew the other way as more of it
   * came into view (a vehicle out from behind another, coming towards the line) */
  if (hypot(vel[0], vel[1]) >= HIDDEN_MIN_SPEED && vel[0] * vx + vel[1] * vy < 0) return 0;
  const double bx = x0 - vx * c->hidden_s, by = y0 - vy * c->hidden_s; /* where it was hidden_s before */
  const int dir = crosses(&c->lines[l], bx, by, x0, y0);
  if (dir == 0) return 0;
  double u, s;
  meet(&c->lines[l], bx, by, x0, y0, &u, &s);
  *t_cross = t0 - (1.0 - u) * c->hidden_s;
  *s_cross = c->hidden_at_track ? along(&c->lines[l], x, y) : s;
  if (t0 - HIDDEN_STRETCH * (t0 - *t_cross) < c->t_first) return 0; /* maybe before the run: not a crossing of it */
  /* its lane beside the line, not across it: the path run back met the line only because its first boxes
   * grew across (a car in the road, its path through the end of a sidewalk's short line) */
  if (*s_cross < -HIDDEN_DS || *s_cross > line_len(&c->lines[l]) + HIDDEN_DS) return 0;
  return dir;
}

/* the zones (x, y) is inside, as a mask */
static uint8_t zones_at(const rs_counter_t *c, double x, double y) {
  uint8_t m = 0;
  for (int z = 0; z < c->nzones; z++)
    if (rs_count_inside(&c->zones[z], x, y)) m |= (uint8_t)(1u << z);
  return m;
}

static uint32_t hash_id(uint32_t id) { return (id * 2654435761u) & (RS_COUNT_SLOTS - 1); }
/* the slot of track id, -1 none */
static int32_t slot_of(const rs_counter_t *c, uint32_t id) {
  uint32_t i = hash_id(id);
  for (int guard = 0; guard < RS_COUNT_SLOTS && c->slot[i].id != 0; guard++, i = (i + 1) & (RS_COUNT_SLOTS - 1))
    if (c->slot[i].id == id) return (int32_t)i;
  return -1;
}

const char *rs_count_how_name(rs_cross_how_t h) {
  return h == RS_CROSS_HIDDEN ? "hidden" : h == RS_CROSS_UNSEEN ? "unseen" : "seen";
}

/* ---- crossing events (count.h) ---- */

/* slot i's trail: (t, x, y) added when RS_COUNT_TRAIL_DT or more after its newest */
static void trail_add(rs_counter_t *c, uint32_t i, double t, double x, double y) {
  const float rt = (float)(t - c->slot[i].t0);
  uint8_t h = c->slot[i].trail_head;
  if (c->slot[i].trail_n > 0) {
    if (rt - c->slot[i].trail_t[h] < (float)RS_COUNT_TRAIL_DT) return;
    h = (uint8_t)((h + 1) % RS_COUNT_TRAIL);
  }
  c->slot[i].trail_t[h] = rt;
  c->slot[i].trail_x[h] = (float)x;
  c->slot[i].trail_y[h] = (float)y;
  c->slot[i].trail_head = h;
  if (c->slot[i].trail_n < RS_COUNT_TRAIL) c->slot[i].trail_n++;
}

/* slot i's newest trail position at or before time tb (its oldest when all are later) */
static void trail_at(const rs_counter_t *c, uint32_t i, double tb, double *t, float *x, float *y) {
  const float rt = (float)(tb - c->slot[i].t0);
  int h = c->slot[i].trail_head;
  for (int k = 0; k + 1 < c->slot[i].trail_n && c->slot[i].trail_t[h] > rt; k++) h = (h + RS_COUNT_TRAIL - 1) % RS_COUNT_TRAIL;
  *t = c->slot[i].t0 + (double)c->slot[i].trail_t[h];
  *x = c->slot[i].trail_x[h];
  *y = c->slot[i].trail_y[h];
}

/* when slot i's track crossed line l: in the trail's newest step whose ends lie on either side of it
 * (with the band it may have crossed a step or two before it is counted), else t */
static double trail_cross_time(const rs_counter_t *c, uint32_t i, int l, double t) {
  const rs_count_line_t *ln = &c->lines[l];
  int h = c->slot[i].trail_head;
  double dh = cross(ln->ax, ln->ay, ln->bx, ln->by, c->slot[i].trail_x[h], c->slot[i].trail_y[h]);
  for (int k = 0; k + 1 < c->slot[i].trail_n; k++) {
    const int g = (h + RS_COUNT_TRAIL - 1) % RS_COUNT_TRAIL;
    const double dg = cross(ln->ax, ln->ay, ln->bx, ln->by, c->slot[i].trail_x[g], c->slot[i].trail_y[g]);
    if ((dg > 0) != (dh > 0)) {
      const double u = dg != dh ? dg / (dg - dh) : 0.0;
      return c->slot[i].t0 + (double)c->slot[i].trail_t[g] + u * (double)(c->slot[i].trail_t[h] - c->slot[i].trail_t[g]);
    }
    h = g;
    dh = dg;
  }
  return t;
}

/* slot i's crossing of line l, crossed at time tc and place `at`: its event's wait begins */
static void open_add(rs_counter_t *c, uint32_t i, int l, rs_cross_how_t how, double tc, double at) {
  if (c->nopen >= RS_COUNT_OPEN_MAX) return; /* its event will be lost (events_lost) */
  const uint32_t k = c->nopen++;
  c->open[k].id = c->slot[i].id;
  c->open[k].line = (uint8_t)l;
  c->open[k].how = (uint8_t)how;
  c->open[k].after = false;
  c->open[k].t = tc;
  c->open[k].at = (float)at;
  trail_at(c, i, tc - RS_COUNT_SPOT_S, &c->open[k].tb, &c->open[k].xb, &c->open[k].yb);
  c->open[k].due = tc + RS_COUNT_SPOT_S;
}

static int open_find(const rs_counter_t *c, uint32_t id, int l) {
  for (uint32_t k = 0; k < c->nopen; k++)
    if (c->open[k].id == id && c->open[k].line == l) return (int)k;
  return -1;
}

/* open entry k done: the last takes its place */
static void open_remove(rs_counter_t *c, int k) { c->open[k] = c->open[--c->nopen]; }

/* track id's crossing of line l taken back: no event */
static void open_drop(rs_counter_t *c, uint32_t id, int l) {
  const int k = open_find(c, id, l);
  if (k >= 0) open_remove(c, k);
}

/* slot i at (x, y) at time t: the position after each of its open crossings once RS_COUNT_SPOT_S past it */
static void open_after(rs_counter_t *c, uint32_t i, double t, double x, double y) {
  for (uint32_t k = 0; k < c->nopen; k++) {
    if (c->open[k].id != c->slot[i].id || c->open[k].after || t < c->open[k].due) continue;
    c->open[k].after = true;
    c->open[k].ta = t;
    c->open[k].xa = (float)x;
    c->open[k].ya = (float)y;
  }
}

/* slot i's crossing of line l in direction dir tallied under class cls: its event */
static void open_event(rs_counter_t *c, uint32_t i, int l, int dir, unsigned cls) {
  const int k = open_find(c, c->slot[i].id, l);
  if (k < 0 || c->nevents >= RS_COUNT_EVENTS_MAX) {
    c->events_lost++;
    if (k >= 0) open_remove(c, k);
    return;
  }
  rs_count_event_t *e = &c->events[c->nevents++];
  e->t = c->open[k].t;
  e->track = c->slot[i].id;
  e->line = (uint8_t)l;
  e->dir = (int8_t)(dir > 0 ? 1 : -1);
  e->cls = (uint8_t)cls;
  e->how = c->open[k].how;
  e->at = c->open[k].at;
  if (c->open[k].how == RS_CROSS_HIDDEN) {
    e->speed = c->slot[i].speed; /* what the track reports now */
  } else { /* before and after, or the last position when tallied sooner */
    const bool after = c->open[k].after;
    const double ta = after ? c->open[k].ta : c->slot[i].t_xy, dt = ta - c->open[k].tb;
    const double dx = (after ? c->open[k].xa : c->slot[i].x) - c->open[k].xb;
    const double dy = (after ? c->open[k].ya : c->slot[i].y) - c->open[k].yb;
    e->speed = dt >= 0.3 ? (float)(hypot(dx, dy) / dt) : -1.0f;
  }
  open_remove(c, k);
}

/* A hidden crossing (found from where a track was first seen and where it
 * was at its first confirmed frame) whose track reports standing still
 * (speed 0) when it is tallied (class_delay_s after the track's first
 * pending crossing was found; a delay under HIDDEN_STILL_S is no time to
 * tell, and nothing is taken back then) is taken back:
 * what looked like travel past the line was its box growing as more of the
 * vehicle came into view (a van waiting 40 m off, uncovered as the car before
 * it moved off). Measured in docs/tracking.md (counting). */
#define HIDDEN_STILL_S 1.0
static bool standing(const rs_counter_t *c, const rs_track_t *tr) {
  return c->class_delay_s >= HIDDEN_STILL_S && tr->speed <= 0.0f;
}

/* Nor does one stand whose track, when it is due to be tallied, moves across
 * line l the other way at HIDDEN_MIN_SPEED or more (vel: its reported
 * velocity, in the lines' frame; NULL: not known): its first boxes grew the
 * wrong way as the vehicle came into view (on the far side of a line, the
 * box of a car coming towards it grew away from it, and its path run back
 * crossed the line the other way), and the line is left to it to cross. */
static bool against(const rs_counter_t *c, int l, const double *vel, int dir) {
  if (vel == NULL || !(c->class_delay_s >= HIDDEN_STILL_S)) return false;
  const rs_count_line_t *ln = &c->lines[l];
  const double across = ((ln->bx - ln->ax) * vel[1] - (ln->by - ln->ay) * vel[0]) / line_len(ln); /* > 0: forward */
  return fabs(across) >= HIDDEN_MIN_SPEED && (across > 0) != (dir > 0);
}

/* slot i's pending crossings of the lines in mask, tallied under its class
 * (those on a prediction only when `all`: the track has ended); still: its
 * track stands (standing()), its hidden ones are taken back; vel: its
 * reported velocity (NULL: not known), a hidden one it goes against
 * (against()) is taken back too */
#define ALL_LINES 0xffffu
static void tally_pending(rs_counter_t *c, uint32_t i, uint16_t mask, bool all, bool still, const double *vel) {
  for (int l = 0; l < c->nlines && c->slot[i].pending; l++) {
    const uint16_t bit = (uint16_t)(1u << l);
    if (!(mask & bit) || !(c->slot[i].pending & bit) || (!all && (c->slot[i].predicted & bit))) continue;
    const int dir = (c->slot[i].pending_fwd & bit) ? 1 : -1;
    const bool hidden = (c->slot[i].hidden & bit) != 0, back = hidden && !still && against(c, l, vel, dir);
    if (hidden && (still || back)) { /* a hidden crossing of a track standing still, or going the other way */
      c->hidden--;
      if (back) c->hidden_reversed++;
      else c->hidden_still++;
      unremember(c, l, c->slot[i].id);
      open_drop(c, c->slot[i].id, l);
      c->slot[i].counted &= (uint16_t)~bit; /* it never crossed: it may yet, driving off */
    } else {
      tally(c, l, dir, c->slot[i].cls);
      open_event(c, i, l, dir, c->slot[i].cls);
    }
    c->slot[i].pending &= (uint16_t)~bit;
    c->slot[i].pending_fwd &= (uint16_t)~bit;
    c->slot[i].predicted &= (uint16_t)~bit;
    c->slot[i].hidden &= (uint16_t)~bit;
    c->pending--;
  }
}

#define UNSEEN_MIN_SPEED 1.0 /* m/s: a slower unseen track is not followed */

/* slot i's track is confirmed but unseen this frame (coasting, or lost and
 * kept for re-acquisition), predicted at (x, y): within unseen_s of its last
 * update, a crossing of its prediction is held as pending on a prediction */
static void unseen_crossings(rs_counter_t *c, uint32_t i, const rs_track_t *tr, double x, double y, double t) {
  if (!c->slot[i].confirmed || !(c->unseen_s > 0) || t - tr->t_update > c->unseen_s ||
      tr->hits < RS_COUNT_UNSEEN_MIN_HITS || hypot(tr->x[2], tr->x[3]) < UNSEEN_MIN_SPEED)
    return;
  for (int l = 0; l < c->nlines; l++) {
    const uint16_t bit = (uint16_t)(1u << l);
    if (c->slot[i].counted & bit) continue;
    const int dir = crosses(&c->lines[l], c->slot[i].x, c->slot[i].y, x, y);
    if (dir == 0) continue;
    double u, s;
    meet(&c->lines[l], c->slot[i].x, c->slot[i].y, x, y, &u, &s);
    mark_counted(c, i, bit, dir);
    const double tc = trail_cross_time(c, i, l, t);
    /* the vehicle's new track counted it already; a walker's, not another walker of a file (one first
     * seen before this one was last seen: people walk in files, a track's new one starts after it is lost) */
    const bool dup = walker_paced(tr) ? counted_near(c, l, tc, s, dir, HIDDEN_DT, NEAR_NEWER, tr->id, tr->t_update - NEWER_SLACK_S)
                                      : counted_near(c, l, tc, s, dir, HIDDEN_DT, NEAR_ANY, 0, 0.0);
    if (dup) {
      c->unseen_dup++;
      continue;
    }
    remember(c, l, tc, s, dir, tr, vehicle_sized(tr));
    if (!c->slot[i].pending) c->slot[i].t_tally = t + c->class_delay_s;
    c->slot[i].pending |= bit;
    c->slot[i].predicted |= bit;
    if (c->band_m > 0) note_side(c, i, l, dir); /* past the line now, though within its band when seen again */
    if (dir > 0) c->slot[i].pending_fwd |= bit;
    c->pending++;
    c->unseen++;
    open_add(c, i, l, RS_CROSS_UNSEEN, tc, s);
  }
  c->slot[i].x = x;
  c->slot[i].y = y;
  c->slot[i].t_xy = t;
}

/* A vehicle-sized track seen crossing line l (at t, s along it, direction dir): a crossing counted
 * for another vehicle-sized track within same_s and HIDDEN_DS is its vehicle's, and this one is its
 * second track, not counted; unless that one was found on a prediction and is still held (unseen_yield):
 * the track followed there while unseen was lost, and whether its vehicle was this one (taken up by a
 * new track) or not (its prediction ran on along the lane, over the line, as another vehicle came), the
 * seen crossing is the one to count. The held one is taken back (its track's line stays counted: were
 * it seen again past the line, that was this crossing). Whether this one counts: false when a crossing
 * near it stands. At most RS_COUNT_RECENT taken back. */
/* slot i's crossing of line l held on a prediction, taken back (its counted bit is the caller's) */
static void drop_held(rs_counter_t *c, uint32_t i, int l) {
  const uint16_t bit = (uint16_t)(1u << l);
  c->slot[i].pending &= (uint16_t)~bit;
  c->slot[i].pending_fwd &= (uint16_t)~bit;
  c->slot[i].predicted &= (uint16_t)~bit;
  c->pending--;
  c->unseen--;
  unremember(c, l, c->slot[i].id);
  open_drop(c, c->slot[i].id, l);
}

static bool yield_unseen(rs_counter_t *c, int l, double t, double s, int dir, uint32_t id) {
  const uint16_t bit = (uint16_t)(1u << l);
  for (int guard = 0; guard < RS_COUNT_RECENT; guard++) {
    const int k = near_crossing(c, l, t, s, dir, c->same_s, NEAR_OTHER_VEHICLE, id, 0.0);
    if (k < 0) return true;
    const int32_t j = c->unseen_yield ? slot_of(c, c->recent[l][k].id) : -1;
    if (j < 0 || !(c->slot[j].predicted & bit) || !(c->slot[j].pending & bit)) return false;
    drop_held(c, (uint32_t)j, l);
    c->unseen_yielded++;
  }
  return false;
}

static void close_interval(rs_counter_t *c, double t_end) {
  c->cur.t_end = t_end;
  c->closed = c->cur;
  c->intervals++;
}

static void forget(rs_counter_t *c, uint32_t i) {
  /* backward-shift deletion: later entries of the chain move up */
  uint32_t j = i;
  for (int guard = 0; guard < RS_COUNT_SLOTS; guard++) {
    c->slot[i].id = 0;
    for (;;) {
      j = (j + 1) & (RS_COUNT_SLOTS - 1);
      if (c->slot[j].id == 0) return;
      const uint32_t h = hash_id(c->slot[j].id);
      /* j's entry may fill i when its home is not in (i, j] (cyclically) */
      if (i <= j ? (h <= i || h > j) : (h <= i && h > j)) break;
    }
    c->slot[i] = c->slot[j];
    i = j;
  }
}

bool rs_count_frame(rs_counter_t *c, const rs_track_list_t *tl, double t) {
  bool closed = false;
  if (c->cur.t_start < 0) {
    c->cur.t_start = t;
    c->cur.t_end = (floor(t / c->interval_s) + 1.0) * c->interval_s; /* boundaries on multiples of the interval */
  } else if (t >= c->cur.t_end) {
    const double end = c->cur.t_end;
    close_interval(c, end);
    memset(&c->cur, 0, sizeof c->cur);
    c->cur.t_start = end;
    c->cur.t_end = (floor(t / c->interval_s) + 1.0) * c->interval_s;
    closed = true;
  }
  c->frame_no++;
  c->nevents = 0;
  if (c->t_first < 0) c->t_first = t;
  uint32_t occupancy[RS_COUNT_ZONES] = {0};
  const uint32_t n = tl->count < RS_TRACK_MAX ? tl->count : RS_TRACK_MAX;
  for (uint32_t k = 0; k < n; k++) {
    const rs_track_t *tr = &tl->track[k];
    if (tr->id == 0) continue;
    double x = tr->x[0], y = tr->x[1], vel[2] = {tr->vel[0], tr->vel[1]};
    if (c->have_pose) {
      const double sx = c->rot[0] * x + c->rot[1] * y + c->trans[0], sy = c->rot[2] * x + c->rot[3] * y + c->trans[1];
      x = sx;
      y = sy;
      const double vx = c->rot[0] * vel[0] + c->rot[1] * vel[1], vy = c->rot[2] * vel[0] + c->rot[3] * vel[1];
      vel[0] = vx;
      vel[1] = vy;
    }
    uint32_t i = hash_id(tr->id);
    int guard = 0;
    while (c->slot[i].id != 0 && c->slot[i].id != tr->id && guard++ < RS_COUNT_SLOTS) i = (i + 1) & (RS_COUNT_SLOTS - 1);
    if (c->slot[i].id != tr->id && tr->state == RS_TRACK_LOST) continue; /* (a counter started mid-run) */
    if (c->slot[i].id != tr->id) {
      if (c->slot[i].id != 0) { /* full: cannot happen with at most RS_TRACK_MAX tracks listed */
        c->forgotten_full++;
        continue;
      }
      c->slot[i].id = tr->id;
      c->slot[i].counted = 0;
      c->slot[i].pending = c->slot[i].pending_fwd = c->slot[i].predicted = c->slot[i].hidden = 0;
      c->slot[i].cls = 0;
      c->slot[i].inside = zones_at(c, x, y); /* inside when first seen: not an entry */
      c->slot[i].x = x; /* where it was first seen: crossings while tentative count when it is confirmed */
      c->slot[i].y = y;
      c->slot[i].t0 = t;
      c->slot[i].x0 = x;
      c->slot[i].y0 = y;
      c->slot[i].t_xy = t;
      c->slot[i].trail_n = c->slot[i].trail_head = 0;
      c->slot[i].confirmed = false;
      c->slot[i].born = tr->state == RS_TRACK_TENTATIVE;
      c->slot[i].side_known = c->slot[i].side_left = 0;
      c->slot[i].counted_fwd = c->slot[i].counted_both = 0;
      for (int l = 0; l < c->nlines && c->band_m > 0; l++) {
        const int side = side_of(c, l, x, y);
        if (side != 0) note_side(c, i, l, side);
      }
    }
    c->slot[i].frame = c->frame_no;
    trail_add(c, i, t, x, y);
    c->slot[i].speed = tr->speed;
    if (c->slot[i].pending) open_after(c, i, t, x, y);
    if (tr->state == RS_TRACK_CONFIRMED) c->slot[i].cls = (uint8_t)((unsigned)tr->cls < RS_CLASS_COUNT ? tr->cls : 0);
    if (c->slot[i].pending && t >= c->slot[i].t_tally) tally_pending(c, i, ALL_LINES, false, standing(c, tr), vel);
    if (tr->state != RS_TRACK_CONFIRMED) { /* tentative, or coasting (lost) on a prediction */
      if (tr->state != RS_TRACK_TENTATIVE) unseen_crossings(c, i, tr, x, y, t);
      continue;
    }
    const bool first_confirmed = !c->slot[i].confirmed, vehicle = vehicle_sized(tr);
    c->slot[i].confirmed = true;
    /* seen again: a crossing on its prediction stands, unless it is back before the line */
    uint16_t undone = 0;
    for (int l = 0; l < c->nlines && c->slot[i].predicted; l++) {
      const uint16_t bit = (uint16_t)(1u << l);
      if (!(c->slot[i].predicted & bit)) continue;
      c->slot[i].predicted &= (uint16_t)~bit;
      const int back = crosses(&c->lines[l], c->slot[i].x, c->slot[i].y, x, y);
      if (back != 0 && (back > 0) != ((c->slot[i].pending_fwd & bit) != 0)) {
        drop_held(c, i, l);
        c->slot[i].counted &= (uint16_t)~bit;
        c->unseen_undone++;
        if (c->band_m > 0) note_side(c, i, l, back); /* before it again: crossing it, seen, counts */
        undone |= bit;
      }
    }
    for (int l = 0; l < c->nlines; l++) {
      const double px = c->slot[i].x, py = c->slot[i].y;
      double u, s = 0, tc = t;
      int dir = 0;
      rs_cross_how_t how = RS_CROSS_SEEN;
      if (c->band_m > 0) {
        dir = band_cross(c, i, l, x, y, &s); /* (the sides kept current on every line) */
        const uint16_t bit = (uint16_t)(1u << l);
        const bool back = dir != 0 && (c->slot[i].pending & bit) && !(undone & bit) &&
                          (dir > 0) != ((c->slot[i].pending_fwd & bit) != 0); /* back before its crossing was tallied */
        if (back && !vehicle && !(c->slot[i].counted_both & bit)) {
          /* a walker's track: its first crossing of this line stands, tallied now, and it crosses back
           * (walked_back below; two walkers meeting on a line may leave with each other's tracks, each one
           * over and back) */
          tally_pending(c, i, bit, false, standing(c, tr), vel);
          c->walked_early++;
        } else if (back) {
          if (c->slot[i].predicted & bit) c->unseen--;
          c->slot[i].pending &= (uint16_t)~bit;
          c->slot[i].pending_fwd &= (uint16_t)~bit;
          c->slot[i].predicted &= (uint16_t)~bit;
          if (c->slot[i].counted_both & bit) { /* its crossing back: the first, tallied, stands */
            c->slot[i].counted_both &= (uint16_t)~bit;
            c->walked_back--;
          } else {
            c->slot[i].counted &= (uint16_t)~bit;
          }
          c->pending--;
          c->back_undone++;
          unremember(c, l, tr->id);
          open_drop(c, tr->id, l);
          continue;
        }
        if ((c->slot[i].counted | undone) & bit) {
          if ((undone & bit) || !counts_back(c, i, bit, dir, vehicle)) continue;
          c->slot[i].counted_both |= bit; /* crossed back after its crossing was tallied: counted that way too */
          c->walked_back++;
        }
      } else {
        if ((c->slot[i].counted | undone) & (1u << l)) continue;
        dir = crosses(&c->lines[l], px, py, x, y);
        if (dir != 0) meet(&c->lines[l], px, py, x, y, &u, &s);
      }
      if (dir != 0) {
        tc = trail_cross_time(c, i, l, t);
        if (vehicle && c->same_s > 0 && !yield_unseen(c, l, tc, s, dir, tr->id)) {
          c->same_dup++;
          mark_counted(c, i, (uint16_t)(1u << l), dir); /* its vehicle's: not checked again */
          continue;
        }
        remember(c, l, tc, s, dir, tr, vehicle);
      } else if (first_confirmed || (c->slot[i].born && t - c->slot[i].t0 <= c->hidden_window_s)) {
        dir = hidden_crossing(c, l, c->slot[i].t0, c->slot[i].x0, c->slot[i].y0, t, x, y, vel, &tc, &s);
        if (dir == 0) continue;
        how = RS_CROSS_HIDDEN;
        if (counted_near(c, l, tc, s, dir, HIDDEN_DT, NEAR_ANY, 0, 0.0)) {
          c->hidden_dup++;
          mark_counted(c, i, (uint16_t)(1u << l), dir); /* its vehicle's: not checked again */
          continue;
        }
        remember(c, l, tc, s, dir, tr, vehicle);
        c->hidden++;
      }
      if (dir == 0) continue;
      const uint16_t bit = (uint16_t)(1u << l);
      mark_counted(c, i, bit, dir);
      if (!c->slot[i].pending) c->slot[i].t_tally = t + c->class_delay_s;
      c->slot[i].pending |= bit;
      if (dir > 0) c->slot[i].pending_fwd |= bit;
      if (how == RS_CROSS_HIDDEN) c->slot[i].hidden |= bit;
      c->pending++;
      open_add(c, i, l, how, tc, s);
    }
    if (c->slot[i].pending && t >= c->slot[i].t_tally) tally_pending(c, i, ALL_LINES, false, standing(c, tr), vel);
    c->slot[i].x = x;
    c->slot[i].y = y;
    c->slot[i].t_xy = t;
    /* zones: the change since its last confirmed frame (or where it was first seen) */
    const uint8_t now = zones_at(c, x, y), was = c->slot[i].inside;
    const unsigned cls = (unsigned)tr->cls < RS_CLASS_COUNT ? (unsigned)tr->cls : 0;
    for (int z = 0; z < c->nzones; z++) {
      const uint8_t bit = (uint8_t)(1u << z);
      if (now & bit) occupancy[z]++;
      if ((now & bit) == (was & bit)) continue;
      if (now & bit) {
        c->cur.zone[z].entered[cls]++;
        c->zone_total[z].entered[cls]++;
      } else {
        c->cur.zone[z].exited[cls]++;
        c->zone_total[z].exited[cls]++;
      }
      c->zone_events++;
    }
    c->slot[i].inside = now;
  }
  for (int z = 0; z < c->nzones; z++) {
    c->cur.zone[z].occupancy = occupancy[z];
    if (occupancy[z] > c->cur.zone[z].occupancy_max) c->cur.zone[z].occupancy_max = occupancy[z];
    c->zone_total[z].occupancy = occupancy[z];
    if (occupancy[z] > c->zone_total[z].occupancy_max) c->zone_total[z].occupancy_max = occupancy[z];
  }
  /* tracks no longer listed are forgotten */
  for (uint32_t i = 0; i < RS_COUNT_SLOTS; i++) {
    if (c->slot[i].id == 0 || c->slot[i].frame == c->frame_no) continue;
    tally_pending(c, i, ALL_LINES, true, false, NULL); /* its crossings, under its last class */
    forget(c, i);
    if (c->slot[i].id != 0 && c->slot[i].frame != c->frame_no) i--; /* a later entry moved here: look again */
  }
  return closed;
}

bool rs_count_flush(rs_counter_t *c, double t) {
  c->nevents = 0;
  for (uint32_t i = 0; i < RS_COUNT_SLOTS; i++)
    if (c->slot[i].id != 0 && c->slot[i].pending) tally_pending(c, i, ALL_LINES, true, false, NULL);
  if (c->cur.t_start < 0) return false;
  close_interval(c, t > c->cur.t_start ? t : c->cur.t_start);
  memset(&c->cur, 0, sizeof c->cur);
  c->cur.t_start = c->cur.t_end = -1.0;
  return true;
}

/* count.c - counting lines (processing thread; no allocation).
 *
 * Per frame: every track of the list is looked up in the slot table (by id,
 * linear probing); a confirmed one whose path since its last position (or,
 * at its first confirmed frame, since where it was first seen) crosses a
 * line it was not counted on is counted; slots of tracks no longer listed
 * are freed (backward-shift deletion keeps the probing chains whole). */
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
    if (hypot(lines[i].bx - lines[i].ax, lines[i].by - lines[i].ay) < 0.1) {
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

static uint32_t hash_id(uint32_t id) { return (id * 2654435761u) & (RS_COUNT_SLOTS - 1); }

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
  const uint32_t n = tl->count < RS_TRACK_MAX ? tl->count : RS_TRACK_MAX;
  for (uint32_t k = 0; k < n; k++) {
    const rs_track_t *tr = &tl->track[k];
    if (tr->id == 0 || tr->state == RS_TRACK_LOST) continue;
    double x = tr->x[0], y = tr->x[1];
    if (c->have_pose) {
      const double sx = c->rot[0] * x + c->rot[1] * y + c->trans[0], sy = c->rot[2] * x + c->rot[3] * y + c->trans[1];
      x = sx;
      y = sy;
    }
    uint32_t i = hash_id(tr->id);
    int guard = 0;
    while (c->slot[i].id != 0 && c->slot[i].id != tr->id && guard++ < RS_COUNT_SLOTS) i = (i + 1) & (RS_COUNT_SLOTS - 1);
    if (c->slot[i].id != tr->id) {
      if (c->slot[i].id != 0) { /* full: cannot happen with at most RS_TRACK_MAX tracks listed */
        c->forgotten_full++;
        continue;
      }
      c->slot[i].id = tr->id;
      c->slot[i].counted = 0;
      c->slot[i].x = x; /* where it was first seen: crossings while tentative count when it is confirmed */
      c->slot[i].y = y;
    }
    c->slot[i].frame = c->frame_no;
    if (tr->state != RS_TRACK_CONFIRMED) continue; /* tentative, or coasting on a prediction */
    for (int l = 0; l < c->nlines; l++) {
      if (c->slot[i].counted & (1u << l)) continue;
      const int dir = crosses(&c->lines[l], c->slot[i].x, c->slot[i].y, x, y);
      if (dir == 0) continue;
      c->slot[i].counted |= (uint16_t)(1u << l);
      const unsigned cls = (unsigned)tr->cls < RS_CLASS_COUNT ? (unsigned)tr->cls : 0;
      if (dir > 0) {
        c->cur.line[l].forward[cls]++;
        c->total[l].forward[cls]++;
      } else {
        c->cur.line[l].backward[cls]++;
        c->total[l].backward[cls]++;
      }
      c->crossings++;
    }
    c->slot[i].x = x;
    c->slot[i].y = y;
  }
  /* tracks no longer listed are forgotten */
  for (uint32_t i = 0; i < RS_COUNT_SLOTS; i++) {
    if (c->slot[i].id == 0 || c->slot[i].frame == c->frame_no) continue;
    forget(c, i);
    if (c->slot[i].id != 0 && c->slot[i].frame != c->frame_no) i--; /* a later entry moved here: look again */
  }
  return closed;
}

bool rs_count_flush(rs_counter_t *c, double t) {
  if (c->cur.t_start < 0) return false;
  close_interval(c, t > c->cur.t_start ? t : c->cur.t_start);
  memset(&c->cur, 0, sizeof c->cur);
  c->cur.t_start = c->cur.t_end = -1.0;
  return true;
}

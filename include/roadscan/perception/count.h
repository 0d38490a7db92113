/* count.h - counting lines: confirmed tracks crossing lines of the site.
 *
 * A stage after the tracker (processing thread; no allocation; bounded).
 * Each line is a segment A -> B on the ground plane, in the site frame when
 * a pose is given (the sensor frame otherwise). A confirmed track crosses it
 * when the segment from its previous position to its current one meets the
 * line segment; it is counted once per line, in the direction it crossed
 * ("forward": from the right of A -> B to its left, i.e. counter-clockwise
 * about A; "backward" the other way), under its class at that moment.
 * Counts accumulate over intervals of sensor time (default 60 s); when an
 * interval ends, rs_count_frame says so and the closed interval's counts
 * are in `closed` for the sinks (LCM, CSV). Totals over the run are kept.
 *
 * Per-track memory (last position, lines already counted) lives in a fixed
 * table keyed by track id; a track no longer in the list is forgotten. */
#ifndef ROADSCAN_COUNT_H
#define ROADSCAN_COUNT_H

#include "roadscan/perception/objects.h"
#include "roadscan/perception/track.h"

#include <stdbool.h>
#include <stdint.h>

#define RS_COUNT_LINES 16
#define RS_COUNT_NAME 32
#define RS_COUNT_SLOTS (2 * RS_TRACK_MAX) /* open addressing: at most half full */

_Static_assert(RS_COUNT_LINES <= 16, "lines counted per track fit in a uint16_t mask");
_Static_assert((RS_COUNT_SLOTS & (RS_COUNT_SLOTS - 1)) == 0, "slots: a power of two");

typedef struct {
  char name[RS_COUNT_NAME];
  double ax, ay, bx, by; /* metres, site frame (sensor frame without a pose) */
} rs_count_line_t;

typedef struct {
  uint32_t forward[RS_CLASS_COUNT], backward[RS_CLASS_COUNT];
} rs_count_tally_t;

typedef struct {
  double t_start, t_end;                 /* capture time (s) */
  rs_count_tally_t line[RS_COUNT_LINES];
} rs_count_interval_t;

typedef struct {
  int nlines;
  rs_count_line_t lines[RS_COUNT_LINES];
  double interval_s;                     /* default 60 */
  bool have_pose;
  double rot[4], trans[2];               /* sensor -> site on the ground plane (from the pose's full rotation) */
  rs_count_interval_t cur, closed;       /* the open interval, the last closed one */
  rs_count_tally_t total[RS_COUNT_LINES];
  uint64_t intervals, crossings, forgotten_full;
  struct {
    uint32_t id;                         /* 0 = free */
    uint16_t counted;                    /* lines this track was counted on */
    uint32_t frame;                      /* last frame it was seen (low 32 bits) */
    double x, y;                         /* last position, site frame */
  } slot[RS_COUNT_SLOTS];
  uint32_t frame_no;
} rs_counter_t;

/* Parses "NAME X1 Y1 X2 Y2" (metres) into a line; RS_E_INVAL with a message. */
int rs_count_parse_line(const char *text, rs_count_line_t *out, char *err, size_t n);
/* lines: nlines (<= RS_COUNT_LINES); pose: NULL or the sensor's pose in the site;
 * interval_s > 0. RS_E_INVAL for bad arguments (a line of zero length). */
int rs_count_init(rs_counter_t *c, const rs_count_line_t *lines, int nlines, const rs_pose_t *pose, double interval_s,
                  char *err, size_t n);
/* One frame's tracks at time t (s); true when an interval closed (c->closed). */
bool rs_count_frame(rs_counter_t *c, const rs_track_list_t *tl, double t);
/* Does the step P0 -> P1 cross line l? 1 forward, -1 backward, 0 no. */
int rs_count_crosses(const rs_count_line_t *l, double x0, double y0, double x1, double y1);
/* Closes the open interval at time t (the end of the run); true when it held a crossing or time. */
bool rs_count_flush(rs_counter_t *c, double t);

#endif

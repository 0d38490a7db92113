/* count.h - counting lines: confirmed tracks crossing lines of the site.
 *
 * A stage after the tracker (processing thread; no allocation; bounded).
 * Each line is a segment A -> B on the ground plane, in the site frame when
 * a pose is given (the sensor frame otherwise). A confirmed track crosses it
 * when the segment from its previous position to its current one meets the
 * line segment; it is counted once per line (a walker's track once each
 * way, see the band below), in the direction it crossed
 * ("forward": from the right of A -> B to its left, i.e. counter-clockwise
 * about A; "backward" the other way), under its class (see the class delay
 * below).
 * Counts accumulate over intervals of sensor time (default 60 s); when an
 * interval ends, rs_count_frame says so and the closed interval's counts
 * are in `closed` for the sinks (LCM, CSV). Totals over the run are kept.
 *
 * Zones: a polygon of the site (3 to RS_COUNT_ZONE_VERTICES corners). A
 * confirmed track whose position moves from outside to inside is counted as
 * entered, from inside to outside as exited, under its class (a track first
 * seen inside entered nothing; one that vanishes inside exited nothing); the
 * confirmed tracks inside are its occupancy, and the interval keeps the
 * largest occupancy it saw. Whether a track was inside is remembered from its
 * first position, as the last position is for lines.
 *
 * Hidden crossings: a track first seen past a line, moving away from it, may
 * have crossed it unseen (a vehicle on a far lane hidden by the near lanes'
 * traffic until it is over the line). At its first confirmed frame, and at
 * each one after until `hidden_window_s` (default 2) after it was first
 * seen, its path is run back from where it was first seen, at its mean
 * velocity since then (at least 1 m/s, and not against the velocity the
 * track reports: a box growing away from the line as a vehicle coming
 * towards it comes into view), for at most `hidden_s` seconds
 * (default 3, 0 = off): when that meets a line it was not counted on, at a
 * time after the run's first frame (with the time run back stretched by 1.5:
 * a vehicle first seen soon after the run started was often pulling away
 * from the line, slower before), and the track's place along the line (below)
 * is within 2.5 m of the line's ends (a car in the road beside a sidewalk's
 * short line is not on it, whatever its first boxes' growth ran it back
 * through), it is counted as crossed there, unless a
 * crossing of that line in the same direction was counted within 1.5 s and
 * 2.5 m of it (the same vehicle, counted by the track it had before it was
 * hidden; the line is then done for this track). Where along the line: the
 * track's place along it when the crossing is found (its lane; hidden_at_track,
 * the default), not where the path run back met it: the first box of a
 * vehicle coming out from behind others is a part of it, its centre off
 * across the lane, and the mean velocity from it points across too, so the
 * path met the line in the next lane, where another vehicle's crossing took
 * it for that one's. The repeats are for a box
 * growing as the vehicle comes into view, whose centre moves little or the
 * wrong way at first; only for a track first listed tentative (born there),
 * not a lost one taken up again.
 * Every counted crossing is remembered per line (time, place along it) for
 * that check: the last RS_COUNT_RECENT.
 *
 * Class delay: a crossing is found when it happens but tallied
 * `class_delay_s` (default 2) later, under the track's class then (a car
 * seen head-on at range settles as a car once it is near): at the first frame
 * that late, when the track leaves the list, or at rs_count_flush. It lands
 * in the interval open at that moment. A hidden crossing whose track then
 * reports standing still (speed 0; with a class delay of 1 s or more) is
 * taken back (hidden_still): its travel past the line was its box growing as
 * more of a standing vehicle came into view; the line is left for it to
 * cross, driving off. So is one whose track then moves across the line the
 * other way at 1 m/s or more (hidden_reversed): its first boxes grew the
 * wrong way as it came into view, and it is yet to cross.
 *
 * A lost track (unpublished, kept by the tracker for re-acquisition) keeps
 * its memory: taken up again past a line, it crossed it.
 *
 * Unseen crossings: a confirmed track not seen this frame (coasting, or lost
 * and kept), of RS_COUNT_UNSEEN_MIN_HITS hits or more, moving at 1 m/s or
 * more, is followed on its prediction until `unseen_s` (default 2, 0 = off)
 * after its last update: a vehicle hidden by the one behind it as it drives
 * away from the sensor crosses a far line unseen and is never seen again.
 * Such a crossing is held (not tallied) until the track is seen again:
 * past the line it stands; back before it (it stopped behind something) it
 * is taken back; or until the track ends, when it is tallied. It is not
 * counted when a crossing of the line in its direction was counted within
 * 1.5 s and 2.5 m (the vehicle's new track), as for hidden crossings; for a
 * walker's track (not vehicle-sized, slower than RS_COUNT_WALKER_PACE) only
 * when the track that counted it was first seen after this one was last
 * seen (the walker's new track): people walk in files, and the one ahead
 * crossed there a moment before.
 *
 * Second tracks: a vehicle-sized track (RS_COUNT_VEHICLE_M long or more)
 * crossing a line within `same_s` (default 1.5, 0 = off) and 2.5 m along it
 * of a crossing counted in its direction for another vehicle-sized track is
 * that vehicle's second track (split off it, or taking over from it): not
 * counted (`same_dup`). Walkers and cyclists are not: two people cross a
 * sidewalk line side by side. Unless that crossing was on a prediction and is
 * still held (`unseen_yield`, default on): a lost track's prediction runs on
 * along its lane whatever its vehicle did; the seen crossing counts and the
 * held one is taken back (`unseen_yielded`; its track's line stays counted).
 *
 * The band: a seen track crosses a line when it is seen more than `band_m`
 * (default 0.3, 0 = at the line) past it, having last been seen more than
 * that before it. The box centre of a standing vehicle wanders by tenths of
 * a metre; a car stopped on a line is counted once, when it drives on, not
 * each time its centre steps over. Where along the line: where the last step
 * met it, else the track's place along it; beyond the segment's ends it is
 * not a crossing. A track seen back past the band before its crossing is
 * tallied (the class delay) takes the crossing back, and may cross again: a
 * track running on over a line as its vehicle stops short of it, then seen
 * where the vehicle stands (`back_undone`). Crossings on a prediction and
 * hidden crossings are found as before; the band's sides are those of the
 * positions the track was seen at (first seen within a band, it has no side
 * of that line until it is seen clear of it), and of its crossings on a
 * prediction (past the line, though seen again within its band; back
 * before it again when such a crossing is taken back).
 * With the band, a track not vehicle-sized (a walker's, a cyclist's) that
 * crosses back is counted that way too, once (`walked_back`): people turn
 * back on a crosswalk or a sidewalk, and two walkers passing on a line may
 * leave with each other's tracks, each track then crossing once each way.
 * Back before its first crossing was tallied, that one is not taken back
 * (as a vehicle's is) but tallied then (`walked_early`); seen back over the
 * line before the second crossing is tallied, that one is taken back and
 * the first stands. A vehicle's track crossing back is not counted (it took
 * another vehicle's place, or its centre wandered).
 *
 * Crossing events: each crossing tallied is also one event in `events` of
 * the frame that tallied it (nevents of them; rs_count_flush's too): when it
 * crossed (the step's share of the frame interval), which line and way,
 * where along it (the crossing's place, as the second-track check has it),
 * the track's id, its class (the tally's), how it was found (seen, hidden:
 * run back, unseen: on a prediction) and its spot speed. The spot speed is
 * the distance between the track's positions about RS_COUNT_SPOT_S before
 * and after the crossing over the time between them: the class delay has
 * them both by the time the crossing is tallied, and a mean over a window
 * centred on the crossing is the speed at it for a vehicle speeding up or
 * braking evenly (the filter's velocity lags it). The position before comes
 * from a trail of the track's last positions (RS_COUNT_TRAIL, at least
 * RS_COUNT_TRAIL_DT apart), the one after is taken at the first frame
 * RS_COUNT_SPOT_S after the crossing (or the last one, when the crossing is
 * tallied sooner: it ended, or a shorter class delay); under 0.3 s apart,
 * the speed is unknown (-1). A hidden crossing was before the track was
 * seen: its speed is the one the track reports when the crossing is
 * tallied (the mean velocity its path was run back at comes from a partial
 * first box, and so do positions just after it was found: on the rush
 * captures 2.4 and 2.7 m/s RMSE, the track's later speed 1.6). What an event needs until it is
 * tallied waits in a pool of RS_COUNT_OPEN_MAX (full: the crossing is still
 * counted, its event is not: `events_lost`); more than RS_COUNT_EVENTS_MAX
 * in one frame are counted in `events_lost` too.
 *
 * Per-track memory (last position, lines already counted, zones inside) lives
 * in a fixed table keyed by track id; a track no longer in the list is forgotten. */
#ifndef ROADSCAN_COUNT_H
#define ROADSCAN_COUNT_H

#include "roadscan/perception/objects.h"
#include "roadscan/perception/track.h"

#include <stdbool.h>
#include <stdint.h>

#define RS_COUNT_LINES 16
#define RS_COUNT_ZONES 8
#define RS_COUNT_ZONE_VERTICES 16
#define RS_COUNT_NAME 32
#define RS_COUNT_SLOTS (2 * RS_TRACK_MAX) /* open addressing: at most half full */
#define RS_COUNT_RECENT 32                /* crossings remembered per line (hidden crossings' check) */
#define RS_COUNT_HIDDEN_S 3.0             /* default hidden_s */
#define RS_COUNT_HIDDEN_WINDOW_S 2.0      /* default hidden_window_s */
#define RS_COUNT_CLASS_DELAY_S 2.0        /* default class_delay_s */
#define RS_COUNT_UNSEEN_S 2.0             /* default unseen_s */
#define RS_COUNT_SAME_S 1.5               /* default same_s */
#define RS_COUNT_BAND_M 0.3               /* default band_m */
#define RS_COUNT_VEHICLE_M 2.5            /* a track this long (its full length) or longer is a vehicle's (same_s) */
#define RS_COUNT_UNSEEN_MIN_HITS 5        /* an unseen track of fewer hits is not followed (a flicker confirmed on 3) */
#define RS_COUNT_WALKER_PACE 3.0          /* m/s: a track not vehicle-sized and slower than this walks (unseen crossings) */
#define RS_COUNT_TRAIL 16                 /* positions kept per track (spot speeds) ... */
#define RS_COUNT_TRAIL_MS 95              /* ... at least this far apart (ms): 1.4 s at any frame rate */
#define RS_COUNT_SPOT_MS 1000             /* a spot speed's window: this long before and after the crossing (ms) */
#define RS_COUNT_TRAIL_DT (RS_COUNT_TRAIL_MS / 1000.0)
#define RS_COUNT_SPOT_S (RS_COUNT_SPOT_MS / 1000.0)
#define RS_COUNT_OPEN_MAX 256             /* crossings found and not yet tallied, waiting for their events */
#define RS_COUNT_EVENTS_MAX 256           /* crossing events of one frame */

_Static_assert(RS_COUNT_LINES <= 16, "lines counted per track fit in a uint16_t mask");
_Static_assert(RS_COUNT_ZONES <= 8, "zones a track is inside fit in a uint8_t mask");
_Static_assert((RS_COUNT_SLOTS & (RS_COUNT_SLOTS - 1)) == 0, "slots: a power of two");
_Static_assert((RS_COUNT_TRAIL - 1) * RS_COUNT_TRAIL_MS > RS_COUNT_SPOT_MS + 200, "the trail reaches a spot window back");
_Static_assert(RS_COUNT_TRAIL <= 255, "trail indices fit in a byte");
_Static_assert(RS_COUNT_OPEN_MAX <= 65535 && RS_COUNT_EVENTS_MAX <= 65535, "pool and events indexed by 16 bits");

typedef struct {
  char name[RS_COUNT_NAME];
  double ax, ay, bx, by; /* metres, site frame (sensor frame without a pose) */
} rs_count_line_t;

typedef struct {
  char name[RS_COUNT_NAME];
  int n;                                 /* corners, 3 .. RS_COUNT_ZONE_VERTICES */
  double x[RS_COUNT_ZONE_VERTICES], y[RS_COUNT_ZONE_VERTICES]; /* metres, site frame (sensor frame without a pose) */
} rs_count_zone_t;

typedef struct {
  uint32_t forward[RS_CLASS_COUNT], backward[RS_CLASS_COUNT];
} rs_count_tally_t;

typedef struct {
  uint32_t entered[RS_CLASS_COUNT], exited[RS_CLASS_COUNT];
  uint32_t occupancy;                    /* confirmed tracks inside at the interval's last frame */
  uint32_t occupancy_max;                /* the most at once during the interval */
} rs_zone_tally_t;

typedef struct {
  double t_start, t_end;                 /* capture time (s) */
  rs_count_tally_t line[RS_COUNT_LINES];
  rs_zone_tally_t zone[RS_COUNT_ZONES];
} rs_count_interval_t;

typedef enum { RS_CROSS_SEEN = 0, RS_CROSS_HIDDEN = 1, RS_CROSS_UNSEEN = 2 } rs_cross_how_t;
const char *rs_count_how_name(rs_cross_how_t h); /* "seen", "hidden", "unseen" */

typedef struct {
  double t;                              /* when it crossed (capture time, s) */
  uint32_t track;                        /* the track's id */
  uint8_t line;                          /* index into lines[] */
  int8_t dir;                            /* 1 forward, -1 backward */
  uint8_t cls;                           /* rs_class_t, the tally's */
  uint8_t how;                           /* rs_cross_how_t */
  float speed;                           /* spot speed (m/s), -1 unknown */
  float at;                              /* where along the line (m from its A end) */
} rs_count_event_t;

typedef struct {
  int nlines;
  rs_count_line_t lines[RS_COUNT_LINES];
  int nzones;
  rs_count_zone_t zones[RS_COUNT_ZONES];
  rs_zone_tally_t zone_total[RS_COUNT_ZONES]; /* occupancy: now; occupancy_max: over the run */
  double interval_s;                     /* default 60 */
  bool have_pose;
  double rot[4], trans[2];               /* sensor -> site on the ground plane (from the pose's full rotation) */
  rs_count_interval_t cur, closed;       /* the open interval, the last closed one */
  rs_count_tally_t total[RS_COUNT_LINES];
  uint64_t intervals, crossings, zone_events, forgotten_full;
  uint64_t hidden;                       /* of the crossings: inferred for tracks first seen past a line */
  uint64_t hidden_dup;                   /* hidden crossings not counted: the vehicle's earlier track was */
  uint64_t hidden_still;                 /* hidden crossings taken back: the track reported standing still when
                                            they were due to be tallied (what looked like travel was its box
                                            growing as more of it came into view) */
  uint64_t hidden_reversed;              /* hidden crossings taken back: the track moved across the line the other
                                            way (1 m/s or more) when they were due to be tallied (its first boxes
                                            grew the wrong way as the vehicle came into view) */
  double hidden_s;                       /* how far back a track's path is run (s; 0 = off); default RS_COUNT_HIDDEN_S */
  double hidden_window_s;                /* ... at each confirmed frame this long after it was first seen (s); RS_COUNT_HIDDEN_WINDOW_S */
  bool hidden_at_track;                  /* a hidden crossing's place along the line: the track's where it is
                                            found (true, the default), or where its path run back met it */
  double class_delay_s;                  /* a crossing is tallied this long after it, under the track's class
                                            then (s; 0 = at once); RS_COUNT_CLASS_DELAY_S */
  double unseen_s;                       /* a confirmed track unseen this long or less is followed on its
                                            prediction (s; 0 = off); RS_COUNT_UNSEEN_S */
  uint64_t unseen;                       /* of the crossings: on a prediction, the track unseen */
  uint64_t unseen_undone;                /* crossings on a prediction taken back: the track seen again before the line */
  uint64_t unseen_dup;                   /* crossings on a prediction not counted: the vehicle's (walker's) new track was */
  double same_s;                         /* a vehicle's second track crossing this soon after its first is not
                                            counted (s; 0 = off); RS_COUNT_SAME_S */
  uint64_t same_dup;                     /* crossings not counted: another track of the vehicle's was */
  bool unseen_yield;                     /* a crossing on a prediction still held gives way to another vehicle-sized
                                            track's seen within same_s (default true) */
  uint64_t unseen_yielded;               /* crossings on a prediction taken back: another track was seen crossing
                                            there (unseen_yield) */
  double band_m;                         /* a seen track crosses a line when it is seen this far past it, having
                                            been seen this far before it; back this far before the crossing is
                                            tallied takes it back (m; 0 = at the line); RS_COUNT_BAND_M */
  uint64_t back_undone;                  /* crossings taken back: the track seen back past the band before they
                                            were tallied (band_m) */
  uint64_t walked_back;                  /* of the crossings, a walker's track's second, back over a line
                                            (band_m) */
  uint64_t walked_early;                 /* ... of them, back before its first was tallied (which was then) */
  uint64_t pending;                      /* crossings found and not yet tallied (their class is settling) */
  rs_count_event_t events[RS_COUNT_EVENTS_MAX]; /* the crossings tallied this frame (or by rs_count_flush) */
  uint32_t nevents;
  uint64_t events_lost;                  /* crossings tallied without an event (pool or frame full) */
  struct {                               /* what a found crossing's event needs until it is tallied */
    uint32_t id;                         /* the track's (0: free) */
    uint8_t line, how;
    bool after;                          /* the position after has been taken */
    double t;                            /* when it crossed */
    double tb, ta;                       /* the positions' times before and after it */
    double due;                          /* the position after is taken at the first frame this late */
    float xb, yb, xa, ya;
    float at;                            /* where along the line */
  } open[RS_COUNT_OPEN_MAX];
  uint32_t nopen;                        /* entries in use are the first nopen */
  double t_first;                        /* the run's first frame (s) */
  struct {
    double t, s;                         /* when, and where along the line (m from A) */
    int dir;                             /* 1 forward, -1 backward, 0 taken back */
    uint32_t id;                         /* the track counted */
    bool vehicle;                        /* ... was vehicle-sized (RS_COUNT_VEHICLE_M) */
    double born;                         /* ... was first seen then (its t_birth, s) */
  } recent[RS_COUNT_LINES][RS_COUNT_RECENT];
  uint32_t recent_n[RS_COUNT_LINES];     /* crossings recorded (the ring holds the last RS_COUNT_RECENT) */
  struct {
    uint32_t id;                         /* 0 = free */
    uint16_t counted;                    /* lines this track was counted on */
    uint16_t pending, pending_fwd;       /* of those, not yet tallied; and which of them forward */
    uint16_t predicted;                  /* of the pending, crossed on a prediction (held until seen or ended) */
    uint16_t hidden;                     /* of the pending, hidden crossings (taken back if it stands still) */
    uint16_t side_known, side_left;      /* band_m: lines it was seen clear of, and on which side (left: forward's) */
    uint16_t counted_fwd, counted_both;  /* of the counted lines, those first crossed forward; those crossed both ways */
    double t_tally;                      /* when the pending ones are tallied */
    uint8_t cls;                         /* its class at its last confirmed frame */
    uint8_t inside;                      /* zones it is inside (as of its last confirmed frame, or first seen) */
    bool confirmed;                      /* it had a confirmed frame */
    bool born;                           /* it was tentative when first seen (not a lost track taken up again) */
    double t0;                           /* when it was first seen */
    double x0, y0;                       /* where (site frame) */
    uint32_t frame;                      /* last frame it was seen (low 32 bits) */
    double x, y;                         /* last position, site frame */
    double t_xy;                         /* ... at this time */
    float speed;                         /* the speed the track reported then */
    float trail_t[RS_COUNT_TRAIL];       /* its last positions (time after t0, site frame), a ring */
    float trail_x[RS_COUNT_TRAIL], trail_y[RS_COUNT_TRAIL];
    uint8_t trail_n, trail_head;         /* entries, the newest's index */
  } slot[RS_COUNT_SLOTS];
  uint32_t frame_no;
} rs_counter_t;

/* Parses "NAME X1 Y1 X2 Y2" (metres) into a line; RS_E_INVAL with a message. */
int rs_count_parse_line(const char *text, rs_count_line_t *out, char *err, size_t n);
/* Parses "NAME X1 Y1 X2 Y2 X3 Y3 ..." (metres, 3 to RS_COUNT_ZONE_VERTICES corners, in order around it,
 * not crossing itself) into a zone; RS_E_INVAL with a message. */
int rs_count_parse_zone(const char *text, rs_count_zone_t *out, char *err, size_t n);
/* The lines and zones a program's options collect, and the option callbacks
 * (util/opts.h RS_OPT_FUNC, .off = the field) that parse one more into them:
 * too many, or one that does not parse, is refused with a message naming the
 * option; nothing is added then. */
typedef struct {
  rs_count_line_t line[RS_COUNT_LINES];
  int n;
} rs_count_lines_t;
typedef struct {
  rs_count_zone_t zone[RS_COUNT_ZONES];
  int n;
} rs_count_zones_t;
int rs_count_opt_line(void *lines, const char *key, const char *text, char *err, size_t n);
int rs_count_opt_zone(void *zones, const char *key, const char *text, char *err, size_t n);
/* Adds zones after rs_count_init (before the first frame); RS_E_INVAL for too many, a name taken. */
int rs_count_add_zones(rs_counter_t *c, const rs_count_zone_t *zones, int nzones, char *err, size_t n);
/* Is (x, y) inside zone z (even-odd rule; on an edge counts as outside or inside, never both ways)? */
bool rs_count_inside(const rs_count_zone_t *z, double x, double y);
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

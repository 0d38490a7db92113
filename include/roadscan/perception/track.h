/* track.h - objects followed over time: ids, velocity, class.
 *
 * A stage after the object stage (processing thread; no allocation; every
 * loop bounded by the capacities below). Each frame's objects are
 * associated with the tracks, the tracks updated, born, confirmed, coasted
 * and ended.
 *
 * State: per track a constant-velocity Kalman filter on the ground plane of
 * the sensor frame, x = (px, py, vx, vy), with the full white-noise-
 * acceleration process noise (S the 2 x 2 acceleration spectral density):
 *   Q = [S dt^3/3, S dt^2/2; S dt^2/2, S dt],
 * S = q_long along the motion and q_accel across it for a track faster than
 * 1 m/s (vehicles speed up and brake along their heading), q_accel I else;
 * q_small I for a track whose box is a walker's size (shorter and narrower
 * than 1.3 m, 3 hits): a walker's velocity changes less in a second than a
 * car's can.
 * The measurement is the centre of the object's oriented box, taken at the
 * object's own time (the middle of its first and last return: a turn lasts
 * 0.1 s, a car at 15 m/s moves 1.5 m in it). Once a track knows the size of
 * what it follows (confirmed, 5 hits, at least 1.5 m long), a box smaller
 * than that size is its near part, and its centre is moved away from the
 * sensor by half what is missing; the update's noise is then meas_sd_fit
 * plus meas_sd_misfit per metre by which the box's extents miss the track's
 * size (a whole view is good to a few centimetres, a partial one is not:
 * the filter follows a vehicle that speeds up or brakes without lagging,
 * and is not pulled by a view that changes). Before that, and for gating,
 * the noise grows with the object's size (meas_sd, meas_sd_per_m). A track
 * born cut by the circle the lowest beam passes over its top inside (a car
 * waiting beside the pole) is turned onto its first whole box's axis when it
 * moves out, its velocity uncertain again (circle_whole). A young track
 * whose box grows by metres as it is uncovered starts its speed estimator
 * again at the velocity it had (uncover_restart). A young track's speed
 * estimator follows its boxes' side nearest the sensor (near_ref_m; a box
 * lying across the line of sight even when an end of it is marked hidden,
 * near_across), or else the end not marked hidden when the other is
 * (end_ref). Time
 * steps come from those capture timestamps only, never the wall clock: a
 * replay at any speed gives the same tracks.
 *
 * Association, per frame: confirmed tracks first, then tentative ones, each
 * round an optimal assignment (Hungarian algorithm) of the tracks and the
 * objects left, gated by Mahalanobis distance (chi-square, 2 degrees of
 * freedom), Euclidean distance and the speed the pairing implies. The gate
 * graph is split into connected groups; each group of at most
 * RS_TRACK_GROUP_MAX tracks and objects is solved exactly on a static cost
 * matrix, a larger one greedily (counted). A track may be left without an
 * object at miss_cost: no pairing dearer than that is made, to pair one more
 * track or at all (the matrix has a column per track for it, so it is up to
 * twice RS_TRACK_GROUP_MAX wide). Ties break by track id, then object order.
 * A moving vehicle's track takes nothing off its lane (reacq_across_m once
 * unseen, seen_across_m while seen); a walker's track takes no vehicle
 * (walked_hits, walker_reacq_s); two tracks on one vehicle end as one
 * (dup_box, twin_s).
 * - One cluster over two confirmed tracks (queued cars touching): the
 *   predicted centres of both lie in its box; neither takes it, both keep
 *   their ids and are held (predicted, kept alive, speeds kept) until they
 *   come apart (two walkers passing each other stay held while their
 *   predictions cross). Each return of such a cluster belongs to the held
 *   track whose box, predicted to the cluster's time, holds it best
 *   (rs_track_owner): the point labels carry both ids.
 * - One object split into two clusters: the one not taken whose centre lies
 *   within a taken track's box (grown by RS_TRACK_SPLIT_MARGIN), or which
 *   fits with the track's own object within the track's known size (grown by
 *   the same margin), starts no track; its returns carry that track's id.
 *   A confirmed track's size there is its full size (split_full_size): its
 *   largest smoothed box, falling slowly, as its smoothed box shrinks with a
 *   part of its object hidden.
 * - A pedestrian's track does not take an object longer than
 *   RS_TRACK_PED_MAX_LENGTH or wider than RS_TRACK_PED_MAX_WIDTH (a vehicle
 *   passing where it walked), nor is a young track that large stitched to
 *   it.
 * Lifecycle (seconds of sensor time): a track is born tentative from an
 * object of at least birth_points returns (birth_far_points for a far
 * walker-sized one clear of every vehicle); it is confirmed after
 * confirm_hits hits when it has moved confirm_move_m from where it was born
 * (a vehicle), a walker-sized one after confirm_hits + 1 hits once it has
 * moved confirm_walk_m on a straight path (confirm_cut_walk_m when it was
 * born at the lowest beam's circle: a walker coming out from under the
 * sensor), or after confirm_still_s of hits with no miss (a pedestrian
 * waiting); a tentative track missed for more than tentative_miss_s ends
 * (flickering foliage, edges and rain never confirm: they do not move and
 * do not last). A confirmed track coasts through occlusion up to coast_s,
 * its uncertainty growing; then it is lost: no longer published, but an
 * object in its gate takes it up again (a pedestrian behind a parked van
 * for 2 s keeps its id) until lost_s (a pedestrian's: lost_walker_s, when
 * longer) more have passed; then it ends, with
 * an end event (its end time: when it was last seen). A track slower
 * than still_speed, or within
 * (one standard deviation of the velocity, capped at 1 m/s) reports speed 0.
 * Heading: of the velocity when moving faster than 1 m/s, else the last one;
 * the box's axis (ambiguous by 180 degrees) is turned to it.
 * Class, from the smoothed box (length L, width W, height H, metres) and the
 * highest speed seen (V, m/s), the first rule that holds:
 *   bus: L >= 10; van/truck: L >= 5.6, or L >= 4 and max(H, T) >= 1.8,
 *   T the smoothed top above the ground (objects.h top_agl; when the ground
 *   is known: a van whose lower half is hidden shows H of a car);
 *   car: L >= 3 and W >= 1.3, or L >= 1.2 and V >= 9 (a vehicle seen edge-on);
 *   cyclist: L >= 1.2 and W < 1.2 and V >= 2;
 *   pedestrian: L < 1.3 and W < 1.3 and H <= 2.3 and Hmax >= 0.9 and V < 4,
 *   Hmax the smoothed height its returns allow (H plus the gaps to the rows
 *   above and below: a VLP-16 at 30 m sees a walker in one or two rows);
 *   else unknown (and every class while tentative).
 * Ids: a counter from 1, never reused in a run. */
#ifndef ROADSCAN_TRACK_H
#define ROADSCAN_TRACK_H

#include "roadscan/perception/objects.h"

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#define RS_TRACK_MAX 512         /* tracks alive at once */
#define RS_TRACK_GROUP_MAX 48    /* tracks or objects in one exactly solved association group */
#define RS_TRACK_ASSIGN_MAX (2 * RS_TRACK_GROUP_MAX) /* its matrix's side: tracks, objects (miss_cost) */
#define RS_TRACK_ENDED_MAX 128   /* end events per frame */
#define RS_TRACK_SPLIT_MARGIN 1.0f
#define RS_TRACK_MERGE_LEN_M 6.0f     /* merge_parts: a track this long (a bus, a truck) */
#define RS_TRACK_MERGE_PART_WID_M 0.5f /* merge_parts: parts this wide or less (a face, a piece of a side) */
#define RS_TRACK_PED_MAX_LENGTH 2.5f /* m, the longest object a pedestrian's track takes */
#define RS_TRACK_PED_MAX_WIDTH 1.5f  /* m, and the widest (a car seen end-on) */
#define RS_TRACK_EDGES_PER_TRACK 8 /* the best gated objects a track keeps per round */
#define RS_TRACK_GRID_BUCKETS 4096 /* object lookup grid (4 m cells, hashed) */
#define RS_TRACK_HOLD_MAX 4        /* held tracks one shared cluster's returns are divided between */
#define RS_TRACK_TOP_GAP 2.0f /* m: a row above an object's top this near bounds it (below_beam) */
#define RS_TRACK_FAR_BIRTHS_MAX 32 /* objects looked at for birth_far_points per frame (each against every track
                                      and object: the bound keeps a frame of far rain or leaves linear) */
#define RS_TRACK_WALKER_KEEP_MAX 60 /* s: the longest a walker's track gone into the blind circle is kept for the link */
#define RS_TRACK_STILL_WINDOW 4     /* measurements a track keeps for confirm_still_window */
#define RS_TRACK_STILL_POINTS_MIN 8 /* returns: the fast confirmation's least (a far car of 10 returns in the truth
                                     often clusters to 8 or 9) */

_Static_assert(RS_TRACK_MAX <= RS_OBJ_MAX, "a track index fits where an object index does");
_Static_assert(RS_TRACK_ASSIGN_MAX * RS_TRACK_ASSIGN_MAX <= 16384,
               "the association matrix (a group's tracks and objects, and a column per track for no object) stays small");
_Static_assert(RS_TRACK_MAX + RS_OBJ_MAX <= UINT16_MAX, "group roots fit in uint16_t");
_Static_assert((RS_TRACK_GRID_BUCKETS & (RS_TRACK_GRID_BUCKETS - 1)) == 0, "buckets: a power of two");
_Static_assert(RS_TRACK_GRID_BUCKETS <= 65536, "buckets: grid_used holds them as uint16_t");

typedef enum { RS_TRACK_TENTATIVE = 0, RS_TRACK_CONFIRMED = 1, RS_TRACK_COASTING = 2, RS_TRACK_LOST = 3 } rs_track_state_t;
typedef enum {
  RS_CLASS_UNKNOWN = 0,
  RS_CLASS_PEDESTRIAN,
  RS_CLASS_CYCLIST,
  RS_CLASS_CAR,
  RS_CLASS_VAN_TRUCK,
  RS_CLASS_BUS,
  RS_CLASS_COUNT
} rs_class_t;

typedef struct {
  double q_accel;          /* m^2/s^3, process noise (across the motion of a moving track; default 1) */
  double q_long;           /* m^2/s^3, the same along its motion (default 1) */
  double q_small;          /* m^2/s^3, both ways for a track of a walker's size (default 0.25) */
  double meas_sd;          /* m, measurement noise of a small object (default 0.15) */
  double meas_sd_per_m;    /* m of noise per m of box length (default 0.1) */
  double meas_sd_fit;      /* m, update noise of a box of the track's known size (default 0.05; 0: meas_sd and
                              meas_sd_per_m throughout) */
  double meas_sd_misfit;   /* m of update noise per m the box's extents miss that size (default 0.5) */
  double gate_chi2;        /* Mahalanobis gate, 2 dof (default 13.8: 99.9 %) */
  double gate_m;           /* Euclidean gate from the prediction (default 4) */
  double max_speed;        /* implied speed gate, m/s (default 50) */
  double init_speed_sd;    /* m/s, velocity uncertainty of a new track (default 25: unknown) */
  double init_small_speed_sd; /* the same for an object shorter than 2 m (default 5) */
  int birth_points;        /* returns an object needs to start a track (default 5) */
  int birth_far_points;    /* ... or, a walker's size, from birth_far_from_m to birth_far_to_m away (its nearest
                              return) and clear of every vehicle-sized track's and object's box by 1.5 m, this many:
                              a person on a far sidewalk seen over the cars by one row of 4 returns (default 4;
                              0 = birth_points everywhere; docs/tracking.md, lifecycle) */
  double birth_far_from_m; /* default 25 */
  double birth_far_to_m;   /* default 50; above birth_far_from_m while birth_far_points is on (rs_track_init) */
  int confirm_hits;        /* default 3 */
  double confirm_move_m;   /* default 0.8 */
  double confirm_still_s;  /* default 1.5 */
  double tentative_miss_s; /* default 0.25 */
  double coast_s;          /* default 1.0 */
  double lost_s;           /* then kept unpublished for re-acquisition (default 2.0) */
  double still_speed;      /* m/s, reported as 0 below (default 0.3) */
  double size_weight;      /* association cost per unit of |ln(points ratio)| to the track's last object, beyond
                              ln(1 + 3 / sqrt(smaller count)) (default 2) */
  double confirm_still_spread; /* a still track whose every measurement lies within this of its first
                                  (m, plus 0.5 % of the range), hit in every frame, confirms with its
                                  confirm_hits (default 0.15; 0 = only after confirm_still_s) */
  int confirm_still_window;    /* ... or, with more hits than this, when its last this many measurements
                                  (2 to RS_TRACK_STILL_WINDOW) lie within it of the first of them and no
                                  other track lies in its gate or beside it (default 3; 0 or 1 = from its
                                  first measurement only) */
  int confirm_steady;          /* 1: a tentative track hit in every frame whose last confirm_still_window
                                  measurements lie on one straight way at one pace (each within the still
                                  spread of its share of the way from the first of them to the last, the way
                                  longer than the spread), each object with the returns the still rule asks
                                  (not the standing walker's bar), confirms as a still one would, when no
                                  other track may claim it: a truck setting off at 1.5 m/s (default 1) */
  double clear_part_share;     /* a tentative track whose last object had at most this share of a track's
                                  returns is a part of that track's object, and does not keep it from the
                                  still window's and the steady rule's fast confirmation (default 0.25;
                                  0 = any track beside it does) */
  int clear_beside;            /* 1: ... and another track keeps it from them only when their boxes, on the
                                  other's axes, come within 1 m (a car in the next lane does not); 0: when
                                  their centres are within half their lengths and 1 m (default 1) */
  int clear_longer;            /* 1: ... nor by one whose box, as long as it has been seen, is shorter than the
                                  track's by more than 0.5 m: the track is no piece of it (default 1) */
  int confirm_still_points;    /* ... when its last object has this many returns or more (default 30):
                                  a vehicle waiting at the line, not leaves */
  double confirm_still_range;  /* m: beyond this range the returns needed fall with the square of the range,
                                  to no fewer than RS_TRACK_STILL_POINTS_MIN (default 20; 0 = the same
                                  everywhere) */
  int confirm_walker_points;   /* the same rule for a walker-sized track, hit in every frame for confirm_hits + 1
                                  hits, needs this many returns instead (scaled by range the same way; default 20;
                                  0 = as a vehicle) */
  int confirm_upright_points;  /* ... and this many when it stands at least 0.5 m tall (two rows or more: a
                                  person at the kerb, not the one-row sliver the beams cut off a car;
                                  scaled the same way; default 8; 0 = confirm_walker_points) */
  int confirm_pace;            /* 1: an upright walker-sized track hit in each of its first 4 frames, its
                                  measurements along one line at one pace (within 0.1 m) and within the
                                  still spread of its birth, needs only confirm_upright_points at its 4th
                                  hit (a person slowing into the crowd at a kerb); 0: off (default 1;
                                  docs/tracking.md) */
  int hidden_anchor;           /* 1: a box end beside something nearer is where the rest of the object may be
                                  (rs_object_t.occluded): its centre is placed from the other end (default 1) */
  double walker_across_m;      /* a walker-sized confirmed track moving at 0.5 m/s or more, unseen for more than
                                  0.5 s, takes no object farther across its heading than this plus half its
                                  width, plus 0.5 m a second unseen beyond 0.5 s (default 1.5; 0 = off) */
  double reacq_across_m;       /* a moving vehicle's track unseen for more than 0.5 s takes no object farther
                                  across its heading than this plus half its width, plus 0.5 m a second
                                  unseen (default 1.0; 0 = off) */
  double confirm_walk_m;       /* a walker-sized track (shorter and narrower than 1.3 m) hit in every frame
                                  confirms after confirm_hits + 1 hits once it has moved this far, on a path
                                  at least 0.8 as straight as it is long (default 0.3; 0 = off) */
  double confirm_cut_walk_m;   /* ... and this far when it was born at the circle inside which the lowest beam
                                  passes over its top (a walker coming out from under the sensor, seen as
                                  that beam's arc across it, whose centre moves at about half its speed;
                                  default 0.15; 0 = confirm_walk_m) */
  double lost_walker_s;        /* a pedestrian's track is kept this long unpublished instead, when longer
                                  than lost_s: walkers stay hidden behind passing and queued vehicles
                                  longer than vehicles do behind each other (default 4.0) */
  int below_beam;              /* 1: a track of known size, seen whole before, partly nearer the sensor than its
                                  lowest beam reaches at the track's top, is measured by the part that beam can
                                  see; its top is midway between its returns' top and the row above (default 1;
                                  docs/tracking.md) */
  int still_lane;              /* 1: a standing vehicle's track (slower than 0.5 m/s) unseen for over 0.5 s whose
                                  side views agree on an axis takes no object farther across that axis than
                                  reacq_across_m plus half its width plus a tenth of how far along it (the
                                  vehicle waiting in the next lane; default 1; docs/tracking.md) */
  int still_coast;             /* 1: a vehicle's track (size known, 2.5 m long or more) that has reported no speed
                                  at any update for 1 s is predicted where it stands while unseen (its velocity
                                  set to 0 when first unseen), not on at the velocity its filter kept from views
                                  that came and went (default 1; docs/tracking.md) */
  int still_reverse;           /* 1: a vehicle's track (size known, 2.5 m long or more) that has moved faster than
                                  2 m/s, first unseen with a velocity pointing back against the way it moved so, is
                                  predicted where it stands (its velocity set to 0): vehicles in traffic do not
                                  back up; that velocity is a box cut at one end (default 1; docs/tracking.md) */
  int queue_coast;             /* 1: a hidden vehicle's track (2.5 m long or more, 1 s old) predicted faster than 1 m/s
                                  keeps its front 1 m behind the rear of the vehicle ahead in its lane (seen this
                                  frame, or standing and unseen for coast_s at most; 1 m ahead or more when it was
                                  last seen), at no more than that one's speed: it does not drive through it
                                  (default 1; docs/tracking.md) */
  int brake_coast;             /* 1: a vehicle's track braking when last seen (its speed estimator's
                                  acceleration along its velocity, 0.5 m/s^2 or more; not at the blind
                                  circle's edge) is predicted braking at that rate while unseen, to a stop,
                                  not on at its last speed (default 1; docs/tracking.md) */
  double blind_s;              /* a track last seen at the edge of the circle its top is below the lowest beam
                                  in is kept, unpublished, until this long after it was last seen, and a young moving track born at the
                                  circle's other side, in its lane, heading away from it, takes its id: a
                                  vehicle pulling away from the line beside the sensor, unseen while it
                                  passes it (default 8.0; 0 = off; docs/tracking.md) */
  int split_object_axis;       /* 1: a free object is also a split part of a track when it fits with the track's
                                  object in the track's size on that object's own axes, when the object is at
                                  least 2 m long and 1.8 times as long as wide (a turning car seen as two parts,
                                  the track's heading behind the turn; default 1; docs/tracking.md) */
  int split_near_circle;       /* 1: for a vehicle's track whose box reaches within 3 m of the lowest beam's reach,
                                  the same fit on any axis (every 5 degrees): a car turning around the sensor's
                                  pole, seen as its two ends (default 1; docs/tracking.md) */
  int blind_turn;              /* 1: the blind-circle link also takes a young track that came out along a way
                                  turning off the old one's: the old track's line and the young one's meeting
                                  ahead of both, at 45-135 degrees (a car turning at the sensor's corner;
                                  default 1; docs/tracking.md) */
  int walked_hits;             /* a track that looked and moved like a walker in this many updates (its shape a
                                  pedestrian's, at most 1 m long and 0.1 m wide or more, at 0.5-3 m/s) takes
                                  no object of a vehicle's size from then on, whatever its box becomes, and
                                  no young vehicle-sized track is stitched to it (default 10; 0 = only while
                                  its shape is a pedestrian's; docs/tracking.md) */
  int speed_imm;               /* 1: the speed and velocity a vehicle's track reports are the speed estimator's
                                  (constant velocity and constant acceleration mixed; rs_track_imm_t), not
                                  the constant-velocity filter's, which lags a vehicle speeding up or
                                  braking (default 1; docs/tracking.md) */
  int imm_birth_wide;          /* 1: the speed estimator starts with its velocity as uncertain as init_speed_sd
                                  whatever the size of a track's first box (a vehicle is often born on a short
                                  one: its front, one row); 0: as the filter's, init_small_speed_sd for a box
                                  under 2 m (default 1; docs/tracking.md) */
  int misfit_own;              /* 1: when a box's axis is over 8 degrees off its track's heading, the speed
                                  estimator's update noise takes the lesser of the box's misfit on the track's
                                  axes and on its own (a whole view on a wrong heading is not a bad
                                  measurement); 0: on the track's axes only (default 1; docs/tracking.md) */
  double q_jerk;               /* m^2/s^5, the constant-acceleration model's jerk density (default 1) */
  double turn_rate;            /* rad/s: a vehicle's track whose velocity turns faster than this (rs_track_turn_rate())
                                  is predicted along a circle at that rate, not a straight line (a coordinated
                                  turn of known rate); 0 = always straight (the default: measured no better
                                  overall, docs/tracking.md, Turning vehicles) */
  int dup_box;                 /* 1: a track unseen this frame and predicted inside the box of an older moving
                                  vehicle's track seen this frame, moving alike, is a part of that vehicle: ended
                                  as a duplicate (default 1) */
  double near_ref_m;           /* m: while a track is younger than near_ref_s, the speed estimator follows
                                  the side of its boxes nearest the sensor, not their centre, as long as
                                  that side is farther than this (a vehicle coming into view grows away
                                  from the sensor); 0 = off (default 25; docs/tracking.md) */
  double near_ref_s;           /* s: the age up to which near_ref_m and end_ref apply (default 2; 0 = off) */
  int near_across;             /* 1: a box lying across the line of sight (its axis over 45 degrees off the
                                  direction to the sensor) is measured by its near side (near_ref_m) even when
                                  an end of it is marked hidden: its ends are beside the near side, not at it;
                                  0: by its centre then (default 1) */
  int end_ref;                 /* 1: while a track is younger than near_ref_s and near_ref_m does not apply,
                                  the speed estimator follows the end of its box along the track's axis that
                                  is not marked hidden when the other is (the seen end moves with the
                                  vehicle; the box grows at the hidden one), the centre otherwise; a box
                                  grown at its hidden end while followed so does not restart the estimator
                                  (uncover_restart); 0: the centre (default 1) */
  double twin_s;               /* s: two tracks, confirmed or coasting, within 50 m, both seen in the last 0.25 s,
                                  moving at 2 m/s or more with velocities within 15 degrees and 2 m/s, whose
                                  boxes overlap by more than 0.5 m along the older one's heading with their
                                  centres across it nearer than half the wider box, for this long, follow one
                                  vehicle: the younger one ends as a duplicate, the older one taking its
                                  object (two vehicles' boxes never overlap; 0 = off; default 0.3;
                                  docs/tracking.md) */
  double walker_reacq_s;       /* s: a track seen only as a walker's body (10 hits, its full box at most 1 m long and
                                  0.2 m wide or more), unseen for longer than this, takes no vehicle-sized object
                                  of over 4 times its last returns (a car coming out of the circle below the
                                  lowest beam, where a walker went in; 0 = off; default 0.3; docs/tracking.md) */
  int circle_whole;            /* 1: a track born at the circle inside which the lowest beam passes over its object's
                                  top (a car waiting beside the pole), the first time it moves out (over 1 m/s,
                                  away from the sensor) with a whole vehicle's box (3 m by 1.2 m or more) whose
                                  axis is within 60 degrees of its velocity, takes that axis as its heading, its
                                  velocity turned onto it and as uncertain as at birth, and its speed estimator
                                  starts again (the boxes of a car coming out of that circle are an arc of the
                                  lowest ring over its roof, then the roof's part beyond it: they move at half
                                  its speed and at an angle to it; default 1; docs/tracking.md) */
  int uncover_restart;         /* 1: a track whose second or third object is over 1 m longer than its last one,
                                  which was marked hidden at an end (something nearer beside it: a vehicle
                                  uncovered as that moves off), starts its speed estimator again there at 0
                                  m/s, as uncertain as at birth (init_speed_sd): the jump of the box's centre
                                  is not speed; the filter and the ids untouched; 2: the same, at the velocity
                                  the estimator had before that object, not 0 (default 2; docs/tracking.md) */
  int merge_parts;             /* 1: a long vehicle's track (full length RS_TRACK_MERGE_LEN_M or more) is updated by
                                  its object together with the free thin parts (RS_TRACK_MERGE_PART_WID_M wide or
                                  less) that fit with it in its size on its axes and lie in no other track's
                                  predicted box: a bus far off seen as its front face and pieces of its side at a
                                  grazing angle, whose track followed the pieces (default 1; docs/tracking.md) */
  double tent_claim_m;         /* m: a walker-sized object within TENT_CLAIM_NEAR_M of the prediction of a tentative
                                  walker's track hit in the last frame, 3 hits or more, is not taken by a confirmed
                                  track predicted this much farther from it (confirmed tracks choose first: a walker's
                                  track that walked on past a standing walker took the one a tentative track had
                                  held for a second; 0 = off; default 0.5; docs/tracking.md) */
  double merge_front_m;        /* m: merge_parts takes no part that stands beside its vehicle's object (its centre
                                  within the object's length, on the object's own axes when it is long and thin, else
                                  the track's) on the sensor's side, more than this far out from the object's near
                                  side: a walker between a truck passing the pole and the sensor is not a piece of
                                  the truck (0 = off; default 1; docs/tracking.md) */
  double seen_across_m;        /* m: a moving vehicle's track of known size, seen within the last 0.5 s, within 80 m
                                  of the sensor and not turning (under 0.1 rad/s), takes no object farther across
                                  its heading from its prediction than this (the next lane is 3-3.7 m over: a
                                  cluster of the vehicle there, or of both, is not this one; 0 = off; default 2;
                                  docs/tracking.md) */
  double kin_accel;            /* m/s^2: a young track that no gate gave to an unseen track is a vehicle's unseen
                                  for a second or more when it lies in that vehicle's lane, between its prediction
                                  and where it would be had it sped up at this acceleration since it was last seen
                                  (a car pulling away in a queue behind a bus), or, for a bus or a truck, is its
                                  rear part where it may be having braked (0 = off; default 2.5; docs/tracking.md,
                                  Kinematic re-acquisition) */
  int walker_part;             /* 1: a walker's track (a pedestrian by its shape, or walked like one) takes no object
                                  lying in the box of a moving vehicle's track (confirmed or coasting, 3 m long or more, 2 m/s
                                  or faster, seen within 0.3 s), predicted to the object's time and grown by 0.5 m:
                                  a part of that vehicle split off by the beams (default 1; docs/tracking.md) */
  int blind_walker;            /* 1: a walker's track gone into the blind circle under the sensor takes nothing before
                                  the point of its way nearest the sensor, and is linked to a young walker's track born
                                  at the circle's other side on its way, moving that way, when the time between fits the
                                  way's length at its walking speed (of several, blind_walker_fifo says which; default 1;
                                  docs/tracking.md, The blind circle) */
  double blind_walker_s;       /* s: with blind_walker, how long a walker's track gone into the blind circle is kept
                                  for the link (blind_s for vehicles; a walker crosses a 10 m circle at 1 m/s in
                                  10 s; default 12) */
  double blind_walker_cross;   /* m/s: with blind_walker, a gone-in walker's track is kept, and may be linked, also
                                  until the time the circle's width (twice the reach at its top, plus the young
                                  track's BLIND_BIRTH_M each side) takes at this pace, when that is longer than
                                  blind_walker_s (a VLP-16 4.9 m up: a walker is unseen 24 m, 15-22 s; a 3 m
                                  pole: 10 m, under blind_walker_s); at most RS_TRACK_WALKER_KEEP_MAX s (default
                                  1; 0 = blind_walker_s alone; docs/tracking.md, The blind circle) */
  int blind_walker_alone;      /* 1: with blind_walker_cross, a walker's track unseen longer than blind_walker_s
                                  takes a young one only when no other gone-in walker's track fits it (over such
                                  times the order they went in is no clock: one waits at the corner to cross
                                  while those behind walk on; default 1; 0 = by the order, as under it) */
  int blind_walker_fifo;       /* 1: with blind_walker, walkers come out in the order they went in: of the gone-in
                                  walkers' tracks whose time fits a young one, the first gone in takes it, and a
                                  gone-in track takes by the gate nothing an earlier one on its way may be coming
                                  out as (their paces at the circle's edge, slowed by the one ahead, are a poor
                                  clock); 0: the best time fit, and the gate as for one walker (default 1;
                                  docs/tracking.md, The blind circle) */
  double blind_walker_line;    /* m: with blind_walker, a gone-in walker's track whose line (its heading through where
                                  it was last seen) passes farther than this from where the young track was born
                                  is linked only when no walker's track whose line passes nearer fits (a walker
                                  who went in along a crossing and stopped inside is not the first choice for one
                                  coming out along the sidewalk; default 1.5; 0 = the order alone;
                                  docs/tracking.md) */
  int speed_full_length;       /* 1: the speed estimator measures a vehicle seen in part by its full length (its largest
                                  smoothed length, falling 0.05 m an update): the box's centre moved by half of what
                                  the box misses of it, not of the smoothed length, which shrinks while the view
                                  stays partial; the filter, gates and ids keep the smoothed length (default 1;
                                  docs/tracking.md, Speed estimator) */
  int split_full_size;         /* 1: a free object is a split part of a track when both fit in the track's
                                  full size (its largest box, falling 0.05 m an update), not only in its
                                  smoothed box, which shrinks while the object is partly hidden (default 1) */
  int stitch_kin;              /* 1: a young track hit in every frame since its birth (5 hits or more) is
                                  stitched to an unseen vehicle's track only when that vehicle could have come
                                  from where it was last seen, at its speed then, to where the young track is,
                                  at its speed now, speeding up at most 3 m/s^2 and braking at most 8 m/s^2
                                  (1 m/s, 2 sd of the young track's velocity and 3 m of slack): a faster car
                                  passing behind the spot a slow track was predicted to is not it (default 1;
                                  docs/tracking.md) */
  int stitch_alike;            /* 1: an unseen track seen in the same frames as a younger one is not stitched to it
                                  when, run back at its velocity to when the unseen one was last seen, the younger one
                                  was farther from it than the longer of the two and 1 m: two objects then (moving
                                  "alike" is no test after 2 s unseen, the velocity's uncertainty grown; default 1;
                                  docs/tracking.md, Association) */
  int gap_unseen;              /* 1: a track unseen in a frame whose columns at its predicted centre were not
                                  measured (a lost packet, rs_object_list_t.gap) was not missed: the frame does
                                  not count against its "hit in every frame" (misses), as it could not have
                                  been seen; the time since it was last seen runs on (default 1; docs/tracking.md) */
  double blind_walker_pace_s;  /* s: with blind_walker, a walker's track gone into the blind circle (confirmed,
                                  moving at 0.5 m/s or more) is predicted, and its time out fitted, at its pace:
                                  the speed of its mean velocity over the last blind_walker_pace_s to twice that
                                  of its updates (at least 1 s of them), when faster than the filter's (which
                                  follows the stop-and-go of walkers in file) and within 45 degrees of it, along
                                  the filter's direction (0 = off; default 3; docs/tracking.md, the blind
                                  circle) */
  double miss_cost;            /* the cost of leaving a gated track without an object in the optimal assignment
                                  (a pairing's: Mahalanobis distance squared + log det + the returns' unlikeness):
                                  the sum of the tracks' pairings, or this for each left out, is the least; so no
                                  pairing dearer than this is made, nor one track paired at the price of another's
                                  growing dearer by more (0 = off: each group pairs as many tracks as it can, then
                                  the cheapest way; default 24; docs/tracking.md, Association) */
  double split_car_m;          /* a moving vehicle's track (confirmed, 3 m/s or faster along its heading) never
                                  seen longer than this: a free object is a split part of it when both span no
                                  more than this along its axis and, across, no more than its width and the
                                  margin or 2.5 m (a car's width), whichever is more: a car seen only in part so
                                  far, split by the traffic in front of it, starts no track from its other part
                                  (default 5.0; 0 = off; docs/tracking.md) */
} rs_track_cfg_t;

/* The speed estimator of a track (speed_imm; docs/tracking.md): two models of
 * its motion on each ground axis, constant velocity (CV: position, velocity)
 * and constant acceleration (CA: the same and the acceleration, white-noise
 * jerk), run side by side on the Kalman filter's measurements and mixed by how
 * well each predicts them (an interacting multiple model filter). It only
 * reports: association, gates and the track's state use the Kalman filter. */
typedef struct {
  double x[2][2][3];         /* [model][axis]: position, velocity, acceleration (0 in CV) */
  double P[2][2][6];         /* [model][axis]: covariance, upper triangle 00 01 02 11 12 22 (CV: 02 12 22 are 0) */
  double mu[2];              /* the models' probabilities, CV and CA */
  double t;                  /* time of x */
} rs_track_imm_t;

typedef struct {
  uint32_t id;
  rs_track_state_t state;
  rs_class_t cls;            /* the class most of its returns were seen as (the votes below; docs/tracking.md) */
  rs_class_t shape_cls;      /* the class rule's answer for the smoothed box as it is now */
  float class_votes[RS_CLASS_COUNT]; /* returns of its confirmed updates, by shape_cls (unknown not counted) */
  double t_birth, t_update;  /* capture time (s) of the first and last update */
  double t_state;            /* time of the state x below */
  double x[4];               /* px py vx vy, sensor frame */
  double P[4][4];
  double px0, py0;           /* where it was born */
  double t_moving;           /* capture time of its last update reporting a speed, or of its birth (still_coast) */
  double spread;             /* the farthest measurement from there, m */
  double win_z[RS_TRACK_STILL_WINDOW][2]; /* its last measurements, a ring (confirm_still_window) */
  uint32_t win_points[RS_TRACK_STILL_WINDOW]; /* ... and their objects' returns */
  double last_z[2];          /* the last measurement */
  double x_seen[4];          /* the filter's state when last updated (brake_coast: no longer its prediction's start) */
  float brake;               /* m/s^2 (>= 0): how hard it was braking when last updated (brake_coast) */
  double t_z;                /* its time (a held track's t_update moves on without one) */
  double prev[2];            /* position at the previous frame (path length) */
  float length, width, height, z_min; /* smoothed box */
  float height_max;                   /* smoothed: height plus the objects' height_gap */
  float top_agl;                      /* smoothed: the objects' top above the ground (objects.h), when known */
  uint32_t top_agl_n;                 /* updates with it known (objects' top_agl > 0; 0: top_agl not known) */
  float top;                          /* smoothed: its top (sensor z), midway between its objects' returns'
                                         top and the row above them, from the top_n objects whose row above
                                         passed within RS_TRACK_TOP_GAP */
  uint32_t top_n;
  uint16_t walked;                    /* updates in which it looked and moved like a walker, up to
                                         walked_hits (rs_track_cfg_t) */
  float across;                       /* smoothed: the box's extent across the heading while moving (0 unknown) */
  float full_length, full_width;      /* the largest smoothed box, falling 0.05 (0.02) m an update */
  float heading;             /* radians from +X, counter-clockwise, (-pi, pi] */
  float hcos, hsin;          /* its cosine and sine */
  double hcd, hsd;           /* the same in double (box_on_axes) */
  float speed;               /* reported (0 when still) */
  float max_speed, sum_speed;
  uint32_t speed_n;
  double distance;           /* path length, m (coasting included) */
  double distance_seen;      /* the same up to the last update */
  uint32_t hits, misses;     /* frames with and without an object */
  uint32_t points;           /* returns of the last object */
  float site[3], site_v[2], site_heading; /* position, velocity and heading in the site frame (with a pose) */
  int32_t object;            /* index in this frame's object list, -1 none */
  int32_t held_object;       /* held: the object it shares with another track this frame, -1 none */
  bool was_held;             /* ... held the frame before */
  bool seen_whole;           /* updated once with all of its box beyond the lowest beam's reach (below_beam) */
  bool blind_kept;           /* lost longer than lost_s, kept for the blind-circle link alone (blind_s) */
  rs_track_imm_t imm;        /* the speed estimator (speed_imm) */
  bool cut;                  /* its first object was cut by the lowest beam's circle (circle_whole,
                                confirm_cut_walk_m) */
  bool last_hidden;          /* its last object was marked hidden at an end (uncover_restart) */
  float last_len;            /* its last object's length (uncover_restart) */
  bool made_whole;           /* circle_whole has acted on it */
  float way_c, way_s;        /* the direction it last moved faster than 2 m/s in; (0, 0) before (still_reverse) */
  uint8_t way_flips;         /* updates in a row moving so against it (the way turns back after 3) */
  uint8_t ref_mode;          /* the point the speed estimator follows: the box's centre, its side nearest the
                                sensor (near_ref_m) or one end along the track's axis (end_ref) */
  bool ref_old;              /* no longer young: the estimator follows the centre from now on */
  double ref_end[2];         /* the followed end's direction from the box's centre (end_ref) */
  double ref_dir[2];         /* towards the sensor from where it was born: the side's direction; (0, 0) when
                                near_ref_m is 0 */
  uint32_t twin;             /* the older track whose box its own overlaps (twin_s), 0 none */
  double twin_t;             /* since when (capture time) */
  float axis_c2, axis_s2;    /* smoothed cosine and sine of twice the axis of its whole side views (kin_accel) */
  uint16_t axis_n;           /* such views */
  double pace_t[2];          /* blind_walker_pace_s: capture times of its two pace anchors, the older first */
  double pace_p[2][2];       /* ... and the filter's position at each */
  double vel[2];             /* reported velocity, m/s: the speed estimator's for a track not of a walker's size
                                (speed_imm), the Kalman filter's otherwise */
} rs_track_t;

/* the turn rate of track t, rad/s counter-clockwise, as turn_rate uses it (docs/tracking.md): its speed
 * estimator's acceleration across its velocity over its speed; 0 for walkers and below 2 m/s */
double rs_track_turn_rate(const rs_track_t *t);

/* whether track t shares a cluster with another track this frame (track.h's "held") */
static inline bool rs_track_held(const rs_track_t *t) { return t->held_object >= 0; }

typedef struct {
  uint32_t id;
  rs_class_t cls;
  bool confirmed;
  double t_birth, t_end;
  double distance, mean_speed, max_speed;
} rs_track_end_t;

typedef struct {
  double t;                  /* the frame's time (its last packet) */
  bool site_valid;           /* tracks carry their site-frame state (rs_track_set_pose) */
  uint32_t count;            /* tracks in track[] (tentative, confirmed and coasting) */
  rs_track_t track[RS_TRACK_MAX];
  uint32_t ended;            /* end events of this frame */
  rs_track_end_t end[RS_TRACK_ENDED_MAX];
  /* per object of the frame: the track that took it (or absorbed it as a split part), 0 none */
  uint32_t object_track[RS_OBJ_MAX];
} rs_track_list_t;

typedef struct {
  uint64_t frames, born, confirmed, ended, overflow, greedy_groups, held, absorbed, ends_dropped, duplicates, stitched, blind_linked;
  uint64_t hold_overflow; /* held tracks beyond RS_TRACK_HOLD_MAX in one cluster (its returns go to the others) */
  uint64_t kin_stitched;  /* tracks taken up by the kinematic re-acquisition (kin_accel; also in stitched) */
  uint64_t merged;        /* split parts a long vehicle's track was updated with (merge_parts; also in absorbed) */
  uint64_t gap_unseen;    /* frames a track went unseen predicted in unmeasured columns, not counted missed (gap_unseen) */
  uint64_t miss_left;     /* tracks of exactly solved groups left without an object: each object in their gate went
                             to another track, or (miss_cost) every pairing left cost more than going without */
  uint64_t gap_runs_dropped; /* runs of unmeasured columns beyond RS_OBJ_GAPS_MAX in a frame, not known to gap_unseen */
  uint64_t far_born;      /* tracks born from fewer than birth_points returns (birth_far_points) */
  uint64_t queued;        /* predictions of hidden vehicles' tracks held behind the vehicle ahead (queue_coast) */
  uint64_t far_dropped;   /* objects that might have been so born, beyond RS_TRACK_FAR_BIRTHS_MAX in a frame: not
                             looked at, no track */
} rs_track_counters_t;

typedef struct {
  uint16_t t, o; /* track index, object index */
  float c;       /* cost: squared Mahalanobis distance + log det S */
} rs_track_edge_t;

typedef struct {
  rs_track_cfg_t cfg;
  rs_track_list_t list;      /* the tracks, in id order */
  uint32_t next_id;
  double low_tan;            /* tangent of the lowest beam's depression (this frame's objects; 0: none) */
  rs_track_counters_t n;
  double last_t;
  /* work areas */
  int32_t taken_by[RS_OBJ_MAX];        /* object -> track index, -1 */
  uint8_t shared[RS_OBJ_MAX];          /* object box holds >= 2 confirmed predictions */
  uint8_t obj_part[RS_OBJ_MAX];        /* walker_part, this frame: 0 not asked yet, 1 no, 2 a moving vehicle's part */
  double obj_t[RS_OBJ_MAX];
  float tent_d[RS_OBJ_MAX];           /* tent_claim_m, this frame: the nearest steady tentative walker's prediction (m) */
  double obj_cs[RS_OBJ_MAX][2];        /* cosine and sine of the object's box heading */
  const rs_object_t *obj_base;         /* the frame's objects (obj_cs's), obj_n of them */
  uint32_t obj_n;
  long obj_cell[RS_OBJ_MAX][2];        /* the grid cell of the object's box centre */
  uint16_t comp[RS_TRACK_MAX + RS_OBJ_MAX];
  uint16_t gt[RS_TRACK_GROUP_MAX], go[RS_TRACK_GROUP_MAX];
  double cost[RS_TRACK_ASSIGN_MAX][RS_TRACK_ASSIGN_MAX];
  uint32_t edges;                      /* gated pairs this round */
  struct {                             /* queue_coast: this frame's vehicles a hidden one may stop behind */
    double x, y, vx, vy;                 /* at the frame's time */
    double hc, hs, len;                  /* heading's cosine and sine, full length */
    uint32_t id;
  } lead[RS_TRACK_MAX];
  uint32_t nlead;
  double lead_maxlen;                  /* the longest of them */
  int32_t lead_head[RS_TRACK_GRID_BUCKETS]; /* them by position (8 m cells, hashed), chained by lead_next */
  int32_t lead_next[RS_TRACK_MAX];
  long lead_cell[RS_TRACK_MAX][2];
  rs_track_edge_t edge[RS_TRACK_MAX * RS_TRACK_EDGES_PER_TRACK];
  rs_track_edge_t gedge[RS_TRACK_MAX * RS_TRACK_EDGES_PER_TRACK]; /* the same, grouped */
  uint16_t eroot[RS_TRACK_MAX * RS_TRACK_EDGES_PER_TRACK];
  uint32_t root_start[RS_TRACK_MAX + RS_OBJ_MAX + 1];
  int32_t grid_head[RS_TRACK_GRID_BUCKETS]; /* -1 but the buckets in grid_used: each frame clears only those */
  int32_t grid_next[RS_OBJ_MAX];
  uint16_t grid_used[RS_OBJ_MAX];
  uint32_t grid_nused;
  int32_t tgrid_head[RS_TRACK_GRID_BUCKETS];  /* tracks by position; -1 but the cells of tcell[0 .. tgrid_n) */
  int32_t tgrid_next[RS_TRACK_MAX];
  uint32_t tgrid_n;
  double tpos[RS_TRACK_MAX][2];
  long tcell[RS_TRACK_MAX][2];
  double vmax;                         /* the fastest track's speed this frame */
  bool have_pose;
  double rot[9], trans[3];             /* sensor -> site (rs_pose_t's convention) */
  uint16_t near[RS_TRACK_MAX];         /* scratch: tracks_near's result, and the stitching's, the blind link's and
                                          the kinematic re-acquisition's candidate lists in their passes */
  double near_pos[RS_TRACK_MAX][2];    /* scratch: the stitching's candidates' tpos, in near's order */
  /* per object of the last frame: the held tracks (list indices) its returns are divided between */
  uint32_t hold_objects;               /* objects of the last frame */
  uint8_t hold_n[RS_OBJ_MAX];
  uint16_t hold_idx[RS_OBJ_MAX][RS_TRACK_HOLD_MAX];
} rs_tracker_t;

void rs_track_cfg_default(rs_track_cfg_t *c);
/* Sets one parameter by its field name ("q_accel", "coast_s", ...) from text,
 * within its range; RS_E_INVAL with a message naming it (and, for an unknown
 * name, every name) otherwise. */
int rs_track_cfg_set(rs_track_cfg_t *c, const char *name, const char *value, char *err, size_t n);
/* The parameters' names, space-separated. */
void rs_track_cfg_names(char *buf, size_t size);
/* RS_E_INVAL for a parameter out of range. */
int rs_track_init(rs_tracker_t *tr, const rs_track_cfg_t *cfg);
/* The sensor's pose in the site (NULL: none): from then on every track also
 * carries its position, velocity and heading in the site frame. */
void rs_track_set_pose(rs_tracker_t *tr, const rs_pose_t *pose);
/* One frame: its objects and its time (s, capture clock). */
void rs_track_frame(rs_tracker_t *tr, const rs_object_list_t *objs, double t_frame);
/* After rs_track_frame: the id of the track a return of object k at (x, y)
 * (sensor frame, m) belongs to. For an object over held tracks, the one
 * whose box, predicted to the object's time, holds the point best (the
 * largest of its along and across offsets over the half length and half
 * width, each at least 0.25 m; ties: the lower id); else the track that took
 * or absorbed the object (object_track[k], 0 none). */
uint32_t rs_track_owner(const rs_tracker_t *tr, uint32_t k, double x, double y);
/* whether object k of the last frame is divided between held tracks */
static inline bool rs_track_divided(const rs_tracker_t *tr, uint32_t k) { return k < tr->hold_objects && tr->hold_n[k] >= 2; }
const char *rs_track_state_name(rs_track_state_t s);
const char *rs_class_name(rs_class_t c);

#endif

/* objects.h - per-cluster attributes of a labelled frame.
 *
 * Input: a frame slot whose cells carry cluster labels (3 + n, both layers)
 * and the sensor that made it; optionally the sensor's pose in the site.
 * Output: one rs_object_t per cluster label present, in label order.
 *
 * Frames: the sensor frame of sensor.h (+X right, +Y forward, +Z up). With
 * a pose (x y z roll pitch yaw: site = Rz(yaw) Ry(pitch) Rx(roll) p + t)
 * every attribute is computed again in the site frame, whose ground plane is
 * what a traffic engineer means by "heading".
 *
 * Oriented box: a rectangle around the convex hull of the object's points
 * projected on the ground plane, oriented along one of the hull's edges:
 * the one whose rectangle the points hug closest (mean distance to the
 * nearest side), then the smaller area. An L-shaped view of a car gives a
 * triangular hull whose diagonal rectangle has the same area as the true
 * one: area alone cannot choose. The points of one map column lie on one
 * ray from the sensor, so only the nearest and farthest of each column are
 * kept as candidates (at most 2 per column); the search costs at most
 * RS_OBJ_HULL_EDGES edges x candidates (larger hulls test every k-th edge
 * and are counted). Heading: angle of the length axis from +X,
 * counter-clockwise, in (-pi/2, pi/2].
 *
 * Times: a point's time is interpolated from its packet index between the
 * frame's first and last packet (packets come at a fixed rate).
 *
 * No allocation: rs_objects_t is caller-owned (static in the programs);
 * every loop is bounded by the map size. Processing thread only. */
#ifndef ROADSCAN_OBJECTS_H
#define ROADSCAN_OBJECTS_H

#include "roadscan/perception/cluster.h"
#include "roadscan/perception/ground.h"
#include "roadscan/frame/frame.h"
#include "roadscan/sensor/sensor.h"

#include <stdbool.h>
#include <stdint.h>

#define RS_OBJ_MAX RS_MAX_CLUSTERS
#define RS_OBJ_CANDIDATES (1 << 18) /* hull candidates per frame and coordinate frame */
#define RS_OBJ_GAPS_MAX 64          /* runs of unmeasured columns kept per frame (5 % of a VLP-16 turn's 75
                                       packets lost: about 4) */
#define RS_OBJ_HULL_EDGES 128

typedef struct {
  double x, y, z;          /* metres, the sensor's origin in the site */
  double roll, pitch, yaw; /* radians */
} rs_pose_t;

typedef struct {
  float centroid[3];
  float box_min[3], box_max[3];  /* axis-aligned box; z min/max = height range */
  float obb_center[2];           /* oriented box on the ground plane */
  float obb_length, obb_width;   /* length >= width */
  float obb_heading;             /* radians, length axis from +X, counter-clockwise */
} rs_obj_geom_t;

/* rs_object_t.occluded: in at least RS_OBJ_HIDDEN_ROWS of the rows of the
 * object's first (last) column, one of the two columns before (after) it
 * returns nearer by more than RS_OBJ_HIDDEN_M: the object may go on behind
 * what is there, so that side of its box is not its end */
#define RS_OBJ_HIDDEN_START 1u
#define RS_OBJ_HIDDEN_END 2u
#define RS_OBJ_HIDDEN_M 0.5f
#define RS_OBJ_HIDDEN_ROWS 2

typedef struct {
  uint32_t id;              /* cluster label - 2: 1, 2, ... per frame */
  uint32_t points;          /* returns, both layers */
  rs_obj_geom_t sensor;     /* sensor frame */
  rs_obj_geom_t site;       /* site frame (valid when the list says so) */
  float range_min;          /* nearest return, m */
  float az_start, az_end;   /* degrees, clockwise from az_start to az_end (may wrap) */
  uint16_t row_min, row_max;
  float height_gap;         /* m: how much taller it may be than its returns show: the vertical gaps
                               to the rows above and below its own at its range (0 at the top row) */
  float top_gap;            /* m: the gap to the row above its top row at its nearest range, which passed
                               over it: its top is below box_max[2] + top_gap (-1: no row above) */
  uint16_t col_start, col_end; /* map columns, clockwise, may wrap past column 0 */
  uint8_t occluded;         /* RS_OBJ_HIDDEN_*: a side beside which something nearer returns (it may go on behind) */
  float top_agl;            /* m: its returns' top above the ground under its centre (rs_ground_t;
                               0: no ground known, or its top not above it) */
  float intensity_mean;
  double t_first, t_last;   /* capture time (s) of the first and last point */
} rs_object_t;

typedef struct {
  bool site_valid;          /* a pose was given */
  uint32_t count;           /* objects in obj[] */
  uint32_t candidates_overflow; /* objects whose hull lost candidates (box may be small) */
  uint32_t approx_boxes;    /* objects whose rectangle search skipped hull edges */
  float lowest_beam_deg;    /* the sensor's lowest beam's elevation (degrees; 0: not known) */
  /* the map columns more than half the rows did not measure this frame (a lost packet's: rs_slot_t.gap is by block
   * azimuth, and a row's returns lie at its laser's azimuth offset from it, so a VLP-32C's 2.4-degree
   * hole is a different 2.4 degrees in each group of rows: no column is unmeasured in more than half), as
   * runs [first, last] of the map's gap_cols columns (column c spans azimuths c to c + 1 times 360 /
   * gap_cols degrees); at most RS_OBJ_GAPS_MAX runs, the rest left out (gaps_dropped) */
  uint16_t gap_cols, ngaps;
  uint32_t gaps_dropped;
  uint16_t gap[RS_OBJ_GAPS_MAX][2];
  rs_object_t obj[RS_OBJ_MAX];
} rs_object_list_t;

typedef struct {
  bool have_pose;
  float rot[9], trans[3];
  const rs_ground_t *ground;          /* the ground under the objects (NULL: not known; the caller sets it) */
  int trig_cols;                      /* columns the tables below were made for */
  float col_sin[RS_MAX_COLS], col_cos[RS_MAX_COLS];
  /* work areas */
  uint32_t col_start_idx[RS_MAX_COLS + 1];
  uint32_t cells[RS_LAYERS * RS_MAX_CELLS];  /* object cells, row-major */
  uint32_t bycol[RS_LAYERS * RS_MAX_CELLS];  /* the same, column by column */
  uint32_t stamp[RS_OBJ_MAX];
  float dmin[2][RS_OBJ_MAX], dmax[2][RS_OBJ_MAX];
  float pmin[2][RS_OBJ_MAX][2], pmax[2][RS_OBJ_MAX][2];
  uint16_t touched[RS_LAYERS * RS_MAX_ROWS];
  uint8_t unmeasured[RS_MAX_COLS];   /* this frame's map columns more than half the rows did not measure */
  double sum[2][RS_OBJ_MAX][3];
  double isum[RS_OBJ_MAX];
  uint32_t first_pkt[RS_OBJ_MAX], last_pkt[RS_OBJ_MAX];
  uint16_t col_lo_hi[RS_OBJ_MAX][4]; /* min, max, min of the upper half, max of the lower half */
  uint32_t ncand[2];
  struct { float x, y; uint16_t obj; } cand[2][RS_OBJ_CANDIDATES];
  float sorted[RS_OBJ_CANDIDATES][2];
  uint32_t start[RS_OBJ_MAX + 1];
  float hull[RS_OBJ_CANDIDATES + 1][2];
} rs_objects_t;

_Static_assert(RS_OBJ_MAX <= UINT16_MAX, "object index fits in uint16_t");
_Static_assert(RS_MAX_COLS <= UINT16_MAX, "a map column fits in uint16_t");

void rs_objects_init(rs_objects_t *o, const rs_pose_t *pose /* NULL: no site frame */);
/* The pose's rotation R = Rz(yaw) Ry(pitch) Rx(roll), row-major (site = R p + t). */
void rs_pose_rotation(const rs_pose_t *pose, double r[9]);
/* Fills `out` from the labels of `s` (layer 0 and 1), scanning the map. */
void rs_objects_extract(rs_objects_t *o, const rs_slot_t *s, const rs_sensor_t *sen, rs_object_list_t *out);
/* The same from the list of object cells the clustering made (rs_cluster_t's
 * members: layer 0 then 1, row-major; cells out of the map, without a return
 * or a cluster label are skipped): no scan of the whole map. */
void rs_objects_extract_cells(rs_objects_t *o, const rs_slot_t *s, const rs_sensor_t *sen, const uint32_t *cells,
                              uint32_t n, rs_object_list_t *out);
/* Whether the map column of ground point (x, y) (sensor frame; its azimuth as rs_objects_xy's: x along
 * its sine, y along its cosine) lies in one of the list's runs of unmeasured columns (gap). A point
 * that is not finite lies in none. */
bool rs_objects_unmeasured_at(const rs_object_list_t *l, double x, double y);

/* Object o's time: the middle of its returns' capture times (s), or fallback when it has none (the
 * tracker's measurement time, the --objects-out t). */
static inline double rs_object_time(const rs_object_t *o, double fallback) {
  return o->points > 0 && o->t_last >= o->t_first ? 0.5 * (o->t_first + o->t_last) : fallback;
}

/* The ground-plane position (sensor frame, m) of cell i's return, as the
 * last extraction placed it (its column tables are the last frame's). */
static inline void rs_objects_xy(const rs_objects_t *o, const rs_slot_t *s, const rs_sensor_t *sen, uint32_t i,
                                 float xy[2]) {
  const uint32_t cols = (uint32_t)s->meta.cols, c = (i % RS_MAX_CELLS) % cols;
  const float h = s->range[i] * sen->cos_el[sen->laser_of_row[(i % RS_MAX_CELLS) / cols]];
  xy[0] = h * o->col_sin[c];
  xy[1] = h * o->col_cos[c];
}

#endif

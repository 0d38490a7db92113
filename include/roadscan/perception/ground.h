/* ground.h - the height of the ground under a place, from the static scene.
 *
 * Why: an object's height from its returns alone (the top of its returns less
 * their bottom) falls short whenever something nearer hides its lower part: a
 * van behind a queue of cars at 45 m shows only its upper metre or so and is
 * measured as tall as a car. Its top above the ground does not depend on what
 * hides its wheels.
 *
 * What: a grid of RS_GROUND_N x RS_GROUND_N cells of RS_GROUND_CELL_M on the
 * sensor frame's ground plane (x, y; the sensor at the centre), each holding
 * the sensor-frame z of the ground there. Built from a background model: every
 * static surface of every map cell (the middle of its range interval) is a
 * point; a grid cell's ground is the RS_GROUND_KTH-lowest of its points (the
 * road, a kerb, a wall's foot are the lowest things in a cell; the k-th, not
 * the lowest, so that one stray return below the road does not decide), kept
 * when it has at least RS_GROUND_KTH points. A 3 x 3 median over the kept cells
 * removes a cell whose only points are a wall or a roof above its neighbours.
 * A plane gives the ground where no cell was kept within RS_GROUND_FILL cells
 * (between the rings of a sparse sensor, under the pole; a filled cell is the
 * plane there, off it as much as its known neighbours are): a sensor that
 * leans or a road that slopes is followed by the plane, a crowned road or a
 * kerb by the cells. The plane: of RS_GROUND_DRAWS planes through three cells
 * within RS_GROUND_NEAR_M at least RS_GROUND_BELOW_M below the sensor (a fixed
 * sequence of draws, RANSAC), the one most of those cells lie on within
 * RS_GROUND_PLANE_TOL, then least squares over the cells near it, the band
 * narrowing to RS_GROUND_PLANE_TOL (walls, trees and roofs stay out; a level
 * beam's hits on walls are at the sensor's own height and never drawn).
 * No ground (every query: not known) when the plane is less than
 * RS_GROUND_BELOW_M below the sensor, steeper than RS_GROUND_STEEP_DEG, or holds
 * less than RS_GROUND_ON_PLANE of those near cells: a sensor mounted on its
 * side, in a small room, or one whose model no plane fits.
 *
 * Threads: built on the processing thread when a model comes (at start, after
 * learning, at each update of the model): bounded work (map cells plus grid
 * cells times a constant), no allocation (rs_ground_t is the caller's).
 * Read by the object stage on the same thread. */
#ifndef ROADSCAN_GROUND_H
#define ROADSCAN_GROUND_H

#include "roadscan/perception/background.h"
#include "roadscan/sensor/sensor.h"

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#define RS_GROUND_CELL_M 2.0f
#define RS_GROUND_HALF 128 /* cells from the sensor to the grid's edge: 256 m (a VLS-128 reaches 245 m) */
#define RS_GROUND_N (2 * RS_GROUND_HALF)
#define RS_GROUND_KTH 3              /* a cell's ground: its k-th lowest point */
#define RS_GROUND_FILL 2             /* cells without ground take their neighbours' this many cells away */
#define RS_GROUND_PLANE_TOL 0.25f    /* m: the last fit of the plane takes the cells this near the one before */
#define RS_GROUND_MIN_CELLS 8        /* fewer kept cells: no ground at all */
#define RS_GROUND_NEAR_M 40.0        /* m: the cells the level and the check of the plane look at */
#define RS_GROUND_BELOW_M 0.5        /* m: the ground is at least this far below the sensor */
#define RS_GROUND_STEEP_DEG 10.0     /* a plane steeper than this is no road's (nor a level-mounted sensor's) */
#define RS_GROUND_ON_PLANE 0.5       /* share of the near cells within 2 RS_GROUND_PLANE_TOL of the plane */
#define RS_GROUND_DRAWS 512          /* planes through three near cells tried (RANSAC) */

_Static_assert(RS_GROUND_N * RS_GROUND_N <= UINT16_MAX + 1, "grid cells fit the median's window index");
_Static_assert(RS_GROUND_KTH >= 1 && RS_GROUND_KTH <= 8, "a small k");

typedef struct {
  bool valid;                               /* a ground was found (else every query says not known) */
  float z[RS_GROUND_N * RS_GROUND_N];       /* sensor-frame z of the ground; NAN: not known */
  double plane[3];                          /* z = plane[0] + plane[1] x + plane[2] y (sensor frame) */
  uint32_t cells_kept, cells_filled, cells_plane; /* how each cell got its ground, at the last build */
  double on_plane;                          /* share of the near kept cells on the plane */
  /* work areas of the build */
  float low[RS_GROUND_N * RS_GROUND_N][RS_GROUND_KTH]; /* the k lowest points' z, ascending */
  uint16_t n[RS_GROUND_N * RS_GROUND_N];    /* points seen, saturating */
  float tmp[RS_GROUND_N * RS_GROUND_N];
  uint16_t near[RS_GROUND_N * RS_GROUND_N]; /* the near cells below the sensor the plane is drawn from */
} rs_ground_t;

/* Builds g from model m of sensor sen (whose rows and columns it must have;
 * otherwise g is left not valid). */
void rs_ground_build(rs_ground_t *g, const rs_bg_model_t *m, const rs_sensor_t *sen);
/* The ground's sensor-frame z under (x, y) (sensor frame, m) into *z: true
 * when known (a valid ground, inside the grid). */
bool rs_ground_at(const rs_ground_t *g, double x, double y, float *z);
/* One line (no newline) saying what the last build found: the sensor's height above the ground and its
 * lean, how the cells got their ground; or why there is none. Into buf (truncated to n). */
void rs_ground_describe(const rs_ground_t *g, char *buf, size_t n);

#endif

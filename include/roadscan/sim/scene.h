/* scene.h - a signalised four-leg intersection seen by a pole-mounted
 * LiDAR: static geometry, foliage, traffic with a signal cycle, and ray
 * casting with sensor effects. Used by the simulator (not real-time code;
 * it allocates at start-up). Deterministic for a given seed.
 *
 * World frame: intersection centre at the origin, x east, y north, z up,
 * ground at z = 0. Roads run along the x and y axes (4 lanes, 14 m wide),
 * sidewalks 5 m wide (kerb 0.15 m) beyond them, buildings behind. The
 * sensor stands on a pole at the south-west corner; its frame is the world
 * frame translated (azimuth 0 = north). */
#ifndef ROADSCAN_SCENE_H
#define ROADSCAN_SCENE_H

#include "roadscan/sensor/sensor.h"

#include "roadscan/util/opts.h"

#include <stdbool.h>
#include <stdint.h>

typedef struct {
  uint64_t s[2];
} rs_rng_t;

void rs_rng_seed(rs_rng_t *r, uint64_t seed);
uint64_t rs_rng_next(rs_rng_t *r);
double rs_rng_uniform(rs_rng_t *r); /* [0, 1) */
double rs_rng_normal(rs_rng_t *r); /* unit variance, |x| < 3.47 */

typedef struct {
  /* site */
  double pole_height;        /* m, default 5 */
  double pole_x, pole_y;     /* default (-11.5, -11.5) */
  double leg_length;         /* m from the centre, default 250 */
  int trees_per_leg;         /* default 6 */
  int site_seed;             /* the site's buildings, trees, signs (default 1); --seed varies traffic and noise */
  double foliage_hit;        /* chance a ray through a canopy returns a leaf, default 0.55 */
  /* traffic */
  double vehicles_per_min;   /* per approach (two lanes), default 8 */
  double pedestrians_per_min;/* per sidewalk path, default 1 */
  double cyclist_share;      /* of vehicles, default 0.05 */
  double green_s;            /* green per phase, default 25 (yellow 3, all-red 2) */
  double objects_min_range;  /* far preset: objects only between these distances */
  double objects_max_range;  /* from the centre (0 = anywhere) */
  double warmup_s;           /* traffic simulated before the capture starts, default 60 */
  double walker_space;       /* m: walkers step aside to keep their centres this far apart (0 = they
                                walk through each other, as before; docs/simulator.md) */
  double turn_share;         /* of the vehicles in a road's outer lane, the share that turn right; of
                                the inner lane's, the share that turn left (default 0: all go straight) */
  /* sensor effects (physics: see docs/simulator.md, measured against real captures) */
  double range_noise;        /* m, sd at 20 m on a surface of intensity 20: default 0.012;
                                sd = range_noise x (0.5 + r / 40 m) x (0.85 + 2 / max(intensity, 5)) */
  double noise_tail;         /* share of returns whose noise is 5 times wider (default 0.005) */
  double dropout;            /* per return, default 0.012 */
  double spurious;           /* per ray (rain, dust), default 0.0002 */
  double attenuation;        /* rain/dust extinction, 1/km (two-way), default 0 */
  double packet_loss;        /* per packet, default 0 */
  double max_range;          /* m, default from the model: a bright surface is detected up to it */
  double beam_div_h, beam_div_v; /* beam divergence, mrad (full angle); default from the model */
  int beam_samples;          /* rays cast across the footprint: 1 (a thin beam) or 9 (default) */
  double mix_depth;          /* m: surfaces closer than this in one footprint return one mixed range
                                (default 0.6); farther apart, the strongest (or the last) wins */
  double rpm_offset;         /* the motor's rate against the nominal, fraction (default -0.0005) */
  double rpm_jitter;         /* sd of its slow wander (2 s correlation), fraction (default 0.0005) */
  /* the sensor's mount: it turns about the vertical (a pole twisting in the wind, a bracket
     knocked), so every surface moves against the model by the same angle */
  double sway_deg;           /* amplitude of a yaw oscillation, degrees (default 0) */
  double sway_period;        /* its period, s (default 4) */
  double knock_deg;          /* a step of the yaw, degrees, ramped over 0.5 s (default 0: none) */
  double knock_at;           /* when, s from the capture's start (default 0) */
  /* a sensor not quite level on its mount: its vertical axis leans tilt_deg towards the azimuth
     tilt_toward (degrees clockwise from +Y); its own frame (the packets', the tracks') then sees the
     level road rise that way. Truth (labels, states) stays the site's */
  double tilt_deg;           /* default 0 */
  double tilt_toward;        /* default 0 */
} rs_scene_cfg_t;

/* the sensor's yaw against its mount (degrees) t seconds into the capture */
double rs_scene_yaw(const rs_scene_cfg_t *cfg, double t);

/* light, rush, turns, far, storm; false for an unknown name */
bool rs_scene_preset(const char *name, rs_scene_cfg_t *cfg);
/* key = value (same names as the fields); RS_OK or RS_E_INVAL with err */
int rs_scene_set(rs_scene_cfg_t *cfg, const char *key, const char *value, char *err, size_t n);
/* The knobs rs_scene_set knows (an option table over rs_scene_cfg_t, util/opts.h), *n of them. */
const rs_opt_t *rs_scene_knobs(int *n);

/* one return on a ray */
typedef struct {
  float range;      /* 0 = none */
  uint8_t intensity;
  uint16_t label;   /* 1 static, 2 foliage/spurious, >= 3 object id (of most of the footprint) */
} rs_hit_t;

typedef struct {
  rs_hit_t first;   /* nearest return */
  rs_hit_t second;  /* a farther return when the first is partial (leaves, dust, a depth edge
                       across the footprint); the brighter of the two is the strongest */
} rs_ray_t;

typedef struct rs_scene rs_scene_t;

/* Builds the world and the static range table for the sensor turning at hz. */
rs_scene_t *rs_scene_create(const rs_scene_cfg_t *cfg, const rs_sensor_t *s, double hz, uint64_t seed);
void rs_scene_destroy(rs_scene_t *sc);

/* Advances traffic to time t (s since the capture start) and prepares the
 * objects seen in azimuths [az_from, az_to] (degrees, may wrap). */
void rs_scene_prepare(rs_scene_t *sc, double t, double az_from, double az_to);
/* Casts the ray of record slot `slot` (bank * 32 + record) of a block whose
 * azimuth field is `block_az` (0.01 degree), i.e. `laser` at true azimuth
 * `az` (degrees, sensor frame), through the prepared scene, with the sensor
 * effects drawn from `rng`. slot = -1 casts `laser` at `az` without the
 * static table (slow; tests). */
void rs_scene_cast(rs_scene_t *sc, int slot, int block_az, int laser, double az, rs_rng_t *rng, rs_ray_t *out);

/* A road user's true state (sensor frame: the world less the sensor's
 * origin, +X right, +Y forward; metres, m/s, radians from +X). */
typedef struct {
  uint16_t id;          /* its truth label */
  const char *cls;      /* car, van, truck, bus, cyclist, pedestrian */
  double x, y;          /* centre of its footprint */
  double vx, vy, heading;
  double length, width, height;
} rs_agent_state_t;
/* The road users in the scene at time t (s since the capture start; traffic
 * advanced by rs_scene_prepare), up to max; returns how many. */
int rs_scene_states(const rs_scene_t *sc, double t, rs_agent_state_t *out, int max);

/* Objects currently in the scene (for statistics and tests). */
int rs_scene_object_count(const rs_scene_t *sc);
/* Frame-level noise state (foliage flicker changes per turn). */
void rs_scene_new_turn(rs_scene_t *sc);

/* Test hooks: the scene with nothing but ground and one box / no traffic. */
rs_scene_t *rs_scene_create_empty(const rs_scene_cfg_t *cfg, const rs_sensor_t *s);
void rs_scene_add_box(rs_scene_t *sc, double cx, double cy, double z0, double l, double w, double h, double yaw,
                      uint16_t label);
/* Test hook: the reflectivity (intensity 0..255) of an added box. */
void rs_scene_set_intensity(rs_scene_t *sc, uint16_t label, uint8_t intensity);
/* Sensor origin in the world. */
void rs_scene_origin(const rs_scene_t *sc, double *x, double *y, double *z);

#endif

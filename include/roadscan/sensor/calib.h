/* calib.h - per-unit calibration files (ROS velodyne_pointcloud YAML:
 * `lasers:` list of {laser_id, rot_correction, vert_correction,
 * dist_correction, vert_offset_correction, ...} in radians and metres,
 * `num_lasers`, `distance_resolution`). Loaded at start-up only. */
#ifndef ROADSCAN_CALIB_H
#define ROADSCAN_CALIB_H

#include "roadscan/sensor/sensor.h"

#include <stddef.h>

/* The most negative distance correction accepted (m): a laser corrected by
 * more would give negative ranges to near returns. Decoding drops any
 * return whose corrected range is not positive. */
#define RS_CALIB_MIN_DIST_CORRECTION -0.5

typedef struct {
  int lasers;
  float dist_res_m;                       /* 0 when the file does not say */
  float elevation_deg[RS_MAX_LASERS];
  float azimuth_offset_deg[RS_MAX_LASERS]; /* = -rot_correction, in degrees */
  float dist_correction_m[RS_MAX_LASERS];
  float vert_offset_m[RS_MAX_LASERS];
  int ignored_fields;                     /* non-zero corrections we do not model */
} rs_calib_t;

/* RS_OK, or RS_E_NOENT / RS_E_CALIB with a message naming the problem. */
int rs_calib_load_yaml(const char *path, rs_calib_t *c, char *err, size_t errlen);
/* Applies to a sensor of the same laser count (RS_E_CALIB otherwise).
 * Values the packet format fixes (the distance unit) are the model's
 * whatever the file says; when the file disagrees, `warn` (optional) names
 * the value ignored, else it is set to "". */
int rs_calib_apply(const rs_calib_t *c, rs_sensor_t *s, char *err, size_t errlen, char *warn, size_t warnlen);

#endif

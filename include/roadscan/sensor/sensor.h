/* sensor.h - Velodyne sensor models: built-in tables and per-unit calibration.
 *
 * Pure data. An rs_sensor_t is filled once at start-up (rs_sensor_init, then
 * optionally rs_calib_load_yaml) and is read-only afterwards, so both threads
 * may read it without locking.
 *
 * Conventions (documented in docs/decoding.md):
 *  - azimuth: degrees, clockwise seen from above, 0 = the sensor's +Y axis
 *    (the Velodyne manuals' convention); a laser's true azimuth is the block
 *    azimuth + the laser's azimuth offset + rotation during its firing delay.
 *  - sensor frame: right-handed, +X right, +Y forward (azimuth 0), +Z up:
 *      x = r cos(el) sin(az),  y = r cos(el) cos(az),  z = r sin(el) + vert_offset
 *  - rows: lasers ordered by elevation, row 0 = lowest beam. */
#ifndef ROADSCAN_SENSOR_H
#define ROADSCAN_SENSOR_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#define RS_MAX_LASERS 128
#define RS_BLOCKS 12           /* data blocks per packet */
#define RS_RECORDS 32          /* channel records per block */
#define RS_PAYLOAD_SIZE 1206   /* UDP payload of a data packet */
#define RS_BLOCK_SIZE 100
#define RS_DEFAULT_DATA_PORT 2368
#define RS_DEFAULT_POSITION_PORT 8308

typedef enum {
  RS_MODEL_UNKNOWN = 0,
  RS_MODEL_VLP16,
  RS_MODEL_PUCK_HIRES,
  RS_MODEL_HDL32E,
  RS_MODEL_VLP32C,
  RS_MODEL_VLS128,
  RS_MODEL_COUNT
} rs_model_t;

/* Return-mode byte (offset 1204). */
enum { RS_MODE_STRONGEST = 0x37, RS_MODE_LAST = 0x38, RS_MODE_DUAL = 0x39 };

typedef struct {
  rs_model_t model;
  const char *name;        /* "VLP-16" */
  uint8_t product_id;      /* factory byte at offset 1205 */
  uint16_t lasers;
  float dist_res_m;        /* metres per distance unit on the wire */
  float cycle_us;          /* one firing cycle: every laser fires once */
  uint8_t cycles_per_block;/* VLP-16 family: 2 firing cycles in one block */
  uint8_t blocks_per_cycle;/* VLS-128: one cycle spans 4 blocks (banks) */
  float min_hz, max_hz;    /* supported rotation rates */
} rs_model_info_t;

typedef struct {
  const rs_model_info_t *info;
  uint16_t lasers;
  float dist_res_m;
  float elevation_deg[RS_MAX_LASERS];
  float azimuth_offset_deg[RS_MAX_LASERS];
  float dist_correction_m[RS_MAX_LASERS];
  float vert_offset_m[RS_MAX_LASERS];
  /* derived by rs_sensor_finish() */
  float cos_el[RS_MAX_LASERS];
  float sin_el[RS_MAX_LASERS];
  uint8_t row_of_laser[RS_MAX_LASERS];
  uint8_t laser_of_row[RS_MAX_LASERS];
  bool calibrated;         /* values came from a calibration file */
} rs_sensor_t;

const rs_model_info_t *rs_model_info(rs_model_t m);
/* Model for a factory product byte; RS_MODEL_UNKNOWN when not known. */
rs_model_t rs_model_from_product(uint8_t product);
/* Model from a name ("VLP-16", "vlp16", "HDL-32E", "VLP-32C", "VLS-128",
 * "puck-hires", "alpha-prime", ...); RS_MODEL_UNKNOWN when not known. */
rs_model_t rs_model_from_name(const char *name);
const char *rs_model_name(rs_model_t m);
/* Comma-separated list of accepted model names, for help texts. */
const char *rs_model_names(void);

/* Built-in (published) table of a model. Returns RS_E_INVAL for UNKNOWN. */
int rs_sensor_init(rs_sensor_t *s, rs_model_t m);
/* Recomputes trig tables and row order after the angles changed. */
void rs_sensor_finish(rs_sensor_t *s);

/* Laser and firing time (µs from the start of the block's firing cycle
 * group) of record `rec` in a block of bank `bank` (VLS-128: 0..3 from the
 * block flag; 0 for other models). */
void rs_sensor_record(const rs_sensor_t *s, int bank, int rec, int *laser, float *t_us);

/* Duration of one azimuth group (the blocks sharing one azimuth reading):
 * cycles_per_block * cycle_us. */
float rs_model_group_us(const rs_model_info_t *mi);

#endif

/* packet.h - validation, decoding and encoding of Velodyne data packets, and
 * model detection from the first packets of a stream.
 *
 * Pure functions over caller-owned buffers; no allocation, no I/O. Bytes are
 * read with explicit little-endian loads, never by casting the payload.
 * Used by the packet thread (decode, detect) and by tools and tests (encode). */
#ifndef ROADSCAN_PACKET_H
#define ROADSCAN_PACKET_H

#include "roadscan/sensor/sensor.h"

#include <stdbool.h>
#include <stdint.h>

#define RS_MAX_POINTS_PER_PACKET (RS_BLOCKS * RS_RECORDS)

/* How a point was returned. Dual mode: even blocks carry the last return,
 * odd blocks the strongest one, or the second strongest when the last return
 * is also the strongest; an odd record equal to its even twin is "same". */
typedef enum {
  RS_RET_STRONGEST = 0,
  RS_RET_LAST = 1,
  RS_RET_DUAL_LAST = 2,
  RS_RET_DUAL_STRONGEST = 3,
  RS_RET_DUAL_SECOND = 4,
  RS_RET_DUAL_SAME = 5,
} rs_return_type_t;

const char *rs_return_type_name(int t);
const char *rs_return_mode_name(uint8_t mode_byte);

typedef struct {
  float x, y, z;           /* metres, sensor frame (see sensor.h) */
  float distance;          /* metres */
  float azimuth;           /* true azimuth, degrees [0, 360) */
  float t_us;              /* firing time after the packet's first firing */
  uint16_t block_azimuth;  /* block azimuth field, 0.01 degree */
  uint8_t intensity;
  uint8_t laser;
  uint8_t row;             /* laser's rank by elevation, 0 = lowest */
  uint8_t block;           /* 0..11 */
  uint8_t channel;         /* record in the block, 0..31 (wire order) */
  uint8_t return_type;     /* rs_return_type_t */
  uint8_t layer;           /* 0 = primary (single, or dual last), 1 = dual second return */
} rs_point_t;

typedef struct {
  rs_model_t model;
  uint8_t product_byte;
  uint8_t mode_byte;
  uint32_t timestamp_us;             /* µs past the hour, first firing */
  uint8_t blocks;                    /* blocks carrying data: 12, or 8 (VLS-128 dual) */
  uint8_t groups;                    /* distinct azimuth groups (firing cycles) */
  uint16_t block_azimuth[RS_BLOCKS]; /* 0.01 degree */
  float az_rate;                     /* degrees per µs used for interpolation */
  bool az_rate_measured;             /* from this packet (else the caller's hint) */
  uint16_t n_points;                 /* returns (distance > 0) */
  uint16_t n_empty;                  /* records with distance 0 */
  rs_point_t points[RS_MAX_POINTS_PER_PACKET];
} rs_packet_t;

/* Structure checks only: size, block flags, azimuth range, return mode.
 * RS_OK or a negative rs_err_t naming the first problem. */
int rs_packet_check(const uint8_t *p, size_t len);

/* Decodes a data packet with sensor `s` (whose model is used whatever the
 * product byte says). `rate_hint` (degrees per µs, > 0) is used when the
 * packet alone cannot give the rotation rate (one azimuth group). */
int rs_packet_decode(const rs_sensor_t *s, const uint8_t *p, size_t len, float rate_hint,
                     rs_packet_t *out);

/* Degrees per µs for a rotation rate in Hz. */
static inline float rs_rate_from_hz(double hz) { return (float)(hz * 360.0 / 1e6); }
static inline double rs_hz_from_rate(float deg_per_us) { return (double)deg_per_us * 1e6 / 360.0; }

/* ---- encoding (simulator, tests, benchmarks) ---- */

typedef struct {
  uint8_t mode_byte;                          /* RS_MODE_* */
  uint8_t product_byte;                       /* 0 = the model's own */
  uint32_t timestamp_us;
  uint16_t block_azimuth[RS_BLOCKS];          /* 0.01 degree */
  uint16_t distance[RS_BLOCKS][RS_RECORDS];   /* wire units */
  uint8_t intensity[RS_BLOCKS][RS_RECORDS];
} rs_encode_t;

/* Writes a 1206-byte packet. Block flags follow the model (VLS-128 banks;
 * dual-mode VLS-128 padding blocks are zero with a valid flag). */
void rs_packet_encode(const rs_model_info_t *mi, const rs_encode_t *in, uint8_t out[RS_PAYLOAD_SIZE]);

/* ---- the packet layout of a model, written once (decoder, encoder, simulators, bench) ----
 * Blocks carrying data: 12, or 8 for a VLS-128 in dual mode (4 padding blocks). */
int rs_layout_blocks(const rs_model_info_t *mi, bool dual);
/* The firing group (azimuth step) of a block: a VLS-128 fires 4 banks per group (dual: one group per
 * packet), the others one block per group (dual: two blocks, the same firing, per group). */
int rs_layout_group(const rs_model_info_t *mi, bool dual, int block);
/* Firing groups per packet: 12, 6 (dual); VLS-128 3, 1 (dual). */
int rs_layout_groups(const rs_model_info_t *mi, bool dual);
/* The bank (0..3, the block flag) of a block; 0 but on the VLS-128. */
int rs_layout_bank(const rs_model_info_t *mi, bool dual, int block);

/* ---- model detection ----
 *
 * Every product byte but 0x21 names its model. 0x21 is the HDL-32E's, and
 * also what early VLP-16 firmware sends; the two are told apart by the
 * packets' structure, never by one packet:
 *  - firing timing: the duration of one block's firing group, from two
 *    packets' sensor timestamps and block azimuths (step per block x time
 *    between the packets / azimuth between them): 110.6 us for a VLP-16
 *    (two firing cycles per block), 46.08 us for an HDL-32E, whatever the
 *    rotation rate and however many packets were lost between them;
 *  - repetition: a VLP-16 block fires the same 16 lasers twice, so records
 *    i and i+16 measure nearly the same range (a share well above half of
 *    the pairs over several packets; one packet at an edge can fall to 20 %);
 *    an HDL-32E's records i and i+16 are lasers 10-20 degrees apart.
 * The decision waits for at least RS_DETECT_MIN_PACKETS packets and for the
 * cues to agree; while they do not, the evidence keeps accumulating up to
 * RS_DETECT_MAX_PACKETS, where the weight of evidence decides and the reason
 * says it was unsure. */

typedef struct {
  rs_model_t forced;       /* != UNKNOWN: no detection, always this model */
  rs_model_t decided;      /* UNKNOWN until decided */
  uint8_t product;         /* product byte of the stream */
  uint8_t mode;
  int packets;             /* valid packets seen while undecided */
  int twin_pairs, twin_close;
  int timing_vlp16, timing_claimed; /* packet pairs whose firing timing fits each model */
  bool have_last;
  uint32_t last_ts;        /* sensor timestamp (us past the hour) and first block azimuth */
  uint16_t last_az;        /* of the previous packet */
  char reason[200];        /* why the decision was made */
} rs_detect_t;

#define RS_DETECT_MIN_PACKETS 6
#define RS_DETECT_MAX_PACKETS 32

void rs_detect_init(rs_detect_t *d, rs_model_t forced);
/* Feeds one data packet that passed rs_packet_check. Returns the decided
 * model (also on later calls), RS_MODEL_UNKNOWN while more packets are
 * needed (at most RS_DETECT_MAX_PACKETS), or a negative error
 * (RS_E_PRODUCT for an unknown product byte with nothing forced). */
int rs_detect_feed(rs_detect_t *d, const uint8_t *p, size_t len);
/* Forces a decision with what was seen (end of input). */
int rs_detect_finish(rs_detect_t *d);

#endif

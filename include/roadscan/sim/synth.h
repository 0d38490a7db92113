/* synth.h - synthetic but well-formed Velodyne captures: a sensor 2 m above
 * flat ground in a room whose wall distance varies with azimuth, with
 * optional faults (lost, reordered, duplicated packets, position packets,
 * foreign traffic). For tests, benchmarks and the README demo; the scene
 * simulator with ground truth is a separate tool. Not real-time code. */
#ifndef ROADSCAN_SYNTH_H
#define ROADSCAN_SYNTH_H

#include "roadscan/sensor/packet.h"

#include <stdbool.h>
#include <stdint.h>

typedef struct {
  rs_model_t model;
  uint8_t mode;              /* RS_MODE_STRONGEST, _LAST, _DUAL */
  uint8_t product;           /* 0 = the model's own byte */
  double hz;                 /* rotation rate */
  double seconds;
  double start_az_deg;
  double t0;                 /* capture time of the first packet (s since epoch) */
  int linktype;              /* RS_LINK_* */
  uint16_t vlan;
  uint16_t data_port;        /* 0 = 2368 */
  int position_every;        /* a position packet every N data packets (0: none) */
  int foreign_every;         /* a non-Velodyne 1206-byte datagram to the data port every N (0: none) */
  const uint32_t *drop; int ndrop;     /* data packet numbers not written */
  const uint32_t *swap; int nswap;     /* packet k written after k+1 */
  const uint32_t *dup; int ndup;       /* packet k written twice */
} rs_synth_cfg_t;

/* Wall distance (m) at azimuth az (degrees) and the distance a beam of
 * elevation el sees (ground at -2 m, wall, nothing above 12 degrees). */
double rs_synth_range(double az_deg, double el_deg);

/* Content of data packet k (0-based, before faults). */
void rs_synth_packet(const rs_synth_cfg_t *cfg, const rs_sensor_t *s, uint32_t k, rs_encode_t *enc);
/* Number of data packets for cfg->seconds. */
uint32_t rs_synth_count(const rs_synth_cfg_t *cfg);
/* Capture time of data packet k. */
double rs_synth_time(const rs_synth_cfg_t *cfg, uint32_t k);

/* Writes the capture; returns the number of data packets written or < 0. */
long rs_synth_write(const rs_synth_cfg_t *cfg, const char *path);

#endif

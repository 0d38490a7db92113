/* synth.c - synthetic capture writer (tools and tests only). */
#include "roadscan/sim/synth.h"

#include "roadscan/util/error.h"
#include "roadscan/capture/net.h"
#include "roadscan/offline/pcapw.h"

#include <math.h>
#include <string.h>

#define DEG2RAD (3.14159265358979323846 / 180.0)
#define SENSOR_HEIGHT 2.0

double rs_synth_range(double az_deg, double el_deg) {
  double wall = 20.0 + 6.0 * sin(3.0 * az_deg * DEG2RAD) + 3.0 * cos(7.0 * az_deg * DEG2RAD);
  if (el_deg > 12.0) return 0.0; /* sky */
  double d_wall = wall / cos(el_deg * DEG2RAD);
  if (el_deg < -0.5) {
    double d_ground = SENSOR_HEIGHT / sin(-el_deg * DEG2RAD);
    if (d_ground < d_wall) return d_ground;
  }
  return d_wall;
}

static double group_us(const rs_model_info_t *mi) { return rs_model_group_us(mi); }

static double packet_us(const rs_model_info_t *mi, bool dual) { return rs_layout_groups(mi, dual) * group_us(mi); }

uint32_t rs_synth_count(const rs_synth_cfg_t *cfg) {
  const rs_model_info_t *mi = rs_model_info(cfg->model);
  return (uint32_t)(cfg->seconds * 1e6 / packet_us(mi, cfg->mode == RS_MODE_DUAL));
}

double rs_synth_time(const rs_synth_cfg_t *cfg, uint32_t k) {
  const rs_model_info_t *mi = rs_model_info(cfg->model);
  return cfg->t0 + (double)k * packet_us(mi, cfg->mode == RS_MODE_DUAL) * 1e-6;
}

void rs_synth_packet(const rs_synth_cfg_t *cfg, const rs_sensor_t *s, uint32_t k, rs_encode_t *enc) {
  const rs_model_info_t *mi = s->info;
  const bool dual = cfg->mode == RS_MODE_DUAL;
  const int nb = rs_layout_blocks(mi, dual);
  const double deg_per_us = cfg->hz * 360.0 / 1e6;
  memset(enc, 0, sizeof *enc);
  enc->mode_byte = cfg->mode;
  enc->product_byte = cfg->product;
  double t_pkt = (double)k * packet_us(mi, dual);
  enc->timestamp_us = (uint32_t)fmod(cfg->t0 * 1e6 + t_pkt, 3600e6);
  for (int b = 0; b < RS_BLOCKS; b++) {
    const int g = rs_layout_group(mi, dual, b < nb ? b : nb - 1); /* padding: the last group's azimuth */
    double tg = t_pkt + g * group_us(mi);
    double az = fmod(cfg->start_az_deg + deg_per_us * tg, 360.0);
    enc->block_azimuth[b] = (uint16_t)((int)lround(az * 100.0) % 36000);
    if (b >= nb) continue;
    const int bank = rs_layout_bank(mi, dual, b);
    for (int c = 0; c < RS_RECORDS; c++) {
      int laser;
      float tf;
      rs_sensor_record(s, bank, c, &laser, &tf);
      double true_az = (double)enc->block_azimuth[b] / 100.0 + s->azimuth_offset_deg[laser] + deg_per_us * tf;
      double d = rs_synth_range(true_az, s->elevation_deg[laser]);
      if (dual && b % 2 == 1 && d > 0.0) d += 0.75; /* a second, farther return */
      long raw = lround(d / s->dist_res_m);
      if (raw > 65535) raw = 0;
      enc->distance[b][c] = (uint16_t)raw;
      enc->intensity[b][c] = (uint8_t)(raw ? 10 + laser % 100 + (dual && b % 2 ? 5 : 0) : 0);
    }
  }
}

static bool listed(const uint32_t *v, int n, uint32_t k) {
  for (int i = 0; i < n; i++)
    if (v[i] == k) return true;
  return false;
}

long rs_synth_write(const rs_synth_cfg_t *cfg, const char *path) {
  rs_sensor_t s;
  if (rs_sensor_init(&s, cfg->model) != RS_OK) return RS_E_INVAL;
  rs_pcapw_t w;
  int rc = rs_pcapw_open(&w, path, cfg->linktype ? cfg->linktype : RS_LINK_ETHERNET, cfg->vlan);
  if (rc != RS_OK) return rc;
  const uint16_t port = cfg->data_port ? cfg->data_port : RS_DEFAULT_DATA_PORT;
  const uint32_t n = rs_synth_count(cfg);
  static rs_encode_t enc;
  static uint8_t pkt[RS_PAYLOAD_SIZE], held[RS_PAYLOAD_SIZE];
  bool holding = false;
  double held_ts = 0.0;
  long written = 0;
  for (uint32_t k = 0; k < n; k++) {
    double ts = rs_synth_time(cfg, k);
    if (cfg->position_every > 0 && k % (uint32_t)cfg->position_every == 0) {
      uint8_t pos[512];
      memset(pos, 0, sizeof pos);
      memcpy(pos + 206, "$GPRMC,000000,A,0000.0000,N,00000.0000,E,0.0,0.0,010120,,,A*00", 62);
      rs_pcapw_write(&w, ts, RS_DEFAULT_POSITION_PORT, pos, sizeof pos);
    }
    if (cfg->foreign_every > 0 && k % (uint32_t)cfg->foreign_every == 1) {
      uint8_t junk[RS_PAYLOAD_SIZE];
      for (int i = 0; i < RS_PAYLOAD_SIZE; i++) junk[i] = (uint8_t)(i * 7 + 3);
      rs_pcapw_write(&w, ts, port, junk, sizeof junk);
    }
    if (listed(cfg->drop, cfg->ndrop, k)) continue;
    rs_synth_packet(cfg, &s, k, &enc);
    rs_packet_encode(s.info, &enc, pkt);
    if (listed(cfg->swap, cfg->nswap, k)) {
      memcpy(held, pkt, sizeof pkt);
      held_ts = ts;
      holding = true;
      continue;
    }
    rs_pcapw_write(&w, ts, port, pkt, sizeof pkt);
    written++;
    if (listed(cfg->dup, cfg->ndup, k)) {
      rs_pcapw_write(&w, ts + 1e-6, port, pkt, sizeof pkt);
      written++;
    }
    if (holding) {
      rs_pcapw_write(&w, held_ts, port, held, sizeof held);
      written++;
      holding = false;
    }
  }
  if (holding) {
    rs_pcapw_write(&w, held_ts, port, held, sizeof held);
    written++;
  }
  rs_pcapw_close(&w);
  return written;
}

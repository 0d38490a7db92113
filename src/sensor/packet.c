/* packet.c - Velodyne data packet validation, decoding, encoding, detection.
 *
 * Pure code, called by the packet thread (one packet at a time into a
 * caller-owned rs_packet_t) and by tools. Layout of a data packet (1206
 * bytes): 12 blocks of 100 bytes (flag 0xFF 0xEE|DD|CC|BB, azimuth u16 LE in
 * 0.01 degree, 32 records of distance u16 LE + intensity u8), then a u32 LE
 * timestamp (µs past the hour), the return-mode byte and the product byte. */
#include "roadscan/sensor/packet.h"

#include "roadscan/util/error.h"

#include <math.h>
#include <stdio.h>
#include <string.h>

#define DEG2RAD (3.14159265358979323846 / 180.0)
#define OFF_TIMESTAMP 1200
#define OFF_MODE 1204
#define OFF_PRODUCT 1205

static uint16_t le16(const uint8_t *p) { return (uint16_t)(p[0] | (p[1] << 8)); }
static uint32_t le32(const uint8_t *p) {
  return (uint32_t)p[0] | ((uint32_t)p[1] << 8) | ((uint32_t)p[2] << 16) | ((uint32_t)p[3] << 24);
}
static void put16(uint8_t *p, uint16_t v) {
  p[0] = (uint8_t)(v & 0xFF);
  p[1] = (uint8_t)(v >> 8);
}
static void put32(uint8_t *p, uint32_t v) {
  for (int i = 0; i < 4; i++) p[i] = (uint8_t)((v >> (8 * i)) & 0xFF);
}

const char *rs_return_type_name(int t) {
  switch (t) {
  case RS_RET_STRONGEST: return "strongest";
  case RS_RET_LAST: return "last";
  case RS_RET_DUAL_LAST: return "dual-last";
  case RS_RET_DUAL_STRONGEST: return "dual-strongest";
  case RS_RET_DUAL_SECOND: return "dual-second";
  case RS_RET_DUAL_SAME: return "dual-same";
  default: return "unknown";
  }
}

const char *rs_return_mode_name(uint8_t mode) {
  switch (mode) {
  case RS_MODE_STRONGEST: return "strongest";
  case RS_MODE_LAST: return "last";
  case RS_MODE_DUAL: return "dual";
  default: return "unknown";
  }
}

/* bank index of a block flag's second byte, -1 when not a flag */
static int flag_bank(const uint8_t *blk) {
  if (blk[0] != 0xFF) return -1;
  switch (blk[1]) {
  case 0xEE: return 0;
  case 0xDD: return 1;
  case 0xCC: return 2;
  case 0xBB: return 3;
  default: return -1;
  }
}

int rs_layout_blocks(const rs_model_info_t *mi, bool dual) {
  return mi->blocks_per_cycle > 1 && dual ? RS_BLOCKS - RS_BLOCKS / 3 : RS_BLOCKS;
}

int rs_layout_group(const rs_model_info_t *mi, bool dual, int block) {
  if (mi->blocks_per_cycle > 1) return dual ? 0 : block / mi->blocks_per_cycle;
  return dual ? block / 2 : block;
}

int rs_layout_groups(const rs_model_info_t *mi, bool dual) {
  return rs_layout_group(mi, dual, rs_layout_blocks(mi, dual) - 1) + 1;
}

int rs_layout_bank(const rs_model_info_t *mi, bool dual, int block) {
  if (mi->blocks_per_cycle <= 1 || block >= rs_layout_blocks(mi, dual)) return 0; /* padding: bank 0 */
  return dual ? block / 2 : block % mi->blocks_per_cycle;
}

/* blocks holding data for this product/mode, from the product byte (the check runs before detection) */
static int blocks_in_use(uint8_t product, uint8_t mode) {
  const rs_model_info_t *vls = rs_model_info(RS_MODEL_VLS128);
  return rs_layout_blocks(product == vls->product_id ? vls : rs_model_info(RS_MODEL_VLP16), mode == RS_MODE_DUAL);
}

int rs_packet_check(const uint8_t *p, size_t len) {
  if (len < RS_PAYLOAD_SIZE) return RS_E_PKT_SHORT;
  if (len > RS_PAYLOAD_SIZE) return RS_E_PKT_LONG;
  uint8_t mode = p[OFF_MODE];
  /* flags first: a payload that is not Velodyne data at all says so */
  int nb = blocks_in_use(p[OFF_PRODUCT], mode);
  for (int b = 0; b < nb; b++)
    if (flag_bank(p + b * RS_BLOCK_SIZE) < 0) return RS_E_BLOCK_FLAG;
  if (mode != RS_MODE_STRONGEST && mode != RS_MODE_LAST && mode != RS_MODE_DUAL) return RS_E_RETURN_MODE;
  /* 36000 (= 360.00 degrees) is what real sensors send at the roll-over */
  for (int b = 0; b < nb; b++)
    if (le16(p + b * RS_BLOCK_SIZE + 2) > 36000) return RS_E_AZIMUTH;
  return RS_OK;
}


int rs_packet_decode(const rs_sensor_t *s, const uint8_t *p, size_t len, float rate_hint,
                     rs_packet_t *out) {
  int rc = rs_packet_check(p, len);
  if (rc != RS_OK) return rc;
  const rs_model_info_t *mi = s->info;
  const bool dual = p[OFF_MODE] == RS_MODE_DUAL;
  const bool vls = mi->blocks_per_cycle > 1;
  const int nb = rs_layout_blocks(mi, dual);
  const float group_us = rs_model_group_us(mi);

  out->model = mi->model;
  out->product_byte = p[OFF_PRODUCT];
  out->mode_byte = p[OFF_MODE];
  out->timestamp_us = le32(p + OFF_TIMESTAMP);
  out->blocks = (uint8_t)nb;
  out->groups = (uint8_t)rs_layout_groups(mi, dual);
  out->n_points = 0;
  out->n_empty = 0;

  for (int b = 0; b < RS_BLOCKS; b++) out->block_azimuth[b] = le16(p + b * RS_BLOCK_SIZE + 2);
  for (int b = 0; b < nb; b++) {
    int bank = flag_bank(p + b * RS_BLOCK_SIZE);
    if (!vls && bank != 0) return RS_E_BLOCK_FLAG;
  }

  /* rotation rate from this packet's first and last azimuth groups */
  out->az_rate = rate_hint;
  out->az_rate_measured = false;
  if (out->groups >= 2) {
    int first = 0, last = 0;
    for (int b = 0; b < nb; b++)
      if (rs_layout_group(mi, dual, b) == out->groups - 1) {
        last = b;
        break;
      }
    int d = ((int)out->block_azimuth[last] - (int)out->block_azimuth[first] + 36000) % 36000;
    float rate = (float)d / 100.0f / ((float)(out->groups - 1) * group_us);
    double hz = rs_hz_from_rate(rate);
    if (hz >= mi->min_hz * 0.5 && hz <= mi->max_hz * 1.5) {
      out->az_rate = rate;
      out->az_rate_measured = true;
    }
  }

  for (int b = 0; b < nb; b++) {
    const uint8_t *blk = p + b * RS_BLOCK_SIZE;
    const int bank = vls ? flag_bank(blk) : 0;
    const int g = rs_layout_group(mi, dual, b);
    /* azimuth reference: the first block of the group */
    int gb = b;
    while (gb > 0 && rs_layout_group(mi, dual, gb - 1) == g) gb--;
    const float az0 = (float)out->block_azimuth[gb] / 100.0f;
    const float tbase = (float)g * group_us;
    const bool odd_twin = dual && (b % 2 == 1);

    for (int c = 0; c < RS_RECORDS; c++) {
      const uint8_t *rec = blk + 4 + 3 * c;
      uint16_t raw = le16(rec);
      if (raw == 0) {
        out->n_empty++;
        continue;
      }
      int laser;
      float t;
      rs_sensor_record(s, bank, c, &laser, &t);
      if (laser >= s->lasers) continue; /* cannot happen with consistent tables */
      const float dist = (float)raw * s->dist_res_m + s->dist_correction_m[laser];
      if (!(dist > 0.0f)) { /* a correction larger than the measured range: no return */
        out->n_empty++;
        continue;
      }
      rs_point_t *pt = &out->points[out->n_points++];
      float az = az0 + s->azimuth_offset_deg[laser] + out->az_rate * t;
      az = fmodf(az, 360.0f);
      if (az < 0.0f) az += 360.0f;
      const float a = az * (float)DEG2RAD;
      const float xy = dist * s->cos_el[laser];
      pt->x = xy * sinf(a);
      pt->y = xy * cosf(a);
      pt->z = dist * s->sin_el[laser] + s->vert_offset_m[laser];
      pt->distance = dist;
      pt->azimuth = az;
      pt->t_us = tbase + t;
      pt->block_azimuth = out->block_azimuth[b];
      pt->intensity = rec[2];
      pt->laser = (uint8_t)laser;
      pt->row = s->row_of_laser[laser];
      pt->block = (uint8_t)b;
      pt->channel = (uint8_t)c;
      pt->layer = 0;
      if (!dual) {
        pt->return_type = p[OFF_MODE] == RS_MODE_LAST ? RS_RET_LAST : RS_RET_STRONGEST;
      } else if (!odd_twin) {
        pt->return_type = RS_RET_DUAL_LAST;
      } else {
        const uint8_t *twin = p + (b - 1) * RS_BLOCK_SIZE + 4 + 3 * c;
        pt->layer = 1;
        if (le16(twin) == raw && twin[2] == rec[2])
          pt->return_type = RS_RET_DUAL_SAME;
        else if (rec[2] > twin[2] || le16(twin) == 0)
          pt->return_type = RS_RET_DUAL_STRONGEST;
        else
          pt->return_type = RS_RET_DUAL_SECOND;
      }
    }
  }
  return RS_OK;
}

void rs_packet_encode(const rs_model_info_t *mi, const rs_encode_t *in, uint8_t out[RS_PAYLOAD_SIZE]) {
  static const uint8_t bank_flag[4] = {0xEE, 0xDD, 0xCC, 0xBB};
  const bool dual = in->mode_byte == RS_MODE_DUAL;
  const int nb = rs_layout_blocks(mi, dual);
  memset(out, 0, RS_PAYLOAD_SIZE);
  for (int b = 0; b < RS_BLOCKS; b++) {
    uint8_t *blk = out + b * RS_BLOCK_SIZE;
    blk[0] = 0xFF;
    blk[1] = bank_flag[rs_layout_bank(mi, dual, b) & 3];
    put16(blk + 2, in->block_azimuth[b]);
    if (b >= nb) continue; /* padding blocks */
    for (int c = 0; c < RS_RECORDS; c++) {
      put16(blk + 4 + 3 * c, in->distance[b][c]);
      blk[4 + 3 * c + 2] = in->intensity[b][c];
    }
  }
  put32(out + OFF_TIMESTAMP, in->timestamp_us);
  out[OFF_MODE] = in->mode_byte;
  out[OFF_PRODUCT] = in->product_byte ? in->product_byte : mi->product_id;
}

/* ---- detection ---- */

void rs_detect_init(rs_detect_t *d, rs_model_t forced) {
  memset(d, 0, sizeof *d);
  d->forced = forced;
  d->decided = forced;
  if (forced != RS_MODEL_UNKNOWN)
    snprintf(d->reason, sizeof d->reason, "model forced to %s", rs_model_name(forced));
}

static int decide(rs_detect_t *d, rs_model_t m, const char *why) {
  d->decided = m;
  snprintf(d->reason, sizeof d->reason, "product byte 0x%02X: %s%s%s", d->product, rs_model_name(m),
           why[0] ? " " : "", why);
  return (int)m;
}

/* The VLP-16 family puts two firing cycles of the same 16 lasers in a block:
 * records i and i+16 measure nearly the same range. An HDL-32E's records i
 * and i+16 are lasers 10-20 degrees apart. */
static void twin_score(rs_detect_t *d, const uint8_t *p) {
  for (int b = 0; b < RS_BLOCKS; b++) {
    const uint8_t *blk = p + b * RS_BLOCK_SIZE + 4;
    for (int i = 0; i < 16; i++) {
      int r1 = le16(blk + 3 * i), r2 = le16(blk + 3 * (i + 16));
      if (r1 == 0 || r2 == 0) continue;
      d->twin_pairs++;
      if (r1 - r2 < 50 && r2 - r1 < 50) d->twin_close++; /* 10 cm at 2 mm */
    }
  }
}

/* Firing timing of the pair (previous packet, this one): the duration of one
 * block group is the azimuth step per group x time / azimuth between the
 * packets' first blocks. Votes for the model it fits within 10 %. */
static void timing_score(rs_detect_t *d, const uint8_t *p) {
  const bool dual = p[OFF_MODE] == RS_MODE_DUAL;
  const int groups = dual ? 6 : 12, per = RS_BLOCKS / groups;
  const uint32_t ts = le32(p + OFF_TIMESTAMP);
  const uint16_t az0 = le16(p + 2), azl = le16(p + (groups - 1) * per * RS_BLOCK_SIZE + 2);
  if (d->have_last) {
    double dt = (double)((ts + 3600000000u - d->last_ts) % 3600000000u);
    double da = (double)((az0 + 36000u - d->last_az) % 36000u);
    double step = (double)((azl + 36000u - az0) % 36000u) / (groups - 1);
    /* adjacent-ish packets only (under 50 ms apart, under half a turn) */
    if (dt > 0 && dt < 50000 && da > 0 && da < 18000 && step > 0) {
      double group_us = step * dt / da;
      double v = rs_model_group_us(rs_model_info(RS_MODEL_VLP16)), h = rs_model_group_us(rs_model_info(RS_MODEL_HDL32E));
      if (fabs(group_us - v) < 0.1 * v) d->timing_vlp16++;
      else if (fabs(group_us - h) < 0.1 * h) d->timing_claimed++;
    }
  }
  d->last_ts = ts;
  d->last_az = az0;
  d->have_last = true;
}

static int decide_hdl_or_vlp16(rs_detect_t *d, bool final) {
  char why[160];
  const int tv = d->timing_vlp16, th = d->timing_claimed, pairs = d->twin_pairs;
  const double share = pairs ? (double)d->twin_close / pairs : 0.5;
  const bool twin_known = pairs >= 256;
  if (d->packets >= RS_DETECT_MIN_PACKETS) {
    /* timing agrees over several pairs, and repetition does not contradict it */
    if (tv >= 3 && tv >= 4 * th && (!twin_known || share >= 0.35)) {
      snprintf(why, sizeof why, "overridden: VLP-16 firing timing in %d of %d packet pairs, records i and i+16 repeat in %.0f%% of %d pairs",
               tv, tv + th, share * 100.0, pairs);
      return decide(d, RS_MODEL_VLP16, why);
    }
    if (th >= 3 && th >= 4 * tv && (!twin_known || share < 0.6)) {
      snprintf(why, sizeof why, "confirmed: HDL-32E firing timing in %d of %d packet pairs, records i and i+16 repeat in %.0f%% of %d pairs",
               th, tv + th, share * 100.0, pairs);
      return decide(d, RS_MODEL_HDL32E, why);
    }
    /* no usable timestamps: repetition alone, over many pairs */
    if (tv + th < 3 && pairs >= 512 && (share >= 0.7 || share <= 0.3)) {
      bool v = share >= 0.7;
      snprintf(why, sizeof why, "%s: records i and i+16 repeat in %.0f%% of %d pairs (no usable timestamps)",
               v ? "overridden" : "confirmed", share * 100.0, pairs);
      return decide(d, v ? RS_MODEL_VLP16 : RS_MODEL_HDL32E, why);
    }
  }
  if (!final) return RS_MODEL_UNKNOWN;
  /* out of patience: the weight of evidence (timing first), said to be unsure */
  bool v = tv != th ? tv > th : (pairs >= 64 ? share > 0.5 : false);
  snprintf(why, sizeof why, "%s, unsure after %d packets: timing VLP-16 %d / HDL-32E %d pairs, records repeat in %.0f%% of %d",
           v ? "overridden" : "kept", d->packets, tv, th, share * 100.0, pairs);
  return decide(d, v ? RS_MODEL_VLP16 : RS_MODEL_HDL32E, why);
}

int rs_detect_feed(rs_detect_t *d, const uint8_t *p, size_t len) {
  if (d->decided != RS_MODEL_UNKNOWN) return (int)d->decided;
  if (len != RS_PAYLOAD_SIZE) return RS_E_INVAL;
  uint8_t product = p[OFF_PRODUCT];
  rs_model_t claimed = rs_model_from_product(product);
  if (claimed == RS_MODEL_UNKNOWN) return RS_E_PRODUCT;
  if (d->packets == 0) {
    d->product = product;
    d->mode = p[OFF_MODE];
  } else if (product != d->product) {
    return RS_E_PRODUCT_MISMATCH;
  }
  d->packets++;
  if (claimed != RS_MODEL_HDL32E) return decide(d, claimed, "");
  twin_score(d, p);
  timing_score(d, p);
  return decide_hdl_or_vlp16(d, d->packets >= RS_DETECT_MAX_PACKETS);
}

int rs_detect_finish(rs_detect_t *d) {
  if (d->decided != RS_MODEL_UNKNOWN) return (int)d->decided;
  if (d->packets == 0) return RS_MODEL_UNKNOWN;
  return decide_hdl_or_vlp16(d, true);
}

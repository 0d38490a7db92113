/* check_packet - decoding hand-built packets against values computed here
 * from the manuals' figures; validation errors; encoder round trip;
 * model detection. */
#include "roadscan/util/error.h"
#include "roadscan/sensor/packet.h"
#include "testutil.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#define D2R (3.14159265358979323846 / 180.0)

static uint8_t pkt[1206];
static rs_packet_t out;

static const rs_point_t *find(int block, int ch) {
  for (int i = 0; i < out.n_points; i++)
    if (out.points[i].block == block && out.points[i].channel == ch) return &out.points[i];
  return NULL;
}

START_TEST(t_vlp16_point) {
  rs_sensor_t s;
  rs_sensor_init(&s, RS_MODEL_VLP16);
  /* 0.40 degree per block of 110.592 us */
  tu_empty_packet(pkt, 9000, 40, 0x37, 0x22);
  tu_record(pkt, 0, 0, 5000, 77);  /* laser 0 (-15 deg), 10.000 m */
  tu_record(pkt, 0, 17, 2500, 5);  /* laser 1 (+1 deg), second firing cycle, 5.000 m */
  tu_record(pkt, 11, 15, 1000, 9); /* laser 15 (+15 deg), last block */
  ck_assert_int_eq(rs_packet_decode(&s, pkt, 1206, 0.0036f, &out), RS_OK);
  ck_assert_int_eq(out.n_points, 3);
  ck_assert_int_eq(out.n_empty, 12 * 32 - 3);
  ck_assert(out.az_rate_measured);
  double rate = 0.40 / 110.592; /* degrees per us */
  ck_assert_float_eq_tol(out.az_rate, rate, 1e-6);

  const rs_point_t *p = find(0, 0);
  ck_assert_ptr_nonnull(p);
  ck_assert_float_eq_tol(p->distance, 10.0, 1e-5);
  ck_assert_float_eq_tol(p->azimuth, 90.0, 1e-4);
  double voff = 0.04191 * tan(15 * D2R);
  ck_assert_float_eq_tol(p->x, 10.0 * cos(-15 * D2R), 1e-3);
  ck_assert_float_eq_tol(p->y, 0.0, 1e-3);
  ck_assert_float_eq_tol(p->z, 10.0 * sin(-15 * D2R) + voff, 1e-3);
  ck_assert_int_eq(p->intensity, 77);
  ck_assert_int_eq(p->laser, 0);
  ck_assert_int_eq(p->row, 0);
  ck_assert_int_eq(p->return_type, RS_RET_STRONGEST);

  p = find(0, 17);
  ck_assert_ptr_nonnull(p);
  double az = 90.0 + rate * (55.296 + 2.304);
  ck_assert_float_eq_tol(p->azimuth, az, 1e-4);
  ck_assert_int_eq(p->laser, 1);
  ck_assert_int_eq(p->row, 8); /* +1 deg is the 9th lowest of -15..15 */
  ck_assert_float_eq_tol(p->x, 5.0 * cos(1 * D2R) * sin(az * D2R), 1e-3);
  ck_assert_float_eq_tol(p->y, 5.0 * cos(1 * D2R) * cos(az * D2R), 1e-3);
  ck_assert_float_eq_tol(p->t_us, 57.6, 1e-3);

  p = find(11, 15);
  ck_assert_ptr_nonnull(p);
  ck_assert_float_eq_tol(p->azimuth, 94.4 + rate * 15 * 2.304, 1e-4);
  ck_assert_float_eq_tol(p->t_us, 11 * 110.592 + 15 * 2.304, 1e-2);
}
END_TEST

START_TEST(t_hdl32_vlp32c_vls128) {
  rs_sensor_t s;
  /* HDL-32E: 1.152 us per laser, 46.08 us per block */
  rs_sensor_init(&s, RS_MODEL_HDL32E);
  tu_empty_packet(pkt, 35990, 20, 0x37, 0x21); /* crosses 360 inside the packet */
  tu_record(pkt, 1, 31, 10000, 1);
  ck_assert_int_eq(rs_packet_decode(&s, pkt, 1206, 0.0036f, &out), RS_OK);
  double rate = 0.20 / 46.08;
  ck_assert_float_eq_tol(out.az_rate, rate, 1e-6);
  const rs_point_t *p = find(1, 31);
  ck_assert_float_eq_tol(p->azimuth, fmod(360.10 + rate * 31 * 1.152, 360.0), 1e-4);
  ck_assert_float_eq_tol(p->distance, 20.0, 1e-5);
  ck_assert_float_eq_tol(p->z, 20.0 * sin(10.67 * D2R) - 0.00545, 1e-3);

  /* VLP-32C: per-laser azimuth offset, pairs every 2.304 us, 4 mm units */
  rs_sensor_init(&s, RS_MODEL_VLP32C);
  tu_empty_packet(pkt, 18000, 20, 0x37, 0x28);
  tu_record(pkt, 0, 1, 2500, 1); /* laser 1: -1 deg, offset -4.2 deg, fires at t=0 */
  tu_record(pkt, 0, 6, 2500, 1); /* laser 6: offset +4.2, fires at 3 * 2.304 us */
  ck_assert_int_eq(rs_packet_decode(&s, pkt, 1206, 0.0036f, &out), RS_OK);
  rate = 0.20 / 55.296;
  ck_assert_float_eq_tol(find(0, 1)->azimuth, 180.0 - 4.2, 1e-4);
  ck_assert_float_eq_tol(find(0, 1)->distance, 10.0, 1e-5);
  ck_assert_float_eq_tol(find(0, 6)->azimuth, 180.0 + 4.2 + rate * 3 * 2.304, 1e-4);

  /* VLS-128: the block flag names the bank of 32 lasers */
  rs_sensor_init(&s, RS_MODEL_VLS128);
  memset(pkt, 0, sizeof pkt);
  static const uint8_t flags[4] = {0xEE, 0xDD, 0xCC, 0xBB};
  for (int b = 0; b < 12; b++) tu_block(pkt, b, flags[b % 4], (uint16_t)(1000 + 20 * (b / 4)));
  tu_tail(pkt, 5, 0x37, 0xA1);
  tu_record(pkt, 5, 0, 2500, 3); /* second cycle, bank 1: laser 32 */
  tu_record(pkt, 11, 31, 2500, 3); /* third cycle, bank 3: laser 127 */
  ck_assert_int_eq(rs_packet_decode(&s, pkt, 1206, 0.0036f, &out), RS_OK);
  rate = 0.20 / 53.3;
  ck_assert_int_eq(out.groups, 3);
  ck_assert_float_eq_tol(out.az_rate, rate, 1e-6);
  p = find(5, 0);
  ck_assert_int_eq(p->laser, 32);
  ck_assert_float_eq_tol(p->azimuth, 10.20 + 6.354 + rate * 4 * 2.665, 1e-4);
  ck_assert_float_eq_tol(p->t_us, 53.3 + 4 * 2.665, 1e-3);
  p = find(11, 31);
  ck_assert_int_eq(p->laser, 127);
  ck_assert_float_eq_tol(p->azimuth, 10.40 - 6.354 + rate * 16 * 2.665, 1e-4);
}
END_TEST

START_TEST(t_dual) {
  rs_sensor_t s;
  rs_sensor_init(&s, RS_MODEL_VLP16);
  memset(pkt, 0, sizeof pkt);
  for (int b = 0; b < 12; b++) tu_block(pkt, b, 0xEE, (uint16_t)(100 + 40 * (b / 2)));
  tu_tail(pkt, 5, 0x39, 0x22);
  tu_record(pkt, 0, 0, 5000, 10);  /* last return */
  tu_record(pkt, 1, 0, 4000, 50);  /* strongest return, nearer */
  tu_record(pkt, 2, 3, 3000, 40);  /* last = strongest */
  tu_record(pkt, 3, 3, 2000, 20);  /* second strongest */
  tu_record(pkt, 4, 5, 3000, 40);  /* single return reported twice */
  tu_record(pkt, 5, 5, 3000, 40);
  ck_assert_int_eq(rs_packet_decode(&s, pkt, 1206, 0.0036f, &out), RS_OK);
  ck_assert_int_eq(out.groups, 6);
  ck_assert_float_eq_tol(out.az_rate, 0.40 / 110.592, 1e-6);
  ck_assert_int_eq(out.n_points, 6);
  ck_assert_int_eq(find(0, 0)->return_type, RS_RET_DUAL_LAST);
  ck_assert_int_eq(find(0, 0)->layer, 0);
  ck_assert_int_eq(find(1, 0)->return_type, RS_RET_DUAL_STRONGEST);
  ck_assert_int_eq(find(1, 0)->layer, 1);
  ck_assert_float_eq_tol(find(1, 0)->azimuth, find(0, 0)->azimuth, 1e-6);
  ck_assert_int_eq(find(3, 3)->return_type, RS_RET_DUAL_SECOND);
  ck_assert_int_eq(find(5, 5)->return_type, RS_RET_DUAL_SAME);
  /* block pair k fires at k * 110.592 us */
  ck_assert_float_eq_tol(find(2, 3)->t_us, 110.592 + 3 * 2.304, 1e-3);
}
END_TEST

START_TEST(t_validation) {
  rs_sensor_t s;
  rs_sensor_init(&s, RS_MODEL_VLP16);
  tu_empty_packet(pkt, 0, 40, 0x37, 0x22);
  ck_assert_int_eq(rs_packet_check(pkt, 1206), RS_OK);
  ck_assert_int_eq(rs_packet_check(pkt, 1205), RS_E_PKT_SHORT);
  ck_assert_int_eq(rs_packet_check(pkt, 1207), RS_E_PKT_LONG);
  ck_assert_int_eq(rs_packet_decode(&s, pkt, 100, 0.0036f, &out), RS_E_PKT_SHORT);
  tu_block(pkt, 7, 0xEF, 280);
  ck_assert_int_eq(rs_packet_decode(&s, pkt, 1206, 0.0036f, &out), RS_E_BLOCK_FLAG);
  tu_empty_packet(pkt, 0, 40, 0x37, 0x22);
  tu_block(pkt, 3, 0xDD, 120); /* a bank flag, but not a VLS-128 */
  ck_assert_int_eq(rs_packet_check(pkt, 1206), RS_OK);
  ck_assert_int_eq(rs_packet_decode(&s, pkt, 1206, 0.0036f, &out), RS_E_BLOCK_FLAG);
  tu_empty_packet(pkt, 0, 40, 0x37, 0x22);
  tu_block(pkt, 11, 0xEE, 36001);
  ck_assert_int_eq(rs_packet_decode(&s, pkt, 1206, 0.0036f, &out), RS_E_AZIMUTH);
  tu_block(pkt, 11, 0xEE, 36000); /* sensors send 360.00 at the roll-over */
  ck_assert_int_eq(rs_packet_decode(&s, pkt, 1206, 0.0036f, &out), RS_OK);
  tu_empty_packet(pkt, 0, 40, 0x40, 0x22);
  ck_assert_int_eq(rs_packet_decode(&s, pkt, 1206, 0.0036f, &out), RS_E_RETURN_MODE);
  /* one azimuth group only: the hint is used */
  tu_empty_packet(pkt, 500, 0, 0x37, 0x22);
  ck_assert_int_eq(rs_packet_decode(&s, pkt, 1206, 0.00123f, &out), RS_OK);
  ck_assert(!out.az_rate_measured);
  ck_assert_float_eq_tol(out.az_rate, 0.00123, 1e-9);
}
END_TEST

START_TEST(t_roundtrip) {
  static const uint8_t modes[3] = {RS_MODE_STRONGEST, RS_MODE_LAST, RS_MODE_DUAL};
  srand(7);
  for (int m = RS_MODEL_VLP16; m < RS_MODEL_COUNT; m++) {
    rs_sensor_t s;
    rs_sensor_init(&s, (rs_model_t)m);
    for (int mi = 0; mi < 3; mi++) {
      static rs_encode_t enc;
      memset(&enc, 0, sizeof enc);
      enc.mode_byte = modes[mi];
      enc.timestamp_us = 123456789u;
      bool dual = modes[mi] == RS_MODE_DUAL, vls = m == RS_MODEL_VLS128;
      int nb = vls && dual ? 8 : 12;
      for (int b = 0; b < 12; b++) {
        int g = vls ? (dual ? 0 : b / 4) : (dual ? b / 2 : b);
        enc.block_azimuth[b] = (uint16_t)(35900 + 20 * g) % 36000;
        for (int c = 0; c < 32; c++) {
          enc.distance[b][c] = (uint16_t)(rand() % 3 == 0 ? 0 : 1 + rand() % 60000);
          enc.intensity[b][c] = (uint8_t)(rand() % 256);
        }
      }
      rs_packet_encode(s.info, &enc, pkt);
      ck_assert_int_eq(pkt[1205], s.info->product_id);
      ck_assert_int_eq(rs_packet_decode(&s, pkt, 1206, 0.0036f, &out), RS_OK);
      ck_assert_int_eq(out.timestamp_us, 123456789u);
      ck_assert_int_eq(out.blocks, nb);
      int expect = 0;
      for (int b = 0; b < nb; b++)
        for (int c = 0; c < 32; c++) expect += enc.distance[b][c] != 0;
      ck_assert_int_eq(out.n_points, expect);
      for (int i = 0; i < out.n_points; i++) {
        const rs_point_t *p = &out.points[i];
        uint16_t raw = enc.distance[p->block][p->channel];
        ck_assert_float_eq_tol(p->distance, raw * s.dist_res_m, 1e-3);
        ck_assert_int_eq(p->intensity, enc.intensity[p->block][p->channel]);
        ck_assert_int_eq(p->block_azimuth, enc.block_azimuth[p->block]);
        int bank = rs_layout_bank(s.info, dual, p->block), laser;
        float t;
        rs_sensor_record(&s, bank, p->channel, &laser, &t);
        ck_assert_int_eq(p->laser, laser);
        float r = sqrtf(p->x * p->x + p->y * p->y + (p->z - s.vert_offset_m[laser]) * (p->z - s.vert_offset_m[laser]));
        ck_assert_float_eq_tol(r, p->distance, 1e-3 * p->distance + 1e-3);
      }
    }
  }
}
END_TEST

/* packet k of a 0x21 stream: block azimuths step `step` (0.01 deg) from
 * k * 12 * step, sensor timestamps `spacing` us apart; records i and i+16
 * repeat (twins) or not */
static void stream_packet(uint8_t *p, int k, int step, uint32_t spacing, bool twins) {
  tu_empty_packet(p, (uint16_t)((k * 12 * step) % 36000), (uint16_t)step, 0x37, 0x21);
  tu_tail(p, 1000u + (uint32_t)k * spacing, 0x37, 0x21);
  for (int b = 0; b < 12; b++)
    for (int i = 0; i < 16; i++) {
      tu_record(p, b, i, (uint16_t)(3000 + 100 * i), 1);
      tu_record(p, b, i + 16, (uint16_t)(twins ? 3000 + 100 * i + 3 : 9000 - 200 * i), 1);
    }
}

/* feeds packets until a decision (or n packets); returns it and the count */
static int feed_until(rs_detect_t *d, int n, int step, uint32_t spacing, bool (*twins)(int), int *used) {
  int r = RS_MODEL_UNKNOWN, k = 0;
  for (; k < n && r == RS_MODEL_UNKNOWN; k++) {
    stream_packet(pkt, k, step, spacing, twins(k));
    r = rs_detect_feed(d, pkt, 1206);
  }
  if (used) *used = k;
  return r;
}
static bool always(int k) { (void)k; return true; }
static bool never(int k) { (void)k; return false; }
static bool first_unlucky(int k) { return k > 0; }
static bool half(int k) { return k % 2 == 0; }

START_TEST(t_detect) {
  rs_detect_t d;
  int used;
  /* early VLP-16 firmware reports 0x21: VLP-16 timing (110.6 us per block at
   * 20 Hz: 80 x 0.01 deg per block, 1327 us per packet), records repeat */
  rs_detect_init(&d, RS_MODEL_UNKNOWN);
  ck_assert_int_eq(feed_until(&d, 40, 80, 1327, always, &used), RS_MODEL_VLP16);
  ck_assert_int_ge(used, RS_DETECT_MIN_PACKETS); /* never one packet */
  ck_assert_ptr_nonnull(strstr(d.reason, "VLP-16 firing timing"));
  /* the same at 5 Hz with packets lost in between: the ratio still fits */
  rs_detect_init(&d, RS_MODEL_UNKNOWN);
  int r = RS_MODEL_UNKNOWN;
  for (int k = 0; k < 60 && r == RS_MODEL_UNKNOWN; k += 3) {
    stream_packet(pkt, k, 20, 1327, true);
    r = rs_detect_feed(&d, pkt, 1206);
  }
  ck_assert_int_eq(r, RS_MODEL_VLP16);
  /* a genuine HDL-32E: 46.08 us per block (20 x 0.01 deg at 12 Hz: 553 us per packet) */
  rs_detect_init(&d, RS_MODEL_UNKNOWN);
  ck_assert_int_eq(feed_until(&d, 40, 20, 553, never, &used), RS_MODEL_HDL32E);
  ck_assert_int_ge(used, RS_DETECT_MIN_PACKETS);
  /* one unlucky first packet (no repetition) does not decide */
  rs_detect_init(&d, RS_MODEL_UNKNOWN);
  ck_assert_int_eq(feed_until(&d, 40, 80, 1327, first_unlucky, NULL), RS_MODEL_VLP16);
  /* no usable timestamps (all the same): repetition alone over many pairs */
  rs_detect_init(&d, RS_MODEL_UNKNOWN);
  ck_assert_int_eq(feed_until(&d, 40, 80, 0, always, &used), RS_MODEL_VLP16);
  ck_assert_ptr_nonnull(strstr(d.reason, "no usable timestamps"));
  rs_detect_init(&d, RS_MODEL_UNKNOWN);
  ck_assert_int_eq(feed_until(&d, 40, 20, 0, never, NULL), RS_MODEL_HDL32E);
  /* cues that disagree (HDL-32E timing, VLP-16 repetition) keep it open up
   * to the pre-buffer's end, then timing decides and the reason says unsure */
  rs_detect_init(&d, RS_MODEL_UNKNOWN);
  ck_assert_int_eq(feed_until(&d, RS_DETECT_MAX_PACKETS, 20, 553, always, &used), RS_MODEL_HDL32E);
  ck_assert_int_eq(used, RS_DETECT_MAX_PACKETS);
  ck_assert_ptr_nonnull(strstr(d.reason, "unsure"));
  /* half the packets repeat, timing says VLP-16: VLP-16 */
  rs_detect_init(&d, RS_MODEL_UNKNOWN);
  ck_assert_int_eq(feed_until(&d, 40, 80, 1327, half, NULL), RS_MODEL_VLP16);
  /* undecided at end of input: the evidence decides, or the product byte */
  rs_detect_init(&d, RS_MODEL_UNKNOWN);
  tu_empty_packet(pkt, 0, 20, 0x37, 0x21);
  ck_assert_int_eq(rs_detect_feed(&d, pkt, 1206), RS_MODEL_UNKNOWN);
  ck_assert_int_eq(rs_detect_finish(&d), RS_MODEL_HDL32E);
  /* other products decide at once; unknown products are errors */
  rs_detect_init(&d, RS_MODEL_UNKNOWN);
  tu_empty_packet(pkt, 0, 20, 0x37, 0x28);
  ck_assert_int_eq(rs_detect_feed(&d, pkt, 1206), RS_MODEL_VLP32C);
  rs_detect_init(&d, RS_MODEL_UNKNOWN);
  tu_empty_packet(pkt, 0, 20, 0x37, 0x99);
  ck_assert_int_eq(rs_detect_feed(&d, pkt, 1206), RS_E_PRODUCT);
  rs_detect_init(&d, RS_MODEL_VLS128);
  ck_assert_int_eq(rs_detect_feed(&d, pkt, 1206), RS_MODEL_VLS128);
}
END_TEST

/* the layout rules against the manuals' tables, written out by hand */
START_TEST(t_layout_rules) {
  const rs_model_info_t *vls = rs_model_info(RS_MODEL_VLS128), *vlp = rs_model_info(RS_MODEL_VLP16),
                        *hdl = rs_model_info(RS_MODEL_HDL32E);
  static const int vls_bank[12] = {0, 1, 2, 3, 0, 1, 2, 3, 0, 1, 2, 3}, vls_group[12] = {0, 0, 0, 0, 1, 1, 1, 1, 2, 2, 2, 2};
  static const int vls_dual_bank[12] = {0, 0, 1, 1, 2, 2, 3, 3, 0, 0, 0, 0};
  ck_assert_int_eq(rs_layout_blocks(vls, false), 12);
  ck_assert_int_eq(rs_layout_blocks(vls, true), 8);
  ck_assert_int_eq(rs_layout_groups(vls, false), 3);
  ck_assert_int_eq(rs_layout_groups(vls, true), 1);
  for (int b = 0; b < 12; b++) {
    ck_assert_int_eq(rs_layout_bank(vls, false, b), vls_bank[b]);
    ck_assert_int_eq(rs_layout_group(vls, false, b), vls_group[b]);
    ck_assert_int_eq(rs_layout_bank(vls, true, b), vls_dual_bank[b]);
    if (b < 8) ck_assert_int_eq(rs_layout_group(vls, true, b), 0);
    ck_assert_int_eq(rs_layout_bank(vlp, false, b), 0);
    ck_assert_int_eq(rs_layout_group(vlp, false, b), b);
    ck_assert_int_eq(rs_layout_group(hdl, true, b), b / 2);
  }
  ck_assert_int_eq(rs_layout_blocks(vlp, true), 12);
  ck_assert_int_eq(rs_layout_groups(vlp, false), 12);
  ck_assert_int_eq(rs_layout_groups(hdl, true), 6);
}
END_TEST

int main(void) {
  Suite *s = suite_create("packet");
  TCase *tc = tcase_create("core");
  tcase_add_test(tc, t_layout_rules);
  tcase_add_test(tc, t_vlp16_point);
  tcase_add_test(tc, t_hdl32_vlp32c_vls128);
  tcase_add_test(tc, t_dual);
  tcase_add_test(tc, t_validation);
  tcase_add_test(tc, t_roundtrip);
  tcase_add_test(tc, t_detect);
  suite_add_tcase(s, tc);
  return tu_run(s);
}

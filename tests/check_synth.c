/* check_synth - synthetic captures: the packet count and timing for the rate
 * and model, the room's ranges decoded back, and the faults (dropped,
 * swapped, duplicated packets, position packets, foreign traffic) where
 * they were asked for. */
#include "roadscan/capture/capture.h"
#include "roadscan/util/error.h"
#include "roadscan/capture/net.h"
#include "roadscan/sensor/packet.h"
#include "roadscan/sensor/sensor.h"
#include "roadscan/sim/synth.h"
#include "testutil.h"

#include <math.h>
#include <string.h>

typedef struct {
  uint32_t data, position, foreign;
  uint32_t ts_order[4096]; /* the data packets' sensor timestamps, in file order */
} tally_t;

static void read_back(const char *path, tally_t *t) {
  memset(t, 0, sizeof *t);
  rs_capture_t c;
  rs_capture_cfg_t cfg = {.data_port = 2368, .speed = 0};
  ck_assert_int_eq(rs_capture_open_file(&c, path, &cfg), RS_OK);
  rs_frame_in_t f;
  while (rs_capture_next(&c, &f, NULL) == 1) {
    rs_udp_t u;
    ck_assert_int_eq(rs_net_parse(c.linktype, f.data, f.caplen, &u), RS_OK);
    if (u.dst_port == 8308) {
      t->position++;
      continue;
    }
    if (rs_packet_check(u.payload, u.len) != RS_OK) {
      t->foreign++;
      continue;
    }
    if (t->data < 4096)
      t->ts_order[t->data] = (uint32_t)u.payload[1200] | (uint32_t)u.payload[1201] << 8 |
                             (uint32_t)u.payload[1202] << 16 | (uint32_t)u.payload[1203] << 24;
    t->data++;
  }
  rs_capture_close(&c);
}

START_TEST(t_counts_and_ranges) {
  rs_synth_cfg_t cfg = {.model = RS_MODEL_VLP16, .mode = RS_MODE_STRONGEST, .hz = 10.0, .seconds = 0.5, .t0 = 1e9,
                        .linktype = RS_LINK_ETHERNET};
  const uint32_t n = rs_synth_count(&cfg);
  /* a VLP-16 sends 754 packets per second in strongest mode */
  ck_assert(fabs((double)n - 0.5 * 753.6) <= 1.0);
  ck_assert_double_eq_tol(rs_synth_time(&cfg, 1) - rs_synth_time(&cfg, 0), 24 * 55.296e-6, 5e-7); /* (t0 = 1e9 s) */
  const char *path = tu_tmp("synth.pcap");
  ck_assert_int_eq(rs_synth_write(&cfg, path), (long)n);
  tally_t t;
  read_back(path, &t);
  ck_assert_uint_eq(t.data, n);
  ck_assert_uint_eq(t.position, 0);
  /* the decoded ranges are the room's */
  rs_sensor_t s;
  rs_sensor_init(&s, RS_MODEL_VLP16);
  rs_encode_t enc;
  rs_synth_packet(&cfg, &s, 10, &enc);
  static uint8_t buf[RS_PAYLOAD_SIZE];
  rs_packet_encode(s.info, &enc, buf);
  static rs_packet_t pkt;
  ck_assert_int_eq(rs_packet_decode(&s, buf, RS_PAYLOAD_SIZE, 0.0036, &pkt), RS_OK);
  int checked = 0;
  for (int i = 0; i < pkt.n_points; i++) {
    const rs_point_t *p = &pkt.points[i];
    const double want = rs_synth_range(p->azimuth, s.elevation_deg[s.laser_of_row[p->row]]);
    if (want <= 0) continue;
    ck_assert_msg(fabs(p->distance - want) < 0.05, "az %.2f: %.3f vs %.3f", p->azimuth, p->distance, want);
    checked++;
  }
  ck_assert_int_gt(checked, 100);
}
END_TEST

START_TEST(t_faults) {
  static const uint32_t drop[] = {5, 6}, swap[] = {10}, dup[] = {20};
  rs_synth_cfg_t cfg = {.model = RS_MODEL_VLP32C, .mode = RS_MODE_STRONGEST, .hz = 10.0, .seconds = 0.1, .t0 = 1e9,
                        .linktype = RS_LINK_ETHERNET, .position_every = 25, .foreign_every = 30,
                        .drop = drop, .ndrop = 2, .swap = swap, .nswap = 1, .dup = dup, .ndup = 1};
  const uint32_t n = rs_synth_count(&cfg);
  const char *path = tu_tmp("synth-faults.pcap");
  ck_assert_int_eq(rs_synth_write(&cfg, path), (long)(n - 2 + 1));
  tally_t t;
  read_back(path, &t);
  ck_assert_uint_eq(t.data, n - 2 + 1);
  ck_assert_uint_ge(t.position, n / 25 - 1);
  ck_assert_uint_ge(t.foreign, n / 30 - 1);
  /* timestamps: 5 and 6 missing, 11 before 10, 20 twice */
  uint32_t prev = 0;
  int backwards = 0, repeats = 0;
  for (uint32_t i = 0; i < t.data && i < 4096; i++) {
    if (i > 0 && t.ts_order[i] < prev) backwards++;
    if (i > 0 && t.ts_order[i] == prev) repeats++;
    prev = t.ts_order[i];
  }
  ck_assert_int_eq(backwards, 1);
  ck_assert_int_eq(repeats, 1);
}
END_TEST

int main(void) {
  Suite *s = suite_create("synth");
  TCase *tc = tcase_create("core");
  tcase_add_test(tc, t_counts_and_ranges);
  tcase_add_test(tc, t_faults);
  suite_add_tcase(s, tc);
  return tu_run(s);
}

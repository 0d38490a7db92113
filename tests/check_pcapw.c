/* check_pcapw - captures written with libpcap's dump API read back with the
 * project's reader and parser: every link type, the VLAN tag, addresses,
 * ports, timestamps, payload bytes, raw frames, and a path that cannot be
 * written. */
#include "roadscan/capture/capture.h"
#include "roadscan/util/error.h"
#include "roadscan/capture/net.h"
#include "roadscan/offline/pcapw.h"
#include "testutil.h"

#include <math.h>
#include <string.h>

START_TEST(t_round_trip_every_linktype) {
  static const int links[] = {RS_LINK_ETHERNET, RS_LINK_SLL, RS_LINK_RAW, RS_LINK_NULL};
  for (size_t li = 0; li < sizeof links / sizeof links[0]; li++) {
    for (int vlan = 0; vlan <= (links[li] == RS_LINK_ETHERNET ? 1 : 0); vlan++) {
      const char *path = tu_tmp("pcapw.pcap");
      rs_pcapw_t w;
      ck_assert_int_eq(rs_pcapw_open(&w, path, links[li], vlan ? 42 : 0), RS_OK);
      uint8_t payload[1206];
      for (int k = 0; k < 3; k++) {
        for (size_t i = 0; i < sizeof payload; i++) payload[i] = (uint8_t)(i * 7 + (size_t)k);
        ck_assert_int_eq(rs_pcapw_write(&w, 1700000000.25 + k * 0.001, (uint16_t)(2368 + k), payload, sizeof payload), RS_OK);
      }
      uint8_t junk[5] = {1, 2, 3, 4, 5};
      ck_assert_int_eq(rs_pcapw_write_raw(&w, 1700000001.0, junk, sizeof junk, 60), RS_OK);
      ck_assert_uint_eq(w.written, 4);
      rs_pcapw_close(&w);

      rs_capture_t c;
      rs_capture_cfg_t cfg = {.data_port = 2368, .speed = 0};
      ck_assert_int_eq(rs_capture_open_file(&c, path, &cfg), RS_OK);
      /* (libpcap stores LINKTYPE_RAW and reads it back as this system's DLT_RAW) */
      ck_assert(c.linktype == links[li] || (links[li] == RS_LINK_RAW && c.linktype == RS_LINK_RAW_DLT));
      for (int k = 0; k < 3; k++) {
        rs_frame_in_t f;
        ck_assert_int_eq(rs_capture_next(&c, &f, NULL), 1);
        ck_assert(fabs(f.ts - (1700000000.25 + k * 0.001)) < 2e-6);
        rs_udp_t u;
        ck_assert_int_eq(rs_net_parse(c.linktype, f.data, f.caplen, &u), RS_OK);
        ck_assert_uint_eq(u.len, 1206);
        ck_assert_uint_eq(u.dst_port, 2368 + k);
        ck_assert_uint_eq(u.src_port, 2368);
        ck_assert_uint_eq(u.vlan, vlan ? 42 : 0);
        ck_assert_uint_eq(u.ip_version, 4);
        static const uint8_t src[4] = {192, 168, 1, 201};
        ck_assert_int_eq(memcmp(u.src_addr, src, 4), 0);
        for (size_t i = 0; i < 1206; i++) ck_assert_uint_eq(u.payload[i], (uint8_t)(i * 7 + (size_t)k));
      }
      rs_frame_in_t f;
      ck_assert_int_eq(rs_capture_next(&c, &f, NULL), 1); /* the raw one, as written */
      ck_assert_uint_eq(f.caplen, 5);
      ck_assert_uint_eq(f.wirelen, 60);
      ck_assert_int_eq(memcmp(f.data, junk, 5), 0);
      ck_assert_int_eq(rs_capture_next(&c, &f, NULL), RS_CAPTURE_EOF);
      rs_capture_close(&c);
    }
  }
}
END_TEST

START_TEST(t_unwritable) {
  rs_pcapw_t w;
  ck_assert_int_ne(rs_pcapw_open(&w, "/nonexistent-dir/x.pcap", RS_LINK_ETHERNET, 0), RS_OK);
}
END_TEST

int main(void) {
  Suite *s = suite_create("pcapw");
  TCase *tc = tcase_create("core");
  tcase_add_test(tc, t_round_trip_every_linktype);
  tcase_add_test(tc, t_unwritable);
  suite_add_tcase(s, tc);
  return tu_run(s);
}

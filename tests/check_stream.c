/* check_stream - classification and counting of everything that reaches
 * the packet thread; the detection pre-buffer loses nothing; source filter;
 * calibration that does not fit the detected sensor. */
#include "roadscan/util/error.h"
#include "roadscan/capture/stream.h"
#include "roadscan/sim/synth.h"
#include "testutil.h"

#include <string.h>

static rs_stream_t st;
static uint8_t pkt[1300];
static uint32_t seen_index[64];
static int nseen;

static void collect(void *user, const rs_packet_t *p, uint32_t index, double ts) {
  (void)user;
  (void)p;
  (void)ts;
  if (nseen < 64) seen_index[nseen] = index;
  nseen++;
}

#define ERR(code) st.n.errors[rs_err_index(code)]

START_TEST(t_classification) {
  rs_stream_cfg_t cfg = {0};
  ck_assert_int_eq(rs_stream_init(&st, &cfg), RS_OK);
  nseen = 0;
  tu_empty_packet(pkt, 100, 40, 0x37, 0x22);
  tu_record(pkt, 0, 0, 1000, 1);
  rs_stream_payload(&st, pkt, 512, 8308, 0, collect, NULL);   /* position packet */
  rs_stream_payload(&st, pkt, 1206, 9999, 0, collect, NULL);  /* other port */
  rs_stream_payload(&st, pkt, 1000, 2368, 0, collect, NULL);  /* short */
  rs_stream_payload(&st, pkt, 1248, 2368, 0, collect, NULL);  /* long */
  rs_stream_payload(&st, pkt, 1206, 2368, 0, collect, NULL);  /* index 0, decoded */
  uint8_t junk[1206];
  memset(junk, 0x5A, sizeof junk);
  rs_stream_payload(&st, junk, 1206, 2368, 0, collect, NULL); /* index 1: not Velodyne */
  tu_empty_packet(pkt, 500, 40, 0x37, 0x77);
  rs_stream_payload(&st, pkt, 1206, 2368, 0, collect, NULL);  /* index 2: other product */
  tu_empty_packet(pkt, 900, 40, 0x37, 0x22);
  rs_stream_payload(&st, pkt, 1206, 2368, 0, collect, NULL);  /* index 3, decoded */
  ck_assert_uint_eq(st.n.position_packets, 1);
  ck_assert_uint_eq(st.n.other_packets, 1);
  ck_assert_uint_eq(ERR(RS_E_PKT_SHORT), 1);
  ck_assert_uint_eq(ERR(RS_E_PKT_LONG), 1);
  ck_assert_uint_eq(ERR(RS_E_BLOCK_FLAG), 1);
  ck_assert_uint_eq(ERR(RS_E_PRODUCT_MISMATCH), 1);
  ck_assert_uint_eq(st.n.data_packets, 4);
  ck_assert_uint_eq(st.n.decoded, 2);
  ck_assert_int_eq(nseen, 2);
  ck_assert_int_eq(seen_index[0], 0);
  ck_assert_int_eq(seen_index[1], 3); /* indices count every 1206-byte data payload */
  ck_assert_uint_eq(rs_stream_error_total(&st.n), 4);
  char buf[256];
  FILE *m = fmemopen(buf, sizeof buf, "w");
  rs_stream_print_errors(&st.n, m);
  fclose(m);
  ck_assert_ptr_nonnull(strstr(buf, "block-flag=1"));
  ck_assert_ptr_nonnull(strstr(buf, "payload-short=1"));
}
END_TEST

START_TEST(t_unknown_product) {
  rs_stream_cfg_t cfg = {0};
  rs_stream_init(&st, &cfg);
  nseen = 0;
  tu_empty_packet(pkt, 100, 40, 0x37, 0x99);
  for (int i = 0; i < 5; i++) rs_stream_payload(&st, pkt, 1206, 2368, 0, collect, NULL);
  ck_assert_uint_eq(ERR(RS_E_PRODUCT), 5);
  ck_assert_int_eq(nseen, 0);
  /* forcing the model decodes them */
  cfg.force_model = RS_MODEL_VLP16;
  rs_stream_init(&st, &cfg);
  for (int i = 0; i < 5; i++) rs_stream_payload(&st, pkt, 1206, 2368, 0, collect, NULL);
  ck_assert_uint_eq(st.n.decoded, 5);
}
END_TEST

START_TEST(t_prebuffer_keeps_everything) {
  /* HDL-32E product byte with empty packets: undecided until the spacing
   * tells (4 packets); all of them come out, in order */
  rs_stream_cfg_t cfg = {0};
  rs_stream_init(&st, &cfg);
  nseen = 0;
  for (int i = 0; i < 10; i++) {
    tu_empty_packet(pkt, (uint16_t)(i * 960), 80, 0x37, 0x21);
    tu_tail(pkt, 1000u + (uint32_t)i * 1327u, 0x37, 0x21);
    rs_stream_payload(&st, pkt, 1206, 2368, 0, collect, NULL);
    if (i == 1) ck_assert_int_eq(nseen, 0);
  }
  ck_assert(st.sensor_ready);
  ck_assert_int_eq(st.sensor.info->model, RS_MODEL_VLP16);
  ck_assert_int_eq(nseen, 10);
  for (int i = 0; i < 10; i++) ck_assert_int_eq(seen_index[i], i);
  /* end of input while undecided: decided with what was seen, then drained */
  rs_stream_init(&st, &cfg);
  nseen = 0;
  tu_empty_packet(pkt, 0, 20, 0x37, 0x21);
  rs_stream_payload(&st, pkt, 1206, 2368, 0, collect, NULL);
  ck_assert_int_eq(nseen, 0);
  rs_stream_finish(&st, collect, NULL);
  ck_assert_int_eq(nseen, 1);
  ck_assert_int_eq(st.sensor.info->model, RS_MODEL_HDL32E);
}
END_TEST

START_TEST(t_source_filter_and_calib) {
  rs_synth_cfg_t sc = {.model = RS_MODEL_VLP32C, .mode = RS_MODE_STRONGEST, .hz = 10, .seconds = 0.05};
  const char *p = tu_tmp("src.pcap");
  long written = rs_synth_write(&sc, p);
  static const struct { const char *addr; long expect; } cases[] = {{"192.168.1.201", -1}, {"10.1.2.3", 0}};
  for (int i = 0; i < 2; i++) {
    rs_capture_cfg_t cc = {.data_port = 2368};
    rs_capture_t c;
    rs_capture_open_file(&c, p, &cc);
    rs_stream_cfg_t cfg = {.source_addr = cases[i].addr};
    ck_assert_int_eq(rs_stream_init(&st, &cfg), RS_OK);
    rs_frame_in_t f;
    while (rs_capture_next(&c, &f, NULL) == 1) rs_stream_frame(&st, c.linktype, &f, NULL, NULL);
    rs_capture_close(&c);
    long expect = cases[i].expect < 0 ? written : cases[i].expect;
    ck_assert_int_eq((long)st.n.decoded, expect);
    ck_assert_int_eq((long)st.n.other_packets, written - expect);
  }
  rs_stream_cfg_t bad = {.source_addr = "not-an-address"};
  ck_assert_int_eq(rs_stream_init(&st, &bad), RS_E_INVAL);
  ck_assert_ptr_nonnull(strstr(st.err, "not-an-address"));
  /* a 16-laser calibration with a VLP-32C stream stops the stream */
  static rs_calib_t cal;
  memset(&cal, 0, sizeof cal);
  cal.lasers = 16;
  rs_stream_cfg_t wc = {.calib = &cal};
  rs_stream_init(&st, &wc);
  tu_empty_packet(pkt, 0, 20, 0x37, 0x28);
  ck_assert_int_eq(rs_stream_payload(&st, pkt, 1206, 2368, 0, NULL, NULL), RS_E_CALIB);
  ck_assert_ptr_nonnull(strstr(st.err, "16 lasers"));
  ck_assert_int_eq(rs_stream_payload(&st, pkt, 1206, 2368, 0, NULL, NULL), RS_E_CALIB);
}
END_TEST

int main(void) {
  Suite *s = suite_create("stream");
  TCase *tc = tcase_create("core");
  tcase_add_test(tc, t_classification);
  tcase_add_test(tc, t_unknown_product);
  tcase_add_test(tc, t_prebuffer_keeps_everything);
  tcase_add_test(tc, t_source_filter_and_calib);
  suite_add_tcase(s, tc);
  return tu_run(s);
}

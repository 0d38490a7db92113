/* check_pipeline - the two threads end to end on synthetic captures:
 * lossless analysis replay, paced replay, stop requests, bad sources. */
#include "roadscan/util/error.h"
#include "roadscan/daemon/pipeline.h"
#include "roadscan/sim/synth.h"
#include "testutil.h"

#include <pcap/pcap.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

static rs_slot_t slots[4];
static rs_pipeline_t pl;

static const uint32_t drops[] = {120, 121};
static const uint32_t swaps[] = {300};
static const uint32_t dups[] = {400};

START_TEST(t_lossless_replay) {
  rs_synth_cfg_t sc = {.model = RS_MODEL_VLP16, .mode = RS_MODE_STRONGEST, .hz = 10, .seconds = 1.0,
                       .start_az_deg = 300, .t0 = 1700000000.0, .position_every = 20, .foreign_every = 100,
                       .drop = drops, .ndrop = 2, .swap = swaps, .nswap = 1, .dup = dups, .ndup = 1};
  const char *p = tu_tmp("pl.pcap");
  long written = rs_synth_write(&sc, p);
  const char *csv = tu_tmp("pl.csv");
  FILE *f = fopen(csv, "w");
  fprintf(f, "%s\n", rs_pipeline_csv_header());
  rs_pipeline_cfg_t cfg = {.pcap_path = p, .capture = {.data_port = 2368, .speed = 0.0}, .lossless = true,
                           .assembly = {.default_hz = 10.0}, .frames_out = f};
  ck_assert_int_eq(rs_pipeline_init(&pl, &cfg, slots, 4), RS_OK);
  ck_assert_int_eq(rs_pipeline_start(&pl), RS_OK);
  rs_pipeline_join(&pl);
  fclose(f);
  ck_assert_int_eq(pl.input_status, RS_OK);
  ck_assert_uint_eq(pl.proc.n.frames, 11);
  ck_assert_uint_eq(pl.proc.n.partial_frames, 2);
  ck_assert_uint_eq(rs_ring_dropped(&pl.ring), 0);
  ck_assert_uint_eq(pl.stream.n.decoded, (uint64_t)written);
  ck_assert_uint_eq(pl.stream.n.errors[rs_err_index(RS_E_BLOCK_FLAG)], 8); /* the foreign datagrams */
  ck_assert_uint_eq(pl.stream.n.position_packets, 38);
  ck_assert_uint_eq(pl.assembly.missing_packets, 2);
  ck_assert_uint_eq(pl.assembly.out_of_order, 1);
  ck_assert_uint_eq(pl.assembly.duplicates, 1);
  ck_assert_int_eq(tu_count_lines(csv), 12);
  ck_assert_uint_eq(pl.t_packet.n, (uint64_t)written);
  ck_assert_uint_eq(pl.t_frame.n, 11);
  char buf[4096];
  FILE *m = fmemopen(buf, sizeof buf, "w");
  rs_pipeline_summary(&pl, m);
  fclose(m);
  ck_assert_ptr_nonnull(strstr(buf, "11 processed (2 partial), 0 dropped"));
  ck_assert_ptr_nonnull(strstr(buf, "block-flag=8"));
  rs_pipeline_deinit(&pl);
}
END_TEST

START_TEST(t_paced_replay_and_stop) {
  rs_synth_cfg_t sc = {.model = RS_MODEL_VLP32C, .mode = RS_MODE_DUAL, .hz = 10, .seconds = 0.5, .t0 = 10};
  const char *p = tu_tmp("paced.pcap");
  rs_synth_write(&sc, p);
  rs_pipeline_cfg_t cfg = {.pcap_path = p, .capture = {.data_port = 2368, .speed = 5.0},
                           .assembly = {.default_hz = 10.0}};
  ck_assert_int_eq(rs_pipeline_init(&pl, &cfg, slots, 4), RS_OK);
  int64_t t0 = rs_now_ns();
  rs_pipeline_start(&pl);
  rs_pipeline_join(&pl);
  double el = (double)(rs_now_ns() - t0) * 1e-9;
  ck_assert_double_ge(el, 0.5 / 5.0 * 0.95); /* lower bound only */
  ck_assert_uint_eq(pl.proc.n.frames + rs_ring_dropped(&pl.ring), 5);
  rs_pipeline_deinit(&pl);

  /* looping at real time never ends by itself: a stop request ends it */
  cfg.capture.speed = 1.0;
  cfg.capture.loop = true;
  ck_assert_int_eq(rs_pipeline_init(&pl, &cfg, slots, 4), RS_OK);
  rs_pipeline_start(&pl);
  /* wait for a condition, not for time: two frames processed (60 s at most: a loaded machine) */
  for (int i = 0; i < 6000 && atomic_load(&pl.frames_done) < 2; i++) usleep(10000);
  rs_pipeline_request_stop(&pl);
  rs_pipeline_join(&pl);
  ck_assert_uint_ge(pl.proc.n.frames, 2);
  ck_assert_int_eq(pl.input_status, RS_OK);
  rs_pipeline_deinit(&pl);
}
END_TEST

/* copies a capture, record `which` moved `by` seconds in time */
static void shift_record(const char *in, const char *out, int which, double by) {
  char e[PCAP_ERRBUF_SIZE];
  pcap_t *r = pcap_open_offline(in, e);
  ck_assert_ptr_nonnull(r);
  pcap_dumper_t *d = pcap_dump_open(r, out);
  ck_assert_ptr_nonnull(d);
  struct pcap_pkthdr *h;
  const u_char *data;
  for (int k = 0; pcap_next_ex(r, &h, &data) == 1; k++) {
    struct pcap_pkthdr h2 = *h;
    if (k == which) h2.ts.tv_sec += (time_t)by;
    pcap_dump((u_char *)d, &h2, data);
  }
  pcap_dump_close(d);
  pcap_close(r);
}

/* One record 10^6 s late does not stop a paced replay: the jump (and the
 * one back) is sent without waiting, counted and reported; every frame
 * is still processed. */
START_TEST(t_paced_replay_clock_jump) {
  rs_synth_cfg_t sc = {.model = RS_MODEL_VLP16, .mode = RS_MODE_STRONGEST, .hz = 10, .seconds = 0.6, .t0 = 1e9};
  const char *clean = tu_tmp("jump-clean.pcap");
  rs_synth_write(&sc, clean);
  char late[600];
  snprintf(late, sizeof late, "%s", tu_tmp("jump-late.pcap"));
  shift_record(clean, late, 200, 1e6);
  /* the clean capture, flat out: how many frames there are */
  rs_pipeline_cfg_t c0 = {.pcap_path = clean, .lossless = true, .capture = {.data_port = 2368},
                          .assembly = {.default_hz = 10.0}};
  ck_assert_int_eq(rs_pipeline_init(&pl, &c0, slots, 4), RS_OK);
  rs_pipeline_start(&pl);
  rs_pipeline_join(&pl);
  const uint64_t frames = pl.proc.n.frames;
  rs_pipeline_deinit(&pl);
  ck_assert_uint_ge(frames, 6);
  rs_pipeline_cfg_t cfg = {.pcap_path = late, .capture = {.data_port = 2368, .speed = 2.0},
                           .assembly = {.default_hz = 10.0}};
  ck_assert_int_eq(rs_pipeline_init(&pl, &cfg, slots, 4), RS_OK);
  rs_pipeline_start(&pl);
  /* without the cap this would wait 5 days: a generous 120 s bound instead */
  for (int i = 0; i < 12000 && !atomic_load(&pl.input_done); i++) usleep(10000);
  const bool done = atomic_load(&pl.input_done);
  if (!done) rs_pipeline_request_stop(&pl);
  rs_pipeline_join(&pl);
  ck_assert_msg(done, "the replay waited for the jump");
  ck_assert_uint_eq(pl.cap.jumps, 2);
  ck_assert_double_eq_tol(pl.cap.jump_max, 1e6, 1.0);
  ck_assert_uint_eq(pl.proc.n.frames + rs_ring_dropped(&pl.ring), frames);
  char *buf = NULL;
  size_t len = 0;
  FILE *f = open_memstream(&buf, &len);
  rs_pipeline_summary(&pl, f);
  fclose(f);
  ck_assert_ptr_nonnull(strstr(buf, "replay: 2 jumps in the capture's clock"));
  free(buf);
  rs_pipeline_deinit(&pl);
}
END_TEST

START_TEST(t_bad_sources) {
  rs_pipeline_cfg_t cfg = {.pcap_path = tu_tmp("missing.pcap"), .capture = {.data_port = 2368}};
  ck_assert_int_eq(rs_pipeline_init(&pl, &cfg, slots, 4), RS_E_NOENT);
  ck_assert_ptr_nonnull(strstr(pl.input_err, "missing.pcap"));
  rs_pipeline_cfg_t c2 = {.iface = "roadscan-no-such0", .capture = {.data_port = 2368}};
  int rc = rs_pipeline_init(&pl, &c2, slots, 4);
  ck_assert(rc == RS_E_NODEV || rc == RS_E_PERM);
  rs_pipeline_cfg_t c3 = {.pcap_path = tu_tmp("missing.pcap"), .stream = {.source_addr = "bogus"}};
  ck_assert_int_eq(rs_pipeline_init(&pl, &c3, slots, 4), RS_E_INVAL);
}
END_TEST

int main(void) {
  Suite *s = suite_create("pipeline");
  TCase *tc = tcase_create("core");
  tcase_set_timeout(tc, 120);
  tcase_add_test(tc, t_lossless_replay);
  tcase_add_test(tc, t_paced_replay_and_stop);
  tcase_add_test(tc, t_paced_replay_clock_jump);
  tcase_add_test(tc, t_bad_sources);
  suite_add_tcase(s, tc);
  return tu_run(s);
}

/* check_tools - the programs as a user runs them: options, errors and exit
 * codes, the frames CSV, export to PCD/CSV, signals, the benchmark. */
#include "roadscan/util/error.h"
#include "roadscan/sim/synth.h"
#include "testutil.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

static const char *capture;

static void make_capture(void) {
  rs_synth_cfg_t sc = {.model = RS_MODEL_VLP32C, .mode = RS_MODE_STRONGEST, .hz = 10, .seconds = 0.6,
                       .start_az_deg = 200, .t0 = 1700000000.0, .position_every = 25};
  capture = tu_tmp("tools.pcap");
  ck_assert_int_gt(rs_synth_write(&sc, capture), 0);
}

START_TEST(t_daemon_usage_errors) {
  const char *out;
  char cmd[1024];
  ck_assert_int_eq(tu_exec("./roadscand --help", &out), 0);
  ck_assert_ptr_nonnull(strstr(out, "--frames-out"));
  ck_assert_ptr_nonnull(strstr(out, "--iface"));
  ck_assert_int_eq(tu_exec("./roadscand", &out), 2);
  ck_assert_ptr_nonnull(strstr(out, "exactly one source"));
  ck_assert_int_eq(tu_exec("./roadscand --pcap x.pcap --speed abc", &out), 2);
  ck_assert_ptr_nonnull(strstr(out, "--speed: 'abc' is not a number"));
  ck_assert_int_eq(tu_exec("./roadscand --pcap x.pcap --model HDL-64E", &out), 2);
  ck_assert_ptr_nonnull(strstr(out, "unknown sensor 'HDL-64E'"));
  ck_assert_int_eq(tu_exec("./roadscand --pcap x.pcap --columns 5", &out), 2);
  ck_assert_ptr_nonnull(strstr(out, "--columns: 5 is out of range"));
  ck_assert_int_eq(tu_exec("./roadscand --iface lo --fast", &out), 2);
  snprintf(cmd, sizeof cmd, "./roadscand --pcap %s", tu_tmp("absent.pcap"));
  ck_assert_int_eq(tu_exec(cmd, &out), 1);
  ck_assert_ptr_nonnull(strstr(out, "absent.pcap: No such file"));
  ck_assert_int_eq(tu_exec("./roadscand --iface roadscan-no-such0", &out), 1);
  ck_assert_ptr_nonnull(strstr(out, "roadscan-no-such0"));
  snprintf(cmd, sizeof cmd, "./roadscand --pcap %s --calibration %s", capture, tu_tmp("absent.yaml"));
  ck_assert_int_eq(tu_exec(cmd, &out), 1);
  ck_assert_ptr_nonnull(strstr(out, "absent.yaml"));
}
END_TEST

START_TEST(t_daemon_frames_and_export) {
  const char *out;
  char cmd[2048];
  const char *csv = tu_tmp("tools.csv");
  snprintf(cmd, sizeof cmd, "./roadscand --pcap %s --fast --frames-out %s", capture, csv);
  ck_assert_int_eq(tu_exec(cmd, &out), 0);
  ck_assert_ptr_nonnull(strstr(out, "sensor: VLP-32C"));
  ck_assert_ptr_nonnull(strstr(out, "errors: none"));
  /* 0.6 s from 200 deg at 10 Hz: 6 roll-overs, 7 frames */
  ck_assert_int_eq(tu_count_lines(csv), 8);
  FILE *f = fopen(csv, "r");
  char line[1024];
  ck_assert_ptr_nonnull(fgets(line, sizeof line, f));
  ck_assert_int_eq(strncmp(line, "frame,t_first,t_last,packets,points,columns,missing_packets,dropped_frames", 74), 0);
  unsigned frame3_points = 0, frame3_coll = 0;
  while (fgets(line, sizeof line, f)) {
    unsigned fr, pk, pt, col, miss, drop, ooo, dup, late, shift, coll;
    double t1, t2;
    ck_assert_int_eq(sscanf(line, "%u,%lf,%lf,%u,%u,%u,%u,%u,%u,%u,%u,%u,%u", &fr, &t1, &t2, &pk, &pt, &col, &miss,
                            &drop, &ooo, &dup, &late, &shift, &coll), 13);
    if (fr == 3) {
      frame3_points = pt;
      frame3_coll = coll;
    }
  }
  fclose(f);
  ck_assert_uint_gt(frame3_points, 10000);

  const char *pcd = tu_tmp("f3.pcd");
  snprintf(cmd, sizeof cmd, "./roadscan-export %s --frame 3 -o %s", capture, pcd);
  ck_assert_int_eq(tu_exec(cmd, &out), 0);
  f = fopen(pcd, "r");
  long points = -1;
  int header = 0;
  while (fgets(line, sizeof line, f)) {
    if (strncmp(line, "POINTS ", 7) == 0) points = atol(line + 7);
    if (strncmp(line, "FIELDS x y z intensity ring azimuth distance return_type", 56) == 0) header++;
    if (strncmp(line, "DATA ascii", 10) == 0) break;
  }
  long body = 0;
  float x, y, z;
  while (fgets(line, sizeof line, f)) {
    ck_assert_int_eq(sscanf(line, "%f %f %f", &x, &y, &z), 3);
    body++;
  }
  fclose(f);
  ck_assert_int_eq(header, 1);
  ck_assert_int_eq(points, body);
  /* the same frame as the daemon's: its map points plus the collided ones */
  ck_assert_int_eq(points, (long)(frame3_points + frame3_coll));

  const char *ecsv = tu_tmp("f3.csv");
  snprintf(cmd, sizeof cmd, "./roadscan-export %s --frame 3 --csv -o %s", capture, ecsv);
  ck_assert_int_eq(tu_exec(cmd, &out), 0);
  ck_assert_int_eq(tu_count_lines(ecsv), points + 1);
  snprintf(cmd, sizeof cmd, "./roadscan-export %s --frame 99 -o %s", capture, pcd);
  ck_assert_int_eq(tu_exec(cmd, &out), 1);
  ck_assert_ptr_nonnull(strstr(out, "frame 99 does not exist"));
}
END_TEST

START_TEST(t_truncated_capture) {
  const char *out;
  char cmd[2048];
  const char *t = tu_tmp("tools-trunc.pcap");
  snprintf(cmd, sizeof cmd, "head -c 300000 %s > %s", capture, t);
  ck_assert_int_eq(system(cmd), 0);
  snprintf(cmd, sizeof cmd, "./roadscand --pcap %s --fast", t);
  ck_assert_int_eq(tu_exec(cmd, &out), 0);
  ck_assert_ptr_nonnull(strstr(out, "cut short"));
  ck_assert_ptr_nonnull(strstr(out, "truncated=1"));
  ck_assert_ptr_nonnull(strstr(out, "frames: 3 processed"));
}
END_TEST

START_TEST(t_sigint) {
  const char *out;
  char cmd[2048];
  snprintf(cmd, sizeof cmd,
           "./roadscand --pcap %s --loop & pid=$!; sleep 0.7; kill -INT $pid; wait $pid; echo exit=$?", capture);
  ck_assert_int_eq(tu_exec(cmd, &out), 0);
  ck_assert_ptr_nonnull(strstr(out, "roadscan summary"));
  ck_assert_ptr_nonnull(strstr(out, "exit=0"));
}
END_TEST

START_TEST(t_bench) {
  const char *out;
  ck_assert_int_eq(tu_exec("./roadscan-bench --seconds 0.05", &out), 0);
  static const char *names[] = {"VLP-16", "Puck-Hi-Res", "HDL-32E", "VLP-32C", "VLS-128"};
  for (int i = 0; i < 5; i++) ck_assert_ptr_nonnull(strstr(out, names[i]));
  char cmd[1024];
  snprintf(cmd, sizeof cmd, "./roadscan-bench %s --repeat 1", capture);
  ck_assert_int_eq(tu_exec(cmd, &out), 0);
  ck_assert_ptr_nonnull(strstr(out, "decode/packet"));
}
END_TEST

int main(void) {
  Suite *s = suite_create("tools");
  TCase *tc = tcase_create("programs");
  tcase_set_timeout(tc, 120);
  tcase_add_unchecked_fixture(tc, make_capture, NULL);
  tcase_add_test(tc, t_daemon_usage_errors);
  tcase_add_test(tc, t_daemon_frames_and_export);
  tcase_add_test(tc, t_truncated_capture);
  tcase_add_test(tc, t_sigint);
  tcase_add_test(tc, t_bench);
  suite_add_tcase(s, tc);
  return tu_run(s);
}

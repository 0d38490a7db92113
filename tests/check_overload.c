/* check_overload - the daemon under more frames than it can process, through
 * the real program: its processing thread made three times slower than the
 * frames arrive (--stall-ms, a test hook that sleeps per frame), on a paced
 * replay and on live capture over the loopback; and a daemon that does not
 * run at all for a while (SIGSTOP) while packets arrive, so that the kernel
 * itself drops them. What must hold: capture never waits for processing
 * (live: the kernel drops nothing while the packet thread runs), every frame
 * is either processed or counted as dropped, and the counts are published in
 * the statistics messages (an LCM log written by the daemon's file://
 * provider, read back by roadscan-listen) as in the summary. Nothing here
 * measures time: the tests wait for conditions with generous timeouts. */
#include "roadscan/sim/synth.h"
#include "testutil.h"

#include <arpa/inet.h>
#include <netinet/in.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/socket.h>
#include <time.h>
#include <unistd.h>

static char cap[600];
static long all_frames; /* frames of the capture, from a --fast run (nothing dropped) */

static long num_after(const char *s, const char *key) {
  const char *p = strstr(s, key);
  ck_assert_msg(p != NULL, "'%s' not in: %s", key, s);
  return strtol(p + strlen(key), NULL, 10);
}

/* the last value of "key": in the JSON lines of a file */
static long last_json(const char *text, const char *key) {
  const char *p = NULL, *q = text;
  while ((q = strstr(q, key)) != NULL) p = q++;
  ck_assert_msg(p != NULL, "'%s' not in the statistics", key);
  return strtol(p + strlen(key), NULL, 10);
}

/* 3 s of a VLP-16 at 10 Hz (30 frames) */
static void setup(void) {
  snprintf(cap, sizeof cap, "%s", tu_tmp("overload.pcap"));
  rs_synth_cfg_t cfg = {.model = RS_MODEL_VLP16, .mode = RS_MODE_STRONGEST, .hz = 10.0, .seconds = 3.0, .t0 = 1e9};
  ck_assert_int_gt(rs_synth_write(&cfg, cap), 2000);
  char cmd[1024];
  const char *out;
  snprintf(cmd, sizeof cmd, "./roadscand --pcap %s --fast --no-publish", cap);
  ck_assert_msg(tu_exec(cmd, &out) == 0, "%s", out);
  all_frames = num_after(out, "frames: ");
  ck_assert_int_ge(all_frames, 30);
}

/* the statistics messages of an LCM log, as JSON lines (roadscan-listen --log) */
static const char *stats_of(const char *lcmlog) {
  char cmd[1024];
  const char *json = tu_tmp("overload-stats.json");
  snprintf(cmd, sizeof cmd, "./roadscan-listen --log %s --json --stats >%s 2>/dev/null", lcmlog, json);
  (void)tu_exec(cmd, NULL);
  return tu_slurp_text(json);
}

/* frames of the frames CSV, and the highest frame number: every frame assembled is numbered, so
 * highest + 1 is what was processed plus what was dropped */
static long csv_frames(const char *csv, long *highest) {
  FILE *f = fopen(csv, "r");
  ck_assert_ptr_nonnull(f);
  char line[1024];
  long n = 0;
  *highest = -1;
  ck_assert_ptr_nonnull(fgets(line, sizeof line, f));
  while (fgets(line, sizeof line, f)) {
    const long k = strtol(line, NULL, 10);
    if (k > *highest) *highest = k;
    n++;
  }
  fclose(f);
  return n;
}

/* a paced replay with processing 3x slower than the frames: every frame processed or dropped,
 * drops published, every processed frame over budget, every packet decoded */
START_TEST(t_paced_replay_three_times_slower) {
  setup();
  const char *lcmlog = tu_tmp("overload-paced.lcmlog"), *csv = tu_tmp("overload-paced.csv");
  remove(lcmlog);
  char cmd[2048];
  const char *out;
  snprintf(cmd, sizeof cmd,
           "timeout 120 ./roadscand --pcap %s --speed 1 --stall-ms 300 --summary-seconds 0 --frames-out %s "
           "--lcm-url 'file://%s?mode=w'",
           cap, csv, lcmlog);
  const int rc = tu_exec(cmd, &out);
  ck_assert_msg(rc == 0, "exit %d: %s", rc, out);
  const long processed = num_after(out, "frames: "), dropped = num_after(out, "partial), ");
  ck_assert_int_eq(processed + dropped, all_frames);
  ck_assert_int_gt(dropped, 0);
  long highest;
  ck_assert_int_eq(csv_frames(csv, &highest), processed);
  ck_assert_int_eq(highest + 1, all_frames);
  ck_assert_int_eq(num_after(out, "deadline: "), processed); /* 300 ms > the 100 ms period, every time */
  /* capture read on: every data packet decoded */
  ck_assert_int_eq(num_after(out, "data ("), num_after(out, "captured, "));
  const char *stats = stats_of(lcmlog);
  ck_assert_int_eq(last_json(stats, "\"frames_processed\":"), processed);
  ck_assert_int_eq(last_json(stats, "\"frames_dropped\":"), dropped);
  ck_assert_int_eq(last_json(stats, "\"deadline_overruns\":"), processed);
  ck_assert_int_eq(last_json(stats, "\"capture_buffer_kib\":"), 0); /* a replay */
}
END_TEST

static int start_live(const char *extra, uint16_t port, const char *log, const char *lcmlog, const char *csv) {
  char cmd[2048];
  snprintf(cmd, sizeof cmd,
           "./roadscand --iface lo --port %u --summary-seconds 0 --frames-out %s --lcm-url 'file://%s?mode=w' %s", port,
           csv, lcmlog, extra);
  remove(log);
  remove(lcmlog);
  remove(csv);
  const int pid = tu_spawn(cmd, log);
  if (tu_wait_for(log, "capturing on lo", 60)) return pid;
  const int rc = tu_stop(pid, SIGINT, 60);
  const char *text = tu_slurp_text(log);
  if (strstr(text, "permission denied")) {
    fprintf(stderr, "check_overload: live capture needs CAP_NET_RAW here; live case skipped\n");
    return -1;
  }
  ck_abort_msg("the daemon did not start capturing (exit %d): %s", rc, text);
  return -1;
}

/* live, paced at the sensor's rate, processing 3x slower, a 4 MiB kernel buffer (about 1 s of the
 * loopback's packets, each taken twice there: see below): if the packet thread waited for
 * processing it would fall 2 s behind in 3 s and the kernel would drop; it must drop nothing,
 * decode every packet and count every dropped frame */
START_TEST(t_live_three_times_slower) {
  setup();
  const char *log = tu_tmp("overload-live.log"), *lcmlog = tu_tmp("overload-live.lcmlog"),
             *csv = tu_tmp("overload-live.csv");
  const uint16_t port = (uint16_t)(25000 + getpid() % 1000);
  const int pid = start_live("--stall-ms 300 --capture-buffer-kib 4096", port, log, lcmlog, csv);
  if (pid < 0) return;
  const long sent = tu_send_capture(cap, port, 1.0);
  ck_assert_int_gt(sent, 2000);
  const long tail = tu_settle_live(port, csv);
  const int rc = tu_stop(pid, SIGINT, 60);
  const char *out = tu_slurp_text(log);
  ck_assert_msg(rc == 0, "exit %d: %s", rc, out);
  ck_assert_msg(strstr(out, "0 dropped by the kernel (buffer of 4096 KiB full), 0 by the interface") != NULL, "%s", out);
  const long decoded = num_after(out, "data (");
  ck_assert_msg(decoded >= sent && decoded <= sent + tail, "%ld decoded, %ld + %ld sent", decoded, sent, tail);
  const long processed = num_after(out, "frames: "), dropped = num_after(out, "partial), ");
  ck_assert_int_gt(dropped, 0);
  long highest;
  ck_assert_int_eq(csv_frames(csv, &highest), processed);
  ck_assert_int_eq(highest + 1, processed + dropped);
  const char *stats = stats_of(lcmlog);
  ck_assert_int_eq(last_json(stats, "\"kernel_dropped\":"), 0);
  ck_assert_int_eq(last_json(stats, "\"capture_buffer_kib\":"), 4096);
  ck_assert_int_eq(last_json(stats, "\"frames_processed\":"), processed);
  ck_assert_int_eq(last_json(stats, "\"frames_dropped\":"), dropped);
}
END_TEST

/* the daemon stopped (SIGSTOP) while 3 s of packets arrive with a 64 KiB kernel buffer: the kernel
 * drops, pcap_stats says how many, the summary and the statistics carry it, and every packet sent
 * was either read or counted as dropped. (On the loopback the kernel sees every datagram twice,
 * going out and coming in, and libpcap discards the outgoing copy after the ring: its counters
 * count both copies, so the drops of the loopback are an upper bound, never exact.) */
START_TEST(t_kernel_drops_are_counted) {
  setup();
  const char *log = tu_tmp("overload-kernel.log"), *lcmlog = tu_tmp("overload-kernel.lcmlog"),
             *csv = tu_tmp("overload-kernel.csv");
  const uint16_t port = (uint16_t)(26000 + getpid() % 1000);
  const int pid = start_live("--capture-buffer-kib 64", port, log, lcmlog, csv);
  if (pid < 0) return;
  ck_assert_int_eq(kill(pid, SIGSTOP), 0);
  const long sent = tu_send_capture(cap, port, 0.0);
  ck_assert_int_eq(kill(pid, SIGCONT), 0);
  const long tail = tu_settle_live(port, csv);
  const int rc = tu_stop(pid, SIGINT, 60);
  const char *out = tu_slurp_text(log);
  ck_assert_msg(rc == 0, "exit %d: %s", rc, out);
  const long passed = num_after(out, "kernel: "), kdrop = num_after(out, "packets passed the filter, ");
  const long data = num_after(out, "captured, ");
  ck_assert_msg(kdrop > 0 && data < sent, "%s", out);
  ck_assert_msg(passed >= sent + tail, "%s", out);
  ck_assert_msg(data + kdrop >= sent, "%ld read + %ld dropped by the kernel, %ld sent while stopped: %s", data, kdrop,
                sent, out);
  ck_assert_int_eq(last_json(stats_of(lcmlog), "\"kernel_dropped\":"), kdrop);
}
END_TEST

int main(void) {
  Suite *s = suite_create("overload");
  TCase *tc = tcase_create("daemon");
  tcase_set_timeout(tc, 600);
  tcase_add_test(tc, t_paced_replay_three_times_slower);
  tcase_add_test(tc, t_live_three_times_slower);
  tcase_add_test(tc, t_kernel_drops_are_counted);
  suite_add_tcase(s, tc);
  return tu_run(s);
}

/* check_faults - broken input through the real programs: a capture cut at
 * many offsets, 100 variants with 2 % of the packets' bytes corrupted,
 * record timestamps thrown hours away or running backwards under a paced
 * replay, the sensor's clock wrapping at the hour, a sensor switched
 * mid-stream and two on one port, a model for the wrong sensor through every
 * tool that takes one, every allocation of the daemon's start-up failing in
 * turn, and garbage and oversized datagrams on the live port. Nothing may
 * crash or hang (a generous timeout, not a measured time), only corrupt
 * packets may lose their returns, and what was lost is counted. */
#include "roadscan/capture/stream.h"
#include "roadscan/util/error.h"
#include "roadscan/sim/synth.h"
#include "testutil.h"

#include <arpa/inet.h>
#include <netinet/in.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/socket.h>
#include <unistd.h>

static uint8_t *clean;
static long clean_len;
static long clean_points, clean_frames;
static char cap[600];

static uint8_t *slurp(const char *path, long *len) {
  FILE *f = fopen(path, "rb");
  ck_assert_ptr_nonnull(f);
  fseek(f, 0, SEEK_END);
  *len = ftell(f);
  rewind(f);
  uint8_t *b = malloc((size_t)*len);
  ck_assert_uint_eq(fread(b, 1, (size_t)*len, f), (size_t)*len);
  fclose(f);
  return b;
}

static void spill(const char *path, const uint8_t *b, long len) {
  FILE *f = fopen(path, "wb");
  ck_assert_ptr_nonnull(f);
  ck_assert_uint_eq(fwrite(b, 1, (size_t)len, f), (size_t)len);
  fclose(f);
}

/* frames and points roadscand counted (its --frames-out), and its exit status */
static int run_daemon(const char *path, const char *extra, long *frames, long *points, const char **out) {
  char csv[600], cmd[2048];
  snprintf(csv, sizeof csv, "%s.frames.csv", path);
  remove(csv);
  snprintf(cmd, sizeof cmd, "timeout 120 ./roadscand --pcap %s --no-publish --frames-out %s %s", path, csv, extra);
  int rc = tu_exec(cmd, out);
  *frames = *points = 0;
  FILE *f = fopen(csv, "r");
  if (f == NULL) return rc;
  char line[1024];
  if (fgets(line, sizeof line, f)) {
    while (fgets(line, sizeof line, f)) {
      /* frame,t_first,t_last,packets,points,... */
      char *p = line;
      for (int k = 0; k < 4 && p; k++) p = strchr(p, ',') ? strchr(p, ',') + 1 : NULL;
      if (p) *points += strtol(p, NULL, 10);
      (*frames)++;
    }
  }
  fclose(f);
  return rc;
}

static void setup(void) {
  snprintf(cap, sizeof cap, "%s", tu_tmp("faults-clean.pcap"));
  rs_synth_cfg_t cfg = {.model = RS_MODEL_VLP16, .mode = RS_MODE_STRONGEST, .hz = 10.0, .seconds = 1.0, .t0 = 1e9,
                        .position_every = 50};
  ck_assert_int_gt(rs_synth_write(&cfg, cap), 0);
  clean = slurp(cap, &clean_len);
  const char *out;
  ck_assert_int_eq(run_daemon(cap, "--fast --quiet", &clean_frames, &clean_points, &out), 0);
  ck_assert_int_ge(clean_frames, 10);
}

/* the records of a classic pcap: offsets of their data and lengths */
static int records(const uint8_t *b, long len, long *at, long *n, int max) {
  int k = 0;
  for (long i = 24; i + 16 <= len && k < max;) {
    const long incl = (long)b[i + 8] | (long)b[i + 9] << 8 | (long)b[i + 10] << 16 | (long)b[i + 11] << 24;
    at[k] = i + 16;
    n[k++] = incl;
    i += 16 + incl;
  }
  return k;
}

START_TEST(t_cut_at_many_offsets) {
  setup();
  const char *path = tu_tmp("faults-cut.pcap");
  int truncated = 0;
  for (int k = 1; k <= 40; k++) {
    const long cut = 24 + (clean_len - 24) * k / 41 + (k * 37) % 900; /* inside headers and payloads alike */
    spill(path, clean, cut < clean_len ? cut : clean_len - 1);
    long frames, points;
    const char *out;
    const int rc = run_daemon(path, "--fast", &frames, &points, &out);
    ck_assert_msg(rc == 0, "cut at %ld: exit %d: %s", cut, rc, out); /* a truncated file ends the input, not the run */
    ck_assert_int_le(points, clean_points);
    ck_assert_int_le(frames, clean_frames);
    truncated += strstr(out, "cut short") != NULL;
  }
  ck_assert_int_ge(truncated, 30); /* most cuts fall inside a record, and say so */
}
END_TEST

static uint64_t next(uint64_t *rng) {
  *rng ^= *rng << 13;
  *rng ^= *rng >> 7;
  *rng ^= *rng << 17;
  return *rng;
}

/* 100 variants: in 50, 2 % of the packets' bytes corrupt (nearly every packet hit: the run must end
 * and account for what it saw); in 50, 2 % of the packets with 3 bytes each corrupt (only those may
 * lose their returns, each may add or remove a frame boundary at most) */
START_TEST(t_corrupt_bytes) {
  setup();
  static long at[4096], len[4096];
  const int nrec = records(clean, clean_len, at, len, 4096);
  ck_assert_int_gt(nrec, 700);
  const char *path = tu_tmp("faults-corrupt.pcap");
  uint8_t *b = malloc((size_t)clean_len);
  uint64_t rng = 0x2545f4914f6cdd1dull;
  long worst_loss = 0, total = 0;
  for (int r = 0; r < nrec; r++) total += len[r];
  for (int v = 0; v < 100; v++) {
    memcpy(b, clean, (size_t)clean_len); /* the pcap record headers stay: libpcap cannot resync past a broken one */
    static bool hit[4096];
    memset(hit, 0, sizeof hit);
    int hit_packets = 0;
    const bool by_bytes = v < 50;
    const long flips = by_bytes ? total / 50 : 3L * (nrec / 50);
    for (long k = 0; k < flips; k++) {
      const int r = by_bytes ? (int)(next(&rng) % (uint64_t)nrec) : (int)((k / 3) * 50 + 7) % nrec;
      if (len[r] == 0) continue;
      b[at[r] + (long)(next(&rng) % (uint64_t)len[r])] ^= (uint8_t)(1 + next(&rng) % 255);
      if (!hit[r]) hit_packets++;
      hit[r] = true;
    }
    spill(path, b, clean_len);
    long frames, points;
    const char *out;
    const int rc = run_daemon(path, "--fast", &frames, &points, &out);
    ck_assert_msg(rc == 0, "variant %d: exit %d: %s", v, rc, out);
    ck_assert_ptr_nonnull(strstr(out, "roadscan summary")); /* it ended and said what it saw */
    if (by_bytes) continue;
    /* a corrupt packet may lose its returns (384 at most) or keep them with other values */
    const long loss = clean_points - points;
    ck_assert_msg(loss <= 384L * hit_packets, "variant %d: %ld returns lost, %d packets corrupt", v, loss, hit_packets);
    ck_assert_msg(labs(frames - clean_frames) <= hit_packets, "variant %d: %ld frames, %ld clean", v, frames,
                  clean_frames);
    if (loss > worst_loss) worst_loss = loss;
  }
  free(b);
  printf("check_faults: 2 %% of the packets corrupt: at most %ld returns lost (of %ld)\n", worst_loss, clean_points);
}
END_TEST

/* record timestamps thrown hours away (a corrupt header, a clock reset) under a paced replay at --speed 8 */
START_TEST(t_paced_replay_of_a_broken_clock) {
  setup();
  static long at[4096], len[4096];
  const int nrec = records(clean, clean_len, at, len, 4096);
  uint8_t *b = malloc((size_t)clean_len);
  memcpy(b, clean, (size_t)clean_len);
  for (int r = 100; r < nrec; r += 150) { /* tv_sec of a few records: hours ahead or behind */
    uint8_t *ts = b + at[r] - 16;
    const uint32_t sec = (uint32_t)ts[0] | (uint32_t)ts[1] << 8 | (uint32_t)ts[2] << 16 | (uint32_t)ts[3] << 24;
    const uint32_t moved = (r / 150) % 2 ? sec + 36000u : sec - 36000u;
    ts[0] = (uint8_t)moved;
    ts[1] = (uint8_t)(moved >> 8);
    ts[2] = (uint8_t)(moved >> 16);
    ts[3] = (uint8_t)(moved >> 24);
  }
  const char *path = tu_tmp("faults-clock.pcap");
  spill(path, b, clean_len);
  free(b);
  long frames, points;
  const char *out;
  const int rc = run_daemon(path, "--speed 8", &frames, &points, &out);
  ck_assert_msg(rc == 0, "exit %d (124: it hung): %s", rc, out);
  ck_assert_ptr_nonnull(strstr(out, "jumps in the capture's clock"));
  ck_assert_int_gt(frames, 0); /* (paced: how many frames a loaded machine drops is not asserted) */
}
END_TEST

/* roadscan-export frames the points as the daemon does: a packet repeated 10 packets later and one
 * delivered half a turn late change nothing in its output (both are left out, as the assembler
 * leaves them out), where a roll-over rule of its own wrote their points again */
START_TEST(t_export_frames_as_the_daemon) {
  setup();
  static long at[4096], n[4096];
  const int k = records(clean, clean_len, at, n, 4096);
  ck_assert_int_gt(k, 200);
  const char *path = tu_tmp("faults-export.pcap");
  FILE *f = fopen(path, "wb");
  ck_assert_ptr_nonnull(f);
  fwrite(clean, 1, 24, f);
  int data = 0, dup = -1, late = -1, extra = 0;
  for (int i = 0; i < k; i++) {
    fwrite(clean + at[i] - 16, 1, (size_t)(16 + n[i]), f);
    if (n[i] != 1248) continue; /* data packets only (42 + 1206 bytes) */
    data++;
    if (data == 20) dup = i;
    if (data == 60) late = i;
    if (data == 30 || data == 98) { /* the packet of data 20, ten later; that of data 60, 38 later */
      const int j = data == 30 ? dup : late;
      fwrite(clean + at[j] - 16, 1, (size_t)(16 + n[j]), f);
      extra++;
    }
  }
  fclose(f);
  ck_assert_int_eq(extra, 2);
  char cmd[2048];
  const char *out;
  char clean_csv[600], bad_csv[600];
  snprintf(clean_csv, sizeof clean_csv, "%s", tu_tmp("faults-export-clean.csv"));
  snprintf(bad_csv, sizeof bad_csv, "%s", tu_tmp("faults-export-bad.csv"));
  snprintf(cmd, sizeof cmd, "./roadscan-export %s --frame all --csv -o %s", cap, clean_csv);
  ck_assert_int_eq(tu_exec(cmd, &out), 0);
  snprintf(cmd, sizeof cmd, "./roadscan-export %s --frame all --csv -o %s", path, bad_csv);
  ck_assert_int_eq(tu_exec(cmd, &out), 0);
  long a_len, b_len;
  uint8_t *a = slurp(clean_csv, &a_len), *b = slurp(bad_csv, &b_len);
  ck_assert_int_eq(a_len, b_len);
  ck_assert(memcmp(a, b, (size_t)a_len) == 0);
  free(a);
  free(b);
  /* and the daemon took the same frames */
  long frames, points;
  ck_assert_int_eq(run_daemon(path, "--fast --quiet", &frames, &points, &out), 0);
  ck_assert_int_eq(frames, clean_frames);
  ck_assert_int_eq(points, clean_points);
}
END_TEST

static void put32(uint8_t *p, uint32_t v) {
  p[0] = (uint8_t)v;
  p[1] = (uint8_t)(v >> 8);
  p[2] = (uint8_t)(v >> 16);
  p[3] = (uint8_t)(v >> 24);
}

static uint32_t get32(const uint8_t *p) {
  return (uint32_t)p[0] | (uint32_t)p[1] << 8 | (uint32_t)p[2] << 16 | (uint32_t)p[3] << 24;
}

/* a record's capture time in ns (the synthesiser writes nanosecond pcap) */
static int64_t rec_ns(const uint8_t *rec) { return (int64_t)get32(rec) * 1000000000LL + get32(rec + 4); }

/* the records of a and b merged by capture time into out (classic pcap, one header) */
static void merge_pcaps(const char *a_path, const char *b_path, const char *out) {
  long alen, blen;
  uint8_t *a = slurp(a_path, &alen), *b = slurp(b_path, &blen);
  static long aat[8192], an[8192], bat[8192], bn[8192];
  const int na = records(a, alen, aat, an, 8192), nb = records(b, blen, bat, bn, 8192);
  FILE *f = fopen(out, "wb");
  ck_assert_ptr_nonnull(f);
  fwrite(a, 1, 24, f);
  for (int i = 0, j = 0; i < na || j < nb;) {
    const bool take_a = j == nb || (i < na && rec_ns(a + aat[i] - 16) <= rec_ns(b + bat[j] - 16));
    if (take_a) fwrite(a + aat[i] - 16, 1, (size_t)(16 + an[i]), f), i++;
    else fwrite(b + bat[j] - 16, 1, (size_t)(16 + bn[j]), f), j++;
  }
  fclose(f);
  free(a);
  free(b);
}

static long num_after(const char *s, const char *key) {
  const char *p = strstr(s, key);
  ck_assert_msg(p != NULL, "'%s' not in: %s", key, s);
  return strtol(p + strlen(key), NULL, 10);
}

/* The frames a paced or live run processed have the clean capture's returns, frame by frame, and
 * with those it dropped (frames that came faster than processing: the ring drops and counts them)
 * they are all of the clean capture's frames. With more (a live run's tail, tu_settle_live), the
 * frames after the clean capture's are not compared. */
static void same_frames_as_clean(const char *csv, const char *out, bool more) {
  static long clean_pts[4096];
  char clean_csv[700];
  snprintf(clean_csv, sizeof clean_csv, "%s.frames.csv", cap);
  long highest = -1, processed = 0;
  for (int pass = 0; pass < 2; pass++) {
    FILE *f = fopen(pass == 0 ? clean_csv : csv, "r");
    ck_assert_ptr_nonnull(f);
    char line[1024];
    ck_assert_ptr_nonnull(fgets(line, sizeof line, f));
    while (fgets(line, sizeof line, f)) {
      const long k = strtol(line, NULL, 10);
      char *p = line;
      for (int j = 0; j < 4 && p; j++) p = strchr(p, ',') ? strchr(p, ',') + 1 : NULL;
      ck_assert(p != NULL && k >= 0 && k < 4096);
      const long pts = strtol(p, NULL, 10);
      if (pass == 0) {
        clean_pts[k] = pts;
        continue;
      }
      if (k > highest) highest = k;
      if (k >= clean_frames - (more ? 1 : 0)) continue; /* the tail's, and the last clean frame: the tail goes on in it */
      ck_assert_msg(pts == clean_pts[k], "frame %ld: %ld returns, clean %ld", k, pts, clean_pts[k]);
      processed++;
    }
    fclose(f);
  }
  if (more) {
    ck_assert_int_ge(processed, 1);
    ck_assert_int_ge(highest + 1, clean_frames);
    return;
  }
  ck_assert_int_eq(highest + 1, clean_frames);
  ck_assert_int_eq(processed + num_after(out, "partial), "), clean_frames);
}

/* A VLP-16 replaced by a VLP-32C mid-stream: the run stops with a message naming both (the map,
 * calibration and background were the old sensor's; systemd's restart identifies the new one),
 * after everything the VLP-16 sent was processed as in the clean capture */
START_TEST(t_sensor_switched_mid_stream) {
  setup();
  const char *v32 = tu_tmp("faults-v32-after.pcap"), *path = tu_tmp("faults-switch.pcap");
  rs_synth_cfg_t cfg = {.model = RS_MODEL_VLP32C, .mode = RS_MODE_STRONGEST, .hz = 10.0, .seconds = 1.0, .t0 = 1e9 + 1.05};
  ck_assert_int_gt(rs_synth_write(&cfg, v32), 500);
  merge_pcaps(cap, v32, path);
  long frames, points;
  const char *out;
  const int rc = run_daemon(path, "--fast", &frames, &points, &out);
  ck_assert_msg(rc == 1, "exit %d: %s", rc, out);
  ck_assert_msg(strstr(out, "the sensor changed mid-stream") && strstr(out, "from a VLP-32C (product byte 0x28)") &&
                    strstr(out, "none from the VLP-16"),
                "%s", out);
  ck_assert_ptr_nonnull(strstr(out, "sensor-changed=1"));
  ck_assert_int_eq(num_after(out, "product-mismatch="), RS_STREAM_SWITCH_PACKETS);
  ck_assert_int_eq(frames, clean_frames);
  ck_assert_int_eq(points, clean_points);
}
END_TEST

/* A VLP-32C sending to the same port as the VLP-16 (from 0.25 s on): its packets are counted and
 * dropped, the VLP-16's frames are the clean capture's, the run goes on to the end */
START_TEST(t_two_sensors_on_one_port) {
  setup();
  const char *v32 = tu_tmp("faults-v32-beside.pcap"), *path = tu_tmp("faults-two.pcap");
  rs_synth_cfg_t cfg = {.model = RS_MODEL_VLP32C, .mode = RS_MODE_STRONGEST, .hz = 10.0, .seconds = 0.7, .t0 = 1e9 + 0.25};
  const long n32 = rs_synth_write(&cfg, v32);
  ck_assert_int_gt(n32, RS_STREAM_SWITCH_PACKETS);
  merge_pcaps(cap, v32, path);
  long frames, points;
  const char *out;
  const int rc = run_daemon(path, "--fast", &frames, &points, &out);
  ck_assert_msg(rc == 0, "exit %d: %s", rc, out);
  ck_assert_int_eq(num_after(out, "product-mismatch="), n32);
  ck_assert_ptr_null(strstr(out, "sensor-changed"));
  ck_assert_int_eq(frames, clean_frames);
  ck_assert_int_eq(points, clean_points);
}
END_TEST

/* The sensor's clock (microseconds past the hour) wraps inside the capture, and a capture whose
 * record clock runs backwards, replayed at --speed 4: the same frames and returns as the clean one */
START_TEST(t_clock_wraps_at_the_hour_and_runs_backwards) {
  setup();
  const char *wrap = tu_tmp("faults-hour.pcap");
  const double hour = 3600.0 * 277778.0; /* 1000000800: an hour boundary near 1e9 s */
  rs_synth_cfg_t cfg = {.model = RS_MODEL_VLP16, .mode = RS_MODE_STRONGEST, .hz = 10.0, .seconds = 1.0, .t0 = hour - 0.45};
  ck_assert_int_gt(rs_synth_write(&cfg, wrap), 700);
  long frames, points;
  const char *out;
  ck_assert_int_eq(run_daemon(wrap, "--fast", &frames, &points, &out), 0);
  ck_assert_msg(labs(frames - clean_frames) <= 1, "%ld frames, clean %ld", frames, clean_frames);
  ck_assert_msg(labs(points - clean_points) <= clean_points / 20, "%ld returns, clean %ld", points, clean_points);
  ck_assert_msg(strstr(out, " 0 missing, 0 out of order, 0 duplicate packets") != NULL, "%s", out);
  /* records stamped t0 - (t - t0): the capture's clock runs backwards */
  static long at[4096], len[4096];
  const int nrec = records(clean, clean_len, at, len, 4096);
  uint8_t *b = malloc((size_t)clean_len);
  memcpy(b, clean, (size_t)clean_len);
  const int64_t t0 = rec_ns(clean + at[0] - 16);
  for (int r = 0; r < nrec; r++) {
    const int64_t t = 2 * t0 - rec_ns(clean + at[r] - 16);
    put32(b + at[r] - 16, (uint32_t)(t / 1000000000LL));
    put32(b + at[r] - 12, (uint32_t)(t % 1000000000LL));
  }
  const char *back = tu_tmp("faults-backwards.pcap");
  spill(back, b, clean_len);
  free(b);
  const int rc = run_daemon(back, "--speed 4", &frames, &points, &out);
  ck_assert_msg(rc == 0, "exit %d (124: it hung): %s", rc, out);
  char csv[700];
  snprintf(csv, sizeof csv, "%s.frames.csv", back);
  same_frames_as_clean(csv, out, false);
}
END_TEST

/* A VLP-32C's model given with a VLP-16 capture: every tool that takes a model refuses it, naming both */
START_TEST(t_model_for_the_wrong_sensor) {
  setup();
  const char *v32 = tu_tmp("faults-v32-model.pcap"), *model = tu_tmp("faults-v32.model");
  rs_synth_cfg_t cfg = {.model = RS_MODEL_VLP32C, .mode = RS_MODE_STRONGEST, .hz = 10.0, .seconds = 0.5, .t0 = 1e9};
  ck_assert_int_gt(rs_synth_write(&cfg, v32), 0);
  char cmd[2048];
  const char *out;
  snprintf(cmd, sizeof cmd, "./roadscan-learn %s -o %s", v32, model);
  ck_assert_msg(tu_exec(cmd, &out) == 0, "%s", out);
  /* labels of the VLP-16 capture, for roadscan-eval */
  const char *labels = tu_tmp("faults-v16-labels.csv");
  snprintf(cmd, sizeof cmd, "./roadscand --pcap %s --fast --no-publish --quiet --labels-out %s", cap, labels);
  ck_assert_msg(tu_exec(cmd, &out) == 0, "%s", out);
  const char *png = tu_tmp("faults-wrong.png");
  struct {
    const char *tool, *fmt;
  } runs[] = {
      {"roadscand", "./roadscand --pcap %s --fast --no-publish --background %s"},
      {"roadscan-bench", "./roadscan-bench %s --model %s"},
      {"roadscan-render", "./roadscan-render %s --frame 3 --background %s -o %s"},
      {"roadscan-eval", "./roadscan-eval %s %s %s --diagnose --model %s"},
  };
  for (size_t i = 0; i < sizeof runs / sizeof runs[0]; i++) {
    if (i == 3) snprintf(cmd, sizeof cmd, runs[i].fmt, cap, labels, labels, model);
    else snprintf(cmd, sizeof cmd, runs[i].fmt, cap, model, png);
    const int rc = tu_exec(cmd, &out);
    ck_assert_msg(rc == 1, "%s: exit %d: %s", runs[i].tool, rc, out);
    ck_assert_msg(strstr(out, "VLP-32C") && strstr(out, "VLP-16"), "%s does not name both sensors: %s", runs[i].tool,
                  out);
  }
}
END_TEST

/* Every allocation the daemon's own code makes while it starts (loading a model, the updater's
 * learner, the label writer, ...) fails in turn (an LD_PRELOAD library): each run ends with a
 * message, never a crash; one that must stop says it ran out of memory */
START_TEST(t_failing_allocations_at_start_up) {
#ifndef RS_FAILALLOC
  fprintf(stderr, "check_faults: failing allocations: not in sanitizer builds (they own malloc); skipped\n");
#else
  setup();
  const char *model = tu_tmp("faults-v16.model"), *report = tu_tmp("faults-allocs.txt");
  char cmd[4096], base[2048];
  const char *out;
  snprintf(cmd, sizeof cmd, "./roadscan-learn %s -o %s", cap, model);
  ck_assert_msg(tu_exec(cmd, &out) == 0, "%s", out);
  const char *configs[] = {"--background %s --labels-out %s.labels --tracks-out %s.tracks",
                           "--learn-seconds 0.5 --learn-out %s.learned --relearn --labels-out %s.labels --tracks-out %s.tracks"};
  for (int c = 0; c < 2; c++) {
    char extra[1200];
    if (c == 0) snprintf(extra, sizeof extra, configs[0], model, report, report);
    else snprintf(extra, sizeof extra, configs[1], report, report, report);
    snprintf(base, sizeof base, "./roadscand --pcap %s --fast --no-publish %s", cap, extra);
    remove(report);
    snprintf(cmd, sizeof cmd, "timeout 120 env RS_FAILALLOC_REPORT=%s LD_PRELOAD=%s %s", report, RS_FAILALLOC, base);
    ck_assert_msg(tu_exec(cmd, &out) == 0, "%s", out);
    const long calls = strtol(tu_slurp_text(report), NULL, 10);
    ck_assert_int_ge(calls, 5); /* the model, the updater's learner, the label buffer, ... */
    int stopped = 0;
    for (long k = 1; k <= calls; k++) {
      snprintf(cmd, sizeof cmd, "timeout 120 env RS_FAILALLOC_NTH=%ld LD_PRELOAD=%s %s", k, RS_FAILALLOC, base);
      const int rc = tu_exec(cmd, &out);
      ck_assert_msg(rc == 0 || rc == 1, "config %d, allocation %ld failing: exit %d: %s", c, k, rc, out);
      if (rc == 1) {
        ck_assert_msg(strstr(out, "out of memory") != NULL, "config %d, allocation %ld: %s", c, k, out);
        stopped++;
      } else {
        ck_assert_msg(strstr(out, "roadscan summary") != NULL, "config %d, allocation %ld: %s", c, k, out);
      }
    }
    ck_assert_int_gt(stopped, 0);
    printf("check_faults: config %d: %ld allocations at start-up, each failing in turn: %d runs stopped with a message, "
           "%ld went on without what failed\n", c, calls, stopped, calls - stopped);
  }
#endif
}
END_TEST

/* Garbage on the live port (loopback): datagrams of every length with random bytes, 1206 random
 * bytes, oversized ones (9000 and 65000 bytes), then the clean capture: every bad one is counted
 * by its kind, the daemon goes on and takes the clean packets whole */
START_TEST(t_garbage_on_the_live_port) {
  setup();
  const char *log = tu_tmp("faults-live.log"), *csv = tu_tmp("faults-live.csv");
  const uint16_t port = (uint16_t)(24000 + getpid() % 1000);
  char cmd[2048];
  snprintf(cmd, sizeof cmd, "./roadscand --iface lo --port %u --no-publish --summary-seconds 0 --frames-out %s", port, csv);
  remove(log);
  const int pid = tu_spawn(cmd, log);
  if (!tu_wait_for(log, "capturing on lo", 60)) {
    const int rc = tu_stop(pid, SIGINT, 60);
    const char *text = tu_slurp_text(log);
    if (strstr(text, "permission denied")) {
      fprintf(stderr, "check_faults: live capture needs CAP_NET_RAW here; garbage on the live port skipped\n");
      return;
    }
    ck_abort_msg("the daemon did not start capturing (exit %d): %s", rc, text);
  }
  int sock = socket(AF_INET, SOCK_DGRAM, 0);
  ck_assert_int_ge(sock, 0);
  struct sockaddr_in to = {.sin_family = AF_INET, .sin_port = htons(port)};
  to.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  static uint8_t junk[65000];
  uint64_t rng = 0x9e3779b97f4a7c15ull;
  for (size_t i = 0; i < sizeof junk; i++) junk[i] = (uint8_t)next(&rng);
  long shorter = 0, longer = 0;
  for (int k = 0; k < 300; k++) { /* every length up to an Ethernet frame's payload */
    const size_t n = 1 + (size_t)(next(&rng) % 1472);
    if (n == 1206) continue;
    ck_assert_int_eq(sendto(sock, junk + k, n, 0, (struct sockaddr *)&to, sizeof to), (ssize_t)n);
    if (n < 1206) shorter++;
    else longer++;
  }
  for (int k = 0; k < 50; k++) /* the right length, random content */
    ck_assert_int_eq(sendto(sock, junk + 3 * k, 1206, 0, (struct sockaddr *)&to, sizeof to), 1206);
  const size_t big[] = {9000, 9000, 65000};
  for (size_t k = 0; k < 3; k++)
    ck_assert_int_eq(sendto(sock, junk, big[k], 0, (struct sockaddr *)&to, sizeof to), (ssize_t)big[k]);
  close(sock);
  const long sent = tu_send_capture(cap, port, 0.0);
  ck_assert_int_gt(sent, 700);
  const long tail = tu_settle_live(port, csv); /* then every packet sent was read */
  const int rc = tu_stop(pid, SIGINT, 60);
  const char *out = tu_slurp_text(log);
  ck_assert_msg(rc == 0, "exit %d: %s", rc, out);
  ck_assert_int_eq(num_after(out, "payload-short="), shorter);
  ck_assert_int_eq(num_after(out, "payload-long="), longer);
  /* 9000 and 65000 bytes are beyond the snapshot length (2048): captured in part, said so, not parsed */
  ck_assert_int_eq(num_after(out, " truncated="), 3);
  ck_assert_int_eq(num_after(out, "block-flag="), 50);
  /* data packets (the right length, to the port); decoded: the clean ones (and the tail's read) */
  const long data = num_after(out, "captured, "), decoded = num_after(out, "data (");
  ck_assert_msg(data - decoded == 50 && decoded >= sent && decoded <= sent + tail, "%ld data, %ld decoded, %ld + %ld sent",
                data, decoded, sent, tail);
  same_frames_as_clean(csv, out, true);
}
END_TEST

int main(void) {
  Suite *s = suite_create("faults");
  TCase *tc = tcase_create("programs");
  tcase_set_timeout(tc, 900);
  tcase_add_test(tc, t_cut_at_many_offsets);
  tcase_add_test(tc, t_corrupt_bytes);
  tcase_add_test(tc, t_paced_replay_of_a_broken_clock);
  tcase_add_test(tc, t_export_frames_as_the_daemon);
  tcase_add_test(tc, t_sensor_switched_mid_stream);
  tcase_add_test(tc, t_two_sensors_on_one_port);
  tcase_add_test(tc, t_clock_wraps_at_the_hour_and_runs_backwards);
  tcase_add_test(tc, t_model_for_the_wrong_sensor);
  tcase_add_test(tc, t_failing_allocations_at_start_up);
  tcase_add_test(tc, t_garbage_on_the_live_port);
  suite_add_tcase(s, tc);
  return tu_run(s);
}

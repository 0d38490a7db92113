/* check_faults - broken input through the real programs: a capture cut at
 * many offsets, 100 variants with 2 % of the packets' bytes corrupted, and
 * record timestamps thrown hours away under a paced replay. Nothing may
 * crash or hang (a generous timeout, not a measured time), only corrupt
 * packets may lose their returns, and what was lost is counted. */
#include "roadscan/util/error.h"
#include "roadscan/sim/synth.h"
#include "testutil.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

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

int main(void) {
  Suite *s = suite_create("faults");
  TCase *tc = tcase_create("programs");
  tcase_set_timeout(tc, 900);
  tcase_add_test(tc, t_cut_at_many_offsets);
  tcase_add_test(tc, t_corrupt_bytes);
  tcase_add_test(tc, t_paced_replay_of_a_broken_clock);
  tcase_add_test(tc, t_export_frames_as_the_daemon);
  suite_add_tcase(s, tc);
  return tu_run(s);
}

/* testutil.c - see testutil.h. */
#include "testutil.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <sys/wait.h>

int tu_run(Suite *s) {
  SRunner *sr = srunner_create(s);
  srunner_run_all(sr, CK_ENV);
  int failed = srunner_ntests_failed(sr);
  srunner_free(sr);
  return failed ? EXIT_FAILURE : EXIT_SUCCESS;
}

static void put16(uint8_t *p, uint16_t v) {
  p[0] = (uint8_t)(v & 0xFF);
  p[1] = (uint8_t)(v >> 8);
}

void tu_block(uint8_t *pkt, int block, uint8_t flag2, uint16_t azimuth) {
  uint8_t *b = pkt + block * 100;
  b[0] = 0xFF;
  b[1] = flag2;
  put16(b + 2, azimuth);
}

void tu_record(uint8_t *pkt, int block, int rec, uint16_t distance, uint8_t intensity) {
  uint8_t *r = pkt + block * 100 + 4 + rec * 3;
  put16(r, distance);
  r[2] = intensity;
}

void tu_tail(uint8_t *pkt, uint32_t ts, uint8_t mode, uint8_t product) {
  for (int i = 0; i < 4; i++) pkt[1200 + i] = (uint8_t)((ts >> (8 * i)) & 0xFF);
  pkt[1204] = mode;
  pkt[1205] = product;
}

void tu_empty_packet(uint8_t *pkt, uint16_t az0, uint16_t step, uint8_t mode, uint8_t product) {
  memset(pkt, 0, 1206);
  for (int b = 0; b < 12; b++) tu_block(pkt, b, 0xEE, (uint16_t)((az0 + step * b) % 36000));
  tu_tail(pkt, 1000, mode, product);
}

const char *tu_tmp(const char *name) {
  static char bufs[8][512];
  static int i;
  char *b = bufs[i++ % 8];
  mkdir(RS_TMP_DIR, 0755);
  snprintf(b, 512, "%s/%s", RS_TMP_DIR, name);
  return b;
}

const char *tu_shared_data(void) {
  struct stat st;
  if (stat(RS_SHARED_DATA, &st) == 0 && S_ISDIR(st.st_mode)) return RS_SHARED_DATA;
  return NULL;
}

int tu_exec(const char *cmdline, const char **out) {
  static char buf[65536];
  char cmd[4096];
  snprintf(cmd, sizeof cmd, "cd %s && { %s ; } 2>&1", RS_BIN_DIR, cmdline);
  FILE *p = popen(cmd, "r");
  if (p == NULL) return -1;
  size_t n = fread(buf, 1, sizeof buf - 1, p);
  buf[n] = '\0';
  while (fread(cmd, 1, sizeof cmd, p) > 0) {
  }
  int st = pclose(p);
  if (out) *out = buf;
  return WIFEXITED(st) ? WEXITSTATUS(st) : -1;
}

long tu_count_lines(const char *path) {
  FILE *f = fopen(path, "r");
  if (f == NULL) return -1;
  long n = 0;
  int c;
  while ((c = fgetc(f)) != EOF)
    if (c == '\n') n++;
  fclose(f);
  return n;
}

void tu_make_site(const char *name, int seed, double test_s, tu_site_t *site) {
  char base[400], cmd[8192];
  const char *out;
  snprintf(base, sizeof base, "%s", tu_tmp(name));
  snprintf(site->pcap, sizeof site->pcap, "%s.pcap", base);
  snprintf(site->truth, sizeof site->truth, "%s.truth.csv", base);
  snprintf(site->model, sizeof site->model, "%s.model", base);
  snprintf(site->objects, sizeof site->objects, "%s.objects.csv", base);
  snprintf(cmd, sizeof cmd,
           "./roadscan-sim --sensor VLP-32C --scenario light --seconds 40 --seed %d -o %s.learn.pcap --labels "
           "%s.learn.csv && ./roadscan-sim --sensor VLP-32C --scenario light --seconds %g --seed %d -o %s --labels %s && "
           "./roadscan-learn %s.learn.pcap -o %s --frames 300 && ./roadscan-eval %s %s %s --objects %s",
           seed, base, base, test_s, seed + 1, site->pcap, site->truth, base, site->model, site->pcap, site->truth,
           site->truth, site->objects);
  ck_assert_msg(tu_exec(cmd, &out) == 0, "%s", out);
}

#define TU_MAX_TRUTH 20000
static struct {
  long frame;
  float c[3];
} truth[TU_MAX_TRUTH];
static int ntruth;

void tu_centroids_load(const char *objects_csv) {
  FILE *f = fopen(objects_csv, "r");
  ck_assert_ptr_nonnull(f);
  char line[256];
  ck_assert_ptr_nonnull(fgets(line, sizeof line, f)); /* header */
  ntruth = 0;
  while (fgets(line, sizeof line, f) && ntruth < TU_MAX_TRUTH) {
    unsigned inst, pts;
    if (sscanf(line, "%ld,%u,%u,%f,%f,%f", &truth[ntruth].frame, &inst, &pts, &truth[ntruth].c[0], &truth[ntruth].c[1],
               &truth[ntruth].c[2]) == 6)
      ntruth++;
  }
  fclose(f);
  ck_assert_int_gt(ntruth, 50);
}

void tu_centroid_add(tu_centroids_t *t, long frame, const float c[3]) {
  float best = INFINITY;
  for (int i = 0; i < ntruth; i++) {
    if (truth[i].frame != frame) continue;
    float dx = truth[i].c[0] - c[0], dy = truth[i].c[1] - c[1], dz = truth[i].c[2] - c[2];
    best = fminf(best, sqrtf(dx * dx + dy * dy + dz * dz));
  }
  t->n++;
  t->within_05 += best < 0.5f;
  t->within_1 += best < 1.0f;
  t->worst = fmaxf(t->worst, best);
}

void tu_centroids_check(const tu_centroids_t *t, const char *what) {
  fprintf(stderr, "%s: %d objects of 50+ returns, %d within 0.5 m of a true object's centroid, %d within 1 m, worst %.2f m\n",
          what, t->n, t->within_05, t->within_1, (double)t->worst);
  ck_assert_int_gt(t->n, 20);
  ck_assert_msg(t->within_05 >= 0.85 * t->n, "%s: %d of %d within 0.5 m", what, t->within_05, t->n);
  ck_assert_msg(t->within_1 >= 0.95 * t->n, "%s: %d of %d within 1 m", what, t->within_1, t->n);
  ck_assert_float_lt(t->worst, 2.0f);
}

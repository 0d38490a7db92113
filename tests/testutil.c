/* testutil.c - see testutil.h. */
#include "testutil.h"

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

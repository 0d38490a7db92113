/* testutil.c - see testutil.h. */
#include "testutil.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <arpa/inet.h>
#include <netinet/in.h>
#include <signal.h>
#include <sys/socket.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>

#include "roadscan/capture/capture.h"
#include "roadscan/capture/net.h"
#include "roadscan/sim/synth.h"

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

int tu_spawn(const char *cmdline, const char *out_path) {
  char cmd[4096];
  snprintf(cmd, sizeof cmd, "cd %s && exec %s >%s 2>&1", RS_BIN_DIR, cmdline, out_path);
  pid_t pid = fork();
  ck_assert_int_ge(pid, 0);
  if (pid == 0) {
    execl("/bin/sh", "sh", "-c", cmd, (char *)NULL);
    _exit(127);
  }
  return (int)pid;
}

static double now_s(void) {
  struct timespec t;
  clock_gettime(CLOCK_MONOTONIC, &t);
  return (double)t.tv_sec + (double)t.tv_nsec * 1e-9;
}

static void nap_ms(long ms) {
  struct timespec d = {ms / 1000, (ms % 1000) * 1000000L};
  nanosleep(&d, NULL);
}

const char *tu_slurp_text(const char *path) {
  static char buf[1 << 20];
  buf[0] = '\0';
  FILE *f = fopen(path, "r");
  if (f == NULL) return buf;
  size_t n = fread(buf, 1, sizeof buf - 1, f);
  buf[n] = '\0';
  fclose(f);
  return buf;
}

bool tu_wait_for(const char *path, const char *needle, double timeout_s) {
  const double end = now_s() + timeout_s;
  do {
    if (strstr(tu_slurp_text(path), needle)) return true;
    nap_ms(20);
  } while (now_s() < end);
  return false;
}

int tu_stop(int pid, int sig, double timeout_s) {
  if (sig) kill(pid, sig);
  const double end = now_s() + timeout_s;
  int st = 0;
  for (;;) {
    pid_t r = waitpid(pid, &st, WNOHANG);
    if (r == pid) break;
    if (r < 0) return -1;
    if (now_s() > end) {
      kill(pid, SIGKILL);
      waitpid(pid, &st, 0);
      break;
    }
    nap_ms(20);
  }
  return WIFEXITED(st) ? WEXITSTATUS(st) : 128 + WTERMSIG(st);
}

long tu_send_capture(const char *path, uint16_t port, double speed) {
  static rs_capture_t c; /* large: not on the stack */
  rs_capture_cfg_t cc = {.data_port = 2368, .speed = speed};
  ck_assert_msg(rs_capture_open_file(&c, path, &cc) == RS_OK, "%s", c.err);
  int sock = socket(AF_INET, SOCK_DGRAM, 0);
  ck_assert_int_ge(sock, 0);
  long sent = 0;
  rs_frame_in_t f;
  while (rs_capture_next(&c, &f, NULL) == 1) {
    rs_udp_t u;
    if (rs_net_parse(c.linktype, f.data, f.caplen, &u) != RS_OK) continue;
    if (port && u.dst_port != 2368) continue; /* other live tests on lo count the position port */
    struct sockaddr_in to = {.sin_family = AF_INET, .sin_port = htons(port ? port : u.dst_port)};
    to.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    if (sendto(sock, u.payload, u.len, 0, (struct sockaddr *)&to, sizeof to) == (ssize_t)u.len) sent++;
  }
  close(sock);
  rs_capture_close(&c);
  return sent;
}

long tu_settle_live(uint16_t port, const char *csv) {
  static int k;
  const char *tail = tu_tmp("settle-tail.pcap");
  rs_synth_cfg_t cfg = {.model = RS_MODEL_VLP16, .mode = RS_MODE_STRONGEST, .hz = 10.0, .seconds = 0.5,
                        .t0 = 2e9 + 10.0 * ++k};
  ck_assert_int_gt(rs_synth_write(&cfg, tail), 300);
  struct timespec now;
  clock_gettime(CLOCK_REALTIME, &now);
  const double t_sent = (double)now.tv_sec + (double)now.tv_nsec * 1e-9;
  const long n = tu_send_capture(tail, port, 1.0); /* paced: a burst would fill a small kernel buffer */
  for (int tries = 0; tries < 6000; tries++) { /* 120 s at most */
    FILE *f = fopen(csv, "r");
    char line[1024];
    bool seen = false;
    while (f && !seen && fgets(line, sizeof line, f)) {
      const char *p = strchr(line, ',');
      seen = p && strtod(p + 1, NULL) >= t_sent; /* t_first: the kernel's receive time */
    }
    if (f) fclose(f);
    if (seen) return n;
    nap_ms(20);
  }
  ck_abort_msg("no frame of the packets sent last in %s", csv);
  return n;
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

bool tu_ground_line(const char *out, double *height, double *lean, double *toward, double *on_plane) {
  const char *g = strstr(out, "ground (from the model): the sensor ");
  if (g == NULL) return false;
  ck_assert_int_eq(
      sscanf(g, "ground (from the model): the sensor %lf m above it; it rises %lf deg towards azimuth %lf", height, lean,
             toward),
      3);
  const char *o = strstr(g, " from the plane; ");
  ck_assert_ptr_nonnull(o);
  ck_assert_int_eq(sscanf(o, " from the plane; %lf %%", on_plane), 1);
  return true;
}

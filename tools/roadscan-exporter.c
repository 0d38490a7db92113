/* roadscan-exporter - the daemon's statistics in the Prometheus text format.
 *
 * A separate process, so the daemon stays lean: it subscribes to the
 * statistics channel (one frame_stats_t per frame and sensor), checks every
 * message before the generated decoder sees it (lcmcheck.h), keeps per sensor
 * the latest totals and a window of the last frames' stage times, and serves
 * them at http://ADDR:PORT/metrics (libmicrohttpd; loopback by default).
 *
 * Threads: the main thread handles LCM and writes the state; libmicrohttpd's
 * own thread renders /metrics. One mutex guards the state (held while a
 * message is applied or a page rendered: microseconds). Sensors, the window
 * and the page are bounded (RS_EXP_SENSORS, --window, RS_EXP_PAGE). */
#include "roadscan/output/lcmcheck.h"
#include "roadscan/output/publish.h"
#include "roadscan/util/error.h"
#include "roadscan/util/opts.h"
#include "roadscan/util/sort.h"

#include <arpa/inet.h>
#include <lcm/lcm.h>
#include <microhttpd.h>
#include <pthread.h>
#include <roadscan_frame_stats_t.h>
#include <signal.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>

#define RS_EXP_SENSORS 16        /* sensors followed; more are counted, not shown */
#define RS_EXP_WINDOW_MAX 36000  /* frames of stage times kept per sensor */
#define RS_EXP_KINDS 64          /* error kinds kept per sensor */
#define RS_EXP_PAGE (256 * 1024) /* the largest page */
#define RS_EXP_STAGES 7

static const char *const stage_name[RS_EXP_STAGES] = {"background", "cluster", "objects", "tracks", "publish",
                                                      "processing", "latency"};

typedef struct {
  char id[128];
  roadscan_frame_stats_t last; /* its strings are not kept: sensor_id is id, the error kinds below */
  double last_seen;            /* CLOCK_REALTIME of the last message */
  uint64_t messages;
  int nkinds;
  char kind[RS_EXP_KINDS][48];
  int64_t kind_count[RS_EXP_KINDS];
  int32_t *win[RS_EXP_STAGES]; /* microseconds, ring of --window frames (latency -1: unknown) */
  int win_n, win_at;
  double sum_s[RS_EXP_STAGES];
  uint64_t count[RS_EXP_STAGES];
} sensor_t;

static struct {
  pthread_mutex_t mu;
  sensor_t s[RS_EXP_SENSORS];
  int n;
  int window;
  uint64_t messages, malformed, other_sensors, scrapes;
} X = {.mu = PTHREAD_MUTEX_INITIALIZER};

static volatile sig_atomic_t stop;
static void on_signal(int sig) {
  (void)sig;
  stop = 1;
}

static double wall_s(void) {
  struct timespec t;
  clock_gettime(CLOCK_REALTIME, &t);
  return (double)t.tv_sec + (double)t.tv_nsec * 1e-9;
}

static sensor_t *sensor_of(const char *id) {
  for (int i = 0; i < X.n; i++)
    if (strcmp(X.s[i].id, id) == 0) return &X.s[i];
  if (X.n == RS_EXP_SENSORS) return NULL;
  sensor_t *s = &X.s[X.n];
  for (int k = 0; k < RS_EXP_STAGES; k++) {
    s->win[k] = calloc((size_t)X.window, sizeof(int32_t));
    if (s->win[k] == NULL) return NULL;
  }
  snprintf(s->id, sizeof s->id, "%s", id);
  X.n++;
  return s;
}

static void on_stats(const lcm_recv_buf_t *rbuf, const char *channel, void *user) {
  (void)user;
  char why[RS_ERRMSG_SIZE] = "it does not decode";
  roadscan_frame_stats_t m;
  memset(&m, 0, sizeof m);
  const bool ok = rs_lcm_check(RS_LCM_FRAME_STATS, rbuf->data, (int)rbuf->data_size, why, sizeof why);
  if (!ok || roadscan_frame_stats_t_decode(rbuf->data, 0, (int)rbuf->data_size, &m) < 0) {
    if (ok) roadscan_frame_stats_t_decode_cleanup(&m);
    pthread_mutex_lock(&X.mu);
    if (X.malformed++ == 0)
      fprintf(stderr, "roadscan-exporter: %s: a message of %u bytes is not roadscan frame statistics (%s); ignored "
                      "(further ones are counted: roadscan_exporter_malformed_total)\n",
              channel, rbuf->data_size, why);
    pthread_mutex_unlock(&X.mu);
    return;
  }
  pthread_mutex_lock(&X.mu);
  X.messages++;
  sensor_t *s = sensor_of(m.sensor_id);
  if (s == NULL) {
    X.other_sensors++;
  } else {
    s->last = m;
    s->last.sensor_id = NULL;
    s->last.error_kinds = NULL;
    s->last.error_counts = NULL;
    s->last_seen = wall_s();
    s->messages++;
    s->nkinds = 0;
    for (int i = 0; i < m.num_errors && s->nkinds < RS_EXP_KINDS; i++) {
      snprintf(s->kind[s->nkinds], sizeof s->kind[0], "%s", m.error_kinds[i]);
      s->kind_count[s->nkinds++] = m.error_counts[i];
    }
    const int32_t us[RS_EXP_STAGES] = {m.background_us, m.cluster_us, m.objects_us, m.tracks_us,
                                       m.publish_us,    m.processing_us, m.latency_us};
    for (int k = 0; k < RS_EXP_STAGES; k++) {
      s->win[k][s->win_at] = us[k];
      if (us[k] >= 0) {
        s->sum_s[k] += us[k] * 1e-6;
        s->count[k]++;
      }
    }
    s->win_at = (s->win_at + 1) % X.window;
    if (s->win_n < X.window) s->win_n++;
  }
  pthread_mutex_unlock(&X.mu);
  roadscan_frame_stats_t_decode_cleanup(&m);
}

/* ---- the page ------------------------------------------------------------ */

typedef struct {
  char *b;
  size_t n, cap;
  bool full;
} page_t;

static void put(page_t *p, const char *fmt, ...) {
  if (p->full) return;
  va_list ap;
  va_start(ap, fmt);
  const int k = vsnprintf(p->b + p->n, p->cap - p->n, fmt, ap);
  va_end(ap);
  if (k < 0 || (size_t)k >= p->cap - p->n) {
    p->full = true;
    return;
  }
  p->n += (size_t)k;
}

/* a label value: backslash, double quote and newline escaped (the exposition format) */
static const char *label(const char *v, char *buf, size_t n) {
  size_t j = 0;
  for (size_t i = 0; v[i] && j + 3 < n; i++) {
    const char c = v[i];
    if (c == '\\' || c == '"') {
      buf[j++] = '\\';
      buf[j++] = c;
    } else if (c == '\n') {
      buf[j++] = '\\';
      buf[j++] = 'n';
    } else {
      buf[j++] = c;
    }
  }
  buf[j] = '\0';
  return buf;
}

static void head(page_t *p, const char *name, const char *type, const char *help) {
  put(p, "# HELP %s %s\n# TYPE %s %s\n", name, help, name, type);
}

typedef enum { F_I64, F_I32, F_F32 } ftype_t;
typedef struct {
  const char *name, *type, *help;
  size_t off;
  ftype_t t;
  double scale;
} field_t;

#define FS(f) offsetof(roadscan_frame_stats_t, f)
static const field_t fields[] = {
    {"roadscan_frames_processed_total", "counter", "Frames the daemon processed since it started.",
     FS(frames_processed), F_I64, 1},
    {"roadscan_frames_dropped_total", "counter",
     "Frames dropped because processing was busy (the packet thread never waits).", FS(frames_dropped), F_I64, 1},
    {"roadscan_deadline_overruns_total", "counter", "Frames whose processing took longer than the budget.",
     FS(deadline_overruns), F_I64, 1},
    {"roadscan_packets_missing_total", "counter", "Data packets missing from frames (by the sensor's sequence).",
     FS(packets_missing), F_I64, 1},
    {"roadscan_kernel_dropped_packets_total", "counter",
     "Packets the kernel or the interface dropped before the daemon read them (live capture).",
     FS(kernel_dropped), F_I64, 1},
    {"roadscan_truncated_lists_total", "counter", "Object lists cut to fit one LCM datagram.", FS(truncated_lists),
     F_I64, 1},
    {"roadscan_frame_points", "gauge", "Returns in the last frame.", FS(points), F_I32, 1},
    {"roadscan_frame_foreground_points", "gauge", "Returns left after background subtraction in the last frame.",
     FS(foreground), F_I32, 1},
    {"roadscan_frame_clusters", "gauge", "Clusters in the last frame.", FS(clusters), F_I32, 1},
    {"roadscan_frame_objects", "gauge", "Objects in the last frame's list.", FS(objects), F_I32, 1},
    {"roadscan_tracks", "gauge", "Tracks alive after the last frame.", FS(tracks), F_I32, 1},
    {"roadscan_frame_budget_seconds", "gauge", "The processing budget of a frame.", FS(budget_ms), F_F32, 1e-3},
    {"roadscan_capture_buffer_bytes", "gauge", "The kernel's capture buffer (live; 0 in a replay).",
     FS(capture_buffer_kib), F_I32, 1024},
    {"roadscan_background_model_age_seconds", "gauge",
     "Since the background model in use was learned or last updated (-1: no model yet).", FS(model_age_s), F_F32, 1},
};

static double field_value(const roadscan_frame_stats_t *m, const field_t *f) {
  const char *b = (const char *)m + f->off;
  double v = 0;
  if (f->t == F_I64) v = (double)*(const int64_t *)(const void *)b;
  else if (f->t == F_I32) v = (double)*(const int32_t *)(const void *)b;
  else v = (double)*(const float *)(const void *)b;
  return v * f->scale;
}

static int cmp_i32(const void *a, const void *b) {
  const int32_t x = *(const int32_t *)a, y = *(const int32_t *)b;
  return (x > y) - (x < y);
}

static void render(page_t *p) {
  char lb[300], lk[120];
  for (size_t i = 0; i < sizeof fields / sizeof fields[0]; i++) {
    head(p, fields[i].name, fields[i].type, fields[i].help);
    for (int k = 0; k < X.n; k++)
      put(p, fields[i].t == F_F32 ? "%s{sensor_id=\"%s\"} %.6g\n" : "%s{sensor_id=\"%s\"} %.17g\n", fields[i].name,
          label(X.s[k].id, lb, sizeof lb), field_value(&X.s[k].last, &fields[i]));
  }
  head(p, "roadscan_input_errors_total", "counter",
       "Input errors by kind since the daemon started (malformed packets, mismatched sensors, ...).");
  for (int k = 0; k < X.n; k++)
    for (int j = 0; j < X.s[k].nkinds; j++)
      put(p, "roadscan_input_errors_total{sensor_id=\"%s\",kind=\"%s\"} %lld\n", label(X.s[k].id, lb, sizeof lb),
          label(X.s[k].kind[j], lk, sizeof lk), (long long)X.s[k].kind_count[j]);
  head(p, "roadscan_stage_seconds", "summary",
       "Time of a frame's stage (CLOCK_MONOTONIC in the daemon): quantiles over the last --window frames, sum and "
       "count over the frames this exporter saw; stage=processing is the whole frame, stage=latency from its last "
       "packet to its list published.");
  static int32_t sorted[RS_EXP_WINDOW_MAX];
  static const double q[3] = {0.5, 0.9, 0.99};
  for (int k = 0; k < X.n; k++) {
    const sensor_t *s = &X.s[k];
    label(s->id, lb, sizeof lb);
    for (int st = 0; st < RS_EXP_STAGES; st++) {
      int n = 0;
      for (int i = 0; i < s->win_n; i++)
        if (s->win[st][i] >= 0) sorted[n++] = s->win[st][i];
      rs_sort(sorted, (size_t)n, sizeof sorted[0], cmp_i32);
      for (int j = 0; j < 3 && n > 0; j++) {
        const int at = (int)(q[j] * (n - 1) + 0.5);
        put(p, "roadscan_stage_seconds{sensor_id=\"%s\",stage=\"%s\",quantile=\"%g\"} %.6f\n", lb, stage_name[st], q[j],
            sorted[at] * 1e-6);
      }
      put(p, "roadscan_stage_seconds_sum{sensor_id=\"%s\",stage=\"%s\"} %.6f\n", lb, stage_name[st], s->sum_s[st]);
      put(p, "roadscan_stage_seconds_count{sensor_id=\"%s\",stage=\"%s\"} %llu\n", lb, stage_name[st],
          (unsigned long long)s->count[st]);
    }
  }
  head(p, "roadscan_last_statistics_timestamp_seconds", "gauge",
       "When the exporter last received this sensor's statistics (Unix time): a daemon that stopped publishing "
       "shows here.");
  for (int k = 0; k < X.n; k++)
    put(p, "roadscan_last_statistics_timestamp_seconds{sensor_id=\"%s\"} %.3f\n", label(X.s[k].id, lb, sizeof lb),
        X.s[k].last_seen);
  head(p, "roadscan_exporter_messages_total", "counter", "Statistics messages received.");
  put(p, "roadscan_exporter_messages_total %llu\n", (unsigned long long)X.messages);
  head(p, "roadscan_exporter_malformed_total", "counter", "Messages refused before decoding (malformed or hostile).");
  put(p, "roadscan_exporter_malformed_total %llu\n", (unsigned long long)X.malformed);
  head(p, "roadscan_exporter_other_sensors_total", "counter",
       "Messages from sensors beyond the ones followed (" "16" ").");
  put(p, "roadscan_exporter_other_sensors_total %llu\n", (unsigned long long)X.other_sensors);
  head(p, "roadscan_exporter_scrapes_total", "counter", "Pages of metrics served.");
  put(p, "roadscan_exporter_scrapes_total %llu\n", (unsigned long long)X.scrapes);
}

static enum MHD_Result reply(struct MHD_Connection *c, unsigned code, const char *type, char *body, size_t n,
                             enum MHD_ResponseMemoryMode mode) {
  struct MHD_Response *r = MHD_create_response_from_buffer(n, body, mode);
  if (r == NULL) return MHD_NO;
  MHD_add_response_header(r, "Content-Type", type);
  MHD_add_response_header(r, "Cache-Control", "no-store");
  const enum MHD_Result ok = MHD_queue_response(c, code, r);
  MHD_destroy_response(r);
  return ok;
}

static enum MHD_Result on_request(void *cls, struct MHD_Connection *c, const char *url, const char *method,
                                  const char *version, const char *upload, size_t *upload_size, void **state) {
  (void)cls;
  (void)version;
  (void)upload;
  if (*state == NULL) { /* first call: headers only */
    static int marker;
    *state = &marker;
    return MHD_YES;
  }
  if (*upload_size) { /* a body is not wanted: discard it */
    *upload_size = 0;
    return MHD_YES;
  }
  static char not_found[] = "not found: the metrics are at /metrics\n", not_allowed[] = "only GET and HEAD\n";
  if (strcmp(method, "GET") != 0 && strcmp(method, "HEAD") != 0)
    return reply(c, MHD_HTTP_METHOD_NOT_ALLOWED, "text/plain", not_allowed, strlen(not_allowed), MHD_RESPMEM_PERSISTENT);
  if (strcmp(url, "/metrics") != 0)
    return reply(c, MHD_HTTP_NOT_FOUND, "text/plain", not_found, strlen(not_found), MHD_RESPMEM_PERSISTENT);
  page_t p = {.b = malloc(RS_EXP_PAGE), .cap = RS_EXP_PAGE};
  if (p.b == NULL) return MHD_NO;
  pthread_mutex_lock(&X.mu);
  X.scrapes++;
  render(&p);
  pthread_mutex_unlock(&X.mu);
  return reply(c, MHD_HTTP_OK, "text/plain; version=0.0.4; charset=utf-8", p.b, p.n, MHD_RESPMEM_MUST_FREE);
}

/* ---- options ---------------------------------------------------------------- */

typedef struct {
  const char *url, *channel, *listen;
  int window;
} settings_t;
static settings_t st;
static rs_opts_t opts;

#define T settings_t
static const rs_opt_t table[] = {
    {.type = RS_OPT_STR, .name = "lcm-url", .arg = "URL", .off = offsetof(T, url),
     .def = "$LCM_DEFAULT_URL, else " RS_PUB_DEFAULT_URL, .help = "LCM provider (file://LOG?speed=0 reads a log)"},
    RS_OPT_STR_("stats-channel", "NAME", T, channel, "the daemon's statistics channel"),
    RS_OPT_STR_("listen", "ADDR:PORT", T, listen, "where /metrics is served (IPv4; 0.0.0.0 for every interface)"),
    RS_OPT_INT_("window", "N", T, window, 10, RS_EXP_WINDOW_MAX, "frames of stage times for the quantiles"),
};
#undef T

static const rs_opts_spec_t spec = {
    .prog = "roadscan-exporter",
    .summary = "roadscand's statistics in the Prometheus text format, over HTTP",
    .synopsis = "[options]",
    .about = "Subscribes to the daemon's statistics channel and serves http://ADDR:PORT/metrics: per sensor the "
             "totals (frames processed and dropped, deadline overruns, packets missing, packets the kernel dropped, "
             "input errors by kind), the last frame's points, clusters, objects and tracks, and the stage times' "
             "quantiles over the last frames (docs/objects-and-lcm.md). Every message is checked before it is "
             "decoded. SIGINT/SIGTERM stop it.",
    .epilog = "Exit status: 0 stopped by a signal, 1 cannot listen or subscribe, 2 bad usage.",
    .opts = table,
    .n = (int)(sizeof table / sizeof table[0]),
};

int main(int argc, char **argv) {
  const char *env = getenv("LCM_DEFAULT_URL");
  st = (settings_t){.url = env && env[0] ? env : RS_PUB_DEFAULT_URL, .channel = RS_PUB_DEFAULT_STATS,
                    .listen = "127.0.0.1:9860", .window = 1200};
  int first;
  const int start = rs_opts_start(&opts, &spec, &st, argc, argv, &first);
  if (start >= 0) return start;
  X.window = st.window;
  char host[64];
  unsigned port = 0;
  char tail;
  const char *colon = strrchr(st.listen, ':');
  struct sockaddr_in sa = {.sin_family = AF_INET};
  if (colon == NULL || (size_t)(colon - st.listen) >= sizeof host ||
      sscanf(colon + 1, "%u%c", &port, &tail) != 1 || port == 0 || port > 65535) {
    fprintf(stderr, "roadscan-exporter: --listen '%s' is not ADDR:PORT\n", st.listen);
    return 2;
  }
  memcpy(host, st.listen, (size_t)(colon - st.listen));
  host[colon - st.listen] = '\0';
  if (inet_pton(AF_INET, host, &sa.sin_addr) != 1) {
    fprintf(stderr, "roadscan-exporter: --listen '%s': '%s' is not an IPv4 address\n", st.listen, host);
    return 2;
  }
  sa.sin_port = htons((uint16_t)port);
  lcm_t *lcm = lcm_create(st.url);
  if (lcm == NULL) {
    fprintf(stderr, "roadscan-exporter: cannot open LCM URL '%s'\n", st.url);
    return 1;
  }
  lcm_subscribe(lcm, st.channel, on_stats, NULL);
  struct MHD_Daemon *d = MHD_start_daemon(
      MHD_USE_INTERNAL_POLLING_THREAD | MHD_USE_ERROR_LOG, (uint16_t)port, NULL, NULL, on_request, NULL,
      MHD_OPTION_SOCK_ADDR, (struct sockaddr *)&sa, MHD_OPTION_CONNECTION_LIMIT, (unsigned)128,
      MHD_OPTION_PER_IP_CONNECTION_LIMIT, (unsigned)64, MHD_OPTION_CONNECTION_TIMEOUT, (unsigned)10,
      MHD_OPTION_CONNECTION_MEMORY_LIMIT, (size_t)32768, MHD_OPTION_END);
  if (d == NULL) {
    fprintf(stderr, "roadscan-exporter: cannot listen on %s (in use, or not an address of this host)\n", st.listen);
    lcm_destroy(lcm);
    return 1;
  }
  fprintf(stderr, "roadscan-exporter: serving http://%s/metrics from %s on %s\n", st.listen, st.channel, st.url);
  struct sigaction sig;
  memset(&sig, 0, sizeof sig);
  sig.sa_handler = on_signal;
  sigaction(SIGINT, &sig, NULL);
  sigaction(SIGTERM, &sig, NULL);
  bool lcm_open = true;
  while (!stop) {
    if (lcm_open) {
      if (lcm_handle_timeout(lcm, 200) < 0) lcm_open = false; /* the end of a log: serve what was read */
    } else {
      struct timespec t = {0, 200000000L};
      nanosleep(&t, NULL);
    }
  }
  MHD_stop_daemon(d);
  lcm_destroy(lcm);
  for (int i = 0; i < X.n; i++)
    for (int k = 0; k < RS_EXP_STAGES; k++) free(X.s[i].win[k]);
  return 0;
}

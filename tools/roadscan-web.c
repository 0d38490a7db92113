/* roadscan-web - a live view of the daemon in the browser.
 *
 * A separate process (the daemon stays lean): it subscribes to the LCM
 * channels (track lists, object lists, counts, statistics, track ends,
 * crossing events),
 * checks every message before decoding it (lcmcheck.h), turns it into the
 * JSON of docs/bridge-schema.json (src/output/json.c) and serves
 *   /            the page (www/index.html, app.js, style.css: no build step,
 *                nothing from the network),
 *   /events      the messages as Server-Sent Events, as they arrive,
 *   /config      the counting lines and zones to draw (--count-line, --count-zone),
 * on a local address (libmicrohttpd; loopback by default). `--log FILE`
 * replays a recorded LCM log at its own pace instead.
 *
 * Threads: the main thread handles LCM and appends events to a ring of the
 * last RS_WEB_EVENTS (each a JSON document of at most RS_WEB_EVENT_MAX bytes);
 * each browser has a thread of libmicrohttpd's that reads the ring from its
 * own cursor (waiting on a condition variable, at most a second, then a
 * keep-alive comment). A browser that reads slowly falls behind and skips to
 * the oldest event still in the ring (its own updates are lost, counted);
 * nothing waits for it. One mutex guards the ring. Connections are limited
 * (--max-clients), requests have a size limit and a timeout. */
#include "roadscan/output/json.h"
#include "roadscan/output/lcmcheck.h"
#include "roadscan/output/publish.h"
#include "roadscan/perception/count.h"
#include "roadscan/util/error.h"
#include "roadscan/util/opts.h"

#include <arpa/inet.h>
#include <errno.h>
#include <lcm/lcm.h>
#include <microhttpd.h>
#include <pthread.h>
#include <signal.h>
#include <stdatomic.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <time.h>
#include <unistd.h>

#define RS_WEB_EVENTS 512          /* events kept for the browsers */
#define RS_WEB_EVENT_MAX (96 * 1024) /* one event's JSON, at most (a full track list is about 60 kB) */
#define RS_WEB_FILE_MAX (1 << 20)  /* a static file, at most */

enum { K_OBJECTS, K_TRACKS, K_TRACK_ENDS, K_COUNTS, K_STATS, K_CROSSINGS, K_KINDS };
static const char *const kind_name[K_KINDS] = {"objects", "tracks", "track_ends", "counts", "stats", "crossings"};
static const rs_lcm_type_t kind_type[K_KINDS] = {RS_LCM_OBJECT_LIST, RS_LCM_TRACK_LIST, RS_LCM_TRACK_END,
                                                 RS_LCM_COUNTS,      RS_LCM_FRAME_STATS, RS_LCM_CROSSING};

typedef struct {
  uint64_t seq;  /* 1, 2, ... */
  int kind;
  size_t len;
  char *data;    /* "event: KIND\ndata: JSON\n\n", owned */
} event_t;

static struct {
  pthread_mutex_t mu;
  pthread_cond_t cv;
  event_t ring[RS_WEB_EVENTS];
  uint64_t next;                   /* seq of the next event */
  uint64_t received[K_KINDS], malformed, too_large, skipped, clients, served;
} W = {.mu = PTHREAD_MUTEX_INITIALIZER, .cv = PTHREAD_COND_INITIALIZER, .next = 1};

static volatile sig_atomic_t stop;
static _Atomic bool quitting;
static void on_signal(int sig) {
  (void)sig;
  stop = 1;
}

static char config_json[16384]; /* the lines and zones, for /config */
static const char *www;

/* ---- events --------------------------------------------------------------- */

static void publish_event(int kind, const char *json) {
  const size_t n = strlen(json);
  if (n > RS_WEB_EVENT_MAX) {
    pthread_mutex_lock(&W.mu);
    W.too_large++;
    pthread_mutex_unlock(&W.mu);
    return;
  }
  char *d = malloc(n + 48);
  if (d == NULL) return;
  const int len = snprintf(d, n + 48, "event: %s\ndata: %s\n\n", kind_name[kind], json);
  pthread_mutex_lock(&W.mu);
  event_t *e = &W.ring[W.next % RS_WEB_EVENTS];
  free(e->data);
  *e = (event_t){.seq = W.next++, .kind = kind, .len = (size_t)len, .data = d};
  W.received[kind]++;
  pthread_cond_broadcast(&W.cv);
  pthread_mutex_unlock(&W.mu);
}

static void on_message(const lcm_recv_buf_t *rbuf, const char *channel, void *user) {
  (void)channel;
  const int kind = (int)(intptr_t)user;
  char why[RS_ERRMSG_SIZE];
  if (!rs_lcm_check(kind_type[kind], rbuf->data, (int)rbuf->data_size, why, sizeof why)) {
    pthread_mutex_lock(&W.mu);
    const bool first = W.malformed++ == 0;
    pthread_mutex_unlock(&W.mu);
    if (first) fprintf(stderr, "roadscan-web: %s: a message refused (%s); further ones are counted\n", channel, why);
    return;
  }
  json_t *j = NULL;
  const void *d = rbuf->data;
  const int n = (int)rbuf->data_size;
  bool text = true;
  switch (kind) {
  case K_OBJECTS: {
    roadscan_object_list_t m;
    if (roadscan_object_list_t_decode(d, 0, n, &m) < 0) return;
    text = rs_json_text_ok(m.sensor_id) && rs_json_text_ok(m.sensor_model);
    if (text) j = rs_json_objects(&m);
    roadscan_object_list_t_decode_cleanup(&m);
    break;
  }
  case K_TRACKS: {
    roadscan_track_list_t m;
    if (roadscan_track_list_t_decode(d, 0, n, &m) < 0) return;
    text = rs_json_text_ok(m.sensor_id);
    if (text) j = rs_json_tracks(&m);
    roadscan_track_list_t_decode_cleanup(&m);
    break;
  }
  case K_TRACK_ENDS: {
    roadscan_track_end_t m;
    if (roadscan_track_end_t_decode(d, 0, n, &m) < 0) return;
    text = rs_json_text_ok(m.sensor_id);
    if (text) j = rs_json_track_end(&m);
    roadscan_track_end_t_decode_cleanup(&m);
    break;
  }
  case K_COUNTS: {
    roadscan_counts_t m;
    if (roadscan_counts_t_decode(d, 0, n, &m) < 0) return;
    text = rs_json_text_ok(m.sensor_id);
    for (int i = 0; i < m.num_lines && text; i++) text = rs_json_text_ok(m.lines[i].name);
    for (int i = 0; i < m.num_zones && text; i++) text = rs_json_text_ok(m.zones[i].name);
    if (text) j = rs_json_counts(&m);
    roadscan_counts_t_decode_cleanup(&m);
    break;
  }
  case K_CROSSINGS: {
    roadscan_crossing_t m;
    if (roadscan_crossing_t_decode(d, 0, n, &m) < 0) return;
    text = rs_json_text_ok(m.sensor_id) && rs_json_text_ok(m.line);
    if (text) j = rs_json_crossing(&m);
    roadscan_crossing_t_decode_cleanup(&m);
    break;
  }
  default: {
    roadscan_frame_stats_t m;
    if (roadscan_frame_stats_t_decode(d, 0, n, &m) < 0) return;
    text = rs_json_text_ok(m.sensor_id);
    for (int i = 0; i < m.num_errors && text; i++) text = rs_json_text_ok(m.error_kinds[i]);
    if (text) j = rs_json_stats(&m);
    roadscan_frame_stats_t_decode_cleanup(&m);
    break;
  }
  }
  char *s = j ? json_dumps(j, RS_JSON_DUMP_FLAGS) : NULL;
  json_decref(j);
  if (s == NULL) {
    pthread_mutex_lock(&W.mu);
    W.malformed++;
    pthread_mutex_unlock(&W.mu);
    return;
  }
  publish_event(kind, s);
  free(s);
}

/* ---- /events: one browser's stream (its own libmicrohttpd thread) --------- */

typedef struct {
  uint64_t cursor;  /* the next event this browser gets */
  char *pending;    /* what is left of the event being sent */
  size_t left;
  char buf[RS_WEB_EVENT_MAX + 64];
} stream_t;

static ssize_t stream_read(void *cls, uint64_t pos, char *out, size_t max) {
  (void)pos;
  stream_t *st = cls;
  if (st->left == 0) {
    pthread_mutex_lock(&W.mu);
    struct timespec until;
    clock_gettime(CLOCK_REALTIME, &until);
    until.tv_sec += 1;
    while (st->cursor >= W.next && !atomic_load(&quitting))
      if (pthread_cond_timedwait(&W.cv, &W.mu, &until) == ETIMEDOUT) break;
    if (atomic_load(&quitting)) {
      pthread_mutex_unlock(&W.mu);
      return MHD_CONTENT_READER_END_OF_STREAM;
    }
    if (st->cursor < W.next) {
      const uint64_t oldest = W.next > RS_WEB_EVENTS ? W.next - RS_WEB_EVENTS : 1;
      if (st->cursor < oldest) { /* fell behind: its own updates are lost */
        W.skipped += oldest - st->cursor;
        st->cursor = oldest;
      }
      const event_t *e = &W.ring[st->cursor % RS_WEB_EVENTS];
      memcpy(st->buf, e->data, e->len);
      st->left = e->len;
      st->cursor++;
    } else { /* a second without news: a comment keeps the connection */
      memcpy(st->buf, ":\n\n", 3);
      st->left = 3;
    }
    pthread_mutex_unlock(&W.mu);
    st->pending = st->buf;
  }
  const size_t n = st->left < max ? st->left : max;
  memcpy(out, st->pending, n);
  st->pending += n;
  st->left -= n;
  return (ssize_t)n;
}

static void stream_free(void *cls) {
  free(cls);
  pthread_mutex_lock(&W.mu);
  W.clients--;
  pthread_mutex_unlock(&W.mu);
}

/* ---- HTTP ------------------------------------------------------------------ */

static enum MHD_Result reply(struct MHD_Connection *c, unsigned code, const char *type, void *body, size_t n,
                             enum MHD_ResponseMemoryMode mode) {
  struct MHD_Response *r = MHD_create_response_from_buffer(n, body, mode);
  if (r == NULL) return MHD_NO;
  MHD_add_response_header(r, "Content-Type", type);
  MHD_add_response_header(r, "Cache-Control", "no-store");
  MHD_add_response_header(r, "X-Content-Type-Options", "nosniff");
  MHD_add_response_header(r, "Content-Security-Policy",
                          "default-src 'self'; img-src 'self' data:; style-src 'self'; script-src 'self'");
  const enum MHD_Result ok = MHD_queue_response(c, code, r);
  MHD_destroy_response(r);
  return ok;
}

static enum MHD_Result text(struct MHD_Connection *c, unsigned code, const char *msg) {
  return reply(c, code, "text/plain; charset=utf-8", (void *)msg, strlen(msg), MHD_RESPMEM_PERSISTENT);
}

/* a file of the page: only the names listed, from --www */
static enum MHD_Result serve_file(struct MHD_Connection *c, const char *name, const char *type) {
  char path[4200];
  snprintf(path, sizeof path, "%s/%s", www, name);
  FILE *f = fopen(path, "rb");
  if (f == NULL) return text(c, MHD_HTTP_NOT_FOUND, "the page's files are not installed (--www)\n");
  char *b = malloc(RS_WEB_FILE_MAX);
  size_t n = b ? fread(b, 1, RS_WEB_FILE_MAX, f) : 0;
  fclose(f);
  if (b == NULL) return MHD_NO;
  return reply(c, MHD_HTTP_OK, type, b, n, MHD_RESPMEM_MUST_FREE);
}

static enum MHD_Result on_request(void *cls, struct MHD_Connection *c, const char *url, const char *method,
                                  const char *version, const char *upload, size_t *upload_size, void **state) {
  (void)cls;
  (void)version;
  (void)upload;
  if (*state == NULL) {
    static int marker;
    *state = &marker;
    return MHD_YES;
  }
  if (*upload_size) {
    *upload_size = 0;
    return MHD_YES;
  }
  if (strcmp(method, "GET") != 0 && strcmp(method, "HEAD") != 0)
    return text(c, MHD_HTTP_METHOD_NOT_ALLOWED, "only GET and HEAD\n");
  if (strcmp(url, "/") == 0 || strcmp(url, "/index.html") == 0) return serve_file(c, "index.html", "text/html; charset=utf-8");
  if (strcmp(url, "/app.js") == 0) return serve_file(c, "app.js", "text/javascript; charset=utf-8");
  if (strcmp(url, "/style.css") == 0) return serve_file(c, "style.css", "text/css; charset=utf-8");
  if (strcmp(url, "/config") == 0)
    return reply(c, MHD_HTTP_OK, "application/json", config_json, strlen(config_json), MHD_RESPMEM_PERSISTENT);
  if (strcmp(url, "/status") == 0) {
    char *b = malloc(512);
    if (b == NULL) return MHD_NO;
    pthread_mutex_lock(&W.mu);
    const int n = snprintf(b, 512,
                           "{\"events\": %llu, \"clients\": %llu, \"served\": %llu, \"skipped\": %llu, \"malformed\": "
                           "%llu, \"too_large\": %llu}\n",
                           (unsigned long long)(W.next - 1), (unsigned long long)W.clients,
                           (unsigned long long)W.served, (unsigned long long)W.skipped,
                           (unsigned long long)W.malformed, (unsigned long long)W.too_large);
    pthread_mutex_unlock(&W.mu);
    return reply(c, MHD_HTTP_OK, "application/json", b, (size_t)n, MHD_RESPMEM_MUST_FREE);
  }
  if (strcmp(url, "/events") == 0) {
    stream_t *st = malloc(sizeof *st);
    if (st == NULL) return MHD_NO;
    pthread_mutex_lock(&W.mu);
    /* a new browser starts with the last few events: the view is not empty until the next frame */
    st->cursor = W.next > 16 ? W.next - 16 : 1;
    if (W.next > RS_WEB_EVENTS && st->cursor < W.next - RS_WEB_EVENTS) st->cursor = W.next - RS_WEB_EVENTS;
    W.clients++;
    W.served++;
    pthread_mutex_unlock(&W.mu);
    st->left = 0;
    struct MHD_Response *r = MHD_create_response_from_callback(MHD_SIZE_UNKNOWN, 64 * 1024, stream_read, st, stream_free);
    if (r == NULL) {
      stream_free(st);
      return MHD_NO;
    }
    MHD_add_response_header(r, "Content-Type", "text/event-stream");
    MHD_add_response_header(r, "Cache-Control", "no-store");
    const enum MHD_Result ok = MHD_queue_response(c, MHD_HTTP_OK, r);
    MHD_destroy_response(r);
    return ok;
  }
  return text(c, MHD_HTTP_NOT_FOUND, "not found\n");
}

/* ---- options -------------------------------------------------------------- */

typedef struct {
  const char *url, *log, *listen, *www;
  const char *ch[K_KINDS];
  int max_clients;
  rs_count_lines_t lines;
  rs_count_zones_t zones;
} settings_t;
static settings_t st;
static rs_opts_t opts;

#define T settings_t
static const rs_opt_t table[] = {
    RS_OPT_HEAD("source", "What to show"),
    {.type = RS_OPT_STR, .name = "lcm-url", .arg = "URL", .off = offsetof(T, url),
     .def = "$LCM_DEFAULT_URL, else " RS_PUB_DEFAULT_URL, .help = "LCM provider"},
    RS_OPT_STR_("log", "FILE", T, log, "replay a recorded LCM log (lcm-logger) at its own pace instead"),
    RS_OPT_STR_("channel", "NAME", T, ch[K_OBJECTS], "object lists"),
    RS_OPT_STR_("tracks-channel", "NAME", T, ch[K_TRACKS], "track lists"),
    RS_OPT_STR_("track-ends-channel", "NAME", T, ch[K_TRACK_ENDS], "ended tracks"),
    RS_OPT_STR_("counts-channel", "NAME", T, ch[K_COUNTS], "counts"),
    RS_OPT_STR_("stats-channel", "NAME", T, ch[K_STATS], "statistics"),
    RS_OPT_STR_("crossings-channel", "NAME", T, ch[K_CROSSINGS], "crossing events ('none' = not shown)"),
    {.type = RS_OPT_FUNC, .name = "count-line", .arg = "\"NAME X1 Y1 X2 Y2\"", .off = offsetof(T, lines),
     .fn = rs_count_opt_line, .flags = RS_OPT_REPEAT, .help = "a counting line to draw (the daemon's)"},
    {.type = RS_OPT_FUNC, .name = "count-zone", .arg = "\"NAME X1 Y1 ...\"", .off = offsetof(T, zones), .fn = rs_count_opt_zone,
     .flags = RS_OPT_REPEAT, .help = "a counting zone to draw (the daemon's)"},
    RS_OPT_HEAD("http", "The page"),
    RS_OPT_STR_("listen", "ADDR:PORT", T, listen, "where the page is served (IPv4; 0.0.0.0 for every interface)"),
    RS_OPT_STR_("www", "DIR", T, www, "the page's files (index.html, app.js, style.css)"),
    RS_OPT_INT_("max-clients", "N", T, max_clients, 1, 256, "browsers (and other connections) at once"),
};
#undef T

static const rs_opts_spec_t spec = {
    .prog = "roadscan-web",
    .summary = "a live view of roadscand in the browser: tracks, counts, crossings and health",
    .synopsis = "[--listen ADDR:PORT] [--log FILE] [options]",
    .about = "Serves one page: a bird's-eye view of the site with the tracks (boxes, ids, classes, speeds, short "
             "trails), the counting lines and zones with their running counts by direction and class, the "
             "last crossings (each marked on its line where it happened, with its class, spot speed and lane), the "
             "daemon's health (frame rate, drops, packets missing, stage times and their p99) and plots of "
             "speeds and counts over the last minutes. Updates reach the browser as they arrive (Server-Sent "
             "Events). The page needs nothing from the network (docs/web.md).",
    .epilog = "Exit status: 0 stopped by a signal, 1 cannot listen or subscribe, 2 bad usage.",
    .opts = table,
    .n = (int)(sizeof table / sizeof table[0]),
};

static void make_config(void) {
  json_t *lines = json_array(), *zones = json_array();
  for (int i = 0; i < st.lines.n; i++) {
    const rs_count_line_t *l = &st.lines.line[i];
    json_array_append_new(lines, json_pack("{s:s, s:[f,f], s:[f,f]}", "name", l->name, "a_m", l->ax, l->ay, "b_m",
                                           l->bx, l->by));
  }
  for (int i = 0; i < st.zones.n; i++) {
    const rs_count_zone_t *z = &st.zones.zone[i];
    json_t *pts = json_array();
    for (int k = 0; k < z->n; k++) json_array_append_new(pts, json_pack("[f,f]", z->x[k], z->y[k]));
    json_array_append_new(zones, json_pack("{s:s, s:o}", "name", z->name, "corners_m", pts));
  }
  json_t *j = json_pack("{s:o, s:o, s:s}", "lines", lines, "zones", zones, "source", st.log ? "log" : "live");
  char *s = json_dumps(j, RS_JSON_DUMP_FLAGS);
  snprintf(config_json, sizeof config_json, "%s", s ? s : "{}");
  free(s);
  json_decref(j);
}

int main(int argc, char **argv) {
  const char *env = getenv("LCM_DEFAULT_URL");
  st = (settings_t){.url = env && env[0] ? env : RS_PUB_DEFAULT_URL,
                    .listen = "127.0.0.1:8086",
                    .www = RS_WEB_DIR,
                    .ch = {RS_PUB_DEFAULT_CHANNEL, RS_PUB_DEFAULT_TRACKS, RS_PUB_DEFAULT_TRACK_ENDS,
                           RS_PUB_DEFAULT_COUNTS, RS_PUB_DEFAULT_STATS, RS_PUB_DEFAULT_CROSSINGS},
                    .max_clients = 32};
  int first;
  const int start = rs_opts_start(&opts, &spec, &st, argc, argv, &first);
  if (start >= 0) return start;
  www = st.www;
  char host[64], tail, logurl[4200];
  unsigned port = 0;
  const char *colon = strrchr(st.listen, ':');
  struct sockaddr_in sa = {.sin_family = AF_INET};
  if (colon == NULL || (size_t)(colon - st.listen) >= sizeof host || sscanf(colon + 1, "%u%c", &port, &tail) != 1 ||
      port == 0 || port > 65535) {
    fprintf(stderr, "roadscan-web: --listen '%s' is not ADDR:PORT\n", st.listen);
    return 2;
  }
  memcpy(host, st.listen, (size_t)(colon - st.listen));
  host[colon - st.listen] = '\0';
  if (inet_pton(AF_INET, host, &sa.sin_addr) != 1) {
    fprintf(stderr, "roadscan-web: --listen '%s': '%s' is not an IPv4 address\n", st.listen, host);
    return 2;
  }
  sa.sin_port = htons((uint16_t)port);
  struct stat sb;
  char index[4200];
  snprintf(index, sizeof index, "%s/index.html", www);
  if (stat(index, &sb) != 0 && !rs_opts_given(&opts, "www")) { /* not installed: the source tree's, when built here */
    www = RS_WEB_SRC_DIR;
    snprintf(index, sizeof index, "%s/index.html", www);
  }
  if (stat(index, &sb) != 0) {
    fprintf(stderr, "roadscan-web: %s: the page is not there (--www DIR)\n", index);
    return 1;
  }
  make_config();
  const char *url = st.url;
  if (st.log) {
    if (access(st.log, R_OK) != 0) {
      fprintf(stderr, "roadscan-web: --log %s: cannot read\n", st.log);
      return 1;
    }
    snprintf(logurl, sizeof logurl, "file://%s?speed=1", st.log);
    url = logurl;
  }
  lcm_t *lcm = lcm_create(url);
  if (lcm == NULL) {
    fprintf(stderr, "roadscan-web: cannot open LCM URL '%s'\n", url);
    return 1;
  }
  for (int k = 0; k < K_KINDS; k++)
    if (st.ch[k] && st.ch[k][0] && strcmp(st.ch[k], "none") != 0)
      lcm_subscribe(lcm, st.ch[k], on_message, (void *)(intptr_t)k);
  struct MHD_Daemon *d = MHD_start_daemon(
      MHD_USE_THREAD_PER_CONNECTION | MHD_USE_INTERNAL_POLLING_THREAD | MHD_USE_ERROR_LOG, (uint16_t)port, NULL, NULL,
      on_request, NULL, MHD_OPTION_SOCK_ADDR, (struct sockaddr *)&sa, MHD_OPTION_CONNECTION_LIMIT,
      (unsigned)st.max_clients, MHD_OPTION_CONNECTION_TIMEOUT, (unsigned)30, MHD_OPTION_CONNECTION_MEMORY_LIMIT,
      (size_t)32768, MHD_OPTION_THREAD_STACK_SIZE, (size_t)(512 * 1024), MHD_OPTION_END);
  if (d == NULL) {
    fprintf(stderr, "roadscan-web: cannot listen on %s (in use, or not an address of this host)\n", st.listen);
    lcm_destroy(lcm);
    return 1;
  }
  fprintf(stderr, "roadscan-web: http://%s/ shows %s\n", st.listen, st.log ? st.log : url);
  struct sigaction sig;
  memset(&sig, 0, sizeof sig);
  sig.sa_handler = on_signal;
  sigaction(SIGINT, &sig, NULL);
  sigaction(SIGTERM, &sig, NULL);
  signal(SIGPIPE, SIG_IGN);
  bool open = true;
  while (!stop) {
    if (open) {
      if (lcm_handle_timeout(lcm, 200) < 0) {
        open = false; /* the end of a log: the page keeps what it showed */
        fprintf(stderr, "roadscan-web: the end of %s\n", st.log ? st.log : url);
      }
    } else {
      struct timespec t = {0, 200000000L};
      nanosleep(&t, NULL);
    }
  }
  atomic_store(&quitting, true);
  pthread_mutex_lock(&W.mu);
  pthread_cond_broadcast(&W.cv);
  pthread_mutex_unlock(&W.mu);
  MHD_stop_daemon(d);
  lcm_destroy(lcm);
  fprintf(stderr,
          "roadscan-web: %llu track lists, %llu object lists, %llu counts, %llu statistics, %llu track ends, %llu "
          "crossings; %llu malformed; %llu browsers served, %llu events skipped by slow ones\n",
          (unsigned long long)W.received[K_TRACKS], (unsigned long long)W.received[K_OBJECTS],
          (unsigned long long)W.received[K_COUNTS], (unsigned long long)W.received[K_STATS],
          (unsigned long long)W.received[K_TRACK_ENDS], (unsigned long long)W.received[K_CROSSINGS],
          (unsigned long long)W.malformed, (unsigned long long)W.served,
          (unsigned long long)W.skipped);
  for (int i = 0; i < RS_WEB_EVENTS; i++) free(W.ring[i].data);
  return 0;
}

/* roadscan-bridge - roadscand's LCM messages to an MQTT broker, as JSON.
 *
 * When sites outgrow one LAN, a broker carries the data. The bridge is a
 * separate process (nothing it does can block the daemon: the daemon only
 * sends UDP datagrams): it subscribes to the LCM channels (object lists,
 * track lists, track ends, counts, statistics), checks every message before
 * the generated decoder sees it (lcmcheck.h), turns it into JSON with one
 * library (jansson; the schema, with the unit of every field, is
 * docs/bridge-schema.json) and publishes it to
 *     PREFIX/SITE/SENSOR_ID/{objects,tracks,track_ends,counts,stats,crossings}
 * (libmosquitto, QoS 1 by default). A retained PREFIX/SITE/bridge/status says
 * "online", and the broker says "offline" (the will) when the bridge goes.
 *
 * Delivery: every message waits in a bounded queue (--buffer messages,
 * --buffer-mib bytes) until the broker acknowledges it (QoS 1/2; sent, for
 * QoS 0). While the broker is away the queue fills; when it is back the
 * bridge reconnects (1 s to 30 s back-off) and sends what waited, in order,
 * at least once (libmosquitto sends the ones in flight at the break again).
 * A message that finds the queue full pushes out the oldest one not yet sent:
 * counted as dropped, never silent; what was sent is never dropped.
 *
 * Threads: the main thread handles LCM, converts, queues and sends; libmosquitto's
 * network thread (mosquitto_loop_start) runs the connect, disconnect and
 * acknowledgement callbacks. One mutex guards the queue and the counters. */
#include "roadscan/output/json.h"
#include "roadscan/output/lcmcheck.h"
#include "roadscan/output/publish.h"
#include "roadscan/util/error.h"
#include "roadscan/util/opts.h"

#include <jansson.h>
#include <lcm/lcm.h>
#include <math.h>
#include <mosquitto.h>
#include <pthread.h>
#include <roadscan_counts_t.h>
#include <roadscan_crossing_t.h>
#include <roadscan_frame_stats_t.h>
#include <roadscan_object_list_t.h>
#include <roadscan_track_end_t.h>
#include <roadscan_track_list_t.h>
#include <signal.h>
#include <stdatomic.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>

#define RS_BRIDGE_QUEUE_MAX 1000000 /* --buffer's upper bound */
#define RS_BRIDGE_INFLIGHT 64       /* messages sent and not yet acknowledged */

enum { K_OBJECTS, K_TRACKS, K_TRACK_ENDS, K_COUNTS, K_STATS, K_CROSSINGS, K_KINDS };
static const char *const kind_name[K_KINDS] = {"objects", "tracks", "track_ends", "counts", "stats", "crossings"};
static const rs_lcm_type_t kind_type[K_KINDS] = {RS_LCM_OBJECT_LIST, RS_LCM_TRACK_LIST, RS_LCM_TRACK_END,
                                                 RS_LCM_COUNTS, RS_LCM_FRAME_STATS, RS_LCM_CROSSING};

typedef struct {
  char *topic, *payload; /* heap: the queue owns them */
  int len;
  int mid;               /* message id while in flight, 0 = waiting */
} entry_t;

static struct {
  pthread_mutex_t mu;
  entry_t *q; /* ring of cap entries */
  int cap, head, n;
  size_t bytes, max_bytes;
  int inflight;
  bool connected;
  uint64_t received[K_KINDS], malformed, queued, sent, acked, resent, dropped, dropped_bytes, connects, disconnects;
} B = {.mu = PTHREAD_MUTEX_INITIALIZER};

static struct mosquitto *mosq;
static int qos = 1;
static char prefix[256];
static volatile sig_atomic_t stop;
static _Atomic bool leaving; /* our own disconnect: nothing to say */
static void on_signal(int sig) {
  (void)sig;
  stop = 1;
}

/* ---- the queue (B.mu held) ---------------------------------------------- */

static entry_t *at(int i) { return &B.q[(B.head + i) % B.cap]; }

static void pop_front(void) {
  entry_t *e = at(0);
  B.bytes -= (size_t)e->len + strlen(e->topic);
  free(e->topic);
  free(e->payload);
  memset(e, 0, sizeof *e);
  B.head = (B.head + 1) % B.cap;
  B.n--;
}

/* removes entry i (0 = the oldest), keeping the order of the others */
static void remove_at(int i) {
  entry_t *e = at(i);
  B.bytes -= (size_t)e->len + strlen(e->topic);
  free(e->topic);
  free(e->payload);
  for (int k = i; k < B.n - 1; k++) *at(k) = *at(k + 1);
  memset(at(B.n - 1), 0, sizeof(entry_t));
  B.n--;
}

/* Room for need bytes: the acknowledged entries go (done), then the oldest waiting ones (counted
 * as dropped). An entry in flight stays: libmosquitto holds it and sends it again after a
 * reconnect until the broker acknowledges it. false: no room (all in flight). */
static bool make_room(size_t need) {
  for (int i = B.n - 1; i >= 0; i--)
    if (at(i)->mid == -1) remove_at(i);
  while (B.n == B.cap || B.bytes + need > B.max_bytes) {
    int i = 0;
    while (i < B.n && at(i)->mid != 0) i++;
    if (i == B.n) return false;
    B.dropped++;
    B.dropped_bytes += (uint64_t)at(i)->len;
    remove_at(i);
  }
  return true;
}

static void enqueue(char *topic, char *payload) {
  const int len = (int)strlen(payload);
  const size_t need = (size_t)len + strlen(topic);
  pthread_mutex_lock(&B.mu);
  if (need > B.max_bytes || !make_room(need)) { /* larger than the whole buffer, or all of it in flight */
    B.dropped++;
    B.dropped_bytes += (uint64_t)len;
    free(topic);
    free(payload);
  } else {
    entry_t *e = at(B.n);
    *e = (entry_t){.topic = topic, .payload = payload, .len = len};
    B.n++;
    B.bytes += need;
    B.queued++;
  }
  pthread_mutex_unlock(&B.mu);
}

/* sends what waits, in order, up to RS_BRIDGE_INFLIGHT unacknowledged (main thread) */
static void drain(void) {
  pthread_mutex_lock(&B.mu);
  for (int i = 0; i < B.n && B.connected && B.inflight < RS_BRIDGE_INFLIGHT; i++) {
    entry_t *e = at(i);
    if (e->mid) continue;
    int mid = 0;
    const int rc = mosquitto_publish(mosq, &mid, e->topic, e->len, e->payload, qos, false);
    if (rc != MOSQ_ERR_SUCCESS) break; /* not connected after all: the reconnect resends */
    B.sent++;
    if (qos == 0) { /* nothing will acknowledge it */
      pop_front();
      i--;
      continue;
    }
    e->mid = mid;
    B.inflight++;
  }
  pthread_mutex_unlock(&B.mu);
}

/* ---- libmosquitto's callbacks (its network thread) ------------------------ */

static void on_connect(struct mosquitto *m, void *user, int rc) {
  (void)user;
  if (rc != 0) {
    fprintf(stderr, "roadscan-bridge: the broker refused the connection: %s\n", mosquitto_connack_string(rc));
    return;
  }
  char topic[320];
  snprintf(topic, sizeof topic, "%s/bridge/status", prefix);
  mosquitto_publish(m, NULL, topic, 6, "online", 1, true);
  pthread_mutex_lock(&B.mu);
  B.connected = true;
  B.connects++;
  pthread_mutex_unlock(&B.mu);
  fprintf(stderr, "roadscan-bridge: connected to the broker\n");
}

static void on_disconnect(struct mosquitto *m, void *user, int rc) {
  (void)m;
  (void)user;
  pthread_mutex_lock(&B.mu);
  B.connected = false;
  B.disconnects++;
  /* sent and not acknowledged: libmosquitto sends them again after the reconnect (the
   * acknowledgement then comes to on_publish); the bridge does not send them twice */
  B.resent += (uint64_t)B.inflight;
  const int waiting = B.n;
  pthread_mutex_unlock(&B.mu);
  if (!atomic_load(&leaving)) fprintf(stderr, "roadscan-bridge: the broker went away (%s); %d messages wait, reconnecting\n",
                     rc ? "connection lost" : "disconnected", waiting);
}

static void on_publish(struct mosquitto *m, void *user, int mid) {
  (void)m;
  (void)user;
  pthread_mutex_lock(&B.mu);
  for (int i = 0; i < B.n; i++)
    if (at(i)->mid == mid) {
      at(i)->mid = -1; /* acknowledged */
      B.inflight--;
      B.acked++;
      break;
    }
  while (B.n > 0 && at(0)->mid == -1) pop_front(); /* the acknowledged head leaves, in order */
  pthread_mutex_unlock(&B.mu);
}

static bool utf8(const char *s) { return rs_json_text_ok(s); }

/* a sensor id as one topic level: MQTT's wildcards and separator replaced */
static void topic_level(const char *in, char *out, size_t n) {
  size_t j = 0;
  for (size_t i = 0; in[i] && j + 1 < n; i++) out[j++] = (in[i] == '/' || in[i] == '+' || in[i] == '#') ? '_' : in[i];
  out[j] = '\0';
  if (j == 0) snprintf(out, n, "_");
}

static void on_message(const lcm_recv_buf_t *rbuf, const char *channel, void *user) {
  const int kind = (int)(intptr_t)user;
  char why[RS_ERRMSG_SIZE] = "it does not decode";
  if (!rs_lcm_check(kind_type[kind], rbuf->data, (int)rbuf->data_size, why, sizeof why)) {
    pthread_mutex_lock(&B.mu);
    const bool first = B.malformed++ == 0;
    pthread_mutex_unlock(&B.mu);
    if (first)
      fprintf(stderr, "roadscan-bridge: %s: a message of %u bytes refused (%s); further ones are counted\n", channel,
              rbuf->data_size, why);
    return;
  }
  json_t *j = NULL;
  const char *sensor = "";
  union {
    roadscan_object_list_t o;
    roadscan_track_list_t t;
    roadscan_track_end_t e;
    roadscan_counts_t c;
    roadscan_frame_stats_t s;
    roadscan_crossing_t x;
  } m;
  memset(&m, 0, sizeof m);
  const void *d = rbuf->data;
  const int n = (int)rbuf->data_size;
  /* JSON strings are UTF-8: a message whose text is not is refused like a malformed one */
  bool text = true;
  switch (kind) {
  case K_OBJECTS:
    if (roadscan_object_list_t_decode(d, 0, n, &m.o) < 0) return;
    text = utf8(m.o.sensor_id) && utf8(m.o.sensor_model);
    j = text ? rs_json_objects(&m.o) : NULL;
    break;
  case K_TRACKS:
    if (roadscan_track_list_t_decode(d, 0, n, &m.t) < 0) return;
    text = utf8(m.t.sensor_id);
    j = text ? rs_json_tracks(&m.t) : NULL;
    break;
  case K_TRACK_ENDS:
    if (roadscan_track_end_t_decode(d, 0, n, &m.e) < 0) return;
    text = utf8(m.e.sensor_id);
    j = text ? rs_json_track_end(&m.e) : NULL;
    break;
  case K_COUNTS:
    if (roadscan_counts_t_decode(d, 0, n, &m.c) < 0) return;
    text = utf8(m.c.sensor_id);
    for (int i = 0; i < m.c.num_lines && text; i++) text = utf8(m.c.lines[i].name);
    for (int i = 0; i < m.c.num_zones && text; i++) text = utf8(m.c.zones[i].name);
    j = text ? rs_json_counts(&m.c) : NULL;
    break;
  case K_CROSSINGS:
    if (roadscan_crossing_t_decode(d, 0, n, &m.x) < 0) return;
    text = utf8(m.x.sensor_id) && utf8(m.x.line);
    j = text ? rs_json_crossing(&m.x) : NULL;
    break;
  default:
    if (roadscan_frame_stats_t_decode(d, 0, n, &m.s) < 0) return;
    text = utf8(m.s.sensor_id);
    for (int i = 0; i < m.s.num_errors && text; i++) text = utf8(m.s.error_kinds[i]);
    j = text ? rs_json_stats(&m.s) : NULL;
    break;
  }
  sensor = j ? json_string_value(json_object_get(j, "sensor_id")) : NULL;
  char level[160], topic[512];
  topic_level(sensor ? sensor : "", level, sizeof level);
  snprintf(topic, sizeof topic, "%s/%s/%s", prefix, level, kind_name[kind]);
  char *payload = j && sensor ? json_dumps(j, RS_JSON_DUMP_FLAGS) : NULL;
  json_decref(j);
  switch (kind) {
  case K_OBJECTS: roadscan_object_list_t_decode_cleanup(&m.o); break;
  case K_TRACKS: roadscan_track_list_t_decode_cleanup(&m.t); break;
  case K_TRACK_ENDS: roadscan_track_end_t_decode_cleanup(&m.e); break;
  case K_COUNTS: roadscan_counts_t_decode_cleanup(&m.c); break;
  case K_CROSSINGS: roadscan_crossing_t_decode_cleanup(&m.x); break;
  default: roadscan_frame_stats_t_decode_cleanup(&m.s); break;
  }
  char *t = payload ? strdup(topic) : NULL;
  if (payload == NULL || t == NULL) {
    free(payload);
    free(t);
    pthread_mutex_lock(&B.mu);
    const bool first = B.malformed++ == 0;
    pthread_mutex_unlock(&B.mu);
    if (first) fprintf(stderr, "roadscan-bridge: %s: a message with text that is not UTF-8 refused\n", channel);
    return;
  }
  pthread_mutex_lock(&B.mu);
  B.received[kind]++;
  pthread_mutex_unlock(&B.mu);
  enqueue(t, payload);
}

/* ---- options -------------------------------------------------------------- */

typedef struct {
  const char *url, *broker, *site, *prefix, *client_id;
  const char *ch[K_KINDS];
  int qos, buffer, buffer_mib, keepalive;
} settings_t;
static settings_t st;
static rs_opts_t opts;

#define T settings_t
static const rs_opt_t table[] = {
    RS_OPT_HEAD("lcm", "LCM: what the daemon publishes"),
    {.type = RS_OPT_STR, .name = "lcm-url", .arg = "URL", .off = offsetof(T, url),
     .def = "$LCM_DEFAULT_URL, else " RS_PUB_DEFAULT_URL, .help = "LCM provider (file://LOG?speed=1 replays a log)"},
    RS_OPT_STR_("channel", "NAME", T, ch[K_OBJECTS], "object lists ('none' = not bridged)"),
    RS_OPT_STR_("tracks-channel", "NAME", T, ch[K_TRACKS], "track lists ('none' = not bridged)"),
    RS_OPT_STR_("track-ends-channel", "NAME", T, ch[K_TRACK_ENDS], "ended tracks ('none' = not bridged)"),
    RS_OPT_STR_("counts-channel", "NAME", T, ch[K_COUNTS], "counts ('none' = not bridged)"),
    RS_OPT_STR_("stats-channel", "NAME", T, ch[K_STATS], "statistics ('none' = not bridged)"),
    RS_OPT_STR_("crossings-channel", "NAME", T, ch[K_CROSSINGS], "crossing events ('none' = not bridged)"),
    RS_OPT_HEAD("mqtt", "MQTT: the broker"),
    RS_OPT_STR_("broker", "HOST:PORT", T, broker, "the broker"),
    RS_OPT_STR_("site", "NAME", T, site, "the site: topics PREFIX/SITE/SENSOR_ID/KIND"),
    RS_OPT_STR_("topic-prefix", "PREFIX", T, prefix, "the first level of every topic"),
    RS_OPT_STR_("client-id", "ID", T, client_id, "the MQTT client id"),
    RS_OPT_INT_("qos", "N", T, qos, 0, 2, "MQTT quality of service (1: at least once)"),
    RS_OPT_INT_("keepalive", "S", T, keepalive, 5, 3600, "seconds between keep-alive pings"),
    RS_OPT_INT_("buffer", "N", T, buffer, 1, RS_BRIDGE_QUEUE_MAX,
                "messages kept until the broker acknowledges them (the oldest go first when it is full, counted)"),
    RS_OPT_INT_("buffer-mib", "M", T, buffer_mib, 1, 4096, "and at most M MiB of them"),
};
#undef T

static const rs_opts_spec_t spec = {
    .prog = "roadscan-bridge",
    .summary = "roadscand's object lists, tracks, counts and statistics to an MQTT broker, as JSON",
    .synopsis = "[--broker HOST:PORT] [--site NAME] [options]",
    .about = "Subscribes to the daemon's LCM channels and publishes every message as JSON (docs/bridge-schema.json, "
             "a unit for every field) to PREFIX/SITE/SENSOR_ID/{objects,tracks,track_ends,counts,stats,crossings}, "
             "with a retained PREFIX/SITE/bridge/status (online, or offline: the will). Messages wait in a bounded buffer "
             "until the broker acknowledges them, across broker restarts (docs/operations.md). At the end it prints "
             "what it received, sent, resent and dropped.",
    .epilog = "Exit status: 0 stopped by a signal or the end of a log, 1 cannot subscribe or connect, 2 bad usage.",
    .opts = table,
    .n = (int)(sizeof table / sizeof table[0]),
};

static double mono_s(void) {
  struct timespec t;
  clock_gettime(CLOCK_MONOTONIC, &t);
  return (double)t.tv_sec + (double)t.tv_nsec * 1e-9;
}

int main(int argc, char **argv) {
  const char *env = getenv("LCM_DEFAULT_URL");
  st = (settings_t){.url = env && env[0] ? env : RS_PUB_DEFAULT_URL,
                    .broker = "127.0.0.1:1883",
                    .site = "site",
                    .prefix = "roadscan",
                    .client_id = NULL,
                    .ch = {RS_PUB_DEFAULT_CHANNEL, RS_PUB_DEFAULT_TRACKS, RS_PUB_DEFAULT_TRACK_ENDS,
                           RS_PUB_DEFAULT_COUNTS, RS_PUB_DEFAULT_STATS, RS_PUB_DEFAULT_CROSSINGS},
                    .qos = 1,
                    .buffer = 10000,
                    .buffer_mib = 64,
                    .keepalive = 30};
  int first;
  const int start = rs_opts_start(&opts, &spec, &st, argc, argv, &first);
  if (start >= 0) return start;
  char host[256];
  unsigned port = 0;
  char tail;
  const char *colon = strrchr(st.broker, ':');
  if (colon == NULL || colon == st.broker || (size_t)(colon - st.broker) >= sizeof host ||
      sscanf(colon + 1, "%u%c", &port, &tail) != 1 || port == 0 || port > 65535) {
    fprintf(stderr, "roadscan-bridge: --broker '%s' is not HOST:PORT\n", st.broker);
    return 2;
  }
  memcpy(host, st.broker, (size_t)(colon - st.broker));
  host[colon - st.broker] = '\0';
  for (const char *p = st.site; *p; p++)
    if (*p == '/' || *p == '+' || *p == '#') {
      fprintf(stderr, "roadscan-bridge: --site '%s': no '/', '+' or '#' (it is one topic level)\n", st.site);
      return 2;
    }
  snprintf(prefix, sizeof prefix, "%s/%s", st.prefix, st.site);
  qos = st.qos;
  B.cap = st.buffer;
  B.max_bytes = (size_t)st.buffer_mib << 20;
  B.q = calloc((size_t)B.cap, sizeof *B.q);
  if (B.q == NULL) {
    fprintf(stderr, "roadscan-bridge: out of memory for a buffer of %d messages\n", B.cap);
    return 1;
  }
  mosquitto_lib_init();
  char cid[128];
  snprintf(cid, sizeof cid, "%s", st.client_id ? st.client_id : "");
  if (!cid[0]) snprintf(cid, sizeof cid, "roadscan-bridge-%s-%ld", st.site, (long)getpid());
  mosq = mosquitto_new(cid, true, NULL);
  if (mosq == NULL) {
    fprintf(stderr, "roadscan-bridge: cannot make an MQTT client\n");
    return 1;
  }
  char status[320];
  snprintf(status, sizeof status, "%s/bridge/status", prefix);
  mosquitto_will_set(mosq, status, 7, "offline", 1, true);
  mosquitto_connect_callback_set(mosq, on_connect);
  mosquitto_disconnect_callback_set(mosq, on_disconnect);
  mosquitto_publish_callback_set(mosq, on_publish);
  mosquitto_reconnect_delay_set(mosq, 1, 30, true);
  mosquitto_max_inflight_messages_set(mosq, RS_BRIDGE_INFLIGHT);
  lcm_t *lcm = lcm_create(st.url);
  if (lcm == NULL) {
    fprintf(stderr, "roadscan-bridge: cannot open LCM URL '%s'\n", st.url);
    return 1;
  }
  for (int k = 0; k < K_KINDS; k++)
    if (st.ch[k] && st.ch[k][0] && strcmp(st.ch[k], "none") != 0)
      lcm_subscribe(lcm, st.ch[k], on_message, (void *)(intptr_t)k);
  /* the first connection is tried at once; the network thread retries it and every later one */
  const int crc = mosquitto_connect_async(mosq, host, (int)port, st.keepalive);
  if (crc != MOSQ_ERR_SUCCESS && crc != MOSQ_ERR_ERRNO)
    fprintf(stderr, "roadscan-bridge: %s:%u: %s; retrying\n", host, port, mosquitto_strerror(crc));
  if (mosquitto_loop_start(mosq) != MOSQ_ERR_SUCCESS) {
    fprintf(stderr, "roadscan-bridge: cannot start the MQTT thread\n");
    return 1;
  }
  fprintf(stderr, "roadscan-bridge: %s -> mqtt://%s:%u/%s/SENSOR_ID/KIND (QoS %d, buffer %d messages, %d MiB)\n",
          st.url, host, port, prefix, qos, B.cap, st.buffer_mib);
  struct sigaction sig;
  memset(&sig, 0, sizeof sig);
  sig.sa_handler = on_signal;
  sigaction(SIGINT, &sig, NULL);
  sigaction(SIGTERM, &sig, NULL);
  bool lcm_open = true;
  while (!stop) {
    if (lcm_open) {
      if (lcm_handle_timeout(lcm, 50) < 0) lcm_open = false; /* the end of a log: deliver what waits, then stop */
    } else {
      struct timespec t = {0, 50000000L};
      nanosleep(&t, NULL);
      pthread_mutex_lock(&B.mu);
      const bool empty = B.n == 0;
      pthread_mutex_unlock(&B.mu);
      if (empty) break;
    }
    drain();
  }
  /* a signal: what is in flight gets a few seconds to be acknowledged */
  for (double end = mono_s() + 5; mono_s() < end;) {
    drain();
    pthread_mutex_lock(&B.mu);
    const bool empty = B.n == 0 || !B.connected;
    pthread_mutex_unlock(&B.mu);
    if (empty) break;
    struct timespec t = {0, 20000000L};
    nanosleep(&t, NULL);
  }
  atomic_store(&leaving, true);
  mosquitto_publish(mosq, NULL, status, 7, "offline", 1, true);
  mosquitto_disconnect(mosq);
  mosquitto_loop_stop(mosq, false);
  pthread_mutex_lock(&B.mu);
  fprintf(stderr,
          "roadscan-bridge: received %llu object lists, %llu track lists, %llu track ends, %llu counts, %llu "
          "statistics, %llu crossings, %llu malformed; sent %llu, acknowledged %llu, %llu in flight at %llu "
          "disconnects, dropped %llu (buffer full), %d still waiting\n",
          (unsigned long long)B.received[K_OBJECTS], (unsigned long long)B.received[K_TRACKS],
          (unsigned long long)B.received[K_TRACK_ENDS], (unsigned long long)B.received[K_COUNTS],
          (unsigned long long)B.received[K_STATS], (unsigned long long)B.received[K_CROSSINGS],
          (unsigned long long)B.malformed, (unsigned long long)B.sent,
          (unsigned long long)B.acked, (unsigned long long)B.resent, (unsigned long long)B.disconnects,
          (unsigned long long)B.dropped, B.n);
  while (B.n > 0) pop_front();
  pthread_mutex_unlock(&B.mu);
  free(B.q);
  mosquitto_destroy(mosq);
  mosquitto_lib_cleanup();
  lcm_destroy(lcm);
  return 0;
}

/* roadscan-listen - subscribes to roadscand's object lists and prints them.
 *
 * One thread: lcm_handle_timeout in a loop; the handler checks the message
 * (fingerprint, object count against its size) before decoding it, prints a
 * table or one JSON line, and tracks the rate and the frame numbers missed
 * (gaps) per sensor id. Reads a live URL or an LCM log file (--log). */
#include "roadscan/util/opts.h"
#include "roadscan/util/error.h"
#include "roadscan/output/json.h"
#include "roadscan/output/lcmcheck.h"
#include "roadscan/output/publish.h"

#include <inttypes.h>
#include <lcm/lcm.h>
#include <math.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>

#define MAX_SENSORS 16

static volatile sig_atomic_t stop;
static void on_signal(int sig) {
  (void)sig;
  stop = 1;
}

static struct {
  bool json, stats, quiet;
  long count, delay_ms;
  uint64_t lists, stats_msgs, malformed, gaps, objects, track_lists, track_ends, counts, crossings;
  double t0, t_last;
  struct {
    char id[RS_PUB_NAME_MAX];
    int64_t last_seq;
  } sensors[MAX_SENSORS];
  int nsensors;
} L;

static double now_s(void) {
  struct timespec ts;
  clock_gettime(CLOCK_MONOTONIC, &ts);
  return (double)ts.tv_sec + (double)ts.tv_nsec * 1e-9;
}

/* One JSON document per line (src/output/json.c: the schema of docs/bridge-schema.json, also the
 * bridge's); a message whose text is not UTF-8 is said and counted. */
static void emit(json_t *j, const char *channel) {
  char *text = j ? json_dumps(j, RS_JSON_DUMP_FLAGS) : NULL;
  json_decref(j);
  if (text == NULL) {
    L.malformed++;
    fprintf(stderr, "roadscan-listen: %s: a message whose text is not UTF-8; not printed as JSON\n", channel);
    return;
  }
  puts(text);
  free(text);
}

/* Frames missed since the previous list of the same sensor. */
static int64_t gap_of(const char *id, int64_t seq) {
  for (int i = 0; i < L.nsensors; i++)
    if (strcmp(L.sensors[i].id, id) == 0) {
      int64_t g = seq > L.sensors[i].last_seq + 1 ? seq - L.sensors[i].last_seq - 1 : 0;
      L.sensors[i].last_seq = seq;
      return g;
    }
  if (L.nsensors < MAX_SENSORS) {
    snprintf(L.sensors[L.nsensors].id, sizeof L.sensors[0].id, "%s", id);
    L.sensors[L.nsensors++].last_seq = seq;
  }
  return 0;
}

static void print_table(const roadscan_object_list_t *m, int64_t gap) {
  double rate = L.lists > 1 && L.t_last > L.t0 ? (double)(L.lists - 1) / (L.t_last - L.t0) : 0.0;
  printf("%s frame %" PRId64 " (%s)  t=%.3f  %d objects%s  %d/%d columns, %d packets missing%s  rate %.1f/s  gaps %" PRIu64
         "%s\n",
         m->sensor_id, m->frame_seq, m->sensor_model, (double)m->t_first * 1e-6, m->num_objects,
         m->truncated ? " (TRUNCATED)" : "", m->columns_covered, m->columns, m->packets_missing,
         m->partial ? ", partial" : "", rate, L.gaps, gap ? "  <- frames missed" : "");
  if (m->num_objects == 0) return;
  const bool site = m->site_valid;
  printf("  %4s %6s %8s %8s %7s %6s %5s %7s %6s %6s %7s %15s%s\n", "id", "points", "x", "y", "z", "length", "width",
         "heading", "z_min", "z_max", "range", "azimuth", site ? "  (site frame)" : "  (sensor frame)");
  for (int i = 0; i < m->num_objects; i++) {
    const roadscan_object_t *o = &m->objects[i];
    const float *c = site ? o->site_centroid : o->centroid, *lo = site ? o->site_box_min : o->box_min,
                *hi = site ? o->site_box_max : o->box_max;
    float len = site ? o->site_obb_length : o->obb_length, wid = site ? o->site_obb_width : o->obb_width;
    float head = site ? o->site_obb_heading : o->obb_heading;
    printf("  %4d %6d %8.2f %8.2f %7.2f %6.2f %5.2f %7.1f %6.2f %6.2f %7.2f %7.2f-%-7.2f\n", o->id, o->points,
           (double)c[0], (double)c[1], (double)c[2], (double)len, (double)wid, (double)head * 180.0 / M_PI,
           (double)lo[2], (double)hi[2], (double)o->range_min, (double)o->azimuth_start, (double)o->azimuth_end);
  }
}

static void on_list(const lcm_recv_buf_t *rbuf, const char *channel, void *user) {
  (void)channel;
  (void)user;
  roadscan_object_list_t m;
  memset(&m, 0, sizeof m);
  char why[RS_ERRMSG_SIZE] = "";
  bool ok = rs_lcm_check(RS_LCM_OBJECT_LIST, rbuf->data, (int)rbuf->data_size, why, sizeof why);
  if (ok && roadscan_object_list_t_decode(rbuf->data, 0, (int)rbuf->data_size, &m) < 0) {
    /* the generated decoder returns what it allocated before failing: free it */
    if (m.objects == NULL) m.num_objects = 0;
    roadscan_object_list_t_decode_cleanup(&m);
    ok = false;
  }
  if (!ok) {
    L.malformed++;
    fprintf(stderr, "roadscan-listen: %s: a message of %u bytes is not a roadscan object list (%s); ignored\n", channel,
            rbuf->data_size, why[0] ? why : "it does not decode");
    return;
  }
  double t = now_s();
  if (L.lists == 0) L.t0 = t;
  L.t_last = t;
  L.lists++;
  L.objects += (uint64_t)m.num_objects;
  int64_t gap = gap_of(m.sensor_id, m.frame_seq);
  L.gaps += (uint64_t)gap;
  if (!L.quiet) {
    if (L.json)
      emit(rs_json_text_ok(m.sensor_id) && rs_json_text_ok(m.sensor_model) ? rs_json_objects(&m) : NULL, channel);
    else
      print_table(&m, gap);
    fflush(stdout);
  }
  roadscan_object_list_t_decode_cleanup(&m);
  if (L.delay_ms > 0) {
    struct timespec d = {L.delay_ms / 1000, (L.delay_ms % 1000) * 1000000L};
    nanosleep(&d, NULL);
  }
  if (L.count > 0 && (long)L.lists >= L.count) stop = 1;
}

static void on_stats(const lcm_recv_buf_t *rbuf, const char *channel, void *user) {
  (void)user;
  roadscan_frame_stats_t s;
  memset(&s, 0, sizeof s);
  char why[RS_ERRMSG_SIZE] = "it does not decode";
  const bool checked = rs_lcm_check(RS_LCM_FRAME_STATS, rbuf->data, (int)rbuf->data_size, why, sizeof why);
  if (!checked || roadscan_frame_stats_t_decode(rbuf->data, 0, (int)rbuf->data_size, &s) < 0) {
    if (checked) roadscan_frame_stats_t_decode_cleanup(&s); /* what the decoder allocated before failing */
    L.malformed++;
    fprintf(stderr, "roadscan-listen: %s: a message of %u bytes is not roadscan frame statistics (%s); ignored\n",
            channel, rbuf->data_size, why);
    return;
  }
  L.stats_msgs++;
  if (!L.quiet) {
    bool text = rs_json_text_ok(s.sensor_id);
    for (int i = 0; i < s.num_errors && text; i++) text = rs_json_text_ok(s.error_kinds[i]);
    if (L.json) {
      emit(text ? rs_json_stats(&s) : NULL, channel);
    } else
      printf("%s frame %" PRId64 " stats: processing %.2f ms (background %.2f, cluster %.2f, objects %.2f, publish "
             "%.2f) latency %.2f ms; %d foreground, %d clusters; %" PRId64 " dropped, %" PRId64 " over budget; %" PRId64
             " packets dropped by the kernel\n",
             s.sensor_id, s.frame_seq, s.processing_us * 1e-3, s.background_us * 1e-3, s.cluster_us * 1e-3,
             s.objects_us * 1e-3, s.publish_us * 1e-3, s.latency_us * 1e-3, s.foreground, s.clusters,
             s.frames_dropped, s.deadline_overruns, s.kernel_dropped);
    fflush(stdout);
  }
  roadscan_frame_stats_t_decode_cleanup(&s);
}

/* track lists, track ends and counts (--tracks, --counts): checked, decoded, printed */
static void on_tracks(const lcm_recv_buf_t *rbuf, const char *channel, void *user) {
  (void)user;
  char why[RS_ERRMSG_SIZE] = "it does not decode";
  const bool ends = strstr(channel, "END") != NULL;
  const rs_lcm_type_t type = ends ? RS_LCM_TRACK_END : RS_LCM_TRACK_LIST;
  if (!rs_lcm_check(type, rbuf->data, (int)rbuf->data_size, why, sizeof why)) {
    L.malformed++;
    fprintf(stderr, "roadscan-listen: %s: a message of %u bytes is not a roadscan %s (%s); ignored\n", channel,
            rbuf->data_size, ends ? "track end" : "track list", why);
    return;
  }
  if (ends) {
    roadscan_track_end_t e;
    if (roadscan_track_end_t_decode(rbuf->data, 0, (int)rbuf->data_size, &e) < 0) return;
    L.track_ends++;
    if (!L.quiet) {
      if (L.json)
        emit(rs_json_text_ok(e.sensor_id) ? rs_json_track_end(&e) : NULL, channel);
      else
        printf("%s track %d ended: class %d, %.1f s, %.1f m, mean %.1f m/s, max %.1f m/s\n", e.sensor_id, e.id,
               e.class_id, (double)e.duration, (double)e.distance, (double)e.mean_speed, (double)e.max_speed);
      fflush(stdout);
    }
    roadscan_track_end_t_decode_cleanup(&e);
    return;
  }
  roadscan_track_list_t m;
  if (roadscan_track_list_t_decode(rbuf->data, 0, (int)rbuf->data_size, &m) < 0) return;
  L.track_lists++;
  if (!L.quiet) {
    if (L.json) {
      emit(rs_json_text_ok(m.sensor_id) ? rs_json_tracks(&m) : NULL, channel);
    } else {
      printf("%s frame %" PRId64 ": %d tracks\n", m.sensor_id, m.frame_seq, m.num_tracks);
      for (int i = 0; i < m.num_tracks; i++) {
        const roadscan_track_t *t = &m.tracks[i];
        if (t->state == 0) continue; /* tentative */
        printf("  track %5d %-9s class %d at (%8.2f, %8.2f) %5.1f m/s heading %6.1f deg\n", t->id,
               t->state == 1 ? "confirmed" : "coasting", t->class_id, (double)t->position[0], (double)t->position[1],
               (double)t->speed, (double)t->heading * 180.0 / M_PI);
      }
    }
    fflush(stdout);
  }
  roadscan_track_list_t_decode_cleanup(&m);
}

/* crossing events (--crossings): checked, decoded, printed */
static void on_crossing(const lcm_recv_buf_t *rbuf, const char *channel, void *user) {
  (void)user;
  char why[RS_ERRMSG_SIZE] = "it does not decode";
  if (!rs_lcm_check(RS_LCM_CROSSING, rbuf->data, (int)rbuf->data_size, why, sizeof why)) {
    L.malformed++;
    fprintf(stderr, "roadscan-listen: %s: a message of %u bytes is not a roadscan crossing (%s); ignored\n", channel,
            rbuf->data_size, why);
    return;
  }
  roadscan_crossing_t x;
  if (roadscan_crossing_t_decode(rbuf->data, 0, (int)rbuf->data_size, &x) < 0) return;
  L.crossings++;
  if (!L.quiet) {
    if (L.json)
      emit(rs_json_text_ok(x.sensor_id) && rs_json_text_ok(x.line) ? rs_json_crossing(&x) : NULL, channel);
    else
      printf("%s crossing %.3f s: line %s %s at %.1f m, track %d class %d, %.2f m/s (how %d)\n", x.sensor_id,
             (double)x.t_cross * 1e-6, x.line, x.direction > 0 ? "forward" : "backward", (double)x.at, x.track_id,
             x.class_id, (double)x.speed, x.how);
    fflush(stdout);
  }
  roadscan_crossing_t_decode_cleanup(&x);
}

static void on_counts(const lcm_recv_buf_t *rbuf, const char *channel, void *user) {
  (void)user;
  char why[RS_ERRMSG_SIZE] = "it does not decode";
  if (!rs_lcm_check(RS_LCM_COUNTS, rbuf->data, (int)rbuf->data_size, why, sizeof why)) {
    L.malformed++;
    fprintf(stderr, "roadscan-listen: %s: a message of %u bytes is not roadscan counts (%s); ignored\n", channel,
            rbuf->data_size, why);
    return;
  }
  roadscan_counts_t c;
  if (roadscan_counts_t_decode(rbuf->data, 0, (int)rbuf->data_size, &c) < 0) return;
  L.counts++;
  if (!L.quiet && L.json) {
    bool text = rs_json_text_ok(c.sensor_id);
    for (int l = 0; l < c.num_lines && text; l++) text = rs_json_text_ok(c.lines[l].name);
    for (int z = 0; z < c.num_zones && text; z++) text = rs_json_text_ok(c.zones[z].name);
    emit(text ? rs_json_counts(&c) : NULL, channel);
    fflush(stdout);
  } else if (!L.quiet) {
    for (int l = 0; l < c.num_lines; l++) {
      int fwd = 0, bwd = 0;
      for (int k = 0; k < 6; k++) {
        fwd += c.lines[l].forward[k];
        bwd += c.lines[l].backward[k];
      }
      printf("%s counts %.1f-%.1f s: line %s forward %d, backward %d\n", c.sensor_id, (double)c.t_start * 1e-6,
             (double)c.t_end * 1e-6, c.lines[l].name, fwd, bwd);
    }
    for (int z = 0; z < c.num_zones; z++) {
      int in = 0, out = 0;
      for (int k = 0; k < 6; k++) {
        in += c.zones[z].entered[k];
        out += c.zones[z].exited[k];
      }
      printf("%s counts %.1f-%.1f s: zone %s entered %d, exited %d, inside %d (at most %d)\n", c.sensor_id,
             (double)c.t_start * 1e-6, (double)c.t_end * 1e-6, c.zones[z].name, in, out, c.zones[z].occupancy,
             c.zones[z].occupancy_max);
    }
    fflush(stdout);
  }
  roadscan_counts_t_decode_cleanup(&c);
}

/* Everything the options set. */
typedef struct {
  const char *url, *channel, *stats, *log, *tracks, *counts, *crossings;
  double timeout;
  int count, delay_ms;
  bool json, quiet;
} settings_t;
static settings_t st;
static rs_opts_t opts;

#define T settings_t
static const rs_opt_t table[] = {
    {.type = RS_OPT_STR, .name = "url", .arg = "URL", .off = offsetof(T, url), .help = "LCM provider"},
    RS_OPT_STR_("log", "FILE", T, log, "read an LCM log (lcm-logger) instead, as fast as possible"),
    RS_OPT_STR_("channel", "NAME", T, channel, "object lists"),
    {.type = RS_OPT_STR, .name = "stats", .arg = "NAME", .off = offsetof(T, stats), .implied = RS_PUB_DEFAULT_STATS,
     .def = "off; NAME: " RS_PUB_DEFAULT_STATS, .help = "also print the frame statistics"},
    {.type = RS_OPT_STR, .name = "tracks", .arg = "NAME", .off = offsetof(T, tracks),
     .implied = RS_PUB_DEFAULT_TRACKS, .def = "off; NAME: " RS_PUB_DEFAULT_TRACKS,
     .help = "also print the track lists and the ended tracks (on NAME_ENDS, " RS_PUB_DEFAULT_TRACK_ENDS
             " for the default NAME)"},
    {.type = RS_OPT_STR, .name = "counts", .arg = "NAME", .off = offsetof(T, counts),
     .implied = RS_PUB_DEFAULT_COUNTS, .def = "off; NAME: " RS_PUB_DEFAULT_COUNTS,
     .help = "also print the counts per interval"},
    {.type = RS_OPT_STR, .name = "crossings", .arg = "NAME", .off = offsetof(T, crossings),
     .implied = RS_PUB_DEFAULT_CROSSINGS, .def = "off; NAME: " RS_PUB_DEFAULT_CROSSINGS,
     .help = "also print each crossing counted (its spot speed, class, track)"},
    RS_OPT_FLAG_("json", T, json, "one JSON object per line and message"),
    {.type = RS_OPT_INT, .name = "count", .arg = "N", .off = offsetof(T, count), .lo = 1, .hi = 1000000000,
     .def = "no limit", .help = "exit after N object lists"},
    {.type = RS_OPT_DOUBLE, .name = "timeout", .arg = "S", .off = offsetof(T, timeout), .lo = 0.01, .hi = 1e6,
     .def = "wait", .help = "exit after S seconds with no message"},
    RS_OPT_INT_("delay-ms", "MS", T, delay_ms, 0, 60000,
                "sleep after each list (to try a consumer that falls behind)"),
    RS_OPT_FLAG_("quiet", T, quiet, "print only the final counts"),
};
#undef T

static const rs_opts_spec_t spec = {
    .prog = "roadscan-listen",
    .summary = "print the object lists, track lists, counts and statistics roadscand publishes over LCM",
    .synopsis = "[options]",
    .about = "Every message is checked before it is decoded (a hostile or truncated one is counted as malformed "
             "and skipped). At the end (signal, --count, --timeout, end of the log) it prints on stderr: lists N, "
             "objects N, gaps N (frames missed), stats N, malformed N, rate R/s, and the track lists, track ends "
             "and counts received.",
    .epilog = "Exit status: 0, 1 when no list was received, 2 bad usage.",
    .opts = table,
    .n = (int)(sizeof table / sizeof table[0]),
};

int main(int argc, char **argv) {
  st = (settings_t){.url = RS_PUB_DEFAULT_URL, .channel = RS_PUB_DEFAULT_CHANNEL};
  char err[RS_ERRMSG_SIZE], logurl[4200];
  int first;
  const int start = rs_opts_start(&opts, &spec, &st, argc, argv, &first);
  if (start >= 0) return start;
  const char *url = st.url, *channel = st.channel, *stats = st.stats, *log = st.log, *tracks = st.tracks,
             *counts = st.counts;
  const double timeout = st.timeout;
  L.json = st.json;
  L.quiet = st.quiet;
  L.count = st.count;
  L.delay_ms = st.delay_ms;
  if (log) {
    if (access(log, R_OK) != 0) {
      snprintf(err, sizeof err, "--log %s: cannot read", log);
      goto bad;
    }
    snprintf(logurl, sizeof logurl, "file://%s?speed=0", log);
    url = logurl;
  }
  lcm_t *lcm = lcm_create(url);
  if (lcm == NULL) {
    fprintf(stderr, "roadscan-listen: cannot open LCM URL '%s'%s\n", url,
            strncmp(url, "udpm://", 7) == 0 ? " (is there a multicast route? e.g. ip route add 224.0.0.0/4 dev lo)" : "");
    return 1;
  }
  lcm_subscription_t *sub = lcm_subscribe(lcm, channel, on_list, NULL);
  lcm_subscription_t *ssub = stats ? lcm_subscribe(lcm, stats, on_stats, NULL) : NULL;
  char ends_channel[256];
  snprintf(ends_channel, sizeof ends_channel, "%s", tracks && strcmp(tracks, RS_PUB_DEFAULT_TRACKS) != 0 ? tracks : "");
  if (ends_channel[0]) strncat(ends_channel, "_ENDS", sizeof ends_channel - strlen(ends_channel) - 1);
  lcm_subscription_t *tsub = tracks ? lcm_subscribe(lcm, tracks, on_tracks, NULL) : NULL;
  lcm_subscription_t *esub =
      tracks ? lcm_subscribe(lcm, ends_channel[0] ? ends_channel : RS_PUB_DEFAULT_TRACK_ENDS, on_tracks, NULL) : NULL;
  lcm_subscription_t *csub = counts ? lcm_subscribe(lcm, counts, on_counts, NULL) : NULL;
  lcm_subscription_t *xsub = st.crossings ? lcm_subscribe(lcm, st.crossings, on_crossing, NULL) : NULL;
  /* subscribed: from here on nothing published is missed (scripts wait for this line
   * before they start a publisher) */
  if (!log && !L.quiet) {
    fprintf(stderr, "roadscan-listen: listening on %s\n", url);
    fflush(stderr);
  }
  struct sigaction sa;
  memset(&sa, 0, sizeof sa);
  sa.sa_handler = on_signal;
  sigaction(SIGINT, &sa, NULL);
  sigaction(SIGTERM, &sa, NULL);
  double idle_since = now_s();
  while (!stop) {
    int rc = lcm_handle_timeout(lcm, 100);
    if (rc < 0) break; /* end of a log, or an error */
    if (rc > 0) {
      idle_since = now_s();
    } else if (timeout > 0 && now_s() - idle_since >= timeout) {
      break;
    }
  }
  lcm_unsubscribe(lcm, sub);
  if (ssub) lcm_unsubscribe(lcm, ssub);
  if (tsub) lcm_unsubscribe(lcm, tsub);
  if (esub) lcm_unsubscribe(lcm, esub);
  if (csub) lcm_unsubscribe(lcm, csub);
  if (xsub) lcm_unsubscribe(lcm, xsub);
  lcm_destroy(lcm);
  double rate = L.lists > 1 && L.t_last > L.t0 ? (double)(L.lists - 1) / (L.t_last - L.t0) : 0.0;
  fprintf(stderr,
          "roadscan-listen: lists %" PRIu64 ", objects %" PRIu64 ", gaps %" PRIu64 ", stats %" PRIu64
          ", malformed %" PRIu64 ", rate %.2f/s; track lists %" PRIu64 ", track ends %" PRIu64 ", counts %" PRIu64
          ", crossings %" PRIu64 "\n",
          L.lists, L.objects, L.gaps, L.stats_msgs, L.malformed, rate, L.track_lists, L.track_ends, L.counts,
          L.crossings);
  return L.lists > 0 ? 0 : 1;
bad:
  fprintf(stderr, "roadscan-listen: %s\n", err);
  return 2;
}

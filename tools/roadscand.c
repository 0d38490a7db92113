/* roadscand - the roadside LiDAR daemon.
 *
 * Main thread: reads the config file (INI, inih) and then the command line
 * (which overrides it) through one table of options, loads calibration and
 * background, opens the LCM publisher, starts the pipeline (packet thread +
 * processing thread), waits, prints the summary. Signal handlers only set
 * the pipeline's stop flag. All large state is static. */
#include "roadscan/sensor/calib.h"
#include "roadscan/util/config.h"
#include "roadscan/util/error.h"
#include "roadscan/util/log.h"
#include "roadscan/daemon/pipeline.h"

#include <ini.h>

#include <arpa/inet.h>
#include <errno.h>
#include <getopt.h>
#include <math.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define RING_SLOTS 4
static rs_slot_t slots[RING_SLOTS];
static rs_pipeline_t pipeline;
static rs_calib_t calib;
static rs_bg_model_t bgmodel;
static rs_cluster_t cluster;
static rs_objects_t objects;
static rs_object_list_t object_list;
static rs_tracker_t tracker;
static rs_counter_t counter;
static rs_publish_t publisher;

/* Every option: its command-line name is its config-file key, in `section`. */
#define OPTIONS(X)                                                                                   \
  X(PCAP, "pcap", 1, "source") X(SPEED, "speed", 1, "source") X(FAST, "fast", 0, "source")            \
  X(LOOP, "loop", 0, "source") X(IFACE, "iface", 1, "source") X(PORT, "port", 1, "source")            \
  X(SOURCE, "source", 1, "source") X(MODEL, "model", 1, "sensor") X(CALIB, "calibration", 1, "sensor") \
  X(RPM, "rpm", 1, "sensor") X(POSE, "pose", 1, "sensor") X(COLS, "columns", 1, "sensor")               \
  X(CUT, "cut-azimuth", 1, "sensor") X(BG, "background", 1, "background")                             \
  X(LEARN, "learn-seconds", 1, "background") X(LEARN_OUT, "learn-out", 1, "background")              \
  X(UPDATE_MIN, "update-minutes", 1, "background") X(UPDATE_EVERY, "update-every", 1, "background")    \
  X(SEE_THROUGH, "see-through", 1, "background") X(BEYOND_FG, "beyond-foreground", 0, "background")  \
  X(CLUSTER, "cluster", 1, "cluster")                                                                \
  X(WINDOW, "window", 1, "cluster") X(EPS, "eps", 1, "cluster") X(MINPTS, "min-pts", 1, "cluster")      \
  X(SEED_SURF, "seed-surfaces", 1, "cluster") X(BORDER_EPS, "border-eps", 1, "cluster")                 \
  X(SPARSE_MINPTS, "sparse-min-pts", 1, "cluster") X(MIN_HALF_W, "min-half-width", 1, "cluster")         \
  X(NO_TRACKING, "no-tracking", 0, "track") X(TRACKS_OUT, "tracks-out", 1, "track")                    \
  X(LABELS_TRACKS, "labels-tracks", 1, "track") X(COAST, "coast-seconds", 1, "track")                  \
  X(TRACK_SET, "track-set", 1, "track")                                                               \
  X(COUNT_LINE, "count-line", 1, "count") X(COUNT_INTERVAL, "count-interval", 1, "count")              \
  X(COUNTS_OUT, "counts-out", 1, "count") X(COUNTS_CH, "counts-channel", 1, "lcm")                     \
  X(TRACKS_CH, "tracks-channel", 1, "lcm") X(ENDS_CH, "track-ends-channel", 1, "lcm")                  \
  X(URL, "lcm-url", 1, "lcm") X(CHANNEL, "channel", 1, "lcm")                                          \
  X(STATS, "stats-channel", 1, "lcm") X(SENSOR_ID, "sensor-id", 1, "lcm")                             \
  X(DATAGRAM, "max-datagram", 1, "lcm") X(NO_PUBLISH, "no-publish", 0, "lcm")                         \
  X(BUDGET, "budget-ms", 1, "daemon") X(SUMMARY, "summary-seconds", 1, "daemon")                      \
  X(SYSLOG, "syslog", 0, "daemon") X(FRAMES, "frames-out", 1, "daemon")                               \
  X(LABELS, "labels-out", 1, "daemon") X(QUIET, "quiet", 0, "daemon")

enum {
#define X(id, name, arg, sec) O_##id,
  OPTIONS(X)
#undef X
  O_COUNT,
  O_CONFIG = O_COUNT, O_HELP, O_VERSION
};
static const struct {
  const char *name;
  int arg;
  const char *section;
} defs[O_COUNT] = {
#define X(id, name, arg, sec) {name, arg, sec},
    OPTIONS(X)
#undef X
};

static void usage(FILE *out) {
  fprintf(out,
          "usage: roadscand [--config FILE] (--pcap FILE | --iface NAME) [options]\n"
          "\n"
          "Every option can also be set in the config file (INI): the key is the option's name,\n"
          "in the section shown in brackets; flags take true/false. The command line overrides\n"
          "the file. Example: /usr/share/doc/roadscan/roadscand.ini (packaging/roadscand.ini).\n"
          "  --config FILE        read options from FILE first\n"
          "\n"
          "Source [source]\n"
          "  --pcap FILE          replay a pcap or pcapng capture\n"
          "  --speed X            replay at X times the original timing (default 1)\n"
          "  --fast               replay as fast as possible, never dropping a frame (analysis)\n"
          "  --loop               start the capture again at its end\n"
          "  --iface NAME         capture live from a network interface (needs CAP_NET_RAW)\n"
          "  --port N             sensor data UDP port (default 2368)\n"
          "  --source ADDR        only packets from this sensor address\n"
          "Sensor [sensor]\n"
          "  --model NAME         force the model: %s\n"
          "                       (default: detected from the packets)\n"
          "  --calibration FILE   per-unit calibration (ROS velodyne YAML)\n"
          "  --rpm N              rotation rate assumed until one is measured (default 600)\n"
          "  --pose \"X Y Z ROLL PITCH YAW\"\n"
          "                       the sensor's pose in the site (metres, degrees; site = Rz Ry Rx p + t):\n"
          "                       objects are also published in the site frame\n"
          "  --columns N          azimuth bins of the map (default: from the measured rate)\n"
          "  --cut-azimuth DEG    azimuth where frames start (default 0)\n"
          "Background [background]\n"
          "  --background MODEL   static-scene model (roadscan-learn): its returns are labelled 1,\n"
          "                       the rest 2 until clustering\n"
          "  --learn-seconds N    with no --background: learn the model from the first N seconds\n"
          "                       of frames, then subtract it (learned in a low-priority thread;\n"
          "                       until then nothing is clustered; --fast waits for it)\n"
          "  --learn-out MODEL    save the model learned online\n"
          "  --update-minutes M   keep the model current from the last M minutes of frames (a relearn\n"
          "                       on sampled frames in a low-priority thread, taken over when it\n"
          "                       explains them at least as well; default 10, 0 = off)\n"
          "  --update-every S     relearn every S seconds of sensor time (default 60)\n"
          "  --see-through N      a return in a cell where the background has N or more static surfaces\n"
          "                       (foliage, edges), or none, is also background when its range lies in a\n"
          "                       static surface of the cell beside it in the same row (default 2, 0 = off)\n"
          "  --beyond-foreground  returns just beyond their cell's farthest static surface (within\n"
          "                       max(0.3 m, 3 %%)) are foreground (default: background: the surface seen\n"
          "                       from a sensor that moved a little); all beyond it are counted\n",
          rs_model_names());
  fprintf(out,
          "Clustering of the foreground [cluster]\n"
          "  --cluster METHOD     fspc-adaptive (default with a background: the best on held-out\n"
          "                       captures, docs/results.md), fspc (the paper's), dbscan, ccl, none\n"
          "  --window HxW         FSPC window, odd numbers (default 5x11)\n"
          "  --eps M              FSPC range difference (default 1.8); the largest one with fspc-adaptive (2.5);\n"
          "                       DBSCAN radius with --cluster dbscan (1.2); CCL's with --cluster ccl (1.0)\n"
          "  --min-pts N          core threshold, the centre counted (default 15)\n"
          "  --seed-surfaces N    fspc-adaptive: a return in a cell where the background has N or more static\n"
          "                       surfaces (foliage, edges: the sensor sees through) joins clusters but does\n"
          "                       not start one (default 3, 0 = off)\n"
          "  --border-eps F       fspc-adaptive: a return that is not a core joins a cluster within F times\n"
          "                       eps of a core return of it (core to core: eps; default 2, at least 1)\n"
          "  --sparse-min-pts N   fspc-adaptive: lowest minPts where the smallest object covers fewer than\n"
          "                       3 cells (far away; default 2: a pair of returns; 3 = as elsewhere)\n"
          "  --min-half-width N   fspc-adaptive: the window reaches at least N columns either side\n"
          "                       (default 2: beyond 120 m returns go missing)\n");
  fprintf(out,
          "Tracking [track]: objects followed over time (docs/tracking.md), on with clustering\n"
          "  --no-tracking        no tracker stage: labels are cluster numbers, no track lists\n"
          "  --tracks-out FILE    one CSV line per track per frame\n"
          "  --labels-tracks WHICH  with --labels-out: a clustered return's label is 2 + its track's\n"
          "                       id; all (default: every track) or confirmed (only confirmed tracks'\n"
          "                       returns are objects, the rest 2)\n"
          "  --coast-seconds S    a confirmed track not seen for S seconds is no longer published (default 1;\n"
          "                       it is kept 2 s more for the object to be taken up again, then ends)\n"
          "  --track-set NAME=VALUE  one tracker parameter (docs/tracking.md; repeatable)\n"
          "Counting [count]: confirmed tracks crossing lines of the site\n"
          "  --count-line \"NAME X1 Y1 X2 Y2\"  a line from (X1, Y1) to (X2, Y2), metres, in the site frame\n"
          "                       with --pose (the sensor frame otherwise); repeatable, up to 16; each track\n"
          "                       counts once per line, forward (from the right of the line to its left,\n"
          "                       looking from X1 Y1 to X2 Y2) or backward, by class\n"
          "  --count-interval S   counts per interval of S seconds of sensor time (default 60)\n"
          "  --counts-out FILE    CSV t_start,t_end,line,direction,class,count per closed interval\n"
          "LCM [lcm]: per frame an object list, a track list and a statistics message; an event per\n"
          "  track that ends\n"
          "  --lcm-url URL        LCM provider (default %s; memq:// and\n"
          "                       file://PATH?mode=w also work)\n"
          "  --channel NAME       object lists (default %s)\n"
          "  --stats-channel NAME per-frame statistics (default %s; 'none' = not sent)\n"
          "  --tracks-channel NAME  track lists (default ROADSCAN_TRACKS; 'none' = not sent)\n"
          "  --track-ends-channel NAME  ended tracks (default ROADSCAN_TRACK_ENDS; 'none' = not sent)\n"
          "  --counts-channel NAME  counts per interval (default ROADSCAN_COUNTS; 'none' = not sent)\n"
          "  --sensor-id ID       sensor_id field of every message (default roadscan)\n"
          "  --max-datagram N     bytes of one LCM datagram; sets the object cap (default %d, min %d)\n"
          "  --no-publish         do not publish (analysis runs)\n"
          "Daemon [daemon]\n"
          "  --budget-ms MS       processing budget per frame (default: the frame period); overruns\n"
          "                       are counted and reported\n"
          "  --summary-seconds S  one log line every S seconds (default 10, 0 = none)\n"
          "  --syslog             log to syslog (daemon facility) instead of stderr\n"
          "  --frames-out FILE    one CSV line per frame\n"
          "  --labels-out FILE    the pipeline's label of every return (specs/point-labels.md)\n"
          "  --quiet              no summary at the end\n"
          "  --help, --version\n"
          "\n"
          "SIGINT/SIGTERM stop cleanly and print the summary. Exit status: 0 done (input errors are\n"
          "counted in the summary), 1 fatal error (including an LCM URL that cannot publish), 2 bad\n"
          "usage or configuration.\n",
          RS_PUB_DEFAULT_URL, RS_PUB_DEFAULT_CHANNEL, RS_PUB_DEFAULT_STATS, RS_PUB_DATAGRAM_MAX,
          RS_PUB_DATAGRAM_MIN);
}

static void on_signal(int sig) {
  (void)sig;
  rs_pipeline_request_stop(&pipeline);
}

static int bad(const char *msg) {
  rs_log(RS_LOG_ERR, "%s", msg);
  return 2;
}

/* Everything the options set. */
static struct {
  rs_pipeline_cfg_t cfg;
  rs_cluster_cfg_t ccfg;
  rs_publish_cfg_t pub;
  rs_pose_t pose;
  const char *frames_path, *calib_path, *bg_path;
  bool quiet, fast, speed_set, cluster_set, have_pose, no_publish, use_syslog, no_tracking;
  rs_track_cfg_t tcfg;
  rs_count_line_t lines[RS_COUNT_LINES];
  int nlines;
  double count_interval;
  double eps;
} st;

static int set_flag(const char *key, const char *val, bool *out, char *err, size_t n) {
  if (val == NULL) {
    *out = true;
    return RS_OK;
  }
  return rs_cfg_bool(key, val, out, err, n);
}

/* Applies one option; key names it in messages ("--eps", "file: [cluster] eps").
 * val is NULL for a flag given on the command line. Strings are kept. */
static int apply(int id, const char *val, const char *key, char *err, size_t n) {
  double d;
  long l;
  rs_pipeline_cfg_t *cfg = &st.cfg;
  /* values outlive the config parser's buffers: kept in a static arena */
  static char arena[16384];
  static size_t used;
  const char *v = val;
  if (val) {
    size_t len = strlen(val) + 1;
    if (len > sizeof arena - used) {
      snprintf(err, n, "%s: the options take more than %zu bytes", key, sizeof arena);
      return RS_E_NOMEM;
    }
    v = memcpy(arena + used, val, len);
    used += len;
  }
  switch (id) {
  case O_PCAP: cfg->pcap_path = v; break;
  case O_IFACE: cfg->iface = v; break;
  case O_SPEED:
    if (rs_cfg_double(key, v, 0.001, 1000.0, &cfg->capture.speed, err, n)) return RS_E_INVAL;
    st.speed_set = true;
    break;
  case O_FAST: return set_flag(key, v, &st.fast, err, n);
  case O_LOOP: return set_flag(key, v, &cfg->capture.loop, err, n);
  case O_PORT:
    if (rs_cfg_long(key, v, 1, 65535, &l, err, n)) return RS_E_INVAL;
    cfg->capture.data_port = (uint16_t)l;
    break;
  case O_SOURCE: {
    unsigned char a[16];
    if (inet_pton(AF_INET, v, a) != 1 && inet_pton(AF_INET6, v, a) != 1) {
      snprintf(err, n, "%s: '%s' is not an IPv4 or IPv6 address", key, v);
      return RS_E_INVAL;
    }
    cfg->capture.source_addr = v;
    break;
  }
  case O_MODEL:
    if (rs_cfg_model(key, v, &cfg->stream.force_model, err, n)) return RS_E_INVAL;
    break;
  case O_CALIB: st.calib_path = v; break;
  case O_RPM:
    if (rs_cfg_double(key, v, 300.0, 1200.0, &d, err, n)) return RS_E_INVAL;
    cfg->assembly.default_hz = d / 60.0;
    break;
  case O_POSE: {
    double x[6];
    char tail;
    if (sscanf(v, "%lf %lf %lf %lf %lf %lf %c", &x[0], &x[1], &x[2], &x[3], &x[4], &x[5], &tail) != 6) {
      snprintf(err, n, "%s: '%s' is not six numbers \"X Y Z ROLL PITCH YAW\" (metres, degrees)", key, v);
      return RS_E_INVAL;
    }
    for (int i = 0; i < 6; i++)
      if (!isfinite(x[i]) || (i < 3 && fabs(x[i]) > 1e7) || (i >= 3 && fabs(x[i]) > 360.0)) {
        snprintf(err, n, "%s: '%s': positions within 1e7 m, angles within 360 degrees", key, v);
        return RS_E_INVAL;
      }
    const double rad = 3.14159265358979323846 / 180.0;
    st.pose = (rs_pose_t){x[0], x[1], x[2], x[3] * rad, x[4] * rad, x[5] * rad};
    st.have_pose = true;
    break;
  }
  case O_COLS:
    if (rs_cfg_long(key, v, RS_MIN_COLS, RS_MAX_COLS, &l, err, n)) return RS_E_INVAL;
    cfg->assembly.columns = (int)l;
    break;
  case O_CUT:
    if (rs_cfg_double(key, v, 0.0, 359.99, &cfg->assembly.cut_deg, err, n)) return RS_E_INVAL;
    break;
  case O_FRAMES: st.frames_path = v; break;
  case O_LABELS: cfg->labels_out = v; break;
  case O_BG: st.bg_path = v; break;
  case O_LEARN:
    if (rs_cfg_double(key, v, 0.1, 3600.0, &cfg->learn_seconds, err, n)) return RS_E_INVAL;
    break;
  case O_LEARN_OUT: cfg->learn_out = v; break;
  case O_UPDATE_MIN:
    if (rs_cfg_double(key, v, 0.0, 1440.0, &d, err, n)) return RS_E_INVAL;
    cfg->update_window_s = d * 60.0;
    break;
  case O_UPDATE_EVERY:
    if (rs_cfg_double(key, v, 5.0, 86400.0, &cfg->update_every_s, err, n)) return RS_E_INVAL;
    break;
  case O_CLUSTER: {
    int m = rs_cluster_method_from_name(v);
    if (m < 0) {
      snprintf(err, n, "%s: '%s' is not fspc, fspc-adaptive, dbscan, ccl or none", key, v);
      return RS_E_INVAL;
    }
    st.ccfg.method = (rs_cluster_method_t)m;
    st.cluster_set = true;
    break;
  }
  case O_WINDOW: {
    int h, w;
    char tail;
    if (sscanf(v, "%dx%d%c", &h, &w, &tail) != 2 || h < 1 || w < 1 || h % 2 == 0 || w % 2 == 0 || h > RS_MAX_WIN_H ||
        w > RS_MAX_WIN_W) {
      snprintf(err, n, "%s: '%s' is not HxW with odd H <= %d and odd W <= %d", key, v, RS_MAX_WIN_H, RS_MAX_WIN_W);
      return RS_E_INVAL;
    }
    st.ccfg.win_h = h;
    st.ccfg.win_w = w;
    break;
  }
  case O_EPS:
    if (rs_cfg_double(key, v, 0.01, 50.0, &st.eps, err, n)) return RS_E_INVAL;
    break;
  case O_MINPTS:
    if (rs_cfg_long(key, v, 1, 255, &l, err, n)) return RS_E_INVAL;
    st.ccfg.min_pts = st.ccfg.dbscan_min_pts = (int)l;
    break;
  case O_SEED_SURF:
    if (rs_cfg_long(key, v, 0, 255, &l, err, n)) return RS_E_INVAL;
    st.ccfg.adapt_seed_surfaces = (int)l;
    break;
  case O_BORDER_EPS:
    if (rs_cfg_double(key, v, 1.0, 10.0, &d, err, n)) return RS_E_INVAL;
    st.ccfg.adapt_border_eps = (float)d;
    break;
  case O_SPARSE_MINPTS:
    if (rs_cfg_long(key, v, 1, 255, &l, err, n)) return RS_E_INVAL;
    st.ccfg.adapt_sparse_min_pts = (int)l;
    break;
  case O_MIN_HALF_W:
    if (rs_cfg_long(key, v, 0, RS_MAX_WIN_W / 2, &l, err, n)) return RS_E_INVAL;
    st.ccfg.adapt_min_half_w = (int)l;
    break;
  case O_SEE_THROUGH:
    if (rs_cfg_long(key, v, 0, RS_BG_SURFACES, &l, err, n)) return RS_E_INVAL;
    st.cfg.bg_see_through = l == 0 ? -1 : (int)l;
    break;
  case O_BEYOND_FG: return set_flag(key, v, &st.cfg.bg_beyond_foreground, err, n);
  case O_URL: st.pub.url = v; break;
  case O_CHANNEL: st.pub.channel = v; break;
  case O_STATS: st.pub.stats_channel = strcmp(v, "none") == 0 ? "" : v; break;
  case O_SENSOR_ID: st.pub.sensor_id = v; break;
  case O_DATAGRAM:
    if (rs_cfg_long(key, v, RS_PUB_DATAGRAM_MIN, RS_PUB_DATAGRAM_MAX, &l, err, n)) return RS_E_INVAL;
    st.pub.max_datagram = (int)l;
    break;
  case O_NO_PUBLISH: return set_flag(key, v, &st.no_publish, err, n);
  case O_NO_TRACKING: return set_flag(key, v, &st.no_tracking, err, n);
  case O_TRACKS_OUT: cfg->tracks_out = v; break;
  case O_LABELS_TRACKS:
    if (strcmp(v, "all") == 0) cfg->labels_confirmed_only = false;
    else if (strcmp(v, "confirmed") == 0) cfg->labels_confirmed_only = true;
    else {
      snprintf(err, n, "%s: '%s' is not all or confirmed", key, v);
      return RS_E_INVAL;
    }
    break;
  case O_COAST:
    if (rs_cfg_double(key, v, 0.1, 60.0, &st.tcfg.coast_s, err, n)) return RS_E_INVAL;
    break;
  case O_TRACK_SET: {
    char name[64];
    const char *eq = strchr(v, '=');
    if (eq == NULL || eq == v || (size_t)(eq - v) >= sizeof name) {
      snprintf(err, n, "%s: '%s' is not NAME=VALUE", key, v);
      return RS_E_INVAL;
    }
    memcpy(name, v, (size_t)(eq - v));
    name[eq - v] = '\0';
    if (rs_track_cfg_set(&st.tcfg, name, eq + 1, err, n) != RS_OK) return RS_E_INVAL;
    break;
  }
  case O_COUNT_LINE:
    if (st.nlines == RS_COUNT_LINES) {
      snprintf(err, n, "%s: at most %d lines", key, RS_COUNT_LINES);
      return RS_E_INVAL;
    }
    if (rs_count_parse_line(v, &st.lines[st.nlines], err, n) != RS_OK) return RS_E_INVAL;
    st.nlines++;
    break;
  case O_COUNT_INTERVAL:
    if (rs_cfg_double(key, v, 1.0, 86400.0, &st.count_interval, err, n)) return RS_E_INVAL;
    break;
  case O_COUNTS_OUT: cfg->counts_out = v; break;
  case O_COUNTS_CH: st.pub.counts_channel = strcmp(v, "none") == 0 ? "" : v; break;
  case O_TRACKS_CH: st.pub.tracks_channel = strcmp(v, "none") == 0 ? "" : v; break;
  case O_ENDS_CH: st.pub.track_ends_channel = strcmp(v, "none") == 0 ? "" : v; break;
  case O_BUDGET:
    if (rs_cfg_double(key, v, 0.1, 10000.0, &cfg->budget_ms, err, n)) return RS_E_INVAL;
    break;
  case O_SUMMARY:
    if (rs_cfg_double(key, v, 0.0, 86400.0, &cfg->summary_s, err, n)) return RS_E_INVAL;
    break;
  case O_SYSLOG: return set_flag(key, v, &st.use_syslog, err, n);
  case O_QUIET: return set_flag(key, v, &st.quiet, err, n);
  default: snprintf(err, n, "%s: not an option", key); return RS_E_INVAL;
  }
  return RS_OK;
}

typedef struct {
  const char *path;
  char err[RS_ERRMSG_SIZE];
  bool failed;
  bool seen[O_COUNT];
} ini_ctx_t;

/* inih's line buffer (INI_MAX_LINE, 200) less the newline and its NUL */
#define RS_INI_LINE_MAX 198

static int on_ini(void *user, const char *section, const char *name, const char *value) {
  ini_ctx_t *c = user;
  if (c->failed) return 0;
  char key[512];
  snprintf(key, sizeof key, "%s: [%s] %s", c->path, section, name);
  for (int id = 0; id < O_COUNT; id++) {
    if (strcmp(defs[id].name, name) != 0) continue;
    if (strcmp(defs[id].section, section) != 0) {
      snprintf(c->err, sizeof c->err, "%s: '%s' belongs in section [%s]", key, name, defs[id].section);
      c->failed = true;
      return 0;
    }
    /* a key given twice is a mistake (the last would win silently), but for the repeatable ones */
    if (c->seen[id] && id != O_COUNT_LINE && id != O_TRACK_SET) {
      snprintf(c->err, sizeof c->err, "%s: given twice in the file", key);
      c->failed = true;
      return 0;
    }
    c->seen[id] = true;
    if (apply(id, value, key, c->err, sizeof c->err) != RS_OK) {
      c->failed = true;
      return 0;
    }
    return 1;
  }
  snprintf(c->err, sizeof c->err, "%s: unknown key '%s' (the keys are the option names of --help)", key, name);
  c->failed = true;
  return 0;
}

/* 0 ok, 2 bad file (message logged). */
static int read_config(const char *path) {
  ini_ctx_t c = {.path = path, .failed = false};
  FILE *f = fopen(path, "r");
  if (f == NULL) {
    snprintf(c.err, sizeof c.err, "--config %s: cannot read: %s", path, strerror(errno));
    return bad(c.err);
  }
  /* what inih would silently cut: a NUL byte (the value ends there), a line longer than its buffer */
  int line = 1, col = 0, ch;
  while ((ch = fgetc(f)) != EOF) {
    if (ch == '\0') {
      snprintf(c.err, sizeof c.err, "%s:%d: a NUL byte (not a text file)", path, line);
      fclose(f);
      return bad(c.err);
    }
    if (ch == '\n') {
      line++;
      col = 0;
    } else if (++col > RS_INI_LINE_MAX) {
      snprintf(c.err, sizeof c.err, "%s:%d: the line is longer than %d characters", path, line, RS_INI_LINE_MAX);
      fclose(f);
      return bad(c.err);
    }
  }
  rewind(f);
  int rc = ini_parse_file(f, on_ini, &c);
  fclose(f);
  if (c.failed) return bad(c.err);
  if (rc != 0) {
    snprintf(c.err, sizeof c.err, "%s:%d: not an INI line (expected [section] or key = value)", path, rc);
    return bad(c.err);
  }
  return 0;
}

int main(int argc, char **argv) {
  static struct option opts[O_VERSION + 2];
  for (int id = 0; id < O_COUNT; id++)
    opts[id] = (struct option){defs[id].name, defs[id].arg ? required_argument : no_argument, NULL, 256 + id};
  opts[O_CONFIG] = (struct option){"config", required_argument, NULL, 256 + O_CONFIG};
  opts[O_HELP] = (struct option){"help", no_argument, NULL, 256 + O_HELP};
  opts[O_VERSION] = (struct option){"version", no_argument, NULL, 256 + O_VERSION};
  rs_log_open("roadscand", false);
  rs_pipeline_cfg_t *cfg = &st.cfg;
  cfg->capture.speed = 1.0;
  cfg->capture.data_port = RS_DEFAULT_DATA_PORT;
  cfg->stream.log = stderr;
  cfg->assembly.default_hz = 10.0;
  cfg->update_window_s = 600.0;
  cfg->summary_s = 10.0;
  rs_cluster_cfg_default(&st.ccfg);
  rs_track_cfg_default(&st.tcfg);
  st.count_interval = 60.0;
  char err[RS_ERRMSG_SIZE];
  /* the config file first, whatever its place on the command line */
  for (int i = 1; i < argc; i++) {
    const char *path = NULL;
    if (strcmp(argv[i], "--config") == 0 && i + 1 < argc) path = argv[i + 1];
    else if (strncmp(argv[i], "--config=", 9) == 0) path = argv[i] + 9;
    if (path && read_config(path) != 0) return 2;
  }
  int c;
  while ((c = getopt_long(argc, argv, "", opts, NULL)) != -1) {
    if (c == 256 + O_CONFIG) continue;
    if (c == 256 + O_HELP) {
      usage(stdout);
      return 0;
    }
    if (c == 256 + O_VERSION) {
      printf("roadscand %s\n", RS_VERSION);
      return 0;
    }
    if (c < 256 || c >= 256 + O_COUNT) {
      usage(stderr);
      return 2;
    }
    char key[64];
    snprintf(key, sizeof key, "--%s", defs[c - 256].name);
    if (apply(c - 256, optarg, key, err, sizeof err) != RS_OK) return bad(err);
  }
  if (optind < argc) {
    snprintf(err, sizeof err, "unexpected argument '%s' (see --help)", argv[optind]);
    return bad(err);
  }
  if (st.use_syslog) rs_log_open("roadscand", true);
  if ((cfg->pcap_path == NULL) == (cfg->iface == NULL)) return bad("give exactly one source: --pcap FILE or --iface NAME");
  if (cfg->iface && (st.fast || st.speed_set || cfg->capture.loop)) return bad("--speed, --fast and --loop apply to --pcap only");
  if (st.fast && st.speed_set) return bad("--fast and --speed exclude each other");
  if (st.fast) {
    cfg->capture.speed = 0.0;
    cfg->lossless = true;
  }
  cfg->stream.data_port = cfg->capture.data_port;
  cfg->stream.source_addr = cfg->capture.source_addr;
  cfg->stream.default_hz = cfg->assembly.default_hz;
  if (st.calib_path) {
    if (rs_calib_load_yaml(st.calib_path, &calib, err, sizeof err) != RS_OK) {
      rs_log(RS_LOG_ERR, "%s", err);
      return 1;
    }
    cfg->stream.calib = &calib;
  }
  if (st.bg_path && cfg->learn_seconds > 0) return bad("--background and --learn-seconds exclude each other");
  if (cfg->learn_out && cfg->learn_seconds <= 0) return bad("--learn-out needs --learn-seconds");
  if (st.bg_path) {
    if (rs_bg_load(&bgmodel, st.bg_path, err, sizeof err) != RS_OK) {
      rs_log(RS_LOG_ERR, "%s", err);
      return 1;
    }
    if (cfg->stream.force_model != RS_MODEL_UNKNOWN && cfg->stream.force_model != bgmodel.model) {
      rs_log(RS_LOG_ERR, "%s: the model is for a %s, --model says %s", st.bg_path, rs_model_name(bgmodel.model),
             rs_model_name(cfg->stream.force_model));
      return 1;
    }
    if (cfg->assembly.columns && cfg->assembly.columns != bgmodel.cols) {
      rs_log(RS_LOG_ERR, "%s: the model has %u columns, --columns says %d", st.bg_path, bgmodel.cols,
             cfg->assembly.columns);
      return 1;
    }
    cfg->background = &bgmodel;
  }
  if (!st.cluster_set) st.ccfg.method = (st.bg_path || cfg->learn_seconds > 0) ? RS_CLUSTER_FSPC_ADAPTIVE : RS_CLUSTER_NONE;
  if (st.eps > 0) {
    if (st.ccfg.method == RS_CLUSTER_DBSCAN) st.ccfg.dbscan_eps = (float)st.eps;
    else if (st.ccfg.method == RS_CLUSTER_CCL) st.ccfg.ccl_eps = (float)st.eps;
    else if (st.ccfg.method == RS_CLUSTER_FSPC_ADAPTIVE) st.ccfg.adapt_eps_max = (float)st.eps;
    else st.ccfg.eps = (float)st.eps;
  }
  if (st.ccfg.method != RS_CLUSTER_NONE) {
    if (rs_cluster_init(&cluster, &st.ccfg, NULL) != RS_OK) return bad("bad clustering parameters");
    cfg->cluster = &cluster;
  }
  if (cfg->cluster) {
    rs_objects_init(&objects, st.have_pose ? &st.pose : NULL);
    cfg->objects = &objects;
    cfg->object_list = &object_list;
    if (!st.no_tracking) {
      if (rs_track_init(&tracker, &st.tcfg) != RS_OK) return bad("bad tracking parameters");
      rs_track_set_pose(&tracker, st.have_pose ? &st.pose : NULL);
      cfg->tracker = &tracker;
    }
  }
  if (cfg->tracks_out && cfg->tracker == NULL) return bad("--tracks-out needs tracking (clustering, no --no-tracking)");
  if ((st.nlines > 0 || cfg->counts_out) && cfg->tracker == NULL)
    return bad("counting needs tracking (clustering, no --no-tracking)");
  if (cfg->counts_out && st.nlines == 0) return bad("--counts-out needs a --count-line");
  if (st.nlines > 0) {
    if (rs_count_init(&counter, st.lines, st.nlines, st.have_pose ? &st.pose : NULL, st.count_interval, err,
                      sizeof err) != RS_OK)
      return bad(err);
    cfg->counter = &counter;
  }
  if (!st.no_publish) {
    int prc = rs_publish_init(&publisher, &st.pub);
    if (prc != RS_OK) {
      rs_log(RS_LOG_ERR, "%s", publisher.err);
      return prc == RS_E_INVAL ? 2 : 1;
    }
    cfg->publish = &publisher;
  }
  FILE *frames = NULL;
  if (st.frames_path) {
    frames = fopen(st.frames_path, "w");
    if (frames == NULL) {
      rs_log(RS_LOG_ERR, "--frames-out %s: cannot write: %s", st.frames_path, strerror(errno));
      rs_publish_deinit(&publisher);
      return 1;
    }
    fprintf(frames, "%s\n", rs_pipeline_csv_header());
    cfg->frames_out = frames;
  }
  int rc = rs_pipeline_init(&pipeline, cfg, slots, RING_SLOTS);
  if (rc != RS_OK) {
    rs_log(RS_LOG_ERR, "%s", pipeline.input_err[0] ? pipeline.input_err : rs_strerror(rc));
    if (frames) fclose(frames);
    rs_publish_deinit(&publisher);
    return 1;
  }
  struct sigaction sa;
  memset(&sa, 0, sizeof sa);
  sa.sa_handler = on_signal;
  sigemptyset(&sa.sa_mask);
  sigaction(SIGINT, &sa, NULL);
  sigaction(SIGTERM, &sa, NULL);
  rc = rs_pipeline_start(&pipeline);
  if (rc != RS_OK) {
    rs_log(RS_LOG_ERR, "cannot start threads: %s", rs_strerror(rc));
    rs_pipeline_deinit(&pipeline);
    rs_publish_deinit(&publisher);
    return 1;
  }
  rs_pipeline_join(&pipeline);
  int status = 0;
  if (pipeline.input_status != RS_OK) {
    rs_log(RS_LOG_ERR, "input ended early: %s", pipeline.input_err);
    if (pipeline.input_status != RS_E_TRUNCATED) status = 1;
  }
  if (!st.quiet) rs_pipeline_summary(&pipeline, stderr);
  rs_pipeline_deinit(&pipeline);
  rs_publish_deinit(&publisher);
  if (st.bg_path) rs_bg_model_free(&bgmodel);
  if (frames && fclose(frames) != 0) {
    rs_log(RS_LOG_ERR, "--frames-out %s: write failed", st.frames_path);
    status = 1;
  }
  return status;
}

/* roadscand - the roadside LiDAR daemon.
 *
 * Main thread: reads the config file (INI, inih) and then the command line
 * (which overrides it) through one table of options, loads calibration and
 * background, opens the LCM publisher, starts the pipeline (packet thread +
 * processing thread), waits, prints the summary. Signal handlers only set
 * the pipeline's stop flag. All large state is static. */
#include "roadscan/sensor/calib.h"
#include "roadscan/util/opts.h"
#include "roadscan/util/error.h"
#include "roadscan/util/log.h"
#include "roadscan/daemon/pipeline.h"

#include <arpa/inet.h>
#include <errno.h>
#include <math.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

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
static rs_notify_t notify;

static void on_signal(int sig) {
  (void)sig;
  rs_pipeline_request_stop(&pipeline);
}

static int bad(const char *msg) {
  rs_log(RS_LOG_ERR, "%s", msg);
  return 2;
}

/* Everything the options set (the option table's target). */
typedef struct {
  rs_pipeline_cfg_t cfg;
  rs_cluster_cfg_t ccfg;
  rs_publish_cfg_t pub;
  rs_pose_t pose;
  const char *frames_path, *calib_path, *bg_path;
  bool quiet, fast, no_publish, use_syslog, no_tracking, allow_root, relearn;
  int buffer_kib;
  rs_track_cfg_t tcfg;
  rs_count_lines_t lines;
  rs_count_zones_t zones;
  double count_interval;
  double count_hidden;
  double count_hidden_window;
  int count_hidden_place;  /* --count-hidden-place: 0 track, 1 path */
  double count_unseen;
  double count_same;
  int count_unseen_yield; /* --count-unseen-yield: 0 on, 1 off */
  double count_band;
  double count_class_delay;
  int method;            /* rs_cluster_method_t */
  double eps;            /* the method's, when given */
  int min_pts;           /* the method's, when given */
  int window[2];         /* the method's, when given */
  int port, see_through, labels_confirmed;
  double shift_gate_pct;
  int rt_priority;       /* --rt-priority: the processing thread's SCHED_FIFO priority, the packet thread's + 1 */
} settings_t;
static settings_t st;
static rs_opts_t opts;

static int check_source(void *t, const char *key, const char *v, char *err, size_t n) {
  (void)t;
  unsigned char a[16];
  if (inet_pton(AF_INET, v, a) == 1 || inet_pton(AF_INET6, v, a) == 1) return RS_OK;
  snprintf(err, n, "%s: '%s' is not an IPv4 or IPv6 address", key, v);
  return RS_E_INVAL;
}

static int parse_pose(void *t, const char *key, const char *v, char *err, size_t n) {
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
  *(rs_pose_t *)t = (rs_pose_t){x[0], x[1], x[2], x[3] * rad, x[4] * rad, x[5] * rad};
  return RS_OK;
}

static int parse_window(void *t, const char *key, const char *v, char *err, size_t n) {
  int h, w;
  char tail;
  if (sscanf(v, "%dx%d%c", &h, &w, &tail) != 2 || h < 1 || w < 1 || h % 2 == 0 || w % 2 == 0 || h > RS_MAX_WIN_H ||
      w > RS_MAX_WIN_W) {
    snprintf(err, n, "%s: '%s' is not HxW with odd H <= %d and odd W <= %d", key, v, RS_MAX_WIN_H, RS_MAX_WIN_W);
    return RS_E_INVAL;
  }
  ((int *)t)[0] = h;
  ((int *)t)[1] = w;
  return RS_OK;
}

static int parse_track_set(void *t, const char *key, const char *v, char *err, size_t n) {
  char name[64];
  const char *eq = strchr(v, '=');
  if (eq == NULL || eq == v || (size_t)(eq - v) >= sizeof name) {
    snprintf(err, n, "%s: '%s' is not NAME=VALUE", key, v);
    return RS_E_INVAL;
  }
  memcpy(name, v, (size_t)(eq - v));
  name[eq - v] = '\0';
  return rs_track_cfg_set(t, name, eq + 1, err, n);
}

#define T settings_t
#define F(nm, f, h) RS_OPT_FLAG_(nm, T, f, h)
#define S(nm, a, f, h) RS_OPT_STR_(nm, a, T, f, h)
#define D(nm, a, f, l, u, h) RS_OPT_DBL_(nm, a, T, f, l, u, h)
#define I(nm, a, f, l, u, h) RS_OPT_INT_(nm, a, T, f, l, u, h)
static const rs_opt_t table[] = {
    RS_OPT_HEAD("source", "Source"),
    S("pcap", "FILE", cfg.pcap_path, "replay a pcap or pcapng capture"),
    D("speed", "X", cfg.capture.speed, 0.001, 1000.0, "replay at X times the original timing"),
    F("fast", fast, "replay as fast as possible, never dropping a frame (analysis)"),
    F("loop", cfg.capture.loop, "start the capture again at its end"),
    S("iface", "NAME", cfg.iface, "capture live from a network interface (needs CAP_NET_RAW)"),
    I("port", "N", port, 1, 65535, "sensor data UDP port"),
    {.type = RS_OPT_STR, .name = "source", .arg = "ADDR", .off = offsetof(T, cfg.capture.source_addr),
     .fn = check_source, .help = "only packets from this sensor address (IPv4 or IPv6)"},
    I("capture-buffer-kib", "N", buffer_kib, RS_CAPTURE_BUFFER_MIN / 1024, RS_CAPTURE_BUFFER_MAX / 1024,
      "live: the kernel's capture buffer, KiB (what a stall of the packet thread can absorb; the kernel's drops "
      "are in the summary and the statistics)"),
    RS_OPT_HEAD("sensor", "Sensor"),
    RS_OPT_FORCE_MODEL_("model", T, cfg.stream.force_model),
    RS_OPT_CALIB_(T, calib_path),
    {.type = RS_OPT_DOUBLE, .name = "rpm", .arg = "N", .off = offsetof(T, cfg.assembly.default_hz), .lo = 300,
     .hi = 1200, .scale = 1.0 / 60.0, .help = "rotation rate assumed until one is measured"},
    {.type = RS_OPT_FUNC, .name = "pose", .arg = "\"X Y Z ROLL PITCH YAW\"", .off = offsetof(T, pose),
     .fn = parse_pose,
     .help = "the sensor's pose in the site (metres, degrees; site = Rz Ry Rx p + t): objects, tracks and "
             "counting lines are also in the site frame"},
    {.type = RS_OPT_INT, .name = "columns", .arg = "N", .off = offsetof(T, cfg.assembly.columns), .lo = RS_MIN_COLS,
     .hi = RS_MAX_COLS, .def = "from the measured rate", .help = "azimuth bins of the map"},
    D("cut-azimuth", "DEG", cfg.assembly.cut_deg, 0.0, 359.99, "azimuth where frames start"),
    RS_OPT_HEAD("background", "Background"),
    S("background", "MODEL", bg_path,
      "static-scene model (roadscan-learn): its returns are labelled 1, the rest 2 until clustering"),
    {.type = RS_OPT_DOUBLE, .name = "learn-seconds", .arg = "N", .off = offsetof(T, cfg.learn_seconds), .lo = 0.1,
     .hi = 3600, .def = "off",
     .help = "with no --background: learn the model from the first N seconds of frames, then subtract it "
             "(learned in a low-priority thread; until then nothing is clustered; --fast waits for it)"},
    S("learn-out", "MODEL", cfg.learn_out,
      "where the site's model is kept: saved (atomically) once learned, loaded instead of learning at every "
      "later start; a stored model that is unreadable or not the sensor's is set aside and learned anew"),
    F("relearn", relearn, "with --learn-out: learn anew even when a model is stored (and replace it)"),
    {.type = RS_OPT_DOUBLE, .name = "update-minutes", .arg = "M", .off = offsetof(T, cfg.update_window_s), .lo = 0,
     .hi = 1440, .scale = 60.0,
     .help = "keep the model current from the last M minutes of frames (a relearn on frames sampled in bursts "
             "in a low-priority thread, once 90 % of the window is sampled, taken over when it explains them at "
             "least as well; 0 = off)"},
    D("update-every", "S", cfg.update_every_s, 5.0, 86400.0, "relearn every S seconds of sensor time"),
    I("see-through", "N", see_through, 0, RS_BG_SURFACES,
      "a return in a cell where the background has N or more static surfaces (foliage, edges), or none, is "
      "also background when its range lies in a static surface of the cell beside it in the same row (0 = off)"),
    F("beyond-foreground", cfg.bg_beyond_foreground,
      "returns just beyond their cell's farthest static surface (within max(0.3 m, 3 %)) are foreground "
      "(default: background: the surface seen from a sensor that moved a little); all beyond it are counted"),
    D("shift-tol", "M", cfg.bg_shift_tol, 0.0, 2.0,
      "a displaced sensor (knocked, a pole twisting): in a frame where the far sides of edges appear where "
      "their near sides were learned, a foreground return within M (3D) of a static surface of a cell nearby "
      "in its row is background (0 = off)"),
    D("shift-deg", "DEG", cfg.bg_shift_deg, 0.0, 5.0,
      "... or within the range x tan(DEG) when more: a sensor that turned moves far surfaces most"),
    D("shift-gate", "PERCENT", shift_gate_pct, 0.0, 100.0,
      "how much evidence makes a frame displaced: returns beyond their cell's farthest surface and within "
      "--shift-tol of a surface nearby, as a share of the frame's returns (0: no gate, every frame)"),
    F("no-shift-behind", cfg.bg_no_behind,
      "in a displaced frame, do not take for background what the sensor sees behind a near object it moved "
      "around (a return past the model within the object's parallax band, atan(--shift-tol / its range), of "
      "its edge, no nearer than the surface beside the edge)"),
    F("no-ground", cfg.no_ground,
      "find no ground in the model (by default the ground under the objects is fitted to the model's lowest "
      "static surfaces, and the class rule reads how high a vehicle's top stands above it): objects' heights "
      "then come from their returns alone (a site where no plane fits, a sensor on a bridge)"),
    RS_OPT_HEAD("cluster", "Clustering of the foreground"),
    {.type = RS_OPT_CHOICE, .name = "cluster", .arg = "METHOD", .off = offsetof(T, method),
     .choices = "none|fspc|fspc-adaptive|dbscan|ccl", .def = "fspc-adaptive with a background, else none",
     .help = "fspc-adaptive is the best on held-out captures (docs/results.md); fspc is the paper's"},
    {.type = RS_OPT_FUNC, .name = "window", .arg = "HxW", .off = offsetof(T, window), .fn = parse_window,
     .def = "5x11", .help = "the FSPC window (the largest with fspc-adaptive), odd numbers"},
    {.type = RS_OPT_DOUBLE, .name = "eps", .arg = "M", .off = offsetof(T, eps), .lo = 0.01, .hi = 50.0,
     .def = "fspc 1.8, fspc-adaptive 2.5, dbscan 1.2, ccl 1.0",
     .help = "the method's distance: FSPC's range difference (the largest with fspc-adaptive), DBSCAN's "
             "radius, CCL's range difference"},
    {.type = RS_OPT_INT, .name = "min-pts", .arg = "N", .off = offsetof(T, min_pts), .lo = 1, .hi = 255,
     .def = "15", .help = "core threshold, the centre counted (the largest with fspc-adaptive; not for ccl)"},
    I("bridge-gap", "N", ccfg.bridge_gap, 0, RS_CLUSTER_BRIDGE_MAX,
      "fspc, fspc-adaptive, ccl: a window reaches across up to N columns no firing fell in this turn (a lost "
      "packet: 12 columns of a VLP-32C, 24 of a VLP-16 at 600 rpm), counting only measured ones (0 = off)"),
    I("seed-surfaces", "N", ccfg.adaptive.seed_surfaces, 0, 255,
      "fspc-adaptive: a return in a cell where the background has N or more static surfaces (foliage, edges: "
      "the sensor sees through) joins clusters but does not start one (0 = off)"),
    RS_OPT_FLT_("border-eps", "F", T, ccfg.adaptive.border_eps, 1.0, 10.0,
                "fspc-adaptive: a return that is not a core joins a cluster within F times eps of a core "
                "return of it (core to core: eps)"),
    RS_OPT_FLT_("eps-share", "F", T, ccfg.adaptive.eps_share, 0.005, 0.2,
                "fspc-adaptive: eps is max(F, the sensor's median row spacing in radians) x range, within "
                "0.5 m and --eps: lower keeps people and vehicles one behind the other apart, higher keeps a "
                "long side seen at a grazing angle together"),
    I("sparse-min-pts", "N", ccfg.adaptive.sparse_min_pts, 1, 255,
      "fspc-adaptive: lowest minPts where the smallest object covers fewer than 3 cells (far away; 2: a "
      "pair of returns)"),
    I("min-half-width", "N", ccfg.adaptive.min_half_w, 0, RS_MAX_WIN_W / 2,
      "fspc-adaptive: the window reaches at least N columns either side (beyond 120 m returns go missing)"),
    RS_OPT_FLT_("split-gap", "M", T, ccfg.adaptive.split_gap, 0.0, 10.0,
                "fspc-adaptive: a cluster is cut where its returns, sorted by range, leave a gap of M or more "
                "and every part is narrow (people one behind the other; 0 = off)"),
    RS_OPT_FLT_("split-width", "M", T, ccfg.adaptive.split_width, 0.05, 10.0,
                "fspc-adaptive: ... no part wider than M across the line of sight"),
    RS_OPT_FLT_("split-depth", "M", T, ccfg.adaptive.split_depth, 0.0, 10.0,
                "fspc-adaptive: ... nor deeper than M in range"),
    I("split-min", "N", ccfg.adaptive.split_min, 1, 1000,
      "fspc-adaptive: ... and no part of fewer than N returns"),
    RS_OPT_HEAD("track", "Tracking: objects followed over time (docs/tracking.md), on with clustering"),
    F("no-tracking", no_tracking, "no tracker stage: labels are cluster numbers, no track lists"),
    S("tracks-out", "FILE", cfg.tracks_out, "one CSV line per track per frame"),
    {.type = RS_OPT_CHOICE, .name = "labels-tracks", .arg = "WHICH", .off = offsetof(T, labels_confirmed),
     .choices = "all|confirmed",
     .help = "with --labels-out: a clustered return's label is 2 + its track's id; all: every track; "
             "confirmed: only confirmed tracks' returns are objects, the rest 2"},
    D("coast-seconds", "S", tcfg.coast_s, 0.1, 60.0,
      "a confirmed track not seen for S seconds is no longer published (it is kept 2 s more for the object "
      "to be taken up again, then ends)"),
    {.type = RS_OPT_FUNC, .name = "track-set", .arg = "NAME=VALUE", .off = offsetof(T, tcfg),
     .fn = parse_track_set, .flags = RS_OPT_REPEAT,
     .help = "one tracker parameter (docs/tracking.md; a wrong name lists them)"},
    RS_OPT_HEAD("count", "Counting: confirmed tracks crossing lines of the site"),
    {.type = RS_OPT_FUNC, .name = "count-line", .arg = "\"NAME X1 Y1 X2 Y2\"", .off = offsetof(T, lines),
     .fn = rs_count_opt_line, .flags = RS_OPT_REPEAT,
     .help = "a line from (X1, Y1) to (X2, Y2), metres, in the site frame with --pose (the sensor frame "
             "otherwise); up to 16; each track counts once per line, forward (from the right of the line to "
             "its left, looking from X1 Y1 to X2 Y2) or backward, by class"},
    {.type = RS_OPT_FUNC, .name = "count-zone", .arg = "\"NAME X1 Y1 X2 Y2 X3 Y3 ...\"", .off = offsetof(T, zones),
     .fn = rs_count_opt_zone, .flags = RS_OPT_REPEAT,
     .help = "a zone: a polygon of 3 to 16 corners in order (metres, the frame of --count-line); up to 8; confirmed "
             "tracks that enter and exit it, by class, and the most inside at once"},
    D("count-interval", "S", count_interval, 1.0, 86400.0, "counts per interval of S seconds of sensor time"),
    D("count-hidden", "S", count_hidden, 0.0, 10.0,
      "a track first seen past a line, moving away from it, crossed it unseen when its path run back S seconds "
      "meets the line (a far lane hidden by the near lanes' traffic); not when the vehicle's earlier track was "
      "counted there (0 = off)"),
    D("count-hidden-window", "S", count_hidden_window, 0.0, 10.0,
      "the hidden-crossing check is repeated at each confirmed frame until S seconds after the track was first "
      "seen, with its mean velocity since then (0 = at its first confirmed frame only)"),
    {.type = RS_OPT_CHOICE, .name = "count-hidden-place", .arg = "WHERE", .off = offsetof(T, count_hidden_place),
     .choices = "track|path",
     .help = "where along the line a hidden crossing is placed, for telling it from another vehicle's: track, the "
             "track's place along the line (its lane) when the crossing is found; path, where its path run back "
             "met the line"},
    D("count-unseen", "S", count_unseen, 0.0, 10.0,
      "a confirmed track unseen for at most S seconds (coasting, or lost and kept), moving and of 5 hits or more, "
      "is followed on its prediction: a crossing there is held until it is seen again past the line (counted), "
      "before it (taken back) or ends (counted; 0 = off)"),
    D("count-same", "S", count_same, 0.0, 10.0,
      "a vehicle-sized track crossing a line within S seconds and 2.5 m along it of a crossing counted in its "
      "direction for another vehicle-sized track is that vehicle's second track: not counted (0 = off)"),
    {.type = RS_OPT_CHOICE, .name = "count-unseen-yield", .arg = "on|off", .off = offsetof(T, count_unseen_yield),
     .choices = "on|off",
     .help = "on: a crossing on a prediction still held gives way to another vehicle-sized track's seen crossing "
             "within --count-same seconds and 2.5 m (taken back; the seen one counted: a lost track's prediction "
             "running on over the line took the cars that crossed next for its second tracks); off: the seen one "
             "is not counted"},
    D("count-band", "M", count_band, 0.0, 5.0,
      "a seen track crosses a line when it is seen M metres past it, having been seen M metres before it (a "
      "standing vehicle's centre wanders); seen back M metres before the crossing is tallied takes it back (0 = "
      "at the line)"),
    D("count-class-delay", "S", count_class_delay, 0.0, 30.0,
      "a crossing is tallied S seconds after it, under the track's class then (its class settles as it comes "
      "near; 0 = at once)"),
    S("counts-out", "FILE", cfg.counts_out, "CSV t_start,t_end,line,direction,class,count per closed interval"),
    S("crossings-out", "FILE", cfg.crossings_out,
      "CSV t,line,direction,at,class,track,speed,how: one line per crossing counted, where along the line (m "
      "from its first end), the spot speed over 2 s around it (m/s, empty when unknown) and how it was found "
      "(seen, hidden, unseen)"),
    RS_OPT_HEAD("lcm", "LCM: per frame an object list, a track list and a statistics message; an event per "
                       "track that ends"),
    {.type = RS_OPT_STR, .name = "lcm-url", .arg = "URL", .off = offsetof(T, pub.url),
     .def = "$LCM_DEFAULT_URL, else " RS_PUB_DEFAULT_URL,
     .help = "LCM provider (memq:// and file://PATH?mode=w also work)"},
    S("channel", "NAME", pub.channel, "object lists"),
    S("stats-channel", "NAME", pub.stats_channel, "per-frame statistics ('none' = not sent)"),
    S("tracks-channel", "NAME", pub.tracks_channel, "track lists ('none' = not sent)"),
    S("track-ends-channel", "NAME", pub.track_ends_channel, "ended tracks ('none' = not sent)"),
    S("counts-channel", "NAME", pub.counts_channel, "counts per interval ('none' = not sent)"),
    S("crossings-channel", "NAME", pub.crossings_channel,
      "one message per crossing counted, with its spot speed, as --crossings-out ('none' = not sent)"),
    S("sensor-id", "ID", pub.sensor_id, "sensor_id field of every message"),
    I("max-datagram", "N", pub.max_datagram, RS_PUB_DATAGRAM_MIN, RS_PUB_DATAGRAM_MAX,
      "bytes of one LCM datagram; sets the object cap"),
    F("no-publish", no_publish, "do not publish (analysis runs)"),
    RS_OPT_HEAD("daemon", "Daemon"),
    {.type = RS_OPT_DOUBLE, .name = "budget-ms", .arg = "MS", .off = offsetof(T, cfg.budget_ms), .lo = 0.1,
     .hi = 10000, .def = "the frame period",
     .help = "processing budget per frame; overruns are counted and reported"},
    D("summary-seconds", "S", cfg.summary_s, 0.0, 86400.0, "one log line every S seconds (0 = none)"),
    F("syslog", use_syslog, "log to syslog (daemon facility) instead of stderr"),
    S("frames-out", "FILE", frames_path, "one CSV line per frame"),
    S("labels-out", "FILE", cfg.labels_out, "the pipeline's label of every return (specs/point-labels.md)"),
    S("objects-out", "FILE", cfg.objects_out,
      "one CSV line per object per frame (docs/objects-and-lcm.md; with --no-tracking its id is its returns' label - 2)"),
    F("quiet", quiet, "no summary at the end"),
    F("allow-root", allow_root,
      "run as root (refused otherwise: live capture needs only CAP_NET_RAW, a replay no privilege; the "
      "environment variable ROADSCAN_ALLOW_ROOT=1 does the same)"),
    I("processing-cpu", "N", cfg.processing_thread.cpu, 0, RS_THREAD_CPU_MAX,
      "run the processing thread on CPU N only (an isolated core: isolcpus=, a cpuset)"),
    I("packet-cpu", "N", cfg.packet_thread.cpu, 0, RS_THREAD_CPU_MAX, "run the packet thread on CPU N only"),
    I("rt-priority", "P", rt_priority, 1, RS_THREAD_PRIO_MAX - 1,
      "schedule the processing thread SCHED_FIFO at priority P and the packet thread at P + 1 (it never waits "
      "for the processing thread); needs CAP_SYS_NICE or an RLIMIT_RTPRIO of P + 1 (systemd: LimitRTPRIO=), "
      "refused with a message otherwise"),
    D("stall-ms", "MS", cfg.stall_ms, 0.0, 10000.0,
      "testing: the processing thread sleeps MS per frame (overload tests: drops are counted and published, "
      "capture never waits)"),
};
#undef T
#undef F
#undef S
#undef D
#undef I

static const rs_opts_spec_t spec = {
    .prog = "roadscand",
    .man_section = 8,
    .summary = "the roadside LiDAR daemon: Velodyne packets to object lists, track lists and counts over LCM",
    .synopsis = "[--config FILE] (--pcap FILE | --iface NAME) [options]",
    .about = "roadscand decodes the packets of a Velodyne sensor (live or from a capture), assembles a frame per "
             "rotation, removes the static scene (a background model), clusters what moves, follows every "
             "object over time and counts what crosses lines of the site. Per frame it publishes an object list, "
             "a track list and statistics over LCM; an example config is /usr/share/doc/roadscan/roadscand.ini.",
    .epilog = "SIGINT/SIGTERM stop cleanly and print the summary. Exit status: 0 done (input errors are counted "
              "in the summary), 1 fatal error (including an LCM URL that cannot publish, or no model learned and "
              "saved for --learn-out), 2 bad usage or configuration.",
    .config_file = true,
    .opts = table,
    .n = (int)(sizeof table / sizeof table[0]),
};
_Static_assert(sizeof table / sizeof table[0] <= RS_OPTS_MAX, "roadscand's options fit the parser");

/* Renames a stored model that cannot be used to PATH.WHY (a previous one of
 * that name is replaced): kept for a look, out of the way of the next start. */
static const char *set_aside(const char *path, const char *why) {
  static char to[4200];
  snprintf(to, sizeof to, "%s.%s", path, why);
  if (rename(path, to) != 0) snprintf(to, sizeof to, "(not renamed: %s)", strerror(errno));
  return to;
}

/* "none" turns a channel off */
static const char *channel_or_off(const char *ch) { return ch && strcmp(ch, "none") == 0 ? "" : ch; }

int main(int argc, char **argv) {
  rs_log_open("roadscand", false);
  rs_pipeline_cfg_t *cfg = &st.cfg;
  /* the defaults, from the modules that own them (--help shows these) */
  cfg->capture.speed = 1.0;
  st.port = RS_DEFAULT_DATA_PORT;
  cfg->stream.log = stderr;
  cfg->assembly.default_hz = 10.0;
  rs_bgu_cfg_t bgu;
  rs_bgu_cfg_default(&bgu);
  cfg->update_window_s = bgu.window_s;
  cfg->update_every_s = bgu.every_s;
  st.see_through = RS_BG_SEE_THROUGH;
  cfg->bg_shift_tol = RS_BG_SHIFT_TOL;
  cfg->bg_shift_deg = RS_BG_SHIFT_DEG;
  st.shift_gate_pct = RS_BG_SHIFT_GATE * 100.0;
  cfg->summary_s = 10.0;
  rs_cluster_cfg_default(&st.ccfg);
  rs_track_cfg_default(&st.tcfg);
  st.count_interval = 60.0;
  st.count_hidden = RS_COUNT_HIDDEN_S;
  st.count_hidden_window = RS_COUNT_HIDDEN_WINDOW_S;
  st.count_unseen = RS_COUNT_UNSEEN_S;
  st.count_same = RS_COUNT_SAME_S;
  st.count_band = RS_COUNT_BAND_M;
  st.count_class_delay = RS_COUNT_CLASS_DELAY_S;
  st.buffer_kib = RS_CAPTURE_BUFFER_DEFAULT / 1024;
  st.pub = (rs_publish_cfg_t){.channel = RS_PUB_DEFAULT_CHANNEL,
                              .stats_channel = RS_PUB_DEFAULT_STATS,
                              .tracks_channel = RS_PUB_DEFAULT_TRACKS,
                              .track_ends_channel = RS_PUB_DEFAULT_TRACK_ENDS,
                              .counts_channel = RS_PUB_DEFAULT_COUNTS,
                              .crossings_channel = RS_PUB_DEFAULT_CROSSINGS,
                              .sensor_id = "roadscan",
                              .max_datagram = RS_PUB_DATAGRAM_MAX};
  char err[RS_ERRMSG_SIZE];
  int first;
  const int start = rs_opts_start(&opts, &spec, &st, argc, argv, &first);
  if (start >= 0) return start;
  cfg->capture.data_port = (uint16_t)st.port;
  cfg->capture.buffer_bytes = st.buffer_kib * 1024;
  cfg->bg_see_through = st.see_through == 0 ? -1 : st.see_through;
  if (cfg->bg_shift_tol == 0) cfg->bg_shift_tol = -1;
  if (cfg->bg_shift_deg == 0) cfg->bg_shift_deg = -1;
  cfg->bg_shift_gate = st.shift_gate_pct > 0 ? st.shift_gate_pct / 100.0 : -1.0;
  cfg->labels_confirmed_only = st.labels_confirmed == 1;
  st.pub.stats_channel = channel_or_off(st.pub.stats_channel);
  st.pub.tracks_channel = channel_or_off(st.pub.tracks_channel);
  st.pub.track_ends_channel = channel_or_off(st.pub.track_ends_channel);
  st.pub.counts_channel = channel_or_off(st.pub.counts_channel);
  st.pub.crossings_channel = channel_or_off(st.pub.crossings_channel);
  const bool speed_set = rs_opts_given(&opts, "speed") > 0, have_pose = rs_opts_given(&opts, "pose") > 0;
  cfg->processing_thread.pin = rs_opts_given(&opts, "processing-cpu") > 0;
  cfg->packet_thread.pin = rs_opts_given(&opts, "packet-cpu") > 0;
  if (st.rt_priority > 0) {
    cfg->processing_thread.priority = st.rt_priority;
    cfg->packet_thread.priority = st.rt_priority + 1;
  }
  if (st.use_syslog) rs_log_open("roadscand", true);
  const char *allow_env = getenv("ROADSCAN_ALLOW_ROOT");
  if (geteuid() == 0 && !st.allow_root && !(allow_env && strcmp(allow_env, "1") == 0))
    return bad("refusing to run as root: live capture needs only CAP_NET_RAW (setcap cap_net_raw=eip on the "
               "binary, or the systemd unit's AmbientCapabilities=CAP_NET_RAW as an unprivileged user), a replay "
               "needs no privilege; --allow-root (or ROADSCAN_ALLOW_ROOT=1) overrides");
  if ((cfg->pcap_path == NULL) == (cfg->iface == NULL)) return bad("give exactly one source: --pcap FILE or --iface NAME");
  if (cfg->iface && (st.fast || speed_set || cfg->capture.loop)) return bad("--speed, --fast and --loop apply to --pcap only");
  if (st.fast && speed_set) return bad("--fast and --speed exclude each other");
  if (cfg->pcap_path && rs_opts_given(&opts, "capture-buffer-kib")) return bad("--capture-buffer-kib applies to --iface only");
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
  if (st.relearn && cfg->learn_out == NULL) return bad("--relearn needs --learn-out (the stored model)");
  /* learn once: a stored model is loaded instead of learning again; one that is not a model (a
   * crash cannot leave half of one: it is saved atomically) or not for this sensor is set aside */
  bool stored = false;
  if (cfg->learn_out && !st.relearn && access(cfg->learn_out, F_OK) == 0) {
    const int lrc = rs_bg_load(&bgmodel, cfg->learn_out, err, sizeof err);
    if (lrc == RS_E_FORMAT) {
      rs_log(RS_LOG_WARN, "background: %s; it is set aside as %s and learned anew", err,
             set_aside(cfg->learn_out, "unreadable"));
    } else if (lrc != RS_OK) {
      rs_log(RS_LOG_ERR, "%s", err);
      return 1;
    } else if ((cfg->stream.force_model != RS_MODEL_UNKNOWN && cfg->stream.force_model != bgmodel.model) ||
               (cfg->assembly.columns && cfg->assembly.columns != bgmodel.cols)) {
      rs_log(RS_LOG_WARN, "background: the stored model %s (%s, %u columns) does not fit --model/--columns; it is set "
             "aside as %s and learned anew", cfg->learn_out, rs_model_name(bgmodel.model), bgmodel.cols,
             set_aside(cfg->learn_out, rs_model_name(bgmodel.model)));
      rs_bg_model_free(&bgmodel);
    } else {
      rs_log(RS_LOG_INFO, "background: the stored model %s (learned from %u frames of a %s) is used; --relearn learns "
             "anew", cfg->learn_out, bgmodel.frames, rs_model_name(bgmodel.model));
      st.bg_path = cfg->learn_out;
      stored = true;
      cfg->learn_seconds = 0;
      cfg->learn_out = NULL;
    }
  }
  if (st.bg_path && !stored) {
    if (rs_bg_load(&bgmodel, st.bg_path, err, sizeof err) != RS_OK) {
      rs_log(RS_LOG_ERR, "%s", err);
      return 1;
    }
  }
  if (st.bg_path) {
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
  st.ccfg.method = rs_opts_given(&opts, "cluster") ? (rs_cluster_method_t)st.method
                   : (st.bg_path || cfg->learn_seconds > 0) ? RS_CLUSTER_FSPC_ADAPTIVE
                                                            : RS_CLUSTER_NONE;
  /* --eps, --min-pts, --window: the chosen method's own */
  const char *method = rs_cluster_method_name(st.ccfg.method);
  if (rs_opts_given(&opts, "eps") && !rs_cluster_cfg_set_eps(&st.ccfg, (float)st.eps))
    return bad("--eps needs a clustering method (--cluster)");
  if (rs_opts_given(&opts, "min-pts") && !rs_cluster_cfg_set_min_pts(&st.ccfg, st.min_pts)) {
    snprintf(err, sizeof err, "--min-pts: --cluster %s has no minPts", method);
    return bad(err);
  }
  if (rs_opts_given(&opts, "window") && !rs_cluster_cfg_set_window(&st.ccfg, st.window[0], st.window[1])) {
    snprintf(err, sizeof err, "--window: --cluster %s has no window", method);
    return bad(err);
  }
  if (st.ccfg.method != RS_CLUSTER_NONE) {
    if (rs_cluster_init(&cluster, &st.ccfg, NULL) != RS_OK) return bad("bad clustering parameters");
    cfg->cluster = &cluster;
  }
  if (cfg->cluster) {
    rs_objects_init(&objects, have_pose ? &st.pose : NULL);
    cfg->objects = &objects;
    cfg->object_list = &object_list;
    if (!st.no_tracking) {
      if (st.tcfg.birth_far_points > 0 && !(st.tcfg.birth_far_from_m < st.tcfg.birth_far_to_m)) {
        rs_log(RS_LOG_ERR, "tracking parameters: birth_far_from_m (%g m) is not below birth_far_to_m (%g m): no far walker "
               "could start a track (birth_far_points=0 turns that off)", st.tcfg.birth_far_from_m, st.tcfg.birth_far_to_m);
        return 2;
      }
      if (rs_track_init(&tracker, &st.tcfg) != RS_OK) return bad("bad tracking parameters");
      rs_track_set_pose(&tracker, have_pose ? &st.pose : NULL);
      cfg->tracker = &tracker;
    }
  }
  if (cfg->objects_out && cfg->cluster == NULL) return bad("--objects-out needs clustering");
  if (cfg->tracks_out && cfg->tracker == NULL) return bad("--tracks-out needs tracking (clustering, no --no-tracking)");
  if ((st.lines.n > 0 || st.zones.n > 0 || cfg->counts_out || cfg->crossings_out) && cfg->tracker == NULL)
    return bad("counting needs tracking (clustering, no --no-tracking)");
  if (cfg->counts_out && st.lines.n == 0 && st.zones.n == 0) return bad("--counts-out needs a --count-line or --count-zone");
  if (cfg->crossings_out && st.lines.n == 0) return bad("--crossings-out needs a --count-line");
  if (st.lines.n > 0 || st.zones.n > 0) {
    if (rs_count_init(&counter, st.lines.line, st.lines.n, have_pose ? &st.pose : NULL, st.count_interval, err,
                      sizeof err) != RS_OK ||
        rs_count_add_zones(&counter, st.zones.zone, st.zones.n, err, sizeof err) != RS_OK)
      return bad(err);
    counter.hidden_s = st.count_hidden;
    counter.hidden_window_s = st.count_hidden_window;
    counter.hidden_at_track = st.count_hidden_place == 0; /* track */
    counter.unseen_s = st.count_unseen;
    counter.same_s = st.count_same;
    counter.unseen_yield = st.count_unseen_yield == 0; /* on */
    counter.band_m = st.count_band;
    counter.class_delay_s = st.count_class_delay;
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
  if (!rs_notify_init(&notify, err, sizeof err)) rs_log(RS_LOG_WARN, "service manager: %s; not notified", err);
  cfg->notify = &notify;
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
    rs_log(RS_LOG_ERR, "cannot start threads: %s", pipeline.input_err[0] ? pipeline.input_err : rs_strerror(rc));
    if (rc == RS_E_PERM)
      rs_log(RS_LOG_ERR, "--rt-priority %d needs CAP_SYS_NICE or an RLIMIT_RTPRIO of %d (the packet thread's)",
             st.rt_priority, st.rt_priority + 1);
    rs_pipeline_deinit(&pipeline);
    rs_publish_deinit(&publisher);
    return 1;
  }
  /* ready: the source is open, the publisher works, the threads run */
  rs_notify_ready(&notify, cfg->iface ? "capturing" : "replaying");
  rs_pipeline_join(&pipeline);
  rs_notify_send(&notify, "STOPPING=1");
  int status = 0;
  if (pipeline.input_status != RS_OK) {
    rs_log(RS_LOG_ERR, "input ended early: %s", pipeline.input_err);
    if (pipeline.input_status != RS_E_TRUNCATED) status = 1;
    if (stored && pipeline.model_mismatch) /* the sensor was changed: the next start learns its model */
      rs_log(RS_LOG_WARN, "background: the stored model is set aside as %s; the next start learns the sensor's",
             set_aside(st.bg_path, rs_model_name(bgmodel.model)));
  }
  if (!st.quiet) rs_pipeline_summary(&pipeline, stderr);
  /* deinit joins the learner (a model still being learned at the input's end is saved first): what
   * it did is final; --learn-out with no model saved says why and exits 1 */
  rs_pipeline_deinit(&pipeline);
  if (cfg->learn_out && !pipeline.proc.bgu.saved) {
    if (pipeline.proc.bgu.save_failed)
      rs_log(RS_LOG_ERR, "--learn-out %s: the model learned was not saved (the error above)", cfg->learn_out);
    else if (pipeline.proc.bgu.store_rc != RS_OK)
      rs_log(RS_LOG_ERR, "--learn-out %s: no model was learned and nothing saved: its samples could not be reserved (%s)",
             cfg->learn_out, rs_strerror(pipeline.proc.bgu.store_rc));
    else
      rs_log(RS_LOG_ERR,
             "--learn-out %s: no model was learned and nothing saved: the input ended when %d complete frames of "
             "the %.1f s to learn from (--learn-seconds) had been kept",
             cfg->learn_out, pipeline.proc.bgu.kept, cfg->learn_seconds);
    status = 1;
  }
  rs_publish_deinit(&publisher);
  rs_notify_deinit(&notify);
  if (st.bg_path) rs_bg_model_free(&bgmodel);
  if (frames && fclose(frames) != 0) {
    rs_log(RS_LOG_ERR, "--frames-out %s: write failed", st.frames_path);
    status = 1;
  }
  return status;
}

/* roadscand - the roadside LiDAR daemon.
 *
 * Main thread: parses options, loads calibration, starts the pipeline
 * (packet thread + processing thread), waits, prints the summary. Signal
 * handlers only set the pipeline's stop flag. All large state is static. */
#include "roadscan/calib.h"
#include "roadscan/config.h"
#include "roadscan/error.h"
#include "roadscan/pipeline.h"

#include <getopt.h>
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

static void usage(FILE *out) {
  fprintf(out,
          "usage: roadscand (--pcap FILE | --iface NAME) [options]\n"
          "\n"
          "Source\n"
          "  --pcap FILE          replay a pcap or pcapng capture\n"
          "  --speed X            replay at X times the original timing (default 1)\n"
          "  --fast               replay as fast as possible, never dropping a frame (analysis)\n"
          "  --loop               start the capture again at its end\n"
          "  --iface NAME         capture live from a network interface (needs CAP_NET_RAW)\n"
          "  --port N             sensor data UDP port (default 2368)\n"
          "  --source ADDR        only packets from this sensor address\n"
          "Sensor\n"
          "  --model NAME         force the model: %s\n"
          "                       (default: detected from the packets)\n"
          "  --calibration FILE   per-unit calibration (ROS velodyne YAML)\n"
          "  --rpm N              rotation rate assumed until one is measured (default 600)\n"
          "Background\n"
          "  --background MODEL   static-scene model (roadscan-learn): its returns are labelled 1,\n"
          "                       the rest 2 until clustering\n"
          "  --learn-seconds N    with no --background: learn the model from the first N seconds\n"
          "                       of frames, then subtract it (real-time replay drops frames while\n"
          "                       it learns; --fast does not)\n"
          "  --learn-out MODEL    save the model learned online\n"
          "Clustering (of the foreground)\n"
          "  --cluster METHOD     fspc (default with a background), fspc-adaptive, dbscan, ccl, none\n"
          "  --window HxW         FSPC window, odd numbers (default 5x11)\n"
          "  --eps M              FSPC range difference (default 1.8); DBSCAN radius with --cluster dbscan (1.2)\n"
          "  --min-pts N          core threshold, the centre counted (default 15)\n"
          "Frames\n"
          "  --columns N          azimuth bins of the map (default: from the measured rate)\n"
          "  --cut-azimuth DEG    azimuth where frames start (default 0)\n"
          "Output\n"
          "  --frames-out FILE    one CSV line per frame\n"
          "  --labels-out FILE    the pipeline's label of every return (specs/point-labels.md)\n"
          "  --quiet              no summary\n"
          "  --help, --version\n"
          "\n"
          "SIGINT/SIGTERM stop cleanly and print the summary. Exit status: 0 done (input errors are\n"
          "counted in the summary), 1 fatal error, 2 bad usage.\n",
          rs_model_names());
}

static void on_signal(int sig) {
  (void)sig;
  rs_pipeline_request_stop(&pipeline);
}

static int bad(const char *msg) {
  fprintf(stderr, "roadscand: %s\n", msg);
  return 2;
}

int main(int argc, char **argv) {
  enum { O_PCAP = 256, O_SPEED, O_FAST, O_LOOP, O_IFACE, O_PORT, O_SOURCE, O_MODEL, O_CALIB, O_RPM, O_COLS,
         O_CUT, O_FRAMES, O_LABELS, O_BG, O_LEARN, O_LEARN_OUT, O_CLUSTER, O_WINDOW, O_EPS, O_MINPTS, O_QUIET, O_HELP, O_VERSION };
  static const struct option opts[] = {
      {"pcap", required_argument, NULL, O_PCAP},       {"speed", required_argument, NULL, O_SPEED},
      {"fast", no_argument, NULL, O_FAST},             {"loop", no_argument, NULL, O_LOOP},
      {"iface", required_argument, NULL, O_IFACE},     {"port", required_argument, NULL, O_PORT},
      {"source", required_argument, NULL, O_SOURCE},   {"model", required_argument, NULL, O_MODEL},
      {"calibration", required_argument, NULL, O_CALIB}, {"rpm", required_argument, NULL, O_RPM},
      {"columns", required_argument, NULL, O_COLS},    {"cut-azimuth", required_argument, NULL, O_CUT},
      {"frames-out", required_argument, NULL, O_FRAMES}, {"labels-out", required_argument, NULL, O_LABELS},
      {"background", required_argument, NULL, O_BG},  {"quiet", no_argument, NULL, O_QUIET},
      {"learn-seconds", required_argument, NULL, O_LEARN}, {"learn-out", required_argument, NULL, O_LEARN_OUT},
      {"cluster", required_argument, NULL, O_CLUSTER}, {"window", required_argument, NULL, O_WINDOW},
      {"eps", required_argument, NULL, O_EPS},          {"min-pts", required_argument, NULL, O_MINPTS},
      {"help", no_argument, NULL, O_HELP},             {"version", no_argument, NULL, O_VERSION},
      {NULL, 0, NULL, 0}};
  rs_pipeline_cfg_t cfg;
  memset(&cfg, 0, sizeof cfg);
  cfg.capture.speed = 1.0;
  cfg.capture.data_port = RS_DEFAULT_DATA_PORT;
  cfg.stream.log = stderr;
  cfg.assembly.default_hz = 10.0;
  const char *frames_path = NULL, *calib_path = NULL, *bg_path = NULL;
  bool quiet = false, fast = false, speed_set = false, cluster_set = false;
  double eps_set = 0;
  rs_cluster_cfg_t ccfg;
  rs_cluster_cfg_default(&ccfg);
  char err[RS_ERRMSG_SIZE];
  double d;
  long l;
  int c;
  while ((c = getopt_long(argc, argv, "", opts, NULL)) != -1) {
    switch (c) {
    case O_PCAP: cfg.pcap_path = optarg; break;
    case O_IFACE: cfg.iface = optarg; break;
    case O_SPEED:
      if (rs_cfg_double("--speed", optarg, 0.001, 1000.0, &cfg.capture.speed, err, sizeof err)) return bad(err);
      speed_set = true;
      break;
    case O_FAST: fast = true; break;
    case O_LOOP: cfg.capture.loop = true; break;
    case O_PORT:
      if (rs_cfg_long("--port", optarg, 1, 65535, &l, err, sizeof err)) return bad(err);
      cfg.capture.data_port = (uint16_t)l;
      break;
    case O_SOURCE: cfg.capture.source_addr = optarg; break;
    case O_MODEL:
      cfg.stream.force_model = rs_model_from_name(optarg);
      if (cfg.stream.force_model == RS_MODEL_UNKNOWN) {
        snprintf(err, sizeof err, "--model: unknown sensor '%s' (known: %s)", optarg, rs_model_names());
        return bad(err);
      }
      break;
    case O_CALIB: calib_path = optarg; break;
    case O_RPM:
      if (rs_cfg_double("--rpm", optarg, 300.0, 1200.0, &d, err, sizeof err)) return bad(err);
      cfg.assembly.default_hz = d / 60.0;
      break;
    case O_COLS:
      if (rs_cfg_long("--columns", optarg, RS_MIN_COLS, RS_MAX_COLS, &l, err, sizeof err)) return bad(err);
      cfg.assembly.columns = (int)l;
      break;
    case O_CUT:
      if (rs_cfg_double("--cut-azimuth", optarg, 0.0, 359.99, &cfg.assembly.cut_deg, err, sizeof err)) return bad(err);
      break;
    case O_FRAMES: frames_path = optarg; break;
    case O_LABELS: cfg.labels_out = optarg; break;
    case O_BG: bg_path = optarg; break;
    case O_LEARN:
      if (rs_cfg_double("--learn-seconds", optarg, 1.0, 3600.0, &cfg.learn_seconds, err, sizeof err)) return bad(err);
      break;
    case O_LEARN_OUT: cfg.learn_out = optarg; break;
    case O_CLUSTER: {
      int m = rs_cluster_method_from_name(optarg);
      if (m < 0) {
        snprintf(err, sizeof err, "--cluster: '%s' is not fspc, fspc-adaptive, dbscan, ccl or none", optarg);
        return bad(err);
      }
      ccfg.method = (rs_cluster_method_t)m;
      cluster_set = true;
      break;
    }
    case O_WINDOW: {
      int h, w;
      char tail;
      if (sscanf(optarg, "%dx%d%c", &h, &w, &tail) != 2 || h < 1 || w < 1 || h % 2 == 0 || w % 2 == 0 ||
          h > RS_MAX_WIN_H || w > RS_MAX_WIN_W) {
        snprintf(err, sizeof err, "--window: '%s' is not HxW with odd H <= %d and odd W <= %d", optarg, RS_MAX_WIN_H,
                 RS_MAX_WIN_W);
        return bad(err);
      }
      ccfg.win_h = h;
      ccfg.win_w = w;
      break;
    }
    case O_EPS:
      if (rs_cfg_double("--eps", optarg, 0.01, 50.0, &d, err, sizeof err)) return bad(err);
      eps_set = d;
      break;
    case O_MINPTS:
      if (rs_cfg_long("--min-pts", optarg, 1, 255, &l, err, sizeof err)) return bad(err);
      ccfg.min_pts = ccfg.dbscan_min_pts = (int)l;
      break;
    case O_QUIET: quiet = true; break;
    case O_HELP: usage(stdout); return 0;
    case O_VERSION: printf("roadscand 0.1.0\n"); return 0;
    default: usage(stderr); return 2;
    }
  }
  if (optind < argc) {
    snprintf(err, sizeof err, "unexpected argument '%s' (see --help)", argv[optind]);
    return bad(err);
  }
  if ((cfg.pcap_path == NULL) == (cfg.iface == NULL)) return bad("give exactly one source: --pcap FILE or --iface NAME");
  if (cfg.iface && (fast || speed_set || cfg.capture.loop)) return bad("--speed, --fast and --loop apply to --pcap only");
  if (fast && speed_set) return bad("--fast and --speed exclude each other");
  if (fast) {
    cfg.capture.speed = 0.0;
    cfg.lossless = true;
  }
  cfg.stream.data_port = cfg.capture.data_port;
  cfg.stream.source_addr = cfg.capture.source_addr;
  cfg.stream.default_hz = cfg.assembly.default_hz;
  if (calib_path) {
    if (rs_calib_load_yaml(calib_path, &calib, err, sizeof err) != RS_OK) {
      fprintf(stderr, "roadscand: %s\n", err);
      return 1;
    }
    cfg.stream.calib = &calib;
  }
  if (bg_path && cfg.learn_seconds > 0) return bad("--background and --learn-seconds exclude each other");
  if (cfg.learn_out && cfg.learn_seconds <= 0) return bad("--learn-out needs --learn-seconds");
  if (bg_path) {
    if (rs_bg_load(&bgmodel, bg_path, err, sizeof err) != RS_OK) {
      fprintf(stderr, "roadscand: %s\n", err);
      return 1;
    }
    if (cfg.stream.force_model != RS_MODEL_UNKNOWN && cfg.stream.force_model != bgmodel.model) {
      fprintf(stderr, "roadscand: %s: the model is for a %s, --model says %s\n", bg_path, rs_model_name(bgmodel.model),
              rs_model_name(cfg.stream.force_model));
      return 1;
    }
    if (cfg.assembly.columns && cfg.assembly.columns != bgmodel.cols) {
      fprintf(stderr, "roadscand: %s: the model has %u columns, --columns says %d\n", bg_path, bgmodel.cols,
              cfg.assembly.columns);
      return 1;
    }
    cfg.background = &bgmodel;
  }
  if (!cluster_set) ccfg.method = (bg_path || cfg.learn_seconds > 0) ? RS_CLUSTER_FSPC : RS_CLUSTER_NONE;
  if (eps_set > 0) {
    if (ccfg.method == RS_CLUSTER_DBSCAN) ccfg.dbscan_eps = (float)eps_set;
    else if (ccfg.method == RS_CLUSTER_CCL) ccfg.ccl_eps = (float)eps_set;
    else ccfg.eps = (float)eps_set;
  }
  if (ccfg.method != RS_CLUSTER_NONE) {
    if (rs_cluster_init(&cluster, &ccfg, NULL) != RS_OK) return bad("bad clustering parameters");
    cfg.cluster = &cluster;
  }
  FILE *frames = NULL;
  if (frames_path) {
    frames = fopen(frames_path, "w");
    if (frames == NULL) {
      fprintf(stderr, "roadscand: --frames-out %s: cannot write: ", frames_path);
      perror(NULL);
      return 1;
    }
    fprintf(frames, "%s\n", rs_pipeline_csv_header());
    cfg.frames_out = frames;
  }
  int rc = rs_pipeline_init(&pipeline, &cfg, slots, RING_SLOTS);
  if (rc != RS_OK) {
    fprintf(stderr, "roadscand: %s\n", pipeline.input_err[0] ? pipeline.input_err : rs_strerror(rc));
    if (frames) fclose(frames);
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
    fprintf(stderr, "roadscand: cannot start threads: %s\n", rs_strerror(rc));
    rs_pipeline_deinit(&pipeline);
    return 1;
  }
  rs_pipeline_join(&pipeline);
  int status = 0;
  if (pipeline.input_status != RS_OK) {
    fprintf(stderr, "roadscand: input ended early: %s\n", pipeline.input_err);
    if (pipeline.input_status != RS_E_TRUNCATED) status = 1;
  }
  if (!quiet) rs_pipeline_summary(&pipeline, stderr);
  rs_pipeline_deinit(&pipeline);
  if (bg_path) rs_bg_model_free(&bgmodel);
  if (frames && fclose(frames) != 0) {
    fprintf(stderr, "roadscand: --frames-out %s: write failed\n", frames_path);
    status = 1;
  }
  return status;
}

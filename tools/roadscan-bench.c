/* roadscan-bench - throughput and per-stage timing of decoding and frame
 * assembly, flat out on one core (CLOCK_MONOTONIC).
 *
 *   roadscan-bench [--seconds S]            synthetic packets of every model and mode
 *   roadscan-bench CAPTURE [--model NAME]   the data packets of a capture
 *
 * Packets are loaded into memory first, so file I/O is not timed. */
#include "roadscan/perception/background.h"
#include "roadscan/perception/cluster.h"
#include "roadscan/perception/objects.h"
#include "roadscan/perception/proc.h"
#include "roadscan/output/publish.h"
#include "roadscan/util/opts.h"
#include "roadscan/util/thread.h"
#include "roadscan/util/error.h"
#include "roadscan/frame/frame.h"
#include "roadscan/frame/framer.h"
#include "roadscan/capture/net.h"
#include "roadscan/capture/stream.h"
#include "roadscan/sim/synth.h"
#include "roadscan/util/timing.h"
#include "roadscan/perception/track.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static rs_slot_t slots[2];
static rs_cluster_t cluster;
static rs_bg_model_t bgm;

/* per-frame stage timings of a capture run with a background model: the
 * daemon's stages (rs_proc_frame, as roadscand runs it), then each
 * clustering method alone on the same frame */
enum { ST_DECODE, ST_ASSEMBLY, ST_BACKGROUND, ST_CLUSTER, ST_OBJECTS, ST_TRACKS, ST_ENCODE, ST_PROCESSING,
       ST_FSPC, ST_FSPC_ADAPTIVE, ST_DBSCAN, ST_CCL, ST_COUNT };
static const char *stage_names[ST_COUNT] = {"decode", "assembly", "background", "cluster", "objects", "tracks",
                                            "lcm encode", "processing (all stages)", "fspc", "fspc-adaptive", "dbscan",
                                            "ccl"};
static const char *stage_cols[ST_COUNT] = {"decode_us", "assembly_us", "background_us", "cluster_us", "objects_us",
                                           "tracks_us", "encode_us", "processing_us", "fspc_us", "fspc_adaptive_us",
                                           "dbscan_us", "ccl_us"};
static rs_tracker_t tracker;
static rs_objects_t objects;
static rs_object_list_t object_list;
static rs_publish_t publisher;
static rs_proc_t proc;
static rs_cluster_t proc_cluster;
static rs_timing_t stage_t[ST_COUNT];
static rs_packet_t pkt;
static rs_timing_t t_decode, t_assemble, t_frame;

typedef struct {
  uint8_t *data; /* n * RS_PAYLOAD_SIZE */
  double *ts;
  size_t n, cap;
} pkts_t;

static int push(pkts_t *p, const uint8_t *payload, double ts) {
  if (p->n == p->cap) {
    size_t nc = p->cap ? p->cap * 2 : 4096;
    uint8_t *nd = realloc(p->data, nc * RS_PAYLOAD_SIZE);
    if (nd == NULL) return -1;
    p->data = nd;
    double *nt = realloc(p->ts, nc * sizeof *nt);
    if (nt == NULL) return -1;
    p->ts = nt;
    p->cap = nc;
  }
  memcpy(p->data + p->n * RS_PAYLOAD_SIZE, payload, RS_PAYLOAD_SIZE);
  p->ts[p->n++] = ts;
  return 0;
}

typedef struct {
  FILE *csv;
  bool with_model;
  rs_cluster_method_t method; /* the daemon's clustering */
  const rs_sensor_t *sensor;
  int best_of;          /* each clustering method runs this many times per frame; the fastest counts */
  int64_t dec_ns, asm_ns; /* of the frame being assembled */
  uint64_t frames;
  double fg_sum;
  uint32_t fg_max;
  uint64_t encode_errors;
  double tracks_sum;
  uint32_t tracks_max;
} stages_t;
static stages_t sg;

static void frame_stages(rs_slot_t *s) {
  int64_t t[ST_COUNT] = {0};
  t[ST_DECODE] = sg.dec_ns;
  t[ST_ASSEMBLY] = sg.asm_ns;
  sg.dec_ns = sg.asm_ns = 0;
  if (s->meta.partial || s->meta.cols != bgm.cols) return;
  /* the daemon's stages */
  rs_proc_report_t r;
  rs_proc_frame(&proc, s, sg.sensor, &r);
  t[ST_BACKGROUND] = r.stage_ns[RS_STAGE_BACKGROUND];
  t[ST_CLUSTER] = r.stage_ns[RS_STAGE_CLUSTER];
  t[ST_OBJECTS] = r.stage_ns[RS_STAGE_OBJECTS];
  t[ST_TRACKS] = r.stage_ns[RS_STAGE_TRACKS];
  if (r.tracks) {
    uint32_t alive = 0;
    for (uint32_t i = 0; i < r.tracks->count; i++) alive += r.tracks->track[i].state != RS_TRACK_LOST;
    sg.tracks_sum += alive;
    if (alive > sg.tracks_max) sg.tracks_max = alive;
  }
  t[ST_PROCESSING] = r.total_ns;
  int64_t a = rs_now_ns();
  roadscan_object_list_t msg;
  rs_publish_fill(&publisher, &s->meta, r.objects, 0, &msg);
  if (roadscan_object_list_t_encode(publisher.buf, 0, (int)sizeof publisher.buf, &msg) < 0) sg.encode_errors++;
  t[ST_ENCODE] = rs_now_ns() - a;
  const uint32_t fg = r.foreground;
  /* each method alone on the same foreground (labels of the map are reset by each run) */
  static const rs_cluster_method_t ms[4] = {RS_CLUSTER_FSPC, RS_CLUSTER_FSPC_ADAPTIVE, RS_CLUSTER_DBSCAN, RS_CLUSTER_CCL};
  rs_cluster_stats_t cs;
  for (int k = 0; k < 4; k++) {
    cluster.cfg.method = ms[k];
    t[ST_FSPC + k] = INT64_MAX;
    for (int rep = 0; rep < sg.best_of; rep++) {
      a = rs_now_ns();
      rs_cluster_run(&cluster, s, &cs);
      const int64_t dt = rs_now_ns() - a;
      if (dt < t[ST_FSPC + k]) t[ST_FSPC + k] = dt;
    }
  }
  for (int k = 0; k < ST_COUNT; k++) rs_timing_add(&stage_t[k], t[k]);
  sg.frames++;
  sg.fg_sum += fg;
  if (fg > sg.fg_max) sg.fg_max = fg;
  if (sg.csv) {
    fprintf(sg.csv, "%llu,%u", (unsigned long long)s->meta.seq, fg);
    for (int k = 0; k < ST_COUNT; k++) fprintf(sg.csv, ",%.1f", (double)t[k] / 1000.0);
    fprintf(sg.csv, "\n");
  }
}

static double median_us(int k) { return rs_timing_pct_us(&stage_t[k], 50); }

static void print_stages(void) {
  printf("per frame (%llu frames, foreground returns mean %.0f, max %u), CLOCK_MONOTONIC, one core;\n"
         "the daemon's stages with --cluster %s, then each method alone:\n",
         (unsigned long long)sg.frames, sg.frames ? sg.fg_sum / (double)sg.frames : 0.0, sg.fg_max,
         rs_cluster_method_name(sg.method));
  for (int k = 0; k < ST_COUNT; k++) {
    stage_t[k].name = stage_names[k];
    rs_timing_print(&stage_t[k], stdout);
  }
  printf("tracks alive per frame: mean %.0f, max %u\n", sg.frames ? sg.tracks_sum / (double)sg.frames : 0.0,
         sg.tracks_max);
  printf("stage ratio of medians: objects/cluster %.2f, tracks/cluster %.2f\n",
         median_us(ST_OBJECTS) / median_us(ST_CLUSTER), median_us(ST_TRACKS) / median_us(ST_CLUSTER));
  printf("ratios of medians: FSPC/DBSCAN %.4f (DBSCAN %.0fx slower), FSPC/CCL %.2f, FSPC-adaptive/FSPC %.2f\n",
         median_us(ST_FSPC) / median_us(ST_DBSCAN), median_us(ST_DBSCAN) / median_us(ST_FSPC),
         median_us(ST_FSPC) / median_us(ST_CCL), median_us(ST_FSPC_ADAPTIVE) / median_us(ST_FSPC));
}

/* One pass over the packets: decode, then the framer the daemon's tools share (assembly, slot swap,
 * rate feedback; with a model every finished frame runs the stages); returns points decoded. */
typedef struct {
  bool timed;
  uint64_t frames;
  int64_t frame_ns, stage_ns;
} pass_t;
static rs_framer_t bench_framer;

static void on_bench_frame(void *user, rs_slot_t *slot) {
  pass_t *ps = user;
  ps->frames++;
  if (ps->timed) rs_timing_add(&t_frame, ps->frame_ns);
  ps->frame_ns = 0;
  if (sg.with_model) {
    const int64_t a = rs_now_ns();
    frame_stages(slot);
    ps->stage_ns += rs_now_ns() - a;
  }
}

static uint64_t run_pass(const rs_sensor_t *s, const pkts_t *p, const rs_asm_cfg_t *acfg, uint64_t *frames,
                         bool timed) {
  pass_t ps = {.timed = timed};
  rs_framer_t *f = &bench_framer;
  rs_framer_start(f, acfg, s, slots, on_bench_frame, &ps);
  uint64_t points = 0;
  for (size_t i = 0; i < p->n; i++) {
    const int64_t t0 = rs_now_ns();
    if (rs_packet_decode(s, p->data + i * RS_PAYLOAD_SIZE, RS_PAYLOAD_SIZE, f->as.rate, &pkt) != RS_OK) continue;
    const int64_t t1 = rs_now_ns();
    ps.stage_ns = 0;
    rs_framer_feed(f, &pkt, (uint32_t)i, p->ts[i]);
    const int64_t t_asm = rs_now_ns() - t1 - ps.stage_ns; /* the stages are timed apart */
    sg.dec_ns += t1 - t0;
    sg.asm_ns += t_asm;
    points += pkt.n_points;
    ps.frame_ns += t1 - t0 + t_asm;
    if (timed) {
      rs_timing_add(&t_decode, t1 - t0);
      rs_timing_add(&t_assemble, t_asm);
    }
  }
  *frames += ps.frames;
  return points;
}

/* The tracker alone on n synthetic objects crossing a site at 10 Hz for the
 * given seconds (straight lines at 1-15 m/s, box centres with 0.2 m noise,
 * a few objects leaving and new ones entering every frame): the stage's time
 * per frame at that many tracks. */
static int tracker_bench(int n, double seconds) {
  static rs_object_list_t ol;
  rs_track_cfg_t tc;
  rs_track_cfg_default(&tc);
  rs_track_init(&tracker, &tc);
  rs_timing_t t;
  rs_timing_init(&t, "tracks/frame");
  uint64_t rng = 88172645463325252ull;
#define RND() (rng ^= rng << 13, rng ^= rng >> 7, rng ^= rng << 17, (double)(rng >> 11) / 9007199254740992.0)
  static double px[RS_OBJ_MAX], py[RS_OBJ_MAX], vx[RS_OBJ_MAX], vy[RS_OBJ_MAX];
  for (int k = 0; k < n; k++) {
    px[k] = -150 + 300 * RND();
    py[k] = -150 + 300 * RND();
    double sp = 1 + 14 * RND(), a = 6.283185307179586 * RND();
    vx[k] = sp * cos(a);
    vy[k] = sp * sin(a);
  }
  const int frames = (int)(seconds * 10.0);
  uint64_t alive_sum = 0;
  for (int f = 0; f < frames; f++) {
    const double tf = 1700000000.0 + 0.1 * f;
    memset(&ol, 0, sizeof ol);
    ol.count = (uint32_t)n;
    for (int k = 0; k < n; k++) {
      px[k] += 0.1 * vx[k];
      py[k] += 0.1 * vy[k];
      if (fabs(px[k]) > 150 || fabs(py[k]) > 150) { /* left: another one enters */
        px[k] = -150 + 300 * RND();
        py[k] = -150 + 300 * RND();
      }
      rs_object_t *o = &ol.obj[k];
      o->id = (uint32_t)k + 1;
      o->points = 40;
      o->sensor.obb_center[0] = (float)(px[k] + 0.2 * (RND() - 0.5));
      o->sensor.obb_center[1] = (float)(py[k] + 0.2 * (RND() - 0.5));
      o->sensor.obb_length = 4.5f;
      o->sensor.obb_width = 1.8f;
      o->sensor.obb_heading = (float)atan2(vy[k], vx[k]);
      o->sensor.box_min[2] = -1.8f;
      o->sensor.box_max[2] = -0.3f;
      o->t_first = o->t_last = tf - 0.05;
    }
    const int64_t a = rs_now_ns();
    rs_track_frame(&tracker, &ol, tf);
    const int64_t b = rs_now_ns();
    if (f >= 10) rs_timing_add(&t, b - a); /* once the tracks exist */
    alive_sum += tracker.list.count;
  }
#undef RND
  printf("tracker alone, %d synthetic objects at 10 Hz for %.0f s (one core): tracks alive mean %.0f\n", n, seconds,
         frames ? (double)alive_sum / frames : 0.0);
  rs_timing_print(&t, stdout);
  return 0;
}

static double packet_rate(const rs_model_info_t *mi, bool dual) {
  return 1e6 / (rs_layout_groups(mi, dual) * rs_model_group_us(mi));
}

static int synthetic(double seconds) {
  printf("decode + frame assembly, flat out, one core, synthetic scene (10 Hz)\n");
  printf("%-12s %-9s %10s %12s %12s %10s %9s\n", "model", "mode", "packets", "packets/s", "Mpoints/s", "us/packet",
         "x realtime");
  static const uint8_t modes[2] = {RS_MODE_STRONGEST, RS_MODE_DUAL};
  for (int m = RS_MODEL_VLP16; m < RS_MODEL_COUNT; m++) {
    for (int mi = 0; mi < 2; mi++) {
      rs_synth_cfg_t cfg = {.model = (rs_model_t)m, .mode = modes[mi], .hz = 10.0, .seconds = 1.0, .t0 = 1e9};
      rs_sensor_t s;
      rs_sensor_init(&s, (rs_model_t)m);
      pkts_t p = {0};
      uint32_t n = rs_synth_count(&cfg);
      static rs_encode_t enc;
      static uint8_t buf[RS_PAYLOAD_SIZE];
      for (uint32_t k = 0; k < n; k++) {
        rs_synth_packet(&cfg, &s, k, &enc);
        rs_packet_encode(s.info, &enc, buf);
        if (push(&p, buf, rs_synth_time(&cfg, k)) != 0) return 1;
      }
      const rs_asm_cfg_t acfg = {.default_hz = 10.0};
      uint64_t frames = 0, points = 0, packets = 0;
      int64_t t0 = rs_now_ns(), elapsed = 0;
      while (elapsed < (int64_t)(seconds * 1e9)) {
        points += run_pass(&s, &p, &acfg, &frames, false);
        packets += p.n;
        elapsed = rs_now_ns() - t0;
      }
      double pps = (double)packets / ((double)elapsed * 1e-9);
      printf("%-12s %-9s %10llu %12.0f %12.2f %10.2f %9.1f\n", s.info->name, rs_return_mode_name(modes[mi]),
             (unsigned long long)packets, pps, (double)points / ((double)elapsed * 1e-9) / 1e6, 1e6 / pps,
             pps / packet_rate(s.info, modes[mi] == RS_MODE_DUAL));
      free(p.data);
      free(p.ts);
    }
  }
  return 0;
}

static int capture(const char *path, rs_model_t force, int repeat) {
  rs_capture_cfg_t ccfg = {.data_port = RS_DEFAULT_DATA_PORT, .speed = 0.0};
  rs_capture_t cap;
  if (rs_capture_open_file(&cap, path, &ccfg) != RS_OK) {
    fprintf(stderr, "roadscan-bench: %s\n", cap.err);
    return 1;
  }
  pkts_t p = {0};
  rs_detect_t det;
  rs_detect_init(&det, force);
  rs_frame_in_t f;
  int rc;
  while ((rc = rs_capture_next(&cap, &f, NULL)) == 1) {
    rs_udp_t u;
    if (rs_net_parse(cap.linktype, f.data, f.caplen, &u) != RS_OK) continue;
    if (u.dst_port != RS_DEFAULT_DATA_PORT || u.len != RS_PAYLOAD_SIZE) continue;
    if (rs_packet_check(u.payload, u.len) != RS_OK) continue;
    rs_detect_feed(&det, u.payload, u.len);
    if (push(&p, u.payload, f.ts) != 0) return 1;
  }
  rs_capture_close(&cap);
  int m = rs_detect_finish(&det);
  if (m <= 0 || p.n == 0) {
    fprintf(stderr, "roadscan-bench: %s: no Velodyne data packets of a known model\n", path);
    return 1;
  }
  static rs_sensor_t s;
  rs_sensor_init(&s, (rs_model_t)m);
  if (sg.with_model) {
    if (bgm.model != (rs_model_t)m) {
      fprintf(stderr, "roadscan-bench: the model is for a %s, the capture is from a %s\n", rs_model_name(bgm.model),
              s.info->name);
      return 1;
    }
    rs_cluster_cfg_t cc;
    rs_cluster_cfg_default(&cc);
    rs_cluster_init(&cluster, &cc, &s);
    cluster.bg_surfaces = bgm.n; /* frame_stages clusters only frames of the model's geometry */
    cc.method = sg.method;
    rs_cluster_init(&proc_cluster, &cc, &s);
    rs_objects_init(&objects, NULL);
    char perr[RS_ERRMSG_SIZE];
    rs_track_cfg_t tc;
    rs_track_cfg_default(&tc);
    rs_track_init(&tracker, &tc);
    rs_proc_cfg_t prc = {.background = &bgm, .lossless = true, .cluster = &proc_cluster, .objects = &objects,
                         .object_list = &object_list, .tracker = &tracker};
    if (rs_proc_init(&proc, &prc, perr, sizeof perr) != RS_OK) {
      fprintf(stderr, "roadscan-bench: %s\n", perr);
      return 1;
    }
    sg.sensor = &s;
    rs_publish_cfg_t pc = {.url = "memq://"}; /* encoding only: nothing is sent */
    if (rs_publish_init(&publisher, &pc) != RS_OK) {
      fprintf(stderr, "roadscan-bench: %s\n", publisher.err);
      return 1;
    }
    for (int k = 0; k < ST_COUNT; k++) rs_timing_init(&stage_t[k], stage_names[k]);
    if (sg.csv) {
      fprintf(sg.csv, "frame,foreground");
      for (int k = 0; k < ST_COUNT; k++) fprintf(sg.csv, ",%s", stage_cols[k]);
      fprintf(sg.csv, "\n");
    }
    repeat = 1;
  }
  rs_timing_init(&t_decode, "decode/packet");
  rs_timing_init(&t_assemble, "assembly/packet");
  rs_timing_init(&t_frame, "decode+assembly/frame");
  uint64_t frames = 0, points = 0;
  int64_t t0 = rs_now_ns();
  for (int r = 0; r < repeat; r++) {
    const rs_asm_cfg_t acfg = {.default_hz = 10.0, .columns = sg.with_model ? bgm.cols : 0};
    points += run_pass(&s, &p, &acfg, &frames, true);
  }
  if (sg.with_model) {
    print_stages();
    rs_proc_deinit(&proc);
    rs_publish_deinit(&publisher);
    if (sg.encode_errors) printf("lcm encode failed on %llu frames\n", (unsigned long long)sg.encode_errors);
    free(p.data);
    free(p.ts);
    return 0;
  }
  double el = (double)(rs_now_ns() - t0) * 1e-9;
  printf("%s: %s, %zu data packets x %d passes, %llu frames\n", path, s.info->name, p.n, repeat,
         (unsigned long long)frames);
  printf("  throughput: %.0f packets/s, %.2f Mpoints/s (flat out, one core)\n", (double)p.n * repeat / el,
         (double)points / el / 1e6);
  rs_timing_print(&t_decode, stdout);
  rs_timing_print(&t_assemble, stdout);
  rs_timing_print(&t_frame, stdout);
  free(p.data);
  free(p.ts);
  return 0;
}

/* Everything the options set. */
typedef struct {
  double seconds;
  int repeat, tracker_n, best_of, method;
  const char *model_path, *csv_path;
  rs_model_t force;
  int cpu, rt_priority;  /* --cpu, --rt-priority (thread.h) */
} settings_t;
static settings_t st;
static rs_opts_t opts;

#define T settings_t
static const rs_opt_t table[] = {
    RS_OPT_DBL_("seconds", "S", T, seconds, 0.05, 60.0,
                "synthetic packets: seconds of each model (the tracker alone: at least 10; 30 by default)"),
    {.type = RS_OPT_INT, .name = "tracker", .arg = "N", .off = offsetof(T, tracker_n), .lo = 1, .hi = RS_TRACK_MAX,
     .flags = RS_OPT_NODEF, .help = "the tracker alone on N synthetic objects"},
    RS_OPT_FORCE_MODEL_("sensor", T, force),
    RS_OPT_INT_("repeat", "N", T, repeat, 1, 1000, "passes over a capture (decode + assembly)"),
    RS_OPT_STR_("model", "MODEL", T, model_path,
                "a background model of the capture's site: every frame runs the daemon's stages as roadscand "
                "runs them (background, clustering, objects, tracks, the LCM encoding), then FSPC, FSPC-adaptive, "
                "DBSCAN and CCL alone on the same frame; median, p99 and max per stage and their ratios"),
    {.type = RS_OPT_CHOICE, .name = "cluster", .arg = "METHOD", .off = offsetof(T, method),
     .choices = "fspc|fspc-adaptive|dbscan|ccl", .help = "with --model: the daemon's clustering method"},
    RS_OPT_STR_("csv", "FILE", T, csv_path, "with --model: the per-frame rows"),
    RS_OPT_INT_("cpu", "N", T, cpu, 0, RS_THREAD_CPU_MAX,
                "run on CPU N only, as roadscand's --processing-cpu places its processing thread"),
    RS_OPT_INT_("rt-priority", "P", T, rt_priority, 1, RS_THREAD_PRIO_MAX,
                "run SCHED_FIFO at priority P, as roadscand's --rt-priority its processing thread (needs "
                "CAP_SYS_NICE or an RLIMIT_RTPRIO of P)"),
    RS_OPT_INT_("best-of", "N", T, best_of, 1, 100,
                "with --model: each clustering method runs N times per frame and the fastest counts (steadier "
                "figures on a shared machine)"),
};
#undef T

static const rs_opts_spec_t spec = {
    .prog = "roadscan-bench",
    .summary = "how fast decoding, frame assembly and every processing stage run",
    .synopsis = "[--seconds S]\n--tracker N [--seconds S]\nCAPTURE [--sensor NAME] [--repeat N]\n"
                "CAPTURE --model MODEL [--cluster METHOD] [--csv FILE] [--best-of N]",
    .about = "Without a capture: synthetic packets of every model, decoded and assembled flat out on one core. "
             "With a capture: its data packets, decoded and assembled --repeat times. With --model: the stages "
             "of roadscand on every frame of the capture, timed with CLOCK_MONOTONIC. With --tracker: the "
             "tracker's update on N synthetic objects.",
    .epilog = "Exit status: 0 done, 1 the capture could not be read, 2 bad usage.",
    .max_args = 1,
    .opts = table,
    .n = (int)(sizeof table / sizeof table[0]),
};

int main(int argc, char **argv) {
  st = (settings_t){.seconds = 1.0, .repeat = 5, .best_of = 1, .method = RS_CLUSTER_FSPC_ADAPTIVE - 1};
  char err[RS_ERRMSG_SIZE];
  int first;
  const int start = rs_opts_start(&opts, &spec, &st, argc, argv, &first);
  if (start >= 0) return start;
  const rs_thread_cfg_t place = {.pin = rs_opts_given(&opts, "cpu") > 0, .cpu = st.cpu, .priority = st.rt_priority};
  if (rs_thread_place(&place, "--cpu, --rt-priority", err, sizeof err) != RS_OK) goto bad;
  if (place.pin || place.priority > 0) {
    char d[160];
    rs_thread_describe(pthread_self(), d, sizeof d);
    printf("runs on %s\n", d);
  }
  sg.best_of = st.best_of;
  sg.method = (rs_cluster_method_t)(st.method + 1); /* the choices start at fspc */
  if (st.model_path) {
    if (rs_bg_load(&bgm, st.model_path, err, sizeof err) != RS_OK) goto bad;
    sg.with_model = true;
  }
  if (st.csv_path) {
    sg.csv = fopen(st.csv_path, "w");
    if (sg.csv == NULL) {
      snprintf(err, sizeof err, "--csv %s: cannot write", st.csv_path);
      goto bad;
    }
  }
  if (st.tracker_n > 0) return tracker_bench(st.tracker_n, st.seconds < 10 ? 30.0 : st.seconds);
  if (first < argc) {
    int rc = capture(argv[first], st.force, st.repeat);
    if (sg.csv && fclose(sg.csv) != 0) rc = 1;
    return rc;
  }
  if (sg.with_model) {
    snprintf(err, sizeof err, "--model needs a CAPTURE");
    goto bad;
  }
  return synthetic(st.seconds);
bad:
  fprintf(stderr, "roadscan-bench: %s\n", err);
  return 2;
}

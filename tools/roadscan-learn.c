/* roadscan-learn - learn the static scene of a site from a capture.
 *
 *   roadscan-learn CAPTURE -o MODEL [--frames N] [--seed S] [--method dbscan|percentile] ...
 *   roadscan-learn --info MODEL [--image OUT.png]
 *
 * One pass over the capture through the daemon's decoder and frame
 * assembler; complete frames are sampled uniformly at random (reservoir),
 * then every cell is clustered (see background.h). Single-threaded tool. */
#include "roadscan/perception/background.h"
#include "roadscan/perception/bgupdate.h"
#include "roadscan/perception/ground.h"
#include "roadscan/sensor/calib.h"
#include "roadscan/util/opts.h"
#include "roadscan/frame/framer.h"
#include "roadscan/util/timing.h"

#include <png.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#define MEMORY_BUDGET (384ull * 1024 * 1024) /* VLS-128 learning stays under 512 MB */

static rs_slot_t slots[2];
static rs_framer_t framer;
static rs_calib_t calib;

typedef struct {
  rs_asm_cfg_t acfg;
  rs_bg_learner_t lr;
  bool lr_ready;
  int max_frames;
  double seconds;         /* > 0: only the complete frames of the first `seconds` */
  double t0;
  uint64_t seed;
  uint64_t frames;
  int rc;
} learn_t;

static void on_frame(void *user, rs_slot_t *s) {
  learn_t *L = user;
  if (L->rc != RS_OK) return;
  L->frames++;
  if (s->meta.partial) return;
  if (L->seconds > 0) {
    if (!L->lr_ready) L->t0 = s->meta.t_first;
    if (s->meta.t_first - L->t0 >= L->seconds - 1e-6) {
      framer.stop = true;
      return;
    }
  }
  if (!L->lr_ready) {
    int mf = L->max_frames;
    while (mf > 2 && rs_bg_learner_bytes(s->meta.rows, s->meta.cols, mf) > MEMORY_BUDGET) mf--;
    if (mf < L->max_frames)
      fprintf(stderr, "roadscan-learn: %d x %d cells: keeping %d frames (memory budget %llu MB)\n", s->meta.rows,
              s->meta.cols, mf, MEMORY_BUDGET >> 20);
    L->rc = rs_bg_learner_init(&L->lr, s->meta.model, s->meta.rows, s->meta.cols, mf, L->seed);
    if (L->rc != RS_OK) return;
    L->lr_ready = true;
  }
  rs_bg_learner_add(&L->lr, s);
}

static rs_ground_t ground;

/* the ground the daemon will find in model m, from sensor sen's geometry */
static void print_ground(const rs_bg_model_t *m, const rs_sensor_t *sen, FILE *out) {
  char line[512];
  rs_ground_build(&ground, m, sen);
  rs_ground_describe(&ground, line, sizeof line);
  fprintf(out, "%s\n", line);
}

static void print_info(const rs_bg_model_t *m, FILE *out) {
  const size_t cells = (size_t)m->rows * m->cols;
  size_t hist[RS_BG_SURFACES + 1] = {0};
  for (size_t c = 0; c < cells; c++) hist[m->n[c]]++;
  time_t t = (time_t)m->created;
  char when[64];
  strftime(when, sizeof when, "%Y-%m-%d %H:%M:%S UTC", gmtime(&t));
  fprintf(out, "background model: %s, %u rows x %u columns, learned at %.2f Hz from %u frames, %s\n",
          rs_model_name(m->model), m->rows, m->cols, (double)m->rate_hz, m->frames, when);
  if (m->params.method == RS_BG_PERCENTILE)
    fprintf(out, "method: per-cell percentile %.0f, tolerance %.2f m\n", m->params.percentile, m->params.percentile_tol);
  else
    fprintf(out, "method: per-cell DBSCAN, eps %.2f..%.2f m by %.2f, minPts %d (max(%d or a tenth of the frames, "
                 "%.0f%%)); nearer clusters kept when they flicker (lift < %.2f) in %.0f%% of %.0f s windows, or "
                 "when the cells beside see them as static; sky persists >= %.2f\n",
            m->params.eps_min, m->params.eps_max, m->params.eps_step, rs_bg_min_pts(&m->params, (int)m->frames),
            m->params.min_pts_floor, m->params.min_pts_share * 100, m->params.flicker_lift, m->params.coverage_min * 100,
            m->params.window_s, m->params.persist_max);
  fprintf(out, "cells by static surfaces:");
  for (int k = 0; k <= RS_BG_SURFACES; k++)
    fprintf(out, " %d: %zu (%.1f%%)", k, hist[k], 100.0 * (double)hist[k] / (double)cells);
  fprintf(out, "\n");
}

/* range image: a row per laser (highest at the top), grey = farthest
 * surface (near = bright), green = cells with several surfaces, black = none */
static int write_png(const rs_bg_model_t *m, const char *path) {
  const int scale = m->rows <= 32 ? 8 : 2, w = m->cols, h = m->rows * scale;
  uint8_t *px = calloc((size_t)w * (size_t)h * 3, 1);
  if (px == NULL) return RS_E_OOM;
  for (int r = 0; r < m->rows; r++)
    for (int c = 0; c < m->cols; c++) {
      size_t cell = (size_t)r * m->cols + (size_t)c;
      int n = m->n[cell];
      uint8_t rgb[3] = {0, 0, 0};
      if (n > 0) {
        uint32_t far = m->lo[cell * RS_BG_SURFACES + (size_t)n - 1];
        double d = far / 100.0;
        uint8_t g = (uint8_t)(255.0 * (1.0 - (d > 120 ? 120 : d) / 130.0));
        rgb[0] = rgb[1] = rgb[2] = g;
        if (n > 1) {
          rgb[0] = (uint8_t)(g / 3);
          rgb[2] = (uint8_t)(g / 3);
          rgb[1] = (uint8_t)(128 + g / 2);
        }
      }
      for (int y = 0; y < scale; y++) {
        uint8_t *p = px + (((size_t)(m->rows - 1 - r) * scale + (size_t)y) * (size_t)w + (size_t)c) * 3;
        memcpy(p, rgb, 3);
      }
    }
  png_image img;
  memset(&img, 0, sizeof img);
  img.version = PNG_IMAGE_VERSION;
  img.width = (png_uint_32)w;
  img.height = (png_uint_32)h;
  img.format = PNG_FORMAT_RGB;
  int ok = png_image_write_to_file(&img, path, 0, px, 0, NULL);
  free(px);
  return ok ? RS_OK : RS_E_IO;
}

/* Everything the options set. */
typedef struct {
  const char *out, *image, *info, *calib_path;
  int max_frames, seed, columns, method;
  double seconds;
  rs_bg_params_t params;
  rs_model_t force_model;
} settings_t;
static settings_t st;
static rs_opts_t opts;

#define T settings_t
static const rs_opt_t table[] = {
    RS_OPT_HEAD("", "Learning"),
    RS_OPT_OUTPUT_("MODEL", T, out, "the model file to write"),
    RS_OPT_INT_("frames", "N", T, max_frames, 10, 100000, "frames sampled at random over the capture"),
    {.type = RS_OPT_DOUBLE, .name = "seconds", .arg = "S", .off = offsetof(T, seconds), .lo = 0.05, .hi = 1e6,
     .def = "the whole capture", .help = "learn from the complete frames of the first S seconds only"},
    RS_OPT_INT_("seed", "S", T, seed, 0, 2147483647.0, "sampling seed"),
    {.type = RS_OPT_CHOICE, .name = "method", .arg = "M", .off = offsetof(T, method), .choices = "dbscan|percentile",
     .help = "per-cell DBSCAN (the paper's static-scene construction) or the per-cell percentile (the common "
             "baseline)"},
    RS_OPT_DBL_("percentile", "P", T, params.percentile, 1, 100, "percentile method: background at this percentile"),
    RS_OPT_DBL_("tolerance", "M", T, params.percentile_tol, 0, 10, "percentile method: minus this many metres"),
    RS_OPT_INT_("min-pts-floor", "N", T, params.min_pts_floor, 2, 100000,
                "DBSCAN minPts floor (minPts = max(floor, 1 % of samples))"),
    RS_OPT_DBL_("chain-gap", "M", T, params.chain_gap, 0, 5,
                "clusters of a cell less than M metres apart are judged as one surface (0 = off)"),
    RS_OPT_DBL_("occluded", "SHARE", T, params.occluded_max, 0, 1,
                "a nearer cluster seen throughout, at one range, with at most SHARE of the returns behind it when "
                "it is not seen (the rest in front: traffic hiding it) is a surface (0 = off)"),
    RS_OPT_DBL_("occluded-clear", "SHARE", T, params.occluded_clear, 0, 1,
                "a nearer cluster hidden by traffic with nothing steady behind it needs only SHARE of the 5 s "
                "windows (not half) and may spread 2.5 times as much (0 = off)"),
    RS_OPT_DBL_("void-stay", "SHARE", T, params.void_stay, 0, 1,
                "the farthest cluster of a cell is no surface when the cell returns nothing more often than it "
                "and, once seen, it is back in the next frame at least SHARE of the time (a vehicle standing "
                "where nothing behind it returns) (0 = off)"),
    RS_OPT_DBL_("coverage-open", "SHARE", T, params.coverage_open, 0, 1,
                "a nearer cluster that flickers is present throughout when it is in 80 % of the 5 s windows it "
                "was not hidden in all along by something in front (a canopy behind a lane where queues stand), "
                "those at least SHARE of all windows (0 = 80 % of all windows)"),
    RS_OPT_DBL_("leaves", "SHARE", T, params.leaves_range, 0, 1,
                "a nearer cluster that, over the frames not hidden by something in front of it, comes and goes at "
                "random and whose range changes from one frame to the next by SHARE of the mean difference between "
                "two of its returns, present throughout, is leaves of a dense canopy behind a lane (0 = off)"),
    RS_OPT_DBL_("sparse-cover", "SHARE", T, params.sparse_cover, 0, 1,
                "a cluster of a cell that flickers, at one range, present in SHARE of the 5 s windows that returns "
                "at random at its rate would be in, and coming and going on its own in its row (a vehicle covers "
                "several cells at once), is a surface whose returns drop out (far ground at a grazing angle) (0 = "
                "off)"),
    {.type = RS_OPT_BOOL, .name = "support", .arg = "on|off", .off = offsetof(T, params.support),
     .help = "a nearer cluster that a neighbouring cell sees as static in half its frames or more is static too "
             "(edges)"},
    RS_OPT_DBL_("connect", "M", T, params.connect_min, 0, 10,
                "a surface reaches half-way to the one beside it in the row when they are less than max(M, 5 % of "
                "the range) apart (0 = off)"),
    RS_OPT_HEAD("", "Sensor"),
    RS_OPT_FORCE_MODEL_("model", T, force_model),
    RS_OPT_CALIB_(T, calib_path),
    {.type = RS_OPT_INT, .name = "columns", .arg = "N", .off = offsetof(T, columns), .lo = RS_MIN_COLS,
     .hi = RS_MAX_COLS, .def = "from the measured rate, as the daemon", .help = "azimuth bins"},
    RS_OPT_HEAD("", "Models"),
    RS_OPT_STR_("image", "OUT.png", T, image,
                "draw the model as a range image (a row per laser; grey: the farthest surface, green: several)"),
    RS_OPT_STR_("info", "MODEL", T, info, "print a model's summary"),
};
#undef T

static const rs_opts_spec_t spec = {
    .prog = "roadscan-learn",
    .summary = "learn the static scene of a site from a capture",
    .synopsis = "CAPTURE -o MODEL [options]\n--info MODEL [--image OUT.png]",
    .about = "One pass over the capture through the daemon's decoder and frame assembler; complete frames are "
             "sampled uniformly at random, then every (laser, azimuth) cell is clustered over the ranges seen in "
             "it (docs/background.md). The model file is checksummed; roadscand --background loads it.",
    .epilog = "Exit status: 0 written, 1 the capture or a file could not be read or written, 2 bad usage.",
    .max_args = 1,
    .opts = table,
    .n = (int)(sizeof table / sizeof table[0]),
};

int main(int argc, char **argv) {
  static learn_t L;
  rs_bg_params_default(&st.params);
  st.max_frames = 1000;
  st.seed = 1;
  st.method = st.params.method == RS_BG_PERCENTILE;
  char err[RS_ERRMSG_SIZE];
  int first;
  const int start = rs_opts_start(&opts, &spec, &st, argc, argv, &first);
  if (start >= 0) return start;
  const char *out = st.out, *image = st.image, *info = st.info, *calib_path = st.calib_path;
  rs_bg_params_t params = st.params;
  params.method = st.method == 1 ? RS_BG_PERCENTILE : RS_BG_DBSCAN;
  L.max_frames = st.max_frames;
  L.seed = (uint64_t)st.seed;
  L.seconds = st.seconds;
  L.acfg.default_hz = 10.0;
  L.acfg.columns = st.columns;
  rs_stream_cfg_t scfg = {.log = stderr, .force_model = st.force_model};
  rs_bg_model_t m;
  if (info) {
    if (first < argc) {
      snprintf(err, sizeof err, "--info takes no capture");
      goto bad;
    }
    if (rs_bg_load(&m, info, err, sizeof err) != RS_OK) {
      fprintf(stderr, "roadscan-learn: %s\n", err);
      return 1;
    }
    print_info(&m, stdout);
    rs_sensor_t sen; /* the model's published table (a unit's calibration moves the ground by millimetres) */
    if (rs_sensor_init(&sen, m.model) == RS_OK) print_ground(&m, &sen, stdout);
    int rc = 0;
    if (image && write_png(&m, image) != RS_OK) {
      fprintf(stderr, "roadscan-learn: %s: cannot write the image\n", image);
      rc = 1;
    }
    rs_bg_model_free(&m);
    return rc;
  }
  if (first + 1 != argc || out == NULL) {
    snprintf(err, sizeof err, "give one capture and -o MODEL (see --help)");
    goto bad;
  }
  if (calib_path) {
    if (rs_calib_load_yaml(calib_path, &calib, err, sizeof err) != RS_OK) {
      fprintf(stderr, "roadscan-learn: %s\n", err);
      return 1;
    }
    scfg.calib = &calib;
  }
  if (rs_framer_init(&framer, &scfg, &L.acfg, slots, on_frame, &L) != RS_OK) {
    fprintf(stderr, "roadscan-learn: %s\n", framer.stream.err);
    return 1;
  }
  int64_t t0 = rs_now_ns();
  int rc = rs_framer_replay_file(&framer, argv[first], err, sizeof err);
  if (rc != RS_OK) fprintf(stderr, "roadscan-learn: %s\n", err);
  if (rc == RS_E_NOENT || rc == RS_E_FORMAT || rc == RS_E_LINKTYPE || rc == RS_E_CALIB) return 1;
  if (L.rc != RS_OK || !L.lr_ready || L.lr.nframes < 2) {
    fprintf(stderr, "roadscan-learn: %s: %s\n", argv[first],
            L.rc != RS_OK ? rs_strerror(L.rc) : "fewer than 2 complete frames: nothing to learn from");
    return 1;
  }
  int64_t t1 = rs_now_ns();
  rc = rs_bg_learn(&L.lr, &params, (float)rs_hz_from_rate(framer.as.rate), &m);
  int64_t t2 = rs_now_ns();
  if (rc != RS_OK) {
    fprintf(stderr, "roadscan-learn: learning failed: %s\n", rs_strerror(rc));
    return 1;
  }
  if (rs_bg_save(&m, out, err, sizeof err) != RS_OK) {
    fprintf(stderr, "roadscan-learn: %s\n", err);
    return 1;
  }
  fprintf(stderr, "roadscan-learn: %llu frames read, %d sampled; decode+assembly %.2f s, learning %.2f s; samples %.0f MB\n",
          (unsigned long long)L.frames, L.lr.nframes, (double)(t1 - t0) * 1e-9, (double)(t2 - t1) * 1e-9,
          (double)rs_bg_learner_bytes(L.lr.rows, L.lr.cols, L.lr.max_frames) / 1048576.0);
  print_info(&m, stderr);
  print_ground(&m, &framer.stream.sensor, stderr);
  const double hz = m.rate_hz > 0 ? m.rate_hz : 10.0;
  if (rs_bgu_few_frames(m.frames, hz))
    fprintf(stderr,
            "roadscan-learn: warning: learned from %u frames (%.1f s at %.1f Hz): a site with traffic needs %.0f s of "
            "it for vehicles that stop to be told from the scene (a scene without traffic needs about 1 s); the model "
            "is usable, and roadscand keeps it current from what the sensor sees (--update-minutes)\n",
            m.frames, m.frames / hz, hz, RS_BG_SITE_SECONDS);
  if (image && write_png(&m, image) != RS_OK) {
    fprintf(stderr, "roadscan-learn: %s: cannot write the image\n", image);
    return 1;
  }
  rs_bg_model_free(&m);
  rs_bg_learner_free(&L.lr);
  return 0;
bad:
  fprintf(stderr, "roadscan-learn: %s\n", err);
  return 2;
}

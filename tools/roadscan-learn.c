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
#include "roadscan/sensor/calib.h"
#include "roadscan/util/config.h"
#include "roadscan/frame/framer.h"
#include "roadscan/util/timing.h"

#include <getopt.h>
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
  if (px == NULL) return RS_E_NOMEM;
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

static void usage(FILE *out) {
  fprintf(out,
          "usage: roadscan-learn CAPTURE -o MODEL [options]\n"
          "       roadscan-learn --info MODEL [--image OUT.png]\n"
          "  -o, --output MODEL     the model file to write\n"
          "  --frames N             frames sampled at random over the capture (default 1000)\n"
          "  --seconds S            learn from the complete frames of the first S seconds only\n"
          "  --seed S               sampling seed (default 1)\n"
          "  --method M             dbscan (default) or percentile (the common baseline)\n"
          "  --percentile P         percentile method: background at this percentile (default 50)\n"
          "  --tolerance M          percentile method: minus this many metres (default 0.3)\n"
          "  --min-pts-floor N      DBSCAN minPts floor (default 10; minPts = max(floor, 1%% of samples))\n"
          "  --chain-gap M          clusters of a cell less than M metres apart are judged as one surface\n"
          "                         (default 0.20, 0 = off)\n"
          "  --support on|off       a nearer cluster that a neighbouring cell sees as static in half\n"
          "                         its frames or more is static too (edges; default on)\n"
          "  --connect M            a surface reaches half-way to the one beside it in the row when\n"
          "                         they are less than max(M, 5 %% of the range) apart (default 0.5, 0 = off)\n"
          "  --model NAME           force the sensor model (%s)\n"
          "  --calibration FILE     per-unit calibration (ROS velodyne YAML)\n"
          "  --columns N            azimuth bins (default: from the measured rate, as the daemon)\n"
          "  --image OUT.png        draw the model as a range image\n"
          "  --info MODEL           print a model's summary\n",
          rs_model_names());
}

int main(int argc, char **argv) {
  enum { O_SUPPORT = 200, O_CONNECT, O_FRAMES = 256, O_SECONDS, O_SEED, O_METHOD, O_PCT, O_TOL, O_FLOOR, O_MODEL, O_CALIB, O_COLS, O_IMAGE, O_INFO, O_HELP, O_CHAIN };
  static const struct option opts[] = {
      {"output", required_argument, NULL, 'o'},         {"frames", required_argument, NULL, O_FRAMES},
      {"seconds", required_argument, NULL, O_SECONDS},
      {"support", required_argument, NULL, O_SUPPORT},  {"connect", required_argument, NULL, O_CONNECT},
      {"seed", required_argument, NULL, O_SEED},        {"method", required_argument, NULL, O_METHOD},
      {"percentile", required_argument, NULL, O_PCT},   {"tolerance", required_argument, NULL, O_TOL},
      {"min-pts-floor", required_argument, NULL, O_FLOOR}, {"model", required_argument, NULL, O_MODEL},
      {"calibration", required_argument, NULL, O_CALIB}, {"columns", required_argument, NULL, O_COLS},
      {"image", required_argument, NULL, O_IMAGE},      {"info", required_argument, NULL, O_INFO},
      {"chain-gap", required_argument, NULL, O_CHAIN},  {"help", no_argument, NULL, O_HELP},
      {NULL, 0, NULL, 0}};
  const char *out = NULL, *image = NULL, *info = NULL, *calib_path = NULL;
  static learn_t L;
  L.max_frames = 1000;
  L.seed = 1;
  L.acfg.default_hz = 10.0;
  rs_bg_params_t params;
  rs_bg_params_default(&params);
  rs_stream_cfg_t scfg = {.log = stderr};
  char err[RS_ERRMSG_SIZE];
  long lv;
  int c;
  while ((c = getopt_long(argc, argv, "o:", opts, NULL)) != -1) {
    switch (c) {
    case 'o': out = optarg; break;
    case O_FRAMES:
      if (rs_cfg_long("--frames", optarg, 10, 100000, &lv, err, sizeof err)) goto bad;
      L.max_frames = (int)lv;
      break;
    case O_SUPPORT:
      if (rs_cfg_bool("--support", optarg, &params.support, err, sizeof err)) goto bad;
      break;
    case O_CONNECT:
      if (rs_cfg_double("--connect", optarg, 0, 10, &params.connect_min, err, sizeof err)) goto bad;
      break;
    case O_SECONDS:
      if (rs_cfg_double("--seconds", optarg, 0.05, 1e6, &L.seconds, err, sizeof err)) goto bad;
      break;
    case O_SEED:
      if (rs_cfg_long("--seed", optarg, 0, 2147483647L, &lv, err, sizeof err)) goto bad;
      L.seed = (uint64_t)lv;
      break;
    case O_METHOD:
      if (strcmp(optarg, "dbscan") == 0) params.method = RS_BG_DBSCAN;
      else if (strcmp(optarg, "percentile") == 0) params.method = RS_BG_PERCENTILE;
      else {
        snprintf(err, sizeof err, "--method: '%s' is not dbscan or percentile", optarg);
        goto bad;
      }
      break;
    case O_PCT:
      if (rs_cfg_double("--percentile", optarg, 1, 100, &params.percentile, err, sizeof err)) goto bad;
      break;
    case O_TOL:
      if (rs_cfg_double("--tolerance", optarg, 0, 10, &params.percentile_tol, err, sizeof err)) goto bad;
      break;
    case O_CHAIN:
      if (rs_cfg_double("--chain-gap", optarg, 0, 5, &params.chain_gap, err, sizeof err)) goto bad;
      break;
    case O_FLOOR:
      if (rs_cfg_long("--min-pts-floor", optarg, 2, 100000, &lv, err, sizeof err)) goto bad;
      params.min_pts_floor = (int)lv;
      break;
    case O_MODEL:
      if (rs_cfg_model("--model", optarg, &scfg.force_model, err, sizeof err)) goto bad;
      break;
    case O_CALIB: calib_path = optarg; break;
    case O_COLS:
      if (rs_cfg_long("--columns", optarg, RS_MIN_COLS, RS_MAX_COLS, &lv, err, sizeof err)) goto bad;
      L.acfg.columns = (int)lv;
      break;
    case O_IMAGE: image = optarg; break;
    case O_INFO: info = optarg; break;
    case O_HELP: usage(stdout); return 0;
    default: usage(stderr); return 2;
    }
  }
  rs_bg_model_t m;
  if (info) {
    if (optind < argc) {
      snprintf(err, sizeof err, "--info takes no capture");
      goto bad;
    }
    if (rs_bg_load(&m, info, err, sizeof err) != RS_OK) {
      fprintf(stderr, "roadscan-learn: %s\n", err);
      return 1;
    }
    print_info(&m, stdout);
    int rc = 0;
    if (image && write_png(&m, image) != RS_OK) {
      fprintf(stderr, "roadscan-learn: %s: cannot write the image\n", image);
      rc = 1;
    }
    rs_bg_model_free(&m);
    return rc;
  }
  if (optind + 1 != argc || out == NULL) {
    usage(stderr);
    return 2;
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
  int rc = rs_framer_replay_file(&framer, argv[optind], err, sizeof err);
  if (rc != RS_OK) fprintf(stderr, "roadscan-learn: %s\n", err);
  if (rc == RS_E_NOENT || rc == RS_E_FORMAT || rc == RS_E_LINKTYPE || rc == RS_E_CALIB) return 1;
  if (L.rc != RS_OK || !L.lr_ready || L.lr.nframes < 2) {
    fprintf(stderr, "roadscan-learn: %s: %s\n", argv[optind],
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
  const double hz = m.rate_hz > 0 ? m.rate_hz : 10.0;
  if (m.frames < RS_BG_SITE_SECONDS * hz * 0.5)
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

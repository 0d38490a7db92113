/* roadscan-render - one frame as a picture: the range image and a bird's-eye
 * view, every return coloured by the label the pipeline gives it (background,
 * noise, each cluster), with a legend and a scale, so anyone can see where a
 * background model leaks (edges, foliage, far range).
 *
 *   roadscan-render CAPTURE --frame N [--background MODEL] [--cluster M] [--range M] -o OUT.png
 *   roadscan-render CAPTURE --frame N --labels PRED.csv -o OUT.png
 *
 * The frame goes through the daemon's decoder, frame assembler, background
 * subtraction (its default settings) and clustering (fspc-adaptive unless
 * --cluster says otherwise); or its labels come from a point-label file
 * (any pipeline's, e.g. roadscand --labels-out, or the simulator's truth).
 * Without either every return is drawn by range.
 * Single-threaded tool. */
#include "render-font.h"
#include "roadscan/perception/background.h"
#include "roadscan/perception/cluster.h"
#include "roadscan/util/opts.h"
#include "roadscan/frame/framer.h"
#include "roadscan/output/labels.h"

#include <math.h>
#include <png.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static rs_slot_t slots[2], frame;
static rs_framer_t framer;
static rs_cluster_t cluster;

typedef struct {
  uint64_t want;
  bool found;
} pick_t;

static void on_frame(void *user, rs_slot_t *s) {
  pick_t *p = user;
  if (s->meta.seq != p->want) return;
  memcpy(&frame.meta, &s->meta, sizeof s->meta);
  const size_t cells = (size_t)s->meta.rows * s->meta.cols;
  for (int l = 0; l < RS_LAYERS; l++) {
    memcpy(frame.range + (size_t)l * RS_MAX_CELLS, s->range + (size_t)l * RS_MAX_CELLS, cells * sizeof(float));
    memcpy(frame.intensity + (size_t)l * RS_MAX_CELLS, s->intensity + (size_t)l * RS_MAX_CELLS, cells);
    memcpy(frame.addr + (size_t)l * RS_MAX_CELLS, s->addr + (size_t)l * RS_MAX_CELLS, cells * sizeof(rs_addr_t));
    memset(frame.label + (size_t)l * RS_MAX_CELLS, 0, cells * sizeof(uint16_t));
  }
  p->found = true;
  framer.stop = true;
}

/* ---- a small RGB canvas ---- */
typedef struct {
  int w, h;
  uint8_t *px;
} canvas_t;

static void put(canvas_t *c, int x, int y, const uint8_t *rgb) {
  if (x < 0 || y < 0 || x >= c->w || y >= c->h) return;
  memcpy(c->px + ((size_t)y * (size_t)c->w + (size_t)x) * 3, rgb, 3);
}
static void rect(canvas_t *c, int x0, int y0, int w, int h, const uint8_t *rgb) {
  for (int y = y0; y < y0 + h; y++)
    for (int x = x0; x < x0 + w; x++) put(c, x, y, rgb);
}
/* text at (x, y), glyphs `scale` pixels per dot; returns the x after it */
static int text(canvas_t *c, int x, int y, int scale, const uint8_t *rgb, const char *s) {
  for (; *s; s++) {
    char ch = *s >= 'a' && *s <= 'z' ? (char)(*s - 'a' + 'A') : *s;
    const char *rows = NULL;
    for (size_t i = 0; i < sizeof rs_font / sizeof rs_font[0]; i++)
      if (rs_font[i].c == ch) rows = rs_font[i].rows;
    if (rows == NULL) rows = rs_font[0].rows; /* unknown: a space */
    for (int r = 0; r < 7; r++)
      for (int k = 0; k < 5; k++)
        if (rows[r * 5 + k] == '#') rect(c, x + k * scale, y + r * scale, scale, scale, rgb);
    x += 6 * scale;
  }
  return x;
}

static const uint8_t WHITE[3] = {235, 235, 235}, GREY[3] = {120, 120, 120}, DARK[3] = {24, 24, 28},
                     NOISE[3] = {230, 40, 40}, NONE[3] = {0, 0, 0};

/* a distinct colour per cluster (golden-angle hues, bright) */
static void cluster_rgb(int id, uint8_t *rgb) {
  double h = fmod(id * 137.508, 360.0) / 60.0, x = 1.0 - fabs(fmod(h, 2.0) - 1.0);
  double r = 0, g = 0, b = 0;
  switch ((int)h) {
  case 0: r = 1; g = x; break;
  case 1: r = x; g = 1; break;
  case 2: g = 1; b = x; break;
  case 3: g = x; b = 1; break;
  case 4: r = x; b = 1; break;
  default: r = 1; b = x; break;
  }
  /* keep clear of the noise red: lift the green and blue of reds */
  rgb[0] = (uint8_t)(60 + 195 * r);
  rgb[1] = (uint8_t)(60 + 195 * g);
  rgb[2] = (uint8_t)(60 + 195 * b);
}

/* background (or every return with no model): grey by range, near bright */
static void range_rgb(float r, double max_r, uint8_t *rgb) {
  double t = fmin(1.0, r / max_r);
  uint8_t v = (uint8_t)(200 - 140 * t);
  rgb[0] = rgb[1] = rgb[2] = v;
}

static void label_rgb(uint16_t label, float r, double max_r, bool have_labels, uint8_t *rgb) {
  if (!have_labels || label <= RS_LABEL_BACKGROUND) range_rgb(r, max_r, rgb);
  else if (label == RS_LABEL_NOISE) memcpy(rgb, NOISE, 3);
  else cluster_rgb(label - RS_LABEL_FIRST_OBJECT + 1, rgb);
}

/* Everything the options set. */
typedef struct {
  int frame, method;
  const char *out, *bg_path, *labels_path;
  double half;
  rs_model_t model;
} settings_t;
static settings_t st;
static rs_opts_t opts;

#define T settings_t
static const rs_opt_t table[] = {
    {.type = RS_OPT_INT, .name = "frame", .arg = "N", .off = offsetof(T, frame), .lo = 0, .hi = 100000000,
     .flags = RS_OPT_NODEF, .help = "frame number (as roadscand's --frames-out; 0 = the partial first one)"},
    RS_OPT_OUTPUT_("FILE", T, out, "the picture (PNG): range image above, bird's-eye view below"),
    RS_OPT_STR_("background", "MODEL", T, bg_path,
                "subtract this static scene (roadscan-learn); without one every return is drawn grey by range"),
    {.type = RS_OPT_CHOICE, .name = "cluster", .arg = "METHOD", .off = offsetof(T, method),
     .choices = "none|fspc|fspc-adaptive|dbscan|ccl", .help = "clustering of the foreground"},
    RS_OPT_STR_("labels", "FILE", T, labels_path,
                "take the labels from a point-label file instead (roadscand --labels-out, roadscan-sim --labels: "
                "any pipeline's, or the truth)"),
    RS_OPT_DBL_("range", "M", T, half, 2.0, 500.0, "bird's-eye view half-width in metres"),
    RS_OPT_FORCE_MODEL_("model", T, model),
};
#undef T

static const rs_opts_spec_t spec = {
    .prog = "roadscan-render",
    .summary = "draw one frame: its range image and a bird's-eye view, coloured by label",
    .synopsis = "CAPTURE --frame N -o OUT.png [options]",
    .about = "Colours: background grey (nearer is lighter), noise (foreground in no cluster) red, each cluster its "
             "own colour, no return black.",
    .epilog = "Exit status: 0 drawn, 1 a file could not be read or written, or no such frame, 2 bad usage.",
    .min_args = 1,
    .max_args = 1,
    .opts = table,
    .n = (int)(sizeof table / sizeof table[0]),
};

int main(int argc, char **argv) {
  st = (settings_t){.frame = -1, .method = RS_CLUSTER_FSPC_ADAPTIVE, .half = 50.0};
  char err[RS_ERRMSG_SIZE];
  int first;
  const int start = rs_opts_start(&opts, &spec, &st, argc, argv, &first);
  if (start >= 0) return start;
  if (st.frame < 0 || st.out == NULL) {
    snprintf(err, sizeof err, "--frame N and -o FILE are required (see --help)");
    goto bad;
  }
  const long frame_no = st.frame;
  const char *out = st.out, *bg_path = st.bg_path, *labels_path = st.labels_path;
  const double half = st.half;
  rs_cluster_cfg_t ccfg;
  rs_cluster_cfg_default(&ccfg);
  ccfg.method = (rs_cluster_method_t)st.method;
  rs_stream_cfg_t scfg = {.log = NULL, .force_model = st.model};
  if (bg_path && labels_path) {
    snprintf(err, sizeof err, "--background and --labels exclude each other");
    goto bad;
  }
  const char *capture = argv[first];
  static rs_bg_model_t model;
  bool have_model = false;
  rs_asm_cfg_t acfg = {.default_hz = 10.0};
  if (bg_path) {
    if (rs_bg_load(&model, bg_path, err, sizeof err) != RS_OK) {
      fprintf(stderr, "roadscan-render: %s\n", err);
      return 1;
    }
    have_model = true;
    acfg.columns = model.cols;
  }
  pick_t pick = {.want = (uint64_t)frame_no};
  if (rs_framer_init(&framer, &scfg, &acfg, slots, on_frame, &pick) != RS_OK) {
    fprintf(stderr, "roadscan-render: %s\n", framer.stream.err);
    return 1;
  }
  framer.flush_last = true;
  int rc = rs_framer_replay_file(&framer, capture, err, sizeof err);
  if (rc == RS_E_NOENT || rc == RS_E_FORMAT || rc == RS_E_LINKTYPE) {
    fprintf(stderr, "roadscan-render: %s\n", err);
    return 1;
  }
  if (!pick.found) {
    fprintf(stderr, "roadscan-render: %s: no frame %ld (the capture has %llu)\n", capture, frame_no,
            (unsigned long long)framer.as.frames);
    return 1;
  }
  rs_sensor_t *sensor = &framer.stream.sensor;
  if (have_model && (model.model != sensor->info->model || model.rows != frame.meta.rows || model.cols != frame.meta.cols)) {
    fprintf(stderr, "roadscan-render: %s is for a %s (%u x %u), the capture is a %s (%u x %u)\n", bg_path,
            rs_model_name(model.model), model.rows, model.cols, sensor->info->name, frame.meta.rows, frame.meta.cols);
    return 1;
  }
  /* the pipeline's labels */
  rs_bg_counts_t bc = {0};
  rs_cluster_stats_t cs;
  memset(&cs, 0, sizeof cs);
  if (labels_path) {
    /* a return not in the file is background; the file's labels by address */
    rs_labels_reader_t lr;
    if (rs_labels_open(&lr, labels_path, UINT32_MAX) != RS_OK) {
      fprintf(stderr, "roadscan-render: %s\n", lr.err);
      return 1;
    }
    const int n = frame.meta.rows * frame.meta.cols;
    for (int i = 0; i < n; i++)
      if (frame.range[i] > 0) frame.label[i] = RS_LABEL_BACKGROUND;
    /* the frame's cells by address */
    const size_t span = ((size_t)frame.meta.last_packet - frame.meta.first_packet + 1) * 384u;
    int32_t *at = malloc(span * sizeof *at);
    static bool seen_cluster[65536];
    if (at == NULL) {
      fprintf(stderr, "roadscan-render: out of memory\n");
      return 1;
    }
    for (size_t i = 0; i < span; i++) at[i] = -1;
    for (int i = 0; i < n; i++)
      if (frame.range[i] > 0 && frame.addr[i].packet >= frame.meta.first_packet && frame.addr[i].packet <= frame.meta.last_packet)
        at[(size_t)(frame.addr[i].packet - frame.meta.first_packet) * 384u + frame.addr[i].block * 32u + frame.addr[i].channel] = i;
    rs_label_t lb;
    int r;
    while ((r = rs_labels_next(&lr, &lb)) == 1) {
      if (lb.packet < frame.meta.first_packet || lb.packet > frame.meta.last_packet) continue;
      const int i = at[(size_t)(lb.packet - frame.meta.first_packet) * 384u + lb.block * 32u + lb.channel];
      if (i < 0) continue;
      frame.label[i] = (uint16_t)(lb.label > 65535 ? 65535 : lb.label);
      if (lb.label >= RS_LABEL_FIRST_OBJECT && !seen_cluster[frame.label[i]]) {
        seen_cluster[frame.label[i]] = true;
        cs.clusters++;
      }
    }
    free(at);
    rs_labels_close(&lr);
    if (r < 0) {
      fprintf(stderr, "roadscan-render: %s\n", lr.err);
      return 1;
    }
    for (int i = 0; i < n; i++)
      if (frame.range[i] > 0) {
        if (frame.label[i] == RS_LABEL_BACKGROUND) bc.background++;
        else bc.foreground++;
      }
    have_model = true; /* labels to draw */
  } else if (have_model) {
    rs_bg_rules_t rules; /* the daemon's defaults */
    rs_bg_rules_default(&rules);
    rs_bg_subtract(&model, &rules, &frame, &bc);
    if (ccfg.method != RS_CLUSTER_NONE) {
      if (rs_cluster_init(&cluster, &ccfg, sensor) != RS_OK) {
        fprintf(stderr, "roadscan-render: bad clustering parameters\n");
        return 1;
      }
      cluster.sensor = sensor;
      cluster.bg_surfaces = model.n;
      rs_cluster_run(&cluster, &frame, &cs);
    }
  }
  const int rows = frame.meta.rows, cols = frame.meta.cols;
  double max_r = 1.0;
  uint32_t returns = 0;
  for (int i = 0; i < rows * cols; i++)
    if (frame.range[i] > 0) {
      returns++;
      if (frame.range[i] > max_r) max_r = frame.range[i];
    }
  max_r = fmin(max_r, 2.0 * half);

  /* layout: title, range image (a row per laser, highest on top), bird's-eye view, legend */
  const int rh = rows <= 16 ? 10 : (rows <= 32 ? 6 : 2);
  const int img_w = cols <= 2000 ? cols : cols / 2, step = cols <= 2000 ? 1 : 2;
  const int bev = 720, margin = 12, title_h = 36, legend_h = 120;
  canvas_t cv;
  cv.w = (img_w > bev ? img_w : bev) + 2 * margin;
  /* the legend beside the bird's-eye view when the range image leaves room, else below it */
  const bool legend_beside = cv.w - (bev + 2 * margin) >= 560;
  cv.h = title_h + rows * rh + margin * 3 + 10 + bev + (legend_beside ? 0 : legend_h);
  cv.px = malloc((size_t)cv.w * (size_t)cv.h * 3);
  if (cv.px == NULL) {
    fprintf(stderr, "roadscan-render: out of memory\n");
    return 1;
  }
  rect(&cv, 0, 0, cv.w, cv.h, DARK);
  char line[256];
  const char *base = strrchr(capture, '/') ? strrchr(capture, '/') + 1 : capture;
  snprintf(line, sizeof line, "%.60s  frame %ld  %s %.1f Hz  %u returns", base, frame_no, sensor->info->name,
           (double)frame.meta.rate_hz, returns);
  text(&cv, margin, 6, 2, WHITE, line);
  if (have_model)
    snprintf(line, sizeof line, "background %.2f %%  foreground %llu  clusters %u (%s)",
             returns ? 100.0 * (double)bc.background / (double)(bc.background + bc.foreground) : 0.0,
             (unsigned long long)bc.foreground, cs.clusters,
             labels_path ? "labels from a file" : rs_cluster_method_name(ccfg.method));
  else
    snprintf(line, sizeof line, "no background model: every return grey by range");
  text(&cv, margin, 23, 1, GREY, line);

  /* the range image: azimuth 0 at the left, laser rows by elevation, highest on top */
  const int y0 = title_h;
  for (int r = 0; r < rows; r++)
    for (int x = 0; x < img_w; x++) {
      /* of the columns drawn into one pixel, a labelled return wins */
      uint8_t rgb[3];
      memcpy(rgb, NONE, 3);
      int best = -1;
      for (int k = 0; k < step; k++) {
        int col = x * step + k, i = r * cols + col;
        if (col >= cols || frame.range[i] <= 0) continue;
        if (frame.label[i] > best) {
          best = frame.label[i];
          label_rgb(frame.label[i], frame.range[i], max_r, have_model, rgb);
        }
      }
      rect(&cv, margin + x, y0 + (rows - 1 - r) * rh, 1, rh, rgb);
    }
  /* azimuth ticks every 45 degrees under the image */
  const int ty = y0 + rows * rh + 2;
  for (int a = 0; a <= 360; a += 45) {
    int x = margin + (int)((double)a / 360.0 * img_w);
    rect(&cv, x, ty, 1, 4, GREY);
    snprintf(line, sizeof line, "%d", a);
    text(&cv, x + 2, ty + 2, 1, GREY, line);
  }

  /* the bird's-eye view: sensor at the centre, +y (azimuth 0) up, 2 x half metres across */
  const int bx = margin, by = ty + margin + 10;
  const double ppm = bev / (2.0 * half);
  rect(&cv, bx, by, bev, bev, NONE);
  /* range rings with labels */
  /* rings every 1, 2 or 5 x 10^k metres, about four across the half-width */
  double ring = pow(10.0, floor(log10(half / 4.0)));
  if (ring * 5 <= half / 4.0 * 1.01) ring *= 5;
  else if (ring * 2 <= half / 4.0 * 1.01) ring *= 2;
  for (double rr = ring; rr <= half * 1.42; rr += ring)
    for (int k = 0; k < 1440; k++) {
      double a = k * 3.14159265358979 / 720.0;
      int x = bx + bev / 2 + (int)(rr * ppm * sin(a)), y = by + bev / 2 - (int)(rr * ppm * cos(a));
      if (x >= bx && x < bx + bev && y >= by && y < by + bev) put(&cv, x, y, (const uint8_t[]){50, 50, 60});
    }
  for (double rr = ring; rr < half; rr += ring) {
    snprintf(line, sizeof line, "%.0f m", rr);
    text(&cv, bx + bev / 2 + 3, by + bev / 2 - (int)(rr * ppm) + 2, 1, GREY, line);
  }
  /* background first, then foreground on top */
  for (int pass = 0; pass < 2; pass++)
    for (int r = 0; r < rows; r++)
      for (int col = 0; col < cols; col++) {
        int i = r * cols + col;
        float d = frame.range[i];
        if (d <= 0) continue;
        bool fg = have_model && frame.label[i] >= RS_LABEL_NOISE;
        if (fg != (pass == 1)) continue;
        int laser = sensor->laser_of_row[r];
        double az = (col + 0.5) * 360.0 / cols * 3.14159265358979 / 180.0;
        double g = d * sensor->cos_el[laser];
        int x = bx + bev / 2 + (int)lround(g * sin(az) * ppm), y = by + bev / 2 - (int)lround(g * cos(az) * ppm);
        if (x < bx || x >= bx + bev || y < by || y >= by + bev) continue;
        uint8_t rgb[3];
        label_rgb(frame.label[i], d, max_r, have_model, rgb);
        if (!fg && have_model) {
          rgb[0] = (uint8_t)(rgb[0] / 2);
          rgb[1] = (uint8_t)(rgb[1] / 2);
          rgb[2] = (uint8_t)(rgb[2] / 2);
        }
        rect(&cv, x, y, fg ? 2 : 1, fg ? 2 : 1, rgb);
      }
  rect(&cv, bx + bev / 2 - 2, by + bev / 2 - 2, 5, 5, WHITE); /* the sensor */
  /* scale bar: ring metres */
  const int sy = by + bev - 16;
  rect(&cv, bx + 10, sy, (int)(ring * ppm), 3, WHITE);
  snprintf(line, sizeof line, "%.0f m", ring);
  text(&cv, bx + 14 + (int)(ring * ppm), sy - 2, 1, WHITE, line);
  text(&cv, bx + bev / 2 - 12, by + 4, 1, GREY, "AZ 0");

  /* legend */
  int ly = legend_beside ? by + 4 : by + bev + 14, lx = legend_beside ? bx + bev + 24 : margin;
  uint8_t c1[3], c2[3], c3[3];
  range_rgb((float)(max_r * 0.1), max_r, c1);
  range_rgb((float)(max_r * 0.9), max_r, c2);
  rect(&cv, lx, ly, 14, 10, c1);
  rect(&cv, lx + 14, ly, 14, 10, c2);
  snprintf(line, sizeof line, "%s, grey by range (light = near, 0 to %.0f m)",
           have_model ? "background" : "every return", max_r);
  text(&cv, lx + 36, ly + 2, 1, WHITE, line);
  ly += 18;
  if (have_model) {
    rect(&cv, lx, ly, 28, 10, NOISE);
    text(&cv, lx + 36, ly + 2, 1, WHITE, "noise: foreground in no cluster");
    ly += 18;
    for (int k = 0; k < 4; k++) {
      cluster_rgb(k + 1, c3);
      rect(&cv, lx + k * 7, ly, 7, 10, c3);
    }
    text(&cv, lx + 36, ly + 2, 1, WHITE, "clusters: one colour each");
    ly += 18;
  }
  rect(&cv, lx, ly, 28, 10, NONE);
  rect(&cv, lx, ly, 28, 1, GREY);
  text(&cv, lx + 36, ly + 2, 1, WHITE, "no return");
  ly += 18;
  text(&cv, lx, ly + 2, 1, GREY, "top: range image, azimuth 0-360 deg left to right,");
  text(&cv, lx, ly + 14, 1, GREY, "lasers by elevation (highest on top)");
  text(&cv, lx, ly + 26, 1, GREY, "below: bird's-eye view, sensor at the centre, azimuth 0 up");

  png_image img;
  memset(&img, 0, sizeof img);
  img.version = PNG_IMAGE_VERSION;
  img.width = (png_uint_32)cv.w;
  img.height = (png_uint_32)cv.h;
  img.format = PNG_FORMAT_RGB;
  int ok = png_image_write_to_file(&img, out, 0, cv.px, 0, NULL);
  free(cv.px);
  if (bg_path) rs_bg_model_free(&model);
  if (!ok) {
    fprintf(stderr, "roadscan-render: %s: cannot write the picture\n", out);
    return 1;
  }
  fprintf(stderr, "roadscan-render: frame %ld of %s: %u returns%s -> %s\n", frame_no, capture, returns,
          have_model ? "" : " (no background model)", out);
  return 0;
bad:
  fprintf(stderr, "roadscan-render: %s\n", err);
  return 2;
}

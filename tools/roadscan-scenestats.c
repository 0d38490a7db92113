/* roadscan-scenestats - the static-scene statistics of captures, side by side.
 *
 *   roadscan-scenestats CAPTURE[@FROM-TO] ... [--max-frames N] [--names A,B,...]
 *
 * Each capture goes through the daemon's decoder and frame assembler; the
 * complete frames FROM to TO (1 = the first complete frame; default all, at
 * most --max-frames) are measured (scenestats.h) and printed as one column
 * of a Markdown table. docs/simulator.md puts the real captures next to the
 * simulator's this way (scripts/sim-vs-real.sh). Single-threaded tool. */
#include "roadscan/util/opts.h"
#include "roadscan/frame/framer.h"
#include "roadscan/offline/scenestats.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define MAX_INPUTS 8

static rs_slot_t slots[2];
static rs_framer_t framer;

typedef struct {
  long from, to, seen;
  int max_frames;
  rs_sstats_frames_t fr;
  bool ready;
  int rc;
} collect_t;

static void on_frame(void *user, rs_slot_t *s) {
  collect_t *c = user;
  if (s->meta.partial || c->rc != RS_OK) return;
  c->seen++;
  if (c->seen < c->from) return;
  if ((c->to > 0 && c->seen > c->to) || (c->ready && c->fr.nframes >= c->fr.max_frames)) {
    framer.stop = true;
    return;
  }
  if (!c->ready) {
    c->rc = rs_sstats_init(&c->fr, s->meta.model, s->meta.rows, s->meta.cols, c->max_frames);
    if (c->rc != RS_OK) return;
    c->ready = true;
  }
  rs_sstats_add(&c->fr, s);
}

static void row(const char *name, const rs_sstats_t *st, int n, double (*get)(const rs_sstats_t *, int), int band,
                const char *fmt) {
  printf("| %s |", name);
  for (int i = 0; i < n; i++) {
    double v = get(&st[i], band);
    if (isnan(v)) printf(" - |");
    else {
      printf(" ");
      printf(fmt, v);
      printf(" |");
    }
  }
  printf("\n");
}

#define G(field) static double g_##field(const rs_sstats_t *s, int b) { (void)b; return s->field; }
#define GB(field) static double g_##field(const rs_sstats_t *s, int b) { return s->field[b]; }
G(frames)
G(hz)
G(rate_jitter)
G(phase_step)
G(steady)
G(multi)
G(edge_spread_med)
G(edge_spread_p90)
G(dwell)
G(dwell_indep)
G(mixed)
GB(flat_sd)
static double g_flat_cells(const rs_sstats_t *s, int b) { return s->flat_cells[b]; }
G(drop_row_min)
G(drop_row_med)
G(drop_row_max)
GB(noise_sd)
GB(dev_p99)
GB(dev_10cm)
GB(dropout)
GB(intensity_med)
static double g_cells(const rs_sstats_t *s, int b) { return s->band_cells[b]; }
static double pct(double v) { return v * 100.0; }
static double g_steady_pct(const rs_sstats_t *s, int b) { return pct(g_steady(s, b)); }
static double g_multi_pct(const rs_sstats_t *s, int b) { return pct(g_multi(s, b)); }
static double g_dev10_pct(const rs_sstats_t *s, int b) { return pct(g_dev_10cm(s, b)); }
static double g_drop_pct(const rs_sstats_t *s, int b) { return pct(g_dropout(s, b)); }
static double g_rowmin_pct(const rs_sstats_t *s, int b) { return pct(g_drop_row_min(s, b)); }
static double g_rowmed_pct(const rs_sstats_t *s, int b) { return pct(g_drop_row_med(s, b)); }
static double g_rowmax_pct(const rs_sstats_t *s, int b) { return pct(g_drop_row_max(s, b)); }
static double g_mixed_pct(const rs_sstats_t *s, int b) { return pct(g_mixed(s, b)); }
static double g_flat_cm(const rs_sstats_t *s, int b) { return 100.0 * g_flat_sd(s, b); }
static double g_sd_cm(const rs_sstats_t *s, int b) { return 100.0 * g_noise_sd(s, b); }
static double g_p99_cm(const rs_sstats_t *s, int b) { return 100.0 * g_dev_p99(s, b); }

/* Everything the options set. */
typedef struct {
  int max_frames;
  const char *names;
} settings_t;
static settings_t settings = {.max_frames = 600};
static rs_opts_t opts;

static const rs_opt_t table[] = {
    RS_OPT_INT_("max-frames", "N", settings_t, max_frames, 2, 100000, "at most N frames of each capture"),
    {.type = RS_OPT_STR, .name = "names", .arg = "A,B,...", .off = offsetof(settings_t, names),
     .def = "the file names", .help = "column names"},
};

static const rs_opts_spec_t spec = {
    .prog = "roadscan-scenestats",
    .summary = "the static-scene statistics of captures, side by side",
    .synopsis = "CAPTURE[@FROM-TO] ... [--max-frames N] [--names A,B,...]",
    .about = "Each capture goes through the daemon's decoder and frame assembler; its complete frames FROM to TO "
             "(CAPTURE@FROM-TO; 1 = the first complete frame; default all, at most --max-frames) are measured and "
             "printed as one column of a Markdown table, up to 8 captures (docs/simulator.md puts the real "
             "captures next to the simulator's this way).",
    .epilog = "Exit status: 0 printed, 1 a capture could not be read, 2 bad usage.",
    .min_args = 1,
    .max_args = MAX_INPUTS,
    .opts = table,
    .n = (int)(sizeof table / sizeof table[0]),
};

int main(int argc, char **argv) {
  char err[RS_ERRMSG_SIZE], names[1024] = "";
  int optind_;
  const int start = rs_opts_start(&opts, &spec, &settings, argc, argv, &optind_);
  if (start >= 0) return start;
  const long max_frames = settings.max_frames;
  if (settings.names) snprintf(names, sizeof names, "%s", settings.names);
  const int n = argc - optind_;
  static rs_sstats_t st[MAX_INPUTS];
  const char *label[MAX_INPUTS];
  char *save = NULL, *tok = names[0] ? strtok_r(names, ",", &save) : NULL;
  for (int i = 0; i < n; i++) {
    char path[1024];
    snprintf(path, sizeof path, "%s", argv[optind_ + i]);
    static collect_t col;
    memset(&col, 0, sizeof col);
    col.from = 1;
    col.max_frames = (int)max_frames;
    char *at = strrchr(path, '@');
    if (at) {
      *at = '\0';
      char *end;
      col.from = strtol(at + 1, &end, 10);
      if (*end == '-') col.to = strtol(end + 1, &end, 10);
      if (*end != '\0' || col.from < 1 || (col.to && col.to < col.from)) {
        snprintf(err, sizeof err, "'@%.64s' is not @FROM-TO", at + 1);
        goto bad;
      }
      if (col.to && col.to - col.from + 1 < col.max_frames) col.max_frames = (int)(col.to - col.from + 1);
    }
    label[i] = tok ? tok : argv[optind_ + i];
    tok = tok ? strtok_r(NULL, ",", &save) : NULL;
    rs_stream_cfg_t scfg = {.log = NULL};
    rs_asm_cfg_t acfg = {.default_hz = 10.0};
    if (rs_framer_init(&framer, &scfg, &acfg, slots, on_frame, &col) != RS_OK) {
      fprintf(stderr, "roadscan-scenestats: %s\n", framer.stream.err);
      return 1;
    }
    int rc = rs_framer_replay_file(&framer, path, err, sizeof err);
    if (rc != RS_OK && !framer.stop) {
      fprintf(stderr, "roadscan-scenestats: %s\n", err);
      if (rc == RS_E_NOENT || rc == RS_E_FORMAT || rc == RS_E_LINKTYPE) return 1;
    }
    if (col.rc != RS_OK || !col.ready || col.fr.nframes < 2) {
      fprintf(stderr, "roadscan-scenestats: %s: fewer than 2 complete frames in the range\n", path);
      return 1;
    }
    if (rs_sstats_compute(&col.fr, &st[i]) != RS_OK) {
      fprintf(stderr, "roadscan-scenestats: out of memory\n");
      return 1;
    }
    rs_sstats_free(&col.fr);
  }
  printf("| statistic |");
  for (int i = 0; i < n; i++) printf(" %s |", label[i]);
  printf("\n|---|");
  for (int i = 0; i < n; i++) printf("---|");
  printf("\n");
  row("frames", st, n, g_frames, 0, "%.0f");
  row("rotation rate (Hz)", st, n, g_hz, 0, "%.2f");
  row("rotation rate jitter (% sd)", st, n, g_rate_jitter, 0, "%.2f");
  row("firings' turn-to-turn move (share of the block step)", st, n, g_phase_step, 0, "%.2f");
  row("steady cells (return in half the frames or more)", st, n, g_steady_pct, 0, "%.1f %%");
  row("steady cells with 2+ surfaces", st, n, g_multi_pct, 0, "%.2f %%");
  row("their range spread, median (m)", st, n, g_edge_spread_med, 0, "%.2f");
  row("their range spread, 90th percentile (m)", st, n, g_edge_spread_p90, 0, "%.2f");
  row("frames on one surface in a row (mean)", st, n, g_dwell, 0, "%.2f");
  row("... if it chose independently every frame", st, n, g_dwell_indep, 0, "%.2f");
  row("returns between the surfaces of those cells (mixed)", st, n, g_mixed_pct, 0, "%.2f %%");
  row("dropout by row: lowest", st, n, g_rowmin_pct, 0, "%.2f %%");
  row("dropout by row: median", st, n, g_rowmed_pct, 0, "%.2f %%");
  row("dropout by row: highest", st, n, g_rowmax_pct, 0, "%.2f %%");
  for (int b = 0; b < RS_SSTATS_BANDS; b++) {
    char name[128], lo[32];
    if (b + 1 < RS_SSTATS_BANDS) snprintf(lo, sizeof lo, "%.0f-%.0f m", rs_sstats_band_lo[b], rs_sstats_band_lo[b + 1]);
    else snprintf(lo, sizeof lo, "%.0f m+", rs_sstats_band_lo[b]);
    snprintf(name, sizeof name, "%s: steady cells", lo);
    row(name, st, n, g_cells, b, "%.0f");
    snprintf(name, sizeof name, "%s: dropout", lo);
    row(name, st, n, g_drop_pct, b, "%.2f %%");
    snprintf(name, sizeof name, "%s: range noise, robust sd (cm)", lo);
    row(name, st, n, g_sd_cm, b, "%.1f");
    snprintf(name, sizeof name, "%s: flat cells", lo);
    row(name, st, n, g_flat_cells, b, "%.0f");
    snprintf(name, sizeof name, "%s: range noise on flat cells, robust sd (cm)", lo);
    row(name, st, n, g_flat_cm, b, "%.1f");
    snprintf(name, sizeof name, "%s: deviation from the cell's median, 99th pct (cm)", lo);
    row(name, st, n, g_p99_cm, b, "%.0f");
    snprintf(name, sizeof name, "%s: returns over 10 cm from the cell's median", lo);
    row(name, st, n, g_dev10_pct, b, "%.2f %%");
    snprintf(name, sizeof name, "%s: intensity, median", lo);
    row(name, st, n, g_intensity_med, b, "%.0f");
  }
  return 0;
bad:
  fprintf(stderr, "roadscan-scenestats: %s\n", err);
  return 2;
}

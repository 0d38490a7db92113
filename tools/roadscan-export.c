/* roadscan-export - write the decoded points of one frame as PCD or CSV.
 *
 * Single-threaded tool: reads the capture flat out through the framer the
 * daemon's tools share (stream decoder + frame assembler) and takes every
 * packet's points with the frame the assembler gave each block, so frame N
 * here is frame N of the daemon's --frames-out. */
#include "roadscan/sensor/calib.h"
#include "roadscan/util/config.h"
#include "roadscan/util/opts.h"
#include "roadscan/util/error.h"
#include "roadscan/frame/frame.h"
#include "roadscan/capture/stream.h"
#include "roadscan/frame/framer.h"

#include <math.h>
#include <limits.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

typedef struct {
  uint64_t want;         /* UINT64_MAX: every frame (--frame all) */
  uint64_t frame;        /* the last frame that took returns */
  rs_point_t *pts;
  uint32_t *fr;          /* frame of each point */
  size_t n, cap;
  bool oom;
} export_t;

static rs_framer_t framer;
static rs_slot_t slots[2];
static rs_calib_t calib;

/* every packet as the daemon's assembler framed it: its points go to the frame of their block */
static void on_packet(void *user, const rs_packet_t *pkt, uint32_t index, const uint64_t *block_seq) {
  (void)index;
  export_t *e = user;
  for (int pi = 0; pi < pkt->n_points && !framer.stop; pi++) {
    const uint64_t seq = block_seq[pkt->points[pi].block];
    if (seq == RS_ASM_DROPPED) continue; /* a duplicate, or a late packet: not in any frame */
    if (e->want != UINT64_MAX && seq > e->want) {
      framer.stop = true;
      break;
    }
    e->frame = seq;
    if (e->want != UINT64_MAX && seq != e->want) continue;
    if (e->n == e->cap) {
      size_t nc = e->cap ? e->cap * 2 : 65536;
      rs_point_t *np = realloc(e->pts, nc * sizeof *np);
      if (np) e->pts = np;
      uint32_t *nf = np ? realloc(e->fr, nc * sizeof *nf) : NULL;
      if (nf == NULL) {
        e->oom = framer.stop = true;
        return;
      }
      e->fr = nf;
      e->cap = nc;
    }
    e->fr[e->n] = (uint32_t)seq;
    e->pts[e->n++] = pkt->points[pi];
  }
}

static int parse_frame(void *t, const char *key, const char *v, char *err, size_t n) {
  long l;
  if (strcmp(v, "all") == 0) l = LONG_MAX;
  else if (rs_cfg_long(key, v, 0, 100000000L, &l, err, n) != RS_OK) return RS_E_INVAL;
  *(long *)t = l;
  return RS_OK;
}

/* Everything the options set. */
typedef struct {
  long frame;
  const char *out_path, *calib_path;
  bool csv;
  int port;
  rs_model_t model;
  double cut;
} settings_t;
static settings_t st;
static rs_opts_t opts;

#define T settings_t
static const rs_opt_t table[] = {
    {.type = RS_OPT_FUNC, .name = "frame", .arg = "N", .off = offsetof(T, frame), .fn = parse_frame,
     .help = "frame number (0 = the partial frame before the first roll-over, as the daemon's --frames-out); "
             "'all': every point of the capture, with its frame (CSV column 'frame')"},
    RS_OPT_OUTPUT_("FILE", T, out_path, "output file (PCD v0.7 ASCII, or CSV with --csv)"),
    RS_OPT_FLAG_("csv", T, csv, "write CSV instead of PCD"),
    RS_OPT_FORCE_MODEL_("model", T, model),
    RS_OPT_CALIB_(T, calib_path),
    RS_OPT_INT_("port", "N", T, port, 1, 65535, "data port"),
    RS_OPT_DBL_("cut-azimuth", "DEG", T, cut, 0.0, 359.99, "frame boundary azimuth"),
};
#undef T

static const rs_opts_spec_t spec = {
    .prog = "roadscan-export",
    .summary = "write the decoded points of one frame (or of all) as PCD or CSV",
    .synopsis = "CAPTURE --frame N -o OUT.pcd [--csv] [options]",
    .about = "The capture is read flat out through the daemon's decoder and frame assembler, so frame N here is "
             "frame N of roadscand --frames-out; duplicated and late packets are left out as the daemon leaves "
             "them out.\n\nFields: x y z (m, sensor frame: +X right, +Y forward, +Z up) intensity ring (row by "
             "elevation, 0 = lowest) azimuth (deg, clockwise from +Y) distance (m) return_type (0 strongest, "
             "1 last, 2 dual-last, 3 dual-strongest, 4 dual-second, 5 dual-same).",
    .epilog = "Exit status: 0 written, 1 the capture or a file could not be read or written, or no such frame, "
              "2 bad usage.",
    .min_args = 1,
    .max_args = 1,
    .opts = table,
    .n = (int)(sizeof table / sizeof table[0]),
};

int main(int argc, char **argv) {
  st = (settings_t){.frame = -1, .port = RS_DEFAULT_DATA_PORT};
  char err[RS_ERRMSG_SIZE];
  int first;
  const int start = rs_opts_start(&opts, &spec, &st, argc, argv, &first);
  if (start >= 0) return start;
  if (st.frame < 0 || st.out_path == NULL) {
    snprintf(err, sizeof err, "--frame N and -o FILE are required (see --help)");
    goto bad;
  }
  const char *out_path = st.out_path;
  const long frame = st.frame;
  const bool csv = st.csv;
  rs_stream_cfg_t scfg = {.log = stderr, .force_model = st.model, .data_port = (uint16_t)st.port};
  if (st.calib_path) {
    if (rs_calib_load_yaml(st.calib_path, &calib, err, sizeof err) != RS_OK) {
      fprintf(stderr, "roadscan-export: %s\n", err);
      return 1;
    }
    scfg.calib = &calib;
  }
  const rs_asm_cfg_t acfg = {.default_hz = 10.0, .cut_deg = st.cut};
  const bool all = frame == LONG_MAX;
  export_t e = {.want = all ? UINT64_MAX : (uint64_t)frame};
  if (rs_framer_init(&framer, &scfg, &acfg, slots, NULL, &e) != RS_OK) {
    fprintf(stderr, "roadscan-export: %s\n", framer.stream.err);
    return 1;
  }
  framer.on_packet = on_packet;
  int rc = rs_framer_replay_file(&framer, argv[first], err, sizeof err);
  if (rc == RS_E_NOENT || rc == RS_E_FORMAT || rc == RS_E_LINKTYPE || rc == RS_E_CALIB) {
    fprintf(stderr, "roadscan-export: %s\n", err);
    return 1;
  }
  if (rc != RS_OK) fprintf(stderr, "roadscan-export: %s\n", err);
  if (e.oom) {
    fprintf(stderr, "roadscan-export: out of memory\n");
    return 1;
  }
  if (!all && e.n == 0) {
    fprintf(stderr, "roadscan-export: the capture has %llu frames (0..%llu); frame %ld does not exist\n",
            (unsigned long long)(e.frame + 1), (unsigned long long)e.frame, frame);
    free(e.pts);
    free(e.fr);
    return 1;
  }
  FILE *out = fopen(out_path, "w");
  if (out == NULL) {
    fprintf(stderr, "roadscan-export: %s: cannot write\n", out_path);
    free(e.pts);
    free(e.fr);
    return 1;
  }
  if (csv) {
    fprintf(out, "x,y,z,intensity,ring,azimuth,distance,return_type,laser,packet_block,channel%s\n", all ? ",frame" : "");
  } else {
    fprintf(out,
            "# .PCD v0.7 - Point Cloud Data file format (roadscan-export)\n"
            "VERSION 0.7\nFIELDS x y z intensity ring azimuth distance return_type\n"
            "SIZE 4 4 4 4 2 4 4 1\nTYPE F F F F U F F U\nCOUNT 1 1 1 1 1 1 1 1\n"
            "WIDTH %zu\nHEIGHT 1\nVIEWPOINT 0 0 0 1 0 0 0\nPOINTS %zu\nDATA ascii\n",
            e.n, e.n);
  }
  for (size_t i = 0; i < e.n; i++) {
    const rs_point_t *p = &e.pts[i];
    if (csv)
      fprintf(out, all ? "%.4f,%.4f,%.4f,%u,%u,%.3f,%.3f,%u,%u,%u,%u,%u\n" : "%.4f,%.4f,%.4f,%u,%u,%.3f,%.3f,%u,%u,%u,%u\n",
              (double)p->x, (double)p->y, (double)p->z, p->intensity, p->row, (double)p->azimuth, (double)p->distance,
              p->return_type, p->laser, p->block, p->channel, e.fr[i]);
    else
      fprintf(out, "%.4f %.4f %.4f %u %u %.3f %.3f %u\n", (double)p->x, (double)p->y, (double)p->z, p->intensity,
              p->row, (double)p->azimuth, (double)p->distance, p->return_type);
  }
  int bad_close = fclose(out) != 0;
  if (all) fprintf(stderr, "roadscan-export: %llu frames: %zu points -> %s\n", (unsigned long long)(e.frame + 1), e.n, out_path);
  else fprintf(stderr, "roadscan-export: frame %ld: %zu points -> %s\n", frame, e.n, out_path);
  free(e.pts);
  free(e.fr);
  return bad_close ? 1 : 0;
bad:
  fprintf(stderr, "roadscan-export: %s\n", err);
  return 2;
}

/* roadscan-export - write the decoded points of one frame as PCD or CSV.
 *
 * Single-threaded tool: reads the capture flat out through the same stream
 * decoder as the daemon and cuts frames with the same roll-over rule, so
 * frame N here is frame N of the daemon's --frames-out. */
#include "roadscan/sensor/calib.h"
#include "roadscan/util/config.h"
#include "roadscan/util/error.h"
#include "roadscan/frame/frame.h"
#include "roadscan/capture/stream.h"

#include <getopt.h>
#include <math.h>
#include <limits.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

typedef struct {
  uint64_t want;         /* UINT64_MAX: every frame (--frame all) */
  uint64_t frame;        /* frame of the current block */
  int cut_cd;
  int32_t last_rel;
  rs_point_t *pts;
  uint32_t *fr;          /* frame of each point */
  size_t n, cap;
  bool done, oom;
} export_t;

static rs_stream_t stream;
static rs_calib_t calib;

static void on_packet(void *user, const rs_packet_t *pkt, uint32_t index, double ts) {
  (void)index;
  (void)ts;
  export_t *e = user;
  if (e->done) return;
  /* a packet behind the previous one (out of order) stays in the current frame */
  int32_t rel0 = ((int32_t)pkt->block_azimuth[0] - e->cut_cd + 36000) % 36000;
  bool behind = e->last_rel >= 0 && rel0 < e->last_rel && e->last_rel - rel0 <= 18000;
  int pi = 0;
  for (int b = 0; b < pkt->blocks; b++) {
    if (!behind && rs_frame_rollover(e->cut_cd, &e->last_rel, pkt->block_azimuth[b])) e->frame++;
    if (e->want != UINT64_MAX && e->frame > e->want) {
      e->done = true;
      return;
    }
    for (; pi < pkt->n_points && pkt->points[pi].block == b; pi++) {
      if (e->want != UINT64_MAX && e->frame != e->want) continue;
      if (e->n == e->cap) {
        size_t nc = e->cap ? e->cap * 2 : 65536;
        rs_point_t *np = realloc(e->pts, nc * sizeof *np);
        if (np) e->pts = np;
        uint32_t *nf = np ? realloc(e->fr, nc * sizeof *nf) : NULL;
        if (nf == NULL) {
          e->oom = e->done = true;
          return;
        }
        e->fr = nf;
        e->cap = nc;
      }
      e->fr[e->n] = (uint32_t)e->frame;
      e->pts[e->n++] = pkt->points[pi];
    }
  }
}

static void usage(FILE *out) {
  fprintf(out,
          "usage: roadscan-export CAPTURE --frame N -o OUT.pcd [--csv] [options]\n"
          "  --frame N            frame number (0 = the partial frame before the first roll-over);\n"
          "                       'all': every point of the capture, with its frame (CSV column 'frame')\n"
          "  -o, --output FILE    output file (PCD v0.7 ASCII, or CSV with --csv)\n"
          "  --csv                write CSV instead of PCD\n"
          "  --model NAME         force the sensor model (%s)\n"
          "  --calibration FILE   per-unit calibration (ROS velodyne YAML)\n"
          "  --port N             data port (default 2368)\n"
          "  --cut-azimuth DEG    frame boundary azimuth (default 0)\n"
          "Fields: x y z (m, sensor frame: +X right, +Y forward, +Z up) intensity ring (row by\n"
          "elevation, 0 = lowest) azimuth (deg, clockwise from +Y) distance (m) return_type\n"
          "(0 strongest, 1 last, 2 dual-last, 3 dual-strongest, 4 dual-second, 5 dual-same).\n",
          rs_model_names());
}

int main(int argc, char **argv) {
  enum { O_FRAME = 256, O_CSV, O_MODEL, O_CALIB, O_PORT, O_CUT, O_HELP };
  static const struct option opts[] = {{"frame", required_argument, NULL, O_FRAME},
                                       {"output", required_argument, NULL, 'o'},
                                       {"csv", no_argument, NULL, O_CSV},
                                       {"model", required_argument, NULL, O_MODEL},
                                       {"calibration", required_argument, NULL, O_CALIB},
                                       {"port", required_argument, NULL, O_PORT},
                                       {"cut-azimuth", required_argument, NULL, O_CUT},
                                       {"help", no_argument, NULL, O_HELP},
                                       {NULL, 0, NULL, 0}};
  const char *out_path = NULL, *calib_path = NULL;
  long frame = -1, l;
  double cut = 0.0;
  bool csv = false;
  char err[RS_ERRMSG_SIZE];
  rs_stream_cfg_t scfg;
  memset(&scfg, 0, sizeof scfg);
  scfg.log = stderr;
  int c;
  while ((c = getopt_long(argc, argv, "o:", opts, NULL)) != -1) {
    switch (c) {
    case O_FRAME:
      if (strcmp(optarg, "all") == 0) frame = LONG_MAX;
      else if (rs_cfg_long("--frame", optarg, 0, 100000000L, &frame, err, sizeof err)) goto bad;
      break;
    case 'o': out_path = optarg; break;
    case O_CSV: csv = true; break;
    case O_MODEL:
      if (rs_cfg_model("--model", optarg, &scfg.force_model, err, sizeof err)) goto bad;
      break;
    case O_CALIB: calib_path = optarg; break;
    case O_PORT:
      if (rs_cfg_long("--port", optarg, 1, 65535, &l, err, sizeof err)) goto bad;
      scfg.data_port = (uint16_t)l;
      break;
    case O_CUT:
      if (rs_cfg_double("--cut-azimuth", optarg, 0.0, 359.99, &cut, err, sizeof err)) goto bad;
      break;
    case O_HELP: usage(stdout); return 0;
    default: usage(stderr); return 2;
    }
  }
  if (optind + 1 != argc || frame < 0 || out_path == NULL) {
    usage(stderr);
    return 2;
  }
  if (calib_path) {
    if (rs_calib_load_yaml(calib_path, &calib, err, sizeof err) != RS_OK) {
      fprintf(stderr, "roadscan-export: %s\n", err);
      return 1;
    }
    scfg.calib = &calib;
  }
  if (rs_stream_init(&stream, &scfg) != RS_OK) {
    fprintf(stderr, "roadscan-export: %s\n", stream.err);
    return 1;
  }
  const bool all = frame == LONG_MAX;
  export_t e = {.want = all ? UINT64_MAX : (uint64_t)frame, .cut_cd = (int)lround(cut * 100.0) % 36000, .last_rel = -1};
  int rc = rs_stream_replay_file(&stream, argv[optind], on_packet, &e, &e.done, err, sizeof err);
  if (rc == RS_E_NOENT || rc == RS_E_FORMAT || rc == RS_E_LINKTYPE || rc == RS_E_CALIB) {
    fprintf(stderr, "roadscan-export: %s\n", err);
    return 1;
  }
  if (rc != RS_OK) fprintf(stderr, "roadscan-export: %s\n", err);
  if (e.oom) {
    fprintf(stderr, "roadscan-export: out of memory\n");
    return 1;
  }
  if (!all && (e.frame < e.want || (e.n == 0 && !e.done))) {
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

/* roadscan-eval - compare two point-label files over a capture.
 *
 *   roadscan-eval CAPTURE TRUTH PRED [--json] [--objects FILE] [--diagnose [--model BG]]
 *
 * Reads the capture with the project's decoder, walks its returns in
 * address order merging both label files (unlisted = 1), cuts frames where
 * a block azimuth is smaller than the previous block's (the spec's rule),
 * skips frame 0, and prints the metrics. --objects writes the centroid of
 * every true instance of every frame (frame numbers as roadscand's
 * frame_seq: 0 is the part before the first roll-over). --diagnose says
 * where the object returns the prediction missed are, and (with the
 * background model) where its false positives are. Single-threaded. */
#include "roadscan/background.h"
#include "roadscan/eval.h"
#include "roadscan/labels.h"
#include "roadscan/stream.h"

#include <getopt.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

typedef struct {
  rs_labels_reader_t rd;
  rs_label_t cur;
  bool have;
  const char *role;
} src_t;

#define MAX_INST 4096
typedef struct {
  uint32_t label, n;
  double sum[3];
} inst_t;

/* --diagnose: the returns of a frame that are true or predicted objects */
typedef struct {
  float az, range;
  uint16_t row;
  uint32_t truth, pred;
} dpt_t;

typedef struct {
  bool on;
  const rs_bg_model_t *model;
  dpt_t *pts;
  size_t n, cap;
  bool oom;
  uint64_t target, missed, whole[3], partial, partial_dr[4]; /* 1-4, 5-9, 10+ returns; <1.8, <3, <6, >=6 m */
  uint64_t by_surfaces[2][RS_BG_SURFACES + 1];                /* [true object?][static surfaces of the cell] */
  uint64_t fp_truth[2];        /* false object returns: static background, foliage or spurious */
  uint64_t fp_where[4];        /* static ones against their cell's surfaces: none, in front, between, beyond */
  uint64_t fp_range[4];        /* static ones by range: < 50, 50-100, 100-150, >= 150 m */
  uint64_t merged[2];          /* merged instances (>= 10 returns): with another object, with non-objects */
  uint64_t merged_range[4];    /* ... by the instance's mean range: < 20, 20-50, 50-100, >= 100 m */
} diag_t;

typedef struct {
  src_t s[2];
  FILE *objects;
  diag_t dg;
  inst_t inst[MAX_INST];
  uint32_t ninst, last;
  rs_eval_t ev;
  int prev_az;
  uint64_t frame;
  bool failed;
  char err[2 * RS_ERRMSG_SIZE];
} ctx_t;

static rs_stream_t stream;

static void add_instance(ctx_t *c, uint32_t label, const rs_point_t *p) {
  if (c->last >= c->ninst || c->inst[c->last].label != label) {
    uint32_t i = 0;
    while (i < c->ninst && c->inst[i].label != label) i++;
    if (i == c->ninst) {
      if (c->ninst == MAX_INST) return;
      c->inst[c->ninst++] = (inst_t){label, 0, {0, 0, 0}};
    }
    c->last = i;
  }
  inst_t *t = &c->inst[c->last];
  t->n++;
  t->sum[0] += p->x;
  t->sum[1] += p->y;
  t->sum[2] += p->z;
}

static int cmp_truth(const void *a, const void *b) {
  uint32_t x = ((const dpt_t *)a)->truth, y = ((const dpt_t *)b)->truth;
  return (x > y) - (x < y);
}

static void diag_point(diag_t *d, const rs_point_t *p, uint32_t truth, uint32_t pred) {
  if (truth < 3 && pred < 3) return;
  if (d->n == d->cap) {
    size_t nc = d->cap ? 2 * d->cap : 65536;
    dpt_t *np = realloc(d->pts, nc * sizeof *np);
    if (np == NULL) {
      d->oom = true;
      return;
    }
    d->pts = np;
    d->cap = nc;
  }
  d->pts[d->n++] = (dpt_t){p->azimuth, p->distance, p->row, truth, pred};
}

/* A true instance pts[a, b): when over half of it lies in one cluster that
 * holds as much else (IoU <= 0.5, as roadscan-eval counts "merged"), what
 * else: another object's returns, or only non-object returns. */
static void diag_merge(diag_t *d, size_t a, size_t b) {
  uint32_t best = 0, inter = 0;
  double range = 0.0;
  for (size_t i = a; i < b; i++) {
    range += d->pts[i].range;
    if (d->pts[i].pred < 3) continue;
    uint32_t c = 0;
    for (size_t j = a; j < b; j++) c += d->pts[j].pred == d->pts[i].pred;
    if (c > inter) {
      inter = c;
      best = d->pts[i].pred;
    }
  }
  const uint32_t n = (uint32_t)(b - a);
  if (2 * inter <= n) return;
  uint32_t size = 0, other_obj = 0;
  for (size_t j = 0; j < d->n; j++) {
    if (d->pts[j].pred != best) continue;
    size++;
    other_obj += d->pts[j].truth >= 3 && (j < a || j >= b);
  }
  if ((double)inter / (double)(n + size - inter) > 0.5) return;
  d->merged[other_obj == 0]++;
  range /= (double)n;
  d->merged_range[range < 20 ? 0 : range < 50 ? 1 : range < 100 ? 2 : 3]++;
}

/* One frame: missed object returns, by whether their object has a clustered return
 * (and how far in range the nearest one, by azimuth and ring, is), and predicted
 * object returns by the static surfaces of their cell. */
static void diag_frame(diag_t *d) {
  qsort(d->pts, d->n, sizeof d->pts[0], cmp_truth);
  for (size_t i = 0; i < d->n; i++) {
    const dpt_t *p = &d->pts[i];
    if (p->pred >= 3 && d->model) {
      int col = (int)(p->az * d->model->cols / 360.0f) % d->model->cols;
      int s = p->row < d->model->rows ? d->model->n[(size_t)p->row * d->model->cols + (size_t)col] : 0;
      d->by_surfaces[p->truth >= 3][s > RS_BG_SURFACES ? RS_BG_SURFACES : s]++;
      if (p->truth < 3) {
        d->fp_truth[p->truth == 2]++;
        if (p->truth != 2) {
          const size_t cell = (size_t)p->row * d->model->cols + (size_t)col;
          const float cm = p->range * 100.0f;
          int w = s == 0 ? 0 : cm < d->model->lo[cell * RS_BG_SURFACES] ? 1 : cm > d->model->hi[cell * RS_BG_SURFACES + (size_t)s - 1] ? 3 : 2;
          d->fp_where[w]++;
          d->fp_range[p->range < 50.0f ? 0 : p->range < 100.0f ? 1 : p->range < 150.0f ? 2 : 3]++;
        }
      }
    }
  }
  for (size_t a = 0, b; a < d->n; a = b) {
    for (b = a; b < d->n && d->pts[b].truth == d->pts[a].truth; b++) {
    }
    if (d->pts[a].truth < 3) continue;
    if (b - a >= RS_EVAL_MIN_INSTANCE) diag_merge(d, a, b);
    size_t hit = 0;
    for (size_t i = a; i < b; i++) hit += d->pts[i].pred >= 3;
    d->target += b - a;
    if (hit == b - a) continue;
    d->missed += b - a - hit;
    if (hit == 0) {
      d->whole[b - a <= 4 ? 0 : b - a <= 9 ? 1 : 2] += b - a;
      continue;
    }
    for (size_t i = a; i < b; i++) {
      if (d->pts[i].pred >= 3) continue;
      float best = INFINITY, dr = 0.0f;
      for (size_t j = a; j < b; j++) {
        if (d->pts[j].pred < 3) continue;
        float daz = fabsf(d->pts[j].az - d->pts[i].az);
        if (daz > 180.0f) daz = 360.0f - daz;
        float dist = daz * 5.0f + (float)abs((int)d->pts[j].row - (int)d->pts[i].row); /* 0.2 degree ~ one ring */
        if (dist < best) {
          best = dist;
          dr = fabsf(d->pts[j].range - d->pts[i].range);
        }
      }
      d->partial++;
      d->partial_dr[dr < 1.8f ? 0 : dr < 3.0f ? 1 : dr < 6.0f ? 2 : 3]++;
    }
  }
  d->n = 0;
}

static void diag_print(const diag_t *d, FILE *out) {
  if (d->oom) fprintf(out, "diagnosis: out of memory, incomplete\n");
  fprintf(out, "diagnosis (frames 1+):\n");
  fprintf(out, "  object returns %llu, missed %llu\n", (unsigned long long)d->target, (unsigned long long)d->missed);
  fprintf(out, "  missed, of objects with no clustered return in the frame: objects of 1-4 returns %llu, 5-9 %llu, 10+ %llu\n",
          (unsigned long long)d->whole[0], (unsigned long long)d->whole[1], (unsigned long long)d->whole[2]);
  fprintf(out,
          "  missed beside a clustered return of the same object: %llu; range difference to the nearest one (azimuth,"
          " ring): < 1.8 m %llu, 1.8-3 m %llu, 3-6 m %llu, >= 6 m %llu\n",
          (unsigned long long)d->partial, (unsigned long long)d->partial_dr[0], (unsigned long long)d->partial_dr[1],
          (unsigned long long)d->partial_dr[2], (unsigned long long)d->partial_dr[3]);
  fprintf(out,
          "  merged instances: with another object %llu, with non-object returns only %llu; by mean range < 20 m "
          "%llu, 20-50 m %llu, 50-100 m %llu, >= 100 m %llu\n",
          (unsigned long long)d->merged[0], (unsigned long long)d->merged[1], (unsigned long long)d->merged_range[0],
          (unsigned long long)d->merged_range[1], (unsigned long long)d->merged_range[2],
          (unsigned long long)d->merged_range[3]);
  if (d->model) {
    fprintf(out, "  returns predicted as objects, by static surfaces of their cell (true / false):");
    for (int k = 0; k <= RS_BG_SURFACES; k++)
      fprintf(out, " %d: %llu / %llu", k, (unsigned long long)d->by_surfaces[1][k], (unsigned long long)d->by_surfaces[0][k]);
    fprintf(out, "\n");
    fprintf(out, "  false object returns: static %llu (no static surface in the cell %llu, in front of the nearest %llu, between"
                 " two %llu, beyond the farthest %llu; < 50 m %llu, 50-100 m %llu, 100-150 m %llu, >= 150 m %llu),"
                 " foliage or spurious %llu\n",
            (unsigned long long)d->fp_truth[0], (unsigned long long)d->fp_where[0], (unsigned long long)d->fp_where[1],
            (unsigned long long)d->fp_where[2], (unsigned long long)d->fp_where[3], (unsigned long long)d->fp_range[0],
            (unsigned long long)d->fp_range[1], (unsigned long long)d->fp_range[2], (unsigned long long)d->fp_range[3],
            (unsigned long long)d->fp_truth[1]);
  }
}

static void end_frame(ctx_t *c) {
  rs_eval_end_frame(&c->ev, c->frame > 0);
  if (c->dg.on) {
    if (c->frame > 0) diag_frame(&c->dg);
    c->dg.n = 0;
  }
  for (uint32_t i = 0; c->objects && i < c->ninst; i++) {
    const inst_t *t = &c->inst[i];
    if (t->n >= RS_EVAL_MIN_INSTANCE)
      fprintf(c->objects, "%llu,%u,%u,%.4f,%.4f,%.4f\n", (unsigned long long)c->frame, t->label, t->n, t->sum[0] / t->n,
              t->sum[1] / t->n, t->sum[2] / t->n);
  }
  c->ninst = 0;
  c->last = 0;
}

static int advance(ctx_t *c, src_t *s) {
  int rc = rs_labels_next(&s->rd, &s->cur);
  if (rc < 0) {
    snprintf(c->err, sizeof c->err, "%s labels: %s", s->role, s->rd.err);
    c->failed = true;
    return rc;
  }
  s->have = rc == 1;
  return RS_OK;
}

/* label of the return at key; unlisted = 1 */
static uint32_t label_at(ctx_t *c, src_t *s, uint64_t key) {
  if (!s->have) return 1;
  uint64_t k = rs_label_key(s->cur.packet, s->cur.block, s->cur.channel);
  if (k < key) {
    snprintf(c->err, sizeof c->err, "%s labels: %s:%ld: address %u,%u,%u has no return in the capture", s->role,
             s->rd.path, s->rd.line, s->cur.packet, s->cur.block, s->cur.channel);
    c->failed = true;
    return 1;
  }
  if (k > key) return 1;
  uint32_t l = s->cur.label;
  advance(c, s);
  return l;
}

static void on_packet(void *user, const rs_packet_t *pkt, uint32_t index, double ts) {
  (void)ts;
  ctx_t *c = user;
  if (c->failed) return;
  int pi = 0;
  for (int b = 0; b < pkt->blocks; b++) {
    int az = pkt->block_azimuth[b];
    if (c->prev_az >= 0 && az < c->prev_az) {
      end_frame(c);
      c->frame++;
    }
    c->prev_az = az;
    for (; pi < pkt->n_points && pkt->points[pi].block == b; pi++) {
      const rs_point_t *p = &pkt->points[pi];
      uint64_t key = rs_label_key(index, b, p->channel);
      uint32_t t = label_at(c, &c->s[0], key), pr = label_at(c, &c->s[1], key);
      if (c->failed) return;
      rs_eval_point(&c->ev, t, pr, p->distance, c->frame > 0);
      if (c->objects && t >= 3) add_instance(c, t, p);
      if (c->dg.on && c->frame > 0) diag_point(&c->dg, p, t, pr);
    }
  }
}

int main(int argc, char **argv) {
  static const struct option opts[] = {{"json", no_argument, NULL, 'j'},
                                       {"objects", required_argument, NULL, 'o'},
                                       {"diagnose", no_argument, NULL, 'd'},
                                       {"model", required_argument, NULL, 'm'},
                                       {"tracking", no_argument, NULL, 't'},
                                       {"mot-dump", required_argument, NULL, 'M'},
                                       {"help", no_argument, NULL, 'h'},
                                       {NULL, 0, NULL, 0}};
  bool json = false;
  const char *objects_path = NULL, *model_path = NULL, *dump_path = NULL;
  bool diagnose = false, tracking = false;
  int o;
  while ((o = getopt_long(argc, argv, "", opts, NULL)) != -1) {
    if (o == 'j') json = true;
    else if (o == 'o') objects_path = optarg;
    else if (o == 'd') diagnose = true;
    else if (o == 'm') model_path = optarg;
    else if (o == 't') tracking = true;
    else if (o == 'M') dump_path = optarg;
    else if (o == 'h') {
      printf("usage: roadscan-eval CAPTURE TRUTH PRED [--json] [--objects FILE] [--diagnose [--model BG]]\n"
             "       roadscan-eval --tracking CAPTURE TRUTH PRED [--json] [--mot-dump FILE]\n"
             "Point-label files as in specs/point-labels.md; metrics as in the FSPC paper's Table 3.\n"
             "  --tracking      also the tracking metrics of PRED's labels (roadscand --labels-out with\n"
             "                  tracking on: 2 + the track id): MOTA, MOTP, IDF1, id switches,\n"
             "                  fragmentations, mostly tracked / lost (true instances of >= %d returns\n"
             "                  and tracks match in a frame when their returns overlap with IoU > 0.5);\n"
             "                  with --json only these, as one JSON object\n"
             "  --mot-dump FILE with --tracking: every frame's true and predicted instances and overlaps\n"
             "                  (CSV frame,truth,pred,iou; a 0 id marks presence alone), for py-motmetrics\n"
             "  --objects FILE  CSV frame,instance,points,x,y,z: the centroid (sensor frame) of every true\n"
             "                  instance of at least %d returns in every frame\n"
             "  --diagnose      where the missed object returns are: in objects with no clustered return\n"
             "                  (by size), or beside a clustered return of their object (by range difference);\n"
             "                  merged instances (with another object or not, by range)\n"
             "  --model BG      with --diagnose: returns predicted as objects by the number of static\n"
             "                  surfaces of their cell in the background model; the false ones by truth\n"
             "                  class, place against their cell's surfaces, and range\n",
             RS_EVAL_MIN_INSTANCE, RS_EVAL_MIN_INSTANCE);
      return 0;
    } else {
      return 2;
    }
  }
  if (argc - optind != 3) {
    fprintf(stderr, "usage: roadscan-eval CAPTURE TRUTH PRED [--json] [--objects FILE] [--diagnose [--model BG]]\n");
    return 2;
  }
  if (dump_path && !tracking) {
    fprintf(stderr, "roadscan-eval: --mot-dump goes with --tracking\n");
    return 2;
  }
  if (model_path && !diagnose) {
    fprintf(stderr, "roadscan-eval: --model goes with --diagnose\n");
    return 2;
  }
  static ctx_t c;
  static rs_bg_model_t bgm;
  c.dg.on = diagnose;
  if (model_path) {
    char merr[RS_ERRMSG_SIZE];
    if (rs_bg_load(&bgm, model_path, merr, sizeof merr) != RS_OK) {
      fprintf(stderr, "roadscan-eval: %s\n", merr);
      return 1;
    }
    c.dg.model = &bgm;
  }
  if (objects_path) {
    c.objects = fopen(objects_path, "w");
    if (c.objects == NULL) {
      fprintf(stderr, "roadscan-eval: --objects %s: cannot write\n", objects_path);
      return 1;
    }
    fprintf(c.objects, "frame,instance,points,x,y,z\n");
  }
  c.prev_az = -1;
  c.s[0].role = "truth";
  c.s[1].role = "prediction";
  for (int i = 0; i < 2; i++) {
    if (rs_labels_open(&c.s[i].rd, argv[optind + 1 + i], UINT32_MAX) != RS_OK) {
      fprintf(stderr, "roadscan-eval: %s labels: %s\n", c.s[i].role, c.s[i].rd.err);
      return 1;
    }
    if (advance(&c, &c.s[i]) != RS_OK) {
      fprintf(stderr, "roadscan-eval: %s\n", c.err);
      return 1;
    }
  }
  if (rs_eval_init(&c.ev) != RS_OK) {
    fprintf(stderr, "roadscan-eval: out of memory\n");
    return 1;
  }
  FILE *dump = NULL;
  rs_mot_t *mot = NULL;
  if (tracking) {
    if (dump_path && (dump = fopen(dump_path, "w")) == NULL) {
      fprintf(stderr, "roadscan-eval: --mot-dump %s: cannot write\n", dump_path);
      return 1;
    }
    mot = rs_mot_new(dump);
    if (mot == NULL) {
      fprintf(stderr, "roadscan-eval: out of memory\n");
      return 1;
    }
    rs_eval_track(&c.ev, mot);
  }
  rs_stream_cfg_t scfg = {.log = stderr};
  rs_stream_init(&stream, &scfg);
  char rerr[RS_ERRMSG_SIZE];
  int rc = rs_stream_replay_file(&stream, argv[optind], on_packet, &c, &c.failed, rerr, sizeof rerr);
  if (rc != RS_OK && !c.failed) {
    fprintf(stderr, "roadscan-eval: %s\n", rerr);
    if (rc != RS_E_TRUNCATED) return 1;
  }
  if (!c.failed) end_frame(&c);
  if (c.objects && fclose(c.objects) != 0) {
    fprintf(stderr, "roadscan-eval: --objects %s: write failed\n", objects_path);
    return 1;
  }
  for (int i = 0; i < 2 && !c.failed; i++)
    if (c.s[i].have)
      snprintf(c.err, sizeof c.err, "%s labels: %s:%ld: address %u,%u,%u is not a return of the capture", c.s[i].role,
               c.s[i].rd.path, c.s[i].rd.line, c.s[i].cur.packet, c.s[i].cur.block, c.s[i].cur.channel),
          c.failed = true;
  if (c.failed) {
    fprintf(stderr, "roadscan-eval: %s\n", c.err);
    return 1;
  }
  if (c.ev.overflow) fprintf(stderr, "roadscan-eval: warning: too many instances in a frame, instance figures incomplete\n");
  if (mot) {
    rs_mot_result_t mr;
    if (rs_mot_finish(mot, &mr) != RS_OK) {
      fprintf(stderr, "roadscan-eval: out of memory\n");
      return 1;
    }
    if (json) {
      rs_mot_print_json(&mr, stdout);
    } else {
      rs_eval_print(&c.ev.r, stdout);
      rs_mot_print(&mr, stdout);
    }
    rs_mot_free(mot);
    if (dump && fclose(dump) != 0) {
      fprintf(stderr, "roadscan-eval: --mot-dump %s: write failed\n", dump_path);
      return 1;
    }
  } else if (json) {
    rs_eval_print_json(&c.ev.r, stdout);
  } else {
    rs_eval_print(&c.ev.r, stdout);
  }
  if (diagnose) diag_print(&c.dg, json ? stderr : stdout); /* JSON on stdout stays JSON */
  free(c.dg.pts);
  if (model_path) rs_bg_model_free(&bgm);
  rs_eval_deinit(&c.ev);
  rs_labels_close(&c.s[0].rd);
  rs_labels_close(&c.s[1].rd);
  return 0;
}

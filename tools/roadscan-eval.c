/* roadscan-eval - compare two point-label files over a capture.
 *
 *   roadscan-eval CAPTURE TRUTH PRED [--json] [--objects FILE]
 *
 * Reads the capture with the project's decoder, walks its returns in
 * address order merging both label files (unlisted = 1), cuts frames where
 * a block azimuth is smaller than the previous block's (the spec's rule),
 * skips frame 0, and prints the metrics. --objects writes the centroid of
 * every true instance of every frame (frame numbers as roadscand's
 * frame_seq: 0 is the part before the first roll-over). Single-threaded. */
#include "roadscan/eval.h"
#include "roadscan/labels.h"
#include "roadscan/stream.h"

#include <getopt.h>
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

typedef struct {
  src_t s[2];
  FILE *objects;
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

static void end_frame(ctx_t *c) {
  rs_eval_end_frame(&c->ev, c->frame > 0);
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
    }
  }
}

int main(int argc, char **argv) {
  static const struct option opts[] = {{"json", no_argument, NULL, 'j'},
                                       {"objects", required_argument, NULL, 'o'},
                                       {"help", no_argument, NULL, 'h'},
                                       {NULL, 0, NULL, 0}};
  bool json = false;
  const char *objects_path = NULL;
  int o;
  while ((o = getopt_long(argc, argv, "", opts, NULL)) != -1) {
    if (o == 'j') json = true;
    else if (o == 'o') objects_path = optarg;
    else if (o == 'h') {
      printf("usage: roadscan-eval CAPTURE TRUTH PRED [--json] [--objects FILE]\n"
             "Point-label files as in specs/point-labels.md; metrics as in the FSPC paper's Table 3.\n"
             "  --objects FILE  CSV frame,instance,points,x,y,z: the centroid (sensor frame) of every true\n"
             "                  instance of at least %d returns in every frame\n",
             RS_EVAL_MIN_INSTANCE);
      return 0;
    } else {
      return 2;
    }
  }
  if (argc - optind != 3) {
    fprintf(stderr, "usage: roadscan-eval CAPTURE TRUTH PRED [--json] [--objects FILE]\n");
    return 2;
  }
  static ctx_t c;
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
  if (json) rs_eval_print_json(&c.ev.r, stdout);
  else rs_eval_print(&c.ev.r, stdout);
  rs_eval_deinit(&c.ev);
  rs_labels_close(&c.s[0].rd);
  rs_labels_close(&c.s[1].rd);
  return 0;
}

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
#include "roadscan/perception/background.h"
#include "roadscan/perception/count.h"
#include "roadscan/offline/eval.h"
#include "roadscan/output/labels.h"
#include "roadscan/capture/stream.h"

#include "roadscan/util/opts.h"
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
  FILE *leaks_out;             /* --leaks-out: static returns not labelled background, object returns labelled so */
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

/* ---- --truth-states with --tracks: speeds, positions, confirmation delay ---- */
typedef struct {
  double t, x, y, vx, vy;
  bool vehicle;
  uint8_t cls; /* the tracker's class of the true one (truth_class) */
} st_row_t;
typedef struct {
  uint64_t key; /* frame << 32 | track id */
  double t, x, y, speed;
  bool confirmed;
} trk_row_t;
typedef struct {
  st_row_t *rows; /* sorted by id, then t */
  uint32_t *ids;
  size_t n, cap;
  trk_row_t *trk; /* sorted by key */
  size_t nt, tcap;
  double period;  /* s per frame */
  double frame0_t; int64_t frame0;
  /* tallies */
  double se_speed[2], se_pos[2];     /* [0] vehicles within 80 m, [1] all */
  uint64_t n_speed[2];
  double abs_speed_sum[2];
  uint32_t *first_inst;              /* per truth id (index): first frame as an instance, +1 */
  uint32_t *first_conf;              /* first frame matched to a confirmed track, +1 */
  uint32_t max_id;
  bool oom;
  char err[600];
} sp_t;
static sp_t sp;

/* truth id -> [first, end) of its rows: rows are in file order (time), grouped by a stable pass */
typedef struct {
  uint32_t first, count;
} span_t;
static span_t *spans;
static st_row_t *by_id;

/* the tracker's class for a class of the simulator's truth (van and truck: van/truck) */
static rs_class_t truth_class(const char *c) {
  if (strcmp(c, "car") == 0) return RS_CLASS_CAR;
  if (strcmp(c, "van") == 0 || strcmp(c, "truck") == 0) return RS_CLASS_VAN_TRUCK;
  if (strcmp(c, "bus") == 0) return RS_CLASS_BUS;
  if (strcmp(c, "pedestrian") == 0) return RS_CLASS_PEDESTRIAN;
  if (strcmp(c, "cyclist") == 0) return RS_CLASS_CYCLIST;
  return RS_CLASS_UNKNOWN;
}

static int load_states(const char *path) {
  FILE *f = fopen(path, "r");
  if (!f) {
    snprintf(sp.err, sizeof sp.err, "--truth-states %s: cannot read", path);
    return -1;
  }
  char line[512];
  if (!fgets(line, sizeof line, f) || strncmp(line, "t,id,class,x,y,vx,vy", 20) != 0) {
    snprintf(sp.err, sizeof sp.err, "--truth-states %s: not a roadscan-sim --truth-states file", path);
    fclose(f);
    return -1;
  }
  long ln = 1;
  while (fgets(line, sizeof line, f)) {
    ln++;
    double t, x, y, vx, vy;
    unsigned id;
    char cls[32];
    if (sscanf(line, "%lf,%u,%31[^,],%lf,%lf,%lf,%lf", &t, &id, cls, &x, &y, &vx, &vy) != 7 || id > 10000000) {
      snprintf(sp.err, sizeof sp.err, "--truth-states %s:%ld: bad line", path, ln);
      fclose(f);
      return -1;
    }
    if (sp.n == sp.cap) {
      size_t nc = sp.cap ? 2 * sp.cap : 65536;
      st_row_t *nr = realloc(sp.rows, nc * sizeof *nr);
      uint32_t *ni = realloc(sp.ids, nc * sizeof *ni);
      if (!nr || !ni) {
        free(nr ? nr : sp.rows);
        sp.rows = NULL;
        fclose(f);
        snprintf(sp.err, sizeof sp.err, "out of memory");
        return -1;
      }
      sp.rows = nr;
      sp.ids = ni;
      sp.cap = nc;
    }
    bool veh = strcmp(cls, "pedestrian") != 0 && strcmp(cls, "cyclist") != 0;
    sp.rows[sp.n] = (st_row_t){t, x, y, vx, vy, veh, (uint8_t)truth_class(cls)};
    sp.ids[sp.n++] = id;
    if (id > sp.max_id) sp.max_id = id;
  }
  fclose(f);
  /* group by id, keeping time order: counting sort */
  spans = calloc((size_t)sp.max_id + 2, sizeof *spans);
  by_id = malloc(sizeof *by_id * (sp.n ? sp.n : 1));
  sp.first_inst = calloc((size_t)sp.max_id + 2, sizeof *sp.first_inst);
  sp.first_conf = calloc((size_t)sp.max_id + 2, sizeof *sp.first_conf);
  if (!spans || !by_id || !sp.first_inst || !sp.first_conf) {
    snprintf(sp.err, sizeof sp.err, "out of memory");
    return -1;
  }
  for (size_t i = 0; i < sp.n; i++) spans[sp.ids[i]].count++;
  uint32_t acc = 0;
  for (uint32_t id = 0; id <= sp.max_id; id++) {
    spans[id].first = acc;
    acc += spans[id].count;
    spans[id].count = 0;
  }
  for (size_t i = 0; i < sp.n; i++) by_id[spans[sp.ids[i]].first + spans[sp.ids[i]].count++] = sp.rows[i];
  return 0;
}

static int cmp_trk(const void *a, const void *b) {
  uint64_t x = ((const trk_row_t *)a)->key, y = ((const trk_row_t *)b)->key;
  return (x > y) - (x < y);
}

static int load_tracks(const char *path) {
  FILE *f = fopen(path, "r");
  if (!f) {
    snprintf(sp.err, sizeof sp.err, "--tracks %s: cannot read", path);
    return -1;
  }
  char line[1024];
  if (!fgets(line, sizeof line, f) || strncmp(line, "frame,t,track,state,class,x,y", 29) != 0) {
    snprintf(sp.err, sizeof sp.err, "--tracks %s: not a roadscand --tracks-out file", path);
    fclose(f);
    return -1;
  }
  long ln = 1;
  int64_t fmin = -1, fmax = -1;
  double tmin = 0, tmax = 0;
  while (fgets(line, sizeof line, f)) {
    ln++;
    long long frame;
    double t, x, y, z, vx, vy, speed;
    unsigned id;
    char state[32], cls[32];
    if (sscanf(line, "%lld,%lf,%u,%31[^,],%31[^,],%lf,%lf,%lf,%lf,%lf,%lf", &frame, &t, &id, state, cls, &x, &y, &z, &vx,
               &vy, &speed) != 11 || frame < 0) {
      snprintf(sp.err, sizeof sp.err, "--tracks %s:%ld: bad line", path, ln);
      fclose(f);
      return -1;
    }
    if (sp.nt == sp.tcap) {
      size_t nc = sp.tcap ? 2 * sp.tcap : 65536;
      trk_row_t *nr = realloc(sp.trk, nc * sizeof *nr);
      if (!nr) {
        fclose(f);
        snprintf(sp.err, sizeof sp.err, "out of memory");
        return -1;
      }
      sp.trk = nr;
      sp.tcap = nc;
    }
    sp.trk[sp.nt++] = (trk_row_t){(uint64_t)frame << 32 | id, t, x, y, speed, strcmp(state, "tentative") != 0};
    if (fmin < 0 || frame < fmin) fmin = frame, tmin = t;
    if (frame > fmax) fmax = frame, tmax = t;
  }
  fclose(f);
  qsort(sp.trk, sp.nt, sizeof *sp.trk, cmp_trk);
  sp.period = fmax > fmin ? (tmax - tmin) / (double)(fmax - fmin) : 0.1;
  sp.frame0 = fmin;
  sp.frame0_t = tmin;
  return 0;
}

/* the truth state of id at time t (linear between the turns' states); false when unknown */
static bool truth_at(uint32_t id, double t, st_row_t *out) {
  if (id > sp.max_id || spans[id].count == 0) return false;
  const st_row_t *r = by_id + spans[id].first;
  const uint32_t n = spans[id].count;
  if (t < r[0].t - 0.15 || t > r[n - 1].t + 0.15) return false;
  uint32_t lo = 0, hi = n;
  while (lo < hi) { /* first row after t */
    uint32_t mid = (lo + hi) / 2;
    if (r[mid].t <= t) lo = mid + 1;
    else hi = mid;
  }
  if (lo == 0 || lo == n) {
    *out = r[lo == 0 ? 0 : n - 1];
    const double dt = t - out->t;
    out->x += out->vx * dt;
    out->y += out->vy * dt;
    return true;
  }
  const st_row_t *a = &r[lo - 1], *b = &r[lo];
  const double w = (t - a->t) / (b->t - a->t);
  *out = *a;
  out->x = a->x + w * (b->x - a->x);
  out->y = a->y + w * (b->y - a->y);
  out->vx = a->vx + w * (b->vx - a->vx);
  out->vy = a->vy + w * (b->vy - a->vy);
  return true;
}

static void on_instance(void *user, uint64_t frame, uint32_t truth, uint32_t pred) {
  (void)user;
  if (truth <= sp.max_id && sp.first_inst[truth] == 0) sp.first_inst[truth] = (uint32_t)frame + 1;
  if (pred < 3) return;
  const uint64_t key = frame << 32 | (pred - 2);
  size_t lo = 0, hi = sp.nt;
  while (lo < hi) {
    size_t mid = (lo + hi) / 2;
    if (sp.trk[mid].key < key) lo = mid + 1;
    else hi = mid;
  }
  if (lo == sp.nt || sp.trk[lo].key != key || !sp.trk[lo].confirmed) return;
  const trk_row_t *k = &sp.trk[lo];
  if (truth <= sp.max_id && sp.first_conf[truth] == 0) sp.first_conf[truth] = (uint32_t)frame + 1;
  st_row_t s;
  if (!truth_at(truth, k->t, &s)) return;
  const double ds = k->speed - hypot(s.vx, s.vy), dp = hypot(k->x - s.x, k->y - s.y);
  for (int c = 0; c < 2; c++) {
    if (c == 0 && !(s.vehicle && hypot(s.x, s.y) <= 80.0)) continue;
    sp.se_speed[c] += ds * ds;
    sp.abs_speed_sum[c] += fabs(ds);
    sp.se_pos[c] += dp * dp;
    sp.n_speed[c]++;
  }
}

static int cmp_dbl(const void *a, const void *b) {
  double x = *(const double *)a, y = *(const double *)b;
  return (x > y) - (x < y);
}

/* ---- --counts with --count-line: true crossings from the states ---- */
/* Everything the options set. */
typedef struct {
  bool json, diagnose, tracking;
  const char *objects_path, *model_path, *leaks_path, *dump_path, *states_path, *tracks_path, *counts_path, *crossings_path;
  const char *events_path; /* --crossings: roadscand --crossings-out */
  const char *unmatched_path; /* --crossings-unmatched: the false and missed crossings */
  rs_count_lines_t lines; /* --count-line */
  rs_count_zones_t zones; /* --count-zone */
} settings_t;
static settings_t st;

/* per line and direction: crossings counted (from the counts CSV) and true ones */
static uint64_t pred_count[RS_COUNT_LINES][2], true_count[RS_COUNT_LINES][2];
/* the same by class (the tracker's classes; the truth's mapped by truth_class) */
static uint64_t pred_cls[RS_COUNT_LINES][2][RS_CLASS_COUNT], true_cls[RS_COUNT_LINES][2][RS_CLASS_COUNT];
/* per zone: entries [0] and exits [1] counted and true, and by class */
static uint64_t pred_zone[RS_COUNT_ZONES][2], true_zone[RS_COUNT_ZONES][2];
static uint64_t pred_zone_cls[RS_COUNT_ZONES][2][RS_CLASS_COUNT], true_zone_cls[RS_COUNT_ZONES][2][RS_CLASS_COUNT];

static int class_index(const char *name) {
  for (int k = 0; k < RS_CLASS_COUNT; k++)
    if (strcmp(rs_class_name((rs_class_t)k), name) == 0) return k;
  return -1;
}

/* path opened for reading, its first line the header (prefix: starting with it); NULL with sp.err naming
 * the option and what the file should have been */
static FILE *open_in(const char *path, const char *option, const char *header, bool prefix, const char *what) {
  FILE *f = fopen(path, "r");
  if (!f) {
    snprintf(sp.err, sizeof sp.err, "%s %s: cannot read", option, path);
    return NULL;
  }
  char line[512];
  const size_t n = strlen(header);
  if (!fgets(line, sizeof line, f) || strncmp(line, header, n) != 0 || (!prefix && strcmp(line + n, "\n") != 0)) {
    snprintf(sp.err, sizeof sp.err, "%s %s: not a %s file", option, path, what);
    fclose(f);
    return NULL;
  }
  return f;
}

static int load_counts(const char *path) {
  FILE *f = open_in(path, "--counts", "t_start,t_end,line,direction,class,count", true, "roadscand --counts-out");
  if (!f) return -1;
  char line[512];
  long ln = 1;
  while (fgets(line, sizeof line, f)) {
    ln++;
    double a, b;
    char name[64], dir[16], cls[32];
    unsigned n;
    if (sscanf(line, "%lf,%lf,%63[^,],%15[^,],%31[^,],%u", &a, &b, name, dir, cls, &n) != 6) {
      snprintf(sp.err, sizeof sp.err, "--counts %s:%ld: bad line", path, ln);
      fclose(f);
      return -1;
    }
    const int d = strcmp(dir, "forward") == 0 ? 0 : 1, k = class_index(cls);
    if (strcmp(cls, "all") != 0 && k < 0) {
      snprintf(sp.err, sizeof sp.err, "--counts %s:%ld: unknown class '%s'", path, ln, cls);
      fclose(f);
      return -1;
    }
    const bool zone_row = strcmp(dir, "entered") == 0 || strcmp(dir, "exited") == 0;
    if (!zone_row && strcmp(dir, "forward") != 0 && strcmp(dir, "backward") != 0 && strcmp(dir, "occupancy_max") != 0) {
      snprintf(sp.err, sizeof sp.err, "--counts %s:%ld: unknown direction '%s' (forward, backward, entered, exited or "
                                      "occupancy_max)", path, ln, dir);
      fclose(f);
      return -1;
    }
    for (int l = 0; l < st.lines.n && !zone_row; l++) {
      if (strcmp(st.lines.line[l].name, name) != 0) continue;
      if (k < 0)
        pred_count[l][d] += n;
      else
        pred_cls[l][d][k] += n;
    }
    for (int z = 0; z < st.zones.n && zone_row; z++) {
      if (strcmp(st.zones.zone[z].name, name) != 0) continue;
      const int e = strcmp(dir, "entered") == 0 ? 0 : 1;
      if (k < 0)
        pred_zone[z][e] += n;
      else
        pred_zone_cls[z][e][k] += n;
    }
  }
  fclose(f);
  return 0;
}

/* roadscan-sim --truth-crossings: the true crossings it wrote (the same rule as below, from its own
 * states); rows of lines not given with --count-line are refused */
static int load_crossings(const char *path) {
  FILE *f = open_in(path, "--truth-crossings", "t,id,class,line,direction", false, "roadscan-sim --truth-crossings");
  if (!f) return -1;
  char line[512];
  long ln = 1;
  while (fgets(line, sizeof line, f)) {
    ln++;
    double t;
    unsigned id;
    char cls[32], name[64], dir[16];
    int l = 0;
    if (sscanf(line, "%lf,%u,%31[^,],%63[^,],%15s", &t, &id, cls, name, dir) != 5 ||
        (strcmp(dir, "forward") != 0 && strcmp(dir, "backward") != 0)) {
      snprintf(sp.err, sizeof sp.err, "--truth-crossings %s:%ld: bad line", path, ln);
      fclose(f);
      return -1;
    }
    while (l < st.lines.n && strcmp(st.lines.line[l].name, name) != 0) l++;
    if (l == st.lines.n) {
      snprintf(sp.err, sizeof sp.err, "--truth-crossings %s:%ld: line '%s' is not a --count-line", path, ln, name);
      fclose(f);
      return -1;
    }
    true_count[l][strcmp(dir, "forward") == 0 ? 0 : 1]++;
    true_cls[l][strcmp(dir, "forward") == 0 ? 0 : 1][truth_class(cls)]++;
  }
  fclose(f);
  return 0;
}

/* every road user once per line, in the direction of its first crossing (as the counter counts tracks) */
static void true_crossings(void) {
  for (uint32_t id = 0; id <= sp.max_id; id++) {
    const st_row_t *r = by_id + spans[id].first;
    for (int l = 0; l < st.lines.n; l++)
      for (uint32_t k = 1; k < spans[id].count; k++) {
        const int d = rs_count_crosses(&st.lines.line[l], r[k - 1].x, r[k - 1].y, r[k].x, r[k].y);
        if (d == 0) continue;
        true_count[l][d > 0 ? 0 : 1]++;
        true_cls[l][d > 0 ? 0 : 1][r[0].cls]++;
        break;
      }
  }
}

/* ---- --crossings: each crossing counted (roadscand --crossings-out) against a true one ---- */
static json_t *jnum(double v);
typedef struct {
  double t, speed;   /* when, and the speed then (the states' interpolated) */
  double at;         /* where along the line (m from its A end) */
  int line, dir;     /* dir 1 forward, -1 backward */
  bool vehicle, used;
  uint8_t cls;
  uint32_t id;       /* the road user's (the states' id) */
} tx_t;
typedef struct {
  double t, speed;   /* speed < 0: unknown */
  double at;
  int line, dir, cls, how;
  uint32_t track;
  long match;        /* index into the true ones, -1 */
} ev_t;
static tx_t *tx;
static size_t ntx;
static ev_t *evs;
static size_t nev;

/* the true crossings with their times and speeds: every road user once per line, its first crossing (as
 * true_crossings counts them) */
static int true_events(void) {
  size_t cap = 0;
  for (uint32_t id = 0; id <= sp.max_id; id++) {
    const st_row_t *r = by_id + spans[id].first;
    for (int l = 0; l < st.lines.n; l++)
      for (uint32_t k = 1; k < spans[id].count; k++) {
        const int d = rs_count_crosses(&st.lines.line[l], r[k - 1].x, r[k - 1].y, r[k].x, r[k].y);
        if (d == 0) continue;
        if (ntx == cap) {
          cap = cap ? 2 * cap : 1024;
          tx_t *n = realloc(tx, cap * sizeof *n);
          if (!n) {
            snprintf(sp.err, sizeof sp.err, "out of memory");
            return -1;
          }
          tx = n;
        }
        /* where along the step it met the line: the share of the step on the line's near side */
        const rs_count_line_t *ln = &st.lines.line[l];
        const double d0 = (ln->bx - ln->ax) * (r[k - 1].y - ln->ay) - (ln->by - ln->ay) * (r[k - 1].x - ln->ax);
        const double d1 = (ln->bx - ln->ax) * (r[k].y - ln->ay) - (ln->by - ln->ay) * (r[k].x - ln->ax);
        const double u = d0 != d1 ? d0 / (d0 - d1) : 0.0;
        const double s0 = hypot(r[k - 1].vx, r[k - 1].vy), s1 = hypot(r[k].vx, r[k].vy);
        const double mx = r[k - 1].x + u * (r[k].x - r[k - 1].x) - ln->ax, my = r[k - 1].y + u * (r[k].y - r[k - 1].y) - ln->ay;
        const double at = (mx * (ln->bx - ln->ax) + my * (ln->by - ln->ay)) / hypot(ln->bx - ln->ax, ln->by - ln->ay);
        tx[ntx++] = (tx_t){r[k - 1].t + u * (r[k].t - r[k - 1].t), s0 + u * (s1 - s0), at, l, d, r[0].vehicle, false,
                           r[0].cls, id};
        break;
      }
  }
  return 0;
}

static int load_events(const char *path) {
  FILE *f = open_in(path, "--crossings", "t,line,direction,at,class,track,speed,how", false, "roadscand --crossings-out");
  if (!f) return -1;
  char line[512];
  size_t cap = 0;
  long ln = 1;
  while (fgets(line, sizeof line, f)) {
    ln++;
    /* eight fields; the speed's may be empty */
    char *fld[8];
    int nf = 0;
    line[strcspn(line, "\r\n")] = '\0';
    for (char *q = line; nf < 8; q++) {
      fld[nf++] = q;
      q = strchr(q, ',');
      if (q == NULL) break;
      *q = '\0';
    }
    char *end = NULL;
    char *end2 = NULL;
    double t = nf == 8 ? strtod(fld[0], &end) : NAN, speed = -1.0, at = nf == 8 ? strtod(fld[3], &end2) : NAN;
    const unsigned long track = nf == 8 ? strtoul(fld[5], NULL, 10) : 0;
    if (nf != 8 || *end != '\0' || *end2 != '\0' || !isfinite(t) || !isfinite(at) || strchr(fld[7], ',')) {
      snprintf(sp.err, sizeof sp.err, "--crossings %s:%ld: bad line", path, ln);
      fclose(f);
      return -1;
    }
    if (fld[6][0]) {
      speed = strtod(fld[6], &end);
      if (*end != '\0' || !(speed >= 0 && speed < 1000)) {
        snprintf(sp.err, sizeof sp.err, "--crossings %s:%ld: bad speed '%.32s'", path, ln, fld[6]);
        fclose(f);
        return -1;
      }
    }
    const char *name = fld[1], *dir = fld[2], *cls = fld[4], *how = fld[7];
    int l = 0;
    while (l < st.lines.n && strcmp(st.lines.line[l].name, name) != 0) l++;
    const int k = class_index(cls);
    int h = RS_CROSS_SEEN; /* the counter's names (rs_count_how_name) */
    while (h <= RS_CROSS_UNSEEN && strcmp(how, rs_count_how_name((rs_cross_how_t)h)) != 0) h++;
    if (h > RS_CROSS_UNSEEN) h = -1;
    if (l == st.lines.n || k < 0 || h < 0 || (strcmp(dir, "forward") != 0 && strcmp(dir, "backward") != 0)) {
      snprintf(sp.err, sizeof sp.err, "--crossings %s:%ld: line '%s' is not a --count-line, or class, direction or how "
                                      "unknown", path, ln, name);
      fclose(f);
      return -1;
    }
    if (nev == cap) {
      cap = cap ? 2 * cap : 1024;
      ev_t *n = realloc(evs, cap * sizeof *n);
      if (!n) {
        snprintf(sp.err, sizeof sp.err, "out of memory");
        fclose(f);
        return -1;
      }
      evs = n;
    }
    evs[nev++] = (ev_t){t, speed, at, l, strcmp(dir, "forward") == 0 ? 1 : -1, k, h, (uint32_t)track, -1};
  }
  fclose(f);
  return 0;
}

#define EVENT_DT 1.5 /* s: a crossing counted and a true one of the line and direction this close in time ... */
#define EVENT_DS 2.5 /* m: ... and along the line (a lane's width less a margin) may match */
typedef struct {
  double dt;
  uint32_t e, x;
} pair_t;
static int cmp_pair(const void *a, const void *b) {
  const pair_t *p = a, *q = b;
  if (p->dt != q->dt) return p->dt < q->dt ? -1 : 1;
  if (p->e != q->e) return p->e < q->e ? -1 : 1;
  return (p->x > q->x) - (p->x < q->x);
}

/* the track's reported speed at its confirmed row nearest in time to t (within 0.2 s), -1 none */
static double track_speed_at(uint32_t id, double t) {
  double best = 0.2, v = -1.0;
  for (size_t i = 0; i < sp.nt; i++) {
    if ((uint32_t)(sp.trk[i].key & 0xffffffffu) != id || !sp.trk[i].confirmed) continue;
    if (fabs(sp.trk[i].t - t) <= best) {
      best = fabs(sp.trk[i].t - t);
      v = sp.trk[i].speed;
    }
  }
  return v;
}

/* --crossings-unmatched: after print_events, the events no true crossing matched ("false") and the true
 * crossings no event matched ("missed"), in time order; 0, or -1 out of memory */
typedef struct {
  double t;
  bool missed;
  size_t k; /* into evs, or tx when missed */
} unmatched_t;
static int cmp_unmatched(const void *a, const void *b) {
  const unmatched_t *p = a, *q = b;
  if (p->t != q->t) return p->t < q->t ? -1 : 1;
  if (p->missed != q->missed) return p->missed ? 1 : -1;
  return (p->k > q->k) - (p->k < q->k);
}
static int write_unmatched(FILE *f) {
  unmatched_t *u = malloc((nev + ntx + 1) * sizeof *u);
  if (u == NULL) return -1;
  size_t n = 0;
  for (size_t k = 0; k < nev; k++)
    if (evs[k].match < 0) u[n++] = (unmatched_t){evs[k].t, false, k};
  for (size_t k = 0; k < ntx; k++)
    if (!tx[k].used) u[n++] = (unmatched_t){tx[k].t, true, k};
  qsort(u, n, sizeof *u, cmp_unmatched);
  fprintf(f, "kind,t,line,direction,at,class,id,how\n");
  for (size_t i = 0; i < n; i++) {
    if (u[i].missed) {
      const tx_t *v = &tx[u[i].k];
      fprintf(f, "missed,%.3f,%s,%s,%.2f,%s,%u,\n", v->t, st.lines.line[v->line].name, v->dir > 0 ? "forward" : "backward",
              v->at, rs_class_name((rs_class_t)v->cls), v->id);
    } else {
      const ev_t *v = &evs[u[i].k];
      fprintf(f, "false,%.3f,%s,%s,%.2f,%s,%u,%s\n", v->t, st.lines.line[v->line].name, v->dir > 0 ? "forward" : "backward",
              v->at, rs_class_name((rs_class_t)v->cls), v->track, rs_count_how_name((rs_cross_how_t)v->how));
    }
  }
  free(u);
  return 0;
}

/* events matched to true crossings (the nearest in time first), then the figures */
static void print_events(FILE *out, json_t *json) {
  size_t np = 0;
  pair_t *pr = NULL;
  for (size_t e = 0; e < nev; e++)
    for (size_t x = 0; x < ntx; x++) {
      if (evs[e].line != tx[x].line || evs[e].dir != tx[x].dir || fabs(evs[e].t - tx[x].t) > EVENT_DT ||
          fabs(evs[e].at - tx[x].at) > EVENT_DS)
        continue;
      pair_t *n = (np & (np - 1)) == 0 ? realloc(pr, (np ? 2 * np : 1) * sizeof *n) : pr;
      if (!n) break;
      pr = n;
      pr[np++] = (pair_t){fabs(evs[e].t - tx[x].t), (uint32_t)e, (uint32_t)x};
    }
  if (np) qsort(pr, np, sizeof *pr, cmp_pair);
  size_t matched = 0, n_sp = 0, n_trk = 0, same_cls = 0, n_all = 0, n_how[3] = {0, 0, 0};
  double se = 0, bias = 0, se_trk = 0, se_same = 0, se_t = 0, se_all = 0, se_how[3] = {0, 0, 0};
  for (size_t k = 0; k < np; k++) {
    ev_t *e = &evs[pr[k].e];
    tx_t *x = &tx[pr[k].x];
    if (e->match >= 0 || x->used) continue;
    e->match = (long)pr[k].x;
    x->used = true;
    matched++;
    se_t += (e->t - x->t) * (e->t - x->t);
    same_cls += e->cls == x->cls;
    if (e->speed < 0) continue;
    se_all += (e->speed - x->speed) * (e->speed - x->speed);
    n_all++;
    if (!x->vehicle) continue;
    const double d2 = (e->speed - x->speed) * (e->speed - x->speed);
    se += d2;
    bias += e->speed - x->speed;
    n_sp++;
    se_how[e->how] += d2; /* (how: 0 seen, 1 hidden, 2 unseen, load_events') */
    n_how[e->how]++;
    const double v = track_speed_at(e->track, e->t); /* the track was listed confirmed then: the same rows */
    if (v >= 0) {
      se_trk += (v - x->speed) * (v - x->speed);
      se_same += d2;
      n_trk++;
    }
  }
  free(pr);
  const double rmse = n_sp ? sqrt(se / (double)n_sp) : NAN, mb = n_sp ? bias / (double)n_sp : NAN;
  const double rmse_trk = n_trk ? sqrt(se_trk / (double)n_trk) : NAN, rmse_all = n_all ? sqrt(se_all / (double)n_all) : NAN;
  double rmse_how[3];
  for (int h = 0; h < 3; h++) rmse_how[h] = n_how[h] ? sqrt(se_how[h] / (double)n_how[h]) : NAN;
  const double rmse_same = n_trk ? sqrt(se_same / (double)n_trk) : NAN, rmse_seen = rmse_how[0];
  const size_t n_seen = n_how[0];
  const double trms = matched ? sqrt(se_t / (double)matched) : NAN, agree = matched ? (double)same_cls / (double)matched : NAN;
  if (json) {
    json_object_set_new(json, "crossing_events", json_integer((json_int_t)nev));
    json_object_set_new(json, "crossing_events_matched", json_integer((json_int_t)matched));
    json_object_set_new(json, "crossing_time_rmse_s", jnum(trms));
    json_object_set_new(json, "crossing_class_agreement", jnum(agree));
    json_object_set_new(json, "spot_speed_rmse_vehicles", jnum(rmse));
    json_object_set_new(json, "spot_speed_bias_vehicles", jnum(mb));
    json_object_set_new(json, "spot_speed_samples_vehicles", json_integer((json_int_t)n_sp));
    json_object_set_new(json, "spot_speed_rmse_all", jnum(rmse_all));
    json_object_set_new(json, "spot_speed_rmse_vehicles_seen", jnum(rmse_seen));
    json_object_set_new(json, "spot_speed_samples_vehicles_seen", json_integer((json_int_t)n_seen));
    json_object_set_new(json, "spot_speed_rmse_vehicles_hidden", jnum(rmse_how[1]));
    json_object_set_new(json, "spot_speed_samples_vehicles_hidden", json_integer((json_int_t)n_how[1]));
    json_object_set_new(json, "spot_speed_rmse_vehicles_unseen", jnum(rmse_how[2]));
    json_object_set_new(json, "spot_speed_samples_vehicles_unseen", json_integer((json_int_t)n_how[2]));
    json_object_set_new(json, "spot_speed_rmse_vehicles_listed", jnum(rmse_same));
    json_object_set_new(json, "track_speed_at_crossing_rmse_vehicles", jnum(rmse_trk));
    json_object_set_new(json, "track_speed_at_crossing_samples_vehicles", json_integer((json_int_t)n_trk));
    return;
  }
  fprintf(out, "  crossings: %zu counted, %zu matched to a true one (same line and way, within %.1f s and %.1f m; time "
               "RMSE %.3f s; class the same %.1f %%)\n", nev, matched, EVENT_DT, EVENT_DS, trms, 100.0 * agree);
  fprintf(out, "  spot speed at the lines, vehicles: RMSE %.3f m/s (bias %+.3f, %zu crossings; seen crossing %.3f, %zu; "
               "hidden %.3f, %zu; unseen %.3f, %zu; all road users %.3f); where the track was listed confirmed at the crossing: spot %.3f, the track's own "
               "speed then %.3f m/s (%zu)\n", rmse, mb, n_sp, rmse_seen, n_seen, rmse_how[1], n_how[1], rmse_how[2], n_how[2],
          rmse_all, rmse_same, rmse_trk, n_trk);
}

/* every road user's entries into and exits from each zone, its centre moving from outside to inside
 * or back from one state to the next (as the counter counts tracks: one first seen inside entered
 * nothing, one that ends inside exited nothing) */
static void true_zone_events(void) {
  for (uint32_t id = 0; id <= sp.max_id; id++) {
    const st_row_t *r = by_id + spans[id].first;
    for (int z = 0; z < st.zones.n && spans[id].count > 0; z++) {
      bool in = rs_count_inside(&st.zones.zone[z], r[0].x, r[0].y);
      for (uint32_t k = 1; k < spans[id].count; k++) {
        const bool now = rs_count_inside(&st.zones.zone[z], r[k].x, r[k].y);
        if (now != in) {
          true_zone[z][now ? 0 : 1]++;
          true_zone_cls[z][now ? 0 : 1][r[0].cls]++;
        }
        in = now;
      }
    }
  }
}

static json_t *jnum(double v) { return isnan(v) || isinf(v) ? json_null() : json_real(v); }

/* one count against the truth: a text line "  KIND NAME WHAT: counted ..." or (json) the key
 * PREFIX_NAME_WHAT: counted, true, relative error, and by class [counted, true] */
static void print_one(FILE *out, json_t *json, const char *kind, const char *prefix, const char *name, const char *what,
                      uint64_t pred, uint64_t truth, const uint64_t *pred_by, const uint64_t *true_by) {
  const double err = truth ? fabs((double)pred - (double)truth) / (double)truth : (pred ? INFINITY : 0.0);
  if (!json) {
    fprintf(out, "  %s %s %s: counted %llu, true %llu (error %.1f %%)\n", kind, name, what, (unsigned long long)pred,
            (unsigned long long)truth, 100.0 * err);
    return;
  }
  char key[1100];
  snprintf(key, sizeof key, "%s_%s_%s", prefix, name, what);
  json_t *by = json_object();
  for (int k = 0; k < RS_CLASS_COUNT; k++)
    if (pred_by[k] || true_by[k])
      json_object_set_new(by, rs_class_name((rs_class_t)k), json_pack("[I, I]", (json_int_t)pred_by[k], (json_int_t)true_by[k]));
  json_object_set_new(json, key, json_pack("{s:I, s:I, s:o, s:o}", "counted", (json_int_t)pred, "true", (json_int_t)truth,
                                           "error", jnum(err), "by_class", by));
}

/* zone entries and exits against the truth */
static void print_zones(FILE *out, json_t *json) {
  for (int z = 0; z < st.zones.n; z++)
    for (int e = 0; e < 2; e++)
      print_one(out, json, "zone", "zone", st.zones.zone[z].name, e == 0 ? "entered" : "exited", pred_zone[z][e],
                true_zone[z][e], pred_zone_cls[z][e], true_zone_cls[z][e]);
}

/* counts against the truth: printed, or (json) added to the report */
static void print_counts(FILE *out, json_t *json) {
  if (st.lines.n == 0) return; /* zones only */
  /* by class: the share of true crossings not matched by one of their class on their line and direction */
  uint64_t miss = 0, all = 0;
  for (int l = 0; l < st.lines.n; l++)
    for (int d = 0; d < 2; d++)
      for (int k = 0; k < RS_CLASS_COUNT; k++) {
        miss += pred_cls[l][d][k] > true_cls[l][d][k] ? pred_cls[l][d][k] - true_cls[l][d][k]
                                                      : true_cls[l][d][k] - pred_cls[l][d][k];
        all += true_cls[l][d][k];
      }
  const double cls_err = all ? (double)miss / (double)all : NAN;
  if (json)
    json_object_set_new(json, "class_count_error", jnum(cls_err));
  else
    fprintf(out, "  counts by class: sum over lines, directions and classes of |counted - true| = %.1f %% of %llu true "
                 "crossings\n", 100.0 * cls_err, (unsigned long long)all);
  for (int l = 0; l < st.lines.n; l++)
    for (int d = 0; d < 2; d++)
      print_one(out, json, "line", "count", st.lines.line[l].name, d == 0 ? "forward" : "backward", pred_count[l][d],
                true_count[l][d], pred_cls[l][d], true_cls[l][d]);
}

/* speeds and confirmation delays against the truth: printed, or (json) added to the report */
static void print_speeds(FILE *out, json_t *json) {
  size_t n = 0, within = 0;
  double *lat = malloc(sizeof *lat * ((size_t)sp.max_id + 1));
  for (uint32_t id = 0; lat && id <= sp.max_id; id++) {
    if (!sp.first_inst[id] || !sp.first_conf[id]) continue;
    const uint32_t k = sp.first_conf[id] > sp.first_inst[id] ? sp.first_conf[id] - sp.first_inst[id] : 0; /* frames */
    lat[n++] = (double)k * sp.period;
    within += rs_eval_within(k, sp.period, 0.3);
  }
  if (lat) qsort(lat, n, sizeof *lat, cmp_dbl);
  const double med = n ? lat[n / 2] : NAN, p90 = n ? lat[(n * 9) / 10 < n ? (n * 9) / 10 : n - 1] : NAN;
  const double rmse_v = sp.n_speed[0] ? sqrt(sp.se_speed[0] / sp.n_speed[0]) : NAN;
  const double rmse_a = sp.n_speed[1] ? sqrt(sp.se_speed[1] / sp.n_speed[1]) : NAN;
  const double pos_v = sp.n_speed[0] ? sqrt(sp.se_pos[0] / sp.n_speed[0]) : NAN;
  const double pos_a = sp.n_speed[1] ? sqrt(sp.se_pos[1] / sp.n_speed[1]) : NAN;
  const double bias_v = sp.n_speed[0] ? sp.abs_speed_sum[0] / sp.n_speed[0] : NAN;
  if (json) {
    json_object_update_new(
        json, json_pack("{s:o, s:o, s:o, s:o, s:o, s:I, s:o, s:o, s:o, s:I}", "speed_rmse_vehicles_80m", jnum(rmse_v),
                        "speed_mae_vehicles_80m", jnum(bias_v), "speed_rmse_all", jnum(rmse_a),
                        "position_rmse_vehicles_80m", jnum(pos_v), "position_rmse_all", jnum(pos_a),
                        "speed_samples_vehicles_80m", (json_int_t)sp.n_speed[0], "confirmation_delay_median_s",
                        jnum(med), "confirmation_delay_p90_s", jnum(p90), "confirmed_within_0_3s",
                        jnum(n ? (double)within / (double)n : NAN), "objects_confirmed", (json_int_t)n));
  } else {
    fprintf(out, "  speed of confirmed tracks against the truth: RMSE %.3f m/s (mean absolute %.3f) for vehicles within "
                 "80 m (%llu samples), %.3f m/s for all; position RMSE %.2f m (vehicles within 80 m), %.2f m (all)\n",
            rmse_v, bias_v, (unsigned long long)sp.n_speed[0], rmse_a, pos_v, pos_a);
    fprintf(out, "  confirmation after an object's first frame of >= %d returns: median %.2f s, 90 %% within %.2f s, "
                 "%.1f %% within 0.3 s (%zu objects)\n",
            RS_EVAL_MIN_INSTANCE, med, p90, n ? 100.0 * (double)within / (double)n : NAN, n);
  }
  free(lat);
}

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

/* the model's cell of a return (its row, its azimuth in degrees): index,
 * column and static surfaces (none beyond the model's rows) */
static size_t model_cell(const rs_bg_model_t *m, unsigned row, float az, int *col, int *surfaces) {
  *col = (int)(az * m->cols / 360.0f) % m->cols;
  const size_t cell = (size_t)row * m->cols + (size_t)*col;
  *surfaces = row < m->rows ? m->n[cell] : 0;
  return cell;
}

/* --leaks-out: a static return the pipeline did not call background (kind
 * static, label: the predicted one), a foliage or spurious return it put in
 * an object (kind foliage, label: the predicted one) or an object return it
 * called background (kind object, label: the object's id), with its cell (as
 * the model indexes it) and the cell's surfaces */
static void leak_point(diag_t *d, uint64_t frame, const rs_point_t *p, const char *kind, uint32_t label) {
  const rs_bg_model_t *m = d->model;
  int col, n;
  const size_t cell = model_cell(m, p->row, p->azimuth, &col, &n);
  fprintf(d->leaks_out, "%llu,%s,%u,%d,%.3f,%u,%d", (unsigned long long)frame, kind, p->row, col,
          p->distance, label, n);
  for (int k = 0; k < RS_BG_SURFACES; k++) {
    if (k < n) fprintf(d->leaks_out, ",%.2f,%.2f", m->lo[cell * RS_BG_SURFACES + (size_t)k] / 100.0,
                       m->hi[cell * RS_BG_SURFACES + (size_t)k] / 100.0);
    else fputs(",,", d->leaks_out);
  }
  fputc('\n', d->leaks_out);
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
      int col, s;
      const size_t cell = model_cell(d->model, p->row, p->az, &col, &s);
      d->by_surfaces[p->truth >= 3][s > RS_BG_SURFACES ? RS_BG_SURFACES : s]++;
      if (p->truth < 3) {
        d->fp_truth[p->truth == 2]++;
        if (p->truth != 2) {
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
  const rs_bg_model_t *m = c->dg.model;
  if (m && (m->model != stream.sensor.info->model || m->rows != stream.sensor.lasers)) {
    snprintf(c->err, sizeof c->err, "--model: the model is for a %s (%u rows), the capture is from a %s",
             rs_model_name(m->model), m->rows, stream.sensor.info->name);
    c->failed = true;
    return;
  }
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
      if (c->dg.leaks_out && c->frame > 0 && ((t == 1 && pr != 1) || (t == 2 && pr >= 3) || (t >= 3 && pr == 1)))
        leak_point(&c->dg, c->frame, p, t >= 3 ? "object" : t == 2 ? "foliage" : "static", t >= 3 ? t : pr);
    }
  }
}

static rs_opts_t opts;

#define T settings_t
static const rs_opt_t table[] = {
    RS_OPT_FLAG_("json", T, json, "one JSON object instead of the text report"),
    RS_OPT_HEAD("", "Tracking"),
    RS_OPT_FLAG_("tracking", T, tracking,
                 "also the tracking metrics of PRED's labels (roadscand --labels-out with tracking on: 2 + the "
                 "track id): MOTA, MOTP, IDF1, id switches, fragmentations, mostly tracked / lost; with --json "
                 "only these"),
    RS_OPT_STR_("mot-dump", "FILE", T, dump_path,
                "with --tracking: every frame's true and predicted instances and overlaps (CSV frame,truth,pred,"
                "iou; a 0 id marks presence alone), for py-motmetrics"),
    RS_OPT_STR_("truth-states", "S", T, states_path,
                "with --tracking and --tracks: roadscan-sim --truth-states of the same run: the speed and position "
                "error of confirmed tracks against their matched object's true state at the track's time (RMSE; "
                "vehicles within 80 m and all), and how long after an object's first frame a confirmed track "
                "matches it"),
    RS_OPT_STR_("tracks", "T", T, tracks_path, "with --truth-states: roadscand --tracks-out of the same run"),
    RS_OPT_STR_("counts", "C", T, counts_path,
                "with --truth-states and --count-line: roadscand --counts-out with the same lines (sensor frame, "
                "no --pose): per line and direction the crossings counted against the true ones (every road user "
                "of the states once per line) and the relative error"),
    {.type = RS_OPT_FUNC, .name = "count-line", .arg = "\"NAME X1 Y1 X2 Y2\"", .off = offsetof(T, lines),
     .fn = rs_count_opt_line, .flags = RS_OPT_REPEAT, .help = "a counting line, as roadscand's"},
    {.type = RS_OPT_FUNC, .name = "count-zone", .arg = "\"NAME X1 Y1 X2 Y2 X3 Y3 ...\"", .off = offsetof(T, zones),
     .fn = rs_count_opt_zone, .flags = RS_OPT_REPEAT,
     .help = "a counting zone, as roadscand's (sensor frame): with --counts, its entries and exits counted against "
             "the true ones (each road user's centre moving in or out, from one state to the next)"},
    RS_OPT_STR_("crossings", "E", T, events_path,
                "with --counts: roadscand --crossings-out of the same run: each crossing counted matched to a true "
                "one of its line and direction (the nearest in time, within 1.5 s and 2.5 m along the line, each "
                "once), the spot speed's "
                "error at the lines (vehicles: RMSE, bias) against the speed the track itself reported there, "
                "the crossing time's error and the share of the same class"),
    RS_OPT_STR_("crossings-unmatched", "FILE", T, unmatched_path,
                "with --crossings: the crossings counted that no true one matched (false) and the true ones no "
                "counted one matched (missed), one CSV line each, in time order: kind,t,line,direction,at,class,id,how "
                "(id: the track, or the true road user; how: the counted crossing's, empty for a missed one)"),
    RS_OPT_STR_("truth-crossings", "X", T, crossings_path,
                "with --counts: the true crossings roadscan-sim wrote (--truth-crossings, the same lines) instead "
                "of those derived here from --truth-states (the same rule: the two agree)"),
    RS_OPT_HEAD("", "Diagnosis"),
    RS_OPT_STR_("objects", "FILE", T, objects_path,
                "CSV frame,instance,points,x,y,z: the centroid (sensor frame) of every true instance in every "
                "frame"),
    RS_OPT_FLAG_("diagnose", T, diagnose,
                 "where the missed object returns are: in objects with no clustered return (by size), or beside "
                 "a clustered return of their object (by range difference); merged instances (with another "
                 "object or not, by range)"),
    RS_OPT_STR_("leaks-out", "FILE", T, leaks_path,
                "with --diagnose --model: CSV of every static return not labelled background (kind static), every "
                "foliage or spurious return put in a cluster (foliage) and every object return labelled "
                "background (object): frame, kind, row, column, range, predicted label or object id, the cell's "
                "static surfaces and each one's range span: where a model leaks"),
    RS_OPT_STR_("model", "BG", T, model_path,
                "with --diagnose: returns predicted as objects by the number of static surfaces of their cell in "
                "the background model; the false ones by truth class, place against their cell's surfaces, and "
                "range"),
};
#undef T

int main(int argc, char **argv) {
  char about[600];
  snprintf(about, sizeof about,
           "Point-label files as in specs/point-labels.md; metrics as in the FSPC paper's Table 3. Instances "
           "count from %d returns; a true instance and a track match in a frame when their returns overlap with "
           "IoU > 0.5.",
           RS_EVAL_MIN_INSTANCE);
  const rs_opts_spec_t spec = {
      .prog = "roadscan-eval",
      .summary = "score a pipeline's point labels (and tracks, and counts) against the ground truth",
      .synopsis = "CAPTURE TRUTH PRED [--json] [--objects FILE] [--diagnose [--model BG]]\n"
                  "--tracking CAPTURE TRUTH PRED [--json] [--mot-dump FILE]\n"
                  "--tracking CAPTURE TRUTH PRED --truth-states S --tracks T [--counts C --count-line L ... --count-zone Z ...]",
      .about = about,
      .epilog = "Exit status: 0 scored, 1 a file could not be read or does not fit the capture, 2 bad usage.",
      .min_args = 3,
      .max_args = 3,
      .opts = table,
      .n = (int)(sizeof table / sizeof table[0]),
  };
  int optind_;
  const int start = rs_opts_start(&opts, &spec, &st, argc, argv, &optind_);
  if (start >= 0) return start;
  const bool json = st.json, diagnose = st.diagnose, tracking = st.tracking;
  const char *objects_path = st.objects_path, *model_path = st.model_path, *dump_path = st.dump_path,
             *states_path = st.states_path, *tracks_path = st.tracks_path, *counts_path = st.counts_path;
  if ((counts_path || st.lines.n || st.zones.n) && !(counts_path && (st.lines.n || st.zones.n) && states_path)) {
    fprintf(stderr, "roadscan-eval: --counts and --count-line (or --count-zone) go together, with --truth-states\n");
    return 2;
  }
  if (st.events_path && !counts_path) {
    fprintf(stderr, "roadscan-eval: --crossings goes with --counts\n");
    return 2;
  }
  if (st.crossings_path && !counts_path) {
    fprintf(stderr, "roadscan-eval: --truth-crossings goes with --counts\n");
    return 2;
  }
  if (st.unmatched_path && !st.events_path) {
    fprintf(stderr, "roadscan-eval: --crossings-unmatched goes with --crossings\n");
    return 2;
  }
  if ((states_path || tracks_path) && !(tracking && states_path && tracks_path)) {
    fprintf(stderr, "roadscan-eval: --truth-states and --tracks go together, with --tracking\n");
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
  if (st.leaks_path && !model_path) {
    fprintf(stderr, "roadscan-eval: --leaks-out goes with --diagnose --model\n");
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
  if (st.leaks_path) {
    if ((c.dg.leaks_out = fopen(st.leaks_path, "w")) == NULL) {
      fprintf(stderr, "roadscan-eval: --leaks-out %s: cannot write\n", st.leaks_path);
      return 1;
    }
    fputs("frame,kind,row,column,range,label,surfaces", c.dg.leaks_out);
    for (int k = 0; k < RS_BG_SURFACES; k++) fprintf(c.dg.leaks_out, ",lo%d,hi%d", k + 1, k + 1);
    fputc('\n', c.dg.leaks_out);
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
    if (rs_labels_open(&c.s[i].rd, argv[optind_ + 1 + i], UINT32_MAX) != RS_OK) {
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
  FILE *dump = NULL, *unmatched = NULL;
  bool unmatched_oom = false;
  rs_mot_t *mot = NULL;
  if (tracking) {
    if (st.unmatched_path && (unmatched = fopen(st.unmatched_path, "w")) == NULL) {
      fprintf(stderr, "roadscan-eval: --crossings-unmatched %s: cannot write\n", st.unmatched_path);
      return 1;
    }
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
    if (states_path) {
      if (load_states(states_path) != 0 || load_tracks(tracks_path) != 0) {
        fprintf(stderr, "roadscan-eval: %s\n", sp.err);
        return 1;
      }
      rs_mot_on_instance(mot, on_instance, NULL);
      if (counts_path) {
        if (load_counts(counts_path) != 0) {
          fprintf(stderr, "roadscan-eval: %s\n", sp.err);
          return 1;
        }
        if (st.crossings_path) {
          if (load_crossings(st.crossings_path) != 0) {
            fprintf(stderr, "roadscan-eval: %s\n", sp.err);
            return 1;
          }
        } else {
          true_crossings();
        }
        true_zone_events();
        if (st.events_path && (true_events() != 0 || load_events(st.events_path) != 0)) {
          fprintf(stderr, "roadscan-eval: %s\n", sp.err);
          return 1;
        }
      }
    }
  }
  rs_stream_cfg_t scfg = {.log = stderr};
  rs_stream_init(&stream, &scfg);
  char rerr[RS_ERRMSG_SIZE];
  int rc = rs_stream_replay_file(&stream, argv[optind_], on_packet, &c, &c.failed, rerr, sizeof rerr);
  if (rc != RS_OK && !c.failed) {
    fprintf(stderr, "roadscan-eval: %s\n", rerr);
    if (rc != RS_E_TRUNCATED) return 1;
  }
  if (!c.failed) end_frame(&c);
  if (c.objects && fclose(c.objects) != 0) {
    fprintf(stderr, "roadscan-eval: --objects %s: write failed\n", objects_path);
    return 1;
  }
  if (c.dg.leaks_out && fclose(c.dg.leaks_out) != 0) {
    fprintf(stderr, "roadscan-eval: --leaks-out %s: write failed\n", st.leaks_path);
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
    if (json && (states_path || counts_path)) { /* one object: the tracking figures, the speeds', the counts' */
      json_t *j = rs_mot_json(&mr);
      if (states_path) print_speeds(stdout, j);
      if (counts_path) {
        print_counts(stdout, j);
        print_zones(stdout, j);
        if (st.events_path) print_events(stdout, j);
        if (unmatched && write_unmatched(unmatched) != 0) unmatched_oom = true;
      }
      char *t = j ? json_dumps(j, RS_EVAL_JSON_FLAGS) : NULL;
      json_decref(j);
      if (t == NULL) {
        fprintf(stderr, "roadscan-eval: the JSON report could not be made (a counting line's name that is not UTF-8?)\n");
        return 1;
      }
      printf("%s\n", t);
      free(t);
    } else if (json) {
      rs_mot_print_json(&mr, stdout);
    } else {
      rs_eval_print(&c.ev.r, stdout);
      rs_mot_print(&mr, stdout);
      if (states_path) print_speeds(stdout, NULL);
      if (counts_path) {
        print_counts(stdout, NULL);
        print_zones(stdout, NULL);
        if (st.events_path) print_events(stdout, NULL);
        if (unmatched && write_unmatched(unmatched) != 0) unmatched_oom = true;
      }
    }
    rs_mot_free(mot);
    if (dump && fclose(dump) != 0) {
      fprintf(stderr, "roadscan-eval: --mot-dump %s: write failed\n", dump_path);
      return 1;
    }
    if (unmatched && (fclose(unmatched) != 0 || unmatched_oom)) {
      fprintf(stderr, "roadscan-eval: --crossings-unmatched %s: %s\n", st.unmatched_path,
              unmatched_oom ? "out of memory" : "write failed");
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

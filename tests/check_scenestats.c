/* check_scenestats - the static-scene statistics on frames whose answer is
 * known (noise, dropouts, a cell switching between two surfaces slowly or
 * independently, the firings' turn-to-turn move), and the simulator next to
 * the real static VLP-16 capture of ../shared/data (when present): the
 * statistics that do not depend on the scene (rotation rate wander, how
 * long an edge cell stays on one surface against independent switching,
 * mixed returns, noise on flat surfaces, dropouts) stay within the bounds
 * docs/simulator.md gives. */
#include "roadscan/util/error.h"
#include "roadscan/frame/framer.h"
#include "roadscan/offline/scenestats.h"
#include "roadscan/sim/scene.h"
#include "testutil.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static rs_slot_t slot;

/* 200 frames of a 16 x 100 map: every cell a wall at 10 m with 1 cm
 * Gaussian noise and 5 % dropouts, except cell (3, 50), which switches
 * between 8 m and 12 m in runs of `run` frames (or at random when run = 0) */
static void synth(rs_sstats_frames_t *f, int run, uint64_t seed) {
  rs_rng_t rng;
  rs_rng_seed(&rng, seed);
  ck_assert_int_eq(rs_sstats_init(f, RS_MODEL_VLP16, 16, 100, 200), RS_OK);
  for (int k = 0; k < 200; k++) {
    memset(&slot.meta, 0, sizeof slot.meta);
    slot.meta.rows = 16;
    slot.meta.cols = 100;
    slot.meta.rate_hz = 10.0f;
    slot.meta.t_first = k * 0.1;
    /* the first block moves 0.1 degree every turn: a quarter of the VLP-16's
     * block step at 10 Hz (two firings of 55.296 us: 0.398 degree) */
    slot.meta.first_azimuth = (uint16_t)(k * 10);
    for (int c = 0; c < 1600; c++) {
      double r = 10.0 + 0.01 * rs_rng_normal(&rng);
      if (rs_rng_uniform(&rng) < 0.05) r = 0.0;
      if (c == 3 * 100 + 50) {
        bool near = run > 0 ? (k / run) % 2 == 0 : rs_rng_uniform(&rng) < 0.5;
        r = near ? 8.0 : 12.0;
      }
      slot.range[c] = (float)r;
      slot.intensity[c] = 40;
    }
    ck_assert(rs_sstats_add(f, &slot));
  }
  ck_assert(!rs_sstats_add(f, &slot)); /* full */
}

START_TEST(t_known) {
  rs_sstats_frames_t f;
  rs_sstats_t st;
  synth(&f, 5, 1);
  ck_assert_int_eq(rs_sstats_compute(&f, &st), RS_OK);
  ck_assert_int_eq(st.frames, 200);
  ck_assert_double_eq_tol(st.steady, 1.0, 1e-9);
  ck_assert_double_eq_tol(st.multi, 1.0 / 1600, 1e-9);
  ck_assert_double_eq_tol(st.edge_spread_med, 4.0, 1e-4);
  ck_assert_double_eq_tol(st.dwell, 5.0, 1e-9);          /* runs of 5 */
  ck_assert_double_eq_tol(st.dwell_indep, 2.0, 1e-9);    /* two surfaces, half and half */
  ck_assert_double_eq_tol(st.dropout[1], 0.05, 0.005);   /* 10 m: the 5-15 m band */
  ck_assert_double_eq_tol(st.noise_sd[1], 0.01, 0.0015);
  ck_assert_double_eq_tol(st.flat_sd[1], 0.01, 0.0015);
  ck_assert_int_gt(st.flat_cells[1], 1500);
  ck_assert_double_eq_tol(st.dev_10cm[1], 0.0, 1e-9);
  ck_assert_double_eq_tol(st.phase_step, 10.0 / (10.0 * 360e-6 * 110.592 * 100.0), 1e-3);
  ck_assert_double_eq_tol(st.intensity_med[1], 40, 1e-9);
  rs_sstats_free(&f);
  /* switching at random: the runs are as long as independence says */
  synth(&f, 0, 2);
  ck_assert_int_eq(rs_sstats_compute(&f, &st), RS_OK);
  ck_assert_double_eq_tol(st.dwell, 2.0, 0.4);
  rs_sstats_free(&f);
}
END_TEST

typedef struct {
  rs_sstats_frames_t f;
  long from, to, seen;
  bool ready;
} coll_t;
static rs_slot_t slots[2];
static rs_framer_t framer;

static void on_frame(void *user, rs_slot_t *s) {
  coll_t *c = user;
  if (s->meta.partial) return;
  if (++c->seen < c->from || (c->to && c->seen > c->to)) return;
  if (!c->ready) {
    ck_assert_int_eq(rs_sstats_init(&c->f, s->meta.model, s->meta.rows, s->meta.cols, 200), RS_OK);
    c->ready = true;
  }
  rs_sstats_add(&c->f, s);
}

static void stats_of(const char *path, long from, long to, rs_sstats_t *st) {
  static coll_t c;
  memset(&c, 0, sizeof c);
  c.from = from;
  c.to = to;
  rs_stream_cfg_t scfg = {0};
  rs_asm_cfg_t acfg = {.default_hz = 10.0};
  ck_assert_int_eq(rs_framer_init(&framer, &scfg, &acfg, slots, on_frame, &c), RS_OK);
  char err[256];
  ck_assert_int_eq(rs_framer_replay_file(&framer, path, err, sizeof err), RS_OK);
  ck_assert(c.ready);
  ck_assert_int_eq(rs_sstats_compute(&c.f, st), RS_OK);
  rs_sstats_free(&c.f);
}

START_TEST(t_sim_vs_real) {
  const char *sim = tu_tmp("empty16.pcap"), *out;
  char cmd[1024];
  snprintf(cmd, sizeof cmd,
           "./roadscan-sim --sensor VLP-16 --hz 20 --scenario light --set vehicles_per_min=0 --set pedestrians_per_min=0 "
           "--seconds 4 --seed 3 -o %s --labels %s",
           sim, tu_tmp("empty16.csv"));
  ck_assert_int_eq(tu_exec(cmd, &out), 0);
  rs_sstats_t s;
  stats_of(sim, 1, 0, &s);
  fprintf(stderr, "simulated empty site: rate wander %.3f %%, firings move %.2f of a step per turn, dwell %.2f (independent "
                  "%.2f), mixed %.3f %%, flat-surface noise 15-40 m %.2f cm, dropout 5-15 m %.2f %%\n",
          s.rate_jitter, s.phase_step, s.dwell, s.dwell_indep, 100 * s.mixed, 100 * s.flat_sd[2], 100 * s.dropout[1]);
  /* the firings drift from turn to turn, irregularly (the motor wanders) */
  ck_assert_double_gt(s.rate_jitter, 0.005);
  ck_assert_double_gt(s.phase_step, 0.1);
  ck_assert_double_lt(s.phase_step, 0.45);
  /* edge cells switch about as often as independent choices would */
  ck_assert_double_gt(s.dwell, 0.75 * s.dwell_indep);
  ck_assert_double_lt(s.dwell, 1.33 * s.dwell_indep);
  ck_assert_double_gt(s.mixed, 0.0);
  ck_assert_double_lt(s.mixed, 0.01);
  if (tu_shared_data() == NULL) {
    fprintf(stderr, "check_scenestats: %s not present, the real capture's side skipped\n", RS_SHARED_DATA);
    return;
  }
  char path[1024];
  snprintf(path, sizeof path, "%s/vlp-16-test-90deg-1-50-frames.pcap", tu_shared_data());
  rs_sstats_t r;
  stats_of(path, 1, 34, &r); /* the sensor stands still until frame 35 (docs/background.md) */
  fprintf(stderr, "real VLP-16 (static part): rate wander %.3f %%, firings move %.2f, dwell %.2f (independent %.2f), "
                  "mixed %.3f %%, flat-surface noise 5-15 m %.2f cm, dropout 5-15 m %.2f %%\n",
          r.rate_jitter, r.phase_step, r.dwell, r.dwell_indep, 100 * r.mixed, 100 * r.flat_sd[1], 100 * r.dropout[1]);
  ck_assert_double_gt(r.dwell, 0.75 * r.dwell_indep);
  ck_assert_double_lt(r.dwell, 1.33 * r.dwell_indep);
  /* scene-independent figures within a factor of two of the real sensor's */
  ck_assert_double_gt(s.flat_sd[2], 0.5 * r.flat_sd[1]);
  ck_assert_double_lt(s.flat_sd[2], 2.0 * r.flat_sd[1]);
  ck_assert_double_gt(s.dropout[1], 0.5 * r.dropout[1]);
  ck_assert_double_lt(s.dropout[1], 2.0 * r.dropout[1]);
  ck_assert_double_gt(s.rate_jitter, 0.5 * r.rate_jitter);
  ck_assert_double_lt(s.rate_jitter, 2.0 * r.rate_jitter);
  ck_assert_double_gt(s.mixed, 0.3 * r.mixed);
  ck_assert_double_lt(s.mixed, 3.0 * r.mixed);
}
END_TEST

int main(void) {
  Suite *s = suite_create("scenestats");
  TCase *tc = tcase_create("core");
  tcase_set_timeout(tc, 120);
  tcase_add_test(tc, t_known);
  tcase_add_test(tc, t_sim_vs_real);
  suite_add_tcase(s, tc);
  return tu_run(s);
}

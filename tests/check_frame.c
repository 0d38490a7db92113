/* check_frame - frame assembly: roll-over, the straddling packet, cut
 * azimuth, columns from the rate, loss, reordering, duplicates, late
 * packets, dual-return layers. Packets come from the synthetic scene and
 * go through the real decoder. */
#include "roadscan/util/error.h"
#include "roadscan/frame/frame.h"
#include "roadscan/sim/synth.h"
#include "testutil.h"

#include <math.h>
#include <string.h>

#define MAXF 64
static rs_slot_t slots[2];
static rs_frame_meta_t metas[MAXF];
static int gapcols[MAXF]; /* each frame's columns no firing fell in (rs_slot_t.gap) */

static int gaps_of(const rs_slot_t *sl) {
  int n = 0;
  for (int c = 0; c < sl->meta.cols; c++) n += sl->gap[c];
  return n;
}
static rs_packet_t pkt;
static rs_encode_t enc;
static uint8_t bytes[1206];

typedef struct {
  int nframes;
  uint64_t decoded_points; /* returns that go to the map (dual-same excluded) */
  rs_asm_t a;
} run_t;

/* order: the sequence of synthetic packet numbers to feed (-1 ends) */
static void run(run_t *r, const rs_synth_cfg_t *cfg, const rs_asm_cfg_t *acfg, const int *order, int n) {
  static rs_sensor_t s;
  rs_sensor_init(&s, cfg->model);
  memset(r, 0, sizeof *r);
  ck_assert_int_eq(rs_asm_init(&r->a, acfg, &s), RS_OK);
  int cur = 0;
  for (int i = 0; i < n; i++) {
    uint32_t k = (uint32_t)order[i];
    rs_synth_packet(cfg, &s, k, &enc);
    rs_packet_encode(s.info, &enc, bytes);
    ck_assert_int_eq(rs_packet_decode(&s, bytes, 1206, r->a.rate, &pkt), RS_OK);
    static bool fed[1 << 16];
    if (i == 0) memset(fed, 0, sizeof fed);
    bool dup = k < (1u << 16) && fed[k];
    if (k < (1u << 16)) fed[k] = true;
    if (!dup)
      for (int j = 0; j < pkt.n_points; j++) r->decoded_points += pkt.points[j].return_type != RS_RET_DUAL_SAME;
    for (int guard = 0; guard <= 12; guard++) {
      if (rs_asm_feed(&r->a, &slots[cur], &pkt, k, rs_synth_time(cfg, k)) == RS_ASM_CONSUMED) break;
      ck_assert_int_lt(r->nframes, MAXF);
      gapcols[r->nframes] = gaps_of(&slots[cur]);
      metas[r->nframes++] = slots[cur].meta;
      cur ^= 1;
    }
  }
  if (rs_asm_flush(&r->a, &slots[cur])) {
    gapcols[r->nframes] = gaps_of(&slots[cur]);
    metas[r->nframes++] = slots[cur].meta;
  }
}

static int seq_order(int *order, int n) {
  for (int i = 0; i < n; i++) order[i] = i;
  return n;
}

static uint64_t map_points(const run_t *r) {
  uint64_t t = 0;
  for (int f = 0; f < r->nframes; f++) t += metas[f].points + metas[f].collisions;
  return t;
}

static int order[20000];

START_TEST(t_frames_no_loss) {
  for (int m = RS_MODEL_VLP16; m < RS_MODEL_COUNT; m++) {
    rs_synth_cfg_t cfg = {.model = (rs_model_t)m, .mode = RS_MODE_STRONGEST, .hz = 10.0, .seconds = 1.0,
                          .start_az_deg = 300.0, .t0 = 1000.0};
    rs_asm_cfg_t acfg = {.default_hz = 10.0};
    run_t r;
    int n = seq_order(order, (int)rs_synth_count(&cfg));
    run(&r, &cfg, &acfg, order, n);
    /* az = 300 + 3600 t crosses 0 ten times in one second */
    ck_assert_int_eq(r.nframes, 11);
    ck_assert(metas[0].partial);
    ck_assert(metas[10].partial);
    uint64_t decoded = r.decoded_points;
    ck_assert_uint_eq(map_points(&r), decoded);
    for (int f = 1; f < 10; f++) {
      ck_assert(!metas[f].partial);
      ck_assert_uint_eq(metas[f].seq, (uint64_t)f);
      ck_assert_uint_eq(metas[f].columns, metas[f].cols); /* the scene returns at every azimuth */
      ck_assert_uint_eq(metas[f].missing_packets, 0);
      ck_assert_float_eq_tol(metas[f].rate_hz, 10.0, 0.05);
      /* a packet straddling the cut belongs to both frames */
      ck_assert(metas[f].first_packet == metas[f - 1].last_packet ||
                metas[f].first_packet == metas[f - 1].last_packet + 1);
      /* a frame lasts one turn */
      ck_assert_float_eq_tol(metas[f].t_last - metas[f].t_first, 0.1, 0.002);
    }
    ck_assert_int_eq(metas[1].cols, rs_frame_columns_for(rs_model_info((rs_model_t)m), 10.0));
    ck_assert_int_eq(metas[1].rows, rs_model_info((rs_model_t)m)->lasers);
  }
}
END_TEST

START_TEST(t_straddle_split) {
  rs_synth_cfg_t cfg = {.model = RS_MODEL_VLP16, .mode = RS_MODE_STRONGEST, .hz = 10.0, .seconds = 0.25,
                        .start_az_deg = 350.0, .t0 = 5.0};
  rs_asm_cfg_t acfg = {.default_hz = 10.0};
  run_t r;
  run(&r, &cfg, &acfg, order, seq_order(order, (int)rs_synth_count(&cfg)));
  ck_assert_int_ge(r.nframes, 3);
  /* frame 1 begins inside the packet that straddles 0: find its first block */
  static rs_sensor_t s;
  rs_sensor_init(&s, RS_MODEL_VLP16);
  uint32_t k = metas[1].first_packet;
  rs_synth_packet(&cfg, &s, k, &enc);
  int first_new = -1;
  for (int b = 1; b < 12; b++)
    if (enc.block_azimuth[b] < enc.block_azimuth[b - 1]) first_new = b;
  ck_assert_int_gt(first_new, 0); /* the cut falls inside this packet */
  /* count returns per side of the cut in that packet, and compare with what
   * the frames hold from it: points of blocks before the cut are in frame 0 */
  int before = 0, after = 0;
  for (int b = 0; b < 12; b++)
    for (int c = 0; c < 32; c++)
      if (enc.distance[b][c]) *(b < first_new ? &before : &after) += 1;
  ck_assert_int_gt(before, 0);
  ck_assert_int_gt(after, 0);
  int in0 = 0, in1 = 0;
  /* slot contents of frame 1 are in slots[1] only while it is the last one
   * flushed; re-run frame by frame instead: count addresses of packet k */
  rs_asm_t a;
  rs_asm_init(&a, &acfg, &s);
  int cur = 0, frame = 0;
  for (uint32_t i = 0; i <= k; i++) {
    rs_synth_packet(&cfg, &s, i, &enc);
    rs_packet_encode(s.info, &enc, bytes);
    rs_packet_decode(&s, bytes, 1206, a.rate, &pkt);
    while (rs_asm_feed(&a, &slots[cur], &pkt, i, 0.0) == RS_ASM_FRAME_DONE) {
      if (frame == 0) {
        const rs_slot_t *sl = &slots[cur];
        for (uint32_t c = 0; c < (uint32_t)sl->meta.rows * sl->meta.cols; c++)
          if (sl->range[c] != 0.0f && sl->addr[c].packet == k) in0++;
      }
      frame++;
      cur ^= 1;
    }
  }
  const rs_slot_t *sl = &slots[cur];
  for (uint32_t c = 0; c < (uint32_t)sl->meta.rows * sl->meta.cols; c++)
    if (sl->range[c] != 0.0f && sl->addr[c].packet == k) {
      in1++;
      ck_assert_int_ge(sl->addr[c].block, first_new);
    }
  ck_assert_int_eq(frame, 1);
  ck_assert_int_eq(in0 + in1 + (int)(slots[0].meta.collisions + slots[1].meta.collisions), before + after);
  ck_assert_int_eq(in1, after - (int)sl->meta.collisions);
}
END_TEST

START_TEST(t_cut_azimuth) {
  rs_synth_cfg_t cfg = {.model = RS_MODEL_VLP32C, .mode = RS_MODE_STRONGEST, .hz = 10.0, .seconds = 1.0,
                        .start_az_deg = 300.0, .t0 = 0.0};
  rs_asm_cfg_t acfg = {.default_hz = 10.0, .cut_deg = 90.0};
  run_t r;
  run(&r, &cfg, &acfg, order, seq_order(order, (int)rs_synth_count(&cfg)));
  /* az = 300 + 3600 t crosses 90 at t = 150/3600 + k/10, ten times */
  ck_assert_int_eq(r.nframes, 11);
  ck_assert_float_eq_tol(metas[1].t_first, 150.0 / 3600.0, 0.001);
  ck_assert_uint_eq(map_points(&r), r.decoded_points);
  rs_asm_t a;
  rs_sensor_t s;
  rs_sensor_init(&s, RS_MODEL_VLP16);
  rs_asm_cfg_t bad = {.cut_deg = 360.0};
  ck_assert_int_eq(rs_asm_init(&a, &bad, &s), RS_E_INVAL);
  rs_asm_cfg_t badc = {.columns = 10};
  ck_assert_int_eq(rs_asm_init(&a, &badc, &s), RS_E_INVAL);
}
END_TEST

START_TEST(t_columns_from_rate) {
  rs_synth_cfg_t cfg = {.model = RS_MODEL_VLP16, .mode = RS_MODE_STRONGEST, .hz = 20.0, .seconds = 0.2};
  rs_asm_cfg_t acfg = {.default_hz = 10.0};
  run_t r;
  run(&r, &cfg, &acfg, order, seq_order(order, (int)rs_synth_count(&cfg)));
  ck_assert_int_eq(metas[0].cols, 910);
  ck_assert_float_eq_tol(metas[1].rate_hz, 20.0, 0.1);
  acfg.columns = 1800;
  run(&r, &cfg, &acfg, order, seq_order(order, (int)rs_synth_count(&cfg)));
  ck_assert_int_eq(metas[0].cols, 1800);
}
END_TEST

START_TEST(t_missing_packets) {
  rs_synth_cfg_t cfg = {.model = RS_MODEL_VLP16, .mode = RS_MODE_STRONGEST, .hz = 10.0, .seconds = 0.5};
  rs_asm_cfg_t acfg = {.default_hz = 10.0};
  int n = 0, total = (int)rs_synth_count(&cfg);
  for (int k = 0; k < total; k++)
    if (k != 100 && k != 101 && k != 300) order[n++] = k;
  run_t r;
  run(&r, &cfg, &acfg, order, n);
  uint32_t missing = 0;
  for (int f = 0; f < r.nframes; f++) missing += metas[f].missing_packets;
  ck_assert_uint_eq(missing, 3);
  ck_assert_uint_eq(r.a.missing_packets, 3);
  ck_assert_uint_eq(map_points(&r), r.decoded_points);
  /* the columns no firing fell in: a VLP-16 packet's 12 blocks of two firings each span 24 columns, the
   * last ones before a gap reach one or two into it (the next block's azimuth jitters); none elsewhere
   * in a whole frame */
  int lossy = 0;
  for (int f = 1; f + 1 < r.nframes; f++) {
    const int lost = (int)metas[f].missing_packets;
    ck_assert_int_le(gapcols[f], 24 * lost);
    ck_assert_int_ge(gapcols[f], 24 * lost - 3);
    lossy += lost > 0;
  }
  ck_assert_int_eq(lossy, 2);
  /* and with nothing lost, nothing unmeasured */
  run(&r, &cfg, &acfg, order, seq_order(order, total));
  for (int f = 1; f + 1 < r.nframes; f++) ck_assert_int_eq(gapcols[f], 0);
}
END_TEST

START_TEST(t_reorder_and_duplicate) {
  rs_synth_cfg_t cfg = {.model = RS_MODEL_VLP16, .mode = RS_MODE_STRONGEST, .hz = 10.0, .seconds = 0.5};
  rs_asm_cfg_t acfg = {.default_hz = 10.0};
  int n = seq_order(order, (int)rs_synth_count(&cfg));
  order[200] = 201; /* swap 200 and 201 */
  order[201] = 200;
  /* duplicate 150 */
  memmove(order + 151, order + 150, sizeof order[0] * (size_t)(n - 150));
  n++;
  run_t r;
  run(&r, &cfg, &acfg, order, n);
  ck_assert_uint_eq(r.a.out_of_order, 1);
  ck_assert_uint_eq(r.a.duplicates, 1);
  ck_assert_uint_eq(r.a.missing_packets, 0);
  ck_assert_uint_eq(r.a.late_points, 0);
  ck_assert_uint_eq(map_points(&r), r.decoded_points); /* nothing lost, nothing twice */
}
END_TEST

START_TEST(t_late_packet) {
  rs_synth_cfg_t cfg = {.model = RS_MODEL_VLP16, .mode = RS_MODE_STRONGEST, .hz = 10.0, .seconds = 0.3,
                        .start_az_deg = 300.0};
  rs_asm_cfg_t acfg = {.default_hz = 10.0};
  static rs_sensor_t s;
  rs_sensor_init(&s, RS_MODEL_VLP16);
  int n = seq_order(order, (int)rs_synth_count(&cfg));
  /* the last packet before the first roll-over arrives 3 packets late */
  int k = 0;
  for (; k < n; k++) {
    rs_synth_packet(&cfg, &s, (uint32_t)k + 1, &enc);
    if (enc.block_azimuth[0] < 1000) break;
  }
  rs_synth_packet(&cfg, &s, (uint32_t)k, &enc);
  int pts = 0;
  for (int b = 0; b < 12; b++)
    for (int c = 0; c < 32; c++) pts += enc.distance[b][c] != 0;
  int late = order[k];
  memmove(order + k, order + k + 1, sizeof order[0] * 3);
  order[k + 3] = late;
  run_t r;
  run(&r, &cfg, &acfg, order, n);
  ck_assert_uint_eq(r.a.out_of_order, 1);
  ck_assert_uint_eq(r.a.late_points, (uint64_t)pts);
  ck_assert_uint_eq(map_points(&r) + r.a.late_points, r.decoded_points);
}
END_TEST

/* A packet delivered more than half a turn late is late, not a roll-over
 * (no extra frame, no phantom missing packets, the next packets' returns
 * kept), and a packet repeated 10 packets later is a duplicate: the sensor's
 * timestamps tell both apart. */
START_TEST(t_half_turn_late_and_far_duplicate) {
  rs_synth_cfg_t cfg = {.model = RS_MODEL_VLP16, .mode = RS_MODE_STRONGEST, .hz = 10.0, .seconds = 0.5};
  rs_asm_cfg_t acfg = {.default_hz = 10.0};
  static rs_sensor_t s;
  rs_sensor_init(&s, RS_MODEL_VLP16);
  int n = seq_order(order, (int)rs_synth_count(&cfg));
  run_t clean;
  run(&clean, &cfg, &acfg, order, n);
  const int clean_frames = clean.nframes;
  /* packet 100 arrives 40 packets (190 degrees) late */
  rs_synth_packet(&cfg, &s, 100, &enc);
  int pts = 0;
  for (int b = 0; b < 12; b++)
    for (int c = 0; c < 32; c++) pts += enc.distance[b][c] != 0;
  memmove(order + 100, order + 101, sizeof order[0] * 40);
  order[140] = 100;
  /* packet 200 again after 210 */
  memmove(order + 212, order + 211, sizeof order[0] * (size_t)(n - 211));
  order[211] = 200;
  n++;
  run_t r;
  run(&r, &cfg, &acfg, order, n);
  ck_assert_int_eq(r.nframes, clean_frames);
  ck_assert_uint_le(r.a.missing_packets, 1); /* its own gap, in its frame: it did miss it */
  ck_assert_uint_eq(r.a.duplicates, 1);
  ck_assert_uint_eq(r.a.late_points, (uint64_t)pts);
  ck_assert_uint_eq(map_points(&r) + r.a.late_points, r.decoded_points);
}
END_TEST

START_TEST(t_dual_layers) {
  rs_synth_cfg_t cfg = {.model = RS_MODEL_VLP32C, .mode = RS_MODE_DUAL, .hz = 10.0, .seconds = 0.3};
  rs_asm_cfg_t acfg = {.default_hz = 10.0};
  run_t r;
  run(&r, &cfg, &acfg, order, seq_order(order, (int)rs_synth_count(&cfg)));
  ck_assert_int_eq(r.nframes, 3); /* 0.3 s from azimuth 0 at 10 Hz */
  ck_assert_uint_eq(map_points(&r), r.decoded_points);
  /* the last and the strongest return of a firing sit in the same cell of two layers */
  const rs_slot_t *sl = &slots[0];
  uint32_t both = 0, l1 = 0;
  for (uint32_t c = 0; c < (uint32_t)sl->meta.rows * sl->meta.cols; c++) {
    if (sl->range[RS_MAX_CELLS + c] != 0.0f) {
      l1++;
      if (sl->range[c] != 0.0f) {
        both++;
        ck_assert_float_eq_tol(sl->range[RS_MAX_CELLS + c] - sl->range[c], 0.75, 0.01);
      }
    }
  }
  ck_assert_uint_gt(l1, 1000);
  ck_assert_uint_ge(both * 100, l1 * 99);
  ck_assert_uint_eq(rs_cell(sl, 1, 2, 5), RS_MAX_CELLS + 2u * sl->meta.cols + 5u);
}
END_TEST

START_TEST(t_rollover_rule) {
  int32_t last = -1;
  ck_assert(!rs_frame_rollover(0, &last, 35990));
  ck_assert(!rs_frame_rollover(0, &last, 36000)); /* 360.00 ends the turn */
  ck_assert(rs_frame_rollover(0, &last, 10));
  ck_assert(!rs_frame_rollover(0, &last, 5)); /* a small step back is no roll-over */
  last = -1;
  ck_assert(!rs_frame_rollover(9000, &last, 8990));
  ck_assert(rs_frame_rollover(9000, &last, 9010));
}
END_TEST

int main(void) {
  Suite *s = suite_create("frame");
  TCase *tc = tcase_create("core");
  tcase_set_timeout(tc, 120);
  tcase_add_test(tc, t_frames_no_loss);
  tcase_add_test(tc, t_straddle_split);
  tcase_add_test(tc, t_cut_azimuth);
  tcase_add_test(tc, t_columns_from_rate);
  tcase_add_test(tc, t_missing_packets);
  tcase_add_test(tc, t_reorder_and_duplicate);
  tcase_add_test(tc, t_late_packet);
  tcase_add_test(tc, t_half_turn_late_and_far_duplicate);
  tcase_add_test(tc, t_dual_layers);
  tcase_add_test(tc, t_rollover_rule);
  suite_add_tcase(s, tc);
  return tu_run(s);
}

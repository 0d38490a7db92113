/* check_cluster - FSPC, adaptive FSPC, DBSCAN and CCL on hand-built maps
 * with known answers. */
#include "roadscan/perception/cluster.h"
#include "roadscan/util/error.h"
#include "testutil.h"

#include <math.h>
#include <string.h>

static rs_slot_t slot;
static rs_cluster_t cl;
static rs_sensor_t sensor;
static rs_sensor_t vlp32c;

#define ROWS 16
#define COLS 200

static void clear_map(int cols) {
  memset(&slot.meta, 0, sizeof slot.meta);
  slot.meta.rows = ROWS;
  slot.meta.cols = (uint16_t)cols;
  memset(slot.range, 0, sizeof slot.range);
  memset(slot.label, 0, sizeof slot.label);
  memset(slot.gap, 0, sizeof slot.gap);
}

static void put(int r, int c, float range) {
  uint32_t i = (uint32_t)r * slot.meta.cols + (uint32_t)c;
  slot.range[i] = range;
  slot.label[i] = 2;
}

static void block(int r0, int r1, int c0, int c1, float range) {
  for (int r = r0; r <= r1; r++)
    for (int c = c0; c <= c1; c++) put(r, c, range);
}

static uint16_t lab(int r, int c) { return slot.label[(uint32_t)r * slot.meta.cols + (uint32_t)c]; }

static void run(rs_cluster_method_t m, rs_cluster_stats_t *st) {
  rs_cluster_cfg_t cfg;
  rs_cluster_cfg_default(&cfg);
  cfg.method = m;
  ck_assert_int_eq(rs_cluster_init(&cl, &cfg, &sensor), RS_OK);
  rs_cluster_run(&cl, &slot, st);
}

static void two_objects(rs_cluster_method_t m) {
  clear_map(COLS);
  block(4, 8, 10, 20, 10.0f); /* 55 cells at 10 m */
  block(4, 8, 21, 31, 20.0f); /* the next columns, 10 m behind */
  put(12, 150, 30.0f);        /* alone */
  rs_cluster_stats_t st;
  run(m, &st);
  ck_assert_uint_eq(st.foreground, 111);
  ck_assert_uint_eq(st.clusters, 2 + (m == RS_CLUSTER_CCL)); /* CCL has no noise: the lone return is a cluster */
  uint16_t a = lab(6, 15), b = lab(6, 26);
  ck_assert_int_ge(a, 3);
  ck_assert_int_ge(b, 3);
  ck_assert_int_ne(a, b);
  for (int r = 4; r <= 8; r++)
    for (int c = 10; c <= 31; c++) ck_assert_int_eq(lab(r, c), c <= 20 ? a : b);
  if (m == RS_CLUSTER_CCL) ck_assert_int_ge(lab(12, 150), 3);
  else ck_assert_int_eq(lab(12, 150), 2);
}

/* bridge_gap: a car's side at 10 m, rows 4-8, with the columns of lost packets empty (block columns
 * gap_from-gap_to, 16 here: wider than the window's reach, which the rows' offsets narrow; in each row
 * at its laser's azimuth offset from them, as the decoder puts its returns). When the slot says no
 * firing fell there (rs_slot_t.gap) the window reaches across them, counting measured columns: one
 * cluster; with bridge_gap 0, or where those columns were measured and hold nothing (a real space
 * between two objects), two; a gap wider than bridge_gap is not reached across. sen: the sensor (its
 * offsets). Returns the clusters. */
static uint32_t bridged(const rs_sensor_t *sen, rs_cluster_method_t m, int bridge_gap, int gap_from, int gap_to,
                        bool marked) {
  clear_map(COLS);
  for (int r = 4; r <= 8; r++) {
    const int sh = (int)lround(sen->azimuth_offset_deg[sen->laser_of_row[r]] * COLS / 360.0);
    block(r, r, 10, gap_from - 1 + sh, 10.0f);
    block(r, r, gap_to + 1 + sh, gap_to + 13, 10.0f);
  }
  if (marked)
    for (int c = gap_from; c <= gap_to; c++) slot.gap[c] = 1;
  rs_cluster_cfg_t cfg;
  rs_cluster_cfg_default(&cfg);
  cfg.method = m;
  cfg.bridge_gap = bridge_gap;
  ck_assert_int_eq(rs_cluster_init(&cl, &cfg, sen), RS_OK);
  rs_cluster_stats_t st;
  rs_cluster_run(&cl, &slot, &st);
  return st.clusters;
}

START_TEST(t_bridge_gap) {
  rs_cluster_cfg_t cfg;
  rs_cluster_cfg_default(&cfg);
  ck_assert_int_eq(cfg.bridge_gap, 32);
  const rs_cluster_method_t ms[] = {RS_CLUSTER_FSPC, RS_CLUSTER_FSPC_ADAPTIVE, RS_CLUSTER_CCL};
  const rs_sensor_t *sens[] = {&sensor, &vlp32c};
  for (int q = 0; q < 2; q++)
    for (int k = 0; k < 3; k++) {
      ck_assert_uint_eq(bridged(sens[q], ms[k], 32, 18, 33, true), 1);
      ck_assert_uint_eq(bridged(sens[q], ms[k], 0, 18, 33, true), 2);
      ck_assert_uint_eq(bridged(sens[q], ms[k], 32, 18, 33, false), 2);
      ck_assert_uint_eq(bridged(sens[q], ms[k], 32, 18, 57, true), 2); /* 40 columns */
      ck_assert_uint_eq(bridged(sens[q], ms[k], 40, 18, 57, true), 1);
    }
  cfg.bridge_gap = -1;
  ck_assert_int_eq(rs_cluster_init(&cl, &cfg, &sensor), RS_E_INVAL);
  cfg.bridge_gap = RS_CLUSTER_BRIDGE_MAX + 1;
  ck_assert_int_eq(rs_cluster_init(&cl, &cfg, &sensor), RS_E_INVAL);
}
END_TEST

START_TEST(t_two_objects) {
  two_objects(RS_CLUSTER_FSPC);
  two_objects(RS_CLUSTER_FSPC_ADAPTIVE);
  two_objects(RS_CLUSTER_DBSCAN);
  two_objects(RS_CLUSTER_CCL);
}
END_TEST

START_TEST(t_seam) {
  static const rs_cluster_method_t ms[] = {RS_CLUSTER_FSPC, RS_CLUSTER_DBSCAN, RS_CLUSTER_CCL};
  for (int i = 0; i < 3; i++) {
    clear_map(COLS);
    block(6, 10, 194, 199, 8.0f);
    block(6, 10, 0, 5, 8.0f);
    rs_cluster_stats_t st;
    run(ms[i], &st);
    ck_assert_uint_eq(st.clusters, 1);
    ck_assert_int_eq(lab(8, 197), lab(8, 2));
    ck_assert_int_ge(lab(8, 2), 3);
  }
}
END_TEST

START_TEST(t_core_border_noise) {
  clear_map(COLS);
  block(5, 9, 50, 54, 10.0f); /* 25 cells: the middle ones see all 25 */
  put(5, 59, 10.5f);          /* within the window of core (5..7, 54), sees only 4 */
  put(5, 61, 10.5f);          /* beyond every core window: noise */
  rs_cluster_stats_t st;
  run(RS_CLUSTER_FSPC, &st);
  ck_assert_uint_eq(st.clusters, 1);
  uint16_t id = lab(7, 52);
  ck_assert_int_ge(id, 3);
  ck_assert_int_eq(lab(5, 59), id); /* border */
  ck_assert_int_eq(lab(5, 61), 2);  /* noise */
  ck_assert_uint_eq(st.clustered, 26);
  ck_assert_uint_eq(st.noise, 1);
  /* with the range gap over eps the border return is not a neighbour */
  slot.range[5 * COLS + 59] = 12.0f;
  slot.label[5 * COLS + 59] = 2;
  run(RS_CLUSTER_FSPC, &st);
  ck_assert_int_eq(lab(5, 59), 2);
  /* background returns are left alone */
  slot.label[7 * COLS + 52] = 1;
  run(RS_CLUSTER_FSPC, &st);
  ck_assert_int_eq(lab(7, 52), 1);
  ck_assert_uint_eq(st.foreground, 26);
}
END_TEST

START_TEST(t_window_clipping) {
  clear_map(COLS);
  block(0, 2, 10, 20, 15.0f);            /* top rows: the window is clipped */
  block(ROWS - 3, ROWS - 1, 100, 110, 15.0f); /* bottom rows */
  rs_cluster_stats_t st;
  run(RS_CLUSTER_FSPC, &st);
  ck_assert_uint_eq(st.clusters, 2);
  ck_assert_uint_eq(st.noise, 0);
  /* one row only: 11 neighbours at most, under minPts 15 */
  clear_map(COLS);
  block(0, 0, 10, 25, 15.0f);
  run(RS_CLUSTER_FSPC, &st);
  ck_assert_uint_eq(st.clusters, 0);
  ck_assert_uint_eq(st.noise, 16);
}
END_TEST

START_TEST(t_cap_overflow) {
  clear_map(300);
  /* every cell its own cluster: distinct ranges 2 m apart, minPts 1 */
  for (int r = 0; r < ROWS; r++)
    for (int c = 0; c < 300; c++) put(r, c, 5.0f + 2.0f * (float)((r * 300 + c) % 97));
  rs_cluster_cfg_t cfg;
  rs_cluster_cfg_default(&cfg);
  cfg.fspc.min_pts = 1;
  cfg.fspc.eps = 0.5f;
  rs_cluster_init(&cl, &cfg, &sensor);
  rs_cluster_stats_t st;
  rs_cluster_run(&cl, &slot, &st);
  ck_assert_uint_eq(st.foreground, ROWS * 300);
  ck_assert_uint_eq(st.clusters, RS_MAX_CLUSTERS);
  ck_assert_uint_gt(st.overflow, 0);
  ck_assert_uint_eq(cl.overflow_total, st.overflow);
  ck_assert_uint_eq(st.noise, ROWS * 300 - st.clustered);
}
END_TEST

START_TEST(t_fspc_equals_dbscan) {
  /* one row, 21 neighbouring columns at 10 m (0.2 degree apart: 3.5 cm), and
   * one return 40 m away: a window covering every column with eps = DBSCAN's
   * radius gives the same neighbourhoods as the 3-D radius search */
  clear_map(1800);
  for (int c = 100; c <= 120; c++) put(8, c, 10.0f);
  put(8, 110 + 300, 50.0f);
  rs_cluster_cfg_t cfg;
  rs_cluster_cfg_default(&cfg);
  cfg.method = RS_CLUSTER_FSPC;
  cfg.fspc.win_h = 1;
  cfg.fspc.win_w = 31;
  cfg.fspc.eps = 1.2f;
  cfg.fspc.min_pts = 15;
  rs_cluster_init(&cl, &cfg, &sensor);
  rs_cluster_stats_t a, b;
  rs_cluster_run(&cl, &slot, &a);
  uint16_t fspc_labels[1800];
  for (int c = 0; c < 1800; c++) fspc_labels[c] = lab(8, c);
  for (int c = 100; c <= 120; c++) slot.label[8 * 1800 + c] = 2;
  slot.label[8 * 1800 + 410] = 2;
  cfg.method = RS_CLUSTER_DBSCAN;
  rs_cluster_init(&cl, &cfg, &sensor);
  rs_cluster_run(&cl, &slot, &b);
  ck_assert_uint_eq(a.clusters, 1);
  ck_assert_uint_eq(b.clusters, 1);
  ck_assert_uint_eq(a.clustered, b.clustered);
  for (int c = 0; c < 1800; c++) ck_assert_int_eq(fspc_labels[c], lab(8, c));
}
END_TEST

START_TEST(t_adaptive_sparse) {
  /* a car roof near the pole seen by one laser only, and a pedestrian at
   * 150 m: 2 columns x 2 rows. Plain FSPC calls both noise, adaptive finds them */
  clear_map(1820);
  block(0, 0, 300, 330, 6.0f);
  block(9, 10, 900, 901, 150.0f);
  rs_cluster_stats_t st;
  run(RS_CLUSTER_FSPC, &st);
  ck_assert_uint_eq(st.clusters, 0);
  run(RS_CLUSTER_FSPC_ADAPTIVE, &st);
  ck_assert_uint_eq(st.clusters, 2);
  ck_assert_int_ge(lab(0, 315), 3);
  ck_assert_int_ge(lab(9, 900), 3);
  ck_assert_int_ne(lab(0, 315), lab(9, 900));
}
END_TEST

/* default adaptive settings and an empty VLP-32C map (32 rows x 1820 columns) */
static void adaptive_vlp32c(rs_cluster_cfg_t *cfg) {
  rs_cluster_cfg_default(cfg);
  cfg->method = RS_CLUSTER_FSPC_ADAPTIVE;
  clear_map(1820);
  slot.meta.rows = 32;
}

static void run_adaptive(const rs_cluster_cfg_t *cfg, rs_cluster_stats_t *st) {
  ck_assert_int_eq(rs_cluster_init(&cl, cfg, &vlp32c), RS_OK);
  rs_cluster_run(&cl, &slot, st);
}

/* VLP-32C beyond 100 m, rows near the horizon (0.33 degrees apart): the
 * smallest object covers fewer than 3 cells, so a pair of returns side by
 * side is an object, even with a column lost between them; one return alone
 * is not, nor is a pair at 20 m, where an object covers dozens of cells. */
START_TEST(t_adaptive_far_pairs) {
  rs_cluster_cfg_t cfg;
  rs_cluster_stats_t st;
  adaptive_vlp32c(&cfg);
  block(18, 18, 900, 901, 180.0f);  /* a pair */
  put(18, 1000, 170.0f);            /* a pair with a missing return between */
  put(18, 1002, 170.3f);
  put(18, 1100, 175.0f);            /* alone */
  block(18, 18, 1300, 1301, 20.0f); /* a pair near the pole */
  run_adaptive(&cfg, &st);
  ck_assert_uint_eq(st.clusters, 2);
  ck_assert_int_ge(lab(18, 900), 3);
  ck_assert_int_eq(lab(18, 901), lab(18, 900));
  ck_assert_int_ge(lab(18, 1000), 3);
  ck_assert_int_eq(lab(18, 1002), lab(18, 1000));
  ck_assert_int_eq(lab(18, 1100), 2);
  ck_assert_int_eq(lab(18, 1300), 2);
  cfg.adaptive.min_half_w = 1; /* the window no longer reaches over the missing return */
  run_adaptive(&cfg, &st);
  ck_assert_uint_eq(st.clusters, 1);
  ck_assert_int_eq(lab(18, 1000), 2);
  cfg.adaptive.sparse_min_pts = 3; /* and pairs are not enough */
  run_adaptive(&cfg, &st);
  ck_assert_uint_eq(st.clusters, 0);
}
END_TEST

/* Two people walking in file at 49 m, the one behind 1.4 m farther and a
 * little to the side (adjacent columns, the same rows): two clusters with
 * the default eps (0.025 x range: 1.24 m there); at the former 0.03 (1.49 m)
 * they were one. */
START_TEST(t_adaptive_people_in_file) {
  rs_cluster_cfg_t cfg;
  rs_cluster_stats_t st;
  adaptive_vlp32c(&cfg);
  ck_assert_float_eq_tol(cfg.adaptive.eps_share, 0.025f, 1e-6f);
  block(14, 19, 700, 702, 48.2f);
  block(14, 19, 703, 705, 49.6f);
  run_adaptive(&cfg, &st);
  ck_assert_uint_eq(st.clusters, 2);
  ck_assert_int_ge(lab(16, 702), 3);
  ck_assert_int_ge(lab(16, 703), 3);
  ck_assert_int_ne(lab(16, 702), lab(16, 703));
  cfg.adaptive.eps_share = 0.03f;
  cfg.adaptive.split_gap = 0.0f; /* the split pass (below) would cut them again */
  run_adaptive(&cfg, &st);
  ck_assert_uint_eq(st.clusters, 1);
  ck_assert_int_eq(lab(16, 702), lab(16, 703));
}
END_TEST

/* The split pass: people in file at 33 m that a wide eps (0.06 x range: 2 m)
 * joins, 1.4 m apart in range, side by side in the image, each 3 columns x 6
 * rows (0.35 m wide, 0.2 m deep) */
static void file_of_people(int n, int col0) {
  for (int p = 0; p < n; p++)
    for (int r = 12; r <= 17; r++)
      for (int k = 0; k < 3; k++) {
        int c = (col0 + 3 * p + k) % 1820;
        put(r, c, 33.0f + 1.4f * (float)p + 0.1f * (float)(r % 3));
      }
}

START_TEST(t_adaptive_split_file) {
  rs_cluster_cfg_t cfg;
  rs_cluster_stats_t st;
  adaptive_vlp32c(&cfg);
  cfg.adaptive.eps_share = 0.06f;
  ck_assert_float_eq_tol(cfg.adaptive.split_gap, 0.5f, 1e-6f);
  /* three people in file, one of them across column 0: three clusters, the nearest keeps its label */
  file_of_people(3, 1817);
  run_adaptive(&cfg, &st);
  ck_assert_uint_eq(st.clusters, 3);
  ck_assert_uint_eq(st.splits, 1);
  ck_assert_uint_eq(st.clustered, 54);
  const uint16_t a = lab(14, 1817), b = lab(14, 1), c = lab(14, 4); /* the second one: columns 0 .. 2 */
  ck_assert_int_eq(a, 3);
  ck_assert_int_ge(b, 3);
  ck_assert_int_ge(c, 3);
  ck_assert(a != b && b != c && a != c);
  for (int r = 12; r <= 17; r++) {
    ck_assert_int_eq(lab(r, 1819), a);
    ck_assert_int_eq(lab(r, 0), b);
    ck_assert_int_eq(lab(r, 2), b);
    ck_assert_int_eq(lab(r, 5), c);
  }
  /* off: one cluster */
  cfg.adaptive.split_gap = 0.0f;
  run_adaptive(&cfg, &st);
  ck_assert_uint_eq(st.clusters, 1);
  ck_assert_uint_eq(st.splits, 0);

  /* mixed ranges in one column between two people stay with the nearer one */
  adaptive_vlp32c(&cfg);
  cfg.adaptive.eps_share = 0.06f;
  file_of_people(2, 700);
  for (int r = 12; r <= 17; r++) put(r, 703, 33.7f);
  run_adaptive(&cfg, &st);
  ck_assert_uint_eq(st.clusters, 2);
  ck_assert_int_eq(lab(13, 703), lab(13, 700));
  ck_assert_int_ne(lab(13, 704), lab(13, 700));
}
END_TEST

/* What the split pass leaves whole: a bumper and, 1.4 m behind, a roof in
 * the rows above; a wide part (the side of a car); a deep part; a part of fewer
 * than split_min returns */
START_TEST(t_adaptive_split_keeps) {
  rs_cluster_cfg_t cfg;
  rs_cluster_stats_t st;
  const int cases = 4;
  for (int k = 0; k < cases; k++) {
    adaptive_vlp32c(&cfg);
    cfg.adaptive.eps_share = 0.06f;
    switch (k) {
    case 0: /* rows 12..14 and 15..17 */
      block(12, 14, 700, 705, 33.0f);
      block(15, 17, 700, 705, 34.4f);
      break;
    case 1: /* 2 m wide (18 columns at 33 m) in front of a person */
      block(12, 17, 700, 717, 33.0f);
      block(12, 17, 718, 720, 34.4f);
      break;
    case 2: /* the near part 0.8 m deep */
      for (int r = 12; r <= 17; r++)
        for (int c = 700; c <= 702; c++) put(r, c, 33.0f + 0.16f * (float)(r - 12));
      block(12, 17, 703, 705, 35.2f);
      break;
    default: /* 4 returns 1.4 m behind */
      block(12, 17, 700, 702, 33.0f);
      block(12, 13, 703, 704, 34.4f);
      break;
    }
    run_adaptive(&cfg, &st);
    ck_assert_msg(st.clusters == 1 && st.splits == 0, "case %d: %u clusters", k, st.clusters);
    /* the same with the limit that case is about relaxed: cut */
    if (k == 1) cfg.adaptive.split_width = 3.0f;
    else if (k == 2) cfg.adaptive.split_depth = 1.0f;
    else if (k == 3) cfg.adaptive.split_min = 4;
    else continue;
    run_adaptive(&cfg, &st);
    ck_assert_msg(st.clusters == 2 && st.splits == 1, "case %d relaxed: %u clusters", k, st.clusters);
  }
  /* bad values */
  rs_cluster_cfg_default(&cfg);
  cfg.adaptive.split_width = 0.0f;
  ck_assert_int_eq(rs_cluster_init(&cl, &cfg, &vlp32c), RS_E_INVAL);
  rs_cluster_cfg_default(&cfg);
  cfg.adaptive.split_gap = -1.0f;
  ck_assert_int_eq(rs_cluster_init(&cl, &cfg, &vlp32c), RS_E_INVAL);
  rs_cluster_cfg_default(&cfg);
  cfg.adaptive.split_min = 0;
  ck_assert_int_eq(rs_cluster_init(&cl, &cfg, &vlp32c), RS_E_INVAL);
}
END_TEST

/* A return 3.5 m behind the edge of an object at 150 m (eps there: 2.5 m) is
 * not a core; it joins the object within twice eps. An object whose own
 * cores are 3.5 m behind stays a separate cluster: core cells link within
 * eps only. */
START_TEST(t_adaptive_border_eps) {
  rs_cluster_cfg_t cfg;
  rs_cluster_stats_t st;
  adaptive_vlp32c(&cfg);
  block(16, 19, 500, 505, 150.0f);
  put(17, 506, 153.5f);
  block(16, 19, 600, 605, 150.0f);
  block(16, 19, 606, 611, 153.5f);
  run_adaptive(&cfg, &st);
  ck_assert_uint_eq(st.clusters, 3);
  ck_assert_int_eq(lab(17, 506), lab(17, 505));
  ck_assert_int_ne(lab(17, 606), lab(17, 605));
  ck_assert_int_ge(lab(17, 606), 3);
  cfg.adaptive.border_eps = 1.0f;
  run_adaptive(&cfg, &st);
  ck_assert_uint_eq(st.clusters, 3);
  ck_assert_int_eq(lab(17, 506), 2);
  cfg.adaptive.border_eps = 0.5f;
  ck_assert_int_eq(rs_cluster_init(&cl, &cfg, &vlp32c), RS_E_INVAL);
}
END_TEST

/* a 3 x 4 object at 40 m whose two right columns lie where the static scene has 3
 * surfaces, and a 3 x 3 group of returns entirely in such cells (foliage flicker);
 * clustered with the surface counts and the given adapt_seed_surfaces */
static uint8_t surfaces[RS_MAX_CELLS];
static void see_through_scene(int seed_surfaces, bool with_counts, rs_cluster_stats_t *st) {
  memset(surfaces, 1, sizeof surfaces);
  for (int r = 10; r <= 12; r++) {
    for (int c = 402; c <= 403; c++) surfaces[r * 1820 + c] = 3;
    for (int c = 800; c <= 802; c++) surfaces[r * 1820 + c] = 3;
  }
  rs_cluster_cfg_t cfg;
  rs_cluster_cfg_default(&cfg);
  cfg.method = RS_CLUSTER_FSPC_ADAPTIVE;
  cfg.adaptive.seed_surfaces = seed_surfaces;
  ck_assert_int_eq(rs_cluster_init(&cl, &cfg, &sensor), RS_OK);
  cl.bg_surfaces = with_counts ? surfaces : NULL;
  clear_map(1820);
  block(10, 12, 400, 403, 40.0f);
  block(10, 12, 800, 802, 55.0f);
  rs_cluster_run(&cl, &slot, st);
}

START_TEST(t_see_through_cells_do_not_seed) {
  rs_cluster_stats_t st;
  see_through_scene(3, false, &st); /* without the model's counts: two clusters */
  ck_assert_uint_eq(st.clusters, 2);
  see_through_scene(3, true, &st);
  ck_assert_uint_eq(st.clusters, 1); /* the flicker is noise */
  for (int r = 10; r <= 12; r++) {
    for (int c = 400; c <= 403; c++) ck_assert_int_eq(lab(r, c), 3); /* joined, though it seeds nothing */
    for (int c = 800; c <= 802; c++) ck_assert_int_eq(lab(r, c), 2);
  }
  see_through_scene(0, true, &st); /* 0 turns it off */
  ck_assert_uint_eq(st.clusters, 2);
  see_through_scene(4, true, &st); /* cells of 3 surfaces are below a threshold of 4 */
  ck_assert_uint_eq(st.clusters, 2);
}
END_TEST

START_TEST(t_dual_layer_and_config) {
  clear_map(COLS);
  block(4, 8, 10, 20, 10.0f);
  slot.range[RS_MAX_CELLS + 6 * COLS + 15] = 10.4f; /* second return of the same object */
  slot.range[RS_MAX_CELLS + 6 * COLS + 16] = 30.0f; /* a wall behind it */
  rs_cluster_stats_t st;
  run(RS_CLUSTER_FSPC, &st);
  ck_assert_int_eq(slot.label[RS_MAX_CELLS + 6 * COLS + 15], lab(6, 15));
  ck_assert_int_eq(slot.label[RS_MAX_CELLS + 6 * COLS + 16], 2);
  rs_cluster_cfg_t cfg;
  rs_cluster_cfg_default(&cfg);
  cfg.fspc.win_w = 10;
  ck_assert_int_eq(rs_cluster_init(&cl, &cfg, &sensor), RS_E_INVAL);
  cfg.fspc.win_w = 11;
  cfg.fspc.eps = 0;
  ck_assert_int_eq(rs_cluster_init(&cl, &cfg, &sensor), RS_E_INVAL);
  cfg.fspc.eps = 1.8f;
  cfg.adaptive.win_h = 4; /* each method's own parameters are checked */
  ck_assert_int_eq(rs_cluster_init(&cl, &cfg, &sensor), RS_E_INVAL);
  cfg.adaptive.win_h = 5;
  cfg.dbscan.min_pts = 0;
  ck_assert_int_eq(rs_cluster_init(&cl, &cfg, &sensor), RS_E_INVAL);
  ck_assert_int_eq(rs_cluster_method_from_name("fspc-adaptive"), RS_CLUSTER_FSPC_ADAPTIVE);
  ck_assert_int_eq(rs_cluster_method_from_name("kmeans"), -1);
}
END_TEST

/* The second layer joins the first within the method's own eps, not FSPC's
 * 1.8 m for every method; the members list holds every clustered cell of
 * both layers, layer 0 first, row-major. */
START_TEST(t_dual_layer_method_eps) {
  static const rs_cluster_method_t ms[] = {RS_CLUSTER_FSPC, RS_CLUSTER_FSPC_ADAPTIVE, RS_CLUSTER_DBSCAN, RS_CLUSTER_CCL};
  /* 1.2 m behind: within FSPC's 1.8 m; beyond the adaptive eps at 10 m (0.5 m), DBSCAN's 1.0 m here and CCL's 1.0 m */
  static const bool joins[] = {true, false, false, false};
  for (int k = 0; k < 4; k++) {
    clear_map(COLS);
    block(4, 8, 10, 20, 10.0f);
    const uint32_t j = RS_MAX_CELLS + 6 * COLS + 15;
    slot.range[j] = 11.2f;
    slot.range[RS_MAX_CELLS + 5 * COLS + 12] = 10.1f; /* close behind: joins with every method */
    rs_cluster_cfg_t cfg;
    rs_cluster_cfg_default(&cfg);
    cfg.method = ms[k];
    cfg.dbscan.eps = 1.0f;
    ck_assert_int_eq(rs_cluster_init(&cl, &cfg, &sensor), RS_OK);
    rs_cluster_stats_t st;
    rs_cluster_run(&cl, &slot, &st);
    ck_assert_int_ge(lab(6, 15), 3);
    ck_assert_msg(slot.label[j] == (joins[k] ? lab(6, 15) : 2), "%s: label %u", rs_cluster_method_name(ms[k]),
                  slot.label[j]);
    ck_assert_int_eq(slot.label[RS_MAX_CELLS + 5 * COLS + 12], lab(5, 12));
    /* members: the 55 cells, then the second layer's */
    ck_assert_uint_eq(cl.nmembers, 55u + 1u + (joins[k] ? 1u : 0u));
    for (uint32_t m = 1; m < cl.nmembers; m++) ck_assert_uint_gt(cl.members[m], cl.members[m - 1]);
    for (uint32_t m = 0; m < cl.nmembers; m++) ck_assert_int_ge(slot.label[cl.members[m]], 3);
    ck_assert_uint_eq(cl.members[55], RS_MAX_CELLS + 5 * COLS + 12);
  }
}
END_TEST

/* --eps, --min-pts and --window reach the chosen method's own parameters, and only those */
START_TEST(t_method_setters) {
  rs_cluster_cfg_t c, d;
  rs_cluster_cfg_default(&c);
  d = c;
  c.method = RS_CLUSTER_DBSCAN;
  ck_assert(rs_cluster_cfg_set_eps(&c, 0.5f));
  ck_assert(rs_cluster_cfg_set_min_pts(&c, 7));
  ck_assert(!rs_cluster_cfg_set_window(&c, 3, 3));
  ck_assert_float_eq(c.dbscan.eps, 0.5f);
  ck_assert_int_eq(c.dbscan.min_pts, 7);
  ck_assert_float_eq(c.fspc.eps, d.fspc.eps);
  ck_assert_float_eq(c.ccl.eps, d.ccl.eps);
  ck_assert_float_eq(c.adaptive.eps_max, d.adaptive.eps_max);
  c.method = RS_CLUSTER_FSPC_ADAPTIVE;
  ck_assert(rs_cluster_cfg_set_eps(&c, 3.0f));
  ck_assert(rs_cluster_cfg_set_window(&c, 7, 15));
  ck_assert(rs_cluster_cfg_set_min_pts(&c, 20));
  ck_assert_float_eq(c.adaptive.eps_max, 3.0f);
  ck_assert_int_eq(c.adaptive.win_w, 15);
  ck_assert_int_eq(c.adaptive.max_min_pts, 20);
  ck_assert_int_eq(c.fspc.win_w, d.fspc.win_w);
  ck_assert_int_eq(c.fspc.min_pts, d.fspc.min_pts);
  c.method = RS_CLUSTER_CCL;
  ck_assert(!rs_cluster_cfg_set_min_pts(&c, 3));
  ck_assert(rs_cluster_cfg_set_eps(&c, 0.7f));
  ck_assert_float_eq(c.ccl.eps, 0.7f);
  c.method = RS_CLUSTER_NONE;
  ck_assert(!rs_cluster_cfg_set_eps(&c, 1.0f));
  c.method = RS_CLUSTER_FSPC;
  ck_assert(rs_cluster_cfg_set_window(&c, 3, 9));
  ck_assert_int_eq(c.fspc.win_h, 3);
  ck_assert_int_eq(c.adaptive.win_w, 15);
}
END_TEST

int main(void) {
  rs_sensor_init(&sensor, RS_MODEL_VLS128); /* 128 rows: any test row has a laser */
  rs_sensor_init(&vlp32c, RS_MODEL_VLP32C);
  Suite *s = suite_create("cluster");
  TCase *tc = tcase_create("core");
  tcase_set_timeout(tc, 60);
  tcase_add_test(tc, t_two_objects);
  tcase_add_test(tc, t_bridge_gap);
  tcase_add_test(tc, t_seam);
  tcase_add_test(tc, t_core_border_noise);
  tcase_add_test(tc, t_window_clipping);
  tcase_add_test(tc, t_cap_overflow);
  tcase_add_test(tc, t_fspc_equals_dbscan);
  tcase_add_test(tc, t_adaptive_sparse);
  tcase_add_test(tc, t_adaptive_far_pairs);
  tcase_add_test(tc, t_adaptive_border_eps);
  tcase_add_test(tc, t_adaptive_people_in_file);
  tcase_add_test(tc, t_adaptive_split_file);
  tcase_add_test(tc, t_adaptive_split_keeps);
  tcase_add_test(tc, t_see_through_cells_do_not_seed);
  tcase_add_test(tc, t_dual_layer_and_config);
  tcase_add_test(tc, t_dual_layer_method_eps);
  tcase_add_test(tc, t_method_setters);
  suite_add_tcase(s, tc);
  return tu_run(s);
}

/* check_calib - ROS velodyne YAML calibration files: applied values, and
 * every kind of bad file rejected with a message naming the problem. */
#include "roadscan/sensor/calib.h"
#include "roadscan/util/error.h"
#include "roadscan/sensor/packet.h"
#include "testutil.h"

#include <math.h>
#include <stdio.h>
#include <string.h>

static char err[RS_ERRMSG_SIZE];

static const char *write_file(const char *name, const char *text) {
  const char *p = tu_tmp(name);
  FILE *f = fopen(p, "w");
  fputs(text, f);
  fclose(f);
  return p;
}

/* a VLP-16 file in the ROS layout (flow mappings), laser 3 tilted */
static const char *vlp16_yaml(const char *name, int drop_laser, int dup_laser, const char *extra) {
  static char buf[8192];
  int n = snprintf(buf, sizeof buf, "lasers:\n");
  for (int i = 0; i < 16; i++) {
    if (i == drop_laser) continue;
    int id = i == dup_laser ? 0 : i;
    double vert = (i % 2 ? (i / 2) * 2 + 1 : -15 + (i / 2) * 2) * 3.14159265358979 / 180.0;
    double rot = i == 3 ? -0.01 : 0.0;
    n += snprintf(buf + n, sizeof buf - (size_t)n,
                  "- {dist_correction: %s, dist_correction_x: 0.0, dist_correction_y: 0.0, focal_distance: 0.0,\n"
                  "  focal_slope: 0.0, laser_id: %d, rot_correction: %.17g, vert_correction: %.17g,\n"
                  "  vert_offset_correction: %s}\n",
                  i == 3 ? "0.05" : "0.0", id, rot, i == 3 ? vert + 0.001 : vert, i == 3 ? "0.01" : "0.0");
  }
  snprintf(buf + n, sizeof buf - (size_t)n, "num_lasers: 16\ndistance_resolution: 0.002\n%s", extra ? extra : "");
  return write_file(name, buf);
}

START_TEST(t_good_file) {
  rs_calib_t c;
  ck_assert_int_eq(rs_calib_load_yaml(vlp16_yaml("good.yaml", -1, -1, NULL), &c, err, sizeof err), RS_OK);
  ck_assert_int_eq(c.lasers, 16);
  ck_assert_float_eq_tol(c.dist_res_m, 0.002, 1e-9);
  ck_assert_float_eq_tol(c.elevation_deg[0], -15.0, 1e-4);
  ck_assert_float_eq_tol(c.azimuth_offset_deg[3], 0.01 * 180.0 / 3.14159265358979, 1e-4);
  ck_assert_int_eq(c.ignored_fields, 0);
  rs_sensor_t s;
  rs_sensor_init(&s, RS_MODEL_VLP16);
  char warn[RS_ERRMSG_SIZE];
  ck_assert_int_eq(rs_calib_apply(&c, &s, err, sizeof err, warn, sizeof warn), RS_OK);
  ck_assert_str_eq(warn, ""); /* 2 mm is the VLP-16's own unit */
  ck_assert(s.calibrated);
  ck_assert_float_eq_tol(s.dist_correction_m[3], 0.05, 1e-6);
  ck_assert_float_eq_tol(s.vert_offset_m[3], 0.01, 1e-6);
  ck_assert_float_eq_tol(s.elevation_deg[3], 3.0 + 0.001 * 180.0 / 3.14159265358979, 1e-4);
  /* a 16-laser file does not fit a 32-laser sensor */
  rs_sensor_init(&s, RS_MODEL_VLP32C);
  ck_assert_int_eq(rs_calib_apply(&c, &s, err, sizeof err, NULL, 0), RS_E_CALIB);
  ck_assert_ptr_nonnull(strstr(err, "16 lasers"));
}
END_TEST

static void expect_bad(const char *path, const char *needle) {
  rs_calib_t c;
  err[0] = '\0';
  ck_assert_int_eq(rs_calib_load_yaml(path, &c, err, sizeof err), RS_E_CALIB);
  ck_assert_msg(strstr(err, needle) != NULL, "message '%s' lacks '%s'", err, needle);
}

START_TEST(t_bad_files) {
  expect_bad(vlp16_yaml("missing.yaml", 5, -1, NULL), "num_lasers is 16 but 'lasers' has 15");
  expect_bad(vlp16_yaml("dup.yaml", -1, 4, NULL), "laser_id 0 appears twice");
  expect_bad(write_file("nan.yaml", "lasers:\n- {laser_id: 0, rot_correction: abc, vert_correction: 0}\nnum_lasers: 1\n"),
             "rot_correction is not a number");
  expect_bad(write_file("deg.yaml", "lasers:\n- {laser_id: 0, rot_correction: 0, vert_correction: -15}\nnum_lasers: 1\n"),
             "radians expected");
  expect_bad(write_file("range.yaml", "lasers:\n- {laser_id: 3, rot_correction: 0, vert_correction: 0}\nnum_lasers: 1\n"),
             "out of range");
  expect_bad(write_file("nolist.yaml", "num_lasers: 16\n"), "missing 'lasers'");
  expect_bad(write_file("syntax.yaml", "lasers: [ {laser_id: 0\n"), "YAML error at line");
  expect_bad(write_file("scalar.yaml", "just text\n"), "not a calibration mapping");
  expect_bad(write_file("res.yaml", "lasers: []\nnum_lasers: 0\n"), "num_lasers must be");
  expect_bad(write_file("noid.yaml", "lasers:\n- {rot_correction: 0, vert_correction: 0}\nnum_lasers: 1\n"),
             "laser_id missing");
  expect_bad(write_file("negid.yaml", "lasers:\n- {laser_id: -1, rot_correction: 0, vert_correction: 0}\nnum_lasers: 1\n"),
             "laser_id -1 is negative");
  rs_calib_t c;
  ck_assert_int_eq(rs_calib_load_yaml(tu_tmp("does-not-exist.yaml"), &c, err, sizeof err), RS_E_NOENT);
  ck_assert_ptr_nonnull(strstr(err, "does-not-exist.yaml"));
}
END_TEST

START_TEST(t_ignored_terms) {
  rs_calib_t c;
  const char *p = write_file("twopt.yaml",
                             "lasers:\n- {laser_id: 0, rot_correction: 0, vert_correction: 0, dist_correction_x: 0.1,\n"
                             "  two_pt_correction_available: true}\nnum_lasers: 1\n");
  ck_assert_int_eq(rs_calib_load_yaml(p, &c, err, sizeof err), RS_OK);
  ck_assert_int_eq(c.ignored_fields, 2);
}
END_TEST

/* A file as tier4/nebula ships it for the VLS-128 says distance_resolution
 * 0.007; the packet format fixes 4 mm: the value is ignored, with a warning
 * naming it, and ranges decode at 4 mm per unit. */
START_TEST(t_fixed_resolution) {
  static char buf[16384];
  int n = snprintf(buf, sizeof buf, "num_lasers: 128\ndistance_resolution: 0.007\nlasers:\n");
  for (int i = 0; i < 128; i++)
    n += snprintf(buf + n, sizeof buf - (size_t)n, "- {laser_id: %d, rot_correction: 0.0, vert_correction: %.6f}\n", i,
                  (-25.0 + i * 0.3) * 3.14159265358979 / 180.0);
  rs_calib_t c;
  ck_assert_int_eq(rs_calib_load_yaml(write_file("vls128.yaml", buf), &c, err, sizeof err), RS_OK);
  ck_assert_float_eq_tol(c.dist_res_m, 0.007, 1e-9); /* read as written */
  rs_sensor_t s;
  rs_sensor_init(&s, RS_MODEL_VLS128);
  char warn[RS_ERRMSG_SIZE];
  ck_assert_int_eq(rs_calib_apply(&c, &s, err, sizeof err, warn, sizeof warn), RS_OK);
  ck_assert_float_eq_tol(s.dist_res_m, 0.004, 1e-9);
  ck_assert_msg(strstr(warn, "distance_resolution") && strstr(warn, "ignored") && strstr(warn, "VLS-128"), "warning: %s",
                warn);
  /* the same file's resolution on a VLP-16-sized file: 2 mm stays */
  const char *p = vlp16_yaml("res7.yaml", -1, -1, NULL);
  ck_assert_int_eq(rs_calib_load_yaml(p, &c, err, sizeof err), RS_OK);
  c.dist_res_m = 0.007f;
  rs_sensor_init(&s, RS_MODEL_VLP16);
  ck_assert_int_eq(rs_calib_apply(&c, &s, err, sizeof err, warn, sizeof warn), RS_OK);
  ck_assert_float_eq_tol(s.dist_res_m, 0.002, 1e-9);
  ck_assert_ptr_nonnull(strstr(warn, "0.002"));
}
END_TEST

/* A correction that can make ranges negative is refused, with its name;
 * one that is accepted never gives a point at or behind the sensor. */
START_TEST(t_negative_correction) {
  char text[8192];
  snprintf(text, sizeof text, "%s", vlp16_yaml("neg.yaml", -1, -1, NULL));
  FILE *f = fopen(text, "r");
  static char buf[8192];
  size_t len = fread(buf, 1, sizeof buf - 1, f);
  buf[len] = '\0';
  fclose(f);
  char *at = strstr(buf, "dist_correction: 0.05");
  ck_assert_ptr_nonnull(at);
  char bad[8192];
  snprintf(bad, sizeof bad, "%.*sdist_correction: -2.0%s", (int)(at - buf), buf, at + strlen("dist_correction: 0.05"));
  expect_bad(write_file("neg2.yaml", bad), "dist_correction -2.000 m would make the ranges of near returns negative");
  char ok[8192];
  snprintf(ok, sizeof ok, "%.*sdist_correction: -0.3%s", (int)(at - buf), buf, at + strlen("dist_correction: 0.05"));
  rs_calib_t c;
  ck_assert_int_eq(rs_calib_load_yaml(write_file("neg03.yaml", ok), &c, err, sizeof err), RS_OK);
  rs_sensor_t s;
  rs_sensor_init(&s, RS_MODEL_VLP16);
  ck_assert_int_eq(rs_calib_apply(&c, &s, err, sizeof err, NULL, 0), RS_OK);
  /* every record 0.1 m (50 x 2 mm): laser 3's corrected range is -0.2 m */
  static rs_encode_t enc;
  memset(&enc, 0, sizeof enc);
  enc.mode_byte = RS_MODE_STRONGEST;
  for (int b = 0; b < RS_BLOCKS; b++) {
    enc.block_azimuth[b] = (uint16_t)(b * 40);
    for (int ch = 0; ch < RS_RECORDS; ch++) enc.distance[b][ch] = 50;
  }
  static uint8_t pkt[RS_PAYLOAD_SIZE];
  rs_packet_encode(s.info, &enc, pkt);
  static rs_packet_t out;
  ck_assert_int_eq(rs_packet_decode(&s, pkt, RS_PAYLOAD_SIZE, 0.0036, &out), RS_OK);
  ck_assert_int_eq(out.n_points, RS_BLOCKS * RS_RECORDS - RS_BLOCKS * 2); /* laser 3 fires twice per block */
  for (int i = 0; i < out.n_points; i++) {
    ck_assert_float_gt(out.points[i].distance, 0.0f);
    ck_assert_int_ne(out.points[i].laser, 3);
  }
}
END_TEST

int main(void) {
  Suite *s = suite_create("calib");
  TCase *tc = tcase_create("core");
  tcase_add_test(tc, t_good_file);
  tcase_add_test(tc, t_bad_files);
  tcase_add_test(tc, t_ignored_terms);
  tcase_add_test(tc, t_fixed_resolution);
  tcase_add_test(tc, t_negative_correction);
  suite_add_tcase(s, tc);
  return tu_run(s);
}

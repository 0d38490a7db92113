/* check_sensor - model tables, names, row order, firing times, columns. */
#include "roadscan/util/error.h"
#include "roadscan/frame/frame.h"
#include "roadscan/sensor/sensor.h"
#include "testutil.h"

#include <math.h>

START_TEST(t_names_and_products) {
  ck_assert_int_eq(rs_model_from_name("VLP-16"), RS_MODEL_VLP16);
  ck_assert_int_eq(rs_model_from_name("vlp16"), RS_MODEL_VLP16);
  ck_assert_int_eq(rs_model_from_name("Puck Hi-Res"), RS_MODEL_PUCK_HIRES);
  ck_assert_int_eq(rs_model_from_name("hdl-32e"), RS_MODEL_HDL32E);
  ck_assert_int_eq(rs_model_from_name("VLP_32C"), RS_MODEL_VLP32C);
  ck_assert_int_eq(rs_model_from_name("alpha-prime"), RS_MODEL_VLS128);
  ck_assert_int_eq(rs_model_from_name("HDL-64E"), RS_MODEL_UNKNOWN);
  ck_assert_int_eq(rs_model_from_name(NULL), RS_MODEL_UNKNOWN);
  ck_assert_int_eq(rs_model_from_product(0x22), RS_MODEL_VLP16);
  ck_assert_int_eq(rs_model_from_product(0x24), RS_MODEL_PUCK_HIRES);
  ck_assert_int_eq(rs_model_from_product(0x21), RS_MODEL_HDL32E);
  ck_assert_int_eq(rs_model_from_product(0x28), RS_MODEL_VLP32C);
  ck_assert_int_eq(rs_model_from_product(0xA1), RS_MODEL_VLS128);
  ck_assert_int_eq(rs_model_from_product(0x99), RS_MODEL_UNKNOWN);
  ck_assert_int_eq(rs_sensor_init(&(rs_sensor_t){0}, RS_MODEL_UNKNOWN), RS_E_INVAL);
}
END_TEST

START_TEST(t_tables) {
  rs_sensor_t s;
  ck_assert_int_eq(rs_sensor_init(&s, RS_MODEL_VLP16), RS_OK);
  ck_assert_int_eq(s.lasers, 16);
  ck_assert_float_eq_tol(s.elevation_deg[0], -15.0, 1e-6);
  ck_assert_float_eq_tol(s.elevation_deg[15], 15.0, 1e-6);
  ck_assert_float_eq_tol(s.dist_res_m, 0.002, 1e-9);
  /* documented VLP-16 vertical offset of laser 0: 11.2 mm */
  ck_assert_float_eq_tol(s.vert_offset_m[0], 0.0112, 2e-4);
  ck_assert_int_eq(rs_sensor_init(&s, RS_MODEL_VLP32C), RS_OK);
  ck_assert_float_eq_tol(s.elevation_deg[0], -25.0, 1e-6);
  ck_assert_float_eq_tol(s.azimuth_offset_deg[0], 1.4, 1e-6);
  ck_assert_float_eq_tol(s.azimuth_offset_deg[1], -4.2, 1e-6);
  ck_assert_float_eq_tol(s.elevation_deg[29], 15.0, 1e-6);
  ck_assert_float_eq_tol(s.dist_res_m, 0.004, 1e-9);
  ck_assert_int_eq(rs_sensor_init(&s, RS_MODEL_VLS128), RS_OK);
  ck_assert_int_eq(s.lasers, 128);
  ck_assert_float_eq_tol(s.elevation_deg[36], -25.0, 1e-6);
  ck_assert_float_eq_tol(s.elevation_deg[59], 15.0, 1e-6);
  ck_assert_float_eq_tol(s.azimuth_offset_deg[0], 6.354, 1e-6);
  ck_assert_float_eq_tol(s.azimuth_offset_deg[15], -6.354, 1e-6);
  ck_assert_int_eq(rs_sensor_init(&s, RS_MODEL_HDL32E), RS_OK);
  ck_assert_float_eq_tol(s.elevation_deg[0], -30.67, 1e-4);
  ck_assert_float_eq_tol(s.elevation_deg[31], 10.67, 1e-4);
  ck_assert_int_eq(rs_sensor_init(&s, RS_MODEL_PUCK_HIRES), RS_OK);
  ck_assert_float_eq_tol(s.elevation_deg[0], -10.0, 1e-6);
  ck_assert_float_eq_tol(s.elevation_deg[15], 10.0, 1e-6);
}
END_TEST

START_TEST(t_row_order) {
  for (int m = RS_MODEL_VLP16; m < RS_MODEL_COUNT; m++) {
    rs_sensor_t s;
    rs_sensor_init(&s, (rs_model_t)m);
    bool seen[RS_MAX_LASERS] = {false};
    for (int r = 0; r < s.lasers; r++) {
      int l = s.laser_of_row[r];
      ck_assert(!seen[l]);
      seen[l] = true;
      ck_assert_int_eq(s.row_of_laser[l], r);
      if (r > 0) ck_assert(s.elevation_deg[s.laser_of_row[r - 1]] <= s.elevation_deg[l]);
    }
  }
  rs_sensor_t s;
  rs_sensor_init(&s, RS_MODEL_VLP16);
  ck_assert_int_eq(s.laser_of_row[0], 0);  /* -15 */
  ck_assert_int_eq(s.laser_of_row[1], 2);  /* -13 */
  ck_assert_int_eq(s.laser_of_row[15], 15); /* +15 */
  rs_sensor_init(&s, RS_MODEL_VLS128);
  ck_assert_int_eq(s.laser_of_row[0], 36); /* -25 */
  ck_assert_int_eq(s.laser_of_row[127], 59); /* +15 */
}
END_TEST

START_TEST(t_firing_times) {
  rs_sensor_t s;
  int laser;
  float t;
  rs_sensor_init(&s, RS_MODEL_VLP16);
  rs_sensor_record(&s, 0, 17, &laser, &t);
  ck_assert_int_eq(laser, 1);
  ck_assert_float_eq_tol(t, 55.296 + 2.304, 1e-3);
  rs_sensor_init(&s, RS_MODEL_HDL32E);
  rs_sensor_record(&s, 0, 31, &laser, &t);
  ck_assert_int_eq(laser, 31);
  ck_assert_float_eq_tol(t, 31 * 1.152, 1e-3);
  rs_sensor_init(&s, RS_MODEL_VLP32C);
  rs_sensor_record(&s, 0, 31, &laser, &t);
  ck_assert_int_eq(laser, 31);
  ck_assert_float_eq_tol(t, 15 * 2.304, 1e-3);
  rs_sensor_init(&s, RS_MODEL_VLS128);
  rs_sensor_record(&s, 3, 31, &laser, &t);
  ck_assert_int_eq(laser, 127);
  ck_assert_float_eq_tol(t, 16 * 2.665, 1e-3); /* group 15 + the idle slot after group 8 */
  rs_sensor_record(&s, 1, 0, &laser, &t);
  ck_assert_int_eq(laser, 32);
  ck_assert_float_eq_tol(t, 4 * 2.665, 1e-3);
}
END_TEST

START_TEST(t_columns) {
  /* VLP-16 at 10 Hz fires every 55.296 us: 1808.4 firings per turn */
  ck_assert_int_eq(rs_frame_columns_for(rs_model_info(RS_MODEL_VLP16), 10.0), 1820);
  ck_assert_int_eq(rs_frame_columns_for(rs_model_info(RS_MODEL_VLP16), 20.0), 910);
  /* HDL-32E at 10 Hz: 2170 firings */
  ck_assert_int_eq(rs_frame_columns_for(rs_model_info(RS_MODEL_HDL32E), 10.0), 2190);
  ck_assert_int_eq(rs_frame_columns_for(rs_model_info(RS_MODEL_HDL32E), 5.0), 4370);
  ck_assert_int_eq(rs_frame_columns_for(rs_model_info(RS_MODEL_HDL32E), 4.0), RS_MAX_COLS);
  ck_assert_int_eq(rs_frame_columns_for(rs_model_info(RS_MODEL_VLS128), 10.0), 1890);
}
END_TEST

START_TEST(t_errors) {
  ck_assert_str_eq(rs_strerror(RS_OK), "success");
  ck_assert_str_eq(rs_err_key(RS_E_BLOCK_FLAG), "block-flag");
  ck_assert_int_eq(rs_err_index(RS_E_INVAL), 0);
  ck_assert_int_eq(rs_err_from_index(rs_err_index(RS_E_THREAD)), RS_E_THREAD);
  ck_assert_int_eq(rs_err_index(5), -1);
  ck_assert_str_eq(rs_strerror(12345), "unknown error");
}
END_TEST

int main(void) {
  Suite *s = suite_create("sensor");
  TCase *tc = tcase_create("core");
  tcase_add_test(tc, t_names_and_products);
  tcase_add_test(tc, t_tables);
  tcase_add_test(tc, t_row_order);
  tcase_add_test(tc, t_firing_times);
  tcase_add_test(tc, t_columns);
  tcase_add_test(tc, t_errors);
  suite_add_tcase(s, tc);
  return tu_run(s);
}

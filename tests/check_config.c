/* check_config - option values: numbers within ranges, whole numbers,
 * booleans, sensor models, and the messages that name the option. */
#include "roadscan/util/config.h"
#include "roadscan/util/error.h"
#include "testutil.h"

#include <math.h>
#include <string.h>

static char err[RS_ERRMSG_SIZE];

START_TEST(t_double) {
  double v = -1;
  ck_assert_int_eq(rs_cfg_double("--speed", "2.5", 0.0, 100.0, &v, err, sizeof err), RS_OK);
  ck_assert_double_eq(v, 2.5);
  ck_assert_int_eq(rs_cfg_double("--speed", "1e1", 0.0, 100.0, &v, err, sizeof err), RS_OK);
  ck_assert_double_eq(v, 10.0);
  static const char *bad[] = {"abc", "", "2.5x", "nan", "inf", "-1", "101", "3 "};
  for (size_t i = 0; i < sizeof bad / sizeof bad[0]; i++) {
    v = 7.0;
    ck_assert_msg(rs_cfg_double("--speed", bad[i], 0.0, 100.0, &v, err, sizeof err) == RS_E_INVAL, "'%s'", bad[i]);
    ck_assert_ptr_nonnull(strstr(err, "--speed"));
    ck_assert_double_eq(v, 7.0); /* untouched */
  }
  ck_assert_int_eq(rs_cfg_double("--speed", "abc", 0.0, 100.0, &v, err, sizeof err), RS_E_INVAL);
  ck_assert_ptr_nonnull(strstr(err, "'abc' is not a number"));
  ck_assert_int_eq(rs_cfg_double("--speed", "101", 0.0, 100.0, &v, err, sizeof err), RS_E_INVAL);
  ck_assert_ptr_nonnull(strstr(err, "out of range"));
}
END_TEST

START_TEST(t_long) {
  long v = -1;
  ck_assert_int_eq(rs_cfg_long("--port", "2368", 1, 65535, &v, err, sizeof err), RS_OK);
  ck_assert_int_eq(v, 2368);
  static const char *bad[] = {"0", "65536", "12.5", "x", "", "99999999999999999999"};
  for (size_t i = 0; i < sizeof bad / sizeof bad[0]; i++) {
    ck_assert_msg(rs_cfg_long("--port", bad[i], 1, 65535, &v, err, sizeof err) == RS_E_INVAL, "'%s'", bad[i]);
    ck_assert_ptr_nonnull(strstr(err, "--port"));
  }
  ck_assert_int_eq(v, 2368);
}
END_TEST

START_TEST(t_bool_and_model) {
  bool b = false;
  static const char *yes[] = {"true", "YES", "On", "1"}, *no[] = {"false", "no", "OFF", "0"};
  for (int i = 0; i < 4; i++) {
    ck_assert_int_eq(rs_cfg_bool("loop", yes[i], &b, err, sizeof err), RS_OK);
    ck_assert(b);
    ck_assert_int_eq(rs_cfg_bool("loop", no[i], &b, err, sizeof err), RS_OK);
    ck_assert(!b);
  }
  ck_assert_int_eq(rs_cfg_bool("loop", "maybe", &b, err, sizeof err), RS_E_INVAL);
  ck_assert_ptr_nonnull(strstr(err, "loop"));
  rs_model_t m = RS_MODEL_UNKNOWN;
  ck_assert_int_eq(rs_cfg_model("--model", "VLP-16", &m, err, sizeof err), RS_OK);
  ck_assert_int_eq(m, RS_MODEL_VLP16);
  ck_assert_int_eq(rs_cfg_model("--model", "HDL-32E", &m, err, sizeof err), RS_OK);
  ck_assert_int_eq(m, RS_MODEL_HDL32E);
  ck_assert_int_eq(rs_cfg_model("--model", "HDL-64", &m, err, sizeof err), RS_E_INVAL);
  ck_assert_ptr_nonnull(strstr(err, "'HDL-64'"));
  ck_assert_ptr_nonnull(strstr(err, "VLP-32C")); /* the known ones are named */
  ck_assert_int_eq(m, RS_MODEL_HDL32E);
}
END_TEST

int main(void) {
  Suite *s = suite_create("config");
  TCase *tc = tcase_create("values");
  tcase_add_test(tc, t_double);
  tcase_add_test(tc, t_long);
  tcase_add_test(tc, t_bool_and_model);
  suite_add_tcase(s, tc);
  return tu_run(s);
}

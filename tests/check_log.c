/* check_log - messages on stderr: "ident: message", formatted, one line
 * each, long ones cut at RS_LOG_MSG_SIZE - 1 characters; the ident set by rs_log_open. */
#include "roadscan/util/log.h"
#include "testutil.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

/* what rs_log writes to stderr while fn runs */
static char *captured(void (*fn)(void)) {
  fflush(stderr);
  const char *path = tu_tmp("log-capture.txt");
  int saved = dup(2);
  FILE *f = freopen(path, "w", stderr);
  ck_assert_ptr_nonnull(f);
  fn();
  fflush(stderr);
  dup2(saved, 2);
  close(saved);
  f = fopen(path, "r");
  static char buf[4096];
  size_t n = fread(buf, 1, sizeof buf - 1, f);
  buf[n] = '\0';
  fclose(f);
  return buf;
}

static void two_messages(void) {
  rs_log_open("roadscand", false);
  rs_log(RS_LOG_WARN, "the sensor turns at %.2f Hz", 9.97);
  rs_log(RS_LOG_ERR, "%s: %d", "errors", 3);
}

static void a_long_message(void) {
  static char big[RS_LOG_MSG_SIZE + 1000];
  memset(big, 'x', sizeof big - 1);
  rs_log(RS_LOG_INFO, "%s", big);
}

START_TEST(t_stderr_lines) {
  const char *out = captured(two_messages);
  ck_assert_str_eq(out, "roadscand: the sensor turns at 9.97 Hz\nroadscand: errors: 3\n");
  out = captured(a_long_message);
  ck_assert_uint_eq(strlen(out), strlen("roadscand: ") + RS_LOG_MSG_SIZE - 1 + 1); /* cut, one line */
  ck_assert_int_eq(out[strlen(out) - 1], '\n');
}
END_TEST

int main(void) {
  Suite *s = suite_create("log");
  TCase *tc = tcase_create("core");
  tcase_add_test(tc, t_stderr_lines);
  suite_add_tcase(s, tc);
  return tu_run(s);
}

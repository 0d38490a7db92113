/* check_thread - threads placed for real time (thread.h): pinned to a CPU
 * they then run on alone, at the SCHED_FIFO priority asked (or refused with
 * a message naming CAP_SYS_NICE and RLIMIT_RTPRIO when the process may not),
 * CPUs the process may not use and priorities out of range refused, and what
 * the kernel reports read back. */
#define _GNU_SOURCE
#include "roadscan/util/error.h"
#include "roadscan/util/thread.h"
#include "testutil.h"

#include <pthread.h>
#include <sched.h>
#include <stdio.h>
#include <string.h>
#include <sys/resource.h>

typedef struct {
  int cpus, cpu, policy, priority;
} seen_t;

/* what the thread finds itself running as */
static void *look(void *arg) {
  seen_t *s = arg;
  cpu_set_t set;
  CPU_ZERO(&set);
  pthread_getaffinity_np(pthread_self(), sizeof set, &set);
  s->cpus = CPU_COUNT(&set);
  s->cpu = sched_getcpu();
  struct sched_param sp;
  pthread_getschedparam(pthread_self(), &s->policy, &sp);
  s->priority = sp.sched_priority;
  return NULL;
}

/* the last CPU this process may run on */
static int last_allowed(void) {
  cpu_set_t set;
  CPU_ZERO(&set);
  ck_assert_int_eq(sched_getaffinity(0, sizeof set, &set), 0);
  int last = -1;
  for (int c = 0; c <= RS_THREAD_CPU_MAX; c++)
    if (CPU_ISSET(c, &set)) last = c;
  ck_assert_int_ge(last, 0);
  return last;
}

START_TEST(t_pinned) {
  char err[RS_ERRMSG_SIZE] = "";
  const int cpu = last_allowed();
  const rs_thread_cfg_t cfg = {.pin = true, .cpu = cpu, .priority = 0};
  pthread_t t;
  seen_t s = {0, -1, -1, -1};
  ck_assert_int_eq(rs_thread_create(&t, &cfg, "the test thread", look, &s, err, sizeof err), RS_OK);
  pthread_join(t, NULL);
  ck_assert_int_eq(s.cpus, 1);
  ck_assert_int_eq(s.cpu, cpu);
  ck_assert_int_eq(s.policy, SCHED_OTHER);
  /* the calling thread placed, and described */
  ck_assert_int_eq(rs_thread_place(&cfg, "the test", err, sizeof err), RS_OK);
  char d[160];
  rs_thread_describe(pthread_self(), d, sizeof d);
  char want[64];
  snprintf(want, sizeof want, "CPU %d, normal scheduling", cpu);
  ck_assert_str_eq(d, want);
  /* no placement: wherever */
  seen_t u = {0, -1, -1, -1};
  ck_assert_int_eq(rs_thread_create(&t, NULL, "the test thread", look, &u, err, sizeof err), RS_OK);
  pthread_join(t, NULL);
  ck_assert_int_ge(u.cpus, 1); /* inherits the caller's (one CPU now) */
}
END_TEST

START_TEST(t_realtime) {
  char err[RS_ERRMSG_SIZE] = "";
  const rs_thread_cfg_t cfg = {.pin = false, .cpu = 0, .priority = 7};
  pthread_t t;
  seen_t s = {0, -1, -1, -1};
  const int rc = rs_thread_create(&t, &cfg, "the test thread", look, &s, err, sizeof err);
  if (rc == RS_OK) {
    pthread_join(t, NULL);
    ck_assert_int_eq(s.policy, SCHED_FIFO);
    ck_assert_int_eq(s.priority, 7);
  } else { /* not permitted here: refused with the way out */
    struct rlimit rl;
    getrlimit(RLIMIT_RTPRIO, &rl);
    ck_assert_int_lt((long long)rl.rlim_cur, 7);
    ck_assert_int_eq(rc, RS_E_PERM);
    ck_assert_ptr_nonnull(strstr(err, "the test thread: SCHED_FIFO priority 7 is not permitted"));
    ck_assert_ptr_nonnull(strstr(err, "CAP_SYS_NICE"));
    ck_assert_ptr_nonnull(strstr(err, "LimitRTPRIO=7"));
  }
}
END_TEST

START_TEST(t_refused) {
  char err[RS_ERRMSG_SIZE] = "";
  pthread_t t;
  seen_t s;
  const rs_thread_cfg_t neg = {.pin = true, .cpu = -1}, big = {.pin = true, .cpu = RS_THREAD_CPU_MAX + 1},
                        p99 = {.priority = 99}, pneg = {.priority = -1};
  ck_assert_int_eq(rs_thread_check(&neg, "x", err, sizeof err), RS_E_INVAL);
  ck_assert_ptr_nonnull(strstr(err, "x: CPU -1 is not a CPU number"));
  ck_assert_int_eq(rs_thread_check(&big, "x", err, sizeof err), RS_E_INVAL);
  ck_assert_int_eq(rs_thread_check(&p99, "x", err, sizeof err), RS_E_INVAL);
  ck_assert_ptr_nonnull(strstr(err, "priority 99 is not 0 (normal) or 1-98"));
  ck_assert_int_eq(rs_thread_check(&pneg, "x", err, sizeof err), RS_E_INVAL);
  /* a CPU outside the process's mask: refused before any thread runs, naming those it may use */
  ck_assert_int_lt(last_allowed(), RS_THREAD_CPU_MAX);
  const rs_thread_cfg_t out = {.pin = true, .cpu = RS_THREAD_CPU_MAX};
  s.cpus = -5;
  ck_assert_int_eq(rs_thread_create(&t, &out, "the test thread", look, &s, err, sizeof err), RS_E_INVAL);
  ck_assert_ptr_nonnull(strstr(err, "the test thread: CPU 1023 is not one this process may run on (it may: "));
  ck_assert_int_eq(s.cpus, -5); /* never ran */
  ck_assert_int_eq(rs_thread_place(&out, "the test", err, sizeof err), RS_E_INVAL);
  ck_assert_int_eq(rs_thread_check(NULL, "x", err, sizeof err), RS_OK);
}
END_TEST

int main(void) {
  Suite *s = suite_create("thread");
  TCase *tc = tcase_create("core");
  tcase_add_test(tc, t_pinned);
  tcase_add_test(tc, t_realtime);
  tcase_add_test(tc, t_refused);
  suite_add_tcase(s, tc);
  return tu_run(s);
}

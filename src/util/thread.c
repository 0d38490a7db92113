/* thread.c - threads pinned to a CPU at a SCHED_FIFO priority (thread.h).
 * The CPU sets and pthread_attr_setaffinity_np are GNU extensions: this file
 * alone asks for them. Called at start-up only, by whichever thread starts
 * or places a thread. */
#define _GNU_SOURCE
#include "roadscan/util/thread.h"

#include "roadscan/util/error.h"

#include <errno.h>
#include <sched.h>
#include <stdio.h>
#include <string.h>
#include <sys/resource.h>

_Static_assert(RS_THREAD_CPU_MAX < CPU_SETSIZE, "a CPU number must fit a cpu_set_t");

/* the CPUs of set as runs ("0-3,6"), written at buf + k (of n): the new end */
static size_t cpu_runs(const cpu_set_t *set, char *buf, size_t k, size_t n) {
  int first = -1;
  bool any = false;
  for (int c = 0; c <= RS_THREAD_CPU_MAX + 1 && k + 12 < n; c++) {
    const bool in = c <= RS_THREAD_CPU_MAX && CPU_ISSET(c, set);
    if (in && first < 0) first = c;
    if (!in && first >= 0) {
      k += (size_t)(c - 1 > first ? snprintf(buf + k, n - k, "%s%d-%d", any ? "," : "", first, c - 1)
                                  : snprintf(buf + k, n - k, "%s%d", any ? "," : "", first));
      any = true;
      first = -1;
    }
  }
  return k;
}

/* the set of CPU cpu alone */
static cpu_set_t one_cpu(int cpu) {
  cpu_set_t one;
  CPU_ZERO(&one);
  CPU_SET(cpu, &one);
  return one;
}

int rs_thread_check(const rs_thread_cfg_t *cfg, const char *what, char *err, size_t n) {
  if (cfg == NULL) return RS_OK;
  if (cfg->priority < 0 || cfg->priority > RS_THREAD_PRIO_MAX) {
    snprintf(err, n, "%s: priority %d is not 0 (normal) or 1-%d (SCHED_FIFO)", what, cfg->priority, RS_THREAD_PRIO_MAX);
    return RS_E_INVAL;
  }
  if (cfg->pin) {
    cpu_set_t allowed;
    CPU_ZERO(&allowed);
    if (cfg->cpu < 0 || cfg->cpu > RS_THREAD_CPU_MAX) {
      snprintf(err, n, "%s: CPU %d is not a CPU number (0-%d)", what, cfg->cpu, RS_THREAD_CPU_MAX);
      return RS_E_INVAL;
    }
    if (sched_getaffinity(0, sizeof allowed, &allowed) != 0) {
      snprintf(err, n, "%s: cannot read this process's CPUs: %s", what, strerror(errno));
      return RS_E_THREAD;
    }
    if (!CPU_ISSET(cfg->cpu, &allowed)) {
      char list[256] = "";
      cpu_runs(&allowed, list, 0, sizeof list);
      snprintf(err, n, "%s: CPU %d is not one this process may run on (it may: %s)", what, cfg->cpu, list);
      return RS_E_INVAL;
    }
  }
  if (cfg->priority > 0) {
    const int lo = sched_get_priority_min(SCHED_FIFO), hi = sched_get_priority_max(SCHED_FIFO);
    if (cfg->priority < lo || cfg->priority > hi) {
      snprintf(err, n, "%s: SCHED_FIFO priority %d is outside this system's %d-%d", what, cfg->priority, lo, hi);
      return RS_E_INVAL;
    }
  }
  return RS_OK;
}

/* err for a refusal by the kernel (errno e) of placing a thread as cfg says */
static int refused(const rs_thread_cfg_t *cfg, const char *what, int e, char *err, size_t n) {
  if (e == EPERM && cfg->priority > 0) {
    struct rlimit rl = {0, 0};
    getrlimit(RLIMIT_RTPRIO, &rl);
    snprintf(err, n,
             "%s: SCHED_FIFO priority %d is not permitted (needs CAP_SYS_NICE or an RLIMIT_RTPRIO of %d, it is "
             "%llu; systemd: LimitRTPRIO=%d and no RestrictRealtime=yes)",
             what, cfg->priority, cfg->priority, (unsigned long long)rl.rlim_cur, cfg->priority);
    return RS_E_PERM;
  }
  if (e == EINVAL && cfg->pin) {
    snprintf(err, n, "%s: CPU %d refused by the kernel (offline, or outside this process's cpuset)", what, cfg->cpu);
    return RS_E_INVAL;
  }
  if (cfg->pin)
    snprintf(err, n, "%s: cannot start it on CPU %d at priority %d: %s", what, cfg->cpu, cfg->priority, strerror(e));
  else
    snprintf(err, n, "%s: cannot start it at priority %d: %s", what, cfg->priority, strerror(e));
  return RS_E_THREAD;
}

int rs_thread_create(pthread_t *t, const rs_thread_cfg_t *cfg, const char *what, void *(*fn)(void *), void *arg,
                     char *err, size_t n) {
  const rs_thread_cfg_t none = {false, 0, 0};
  if (cfg == NULL) cfg = &none;
  int rc = rs_thread_check(cfg, what, err, n);
  if (rc != RS_OK) return rc;
  pthread_attr_t attr;
  if (pthread_attr_init(&attr) != 0) {
    snprintf(err, n, "%s: cannot set up the thread's attributes", what);
    return RS_E_THREAD;
  }
  int e = 0;
  if (cfg->pin) {
    const cpu_set_t one = one_cpu(cfg->cpu);
    e = pthread_attr_setaffinity_np(&attr, sizeof one, &one);
  }
  if (e == 0 && cfg->priority > 0) {
    const struct sched_param sp = {.sched_priority = cfg->priority};
    e = pthread_attr_setinheritsched(&attr, PTHREAD_EXPLICIT_SCHED);
    if (e == 0) e = pthread_attr_setschedpolicy(&attr, SCHED_FIFO);
    if (e == 0) e = pthread_attr_setschedparam(&attr, &sp);
  }
  if (e == 0) e = pthread_create(t, &attr, fn, arg);
  pthread_attr_destroy(&attr);
  return e == 0 ? RS_OK : refused(cfg, what, e, err, n);
}

int rs_thread_place(const rs_thread_cfg_t *cfg, const char *what, char *err, size_t n) {
  int rc = rs_thread_check(cfg, what, err, n);
  if (rc != RS_OK || cfg == NULL) return rc;
  if (cfg->pin) {
    const cpu_set_t one = one_cpu(cfg->cpu);
    const int e = pthread_setaffinity_np(pthread_self(), sizeof one, &one);
    if (e != 0) return refused(cfg, what, e, err, n);
  }
  if (cfg->priority > 0) {
    const struct sched_param sp = {.sched_priority = cfg->priority};
    const int e = pthread_setschedparam(pthread_self(), SCHED_FIFO, &sp);
    if (e != 0) return refused(cfg, what, e, err, n);
  }
  return RS_OK;
}

void rs_thread_describe(pthread_t t, char *buf, size_t n) {
  cpu_set_t set;
  CPU_ZERO(&set);
  size_t k;
  if (pthread_getaffinity_np(t, sizeof set, &set) == 0)
    k = cpu_runs(&set, buf, (size_t)snprintf(buf, n, "CPU%s ", CPU_COUNT(&set) == 1 ? "" : "s"), n);
  else
    k = (size_t)snprintf(buf, n, "CPUs unknown");
  int policy = SCHED_OTHER;
  struct sched_param sp = {0};
  if (k >= n || pthread_getschedparam(t, &policy, &sp) != 0) return;
  if (policy == SCHED_OTHER)
    snprintf(buf + k, n - k, ", normal scheduling");
  else
    snprintf(buf + k, n - k, ", %s %d", policy == SCHED_FIFO ? "SCHED_FIFO" : policy == SCHED_RR ? "SCHED_RR" : "policy",
             sp.sched_priority);
}

/* thread.h - threads placed for real time: pinned to one CPU, scheduled
 * SCHED_FIFO at a fixed priority.
 *
 * On an edge box the daemon's two threads share the cores with everything
 * else the box runs; a frame's processing that is preempted or moved to
 * another core mid-frame is late by however long the other work takes (the
 * tracker stage alone: p99 207-227 us pinned and SCHED_FIFO, 212-371 us
 * not, the same build, docs/operations.md). rs_thread_create starts a thread
 * with its placement set before it runs (pthread attributes: nothing of it
 * runs anywhere else); rs_thread_place sets the calling thread's (the
 * benchmark). Both refuse with a message that names what is missing:
 * SCHED_FIFO needs CAP_SYS_NICE or an RLIMIT_RTPRIO of the priority (systemd:
 * LimitRTPRIO=, and no RestrictRealtime=), a CPU must be one the process may
 * run on (its affinity mask: taskset, cgroups' cpusets).
 *
 * No allocation, no hidden state: the caller's configuration only. */
#ifndef ROADSCAN_THREAD_H
#define ROADSCAN_THREAD_H

#include <pthread.h>
#include <stdbool.h>
#include <stddef.h>

#define RS_THREAD_CPU_MAX 1023   /* the highest CPU number accepted */
#define RS_THREAD_PRIO_MAX 98    /* SCHED_FIFO priorities 1..98 (99 is the kernel's watchdogs') */

typedef struct {
  bool pin;                      /* run on `cpu` only (false: wherever the scheduler puts it) */
  int cpu;                       /* 0..RS_THREAD_CPU_MAX */
  int priority;                  /* 0: the normal scheduler; 1..RS_THREAD_PRIO_MAX: SCHED_FIFO at it */
} rs_thread_cfg_t;

/* Whether cfg can be had by this process: the CPU in its affinity mask, the
 * priority within what it may set (CAP_SYS_NICE or RLIMIT_RTPRIO). RS_OK, or
 * RS_E_INVAL (a CPU not allowed, a priority out of range) / RS_E_PERM (not
 * permitted) with err naming the problem and the way out. */
int rs_thread_check(const rs_thread_cfg_t *cfg, const char *what, char *err, size_t n);

/* Starts fn(arg) placed as cfg says (NULL: as the caller's default). RS_OK,
 * or an error with err set (the thread is not started). */
int rs_thread_create(pthread_t *t, const rs_thread_cfg_t *cfg, const char *what, void *(*fn)(void *), void *arg,
                     char *err, size_t n);

/* Places the calling thread as cfg says. RS_OK, or an error with err set. */
int rs_thread_place(const rs_thread_cfg_t *cfg, const char *what, char *err, size_t n);

/* What thread t runs as, read back from the kernel: "CPU 2, SCHED_FIFO 20",
 * "CPUs 0-3, normal scheduling", ... */
void rs_thread_describe(pthread_t t, char *buf, size_t n);

#endif

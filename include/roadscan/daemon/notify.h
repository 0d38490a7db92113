/* notify.h - the systemd service protocol, without libsystemd: readiness,
 * status, stopping and the watchdog (sd_notify(3): datagrams of "KEY=VALUE"
 * lines to the AF_UNIX socket named by $NOTIFY_SOCKET).
 *
 * rs_notify_init reads the environment once at start-up (main thread); with
 * no $NOTIFY_SOCKET every call does nothing. The watchdog interval is half of
 * $WATCHDOG_USEC (ignored when $WATCHDOG_PID names another process). Who
 * calls what: the main thread sends READY and STOPPING; the processing thread
 * feeds the watchdog (rs_notify_watchdog: at most one datagram per interval)
 * and sends STATUS lines, so a hung processing thread stops the feeding and
 * systemd restarts the service. The socket is the caller's (one per process). */
#ifndef ROADSCAN_NOTIFY_H
#define ROADSCAN_NOTIFY_H

#include <stdatomic.h>
#include <stdbool.h>
#include <stdint.h>

typedef struct {
  int fd;                     /* -1: not under a service manager */
  char path[108];             /* sun_path; a leading '@' is the abstract namespace */
  int64_t watchdog_ns;        /* feeding interval (half the timeout), 0 = no watchdog */
  int64_t last_fed_ns;
  _Atomic bool ready;         /* READY=1 sent (main thread): the watchdog is fed from then on */
  _Atomic uint64_t sent, failed; /* datagrams (both threads send) */
} rs_notify_t;

/* From the environment ($NOTIFY_SOCKET, $WATCHDOG_USEC, $WATCHDOG_PID).
 * Returns false with err set when $NOTIFY_SOCKET is set but unusable. */
bool rs_notify_init(rs_notify_t *n, char *err, unsigned errlen);
void rs_notify_deinit(rs_notify_t *n);
/* Sends one message ("READY=1", "STATUS=...", "STOPPING=1"); false when it
 * could not be sent (counted). No-op without a manager. */
bool rs_notify_send(rs_notify_t *n, const char *msg);
/* READY=1 and a status line (main thread, once the service works). */
bool rs_notify_ready(rs_notify_t *n, const char *status);
/* WATCHDOG=1 when the interval has passed since the last one (now_ns on
 * CLOCK_MONOTONIC), from READY on. No-op without a watchdog. */
void rs_notify_watchdog(rs_notify_t *n, int64_t now_ns);

#endif

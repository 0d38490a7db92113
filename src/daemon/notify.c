/* notify.c - see notify.h. */
#include "roadscan/daemon/notify.h"

#include <errno.h>
#include <fcntl.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/socket.h>
#include <sys/un.h>
#include <unistd.h>

bool rs_notify_init(rs_notify_t *n, char *err, unsigned errlen) {
  memset(n, 0, sizeof *n);
  atomic_init(&n->ready, false);
  atomic_init(&n->sent, 0);
  atomic_init(&n->failed, 0);
  n->fd = -1;
  const char *sock = getenv("NOTIFY_SOCKET");
  if (sock == NULL || sock[0] == '\0') return true;
  if ((sock[0] != '/' && sock[0] != '@') || strlen(sock) >= sizeof n->path) {
    snprintf(err, errlen, "NOTIFY_SOCKET '%s' is not an absolute path or an abstract name that fits a socket address",
             sock);
    return false;
  }
  snprintf(n->path, sizeof n->path, "%s", sock);
  n->fd = socket(AF_UNIX, SOCK_DGRAM | SOCK_CLOEXEC, 0);
  if (n->fd < 0) {
    snprintf(err, errlen, "NOTIFY_SOCKET: socket: %s", strerror(errno));
    return false;
  }
  const char *usec = getenv("WATCHDOG_USEC"), *pid = getenv("WATCHDOG_PID");
  char *end = NULL;
  const long long us = usec ? strtoll(usec, &end, 10) : 0;
  const bool ours = pid == NULL || strtol(pid, NULL, 10) == (long)getpid();
  if (usec && (end == usec || *end != '\0' || us <= 0)) {
    snprintf(err, errlen, "WATCHDOG_USEC '%s' is not a positive number of microseconds", usec);
    rs_notify_deinit(n);
    return false;
  }
  if (us > 0 && ours) n->watchdog_ns = us * 1000 / 2;
  return true;
}

void rs_notify_deinit(rs_notify_t *n) {
  if (n->fd >= 0) close(n->fd);
  n->fd = -1;
  n->watchdog_ns = 0;
}

bool rs_notify_send(rs_notify_t *n, const char *msg) {
  if (n->fd < 0) return true;
  struct sockaddr_un a;
  memset(&a, 0, sizeof a);
  a.sun_family = AF_UNIX;
  size_t len = strlen(n->path);
  memcpy(a.sun_path, n->path, len);
  if (n->path[0] == '@') a.sun_path[0] = '\0'; /* abstract: no terminating NUL in the length */
  const socklen_t alen = (socklen_t)(offsetof(struct sockaddr_un, sun_path) + len);
  /* never waits: a full queue at the manager loses this datagram (counted), not the processing thread's time */
  if (sendto(n->fd, msg, strlen(msg), MSG_NOSIGNAL | MSG_DONTWAIT, (const struct sockaddr *)&a, alen) < 0) {
    n->failed++;
    return false;
  }
  n->sent++;
  return true;
}

bool rs_notify_ready(rs_notify_t *n, const char *status) {
  char msg[256];
  snprintf(msg, sizeof msg, "READY=1\nSTATUS=%s", status);
  const bool ok = rs_notify_send(n, msg);
  atomic_store(&n->ready, true);
  return ok;
}

void rs_notify_watchdog(rs_notify_t *n, int64_t now_ns) {
  if (n->watchdog_ns <= 0 || !atomic_load(&n->ready) || now_ns - n->last_fed_ns < n->watchdog_ns) return;
  n->last_fed_ns = now_ns;
  rs_notify_send(n, "WATCHDOG=1");
}

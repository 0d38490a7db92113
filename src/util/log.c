/* log.c - stderr or syslog. The ident and the choice are written once by
 * the main thread before any other thread starts. */
#include "roadscan/util/log.h"

#include <stdarg.h>
#include <stdio.h>
#include <syslog.h>

static const char *log_ident = "roadscan";
static bool log_syslog;

void rs_log_open(const char *ident, bool use_syslog) {
  log_ident = ident;
  log_syslog = use_syslog;
  if (use_syslog) openlog(ident, LOG_PID, LOG_DAEMON);
}

void rs_log_close(void) {
  if (log_syslog) closelog();
  log_syslog = false;
}

void rs_log(rs_log_level_t level, const char *fmt, ...) {
  char msg[RS_LOG_MSG_SIZE];
  va_list ap;
  va_start(ap, fmt);
  vsnprintf(msg, sizeof msg, fmt, ap);
  va_end(ap);
  if (log_syslog)
    syslog((int)level, "%s", msg);
  else
    fprintf(stderr, "%s: %s\n", log_ident, msg);
}

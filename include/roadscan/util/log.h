/* log.h - the daemon's messages: to stderr, or to syslog when it runs as a
 * service. Set up once at start-up (rs_log_open), then callable from any
 * thread (one fprintf or syslog call per message, both thread-safe). */
#ifndef ROADSCAN_LOG_H
#define ROADSCAN_LOG_H

#include "roadscan/util/error.h"

#include <stdbool.h>

/* a message's longest (with its NUL): an error message and what is said around it; longer ones are cut */
#define RS_LOG_MSG_SIZE (RS_ERRMSG_SIZE + 256)

typedef enum { RS_LOG_ERR = 3, RS_LOG_WARN = 4, RS_LOG_INFO = 6 } rs_log_level_t;

/* use_syslog: openlog(ident, LOG_PID, LOG_DAEMON); otherwise "ident: msg" on stderr. */
void rs_log_open(const char *ident, bool use_syslog);
void rs_log_close(void);
void rs_log(rs_log_level_t level, const char *fmt, ...) __attribute__((format(printf, 2, 3)));

#endif

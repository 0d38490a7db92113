/* lcmcheck.h - untrusted LCM bytes checked before a generated decoder sees them.
 *
 * LCM's generated C decoders trust the wire: a string's length is malloc'ed
 * as read (a negative one crashes), its terminating NUL is not checked (a
 * string without one is read past its end), an array's element count is
 * allocated as read. Every consumer of roadscan's messages checks the bytes
 * with these first: the fingerprint of the type, every string (length from
 * 1 to RS_LCMCHECK_STRING_MAX, within the message, NUL-terminated, no NUL
 * before it), every array count (not negative, its elements within the
 * message), and nothing left over. Pure functions; any thread. */
#ifndef ROADSCAN_LCMCHECK_H
#define ROADSCAN_LCMCHECK_H

#include <stdbool.h>
#include <stddef.h>

#define RS_LCMCHECK_STRING_MAX 4096

typedef enum {
  RS_LCM_OBJECT_LIST,
  RS_LCM_FRAME_STATS,
  RS_LCM_TRACK_LIST,
  RS_LCM_TRACK_END,
  RS_LCM_COUNTS,
  RS_LCM_CROSSING,
  RS_LCM_TYPES
} rs_lcm_type_t;

/* true when data (len bytes) is a well-formed encoding of the type; else
 * false with err naming the first problem (its byte offset). */
bool rs_lcm_check(rs_lcm_type_t type, const void *data, int len, char *err, size_t n);
const char *rs_lcm_type_name(rs_lcm_type_t type);

#endif

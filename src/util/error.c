/* error.c - messages and keys of the error table (pure, no state). */
#include "roadscan/util/error.h"

#include <stddef.h>

static const char *const msgs[] = {
#define RS_ERR_MSG(name, key, msg) msg,
    RS_ERRNO_MAP(RS_ERR_MSG)
#undef RS_ERR_MSG
};
static const char *const keys[] = {
#define RS_ERR_KEY(name, key, msg) key,
    RS_ERRNO_MAP(RS_ERR_KEY)
#undef RS_ERR_KEY
};

_Static_assert(sizeof(msgs) / sizeof(msgs[0]) == RS_ERR_COUNT, "error table size");

int rs_err_index(int code) {
  if (code <= RS_ERR_FIRST_ || code >= RS_ERR_END_) return -1;
  return code - RS_ERR_FIRST_ - 1;
}

int rs_err_from_index(int index) { return RS_ERR_FIRST_ + 1 + index; }

const char *rs_strerror(int code) {
  if (code == RS_OK) return "success";
  int i = rs_err_index(code);
  return i < 0 ? "unknown error" : msgs[i];
}

const char *rs_err_key(int code) {
  if (code == RS_OK) return "ok";
  int i = rs_err_index(code);
  return i < 0 ? "unknown" : keys[i];
}

/* fuzz_lcm - untrusted LCM bytes the way every consumer takes them: checked
 * (rs_lcm_check), then decoded by the generated decoder, which must read the
 * whole message. Input: a type selector byte, then the message. */
#include "fuzz.h"

#include "roadscan/output/lcmcheck.h"

#include <roadscan_counts_t.h>
#include <roadscan_frame_stats_t.h>
#include <roadscan_object_list_t.h>
#include <roadscan_track_end_t.h>
#include <roadscan_track_list_t.h>
#include <string.h>

#define DECODE(T, buf, len)                                                              \
  do {                                                                                   \
    T m;                                                                                 \
    memset(&m, 0, sizeof m);                                                             \
    if (T##_decode(buf, 0, len, &m) != len) abort(); /* checked, so it must decode whole */ \
    T##_decode_cleanup(&m);                                                              \
  } while (0)

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size) {
  if (size < 1 || size > (1 << 20)) return 0;
  const rs_lcm_type_t type = (rs_lcm_type_t)(data[0] % RS_LCM_TYPES);
  const int len = (int)size - 1;
  uint8_t *msg = malloc((size_t)len + 1);
  if (msg == NULL) return 0;
  memcpy(msg, data + 1, (size_t)len);
  char err[256];
  if (rs_lcm_check(type, msg, len, err, sizeof err)) {
    switch (type) {
    case RS_LCM_OBJECT_LIST: DECODE(roadscan_object_list_t, msg, len); break;
    case RS_LCM_FRAME_STATS: DECODE(roadscan_frame_stats_t, msg, len); break;
    case RS_LCM_TRACK_LIST: DECODE(roadscan_track_list_t, msg, len); break;
    case RS_LCM_TRACK_END: DECODE(roadscan_track_end_t, msg, len); break;
    case RS_LCM_COUNTS: DECODE(roadscan_counts_t, msg, len); break;
    default: break;
    }
  }
  free(msg);
  return 0;
}

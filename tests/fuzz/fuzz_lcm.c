/* fuzz_lcm - untrusted LCM bytes the way every consumer takes them: checked
 * (rs_lcm_check), then decoded by the generated decoder, which must read the
 * whole message, then turned into JSON as roadscan-bridge and roadscan-listen
 * --json do (src/output/json.c; text that is not UTF-8 is refused first).
 * Input: a type selector byte, then the message. */
#include "fuzz.h"

#include "roadscan/output/json.h"
#include "roadscan/output/lcmcheck.h"

#include <roadscan_counts_t.h>
#include <roadscan_crossing_t.h>
#include <roadscan_frame_stats_t.h>
#include <roadscan_object_list_t.h>
#include <roadscan_track_end_t.h>
#include <roadscan_track_list_t.h>
#include <string.h>

static void dump(json_t *j) {
  char *t = j ? json_dumps(j, RS_JSON_DUMP_FLAGS) : NULL;
  json_decref(j);
  free(t);
}

static json_t *as_json(const roadscan_object_list_t *m) {
  return rs_json_text_ok(m->sensor_id) && rs_json_text_ok(m->sensor_model) ? rs_json_objects(m) : NULL;
}
static json_t *as_json_s(const roadscan_frame_stats_t *m) {
  bool ok = rs_json_text_ok(m->sensor_id);
  for (int i = 0; i < m->num_errors && ok; i++) ok = rs_json_text_ok(m->error_kinds[i]);
  return ok ? rs_json_stats(m) : NULL;
}
static json_t *as_json_t(const roadscan_track_list_t *m) { return rs_json_text_ok(m->sensor_id) ? rs_json_tracks(m) : NULL; }
static json_t *as_json_e(const roadscan_track_end_t *m) {
  return rs_json_text_ok(m->sensor_id) ? rs_json_track_end(m) : NULL;
}
static json_t *as_json_c(const roadscan_counts_t *m) {
  bool ok = rs_json_text_ok(m->sensor_id);
  for (int i = 0; i < m->num_lines && ok; i++) ok = rs_json_text_ok(m->lines[i].name);
  for (int i = 0; i < m->num_zones && ok; i++) ok = rs_json_text_ok(m->zones[i].name);
  return ok ? rs_json_counts(m) : NULL;
}
static json_t *as_json_x(const roadscan_crossing_t *m) {
  return rs_json_text_ok(m->sensor_id) && rs_json_text_ok(m->line) ? rs_json_crossing(m) : NULL;
}

#define DECODE(T, buf, len, conv)                                                        \
  do {                                                                                   \
    T m;                                                                                 \
    memset(&m, 0, sizeof m);                                                             \
    if (T##_decode(buf, 0, len, &m) != len) abort(); /* checked, so it must decode whole */ \
    dump(conv(&m));                                                                      \
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
    case RS_LCM_OBJECT_LIST: DECODE(roadscan_object_list_t, msg, len, as_json); break;
    case RS_LCM_FRAME_STATS: DECODE(roadscan_frame_stats_t, msg, len, as_json_s); break;
    case RS_LCM_TRACK_LIST: DECODE(roadscan_track_list_t, msg, len, as_json_t); break;
    case RS_LCM_TRACK_END: DECODE(roadscan_track_end_t, msg, len, as_json_e); break;
    case RS_LCM_COUNTS: DECODE(roadscan_counts_t, msg, len, as_json_c); break;
    case RS_LCM_CROSSING: DECODE(roadscan_crossing_t, msg, len, as_json_x); break;
    default: break;
    }
  }
  free(msg);
  return 0;
}

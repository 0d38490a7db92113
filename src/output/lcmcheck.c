/* lcmcheck.c - walks an encoded message by the layout of its type in
 * lcmtypes/roadscan.lcm (big-endian: int8/boolean 1 byte, int16 2, int32 and
 * float 4, int64 8; a string is an int32 length counting its NUL, then the
 * bytes). Nested structs of fixed size are skipped by their encoded size,
 * taken from the generated code, so a field added to the .lcm changes it in
 * one place; the layouts below list the fields up to and between them. */
#include "roadscan/output/lcmcheck.h"

#include <roadscan_count_line_t.h>
#include <roadscan_count_zone_t.h>
#include <roadscan_counts_t.h>
#include <roadscan_crossing_t.h>
#include <roadscan_frame_stats_t.h>
#include <roadscan_object_list_t.h>
#include <roadscan_object_t.h>
#include <roadscan_track_end_t.h>
#include <roadscan_track_list_t.h>
#include <roadscan_track_t.h>

#include <stdint.h>
#include <stdio.h>
#include <string.h>

typedef struct {
  const uint8_t *p;
  int len, pos;
  char *err;
  size_t n;
  bool ok;
} rd_t;

static bool fail(rd_t *r, const char *what) {
  if (r->ok) snprintf(r->err, r->n, "%s at byte %d of %d", what, r->pos, r->len);
  r->ok = false;
  return false;
}

static bool skip(rd_t *r, int64_t bytes) {
  if (!r->ok) return false;
  if (bytes < 0 || bytes > (int64_t)(r->len - r->pos)) return fail(r, "the message ends inside a field");
  r->pos += (int)bytes;
  return true;
}

static int32_t i32(rd_t *r) {
  if (!r->ok || r->len - r->pos < 4) {
    fail(r, "the message ends inside a field");
    return -1;
  }
  const uint8_t *b = r->p + r->pos;
  r->pos += 4;
  return (int32_t)((uint32_t)b[0] << 24 | (uint32_t)b[1] << 16 | (uint32_t)b[2] << 8 | b[3]);
}

static int32_t i16(rd_t *r) {
  if (!r->ok || r->len - r->pos < 2) {
    fail(r, "the message ends inside a field");
    return -1;
  }
  const uint8_t *b = r->p + r->pos;
  r->pos += 2;
  return (int16_t)((uint16_t)b[0] << 8 | b[1]);
}

static bool fingerprint(rd_t *r, int64_t want) {
  if (r->len < 8) return fail(r, "shorter than a fingerprint");
  uint64_t v = 0;
  for (int i = 0; i < 8; i++) v = v << 8 | r->p[i];
  if ((int64_t)v != want) return fail(r, "not this type (fingerprint)");
  r->pos = 8;
  return true;
}

static bool str(rd_t *r) {
  const int at = r->pos;
  const int32_t l = i32(r);
  if (!r->ok) return false;
  if (l < 1 || l > RS_LCMCHECK_STRING_MAX) {
    r->pos = at;
    return fail(r, "a string length out of range");
  }
  if (l > r->len - r->pos) {
    r->pos = at;
    return fail(r, "a string longer than the message");
  }
  const uint8_t *s = r->p + r->pos;
  if (s[l - 1] != 0 || memchr(s, 0, (size_t)l - 1) != NULL) {
    r->pos = at;
    return fail(r, "a string not ended by its NUL");
  }
  r->pos += l;
  return true;
}

/* a count read earlier: elements of `each` bytes must fit in what is left */
static bool array(rd_t *r, int32_t count, int each) {
  if (!r->ok) return false;
  if (count < 0) return fail(r, "a negative array length");
  return skip(r, (int64_t)count * each);
}

static bool done(rd_t *r) {
  if (r->ok && r->pos != r->len) return fail(r, "bytes left over after the message");
  return r->ok;
}

static int size_object(void) {
  roadscan_object_t z;
  memset(&z, 0, sizeof z);
  return __roadscan_object_t_encoded_array_size(&z, 1);
}

static int size_track(void) {
  roadscan_track_t z;
  memset(&z, 0, sizeof z);
  return __roadscan_track_t_encoded_array_size(&z, 1);
}

/* the fixed part of a message after its last string: its encoded size with
 * empty strings (and empty arrays), less the fingerprint, what precedes and
 * the strings */
static int tail_stats(void) {
  roadscan_frame_stats_t z;
  memset(&z, 0, sizeof z);
  z.sensor_id = (char *)"";
  return roadscan_frame_stats_t_encoded_size(&z) - 8 - 8 - 5;
}

static int tail_track_end(void) {
  roadscan_track_end_t z;
  memset(&z, 0, sizeof z);
  z.sensor_id = (char *)"";
  return roadscan_track_end_t_encoded_size(&z) - 8 - 8 - 5;
}

static int tail_crossing(void) {
  roadscan_crossing_t z;
  memset(&z, 0, sizeof z);
  z.sensor_id = (char *)"";
  z.line = (char *)"";
  return roadscan_crossing_t_encoded_size(&z) - 8 - 8 - 5 - 5;
}

bool rs_lcm_check(rs_lcm_type_t type, const void *data, int len, char *err, size_t n) {
  rd_t r = {data, len, 0, err, n, true};
  if (data == NULL || len < 0) return fail(&r, "no message");
  switch (type) {
  case RS_LCM_OBJECT_LIST: {
    if (!fingerprint(&r, __roadscan_object_list_t_get_hash())) return false;
    skip(&r, 8); /* utime */
    const int32_t num = i32(&r);
    str(&r);       /* sensor_id */
    str(&r);       /* sensor_model */
    skip(&r, 3 * 8 + 4 * 4 + 2 + 4 + 1); /* frame_seq t_first t_last, packets .. columns, partial truncated,
                                             num_clusters, site_valid */
    array(&r, num, size_object());
    return done(&r);
  }
  case RS_LCM_FRAME_STATS: {
    if (!fingerprint(&r, __roadscan_frame_stats_t_get_hash())) return false;
    skip(&r, 8);
    str(&r);
    skip(&r, tail_stats() - 2 - 4); /* the fixed fields up to num_errors (model_age_s comes after the arrays) */
    const int32_t num = i16(&r);
    if (r.ok && num < 0) return fail(&r, "a negative array length");
    for (int32_t i = 0; i < num && r.ok; i++) { /* error_kinds: a string each (5 bytes at least) */
      if (r.len - r.pos < 5) return fail(&r, "more error kinds than the message holds");
      str(&r);
    }
    array(&r, num, 8); /* error_counts */
    skip(&r, 4);       /* model_age_s */
    return done(&r);
  }
  case RS_LCM_TRACK_LIST: {
    if (!fingerprint(&r, __roadscan_track_list_t_get_hash())) return false;
    skip(&r, 8);
    str(&r);
    skip(&r, 8 + 8 + 1 + 1 + 4); /* frame_seq t_frame truncated site_valid num_alive */
    const int32_t num = i32(&r);
    array(&r, num, size_track());
    return done(&r);
  }
  case RS_LCM_TRACK_END:
    if (!fingerprint(&r, __roadscan_track_end_t_get_hash())) return false;
    skip(&r, 8);
    str(&r);
    skip(&r, tail_track_end());
    return done(&r);
  case RS_LCM_COUNTS: {
    if (!fingerprint(&r, __roadscan_counts_t_get_hash())) return false;
    skip(&r, 8);
    str(&r);
    skip(&r, 8 + 8); /* t_start t_end */
    const int32_t num = i32(&r);
    if (r.ok && num < 0) return fail(&r, "a negative array length");
    for (int32_t i = 0; i < num && r.ok; i++) { /* count_line_t: a name, 6 + 6 int32 */
      if (r.len - r.pos < 5 + 48) return fail(&r, "more lines than the message holds");
      str(&r);
      skip(&r, 48);
    }
    const int32_t nz = i32(&r);
    if (r.ok && nz < 0) return fail(&r, "a negative array length");
    for (int32_t i = 0; i < nz && r.ok; i++) { /* count_zone_t: a name, 6 + 6 + 2 int32 */
      if (r.len - r.pos < 5 + 56) return fail(&r, "more zones than the message holds");
      str(&r);
      skip(&r, 56);
    }
    return done(&r);
  }
  case RS_LCM_CROSSING:
    if (!fingerprint(&r, __roadscan_crossing_t_get_hash())) return false;
    skip(&r, 8);
    str(&r); /* sensor_id */
    str(&r); /* line */
    skip(&r, tail_crossing());
    return done(&r);
  default: return fail(&r, "unknown type");
  }
}

const char *rs_lcm_type_name(rs_lcm_type_t type) {
  static const char *const names[RS_LCM_TYPES] = {"object_list_t", "frame_stats_t", "track_list_t", "track_end_t",
                                                  "counts_t", "crossing_t"};
  return (unsigned)type < RS_LCM_TYPES ? names[type] : "?";
}

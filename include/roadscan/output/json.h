/* json.h - roadscan's messages as JSON, through one library (jansson).
 *
 * The documents of docs/bridge-schema.json: one per LCM message, with
 * "schema": "roadscan.KIND/1", and a unit in the name of every field that has
 * one (_m, _mps, _deg, _s, _ms, _us, _m2; headings in degrees). Used by
 * roadscan-bridge (MQTT) and roadscan-listen --json, so the two cannot
 * disagree. The strings of a message must be UTF-8 (rs_json_text_ok): the
 * builders return NULL or leave a field out otherwise. Pure functions; the
 * caller owns the result (json_decref). Not for the real-time path. */
#ifndef ROADSCAN_JSON_H
#define ROADSCAN_JSON_H

#include <jansson.h>
#include <roadscan_counts_t.h>
#include <roadscan_crossing_t.h>
#include <roadscan_frame_stats_t.h>
#include <roadscan_object_list_t.h>
#include <roadscan_track_end_t.h>
#include <roadscan_track_list_t.h>
#include <stdbool.h>

#define RS_JSON_SCHEMA_VERSION 1
/* json_dumps flags: one line, ASCII, 8 significant digits (millimetres up to 100 km) */
#define RS_JSON_DUMP_FLAGS (JSON_COMPACT | JSON_ENSURE_ASCII | JSON_REAL_PRECISION(8))

json_t *rs_json_objects(const roadscan_object_list_t *l);
json_t *rs_json_tracks(const roadscan_track_list_t *l);
json_t *rs_json_track_end(const roadscan_track_end_t *e);
json_t *rs_json_counts(const roadscan_counts_t *c);
json_t *rs_json_crossing(const roadscan_crossing_t *x);
json_t *rs_json_stats(const roadscan_frame_stats_t *s);
/* true when s is valid UTF-8 (a JSON string can hold it) */
bool rs_json_text_ok(const char *s);

#endif

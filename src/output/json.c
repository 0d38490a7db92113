/* json.c - see json.h. */
#include "roadscan/output/json.h"

#include <math.h>
#include <stdio.h>
#include <string.h>


static const double DEG = 180.0 / M_PI;

static json_t *floats(const float *v, int n, double scale) {
  json_t *a = json_array();
  for (int i = 0; i < n; i++) json_array_append_new(a, json_real(round((double)v[i] * scale * 1e4) / 1e4));
  return a;
}

static json_t *real(double v) { return json_real(round(v * 1e4) / 1e4); }

static json_t *header(const char *kind, const char *sensor_id, int64_t utime) {
  char schema[64];
  snprintf(schema, sizeof schema, "roadscan.%s/%d", kind, RS_JSON_SCHEMA_VERSION);
  return json_pack("{s:s, s:s, s:I}", "schema", schema, "sensor_id", sensor_id, "published_us", (json_int_t)utime);
}

static json_t *geometry(const float *c, const float *bmin, const float *bmax, const float *oc, float len, float wid,
                        float head) {
  return json_pack("{s:o, s:o, s:o, s:o, s:o, s:o, s:o}", "centroid_m", floats(c, 3, 1), "box_min_m",
                   floats(bmin, 3, 1), "box_max_m", floats(bmax, 3, 1), "obb_center_m", floats(oc, 2, 1),
                   "obb_length_m", real(len), "obb_width_m", real(wid), "obb_heading_deg", real(head * DEG));
}

json_t *rs_json_objects(const roadscan_object_list_t *l) {
  json_t *j = header("objects", l->sensor_id, l->utime);
  json_object_update_new(j, json_pack("{s:s, s:I, s:I, s:I, s:i, s:i, s:i, s:i, s:b, s:b, s:i, s:b}", "sensor_model",
                                      l->sensor_model, "frame_seq", (json_int_t)l->frame_seq, "t_first_us",
                                      (json_int_t)l->t_first, "t_last_us", (json_int_t)l->t_last, "packets", l->packets,
                                      "packets_missing", l->packets_missing, "columns_covered", l->columns_covered,
                                      "columns", l->columns, "partial", l->partial, "truncated", l->truncated,
                                      "num_clusters", l->num_clusters, "site_valid", l->site_valid));
  json_t *a = json_array();
  for (int i = 0; i < l->num_objects; i++) {
    const roadscan_object_t *o = &l->objects[i];
    json_t *ob = json_pack("{s:i, s:i, s:o, s:o, s:o, s:o, s:[i,i], s:[i,i], s:o, s:I, s:I}", "id", o->id, "points",
                           o->points, "sensor", geometry(o->centroid, o->box_min, o->box_max, o->obb_center,
                                                         o->obb_length, o->obb_width, o->obb_heading),
                           "range_min_m", real(o->range_min), "azimuth_start_deg", real(o->azimuth_start),
                           "azimuth_end_deg", real(o->azimuth_end), "rows", o->row_min, o->row_max, "columns",
                           o->col_start, o->col_end, "intensity_mean", real(o->intensity_mean), "t_first_us",
                           (json_int_t)o->t_first, "t_last_us", (json_int_t)o->t_last);
    if (l->site_valid)
      json_object_set_new(ob, "site", geometry(o->site_centroid, o->site_box_min, o->site_box_max, o->site_obb_center,
                                               o->site_obb_length, o->site_obb_width, o->site_obb_heading));
    json_array_append_new(a, ob);
  }
  json_object_set_new(j, "objects", a);
  return j;
}

static const char *const class_names[6] = {"unknown", "pedestrian", "cyclist", "car", "van/truck", "bus"};
static const char *const state_names[3] = {"tentative", "confirmed", "coasting"};
static const char *name_of(const char *const *names, int n, int k) { return k >= 0 && k < n ? names[k] : "unknown"; }

json_t *rs_json_tracks(const roadscan_track_list_t *l) {
  json_t *j = header("tracks", l->sensor_id, l->utime);
  json_object_update_new(j, json_pack("{s:I, s:I, s:b, s:b, s:i}", "frame_seq", (json_int_t)l->frame_seq, "t_frame_us",
                                      (json_int_t)l->t_frame, "truncated", l->truncated, "site_valid", l->site_valid,
                                      "num_alive", l->num_alive));
  json_t *a = json_array();
  for (int i = 0; i < l->num_tracks; i++) {
    const roadscan_track_t *t = &l->tracks[i];
    json_t *tj = json_pack(
        "{s:i, s:s, s:s, s:o, s:i, s:i, s:o, s:o, s:o, s:o, s:o, s:o, s:o, s:i, s:o}", "id", t->id, "state",
        name_of(state_names, 3, t->state), "class", name_of(class_names, 6, t->class_id), "age_s", real(t->age),
        "hits", t->hits, "misses", t->misses, "position_m", floats(t->position, 3, 1), "velocity_mps",
        floats(t->velocity, 2, 1), "speed_mps", real(t->speed), "heading_deg", real(t->heading * DEG), "length_m",
        real(t->length), "width_m", real(t->width), "height_m", real(t->height), "points", t->points,
        "position_cov_m2", floats(t->position_cov, 3, 1));
    if (l->site_valid)
      json_object_set_new(tj, "site", json_pack("{s:o, s:o, s:o}", "position_m", floats(t->site_position, 3, 1),
                                                "velocity_mps", floats(t->site_velocity, 2, 1), "heading_deg",
                                                real(t->site_heading * DEG)));
    json_array_append_new(a, tj);
  }
  json_object_set_new(j, "tracks", a);
  return j;
}

json_t *rs_json_track_end(const roadscan_track_end_t *e) {
  json_t *j = header("track_ends", e->sensor_id, e->utime);
  json_object_update_new(j, json_pack("{s:i, s:s, s:I, s:I, s:o, s:o, s:o, s:o}", "id", e->id, "class",
                                      name_of(class_names, 6, e->class_id), "t_first_us", (json_int_t)e->t_first,
                                      "t_last_us", (json_int_t)e->t_last, "duration_s", real(e->duration), "distance_m",
                                      real(e->distance), "mean_speed_mps", real(e->mean_speed), "max_speed_mps",
                                      real(e->max_speed)));
  return j;
}

static json_t *by_class(const int32_t *v) {
  json_t *o = json_object();
  for (int k = 0; k < 6; k++) json_object_set_new(o, class_names[k], json_integer(v[k]));
  return o;
}

json_t *rs_json_counts(const roadscan_counts_t *c) {
  json_t *j = header("counts", c->sensor_id, c->utime);
  json_object_update_new(j, json_pack("{s:I, s:I}", "t_start_us", (json_int_t)c->t_start, "t_end_us",
                                      (json_int_t)c->t_end));
  json_t *a = json_array();
  for (int i = 0; i < c->num_lines; i++)
    json_array_append_new(a, json_pack("{s:s, s:o, s:o}", "name", c->lines[i].name, "forward",
                                       by_class(c->lines[i].forward), "backward", by_class(c->lines[i].backward)));
  json_object_set_new(j, "lines", a);
  json_t *zs = json_array();
  for (int i = 0; i < c->num_zones; i++)
    json_array_append_new(zs, json_pack("{s:s, s:o, s:o, s:i, s:i}", "name", c->zones[i].name, "entered",
                                        by_class(c->zones[i].entered), "exited", by_class(c->zones[i].exited),
                                        "occupancy", c->zones[i].occupancy, "occupancy_max",
                                        c->zones[i].occupancy_max));
  json_object_set_new(j, "zones", zs);
  return j;
}

static const char *const how_names[3] = {"seen", "hidden", "unseen"};

json_t *rs_json_crossing(const roadscan_crossing_t *x) {
  json_t *j = header("crossings", x->sensor_id, x->utime);
  json_object_update_new(j, json_pack("{s:s, s:I, s:s, s:o, s:s, s:i, s:o, s:s}", "line", x->line, "t_cross_us",
                                      (json_int_t)x->t_cross, "direction", x->direction > 0 ? "forward" : "backward",
                                      "at_m", real(x->at), "class", name_of(class_names, 6, x->class_id), "track_id",
                                      x->track_id, "speed_mps", x->speed >= 0.0f ? real(x->speed) : json_null(), "how",
                                      name_of(how_names, 3, x->how)));
  return j;
}

json_t *rs_json_stats(const roadscan_frame_stats_t *s) {
  json_t *j = header("stats", s->sensor_id, s->utime);
  json_t *stage = json_pack("{s:o, s:o, s:o, s:o, s:o, s:o}", "background_ms", real(s->background_us * 1e-3),
                            "cluster_ms", real(s->cluster_us * 1e-3), "objects_ms", real(s->objects_us * 1e-3),
                            "tracks_ms", real(s->tracks_us * 1e-3), "publish_ms", real(s->publish_us * 1e-3),
                            "processing_ms", real(s->processing_us * 1e-3));
  json_object_update_new(
      j, json_pack("{s:I, s:o, s:o, s:o, s:i, s:i, s:i, s:i, s:i, s:i, s:I, s:I, s:I, s:I, s:I, s:I, s:i}", "frame_seq",
                   (json_int_t)s->frame_seq, "stage_times", stage, "latency_ms",
                   s->latency_us >= 0 ? real(s->latency_us * 1e-3) : json_null(), "budget_ms", real(s->budget_ms),
                   "points", s->points, "foreground", s->foreground, "clusters", s->clusters, "noise", s->noise,
                   "objects", s->objects, "tracks", s->tracks, "frames_processed", (json_int_t)s->frames_processed,
                   "frames_dropped", (json_int_t)s->frames_dropped, "deadline_overruns",
                   (json_int_t)s->deadline_overruns, "packets_missing", (json_int_t)s->packets_missing,
                   "truncated_lists", (json_int_t)s->truncated_lists, "kernel_dropped",
                   (json_int_t)s->kernel_dropped, "capture_buffer_kib", s->capture_buffer_kib));
  json_t *e = json_object();
  for (int i = 0; i < s->num_errors; i++) json_object_set_new(e, s->error_kinds[i], json_integer(s->error_counts[i]));
  json_object_set_new(j, "input_errors", e);
  json_object_set_new(j, "model_age_s", s->model_age_s >= 0 ? real(s->model_age_s) : json_null());
  return j;
}

bool rs_json_text_ok(const char *s) {
  json_t *t = json_string(s);
  json_decref(t);
  return t != NULL;
}

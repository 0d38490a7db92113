/* calib.c - ROS velodyne YAML calibration loader (start-up only; libyaml's
 * document API allocates, which is fine here). */
#include "roadscan/sensor/calib.h"

#include "roadscan/util/error.h"

#include <errno.h>
#include <stdarg.h>
#include <limits.h>
#include <math.h>
#include <stdbool.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <yaml.h>

#define RAD2DEG (180.0 / 3.14159265358979323846)

static const char *scalar(yaml_document_t *doc, yaml_node_t *n) {
  if (n == NULL || n->type != YAML_SCALAR_NODE) return NULL;
  (void)doc;
  return (const char *)n->data.scalar.value;
}

static bool to_double(const char *s, double *v) {
  if (s == NULL || *s == '\0') return false;
  char *end;
  errno = 0;
  *v = strtod(s, &end);
  return errno == 0 && *end == '\0' && isfinite(*v);
}

static bool to_int(const char *s, long *v) {
  if (s == NULL || *s == '\0') return false;
  char *end;
  errno = 0;
  *v = strtol(s, &end, 10);
  return errno == 0 && *end == '\0';
}

static bool truthy(const char *s) { return s && (strcmp(s, "true") == 0 || strcmp(s, "True") == 0); }

__attribute__((format(printf, 4, 5))) static int fail(char *err, size_t n, const char *path, const char *fmt, ...) {
  char what[200];
  va_list ap;
  va_start(ap, fmt);
  vsnprintf(what, sizeof what, fmt, ap);
  va_end(ap);
  snprintf(err, n, "%s: %s", path, what);
  return RS_E_CALIB;
}

static int parse_laser(yaml_document_t *doc, yaml_node_t *m, rs_calib_t *c, bool *seen, long entry,
                       const char *path, char *err, size_t n) {
  if (m->type != YAML_MAPPING_NODE) return fail(err, n, path, "lasers[%ld] is not a mapping", entry);
  long id = LONG_MIN; /* not given */
  double rot = NAN, vert = NAN, dist = 0.0, voff = 0.0;
  int ignored = 0;
  for (yaml_node_pair_t *p = m->data.mapping.pairs.start; p < m->data.mapping.pairs.top; p++) {
    const char *k = scalar(doc, yaml_document_get_node(doc, p->key));
    const char *v = scalar(doc, yaml_document_get_node(doc, p->value));
    if (k == NULL) continue;
    double d;
    if (strcmp(k, "laser_id") == 0) {
      if (!to_int(v, &id)) return fail(err, n, path, "lasers[%ld]: laser_id is not an integer", entry);
      continue;
    }
    if (strcmp(k, "two_pt_correction_available") == 0) {
      if (truthy(v)) ignored++;
      continue;
    }
    if (strcmp(k, "min_intensity") == 0 || strcmp(k, "max_intensity") == 0) continue;
    if (!to_double(v, &d)) {
      return fail(err, n, path, "lasers[%ld]: %s is not a number", entry, k);
    }
    if (strcmp(k, "rot_correction") == 0) rot = d;
    else if (strcmp(k, "vert_correction") == 0) vert = d;
    else if (strcmp(k, "dist_correction") == 0) dist = d;
    else if (strcmp(k, "vert_offset_correction") == 0) voff = d;
    else if (d != 0.0) ignored++; /* horiz offset, two-point and focal terms */
  }
  if (id == LONG_MIN) return fail(err, n, path, "lasers[%ld]: laser_id missing", entry);
  if (id < 0) return fail(err, n, path, "lasers[%ld]: laser_id %ld is negative", entry, id);
  if (id >= c->lasers) {
    return fail(err, n, path, "lasers[%ld]: laser_id %ld out of range (num_lasers %d)", entry, id, c->lasers);
  }
  if (seen[id]) return fail(err, n, path, "laser_id %ld appears twice", id);
  if (isnan(rot) || isnan(vert))
    return fail(err, n, path, "laser_id %ld: rot_correction and vert_correction are required", id);
  if (fabs(vert) > 1.5707963 || fabs(rot) > 0.5236)
    return fail(err, n, path, "laser_id %ld: angle out of range (radians expected)", id);
  if (fabs(dist) > 2.0 || fabs(voff) > 0.5)
    return fail(err, n, path, "laser_id %ld: distance correction out of range (metres expected)", id);
  if (dist < RS_CALIB_MIN_DIST_CORRECTION)
    return fail(err, n, path,
                "laser_id %ld: dist_correction %.3f m would make the ranges of near returns negative (points "
                "mirrored through the sensor); at least %.1f m is accepted",
                id, dist, RS_CALIB_MIN_DIST_CORRECTION);
  seen[id] = true;
  c->elevation_deg[id] = (float)(vert * RAD2DEG);
  c->azimuth_offset_deg[id] = (float)(-rot * RAD2DEG);
  c->dist_correction_m[id] = (float)dist;
  c->vert_offset_m[id] = (float)voff;
  c->ignored_fields += ignored;
  return RS_OK;
}

int rs_calib_load_yaml(const char *path, rs_calib_t *c, char *err, size_t n) {
  memset(c, 0, sizeof *c);
  FILE *f = fopen(path, "rb");
  if (f == NULL) {
    snprintf(err, n, "%s: %s", path, strerror(errno));
    return errno == ENOENT ? RS_E_NOENT : RS_E_IO;
  }
  yaml_parser_t parser;
  yaml_document_t doc;
  yaml_parser_initialize(&parser);
  yaml_parser_set_input_file(&parser, f);
  if (!yaml_parser_load(&parser, &doc)) {
    snprintf(err, n, "%s: YAML error at line %lu: %s", path, (unsigned long)parser.problem_mark.line + 1,
             parser.problem ? parser.problem : "unknown");
    yaml_parser_delete(&parser);
    fclose(f);
    return RS_E_CALIB;
  }
  int rc = RS_OK;
  yaml_node_t *root = yaml_document_get_root_node(&doc);
  yaml_node_t *lasers = NULL;
  long num = -1;
  if (root == NULL || root->type != YAML_MAPPING_NODE) {
    rc = fail(err, n, path, "not a calibration mapping (expected num_lasers and lasers)");
    goto out;
  }
  for (yaml_node_pair_t *p = root->data.mapping.pairs.start; p < root->data.mapping.pairs.top; p++) {
    const char *k = scalar(&doc, yaml_document_get_node(&doc, p->key));
    yaml_node_t *vn = yaml_document_get_node(&doc, p->value);
    if (k == NULL) continue;
    if (strcmp(k, "lasers") == 0) lasers = vn;
    else if (strcmp(k, "num_lasers") == 0) {
      if (!to_int(scalar(&doc, vn), &num) || num < 1 || num > RS_MAX_LASERS) {
        rc = fail(err, n, path, "num_lasers must be an integer from 1 to %d", RS_MAX_LASERS);
        goto out;
      }
    } else if (strcmp(k, "distance_resolution") == 0) {
      double d;
      if (!to_double(scalar(&doc, vn), &d) || d <= 0.0 || d > 0.01) {
        rc = fail(err, n, path, "distance_resolution must be in (0, 0.01] metres");
        goto out;
      }
      c->dist_res_m = (float)d;
    }
  }
  if (lasers == NULL || lasers->type != YAML_SEQUENCE_NODE) {
    rc = fail(err, n, path, "missing 'lasers' list");
    goto out;
  }
  long count = (long)(lasers->data.sequence.items.top - lasers->data.sequence.items.start);
  if (num < 0) num = count;
  if (count != num || num > RS_MAX_LASERS) {
    rc = fail(err, n, path, "num_lasers is %ld but 'lasers' has %ld entries", num, count);
    goto out;
  }
  c->lasers = (int)num;
  bool seen[RS_MAX_LASERS] = {false};
  long entry = 0;
  for (yaml_node_item_t *it = lasers->data.sequence.items.start; it < lasers->data.sequence.items.top; it++, entry++) {
    rc = parse_laser(&doc, yaml_document_get_node(&doc, *it), c, seen, entry, path, err, n);
    if (rc != RS_OK) goto out;
  }
out:
  yaml_document_delete(&doc);
  yaml_parser_delete(&parser);
  fclose(f);
  return rc;
}

int rs_calib_apply(const rs_calib_t *c, rs_sensor_t *s, char *err, size_t n, char *warn, size_t wn) {
  if (warn && wn) warn[0] = '\0';
  if (c->lasers != s->lasers) {
    snprintf(err, n, "calibration has %d lasers but the sensor (%s) has %d", c->lasers, s->info->name, s->lasers);
    return RS_E_CALIB;
  }
  for (int i = 0; i < c->lasers; i++) {
    s->elevation_deg[i] = c->elevation_deg[i];
    s->azimuth_offset_deg[i] = c->azimuth_offset_deg[i];
    s->dist_correction_m[i] = c->dist_correction_m[i];
    s->vert_offset_m[i] = c->vert_offset_m[i];
  }
  /* every supported model's packet format fixes the distance unit (the
   * manuals: 2 mm VLP-16, Puck Hi-Res, HDL-32E; 4 mm VLP-32C, VLS-128);
   * files as shipped sometimes say otherwise (tier4/nebula's VLS128.yaml:
   * 0.007), and honouring them scales every range */
  if (c->dist_res_m > 0.0f && fabsf(c->dist_res_m - s->info->dist_res_m) > 1e-6f && warn && wn)
    snprintf(warn, wn, "distance_resolution %.4g m ignored: the %s packet format fixes it at %.4g m", (double)c->dist_res_m,
             s->info->name, (double)s->info->dist_res_m);
  s->dist_res_m = s->info->dist_res_m;
  s->calibrated = true;
  rs_sensor_finish(s);
  return RS_OK;
}

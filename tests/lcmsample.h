/* lcmsample.h - a counts message with both of its variable-length parts (two
 * lines and a zone), and a crossing event, built the same way by the hostile-message tests
 * (check_lcm) and the fuzz seeds (fuzz/seeds.c): the caller owns the storage
 * the message points into. */
#ifndef ROADSCAN_TESTS_LCMSAMPLE_H
#define ROADSCAN_TESTS_LCMSAMPLE_H

#include "roadscan_counts_t.h"
#include "roadscan_crossing_t.h"

#include <string.h>

static inline void ts_sample_counts(roadscan_counts_t *cm, roadscan_count_line_t lines[2],
                                    roadscan_count_zone_t zones[1]) {
  memset(lines, 0, 2 * sizeof lines[0]);
  lines[0].name = "east";
  lines[1].name = "west";
  memset(zones, 0, sizeof zones[0]);
  zones[0].name = "box";
  zones[0].entered[3] = 2;
  zones[0].occupancy_max = 1;
  memset(cm, 0, sizeof *cm);
  cm->sensor_id = "north";
  cm->num_lines = 2;
  cm->lines = lines;
  cm->num_zones = 1;
  cm->zones = zones;
}

/* a crossing event with its strings */
static inline void ts_sample_crossing(roadscan_crossing_t *x) {
  memset(x, 0, sizeof *x);
  x->sensor_id = "north";
  x->line = "east";
  x->t_cross = 1700000000123456LL;
  x->direction = 1;
  x->at = 3.5f;
  x->class_id = 3;
  x->track_id = 42;
  x->speed = 9.25f;
}

#endif

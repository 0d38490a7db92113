/* check_objects - cluster attributes on hand-built maps: a box rendered by
 * ray casting (its oriented box must come back), extents across the column
 * seam, times, intensity, missing labels, and the site frame of a pose. */
#include "roadscan/util/error.h"
#include "roadscan/perception/objects.h"
#include "testutil.h"

#include <math.h>
#include <string.h>

#define PI 3.14159265358979323846
#define COLS 1800

static rs_slot_t slot;
static rs_objects_t objs;
static rs_object_list_t list;
static rs_sensor_t sensor;

static void clear_map(void) {
  ck_assert_int_eq(rs_sensor_init(&sensor, RS_MODEL_VLP32C), RS_OK);
  memset(&slot.meta, 0, sizeof slot.meta);
  slot.meta.rows = (uint16_t)sensor.lasers;
  slot.meta.cols = COLS;
  memset(slot.range, 0, sizeof slot.range);
  memset(slot.label, 0, sizeof slot.label);
  memset(slot.intensity, 0, sizeof slot.intensity);
  memset(slot.addr, 0, sizeof slot.addr);
  memset(slot.gap, 0, sizeof slot.gap);
}

/* Casts the ray of every cell at a vertical box (centre cx, cy; length L
 * along heading h; width W; z from z0 to z1 in the sensor frame) and labels
 * the cells that hit it, unless something nearer was drawn there. Returns
 * the number of cells hit. */
static int render_box(float cx, float cy, float h, float L, float W, float z0, float z1, uint16_t label) {
  int hits = 0;
  const float ch = cosf(h), sh = sinf(h);
  for (int r = 0; r < slot.meta.rows; r++) {
    int laser = sensor.laser_of_row[r];
    for (int c = 0; c < COLS; c++) {
      float az = (float)((c + 0.5) * 2.0 * PI / COLS);
      float dx = sinf(az), dy = cosf(az); /* ground direction of the ray */
      /* ray origin in box coordinates (u along the length, v across) */
      float ou = (0 - cx) * ch + (0 - cy) * sh, ov = -(0 - cx) * sh + (0 - cy) * ch;
      float du = dx * ch + dy * sh, dv = -dx * sh + dy * ch;
      float tmin = 0.0f, tmax = 1e9f;
      const float o2[2] = {ou, ov}, d2[2] = {du, dv}, half[2] = {L / 2, W / 2};
      bool miss = false;
      for (int a = 0; a < 2 && !miss; a++) {
        if (fabsf(d2[a]) < 1e-9f) {
          if (fabsf(o2[a]) > half[a]) miss = true;
          continue;
        }
        float t1 = (-half[a] - o2[a]) / d2[a], t2 = (half[a] - o2[a]) / d2[a];
        if (t1 > t2) {
          float t = t1;
          t1 = t2;
          t2 = t;
        }
        tmin = fmaxf(tmin, t1);
        tmax = fminf(tmax, t2);
        if (tmin > tmax) miss = true;
      }
      if (miss || tmin <= 0.0f) continue;
      /* ground distance tmin -> range and height along this laser */
      float range = tmin / sensor.cos_el[laser];
      float z = range * sensor.sin_el[laser] + sensor.vert_offset_m[laser];
      if (z < z0 || z > z1) continue;
      uint32_t i = rs_cell(&slot, 0, r, c);
      if (slot.range[i] != 0.0f && slot.range[i] <= range) continue; /* something nearer is in the way */
      slot.range[i] = range;
      slot.label[i] = label;
      slot.intensity[i] = 40;
      hits++;
    }
  }
  return hits;
}

static float angle_diff(float a, float b) { /* headings modulo pi */
  float d = fmodf(fabsf(a - b), (float)PI);
  return fminf(d, (float)PI - d);
}

START_TEST(test_box_comes_back) {
  /* a 4.5 x 1.8 m car, 15 m away, heading 30 degrees, seen from a 4 m pole */
  const float headings[] = {0.0f, 0.5236f, -1.1f, 1.5f};
  for (int t = 0; t < 4; t++) {
    clear_map();
    float cx = 9.0f, cy = 12.0f;
    int hits = render_box(cx, cy, headings[t], 4.5f, 1.8f, -2.0f, -0.4f, 3);
    ck_assert_int_gt(hits, 100);
    rs_objects_init(&objs, NULL);
    rs_objects_extract(&objs, &slot, &sensor, &list);
    ck_assert_uint_eq(list.count, 1);
    const rs_object_t *o = &list.obj[0];
    ck_assert_uint_eq(o->points, (uint32_t)hits);
    ck_assert_uint_eq(o->id, 1);
    ck_assert(!list.site_valid);
    /* visible faces give three corners: the full box, to the map's resolution */
    ck_assert_float_eq_tol(o->sensor.obb_length, 4.5f, 0.15f);
    ck_assert_float_eq_tol(o->sensor.obb_width, 1.8f, 0.15f);
    ck_assert_float_le(angle_diff(o->sensor.obb_heading, headings[t]), 0.05f);
    ck_assert_float_eq_tol(o->sensor.obb_center[0], cx, 0.15f);
    ck_assert_float_eq_tol(o->sensor.obb_center[1], cy, 0.15f);
    ck_assert(o->sensor.obb_heading > -PI / 2 - 1e-6 && o->sensor.obb_heading <= PI / 2 + 1e-6);
    /* axis-aligned box and height */
    ck_assert_float_ge(o->sensor.box_min[2], -2.0f - 0.01f);
    ck_assert_float_le(o->sensor.box_max[2], -0.4f + 0.01f);
    ck_assert_float_le(o->sensor.box_min[0], o->sensor.centroid[0]);
    ck_assert_float_ge(o->sensor.box_max[0], o->sensor.centroid[0]);
    /* the aligned box of a rotated car is wider than the car, the oriented one is not */
    float aabb_area = (o->sensor.box_max[0] - o->sensor.box_min[0]) * (o->sensor.box_max[1] - o->sensor.box_min[1]);
    ck_assert_float_ge(aabb_area + 0.05f, o->sensor.obb_length * o->sensor.obb_width);
    ck_assert_float_eq_tol(o->intensity_mean, 40.0f, 1e-3f);
    float near = sqrtf(cx * cx + cy * cy) - 2.5f;
    ck_assert_float_ge(o->range_min, near * 0.9f);
    ck_assert_float_le(o->range_min, sqrtf(cx * cx + cy * cy));
  }
}
END_TEST

START_TEST(test_centroid_and_extents) {
  clear_map();
  double sx = 0, sy = 0, sz = 0;
  int n = 0;
  for (int r = 3; r <= 6; r++)
    for (int c = 100; c <= 119; c++) {
      uint32_t i = rs_cell(&slot, 0, r, c);
      slot.range[i] = 20.0f + 0.01f * (float)c;
      slot.label[i] = 3;
      slot.intensity[i] = (uint8_t)(c - 100);
      /* the sensor frame of sensor.h, at the column's centre azimuth */
      int laser = sensor.laser_of_row[r];
      double az = (c + 0.5) * 2.0 * PI / COLS, el = sensor.elevation_deg[laser] * PI / 180.0;
      sx += slot.range[i] * cos(el) * sin(az);
      sy += slot.range[i] * cos(el) * cos(az);
      sz += slot.range[i] * sin(el) + sensor.vert_offset_m[laser];
      n++;
    }
  rs_objects_init(&objs, NULL);
  rs_objects_extract(&objs, &slot, &sensor, &list);
  ck_assert_uint_eq(list.count, 1);
  const rs_object_t *o = &list.obj[0];
  ck_assert_uint_eq(o->points, (uint32_t)n);
  ck_assert_float_eq_tol(o->sensor.centroid[0], sx / n, 1e-4);
  ck_assert_float_eq_tol(o->sensor.centroid[1], sy / n, 1e-4);
  ck_assert_float_eq_tol(o->sensor.centroid[2], sz / n, 1e-4);
  /* each return's ground-plane position, as the extraction placed it */
  double qx = 0, qy = 0;
  for (int r = 3; r <= 6; r++)
    for (int c = 100; c <= 119; c++) {
      float xy[2];
      rs_objects_xy(&objs, &slot, &sensor, rs_cell(&slot, 0, r, c), xy);
      qx += xy[0];
      qy += xy[1];
    }
  ck_assert_float_eq_tol(qx / n, sx / n, 1e-4);
  ck_assert_float_eq_tol(qy / n, sy / n, 1e-4);
  ck_assert_uint_eq(o->row_min, 3);
  ck_assert_uint_eq(o->row_max, 6);
  ck_assert_uint_eq(o->col_start, 100);
  ck_assert_uint_eq(o->col_end, 119);
  ck_assert_float_eq_tol(o->az_start, 20.0f, 1e-4f);
  ck_assert_float_eq_tol(o->az_end, 24.0f, 1e-4f);
  ck_assert_float_eq_tol(o->range_min, 21.0f, 1e-4f);
  ck_assert_float_eq_tol(o->intensity_mean, 9.5f, 1e-4f);
  /* the gaps to rows 7 and 2 at 21 m: what the sensor could have missed above and below */
  {
    const double tn = tan(sensor.elevation_deg[sensor.laser_of_row[7]] * PI / 180.0) -
                      tan(sensor.elevation_deg[sensor.laser_of_row[6]] * PI / 180.0) +
                      tan(sensor.elevation_deg[sensor.laser_of_row[3]] * PI / 180.0) -
                      tan(sensor.elevation_deg[sensor.laser_of_row[2]] * PI / 180.0);
    ck_assert_float_gt(o->height_gap, 0.1f);
    ck_assert_float_eq_tol(o->height_gap, 21.0 * tn, 1e-3);
    /* the row above alone bounds its top */
    const double up = tan(sensor.elevation_deg[sensor.laser_of_row[7]] * PI / 180.0) -
                      tan(sensor.elevation_deg[sensor.laser_of_row[6]] * PI / 180.0);
    ck_assert_float_eq_tol(o->top_gap, 21.0 * up, 1e-3);
  }
}
END_TEST

/* an object in the top row: no row above bounds its top */
START_TEST(test_top_gap_top_row) {
  clear_map();
  const int top = (int)sensor.lasers - 1;
  for (int r = top - 1; r <= top; r++)
    for (int c = 200; c <= 209; c++) {
      uint32_t i = rs_cell(&slot, 0, r, c);
      slot.range[i] = 15.0f;
      slot.label[i] = 3;
    }
  rs_objects_init(&objs, NULL);
  rs_objects_extract(&objs, &slot, &sensor, &list);
  ck_assert_uint_eq(list.count, 1);
  ck_assert_uint_eq(list.obj[0].row_max, (uint32_t)top);
  ck_assert_float_eq(list.obj[0].top_gap, -1.0f);
}
END_TEST

START_TEST(test_seam_missing_labels_and_times) {
  clear_map();
  slot.meta.first_packet = 1000;
  slot.meta.last_packet = 1100;
  slot.meta.t_first = 50.0;
  slot.meta.t_last = 50.1;
  /* object 1 (label 3) across column 0; object 3 (label 5) elsewhere; no label 4 */
  for (int c = COLS - 5; c < COLS + 5; c++) {
    int col = c % COLS;
    uint32_t i = rs_cell(&slot, 0, 10, col);
    slot.range[i] = 8.0f;
    slot.label[i] = 3;
    slot.addr[i].packet = col < 5 ? 1000 + (uint32_t)col : 1095 + (uint32_t)(col - (COLS - 5));
  }
  for (int c = 500; c < 510; c++) {
    uint32_t i = rs_cell(&slot, 1, 12, c); /* second layer only */
    slot.range[i] = 30.0f;
    slot.label[i] = 5;
    slot.addr[i].packet = 1040;
  }
  rs_objects_init(&objs, NULL);
  rs_objects_extract(&objs, &slot, &sensor, &list);
  ck_assert_uint_eq(list.count, 3);
  const rs_object_t *a = &list.obj[0], *b = &list.obj[1], *c = &list.obj[2];
  ck_assert_uint_eq(a->points, 10);
  ck_assert_uint_eq(a->col_start, COLS - 5);
  ck_assert_uint_eq(a->col_end, 4);
  ck_assert_float_eq_tol(a->az_start, 359.0f, 1e-3f);
  ck_assert_float_eq_tol(a->az_end, 1.0f, 1e-3f);
  ck_assert_double_eq_tol(a->t_first, 50.0, 1e-9);
  ck_assert_double_eq_tol(a->t_last, 50.099, 1e-9);
  ck_assert_uint_eq(b->points, 0);
  ck_assert_uint_eq(c->points, 10);
  ck_assert_uint_eq(c->id, 3);
  ck_assert_double_eq_tol(c->t_first, 50.04, 1e-9);
  ck_assert_double_eq_tol(c->t_last, 50.04, 1e-9);
  /* a point-like column set: 10 returns at one range along an arc */
  ck_assert_float_le(c->sensor.obb_width, 0.05f);
  ck_assert_float_eq_tol(c->sensor.obb_length, 2.0f * 30.0f * sensor.cos_el[sensor.laser_of_row[12]] *
                                                   sinf((float)(9.0 * PI / COLS)), 0.02f);
}
END_TEST

START_TEST(test_site_frame) {
  clear_map();
  int hits = render_box(-6.0f, 14.0f, 0.3f, 4.0f, 1.7f, -5.0f, -3.5f, 3);
  ck_assert_int_gt(hits, 50);
  rs_objects_init(&objs, NULL);
  rs_objects_extract(&objs, &slot, &sensor, &list);
  rs_object_t plain = list.obj[0];
  /* sensor 5 m up at (100, 200), turned 90 degrees left, level */
  rs_pose_t pose = {100.0, 200.0, 5.0, 0.0, 0.0, PI / 2};
  rs_objects_init(&objs, &pose);
  rs_objects_extract(&objs, &slot, &sensor, &list);
  ck_assert(list.site_valid);
  const rs_object_t *o = &list.obj[0];
  /* the sensor frame is unchanged */
  ck_assert_float_eq_tol(o->sensor.centroid[0], plain.sensor.centroid[0], 1e-5f);
  ck_assert_float_eq_tol(o->sensor.obb_heading, plain.sensor.obb_heading, 1e-5f);
  /* rotation by +90 degrees: (x, y) -> (-y, x) */
  ck_assert_float_eq_tol(o->site.centroid[0], 100.0f - plain.sensor.centroid[1], 1e-3f);
  ck_assert_float_eq_tol(o->site.centroid[1], 200.0f + plain.sensor.centroid[0], 1e-3f);
  ck_assert_float_eq_tol(o->site.centroid[2], 5.0f + plain.sensor.centroid[2], 1e-3f);
  ck_assert_float_eq_tol(o->site.box_min[2], 5.0f + plain.sensor.box_min[2], 1e-3f);
  ck_assert_float_le(angle_diff(o->site.obb_heading, plain.sensor.obb_heading + (float)(PI / 2)), 0.02f);
  ck_assert_float_eq_tol(o->site.obb_length, plain.sensor.obb_length, 0.02f);
  ck_assert_float_eq_tol(o->site.obb_width, plain.sensor.obb_width, 0.02f);
  /* a pitched sensor: the site z of a point ahead changes with the pitch */
  rs_pose_t tilt = {0.0, 0.0, 0.0, 0.0, 0.1, 0.0};
  rs_objects_init(&objs, &tilt);
  rs_objects_extract(&objs, &slot, &sensor, &list);
  const float *p = plain.sensor.centroid;
  float z = (float)(-sin(0.1) * p[0] + cos(0.1) * p[2]);
  ck_assert_float_eq_tol(list.obj[0].site.centroid[2], z, 1e-3f);
}
END_TEST

/* A car (4.5 x 1.8 m at 9, 12, along +x) partly behind a post nearer the
 * sensor (1.5 x 1.5 m at range 8, azimuth 25 degrees): the car's first
 * column lies beside the post's nearer returns (its rear goes on behind it),
 * its last beside nothing. The post's own sides: beside the farther car and
 * nothing, neither hidden. A wall behind the car's end (range 25) hides
 * nothing; a wall in front of it does. */
START_TEST(test_hidden_sides) {
  clear_map();
  const float pa = 25.0f * (float)PI / 180.0f;
  ck_assert_int_gt(render_box(8.0f * sinf(pa), 8.0f * cosf(pa), 0.0f, 1.5f, 1.5f, -2.5f, 0.5f, 4), 20);
  ck_assert_int_gt(render_box(9.0f, 12.0f, 0.0f, 4.5f, 1.8f, -2.0f, -0.4f, 3), 50);
  rs_objects_init(&objs, NULL);
  rs_objects_extract(&objs, &slot, &sensor, &list);
  ck_assert_uint_eq(list.count, 2);
  ck_assert_uint_eq(list.obj[0].occluded, RS_OBJ_HIDDEN_START);
  ck_assert_uint_eq(list.obj[1].occluded, 0);
  ck_assert_float_lt(list.obj[0].sensor.obb_length, 4.3f); /* the part that shows */
  /* a wall beyond the car's end: farther, nothing hidden there */
  ck_assert_int_gt(render_box(18.0f, 17.0f, 0.5f, 4.0f, 0.3f, -3.0f, 1.0f, 5), 20);
  rs_objects_extract(&objs, &slot, &sensor, &list);
  ck_assert_uint_eq(list.obj[0].occluded, RS_OBJ_HIDDEN_START);
  /* the same car with nothing in front of it, then a post in front of its front end */
  clear_map();
  render_box(9.0f, 12.0f, 0.0f, 4.5f, 1.8f, -2.0f, -0.4f, 3);
  rs_objects_extract(&objs, &slot, &sensor, &list);
  ck_assert_uint_eq(list.obj[0].occluded, 0);
  clear_map();
  const float pb = 46.0f * (float)PI / 180.0f;
  render_box(8.0f * sinf(pb), 8.0f * cosf(pb), 0.0f, 1.5f, 1.5f, -2.5f, 0.5f, 4);
  render_box(9.0f, 12.0f, 0.0f, 4.5f, 1.8f, -2.0f, -0.4f, 3);
  rs_objects_extract(&objs, &slot, &sensor, &list);
  ck_assert_uint_eq(list.obj[0].occluded, RS_OBJ_HIDDEN_END);
  /* one stray nearer return beside it among many rows is not a post */
  clear_map();
  render_box(9.0f, 12.0f, 0.0f, 4.5f, 1.8f, -2.0f, -0.4f, 3);
  rs_objects_extract(&objs, &slot, &sensor, &list);
  const int c0 = list.obj[0].col_start, r0 = list.obj[0].row_min;
  ck_assert_int_gt(list.obj[0].row_max - r0, 3);
  for (int r = r0; r <= list.obj[0].row_max; r++)
    if (slot.label[rs_cell(&slot, 0, r, c0)] == 3) {
      slot.range[rs_cell(&slot, 0, r, c0 - 1)] = 3.0f;
      slot.label[rs_cell(&slot, 0, r, c0 - 1)] = 2;
      break;
    }
  rs_objects_extract(&objs, &slot, &sensor, &list);
  ck_assert_uint_eq(list.obj[0].occluded, 0);
}
END_TEST

START_TEST(test_empty_frame) {
  clear_map();
  slot.range[rs_cell(&slot, 0, 0, 0)] = 5.0f;
  slot.label[rs_cell(&slot, 0, 0, 0)] = 2; /* noise is not an object */
  rs_objects_init(&objs, NULL);
  rs_objects_extract(&objs, &slot, &sensor, &list);
  ck_assert_uint_eq(list.count, 0);
}
END_TEST

/* The unmeasured columns the list carries (rs_object_list_t.gap): a column counts when more than half
 * the rows did not measure it. A VLP-16's rows fire at their block's azimuth, so a lost packet's 24
 * block columns are one run; a VLP-32C's rows lie 1.4 or 4.2 degrees (7 or 21 columns) either side, so
 * one lost packet (12 columns) leaves no column unmeasured in more than 16 of its 32 rows, two in a
 * row (24 columns) leave the 10 columns that both its 1.4-degree groups (22 rows) missed (where a
 * 1.4-degree and a 4.2-degree group overlap, 16 rows: half, not more). */
static void unmeasured_runs(rs_model_t model, int first, int last) {
  clear_map();
  ck_assert_int_eq(rs_sensor_init(&sensor, model), RS_OK);
  slot.meta.rows = (uint16_t)sensor.lasers;
  for (int c = first; c <= last; c++) slot.gap[c] = 1;
  rs_objects_init(&objs, NULL);
  rs_objects_extract(&objs, &slot, &sensor, &list);
  ck_assert_uint_eq(list.gap_cols, COLS);
}
/* ... and the list holds the one run [first, last] */
static void one_run(rs_model_t model, int first, int last, int run_first, int run_last) {
  unmeasured_runs(model, first, last);
  ck_assert_uint_eq(list.ngaps, 1);
  ck_assert_uint_eq(list.gap[0][0], run_first);
  ck_assert_uint_eq(list.gap[0][1], run_last);
}
/* a ground point 20 m out at azimuth deg (clockwise from +Y): in an unmeasured run? */
static bool unmeasured_at_deg(double deg) {
  const double a = deg * M_PI / 180.0;
  return rs_objects_unmeasured_at(&list, 20.0 * sin(a), 20.0 * cos(a));
}
START_TEST(test_unmeasured_columns) {
  one_run(RS_MODEL_VLP16, 100, 123, 100, 123); /* 20 to 24.8 degrees */
  ck_assert(unmeasured_at_deg(20.1) && unmeasured_at_deg(24.7));
  ck_assert(!unmeasured_at_deg(19.9) && !unmeasured_at_deg(24.9) && !unmeasured_at_deg(200.0));
  ck_assert(!rs_objects_unmeasured_at(&list, NAN, 20.0) && !rs_objects_unmeasured_at(&list, 7.5, NAN)); /* in none */
  one_run(RS_MODEL_VLP16, 1790, 1799, 1790, 1799); /* the turn's last 2 degrees, west of +Y */
  ck_assert(unmeasured_at_deg(359.5) && unmeasured_at_deg(-0.5));
  ck_assert(!unmeasured_at_deg(0.5) && !unmeasured_at_deg(357.9));
  unmeasured_runs(RS_MODEL_VLP32C, 100, 111);
  ck_assert_uint_eq(list.ngaps, 0);
  one_run(RS_MODEL_VLP32C, 100, 123, 107, 116);
  /* a whole frame: none; more runs than RS_OBJ_GAPS_MAX: the first kept, the rest counted */
  unmeasured_runs(RS_MODEL_VLP16, 1, 0);
  ck_assert_uint_eq(list.ngaps, 0);
  clear_map();
  ck_assert_int_eq(rs_sensor_init(&sensor, RS_MODEL_VLP16), RS_OK);
  slot.meta.rows = (uint16_t)sensor.lasers;
  for (int k = 0; k < RS_OBJ_GAPS_MAX + 5; k++) slot.gap[10 * k] = 1;
  rs_objects_extract(&objs, &slot, &sensor, &list);
  ck_assert_uint_eq(list.ngaps, RS_OBJ_GAPS_MAX);
  ck_assert_uint_eq(list.gaps_dropped, 5);
  ck_assert_uint_eq(list.gap[RS_OBJ_GAPS_MAX - 1][0], 10 * (RS_OBJ_GAPS_MAX - 1));
}
END_TEST

int main(void) {
  Suite *s = suite_create("objects");
  TCase *tc = tcase_create("core");
  tcase_set_timeout(tc, 60);
  tcase_add_test(tc, test_box_comes_back);
  tcase_add_test(tc, test_centroid_and_extents);
  tcase_add_test(tc, test_top_gap_top_row);
  tcase_add_test(tc, test_seam_missing_labels_and_times);
  tcase_add_test(tc, test_site_frame);
  tcase_add_test(tc, test_hidden_sides);
  tcase_add_test(tc, test_empty_frame);
  tcase_add_test(tc, test_unmeasured_columns);
  suite_add_tcase(s, tc);
  return tu_run(s);
}

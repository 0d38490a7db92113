/* sensor.c - built-in tables of the supported Velodyne models.
 *
 * Pure and read-only after start-up. Elevations and azimuth offsets are the
 * published per-model values (user manuals; the same values ship as the ROS
 * velodyne driver's default calibrations). Azimuth offsets use the manuals'
 * sign: true azimuth = block azimuth + offset (the ROS files store the
 * negated value as rot_correction). Vertical offsets are the distance of the
 * beam origin above the optical centre: documented for HDL-32E and Puck
 * Hi-Res; focal distance * tan(-elevation) for the others, which reproduces
 * the documented VLP-16 values. */
#include "roadscan/sensor/sensor.h"

#include "roadscan/util/error.h"

#include <ctype.h>
#include <math.h>
#include <string.h>

#define DEG2RAD (3.14159265358979323846 / 180.0)

static const rs_model_info_t model_table[RS_MODEL_COUNT] = {
    [RS_MODEL_UNKNOWN] = {RS_MODEL_UNKNOWN, "unknown", 0x00, 0, 0.0f, 0.0f, 0, 0, 0.0f, 0.0f},
    [RS_MODEL_VLP16] = {RS_MODEL_VLP16, "VLP-16", 0x22, 16, 0.002f, 55.296f, 2, 1, 5.0f, 20.0f},
    [RS_MODEL_PUCK_HIRES] = {RS_MODEL_PUCK_HIRES, "Puck-Hi-Res", 0x24, 16, 0.002f, 55.296f, 2, 1, 5.0f, 20.0f},
    [RS_MODEL_HDL32E] = {RS_MODEL_HDL32E, "HDL-32E", 0x21, 32, 0.002f, 46.08f, 1, 1, 5.0f, 20.0f},
    [RS_MODEL_VLP32C] = {RS_MODEL_VLP32C, "VLP-32C", 0x28, 32, 0.004f, 55.296f, 1, 1, 5.0f, 20.0f},
    [RS_MODEL_VLS128] = {RS_MODEL_VLS128, "VLS-128", 0xA1, 128, 0.004f, 53.3f, 1, 4, 5.0f, 20.0f},
};

static const float vlp16_el[16] = {-15, 1, -13, 3, -11, 5, -9, 7, -7, 9, -5, 11, -3, 13, -1, 15};

static const float hires_el[16] = {-10,     0.667f, -8.667f, 2,  -7.333f, 3.333f, -6, 4.667f,
                                   -4.667f, 6,      -3.333f, 7.333f, -2, 8.667f, -0.667f, 10};
static const float hires_voff_mm[16] = {7.4f, -0.9f, 6.5f, -1.8f, 5.5f, -2.7f, 4.6f, -3.7f,
                                        3.7f, -4.6f, 2.7f, -5.5f, 1.8f, -6.5f, 0.9f, -7.4f};

static const float hdl32_el[32] = {-30.67f, -9.33f, -29.33f, -8.00f, -28.00f, -6.67f, -26.67f, -5.33f,
                                   -25.33f, -4.00f, -24.00f, -2.67f, -22.67f, -1.33f, -21.33f, 0.00f,
                                   -20.00f, 1.33f,  -18.67f, 2.67f,  -17.33f, 4.00f,  -16.00f, 5.33f,
                                   -14.67f, 6.67f,  -13.33f, 8.00f,  -12.00f, 9.33f,  -10.67f, 10.67f};
static const float hdl32_voff_mm[32] = {17.17f, 4.76f,  16.27f, 4.07f,  15.4f,  3.38f,  14.54f, 2.7f,
                                        13.71f, 2.02f,  12.89f, 1.35f,  12.09f, 0.67f,  11.31f, 0.0f,
                                        10.54f, -0.67f, 9.78f,  -1.35f, 9.04f,  -2.02f, 8.3f,   -2.7f,
                                        7.58f,  -3.38f, 6.86f,  -4.07f, 6.15f,  -4.76f, 5.45f,  -5.45f};

static const float vlp32c_el[32] = {-25,     -1,     -1.667f, -15.639f, -11.31f, 0,      -0.667f, -8.843f,
                                    -7.254f, 0.333f, -0.333f, -6.148f,  -5.333f, 1.333f, 0.667f,  -4,
                                    -4.667f, 1.667f, 1,       -3.667f,  -3.333f, 3.333f, 2.333f,  -2.667f,
                                    -3,      7,      4.667f,  -2.333f,  -2,      15,     10.333f, -1.333f};
static const float vlp32c_az[32] = {1.4f,  -4.2f, 1.4f,  -1.4f, 1.4f,  -1.4f, 4.2f,  -1.4f,
                                    1.4f,  -4.2f, 1.4f,  -1.4f, 4.2f,  -1.4f, 4.2f,  -1.4f,
                                    1.4f,  -4.2f, 1.4f,  -4.2f, 4.2f,  -1.4f, 1.4f,  -1.4f,
                                    1.4f,  -1.4f, 1.4f,  -4.2f, 4.2f,  -1.4f, 1.4f,  -1.4f};

static const float vls128_el[128] = {
    -11.742f, -1.99f,  3.4f,    -5.29f,  -0.78f,  4.61f,    -4.08f,  1.31f,    /*   0 */
    -6.5f,    -1.11f,  4.28f,   -4.41f,  0.1f,    6.48f,    -3.2f,   2.19f,    /*   8 */
    -3.86f,   1.53f,   -9.244f, -1.77f,  2.74f,   -5.95f,   -0.56f,  4.83f,    /*  16 */
    -2.98f,   2.41f,   -6.28f,  -0.89f,  3.62f,   -5.07f,   0.32f,   7.58f,    /*  24 */
    -0.34f,   5.18f,   -3.64f,  1.75f,   -25.0f,  -2.43f,   2.96f,   -5.73f,   /*  32 */
    0.54f,    9.7f,    -2.76f,  2.63f,   -7.65f,  -1.55f,   3.84f,   -4.85f,   /*  40 */
    3.18f,    -5.51f,  -0.12f,  5.73f,   -4.3f,   1.09f,    -16.042f, -2.21f,  /*  48 */
    4.06f,    -4.63f,  0.76f,   15.0f,   -3.42f,  1.97f,    -6.85f,  -1.33f,   /*  56 */
    -5.62f,   -0.23f,  5.43f,   -3.53f,  0.98f,   -19.582f, -2.32f,  3.07f,    /*  64 */
    -4.74f,   0.65f,   11.75f,  -2.65f,  1.86f,   -7.15f,   -1.44f,  3.95f,    /*  72 */
    -2.1f,    3.29f,   -5.4f,   -0.01f,  4.5f,    -4.19f,   1.2f,    -13.565f, /*  80 */
    -1.22f,   4.17f,   -4.52f,  0.87f,   6.08f,   -3.31f,   2.08f,   -6.65f,   /*  88 */
    1.42f,    -10.346f, -1.88f, 3.51f,   -6.06f,  -0.67f,   4.72f,   -3.97f,   /*  96 */
    2.3f,     -6.39f,  -1.0f,   4.39f,   -5.18f,  0.21f,    6.98f,   -3.09f,   /* 104 */
    4.98f,    -3.75f,  1.64f,   -8.352f, -2.54f,  2.85f,    -5.84f,  -0.45f,   /* 112 */
    8.43f,    -2.87f,  2.52f,   -6.17f,  -1.66f,  3.73f,    -4.96f,  0.43f,    /* 120 */
};
/* VLS-128 azimuth offsets repeat with the laser index modulo 8. */
static const float vls128_az8[8] = {6.354f, 4.548f, 2.732f, 0.911f, -0.911f, -2.732f, -4.548f, -6.354f};

/* Focal distances (m) for the vertical offsets not tabulated above. */
#define VLP16_FOCAL_M 0.04191f
#define VLP32C_FOCAL_M 0.0424f
#define VLS128_FOCAL_M 0.05863f

_Static_assert(sizeof(vls128_el) / sizeof(vls128_el[0]) == 128, "VLS-128 table");
_Static_assert(RS_MAX_LASERS <= 255, "row index fits in uint8_t");

const rs_model_info_t *rs_model_info(rs_model_t m) {
  if ((int)m <= RS_MODEL_UNKNOWN || (int)m >= RS_MODEL_COUNT) return NULL;
  return &model_table[m];
}

rs_model_t rs_model_from_product(uint8_t product) {
  for (int m = RS_MODEL_UNKNOWN + 1; m < RS_MODEL_COUNT; m++)
    if (model_table[m].product_id == product) return (rs_model_t)m;
  return RS_MODEL_UNKNOWN;
}

const char *rs_model_name(rs_model_t m) {
  const rs_model_info_t *mi = rs_model_info(m);
  return mi ? mi->name : "unknown";
}

const char *rs_model_names(void) { return "VLP-16, Puck-Hi-Res, HDL-32E, VLP-32C, VLS-128"; }

/* Lower-case, without '-', '_', ' ' and '.' */
static void squash(const char *in, char *out, size_t n) {
  size_t j = 0;
  for (size_t i = 0; in[i] != '\0' && j + 1 < n; i++) {
    char c = in[i];
    if (c == '-' || c == '_' || c == ' ' || c == '.') continue;
    out[j++] = (char)tolower((unsigned char)c);
  }
  out[j] = '\0';
}

rs_model_t rs_model_from_name(const char *name) {
  static const struct {
    const char *alias;
    rs_model_t m;
  } aliases[] = {
      {"vlp16", RS_MODEL_VLP16},         {"puck", RS_MODEL_VLP16},
      {"pucklite", RS_MODEL_VLP16},      {"puckhires", RS_MODEL_PUCK_HIRES},
      {"vlp16hires", RS_MODEL_PUCK_HIRES}, {"hires", RS_MODEL_PUCK_HIRES},
      {"hdl32e", RS_MODEL_HDL32E},       {"hdl32", RS_MODEL_HDL32E},
      {"vlp32c", RS_MODEL_VLP32C},       {"ultrapuck", RS_MODEL_VLP32C},
      {"vls128", RS_MODEL_VLS128},       {"alphaprime", RS_MODEL_VLS128},
  };
  if (name == NULL) return RS_MODEL_UNKNOWN;
  char buf[32];
  squash(name, buf, sizeof buf);
  for (size_t i = 0; i < sizeof aliases / sizeof aliases[0]; i++)
    if (strcmp(buf, aliases[i].alias) == 0) return aliases[i].m;
  return RS_MODEL_UNKNOWN;
}

float rs_model_group_us(const rs_model_info_t *mi) { return mi->cycle_us * (float)mi->cycles_per_block; }

static float focal_offset(float focal_m, float el_deg) { return focal_m * (float)tan(-el_deg * DEG2RAD); }

int rs_sensor_init(rs_sensor_t *s, rs_model_t m) {
  const rs_model_info_t *mi = rs_model_info(m);
  if (mi == NULL) return RS_E_INVAL;
  memset(s, 0, sizeof *s);
  s->info = mi;
  s->lasers = mi->lasers;
  s->dist_res_m = mi->dist_res_m;
  for (int i = 0; i < mi->lasers; i++) {
    float el = 0.0f, az = 0.0f, voff = 0.0f;
    switch (m) {
    case RS_MODEL_VLP16: el = vlp16_el[i]; voff = focal_offset(VLP16_FOCAL_M, el); break;
    case RS_MODEL_PUCK_HIRES: el = hires_el[i]; voff = hires_voff_mm[i] * 1e-3f; break;
    case RS_MODEL_HDL32E: el = hdl32_el[i]; voff = hdl32_voff_mm[i] * 1e-3f; break;
    case RS_MODEL_VLP32C:
      el = vlp32c_el[i];
      az = vlp32c_az[i];
      voff = focal_offset(VLP32C_FOCAL_M, el);
      break;
    case RS_MODEL_VLS128:
      el = vls128_el[i];
      az = vls128_az8[i % 8];
      voff = focal_offset(VLS128_FOCAL_M, el);
      break;
    default: return RS_E_INVAL;
    }
    s->elevation_deg[i] = el;
    s->azimuth_offset_deg[i] = az;
    s->vert_offset_m[i] = voff;
  }
  rs_sensor_finish(s);
  return RS_OK;
}

void rs_sensor_finish(rs_sensor_t *s) {
  int n = s->lasers;
  for (int i = 0; i < n; i++) {
    double el = s->elevation_deg[i] * DEG2RAD;
    s->cos_el[i] = (float)cos(el);
    s->sin_el[i] = (float)sin(el);
    s->laser_of_row[i] = (uint8_t)i;
  }
  /* insertion sort by (elevation, laser id): n <= 128, once at start-up */
  for (int i = 1; i < n; i++) {
    uint8_t l = s->laser_of_row[i];
    int j = i - 1;
    while (j >= 0 && s->elevation_deg[s->laser_of_row[j]] > s->elevation_deg[l]) {
      s->laser_of_row[j + 1] = s->laser_of_row[j];
      j--;
    }
    s->laser_of_row[j + 1] = l;
  }
  for (int r = 0; r < n; r++) s->row_of_laser[s->laser_of_row[r]] = (uint8_t)r;
}

void rs_sensor_record(const rs_sensor_t *s, int bank, int rec, int *laser, float *t_us) {
  switch (s->info->model) {
  case RS_MODEL_VLP16:
  case RS_MODEL_PUCK_HIRES:
    /* two firing cycles of 16 lasers, 2.304 µs apart, cycle 55.296 µs */
    *laser = rec % 16;
    *t_us = (float)(rec / 16) * 55.296f + (float)(rec % 16) * 2.304f;
    break;
  case RS_MODEL_HDL32E:
    /* 32 lasers fired one after the other every 1.152 µs */
    *laser = rec;
    *t_us = (float)rec * 1.152f;
    break;
  case RS_MODEL_VLP32C:
    /* lasers fire in pairs every 2.304 µs */
    *laser = rec;
    *t_us = (float)(rec / 2) * 2.304f;
    break;
  case RS_MODEL_VLS128: {
    /* 16 firing groups of 8 lasers every 2.665 µs, one idle slot after group 8 */
    int l = bank * 32 + rec;
    *laser = l;
    *t_us = 2.665f * (float)(l / 8 + l / 64);
    break;
  }
  default:
    *laser = rec;
    *t_us = 0.0f;
    break;
  }
}

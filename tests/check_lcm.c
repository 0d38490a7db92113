/* check_lcm - object lists over real LCM (memq:// in process): the encoded
 * list decodes back to the objects, truncation keeps the largest clusters
 * within one datagram, bad settings are refused with the reason, untrusted
 * bytes are checked before decoding; and the whole pipeline on a simulated
 * capture publishes one list per frame whose centroids agree with the
 * simulator's ground truth. */
#include "roadscan/util/error.h"
#include "roadscan/output/lcmcheck.h"
#include "roadscan/perception/objects.h"
#include "roadscan/daemon/pipeline.h"
#include "roadscan/output/publish.h"
#include "testutil.h"
#include "lcmsample.h"

#include <lcm/eventlog.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static rs_publish_t pub;
static rs_object_list_t list;
static rs_frame_meta_t meta;

/* what a raw subscriber received */
#define MAX_MSGS 400
static struct {
  int n;
  int len[MAX_MSGS];
  uint8_t *data[MAX_MSGS];
} rx;

static void on_raw(const lcm_recv_buf_t *rbuf, const char *channel, void *user) {
  (void)channel;
  (void)user;
  if (rx.n == MAX_MSGS) return;
  rx.data[rx.n] = malloc(rbuf->data_size);
  memcpy(rx.data[rx.n], rbuf->data, rbuf->data_size);
  rx.len[rx.n++] = (int)rbuf->data_size;
}

/* track lists (and ends) of the pipeline test */
static struct {
  int n, ends;
  int len[MAX_MSGS];
  uint8_t *data[MAX_MSGS];
} trx;

static struct {
  int n;
  long forward, backward, entered;
  long x_forward, x_backward, x_speed; /* crossing events: each way, and with a spot speed */
} crx;

static void on_tracks(const lcm_recv_buf_t *rbuf, const char *channel, void *user) {
  (void)user;
  if (strcmp(channel, "TRK_CNT") == 0) {
    roadscan_counts_t c;
    ck_assert_int_eq(roadscan_counts_t_decode(rbuf->data, 0, (int)rbuf->data_size, &c), (int)rbuf->data_size);
    ck_assert_int_eq(c.num_lines, 2);
    ck_assert_int_eq(c.num_zones, 1);
    ck_assert_str_eq(c.zones[0].name, "centre");
    ck_assert_int_ge(c.zones[0].occupancy_max, c.zones[0].occupancy);
    for (int k = 0; k < 6; k++) crx.entered += c.zones[0].entered[k];
    ck_assert_int_gt(c.t_end, c.t_start);
    for (int l = 0; l < c.num_lines; l++)
      for (int k = 0; k < 6; k++) {
        crx.forward += c.lines[l].forward[k];
        crx.backward += c.lines[l].backward[k];
      }
    roadscan_counts_t_decode_cleanup(&c);
    crx.n++;
    return;
  }
  if (strcmp(channel, "TRK_X") == 0) { /* a crossing event: checked as a consumer does, then decoded */
    char why[RS_ERRMSG_SIZE];
    ck_assert_msg(rs_lcm_check(RS_LCM_CROSSING, rbuf->data, (int)rbuf->data_size, why, sizeof why), "%s", why);
    roadscan_crossing_t x;
    ck_assert_int_eq(roadscan_crossing_t_decode(rbuf->data, 0, (int)rbuf->data_size, &x), (int)rbuf->data_size);
    ck_assert(strcmp(x.line, "east") == 0 || strcmp(x.line, "west") == 0);
    ck_assert(x.direction == 1 || x.direction == -1);
    ck_assert(x.class_id >= 0 && x.class_id < RS_CLASS_COUNT);
    ck_assert(x.how >= 0 && x.how <= 2);
    ck_assert(x.speed == -1.0f || (x.speed >= 0.0f && x.speed < 60.0f));
    ck_assert(x.at >= -0.01f && x.at <= 14.01f); /* along the 14 m lines */
    ck_assert_int_gt(x.track_id, 0);
    ck_assert_int_gt(x.t_cross, 1000000000000000LL); /* capture time, microseconds */
    crx.x_forward += x.direction > 0;
    crx.x_backward += x.direction < 0;
    crx.x_speed += x.speed >= 0.0f;
    roadscan_crossing_t_decode_cleanup(&x);
    return;
  }
  if (strcmp(channel, "TRK_END") == 0) {
    roadscan_track_end_t e;
    ck_assert_int_eq(roadscan_track_end_t_decode(rbuf->data, 0, (int)rbuf->data_size, &e), (int)rbuf->data_size);
    ck_assert_int_gt(e.id, 0);
    ck_assert_float_ge(e.duration, 0.0f);
    ck_assert_int_ge(e.t_last, e.t_first);
    roadscan_track_end_t_decode_cleanup(&e);
    trx.ends++;
    return;
  }
  if (trx.n == MAX_MSGS) return;
  trx.data[trx.n] = malloc(rbuf->data_size);
  memcpy(trx.data[trx.n], rbuf->data, rbuf->data_size);
  trx.len[trx.n++] = (int)rbuf->data_size;
}

static void rx_clear(void) {
  for (int i = 0; i < rx.n; i++) free(rx.data[i]);
  rx.n = 0;
}

static void drain(lcm_t *lcm) {
  while (lcm_handle_timeout(lcm, 0) > 0) {
  }
}

static void make_objects(uint32_t n) {
  memset(&list, 0, sizeof list);
  list.count = n;
  for (uint32_t k = 0; k < n; k++) {
    rs_object_t *o = &list.obj[k];
    o->id = k + 1;
    o->points = 10 + (k * 37) % 101; /* distinct enough, not sorted */
    o->sensor.centroid[0] = (float)k;
    o->sensor.centroid[1] = 2.0f * (float)k;
    o->sensor.centroid[2] = -1.5f;
    o->sensor.obb_length = 4.5f;
    o->sensor.obb_width = 1.8f;
    o->sensor.obb_heading = 0.25f;
    o->range_min = 7.0f + (float)k;
    o->az_start = 350.0f;
    o->az_end = 4.5f;
    o->row_min = 2;
    o->row_max = 9;
    o->col_start = 1790;
    o->col_end = 12;
    o->intensity_mean = 33.5f;
    o->t_first = 1700000000.123456;
    o->t_last = 1700000000.1300004;
  }
  memset(&meta, 0, sizeof meta);
  meta.seq = 42;
  meta.model = RS_MODEL_VLP32C;
  meta.t_first = 1700000000.1;
  meta.t_last = 1700000000.2;
  meta.packets = 151;
  meta.missing_packets = 3;
  meta.columns = 1700;
  meta.cols = 1820;
}

START_TEST(t_round_trip) {
  lcm_t *lcm = lcm_create("memq://");
  ck_assert_ptr_nonnull(lcm);
  lcm_subscription_t *sub = lcm_subscribe(lcm, "OBJ", on_raw, NULL);
  rs_publish_cfg_t cfg = {.channel = "OBJ", .stats_channel = "", .sensor_id = "north-pole", .lcm = lcm};
  ck_assert_int_eq(rs_publish_init(&pub, &cfg), RS_OK);
  make_objects(5);
  list.obj[2].points = 0; /* a label with no returns is not an object */
  ck_assert_int_eq(rs_publish_objects(&pub, &meta, &list, 123456789), RS_OK);
  drain(lcm);
  ck_assert_int_eq(rx.n, 1);
  ck_assert(rs_publish_list_plausible(rx.data[0], rx.len[0]));
  roadscan_object_list_t m;
  ck_assert_int_eq(roadscan_object_list_t_decode(rx.data[0], 0, rx.len[0], &m), rx.len[0]);
  ck_assert_str_eq(m.sensor_id, "north-pole");
  ck_assert_str_eq(m.sensor_model, "VLP-32C");
  ck_assert_int_eq(m.utime, 123456789);
  ck_assert_int_eq(m.frame_seq, 42);
  ck_assert_int_eq(m.t_first, 1700000000100000LL);
  ck_assert_int_eq(m.t_last, 1700000000200000LL);
  ck_assert_int_eq(m.packets, 151);
  ck_assert_int_eq(m.packets_missing, 3);
  ck_assert_int_eq(m.columns_covered, 1700);
  ck_assert_int_eq(m.columns, 1820);
  ck_assert(!m.truncated);
  ck_assert(!m.site_valid);
  ck_assert_int_eq(m.num_clusters, 4);
  ck_assert_int_eq(m.num_objects, 4);
  const int ids[4] = {1, 2, 4, 5};
  for (int i = 0; i < 4; i++) {
    const roadscan_object_t *w = &m.objects[i];
    const rs_object_t *o = &list.obj[ids[i] - 1];
    ck_assert_int_eq(w->id, ids[i]);
    ck_assert_int_eq(w->points, (int)o->points);
    ck_assert_float_eq(w->centroid[1], o->sensor.centroid[1]);
    ck_assert_float_eq(w->obb_heading, 0.25f);
    ck_assert_float_eq(w->range_min, o->range_min);
    ck_assert_float_eq(w->azimuth_start, 350.0f);
    ck_assert_int_eq(w->col_start, 1790);
    ck_assert_int_eq(w->col_end, 12);
    ck_assert_int_eq(w->row_max, 9);
    ck_assert_int_eq(w->t_first, 1700000000123456LL);
    ck_assert_int_eq(w->t_last, 1700000000130000LL);
  }
  roadscan_object_list_t_decode_cleanup(&m);
  /* statistics are off (empty channel): nothing else was sent */
  roadscan_frame_stats_t st;
  memset(&st, 0, sizeof st);
  st.sensor_id = "x";
  ck_assert_int_eq(rs_publish_stats(&pub, &st), RS_OK);
  drain(lcm);
  ck_assert_int_eq(rx.n, 1);
  ck_assert_uint_eq(pub.lists, 1);
  ck_assert_uint_eq(pub.stats, 0);
  rx_clear();
  rs_publish_deinit(&pub);
  lcm_unsubscribe(lcm, sub);
  lcm_destroy(lcm);
}
END_TEST

START_TEST(t_truncation) {
  lcm_t *lcm = lcm_create("memq://");
  lcm_subscription_t *sub = lcm_subscribe(lcm, "OBJ", on_raw, NULL);
  rs_publish_cfg_t cfg = {.channel = "OBJ", .max_datagram = 1400, .lcm = lcm};
  ck_assert_int_eq(rs_publish_init(&pub, &cfg), RS_OK);
  const uint32_t cap = pub.cap;
  ck_assert_uint_ge(cap, 3);
  ck_assert_uint_lt(cap, 20);
  rs_publish_t big;
  rs_publish_cfg_t bcfg = {.channel = "OBJ", .lcm = lcm};
  ck_assert_int_eq(rs_publish_init(&big, &bcfg), RS_OK);
  ck_assert_uint_gt(big.cap, 300); /* a 64 kB datagram holds hundreds */
  rs_publish_deinit(&big);
  /* exactly the cap: not truncated */
  make_objects(cap);
  ck_assert_int_eq(rs_publish_objects(&pub, &meta, &list, 1), RS_OK);
  /* three times the cap: the largest clusters are kept */
  make_objects(3 * cap);
  ck_assert_int_eq(rs_publish_objects(&pub, &meta, &list, 2), RS_OK);
  drain(lcm);
  ck_assert_int_eq(rx.n, 2);
  for (int i = 0; i < 2; i++) ck_assert_int_le(rx.len[i] + (int)strlen("OBJ") + 1, 1400);
  roadscan_object_list_t m;
  ck_assert_int_ge(roadscan_object_list_t_decode(rx.data[0], 0, rx.len[0], &m), 0);
  ck_assert(!m.truncated);
  ck_assert_int_eq(m.num_objects, (int)cap);
  roadscan_object_list_t_decode_cleanup(&m);
  ck_assert_int_ge(roadscan_object_list_t_decode(rx.data[1], 0, rx.len[1], &m), 0);
  ck_assert(m.truncated);
  ck_assert_int_eq(m.num_objects, (int)cap);
  ck_assert_int_eq(m.num_clusters, (int)(3 * cap));
  int32_t smallest_kept = INT32_MAX;
  for (int i = 0; i < m.num_objects; i++)
    if (m.objects[i].points < smallest_kept) smallest_kept = m.objects[i].points;
  /* nothing dropped is larger than anything kept */
  for (uint32_t k = 0; k < 3 * cap; k++) {
    bool kept = false;
    for (int i = 0; i < m.num_objects; i++) kept |= m.objects[i].id == (int32_t)k + 1;
    if (!kept) ck_assert_int_le((int)list.obj[k].points, smallest_kept);
  }
  roadscan_object_list_t_decode_cleanup(&m);
  ck_assert_uint_eq(pub.truncated_lists, 1);
  ck_assert_uint_eq(pub.objects_dropped, 2 * cap);
  rx_clear();
  rs_publish_deinit(&pub);
  lcm_unsubscribe(lcm, sub);
  lcm_destroy(lcm);
}
END_TEST

START_TEST(t_bad_settings) {
  struct {
    rs_publish_cfg_t cfg;
    int rc;
    const char *msg;
  } cases[] = {
      {{.url = "tcpq://localhost"}, RS_E_INVAL, "provider"},
      {{.url = "udpm://10.1.2.3:7667"}, RS_E_INVAL, "not an IPv4 multicast address"},
      {{.url = "udpm://239.255.76.67:99999"}, RS_E_INVAL, "bad port"},
      {{.url = "memq://", .channel = "has space"}, RS_E_INVAL, "channel"},
      {{.url = "memq://", .channel = ""}, RS_E_INVAL, "channel"},
      {{.url = "memq://", .max_datagram = 100}, RS_E_INVAL, "max datagram"},
      {{.url = "memq://", .max_datagram = 70000}, RS_E_INVAL, "max datagram"},
      {{.url = "memq://", .sensor_id = "a-sensor-id-that-is-far-too-long-to-be-useful-in-any-message-at-all"},
       RS_E_INVAL, "sensor id"},
  };
  for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
    ck_assert_int_eq(rs_publish_init(&pub, &cases[i].cfg), cases[i].rc);
    ck_assert_msg(strstr(pub.err, cases[i].msg) != NULL, "case %zu: '%s'", i, pub.err);
    rs_publish_deinit(&pub);
  }
  rs_publish_cfg_t ok = {.url = "memq://"};
  ck_assert_int_eq(rs_publish_init(&pub, &ok), RS_OK);
  ck_assert_str_eq(pub.channel, RS_PUB_DEFAULT_CHANNEL);
  ck_assert_str_eq(pub.stats_channel, RS_PUB_DEFAULT_STATS);
  rs_publish_deinit(&pub);
}
END_TEST

START_TEST(t_untrusted_bytes) {
  lcm_t *lcm = lcm_create("memq://");
  lcm_subscription_t *sub = lcm_subscribe(lcm, "OBJ", on_raw, NULL);
  rs_publish_cfg_t cfg = {.channel = "OBJ", .lcm = lcm};
  ck_assert_int_eq(rs_publish_init(&pub, &cfg), RS_OK);
  make_objects(3);
  ck_assert_int_eq(rs_publish_objects(&pub, &meta, &list, 1), RS_OK);
  drain(lcm);
  ck_assert_int_eq(rx.n, 1);
  uint8_t *b = rx.data[0];
  ck_assert(rs_publish_list_plausible(b, rx.len[0]));
  ck_assert(!rs_publish_list_plausible(b, 10));
  b[16] = 0x80; /* negative count */
  ck_assert(!rs_publish_list_plausible(b, rx.len[0]));
  b[16] = 0x00;
  b[17] = 0x10; /* a million objects in a few hundred bytes */
  ck_assert(!rs_publish_list_plausible(b, rx.len[0]));
  b[17] = 0x00;
  ck_assert(rs_publish_list_plausible(b, rx.len[0]));
  /* the sensor id's length (bytes 20-23): negative, past the end, and a string without its NUL */
  char why[RS_ERRMSG_SIZE];
  uint8_t save[4];
  memcpy(save, b + 20, 4);
  const uint8_t neg[4] = {0xff, 0xff, 0xff, 0xf0}, huge[4] = {0x00, 0x10, 0x00, 0x00};
  memcpy(b + 20, neg, 4);
  ck_assert(!rs_lcm_check(RS_LCM_OBJECT_LIST, b, rx.len[0], why, sizeof why));
  ck_assert_ptr_nonnull(strstr(why, "a string length out of range at byte 20"));
  memcpy(b + 20, huge, 4);
  ck_assert(!rs_lcm_check(RS_LCM_OBJECT_LIST, b, rx.len[0], why, sizeof why));
  memcpy(b + 20, save, 4);
  const int idlen = (int)save[3]; /* "roadscan" + NUL = 9 */
  b[24 + idlen - 1] = 'x';
  ck_assert(!rs_lcm_check(RS_LCM_OBJECT_LIST, b, rx.len[0], why, sizeof why));
  ck_assert_ptr_nonnull(strstr(why, "a string not ended by its NUL"));
  rx_clear();
  rs_publish_deinit(&pub);
  lcm_unsubscribe(lcm, sub);
  lcm_destroy(lcm);
}
END_TEST

/* roadscan-listen counts and skips what is not an object list, and goes on */
/* Every message type, encoded, then mutated 3000 times each (bytes flipped,
 * lengths and counts forged, cut, grown): whatever the checker passes the
 * generated decoder reads completely, within the bytes (ASan watches), and
 * the unmutated ones pass. */
static uint64_t next_rand(uint64_t *rng) {
  *rng ^= *rng << 13;
  *rng ^= *rng >> 7;
  *rng ^= *rng << 17;
  return *rng;
}

static int mutate(uint8_t *b, int len, int cap, uint64_t *rng) {
#define R() next_rand(rng)
  const int kind = (int)(R() % 5);
  if (kind == 0 && len > 0) b[R() % (uint64_t)len] ^= (uint8_t)(1u << (R() % 8));
  if (kind == 1 && len >= 4) { /* a 4-byte field forged: negative, zero, huge or off by one */
    const int at = (int)(R() % (uint64_t)(len - 3));
    static const uint32_t vals[] = {0xffffffffu, 0x80000000u, 0u, 0x7fffffffu, 1u, 0x00010000u};
    uint32_t v = vals[R() % 6];
    if (R() % 2) v = ((uint32_t)b[at] << 24 | (uint32_t)b[at + 1] << 16 | (uint32_t)b[at + 2] << 8 | b[at + 3]) + 1;
    b[at] = (uint8_t)(v >> 24);
    b[at + 1] = (uint8_t)(v >> 16);
    b[at + 2] = (uint8_t)(v >> 8);
    b[at + 3] = (uint8_t)v;
  }
  if (kind == 2 && len > 0) len = (int)(R() % (uint64_t)len);
  if (kind == 3 && len + 8 <= cap) len += (int)(R() % 8) + 1;
  if (kind == 4 && len > 0) b[R() % (uint64_t)len] = 0;
  return len;
#undef R
}

START_TEST(t_checked_decode_survives_mutations) {
  static uint8_t good[RS_LCM_TYPES][4096], b[4096 + 64];
  int glen[RS_LCM_TYPES];
  /* one of each, with strings and arrays */
  make_objects(3);
  rs_publish_cfg_t cfg = {.url = "memq://"};
  ck_assert_int_eq(rs_publish_init(&pub, &cfg), RS_OK);
  roadscan_object_list_t ol;
  rs_publish_fill(&pub, &meta, &list, 1, &ol);
  glen[RS_LCM_OBJECT_LIST] = roadscan_object_list_t_encode(good[RS_LCM_OBJECT_LIST], 0, 4096, &ol);
  roadscan_frame_stats_t st;
  memset(&st, 0, sizeof st);
  st.sensor_id = "north";
  static char *kinds[2] = {"payload-short", "block-flag"}; /* the variable-length part */
  static int64_t kind_counts[2] = {3, 7};
  st.num_errors = 2;
  st.error_kinds = kinds;
  st.error_counts = kind_counts;
  glen[RS_LCM_FRAME_STATS] = roadscan_frame_stats_t_encode(good[RS_LCM_FRAME_STATS], 0, 4096, &st);
  static rs_track_list_t tl;
  memset(&tl, 0, sizeof tl);
  tl.count = 2;
  tl.track[0].id = 5;
  tl.track[1].id = 9;
  roadscan_track_list_t tm;
  rs_publish_fill_tracks(&pub, &meta, &tl, 1, &tm);
  glen[RS_LCM_TRACK_LIST] = roadscan_track_list_t_encode(good[RS_LCM_TRACK_LIST], 0, 4096, &tm);
  roadscan_track_end_t te;
  memset(&te, 0, sizeof te);
  te.sensor_id = "north";
  glen[RS_LCM_TRACK_END] = roadscan_track_end_t_encode(good[RS_LCM_TRACK_END], 0, 4096, &te);
  roadscan_count_line_t lines[2];
  roadscan_count_zone_t zones[1];
  roadscan_counts_t cm;
  ts_sample_counts(&cm, lines, zones);
  glen[RS_LCM_COUNTS] = roadscan_counts_t_encode(good[RS_LCM_COUNTS], 0, 4096, &cm);
  roadscan_crossing_t xm;
  ts_sample_crossing(&xm);
  glen[RS_LCM_CROSSING] = roadscan_crossing_t_encode(good[RS_LCM_CROSSING], 0, 4096, &xm);
  rs_publish_deinit(&pub);
  char why[RS_ERRMSG_SIZE];
  uint64_t rng = 0x9e3779b97f4a7c15ull;
  int passed = 0, refused = 0;
  for (int t = 0; t < RS_LCM_TYPES; t++) {
    ck_assert_int_gt(glen[t], 8);
    ck_assert_msg(rs_lcm_check((rs_lcm_type_t)t, good[t], glen[t], why, sizeof why), "%s: %s",
                  rs_lcm_type_name((rs_lcm_type_t)t), why);
    for (int other = 0; other < RS_LCM_TYPES; other++) /* another type's bytes are refused */
      if (other != t) ck_assert(!rs_lcm_check((rs_lcm_type_t)other, good[t], glen[t], why, sizeof why));
    for (int k = 0; k < 3000; k++) {
      memcpy(b, good[t], (size_t)glen[t]);
      int len = glen[t];
      const int rounds = 1 + k % 3;
      for (int m = 0; m < rounds; m++) len = mutate(b, len, (int)sizeof b - 8, &rng);
      /* the decoder is handed exactly the message's bytes: a copy of len bytes on the heap */
      uint8_t *heap = malloc((size_t)len + 1);
      memcpy(heap, b, (size_t)len);
      if (!rs_lcm_check((rs_lcm_type_t)t, heap, len, why, sizeof why)) {
        refused++;
        free(heap);
        continue;
      }
      passed++;
      switch (t) {
      case RS_LCM_OBJECT_LIST: {
        roadscan_object_list_t d;
        ck_assert_int_eq(roadscan_object_list_t_decode(heap, 0, len, &d), len);
        ck_assert_int_eq((int)strlen(d.sensor_id), (int)strlen(d.sensor_id));
        roadscan_object_list_t_decode_cleanup(&d);
        break;
      }
      case RS_LCM_FRAME_STATS: {
        roadscan_frame_stats_t d;
        ck_assert_int_eq(roadscan_frame_stats_t_decode(heap, 0, len, &d), len);
        roadscan_frame_stats_t_decode_cleanup(&d);
        break;
      }
      case RS_LCM_TRACK_LIST: {
        roadscan_track_list_t d;
        ck_assert_int_eq(roadscan_track_list_t_decode(heap, 0, len, &d), len);
        roadscan_track_list_t_decode_cleanup(&d);
        break;
      }
      case RS_LCM_TRACK_END: {
        roadscan_track_end_t d;
        ck_assert_int_eq(roadscan_track_end_t_decode(heap, 0, len, &d), len);
        roadscan_track_end_t_decode_cleanup(&d);
        break;
      }
      case RS_LCM_COUNTS: {
        roadscan_counts_t d;
        ck_assert_int_eq(roadscan_counts_t_decode(heap, 0, len, &d), len);
        for (int l = 0; l < d.num_lines; l++) ck_assert_ptr_nonnull(memchr(d.lines[l].name, 0, 4097));
        for (int z = 0; z < d.num_zones; z++) ck_assert_ptr_nonnull(memchr(d.zones[z].name, 0, 4097));
        roadscan_counts_t_decode_cleanup(&d);
        break;
      }
      case RS_LCM_CROSSING: {
        roadscan_crossing_t d;
        ck_assert_int_eq(roadscan_crossing_t_decode(heap, 0, len, &d), len);
        ck_assert_ptr_nonnull(memchr(d.line, 0, 4097));
        roadscan_crossing_t_decode_cleanup(&d);
        break;
      }
      }
      free(heap);
    }
  }
  printf("lcm mutations: %d passed the check and decoded whole, %d refused\n", passed, refused);
  ck_assert_int_gt(refused, 5000);
  ck_assert_int_gt(passed, 100);
}
END_TEST

START_TEST(t_listener_rejects_garbage) {
  const char *path = tu_tmp("lcm-garbage.lcmlog");
  remove(path);
  lcm_eventlog_t *log = lcm_eventlog_create(path, "w");
  ck_assert_ptr_nonnull(log);
  rs_publish_cfg_t cfg = {.url = "memq://"};
  ck_assert_int_eq(rs_publish_init(&pub, &cfg), RS_OK);
  static uint8_t buf[RS_PUB_DATAGRAM_MAX], bad[64];
  int64_t n = 0;
  for (int f = 0; f < 6; f++) {
    void *data = buf;
    int len;
    make_objects(4);
    meta.seq = (uint64_t)f;
    roadscan_object_list_t m;
    rs_publish_fill(&pub, &meta, &list, 1, &m);
    if (f == 5) m.sensor_id = "gate \"north\" \\ 2"; /* JSON must escape it */
    len = roadscan_object_list_t_encode(buf, 0, (int)sizeof buf, &m);
    ck_assert_int_gt(len, 0);
    if (f == 1) { /* a few random-looking bytes */
      for (int i = 0; i < 40; i++) bad[i] = (uint8_t)(i * 73 + 11);
      data = bad;
      len = 40;
    } else if (f == 2) { /* a million objects claimed in a few hundred bytes */
      buf[17] = 0x10;
    } else if (f == 3) { /* another type's fingerprint */
      buf[0] ^= 0xff;
    } else if (f == 4) { /* cut short */
      len -= 50;
    }
    lcm_eventlog_event_t ev = {n++, 1700000000000000LL + f, 16, len, (char *)RS_PUB_DEFAULT_CHANNEL, data};
    ck_assert_int_eq(lcm_eventlog_write_event(log, &ev), 0);
  }
  /* statistics cut short (the decoder has allocated the sensor id by then) */
  roadscan_frame_stats_t st;
  memset(&st, 0, sizeof st);
  st.sensor_id = "north";
  int slen = roadscan_frame_stats_t_encode(buf, 0, (int)sizeof buf, &st);
  lcm_eventlog_event_t sev = {n++, 1700000000000009LL, 14, slen - 20, (char *)RS_PUB_DEFAULT_STATS, buf};
  ck_assert_int_eq(lcm_eventlog_write_event(log, &sev), 0);
  /* 21 bytes: the statistics' fingerprint, a time, a negative string length and a byte (crashed LCM's decoder) */
  uint8_t crash[21];
  memcpy(crash, buf, 16);
  crash[16] = 0x80;
  crash[17] = crash[18] = crash[19] = 0;
  crash[20] = 'x';
  lcm_eventlog_event_t cev = {n++, 1700000000000010LL, 14, 21, (char *)RS_PUB_DEFAULT_STATS, crash};
  ck_assert_int_eq(lcm_eventlog_write_event(log, &cev), 0);
  /* a track list, the same with a forged track count, counts of one line */
  static rs_track_list_t tl;
  memset(&tl, 0, sizeof tl);
  tl.count = 1;
  tl.track[0].id = 7;
  tl.track[0].state = RS_TRACK_CONFIRMED;
  roadscan_track_list_t tm;
  rs_publish_fill_tracks(&pub, &meta, &tl, 1, &tm);
  int tlen = roadscan_track_list_t_encode(buf, 0, (int)sizeof buf, &tm);
  lcm_eventlog_event_t tev = {n++, 1700000000000011LL, 15, tlen, (char *)RS_PUB_DEFAULT_TRACKS, buf};
  ck_assert_int_eq(lcm_eventlog_write_event(log, &tev), 0);
  static uint8_t forged[4096];
  memcpy(forged, buf, (size_t)tlen);
  const int at_num = tlen - (int)(__roadscan_track_t_encoded_array_size(&tm.tracks[0], 1)) - 4;
  forged[at_num] = 0x7f;
  lcm_eventlog_event_t fev = {n++, 1700000000000012LL, 15, tlen, (char *)RS_PUB_DEFAULT_TRACKS, forged};
  ck_assert_int_eq(lcm_eventlog_write_event(log, &fev), 0);
  roadscan_count_line_t cl;
  memset(&cl, 0, sizeof cl);
  cl.name = "east";
  cl.forward[3] = 2;
  roadscan_counts_t cm;
  memset(&cm, 0, sizeof cm);
  cm.sensor_id = "north";
  cm.num_lines = 1;
  cm.lines = &cl;
  int clen = roadscan_counts_t_encode(buf, 0, (int)sizeof buf, &cm);
  lcm_eventlog_event_t cnv = {n++, 1700000000000013LL, 15, clen, (char *)RS_PUB_DEFAULT_COUNTS, buf};
  ck_assert_int_eq(lcm_eventlog_write_event(log, &cnv), 0);
  /* a crossing event, then the same cut inside its line's name */
  roadscan_crossing_t xm;
  ts_sample_crossing(&xm);
  int xlen = roadscan_crossing_t_encode(buf, 0, (int)sizeof buf, &xm);
  lcm_eventlog_event_t xev = {n++, 1700000000000014LL, 18, xlen, (char *)RS_PUB_DEFAULT_CROSSINGS, buf};
  ck_assert_int_eq(lcm_eventlog_write_event(log, &xev), 0);
  lcm_eventlog_event_t xcut = {n++, 1700000000000015LL, 18, 8 + 8 + 10 + 6, (char *)RS_PUB_DEFAULT_CROSSINGS, buf};
  ck_assert_int_eq(lcm_eventlog_write_event(log, &xcut), 0);
  lcm_eventlog_destroy(log);
  rs_publish_deinit(&pub);
  char cmd[1024];
  const char *out;
  snprintf(cmd, sizeof cmd, "./roadscan-listen --log %s --json --stats", path);
  ck_assert_int_eq(tu_exec(cmd, &out), 0);
  ck_assert_ptr_nonnull(strstr(out, "lists 2, objects 8, gaps 0, stats 0, malformed 6"));
  ck_assert_ptr_nonnull(strstr(out, "a message of 21 bytes is not roadscan frame statistics (a string length out of range"));
  ck_assert_ptr_nonnull(strstr(out, "is not roadscan frame statistics (the message ends inside a field"));
  ck_assert_ptr_nonnull(strstr(out, "a message of 40 bytes is not a roadscan object list (not this type (fingerprint)"));
  ck_assert_ptr_nonnull(strstr(out, "\"frame_seq\":0,"));
  ck_assert_ptr_nonnull(strstr(out, "\"frame_seq\":5,"));
  ck_assert_ptr_nonnull(strstr(out, "\"sensor_id\":\"gate \\\"north\\\" \\\\ 2\","));
  /* with --tracks and --counts: the track list and the counts printed, the forged list refused */
  snprintf(cmd, sizeof cmd, "./roadscan-listen --log %s --tracks --counts", path);
  ck_assert_int_eq(tu_exec(cmd, &out), 0);
  ck_assert_ptr_nonnull(strstr(out, "track lists 1, track ends 0, counts 1"));
  ck_assert_ptr_nonnull(strstr(out, "track     7 confirmed"));
  ck_assert_ptr_nonnull(strstr(out, "line east forward 2, backward 0"));
  ck_assert_ptr_nonnull(strstr(out, "is not a roadscan track list (the message ends inside a field"));
  /* with --crossings: the event printed, the cut one refused; as JSON, its document */
  snprintf(cmd, sizeof cmd, "./roadscan-listen --log %s --crossings", path);
  ck_assert_int_eq(tu_exec(cmd, &out), 0);
  ck_assert_msg(strstr(out, "counts 0, crossings 1") != NULL, "%s", out);
  ck_assert_msg(strstr(out, "north crossing 1700000000.123 s: line east forward at 3.5 m, track 42 class 3, 9.25 m/s") !=
                    NULL, "%s", out);
  ck_assert_msg(strstr(out, "a message of 32 bytes is not a roadscan crossing (a string longer than the message") != NULL,
                "%s", out);
  snprintf(cmd, sizeof cmd, "./roadscan-listen --log %s --crossings --json", path);
  ck_assert_int_eq(tu_exec(cmd, &out), 0);
  ck_assert_msg(strstr(out, "\"schema\":\"roadscan.crossings/1\",\"sensor_id\":\"north\"") != NULL, "%s", out);
  ck_assert_msg(strstr(out, "\"line\":\"east\",\"t_cross_us\":1700000000123456,\"direction\":\"forward\",\"at_m\":3.5,"
                            "\"class\":\"car\",\"track_id\":42,\"speed_mps\":9.25,\"how\":\"seen\"") != NULL,
                "%s", out);
}
END_TEST

/* ---- the whole pipeline on a simulated capture ---- */

static rs_slot_t slots[4];
static rs_pipeline_t pipe;
static rs_bg_model_t model;
static rs_cluster_t cluster;
static rs_objects_t objects;
static rs_tracker_t tracker;
static rs_counter_t counter;

START_TEST(t_pipeline_end_to_end) {
  static tu_site_t site;
  tu_make_site("lcm-site", 31, 5, &site);
  tu_centroids_load(site.objects);
  char err[RS_ERRMSG_SIZE];
  ck_assert_int_eq(rs_bg_load(&model, site.model, err, sizeof err), RS_OK);
  rs_cluster_cfg_t ccfg;
  rs_cluster_cfg_default(&ccfg);
  ccfg.method = RS_CLUSTER_FSPC_ADAPTIVE;
  ck_assert_int_eq(rs_cluster_init(&cluster, &ccfg, NULL), RS_OK);
  rs_objects_init(&objects, NULL);
  lcm_t *lcm = lcm_create("memq://");
  lcm_subscription_t *sub = lcm_subscribe(lcm, "OBJ", on_raw, NULL);
  lcm_subscription_t *tsub = lcm_subscribe(lcm, "TRK.*", on_tracks, NULL);
  rs_publish_cfg_t pcfg = {.channel = "OBJ", .stats_channel = "", .tracks_channel = "TRK", .track_ends_channel = "TRK_END",
                           .counts_channel = "TRK_CNT", .crossings_channel = "TRK_X", .lcm = lcm};
  /* the site's roads, in the sensor frame (the intersection's centre is at 11.5, 11.5) */
  rs_count_line_t lines[2];
  char lerr[RS_ERRMSG_SIZE];
  ck_assert_int_eq(rs_count_parse_line("east 31.5 4.5 31.5 18.5", &lines[0], lerr, sizeof lerr), RS_OK);
  ck_assert_int_eq(rs_count_parse_line("west -8.5 4.5 -8.5 18.5", &lines[1], lerr, sizeof lerr), RS_OK);
  ck_assert_int_eq(rs_count_init(&counter, lines, 2, NULL, 1.0, lerr, sizeof lerr), RS_OK);
  rs_count_zone_t centre; /* the intersection's box */
  ck_assert_int_eq(rs_count_parse_zone("centre 4.5 4.5 18.5 4.5 18.5 18.5 4.5 18.5", &centre, lerr, sizeof lerr), RS_OK);
  ck_assert_int_eq(rs_count_add_zones(&counter, &centre, 1, lerr, sizeof lerr), RS_OK);
  rs_track_cfg_t tcfg;
  rs_track_cfg_default(&tcfg);
  ck_assert_int_eq(rs_track_init(&tracker, &tcfg), RS_OK);
  ck_assert_int_eq(rs_publish_init(&pub, &pcfg), RS_OK);
  rs_pipeline_cfg_t cfg;
  memset(&cfg, 0, sizeof cfg);
  cfg.pcap_path = site.pcap;
  cfg.lossless = true;
  cfg.capture.data_port = RS_DEFAULT_DATA_PORT;
  cfg.stream.data_port = RS_DEFAULT_DATA_PORT;
  cfg.stream.default_hz = cfg.assembly.default_hz = 10.0;
  cfg.background = &model;
  cfg.cluster = &cluster;
  cfg.objects = &objects;
  cfg.object_list = &list;
  cfg.tracker = &tracker;
  cfg.counter = &counter;
  cfg.publish = &pub;
  ck_assert_int_eq(rs_pipeline_init(&pipe, &cfg, slots, 4), RS_OK);
  ck_assert_int_eq(rs_pipeline_start(&pipe), RS_OK);
  rs_pipeline_join(&pipe);
  const uint64_t frames = pipe.proc.n.frames;
  rs_pipeline_deinit(&pipe);
  drain(lcm);
  /* one list per frame, in order */
  ck_assert_uint_ge(frames, 49);
  ck_assert_int_eq(rx.n, (int)frames);
  tu_centroids_t cent = {0, 0, 0, 0.0f};
  for (int i = 0; i < rx.n; i++) {
    roadscan_object_list_t m;
    ck_assert(rs_publish_list_plausible(rx.data[i], rx.len[i]));
    ck_assert_int_eq(roadscan_object_list_t_decode(rx.data[i], 0, rx.len[i], &m), rx.len[i]);
    ck_assert_int_eq(m.frame_seq, i);
    ck_assert(!m.truncated);
    for (int k = 0; k < m.num_objects && m.frame_seq > 0 && !m.partial; k++) {
      const roadscan_object_t *o = &m.objects[k];
      if (o->points < 50) continue; /* small clusters: parts of instances, foliage */
      tu_centroid_add(&cent, (long)m.frame_seq, o->centroid);
      /* the box holds the centroid; the oriented box is no larger than the aligned one allows */
      for (int a = 0; a < 3; a++) {
        ck_assert_float_le(o->box_min[a], o->centroid[a] + 1e-3f);
        ck_assert_float_ge(o->box_max[a], o->centroid[a] - 1e-3f);
      }
      ck_assert_float_ge(o->obb_length, o->obb_width);
    }
    roadscan_object_list_t_decode_cleanup(&m);
  }
  /* a cluster that misses part of a car (taken by the background or left as noise)
   * moves its centroid: the tolerance of tu_centroids_check */
  tu_centroids_check(&cent, "lcm (memq, in process)");
  /* one track list per frame, in order; ids unique in a list; objects followed
   * from list to list under one id; every track that ended confirmed said so */
  ck_assert_int_eq(trx.n, (int)frames);
  int longest = 0;
  static int run[RS_TRACK_MAX * 8];
  memset(run, 0, sizeof run);
  for (int i = 0; i < trx.n; i++) {
    roadscan_track_list_t m;
    ck_assert_int_eq(roadscan_track_list_t_decode(trx.data[i], 0, trx.len[i], &m), trx.len[i]);
    ck_assert_int_eq(m.frame_seq, i);
    ck_assert_int_ge(m.num_alive, m.num_tracks);
    static int seen_in[RS_TRACK_MAX * 8];
    for (int k = 0; k < m.num_tracks; k++) {
      const roadscan_track_t *t = &m.tracks[k];
      ck_assert_int_gt(t->id, 0);
      ck_assert_int_lt(t->id, RS_TRACK_MAX * 8);
      ck_assert_int_ne(seen_in[t->id], i + 1); /* once per list */
      seen_in[t->id] = i + 1;
      ck_assert(t->state >= 0 && t->state <= 2);
      ck_assert(t->class_id >= 0 && t->class_id < RS_CLASS_COUNT);
      ck_assert(isfinite(t->speed) && t->speed >= 0.0f && t->speed < 60.0f);
      ck_assert_float_ge(t->position_cov[0], 0.0f);
      if (t->state == 1) {
        run[t->id]++;
        if (run[t->id] > longest) longest = run[t->id];
      }
    }
    roadscan_track_list_t_decode_cleanup(&m);
  }
  ck_assert_int_ge(longest, 20); /* a vehicle followed for 2 s under one id */
  ck_assert_int_eq(trx.ends, (int)pub.track_ends);
  /* one counts message per interval of 1 s (the last one closed at the end), the sums the counter's */
  ck_assert_int_ge(crx.n, 5);
  ck_assert_int_eq(crx.n, (int)counter.intervals);
  long fwd = 0, bwd = 0;
  for (int l = 0; l < 2; l++)
    for (int k = 0; k < RS_CLASS_COUNT; k++) {
      fwd += counter.total[l].forward[k];
      bwd += counter.total[l].backward[k];
    }
  ck_assert_int_eq(crx.forward, fwd);
  ck_assert_int_eq(crx.backward, bwd);
  /* one crossing event per crossing counted, each way */
  ck_assert_int_eq(crx.x_forward, fwd);
  ck_assert_int_eq(crx.x_backward, bwd);
  ck_assert_int_eq(crx.x_forward + crx.x_backward, (long)pub.crossings);
  ck_assert_int_gt(fwd + bwd, 0);
  ck_assert_int_gt(crx.x_speed, 0);
  long entered = 0;
  for (int k = 0; k < RS_CLASS_COUNT; k++) entered += counter.zone_total[0].entered[k];
  ck_assert_int_eq(crx.entered, entered);
  ck_assert_int_gt(entered, 0); /* traffic crosses the intersection */
  printf("lcm: %d counts messages, %ld forward and %ld backward crossings, %ld entered the centre\n", crx.n, fwd, bwd,
         entered);
  for (int i = 0; i < trx.n; i++) free(trx.data[i]);
  trx.n = 0;
  lcm_unsubscribe(lcm, tsub);
  rx_clear();
  rs_publish_deinit(&pub);
  lcm_unsubscribe(lcm, sub);
  lcm_destroy(lcm);
  rs_bg_model_free(&model);
}
END_TEST

int main(void) {
  Suite *s = suite_create("lcm");
  TCase *tc = tcase_create("core");
  tcase_set_timeout(tc, 280);
  tcase_add_test(tc, t_round_trip);
  tcase_add_test(tc, t_truncation);
  tcase_add_test(tc, t_bad_settings);
  tcase_add_test(tc, t_untrusted_bytes);
  tcase_add_test(tc, t_listener_rejects_garbage);
  tcase_add_test(tc, t_checked_decode_survives_mutations);
  tcase_add_test(tc, t_pipeline_end_to_end);
  suite_add_tcase(s, tc);
  return tu_run(s);
}

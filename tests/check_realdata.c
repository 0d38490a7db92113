/* check_realdata - the real captures of ../shared/data (skipped when the
 * folder is absent): the sensor is identified, frames are cut where the
 * block azimuth field rolls over (counted here independently, straight
 * from the file), points per frame are steady, and consecutive frames of
 * the static sensors see the same scene; the model is identified from any
 * starting packet (a capture can start anywhere); a packet left out is the
 * frame's one run of unmeasured columns, at that packet's azimuths. */
#include "roadscan/util/error.h"
#include "roadscan/frame/frame.h"
#include "roadscan/capture/stream.h"
#include "roadscan/perception/objects.h"
#include "testutil.h"

#include <math.h>
#include <pcap/pcap.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

typedef struct {
  const char *file;
  rs_model_t model;
  double hz;
  bool static_sensor;
} capture_t;

static const capture_t caps[] = {
    {"sample_velodyne_vlp16_gps.pcap", RS_MODEL_VLP16, 10.0, true},
    {"vlp-16-test-90deg-1-50-frames.pcap", RS_MODEL_VLP16, 20.0, true},
    {"monterey-first-100-packets.pcap", RS_MODEL_HDL32E, 11.8, false},
};

/* Independent count: Ethernet/IPv4/UDP at fixed offsets, as these files are. */
static int rollovers_in_file(const char *path, int *data_packets) {
  char eb[PCAP_ERRBUF_SIZE];
  pcap_t *p = pcap_open_offline(path, eb);
  ck_assert_ptr_nonnull(p);
  struct pcap_pkthdr *h;
  const u_char *d;
  int prev = -1, rolls = 0;
  *data_packets = 0;
  while (pcap_next_ex(p, &h, &d) == 1) {
    if (h->caplen != 1248 || d[23] != 17 || ((d[36] << 8) | d[37]) != 2368) continue;
    (*data_packets)++;
    for (int b = 0; b < 12; b++) {
      int az = d[42 + b * 100 + 2] | (d[42 + b * 100 + 3] << 8);
      if (prev >= 0 && az < prev) rolls++;
      prev = az;
    }
  }
  pcap_close(p);
  return rolls;
}

static rs_stream_t st;
static rs_asm_t as;
static bool as_ready;
static rs_slot_t slots[2];
static int cur;
static rs_frame_meta_t metas[128];
static int nmeta;
static double agree_sum;
static int agree_n;
static double agree_min;

/* share of cells filled in both frames whose ranges agree within 10 cm */
static double agreement(const rs_slot_t *a, const rs_slot_t *b) {
  uint32_t both = 0, same = 0, cells = (uint32_t)a->meta.rows * a->meta.cols;
  for (uint32_t i = 0; i < cells; i++) {
    float ra = a->range[i], rb = b->range[i];
    if (ra == 0.0f || rb == 0.0f) continue;
    both++;
    same += fabsf(ra - rb) < 0.10f;
  }
  return both ? (double)same / both : 0.0;
}

/* t_lost_packet: the data packet not fed (at or after drop_from), its block azimuths, and the object
 * list of the frame that should have held it */
static uint32_t drop_from = UINT32_MAX, dropped = UINT32_MAX;
static uint16_t dropped_az[2];
static bool dropped_seen;
static rs_objects_t lost_objs;
static rs_object_list_t lost_list;

static void on_packet(void *user, const rs_packet_t *pkt, uint32_t index, double ts) {
  (void)user;
  if (index >= drop_from && dropped == UINT32_MAX) {
    dropped = index;
    dropped_az[0] = pkt->block_azimuth[0];
    dropped_az[1] = pkt->block_azimuth[pkt->blocks - 1];
    return;
  }
  if (!as_ready) {
    rs_asm_cfg_t cfg = {.default_hz = 10.0};
    ck_assert_int_eq(rs_asm_init(&as, &cfg, &st.sensor), RS_OK);
    as_ready = true;
  }
  while (rs_asm_feed(&as, &slots[cur], pkt, index, ts) == RS_ASM_FRAME_DONE) {
    metas[nmeta++] = slots[cur].meta;
    if (dropped != UINT32_MAX && !dropped_seen && slots[cur].meta.first_packet < dropped &&
        slots[cur].meta.last_packet > dropped) {
      rs_objects_extract(&lost_objs, &slots[cur], &st.sensor, &lost_list);
      dropped_seen = true;
    }
    if (nmeta >= 3 && !slots[cur ^ 1].meta.partial && !slots[cur].meta.partial) {
      double a = agreement(&slots[cur], &slots[cur ^ 1]);
      agree_sum += a;
      agree_n++;
      if (a < agree_min) agree_min = a;
    }
    cur ^= 1;
  }
  st.rate_hint = as.rate;
}

static int cmp_u32(const void *x, const void *y) {
  uint32_t a = *(const uint32_t *)x, b = *(const uint32_t *)y;
  return (a > b) - (a < b);
}

/* decodes and assembles a capture, leaving out its first data packet at or after index drop */
static void replay(const char *path, uint32_t drop) {
  rs_capture_cfg_t cc = {.data_port = 2368};
  rs_capture_t cap;
  ck_assert_int_eq(rs_capture_open_file(&cap, path, &cc), RS_OK);
  rs_stream_cfg_t sc = {0};
  rs_stream_init(&st, &sc);
  as_ready = false;
  cur = 0;
  nmeta = 0;
  agree_sum = 0;
  agree_n = 0;
  agree_min = 1.0;
  drop_from = drop;
  dropped = UINT32_MAX;
  dropped_seen = false;
  rs_frame_in_t f;
  while (rs_capture_next(&cap, &f, NULL) == 1) rs_stream_frame(&st, cap.linktype, &f, on_packet, NULL);
  rs_stream_finish(&st, on_packet, NULL);
  rs_capture_close(&cap);
  if (rs_asm_flush(&as, &slots[cur])) metas[nmeta++] = slots[cur].meta;
}

START_TEST(t_capture) {
  const capture_t *c = &caps[_i];
  char path[1024];
  snprintf(path, sizeof path, "%s/%s", tu_shared_data(), c->file);
  int data_packets = 0;
  int rolls = rollovers_in_file(path, &data_packets);

  replay(path, UINT32_MAX);

  ck_assert_int_eq(st.sensor.info->model, c->model);
  ck_assert_uint_eq(st.n.decoded, (uint64_t)data_packets);
  ck_assert_uint_eq(rs_stream_error_total(&st.n), 0);
  ck_assert_int_eq(nmeta, rolls + 1);
  ck_assert_uint_eq(as.missing_packets, 0);
  ck_assert_uint_eq(as.out_of_order + as.duplicates, 0);
  ck_assert_double_eq_tol(rs_hz_from_rate(as.rate), c->hz, 0.1);

  /* full frames: every column seen, steady point counts, few collisions */
  uint32_t pts[128];
  int nf = 0;
  for (int i = 1; i + 1 < nmeta; i++) {
    ck_assert(!metas[i].partial);
    /* the MRPT sample has no return at all in about 9 % of its azimuths */
    ck_assert_uint_ge(metas[i].columns * 100, metas[i].cols * 85u);
    ck_assert_uint_le(metas[i].collisions * 500, metas[i].points); /* < 0.2 % */
    pts[nf++] = metas[i].points;
  }
  ck_assert_int_ge(nf, 2);
  qsort(pts, (size_t)nf, sizeof pts[0], cmp_u32);
  uint32_t med = pts[nf / 2];
  for (int i = 0; i < nf; i++) ck_assert_msg(abs((int)pts[i] - (int)med) * 100 <= (int)med * 3, "frame points %u vs median %u", pts[i], med);

  /* the static sensors see the same scene frame after frame */
  if (c->static_sensor) {
    ck_assert_int_ge(agree_n, 1);
    ck_assert_msg(agree_min > 0.85, "consecutive frames agree on only %.1f%% of cells", agree_min * 100);
  }
  fprintf(stderr, "%s: %s %.2f Hz, %d frames, median %u points, range agreement min %.3f mean %.3f\n", c->file,
          st.sensor.info->name, rs_hz_from_rate(as.rate), nmeta, med, agree_min, agree_n ? agree_sum / agree_n : 0);
}
END_TEST

/* One data packet left out in the middle of each real capture (a lost packet): the frame that should
 * have held it lists one run of unmeasured columns (rs_object_list_t.gap, for the tracker's
 * gap_unseen), and it spans that packet's block azimuths, read from the packet: from its first block's
 * to one block step past its last, within a block step (a VLP-16's and an HDL-32E's rows fire at the
 * block's azimuth). No other frame has one. */
START_TEST(t_lost_packet) {
  const capture_t *c = &caps[_i];
  char path[1024];
  snprintf(path, sizeof path, "%s/%s", tu_shared_data(), c->file);
  int data_packets = 0;
  rollovers_in_file(path, &data_packets);
  rs_objects_init(&lost_objs, NULL);
  replay(path, (uint32_t)data_packets / 2);
  ck_assert_uint_ne(dropped, UINT32_MAX);
  ck_assert(dropped_seen);
  ck_assert_uint_eq(as.missing_packets, 1);
  ck_assert_uint_eq(lost_list.ngaps, 1);
  const double deg = 360.0 / lost_list.gap_cols;
  const double a0 = dropped_az[0] / 100.0, a1 = dropped_az[1] / 100.0;
  const double step = (a1 >= a0 ? a1 - a0 : a1 + 360.0 - a0) / 11.0; /* 12 blocks */
  const double g0 = lost_list.gap[0][0] * deg, g1 = (lost_list.gap[0][1] + 1) * deg;
  fprintf(stderr, "%s: packet %u left out (blocks %.2f-%.2f deg): unmeasured %.2f-%.2f deg\n", c->file, dropped, a0, a1, g0, g1);
  ck_assert_double_le(fabs(g0 - a0), step + deg);
  ck_assert_double_le(fabs(g1 - (a1 + step)), step + deg);
}
END_TEST

/* foreground returns over the complete frames from..to of a frames CSV
 * (foreground column), their points and their clusters */
static long foreground_in(const char *csv, int from, int to, long *points, long *clusters, long *frames) {
  FILE *f = fopen(csv, "r");
  ck_assert_ptr_nonnull(f);
  char line[1024];
  long fg = 0;
  *points = *clusters = *frames = 0;
  ck_assert_ptr_nonnull(fgets(line, sizeof line, f)); /* header */
  while (fgets(line, sizeof line, f)) {
    /* frame is column 1, points 5, partial 14, foreground 26, clusters 27 */
    char *col[32];
    int n = 0;
    for (char *t = strtok(line, ","); t && n < 32; t = strtok(NULL, ",")) col[n++] = t;
    ck_assert_int_eq(n, 29);
    int fr = atoi(col[0]);
    if (fr < from || fr > to || atoi(col[13]) != 0) continue;
    *points += atol(col[4]);
    fg += atol(col[25]);
    *clusters += atol(col[26]);
    (*frames)++;
  }
  fclose(f);
  return fg;
}

/* The learned background is never worse than the per-cell percentile
 * baseline on a real capture of a static scene, and leaves at most 0.5 % of
 * the returns foreground: the 90-degree VLP-16 while it stands still
 * (learned from its first second, frames 21-34 labelled), its last second,
 * where the sensor moves by up to 8 cm (learned from the first 1.5 s: the
 * shift rule, background.h; docs/background.md), all of it (0.75 %: learned
 * from frames taken from two positions), and the MRPT VLP-16 (3 frames,
 * learned and labelled). In the last second, what the moved sensor sees
 * behind a near object is background too: at most 0.5 clusters per frame
 * there, as on the MRPT capture (in the static part a person stands beside
 * the sensor: no such bound). */
START_TEST(t_background_vs_percentile) {
  static const struct {
    const char *file, *learn;
    int from, to;
    double max_share;    /* foreground share the learned model stays under */
    double max_clusters; /* ... and clusters per frame (0: not bounded) */
  } c[] = {/* the static part; then the last second, where the sensor moves by up to 8 cm (the
              shift rule), learned from the first 1.5 s; then all of it, learned from all of it */
           {"vlp-16-test-90deg-1-50-frames.pcap", "--seconds 1", 21, 34, 0.005, 0},
           {"vlp-16-test-90deg-1-50-frames.pcap", "--seconds 1.5", 31, 50, 0.005, 0.5},
           {"vlp-16-test-90deg-1-50-frames.pcap", "", 1, 50, 0.0075, 0},
           {"sample_velodyne_vlp16_gps.pcap", "", 1, 99, 0.005, 0.5}};
  for (size_t i = 0; i < sizeof c / sizeof c[0]; i++) {
    long fg[2], pts[2], clusters[2], frames[2];
    for (int m = 0; m < 2; m++) {
      char cmd[4096];
      const char *out, *model = tu_tmp("real.bg"), *csv = tu_tmp("real-frames.csv");
      snprintf(cmd, sizeof cmd,
               "./roadscan-learn %s/%s -o %s %s --method %s && ./roadscand --pcap %s/%s --fast --background %s "
               "--no-publish --quiet --frames-out %s",
               tu_shared_data(), c[i].file, model, c[i].learn, m ? "percentile" : "dbscan", tu_shared_data(), c[i].file,
               model, csv);
      ck_assert_int_eq(tu_exec(cmd, &out), 0);
      fg[m] = foreground_in(csv, c[i].from, c[i].to, &pts[m], &clusters[m], &frames[m]);
    }
    fprintf(stderr,
            "%s, frames %d-%d: foreground %ld of %ld returns (%.2f %%), %.2f clusters per frame learned, %ld (%.2f %%), "
            "%.2f percentile\n",
            c[i].file, c[i].from, c[i].to, fg[0], pts[0], 100.0 * fg[0] / pts[0], (double)clusters[0] / frames[0], fg[1],
            100.0 * fg[1] / pts[1], (double)clusters[1] / frames[1]);
    ck_assert_int_gt(pts[0], 10000);
    ck_assert_int_le(fg[0], fg[1]);
    ck_assert_double_le((double)fg[0] / pts[0], c[i].max_share);
    if (c[i].max_clusters > 0) ck_assert_double_le((double)clusters[0] / frames[0], c[i].max_clusters);
  }
}
END_TEST

/* The ground the daemon finds in a model learned from a real capture (ground.h): the Monterey HDL-32E,
 * on a car, 1.5-3 m above a street, the plane holding at least half the cells near it (picking the level
 * of the cells its level beam (0 degrees) puts on walls said 0 m once); the MRPT VLP-16 has 95 % of its
 * returns within 2.3 m: no ground, and the summary says so. */
START_TEST(t_ground) {
  static const struct {
    const char *file;
    bool found;
  } c[] = {{"monterey-first-100-packets.pcap", true}, {"sample_velodyne_vlp16_gps.pcap", false}};
  for (size_t i = 0; i < sizeof c / sizeof c[0]; i++) {
    char cmd[4096];
    const char *out, *model = tu_tmp("ground.bg");
    snprintf(cmd, sizeof cmd, "./roadscan-learn %s/%s -o %s && ./roadscand --pcap %s/%s --fast --background %s --no-publish",
             tu_shared_data(), c[i].file, model, tu_shared_data(), c[i].file, model);
    ck_assert_int_eq(tu_exec(cmd, &out), 0);
    double h = 0, up = 0, toward = 0, on = 0;
    const bool found = tu_ground_line(out, &h, &up, &toward, &on);
    if (!c[i].found) {
      ck_assert_msg(!found && strstr(out, "ground: not found in the model") != NULL, "%s: %s", c[i].file, out);
      continue;
    }
    ck_assert_msg(found, "%s: no ground in %s", c[i].file, out);
    fprintf(stderr, "%s: the sensor %.2f m above the ground, rising %.2f deg, %.0f %% of the near cells on it\n",
            c[i].file, h, up, on);
    ck_assert_double_ge(h, 1.5);
    ck_assert_double_le(h, 3.0);
    ck_assert_double_ge(on, 50.0);
  }
}
END_TEST

/* The data payloads of a capture (Ethernet/IPv4/UDP at fixed offsets). */
static uint8_t (*payloads)[1206];
static int read_payloads(const char *path) {
  char eb[PCAP_ERRBUF_SIZE];
  pcap_t *p = pcap_open_offline(path, eb);
  ck_assert_ptr_nonnull(p);
  struct pcap_pkthdr *h;
  const u_char *d;
  int n = 0, cap = 4096;
  payloads = malloc((size_t)cap * sizeof *payloads);
  ck_assert_ptr_nonnull(payloads);
  while (pcap_next_ex(p, &h, &d) == 1 && n < cap) {
    if (h->caplen != 1248 || d[23] != 17 || ((d[36] << 8) | d[37]) != 2368) continue;
    memcpy(payloads[n++], d + 42, 1206);
  }
  pcap_close(p);
  return n;
}

/* Both captures whose product byte is 0x21 (an early VLP-16 and an HDL-32E),
 * started at every data packet: the detector names the right model every
 * time, from at least RS_DETECT_MIN_PACKETS packets. */
START_TEST(t_detect_any_start) {
  static const struct {
    const char *file;
    rs_model_t model;
  } c[] = {{"vlp-16-test-90deg-1-50-frames.pcap", RS_MODEL_VLP16}, {"monterey-first-100-packets.pcap", RS_MODEL_HDL32E}};
  for (size_t i = 0; i < sizeof c / sizeof c[0]; i++) {
    char path[1024];
    snprintf(path, sizeof path, "%s/%s", tu_shared_data(), c[i].file);
    int n = read_payloads(path), wrong = 0, starts = 0, most = 0;
    ck_assert_int_gt(n, 100);
    for (int k = 0; k + RS_DETECT_MAX_PACKETS <= n; k++, starts++) {
      rs_detect_t d;
      rs_detect_init(&d, RS_MODEL_UNKNOWN);
      int r = RS_MODEL_UNKNOWN, used = 0;
      for (int j = k; j < n && r == RS_MODEL_UNKNOWN; j++, used++) r = rs_detect_feed(&d, payloads[j], 1206);
      if (r != (int)c[i].model) {
        if (wrong++ == 0) fprintf(stderr, "%s from packet %d: %s (%s)\n", c[i].file, k, rs_model_name((rs_model_t)r), d.reason);
      }
      ck_assert_int_ge(used, RS_DETECT_MIN_PACKETS);
      if (used > most) most = used;
    }
    fprintf(stderr, "%s: %s from all %d starting packets (%d wrong), decided within %d packets\n", c[i].file,
            rs_model_name(c[i].model), starts, wrong, most);
    ck_assert_int_eq(wrong, 0);
    free(payloads);
  }
}
END_TEST

int main(void) {
  if (tu_shared_data() == NULL) {
    fprintf(stderr, "check_realdata: %s not present, real-capture tests skipped\n", RS_SHARED_DATA);
    return 77;
  }
  Suite *s = suite_create("realdata");
  TCase *tc = tcase_create("captures");
  tcase_set_timeout(tc, 120);
  tcase_add_loop_test(tc, t_capture, 0, (int)(sizeof caps / sizeof caps[0]));
  tcase_add_test(tc, t_detect_any_start);
  tcase_add_loop_test(tc, t_lost_packet, 0, (int)(sizeof caps / sizeof caps[0]));
  tcase_add_test(tc, t_background_vs_percentile);
  tcase_add_test(tc, t_ground);
  suite_add_tcase(s, tc);
  return tu_run(s);
}

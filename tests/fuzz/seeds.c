/* seeds.c - writes the fuzz targets' starting inputs into DIR/<target>/,
 * made by the project's own encoders: payloads of every model and return
 * mode, small captures of every link type, one message of every LCM type, a
 * calibration file, a background model, a label file, maps with objects,
 * option values. Run before the corpus replay tests and by scripts/fuzz.sh. */
#include "roadscan/perception/background.h"
#include "roadscan/perception/count.h"
#include "roadscan/util/error.h"
#include "roadscan/output/lcmcheck.h"
#include "roadscan/capture/net.h"
#include "roadscan/output/publish.h"
#include "roadscan/sim/synth.h"
#include "../lcmsample.h"

#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

static char dir[512];

static FILE *open_seed(const char *target, const char *name) {
  char p[1024];
  snprintf(p, sizeof p, "%s/%s", dir, target);
  mkdir(p, 0755);
  snprintf(p, sizeof p, "%s/%s/%s", dir, target, name);
  FILE *f = fopen(p, "wb");
  if (f == NULL) {
    fprintf(stderr, "fuzz-seeds: %s: %s\n", p, strerror(errno));
    exit(1);
  }
  return f;
}

static void put(const char *target, const char *name, const void *a, size_t n, const void *b, size_t m) {
  FILE *f = open_seed(target, name);
  fwrite(a, 1, n, f);
  if (m) fwrite(b, 1, m, f);
  fclose(f);
}

static void stream_seeds(void) {
  static const uint8_t modes[3] = {RS_MODE_STRONGEST, RS_MODE_LAST, RS_MODE_DUAL};
  for (int m = RS_MODEL_UNKNOWN + 1; m < RS_MODEL_COUNT; m++)
    for (int mi = 0; mi < 3; mi++) {
      rs_synth_cfg_t cfg = {.model = (rs_model_t)m, .mode = modes[mi], .hz = 10.0, .seconds = 0.02, .t0 = 1000};
      rs_sensor_t s;
      rs_sensor_init(&s, (rs_model_t)m);
      char name[64];
      snprintf(name, sizeof name, "%s-%s", rs_model_name((rs_model_t)m), rs_return_mode_name(modes[mi]));
      FILE *f = open_seed("stream", name);
      static rs_encode_t enc;
      static uint8_t buf[RS_PAYLOAD_SIZE];
      for (uint32_t k = 0; k < 12; k++) {
        rs_synth_packet(&cfg, &s, k, &enc);
        rs_packet_encode(s.info, &enc, buf);
        const uint8_t hdr[8] = {RS_PAYLOAD_SIZE >> 8, RS_PAYLOAD_SIZE & 0xff, 2368 >> 8, 2368 & 0xff, 0, 0, 0x05, 0x2f};
        fwrite(hdr, 1, 8, f);
        fwrite(buf, 1, sizeof buf, f);
      }
      fclose(f);
    }
}

static void capture_seeds(void) {
  static const int links[] = {RS_LINK_ETHERNET, RS_LINK_SLL, RS_LINK_RAW, RS_LINK_NULL};
  for (size_t i = 0; i < sizeof links / sizeof links[0]; i++) {
    char p[1024];
    snprintf(p, sizeof p, "%s/capture", dir);
    mkdir(p, 0755);
    snprintf(p, sizeof p, "%s/capture/link-%d.pcap", dir, links[i]);
    rs_synth_cfg_t cfg = {.model = RS_MODEL_VLP16, .mode = RS_MODE_STRONGEST, .hz = 10.0, .seconds = 0.005,
                          .t0 = 1000, .linktype = links[i], .vlan = links[i] == RS_LINK_ETHERNET ? 7 : 0,
                          .position_every = 2};
    if (rs_synth_write(&cfg, p) < 0) exit(1);
  }
}

static void lcm_seeds(void) {
  static rs_publish_t pub;
  rs_publish_cfg_t pc = {.url = "memq://"};
  if (rs_publish_init(&pub, &pc) != RS_OK) exit(1);
  static uint8_t buf[65536];
  static rs_object_list_t ol;
  memset(&ol, 0, sizeof ol);
  ol.count = 2;
  ol.obj[0].points = 30;
  ol.obj[1].points = 12;
  rs_frame_meta_t meta;
  memset(&meta, 0, sizeof meta);
  meta.model = RS_MODEL_VLP16;
  roadscan_object_list_t m;
  rs_publish_fill(&pub, &meta, &ol, 1, &m);
  uint8_t sel = RS_LCM_OBJECT_LIST;
  int n = roadscan_object_list_t_encode(buf, 0, sizeof buf, &m);
  put("lcm", "object_list", &sel, 1, buf, (size_t)n);
  roadscan_frame_stats_t st;
  memset(&st, 0, sizeof st);
  st.sensor_id = "north";
  static char *kinds[2] = {"payload-short", "block-flag"}; /* the variable-length part */
  static int64_t kind_counts[2] = {3, 7};
  st.num_errors = 2;
  st.error_kinds = kinds;
  st.error_counts = kind_counts;
  sel = RS_LCM_FRAME_STATS;
  n = roadscan_frame_stats_t_encode(buf, 0, sizeof buf, &st);
  put("lcm", "frame_stats", &sel, 1, buf, (size_t)n);
  static rs_track_list_t tl;
  memset(&tl, 0, sizeof tl);
  tl.count = 2;
  tl.track[0].id = 1;
  tl.track[1].id = 2;
  roadscan_track_list_t tm;
  rs_publish_fill_tracks(&pub, &meta, &tl, 1, &tm);
  sel = RS_LCM_TRACK_LIST;
  n = roadscan_track_list_t_encode(buf, 0, sizeof buf, &tm);
  put("lcm", "track_list", &sel, 1, buf, (size_t)n);
  roadscan_track_end_t te;
  memset(&te, 0, sizeof te);
  te.sensor_id = "north";
  sel = RS_LCM_TRACK_END;
  n = roadscan_track_end_t_encode(buf, 0, sizeof buf, &te);
  put("lcm", "track_end", &sel, 1, buf, (size_t)n);
  roadscan_count_line_t lines[2];
  roadscan_count_zone_t zones[1];
  roadscan_counts_t cm;
  ts_sample_counts(&cm, lines, zones);
  sel = RS_LCM_COUNTS;
  n = roadscan_counts_t_encode(buf, 0, sizeof buf, &cm);
  put("lcm", "counts", &sel, 1, buf, (size_t)n);
  roadscan_crossing_t xm;
  ts_sample_crossing(&xm);
  sel = RS_LCM_CROSSING;
  n = roadscan_crossing_t_encode(buf, 0, sizeof buf, &xm);
  put("lcm", "crossing", &sel, 1, buf, (size_t)n);
  rs_publish_deinit(&pub);
}

static void file_seeds(void) {
  uint8_t sel = 0;
  char yaml[8192];
  int k = snprintf(yaml, sizeof yaml, "lasers:\n");
  for (int i = 0; i < 16; i++)
    k += snprintf(yaml + k, sizeof yaml - (size_t)k,
                  "- {dist_correction: 0.0, laser_id: %d, rot_correction: 0.0, vert_correction: %.6f, "
                  "vert_offset_correction: 0.0}\n",
                  i, (i % 2 ? (i / 2) * 2 + 1 : -15 + (i / 2) * 2) * 0.017453292519943295);
  k += snprintf(yaml + k, sizeof yaml - (size_t)k, "num_lasers: 16\ndistance_resolution: 0.002\n");
  put("files", "calib.yaml", &sel, 1, yaml, (size_t)k);
  /* a small background model: 16 rows x 90 columns, a wall with something in front in places */
  rs_bg_model_t m;
  if (rs_bg_model_alloc(&m, RS_MODEL_VLP16, 16, 90) != RS_OK) exit(1);
  for (int c = 0; c < 16 * 90; c++) {
    m.n[c] = (uint8_t)(1 + (c % 5 == 0));
    m.far_seen[c] = 90;
    m.lo[c * RS_BG_SURFACES] = 500;
    m.hi[c * RS_BG_SURFACES] = 540;
    m.lo[c * RS_BG_SURFACES + 1] = 1200;
    m.hi[c * RS_BG_SURFACES + 1] = 1260;
  }
  m.rate_hz = 10.0f;
  m.frames = 100;
  char p[1024], err[256];
  snprintf(p, sizeof p, "%s/bg.tmp", dir);
  if (rs_bg_save(&m, p, err, sizeof err) != RS_OK) exit(1);
  rs_bg_model_free(&m);
  FILE *f = fopen(p, "rb");
  static uint8_t buf[1 << 20];
  size_t n = fread(buf, 1, sizeof buf, f);
  fclose(f);
  remove(p);
  sel = 1;
  put("files", "model.bg", &sel, 1, buf, n);
  const char *labels = "# a comment\npacket,block,channel,label\n0,0,1,2\n0,3,7,5\n12,11,31,3\n";
  sel = 2;
  put("files", "labels.csv", &sel, 1, labels, strlen(labels));
}

static void stage_seeds(void) {
  /* a VLP-16 map with two boxes of returns, over 3 frames */
  static uint8_t buf[1 + 3 * 16 * 360 * 2];
  buf[0] = 0;
  for (int f = 0; f < 3; f++)
    for (int r = 0; r < 16; r++)
      for (int c = 0; c < 360; c++) {
        uint16_t v = 0;
        if (r < 6 && c >= 40 + 3 * f && c < 60 + 3 * f) v = 1200; /* 12 m */
        if (r < 4 && c >= 200 && c < 205) v = 3000;
        uint8_t *o = buf + 1 + ((size_t)f * 16 * 360 + (size_t)r * 360 + (size_t)c) * 2;
        o[0] = (uint8_t)(v >> 8);
        o[1] = (uint8_t)v;
      }
  put("stages", "two-objects", buf, sizeof buf, NULL, 0);
}

static void value_seeds(void) {
  static const char *vals[] = {"\x00" "2.5", "\x01" "2368", "\x02" "yes", "\x03" "VLP-32C", "\x04" "east 1 2 3 4",
                               "\x05" "q_accel=2",
                               "\x06" "# a site\n[source]\npcap = a.pcap\nspeed = 2\nfast = yes\n[cluster]\ncluster = "
                               "dbscan\ncount-line = east 1 2 3 4\ncount-line = west 0 0 1 1\n[lcm]\nsensor-id = north\n",
                               "\x06" "pole_height = 7\nvehicles_per_min = 12\ntrees_per_leg = 3\n"};
  for (int i = 0; i < 8; i++) {
    char name[16];
    snprintf(name, sizeof name, "v%d", i);
    put("values", name, vals[i], i == 0 ? 4 : strlen(vals[i]), NULL, 0);
  }
}

int main(int argc, char **argv) {
  if (argc != 2) {
    fprintf(stderr, "usage: fuzz-seeds DIR\n");
    return 2;
  }
  snprintf(dir, sizeof dir, "%s", argv[1]);
  mkdir(dir, 0755);
  stream_seeds();
  capture_seeds();
  lcm_seeds();
  file_seeds();
  stage_seeds();
  value_seeds();
  printf("fuzz seeds in %s\n", dir);
  return 0;
}

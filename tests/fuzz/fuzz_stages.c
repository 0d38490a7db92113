/* fuzz_stages - a frame's map (ranges from the input) through the
 * processing stages the daemon runs after the background: adaptive FSPC,
 * objects, the tracker over several frames, a counting line. Input: a
 * header byte (rows: 16 or 32), then 2 bytes per cell of a 360-column map,
 * frame after frame. */
#include "fuzz.h"

#include "roadscan/perception/cluster.h"
#include "roadscan/perception/count.h"
#include "roadscan/perception/objects.h"
#include "roadscan/perception/track.h"

#include <string.h>

static rs_slot_t slot;
static rs_cluster_t cl;
static rs_objects_t ob;
static rs_object_list_t list;
static rs_tracker_t tr;
static rs_counter_t cnt;

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size) {
  if (size < 1) return 0;
  rs_sensor_t s;
  rs_sensor_init(&s, data[0] & 1 ? RS_MODEL_VLP32C : RS_MODEL_VLP16);
  const int rows = s.lasers, cols = 360;
  rs_cluster_cfg_t cc;
  rs_cluster_cfg_default(&cc);
  cc.method = (rs_cluster_method_t)(1 + (data[0] >> 1) % 4);
  if (rs_cluster_init(&cl, &cc, &s) != 0) return 0;
  rs_objects_init(&ob, NULL);
  rs_track_cfg_t tc;
  rs_track_cfg_default(&tc);
  rs_track_init(&tr, &tc);
  rs_count_line_t line;
  char err[256];
  rs_count_parse_line("gate 0 -50 0 50", &line, err, sizeof err);
  rs_count_init(&cnt, &line, 1, NULL, 10.0, err, sizeof err);
  rs_count_zone_t zone; /* and a zone around the sensor */
  rs_count_parse_zone("near -20 -20 20 -20 20 20 -20 20", &zone, err, sizeof err);
  rs_count_add_zones(&cnt, &zone, 1, err, sizeof err);
  size_t at = 1;
  const size_t per = (size_t)rows * cols * 2;
  for (int f = 0; f < 8 && at < size; f++) {
    memset(&slot.meta, 0, sizeof slot.meta);
    slot.meta.rows = (uint16_t)rows;
    slot.meta.cols = (uint16_t)cols;
    slot.meta.t_first = 100.0 + 0.1 * f;
    slot.meta.t_last = slot.meta.t_first + 0.1;
    slot.meta.first_packet = (uint32_t)f * 100;
    slot.meta.last_packet = slot.meta.first_packet + 99;
    for (int l = 0; l < RS_LAYERS; l++)
      for (int i = 0; i < rows * cols; i++) {
        const uint32_t c = (uint32_t)l * RS_MAX_CELLS + (uint32_t)i;
        float r = 0.0f;
        if (l == 0 && at + 2 * (size_t)i + 1 < size && 2 * (size_t)i + 1 < per) {
          const uint16_t v = (uint16_t)(data[at + 2 * (size_t)i] << 8 | data[at + 2 * (size_t)i + 1]);
          r = v == 0 ? 0.0f : (float)v * 0.01f;
        }
        slot.range[c] = r;
        slot.label[c] = r > 0.0f && (i % 7) == 0 ? 1 : 2;
        slot.intensity[c] = (uint8_t)i;
        slot.addr[c].packet = slot.meta.first_packet + (uint32_t)(i % 100);
      }
    at += per;
    rs_cluster_stats_t cs;
    rs_cluster_run(&cl, &slot, &cs);
    rs_objects_extract_cells(&ob, &slot, &s, cl.members, cl.nmembers, &list);
    rs_track_frame(&tr, &list, slot.meta.t_last);
    rs_count_frame(&cnt, &tr.list, slot.meta.t_last);
  }
  return 0;
}

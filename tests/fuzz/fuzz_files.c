/* fuzz_files - the loaders of what users hand the programs: a calibration
 * YAML (then applied to every model), a background model file (then used on
 * a frame of its geometry, and the ground built from it), a point-label file (read to the end). Input: a
 * selector byte, then the file. */
#include "fuzz.h"

#include "roadscan/perception/background.h"
#include "roadscan/perception/ground.h"
#include "roadscan/sensor/calib.h"
#include "roadscan/output/labels.h"

#include <string.h>

static rs_slot_t slot;

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size) {
  if (size < 1) return 0;
  const int which = data[0] % 3;
  const char *path = fuzz_file(data + 1, size - 1, which == 0 ? ".yaml" : which == 1 ? ".bg" : ".csv");
  if (path == NULL) return 0;
  char err[512];
  if (which == 0) {
    static rs_calib_t c;
    if (rs_calib_load_yaml(path, &c, err, sizeof err) == 0) {
      for (int m = RS_MODEL_UNKNOWN + 1; m < RS_MODEL_COUNT; m++) {
        rs_sensor_t s;
        rs_sensor_init(&s, (rs_model_t)m);
        char warn[256];
        rs_calib_apply(&c, &s, err, sizeof err, warn, sizeof warn);
      }
    }
  } else if (which == 1) {
    static rs_bg_model_t m;
    if (rs_bg_load(&m, path, err, sizeof err) == 0) {
      memset(&slot.meta, 0, sizeof slot.meta);
      slot.meta.rows = m.rows;
      slot.meta.cols = m.cols;
      for (uint32_t i = 0; i < (uint32_t)m.rows * m.cols; i++) slot.range[i] = 0.5f + (float)(i % 97);
      rs_bg_counts_t bc;
      memset(&bc, 0, sizeof bc);
      rs_bg_rules_t rules;
      rs_bg_rules_default(&rules);
      rs_bg_subtract(&m, &rules, &slot, &bc);
      static rs_ground_t g; /* the ground the daemon builds from a model it loaded */
      rs_sensor_t s;
      if (rs_sensor_init(&s, m.model) == RS_OK) {
        rs_ground_build(&g, &m, &s);
        float z;
        (void)rs_ground_at(&g, 10.0, -20.0, &z);
      }
      rs_bg_model_free(&m);
    }
  } else {
    rs_labels_reader_t r;
    if (rs_labels_open(&r, path, 1000000) == 0) {
      rs_label_t l;
      for (int k = 0; k < 1000000 && rs_labels_next(&r, &l) == 1; k++) {
      }
      rs_labels_close(&r);
    }
  }
  unlink(path);
  return 0;
}

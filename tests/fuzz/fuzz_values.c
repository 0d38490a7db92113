/* fuzz_values - option values as users type them: numbers, booleans,
 * sensor names, counting lines, tracker parameters (NAME=VALUE). Input:
 * a selector byte, then the text. */
#include "fuzz.h"

#include "roadscan/util/config.h"
#include "roadscan/perception/count.h"
#include "roadscan/perception/track.h"

#include <string.h>

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size) {
  if (size < 1 || size > 4096) return 0;
  char text[4097];
  memcpy(text, data + 1, size - 1);
  text[size - 1] = '\0';
  char err[512];
  switch (data[0] % 6) {
  case 0: {
    double d;
    rs_cfg_double("--x", text, -1e9, 1e9, &d, err, sizeof err);
    break;
  }
  case 1: {
    long v;
    rs_cfg_long("--x", text, -1000000, 1000000, &v, err, sizeof err);
    break;
  }
  case 2: {
    bool b;
    rs_cfg_bool("--x", text, &b, err, sizeof err);
    break;
  }
  case 3: {
    rs_model_t m;
    rs_cfg_model("--x", text, &m, err, sizeof err);
    break;
  }
  case 4: {
    rs_count_line_t l;
    rs_count_parse_line(text, &l, err, sizeof err);
    break;
  }
  default: {
    rs_track_cfg_t c;
    rs_track_cfg_default(&c);
    char *eq = strchr(text, '=');
    if (eq) {
      *eq = '\0';
      rs_track_cfg_set(&c, text, eq + 1, err, sizeof err);
    }
    break;
  }
  }
  return 0;
}

/* fuzz_values - option values as users type them: numbers, booleans,
 * sensor names, counting lines, tracker parameters (NAME=VALUE), and whole
 * INI files through an option table (sections, strings, repeatable keys,
 * the simulator's scene knobs). Input: a selector byte, then the text. */
#include "fuzz.h"

#include "roadscan/util/config.h"
#include "roadscan/perception/count.h"
#include "roadscan/perception/track.h"
#include "roadscan/sim/scene.h"
#include "roadscan/util/error.h"
#include "roadscan/util/opts.h"

#include <stdio.h>

#include <string.h>

typedef struct {
  const char *path, *name;
  double speed;
  int port, method, lines;
  bool fast;
  rs_scene_cfg_t scene;
} ini_t;

static int add_line(void *t, const char *key, const char *v, char *err, size_t n) {
  rs_count_line_t l;
  if (rs_count_parse_line(v, &l, err, n) != RS_OK) return RS_E_INVAL;
  (void)key;
  ++*(int *)t;
  return RS_OK;
}

static const rs_opt_t ini_table[] = {
    RS_OPT_HEAD("source", "Source"),
    RS_OPT_STR_("pcap", "FILE", ini_t, path, "a capture"),
    RS_OPT_DBL_("speed", "X", ini_t, speed, 0.001, 1000.0, "speed"),
    RS_OPT_FLAG_("fast", ini_t, fast, "flat out"),
    RS_OPT_INT_("port", "N", ini_t, port, 1, 65535, "port"),
    RS_OPT_HEAD("cluster", "Clustering"),
    {.type = RS_OPT_CHOICE, .name = "cluster", .arg = "M", .off = offsetof(ini_t, method),
     .choices = "none|fspc|fspc-adaptive|dbscan|ccl", .help = "method"},
    {.type = RS_OPT_FUNC, .name = "count-line", .arg = "L", .off = offsetof(ini_t, lines), .fn = add_line,
     .flags = RS_OPT_REPEAT, .help = "a line"},
    RS_OPT_HEAD("lcm", "LCM"),
    RS_OPT_STR_("sensor-id", "ID", ini_t, name, "id"),
};

static void ini_file(const uint8_t *bytes, size_t n) {
  static ini_t st;
  static rs_opts_t o;
  memset(&st, 0, sizeof st);
  const rs_opts_spec_t spec = {.prog = "fuzz", .summary = "s", .config_file = true, .opts = ini_table,
                               .n = (int)(sizeof ini_table / sizeof ini_table[0])};
  if (rs_opts_init(&o, &spec, &st) != RS_OK) __builtin_trap();
  FILE *f = fmemopen((void *)(uintptr_t)bytes, n ? n : 1, "r");
  if (f == NULL) return;
  rs_opts_read_stream(&o, f, "fuzz.ini");
  fclose(f);
  /* the scene knobs: keys outside any section */
  int nk;
  const rs_opt_t *knobs = rs_scene_knobs(&nk);
  rs_scene_preset("light", &st.scene);
  const rs_opts_spec_t sspec = {.prog = "scene", .summary = "s", .opts = knobs, .n = nk};
  if (rs_opts_init(&o, &sspec, &st.scene) != RS_OK) __builtin_trap();
  f = fmemopen((void *)(uintptr_t)bytes, n ? n : 1, "r");
  if (f == NULL) return;
  rs_opts_read_stream(&o, f, "scene.ini");
  fclose(f);
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size) {
  if (size < 1 || size > 4096) return 0;
  char text[4097];
  memcpy(text, data + 1, size - 1);
  text[size - 1] = '\0';
  char err[512];
  switch (data[0] % 7) {
  case 6: ini_file(data + 1, size - 1); break;
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

/* roadscan-synth - write a synthetic Velodyne capture (a sensor 2 m above
 * flat ground inside an irregular round wall), for trying the tools without
 * a sensor. No ground truth: that is the scene simulator's job. */
#include "roadscan/util/opts.h"
#include "roadscan/util/error.h"
#include "roadscan/capture/net.h"
#include "roadscan/sim/synth.h"

#include <stdio.h>
#include <string.h>

/* Everything the options set. */
typedef struct {
  rs_synth_cfg_t cfg;
  const char *out;
  int mode_i;
} settings_t;
static settings_t st;
static rs_opts_t opts;
static const uint8_t mode_of[] = {RS_MODE_STRONGEST, RS_MODE_LAST, RS_MODE_DUAL};

#define T settings_t
static const rs_opt_t table[] = {
    RS_OPT_OUTPUT_("FILE", T, out, "the capture (pcap, Ethernet)"),
    {.type = RS_OPT_MODEL, .name = "model", .arg = "NAME", .off = offsetof(T, cfg.model), .help = "the sensor"},
    RS_OPT_DBL_("seconds", "S", T, cfg.seconds, 0.01, 3600.0, "capture length"),
    RS_OPT_DBL_("hz", "HZ", T, cfg.hz, 5.0, 20.0, "rotation rate"),
    {.type = RS_OPT_CHOICE, .name = "mode", .arg = "MODE", .off = offsetof(T, mode_i),
     .choices = "strongest|last|dual", .help = "return mode"},
};
#undef T

static const rs_opts_spec_t spec = {
    .prog = "roadscan-synth",
    .summary = "write a synthetic Velodyne capture, for trying the tools without a sensor",
    .synopsis = "-o OUT.pcap [--model NAME] [--seconds S] [--hz HZ] [--mode MODE]",
    .about = "A sensor 2 m above flat ground inside an irregular round wall, with position packets. No ground "
             "truth: roadscan-sim writes captures of a simulated intersection with their truth.",
    .epilog = "Exit status: 0 written, 1 cannot write, 2 bad usage.",
    .opts = table,
    .n = (int)(sizeof table / sizeof table[0]),
};

int main(int argc, char **argv) {
  st.cfg = (rs_synth_cfg_t){.model = RS_MODEL_VLP16, .mode = RS_MODE_STRONGEST, .hz = 10.0, .seconds = 2.0,
                            .t0 = 1700000000.0, .linktype = RS_LINK_ETHERNET, .position_every = 50};
  char err[RS_ERRMSG_SIZE];
  int first;
  const int start = rs_opts_start(&opts, &spec, &st, argc, argv, &first);
  if (start >= 0) return start;
  const char *out = st.out;
  rs_synth_cfg_t cfg = st.cfg;
  cfg.mode = mode_of[st.mode_i];
  if (out == NULL) {
    snprintf(err, sizeof err, "-o OUT.pcap is required");
    goto bad;
  }
  long n = rs_synth_write(&cfg, out);
  if (n < 0) {
    fprintf(stderr, "roadscan-synth: %s: cannot write (%s)\n", out, rs_strerror((int)n));
    return 1;
  }
  fprintf(stderr, "roadscan-synth: %s: %ld %s data packets, %.1f s at %.1f Hz (%s return)\n", out, n,
          rs_model_name(cfg.model), cfg.seconds, cfg.hz, rs_return_mode_name(cfg.mode));
  return 0;
bad:
  fprintf(stderr, "roadscan-synth: %s\n", err);
  return 2;
}

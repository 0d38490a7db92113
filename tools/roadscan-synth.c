/* roadscan-synth - write a synthetic Velodyne capture (a sensor 2 m above
 * flat ground inside an irregular round wall), for trying the tools without
 * a sensor. No ground truth: that is the scene simulator's job. */
#include "roadscan/util/config.h"
#include "roadscan/util/error.h"
#include "roadscan/capture/net.h"
#include "roadscan/sim/synth.h"

#include <getopt.h>
#include <stdio.h>
#include <string.h>

int main(int argc, char **argv) {
  enum { O_MODEL = 256, O_SECONDS, O_HZ, O_MODE, O_HELP };
  static const struct option opts[] = {{"output", required_argument, NULL, 'o'},
                                       {"model", required_argument, NULL, O_MODEL},
                                       {"seconds", required_argument, NULL, O_SECONDS},
                                       {"hz", required_argument, NULL, O_HZ},
                                       {"mode", required_argument, NULL, O_MODE},
                                       {"help", no_argument, NULL, O_HELP},
                                       {NULL, 0, NULL, 0}};
  rs_synth_cfg_t cfg = {.model = RS_MODEL_VLP16, .mode = RS_MODE_STRONGEST, .hz = 10.0, .seconds = 2.0,
                        .t0 = 1700000000.0, .linktype = RS_LINK_ETHERNET, .position_every = 50};
  const char *out = NULL;
  char err[RS_ERRMSG_SIZE];
  int c;
  while ((c = getopt_long(argc, argv, "o:", opts, NULL)) != -1) {
    switch (c) {
    case 'o': out = optarg; break;
    case O_MODEL:
      if (rs_cfg_model("--model", optarg, &cfg.model, err, sizeof err)) goto bad;
      break;
    case O_SECONDS:
      if (rs_cfg_double("--seconds", optarg, 0.01, 3600.0, &cfg.seconds, err, sizeof err)) goto bad;
      break;
    case O_HZ:
      if (rs_cfg_double("--hz", optarg, 5.0, 20.0, &cfg.hz, err, sizeof err)) goto bad;
      break;
    case O_MODE:
      if (strcmp(optarg, "strongest") == 0) cfg.mode = RS_MODE_STRONGEST;
      else if (strcmp(optarg, "last") == 0) cfg.mode = RS_MODE_LAST;
      else if (strcmp(optarg, "dual") == 0) cfg.mode = RS_MODE_DUAL;
      else {
        snprintf(err, sizeof err, "--mode: '%s' is not strongest, last or dual", optarg);
        goto bad;
      }
      break;
    case O_HELP:
      printf("usage: roadscan-synth -o OUT.pcap [--model NAME] [--seconds S] [--hz HZ] [--mode strongest|last|dual]\n"
             "models: %s\n", rs_model_names());
      return 0;
    default: return 2;
    }
  }
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

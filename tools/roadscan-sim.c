/* roadscan-sim - a signalised intersection seen by a roadside Velodyne:
 * writes a pcap of genuine sensor packets and the per-point ground truth
 * (../shared/specs/point-labels.md). Deterministic for a given --seed.
 *
 * Single-threaded tool. The firing timing, block layout and azimuths are
 * those the decoder reads back (round-trip tested); every ray is cast
 * through the scene at the true azimuth of its firing. */
#include "roadscan/util/config.h"
#include "roadscan/util/error.h"
#include "roadscan/output/labels.h"
#include "roadscan/capture/net.h"
#include "roadscan/sensor/packet.h"
#include "roadscan/offline/pcapw.h"
#include "roadscan/sim/scene.h"
#include "roadscan/util/timing.h"

#include <getopt.h>
#include <ini.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define MAX_TURNS 100000

static rs_encode_t enc;
static uint8_t payload[RS_PAYLOAD_SIZE];
static uint32_t turn_points[MAX_TURNS];

typedef struct {
  rs_scene_cfg_t *cfg;
  char err[RS_ERRMSG_SIZE];
  int line;
} ini_ctx_t;

static int on_ini(void *user, const char *section, const char *name, const char *value) {
  ini_ctx_t *c = user;
  (void)section;
  char e[RS_ERRMSG_SIZE];
  if (rs_scene_set(c->cfg, name, value, e, sizeof e) != RS_OK) {
    snprintf(c->err, sizeof c->err, "%s", e);
    return 0;
  }
  return 1;
}

static int cmp_u32(const void *a, const void *b) {
  uint32_t x = *(const uint32_t *)a, y = *(const uint32_t *)b;
  return (x > y) - (x < y);
}

static void usage(FILE *out) {
  fprintf(out,
          "usage: roadscan-sim --sensor NAME -o OUT.pcap --labels OUT.csv [options]\n"
          "  --sensor NAME          %s (default VLP-32C)\n"
          "  --scenario NAME        light, rush, far, storm (default light)\n"
          "  --scenario-file FILE   key = value lines overriding the preset (INI)\n"
          "  --set KEY=VALUE        one scene knob (repeatable); keys:\n"
          "                         %s\n"
          "  --seconds S            capture length (default 10)\n"
          "  --hz HZ                rotation rate: 5, 10 or 20 (default 10)\n"
          "  --return-mode MODE     strongest, last or dual (default strongest)\n"
          "  --seed N               random seed (default 1)\n"
          "  --start-time T         capture time of the first packet, s since 1970 (default 1700000000)\n"
          "  -o, --output FILE      the capture (pcap, Ethernet)\n"
          "  --labels FILE          ground truth: labels 2 (foliage, spurious) and 3+ (object ids)\n"
          "  --truth-states FILE    every road user's true state at the start of every turn (CSV t,id,class,\n"
          "                         x,y,vx,vy,heading,length,width,height; sensor frame, capture time)\n",
          rs_model_names(), rs_scene_keys());
}

int main(int argc, char **argv) {
  enum { O_SENSOR = 256, O_SCEN, O_SFILE, O_SET, O_SECONDS, O_HZ, O_MODE, O_SEED, O_LABELS, O_START, O_STATES, O_HELP };
  static const struct option opts[] = {
      {"sensor", required_argument, NULL, O_SENSOR},      {"model", required_argument, NULL, O_SENSOR},
      {"scenario", required_argument, NULL, O_SCEN},      {"scenario-file", required_argument, NULL, O_SFILE},
      {"set", required_argument, NULL, O_SET},            {"seconds", required_argument, NULL, O_SECONDS},
      {"hz", required_argument, NULL, O_HZ},              {"return-mode", required_argument, NULL, O_MODE},
      {"seed", required_argument, NULL, O_SEED},          {"output", required_argument, NULL, 'o'},
      {"labels", required_argument, NULL, O_LABELS},      {"start-time", required_argument, NULL, O_START},
      {"truth-states", required_argument, NULL, O_STATES}, {"help", no_argument, NULL, O_HELP},
      {NULL, 0, NULL, 0}};
  rs_model_t model = RS_MODEL_VLP32C;
  const char *scenario = "light", *sfile = NULL, *out = NULL, *labels = NULL, *states_path = NULL;
  const char *sets[64];
  int nsets = 0;
  double seconds = 10.0, hz = 10.0, t0 = 1700000000.0;
  long seed = 1;
  uint8_t mode = RS_MODE_STRONGEST;
  char err[RS_ERRMSG_SIZE];
  int c;
  while ((c = getopt_long(argc, argv, "o:", opts, NULL)) != -1) {
    switch (c) {
    case O_SENSOR:
      if (rs_cfg_model("--sensor", optarg, &model, err, sizeof err)) goto bad;
      break;
    case O_SCEN: scenario = optarg; break;
    case O_SFILE: sfile = optarg; break;
    case O_SET:
      if (nsets == 64) {
        snprintf(err, sizeof err, "--set: at most 64");
        goto bad;
      }
      sets[nsets++] = optarg;
      break;
    case O_SECONDS:
      if (rs_cfg_double("--seconds", optarg, 0.1, 7200.0, &seconds, err, sizeof err)) goto bad;
      break;
    case O_HZ:
      if (rs_cfg_double("--hz", optarg, 5.0, 20.0, &hz, err, sizeof err)) goto bad;
      if (hz != 5.0 && hz != 10.0 && hz != 20.0) {
        snprintf(err, sizeof err, "--hz: %s is not 5, 10 or 20", optarg);
        goto bad;
      }
      break;
    case O_MODE:
      if (strcmp(optarg, "strongest") == 0) mode = RS_MODE_STRONGEST;
      else if (strcmp(optarg, "last") == 0) mode = RS_MODE_LAST;
      else if (strcmp(optarg, "dual") == 0) mode = RS_MODE_DUAL;
      else {
        snprintf(err, sizeof err, "--return-mode: '%s' is not strongest, last or dual", optarg);
        goto bad;
      }
      break;
    case O_SEED:
      if (rs_cfg_long("--seed", optarg, 0, 2147483647L, &seed, err, sizeof err)) goto bad;
      break;
    case O_START:
      if (rs_cfg_double("--start-time", optarg, 0.0, 4e9, &t0, err, sizeof err)) goto bad;
      break;
    case 'o': out = optarg; break;
    case O_LABELS: labels = optarg; break;
    case O_STATES: states_path = optarg; break;
    case O_HELP: usage(stdout); return 0;
    default: usage(stderr); return 2;
    }
  }
  if (optind < argc) {
    snprintf(err, sizeof err, "unexpected argument '%s'", argv[optind]);
    goto bad;
  }
  if (out == NULL || labels == NULL) {
    snprintf(err, sizeof err, "-o OUT.pcap and --labels OUT.csv are required");
    goto bad;
  }
  rs_scene_cfg_t scfg;
  if (!rs_scene_preset(scenario, &scfg)) {
    snprintf(err, sizeof err, "--scenario: unknown scenario '%s' (light, rush, far, storm)", scenario);
    goto bad;
  }
  if (sfile) {
    ini_ctx_t ctx = {.cfg = &scfg};
    int rc = ini_parse(sfile, on_ini, &ctx);
    if (rc < 0) {
      fprintf(stderr, "roadscan-sim: --scenario-file %s: cannot read\n", sfile);
      return 1;
    }
    if (rc > 0) {
      fprintf(stderr, "roadscan-sim: %s:%d: %s\n", sfile, rc, ctx.err[0] ? ctx.err : "syntax error");
      return 1;
    }
  }
  for (int i = 0; i < nsets; i++) {
    char key[64];
    const char *eq = strchr(sets[i], '=');
    if (eq == NULL || eq == sets[i] || (size_t)(eq - sets[i]) >= sizeof key) {
      snprintf(err, sizeof err, "--set: '%s' is not KEY=VALUE", sets[i]);
      goto bad;
    }
    memcpy(key, sets[i], (size_t)(eq - sets[i]));
    key[eq - sets[i]] = '\0';
    char e[RS_ERRMSG_SIZE / 2];
    if (rs_scene_set(&scfg, key, eq + 1, e, sizeof e) != RS_OK) {
      snprintf(err, sizeof err, "--set: %s", e);
      goto bad;
    }
  }

  static rs_sensor_t sensor;
  rs_sensor_init(&sensor, model);
  const rs_model_info_t *mi = sensor.info;
  int64_t tstart = rs_now_ns();
  rs_scene_t *sc = rs_scene_create(&scfg, &sensor, hz, (uint64_t)seed);
  if (sc == NULL) {
    fprintf(stderr, "roadscan-sim: out of memory building the scene\n");
    return 1;
  }
  double build_s = (double)(rs_now_ns() - tstart) * 1e-9;
  rs_pcapw_t w;
  if (rs_pcapw_open(&w, out, RS_LINK_ETHERNET, 0) != RS_OK) {
    fprintf(stderr, "roadscan-sim: %s: cannot write\n", out);
    return 1;
  }
  char comment[512];
  snprintf(comment, sizeof comment,
           "roadscan-sim sensor=%s scenario=%s seconds=%g hz=%g return=%s seed=%ld\n"
           "labels: 2 = foliage or spurious return, 3+ = object id (stable over the capture)",
           mi->name, scenario, seconds, hz, rs_return_mode_name(mode), seed);
  rs_labels_writer_t lw;
  if (rs_labels_create(&lw, labels, comment) != RS_OK) {
    fprintf(stderr, "roadscan-sim: %s: cannot write\n", labels);
    return 1;
  }
  FILE *states = NULL;
  static rs_agent_state_t agents[4096];
  if (states_path) {
    states = fopen(states_path, "w");
    if (states == NULL) {
      fprintf(stderr, "roadscan-sim: %s: cannot write\n", states_path);
      return 1;
    }
    fprintf(states, "t,id,class,x,y,vx,vy,heading,length,width,height\n");
  }

  const bool dual = mode == RS_MODE_DUAL, vls = mi->blocks_per_cycle > 1;
  const int nb = vls && dual ? 8 : RS_BLOCKS;
  const int groups = vls ? (dual ? 1 : 3) : (dual ? 6 : 12);
  const double group_us = rs_model_group_us(mi), packet_us = groups * group_us;
  const double deg_per_us = hz * 360.0 / 1e6;
  const uint64_t npackets = (uint64_t)(seconds * 1e6 / packet_us);
  rs_rng_t fx;
  rs_rng_seed(&fx, (uint64_t)seed * 7919u + 17u);
  uint32_t index = 0;
  uint64_t lost = 0, points = 0, object_points = 0;
  int turns = 0;
  uint32_t cur_turn = 0;
  double last_az = -1;
  rs_ray_t rays[RS_RECORDS];
  /* the motor: the nominal rate x (1 + offset + a slow wander, 2 s
   * correlation); the firing clock stays exact, so where the firings fall
   * drifts from turn to turn as on a real sensor */
  rs_rng_t motor;
  rs_rng_seed(&motor, (uint64_t)seed * 104729u + 3u);
  const double ar = exp(-packet_us * 1e-6 / 2.0), ar_sd = scfg.rpm_jitter * sqrt(1.0 - ar * ar);
  double jitter = scfg.rpm_jitter * rs_rng_normal(&motor), phase = 0.0;
  for (uint64_t k = 0; k < npackets; k++) {
    double t_pkt = (double)k * packet_us; /* µs */
    const double rate = deg_per_us * (1.0 + scfg.rpm_offset + jitter); /* degrees per µs */
    double az0 = phase;
    double az_end = phase + rate * packet_us;
    phase = fmod(az_end, 360.0);
    jitter = ar * jitter + ar_sd * rs_rng_normal(&motor);
    if (last_az >= 0 && fmod(az0, 360.0) < last_az) {
      if (turns < MAX_TURNS) turn_points[turns++] = cur_turn;
      cur_turn = 0;
      rs_scene_new_turn(sc);
      if (states) { /* the road users at the turn's start */
        rs_scene_prepare(sc, t_pkt * 1e-6, 0.0, 0.0);
        const int na = rs_scene_states(sc, t_pkt * 1e-6, agents, (int)(sizeof agents / sizeof agents[0]));
        for (int i = 0; i < na; i++)
          fprintf(states, "%.6f,%u,%s,%.3f,%.3f,%.3f,%.3f,%.4f,%.2f,%.2f,%.2f\n", t0 + t_pkt * 1e-6, agents[i].id,
                  agents[i].cls, agents[i].x, agents[i].y, agents[i].vx, agents[i].vy, agents[i].heading,
                  agents[i].length, agents[i].width, agents[i].height);
      }
    }
    last_az = fmod(az0, 360.0);
    rs_scene_prepare(sc, t_pkt * 1e-6, fmod(az0 - 8.0 + 720.0, 360.0), fmod(az_end + 8.0, 360.0));
    bool lose = scfg.packet_loss > 0 && rs_rng_uniform(&fx) < scfg.packet_loss;
    memset(&enc, 0, sizeof enc);
    enc.mode_byte = mode;
    enc.timestamp_us = (uint32_t)fmod(t0 * 1e6 + t_pkt, 3600e6);
    for (int b = 0; b < RS_BLOCKS; b++) {
      int g = vls ? (dual ? 0 : b / 4) : (dual ? b / 2 : b);
      double azg = az0 + rate * g * group_us;
      enc.block_azimuth[b] = (uint16_t)((long)llround(fmod(azg, 360.0) * 100.0) % 36000);
      if (b >= nb) continue;
      int bank = vls ? rs_vls128_bank_of_block(b, dual) : 0;
      bool odd = dual && (b % 2 == 1);
      if (!odd) {
        for (int ch = 0; ch < RS_RECORDS; ch++) {
          int laser;
          float tf;
          rs_sensor_record(&sensor, bank, ch, &laser, &tf);
          double az = (double)enc.block_azimuth[b] / 100.0 + sensor.azimuth_offset_deg[laser] + rate * tf;
          rs_scene_cast(sc, bank * RS_RECORDS + ch, enc.block_azimuth[b], laser, az, &fx, &rays[ch]);
        }
      }
      for (int ch = 0; ch < RS_RECORDS; ch++) {
        const rs_ray_t *r = &rays[ch];
        const rs_hit_t *h;
        bool two = r->second.range > 0;
        if (mode == RS_MODE_LAST || (dual && !odd)) h = two ? &r->second : &r->first;
        else if (dual) h = &r->first; /* strongest, or second strongest when the last is strongest */
        else h = (two && r->second.intensity > r->first.intensity) ? &r->second : &r->first;
        long raw = h->range > 0 ? lround(h->range / sensor.dist_res_m) : 0;
        if (raw > 65535) raw = 0;
        enc.distance[b][ch] = (uint16_t)raw;
        enc.intensity[b][ch] = raw ? h->intensity : 0;
        if (raw == 0 || lose) continue;
        points++;
        if (h->label >= RS_LABEL_NOISE) rs_labels_write(&lw, index, b, ch, h->label);
        if (h->label >= RS_LABEL_FIRST_OBJECT) {
          object_points++;
          cur_turn++;
        }
      }
    }
    if (lose) {
      lost++;
      continue;
    }
    rs_packet_encode(mi, &enc, payload);
    rs_pcapw_write(&w, t0 + t_pkt * 1e-6, RS_DEFAULT_DATA_PORT, payload, sizeof payload);
    if (index % 200 == 0) { /* position packets as the sensors send them */
      uint8_t pos[512];
      memset(pos, 0, sizeof pos);
      memcpy(pos + 206, "$GPRMC,000000,A,0000.0000,N,00000.0000,E,0.0,0.0,010120,,,A*00", 62);
      rs_pcapw_write(&w, t0 + t_pkt * 1e-6 + 1e-5, RS_DEFAULT_POSITION_PORT, pos, sizeof pos);
    }
    index++;
  }
  rs_pcapw_close(&w);
  int lrc = rs_labels_finish(&lw);
  double el = (double)(rs_now_ns() - tstart) * 1e-9;
  uint32_t med = 0, mx = 0;
  if (turns > 1) {
    /* the first turn is partial */
    qsort(turn_points + 1, (size_t)(turns - 1), sizeof turn_points[0], cmp_u32);
    med = turn_points[1 + (turns - 1) / 2];
    mx = turn_points[turns - 1];
  }
  fprintf(stderr,
          "roadscan-sim: %s %s %.0f s at %.0f Hz (%s): %u packets written, %llu lost, %llu returns, "
          "%llu object returns\n"
          "  object returns per turn: median %u, max %u; %d objects in the scene at the end\n"
          "  %.2f s (scene %.2f s), %.1fx real time\n",
          mi->name, scenario, seconds, hz, rs_return_mode_name(mode), index, (unsigned long long)lost,
          (unsigned long long)points, (unsigned long long)object_points, med, mx, rs_scene_object_count(sc), el,
          build_s, seconds / el);
  rs_scene_destroy(sc);
  if (states && fclose(states) != 0) {
    fprintf(stderr, "roadscan-sim: %s: write failed\n", states_path);
    return 1;
  }
  if (lrc != RS_OK || lw.rejected) {
    fprintf(stderr, "roadscan-sim: %s: write failed\n", labels);
    return 1;
  }
  return 0;
bad:
  fprintf(stderr, "roadscan-sim: %s\n", err);
  return 2;
}

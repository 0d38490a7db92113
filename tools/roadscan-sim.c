/* roadscan-sim - a signalised intersection seen by a roadside Velodyne:
 * writes a pcap of genuine sensor packets and the per-point ground truth
 * (../shared/specs/point-labels.md). Deterministic for a given --seed.
 *
 * Single-threaded tool. The firing timing, block layout and azimuths are
 * those the decoder reads back (round-trip tested); every ray is cast
 * through the scene at the true azimuth of its firing. */
#include "roadscan/util/opts.h"
#include "roadscan/util/error.h"
#include "roadscan/output/labels.h"
#include "roadscan/capture/net.h"
#include "roadscan/sensor/packet.h"
#include "roadscan/offline/pcapw.h"
#include "roadscan/perception/count.h"
#include "roadscan/sim/scene.h"
#include "roadscan/util/timing.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define MAX_TURNS 100000

static rs_encode_t enc;
static uint8_t payload[RS_PAYLOAD_SIZE];
static uint32_t turn_points[MAX_TURNS];

static int cmp_u32(const void *a, const void *b) {
  uint32_t x = *(const uint32_t *)a, y = *(const uint32_t *)b;
  return (x > y) - (x < y);
}

#define MAX_SETS 64
typedef struct {
  rs_model_t model;
  const char *scenario, *sfile, *out, *labels, *states_path, *crossings_path;
  char sets[MAX_SETS][128]; /* --set KEY=VALUE, applied after the preset and the scenario file */
  int nsets;
  rs_count_lines_t lines; /* --count-line, for --truth-crossings */
  double seconds, t0;
  int hz_i, mode_i, seed;
} settings_t;
static settings_t st;
static rs_opts_t opts;
static const double hz_of[] = {5.0, 10.0, 20.0};
static const uint8_t mode_of[] = {RS_MODE_STRONGEST, RS_MODE_LAST, RS_MODE_DUAL};

static int check_scenario(void *t, const char *key, const char *v, char *err, size_t n) {
  (void)t;
  rs_scene_cfg_t c;
  if (rs_scene_preset(v, &c)) return RS_OK;
  snprintf(err, n, "%s: unknown scenario '%s' (light, rush, turns, far, storm)", key, v);
  return RS_E_INVAL;
}

static int add_set(void *t, const char *key, const char *v, char *err, size_t n) {
  settings_t *s = (settings_t *)(void *)((char *)t - offsetof(settings_t, sets));
  const char *eq = strchr(v, '=');
  if (eq == NULL || eq == v) {
    snprintf(err, n, "%s: '%s' is not KEY=VALUE", key, v);
    return RS_E_INVAL;
  }
  if (strlen(v) >= sizeof s->sets[0]) {
    snprintf(err, n, "%s: '%.32s...' is longer than %zu characters", key, v, sizeof s->sets[0] - 1);
    return RS_E_INVAL;
  }
  if (s->nsets == MAX_SETS) {
    snprintf(err, n, "%s: at most %d", key, MAX_SETS);
    return RS_E_INVAL;
  }
  snprintf(s->sets[s->nsets++], sizeof s->sets[0], "%s", v);
  return RS_OK;
}

#define T settings_t
static const rs_opt_t table[] = {
    {.type = RS_OPT_MODEL, .name = "sensor", .arg = "NAME", .off = offsetof(T, model), .help = "the sensor"},
    {.type = RS_OPT_MODEL, .name = "model", .arg = "NAME", .off = offsetof(T, model), .flags = RS_OPT_NODEF,
     .help = "the same as --sensor"},
    {.type = RS_OPT_STR, .name = "scenario", .arg = "NAME", .off = offsetof(T, scenario), .fn = check_scenario,
     .help = "light, rush, turns, far or storm (docs/simulator.md)"},
    RS_OPT_STR_("scenario-file", "FILE", T, sfile, "KEY = VALUE lines (the --set keys) overriding the preset"),
    {.type = RS_OPT_FUNC, .name = "set", .arg = "KEY=VALUE", .off = offsetof(T, sets), .fn = add_set,
     .flags = RS_OPT_REPEAT, .help = "one scene knob, after the scenario file (the keys are listed above)"},
    RS_OPT_DBL_("seconds", "S", T, seconds, 0.1, 7200.0, "capture length"),
    {.type = RS_OPT_CHOICE, .name = "hz", .arg = "HZ", .off = offsetof(T, hz_i), .choices = "5|10|20",
     .help = "rotation rate"},
    {.type = RS_OPT_CHOICE, .name = "return-mode", .arg = "MODE", .off = offsetof(T, mode_i),
     .choices = "strongest|last|dual", .help = "which returns the sensor reports"},
    RS_OPT_INT_("seed", "N", T, seed, 0, 2147483647.0, "random seed (the traffic; the site has site_seed)"),
    RS_OPT_DBL_("start-time", "T", T, t0, 0.0, 4e9, "capture time of the first packet, s since 1970"),
    RS_OPT_OUTPUT_("FILE", T, out, "the capture (pcap, Ethernet)"),
    RS_OPT_STR_("labels", "FILE", T, labels, "ground truth: labels 2 (foliage, spurious) and 3+ (object ids)"),
    RS_OPT_STR_("truth-states", "FILE", T, states_path,
                "every road user's true state at the start of every turn (CSV t,id,class,x,y,vx,vy,heading,"
                "length,width,height; sensor frame, capture time)"),
    {.type = RS_OPT_FUNC, .name = "count-line", .arg = "\"NAME X1 Y1 X2 Y2\"", .off = offsetof(T, lines),
     .fn = rs_count_opt_line, .flags = RS_OPT_REPEAT,
     .help = "a counting line (metres, sensor frame), as roadscand's --count-line: its true crossings go to "
             "--truth-crossings"},
    RS_OPT_STR_("truth-crossings", "FILE", T, crossings_path,
                "every road user's true crossing of each --count-line (CSV t,id,class,line,direction; once per "
                "user and line, at the first turn its centre is past the line; forward: from the right of "
                "X1 Y1 -> X2 Y2 to its left)"),
};
#undef T

int main(int argc, char **argv) {
  st = (settings_t){.model = RS_MODEL_VLP32C, .scenario = "light", .seconds = 10.0, .t0 = 1700000000.0,
                    .hz_i = 1, .mode_i = 0, .seed = 1};
  int nk;
  const rs_opt_t *knobs = rs_scene_knobs(&nk);
  char keys[1024], about[1400];
  rs_opt_names(knobs, nk, keys, sizeof keys);
  snprintf(about, sizeof about,
           "Deterministic for a given --seed. The firing timing, block layout and azimuths are those the decoder "
           "reads back; every ray is cast through the scene at the true azimuth of its firing.\n\nScene knobs "
           "(--set, --scenario-file): %s.",
           keys);
  const rs_opts_spec_t spec = {
      .prog = "roadscan-sim",
      .summary = "a signalised intersection seen by a roadside Velodyne: a pcap of genuine sensor packets and "
                 "the per-point ground truth",
      .synopsis = "--sensor NAME -o OUT.pcap --labels OUT.csv [options]",
      .about = about,
      .epilog = "Exit status: 0 written, 1 cannot write or read a file, 2 bad usage.",
      .opts = table,
      .n = (int)(sizeof table / sizeof table[0]),
  };
  char err[RS_ERRMSG_SIZE];
  int first;
  const int start = rs_opts_start(&opts, &spec, &st, argc, argv, &first);
  if (start >= 0) return start;
  if (st.out == NULL || st.labels == NULL) {
    snprintf(err, sizeof err, "-o OUT.pcap and --labels OUT.csv are required");
    goto bad;
  }
  if (st.crossings_path && st.lines.n == 0) {
    snprintf(err, sizeof err, "--truth-crossings needs a --count-line");
    goto bad;
  }
  const rs_model_t model = st.model;
  const char *scenario = st.scenario, *out = st.out, *labels = st.labels, *states_path = st.states_path;
  const double seconds = st.seconds, hz = hz_of[st.hz_i], t0 = st.t0;
  const long seed = st.seed;
  const uint8_t mode = mode_of[st.mode_i];
  rs_scene_cfg_t scfg;
  rs_scene_preset(scenario, &scfg);
  if (st.sfile) {
    /* the scenario file: the scene knobs as keys, outside any section */
    static rs_opts_t sopts;
    const rs_opts_spec_t sspec = {.prog = "--scenario-file", .summary = "scene knobs", .opts = knobs, .n = nk};
    if (rs_opts_init(&sopts, &sspec, &scfg) != RS_OK || rs_opts_read_file(&sopts, st.sfile) != RS_OK) {
      fprintf(stderr, "roadscan-sim: %s\n", sopts.err);
      return 1;
    }
  }
  for (int i = 0; i < st.nsets; i++) {
    char key[128];
    const char *eq = strchr(st.sets[i], '=');
    snprintf(key, sizeof key, "%.*s", (int)(eq - st.sets[i]), st.sets[i]);
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
  FILE *states = NULL, *crossings = NULL;
  static rs_agent_state_t agents[4096];
  /* the true crossings: each road user's previous position (by id) and the lines it has crossed */
  typedef struct {
    double x, y;
    bool seen;
    uint16_t counted;
  } prev_t;
  prev_t *prev = NULL;
  size_t nprev = 0;
  uint64_t ncross = 0;
  if (st.crossings_path) {
    crossings = fopen(st.crossings_path, "w");
    if (crossings == NULL) {
      fprintf(stderr, "roadscan-sim: %s: cannot write\n", st.crossings_path);
      return 1;
    }
    fprintf(crossings, "t,id,class,line,direction\n");
  }
  if (states_path) {
    states = fopen(states_path, "w");
    if (states == NULL) {
      fprintf(stderr, "roadscan-sim: %s: cannot write\n", states_path);
      return 1;
    }
    fprintf(states, "t,id,class,x,y,vx,vy,heading,length,width,height\n");
  }

  const bool dual = mode == RS_MODE_DUAL;
  const int nb = rs_layout_blocks(mi, dual);
  const int groups = rs_layout_groups(mi, dual);
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
      if (states || crossings) { /* the road users at the turn's start */
        rs_scene_prepare(sc, t_pkt * 1e-6, 0.0, 0.0);
        const int na = rs_scene_states(sc, t_pkt * 1e-6, agents, (int)(sizeof agents / sizeof agents[0]));
        for (int i = 0; i < na && states; i++)
          fprintf(states, "%.6f,%u,%s,%.3f,%.3f,%.3f,%.3f,%.4f,%.2f,%.2f,%.2f\n", t0 + t_pkt * 1e-6, agents[i].id,
                  agents[i].cls, agents[i].x, agents[i].y, agents[i].vx, agents[i].vy, agents[i].heading,
                  agents[i].length, agents[i].width, agents[i].height);
        for (int i = 0; i < na && crossings; i++) {
          const uint32_t id = agents[i].id;
          if (id >= nprev) { /* ids grow one by one: a table indexed by id */
            const size_t n2 = (id + 1) * 2;
            prev_t *np = realloc(prev, n2 * sizeof *np);
            if (np == NULL) {
              fprintf(stderr, "roadscan-sim: out of memory for the crossings\n");
              return 1;
            }
            memset(np + nprev, 0, (n2 - nprev) * sizeof *np);
            prev = np;
            nprev = n2;
          }
          prev_t *p = &prev[id];
          for (int l = 0; l < st.lines.n && p->seen; l++) {
            if (p->counted & (1u << l)) continue;
            const int d = rs_count_crosses(&st.lines.line[l], p->x, p->y, agents[i].x, agents[i].y);
            if (d == 0) continue;
            p->counted |= (uint16_t)(1u << l);
            ncross++;
            fprintf(crossings, "%.6f,%u,%s,%s,%s\n", t0 + t_pkt * 1e-6, id, agents[i].cls, st.lines.line[l].name,
                    d > 0 ? "forward" : "backward");
          }
          p->x = agents[i].x;
          p->y = agents[i].y;
          p->seen = true;
        }
      }
    }
    last_az = fmod(az0, 360.0);
    rs_scene_prepare(sc, t_pkt * 1e-6, fmod(az0 - 8.0 + 720.0, 360.0), fmod(az_end + 8.0, 360.0));
    bool lose = scfg.packet_loss > 0 && rs_rng_uniform(&fx) < scfg.packet_loss;
    memset(&enc, 0, sizeof enc);
    enc.mode_byte = mode;
    enc.timestamp_us = (uint32_t)fmod(t0 * 1e6 + t_pkt, 3600e6);
    const double yaw = rs_scene_yaw(&scfg, t_pkt * 1e-6);
    const long yaw_c = lround(yaw * 100.0) % 36000L;
    for (int b = 0; b < RS_BLOCKS; b++) {
      const int g = rs_layout_group(mi, dual, b < nb ? b : nb - 1);
      double azg = az0 + rate * g * group_us;
      enc.block_azimuth[b] = (uint16_t)((long)llround(fmod(azg, 360.0) * 100.0) % 36000);
      if (b >= nb) continue;
      const int bank = rs_layout_bank(mi, dual, b);
      bool odd = dual && (b % 2 == 1);
      if (!odd) {
        for (int ch = 0; ch < RS_RECORDS; ch++) {
          int laser;
          float tf;
          rs_sensor_record(&sensor, bank, ch, &laser, &tf);
          /* the sensor turned against its mount by yaw: the ray leaves at its azimuth field
           * plus yaw, the field reads as ever */
          double az = (double)enc.block_azimuth[b] / 100.0 + yaw + sensor.azimuth_offset_deg[laser] + rate * tf;
          rs_scene_cast(sc, bank * RS_RECORDS + ch, (int)(((long)enc.block_azimuth[b] + yaw_c + 36000L) % 36000L), laser,
                        az, &fx, &rays[ch]);
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
  free(prev);
  if (crossings) {
    if (fclose(crossings) != 0) {
      fprintf(stderr, "roadscan-sim: %s: write failed\n", st.crossings_path);
      return 1;
    }
    fprintf(stderr, "roadscan-sim: %llu true crossings of %d lines written to %s\n", (unsigned long long)ncross,
            st.lines.n, st.crossings_path);
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

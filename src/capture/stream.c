/* stream.c - classification, detection pre-buffer and decoding (packet thread). */
#include "roadscan/capture/stream.h"

#include "roadscan/capture/net.h"

#include <arpa/inet.h>
#include <string.h>

int rs_stream_init(rs_stream_t *st, const rs_stream_cfg_t *cfg) {
  memset(st, 0, sizeof *st);
  st->cfg = *cfg;
  if (st->cfg.data_port == 0) st->cfg.data_port = RS_DEFAULT_DATA_PORT;
  if (st->cfg.position_port == 0) st->cfg.position_port = RS_DEFAULT_POSITION_PORT;
  if (st->cfg.default_hz <= 0.0) st->cfg.default_hz = 10.0;
  st->rate_hint = rs_rate_from_hz(st->cfg.default_hz);
  if (cfg->source_addr && cfg->source_addr[0]) {
    if (inet_pton(AF_INET, cfg->source_addr, st->src_addr) == 1) st->src_ver = 4;
    else if (inet_pton(AF_INET6, cfg->source_addr, st->src_addr) == 1) st->src_ver = 6;
    else {
      snprintf(st->err, sizeof st->err, "source address \"%s\" is not an IPv4 or IPv6 address", cfg->source_addr);
      return RS_E_INVAL;
    }
    st->have_src = true;
  }
  rs_detect_init(&st->det, cfg->force_model);
  return RS_OK;
}

void rs_stream_count(rs_stream_t *st, int code, const char *detail) {
  int i = rs_err_index(code);
  if (i < 0) return;
  if (st->n.errors[i]++ == 0 && st->cfg.log)
    fprintf(st->cfg.log, "roadscan: %s%s%s (further ones are counted, see the summary)\n", rs_strerror(code),
            detail ? ": " : "", detail ? detail : "");
}

uint64_t rs_stream_error_total(const rs_stream_counters_t *n) {
  uint64_t t = 0;
  for (int i = 0; i < RS_ERR_COUNT; i++) t += n->errors[i];
  return t;
}

void rs_stream_print_errors(const rs_stream_counters_t *n, FILE *out) {
  bool any = false;
  for (int i = 0; i < RS_ERR_COUNT; i++) {
    if (n->errors[i] == 0) continue;
    fprintf(out, "%s%s=%llu", any ? " " : "", rs_err_key(rs_err_from_index(i)), (unsigned long long)n->errors[i]);
    any = true;
  }
  if (!any) fprintf(out, "none");
}

static int make_sensor(rs_stream_t *st, rs_model_t m) {
  rs_sensor_init(&st->sensor, m);
  if (st->cfg.calib) {
    char warn[RS_ERRMSG_SIZE];
    int rc = rs_calib_apply(st->cfg.calib, &st->sensor, st->err, sizeof st->err, warn, sizeof warn);
    if (rc != RS_OK) {
      st->failed = true;
      st->fail_code = RS_E_CALIB;
      return rc;
    }
    if (warn[0] && st->cfg.log) fprintf(st->cfg.log, "roadscan: calibration: %s\n", warn);
  }
  st->sensor_ready = true;
  if (st->cfg.log) fprintf(st->cfg.log, "roadscan: sensor %s (%s)%s\n", rs_model_name(m),
                           st->det.reason, st->cfg.calib ? ", per-unit calibration applied" : "");
  return RS_OK;
}

/* A packet of another model: counted; a run of them is a switched sensor. */
static int foreign_packet(rs_stream_t *st, const uint8_t *p, uint32_t index) {
  char detail[128];
  const uint8_t prod = p[RS_PAYLOAD_SIZE - 1];
  const rs_model_t m = rs_model_from_product(prod);
  snprintf(detail, sizeof detail, "data packet %u has product byte 0x%02X (%s), the stream's sensor is a %s (0x%02X)",
           index, prod, m == RS_MODEL_UNKNOWN ? "unknown" : rs_model_name(m), st->sensor.info->name, st->det.product);
  rs_stream_count(st, RS_E_PRODUCT_MISMATCH, detail);
  if (m == RS_MODEL_UNKNOWN) return RS_OK; /* a corrupt byte, not another sensor */
  if (st->foreign_run++ == 0) st->foreign_first = index;
  if (st->foreign_run < RS_STREAM_SWITCH_PACKETS) return RS_OK;
  snprintf(st->err, sizeof st->err,
           "the sensor changed mid-stream: the %u data packets since packet %u are from a %s (product byte 0x%02X), "
           "none from the %s this run was set up for; restart to identify the new sensor (a background model and "
           "calibration are per sensor)",
           st->foreign_run, st->foreign_first, rs_model_name(m), prod, st->sensor.info->name);
  rs_stream_count(st, RS_E_SENSOR_CHANGED, NULL);
  st->failed = true;
  st->fail_code = RS_E_SENSOR_CHANGED;
  return RS_E_SENSOR_CHANGED;
}

static int decode_emit(rs_stream_t *st, const uint8_t *p, uint32_t index, double ts, rs_stream_emit_fn emit,
                       void *user) {
  char detail[96];
  if (st->det.forced == RS_MODEL_UNKNOWN && p[RS_PAYLOAD_SIZE - 1] != st->det.product)
    return foreign_packet(st, p, index);
  int rc = rs_packet_decode(&st->sensor, p, RS_PAYLOAD_SIZE, st->rate_hint, &st->pkt);
  if (rc != RS_OK) {
    snprintf(detail, sizeof detail, "data packet %u", index);
    rs_stream_count(st, rc, detail);
    return RS_OK;
  }
  st->foreign_run = 0;
  st->n.decoded++;
  if (emit) emit(user, &st->pkt, index, ts);
  return RS_OK;
}

static int drain(rs_stream_t *st, rs_stream_emit_fn emit, void *user) {
  int rc = RS_OK;
  for (int i = 0; i < st->npre && rc == RS_OK; i++)
    rc = decode_emit(st, st->pre[i], st->pre_index[i], st->pre_ts[i], emit, user);
  st->npre = 0;
  return rc;
}

int rs_stream_payload(rs_stream_t *st, const uint8_t *payload, uint32_t len, uint16_t dst_port, double ts,
                      rs_stream_emit_fn emit, void *user) {
  char detail[96];
  if (st->failed) return st->fail_code;
  if (dst_port != st->cfg.data_port) {
    if (dst_port == st->cfg.position_port) st->n.position_packets++;
    else st->n.other_packets++;
    return RS_OK;
  }
  if (len != RS_PAYLOAD_SIZE) {
    snprintf(detail, sizeof detail, "%u-byte payload to port %u at t=%.6f", len, dst_port, ts);
    rs_stream_count(st, len < RS_PAYLOAD_SIZE ? RS_E_PKT_SHORT : RS_E_PKT_LONG, detail);
    return RS_OK;
  }
  uint32_t index = st->next_index++;
  st->n.data_packets++;
  int rc = rs_packet_check(payload, len);
  if (rc != RS_OK) {
    snprintf(detail, sizeof detail, "data packet %u", index);
    rs_stream_count(st, rc, detail);
    return RS_OK;
  }
  if (!st->sensor_ready) {
    int m = rs_detect_feed(&st->det, payload, len);
    if (m < 0) {
      snprintf(detail, sizeof detail, "data packet %u, product byte 0x%02X (known: %s)", index,
               payload[RS_PAYLOAD_SIZE - 1], rs_model_names());
      rs_stream_count(st, m, detail);
      return RS_OK;
    }
    if (m == RS_MODEL_UNKNOWN) {
      memcpy(st->pre[st->npre], payload, RS_PAYLOAD_SIZE);
      st->pre_index[st->npre] = index;
      st->pre_ts[st->npre] = ts;
      st->npre++;
      return RS_OK;
    }
    rc = make_sensor(st, (rs_model_t)m);
    if (rc != RS_OK) return rc;
    rc = drain(st, emit, user);
    if (rc != RS_OK) return rc;
  }
  return decode_emit(st, payload, index, ts, emit, user);
}

int rs_stream_frame(rs_stream_t *st, int linktype, const rs_frame_in_t *f, rs_stream_emit_fn emit, void *user) {
  st->n.frames++;
  rs_udp_t u;
  int rc = rs_net_parse(linktype, f->data, f->caplen, &u);
  if (rc == RS_E_NOT_IP || rc == RS_E_NOT_UDP) {
    st->n.other_packets++;
    return RS_OK;
  }
  if (rc != RS_OK) {
    char detail[96];
    snprintf(detail, sizeof detail, "captured frame %llu (%u of %u bytes captured)", (unsigned long long)st->n.frames,
             f->caplen, f->wirelen);
    rs_stream_count(st, rc, detail);
    return RS_OK;
  }
  if (st->have_src) {
    size_t alen = st->src_ver == 4 ? 4 : 16;
    if (u.ip_version != st->src_ver || memcmp(u.src_addr, st->src_addr, alen) != 0) {
      st->n.other_packets++;
      return RS_OK;
    }
  }
  return rs_stream_payload(st, u.payload, u.len, u.dst_port, f->ts, emit, user);
}

int rs_stream_finish(rs_stream_t *st, rs_stream_emit_fn emit, void *user) {
  if (st->failed) return st->fail_code;
  if (!st->sensor_ready && st->npre > 0) {
    int m = rs_detect_finish(&st->det);
    if (m <= 0) return RS_OK;
    int rc = make_sensor(st, (rs_model_t)m);
    if (rc != RS_OK) return rc;
  }
  return drain(st, emit, user);
}

int rs_stream_replay_file(rs_stream_t *st, const char *path, rs_stream_emit_fn emit, void *user, const bool *stop,
                          char *err, size_t n) {
  rs_capture_cfg_t cc = {.data_port = st->cfg.data_port, .speed = 0.0};
  static rs_capture_t cap; /* tools only: one replay at a time */
  int rc = rs_capture_open_file(&cap, path, &cc);
  if (rc != RS_OK) {
    snprintf(err, n, "%s", cap.err);
    return rc;
  }
  rs_frame_in_t f;
  int status = RS_OK;
  while (!(stop && *stop)) {
    rc = rs_capture_next(&cap, &f, NULL);
    if (rc != 1) {
      if (rc < 0) {
        snprintf(err, n, "%s", cap.err);
        status = rc;
      }
      break;
    }
    if ((rc = rs_stream_frame(st, cap.linktype, &f, emit, user)) != RS_OK) {
      snprintf(err, n, "%s", st->err);
      status = rc;
      break;
    }
  }
  rs_capture_close(&cap);
  if (!st->failed && !(stop && *stop) && (rc = rs_stream_finish(st, emit, user)) != RS_OK) {
    snprintf(err, n, "%s", st->err);
    status = rc;
  }
  return status;
}

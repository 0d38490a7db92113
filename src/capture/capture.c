/* capture.c - libpcap wrapper (packet thread). */
#include "roadscan/capture/capture.h"

#include "roadscan/util/error.h"
#include "roadscan/capture/net.h"
#include "roadscan/sensor/sensor.h"

#include <errno.h>
#include <pcap/pcap.h>
#include <poll.h>
#include <stdio.h>
#include <math.h>
#include <string.h>
#include <sys/stat.h>

#define POLL_MS 100

void rs_capture_filter(const rs_capture_cfg_t *cfg, char *buf, size_t n) {
  /* data and position packets (the stream counts the position ones) */
  if (cfg->source_addr && cfg->source_addr[0])
    snprintf(buf, n, "udp and (dst port %u or dst port %u) and src host %s", cfg->data_port, RS_DEFAULT_POSITION_PORT,
             cfg->source_addr);
  else
    snprintf(buf, n, "udp and (dst port %u or dst port %u)", cfg->data_port, RS_DEFAULT_POSITION_PORT);
}

static int check_linktype(rs_capture_t *c) {
  c->linktype = pcap_datalink(c->p);
  if (!rs_net_linktype_supported(c->linktype)) {
    const char *name = pcap_datalink_val_to_name(c->linktype);
    snprintf(c->err, sizeof c->err, "%s: unsupported link-layer type %d (%s); supported: Ethernet, VLAN, Linux cooked v1/v2, raw IP, loopback",
             c->path, c->linktype, name ? name : "?");
    pcap_close(c->p);
    c->p = NULL;
    return RS_E_LINKTYPE;
  }
  return RS_OK;
}

static int open_offline(rs_capture_t *c) {
  char eb[PCAP_ERRBUF_SIZE] = "";
  c->p = pcap_open_offline_with_tstamp_precision(c->path, PCAP_TSTAMP_PRECISION_NANO, eb);
  c->ts_unit = 1e-9;
  if (c->p == NULL) {
    struct stat st;
    if (stat(c->path, &st) != 0) {
      snprintf(c->err, sizeof c->err, "%s: %s", c->path, strerror(errno));
      return errno == ENOENT ? RS_E_NOENT : RS_E_IO;
    }
    snprintf(c->err, sizeof c->err, "%s: not a readable pcap/pcapng capture: %s", c->path, eb);
    return RS_E_FORMAT;
  }
  return check_linktype(c);
}

int rs_capture_open_file(rs_capture_t *c, const char *path, const rs_capture_cfg_t *cfg) {
  memset(c, 0, sizeof *c);
  c->cfg = *cfg;
  snprintf(c->path, sizeof c->path, "%s", path);
  return open_offline(c);
}

int rs_capture_open_live(rs_capture_t *c, const char *iface, const rs_capture_cfg_t *cfg) {
  memset(c, 0, sizeof *c);
  c->cfg = *cfg;
  c->live = true;
  snprintf(c->path, sizeof c->path, "%s", iface);
  char eb[PCAP_ERRBUF_SIZE] = "";
  c->p = pcap_create(iface, eb);
  if (c->p == NULL) {
    snprintf(c->err, sizeof c->err, "%s: %s", iface, eb);
    return RS_E_CAPTURE;
  }
  pcap_set_snaplen(c->p, cfg->snaplen > 0 ? cfg->snaplen : 2048);
  pcap_set_promisc(c->p, 0);
  pcap_set_immediate_mode(c->p, 1);
  (void)pcap_set_tstamp_precision(c->p, PCAP_TSTAMP_PRECISION_NANO); /* microseconds where refused */
  c->buffer_bytes = cfg->buffer_bytes > 0 ? cfg->buffer_bytes : RS_CAPTURE_BUFFER_DEFAULT;
  pcap_set_buffer_size(c->p, c->buffer_bytes);
  int rc = pcap_activate(c->p);
  if (rc < 0) {
    int code = RS_E_CAPTURE;
    if (rc == PCAP_ERROR_PERM_DENIED) {
      snprintf(c->err, sizeof c->err,
               "%s: permission denied (run as root or give the binary cap_net_raw: setcap cap_net_raw=eip roadscand)", iface);
      code = RS_E_PERM;
    } else if (rc == PCAP_ERROR_NO_SUCH_DEVICE) {
      snprintf(c->err, sizeof c->err, "%s: no such capture interface", iface);
      code = RS_E_NODEV;
    } else {
      snprintf(c->err, sizeof c->err, "%s: %s", iface, pcap_geterr(c->p));
    }
    pcap_close(c->p);
    c->p = NULL;
    return code;
  }
  c->ts_unit = pcap_get_tstamp_precision(c->p) == PCAP_TSTAMP_PRECISION_NANO ? 1e-9 : 1e-6;
  rc = check_linktype(c);
  if (rc != RS_OK) return rc;
  char filter[160];
  rs_capture_filter(cfg, filter, sizeof filter);
  struct bpf_program prog;
  if (pcap_compile(c->p, &prog, filter, 1, PCAP_NETMASK_UNKNOWN) != 0 || pcap_setfilter(c->p, &prog) != 0) {
    snprintf(c->err, sizeof c->err, "%s: BPF filter \"%s\": %s", iface, filter, pcap_geterr(c->p));
    pcap_close(c->p);
    c->p = NULL;
    return RS_E_INVAL;
  }
  pcap_freecode(&prog);
  if (pcap_setnonblock(c->p, 1, eb) != 0) {
    snprintf(c->err, sizeof c->err, "%s: %s", iface, eb);
    pcap_close(c->p);
    c->p = NULL;
    return RS_E_CAPTURE;
  }
  return RS_OK;
}

void rs_capture_close(rs_capture_t *c) {
  if (c->p) pcap_close(c->p);
  c->p = NULL;
}

bool rs_capture_kstats(rs_capture_t *c) {
  if (!c->live || c->p == NULL) return false;
  struct pcap_stat ps;
  if (pcap_stats(c->p, &ps) != 0) return false;
  /* libpcap's counters are 32-bit and wrap: carry them into 64 bits */
  uint32_t last[3] = {(uint32_t)c->kstats.received, (uint32_t)c->kstats.dropped, (uint32_t)c->kstats.if_dropped};
  c->kstats.received += (uint32_t)(ps.ps_recv - last[0]);
  c->kstats.dropped += (uint32_t)(ps.ps_drop - last[1]);
  c->kstats.if_dropped += (uint32_t)(ps.ps_ifdrop - last[2]);
  return true;
}

static double ts_of(const rs_capture_t *c, const struct pcap_pkthdr *h) {
  /* tv_usec holds nanoseconds where the handle has nanosecond precision
   * (files always; live when the kernel grants it), else microseconds */
  return (double)h->ts.tv_sec + (double)h->ts.tv_usec * c->ts_unit;
}

static void pace(rs_capture_t *c, double ts, const _Atomic bool *stop) {
  if (c->cfg.speed <= 0.0) return;
  if (!c->have_t0) {
    c->have_t0 = true;
    c->t0_cap = ts;
    clock_gettime(CLOCK_MONOTONIC, &c->t0_mono);
    return;
  }
  const double gap = ts - c->last_ts;
  if (gap > RS_CAPTURE_MAX_GAP_S || gap < -RS_CAPTURE_MAX_GAP_S) {
    /* a jump in the capture's clock (a pause, a corrupt record, a clock reset):
     * the timing goes on from here, as if this record came right after the previous one */
    c->t0_cap += gap;
    c->jumps++;
    if (fabs(gap) > c->jump_max) c->jump_max = fabs(gap);
  }
  double wait = (ts - c->t0_cap) / c->cfg.speed;
  if (wait < 0) return; /* within the tolerance, a little backwards: no wait */
  struct timespec due = c->t0_mono;
  double sec = (double)(long)wait;
  due.tv_sec += (time_t)sec;
  due.tv_nsec += (long)((wait - sec) * 1e9);
  if (due.tv_nsec >= 1000000000L) {
    due.tv_sec++;
    due.tv_nsec -= 1000000000L;
  }
  /* sleep in slices so a stop request is honoured within POLL_MS */
  for (int i = 0; i < 1000000; i++) {
    struct timespec now;
    clock_gettime(CLOCK_MONOTONIC, &now);
    double left = (double)(due.tv_sec - now.tv_sec) + (double)(due.tv_nsec - now.tv_nsec) * 1e-9;
    if (left <= 0 || (stop && atomic_load(stop))) return;
    if (left > POLL_MS * 1e-3) {
      struct timespec d = {0, POLL_MS * 1000000L};
      nanosleep(&d, NULL);
    } else {
      clock_nanosleep(CLOCK_MONOTONIC, TIMER_ABSTIME, &due, NULL);
      return;
    }
  }
}

static void deliver(rs_capture_t *c, const struct pcap_pkthdr *h, const u_char *data, rs_frame_in_t *out,
                    const _Atomic bool *stop) {
  double ts = ts_of(c, h) + c->loop_offset;
  if (!c->live) pace(c, ts, stop);
  c->last_ts = ts;
  out->data = data;
  out->caplen = h->caplen;
  out->wirelen = h->len;
  out->ts = ts;
}

/* Loop mode at the end of the file: reopen, and shift the capture times so
 * the next pass starts one millisecond after the previous one ended. */
static int restart(rs_capture_t *c, struct pcap_pkthdr **h, const u_char **data) {
  double span_end = c->last_ts;
  pcap_close(c->p);
  c->p = NULL;
  int rc = open_offline(c);
  if (rc != RS_OK) return rc;
  if (pcap_next_ex(c->p, h, data) != 1) return RS_CAPTURE_EOF;
  c->loop_offset = span_end + 1e-3 - ts_of(c, *h);
  c->loops++;
  return 1;
}

int rs_capture_next(rs_capture_t *c, rs_frame_in_t *out, const _Atomic bool *stop) {
  struct pcap_pkthdr *h;
  const u_char *data;
  int rc = pcap_next_ex(c->p, &h, &data);
  if (c->live) {
    if (rc == 0) { /* non-blocking: wait for the descriptor, then try once more */
      struct pollfd pfd = {.fd = pcap_get_selectable_fd(c->p), .events = POLLIN};
      if (pfd.fd >= 0) poll(&pfd, 1, POLL_MS);
      rc = pcap_next_ex(c->p, &h, &data);
      if (rc == 0) return 0;
    }
    if (rc < 0) {
      snprintf(c->err, sizeof c->err, "%s: %s", c->path, pcap_geterr(c->p));
      return RS_E_CAPTURE;
    }
    deliver(c, h, data, out, stop);
    return 1;
  }
  if (rc == PCAP_ERROR_BREAK) {
    if (!c->cfg.loop || (stop && atomic_load(stop))) return RS_CAPTURE_EOF;
    rc = restart(c, &h, &data);
    if (rc != 1) return rc;
  }
  if (rc == 1) {
    deliver(c, h, data, out, stop);
    return 1;
  }
  /* libpcap says "truncated dump file" for a capture cut short */
  const char *e = pcap_geterr(c->p);
  bool trunc = strstr(e, "truncated") != NULL;
  snprintf(c->err, sizeof c->err, "%s: %s%s", c->path, e,
           trunc ? " (capture file cut short; everything before this point was read)" : "");
  return trunc ? RS_E_TRUNCATED : RS_E_IO;
}

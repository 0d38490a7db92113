/* pcapw.c - pcap writer over libpcap's dump API (tools and tests only). */
#include "roadscan/offline/pcapw.h"

#include "roadscan/util/error.h"
#include "roadscan/capture/net.h"

#include <pcap/pcap.h>
#include <string.h>

#define FRAME_CAP 2048

int rs_pcapw_open(rs_pcapw_t *w, const char *path, int linktype, uint16_t vlan) {
  memset(w, 0, sizeof *w);
  int dlt = linktype == RS_LINK_RAW ? DLT_RAW : linktype;
  w->p = pcap_open_dead_with_tstamp_precision(dlt, 65535, PCAP_TSTAMP_PRECISION_NANO);
  if (w->p == NULL) return RS_E_IO;
  w->d = pcap_dump_open(w->p, path);
  if (w->d == NULL) {
    pcap_close(w->p);
    w->p = NULL;
    return RS_E_IO;
  }
  w->linktype = linktype;
  w->vlan = vlan;
  const uint8_t src[4] = {192, 168, 1, 201}, dst[4] = {255, 255, 255, 255};
  memcpy(w->src_ip, src, 4);
  memcpy(w->dst_ip, dst, 4);
  w->src_port = 2368;
  return RS_OK;
}

int rs_pcapw_write_raw(rs_pcapw_t *w, double ts, const uint8_t *frame, size_t caplen, size_t wirelen) {
  struct pcap_pkthdr h;
  memset(&h, 0, sizeof h);
  h.ts.tv_sec = (time_t)ts;
  h.ts.tv_usec = (suseconds_t)((ts - (double)h.ts.tv_sec) * 1e9 + 0.5); /* nanoseconds */
  if (h.ts.tv_usec >= 1000000000) {
    h.ts.tv_sec++;
    h.ts.tv_usec -= 1000000000;
  }
  h.caplen = (bpf_u_int32)caplen;
  h.len = (bpf_u_int32)wirelen;
  pcap_dump((u_char *)w->d, &h, frame);
  w->written++;
  return RS_OK;
}

int rs_pcapw_write(rs_pcapw_t *w, double ts, uint16_t dst_port, const uint8_t *payload, size_t len) {
  uint8_t frame[FRAME_CAP];
  size_t n = rs_net_build_udp4(w->linktype, w->vlan, w->src_ip, w->dst_ip, w->src_port, dst_port, payload, len,
                               frame, sizeof frame);
  if (n == 0) return RS_E_INVAL;
  return rs_pcapw_write_raw(w, ts, frame, n, n);
}

void rs_pcapw_close(rs_pcapw_t *w) {
  if (w->d) pcap_dump_close(w->d);
  if (w->p) pcap_close(w->p);
  w->d = NULL;
  w->p = NULL;
}

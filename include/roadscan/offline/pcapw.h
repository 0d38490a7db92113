/* pcapw.h - writing Velodyne traffic to pcap files (libpcap's dump API), for
 * the simulator, tools and tests. Not used on the real-time path. */
#ifndef ROADSCAN_PCAPW_H
#define ROADSCAN_PCAPW_H

#include <stddef.h>
#include <stdint.h>

typedef struct pcap pcap_t;
typedef struct pcap_dumper pcap_dumper_t;

typedef struct {
  pcap_t *p;
  pcap_dumper_t *d;
  int linktype;
  uint16_t vlan;
  uint8_t src_ip[4], dst_ip[4];
  uint16_t src_port;
  uint64_t written;
} rs_pcapw_t;

/* linktype: RS_LINK_ETHERNET (vlan > 0 adds a tag), RS_LINK_SLL, RS_LINK_SLL2,
 * RS_LINK_RAW, RS_LINK_NULL. Source 192.168.1.201:2368 -> 255.255.255.255. */
int rs_pcapw_open(rs_pcapw_t *w, const char *path, int linktype, uint16_t vlan);
/* One UDP datagram to dst_port at capture time ts (s). */
int rs_pcapw_write(rs_pcapw_t *w, double ts, uint16_t dst_port, const uint8_t *payload, size_t len);
/* A raw frame as is (for malformed-input tests). */
int rs_pcapw_write_raw(rs_pcapw_t *w, double ts, const uint8_t *frame, size_t caplen, size_t wirelen);
void rs_pcapw_close(rs_pcapw_t *w);

#endif

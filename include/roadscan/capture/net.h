/* net.h - link-layer, IP and UDP parsing of captured frames, and building of
 * such frames for the capture writer.
 *
 * Pure functions; the packet thread calls rs_net_parse on every captured
 * frame. Link types: Ethernet (with any number of 802.1Q/802.1ad tags),
 * Linux cooked v1 and v2, raw IP (DLT_RAW, LINKTYPE_RAW, DLT_IPV4, DLT_IPV6),
 * BSD loopback (DLT_NULL, DLT_LOOP). IPv4 and IPv6. */
#ifndef ROADSCAN_NET_H
#define ROADSCAN_NET_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

/* pcap link-type numbers (LINKTYPE_*), fixed by the file format */
enum {
  RS_LINK_NULL = 0,
  RS_LINK_ETHERNET = 1,
  RS_LINK_RAW_DLT = 12,   /* DLT_RAW on most systems */
  RS_LINK_RAW_DLT14 = 14, /* DLT_RAW on some BSDs */
  RS_LINK_RAW = 101,
  RS_LINK_LOOP = 108,
  RS_LINK_SLL = 113,
  RS_LINK_IPV4 = 228,
  RS_LINK_IPV6 = 229,
  RS_LINK_SLL2 = 276,
};

typedef struct {
  const uint8_t *payload;
  uint32_t len;          /* UDP payload length (from the UDP header) */
  uint16_t src_port, dst_port;
  uint8_t ip_version;    /* 4 or 6 */
  uint8_t src_addr[16];  /* IPv4 in the first 4 bytes */
  uint8_t dst_addr[16];
  uint16_t vlan;         /* outermost VLAN id, 0 if none */
} rs_udp_t;

bool rs_net_linktype_supported(int linktype);
const char *rs_net_linktype_name(int linktype);

/* RS_OK and *out filled; or RS_E_LINKTYPE, RS_E_TRUNCATED (caplen short of
 * what the headers announce), RS_E_NOT_IP, RS_E_NOT_UDP, RS_E_FRAGMENT,
 * RS_E_IP_HEADER, RS_E_UDP_LENGTH. */
int rs_net_parse(int linktype, const uint8_t *frame, uint32_t caplen, rs_udp_t *out);

/* Builds a frame of the given link type carrying one IPv4 UDP datagram
 * (IPv4 header checksum set, UDP checksum 0). `vlan` > 0 adds an 802.1Q tag
 * (Ethernet only). Returns the frame length, or 0 when `cap` is too small. */
size_t rs_net_build_udp4(int linktype, uint16_t vlan, const uint8_t src_ip[4], const uint8_t dst_ip[4],
                         uint16_t src_port, uint16_t dst_port, const uint8_t *payload, size_t len,
                         uint8_t *frame, size_t cap);

#endif

/* net.c - captured-frame parsing down to the UDP payload (pure). */
#include "roadscan/capture/net.h"

#include "roadscan/util/error.h"

#include <string.h>

static uint16_t be16(const uint8_t *p) { return (uint16_t)((p[0] << 8) | p[1]); }
static uint32_t le32(const uint8_t *p) {
  return (uint32_t)p[0] | ((uint32_t)p[1] << 8) | ((uint32_t)p[2] << 16) | ((uint32_t)p[3] << 24);
}
static uint32_t be32(const uint8_t *p) {
  return ((uint32_t)p[0] << 24) | ((uint32_t)p[1] << 16) | ((uint32_t)p[2] << 8) | (uint32_t)p[3];
}

#define ETH_IPV4 0x0800
#define ETH_IPV6 0x86DD
#define ETH_VLAN 0x8100
#define ETH_QINQ 0x88A8
#define ETH_QINQ_OLD 0x9100
#define MAX_VLAN_TAGS 4
#define MAX_IPV6_EXT 8

bool rs_net_linktype_supported(int lt) {
  switch (lt) {
  case RS_LINK_NULL: case RS_LINK_ETHERNET: case RS_LINK_RAW_DLT: case RS_LINK_RAW_DLT14:
  case RS_LINK_RAW: case RS_LINK_LOOP: case RS_LINK_SLL: case RS_LINK_IPV4: case RS_LINK_IPV6:
  case RS_LINK_SLL2:
    return true;
  default: return false;
  }
}

const char *rs_net_linktype_name(int lt) {
  switch (lt) {
  case RS_LINK_NULL: return "BSD loopback (NULL)";
  case RS_LINK_ETHERNET: return "Ethernet";
  case RS_LINK_RAW_DLT: case RS_LINK_RAW_DLT14: case RS_LINK_RAW: return "raw IP";
  case RS_LINK_LOOP: return "OpenBSD loopback";
  case RS_LINK_SLL: return "Linux cooked (SLL)";
  case RS_LINK_IPV4: return "raw IPv4";
  case RS_LINK_IPV6: return "raw IPv6";
  case RS_LINK_SLL2: return "Linux cooked v2 (SLL2)";
  default: return "unsupported";
  }
}

static int parse_udp(const uint8_t *p, uint32_t n, rs_udp_t *out) {
  if (n < 8) return RS_E_TRUNCATED;
  uint16_t ulen = be16(p + 4);
  if (ulen < 8 || ulen > n) return RS_E_UDP_LENGTH; /* n: what the IP header announces */
  out->src_port = be16(p);
  out->dst_port = be16(p + 2);
  out->payload = p + 8;
  out->len = (uint32_t)ulen - 8;
  return RS_OK;
}

static int parse_ipv4(const uint8_t *p, uint32_t n, rs_udp_t *out) {
  if (n < 20) return RS_E_TRUNCATED;
  if ((p[0] >> 4) != 4) return RS_E_IP_HEADER;
  uint32_t ihl = (uint32_t)(p[0] & 0x0F) * 4;
  uint32_t total = be16(p + 2);
  if (ihl < 20 || total < ihl) return RS_E_IP_HEADER;
  if (n < ihl + 8) return RS_E_TRUNCATED;
  uint16_t frag = be16(p + 6);
  if ((frag & 0x3FFF) != 0) return RS_E_FRAGMENT; /* MF set or offset != 0 */
  if (p[9] != 17) return RS_E_NOT_UDP;
  out->ip_version = 4;
  memset(out->src_addr, 0, sizeof out->src_addr);
  memset(out->dst_addr, 0, sizeof out->dst_addr);
  memcpy(out->src_addr, p + 12, 4);
  memcpy(out->dst_addr, p + 16, 4);
  /* Bytes past `total` are Ethernet padding. Some sensors (early VLP-16
   * firmware, position packets) announce a total length larger than what
   * they send; the datagram is still whole when the UDP length fits in what
   * arrived, so the UDP header decides. */
  uint32_t avail = (total < n ? total : n) - ihl;
  uint32_t ulen = be16(p + ihl + 4);
  if (ulen > avail && ulen <= total - ihl) return RS_E_TRUNCATED; /* the capture cut it */
  return parse_udp(p + ihl, avail, out);
}

static int parse_ipv6(const uint8_t *p, uint32_t n, rs_udp_t *out) {
  if (n < 40) return RS_E_TRUNCATED;
  if ((p[0] >> 4) != 6) return RS_E_IP_HEADER;
  uint32_t plen = be16(p + 4);
  if (n < 40 + plen) return RS_E_TRUNCATED;
  n = 40 + plen;
  uint8_t next = p[6];
  uint32_t off = 40;
  out->ip_version = 6;
  memcpy(out->src_addr, p + 8, 16);
  memcpy(out->dst_addr, p + 24, 16);
  for (int i = 0; i < MAX_IPV6_EXT; i++) {
    if (next == 17) return parse_udp(p + off, n - off, out);
    if (next == 44) return RS_E_FRAGMENT;
    if (next != 0 && next != 43 && next != 60) return RS_E_NOT_UDP;
    if (n < off + 8) return RS_E_TRUNCATED;
    uint32_t hl = ((uint32_t)p[off + 1] + 1) * 8;
    next = p[off];
    off += hl;
    if (off > n) return RS_E_TRUNCATED;
  }
  return RS_E_IP_HEADER;
}

static int parse_ip(const uint8_t *p, uint32_t n, rs_udp_t *out) {
  if (n < 1) return RS_E_TRUNCATED;
  switch (p[0] >> 4) {
  case 4: return parse_ipv4(p, n, out);
  case 6: return parse_ipv6(p, n, out);
  default: return RS_E_NOT_IP;
  }
}

static int by_ethertype(uint16_t type, const uint8_t *p, uint32_t n, rs_udp_t *out) {
  if (type == ETH_IPV4) return parse_ipv4(p, n, out);
  if (type == ETH_IPV6) return parse_ipv6(p, n, out);
  return RS_E_NOT_IP;
}

int rs_net_parse(int lt, const uint8_t *f, uint32_t n, rs_udp_t *out) {
  memset(out, 0, sizeof *out);
  switch (lt) {
  case RS_LINK_ETHERNET: {
    if (n < 14) return RS_E_TRUNCATED;
    uint32_t off = 12;
    uint16_t type = be16(f + off);
    for (int i = 0; i < MAX_VLAN_TAGS && (type == ETH_VLAN || type == ETH_QINQ || type == ETH_QINQ_OLD); i++) {
      if (n < off + 6) return RS_E_TRUNCATED;
      if (out->vlan == 0) out->vlan = be16(f + off + 2) & 0x0FFF;
      off += 4;
      type = be16(f + off);
    }
    off += 2;
    return by_ethertype(type, f + off, n - off, out);
  }
  case RS_LINK_SLL:
    if (n < 16) return RS_E_TRUNCATED;
    return by_ethertype(be16(f + 14), f + 16, n - 16, out);
  case RS_LINK_SLL2:
    if (n < 20) return RS_E_TRUNCATED;
    return by_ethertype(be16(f), f + 20, n - 20, out);
  case RS_LINK_RAW_DLT: case RS_LINK_RAW_DLT14: case RS_LINK_RAW:
    return parse_ip(f, n, out);
  case RS_LINK_IPV4: return parse_ipv4(f, n, out);
  case RS_LINK_IPV6: return parse_ipv6(f, n, out);
  case RS_LINK_NULL: case RS_LINK_LOOP: {
    if (n < 4) return RS_E_TRUNCATED;
    /* address family, host byte order of the writer (NULL) or network (LOOP) */
    uint32_t af = lt == RS_LINK_LOOP ? be32(f) : le32(f);
    if (lt == RS_LINK_NULL && af > 0xFFFF) af = be32(f);
    if (af == 2) return parse_ipv4(f + 4, n - 4, out);
    if (af == 10 || af == 24 || af == 28 || af == 30) return parse_ipv6(f + 4, n - 4, out);
    return RS_E_NOT_IP;
  }
  default: return RS_E_LINKTYPE;
  }
}

static void put_be16(uint8_t *p, uint16_t v) {
  p[0] = (uint8_t)(v >> 8);
  p[1] = (uint8_t)(v & 0xFF);
}

static uint16_t ip_checksum(const uint8_t *h, size_t n) {
  uint32_t sum = 0;
  for (size_t i = 0; i + 1 < n; i += 2) sum += (uint32_t)((h[i] << 8) | h[i + 1]);
  while (sum >> 16) sum = (sum & 0xFFFF) + (sum >> 16);
  return (uint16_t)~sum;
}

size_t rs_net_build_udp4(int lt, uint16_t vlan, const uint8_t src_ip[4], const uint8_t dst_ip[4],
                         uint16_t src_port, uint16_t dst_port, const uint8_t *payload, size_t len,
                         uint8_t *f, size_t cap) {
  size_t l2 = 0;
  switch (lt) {
  case RS_LINK_ETHERNET: l2 = vlan ? 18 : 14; break;
  case RS_LINK_SLL: l2 = 16; break;
  case RS_LINK_SLL2: l2 = 20; break;
  case RS_LINK_RAW: case RS_LINK_RAW_DLT: case RS_LINK_IPV4: l2 = 0; break;
  case RS_LINK_NULL: l2 = 4; break;
  default: return 0;
  }
  size_t total = l2 + 20 + 8 + len;
  if (total > cap || 28 + len > 0xFFFF) return 0;
  memset(f, 0, l2 + 28);
  uint8_t *ip = f + l2;
  switch (lt) {
  case RS_LINK_ETHERNET:
    memset(f, 0xFF, 6); /* broadcast, as Velodyne sensors send */
    f[6] = 0x60; f[7] = 0x76; f[8] = 0x88; f[9] = 0x00; f[10] = 0x00; f[11] = 0x01;
    if (vlan) {
      put_be16(f + 12, ETH_VLAN);
      put_be16(f + 14, vlan & 0x0FFF);
      put_be16(f + 16, ETH_IPV4);
    } else {
      put_be16(f + 12, ETH_IPV4);
    }
    break;
  case RS_LINK_SLL:
    put_be16(f, 1);     /* broadcast */
    put_be16(f + 2, 1); /* ARPHRD_ETHER */
    put_be16(f + 4, 6);
    put_be16(f + 14, ETH_IPV4);
    break;
  case RS_LINK_SLL2:
    put_be16(f, ETH_IPV4); /* protocol */
    f[7] = 1;              /* interface index */
    put_be16(f + 8, 1);    /* ARPHRD_ETHER */
    f[10] = 1;             /* broadcast */
    f[11] = 6;             /* address length */
    break;
  case RS_LINK_NULL: f[0] = 2; break; /* AF_INET, little-endian writer */
  default: break;
  }
  ip[0] = 0x45;
  put_be16(ip + 2, (uint16_t)(28 + len));
  put_be16(ip + 6, 0x4000); /* don't fragment */
  ip[8] = 64;
  ip[9] = 17;
  memcpy(ip + 12, src_ip, 4);
  memcpy(ip + 16, dst_ip, 4);
  put_be16(ip + 10, ip_checksum(ip, 20));
  uint8_t *udp = ip + 20;
  put_be16(udp, src_port);
  put_be16(udp + 2, dst_port);
  put_be16(udp + 4, (uint16_t)(8 + len));
  memcpy(udp + 8, payload, len);
  return total;
}

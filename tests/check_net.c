/* check_net - link-layer, IP and UDP parsing of every supported link type,
 * and rejection of what is not a complete UDP datagram. */
#include "roadscan/util/error.h"
#include "roadscan/capture/net.h"
#include "testutil.h"

#include <string.h>

static const uint8_t src[4] = {192, 168, 1, 201}, dst[4] = {255, 255, 255, 255};
static uint8_t payload[1206], frame[2048];

START_TEST(t_all_link_types) {
  static const int types[] = {RS_LINK_ETHERNET, RS_LINK_SLL, RS_LINK_SLL2, RS_LINK_RAW, RS_LINK_RAW_DLT,
                              RS_LINK_IPV4, RS_LINK_NULL};
  for (size_t i = 0; i < sizeof types / sizeof types[0]; i++) {
    for (int k = 0; k < 1206; k++) payload[k] = (uint8_t)(k * 13 + (int)i);
    size_t n = rs_net_build_udp4(types[i], 0, src, dst, 2368, 2368, payload, sizeof payload, frame, sizeof frame);
    ck_assert_uint_gt(n, 1206);
    rs_udp_t u;
    ck_assert_int_eq(rs_net_parse(types[i], frame, (uint32_t)n, &u), RS_OK);
    ck_assert_int_eq(u.len, 1206);
    ck_assert_int_eq(u.dst_port, 2368);
    ck_assert_int_eq(u.ip_version, 4);
    ck_assert_mem_eq(u.src_addr, src, 4);
    ck_assert_mem_eq(u.payload, payload, 1206);
    ck_assert(rs_net_linktype_supported(types[i]));
  }
}
END_TEST

START_TEST(t_vlan_and_padding) {
  size_t n = rs_net_build_udp4(RS_LINK_ETHERNET, 42, src, dst, 5000, 2369, payload, 512, frame, sizeof frame);
  rs_udp_t u;
  ck_assert_int_eq(rs_net_parse(RS_LINK_ETHERNET, frame, (uint32_t)n, &u), RS_OK);
  ck_assert_int_eq(u.vlan, 42);
  ck_assert_int_eq(u.src_port, 5000);
  ck_assert_int_eq(u.dst_port, 2369);
  ck_assert_int_eq(u.len, 512);
  /* Ethernet trailer padding after the IP datagram is ignored */
  memset(frame + n, 0xAB, 8);
  ck_assert_int_eq(rs_net_parse(RS_LINK_ETHERNET, frame, (uint32_t)n + 8, &u), RS_OK);
  ck_assert_int_eq(u.len, 512);
}
END_TEST

START_TEST(t_ipv6) {
  uint8_t f[14 + 40 + 8 + 16];
  memset(f, 0, sizeof f);
  f[12] = 0x86;
  f[13] = 0xDD;
  uint8_t *ip = f + 14;
  ip[0] = 0x60;
  ip[4] = 0;
  ip[5] = 24; /* payload length */
  ip[6] = 17;
  ip[7] = 64;
  ip[8] = 0xfe;
  ip[9] = 0x80;
  ip[23] = 1;
  uint8_t *udp = ip + 40;
  udp[0] = 0x09; udp[1] = 0x40; /* 2368 */
  udp[2] = 0x09; udp[3] = 0x40;
  udp[5] = 24;
  rs_udp_t u;
  ck_assert_int_eq(rs_net_parse(RS_LINK_ETHERNET, f, sizeof f, &u), RS_OK);
  ck_assert_int_eq(u.ip_version, 6);
  ck_assert_int_eq(u.len, 16);
  ck_assert_int_eq(u.src_addr[0], 0xfe);
  ck_assert_int_eq(rs_net_parse(RS_LINK_IPV6, ip, 40 + 24, &u), RS_OK);
  ip[6] = 44; /* fragment header */
  ck_assert_int_eq(rs_net_parse(RS_LINK_ETHERNET, f, sizeof f, &u), RS_E_FRAGMENT);
}
END_TEST

START_TEST(t_rejects) {
  size_t n = rs_net_build_udp4(RS_LINK_ETHERNET, 0, src, dst, 2368, 2368, payload, 1206, frame, sizeof frame);
  rs_udp_t u;
  /* snapshot length cut the payload */
  ck_assert_int_eq(rs_net_parse(RS_LINK_ETHERNET, frame, 600, &u), RS_E_TRUNCATED);
  ck_assert_int_eq(rs_net_parse(RS_LINK_ETHERNET, frame, 10, &u), RS_E_TRUNCATED);
  /* ARP */
  uint8_t arp[60] = {0};
  arp[12] = 0x08;
  arp[13] = 0x06;
  ck_assert_int_eq(rs_net_parse(RS_LINK_ETHERNET, arp, sizeof arp, &u), RS_E_NOT_IP);
  /* TCP */
  frame[14 + 9] = 6;
  ck_assert_int_eq(rs_net_parse(RS_LINK_ETHERNET, frame, (uint32_t)n, &u), RS_E_NOT_UDP);
  frame[14 + 9] = 17;
  /* more-fragments flag */
  frame[14 + 6] = 0x20;
  ck_assert_int_eq(rs_net_parse(RS_LINK_ETHERNET, frame, (uint32_t)n, &u), RS_E_FRAGMENT);
  frame[14 + 6] = 0x40;
  /* bad IHL */
  frame[14] = 0x43;
  ck_assert_int_eq(rs_net_parse(RS_LINK_ETHERNET, frame, (uint32_t)n, &u), RS_E_IP_HEADER);
  frame[14] = 0x45;
  /* UDP length beyond the IP datagram */
  frame[14 + 20 + 4] = 0x10;
  ck_assert_int_eq(rs_net_parse(RS_LINK_ETHERNET, frame, (uint32_t)n, &u), RS_E_UDP_LENGTH);
  frame[14 + 20 + 4] = 0x00;
  frame[14 + 20 + 5] = 4; /* shorter than the UDP header itself */
  ck_assert_int_eq(rs_net_parse(RS_LINK_ETHERNET, frame, (uint32_t)n, &u), RS_E_UDP_LENGTH);
  /* unsupported link type (802.11) */
  ck_assert_int_eq(rs_net_parse(105, frame, (uint32_t)n, &u), RS_E_LINKTYPE);
  ck_assert(!rs_net_linktype_supported(105));
  /* builder refuses a too-small buffer */
  ck_assert_uint_eq(rs_net_build_udp4(RS_LINK_ETHERNET, 0, src, dst, 1, 2, payload, 1206, frame, 100), 0);
}
END_TEST

int main(void) {
  Suite *s = suite_create("net");
  TCase *tc = tcase_create("core");
  tcase_add_test(tc, t_all_link_types);
  tcase_add_test(tc, t_vlan_and_padding);
  tcase_add_test(tc, t_ipv6);
  tcase_add_test(tc, t_rejects);
  suite_add_tcase(s, tc);
  return tu_run(s);
}

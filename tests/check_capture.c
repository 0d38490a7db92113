/* check_capture - libpcap sources: every link type, pcapng, truncated and
 * unreadable files, replay pacing and looping, live capture on loopback. */
#include "roadscan/capture/capture.h"
#include "roadscan/util/error.h"
#include "roadscan/capture/net.h"
#include "roadscan/capture/stream.h"
#include "roadscan/sim/synth.h"
#include "roadscan/util/timing.h"
#include "testutil.h"

#include <arpa/inet.h>
#include <pcap/pcap.h>
#include <stdio.h>
#include <string.h>
#include <sys/socket.h>
#include <time.h>
#include <unistd.h>

static rs_stream_t st;

/* Reads a whole file through capture + stream; returns decoded packets. */
static int read_all(const char *path, rs_capture_cfg_t *cc, int *status) {
  rs_capture_t c;
  ck_assert_int_eq(rs_capture_open_file(&c, path, cc), RS_OK);
  rs_stream_cfg_t sc = {0};
  ck_assert_int_eq(rs_stream_init(&st, &sc), RS_OK);
  rs_frame_in_t f;
  int rc;
  while ((rc = rs_capture_next(&c, &f, NULL)) == 1) rs_stream_frame(&st, c.linktype, &f, NULL, NULL);
  rs_stream_finish(&st, NULL, NULL);
  rs_capture_close(&c);
  if (status) *status = rc;
  return (int)st.n.decoded;
}

START_TEST(t_link_types) {
  static const struct { int lt; uint16_t vlan; } cases[] = {{RS_LINK_ETHERNET, 0}, {RS_LINK_ETHERNET, 7},
                                                           {RS_LINK_SLL, 0},      {RS_LINK_SLL2, 0},
                                                           {RS_LINK_RAW, 0},      {RS_LINK_NULL, 0}};
  for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
    rs_synth_cfg_t cfg = {.model = RS_MODEL_VLP16, .mode = RS_MODE_STRONGEST, .hz = 10, .seconds = 0.2,
                          .linktype = cases[i].lt, .vlan = cases[i].vlan, .position_every = 10, .t0 = 100};
    const char *p = tu_tmp("lt.pcap");
    long written = rs_synth_write(&cfg, p);
    ck_assert_int_gt(written, 100);
    rs_capture_cfg_t cc = {.data_port = 2368};
    int status;
    ck_assert_int_eq(read_all(p, &cc, &status), written);
    ck_assert_int_eq(status, RS_CAPTURE_EOF);
    ck_assert_uint_eq(st.n.position_packets, (written + 9) / 10);
    ck_assert_uint_eq(rs_stream_error_total(&st.n), 0);
  }
}
END_TEST

static void put32(FILE *f, uint32_t v) { fwrite(&v, 4, 1, f); } /* pcapng in host (little-endian) order */
static void put16(FILE *f, uint16_t v) { fwrite(&v, 2, 1, f); }

START_TEST(t_pcapng) {
  const char *p = tu_tmp("x.pcapng");
  FILE *f = fopen(p, "wb");
  /* section header block */
  put32(f, 0x0A0D0D0A); put32(f, 28); put32(f, 0x1A2B3C4D); put16(f, 1); put16(f, 0);
  put32(f, 0xFFFFFFFF); put32(f, 0xFFFFFFFF); put32(f, 28);
  /* interface description block: Ethernet, snaplen 65535 */
  put32(f, 1); put32(f, 20); put16(f, 1); put16(f, 0); put32(f, 65535); put32(f, 20);
  rs_synth_cfg_t cfg = {.model = RS_MODEL_VLP32C, .mode = RS_MODE_STRONGEST, .hz = 10, .seconds = 0.05};
  rs_sensor_t s;
  rs_sensor_init(&s, RS_MODEL_VLP32C);
  uint32_t n = rs_synth_count(&cfg);
  static rs_encode_t enc;
  static uint8_t payload[1206], frame[1400];
  const uint8_t src[4] = {10, 0, 0, 2}, dst[4] = {10, 0, 0, 255};
  for (uint32_t k = 0; k < n; k++) {
    rs_synth_packet(&cfg, &s, k, &enc);
    rs_packet_encode(s.info, &enc, payload);
    size_t len = rs_net_build_udp4(RS_LINK_ETHERNET, 0, src, dst, 40000, 2368, payload, 1206, frame, sizeof frame);
    uint32_t padded = (uint32_t)((len + 3) & ~(size_t)3);
    uint32_t blen = 28 + padded + 4;
    uint64_t ts = 1600000000000000ull + k * 664ull; /* microseconds */
    put32(f, 6); put32(f, blen); put32(f, 0); put32(f, (uint32_t)(ts >> 32)); put32(f, (uint32_t)ts);
    put32(f, (uint32_t)len); put32(f, (uint32_t)len);
    fwrite(frame, 1, len, f);
    for (size_t z = len; z < padded; z++) fputc(0, f);
    put32(f, blen);
  }
  fclose(f);
  rs_capture_cfg_t cc = {.data_port = 2368};
  ck_assert_int_eq(read_all(p, &cc, NULL), (int)n);
  ck_assert_int_eq(st.sensor.info->model, RS_MODEL_VLP32C);
}
END_TEST

START_TEST(t_truncated_and_bad_files) {
  rs_synth_cfg_t cfg = {.model = RS_MODEL_VLP16, .mode = RS_MODE_STRONGEST, .hz = 10, .seconds = 0.1};
  const char *p = tu_tmp("trunc.pcap");
  long written = rs_synth_write(&cfg, p);
  FILE *f = fopen(p, "r+b");
  fseek(f, 0, SEEK_END);
  long size = ftell(f);
  fclose(f);
  ck_assert_int_eq(truncate(p, size - 500), 0);
  rs_capture_cfg_t cc = {.data_port = 2368};
  int status;
  ck_assert_int_eq(read_all(p, &cc, &status), written - 1);
  ck_assert_int_eq(status, RS_E_TRUNCATED);

  rs_capture_t c;
  ck_assert_int_eq(rs_capture_open_file(&c, tu_tmp("nope.pcap"), &cc), RS_E_NOENT);
  ck_assert_ptr_nonnull(strstr(c.err, "nope.pcap"));
  const char *g = tu_tmp("garbage.pcap");
  f = fopen(g, "wb");
  fputs("this is not a capture file at all, just text\n", f);
  fclose(f);
  ck_assert_int_eq(rs_capture_open_file(&c, g, &cc), RS_E_FORMAT);
  ck_assert_ptr_nonnull(strstr(c.err, "not a readable pcap"));
  /* a radiotap (802.11) capture */
  const char *w = tu_tmp("wifi.pcap");
  pcap_t *dead = pcap_open_dead(127, 65535);
  pcap_dumper_t *d = pcap_dump_open(dead, w);
  pcap_dump_close(d);
  pcap_close(dead);
  ck_assert_int_eq(rs_capture_open_file(&c, w, &cc), RS_E_LINKTYPE);
  ck_assert_ptr_nonnull(strstr(c.err, "unsupported link-layer type 127"));
}
END_TEST

START_TEST(t_pacing_and_loop) {
  rs_synth_cfg_t cfg = {.model = RS_MODEL_HDL32E, .mode = RS_MODE_STRONGEST, .hz = 10, .seconds = 0.4, .t0 = 50};
  const char *p = tu_tmp("pace.pcap");
  long written = rs_synth_write(&cfg, p);
  /* at 4x the 0.4 s capture cannot take less than 0.1 s (a lower bound only) */
  rs_capture_cfg_t cc = {.data_port = 2368, .speed = 4.0};
  rs_capture_t c;
  ck_assert_int_eq(rs_capture_open_file(&c, p, &cc), RS_OK);
  rs_frame_in_t f;
  int64_t t0 = rs_now_ns();
  long n = 0;
  double first = -1, last = 0;
  while (rs_capture_next(&c, &f, NULL) == 1) {
    if (first < 0) first = f.ts;
    last = f.ts;
    n++;
  }
  double el = (double)(rs_now_ns() - t0) * 1e-9;
  rs_capture_close(&c);
  ck_assert_int_eq(n, written);
  ck_assert_double_ge(el, (last - first) / 4.0 * 0.99);
  /* loop: capture times keep increasing across passes */
  rs_capture_cfg_t lc = {.data_port = 2368, .speed = 0.0, .loop = true};
  ck_assert_int_eq(rs_capture_open_file(&c, p, &lc), RS_OK);
  double prev = -1;
  for (long i = 0; i < written * 5 / 2; i++) {
    ck_assert_int_eq(rs_capture_next(&c, &f, NULL), 1);
    ck_assert_double_gt(f.ts, prev);
    prev = f.ts;
  }
  ck_assert_uint_eq(c.loops, 2);
  _Atomic bool stop = true;
  int rc;
  while ((rc = rs_capture_next(&c, &f, &stop)) == 1) {
  }
  ck_assert_int_eq(rc, RS_CAPTURE_EOF); /* a stop ends the loop at the end of the file */
  rs_capture_close(&c);
}
END_TEST

START_TEST(t_live_loopback) {
  rs_capture_t c;
  rs_capture_cfg_t cc = {.data_port = (uint16_t)(23000 + getpid() % 1000)};
  ck_assert_int_eq(rs_capture_open_live(&c, "roadscan-no-such0", &cc), RS_E_NODEV);
  int rc = rs_capture_open_live(&c, "lo", &cc);
  if (rc == RS_E_PERM) {
    fprintf(stderr, "check_capture: live capture needs CAP_NET_RAW here; loopback case skipped (%s)\n", c.err);
    return;
  }
  ck_assert_msg(rc == RS_OK, "open lo: %s", c.err);
  int sock = socket(AF_INET, SOCK_DGRAM, 0);
  struct sockaddr_in to = {.sin_family = AF_INET, .sin_port = htons(cc.data_port)};
  to.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  rs_synth_cfg_t cfg = {.model = RS_MODEL_VLP16, .mode = RS_MODE_STRONGEST, .hz = 10, .seconds = 0.02};
  rs_sensor_t s;
  rs_sensor_init(&s, RS_MODEL_VLP16);
  static rs_encode_t enc;
  static uint8_t payload[1206];
  const int N = 10;
  for (int k = 0; k < N; k++) {
    rs_synth_packet(&cfg, &s, (uint32_t)k, &enc);
    rs_packet_encode(s.info, &enc, payload);
    ck_assert_int_eq(sendto(sock, payload, sizeof payload, 0, (struct sockaddr *)&to, sizeof to), 1206);
  }
  /* another port: the BPF filter keeps it out */
  struct sockaddr_in other = to;
  other.sin_port = htons((uint16_t)(cc.data_port + 1));
  sendto(sock, payload, sizeof payload, 0, (struct sockaddr *)&other, sizeof other);
  /* position packets (port 8308): the filter lets them in, the stream counts them */
  struct sockaddr_in pos = to;
  pos.sin_port = htons(RS_DEFAULT_POSITION_PORT);
  static uint8_t gprmc[512];
  for (int k = 0; k < 2; k++) ck_assert_int_eq(sendto(sock, gprmc, sizeof gprmc, 0, (struct sockaddr *)&pos, sizeof pos), 512);
  close(sock);
  rs_stream_cfg_t sc = {.data_port = cc.data_port, .position_port = RS_DEFAULT_POSITION_PORT};
  rs_stream_init(&st, &sc);
  rs_frame_in_t f;
  for (int tries = 0; tries < 30 && (st.n.decoded < (uint64_t)N || st.n.position_packets < 2); tries++) {
    rc = rs_capture_next(&c, &f, NULL);
    ck_assert_int_ge(rc, 0);
    if (rc == 1) rs_stream_frame(&st, c.linktype, &f, NULL, NULL);
  }
  ck_assert_uint_eq(st.n.decoded, (uint64_t)N);
  ck_assert_uint_eq(st.n.position_packets, 2);
  ck_assert_uint_eq(st.n.other_packets, 0);
  char filter[160];
  rs_capture_filter(&cc, filter, sizeof filter);
  ck_assert_ptr_nonnull(strstr(filter, "dst port 8308"));
  /* nothing more arrives: next returns 0 within the poll interval, not blocking */
  ck_assert_int_eq(rs_capture_next(&c, &f, NULL), 0);
  rs_capture_close(&c);
}
END_TEST

/* live capture time has the kernel's sub-second resolution: two datagrams sent 200 ms apart are
 * 200 ms apart or more (microseconds read as nanoseconds put them under a millisecond apart) */
START_TEST(t_live_timestamps) {
  rs_capture_t c;
  rs_capture_cfg_t cc = {.data_port = (uint16_t)(27000 + getpid() % 1000)};
  int rc = rs_capture_open_live(&c, "lo", &cc);
  if (rc == RS_E_PERM) {
    fprintf(stderr, "check_capture: live capture needs CAP_NET_RAW here; timestamps case skipped\n");
    return;
  }
  ck_assert_msg(rc == RS_OK, "open lo: %s", c.err);
  int sock = socket(AF_INET, SOCK_DGRAM, 0);
  struct sockaddr_in to = {.sin_family = AF_INET, .sin_port = htons(cc.data_port)};
  to.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  static uint8_t payload[1206];
  struct timespec wall;
  clock_gettime(CLOCK_REALTIME, &wall);
  const double sent0 = (double)wall.tv_sec + (double)wall.tv_nsec * 1e-9;
  ck_assert_int_eq(sendto(sock, payload, sizeof payload, 0, (struct sockaddr *)&to, sizeof to), 1206);
  struct timespec gap = {0, 200000000L};
  nanosleep(&gap, NULL);
  ck_assert_int_eq(sendto(sock, payload, sizeof payload, 0, (struct sockaddr *)&to, sizeof to), 1206);
  close(sock);
  double ts[2];
  int got = 0;
  rs_frame_in_t f;
  for (int tries = 0; tries < 100 && got < 2; tries++) {
    rc = rs_capture_next(&c, &f, NULL);
    ck_assert_int_ge(rc, 0);
    if (rc == 1) ts[got++] = f.ts;
  }
  ck_assert_int_eq(got, 2);
  ck_assert_msg(ts[1] - ts[0] >= 0.19, "captured %.6f s apart, sent 0.2 s apart", ts[1] - ts[0]);
  ck_assert_msg(ts[0] >= sent0 - 0.01 && ts[0] < sent0 + 60, "captured at %.6f, sent at %.6f", ts[0], sent0);
  rs_capture_close(&c);
}
END_TEST

int main(void) {
  Suite *s = suite_create("capture");
  TCase *tc = tcase_create("core");
  tcase_set_timeout(tc, 120);
  tcase_add_test(tc, t_link_types);
  tcase_add_test(tc, t_pcapng);
  tcase_add_test(tc, t_truncated_and_bad_files);
  tcase_add_test(tc, t_pacing_and_loop);
  tcase_add_test(tc, t_live_loopback);
  tcase_add_test(tc, t_live_timestamps);
  suite_add_tcase(s, tc);
  return tu_run(s);
}

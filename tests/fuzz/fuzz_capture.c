/* fuzz_capture - a whole capture file (pcap or pcapng, any link type)
 * through libpcap, the project's reader and link/IP/UDP parser, and the
 * stream. */
#include "fuzz.h"

#include "roadscan/capture/stream.h"

static rs_stream_t st;

static void on_packet(void *user, const rs_packet_t *pkt, uint32_t index, double ts) {
  (void)user;
  (void)pkt;
  (void)index;
  (void)ts;
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size) {
  const char *path = fuzz_file(data, size, ".pcap");
  if (path == NULL) return 0;
  rs_stream_cfg_t cfg = {.data_port = 2368, .position_port = 8308, .default_hz = 10.0};
  rs_stream_init(&st, &cfg);
  char err[256];
  rs_stream_replay_file(&st, path, on_packet, NULL, NULL, err, sizeof err);
  unlink(path);
  return 0;
}

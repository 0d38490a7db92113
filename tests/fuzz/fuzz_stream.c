/* fuzz_stream - UDP payloads through the stream (classification, model
 * detection, decoding) and the frame assembler (roll-over, loss, reorder,
 * duplicates, late packets), as the packet thread takes them.
 * Input: records of [u16 length][u16 port][u32 time offset in µs] + payload. */
#include "fuzz.h"

#include "roadscan/frame/frame.h"
#include "roadscan/capture/stream.h"

#include <string.h>

static rs_stream_t st;
static rs_asm_t as;
static bool as_ready;
static rs_slot_t slots[2];
static int cur;

static void on_packet(void *user, const rs_packet_t *pkt, uint32_t index, double ts) {
  (void)user;
  if (!as_ready) {
    rs_asm_cfg_t cfg = {.default_hz = 10.0};
    if (rs_asm_init(&as, &cfg, &st.sensor) != 0) return;
    as_ready = true;
  }
  for (int i = 0; i <= RS_BLOCKS; i++) {
    if (rs_asm_feed(&as, &slots[cur], pkt, index, ts) == RS_ASM_CONSUMED) break;
    cur ^= 1;
  }
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size) {
  rs_stream_cfg_t cfg = {.data_port = 2368, .position_port = 8308, .default_hz = 10.0};
  rs_stream_init(&st, &cfg);
  as_ready = false;
  cur = 0;
  size_t at = 0;
  double t = 1000.0;
  for (int rec = 0; rec < 20000 && at + 8 <= size; rec++) {
    const size_t len = (size_t)data[at] << 8 | data[at + 1];
    const uint16_t port = (uint16_t)(data[at + 2] << 8 | data[at + 3]);
    const uint32_t dt = (uint32_t)data[at + 4] << 24 | (uint32_t)data[at + 5] << 16 | (uint32_t)data[at + 6] << 8 | data[at + 7];
    at += 8;
    const size_t n = len < size - at ? len : size - at;
    t += dt * 1e-6;
    rs_stream_payload(&st, data + at, (uint32_t)n, port, t, on_packet, NULL);
    at += n;
  }
  rs_stream_finish(&st, on_packet, NULL);
  if (as_ready) rs_asm_flush(&as, &slots[cur]);
  return 0;
}

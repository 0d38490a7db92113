/* error.h - one table of negative error codes for the whole project.
 *
 * Every expected runtime failure is a negative code from RS_ERRNO_MAP, with a
 * stable short name (used as a counter key in summaries) and a message.
 * Counters indexed by code live with whoever meets the error (packet thread,
 * processing thread); this header only names them. */
#ifndef ROADSCAN_ERROR_H
#define ROADSCAN_ERROR_H

/* X(name, short key, message) */
#define RS_ERRNO_MAP(X)                                                              \
  X(INVAL, "invalid-argument", "invalid argument")                                  \
  X(NOMEM, "capacity", "compile-time capacity exceeded")                            \
  X(OOM, "out-of-memory", "out of memory")                                          \
  X(IO, "io", "input/output error")                                                 \
  X(NOENT, "no-such-file", "no such file")                                          \
  X(FORMAT, "bad-format", "malformed file")                                         \
  X(LINKTYPE, "link-type", "unsupported link-layer type")                           \
  X(TRUNCATED, "truncated", "packet truncated by the capture (caplen too short)")  \
  X(NOT_IP, "not-ip", "not an IP packet")                                           \
  X(NOT_UDP, "not-udp", "not a UDP datagram")                                       \
  X(FRAGMENT, "ip-fragment", "fragmented IP datagram")                              \
  X(IP_HEADER, "ip-header", "malformed IP header")                                  \
  X(UDP_LENGTH, "udp-length", "UDP length field disagrees with the packet")         \
  X(PKT_SHORT, "payload-short", "data payload shorter than 1206 bytes")             \
  X(PKT_LONG, "payload-long", "data payload longer than 1206 bytes")                \
  X(BLOCK_FLAG, "block-flag", "bad data block flag (not a Velodyne data packet)")   \
  X(AZIMUTH, "azimuth-range", "block azimuth out of range (> 36000)")              \
  X(RETURN_MODE, "return-mode", "unknown return mode byte")                         \
  X(PRODUCT, "unknown-product", "unknown product (model) byte")                     \
  X(PRODUCT_MISMATCH, "product-mismatch", "product byte differs from the stream's sensor") \
  X(SENSOR_CHANGED, "sensor-changed", "the sensor changed mid-stream")             \
  X(DUPLICATE, "duplicate-packet", "duplicate packet")                              \
  X(OUT_OF_ORDER, "out-of-order", "packet out of order")                            \
  X(CALIB, "calibration", "bad calibration file")                                   \
  X(PERM, "permission", "permission denied")                                        \
  X(NODEV, "no-device", "no such capture interface")                                \
  X(CAPTURE, "capture", "capture error")                                            \
  X(THREAD, "thread", "thread error")                                              \
  X(LCM, "lcm", "LCM error")                                                        \
  X(NOROUTE, "no-route", "no route to the LCM multicast group")

typedef enum {
  RS_OK = 0,
#define RS_ERR_ENUM(name, key, msg) RS_E_##name,
  RS_ERR_FIRST_ = -1000,
  RS_ERRNO_MAP(RS_ERR_ENUM)
#undef RS_ERR_ENUM
  RS_ERR_END_
} rs_err_t;

/* Number of distinct error codes; index of a code is rs_err_index(code). */
#define RS_ERR_COUNT (RS_ERR_END_ - RS_ERR_FIRST_ - 1)

/* Size of every error-message buffer in the project (an unknown tracking parameter's message lists
 * every name: over 1500 characters). */
#define RS_ERRMSG_SIZE 2048

const char *rs_strerror(int code);
/* Short stable key ("block-flag"), for counters and logs. */
const char *rs_err_key(int code);
/* 0 .. RS_ERR_COUNT-1 for a valid code, -1 otherwise. */
int rs_err_index(int code);
/* The code for an index. */
int rs_err_from_index(int index);

#endif

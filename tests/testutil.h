/* testutil.h - helpers shared by the Check suites: hand-built packet bytes
 * (written independently of the library's encoder), temporary paths, and
 * running a program of build/bin. */
#ifndef ROADSCAN_TESTUTIL_H
#define ROADSCAN_TESTUTIL_H

#include <check.h>
#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

/* Runs the suite (fork mode, CK_ENV verbosity); exit status for main(). */
int tu_run(Suite *s);

/* Packet bytes, little-endian, by hand. */
void tu_block(uint8_t *pkt, int block, uint8_t flag2, uint16_t azimuth);
void tu_record(uint8_t *pkt, int block, int rec, uint16_t distance, uint8_t intensity);
void tu_tail(uint8_t *pkt, uint32_t timestamp_us, uint8_t mode, uint8_t product);
/* A packet with all 12 blocks flagged 0xFFEE at az0 + step*b, no returns. */
void tu_empty_packet(uint8_t *pkt, uint16_t az0, uint16_t step, uint8_t mode, uint8_t product);

/* RS_TMP_DIR/<name>; the returned buffer is one of 8 rotating ones. */
const char *tu_tmp(const char *name);
/* Shared real captures directory when present (NULL otherwise). */
const char *tu_shared_data(void);

/* Runs build/bin/<prog> with a shell command line; captures stderr+stdout
 * into *out (static buffer). Returns the exit status (or -1). */
int tu_exec(const char *cmdline, const char **out);

/* Starts build/bin/<cmdline> in the background (sh -c, in RS_BIN_DIR), its
 * stdout and stderr to out_path; returns its pid. */
int tu_spawn(const char *cmdline, const char *out_path);
/* Waits until the file at path holds needle (true), or timeout_s passes
 * (false): a condition, never a measured time. */
bool tu_wait_for(const char *path, const char *needle, double timeout_s);
/* Sends sig to pid (0: none) and waits up to timeout_s for it to end (then
 * SIGKILL). Returns its exit status, or 128 + the signal that ended it. */
int tu_stop(int pid, int sig, double timeout_s);
/* Sends the UDP payloads of a capture to 127.0.0.1: every one to its captured
 * destination port, or (port > 0) only the data packets, to port; paced at the capture's timing times speed (0: flat
 * out). Returns the number of datagrams sent. */
long tu_send_capture(const char *path, uint16_t port, double speed);
/* After what a live test sent to a daemon on lo (data port `port`, frames CSV
 * `csv`): 0.5 s more of a VLP-16 at its rate (a capture that starts 10 s of
 * sensor time after the last one this made), then a wait until a frame that
 * began with one of those packets is in the CSV. The kernel hands packets over
 * in order, so every packet sent before was read by then. Returns the
 * datagrams of the 0.5 s. */
long tu_settle_live(uint16_t port, const char *csv);
/* A file's contents (static buffer, 1 MiB at most; "" when unreadable). */
const char *tu_slurp_text(const char *path);

/* The ground line of a summary (roadscand's, roadscan-learn's; ground.h): false when it has none (it
 * found no ground); else the sensor's height above it (m), its lean (deg), towards which azimuth (deg), and
 * the share of the near cells on the plane (%). */
bool tu_ground_line(const char *out, double *height, double *lean, double *toward, double *on_plane);

/* Counts lines of a text file (-1 if unreadable). */
long tu_count_lines(const char *path);

/* A simulated site (VLP-32C, light traffic): a 40 s capture (seed) to learn the
 * background from, and a test capture of test_s seconds (seed + 1) with its
 * truth labels and its true objects' centroids (roadscan-eval --objects). Files
 * RS_TMP_DIR/<name>.{learn.pcap,pcap,truth.csv,model,objects.csv}. */
typedef struct {
  char pcap[512], truth[512], model[512], objects[512];
} tu_site_t;
void tu_make_site(const char *name, int seed, double test_s, tu_site_t *site);

/* Objects' centroids against the site's true objects: tu_centroids_load reads
 * the objects file, tu_centroid_add scores one object of a frame (nearest true
 * centroid of that frame), tu_centroids_check prints the tally and asserts the
 * tolerance the tests state: 85 % within 0.5 m, 95 % within 1 m, none beyond 2 m. */
typedef struct {
  int n, within_05, within_1;
  float worst;
} tu_centroids_t;
void tu_centroids_load(const char *objects_csv);
void tu_centroid_add(tu_centroids_t *t, long frame, const float c[3]);
void tu_centroids_check(const tu_centroids_t *t, const char *what);

#endif

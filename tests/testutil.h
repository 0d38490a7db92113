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

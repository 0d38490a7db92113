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

#endif

/* fuzz.h - what every fuzz target shares: the libFuzzer entry point, and a
 * temporary file for the loaders that read a path. Built two ways: with
 * clang's libFuzzer (RS_FUZZ=ON, scripts/fuzz.sh) and, in every normal
 * build, with replay.c's main, which runs the committed corpus
 * (tests/fuzz/corpus/<target>/, seeds and every crasher found) as a test. */
#ifndef ROADSCAN_FUZZ_H
#define ROADSCAN_FUZZ_H

#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <unistd.h>

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

/* data written to a fresh temporary file; its path (static buffer) or NULL */
static inline const char *fuzz_file(const uint8_t *data, size_t size, const char *suffix) {
  static char path[128];
  snprintf(path, sizeof path, "/tmp/roadscan-fuzz-%d%s", (int)getpid(), suffix);
  FILE *f = fopen(path, "wb");
  if (f == NULL) return NULL;
  if (size && fwrite(data, 1, size, f) != size) {
    fclose(f);
    return NULL;
  }
  fclose(f);
  return path;
}

#endif

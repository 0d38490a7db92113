/* replay.c - runs a fuzz target over files and directories of inputs (the
 * committed corpus) without libFuzzer: the regression test of every input
 * that ever crashed, in the normal test run (and under the sanitizers). */
#include "fuzz.h"

#include <dirent.h>
#include <string.h>
#include <sys/stat.h>

static int run_file(const char *path) {
  FILE *f = fopen(path, "rb");
  if (f == NULL) {
    fprintf(stderr, "%s: cannot read\n", path);
    return 1;
  }
  static uint8_t buf[1 << 22];
  size_t n = fread(buf, 1, sizeof buf, f);
  fclose(f);
  uint8_t *copy = malloc(n ? n : 1); /* its own allocation: ASan sees reads past the end */
  if (copy == NULL) return 1;
  memcpy(copy, buf, n);
  LLVMFuzzerTestOneInput(copy, n);
  free(copy);
  return 0;
}

int main(int argc, char **argv) {
  int inputs = 0, bad = 0;
  for (int i = 1; i < argc; i++) {
    struct stat st;
    if (stat(argv[i], &st) != 0) {
      fprintf(stderr, "%s: missing\n", argv[i]);
      return 1;
    }
    if (!S_ISDIR(st.st_mode)) {
      bad += run_file(argv[i]);
      inputs++;
      continue;
    }
    DIR *d = opendir(argv[i]);
    if (d == NULL) return 1;
    /* sorted, for the same order everywhere */
    char *names[4096];
    int n = 0;
    for (struct dirent *e; (e = readdir(d)) != NULL && n < 4096;)
      if (e->d_name[0] != '.') names[n++] = strdup(e->d_name);
    closedir(d);
    for (int a = 1; a < n; a++)
      for (int b = a; b > 0 && strcmp(names[b - 1], names[b]) > 0; b--) {
        char *t = names[b];
        names[b] = names[b - 1];
        names[b - 1] = t;
      }
    for (int k = 0; k < n; k++) {
      char p[4096];
      snprintf(p, sizeof p, "%s/%s", argv[i], names[k]);
      bad += run_file(p);
      inputs++;
      free(names[k]);
    }
  }
  printf("%d inputs replayed\n", inputs);
  return bad || inputs == 0;
}

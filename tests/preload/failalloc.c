/* failalloc.c - LD_PRELOAD fault injection for the start-up allocation tests
 * (check_faults t_failing_allocations): malloc, calloc and realloc called by
 * the program itself (its own code and the roadscan libraries linked into it,
 * not libc, libpcap or LCM) fail on the Nth such call when
 * RS_FAILALLOC_NTH=N; RS_FAILALLOC_REPORT=FILE receives, at exit, how many
 * such calls were made. Not for sanitizer builds (they own malloc). */
#define _GNU_SOURCE
#include <errno.h>
#include <link.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>

extern void *__libc_malloc(size_t);
extern void *__libc_calloc(size_t, size_t);
extern void *__libc_realloc(void *, size_t);

static uintptr_t text_lo, text_hi; /* the main program's executable segment */
static long nth, calls;
static const char *report;

static int first_object(struct dl_phdr_info *info, size_t size, void *data) {
  (void)size;
  (void)data;
  for (int i = 0; i < info->dlpi_phnum; i++) {
    const ElfW(Phdr) *ph = &info->dlpi_phdr[i];
    if (ph->p_type == PT_LOAD && (ph->p_flags & PF_X)) {
      text_lo = info->dlpi_addr + ph->p_vaddr;
      text_hi = text_lo + ph->p_memsz;
    }
  }
  return 1; /* the first object is the program */
}

__attribute__((constructor)) static void failalloc_init(void) {
  const char *n = getenv("RS_FAILALLOC_NTH");
  nth = n ? strtol(n, NULL, 10) : 0;
  report = getenv("RS_FAILALLOC_REPORT");
  dl_iterate_phdr(first_object, NULL);
}

__attribute__((destructor)) static void failalloc_fini(void) {
  if (report == NULL) return;
  FILE *f = fopen(report, "w");
  if (f == NULL) return;
  fprintf(f, "%ld\n", calls);
  fclose(f);
}

/* true: this call, made by the program, is the one to fail */
static int fail_here(const void *caller) {
  const uintptr_t a = (uintptr_t)caller;
  if (a < text_lo || a >= text_hi) return 0;
  return ++calls == nth;
}

void *malloc(size_t n) {
  if (fail_here(__builtin_return_address(0))) {
    errno = ENOMEM;
    return NULL;
  }
  return __libc_malloc(n);
}

void *calloc(size_t k, size_t n) {
  if (fail_here(__builtin_return_address(0))) {
    errno = ENOMEM;
    return NULL;
  }
  return __libc_calloc(k, n);
}

void *realloc(void *p, size_t n) {
  if (fail_here(__builtin_return_address(0))) {
    errno = ENOMEM;
    return NULL;
  }
  return __libc_realloc(p, n);
}

/* labels.c - point-label file reader and writer. */
#include "roadscan/output/labels.h"

#include "roadscan/util/sort.h"

#include <errno.h>
#include <stdlib.h>
#include <string.h>

#define HEADER "packet,block,channel,label"

static int bad(rs_labels_reader_t *r, const char *what) {
  snprintf(r->err, sizeof r->err, "%s:%ld: %s", r->path, r->line, what);
  return RS_E_FORMAT;
}

int rs_labels_open(rs_labels_reader_t *r, const char *path, uint32_t max_packets) {
  memset(r, 0, sizeof *r);
  snprintf(r->path, sizeof r->path, "%s", path);
  r->max_packets = max_packets;
  r->f = fopen(path, "r");
  if (r->f == NULL) {
    snprintf(r->err, sizeof r->err, "%s: %s", path, strerror(errno));
    return errno == ENOENT ? RS_E_NOENT : RS_E_IO;
  }
  char buf[256];
  for (;;) {
    if (fgets(buf, sizeof buf, r->f) == NULL) {
      r->line++;
      int rc = bad(r, "missing header line \"" HEADER "\"");
      fclose(r->f);
      r->f = NULL;
      return rc;
    }
    r->line++;
    if (buf[0] == '#') continue;
    buf[strcspn(buf, "\r\n")] = '\0';
    if (strcmp(buf, HEADER) != 0) {
      int rc = bad(r, "expected the header \"" HEADER "\"");
      fclose(r->f);
      r->f = NULL;
      return rc;
    }
    return RS_OK;
  }
}

static bool field(const char **p, unsigned long *v) {
  char *end;
  if (**p < '0' || **p > '9') return false;
  errno = 0;
  *v = strtoul(*p, &end, 10);
  if (errno != 0) return false;
  *p = end;
  return true;
}

int rs_labels_next(rs_labels_reader_t *r, rs_label_t *out) {
  char buf[256];
  if (r->f == NULL) return 0;
  if (fgets(buf, sizeof buf, r->f) == NULL) return 0;
  r->line++;
  size_t n = strcspn(buf, "\r\n");
  if (buf[n] == '\0' && !feof(r->f)) return bad(r, "line too long");
  buf[n] = '\0';
  const char *p = buf;
  unsigned long v[4];
  for (int i = 0; i < 4; i++) {
    if (!field(&p, &v[i])) return bad(r, "expected four unsigned integers: packet,block,channel,label");
    if (i < 3) {
      if (*p != ',') return bad(r, "expected four comma-separated fields");
      p++;
    }
  }
  if (*p != '\0') return bad(r, "trailing characters after the label");
  if (v[1] > 11) return bad(r, "block out of range (0..11)");
  if (v[2] > 31) return bad(r, "channel out of range (0..31)");
  if (v[0] > UINT32_MAX || (r->max_packets != UINT32_MAX && v[0] >= r->max_packets))
    return bad(r, "packet index beyond the capture's data packets");
  if (v[3] < 2 || v[3] > UINT32_MAX) return bad(r, "label must be 2 or more (1 and 0 are implied)");
  uint64_t key = rs_label_key((uint32_t)v[0], (int)v[1], (int)v[2]);
  if (r->any && key <= r->last_key)
    return bad(r, key == r->last_key ? "address listed twice" : "address out of order (lines must be sorted)");
  r->any = true;
  r->last_key = key;
  out->packet = (uint32_t)v[0];
  out->block = (uint8_t)v[1];
  out->channel = (uint8_t)v[2];
  out->label = (uint32_t)v[3];
  return 1;
}

void rs_labels_close(rs_labels_reader_t *r) {
  if (r->f) fclose(r->f);
  r->f = NULL;
}

int rs_labels_create(rs_labels_writer_t *w, const char *path, const char *comment) {
  memset(w, 0, sizeof *w);
  w->f = fopen(path, "w");
  if (w->f == NULL) return RS_E_IO;
  setvbuf(w->f, NULL, _IOFBF, 1 << 20);
  if (comment && comment[0]) {
    const char *p = comment;
    while (*p) {
      size_t n = strcspn(p, "\n");
      fprintf(w->f, "# %.*s\n", (int)n, p);
      p += n;
      if (*p == '\n') p++;
    }
  }
  fprintf(w->f, HEADER "\n");
  return RS_OK;
}

int rs_labels_write(rs_labels_writer_t *w, uint32_t packet, int block, int channel, uint32_t label) {
  uint64_t key = rs_label_key(packet, block, channel);
  if (label < 2 || block < 0 || block > 11 || channel < 0 || channel > 31 || (w->any && key <= w->last_key)) {
    w->rejected++;
    return RS_E_INVAL;
  }
  w->any = true;
  w->last_key = key;
  /* hand-formatted: simulators write millions of these */
  char buf[48], *p = buf + sizeof buf;
  uint32_t vals[4] = {label, (uint32_t)channel, (uint32_t)block, packet};
  *--p = '\n';
  for (int i = 0; i < 4; i++) {
    uint32_t v = vals[i];
    do {
      *--p = (char)('0' + v % 10);
      v /= 10;
    } while (v);
    if (i < 3) *--p = ',';
  }
  fwrite(p, 1, (size_t)(buf + sizeof buf - p), w->f);
  w->written++;
  return RS_OK;
}

int rs_labels_finish(rs_labels_writer_t *w) {
  if (w->f == NULL) return RS_OK;
  int bad_close = fclose(w->f) != 0;
  w->f = NULL;
  return bad_close ? RS_E_IO : RS_OK;
}

static int cmp_entry(const void *a, const void *b) {
  uint64_t x = ((const rs_label_entry_t *)a)->key, y = ((const rs_label_entry_t *)b)->key;
  return (x > y) - (x < y);
}

void rs_labels_write_frame(rs_labels_writer_t *w, const rs_slot_t *s, rs_label_entry_t *buf, const uint32_t *map,
                           uint32_t nmap, const rs_labels_cells_t *each) {
  const uint32_t cells = (uint32_t)s->meta.rows * s->meta.cols;
  size_t n = 0;
  uint32_t e = 0; /* cursor in each->cell (ascending, as the cells are visited) */
  for (int l = 0; l < RS_LAYERS; l++)
    for (uint32_t i = 0; i < cells; i++) {
      uint32_t c = (uint32_t)l * RS_MAX_CELLS + i;
      if (s->range[c] == 0.0f || s->label[c] < RS_LABEL_NOISE) continue;
      buf[n].key = rs_label_key(s->addr[c].packet, s->addr[c].block, s->addr[c].channel);
      uint32_t lab = s->label[c];
      if (map && lab >= RS_LABEL_FIRST_OBJECT) {
        const uint32_t k = lab - RS_LABEL_FIRST_OBJECT;
        lab = k < nmap && map[k] ? map[k] : RS_LABEL_NOISE;
        if (each) {
          while (e < each->n && each->cell[e] < c) e++;
          if (e < each->n && each->cell[e] == c) {
            const uint32_t v = each->value[e];
            lab = v && v + each->offset > v ? v + each->offset : RS_LABEL_NOISE;
          }
        }
      }
      buf[n].label = lab;
      n++;
    }
  rs_sort(buf, n, sizeof buf[0], cmp_entry); /* qsort may allocate */
  for (size_t i = 0; i < n; i++)
    rs_labels_write(w, (uint32_t)(buf[i].key / 384u), (int)(buf[i].key / 32u % 12u), (int)(buf[i].key % 32u),
                    buf[i].label);
}

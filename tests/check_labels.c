/* check_labels - point-label files: valid files read back, every kind of
 * malformed line rejected with its line number, writer ordering. */
#include "roadscan/output/labels.h"
#include "testutil.h"

#include <stdio.h>
#include <string.h>

static const char *write_file(const char *name, const char *text) {
  const char *p = tu_tmp(name);
  FILE *f = fopen(p, "w");
  fputs(text, f);
  fclose(f);
  return p;
}

START_TEST(t_read_good) {
  const char *p = write_file("good.csv", "# generator test\n# seed 1\npacket,block,channel,label\n0,0,5,2\n0,11,31,3\n7,2,0,41\n");
  rs_labels_reader_t r;
  ck_assert_int_eq(rs_labels_open(&r, p, 10), RS_OK);
  rs_label_t l;
  ck_assert_int_eq(rs_labels_next(&r, &l), 1);
  ck_assert_int_eq(l.packet, 0);
  ck_assert_int_eq(l.channel, 5);
  ck_assert_int_eq(l.label, 2);
  ck_assert_int_eq(rs_labels_next(&r, &l), 1);
  ck_assert_int_eq(l.block, 11);
  ck_assert_int_eq(rs_labels_next(&r, &l), 1);
  ck_assert_int_eq(l.packet, 7);
  ck_assert_int_eq(l.label, 41);
  ck_assert_int_eq(rs_labels_next(&r, &l), 0);
  rs_labels_close(&r);
}
END_TEST

static void expect_bad(const char *body, long line, const char *needle) {
  char text[512];
  snprintf(text, sizeof text, "packet,block,channel,label\n%s", body);
  const char *p = write_file("bad.csv", text);
  rs_labels_reader_t r;
  ck_assert_int_eq(rs_labels_open(&r, p, 100), RS_OK);
  rs_label_t l;
  int rc;
  while ((rc = rs_labels_next(&r, &l)) == 1) {
  }
  ck_assert_int_eq(rc, RS_E_FORMAT);
  char where[64];
  snprintf(where, sizeof where, "bad.csv:%ld:", line);
  ck_assert_msg(strstr(r.err, where) != NULL, "'%s' lacks '%s'", r.err, where);
  ck_assert_msg(strstr(r.err, needle) != NULL, "'%s' lacks '%s'", r.err, needle);
  rs_labels_close(&r);
}

START_TEST(t_read_bad) {
  expect_bad("1,2,3\n", 2, "four");
  expect_bad("1,2,3,4,5\n", 2, "trailing");
  expect_bad("1,12,3,4\n", 2, "block out of range");
  expect_bad("1,2,32,4\n", 2, "channel out of range");
  expect_bad("1,2,3,1\n", 2, "label must be 2 or more");
  expect_bad("100,2,3,4\n", 2, "beyond the capture");
  expect_bad("1,2,3,4\n1,2,3,5\n", 3, "listed twice");
  expect_bad("1,2,3,4\n1,2,2,5\n", 3, "out of order");
  expect_bad("a,2,3,4\n", 2, "four");
  expect_bad("1,2,3,-4\n", 2, "four");
  rs_labels_reader_t r;
  ck_assert_int_eq(rs_labels_open(&r, write_file("nohdr.csv", "1,2,3,4\n"), 10), RS_E_FORMAT);
  ck_assert_ptr_nonnull(strstr(r.err, "expected the header"));
  ck_assert_int_eq(rs_labels_open(&r, write_file("empty.csv", ""), 10), RS_E_FORMAT);
  ck_assert_ptr_nonnull(strstr(r.err, "missing header"));
  ck_assert_int_eq(rs_labels_open(&r, tu_tmp("absent.csv"), 10), RS_E_NOENT);
}
END_TEST

START_TEST(t_write) {
  const char *p = tu_tmp("w.csv");
  rs_labels_writer_t w;
  ck_assert_int_eq(rs_labels_create(&w, p, "one\ntwo"), RS_OK);
  ck_assert_int_eq(rs_labels_write(&w, 3, 1, 2, 5), RS_OK);
  ck_assert_int_eq(rs_labels_write(&w, 3, 1, 2, 6), RS_E_INVAL); /* same address */
  ck_assert_int_eq(rs_labels_write(&w, 2, 0, 0, 6), RS_E_INVAL); /* going back */
  ck_assert_int_eq(rs_labels_write(&w, 4, 0, 0, 1), RS_E_INVAL); /* label 1 is implied */
  ck_assert_int_eq(rs_labels_write(&w, 4294967295u, 11, 31, 4000000000u), RS_OK);
  ck_assert_int_eq(rs_labels_finish(&w), RS_OK);
  ck_assert_uint_eq(w.written, 2);
  ck_assert_uint_eq(w.rejected, 3);
  rs_labels_reader_t r;
  ck_assert_int_eq(rs_labels_open(&r, p, UINT32_MAX), RS_OK);
  rs_label_t l;
  ck_assert_int_eq(rs_labels_next(&r, &l), 1);
  ck_assert_int_eq(l.packet, 3);
  ck_assert_int_eq(l.label, 5);
  ck_assert_int_eq(rs_labels_next(&r, &l), 1);
  ck_assert_uint_eq(l.label, 4000000000u);
  ck_assert_int_eq(rs_labels_next(&r, &l), 0);
  rs_labels_close(&r);
  ck_assert_int_eq(tu_count_lines(p), 5);
}
END_TEST

/* a frame's labels: clusters through the map, listed returns one by one */
START_TEST(t_write_frame) {
  static rs_slot_t s;
  static rs_label_entry_t buf[RS_LABELS_FRAME_MAX];
  memset(&s.meta, 0, sizeof s.meta);
  s.meta.rows = 2;
  s.meta.cols = 4;
  memset(s.range, 0, sizeof s.range);
  memset(s.label, 0, sizeof s.label);
  /* cells 0..4 of layer 0: cluster 3, 3, 4, 3, noise; one return of layer 1, cluster 4 */
  static const uint16_t lab[5] = {3, 3, 4, 3, 2};
  for (uint32_t i = 0; i < 5; i++) {
    s.range[i] = 10.0f;
    s.label[i] = lab[i];
    s.addr[i].packet = 7;
    s.addr[i].block = (uint8_t)(i / 2);
    s.addr[i].channel = (uint8_t)(10 - i); /* addresses out of cell order: written sorted */
  }
  const uint32_t c1 = RS_MAX_CELLS + 6;
  s.range[c1] = 10.0f;
  s.label[c1] = 4;
  s.addr[c1].packet = 9;
  const uint32_t map[2] = {10, 11};
  const uint32_t cell[3] = {1, 3, c1}, value[3] = {7, 0, 8};
  const rs_labels_cells_t each = {cell, value, 3, 2};
  const char *p = tu_tmp("frame.csv");
  rs_labels_writer_t w;
  ck_assert_int_eq(rs_labels_create(&w, p, NULL), RS_OK);
  rs_labels_write_frame(&w, &s, buf, map, 2, &each);
  ck_assert_int_eq(rs_labels_finish(&w), RS_OK);
  ck_assert_uint_eq(w.rejected, 0);
  rs_labels_reader_t r;
  ck_assert_int_eq(rs_labels_open(&r, p, UINT32_MAX), RS_OK);
  /* by address: cell 1 (listed: 7 + 2), 0 (cluster 3), 3 (listed 0: noise), 2 (cluster 4), 4 (noise), layer 1's
   * (listed: 8 + 2) */
  static const uint32_t want_label[6] = {9, 10, 2, 11, 2, 10};
  static const int want_channel[6] = {9, 10, 7, 8, 6, 0};
  for (int k = 0; k < 6; k++) {
    rs_label_t l;
    ck_assert_int_eq(rs_labels_next(&r, &l), 1);
    ck_assert_int_eq(l.channel, want_channel[k]);
    ck_assert_uint_eq(l.label, want_label[k]);
  }
  rs_label_t l;
  ck_assert_int_eq(rs_labels_next(&r, &l), 0);
  rs_labels_close(&r);
}
END_TEST

int main(void) {
  Suite *s = suite_create("labels");
  TCase *tc = tcase_create("core");
  tcase_add_test(tc, t_read_good);
  tcase_add_test(tc, t_read_bad);
  tcase_add_test(tc, t_write);
  tcase_add_test(tc, t_write_frame);
  suite_add_tcase(s, tc);
  return tu_run(s);
}

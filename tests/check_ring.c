/* check_ring - slot hand-off: order, drop-oldest when full, newest-only
 * consumer, lossless waiting, and a two-thread run where every published
 * frame is either processed or counted as dropped. */
#include "roadscan/util/error.h"
#include "roadscan/frame/ring.h"
#include "testutil.h"

#include <pthread.h>

START_TEST(t_fifo_and_drop_oldest) {
  rs_ring_t r;
  ck_assert_int_eq(rs_ring_init(&r, 2, false, false), RS_E_INVAL);
  ck_assert_int_eq(rs_ring_init(&r, 4, false, false), RS_OK);
  int a = rs_ring_acquire(&r, NULL);
  rs_ring_publish(&r, a);
  int b = rs_ring_acquire(&r, NULL);
  rs_ring_publish(&r, b);
  int c = rs_ring_acquire(&r, NULL);
  rs_ring_publish(&r, c);
  int d = rs_ring_acquire(&r, NULL); /* the fourth and last free slot */
  ck_assert(a != b && b != c && c != d && a != d);
  ck_assert_uint_eq(rs_ring_dropped(&r), 0);
  rs_ring_publish(&r, d);
  int e = rs_ring_acquire(&r, NULL); /* none free: the oldest (a) is dropped and reused */
  ck_assert_int_eq(e, a);
  ck_assert_uint_eq(rs_ring_dropped(&r), 1);
  ck_assert_int_eq(rs_ring_take(&r, 0), b); /* consumer gets the oldest left */
  ck_assert_int_eq(rs_ring_take(&r, 0), c);
  rs_ring_release(&r, b);
  rs_ring_release(&r, c);
  ck_assert_int_eq(rs_ring_take(&r, 0), d);
  ck_assert_int_eq(rs_ring_take(&r, 10), -1); /* empty: times out */
  rs_ring_release(&r, d);
  rs_ring_discard(&r, e);
  rs_ring_deinit(&r);
}
END_TEST

START_TEST(t_newest) {
  rs_ring_t r;
  rs_ring_init(&r, 4, false, true);
  int s[3];
  for (int i = 0; i < 3; i++) {
    s[i] = rs_ring_acquire(&r, NULL);
    rs_ring_publish(&r, s[i]);
  }
  ck_assert_int_eq(rs_ring_take(&r, 0), s[2]); /* skips to the newest */
  ck_assert_uint_eq(rs_ring_dropped(&r), 2);
  /* the skipped slots are free again */
  int x = rs_ring_acquire(&r, NULL), y = rs_ring_acquire(&r, NULL);
  ck_assert(x != s[2] && y != s[2] && x != y);
  rs_ring_deinit(&r);
}
END_TEST

START_TEST(t_lossless_waits) {
  rs_ring_t r;
  rs_ring_init(&r, 3, true, false);
  for (int i = 0; i < 3; i++) {
    int k = rs_ring_acquire(&r, NULL);
    ck_assert_int_ge(k, 0);
    rs_ring_publish(&r, k);
  }
  _Atomic bool stop = true; /* nothing free and a stop request: gives up */
  ck_assert_int_eq(rs_ring_acquire(&r, &stop), -1);
  ck_assert_uint_eq(rs_ring_dropped(&r), 0);
  int t = rs_ring_take(&r, 0);
  rs_ring_release(&r, t);
  atomic_store(&stop, false);
  ck_assert_int_eq(rs_ring_acquire(&r, &stop), t);
  rs_ring_deinit(&r);
}
END_TEST

#define FRAMES 20000
static rs_ring_t ring;
static int seqno[RS_RING_MAX_SLOTS];
static _Atomic bool done;

static void *consumer(void *arg) {
  long *got = arg;
  int last = -1;
  for (;;) {
    int k = rs_ring_take(&ring, 20);
    if (k < 0) {
      if (atomic_load(&done)) {
        k = rs_ring_take(&ring, 0);
        if (k < 0) break;
      } else {
        continue;
      }
    }
    if (seqno[k] <= last) {
      *got = -1000000; /* out of order: fail below */
    }
    last = seqno[k];
    (*got)++;
    rs_ring_release(&ring, k);
  }
  return NULL;
}

static void threaded(bool lossless, bool newest) {
  rs_ring_init(&ring, 4, lossless, newest);
  atomic_store(&done, false);
  long got = 0;
  pthread_t th;
  pthread_create(&th, NULL, consumer, &got);
  for (int i = 0; i < FRAMES; i++) {
    int k = rs_ring_acquire(&ring, NULL);
    ck_assert_int_ge(k, 0);
    seqno[k] = i;
    rs_ring_publish(&ring, k);
  }
  atomic_store(&done, true);
  sem_post(&ring.ready);
  pthread_join(th, NULL);
  ck_assert_int_ge(got, 1);
  ck_assert_uint_eq((uint64_t)got + rs_ring_dropped(&ring), FRAMES);
  if (lossless) ck_assert_int_eq(got, FRAMES);
  rs_ring_deinit(&ring);
}

START_TEST(t_threads_drop) { threaded(false, false); }
END_TEST
START_TEST(t_threads_newest) { threaded(false, true); }
END_TEST
START_TEST(t_threads_lossless) { threaded(true, false); }
END_TEST

int main(void) {
  Suite *s = suite_create("ring");
  TCase *tc = tcase_create("core");
  tcase_set_timeout(tc, 120);
  tcase_add_test(tc, t_fifo_and_drop_oldest);
  tcase_add_test(tc, t_newest);
  tcase_add_test(tc, t_lossless_waits);
  tcase_add_test(tc, t_threads_drop);
  tcase_add_test(tc, t_threads_newest);
  tcase_add_test(tc, t_threads_lossless);
  suite_add_tcase(s, tc);
  return tu_run(s);
}

/* subscriber.c - a C subscriber to roadscand's object lists, written against
 * the installed package (the consumer library and its pkg-config file):
 *
 *   cc subscriber.c $(pkg-config --cflags --libs roadscan-lcmtypes) -o subscriber
 *   ./subscriber [URL [CHANNEL]]
 *
 * URL: the daemon's (udpm://239.255.76.67:7667?ttl=0) by default; a log
 * recorded with lcm-logger reads as file:///abs/path.lcmlog?speed=0. One line
 * per object list; the totals at the end (2 s without a message, or the end
 * of a log). Every message is checked (lcmcheck.h) before the generated
 * decoder sees it: the generated code trusts the wire, and a forged string or
 * array length would crash it. */
#include <lcm/lcm.h>
#include <lcmcheck.h>
#include <roadscan_object_list_t.h>

#include <inttypes.h>
#include <stdio.h>

static long lists, objects, refused;

static void on_list(const lcm_recv_buf_t *rbuf, const char *channel, void *user) {
  (void)user;
  char why[256];
  if (!rs_lcm_check(RS_LCM_OBJECT_LIST, rbuf->data, (int)rbuf->data_size, why, sizeof why)) {
    refused++;
    fprintf(stderr, "subscriber: %s: a message of %u bytes refused: %s\n", channel, rbuf->data_size, why);
    return;
  }
  roadscan_object_list_t l;
  if (roadscan_object_list_t_decode(rbuf->data, 0, (int)rbuf->data_size, &l) < 0) {
    refused++;
    return;
  }
  lists++;
  objects += l.num_objects;
  printf("%s frame %" PRId64 ": %d objects\n", l.sensor_id, l.frame_seq, l.num_objects);
  roadscan_object_list_t_decode_cleanup(&l);
}

int main(int argc, char **argv) {
  const char *url = argc > 1 ? argv[1] : "udpm://239.255.76.67:7667?ttl=0";
  const char *channel = argc > 2 ? argv[2] : "ROADSCAN_OBJECTS";
  lcm_t *lcm = lcm_create(url);
  if (lcm == NULL) {
    fprintf(stderr, "subscriber: cannot open LCM at %s\n", url);
    return 1;
  }
  lcm_subscribe(lcm, channel, on_list, NULL);
  while (lcm_handle_timeout(lcm, 2000) > 0) {
  }
  fprintf(stderr, "subscriber: lists %ld, objects %ld, refused %ld\n", lists, objects, refused);
  lcm_destroy(lcm);
  return lists > 0 ? 0 : 1;
}

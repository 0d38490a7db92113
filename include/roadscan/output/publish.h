/* publish.h - object lists and frame statistics over LCM.
 *
 * Start-up (rs_publish_init, main thread): checks the URL, for udpm://
 * that the kernel has a route to the multicast group (otherwise it says
 * which command adds one), creates the lcm_t and computes the object cap:
 * as many objects as fit in one LCM datagram (max_datagram bytes, channel
 * name included). Run time (processing thread): each list is encoded into a
 * static buffer with the generated _encode and sent with lcm_publish; no
 * allocation. A frame with more clusters than the cap keeps the ones with
 * the most returns, sets `truncated` and counts it. */
#ifndef ROADSCAN_PUBLISH_H
#define ROADSCAN_PUBLISH_H

#include "roadscan/util/error.h"
#include "roadscan/frame/frame.h"
#include "roadscan/perception/count.h"
#include "roadscan/perception/objects.h"
#include "roadscan/perception/track.h"

#include <lcm/lcm.h>
#include <roadscan_counts_t.h>
#include <roadscan_crossing_t.h>
#include <roadscan_frame_stats_t.h>
#include <roadscan_object_list_t.h>
#include <roadscan_track_end_t.h>
#include <roadscan_track_list_t.h>
#include <stdbool.h>
#include <stdint.h>

#define RS_PUB_DEFAULT_URL "udpm://239.255.76.67:7667?ttl=0"
#define RS_PUB_DEFAULT_CHANNEL "ROADSCAN_OBJECTS"
#define RS_PUB_DEFAULT_STATS "ROADSCAN_STATS"
#define RS_PUB_DEFAULT_TRACKS "ROADSCAN_TRACKS"
#define RS_PUB_DEFAULT_TRACK_ENDS "ROADSCAN_TRACK_ENDS"
#define RS_PUB_DEFAULT_COUNTS "ROADSCAN_COUNTS"
#define RS_PUB_DEFAULT_CROSSINGS "ROADSCAN_CROSSINGS"
#define RS_PUB_DATAGRAM_MAX 65499 /* LCM's single-datagram limit on Linux: channel + NUL + payload */
#define RS_PUB_DATAGRAM_MIN 1400
#define RS_PUB_MAX_OBJECTS 512    /* >= what fits in RS_PUB_DATAGRAM_MAX (checked at init) */
#define RS_PUB_NAME_MAX 64

typedef struct {
  const char *url;           /* NULL: $LCM_DEFAULT_URL, else RS_PUB_DEFAULT_URL */
  const char *channel;       /* NULL: RS_PUB_DEFAULT_CHANNEL */
  const char *stats_channel; /* NULL: RS_PUB_DEFAULT_STATS; "" = no statistics */
  const char *tracks_channel;     /* NULL: RS_PUB_DEFAULT_TRACKS; "" = no track lists */
  const char *track_ends_channel; /* NULL: RS_PUB_DEFAULT_TRACK_ENDS; "" = no end events */
  const char *counts_channel;     /* NULL: RS_PUB_DEFAULT_COUNTS; "" = no counts */
  const char *crossings_channel;  /* NULL: RS_PUB_DEFAULT_CROSSINGS; "" = no crossing events */
  const char *sensor_id;     /* NULL: "roadscan" */
  int max_datagram;          /* 0: RS_PUB_DATAGRAM_MAX */
  lcm_t *lcm;                /* optional: publish on this instance (not destroyed) */
} rs_publish_cfg_t;

typedef struct {
  char url[512], channel[RS_PUB_NAME_MAX], stats_channel[RS_PUB_NAME_MAX], sensor_id[RS_PUB_NAME_MAX];
  char tracks_channel[RS_PUB_NAME_MAX], ends_channel[RS_PUB_NAME_MAX], counts_channel[RS_PUB_NAME_MAX];
  char crossings_channel[RS_PUB_NAME_MAX];
  int max_datagram;
  lcm_t *lcm;
  bool own_lcm;
  uint32_t cap;                 /* objects per list */
  uint32_t track_cap;           /* tracks per list */
  uint64_t lists, stats, truncated_lists, objects_dropped, errors;
  uint64_t track_lists, track_ends, truncated_track_lists, counts, crossings;
  roadscan_count_line_t count_wire[RS_COUNT_LINES];
  roadscan_count_zone_t zone_wire[RS_COUNT_ZONES];
  uint16_t track_order[RS_TRACK_MAX];
  roadscan_track_t track_wire[RS_TRACK_MAX];
  uint16_t order[RS_OBJ_MAX];
  roadscan_object_t wire[RS_PUB_MAX_OBJECTS];
  uint8_t buf[RS_PUB_DATAGRAM_MAX];
  char err[RS_ERRMSG_SIZE];
} rs_publish_t;

/* RS_OK; RS_E_INVAL (bad URL or names), RS_E_NOROUTE, RS_E_LCM with p->err. */
int rs_publish_init(rs_publish_t *p, const rs_publish_cfg_t *cfg);
void rs_publish_deinit(rs_publish_t *p);

/* Fills `msg` (whose objects point into p->wire) from a frame and its objects. */
void rs_publish_fill(rs_publish_t *p, const rs_frame_meta_t *m, const rs_object_list_t *objs, int64_t utime,
                     roadscan_object_list_t *msg);
/* Encodes and publishes; RS_OK or RS_E_LCM (counted). */
int rs_publish_objects(rs_publish_t *p, const rs_frame_meta_t *m, const rs_object_list_t *objs, int64_t utime);
int rs_publish_stats(rs_publish_t *p, const roadscan_frame_stats_t *st);
/* Fills `msg` (whose tracks point into p->track_wire): confirmed and
 * coasting tracks first, then tentative ones, each in id order, up to the cap. */
void rs_publish_fill_tracks(rs_publish_t *p, const rs_frame_meta_t *m, const rs_track_list_t *tl, int64_t utime,
                            roadscan_track_list_t *msg);
/* The counts of every line over a closed interval. */
int rs_publish_counts(rs_publish_t *p, const rs_counter_t *c, const rs_count_interval_t *iv, int64_t utime);
/* One message per crossing event (count.h) of a frame. */
int rs_publish_crossings(rs_publish_t *p, const rs_counter_t *c, const rs_count_event_t *ev, uint32_t n, int64_t utime);
/* The track list of a frame, then one message per track that ended. */
int rs_publish_tracks(rs_publish_t *p, const rs_frame_meta_t *m, const rs_track_list_t *tl, int64_t utime);

/* Microseconds since the Unix epoch (CLOCK_REALTIME), for utime fields. */
int64_t rs_publish_utime(void);

/* For readers of untrusted bytes: true when len bytes are a well-formed
 * object_list_t (rs_lcm_check: every string and count checked before the
 * generated _decode, which trusts them). */
bool rs_publish_list_plausible(const void *data, int len);

#endif

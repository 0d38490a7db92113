/* publish.c - LCM object lists and statistics.
 *
 * rs_publish_init runs in the main thread before the pipeline starts; the
 * publish calls run in the processing thread only and use the static
 * buffers of rs_publish_t (the generated *_publish, which allocates, is
 * never called). */
#include "roadscan/output/publish.h"

#include "roadscan/output/lcmcheck.h"

#include "roadscan/output/labels.h"

#include <arpa/inet.h>
#include <errno.h>
#include <math.h>
#include <netinet/in.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/socket.h>
#include <time.h>
#include <unistd.h>

int64_t rs_publish_utime(void) {
  struct timespec ts;
  clock_gettime(CLOCK_REALTIME, &ts);
  return (int64_t)ts.tv_sec * 1000000 + ts.tv_nsec / 1000;
}

static bool copy_name(char *dst, size_t n, const char *src, const char *what, char *err, size_t errn) {
  size_t len = strlen(src);
  if (len == 0 || len >= n) {
    snprintf(err, errn, "%s: '%s' must have 1 to %zu characters", what, src, n - 1);
    return false;
  }
  for (size_t i = 0; i < len; i++)
    if ((unsigned char)src[i] <= ' ' || (unsigned char)src[i] > '~') {
      snprintf(err, errn, "%s: '%s' has a space or a non-ASCII character", what, src);
      return false;
    }
  memcpy(dst, src, len + 1);
  return true;
}

/* udpm://ADDR:PORT?opts (address and port optional): can the kernel route
 * a datagram to the group? connect() on a UDP socket asks exactly that. */
static int check_udpm_route(const char *url, char *err, size_t n) {
  const char *hostport = url + strlen("udpm://");
  char addr[128] = "239.255.76.67";
  int port = 7667;
  size_t len = strcspn(hostport, "?");
  if (len > 0) {
    char hp[128];
    if (len >= sizeof hp) {
      snprintf(err, n, "LCM URL '%s': address too long", url);
      return RS_E_INVAL;
    }
    memcpy(hp, hostport, len);
    hp[len] = '\0';
    char *colon = strchr(hp, ':');
    if (colon) {
      *colon = '\0';
      char *end;
      long p = strtol(colon + 1, &end, 10);
      if (*end != '\0' || p < 1 || p > 65535) {
        snprintf(err, n, "LCM URL '%s': bad port '%s'", url, colon + 1);
        return RS_E_INVAL;
      }
      port = (int)p;
    }
    if (hp[0]) snprintf(addr, sizeof addr, "%s", hp);
  }
  struct sockaddr_in sa;
  memset(&sa, 0, sizeof sa);
  sa.sin_family = AF_INET;
  sa.sin_port = htons((uint16_t)port);
  if (inet_pton(AF_INET, addr, &sa.sin_addr) != 1 || !IN_MULTICAST(ntohl(sa.sin_addr.s_addr))) {
    snprintf(err, n, "LCM URL '%s': '%s' is not an IPv4 multicast address (224.0.0.0/4)", url, addr);
    return RS_E_INVAL;
  }
  int fd = socket(AF_INET, SOCK_DGRAM, 0);
  if (fd < 0) {
    snprintf(err, n, "LCM URL '%s': cannot open a UDP socket: %s", url, strerror(errno));
    return RS_E_LCM;
  }
  int rc = connect(fd, (struct sockaddr *)&sa, sizeof sa);
  int e = errno;
  close(fd);
  if (rc != 0) {
    snprintf(err, n,
             "LCM URL '%s': no route to the multicast group %s (%s), so nothing could be published. "
             "To publish on this host only, run as root: ip link set lo up && ip route add 224.0.0.0/4 dev lo "
             "(or route 224.0.0.0/4 to the interface the consumers are on)",
             url, addr, strerror(e));
    return RS_E_NOROUTE;
  }
  return RS_OK;
}

int rs_publish_init(rs_publish_t *p, const rs_publish_cfg_t *cfg) {
  memset(p, 0, sizeof *p);
  const char *env = getenv("LCM_DEFAULT_URL"); /* LCM's own convention */
  const char *url = cfg->url && cfg->url[0] ? cfg->url : env && env[0] ? env : RS_PUB_DEFAULT_URL;
  if (strlen(url) >= sizeof p->url) {
    snprintf(p->err, sizeof p->err, "LCM URL too long");
    return RS_E_INVAL;
  }
  snprintf(p->url, sizeof p->url, "%s", url);
  if (!copy_name(p->channel, sizeof p->channel, cfg->channel ? cfg->channel : RS_PUB_DEFAULT_CHANNEL, "channel",
                 p->err, sizeof p->err) ||
      !copy_name(p->sensor_id, sizeof p->sensor_id, cfg->sensor_id ? cfg->sensor_id : "roadscan", "sensor id", p->err,
                 sizeof p->err))
    return RS_E_INVAL;
  const char *stats = cfg->stats_channel ? cfg->stats_channel : RS_PUB_DEFAULT_STATS;
  if (stats[0] && !copy_name(p->stats_channel, sizeof p->stats_channel, stats, "stats channel", p->err, sizeof p->err))
    return RS_E_INVAL;
  const char *tch = cfg->tracks_channel ? cfg->tracks_channel : RS_PUB_DEFAULT_TRACKS;
  if (tch[0] && !copy_name(p->tracks_channel, sizeof p->tracks_channel, tch, "tracks channel", p->err, sizeof p->err))
    return RS_E_INVAL;
  const char *cch = cfg->counts_channel ? cfg->counts_channel : RS_PUB_DEFAULT_COUNTS;
  if (cch[0] && !copy_name(p->counts_channel, sizeof p->counts_channel, cch, "counts channel", p->err, sizeof p->err))
    return RS_E_INVAL;
  const char *xch = cfg->crossings_channel ? cfg->crossings_channel : RS_PUB_DEFAULT_CROSSINGS;
  if (xch[0] &&
      !copy_name(p->crossings_channel, sizeof p->crossings_channel, xch, "crossings channel", p->err, sizeof p->err))
    return RS_E_INVAL;
  const char *ech = cfg->track_ends_channel ? cfg->track_ends_channel : RS_PUB_DEFAULT_TRACK_ENDS;
  if (ech[0] && !copy_name(p->ends_channel, sizeof p->ends_channel, ech, "track ends channel", p->err, sizeof p->err))
    return RS_E_INVAL;
  p->max_datagram = cfg->max_datagram ? cfg->max_datagram : RS_PUB_DATAGRAM_MAX;
  if (p->max_datagram < RS_PUB_DATAGRAM_MIN || p->max_datagram > RS_PUB_DATAGRAM_MAX) {
    snprintf(p->err, sizeof p->err, "max datagram: %d must be between %d and %d bytes", p->max_datagram,
             RS_PUB_DATAGRAM_MIN, RS_PUB_DATAGRAM_MAX);
    return RS_E_INVAL;
  }
  /* the cap: what fits next to the channel name and the list's fixed part */
  roadscan_object_list_t empty;
  memset(&empty, 0, sizeof empty);
  empty.sensor_id = p->sensor_id;
  empty.sensor_model = (char *)rs_model_name(RS_MODEL_UNKNOWN);
  for (int mdl = RS_MODEL_UNKNOWN + 1; mdl < RS_MODEL_COUNT; mdl++) /* the longest model name */
    if (strlen(rs_model_name((rs_model_t)mdl)) > strlen(empty.sensor_model))
      empty.sensor_model = (char *)rs_model_name((rs_model_t)mdl);
  roadscan_object_t one;
  memset(&one, 0, sizeof one);
  int fixed = roadscan_object_list_t_encoded_size(&empty) + (int)strlen(p->channel) + 1;
  int each = __roadscan_object_t_encoded_array_size(&one, 1);
  int cap = (p->max_datagram - fixed) / each;
  if (cap < 1) {
    snprintf(p->err, sizeof p->err, "max datagram: %d bytes cannot hold one object", p->max_datagram);
    return RS_E_INVAL;
  }
  if (cap > RS_PUB_MAX_OBJECTS) cap = RS_PUB_MAX_OBJECTS; /* only if RS_PUB_DATAGRAM_MAX grew */
  p->cap = (uint32_t)cap;
  roadscan_track_list_t tempty;
  memset(&tempty, 0, sizeof tempty);
  tempty.sensor_id = p->sensor_id;
  roadscan_track_t tone;
  memset(&tone, 0, sizeof tone);
  const int tfixed = roadscan_track_list_t_encoded_size(&tempty) + (int)strlen(p->tracks_channel) + 1;
  const int tcap = (p->max_datagram - tfixed) / __roadscan_track_t_encoded_array_size(&tone, 1);
  p->track_cap = tcap < 1 ? 1 : (tcap > RS_TRACK_MAX ? RS_TRACK_MAX : (uint32_t)tcap);
  if (cfg->lcm) {
    p->lcm = cfg->lcm;
    return RS_OK;
  }
  if (strncmp(url, "udpm://", 7) == 0) {
    int rc = check_udpm_route(url, p->err, sizeof p->err);
    if (rc != RS_OK) return rc;
  } else if (strncmp(url, "memq://", 7) != 0 && strncmp(url, "file://", 7) != 0) {
    snprintf(p->err, sizeof p->err, "LCM URL '%s': provider not udpm://, file:// or memq://", url);
    return RS_E_INVAL;
  }
  p->lcm = lcm_create(url);
  if (p->lcm == NULL) {
    snprintf(p->err, sizeof p->err, "LCM URL '%s': lcm_create failed (see LCM's message above)", url);
    return RS_E_LCM;
  }
  p->own_lcm = true;
  return RS_OK;
}

void rs_publish_deinit(rs_publish_t *p) {
  if (p->own_lcm && p->lcm) lcm_destroy(p->lcm);
  p->lcm = NULL;
  p->own_lcm = false;
}

static int64_t usec(double t) { return (int64_t)llround(t * 1e6); }

static void geom_to_wire(const rs_obj_geom_t *g, float *centroid, float *bmin, float *bmax, float *oc, float *len,
                         float *wid, float *head) {
  memcpy(centroid, g->centroid, sizeof g->centroid);
  memcpy(bmin, g->box_min, sizeof g->box_min);
  memcpy(bmax, g->box_max, sizeof g->box_max);
  memcpy(oc, g->obb_center, sizeof g->obb_center);
  *len = g->obb_length;
  *wid = g->obb_width;
  *head = g->obb_heading;
}

static void object_to_wire(const rs_object_t *o, bool site, roadscan_object_t *w) {
  memset(w, 0, sizeof *w);
  w->id = (int32_t)o->id;
  w->points = (int32_t)o->points;
  geom_to_wire(&o->sensor, w->centroid, w->box_min, w->box_max, w->obb_center, &w->obb_length, &w->obb_width,
               &w->obb_heading);
  if (site)
    geom_to_wire(&o->site, w->site_centroid, w->site_box_min, w->site_box_max, w->site_obb_center,
                 &w->site_obb_length, &w->site_obb_width, &w->site_obb_heading);
  w->range_min = o->range_min;
  w->azimuth_start = o->az_start;
  w->azimuth_end = o->az_end;
  w->row_min = (int16_t)o->row_min;
  w->row_max = (int16_t)o->row_max;
  w->col_start = (int16_t)o->col_start;
  w->col_end = (int16_t)o->col_end;
  w->intensity_mean = o->intensity_mean;
  w->t_first = usec(o->t_first);
  w->t_last = usec(o->t_last);
}

void rs_publish_fill(rs_publish_t *p, const rs_frame_meta_t *m, const rs_object_list_t *objs, int64_t utime,
                     roadscan_object_list_t *msg) {
  memset(msg, 0, sizeof *msg);
  msg->utime = utime;
  msg->sensor_id = p->sensor_id;
  msg->sensor_model = (char *)rs_model_name(m->model);
  msg->frame_seq = (int64_t)m->seq;
  msg->t_first = usec(m->t_first);
  msg->t_last = usec(m->t_last);
  msg->packets = (int32_t)m->packets;
  msg->packets_missing = (int32_t)m->missing_packets;
  msg->columns_covered = (int32_t)m->columns;
  msg->columns = m->cols;
  msg->partial = m->partial;
  msg->site_valid = objs->site_valid;
  /* non-empty clusters, by id */
  uint32_t n = 0;
  for (uint32_t k = 0; k < objs->count; k++)
    if (objs->obj[k].points > 0) p->order[n++] = (uint16_t)k;
  msg->num_clusters = (int32_t)n;
  if (n > p->cap) {
    /* keep the clusters with the most returns (insertion of the cap best: bounded by cap x n) */
    uint32_t kept = 0;
    for (uint32_t i = 0; i < n; i++) {
      uint16_t k = p->order[i];
      uint32_t pts = objs->obj[k].points, j = kept < p->cap ? kept : p->cap - 1;
      if (kept == p->cap && pts <= objs->obj[p->order[j]].points) continue;
      while (j > 0 && objs->obj[p->order[j - 1]].points < pts) {
        p->order[j] = p->order[j - 1];
        j--;
      }
      p->order[j] = k;
      if (kept < p->cap) kept++;
    }
    p->objects_dropped += n - p->cap;
    p->truncated_lists++;
    msg->truncated = true;
    n = p->cap;
  }
  for (uint32_t i = 0; i < n; i++) object_to_wire(&objs->obj[p->order[i]], objs->site_valid, &p->wire[i]);
  msg->num_objects = (int32_t)n;
  msg->objects = p->wire;
}

int rs_publish_objects(rs_publish_t *p, const rs_frame_meta_t *m, const rs_object_list_t *objs, int64_t utime) {
  roadscan_object_list_t msg;
  rs_publish_fill(p, m, objs, utime, &msg);
  int len = roadscan_object_list_t_encode(p->buf, 0, (int)sizeof p->buf, &msg);
  if (len < 0 || lcm_publish(p->lcm, p->channel, p->buf, (unsigned)len) != 0) {
    p->errors++;
    return RS_E_LCM;
  }
  p->lists++;
  return RS_OK;
}

int rs_publish_stats(rs_publish_t *p, const roadscan_frame_stats_t *st) {
  if (!p->stats_channel[0]) return RS_OK;
  int len = roadscan_frame_stats_t_encode(p->buf, 0, (int)sizeof p->buf, st);
  if (len < 0 || lcm_publish(p->lcm, p->stats_channel, p->buf, (unsigned)len) != 0) {
    p->errors++;
    return RS_E_LCM;
  }
  p->stats++;
  return RS_OK;
}

bool rs_publish_list_plausible(const void *data, int len) {
  char err[128];
  return rs_lcm_check(RS_LCM_OBJECT_LIST, data, len, err, sizeof err);
}

static void track_to_wire(const rs_track_t *t, double t_frame, roadscan_track_t *w) {
  memset(w, 0, sizeof *w);
  w->id = (int32_t)t->id;
  w->state = (int8_t)t->state;
  w->class_id = (int8_t)t->cls;
  w->age = (float)(t_frame - t->t_birth);
  w->hits = (int32_t)t->hits;
  w->misses = (int32_t)t->misses;
  w->position[0] = (float)t->x[0];
  w->position[1] = (float)t->x[1];
  w->position[2] = t->z_min;
  w->velocity[0] = (float)t->vel[0];
  w->velocity[1] = (float)t->vel[1];
  w->speed = t->speed;
  w->heading = t->heading;
  w->length = t->length;
  w->width = t->width;
  w->height = t->height;
  w->points = (int32_t)t->points;
  w->position_cov[0] = (float)t->P[0][0];
  w->position_cov[1] = (float)t->P[0][1];
  w->position_cov[2] = (float)t->P[1][1];
  memcpy(w->site_position, t->site, sizeof w->site_position);
  memcpy(w->site_velocity, t->site_v, sizeof w->site_velocity);
  w->site_heading = t->site_heading;
}

void rs_publish_fill_tracks(rs_publish_t *p, const rs_frame_meta_t *m, const rs_track_list_t *tl, int64_t utime,
                            roadscan_track_list_t *msg) {
  memset(msg, 0, sizeof *msg);
  msg->utime = utime;
  msg->sensor_id = p->sensor_id;
  msg->frame_seq = (int64_t)m->seq;
  msg->t_frame = usec(m->t_last);
  msg->site_valid = tl->site_valid;
  const uint32_t count = tl->count < RS_TRACK_MAX ? tl->count : RS_TRACK_MAX;
  uint32_t n = 0, alive = 0; /* lost tracks (kept for re-acquisition) are not published */
  for (uint32_t i = 0; i < count; i++) alive += tl->track[i].state != RS_TRACK_LOST;
  msg->num_alive = (int32_t)alive;
  for (int pass = 0; pass < 2; pass++) /* confirmed and coasting first */
    for (uint32_t i = 0; i < count && n < p->track_cap; i++)
      if (tl->track[i].state != RS_TRACK_LOST && (tl->track[i].state != RS_TRACK_TENTATIVE) == (pass == 0))
        p->track_order[n++] = (uint16_t)i;
  if (n < alive) {
    msg->truncated = true;
    p->truncated_track_lists++;
  }
  for (uint32_t i = 0; i < n; i++) track_to_wire(&tl->track[p->track_order[i]], tl->t, &p->track_wire[i]);
  msg->num_tracks = (int32_t)n;
  msg->tracks = p->track_wire;
}

int rs_publish_tracks(rs_publish_t *p, const rs_frame_meta_t *m, const rs_track_list_t *tl, int64_t utime) {
  int rc = RS_OK;
  if (p->tracks_channel[0]) {
    roadscan_track_list_t msg;
    rs_publish_fill_tracks(p, m, tl, utime, &msg);
    int len = roadscan_track_list_t_encode(p->buf, 0, (int)sizeof p->buf, &msg);
    if (len < 0 || lcm_publish(p->lcm, p->tracks_channel, p->buf, (unsigned)len) != 0) {
      p->errors++;
      rc = RS_E_LCM;
    } else {
      p->track_lists++;
    }
  }
  for (uint32_t i = 0; i < tl->ended && i < RS_TRACK_ENDED_MAX && p->ends_channel[0]; i++) {
    const rs_track_end_t *e = &tl->end[i];
    roadscan_track_end_t ev;
    memset(&ev, 0, sizeof ev);
    ev.utime = utime;
    ev.sensor_id = p->sensor_id;
    ev.id = (int32_t)e->id;
    ev.class_id = (int8_t)e->cls;
    ev.t_first = usec(e->t_birth);
    ev.t_last = usec(e->t_end);
    ev.duration = (float)(e->t_end - e->t_birth);
    ev.distance = (float)e->distance;
    ev.mean_speed = (float)e->mean_speed;
    ev.max_speed = (float)e->max_speed;
    int len = roadscan_track_end_t_encode(p->buf, 0, (int)sizeof p->buf, &ev);
    if (len < 0 || lcm_publish(p->lcm, p->ends_channel, p->buf, (unsigned)len) != 0) {
      p->errors++;
      rc = RS_E_LCM;
    } else {
      p->track_ends++;
    }
  }
  return rc;
}

int rs_publish_crossings(rs_publish_t *p, const rs_counter_t *c, const rs_count_event_t *ev, uint32_t n, int64_t utime) {
  int rc = RS_OK;
  for (uint32_t k = 0; k < n && p->crossings_channel[0]; k++) {
    roadscan_crossing_t m;
    memset(&m, 0, sizeof m);
    m.utime = utime;
    m.sensor_id = p->sensor_id;
    m.line = (char *)c->lines[ev[k].line].name;
    m.t_cross = usec(ev[k].t);
    m.direction = ev[k].dir;
    m.at = ev[k].at;
    m.class_id = (int8_t)ev[k].cls;
    m.track_id = (int32_t)ev[k].track;
    m.speed = ev[k].speed;
    m.how = (int8_t)ev[k].how;
    const int len = roadscan_crossing_t_encode(p->buf, 0, (int)sizeof p->buf, &m);
    if (len < 0 || lcm_publish(p->lcm, p->crossings_channel, p->buf, (unsigned)len) != 0) {
      p->errors++;
      rc = RS_E_LCM;
    } else {
      p->crossings++;
    }
  }
  return rc;
}

_Static_assert(RS_CLASS_COUNT == 6, "count_line_t has 6 classes (lcmtypes/roadscan.lcm)");

int rs_publish_counts(rs_publish_t *p, const rs_counter_t *c, const rs_count_interval_t *iv, int64_t utime) {
  if (!p->counts_channel[0]) return RS_OK;
  roadscan_counts_t msg;
  memset(&msg, 0, sizeof msg);
  msg.utime = utime;
  msg.sensor_id = p->sensor_id;
  msg.t_start = usec(iv->t_start);
  msg.t_end = usec(iv->t_end);
  msg.num_lines = c->nlines;
  for (int l = 0; l < c->nlines; l++) {
    roadscan_count_line_t *w = &p->count_wire[l];
    w->name = (char *)c->lines[l].name;
    for (int k = 0; k < RS_CLASS_COUNT; k++) {
      w->forward[k] = (int32_t)iv->line[l].forward[k];
      w->backward[k] = (int32_t)iv->line[l].backward[k];
    }
  }
  msg.lines = p->count_wire;
  msg.num_zones = c->nzones;
  for (int z = 0; z < c->nzones; z++) {
    roadscan_count_zone_t *w = &p->zone_wire[z];
    w->name = (char *)c->zones[z].name;
    for (int k = 0; k < RS_CLASS_COUNT; k++) {
      w->entered[k] = (int32_t)iv->zone[z].entered[k];
      w->exited[k] = (int32_t)iv->zone[z].exited[k];
    }
    w->occupancy = (int32_t)iv->zone[z].occupancy;
    w->occupancy_max = (int32_t)iv->zone[z].occupancy_max;
  }
  msg.zones = p->zone_wire;
  int len = roadscan_counts_t_encode(p->buf, 0, (int)sizeof p->buf, &msg);
  if (len < 0 || lcm_publish(p->lcm, p->counts_channel, p->buf, (unsigned)len) != 0) {
    p->errors++;
    return RS_E_LCM;
  }
  p->counts++;
  return RS_OK;
}

/* pipeline.c - packet thread and processing thread.
 *
 * Ownership: the packet thread owns cap, stream, assembly, cur and t_packet;
 * the processing thread owns proc, t_frame and frames_out; slots move
 * between them only through the ring. stop/input_done are atomics. */
#include "roadscan/daemon/pipeline.h"

#include "roadscan/util/error.h"
#include "roadscan/util/log.h"

#include <inttypes.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#define TAKE_TIMEOUT_MS 100

const char *rs_pipeline_counts_header(void) { return "t_start,t_end,line,direction,class,count"; }

const char *rs_pipeline_crossings_header(void) { return "t,line,direction,at,class,track,speed,how"; }

const char *rs_pipeline_tracks_header(void) {
  return "frame,t,track,state,class,x,y,z,vx,vy,speed,heading,length,width,height,points,hits,misses,age,"
         "cov_xx,cov_xy,cov_yy,site_x,site_y,site_z,site_vx,site_vy,site_heading";
}

const char *rs_pipeline_objects_header(void) {
  return "frame,t,object,x,y,length,width,heading,z_min,z_max,centroid_x,centroid_y,centroid_z,points,range_min,"
         "occluded,site_x,site_y,site_heading";
}

const char *rs_pipeline_csv_header(void) {
  return "frame,t_first,t_last,packets,points,columns,missing_packets,dropped_frames,"
         "out_of_order,duplicates,late_points,shifted,collisions,partial,rows,cols,rate_hz,return_mode,"
         "first_packet,last_packet,layer0_cells,layer1_cells,min_range,max_range,process_us,foreground,clusters,"
         "displaced,shift_evidence";
}


/* a CSV sink with its header; false with input_err naming the option */
static bool open_csv(rs_pipeline_t *p, FILE **f, const char *path, const char *option, const char *header) {
  *f = fopen(path, "w");
  if (*f == NULL) {
    snprintf(p->input_err, sizeof p->input_err, "%s %s: cannot write", option, path);
    return false;
  }
  fprintf(*f, "%s\n", header);
  return true;
}

int rs_pipeline_init(rs_pipeline_t *p, const rs_pipeline_cfg_t *cfg, rs_slot_t *slots, int nslots) {
  memset(p, 0, sizeof *p);
  p->cfg = *cfg;
  p->slots = slots;
  p->cur = -1;
  atomic_init(&p->stop, false);
  atomic_init(&p->input_done, false);
  atomic_init(&p->frames_done, 0);
  rs_timing_init(&p->t_packet, "decode+assembly/pkt");
  rs_timing_init(&p->t_frame, "processing/frame (stages and sinks)");
  rs_timing_init(&p->t_publish, "publish/frame");
  rs_timing_init(&p->t_latency, "latency/frame (last packet read -> list published)");
  p->line.t0_ns = rs_now_ns();
  if (cfg->background) {
    /* the map must have the model's geometry */
    p->cfg.assembly.columns = cfg->background->cols;
  }
  int rc = rs_stream_init(&p->stream, &cfg->stream);
  if (rc != RS_OK) {
    snprintf(p->input_err, sizeof p->input_err, "%s", p->stream.err);
    return rc;
  }
  /* lossless (analysis) mode: consumer takes every frame in order */
  rc = rs_ring_init(&p->ring, nslots, cfg->lossless, !cfg->lossless);
  if (rc != RS_OK) {
    snprintf(p->input_err, sizeof p->input_err, "ring: %s", rs_strerror(rc));
    return rc;
  }
  if (cfg->labels_out) {
    if (rs_labels_create(&p->labels, cfg->labels_out, "roadscand point labels (1 = background, 2 = noise, 3+ = cluster)") != RS_OK) {
      snprintf(p->input_err, sizeof p->input_err, "--labels-out %s: cannot write", cfg->labels_out);
      rs_ring_deinit(&p->ring);
      return RS_E_IO;
    }
    p->labels_open = true;
  }
  if (cfg->iface)
    rc = rs_capture_open_live(&p->cap, cfg->iface, &cfg->capture);
  else
    rc = rs_capture_open_file(&p->cap, cfg->pcap_path, &cfg->capture);
  if (rc != RS_OK) {
    snprintf(p->input_err, sizeof p->input_err, "%s", p->cap.err);
    rs_ring_deinit(&p->ring);
    if (p->labels_open) rs_labels_finish(&p->labels);
    p->labels_open = false;
    return rc;
  }
  if (cfg->iface) { /* from here the kernel keeps what passes the filter for the packet thread */
    char filter[160];
    rs_capture_filter(&cfg->capture, filter, sizeof filter);
    rs_log(RS_LOG_INFO, "capturing on %s: filter \"%s\", kernel buffer %d KiB", cfg->iface, filter,
           p->cap.buffer_bytes / 1024);
  }
  /* last, so that no failure above leaves them allocated */
  if ((cfg->objects_out && !open_csv(p, &p->objects_out, cfg->objects_out, "--objects-out", rs_pipeline_objects_header())) ||
      (cfg->tracks_out && !open_csv(p, &p->tracks_out, cfg->tracks_out, "--tracks-out", rs_pipeline_tracks_header())) ||
      (cfg->counts_out && !open_csv(p, &p->counts_out, cfg->counts_out, "--counts-out", rs_pipeline_counts_header())) ||
      (cfg->crossings_out &&
       !open_csv(p, &p->crossings_out, cfg->crossings_out, "--crossings-out", rs_pipeline_crossings_header()))) {
    rs_pipeline_deinit(p); /* a failed init releases what it had: the caller does not deinit */
    return RS_E_IO;
  }
  if (p->labels_open) {
    p->label_buf = malloc(sizeof *p->label_buf * RS_LABELS_FRAME_MAX);
    if (p->label_buf == NULL) {
      snprintf(p->input_err, sizeof p->input_err, "out of memory");
      rs_pipeline_deinit(p);
      return RS_E_OOM;
    }
  }
  rs_proc_cfg_t pc = {
      .background = cfg->background,
      .learn_seconds = cfg->learn_seconds,
      .learn_out = cfg->learn_out,
      .update_window_s = cfg->update_window_s,
      .update_every_s = cfg->update_every_s,
      .lossless = cfg->lossless,
      .see_through = cfg->bg_see_through,
      .beyond_foreground = cfg->bg_beyond_foreground,
      .no_behind = cfg->bg_no_behind,
      .no_ground = cfg->no_ground,
      .shift_tol = cfg->bg_shift_tol,
      .shift_gate = cfg->bg_shift_gate,
      .shift_deg = cfg->bg_shift_deg,
      .cluster = cfg->cluster,
      .objects = cfg->objects,
      .object_list = cfg->object_list,
      .tracker = cfg->tracker,
      .counter = cfg->counter,
  };
  rc = rs_proc_init(&p->proc, &pc, p->input_err, sizeof p->input_err);
  if (rc != RS_OK) {
    rs_pipeline_deinit(p);
    return rc;
  }
  return RS_OK;
}

/* live: the kernel's drop counters, once per frame (the handle is the packet thread's); and a copy
 * of the stream's error counters the processing thread may read */
static void poll_kstats(rs_pipeline_t *p) {
  for (int i = 0; i < RS_ERR_COUNT; i++) /* and the error counters, for the statistics message */
    atomic_store_explicit(&p->errors[i], p->stream.n.errors[i], memory_order_relaxed);
  if (rs_capture_kstats(&p->cap))
    atomic_store_explicit(&p->kernel_dropped, p->cap.kstats.dropped + p->cap.kstats.if_dropped, memory_order_relaxed);
}

static void publish_cur(rs_pipeline_t *p) {
  poll_kstats(p);
  rs_slot_t *s = &p->slots[p->cur];
  s->meta.assembled_ns = rs_now_ns();
  s->meta.dropped_frames = rs_ring_dropped(&p->ring);
  rs_ring_publish(&p->ring, p->cur);
  p->cur = rs_ring_acquire(&p->ring, &p->stop);
  if (p->cur < 0 && !atomic_load(&p->stop)) {
    p->input_status = RS_E_NOMEM;
    snprintf(p->input_err, sizeof p->input_err, "no free frame slot");
    atomic_store(&p->stop, true);
  }
}

static void on_packet(void *user, const rs_packet_t *pkt, uint32_t index, double ts) {
  rs_pipeline_t *p = user;
  if (!p->asm_ready) {
    int rc = rs_asm_init(&p->assembly, &p->cfg.assembly, &p->stream.sensor);
    if (rc != RS_OK) {
      p->input_status = rc;
      snprintf(p->input_err, sizeof p->input_err, "frame assembly: %s", rs_strerror(rc));
      atomic_store(&p->stop, true);
      return;
    }
    p->asm_ready = true;
    const rs_bg_model_t *bg = p->cfg.background;
    if (bg && (bg->model != p->stream.sensor.info->model || bg->rows != p->stream.sensor.lasers)) {
      p->input_status = RS_E_INVAL;
      p->model_mismatch = true;
      snprintf(p->input_err, sizeof p->input_err, "the background model is for a %s (%u rows), the sensor is a %s",
               rs_model_name(bg->model), bg->rows, p->stream.sensor.info->name);
      atomic_store(&p->stop, true);
      return;
    }
  }
  /* bounded: every FRAME_DONE resumes at least one block further */
  const int64_t now = rs_now_ns();
  for (int i = 0; i <= RS_BLOCKS && p->cur >= 0; i++) {
    rs_slot_t *s = &p->slots[p->cur];
    rs_asm_result_t r = rs_asm_feed(&p->assembly, s, pkt, index, ts);
    if (s->meta.packets > 0 && s->meta.last_packet == index) s->meta.last_packet_ns = now; /* it contributed */
    if (r == RS_ASM_CONSUMED) break;
    publish_cur(p);
  }
  p->stream.rate_hint = p->assembly.rate;
}

/* a thread placed by its cfg (thread.h) says where it runs, as the kernel has it, before any work */
static void say_placement(const rs_thread_cfg_t *c, const char *what) {
  if (!c->pin && c->priority == 0) return;
  char d[160];
  rs_thread_describe(pthread_self(), d, sizeof d);
  rs_log(RS_LOG_INFO, "%s runs on %s", what, d);
}

static void *packet_main(void *arg) {
  rs_pipeline_t *p = arg;
  say_placement(&p->cfg.packet_thread, "the packet thread");
  p->cur = rs_ring_acquire(&p->ring, &p->stop);
  const int linktype = p->cap.linktype;
  while (!atomic_load(&p->stop) && p->cur >= 0) {
    atomic_store_explicit(&p->pkt_alive_ns, rs_now_ns(), memory_order_relaxed);
    rs_frame_in_t f;
    int rc = rs_capture_next(&p->cap, &f, &p->stop);
    if (rc == 0) continue;
    if (rc == RS_CAPTURE_EOF) break;
    if (rc < 0) {
      rs_stream_count(&p->stream, rc, p->cap.err);
      p->input_status = rc;
      snprintf(p->input_err, sizeof p->input_err, "%s", p->cap.err);
      break;
    }
    int64_t t0 = rs_now_ns();
    uint64_t before = p->stream.n.decoded;
    rc = rs_stream_frame(&p->stream, linktype, &f, on_packet, p);
    if (p->stream.n.decoded != before) rs_timing_add(&p->t_packet, rs_now_ns() - t0);
    if (rc != RS_OK) {
      p->input_status = rc;
      snprintf(p->input_err, sizeof p->input_err, "%s", p->stream.err);
      break;
    }
  }
  if (p->input_status == RS_OK || p->input_status == RS_E_TRUNCATED) {
    rs_stream_finish(&p->stream, on_packet, p);
  }
  poll_kstats(p);
  if (p->cur >= 0) {
    /* end of input: let the consumer take what is queued first, or its
     * skip-to-newest policy would drop the last full frame for the partial
     * one (bounded: 200 x 5 ms) */
    for (int i = 0; i < 200 && rs_ring_queued(&p->ring) > 0 && !p->cfg.lossless; i++) {
      struct timespec d = {0, 5000000L};
      nanosleep(&d, NULL);
    }
    if (p->asm_ready && rs_asm_flush(&p->assembly, &p->slots[p->cur])) {
      p->slots[p->cur].meta.assembled_ns = rs_now_ns();
      p->slots[p->cur].meta.dropped_frames = rs_ring_dropped(&p->ring);
      rs_ring_publish(&p->ring, p->cur);
    } else {
      rs_ring_discard(&p->ring, p->cur);
    }
    p->cur = -1;
  }
  atomic_store(&p->input_done, true);
  sem_post(&p->ring.ready);
  return NULL;
}

/* The service manager's watchdog, fed by the processing thread while it runs
 * and, live, while the packet thread still goes round its loop (it returns
 * from the capture at least every 100 ms): a hang of either stops the feeding
 * and systemd restarts the service. */
static void feed_watchdog(rs_pipeline_t *p) {
  rs_notify_t *n = p->cfg.notify;
  if (n == NULL || n->watchdog_ns <= 0) return;
  const int64_t now = rs_now_ns();
  if (p->cfg.iface && !atomic_load(&p->input_done) &&
      now - atomic_load_explicit(&p->pkt_alive_ns, memory_order_relaxed) > 2 * n->watchdog_ns)
    return;
  rs_notify_watchdog(n, now);
}

/* One log line per summary_s seconds: never one per frame or packet. */
static void maybe_log_line(rs_pipeline_t *p) {
  if (p->cfg.summary_s <= 0) return;
  int64_t now = rs_now_ns();
  double dt = (double)(now - p->line.t0_ns) * 1e-9;
  if (dt < p->cfg.summary_s) return;
  const rs_proc_counters_t *n = &p->proc.n;
  uint64_t frames = n->frames - p->line.frames, objects = n->objects - p->line.objects;
  rs_log(RS_LOG_INFO,
         "last %.0f s: %" PRIu64 " frames (%.1f/s), %" PRIu64 " objects; totals: %" PRIu64 " frames, %" PRIu64
         " dropped, %" PRIu64 " over budget, %" PRIu64 " packets missing, %" PRIu64
         " publish errors; worst stage %s %.2f ms",
         dt, frames, (double)frames / dt, objects, n->frames, rs_ring_dropped(&p->ring), p->overruns,
         n->missing_packets, p->cfg.publish ? p->cfg.publish->errors : 0, p->line.worst ? p->line.worst : "-",
         (double)p->line.worst_ns * 1e-6);
  if (p->cfg.notify) {
    char status[160];
    snprintf(status, sizeof status, "STATUS=%" PRIu64 " frames, %" PRIu64 " dropped, %" PRIu64 " over budget; %.1f frames/s",
             n->frames, rs_ring_dropped(&p->ring), p->overruns, (double)frames / dt);
    rs_notify_send(p->cfg.notify, status);
  }
  p->line.t0_ns = now;
  p->line.frames = n->frames;
  p->line.objects = n->objects;
  p->line.worst_ns = 0;
  p->line.worst = NULL;
}

/* sink: the frame statistics message */
static void publish_stats(rs_pipeline_t *p, const rs_slot_t *s, const rs_proc_report_t *r, int64_t pub_ns,
                          int64_t published_ns, int64_t frame_ns, double budget_ms) {
  const rs_frame_meta_t *m = &s->meta;
  roadscan_frame_stats_t st;
  memset(&st, 0, sizeof st);
  st.utime = rs_publish_utime();
  st.sensor_id = p->cfg.publish->sensor_id;
  st.frame_seq = (int64_t)m->seq;
  st.background_us = (int32_t)(r->stage_ns[RS_STAGE_BACKGROUND] / 1000);
  st.cluster_us = (int32_t)(r->stage_ns[RS_STAGE_CLUSTER] / 1000);
  st.objects_us = (int32_t)(r->stage_ns[RS_STAGE_OBJECTS] / 1000);
  st.tracks_us = (int32_t)(r->stage_ns[RS_STAGE_TRACKS] / 1000);
  st.tracks = r->tracks ? (int32_t)r->tracks->count : 0;
  st.publish_us = (int32_t)(pub_ns / 1000);
  st.processing_us = (int32_t)(frame_ns / 1000);
  st.latency_us = m->last_packet_ns > 0 ? (int32_t)((published_ns - m->last_packet_ns) / 1000) : -1;
  st.points = (int32_t)m->points;
  st.foreground = (int32_t)r->foreground;
  st.clusters = (int32_t)r->cluster.clusters;
  st.noise = (int32_t)r->cluster.noise;
  st.frames_processed = (int64_t)p->proc.n.frames;
  st.frames_dropped = (int64_t)m->dropped_frames;
  st.deadline_overruns = (int64_t)p->overruns;
  st.packets_missing = (int64_t)p->proc.n.missing_packets;
  st.truncated_lists = (int64_t)p->cfg.publish->truncated_lists;
  st.budget_ms = (float)budget_ms;
  st.kernel_dropped = (int64_t)atomic_load_explicit(&p->kernel_dropped, memory_order_relaxed);
  st.capture_buffer_kib = p->cap.live ? (int32_t)(p->cap.buffer_bytes / 1024) : 0;
  st.objects = r->objects ? (int32_t)r->objects->count : 0;
  int16_t k = 0;
  for (int i = 0; i < RS_ERR_COUNT; i++) {
    const uint64_t v = atomic_load_explicit(&p->errors[i], memory_order_relaxed);
    if (v == 0) continue;
    p->err_keys[k] = rs_err_key(rs_err_from_index(i));
    p->err_counts[k++] = (int64_t)v;
  }
  st.num_errors = k;
  const rs_bg_model_t *model = rs_proc_model(&p->proc);
  if (model == NULL) st.model_age_s = -1.0f;
  else if (p->proc.bgu.changed_at > 0) st.model_age_s = (float)(m->t_last - p->proc.bgu.changed_at);
  else st.model_age_s = (float)((double)time(NULL) - (double)model->created);
  st.error_kinds = (char **)p->err_keys;
  st.error_counts = p->err_counts;
  rs_publish_stats(p->cfg.publish, &st);
}

/* sink: the tracks CSV, one line per track alive */
static void write_tracks(FILE *f, const rs_slot_t *s, const rs_track_list_t *tl) {
  for (uint32_t i = 0; i < tl->count; i++) {
    const rs_track_t *t = &tl->track[i];
    if (t->state == RS_TRACK_LOST) continue; /* kept for re-acquisition, not published */
    fprintf(f, "%" PRIu64 ",%.6f,%u,%s,%s,%.3f,%.3f,%.3f,%.3f,%.3f,%.3f,%.4f,%.2f,%.2f,%.2f,%u,%u,%u,%.3f,%.4f,%.4f,%.4f",
            s->meta.seq, t->t_state, t->id, rs_track_state_name(t->state), rs_class_name(t->cls), t->x[0], t->x[1],
            (double)t->z_min, t->vel[0], t->vel[1], (double)t->speed, (double)t->heading, (double)t->length,
            (double)t->width, (double)t->height, t->points, t->hits, t->misses, tl->t - t->t_birth, t->P[0][0],
            t->P[0][1], t->P[1][1]);
    if (tl->site_valid) /* (empty without a pose) */
      fprintf(f, ",%.3f,%.3f,%.3f,%.3f,%.3f,%.4f\n", (double)t->site[0], (double)t->site[1], (double)t->site[2],
              (double)t->site_v[0], (double)t->site_v[1], (double)t->site_heading);
    else
      fputs(",,,,,,\n", f);
  }
}

/* sink: the objects CSV, one line per object of the frame (its id is its cluster's label - 2, as in
 * --labels-out with --no-tracking; t the middle of its returns' capture times; sensor frame, and the
 * site frame's centre and heading with a pose) */
static void write_objects(FILE *f, const rs_slot_t *s, const rs_object_list_t *ol) {
  const uint32_t n = ol->count < RS_OBJ_MAX ? ol->count : RS_OBJ_MAX;
  for (uint32_t k = 0; k < n; k++) {
    const rs_object_t *o = &ol->obj[k];
    const rs_obj_geom_t *g = &o->sensor;
    const double t = rs_object_time(o, s->meta.t_last);
    fprintf(f, "%" PRIu64 ",%.6f,%u,%.3f,%.3f,%.2f,%.2f,%.4f,%.3f,%.3f,%.3f,%.3f,%.3f,%u,%.3f,%u", s->meta.seq, t, o->id,
            (double)g->obb_center[0], (double)g->obb_center[1], (double)g->obb_length, (double)g->obb_width,
            (double)g->obb_heading, (double)g->box_min[2], (double)g->box_max[2], (double)g->centroid[0],
            (double)g->centroid[1], (double)g->centroid[2], o->points, (double)o->range_min, (unsigned)o->occluded);
    if (ol->site_valid)
      fprintf(f, ",%.3f,%.3f,%.4f\n", (double)o->site.obb_center[0], (double)o->site.obb_center[1],
              (double)o->site.obb_heading);
    else
      fputs(",,,\n", f);
  }
}

/* the label each cluster's returns get in --labels-out: 2 + its track's id */
static void track_labels(rs_pipeline_t *p, const rs_proc_report_t *r) {
  const rs_track_list_t *tl = r->tracks;
  const uint32_t n = r->objects->count < RS_OBJ_MAX ? r->objects->count : RS_OBJ_MAX;
  for (uint32_t k = 0; k < n; k++) {
    uint32_t id = tl->object_track[k], lab = 0;
    if (id && p->cfg.labels_confirmed_only) {
      uint32_t lo = 0, hi = tl->count; /* tracks are in id order */
      while (lo < hi) {
        uint32_t mid = (lo + hi) / 2;
        if (tl->track[mid].id < id) lo = mid + 1;
        else hi = mid;
      }
      if (lo == tl->count || tl->track[lo].id != id || tl->track[lo].state == RS_TRACK_TENTATIVE) id = 0;
    }
    if (id) lab = id + RS_LABEL_NOISE < id ? 0 : id + RS_LABEL_NOISE;
    p->label_map[k] = lab;
  }
}

/* sink: the counts of a closed interval: per line and direction every class
 * counted and the sum ("all", also when 0: an empty interval is a figure) */
static void write_counts(FILE *f, const rs_counter_t *c, const rs_count_interval_t *iv) {
  for (int l = 0; l < c->nlines; l++)
    for (int d = 0; d < 2; d++) {
      const uint32_t *v = d == 0 ? iv->line[l].forward : iv->line[l].backward;
      uint32_t sum = 0;
      for (int k = 0; k < RS_CLASS_COUNT; k++) {
        sum += v[k];
        if (v[k])
          fprintf(f, "%.3f,%.3f,%s,%s,%s,%u\n", iv->t_start, iv->t_end, c->lines[l].name, d == 0 ? "forward" : "backward",
                  rs_class_name((rs_class_t)k), v[k]);
      }
      fprintf(f, "%.3f,%.3f,%s,%s,all,%u\n", iv->t_start, iv->t_end, c->lines[l].name, d == 0 ? "forward" : "backward",
              sum);
    }
  /* zones: entered and exited likewise; the most inside at once (class all) */
  for (int z = 0; z < c->nzones; z++) {
    for (int d = 0; d < 2; d++) {
      const uint32_t *v = d == 0 ? iv->zone[z].entered : iv->zone[z].exited;
      uint32_t sum = 0;
      for (int k = 0; k < RS_CLASS_COUNT; k++) {
        sum += v[k];
        if (v[k])
          fprintf(f, "%.3f,%.3f,%s,%s,%s,%u\n", iv->t_start, iv->t_end, c->zones[z].name, d == 0 ? "entered" : "exited",
                  rs_class_name((rs_class_t)k), v[k]);
      }
      fprintf(f, "%.3f,%.3f,%s,%s,all,%u\n", iv->t_start, iv->t_end, c->zones[z].name, d == 0 ? "entered" : "exited",
              sum);
    }
    fprintf(f, "%.3f,%.3f,%s,occupancy_max,all,%u\n", iv->t_start, iv->t_end, c->zones[z].name,
            iv->zone[z].occupancy_max);
  }
}

/* sink: the crossings tallied with a frame, one line each (speed empty when unknown) */
static void write_crossings(FILE *f, const rs_counter_t *c, const rs_count_event_t *e, uint32_t n) {
  for (uint32_t k = 0; k < n; k++) {
    fprintf(f, "%.3f,%s,%s,%.2f,%s,%u,", e[k].t, c->lines[e[k].line].name, e[k].dir > 0 ? "forward" : "backward",
            (double)e[k].at, rs_class_name((rs_class_t)e[k].cls), e[k].track);
    if (e[k].speed >= 0.0f) fprintf(f, "%.2f", (double)e[k].speed);
    fprintf(f, ",%s\n", rs_count_how_name((rs_cross_how_t)e[k].how));
  }
}

static void count_sinks(rs_pipeline_t *p, const rs_proc_report_t *r) {
  if (p->crossings_out && r->ncrossings) write_crossings(p->crossings_out, p->cfg.counter, r->crossings, r->ncrossings);
  if (p->cfg.publish && r->ncrossings)
    rs_publish_crossings(p->cfg.publish, p->cfg.counter, r->crossings, r->ncrossings, rs_publish_utime());
  if (r->counts == NULL) return;
  if (p->cfg.publish) rs_publish_counts(p->cfg.publish, p->cfg.counter, r->counts, rs_publish_utime());
  if (p->counts_out) write_counts(p->counts_out, p->cfg.counter, r->counts);
}

/* sink: one line of the frames CSV */
static void write_frame_line(FILE *f, const rs_slot_t *s, const rs_proc_report_t *r, int64_t frame_ns) {
  const rs_frame_meta_t *m = &s->meta;
  fprintf(f,
          "%" PRIu64 ",%.6f,%.6f,%u,%u,%u,%u,%" PRIu64 ",%u,%u,%u,%u,%u,%d,%u,%u,%.3f,%s,%u,%u,%u,%u,%.3f,%.3f,%.1f,%u"
          ",%u,%d,%u\n",
          m->seq, m->t_first, m->t_last, m->packets, m->points, m->columns, m->missing_packets, m->dropped_frames,
          m->out_of_order, m->duplicates, m->late_points, m->shifted, m->collisions, m->partial ? 1 : 0, m->rows, m->cols,
          (double)m->rate_hz, rs_return_mode_name(m->mode_byte), m->first_packet, m->last_packet, r->filled[0],
          r->filled[1], (double)r->min_range, (double)r->max_range, (double)frame_ns / 1000.0, r->foreground,
          r->cluster.clusters, r->displaced ? 1 : 0, r->shift_evidence);
}

static void process_frame(rs_pipeline_t *p, rs_slot_t *s) {
  const int64_t t0 = rs_now_ns();
  rs_proc_report_t r;
  rs_proc_frame(&p->proc, s, &p->stream.sensor, &r);
  for (int k = 0; k < RS_STAGES; k++)
    if (r.ran[k] && r.stage_ns[k] > p->line.worst_ns) {
      p->line.worst_ns = r.stage_ns[k];
      p->line.worst = rs_proc_stage_name(k);
    }
  int64_t published_ns = 0, pub_ns = 0;
  if (p->cfg.publish) {
    int64_t tp = rs_now_ns();
    rs_publish_objects(p->cfg.publish, &s->meta, r.objects, rs_publish_utime());
    published_ns = rs_now_ns();
    pub_ns = published_ns - tp;
    rs_timing_add(&p->t_publish, pub_ns);
    if (pub_ns > p->line.worst_ns) {
      p->line.worst_ns = pub_ns;
      p->line.worst = p->t_publish.name;
    }
    if (s->meta.last_packet_ns > 0) rs_timing_add(&p->t_latency, published_ns - s->meta.last_packet_ns);
    if (r.tracks) rs_publish_tracks(p->cfg.publish, &s->meta, r.tracks, rs_publish_utime());
  }
  if (p->objects_out && r.objects) write_objects(p->objects_out, s, r.objects);
  if (p->tracks_out && r.tracks) write_tracks(p->tracks_out, s, r.tracks);
  count_sinks(p, &r);
  if (p->labels_open) {
    if (r.tracks) {
      track_labels(p, &r);
      /* a cluster over held tracks: each return its track's id (track ids, held ones confirmed) */
      const rs_labels_cells_t each = {r.divided_cell, r.divided_track, r.divided, RS_LABEL_NOISE};
      rs_labels_write_frame(&p->labels, s, p->label_buf, p->label_map, r.objects->count, &each);
    } else {
      rs_labels_write_frame(&p->labels, s, p->label_buf, NULL, 0, NULL);
    }
  }
  if (p->cfg.stall_ms > 0) { /* the overload tests' slow processing thread */
    const double ms = p->cfg.stall_ms;
    struct timespec d = {(time_t)(ms / 1000.0), (long)(fmod(ms, 1000.0) * 1e6)};
    nanosleep(&d, NULL);
  }
  const int64_t dt = rs_now_ns() - t0;
  rs_timing_add(&p->t_frame, dt);
  const double hz = s->meta.rate_hz > 0 ? s->meta.rate_hz : 10.0;
  /* the default budget is the frame period, in wall-clock time: a replay at --speed X brings frames X times as often */
  const double speed = !p->cfg.iface && p->cfg.capture.speed > 0 ? p->cfg.capture.speed : 1.0;
  const double budget_ms = p->cfg.budget_ms > 0 ? p->cfg.budget_ms : 1000.0 / hz / speed;
  if ((double)dt * 1e-6 > budget_ms) p->overruns++;
  if (p->cfg.publish) publish_stats(p, s, &r, pub_ns, published_ns, dt, budget_ms);
  if (p->cfg.frames_out) {
    write_frame_line(p->cfg.frames_out, s, &r, dt);
    fflush(p->cfg.frames_out); /* a frame's line is there when the frame is done (tail -f, the tests) */
  }
}

static void *proc_main(void *arg) {
  rs_pipeline_t *p = arg;
  say_placement(&p->cfg.processing_thread, "the processing thread");
  for (;;) {
    feed_watchdog(p);
    int idx = rs_ring_take(&p->ring, TAKE_TIMEOUT_MS);
    if (idx < 0) {
      if (atomic_load(&p->input_done)) {
        idx = rs_ring_take(&p->ring, 0);
        if (idx < 0) break;
      } else {
        maybe_log_line(p);
        continue;
      }
    }
    process_frame(p, &p->slots[idx]);
    rs_ring_release(&p->ring, idx);
    atomic_store_explicit(&p->frames_done, p->proc.n.frames, memory_order_release);
    maybe_log_line(p);
  }
  rs_proc_report_t end;
  rs_proc_finish(&p->proc, &end); /* the last counting interval */
  count_sinks(p, &end);
  if (p->cfg.frames_out) fflush(p->cfg.frames_out);
  if (p->counts_out && (fflush(p->counts_out) != 0 || ferror(p->counts_out))) {
    p->input_status = RS_E_IO;
    snprintf(p->input_err, sizeof p->input_err, "--counts-out %s: write failed", p->cfg.counts_out);
  }
  if (p->crossings_out && (fflush(p->crossings_out) != 0 || ferror(p->crossings_out))) {
    p->input_status = RS_E_IO;
    snprintf(p->input_err, sizeof p->input_err, "--crossings-out %s: write failed", p->cfg.crossings_out);
  }
  if (p->objects_out && (fflush(p->objects_out) != 0 || ferror(p->objects_out))) {
    p->input_status = RS_E_IO;
    snprintf(p->input_err, sizeof p->input_err, "--objects-out %s: write failed", p->cfg.objects_out);
  }
  if (p->tracks_out && (fflush(p->tracks_out) != 0 || ferror(p->tracks_out))) {
    p->input_status = RS_E_IO;
    snprintf(p->input_err, sizeof p->input_err, "--tracks-out %s: write failed", p->cfg.tracks_out);
  }
  if (p->labels_open && rs_labels_finish(&p->labels) != RS_OK) {
    p->input_status = RS_E_IO;
    snprintf(p->input_err, sizeof p->input_err, "--labels-out %s: write failed", p->cfg.labels_out);
  }
  p->labels_open = false;
  return NULL;
}

int rs_pipeline_start(rs_pipeline_t *p) {
  /* both placements checked before either thread runs */
  int rc = rs_thread_check(&p->cfg.processing_thread, "the processing thread", p->input_err, sizeof p->input_err);
  if (rc == RS_OK) rc = rs_thread_check(&p->cfg.packet_thread, "the packet thread", p->input_err, sizeof p->input_err);
  if (rc != RS_OK) return rc;
  rc = rs_thread_create(&p->proc_thread, &p->cfg.processing_thread, "the processing thread", proc_main, p, p->input_err,
                        sizeof p->input_err);
  if (rc != RS_OK) return rc;
  rc = rs_thread_create(&p->pkt_thread, &p->cfg.packet_thread, "the packet thread", packet_main, p, p->input_err,
                        sizeof p->input_err);
  if (rc != RS_OK) {
    atomic_store(&p->stop, true);
    atomic_store(&p->input_done, true);
    pthread_join(p->proc_thread, NULL);
    return rc;
  }
  p->threads_started = true;
  return RS_OK;
}

void rs_pipeline_request_stop(rs_pipeline_t *p) { atomic_store(&p->stop, true); }

void rs_pipeline_join(rs_pipeline_t *p) {
  if (!p->threads_started) return;
  pthread_join(p->pkt_thread, NULL);
  pthread_join(p->proc_thread, NULL);
  p->threads_started = false;
}

void rs_pipeline_deinit(rs_pipeline_t *p) {
  rs_proc_deinit(&p->proc);
  if (p->objects_out) fclose(p->objects_out);
  p->objects_out = NULL;
  if (p->tracks_out) fclose(p->tracks_out);
  p->tracks_out = NULL;
  if (p->counts_out) fclose(p->counts_out);
  p->counts_out = NULL;
  if (p->crossings_out) fclose(p->crossings_out);
  p->crossings_out = NULL;
  free(p->label_buf);
  p->label_buf = NULL;
  if (p->labels_open) rs_labels_finish(&p->labels);
  p->labels_open = false;
  rs_capture_close(&p->cap);
  rs_ring_deinit(&p->ring);
}

void rs_pipeline_summary(const rs_pipeline_t *p, FILE *out) {
  const rs_stream_counters_t *n = &p->stream.n;
  const rs_asm_t *a = &p->assembly;
  fprintf(out, "roadscan summary\n");
  fprintf(out, "  source: %s%s\n", p->cfg.iface ? "interface " : "", p->cfg.iface ? p->cfg.iface : p->cfg.pcap_path);
  if (p->cap.jumps)
    fprintf(out, "  replay: %llu jumps in the capture's clock (over %.1f s) sent without waiting; the largest %.3g s\n",
            (unsigned long long)p->cap.jumps, RS_CAPTURE_MAX_GAP_S, p->cap.jump_max);
  if (p->stream.sensor_ready)
    fprintf(out, "  sensor: %s, %.2f Hz, %d x %d map\n", p->stream.sensor.info->name,
            rs_hz_from_rate(p->assembly.rate), p->stream.sensor.lasers, a->cols);
  else
    fprintf(out, "  sensor: not identified (no valid data packet)\n");
  fprintf(out, "  frames: %llu processed (%llu partial), %llu dropped\n", (unsigned long long)p->proc.n.frames,
          (unsigned long long)p->proc.n.partial_frames, (unsigned long long)rs_ring_dropped(&p->ring));
  fprintf(out, "  packets: %llu captured, %llu data (%llu decoded), %llu position, %llu other\n",
          (unsigned long long)n->frames, (unsigned long long)n->data_packets, (unsigned long long)n->decoded,
          (unsigned long long)n->position_packets, (unsigned long long)n->other_packets);
  if (p->cap.live)
    fprintf(out, "  kernel: %llu packets passed the filter, %llu dropped by the kernel (buffer of %d KiB full), %llu by the "
                 "interface\n",
            (unsigned long long)p->cap.kstats.received, (unsigned long long)p->cap.kstats.dropped,
            p->cap.buffer_bytes / 1024, (unsigned long long)p->cap.kstats.if_dropped);
  fprintf(out, "  stream: %llu missing, %llu out of order, %llu duplicate packets; %llu late returns dropped, %llu cell collisions\n",
          (unsigned long long)a->missing_packets, (unsigned long long)a->out_of_order,
          (unsigned long long)a->duplicates, (unsigned long long)a->late_points, (unsigned long long)a->collisions);
  fprintf(out, "  points: %llu\n", (unsigned long long)p->proc.n.points);
  const rs_proc_t *pr = &p->proc;
  const rs_bg_model_t *m = rs_proc_model(pr);
  if (pr->bgu_on && m == NULL) fprintf(out, "  background: none yet (learning the first %.1f s)\n", p->cfg.learn_seconds);
  if (m) {
    size_t cells = (size_t)m->rows * m->cols, changed = 0;
    for (size_t c = 0; c < cells; c++) changed += pr->beyond_cells[c] > pr->n.frames / 2;
    const rs_bgu_t *u = &pr->bgu;
    fprintf(out, "  background model: learned from %u frames%s; ", u->initial_frames,
            p->cfg.background ? " (loaded)" : "");
    if (p->cfg.update_window_s > 0)
      fprintf(out, "kept current from the last %.0f s: %llu updates, %llu not taken, %llu failed", p->cfg.update_window_s,
              (unsigned long long)u->updates, (unsigned long long)u->rejected, (unsigned long long)u->failed);
    else
      fprintf(out, "not updated (--update-minutes 0)");
    if (u->changed_at > 0) {
      char when[64], wall[64];
      time_t c = (time_t)u->changed_at, w = (time_t)u->changed_wall;
      strftime(when, sizeof when, "%Y-%m-%d %H:%M:%S UTC", gmtime(&c));
      strftime(wall, sizeof wall, "%Y-%m-%d %H:%M:%S UTC", gmtime(&w));
      fprintf(out, "; last changed at capture time %s (%s here)", when, wall);
    } else {
      fprintf(out, "; unchanged since start");
    }
    fprintf(out, "\n");
    fprintf(out, "  background: %llu returns background, %llu foreground, %llu beyond the farthest surface",
            (unsigned long long)pr->bg.background, (unsigned long long)pr->bg.foreground,
            (unsigned long long)pr->bg.beyond);
    if (changed > cells / 100)
      fprintf(out, "; in %zu cells more than every other frame: the scene changed, relearn the model", changed);
    fprintf(out, "\n");
    const rs_ground_t *g = rs_proc_ground(pr);
    if (p->cfg.no_ground)
      fprintf(out, "  ground: off (--no-ground): objects' heights from their returns alone\n");
    else if (g) {
      char line[512];
      rs_ground_describe(g, line, sizeof line);
      if (g->valid)
        fprintf(out, "  %s; builds %u, the last %.2f ms\n", line, pr->ground_builds, (double)pr->ground_ns / 1e6);
      else
        fprintf(out, "  %s\n", line);
    }
    if (pr->bg.displaced_frames > 0)
      fprintf(out,
              "  the sensor was displaced against the model in %llu of %llu frames (edges seen from another place; "
              "%llu returns background by --shift-tol, %llu seen behind near objects): was it "
              "knocked, does its mount sway?\n",
              (unsigned long long)pr->bg.displaced_frames, (unsigned long long)pr->n.frames,
              (unsigned long long)pr->bg.shifted, (unsigned long long)pr->bg.behind);
  }
  if (p->cfg.cluster && p->cfg.cluster->cfg.method != RS_CLUSTER_NONE)
    fprintf(out,
            "  clusters: %s, %llu clusters (%.1f per frame), %llu returns clustered, %llu noise, %llu cut at range gaps "
            "(people in file), %llu beyond the cluster cap\n",
            rs_cluster_method_name(p->cfg.cluster->cfg.method), (unsigned long long)pr->n.clusters,
            pr->n.frames ? (double)pr->n.clusters / (double)pr->n.frames : 0.0, (unsigned long long)pr->n.clustered,
            (unsigned long long)pr->n.noise, (unsigned long long)pr->n.splits,
            (unsigned long long)p->cfg.cluster->overflow_total);
  if (p->cfg.tracker) {
    const rs_tracker_t *tr = p->cfg.tracker;
    fprintf(out, "  tracks: %llu born, %llu confirmed, %llu ended, %u alive; %llu frames with clusters shared by tracks, "
                 "%llu split parts absorbed (%llu measured with their track), %llu tracks joined to an older one (%llu out of the blind circle, "
                 "%llu where a hidden vehicle may have got to), %llu frames unseen in unmeasured columns not counted missed (%llu runs of them beyond "
                 "%d in a frame left out), %llu beyond "
                 "the %d-track capacity, "
                 "%llu groups assigned greedily, %llu tracks of exactly solved groups left without an object; %llu returns of shared clusters divided between their tracks (%llu beyond "
                 "%d per frame, %llu tracks beyond %d in one cluster, left with the others); %llu born from few returns far off (%llu "
                 "objects beyond %d in a frame not looked at); %llu predictions of hidden vehicles held behind the vehicle ahead\n",
            (unsigned long long)tr->n.born, (unsigned long long)tr->n.confirmed, (unsigned long long)tr->n.ended,
            tr->list.count, (unsigned long long)tr->n.held, (unsigned long long)tr->n.absorbed, (unsigned long long)tr->n.merged,
            (unsigned long long)(tr->n.stitched + tr->n.duplicates + tr->n.blind_linked),
            (unsigned long long)tr->n.blind_linked, (unsigned long long)tr->n.kin_stitched, (unsigned long long)tr->n.gap_unseen,
            (unsigned long long)tr->n.gap_runs_dropped, RS_OBJ_GAPS_MAX,
            (unsigned long long)tr->n.overflow, RS_TRACK_MAX, (unsigned long long)tr->n.greedy_groups,
            (unsigned long long)tr->n.miss_left, (unsigned long long)pr->n.divided, (unsigned long long)pr->n.divided_overflow, RS_PROC_DIVIDED_MAX,
            (unsigned long long)tr->n.hold_overflow, RS_TRACK_HOLD_MAX, (unsigned long long)tr->n.far_born,
            (unsigned long long)tr->n.far_dropped, RS_TRACK_FAR_BIRTHS_MAX, (unsigned long long)tr->n.queued);
  }
  if (p->cfg.counter) {
    const rs_counter_t *c = p->cfg.counter;
    fprintf(out, "  counts (%llu intervals of %.0f s):", (unsigned long long)c->intervals, c->interval_s);
    for (int l = 0; l < c->nlines; l++) {
      for (int d = 0; d < 2; d++) {
        const uint32_t *v = d == 0 ? c->total[l].forward : c->total[l].backward;
        uint32_t sum = 0;
        for (int k = 0; k < RS_CLASS_COUNT; k++) sum += v[k];
        fprintf(out, "%s %s %s %u", l || d ? ";" : "", c->lines[l].name, d == 0 ? "forward" : "backward", sum);
        bool any = false;
        for (int k = 0; k < RS_CLASS_COUNT; k++)
          if (v[k]) {
            fprintf(out, "%s%s %u", any ? ", " : " (", rs_class_name((rs_class_t)k), v[k]);
            any = true;
          }
        if (any) fprintf(out, ")");
      }
    }
    for (int z = 0; z < c->nzones; z++) {
      uint32_t in = 0, out_n = 0;
      for (int k = 0; k < RS_CLASS_COUNT; k++) {
        in += c->zone_total[z].entered[k];
        out_n += c->zone_total[z].exited[k];
      }
      fprintf(out, "%s zone %s entered %u, exited %u, inside now %u (at most %u)", c->nlines || z ? ";" : "",
              c->zones[z].name, in, out_n, c->zone_total[z].occupancy, c->zone_total[z].occupancy_max);
    }
    if (c->nlines)
      fprintf(out,
              "; of the crossings %llu hidden (tracks first seen past a line; %llu more were the same vehicle's, %llu more "
              "taken back: the track stood still, %llu taken back: it went the other way), "
              "%llu on a prediction (the track unseen; %llu more taken back: seen again before the line; %llu more "
              "were the same vehicle's, %llu taken back: another track seen crossing there, --count-unseen-yield); %llu not "
              "counted: a second track of a vehicle counted (--count-same); %llu "
              "taken back: the track seen back before the line (--count-band), %llu a walker's back over a line it "
              "had crossed (%llu of them before that crossing was tallied)",
              (unsigned long long)c->hidden, (unsigned long long)c->hidden_dup, (unsigned long long)c->hidden_still,
              (unsigned long long)c->hidden_reversed,
              (unsigned long long)c->unseen,
              (unsigned long long)c->unseen_undone, (unsigned long long)c->unseen_dup, (unsigned long long)c->unseen_yielded,
              (unsigned long long)c->same_dup,
              (unsigned long long)c->back_undone, (unsigned long long)c->walked_back, (unsigned long long)c->walked_early);
    if (c->pending)
      fprintf(out, "; %llu more found, tallied once their class settles (--count-class-delay)", (unsigned long long)c->pending);
    if (c->events_lost)
      fprintf(out, "; %llu crossings without an event (--crossings-out: more than %d waiting or %d in a frame)",
              (unsigned long long)c->events_lost, RS_COUNT_OPEN_MAX, RS_COUNT_EVENTS_MAX);
    fprintf(out, "\n");
  }
  if (p->cfg.publish) {
    const rs_publish_t *pub = p->cfg.publish;
    fprintf(out, "  lcm: %llu object lists on %s, %llu statistics%s%s, %s; %llu truncated (%llu objects beyond %u), %llu errors\n",
            (unsigned long long)pub->lists, pub->channel, (unsigned long long)pub->stats,
            pub->stats_channel[0] ? " on " : "", pub->stats_channel, pub->url, (unsigned long long)pub->truncated_lists,
            (unsigned long long)pub->objects_dropped, pub->cap, (unsigned long long)pub->errors);
    if (p->cfg.tracker)
      fprintf(out, "  lcm: %llu track lists on %s (%llu truncated to %u), %llu track ends on %s\n",
              (unsigned long long)pub->track_lists, pub->tracks_channel[0] ? pub->tracks_channel : "(none)",
              (unsigned long long)pub->truncated_track_lists, pub->track_cap, (unsigned long long)pub->track_ends,
              pub->ends_channel[0] ? pub->ends_channel : "(none)");
    if (p->cfg.counter && p->cfg.counter->nlines)
      fprintf(out, "  lcm: %llu counts on %s, %llu crossings on %s\n", (unsigned long long)pub->counts,
              pub->counts_channel[0] ? pub->counts_channel : "(none)", (unsigned long long)pub->crossings,
              pub->crossings_channel[0] ? pub->crossings_channel : "(none)");
  }
  fprintf(out, "  deadline: %llu of %llu frames over budget (",
          (unsigned long long)p->overruns, (unsigned long long)pr->n.frames);
  if (p->cfg.budget_ms > 0)
    fprintf(out, "%.1f ms)\n", p->cfg.budget_ms);
  else if (!p->cfg.iface && p->cfg.capture.speed > 0 && p->cfg.capture.speed != 1.0)
    fprintf(out, "the frame period / %g: the replay's speed)\n", p->cfg.capture.speed);
  else
    fprintf(out, "the frame period)\n");
  if (p->cfg.labels_out && p->labels.rejected)
    fprintf(out, "  labels-out: %llu lines written, %llu not written (address behind an earlier one: packets out of order)\n",
            (unsigned long long)p->labels.written, (unsigned long long)p->labels.rejected);
  fprintf(out, "  errors: ");
  rs_stream_print_errors(n, out);
  fprintf(out, "\n  timings (CLOCK_MONOTONIC):\n");
  rs_timing_print(&p->t_packet, out);
  for (int k = 0; k < RS_STAGES; k++)
    if (pr->t_stage[k].n) rs_timing_print(&pr->t_stage[k], out);
  if (p->t_publish.n) rs_timing_print(&p->t_publish, out);
  rs_timing_print(&p->t_frame, out);
  if (p->t_latency.n) rs_timing_print(&p->t_latency, out);
}

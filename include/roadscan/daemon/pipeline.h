/* pipeline.h - the daemon's two threads and what connects them.
 *
 * Packet thread: capture -> stream (parse, detect, decode) -> frame assembly
 * into the slot it owns -> ring. Processing thread: takes complete frames,
 * subtracts the background, clusters, extracts objects, publishes the
 * object list and the frame statistics over LCM, writes the frames CSV,
 * releases the slot. Each frame has a time budget (default: the frame
 * period); overruns are counted, and the ring hands the processing thread
 * the newest frame, so a late frame never delays the next one. Slots are the
 * caller's (statically allocated by the program). After start-up nothing
 * allocates on either thread; the static scene is learned and kept current
 * by a third, low-priority thread (bgupdate.h) that hands models over at a
 * frame boundary. Counters are written by their own thread and read by the
 * caller after rs_pipeline_join. */
#ifndef ROADSCAN_PIPELINE_H
#define ROADSCAN_PIPELINE_H

#include "roadscan/perception/background.h"
#include "roadscan/perception/bgupdate.h"
#include "roadscan/capture/capture.h"
#include "roadscan/perception/cluster.h"
#include "roadscan/daemon/notify.h"
#include "roadscan/frame/frame.h"
#include "roadscan/output/labels.h"
#include "roadscan/perception/objects.h"
#include "roadscan/perception/proc.h"
#include "roadscan/output/publish.h"
#include "roadscan/frame/ring.h"
#include "roadscan/capture/stream.h"
#include "roadscan/util/thread.h"
#include "roadscan/util/timing.h"

#include <pthread.h>
#include <stdatomic.h>
#include <stdio.h>

typedef struct {
  const char *pcap_path;       /* offline source, or */
  const char *iface;           /* live source */
  rs_capture_cfg_t capture;    /* speed 0 = flat out */
  bool lossless;               /* flat-out analysis: never drop a frame */
  rs_stream_cfg_t stream;
  rs_asm_cfg_t assembly;
  FILE *frames_out;            /* optional CSV, one line per frame */
  const char *labels_out;      /* optional point-label file of the pipeline's decisions */
  rs_bg_model_t *background;   /* optional static-scene model (processing thread) */
  int bg_see_through;          /* 0: the model's own see_through (RS_BG_SEE_THROUGH); N > 0: N; < 0: off */
  bool bg_beyond_foreground;   /* returns beyond the farthest surface are foreground (default: background) */
  bool bg_no_behind;         /* displaced frames: no surface continued past a near object */
  bool no_ground;             /* no ground from the model (rs_proc_cfg_t.no_ground) */
  double bg_shift_tol;         /* a displaced sensor (background.h): 0 = RS_BG_SHIFT_TOL, < 0 = off */
  double bg_shift_gate;        /* share of a frame's returns, 0 = RS_BG_SHIFT_GATE, < 0 = no gate */
  double bg_shift_deg;         /* 0 = RS_BG_SHIFT_DEG, < 0 = none */
  double learn_seconds;        /* > 0 and no model: learn from the first seconds, then subtract */
  const char *learn_out;       /* where the learned model is saved */
  double update_window_s;      /* > 0: keep the model current from the last window (bgupdate.h) */
  double update_every_s;       /* relearn every (0: the updater's default, 60 s) */
  rs_cluster_t *cluster;       /* optional: clustering work area, configured (processing thread) */
  rs_objects_t *objects;       /* optional with cluster: object work area (rs_objects_init done) */
  rs_object_list_t *object_list; /* required with objects: the frame's objects */
  rs_tracker_t *tracker;       /* optional with objects: rs_track_init done */
  const char *objects_out;     /* optional CSV (with objects), one line per object per frame */
  const char *tracks_out;      /* optional CSV, one line per track per frame */
  rs_counter_t *counter;       /* optional with tracker: counting lines (rs_count_init done) */
  const char *counts_out;      /* optional CSV, the counts of every closed interval */
  const char *crossings_out;   /* optional CSV, one line per crossing tallied (count.h's events) */
  bool labels_confirmed_only;  /* with a tracker: only confirmed tracks' returns are objects in labels_out */
  rs_publish_t *publish;       /* optional: LCM publisher (rs_publish_init done) */
  double budget_ms;            /* per-frame processing budget; 0 = the frame period */
  double summary_s;            /* > 0: one log line every summary_s seconds */
  double stall_ms;             /* test hook (overload tests): the processing thread sleeps this long per frame */
  rs_notify_t *notify;         /* optional: the service manager (watchdog fed by the processing thread) */
  rs_thread_cfg_t packet_thread, processing_thread; /* where each runs and at what priority (thread.h;
                                                      zero: anywhere, normally scheduled) */
} rs_pipeline_cfg_t;

typedef struct {
  rs_pipeline_cfg_t cfg;
  rs_capture_t cap;
  rs_stream_t stream;
  rs_asm_t assembly;
  bool asm_ready;
  rs_ring_t ring;
  rs_slot_t *slots;
  int cur;                     /* slot being filled, -1 none */
  pthread_t pkt_thread, proc_thread;
  bool threads_started;
  _Atomic bool stop;
  _Atomic bool input_done;
  _Atomic uint64_t frames_done; /* frames processed so far (any thread may read it) */
  _Atomic int64_t pkt_alive_ns; /* the packet thread's last loop (CLOCK_MONOTONIC), for the watchdog */
  _Atomic uint64_t kernel_dropped; /* live: packets the kernel or the interface dropped (packet thread, per frame) */
  _Atomic uint64_t errors[RS_ERR_COUNT]; /* the stream's error counters, copied per frame (packet thread) */
  const char *err_keys[RS_ERR_COUNT];   /* the statistics message's error arrays (processing thread) */
  int64_t err_counts[RS_ERR_COUNT];
  int input_status;            /* RS_OK, or why the input ended badly */
  bool model_mismatch;         /* the background model is not the sensor's (input_status RS_E_INVAL) */
  char input_err[RS_ERRMSG_SIZE];
  rs_timing_t t_packet;        /* decode + assembly per data packet (packet thread) */
  /* processing thread: the stages (proc.h), then the sinks */
  rs_proc_t proc;
  rs_timing_t t_frame;         /* stages and sinks per frame */
  rs_timing_t t_publish;       /* encoding + lcm_publish per frame */
  rs_timing_t t_latency;       /* frame complete -> object list published */
  uint64_t overruns;           /* frames over budget (stages and sinks) */
  struct {                     /* the periodic log line (processing thread) */
    int64_t t0_ns;
    uint64_t frames, objects;
    int64_t worst_ns;
    const char *worst;
  } line;
  rs_labels_writer_t labels;   /* the --labels-out sink */
  rs_label_entry_t *label_buf; /* its sort area (allocated at init) */
  bool labels_open;
  uint32_t label_map[RS_OBJ_MAX]; /* cluster k -> the label written (tracks) */
  FILE *objects_out;           /* the --objects-out sink */
  FILE *tracks_out;            /* the --tracks-out sink */
  FILE *counts_out;            /* the --counts-out sink */
  FILE *crossings_out;         /* the --crossings-out sink */
} rs_pipeline_t;

/* Opens the source; slots: nslots (3..RS_RING_MAX_SLOTS) caller-owned slots.
 * Returns RS_OK or a negative code with p->input_err set. */
int rs_pipeline_init(rs_pipeline_t *p, const rs_pipeline_cfg_t *cfg, rs_slot_t *slots, int nslots);
/* Starts both threads, each placed as its cfg says (packet_thread, processing_thread).
 * RS_OK, or a negative code with p->input_err naming the problem (neither runs then). */
int rs_pipeline_start(rs_pipeline_t *p);
/* Asks both threads to stop (async-signal-safe: an atomic store). */
void rs_pipeline_request_stop(rs_pipeline_t *p);
/* Waits for the input to end (or a stop) and for every queued frame to be processed. */
void rs_pipeline_join(rs_pipeline_t *p);
void rs_pipeline_deinit(rs_pipeline_t *p);
/* Human-readable summary (frames, packets, drops, errors by kind, timings). */
void rs_pipeline_summary(const rs_pipeline_t *p, FILE *out);
/* The frames CSV header (one line, no newline). */
const char *rs_pipeline_csv_header(void);
/* The counts CSV header (one line, no newline). */
const char *rs_pipeline_counts_header(void);
const char *rs_pipeline_crossings_header(void);
/* The tracks CSV header (one line, no newline). */
const char *rs_pipeline_tracks_header(void);
/* the --objects-out CSV's header line (no newline) */
const char *rs_pipeline_objects_header(void);

#endif

/* frame.c - frame assembly (pure state machine, owned by the packet thread).
 *
 * Roll-over: the block azimuth, taken relative to the cut azimuth, drops by
 * more than 180 degrees from one block to the next (across packets). A
 * smaller backwards step is a packet out of order: its points are kept in
 * the current frame (they address cells by azimuth) but it does not move
 * the frame's azimuth. A forward jump of more than 180 degrees is a late
 * packet of the previous (already published) frame: its returns are
 * dropped and counted, unless three come in a row, which means the stream
 * really jumped (then it is accepted and the gap counted as missing).
 *
 * The sensor's own timestamp (microseconds past the hour) settles what the
 * azimuth alone cannot: a packet older than the last one taken (by less
 * than a second) is behind it, never a roll-over into the next turn: one
 * delivered half a turn late is late, not a new frame. Duplicates are
 * recognised by timestamp and azimuth over the last RS_DUP_HISTORY packets,
 * looked for only when a packet is not newer than the newest seen. */
#include "roadscan/frame/frame.h"

#include "roadscan/util/error.h"

#include <math.h>
#include <string.h>

#define HALF_TURN_CD 18000
#define TURN_CD 36000
#define LATE_STREAK_RESYNC 3
#define HOUR_US 3600000000u
#define TS_PLAUSIBLE_US 1000000 /* sensor clocks within a second of each other: comparable */

/* b - a in microseconds past the hour, wrapped to (-30 min, 30 min] */
static int64_t ts_diff(uint32_t a, uint32_t b) {
  int64_t d = ((int64_t)b - (int64_t)a) % (int64_t)HOUR_US;
  if (d > (int64_t)HOUR_US / 2) d -= HOUR_US;
  if (d <= -(int64_t)HOUR_US / 2) d += HOUR_US;
  return d;
}

int rs_frame_columns_for(const rs_model_info_t *mi, double hz) {
  if (hz <= 0.0) hz = 10.0;
  /* 0.5 % headroom: the measured rate jitters, and two firings in one bin lose one */
  double firings = 1.005e6 / (hz * (double)mi->cycle_us);
  int cols = (int)ceil(firings / 10.0 - 1e-9) * 10;
  if (cols < RS_MIN_COLS) cols = RS_MIN_COLS;
  if (cols > RS_MAX_COLS) cols = RS_MAX_COLS;
  return cols;
}

int rs_asm_init(rs_asm_t *a, const rs_asm_cfg_t *cfg, const rs_sensor_t *s) {
  if (cfg->columns != 0 && (cfg->columns < RS_MIN_COLS || cfg->columns > RS_MAX_COLS)) return RS_E_INVAL;
  if (!(cfg->cut_deg >= 0.0 && cfg->cut_deg < 360.0)) return RS_E_INVAL;
  if (s == NULL || s->info == NULL || s->lasers > RS_MAX_ROWS) return RS_E_INVAL;
  memset(a, 0, sizeof *a);
  a->cfg = *cfg;
  if (a->cfg.default_hz <= 0.0) a->cfg.default_hz = 10.0;
  a->sensor = s;
  a->cut_cd = (int)lround(cfg->cut_deg * 100.0) % TURN_CD;
  a->rate = rs_rate_from_hz(a->cfg.default_hz);
  a->last_rel = -1;
  a->resume_block = -1;
  return RS_OK;
}

/* Block azimuth relative to the cut. The raw field is used as is (36000
 * stays the last value of a turn), as specs/point-labels.md defines frames. */
static int32_t rel_of(int cut_cd, uint16_t az) {
  int32_t r = (int32_t)az - cut_cd;
  return r < 0 ? r + TURN_CD : r;
}

bool rs_frame_rollover(int cut_cd, int32_t *last_rel, uint16_t az_cd) {
  int32_t rel = rel_of(cut_cd, az_cd);
  bool roll = *last_rel >= 0 && rel - *last_rel < -HALF_TURN_CD;
  *last_rel = rel;
  return roll;
}

static void open_slot(rs_asm_t *a, rs_slot_t *slot) {
  const int rows = a->sensor->lasers, cols = a->cols;
  memset(&slot->meta, 0, sizeof slot->meta);
  slot->meta.seq = a->next_seq++;
  slot->meta.model = a->sensor->info->model;
  slot->meta.rows = (uint16_t)rows;
  slot->meta.cols = (uint16_t)cols;
  slot->meta.partial = slot->meta.seq == 0;
  memset(slot->colmask, 0, (size_t)cols);
  memset(slot->gap, 1, (size_t)cols); /* until a block's firings fall there (cover) */
  for (int l = 0; l < RS_LAYERS; l++) {
    memset(slot->range + (size_t)l * RS_MAX_CELLS, 0, sizeof(float) * (size_t)rows * (size_t)cols);
    memset(slot->label + (size_t)l * RS_MAX_CELLS, 0, sizeof(uint16_t) * (size_t)rows * (size_t)cols);
  }
  a->slot_open = true;
  a->counted_packet = false;
}

/* the columns a block's firings fall in, by its azimuth: from its own for the group's firing time at
 * the packet's rate, and half that again (the next block's azimuth jitters), at most COVER_MAX */
#define COVER_MAX 64
static void cover(const rs_asm_t *a, rs_slot_t *slot, const rs_packet_t *pkt, uint16_t az_cd) {
  const int cols = a->cols;
  const double w = 360.0 / cols, span = 1.5 * rs_model_group_us(a->sensor->info) * (double)pkt->az_rate;
  int c = (int)((double)az_cd / 100.0 / w);
  int n = (span > 0.0 && isfinite(span)) ? (int)ceil(span / w) + 1 : 1;
  if (n > COVER_MAX) n = COVER_MAX;
  for (int k = 0; k < n; k++) slot->gap[((c + k) % cols + cols) % cols] = 0;
}

static void count_packet(rs_asm_t *a, rs_slot_t *slot, const rs_packet_t *pkt, uint32_t index, double ts, uint16_t az) {
  if (a->counted_packet) return;
  rs_frame_meta_t *m = &slot->meta;
  if (m->packets == 0) {
    m->t_first = ts;
    m->first_packet = index;
    m->first_azimuth = az;
  }
  m->t_last = ts;
  m->last_packet = index;
  m->mode_byte = pkt->mode_byte;
  m->packets++;
  a->counted_packet = true;
}

static void write_point(rs_asm_t *a, rs_slot_t *slot, const rs_point_t *pt, uint32_t index) {
  if (pt->return_type == RS_RET_DUAL_SAME) return; /* the same return as layer 0 */
  const int cols = a->cols;
  int col = (int)(pt->azimuth * (float)cols / 360.0f);
  if (col >= cols) col -= cols;
  if (col < 0) col = 0;
  const uint32_t row0 = (uint32_t)pt->layer * RS_MAX_CELLS + (uint32_t)pt->row * (uint32_t)cols;
  uint32_t i = row0 + (uint32_t)col;
  rs_frame_meta_t *m = &slot->meta;
  if (slot->range[i] != 0.0f) {
    /* azimuth jitter put two firings in one bin: the neighbour on the side
     * the point leans to is usually free */
    float frac = pt->azimuth * (float)cols / 360.0f - (float)col;
    int alt = frac >= 0.5f ? (col + 1 == cols ? 0 : col + 1) : (col == 0 ? cols - 1 : col - 1);
    if (slot->range[row0 + (uint32_t)alt] == 0.0f) {
      col = alt;
      i = row0 + (uint32_t)alt;
      m->shifted++;
      m->points++;
    } else {
      m->collisions++;
      a->collisions++;
      if (pt->distance >= slot->range[i]) return;
    }
  } else {
    m->points++;
  }
  slot->range[i] = pt->distance;
  slot->intensity[i] = pt->intensity;
  slot->addr[i].packet = index;
  slot->addr[i].block = pt->block;
  slot->addr[i].channel = pt->channel;
  if (!slot->colmask[col]) {
    slot->colmask[col] = 1;
    m->columns++;
  }
}

static bool seen_before(rs_asm_t *a, const rs_packet_t *pkt) {
  const uint32_t ts = pkt->timestamp_us;
  const bool newer = a->have_newest && ts_diff(a->newest_ts, ts) > 0;
  if (!newer) { /* a duplicate is never newer than the newest packet: look back */
    for (int k = 1; k <= a->recent_n; k++) {
      const int i = (a->recent_i - k + RS_DUP_HISTORY) % RS_DUP_HISTORY;
      if (a->recent[i].ts != ts || a->recent[i].az != pkt->block_azimuth[0]) continue;
      /* a sensor that sends no timestamps (all 0) repeats an azimuth every turn: only near ones count */
      if (ts != 0 || k <= RS_DUP_NEAR) return true;
    }
  }
  if (!a->have_newest || newer) {
    a->newest_ts = ts;
    a->have_newest = true;
  }
  a->recent[a->recent_i].ts = ts;
  a->recent[a->recent_i].az = pkt->block_azimuth[0];
  a->recent_i = (a->recent_i + 1) % RS_DUP_HISTORY;
  if (a->recent_n < RS_DUP_HISTORY) a->recent_n++;
  return false;
}

/* Classifies a fresh packet against the stream position. */
typedef enum { PKT_IN_ORDER, PKT_BEHIND, PKT_LATE } pkt_order_t;

static pkt_order_t classify(rs_asm_t *a, const rs_packet_t *pkt, uint32_t *missing) {
  *missing = 0;
  if (a->last_rel < 0) return PKT_IN_ORDER;
  int32_t rel0 = rel_of(a->cut_cd, pkt->block_azimuth[0]);
  int32_t d = rel0 - a->last_rel;
  if (d < 0 && d >= -HALF_TURN_CD) return PKT_BEHIND;
  if (d > HALF_TURN_CD && a->late_streak + 1 < LATE_STREAK_RESYNC) return PKT_LATE;
  /* older than the last packet taken, by the sensor's clock: not a roll-over
   * into the next turn (nor a step ahead) but a packet of the turn before */
  if (a->have_last_ts && a->late_streak + 1 < LATE_STREAK_RESYNC) {
    const int64_t dt = ts_diff(a->last_ts, pkt->timestamp_us);
    if (dt < 0 && dt > -TS_PLAUSIBLE_US) return PKT_LATE;
  }
  /* in order (possibly across the cut): judge missing packets from the gap */
  int32_t gap = (d + TURN_CD) % TURN_CD;
  const rs_model_info_t *mi = a->sensor->info;
  double step = (double)a->rate * rs_model_group_us(mi) * 100.0; /* cd per azimuth group */
  if (step > 0.0 && gap > 1.5 * step && pkt->groups > 0) {
    double m = ((double)gap - step) / ((double)pkt->groups * step);
    *missing = (uint32_t)lround(m);
  }
  return PKT_IN_ORDER;
}

rs_asm_result_t rs_asm_feed(rs_asm_t *a, rs_slot_t *slot, const rs_packet_t *pkt, uint32_t index,
                            double cap_ts) {
  if (a->cols == 0) {
    double hz = pkt->az_rate_measured ? rs_hz_from_rate(pkt->az_rate) : a->cfg.default_hz;
    a->cols = a->cfg.columns ? a->cfg.columns : rs_frame_columns_for(a->sensor->info, hz);
  }
  if (!a->slot_open) open_slot(a, slot);

  const bool resuming = a->resume_block >= 0;
  bool behind = false;
  if (!resuming) {
    for (int b = 0; b < RS_BLOCKS; b++) a->block_seq[b] = RS_ASM_DROPPED;
    if (seen_before(a, pkt)) {
      slot->meta.duplicates++;
      a->duplicates++;
      return RS_ASM_CONSUMED;
    }
    uint32_t missing = 0;
    pkt_order_t order = classify(a, pkt, &missing);
    if (order == PKT_LATE) {
      a->late_streak++;
      slot->meta.out_of_order++;
      slot->meta.late_points += pkt->n_points;
      a->out_of_order++;
      a->late_points += pkt->n_points;
      return RS_ASM_CONSUMED;
    }
    a->late_streak = 0;
    if (order == PKT_IN_ORDER) {
      a->last_ts = pkt->timestamp_us;
      a->have_last_ts = true;
    }
    if (order == PKT_BEHIND) {
      behind = true;
      slot->meta.out_of_order++;
      a->out_of_order++;
      /* the gap its successor left was counted as missing: it turned up */
      if (slot->meta.missing_packets > 0) {
        slot->meta.missing_packets--;
        a->missing_packets--;
      }
    }
    a->pending_missing = missing;
    if (pkt->az_rate_measured) {
      a->rate = a->rate_known ? 0.95f * a->rate + 0.05f * pkt->az_rate : pkt->az_rate;
      a->rate_known = true;
    }
  }

  const int start = resuming ? a->resume_block : 0;
  a->resume_block = -1;
  int pi = 0;
  while (pi < pkt->n_points && pkt->points[pi].block < start) pi++;
  for (int b = start; b < pkt->blocks; b++) {
    const uint16_t az = pkt->block_azimuth[b];
    if (!behind) {
      int32_t last = a->last_rel;
      bool roll = rs_frame_rollover(a->cut_cd, &a->last_rel, az);
      if (roll && !(resuming && b == start) && slot->meta.packets > 0) {
        a->last_rel = last; /* re-evaluated (and skipped) when resumed */
        slot->meta.rate_hz = (float)rs_hz_from_rate(a->rate);
        a->slot_open = false;
        a->resume_block = b;
        if (!a->cols_fixed) {
          /* frame 0 (partial) used the first packet's rate; from frame 1 on
           * the columns follow the rate measured over all of frame 0 */
          a->cols_fixed = true;
          if (!a->cfg.columns) a->cols = rs_frame_columns_for(a->sensor->info, rs_hz_from_rate(a->rate));
        }
        a->frames++;
        return RS_ASM_FRAME_DONE;
      }
    }
    if (b == start) {
      count_packet(a, slot, pkt, index, cap_ts, az);
      slot->meta.missing_packets += a->pending_missing;
      a->missing_packets += a->pending_missing;
      a->pending_missing = 0;
    }
    a->block_seq[b] = slot->meta.seq;
    cover(a, slot, pkt, az);
    while (pi < pkt->n_points && pkt->points[pi].block == b) write_point(a, slot, &pkt->points[pi++], index);
  }
  a->counted_packet = false;
  return RS_ASM_CONSUMED;
}

bool rs_asm_flush(rs_asm_t *a, rs_slot_t *slot) {
  if (!a->slot_open) return false;
  a->slot_open = false;
  if (slot->meta.packets == 0) {
    a->next_seq--; /* nothing was written: the number is reused */
    return false;
  }
  slot->meta.partial = true;
  slot->meta.rate_hz = (float)rs_hz_from_rate(a->rate);
  a->frames++;
  return true;
}

// roadscan live view: the events of roadscan-web (/events, Server-Sent Events: the JSON documents of
// docs/bridge-schema.json) drawn as a bird's-eye view, counts, crossings, health and plots. No library, nothing
// from the network. Units: metres, metres per second, degrees, milliseconds, as the schema says.
"use strict";

const CLASSES = ["unknown", "pedestrian", "cyclist", "car", "van/truck", "bus"];
const COLOURS = { unknown: "#b0b8c0", pedestrian: "#ff6b6b", cyclist: "#f7b801", car: "#4cc9f0",
                  "van/truck": "#90be6d", bus: "#c77dff" };
const STAGES = ["background_ms", "cluster_ms", "objects_ms", "tracks_ms", "publish_ms", "processing_ms"];
const TRAIL = 40;        // positions kept per track
const WINDOW = 600;      // frames for the p99 of stage times
const HISTORY_S = 300;   // seconds of the plot
const CROSSINGS_SHOWN = 12; // the last crossings listed
const MARK_S = 4;        // seconds of sensor time a crossing stays marked on its line

const view = document.getElementById("view"), ctx = view.getContext("2d");
const plot = document.getElementById("plot"), pctx = plot.getContext("2d");
const $ = (id) => document.getElementById(id);

const state = {
  config: { lines: [], zones: [] },
  tracks: [], trails: new Map(), ended: 0,
  counts: new Map(),     // name -> {kind: "line"|"zone", a: {class: n}, b: {class: n}}
  crossings: [],         // the last CROSSINGS_SHOWN crossing events, newest first
  crossingsSeen: 0,
  frameT: 0,             // the last track list's capture time (s)
  countsTotal: 0,
  stats: null, statsAt: 0, frameTimes: [], stageHist: new Map(),
  history: [],           // {t, speed, count}
  bucket: { t: 0, count: 0 },
  cam: { x: 0, y: 0, scale: 8 }, // metres at the centre, pixels per metre
};

// ---- the view ---------------------------------------------------------------------------
function toScreen(x, y) {
  return [view.width / 2 + (x - state.cam.x) * state.cam.scale, view.height / 2 - (y - state.cam.y) * state.cam.scale];
}

function drawGrid() {
  const s = state.cam.scale, step = s > 12 ? 5 : s > 4 ? 10 : 50;
  ctx.strokeStyle = "#1d242c";
  ctx.lineWidth = 1;
  ctx.font = "11px system-ui";
  ctx.fillStyle = "#55616d";
  const x0 = state.cam.x - view.width / 2 / s, x1 = state.cam.x + view.width / 2 / s;
  const y0 = state.cam.y - view.height / 2 / s, y1 = state.cam.y + view.height / 2 / s;
  for (let x = Math.ceil(x0 / step) * step; x <= x1; x += step) {
    const [px] = toScreen(x, 0);
    ctx.beginPath(); ctx.moveTo(px, 0); ctx.lineTo(px, view.height); ctx.stroke();
    ctx.fillText(`${x} m`, px + 2, view.height - 4);
  }
  for (let y = Math.ceil(y0 / step) * step; y <= y1; y += step) {
    const [, py] = toScreen(0, y);
    ctx.beginPath(); ctx.moveTo(0, py); ctx.lineTo(view.width, py); ctx.stroke();
    ctx.fillText(`${y} m`, 2, py - 2);
  }
  // the sensor
  const [sx, sy] = toScreen(0, 0);
  ctx.fillStyle = "#ffffff";
  ctx.beginPath(); ctx.arc(sx, sy, 4, 0, 2 * Math.PI); ctx.fill();
  ctx.fillText("sensor", sx + 6, sy - 6);
  // scale bar
  const bar = step * s;
  ctx.strokeStyle = "#dde3ea";
  ctx.beginPath(); ctx.moveTo(view.width - bar - 20, 20); ctx.lineTo(view.width - 20, 20); ctx.stroke();
  ctx.fillStyle = "#dde3ea";
  ctx.fillText(`${step} m`, view.width - bar / 2 - 30, 34);
}

function drawConfig() {
  ctx.lineWidth = 2;
  ctx.font = "12px system-ui";
  for (const z of state.config.zones) {
    ctx.beginPath();
    z.corners_m.forEach(([x, y], i) => { const [px, py] = toScreen(x, y); i ? ctx.lineTo(px, py) : ctx.moveTo(px, py); });
    ctx.closePath();
    ctx.fillStyle = "rgba(76, 201, 240, 0.08)";
    ctx.fill();
    ctx.strokeStyle = "#4c9bf0";
    ctx.stroke();
    const [px, py] = toScreen(z.corners_m[0][0], z.corners_m[0][1]);
    ctx.fillStyle = "#4c9bf0";
    ctx.fillText(`zone ${z.name}`, px + 3, py - 3);
  }
  for (const l of state.config.lines) {
    const [ax, ay] = toScreen(l.a_m[0], l.a_m[1]), [bx, by] = toScreen(l.b_m[0], l.b_m[1]);
    ctx.strokeStyle = "#ffd166";
    ctx.beginPath(); ctx.moveTo(ax, ay); ctx.lineTo(bx, by); ctx.stroke();
    ctx.fillStyle = "#ffd166";
    ctx.fillText(`line ${l.name}`, bx + 4, by);
  }
}

// each crossing of the last MARK_S seconds: a dot where it crossed its line, in its class's colour,
// with an arrow the way it went (forward: to the left of the line's A -> B), fading out
function drawCrossings() {
  ctx.font = "11px system-ui";
  for (const c of state.crossings) {
    const age = state.frameT - c.t;
    const l = state.config.lines.find((k) => k.name === c.line);
    if (!l || age > MARK_S || age < -1) continue;
    const dx = l.b_m[0] - l.a_m[0], dy = l.b_m[1] - l.a_m[1], len = Math.hypot(dx, dy) || 1;
    const ux = dx / len, uy = dy / len, side = c.direction === "forward" ? 1 : -1;
    const x = l.a_m[0] + ux * c.at_m, y = l.a_m[1] + uy * c.at_m;
    const [px, py] = toScreen(x, y), [qx, qy] = toScreen(x - uy * side * 2.5, y + ux * side * 2.5);
    ctx.globalAlpha = Math.max(0.15, 1 - Math.max(0, age) / MARK_S);
    ctx.strokeStyle = ctx.fillStyle = COLOURS[c.class] || COLOURS.unknown;
    ctx.lineWidth = 2;
    ctx.beginPath(); ctx.arc(px, py, 5, 0, 2 * Math.PI); ctx.fill();
    ctx.beginPath(); ctx.moveTo(px, py); ctx.lineTo(qx, qy); ctx.stroke();
    ctx.fillText(c.speed_mps === null ? "? km/h" : `${(c.speed_mps * 3.6).toFixed(0)} km/h`, qx + 4, qy);
    ctx.globalAlpha = 1;
  }
}

function drawTracks() {
  ctx.font = "11px system-ui";
  for (const t of state.tracks) {
    const colour = COLOURS[t.class] || COLOURS.unknown;
    const trail = state.trails.get(t.id) || [];
    if (trail.length > 1) {
      ctx.strokeStyle = colour;
      ctx.globalAlpha = 0.45;
      ctx.lineWidth = 1.5;
      ctx.beginPath();
      trail.forEach(([x, y], i) => { const [px, py] = toScreen(x, y); i ? ctx.lineTo(px, py) : ctx.moveTo(px, py); });
      ctx.stroke();
      ctx.globalAlpha = 1;
    }
    const [cx, cy] = toScreen(t.position_m[0], t.position_m[1]);
    const h = (t.heading_deg * Math.PI) / 180;
    const L = Math.max(t.length_m, 0.3) * state.cam.scale, Wd = Math.max(t.width_m, 0.3) * state.cam.scale;
    ctx.save();
    ctx.translate(cx, cy);
    ctx.rotate(-h);
    ctx.strokeStyle = colour;
    ctx.lineWidth = t.state === "confirmed" ? 2 : 1;
    ctx.setLineDash(t.state === "coasting" ? [4, 3] : t.state === "tentative" ? [1, 3] : []);
    ctx.strokeRect(-L / 2, -Wd / 2, L, Wd);
    ctx.setLineDash([]);
    if (t.speed_mps > 0) { ctx.beginPath(); ctx.moveTo(0, 0); ctx.lineTo(L / 2 + 6, 0); ctx.stroke(); }
    ctx.restore();
    if (t.state !== "tentative") {
      ctx.fillStyle = colour;
      ctx.fillText(`${t.id} ${t.class} ${(t.speed_mps * 3.6).toFixed(0)} km/h`, cx + 6, cy - 6);
    }
  }
}

function draw() {
  ctx.clearRect(0, 0, view.width, view.height);
  drawGrid();
  drawConfig();
  drawCrossings();
  drawTracks();
  requestAnimationFrame(draw);
}

// zoom and pan
let drag = null;
view.addEventListener("wheel", (e) => {
  e.preventDefault();
  state.cam.scale = Math.min(80, Math.max(0.5, state.cam.scale * (e.deltaY < 0 ? 1.15 : 1 / 1.15)));
}, { passive: false });
view.addEventListener("mousedown", (e) => { drag = [e.clientX, e.clientY]; view.style.cursor = "grabbing"; });
window.addEventListener("mouseup", () => { drag = null; view.style.cursor = "grab"; });
window.addEventListener("mousemove", (e) => {
  if (!drag) return;
  const k = view.width / view.clientWidth;
  state.cam.x -= ((e.clientX - drag[0]) * k) / state.cam.scale;
  state.cam.y += ((e.clientY - drag[1]) * k) / state.cam.scale;
  drag = [e.clientX, e.clientY];
});
view.addEventListener("dblclick", () => { state.cam = { x: 0, y: 0, scale: 8 }; });

function legend() {
  $("legend").innerHTML = CLASSES.map((c, i) => `<span class="sw c${i}"></span>${c}`).join("") +
    " · solid: confirmed, dashed: coasting, dotted: tentative · label: id, class, speed (km/h) · boxes to scale (m)";
}

// ---- events -----------------------------------------------------------------------------
function onTracks(m) {
  state.tracks = m.tracks;
  const alive = new Set();
  for (const t of m.tracks) {
    alive.add(t.id);
    const tr = state.trails.get(t.id) || [];
    tr.push([t.position_m[0], t.position_m[1]]);
    if (tr.length > TRAIL) tr.shift();
    state.trails.set(t.id, tr);
  }
  for (const id of state.trails.keys()) if (!alive.has(id)) state.trails.delete(id);
  const confirmed = m.tracks.filter((t) => t.state === "confirmed");
  $("tracks-count").textContent = confirmed.length;
  $("tracks-other").textContent =
    `${m.tracks.filter((t) => t.state === "tentative").length} / ${m.tracks.filter((t) => t.state === "coasting").length}`;
  const moving = confirmed.filter((t) => t.speed_mps > 0);
  const mean = moving.length ? moving.reduce((s, t) => s + t.speed_mps, 0) / moving.length : 0;
  $("mean-speed").textContent = moving.length ? `${mean.toFixed(1)} m/s (${(mean * 3.6).toFixed(0)} km/h)` : "– m/s";
  history(m.t_frame_us / 1e6, mean, 0);
  $("sensor").textContent = m.sensor_id;
  state.frameT = m.t_frame_us / 1e6;
  const ft = $("frame-time");
  ft.dataset.us = m.t_frame_us;
  ft.dataset.frame = m.frame_seq;
  ft.dataset.confirmed = confirmed.length;
  ft.textContent = `${new Date(m.t_frame_us / 1000).toISOString().slice(11, 23)} (frame ${m.frame_seq})`;
}

function addCounts(name, kind, a, b) {
  const c = state.counts.get(name) || { kind, a: {}, b: {} };
  for (const k of CLASSES) { c.a[k] = (c.a[k] || 0) + (a[k] || 0); c.b[k] = (c.b[k] || 0) + (b[k] || 0); }
  state.counts.set(name, c);
  let n = 0;
  for (const k of CLASSES) n += (a[k] || 0) + (kind === "line" ? b[k] || 0 : 0);
  return n;
}

function onCounts(m) {
  let n = 0;
  for (const l of m.lines) n += addCounts(l.name, "line", l.forward, l.backward);
  for (const z of m.zones || []) n += addCounts(z.name, "zone", z.entered, z.exited);
  state.countsTotal += n;
  $("counts-total").textContent = state.countsTotal;
  history(m.t_end_us / 1e6, null, n);
  const rows = [];
  for (const [name, c] of state.counts) {
    const [ha, hb] = c.kind === "line" ? ["forward", "backward"] : ["entered", "exited"];
    rows.push(`<tr><th>${c.kind} ${escapeHtml(name)}</th><td colspan="${CLASSES.length + 1}"></td></tr>`);
    for (const [h, v] of [[ha, c.a], [hb, c.b]]) {
      const total = CLASSES.reduce((s, k) => s + v[k], 0);
      rows.push(`<tr><th>&nbsp;${h}</th>${CLASSES.map((k) => `<td title="${k}">${v[k]}</td>`).join("")}<td><b>${total}</b></td></tr>`);
    }
  }
  $("counts").innerHTML = `<table><tr><th></th>${CLASSES.map((k) => `<th title="${k}">${k.slice(0, 4)}</th>`).join("")}<th>all</th></tr>${rows.join("")}</table>`;
}

function onCrossing(m) {
  state.crossings.unshift({ t: m.t_cross_us / 1e6, line: m.line, direction: m.direction, at_m: m.at_m, class: m.class,
                            track_id: m.track_id, speed_mps: m.speed_mps, how: m.how });
  if (state.crossings.length > CROSSINGS_SHOWN) state.crossings.pop();
  state.crossingsSeen++;
  $("crossings-seen").textContent = state.crossingsSeen;
  const rows = state.crossings.map((c) =>
    `<tr><td>${new Date(c.t * 1000).toISOString().slice(11, 22)}</td><td>${escapeHtml(c.line)}</td>` +
    `<td>${c.direction === "forward" ? "fwd" : "back"}</td><td>${c.at_m.toFixed(1)}</td>` +
    `<td><span class="sw c${Math.max(0, CLASSES.indexOf(c.class))}"></span>${escapeHtml(c.class)}</td>` +
    `<td>${c.speed_mps === null ? "–" : (c.speed_mps * 3.6).toFixed(0)}</td><td>${c.how}</td><td>${c.track_id}</td></tr>`);
  $("crossings").innerHTML = `<table><tr><th>time</th><th>line</th><th>way</th><th>at m</th><th>class</th>` +
    `<th>km/h</th><th>how</th><th>track</th></tr>${rows.join("")}</table>`;
}

function escapeHtml(s) {
  return String(s).replace(/[&<>"']/g, (c) => ({ "&": "&amp;", "<": "&lt;", ">": "&gt;", '"': "&quot;", "'": "&#39;" })[c]);
}

function p99(values) {
  if (!values.length) return NaN;
  const s = [...values].sort((a, b) => a - b);
  return s[Math.min(s.length - 1, Math.floor(0.99 * (s.length - 1) + 0.5))];
}

function onStats(m) {
  state.stats = m;
  state.statsAt = Date.now();
  const now = m.published_us / 1e6;
  state.frameTimes.push(now);
  while (state.frameTimes.length > 50) state.frameTimes.shift();
  const span = state.frameTimes[state.frameTimes.length - 1] - state.frameTimes[0];
  $("fps").textContent = span > 0 ? `${((state.frameTimes.length - 1) / span).toFixed(1)} frames/s` : "– frames/s";
  $("frames").textContent = `${m.frames_processed} / ${m.frames_dropped}`;
  $("overruns").textContent = m.deadline_overruns;
  $("missing").textContent = m.packets_missing;
  $("kdropped").textContent = m.kernel_dropped;
  const errs = Object.entries(m.input_errors);
  $("errors").textContent = errs.length ? errs.map(([k, v]) => `${k} ${v}`).join(", ") : "none";
  const age = m.model_age_s;
  $("model-age").textContent = age === null ? "no model yet"
    : age < 120 ? `${age.toFixed(0)} s` : age < 7200 ? `${(age / 60).toFixed(0)} min` : `${(age / 3600).toFixed(1)} h`;
  const rows = [];
  for (const k of STAGES.concat(["latency_ms"])) {
    const v = k === "latency_ms" ? m.latency_ms : m.stage_times[k];
    if (v === null || v === undefined) continue;
    const h = state.stageHist.get(k) || [];
    h.push(v);
    if (h.length > WINDOW) h.shift();
    state.stageHist.set(k, h);
    rows.push(`<tr><td>${k.replace("_ms", "")}</td><td>${v.toFixed(2)}</td><td>${p99(h).toFixed(2)}</td></tr>`);
  }
  document.querySelector("#stages tbody").innerHTML = rows.join("");
  $("sensor").textContent = m.sensor_id;
}

setInterval(() => {
  $("age").textContent = state.statsAt ? `${((Date.now() - state.statsAt) / 1000).toFixed(0)} s ago` : "–";
}, 1000);

// ---- the plot: mean speed and counts per 10 s over the last minutes -----------------------------
function history(t, speed, count) {
  if (!isFinite(t)) return;
  const slot = Math.floor(t / 10) * 10;
  let last = state.history[state.history.length - 1];
  if (!last || last.t !== slot) {
    last = { t: slot, speedSum: 0, speedN: 0, count: 0 };
    state.history.push(last);
    while (state.history.length && state.history[0].t < slot - HISTORY_S) state.history.shift();
  }
  if (speed !== null) { last.speedSum += speed; last.speedN++; }
  last.count += count;
  drawPlot();
}

function drawPlot() {
  const w = plot.width, h = plot.height, m = 28;
  pctx.clearRect(0, 0, w, h);
  pctx.strokeStyle = "#2b323c";
  pctx.strokeRect(m, 8, w - 2 * m, h - m - 8);
  pctx.font = "10px system-ui";
  pctx.fillStyle = "#7d8b99";
  pctx.fillText(`last ${HISTORY_S / 60} min (s of sensor time)`, m, h - 4);
  if (!state.history.length) return;
  const t1 = state.history[state.history.length - 1].t + 10, t0 = t1 - HISTORY_S;
  const sMax = Math.max(5, ...state.history.map((b) => (b.speedN ? b.speedSum / b.speedN : 0)));
  const cMax = Math.max(5, ...state.history.map((b) => b.count));
  const X = (t) => m + ((t - t0) / HISTORY_S) * (w - 2 * m);
  pctx.fillText(`${sMax.toFixed(0)} m/s`, 0, 16);
  pctx.fillText(`${cMax}`, w - m + 4, 16);
  pctx.fillStyle = "#4cc9f0";
  for (const b of state.history) {
    const bh = (b.count / cMax) * (h - m - 8);
    pctx.fillRect(X(b.t) + 1, h - m - bh, Math.max(1, X(b.t + 10) - X(b.t) - 2), bh);
  }
  pctx.strokeStyle = "#ffd166";
  pctx.lineWidth = 2;
  pctx.beginPath();
  let first = true;
  for (const b of state.history) {
    if (!b.speedN) continue;
    const y = h - m - ((b.speedSum / b.speedN) / sMax) * (h - m - 8);
    first ? pctx.moveTo(X(b.t + 5), y) : pctx.lineTo(X(b.t + 5), y);
    first = false;
  }
  pctx.stroke();
}

// ---- start ---------------------------------------------------------------------------------
async function start() {
  legend();
  try {
    const r = await fetch("config");
    state.config = await r.json();
  } catch (e) {
    console.warn("no /config", e);
  }
  const es = new EventSource("events");
  es.onopen = () => { $("conn").textContent = "live"; $("conn").className = "good"; };
  es.onerror = () => { $("conn").textContent = "reconnecting…"; $("conn").className = "bad"; };
  es.addEventListener("tracks", (e) => onTracks(JSON.parse(e.data)));
  es.addEventListener("counts", (e) => onCounts(JSON.parse(e.data)));
  es.addEventListener("crossings", (e) => onCrossing(JSON.parse(e.data)));
  es.addEventListener("stats", (e) => onStats(JSON.parse(e.data)));
  es.addEventListener("track_ends", () => { state.ended++; $("ended").textContent = state.ended; });
  requestAnimationFrame(draw);
}
start();

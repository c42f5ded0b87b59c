// The web face of `infocus live`: reads the states from /events and the frames from
// /stream.mjpg, draws each frame with the overlays of the state that measured it, and sends the
// person's controls to /control. Plain ES2020, no library: the binary serves this file as it is.
"use strict";

const token = new URLSearchParams(location.search).get("token");

// withToken adds the page's token to a path: the server wants it on every request, and
// EventSource and <img> cannot send a header.
function withToken(path) {
  if (!token) return path;
  return path + (path.includes("?") ? "&" : "?") + "token=" + encodeURIComponent(token);
}

const $ = (id) => document.getElementById(id);
const el = {
  conn: $("conn"), source: $("source"), preview: $("preview"), waiting: $("waiting"),
  inset: $("inset"), loupe: $("loupe"), loupeLabel: $("loupe-label"), zoom: $("zoom"),
  loupeOff: $("loupe-off"), showHeat: $("show-heat"), showLine: $("show-line"),
  cue: $("cue"), pct: $("pct"), trend: $("trend"), score: $("score"), blur: $("blur"),
  history: $("history"), lens: $("lens"), focus: $("focus"), position: $("position"),
  focusAt: $("focus-at"), af: $("af"), afc: $("afc"), afState: $("af-state"), reset: $("reset"), grid: $("grid"),
  peaking: $("peaking"), audio: $("audio"), optics: $("optics"), dof: $("dof"),
  dofText: $("dof-text"), tilt: $("tilt"), message: $("message"), stats: $("stats"),
};

// ---- state from /events -------------------------------------------------------------------

// The stream's frames arrive a little after or before their states; keeping the last states
// by frame number lets each picture be drawn with the overlays measured on it.
const kStatesKept = 90;
const states = new Map();
let latest = null;
let events = null;
let eventsLive = false;
let streamLive = false;

let everLive = false; // "connecting…" until both first answer, "reconnecting…" after a loss

function setConnection() {
  const live = eventsLive && streamLive;
  everLive = everLive || live;
  el.conn.textContent = live ? "live" : everLive ? "reconnecting…" : "connecting…";
  el.conn.className = "conn " + (live ? "live" : "wait");
}

function onState(s) {
  latest = s;
  states.set(s.frame, s);
  if (states.size > kStatesKept) states.delete(states.keys().next().value);
  updatePanel(s);
  audioCue(s);
}

// EventSource retries by itself after a dropped connection, but gives up for good on an HTTP
// error (a server still starting answers 503); then it is opened again after a pause.
function openEvents() {
  events = new EventSource(withToken("/events"));
  events.onopen = () => { eventsLive = true; setConnection(); };
  events.onmessage = (e) => {
    try { onState(JSON.parse(e.data)); } catch (err) { console.warn("bad state", err); }
  };
  events.onerror = () => {
    eventsLive = false;
    setConnection();
    if (events.readyState === EventSource.CLOSED) setTimeout(openEvents, 2000);
  };
}

// ---- the MJPEG stream ---------------------------------------------------------------------

const enc = new TextEncoder();
const kBoundary = enc.encode("--infocusframe");
const kHeaderEnd = enc.encode("\r\n\r\n");

// indexOf finds needle in hay from start; -1 when absent.
function indexOf(hay, needle, start) {
  outer: for (let i = start; i <= hay.length - needle.length; i++) {
    for (let j = 0; j < needle.length; j++) if (hay[i + j] !== needle[j]) continue outer;
    return i;
  }
  return -1;
}

// A growable byte buffer: parts are taken off the front once complete.
class Bytes {
  constructor() { this.buf = new Uint8Array(1 << 18); this.len = 0; }
  push(chunk) {
    if (this.len + chunk.length > this.buf.length) {
      const bigger = new Uint8Array(Math.max(this.buf.length * 2, this.len + chunk.length));
      bigger.set(this.buf.subarray(0, this.len));
      this.buf = bigger;
    }
    this.buf.set(chunk, this.len);
    this.len += chunk.length;
  }
  view() { return this.buf.subarray(0, this.len); }
  drop(n) { this.buf.copyWithin(0, n, this.len); this.len -= n; }
}

// parseParts takes every complete part off the buffer and hands its JPEG and frame number on.
function parseParts(bytes, onPart) {
  for (;;) {
    const v = bytes.view();
    const b = indexOf(v, kBoundary, 0);
    if (b < 0) return;
    const h = indexOf(v, kHeaderEnd, b);
    if (h < 0) return;
    const head = new TextDecoder().decode(v.subarray(b + kBoundary.length, h));
    const length = Number((/content-length:\s*(\d+)/i.exec(head) || [])[1]);
    const frame = Number((/x-frame:\s*(\d+)/i.exec(head) || [])[1]);
    const start = h + kHeaderEnd.length;
    if (!Number.isFinite(length)) { bytes.drop(start); continue; } // a part we cannot size
    if (v.length < start + length) return;
    onPart(v.slice(start, start + length), frame);
    bytes.drop(start + length);
  }
}

let streamDelay = 500;
let pending = null; // the newest decoded frame not drawn yet: a slow screen skips, never queues
let decoding = false;

async function runStream() {
  try {
    const res = await fetch(withToken("/stream.mjpg"), { cache: "no-store" });
    if (!res.ok || !res.body) throw new Error("stream: HTTP " + res.status);
    streamLive = true;
    streamDelay = 500;
    setConnection();
    const reader = res.body.getReader();
    const bytes = new Bytes();
    for (;;) {
      const { value, done } = await reader.read();
      if (done) break;
      bytes.push(value);
      parseParts(bytes, onJpeg);
    }
  } catch (err) {
    // The server went away or refused (503 when too many viewers): retried below.
  }
  streamLive = false;
  setConnection();
  setTimeout(runStream, streamDelay);
  streamDelay = Math.min(streamDelay * 2, 8000);
}

function onJpeg(jpeg, frame) {
  if (decoding) return; // the decoder is behind: this frame is skipped, the next one drawn
  decoding = true;
  createImageBitmap(new Blob([jpeg], { type: "image/jpeg" }))
    .then((bitmap) => {
      if (pending) pending.bitmap.close();
      pending = { bitmap, frame };
      requestAnimationFrame(drawPending);
    })
    .catch(() => {})
    .finally(() => { decoding = false; });
}

// stateFor gives the state measured on this frame, else the newest one before it.
function stateFor(frame) {
  if (states.has(frame)) return states.get(frame);
  let best = null;
  for (const s of states.values())
    if (s.frame <= frame && (!best || s.frame > best.frame)) best = s;
  return best || latest;
}

// ---- the preview and its overlays ---------------------------------------------------------

let shown = null; // {bitmap, frame} on the canvas now, redrawn when the layout changes

function drawPending() {
  if (!pending) return;
  if (shown) shown.bitmap.close();
  shown = pending;
  pending = null;
  drawPreview();
}

// The canvas is sized to its on-screen pixels so overlay text stays sharp and readable on a
// phone, whatever the preview's own size.
function fitCanvas(canvas, aspect) {
  if (aspect) canvas.style.aspectRatio = String(aspect);
  const dpr = window.devicePixelRatio || 1;
  const w = Math.max(1, Math.round(canvas.clientWidth * dpr));
  const h = Math.max(1, Math.round(canvas.clientHeight * dpr));
  if (canvas.width !== w || canvas.height !== h) { canvas.width = w; canvas.height = h; }
  return dpr;
}

// The heat class each region carries in the state (blur against the circle of confusion, from a
// reading the engine is confident in); "unknown" regions are left unshaded.
const kHeatRgb = { in_coc: "61,220,132", near: "255,214,64", far: "255,140,40", beyond: "255,70,60" };

function heatColour(heat, alpha) {
  return `rgba(${kHeatRgb[heat]},${alpha})`;
}

function drawPreview() {
  if (!shown) return;
  const c = el.preview;
  const { bitmap, frame } = shown;
  const dpr = fitCanvas(c, bitmap.width / bitmap.height);
  el.waiting.hidden = true;
  const g = c.getContext("2d");
  g.drawImage(bitmap, 0, 0, c.width, c.height);
  const s = stateFor(frame);
  if (!s || !s.width) return;
  const k = c.width / s.width; // frame pixels → canvas pixels
  if (el.showHeat.checked) drawHeat(g, s, k, dpr);
  if (peakMask && s.peaking !== "off") g.drawImage(peakMask, 0, 0, c.width, c.height);
  if (s.roi) {
    g.strokeStyle = "#ffe14f";
    g.lineWidth = 2 * dpr;
    g.strokeRect(s.roi[0] * k, s.roi[1] * k, s.roi[2] * k, s.roi[3] * k);
  }
  if (el.showLine.checked && s.in_focus_line) {
    // An object {x0, y0, x1, y1}; an array [x0, y0, x1, y1] is read the same way.
    const a = s.in_focus_line;
    const l = Array.isArray(a) ? { x0: a[0], y0: a[1], x1: a[2], y1: a[3] } : a;
    g.strokeStyle = "#4fe3ff";
    g.lineWidth = 3 * dpr;
    g.setLineDash([8 * dpr, 5 * dpr]);
    g.beginPath();
    g.moveTo(l.x0 * k, l.y0 * k);
    g.lineTo(l.x1 * k, l.y1 * k);
    g.stroke();
    g.setLineDash([]);
  }
  if (s.magnifier) drawMark(g, s.magnifier.x * k, s.magnifier.y * k, dpr);
}

// drawHeat tints each confident region by its blur against the circle of confusion, and writes
// the blur where the cell is wide enough for the digits.
function drawHeat(g, s, k, dpr) {
  // Digits grow with the cells (a coarse grid on a desktop), from 10 to 16 px.
  const cell = s.regions && s.regions.length ? (s.regions[0].w * k) / dpr : 0;
  g.font = `600 ${Math.min(16, Math.max(10, cell / 4)) * dpr}px system-ui, sans-serif`;
  g.textAlign = "center";
  g.textBaseline = "middle";
  for (const r of s.regions || []) {
    const x = r.x * k, y = r.y * k, w = r.w * k, h = r.h * k;
    // Too dark or clipped to measure: say so rather than leave the cell looking untextured.
    if (r.status && r.status !== "ok") {
      g.fillStyle = "rgba(60,60,70,0.45)";
      g.fillRect(x, y, w, h);
      if (w >= 28 * dpr && h >= 12 * dpr) {
        g.fillStyle = "#ccc";
        g.fillText(r.status === "dark" ? "dark" : "clip", x + w / 2, y + h / 2);
      }
      continue;
    }
    if (r.blur_px == null || !(r.heat in kHeatRgb)) continue;
    g.fillStyle = heatColour(r.heat, 0.28);
    g.fillRect(x, y, w, h);
    if (w >= 20 * dpr && h >= 12 * dpr) {
      const text = r.blur_px < 10 ? r.blur_px.toFixed(1) : r.blur_px.toFixed(0);
      g.fillStyle = "rgba(0,0,0,0.55)";
      g.fillText(text, x + w / 2 + dpr, y + h / 2 + dpr);
      g.fillStyle = "#fff";
      g.fillText(text, x + w / 2, y + h / 2);
    }
  }
}

function drawMark(g, x, y, dpr) {
  g.strokeStyle = "#4fb3ff";
  g.lineWidth = 2 * dpr;
  g.beginPath();
  g.arc(x, y, 10 * dpr, 0, 2 * Math.PI);
  g.moveTo(x - 16 * dpr, y); g.lineTo(x + 16 * dpr, y);
  g.moveTo(x, y - 16 * dpr); g.lineTo(x, y + 16 * dpr);
  g.stroke();
}

// ---- peaking: the server's mask, tinted once per fetch ------------------------------------

let peakMask = null;

async function refreshPeaking() {
  if (!latest || latest.peaking === "off") { peakMask = null; return; }
  try {
    const res = await fetch(withToken("/peaking.png"), { cache: "no-store" });
    if (!res.ok) { peakMask = null; return; }
    const bitmap = await createImageBitmap(await res.blob());
    const t = document.createElement("canvas");
    t.width = bitmap.width;
    t.height = bitmap.height;
    const g = t.getContext("2d");
    g.drawImage(bitmap, 0, 0);
    // Keep the mask's opaque pixels, in a colour no grey preview contains.
    g.globalCompositeOperation = "source-in";
    g.fillStyle = "#ff2bd6";
    g.fillRect(0, 0, t.width, t.height);
    bitmap.close();
    peakMask = t;
  } catch (err) { peakMask = null; }
}

// ---- the magnifier ------------------------------------------------------------------------

let zoom = 1;
let loupeUrl = null;

el.zoom.addEventListener("click", () => {
  zoom = zoom === 1 ? 2 : 1;
  el.zoom.textContent = `loupe ${zoom}:1`;
  el.zoom.classList.toggle("on", zoom === 2);
  if (latest && latest.magnifier)
    send({ magnifier: [latest.magnifier.x, latest.magnifier.y, zoom] });
});

// A tap on the picture places the magnifier at that point, in frame pixels.
el.preview.addEventListener("click", (e) => {
  if (!latest || !latest.width) return;
  const r = el.preview.getBoundingClientRect();
  const x = Math.round(((e.clientX - r.left) / r.width) * latest.width);
  const y = Math.round(((e.clientY - r.top) / r.height) * latest.height);
  const cx = Math.min(Math.max(x, 0), latest.width - 1);
  const cy = Math.min(Math.max(y, 0), latest.height - 1);
  clearing = false;
  // The crop is fetched once a state shows the magnifier placed: asked for earlier, the server
  // may have none yet.
  send({ magnifier: [cx, cy, zoom] });
});

// After "hide", states measured before the server took the command still show the magnifier;
// they are not followed, or the crop would be asked for after it is gone.
let clearing = false;
el.loupeOff.addEventListener("click", () => {
  clearing = true;
  el.inset.hidden = true;
  el.loupeOff.hidden = true;
  send({ magnifier: null });
  setTimeout(() => { clearing = false; }, 3000);
});

async function refreshLoupe() {
  const placed = latest && latest.magnifier;
  if (!placed) clearing = false;
  if (!placed || clearing) { el.inset.hidden = true; el.loupeOff.hidden = true; return; }
  el.loupeOff.hidden = false;
  try {
    const res = await fetch(withToken("/magnifier.jpg"), { cache: "no-store" });
    if (!res.ok) return;
    const url = URL.createObjectURL(await res.blob());
    el.loupe.onload = () => { if (loupeUrl) URL.revokeObjectURL(loupeUrl); loupeUrl = url; };
    el.loupe.src = url;
    el.loupeLabel.textContent = `${placed.x}, ${placed.y} · ${placed.zoom}:1`;
    // The inset goes to the side away from the point it magnifies, so both stay visible.
    el.inset.classList.toggle("left", placed.x > latest.width / 2);
    el.inset.hidden = false;
  } catch (err) { /* the next refresh tries again */ }
}

// ---- controls -----------------------------------------------------------------------------

// say shows a control's answer; a plain answer fades after 4 s so it does not outlive what it
// describes ("autofocus started" after the sweep), an error stays until the next answer.
let sayTimer = 0;
function say(text, isError) {
  clearTimeout(sayTimer);
  el.message.textContent = text;
  el.message.className = isError ? "error" : "dim";
  if (!isError) sayTimer = setTimeout(() => { el.message.textContent = ""; }, 4000);
}

// send posts one command; its answer (or the reason it failed) shows under the controls.
async function send(cmd) {
  try {
    const res = await fetch(withToken("/control"), {
      method: "POST",
      headers: { "Content-Type": "application/json" },
      body: JSON.stringify(cmd),
    });
    const body = await res.json().catch(() => ({}));
    if (!res.ok) say(body.error || `control failed: HTTP ${res.status}`, true);
    else if (body.status) say(body.status, false);
    return res.ok;
  } catch (err) {
    say("the server is not answering", true);
    return false;
  }
}

for (const id of ["minus10", "minus1", "plus1", "plus10"])
  $(id).addEventListener("click", (e) =>
    send({ focus_step: Number(e.currentTarget.dataset.step) }));

let sliding = false; // while a finger is on the slider, the state does not move it
el.focus.addEventListener("input", () => { sliding = true; });
el.focus.addEventListener("change", () => {
  sliding = false;
  send({ focus: Number(el.focus.value) });
});
el.af.addEventListener("click", () => send({ autofocus: true }));
el.afc.addEventListener("click", () =>
  send({ autofocus: el.afc.getAttribute("aria-pressed") === "true" ? "off" : "continuous" }));
el.reset.addEventListener("click", () => send({ reset_peak: true }));
el.grid.addEventListener("change", () => send({ grid: el.grid.value.split(",").map(Number) }));
el.peaking.addEventListener("change", () => send({ peaking: el.peaking.value }));
el.showHeat.addEventListener("change", drawPreview);
el.showLine.addEventListener("change", drawPreview);

// ---- the panel ----------------------------------------------------------------------------

function fmtNumber(v) {
  if (v == null || !Number.isFinite(v)) return "–";
  const a = Math.abs(v);
  if (a !== 0 && (a < 0.01 || a >= 1e5)) return v.toExponential(2);
  return v.toPrecision(3);
}

function fmtDistance(m) {
  if (m === "inf") return "∞";
  if (m == null || !Number.isFinite(m)) return "–";
  return m < 1 ? `${(m * 100).toFixed(m < 0.1 ? 1 : 0)} cm` : `${m.toFixed(m < 10 ? 2 : 0)} m`;
}

// afText says what autofocus does, as the terminal and the window say it.
function afText(af) {
  if (af.state === "failed") return `autofocus failed: ${af.reason}`;
  if (af.mode === "continuous")
    return `continuous autofocus: ${af.state}` + (af.reason ? ` (${af.reason})` : "");
  if (af.state === "focused") return `autofocus: in focus in ${af.frames} frames`;
  return `autofocus: ${af.state}, ${af.frames} frames`;
}

const kTrend = { sharper: "▲ sharper", worse: "▼ worse", steady: "● steady" };

function updatePanel(s) {
  el.source.textContent = `${s.source || ""} ${s.width}×${s.height}`;
  el.pct.textContent = s.percent_of_peak == null ? "–" : `${Math.round(s.percent_of_peak)}%`;
  el.score.textContent = fmtNumber(s.score);
  el.blur.textContent = s.blur_px == null ? "–"
    : `${s.blur_px.toFixed(1)} px` + (s.coc_px ? ` (CoC ${s.coc_px.toFixed(1)})` : "");
  el.trend.textContent = kTrend[s.trend] || s.trend;
  el.trend.className = "trend " + s.trend;
  el.cue.hidden = !s.past_peak;
  drawHistory(s);

  el.lens.hidden = !s.has_focus_control;
  const af = s.autofocus || { mode: "off", state: "idle", frames: 0, reason: "" };
  const continuous = af.mode === "continuous";
  el.af.disabled = !s.has_focus_control || s.autofocus_running || continuous;
  el.af.textContent = s.autofocus_running ? "Autofocus…" : "Autofocus";
  el.afc.disabled = !s.has_focus_control || s.autofocus_running;
  el.afc.setAttribute("aria-pressed", String(continuous));
  el.afc.textContent = continuous ? "Continuous ●" : "Continuous";
  el.afState.hidden = af.mode === "off" && af.state === "idle";
  el.afState.textContent = afText(af);
  const fr = s.focus_range;
  if (fr) {
    el.focus.min = fr.min;
    el.focus.max = fr.max;
    el.focus.step = fr.step || "any";
  }
  const lp = s.lens_position;
  if (lp && !sliding && Number.isFinite(lp.value)) el.focus.value = lp.value;
  el.position.textContent = !lp ? "–"
    : `${fmtNumber(lp.value)} ${lp.unit === "dioptre" ? "dpt" : lp.unit || ""}`;
  el.focusAt.textContent = fmtDistance(s.in_focus_distance_m);

  if (document.activeElement !== el.grid && s.grid) el.grid.value = s.grid.join(",");
  if (document.activeElement !== el.peaking && s.peaking) el.peaking.value = s.peaking;

  el.optics.hidden = s.dof_near_m == null;
  if (s.dof_near_m != null) drawDof(s);

  const lat = s.latency_p50_ms == null ? "–"
    : `${s.latency_p50_ms.toFixed(0)}/${s.latency_p99_ms.toFixed(0)} ms`;
  el.stats.textContent = `${fmtNumber(s.fps)} fps · dropped ${s.dropped} · skipped ${s.skipped}` +
    ` · latency p50/p99 ${lat} · frame ${s.frame}` + (s.status ? ` · ${s.status}` : "");
}

// drawHistory plots the last 10 s of scores, the peak as a dot with its time.
function drawHistory(s) {
  const c = el.history;
  const dpr = fitCanvas(c);
  const g = c.getContext("2d");
  g.clearRect(0, 0, c.width, c.height);
  const h = s.history || [];
  if (h.length < 2) return;
  const t1 = h[h.length - 1][0], t0 = t1 - 10;
  let top = 0;
  for (const p of h) top = Math.max(top, p[1]);
  if (s.history_peak) top = Math.max(top, s.history_peak[1]);
  if (!(top > 0)) return;
  const pad = 4 * dpr;
  const X = (t) => pad + ((t - t0) / 10) * (c.width - 2 * pad);
  const Y = (v) => c.height - pad - (v / (top * 1.08)) * (c.height - 2 * pad);
  g.strokeStyle = "#4fb3ff";
  g.lineWidth = 1.5 * dpr;
  g.beginPath();
  h.forEach((p, i) => (i ? g.lineTo(X(p[0]), Y(p[1])) : g.moveTo(X(p[0]), Y(p[1]))));
  g.stroke();
  if (s.history_peak) {
    const [pt, pv] = s.history_peak;
    g.fillStyle = "#ffc640";
    g.beginPath();
    g.arc(X(Math.max(pt, t0)), Y(pv), 3.5 * dpr, 0, 2 * Math.PI);
    g.fill();
    g.font = `${10 * dpr}px system-ui, sans-serif`;
    g.textBaseline = "top";
    g.textAlign = X(pt) > c.width / 2 ? "right" : "left";
    g.fillText("peak", X(Math.max(pt, t0)) + (X(pt) > c.width / 2 ? -6 : 6) * dpr, pad);
  }
}

// drawDof shows the depth of field on a log distance axis, with the in-focus distance marked.
function drawDof(s) {
  const c = el.dof;
  const dpr = fitCanvas(c);
  const g = c.getContext("2d");
  g.clearRect(0, 0, c.width, c.height);
  const far = s.dof_far_m === "inf" ? Infinity : s.dof_far_m;
  const at = s.in_focus_distance_m === "inf" ? Infinity : s.in_focus_distance_m;
  // The axis spans a decade either side of the sharp zone, within 5 cm .. 200 m.
  const lo = Math.max(0.05, s.dof_near_m / 4);
  const hi = Math.min(200, Number.isFinite(far) ? far * 4 : 200);
  const pad = 8 * dpr;
  const X = (m) => pad + ((Math.log(Math.min(Math.max(m, lo), hi)) - Math.log(lo)) /
    (Math.log(hi) - Math.log(lo))) * (c.width - 2 * pad);
  const mid = c.height * 0.4;
  g.strokeStyle = "#3a444f";
  g.lineWidth = 2 * dpr;
  g.beginPath(); g.moveTo(pad, mid); g.lineTo(c.width - pad, mid); g.stroke();
  g.fillStyle = "rgba(61,220,132,0.8)";
  const x0 = X(s.dof_near_m), x1 = Number.isFinite(far) ? X(far) : c.width - pad;
  g.fillRect(x0, mid - 6 * dpr, Math.max(2 * dpr, x1 - x0), 12 * dpr);
  // Each region's depth as a dot: a blur width has two candidate distances, in front of the
  // in-focus plane (filled, above the axis) and behind it (hollow, below).
  for (const r of s.regions || []) {
    if (!r.depth_m) continue;
    const [near, farRoot] = r.depth_m;
    g.fillStyle = "rgba(120,190,255,0.7)";
    g.beginPath(); g.arc(X(near), mid - 9 * dpr, 2.5 * dpr, 0, 2 * Math.PI); g.fill();
    if (farRoot != null) {
      const xf = farRoot === "inf" ? c.width - pad : X(farRoot);
      g.strokeStyle = "rgba(120,190,255,0.7)";
      g.lineWidth = dpr;
      g.beginPath(); g.arc(xf, mid + 9 * dpr, 2.5 * dpr, 0, 2 * Math.PI); g.stroke();
    }
  }
  if (at != null) {
    const xa = Number.isFinite(at) ? X(at) : c.width - pad;
    g.fillStyle = "#fff";
    g.fillRect(xa - dpr, mid - 10 * dpr, 2 * dpr, 20 * dpr);
  }
  // Ticks at round distances the axis covers, labelled where they fit.
  g.fillStyle = "#9aa5b1";
  g.font = `${10 * dpr}px system-ui, sans-serif`;
  g.textAlign = "center";
  g.textBaseline = "bottom";
  for (const m of [0.1, 0.2, 0.5, 1, 2, 5, 10, 20, 50, 100]) {
    if (m < lo || m > hi) continue;
    g.fillRect(X(m) - 0.5 * dpr, mid + 8 * dpr, dpr, 4 * dpr);
    g.fillText(m < 1 ? `${m * 100}cm` : `${m}m`, X(m), c.height);
  }
  el.dofText.textContent = `${fmtDistance(s.dof_near_m)} – ${fmtDistance(s.dof_far_m)}`;
  el.tilt.textContent = s.tilt_deg == null ? "–" : `${s.tilt_deg.toFixed(1)}°`;
}

// ---- the sound: pitch rises as the blur falls, a chime when it reaches the CoC ------------

let audio = null;
let wasSharp = false;

el.audio.addEventListener("change", () => {
  // The audio context may only start from a person's gesture, hence here and not at load.
  if (el.audio.checked && !audio) {
    const ctx = new AudioContext();
    const osc = ctx.createOscillator();
    const gain = ctx.createGain();
    osc.type = "sine";
    gain.gain.value = 0;
    osc.connect(gain).connect(ctx.destination);
    osc.start();
    audio = { ctx, osc, gain };
  }
  if (audio && !el.audio.checked) audio.gain.gain.setTargetAtTime(0, audio.ctx.currentTime, 0.05);
  if (audio && el.audio.checked) audio.ctx.resume();
});

function audioCue(s) {
  if (!audio || !el.audio.checked || s.blur_px == null) return;
  const coc = s.coc_px || 2;
  const now = audio.ctx.currentTime;
  // 220 Hz at 16 CoCs of blur or more, two octaves up at the CoC.
  const ratio = Math.min(Math.max(s.blur_px / coc, 1), 16);
  audio.osc.frequency.setTargetAtTime(880 / Math.pow(ratio, 0.5), now, 0.05);
  audio.gain.gain.setTargetAtTime(0.04, now, 0.05);
  const sharp = s.blur_px <= coc;
  if (sharp && !wasSharp) chime(now);
  wasSharp = sharp;
}

function chime(now) {
  const o = audio.ctx.createOscillator();
  const g = audio.ctx.createGain();
  o.frequency.value = 1568;
  g.gain.setValueAtTime(0.15, now);
  g.gain.exponentialRampToValueAtTime(0.001, now + 0.4);
  o.connect(g).connect(audio.ctx.destination);
  o.start(now);
  o.stop(now + 0.45);
}

// ---- start --------------------------------------------------------------------------------

async function start() {
  // One state at once, so the panel is filled before the first event arrives.
  try {
    const res = await fetch(withToken("/state"), { cache: "no-store" });
    if (res.ok) onState(await res.json());
  } catch (err) { /* the event stream will bring it */ }
  setConnection();
  openEvents();
  runStream();
  setInterval(refreshPeaking, 250);
  setInterval(refreshLoupe, 300);
  window.addEventListener("resize", () => { drawPreview(); if (latest) updatePanel(latest); });
}

if (document.readyState === "loading") document.addEventListener("DOMContentLoaded", start);
else start();

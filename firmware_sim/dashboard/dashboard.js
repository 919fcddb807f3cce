// swum-emu's live dashboard (docs/http-api.md "Dashboard"): the telemetry stream (server-sent
// events) into uPlot charts, the fault buttons, the recording and, in lockstep, a step button.
// Everything it loads comes from the emulator that serves it.
"use strict";

const HISTORY_POINTS = 1200;  // per series: 60 s at the default 20 Hz
const STREAM_RATE_HZ = 20;

// The token: from the page's address (#token=...), else asked for when the API says 401.
let token = new URLSearchParams(location.hash.slice(1)).get("token") || sessionStorage.getItem("swum-token") || "";

function withToken(path) {
  return token ? path + (path.includes("?") ? "&" : "?") + "token=" + encodeURIComponent(token) : path;
}

async function api(path, options = {}) {
  const sent = token;  // a 401 to a token already replaced (a request still on its way) is old news
  const headers = Object.assign({}, options.headers || {});
  if (token) headers["Authorization"] = "Bearer " + token;
  if (options.body !== undefined) headers["Content-Type"] = "application/json";
  const response = await fetch(path, Object.assign({}, options, { headers }));
  const text = await response.text();
  let body = null;
  try { body = text ? JSON.parse(text) : null; } catch (e) { body = { error: text }; }
  if (response.status === 401 && sent === token) askForToken(body && body.error);
  if (!response.ok) throw new Error((body && body.error) || response.status + " " + response.statusText);
  return body;
}

function askForToken(message) {
  document.getElementById("token-box").hidden = false;
  document.getElementById("token-error").textContent = message || "";
}

document.getElementById("token-apply").addEventListener("click", () => {
  token = document.getElementById("token").value.trim();
  sessionStorage.setItem("swum-token", token);
  document.getElementById("token-box").hidden = true;
  start();
});

// ---- charts -------------------------------------------------------------------------------
const charts = {};
const data = {};  // name -> [x[], y1[], y2[], ...]

// A value axis as wide as its longest label (uPlot's default 50 px cuts "10,000" to "0,000").
function valueAxisSize(self, values, axisIndex, cycle) {
  const axis = self.axes[axisIndex];
  if (cycle > 1) return axis._size;  // settle: do not grow again in the same layout
  const longest = (values || []).reduce((a, v) => (String(v).length > a.length ? String(v) : a), "");
  self.ctx.font = axis.font[0];
  const text = longest ? self.ctx.measureText(longest).width / devicePixelRatio : 0;
  return Math.max(50, Math.ceil(axis.ticks.size + axis.gap + text + 4));
}

function makeChart(name, series) {
  const element = document.getElementById("chart-" + name);
  const options = {
    width: Math.max(320, element.clientWidth || 420),
    height: 200,
    scales: { x: { time: false } },
    axes: [{ label: "emulated time (s)" }, { size: valueAxisSize }],
    series: [{ label: "t (s)" }].concat(series.map(([label, stroke]) => ({ label, stroke, width: 1.5 }))),
  };
  data[name] = [[]].concat(series.map(() => []));
  charts[name] = new uPlot(options, data[name], element);
  // Follow the panel's width (window resized, grid columns changed), else the canvas overflows.
  new ResizeObserver(() => {
    const width = Math.max(320, element.clientWidth);
    if (width !== charts[name].width) charts[name].setSize({ width, height: options.height });
  }).observe(element);
}

makeChart("speed", [["speed", "#2563eb"]]);
makeChart("frequency", [["drive", "#dc2626"], ["L1 peak", "#2563eb"], ["B2 peak", "#7c3aed"]]);
makeChart("current", [["phase A", "#0f766e"], ["phase B", "#b45309"]]);
makeChart("phase", [["V–I A", "#0f766e"], ["V–I B", "#b45309"]]);
makeChart("temperature", [["stator", "#be123c"]]);
makeChart("lateness", [["p99", "#4b5563"]]);

function push(name, x, values) {
  const d = data[name];
  d[0].push(x);
  values.forEach((v, i) => d[i + 1].push(v === null || v === undefined ? null : v));
  if (d[0].length > HISTORY_POINTS) d.forEach((column) => column.shift());
}

let redrawPending = false;
function redraw() {
  if (redrawPending) return;
  redrawPending = true;
  requestAnimationFrame(() => {
    redrawPending = false;
    for (const name in charts) charts[name].setData(data[name]);
  });
}

// ---- telemetry ----------------------------------------------------------------------------
let lastTick = -1;
let updates = 0;
const khz = (hz) => (hz / 1000).toFixed(3);

const fixed = (value, digits) => (value === null || value === undefined ? "–" : value.toFixed(digits));

function showOperatingPoint(s) {
  const drive = s.output.frequency_hz, normal = s.resonance.normal_peak_hz, tangential = s.resonance.tangential_peak_hz;
  document.getElementById("op-frequency").textContent = drive === null ? "–" : khz(drive);
  document.getElementById("op-amplitude-v").textContent = fixed(s.output.amplitude_v, 0);
  document.getElementById("op-normal").textContent = normal ? khz(normal) : "–";
  document.getElementById("op-tangential").textContent = tangential ? khz(tangential) : "–";
  if (!normal || !tangential || drive === null) return;
  const side = (peak, label) => label + (drive >= peak ? " +" : " ") + khz(drive - peak) + " kHz";
  document.getElementById("op-side").textContent =
    "drive − peak: " + side(normal, "L1") + ", " + side(tangential, "B2") +
    (drive >= Math.max(normal, tangential) ? " (above both: the side a softening resonance is swept from)" : "");
  const lo = Math.min(drive, normal, tangential) - 1000, hi = Math.max(drive, normal, tangential) + 1000;
  const place = (id, hz) => { document.getElementById(id).style.left = (100 * (hz - lo) / (hi - lo)) + "%"; };
  place("op-marker-drive", drive);
  place("op-marker-normal", normal);
  place("op-marker-tangential", tangential);
}

function show(s) {
  updates += 1;
  document.body.dataset.updates = String(updates);
  document.body.dataset.tick = String(s.tick);
  document.getElementById("state").textContent = s.state;
  document.getElementById("fault").textContent = s.fault;
  document.getElementById("fault-code").textContent = String(s.fault_code);
  // The CANopen node (--can-profile cia402): its NMT state and the CiA 402 drive's.
  const co = s.canopen;
  document.getElementById("canopen-row").hidden = !co;
  if (co) {
    const hex = (v) => "0x" + v.toString(16).toUpperCase().padStart(4, "0");
    document.getElementById("canopen-nmt").textContent = co.nmt;
    document.getElementById("canopen-state").textContent = co.cia402_state;
    document.getElementById("canopen-statusword").textContent = hex(co.statusword);
    document.getElementById("canopen-error").textContent = hex(co.error_code);
  }
  document.getElementById("sim-time").textContent = fixed(s.sim_time_s, 3);
  document.getElementById("clock").textContent = s.external_clock ? "external (lockstep)" : "internal";
  document.getElementById("step-box").hidden = !s.external_clock;
  document.getElementById("active-faults").textContent = s.active_faults.length ? s.active_faults.join(", ") : "none";
  showOperatingPoint(s);
  if (s.tick === lastTick) return;  // lockstep and not stepped: nothing new to plot
  lastTick = s.tick;
  const t = s.sim_time_s, e = s.electrical;
  push("speed", t, [s.speed_m_s === null ? null : s.speed_m_s * 1000]);
  const kilo = (hz) => (hz === null ? null : hz / 1000);
  push("frequency", t, [kilo(s.output.frequency_hz), kilo(s.resonance.normal_peak_hz), kilo(s.resonance.tangential_peak_hz)]);
  push("current", t, [e.current_a_a, e.current_b_a]);
  push("phase", t, [e.phase_a_deg, e.phase_b_deg]);
  push("temperature", t, [s.stator_temperature_c]);
  push("lateness", t, [s.loop.lateness_p99_ns / 1000]);
  document.body.dataset.points = String(data.speed[0].length);
  redraw();
}

let source = null;
function connect() {
  if (source) source.close();
  const badge = document.getElementById("connection");
  source = new EventSource(withToken("/api/v1/stream?rate_hz=" + STREAM_RATE_HZ));
  source.addEventListener("telemetry", (event) => {
    badge.textContent = "live";
    badge.className = "badge live";
    show(JSON.parse(event.data));
  });
  source.onerror = () => {
    badge.textContent = "reconnecting…";
    badge.className = "badge lost";
    // A refused stream (401, 503) closes the source: look at why, then try again.
    if (source.readyState === EventSource.CLOSED) {
      api("/api/v1/state").then(() => setTimeout(connect, 1000)).catch((e) => { badge.textContent = e.message; });
    }
  };
}

// ---- faults -------------------------------------------------------------------------------
// A value for each required key, so that one click starts a fault (docs/scenarios.md ranges).
const DEFAULTS = { duration_s: 1, factor: 0.5, sigma_um: 10, bias_mm_s: 5, sigma_mm_s: 1, delay_ms: 20 };

function faultMessage(text, isError) {
  const element = document.getElementById("fault-message");
  element.textContent = text;
  element.className = "message" + (isError ? " error" : "");
}

async function inject(request) {
  try {
    const reply = await api("/api/v1/faults", { method: "POST", body: JSON.stringify(request) });
    faultMessage("queued " + reply.queued + " after tick " + reply.after_tick, false);
  } catch (e) {
    faultMessage(e.message, true);
  }
}

function addButton(label, request) {
  const button = document.createElement("button");
  button.className = "fault";
  button.textContent = label;
  button.dataset.fault = label;
  button.addEventListener("click", () => inject(request));
  document.getElementById("fault-buttons").appendChild(button);
}

async function loadFaults() {
  const faults = await api("/api/v1/faults");
  document.getElementById("fault-buttons").textContent = "";
  for (const type of faults.types) {
    const request = { type: type.type };
    let phased = false;
    for (const key of type.keys) {
      if (!key.required) continue;
      if (key.kind === "phase") phased = true;
      else if (key.name in DEFAULTS) request[key.name] = DEFAULTS[key.name];
      else request[key.name] = key.min_exclusive ? key.max / 2 : key.min;
    }
    if (phased) {
      addButton(type.type + " A", Object.assign({ phase: "A" }, request));
      addButton(type.type + " B", Object.assign({ phase: "B" }, request));
    } else {
      addButton(type.type, request);
    }
  }
}

document.getElementById("clear-faults").addEventListener("click", async () => {
  try {
    await api("/api/v1/faults", { method: "DELETE" });
    faultMessage("cleared every fault", false);
  } catch (e) {
    faultMessage(e.message, true);
  }
});

// ---- recording and lockstep ----------------------------------------------------------------
async function refreshRecording() {
  try {
    const r = await api("/api/v1/recording");
    document.getElementById("record-status").textContent =
      (r.recording ? "recording: " : "") + r.rows + " rows" + (r.dropped ? ", " + r.dropped + " ticks dropped" : "") +
      (r.error ? " (" + r.error + ")" : "");
    const link = document.getElementById("record-download");
    link.href = withToken("/api/v1/recording.csv");
    link.hidden = !r.available;
  } catch (e) {
    document.getElementById("record-status").textContent = e.message;
  }
}

for (const [id, path] of [["record-start", "start"], ["record-stop", "stop"]]) {
  document.getElementById(id).addEventListener("click", async () => {
    try { await api("/api/v1/recording/" + path, { method: "POST", body: "{}" }); } catch (e) {
      document.getElementById("record-status").textContent = e.message;
      return;
    }
    refreshRecording();
  });
}

document.getElementById("step").addEventListener("click", async () => {
  const ticks = Number(document.getElementById("step-ticks").value);
  try { await api("/api/v1/step", { method: "POST", body: JSON.stringify({ ticks }) }); } catch (e) {
    faultMessage(e.message, true);
  }
});

async function start() {
  try {
    await loadFaults();
  } catch (e) {
    faultMessage(e.message, true);
    return;
  }
  connect();
  refreshRecording();
}

setInterval(refreshRecording, 2000);
start();

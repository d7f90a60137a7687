// The operator panel (src/app/panel/panel_server.hpp has the API). Everything on screen comes from
// /api/state and the session's event stream (/api/events, Server-Sent Events): a reload or a second
// browser replays the running session from its start and goes on live.
"use strict";

const token = new URLSearchParams(location.search).get("token");
const withToken = (path) =>
  token ? path + (path.includes("?") ? "&" : "?") + "token=" + encodeURIComponent(token) : path;
const $ = (id) => document.getElementById(id);
const pageLoadedMs = Date.now();

const state = {
  running: false,
  session: "",
  runCount: 0,
  plotRun: -1,
  outcome: null,
  latencies: [],  // ms from an event's time stamp to the frame that shows it (live events only)
  slowest: [],
};

function text(id, value) { $(id).textContent = value; }
function fmt(x, digits) { return x === null || x === undefined ? "—" : Number(x).toFixed(digits); }
function message(textValue, kind) {
  const m = $("message");
  m.textContent = textValue;
  m.dataset.kind = kind || "error";
}

// ---- the live plot: Chart.js from Debian's libjs-chart.js, served by the panel ----
const colours = ["#1f77b4", "#d62728", "#2ca02c", "#9467bd"];
const plot = new Chart($("plot").getContext("2d"), {
  type: "line",
  data: { datasets: [0, 1, 2, 3].map((i) => ({
    label: "y" + (i + 1), data: [], borderColor: colours[i], borderWidth: 1, pointRadius: 0 })) },
  options: {
    animation: false, parsing: false, normalized: true, responsive: false,
    scales: { x: { type: "linear", title: { display: true, text: "t (s) since release" } } },
  },
});
function plotReset(runId) {
  state.plotRun = runId;
  plot.data.datasets.forEach((d) => { d.data = []; });
  plot.update("none");
  $("plot").dataset.points = "0";
  $("plot").dataset.run = String(runId);
}
function plotSamples(e) {
  if (e.run_id !== state.plotRun) plotReset(e.run_id);
  for (let k = 0; k < e.t_s.length; ++k)
    for (let c = 0; c < 4; ++c) plot.data.datasets[c].data.push({ x: e.t_s[k], y: e.y[k][c] });
  plot.update("none");
  $("plot").dataset.points = String(plot.data.datasets[0].data.length);
}

// ---- session display ----
function resetSession(e) {
  state.session = e.session;
  state.outcome = null;
  state.running = true;
  text("unit", e.unit);
  text("session-name", e.session + (e.sequence ? " · " + e.sequence : "") +
       (e.limits ? " · limits " + e.limits : "") + (e.resume ? " · resumed" : ""));
  $("interrupted-box").hidden = true;
  $("outcome-box").hidden = true;
  $("outcome").dataset.kind = "";
  text("outcome", "—");
  text("outcome-reason", "");
  $("failed").innerHTML = "";
  $("bands").innerHTML = "";
  $("report-link").hidden = true;
  $("runs").tBodies[0].innerHTML = "";
  $("log").innerHTML = "";
  $("progress-bar").style.width = "0";
  plotReset(-1);
  $("abort").disabled = false;
}
function logLine(textValue, cls) {
  const li = document.createElement("li");
  li.textContent = textValue;
  if (cls) li.className = cls;
  $("log").appendChild(li);
  while ($("log").children.length > 200) $("log").firstChild.remove();
  $("log").scrollTop = $("log").scrollHeight;
}
function showProgress(e) {
  text("run", e.run > 0 ? e.run + " of " + e.run_count : "—");
  text("phase", e.phase);
  $("phase").dataset.phase = e.phase;
  text("omega", e.run > 0 ? fmt(e.omega_rad_s, 4) + " rad/s" : "—");
  if (e.type !== "progress") return;
  text("elapsed", fmt(e.elapsed_s, 1) + " s");
  text("remaining", "~" + fmt(e.remaining_s, 1) + " s");
  text("samples", e.samples + " / " + e.samples_expected);
  $("samples").dataset.samples = String(e.samples);
  text("drops", String(e.samples_lost));
  text("table-rate", e.table_rate_rad_s === null ? "—" : fmt(e.table_rate_rad_s, 5) + " rad/s");
  // Every run captured once the estimate begins (its progress event carries no run).
  const done = e.phase === "estimate" ? 1 : e.run_count > 0 ? (Math.max(e.run - 1, 0) +
      (e.samples_expected > 0 ? e.samples / e.samples_expected : 0)) / e.run_count : 0;
  $("progress-bar").style.width = (100 * Math.min(done, 1)).toFixed(1) + "%";
}
// One limit's decision as a small bar (the report draws the same: src/report/guard_band_bar.cpp):
// the tolerance, its guard bands shaded, the value with v ± k·u coloured by the zone. From the
// limit event, which is the record's outcome.verdict.limits[k]; null when there is nothing to draw.
function guardBandBar(e) {
  const fin = (v) => typeof v === "number" && isFinite(v);
  if (!fin(e.value) || !fin(e.min) || !fin(e.max)) return null;
  const hasInterval = fin(e.interval_min) && fin(e.interval_max);
  let lo = Math.min(e.min, e.value), hi = Math.max(e.max, e.value);
  if (hasInterval) { lo = Math.min(lo, e.interval_min); hi = Math.max(hi, e.interval_max); }
  const span = hi > lo ? hi - lo : Math.max(Math.abs(hi), 1);
  lo -= 0.05 * span; hi += 0.05 * span;
  const W = 240, x = (v) => 6 + (v - lo) / (hi - lo) * (W - 12);
  const colour = { conforming: "#1b7f3b", non_conforming: "#b3261e", undecided: "#c77700" }[e.zone]
    || "#555";
  const ns = "http://www.w3.org/2000/svg";
  const svg = document.createElementNS(ns, "svg");
  const add = (tag, attrs) => {
    const el = document.createElementNS(ns, tag);
    for (const [k, v] of Object.entries(attrs)) el.setAttribute(k, String(v));
    svg.appendChild(el);
    return el;
  };
  Object.entries({ class: "guard-band", width: W, height: 20, viewBox: "0 0 " + W + " 20" })
    .forEach(([k, v]) => svg.setAttribute(k, String(v)));
  svg.dataset.quantity = e.quantity;
  svg.dataset.zone = e.zone || "not_recorded";
  add("rect", { class: "tolerance", x: x(e.min), y: 4, width: Math.max(x(e.max) - x(e.min), 1),
    height: 12, fill: "#e3f1e6", stroke: "#1b7f3b" });
  if (fin(e.acceptance_min) && fin(e.acceptance_max)) {
    const empty = e.acceptance_min > e.acceptance_max;
    const a = empty ? e.max : Math.min(Math.max(e.acceptance_min, e.min), e.max);
    const b = empty ? e.max : Math.min(Math.max(e.acceptance_max, e.min), e.max);
    for (const [from, to] of [[e.min, a], [b, e.max]])
      if (x(to) - x(from) >= 0.05)
        add("rect", { class: "guard", x: x(from), y: 4, width: x(to) - x(from), height: 12,
          fill: "#f6d9a8" });
  }
  if (hasInterval) {
    add("line", { class: "interval", x1: x(e.interval_min), x2: x(e.interval_max), y1: 10, y2: 10,
      stroke: colour, "stroke-width": 2 });
    for (const end of [e.interval_min, e.interval_max])
      add("line", { x1: x(end), x2: x(end), y1: 5, y2: 15, stroke: colour, "stroke-width": 2 });
  }
  add("circle", { class: "value", cx: x(e.value), cy: 10, r: 3.5, fill: colour });
  const row = document.createElement("div");
  const label = document.createElement("span");
  label.textContent = e.quantity + " = " + Number(e.value).toPrecision(4) +
    (hasInterval ? " ± " + Number(e.expanded_uncertainty).toPrecision(2) +
      " (k = " + e.coverage_factor + ")" : "") +
    (e.zone ? " · " + e.zone.replace("_", " ") : "");
  row.append(label, svg);
  return row;
}

function showOutcome(kind, reason) {
  state.outcome = kind;
  $("outcome-box").hidden = false;
  $("outcome").dataset.kind = kind;
  text("outcome", kind);
  text("outcome-reason", reason);
}
function ended(e) {
  closePrompt();
  state.running = false;
  $("abort").disabled = true;
  if (!state.outcome)
    showOutcome("ERROR", "the session ended without an outcome (" +
      (e.exit_code !== undefined ? "exit code " + e.exit_code : "signal " + e.signal) + ")");
  loadState();
}

// ---- operator prompts: a modal dialog while the session waits for the operator ----
let openPrompt = null;
function showPrompt(e) {
  openPrompt = e.id;
  text("prompt-at", "(" + e.at + ")");
  text("prompt-text", e.text);
  const image = $("prompt-image");
  image.hidden = !e.image;
  if (e.image) image.src = e.image; else image.removeAttribute("src");
  $("prompt-operator").value = $("operator").value.trim();
  text("prompt-message", "");
  $("prompt-dialog").dataset.id = e.id;
  if (!$("prompt-dialog").open) $("prompt-dialog").showModal();
  logLine("operator prompt (" + e.at + "): " + e.text);
}
function closePrompt() {
  openPrompt = null;
  if ($("prompt-dialog").open) $("prompt-dialog").close();
}
async function answerPrompt(answer) {
  if (openPrompt === null) return;
  const operator = $("prompt-operator").value.trim();
  if (!operator) { text("prompt-message", "enter or scan your operator id to answer"); return; }
  if (answer === "abort" && !confirm("Abort the session? The table stays at zero rate and the " +
                                     "record says who aborted it.")) return;
  const r = await post("api/prompt", { id: openPrompt, answer, operator });
  if (!r.ok) text("prompt-message", r.reply.error || "refused (HTTP " + r.status + ")");
}
$("prompt-confirm").addEventListener("click", () => answerPrompt("confirm"));
$("prompt-abort").addEventListener("click", () => answerPrompt("abort"));
// Escape would hide the dialog and leave the session waiting unseen: answering is the only way.
$("prompt-dialog").addEventListener("cancel", (ev) => ev.preventDefault());

const handlers = {
  panel_session: (e) => { closePrompt(); resetSession(e); },
  prompt: showPrompt,
  prompt_answered: (e) => {
    logLine("prompt " + e.id + ": " + (e.answer === "confirm" ? "confirmed" : "aborted") +
            (e.by ? " by " + e.by : ""));
    closePrompt();
  },
  panel_abort: () => { logLine("abort requested by the operator: table to zero, gyro safe"); },
  panel_exit: ended,
  session_started: (e) => { state.runCount = e.plan.length; text("run", "0 of " + e.plan.length); },
  phase: showProgress,
  progress: showProgress,
  samples: plotSamples,
  log: (e) => logLine(e.message),
  warning: (e) => logLine("warning: " + e.message, "warning"),
  run_result: (e) => {
    const row = $("runs").tBodies[0].insertRow();
    row.dataset.run = String(e.run_id);
    [e.run_id, e.status, e.samples + " / " + e.samples_expected, fmt(e.omega_rad_s, 6), e.reason]
      .forEach((v) => { row.insertCell().textContent = v; });
  },
  estimate: () => {},
  limit: (e) => {
    const bar = guardBandBar(e);
    if (bar) $("bands").appendChild(bar);
    if (e.status !== "FAIL") return;
    const li = document.createElement("li");
    li.textContent = e.message || e.quantity;
    li.dataset.quantity = e.quantity;
    $("failed").appendChild(li);
  },
  outcome: (e) => showOutcome(e.outcome, e.reason),
  report: (e) => {
    if (!e.path || !state.session) return;
    const a = $("report-link");
    a.href = withToken("sessions/" + encodeURIComponent(state.session) + "/report/report.html");
    a.hidden = false;
  },
  end: (e) => { if (e.events_lost > 0) logLine("the panel missed " + e.events_lost + " events"); },
};

function onEvent(raw) {
  let e;
  try { e = JSON.parse(raw.data); } catch (err) { return; }
  const handler = handlers[e.type];
  if (handler) handler(e);
  Station.onEvent(e);  // panel_station.js: the plan, a fixture's units, not judged
  document.body.dataset.lastEvent = e.type;
  // Latency: from the event's stamp (the bench's wall clock, ms) to the frame that shows it.
  if (typeof e.time_unix_s === "number" && e.time_unix_s * 1000 >= pageLoadedMs) {
    requestAnimationFrame(() => {
      const ms = Date.now() - e.time_unix_s * 1000;
      state.latencies.push(ms);
      // The slowest few, with their type, say where the time goes.
      state.slowest.push({ type: e.type, ms });
      state.slowest.sort((a, b) => b.ms - a.ms);
      state.slowest.length = Math.min(state.slowest.length, 8);
      document.body.dataset.latencySlowest = JSON.stringify(state.slowest);
      const sorted = state.latencies.slice().sort((a, b) => a - b);
      document.body.dataset.latencyCount = String(sorted.length);
      document.body.dataset.latencyMedianMs = String(sorted[Math.floor(sorted.length / 2)]);
      document.body.dataset.latencyP95Ms = String(sorted[Math.floor(sorted.length * 0.95)]);
      document.body.dataset.latencyMaxMs = String(sorted[sorted.length - 1]);
    });
  }
}

function connect() {
  const source = new EventSource(withToken("api/events"));
  source.onopen = () => { $("connection").dataset.state = "open"; text("connection", "live"); };
  source.onerror = () => { $("connection").dataset.state = "lost"; text("connection", "reconnecting"); };
  source.onmessage = onEvent;
}

// ---- state, start, abort ----
async function loadState() {
  const res = await fetch(withToken("api/state"));
  const s = await res.json();
  if (!res.ok) { message(s.error || "the panel refused"); return; }
  text("station", s.station + " (" + s.station_kind + ")");
  const fill = (select, items, none) => {
    const keep = select.value;
    select.innerHTML = "";
    if (none) select.add(new Option("none", ""));
    items.forEach((i) => select.add(new Option(i.name + (i.description ? " — " + i.description : ""), String(i.id))));
    if (keep && [...select.options].some((o) => o.value === keep)) select.value = keep;
  };
  if ($("sequence").options.length === 0) {
    // The station's defaults (its [offers]), never merely the first by name; "none" only when
    // the station offers a session without limits.
    fill($("sequence"), s.sequences, false);
    fill($("limits"), s.limits, s.no_limits);
    $("sequence").value = String(s.default_sequence);
    if (s.default_limits !== null) $("limits").value = String(s.default_limits);
  }
  Station.onState(s);
  // A session whose process died with its record open: say why and offer to continue it.
  const i = s.interrupted;
  $("interrupted-box").hidden = !i || s.session?.running;
  if (i) text("interrupted-reason", (i.unit === "fixture" ? "Fixture session " + i.session
                                      : "Session " + i.session + " (unit " + i.unit + ")") +
              " was interrupted: " + i.reason + ".");
  // Its record has no outcome yet (not ERROR: the resume judges it).
  if (i && !s.session?.running && state.session === i.session)
    showOutcome("INTERRUPTED", "not closed: the record is open until it is resumed");
  $('recent-source').textContent = 'from ' + (s.recent_source ?? 'the sessions folder');
  const body = $("recent").tBodies[0];
  body.innerHTML = "";
  for (const r of s.recent) {
    const row = body.insertRow();
    row.dataset.session = r.name;
    row.insertCell().textContent = r.name;
    row.insertCell().textContent = r.unit ?? "";
    const o = row.insertCell();
    o.textContent = r.outcome ?? "not closed";
    o.className = r.outcome ?? "";
    row.insertCell().textContent = r.reason ?? "";
    const link = row.insertCell();
    if (r.report) {
      const a = document.createElement("a");
      a.href = withToken(r.report);
      a.textContent = "report";
      link.appendChild(a);
    }
  }
  document.body.dataset.stateLoaded = "true";
}

async function post(path, body) {
  const res = await fetch(withToken(path), {
    method: "POST", headers: { "Content-Type": "application/json" }, body: JSON.stringify(body) });
  let reply = {};
  try { reply = await res.json(); } catch (err) { reply = { error: "HTTP " + res.status }; }
  return { ok: res.ok, status: res.status, reply };
}

$("start").addEventListener("click", async () => {
  const limits = $("limits").value;
  const units = Station.startBody();  // {serial | serials, operator} or {error}
  if (units.error) { message(units.error); return; }
  const r = await post("api/start", Object.assign(units, {
    sequence: Number($("sequence").value),
    limits: limits === "" ? null : Number(limits),
  }));
  if (r.ok) {
    message("started " + r.reply.session, "info");
    $("serial").value = "";
    Station.afterStart();
  } else {
    message(r.reply.error || "refused (HTTP " + r.status + ")");
  }
});
$("serial").addEventListener("keydown", (ev) => { if (ev.key === "Enter") $("start").click(); });
$("resume").addEventListener("click", async () => {
  const operator = $("operator").value.trim();
  const r = await post("api/resume", operator ? { operator } : {});
  if (r.ok) {
    message("resuming " + r.reply.session, "info");
    $("interrupted-box").hidden = true;
  } else {
    message(r.reply.error || "refused (HTTP " + r.status + ")");
  }
});
$("abort").addEventListener("click", async () => {
  if (!confirm("Abort the session? The table goes to zero rate and the gyro to its safe state; " +
               "the record says it was aborted by the operator.")) return;
  const r = await post("api/abort", {});
  message(r.ok ? "aborting: table to zero, gyro safe" : (r.reply.error || "refused"),
          r.ok ? "info" : "error");
});

loadState().then(connect);

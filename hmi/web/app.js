// ncplc HMI front end: plain JS, no build step. Talks to the JSON API (hmi/API.md) and /ws.
"use strict";

const OFFSET = { A: 0, K: 128, N: 1152, T: 2176 };
const LEN = { A: 128, K: 1024, N: 1024, T: 64 };
const token = new URLSearchParams(location.search).get("token");
const state = {
  page: "signals", snap: null, image: new Uint8Array(0), names: [], program: null,
  readonly: false, frames: 0, fps: 0, forced: new Map(),
};

// ---- helpers ---------------------------------------------------------------------------------
function headers(extra) {
  const h = Object.assign({}, extra || {});
  if (token) h["Authorization"] = "Bearer " + token;
  return h;
}
async function api(method, path, body) {
  const opts = { method, headers: headers(body ? { "Content-Type": "application/json" } : {}) };
  if (body) opts.body = JSON.stringify(body);
  const r = await fetch(path, opts);
  const j = await r.json();
  if (!r.ok) throw new Error(j.error || r.statusText);
  return j;
}
function message(text, ok) {
  const m = document.getElementById("message");
  m.textContent = text;
  m.className = ok ? "ok" : "";
  m.hidden = !text;
}
// Parses I0A3 / U4A0 / W14K0 into {byte, bit} (bit null for a byte signal).
function parseAddr(s) {
  let m = /^([IU])(\d+)([AKNT])(\d+)$/.exec(s);
  if (m) {
    const c = +m[2], n = +m[4];
    return { byte: OFFSET[m[3]] + c * 4 + (n >> 3), bit: n & 7, packet: m[3] };
  }
  m = /^W(\d+)([AKNT])([0-3])$/.exec(s);
  if (m) return { byte: OFFSET[m[2]] + (+m[1]) * 4 + (+m[3]), bit: null, packet: m[2] };
  return null;
}
function readAddr(s) {
  const a = parseAddr(s);
  if (!a || a.byte >= state.image.length) return null;
  const b = state.image[a.byte];
  return a.bit === null ? b : (b >> a.bit) & 1;
}
function storageKey(s) {
  const a = parseAddr(s);
  return a ? a.byte + ":" + a.bit : s;
}
function hexToBytes(hex) {
  const out = new Uint8Array(hex.length / 2);
  for (let i = 0; i < out.length; i++) out[i] = parseInt(hex.substr(i * 2, 2), 16);
  return out;
}
function el(tag, attrs, ...kids) {
  const e = document.createElement(tag);
  for (const [k, v] of Object.entries(attrs || {})) {
    if (k === "class") e.className = v; else if (k.startsWith("on")) e.addEventListener(k.slice(2), v); else e.setAttribute(k, v);
  }
  for (const k of kids) e.append(k);
  return e;
}

// ---- pages -----------------------------------------------------------------------------------
function showPage(p) {
  state.page = p;
  for (const b of document.querySelectorAll("nav button")) b.classList.toggle("active", b.dataset.page === p);
  for (const s of document.querySelectorAll(".page")) s.hidden = s.id !== "page-" + p;
  if (p === "trace") ensureChart();
  render();
}

// Signals -------------------------------------------------------------------------------------
let signalRows = [];
function buildSignalRows() {
  const q = document.getElementById("search").value.trim().toUpperCase();
  const tbody = document.querySelector("#signals tbody");
  tbody.replaceChildren();
  signalRows = [];
  let list = state.names.filter(n => !q || n.name.includes(q) || n.signal.includes(q));
  if (q && parseAddr(q) && !list.some(n => n.signal === q)) list = [{ name: "", signal: q, origin: "address", meaning: "" }].concat(list);
  for (const n of list.slice(0, 400)) {
    const val = el("span", { class: "val" });
    const mark = el("span");
    const input = el("input", { value: "1", "aria-label": "value for " + n.signal });
    const row = el("tr", { "data-signal": n.signal },
      el("td", {}, n.name), el("td", {}, n.signal), el("td", {}, n.origin),
      el("td", {}, val), el("td", {}, mark),
      el("td", {}, input,
        el("button", { class: "write", onclick: () => setSignal("write", n.signal, input.value) }, "Write"),
        el("button", { class: "force", onclick: () => setSignal("force", n.signal, input.value) }, "Force"),
        el("button", { class: "unforce", onclick: () => unforce(n.signal) }, "Unforce")),
      el("td", {}, n.meaning));
    tbody.append(row);
    signalRows.push({ signal: n.signal, val, mark, cell: val.parentElement });
  }
}
function renderSignals() {
  const bytesView = document.querySelector("input[name=view]:checked").value === "bytes";
  document.getElementById("signals").hidden = bytesView;
  document.getElementById("bytes").hidden = !bytesView;
  if (bytesView) return renderBytes();
  for (const r of signalRows) {
    const v = readAddr(r.signal);
    const text = v === null ? "?" : String(v);
    if (r.val.textContent !== text) r.val.textContent = text;
    r.cell.classList.toggle("v1", v === 1);
    const f = state.forced.get(storageKey(r.signal));
    const ftext = f === undefined ? "" : "F=" + f;
    if (r.mark.textContent !== ftext) { r.mark.textContent = ftext; r.mark.className = ftext ? "forced" : ""; }
  }
}
function renderBytes() {
  const p = document.getElementById("bytes-packet").value;
  const tbody = document.querySelector("#bytes tbody");
  const rows = LEN[p] / 4;
  if (tbody.dataset.packet !== p) {
    tbody.replaceChildren();
    for (let c = 0; c < rows; c++) {
      const tr = el("tr", {}, el("td", {}, p + c));
      for (let b = 0; b < 4; b++) tr.append(el("td", { "data-w": "W" + c + p + b }));
      tbody.append(tr);
    }
    tbody.dataset.packet = p;
  }
  for (const td of tbody.querySelectorAll("td[data-w]")) {
    const a = parseAddr(td.dataset.w);
    const b = state.image[a.byte] || 0;
    const text = b.toString(16).padStart(2, "0") + " " + b.toString(2).padStart(8, "0");
    if (td.textContent !== text) td.textContent = text;
  }
}
async function setSignal(kind, signal, value) {
  const v = Number(value);
  if (!Number.isInteger(v)) return message(signal + ": the value must be a whole number");
  if (kind === "force" && signal.startsWith("U") && autoMode() &&
      !window.confirm("The machine is in AUTO. Force output " + signal + " = " + v + "?")) return;
  try {
    const r = await api("POST", "/api/" + kind, { signal, value: v });
    message(kind + " " + r.signal + " = " + r.value + " at tick " + r.tick, true);
  } catch (e) { message(e.message); }
}
async function unforce(signal) {
  try { const r = await api("DELETE", "/api/force/" + encodeURIComponent(signal)); message("unforced " + r.signal + " at tick " + r.tick, true); }
  catch (e) { message(e.message); }
}
function autoMode() {
  const ps = (state.snap && state.snap.machine.processes) || [];
  return ps.some(p => p.mode && /auto/i.test(p.mode));
}

// Program -------------------------------------------------------------------------------------
let sourceRows = [];
function buildProgram() {
  const pre = document.getElementById("source");
  pre.replaceChildren();
  sourceRows = [];
  document.getElementById("program-file").textContent = state.program.file;
  for (const l of state.program.lines) {
    const vals = el("span", { class: "sv" });
    const line = el("span", { class: "line" }, el("span", { class: "ln" }, String(l.line)), l.text, vals);
    pre.append(line, "\n");
    sourceRows.push({ l, line, vals });
  }
}
function renderProgram() {
  if (!state.snap) return;
  document.getElementById("online").textContent = state.snap.online;
  // Power flow from the scan: [line, value] per statement; a line's last one is its rung.
  const flow = new Map();
  for (const [line, v] of (state.snap.flow || [])) {
    if (!flow.has(line)) flow.set(line, []);
    flow.get(line).push(v);
  }
  const note = document.getElementById("flow-note");
  const on = !!state.snap.flow_enabled, has = (state.snap.flow || []).length > 0;
  if (note) { note.hidden = on === has; note.textContent = on ? "(compiling…)" : "(switching off…)"; }
  const toggle = document.getElementById("flow-toggle");
  if (toggle && document.activeElement !== toggle) toggle.checked = on;
  for (const r of sourceRows) {
    const parts = [];
    const fv = flow.get(r.l.line);
    if (fv) parts.push("⇒ " + fv.join(" "));
    for (const s of r.l.writes) parts.push(s + "=" + readAddr(s));
    if (r.l.reads.length) parts.push("← " + r.l.reads.map(s => s + "=" + readAddr(s)).join(" "));
    const text = parts.join("  ");
    if (r.vals.textContent !== text) r.vals.textContent = text;
    if (fv) {
      r.line.className = "line " + (fv[fv.length - 1] !== 0 ? "on" : "off");
    } else if (r.l.writes.length) {
      const on = r.l.writes.some(s => readAddr(s) > 0);
      r.line.className = "line " + (on ? "on" : "off");
    }
  }
}

// Trace ---------------------------------------------------------------------------------------
const trace = { chart: null, signals: [], ticks: [], data: [], armed: false, frozen: false, trigPrev: null, postLeft: 0, cap: 2000 };
function traceSignals() {
  return document.getElementById("trace-signals").value.split(",").map(s => s.trim()).filter(s => parseAddr(s));
}
function ensureChart() {
  const sigs = traceSignals();
  if (trace.chart && sigs.join() === trace.signals.join()) return;
  if (typeof uPlot === "undefined") return;
  if (trace.chart) trace.chart.destroy();
  trace.signals = sigs;
  trace.ticks = [];
  trace.data = sigs.map(() => []);
  const series = [{ label: "tick" }].concat(sigs.map((s, i) => ({
    label: s, stroke: ["#2680c2", "#d64545", "#3ebd93", "#f0b429", "#7b61ff", "#52606d"][i % 6],
    paths: uPlot.paths.stepped({ align: 1 }), value: (u, v) => v === null ? "" : String(v - 2 * (sigs.length - 1 - i)),
  })));
  trace.chart = new uPlot({ width: Math.max(600, window.innerWidth - 60), height: 80 + 50 * Math.max(1, sigs.length),
    scales: { x: { time: false } }, axes: [{}, { show: false }], series }, [[]].concat(sigs.map(() => [])), document.getElementById("chart"));
}
function traceSample() {
  if (!trace.chart || trace.frozen || !state.snap) return;
  const t = state.snap.tick;
  if (trace.ticks.length && trace.ticks[trace.ticks.length - 1] === t) return;
  trace.ticks.push(t);
  const n = trace.signals.length;
  trace.signals.forEach((s, i) => {
    const v = readAddr(s);
    // Digital lanes stacked: lane i at offset 2*(n-1-i); bytes are drawn scaled to one lane.
    const a = parseAddr(s);
    const lane = a.bit === null ? v / 255 : v;
    trace.data[i].push(lane + 2 * (n - 1 - i));
  });
  if (trace.armed) {
    const trig = document.getElementById("trigger").value.trim();
    const v = readAddr(trig);
    const rising = document.getElementById("edge").value === "rising";
    if (trace.postLeft > 0) {
      if (--trace.postLeft === 0) freeze();
    } else if (trace.trigPrev !== null && v !== null && ((rising && trace.trigPrev === 0 && v === 1) || (!rising && trace.trigPrev === 1 && v === 0))) {
      trace.postLeft = Math.max(1, +document.getElementById("post").value);
      trace.trigTick = t;
      document.getElementById("trace-state").textContent = "triggered at tick " + t;
    }
    trace.trigPrev = v;
  }
  const keep = trace.armed ? (+document.getElementById("pre").value + (+document.getElementById("post").value) + 1) : trace.cap;
  while (trace.ticks.length > keep) { trace.ticks.shift(); for (const d of trace.data) d.shift(); }
  trace.chart.setData([trace.ticks.slice()].concat(trace.data.map(d => d.slice())));
}
function freeze() {
  trace.frozen = true;
  trace.armed = false;
  document.getElementById("trace-state").textContent = "stopped: window around tick " + trace.trigTick;
}
// The window as a trace file: one record per sampled tick where a value changed (sampled at the
// publish rate, so it shows what the HMI saw; `ncplc run --record` gives every tick).
function saveWindow() {
  const lines = [JSON.stringify({ format: "ncplc-trace", version: 1, tick_ms: (state.snap && state.snap.tick_ms) || 10 })];
  const t0 = trace.ticks[0] || 0;
  const prev = {};
  trace.ticks.forEach((t, k) => {
    const rec = { t: t - t0 };
    const ins = {}, outs = {};
    trace.signals.forEach((s, i) => {
      const n = trace.signals.length;
      const a = parseAddr(s);
      let v = trace.data[i][k] - 2 * (n - 1 - i);
      v = a.bit === null ? Math.round(v * 255) : Math.round(v);
      if (prev[s] !== v) { (s.startsWith("U") ? outs : ins)[s] = v; prev[s] = v; }
    });
    if (Object.keys(ins).length) rec.in = ins;
    if (Object.keys(outs).length) rec.out = outs;
    if (rec.in || rec.out || k === trace.ticks.length - 1) lines.push(JSON.stringify(rec));
  });
  const a = el("a", { href: URL.createObjectURL(new Blob([lines.join("\n") + "\n"], { type: "application/x-ndjson" })), download: "window.jsonl" });
  document.body.append(a); a.click(); a.remove();
}

// Machine -------------------------------------------------------------------------------------
const MODES = ["AUTO", "STEP", "MDI", "MANU", "MANJ", "HOME"];
let machineBuilt = "";
const paths = new Map(); // process → { id, axes, programmed, actual, fetching, tick }
function alarmItems(list) {
  return list.map(a => el("li", { class: (a.active ? "active" : "gone") + (a.acknowledged ? " acked" : "") },
    a.text + " (tick " + a.tick + (a.active ? "" : ", gone") + (a.acknowledged ? ", acknowledged" : "") + ")"));
}
// A PLC message (docs/plc-messages.md): process, number, text, tick, state.
function messageItems(list) {
  return list.map(m => el("li", { class: (m.active ? "active" : "gone") + (m.acknowledged ? " acked" : ""), "data-number": m.number },
    "P" + m.process + " #" + m.number + ": " + m.text + " (tick " + m.tick + (m.active ? "" : ", gone") + (m.acknowledged ? ", acknowledged" : "") + ")"));
}
function buildMachine(ps) {
  const div = document.getElementById("processes");
  div.replaceChildren();
  for (const p of ps) {
    const mdi = el("input", { class: "mdi-line", placeholder: "MDI block, e.g. G01 X-40 F200", size: 30 });
    const mode = el("select", { class: "mode-select" }, ...MODES.map(m => el("option", {}, m)));
    const span = c => el("span", { class: c });
    div.append(el("div", { class: "proc", id: "proc-" + p.process },
      el("h3", {}, "Process " + p.process + " ", span("state")),
      el("div", { class: "info" }),
      el("div", { class: "facts" },
        "mode ", span("mode"), " · program ", span("program"), " · block ", span("block"),
        " ", el("code", { class: "source" }), el("br"),
        "path speed ", span("speed"), " mm/min · spindle ", span("spindle"), " rev/min · codes ", span("codes"), " · modal ", span("modal")),
      el("table", { class: "dro" }),
      el("div", { class: "cmds" },
        el("button", { class: "start", onclick: () => command(p.process, { command: "start" }) }, "START"),
        el("button", { class: "hold", onclick: () => command(p.process, { command: "hold" }) }, "FEED HOLD"),
        el("button", { class: "reset", onclick: () => command(p.process, { command: "reset" }) }, "RESET"),
        mode, el("button", { class: "set-mode", onclick: () => command(p.process, { command: "mode", mode: mode.value }) }, "Mode"),
        mdi, el("button", { class: "mdi", onclick: () => command(p.process, { command: "mdi", line: mdi.value }) }, "MDI")),
      el("div", { class: "alarm-box" }, el("ul", { class: "alarms" }),
        el("button", { class: "ack", onclick: () => command(p.process, { command: "ack" }) }, "Acknowledge")),
      el("canvas", { class: "toolpath", width: 560, height: 320, hidden: "" })));
  }
}
function setText(box, css, text) {
  const e = box.querySelector(css);
  if (e && e.textContent !== text) e.textContent = text;
}
function renderMachine() {
  if (!state.snap) return;
  const ps = state.snap.machine.processes;
  const key = ps.map(p => p.process).join();
  if (key !== machineBuilt) { buildMachine(ps); machineBuilt = key; }
  const wide = document.getElementById("machine-alarms");
  const wideKey = JSON.stringify(state.snap.alarms);
  if (wide.dataset.key !== wideKey) { wide.replaceChildren(...alarmItems(state.snap.alarms)); wide.dataset.key = wideKey; }
  const msgs = document.getElementById("plc-messages");
  const msgKey = JSON.stringify(state.snap.messages);
  if (msgs.dataset.key !== msgKey) { msgs.replaceChildren(...messageItems(state.snap.messages || [])); msgs.dataset.key = msgKey; }
  for (const p of ps) {
    const box = document.getElementById("proc-" + p.process);
    const f = v => v === null || v === undefined ? "—" : String(v);
    const h = p.handshakes;
    const text = "F " + f(p.feed_override) + "% S " + f(p.spindle_override) + "% R " + f(p.rapid_override) + "%" +
      (p.on === null || p.on === undefined ? "" : " · " + (p.on ? "on" : "OFF") + (p.homed ? ", homed" : ", not homed")) +
      (h ? " · M/S/T done " + h.m + "/" + h.s + "/" + h.t + ", timeouts " + h.timeouts : "");
    setText(box, ".info", text);
    setText(box, ".state", f(p.state));
    setText(box, ".mode", f(p.mode));
    setText(box, ".program", f(p.program));
    setText(box, ".block", p.block_index === null || p.block_index === undefined ? "—" :
      (p.block === null ? "" : "N" + p.block + " ") + "(" + p.block_index + ")");
    setText(box, ".source", p.block_source || "");
    setText(box, ".speed", p.path_speed === null || p.path_speed === undefined ? "—" : p.path_speed.toFixed(1));
    setText(box, ".spindle", p.spindle_speed === null || p.spindle_speed === undefined ? "—" : p.spindle_speed.toFixed(0));
    setText(box, ".codes", p.active_codes.join(" "));
    setText(box, ".modal", p.modal_codes.join(" "));
    const dro = box.querySelector(".dro");
    const rows = p.axes.map(a => "<tr data-axis=\"" + a.name + "\"><td>" + a.name + "</td><td class=\"cmd\">" + a.command.toFixed(3) + "</td><td class=\"act\">" +
      a.actual.toFixed(3) + "</td><td class=\"ferr\">" + a.following_error.toFixed(4) + "</td><td class=\"srv\">" +
      (a.limit ? a.limit + " " + (a.limit_mm > 0 ? a.limit_mm : "unchecked") : "—") + "</td><td class=\"largest\">" +
      a.largest.toFixed(4) + "</td></tr>").join("");
    const html = p.axes.length ? "<tr><th>axis</th><th>command</th><th>actual</th><th>following error</th><th>SRV limit</th><th>largest</th></tr>" + rows : "";
    if (dro.dataset.html !== html) { dro.innerHTML = html; dro.dataset.html = html; }
    const ul = box.querySelector(".alarms");
    const akey = JSON.stringify(p.alarms);
    if (ul.dataset.key !== akey) { ul.replaceChildren(...alarmItems(p.alarms)); ul.dataset.key = akey; }
    box.classList.toggle("alarm", p.alarms.some(a => a.active));
    drawToolpath(p, box.querySelector("canvas.toolpath"));
  }
}
// The tool path: the plan's pieces (rapids dashed) fetched when the program changes, the set
// points sampled by the runtime, and the live set point appended from every frame.
function drawToolpath(p, c) {
  if (p.toolpath === null || p.toolpath === undefined) return;
  let tp = paths.get(p.process);
  if ((!tp || tp.id !== p.toolpath) && !(tp && tp.fetching)) {
    const fetching = { id: tp ? tp.id : null, fetching: true };
    paths.set(p.process, fetching);
    api("GET", "/api/toolpath/" + p.process).then(t => { t.tick = -1; paths.set(p.process, t); })
      .catch(e => { paths.delete(p.process); message(e.message); });
    return;
  }
  if (!tp || tp.fetching || tp.tick === state.snap.tick) return;
  tp.tick = state.snap.tick;
  const ax = n => p.axes.find(a => a.name === n);
  const h = ax(tp.axes[0]), v = ax(tp.axes[1]);
  if (h && v) {
    const last = tp.actual[tp.actual.length - 1];
    if (!last || last[0] !== h.command || last[1] !== v.command) tp.actual.push([h.command, v.command]);
    if (tp.actual.length > 8000) tp.actual.splice(0, tp.actual.length - 8000);
  }
  c.hidden = false;
  const g = c.getContext("2d");
  const pts = tp.programmed.flatMap(pc => pc.points).concat(tp.actual);
  if (!pts.length) return;
  let x0 = Infinity, x1 = -Infinity, y0 = Infinity, y1 = -Infinity;
  for (const [x, y] of pts) { x0 = Math.min(x0, x); x1 = Math.max(x1, x); y0 = Math.min(y0, y); y1 = Math.max(y1, y); }
  const m = 20, s = Math.min((c.width - 2 * m) / ((x1 - x0) || 1), (c.height - 2 * m) / ((y1 - y0) || 1));
  const X = x => m + (x - x0) * s, Y = y => c.height - m - (y - y0) * s;
  g.clearRect(0, 0, c.width, c.height);
  g.lineWidth = 1;
  for (const pc of tp.programmed) {
    g.strokeStyle = pc.rapid ? "#9aa5b1" : "#2680c2";
    g.setLineDash(pc.rapid ? [5, 4] : []);
    g.beginPath();
    pc.points.forEach(([x, y], k) => k ? g.lineTo(X(x), Y(y)) : g.moveTo(X(x), Y(y)));
    g.stroke();
  }
  g.setLineDash([]);
  g.strokeStyle = "#d64545"; g.lineWidth = 2;
  g.beginPath();
  tp.actual.forEach(([x, y], k) => k ? g.lineTo(X(x), Y(y)) : g.moveTo(X(x), Y(y)));
  g.stroke();
  const cur = tp.actual[tp.actual.length - 1];
  if (cur) { g.fillStyle = "#d64545"; g.beginPath(); g.arc(X(cur[0]), Y(cur[1]), 4, 0, 2 * Math.PI); g.fill(); }
  g.fillStyle = "#52606d"; g.font = "12px sans-serif";
  g.fillText(tp.axes[0] + " →   " + tp.axes[1] + " ↑   " + tp.program + " (blue feed, grey rapid, red set points)", 4, 12);
}
async function command(process, body) {
  try {
    const r = await api("POST", "/api/command", Object.assign({ process }, body));
    message(r.command.command + " applied at tick " + r.tick, true);
  } catch (e) { message(e.message); }
}

// ---- live data -------------------------------------------------------------------------------
function render() {
  if (state.page === "signals") renderSignals();
  else if (state.page === "program" && state.program) renderProgram();
  else if (state.page === "machine") renderMachine();
}
function onSnapshot(s) {
  state.snap = s;
  state.image = hexToBytes(s.image);
  state.forced = new Map(s.forced.map(f => [storageKey(f.signal), f.value]));
  state.frames++;
  const st = document.getElementById("status");
  st.textContent = "tick " + s.tick + " · " + s.engine + " · scan " + s.scan.scan_p50_us.toFixed(1) + " µs (max " + s.scan.scan_max_us.toFixed(1) +
    ") · overruns " + s.scan.overruns + " · " + state.fps + " Hz" + (s.alarms.length ? " · ALARM " + s.alarms.map(a => a.text).join("; ") : "") + (s.tripped ? " · SAFE STATE" : "");
  st.dataset.tick = s.tick;
  traceSample();
}
let rendering = false;
function frame() {
  render();
  requestAnimationFrame(frame);
}
function connect() {
  // ack=1: the server sends the next (latest) snapshot only after this page has taken the last one,
  // so a slow page skips snapshots instead of falling behind.
  const ws = new WebSocket((location.protocol === "https:" ? "wss://" : "ws://") + location.host + "/ws?ack=1" + (token ? "&token=" + encodeURIComponent(token) : ""));
  ws.onmessage = ev => { try { onSnapshot(JSON.parse(ev.data)); } finally { ws.send("ack"); } };
  ws.onclose = () => { document.getElementById("status").textContent = "disconnected; retrying…"; setTimeout(connect, 1000); };
}
async function start() {
  for (const b of document.querySelectorAll("nav button")) b.addEventListener("click", () => showPage(b.dataset.page));
  document.getElementById("search").addEventListener("input", buildSignalRows);
  document.getElementById("ack-all").addEventListener("click", async () => {
    try { const r = await api("POST", "/api/command", { command: "ack" }); message("alarms acknowledged at tick " + r.tick, true); } catch (e) { message(e.message); }
  });
  document.getElementById("unforce-all").addEventListener("click", async () => {
    try { await api("DELETE", "/api/force"); message("every force removed", true); } catch (e) { message(e.message); }
  });
  document.getElementById("trace-signals").addEventListener("change", ensureChart);
  document.getElementById("arm").addEventListener("click", () => {
    trace.armed = true; trace.frozen = false; trace.postLeft = 0; trace.trigPrev = null;
    document.getElementById("trace-state").textContent = "armed";
  });
  document.getElementById("run").addEventListener("click", () => { trace.armed = false; trace.frozen = false; document.getElementById("trace-state").textContent = "running"; });
  document.getElementById("save").addEventListener("click", saveWindow);
  document.getElementById("flow-toggle").addEventListener("change", async ev => {
    const enabled = ev.target.checked;
    try { const r = await api("POST", "/api/flow", { enabled }); message("power flow " + (enabled ? "on" : "off") + " from tick " + r.tick, true); } catch (e) { message(e.message); }
    ev.target.blur();
  });
  const [st, sg, pg] = await Promise.all([api("GET", "/api/status"), api("GET", "/api/signals"), api("GET", "/api/program")]);
  state.readonly = st.readonly;
  document.getElementById("readonly").hidden = !st.readonly;
  document.getElementById("machine").textContent = "ncplc · " + st.machine_name;
  state.names = sg.names;
  state.program = pg;
  const outs = state.names.filter(n => n.origin === "program").slice(0, 4).map(n => n.signal);
  document.getElementById("trace-signals").value = outs.join(",");
  buildSignalRows();
  buildProgram();
  setInterval(() => { state.fps = state.frames; state.frames = 0; }, 1000);
  connect();
  requestAnimationFrame(frame);
}
start().catch(e => message("HMI start: " + e.message));

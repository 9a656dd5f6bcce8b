// linkage app: the page over the JSON API of sim/front/app.py. No build step, no framework: uPlot draws the
// curves, a canvas draws the linkage. The last solve is kept in window.linkageState (the last simulation in
// window.linkageSimulation, the forces panel's answer in window.linkageForces, the dynamics panel's in
// window.linkageDynamics, the synthesis panel's in window.linkageSynthesis) and every redraw increments
// document.body.dataset.revision: tests and the latency benchmark wait on it.
"use strict";

(() => {
  const DEG = 180 / Math.PI;
  const SAMPLES = 361;
  const DRAG_DIGITS = 7;          // significant digits asked for while dragging: half the bytes to move
  const FIGURES_DELAY_MS = 250;   // figures of merit (50 ms - 2 s on the server) once the input settles
  const HOLD_MS = 300;            // the animation pauses this long after each edit
  const MAX_UPLOAD = 900000;
  const FEW_OUTPUTS = 24;         // up to this many outputs all are fetched; above, only the plotted ones
  // links' and curves' colours; red is the output point's path alone (the videos use the same: sim/output/drawing.py)
  const COLORS = ["#1f77b4", "#2ca02c", "#9467bd", "#ff7f0e", "#17becf", "#8c564b", "#e377c2", "#bcbd22"];
  const SIM_COLOR = "#111";
  const CHART_HEIGHT = 175;
  const ERROR_HEIGHT = 130;

  const $ = (sel) => document.querySelector(sel);
  const state = {
    mech: { name: null, text: null },   // a library name, or an uploaded file's text
    describe: null,
    set: {},                            // the values the user gave, by parameter name (as typed)
    ranges: {},                         // slider ranges from the defaults: they must not move under a drag
    lastEdited: null,
    inputRange: "",
    revolutions: 1,
    solve: null,
    sim: null,
    selected: [],
    charts: [],
    display: { deg: true, rpm: false },  // angles in deg (else rad), angular speeds in rpm; lengths: the file's
    frame: 0,
    playing: true,
    speed: 1,
    version: 0,                         // bumped by every edit; answers to older versions are dropped
    applied: -1,
    opened: 0,                          // the version at which the current mechanism was opened
    built: -1,                          // the `opened` the panels were built for
    geometry: null,
    holdUntil: 0,
    tab: "curves",                      // the right panel's tab: curves, forces, dynamics, synthesis
    loads: { gravity: null, force: null, cutting: null },   // SI, as the API takes them
    loadsDraw: null,                    // the file's [[loads]] as drawn (POST /api/loads/draw) and its version
    loadItems: [],
    loadEditing: null,                  // the name of the load the form edits (null: adding)
    forces: null,                       // the forces panel's last answer (with its "simulated" part)
    forcesVersion: -1,                  // the version it answers
    forceCharts: [],
    forceKey: "",
    dynamics: null,
    dynamicsCharts: [],
    synth: { targets: [], result: null, selected: 0, charts: [] },
    cam: { name: null, data: null, charts: [], changes: 0, draft: false },   // the cam panel: the cam shown and its last answer (POST /api/cam)
    draw: null,                         // the drawing on the empty page (null: not drawing)
    drag: null,                         // the point being dragged: {point, before, moved, input}
    undo: [],                           // snapshots before each drag or edit (values, file text, frame)
    editBefore: null,                   // the snapshot a slider or number-box edit started from
    redo: [],
  };

  // ------------------------------------------------------------------------------------------ api
  async function api(path, body) {
    const res = await fetch(path, {
      method: "POST",
      headers: { "Content-Type": "application/json" },
      body: JSON.stringify(body || {}),
    });
    if (!res.ok) {
      let message = `${res.status} ${res.statusText}`;
      try { message = (await res.json()).error || message; } catch (e) { /* not JSON: keep the status */ }
      throw new ApiError(message, res.status);
    }
    return res;
  }

  // Drag steps over a WebSocket (GET /api/socket, tornado's WebSocket in sim/front/app.py): a frame each way instead of an HTTP
  // request and answer, ~1 ms of round trip where fetch takes 4-7 ms. Opened when a drag starts (the server
  // closes it after 10 s idle); any request made while it is not open, or that it drops, goes by fetch.
  const sock = { ws: null, next: 1, waiting: new Map() };

  function socketOpen() {
    if (sock.ws || typeof WebSocket === "undefined") return;
    let ws;
    try { ws = new WebSocket(`ws://${location.host}/api/socket`); } catch (err) { return; }
    sock.ws = ws;
    ws.onmessage = (e) => {
      const m = JSON.parse(e.data);
      const w = sock.waiting.get(m.id);
      if (!w) return;
      sock.waiting.delete(m.id);
      if (m.status === 200) w.resolve(m.answer); else w.reject(new ApiError(m.error, m.status));
    };
    ws.onclose = () => {
      if (sock.ws === ws) sock.ws = null;
      for (const w of sock.waiting.values()) w.retry();     // dropped with the socket: asked again by fetch
      sock.waiting.clear();
    };
  }

  // The JSON answer of a POST to ``path``: over the socket when it is open, else by fetch.
  // ``sock.last``: how the last answer came ("socket" or "fetch"), for the drag's timing.
  function apiJson(path, body) {
    const ws = sock.ws;
    const fetched = () => api(path, body).then((res) => res.json()).then((data) => { sock.last = "fetch"; return data; });
    if (!ws || ws.readyState !== WebSocket.OPEN) return fetched();
    return new Promise((resolve, reject) => {
      const id = sock.next++;
      const retry = () => fetched().then(resolve, reject);
      sock.waiting.set(id, { resolve: (data) => { sock.last = "socket"; resolve(data); }, reject, retry });
      ws.send(JSON.stringify({ id, path, body: body || {} }));
    });
  }
  window.linkageSocket = sock;                  // for tests and the drag benchmark

  class ApiError extends Error {
    constructor(message, status) { super(message); this.status = status; }
  }

  function requestBody(extra) {
    const body = { set: { ...state.set } };
    if (state.mech.text !== null) body.text = state.mech.text; else body.mechanism = state.mech.name;
    if (state.inputRange.trim()) body.input_range = state.inputRange.trim();
    const r = Number(state.revolutions);
    body.revolutions = state.revolutions === "" || !Number.isFinite(r) ? state.revolutions : r;
    return Object.assign(body, extra || {});
  }

  // Two channels: "curves" answers each edit at once (one request in flight, the latest edit wins);
  // "full" adds the figures of merit once the edits have settled.
  const channels = { curves: { busy: false, queued: false }, full: { busy: false, queued: false, timer: 0 } };

  function edited() {
    state.version += 1;
    state.holdUntil = performance.now() + HOLD_MS;
    clearSimulation();
    staleDynamics();
    $("#video").hidden = true;             // a video of other values
    $("#figures").classList.add("pending");
    if (state.tab === "forces") $("#force-charts").classList.add("stale-fade");
    send("curves");
    const full = channels.full;
    clearTimeout(full.timer);
    full.timer = setTimeout(() => send("full"), FIGURES_DELAY_MS);
  }

  async function send(kind) {
    const ch = channels[kind];
    if (ch.busy) { ch.queued = true; return; }
    ch.busy = true;
    ch.queued = false;
    const version = state.version;
    const extra = kind === "full"
      ? { samples: SAMPLES, figures: true, outputs: wantedOutputs() }
      : { samples: SAMPLES, figures: false, digits: DRAG_DIGITS, outputs: wantedOutputs(true) };
    const current = () => version >= state.opened && version >= state.applied;
    // with the forces panel open, each edit's forces are asked for at once and drawn with its curves
    const forcesToo = kind === "curves" && state.tab === "forces" && state.built === state.opened;
    try {
      const started = performance.now();
      const forcesAnswer = forcesToo ? fetchForces(version) : null;
      const res = await api("/api/solve", requestBody(extra));
      const data = await res.json();
      const forces = forcesAnswer ? await forcesAnswer : null;
      const received = performance.now();
      let drawn = false;
      if (current() && !(kind === "curves" && version === state.applied)) {
        applySolve(data, version, kind === "full", false);
        drawn = true;
      }
      if (forces && version >= state.forcesVersion && version >= state.opened && state.solve) {
        applyForces(forces, version);
        drawn = true;
      }
      if (drawn) {
        bumpRevision();
        const done = performance.now();
        window.linkageTiming = { kind, request_ms: received - started, draw_ms: done - received, forces: !!forces };
        status(`${data.mechanism}: solved and drawn in ${Math.round(done - started)} ms`
          + (forces ? " (with the joint forces)" : ""));
      }
    } catch (err) {
      if (current()) showError(err, version);
    } finally {
      ch.busy = false;
      if (ch.queued) send(kind);
    }
  }

  // The outputs to fetch: every one for a mechanism with few (the figures' answer, the output picker), only the
  // plotted ones for one with many; while a value or a point is being dragged (``plottedOnly``) the plotted
  // ones alone, which cuts the answer to a fraction (a four-bar's 13 outputs are half its bytes) -- the full
  // answer that follows the edit (FIGURES_DELAY_MS after it settles) brings the others back.
  function wantedOutputs(plottedOnly) {
    const built = state.built === state.opened;
    const many = built && (plottedOnly || state.describe.outputs.length > FEW_OUTPUTS);
    return many ? state.selected : undefined;
  }

  // ------------------------------------------------------------------------------------ redraw
  function applySolve(data, version, full, bump = true, draw = true) {
    state.applied = version;
    const rebuild = state.built !== state.opened;
    state.describe = data.describe;
    if (full || !state.solve || rebuild) {
      state.solve = data;
    } else {                             // a curves-only answer: keep the figures of the last full one
      state.solve = { ...data, figures: state.solve.figures, summary: state.solve.summary };
    }
    window.linkageState = state.solve;
    if (rebuild) {
      state.built = state.opened;
      $("#description").textContent = data.describe.description;
      buildParameters(data.describe);
      state.selected = defaultOutputs(data);
      unitToggles();
      buildOutputPicker();
      buildCharts();
      setFrame(0);
      if (state.tab === "forces") setTimeout(requestForces, 0);
      camOpened(data.describe, data.mechanism);
    }
    clearErrors();
    syncParameters(data.parameters);
    if (!state.drag || !state.geometry) state.geometry = geometry(data);    // the view holds still under a drag
    updateCharts();
    if (draw) drawFrame();
    if (full) showFigures(data);
    if (full && !rebuild && state.tab === "cam") requestCam();          // the values may move the cam
    if (full || rebuild || !state.loadsDraw || hasFileLoads()) requestLoadsDraw();   // the loads follow each edit
    if (bump) bumpRevision();
  }

  function bumpRevision() {
    document.body.dataset.revision = String(Number(document.body.dataset.revision || 0) + 1);
  }

  function showError(err, version) {
    state.applied = Math.max(state.applied, version);
    const message = err.message || String(err);
    const name = fieldOfError(message);
    clearErrors();
    const row = name && document.querySelector(`.param[data-name="${CSS.escape(name)}"]`);
    const target = row ? row.querySelector(".field-error") : $("#file-error");
    target.textContent = message;
    if (row) row.classList.add("invalid");
    document.body.classList.add("stale");
    status(message, true);
    bumpRevision();
  }

  // The field an error belongs to: a parameter it names first ("l1=0.2 is not ..."), else the one edited.
  function fieldOfError(message) {
    const m = /^(?:set\.)?'?([A-Za-z_][A-Za-z0-9_]*)'?(?:=| must| is)/.exec(message);
    const names = new Set((state.describe ? state.describe.parameters : []).map((p) => p.name));
    if (m && (names.has(m[1]) || m[1] === "revolutions")) return m[1];
    if (/^(input range|input_range)/.test(message)) return "input_range";
    return state.lastEdited;
  }

  function clearErrors() {
    document.querySelectorAll(".field-error").forEach((el) => { el.textContent = ""; });
    document.querySelectorAll(".param.invalid").forEach((el) => el.classList.remove("invalid"));
    document.body.classList.remove("stale");
  }

  function status(text, bad) {
    const el = $("#status");
    el.textContent = text;
    el.classList.toggle("bad", !!bad);
  }

  // -------------------------------------------------------------------------------- parameters
  function fmt(v, digits = 6) {
    if (v === null || v === undefined || !Number.isFinite(v)) return "–";
    if (v !== 0 && (Math.abs(v) >= 1e6 || Math.abs(v) < 1e-4)) return v.toExponential(digits - 1).replace(/\.?0+e/, "e");
    return String(Number(v.toPrecision(digits)));
  }

  function buildParameters(describe) {
    const box = $("#params");
    box.replaceChildren();
    state.ranges = {};
    for (const p of describe.parameters) {
      state.ranges[p.name] = { min: p.min, max: p.max };
      box.appendChild(parameterRow(p));
    }
  }

  function parameterRow(p) {
    const row = document.createElement("div");
    row.className = "param";
    row.dataset.name = p.name;
    const unit = p.unit ? ` ${p.unit}` : "";
    row.innerHTML = `
      <label></label>
      <input type="range">
      <input type="text" inputmode="decimal" autocomplete="off" spellcheck="false">
      <span class="unit"></span>
      <p class="hint"></p>
      <p class="field-error" role="alert"></p>`;
    const label = row.querySelector("label");
    label.textContent = p.name;
    label.htmlFor = `p-${p.name}`;
    const slider = row.querySelector("input[type=range]");
    slider.dataset.param = p.name;
    slider.setAttribute("aria-label", `${p.name} slider`);
    slider.min = p.min; slider.max = p.max; slider.step = p.step; slider.value = p.value;
    const box = row.querySelector("input[type=text]");
    box.id = `p-${p.name}`;
    box.name = p.name;
    box.value = fmt(p.value);
    row.querySelector(".unit").textContent = p.unit || "";
    row.querySelector(".hint").textContent = p.kind === "branch"
      ? "branch: +1 or -1"
      : `range ${fmt(p.min, 4)} … ${fmt(p.max, 4)}${unit}${p.derived ? " · derived from the others until set" : ""}`;
    if (p.kind === "length") {                  // a locked length stays when a point is dragged
      const lock = document.createElement("label");
      lock.className = "lock";
      lock.title = `keep ${p.name} when dragging points`;
      const check = document.createElement("input");
      check.type = "checkbox";
      check.dataset.lock = p.name;
      lock.append(check, "lock");
      row.querySelector(".hint").before(lock);
    }
    // an edit by slider or number box is one undo step, from where it started to where it ended
    const start = () => { state.editBefore = snapshot(); };
    const begin = () => { if (!state.editBefore) start(); };
    const end = () => { const before = state.editBefore; state.editBefore = null; if (before) pushUndo(before); };
    for (const el of [slider, box]) {
      el.addEventListener("pointerdown", start);
      el.addEventListener("focus", start);
      el.addEventListener("change", end);
      el.addEventListener("blur", () => { state.editBefore = null; });
    }
    slider.addEventListener("input", () => {
      begin();
      state.set[p.name] = Number(slider.value);
      box.value = fmt(Number(slider.value));
      state.lastEdited = p.name;
      edited();
    });
    box.addEventListener("input", () => {
      begin();
      const text = box.value.trim();
      state.set[p.name] = text;
      const v = Number(text);
      if (text !== "" && Number.isFinite(v)) moveSlider(slider, p.name, v);
      state.lastEdited = p.name;
      edited();
    });
    return row;
  }

  function moveSlider(slider, name, v) {
    const r = state.ranges[name];
    slider.min = Math.min(r.min, v);     // a typed value outside the range widens the slider
    slider.max = Math.max(r.max, v);
    slider.value = v;
  }

  // Values the user did not set (defaults, derived ones) follow the solve.
  function syncParameters(values) {
    for (const [name, v] of Object.entries(values)) {
      if (name in state.set) continue;
      const box = document.querySelector(`#params input[name="${CSS.escape(name)}"]`);
      const slider = document.querySelector(`#params input[data-param="${CSS.escape(name)}"]`);
      if (box && document.activeElement !== box) box.value = fmt(v);
      if (slider) moveSlider(slider, name, v);
    }
  }

  // --------------------------------------------------------------------------------- outputs
  // Units of results (SPEC): the API answers in SI; what is shown is in the file's length unit, angles in
  // deg or rad and angular speeds in rpm as toggled (analytic/quantities.py does the same for the CLI).
  const METRES = { m: 1, mm: 1e-3, cm: 1e-2, in: 0.0254 };
  function lengthUnit() {
    if (state.draw) return { unit: "mm", f: 1000 };
    const u = (state.solve && state.solve.describe.units) || (state.describe && state.describe.units) || "m";
    return { unit: u, f: 1 / (METRES[u] || 1) };
  }

  // [display unit, factor from SI] of a column whose SI unit is units[name]
  function shownAs(name, units) {
    const u = units[name] || "";
    const L = lengthUnit();
    const deg = state.display.deg;
    const table = {
      m: [L.unit, L.f], "m/s": [`${L.unit}/s`, L.f], "m/s^2": [`${L.unit}/s^2`, L.f],
      rad: deg ? ["deg", DEG] : ["rad", 1],
      "rad/s": state.display.rpm ? ["rpm", 30 / Math.PI] : (deg ? ["deg/s", DEG] : ["rad/s", 1]),
      "rad/s^2": deg ? ["deg/s^2", DEG] : ["rad/s^2", 1],
    };
    return table[u] || [u, 1];
  }

  function displayUnit(name, units) {
    return shownAs(name, units)[0];
  }

  function unitToggles() {
    if ($("#unit-toggles")) return;
    const box = document.createElement("span");
    box.id = "unit-toggles";
    box.className = "muted";
    for (const [key, text] of [["deg", "angles in deg"], ["rpm", "speeds in rpm"]]) {
      const label = document.createElement("label");
      const check = document.createElement("input");
      check.type = "checkbox";
      check.name = `units-${key}`;
      check.checked = state.display[key];
      check.addEventListener("change", () => {
        state.display[key] = check.checked;
        if (!state.solve) return;
        buildOutputPicker(); buildCharts(); updateCharts(); drawFrame();
        if (state.sim) showVerdict(state.sim);
        if (state.forces) drawForces();
        bumpRevision();
      });
      label.style.whiteSpace = "nowrap";
      label.style.marginLeft = "0.6em";
      label.append(check, ` ${text}`);
      box.appendChild(label);
    }
    $("#analysis-panel .panel-head").appendChild(box);
  }

  // A first choice of curves: link angles, a slide, a transmission angle, the output point's path; outputs
  // that stay constant (a block's angle on a fixed guide) are left out.
  function defaultOutputs(data) {
    const describe = data.describe;
    const units = data.units;
    const varies = (n) => {
      const v = (data.outputs[n] || []).filter((x) => x !== null);
      return v.length > 0 && Math.max(...v) - Math.min(...v) > 1e-9 * (1 + Math.abs(v[0]));
    };
    const outs = describe.outputs.filter(varies);
    const p = describe.output_point;
    const inputs = new Set(describe.inputs.flatMap((i) => [i.q, i.qd, i.qdd]));
    const angles = outs.filter((n) => units[n] === "rad" && !n.startsWith("mu") && !inputs.has(n)).slice(0, 2);
    const slides = outs.filter((n) => units[n] === "m" && !/^[xy]/.test(n)).slice(0, 1);
    const mus = outs.filter((n) => n.startsWith("mu")).slice(0, 1);
    const path = [`x${p}`, `y${p}`].filter((n) => outs.includes(n));
    const picked = [...new Set([...angles, ...slides, ...mus, ...path])].slice(0, 4);
    return picked.length ? picked : describe.outputs.slice(0, 4);
  }

  function buildOutputPicker() {
    const box = $("#output-picker");
    box.replaceChildren();
    const units = state.solve.units;
    state.selected.forEach((name, k) => {
      const chip = document.createElement("button");
      chip.className = "chip";
      chip.style.setProperty("--chip", COLORS[k % COLORS.length]);
      chip.textContent = `${name} ✕`;
      chip.title = `remove ${name} [${displayUnit(name, units)}]`;
      chip.addEventListener("click", () => {
        state.selected = state.selected.filter((n) => n !== name);
        selectionChanged();
      });
      box.appendChild(chip);
    });
    const add = document.createElement("select");
    add.setAttribute("aria-label", "add an output");
    add.innerHTML = `<option value="">+ output…</option>`;
    for (const name of state.describe.outputs) {
      if (state.selected.includes(name)) continue;
      const opt = document.createElement("option");
      opt.value = name;
      opt.textContent = `${name} [${displayUnit(name, units) || "–"}]`;
      add.appendChild(opt);
    }
    add.addEventListener("change", () => {
      if (!add.value) return;
      state.selected = [...state.selected, add.value];
      selectionChanged();
    });
    box.appendChild(add);
  }

  function selectionChanged() {
    buildOutputPicker();
    buildCharts();
    const missing = state.selected.some((n) => !(n in state.solve.outputs));
    if (missing) { state.version += 1; send("curves"); } else { updateCharts(); bumpRevision(); }
  }

  // ---------------------------------------------------------------------------------- charts
  function inputAxis(data) {
    const q = data.input;
    const crank = data.units[q] === "rad";
    const shown = crank ? ["deg", DEG] : shownAs(q, data.units);
    return { key: q, crank, f: shown[1], label: `input ${q} [${shown[0]}]` };
  }

  function buildCharts() {
    for (const c of state.charts) { c.plot.destroy(); if (c.err) c.err.destroy(); }
    const box = $("#charts");
    box.replaceChildren();
    state.charts = [];
    const axis = inputAxis(state.solve);
    const width = chartWidth();
    state.selected.forEach((name, k) => {
      const color = COLORS[k % COLORS.length];
      const card = document.createElement("div");
      card.className = "chart-card";
      box.appendChild(card);
      const unit = displayUnit(name, state.solve.units);
      const plot = new uPlot({
        width, height: CHART_HEIGHT, title: `${name} [${unit}]`,
        scales: { x: { time: false } },
        legend: { show: true, live: false },
        cursor: { drag: { x: false, y: false } },
        axes: [axisOptions(axis.label), axisOptions(`${name} [${unit}]`, 64)],
        series: [
          { label: axis.label },
          { label: "analytic", stroke: color, width: 1.8, spanGaps: true },
          { label: "MuJoCo", stroke: SIM_COLOR, width: 0, paths: () => null,
            points: { show: true, size: 6, width: 1.2, stroke: SIM_COLOR, fill: "#fff" } },
        ],
      }, [[], [], []], card);
      const line = document.createElement("div");
      line.className = "cursor-line";
      plot.over.appendChild(line);
      const errBox = document.createElement("div");
      errBox.className = "error-chart";
      errBox.hidden = true;
      card.appendChild(errBox);
      const err = new uPlot({
        width, height: ERROR_HEIGHT, title: `${name}: MuJoCo − analytic, in tolerances`,
        scales: { x: { time: false }, y: { range: (u, lo, hi) => [Math.min(-1.5, lo), Math.max(1.5, hi)] } },
        legend: { show: false },
        cursor: { drag: { x: false, y: false } },
        axes: [axisOptions(null), { ...axisOptions("error / tol", 64), space: 14 }],
        series: [
          {},
          { label: "error / tol", stroke: color, width: 1.4 },
          { label: "+tol", stroke: "#c33", width: 1, dash: [4, 4] },
          { label: "-tol", stroke: "#c33", width: 1, dash: [4, 4] },
        ],
      }, [[], [], [], []], errBox);
      state.charts.push({ name, plot, err, errBox, line });
    });
  }

  function axisOptions(label, size) {
    const o = { labelSize: 16, labelFont: "12px system-ui, sans-serif", font: "11px system-ui, sans-serif",
      stroke: "#333", grid: { stroke: "#e6e6e6", width: 1 }, ticks: { stroke: "#ccc", width: 1 } };
    if (label) o.label = label;
    if (size) o.size = size;
    return o;
  }

  function chartWidth() {
    const box = $("#charts");
    const w = box.clientWidth || 600;
    return w >= 760 ? Math.floor((w - 12) / 2) : Math.floor(w);
  }

  function toDisplay(name, values, units) {
    if (units[name] !== "rad") {
      const f = shownAs(name, units)[1];
      return f === 1 ? values : values.map((v) => (v === null ? null : v * f));
    }
    const unit = state.display.deg ? DEG : 1;
    const out = new Array(values.length);
    const wrap = !name.startsWith("mu");    // turning links: a continuous curve, not jumps at +-180
    let offset = 0; let prev = null;
    for (let i = 0; i < values.length; i++) {
      const v = values[i];
      if (v === null) { out[i] = null; continue; }
      if (wrap && prev !== null) {
        const d = v + offset - prev;
        if (d > Math.PI) offset -= 2 * Math.PI; else if (d < -Math.PI) offset += 2 * Math.PI;
      }
      prev = v + offset;
      out[i] = prev * unit;
    }
    return out;
  }

  function inputValues(data, inputs) {
    const axis = inputAxis(data);
    const q = inputs[axis.key];
    return q.map((v) => (v === null ? null : v * axis.f));
  }

  // uPlot wants ascending x; a reversed crank or a rocking run is sorted first.
  function sortedBy(x, ...ys) {
    const idx = x.map((_, i) => i).filter((i) => x[i] !== null).sort((a, b) => x[a] - x[b]);
    return [idx.map((i) => x[i]), ...ys.map((y) => idx.map((i) => y[i]))];
  }

  function updateCharts() {
    const data = state.solve;
    const sim = state.sim;
    const xa = inputValues(data, data.inputs);
    const xs = sim ? inputValues(data, sim.simulated.inputs) : null;
    for (const c of state.charts) {
      const ya = data.outputs[c.name];
      if (!ya) continue;
      const analytic = sortedBy(xa, toDisplay(c.name, ya, data.units));
      const simY = sim && sim.simulated.outputs[c.name];
      if (simY) {
        const every = Math.max(1, Math.round(xs.length / 72));    // a marker every ~5 deg of a turn
        const xm = xs.filter((_, i) => i % every === 0);
        const ym = toDisplay(c.name, simY, data.units).filter((_, i) => i % every === 0);
        c.plot.setData(uPlot.join([analytic, sortedBy(xm, ym)]));
        const tol = (sim.errors[c.name] || {}).tol || 1;
        const [xe, ye] = sortedBy(xs, sim.simulated.errors[c.name].map((e) => (e === null ? null : e / tol)));
        c.err.setData([xe, ye, xe.map(() => 1), xe.map(() => -1)]);
        c.errBox.hidden = false;
        const [eu, ef] = shownAs(c.name, data.units);
        c.errBox.title = `tolerance ${fmt(tol * ef, 2)} ${eu}`;
      } else {
        c.plot.setData([analytic[0], analytic[1], analytic[0].map(() => null)]);
        c.errBox.hidden = true;
      }
    }
    moveCursors();
  }

  function moveCursors() {
    const data = state.solve;
    if (!data) return;
    const axis = inputAxis(data);
    const q = data.inputs[axis.key][state.frame];
    if (q === null || q === undefined) return;
    const x = q * axis.f;
    for (const c of [...state.charts, ...state.forceCharts]) {
      const left = c.plot.valToPos(x, "x");
      c.line.style.transform = `translateX(${left}px)`;
    }
  }

  // ----------------------------------------------------------------------------- figures, sim
  function showFigures(data) {
    const list = $("#figures");
    list.replaceChildren();
    for (const line of data.summary || []) {
      const li = document.createElement("li");
      li.textContent = line.trim();
      list.appendChild(li);
    }
    list.classList.remove("pending");
    $("#all-figures pre").textContent = JSON.stringify(data.figures, null, 1);
  }

  function clearSimulation() {
    if (!state.sim) return;
    state.sim = null;
    window.linkageSimulation = null;
    $("#verdict").hidden = true;
    $("#errors").hidden = true;
    $("#sim-status").textContent = "parameters changed: simulate again";
  }

  async function simulate() {
    const button = $("#simulate");
    button.disabled = true;
    $("#sim-status").classList.remove("bad");
    $("#sim-status").textContent = "simulating…";
    const version = state.version;
    try {
      const res = await api("/api/simulate", requestBody({ outputs: wantedOutputs() }));
      const sim = await res.json();
      if (version !== state.version) return;           // the parameters moved on meanwhile
      state.sim = sim;
      window.linkageSimulation = sim;
      showVerdict(sim);
      updateCharts();
      drawFrame();
      $("#sim-status").textContent = `${sim.steps} steps of ${fmt(sim.timestep * 1e3, 3)} ms (${sim.integrator}), `
        + `${fmt(sim.cpu_seconds * 1e3, 3)} ms CPU`;
      bumpRevision();
    } catch (err) {
      actionError(err);
    } finally {
      button.disabled = false;
    }
  }

  // A failed action (simulate, render, export) is said beside its buttons: it is not one field's fault.
  function actionError(err) {
    const el = $("#sim-status");
    el.textContent = err.message || String(err);
    el.classList.add("bad");
    status(el.textContent, true);
    bumpRevision();
  }

  function showVerdict(sim) {
    const v = $("#verdict");
    v.hidden = false;
    v.className = sim.passed ? "verdict passed" : "verdict failed";
    v.textContent = sim.passed ? "PASSED" : "FAILED";
    const small = document.createElement("small");
    small.textContent = ` drive error ${fmt(sim.drive_error, 3)} (tol ${fmt(sim.drive_tol, 2)}) · loop violation `
      + `${fmt(sim.max_loop_violation * lengthUnit().f, 3)} ${lengthUnit().unit} `
      + `(tol ${fmt(sim.loop_tol * lengthUnit().f, 2)}) · work balance ${fmt(sim.work_balance, 3)}`;
    v.appendChild(small);
    const table = $("#errors");
    table.hidden = false;
    table.innerHTML = "<thead><tr><th>output</th><th>max error</th><th>rms</th><th>tolerance</th><th>unit</th>"
      + "<th></th></tr></thead>";
    const body = document.createElement("tbody");
    for (const [name, e] of Object.entries(sim.errors)) {
      const tr = document.createElement("tr");
      if (!e.passed) tr.className = "fail";
      const [u, f] = shownAs(name, { [name]: e.unit });
      for (const text of [name, fmt(e.max * f, 3), fmt(e.rms * f, 3), fmt(e.tol * f, 2), u, e.passed ? "✓" : "✗"]) {
        const td = document.createElement("td");
        td.textContent = text;
        tr.appendChild(td);
      }
      body.appendChild(tr);
    }
    table.appendChild(body);
  }

  async function renderVideo() {
    const button = $("#render");
    button.disabled = true;
    $("#sim-status").classList.remove("bad");
    $("#sim-status").textContent = "rendering the MuJoCo video…";
    try {
      const revolutions = Math.min(5, Number(state.revolutions) || 1);
      const res = await api("/api/render", requestBody({ revolutions, size: "640x480", fps: 30 }));
      const video = $("#video");
      if (video.src) URL.revokeObjectURL(video.src);
      video.src = URL.createObjectURL(await res.blob());
      video.hidden = false;
      video.play().catch(() => {});
      $("#sim-status").textContent = "video rendered offscreen by MuJoCo";
    } catch (err) {
      actionError(err);
    } finally {
      button.disabled = false;
    }
  }

  async function download(kind) {
    try {
      const res = await api(`/api/export/${kind}`, requestBody(kind === "csv" || kind === "json" ? { samples: SAMPLES } : {}));
      const name = (/filename="([^"]+)"/.exec(res.headers.get("Content-Disposition") || "") || [])[1] || `linkage.${kind}`;
      const url = URL.createObjectURL(await res.blob());
      const a = document.createElement("a");
      a.href = url;
      a.download = name;
      document.body.appendChild(a);
      a.click();
      a.remove();
      setTimeout(() => URL.revokeObjectURL(url), 1000);
      status(`downloaded ${name}`);
    } catch (err) {
      actionError(err);
    }
  }

  // ------------------------------------------------------------------------------------- tabs
  function showTab(name) {
    state.tab = name;
    document.querySelectorAll("#analysis-panel [role=tab]").forEach((b) => {
      b.setAttribute("aria-selected", String(b.dataset.tab === name));
    });
    document.querySelectorAll("#analysis-panel .pane").forEach((p) => { p.hidden = p.id !== `pane-${name}`; });
    $("#view").classList.toggle("picking", name === "synthesis");
    if (name === "forces" && state.solve && state.forcesVersion < state.version) requestForces();
    if (name === "synthesis") synthTypes();
    if (name === "cam") { if (state.cam.data) drawCamProfile(); requestCam(); }
    resizePanels();
    drawFrame();
    bumpRevision();
  }

  function resizePanels() {
    const w = paneWidth();
    for (const c of [...state.forceCharts, ...state.dynamicsCharts]) c.plot.setSize({ width: w, height: c.height });
    moveCursors();
  }

  function paneWidth() {
    const pane = document.querySelector("#analysis-panel .pane:not([hidden])") || $("#analysis-panel");
    const w = pane.clientWidth || 600;
    return w >= 760 ? Math.floor((w - 12) / 2) : Math.floor(w);
  }

  function newChart(box, opts, data, height, cls) {
    const card = document.createElement("div");
    card.className = cls || "panel-chart";
    box.appendChild(card);
    const plot = new uPlot({ width: paneWidth(), height, scales: { x: { time: false } },
      cursor: { drag: { x: false, y: false } }, ...opts }, data, card);
    const line = document.createElement("div");
    line.className = "cursor-line";
    plot.over.appendChild(line);
    return { plot, line, card, height };
  }

  // ------------------------------------------------------------------------------------ loads
  // Typed "GX,GY" (m/s^2), "FX,FY" (N) and "F" (N); kept as the API takes them, checked as typed.
  function parseLoad(name, text) {
    const t = text.trim();
    if (!t) return [null, ""];
    if (name === "cutting") {
      const v = Number(t);
      return Number.isFinite(v) && v >= 0 ? [v, ""] : [null, `cutting ${t} must be a force F >= 0 [N], e.g. 100`];
    }
    const texts = t.split(",").map((x) => x.trim());
    const parts = texts.map(Number);
    if (parts.length === 2 && texts.every((x) => x !== "") && parts.every(Number.isFinite)) return [parts, ""];
    return [null, `${name} ${t} must be two numbers ${name === "gravity" ? "GX,GY [m/s²], e.g. 0,-9.81" : "FX,FY [N], e.g. 10,0"}`];
  }

  function loadsEdited(name, text) {
    const [value, error] = parseLoad(name, text);
    const row = document.querySelector(`.loads .param[data-name="${name}"]`);
    row.querySelector(".field-error").textContent = error;
    row.classList.toggle("invalid", !!error);
    if (error) return;
    state.loads[name] = value;
    state.version += 1;                   // the forces of other loads are stale; the curves are not
    clearForcesSimulation();
    staleDynamics();
    if (state.tab === "forces") requestForces();
  }

  function loadsBody() {
    const out = {};
    // the page's "cutting" field is the API's cutting_force (the door's keyword)
    for (const [k, v] of Object.entries(state.loads)) if (v !== null) out[k === "cutting" ? "cutting_force" : k] = v;
    return out;
  }

  // ----------------------------------------------------------------------------------- forces
  // The joint forces of the current values: asked for beside each edit's curves while the panel is open
  // (send), on their own when the panel opens or the loads change (requestForces).
  async function fetchForces(version, simulate) {
    try {
      const extra = { samples: SAMPLES, ...loadsBody() };
      if (simulate) extra.simulate = true; else extra.digits = DRAG_DIGITS;
      const res = await api("/api/forces", requestBody(extra));
      return { data: await res.json(), version };
    } catch (err) {
      return { error: err, version };
    }
  }

  const forcesChannel = { busy: false, queued: false };
  async function requestForces() {
    if (forcesChannel.busy) { forcesChannel.queued = true; return; }
    forcesChannel.busy = true;
    forcesChannel.queued = false;
    const version = state.version;
    $("#forces-status").textContent = "computing the joint forces…";
    const answer = await fetchForces(version, false);
    if (version >= state.forcesVersion && version >= state.opened && state.solve) {
      applyForces(answer, version);
      bumpRevision();
    }
    forcesChannel.busy = false;
    if (forcesChannel.queued) requestForces();
  }

  function applyForces(answer, version) {
    state.forcesVersion = version;
    $("#force-charts").classList.remove("stale-fade");
    const st = $("#forces-status");
    st.classList.toggle("bad", !!answer.error);
    if (answer.error) {
      st.textContent = answer.error.message || String(answer.error);
      $("#force-charts").classList.add("stale-fade");
      return;
    }
    const data = answer.data;
    state.forces = data;
    window.linkageForces = data;
    drawForces();
    st.textContent = forcesLine(data);
  }

  function forcesLine(data) {
    const parts = [];
    const l = data.loads || {};
    if (l.gravity) parts.push(`gravity ${l.gravity[0]},${l.gravity[1]} m/s²`);
    if (l.force) parts.push(`${l.force.cutting ? "cutting force" : "force"} ${fmt(l.force.Fx, 4)},${fmt(l.force.Fy, 4)} N on ${l.force.point} (link ${l.force.link})`);
    const own = (data.applied || []).filter((x) => x.kind !== "gravity" && !(x.name === "force" && x.kind === "force" && l.force));
    if (own.length) parts.push(`file loads ${own.map((x) => x.name).join(", ")}`);
    if (data.friction && data.friction.pins && (Object.keys(data.friction.pins).length || Object.keys(data.friction.prismatic || {}).length)) parts.push("friction");
    return `${data.joints.length} joints over ${data.samples} samples; ${parts.join(", ") || "inertia only"}`;
  }

  function clearForcesSimulation() {
    if (!state.forces || !state.forces.simulated) return;
    state.forces = { ...state.forces, simulated: null };
    window.linkageForces = state.forces;
    $("#forces-verdict").hidden = true;
  }

  function forceColor(k) { return COLORS[k % COLORS.length]; }

  // x values of a forces answer (the first input, shown as the curves show it) and ys sorted by them
  function forceXY(data, ys) {
    const axis = inputAxis(state.solve);
    const x = (data.inputs[data.input] || []).map((v) => (v === null ? null : v * axis.f));
    return sortedBy(x, ...ys);
  }

  function buildForceCharts(data) {
    for (const c of state.forceCharts) c.plot.destroy();
    const box = $("#force-charts");
    box.replaceChildren();
    state.forceCharts = [];
    const axis = inputAxis(state.solve);
    const sim = !!data.simulated;
    const fu = data.units.force || "N"; const mu = data.units.moment || "N m";   // the file's force_units
    const marker = (color) => ({ stroke: color, width: 0, paths: () => null,
      points: { show: true, size: 5, width: 1.2, stroke: color, fill: "#fff" } });
    // joints: one line each, named in the legend (and the table below), MuJoCo's markers beside them
    const jointSeries = [{ label: axis.label }];
    data.joints.forEach((j, k) => {
      jointSeries.push({ label: j.name, stroke: forceColor(k), width: 1.6, spanGaps: true });
      if (sim) jointSeries.push({ label: `${j.name} MuJoCo`, ...marker(forceColor(k)) });
    });
    state.forceCharts.push({ kind: "joints", height: 230, ...newChart(box, {
      title: `joint forces |F| [${fu}]`, legend: { show: true, live: false },
      axes: [axisOptions(axis.label), axisOptions(`|F| [${fu}]`, 64)], series: jointSeries,
    }, jointSeries.map(() => []), 230) });
    const drives = Object.keys(data.drives);
    const driveUnit = (q) => (data.units.drives || {})[q] || mu;
    const driveSeries = [{ label: axis.label }];
    drives.forEach((q, k) => {
      driveSeries.push({ label: `${q} drive [${driveUnit(q)}]`, stroke: COLORS[(k + 3) % COLORS.length], width: 1.8, spanGaps: true });
      if (sim) driveSeries.push({ label: "MuJoCo", ...marker(SIM_COLOR) });
    });
    const units = [...new Set(drives.map(driveUnit))].join(", ");
    state.forceCharts.push({ kind: "drives", height: 190, ...newChart(box, {
      title: `drive ${units === fu ? "force" : "torque"} [${units}]`, legend: { show: true, live: false },
      axes: [axisOptions(axis.label), axisOptions(`[${units}]`, 64)], series: driveSeries,
    }, driveSeries.map(() => []), 190) });
    const shakeSeries = [{ label: axis.label },
      { label: `|Fs| [${fu}]`, stroke: "#c51b8a", width: 1.8, scale: "F", spanGaps: true },
      { label: `Ms [${mu}]`, stroke: "#8c564b", width: 1.2, dash: [5, 4], scale: "M", spanGaps: true }];
    if (sim) shakeSeries.push({ label: "MuJoCo |Fs|", scale: "F", ...marker(SIM_COLOR) });
    state.forceCharts.push({ kind: "shaking", height: 190, ...newChart(box, {
      title: "shaking force |Fs| and moment Ms (about the origin)", legend: { show: true, live: false },
      scales: { x: { time: false }, F: {}, M: {} },
      axes: [axisOptions(axis.label), { ...axisOptions(`|Fs| [${fu}]`, 64), scale: "F" },
        { ...axisOptions(`Ms [${mu}]`, 64), scale: "M", side: 1, grid: { show: false } }],
      series: shakeSeries,
    }, shakeSeries.map(() => []), 190) });
  }

  function drawForces() {
    const data = state.forces;
    if (!data || !state.solve) return;
    const key = `${state.built}|${data.joints.map((j) => j.name).join(",")}|${!!data.simulated}|${state.display.deg}|${data.units.force}|${data.units.moment}`;
    if (key !== state.forceKey) { buildForceCharts(data); state.forceKey = key; }
    const sim = data.simulated;
    const every = sim ? Math.max(1, Math.round(sim.inputs[sim.input].length / 72)) : 1;
    const thin = (a) => a.map((v, i) => (i % every === 0 ? v : null));
    // analytic lines and MuJoCo's markers interleaved per series, on the union of their x values
    const interleave = (an, mj, n) => {
      const joined = uPlot.join([an, mj]);
      const out = [joined[0]];
      for (let k = 0; k < n; k++) out.push(joined[1 + k], joined[1 + n + k]);
      return out;
    };
    const qs = Object.keys(data.drives);
    for (const c of state.forceCharts) {
      if (c.kind === "joints") {
        const an = forceXY(data, data.joints.map((j) => j.F));
        c.plot.setData(sim ? interleave(an, forceXY(sim, sim.joints.map((j) => thin(j.F))), data.joints.length) : an);
      } else if (c.kind === "drives") {
        const an = forceXY(data, qs.map((q) => data.drives[q]));
        c.plot.setData(sim ? interleave(an, forceXY(sim, qs.map((q) => thin(sim.drives[q]))), qs.length) : an);
      } else {
        const an = forceXY(data, [data.shaking.F, data.shaking.M]);
        c.plot.setData(sim ? uPlot.join([an, forceXY(sim, [thin(sim.shaking.F)])]) : an);
      }
    }
    forcePeaks(data);
    if (sim) forcesVerdict(sim); else $("#forces-verdict").hidden = true;
    moveCursors();
  }

  function angleText(q) {
    const axis = inputAxis(state.solve);
    return axis.crank ? `${fmt(q * DEG, 4)}°` : `${fmt(q * axis.f, 4)} ${displayUnit(axis.key, state.solve.units)}`;
  }

  function forcePeaks(data) {
    const table = $("#force-peaks");
    const sim = data.simulated;
    const fu = data.units.force || "N";
    const head = ["", "joint", "kind", "links", `peak |F| [${fu}]`, `at ${data.input}`];
    if (sim) head.push("MuJoCo − analytic", "of the peak");     // a drive's difference is in its own unit
    table.replaceChildren();
    const thead = document.createElement("thead");
    const hr = document.createElement("tr");
    for (const h of head) { const th = document.createElement("th"); th.textContent = h; hr.appendChild(th); }
    thead.appendChild(hr);
    table.appendChild(thead);
    const body = document.createElement("tbody");
    const row = (cells, swatch) => {
      const tr = document.createElement("tr");
      const sw = document.createElement("td");
      if (swatch) { const s = document.createElement("span"); s.className = "swatch"; s.style.background = swatch; sw.appendChild(s); }
      tr.appendChild(sw);
      for (const text of cells) { const td = document.createElement("td"); td.textContent = text; tr.appendChild(td); }
      body.appendChild(tr);
      return tr;
    };
    data.joints.forEach((j, k) => {
      const pk = data.peaks.joints[j.name];
      const cells = [j.name, j.kind + (j.input ? " (driven)" : ""), j.links.join("–"), fmt(pk.F, 4),
        angleText(pk[data.input])];
      if (sim) {
        const a = sim.agreement.joints[j.name] || {};
        cells.push(`${fmt(a.max, 2)} ${fu}`, fmt(a.share, 2));
      }
      const tr = row(cells, forceColor(k));
      if (sim && (sim.agreement.joints[j.name] || {}).share > sim.agreement.tol) tr.className = "fail";
    });
    for (const [q, d] of Object.entries(data.peaks.drives)) {
      const unit = (data.units.drives || {})[q] || "";
      const cells = [`drive ${q}`, "", "", `${fmt(d.value, 4)} ${unit}`, angleText(d[data.input])];
      if (sim) { const a = sim.agreement.drives[q] || {}; cells.push(`${fmt(a.mujoco_max, 2)} ${unit}`, fmt(a.mujoco_share, 2)); }
      row(cells, null);
    }
    for (const [name, a] of Object.entries(data.actuators || {})) {   // each cylinder's peak push and pull
      for (const side of ["push", "pull"]) {
        const pk = a[side];
        const p = pk.pressure !== undefined ? ` (${fmt(pk.pressure / 1e5, 4)} bar)` : "";
        const at = pk.at === null ? "never" : angleText(data.inputs[data.input][pk.at]);
        const cells = [`cylinder ${name} ${side}`, "", "", `${fmt(pk.F, 4)} N${p}`, at];
        if (sim) cells.push("", "");
        row(cells, null).dataset.cylinder = `${name} ${side}`;
      }
    }
    const sh = data.peaks.shaking;
    const cells = ["shaking", "", "", `${fmt(sh.F, 4)} (RMS ${fmt(sh.F_rms, 4)})`, angleText(sh[data.input])];
    if (sim) cells.push(`${fmt(sim.agreement.shaking.F_max, 2)} ${fu}`, fmt(sim.agreement.shaking.F_share, 2));
    row(cells, null);
    table.appendChild(body);
  }

  function forcesVerdict(sim) {
    const v = $("#forces-verdict");
    const a = sim.agreement;
    v.hidden = false;
    v.className = sim.passed ? "verdict passed" : "verdict failed";
    v.textContent = sim.passed ? "PASSED" : "FAILED";
    const small = document.createElement("small");
    small.textContent = ` MuJoCo's joint forces within ${fmt(a.worst, 2)} of the peak ${fmt(a.peak, 4)} N `
      + `(worst ${a.worst_of}, median ${fmt(a.median, 2)}); tolerance ${fmt(a.tol, 2)} · ${sim.steps} steps of `
      + `${fmt(sim.timestep * 1e3, 3)} ms`;
    v.appendChild(small);
  }

  async function simulateForces() {
    const button = $("#forces-simulate");
    button.disabled = true;
    const st = $("#forces-status");
    st.classList.remove("bad");
    st.textContent = "simulating the joint forces in MuJoCo…";
    const version = state.version;
    const answer = await fetchForces(version, true);
    button.disabled = false;
    if (version !== state.version) { st.textContent = "values changed: simulate again"; return; }
    applyForces(answer, version);
    bumpRevision();
  }

  // ---------------------------------------------------------------------------------- dynamics
  const RPM = 30 / Math.PI;           // rpm per rad/s
  const SPEED_UNITS = { rpm: 1 / RPM, "rad/s": 1 };     // rad/s per unit: the units `linkage dynamics` takes

  // A speed field [rad/s]: a number in the unit chosen beside W0, or a number with its unit written after it
  // ("150rpm", "15.7 rad/s"), as `linkage dynamics --motor T0,W0` reads W0 (where a bare number is rad/s).
  function readSpeed(id, name) {
    const el = $(id);
    const row = el.closest(".param");
    const m = /^\s*([-+]?(?:\d+\.?\d*|\.\d+)(?:e[-+]?\d+)?)\s*(rpm|rad\/s)?\s*$/i.exec(el.value);
    const ok = m !== null && Number.isFinite(Number(m[1]));
    const unit = ok && m[2] ? m[2].toLowerCase() : $("#dyn-speed-unit").value;
    row.querySelector(".field-error").textContent = ok ? "" : `${name}: give a number, in ${$("#dyn-speed-unit").value} or with rpm or rad/s after it`;
    row.classList.toggle("invalid", !ok);
    if (!ok) throw new ApiError(`${name}: give a number, or one with rpm or rad/s after it`, 0);
    return Number(m[1]) * SPEED_UNITS[unit];
  }

  function speedUnitChanged(e) {              // the boxes' bare numbers converted: the motor stays the same
    const to = e.target.value; const from = to === "rpm" ? "rad/s" : "rpm";
    for (const id of ["#dyn-W0", "#dyn-start"]) {
      const el = $(id);
      const m = /^\s*([-+]?(?:\d+\.?\d*|\.\d+)(?:e[-+]?\d+)?)\s*$/i.exec(el.value);
      if (m) el.value = fmt(Number(m[1]) * SPEED_UNITS[from] / SPEED_UNITS[to], 6);
    }
    $("#dyn-start-unit").textContent = to;
  }

  function dynamicsInputs(size) {
    const read = (id, name) => {
      const el = $(id);
      const v = Number(el.value.trim());
      const row = el.closest(".param");
      const ok = el.value.trim() !== "" && Number.isFinite(v);
      row.querySelector(".field-error").textContent = ok ? "" : `${name}: give a number`;
      row.classList.toggle("invalid", !ok);
      if (!ok) throw new ApiError(`${name}: give a number`, 0);
      return v;
    };
    const body = {
      motor: { T0: read("#dyn-T0", "T0"), W0: readSpeed("#dyn-W0", "W0") },
      start_speed: readSpeed("#dyn-start", "start"),
      revolutions: read("#dyn-revolutions", "revolutions"),
      simulate: $("#dynamics-mujoco").checked,
      ...loadsBody(),
    };
    if (size) body.target_fluctuation = read("#dyn-target", "target Cs");
    else body.flywheel = read("#dyn-flywheel", "flywheel");
    const b = requestBody(body);
    delete b.input_range;               // the motor turns the input through whole revolutions
    return b;
  }

  async function runDynamics(size) {
    const buttons = [$("#dynamics-run"), $("#dynamics-size")];
    const st = $("#dynamics-status");
    st.classList.remove("bad");
    let body;
    try { body = dynamicsInputs(size); } catch (err) { st.textContent = err.message; st.classList.add("bad"); return; }
    buttons.forEach((b) => { b.disabled = true; });
    const version = state.version;
    const started = performance.now();
    st.textContent = size ? "sizing the flywheel and checking it by both runs…"
      : `integrating the reduced equation${body.simulate ? " and running MuJoCo" : ""}…`;
    try {
      const res = await api("/api/dynamics", body);
      const data = await res.json();
      if (version !== state.version) { st.textContent = "values changed: run again"; return; }
      state.dynamics = data;
      window.linkageDynamics = data;
      if (size) $("#dyn-flywheel").value = fmt(data.flywheel, 6);
      drawDynamics(data);
      st.textContent = `done in ${fmt((performance.now() - started) / 1000, 3)} s`;
      bumpRevision();
    } catch (err) {
      st.textContent = err.message || String(err);
      st.classList.add("bad");
      bumpRevision();
    } finally {
      buttons.forEach((b) => { b.disabled = false; });
    }
  }

  function staleDynamics() {
    if (!state.dynamics) return;
    state.dynamics = null;
    window.linkageDynamics = null;
    $("#dynamics-status").textContent = "values changed: run again";
    $("#dynamics-charts").classList.add("stale-fade");
  }

  function drawDynamics(data) {
    for (const c of state.dynamicsCharts) c.plot.destroy();
    const box = $("#dynamics-charts");
    box.replaceChildren();
    box.classList.remove("stale-fade");
    state.dynamicsCharts = [];
    const sim = data.simulated;
    const marker = { stroke: SIM_COLOR, width: 0, paths: () => null,
      points: { show: true, size: 5, width: 1.2, stroke: SIM_COLOR, fill: "#fff" } };
    const deg = (a) => a.map((v) => (v === null ? null : v * DEG));
    const rpm = (a) => a.map((v) => (v === null ? null : Math.abs(v) * RPM));
    // speed against angle over the last revolution, its mean and the Cs band
    const cx = deg(data.cycle.advance);
    const an = [cx, rpm(data.cycle.omega), cx.map(() => data.w_max * RPM), cx.map(() => data.w_min * RPM),
      cx.map(() => data.mean_speed * RPM)];
    let cycle = an;
    const series = [{ label: "advance [deg]" }, { label: "reduced equation", stroke: "#1f77b4", width: 1.8 },
      { label: `max ${fmt(data.w_max * RPM, 4)} rpm (Cs = ${fmt(data.fluctuation, 4)})`, stroke: "rgba(31,119,180,0.35)", width: 1 },
      { label: `min ${fmt(data.w_min * RPM, 4)} rpm`, stroke: "rgba(31,119,180,0.35)", width: 1 },  // a label, not uPlot's "Value"
      { label: `mean ${fmt(data.mean_speed * RPM, 4)} rpm`, stroke: "#222", width: 1, dash: [6, 4] }];
    if (sim) {
      const step = Math.max(1, Math.round(sim.cycle.advance.length / 90));
      const sx = deg(sim.cycle.advance).filter((_, i) => i % step === 0);
      const sy = rpm(sim.cycle.omega).filter((_, i) => i % step === 0);
      cycle = uPlot.join([an, sortedBy(sx, sy)]);
      series.push({ label: "MuJoCo", ...marker });
    }
    state.dynamicsCharts.push({ height: 210, ...newChart(box, {
      title: "speed over the last revolution [rpm]", legend: { show: true, live: false },
      bands: [{ series: [2, 3], fill: "rgba(31,119,180,0.12)" }],
      scales: { x: { time: false, range: [0, 360] } },
      axes: [axisOptions("input's advance over the last revolution [deg]"), axisOptions("speed [rpm]", 64)],
      series,
    }, cycle, 210) });
    // start-up against time, and the motor's torque
    const timeChart = (title, ylabel, ys, simYs, color) => {
      let d = [data.run.t, ys];
      const ser = [{ label: "t [s]" }, { label: "reduced equation", stroke: color, width: 1.5 }];
      if (sim) {
        const step = Math.max(1, Math.round(sim.t.length / 300));
        d = uPlot.join([d, [sim.t.filter((_, i) => i % step === 0), simYs.filter((_, i) => i % step === 0)]]);
        ser.push({ label: "MuJoCo", ...marker });
      }
      state.dynamicsCharts.push({ height: 180, ...newChart(box, {
        title, legend: { show: true, live: false },
        axes: [axisOptions("time [s]"), axisOptions(ylabel, 64)], series: ser,
      }, d, 180) });
    };
    timeChart(`start-up: speed [rpm] (95 % of the mean at ${fmt(data.startup_time, 3)} s)`, "speed [rpm]",
      rpm(data.run.omega), sim ? rpm(sim.omega) : null, "#1f77b4");
    timeChart(`motor torque [N m] (peak ${fmt(data.peak_torque, 3)} N m, ${fmt(data.peak_power, 3)} W)`, "torque [N m]",
      data.run.torque, sim ? sim.torque : null, "#2ca02c");
    dynamicsTable(data);
  }

  function dynamicsTable(data) {
    const sim = data.simulated;
    const table = $("#dynamics-table");
    table.hidden = false;
    table.replaceChildren();
    const add = (cells, tag = "td") => {
      const tr = document.createElement("tr");
      for (const c of cells) { const td = document.createElement(tag); td.textContent = c; tr.appendChild(td); }
      table.appendChild(tr);
    };
    add(["", "reduced equation", "MuJoCo", "difference", "tolerance"], "th");
    const ag = sim ? sim.agreement : null;
    add(["mean speed [rpm]", fmt(data.mean_speed * RPM, 6), sim ? fmt(sim.mean_speed * RPM, 6) : "–",
      ag ? `${fmt(ag.mean_speed, 2)} (relative)` : "", ag ? fmt(ag.tolerances.mean_speed, 2) : ""]);
    add(["mean speed [rad/s]", fmt(data.mean_speed, 6), sim ? fmt(sim.mean_speed, 6) : "–", "", ""]);
    add(["fluctuation Cs", fmt(data.fluctuation, 5), sim ? fmt(sim.fluctuation, 5) : "–", ag ? fmt(ag.fluctuation, 2) : "",
      ag ? fmt(ag.tolerances.fluctuation, 2) : ""]);
    add(["start-up time [s]", fmt(data.startup_time, 5), sim ? fmt(sim.startup_time, 5) : "–", "", ""]);
    if (ag) {
      add(["speed against angle", "", "", `${fmt(ag.speed_vs_angle, 2)} of the mean`, fmt(ag.tolerances.speed_vs_angle, 2)]);
      add(["speed against time", "", "", `${fmt(ag.speed_vs_time, 2)} of the mean`, fmt(ag.tolerances.speed_vs_time, 2)]);
    }
    add(["flywheel [kg m²]", fmt(data.flywheel, 5), "", "", ""]);
    add(["energy per cycle [J]", fmt(data.energy_per_cycle, 4), "", "", ""]);
    for (const ld of data.loads || []) {          // the file's [[loads]]: each one's work over the last turn
      add([`load ${ld.name} (${ld.kind.replace("_", " ")}) work [J]`, fmt(ld.work_per_cycle, 4), "", "", ""]);
    }
    const v = $("#dynamics-verdict");
    const sizing = data.sizing;
    if (!sim && !sizing) { v.hidden = true; return; }
    v.hidden = false;
    v.className = data.passed ? "verdict passed" : "verdict failed";
    v.textContent = data.passed ? "PASSED" : "FAILED";
    const small = document.createElement("small");
    const parts = [];
    if (sim) parts.push(`MuJoCo ${sim.passed ? "agrees" : "DISAGREES"} (${sim.steps} steps of ${fmt(sim.timestep * 1e3, 3)} ms)`);
    if (sizing) parts.push(`flywheel ${fmt(sizing.flywheel, 5)} kg m² sized for Cs = ${fmt(sizing.target, 3)}: `
      + `${fmt(sizing.fluctuation, 4)}${sizing.simulated_fluctuation !== null ? ` (MuJoCo ${fmt(sizing.simulated_fluctuation, 4)})` : ""}`
      + ` ${sizing.passed ? "within" : "outside"} ${fmt(sizing.tolerance * 100, 2)} %`);
    small.textContent = ` ${parts.join(" · ")}`;
    v.appendChild(small);
  }

  // --------------------------------------------------------------------------------- synthesis
  // Target points [m] clicked on the drawing (or loaded from a CSV in the file's unit); the candidates'
  // coupler curves drawn over them on the same canvas; a candidate opens as the current mechanism.
  function synthTypes() {
    const select = $("#synth-type");
    if (select.options.length || !state.synthesisInfo) return;
    for (const t of state.synthesisInfo.types) {
      const opt = document.createElement("option");
      opt.value = t;
      opt.textContent = t;
      select.appendChild(opt);
    }
  }

  function synthTargetsChanged() {
    const n = state.synth.targets.length;
    $("#synth-targets").textContent = n ? `${n} target point${n > 1 ? "s" : ""} (click the drawing to add more)`
      : "no target points yet: click the drawing or load a CSV";
    state.synth.result = null;
    window.linkageSynthesis = null;
    $("#synth-table").hidden = true;
    if (state.solve) state.geometry = geometry(state.solve);
    drawFrame();
    bumpRevision();
  }

  function pickTarget(e) {
    if (state.draw) return;
    if (state.tab !== "synthesis" || !state.geometry) return;
    const r = canvas.getBoundingClientRect();
    const px = e.clientX - r.left; const py = e.clientY - r.top;
    const v = view();
    if (px < MARGIN.left || px > MARGIN.left + v.w || py < MARGIN.top || py > MARGIN.top + v.h) return;
    state.synth.targets.push(v.inv(px, py));
    synthTargetsChanged();
  }

  async function loadTargets(file) {
    const st = $("#synth-status");
    st.classList.remove("bad");
    try {
      const res = await api("/api/targets", { text: await file.text(), filename: file.name, unit: lengthUnit().unit });
      const data = await res.json();
      state.synth.targets = data.targets;
      synthTargetsChanged();
      st.textContent = `${file.name}: ${data.targets.length} targets`;
    } catch (err) {
      st.textContent = err.message || String(err);
      st.classList.add("bad");
      bumpRevision();
    }
  }

  // The search runs as a server job: the bar follows its real stages (the search's restarts, then each
  // candidate's MuJoCo check) polled from /api/synthesize/status; Cancel kills it (and its workers) at once.
  const STAGES = { starting: "starting", search: "searching", polish: "multi-starts, basin hopping and polishing the best",
    check: "checking the candidates in MuJoCo" };
  function synthProgress(s) {
    const bar = $("#synth-progress");
    if (s.state !== "running") return;
    const frac = s.total ? s.done / s.total : 0;
    bar.value = s.stage === "check" ? 0.85 + 0.15 * frac : s.stage === "polish" ? 0.7
      : s.stage === "search" ? 0.7 * frac : 0;
    const what = s.stage === "search" ? `${STAGES.search}: restart ${s.done} of ${s.total}`
      : s.stage === "polish" ? STAGES.polish
      : s.stage === "check" ? `${STAGES.check}: ${s.done} of ${s.total}` : "starting the search";
    $("#synth-status").textContent = s.stage === "starting"
      ? `starting the search (${(s.startup || 0).toFixed(1)} s; the budget of ${fmt(s.budget, 3)} s starts with the search)`
      : `${what} · ${s.elapsed.toFixed(1)} s of the ${fmt(s.budget, 3)} s budget`;
  }

  async function synthesize() {
    const st = $("#synth-status");
    st.classList.remove("bad");
    const budget = Number($("#synth-budget").value);
    const bar = $("#synth-progress");
    const button = $("#synth-run");
    const cancel = $("#synth-cancel");
    button.disabled = true;
    cancel.hidden = false;
    cancel.disabled = false;
    bar.hidden = false;
    bar.value = 0;
    st.textContent = "starting the search";
    let polling = true;
    const poll = async () => {
      while (polling) {
        try {
          const res = await api("/api/synthesize/status", {});
          if (polling) synthProgress(await res.json());
        } catch (err) { /* the answer comes through the request itself */ }
        await new Promise((r) => setTimeout(r, 250));
      }
    };
    poll();
    try {
      const res = await api("/api/synthesize", { targets: state.synth.targets, type: $("#synth-type").value,
        closed: $("#synth-closed").checked, budget: Number.isFinite(budget) ? budget : $("#synth-budget").value,
        unit: lengthUnit().unit });
      const data = await res.json();
      state.synth.result = data;
      state.synth.selected = 0;
      window.linkageSynthesis = data;
      if (state.solve) state.geometry = geometry(state.solve);
      synthTable(data);
      drawFrame();
      const n = data.designs.length;
      const dropped = (data.asked || n) - n;
      st.textContent = `${n} distinct candidate${n === 1 ? "" : "s"} in ${fmt(data.seconds, 3)} s of the `
        + `${fmt(data.budget, 3)} s budget (and ${fmt(data.startup || 0, 2)} s to start)` + (dropped ? `; ${dropped} repeat${dropped > 1 ? "s" : ""} of a better one dropped` : "");
      bar.value = 1;
    } catch (err) {
      st.textContent = err.message || String(err);
      st.classList.toggle("bad", !/cancelled/.test(st.textContent));
    } finally {
      polling = false;
      button.disabled = false;
      cancel.hidden = true;
      bar.hidden = true;
      bumpRevision();
    }
  }

  async function cancelSynthesis() {
    $("#synth-cancel").disabled = true;
    try {
      const res = await api("/api/synthesize/cancel", {});
      window.linkageCancel = await res.json();
    } catch (err) {
      $("#synth-status").textContent = err.message || String(err);
    }
  }

  function synthTable(data) {
    const table = $("#synth-table");
    table.hidden = false;
    table.replaceChildren();
    const unit = lengthUnit();
    const head = document.createElement("tr");
    for (const h of ["", "#", `sum of squares [${unit.unit}²]`, `max [${unit.unit}]`, "transmission ≥", "compare", ""]) {
      const th = document.createElement("th"); th.textContent = h; head.appendChild(th);
    }
    table.appendChild(head);
    data.designs.forEach((d, k) => {
      const tr = document.createElement("tr");
      tr.className = k === state.synth.selected ? "selected" : "";
      if (d.failed || !d.compare_passed) tr.classList.add("fail");
      const sw = document.createElement("td");
      const s = document.createElement("span"); s.className = "swatch"; s.style.background = COLORS[k % COLORS.length];
      sw.appendChild(s);
      tr.appendChild(sw);
      const f2 = unit.f * unit.f;
      const cells = [String(k + 1), fmt(d.error.sum_sq * f2, 4), fmt(d.error.max * unit.f, 3),
        Number.isFinite(d.mu_min_deg) ? `${fmt(d.mu_min_deg, 3)}°` : "–",
        d.failed ? d.failed : (d.compare_passed ? "passed" : "FAILED")];
      for (const c of cells) { const td = document.createElement("td"); td.textContent = c; tr.appendChild(td); }
      const td = document.createElement("td");
      const open = document.createElement("button");
      open.textContent = "Open";
      open.title = "open this design as the current mechanism";
      open.dataset.candidate = String(k);
      open.addEventListener("click", (e) => {
        e.stopPropagation();
        addUploadOption(d.name, d.text, `synthesised #${k + 1}`);
        openMechanism(d.name, d.text);
      });
      td.appendChild(open);
      tr.appendChild(td);
      tr.addEventListener("click", () => {
        state.synth.selected = k;
        synthTable(data);
        drawFrame();
        bumpRevision();
      });
      table.appendChild(tr);
    });
  }

  // extra world points the view must hold in the synthesis panel: the targets and the candidates' curves
  function synthPoints() {
    if (state.tab !== "synthesis") return [];
    const pts = [...state.synth.targets];
    const r = state.synth.result;
    if (r) for (const d of r.designs) for (let i = 0; i < d.curve.x.length; i += 8) pts.push([d.curve.x[i], d.curve.y[i]]);
    return pts;
  }

  function drawSynthesis(v) {
    if (state.tab !== "synthesis") return;
    const r = state.synth.result;
    if (r) {
      r.designs.forEach((d, k) => {
        if (k === state.synth.selected) return;
        pathLine(v, d.curve.x, d.curve.y, d.curve.x.length, `${COLORS[k % COLORS.length]}99`, 1.2, [4, 3]);
      });
      const d = r.designs[state.synth.selected];
      if (d) pathLine(v, d.curve.x, d.curve.y, d.curve.x.length, COLORS[state.synth.selected % COLORS.length], 2.4);
    }
    ctx.save();
    ctx.strokeStyle = "#111"; ctx.lineWidth = 1.6; ctx.fillStyle = "#111";
    ctx.font = "10px system-ui, sans-serif";
    state.synth.targets.forEach(([x, y], k) => {
      const px = v.X(x); const py = v.Y(y);
      ctx.beginPath();
      ctx.moveTo(px - 5, py - 5); ctx.lineTo(px + 5, py + 5); ctx.moveTo(px - 5, py + 5); ctx.lineTo(px + 5, py - 5);
      ctx.stroke();
      ctx.fillText(String(k + 1), px + 6, py - 5);
    });
    ctx.restore();
  }

  // -------------------------------------------------------------------------------- animation
  // World bounds over the whole run (every point's path), so the view holds still while it moves.
  function geometry(data) {
    let x0 = Infinity; let x1 = -Infinity; let y0 = Infinity; let y1 = -Infinity;
    for (const p of Object.values(data.points)) {
      for (let i = 0; i < p.x.length; i++) {
        const x = p.x[i]; const y = p.y[i];
        if (x === null || y === null) continue;
        if (x < x0) x0 = x; if (x > x1) x1 = x; if (y < y0) y0 = y; if (y > y1) y1 = y;
      }
    }
    for (const [x, y] of synthPoints()) {
      if (x < x0) x0 = x; if (x > x1) x1 = x; if (y < y0) y0 = y; if (y > y1) y1 = y;
    }
    for (const cm of (data.describe && data.describe.cams) || []) {   // a plate reaches its largest radius all round
      const p = data.points[cm.pivot];
      const reach = Math.max(...cm.outline.map(([x, y]) => Math.hypot(x, y)));
      if (!p) continue;
      for (let i = 0; i < p.x.length; i++) {
        if (p.x[i] === null || p.y[i] === null) continue;
        x0 = Math.min(x0, p.x[i] - reach); x1 = Math.max(x1, p.x[i] + reach);
        y0 = Math.min(y0, p.y[i] - reach); y1 = Math.max(y1, p.y[i] + reach);
      }
    }
    if (!Number.isFinite(x0)) { x0 = -1; x1 = 1; y0 = -1; y1 = 1; }
    const pad = 0.08 * Math.max(x1 - x0, y1 - y0, 1e-9);
    return { x0: x0 - pad, x1: x1 + pad, y0: y0 - pad, y1: y1 + pad, n: data.t.length };
  }

  const canvas = $("#view");
  const ctx = canvas.getContext("2d");
  const MARGIN = { left: 52, right: 12, top: 12, bottom: 38 };

  // The canvas's CSS size as sizeCanvas set it: read from here, not from canvas.clientWidth, which forces a
  // layout of the whole page when a redraw follows DOM changes (a drag step's values and charts: ~1 ms).
  const canvasCss = { w: 0, h: 0 };

  function sizeCanvas() {
    const wrap = canvas.parentElement;
    const w = wrap.clientWidth;
    const h = Math.round(Math.min(w * 0.8, 520));
    const dpr = window.devicePixelRatio || 1;
    canvas.style.width = `${w}px`;
    canvas.style.height = `${h}px`;
    canvasCss.w = w;
    canvasCss.h = h;
    canvas.width = Math.round(w * dpr);
    canvas.height = Math.round(h * dpr);
    ctx.setTransform(dpr, 0, 0, dpr, 0, 0);
  }

  function view() {
    const g = state.geometry;
    const w = canvasCss.w - MARGIN.left - MARGIN.right;
    const h = canvasCss.h - MARGIN.top - MARGIN.bottom;
    const s = Math.min(w / (g.x1 - g.x0), h / (g.y1 - g.y0));
    const cx = MARGIN.left + w / 2 - s * (g.x0 + g.x1) / 2;
    const cy = MARGIN.top + h / 2 + s * (g.y0 + g.y1) / 2;
    return { s, X: (x) => cx + s * x, Y: (y) => cy - s * y, inv: (px, py) => [(px - cx) / s, (cy - py) / s], w, h };
  }

  function niceStep(span) {
    const raw = span / 6;
    const p = 10 ** Math.floor(Math.log10(raw));
    return [1, 2, 5, 10].map((m) => m * p).find((v) => v >= raw);
  }

  function drawAxes(v) {
    const [xa, yb] = v.inv(MARGIN.left, MARGIN.top + v.h);
    const [xb, ya] = v.inv(MARGIN.left + v.w, MARGIN.top);
    const L = lengthUnit();                   // ticks round in the file's unit
    const step = niceStep(Math.max(xb - xa, ya - yb) * L.f) / L.f;
    ctx.save();
    ctx.strokeStyle = "#eceff3";
    ctx.fillStyle = "#555";
    ctx.font = "11px system-ui, sans-serif";
    ctx.lineWidth = 1;
    ctx.textAlign = "center";
    for (let x = Math.ceil(xa / step) * step; x <= xb; x += step) {
      const px = Math.round(v.X(x)) + 0.5;
      ctx.beginPath(); ctx.moveTo(px, MARGIN.top); ctx.lineTo(px, MARGIN.top + v.h); ctx.stroke();
      ctx.fillText(fmt(x * L.f, 3), px, MARGIN.top + v.h + 14);
    }
    ctx.textAlign = "right";
    for (let y = Math.ceil(yb / step) * step; y <= ya; y += step) {
      const py = Math.round(v.Y(y)) + 0.5;
      ctx.beginPath(); ctx.moveTo(MARGIN.left, py); ctx.lineTo(MARGIN.left + v.w, py); ctx.stroke();
      ctx.fillText(fmt(y * L.f, 3), MARGIN.left - 6, py + 4);
    }
    ctx.strokeStyle = "#bbb";
    ctx.strokeRect(MARGIN.left + 0.5, MARGIN.top + 0.5, v.w, v.h);
    ctx.fillStyle = "#333";
    ctx.font = "12px system-ui, sans-serif";
    ctx.textAlign = "center";
    ctx.fillText(`x [${L.unit}]`, MARGIN.left + v.w / 2, MARGIN.top + v.h + 31);
    ctx.translate(13, MARGIN.top + v.h / 2);
    ctx.rotate(-Math.PI / 2);
    ctx.fillText(`y [${L.unit}]`, 0, 0);
    ctx.restore();
  }

  function pathLine(v, xs, ys, upto, style, width, dash) {
    ctx.save();
    ctx.strokeStyle = style; ctx.lineWidth = width; ctx.setLineDash(dash || []);
    ctx.beginPath();
    let pen = false;
    for (let i = 0; i <= upto && i < xs.length; i++) {
      if (xs[i] === null || ys[i] === null) { pen = false; continue; }
      if (pen) ctx.lineTo(v.X(xs[i]), v.Y(ys[i])); else ctx.moveTo(v.X(xs[i]), v.Y(ys[i]));
      pen = true;
    }
    ctx.stroke();
    ctx.restore();
  }

  function hull(pts) {
    if (pts.length < 3) return pts;
    const s = [...pts].sort((a, b) => a[0] - b[0] || a[1] - b[1]);
    const cross = (o, a, b) => (a[0] - o[0]) * (b[1] - o[1]) - (a[1] - o[1]) * (b[0] - o[0]);
    const half = (list) => {
      const out = [];
      for (const p of list) {
        while (out.length >= 2 && cross(out[out.length - 2], out[out.length - 1], p) <= 0) out.pop();
        out.push(p);
      }
      out.pop();
      return out;
    };
    return [...half(s), ...half([...s].reverse())];
  }

  function drawFrame() {
    if (state.draw) { drawDrawing(); return; }
    const data = state.solve;
    if (!data || !state.geometry) return;
    const W = canvasCss.w; const H = canvasCss.h;
    ctx.clearRect(0, 0, W, H);
    const v = view();
    drawAxes(v);
    ctx.save();
    ctx.beginPath(); ctx.rect(MARGIN.left, MARGIN.top, v.w, v.h); ctx.clip();
    const i = state.frame;
    const d = data.describe;
    const at = (p) => {
      const q = data.points[p];
      return q && q.x[i] !== null && q.y[i] !== null ? [v.X(q.x[i]), v.Y(q.y[i])] : null;
    };
    const out = data.points[d.output_point];
    if (out) pathLine(v, out.x, out.y, out.x.length, "rgba(214,39,40,0.25)", 1.5);
    const sp = state.sim && state.sim.simulated.points[d.output_point];
    if (sp) pathLine(v, sp.x, sp.y, sp.x.length, SIM_COLOR, 1.1, [5, 4]);    // MuJoCo's path, under the trace
    if (out) pathLine(v, out.x, out.y, i, "#d62728", 2.4);
    const colorOf = Object.fromEntries(d.links.map((link, k) => [link.name, COLORS[k % COLORS.length]]));
    for (const w of d.wheels || []) drawWheel(w, at, v, colorOf[w.link] || "#888888");
    for (const cm of d.cams || []) drawCam(cm, at, v, colorOf[cm.link] || "#888888");
    const ownDrawn = new Set((d.cylinders || []).flatMap((c) => [c.barrel, c.rod]));   // a cylinder draws its own
    for (const c of d.cylinders || []) drawCylinder(c, at, v, d.size);
    d.links.filter((link) => !ownDrawn.has(link.name)).forEach((link, k) => drawLink(link, k, at, data, i, v));
    for (const g of d.ground) { const p = at(g); if (p) drawGround(p); }
    for (const name of d.points) drawJoint(name, at(name), name === d.output_point, d.ground.includes(name));
    drawLoads(v, i);
    drawSynthesis(v);
    ctx.restore();
    drawLegend(d.output_point, !!sp);
    updateReadout();
    if (state.tab === "cam") paintCamProfile();
  }

  function drawLegend(point, sim) {
    const items = [[`path of ${point}`, "#d62728", 2.4, []]];
    if (sim) items.push(["MuJoCo", SIM_COLOR, 1.1, [5, 4]]);
    ctx.save();
    ctx.font = "11px system-ui, sans-serif";
    ctx.textBaseline = "middle";
    let x = MARGIN.left + 8;
    const y = MARGIN.top + 10;
    for (const [label, color, width, dash] of items) {
      ctx.strokeStyle = color; ctx.lineWidth = width; ctx.setLineDash(dash);
      ctx.beginPath(); ctx.moveTo(x, y); ctx.lineTo(x + 22, y); ctx.stroke();
      ctx.fillStyle = "#333";
      ctx.fillText(label, x + 27, y);
      x += 27 + ctx.measureText(label).width + 14;
    }
    ctx.restore();
  }

  // A linear actuator (describe's cylinders, as the videos draw them: sim/output/drawing.py Painter._cylinder):
  // a barrel from its pin along the cylinder, a thinner rod from the other pin back into it.
  function drawCylinder(c, at, v, size) {
    const b = at(c.base); const e = at(c.end);
    if (!b || !e) return;
    const len = Math.hypot(e[0] - b[0], e[1] - b[1]);
    if (!(len > 0)) return;
    const ux = (e[0] - b[0]) / len; const uy = (e[1] - b[1]) / len;
    const wide = Math.max(9, c.bore > 0 ? c.bore * v.s : 0.035 * size * v.s);
    const inside = Math.min(c.rod_inside * v.s, len); const barrel = Math.min(c.barrel_length * v.s, len);
    ctx.save();
    ctx.lineCap = "butt";
    ctx.strokeStyle = "#b8c2cc"; ctx.lineWidth = Math.max(1, 0.45 * wide);
    ctx.beginPath(); ctx.moveTo(b[0] + ux * inside, b[1] + uy * inside); ctx.lineTo(e[0], e[1]); ctx.stroke();
    ctx.strokeStyle = "#5a6470"; ctx.lineWidth = wide;
    ctx.beginPath(); ctx.moveTo(b[0], b[1]); ctx.lineTo(b[0] + ux * barrel, b[1] + uy * barrel); ctx.stroke();
    ctx.restore();
  }

  function drawLink(link, k, at, data, i, v) {
    const pts = link.points.map(at).filter(Boolean);
    if (!pts.length) return;
    const color = COLORS[k % COLORS.length];
    ctx.save();
    ctx.lineJoin = "round"; ctx.lineCap = "round";
    if (link.block) {
      ctx.strokeStyle = color; ctx.lineWidth = 6;                 // a point the block carries (a yoke's arm)
      for (const p of pts.slice(1)) {
        ctx.beginPath(); ctx.moveTo(pts[0][0], pts[0][1]); ctx.lineTo(p[0], p[1]); ctx.stroke();
      }
      const phi = (data.angles[link.name] || [])[i] ?? 0;
      const size = Math.max(10, 0.06 * data.describe.size * v.s);
      ctx.translate(pts[0][0], pts[0][1]);
      ctx.rotate(-phi);
      ctx.fillStyle = `${color}33`; ctx.strokeStyle = color; ctx.lineWidth = 2;
      ctx.fillRect(-size, -size * 0.55, 2 * size, 1.1 * size);
      ctx.strokeRect(-size, -size * 0.55, 2 * size, 1.1 * size);
    } else if (pts.length >= 3) {
      const poly = hull(pts);
      ctx.fillStyle = `${color}2e`; ctx.strokeStyle = color; ctx.lineWidth = 4;
      ctx.beginPath();
      poly.forEach((p, j) => (j ? ctx.lineTo(p[0], p[1]) : ctx.moveTo(p[0], p[1])));
      ctx.closePath(); ctx.fill(); ctx.stroke();
    } else if (pts.length === 2) {
      ctx.strokeStyle = color; ctx.lineWidth = 6;
      ctx.beginPath(); ctx.moveTo(pts[0][0], pts[0][1]); ctx.lineTo(pts[1][0], pts[1][1]); ctx.stroke();
    }
    ctx.restore();
  }

  // A gear (describe's wheels, as the videos draw them: sim/output/drawing.py Painter._wheel): a toothed
  // outline about its centre turning with its link (the direction centre -> ref), teeth in the ratio;
  // external gears filled pale, ring gears (teeth inward) in outline with their rim.
  function drawWheel(w, at, v, color) {
    const c = at(w.centre);
    if (!c) return;
    let base = 0;
    const r = w.ref ? at(w.ref) : null;
    if (r) base = Math.atan2(-(r[1] - c[1]), r[0] - c[0]);       // canvas y points down
    const m = 2 * w.radius / w.teeth;                            // the module: addendum m, dedendum 1.25 m
    const tip = w.ring ? w.radius - m : w.radius + m;
    const root = w.ring ? w.radius + 1.25 * m : w.radius - 1.25 * m;
    const pitch = 2 * Math.PI / w.teeth;
    ctx.save();
    ctx.beginPath();
    for (let k = 0; k < w.teeth; k++) {
      const a = base + w.phase + k * pitch;
      for (const [rad, da] of [[root, -0.30], [tip, -0.17], [tip, 0.17], [root, 0.30], [root, 0.5]]) {
        const px = c[0] + v.s * rad * Math.cos(a + da * pitch);
        const py = c[1] - v.s * rad * Math.sin(a + da * pitch);
        if (k === 0 && da === -0.30) ctx.moveTo(px, py); else ctx.lineTo(px, py);
      }
    }
    ctx.closePath();
    ctx.strokeStyle = color; ctx.lineWidth = 1.5;
    if (!w.ring) { ctx.fillStyle = `${color}24`; ctx.fill(); }
    ctx.stroke();
    if (w.ring) {
      ctx.beginPath(); ctx.arc(c[0], c[1], (root + 1.5 * m) * v.s, 0, 2 * Math.PI); ctx.stroke();
    }
    ctx.restore();
  }

  function drawGround([x, y]) {
    ctx.save();
    ctx.strokeStyle = "#444"; ctx.fillStyle = "#e8e8e8"; ctx.lineWidth = 1.2;
    ctx.beginPath(); ctx.moveTo(x, y); ctx.lineTo(x - 9, y + 14); ctx.lineTo(x + 9, y + 14); ctx.closePath();
    ctx.fill(); ctx.stroke();
    ctx.beginPath();
    for (let k = -12; k <= 8; k += 5) { ctx.moveTo(x + k, y + 20); ctx.lineTo(x + k + 5, y + 14); }
    ctx.moveTo(x - 13, y + 14); ctx.lineTo(x + 13, y + 14);
    ctx.stroke();
    ctx.restore();
  }

  function drawJoint(name, p, output, ground) {
    if (!p) return;
    ctx.save();
    ctx.fillStyle = output ? "#d62728" : "#fff";
    ctx.strokeStyle = output ? "#8b0000" : "#222";
    ctx.lineWidth = 1.5;
    ctx.beginPath(); ctx.arc(p[0], p[1], output ? 5 : 4, 0, 2 * Math.PI); ctx.fill(); ctx.stroke();
    ctx.fillStyle = "#222";
    ctx.font = `${output ? "bold " : ""}12px system-ui, sans-serif`;
    ctx.fillText(name, p[0] + 7, p[1] - (ground ? -4 : 7));
    ctx.restore();
  }

  function updateReadout() {
    const data = state.solve;
    const axis = inputAxis(data);
    const q = data.inputs[axis.key][state.frame];
    const value = axis.crank ? `${(q * DEG).toFixed(1)}°` : `${fmt(q * axis.f, 4)} ${displayUnit(axis.key, data.units)}`;
    $("#readout").textContent = `${axis.key} = ${value} · t = ${data.t[state.frame].toFixed(3)} s`;
  }

  function setFrame(i) {
    const n = state.solve ? state.solve.t.length : 1;
    state.frame = Math.max(0, Math.min(n - 1, i));
    const scrub = $("#scrub");
    scrub.max = String(n - 1);
    scrub.value = String(state.frame);
  }

  let clock = { wall: 0, sim: 0 };
  // While values are being edited the pose holds still (each answer redraws it): the main thread and the
  // two cores stay with the edit, which halves the slider-to-redraw latency, and the motion resumes from
  // the same pose when the edits pause.
  function tick(now) {
    const data = state.solve;
    if (now < state.holdUntil) {
      clock = { wall: now, sim: data ? data.t[state.frame] || 0 : 0 };
    } else if (state.playing && data && data.t.length > 1) {
      const tEnd = data.t[data.t.length - 1];
      const elapsed = ((now - clock.wall) / 1000) * state.speed;
      const t = (clock.sim + elapsed) % tEnd;
      const i = Math.round((t / tEnd) * (data.t.length - 1));
      if (i !== state.frame) {
        setFrame(i);
        drawFrame();
        moveCursors();
      }
    }
    requestAnimationFrame(tick);
  }

  function syncClock() {
    const data = state.solve;
    clock = { wall: performance.now(), sim: data ? data.t[state.frame] || 0 : 0 };
  }



  // --------------------------------------------------------------------------------- drawing
  // A linkage drawn from an empty page: ground pivots and joints placed with clicks, joined into links, one
  // link marked as the driven input. Each change asks /api/draw for the links-and-joints file, its mobility
  // and its Assur groups (or the one line that says what is wrong, whose names are marked in red).
  const DRAW_VIEW = { x0: -0.05, x1: 0.2, y0: -0.06, y1: 0.14, n: 1 };     // [m] the empty page's extent

  function startDrawing() {
    state.playing = false;
    $("#play").textContent = "Play";
    state.draw = { points: {}, links: [], input: null, pending: null, result: null, counts: { O: 0, J: 0, L: 0 } };
    state.savedGeometry = state.geometry;
    state.geometry = { ...DRAW_VIEW };
    document.body.classList.add("drawing");
    $("#draw-tools").hidden = false;
    $("#draw-note").hidden = false;
    drawNote("click to place ground pivots (drag one to move it); pick “joint” for moving joints, “link” to join "
      + "two points (Shift+click adds a point to the last link), “input” for the driven link", false);
    drawFrame();
    bumpRevision();
  }

  function leaveDrawing() {
    state.draw = null;
    document.body.classList.remove("drawing");
    $("#draw-tools").hidden = true;
    $("#draw-note").hidden = true;
    state.geometry = state.solve ? geometry(state.solve) : state.savedGeometry;
    drawFrame();
    bumpRevision();
  }

  function drawTool() { return document.querySelector("input[name=draw-tool]:checked").value; }

  function drawHit(e) {
    const r = canvas.getBoundingClientRect();
    const px = e.clientX - r.left; const py = e.clientY - r.top;
    const v = view();
    let best = null; let bestD = HIT_PX;
    for (const [name, p] of Object.entries(state.draw.points)) {
      const d = Math.hypot(v.X(p.x) - px, v.Y(p.y) - py);
      if (d <= bestD) { best = name; bestD = d; }
    }
    return best;
  }

  function drawLinkHit(e) {
    const r = canvas.getBoundingClientRect();
    const px = e.clientX - r.left; const py = e.clientY - r.top;
    const v = view();
    let best = null; let bestD = HIT_PX;
    for (const link of state.draw.links) {
      const pts = link.points.map((n) => state.draw.points[n]);
      for (let i = 0; i < pts.length; i++) {
        for (let j = i + 1; j < pts.length; j++) {
          const ax = v.X(pts[i].x); const ay = v.Y(pts[i].y); const bx = v.X(pts[j].x); const by = v.Y(pts[j].y);
          const L2 = (bx - ax) ** 2 + (by - ay) ** 2 || 1;
          const t = Math.max(0, Math.min(1, ((px - ax) * (bx - ax) + (py - ay) * (by - ay)) / L2));
          const d = Math.hypot(px - ax - t * (bx - ax), py - ay - t * (by - ay));
          if (d <= bestD) { best = link.name; bestD = d; }
        }
      }
    }
    return best;
  }

  function drawClick(e) {
    const d = state.draw;
    const tool = drawTool();
    const hit = drawHit(e);
    if (tool === "ground" || tool === "joint") {
      if (hit) {                                  // a placed point: move it with the pointer
        d.moving = hit;
        try { canvas.setPointerCapture(e.pointerId); } catch (err) { /* a synthetic event */ }
        return;
      }
      const [x, y] = worldAt(e);
      const ground = tool === "ground";
      let name;
      if (ground) name = `O${++d.counts.O}`;
      else { const k = d.counts.J++; name = k < 26 ? String.fromCharCode(65 + k) : `J${k - 25}`; }
      d.points[name] = { x, y, ground };
    } else if (tool === "link") {
      if (!hit) return;
      const last = d.links[d.links.length - 1];
      if (e.shiftKey && last) {
        if (!last.points.includes(hit)) last.points.push(hit);
      } else if (d.pending === null) {
        d.pending = hit;
        drawFrame();
        return;
      } else if (d.pending !== hit) {
        d.links.push({ name: `L${++d.counts.L}`, points: [d.pending, hit] });
        d.pending = null;
      } else {
        d.pending = null;
      }
    } else if (tool === "input") {
      const link = drawLinkHit(e);
      if (!link) return;
      d.input = link;
    } else if (tool === "erase") {
      if (hit) {
        delete d.points[hit];
        for (const link of d.links) link.points = link.points.filter((p) => p !== hit);
        d.links = d.links.filter((link) => link.points.length >= 2);
      } else {
        const link = drawLinkHit(e);
        if (!link) return;
        d.links = d.links.filter((l) => l.name !== link);
      }
      if (d.input && !d.links.some((l) => l.name === d.input)) d.input = null;
      d.pending = null;
    }
    drawFrame();
    drawCheck();
  }

  function drawingBody() {
    const d = state.draw;
    return { points: d.points, links: d.links.map((l) => ({ name: l.name, points: [...l.points] })), input: d.input };
  }

  async function drawCheck() {
    const d = state.draw;
    if (!Object.keys(d.points).length) { d.result = null; drawFrame(); bumpRevision(); return; }
    try {
      const body = drawingBody();
      window.linkageDrawingSent = body;
      const res = await api("/api/draw", { drawing: body });
      const r = await res.json();
      if (state.draw !== d) return;
      d.result = r;
      window.linkageDrawing = r;
      if (r.error) drawNote(r.error, true);
      else {
        const groups = r.groups.map((g) => `${g.places.join("+")} (links ${g.links.join(", ")}): ${g.class}`).join("; ");
        drawNote(`mobility ${r.mobility}, one input · Assur groups: ${groups || "none"} · Analyse opens it, Save writes it`, false);
      }
    } catch (err) {
      if (state.draw !== d) return;
      d.result = { error: err.message || String(err), names: [] };
      window.linkageDrawing = d.result;
      drawNote(d.result.error, true);
    }
    drawFrame();
    bumpRevision();
  }

  function drawNote(text, bad) {
    const el = $("#draw-note");
    el.textContent = text;
    el.classList.toggle("bad", !!bad);
  }

  function drawingText() {
    const r = state.draw && state.draw.result;
    if (!r || !r.text || r.error) {
      drawNote(r && r.error ? `fix the drawing first: ${r.error}` : "draw a linkage first", true);
      return null;
    }
    return r.text;
  }

  function saveDrawing() {
    const text = drawingText();
    if (!text) return;
    const url = URL.createObjectURL(new Blob([text], { type: "application/toml" }));
    const a = document.createElement("a");
    a.href = url; a.download = "drawn.toml";
    document.body.appendChild(a); a.click(); a.remove();
    setTimeout(() => URL.revokeObjectURL(url), 1000);
  }

  function analyseDrawing() {
    const text = drawingText();
    if (!text) return;
    leaveDrawing();
    addUploadOption("drawn", text, "drawing");
    openMechanism("drawn", text);
  }

  function drawDrawing() {
    const d = state.draw;
    const W = canvas.clientWidth; const H = canvas.clientHeight;
    ctx.clearRect(0, 0, W, H);
    const v = view();
    drawAxes(v);
    ctx.save();
    ctx.beginPath(); ctx.rect(MARGIN.left, MARGIN.top, v.w, v.h); ctx.clip();
    const bad = new Set((d.result && d.result.error && d.result.names) || []);
    const at = (n) => { const p = d.points[n]; return p ? [v.X(p.x), v.Y(p.y)] : null; };
    d.links.forEach((link, k) => {
      const pts = link.points.map(at).filter(Boolean);
      const color = bad.has(link.name) ? "#b42318" : COLORS[k % COLORS.length];
      ctx.save();
      ctx.lineJoin = "round"; ctx.lineCap = "round";
      ctx.strokeStyle = color; ctx.fillStyle = `${color}2e`;
      ctx.lineWidth = link.name === d.input ? 8 : 5;
      ctx.beginPath();
      const poly = pts.length >= 3 ? hull(pts) : pts;
      poly.forEach((p, j) => (j ? ctx.lineTo(p[0], p[1]) : ctx.moveTo(p[0], p[1])));
      if (pts.length >= 3) { ctx.closePath(); ctx.fill(); }
      ctx.stroke();
      const cx = pts.reduce((s, p) => s + p[0], 0) / pts.length;
      const cy = pts.reduce((s, p) => s + p[1], 0) / pts.length;
      ctx.fillStyle = color; ctx.font = "11px system-ui, sans-serif";
      ctx.fillText(link.name === d.input ? `${link.name} (input ↻)` : link.name, cx + 6, cy + 14);
      ctx.restore();
    });
    for (const [name, p] of Object.entries(d.points)) {
      const q = at(name);
      if (p.ground) drawGround(q);
      drawJoint(name, q, false, p.ground);
      if (bad.has(name) || name === d.pending) {
        ctx.save();
        ctx.strokeStyle = name === d.pending ? "#1f5fbf" : "#b42318"; ctx.lineWidth = 2;
        ctx.beginPath(); ctx.arc(q[0], q[1], 9, 0, 2 * Math.PI); ctx.stroke();
        ctx.restore();
      }
    }
    ctx.restore();
    if (d.result && d.result.error) {                 // the error on the canvas itself
      ctx.save();
      ctx.font = "12px system-ui, sans-serif"; ctx.fillStyle = "#b42318";
      const words = d.result.error.split(" ");
      let line = ""; let y = MARGIN.top + 18;
      for (const w of words) {
        if (ctx.measureText(`${line} ${w}`).width > v.w - 20 && line) { ctx.fillText(line, MARGIN.left + 10, y); line = w; y += 15; }
        else line = line ? `${line} ${w}` : w;
      }
      ctx.fillText(line, MARGIN.left + 10, y);
      ctx.restore();
    }
  }

  // -------------------------------------------------------------------------------- dragging
  // Grab a point of the drawing and drag it: /api/drag changes the file's values that place it (the
  // server inverts the file's parameterisation: sim/service/editing.py) and answers the new values with their
  // solve, so each step is one round trip; the input's tip scrubs the pose. Undo/redo restores the values
  // (and the file's text where a links-and-joints pose was changed) as they were before each drag.
  const HIT_PX = 10;
  const dragCh = { busy: false, next: null };

  function framePoints() {
    const data = state.solve;
    if (!data || !state.geometry) return [];
    const v = view();
    const i = state.frame;
    const out = [];
    for (const name of data.describe.points) {
      const q = data.points[name];
      if (!q || q.x[i] === null || q.y[i] === null) continue;
      out.push({ name, px: v.X(q.x[i]), py: v.Y(q.y[i]) });
    }
    return out;
  }

  function pointAt(e) {
    const r = canvas.getBoundingClientRect();
    const px = e.clientX - r.left; const py = e.clientY - r.top;
    let best = null; let bestD = HIT_PX;
    for (const p of framePoints()) {
      const d = Math.hypot(p.px - px, p.py - py);
      if (d <= bestD) { best = p.name; bestD = d; }
    }
    return best;
  }

  function gridStep() {                         // [m] a tenth of the axes' step, round in the file's unit
    const v = view();
    const [xa] = v.inv(MARGIN.left, 0); const [xb] = v.inv(MARGIN.left + v.w, 0);
    const L = lengthUnit();
    return niceStep((xb - xa) * L.f) / 10 / L.f;
  }

  function worldAt(e) {
    const r = canvas.getBoundingClientRect();
    let [x, y] = view().inv(e.clientX - r.left, e.clientY - r.top);
    if ($("#snap-grid").checked) {
      const g = gridStep();
      x = Math.round(x / g) * g; y = Math.round(y / g) * g;
    }
    return [x, y];
  }

  function poseInputs() {
    const data = state.solve;
    return data.describe.inputs.map((inp) => data.inputs[inp.q][state.frame]);
  }

  function snapshot() {
    return { set: { ...state.set }, text: state.mech.text, frame: state.frame };
  }

  function dragStart(e) {
    if (state.draw) { if (e.button === 0) drawClick(e); return; }
    if (state.tab === "synthesis" || !state.solve || e.button !== 0) return;
    const name = pointAt(e);
    if (!name) return;
    e.preventDefault();
    try { canvas.setPointerCapture(e.pointerId); } catch (err) { /* a synthetic event: no pointer to capture */ }
    state.playing = false;
    $("#play").textContent = "Play";
    state.drag = { point: name, before: snapshot(), moved: false, input: poseInputs() };
    socketOpen();
    canvas.style.cursor = "grabbing";
    dragNote(`dragging ${name}`, false);
  }

  function dragMove(e) {
    if (state.draw) {
      const d = state.draw;
      if (d.moving) {
        const [x, y] = worldAt(e);
        d.points[d.moving].x = x;
        d.points[d.moving].y = y;
        drawFrame();
      } else {
        const tool = drawTool();
        canvas.style.cursor = (tool === "ground" || tool === "joint") && drawHit(e) ? "grab" : "crosshair";
      }
      return;
    }
    if (!state.drag) {
      if (state.tab !== "synthesis" && state.solve) canvas.style.cursor = pointAt(e) ? "grab" : "";
      return;
    }
    if (state.drag.raw) return;                    // this drag's moves come as pointerrawupdate (dragRaw)
    state.drag.moved = true;
    dragSend(worldAt(e), e.type);
  }

  // A drag step goes to the server as the pointer moves, not when the page's next frame hands the move over:
  // Chromium holds a pointermove for the next frame's input phase (up to a frame, ~7 ms median measured by
  // benchmarks/app_drag.py --input real), while pointerrawupdate (a secure context: the app's localhost page)
  // comes as the input arrives. The answer is then drawn at the frame after it, one frame wait instead of two.
  // Events coming faster than the server answers are coalesced (dragSend keeps only the latest target).
  function dragRaw(e) {
    if (state.draw || !state.drag) return;
    state.drag.raw = true;
    state.drag.moved = true;
    dragSend(worldAt(e), e.type);
  }

  function dragEnd() {
    if (state.draw) {
      if (state.draw.moving) { state.draw.moving = null; drawCheck(); }
      return;
    }
    const d = state.drag;
    if (!d) return;
    state.drag = null;
    canvas.style.cursor = "";
    if (state.solve) { state.geometry = geometry(state.solve); drawFrame(); }
    const changed = pushUndo(d.before);
    if (changed) {                                  // the figures of merit once the values have settled
      const full = channels.full;
      clearTimeout(full.timer);
      full.timer = setTimeout(() => send("full"), FIGURES_DELAY_MS);
    }
  }

  async function dragSend(target, via = "") {   // via: the event that moved the pointer (for the benchmark)
    if (dragCh.busy) { dragCh.next = { target, via }; return; }
    dragCh.busy = true;
    dragCh.next = null;
    const d = state.drag;
    const version = ++state.version;
    state.holdUntil = performance.now() + HOLD_MS;
    const locked = [...document.querySelectorAll("#params input[data-lock]:checked")].map((c) => c.dataset.lock);
    const body = requestBody({ samples: SAMPLES, figures: false, arrays: "f64", outputs: wantedOutputs(true),
      point: d ? d.point : "", target, input: d ? d.input : poseInputs(), locked });
    if ($("#round-values").checked) body.round = gridStep() * lengthUnit().f;
    window.linkageDragBody = body;                  // for the drag benchmark's replay
    try {
      const started = performance.now();
      const answer = await apiJson("/api/drag", body);
      const received = performance.now();
      const socket = sock.last === "socket";
      applyDrag(answer, version);
      const done = performance.now();
      window.linkageTiming = { kind: "drag", request_ms: received - started, draw_ms: done - received, socket, via };
    } catch (err) {
      dragNote(err.message || String(err), true);
      bumpRevision();
    } finally {
      dragCh.busy = false;
      if (dragCh.next && state.drag) dragSend(dragCh.next.target, dragCh.next.via);
    }
  }

  // A drag step's arrays come as {f64: base64} (exact float64, little-endian as every browser's typed arrays):
  // ~1/10 of the server's time to write them as JSON numbers; NaN, a sample that does not assemble, as null.
  function unpack(v) {
    if (!v || typeof v.f64 !== "string") return v;
    const b = atob(v.f64);
    const u = new Uint8Array(b.length);
    for (let i = 0; i < b.length; i++) u[i] = b.charCodeAt(i);
    const f = new Float64Array(u.buffer);
    const out = new Array(f.length);
    for (let i = 0; i < f.length; i++) out[i] = Number.isNaN(f[i]) ? null : f[i];
    return out;
  }

  function unpackSolve(data) {
    const each = (o) => { for (const k of Object.keys(o || {})) o[k] = unpack(o[k]); };
    data.t = unpack(data.t);
    each(data.inputs); each(data.outputs); each(data.angles);
    for (const p of Object.values(data.points || {})) each(p);
    return data;
  }

  function applyDrag(answer, version) {
    const g = answer.drag;
    if (answer.solve) unpackSolve(answer.solve);
    window.linkageDrag = g;
    clearSimulation();
    staleDynamics();
    $("#video").hidden = true;
    state.set = g.set;
    if (g.text !== null) setText(g.text);
    for (const [name, v] of Object.entries(g.changed)) showValue(name, v);
    if (answer.solve) {
      $("#figures").classList.add("pending");
      applySolve(answer.solve, version, false, false, false);   // drawn once below, at the pose to show
      if (state.tab === "forces") requestForces();     // the joint forces follow the drag (one request at a time)
    }
    if (g.input !== null) setFrame(nearestFrame(g.input, g.input_name));
    drawFrame();
    moveCursors();
    dragNote(g.message, !g.reached && !g.scrub);
    bumpRevision();
  }

  function nearestFrame(q, name) {              // name: the input q is a value of (an actuator's own), else the first
    const data = state.solve;
    const inp = data.describe.inputs.find((i) => i.q === name) || data.describe.inputs[0];
    const qs = data.inputs[inp.q];
    const crank = inp.periodic;                    // its kind turns fully: compare angles round the turn
    let best = state.frame; let bestD = Infinity;
    for (let i = 0; i < qs.length; i++) {
      let dq = qs[i] - q;
      if (crank) dq = Math.abs(Math.atan2(Math.sin(dq), Math.cos(dq)));
      else dq = Math.abs(dq);
      if (dq < bestD) { bestD = dq; best = i; }
    }
    return best;
  }

  function setText(text) {                      // the file's new text: later requests and the picker carry it
    state.mech.text = text;
    const opt = $("#mechanism").selectedOptions[0];
    if (opt && opt.dataset.text !== undefined) opt.dataset.text = text;
  }

  function showValue(name, v) {
    const box = document.querySelector(`#params input[name="${CSS.escape(name)}"]`);
    const slider = document.querySelector(`#params input[data-param="${CSS.escape(name)}"]`);
    if (box) box.value = fmt(v);
    if (slider) moveSlider(slider, name, v);
  }

  function dragNote(text, bad) {
    const el = $("#drag-note");
    el.textContent = text;
    el.classList.toggle("bad", !!bad);
  }

  function restore(entry) {
    state.set = { ...entry.set };
    camDraftDropped();
    if (entry.text !== state.mech.text && entry.text !== null) setText(entry.text);
    for (const [name, v] of Object.entries(state.set)) if (Number.isFinite(Number(v))) showValue(name, Number(v));
    const frame = entry.frame;
    edited();
    state.frame = frame;
    undoButtons();
  }

  function undo() {
    if (!state.undo.length) return;
    state.redo.push(snapshot());
    restore(state.undo.pop());
    dragNote("undone", false);
  }

  function redo() {
    if (!state.redo.length) return;
    state.undo.push(snapshot());
    restore(state.redo.pop());
    dragNote("redone", false);
  }

  function pushUndo(before) {                    // an undo step where the values or the file changed
    const changed = JSON.stringify(before.set) !== JSON.stringify(state.set) || before.text !== state.mech.text;
    if (changed) {
      state.undo.push(before);
      state.redo = [];
      undoButtons();
    }
    return changed;
  }

  function undoButtons() {
    $("#undo").disabled = !state.undo.length;
    $("#redo").disabled = !state.redo.length;
  }

  // ------------------------------------------------------------------------------ mechanisms
  async function loadMechanisms() {
    const res = await fetch("/api/mechanisms");
    const data = await res.json();
    state.synthesisInfo = data.synthesis || null;
    const select = $("#mechanism");
    for (const m of data.mechanisms) {
      const opt = document.createElement("option");
      opt.value = m.name;
      opt.textContent = m.builtin ? `${m.name} (built-in)` : m.name;
      opt.title = m.description;
      select.appendChild(opt);
    }
    const first = data.initial || { name: data.names[0] };
    if (first.text) addUploadOption(first.name, first.text); else select.value = first.name;
    openMechanism(first.name, first.text ?? null);
  }

  // an opened file (or a synthesised design) among the picker's mechanisms; `from` says where it came from
  function addUploadOption(name, text, from = "file") {
    const select = $("#mechanism");
    const opt = document.createElement("option");
    opt.value = `upload:${select.options.length}`;
    opt.textContent = `${name} (${from})`;
    opt.dataset.name = name;
    opt.dataset.text = text;
    select.appendChild(opt);
    select.value = opt.value;
  }

  function openMechanism(name, text) {
    if (state.draw) leaveDrawing();
    state.editBefore = null;
    state.mech = { name, text };
    state.undo = [];
    state.redo = [];
    if ($("#undo")) undoButtons();
    state.set = {};
    state.lastEdited = null;
    state.inputRange = "";
    state.revolutions = 1;
    $("#input-range").value = "";
    $("#revolutions").value = "1";
    clearSimulation();
    $("#sim-status").textContent = "";
    $("#figures").replaceChildren();
    state.forces = null;
    window.linkageForces = null;
    state.forceKey = "";
    state.loadsDraw = null;
    stopEditingLoad();
    camDraftDropped();
    for (const c of state.forceCharts) c.plot.destroy();
    state.forceCharts = [];
    $("#force-charts").replaceChildren();
    $("#force-peaks").replaceChildren();
    $("#forces-verdict").hidden = true;
    $("#forces-status").textContent = "";
    staleDynamics();
    state.opened = state.version + 1;
    edited();
  }

  async function openFile(file) {
    $("#file-error").textContent = "";
    if (file.size > MAX_UPLOAD) {
      $("#file-error").textContent = `${file.name} is ${file.size} bytes: a mechanism file is at most ${MAX_UPLOAD}`;
      return;
    }
    const raw = await file.text();
    try {
      const res = await api("/api/open", { text: raw, filename: file.name });
      const { mechanism, text, kind } = await res.json();
      await api("/api/solve", { text, samples: 2, figures: false });     // it assembles, or say why here
      addUploadOption(mechanism, text, kind === "linkage/1" ? "file" : kind);
      openMechanism(mechanism, text);
    } catch (err) {
      $("#file-error").textContent = `${file.name}: ${err.message}`;
      status(`${file.name}: ${err.message}`, true);
    }
  }

  // ---------------------------------------------------------------------------------- wiring
  function wire() {
    $("#mechanism").addEventListener("change", (e) => {
      const opt = e.target.selectedOptions[0];
      openMechanism(opt.dataset.name || opt.value, opt.dataset.text ?? null);
    });
    $("#file").addEventListener("change", (e) => { if (e.target.files[0]) openFile(e.target.files[0]); e.target.value = ""; });
    $("#clear").addEventListener("click", () => openMechanism(state.mech.name, state.mech.text));
    $("#input-range").addEventListener("input", (e) => {
      state.inputRange = e.target.value;
      state.lastEdited = "input_range";
      edited();
    });
    $("#revolutions").addEventListener("input", (e) => {
      state.revolutions = e.target.value.trim();
      state.lastEdited = "revolutions";
      edited();
    });
    document.querySelectorAll("#analysis-panel [role=tab]").forEach((b) => b.addEventListener("click", () => showTab(b.dataset.tab)));
    for (const name of ["gravity", "force", "cutting"]) {
      $(`#${name}`).addEventListener("input", (e) => loadsEdited(name, e.target.value));
    }
    $("#forces-simulate").addEventListener("click", simulateForces);
    $("#dynamics-run").addEventListener("click", () => runDynamics(false));
    $("#dyn-speed-unit").addEventListener("change", speedUnitChanged);
    $("#dynamics-size").addEventListener("click", () => runDynamics(true));
    canvas.addEventListener("click", pickTarget);
    canvas.addEventListener("pointerdown", dragStart);
    canvas.addEventListener("pointermove", dragMove);
    canvas.addEventListener("pointerrawupdate", dragRaw);
    canvas.addEventListener("pointerup", dragEnd);
    canvas.addEventListener("pointercancel", dragEnd);
    $("#undo").addEventListener("click", undo);
    $("#draw-new").addEventListener("click", startDrawing);
    $("#draw-save").addEventListener("click", saveDrawing);
    $("#draw-open").addEventListener("click", analyseDrawing);
    $("#draw-exit").addEventListener("click", leaveDrawing);
    $("#redo").addEventListener("click", redo);
    document.addEventListener("keydown", (e) => {
      if (!(e.ctrlKey || e.metaKey) || e.target.matches("input[type=text], textarea")) return;
      const key = e.key.toLowerCase();
      if (key === "z" && !e.shiftKey) { e.preventDefault(); undo(); }
      else if (key === "y" || (key === "z" && e.shiftKey)) { e.preventDefault(); redo(); }
    });
    $("#synth-clear").addEventListener("click", () => { state.synth.targets = []; synthTargetsChanged(); });
    $("#synth-file").addEventListener("change", (e) => { if (e.target.files[0]) loadTargets(e.target.files[0]); e.target.value = ""; });
    $("#synth-run").addEventListener("click", synthesize);
    $("#synth-cancel").addEventListener("click", cancelSynthesis);
    $("#simulate").addEventListener("click", simulate);
    $("#render").addEventListener("click", renderVideo);
    document.querySelectorAll("[data-export]").forEach((b) => b.addEventListener("click", () => download(b.dataset.export)));
    $("#exit").addEventListener("click", exitApp);
    $("#play").addEventListener("click", () => {
      state.playing = !state.playing;
      $("#play").textContent = state.playing ? "Pause" : "Play";
      syncClock();
    });
    $("#scrub").addEventListener("input", (e) => {
      state.playing = false;
      $("#play").textContent = "Play";
      setFrame(Number(e.target.value));
      drawFrame();
      moveCursors();
    });
    $("#speed").addEventListener("change", (e) => { state.speed = Number(e.target.value); syncClock(); });
    window.addEventListener("resize", () => {
      sizeCanvas();
      drawFrame();
      const w = chartWidth();
      for (const c of state.charts) { c.plot.setSize({ width: w, height: CHART_HEIGHT }); c.err.setSize({ width: w, height: ERROR_HEIGHT }); }
      resizePanels();
      for (const c of state.cam.charts) c.setSize({ width: camChartWidth(), height: CAM_CHART_HEIGHT });
      drawCamProfile();
    });
  }

  async function exitApp() {
    try { await api("/api/exit", {}); } catch (err) { /* already gone */ }
    state.playing = false;
    $("#stopped").hidden = false;
  }


  // ----------------------------------------------------------------------------------- file loads
  // The file's [[loads]] drawn on the animation (POST /api/loads/draw: where each acts and how much over the
  // solve's samples) and the panel that adds, edits and removes them (POST /api/loads/edit rewrites the
  // file's [[loads]] text; the new text is the mechanism's from then on, one undo step).
  const LOAD_COLOR = "#c2185b";
  function hasFileLoads() {
    const t = state.mech && state.mech.text;
    return !!t && /\[\[\s*loads\s*\]\]|\[\s*friction\s*\]|"loads"\s*:|"friction"\s*:/.test(t);
  }

  const loadsChannel = { busy: false, queued: false };
  async function requestLoadsDraw() {
    if (!hasFileLoads()) {
      state.loadsDraw = null;
      window.linkageLoads = null;
      fileLoadsList([]);
      return;
    }
    if (loadsChannel.busy) { loadsChannel.queued = true; return; }
    loadsChannel.busy = true;
    loadsChannel.queued = false;
    const version = state.version;
    try {
      const res = await api("/api/loads/draw", requestBody({ samples: SAMPLES, digits: DRAG_DIGITS }));
      const data = await res.json();
      if (version >= state.opened && version >= (state.loadsDraw ? state.loadsDraw.version : -1)) {
        state.loadsDraw = { ...data, version };
        window.linkageLoads = state.loadsDraw;
        fileLoadsList(data.items || []);
        drawFrame();
        bumpRevision();
      }
    } catch (err) {
      $("#load-error").textContent = err.message || String(err);
    } finally {
      loadsChannel.busy = false;
      if (loadsChannel.queued) requestLoadsDraw();
    }
  }

  function loadScale(ld) {                      // the largest |value| of its kind's loads over the cycle
    let peak = 0;
    for (const o of state.loadsDraw.loads) {
      if (o.shape !== ld.shape) continue;
      const n = o.shape === "arrow" ? o.fx.length : o.value.length;
      for (let k = 0; k < n; k++) {
        const m = o.shape === "arrow" ? Math.hypot(o.fx[k] || 0, o.fy[k] || 0) : Math.abs(o.value[k] || 0);
        if (m > peak) peak = m;
      }
    }
    return peak || 1;
  }

  function arrowHead(x, y, ang, size) {
    ctx.beginPath();
    ctx.moveTo(x, y);
    ctx.lineTo(x - size * Math.cos(ang - 0.4), y - size * Math.sin(ang - 0.4));
    ctx.lineTo(x - size * Math.cos(ang + 0.4), y - size * Math.sin(ang + 0.4));
    ctx.closePath(); ctx.fill();
  }

  // The loads' labels are placed after every load is drawn, so that none covers another, a joint or a joint's
  // name: each wants the spot next to its load (``x``, ``y``: the text's left end on its baseline) and takes
  // the nearest free one among spots stepped a line at a time above and below it and to the left of its
  // anchor; one that had to move from its spot gets a thin leader line to the anchor (``ax``, ``ay``).
  const LABEL_LINE = 13;          // px: an 11 px label's height with a pixel above and below

  function labelBox(text, x, y, font) {
    ctx.save(); ctx.font = font;
    const w = ctx.measureText(text).width;
    ctx.restore();
    return { x, y: y - LABEL_LINE + 3, w, h: LABEL_LINE };
  }

  function overlaps(a, b) {
    return a.x < b.x + b.w && b.x < a.x + a.w && a.y < b.y + b.h && b.y < a.y + a.h;
  }

  function jointObstacles(v, i) {                 // every joint (its circle) and its name, as drawJoint draws them
    const data = state.solve; const d = data.describe;
    const out = [];
    for (const name of d.points) {
      const q = data.points[name];
      if (!q || q.x[i] === null || q.y[i] === null) continue;
      const p = [v.X(q.x[i]), v.Y(q.y[i])];
      out.push({ x: p[0] - 6, y: p[1] - 6, w: 12, h: 12 });
      const ground = d.ground.includes(name);
      out.push(labelBox(name, p[0] + 7, p[1] - (ground ? -4 : 7), "bold 12px system-ui, sans-serif"));
    }
    return out;
  }

  function placeLabels(labels, obstacles, v) {
    const placed = [];
    const taken = [...obstacles];
    const inView = (b) => b.x >= MARGIN.left + 2 && b.x + b.w <= MARGIN.left + v.w - 2 && b.y >= MARGIN.top + 2
      && b.y + b.h <= MARGIN.top + v.h - 2;
    for (const lb of labels) {
      const font = lb.font || "11px system-ui, sans-serif";
      const first = labelBox(lb.text, lb.x, lb.y, font);
      const spots = [];
      for (let k = 0; k <= 8; k++) {
        for (const dy of k ? [k * LABEL_LINE, -k * LABEL_LINE] : [0]) {
          for (const x of [lb.x, lb.ax - first.w - 10, lb.ax + 10]) spots.push([x, lb.y + dy]);
        }
      }
      spots.sort((a, b) => Math.hypot(a[0] - lb.x, a[1] - lb.y) - Math.hypot(b[0] - lb.x, b[1] - lb.y));
      let best = null;
      for (const [x, y] of spots) {
        const box = labelBox(lb.text, x, y, font);
        if (inView(box) && !taken.some((o) => overlaps(o, box))) { best = { ...box, bx: x, by: y }; break; }
      }
      if (!best) best = { ...first, bx: lb.x, by: lb.y };            // no free spot: where it wanted to be
      taken.push(best);
      placed.push({ text: lb.text, x: best.x, y: best.y, w: best.w, h: best.h, ax: lb.ax, ay: lb.ay });
      ctx.save(); ctx.font = font;
      if (Math.hypot(best.bx - lb.x, best.by - lb.y) > 1) {           // a leader line back to its load
        const cx = Math.min(Math.max(lb.ax, best.x), best.x + best.w);
        const cy = Math.min(Math.max(lb.ay, best.y), best.y + best.h);
        ctx.strokeStyle = lb.color; ctx.globalAlpha = 0.6; ctx.lineWidth = 0.8;
        ctx.beginPath(); ctx.moveTo(lb.ax, lb.ay); ctx.lineTo(cx, cy); ctx.stroke();
        ctx.globalAlpha = 1;
      }
      ctx.lineWidth = 3; ctx.strokeStyle = "rgba(255,255,255,0.85)";
      ctx.strokeText(lb.text, best.bx, best.by);
      ctx.fillStyle = lb.color; ctx.fillText(lb.text, best.bx, best.by);
      ctx.restore();
    }
    window.linkageLabels = { labels: placed, obstacles };
  }

  function drawLoads(v, i) {
    const L = state.loadsDraw;
    if (!L || !state.solve || L.samples !== state.solve.t.length) return;
    ctx.save();
    ctx.strokeStyle = LOAD_COLOR; ctx.fillStyle = LOAD_COLOR; ctx.lineCap = "round";
    const labels = [];
    const loadLabel = (text, x, y, ax, ay) => labels.push({ text, x, y, ax, ay, color: LOAD_COLOR });
    for (const ld of L.loads) {
      if (ld.shape === "arrow") {
        const x = ld.x[i]; const y = ld.y[i]; const fx = ld.fx[i]; const fy = ld.fy[i];
        if (x === null || y === null || fx === null || fy === null) continue;
        const m = Math.hypot(fx, fy);
        const p = [v.X(x), v.Y(y)];
        const len = m > 0 ? 22 + 48 * m / loadScale(ld) : 0;       // px: the largest force of the cycle 70 px
        const ang = Math.atan2(-fy, fx);                                   // canvas y points down
        const tip = [p[0] + len * Math.cos(ang), p[1] + len * Math.sin(ang)];
        ctx.strokeStyle = "rgba(255,255,255,0.9)"; ctx.lineWidth = 5;     // a halo: readable over a link
        ctx.beginPath(); ctx.moveTo(p[0], p[1]); ctx.lineTo(tip[0], tip[1]); ctx.stroke();
        ctx.strokeStyle = LOAD_COLOR; ctx.lineWidth = 2.2;
        ctx.beginPath(); ctx.moveTo(p[0], p[1]); ctx.lineTo(tip[0], tip[1]); ctx.stroke();
        if (len) arrowHead(tip[0], tip[1], ang, 9);
        loadLabel(`${ld.name} ${fmt(m, 3)} ${ld.unit}`, tip[0] + 4, tip[1] - 4, tip[0], tip[1]);
      } else if (ld.shape === "moment" || ld.shape === "pin") {
        const x = ld.x[i]; const y = ld.y[i]; const val = ld.value[i];
        if (x === null || y === null || val === null) continue;
        const p = [v.X(x), v.Y(y)];
        const r = ld.shape === "pin" ? 13 : 18;
        const ccw = val >= 0;                                           // + counter-clockwise in the world
        const a0 = ccw ? 0.5 : -0.5; const a1 = ccw ? -Math.PI * 1.25 : Math.PI * 1.25;
        ctx.lineWidth = 2;
        ctx.setLineDash(ld.symbol === "dashpot" ? [3, 2] : []);
        ctx.beginPath(); ctx.arc(p[0], p[1], r, a0, a1, ccw); ctx.stroke();
        ctx.setLineDash([]);
        const ex = p[0] + r * Math.cos(a1); const ey = p[1] + r * Math.sin(a1);
        arrowHead(ex, ey, a1 + (ccw ? -Math.PI / 2 : Math.PI / 2), 8);
        loadLabel(`${ld.name} ${fmt(val, 3)} ${ld.unit}`, p[0] + r + 4, p[1] + r + 2, p[0] + r * 0.7, p[1] + r * 0.7);
      } else if (ld.shape === "between") {
        const a = [v.X(ld.x1[i]), v.Y(ld.y1[i])]; const b = [v.X(ld.x2[i]), v.Y(ld.y2[i])];
        if ([...a, ...b].some((c) => !Number.isFinite(c))) continue;
        const dx = b[0] - a[0]; const dy = b[1] - a[1]; const len = Math.hypot(dx, dy) || 1;
        const ux = dx / len; const uy = dy / len; const nx = -uy; const ny = ux;
        // loads between the same two ends (a spring and a damper in parallel) side by side, 16 px apart
        const key = (o) => [o.x1[i], o.y1[i], o.x2[i], o.y2[i]].map((c) => Math.round(c * 1e6)).join();   // to a micrometre
        const twins = L.loads.filter((o) => o.shape === "between" && key(o) === key(ld));
        const off = (twins.indexOf(ld) - (twins.length - 1) / 2) * 16;
        if (off) {
          ctx.lineWidth = 1; ctx.beginPath();
          ctx.moveTo(a[0], a[1]); ctx.lineTo(a[0] + nx * off, a[1] + ny * off);
          ctx.moveTo(b[0], b[1]); ctx.lineTo(b[0] + nx * off, b[1] + ny * off); ctx.stroke();
          a[0] += nx * off; a[1] += ny * off; b[0] += nx * off; b[1] += ny * off;
        }
        const at = (s, w) => [a[0] + ux * s + nx * w, a[1] + uy * s + ny * w];
        ctx.lineWidth = 1.6;
        ctx.beginPath(); ctx.moveTo(a[0], a[1]);
        if (ld.symbol === "zigzag") {                                  // a zig-zag over the middle 70 %
          const z = 10; const s0 = 0.15 * len; const s1 = 0.85 * len;
          ctx.lineTo(...at(s0, 0));
          for (let k = 1; k < 2 * z; k++) ctx.lineTo(...at(s0 + (s1 - s0) * k / (2 * z), (k % 2 ? 1 : -1) * 6));
          ctx.lineTo(...at(s1, 0)); ctx.lineTo(b[0], b[1]); ctx.stroke();
        } else if (ld.symbol === "strut") {                            // a gas strut: a body and its rod
          const c1 = 0.55 * len;
          ctx.stroke();
          ctx.beginPath(); ctx.moveTo(...at(0, -5)); ctx.lineTo(...at(c1, -5)); ctx.lineTo(...at(c1, 5));
          ctx.lineTo(...at(0, 5)); ctx.closePath(); ctx.stroke();
          ctx.beginPath(); ctx.moveTo(...at(c1, 0)); ctx.lineTo(b[0], b[1]); ctx.stroke();
        } else {                                                         // a dashpot: cylinder and piston
          const c0 = 0.3 * len; const c1 = 0.62 * len; const pst = 0.5 * len;
          ctx.lineTo(...at(c0, 0)); ctx.stroke();
          ctx.beginPath(); ctx.moveTo(...at(c0, -7)); ctx.lineTo(...at(c0, 7));
          ctx.moveTo(...at(c0, -7)); ctx.lineTo(...at(c1, -7));
          ctx.moveTo(...at(c0, 7)); ctx.lineTo(...at(c1, 7)); ctx.stroke();
          ctx.beginPath(); ctx.moveTo(...at(pst, -5)); ctx.lineTo(...at(pst, 5));
          ctx.moveTo(...at(pst, 0)); ctx.lineTo(b[0], b[1]); ctx.stroke();
        }
        const mid = at(0.5 * len, off < 0 ? -14 : 12);
        const centre = at(0.5 * len, 0);
        loadLabel(`${ld.name} ${fmt(ld.value[i], 3)} ${ld.unit}`, mid[0], mid[1], centre[0], centre[1]);
      }
    }
    const data = state.solve;
    for (const f of L.friction || []) {                                // friction: a hatched ring at the joint
      const q = data.points[f.point];
      if (!q || q.x[i] === null) continue;
      const p = [v.X(q.x[i]), v.Y(q.y[i])];
      ctx.lineWidth = 1.2; ctx.strokeStyle = "#6d4c41";
      ctx.beginPath(); ctx.arc(p[0], p[1], 9, 0, 2 * Math.PI); ctx.stroke();
      ctx.beginPath();
      for (let k = 0; k < 8; k++) {
        const a = k * Math.PI / 4;
        ctx.moveTo(p[0] + 9 * Math.cos(a), p[1] + 9 * Math.sin(a));
        ctx.lineTo(p[0] + 13 * Math.cos(a + 0.3), p[1] + 13 * Math.sin(a + 0.3));
      }
      ctx.stroke();
      const text = `μ ${fmt(f.mu, 2)}`;
      const font = "10px system-ui, sans-serif";
      const w = labelBox(text, 0, 0, font).w;
      labels.push({ text, x: p[0] - 14 - w, y: p[1] - 8, ax: p[0] - 9, ay: p[1] - 4, color: "#6d4c41", font });
    }
    ctx.restore();
    placeLabels(labels, jointObstacles(v, i), v);
  }

  function describeLoad(it) {
    const where = it.point || (it.at ? `[${it.at.join(", ")}]` : "") || it.joint || "";
    const between = it.between ? it.between.map((e) => `${e[0]}:${Array.isArray(e[1]) ? e[1].join(",") : e[1]}`).join(" – ") : "";
    const law = it.magnitude !== undefined ? `${it.magnitude}` : it.table !== undefined ? "table" : "";
    const extra = it.stiffness !== undefined ? `k ${it.stiffness}` : it.damping !== undefined ? `c ${it.damping}` : "";
    return `${it.name}: ${it.kind.replace("_", " ")} ${it.link ? `on ${it.link} ` : ""}${where ? `at ${where} ` : ""}${between} ${law} ${extra}`.replace(/\s+/g, " ").trim();
  }

  function fileLoadsList(items) {
    state.loadItems = items;
    const ul = $("#file-loads");
    ul.replaceChildren();
    for (const it of items) {
      const li = document.createElement("li");
      const what = document.createElement("span");
      what.className = "load-what";
      what.textContent = describeLoad(it);
      const edit = document.createElement("button");
      edit.textContent = "Edit"; edit.title = `edit ${it.name}`;
      edit.addEventListener("click", () => editLoad(it));
      const rm = document.createElement("button");
      rm.textContent = "Remove"; rm.title = `remove ${it.name}`;
      rm.addEventListener("click", () => sendLoadEdit({ action: "remove", name: it.name }));
      li.append(what, edit, rm);
      ul.appendChild(li);
    }
  }

  // the form's fields come from the load kinds' registry (written into the page: sim.front.loads_panel.form_html):
  // each input has data-field (the [[loads]] key) and data-type (how its text is read), its label data-kinds
  const loadInputs = () => [...document.querySelectorAll("#load-form [data-field]")];

  function loadKindChanged() {
    const kind = $("#load-kind").value;
    document.querySelectorAll("#load-form label[data-kinds]").forEach((l) => {
      l.hidden = !l.dataset.kinds.split(" ").includes(kind);
    });
  }

  function numberOrText(t) { const n = Number(t); return t !== "" && Number.isFinite(n) ? n : t; }
  function pairOf(t) { return t.split(",").map((x) => numberOrText(x.trim())); }

  const READ_FIELD = {                           // data-type -> the [[loads]] value(s) of the typed text
    text: (t, k) => ({ [k]: t }),
    number: (t, k) => ({ [k]: numberOrText(t) }),
    pair: (t, k) => ({ [k]: pairOf(t) }),
    point: (t) => (t.includes(",") ? { at: pairOf(t) } : { point: t }),
    table: (t, k) => ({ [k]: t.split(";").filter((r) => r.trim()).map(pairOf) }),
    links: (t, k) => ({ [k]: t.split(",").map((x) => x.trim()) }),
    between: (t, k) => ({ [k]: t.split(/\s+/).map((e) => {
      const [link, rest] = [e.slice(0, e.indexOf(":")), e.slice(e.indexOf(":") + 1)];
      return [link, rest.includes(",") ? pairOf(rest) : rest];
    }) }),
    frame: (t, k) => (t === "link" ? { [k]: "link" } : {}),
  };

  function loadFromForm() {                      // the form as a [[loads]] table (the server checks it)
    const out = { name: $("#load-name").value.trim(), kind: $("#load-kind").value };
    for (const el of loadInputs()) {
      const t = el.value.trim();
      if (el.closest("label").hidden || t === "") continue;
      Object.assign(out, (READ_FIELD[el.dataset.type] || READ_FIELD.text)(t, el.dataset.field));
    }
    return out;
  }

  function editLoad(it) {
    state.loadEditing = it.name;
    $("#load-name").value = it.name;
    $("#load-kind").value = it.kind;
    loadKindChanged();
    const text = (v) => (Array.isArray(v) ? v.join(",") : String(v));
    for (const el of loadInputs()) {
      const k = el.dataset.field; const type = el.dataset.type;
      el.value = type === "frame" ? "world" : "";
      if (type === "point") {
        if (it.point !== undefined) el.value = it.point; else if (it.at) el.value = text(it.at);
      } else if (it[k] === undefined) {
        continue;
      } else if (type === "table" && Array.isArray(it[k])) {
        el.value = it[k].map(text).join("; ");
      } else if (type === "between") {
        el.value = it[k].map((e) => `${e[0]}:${text(e[1])}`).join(" ");
      } else if (type === "frame") {
        el.value = it[k] === "link" ? "link" : "world";
      } else {
        el.value = text(it[k]);
      }
    }
    $("#load-save").hidden = false; $("#load-cancel").hidden = false;
    $("#load-add").hidden = true;
  }

  function stopEditingLoad() {
    state.loadEditing = null;
    $("#load-save").hidden = true; $("#load-cancel").hidden = true; $("#load-add").hidden = false;
  }

  async function sendLoadEdit(extra) {
    $("#load-error").textContent = "";
    const body = { set: { ...state.set }, ...extra };
    if (state.mech.text !== null) body.text = state.mech.text; else body.mechanism = state.mech.name;
    try {
      const res = await api("/api/loads/edit", body);
      const data = await res.json();
      stopEditingLoad();
      if (extra.action === "add") {               // the next load's name: F1 -> F2 (names are unique)
        const names = new Set(data.loads.map((x) => x.name));
        const m = /^(.*?)(\d*)$/.exec(extra.load.name);
        let k = Number(m[2] || 1) + 1;
        while (names.has(`${m[1]}${k}`)) k += 1;
        $("#load-name").value = `${m[1]}${k}`;
      }
      if (state.mech.text === null) {             // a library mechanism becomes a file with its values and loads
        addUploadOption(data.mechanism, data.text, "with loads");
        openMechanism(data.mechanism, data.text);
      } else {
        const before = snapshot();
        setText(data.text);
        pushUndo(before);
        edited();
      }
      status(`${extra.action === "remove" ? "removed" : "wrote"} load ${extra.name || extra.load.name}; running again`);
    } catch (err) {
      $("#load-error").textContent = err.message || String(err);
      status(err.message || String(err), true);
    }
  }

  function wireLoads() {
    $("#load-kind").addEventListener("change", loadKindChanged);
    loadKindChanged();
    $("#load-add").addEventListener("click", () => sendLoadEdit({ action: "add", load: loadFromForm() }));
    $("#load-save").addEventListener("click", () => sendLoadEdit({ action: "replace", name: state.loadEditing, load: loadFromForm() }));
    $("#load-cancel").addEventListener("click", stopEditingLoad);
  }

  // ------------------------------------------------------------------------------------- cam panel
  // A cam's law (POST /api/cam: the segments as the file writes them, the SVAJ diagram over the cam angle and
  // the profile with its pressure angle and radius of curvature, all computed by the server) and its editor:
  // each change of a row, the roller or the base radius is sent as an edit, which the server writes into the
  // file (tomlkit, comments kept) and answers with the new diagram; a refused edit shows its one line here.
  const CAM_SVAJ = [["s", "displacement", "#1f77b4"], ["v", "velocity", "#2ca02c"],
    ["a", "acceleration", "#ff7f0e"], ["j", "jerk", "#9467bd"]];
  const CAM_CHART_HEIGHT = 200;
  const CAM_PA_SCALE = 45;            // [deg] the profile's colour ramp: green at 0, red from here up
  const camChannel = { busy: false, queued: null };

  function camsOf(d) { return (d && d.cams) || []; }

  function camDraftDropped() {                      // undo, Clear or another file: the rows follow the file again
    state.cam.draft = false;
    $("#cam-error").textContent = "";
  }

  function camOpened(d, mechanism) {               // a new mechanism: the tab and the picker follow its cams
    const cams = camsOf(d);
    $("#tab-cam").hidden = !cams.length;
    const key = `${mechanism}:${cams.map((c) => c.name).join(",")}`;
    if (key === state.cam.key && cams.length) {     // the same cams again (a library one written out by an edit)
      if (state.tab === "cam") requestCam();
      return;
    }
    state.cam.key = key;
    state.cam.data = null;
    state.cam.draft = false;
    window.linkageCam = null;
    const pick = $("#cam-pick");
    pick.replaceChildren(...cams.map((c) => { const o = document.createElement("option"); o.value = c.name; o.textContent = c.name; return o; }));
    pick.hidden = cams.length < 2;
    state.cam.name = cams.length ? cams[0].name : null;
    if (!cams.length && state.tab === "cam") showTab("curves");
    else if (cams.length && state.tab === "cam") requestCam();
  }

  function camBody(extra) {
    const body = { set: { ...state.set }, cam: state.cam.name, ...(extra || {}) };
    if (state.mech.text !== null) body.text = state.mech.text; else body.mechanism = state.mech.name;
    return body;
  }

  // The rows are the user's draft: every local change (a box, a row added or removed) marks it, and until an
  // edit of the latest draft is written into the file the answers that only refresh the panel (after a slider
  // moved, say) leave the rows, the plots and the line alone. A refused edit keeps its draft to be fixed.
  function camTouched() {
    state.cam.changes += 1;
    state.cam.draft = true;
  }

  async function requestCam(edit) {
    if (!state.cam.name) return;
    if (camChannel.busy) { camChannel.queued = edit ? { edit } : (camChannel.queued || {}); return; }
    camChannel.busy = true;
    camChannel.queued = null;
    const version = state.version;
    const changes = state.cam.changes;              // the draft this edit sends
    try {
      const res = await api("/api/cam", camBody(edit ? { edit } : {}));
      const data = await res.json();
      const cam = data.cams[state.cam.name];
      if (!edit && state.cam.draft) return;         // a refresh under a draft: the draft stays as it is
      $("#cam-error").textContent = data.problem || "";
      if (edit && data.text) {
        if (state.cam.changes === changes) state.cam.draft = false;   // written; a later change is still a draft
        if (state.mech.text === null) {             // a library mechanism becomes a file with its values and its law
          addUploadOption(data.mechanism, data.text, "cam edited");
          openMechanism(data.mechanism, data.text);
        } else {
          const before = snapshot();
          setText(data.text);
          pushUndo(before);
          edited();
        }
        status(`wrote the law of cam ${state.cam.name}; running again`);
      } else if (data.problem) {
        state.cam.draft = true;                     // refused: its draft stays to be fixed
        status(data.problem, true);
      }
      if (edit || version >= state.opened) showCam(cam, !!data.problem);
    } catch (err) {
      if (!edit && state.cam.draft) return;
      if (edit) state.cam.draft = true;
      $("#cam-error").textContent = err.message || String(err);
      $("#cam-status").textContent = "not written";
      status(err.message || String(err), true);
      bumpRevision();
    } finally {
      camChannel.busy = false;
      const next = camChannel.queued;
      if (next) requestCam(next.edit);
    }
  }

  function showCam(cam, refused) {
    state.cam.data = cam;
    window.linkageCam = cam;
    // the rows follow the file, except a draft not yet written (a refused edit stays to be fixed) and a box
    // being typed in (the answer to the edit of another box must not overwrite it)
    const el = document.activeElement;
    const typing = el && el.matches("#pane-cam input, #pane-cam select") && cam.written
      && document.querySelectorAll("#cam-segments tbody tr").length === cam.written.segments.length;
    if (!state.cam.draft && !typing) camRows(cam.written, cam.shapes);
    $("#cam-status").textContent = refused ? "not written: fix the edit" : "";
    drawSvaj(cam);
    drawCamProfile();
    camMarks(cam);
    bumpRevision();
  }

  function camRows(written, shapes) {
    const body = $("#cam-segments tbody");
    $("#cam-segments").hidden = !written;
    for (const el of document.querySelectorAll(".cam-fields > :not(#cam-status)")) el.hidden = !written;
    if (!written) {                                 // a cam given by its outline (profile = "cam.csv")
      body.replaceChildren();
      $("#cam-status").textContent = "this cam is given by its profile: the law below is found from it, no segments to edit";
      return;
    }
    const unit = written.rise_measure === "angle" ? "angle, e.g. 12deg" : (state.cam.data || {}).length_unit || "";
    $("#cam-rise-head").textContent = `rise [${unit}]`;
    body.replaceChildren(...written.segments.map((seg, k) => {
      const tr = document.createElement("tr");
      const cell = (el) => { const td = document.createElement("td"); td.appendChild(el); tr.appendChild(td); return el; };
      const num = document.createElement("span"); num.textContent = String(k + 1); cell(num);
      const sel = document.createElement("select");
      sel.dataset.key = "shape";
      sel.setAttribute("aria-label", `segment ${k + 1} shape`);
      for (const s of shapes) { const o = document.createElement("option"); o.value = s; o.textContent = s.replace("_", " "); sel.appendChild(o); }
      sel.value = seg.shape;
      cell(sel);
      for (const key of ["duration", "rise"]) {
        const box = document.createElement("input");
        box.type = "text"; box.dataset.key = key; box.autocomplete = "off"; box.spellcheck = false;
        box.setAttribute("aria-label", `segment ${k + 1} ${key}`);
        box.value = seg[key] === undefined ? "" : String(seg[key]);
        box.disabled = key === "rise" && seg.shape === "dwell";
        cell(box);
      }
      const del = document.createElement("button");
      del.textContent = "×"; del.title = "remove this segment"; del.dataset.remove = "1";
      del.disabled = written.segments.length < 2;
      cell(del);
      return tr;
    }));
    $("#cam-roller").value = String(written.roller);
    $("#cam-roller-label").hidden = !!state.cam.data && state.cam.data.contact !== "roller";
    $("#cam-base").value = String(written.base_radius);
    $("#cam-length-unit").textContent = (state.cam.data || {}).length_unit || "";
  }

  function camEdit() {                              // the rows as the edit the server takes
    const segments = [];
    [...document.querySelectorAll("#cam-segments tbody tr")].forEach((tr) => {
      const shape = tr.querySelector("[data-key=shape]").value;
      const row = { shape, duration: numberOrText(tr.querySelector("[data-key=duration]").value.trim()) };
      const rise = tr.querySelector("[data-key=rise]");
      if (shape !== "dwell" && rise.value.trim() !== "") row.rise = numberOrText(rise.value.trim());
      if (shape === "dwell") rise.value = "";
      rise.disabled = shape === "dwell";
      segments.push(row);
    });
    const edit = { base_radius: numberOrText($("#cam-base").value.trim()) };
    if (segments.length) edit.segments = segments;
    if (state.cam.data && state.cam.data.contact === "roller") edit.roller = numberOrText($("#cam-roller").value.trim());
    return edit;
  }

  function camAddRow() {
    camTouched();
    const edit = camEdit();
    edit.segments.push({ shape: "dwell", duration: "0deg" });
    const written = { ...state.cam.data.written, segments: edit.segments, roller: $("#cam-roller").value,
      base_radius: $("#cam-base").value };
    camRows(written, state.cam.data.shapes);
    const boxes = document.querySelectorAll("#cam-segments [data-key=duration]");
    boxes[boxes.length - 1].focus();
    $("#cam-status").textContent = "give the new segment a duration and take it from another (they make one turn)";
  }

  function camChartWidth() {
    const box = $("#cam-svaj");
    const w = box.clientWidth || paneWidth();
    return w >= 480 ? Math.floor((w - 12) / 2) - 8 : Math.floor(w) - 8;   // a card's border and padding
  }

  function drawSvaj(cam) {
    for (const c of state.cam.charts) c.destroy();
    state.cam.charts = [];
    const box = $("#cam-svaj");
    box.replaceChildren();
    const s = cam.svaj;
    const bounds = cam.boundaries || [];
    const marks = (u) => {                          // the segments' ends, as faint verticals
      const c = u.ctx;
      c.save();
      c.strokeStyle = "rgba(0,0,0,0.18)"; c.setLineDash([3, 3]); c.lineWidth = 1;
      for (const b of bounds) {
        const x = Math.round(u.valToPos(b, "x", true)) + 0.5;
        c.beginPath(); c.moveTo(x, u.bbox.top); c.lineTo(x, u.bbox.top + u.bbox.height); c.stroke();
      }
      c.restore();
    };
    for (const [key, name, color] of CAM_SVAJ) {
      const card = document.createElement("div");
      card.className = "panel-chart";
      card.dataset.quantity = key;
      box.appendChild(card);
      const plot = new uPlot({
        width: camChartWidth(), height: CAM_CHART_HEIGHT, title: `${name} ${key} [${s.units[key]}]`,
        scales: { x: { time: false, range: [0, 360] } }, legend: { show: false },
        cursor: { drag: { x: false, y: false } }, hooks: { draw: [marks] },
        axes: [{ ...axisOptions("cam angle [deg]"), incrs: [15, 30, 45, 90, 180] }, axisOptions("", 60)],
        series: [{ label: "cam angle" }, { label: key, stroke: color, width: 1.8 }],
      }, [s.theta, s[key]], card);
      state.cam.charts.push(plot);
    }
    window.linkageCamPlots = state.cam.charts;      // for tests: the SVAJ plots as drawn
  }

  function paColor(deg) {                          // |pressure angle| -> green, yellow, red
    const f = Math.max(0, Math.min(1, Math.abs(deg) / CAM_PA_SCALE));
    const r = f < 0.5 ? Math.round(60 + 2 * f * (230 - 60)) : 230;
    const g = f < 0.5 ? 170 : Math.round(170 - 2 * (f - 0.5) * 150);
    return `rgb(${r},${g},40)`;
  }

  function drawCamProfile() {
    const cam = state.cam.data;
    const shown = $("#cam-profile");
    if (!cam || $("#pane-cam").hidden) return;
    const dpr = window.devicePixelRatio || 1;
    const W = shown.clientWidth || 500; const H = shown.clientHeight || 380;
    const cv = document.createElement("canvas");     // the still drawing; paintCamProfile adds the pose on it
    cv.width = Math.round(W * dpr); cv.height = Math.round(H * dpr);
    shown.width = cv.width; shown.height = cv.height;
    const c = cv.getContext("2d");
    c.setTransform(dpr, 0, 0, dpr, 0, 0);
    c.clearRect(0, 0, W, H);
    const P = cam.profile; const Q = cam.pitch;
    let reach = 0;
    for (let i = 0; i < P.x.length; i++) {
      for (const [x, y] of [[P.x[i], P.y[i]], [Q.x[i], Q.y[i]]]) if (x !== null && y !== null) reach = Math.max(reach, Math.abs(x), Math.abs(y));
    }
    reach = reach || 1;
    const legendW = 110;
    const s = 0.46 * Math.min(W - legendW, H) / reach;
    const cx = (W - legendW) / 2; const cy = H / 2;
    const X = (x) => cx + s * x; const Y = (y) => cy - s * y;
    c.save();
    c.strokeStyle = "#bbb"; c.lineWidth = 1; c.setLineDash([2, 4]);
    c.beginPath(); c.arc(cx, cy, s * cam.base_radius, 0, 2 * Math.PI); c.stroke();     // the base circle
    c.setLineDash([6, 4]); c.strokeStyle = "#999";
    c.beginPath();
    Q.x.forEach((x, i) => { if (x !== null && Q.y[i] !== null) (i ? c.lineTo(X(x), Y(Q.y[i])) : c.moveTo(X(x), Y(Q.y[i]))); });
    c.closePath(); c.stroke();                                                            // the pitch curve
    c.setLineDash([]);
    c.lineWidth = 4; c.lineCap = "round";
    const n = P.x.length;
    for (let i = 0; i < n; i++) {                    // the profile, each piece coloured by its pressure angle
      const j = (i + 1) % n;
      if ([P.x[i], P.y[i], P.x[j], P.y[j]].includes(null)) continue;
      c.strokeStyle = paColor(P.pressure_angle[i] ?? 0);
      c.beginPath(); c.moveTo(X(P.x[i]), Y(P.y[i])); c.lineTo(X(P.x[j]), Y(P.y[j])); c.stroke();
    }
    c.strokeStyle = "#d00000"; c.lineWidth = 7;      // where it undercuts
    for (let i = 0; i < n; i++) {
      const j = (i + 1) % n;
      if (!P.undercut[i] || [P.x[i], P.y[i], P.x[j], P.y[j]].includes(null)) continue;
      c.beginPath(); c.moveTo(X(P.x[i]), Y(P.y[i])); c.lineTo(X(P.x[j]), Y(P.y[j])); c.stroke();
    }
    c.fillStyle = "#222"; c.beginPath(); c.arc(cx, cy, 3, 0, 2 * Math.PI); c.fill();    // the pivot
    const unit = cam.length_unit;
    const labels = [];
    const pa = cam.pressure_angle_max;
    labels.push([pa, "#b35900", `max pressure angle ${fmt(pa.value, 3)}° at ${fmt(pa.theta, 4)}°`, "triangle"]);
    const rho = cam.rho_convex_min;
    if (rho && rho.value !== null) labels.push([rho, "#1f5fbf", `smallest radius of curvature ${fmt(rho.value, 3)} ${unit} at ${fmt(rho.theta, 4)}°`, "circle"]);
    if (cam.undercut) labels.push([cam.undercut, "#d00000", `undercut at cam angle ${fmt(cam.undercut.theta, 4)}°`, "cross"]);
    c.font = "12px system-ui, sans-serif";
    const placed = [];                               // labels drawn [left, y, width]: the next one moves down clear
    for (const [m, color, text, shape] of labels) {
      const px = X(m.x); const py = Y(m.y);
      c.strokeStyle = color; c.fillStyle = color; c.lineWidth = 2.2;
      c.beginPath();
      if (shape === "triangle") { c.moveTo(px, py - 8); c.lineTo(px - 7, py + 5); c.lineTo(px + 7, py + 5); c.closePath(); c.fill(); }
      else if (shape === "circle") { c.arc(px, py, 6, 0, 2 * Math.PI); c.stroke(); }
      else { c.moveTo(px - 8, py - 8); c.lineTo(px + 8, py + 8); c.moveTo(px + 8, py - 8); c.lineTo(px - 8, py + 8); c.stroke(); }
      // the label outward from the pivot, on the side the mark is
      const out = Math.atan2(py - cy, px - cx);
      const lx = px + 16 * Math.cos(out); const ly0 = py + 16 * Math.sin(out);
      c.textAlign = Math.cos(out) >= 0 ? "left" : "right";
      c.textBaseline = "middle";
      const wdt = c.measureText(text).width;
      const left = Math.max(4, Math.min(W - legendW - wdt - 4, c.textAlign === "left" ? lx : lx - wdt));
      let ly = ly0;
      while (placed.some(([l, t, w]) => left < l + w + 4 && l < left + wdt + 4 && Math.abs(ly - t) < 17)) ly += 18;
      placed.push([left, ly, wdt]);
      c.textAlign = "left";
      c.fillStyle = "rgba(255,255,255,0.85)";
      c.fillRect(left - 2, ly - 8, wdt + 4, 16);
      c.fillStyle = color;
      c.fillText(text, left, ly);
    }
    // the colour ramp's legend
    const lx = W - legendW + 24; const top = 30; const hgt = H - 110;
    for (let k = 0; k <= 60; k++) {
      c.fillStyle = paColor(CAM_PA_SCALE * (1 - k / 60));
      c.fillRect(lx, top + (k / 60) * hgt, 14, hgt / 60 + 1);
    }
    c.fillStyle = "#333"; c.textAlign = "left"; c.textBaseline = "middle"; c.font = "11px system-ui, sans-serif";
    for (const v of [0, 15, 30, 45]) c.fillText(`${v}°${v === CAM_PA_SCALE ? "+" : ""}`, lx + 20, top + (1 - v / CAM_PA_SCALE) * hgt);
    c.fillText("|pressure angle|", lx - 10, top - 14);
    c.strokeStyle = "#999"; c.setLineDash([6, 4]); c.lineWidth = 1;
    c.beginPath(); c.moveTo(lx - 20, top + hgt + 30); c.lineTo(lx + 4, top + hgt + 30); c.stroke();
    c.setLineDash([2, 4]); c.beginPath(); c.moveTo(lx - 20, top + hgt + 48); c.lineTo(lx + 4, top + hgt + 48); c.stroke();
    c.fillText("pitch curve", lx + 10, top + hgt + 30);
    c.fillText("base circle", lx + 10, top + hgt + 48);
    c.restore();
    state.cam.sheet = { canvas: cv, X, Y, s, cam };
    paintCamProfile();
  }

  // The profile's still drawing and, on it, the follower at the animation's pose seen from the cam: the contact
  // point and the roller (or the face's foot) at the cam angle of the current frame. Called at every frame.
  function paintCamProfile() {
    const sheet = state.cam.sheet;
    if (!sheet || sheet.cam !== state.cam.data || $("#pane-cam").hidden) return;
    const shown = $("#cam-profile");
    const c = shown.getContext("2d");
    c.setTransform(1, 0, 0, 1, 0, 0);
    c.clearRect(0, 0, shown.width, shown.height);
    c.drawImage(sheet.canvas, 0, 0);
    if (state.cam.draft) return;                    // a draft's profile: the animation still runs the file's law
    const data = state.solve;
    const cm = ((data && data.describe && data.describe.cams) || []).find((x) => x.name === state.cam.name);
    if (!cm) return;
    const a = data.points[cm.ref[0]]; const b = data.points[cm.ref[1]]; const i = state.frame;
    if (!a || !b || [a.x[i], a.y[i], b.x[i], b.y[i]].includes(null)) return;
    const theta = ((Math.atan2(b.y[i] - a.y[i], b.x[i] - a.x[i]) * DEG) % 360 + 360) % 360;
    const P = sheet.cam.profile; const Q = sheet.cam.pitch;
    let k = 0; let best = Infinity;
    P.theta.forEach((t, j) => { const d = Math.abs(t - theta); if (d < best) { best = d; k = j; } });
    if (P.x[k] === null || Q.x[k] === null) return;
    const dpr = window.devicePixelRatio || 1;
    c.setTransform(dpr, 0, 0, dpr, 0, 0);
    c.strokeStyle = "#1a1a1a"; c.fillStyle = "#1a1a1a"; c.lineWidth = 1.2;
    const rr = sheet.cam.contact === "roller" ? sheet.cam.roller : 0;
    if (rr > 0) { c.beginPath(); c.arc(sheet.X(Q.x[k]), sheet.Y(Q.y[k]), rr * sheet.s, 0, 2 * Math.PI); c.stroke(); }
    c.beginPath(); c.arc(sheet.X(P.x[k]), sheet.Y(P.y[k]), 3.5, 0, 2 * Math.PI); c.fill();
    c.font = "11px system-ui, sans-serif"; c.textAlign = "left"; c.textBaseline = "top";
    c.fillText(`contact at cam angle ${theta.toFixed(1)}°`, 8, 8);
  }

  function camMarks(cam) {
    const li = (text, bad) => { const el = document.createElement("li"); el.textContent = text; if (bad) el.className = "bad"; return el; };
    const items = [li(`largest pressure angle ${fmt(cam.pressure_angle_max.value, 4)}° at cam angle ${fmt(cam.pressure_angle_max.theta, 4)}°`)];
    const sharp = cam.rho_convex_min;
    if (sharp && sharp.value !== null) items.push(li(`smallest convex radius of curvature ${fmt(sharp.value, 4)} ${cam.length_unit} at cam angle ${fmt(sharp.theta, 4)}° (marked)`));
    if (cam.rho_min.value !== null && cam.rho_min.value < 0) items.push(li(`concave: radius of curvature down to ${fmt(cam.rho_min.value, 4)} ${cam.length_unit} at cam angle ${fmt(cam.rho_min.theta, 4)}° (linkage check's rho_min)`));
    if (cam.undercut) items.push(li(cam.undercut.message, true));
    $("#cam-marks").replaceChildren(...items);
  }

  function wireCam() {
    $("#cam-pick").addEventListener("change", (e) => { state.cam.name = e.target.value; requestCam(); });
    $("#cam-segments").addEventListener("change", () => { camTouched(); requestCam(camEdit()); });
    $("#cam-segments").addEventListener("click", (e) => {
      const b = e.target.closest("button[data-remove]");
      if (!b) return;
      b.closest("tr").remove();                      // the table is the draft: the row goes, then the draft is sent
      const rows = [...document.querySelectorAll("#cam-segments tbody tr")];
      camTouched();
      rows.forEach((tr, k) => { tr.firstChild.textContent = String(k + 1); });
      if (rows.length < 2) rows.forEach((tr) => { tr.querySelector("button[data-remove]").disabled = true; });
      requestCam(camEdit());
    });
    $("#cam-add").addEventListener("click", camAddRow);
    for (const id of ["#cam-roller", "#cam-base"]) $(id).addEventListener("change", () => { camTouched(); requestCam(camEdit()); });
  }

  // The cam plates on the animation (describe's cams, as the videos draw them: sim/output/drawing.py
  // Painter._plate): each outline turned with its link about its pivot, the roller on the follower, or the
  // flat face square to its guide.
  function drawCam(cm, at, v, color) {
    const o = at(cm.pivot); const a = at(cm.ref[0]); const b = at(cm.ref[1]);
    if (!o || !a || !b) return;
    const ang = Math.atan2(-(b[1] - a[1]), b[0] - a[0]);       // the link's angle (canvas y points down)
    const cs = Math.cos(ang); const sn = Math.sin(ang);
    ctx.save();
    ctx.beginPath();
    cm.outline.forEach(([x, y], k) => {
      const px = o[0] + v.s * (cs * x - sn * y); const py = o[1] - v.s * (sn * x + cs * y);
      if (k) ctx.lineTo(px, py); else ctx.moveTo(px, py);
    });
    ctx.closePath();
    ctx.fillStyle = `${color}30`; ctx.strokeStyle = color; ctx.lineWidth = 1.5;
    ctx.fill(); ctx.stroke();
    const f = at(cm.point);
    if (f && cm.roller > 0) {
      ctx.fillStyle = "rgba(255,255,255,0.82)"; ctx.strokeStyle = "#1a1a1a";
      ctx.beginPath(); ctx.arc(f[0], f[1], cm.roller * v.s, 0, 2 * Math.PI); ctx.fill(); ctx.stroke();
    }
    if (f && cm.face) {
      const [ux, uy] = cm.face.u; const nx = -uy; const ny = ux;
      const [lo, hi] = cm.face.ends;
      ctx.strokeStyle = "#1a1a1a"; ctx.lineWidth = 3; ctx.lineCap = "butt";
      ctx.beginPath();
      ctx.moveTo(f[0] + v.s * nx * lo, f[1] - v.s * ny * lo); ctx.lineTo(f[0] + v.s * nx * hi, f[1] - v.s * ny * hi);
      ctx.stroke();
    }
    ctx.restore();
  }

  // for tests and the drag benchmark: a world point [m] as client pixels of the page, and back
  window.linkageCanvas = {
    toClient(x, y) { const r = canvas.getBoundingClientRect(); const v = view(); return [r.left + v.X(x), r.top + v.Y(y)]; },
    toWorld(cx, cy) { const r = canvas.getBoundingClientRect(); return view().inv(cx - r.left, cy - r.top); },
  };

  function start() {
    wire();
    wireLoads();
    wireCam();
    sizeCanvas();
    syncClock();
    requestAnimationFrame(tick);
    loadMechanisms().catch((err) => status(`cannot reach the server: ${err.message}`, true));
  }

  start();
})();

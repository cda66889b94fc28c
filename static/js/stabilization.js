// Panel 3: stabilization diagram over the CMIF; clicking a pole selects its order and mode everywhere. Above the
// poles, one mark per candidate era judged (era.choose_modes: the clusters, or the exact realization's modes of
// noise-free data): the chosen modes (green, numbered, with a line down the diagram) and every other candidate
// (grey), whose hover says why it was left out. The page applies no rule of its own.
import { api } from "./api.js";
import { state, emit, on, plotConfig, plain as esc } from "./state.js";

const PLOT = "stab-plot";

function categories(s) {
  const all = [], freq = [], none = [];
  s.order.forEach((_, i) => {
    if (s.frequency_hz[i] === null) return;
    if (s.stable[i]) all.push(i);
    else if (s.stable_frequency[i]) freq.push(i);
    else none.push(i);
  });
  return { all, freq, none };
}

const mark = (ok) => (ok ? "✓" : "✗");
const { pm } = window.EraFormat;  // value ± 1.96 σ (95 % interval from the data) when the server gave σ
const sd = (values, i, scale = 1) => (values && values[i] !== null && values[i] !== undefined ? scale * values[i] : null);

// Plotly reads a few HTML tags in hover text: the server's sentences are shown as written.

// The verdict on a candidate in words: "chosen automatically: mode 2" or why it was left out.
function verdict(c) {
  return c.chosen ? `chosen automatically: mode ${c.mode + 1}` : `not chosen: ${esc(c.reason)}`;
}

// What era weighed, in one line (its own names: persistence, coverage, emac_mpc, strength, ...).
function weighed(c) {
  if (!c.evidence) return "";
  const fmt = (v) => (v === null ? "–" : Math.abs(v) >= 100 || Number.isInteger(v) ? String(Math.round(v)) : v.toPrecision(3));
  return "<br>weighed: " + Object.entries(c.evidence).map(([k, v]) => `${esc(k)} ${fmt(v)}`).join(", ");
}

// Each pole's candidate (index into s.candidates), or -1 for a pole of none.
function candidateOfPole(s) {
  const of = new Array(s.order.length).fill(-1);
  s.candidates.forEach((c, k) => c.pole_indices.forEach((i) => { of[i] = k; }));
  return of;
}

function poleTrace(s, idx, name, marker, judged) {
  return {
    x: idx.map((i) => s.frequency_hz[i]), y: idx.map((i) => s.order[i]), customdata: idx.map((i) => [s.order[i], s.mode_index[i]]),
    text: idx.map((i) => `order ${s.order[i]}, mode ${s.mode_index[i] + 1}<br>f = ${pm(s.frequency_hz[i], sd(s.frequency_std_hz, i), 4)} Hz, ` +
      `ζ = ${pm(100 * s.damping_ratio[i], sd(s.damping_std, i, 100), 2)} %<br>γ = ${s.emac[i].toFixed(3)}, μ = ${s.mpc[i].toFixed(3)}<br>` +
      `against the previous order: f ${mark(s.stable_frequency[i])}, ζ ${mark(s.stable_damping[i])}, ` +
      `shape ${mark(s.stable_shape[i])}` + (judged[i] >= 0 ? `<br>${verdict(s.candidates[judged[i]])}` : "")),
    hovertemplate: "%{text}<extra></extra>", type: "scatter", mode: "markers", name, marker,
  };
}

// One mark per candidate on a row above the poles (its own axis, y3: it stays there when the diagram is zoomed).
// A click on a chosen mark selects that mode at the chosen order; on another mark, its pole at its highest order.
function verdictTrace(s, list, name, marker) {
  const at = (c) => {
    if (c.chosen) return [s.chosen_order, s.chosen_indices[c.mode]];
    const last = c.pole_indices.at(-1);
    return last === undefined ? null : [s.order[last], s.mode_index[last]];
  };
  const where = (c) => (c.orders.length === 1 ? `at order ${c.orders[0]}`
    : `at ${c.orders.length} of the ${s.orders.length} orders (${c.orders[0]}–${c.orders.at(-1)})`);
  return {
    x: list.map((c) => c.frequency_hz), y: list.map(() => 0.96), yaxis: "y3",
    customdata: list.map(at), type: "scatter", mode: "markers+text", name, marker,
    text: list.map((c) => (c.chosen ? String(c.mode + 1) : "")), textposition: "top center",
    textfont: { color: "#137a3a", size: 11 }, cliponaxis: false,
    hovertext: list.map((c) => `${Number(c.frequency_hz).toFixed(4)} Hz, ζ = ${(100 * c.damping_ratio).toFixed(2)} %, ` +
      `found ${where(c)}<br>${verdict(c)}${weighed(c)}`),
    hovertemplate: "%{hovertext}<extra></extra>",
  };
}

function draw() {
  const s = state.stabilization;
  const { all, freq, none } = categories(s);
  const judged = candidateOfPole(s);
  const gm = all.map((i) => s.emac[i] * s.mpc[i]);
  const traces = [];
  s.spectrum.values.forEach((v, k) => traces.push({
    x: s.spectrum.frequency_hz, y: v, yaxis: "y2", type: "scatter", mode: "lines", hoverinfo: "skip",
    name: "CMIF", legendgroup: "cmif", showlegend: k === 0, line: { color: k === 0 ? "rgba(90,100,120,0.55)" : "rgba(150,160,180,0.45)", width: 1 },
  }));
  traces.push(poleTrace(s, none, "not stable", { symbol: "x-thin-open", size: 5, color: "#b0b6c2", line: { width: 1 } }, judged));
  traces.push(poleTrace(s, freq, "stable frequency", { symbol: "diamond-open", size: 7, color: "#6a7a99" }, judged));
  traces.push(poleTrace(s, all, "stable f, ζ, shape", {
    symbol: "circle", size: 8, color: gm, cmin: 0.5, cmax: 1, colorscale: "Viridis",
    colorbar: { title: { text: "γ·μ" }, x: 1.07, len: 0.8 }, line: { width: 0.5, color: "#222" } }, judged));
  const chosen = s.candidates.filter((c) => c.chosen), others = s.candidates.filter((c) => !c.chosen);
  traces.push(verdictTrace(s, others, "other candidates (hover: why not)",
                           { symbol: "triangle-down-open", size: 8, color: "#8a93a6", line: { width: 1 } }));
  traces.push(verdictTrace(s, chosen, "chosen modes",
                           { symbol: "triangle-down", size: 12, color: "#1a9a4a", line: { width: 1, color: "#0b4d24" } }));
  const fmax = s.nyquist_hz;
  // the chosen modes (era.choose_modes): a green line down the diagram under each one's mark
  const lines = chosen.map((c) => ({
    type: "line", xref: "x", x0: c.frequency_hz, x1: c.frequency_hz, yref: "paper", y0: 0, y1: 0.93,
    layer: "below", line: { color: "rgba(26,154,74,0.55)", width: 1.5 } }));
  const div = document.getElementById(PLOT);
  Plotly.react(div, traces, {
    margin: { l: 55, r: 90, t: 10, b: 45 }, hovermode: "closest", shapes: lines,
    xaxis: { title: { text: "frequency (Hz)" }, range: [0, fmax] },
    yaxis: { title: { text: "model order n" }, rangemode: "tozero", domain: [0, 0.92] },
    yaxis2: { overlaying: "y", side: "right", type: "log", showgrid: false, showticklabels: false, title: { text: "CMIF (log scale)" } },
    yaxis3: { domain: [0.92, 1], range: [0, 1.3], fixedrange: true, visible: false },
    legend: { orientation: "h", y: -0.18 },
  }, plotConfig);
  div.removeAllListeners?.("plotly_click");
  div.on("plotly_click", (ev) => {
    const pt = ev.points.find((p) => p.customdata);
    if (pt) emit("pole", { order: pt.customdata[0], index: pt.customdata[1] });
  });
  div.removeAllListeners?.("plotly_afterplot");
  div.on("plotly_afterplot", highlight);  // zoom, pan, resize: the marks follow the axes
  highlight();
}

// The current order (a dotted line and a ring on each of its poles) and the selected mode (an orange ring) are
// drawn in an SVG laid over the plot area, not as plotly shapes: a slider step then rewrites a few dozen SVG
// elements instead of a plotly relayout over a figure of thousands of poles (5-10 ms less per step).
const SVG = "http://www.w3.org/2000/svg";
let extended = false;  // the y axis was extended to show an order above the diagram's orders

function svg(tag, attrs) {
  const node = document.createElementNS(SVG, tag);
  for (const [k, v] of Object.entries(attrs)) node.setAttribute(k, v);
  return node;
}

function highlight() {
  if (!state.stabilization || !state.modes) return;
  const div = document.getElementById(PLOT), fl = div._fullLayout;
  if (!div.data || !fl?.yaxis) return;
  const m = state.modes, n = state.order, sel = state.selected;
  // An order above the diagram's orders extends the axis, and back below them the axis fits the poles again
  // (the marks are redrawn on plotly_afterplot).
  const top = state.stabilization.orders.at(-1);
  if (n > top && (fl.yaxis.autorange || extended) && n > Math.max(...fl.yaxis.range)) {
    extended = true;
    Plotly.relayout(div, { "yaxis.range": [0, Math.ceil(1.05 * n) + 1] });
    return;
  }
  if (n <= top && extended) {
    extended = false;
    Plotly.relayout(div, { "yaxis.autorange": true });
    return;
  }
  let marks = document.getElementById("stab-marks");
  if (!marks) {
    div.style.position = "relative";
    marks = svg("svg", { id: "stab-marks", style: "position:absolute; pointer-events:none; overflow:hidden" });
    div.append(marks);
  }
  const { l, t, w, h } = fl._size;
  Object.assign(marks.style, { left: `${l}px`, top: `${t}px`, width: `${w}px`, height: `${h}px` });
  marks.dataset.order = String(n);
  // the order axis is the lower part of the plot area (the verdict marks have the top): its own offset
  const x = (f) => fl.xaxis.l2p(f), y = fl.yaxis._offset - t + fl.yaxis.l2p(n);
  const items = [svg("line", { x1: 0, x2: w, y1: y, y2: y, stroke: "rgba(179,38,30,0.5)", "stroke-dasharray": "2 3" })];
  m.frequency_hz.forEach((f) => {
    if (f !== null) items.push(svg("circle", { cx: x(f), cy: y, r: 6, fill: "none", stroke: "#b3261e", "stroke-width": 1.5 }));
  });
  if (sel !== null && m.frequency_hz[sel] !== null) {
    items.push(svg("circle", { cx: x(m.frequency_hz[sel]), cy: y, r: 11, fill: "none", stroke: "#ff8c00", "stroke-width": 3 }));
  }
  marks.replaceChildren(...items);
}

export function init() {
  on("analysis", async (a) => {
    state.stabilization = null;
    Plotly.purge(PLOT);
    document.getElementById("stab-marks")?.remove();
    extended = false;
    try {
      const status = document.getElementById("stab-status");
      status.textContent = "Computing the stabilization diagram…";
      state.stabilization = await api(`/api/analyses/${a.id}/stabilization`,
                                      { progress: (text) => { status.textContent = text; } });
      const s = state.stabilization, n = s.chosen_indices.length;
      status.textContent = `${s.orders.length} orders (${s.orders[0]}–${s.orders.at(-1)}), ${s.order.length} poles, ` +
        `${s.modes.length} clusters stable over ≥ 3 orders (${s.modes.filter((mo) => mo.coherent).length} coherent, ` +
        `mean γ·μ ≥ ${s.coherent_min}). ` +
        (n ? `era chose ${n} mode${n > 1 ? "s" : ""} of the structure, read at order ${s.chosen_order}` +
             `${s.band_hz ? ` (band ${+s.band_hz[0].toPrecision(4)}–${+s.band_hz[1].toPrecision(4)} Hz)` : ""}: ` +
             "the green marks; hover over a grey one for why it was left out."
           : "era chose no mode" + (s.candidates.length ? " (hover over the grey marks for why)." : "."));
      if (state.analysis && state.analysis.id === a.id) draw();
    } catch (err) {
      document.getElementById("stab-status").textContent = "";
      document.getElementById(PLOT).textContent = err.message;
    }
  });
  on("modes", highlight);
  on("select", highlight);
}

// Panel 3: stabilization diagram over the CMIF; clicking a pole selects its order and mode everywhere.
import { api } from "./api.js";
import { state, emit, on, plotConfig } from "./state.js";

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

function poleTrace(s, idx, name, marker) {
  return {
    x: idx.map((i) => s.frequency_hz[i]), y: idx.map((i) => s.order[i]), customdata: idx.map((i) => [s.order[i], s.mode_index[i]]),
    text: idx.map((i) => `order ${s.order[i]}, mode ${s.mode_index[i] + 1}<br>f = ${pm(s.frequency_hz[i], sd(s.frequency_std_hz, i), 4)} Hz, ` +
      `ζ = ${pm(100 * s.damping_ratio[i], sd(s.damping_std, i, 100), 2)} %<br>γ = ${s.emac[i].toFixed(3)}, μ = ${s.mpc[i].toFixed(3)}<br>` +
      `against the previous order: f ${mark(s.stable_frequency[i])}, ζ ${mark(s.stable_damping[i])}, ` +
      `shape ${mark(s.stable_shape[i])}`),
    hovertemplate: "%{text}<extra></extra>", type: "scatter", mode: "markers", name, marker,
  };
}

function draw() {
  const s = state.stabilization;
  const { all, freq, none } = categories(s);
  const gm = all.map((i) => s.emac[i] * s.mpc[i]);
  const traces = [];
  s.spectrum.values.forEach((v, k) => traces.push({
    x: s.spectrum.frequency_hz, y: v, yaxis: "y2", type: "scatter", mode: "lines", hoverinfo: "skip",
    name: "CMIF", legendgroup: "cmif", showlegend: k === 0, line: { color: k === 0 ? "rgba(90,100,120,0.55)" : "rgba(150,160,180,0.45)", width: 1 },
  }));
  traces.push(poleTrace(s, none, "not stable", { symbol: "x-thin-open", size: 5, color: "#b0b6c2", line: { width: 1 } }));
  traces.push(poleTrace(s, freq, "stable frequency", { symbol: "diamond-open", size: 7, color: "#6a7a99" }));
  traces.push(poleTrace(s, all, "stable f, ζ, shape", {
    symbol: "circle", size: 8, color: gm, cmin: 0.5, cmax: 1, colorscale: "Viridis",
    colorbar: { title: { text: "γ·μ" }, x: 1.07, len: 0.8 }, line: { width: 0.5, color: "#222" } }));
  const fmax = s.nyquist_hz;
  // suggested modes (stable over ≥ 3 orders) that the server marks coherent (mean γ·μ ≥ s.coherent_min): faint
  // vertical lines. The page shows the server's rule; it applies no threshold of its own.
  const suggested = s.modes.filter((mo) => mo.coherent).map((mode) => ({
    type: "line", xref: "x", x0: mode.frequency_hz, x1: mode.frequency_hz, yref: "paper", y0: 0, y1: 1,
    layer: "below", line: { color: "rgba(31,95,191,0.25)", width: 1 } }));
  const div = document.getElementById(PLOT);
  Plotly.react(div, traces, {
    margin: { l: 55, r: 90, t: 10, b: 45 }, hovermode: "closest", shapes: suggested,
    xaxis: { title: { text: "frequency (Hz)" }, range: [0, fmax] },
    yaxis: { title: { text: "model order n" }, rangemode: "tozero" },
    yaxis2: { overlaying: "y", side: "right", type: "log", showgrid: false, showticklabels: false, title: { text: "CMIF (log scale)" } },
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
  const x = (f) => fl.xaxis.l2p(f), y = fl.yaxis.l2p(n);
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
      status.textContent = `${state.stabilization.orders.length} orders (${state.stabilization.orders[0]}–` +
        `${state.stabilization.orders.at(-1)}), ${state.stabilization.order.length} poles, ` +
        `${state.stabilization.modes.length} modes stable over ≥ 3 orders, ` +
        `${state.stabilization.modes.filter((mo) => mo.coherent).length} of them coherent ` +
        `(mean γ·μ ≥ ${state.stabilization.coherent_min}: the faint vertical lines).`;
      if (state.analysis && state.analysis.id === a.id) draw();
    } catch (err) {
      document.getElementById("stab-status").textContent = "";
      document.getElementById(PLOT).textContent = err.message;
    }
  });
  on("modes", highlight);
  on("select", highlight);
}

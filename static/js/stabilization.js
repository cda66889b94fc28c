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

function poleTrace(s, idx, name, marker) {
  return {
    x: idx.map((i) => s.frequency_hz[i]), y: idx.map((i) => s.order[i]), customdata: idx.map((i) => [s.order[i], s.mode_index[i]]),
    text: idx.map((i) => `order ${s.order[i]}, mode ${s.mode_index[i] + 1}<br>f = ${s.frequency_hz[i].toFixed(4)} Hz, ` +
      `ζ = ${(100 * s.damping_ratio[i]).toFixed(2)} %<br>γ = ${s.emac[i].toFixed(3)}, μ = ${s.mpc[i].toFixed(3)}`),
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
  Plotly.react(PLOT, traces, {
    margin: { l: 55, r: 90, t: 10, b: 45 }, hovermode: "closest",
    xaxis: { title: { text: "frequency (Hz)" }, range: [0, fmax] },
    yaxis: { title: { text: "model order n" }, rangemode: "tozero" },
    yaxis2: { overlaying: "y", side: "right", type: "log", showgrid: false, showticklabels: false, title: { text: "CMIF (log scale)" } },
    legend: { orientation: "h", y: -0.18 },
  }, plotConfig);
  const div = document.getElementById(PLOT);
  div.removeAllListeners?.("plotly_click");
  div.on("plotly_click", (ev) => {
    const pt = ev.points.find((p) => p.customdata);
    if (pt) emit("pole", { order: pt.customdata[0], index: pt.customdata[1] });
  });
  highlight();
}

// The current order and the selected mode are layout shapes, not traces: moving them redraws only the shapes
// (plotly's fast path), not the thousands of pole markers; this keeps the slider well under 100 ms.
function ring(f, n, size, color, width) {
  return { type: "circle", xref: "x", yref: "y", xsizemode: "pixel", ysizemode: "pixel", xanchor: f, yanchor: n,
           x0: -size, x1: size, y0: -size, y1: size, line: { color, width } };
}

function highlight() {
  if (!state.stabilization || !state.modes) return;
  const div = document.getElementById(PLOT);
  if (!div.data) return;
  const m = state.modes, n = state.order, sel = state.selected;
  const shapes = [{ type: "line", xref: "paper", x0: 0, x1: 1, yref: "y", y0: n, y1: n,
                    line: { color: "rgba(179,38,30,0.5)", width: 1, dash: "dot" } }];
  // suggested modes (stable over ≥ 3 orders) that are also coherent (mean γ·μ ≥ 0.9): faint vertical lines
  for (const mode of state.stabilization.modes.filter((mo) => mo.emac * mo.mpc >= 0.9)) {
    shapes.push({ type: "line", xref: "x", x0: mode.frequency_hz, x1: mode.frequency_hz, yref: "paper", y0: 0, y1: 1,
                  layer: "below", line: { color: "rgba(31,95,191,0.25)", width: 1 } });
  }
  m.frequency_hz.forEach((f, k) => { if (f !== null) shapes.push(ring(f, n, 6, "#b3261e", 1.5)); });
  if (sel !== null && m.frequency_hz[sel] !== null) shapes.push(ring(m.frequency_hz[sel], n, 11, "#ff8c00", 3));
  Plotly.relayout(PLOT, { shapes });
}

export function init() {
  on("analysis", async (a) => {
    state.stabilization = null;
    Plotly.purge(PLOT);
    try {
      const status = document.getElementById("stab-status");
      status.textContent = "Computing the stabilization diagram…";
      state.stabilization = await api(`/api/analyses/${a.id}/stabilization`,
                                      { progress: (text) => { status.textContent = text; } });
      status.textContent = `${state.stabilization.orders.length} orders (${state.stabilization.orders[0]}–` +
        `${state.stabilization.orders.at(-1)}), ${state.stabilization.order.length} poles, ` +
        `${state.stabilization.modes.length} modes stable over ≥ 3 orders.`;
      if (state.analysis && state.analysis.id === a.id) draw();
    } catch (err) {
      document.getElementById("stab-status").textContent = "";
      document.getElementById(PLOT).textContent = err.message;
    }
  });
  on("modes", highlight);
  on("select", highlight);
}

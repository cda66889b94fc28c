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
  traces.push({ x: [], y: [], type: "scatter", mode: "markers", name: "current order", hoverinfo: "skip",
                marker: { symbol: "circle-open", size: 13, color: "#b3261e", line: { width: 2 } } });
  traces.push({ x: [], y: [], type: "scatter", mode: "markers", name: "selected", hoverinfo: "skip",
                marker: { symbol: "star", size: 16, color: "#ffb000", line: { width: 1, color: "#000" } } });
  const fmax = s.nyquist_hz;
  Plotly.react(PLOT, traces, {
    margin: { l: 55, r: 90, t: 10, b: 45 }, hovermode: "closest",
    xaxis: { title: { text: "frequency (Hz)" }, range: [0, fmax] },
    yaxis: { title: { text: "model order n" }, rangemode: "tozero" },
    yaxis2: { overlaying: "y", side: "right", type: "log", showgrid: false, title: { text: "CMIF" }, exponentformat: "e" },
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

// Ring the poles of the current order (from /modes, so orders between the diagram's are shown too) and star the selected mode.
function highlight() {
  if (!state.stabilization || !state.modes) return;
  const div = document.getElementById(PLOT);
  if (!div.data) return;
  const n = div.data.length;
  const m = state.modes;
  const freqs = m.frequency_hz.filter((f) => f !== null);
  const sel = state.selected;
  Plotly.restyle(PLOT, {
    x: [freqs, sel === null ? [] : [m.frequency_hz[sel]]],
    y: [freqs.map(() => state.order), sel === null ? [] : [state.order]],
  }, [n - 2, n - 1]);
}

export function init() {
  on("analysis", async (a) => {
    state.stabilization = null;
    Plotly.purge(PLOT);
    try {
      state.stabilization = await api(`/api/analyses/${a.id}/stabilization`);
      if (state.analysis && state.analysis.id === a.id) draw();
    } catch (err) {
      document.getElementById(PLOT).textContent = err.message;
    }
  });
  on("modes", highlight);
  on("select", highlight);
}

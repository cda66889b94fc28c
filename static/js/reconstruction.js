// Panel 5: measured against reconstructed response of one channel and reference, for the kept modes.
import { api } from "./api.js";
import { state, on, el, plotConfig } from "./state.js";

const $ = (id) => document.getElementById(id);
let sequence = 0;

export async function update() {
  if (!state.analysis || !state.modes) return;
  const mine = ++sequence;
  const kept = [...state.kept].sort((a, b) => a - b).join(",");
  const q = new URLSearchParams({ order: state.order, modes: kept, output: $("recon-output").value || 0,
                                  input: $("recon-input").value || 0 });
  const r = await api(`/api/analyses/${state.analysis.id}/reconstruction?${q}`);
  if (mine !== sequence) return;  // a newer request is on its way
  const fit = r.fit_percent;
  $("recon-fit").textContent = `fit ${fit === null ? "–" : fit.toFixed(2)} % with ${state.kept.size} kept modes`;
  Plotly.react("recon-plot", [
    { x: r.time_s, y: r.measured, name: "measured", type: "scatter", mode: "lines", line: { color: "#1d2330", width: 1.5 } },
    { x: r.time_s, y: r.reconstructed, name: "reconstructed", type: "scatter", mode: "lines",
      line: { color: "#e4572e", width: 1.5, dash: "dash" } },
  ], { margin: { l: 55, r: 10, t: 10, b: 40 }, xaxis: { title: { text: "time (s)" } },
       yaxis: { title: { text: `${r.output} / ${r.input}` } }, legend: { orientation: "h", y: 1.12 } }, plotConfig);
}

export function init() {
  on("dataset", (ds) => {
    $("recon-output").replaceChildren(...ds.outputs.map((n, i) => el("option", { value: i, text: n })));
    $("recon-input").replaceChildren(...ds.inputs.map((n, j) => el("option", { value: j, text: n })));
  });
  $("recon-output").addEventListener("change", update);
  $("recon-input").addEventListener("change", update);
  on("kept", update);
}

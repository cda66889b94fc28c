// Panel 5: measured against reconstructed response of one channel and reference, for the kept modes.
// The server decides which modes are kept by the thresholds (the same rule for the table), so one request per
// slider step gives both the kept set and the curves.
import { api } from "./api.js";
import { state, on, el, plotConfig, plain } from "./state.js";
import { thresholds } from "./table.js";

const $ = (id) => document.getElementById(id);
let sequence = 0;

// kept: "thresholds" (the table's thresholds pick the modes) or a Set of mode indices.
export async function fetchFor(order, kept) {
  const q = new URLSearchParams({ order, output: $("recon-output").value || 0, input: $("recon-input").value || 0 });
  if (kept === "thresholds") {
    const t = thresholds();
    q.set("min_emac", t.emac); q.set("min_mpc", t.mpc); q.set("min_contribution", t.contribution);
    q.set("physical_only", t.physicalOnly);
  } else {
    q.set("modes", [...kept].sort((a, b) => a - b).join(","));
  }
  return api(`/api/analyses/${state.analysis.id}/reconstruction?${q}`);
}

export function draw(r) {
  const fit = r.fit_percent;
  $("recon-fit").textContent = `fit ${fit === null ? "–" : fit.toFixed(2)} % with ${r.kept.length} kept modes`;
  Plotly.react("recon-plot", [
    { x: r.time_s, y: r.measured, name: "measured", type: "scatter", mode: "lines", line: { color: "#1d2330", width: 1.5 } },
    { x: r.time_s, y: r.reconstructed, name: "reconstructed", type: "scatter", mode: "lines",
      line: { color: "#e4572e", width: 1.5, dash: "dash" } },
  ], { margin: { l: 55, r: 10, t: 10, b: 40 }, xaxis: { title: { text: "time (s)" } },
       yaxis: { title: { text: plain(`${r.output} / ${r.input}`) } }, legend: { orientation: "h", y: 1.12 } }, plotConfig);
}

// Redraw for the current order and kept set (after a keep/reject click or a channel change).
export async function update() {
  if (!state.analysis || !state.modes) return;
  const mine = ++sequence;
  const r = await fetchFor(state.order, state.kept);
  if (mine === sequence) draw(r);  // else a newer request is on its way
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

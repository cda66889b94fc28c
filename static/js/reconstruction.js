// Panel 5: measured against reconstructed response of one channel and reference, for the kept modes.
// The server decides which modes are kept by the thresholds (the same rule for the table), so one request per
// slider step gives both the kept set and the curves.
import { api } from "./api.js";
import { state, on, el, plotConfig, plain } from "./state.js";
import { thresholds } from "./table.js";

const $ = (id) => document.getElementById(id);
let sequence = 0;

// kept: "thresholds" (the table's thresholds pick the modes) or a Set of mode indices.
function query(order, kept) {
  const q = new URLSearchParams({ order, output: $("recon-output").value || 0, input: $("recon-input").value || 0 });
  if (kept === "thresholds") {
    const t = thresholds();
    q.set("min_emac", t.emac); q.set("min_mpc", t.mpc); q.set("min_contribution", t.contribution);
    q.set("physical_only", t.physicalOnly);
  } else {
    q.set("modes", [...kept].sort((a, b) => a - b).join(","));
  }
  return q;
}

export async function fetchFor(order, kept) {
  return api(`/api/analyses/${state.analysis.id}/reconstruction?${query(order, kept)}`);
}

// One slider step: {modes, reconstruction} of an order; kept: "thresholds" or a Set of mode indices.
export async function fetchStep(order, kept = "thresholds") {
  return api(`/api/analyses/${state.analysis.id}/step?${query(order, kept)}`);
}

let shown = null;  // the channel pair and the time axis that the plot shows: `${output}|${input}|${samples}`
let moving = null;  // a curve move (Plotly.animate) that plotly draws in the next animation frame, until then
// A move still queued would overwrite a newer curve drawn at once (restyle, react): drop it first.
function dropMove(div) {
  if (moving) Plotly.animate(div, [], { mode: "immediate" });
  moving = null;
}
let insideBefore = false;  // the drawn reconstruction lies within the measured range (the axes are the measured's)
const sameArray = (a, b) => a.length === b.length && a.every((v, i) => v === b[i]);

function within(y, ref) {
  let lo = Infinity, hi = -Infinity;
  for (const v of ref) if (v !== null) { if (v < lo) lo = v; if (v > hi) hi = v; }
  return y.every((v) => v === null || (v >= lo && v <= hi));
}

// Draws a reconstruction; the promise resolves when plotly has drawn it.
export function draw(r) {
  const fit = r.fit_percent;
  $("recon-fit").textContent = `fit ${fit === null ? "–" : fit.toFixed(2)} % with ${r.kept.length} kept modes`;
  const div = $("recon-plot");
  const same = `${r.output}|${r.input}|${r.time_s.length}`;
  if (shown === same && div.data?.length === 2 && sameArray(div.data[0].y, r.measured) && sameArray(div.data[0].x, r.time_s)) {
    // Only the reconstructed curve changed. Within the measured curve's range (the axes stay as they are), move
    // it with plotly's transition path: no recalculation of the axes, legend and hover (~2x cheaper than
    // restyle). Otherwise restyle it, and the y axis rescales to show it all.
    // A newer move replaces one plotly has not drawn yet ("immediate"); that one's promise then resolves too.
    const inside = within(r.reconstructed, r.measured);
    if (inside && insideBefore) {
      const move = moving = Plotly.animate(div, { data: [{ y: r.reconstructed }], traces: [1] },
                                           { mode: "immediate", transition: { duration: 0 }, frame: { duration: 0, redraw: false } })
        .catch(() => {}).finally(() => { if (moving === move) moving = null; });
      return move;
    }
    dropMove(div);
    insideBefore = inside;
    return Plotly.restyle(div, { y: [r.reconstructed] }, [1]);
  }
  dropMove(div);
  insideBefore = within(r.reconstructed, r.measured);
  shown = same;
  return Plotly.react(div, [
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
  if (mine === sequence) await draw(r);  // else a newer request is on its way
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

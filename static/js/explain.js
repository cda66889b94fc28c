// Panel "Simulation vs test" (issues 5, 9): runs era.explain on the current analysis (its H(0); the modes era chose,
// or the modes kept in the table at the current order) against the dataset's structure model
// (model.js) or, for the grid example without one, the NASA grid model, then draws
// the result with explain_view.js, which says what was used (basis). The server stores it with the analysis, so a reload shows it
// again and a report created afterwards includes it. The 3-D viewers show the measured shapes expanded to all
// joints (SEREP) and the updated model's, side by side.
import { api } from "./api.js";
import { state, on, el, showError } from "./state.js";

const $ = (id) => document.getElementById(id);
let shown = null;    // analysis id whose result is drawn
let viewers = null;  // [{mode_url}, {mode_url}] when the viser viewer is available
let model = null;    // the dataset's structure model (model.js), or null
let made = null;     // the model the drawn result was made with (summary.model_used), or null

function request() {
  const body = { nominal: $("explain-gravity").checked ? {} : { gravity: false }, modes: $("explain-which").value };
  if (body.modes === "kept") Object.assign(body, { order: state.order, kept: [...state.kept].sort((a, b) => a - b) });
  return body;
}

function overlay(output, input) {
  const q = new URLSearchParams({ output, input, overlay_only: true });
  return api(`/api/analyses/${state.analysis.id}/explain?${q}`).then((r) => r.overlay);
}

async function showViewers(box, k) {
  viewers = null;
  try {
    const made = await Promise.all(["measured", "model"].map((which) =>
      api(`/api/analyses/${state.analysis.id}/explain/viewer`, { method: "POST", body: { which } })));
    const frames = made.map((v, n) => el("iframe", { class: "viewer", src: v.url, style: "flex:1 1 420px;min-width:320px;height:420px",
      title: n === 0 ? "measured shape, SEREP-expanded" : "updated model shape" }));
    const row = el("div", { style: "display:flex;flex-wrap:wrap;gap:12px" }, ...frames);
    box.replaceChildren(el("div", { class: "note", text: "Left: measured (expanded); right: updated model. Drag to turn." }), row);
    viewers = made;
    setTimeout(() => moveViewers(k), 800);  // the viewer pages connect first
  } catch (err) {
    box.replaceChildren(el("div", { class: "note", text: `3-D viewer: ${err.message}` }));
  }
}

async function moveViewers(k) {
  if (!viewers) return;
  for (const v of viewers) {
    try { await api(v.mode_url, { method: "POST", body: { index: k, amplitude: 0.15, speed: 0.5 } }); } catch { /* best effort */ }
  }
}

// The drawn result against the dataset's model now: a result made with another model (saved since, or a file
// uploaded) is marked stale with the model it used, and offers to run again. ``why``: the server's sentence.
function markStale(why) {
  const box = $("explain-stale");
  if (!box) return;
  if (why === undefined) {
    const fp = made ? made.fingerprint : undefined;
    const current = model ? model.fingerprint : null;
    why = made === null || fp === current ? null
      : `This result was made with an earlier model: ${made.text}. The dataset's model has changed since (now ${model ? model.text : "none"}): run simulation vs test again to compare with it.`;
  }
  box.hidden = !why;
  if (!why) return;
  const again = el("button", { id: "explain-rerun", text: "Run again with the current model" });
  again.addEventListener("click", run);
  box.replaceChildren(why, again);
}

function draw(summary) {
  $("explain-result").hidden = false;
  const { viewers: box } = window.EraExplainView.render($("explain-result"), summary, { id: "explain", overlay, onShape: moveViewers });
  made = summary.model_used || null;
  markStale(summary.stale || null);
  shown = state.analysis.id;
  $("explain-status").textContent = `Done in ${summary.seconds.toFixed(1)} s (ERA ${summary.timing_s.era_s.toFixed(1)} s, ranking ${summary.timing_s.ranking_s.toFixed(1)} s). Stored with this analysis: a report created now includes it.`;
  if (!summary.fe_model || summary.mesh) showViewers(box, 0);   // an FE model without coordinates is not drawn
}

// What the comparison would use: this dataset's model, else the NASA grid's for the grid's nine sensors, else none.
function comparedWith() {
  const ds = state.dataset;
  return model ? "model" : (ds && ds.n_outputs === 9 && ds.geometry ? "grid" : null);
}

async function run() {
  if (!state.analysis) return;
  showError("explain-error", null);
  if (!comparedWith()) {  // nothing to compare with: say what to do here, without asking the server
    showError("explain-error", "There is no model of this structure yet: describe it in the Model panel above "
      + "(Describe it from the test geometry) or upload a model file, then run again.");
    return;
  }
  $("explain-run").disabled = true;
  $("explain-status").textContent = "Starting…";
  try {
    const r = await api(`/api/analyses/${state.analysis.id}/explain`, {
      method: "POST", body: request(), progress: (text) => { $("explain-status").textContent = text; } });
    state.analysis.has_explanation = true;  // stored with the analysis now
    draw(r);
  } catch (err) {
    $("explain-status").textContent = "";
    showError("explain-error", err);
  } finally {
    $("explain-run").disabled = false;
  }
}

// A stored result of this analysis (after a reload), if the panel ran on it before.
async function restore(a) {
  if (!a.has_explanation) return;  // not run on it yet: asking would be a 404
  try {
    const r = await api(`/api/analyses/${a.id}/explain`);
    if (state.analysis && state.analysis.id === a.id) draw(r);
  } catch { /* not run yet */ }
}

export function init() {
  $("explain-run").addEventListener("click", run);
  const hint = () => {
    const what = comparedWith();
    $("field-explain-gravity").hidden = what !== "grid";  // the grid's nominal model only: not on other data
    $("explain-hint").textContent = what === "model" ? `Compares with this dataset's model: ${model.text}.`
      : what === "grid" ? "Compares with the NASA grid's model (this dataset has no model of its own)."
      : "Describe the structure in the Model panel above (or upload a model file) first.";
  };
  on("dataset", () => { model = null; made = null; hint(); });
  on("model", (m) => { model = m; hint(); showError("explain-error", null); if (shown && made) markStale(); });
  on("analysis", (a) => {
    $("explain-run").disabled = false;
    if (shown !== a.id) { $("explain-result").hidden = true; $("explain-result").replaceChildren(); $("explain-status").textContent = ""; showError("explain-error", null); }
    restore(a);
  });
}

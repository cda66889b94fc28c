// Wires the panels. The order slider drives: modes of that order (table, poles) -> reconstruction.
// Requests are coalesced: while one order is on its way, only the latest slider position waits.
// The analysis opens at the order era's choice of modes is read at, with the chosen modes ticked (table.js).
import { api } from "./api.js";
import { state, on, emit, showError } from "./state.js";
import * as data from "./data.js";
import * as hankel from "./hankel.js";
import * as stabilization from "./stabilization.js";
import * as table from "./table.js";
import * as reconstruction from "./reconstruction.js";
import * as shapes from "./shapes.js";
import * as share from "./share.js";
import * as model from "./model.js";
import * as explain from "./explain.js";

// Timing of the last slider updates (ms from the order change to table and reconstruction drawn), for tests.
window.eraTiming = { order: [], parts: [] };

let busy = false, wanted = null, pendingSelect = null;

// One request per slider step (GET /step: the modes and the reconstruction of that order), one at a time: while
// one is on its way only the latest slider position waits. A fast drag never queues stale steps, and only the
// latest order is drawn. (Aborting the request of an older order measured worse: the server finishes a
// realization it has started anyway, and the aborted ones compete with the latest for the CPU.)
async function pump() {
  if (busy || wanted === null) return;
  const { order, t0 } = wanted;
  wanted = null;
  busy = true;
  let curve = null, t1, t2, t3;
  try {
    const keep = table.defaultKept(order);
    const { modes, reconstruction: rec } = await reconstruction.fetchStep(order, keep);
    if (order !== state.order) return;
    t1 = performance.now();
    state.modes = modes;
    state.kept = new Set(rec.kept);
    state.keptBy = keep === "thresholds" ? "thresholds" : "choice";
    if (pendingSelect !== null && pendingSelect.order === order) {
      state.selected = pendingSelect.index < modes.n_modes ? pendingSelect.index : null;
      pendingSelect = null;
    } else if (state.selected !== null) {
      state.selected = nearestMode(modes, state.selectedFrequency);
    }
    // plotly first (it measures the page), then the listeners' DOM writes (table): one layout, not several
    curve = reconstruction.draw(rec);
    t2 = performance.now();
    emit("modes", modes);
    if (state.selected !== null) emit("select", state.selected);
    t3 = performance.now();
  } catch (err) {
    showError("hankel-error", err);
  } finally {
    busy = false;
    pump();
  }
  if (curve === null) return;
  await curve;  // plotly may draw the curve in the next animation frame
  if (order !== state.order) return;
  const ms = performance.now() - t0;
  window.eraTiming.order.push(ms);
  window.eraTiming.parts.push({ order, fetch: t1 - t0, reconstruction: t2 - t1, draw: t3 - t2, frame: t0 + ms - t3 });
  document.getElementById("order-timing").textContent = `order ${order}: updated in ${ms.toFixed(0)} ms`;
}

function nearestMode(m, f) {
  if (f === undefined || f === null || !m.n_modes) return null;
  let best = null;
  m.frequency_hz.forEach((fk, k) => { if (fk !== null && (best === null || Math.abs(fk - f) < Math.abs(m.frequency_hz[best] - f))) best = k; });
  return best;
}

// First listener of "select": the state is updated before any panel redraws.
on("select", (k) => { state.selected = k; state.selectedFrequency = k === null ? null : state.modes.frequency_hz[k]; });

data.init();
hankel.init();
stabilization.init();
table.init();
reconstruction.init();
shapes.init();
share.init();
model.init();
explain.init();
api("/api/health").then((h) => { document.getElementById("version").textContent = h.version; }).catch(() => {});

on("order", (order) => { wanted = { order, t0: performance.now() }; pump(); });
on("pole", ({ order, index }) => {
  if (order === state.order) { emit("select", index); return; }
  pendingSelect = { order, index };
  hankel.setOrder(order);
});
on("thresholds", async () => {
  const rec = await reconstruction.fetchFor(state.order, "thresholds");
  state.kept = new Set(rec.kept);
  state.keptBy = "thresholds";
  emit("modes", state.modes);
  reconstruction.draw(rec);
});
// Back to the automatic choice: its order (a slider step there ticks the chosen modes), or at that order its modes.
on("choice", async () => {
  const a = state.analysis;
  if (!a) return;
  if (state.order !== a.suggested_order) { hankel.setOrder(a.suggested_order); return; }
  const rec = await reconstruction.fetchFor(state.order, table.chosenAt(state.order));
  state.kept = new Set(rec.kept);
  state.keptBy = "choice";
  emit("modes", state.modes);
  reconstruction.draw(rec);
});
on("analysis", (a) => {
  state.selected = null;
  state.modes = null;
  history.replaceState(null, "", `#analysis=${encodeURIComponent(a.id)}`);
});
// The address follows the order once the slider rests: each replaceState costs a style pass (~10 ms).
let addressTimer = null;
on("modes", () => {
  clearTimeout(addressTimer);
  addressTimer = setTimeout(() => history.replaceState(null, "",
    `#analysis=${encodeURIComponent(state.analysis.id)}&order=${state.order}`), 150);
});

// A reload (or a bookmarked address) reopens the analysis in the address: #analysis=ID&order=n.
async function restore() {
  const params = new URLSearchParams(location.hash.slice(1));
  const id = params.get("analysis");
  if (!id) return;
  try {
    state.restoring = true;
    const a = await api(`/api/analyses/${encodeURIComponent(id)}`, {
      progress: (text) => { document.getElementById("hankel-status").textContent = text; } });
    const ds = await api(`/api/datasets/${encodeURIComponent(a.dataset_id)}`);
    state.dataset = ds;
    emit("dataset", ds);
    state.analysis = a;
    emit("analysis", a);
    document.getElementById("hankel-status").textContent =
      `Reopened: H(0) is ${a.hankel_shape[0]} × ${a.hankel_shape[1]} (${a.svd_method} SVD); orders up to ${a.max_order} available.`;
    const order = Number(params.get("order"));
    if (order >= 1 && order <= a.max_order) hankel.setOrder(order);
  } catch (err) {
    showError("data-error", new Error(`Could not reopen the analysis in the address: ${err.message}`));
  } finally {
    state.restoring = false;
  }
}
restore();

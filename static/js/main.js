// Wires the panels. The order slider drives: modes of that order (table, poles) -> reconstruction.
// Requests are coalesced: while one order is on its way, only the latest slider position waits.
import { api } from "./api.js";
import { state, on, emit, showError } from "./state.js";
import * as data from "./data.js";
import * as hankel from "./hankel.js";
import * as stabilization from "./stabilization.js";
import * as table from "./table.js";
import * as reconstruction from "./reconstruction.js";
import * as shapes from "./shapes.js";
import * as share from "./share.js";
import * as explain from "./explain.js";

// Timing of the last slider updates (ms from the order change to table and reconstruction drawn), for tests.
window.eraTiming = { order: [], parts: [] };

let busy = false, wanted = null, pendingSelect = null;

async function pump() {
  if (busy || wanted === null) return;
  const { order, t0 } = wanted;
  wanted = null;
  busy = true;
  try {
    // Both at once: the modes of this order, and the reconstruction with the modes the thresholds keep.
    const [modes, rec] = await Promise.all([api(`/api/analyses/${state.analysis.id}/modes?order=${order}&fit=false`),
                                            reconstruction.fetchFor(order, "thresholds")]);
    const t1 = performance.now();
    if (order === state.order) {
      state.modes = modes;
      state.kept = new Set(rec.kept);
      if (pendingSelect !== null && pendingSelect.order === order) {
        state.selected = pendingSelect.index < modes.n_modes ? pendingSelect.index : null;
        pendingSelect = null;
      } else if (state.selected !== null) {
        state.selected = nearestMode(modes, state.selectedFrequency);
      }
      emit("modes", modes);
      const t2 = performance.now();
      reconstruction.draw(rec);
      if (state.selected !== null) emit("select", state.selected);
      const ms = performance.now() - t0;
      window.eraTiming.order.push(ms);
      window.eraTiming.parts.push({ order, fetch: t1 - t0, draw: t2 - t1, reconstruction: performance.now() - t2 });
      document.getElementById("order-timing").textContent = `order ${order}: updated in ${ms.toFixed(0)} ms`;
    }
  } catch (err) {
    showError("hankel-error", err);
  } finally {
    busy = false;
    pump();
  }
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
explain.init();

on("order", (order) => { wanted = { order, t0: performance.now() }; pump(); });
on("pole", ({ order, index }) => {
  if (order === state.order) { emit("select", index); return; }
  pendingSelect = { order, index };
  hankel.setOrder(order);
});
on("thresholds", async () => {
  const rec = await reconstruction.fetchFor(state.order, "thresholds");
  state.kept = new Set(rec.kept);
  emit("modes", state.modes);
  reconstruction.draw(rec);
});
on("analysis", (a) => {
  state.selected = null;
  state.modes = null;
  history.replaceState(null, "", `#analysis=${encodeURIComponent(a.id)}`);
});
on("modes", () => {
  history.replaceState(null, "", `#analysis=${encodeURIComponent(state.analysis.id)}&order=${state.order}`);
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

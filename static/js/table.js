// Panel 4: the γ/μ table: sortable, a keep/reject checkbox per mode. At the order era's automatic choice is read at
// (the analysis's suggested_order) the chosen modes are ticked; at other orders the thresholds tick; the person may
// tick and untick anything, and what is ticked is what the reconstruction, the report and explain use.
import { state, emit, on, el } from "./state.js";
import { api } from "./api.js";

const $ = (id) => document.getElementById(id);
const { columns } = window.EraFormat;
let sortKey = "frequency_hz", ascending = true;

export function thresholds() {
  return { emac: Number($("min-emac").value), mpc: Number($("min-mpc").value),
           contribution: Number($("min-contrib").value) / 100, physicalOnly: $("physical-only").checked };
}

// The modes era chose (era.choose_modes) at this order: a Set of their indices, or null at any other order (and when
// era chose none).
export function chosenAt(order) {
  const a = state.analysis;
  return a && order === a.suggested_order && a.chosen_indices.length ? new Set(a.chosen_indices) : null;
}

// What a slider step ticks at an order: the chosen modes at the choice's order, else the thresholds.
export function defaultKept(order) {
  return chosenAt(order) || "thresholds";
}

function sortedIndices(m) {
  const col = columns.find((c) => c.key === sortKey) || columns[1];
  const idx = [...Array(m.n_modes).keys()];
  idx.sort((a, b) => {
    const va = col.value(m, a), vb = col.value(m, b);
    const d = (va === null ? -Infinity : va) - (vb === null ? -Infinity : vb);
    return ascending ? d : -d;
  });
  return idx;
}

export function render() {
  const m = state.modes;
  const table = $("modes-table");
  const head = el("tr", {}, el("th", { class: "keep", text: "keep", title: "keep the mode in the reduced model" }));
  for (const c of columns) {
    const th = el("th", { text: c.label, title: c.title, "data-key": c.key });
    if (c.key === sortKey) th.className = ascending ? "sorted asc" : "sorted";
    th.addEventListener("click", () => { ascending = sortKey === c.key ? !ascending : true; sortKey = c.key; render(); });
    head.append(th);
  }
  table.tHead.replaceChildren(head);
  const chosen = chosenAt(m.order) || new Set();
  const rows = sortedIndices(m).map((k) => {
    const box = el("input", { type: "checkbox", "aria-label": `keep mode ${k + 1}`, "data-mode": k });
    box.checked = state.kept.has(k);
    box.addEventListener("click", (e) => e.stopPropagation());
    box.addEventListener("change", () => {
      if (box.checked) state.kept.add(k); else state.kept.delete(k);
      tr.classList.toggle("rejected", !box.checked);
      state.keptBy = "hand";
      note();
      emit("kept", state.kept);
    });
    const keep = el("td", { class: "keep", title: chosen.has(k) ? "chosen automatically (era.choose_modes)" : null }, box);
    const tr = el("tr", { "data-mode": k, class: chosen.has(k) ? "chosen" : null }, keep,
                  ...columns.map((c) => el("td", { text: c.text(m, k), "data-key": c.key,
                                                   title: c.cellTitle ? c.cellTitle(m, k) : null })));
    if (!state.kept.has(k)) tr.classList.add("rejected");
    if (state.selected === k) tr.classList.add("selected");
    tr.addEventListener("click", () => emit("select", k));
    return tr;
  });
  table.tBodies[0].replaceChildren(...rows);
  note();
}

function note() {
  // ± columns: 95 % intervals, σ from the records' scatter or from the one record's residuals (era.core.uncertainty)
  const source = state.modes.uncertainty_source ? `± 1.96 ${state.modes.uncertainty_source}${shared(state.modes)} · ` : "";
  $("table-note").textContent = `${source}${state.kept.size} of ${state.modes.n_modes} modes kept at order ${state.order}`;
  rule();
}

// The modes that share one ± (a repeated cluster, schemas.Modes.std_group), said once under the table.
function shared(m) {
  const seen = new Set(), groups = [];
  for (const g of m.std_group || []) {
    if (g && !seen.has(g.join())) { seen.add(g.join()); groups.push(g.map((j) => j + 1)); }
  }
  if (!groups.length) return "";
  const words = groups.map((g) => `${g.slice(0, -1).join(", ")} and ${g[g.length - 1]}`).join("; ");
  return ` (modes ${words}: one ± for the group, their poles closer together than their scatter)`;
}

// Which rule ticked the table, and the way back to the automatic choice when another did.
function rule() {
  const a = state.analysis, box = $("table-rule");
  if (!a || !state.modes) { box.textContent = ""; return; }
  const n = a.chosen_indices.length, at = a.suggested_order;
  const choice = n ? `the ${n} mode${n > 1 ? "s" : ""} era chose at order ${at}` : "";
  const same = chosenAt(state.order) && state.kept.size === n && a.chosen_indices.every((k) => state.kept.has(k));
  let text;
  if (!n) text = "era chose no mode (no cluster of the diagram qualifies): the thresholds tick the table.";
  else if (same) text = `Ticked: ${choice} (era.choose_modes; hover over the marks above the diagram for why each other candidate was left out).`;
  else if (state.keptBy === "hand") text = `Ticked by hand. The automatic choice: ${choice}.`;
  else text = `Ticked by the thresholds at this order. The automatic choice: ${choice}.`;
  box.textContent = text + " ";
  $("use-choice").hidden = !n || same;
}

function markSelected() {
  for (const tr of $("modes-table").tBodies[0].rows) {
    const on_ = Number(tr.dataset.mode) === state.selected;
    tr.classList.toggle("selected", on_);
    if (on_) tr.scrollIntoView({ block: "nearest" });
  }
}

// The shape scatter (1 − MAC) costs n pole functionals per mode (0.03 s at order 20, 1.7 s at 160 on the grid),
// too much for every slider step: it is asked for once the slider has rested on an order for SCATTER_WAIT ms.
const SCATTER_WAIT = 600;
let scatterTimer = null;

function askScatter() {
  clearTimeout(scatterTimer);
  const m = state.modes, a = state.analysis;
  if (!m || !a || m.shape_scatter) return;
  const order = m.order;
  scatterTimer = setTimeout(async () => {
    try {
      const full = await api(`/api/analyses/${a.id}/modes?order=${order}&fit=false&scatter=true`);
      if (state.modes && state.modes.order === order && state.analysis === a && full.shape_scatter) {
        state.modes.shape_scatter = full.shape_scatter;
        render();
      }
    } catch { /* the column keeps its dashes */ }
  }, SCATTER_WAIT);
}

export function init() {
  $("use-choice").addEventListener("click", () => emit("choice"));
  for (const id of ["min-emac", "min-mpc", "min-contrib", "physical-only"]) {
    $(id).addEventListener("change", () => { if (state.modes) emit("thresholds", thresholds()); });
  }
  on("modes", () => { render(); askScatter(); });
  on("select", markSelected);
}

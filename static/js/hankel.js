// Panel 2: Hankel size (defaults and limits from the data), identification, singular values, order slider.
import { api } from "./api.js";
import { state, emit, on, showError, plotConfig } from "./state.js";

const $ = (id) => document.getElementById(id);

function parseShifts(text, name) {
  const t = text.trim();
  if (!t) return null;
  const parts = t.split(/[\s,;]+/).filter(Boolean).map(Number);
  if (parts.some((x) => !Number.isInteger(x))) throw new Error(`${name}: give whole numbers separated by commas.`);
  return parts;
}

async function identify() {
  showError("hankel-error", null);
  const ds = state.dataset;
  let body;
  try {
    body = {
      dataset_id: ds.id, rows: Number($("rows").value), cols: Number($("cols").value),
      row_shifts: parseShifts($("row-shifts").value, "Row shifts"),
      col_shifts: parseShifts($("col-shifts").value, "Column shifts"),
      max_order: $("max-order").value ? Number($("max-order").value) : null,
    };
  } catch (err) { showError("hankel-error", err); return; }
  $("identify").disabled = true;
  const t0 = performance.now();
  $("hankel-status").textContent = "Building H(0), H(1) and taking the SVD…";
  try {
    const a = await api("/api/analyses", { method: "POST", body,
                                           progress: (text) => { $("hankel-status").textContent = text; } });
    $("hankel-status").textContent =
      `H(0) is ${a.hankel_shape[0]} × ${a.hankel_shape[1]} (${a.svd_method} SVD, ${((performance.now() - t0) / 1000).toFixed(2)} s); ` +
      `orders up to ${a.max_order} available.`;
    state.analysis = a;
    emit("analysis", a);
  } catch (err) {
    $("hankel-status").textContent = "";
    showError("hankel-error", err);
  } finally {
    $("identify").disabled = false;
  }
}

const isDefault = (shifts) => shifts.every((t, i) => t === i + 1);

function plotSingularValues(a, order) {
  const d = a.singular_values;
  const x = d.map((_, i) => i + 1);
  Plotly.react("sv-plot", [
    { x, y: d, type: "scatter", mode: "lines+markers", marker: { size: 4 }, name: "d_i", hovertemplate: "d_%{x} = %{y:.3e}<extra></extra>" },
  ], {
    margin: { l: 60, r: 10, t: 10, b: 40 }, yaxis: { type: "log", title: { text: "singular value d_i" }, exponentformat: "e" },
    xaxis: { title: { text: "index i" }, range: [0, Math.min(d.length, Math.max(2 * a.max_order, 20)) + 1] },
    shapes: [{ type: "line", x0: order + 0.5, x1: order + 0.5, yref: "paper", y0: 0, y1: 1, line: { color: "#b3261e", width: 2 } }],
    annotations: [{ x: order + 0.5, yref: "paper", y: 1, text: `n = ${order}`, showarrow: false, xanchor: "left", font: { color: "#b3261e" } }],
    showlegend: false,
  }, plotConfig);
}

export function setOrder(n, { fromSlider = false } = {}) {
  const a = state.analysis;
  n = Math.max(1, Math.min(a.max_order, Math.round(n)));
  if (!fromSlider) $("order").value = n;
  $("order-value").textContent = String(n);
  if (n === state.order) return;
  state.order = n;
  Plotly.relayout("sv-plot", { "shapes[0].x0": n + 0.5, "shapes[0].x1": n + 0.5, "annotations[0].x": n + 0.5,
                               "annotations[0].text": `n = ${n}` });
  emit("order", n);
}

export function init() {
  $("hankel-form").addEventListener("submit", (e) => { e.preventDefault(); identify(); });
  $("order").addEventListener("input", (e) => setOrder(Number(e.target.value), { fromSlider: true }));
  on("dataset", (ds) => {
    $("rows").value = ds.defaults.rows;
    $("cols").value = ds.defaults.cols;
    $("max-order").value = ds.defaults.max_order;
    $("row-shifts").value = "";
    $("col-shifts").value = "";
    $("rows").max = ds.n_samples - 1;
    $("cols").max = ds.n_samples - 1;
    $("max-order").max = ds.limits.max_order;
    $("limits").textContent = `Defaults from the data. Limits: ${ds.limits.note}`;
    $("identify").disabled = false;
    if (!state.restoring) identify();  // a first look with the defaults; change them and press Identify again
  });
  on("analysis", (a) => {
    $("rows").value = a.rows;
    $("cols").value = a.cols;
    $("max-order").value = a.requested_max_order || a.max_order;
    $("row-shifts").value = isDefault(a.row_shifts) ? "" : a.row_shifts.join(",");
    $("col-shifts").value = isDefault(a.col_shifts) ? "" : a.col_shifts.join(",");
    const slider = $("order");
    slider.min = 1;
    slider.max = a.max_order;
    slider.disabled = false;
    state.order = null;
    plotSingularValues(a, a.suggested_order);
    $("order-note").textContent = `Suggested order ${a.suggested_order} (singular values above the noise floor). ` +
      "Move the slider: poles, table and reconstruction follow; the SVD is not recomputed.";
    setOrder(a.suggested_order);
  });
}

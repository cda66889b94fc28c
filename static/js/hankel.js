// Panel 2: Hankel size (defaults and limits from the data), identification, singular values, order slider.
import { api } from "./api.js";
import { state, emit, on, el, showError, plotConfig } from "./state.js";

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

function plotSingularValues(a) {
  const d = a.singular_values;
  const x = d.map((_, i) => i + 1);
  const div = $("sv-plot");
  Plotly.react(div, [
    { x, y: d, type: "scatter", mode: "lines+markers", marker: { size: 4 }, name: "d_i", hovertemplate: "d_%{x} = %{y:.3e}<extra></extra>" },
  ], {
    margin: { l: 60, r: 10, t: 10, b: 40 }, yaxis: { type: "log", title: { text: "singular value d_i" }, exponentformat: "e" },
    xaxis: { title: { text: "index i" }, range: [0, Math.min(d.length, Math.max(2 * a.max_order, 20)) + 1] },
    showlegend: false,
  }, plotConfig).then(() => {
    if (!div.dataset.hooked) { div.on("plotly_afterplot", placeOrderMark); div.dataset.hooked = "1"; }
    placeOrderMark();
  });
}

// The order line over the singular values is a div over the plot, not a plotly shape: moving a plotly shape or
// annotation redraws the figure (40-130 ms per slider step in software rendering); moving a div costs nothing.
// Its scale is read from plotly after each draw (zoom, resize) and kept, so a slider step reads no layout.
let svArea = null;  // {left, width, x: data -> px} of the plot area, from plotly's last draw

function placeOrderMark() {
  const fl = $("sv-plot")._fullLayout;
  if (!fl?.xaxis) return;
  const xa = fl.xaxis;
  svArea = { left: fl._size.l, width: fl._size.w, x: (v) => xa.l2p(v) };
  const mark = $("sv-order");
  mark.style.top = `${fl._size.t}px`;
  mark.style.height = `${fl._size.h}px`;
  markOrder(state.order);
}

function markOrder(n) {
  const mark = $("sv-order");
  const x = svArea && n !== null ? svArea.x(n + 0.5) : -1;
  mark.hidden = !(x >= 0 && x <= svArea.width);
  if (mark.hidden) return;
  mark.style.left = `${svArea.left + x}px`;
  mark.firstChild.textContent = `n = ${n}`;
}

export function setOrder(n, { fromSlider = false } = {}) {
  const a = state.analysis;
  n = Math.max(1, Math.min(a.max_order, Math.round(n)));
  if (!fromSlider) $("order").value = n;
  $("order-value").textContent = String(n);
  if (n === state.order) return;
  state.order = n;
  markOrder(n);
  emit("order", n);
}

export function init() {
  const plot = $("sv-plot");
  plot.style.position = "relative";
  plot.append(el("div", { id: "sv-order", hidden: true, style: "position:absolute; z-index:1; width:0; " +
                          "border-left:2px solid #b3261e; pointer-events:none" },
                 el("span", { style: "position:absolute; left:4px; top:0; color:#b3261e; font-size:12px; white-space:nowrap" })));
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
    plotSingularValues(a);
    const n = a.chosen_indices.length;
    $("order-note").textContent = (n
      ? `Order ${a.suggested_order}: where the ${n} mode${n > 1 ? "s" : ""} era chose automatically are read (one of the diagram's orders). `
      : `Order ${a.suggested_order}: era chose no mode; this is the diagram order nearest the singular values' ${a.noise_floor_order}. `) +
      `The singular values stand above the noise floor up to ${a.noise_floor_order}. ` +
      "Move the slider: poles, table and reconstruction follow; the SVD is not recomputed.";
    setOrder(a.suggested_order);
  });
}

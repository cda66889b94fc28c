// Panel "Model of the structure" (issue 9): the era.Frame simulation vs test compares the test with. Described
// here from the dataset's geometry (one member per trace line segment, grouped by named trace line; a section and
// material per group; supports, springs and lumped masses set by clicking nodes in the drawing, in the 3-D view or in
// the node table; members added, removed or turned in the member table (model_edit.js); the sensors are the
// dataset's channels) or uploaded as a model file (era.Frame JSON/TOML, or the engineer's FE model: a Nastran deck or
// a .zip of matrices, its outputs matched to model nodes in model_fe.js's table). The server checks and keeps it with the
// dataset (PUT /api/datasets/{id}/model): a reload or the analysis link shows it again, a report freezes it.
// Sizes are typed in mm and sent in m (era.structure's SI file format).
import { api, upload } from "./api.js";
import { state, on, emit, el, showError, plotConfig, plain } from "./state.js";
import { drawNodes as nodeTable, drawMembers as memberTable, drawAdd, usedNodes, supportOf as supportIn, placeRefusal,
         clearRefusals, head, select } from "./model_edit.js";
import { View3D } from "./model_view3d.js";
import { drawMapping, feRows } from "./model_fe.js";

const $ = (id) => document.getElementById(id);
const SIZES = { rectangle: ["width", "depth"], tube: ["diameter", "wall"], square_tube: ["width", "wall"], circle: ["diameter"] };
const SHAPE_WORDS = { rectangle: "solid rectangle", tube: "round tube", square_tube: "square tube", circle: "solid round bar" };
const DEFAULT_MM = { width: 50, depth: 6, diameter: 30, wall: 3 };

let draft = null;   // GET .../model/draft: nodes (m), members [i, j, group], sensors, materials, shapes
let desc = null;    // what the person describes: members, sections {group: {shape, sizes (m), material}}, supports, masses
let saved = null;   // the stored model's summary (schemas.StructureModel), or null

function datasetUrl() { return `/api/datasets/${encodeURIComponent(state.dataset.id)}/model`; }

// ---- the description -> era.Frame's file format ----------------------------------------------------------------
function frameModel() {
  const groups = [...new Set(desc.members.map((m) => m[2]))];
  const sections = {};
  for (const g of groups) sections[g] = { ...desc.sections[g] };
  const supports = Object.fromEntries(Object.entries(desc.supports).filter(([, s]) => s !== "free"));
  const masses = Object.fromEntries(Object.entries(desc.masses).filter(([, m]) => m !== 0 && m !== ""));
  return { nodes: usedNodes(desc, draft), members: desc.members.map((m) => [...m]), sections, supports, masses,
           sensors: draft.sensors, ...(desc.gravity ? { gravity: desc.gravity } : {}) };
}

function newSection() {
  return { shape: "rectangle", width: DEFAULT_MM.width / 1000, depth: DEFAULT_MM.depth / 1000, material: "" };
}

// A stored model described from this geometry (its nodes among the geometry's) is edited again; anything else
// starts from the draft.
function startFrom(stored) {
  const same = stored && stored.source === "geometry" && Object.keys(stored.model.nodes || {}).every((n) => n in draft.nodes);
  const m = same ? stored.model : null;
  desc = { members: (m ? m.members : draft.members).map((x) => [String(x[0]), String(x[1]), String(x[2]),
                                                               ...(x[3] == null ? [] : [x[3]])]),
           sections: {}, supports: {}, masses: {}, gravity: m ? m.gravity || null : null };
  for (const [g, s] of Object.entries(m ? m.sections : {})) if (s.shape) desc.sections[g] = { ...s };
  for (const [n, s] of Object.entries(m ? m.supports || {} : {})) desc.supports[n] = s;
  for (const [n, kg] of Object.entries(m ? m.masses || {} : {})) desc.masses[n] = kg;
  for (const g of new Set(desc.members.map((x) => x[2]))) desc.sections[g] ||= newSection();
  $("model-gravity").checked = !!desc.gravity;
}

// ---- drawing: sections, nodes, members, the clickable view ----------------------------------------------------------

function drawSections() {
  const t = $("model-sections");
  head(t, ["group", "members", "shape", "sizes (mm)", "material"]);
  const count = {};
  for (const m of desc.members) count[m[2]] = (count[m[2]] || 0) + 1;
  for (const g of Object.keys(count).sort()) {
    const sec = desc.sections[g];
    const shape = select(draft.shapes.map((s) => [s, SHAPE_WORDS[s] || s]), sec.shape, { class: "shape", "aria-label": `shape of ${g}` });
    const sizes = el("span");
    const drawSizes = () => sizes.replaceChildren(...SIZES[sec.shape].map((k) => {
      const input = el("input", { type: "number", min: "0", step: "any", "data-size": k, "aria-label": `${k} of ${g} (mm)`,
                                  value: String(+((sec[k] ?? DEFAULT_MM[k] / 1000) * 1000).toPrecision(6)), style: "width:80px" });
      input.addEventListener("change", () => { sec[k] = Number(input.value) / 1000; });
      return el("label", { class: "note", style: "margin-right:8px" }, `${k} `, input);
    }));
    shape.addEventListener("change", () => {
      for (const k of SIZES[sec.shape]) delete sec[k];
      sec.shape = shape.value;
      for (const k of SIZES[sec.shape]) sec[k] = DEFAULT_MM[k] / 1000;
      drawSizes();
    });
    const material = select([["", "— choose —"], ...draft.materials.map((m) => [m, m.replace(/_/g, " ")])], sec.material || "",
                            { class: "material", "aria-label": `material of ${g}` });
    material.addEventListener("change", () => { sec.material = material.value; });
    drawSizes();
    const tr = el("tr", { "data-group": g });
    for (const c of [el("td", { text: g }), el("td", { text: String(count[g]) }), el("td", {}, shape), el("td", {}, sizes), el("td", {}, material)]) tr.append(c);
    t.tBodies[0].append(tr);
  }
}

function supportOf(n) { return supportIn(desc, n); }

// A support or mass changed: the drawing and the 3-D view follow.
function changedNodes() { drawPlot(); view3d.mark(marks()); }

function drawNodes() { nodeTable($("model-nodes"), desc, draft, changedNodes, (n) => { selectNode(n); view3d.look(n); }); }

// Members added, removed or regrouped: the tables, the drawing and the 3-D view follow.
function changedMembers(groups) {
  if (groups) drawSections();
  drawMembers();
  drawPlot();
  if (groups) view3d.republish();
}

function drawMembers() {
  memberTable($("model-members"), desc, draft, changedMembers, newSection);
  drawAdd($("model-member-add"), desc, draft, changedMembers, newSection);
}

function selectNode(n) {
  for (const r of document.querySelectorAll("#model-nodes tr.selected")) r.classList.remove("selected");
  const row = document.querySelector(`#model-nodes tr[data-node="${CSS.escape(n)}"]`);
  if (row) { row.classList.add("selected"); row.scrollIntoView({ block: "nearest" }); }
}

// What the 3-D view colours: each node's support ("fixed", "pinned", "springs") or "mass", else "".
function marks() {
  return Object.fromEntries(Object.keys(draft.nodes).map((n) => [n, supportOf(n) !== "free" ? supportOf(n) : desc.masses[n] > 0 ? "mass" : ""]));
}

// The two axes of the view: chosen, or those along which the structure is largest (a portal in x-z: the front).
function plane() {
  const chosen = $("model-view").value;
  if (chosen !== "auto") return chosen.split(",").map(Number);
  const xyz = Object.values(draft.nodes);
  const span = [0, 1, 2].map((a) => Math.max(...xyz.map((p) => p[a])) - Math.min(...xyz.map((p) => p[a])));
  return [0, 1, 2].sort((i, j) => span[j] - span[i] || i - j).slice(0, 2).sort();
}

function drawPlot() {
  const [a, b] = plane();
  const ids = Object.keys(draft.nodes), P = draft.nodes;
  const x = [], y = [];
  for (const [i, j] of desc.members) { x.push(P[i][a], P[j][a], null); y.push(P[i][b], P[j][b], null); }
  const symbol = (n) => ({ fixed: "square", pinned: "triangle-up", springs: "star" }[supportOf(n)] || (desc.masses[n] > 0 ? "diamond" : "circle"));
  const colour = (n) => supportOf(n) !== "free" ? "#b3261e" : desc.masses[n] > 0 ? "#9a6700" : "#1f5fbf";
  const sensed = [...new Set(draft.sensors.map((s) => s[0]))];
  Plotly.react("model-plot", [
    { type: "scatter", mode: "lines", x, y, line: { color: "#8a93a3", width: 2 }, hoverinfo: "skip", name: "members" },
    { type: "scatter", mode: "markers", x: sensed.map((n) => P[n][a]), y: sensed.map((n) => P[n][b]), hoverinfo: "skip", name: "sensors",
      marker: { symbol: "circle-open", size: 18, color: "#1d2330", line: { width: 1.5 } } },
    { type: "scatter", mode: "markers+text", x: ids.map((n) => P[n][a]), y: ids.map((n) => P[n][b]), text: ids.map(plain),
      textposition: "top right", customdata: ids.map((n) => `${supportOf(n)}${desc.masses[n] > 0 ? `, ${desc.masses[n]} kg` : ""}`),
      hovertemplate: "node %{text}: %{customdata}<extra></extra>", name: "nodes",
      marker: { size: 12, symbol: ids.map(symbol), color: ids.map(colour) } },
  ], { margin: { l: 50, r: 10, t: 10, b: 40 }, showlegend: false, hovermode: "closest",
       xaxis: { title: { text: `${"xyz"[a]} (m)` }, constrain: "domain" }, yaxis: { title: { text: `${"xyz"[b]} (m)` }, scaleanchor: "x" } },
  plotConfig).then((div) => {
    if (div._eraClick) return;
    div._eraClick = true;
    div.on("plotly_click", (ev) => {
      const p = (ev.points || []).find((q) => q.curveNumber === 2);
      if (p) clickNode(Object.keys(draft.nodes)[p.pointNumber]);
    });
  });
}

// A node clicked in the drawing or picked in the 3-D view: what "Clicking a node" says, then its row selected.
function clickNode(n) {
  if (!draft || !(n in draft.nodes)) return;
  const what = $("model-click").value;
  if (what === "mass") desc.masses[n] = (Number(desc.masses[n]) || 0) + (Number($("model-click-mass").value) || 0);
  else if (what === "free") delete desc.supports[n];
  else desc.supports[n] = what;
  drawNodes();
  changedNodes();
  selectNode(n);
}

// The 3-D view of the description (viser): nodes picked there act as clicks in the drawing.
const view3d = new View3D({
  url: () => `${datasetUrl()}/viewer`,
  scene: () => ({ nodes: usedNodes(desc, draft), members: desc.members.map((m) => [m[0], m[1]]), marks: marks() }),
  picked: clickNode,
});

async function openEditor() {
  showError("model-error", null);
  $("model-status").textContent = "Reading the geometry…";
  try {
    draft = await api(`${datasetUrl()}/draft`);
    startFrom(saved);
    clearRefusals();
    view3d.close();
    $("model-sensors").textContent = draft.sensors.map(([n, d], i) => `${draft.outputs[i]} → node ${n} ${Array.isArray(d) ? "oblique" : d}`).join(", ");
    $("model-editor").hidden = false;
    drawSections();
    drawNodes();
    drawMembers();
    drawPlot();
    $("model-status").textContent = `${Object.keys(draft.nodes).length} nodes and ${draft.members.length} members from the trace lines. Choose a section and material per group, the supports and any lumped masses, then save.`;
  } catch (err) {
    $("model-status").textContent = "";
    showError("model-error", err);
  }
}

// ---- saving, uploading, showing the stored model -----------------------------------------------------------------
function show(summary) {
  saved = summary;
  if (summary && state.dataset) state.dataset.has_model = true;  // so a later visit asks for it
  render();
  if (summary) {
    const blob = new Blob([JSON.stringify(summary.model, null, 1)], { type: "application/json" });
    if ($("model-download").href.startsWith("blob:")) URL.revokeObjectURL($("model-download").href);
    $("model-download").href = URL.createObjectURL(blob);
  }
  $("model-download").hidden = !summary || summary.source === "fe";   // an FE model stays the engineer's file
  drawMapping(summary, datasetUrl(), (r) => show(r));
  emit("model", summary);
}

// The stored model beside the test: its lowest frequencies, and the test's kept modes at the current order.
function render() {
  const summary = saved, dl = $("model-summary");
  canCompare();
  dl.replaceChildren();
  dl.hidden = !summary;
  if (!summary) return;
  const rows = summary.source === "fe" ? feRows(summary) : [
    ["Model", summary.source === "file" ? `from the file ${summary.name}` : "described from the test geometry"],
    ["Structure", summary.text], ["Mass", `${summary.total_mass_kg.toPrecision(4)} kg`],
    ["Model's lowest modes (Hz)", summary.frequency_hz.filter((f) => f !== null && f > 1e-6).map((f) => f.toPrecision(4)).join(", ")]];
  if (state.modes && state.modes.n_modes) {
    const kept = [...state.kept].sort((a, b) => a - b).map((k) => state.modes.frequency_hz[k]).filter((f) => f !== null);
    rows.push([`Test's kept modes at order ${state.order} (Hz)`, kept.map((f) => f.toPrecision(4)).join(", ") || "none kept"]);
  }
  for (const [k, v] of rows) dl.append(el("dt", { text: k }), el("dd", { text: v }));
}

async function save() {
  showError("model-error", null);
  clearRefusals();
  $("model-save").disabled = true;
  $("model-status").textContent = "Checking the model…";
  try {
    const r = await api(datasetUrl(), { method: "PUT", body: { model: frameModel(), source: "geometry" },
                                        progress: (text) => { $("model-status").textContent = text; } });
    $("model-status").textContent = "Saved with this dataset: simulation vs test now compares with it.";
    show(r);
  } catch (err) {
    $("model-status").textContent = "";
    if (!placeRefusal(err)) showError("model-error", err);   // under its row, else here; the stored model is unchanged
  } finally {
    $("model-save").disabled = false;
  }
}

async function uploadModel(file) {
  showError("model-file-error", null);
  showError("model-error", null);
  $("model-status").textContent = `Reading ${file.name}…`;
  try {
    const r = await upload(`${datasetUrl()}/file`, file, () => {}, (text) => { $("model-status").textContent = text; });
    $("model-status").textContent = `Saved ${file.name} with this dataset: simulation vs test now compares with it.`;
    $("model-editor").hidden = true;
    show(r);
  } catch (err) {
    $("model-status").textContent = "";
    showError("model-file-error", err);
  } finally {
    $("model-file").value = "";
  }
}

// The saved model's modes beside the test's kept modes at the current order: MAC at the sensors.
async function compare() {
  showError("model-compare-error", null);
  const kept = [...state.kept].sort((a, b) => a - b);
  if (!kept.length) { showError("model-compare-error", new Error("Keep at least one mode in the table first.")); return; }
  $("model-compare").disabled = true;
  try {
    const q = new URLSearchParams({ order: state.order, modes: kept.join(",") });
    const r = await api(`/api/analyses/${state.analysis.id}/model/mac?${q}`,
                        { progress: (text) => { $("model-compare-note").textContent = text; } });
    $("model-mac").hidden = false;
    await Plotly.react("model-mac", [{ type: "heatmap", z: r.mac, zmin: 0, zmax: 1,
      colorscale: [[0, "#ffffff"], [0.5, "#9ab8e6"], [1, "#123e85"]],
      x: r.model_hz.map((f, j) => `${j + 1}: ${f === null ? "–" : f.toFixed(3)}`), y: r.test_hz.map((f, i) => `${i + 1}: ${f.toFixed(3)}`),
      hovertemplate: "test %{y} Hz<br>model %{x} Hz<br>MAC %{z:.3f}<extra></extra>" }],
      { title: { text: `MAC: the test's kept modes at order ${state.order} against the model`, font: { size: 13 } },
        margin: { l: 80, r: 10, t: 30, b: 70 }, xaxis: { title: { text: "model mode (Hz)" }, tickangle: -45 },
        yaxis: { title: { text: "test mode (Hz)" }, autorange: "reversed" } }, plotConfig);
    $("model-compare-note").textContent = r.best.map((b, i) => b === null ? `test ${r.test_hz[i].toFixed(3)} Hz: no model partner` :
      `test ${r.test_hz[i].toFixed(3)} Hz ↔ model ${r.model_hz[b.model_mode].toFixed(3)} Hz (MAC ${b.mac.toFixed(3)}, ${b.frequency_error_pct >= 0 ? "+" : ""}${b.frequency_error_pct.toFixed(1)} %)`).join("; ");
  } catch (err) {
    $("model-compare-note").textContent = "";
    showError("model-compare-error", err);
  } finally {
    canCompare();
  }
}

function canCompare() { $("model-compare").disabled = !(saved && state.analysis && state.modes); }

const NO_TRACE_LINES = "This dataset has no trace lines: upload a model file instead.";

// The visible reason under a disabled button (a hover title alone is missed): made once, in a box with the button.
function whyDisabled(button) {
  let note = document.getElementById(`${button.id}-why`);
  if (!note) {
    const box = el("div", { class: "with-why", style: "display:flex;flex-direction:column;align-items:flex-start;gap:4px" });
    button.replaceWith(box);
    note = el("div", { id: `${button.id}-why`, class: "note", style: "max-width:380px" });
    box.append(button, note);
  }
  return note;
}

async function load(ds) {
  saved = null; draft = null; desc = null;
  view3d.close();
  $("model-editor").hidden = true;
  $("model-mac").hidden = true;
  $("model-compare-note").textContent = "";
  $("model-status").textContent = "";
  for (const id of ["model-error", "model-file-error", "model-compare-error", "model-mapping-error"]) showError(id, null);
  const button = $("model-from-geometry");
  button.disabled = !(ds.geometry && ds.geometry.n_edges > 0);
  button.title = button.disabled ? NO_TRACE_LINES : "";
  whyDisabled(button).textContent = button.disabled ? NO_TRACE_LINES : "";
  if (!ds.has_model) { show(null); return; }  // none stored: asking would be a 404
  try {
    const r = await api(`/api/datasets/${encodeURIComponent(ds.id)}/model`);
    if (state.dataset && state.dataset.id === ds.id) show(r);
  } catch {
    if (state.dataset && state.dataset.id === ds.id) show(null);  // none yet
  }
}

export function init() {
  $("model-from-geometry").addEventListener("click", openEditor);
  $("model-save").addEventListener("click", save);
  $("model-compare").addEventListener("click", compare);
  $("model-view").addEventListener("change", () => { if (draft) drawPlot(); });
  $("model-3d").addEventListener("click", () => { if (draft) view3d.open($("model-3d-box")); });
  $("model-gravity").addEventListener("change", () => { desc.gravity = $("model-gravity").checked ? [0, 0, -9.81] : null; });
  $("model-file").addEventListener("change", () => { const f = $("model-file").files[0]; if (f) uploadModel(f); });
  on("dataset", load);
  on("modes", render);
}

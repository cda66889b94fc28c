// The multi-setup page: /setups uploads one file per setup (POST /api/setups), /s/{id} reopens a test. The
// reference picker proposes the channels found from the data (their components keep the same ratios in every
// setup; the evidence shown), else those named alike; the merge (POST /api/setups/{id}/merge)
// analyses every setup and joins them through the references; the merged modes are shown at every point.
import { api } from "./api.js";
import { el, plain, plotConfig, showError } from "./state.js";

const $ = (id) => document.getElementById(id);
const METHODS = { poser: "PoSER", preger: "PreGER" };
const CONTROLS = ["file", "kind", "dt", "references", "points"];  // a refusal's `option` -> the box next to its control
let test = null;       // schemas.SetupsTest
let selected = 0;

function refuse(err) {
  const option = CONTROLS.includes(err.option) ? err.option : null;
  for (const c of CONTROLS) showError(`setups-${c}-error`, null);
  showError(`setups-${option || (test ? "references" : "file")}-error`, err);
}

// ---- 1 the setups -------------------------------------------------------------------------------------------
async function upload(ev) {
  ev.preventDefault();
  for (const c of CONTROLS) showError(`setups-${c}-error`, null);
  const files = $("setups-files").files;
  const form = new FormData();
  for (const f of files) form.append("file", f, f.name);
  form.append("kind", $("setups-kind").value);
  if ($("setups-name").value) form.append("name", $("setups-name").value);
  const rate = Number($("setups-rate").value);
  if (rate > 0) form.append("dt", String(1 / rate));
  $("setups-upload").disabled = true;
  $("setups-status").textContent = `Reading ${files.length} ${files.length === 1 ? "file" : "files"}…`;
  try {
    const res = await fetch("/api/setups", { method: "POST", body: form });
    const body = await res.json().catch(() => null);
    if (!res.ok) {
      const err = new Error((body && body.error) || `${res.status} ${res.statusText}`);
      err.option = body && body.option;
      if (err.option === "dt") err.message = err.message.replace(/\bdt\b/g, "the sample rate");
      throw err;
    }
    history.pushState(null, "", `/s/${body.id}`);
    show(body);
    $("setups-status").textContent = `${body.setups.length} setups read.`;
  } catch (err) {
    $("setups-status").textContent = "";
    refuse(err);
  } finally {
    $("setups-upload").disabled = false;
  }
}

// ---- 2 the reference picker ---------------------------------------------------------------------------------
function picker(references) {
  const head = el("tr", {}, el("th", { text: "reference" }),
    ...test.setups.map((s, k) => el("th", { text: `setup ${k + 1} (${s.file})` })));
  $("setups-ref-table").tHead.replaceChildren(head);
  const body = $("setups-ref-table").tBodies[0];
  body.replaceChildren();
  const n = references.length ? references[0].length : 0;
  for (let r = 0; r < n; r++) addRow(references.map((refs) => refs[r]));
}

function addRow(choice) {
  const body = $("setups-ref-table").tBodies[0];
  const r = body.rows.length;
  const cells = test.setups.map((s, k) => {
    const select = el("select", { class: "ref-select", "data-setup": k, "data-row": r,
                                  "aria-label": `reference ${r + 1} in setup ${k + 1}` },
      ...s.outputs.map((name, i) => el("option", { value: i, text: name })));
    select.value = String(choice ? choice[k] : Math.min(r, s.outputs.length - 1));
    return el("td", {}, select);
  });
  body.append(el("tr", {}, el("td", { text: String(r + 1) }), ...cells));
}

function picked() {
  const rows = [...$("setups-ref-table").tBodies[0].rows];
  return test.setups.map((_, k) => rows.map((tr) => Number(tr.querySelector(`select[data-setup="${k}"]`).value)));
}

async function merge() {
  for (const c of CONTROLS) showError(`setups-${c}-error`, null);
  $("setups-merge").disabled = true;
  $("setups-merge-status").textContent = `Analysing ${test.setups.length} setups and merging them…`;
  try {
    const t = await api(`/api/setups/${test.id}/merge`, {
      method: "POST", body: { references: picked(), points: $("setups-points").value || null,
                              next_references: $("setups-next").value, method: $("setups-method").value },
      progress: (text) => { $("setups-merge-status").textContent = text; } });
    show(t);
    $("setups-merge-status").textContent = `Merged by ${METHODS[t.merged.method || "poser"]}: ${t.merged.modes.length} modes at ${t.merged.points.length} points.`;
  } catch (err) {
    $("setups-merge-status").textContent = "";
    const box = ["file", "points"].includes(err.option) ? err.option : "references";
    if (box === "points") $("setups-points-box").open = true;
    showError(`setups-${box}-error`, err);
  } finally {
    $("setups-merge").disabled = false;
  }
}

// ---- 3 the merged modes -------------------------------------------------------------------------------------
function show(t) {
  test = t;
  $("setups-title").textContent = `ERA multi-setup test: ${t.name}`;
  $("setups-refs").hidden = false;
  const names = t.proposed_names;
  const perSetup = t.proposed.map((refs, k) => `${refs.map((i) => t.setups[k].outputs[i]).join(", ")} in setup ${k + 1}`);
  const said = t.data_proposal ? ` The data: ${t.data_proposal}.` : "";
  $("setups-proposal").textContent = t.proposed_from === "data"
    ? `Proposed from the data: ${perSetup.join("; ")}. ${t.data_proposal.replace(/^./, (c) => c.toUpperCase())}.`
    : names.length
      ? `Proposed from the names: ${names.join(", ")}: the channels with the same names in every setup.${said}`
      : `No proposal: pick each setup's reference channels below (at least two).${said}`;
  evidence(t);
  const missing = t.unmatched.map((u) => `${u.name} is not in setup ${u.missing_in.join(", ")}`);
  $("setups-unmatched").hidden = !missing.length;
  $("setups-unmatched").textContent = missing.length
    ? `${missing.join("; ")}: if it is a reference there under another name, add it below.` : "";
  picker(t.merged ? t.merged.references : (t.proposed[0].length ? t.proposed : t.setups.map(() => [0, 1])));
  if (t.merged) $("setups-method").value = t.merged.method || "poser";
  if (t.merged && t.merged.next_asked && t.merged.method !== "preger") $("setups-next").value = t.merged.next_asked;
  methodChanged();
  if (t.merged && t.merged.points_table && !$("setups-points").value) {
    $("setups-points").value = t.merged.points_table;
  }
  nodesNote(t);
  $("setups-result").hidden = !t.merged;
  if (t.merged) result(t.merged);
}

// The UFF file of nodes given for a points table point,node,direction.
function nodesNote(t) {
  const n = t.nodes;
  $("setups-nodes-note").textContent = n
    ? `${n.file}: ${n.n_nodes} nodes (${n.node_ids.slice(0, 6).join(", ")}${n.n_nodes > 6 ? ", …" : ""}), ${n.n_lines} trace ${n.n_lines === 1 ? "line" : "lines"}; the table may read point,node,direction.`
    : "";
}

// The reference evidence: the best pairs of channels and their MAC over the modes every setup found.
function evidence(t) {
  const table = $("setups-evidence");
  table.hidden = !(t.candidates && t.candidates.length);
  if (table.hidden) return;
  table.tHead.replaceChildren(el("tr", {}, el("th", { text: "channels (setup 1 / 2 / …)" }), el("th", { text: "MAC" }),
    el("th", { text: "next best" }), ...t.shared_hz.map((f) => el("th", { text: `${f.toFixed(3)} Hz` }))));
  table.tBodies[0].replaceChildren(...t.candidates.map((c) => el("tr", {},
    el("td", { text: c.channels.map((pair) => pair.join("+")).join(" / ") }), el("td", { text: c.score.toFixed(4) }),
    el("td", { text: c.runner_up === null ? "–" : c.runner_up.toFixed(4) }),
    ...t.shared_hz.map((_, m) => el("td", { text: Math.min(...c.mac.slice(1).map((row) => row[m])).toFixed(3) })))));
}

const pct = (x) => (x === null || x === undefined ? "–" : (100 * x).toFixed(3));
// The largest relative σ of the factors the setups' parts were scaled by, in %.
const scaleStd = (mode) => {
  const sd = (mode.scale_std || []).filter((x) => x !== null);
  return sd.length ? `±${(100 * Math.max(...sd)).toFixed(1)}` : "–";
};
const num = (x, d) => (x === null || x === undefined ? "–" : x.toFixed(d));

function result(m) {
  $("setups-rule").textContent = m.method === "preger"
    ? "PreGER: one identification of every setup's correlations, so each mode is known at every point"
    : "PoSER: a mode two setups or more chose is kept; its shape is unknown (not zero) at the points of a setup that missed it";
  const frozen = test.report;  // a report: the merge as it was frozen, read-only
  const link = `${location.origin}${frozen ? frozen.url : `/s/${test.id}`}`;
  $("setups-link").textContent = link;
  $("setups-link").href = link;
  const base = frozen ? `/api/setups/${test.id}/reports/${frozen.token}` : `/api/setups/${test.id}`;
  const files = test.offline_files;  // the downloaded report: its files inside it
  $("setups-csv").href = files ? `data:text/csv;base64,${files.csv}` : `${base}/modes.csv`;
  $("setups-uff").hidden = Boolean(files && !files.uff);
  $("setups-uff").href = files ? `data:application/octet-stream;base64,${files.uff || ""}` : `${base}/modes.uff`;
  $("setups-html").hidden = !frozen || Boolean(test.standalone);
  $("setups-html").href = `${base}/report.html`;
  if (test.standalone) {
    $("setups-link").textContent = `${frozen.url} (on the server the report was made on)`;
    $("setups-link").removeAttribute("href");
  }
  $("setups-report-note").hidden = !frozen;
  $("setups-report-note").textContent = frozen
    ? `Read-only report, frozen ${new Date(frozen.created * 1000).toISOString().slice(0, 16).replace("T", " ")} UTC: the merged modes and their geometry as they were then. The test itself: /s/${test.id}.` : "";
  $("setups-report-row").hidden = Boolean(frozen);
  const partial = m.modes.map((mode, j) => [mode, j]).filter(([mode]) => !mode.complete);
  $("setups-uff-note").textContent = partial.length
    ? `The UFF 55 file leaves out ${partial.map(([mode, j]) => `mode ${j + 1} (${mode.frequency_hz.toFixed(3)} Hz, not measured in setup ${mode.missing_setups.join(", ")})`).join("; ")}: UFF 55 holds a value at every node. The CSV has it, with empty cells where it is unknown.`
    : "Every mode is known at every point.";
  const preger = m.method === "preger";
  $("setups-method-note").textContent = preger
    ? "Merged by PreGER (the setups' correlations joined, then one identification): every mode found is known at every point."
    : "Merged by PoSER (each setup identified, then the shapes joined through the references).";
  $("setups-next-note").textContent = m.next_choice ? (preger ? m.next_choice : `NExT references: ${m.next_choice}`) : "";
  const body = $("setups-modes").tBodies[0];
  body.replaceChildren(...m.modes.map((mode, j) => {
    const cells = [["mode", String(j + 1)], ["frequency_hz", num(mode.frequency_hz, 4)],
                   ["frequency_std_hz", num(mode.frequency_std_hz, 4)], ["damping", pct(mode.damping_ratio)],
                   ["damping_std", pct(mode.damping_std)], ["mpc", num(mode.mpc, 3)],
                   ["scale_std", scaleStd(mode)], ["seen", mode.seen],
                   ["note", mode.note]];
    const tr = el("tr", { "data-mode": j, class: mode.complete ? "" : "incomplete" },
      ...cells.map(([key, text]) => el("td", { "data-key": key, text })));
    tr.addEventListener("click", () => { selected = j; shape(); });
    return tr;
  }));
  $("setups-dropped").replaceChildren(...(m.dropped.length ? m.dropped.map((d) =>
    el("li", { text: `setup ${d.setup} (${d.file}), ${d.frequency_hz.toFixed(3)} Hz: ${d.reason}` }))
    : [el("li", { text: "nothing" })]));
  selected = Math.min(selected, m.modes.length - 1);
  shape();
  viewer();
}

function shape() {
  const m = test.merged, j = selected;
  if (!m || j < 0) return;
  const mode = m.modes[j];
  $("setups-shape-title").textContent = `mode ${j + 1}: ${mode.frequency_hz.toFixed(4)} Hz, ζ ${pct(mode.damping_ratio)} %, ${mode.seen}`;
  for (const tr of $("setups-modes").tBodies[0].rows) tr.classList.toggle("selected", Number(tr.dataset.mode) === j);
  const where = m.points.map(plain);
  const setupOf = m.point_setup.map((k) => (k === 0 ? "reference" : `setup ${k}`));
  Plotly.react("setups-shape-plot", [
    { x: where, y: m.shapes_re[j], name: "real", type: "bar", marker: { color: "#1f5fbf" }, text: setupOf, textposition: "none",
      hovertemplate: "%{x} (%{text}): %{y:.3f}<extra></extra>" },
    { x: where, y: m.shapes_im[j], name: "imaginary", type: "bar", marker: { color: "#e4572e" } },
  ], { margin: { l: 45, r: 10, t: 10, b: 60 }, barmode: "group", yaxis: { title: { text: "shape (largest = 1)" } },
       legend: { orientation: "h", y: 1.15 } }, plotConfig);
  drawing(m, j);
}

// The merged shape drawn on the geometry (nodes moved along their points' directions), else the points in a row.
function drawing(m, j) {
  const re = m.shapes_re[j];
  const g = m.geometry;
  $("setups-drawing-note").textContent = g
    ? `The shape on the ${g.node_ids.length} nodes given, each point moving along its direction.`
    : "No geometry: the points are drawn in a row. To see the shape on the structure, give each point's coordinates "
      + "and direction (a CSV point,x,y,z,direction, and the lines between points) under \"Where the points are\" "
      + "in step 2, then merge again.";
  if (!g) {  // the points in a row, in the order of their names (P1, P2, …, P10: numbers as numbers)
    const order = m.points.map((_, q) => q).sort((a, b) => m.points[a].localeCompare(m.points[b], undefined, { numeric: true }));
    const x = order.map((q) => plain(m.points[q]));
    Plotly.react("setups-drawing", [
      { x, y: x.map(() => 0), mode: "markers", name: "at rest", marker: { color: "#aaa" } },
      { x, y: order.map((q) => re[q]), mode: "lines+markers", name: "mode shape (real part), points by name",
        connectgaps: false, marker: { color: "#1f5fbf" } },
    ], { margin: { l: 45, r: 10, t: 10, b: 60 }, yaxis: { title: { text: "shape" } }, legend: { orientation: "h", y: 1.15 } },
    plotConfig);
    return;
  }
  const xyz = g.coordinates.map((c) => c.slice());
  const span = Math.max(...[0, 1, 2].map((a) => Math.max(...xyz.map((c) => c[a])) - Math.min(...xyz.map((c) => c[a])))) || 1;
  const moved = xyz.map((c) => c.slice());
  g.channel_nodes.forEach((node, q) => {
    if (node < 0 || re[q] === null) return;
    for (let a = 0; a < 3; a++) moved[node][a] += 0.15 * span * re[q] * g.channel_directions[q][a];
  });
  const lines = (pts, name, color) => {
    const x = [], y = [], z = [];
    for (const [a, b] of g.edges) { x.push(pts[a][0], pts[b][0], null); y.push(pts[a][1], pts[b][1], null); z.push(pts[a][2], pts[b][2], null); }
    return { type: "scatter3d", mode: "lines", x, y, z, name, line: { color, width: 4 } };
  };
  const nodes = { type: "scatter3d", mode: "markers", name: "points", x: moved.map((c) => c[0]), y: moved.map((c) => c[1]),
                  z: moved.map((c) => c[2]), marker: { size: 3, color: "#1f5fbf" } };
  Plotly.react("setups-drawing", [lines(xyz, "at rest", "#bbb"), lines(moved, "mode shape", "#1f5fbf"), nodes],
    { margin: { l: 0, r: 0, t: 0, b: 0 }, scene: { aspectmode: "data" }, legend: { orientation: "h" } }, plotConfig);
}

let published = null;
async function viewer() {
  const box = $("setups-viewer");
  if (test.standalone) {  // no server: the drawing above is the shape on its geometry
    box.replaceChildren(el("div", { class: "note", text: "Downloaded report: the 3-D viewer needs the app; the drawing above shows the shape." }));
    return;
  }
  try {
    const where = test.report ? `/api/setups/${test.id}/reports/${test.report.token}` : `/api/setups/${test.id}`;
    const v = await api(`${where}/viewer`, { method: "POST" });
    published = v;
    box.replaceChildren(el("iframe", { class: "viewer", src: v.url, title: "merged mode shape viewer" }));
  } catch (err) {
    published = null;
    box.replaceChildren(el("div", { class: "note", text: `3-D viewer: ${err.message} The drawing above shows the shape.` }));
  }
}

async function sendMode() {
  if (published) await api(published.mode_url, { method: "POST", body: { index: selected } }).catch(() => {});
}

async function reopen(id, token) {
  try {
    const t = await api(token ? `/api/setups/${id}/reports/${token}` : `/api/setups/${id}`);
    show(t);
    if (token) reportOnly(t);
  } catch (err) {
    showError("setups-file-error", err);
  }
}

async function freeze() {
  try {
    const r = await api(`/api/setups/${test.id}/report`, { method: "POST" });
    const link = `${location.origin}${r.url}`;
    $("setups-report-link").textContent = link;
    $("setups-report-link").href = link;
    $("setups-report-share").hidden = false;
  } catch (err) {
    showError("setups-references-error", err);
  }
}

// PreGER correlates with the picked references only: the NExT choice is PoSER's.
function methodChanged() {
  $("setups-next-field").hidden = $("setups-method").value === "preger";
}

$("setups-form").addEventListener("submit", upload);
$("setups-method").addEventListener("change", methodChanged);
$("setups-add-ref").addEventListener("click", () => addRow(null));
$("setups-remove-ref").addEventListener("click", () => $("setups-ref-table").tBodies[0].lastElementChild?.remove());
$("setups-merge").addEventListener("click", merge);
$("setups-points-file").addEventListener("change", async (ev) => {
  const f = ev.target.files[0];
  if (f) $("setups-points").value = await f.text();
});
$("setups-nodes-file").addEventListener("change", async (ev) => {
  const f = ev.target.files[0];
  if (!f) return;
  showError("setups-points-error", null);
  const form = new FormData();
  form.append("file", f, f.name);
  try {
    const res = await fetch(`/api/setups/${test.id}/nodes`, { method: "POST", body: form });
    const body = await res.json().catch(() => null);
    if (!res.ok) throw new Error((body && body.error) || `${res.status} ${res.statusText}`);
    test = Object.assign(body, { merged: test.merged });
    nodesNote(test);
  } catch (err) {
    showError("setups-points-error", err);
  }
});
$("setups-modes").addEventListener("click", sendMode);
$("setups-freeze").addEventListener("click", freeze);
// A report shows only the frozen result.
function reportOnly(t) {
  $("setups-new").hidden = true;
  $("setups-refs").hidden = true;
  $("setups-title").textContent = `ERA multi-setup test report: ${t.name}`;
}

const opened = location.pathname.match(/^\/s\/([A-Za-z0-9_-]+)(?:\/r\/([A-Za-z0-9_-]+))?$/);
if (window.SETUPS_DATA) {  // the downloaded report (app/setups_offline.py): the document is in the page
  show(window.SETUPS_DATA);
  reportOnly(window.SETUPS_DATA);
} else if (opened) reopen(opened[1], opened[2]);

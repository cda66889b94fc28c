// Panel 1: drop files (-> the import step, import.js), examples, the dataset summary and the records.
import { api } from "./api.js";
import * as importer from "./import.js";
import { state, emit, on, el, showError, plotConfig, plain } from "./state.js";

const $ = (id) => document.getElementById(id);

function setStatus(text) { $("data-status").textContent = text; }

async function loadDataset(promise, label) {
  showError("data-error", null);
  $("import").hidden = true;
  setStatus(label);
  try {
    const ds = await promise;
    state.dataset = ds;
    setStatus("");
    emit("dataset", ds);
  } catch (err) {
    setStatus("");
    showError("data-error", err);
  } finally {
    $("upload-progress").hidden = true;
  }
}

function renderSummary(ds) {
  const dl = $("summary");
  dl.replaceChildren();
  const u = ds.output_units;
  const units = !u ? "not given" : u.every((x) => x === u[0]) ? `${u[0]} (every output)` : u.join(", ");
  const rows = [
    ["Name", ds.name], ["Outputs (p)", `${ds.n_outputs}: ${ds.outputs.join(", ")}`],
    ["Inputs (m)", `${ds.n_inputs}: ${ds.inputs.join(", ")}`], ["Δt", `${window.EraFormat.step(ds.dt)}, Nyquist ${Number(ds.nyquist_hz.toPrecision(6))} Hz`],
    ["Length", `${ds.n_samples} samples, ${ds.duration_s.toFixed(3)} s`], ["Units", units],
    ["Geometry", ds.geometry ? `${ds.geometry.n_nodes} nodes, ${ds.geometry.n_edges} lines (${ds.geometry.units})` : "none"],
  ];
  const src = ds.source || {};
  if (src.format) rows.push(["Read as", `${src.format.toUpperCase()}${src.kind ? `, ${src.kind}` : ""}` +
                                          (src.records ? `: ${src.records.join("; ")}` : "")]);
  if (src.conversions && src.conversions.length) rows.push(["Converted", src.conversions.join("; ")]);
  const said = window.EraFormat.importChoices(src);
  if (said) rows.push(["Import choices", said]);
  for (const [k, v] of rows) dl.append(el("dt", { text: k }), el("dd", { text: v }));
  dl.hidden = false;
}

async function plotRecords(input) {
  const ds = state.dataset;
  const rec = await api(`/api/datasets/${ds.id}/records?input=${input}`);
  const traces = rec.series.map((y, i) => ({ x: rec.time_s, y, name: plain(rec.outputs[i]), type: "scatter", mode: "lines",
                                             line: { width: 1 } }));
  Plotly.react("records-plot", traces, {
    margin: { l: 55, r: 10, t: 10, b: 30 }, xaxis: { title: { text: "time (s)", standoff: 4 } },
    yaxis: { title: { text: plain(ds.output_units ? ds.output_units[0] : "response") } },
    legend: { orientation: "h", y: -0.25 }, showlegend: rec.series.length <= 12,
  }, plotConfig);
}

export function init() {
  const drop = $("drop");
  drop.addEventListener("dragover", (e) => { e.preventDefault(); drop.classList.add("over"); });
  drop.addEventListener("dragleave", () => drop.classList.remove("over"));
  drop.addEventListener("drop", (e) => {
    e.preventDefault();
    drop.classList.remove("over");
    if (e.dataTransfer.files.length) importer.start([...e.dataTransfer.files], setStatus);
  });
  $("file").addEventListener("change", (e) => {
    if (e.target.files.length) importer.start([...e.target.files], setStatus);
    e.target.value = "";
  });
  importer.init((ds) => { state.dataset = ds; emit("dataset", ds); });

  api("/api/examples").then((list) => {
    for (const ex of list) {
      $("examples").append(el("button", {
        class: "secondary", type: "button", title: ex.description, "data-example": ex.name, text: ex.title,
        onclick: () => loadDataset(api(`/api/examples/${ex.name}`, { method: "POST", progress: setStatus }),
                                   `Loading ${ex.title}…`),
      }));
    }
  }).catch((err) => showError("data-error", err));

  $("records-input").addEventListener("change", (e) => plotRecords(Number(e.target.value)));
  on("dataset", (ds) => {
    renderSummary(ds);
    const sel = $("records-input");
    sel.replaceChildren(...ds.inputs.map((name, j) => el("option", { value: j, text: name })));
    plotRecords(0).catch((err) => showError("data-error", err));
  });
}

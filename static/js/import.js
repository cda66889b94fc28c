// The import step: after a drop, what was read (channels, units, nodes, sampling, a plot of every channel) and
// the controls for what the files could not say (sample rate, rows/columns, record kind, start sample, channel
// roles, channels left out, the band of FRFs). Every change reads the staged files again (POST /api/imports/{id}/preview); "Use
// these records" makes the dataset (POST /api/imports/{id}/dataset). A refusal is shown next to its control.
import { api, upload } from "./api.js";
import { el, plotConfig, plain, showError } from "./state.js";

const $ = (id) => document.getElementById(id);
const { counted } = window.EraFormat;

// The option a refusal names -> the element that shows it (next to its control).
const ERROR_BOX = { dt: "import-error-dt", resample: "import-error-resample", orientation: "import-error-orientation", kind: "import-error-kind",
                    start_sample: "import-error-start_sample", variable: "import-error-variable",
                    group: "import-error-group", frf_sign: "import-error-frf_sign", band_hz: "import-error-band_hz",
                    forces: "import-error-channels", references: "import-error-channels",
                    drop: "import-error-channels", points: "import-error-channels" };
const ROLES = { response: "response", force: "force (excitation, input)", reference: "NExT reference response",
                drop: "left out" };

let current = null;        // the last answer of /api/imports (id, files, preview, error, option)
let roles = [];            // role of each channel as read: response | force | reference | drop
let points = [];           // the point each time channel is at, as typed ("4X": node 4 along X), "" unknown
let fileForces = "";       // the channels the files themselves mark as forces (units N, names), as "0,3"
let fileRate = false;      // the files carry their own sampling interval
let onDataset = null;      // callback(dataset summary)
let rereading = null;      // debounce timer
let generation = 0;        // answers to older previews are ignored
let bandProposed = false;  // the setup's band (fMin, fMax) was put in the band fields for this upload

function clearErrors() {
  for (const id of new Set(Object.values(ERROR_BOX))) showError(id, null);
  for (const label of document.querySelectorAll("#import label.field.problem")) label.classList.remove("problem");
  showError("import-error", null);
}

// Show a refusal next to the control that fixes it (or below the panel when no control does).
function showProblem(message, option) {
  const box = ERROR_BOX[option];
  if (!box) { showError("import-error", new Error(message)); return; }
  showError(box, new Error(message));
  const label = $(box).closest("label.field");
  if (label) {
    label.classList.add("problem");
    const input = label.querySelector("input, select");
    if (input && document.activeElement !== input) input.focus({ preventScroll: true });
  }
}

// The options of the form, as POST /api/imports/{id}/preview and /dataset take them (schemas.ImportOptions).
export function options() {
  const o = { kind: $("kind").value };
  const rate = parseFloat($("import-rate").value);
  if (!fileRate && rate > 0) o.dt = 1 / rate;
  if (!$("field-resample").hidden && $("import-resample").checked) o.resample = true;  // never without the person
  if ($("import-orientation").value) o.orientation = $("import-orientation").value;
  const start = parseInt($("import-start").value, 10);
  if (start > 0) o.start_sample = start;
  if (!$("field-variable").hidden && $("import-variable").value.trim()) o.variable = $("import-variable").value.trim();
  if (!$("field-group").hidden && $("import-group").value.trim()) o.group = $("import-group").value.trim();
  if (!$("field-frf-sign").hidden && $("import-frf-sign").value !== "auto") o.frf_sign = $("import-frf-sign").value;
  const low = parseFloat($("import-band-low").value), high = parseFloat($("import-band-high").value);
  if (!$("field-band").hidden && low >= 0 && high > 0) o.band_hz = [low, high];  // FRFs: the band they are valid in
  const pick = (role) => roles.flatMap((r, i) => (r === role ? [i] : []));
  if (pick("drop").length) o.drop = pick("drop");
  const pv = current && current.preview;
  if (pv && pv.domain === "time" && pick("force").join() !== fileForces) o.forces = pick("force");  // changed marks
  if (pick("reference").length) o.references = pick("reference");
  const placed = points.flatMap((p, i) => (p && roles[i] !== "drop" ? [[String(i), p]] : []));
  if (pv && pv.domain === "time" && placed.length) o.points = Object.fromEntries(placed);  // the shape at these points
  return o;
}

function renderChannels(pv) {
  const body = $("import-channels").tBodies[0];
  const kind = $("kind").value === "auto" ? pv.kind : $("kind").value;
  const allowed = pv.domain !== "time" ? ["response", "drop"]
    : ["response", "force", ...(kind === "ambient" ? ["reference"] : []), "drop"];
  body.replaceChildren(...pv.channels.map((c) => {
    if (!allowed.includes(roles[c.index])) roles[c.index] = "response";
    const select = el("select", { "data-channel": c.index, "aria-label": `role of ${c.name}`,
                                  onchange: (e) => { roles[c.index] = e.target.value; reread(); } },
                      ...allowed.map((r) => el("option", { value: r, text: ROLES[r], selected: r === roles[c.index] })));
    // time channels: the point the person types (a force's: where it was struck); FRFs' come from the file
    const point = pv.domain !== "time" ? el("td", { text: "–" }) : el("td", {}, el("input", {
      class: "point", size: 6, "data-channel": c.index, value: points[c.index] || "", placeholder: "e.g. 4X",
      "aria-label": `point of ${c.name}`, onchange: (e) => { points[c.index] = e.target.value.trim(); } }));
    return el("tr", { class: roles[c.index] === "drop" ? "dropped" : null, "data-channel": c.index },
              el("td", { text: String(c.index) }), el("td", { text: c.name }), el("td", { text: c.unit || "–" }),
              el("td", { text: c.node === null ? "–" : String(c.node) }),
              el("td", { text: c.direction || "–" }), el("td", {}, select), point);
  }));
}

// A record kind in the words of the "The records are" control ("io" -> "input and output time histories").
function kindWords(kind) {
  const option = [...$("kind").options].find((o) => o.value === kind);
  return `“${option ? option.text : kind}”`;
}

function renderRead(answer) {
  const pv = answer.preview;
  const n = answer.files.length;
  $("import-files").textContent = `${n > 1 ? `${n} files: ` : ""}${answer.files.join(", ")} · ` +
    `${(answer.bytes / 1e6).toFixed(2)} MB`;
  if (!pv) {
    $("import-read").textContent = "";
    $("import-channels").tBodies[0].replaceChildren();
    Plotly.purge("import-plot");
    return;
  }
  const timeLike = pv.domain !== "frequency";
  fileRate = pv.dt !== null && !("dt" in answer.options) && timeLike;
  const rate = $("import-rate");
  rate.disabled = fileRate || !timeLike;
  if (fileRate) rate.value = String(Number(pv.sample_rate_hz.toPrecision(6)));
  rate.title = fileRate ? "read from the file" : timeLike ? "the files carry no sampling interval: give it" : "FRFs";
  $("field-orientation").hidden = !["csv", "text", "npy", "mat", "hdf5"].includes(pv.format);
  $("field-variable").hidden = !["mat", "hdf5"].includes(pv.format) && answer.option !== "variable";
  $("field-group").hidden = pv.format !== "tdms";
  // only for a clock that needs it (or once ticked): the refusal names it, the person decides
  $("field-resample").hidden = answer.option !== "resample" && !("resample" in answer.options);
  $("field-frf-sign").hidden = pv.domain !== "frequency";
  $("field-band").hidden = pv.domain !== "frequency";
  if (pv.proposed_band_hz && !bandProposed && !$("import-band-low").value && !$("import-band-high").value) {
    [$("import-band-low").value, $("import-band-high").value] = pv.proposed_band_hz.map(String);  // setup.csv's fMin, fMax
    bandProposed = true;  // once per upload: a band the person cleared stays cleared
  }
  $("import-start").disabled = pv.domain === "frequency";
  // one sentence: what the reader found (its counts, step and where it came from; the person's choices), then how
  // the records will be read; the counts are the reader's, not said a second time here
  const read = pv.described.join("; ");
  const nodes = pv.geometry_nodes && !read.includes(`${pv.geometry_nodes} node`)
    ? `; geometry of ${counted(pv.geometry_nodes, "node")}` : "";
  $("import-read").textContent = `${read}${nodes}; read as ${kindWords(pv.kind)} unless you say otherwise.`;
  renderChannels(pv);
  const traces = pv.traces.map((y, i) => ({
    x: pv.x, y, name: plain(pv.channels[i].name), type: "scatter", mode: "lines",
    line: { width: 1, dash: roles[i] === "drop" ? "dot" : "solid" }, opacity: roles[i] === "drop" ? 0.35 : 1,
  }));
  const start = parseInt($("import-start").value, 10) || 0;
  const shapes = start > 0 && timeLike ? [{ type: "line", xref: "x", yref: "paper", y0: 0, y1: 1,
                                          x0: pv.start, x1: pv.start, line: { color: "#b3261e", width: 2 } }] : [];
  Plotly.react("import-plot", traces, {
    margin: { l: 55, r: 10, t: 10, b: 30 }, xaxis: { title: { text: pv.x_label, standoff: 4 } },
    yaxis: { type: timeLike ? "linear" : "log" }, shapes, legend: { orientation: "h", y: -0.25 },
    showlegend: pv.traces.length <= 12,
  }, plotConfig);
}

function show(answer) {
  current = answer;
  const pv = answer.preview;
  if (pv && roles.length !== pv.channels.length) {  // the first reading (no options yet): the files' own marks
    roles = pv.channels.map((c) => (c.dropped ? "drop" : c.force ? "force" : "response"));
    fileForces = pv.channels.filter((c) => c.force).map((c) => c.index).join();
  }
  clearErrors();
  $("import").hidden = false;  // shown before the plot is drawn: a hidden box gives Plotly no width (it took 700 px)
  renderRead(answer);
  if (answer.error) showProblem(answer.error, answer.option);
  $("import-use").disabled = !!answer.error || !pv;
}

function setStatus(text) { $("import-status").textContent = text; }

// Read the staged files again with the form's options (debounced: typing a rate is one request).
function reread() {
  clearTimeout(rereading);
  $("import-use").disabled = true;
  rereading = setTimeout(async () => {
    if (!current) return;
    const mine = ++generation;
    setStatus("Reading again…");
    try {
      const answer = await api(`/api/imports/${current.id}/preview`, { method: "POST", body: options(),
                                                                        progress: setStatus });
      if (mine === generation) show(answer);
    } catch (err) {
      if (mine === generation) { clearErrors(); showProblem(err.message, err.option); }
    } finally {
      if (mine === generation) setStatus("");
    }
  }, 350);
}

// Upload dropped files (one dataset) and show what was read.
export async function start(files, setDataStatus) {
  const bar = $("upload-progress");
  const label = files.length === 1 ? files[0].name : `${files.length} files`;
  bar.hidden = false;
  bar.value = 0;
  showError("data-error", null);
  roles = [];
  points = [];
  $("import-rate").value = "";
  $("import-orientation").value = "";
  $("import-resample").checked = false;
  $("field-resample").hidden = true;
  $("import-start").value = "0";
  $("import-variable").value = "";
  $("import-group").value = "";
  $("import-frf-sign").value = "auto";
  $("import-band-low").value = "";
  $("import-band-high").value = "";
  bandProposed = false;
  try {
    const answer = await upload("/api/imports", files, (f) => {
      bar.value = f;
      setDataStatus(f < 1 ? `Uploading ${label}: ${Math.round(100 * f)} %` : `Reading ${label}…`);
    }, setDataStatus);
    setDataStatus("");
    show(answer);
  } catch (err) {
    setDataStatus("");
    showError("data-error", err);
  } finally {
    bar.hidden = true;
  }
}

async function use() {
  if (!current) return;
  clearErrors();
  $("import-use").disabled = true;
  setStatus("Making the dataset…");
  try {
    const ds = await api(`/api/imports/${current.id}/dataset`, { method: "POST", body: options(),
                                                                  progress: setStatus });
    current = null;
    $("import").hidden = true;
    onDataset(ds);
  } catch (err) {
    showProblem(err.message, err.option);
    $("import-use").disabled = false;
  } finally {
    setStatus("");
  }
}

export function init(datasetReady) {
  onDataset = datasetReady;
  for (const id of ["import-rate", "import-start", "import-variable", "import-group"]) $(id).addEventListener("input", reread);
  for (const id of ["import-orientation", "kind", "import-frf-sign", "import-resample"]) $(id).addEventListener("change", reread);
  $("import-use").addEventListener("click", use);
  $("import-cancel").addEventListener("click", () => { current = null; $("import").hidden = true; clearErrors(); });
}

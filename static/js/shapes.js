// Panel 6: the selected mode shape: animated in the viser viewer (iframe) when the server has it, and its
// components per channel in a bar chart.
import { api } from "./api.js";
import { state, on, el, plotConfig, plain } from "./state.js";

const $ = (id) => document.getElementById(id);
let viewer = null;          // {key, url, mode_url, order} of the published modes, or null
let viewerAvailable = true; // false after the server said it has no viewer
let publishing = null;
let settle = null;

async function publish() {
  if (!viewerAvailable || !state.analysis) return null;
  const order = state.order, id = state.analysis.id;
  if (viewer && viewer.order === order && viewer.analysis === id) return viewer;
  try {
    const v = await api(`/api/analyses/${id}/viewer`, { method: "POST", body: { order } });
    viewer = { ...v, order, analysis: id };
    const frame = el("iframe", { class: "viewer", src: v.url, title: "mode shape viewer" });
    $("viewer-box").replaceChildren(frame);
    return viewer;
  } catch (err) {
    viewerAvailable = false;
    $("viewer-box").replaceChildren(el("div", { class: "note", text: `3-D viewer: ${err.message}` }));
    return null;
  }
}

async function showMode() {
  const k = state.selected, m = state.modes;
  if (k === null || !m) return;
  $("shape-title").textContent = `mode ${k + 1}: ${m.frequency_hz[k].toFixed(4)} Hz, ζ ${(100 * m.damping_ratio[k]).toFixed(3)} %`;
  // the shape at every measured or struck point (a roving hammer's hit points too), else at the sensors
  const atPoints = m.points && m.points.length && m.point_shapes_re && m.point_shapes_re.length === m.n_modes;
  const re = atPoints ? m.point_shapes_re[k] : m.shapes_re[k], im = atPoints ? m.point_shapes_im[k] : m.shapes_im[k];
  const where = (atPoints ? m.points : m.outputs).map(plain);
  Plotly.react("shape-plot", [
    { x: where, y: re, name: "real", type: "bar", marker: { color: "#1f5fbf" } },
    { x: where, y: im, name: "imaginary", type: "bar", marker: { color: "#e4572e" } },
  // the legend above the plot area, in a top margin of its own: inside the 10 px margin its white box covered the
  // top of the bars next to it (a bar of 1 drawn notched, as if 0.97)
  ], { margin: { l: 45, r: 10, t: 30, b: 60 }, barmode: "group", yaxis: { title: { text: "shape (largest = 1)" } },
       legend: { orientation: "h", x: 0, y: 1, yanchor: "bottom", bgcolor: "rgba(0,0,0,0)" } }, plotConfig);
  // Publishing loads a new viewer page; wait until the order slider has settled so dragging stays fast.
  clearTimeout(settle);
  settle = setTimeout(async () => {
    publishing = publishing || publish().finally(() => { publishing = null; });
    const v = await publishing;
    if (v && v.order === state.order && state.selected !== null) await sendMode(v);
  }, viewer && viewer.order === state.order ? 0 : 500);
}

async function sendMode(v) {
  try {
    await api(v.mode_url, { method: "POST", body: { index: state.selected, amplitude: Number($("shape-amplitude").value),
                                                    speed: Number($("shape-speed").value) } });
  } catch (err) { $("viewer-note")?.replaceChildren(err.message); }
}

export function init() {
  on("select", showMode);
  on("modes", () => { if (state.selected !== null) showMode(); });
  for (const id of ["shape-amplitude", "shape-speed"]) {
    $(id).addEventListener("change", () => { if (viewer && state.selected !== null) sendMode(viewer); });
  }
}

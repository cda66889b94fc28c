// The engineer's own FE model in the Model panel (a Nastran deck or a .zip of matrices): the table matching each
// output of the test to a model node and direction, editable (PUT /api/datasets/{id}/model/mapping), and the
// outputs that match no free DOF of the model, said in one sentence above it.
import { api } from "./api.js";
import { el, showError } from "./state.js";

const $ = (id) => document.getElementById(id);
const DIRECTIONS = ["x", "y", "z", "rx", "ry", "rz", "-x", "-y", "-z", "-rx", "-ry", "-rz"];

// The summary's rows for an FE model (schemas.StructureModel with source "fe").
export function feRows(summary) {
  const rows = [["Model", `your FE model, from the file ${summary.name}`], ["Structure", summary.text],
    ["Model's lowest modes (Hz)", summary.frequency_hz.filter((f) => f !== null && f > 1e-6).map((f) => f.toPrecision(4)).join(", ")]];
  const mass = summary.total_mass ?? summary.total_mass_kg;
  if (mass !== null && mass !== undefined) {
    // in the model's own unit, and in kg where that unit is known and is not kg already
    const kg = summary.mass_unit && summary.mass_unit !== "kg" ? ` = ${summary.total_mass_kg.toPrecision(4)} kg` : "";
    const text = summary.mass_unit ? `${mass.toPrecision(4)} ${summary.mass_unit}${kg}` : `${mass.toPrecision(4)} in the model's own mass unit`;
    rows.push(["Mass", summary.mass_unit_note ? `${text} (${summary.mass_unit_note})` : text]);
  }
  for (const note of summary.notes || []) rows.push(["Read", note]);
  return rows;
}

// The mapping table of ``summary`` (hidden for a model that has none); ``url`` the dataset's model URL;
// ``done(summary)`` shows the model saved with the new mapping.
export function drawMapping(summary, url, done) {
  const box = $("model-mapping");
  box.hidden = !(summary && summary.source === "fe" && summary.mapping);
  if (box.hidden) return;
  showError("model-mapping-error", null);
  $("model-unmatched").textContent = summary.unmatched
    || `Every output is matched to a model node and direction (${summary.mapping.length} in all): simulation vs test compares there.`;
  const body = $("model-mapping-table").querySelector("tbody");
  body.replaceChildren();
  summary.mapping.forEach((m, k) => {
    const node = el("input", { type: "text", value: m.node || "", size: 8, id: `model-map-node-${k}`, "aria-label": `model node of output ${m.output}` });
    const dir = el("select", { id: `model-map-dir-${k}`, "aria-label": `direction of output ${m.output}` });
    dir.append(el("option", { value: "", text: "–" }));
    for (const d of DIRECTIONS) dir.append(el("option", { value: d, text: d }));
    dir.value = m.direction || "";
    const row = el("tr", m.matched ? {} : { class: "unmatched", style: "background:#fff3e0" },
      el("td", { text: m.output }), el("td", { text: m.point || "–" }), el("td", {}, node), el("td", {}, dir));
    body.append(row);
  });
  $("model-mapping-save").onclick = async () => {
    showError("model-mapping-error", null);
    const sensors = summary.mapping.map((_, k) => {
      const n = $(`model-map-node-${k}`).value.trim(), d = $(`model-map-dir-${k}`).value;
      return n && d ? [n, d] : null;
    });
    $("model-mapping-save").disabled = true;
    $("model-mapping-status").textContent = "Checking the mapping…";
    try {
      const r = await api(`${url}/mapping`, { method: "PUT", body: { sensors } });
      $("model-mapping-status").textContent = "Mapping saved: simulation vs test compares at these nodes.";
      done(r);
    } catch (err) {
      $("model-mapping-status").textContent = "";
      showError("model-mapping-error", err);
    } finally {
      $("model-mapping-save").disabled = false;
    }
  };
}

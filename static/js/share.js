// Panel 7: freeze the analysis into a report link; downloads of the report (HTML), and the modes (CSV, UFF 55).
import { api } from "./api.js";
import { state, on, showError } from "./state.js";

const $ = (id) => document.getElementById(id);

async function createReport() {
  showError("share-error", null);
  $("create-report").disabled = true;
  $("share-status").textContent = "Freezing the analysis…";
  try {
    const kept = [...state.kept].sort((a, b) => a - b);
    const r = await api("/api/reports", { method: "POST", body: { analysis_id: state.analysis.id, order: state.order, modes: kept },
                                          progress: (text) => { $("share-status").textContent = text; } });
    const url = new URL(r.url, location.href).href;
    $("report-link").href = r.url;
    $("report-link").textContent = url;
    $("report-link-box").hidden = false;
    $("dl-html").href = `/api/reports/${r.token}/report.html`;
    $("dl-csv").href = `/api/reports/${r.token}/modes.csv`;
    $("dl-uff").href = `/api/reports/${r.token}/modes.uff`;
    $("downloads").hidden = false;
    $("share-status").textContent = `Saved: order ${state.order}, ${kept.length} kept modes.`;
  } catch (err) {
    $("share-status").textContent = "";
    showError("share-error", err);
  } finally {
    $("create-report").disabled = false;
  }
}

export function init() {
  $("create-report").addEventListener("click", createReport);
  on("modes", () => { $("create-report").disabled = false; });
  on("analysis", () => { $("report-link-box").hidden = true; $("downloads").hidden = true; });
}

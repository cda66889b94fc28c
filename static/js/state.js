// The page's shared state and a tiny event bus: panels listen, none reaches into another.
//   dataset  -> summary of the loaded dataset          analysis -> {id, singular_values, ...}
//   order    -> chosen model order                     modes    -> modes at that order (from the API)
//   kept     -> Set of kept mode indices               selected -> selected mode index or null
//   keptBy   -> what ticked them: "choice" (era's automatic choice, at its order), "thresholds" or "hand"
//   choice   -> (event) back to the automatic choice: its order, its modes ticked
export const state = { dataset: null, analysis: null, order: null, modes: null, kept: new Set(), keptBy: null,
                       selected: null, stabilization: null };

const listeners = {};
export function on(event, fn) { (listeners[event] ||= []).push(fn); }
export function emit(event, detail) { for (const fn of listeners[event] || []) fn(detail); }

export function el(tag, attrs = {}, ...children) {
  const node = document.createElement(tag);
  for (const [k, v] of Object.entries(attrs)) {
    if (k === "text") node.textContent = v;  // text only: names from files never become HTML
    else if (k.startsWith("on")) node.addEventListener(k.slice(2), v);
    else if (v !== false && v !== null && v !== undefined) node.setAttribute(k, v === true ? "" : v);
  }
  for (const c of children) node.append(c);
  return node;
}

export function showError(id, err) {
  const box = document.getElementById(id);
  if (!err) { box.hidden = true; box.textContent = ""; return; }
  box.hidden = false;
  box.textContent = err.message || String(err);
}

export const plotConfig = { responsive: true, displaylogo: false };

// Plotly reads a few HTML tags and entities in trace names, titles and categories; channel and file names
// must show as typed, so escape them (plotly turns the entities back into the characters).
export function plain(text) {
  return String(text).replace(/&/g, "&amp;").replace(/</g, "&lt;").replace(/>/g, "&gt;");
}

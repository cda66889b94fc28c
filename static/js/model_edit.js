// The Model panel's editing tables (issue 9): the node table (support: free, fixed, pinned or springs kx..rz in
// N/m and N·m/rad; lumped mass in kg) and the member table (group, orientation vector of the section's local z,
// remove; add a member between two nodes). Values go to the server as typed: era.Frame checks them when the
// model is saved, and its refusal comes back with the control that fixes it ("node:7", "member:3",
// "section:col"), shown under that row (placeRefusal). Nothing here checks a value itself.
import { el } from "./state.js";

const SUPPORTS = ["free", "fixed", "pinned", "springs"];
export const SPRINGS = [["kx", "N/m"], ["ky", "N/m"], ["kz", "N/m"], ["rx", "N·m/rad"], ["ry", "N·m/rad"], ["rz", "N·m/rad"]];

// A typed value as era.Frame's file format takes it: a number, "fixed", or (left as typed) text it will refuse.
export function typed(text) {
  const t = String(text).trim();
  if (/^fixed$/i.test(t)) return "fixed";
  const v = Number(t);
  return t !== "" && Number.isFinite(v) ? v : t;
}

// "0, 1, 0" -> [0, 1, 0]; blank -> null (the default orientation); anything else as typed (refused by era.Frame).
export function vector(text) {
  const t = String(text).trim();
  if (!t) return null;
  const parts = t.replace(/^[([]|[)\]]$/g, "").split(/[\s,;]+/).filter(Boolean).map(Number);
  return parts.length === 3 && parts.every(Number.isFinite) ? parts : t;
}

export function head(table, names) {
  const tr = el("tr");
  for (const n of names) tr.append(el("th", { text: n }));
  table.tHead.replaceChildren(tr);
  table.tBodies[0].replaceChildren();
}

export function select(options, value, attrs) {
  const s = el("select", attrs);
  for (const [v, t] of options) s.append(el("option", { value: v, text: t }));
  s.value = value;
  return s;
}

export function supportOf(desc, n) {
  const s = desc.supports[n];
  return s === undefined ? "free" : typeof s === "string" ? s : "springs";
}

// The node table. changed(): a support or mass changed (redraw the drawing); picked(n): a row was chosen.
export function drawNodes(table, desc, draft, changed, picked) {
  head(table, ["node", "x, y, z (m)", "support", "springs to ground", "mass (kg)", "sensors"]);
  const sensors = {};
  draft.sensors.forEach(([n, d], i) => { (sensors[n] ||= []).push(`${draft.outputs[i]} (${Array.isArray(d) ? "oblique" : d})`); });
  for (const [n, xyz] of Object.entries(draft.nodes)) {
    const sup = select(SUPPORTS.map((s) => [s, s]), supportOf(desc, n), { class: "support", "aria-label": `support at node ${n}` });
    const springs = el("span", { class: "springs" });
    const drawSprings = () => {
      const s = desc.supports[n];
      springs.hidden = !(s && typeof s === "object");
      if (springs.hidden) return springs.replaceChildren();
      springs.replaceChildren(...SPRINGS.map(([k, unit]) => {
        const input = el("input", { type: "text", inputmode: "decimal", "data-spring": k, value: s[k] === undefined ? "" : String(s[k]),
                                    "aria-label": `${k} at node ${n} (${unit})`, title: `${k} in ${unit}: a stiffness ≥ 0, or "fixed"; blank: free`,
                                    placeholder: k, style: "width:64px" });
        input.addEventListener("change", () => {
          const v = typed(input.value);
          if (v === "") delete s[k]; else s[k] = v;
          changed();
        });
        return input;
      }));
    };
    sup.addEventListener("change", () => {
      if (sup.value === "free") delete desc.supports[n];
      else if (sup.value === "springs") desc.supports[n] = typeof desc.supports[n] === "object" ? desc.supports[n] : {};
      else desc.supports[n] = sup.value;
      drawSprings();
      changed();
    });
    drawSprings();
    const mass = el("input", { type: "number", min: "0", step: "any", class: "mass", "aria-label": `mass at node ${n} (kg)`,
                               value: desc.masses[n] ? String(desc.masses[n]) : "", style: "width:80px" });
    mass.addEventListener("change", () => { desc.masses[n] = mass.value === "" ? 0 : typed(mass.value); changed(); });
    const tr = el("tr", { "data-node": n });
    tr.append(el("td", { text: n }), el("td", { text: xyz.map((v) => v.toFixed(3)).join(", ") }), el("td", {}, sup),
              el("td", {}, springs), el("td", {}, mass), el("td", { text: (sensors[n] || []).join(", ") }));
    tr.addEventListener("click", (ev) => { if (ev.target === tr || ev.target.tagName === "TD") picked(n); });
    table.tBodies[0].append(tr);
  }
}

// The member table and the row that adds one. changed(groupsToo): the members changed (redraw the drawing, and the
// section table when groups may have).
export function drawMembers(table, desc, draft, changed, newSection) {
  head(table, ["member", "group (type a new name to make a group)", "orientation: local z (x, y, z)", ""]);
  desc.members.forEach((m, k) => {
    const group = el("input", { value: m[2], class: "group", "aria-label": `group of member ${m[0]}-${m[1]}`, style: "width:120px" });
    group.addEventListener("change", () => {
      const g = group.value.trim();
      if (!g) { group.value = m[2]; return; }
      m[2] = g;
      desc.sections[g] ||= newSection();
      changed(true);
    });
    const o = m[3];
    const orient = el("input", { value: o == null ? "" : Array.isArray(o) ? o.join(", ") : String(o), class: "orientation",
                                 placeholder: "default", style: "width:100px", "aria-label": `orientation of member ${m[0]}-${m[1]}`,
                                 title: "the vector the section's local z (a rectangle's depth) turns towards, e.g. 0, 1, 0; blank: +Z (+X for a vertical member)" });
    orient.addEventListener("change", () => {
      const v = vector(orient.value);
      if (v === null) m.length = 3; else m[3] = v;
      changed(false);
    });
    const remove = el("button", { class: "secondary remove", text: "✕", title: `remove member ${m[0]}–${m[1]}`, "aria-label": `remove member ${m[0]}-${m[1]}` });
    remove.addEventListener("click", () => { desc.members.splice(k, 1); changed(true); });
    const tr = el("tr", { "data-member": String(k) });
    tr.append(el("td", { text: `${m[0]} – ${m[1]}` }), el("td", {}, group), el("td", {}, orient), el("td", {}, remove));
    table.tBodies[0].append(tr);
  });
}

// The controls that add a member between two of the geometry's nodes (in box).
export function drawAdd(box, desc, draft, changed, newSection) {
  const ids = Object.keys(draft.nodes).map((n) => [n, n]);
  const groups = [...new Set(desc.members.map((m) => m[2]))];
  const i = select(ids, ids[0][0], { id: "model-add-i", "aria-label": "new member from node" });
  const j = select(ids, ids[Math.min(1, ids.length - 1)][0], { id: "model-add-j", "aria-label": "new member to node" });
  const g = el("input", { id: "model-add-group", value: groups[0] || "members", list: "model-groups", style: "width:120px",
                          "aria-label": "group of the new member" });
  const list = el("datalist", { id: "model-groups" }, ...groups.map((x) => el("option", { value: x })));
  const add = el("button", { id: "model-add-member", class: "secondary", text: "Add member" });
  add.addEventListener("click", () => {
    const group = g.value.trim() || groups[0] || "members";
    desc.members.push([i.value, j.value, group]);
    desc.sections[group] ||= newSection();
    changed(true);
  });
  box.replaceChildren(el("span", { class: "note", text: "Add a member from node " }), i, el("span", { class: "note", text: " to " }), j,
                      el("span", { class: "note", text: " in group " }), g, list, add);
}

// The nodes the model sends: those members join, and any other that carries a support, a mass or a sensor (then
// era.Frame says it is on no member, next to its row). A node left without members is dropped.
export function usedNodes(desc, draft) {
  const keep = new Set(desc.members.flatMap((m) => [m[0], m[1]]));
  for (const n of Object.keys(desc.supports)) keep.add(n);
  for (const [n, kg] of Object.entries(desc.masses)) if (kg) keep.add(n);
  for (const [n] of draft.sensors) keep.add(n);
  return Object.fromEntries(Object.entries(draft.nodes).filter(([n]) => keep.has(n)));
}

// A refusal under the row of the control it names (err.option "node:7", "member:3", "section:col"); false when
// it names none shown here (the caller shows it in the panel's error box).
export function placeRefusal(err) {
  clearRefusals();
  const opt = (err && err.option) || "";
  const cut = opt.indexOf(":");
  if (cut < 0) return false;
  const [kind, what] = [opt.slice(0, cut), opt.slice(cut + 1)];
  const where = { node: ["model-nodes", "node"], member: ["model-members", "member"], section: ["model-sections", "group"] }[kind];
  if (!where) return false;
  const row = document.querySelector(`#${where[0]} tr[data-${where[1]}="${CSS.escape(what)}"]`);
  if (!row) return false;
  row.classList.add("refused");
  const cell = el("td", { colspan: String(row.children.length) }, el("div", { class: "error", text: err.message }));
  row.after(el("tr", { class: "refusal" }, cell));
  row.scrollIntoView({ block: "nearest" });
  return true;
}

export function clearRefusals() {
  for (const r of document.querySelectorAll("#model-editor tr.refusal")) r.remove();
  for (const r of document.querySelectorAll("#model-editor tr.refused")) r.classList.remove("refused");
}

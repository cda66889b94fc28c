// The model being described, in the 3-D viewer (viser; app/viewer/picking.py): every node a sphere, coloured by
// its support or mass; clicking one there acts as a click on it in the Model panel's drawing. The page polls the
// clicks (GET /viser/{key}/picks), turns the view to the node chosen in the table (look) and recolours the nodes
// when a support or mass changes (mark).
import { api } from "./api.js";
import { el } from "./state.js";

const POLL_MS = 400;

export class View3D {
  // url(): POST address that publishes the scene; scene(): {nodes, members, marks}; picked(node): a click there.
  constructor({ url, scene, picked }) {
    Object.assign(this, { url, scene, picked });
    this.link = null;     // schemas.ModelViewLink while open
    this.box = null;
    this.seen = 0;
    this.timer = null;
    this.marking = null;
  }

  async open(box) {
    this.close();
    this.box = box;
    box.hidden = false;
    box.replaceChildren(el("div", { class: "note", text: "Opening the 3-D view…" }));
    try {
      const link = await api(this.url(), { method: "POST", body: this.scene() });
      if (this.box !== box) return;     // closed meanwhile
      this.link = link;
      this.seen = 0;
      const frame = el("iframe", { class: "viewer", id: "model-3d-frame", src: link.url, title: "the model in 3-D: click a node",
                                   style: "width:100%;height:420px" });
      box.replaceChildren(el("div", { class: "note", text: "Click a node here: it does what “Clicking a node” says, as in the drawing. Choosing a row in the node table turns this view to it." }), frame);
      this.poll();
    } catch (err) {
      box.replaceChildren(el("div", { class: "error", text: `3-D view: ${err.message}` }));
    }
  }

  close() {
    clearTimeout(this.timer);
    this.timer = null;
    this.link = null;
    if (this.box) { this.box.replaceChildren(); this.box.hidden = true; }
    this.box = null;
  }

  // Members added or removed: the view is published again (a new key).
  republish() { if (this.link && this.box) this.open(this.box); }

  async poll() {
    const link = this.link;
    if (!link) return;
    try {
      const r = await api(`${link.picks_url}?after=${this.seen}`);
      if (this.link !== link) return;
      for (const p of r.picks) { this.seen = Math.max(this.seen, p.seq); this.picked(p.node); }
    } catch { /* a 404 after a restart: the next open publishes again */ }
    if (this.link === link) this.timer = setTimeout(() => this.poll(), POLL_MS);
  }

  look(node) {
    if (this.link) api(this.link.look_url, { method: "POST", body: { node } }).catch(() => {});
  }

  mark(marks) {
    if (!this.link) return;
    clearTimeout(this.marking);
    const link = this.link;
    this.marking = setTimeout(() => api(link.marks_url, { method: "POST", body: { marks } }).catch(() => {}), 150);
  }
}

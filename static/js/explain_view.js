/* Draws a simulation-vs-test result (era.explain's summary): verdict, named effect, gap before/after, ranking,
   per-mode table, MAC matrices, response overlay and measured vs model shapes. Shared by the analysis page's panel
   (explain.js) and the read-only report (a classic script with no imports: the report download inlines it).
   Every name from a file is set with textContent; plotly gets it through plain(). */
(function () {
  "use strict";
  const cfg = { responsive: true, displaylogo: false };
  const plain = (t) => String(t).replace(/&/g, "&amp;").replace(/</g, "&lt;").replace(/>/g, "&gt;");
  const num = (v, d) => (v === null || v === undefined || !isFinite(v)) ? "–" : Number(v).toFixed(d);
  const signed = (v, d) => (v === null || v === undefined || !isFinite(v)) ? "–" : (v >= 0 ? "+" : "") + Number(v).toFixed(d);
  const VERDICT = {
    explained: ["Explained", "#e6f4ea", "#1e7b34"],
    no_significant_discrepancy: ["No significant discrepancy", "#eef4ff", "#1f5fbf"],
    ambiguous: ["Ambiguous", "#fff6e0", "#9a6700"],
    unexplained: ["Unexplained", "#fdecea", "#b3261e"],
  };
  // Units and plain words for the fitted parameters (keywords of era.grid.nasa_grid).
  const PARAM = {
    stiffness_factor: ["global stiffness factor", ""], joint_stiffness: ["joint stiffness", "N·m/rad"],
    torsion_factor: ["torsion (GJ) factor", ""], cable_length_m: ["cable length", "m"],
    distributed_mass_kg: ["distributed mass", "kg"], point_mass_kg: ["point mass", "kg"],
    loose_joint_stiffness: ["loose-joint stiffness", "N·m/rad"], gravity: ["gravity stiffening fraction", ""],
    member_factor: ["member stiffness factor", ""], support_rotation_stiffness: ["support rotational stiffness", "N·m/rad"],
    support_vertical_stiffness: ["support vertical stiffness", "N/m"],
  };
  function el(tag, text, attrs) {
    const n = document.createElement(tag);
    if (text !== undefined && text !== null) n.textContent = text;  // text only, never HTML
    for (const [k, v] of Object.entries(attrs || {})) n.setAttribute(k, v);
    return n;
  }

  function table(id, headers, rows) {
    const t = el("table", null, { class: "modes", id });
    const tr = el("tr");
    for (const h of headers) tr.append(el("th", h[0], h[1] ? { title: h[1] } : {}));
    t.append(el("thead"), el("tbody"));
    t.tHead.append(tr);
    for (const r of rows) {
      const row = el("tr");
      for (const c of r) row.append(el("td", c));
      t.tBodies[0].append(row);
    }
    return el("div", null, { class: "tablewrap" }).appendChild(t).parentNode;
  }

  // Where a located effect is: a grid joint (x, y) ft, or on a frame a node id or a member (its two end nodes).
  // A place: a grid joint [x, y] ft or member [[x1, y1], [x2, y2]] ft; a frame's node id or member [i, j].
  function where(loc) {
    if (typeof loc === "string") return `node ${loc}`;
    if (Array.isArray(loc) && Array.isArray(loc[0])) return `member (${loc[0][0]}, ${loc[0][1]})–(${loc[1][0]}, ${loc[1][1]}) ft`;
    if (Array.isArray(loc) && typeof loc[0] === "string") return loc[0] === "*" ? "every member" : `member ${loc[0]}–${loc[1]}`;
    return `joint (x = ${loc[0]} ft, y = ${loc[1]} ft)`;
  }

  function value(name, v) {
    const [, unit] = PARAM[name] || [name, ""];
    const digits = Math.abs(v) >= 100 ? 1 : Math.abs(v) >= 10 ? 2 : 4;
    return `${num(v, digits)}${unit ? " " + unit : ""}`;
  }

  // interval: {name: [low, high]} 95 %, null on a side the data do not bound: shown as a bound, not a value
  function paramText(params, unc, interval) {
    return Object.entries(params || {}).map(([k, v]) => {
      const label = (PARAM[k] || [k])[0];
      if (typeof v !== "number") return `${label} = ${Array.isArray(v) ? `(${v.join(", ")})` : String(v)}`;
      const [lo, hi] = (interval || {})[k] || [0, 0];
      if (lo === null && typeof hi === "number") return `${label} ≤ ${value(k, hi)} (95 %; lower values fit as well)`;
      if (hi === null && typeof lo === "number") return `${label} ≥ ${value(k, lo)} (95 %; higher values fit as well)`;
      const u = unc && typeof unc[k] === "number" ? ` ± ${value(k, unc[k])}` : "";
      return `${label} = ${value(k, v)}${u}`;
    }).join("; ");
  }

  // the effect's size: its own parameter with the 95 % interval (a bound when the data close one side only)
  function sizeText(e) {
    const k = e.size_parameter;
    if (!k || !e.parameters || typeof e.parameters[k] !== "number") return "";
    const label = (PARAM[k] || [k])[0];
    const [lo, hi] = e.size_interval || [null, null];
    if (lo === null && typeof hi === "number") return `${label} ≤ ${value(k, hi)} (lower values fit as well)`;
    if (hi === null && typeof lo === "number") return `${label} ≥ ${value(k, lo)} (higher values fit as well)`;
    const range = typeof lo === "number" && typeof hi === "number" ? ` (95 %: ${value(k, lo)} to ${value(k, hi)})` : "";
    return `${label} = ${value(k, e.parameters[k])}${range}`;
  }

  function gapText(g) {
    return g ? `max |Δf| ${num(g.max_abs_freq_error_pct, 2)} %, min MAC ${num(g.min_mac, 3)}` : "–";
  }

  function verdictBox(s, id) {
    const [title, bg, ink] = VERDICT[s.verdict] || [s.verdict, "#f4f6f9", "#1d2330"];
    const box = el("div", null, { id: `${id}-verdict`, "data-verdict": s.verdict,
      style: `background:${bg};border-left:4px solid ${ink};padding:8px 12px;border-radius:5px;margin:6px 0` });
    const head = el("div", null, { style: `font-weight:600;color:${ink};font-size:15px` });
    // several effects (result.effects, most important first); results stored before them carry one
    const effects = (s.effects && s.effects.length) ? s.effects : (s.effect ? [s.effect] : []);
    head.textContent = effects.length ? `${title}: ${effects.map((e) => e.name.replace(/_/g, " ")).join(" + ")}` : title;
    box.append(head, el("div", s.message, { style: "margin-top:4px" }));
    effects.forEach((e, k) => {
      const dl = el("dl", null, { class: "summary", id: k === 0 ? `${id}-effect` : `${id}-effect-${k + 1}` });
      const add = (key, v) => dl.append(el("dt", key), el("dd", v));
      add(effects.length > 1 ? `Effect ${k + 1}` : "Effect", e.name);
      const own = Object.fromEntries(Object.entries(e.parameters || {}).filter(([n]) => n !== "stiffness_factor"));
      const shown = effects.length > 1 && Object.keys(own).length ? own : e.parameters;
      if ((e.places || []).length > 1) {   // places the data cannot tell apart: the set, with the probability of each
        add("Place", `one of these: ${e.places.map(([l, q]) => `${where(l)} ${num(100 * q, 0)} %`).join(", ")}`);
      } else if (e.location) {
        add("Place", where(e.location) +
          (e.location_probability !== null && e.location_probability !== undefined ? `, ${num(100 * e.location_probability, 0)} % certain` : "") +
          ((e.other_locations || []).length ? `; also possible ${e.other_locations.map(([l, q]) => `${where(l)} ${num(100 * q, 0)} %`).join(", ")}` : ""));
      }
      const size = sizeText(e);
      if (size) add("Size (95 % interval)", size);
      add("Parameters (± 1σ)", paramText(shown, e.uncertainty, e.interval));
      add("The data cannot tell", (e.cannot_tell || []).length ? e.cannot_tell.join("; ")
        : "nothing more: one place, a size bounded on both sides, no other candidate left");
      add(k === 0 ? "Posterior probability" : "Posterior probability (given the effects before)", `${num(100 * e.probability, 1)} %`);
      const prev = k === 0 ? s.before : effects[k - 1].gap_after;
      if (e.gap_after) add("Gap before → after", `${gapText(prev)} → ${gapText(e.gap_after)}`);
      box.append(dl);
    });
    if (s.model_form) {   // results stored before it was recorded have none
      const mf = s.model_form;
      box.append(el("div", "Model-form allowance (how far a nominal model may miss the real structure, 1σ): " +
        (mf.frequency || mf.shape ? `${num(100 * mf.frequency, 1)} % on each frequency, ${num(mf.shape, 3)} on each shape component`
          : "none for this model (its error floors were calibrated on its own simulated tests)"),
        { id: `${id}-model-form`, style: "margin-top:4px;color:#4a5160" }));
    }
    if (effects.length > 1 && effects[0].parameters && "stiffness_factor" in effects[0].parameters) {
      box.append(el("div", `Global stiffness factor (nuisance): ${num(effects[0].parameters.stiffness_factor, 3)}`));
    }
    return box;
  }

  function gapTable(s, id) {
    const steps = (s.effects || []).length > 1
      ? s.effects.map((e, k) => [`after step ${k + 1} (+ ${e.name.replace(/_/g, " ")})`, e.gap_after]).filter(([, g]) => g)
      : [["after (updated model)", s.after]];
    const rows = [["before (nominal model)", s.before], ...steps].map(([k, g]) =>
      [k, num(g.max_abs_freq_error_pct, 2), num(g.rms_freq_error_pct, 2), num(g.min_mac, 3), num(g.mean_mac, 3), String(g.n_pairs ?? "–")]);
    return table(`${id}-gap`, [["model"], ["max |Δf| (%)", "largest frequency error over the paired modes"],
      ["rms Δf (%)"], ["min MAC", "worst shape agreement (nearly repeated modes compared as a plane)"], ["mean MAC"],
      ["paired modes"]], rows);
  }

  function rankingTable(s, id) {
    const rows = s.ranking.map((r) => [r.name, `${num(100 * r.probability, 1)} %`, num(r.log_evidence, 1),
      r.name === "none" ? "(reference)" : num(r.log_bayes_factor, 1),
      paramText(r.parameters) + (r.location ? `; at ${where(r.location)}` : ""),
      r.adequate ? "yes" : "no", num(r.max_abs_freq_error_pct, 2), num(r.min_mac, 3)]);
    return table(`${id}-ranking`, [["candidate"], ["posterior", "probability given the data, within this library"],
      ["ln evidence", "Laplace approximation (Beck & Yuen 2004)"], ["ln Bayes factor vs none", "against the nominal model with a global stiffness factor"],
      ["fitted parameters"], ["adequate fit", "fits within the error levels"], ["max |Δf| (%)"], ["min MAC"]], rows);
  }

  function modeTable(s, id) {
    const rows = s.modes.map((m) => [String(m.mode), num(m.measured_hz, 4), num(100 * m.damping_ratio, 2),
      num(m.nominal_hz, 4), signed(m.nominal_error_pct, 2), num(m.nominal_mac, 3),
      num(m.updated_hz, 4), signed(m.updated_error_pct, 2), num(m.updated_mac, 3), m.nearly_repeated ? "yes" : ""]);
    return table(`${id}-modes`, [["#"], ["measured f (Hz)", "identified by ERA"], ["ζ (%)"], ["nominal f (Hz)"],
      ["nominal error (%)", "(model − measured) / measured"], ["nominal MAC"], ["updated f (Hz)"], ["updated error (%)"],
      ["updated MAC"], ["nearly repeated", "close modes: their shapes are compared as a plane"]], rows);
  }

  function macPlots(s, div, which) {
    const mac = which === "before" ? s.mac_before : s.mac_after;
    const fx = which === "before" ? s.model_hz_before : s.model_hz_after;
    Plotly.react(div, [{ type: "heatmap", z: mac, zmin: 0, zmax: 1, colorscale: [[0, "#ffffff"], [0.5, "#9ab8e6"], [1, "#123e85"]], showscale: which === "after",
      x: fx.map((f, j) => `${j + 1}: ${num(f, 3)}`), y: s.measured_hz.map((f, i) => `${i + 1}: ${num(f, 3)}`),
      hovertemplate: "measured %{y} Hz<br>model %{x} Hz<br>MAC %{z:.3f}<extra></extra>" }],
      { title: { text: which === "before" ? "MAC, nominal model" : "MAC, updated model", font: { size: 13 } },
        margin: { l: 80, r: 10, t: 30, b: 70 }, xaxis: { title: { text: "model mode (Hz)" }, tickangle: -45 },
        yaxis: { title: { text: "measured mode (Hz)" }, autorange: "reversed" } }, cfg);
  }

  function drawOverlay(s, div, fitBox, o) {
    const i = o.output_index, j = o.input_index;
    const fits = s.overlay_fit_percent || {};
    const f = (k) => fits[k] && fits[k][i] ? num(fits[k][i][j], 1) : "–";
    fitBox.textContent = `fit: nominal ${f("nominal")} %, updated ${f("updated")} %`;
    Plotly.react(div, [
      { x: o.time_s, y: o.measured, name: "measured", type: "scatter", mode: "lines", line: { color: "#1d2330", width: 1.4 } },
      { x: o.time_s, y: o.nominal, name: "nominal model", type: "scatter", mode: "lines", line: { color: "#9aa2b1", width: 1.2, dash: "dot" } },
      { x: o.time_s, y: o.updated, name: "updated model", type: "scatter", mode: "lines", line: { color: "#e4572e", width: 1.4, dash: "dash" } },
    ], { margin: { l: 55, r: 10, t: 10, b: 40 }, xaxis: { title: { text: "time (s)" } },
         yaxis: { title: { text: plain(`${s.outputs[i]} / ${s.inputs[j]}`) } }, legend: { orientation: "h", y: 1.12 } }, cfg);
  }

  // A shape over the grid's joints as a heatmap (x across, y up), largest component 1.
  function shapeGrid(s, column, sign) {
    const xs = [...new Set(s.node_xy_ft.map((p) => p[0]))].sort((a, b) => a - b);
    const ys = [...new Set(s.node_xy_ft.map((p) => p[1]))].sort((a, b) => a - b);
    const z = ys.map(() => xs.map(() => null));
    const big = Math.max(1e-300, ...column.map((v) => Math.abs(v)));
    s.node_xy_ft.forEach((p, n) => { z[ys.indexOf(p[1])][xs.indexOf(p[0])] = sign * column[n] / big; });
    return { xs, ys, z };
  }

  // A frame's shape (rows "node:x", ...) drawn in the plane of its two largest extents: the undeformed members
  // in grey, the deformed ones in colour (largest displacement 12 % of the size), ○ at the sensors' nodes.
  function frameTraces(s, column, sign) {
    const f = s.frame, ids = Object.keys(f.nodes), xyz = ids.map((n) => f.nodes[n]);
    const span = [0, 1, 2].map((a) => Math.max(...xyz.map((p) => p[a])) - Math.min(...xyz.map((p) => p[a])));
    const [a, b] = [0, 1, 2].sort((i, j) => span[j] - span[i] || i - j).slice(0, 2).sort();
    const u = Object.fromEntries(ids.map((n) => [n, [0, 0, 0]]));
    f.node_labels.forEach((label, r) => { const [n, d] = [label.slice(0, label.lastIndexOf(":")), label.slice(-1)]; u[n]["xyz".indexOf(d)] = column[r]; });
    const big = Math.max(1e-300, ...column.map((v) => Math.abs(v))), scale = sign * 0.12 * Math.max(...span) / big;
    const line = (moved) => { const x = [], y = [], t = [];
      for (const [i, j] of f.members) for (const n of [i, j, null]) {
        if (n === null) { x.push(null); y.push(null); t.push(null); continue; }
        const p = f.nodes[n], d = moved ? u[n] : [0, 0, 0];
        x.push(p[a] + scale * d[a]); y.push(p[b] + scale * d[b]); t.push(`node ${n}`);
      }
      return { x, y, t }; };
    const rest = line(false), moved = line(true), seen = [...new Set(f.sensors.map((q) => q[0]))];
    return { axes: ["xyz"[a], "xyz"[b]], traces: [
      { type: "scatter", mode: "lines", x: rest.x, y: rest.y, line: { color: "#c5cbd6", width: 1 }, hoverinfo: "skip" },
      { type: "scatter", mode: "lines+markers", x: moved.x, y: moved.y, text: moved.t.map((t) => t === null ? null : plain(t)),
        line: { color: "#e4572e", width: 2 }, marker: { size: 4 }, hovertemplate: "%{text}<extra></extra>" },
      { type: "scatter", mode: "markers+text", x: seen.map((n) => f.nodes[n][a]), y: seen.map((n) => f.nodes[n][b]),
        text: seen.map(plain), textposition: "top left", marker: { symbol: "circle-open", size: 9, color: "#1d2330", line: { width: 2 } }, hoverinfo: "skip" }] };
  }

  function drawShapes(s, divs, k) {
    const meas = s.expanded_measured.map((r) => r[k]), model = s.expanded_model.map((r) => r[k]);
    const dot = meas.reduce((a, v, n) => a + v * model[n], 0);
    const m = s.modes[k];
    const panels = [[divs[0], shapeGrid(s, meas, 1), `measured ${num(m.measured_hz, 3)} Hz (SEREP-expanded)`],
                    [divs[1], shapeGrid(s, model, dot < 0 ? -1 : 1), `updated model ${num(m.updated_hz, 3)} Hz, MAC ${num(m.updated_mac, 3)}`]];
    if (s.frame) {
      for (const [div, column, sign, title] of [[divs[0], meas, 1, panels[0][2]], [divs[1], model, dot < 0 ? -1 : 1, panels[1][2]]]) {
        const g = frameTraces(s, column, sign);
        Plotly.react(div, g.traces, { title: { text: title, font: { size: 13 } }, margin: { l: 40, r: 10, t: 30, b: 35 }, showlegend: false,
          xaxis: { title: { text: `${g.axes[0]} (m)` }, constrain: "domain" }, yaxis: { title: { text: `${g.axes[1]} (m)` }, scaleanchor: "x" } }, cfg);
      }
      return;
    }
    for (const [div, g, title] of panels) {
      Plotly.react(div, [
        { type: "contour", x: g.xs, y: g.ys, z: g.z, zmin: -1, zmax: 1, colorscale: "RdBu", reversescale: true,
          contours: { coloring: "heatmap" }, line: { width: 0.5 }, showscale: false,
          hovertemplate: "(%{x}, %{y}) ft: %{z:.3f}<extra></extra>" },
        { type: "scatter", mode: "markers", x: s.sensors_ft.map((p) => p[0]), y: s.sensors_ft.map((p) => p[1]),
          marker: { symbol: "circle-open", size: 9, color: "#1d2330", line: { width: 2 } }, name: "sensors", hoverinfo: "skip" },
      ], { title: { text: title, font: { size: 13 } }, margin: { l: 40, r: 10, t: 30, b: 35 }, showlegend: false,
           xaxis: { title: { text: "x (ft)" }, constrain: "domain" }, yaxis: { title: { text: "y (ft)" }, scaleanchor: "x" } }, cfg);
    }
  }

  function select(id, label, options, onChange) {
    const sel = el("select", null, { id });
    options.forEach(([v, t]) => sel.append(el("option", t, { value: String(v) })));
    sel.addEventListener("change", () => onChange(sel));
    const lab = el("label", label, { class: "field" });
    lab.append(sel);
    return [lab, sel];
  }

  /* Draw summary s into root. opts.id: prefix of element ids; opts.overlay(output, input): Promise of an overlay
     (the page asks the server) or undefined to use s.overlays (the report); opts.onShape(k): called when the
     chosen mode changes (the page moves its viewers). */
  function render(root, s, opts) {
    const id = (opts && opts.id) || "explain";
    root.replaceChildren();
    const h = (t) => el("h3", t, { style: "font-size:14px;margin:14px 0 6px" });
    const half = () => el("div", null, { class: "plot", style: "flex:1 1 420px;min-width:320px;height:340px" });
    const pair = (...kids) => { const d = el("div", null, { style: "display:flex;flex-wrap:wrap;gap:12px" }); d.append(...kids); return d; };

    // A result made with another model than the dataset's now (issue 9): said first, with the model it used.
    const stale = el("div", s.stale || "", { class: "stale", id: `${id}-stale` });
    stale.hidden = !s.stale;
    root.append(stale, verdictBox(s, id));
    if (s.basis) root.append(el("p", `Compared: ${s.basis.text}`, { class: "note", id: `${id}-basis` }));
    const made = s.model_used && s.model_used.saved ? `, saved ${new Date(1000 * s.model_used.saved).toLocaleString()}` : "";
    const from = s.model_used && s.model_used.source === "file" ? `the file ${s.model_used.name}: ` : "";
    const fe = !!s.fe_model;   // the engineer's FE model: its shapes over the mesh are not drawn here yet
    if (s.model_text) root.append(el("p", `Nominal model: this dataset's structure model (${from}${s.model_text}${made}).`, { class: "note", id: `${id}-model` }));
    if (s.nominal_params && Object.keys(s.nominal_params).length) {
      root.append(el("p", `Nominal model: nasa_grid(${Object.entries(s.nominal_params).map(([k, v]) => `${k}=${JSON.stringify(v)}`).join(", ")})`, { class: "note" }));
    }
    root.append(h("Gap between model and test, before and after the update"), gapTable(s, id));
    root.append(h("Candidate effects, most probable first"), rankingTable(s, id));
    root.append(h("Modes: measured against the nominal and the updated model"), modeTable(s, id));
    if ((s.unpaired_measured_hz || []).length) {
      root.append(el("p", `Set aside (no model partner): ${s.unpaired_measured_hz.map((f) => num(f, 3) + " Hz").join(", ")}.`, { class: "note" }));
    }
    const macB = half(), macA = half();
    macB.id = `${id}-mac-before`; macA.id = `${id}-mac-after`;
    root.append(h("MAC matrices"), pair(macB, macA));

    // Response overlay for one output and input.
    const fitBox = el("span", null, { class: "fit" });
    const ov = el("div", null, { class: "plot", id: `${id}-overlay` });
    let output = 0, input = 0;
    const redraw = async () => {
      const o = opts && opts.overlay ? await opts.overlay(output, input)
        : (s.overlays || []).find((x) => x.output_index === output && x.input_index === input);
      if (o) drawOverlay(s, ov, fitBox, o);
    };
    const [labO, selO] = select(`${id}-output`, "Output", s.outputs.map((n, i) => [i, n]), (x) => { output = Number(x.value); redraw(); });
    const [labI, selI] = select(`${id}-input`, "Input", s.inputs.map((n, j) => [j, n]), (x) => { input = Number(x.value); redraw(); });
    const row = el("div", null, { class: "row" });
    row.append(labO, labI, fitBox);
    root.append(h("Measured against simulated response (model frequencies and shapes, ERA's damping, fitted amplitudes)"), row, ov);
    if (s.overlay) { output = s.overlay.output_index; input = s.overlay.input_index; selO.value = String(output); selI.value = String(input); drawOverlay(s, ov, fitBox, s.overlay); }
    else redraw();

    if (fe) {
      const box = el("div", null, { id: `${id}-viewers` });
      root.append(el("p", s.mesh ? "Mode shapes over the FE model's mesh (its bars and shell edges as lines), measured (SEREP-expanded) and updated model, in the 3-D viewer:"
                                 : "This FE model has no node coordinates: its shapes are compared at the sensors by the MAC matrices above.", { class: "note", id: `${id}-fe-shapes` }), box);
      macPlots(s, macB, "before");
      macPlots(s, macA, "after");
      return { viewers: box };
    }
    // Shapes: measured (expanded to all joints) and the updated model, side by side.
    const shapeRow = el("div", null, { class: "row" });
    const [labM] = select(`${id}-mode`, "Mode", s.modes.map((m, k) => [k, `${m.mode}: ${num(m.measured_hz, 3)} Hz`]), (x) => {
      drawShapes(s, [shM, shU], Number(x.value));
      if (opts && opts.onShape) opts.onShape(Number(x.value));
    });
    shapeRow.append(labM);
    const shM = half(), shU = half();
    shM.id = `${id}-shape-measured`; shU.id = `${id}-shape-model`;
    const viewers = el("div", null, { id: `${id}-viewers` });
    root.append(h(s.frame ? `Mode shapes over the whole structure: measured (SEREP expansion of the ${s.outputs.length} sensors) and updated model`
                          : "Mode shapes over the whole grid: measured (SEREP expansion of the nine sensors) and updated model"),
                shapeRow, viewers, pair(shM, shU),
                el("p", s.frame ? "Grey: the frame at rest; colour: displaced, largest 12 % of its size (the model's sign matched to the measured). ○ sensors' nodes."
                                : "Colour: out-of-plane displacement w, largest = 1 (the model's sign matched to the measured). ○ sensors.", { class: "note" }));
    macPlots(s, macB, "before");
    macPlots(s, macA, "after");
    if (s.modes.length) drawShapes(s, [shM, shU], 0);
    return { viewers };
  }

  window.EraExplainView = { render };
})();

/* The read-only report page (/r/{token} and the downloaded HTML file). A classic script with no imports: the
   download inlines it next to the report data (window.REPORT_DATA), so the file opens with no server. */
(function () {
  "use strict";
  const F = window.EraFormat;
  const $ = (id) => document.getElementById(id);
  const cfg = { responsive: true, displaylogo: false };
  let animation = null;
  // Plotly reads a few HTML tags in categories and titles: channel names must show as typed.
  const plain = (t) => String(t).replace(/&/g, "&amp;").replace(/</g, "&lt;").replace(/>/g, "&gt;");

  function el(tag, text, attrs) {
    const n = document.createElement(tag);
    if (text !== undefined) n.textContent = text;  // text only: names from files never become HTML
    for (const [k, v] of Object.entries(attrs || {})) n.setAttribute(k, v);
    return n;
  }

  async function load() {
    if (window.REPORT_DATA) return window.REPORT_DATA;
    const token = decodeURIComponent(location.pathname.split("/").filter(Boolean).pop());
    const res = await fetch(`/api/reports/${encodeURIComponent(token)}`);
    const body = await res.json().catch(() => null);
    if (!res.ok) throw new Error((body && body.error) || `${res.status} ${res.statusText}`);
    return body;
  }

  // Whether the kept modes are era's automatic choice (reports frozen before it existed say nothing).
  function keptHow(r) {
    const chosen = r.analysis.chosen_indices;
    if (!chosen) return "";
    if (!chosen.length) return " (era chose no mode; kept by hand or by the thresholds)";
    const same = r.order === r.analysis.suggested_order && chosen.length === r.kept.length && chosen.every((k) => r.kept.includes(k));
    return same ? ": the modes era chose automatically" : ` (changed by hand: era chose ${chosen.length} at order ${r.analysis.suggested_order})`;
  }

  function meta(r) {
    const a = r.analysis, d = r.dataset, kept = new Set(r.kept);
    $("report-title").textContent = `ERA report: ${d.name}`;
    document.title = `ERA report: ${d.name}`;
    const fits = (r.kept_fit_percent || []).flat().filter((v) => v !== null);
    const mean = fits.length ? fits.reduce((s, v) => s + v, 0) / fits.length : null;
    const rows = [
      ["Dataset", `${d.name}: ${d.n_outputs} outputs × ${d.n_inputs} inputs, ${d.n_samples} samples, Δt = ${window.EraFormat.step(d.dt)}`],
      ["Dataset SHA-256", d.sha256],
      ...(d.source && d.source.format ? [["Read as", `${d.source.format.toUpperCase()}${d.source.kind ? `, ${d.source.kind}` : ""}` +
                                                     (d.source.records ? `: ${d.source.records.join("; ")}` : "")]] : []),
      ...(d.source && d.source.conversions && d.source.conversions.length
        ? [["Converted", d.source.conversions.join("; ")]] : []),
      ...(window.EraFormat.importChoices(d.source) ? [["Import choices", window.EraFormat.importChoices(d.source)]] : []),
      ["Hankel matrix", `rows r = ${a.rows}, columns s = ${a.cols}, H(0) ${a.hankel_shape[0]} × ${a.hankel_shape[1]}, ${a.svd_method} SVD`],
      ["Order", `n = ${r.order} (max ${a.max_order}, ${a.chosen_indices ? "automatic choice at" : "suggested"} ${a.suggested_order})`],
      ["Kept modes", `${kept.size} of ${r.modes.n_modes}${keptHow(r)}`],
      ["Uncertainty (±: 95 % intervals)", r.modes.uncertainty_source || "–"],
      ["Fit with kept modes", mean === null ? "–" : `${mean.toFixed(2)} % (mean over channels)`],
      ["Created", r.created], ["Software", Object.entries(r.software).map(([k, v]) => `${k} ${v}`).join(", ")],
    ];
    const dl = $("report-meta");
    for (const [k, v] of rows) { dl.append(el("dt", k), el("dd", v)); }
    if (r.structure_model) {  // the dataset's structure model when the report was made (issue 9), frozen here
      const m = r.structure_model, dd = el("dd", `${m.source === "file" ? `file ${m.name}: ` : ""}${m.text} `, { id: "report-model" });
      const blob = new Blob([JSON.stringify(m.model, null, 1)], { type: "application/json" });
      dd.append(el("a", "model (JSON)", { href: URL.createObjectURL(blob), download: "model.json" }));
      dl.append(el("dt", "Model of the structure"), dd);
    }
    if (!r.standalone) {
      const links = el("dd");
      for (const [text, href] of [["report (HTML)", `/api/reports/${r.token}/report.html`],
                                  ["modes (CSV)", `/api/reports/${r.token}/modes.csv`],
                                  ["modes (UFF 55)", `/api/reports/${r.token}/modes.uff`]]) {
        const a = el("a", text, { href, download: "" });
        links.append(a, document.createTextNode("  "));
      }
      dl.append(el("dt", "Download"), links);
    }
  }

  function table(r) {
    const m = r.modes, kept = new Set(r.kept);
    $("report-order").textContent = String(r.order);
    const head = el("tr");
    head.append(el("th", "keep"));
    for (const c of F.columns) head.append(el("th", c.label, { title: c.title }));
    $("report-table").tHead.append(head);
    for (let k = 0; k < m.n_modes; k++) {
      const tr = el("tr", undefined, { "data-mode": String(k) });
      if (!kept.has(k)) tr.className = "rejected";
      tr.append(el("td", kept.has(k) ? "✓" : "", { class: "keep" }));
      for (const c of F.columns) tr.append(el("td", c.text(m, k), { "data-key": c.key }));
      $("report-table").tBodies[0].append(tr);
    }
  }

  function stabilization(r) {
    const s = r.stabilization, m = r.modes;
    const groups = { all: [], freq: [], none: [] };
    s.order.forEach((_, i) => {
      if (s.frequency_hz[i] === null) return;
      (s.stable[i] ? groups.all : s.stable_frequency[i] ? groups.freq : groups.none).push(i);
    });
    const pick = (idx, name, marker) => ({ x: idx.map((i) => s.frequency_hz[i]), y: idx.map((i) => s.order[i]), type: "scatter",
      mode: "markers", name, marker, hovertemplate: "%{x:.4f} Hz, order %{y}<extra></extra>" });
    const traces = s.spectrum.values.map((v, k) => ({ x: s.spectrum.frequency_hz, y: v, yaxis: "y2", type: "scatter",
      mode: "lines", name: "CMIF", legendgroup: "cmif", showlegend: k === 0, hoverinfo: "skip", line: { width: 1, color: "rgba(120,130,150,0.55)" } }));
    traces.push(pick(groups.none, "not stable", { symbol: "x-thin-open", size: 5, color: "#b0b6c2", line: { width: 1 } }));
    traces.push(pick(groups.freq, "stable frequency", { symbol: "diamond-open", size: 7, color: "#6a7a99" }));
    traces.push(pick(groups.all, "stable f, ζ, shape", { symbol: "circle", size: 8, colorscale: "Viridis", cmin: 0.5, cmax: 1,
      color: groups.all.map((i) => s.emac[i] * s.mpc[i]), colorbar: { title: { text: "γ·μ" }, x: 1.07, len: 0.8 } }));
    traces.push({ x: r.kept.map((k) => m.frequency_hz[k]), y: r.kept.map(() => r.order), type: "scatter", mode: "markers",
      name: "kept modes", marker: { symbol: "star", size: 15, color: "#ffb000", line: { width: 1, color: "#000" } } });
    // era's verdict on every cluster (reports frozen before the automatic choice have none): green lines for the
    // chosen modes, the reason of every other in its pole's hover
    const judged = s.candidates || [];
    const shapes = judged.filter((c) => c.chosen).map((c) => ({ type: "line", x0: c.frequency_hz, x1: c.frequency_hz,
      yref: "paper", y0: 0, y1: 1, layer: "below", line: { color: "rgba(26,154,74,0.55)", width: 1.5 } }));
    const others = judged.filter((c) => !c.chosen && c.pole_indices.length);
    if (others.length) {
      const last = others.map((mo) => mo.pole_indices.at(-1));
      traces.push({ x: last.map((i) => s.frequency_hz[i]), y: last.map((i) => s.order[i]), type: "scatter", mode: "markers",
        name: "not chosen (hover: why)", marker: { symbol: "triangle-down-open", size: 8, color: "#8a93a6" },
        hovertext: others.map((mo) => `${mo.frequency_hz.toFixed(4)} Hz: ${plain(mo.reason)}`), hovertemplate: "%{hovertext}<extra></extra>" });
    }
    Plotly.newPlot("report-stab", traces, { margin: { l: 55, r: 90, t: 10, b: 45 }, hovermode: "closest", shapes,
      xaxis: { title: { text: "frequency (Hz)" }, range: [0, s.nyquist_hz] }, yaxis: { title: { text: "model order n" } },
      yaxis2: { overlaying: "y", side: "right", type: "log", showgrid: false, showticklabels: false, title: { text: "CMIF (log scale)" } },
      legend: { orientation: "h", y: -0.18 } }, cfg);
  }

  function singularValues(r) {
    const d = r.analysis.singular_values, n = r.order;
    Plotly.newPlot("report-sv", [{ x: d.map((_, i) => i + 1), y: d, type: "scatter", mode: "lines+markers", marker: { size: 4 } }],
      { margin: { l: 60, r: 10, t: 10, b: 40 }, yaxis: { type: "log", title: { text: "d_i" }, exponentformat: "e" },
        xaxis: { title: { text: "index i" } }, showlegend: false,
        shapes: [{ type: "line", x0: n + 0.5, x1: n + 0.5, yref: "paper", y0: 0, y1: 1, line: { color: "#b3261e", width: 2 } }] }, cfg);
  }

  function reconstruction(r) {
    const sel = $("report-pair");
    r.reconstruction.pairs.forEach((p, i) => sel.append(el("option", `${p.output} / ${p.input}`, { value: String(i) })));
    const draw = () => {
      const p = r.reconstruction.pairs[Number(sel.value)];
      const fit = r.kept_fit_percent[p.output_index][p.input_index];
      $("report-fit").textContent = `fit ${fit === null ? "–" : fit.toFixed(2)} %`;
      Plotly.react("report-recon", [
        { x: r.reconstruction.time_s, y: p.measured, name: "measured", type: "scatter", mode: "lines", line: { color: "#1d2330", width: 1.5 } },
        { x: r.reconstruction.time_s, y: p.reconstructed, name: "reconstructed", type: "scatter", mode: "lines",
          line: { color: "#e4572e", width: 1.5, dash: "dash" } },
      ], { margin: { l: 55, r: 10, t: 10, b: 40 }, xaxis: { title: { text: "time (s)" } }, legend: { orientation: "h", y: 1.12 } }, cfg);
    };
    sel.addEventListener("change", draw);
    if (r.reconstruction.pairs.length) draw();
  }

  // Displaced geometry for a real shape: every channel moves its node along its direction.
  function displaced(g, shape, scale) {
    const xyz = g.coordinates.map((c) => c.slice());
    g.channel_nodes.forEach((node, i) => {
      if (node < 0 || shape[i] === null) return;
      for (let a = 0; a < 3; a++) xyz[node][a] += scale * shape[i] * g.channel_directions[i][a];
    });
    return xyz;
  }

  function lines(g, xyz) {
    const x = [], y = [], z = [];
    for (const [a, b] of g.edges) { x.push(xyz[a][0], xyz[b][0], null); y.push(xyz[a][1], xyz[b][1], null); z.push(xyz[a][2], xyz[b][2], null); }
    return { x, y, z };
  }

  // Axes padded by the animation amplitude, drawn to scale (a flat grid keeps some height to move in).
  function sceneLayout(g, scale) {
    const lo = [0, 1, 2].map((a) => Math.min(...g.coordinates.map((c) => c[a])) - 1.5 * scale);
    const hi = [0, 1, 2].map((a) => Math.max(...g.coordinates.map((c) => c[a])) + 1.5 * scale);
    const span = hi.map((h, a) => h - lo[a]);
    const big = Math.max(...span);
    const axis = (a) => ({ range: [lo[a], hi[a]], title: { text: "xyz"[a] + ` (${g.units})` } });
    return { aspectmode: "manual", aspectratio: { x: span[0] / big, y: span[1] / big, z: Math.max(span[2] / big, 0.25) },
             xaxis: axis(0), yaxis: axis(1), zaxis: axis(2), camera: { eye: { x: 0.9, y: -1.5, z: 0.9 } } };
  }

  function shape(r, k) {
    const m = r.modes;
    let g = r.geometry;
    $("report-shape-title").textContent = `mode ${k + 1}: ${F.num(m.frequency_hz[k], 4)} Hz, ζ ${F.num(100 * m.damping_ratio[k], 3)} %`;
    if (animation) { clearInterval(animation); animation = null; }
    const box = $("report-viewer");
    box.replaceChildren();
    const key = String(k);
    let viser = false;
    if (!r.standalone && r.playback && r.playback[key]) {  // served: viser's client plays the stored recording
      box.append(el("iframe", undefined, { class: "viewer", src: r.playback[key], title: "mode shape (viser playback)" }));
      viser = true;
    } else if (r.standalone && window.VISER_PAGE && r.offline_recordings && r.offline_recordings[key]) {
      // downloaded file: viser's standalone player with this mode's recording inlined, no server needed
      const frame = el("iframe", undefined, { class: "viewer", title: "mode shape (viser playback)" });
      frame.srcdoc = window.VISER_PAGE.replace(r.viser_marker, () => `window.__VISER_EMBED_DATA__="${r.offline_recordings[key]}"`);
      box.append(frame);
      viser = true;
    }
    // the shape at every measured or struck point (issue 26: a roving hammer's hit points) when the report has
    // them; the geometry then places the points (app/viewing.modes_scene), else the sensors
    const atPoints = m.points && m.point_shapes_re && m.point_shapes_re.length === m.n_modes &&
      m.points.join("\u0001") !== m.outputs.join("\u0001");
    const re = atPoints ? m.point_shapes_re[k] : m.shapes_re[k], im = atPoints ? m.point_shapes_im[k] : m.shapes_im[k];
    const where = atPoints ? m.points : m.outputs;
    if (g && g.channel_nodes.length !== re.length) g = null;  // a report frozen with the sensors' geometry only
    $("report-shape").hidden = viser;  // plotly animates the shape only where viser cannot
    $("report-shape").style.height = g ? "460px" : "300px";
    if (viser) return;
    if (!g) {
      Plotly.react("report-shape", [{ x: where.map(plain), y: re, type: "bar", name: "real" },
                                    { x: where.map(plain), y: im, type: "bar", name: "imaginary" }],
                   { margin: { l: 45, r: 10, t: 10, b: 60 }, barmode: "group" }, cfg);
      return;
    }
    const span = Math.max(...[0, 1, 2].map((a) => Math.max(...g.coordinates.map((c) => c[a])) - Math.min(...g.coordinates.map((c) => c[a]))));
    const scale = 0.15 * (span || 1);
    const rest = lines(g, g.coordinates);
    const moving = lines(g, displaced(g, re, scale));
    Plotly.react("report-shape", [
      { ...rest, type: "scatter3d", mode: "lines", name: "undeformed", line: { color: "#c3c9d4", width: 2 }, hoverinfo: "skip" },
      { ...moving, type: "scatter3d", mode: "lines", name: "mode shape", line: { color: "#1f5fbf", width: 5 }, hoverinfo: "skip" },
    ], { margin: { l: 0, r: 0, t: 0, b: 0 }, showlegend: true,
      scene: sceneLayout(g, scale) }, cfg);
    let phase = 0;
    animation = setInterval(() => {
      phase += 0.25;
      const xyz = lines(g, displaced(g, re, scale * Math.cos(phase)));
      Plotly.restyle("report-shape", { x: [xyz.x], y: [xyz.y], z: [xyz.z] }, [1]);
    }, 80);
  }

  function shapes(r) {
    const sel = $("report-mode");
    const list = r.kept.length ? r.kept : [...Array(r.modes.n_modes).keys()];
    for (const k of list) sel.append(el("option", `mode ${k + 1}: ${F.num(r.modes.frequency_hz[k], 4)} Hz`, { value: String(k) }));
    sel.addEventListener("change", () => shape(r, Number(sel.value)));
    if (list.length) shape(r, list[0]);
  }

  load().then((r) => {
    window.eraReport = r;
    meta(r); table(r); stabilization(r); singularValues(r); reconstruction(r); shapes(r);
    if (r.explanation && window.EraExplainView) {  // simulation vs test, when its panel ran before the report
      $("report-explain-card").hidden = false;
      try { window.EraExplainView.render($("report-explain"), r.explanation, { id: "report-explain" }); }
      catch (err) { $("report-explain").textContent = `The simulation-vs-test section cannot be drawn: ${err.message}`; }
    }
    document.body.dataset.ready = "1";
  }).catch((err) => {
    const box = $("report-error");
    box.hidden = false;
    box.textContent = `This report cannot be shown: ${err.message}`;
    document.body.dataset.ready = "error";
  });
})();

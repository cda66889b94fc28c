/* The campaign page: /campaigns starts one (POST /api/campaigns), /c/{id} follows it and draws its result. A
   classic script with no imports, like report.js: the download inlines it next to window.CAMPAIGN_DATA. */
(function () {
  "use strict";
  const $ = (id) => document.getElementById(id);
  const cfg = { responsive: true, displaylogo: false };
  const plain = (t) => String(t).replace(/&/g, "&amp;").replace(/</g, "&lt;").replace(/>/g, "&gt;");
  const POLL_MS = 1000;

  function el(tag, text, attrs) {
    const n = document.createElement(tag);
    if (text !== undefined) n.textContent = text;  // text only: file names never become HTML
    for (const [k, v] of Object.entries(attrs || {})) n.setAttribute(k, v);
    return n;
  }

  async function json(res) {
    const body = await res.json().catch(() => null);
    if (!res.ok) throw new Error((body && body.error) || `${res.status} ${res.statusText}`);
    return body;
  }

  function fail(box, err) {
    $(box).textContent = err.message || String(err);
    $(box).hidden = false;
  }

  // ---- /campaigns: the form ---------------------------------------------------------------------------
  async function newCampaign() {
    $("campaign-new").hidden = false;
    try {
      const server = await json(await fetch("/api/campaigns/folders"));
      $("campaign-engine").textContent = `Records run on ${server.engine}; at most ${server.max_records} records per campaign.`;
      if (server.enabled && server.folders.length) {
        for (const f of server.folders) $("campaign-folder").append(el("option", `${f.name} (${f.n_files} files)`, { value: f.name }));
        $("campaign-folder-field").hidden = false;
      }
    } catch (err) { fail("campaign-form-error", err); }
    $("campaign-form").addEventListener("submit", async (ev) => {
      ev.preventDefault();
      $("campaign-form-error").hidden = true;
      const form = new FormData();
      const folder = $("campaign-folder").value;
      if (folder) form.append("folder", folder);
      else for (const f of $("campaign-files").files) form.append("file", f, f.name);
      for (const id of ["campaign-name", "campaign-kind", "campaign-dt", "campaign-order"]) {
        const input = $(id);
        if (input.value !== "") form.append(input.name, input.value);
      }
      $("campaign-start").disabled = true;
      try {
        const c = await json(await fetch("/api/campaigns", { method: "POST", body: form }));
        location.assign(c.url);
      } catch (err) {
        fail("campaign-form-error", err);
        $("campaign-start").disabled = false;
      }
    });
  }

  // ---- /c/{id}: progress, then the result -------------------------------------------------------------
  async function follow(id) {
    $("campaign-status").hidden = false;
    for (;;) {
      let c;
      try {
        c = await json(await fetch(`/api/campaigns/${encodeURIComponent(id)}`));
      } catch (err) {
        fail("campaign-error", err);
        return;
      }
      $("campaign-title").textContent = `ERA campaign: ${c.name}`;
      document.title = `ERA campaign: ${c.name}`;
      $("campaign-progress").max = Math.max(1, c.total);
      $("campaign-progress").value = c.done;
      $("campaign-state").textContent = `${c.state}: ${c.done} of ${c.total} records on ${c.engine}`;
      if (c.message) fail("campaign-error", new Error(c.message));
      if (c.state === "done") { show(c); return; }
      if (c.state === "failed") return;
      await new Promise((r) => setTimeout(r, POLL_MS));
    }
  }

  function show(c) {
    const r = c.result;
    $("campaign-status").hidden = true;
    $("campaign-summary").hidden = false;
    document.querySelectorAll("[data-result]").forEach((n) => { n.hidden = false; });
    const a = r.analysis, orders = a.orders;
    const span = r.records.length ? `${r.records[0].time} … ${r.records[r.records.length - 1].time}` : "–";
    const rows = [
      ["Records", `${r.n_records}: ${r.records.length} analysed, ${r.failed.length} failed`],
      [r.time_axis === "date" ? "From … to" : "Order", r.time_axis === "date" ? span : "file names hold no date: records in the order given"],
      ["Tracked modes", String(r.modes.length)],
      ["Each record", `${a.kind}${a.dt ? `, Δt = ${window.EraFormat.step(a.dt)}` : ""}, orders ${orders[0]}–${orders[orders.length - 1]}, suggested Hankel size`],
      ["Ran on", `${r.engine} in ${r.seconds.toFixed(1)} s`],
    ];
    for (const [k, v] of rows) $("campaign-meta").append(el("dt", k), el("dd", v));
    $("campaign-title").textContent = `ERA campaign: ${c.name}`;
    document.title = `ERA campaign: ${c.name}`;
    if (c.standalone) {
      $("campaign-share").hidden = true;  // the downloaded file: no server behind it
    } else {
      $("campaign-link").textContent = location.origin + c.url;
      $("campaign-link").href = c.url;
      $("campaign-html").href = `/api/campaigns/${encodeURIComponent(c.id)}/campaign.html`;
      $("campaign-csv").href = `/api/campaigns/${encodeURIComponent(c.id)}/table.csv`;
    }
    plots(r);
    modes(r);
    failed(r);
    document.body.dataset.ready = "1";
  }

  function plots(r) {
    const x = r.records.map((rec) => rec.time);
    const names = r.records.map((rec) => rec.name);
    const label = (m) => `mode ${m.mode} (${m.reference_frequency_hz === null ? "–" : m.reference_frequency_hz.toFixed(3)} Hz)`;
    const modeOf = Object.fromEntries(r.modes.map((m) => [m.mode, m]));
    const traces = (key, scale) => r.series.map((s) => ({
      x, y: s[key].map((v) => (v === null ? null : v * scale)), type: "scatter", mode: "lines+markers",
      name: plain(label(modeOf[s.mode])), text: names.map(plain), connectgaps: false,
      hovertemplate: "%{text}<br>%{y:.4g}<extra>%{fullData.name}</extra>",
    }));
    const xaxis = () => ({ title: { text: r.time_axis === "date" ? "time" : "record" }, type: r.time_axis === "date" ? "date" : "linear" });
    const layout = (title, extra) => Object.assign({ margin: { l: 60, r: 10, t: 10, b: 45 }, xaxis: xaxis(),
      yaxis: { title: { text: title } }, legend: { orientation: "h", y: -0.25 } }, extra || {});
    const frequency = () => {
      if ($("campaign-freq-scale").value === "hz") {
        Plotly.react("campaign-freq", traces("frequency_hz", 1), layout("frequency, Hz"), cfg);
        return;
      }
      // each mode relative to its reference frequency: a drift or a damage step of 1 % shows at any frequency
      const rel = traces("frequency_hz", 1).map((t, k) => {
        const f0 = modeOf[r.series[k].mode].reference_frequency_hz;
        return Object.assign(t, { y: t.y.map((v) => (v === null || !f0 ? null : 100 * (v / f0 - 1))) });
      });
      Plotly.react("campaign-freq", rel, layout("change from the reference frequency, %"), cfg);
    };
    frequency();
    $("campaign-freq-scale").addEventListener("change", frequency);
    Plotly.newPlot("campaign-damp", traces("damping_ratio", 100), layout("damping ratio, %"), cfg);
    Plotly.newPlot("campaign-mac", traces("mac_to_reference", 1), layout("MAC to reference", { yaxis: { title: { text: "MAC to reference" }, range: [0, 1.02] } }), cfg);
  }

  function modes(r) {
    const analysed = r.records.length;
    const nameOf = Object.fromEntries(r.records.map((rec) => [rec.record, rec.name]));
    const body = $("campaign-modes").tBodies[0];
    for (const m of r.modes) {
      const tr = el("tr", undefined, { "data-mode": String(m.mode) });
      const cells = [String(m.mode), m.reference_frequency_hz === null ? "–" : m.reference_frequency_hz.toFixed(4),
        m.reference_damping_ratio === null ? "–" : (100 * m.reference_damping_ratio).toFixed(2), m.origin,
        m.first_record < 0 ? "given reference" : (nameOf[m.first_record] || `record ${m.first_record}`),
        `${m.n_found} of ${m.n_held || analysed} records`,
        m.identification_rate === null || m.identification_rate === undefined ? "–" : `${(100 * m.identification_rate).toFixed(1)} %`];
      for (const text of cells) tr.append(el("td", text));
      body.append(tr);
    }
  }

  function failed(r) {
    $("campaign-failed-count").textContent = r.failed.length ? `${r.failed.length} of ${r.n_records}: listed, the others finished` : "none";
    for (const f of r.failed) {
      const li = el("li", undefined, { "data-record": String(f.record) });
      const reason = f.reason.startsWith(`${f.name}: `) ? f.reason.slice(f.name.length + 2) : f.reason;  // named once
      li.append(el("strong", f.name), document.createTextNode(`: ${reason}`));
      $("campaign-failed").append(li);
    }
    if (!r.failed.length) $("campaign-failed").append(el("li", "Every record was analysed."));
  }

  const parts = location.pathname.split("/").filter(Boolean);
  if (window.CAMPAIGN_DATA) show(window.CAMPAIGN_DATA);
  else if (parts[0] === "c" && parts[1]) follow(decodeURIComponent(parts[1]));
  else newCampaign();
})();

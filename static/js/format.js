/* Number formats and the modes-table columns, shared by the analysis page and the report (classic script:
   the report download inlines it). */
(function () {
  const num = (v, digits) => (v === null || v === undefined || !isFinite(v)) ? "–" : Number(v).toFixed(digits);
  // value ± 1.96 σ (the 95 % interval the data give, era.core.uncertainty), or the value alone when σ is unknown
  const pm = (v, sd, digits) => {
    const ok = sd !== null && sd !== undefined && isFinite(sd);
    return ok ? `${num(v, digits)} ± ${num(1.96 * sd, digits)}` : num(v, digits);
  };
  // a sampling step as a person reads it: 6 significant digits and its rate, "0.000605469 s (1651.61 Hz)"
  const step = (dt) => (dt === null || dt === undefined || !(dt > 0)) ? "–"
    : `${Number(Number(dt).toPrecision(6))} s (${Number((1 / dt).toPrecision(6))} Hz)`;
  // "1 channel", "2 channels": a count and the noun that agrees with it
  const counted = (n, one, many) => `${n} ${n === 1 ? one : (many || `${one}s`)}`;
  const std = (m, key, k) => (m[key] ? m[key][k] : null);
  // What a cell cannot say, shown as "—" with its reason on hover: a real pole has no frequency or damping of an
  // oscillation (its Im s is 0, its ζ 1 by definition); with one sensor μ is 1 and 1 − MAC 0 by construction.
  const DASH = "—";
  const REAL_POLE = "a real pole: no oscillation";
  const ONE_SENSOR = "one sensor";
  const oneSensor = (m) => m.outputs.length === 1;
  // The modes that share one ± (schemas.Modes.std_group): poles closer together than their scatter, which the data
  // cannot tell apart (era.core.decomposition.repeated_clusters), each given the group's largest σ.
  const group = (m, k) => (m.std_group && m.std_group[k] ? m.std_group[k] : null);
  const groupWords = (m, k) => {
    const g = group(m, k);
    const modes = g.map((j) => j + 1), fs = g.map((j) => num(m.frequency_hz[j], 2));
    return `the ± of the group of modes ${modes.slice(0, -1).join(", ")} and ${modes[modes.length - 1]} ` +
      `(${fs.join(", ")} Hz): their poles lie closer together than their scatter, so the data cannot tell them ` +
      "apart; each carries the group's largest ±";
  };
  const withGroup = (m, k, text) => (group(m, k) && text.includes("±") ? `${text} (group)` : text);
  const columns = [
    { key: "index", label: "#", title: "mode number at this order", value: (m, k) => k, text: (m, k) => String(k + 1) },
    { key: "frequency_hz", label: "f (Hz)", title: "damped natural frequency ± its 95 % interval from the data",
      value: (m, k) => m.frequency_hz[k],
      text: (m, k) => (m.is_pair[k] ? withGroup(m, k, pm(m.frequency_hz[k], std(m, "frequency_std_hz", k), 4)) : DASH),
      cellTitle: (m, k) => (!m.is_pair[k] ? REAL_POLE : group(m, k) ? groupWords(m, k) : null) },
    { key: "damping_ratio", label: "ζ (%)", title: "damping ratio ± its 95 % interval from the data",
      value: (m, k) => m.damping_ratio[k],
      text: (m, k) => (m.is_pair[k] ? withGroup(m, k, pm(100 * m.damping_ratio[k],
        std(m, "damping_std", k) === null ? null : 100 * std(m, "damping_std", k), 3)) : DASH),
      cellTitle: (m, k) => (!m.is_pair[k] ? REAL_POLE : group(m, k) ? groupWords(m, k) : null) },
    { key: "emac", label: "γ", title: "modal amplitude coherence (eqs. 42-45)", value: (m, k) => m.emac[k],
      text: (m, k) => num(m.emac[k], 3) },
    { key: "mpc", label: "μ", title: "modal phase collinearity (eqs. 46-54)", value: (m, k) => m.mpc[k],
      text: (m, k) => (oneSensor(m) ? DASH : num(m.mpc[k], 3)), cellTitle: (m) => (oneSensor(m) ? ONE_SENSOR : null) },
    { key: "shape_scatter", label: "1 − MAC",
      title: "shape scatter from the data: expected 1 − MAC between this shape and the true one (– until computed)",
      value: (m, k) => std(m, "shape_scatter", k),
      text: (m, k) => (oneSensor(m) ? DASH : num(std(m, "shape_scatter", k), 4)),
      cellTitle: (m) => (oneSensor(m) ? ONE_SENSOR : null) },
    { key: "emac_mpc", label: "γ·μ", title: "product, the colour of the stabilization diagram",
      value: (m, k) => m.emac_mpc[k], text: (m, k) => num(m.emac_mpc[k], 3) },
    { key: "contribution_relative", label: "contribution (%)", title: "share of H(0) relative to the strongest mode",
      value: (m, k) => m.contribution_relative[k], text: (m, k) => num(100 * m.contribution_relative[k], 1) },
    { key: "is_pair", label: "type", title: "complex pair or real pole", value: (m, k) => m.is_pair[k] ? 1 : 0,
      text: (m, k) => m.is_pair[k] ? "pair" : "real" },
  ];
  // What the person said at the import step (dataset.source.options), in words; null when nothing was said.
  // Channels are positions as read; source.channels (when present) names them.
  function importChoices(src) {
    const o = (src && src.options) || {};
    const names = src && src.channels_read;
    const ch = (list) => list.map((i) => (names && names[i] !== undefined ? names[i] : `#${i}`)).join(", ");
    const out = [];
    if (o.kind) out.push(`records read as ${o.kind}`);
    if (o.dt) out.push(`sample rate ${Number((1 / o.dt).toPrecision(6))} Hz (Δt ${Number(o.dt.toPrecision(6))} s)`);
    if (o.resample) out.push("time stamps resampled onto an even grid at the mean rate");
    if (o.orientation) out.push(`channels in ${o.orientation}`);
    if (o.format) out.push(`format ${o.format}`);
    if (o.variable) out.push(`array ${o.variable}`);
    if (o.group) out.push(`group ${o.group}`);
    if (o.frf_sign && o.frf_sign !== "auto") out.push(`FRF sign ${o.frf_sign}`);
    if (o.band_hz) out.push(`band ${o.band_hz[0]}–${o.band_hz[1]} Hz`);
    if (o.start_sample) out.push(`records start at sample ${o.start_sample}`);
    if (o.drop && o.drop.length) out.push(`left out: ${ch(o.drop)}`);
    if (o.forces) out.push(o.forces.length ? `force channels: ${ch(o.forces)}` : "no force channel");
    if (o.references && o.references.length) out.push(`NExT references: ${ch(o.references)}`);
    return out.length ? out.join("; ") : null;
  }
  window.EraFormat = { num, pm, step, counted, columns, importChoices };
})();

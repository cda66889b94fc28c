// Calls to the backend. Errors come back as {error: message, option?}; they are thrown as Error(message)
// with .option.

// A busy server (503) or a rate limit (429) says when to come back (Retry-After): the page waits and sends the
// request again by itself, at most RETRIES times, saying so through `progress`.
const RETRIES = 10;
const retryAfter = (res) => Math.min(60, Math.max(1, Number(res.headers.get("Retry-After")) || 2));
const sleep = (s) => new Promise((resolve) => setTimeout(resolve, 1000 * s));

// progress: optional callback(text) called while heavy work is queued or running (GET /api/jobs/{key}).
export async function api(path, { method = "GET", body, progress } = {}) {
  const opts = { method, headers: {} };
  if (body !== undefined) {
    opts.headers["Content-Type"] = "application/json";
    opts.body = JSON.stringify(body);
  }
  const stop = progress ? watch(opts.headers, progress) : () => {};
  try {
    for (let attempt = 0; ; attempt++) {
      const res = await fetch(path, opts);
      let payload = null;
      try { payload = await res.json(); } catch { /* not JSON */ }
      if ((res.status === 503 || res.status === 429) && attempt < RETRIES) {
        const wait = retryAfter(res);
        if (progress) progress(`The server is busy; trying again in ${wait} s…`);
        await sleep(wait);
        continue;
      }
      if (!res.ok) throw refusal(payload, `${res.status} ${res.statusText}`);
      return payload;
    }
  } finally {
    stop();
  }
}

// An Error with the server's sentence; ``option`` names the form control that fixes it (schemas.Error).
function refusal(payload, fallback) {
  const err = new Error((payload && payload.error) || fallback);
  err.option = (payload && payload.option) || null;
  return err;
}

export function describe(p) {
  if (p.state === "queued") {
    return `Waiting for ${p.queued_ahead + p.running_total} other ${p.queued_ahead + p.running_total === 1 ? "computation" : "computations"} to finish… ${p.seconds.toFixed(1)} s`;
  }
  return `${p.message}… ${p.seconds.toFixed(1)} s`;
}

// Name the request with a random key and poll its progress until stop() is called.
function watch(headers, callback) {
  const key = Array.from(crypto.getRandomValues(new Uint8Array(16)), (b) => b.toString(16).padStart(2, "0")).join("");
  headers["X-Progress-Key"] = key;
  let active = true;
  const poll = async () => {
    if (!active) return;
    try {
      const res = await fetch(`/api/jobs/${key}`);
      if (res.ok && active) callback(describe(await res.json()));
    } catch { /* progress is best effort */ }
    if (active) timer = setTimeout(poll, 400);
  };
  let timer = setTimeout(poll, 300);
  return () => { active = false; clearTimeout(timer); };
}

// Multipart upload of one File or an array of them, with progress (fetch cannot report upload progress;
// XMLHttpRequest can).
// onProgress(fraction) while the bytes go up; onWork(text) while the server reads the file.
export async function upload(path, file, onProgress, onWork, fields = {}) {
  for (let attempt = 0; ; attempt++) {
    try {
      return await uploadOnce(path, file, onProgress, onWork, fields);
    } catch (err) {
      if (!err.retryAfter || attempt >= RETRIES) throw err;
      if (onWork) onWork(`The server is busy; trying again in ${err.retryAfter} s…`);
      await sleep(err.retryAfter);
    }
  }
}

function uploadOnce(path, file, onProgress, onWork, fields) {
  return new Promise((resolve, reject) => {
    const xhr = new XMLHttpRequest();
    xhr.open("POST", path);
    const headers = {};
    const stop = watch(headers, onWork || (() => {}));
    for (const [k, v] of Object.entries(headers)) xhr.setRequestHeader(k, v);
    xhr.upload.onprogress = (e) => { if (e.lengthComputable) onProgress(e.loaded / e.total); };
    xhr.onloadend = stop;
    xhr.onload = () => {
      let payload = null;
      try { payload = JSON.parse(xhr.responseText); } catch { /* not JSON */ }
      if (xhr.status >= 200 && xhr.status < 300) { resolve(payload); return; }
      const err = refusal(payload, `${xhr.status} ${xhr.statusText}`);
      if (xhr.status === 503 || xhr.status === 429) {
        err.retryAfter = Math.min(60, Math.max(1, Number(xhr.getResponseHeader("Retry-After")) || 2));
      }
      reject(err);
    };
    xhr.onerror = () => reject(new Error("The upload failed: the server could not be reached."));
    const form = new FormData();
    for (const f of [].concat(file)) form.append("file", f, f.name);  // several files: one dataset
    for (const [k, v] of Object.entries(fields)) form.append(k, v);
    xhr.send(form);
  });
}

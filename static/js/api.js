// Calls to the backend. Errors come back as {error: message}; they are thrown as Error(message).

export async function api(path, { method = "GET", body } = {}) {
  const opts = { method, headers: {} };
  if (body !== undefined) {
    opts.headers["Content-Type"] = "application/json";
    opts.body = JSON.stringify(body);
  }
  const res = await fetch(path, opts);
  let payload = null;
  try { payload = await res.json(); } catch { /* not JSON */ }
  if (!res.ok) throw new Error((payload && payload.error) || `${res.status} ${res.statusText}`);
  return payload;
}

// Multipart upload with progress (fetch cannot report upload progress; XMLHttpRequest can).
export function upload(path, file, onProgress) {
  return new Promise((resolve, reject) => {
    const xhr = new XMLHttpRequest();
    xhr.open("POST", path);
    xhr.upload.onprogress = (e) => { if (e.lengthComputable) onProgress(e.loaded / e.total); };
    xhr.onload = () => {
      let payload = null;
      try { payload = JSON.parse(xhr.responseText); } catch { /* not JSON */ }
      if (xhr.status >= 200 && xhr.status < 300) resolve(payload);
      else reject(new Error((payload && payload.error) || `${xhr.status} ${xhr.statusText}`));
    };
    xhr.onerror = () => reject(new Error("The upload failed: the server could not be reached."));
    const form = new FormData();
    form.append("file", file, file.name);
    xhr.send(form);
  });
}

"""Every operation of the app's own OpenAPI, sent bounded hostile examples (issue 29): integers past 64 bits,
negative and non-numeric values, NaN and 1e400, NUL and 10 000-character strings, bodies of the wrong JSON type, for
each query parameter and each JSON body field in turn, on real ids. The contract: never a 5xx, only statuses the
operation declares, and every refusal the documented ``{"error"}``."""

from __future__ import annotations

import re

from apiclient import analysis, client

BIG = 99999999999999999999
QUERY = {"integer": [str(BIG), "-1", "9223372036854775808", "x"], "number": ["nan", "inf", "1e400", "x"],
         "boolean": ["maybe"], "string": ["a", str(BIG), "-1", ",,", "0,0,0", "\x00"]}
FIELD = {"integer": [BIG, -BIG, 2**63, "x", 1.5], "number": [1e308, -1e308, "x"],
         "string": ["", "\x00", "x" * 10_000, 5], "boolean": ["maybe"], "array": [[BIG], [], ["x"], "x"],
         "object": [[], "x"]}


def _type(schema: dict, spec: dict) -> str | None:
    while "$ref" in schema:
        schema = spec["components"]["schemas"][schema["$ref"].rsplit("/", 1)[-1]]
    if "type" in schema:
        return schema["type"]
    for option in schema.get("anyOf", []):
        if option.get("type") != "null":
            return _type(option, spec)
    return None


def _resolve(schema: dict, spec: dict) -> dict:
    while "$ref" in schema:
        schema = spec["components"]["schemas"][schema["$ref"].rsplit("/", 1)[-1]]
    return schema


def _checked(r, declared: dict, what: str) -> None:
    assert r.status_code < 500, (what, r.status_code, r.text[:300])
    assert str(r.status_code) in declared, (what, r.status_code, sorted(declared))
    if r.status_code >= 400:
        body = r.json()
        assert set(body) <= {"error", "option"} and body["error"], (what, body)


def test_hostile_examples_of_every_operation_get_documented_answers(tmp_path):
    with client(tmp_path, raise_errors=False) as c:
        ds, an = analysis(c, rows=20, cols=20)
        token = c.post("/api/reports", json={"analysis_id": an["id"], "order": 4, "modes": [0]}).json()["token"]
        staged = c.post("/api/imports", files={"file": ("y.csv", b"t,a,b\n" + b"".join(
            f"{k / 100},{k % 7},{k % 5}\n".encode() for k in range(200)))}).json()["id"]
        ids = {"dataset_id": ds["id"], "analysis_id": an["id"], "token": token, "name": "case1",
               "upload_id": staged, "campaign_id": "nope", "key": "nope-nope-nope"}
        good = {"/api/analyses": {"dataset_id": ds["id"], "rows": 20, "cols": 20},  # each field mutated from these
                "/api/reports": {"analysis_id": an["id"], "order": 4, "modes": [0]},
                "/api/analyses/{analysis_id}/viewer": {"order": 4},
                "/api/analyses/{analysis_id}/explain": {"modes": "kept", "order": 4, "kept": [0]}}
        spec = c.get("/openapi.json").json()
        sent = 0
        for path, ops in spec["paths"].items():
            url = re.sub(r"\{([^}]+)\}", lambda m: ids.get(m.group(1), "nope"), path)
            for method, op in ops.items():
                if method == "post" and path in ("/api/examples/{name}", "/api/campaigns"):
                    continue  # whole examples and campaigns: their refusals have tests of their own
                declared = op["responses"]
                base = {p["name"]: "4" for p in op.get("parameters", []) if p["in"] == "query" and p.get("required")}
                for p in op.get("parameters", []):
                    if p["in"] != "query":
                        continue
                    for value in QUERY.get(_type(p["schema"], spec), []):
                        r = c.request(method, url, params=dict(base, **{p["name"]: value}))
                        _checked(r, declared, f"{method} {path} ?{p['name']}={value!r}")
                        sent += 1
                content = op.get("requestBody", {}).get("content", {})
                if "application/json" not in content:
                    continue
                schema = _resolve(content["application/json"]["schema"], spec)
                for body in ([], "x", None, 1):
                    _checked(c.request(method, url, json=body), declared, f"{method} {path} body {body!r}")
                    sent += 1
                for name, prop in schema.get("properties", {}).items():
                    for value in FIELD.get(_type(prop, spec), []):
                        r = c.request(method, url, json=dict(good.get(path, {}), **{name: value}))
                        _checked(r, declared, f"{method} {path} {name}={str(value)[:40]!r}")
                        sent += 1
        assert sent > 150, sent
        print(f"{sent} hostile requests, none answered 5xx or undocumented")

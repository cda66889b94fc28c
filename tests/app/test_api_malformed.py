"""Malformed requests (issue 29): integers past 64 bits, bodies that are not UTF-8 or not multipart, unknown ids
on routes whose success is HTML or CSV. Each is answered with a status the OpenAPI declares, in the content type
it declares, as ``{"error": ...}``: never a 500, never ``{"detail": ...}``, never a number the user did not send."""

from __future__ import annotations

import re

import pytest

from apiclient import analysis, client

BIG = 99999999999999999999
I64 = 9223372036854775808


def refusal(r, status: int | tuple = (400, 422)) -> str:
    assert r.status_code in ((status,) if isinstance(status, int) else status), (r.status_code, r.text)
    assert r.headers["content-type"].startswith("application/json")
    body = r.json()
    assert set(body) <= {"error", "option"} and body["error"], body
    return body["error"]


def test_integers_past_64_bits_are_422_naming_the_field_not_500(tmp_path):
    with client(tmp_path, raise_errors=False) as c:
        dataset, an = analysis(c, rows=20, cols=20)
        ds, a = dataset["id"], an["id"]
        said = refusal(c.post("/api/analyses", json={"dataset_id": ds, "rows": 20, "cols": 20,
                                                     "row_shifts": [BIG]}), 422)
        assert "row_shifts" in said and "2147483647" in said
        said = refusal(c.post("/api/analyses", json={"dataset_id": ds, "rows": 3, "cols": 3,
                                                     "col_shifts": [1, I64]}), 422)
        assert "col_shifts" in said and "-9223372036854775808" not in said
        for r in (c.get(f"/api/analyses/{a}/step", params={"order": 4, "output": I64}),
                  c.get(f"/api/analyses/{a}/modes", params={"order": BIG}),
                  c.post("/api/reports", json={"analysis_id": a, "order": 4, "modes": [BIG]}),
                  c.post(f"/api/analyses/{a}/explain", json={"order": BIG}),
                  c.post("/api/datasets", files={"file": ("a.csv", b"t,y\n0,1\n0.1,2\n")},
                         data={"start_sample": str(BIG)})):
            refusal(r, 422)
        said = refusal(c.post("/api/datasets", files={"file": ("a.csv", b"t,y,z\n0,1,2\n0.1,2,3\n0.2,3,3\n")},
                              data={"drop": str(BIG)}), 422)
        assert str(BIG) in said  # the number as sent


@pytest.mark.parametrize("headers, body", [
    ({"content-type": "multipart/form-data"}, b"\xff\xfe"),                              # no boundary
    ({"content-type": "multipart/form-data; boundary=xx"}, b"--xx\r\nbroken"),          # cut
    ({"content-type": "multipart/form-data; boundary=xx"},
     b'--xx\r\nContent-Disposition: form-data; name="kind"\r\n\r\n\xff\xfe\r\n--xx--\r\n'),  # not UTF-8
    ({"content-type": "application/x-www-form-urlencoded"}, b"kind=\xff\xfe"),
])
def test_malformed_upload_bodies_are_the_documented_error_shape(tmp_path, headers, body):
    with client(tmp_path, raise_errors=False) as c:
        for route in ("/api/datasets", "/api/imports", "/api/campaigns"):
            refusal(c.post(route, content=body, headers=headers))


def test_a_json_body_that_is_not_utf8_is_refused_as_error(tmp_path):
    with client(tmp_path, raise_errors=False) as c:
        for route in ("/api/analyses", "/api/reports", "/api/imports/nope/preview"):
            refusal(c.post(route, content=b"\xff\xfe{bad", headers={"content-type": "application/json"}))


def test_every_error_of_every_get_route_is_served_as_the_openapi_declares(tmp_path):
    """Unknown ids on every GET route (report.html, modes.csv, files, campaign pages included): the status is
    declared for the operation and the answer's content type is the declared one."""
    with client(tmp_path, raise_errors=False) as c:
        spec = c.get("/openapi.json").json()
        checked = 0
        for path, ops in spec["paths"].items():
            if "get" not in ops or "{" not in path:
                continue
            r = c.get(re.sub(r"\{[^}]+\}", "nope", path))
            declared = ops["get"]["responses"]
            assert str(r.status_code) in declared, (path, r.status_code, sorted(declared))
            if r.status_code >= 400:
                content = declared[str(r.status_code)].get("content", {})
                assert r.headers["content-type"].split(";")[0] in content, (path, r.headers["content-type"], content)
                refusal(r, r.status_code)
                checked += 1
        assert checked >= 10
        html = spec["paths"]["/api/reports/{token}/report.html"]["get"]["responses"]
        assert list(html["404"]["content"]) == ["application/json"] and "text/html" in html["200"]["content"]
        assert c.get("/api/no-such-route").json()["error"]

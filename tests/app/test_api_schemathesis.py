"""Schemathesis on the app's own OpenAPI (issue 29): bounded generated examples for every operation, sent to a real
server on 127.0.0.1 (uvicorn in a subprocess, a temporary data folder). The contract: never a 5xx, and only the
statuses each operation declares. tests/app/test_api_openapi_fuzz.py adds hand-made hostile values on real ids."""

from __future__ import annotations

import pytest
import schemathesis
from hypothesis import HealthCheck, settings
from schemathesis.specs.openapi.checks import status_code_conformance

from apiclient import live_server

EXAMPLES = 10  # per operation: 38 operations in about 15 s


@pytest.fixture(scope="module")
def api_schema(tmp_path_factory):
    folder = tmp_path_factory.mktemp("schemathesis")
    with open(folder / "server.log", "wb") as log, \
            live_server(folder / "data", log=log, ERA_RATE_LIMIT="100000/min") as (base, _):
        yield schemathesis.openapi.from_url(base + "/openapi.json")


schema = schemathesis.pytest.from_fixture("api_schema")


@schema.parametrize()
@settings(max_examples=EXAMPLES, deadline=None, suppress_health_check=list(HealthCheck))
def test_every_operation_answers_a_documented_status_and_never_a_5xx(case):
    case.call_and_validate(checks=[schemathesis.checks.not_a_server_error, status_code_conformance])

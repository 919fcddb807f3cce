"""swum-emu's HTTP control API (--http) against its contract, docs/openapi.yaml.

Every response any test here receives is checked against the document: its status must be one
documented for the operation, and a JSON body must validate against the documented schema (an
undocumented path must be a 404 with an Error body). test_openapi_every_operation additionally
exercises every documented (path, method) and fails when the document and the server's routes
drift apart.

Run: SWUM_EMU=build/ci/firmware_sim/swum-emu SWUM_SOURCE_DIR=. /usr/bin/python3 -m pytest -q \
     tests/firmware_sim/http_api_test.py -p no:cacheprovider
Only the standard library speaks HTTP here (http.client, socket); pymodbus plays the controller.
No sleeps as synchronisation: everything that waits polls with a deadline.
"""
import csv
import http.client
import io
import json
import os
import re
import signal
import socket
import subprocess
import sys
import time
import urllib.parse

import jsonschema
import pytest
import yaml

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
try:
    import serial_asyncio  # noqa: F401  (pymodbus.client imports it; only Recommended by Debian)
except ImportError:
    import types
    sys.modules["serial_asyncio"] = types.SimpleNamespace(create_serial_connection=None)
from pymodbus.client import ModbusTcpClient  # noqa: E402

import emu_harness  # noqa: E402
from emu_harness import CONFIG, SOURCE_DIR, Emulator, RegisterMap  # noqa: E402

OPENAPI_PATH = os.path.join(SOURCE_DIR, "docs/openapi.yaml")
RECORDING_SOURCE = os.path.join(SOURCE_DIR, "firmware_sim/http_recording.cpp")
TOKEN = "s3cret-token"
TICK_HZ = 10000.0  # swum-emu's default --tick-hz
FAULT_CODE_OVER_TEMPERATURE = 4


# ---------------------------------------------------------------------------------------------
# The contract: docs/openapi.yaml
# ---------------------------------------------------------------------------------------------

class Contract:
    """docs/openapi.yaml, and the check of one response against it."""

    def __init__(self, path):
        with open(path) as f:
            self.doc = yaml.safe_load(f)
        self.resolver = jsonschema.RefResolver.from_schema(self.doc)
        self.templates = []  # (regex, template) for each documented path
        for template in self.doc["paths"]:
            pattern = "^" + re.sub(r"\\\{[^}]+\\\}", "[^/]+", re.escape(template)) + "$"
            self.templates.append((re.compile(pattern), template))

    def operations(self):
        return {(t, m.upper()) for t, item in self.doc["paths"].items() for m in item
                if m in ("get", "put", "post", "delete", "patch", "head", "options")}

    def deref(self, node):
        while isinstance(node, dict) and "$ref" in node:
            _, node = self.resolver.resolve(node["$ref"])
        return node

    def validate(self, instance, schema, what):
        validator_class = jsonschema.validators.validator_for(
            {"$schema": "https://json-schema.org/draft/2020-12/schema"})
        validator = validator_class(schema, resolver=self.resolver)
        errors = sorted(validator.iter_errors(instance), key=lambda e: list(e.absolute_path))
        assert not errors, f"{what}: does not match docs/openapi.yaml: " + "; ".join(
            f"at /{'/'.join(map(str, e.absolute_path))}: {e.message}" for e in errors[:5])

    def template_of(self, path):
        path = urllib.parse.urlsplit(path).path
        for regex, template in self.templates:
            if regex.match(path):
                return template
        return None

    def response_spec(self, template, method, status):
        operation = self.doc["paths"][template][method.lower()]
        responses = operation["responses"]
        assert str(status) in responses, (
            f"{method} {template} answered {status}, not documented (documented: {sorted(responses)})")
        return self.deref(responses[str(status)])

    def check(self, method, path, reply):
        """Checks one response; returns its operation (template, METHOD), or None when undocumented."""
        template = self.template_of(path)
        if template is None or method.lower() not in self.doc["paths"][template]:
            # The token is checked first: without it any /api/ path is 401, documented or not.
            allowed = (404, 401) if urllib.parse.urlsplit(path).path.startswith("/api/") else (404,)
            assert reply.status in allowed, f"{method} {path}: undocumented, yet answered {reply.status}"
            assert_error_body(reply)
            return None
        spec = self.response_spec(template, method, reply.status)
        content = spec.get("content")
        if content is not None:
            media = reply.media_type
            assert media in content, f"{method} {template} {reply.status}: Content-Type {media} not in {list(content)}"
            if media == "application/json":
                self.validate(reply.json(), content[media]["schema"], f"{method} {path} {reply.status}")
        for name in spec.get("headers") or {}:
            assert reply.headers.get(name) is not None, f"{method} {template} {reply.status}: no {name} header"
        return (template, method.upper())

    def event_schema(self, name):
        media = self.doc["paths"]["/api/v1/stream"]["get"]["responses"]["200"]["content"]["text/event-stream"]
        return media["x-events"][name]["data"]

    def schema(self, name):
        return {"$ref": f"#/components/schemas/{name}"}


CONTRACT = Contract(OPENAPI_PATH)


# ---------------------------------------------------------------------------------------------
# HTTP helpers
# ---------------------------------------------------------------------------------------------

class Reply:
    def __init__(self, status, headers, body, operation=None):
        self.status = status
        self.headers = headers  # http.client.HTTPMessage: case-insensitive get()
        self.body = body
        self.operation = operation

    @property
    def media_type(self):
        return (self.headers.get("Content-Type") or "").split(";")[0].strip()

    def json(self):
        return json.loads(self.body)

    def __repr__(self):
        return f"Reply({self.status}, {self.body[:300]!r})"


def assert_error_body(reply):
    """A refusal: {"error": "one line"}, ending in a newline, JSON."""
    assert reply.media_type == "application/json", reply
    text = reply.body.decode()
    assert text.endswith("\n") and text.count("\n") == 1, f"error body not one line: {text!r}"
    body = json.loads(text)
    assert set(body) == {"error"} and isinstance(body["error"], str) and body["error"], body
    return body["error"]


_NO_JSON = object()


class Api:
    """HTTP client of one emulator: a fresh connection per request; every reply checked against
    docs/openapi.yaml (CONTRACT)."""

    def __init__(self, emu, token=None):
        m = re.search(r"http=http://([\d.]+):(\d+)", emu.ready)
        assert m, f"no http= in the ready line: {emu.ready!r}"
        self.host, self.port = m.group(1), int(m.group(2))
        self.token = token

    def connection(self, timeout=10):
        return http.client.HTTPConnection(self.host, self.port, timeout=timeout)

    def _headers(self, headers, token):
        h = {}
        token = self.token if token is None else token
        if token:
            h["Authorization"] = f"Bearer {token}"
        h.update(headers or {})
        return h

    def request(self, method, path, json_body=_NO_JSON, *, body=None, headers=None, token=None,
                content_type="application/json", timeout=10):
        """(status, headers, body) as a Reply. json_body: a value sent as JSON; body: raw bytes."""
        h = self._headers(headers, token)
        if json_body is not _NO_JSON:
            body = json.dumps(json_body).encode()
        if body is not None and content_type is not None:
            h.setdefault("Content-Type", content_type)
        conn = self.connection(timeout)
        try:
            conn.request(method, path, body=body, headers=h)
            response = conn.getresponse()
            reply = Reply(response.status, response.headers, response.read())
        finally:
            conn.close()
        reply.operation = CONTRACT.check(method, path, reply)
        return reply

    def get(self, path, **kw):
        return self.request("GET", path, **kw)

    def post(self, path, json_body=_NO_JSON, **kw):
        return self.request("POST", path, json_body, **kw)

    def delete(self, path, **kw):
        return self.request("DELETE", path, **kw)

    def ok(self, method, path, json_body=_NO_JSON, status=200, **kw):
        reply = self.request(method, path, json_body, **kw)
        assert reply.status == status, f"{method} {path}: {reply}"
        return reply.json() if reply.media_type == "application/json" else reply

    def state(self):
        return self.ok("GET", "/api/v1/state")

    def stats(self):
        return self.ok("GET", "/api/v1/stats")

    def faults(self):
        return self.ok("GET", "/api/v1/faults")

    def recording(self):
        return self.ok("GET", "/api/v1/recording")

    def open_stream(self, query="", token=None, timeout=10):
        """GET /api/v1/stream: returns a Stream (200) or the refusal's Reply."""
        conn = self.connection(timeout)
        path = "/api/v1/stream" + (("?" + query) if query else "")
        conn.request("GET", path, headers=self._headers({"Accept": "text/event-stream"}, token))
        response = conn.getresponse()
        if response.status != 200:
            reply = Reply(response.status, response.headers, response.read())
            conn.close()
            reply.operation = CONTRACT.check("GET", path, reply)
            return reply
        reply = Reply(response.status, response.headers, b"")
        reply.operation = CONTRACT.check("GET", path, reply)
        assert reply.media_type == "text/event-stream"
        assert response.headers.get("Cache-Control") == "no-store"
        return Stream(conn, response, reply)


class Stream:
    """An open /api/v1/stream: events read one by one, each data checked against the document."""

    def __init__(self, conn, response, reply):
        self.conn, self.response, self.reply = conn, response, reply
        self.status = reply.status
        self.operation = reply.operation

    def next_event(self):
        name, data = None, []
        while True:
            line = self.response.readline()
            assert line, "the stream ended"
            line = line.decode().rstrip("\n")
            if line == "":
                if name is None and not data:
                    continue
                break
            field, _, value = line.partition(":")
            value = value[1:] if value.startswith(" ") else value
            if field == "event":
                name = value
            elif field == "data":
                data.append(value)
        assert name == "telemetry", f"event {name!r}"
        state = json.loads("\n".join(data))
        CONTRACT.validate(state, CONTRACT.event_schema(name), "stream event data")
        return state

    def close(self):
        self.response.close()
        self.conn.close()


def poll(what, predicate, timeout=10.0, interval=0.01):
    """predicate() until truthy (returned), or fail naming `what` after `timeout` s."""
    end = time.monotonic() + timeout
    last = None
    while time.monotonic() < end:
        last = predicate()
        if last:
            return last
        time.sleep(interval)  # a polling interval, not a synchronisation
    pytest.fail(f"timed out after {timeout} s waiting for {what} (last: {last!r})")


def active_types(api):
    return [f["type"] for f in api.faults()["active"]]


def recording_header():
    """kRecordingHeader of firmware_sim/http_recording.cpp (its string literals joined)."""
    with open(RECORDING_SOURCE) as f:
        source = f.read()
    m = re.search(r"kRecordingHeader\s*=\s*((?:\s*\"[^\"]*\")+)\s*;", source)
    assert m, "kRecordingHeader not found in http_recording.cpp"
    return "".join(re.findall(r"\"([^\"]*)\"", m.group(1)))


# ---------------------------------------------------------------------------------------------
# Fixtures: emulators with --http, each stopped by its pid
# ---------------------------------------------------------------------------------------------

def start_emulator(*args):
    return Emulator("--http", "127.0.0.1:0", *args)


def stop_emulator(emu):
    rc = emu.stop(timeout=30)  # SIGTERM to its pid; waits
    assert rc == 0, f"swum-emu exited {rc}: {emu.stderr}"


@pytest.fixture
def emulator_factory():
    """start(*args) -> (emu, api); every emulator started is stopped (by pid) at teardown."""
    started = []

    def start(*args, token=None):
        emu = start_emulator(*args)
        started.append(emu)
        return emu, Api(emu, token=token)

    yield start
    for emu in started:
        with emu:
            stop_emulator(emu)


@pytest.fixture
def api(emulator_factory):
    """An emulator on its internal clock with --http."""
    return emulator_factory()[1]


@pytest.fixture
def lockstep_api(emulator_factory):
    """An emulator with --clock external and --http."""
    return emulator_factory("--clock", "external")[1]


MAX_BODY = 256


@pytest.fixture(scope="module")
def shared_api():
    """One internal-clock emulator for the tests that must change nothing (--http-max-body-bytes 256)."""
    emu = start_emulator("--http-max-body-bytes", str(MAX_BODY))
    with emu:
        yield Api(emu)
        stop_emulator(emu)


@pytest.fixture(scope="module")
def shared_lockstep_api():
    emu = start_emulator("--clock", "external")
    with emu:
        yield Api(emu)
        stop_emulator(emu)


# ---------------------------------------------------------------------------------------------
# The document itself, and every operation in it
# ---------------------------------------------------------------------------------------------

def test_openapi_document_is_well_formed():
    doc = CONTRACT.doc
    assert doc["openapi"].startswith("3.1")
    for name, schema in doc["components"]["schemas"].items():
        jsonschema.Draft202012Validator.check_schema(schema)
    schemes = doc["components"]["securitySchemes"]
    assert schemes["bearerAuth"] == {**schemes["bearerAuth"], "type": "http", "scheme": "bearer"}
    assert schemes["queryToken"]["in"] == "query" and schemes["queryToken"]["name"] == "token"
    for template, item in doc["paths"].items():
        for method, operation in item.items():
            responses = operation["responses"]
            assert responses, f"{method} {template}: no responses"
            if template.startswith("/api/"):
                assert "security" not in operation, f"{method} {template}: /api/ paths take the global security"
                assert "401" in responses, f"{method} {template}: no 401"
            else:
                assert operation.get("security") == [], f"{method} {template}: the page needs no token"
            for status, response in responses.items():
                response = CONTRACT.deref(response)
                for media, content in (response.get("content") or {}).items():
                    if media == "application/json":
                        assert "schema" in content, f"{method} {template} {status}: no schema"
                    if int(status) >= 400:
                        assert media == "application/json" and content["schema"] == CONTRACT.schema("Error"), (
                            f"{method} {template} {status}: a refusal's body is an Error")


def test_openapi_every_operation(emulator_factory):
    """Each documented (path, method) answered with a documented status and a conforming body,
    and exactly the documented operations exist."""
    emu, api = emulator_factory("--clock", "external")
    replies = []

    def call(method, path, json_body=_NO_JSON, status=200, **kw):
        if json_body is not _NO_JSON:  # what we send conforms too
            operation = CONTRACT.doc["paths"][CONTRACT.template_of(path)][method.lower()]
            schema = operation["requestBody"]["content"]["application/json"]["schema"]
            CONTRACT.validate(json_body, schema, f"request body of {method} {path}")
        reply = api.request(method, path, json_body, **kw)
        assert reply.status == status, f"{method} {path}: {reply}"
        replies.append(reply)
        return reply

    for asset in ("/", "/dashboard.js", "/dashboard.css", "/uPlot.iife.min.js", "/uPlot.min.css"):
        assert call("GET", asset).body
    call("GET", "/api/v1/state")
    call("GET", "/api/v1/stats")
    call("GET", "/api/v1/faults")
    call("GET", "/api/v1/recording")
    call("POST", "/api/v1/faults", {"type": "voltage_sag", "factor": 0.5, "duration_s": 0}, status=202)
    call("DELETE", "/api/v1/faults/voltage_sag", status=202)
    call("DELETE", "/api/v1/faults", status=202)
    call("POST", "/api/v1/recording/start")
    call("POST", "/api/v1/step", {"ticks": 50})
    stopped = call("POST", "/api/v1/recording/stop").json()
    assert stopped["rows"] == 50, stopped
    csv_reply = call("GET", "/api/v1/recording.csv")
    assert csv_reply.media_type == "text/csv"
    stream = api.open_stream("rate_hz=50")
    try:
        assert stream.status == 200
        replies.append(stream)
        stream.next_event()
        stream.next_event()
    finally:
        stream.close()

    # An undocumented path: 404 with an Error body (checked by CONTRACT.check).
    nothing = api.get("/api/v1/nothing")
    assert nothing.status == 404 and nothing.operation is None
    assert api.request("PUT", "/api/v1/state", {}).status == 404

    exercised = {r.operation for r in replies}
    assert None not in exercised
    assert exercised == CONTRACT.operations(), (
        f"documented but not exercised: {sorted(CONTRACT.operations() - exercised)}; "
        f"exercised but not documented: {sorted(exercised - CONTRACT.operations())}")


# ---------------------------------------------------------------------------------------------
# Bad requests: 4xx, one-line Error, nothing changed
# ---------------------------------------------------------------------------------------------

def snapshot(api):
    """What a refused request must not change."""
    state = api.state()
    faults = api.faults()
    return {"active": faults["active"], "refused": faults["refused"], "fault": state["fault"],
            "fault_code": state["fault_code"], "active_faults": state["active_faults"],
            "faults_queued": api.stats()["http"]["faults_queued"]}


PADDED = (b'{"type": "phase_open", "phase": "B"' + b" " * 1000 + b"}")
BAD_REQUESTS = [
    # id, method, path, body (bytes or None), content type, expected status
    ("malformed-json", "POST", "/api/v1/faults", b'{"type": "phase_open",', "application/json", 400),
    ("empty-body", "POST", "/api/v1/faults", b"", "application/json", 400),
    ("json-array", "POST", "/api/v1/faults", b'[{"type": "phase_open", "phase": "B"}]', "application/json", 400),
    ("json-string", "POST", "/api/v1/faults", b'"phase_open"', "application/json", 400),
    ("no-type", "POST", "/api/v1/faults", b'{"phase": "B"}', "application/json", 400),
    ("type-not-string", "POST", "/api/v1/faults", b'{"type": 5}', "application/json", 400),
    ("unknown-fault", "POST", "/api/v1/faults", b'{"type": "no_such_fault"}', "application/json", 400),
    ("not-a-fault", "POST", "/api/v1/faults", b'{"type": "load_step", "load_n": 1}', "application/json", 400),
    ("ambient-not-a-fault", "POST", "/api/v1/faults", b'{"type": "ambient", "temperature_c": 30}',
     "application/json", 400),
    ("out-of-range", "POST", "/api/v1/faults", b'{"type": "voltage_sag", "factor": 2}', "application/json", 400),
    ("negative-duration", "POST", "/api/v1/faults", b'{"type": "phase_open", "phase": "B", "duration_s": -1}',
     "application/json", 400),
    ("wrong-key", "POST", "/api/v1/faults", b'{"type": "voltage_sag", "factr": 0.5}', "application/json", 400),
    ("missing-key", "POST", "/api/v1/faults", b'{"type": "phase_open"}', "application/json", 400),
    ("bad-phase", "POST", "/api/v1/faults", b'{"type": "phase_open", "phase": "C"}', "application/json", 400),
    ("boolean-value", "POST", "/api/v1/faults", b'{"type": "phase_open", "phase": "B", "duration_s": true}',
     "application/json", 400),
    ("null-value", "POST", "/api/v1/faults", b'{"type": "voltage_sag", "factor": null}', "application/json", 400),
    ("object-value", "POST", "/api/v1/faults", b'{"type": "voltage_sag", "factor": {"v": 1}}',
     "application/json", 400),
    ("number-as-string", "POST", "/api/v1/faults", b'{"type": "voltage_sag", "factor": "0.5"}',
     "application/json", 400),
    ("integer-key-float", "POST", "/api/v1/faults", b'{"type": "modbus_drop", "count": 1.5}', "application/json", 400),
    ("integer-key-huge", "POST", "/api/v1/faults", b'{"type": "modbus_drop", "count": 18446744073709551615}',
     "application/json", 400),
    ("number-overflow", "POST", "/api/v1/faults", b'{"type": "voltage_sag", "factor": 1e400}', "application/json", 400),
    ("clear-not-a-fault", "POST", "/api/v1/faults", b'{"type": "clear", "fault": "load_step"}', "application/json", 400),
    ("oversized", "POST", "/api/v1/faults", PADDED, "application/json", 413),
    ("text-plain", "POST", "/api/v1/faults", b'{"type": "phase_open", "phase": "B"}', "text/plain", 415),
    ("form", "POST", "/api/v1/faults", b"type=phase_open&phase=B", "application/x-www-form-urlencoded", 415),
    ("delete-not-a-fault-name", "DELETE", "/api/v1/faults/not_a_fault", None, None, 404),
    ("delete-load-step", "DELETE", "/api/v1/faults/load_step", None, None, 400),
    ("delete-clear", "DELETE", "/api/v1/faults/clear", None, None, 400),
    ("stream-rate-0", "GET", "/api/v1/stream?rate_hz=0", None, None, 400),
    ("stream-rate-1000", "GET", "/api/v1/stream?rate_hz=1000", None, None, 400),
    ("stream-rate-abc", "GET", "/api/v1/stream?rate_hz=abc", None, None, 400),
    ("stream-rate-negative", "GET", "/api/v1/stream?rate_hz=-5", None, None, 400),
    ("stream-rate-nan", "GET", "/api/v1/stream?rate_hz=nan", None, None, 400),
    ("stream-rate-empty", "GET", "/api/v1/stream?rate_hz=", None, None, 400),
    ("step-internal-clock", "POST", "/api/v1/step", b'{"ticks": 100}', "application/json", 409),
    ("recording-stop-without-start", "POST", "/api/v1/recording/stop", None, None, 409),
    ("download-before-recording", "GET", "/api/v1/recording.csv", None, None, 404),
    ("undocumented-path", "GET", "/api/v1/nothing", None, None, 404),
    ("undocumented-method", "PUT", "/api/v1/faults", b'{"type": "phase_open", "phase": "B"}', "application/json", 404),
]


@pytest.mark.parametrize("method,path,body,content_type,status", [c[1:] for c in BAD_REQUESTS],
                         ids=[c[0] for c in BAD_REQUESTS])
def test_bad_request_changes_nothing(shared_api, method, path, body, content_type, status):
    before = snapshot(shared_api)
    reply = shared_api.request(method, path, body=body, content_type=content_type)
    assert reply.status == status, reply
    assert_error_body(reply)
    after = snapshot(shared_api)
    assert after == before
    assert after["active"] == [] and after["fault"] == "none"
    recording = shared_api.recording()
    assert not recording["recording"] and not recording["available"]


def test_duplicate_key_is_refused(api):
    before = snapshot(api)
    reply = api.request("POST", "/api/v1/faults", body=b'{"type": "voltage_sag", "factor": 0.5, "factor": 0.6}')
    assert reply.status == 400, reply
    assert_error_body(reply)
    assert snapshot(api) == before


STEP_BAD_BODIES = [
    ("zero", b'{"ticks": 0}'),
    ("negative", b'{"ticks": -1}'),
    ("fraction", b'{"ticks": 1.5}'),
    ("string", b'{"ticks": "100"}'),
    ("boolean", b'{"ticks": true}'),
    ("over-60-s", b'{"ticks": 600001}'),
    ("huge", b'{"ticks": 18446744073709551615}'),
    ("both", b'{"ticks": 100, "seconds": 0.01}'),
    ("neither", b"{}"),
    ("unknown-key", b'{"ticks": 100, "tick": 1}'),
    ("half-a-tick", b'{"seconds": 0.00005}'),
    ("seconds-zero", b'{"seconds": 0}'),
    ("seconds-negative", b'{"seconds": -0.01}'),
    ("seconds-string", b'{"seconds": "0.01"}'),
    ("malformed", b'{"ticks": '),
    ("array", b"[100]"),
    ("empty", b""),
]


@pytest.mark.parametrize("body", [b for _, b in STEP_BAD_BODIES], ids=[n for n, _ in STEP_BAD_BODIES])
def test_step_bad_body_in_lockstep(shared_lockstep_api, body):
    api = shared_lockstep_api
    tick = api.state()["tick"]
    reply = api.request("POST", "/api/v1/step", body=body)
    assert reply.status == 400, reply
    assert_error_body(reply)
    assert api.state()["tick"] == tick  # no tick ran


def test_step_wrong_content_type_in_lockstep(shared_lockstep_api):
    api = shared_lockstep_api
    tick = api.state()["tick"]
    reply = api.request("POST", "/api/v1/step", body=b'{"ticks": 10}', content_type="text/plain")
    assert reply.status == 415, reply
    assert_error_body(reply)
    assert api.state()["tick"] == tick


def test_oversized_step_body_in_lockstep(shared_lockstep_api):
    api = shared_lockstep_api
    tick = api.state()["tick"]
    reply = api.request("POST", "/api/v1/step", body=b'{"ticks": 10' + b" " * 5000 + b"}")
    assert reply.status == 413, reply  # default --http-max-body-bytes 4096
    assert_error_body(reply)
    assert api.state()["tick"] == tick


# ---------------------------------------------------------------------------------------------
# A slow client does not block the others
# ---------------------------------------------------------------------------------------------

def test_slow_client_is_answered_or_closed_and_blocks_nobody(api):
    slow = socket.create_connection((api.host, api.port), timeout=10)
    try:
        sent_at = time.monotonic()
        slow.sendall(b"POST /api/v1/faults HTTP/1.1\r\nHost: 127.0.0.1\r\nContent-Type: application/json\r\n"
                     b"Content-Length: 100\r\n\r\n" + b'{"type": "phase_open", "phase": "B"')
        # Meanwhile another client is served promptly.
        started = time.monotonic()
        state = api.state()
        assert time.monotonic() - started < 1.0
        assert state["fault"] == "none"
        # The server gives up on the slow body (read timeout 2 s): 400, or the connection closed.
        slow.settimeout(8)
        received = b""
        while True:
            try:
                chunk = slow.recv(4096)
            except ConnectionResetError:
                break
            if not chunk:
                break
            received += chunk
            if b"\r\n\r\n" in received:
                head, _, rest = received.partition(b"\r\n\r\n")
                length = re.search(rb"Content-Length: (\d+)", head, re.I)
                if length and len(rest) >= int(length.group(1)):
                    break
        elapsed = time.monotonic() - sent_at
        assert elapsed < 5.0, f"the slow client was held {elapsed:.1f} s"
        if received:
            head, _, rest = received.partition(b"\r\n\r\n")
            assert head.startswith(b"HTTP/1.1 400"), received
            reply = Reply(400, http.client.parse_headers(io.BytesIO(head.split(b"\r\n", 1)[1] + b"\r\n\r\n")), rest)
            assert_error_body(reply)
    finally:
        slow.close()
    assert active_types(api) == []
    assert api.stats()["http"]["faults_queued"] == 0


def test_many_slow_clients_do_not_starve_the_api(api):
    """More half-sent requests than server threads: a normal request is still served promptly."""
    idle = [socket.create_connection((api.host, api.port), timeout=10) for _ in range(40)]
    try:
        for s in idle:
            s.sendall(b"GET /api/v1/state HTTP/1.1\r\nHost: 127.0.0.1\r\n")  # headers never finished
        started = time.monotonic()
        try:
            reply = api.get("/api/v1/state", timeout=1.5)
        except (socket.timeout, TimeoutError):
            pytest.fail("/api/v1/state not answered within 1.5 s behind 40 slow clients")
        assert reply.status == 200
        assert time.monotonic() - started < 1.5
    finally:
        for s in idle:
            s.close()


# ---------------------------------------------------------------------------------------------
# Token
# ---------------------------------------------------------------------------------------------

def test_token(emulator_factory):
    emu, api = emulator_factory("--http-token", TOKEN, token=TOKEN)  # token="" below: none sent
    anonymous = api.get("/api/v1/state", token="")
    assert anonymous.status == 401
    assert anonymous.headers.get("WWW-Authenticate", "").startswith("Bearer")
    assert_error_body(anonymous)

    wrong = api.get("/api/v1/state", token="s3cret-tokeN")
    assert wrong.status == 401 and "WWW-Authenticate" in wrong.headers
    assert api.get("/api/v1/state?token=wrong", token="").status == 401
    assert api.get("/api/v1/state", token=TOKEN[:-1]).status == 401  # a prefix is not the token
    assert api.get("/api/v1/state", token=TOKEN + "x").status == 401

    assert api.get("/api/v1/state", token=TOKEN).status == 200
    assert api.get("/api/v1/state?token=" + TOKEN, token="").status == 200
    assert api.get("/api/v1/stats", headers={"Authorization": "Basic " + TOKEN}, token="").status == 401

    # The token is checked before the request: a bad body without a token is 401, and changes nothing.
    refused = api.request("POST", "/api/v1/faults", {"type": "phase_open", "phase": "B"}, token="")
    assert refused.status == 401
    assert api.delete("/api/v1/faults", token="").status == 401
    assert api.post("/api/v1/step", {"ticks": 1}, token="").status == 401
    assert api.post("/api/v1/recording/start", token="").status == 401
    assert api.get("/api/v1/recording.csv", token="").status == 401
    assert api.get("/api/v1/nothing", token="").status == 401
    assert api.faults()["active"] == [] and api.stats()["http"]["faults_queued"] == 0
    assert not api.recording()["recording"]
    missing_stream = api.open_stream("rate_hz=50", token="")
    assert missing_stream.status == 401

    # EventSource and download links carry ?token=.
    stream = api.open_stream(f"rate_hz=50&token={TOKEN}", token="")
    try:
        assert stream.status == 200
        stream.next_event()
    finally:
        stream.close()
    assert api.get(f"/api/v1/recording.csv?token={TOKEN}", token="").status == 404  # authorised, none yet

    # The page and its files need none.
    page = api.get("/", token="")
    assert page.status == 200 and page.media_type == "text/html"
    assert api.get("/dashboard.js", token="").status == 200


def test_token_file(emulator_factory, tmp_path):
    token_file = tmp_path / "token"
    token_file.write_text("file-token-42\n")
    emu, api = emulator_factory("--http-token-file", str(token_file))
    assert api.get("/api/v1/state", token="").status == 401
    assert api.get("/api/v1/state", token=TOKEN).status == 401
    assert api.get("/api/v1/state", token="file-token-42").status == 200
    assert api.get("/api/v1/faults?token=file-token-42", token="").status == 200


# ---------------------------------------------------------------------------------------------
# Stream
# ---------------------------------------------------------------------------------------------

def test_stream_events_are_states_with_increasing_tick(api):
    stream = api.open_stream("rate_hz=50")
    ticks = []
    try:
        assert stream.status == 200
        end = time.monotonic() + 10
        # Under CPU load the loop (or the stream) may be late: two events can show the same tick,
        # never a smaller one. Read until the tick has moved on 5 times.
        while len(set(ticks)) < 6:
            assert time.monotonic() < end, f"the tick did not advance in the stream: {ticks}"
            ticks.append(stream.next_event()["tick"])
    finally:
        stream.close()
    assert all(b >= a for a, b in zip(ticks, ticks[1:])), ticks


def test_stream_default_rate(emulator_factory):
    emu, api = emulator_factory("--http-stream-hz", "50")
    stream = api.open_stream()
    try:
        first = stream.next_event()
        second = stream.next_event()
    finally:
        stream.close()
    assert second["tick"] > first["tick"]


def test_stream_clients_are_limited(emulator_factory):
    emu, api = emulator_factory("--http-stream-clients", "2")
    streams = []
    try:
        for _ in range(2):
            s = api.open_stream("rate_hz=50")
            assert s.status == 200
            streams.append(s)
            s.next_event()
        assert api.stats()["http"]["stream_clients"] == 2
        third = api.open_stream("rate_hz=50")
        assert third.status == 503, third
        assert "--http-stream-clients" in assert_error_body(third)
        stats = api.stats()["http"]
        assert stats["stream_refused"] == 1 and stats["stream_clients"] == 2 and stats["stream_clients_max"] == 2

        streams.pop().close()
        poll("the closed stream's slot to be freed", lambda: api.stats()["http"]["stream_clients"] == 1)
        fourth = api.open_stream("rate_hz=50")
        assert fourth.status == 200, fourth
        streams.append(fourth)
        fourth.next_event()
    finally:
        for s in streams:
            s.close()
    poll("every stream slot to be freed", lambda: api.stats()["http"]["stream_clients"] == 0)


def test_stop_with_open_stream_exits_promptly(emulator_factory):
    emu, api = emulator_factory()
    stream = api.open_stream("rate_hz=1")
    stream.next_event()
    started = time.monotonic()
    stop_emulator(emu)
    assert time.monotonic() - started < 5.0
    stream.close()


# ---------------------------------------------------------------------------------------------
# Faults
# ---------------------------------------------------------------------------------------------

def test_fault_lifecycle(api):
    queued = api.ok("POST", "/api/v1/faults", {"type": "phase_open", "phase": "B", "duration_s": 30}, status=202)
    assert queued["queued"].startswith("phase_open") and "phase=B" in queued["queued"], queued

    def phase_open_active():
        active = [f for f in api.faults()["active"] if f["type"] == "phase_open"]
        return active[0] if active else None

    fault = poll("phase_open to be in force", phase_open_active)
    assert fault["parameters"]["phase"] == "B" and fault["parameters"]["duration_s"] == 30
    assert fault["until_s"] == pytest.approx(fault["since_s"] + 30, abs=1e-6)
    assert fault["since_s"] >= queued["after_tick"] / TICK_HZ
    assert "phase_open" in api.state()["active_faults"]

    assert api.ok("DELETE", "/api/v1/faults/phase_open", status=202)["queued"].startswith("clear")
    poll("phase_open to be cleared", lambda: phase_open_active() is None)
    assert "phase_open" not in api.state()["active_faults"]

    api.ok("POST", "/api/v1/faults", {"type": "phase_open", "phase": "A"}, status=202)
    api.ok("POST", "/api/v1/faults", {"type": "voltage_sag", "factor": 0.5}, status=202)
    api.ok("POST", "/api/v1/faults", {"type": "jam"}, status=202)
    poll("three faults in force", lambda: sorted(active_types(api)) == ["jam", "phase_open", "voltage_sag"])
    by_type = {f["type"]: f for f in api.faults()["active"]}
    assert by_type["phase_open"]["until_s"] is None  # until cleared
    assert by_type["jam"]["parameters"]["position_um"] is None
    assert by_type["voltage_sag"]["parameters"]["factor"] == 0.5

    # A clear of a fault not in force is accepted and changes nothing else.
    api.ok("DELETE", "/api/v1/faults/encoder_stuck", status=202)
    assert api.ok("DELETE", "/api/v1/faults", status=202)["queued"] == "clear all"
    poll("every fault to be cleared", lambda: active_types(api) == [])
    assert api.stats()["http"]["faults_queued"] == 7


def test_fault_with_duration_ends_by_itself(api):
    api.ok("POST", "/api/v1/faults", {"type": "encoder_stuck", "duration_s": 0.05}, status=202)
    # It may start and end between two polls: the active list is empty again, and it was queued.
    poll("the 50 ms fault to have ended",
         lambda: api.state()["sim_time_s"] > 0.2 and active_types(api) == [])
    assert api.stats()["http"]["faults_queued"] == 1


def test_every_fault_type_is_accepted(api):
    """Every type GET /api/v1/faults lists can be queued with its required keys (mid-range values)."""
    for fault_type in api.faults()["types"]:
        body = {"type": fault_type["type"]}
        for key in fault_type["keys"]:
            if not key["required"]:
                continue
            if key["kind"] == "phase":
                body[key["name"]] = "A"
            elif key["kind"] == "integer":
                body[key["name"]] = int(key["min"]) + 1
            else:
                body[key["name"]] = (key["min"] + key["max"]) / 2
        documented_keys = CONTRACT.doc["components"]["schemas"]["FaultRequest"]["properties"]
        assert all(k["name"] in documented_keys for k in fault_type["keys"]), fault_type
        CONTRACT.validate(body, CONTRACT.schema("FaultRequest"), f"request {body}")
        reply = api.post("/api/v1/faults", body)
        assert reply.status == 202, (body, reply)
        api.ok("DELETE", "/api/v1/faults", status=202)
    documented = set(CONTRACT.doc["components"]["schemas"]["FaultType"]["enum"])
    assert {t["type"] for t in api.faults()["types"]} == documented


def test_over_temperature_trips_the_enabled_amplifier(emulator_factory):
    emu, api = emulator_factory("--watchdog-ms", "0")
    registers = RegisterMap()
    client = ModbusTcpClient(emu.host, port=emu.port, timeout=5)
    assert client.connect(), "cannot connect over Modbus"
    try:
        def inputs():
            rr = client.read_input_registers(0, registers.input_count, slave=1)
            assert not rr.isError(), rr
            return registers.decode_inputs(rr.registers)

        rr = client.write_register(registers.holding["command"]["address"], 1, slave=1)  # enable
        assert not rr.isError(), rr
        poll("the amplifier to be enabled", lambda: api.state()["state"] == "enabled")
        assert inputs()["fault_code"] == 0

        api.ok("POST", "/api/v1/faults", {"type": "over_temperature"}, status=202)
        poll("Modbus fault_code 4", lambda: inputs()["fault_code"] == FAULT_CODE_OVER_TEMPERATURE)
        state = api.state()
        assert state["fault_code"] == FAULT_CODE_OVER_TEMPERATURE
        assert state["fault"] == "over_temperature" and state["state"] == "fault"
        assert "over_temperature" in state["active_faults"]
    finally:
        client.close()


def test_faults_refused_while_recording_a_trace(emulator_factory, tmp_path):
    trace = tmp_path / "trace.csv"
    emu, api = emulator_factory("--record", str(trace))
    for method, path, body in (("POST", "/api/v1/faults", {"type": "phase_open", "phase": "B"}),
                               ("DELETE", "/api/v1/faults", _NO_JSON),
                               ("DELETE", "/api/v1/faults/phase_open", _NO_JSON)):
        reply = api.request(method, path, body)
        assert reply.status == 409, reply
        assert "--record" in assert_error_body(reply)
    assert api.faults()["active"] == [] and api.stats()["http"]["faults_queued"] == 0


# ---------------------------------------------------------------------------------------------
# Recording
# ---------------------------------------------------------------------------------------------

def test_recording(api):
    assert api.recording() == {"recording": False, "available": False, "rows": 0, "dropped": 0,
                               "first_tick": 0, "last_tick": 0, "error": None}
    assert api.ok("POST", "/api/v1/recording/start") == {"recording": True}
    again = api.post("/api/v1/recording/start")
    assert again.status == 409
    assert_error_body(again)
    while_recording = api.get("/api/v1/recording.csv")
    assert while_recording.status == 409
    assert_error_body(while_recording)
    poll("500 rows recorded", lambda: api.recording()["rows"] >= 500)
    assert api.recording()["recording"]

    stopped = api.ok("POST", "/api/v1/recording/stop")
    assert stopped["recording"] is False and stopped["rows"] > 0
    status = api.recording()
    assert status["available"] and not status["recording"] and status["error"] is None
    assert status["rows"] == stopped["rows"] and status["dropped"] == stopped["dropped"] == 0
    assert status["last_tick"] - status["first_tick"] + 1 == status["rows"]
    assert api.post("/api/v1/recording/stop").status == 409  # not running any more

    download = api.get("/api/v1/recording.csv")
    assert download.status == 200 and download.media_type == "text/csv"
    assert "attachment" in download.headers.get("Content-Disposition", "")
    text = download.body.decode()
    lines = text.splitlines()
    header = recording_header()
    assert lines[0] == header
    rows = list(csv.reader(lines[1:]))
    assert len(rows) == stopped["rows"]
    columns = header.split(",")
    assert all(len(row) == len(columns) for row in rows)
    ticks = [int(row[columns.index("tick")]) for row in rows]
    assert ticks[0] == status["first_tick"] and ticks[-1] == status["last_tick"]
    assert all(b - a == 1 for a, b in zip(ticks, ticks[1:])), "a tick is missing or repeated"
    sim_time = [float(row[columns.index("sim_time_s")]) for row in rows]
    assert all(b > a for a, b in zip(sim_time, sim_time[1:]))

    # A new recording replaces the last; downloading twice gives the same file.
    assert api.get("/api/v1/recording.csv").body == download.body
    api.ok("POST", "/api/v1/recording/start")
    assert api.get("/api/v1/recording.csv").status == 409
    api.ok("POST", "/api/v1/recording/stop")
    assert api.get("/api/v1/recording.csv").status == 200


def test_recording_in_lockstep_has_exactly_the_stepped_ticks(lockstep_api):
    api = lockstep_api
    first = api.state()["tick"]
    api.ok("POST", "/api/v1/recording/start")
    api.ok("POST", "/api/v1/step", {"ticks": 250})
    api.ok("POST", "/api/v1/step", {"ticks": 50})
    stopped = api.ok("POST", "/api/v1/recording/stop")
    assert stopped["rows"] == 300 and stopped["dropped"] == 0
    lines = api.get("/api/v1/recording.csv").body.decode().splitlines()
    assert lines[0] == recording_header()
    ticks = [int(line.split(",", 1)[0]) for line in lines[1:]]
    assert len(ticks) == 300
    assert ticks == list(range(ticks[0], ticks[0] + 300))
    assert first <= ticks[0] <= first + 1


def test_recording_directory(emulator_factory, tmp_path):
    emu, api = emulator_factory("--http-recording-dir", str(tmp_path), "--clock", "external")
    api.ok("POST", "/api/v1/recording/start")
    api.ok("POST", "/api/v1/step", {"ticks": 10})
    api.ok("POST", "/api/v1/recording/stop")
    files = list(tmp_path.glob("*.csv"))
    assert len(files) == 1, files
    assert files[0].read_bytes() == api.get("/api/v1/recording.csv").body


# ---------------------------------------------------------------------------------------------
# Lockstep
# ---------------------------------------------------------------------------------------------

def test_step_ticks_and_seconds(lockstep_api):
    api = lockstep_api
    stats = api.stats()
    assert stats["clock"] == "external" and stats["tick_hz"] == TICK_HZ
    state = api.state()
    assert state["external_clock"] is True
    tick = state["tick"]
    assert api.state()["tick"] == tick  # nothing runs unstepped

    reply = api.ok("POST", "/api/v1/step", {"ticks": 100})
    assert reply["stepped_ticks"] == 100 and reply["tick"] == tick + 100
    assert reply["sim_time_s"] == pytest.approx((tick + 100) / TICK_HZ, abs=1e-9)
    assert api.state()["tick"] == tick + 100

    reply = api.ok("POST", "/api/v1/step", {"seconds": 0.01})
    assert reply["stepped_ticks"] == 100 and reply["tick"] == tick + 200
    assert api.state()["tick"] == tick + 200

    reply = api.ok("POST", "/api/v1/step", {"ticks": 1})
    assert reply["stepped_ticks"] == 1 and api.state()["tick"] == tick + 201


def test_fault_queued_before_a_step_is_in_force_after_it(lockstep_api):
    api = lockstep_api
    api.ok("POST", "/api/v1/step", {"ticks": 10})
    tick = api.state()["tick"]
    queued = api.ok("POST", "/api/v1/faults", {"type": "phase_open", "phase": "B", "duration_s": 0.005}, status=202)
    assert queued["after_tick"] == tick
    assert api.faults()["active"] == []  # no tick boundary yet
    api.ok("POST", "/api/v1/step", {"ticks": 1})
    active = api.faults()["active"]
    assert [f["type"] for f in active] == ["phase_open"], active
    assert active[0]["since_s"] == pytest.approx(tick / TICK_HZ, abs=1e-12)
    assert active[0]["until_s"] == pytest.approx(tick / TICK_HZ + 0.005, abs=1e-12)
    assert api.state()["active_faults"] == ["phase_open"]
    # It ends at its tick: 50 ticks after it started.
    api.ok("POST", "/api/v1/step", {"ticks": 48})
    assert active_types(api) == ["phase_open"]
    api.ok("POST", "/api/v1/step", {"ticks": 2})
    assert active_types(api) == []

    api.ok("POST", "/api/v1/faults", {"type": "voltage_sag", "factor": 0.25}, status=202)
    api.ok("DELETE", "/api/v1/faults/voltage_sag", status=202)
    api.ok("POST", "/api/v1/step", {"ticks": 1})
    assert active_types(api) == []  # queued in order: started, then cleared


def test_step_ends_with_the_run(emulator_factory):
    emu, api = emulator_factory("--clock", "external", "--duration", "0.01")
    reply = api.post("/api/v1/step", {"ticks": 1000})
    # The run ends at 100 ticks: the step cannot complete (503) or the emulator is gone.
    assert reply.status in (200, 503), reply
    if reply.status == 503:
        assert_error_body(reply)
    emu.wait(timeout=30)


# ---------------------------------------------------------------------------------------------
# Command line
# ---------------------------------------------------------------------------------------------

def run_cli(*args):
    """swum-emu with these options, expected to refuse them. One that starts anyway (prints its
    ready line) is stopped by its pid at once and reported with returncode 0 ("started")."""
    proc = subprocess.Popen([emu_harness.EMU, "--config", CONFIG, "--modbus", "tcp://127.0.0.1:0", *args],
                            stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    try:
        first = proc.stdout.readline()  # the ready line, or EOF when it refuses
        if "swum-emu ready" in first:
            os.kill(proc.pid, signal.SIGTERM)
            out, err = proc.communicate(timeout=30)
            return subprocess.CompletedProcess(proc.args, 0, first + out, err)
        out, err = proc.communicate(timeout=30)
        return subprocess.CompletedProcess(proc.args, proc.returncode, first + out, err)
    finally:
        if proc.poll() is None:
            proc.kill()
            proc.wait()


def assert_one_line_error(result, *words):
    assert result.returncode != 0, result
    assert result.stdout == "" or "ready" not in result.stdout
    lines = result.stderr.splitlines()
    assert len(lines) == 1, result.stderr
    assert lines[0].startswith("swum-emu:"), result.stderr
    for word in words:
        assert word in lines[0], result.stderr


@pytest.mark.parametrize("value", ["nonsense", "127.0.0.1:99999", "127.0.0.1", "127.0.0.1:-1",
                                   "http://127.0.0.1:0", "127.0.0.1:80x", "127.0.0.1:"])
def test_cli_bad_http_value(value):
    assert_one_line_error(run_cli("--http", value), "--http")


def test_cli_http_empty_host():
    assert_one_line_error(run_cli("--http", ":0"), "--http")


def test_cli_http_empty_value():
    assert_one_line_error(run_cli("--http", ""), "--http")


def test_cli_http_address_not_of_this_machine():
    assert_one_line_error(run_cli("--http", "10.255.255.254:0"), "--http", "10.255.255.254")


@pytest.mark.parametrize("option,value", [("--http-token", "x"), ("--http-stream-hz", "10"),
                                          ("--http-stream-clients", "2"), ("--http-max-body-bytes", "1000"),
                                          ("--http-recording-dir", "/tmp")])
def test_cli_http_option_without_http(option, value):
    assert_one_line_error(run_cli(option, value), option, "--http")


def test_cli_token_and_token_file_together(tmp_path):
    token_file = tmp_path / "token"
    token_file.write_text("abc\n")
    assert_one_line_error(run_cli("--http", "127.0.0.1:0", "--http-token", "a", "--http-token-file", str(token_file)),
                          "--http-token")


@pytest.mark.parametrize("content", ["", "\n", "two words\n"])
def test_cli_unusable_token_file(tmp_path, content):
    token_file = tmp_path / "token"
    token_file.write_text(content)
    assert_one_line_error(run_cli("--http", "127.0.0.1:0", "--http-token-file", str(token_file)), "--http-token")


def test_cli_http_port_in_use():
    with socket.socket() as taken:
        taken.bind(("127.0.0.1", 0))
        taken.listen(1)
        port = taken.getsockname()[1]
        assert_one_line_error(run_cli("--http", f"127.0.0.1:{port}"), "--http", str(port))

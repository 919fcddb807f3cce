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
import threading
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
RECORDING_SOURCE = os.path.join(SOURCE_DIR, "firmware_sim/http/http_recording.cpp")
TOKEN = "s3cret-token"
TICK_HZ = 10000.0  # swum-emu's default --tick-hz
FAULT_CODE_OVER_TEMPERATURE = 4
FOREIGN_HOST = "evil.example"

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
            # Refused before routing, documented path or not: a foreign Host or Origin (403), a POST
            # not declared JSON (415), a byte range asked of the API (400), no token under /api/ (401).
            allowed = {404, 403} | ({415} if method.upper() == "POST" else set())
            if urllib.parse.urlsplit(path).path.startswith("/api/"):
                allowed |= {400, 401}
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
        for name, header in (spec.get("headers") or {}).items():
            value = reply.headers.get(name)
            if header.get("required"):
                assert value is not None, f"{method} {template} {reply.status}: no {name} header"
            if value is not None:
                self.validate(value, header["schema"], f"{method} {template} {reply.status} header {name}")
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
    """A refusal: {"error": "one line"}, ending in a newline, JSON (UTF-8: bytes of the request
    that were not are replaced by U+FFFD)."""
    assert reply.media_type == "application/json", reply
    content_range = reply.headers.get("Content-Range")  # only a 416's "bytes */SIZE" (RFC 9110)
    assert content_range is None or (reply.status == 416 and re.fullmatch(r"bytes \*/\d+", content_range)), \
        f"a refusal cut to a byte range: {reply} {content_range}"
    text = reply.body.decode()  # strict: the body is UTF-8
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

    @property
    def authority(self):
        """What a client puts in Host (and, after http://, in Origin)."""
        return f"{self.host}:{self.port}"

    def request(self, method, path, json_body=_NO_JSON, *, body=None, headers=None, token=None,
                content_type="application/json", timeout=10, check=True):
        """(status, headers, body) as a Reply. json_body: a value sent as JSON; body: raw bytes.
        content_type is sent with any body and with every POST (the server wants it even on an
        empty one); None: no Content-Type. headers may replace Host. check=False: the reply is not
        checked against the document (only for cpp-httplib's 416 to a malformed Range, which it
        sends before routing, on any path: docs/http-api.md "Safety")."""
        h = self._headers(headers, token)
        if json_body is not _NO_JSON:
            body = json.dumps(json_body).encode()
        if (body is not None or method.upper() == "POST") and content_type is not None:
            h.setdefault("Content-Type", content_type)
        conn = self.connection(timeout)
        try:
            conn.request(method, path, body=body, headers=h)
            response = conn.getresponse()
            reply = Reply(response.status, response.headers, response.read())
        finally:
            conn.close()
        if check:
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

    def open_stream(self, query="", token=None, timeout=10, headers=None):
        """GET /api/v1/stream: returns a Stream (200) or the refusal's Reply."""
        conn = self.connection(timeout)
        path = "/api/v1/stream" + (("?" + query) if query else "")
        conn.request("GET", path, headers=self._headers({"Accept": "text/event-stream", **(headers or {})}, token))
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
    """An open /api/v1/stream: events read one by one, each data checked against the document.
    Comment lines (": keep-alive", sent between events) are skipped and counted."""

    def __init__(self, conn, response, reply):
        self.conn, self.response, self.reply = conn, response, reply
        self.status = reply.status
        self.operation = reply.operation
        self.comments = []  # (the comment line, time.monotonic() when read)

    def next_line(self):
        line = self.response.readline()
        assert line, "the stream ended"
        return line.decode().rstrip("\n")

    def next_event(self):
        name, data = None, []
        while True:
            line = self.next_line()
            if line.startswith(":"):  # a comment (the keep-alive): no field, not an event
                self.comments.append((line, time.monotonic()))
                continue
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


def raw_exchange(api, request, timeout=10):
    """Sends `request` (bytes, ending its headers; "PORT" replaced by the server's port) on a
    socket of its own and reads the answer until the server closes: a Reply, not checked against
    the document (for what http.client cannot send or would not read)."""
    with socket.create_connection((api.host, api.port), timeout=timeout) as s:
        s.sendall(request.replace(b"PORT", str(api.port).encode()))
        received = b""
        while True:
            try:
                chunk = s.recv(65536)
            except ConnectionResetError:
                break
            if not chunk:
                break
            received += chunk
    head, _, body = received.partition(b"\r\n\r\n")
    status_line, _, header_lines = head.partition(b"\r\n")
    m = re.match(rb"HTTP/1\.[01] (\d{3}) ", status_line)
    assert m, f"no status line in {received[:200]!r}"
    headers = http.client.parse_headers(io.BytesIO(header_lines + b"\r\n\r\n"))
    return Reply(int(m.group(1)), headers, body)


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


def open_idle_connections(api, count, deadline_s=10.0):
    """`count` open connections to the API, made in well under a second. The listen backlog is
    cpp-httplib's 5 and the accepting thread runs niced (api_thread_priority.h): a burst of
    connects overflows the backlog, and the kernel resends a dropped SYN only after its 1 s
    initial retransmission timeout: 64 plain connects took ~9 s on a busy 2-core machine, and the
    first connections had passed the server's 2 s idle timeout before the last one was open. A connect not answered
    within 50 ms is abandoned and made again at once (a polling interval, not a synchronisation)."""
    connections = []
    end = time.monotonic() + deadline_s
    while len(connections) < count:
        try:
            s = socket.create_connection((api.host, api.port), timeout=0.05)
        except (socket.timeout, TimeoutError):
            assert time.monotonic() < end, f"{len(connections)} of {count} connections in {deadline_s} s"
            continue
        s.settimeout(10)
        connections.append(s)
    return connections


def active_types(api):
    return [f["type"] for f in api.faults()["active"]]


def recording_header():
    """kRecordingHeader of firmware_sim/http/http_recording.cpp (its string literals joined)."""
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
            # The refusals before routing apply to every path: a foreign Host or Origin (403) on
            # every operation, the page's too; a POST not declared JSON (415); a byte range on the
            # API but for the recording's download (400).
            assert "403" in responses, f"{method} {template}: no 403"
            if method == "post":
                assert "415" in responses, f"{method} {template}: no 415"
            if template.startswith("/api/") and template != "/api/v1/recording.csv":
                assert "400" in responses, f"{method} {template}: no 400 (Range)"
    download = doc["paths"]["/api/v1/recording.csv"]["get"]["responses"]
    assert "206" in download and "416" in download
    assert "Content-Range" in CONTRACT.deref(download["206"])["headers"]
    assert CONTRACT.deref(download["200"])["headers"]["Content-Disposition"]["required"] is True
    assert CONTRACT.deref(doc["components"]["responses"]["Unauthorized"])["headers"]["WWW-Authenticate"]["required"]
    rate = next(p for p in doc["paths"]["/api/v1/stream"]["get"]["parameters"] if p["name"] == "rate_hz")
    assert rate["schema"]["minimum"] == 0.1 and rate["schema"]["maximum"] == 100


def identifiers_in_codes_source(signature):
    """The strings the function `signature` of protocol/codes.cpp returns, in order."""
    with open(os.path.join(SOURCE_DIR, "protocol/codes.cpp")) as f:
        source = f.read()
    start = source.index(signature)
    body = source[start:source.index("\n}\n", start)]
    return [name for name in re.findall(r'return "([^"]*)";', body) if name != "?"]


def test_openapi_enums_are_the_servers_identifiers():
    schemas = CONTRACT.doc["components"]["schemas"]
    with open(os.path.join(SOURCE_DIR, "config/modbus_registers.json")) as f:
        reason_codes = json.load(f)["reason_codes"]
    assert schemas["RejectReason"]["enum"] == [reason_codes[k] for k in sorted(reason_codes, key=int)]
    assert schemas["RejectReason"]["enum"] == identifiers_in_codes_source("const char* identifier(Reason ")
    assert schemas["FaultName"]["enum"] == identifiers_in_codes_source("const char* identifier(FaultCode ")


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


def example_path(template):
    return template.replace("{type}", "phase_open")


def example_body(template, method):
    """A valid body for the operations that take one, else None."""
    return {("/api/v1/faults", "POST"): b'{"type": "phase_open", "phase": "B"}',
            ("/api/v1/step", "POST"): b'{"ticks": 10}'}.get((template, method))


def test_every_operation_refuses_before_routing(emulator_factory):
    """On each documented operation, valid otherwise: a foreign Host or Origin is 403, a POST
    without Content-Type: application/json is 415, a byte range asked of the API (but the
    recording's download) is 400; nothing runs, nothing changes."""
    emu, api = emulator_factory("--clock", "external")
    tick = api.state()["tick"]
    refusals = 0
    for template, method in sorted(CONTRACT.operations()):
        path, body = example_path(template), example_body(template, method)

        def refused(status, what, **kw):
            reply = api.request(method, path, body=body, **kw)
            assert reply.status == status, f"{method} {path} with {what}: {reply}"
            assert reply.operation == (template, method)  # documented (CONTRACT.check)
            return assert_error_body(reply)

        message = refused(403, "a foreign Host", headers={"Host": f"{FOREIGN_HOST}:{api.port}"})
        assert message == f"Host '{FOREIGN_HOST}:{api.port}' is not this server (127.0.0.1:{api.port})"
        message = refused(403, "a foreign Origin", headers={"Origin": f"http://{FOREIGN_HOST}"})
        assert message == f"cross-origin request refused (Origin http://{FOREIGN_HOST})"
        refusals += 2
        if method == "POST":
            message = refused(415, "no Content-Type", content_type=None)
            assert message == "Content-Type: application/json is required (even with an empty body)"
            message = refused(415, "Content-Type text/plain", content_type="text/plain")
            assert message == "Content-Type must be application/json, not text/plain"
            refusals += 2
        if template.startswith("/api/") and template != "/api/v1/recording.csv":
            reply = api.request(method, path, body=body, headers={"Range": "bytes=0-10"})
            assert reply.status == 400, f"{method} {path} with a Range: {reply}"
            assert assert_error_body(reply) == "the API does not serve byte ranges (Range is for /api/v1/recording.csv)"
            CONTRACT.response_spec(template, method, 400)  # documented
            refusals += 1
    assert api.state()["tick"] == tick  # no step ran
    assert api.faults()["active"] == [] and api.faults()["active_total"] == 0
    stats = api.stats()["http"]
    assert stats["faults_queued"] == 0 and stats["stream_clients"] == 0 and stats["stream_events"] == 0
    assert stats["refused"] >= refusals
    assert api.recording() == {"recording": False, "available": False, "rows": 0, "dropped": 0,
                               "first_tick": 0, "last_tick": 0, "error": None}


@pytest.mark.parametrize("host", ["127.0.0.1:{port}", "localhost:{port}", "[::1]:{port}", None])
def test_loopback_names_of_this_server_are_accepted(shared_api, host):
    api = shared_api
    if host is None:  # HTTP/1.0 without Host: nothing to check
        reply = raw_exchange(api, b"GET /api/v1/state HTTP/1.0\r\n\r\n")
        assert reply.status == 200 and "tick" in json.loads(reply.body)
        return
    headers = {"Host": host.format(port=api.port)}
    assert api.get("/api/v1/state", headers=headers).status == 200
    assert api.get("/", headers=headers).status == 200
    # Same-origin: Origin is http:// + that Host.
    headers["Origin"] = "http://" + headers["Host"]
    assert api.get("/api/v1/state", headers=headers).status == 200
    assert api.get("/", headers=headers).status == 200


def test_another_loopback_address_is_a_loopback_bind():
    """Bound to 127.0.0.2 (any of 127/8): no warning that others can reach it, its own name is
    accepted as Host, and a foreign Host is refused (the DNS-rebinding check applies)."""
    emu = Emulator("--http", "127.0.0.2:0")
    with emu:
        api = Api(emu)
        assert api.host == "127.0.0.2"
        assert api.get("/api/v1/state").status == 200  # Host: 127.0.0.2:PORT
        foreign = api.get("/api/v1/state", headers={"Host": f"{FOREIGN_HOST}:{api.port}"})
        assert foreign.status == 403, foreign
        assert assert_error_body(foreign) == f"Host '{FOREIGN_HOST}:{api.port}' is not this server (127.0.0.2:{api.port})"
        stop_emulator(emu)
    assert "warning" not in emu.stderr, emu.stderr


@pytest.mark.parametrize("refusal", ["origin", "content-type", "host"])
def test_refused_request_body_is_never_read_as_a_request(emulator_factory, refusal):
    """A request refused before routing leaves its body unread. That body must not be served as
    the next request on the connection: a page elsewhere would smuggle a fault past the refusal."""
    emu, api = emulator_factory()
    inner = b'{"type": "over_temperature"}'
    smuggled = (b"POST /api/v1/faults HTTP/1.1\r\nHost: 127.0.0.1:PORT\r\nContent-Type: application/json\r\n"
                b"Content-Length: %d\r\n\r\n" % len(inner)) + inner
    smuggled = smuggled.replace(b"PORT", str(api.port).encode())
    host, extra, content_type = b"127.0.0.1:PORT", b"", b"application/json"
    if refusal == "origin":
        extra = b"Origin: http://evil.example\r\n"
    elif refusal == "content-type":
        content_type = b"text/plain;charset=UTF-8"
    else:
        host = FOREIGN_HOST.encode()
    head = (b"POST /api/v1/faults HTTP/1.1\r\nHost: " + host + b"\r\n" + extra + b"Content-Type: " + content_type +
            b"\r\nContent-Length: %d\r\n\r\n" % len(smuggled))
    reply = raw_exchange(api, head + smuggled)  # reads until the server closes
    assert reply.status in (403, 415), reply
    assert b"HTTP/1.1 202" not in reply.body, reply.body  # no second answer on the connection
    assert reply.headers.get("Connection") == "close"
    assert api.faults()["active"] == [] and api.stats()["http"]["faults_queued"] == 0
    assert api.state()["fault_code"] == 0


@pytest.mark.parametrize("what", ["path", "range-list", "range-spaced", "range-long-numbers"])
def test_longest_request_parts_are_refused_not_fatal(emulator_factory, what):
    """cpp-httplib matches paths and parses Range with std::regex, which recurses per character:
    a path or a Range header near the 8 KiB limits must not exhaust a server thread's stack. A
    long path is refused (414); a long Range is answered; the emulator serves on."""
    emu, api = emulator_factory()
    if what == "path":
        request = b"DELETE /api/v1/faults/" + b"a" * 8100 + b" HTTP/1.1\r\nHost: 127.0.0.1:PORT\r\n\r\n"
    else:
        unit = {"range-list": b"0-1,", "range-spaced": b"0-1, ", "range-long-numbers": b"0123456789-,"}[what]
        value = (unit * 4000)[:8150].rstrip(b", ")
        request = b"GET /api/v1/recording.csv HTTP/1.1\r\nHost: 127.0.0.1:PORT\r\nRange: bytes=" + value + b"\r\n\r\n"
    reply = raw_exchange(api, request)
    assert 400 <= reply.status < 500, reply
    if what == "path":
        assert reply.status == 414 and assert_error_body(reply) == "path over 256 bytes"
    assert emu.proc.poll() is None, f"swum-emu died (exit status {emu.proc.returncode})"
    assert api.state()["tick"] >= 0


def test_every_operation_needs_the_token(emulator_factory):
    """With --http-token, every documented operation (the page and its files apart) answers 401
    without the token and with a wrong one, before anything runs; with it, it is served."""
    emu, api = emulator_factory("--http-token", TOKEN, "--clock", "external", token=TOKEN)
    tick = api.state()["tick"]
    checked = 0
    for template, method in sorted(CONTRACT.operations()):
        if not template.startswith("/api/"):
            continue
        path, body = example_path(template), example_body(template, method)
        for token, www in (("", "Bearer"), ("wrong-token", 'Bearer error="invalid_token"')):
            reply = api.request(method, path, body=body, token=token)
            assert reply.status == 401, f"{method} {path} with token {token!r}: {reply}"
            assert reply.headers.get("WWW-Authenticate") == www, (method, path, dict(reply.headers))
            assert_error_body(reply)
            checked += 1
    assert checked >= 2 * 10
    assert api.state()["tick"] == tick  # no step ran
    assert api.faults()["active"] == [] and api.stats()["http"]["faults_queued"] == 0
    assert not api.recording()["recording"] and not api.recording()["available"]
    assert api.stats()["http"]["stream_events"] == 0


@pytest.mark.parametrize("host", [FOREIGN_HOST, f"{FOREIGN_HOST}:{{port}}", "127.0.0.1", "localhost",
                                  "127.0.0.1:{other}", "127.0.0.2:{port}", "127.0.0.1:{port}.evil.example"])
def test_foreign_host_is_refused_everywhere(shared_api, host):
    """DNS rebinding: a name that resolves to 127.0.0.1 but is not one of this server's."""
    api = shared_api
    host = host.format(port=api.port, other=api.port + 1 if api.port < 65535 else api.port - 1)
    before = snapshot(api)
    for method, path, body in (("GET", "/", None), ("GET", "/dashboard.js", None), ("GET", "/api/v1/state", None),
                               ("GET", "/api/v1/nothing", None), ("DELETE", "/api/v1/faults", None),
                               ("POST", "/api/v1/faults", b'{"type": "phase_open", "phase": "B"}'),
                               ("POST", "/api/v1/recording/start", None)):
        reply = api.request(method, path, body=body, headers={"Host": host})
        assert reply.status == 403, f"{method} {path} Host {host}: {reply}"
        assert assert_error_body(reply) == f"Host '{host}' is not this server (127.0.0.1:{api.port})"
    stream = api.open_stream("rate_hz=50", headers={"Host": host})
    assert stream.status == 403, stream
    assert snapshot(api) == before
    assert not api.recording()["recording"]


@pytest.mark.parametrize("origin", [f"http://{FOREIGN_HOST}", "null", "https://127.0.0.1:{port}",
                                    "http://localhost:{port}", "http://127.0.0.1:{port}/", "http://127.0.0.1"])
def test_cross_origin_request_is_refused(shared_api, origin):
    """CSRF: an Origin that is not http:// + the Host sent (127.0.0.1:PORT here)."""
    api = shared_api
    origin = origin.format(port=api.port)
    before = snapshot(api)
    for method, path, body in (("GET", "/", None), ("GET", "/api/v1/state", None), ("DELETE", "/api/v1/faults", None),
                               ("POST", "/api/v1/faults", b'{"type": "phase_open", "phase": "B"}'),
                               ("POST", "/api/v1/recording/start", None)):
        reply = api.request(method, path, body=body, headers={"Origin": origin})
        assert reply.status == 403, f"{method} {path} Origin {origin}: {reply}"
        assert assert_error_body(reply) == f"cross-origin request refused (Origin {origin})"
    assert snapshot(api) == before
    assert not api.recording()["recording"]


def test_same_origin_post_is_served(api):
    origin = {"Origin": f"http://{api.authority}"}
    reply = api.post("/api/v1/faults", {"type": "phase_open", "phase": "B"}, headers=origin)
    assert reply.status == 202, reply
    poll("phase_open to be in force", lambda: active_types(api) == ["phase_open"])
    assert api.ok("POST", "/api/v1/recording/start", headers=origin) == {"recording": True}
    assert api.ok("POST", "/api/v1/recording/stop", headers=origin)["recording"] is False


@pytest.mark.parametrize("content_type", ["application/json", "application/json; charset=utf-8",
                                          "Application/JSON", "APPLICATION/JSON;charset=UTF-8",
                                          "application/json ; charset=utf-8"])
def test_json_content_type_forms_are_accepted(lockstep_api, content_type):
    api = lockstep_api
    assert api.ok("POST", "/api/v1/recording/start", content_type=content_type) == {"recording": True}
    assert api.ok("POST", "/api/v1/step", body=b'{"ticks": 3}', content_type=content_type)["stepped_ticks"] == 3
    assert api.ok("POST", "/api/v1/recording/stop", content_type=content_type)["rows"] == 3
    queued = api.ok("POST", "/api/v1/faults", body=b'{"type": "jam"}', content_type=content_type, status=202)
    assert queued["queued"].startswith("jam")


# ---------------------------------------------------------------------------------------------
# Byte ranges: the recording's download only
# ---------------------------------------------------------------------------------------------

@pytest.fixture
def recorded(lockstep_api):
    """(api, the CSV bytes) after a 20-tick recording in lockstep."""
    api = lockstep_api
    api.ok("POST", "/api/v1/recording/start")
    api.ok("POST", "/api/v1/step", {"ticks": 20})
    api.ok("POST", "/api/v1/recording/stop")
    whole = api.get("/api/v1/recording.csv")
    assert whole.status == 200
    return api, whole.body


@pytest.mark.parametrize("spec,first,last", [("bytes=0-9", 0, 9), ("bytes=10-", 10, None), ("bytes=-20", -20, None),
                                             ("bytes=5-5", 5, 5), ("bytes=0-", 0, None)])
def test_recording_download_serves_a_byte_range(recorded, spec, first, last):
    api, whole = recorded
    n = len(whole)
    begin = first % n
    end = n - 1 if last is None else last
    reply = api.get("/api/v1/recording.csv", headers={"Range": spec})
    assert reply.status == 206, reply
    assert reply.media_type == "text/csv"
    assert reply.headers.get("Content-Range") == f"bytes {begin}-{end}/{n}"
    assert reply.body == whole[begin:end + 1]


@pytest.mark.parametrize("spec", ["bytes=5-2", "bytes=x-y", "items=0-5", "foo"])
def test_recording_download_unsatisfiable_range(recorded, spec):
    api, whole = recorded
    reply = api.get("/api/v1/recording.csv", headers={"Range": spec})
    assert reply.status == 416, reply
    assert assert_error_body(reply) == f"byte range not satisfiable: malformed Range header '{spec}'"


def multipart_parts(reply):
    """[(part headers, part body)] of a multipart/byteranges reply."""
    boundary = re.search(r"boundary=(\S+)", reply.headers["Content-Type"]).group(1).encode()
    parts = []
    for chunk in reply.body.split(b"--" + boundary)[1:]:
        if chunk.startswith(b"--"):
            break  # the closing delimiter
        head, _, body = chunk.lstrip(b"\r\n").partition(b"\r\n\r\n")
        parts.append((http.client.parse_headers(io.BytesIO(head + b"\r\n\r\n")), body[:-2]))  # less its CRLF
    return parts


def test_resumed_download_of_another_recording_gets_the_whole_new_file(lockstep_api):
    """The download names its recording (ETag). A resume (Range + If-Range) of the same one gets
    the rest; after another recording replaced it, the whole new file, not its bytes joined to
    the old ones."""
    api = lockstep_api

    def record(ticks):
        api.ok("POST", "/api/v1/recording/start")
        api.ok("POST", "/api/v1/step", {"ticks": ticks})
        api.ok("POST", "/api/v1/recording/stop")
        whole = api.get("/api/v1/recording.csv")
        assert whole.status == 200 and whole.headers.get("ETag"), whole
        return whole

    first = record(20)
    etag = first.headers["ETag"]
    again = api.get("/api/v1/recording.csv")
    assert again.headers["ETag"] == etag  # the same recording, the same name
    rest = api.get("/api/v1/recording.csv", headers={"Range": "bytes=100-", "If-Range": etag})
    assert rest.status == 206 and rest.body == first.body[100:], rest
    second = record(30)
    assert second.headers["ETag"] != etag
    stale = api.get("/api/v1/recording.csv", headers={"Range": "bytes=100-", "If-Range": etag})
    assert stale.status == 200 and "Content-Range" not in stale.headers, stale
    assert stale.body == second.body
    dated = api.get("/api/v1/recording.csv",  # a date is no name of a recording: the whole file
                    headers={"Range": "bytes=100-", "If-Range": "Sat, 28 Nov 2026 05:00:00 GMT"})
    assert dated.status == 200 and dated.body == second.body


def test_recording_download_with_several_ranges_is_the_whole_file(recorded):
    """Several ranges are not served as multipart: the whole file, 200 (RFC 9110 lets a server
    ignore Range), never a part with a wrong Content-Range."""
    api, whole = recorded
    for spec in ("bytes=0-3,10-19,-5", "bytes=0-3, 10-19"):
        reply = api.get("/api/v1/recording.csv", headers={"Range": spec})
        assert reply.status == 200 and reply.media_type == "text/csv", (spec, reply)
        assert "Content-Range" not in reply.headers
        assert reply.body == whole


@pytest.mark.parametrize("past", ["bytes={n}-", "bytes={n}-{m}", "bytes=999999-", "bytes=999999-9999999"])
def test_recording_download_range_past_the_end(recorded, past):
    api, whole = recorded
    spec = past.format(n=len(whole), m=len(whole) + 10)
    reply = raw_exchange(api, b"GET /api/v1/recording.csv HTTP/1.1\r\nHost: 127.0.0.1:PORT\r\nRange: " +
                         spec.encode() + b"\r\nConnection: close\r\n\r\n")
    assert reply.status == 416, (spec, reply.status, dict(reply.headers))
    assert reply.headers.get("Content-Range") == f"bytes */{len(whole)}"
    assert int(reply.headers["Content-Length"]) == len(reply.body)
    assert assert_error_body(reply) == f"byte range not satisfiable: the recording has {len(whole)} bytes"


def test_recording_download_range_reaching_past_the_end_is_cut_at_the_end(recorded):
    api, whole = recorded
    n = len(whole)
    reply = api.get("/api/v1/recording.csv", headers={"Range": f"bytes={n - 7}-{n + 100}"})
    assert reply.status == 206, reply
    assert reply.headers.get("Content-Range") == f"bytes {n - 7}-{n - 1}/{n}"
    assert reply.body == whole[-7:]
    longer = api.get("/api/v1/recording.csv", headers={"Range": f"bytes=-{n + 100}"})  # more than the file
    assert longer.status == 206 and longer.body == whole
    assert longer.headers.get("Content-Range") == f"bytes 0-{n - 1}/{n}"


def test_range_on_the_api_is_refused(shared_api):
    """400 on any /api/ path but recording.csv."""
    api = shared_api
    before = snapshot(api)
    for method, path, body in (("GET", "/api/v1/state", None), ("GET", "/api/v1/stats", None),
                               ("GET", "/api/v1/nothing", None), ("GET", "/api/v1/stream?rate_hz=50", None),
                               ("POST", "/api/v1/faults", b'{"type": "phase_open", "phase": "B"}'),
                               ("DELETE", "/api/v1/faults/phase_open", None)):
        reply = api.request(method, path, body=body, headers={"Range": "bytes=0-10"})
        assert reply.status == 400, f"{method} {path}: {reply}"
    assert snapshot(api) == before


@pytest.mark.parametrize("path,headers,status,message", [
    ("/api/v1/state", {}, 400, "the API does not serve byte ranges (Range is for /api/v1/recording.csv)"),
    ("/api/v1/recording.csv", {}, 404, "no recording to download: start and stop one first"),
    ("/", {"Host": FOREIGN_HOST}, 403, f"Host '{FOREIGN_HOST}' is not this server"),
], ids=["api-range", "download-refusal", "foreign-host"])
def test_range_refusals_are_whole_error_bodies(shared_api, path, headers, status, message):
    reply = shared_api.request("GET", path, headers={"Range": "bytes=0-10", **headers})
    assert reply.status == status, reply
    assert assert_error_body(reply).startswith(message)


def test_malformed_range_is_a_416_on_any_path(shared_api):
    """A Range header cpp-httplib cannot parse is answered 416 before routing, on any path (and
    so before the Host and token checks): a whole one-line error, nothing changed."""
    api = shared_api
    before = snapshot(api)
    # "bytes=0-5,9-3": cpp-httplib keeps the first range it parsed before it refuses the second,
    # which must not cut the error body to bytes 0-5.
    for spec in ("foo", "items=0-5", "Bytes=0-5", "bytes=0-5,9-3", "bytes=99999999999999999999-"):
        for method, path in (("GET", "/api/v1/state"), ("GET", "/api/v1/recording.csv"),
                             ("POST", "/api/v1/faults"), ("GET", "/")):
            body = b'{"type": "phase_open", "phase": "B"}' if method == "POST" else None
            reply = api.request(method, path, body=body, headers={"Range": spec}, check=False)
            assert reply.status == 416, (spec, path, reply)
            assert assert_error_body(reply) == f"byte range not satisfiable: malformed Range header '{spec}'"
            assert "Content-Range" not in reply.headers, (spec, path, dict(reply.headers))
    assert snapshot(api) == before


# ---------------------------------------------------------------------------------------------
# Bad requests: 4xx, one-line Error, nothing changed
# ---------------------------------------------------------------------------------------------

def snapshot(api):
    """What a refused request must not change."""
    state = api.state()
    faults = api.faults()
    return {"active": faults["active"], "active_total": faults["active_total"], "refused": faults["refused"],
            "fault": state["fault"],
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
    ("no-content-type", "POST", "/api/v1/faults", b'{"type": "phase_open", "phase": "B"}', None, 415),
    ("json-lookalike", "POST", "/api/v1/faults", b'{"type": "phase_open", "phase": "B"}', "application/jsonx", 415),
    ("json-seq", "POST", "/api/v1/faults", b'{"type": "phase_open", "phase": "B"}', "application/json-seq", 415),
    ("empty-content-type", "POST", "/api/v1/faults", b'{"type": "phase_open", "phase": "B"}', "", 415),
    ("content-type-not-utf8", "POST", "/api/v1/faults", b'{"type": "phase_open", "phase": "B"}', "text/\xff", 415),
    ("recording-start-no-content-type", "POST", "/api/v1/recording/start", None, None, 415),
    ("recording-start-text-plain", "POST", "/api/v1/recording/start", None, "text/plain", 415),
    ("recording-stop-no-content-type", "POST", "/api/v1/recording/stop", None, None, 415),
    ("post-undocumented-path-no-content-type", "POST", "/api/v1/nothing", None, None, 415),
    ("post-page-no-content-type", "POST", "/", None, None, 415),
    ("post-undocumented-path", "POST", "/api/v1/nothing", None, "application/json", 404),
    ("delete-not-a-fault-name", "DELETE", "/api/v1/faults/not_a_fault", None, None, 404),
    ("delete-load-step", "DELETE", "/api/v1/faults/load_step", None, None, 400),
    ("delete-clear", "DELETE", "/api/v1/faults/clear", None, None, 400),
    ("stream-rate-0", "GET", "/api/v1/stream?rate_hz=0", None, None, 400),
    ("stream-rate-1000", "GET", "/api/v1/stream?rate_hz=1000", None, None, 400),
    ("stream-rate-abc", "GET", "/api/v1/stream?rate_hz=abc", None, None, 400),
    ("stream-rate-negative", "GET", "/api/v1/stream?rate_hz=-5", None, None, 400),
    ("stream-rate-nan", "GET", "/api/v1/stream?rate_hz=nan", None, None, 400),
    ("stream-rate-empty", "GET", "/api/v1/stream?rate_hz=", None, None, 400),
    ("stream-rate-0.05", "GET", "/api/v1/stream?rate_hz=0.05", None, None, 400),
    ("stream-rate-1e-300", "GET", "/api/v1/stream?rate_hz=1e-300", None, None, 400),
    ("stream-rate-100.001", "GET", "/api/v1/stream?rate_hz=100.001", None, None, 400),
    ("stream-rate-inf", "GET", "/api/v1/stream?rate_hz=inf", None, None, 400),
    ("stream-rate-not-utf8", "GET", "/api/v1/stream?rate_hz=%FF", None, None, 400),
    ("path-not-utf8", "GET", "/%FF", None, None, 404),
    ("api-path-not-utf8", "GET", "/api/v1/%FF%FE", None, None, 404),
    ("delete-not-utf8", "DELETE", "/api/v1/faults/%FF", None, None, 404),
    ("host-not-utf8", "GET", "/api/v1/state", None, None, 403),
    ("origin-not-utf8", "GET", "/api/v1/state", None, None, 403),
    ("step-internal-clock", "POST", "/api/v1/step", b'{"ticks": 100}', "application/json", 409),
    ("recording-stop-without-start", "POST", "/api/v1/recording/stop", None, "application/json", 409),
    ("download-before-recording", "GET", "/api/v1/recording.csv", None, None, 404),
    ("undocumented-path", "GET", "/api/v1/nothing", None, None, 404),
    ("undocumented-method", "PUT", "/api/v1/faults", b'{"type": "phase_open", "phase": "B"}', "application/json", 404),
]


# Headers some of them carry (latin-1 strings: "\xff" is the byte 0xFF, not UTF-8).
BAD_REQUEST_HEADERS = {"host-not-utf8": {"Host": "\xff:80"}, "origin-not-utf8": {"Origin": "http://\xff"}}
# Bytes of the request that are not UTF-8 are quoted in the message as U+FFFD.
NOT_UTF8 = {"content-type-not-utf8", "stream-rate-not-utf8", "path-not-utf8", "api-path-not-utf8", "delete-not-utf8",
            "host-not-utf8", "origin-not-utf8"}


@pytest.mark.parametrize("name,method,path,body,content_type,status", BAD_REQUESTS, ids=[c[0] for c in BAD_REQUESTS])
def test_bad_request_changes_nothing(shared_api, name, method, path, body, content_type, status):
    before = snapshot(shared_api)
    reply = shared_api.request(method, path, body=body, content_type=content_type,
                               headers=BAD_REQUEST_HEADERS.get(name))
    assert reply.status == status, reply
    message = assert_error_body(reply)
    if name in NOT_UTF8:
        assert "\ufffd" in message, message
    after = snapshot(shared_api)  # the server is still there
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
        slow.sendall(f"POST /api/v1/faults HTTP/1.1\r\nHost: {api.authority}\r\n".encode() +
                     b"Content-Type: application/json\r\nContent-Length: 100\r\n\r\n" +
                     b'{"type": "phase_open", "phase": "B"')
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


def test_more_slow_clients_than_threads_delay_but_never_lock_out(api):
    """64 half-sent requests, more than the 52 server threads (4 stream + 48): a normal request
    waits for a thread, which the read timeout (2 s) frees, and is then served."""
    idle = open_idle_connections(api, 64)
    try:
        for s in idle:
            s.sendall(f"GET /api/v1/state HTTP/1.1\r\nHost: {api.authority}\r\n".encode())  # never finished
        try:
            reply = api.get("/api/v1/state", timeout=10)  # 2 s read timeout, with room for a busy machine
        except (socket.timeout, TimeoutError):
            pytest.fail("/api/v1/state not answered within 10 s behind 64 slow clients")
        assert reply.status == 200
    finally:
        for s in idle:
            s.close()


def test_many_slow_clients_do_not_starve_the_api(api):
    """40 half-sent requests (fewer than the 52 server threads): a normal request is still served
    at once. (More than the threads: test_more_slow_clients_than_threads_delay_but_never_lock_out.)"""
    idle = open_idle_connections(api, 40)
    try:
        for s in idle:
            s.sendall(f"GET /api/v1/state HTTP/1.1\r\nHost: {api.authority}\r\n".encode())  # never finished
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


ABANDONED_CONNECTION = "swum-emu: --http: a connection was still open 3 s after the stop; exiting without it"


def test_trickling_client_does_not_keep_the_emulator_alive(emulator_factory):
    """A client sending its headers one line a second (each read within the 2 s timeout, the
    request never finished) holds its thread; at SIGTERM swum-emu waits 3 s for it, says so,
    reports and exits 0 while the client still sends."""
    emu, api = emulator_factory()
    slow = socket.create_connection((api.host, api.port), timeout=10)
    done = threading.Event()
    sent = []  # time.monotonic() of each line sent

    def trickle():
        try:
            slow.sendall(f"GET /api/v1/state HTTP/1.1\r\nHost: {api.authority}\r\n".encode())
            sent.append(time.monotonic())
            while not done.wait(1.0):  # the pace of the trickle, not a synchronisation
                slow.sendall(f"X-Trickle-{len(sent)}: {len(sent)}\r\n".encode())
                sent.append(time.monotonic())
        except OSError:  # the emulator is gone
            pass

    sender = threading.Thread(target=trickle, daemon=True)
    sender.start()
    try:
        poll("3 s of trickling (past the 2 s read timeout)", lambda: len(sent) >= 4, timeout=10)
        assert api.state()["fault"] == "none"  # the others are served meanwhile
        signalled = time.monotonic()
        os.kill(emu.proc.pid, signal.SIGTERM)
        try:
            rc = emu.wait(timeout=8)
        except subprocess.TimeoutExpired:
            pytest.fail("swum-emu still running 8 s after SIGTERM behind a trickling client")
        elapsed = time.monotonic() - signalled
        assert sum(1 for t in sent if t > signalled) >= 2, "the client stopped trickling before the exit"
    finally:
        done.set()
        sender.join(timeout=5)
        slow.close()
    assert rc == 0, emu.stderr
    assert elapsed >= 2.5, f"exited {elapsed:.1f} s after SIGTERM: did it wait for the connection?"
    assert ABANDONED_CONNECTION in emu.stderr.splitlines(), emu.stderr
    report = emu.output.splitlines()
    assert report[0].startswith("swum-emu ready") and report[1].startswith("swum-emu stopped: signal"), emu.output


def test_idle_connection_does_not_hold_the_stop(emulator_factory):
    """A connection that sends nothing (a browser's preconnect, a port probe) is closed after
    2 s: open at SIGTERM, it ends within the 3 s the stop waits for, so nothing is abandoned."""
    emu, api = emulator_factory()
    idle = socket.create_connection((api.host, api.port), timeout=10)
    try:
        api.state()  # the idle connection was accepted before this one was served
        stop_emulator(emu)
    finally:
        idle.close()
    assert ABANDONED_CONNECTION not in emu.stderr, emu.stderr


def test_stop_without_open_connections_says_nothing_of_them(emulator_factory):
    emu, api = emulator_factory()
    api.state()
    started = time.monotonic()
    stop_emulator(emu)
    assert time.monotonic() - started < 2.5
    assert ABANDONED_CONNECTION not in emu.stderr
    assert emu.output.splitlines()[1].startswith("swum-emu stopped: signal")


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
    # The scheme is case-insensitive; the token is not.
    for scheme in ("bearer", "BEARER", "bEaReR"):
        assert api.get("/api/v1/state", headers={"Authorization": f"{scheme} {TOKEN}"}, token="").status == 200
    assert api.get("/api/v1/state", headers={"Authorization": f"Bearer {TOKEN.upper()}"}, token="").status == 401
    assert api.get("/api/v1/state", headers={"Authorization": "Bearer"}, token="").status == 401
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


def test_refusals_before_routing_come_before_the_token(emulator_factory):
    """Host, Origin, Range and Content-Type are checked first: without a token (or with a wrong
    one) such a request gets 403/400/415, not 401; only a request that passes them gets 401."""
    emu, api = emulator_factory("--http-token", TOKEN, token=TOKEN)
    fault = b'{"type": "phase_open", "phase": "B"}'
    for token in ("", "wrong"):
        foreign = api.post("/api/v1/faults", body=fault, token=token, headers={"Host": FOREIGN_HOST})
        assert foreign.status == 403 and "WWW-Authenticate" not in foreign.headers, foreign
        cross = api.post("/api/v1/faults", body=fault, token=token, headers={"Origin": f"http://{FOREIGN_HOST}"})
        assert cross.status == 403, cross
        assert api.get("/api/v1/state", token=token, headers={"Origin": "null"}).status == 403
        not_json = api.post("/api/v1/faults", body=fault, token=token, content_type="text/plain")
        assert not_json.status == 415, not_json
        assert api.post("/api/v1/recording/start", token=token, content_type=None).status == 415
        ranged = api.request("GET", "/api/v1/state", token=token, headers={"Range": "bytes=0-10"})
        assert ranged.status == 400, ranged
        assert api.get("/", token=token, headers={"Host": FOREIGN_HOST}).status == 403
        # All of them passed: the token is the next check.
        anonymous = api.post("/api/v1/faults", body=fault, token=token)
        assert anonymous.status == 401 and "WWW-Authenticate" in anonymous.headers, anonymous
    # With the token, all of them still apply.
    assert api.post("/api/v1/faults", body=fault, headers={"Host": FOREIGN_HOST}).status == 403
    assert api.post("/api/v1/faults", body=fault, content_type="text/plain").status == 415
    assert api.faults()["active"] == [] and api.stats()["http"]["faults_queued"] == 0
    assert not api.recording()["recording"]
    assert api.post("/api/v1/faults", body=fault, headers={"Origin": f"http://{api.authority}"}).status == 202


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
    assert stream.comments == []  # events every 20 ms: no keep-alive needed between them


def test_stream_rate_bounds_are_accepted(api):
    """rate_hz in [0.1, 100], ends included (0.05, 1e-300 and 100.001 are bad requests, above)."""
    streams = {rate: api.open_stream(f"rate_hz={rate}") for rate in ("0.1", "0.10", "1e2", "100.0")}  # 4 slots
    for rate, stream in streams.items():
        assert stream.status == 200, (rate, stream)
        stream.close()
    poll("the 4 slots to be freed", lambda: api.stats()["http"]["stream_clients"] == 0, timeout=5)
    stream = api.open_stream("rate_hz=100")
    try:
        first, second = stream.next_event(), stream.next_event()
        assert second["tick"] >= first["tick"]
    finally:
        stream.close()
    poll("every stream slot to be freed", lambda: api.stats()["http"]["stream_clients"] == 0, timeout=5)


def test_stream_sends_keep_alive_comments_between_events(api):
    """At 0.1 Hz (an event every 10 s) the stream carries ': keep-alive' about every second. (At
    0.2 Hz two events can fall in the up to 8 s this test reads under load, and its "at most one
    event" would fail for no fault.)"""
    stream = api.open_stream("rate_hz=0.1")
    try:
        assert stream.status == 200
        opened = time.monotonic()
        lines = []
        while len(stream.comments) < 3:
            assert time.monotonic() - opened < 8, f"fewer than 3 keep-alives in 8 s: {lines}"
            line = stream.next_line()
            lines.append(line)
            if line.startswith(":"):
                assert line == ": keep-alive", lines
                stream.comments.append((line, time.monotonic()))
                assert stream.next_line() == "", lines  # a comment ends like an event: a blank line
            elif line.startswith("event:"):
                assert line == "event: telemetry"
        gaps = [b[1] - a[1] for a, b in zip(stream.comments, stream.comments[1:])]
        assert all(g < 2.5 for g in gaps), gaps
        assert sum(1 for line in lines if line.startswith("event:")) <= 1, lines  # at most one in the ~3 s
        stream.next_event()  # the reader skips the comments to the next event (within 5 s)
    finally:
        stream.close()


def test_stream_default_rate(emulator_factory):
    # Events come at 50 Hz from the loop's latest state; a loop starved by a loaded machine may
    # not have ticked between two of them, so the events are read until the tick moves on (never
    # back), with a deadline that is only a hang guard.
    emu, api = emulator_factory("--http-stream-hz", "50")
    stream = api.open_stream()
    try:
        ticks = [stream.next_event()["tick"]]
        deadline = time.monotonic() + 30
        while ticks[-1] == ticks[0] and time.monotonic() < deadline:
            ticks.append(stream.next_event()["tick"])
    finally:
        stream.close()
    assert all(b >= a for a, b in zip(ticks, ticks[1:])), ticks
    assert ticks[-1] > ticks[0], ticks


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


def test_slow_streams_that_leave_free_their_slots(emulator_factory):
    """Clients at rate_hz=0.1 that connect and leave: the keep-alive finds them gone within a
    second or two, not at their next event 10 s later; their slots serve new clients."""
    emu, api = emulator_factory("--http-stream-clients", "4")
    streams = [api.open_stream("rate_hz=0.1") for _ in range(4)]
    assert all(s.status == 200 for s in streams), streams
    assert api.stats()["http"]["stream_clients"] == 4
    refused = api.open_stream("rate_hz=0.1")
    assert refused.status == 503, refused
    closed = time.monotonic()
    for s in streams:
        s.close()
    poll("the 4 slow streams' slots to be freed", lambda: api.stats()["http"]["stream_clients"] == 0, timeout=5)
    assert time.monotonic() - closed < 5
    again = [api.open_stream("rate_hz=0.1") for _ in range(4)]
    try:
        assert all(s.status == 200 for s in again), again
        # Served: a keep-alive comment, or an event if the open fell just before a grid point
        # (events sit on a 10 s grid of the steady clock, so the first may come at once).
        assert again[0].next_line() in (": keep-alive", "event: telemetry")
    finally:
        for s in again:
            s.close()
    poll("every slot to be freed again", lambda: api.stats()["http"]["stream_clients"] == 0, timeout=5)
    assert api.stats()["http"]["stream_refused"] == 1


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


def test_fault_with_duration_ends_by_itself(lockstep_api):
    """Seen in force after the next tick, gone once its 50 ms (500 ticks) have run; none refused."""
    api = lockstep_api
    queued = api.ok("POST", "/api/v1/faults", {"type": "encoder_stuck", "duration_s": 0.05}, status=202)
    api.ok("POST", "/api/v1/step", {"ticks": 1})
    faults = api.faults()
    assert [f["type"] for f in faults["active"]] == ["encoder_stuck"], faults["active"]
    assert faults["active_total"] == 1 and faults["refused"] == 0
    fault = faults["active"][0]
    assert fault["since_s"] == pytest.approx(queued["after_tick"] / TICK_HZ, abs=1e-12)
    assert fault["until_s"] == pytest.approx(fault["since_s"] + 0.05, abs=1e-9)
    api.ok("POST", "/api/v1/step", {"ticks": 600})  # past its end
    faults = api.faults()
    assert faults["active"] == [] and faults["active_total"] == 0 and faults["refused"] == 0
    assert api.state()["active_faults"] == []
    assert api.stats()["http"]["faults_queued"] == 1


def test_active_total_and_refused(emulator_factory):
    """active lists the first 32 faults in force, active_total counts them all; run-time faults
    beyond 32 in force are refused by the loop (refused), beyond 64 waiting by the API (503)."""
    emu, api = emulator_factory("--clock", "external", "--inject", "speed_bias@0:bias_mm_s=1",
                                "--inject", "encoder_noise@0:sigma_um=1")
    api.ok("POST", "/api/v1/step", {"ticks": 1})
    faults = api.faults()
    assert sorted(f["type"] for f in faults["active"]) == ["encoder_noise", "speed_bias"], faults["active"]
    assert faults["active_total"] == 2 and faults["refused"] == 0
    for i in range(64):  # the queue holds 64 until the next tick
        api.ok("POST", "/api/v1/faults", {"type": "voltage_sag", "factor": 0.5}, status=202)
    full = api.post("/api/v1/faults", {"type": "voltage_sag", "factor": 0.5})
    assert full.status == 503, full
    assert "try again" in assert_error_body(full)
    assert api.faults()["active_total"] == 2  # nothing applied before the tick
    api.ok("POST", "/api/v1/step", {"ticks": 1})
    faults = api.faults()
    assert len(faults["active"]) == 32, len(faults["active"])
    assert faults["active_total"] == 2 + 32  # the scenario's two and 32 run-time faults
    assert faults["refused"] == 64 - 32
    assert api.stats()["http"]["faults_queued"] == 64
    api.ok("DELETE", "/api/v1/faults", status=202)
    api.ok("POST", "/api/v1/step", {"ticks": 1})
    faults = api.faults()
    assert faults["active"] == [] and faults["active_total"] == 0 and faults["refused"] == 32


def test_queued_faults_are_logged_on_stderr(emulator_factory):
    """'swum-emu: http: queued TYPE[:k=v,...] after tick N', by the API as it queues; the loop
    logs nothing of them."""
    emu, api = emulator_factory("--clock", "external")
    api.ok("POST", "/api/v1/step", {"ticks": 5})
    replies = [api.ok("POST", "/api/v1/faults", {"type": "phase_open", "phase": "B", "duration_s": 0.5}, status=202)]
    api.ok("POST", "/api/v1/step", {"ticks": 3})
    replies.append(api.ok("POST", "/api/v1/faults", {"type": "jam"}, status=202))
    replies.append(api.ok("DELETE", "/api/v1/faults/phase_open", status=202))
    replies.append(api.ok("DELETE", "/api/v1/faults", status=202))
    api.ok("POST", "/api/v1/step", {"ticks": 1})
    assert [r["after_tick"] for r in replies] == [6, 9, 9, 9], replies
    assert [r["queued"] for r in replies] == ["phase_open:phase=B,duration_s=0.5", "jam:duration_s=0", "clear:fault=phase_open",
                                              "clear all"], replies
    stop_emulator(emu)
    expected = [f"swum-emu: http: queued {r['queued']} after tick {r['after_tick']}" for r in replies]
    logged = [line for line in emu.stderr.splitlines() if "phase_open" in line or "jam" in line or "clear" in line]
    assert logged == expected, emu.stderr


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

        api.ok("POST", "/api/v1/recording/start")
        poll("a few rows recorded before the fault", lambda: api.recording()["rows"] >= 100)
        api.ok("POST", "/api/v1/faults", {"type": "over_temperature"}, status=202)
        poll("Modbus fault_code 4", lambda: inputs()["fault_code"] == FAULT_CODE_OVER_TEMPERATURE)
        state = api.state()
        assert state["fault_code"] == FAULT_CODE_OVER_TEMPERATURE
        assert state["fault"] == "over_temperature" and state["state"] == "fault"  # identifiers
        assert "over_temperature" in state["active_faults"]
        assert state["rejects"]["last"] == "none"

        # Enabling a faulted amplifier is rejected: the reason is an identifier too.
        rejected = state["rejects"]["count"]
        rr = client.write_register(registers.holding["command"]["address"], 1, slave=1)
        assert not rr.isError(), rr
        poll("the enable to be rejected", lambda: api.state()["rejects"]["count"] > rejected)
        assert api.state()["rejects"]["last"] == "fault_active"

        stopped = api.ok("POST", "/api/v1/recording/stop")
        assert stopped["dropped"] == 0
    finally:
        client.close()
    lines = api.get("/api/v1/recording.csv").body.decode().splitlines()
    columns = lines[0].split(",")
    rows = list(csv.reader(lines[1:]))
    faults = [row[columns.index("fault")] for row in rows]
    states = [row[columns.index("state")] for row in rows]
    assert faults[0] == "none" and states[0] == "enabled"
    assert faults[-1] == "over_temperature" and states[-1] == "fault"  # the identifier, as in State
    assert set(faults) == {"none", "over_temperature"}


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
    """A recording is written to a file of its own (NAME.XXXXXX), renamed to
    swum-emu-recording-PID.csv at the stop (replacing the last), and removed when swum-emu exits."""
    emu, api = emulator_factory("--http-recording-dir", str(tmp_path), "--clock", "external")
    final = tmp_path / f"swum-emu-recording-{emu.proc.pid}.csv"

    def names():
        return sorted(p.name for p in tmp_path.iterdir())

    api.ok("POST", "/api/v1/recording/start")
    api.ok("POST", "/api/v1/step", {"ticks": 10})
    [part] = names()
    assert re.fullmatch(re.escape(final.name) + r"\.[A-Za-z0-9]{6}", part), part
    api.ok("POST", "/api/v1/recording/stop")
    assert names() == [final.name]
    first = api.get("/api/v1/recording.csv").body
    assert final.read_bytes() == first and len(first.decode().splitlines()) == 1 + 10

    # The next recording: a new part beside the last one, which stays until the stop replaces it.
    api.ok("POST", "/api/v1/recording/start")
    api.ok("POST", "/api/v1/step", {"ticks": 5})
    during = names()
    assert len(during) == 2 and final.name in during, during
    assert final.read_bytes() == first
    api.ok("POST", "/api/v1/recording/stop")
    assert names() == [final.name]
    second = api.get("/api/v1/recording.csv").body
    assert final.read_bytes() == second and len(second.decode().splitlines()) == 1 + 5

    stop_emulator(emu)
    assert names() == [], "the recording outlived swum-emu"


def test_recording_under_way_is_removed_at_exit(emulator_factory, tmp_path):
    emu, api = emulator_factory("--http-recording-dir", str(tmp_path))
    api.ok("POST", "/api/v1/recording/start")
    poll("rows recorded", lambda: api.recording()["rows"] > 0)
    assert len(list(tmp_path.iterdir())) == 1
    stop_emulator(emu)
    assert list(tmp_path.iterdir()) == []


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
    emu, api = emulator_factory("--clock", "external", "--duration-s", "0.01")
    reply = api.post("/api/v1/step", {"ticks": 1000})
    # --duration-s 0.01 at 10 kHz is 100 ticks: a 1000-tick step cannot complete.
    assert reply.status == 503, reply
    assert assert_error_body(reply) == "the emulator stopped before the ticks ran"
    assert emu.wait(timeout=30) == 0, emu.stderr
    assert emu.output.splitlines()[1].startswith("swum-emu stopped: duration"), emu.output


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

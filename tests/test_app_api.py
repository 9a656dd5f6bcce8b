"""``linkage app``'s JSON API, over HTTP against a server started in-process: the contract the page and
outside tests rely on, NaN as null, and every class of bad request answered with a 4xx and one line,
after which the server still answers."""

import http.client
import json
import math
import subprocess
import sys
import threading
from pathlib import Path

import numpy as np
import pytest

import analytic
from sim.front import app
from sim import service

LIBRARY = Path(analytic.__file__).parent / "library"



def request(srv, method, path, body=None, headers=None, raw=None):
    """(status, headers, bytes) of one request on a fresh connection."""
    conn = http.client.HTTPConnection("127.0.0.1", srv.port, timeout=60)
    h = {"Host": f"127.0.0.1:{srv.port}"}
    if body is not None or raw is not None:
        h["Content-Type"] = "application/json"
    h.update(headers or {})
    data = raw if raw is not None else (json.dumps(body).encode() if body is not None else None)
    conn.request(method, path, body=data, headers=h)
    r = conn.getresponse()
    out = r.status, dict(r.getheaders()), r.read()
    conn.close()
    return out


def post(srv, path, body, **kw):
    status, headers, data = request(srv, "POST", path, body, **kw)
    return status, (json.loads(data) if headers.get("Content-Type") == "application/json" else data)


def assert_refused(srv, status, data, expect=range(400, 500)):
    assert status in expect, (status, data)
    err = json.loads(data) if isinstance(data, bytes) else data
    assert isinstance(err["error"], str) and err["error"] and "\n" not in err["error"]
    assert "Traceback" not in err["error"]
    # the server keeps serving
    s, _, d = request(srv, "GET", "/api/mechanisms")
    assert s == 200 and "fourbar" in json.loads(d)["names"]


# ------------------------------------------------------------------------------------ contract
def test_page_has_an_input_for_every_parameter_with_unit_and_range(server):
    status, headers, data = request(server, "GET", "/")
    assert status == 200 and headers["Content-Type"].startswith("text/html")
    text = data.decode()
    for p in service.describe(service.load("fourbar"))["parameters"]:
        assert f'name="{p["name"]}"' in text and f'data-param="{p["name"]}"' in text
    assert 'type="range"' in text and "range 0.02 … 0.2 m" in text
    assert headers["X-Content-Type-Options"] == "nosniff" and "frame-ancestors 'none'" in headers["Content-Security-Policy"]
    for path in ("/app.js", "/app.css", "/vendor/uPlot.iife.min.js", "/vendor/uPlot.min.css"):
        assert request(server, "GET", path)[0] == 200


def test_mechanisms_lists_builtins_and_library(server):
    status, _, data = request(server, "GET", "/api/mechanisms")
    body = json.loads(data)
    assert status == 200 and body["names"] == list(analytic.names())
    assert {"fourbar", "sixbar", "fivebar", "jansen"} <= set(body["names"])
    assert body["initial"] == {"name": "fourbar"}
    assert all({"name", "description", "inputs", "builtin"} <= set(m) for m in body["mechanisms"])


def test_solve_answers_parameters_outputs_points_and_figures(server):
    status, body = post(server, "/api/solve", {"mechanism": "fourbar", "set": {"l1": 0.12, "phi1_0": "30deg"},
                                               "samples": 91})
    assert status == 200
    assert body["parameters"]["l1"] == 0.12 and body["parameters"]["phi1_0"] == pytest.approx(math.pi / 6)
    mech = service.load("fourbar", {"l1": 0.12, "phi1_0": "30deg"})
    ref = service.analyze(mech, 91)
    assert set(body["outputs"]) == set(mech.outputs)
    for name in mech.outputs:
        assert np.allclose(body["outputs"][name], ref.solution[name], rtol=0, atol=1e-12)
    assert len(body["t"]) == 91 and set(body["inputs"]) == {"phi1", "omega1", "alpha1"}
    assert set(body["points"]) == {"A", "B", "C", "D", "E"}
    assert np.allclose(body["points"]["E"]["x"], ref.solution["xE"], atol=1e-12)
    assert body["figures"]["grashof"] == "grashof" and body["summary"]
    assert body["describe"]["output_point"] == "E" and body["units"]["phi3"] == "rad"
    assert [ln["points"] for ln in body["describe"]["links"]] == [["A", "B"], ["B", "C", "E"], ["D", "C"]]


def test_solve_without_figures_and_selected_outputs_at_fewer_digits(server):
    status, body = post(server, "/api/solve", {"mechanism": "sixbar", "figures": False, "outputs": ["s", "phi3"],
                                               "digits": 7})
    assert status == 200 and body["figures"] is None and set(body["outputs"]) == {"s", "phi3"}
    ref = service.analyze(service.load("sixbar"), 361).solution["s"]
    assert np.allclose(body["outputs"]["s"], ref, rtol=0, atol=1e-6 * np.max(np.abs(ref)))  # 7 digits of the peak


def test_nan_goes_out_as_null(server):
    # a slider-crank's stroke-time ratio is NaN (its piston has no quick return): null in strict JSON
    assert math.isnan(service.analyze(service.load("slider_crank"), 50).figures["time_ratio"])
    status, _, data = request(server, "POST", "/api/solve", {"mechanism": "slider_crank", "samples": 50})
    assert status == 200 and b"NaN" not in data and b"Infinity" not in data
    assert json.loads(data, parse_constant=pytest.fail)["figures"]["time_ratio"] is None
    assert app.series(np.array([1.0, np.nan, -np.inf])) == [1.0, None, None]


def test_every_mechanism_solves(server):
    for name in analytic.names():
        status, body = post(server, "/api/solve", {"mechanism": name, "samples": 25, "figures": False})
        assert status == 200, (name, body)
        assert body["points"] and body["outputs"] and len(body["t"]) == 25


def test_simulate_answers_compare_json_and_the_overlay(server):
    status, body = post(server, "/api/simulate", {"mechanism": "fourbar", "set": {"l1": 0.11}})
    assert status == 200 and body["passed"] is True
    mech = service.load("fourbar", {"l1": 0.11})
    assert set(body["errors"]) >= set(mech.outputs) and body["parameters"]["l1"] == 0.11
    sim = body["simulated"]
    n = len(sim["t"])
    assert 10 < n <= app.OVERLAY_POINTS and set(sim["outputs"]) == set(mech.outputs)
    assert len(sim["points"]["E"]["x"]) == n and len(sim["inputs"]["phi1"]) == n
    assert max(abs(e) for e in sim["errors"]["phi3"]) <= body["errors"]["phi3"]["tol"]


def test_uploaded_file_text_is_solved_and_simulated(server):
    text = (LIBRARY / "slider_crank.toml").read_text().replace('name = "slider_crank"', 'name = "my_engine"')
    status, body = post(server, "/api/solve", {"text": text, "set": {"r": 0.06}, "samples": 11})
    assert status == 200 and body["mechanism"] == "my_engine" and body["parameters"]["r"] == 0.06
    status, body = post(server, "/api/simulate", {"text": text, "outputs": ["xC"]})
    assert status == 200 and body["passed"] is True and set(body["simulated"]["outputs"]) == {"xC"}
    status, body = post(server, "/api/solve", {"text": "format = 'linkage/1'\nname = 'x'\n[[nonsense"})
    assert_refused(server, status, body)


def test_exports_are_downloads(server):
    body = {"mechanism": "fourbar", "set": {"l1": 0.11}}
    status, headers, data = request(server, "POST", "/api/export/csv", dict(body, samples=5))
    assert status == 200 and headers["Content-Disposition"] == 'attachment; filename="fourbar.csv"'
    lines = data.decode().splitlines()
    assert lines[0].startswith("t,phi1,omega1,alpha1,phi2") and len(lines) == 6
    status, headers, data = request(server, "POST", "/api/export/json", body)
    assert status == 200 and json.loads(data)["parameters"]["l1"] == 0.11
    status, headers, data = request(server, "POST", "/api/export/toml", body)
    assert status == 200 and b"l1 = 0.11" in data and headers["Content-Disposition"].endswith('fourbar.toml"')
    status, headers, data = request(server, "POST", "/api/export/mjcf", body)
    assert status == 200 and b"<mujoco" in data


def test_render_answers_an_mp4(server):
    status, headers, data = request(server, "POST", "/api/render", {"mechanism": "fourbar", "size": "160x120",
                                                                   "fps": 10})
    assert status == 200 and headers["Content-Type"] == "video/mp4" and data[4:8] == b"ftyp"


# ---------------------------------------------------------------------------------- bad requests
BAD_BODIES = [
    {"mechanism": "nosuch"},
    {"mechanism": "../analytic/library/fourbar.toml"},
    {"mechanism": "/etc/passwd"},
    {"mechanism": 3},
    {},
    {"mechanism": "fourbar", "set": {"l1": "abc"}},
    {"mechanism": "fourbar", "set": {"l1": -0.1}},
    {"mechanism": "fourbar", "set": {"l1": 1e300}},
    {"mechanism": "fourbar", "set": {"l1": True}},
    {"mechanism": "fourbar", "set": {"l1": [1]}},
    {"mechanism": "fourbar", "set": {"nosuch": 1}},
    {"mechanism": "fourbar", "set": [1, 2]},
    {"mechanism": "fourbar", "set": {"l1": 0.2, "l3": 0.1}},
    {"mechanism": "fourbar", "samples": 10 ** 30},
    {"mechanism": "fourbar", "samples": 1},
    {"mechanism": "fourbar", "samples": "361"},
    {"mechanism": "fourbar", "samples": 2.5},
    {"mechanism": "fourbar", "revolutions": 1e9},
    {"mechanism": "fourbar", "revolutions": -1},
    {"mechanism": "fourbar", "input_range": "x:y"},
    {"mechanism": "fourbar", "input_range": [1]},
    {"mechanism": "fourbar", "input_range": "2:1"},
    {"mechanism": "fourbar", "outputs": ["nosuch"]},
    {"mechanism": "fourbar", "outputs": "phi3"},
    {"mechanism": "fourbar", "figures": "yes"},
    {"mechanism": "fourbar", "digits": 99},
    {"mechanism": "fourbar", "sets": {"l1": 0.1}},
    {"text": 42},
    {"text": "not a mechanism file"},
]


@pytest.mark.parametrize("body", BAD_BODIES, ids=[json.dumps(b)[:40] for b in BAD_BODIES])
def test_bad_solve_bodies_are_refused_in_one_line(server, body):
    status, data = post(server, "/api/solve", body)
    assert_refused(server, status, data)


def test_cannot_turn_fully_says_where_it_can(server):
    status, data = post(server, "/api/solve", {"mechanism": "fourbar", "set": {"l1": 0.2, "l3": 0.1}})
    assert status == 400 and "cannot turn fully" in data["error"] and "reachable" in data["error"]


@pytest.mark.parametrize("raw", [b"{", b"[1, 2]", b'"text"', b"\xff\xfe", b'{"mechanism": NaN}',
                                 b'{"a": Infinity}', b"[" * 100000 + b"]" * 100000, b"1" * 5000])
def test_malformed_json_is_refused(server, raw):
    status, _, data = request(server, "POST", "/api/solve", raw=raw)
    assert_refused(server, status, data)


@pytest.mark.parametrize("path", ["/api/simulate", "/api/render", "/api/export/csv", "/api/export/mjcf"])
def test_other_actions_refuse_bad_bodies(server, path):
    for body in ({"mechanism": "nosuch"}, {"mechanism": "fourbar", "revolutions": 1e6},
                 {"mechanism": "fourbar", "set": {"l1": "x"}}, {"mechanism": "fourbar", "junk": 1}):
        status, data = post(server, path, body)
        assert_refused(server, status, data)


def test_render_size_and_rate_are_bounded(server):
    for extra in ({"size": "4096x4096"}, {"size": "641x480"}, {"size": "abc"}, {"fps": 1000},
                  {"revolutions": 6}):
        status, data = post(server, "/api/render", {"mechanism": "fourbar", **extra})
        assert_refused(server, status, data)


def test_wrong_content_type_length_and_size(server):
    status, _, data = request(server, "POST", "/api/solve", raw=b'{"mechanism": "fourbar"}',
                              headers={"Content-Type": "text/plain"})
    assert_refused(server, status, data, {415})
    # Declared too large: refused from the Content-Length alone, before any of the body is read. The body is
    # not sent (the server closes after its answer, so sending it would race that close: BrokenPipe).
    reply = raw_exchange(server, (f"POST /api/solve HTTP/1.1\r\nHost: 127.0.0.1:{server.port}\r\n"
                                  f"Content-Type: application/json\r\nContent-Length: {app.MAX_BODY + 1}\r\n\r\n"
                                  ).encode())
    head, _, data = reply.partition(b"\r\n\r\n")
    assert_refused(server, int(head.split()[1]), data, {413})
    conn = http.client.HTTPConnection("127.0.0.1", server.port, timeout=30)
    conn.putrequest("POST", "/api/solve", skip_host=True)
    conn.putheader("Host", f"127.0.0.1:{server.port}")
    conn.putheader("Content-Type", "application/json")
    conn.putheader("Transfer-Encoding", "chunked")
    conn.endheaders()
    conn.send(b"2\r\n{}\r\n0\r\n\r\n")
    r = conn.getresponse()
    assert_refused(server, r.status, r.read(), {411})


@pytest.mark.parametrize("method,path", [("GET", "/nosuch"), ("GET", "/api/solve"), ("GET", "/../sim/app.py"),
                                         ("GET", "/%2e%2e/sim/app.py"), ("GET", "/static/app.js"),
                                         ("POST", "/api/nosuch"), ("POST", "/"), ("PUT", "/api/solve"),
                                         ("DELETE", "/"), ("OPTIONS", "/api/solve"), ("PATCH", "/api/solve"),
                                         ("BREW", "/")])
def test_unknown_paths_and_methods(server, method, path):
    status, _, data = request(server, method, path, {"mechanism": "fourbar"} if method != "GET" else None)
    assert_refused(server, status, data, {404, 405})


def raw_exchange(srv, data: bytes) -> bytes:
    """Send raw bytes; the whole reply, up to the server closing the connection (it does after an error)."""
    import socket
    reply = b""
    with socket.create_connection(("127.0.0.1", srv.port), timeout=10) as s:
        s.sendall(data)
        try:
            while chunk := s.recv(65536):
                reply += chunk
        except ConnectionResetError:          # closed with part of an over-long request unread
            pass
    return reply


def test_malformed_requests_are_refused_by_the_framework_in_json(server):
    # a request line that is not HTTP/1.x: tornado's own refusal, before any handler (a bare 400, then closed)
    reply = raw_exchange(server, b"GET / HTTP/9.9\r\nHost: 127.0.0.1\r\n\r\n")
    assert reply.split(b"\r\n")[0] == b"HTTP/1.1 400 Bad Request" and b"Traceback" not in reply
    reply = raw_exchange(server, b"GET / HTTP/1.1\r\nHost: 127.0.0.1\r\nX: " + b"a" * 70000 + b"\r\n\r\n")
    assert reply.split(b"\r\n")[0] == b"HTTP/1.1 431 Request Header Fields Too Large" and b'{"error":' in reply
    reply = raw_exchange(server, b"GET /" + b"a" * 70000 + b" HTTP/1.1\r\n\r\n")     # HTTP/1.1 without a Host: as the first
    assert reply.split(b"\r\n")[0] == b"HTTP/1.1 400 Bad Request"
    reply = raw_exchange(server, b"GET /" + b"a" * 70000 + b" HTTP/1.1\r\nHost: 127.0.0.1:%d\r\n\r\n" % server.port)
    assert reply.split(b"\r\n")[0] == b"HTTP/1.1 414 Request-URI Too Long" and b'{"error":' in reply
    assert request(server, "GET", "/api/mechanisms")[0] == 200


# ------------------------------------------------------------------------------------- security
@pytest.mark.parametrize("host", ["evil.example:{port}", "127.0.0.1:1", "localhost", "", "127.0.0.1.evil:{port}"])
def test_foreign_host_header_is_refused(server, host):
    status, _, data = request(server, "GET", "/", headers={"Host": host.format(port=server.port)})
    assert_refused(server, status, data, {403})
    status, _, data = request(server, "POST", "/api/solve", {"mechanism": "fourbar"},
                              headers={"Host": host.format(port=server.port)})
    assert_refused(server, status, data, {403})


def test_localhost_host_and_same_origin_are_accepted(server):
    port = server.port
    assert request(server, "GET", "/", headers={"Host": f"localhost:{port}"})[0] == 200
    for origin in (f"http://127.0.0.1:{port}", f"http://localhost:{port}"):
        status, _ = post(server, "/api/solve", {"mechanism": "fourbar", "samples": 3}, headers={"Origin": origin})
        assert status == 200


@pytest.mark.parametrize("origin", ["http://evil.example", "null", "http://127.0.0.1:1", "https://127.0.0.1:{port}"])
def test_cross_origin_post_is_refused(server, origin):
    status, data = post(server, "/api/solve", {"mechanism": "fourbar"}, headers={"Origin": origin.format(port=server.port)})
    assert_refused(server, status, data, {403})


def test_binds_loopback_only(server):
    assert server.server_address[0] == "127.0.0.1"


# --------------------------------------------------------------------------------- the command
def test_exit_stops_the_server():
    srv = app.AppServer(0, {"name": "sixbar"})
    thread = threading.Thread(target=srv.serve_forever, daemon=True)
    thread.start()
    status, body = post(srv, "/api/exit", {})
    assert status == 200 and body == {"stopped": True}
    thread.join(10)
    assert not thread.is_alive()
    srv.server_close()


def test_command_prints_the_url_and_stops_on_exit(tmp_path):
    text = (LIBRARY / "klann.toml").read_text()
    path = tmp_path / "leg.toml"
    path.write_text(text)
    proc = subprocess.Popen([sys.executable, "-m", "sim", "app", str(path), "--port", "0", "--no-browser"],
                            stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, env=_no_display())
    try:
        line = proc.stdout.readline()
        assert line.startswith("linkage app: http://127.0.0.1:"), line
        port = int(line.split("127.0.0.1:")[1].split("/")[0])
        srv = type("S", (), {"port": port})
        status, _, data = request(srv, "GET", "/api/mechanisms")
        assert json.loads(data)["initial"] == {"name": "klann", "text": text}
        assert post(srv, "/api/exit", {})[0] == 200
        assert proc.wait(20) == 0
        assert "Traceback" not in proc.stderr.read()
    finally:
        proc.kill()


def test_command_refuses_a_bad_mechanism_in_one_line():
    r = subprocess.run([sys.executable, "-m", "sim", "app", "nosuch.toml", "--no-browser"], capture_output=True,
                       text=True, env=_no_display(), timeout=60)
    assert r.returncode == 2 and r.stderr.startswith("linkage: error:") and r.stderr.count("\n") == 1


def test_ctrl_c_stops_cleanly():
    import signal
    proc = subprocess.Popen([sys.executable, "-m", "sim", "app", "--port", "0", "--no-browser"],
                            stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, env=_no_display())
    try:
        line = proc.stdout.readline()
        assert line.startswith("linkage app: http://"), line
        # the event the signal waits on: the server answers a request (its loop runs), not a delay
        srv = type("S", (), {"port": int(line.split("127.0.0.1:")[1].split("/")[0])})
        assert request(srv, "GET", "/api/mechanisms")[0] == 200
        proc.send_signal(signal.SIGINT)
        assert proc.wait(120) in (0, 130)                 # a guard against a hang, not a measure of speed
        assert "Traceback" not in proc.stderr.read()
    finally:
        proc.kill()


def _no_display():
    import os
    return {k: v for k, v in os.environ.items() if k not in ("DISPLAY", "WAYLAND_DISPLAY")}

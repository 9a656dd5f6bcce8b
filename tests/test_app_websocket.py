"""The app's WebSocket for drag steps (sim/front/websocket.py, GET /api/socket): RFC 6455's handshake and
framing checked against the RFC's own worked examples, the page's origin alone let in, and a drag step over
the socket answering what the same POST answers."""

from __future__ import annotations

import http.client
import io
import json
import os
import socket
import struct

import numpy as np
import pytest

from sim.front import websocket as ws

RFC_KEY = "dGhlIHNhbXBsZSBub25jZQ=="
RFC_ACCEPT = "s3pPLMBiTxaQ9kYGzzhZRbK+xOo="          # RFC 6455 section 1.3's example
# RFC 6455 section 5.7: a single-frame masked text message "Hello"
RFC_MASKED_HELLO = bytes([0x81, 0x85, 0x37, 0xFA, 0x21, 0x3D, 0x7F, 0x9F, 0x4D, 0x51, 0x58])
RFC_UNMASKED_HELLO = bytes([0x81, 0x05, 0x48, 0x65, 0x6C, 0x6C, 0x6F])


def test_accept_key_is_rfc_6455_example():
    assert ws.accept_key(RFC_KEY) == RFC_ACCEPT


def test_masked_frame_from_rfc_decoded():
    fin, op, data = ws.read_frame(io.BytesIO(RFC_MASKED_HELLO), 1000)
    assert (fin, op, data) == (True, ws.TEXT, b"Hello")


def test_server_frame_is_rfc_unmasked_example():
    assert ws.encode(b"Hello") == RFC_UNMASKED_HELLO


@pytest.mark.parametrize("n", [0, 5, 125, 126, 65535, 65536])
def test_masked_frames_round_trip_at_every_length_form(n):
    payload = bytes(range(256)) * (n // 256) + bytes(range(n % 256))
    frame = ws.encode(payload, mask=b"\x01\x80\xfe\x7f")
    assert ws.read_frame(io.BytesIO(frame), 1 << 20) == (True, ws.TEXT, payload)


def test_unmasked_client_frame_refused():
    with pytest.raises(ws.Closed) as exc:
        ws.read_frame(io.BytesIO(RFC_UNMASKED_HELLO), 1000)
    assert exc.value.code == ws.PROTOCOL_ERROR


def test_frame_over_limit_refused():
    with pytest.raises(ws.Closed) as exc:
        ws.read_frame(io.BytesIO(ws.encode(b"x" * 200, mask=b"abcd")), 100)
    assert exc.value.code == ws.TOO_BIG


def test_fragments_joined_and_ping_answered():
    frames = (bytes([0x01, 0x83]) + b"abcd" + ws.unmask(b"Hel", b"abcd")       # text, not final
              + ws.encode(b"p", ws.PING, mask=b"wxyz")                           # a ping between fragments
              + bytes([0x80, 0x82]) + b"efgh" + ws.unmask(b"lo", b"efgh"))       # the final continuation
    out = io.BytesIO()
    assert ws.read_message(io.BytesIO(frames), out, 1000) == "Hello"
    assert out.getvalue() == bytes([0x8A, 0x01]) + b"p"                          # the pong echoes the ping


def _handshake(srv, origin: str | None, key: str = RFC_KEY) -> tuple[socket.socket, bytes]:
    s = socket.create_connection(("127.0.0.1", srv.port), timeout=10)
    lines = ["GET /api/socket HTTP/1.1", f"Host: 127.0.0.1:{srv.port}", "Upgrade: websocket",
             "Connection: Upgrade", f"Sec-WebSocket-Key: {key}", "Sec-WebSocket-Version: 13"]
    if origin is not None:
        lines.append(f"Origin: {origin}")
    s.sendall(("\r\n".join(lines) + "\r\n\r\n").encode())
    head = b""
    while b"\r\n\r\n" not in head:
        chunk = s.recv(4096)
        if not chunk:
            break
        head += chunk
    return s, head


def _read_server_frame(s: socket.socket) -> tuple[int, bytes]:
    f = s.makefile("rb")
    b0, b1 = f.read(2)
    n = b1 & 0x7F
    if n == 126:
        n = struct.unpack("!H", f.read(2))[0]
    elif n == 127:
        n = struct.unpack("!Q", f.read(8))[0]
    return b0 & 0x0F, f.read(n)


def test_handshake_accepts_own_origin(server):
    s, head = _handshake(server, server.url.rstrip("/"))
    with s:
        assert head.startswith(b"HTTP/1.1 101")
        assert f"Sec-WebSocket-Accept: {RFC_ACCEPT}".encode() in head


@pytest.mark.parametrize("origin", ["http://evil.example", "http://127.0.0.1:1", None])
def test_bad_origin_refused(server, origin):
    s, head = _handshake(server, origin)
    with s:
        assert head.startswith(b"HTTP/1.1 403")
        assert b"Sec-WebSocket-Accept" not in head


def test_drag_over_socket_answers_as_post(server):
    body = {"mechanism": "fourbar", "set": {}, "samples": 73, "figures": False, "point": "C",
            "target": [0.1, 0.12], "input": [0.6], "locked": []}
    conn = http.client.HTTPConnection("127.0.0.1", server.port, timeout=30)
    conn.request("POST", "/api/drag", json.dumps(body), {"Content-Type": "application/json"})
    posted = json.loads(conn.getresponse().read())
    s, head = _handshake(server, server.url.rstrip("/"))
    with s:
        assert head.startswith(b"HTTP/1.1 101")
        msg = json.dumps({"id": 7, "path": "/api/drag", "body": body}).encode()
        s.sendall(ws.encode(msg, mask=os.urandom(4)))
        op, data = _read_server_frame(s)
        got = json.loads(data)
        assert op == ws.TEXT and got["id"] == 7 and got["status"] == 200
        answer = got["answer"]
        assert answer["drag"]["set"].keys() == posted["drag"]["set"].keys()
        for k, v in posted["drag"]["set"].items():
            # the same inversion from the same start: only float summation order could differ
            assert answer["drag"]["set"][k] == pytest.approx(v, rel=1e-9, abs=1e-12)
        for p, xy in posted["solve"]["points"].items():
            np.testing.assert_allclose(np.array(answer["solve"]["points"][p]["x"], float),
                                       np.array(xy["x"], float), rtol=1e-9, atol=1e-12)  # as above
        s.sendall(ws.encode(json.dumps({"id": 8, "path": "/api/exit", "body": {}}).encode(), mask=b"abcd"))
        op, data = _read_server_frame(s)
        assert json.loads(data)["status"] == 404 and json.loads(data)["id"] == 8      # not a socket action
        s.sendall(ws.encode(b"\x03\xe8", ws.CLOSE, mask=b"abcd"))
        op, data = _read_server_frame(s)
        assert op == ws.CLOSE and data == b"\x03\xe8"


def test_unmasked_frame_closes_with_protocol_error(server):
    s, head = _handshake(server, server.url.rstrip("/"))
    with s:
        s.sendall(RFC_UNMASKED_HELLO)
        op, data = _read_server_frame(s)
        assert op == ws.CLOSE and struct.unpack("!H", data[:2])[0] == ws.PROTOCOL_ERROR


def test_packed_arrays_are_exact_float64():
    import base64
    from sim.front.requests import packed
    a = np.array([0.1, -2.5e-300, np.pi, np.nan, 1e300])
    got = np.frombuffer(base64.b64decode(packed(a)["f64"]), dtype="<f8")
    np.testing.assert_array_equal(got, a)             # bit for bit: nothing rounded, NaN kept as the gap
    assert np.frombuffer(base64.b64decode(packed(np.float64(2.0), 3)["f64"]), "<f8").tolist() == [2.0, 2.0, 2.0]


def test_solve_with_packed_arrays_holds_the_listed_values():
    import base64
    from sim.front import app
    body = {"mechanism": "fourbar", "samples": 37, "figures": False}
    listed = app.solve(body)
    packed = app.solve({**body, "arrays": "f64"})

    def un(v):
        return np.frombuffer(base64.b64decode(v["f64"]), "<f8")
    np.testing.assert_array_equal(un(packed["t"]), np.array(listed["t"], float))
    assert packed["outputs"].keys() == listed["outputs"].keys() and packed["points"].keys() == listed["points"].keys()
    for k, v in listed["outputs"].items():
        np.testing.assert_array_equal(un(packed["outputs"][k]), np.array(v, float))
    for p, xy in listed["points"].items():
        for c in "xy":
            np.testing.assert_array_equal(un(packed["points"][p][c]), np.array(xy[c], float))
    with pytest.raises(app.RequestError):
        app.solve({**body, "arrays": "f32"})


@pytest.mark.parametrize("text, status", [("not json", 400), ('{"id": 1, "path": ["x"], "body": {}}', 404),
                                          ('{"id": "a", "path": "/api/drag", "body": {}}', 400),
                                          ('{"id": 2, "path": "/api/drag", "body": []}', 400),
                                          ('{"id": 3, "path": "/api/drag", "body": {"point": 1}}', 400)])
def test_bad_socket_messages_answer_one_line(text, status):
    from sim.front import app
    got = json.loads(app.socket_answer(text))
    assert got["status"] == status and isinstance(got["error"], str) and "\n" not in got["error"]

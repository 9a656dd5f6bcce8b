"""The app's WebSocket for drag steps (GET /api/socket, tornado's): RFC 6455's handshake and framing checked over
a real socket against the RFC's own worked examples (frames built here, by hand, not by the server's library),
the page's origin alone let in, hostile frames refused, and a drag step over the socket answering what the same
POST answers."""

from __future__ import annotations

import http.client
import json
import os
import socket
import struct

import numpy as np
import pytest

from sim.front import app

RFC_KEY = "dGhlIHNhbXBsZSBub25jZQ=="
RFC_ACCEPT = "s3pPLMBiTxaQ9kYGzzhZRbK+xOo="          # RFC 6455 section 1.3's example
# RFC 6455 section 5.7: a single-frame masked text message "Hello", and the same unmasked
RFC_MASKED_HELLO = bytes([0x81, 0x85, 0x37, 0xFA, 0x21, 0x3D, 0x7F, 0x9F, 0x4D, 0x51, 0x58])
RFC_UNMASKED_HELLO = bytes([0x81, 0x05, 0x48, 0x65, 0x6C, 0x6C, 0x6F])
TEXT, BINARY, CLOSE, PING, PONG, CONTINUATION = 0x1, 0x2, 0x8, 0x9, 0xA, 0x0


def frame(payload: bytes, opcode: int = TEXT, mask: bytes = b"\x01\x80\xfe\x7f", fin: bool = True) -> bytes:
    """A client's frame (RFC 6455 5.2), masked with ``mask`` (4 bytes)."""
    n = len(payload)
    head = bytes([(0x80 if fin else 0) | opcode])
    if n < 126:
        head += bytes([0x80 | n])
    elif n < 1 << 16:
        head += bytes([0x80 | 126]) + struct.pack("!H", n)
    else:
        head += bytes([0x80 | 127]) + struct.pack("!Q", n)
    return head + mask + bytes(b ^ mask[i % 4] for i, b in enumerate(payload))


def _handshake(srv, origin: str | None, key: str = RFC_KEY) -> tuple[socket.socket, bytes]:
    s = socket.create_connection(("127.0.0.1", srv.port), timeout=10)
    lines = ["GET /api/socket HTTP/1.1", f"Host: 127.0.0.1:{srv.port}", "Upgrade: websocket",
             "Connection: Upgrade", f"Sec-WebSocket-Key: {key}", "Sec-WebSocket-Version: 13"]
    if origin is not None:
        lines.append(f"Origin: {origin}")
    s.sendall(("\r\n".join(lines) + "\r\n\r\n").encode())
    head = b""
    while b"\r\n\r\n" not in head:
        chunk = s.recv(1)
        if not chunk:
            break
        head += chunk
    return s, head


def _read_server_frame(s: socket.socket) -> tuple[int, bytes] | None:
    """(opcode, payload) of the server's next frame (which must be unmasked), or None at the end of the
    connection."""
    f = s.makefile("rb")
    two = f.read(2)
    if len(two) < 2:
        return None
    b0, b1 = two
    assert not b1 & 0x80                                  # a server's frames are never masked (RFC 6455 5.1)
    n = b1 & 0x7F
    if n == 126:
        n = struct.unpack("!H", f.read(2))[0]
    elif n == 127:
        n = struct.unpack("!Q", f.read(8))[0]
    return b0 & 0x0F, f.read(n)


def _opened(srv) -> socket.socket:
    s, head = _handshake(srv, srv.url.rstrip("/"))
    assert head.startswith(b"HTTP/1.1 101"), head
    return s


def test_handshake_accepts_own_origin_with_the_rfc_accept_key(server):
    s, head = _handshake(server, server.url.rstrip("/"))
    with s:
        assert head.startswith(b"HTTP/1.1 101")
        headers = dict(line.split(": ", 1) for line in head.decode().split("\r\n")[1:] if ": " in line)
        assert {k.lower(): v for k, v in headers.items()}["sec-websocket-accept"] == RFC_ACCEPT


@pytest.mark.parametrize("origin", ["http://evil.example", "http://127.0.0.1:1", "null", None])
def test_bad_origin_refused(server, origin):
    s, head = _handshake(server, origin)
    with s:
        assert head.startswith(b"HTTP/1.1 403")
        assert b"sec-websocket-accept" not in head.lower()
        body = b""
        while chunk := s.recv(4096):                      # the server closes the connection after a refusal
            body += chunk
        error = json.loads(body)["error"]
        assert "origin" in error.lower() and "\n" not in error


def test_the_rfc_masked_hello_is_read_and_answered_in_one_line(server):
    with _opened(server) as s:
        s.sendall(RFC_MASKED_HELLO)                       # "Hello": text, but not JSON
        op, data = _read_server_frame(s)
        got = json.loads(data)
        assert op == TEXT and got["id"] is None and got["status"] == 400 and "\n" not in got["error"]


@pytest.mark.parametrize("n", [5, 125, 126, 65535, 65536])
def test_frames_of_every_length_form_are_read(server, n):
    # a message of exactly n bytes (JSON padded with spaces), in the 7-bit, 16-bit and 64-bit length forms
    core = json.dumps({"id": n, "path": "/api/none", "body": {}}).encode()
    payload = core + b" " * (n - len(core)) if n >= len(core) else b"x" * n
    with _opened(server) as s:
        s.sendall(frame(payload, mask=os.urandom(4)))
        op, data = _read_server_frame(s)
        got = json.loads(data)
        assert op == TEXT and got["id"] == (n if n >= len(core) else None) and got["status"] in (400, 404)


def test_fragments_joined_and_ping_answered(server):
    message = json.dumps({"id": 5, "path": "/api/none", "body": {}}).encode()
    with _opened(server) as s:
        s.sendall(frame(message[:10], TEXT, b"abcd", fin=False)          # text, not final
                  + frame(b"p", PING, b"wxyz")                             # a ping between fragments
                  + frame(message[10:], CONTINUATION, b"efgh"))           # the final continuation
        assert _read_server_frame(s) == (PONG, b"p")                      # the pong echoes the ping
        op, data = _read_server_frame(s)
        assert op == TEXT and json.loads(data)["id"] == 5                  # the two fragments as one message


@pytest.mark.xfail(strict=True, reason="tornado 6.6 answers a client's unmasked frame (RFC 6455 5.1: the server "
                                      "MUST close): no guard is lost, a client that can send one (not a browser) "
                                      "can send the same bytes masked; the Host and Origin checks are the guard")
def test_unmasked_frame_ends_the_connection_unanswered(server):
    with _opened(server) as s:
        s.sendall(RFC_UNMASKED_HELLO)
        f = _read_server_frame(s)
        assert f is None or f[0] == CLOSE, f                              # no answer, the connection closed


def test_a_message_over_the_body_limit_is_closed_too_big(server):
    with _opened(server) as s:
        # only the header of a frame declaring MAX_BODY + 1 bytes: refused from its length, before its payload
        s.sendall(bytes([0x81, 0x80 | 127]) + struct.pack("!Q", app.MAX_BODY + 1) + b"abcd")
        f = _read_server_frame(s)
        assert f is not None and f[0] == CLOSE and struct.unpack("!H", f[1][:2])[0] == 1009


def test_a_binary_frame_is_closed_unsupported(server):
    with _opened(server) as s:
        s.sendall(frame(b"\x00\x01", BINARY))
        op, data = _read_server_frame(s)
        assert op == CLOSE and struct.unpack("!H", data[:2])[0] == 1003


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
        s.sendall(frame(msg, mask=os.urandom(4)))
        op, data = _read_server_frame(s)
        got = json.loads(data)
        assert op == TEXT and got["id"] == 7 and got["status"] == 200
        answer = got["answer"]
        assert answer["drag"]["set"].keys() == posted["drag"]["set"].keys()
        for k, v in posted["drag"]["set"].items():
            # the same inversion from the same start: only float summation order could differ
            assert answer["drag"]["set"][k] == pytest.approx(v, rel=1e-9, abs=1e-12)
        for p, xy in posted["solve"]["points"].items():
            np.testing.assert_allclose(np.array(answer["solve"]["points"][p]["x"], float),
                                       np.array(xy["x"], float), rtol=1e-9, atol=1e-12)  # as above
        s.sendall(frame(json.dumps({"id": 8, "path": "/api/exit", "body": {}}).encode(), mask=b"abcd"))
        op, data = _read_server_frame(s)
        assert json.loads(data)["status"] == 404 and json.loads(data)["id"] == 8      # not a socket action
        s.sendall(frame(b"\x03\xe8", CLOSE, mask=b"abcd"))
        op, data = _read_server_frame(s)
        assert op == CLOSE and data[:2] == b"\x03\xe8"


def test_packed_arrays_are_exact_float64():
    import base64
    from sim.front.requests import packed
    a = np.array([0.1, -2.5e-300, np.pi, np.nan, 1e300])
    got = np.frombuffer(base64.b64decode(packed(a)["f64"]), dtype="<f8")
    np.testing.assert_array_equal(got, a)             # bit for bit: nothing rounded, NaN kept as the gap
    assert np.frombuffer(base64.b64decode(packed(np.float64(2.0), 3)["f64"]), "<f8").tolist() == [2.0, 2.0, 2.0]


def test_solve_with_packed_arrays_holds_the_listed_values():
    import base64
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
    got = json.loads(app.socket_answer(text))
    assert got["status"] == status and isinstance(got["error"], str) and "\n" not in got["error"]

"""A minimal RFC 6455 WebSocket for the app's drag steps: the handshake's accept key, the checks of an upgrade
request, and reading and writing frames over a connection's file objects (standard library only).

A drag step over fetch pays the HTTP request and answer headers and the browser's fetch machinery each time
(4-7 ms of round trip for an empty request on this machine where the server answers in 0.2 ms); over one
open socket a step is a frame each way. Only what the page needs: text frames (fragmented ones joined), ping,
pong and close; binary frames and extensions are refused. A client's frames must be masked (RFC 6455 5.1).
"""

from __future__ import annotations

import base64
import hashlib
import struct

GUID = "258EAFA5-E914-47DA-95CA-C5AB0DC85B11"
"""RFC 6455 section 1.3: appended to the client's key before hashing."""

TEXT, BINARY, CLOSE, PING, PONG, CONTINUATION = 0x1, 0x2, 0x8, 0x9, 0xA, 0x0

PROTOCOL_ERROR, UNSUPPORTED, TOO_BIG = 1002, 1003, 1009
"""Close codes (RFC 6455 7.4.1)."""


class Closed(Exception):
    """The connection ended: the peer closed it, went away, or broke the protocol (``code``, ``reason``)."""

    def __init__(self, code: int = 1000, reason: str = ""):
        super().__init__(reason or f"closed ({code})")
        self.code = code
        self.reason = reason


def accept_key(key: str) -> str:
    """Sec-WebSocket-Accept for a client's Sec-WebSocket-Key: base64(SHA-1(key + GUID))."""
    return base64.b64encode(hashlib.sha1((key.strip() + GUID).encode("ascii")).digest()).decode("ascii")


def upgrade_problem(headers, origins: set[str]) -> str | None:
    """Why an upgrade request cannot become a WebSocket (one line), or None when it can. ``headers``: the
    request's (case-insensitive ``get``); ``origins``: the page's own origins, the only ones let in (a browser
    sends an Origin with every WebSocket handshake, and no same-origin policy guards a socket: this does)."""
    if "websocket" not in (headers.get("Upgrade") or "").lower():
        return "Upgrade: websocket is required"
    if "upgrade" not in [t.strip() for t in (headers.get("Connection") or "").lower().split(",")]:
        return "Connection: Upgrade is required"
    if (headers.get("Sec-WebSocket-Version") or "").strip() != "13":
        return "Sec-WebSocket-Version 13 is required"
    key = (headers.get("Sec-WebSocket-Key") or "").strip()
    try:
        if len(base64.b64decode(key, validate=True)) != 16:
            raise ValueError
    except ValueError:
        return "Sec-WebSocket-Key must be 16 bytes in base64"
    origin = (headers.get("Origin") or "").strip().lower()
    if origin not in origins:
        return f"WebSocket from origin {origin[:80] or '(none)'!r} refused: only the page's own origin may connect"
    return None


def encode(payload: bytes, opcode: int = TEXT, mask: bytes | None = None) -> bytes:
    """One final frame. A server's frames are unmasked; ``mask`` (4 bytes) makes a client's (for tests)."""
    n = len(payload)
    head = bytes([0x80 | opcode])
    bit = 0x80 if mask else 0
    if n < 126:
        head += bytes([bit | n])
    elif n < 1 << 16:
        head += bytes([bit | 126]) + struct.pack("!H", n)
    else:
        head += bytes([bit | 127]) + struct.pack("!Q", n)
    if mask:
        return head + mask + unmask(payload, mask)
    return head + payload


def unmask(data: bytes, mask: bytes) -> bytes:
    """XOR with the 4-byte mask repeated (its own inverse)."""
    n = len(data)
    if not n:
        return b""
    key = int.from_bytes((mask * (n // 4 + 1))[:n], "big")
    return (int.from_bytes(data, "big") ^ key).to_bytes(n, "big")


def _exactly(rfile, n: int) -> bytes:
    data = rfile.read(n) if n else b""
    if len(data) < n:
        raise Closed(1006, "the connection ended mid-frame")
    return data


def read_frame(rfile, limit: int) -> tuple[bool, int, bytes]:
    """(fin, opcode, payload) of the next frame, unmasked; ``limit``: the largest payload accepted [bytes]."""
    b0, b1 = _exactly(rfile, 2)
    if b0 & 0x70:
        raise Closed(PROTOCOL_ERROR, "reserved bits set: no extension was agreed")
    if not b1 & 0x80:
        raise Closed(PROTOCOL_ERROR, "a client's frame must be masked")
    n = b1 & 0x7F
    if n == 126:
        n = struct.unpack("!H", _exactly(rfile, 2))[0]
    elif n == 127:
        n = struct.unpack("!Q", _exactly(rfile, 8))[0]
    if n > limit:
        raise Closed(TOO_BIG, f"a frame of {n} bytes; at most {limit} are accepted")
    mask = _exactly(rfile, 4)
    return bool(b0 & 0x80), b0 & 0x0F, unmask(_exactly(rfile, n), mask)


def read_message(rfile, wfile, limit: int) -> str:
    """The next text message (fragments joined); answers pings, skips pongs; raises :class:`Closed` at a
    close frame (after echoing it) or a protocol error."""
    parts: list[bytes] = []
    size = 0
    while True:
        fin, op, data = read_frame(rfile, limit)
        if op == CLOSE:
            code = struct.unpack("!H", data[:2])[0] if len(data) >= 2 else 1000
            try:
                wfile.write(encode(data[:2], CLOSE))
            except OSError:
                pass
            raise Closed(code, "closed by the page")
        if op == PING:
            wfile.write(encode(data, PONG))
            continue
        if op == PONG:
            continue
        if op == BINARY:
            raise Closed(UNSUPPORTED, "text frames only")
        if op not in (TEXT, CONTINUATION) or (op == TEXT) == bool(parts):
            raise Closed(PROTOCOL_ERROR, f"unexpected opcode {op}")     # a continuation must follow a text frame
        size += len(data)
        if size > limit:
            raise Closed(TOO_BIG, f"a message over {limit} bytes")
        parts.append(data)
        if fin:
            try:
                return b"".join(parts).decode("utf-8")
            except UnicodeDecodeError:
                raise Closed(1007, "a text message that is not UTF-8") from None


def close_frame(code: int, reason: str = "") -> bytes:
    return encode(struct.pack("!H", code) + reason.encode("utf-8")[:120], CLOSE)


def serve(rfile, wfile, answer, limit: int) -> int:
    """Answer each text message with ``answer(text) -> bytes`` (sent as one text frame) until the page closes
    the socket, the connection ends or times out, or a frame breaks the protocol (closed with its code).
    Returns the messages answered."""
    count = 0
    while True:
        try:
            text = read_message(rfile, wfile, limit)
        except Closed as exc:
            if exc.code not in (1000, 1001, 1006):
                try:
                    wfile.write(close_frame(exc.code, exc.reason))
                except OSError:
                    pass
            return count
        except (OSError, ValueError):          # a timeout on an idle socket, a reset: the page reconnects
            try:
                wfile.write(close_frame(1001, "idle"))
            except OSError:
                pass
            return count
        wfile.write(encode(answer(text)))
        count += 1

"""A JSON POST to the app's server in the tests (the ``server`` fixture of tests/conftest.py)."""

from __future__ import annotations

import http.client
import json


def post(srv, path: str, body) -> tuple[int, object]:
    """(status, decoded JSON body) of POSTing ``body`` as JSON to ``path`` on ``srv``."""
    conn = http.client.HTTPConnection("127.0.0.1", srv.port, timeout=300)
    conn.request("POST", path, body=json.dumps(body).encode(),
                 headers={"Host": f"127.0.0.1:{srv.port}", "Content-Type": "application/json"})
    r = conn.getresponse()
    data = r.read()
    conn.close()
    return r.status, json.loads(data)

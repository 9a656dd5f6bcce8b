import pathlib
import sys

# Make tests/oracle.py importable as a plain module.
sys.path.insert(0, str(pathlib.Path(__file__).parent))

# A run started in the background of a non-interactive shell inherits SIGINT ignored; the Ctrl-C tests
# (signals sent to the command, or raised in this process) need it handled, as at a terminal. A handler
# here also gives the commands the tests start SIGINT's default (exec resets handled signals, not ignored).
import signal  # noqa: E402

if signal.getsignal(signal.SIGINT) == signal.SIG_IGN:
    signal.signal(signal.SIGINT, signal.default_int_handler)


# ------------------------------------------------------------------------------------- the app's tests
import threading  # noqa: E402

import pytest  # noqa: E402


@pytest.fixture(scope="module")
def server():
    """``linkage app`` on the four-bar, on a free port of 127.0.0.1, for one test module."""
    from sim.front import app
    srv = app.AppServer(0, {"name": "fourbar"})
    threading.Thread(target=srv.serve_forever, daemon=True).start()
    yield srv
    srv.shutdown()
    srv.server_close()


@pytest.fixture(scope="module")
def browser(request):
    """Debian's Chromium driven by Playwright (never a downloaded browser), launched with the test module's
    ``CHROMIUM`` path and ``ARGS``."""
    from playwright import sync_api
    with sync_api.sync_playwright() as p:
        b = p.chromium.launch(executable_path=request.module.CHROMIUM, args=request.module.ARGS)
        yield b
        b.close()

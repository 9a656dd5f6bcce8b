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

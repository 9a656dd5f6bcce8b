"""The ``linkage`` command (also ``python -m sim``): argument parsing over :mod:`sim.service`.

One module per command in this package, each with ``register(sub)`` (its options; it imports nothing
heavy, so that building the parser stays cheap) and the function that runs it; what they share is in
:mod:`sim.front.cli.options`. This module assembles the parser from :data:`COMMANDS` and runs one command.

Every user error ends in one line on stderr and exit code 2, never a traceback. MuJoCo, matplotlib and
scipy are imported only by the commands that need them.
"""

from __future__ import annotations

import argparse
import importlib
import os
import sys
import threading
import warnings

from analytic import ParameterError
from sim.front.cli.options import guard_outputs, one_line

COMMANDS = ("listing", "check", "analyze", "simulate", "compare", "render", "plot", "export", "run",
            "synthesize", "sweep", "dynamics", "forces", "import_file", "tolerance", "app")
"""The command modules of this package, in the order ``linkage --help`` lists them."""
MODULE_OF = {"list": "listing", "import": "import_file"}
"""The command modules not named as their command."""


class _Parser(argparse.ArgumentParser):
    def error(self, message):            # argparse's own errors: one line, exit 2
        self.exit(2, f"linkage: error: {message}\n")


def make_parser(command: str | None = None) -> argparse.ArgumentParser:
    """The parser of every command, or of ``command`` alone (what a run of it needs: the other commands'
    modules, and what they import, are not loaded)."""
    parser = _Parser(prog="linkage", description="Planar linkage kinematics, MuJoCo simulation and rendering.")
    sub = parser.add_subparsers(dest="command", required=True, parser_class=_Parser)
    module = MODULE_OF.get(command, command)
    for name in (module,) if module in COMMANDS else COMMANDS:
        importlib.import_module(f"sim.front.cli.{name}").register(sub)
    return parser


def _join_negative_values(parser: argparse.ArgumentParser, argv: list[str]) -> list[str]:
    """``--force -10,0`` as ``--force=-10,0``: argparse would take ``-10,0`` for an option. A value that
    starts with one '-' (``-10,0``, ``-inf:inf``, ``-.5``) and is not an option of the parser is joined to
    the option before it."""
    takes_value, options = set(), set()
    for action in _all_actions(parser):
        options.update(action.option_strings)
        if action.option_strings and action.nargs is None and not isinstance(
                action, (argparse._StoreTrueAction, argparse._StoreFalseAction, argparse._HelpAction)):
            takes_value.update(action.option_strings)
    out, i = [], 0
    while i < len(argv):
        tok = argv[i]
        nxt = argv[i + 1] if i + 1 < len(argv) else ""
        if tok in takes_value and len(nxt) > 1 and nxt[0] == "-" and nxt[1] != "-" and nxt not in options:
            out.append(f"{tok}={argv[i + 1]}")
            i += 2
            continue
        out.append(tok)
        i += 1
    return out


def _all_actions(parser):
    for action in parser._actions:
        yield action
        if isinstance(action, argparse._SubParsersAction):
            for sub in action.choices.values():
                yield from _all_actions(sub)


def interrupted(exc: BaseException) -> bool:
    """Whether ``exc`` was caused by Ctrl-C (a KeyboardInterrupt anywhere in its chain of causes)."""
    seen = set()
    while exc is not None and id(exc) not in seen:
        if isinstance(exc, KeyboardInterrupt):
            return True
        seen.add(id(exc))
        exc = exc.__cause__ or exc.__context__
    return False


class Terminated(BaseException):
    """SIGTERM, raised in the main thread so that partial outputs are removed on the way out."""


def _on_sigterm(signum, frame):
    raise Terminated()


def main(argv: list[str] | None = None) -> int:
    import signal
    main_thread = threading.current_thread() is threading.main_thread()
    previous = signal.signal(signal.SIGTERM, _on_sigterm) if main_thread else None
    try:
        with warnings.catch_warnings():
            # numpy's RuntimeWarnings (sqrt of a negative, 0/0) mark poses where a group does not assemble;
            # the solver flags those samples itself (Solution.valid) and every command reports them in words
            warnings.simplefilter("ignore", RuntimeWarning)
            return _main(argv)
    finally:
        if main_thread:
            signal.signal(signal.SIGTERM, previous)


def _main(argv: list[str] | None) -> int:
    try:
        argv = list(sys.argv[1:] if argv is None else argv)
        parser = make_parser(argv[0] if argv else None)
        argv = _join_negative_values(parser, argv)
        args = parser.parse_args(argv)
        guard_outputs(args)
        code = args.func(args)
        sys.stdout.flush()                   # here, not at exit: a reader gone (| head -n 0) is caught below
        return code
    except ParameterError as exc:
        print(f"linkage: error: {one_line(str(exc))}", file=sys.stderr)
        return 2
    except RecursionError:                   # a reader that does not name its input yet: still one line
        print("linkage: error: an input is nested too deeply (a JSON, TOML or YAML value inside thousands of "
              "brackets); flatten it", file=sys.stderr)
        return 2
    except KeyboardInterrupt:
        print("linkage: interrupted", file=sys.stderr)
        return 130
    except ImportError as exc:               # Ctrl-C while a compiled module (mujoco) initialises reaches us
        extra = getattr(exc, "name", None) in ("ezdxf", "trimesh", "build123d")
        if extra:                            # a library of the parts extra, needed past the early check
            print(f"linkage: error: this needs {exc.name} (the parts extra): pip install 'linkage[parts]'",
                  file=sys.stderr)
            return 2
        if not interrupted(exc):             # as "ImportError: initialization failed" caused by it
            raise
        print("linkage: interrupted", file=sys.stderr)
        return 130
    except Terminated:
        print("linkage: terminated", file=sys.stderr)
        return 143
    except BrokenPipeError:
        # the reader went away (e.g. | head): stop quietly, and keep Python from complaining at exit
        devnull = os.open(os.devnull, os.O_WRONLY)
        os.dup2(devnull, sys.stdout.fileno())
        return 0
    except OSError as exc:
        where = f" {exc.filename}" if exc.filename else ""
        print(one_line(f"linkage: error:{where} {exc.strerror or exc}"), file=sys.stderr)
        return 2
    except MemoryError:
        print("linkage: error: out of memory: reduce --samples, --revolutions or the sweep grid", file=sys.stderr)
        return 2


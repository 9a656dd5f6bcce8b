"""``linkage app``: its options. The server (:mod:`sim.front.app`) is imported when the command runs, so
that every other command's start does not pay for it."""

from __future__ import annotations

DEFAULT_PORT = 8765


def register(sub) -> None:
    """Add ``linkage app [MECH] [--port N] [--no-browser]`` to the CLI's subcommands."""
    import analytic
    p = sub.add_parser("app", help="interactive page: parameters, curves, animation, simulation, exports")
    first = analytic.names()[0]
    p.add_argument("mechanism", metavar="MECH", nargs="?", default=first,
                   help=f"the mechanism to open: a name (linkage list) or a linkage/1 file (default {first})")
    p.add_argument("--port", type=int, default=DEFAULT_PORT, metavar="N",
                   help=f"port on 127.0.0.1 (default {DEFAULT_PORT}; 0 picks a free one)")
    p.add_argument("--no-browser", action="store_true", help="do not open a browser; just print the URL")
    p.set_defaults(func=cmd_app)


def cmd_app(args) -> int:
    from sim.front.app import cmd_app as serve
    return serve(args)

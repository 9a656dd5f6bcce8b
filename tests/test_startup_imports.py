"""What a command loads before it works (issue 30, item 5): ``linkage list`` reads the library files' headers
and loads no numpy and no solver; a command's parser is built from its own module alone, with the same options
as in the full parser; the light modules that make this possible agree with the heavy ones they stand for."""

from __future__ import annotations

import argparse
import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]


def _loaded_after(code: str) -> set[str]:
    prog = ("import sys, io, contextlib\n" + code + "\nprint(' '.join(sorted(sys.modules)))")
    r = subprocess.run([sys.executable, "-c", prog], capture_output=True, text=True, cwd=ROOT, timeout=120)
    assert r.returncode == 0, r.stderr
    return set(r.stdout.splitlines()[-1].split())


def test_linkage_list_loads_no_numpy_and_no_solver():
    mods = _loaded_after("from sim.front.cli import main\n"
                         "with contextlib.redirect_stdout(io.StringIO()):\n    assert main(['list']) == 0")
    assert "numpy" not in mods
    heavy = sorted(m for m in mods if m.startswith(("analytic.mechanism", "analytic.registry", "analytic.solver",
                                                    "analytic.kinds", "analytic.closed_forms", "sim.model")))
    assert heavy == [], heavy


def test_linkage_list_prints_every_mechanism_the_registry_knows():
    """The light listing (analytic.catalog, the files' headers) against the library folder and the registry
    that builds the mechanisms: the built-ins first, then every shipped file in name order, each with the
    description its full definition gives."""
    import io
    import contextlib
    import analytic
    from sim.front.cli import main
    out = io.StringIO()
    with contextlib.redirect_stdout(out):
        assert main(["list"]) == 0
    rows = [line.split(maxsplit=1) for line in out.getvalue().splitlines()]
    listed = [name for name, _ in rows]
    shipped = {p.stem for p in (ROOT / "analytic" / "library").glob("*.toml")}
    assert set(listed) == shipped and len(listed) == len(shipped)
    assert listed[:3] == list(analytic.BUILTINS) and listed[3:] == sorted(listed[3:])
    for name, rest in rows:
        assert rest.endswith(analytic.definition(name).description), name


def _options(parser: argparse.ArgumentParser, command: str) -> list[tuple]:
    sub = next(a for a in parser._actions if isinstance(a, argparse._SubParsersAction)).choices[command]
    return sorted((tuple(a.option_strings), a.dest, repr(a.default), repr(a.choices)) for a in sub._actions)


def test_a_command_parsed_alone_has_the_options_of_the_full_parser():
    from sim.front.cli import make_parser
    full = make_parser()
    for command in ("list", "check", "analyze", "compare", "import", "synthesize", "dynamics"):
        alone = make_parser(command)
        commands = next(a for a in alone._actions if isinstance(a, argparse._SubParsersAction)).choices
        assert list(commands) == [command]
        assert _options(alone, command) == _options(full, command), command


def test_the_full_parser_loads_no_heavy_library():
    """``linkage --help`` and an unknown command build every command's options: still without scipy,
    matplotlib, MuJoCo or Dask (each 0.2-0.7 s of CPU)."""
    mods = _loaded_after("from sim.front.cli import make_parser\nmake_parser()")
    heavy = ("scipy", "matplotlib", "mujoco", "dask", "SALib", "pymoo", "shapely", "ezdxf", "trimesh", "build123d")
    assert sorted(m for m in heavy if m in mods) == []


def test_the_errors_are_one_class_whichever_module_names_them():
    import analytic
    from analytic import _common, errors
    assert analytic.ParameterError is errors.ParameterError is _common.ParameterError
    assert issubclass(analytic.FileError, analytic.ParameterError)
    assert issubclass(analytic.AssemblyError, analytic.ParameterError)


def test_the_lazy_faces_list_every_module_and_give_every_name():
    """The packages' lazy faces (lazy_loader.attach): each lists every module of its folder (a module left out
    could not be reached as an attribute), and every name each gives resolves, in a fresh process whose
    first ``import`` loaded none of them."""
    import pkgutil
    import analytic
    import analytic.format
    import sim.service
    for package, listed in ((analytic, analytic.SUBMODULES), (sim.service, sim.service.SUBMODULES),
                            (analytic.format, analytic.format.__all__)):
        found = {m.name for m in pkgutil.iter_modules(package.__path__)}
        assert set(listed) == found, (package.__name__, sorted(set(listed) ^ found))
    code = ("import analytic, analytic.format, sim.service\n"
            "light = {'numpy', 'analytic.registry', 'sim.service.analysis'} & set(sys.modules)\n"
            "for pkg, names in ((analytic, analytic.__all__), (analytic.format, analytic.format.__all__), "
            "(sim.service, sim.service.__all__)):\n"
            "    for n in names:\n        assert getattr(pkg, n) is not None, n\n"
            "print(sorted(light))")
    r = subprocess.run([sys.executable, "-c", "import sys\n" + code], capture_output=True, text=True, cwd=ROOT,
                       timeout=120)
    assert r.returncode == 0, r.stderr
    assert r.stdout.strip() == "[]", r.stdout          # nothing heavy before the first use


def test_analyze_of_the_four_bar_loads_only_what_it_uses():
    """Issue 39: ``linkage analyze fourbar`` imports the kinds it is built of (crank, RRR; ``point`` for its
    coupler point), its own closed form, and none of: the other kinds' modules (the cam's, the general
    group's solvers), the links-and-joints form, the motion laws, the other tools' formats, the loads, the
    other built-ins' closed forms, tempfile (no file written)."""
    mods = _loaded_after("from sim.front.cli import main\n"
                         "with contextlib.redirect_stdout(io.StringIO()):\n    assert main(['analyze', 'fourbar']) == 0")
    kinds = sorted(m.removeprefix("analytic.kinds.") for m in mods if m.startswith("analytic.kinds."))
    assert kinds == ["base", "compiled", "crank", "point", "rrr"], kinds
    unused = ("analytic.format.joints", "analytic.laws", "analytic.cams", "analytic.format.foreign",
              "analytic.format.pyslvs", "analytic.format.pmks", "sim.service.importing", "sim.service.loads",
              "analytic.loads", "analytic.solver.general_group", "analytic.solver.prismatic_group",
              "analytic.closed_forms.sixbar", "analytic.closed_forms.fivebar", "tempfile")
    assert sorted(m for m in unused if m in mods) == []


def test_the_kinds_table_names_each_kinds_module_and_section():
    """analytic.kinds.SECTIONS (light: no kind's module loaded to list the kinds or a section's) against each
    kind's own module: the same names, in the same sections."""
    from analytic import kinds
    import importlib
    for name, section in kinds.SECTIONS.items():
        kind = importlib.import_module(f"analytic.kinds.{name.lower()}").KIND
        assert (kind.name, kind.section) == (name, section)
        assert kinds.KINDS[name] is kind
    found = {p.stem for p in (ROOT / "analytic" / "kinds").glob("*.py")} - {"__init__", "base", "compiled", "_lines"}
    assert found == set(kinds.MODULES)
    assert "nope" not in kinds.KINDS and kinds.KINDS.get("nope") is None and len(kinds.KINDS) == len(found)


def test_the_light_lists_agree_with_the_modules_they_stand_for():
    """linkfile's JOINTS_FORM is joints.FIELDS (linkfile loads joints only for such a file); the lazy BUILTINS
    give each built-in its own closed-form module and parameter class."""
    import analytic
    from analytic.closed_forms import Builtin
    from analytic.format import joints, linkfile
    assert linkfile.JOINTS_FORM == joints.FIELDS
    assert list(analytic.BUILTINS) == list(analytic.catalog.BUILTIN_NAMES)
    for name, b in analytic.BUILTINS.items():
        assert isinstance(b, Builtin) and b.module.__name__ == f"analytic.closed_forms.{name}"
        assert b.params.__module__ == b.module.__name__ and b.outputs == b.module.OUTPUTS


def test_a_command_asks_openblas_for_one_thread_unless_told():
    """The entry point sets OPENBLAS_NUM_THREADS before numpy loads (OpenBLAS' spinning threads cost a command
    ~60 ms of CPU), and keeps the user's value."""
    code = ("import os, sys\nsys.argv = ['linkage', 'list']\nfrom sim.front import launch\n"
            "import contextlib, io\nwith contextlib.redirect_stdout(io.StringIO()):\n    launch.main()\n"
            "print(os.environ['OPENBLAS_NUM_THREADS'])")
    for given, expected in ((None, "1"), ("3", "3")):
        env = {k: v for k, v in __import__("os").environ.items() if k != "OPENBLAS_NUM_THREADS"}
        if given:
            env["OPENBLAS_NUM_THREADS"] = given
        r = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, cwd=ROOT, env=env,
                           timeout=120)
        assert r.returncode == 0, r.stderr
        assert r.stdout.split()[-1] == expected


def test_the_gl_backend_is_chosen_without_looking_for_osmesa_where_egl_is_found(monkeypatch):
    """EGL where it is installed, else OSMesa where that is, else EGL (MuJoCo's message then names it); a
    library not found costs ldconfig, gcc and ld runs, so OSMesa is not looked for where EGL is found."""
    import ctypes.util
    from sim.output import gl
    for egl, osmesa, expected in ((True, True, "egl"), (True, False, "egl"), (False, True, "osmesa"),
                                  (False, False, "egl")):
        asked = []
        found = {"EGL": egl, "OSMesa": osmesa}
        monkeypatch.setattr(ctypes.util, "find_library",
                            lambda name: asked.append(name) or (f"lib{name}.so" if found[name] else None))
        for var in ("MUJOCO_GL", "PYOPENGL_PLATFORM"):      # set first: their state is restored after the test
            monkeypatch.setenv(var, "")
            monkeypatch.delenv(var)
        assert gl.ensure_gl_backend() == expected
        assert asked == (["EGL"] if egl else ["EGL", "OSMesa"])
    monkeypatch.setenv("MUJOCO_GL", "glfw")                 # the user's choice, nothing looked for
    assert gl.ensure_gl_backend() == "glfw"


def test_every_kinds_module_is_an_attribute_of_its_package_though_imported_lazily():
    """``analytic.loads.torque`` and ``analytic.kinds.rrr`` read as before the kinds were imported on first use
    (a script's ``from analytic import loads; loads.torque.constant(...)`` failed with an AttributeError)."""
    code = ("import analytic.loads as L, analytic.kinds as K\n"
            "print(all(getattr(L, m).__name__ == 'analytic.loads.' + m for m in L.MODULES),"
            " all(getattr(K, m).__name__ == 'analytic.kinds.' + m for m in K.MODULES))\n"
            "try:\n    L.no_such_kind\nexcept AttributeError:\n    print('refused')\n")
    r = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, cwd=ROOT, timeout=120)
    assert r.returncode == 0, r.stderr
    assert r.stdout.split() == ["True", "True", "refused"], r.stdout

"""The issue's fuzzing campaign at its full size (seeded): mutated mechanism files (TOML and JSON), option sets
through the ``linkage`` command, hostile requests to the app's API. tests/test_fuzz.py runs a small part of
it in the suite; this runs 1,500 files, 450 option sets and 500 app requests and reports every class.

Run:  python benchmarks/fuzz.py [--seed N] [--files N] [--options N] [--requests N]

What counts as handled (issue 20): a file parses or is refused with ParameterError in one line; an option set
exits 0 (1 for a compare that fails its verdict) or 2 with one line (argparse: usage + one line), writes
nothing outside its output folder; an app request gets 2xx or 4xx with a one-line error, never 5xx; every
case within 20 s, the process within 4 GB. Exit status 0 if every case is handled, 1 otherwise (the
classes that were not are listed with a minimal example).
"""

from __future__ import annotations

import argparse
import contextlib
import http.client
import io
import json
import os
import random
import re
import resource
import signal
import sys
import tempfile
import threading
import time
from collections import Counter
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT))

import analytic  # noqa: E402
from analytic import ParameterError  # noqa: E402
from analytic.applications import figures  # noqa: E402
from analytic.registry import LIBRARY  # noqa: E402

CASE_SECONDS = 20
"""The longest a case may take (issue 20: nonsense refused within 20 s)."""
MEMORY_GB = 4.0

TOKENS = ['"30deg"', '"1/30deg"', "1e308", "-1e308", "9" * 40, "0", "-0.0", "[]", "[[[[1]]]]", "{a = 1}", '""',
          '"' + "1" * 300 + '"', '"' + "(" * 60 + "1" + ")" * 60 + '"', '"sqrt(-1)"', '"l1/0"', '"l1**99"', "true",
          '"nan"', '"inf"', '"a\\nb"', '"l1 deg"', '"__import__(\'os\')"', "nan", "inf", '"' + "-" * 200 + '1"',
          "1e-300", '"2deg/3"', '"1e999"', '["x", "y", "z"]', '"' + "1" * 2000 + 'x"', "1" * 400,
          '"' + "+".join(["1"] * 300) + '"', '{ through = [1e308, "x"], angle = "1e308deg" }', '"\\u0000"',
          '"9e9999deg"', "-inf", '"' + "9." * 500 + '"', "[" * 200 + "]" * 200]


class Timeout(BaseException):
    """A case ran past CASE_SECONDS."""


def _alarm(signum, frame):
    raise Timeout()


def mutate(rng: random.Random, text: str) -> str:
    """1-4 line edits: delete, duplicate, replace a value by a hostile token, truncate, insert a parameter,
    corrupt digits, add a long chain of parameters in reverse order, or nest a table deeply."""
    lines = text.splitlines() or [""]
    for _ in range(rng.randint(1, 3)):
        i = rng.randrange(len(lines))
        op = rng.randrange(6) if rng.random() < 0.85 else rng.randrange(6, 9)
        if op == 0:
            del lines[i]
        elif op == 1:
            lines.insert(i, lines[rng.randrange(len(lines))])
        elif op == 2 and "=" in lines[i]:
            lines[i] = lines[i].split("=", 1)[0] + "= " + rng.choice(TOKENS)
        elif op == 3:
            lines[i] = lines[i][: rng.randrange(len(lines[i]) + 1)]
        elif op == 4:
            lines.insert(i, f"p{rng.randrange(99)} = {rng.choice(TOKENS)}")
        elif op == 5:
            lines[i] = lines[i].replace(rng.choice("0123456789"), rng.choice(["", "9" * 30, "e", ".", "-"]))
        elif op == 6:                                 # a long chain defined in reverse order
            n = rng.choice([50, 600, 1500])
            chain = [f"c{k} = \"c{k + 1} + 1\"" for k in range(n)] + [f"c{n} = 1"]
            at = next((k for k, ln in enumerate(lines) if ln.strip() == "[parameters]"), None)
            if at is not None:
                lines[at + 1:at + 1] = chain
        elif op == 7:                                 # deep nesting
            lines.insert(i, "deep = " + "[" * rng.choice([50, 500, 5000]) + "]" * 0)
        else:                                         # a huge ground table
            if any(ln.strip() == "[ground]" for ln in lines):
                at = next(k for k, ln in enumerate(lines) if ln.strip() == "[ground]")
                lines[at + 1:at + 1] = [f"G{k} = [{k}, {k}]" for k in range(rng.choice([100, 600, 9000]))]
        if not lines:
            lines = [""]
    return "\n".join(lines) + "\n"


def mutate_json(rng: random.Random, text: str) -> str:
    data = json.loads(json.dumps(analytic.format.linkfile.tomllib.loads(text)))
    for _ in range(rng.randint(1, 3)):
        key = rng.choice(sorted(data))
        data[key] = rng.choice([None, [], {}, "x", 1e308, -1, [[1]], {"a": {"b": []}}, "1/30deg", 10 ** 30,
                                "(" * 100 + "1" + ")" * 100, [[[[[[]]]]]] * 3, {"format": "linkage/1"}])
    raw = json.dumps(data)
    if rng.random() < 0.1:                            # a duplicate key, or deep nesting
        raw = raw[:-1] + ', "format": "linkage/1"}' if rng.random() < 0.5 else "[" * 3000 + "]" * 3000
    return raw


def one_line(msg: str) -> bool:
    return bool(msg) and "\n" not in msg.strip() and len(msg) < 600


def _timed(fn):
    """(class, seconds) of running fn under the CASE_SECONDS alarm."""
    t0 = time.perf_counter()
    signal.alarm(CASE_SECONDS)
    try:
        cls = fn()
    except Timeout:
        cls = "TIMEOUT"
    finally:
        signal.alarm(0)
    return cls, time.perf_counter() - t0


# ------------------------------------------------------------------------------------------ files
def file_case(text: str, suffix: str) -> str:
    try:
        mech = analytic.from_text(text, f"fuzz{suffix}")
        analytic.format.linkfile.parameter_values(mech.definition)
        if len(mech.inputs) == 1:
            figures.assembly_ranges(mech, samples=72)
        mech.solve([mech.inputs[0].motion.q0] * 1 if len(mech.inputs) == 1 else [[i.motion.q0 for i in mech.inputs]])
        return "parsed"
    except ParameterError as exc:
        return "refused" if one_line(str(exc)) else "MULTI-LINE MESSAGE"
    except RecursionError:
        return "CRASH RecursionError"
    except MemoryError:
        return "CRASH MemoryError"
    except Exception as exc:                          # noqa: BLE001 - what the campaign looks for
        return f"CRASH {type(exc).__name__}"


# ---------------------------------------------------------------------------------------- options
OPTIONS = [["--set", "l1=0.12"], ["--set", "l1=5deg"], ["--set", "zz=1"], ["--set", "l1=1e308"], ["--set", "l1=-1"],
           ["--samples", "0"], ["--samples", "3"], ["--samples", "1e9"], ["--revolutions", "-1"],
           ["--revolutions", "0.3"], ["--input-range", "10deg:20deg"], ["--input-range", "20deg:10deg"],
           ["--input-range", "x"], ["--set", "branch=0"], ["--set", "l1=1/30deg"], ["--set", "l1="],
           ["--set", "=1"], ["--set", "l1=" + "1" * 500], ["--json"], ["--units", "mm"], ["--angles", "deg"],
           ["--speeds", "rpm"], ["--units", "furlong"], ["--set", "phi1_0=1e308"], ["--set", "omega1=0"],
           ["--set", "l1=" + "(" * 200 + "1" + ")" * 200], ["--set", "l1=" + "9." * 1000],
           ["--input-range", "0:1e308"], ["--input-range", "-1e308:1e308"], ["--set", "r=1"], ["--set", "l2=4deg"],
           ["--csv", "out.csv"], ["--csv", "/dev/null/x.csv"], ["--csv", "out.txt"], ["--set", "l1=nan"],
           ["--set", "l1=inf"], ["--set", "omega2=1e6"], ["--set", "l1=\x00"], ["--set", "l1=0.1\nl2=3"]]
COMMANDS = ["analyze"] * 6 + ["check"] * 2 + ["export"]
MECHANISMS = ["fourbar", "fivebar", "sixbar", "slider_crank", "whitworth", "jansen", "nope", "../etc/passwd"]


def option_case(argv: list[str], folder: Path) -> str:
    from sim.front.cli import main
    err = io.StringIO()
    before = set(os.listdir(folder))
    with contextlib.redirect_stdout(io.StringIO()), contextlib.redirect_stderr(err):
        try:
            code = main(argv)
        except SystemExit as exc:                     # argparse's own usage errors
            code = exc.code
        except Timeout:
            raise
        except Exception as exc:                      # noqa: BLE001
            return f"CRASH {type(exc).__name__}"
    text = err.getvalue().strip()
    lines = text.splitlines()
    if "Traceback" in text:
        return "TRACEBACK"
    if code == 2 and not (1 <= len(lines) <= 2):
        return "EXIT 2 WITHOUT ONE LINE"
    if code not in (0, 1, 2):
        return f"EXIT {code}"
    for name in set(os.listdir(folder)) - before:
        os.remove(folder / name) if (folder / name).is_file() else None
    return f"exit {code}"


def option_sets(rng: random.Random, n: int):
    for _ in range(n):
        cmd = rng.choice(COMMANDS)
        mech = rng.choice(MECHANISMS)
        opts = [o for _ in range(rng.randint(1, 3)) for o in rng.choice(OPTIONS)]
        if cmd == "check":
            opts = [o for o in opts if o not in ("--json",) and not o.startswith("out.") and o != "--csv"]
            opts = [o for o in opts if o not in ("--samples", "--input-range", "0", "3", "1e9")]
        if cmd == "export":
            opts = ["--toml", "out.toml"] + [o for k, o in enumerate(opts) if opts[k - 1] == "--set" or o == "--set"]
        yield [cmd, mech, *opts]


# ----------------------------------------------------------------- issue 32: the newer surfaces
PEERS = ROOT / "tests" / "peers_examples"
HOSTILE_JSON = ['{"2": ' + "[" * 50_000 + "]" * 50_000 + "}", '{"2": {"m": ' + "9" * 5001 + ', "cx": 0, "cy": 0, "I": 1}}',
                '{"2": {"m": 1, "cx": 0, "cy": 0, "I": ' + "9" * 400 + "}}", '{"2": {"m": NaN, "cx": 0, "cy": 0, "I": 1}}',
                '{"2": {"m": 1e308, "cx": 0, "cy": 0, "I": 1}}', '{"2": {"m": "a"}}', "[1, 2]", "", "\xff",
                '{"9": {"m": 1, "cx": 0, "cy": 0, "I": 1}}', '{"2": {"m": 1, "cx": 0, "cy": 0, "I": 0.01}}']
HOSTILE_CSV = ["omega;tau\n0;2\n100;0\n", "omega,tau\n0," + "1" * 200_000 + "\n100,0\n", "omega,tau\n0,2\xb0\n100,0\n",
               "", "omega,tau\n", "omega,tau\n0,1e308\n100,0\n", "omega,tau\nnan,2\n100,0\n", "rpm,tau\n0,2\n1000,0\n",
               "omega,tau\n0,2\n100,0\n", "omega,tau\n0,2\n0,0\n", "omega,tau\n0," + "9" * 5001 + "\n100,0\n",
               "x,y\n0,0\n1,0.2\n2,0.1\n3,-0.4\n", "x;y\n0;0\n1;0.2\n2;0.1\n3;-0.4\n", "x,y\n0,0\n0,0\n0,0\n0,0\n",
               "x,y\n0," + "1" * 200_000 + "\n1,0\n2,0\n3,1\n"]
VALUES = ["2,150rpm", "2,15.7rad/s", "1e308,1", "2,inf", "2,-5", "0,0", "2", "a,b", "2,150rpm,3", "-2,150", "1e-300,1e-300",
          "9" * 400 + ",1", "2,150furlong", "2,1e308"]
SCALARS = ["0", "-1", "1e308", "inf", "nan", "1e-300", "0.01", "30deg", "10000kg*mm^2", "x", "9" * 400, "0.5", "150rpm"]
SURFACE_OPTIONS = {
    "forces": [["--inertia", "in.json"], ["--samples", "SCALAR"], ["--gravity", "0,SCALAR"], ["--force", "SCALAR,0"],
               ["--cutting-force", "SCALAR"], ["--balance"], ["--balance", "2,9"], ["--csv", "in.json"], ["--csv", "f.csv"],
               ["--json"], ["--csv", "LIBRARY/x.csv"], ["--csv", "a\nb.csv"], ["--revolutions", "SCALAR"]],
    "dynamics": [["--motor", "VALUE"], ["--motor-table", "table.csv"], ["--flywheel", "SCALAR"], ["--start-speed", "SCALAR"],
                 ["--target-fluctuation", "SCALAR"], ["--inertia", "in.json"], ["--csv", "table.csv"], ["--plot", "d.png"],
                 ["--csv", "d.csv"], ["--revolutions", "SCALAR"], ["--json"], ["--plot", "LIBRARY/d.png"]],
    "synthesize": [["--popsize", "SCALAR"], ["--seed", "SCALAR"], ["--budget", "SCALAR"], ["--restarts", "SCALAR"],
                   ["--min-transmission", "SCALAR"], ["--max-ratio", "SCALAR"], ["--region", "SCALAR"], ["--units", "mm"],
                   ["--out", "t.csv"], ["--out", "LIBRARY/s.toml"], ["--out", "s.toml"], ["--plot", "t.csv"],
                   ["--designs", "SCALAR"], ["--type", "sixbar"]],
    "import": [["--input", "0,1"], ["--input", "SCALAR,1"], ["--units", "cm"], ["--out", "src.txt"], ["--out", "LIBRARY/i.toml"],
               ["--out", "i.toml"], ["--out", "a\nb.toml"]],
}


def surface_cases(rng: random.Random, n: int):
    """(argv, files to write first): the newer commands with hostile options and input files."""
    from analytic.registry import LIBRARY as lib
    sources = [p for p in sorted(PEERS.iterdir()) if p.suffix in (".txt", ".pyslvs")]
    for _ in range(n):
        cmd = rng.choice(list(SURFACE_OPTIONS))
        files = {"in.json": rng.choice(HOSTILE_JSON), "table.csv": rng.choice(HOSTILE_CSV), "t.csv": rng.choice(HOSTILE_CSV)}
        opts = [o for _ in range(rng.randint(1, 3)) for o in rng.choice(SURFACE_OPTIONS[cmd])]
        opts = [o.replace("SCALAR", rng.choice(SCALARS)).replace("VALUE", rng.choice(VALUES))
                .replace("LIBRARY", str(lib)) for o in opts]
        if cmd == "forces":
            argv = ["forces", rng.choice(["fourbar", "sixbar", "slider_crank", "fivebar"]), *opts]
        elif cmd == "dynamics":
            if "--motor" not in opts and "--motor-table" not in opts:
                opts = ["--motor", rng.choice(VALUES)] + opts
            argv = ["dynamics", rng.choice(["fourbar", "slider_crank"]), "--revolutions", "2", *opts]
        elif cmd == "synthesize":
            argv = ["synthesize", "path", "t.csv", "--budget", "2", "--restarts", "1", "--generations", "2", *opts]
        else:
            src = rng.choice(sources)
            text = src.read_text()
            nums = list(re.finditer(r"-?\d+(\.\d+)?", text))
            for _ in range(rng.randint(0, 2)):
                m = rng.choice(nums)
                text = text[:m.start()] + rng.choice(SCALARS + ["1e999", "-0", ""]) + text[m.end():]
                nums = list(re.finditer(r"-?\d+(\.\d+)?", text))
            name = "src" + src.suffix
            files[name] = text
            argv = ["import", name, *(opts if "--out" in opts else ["--out", "i.toml", *opts])]
        yield argv, files


def _is_output(argv: list[str], name: str) -> bool:
    """Whether ``name`` appears only as an output of ``argv`` (a file the command may write)."""
    outs = {argv[i + 1] for i, a in enumerate(argv[:-1]) if a in ("--csv", "--out", "--plot", "--render", "--toml")}
    ins = {argv[i + 1] for i, a in enumerate(argv[:-1]) if a in ("--inertia", "--motor-table")} | {
        a for i, a in enumerate(argv) if i and not argv[i - 1].startswith("--") and not a.startswith("--")}
    return name in outs and name not in ins


def surface_case(argv: list[str], files: dict, folder: Path) -> str:
    """One run of the newer surfaces: handled if exit 0/1, or 2 with one line; the inputs byte-identical,
    nothing written into the library, no temporary left."""
    from analytic.registry import LIBRARY as lib
    for name in list(os.listdir(folder)):
        (folder / name).unlink()
    for name, text in files.items():
        (folder / name).write_bytes(text.encode("utf-8", "surrogateescape") if "\xff" not in text and "\xb0" not in text
                                    else text.encode("latin-1", "replace"))
    before = {n: (folder / n).read_bytes() for n in os.listdir(folder) if n in argv and not _is_output(argv, n)}
    library = sorted(os.listdir(lib))
    cls = option_case(argv, folder)
    if any((folder / n).read_bytes() != b for n, b in before.items() if (folder / n).exists()) or \
            any(not (folder / n).exists() for n in before):
        return "INPUT OVERWRITTEN"
    if sorted(os.listdir(lib)) != library:
        for n in set(os.listdir(lib)) - set(library):
            (lib / n).unlink()
        return "WROTE INTO THE LIBRARY"
    if any(n.startswith(".") for n in os.listdir(folder)):
        return "TEMPORARY LEFT"
    return cls if cls != "exit 1" else "exit 1 (verdict)"


# ------------------------------------------------------------------------------------------- app
def app_requests(rng: random.Random, n: int, files: list[Path]):
    values = [None, True, -1, 0, 1e308, 10 ** 40, "x", "30deg", "1/30deg", "1" * 300, [], [1, 2], {}, {"l1": "x"},
              {"l1": 1e308}, {"l1": "(" * 50}, "fourbar", "../../etc/passwd", "\u0000", "a\nb", {"l1": 0.12},
              [0.5, 1.5], "1:2", 3, 0.25]
    fields = ["mechanism", "set", "samples", "revolutions", "input_range", "outputs", "text", "zz", "figures", "digits"]
    paths = ["/api/solve"] * 6 + ["/api/simulate", "/api/export/toml", "/api/export/json", "/api/describe",
                                  "/api/nope", "/../../etc/passwd"]
    for k in range(n):
        body = {"mechanism": rng.choice(["fourbar", "fivebar", "whitworth"])} if rng.random() < 0.6 else {}
        for _ in range(rng.randint(0 if body else 1, 3)):
            body[rng.choice(fields)] = rng.choice(values)
        if k % 8 == 0:
            body["text"] = mutate(rng, files[k % len(files)].read_text())
        path = rng.choice(paths)
        if path == "/api/simulate":
            body["revolutions"] = 0.1
        raw = json.dumps(body).encode()
        if k % 13 == 7:
            raw = raw[: rng.randrange(len(raw))] + bytes([rng.randrange(128, 256)])
        if k % 29 == 3:
            raw = b"[" * 100_000
        yield path, raw


def app_case(port: int, path: str, raw: bytes) -> str:
    conn = http.client.HTTPConnection("127.0.0.1", port, timeout=CASE_SECONDS)
    try:
        conn.request("POST", path, body=raw, headers={"Host": f"127.0.0.1:{port}", "Content-Type": "application/json"})
        r = conn.getresponse()
        status, data = r.status, r.read()
    except Exception as exc:                          # noqa: BLE001
        return f"NO ANSWER {type(exc).__name__}"
    finally:
        conn.close()
    if status >= 500:
        return f"HTTP {status}"
    if status >= 400:
        try:
            msg = json.loads(data)["error"]
        except (ValueError, KeyError, TypeError):
            return f"HTTP {status} WITHOUT A JSON ERROR"
        return f"http {status}" if one_line(msg) else f"HTTP {status} MULTI-LINE"
    return f"http {status}"


# ------------------------------------------------------------------------------------------- run
def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--seed", type=int, default=20)
    ap.add_argument("--files", type=int, default=1500)
    ap.add_argument("--options", type=int, default=450)
    ap.add_argument("--requests", type=int, default=500)
    ap.add_argument("--surfaces", type=int, default=300, help="issue 32: forces, dynamics, synthesis, import cases")
    args = ap.parse_args(argv)
    import warnings
    warnings.simplefilter("ignore", RuntimeWarning)
    signal.signal(signal.SIGALRM, _alarm)
    files = sorted(LIBRARY.glob("*.toml"))
    rng = random.Random(args.seed)
    report: dict[str, Counter] = {}
    slowest: dict[str, float] = {}
    examples: dict[tuple[str, str], str] = {}

    def record(section, cls, seconds, example):
        report.setdefault(section, Counter())[cls] += 1
        slowest[section] = max(slowest.get(section, 0.0), seconds)
        if cls.isupper() or cls.split()[0].isupper():
            examples.setdefault((section, cls), example[:300])

    t0 = time.perf_counter()
    for k in range(args.files):
        source = files[k % len(files)].read_text()
        if k % 4 == 3:
            text, suffix = mutate_json(rng, source), ".json"
        else:
            text, suffix = mutate(rng, source), ".toml"
        cls, s = _timed(lambda: file_case(text, suffix))
        record("files", cls if s <= CASE_SECONDS else "SLOW", s, text)
    with tempfile.TemporaryDirectory() as tmp:
        folder = Path(tmp)
        cwd = os.getcwd()
        os.chdir(folder)
        try:
            for argv_ in option_sets(rng, args.options):
                cls, s = _timed(lambda: option_case(argv_, folder))
                record("options", cls if s <= CASE_SECONDS else "SLOW", s, " ".join(argv_))
        finally:
            os.chdir(cwd)
        stray = sorted(os.listdir(folder))
    with tempfile.TemporaryDirectory() as tmp:
        folder = Path(tmp)
        cwd = os.getcwd()
        os.chdir(folder)
        try:
            for argv_, files_ in surface_cases(rng, args.surfaces):
                cls, s = _timed(lambda: surface_case(argv_, files_, folder))
                record("surfaces", cls if s <= CASE_SECONDS else "SLOW", s, " ".join(argv_))
        finally:
            os.chdir(cwd)
    if stray:
        report["options"]["FILES LEFT BEHIND"] += len(stray)
    from sim.front import app
    srv = app.AppServer(0, {"name": "fourbar"})
    thread = threading.Thread(target=srv.serve_forever, daemon=True)
    thread.start()
    try:
        for path, raw in app_requests(rng, args.requests, files):
            t = time.perf_counter()
            cls = app_case(srv.port, path, raw)
            s = time.perf_counter() - t
            record("app", cls if s <= CASE_SECONDS else "SLOW", s, f"{path} {raw[:200]!r}")
    finally:
        srv.shutdown()
        srv.server_close()
    rss_gb = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024 ** 2
    bad = 0
    for section, counts in report.items():
        line = ", ".join(f"{cls}: {n}" for cls, n in sorted(counts.items()))
        print(f"{section:<8s} {sum(counts.values()):5d} cases, slowest {slowest[section]:.2f} s; {line}")
    for (section, cls), ex in sorted(examples.items()):
        bad += 1
        print(f"  NOT HANDLED [{section}] {cls}: {ex!r}")
    print(f"peak memory {rss_gb:.2f} GB (limit {MEMORY_GB:g}); total {time.perf_counter() - t0:.0f} s")
    if rss_gb > MEMORY_GB:
        bad += 1
    return 1 if bad else 0


if __name__ == "__main__":
    sys.exit(main())

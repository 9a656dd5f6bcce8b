"""Seeded fuzzing of the three ways in: the file format, the command-line options and the app's API.

Every mutated input either works or is refused with ParameterError (one line; the CLI's exit 2, the app's
4xx); no other exception, no 5xx, no multi-line message. Small enough to run in a few seconds."""

import contextlib
import http.client
import io
import json
import random
import threading

import pytest

import analytic
from analytic import ParameterError
from analytic.applications import figures
from analytic.registry import LIBRARY
from sim.front.cli import main

pytestmark = pytest.mark.slow  # the whole module: see pyproject's markers

SEED = 20
FILES = sorted(LIBRARY.glob("*.toml"))
TOKENS = ['"30deg"', '"1/30deg"', "1e308", "-1e308", "9" * 40, "0", "-0.0", "[]", "[[[[1]]]]", "{a = 1}", '""',
          '"' + "1" * 300 + '"', '"(' * 30 + '1' + ')"' * 0 + '"', '"sqrt(-1)"', '"l1/0"', '"l1**99"', "true",
          '"nan"', '"inf"', '"a\\nb"', '"l1 deg"', '"__import__(\'os\')"', "nan", "inf", '"' + "-" * 200 + '1"',
          "1e-300", '"2deg/3"', '"1e999"', '["x", "y", "z"]']


def _mutate(rng: random.Random, text: str) -> str:
    lines = text.splitlines()
    for _ in range(rng.randint(1, 3)):
        i = rng.randrange(len(lines))
        op = rng.randrange(6)
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
        else:
            lines[i] = lines[i].replace(rng.choice("0123456789"), rng.choice(["", "9" * 30, "e", ".", "-"]))
        if not lines:
            lines = [""]
    return "\n".join(lines) + "\n"


def _one_line(exc: Exception) -> None:
    msg = str(exc)
    assert msg and "\n" not in msg and len(msg) < 600, msg


def test_mutated_files_parse_or_are_refused_in_one_line():
    rng = random.Random(SEED)
    worked = refused = 0
    for k in range(400):
        text = _mutate(rng, FILES[k % len(FILES)].read_text())
        try:
            mech = analytic.from_text(text, "fuzz.toml")
            analytic.format.linkfile.parameter_values(mech.definition)
            if len(mech.inputs) == 1:
                figures.assembly_ranges(mech, samples=36)
            worked += 1
        except ParameterError as exc:
            _one_line(exc)
            refused += 1
    assert worked > 20 and refused > 100, (worked, refused)     # both paths exercised


def test_mutated_json_files_too():
    rng = random.Random(SEED + 1)
    for k in range(100):
        data = json.loads(json.dumps(analytic.format.linkfile.tomllib.loads(FILES[k % len(FILES)].read_text())))
        key = rng.choice(sorted(data))
        data[key] = rng.choice([None, [], {}, "x", 1e308, -1, [[1]], {"a": {"b": []}}, "1/30deg", 10 ** 30])
        with contextlib.suppress(ParameterError):
            analytic.from_text(json.dumps(data), "fuzz.json")


OPTIONS = [["--set", "l1=0.12"], ["--set", "l1=5deg"], ["--set", "zz=1"], ["--set", "l1=1e308"], ["--set", "l1=-1"],
           ["--samples", "0"], ["--samples", "3"], ["--samples", "1e9"], ["--revolutions", "-1"],
           ["--revolutions", "0.3"], ["--input-range", "10deg:20deg"], ["--input-range", "20deg:10deg"],
           ["--input-range", "x"], ["--set", "branch=0"], ["--set", "l1=1/30deg"], ["--set", "l1="],
           ["--set", "=1"], ["--set", "l1=" + "1" * 500], ["--json"], ["--units", "mm"], ["--angles", "deg"]]


def test_option_sets_exit_0_or_2_in_one_line(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    rng = random.Random(SEED + 2)
    codes = set()
    for _ in range(60):
        mech = rng.choice(["fourbar", "fivebar", "slider_crank", "whitworth"])
        opts = [o for _ in range(rng.randint(1, 3)) for o in rng.choice(OPTIONS)]
        err = io.StringIO()
        with contextlib.redirect_stdout(io.StringIO()), contextlib.redirect_stderr(err):
            try:
                code = main(["analyze", mech, *opts])
            except SystemExit as exc:                      # argparse's own usage errors
                code = exc.code
        codes.add(code)
        assert code in (0, 2), (mech, opts, code, err.getvalue())
        if code == 2:
            assert len(err.getvalue().strip().splitlines()) <= 2, err.getvalue()   # argparse: usage + error
    assert list(tmp_path.iterdir()) == [] and codes == {0, 2}



def _post(srv, path, raw: bytes, ctype="application/json"):
    conn = http.client.HTTPConnection("127.0.0.1", srv.port, timeout=60)
    conn.request("POST", path, body=raw, headers={"Host": f"127.0.0.1:{srv.port}", "Content-Type": ctype})
    r = conn.getresponse()
    out = r.status, r.read()
    conn.close()
    return out


def test_hostile_app_requests_get_4xx_never_5xx(server):
    rng = random.Random(SEED + 3)
    values = [None, True, -1, 0, 1e308, 10 ** 40, "x", "30deg", "1/30deg", "1" * 300, [], [1, 2], {}, {"l1": "x"},
              {"l1": 1e308}, {"l1": "(" * 50}, "fourbar", "../../etc/passwd", "\u0000", "a\nb"]
    fields = ["mechanism", "set", "samples", "revolutions", "input_range", "outputs", "text", "zz"]
    statuses = set()
    for k in range(120):
        body = {"mechanism": "fourbar"} if rng.random() < 0.5 else {}
        for _ in range(rng.randint(1, 3)):
            body[rng.choice(fields)] = rng.choice(values)
        if k % 10 == 0:
            body["text"] = _mutate(rng, FILES[k % len(FILES)].read_text())
        raw = json.dumps(body).encode()
        if k % 15 == 7:
            raw = raw[: rng.randrange(len(raw))] + bytes([rng.randrange(128, 256)])    # broken JSON / UTF-8
        status, data = _post(server, "/api/solve", raw)
        statuses.add(status)
        assert status < 500, (body, status, data[:300])
        if status >= 400:
            msg = json.loads(data)["error"]
            assert msg and "\n" not in msg, msg
    assert any(400 <= s < 500 for s in statuses)
    # and it still answers a plain request (the random ones above may all be refused: which of them are
    # depends on the library's files, which the mutated texts are drawn from)
    assert _post(server, "/api/solve", json.dumps({"mechanism": "fourbar"}).encode())[0] == 200


def test_twenty_simultaneous_simulate_requests_are_all_answered(server):
    statuses: list[int] = []
    body = json.dumps({"mechanism": "fourbar", "revolutions": 0.25}).encode()
    threads = [threading.Thread(target=lambda: statuses.append(_post(server, "/api/simulate", body)[0]))
               for _ in range(20)]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    assert statuses == [200] * 20                 # none reset by a short listen queue, none refused

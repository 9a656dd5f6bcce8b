"""The app's synthesis keeps its word (issue 31): Cancel stops the server's work at once, processes
included; a budgeted search ends within its budget plus 1 s; progress follows the real stages; the
candidate table holds distinct designs."""

import json
import math
import os
import threading
import time

import numpy as np
import pytest

from sim.front import app, synth_job

SLACK = 0.5
"""[s] thread scheduling and the HTTP round trip on two shared cores, beyond the bounds under test."""


@pytest.fixture
def server():
    srv = app.AppServer(0, {"name": "fourbar"})
    threading.Thread(target=srv.serve_forever, daemon=True).start()
    yield srv
    srv.shutdown()
    srv.server_close()


def post(server, path, body, timeout=200):
    import http.client
    conn = http.client.HTTPConnection("127.0.0.1", server.port, timeout=timeout)
    conn.request("POST", path, json.dumps(body), {"Content-Type": "application/json",
                                                  "Host": f"127.0.0.1:{server.port}"})
    res = conn.getresponse()
    return res.status, json.loads(res.read())


def ellipse(n=12):
    t = np.linspace(0, 2 * math.pi, n, endpoint=False)
    return np.column_stack([0.1 * np.cos(t), 0.05 * np.sin(t)]).tolist()


def group_members(pgid: int) -> list[int]:
    """Live processes of a process group (zombies are dead: they hold no CPU or memory)."""
    out = []
    for p in os.listdir("/proc"):
        if not p.isdigit():
            continue
        try:
            fields = open(f"/proc/{p}/stat").read().rsplit(")", 1)[1].split()
        except OSError:
            continue
        if int(fields[2]) == pgid and fields[0] != "Z":
            out.append(int(p))
    return out


def test_distinct_drops_a_repeat_whatever_its_phase_or_direction():
    t = np.linspace(0, 2 * math.pi, 361)
    a = {"curve": {"x": np.cos(t).tolist(), "y": (0.5 * np.sin(t)).tolist()}}
    same = {"curve": {"x": np.cos(-t + 1.0).tolist(), "y": (0.5 * np.sin(-t + 1.0)).tolist()}}   # reversed, shifted
    near = {"curve": {"x": (np.cos(t) + 0.01).tolist(), "y": (0.5 * np.sin(t)).tolist()}}      # 0.5 % of the size
    other = {"curve": {"x": np.cos(t).tolist(), "y": (0.6 * np.sin(t)).tolist()}}
    kept = synth_job.distinct([a, same, near, other], size=2.0)
    assert kept == [a, near, other]
    assert synth_job.distinct([a, same], size=2.0 * 1e3) == [a]     # within 1e-3 of a large size: the same


def test_the_stages_reported_are_the_searchs_own(monkeypatch):
    from sim.service import design as design_service
    seen = {}

    def fake(target, options, unit, progress=None):         # the service's calls, in its order
        seen["budget"], seen["workers"] = options.budget, options.workers
        n = max(options.restart_count, options.designs)
        for i in range(1, n + 1):
            progress(i, n + options.designs)
        for i in range(options.designs):
            progress(n + i + 1, n + options.designs)
        return []
    monkeypatch.setattr(design_service, "synthesize_path", fake)
    events = []
    out = synth_job.run({"targets": ellipse(), "type": "fourbar", "closed": True, "workers": 2,
                         "deadline": time.time() + 8.0}, events.append)
    assert out == {"designs": [], "asked": 0}
    n = design_service.PathOptions(types=("fourbar",), designs=synth_job.DESIGNS).restart_count
    stages = [(e["stage"], e["done"], e["total"]) for e in events]
    assert stages == ([("search", i, n) for i in range(n)] + [("polish", 0, 0)]
                      + [("check", i + 1, synth_job.DESIGNS) for i in range(synth_job.DESIGNS)])
    # the search gets its share of what is left of the budget; the checks the rest
    assert 0.7 * 8.0 <= seen["budget"] <= synth_job.SEARCH_SHARE * 8.0 and seen["workers"] == 2


@pytest.mark.slow
def test_cancel_stops_the_search_and_its_processes_within_a_second(server):
    answer = {}
    runner = threading.Thread(target=lambda: answer.update(
        r=post(server, "/api/synthesize", {"targets": ellipse(), "budget": 60, "closed": True})))
    runner.start()
    deadline = time.monotonic() + 30
    while time.monotonic() < deadline:                 # the job is under way: its search has started
        status, st = post(server, "/api/synthesize/status", {})
        if st.get("stage") == "search":
            break
        time.sleep(0.1)
    assert st["state"] == "running" and st["stage"] == "search" and st["total"] >= 1
    pgid = server.synthesis.proc.pid
    assert group_members(pgid)                          # the job's processes are alive
    t0 = time.monotonic()
    status, c = post(server, "/api/synthesize/cancel", {})
    assert status == 200 and c["cancelled"]
    while group_members(pgid) and time.monotonic() - t0 < 5:
        time.sleep(0.02)
    gone = time.monotonic() - t0
    assert group_members(pgid) == [] and gone < 1.0
    runner.join(5)
    assert answer["r"][0] == 409 and "cancelled" in answer["r"][1]["error"]
    assert post(server, "/api/synthesize/status", {})[1]["state"] == "idle"
    assert post(server, "/api/synthesize/cancel", {})[1]["cancelled"] is False     # nothing left to cancel


@pytest.mark.slow
def test_cancel_kills_the_worker_processes_too():
    job = synth_job.Job({"targets": ellipse(), "type": "fourbar", "closed": True, "workers": 2}, 60)
    pgid = job.proc.pid
    deadline = time.monotonic() + 30
    while len(group_members(pgid)) < 3 and time.monotonic() < deadline:   # the job, its pool's server, workers
        time.sleep(0.05)
    assert len(group_members(pgid)) >= 3
    t0 = time.monotonic()
    job.cancel()
    while group_members(pgid) and time.monotonic() - t0 < 5:
        time.sleep(0.02)
    assert group_members(pgid) == [] and time.monotonic() - t0 < 1.0
    assert job.wait()["state"] == "cancelled"


@pytest.mark.slow
def test_a_budgeted_synthesis_ends_within_its_budget_plus_one_second(server):
    budget = 2.0
    t0 = time.monotonic()
    status, data = post(server, "/api/synthesize", {"targets": ellipse(), "budget": budget, "closed": True})
    took = time.monotonic() - t0
    if status == 200:                                   # a search that keeps the budget: its true time
        # the budget counts from the search's start; the process's start-up before it is reported apart
        assert data["seconds"] <= budget + synth_job.GRACE and data["budget"] == budget
        assert took <= data["startup"] + budget + synth_job.GRACE + SLACK
    else:                                               # one that does not is stopped, and says so; on a loaded
        # machine the search may see at once that its checks' reserve leaves nothing of the budget, and says that
        assert status == 400 and (f"past its {budget:g} s budget" in data["error"]
                                  or "no restart could run" in data["error"]), data["error"]
        assert took <= synth_job.STARTUP_LIMIT + budget + synth_job.GRACE + SLACK
    assert post(server, "/api/synthesize/status", {})[1]["state"] == "idle"
    assert group_members(server.synthesis.proc.pid) == []


@pytest.mark.slow
def test_a_second_synthesis_while_one_runs_is_refused(server):
    runner = threading.Thread(target=lambda: post(server, "/api/synthesize", {"targets": ellipse(), "budget": 30}))
    runner.start()
    deadline = time.monotonic() + 10
    while server.synthesis is None and time.monotonic() < deadline:
        time.sleep(0.05)
    status, data = post(server, "/api/synthesize", {"targets": ellipse(), "budget": 30})
    assert status == 409 and "already running" in data["error"]
    post(server, "/api/synthesize/cancel", {})
    runner.join(5)


SLOW_START = """
import json, sys, time
request = json.loads(sys.stdin.readline())
time.sleep(2.5)                                  # the interpreter and the libraries loading
print(json.dumps({"stage": "search", "done": 0, "total": 1}), flush=True)
time.sleep(0.3)                                  # the search, well within its budget
print(json.dumps({"result": {"designs": [], "asked": 0, "budget_seen": request.get("budget")}}), flush=True)
"""


def test_the_start_up_is_not_taken_out_of_the_budget(tmp_path):
    # issue 41: the budget counted from the request, so a job whose process took 2.5 s to start was killed at
    # its 1 s budget plus 1 s before its search began; now the budget counts from the search's first stage
    script = tmp_path / "slow_start.py"
    script.write_text(SLOW_START)
    job = synth_job.Job({"targets": ellipse(), "type": "fourbar", "closed": True}, 1.0, command=(str(script),))
    out = job.wait()
    assert out["state"] == "done", out
    assert out["answer"]["budget_seen"] == 1.0                  # the child gets the budget, not a deadline
    assert out["startup"] >= 2.5 and out["seconds"] < 1.0 + synth_job.GRACE, out


def test_a_budget_message_in_the_pages_words():
    # the service's command-line wording ("--budget") reads as the page's budget box
    line = "--budget 0.5 s ran out before the first restart could start; give more"
    assert synth_job.page_words(line) == "the budget of 0.5 s ran out before the first restart could start; give more"

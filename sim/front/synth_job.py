"""The app's path synthesis as a job it can stop: the search runs in a child process of its own session
(so the job and every worker process it starts are one process group, killed together), reports its real
stages as it goes, and is killed at its deadline (the budget, plus GRACE) or when the page cancels it.

The child is ``python -m sim.front.synth_job``: it reads one JSON request on stdin ({"targets": [[x, y],
...] m, "type", "closed", "workers", "deadline": epoch seconds by which it must be done}), writes one JSON
line per stage ({"stage": "search", "done": i, "total": n}, {"stage": "polish"}, {"stage": "check", ...}) and
a last line
{"result": {"designs": [...]}} or {"error": "one line"}.
"""

from __future__ import annotations

import json
import os
import signal
import subprocess
import sys
import threading
import time

import numpy as np

GRACE = 1.0
"""[s] How long past its budget a job may run before it is killed (the issue's bound: budget plus 1 s)."""
STARTUP_LIMIT = 120.0
"""[s] The longest the job's process may take to start (interpreter, numpy, scipy, MuJoCo) before its search
begins; the budget counts from there (issue 41: the start-up came out of the user's budget)."""
WORKERS = max(1, min(4, (os.cpu_count() or 1) // 2))
"""Processes the app's search uses: half the cores (the page and the server keep the rest), at most 4; the
answer does not depend on it (each restart carries its own seed)."""
SEARCH_SHARE = 0.75
"""The share of what is left of the budget when the child starts that the search itself gets: the rest is
for the candidates' checks (a MuJoCo run each) that follow it."""
DESIGNS = 3
"""Candidates asked of the search; those that repeat an earlier one are dropped (:func:`distinct`)."""
SAME_CURVE = 1e-3
"""Two candidates whose coupler curves lie within this fraction of the targets' size of each other (each
sample of one to the nearest of the other, both ways) are the same design to the user's eye."""


# ------------------------------------------------------------------------------------ the child
def distinct(designs: list[dict], size: float) -> list[dict]:
    """``designs`` (best first, each with its ``curve`` {x, y}) without those whose curve repeats an earlier
    one's (within SAME_CURVE of ``size``, whatever the samples' phase or direction)."""
    kept: list[tuple[dict, np.ndarray]] = []
    for d in designs:
        c = np.column_stack([np.asarray(d["curve"]["x"], float), np.asarray(d["curve"]["y"], float)])
        c = c[np.all(np.isfinite(c), axis=1)]
        same = False
        for _, k in kept:
            if len(c) > 1 and len(k) > 1 and max(_gap(c, k), _gap(k, c)) <= SAME_CURVE * size:
                same = True
                break
        if not same:
            kept.append((d, c))
    return [d for d, _ in kept]


def _gap(a: np.ndarray, b: np.ndarray) -> float:
    """The farthest any sample of polyline ``a`` lies from polyline ``b`` (distance to its segments)."""
    p0, d = b[:-1], np.diff(b, axis=0)
    rel = a[:, None] - p0[None]
    t = np.clip((rel * d[None]).sum(-1) / np.maximum((d * d).sum(-1), 1e-300)[None], 0.0, 1.0)
    return float(np.sqrt(((rel - t[..., None] * d[None]) ** 2).sum(-1)).min(1).max())


def run(request: dict, emit) -> dict:
    """The search of one request, its stages sent to ``emit``; the answer the page draws."""
    from sim.service import design as design_service
    from sim.service import path_targets
    from sim.output.jsonout import clean
    xy = np.asarray(request["targets"], dtype=float)
    target = path_targets.target(xy, request["closed"])
    import mujoco  # noqa: F401  (the libraries the search and its checks load on first use: part of the
    import scipy.optimize  # noqa: F401  start-up, 1.8 s for scipy.optimize on a busy machine, not of the budget)
    # the budget counts from here, the process started and its libraries loaded (a request may instead carry
    # an absolute deadline); the candidates' MuJoCo checks follow the search
    deadline = float(request["deadline"]) if "deadline" in request else time.time() + float(request["budget"])
    budget = max(0.1, SEARCH_SHARE * (deadline - time.time()))
    options = design_service.PathOptions(types=(request["type"],), budget=budget, designs=DESIGNS,
                                         workers=int(request.get("workers", 1)))
    restarts = max(options.restart_count, options.designs)

    def progress(done: int, total: int) -> None:
        if done < restarts:
            emit({"stage": "search", "done": done, "total": restarts})
        elif done == restarts:          # then the multi-starts, basin hopping and the polish of the best
            emit({"stage": "polish", "done": 0, "total": 0})
        else:
            emit({"stage": "check", "done": done - restarts, "total": total - restarts})

    emit({"stage": "search", "done": 0, "total": restarts})
    found = design_service.synthesize_path(target, options, "m", progress=progress)
    designs = []
    for k, f in enumerate(found):
        cx, cy = path_targets.coupler_curve(f["design"], 361)
        designs.append({"name": f"synthesised_{k + 1}", "text": f["text"], "error": clean(f["error"]),
                        "mu_min_deg": clean(f["parameters"].get("mu_min_deg")), "failed": f["failed"],
                        "compare_passed": bool(f["compare_passed"]),
                        "curve": {"x": clean(cx.tolist()), "y": clean(cy.tolist())}})
    size = float(np.ptp(xy, axis=0).max())
    kept = distinct(designs, size)
    for k, d in enumerate(kept):
        d["name"] = f"synthesised_{k + 1}"
    return {"designs": kept, "asked": len(designs)}


def main() -> int:
    request = json.loads(sys.stdin.readline())

    def emit(obj: dict) -> None:
        sys.stdout.write(json.dumps(obj, allow_nan=False) + "\n")
        sys.stdout.flush()
    try:
        emit({"result": run(request, emit)})
    except Exception as exc:                   # ParameterError and any failure: one line for the page
        emit({"error": page_words((str(exc).strip().splitlines() or [type(exc).__name__])[0])})
    return 0


def page_words(line: str) -> str:
    """A message of the synthesis service in the words of the page's Synthesis tab (its ``budget`` box, not
    the command line's ``--budget``)."""
    import re
    return re.sub(r"--budget (\S+) s\b", r"the budget of \1 s", line).replace("--budget", "the budget")


# ----------------------------------------------------------------------------------- the server
class Job:
    """One synthesis running in its own process group. ``wait()`` gives its answer (or raises JobError);
    ``status()`` what it is doing now; ``cancel()`` kills it and its workers at once."""

    COMMAND = ("-m", "sim.front.synth_job")
    """The job's process: this module run by the same interpreter (a test may start another)."""

    def __init__(self, request: dict, budget: float, command: tuple | None = None):
        self.requested = time.monotonic()
        self.started: float | None = None    # when the search began (its first stage): the budget counts from it
        self._searching = threading.Event()
        self.budget = float(budget)
        self.state = "running"          # running, done, failed, cancelled, over budget
        self.stage = {"stage": "starting", "done": 0, "total": 0}
        self.answer: dict | None = None
        self.error: str | None = None
        self._lock = threading.Lock()
        self._done = threading.Event()
        env = {**os.environ, "PYTHONUNBUFFERED": "1"}
        self.proc = subprocess.Popen([sys.executable, *(command or self.COMMAND)], stdin=subprocess.PIPE,
                                     stdout=subprocess.PIPE, stderr=subprocess.DEVNULL, text=True,
                                     start_new_session=True, env=env)
        self.proc.stdin.write(json.dumps({**request, "budget": self.budget}) + "\n")
        self.proc.stdin.close()
        threading.Thread(target=self._read, daemon=True, name="linkage-synthesis-reader").start()
        threading.Thread(target=self._watch, daemon=True, name="linkage-synthesis-deadline").start()

    @property
    def elapsed(self) -> float:
        """[s] Of the budget: since the search began (0 while the process starts)."""
        return 0.0 if self.started is None else time.monotonic() - self.started

    @property
    def startup(self) -> float:
        """[s] The process's start, not counted in the budget (so far, while it starts)."""
        return (self.started if self.started is not None else time.monotonic()) - self.requested

    def _finish(self, state: str, answer: dict | None = None, error: str | None = None) -> None:
        with self._lock:
            if self._done.is_set():
                return
            self.state, self.answer, self.error = state, answer, error
            self.seconds = self.elapsed
            self.startup_seconds = self.startup
            self._done.set()

    def _read(self) -> None:
        for line in self.proc.stdout:
            try:
                msg = json.loads(line)
            except ValueError:
                continue
            if "result" in msg or "error" in msg:
                self._kill()                             # the answer is in: no worker outlives the job
                if "result" in msg:
                    self._finish("done", msg["result"])
                else:
                    self._finish("failed", error=msg["error"])
            else:
                with self._lock:
                    if self.started is None:         # the search's first stage: the budget starts
                        self.started = time.monotonic()
                    self.stage = msg
                self._searching.set()
        self.proc.wait()
        self._finish("failed", error="the synthesis process ended without an answer")

    def _watch(self) -> None:
        if not self._searching.wait(STARTUP_LIMIT) and not self._done.is_set():
            self._kill()
            self._finish("failed", error=f"the synthesis did not start within {STARTUP_LIMIT:g} s (the machine is "
                                         f"busy?); try again")
            return
        if self._done.is_set():
            return
        left = self.budget + GRACE - (time.monotonic() - self.started)
        if not self._done.wait(max(0.0, left)):
            self._kill()
            self._finish("over budget", error=f"the search ran past its {self.budget:g} s budget and was stopped "
                                              f"at {self.budget + GRACE:g} s: no design was finished; raise the "
                                              f"budget")

    def _kill(self) -> None:
        try:
            os.killpg(self.proc.pid, signal.SIGKILL)     # the job and every worker it started
        except (ProcessLookupError, PermissionError):
            pass
        self.proc.wait()

    def cancel(self) -> None:
        self._kill()
        self._finish("cancelled", error="cancelled")

    def wait(self) -> dict:
        self._done.wait()
        return {"state": self.state, "answer": self.answer, "error": self.error, "seconds": self.seconds,
                "startup": self.startup_seconds}

    def status(self) -> dict:
        with self._lock:
            return {"state": self.state, "elapsed": self.elapsed, "startup": self.startup, "budget": self.budget,
                    **self.stage}

    @property
    def running(self) -> bool:
        return not self._done.is_set()


if __name__ == "__main__":
    sys.exit(main())

"""The app under load: rounds of 20 simultaneous simulate requests plus a solve, an MJCF export and a
small render; prints the statuses and the server's resident memory after the first and the last round.

    python benchmarks/app_load.py [ROUNDS]      (default 20; about 1 s of CPU per round)
"""

import http.client
import json
import re
import subprocess
import sys
import threading


def main(rounds: int) -> None:
    p = subprocess.Popen([sys.executable, "-m", "sim", "app", "--port", "0", "--no-browser"], stdout=subprocess.PIPE,
                         text=True)
    port = int(re.search(r":(\d+)/", p.stdout.readline()).group(1))

    def post(path, body):
        c = http.client.HTTPConnection("127.0.0.1", port, timeout=120)
        b = json.dumps(body).encode()
        c.request("POST", path, b, {"Content-Type": "application/json", "Host": f"127.0.0.1:{port}"})
        r = c.getresponse()
        r.read()
        c.close()
        return r.status

    def rss() -> float:
        return int(re.search(r"VmRSS:\s+(\d+)", open(f"/proc/{p.pid}/status").read()).group(1)) / 1024

    def one_round() -> list[int]:
        res: list[int] = []
        ts = [threading.Thread(target=lambda: res.append(post("/api/simulate", {"mechanism": "fourbar"})))
              for _ in range(20)]
        for t in ts:
            t.start()
        for t in ts:
            t.join()
        res.append(post("/api/solve", {"mechanism": "fivebar"}))
        res.append(post("/api/render", {"mechanism": "fourbar", "size": "160x120", "revolutions": 0.2}))
        res.append(post("/api/export/mjcf", {"mechanism": "whitworth"}))
        return res

    try:
        r = one_round()
        first = rss()
        print(f"round 1: {len(r)} answers, statuses {sorted(set(r))}, RSS {first:.0f} MB")
        for _ in range(rounds - 1):
            r = one_round()
        print(f"round {rounds}: {len(r)} answers, statuses {sorted(set(r))}, RSS {rss():.0f} MB "
              f"({rss() / first - 1:+.1%} of round 1)")
    finally:
        p.terminate()
        p.wait()


if __name__ == "__main__":
    main(int(sys.argv[1]) if len(sys.argv) > 1 else 20)

#!/usr/bin/env python3
"""Throughput of a 40-point study with 1, 2 and 4 worker processes on one PostgreSQL.

For each worker count: a fresh database on a throw-away PostgreSQL server (initdb in a
temporary directory, Unix socket only), one API node (`serve --workers 0`) and N
`bearing-sim worker --workers 1` processes. The study is POSTed to the API node and
polled until every point has finished; the wall time from the POST to the last point
is the figure. Prints a Markdown table for docs/lab/benchmarks.md ("Scale-out").

Usage: cargo build --release && python3 scripts/reports/scale_out_throughput.py [--workers 1,2,4]
       [--points 40] [--duration 0.1]
Only the standard library; needs PostgreSQL's server programs (Debian: postgresql).
"""

import argparse
import glob
import json
import os
import platform
import shutil
import subprocess
import tempfile
import time
import urllib.error
import urllib.request
import uuid

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
BIN = os.path.join(ROOT, "target", "release", "bearing-sim")


def pg_bin():
    found = shutil.which("initdb")
    if found:
        return os.path.dirname(os.path.realpath(found))
    dirs = sorted(glob.glob("/usr/lib/postgresql/*/bin"), key=lambda d: int(d.split("/")[-2]))
    if not dirs:
        raise SystemExit("PostgreSQL's initdb was not found (Debian: apt-get install postgresql)")
    return dirs[-1]


class Cluster:
    def __init__(self):
        self.bin = pg_bin()
        self.dir = tempfile.mkdtemp(prefix="bearing-sim-pg-")
        self.as_user = ["runuser", "-u", "postgres", "--"] if os.geteuid() == 0 else []
        if self.as_user:
            subprocess.run(["chown", "postgres", self.dir], check=True)
        self.data = os.path.join(self.dir, "data")
        self.run("initdb", "-D", self.data, "-A", "trust", "-U", "postgres", "--no-sync", "-E", "UTF8")
        # durable settings (fsync on): the figure is what an operator would see
        opts = f"-k {self.dir} -p 5432 -c listen_addresses='' -c max_connections=200"
        self.run("pg_ctl", "-D", self.data, "-o", opts, "-l", os.path.join(self.dir, "log"), "-w", "start")

    def run(self, prog, *args):
        subprocess.run(self.as_user + [os.path.join(self.bin, prog), *args], check=True,
                       stdout=subprocess.DEVNULL)

    def new_database(self):
        name = "tp_" + uuid.uuid4().hex[:12]
        subprocess.run([os.path.join(self.bin, "createdb"), "-h", self.dir, "-p", "5432",
                        "-U", "postgres", name], check=True)
        return f"postgres://postgres@localhost:5432/{name}?host={self.dir}"

    def stop(self):
        self.run("pg_ctl", "-D", self.data, "-m", "fast", "stop")
        shutil.rmtree(self.dir, ignore_errors=True)


def start(args, ready, log):
    p = subprocess.Popen([BIN, *args], stdout=subprocess.PIPE, stderr=open(log, "w"), text=True)
    for line in p.stdout:
        if line.startswith(ready):
            return p, line[len(ready):].strip()
    raise SystemExit(f"{args[0]} exited before it was ready; see {log}")


def http(method, url, body=None):
    data = json.dumps(body).encode() if body is not None else None
    req = urllib.request.Request(url, data=data, method=method,
                                 headers={"content-type": "application/json"})
    try:
        with urllib.request.urlopen(req, timeout=60) as r:
            return json.loads(r.read())
    except urllib.error.HTTPError as e:
        raise SystemExit(f"{method} {url}: {e.code} {e.read().decode(errors='replace')}")


def study(points, duration):
    loads = [200.0 + 10.0 * i for i in range(points)]
    return {
        "name": f"throughput, {points} axial loads",
        "base": {"preset": "h7005c", "fault_case": "outer",
                 "overrides": {"solver": {"duration": duration}}},
        "design": {"type": "one_at_a_time", "factors": [
            {"name": "axial_load", "pointer": "/operating/axial_load", "values": loads}]},
    }


def measure(cluster, n_workers, points, duration, logs):
    url = cluster.new_database()
    api, base = start(["serve", "--bind", "127.0.0.1:0", "--database-url", url, "--workers", "0"],
                      "listening on ", os.path.join(logs, f"api-{n_workers}.log"))
    workers = [start(["worker", "--database-url", url, "--workers", "1"], "worker ready:",
                     os.path.join(logs, f"worker-{n_workers}-{i}.log"))[0]
               for i in range(n_workers)]
    try:
        t0 = time.monotonic()
        st = http("POST", base + "/v1/studies", study(points, duration))
        while True:
            st = http("GET", f"{base}/v1/studies/{st['id']}")
            if st["progress"]["points_done"] == points:
                break
            time.sleep(0.05)
        wall = time.monotonic() - t0
        assert st["progress"]["points_succeeded"] == points, st["progress"]
        # each job's run time, from its claim to its outcome
        run_times = []
        for p in st["points"]:
            job = http("GET", f"{base}/v1/simulations/{p['job_id']}")
            run_times.append((_ms(job["finished_at"]) - _ms(job["started_at"])) / 1000.0)
        return wall, sum(run_times) / len(run_times)
    finally:
        for p in workers + [api]:
            p.terminate()
            p.wait()


def _ms(ts):
    # RFC 3339 with milliseconds, as the API writes it
    from datetime import datetime
    return datetime.fromisoformat(ts.replace("Z", "+00:00")).timestamp() * 1000.0


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--workers", default="1,2,4")
    ap.add_argument("--points", type=int, default=40)
    ap.add_argument("--duration", type=float, default=0.1)
    a = ap.parse_args()
    logs = tempfile.mkdtemp(prefix="bearing-sim-throughput-")
    cluster = Cluster()
    rows = []
    try:
        for n in [int(x) for x in a.workers.split(",")]:
            wall, per_job = measure(cluster, n, a.points, a.duration, logs)
            rows.append((n, wall, per_job))
            print(f"{n} worker processes: {wall:.1f} s", flush=True)
    finally:
        cluster.stop()
    print(f"\n{a.points}-point study, {a.duration} s simulated per point, "
          f"{os.cpu_count()} cores ({platform.processor() or platform.machine()}), "
          f"{time.strftime('%Y-%m-%d')}\n")
    print("| worker processes | wall time, s | points per minute | speed-up | mean job run time, s |")
    print("|---:|---:|---:|---:|---:|")
    for n, wall, per_job in rows:
        print(f"| {n} | {wall:.1f} | {60 * a.points / wall:.1f} | {rows[0][1] / wall:.2f} | {per_job:.2f} |")
    print(f"\nlogs: {logs}")


if __name__ == "__main__":
    main()

#!/usr/bin/env python3
"""Does `rosenbrock_w`'s offset from the explicit reference at full fidelity come from steps
its error estimate accepts? Runs the compound-fault H7005C, at a constant 10000 rpm for 0.2 s
(`--scene constant`, default) or on the Table-1 ramp for 0.5 s (`--scene table1`, the
work-precision scene), with `rosenbrock_w` at rtol = atol = 1e-5 and the largest step capped
ever lower, against `rk4_fsal` at 1e-7 (and 1e-5 for scale), and prints the mean cage speed
and the pedestal Z RMS below and above 20 kHz (steady window from the run's summary) against
that reference. Dev script (docs/lab/benchmarks.md, "Run time against error"): needs numpy and a
release build.

    cargo build --release && python3 scripts/research/rosenbrock_step_cap.py [--scene table1] [--work DIR]
"""
import argparse
import json
import os
import subprocess
import tempfile

import numpy as np

ROOT = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..")
BIN = os.environ.get("BEARING_SIM", os.path.join(ROOT, "target/release/bearing-sim"))
RUNS = [  # name, solver overrides
    ("rk4_fsal 1e-7 (reference)", dict(integrator="rk4_fsal", rtol=1e-7, atol=1e-7)),
    ("rk4_fsal 1e-5", dict(integrator="rk4_fsal", rtol=1e-5, atol=1e-5)),
] + [
    (f"rosenbrock_w 1e-5, max step {h:g} s", dict(integrator="rosenbrock_w", rtol=1e-5, atol=1e-5, max_step=h))
    for h in (1e-4, 1e-5, 3e-6, 1e-6, 3e-7)
]


def run(scene, overrides, duration, work, i):
    s = json.loads(json.dumps(scene))
    s["solver"].update(overrides)
    s["solver"]["duration"] = duration
    s["solver"]["initial_step"] = min(1e-6, s["solver"]["max_step"])
    path, out = os.path.join(work, f"{i}.json"), os.path.join(work, f"{i}.out.json")
    json.dump(s, open(path, "w"))
    subprocess.run([BIN, "run", path, "--out", out], check=True, capture_output=True)
    d = json.load(open(out))
    summary, ch = d["summary"], d["channels"]
    fs = ch["sample_rate"]
    z = np.array(next(c for c in ch["channels"] if c["name"] == "outer_ring_accel_z")["data"])
    t0, t1 = summary["steady_window"]
    x = z[int(t0 * fs):int(t1 * fs)]
    spec, f = np.fft.rfft(x - x.mean()), np.fft.rfftfreq(len(x), 1 / fs)

    def rms(lo, hi):  # Parseval over the band's bins
        return np.sqrt(2 * np.sum(np.abs(spec[(f >= lo) & (f < hi)]) ** 2)) / len(x)

    st = summary["stats"]
    return summary["mean_cage_speed"], rms(0, 20e3), rms(20e3, fs / 2), st


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--scene", choices=["constant", "table1"], default="constant")
    ap.add_argument("--work", default=None, help="keep the scenes and results here")
    args = ap.parse_args()
    work = args.work or tempfile.mkdtemp()
    os.makedirs(work, exist_ok=True)
    scene = json.loads(subprocess.run([BIN, "scene", "h7005c", "--fault", "compound"],
                                      check=True, capture_output=True, text=True).stdout)
    duration = 0.5
    if args.scene == "constant":
        scene["operating"]["speed"] = {"initial_rpm": 10000.0, "steady_rpm": 10000.0, "ramp_time": 0.0}
        duration = 0.2
    print("| run | wall (s) | accepted steps | largest step (s) | cage speed vs reference "
          "| RMS < 20 kHz vs reference | RMS 20-51.2 kHz vs reference |")
    print("| --- | --- | --- | --- | --- | --- | --- |")
    ref = None
    for i, (name, over) in enumerate(RUNS):
        cage, low, high, st = run(scene, over, duration, work, i)
        ref = ref or (cage, low, high)
        print(f"| {name} | {st['wall_time']:.2f} | {st['accepted_steps']} | {st['max_step']:.2g} "
              f"| {cage / ref[0] - 1:+.1e} | {(low / ref[1] - 1) * 100:+.2f} % "
              f"| {(high / ref[2] - 1) * 100:+.1f} % |", flush=True)


if __name__ == "__main__":
    main()

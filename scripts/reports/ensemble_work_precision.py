#!/usr/bin/env python3
"""Run time against error under the preset's default physics, read as ensemble means.

Under the rheology law one run's band RMS and mean cage speed move by about 1 % and 1e-4 with
the step sequence alone (docs/lab/benchmarks.md, "The default law's runs scatter"), so a single
run against a single tight reference measures that scatter, not the tolerance. Here every
setting is run K times with different `solver.initial_step` (which changes the whole step
sequence), and each setting's ensemble mean is compared with the pooled ensembles of two
methods at a tight tolerance (the reference, and the second method that checks it).

Per run: RHS evaluations and user CPU (the finished process's, from the operating system),
the summary's mean cage speed, and the band RMS below 20 kHz of `outer_ring_accel_z` over the
summary's steady window, computed as `simulation_analysis::steady_band_rms` does (one FFT of
the window, one-sided bins up to 20 kHz). Two runs at a time.

Dev script: needs numpy and a release build (`cargo build --release`).

    python3 scripts/reports/ensemble_work_precision.py [--runs 5] [--fault compound] \
        [--bin target/release/bearing-sim] [--out work-precision.json]
"""
import argparse
import concurrent.futures
import json
import os
import resource
import subprocess
import sys
import tempfile

import numpy as np

# (integrator, rtol = atol); the reference and its check come last
SETTINGS = [
    ("auto_slip", 1e-4),
    ("auto_slip", 1e-5),
    ("auto_slip", 1e-6),
    ("rk4_fsal", 1e-4),
    ("rk4_fsal", 1e-5),
    ("rk4_fsal", 1e-6),
    ("slip_implicit", 1e-4),
    ("slip_implicit", 1e-5),
    ("slip_implicit", 1e-6),
]
REFERENCE = [("auto_slip", 1e-7), ("rk4_fsal", 1e-7)]
INITIAL_STEPS = [1.0e-4, 0.9e-4, 0.8e-4, 0.7e-4, 0.6e-4, 0.55e-4, 0.5e-4, 0.45e-4]
FMAX = 20_000.0


def band_rms(x, fs, fmax):
    n = len(x)
    spec = np.fft.rfft(x)
    k = np.arange(len(spec))
    keep = (k >= 1) & (k * fs / n <= fmax)
    weight = np.where(2 * k == n, 1.0, 2.0)
    return float(np.sqrt(np.sum(weight[keep] * np.abs(spec[keep]) ** 2) / (n * n)))


def run_one(binary, scene, workdir, tag):
    path = os.path.join(workdir, f"{tag}.json")
    out = os.path.join(workdir, f"{tag}.out.json")
    with open(path, "w") as f:
        json.dump(scene, f)
    # user CPU of this child alone: wait4 through a shell-free Popen
    p = subprocess.Popen([binary, "run", path, "--out", out], stdout=subprocess.DEVNULL,
                         stderr=subprocess.PIPE)
    _, status, usage = os.wait4(p.pid, 0)
    p.returncode = os.waitstatus_to_exitcode(status)
    if p.returncode != 0:
        raise RuntimeError(f"{tag}: {p.stderr.read().decode()}")
    with open(out) as f:
        r = json.load(f)
    os.remove(out)
    ch = r["channels"]
    fs = ch["sample_rate"]
    data = next(c["data"] for c in ch["channels"] if c["name"] == "outer_ring_accel_z")
    s = r["summary"]
    w0 = int((s["steady_window"][0] - ch["start_time"]) * fs)
    return {
        "evaluations": s["stats"]["rhs_evaluations"],
        "user_s": usage.ru_utime,
        "cage": s["mean_cage_speed"],
        "band_rms": band_rms(np.asarray(data[w0:]), fs, FMAX),
    }


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--runs", type=int, default=5)
    ap.add_argument("--fault", default="compound")
    ap.add_argument("--bin", default="target/release/bearing-sim")
    ap.add_argument("--out", default=None)
    a = ap.parse_args()
    base = json.loads(subprocess.check_output([a.bin, "scene", "h7005c", "--fault", a.fault]))
    jobs = []
    for integrator, tol in SETTINGS + REFERENCE:
        for k in range(a.runs):
            s = json.loads(json.dumps(base))
            s["solver"]["integrator"] = integrator
            s["solver"]["rtol"] = s["solver"]["atol"] = tol
            s["solver"]["initial_step"] = INITIAL_STEPS[k % len(INITIAL_STEPS)]
            jobs.append(((integrator, tol), k, s))
    results = {}
    with tempfile.TemporaryDirectory() as work, \
            concurrent.futures.ThreadPoolExecutor(max_workers=2) as pool:
        futs = {pool.submit(run_one, a.bin, s, work, f"{key[0]}_{key[1]:g}_{k}"): key
                for key, k, s in jobs}
        for fut in concurrent.futures.as_completed(futs):
            key = futs[fut]
            results.setdefault(key, []).append(fut.result())
            print(f"{key[0]} {key[1]:g}: {len(results[key])} of {a.runs}", file=sys.stderr)
    ref = [r for key in REFERENCE for r in results[key]]
    ref_band = np.mean([r["band_rms"] for r in ref])
    ref_cage = np.mean([r["cage"] for r in ref])
    print(f"reference (pooled {', '.join(f'{m} {t:g}' for m, t in REFERENCE)}, "
          f"{len(ref)} runs): band RMS {ref_band:.3f} m/s^2, cage {ref_cage:.4f} rad/s")
    print("| method | rtol = atol | evaluations (median) | user CPU, s (median) "
          "| band RMS, mean and s.d. (m/s^2) | against the reference (s.e.) "
          "| mean cage, mean and s.d. (rad/s) | against the reference (s.e.) |")
    print("| --- | --- | --- | --- | --- | --- | --- | --- |")
    table = []
    for key in SETTINGS + REFERENCE:
        rs = results[key]
        band = np.array([r["band_rms"] for r in rs])
        cage = np.array([r["cage"] for r in rs])
        n = len(rs)
        row = {
            "method": key[0],
            "tolerance": key[1],
            "evaluations": float(np.median([r["evaluations"] for r in rs])),
            "user_s": float(np.median([r["user_s"] for r in rs])),
            "band_mean": float(band.mean()),
            "band_sd": float(band.std(ddof=1)),
            "band_rel": float(band.mean() / ref_band - 1),
            "band_rel_se": float(band.std(ddof=1) / np.sqrt(n) / ref_band),
            "cage_mean": float(cage.mean()),
            "cage_sd": float(cage.std(ddof=1)),
            "cage_rel": float(cage.mean() / ref_cage - 1),
            "cage_rel_se": float(cage.std(ddof=1) / np.sqrt(n) / ref_cage),
            "runs": rs,
        }
        table.append(row)
        evals = f"{row['evaluations']:,.0f}".replace(",", " ")
        print(f"| `{key[0]}` | {key[1]:g} | {evals} | {row['user_s']:.2f} "
              f"| {row['band_mean']:.3f}, {row['band_sd']:.3f} "
              f"| {100 * row['band_rel']:+.2f} % ({100 * row['band_rel_se']:.2f} %) "
              f"| {row['cage_mean']:.4f}, {row['cage_sd']:.4f} "
              f"| {row['cage_rel']:+.1e} ({row['cage_rel_se']:.1e}) |")
    if a.out:
        with open(a.out, "w") as f:
            json.dump({"fault": a.fault, "reference_band_rms": ref_band,
                       "reference_cage": ref_cage, "rows": table}, f, indent=1)


if __name__ == "__main__":
    main()

#!/usr/bin/env python3
"""Linear-prediction (autoregressive) pre-whitening before the verdict: the first step of
Sawalhi, Randall and Endo (MSSP 21, 2007), which removes the predictable (discrete) part of
a signal and keeps the impulsive part, on the CWRU signals of the evaluation set and, when
../shared is there, on their whole recordings. A check of whether it would rescue OR014
(docs/lab/cwru.md), not part of the product. Dev script: needs numpy and a release build.

    cargo build --release && python3 scripts/research/ar_check.py

The AR coefficients come from the biased autocorrelation by Levinson-Durbin; the residual
e[n] = sum_k a_k x[n-k] drops its first p samples (where the filter has no full history).
The order p is chosen as in the paper, by the largest kurtosis of the residual (here over
p = 10, 20, ..., 200), and, to show how much the verdict depends on that choice, also held
at 50, 100 and 200. Each cell gives the verdict with the DTCWT method / with the kurtogram
method (levels as scripts/reports/eval_report.py).
"""
import json
import math
import os
import subprocess
import tempfile

import numpy as np
from cwru_records import cwru_records

ROOT = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..")
BIN = os.environ.get("BEARING_SIM", os.path.join(ROOT, "target/release/bearing-sim"))
SHORT = {"outer_race": "OR", "inner_race": "IR", "rolling_element": "ball", "cage": "cage"}
SEARCH = list(range(10, 201, 10))
FIXED = [50, 100, 200]


def levinson(r, p):
    """Prediction-error filter a (a[0] = 1) of order p from autocorrelation r[0..p]."""
    a = np.zeros(p + 1)
    a[0] = 1.0
    err = r[0]
    for k in range(1, p + 1):
        refl = -(r[k] + np.dot(a[1:k], r[k - 1:0:-1])) / err
        a[1:k] = a[1:k] + refl * a[k - 1:0:-1]
        a[k] = refl
        err *= 1.0 - refl * refl
    return a


def ar_residual(x, p):
    x = x - x.mean()
    n = len(x)
    nfft = 1 << (2 * n - 1).bit_length()
    spec = np.fft.rfft(x, nfft)
    r = np.fft.irfft(np.abs(spec) ** 2, nfft)[: p + 1] / n
    return np.convolve(x, levinson(r, p))[:n][p:]


def kurtosis(x):
    x = x - x.mean()
    return np.mean(x**4) / np.mean(x**2) ** 2


def kurtogram_levels(fs):
    return max(1, min(12, round(math.log2(fs / 2 / 100))))


def verdict(path, sig, method):
    cmd = [BIN, "analyze", path, "--fs", str(sig["fs_hz"]), "--rpm", repr(sig["shaft_hz"] * 60),
           "--bearing", sig["bearing"]]
    if method == "kurtogram":
        cmd += ["--kurtogram-levels", str(kurtogram_levels(sig["fs_hz"]))]
    v = json.loads(subprocess.run(cmd, capture_output=True, text=True, check=True).stdout)["verdict"]
    return " + ".join(SHORT[f] for f in v["faults"]) or "none"


def cell(x, p, sig, tmp, truth):
    path = os.path.join(tmp, "w.f32le")
    ar_residual(x, p).astype("<f4").tofile(path)
    both = [verdict(path, sig, m) for m in ("dtcwt", "kurtogram")]
    return " / ".join(v if v == truth else f"{v} **x**" for v in both)


def main():
    print("| signal | record | truth | p by kurtosis: verdict | p = 50 | p = 100 | p = 200 |")
    print("| --- | --- | --- | --- | --- | --- | --- |")
    with tempfile.TemporaryDirectory() as tmp:
        for sig, what, x in cwru_records():
            truth = " + ".join(SHORT.get(t, t) for t in sig["truth"]) or "none"
            best = max(SEARCH, key=lambda p: kurtosis(ar_residual(x, p)))
            cells = [f"p = {best}: {cell(x, best, sig, tmp, truth)}"]
            cells += [cell(x, p, sig, tmp, truth) for p in FIXED]
            print(f"| {sig['id']} | {what} ({len(x) / sig['fs_hz']:.1f} s) | {truth} | "
                  + " | ".join(cells) + " |", flush=True)


if __name__ == "__main__":
    main()

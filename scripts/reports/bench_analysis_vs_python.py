#!/usr/bin/env python3
"""Side-by-side benchmark of `bearing-sim analyze` against a Python pipeline (dtcwt 0.14 +
scipy) on the same 2^20-sample file, in one run on one machine: wall time and peak memory
(max RSS) of each whole process, median of RUNS alternating runs. Dev script; its table
goes in docs/lab/benchmarks.md ("Analysis against Python").

    python3 -m venv /tmp/dtv && /tmp/dtv/bin/pip install "numpy<2" dtcwt==0.14.0 scipy
    cargo build --release
    /tmp/dtv/bin/python scripts/reports/bench_analysis_vs_python.py [--runs 5]

The signal: 2^20 samples at 51.2 kHz, a 9 kHz resonance struck at 1134.6 Hz (the H7005C's
BPFO at 10000 rpm) plus uniform noise, as in crates/bearing-core/benches/analysis.rs, written
as raw float32.

Python does less than the binary: the DTCWT (near_sym_b / qshift_b, 5 levels), the five
single-level components (inverse with the other levels and the low-pass zeroed), their
kurtosis, and the Hann-windowed envelope spectrum (scipy.signal.hilbert) of the component
of largest kurtosis. The binary also takes the raw signal's and the runner-up's envelope
spectra, identifies every characteristic line and harmonic, and gives the verdict.
"""
import argparse
import json
import math
import os
import platform
import random
import struct
import subprocess
import sys
import tempfile

ROOT = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..")
N = 1 << 20
FS = 51200.0


def write_signal(path):
    rng = random.Random(1)
    with open(path, "wb") as f:
        chunk = []
        for i in range(N):
            t = math.fmod(i / FS * 1134.6, 1.0) / 1134.6
            v = (rng.random() - 0.5) + math.exp(-3000 * t) * math.sin(2 * math.pi * 9000 * t)
            chunk.append(v)
            if len(chunk) == 65536:
                f.write(struct.pack(f"<{len(chunk)}f", *chunk))
                chunk = []
        if chunk:
            f.write(struct.pack(f"<{len(chunk)}f", *chunk))


def python_pipeline(path):
    import dtcwt
    import numpy as np
    from scipy.signal import hilbert

    x = np.fromfile(path, dtype="<f4").astype(np.float64)
    t = dtcwt.Transform1d(biort="near_sym_b", qshift="qshift_b")
    p = t.forward(x, nlevels=5)
    comps = []
    for lev in range(5):
        hp = tuple(h if i == lev else np.zeros_like(h) for i, h in enumerate(p.highpasses))
        comps.append(t.inverse(dtcwt.Pyramid(np.zeros_like(p.lowpass), hp)).ravel())
    def kurt(c):
        c = c - c.mean()
        return float((c ** 4).mean() / (c ** 2).mean() ** 2)
    k = [kurt(c) for c in comps]
    best = comps[int(np.argmax(k))]
    env = np.abs(hilbert(best))
    env = env - env.mean()
    w = np.hanning(len(env))
    spec = np.abs(np.fft.rfft(env * w)) * 2 / w.sum()
    print(json.dumps({"kurtosis": k, "peak_hz": float(np.argmax(spec[1:]) + 1) * FS / len(env)}))


def timed(cmd):
    out = subprocess.run(["/usr/bin/time", "-f", "%e %M"] + cmd, capture_output=True, text=True)
    if out.returncode:
        sys.exit(f"{cmd[0]} failed: {out.stderr}")
    secs, kib = out.stderr.strip().splitlines()[-1].split()
    return float(secs), int(kib) / 1024


def median(v):
    v = sorted(v)
    return v[len(v) // 2]


def main():
    if len(sys.argv) == 3 and sys.argv[1] == "--python-pipeline":
        return python_pipeline(sys.argv[2])
    ap = argparse.ArgumentParser()
    ap.add_argument("--runs", type=int, default=5)
    ap.add_argument("--binary", default=os.path.join(ROOT, "target/release/bearing-sim"))
    a = ap.parse_args()
    with tempfile.TemporaryDirectory() as tmp:
        path = os.path.join(tmp, "signal.f32le")
        write_signal(path)
        ours_cmd = [a.binary, "analyze", path, "--fs", str(FS), "--rpm", "10000", "--bearing", "h7005c"]
        py_cmd = [sys.executable, os.path.abspath(__file__), "--python-pipeline", path]
        ours, py = [], []
        for _ in range(a.runs):
            ours.append(timed(ours_cmd))
            py.append(timed(py_cmd))
    cpu = next((l.split(":", 1)[1].strip() for l in open("/proc/cpuinfo") if l.startswith("model name")), "?")
    print(f"{N} samples at {FS:.0f} Hz; median of {a.runs} alternating runs; {os.cpu_count()} cores, {cpu}; "
          f"Python {platform.python_version()}\n")
    print("| pipeline | wall time (s) | peak memory, max RSS (MiB) |")
    print("| --- | ---: | ---: |")
    to = median([t for t, _ in ours]); mo = median([m for _, m in ours])
    tp = median([t for t, _ in py]); mp = median([m for _, m in py])
    print(f"| `bearing-sim analyze` (whole process) | {to:.2f} | {mo:.0f} |")
    print(f"| Python dtcwt 0.14 + scipy (whole process) | {tp:.2f} | {mp:.0f} |")
    print(f"\nspeed ratio Python / ours: **{tp / to:.1f}x**; all runs, ours: "
          + ", ".join(f"{t:.2f} s/{m:.0f} MiB" for t, m in ours)
          + "; Python: " + ", ".join(f"{t:.2f} s/{m:.0f} MiB" for t, m in py))


if __name__ == "__main__":
    main()

#!/usr/bin/env python3
"""How strong the lines of a race fault's ball-return comb are, against the other race's
harmonics that fall on it: the envelope order spectrum of an exported run (resampled to
constant shaft angle by its `shaft_angle` column, Hilbert envelope, FFT, prominence over a
17-bin local median), listed at every multiple m of the identified BPFO / Z (the cage
frequency). A check for docs/lab/cwru.md, "The ball-return comb"; not the verdict's code.
Dev script: needs numpy and a run exported by `bearing-sim run ... --export run.csv`.

    python3 scripts/research/ball_return_comb.py run.csv outer_ring_accel_z T0 T1 BPFO_HZ [Z]
"""
import sys

import numpy as np


def main():
    path, channel, t0, t1, bpfo = sys.argv[1], sys.argv[2], *map(float, sys.argv[3:6])
    z = int(sys.argv[6]) if len(sys.argv) > 6 else 16
    header = open(path).readline().strip().split(",")
    col = lambda name: next(i for i, h in enumerate(header) if h.startswith(name))
    d = np.loadtxt(path, delimiter=",", skiprows=1)
    keep = (d[:, 0] >= t0) & (d[:, 0] <= t1)
    t, x, angle = d[keep, 0], d[keep, col(channel)], d[keep, col("shaft_angle")]
    revs = (angle[-1] - angle[0]) / (2 * np.pi)
    fr = revs / (t[-1] - t[0])  # mean shaft rate, Hz: the order spectrum's lines in Hz
    n = len(x)
    xr = np.interp(np.linspace(angle[0], angle[-1], n), angle, x)
    spec = np.fft.fft(xr - xr.mean())
    h = np.zeros(n)
    h[0] = 1
    h[1 : (n + 1) // 2] = 2
    if n % 2 == 0:
        h[n // 2] = 1
    env = np.abs(np.fft.ifft(spec * h))
    amp = np.abs(np.fft.rfft(env - env.mean()))
    df = fr / revs
    k_max = int(6000 / df)
    median = np.array([np.median(amp[max(1, i - 8) : i + 9]) for i in range(k_max)])
    prominence = 20 * np.log10(amp[:k_max] / median)
    peaks = [i for i in range(2, k_max - 1) if amp[i] > amp[i - 1] and amp[i] >= amp[i + 1]]
    peaks.sort(key=lambda i: -prominence[i])
    rank = {i: r + 1 for r, i in enumerate(peaks)}
    fc = bpfo / z
    bpfi = z * fr - bpfo  # the balls pass the two rings at Z FTF and Z (f_r - FTF)
    print(f"mean shaft {fr:.2f} Hz, {revs:.1f} revolutions, df {df:.2f} Hz; "
          f"FTF {fc:.3f} Hz, BPFI = Z f_r - BPFO = {bpfi:.1f} Hz")
    print("m, m FTF (Hz), prominence (dB), rank, what else lies there")
    for m in range(10, 100):
        k = int(round(m * fc / df))
        best = max(range(k - 1, k + 2), key=lambda j: prominence[j] if j in rank else -99)
        label = f"{m // z}xBPFO" if m % z == 0 else ""
        for hh in range(1, 5):
            if abs(m * fc - hh * bpfi) < 1.5 * df:
                label += f" {hh}xBPFI"
        print(f"{m:3d} {m * fc:8.1f} {prominence[best]:6.1f} {rank.get(best, '-'):>4} {label}")


if __name__ == "__main__":
    main()

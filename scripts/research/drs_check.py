#!/usr/bin/env python3
"""Discrete/random separation (DRS; Antoni & Randall, MSSP 18, 2004) before the verdict, on
CWRU OR014 (record 197: 0.014 in outer race, centred, 0 hp, 12 kHz drive end): the first
step of Smith & Randall's "Method 3" (MSSP 64-65, 2015), the only one of their three that
diagnosed this record. A check of whether DRS would rescue OR014 (docs/lab/cwru.md), not part
of the product. Dev script: needs numpy, a release build and ../shared (the whole record).

    cargo build --release && python3 scripts/research/drs_check.py

DRS as implemented: pairs of Hann-windowed segments of N samples, the second taken D = N +
gap earlier (so the two never share a sample), pairs every N/3; the transfer function
H(f) = sum A conj(B) / sum |B|^2 with the delay's phase removed is ~1 at discrete
(periodic) lines and small elsewhere; |H| is applied to the signal by overlap-add (hop
N/4) and the residual x - |H| x is the random part. With overlapping pairs (D < N) |H|
comes out ~1 everywhere, which is why D > N.

For each input the script prints our verdict (`bearing-sim analyze`, both band-selection
methods) on the residual, and the squared envelope spectrum's lines near BPFO and BPFI
(1-3 x, +/-1 %) in the fixed band 2-5.5 kHz, in dB over a running median of +/-5 Hz.
"""
import json
import os
import subprocess
import tempfile

import numpy as np

ROOT = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..")
EVAL = os.path.join(ROOT, "crates/bearing-core/tests/fixtures/eval")
SHARED = os.path.join(ROOT, "../shared/data/cwru")
BIN = os.environ.get("BEARING_SIM", os.path.join(ROOT, "target/release/bearing-sim"))
ID = "cwru_or014c_0hp_12k_de"


def hann(n):
    return 0.5 - 0.5 * np.cos(2 * np.pi * np.arange(n) / n)


def drs_residual(x, n, gap):
    """x minus its discrete part, |H| from pairs of segments D = n + gap apart."""
    d = n + gap
    w = hann(n)
    sab = np.zeros(n // 2 + 1, complex)
    sbb = np.zeros(n // 2 + 1)
    pairs = 0
    for s in range(d, len(x) - n + 1, n // 3):  # pair_count(len(x), n, gap) of them
        a = np.fft.rfft(w * x[s:s + n])
        b = np.fft.rfft(w * x[s - d:s - d + n])
        sab += a * np.conj(b)
        sbb += np.abs(b) ** 2
        pairs += 1
    if pairs < 2:
        return None, pairs
    h = np.abs(sab / np.maximum(sbb, 1e-30))
    xp = np.concatenate([np.zeros(n), x, np.zeros(n)])
    det = np.zeros_like(xp)
    acc = np.zeros_like(xp)
    for s in range(0, len(xp) - n + 1, n // 4):
        det[s:s + n] += np.fft.irfft(h * np.fft.rfft(w * xp[s:s + n]), n)
        acc[s:s + n] += w
    det = (det / np.maximum(acc, 1e-12))[n:n + len(x)]
    return x - det, pairs


def envelope_lines(x, fs, lo, hi, targets):
    """dB over the running median (+/-5 Hz) of the strongest line within 1 % of each target."""
    # analytic signal of the band: positive frequencies in the band, doubled
    spec = np.fft.fft(x * hann(len(x)))
    f = np.fft.fftfreq(len(x), 1 / fs)
    spec[(f < lo) | (f > hi)] = 0
    env = np.abs(np.fft.ifft(2 * spec)) ** 2
    env -= env.mean()
    m = 2 * len(env)
    ses = np.abs(np.fft.rfft(env * hann(len(env)), m))
    fe = np.fft.rfftfreq(m, 1 / fs)
    half = max(1, int(5.0 / (fe[1] - fe[0])))
    out = []
    for name, fc in targets:
        idx = np.flatnonzero(np.abs(fe - fc) <= 0.01 * fc)
        i = idx[np.argmax(ses[idx])]
        bg = np.median(ses[max(0, i - half):i + half + 1])
        out.append(f"{name} {fe[i]:.2f} Hz {20 * np.log10(ses[i] / bg):.1f} dB")
    return ", ".join(out)


def verdict(path, sig, method):
    cmd = [BIN, "analyze", path, "--fs", str(sig["fs_hz"]), "--rpm", repr(sig["shaft_hz"] * 60),
           "--bearing", sig["bearing"]]
    if method == "kurtogram":
        # as scripts/reports/eval_report.py: 6 levels at 12 kHz
        cmd += ["--kurtogram-levels", "6"]
    v = json.loads(subprocess.run(cmd, capture_output=True, text=True, check=True).stdout)["verdict"]
    p = {e["fault"]: e["p_value"] for e in v["evidence"]}
    return f"{', '.join(v['faults']) or 'none'} (p outer {p['outer_race']:.1g}, inner {p['inner_race']:.1g})"


def pair_count(length, n, gap):
    """Segment pairs `drs_residual` averages for a window of n samples."""
    return max(0, (length - 2 * n - gap) // (n // 3) + 1)


def window_for(length, gap, pairs=5):
    """The longest power-of-two window that still gives `pairs` segment pairs (finer
    resolution separates discrete lines from the bearing's smeared ones; fewer averages
    leave H noisy)."""
    n = 2 ** 10
    while pair_count(length, 2 * n, gap) >= pairs:
        n *= 2
    return n


def main():
    signals = json.load(open(os.path.join(EVAL, "manifest.json")))["signals"]
    man = json.load(open(os.path.join(SHARED, "manifest.json")))
    with tempfile.TemporaryDirectory() as tmp:
        path = os.path.join(tmp, "r.f32le")
        # OR014 in detail: the window of the rule, half of it, and the committed excerpt
        sig = next(s for s in signals if s["id"] == ID)
        fs = sig["fs_hz"]
        gap = int(0.1 * fs)
        whole = np.fromfile(os.path.join(SHARED, sig["file"]), dtype="<f4").astype(float)
        excerpt = np.fromfile(os.path.join(EVAL, sig["file"]), dtype="<f4").astype(float)
        rec = next(r for r in man["recordings"] if r["id"] == ID)
        bpfo = rec["expected_fault_frequencies_hz"]["BPFO"]
        bpfi = rec["expected_fault_frequencies_hz"]["BPFI"]
        targets = [(f"{h}xBPFO", h * bpfo) for h in (1, 2, 3)] + [(f"{h}xBPFI", h * bpfi) for h in (1, 2, 3)]
        n_whole = window_for(len(whole), gap)
        for what, x, n in [("whole record", whole, n_whole), ("whole record", whole, n_whole // 2),
                           ("committed 2 s excerpt", excerpt, window_for(len(excerpt), gap))]:
            x = x - x.mean()
            res, pairs = drs_residual(x, n, gap)
            print(f"## {ID}, {what} ({len(x) / fs:.1f} s), DRS N = {n}, gap 0.1 s, {pairs} pairs")
            print(f"- lines, no DRS, 2-5.5 kHz: {envelope_lines(x, fs, 2000, 5500, targets)}")
            print(f"- lines, DRS, 2-5.5 kHz: {envelope_lines(res, fs, 2000, 5500, targets)}")
            res.astype("<f4").tofile(path)
            for method in ("dtcwt", "kurtogram"):
                print(f"- verdict on the residual, {method}: {verdict(path, sig, method)}")
        # every CWRU recording of the evaluation set, whole, with the rule's window
        print()
        print("| signal | truth | DRS window | verdict, dtcwt | verdict, kurtogram |")
        print("| --- | --- | --- | --- | --- |")
        for sig in signals:
            if sig["kind"] != "cwru":
                continue
            fs = sig["fs_hz"]
            gap = int(0.1 * fs)
            x = np.fromfile(os.path.join(SHARED, sig["file"]), dtype="<f4").astype(float)
            x = x - x.mean()
            n = window_for(len(x), gap)
            res, pairs = drs_residual(x, n, gap)
            res.astype("<f4").tofile(path)
            v = [verdict(path, sig, m) for m in ("dtcwt", "kurtogram")]
            print(f"| {sig['id']} ({len(x) / fs:.1f} s) | {', '.join(sig['truth']) or 'none'} | "
                  f"{n} ({n / fs:.2f} s, {pairs} pairs) | {v[0]} | {v[1]} |")


if __name__ == "__main__":
    main()

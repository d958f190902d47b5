#!/usr/bin/env python3
"""Regenerate the signal-analysis fixtures committed in this repository.

Only needed when a fixture changes; building, running and testing never need Python.

    python3 -m venv .venv && .venv/bin/pip install "numpy<2" dtcwt==0.14 scipy
    .venv/bin/python scripts/gen_signal_fixtures.py ../shared

Writes
  crates/bearing-core/src/signal/dtcwt/filters.json         filter sets usable by the 1-D transform (float64)
  crates/bearing-core/tests/fixtures/dtcwt/<case>/   golden DTCWT data, raw little-endian float64:
      input.f64, coeffs_level<k>.f64 (re, im interleaved), lowpass.f64,
      component_level<k>.f64, component_lowpass.f64, summary.json
  crates/bearing-core/tests/fixtures/cwru/<id>.f32le short excerpts of two CWRU 12 kHz recordings
"""
import json
import os
import sys

import numpy as np
import dtcwt

SHARED = sys.argv[1] if len(sys.argv) > 1 else "../shared"
ROOT = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..")
BIORT = ["antonini", "legall", "near_sym_a", "near_sym_b"]
QSHIFT = ["qshift_06", "qshift_a", "qshift_b", "qshift_c", "qshift_d", "qshift_32"]


def write_filters():
    src = json.load(open(os.path.join(SHARED, "reference/dtcwt/filters.json")))
    out = {}
    for name in BIORT:
        out[name] = {k: src[name][k] for k in ("h0o", "g0o", "h1o", "g1o")}
    for name in QSHIFT:
        out[name] = {k: src[name][k] for k in ("h0a", "h0b", "g0a", "g0b", "h1a", "h1b", "g1a", "g1b")}
    # cross-check against the tables shipped in the package
    for name in BIORT:
        ref = dtcwt.coeffs.biort(name)
        for k, v in zip(("h0o", "g0o", "h1o", "g1o"), ref):
            assert np.array_equal(np.asarray(out[name][k]), np.asarray(v).ravel()), (name, k)
    for name in QSHIFT:
        ref = dtcwt.coeffs.qshift(name)
        for k, v in zip(("h0a", "h0b", "g0a", "g0b", "h1a", "h1b", "g1a", "g1b"), ref):
            assert np.array_equal(np.asarray(out[name][k]), np.asarray(v).ravel()), (name, k)
    path = os.path.join(ROOT, "crates/bearing-core/src/signal/dtcwt/filters.json")
    with open(path, "w") as f:
        json.dump(out, f, indent=1)
        f.write("\n")


def kurtosis_pearson(x):
    x = np.asarray(x) - np.mean(x)
    return float(np.mean(x ** 4) / np.mean(x ** 2) ** 2)


def golden_case(name, x, levels, biort="near_sym_b", qshift="qshift_b", check_dir=None):
    n = len(x)
    xt = np.append(x, x[-1]) if n % 2 else x.copy()
    t = dtcwt.Transform1d(biort=biort, qshift=qshift)
    p = t.forward(xt, nlevels=levels)
    comps = []
    for k in range(levels):
        hp = [np.zeros_like(h) for h in p.highpasses]
        hp[k] = p.highpasses[k]
        comps.append(t.inverse(dtcwt.Pyramid(np.zeros_like(p.lowpass), hp))[:n])
    low = t.inverse(dtcwt.Pyramid(p.lowpass, [np.zeros_like(h) for h in p.highpasses]))[:n]
    err = np.max(np.abs(sum(comps) + low - x))
    assert err < 1e-13, err
    d = os.path.join(ROOT, "crates/bearing-core/tests/fixtures/dtcwt", name)
    os.makedirs(d, exist_ok=True)
    np.asarray(x, "<f8").tofile(os.path.join(d, "input.f64"))
    for k, h in enumerate(p.highpasses):
        h = h.ravel()
        np.column_stack([h.real, h.imag]).astype("<f8").tofile(os.path.join(d, f"coeffs_level{k+1}.f64"))
        np.asarray(comps[k], "<f8").tofile(os.path.join(d, f"component_level{k+1}.f64"))
    np.asarray(p.lowpass.ravel(), "<f8").tofile(os.path.join(d, "lowpass.f64"))
    np.asarray(low, "<f8").tofile(os.path.join(d, "component_lowpass.f64"))
    summary = {
        "dtcwt_version": dtcwt.__version__, "n": n, "levels": levels, "biort": biort, "qshift": qshift,
        "highpass_lengths": [int(h.shape[0]) for h in p.highpasses],
        "lowpass_length": int(p.lowpass.shape[0]),
        "kurtosis_pearson": [kurtosis_pearson(c) for c in comps],
    }
    json.dump(summary, open(os.path.join(d, "summary.json"), "w"), indent=1)
    if check_dir:  # the shared reference outputs must be reproduced exactly
        for k in range(levels):
            ref = np.loadtxt(os.path.join(check_dir, f"component_level{k+1}.txt"))
            assert np.max(np.abs(ref - comps[k])) < 1e-15, (name, k)
            refc = np.loadtxt(os.path.join(check_dir, f"coeffs_level{k+1}.txt"))
            h = p.highpasses[k].ravel()
            assert np.max(np.abs(refc[:, 0] - h.real)) < 1e-15 and np.max(np.abs(refc[:, 1] - h.imag)) < 1e-15


def write_goldens():
    g = os.path.join(SHARED, "reference/dtcwt/golden")
    for n in (1030, 1001):
        x = np.loadtxt(os.path.join(g, f"random_{n}.txt"))
        golden_case(f"random_{n}_L4", x, 4, check_dir=os.path.join(g, f"random_{n}_L4_nsb_qb"))
    rng = np.random.default_rng(20261121)
    for n in (302, 301):
        golden_case(f"random_{n}_L5", rng.standard_normal(n), 5)
    # another filter pair, to check the selectable sets (qshift_c has an even half-length)
    golden_case("random_256_L4_nsa_qc", rng.standard_normal(256), 4, biort="near_sym_a", qshift="qshift_c")


def write_cwru_excerpts():
    man = json.load(open(os.path.join(SHARED, "data/cwru/manifest.json")))
    d = os.path.join(ROOT, "crates/bearing-core/tests/fixtures/cwru")
    os.makedirs(d, exist_ok=True)
    meta = {}
    for rid in ("cwru_ir007_0hp_12k_de", "cwru_or007c_0hp_12k_de"):
        rec = next(r for r in man["recordings"] if r["id"] == rid)
        x = np.fromfile(os.path.join(SHARED, "data/cwru", rec["file"]), "<f4")
        n = 18000  # 1.5 s at 12 kHz, from the start of the recording
        x[:n].astype("<f4").tofile(os.path.join(d, rid + ".f32le"))
        meta[rid] = {k: rec[k] for k in ("fs_hz", "rpm", "shaft_hz", "fault_type", "fault_diameter_in",
                                         "expected_fault_frequencies_hz")}
        meta[rid]["n_samples"] = n
        meta[rid]["source_file"] = rec["file"]
        meta[rid]["excerpt"] = "first 18000 samples (1.5 s)"
    json.dump(meta, open(os.path.join(d, "manifest.json"), "w"), indent=1)


if __name__ == "__main__":
    write_filters()
    write_goldens()
    write_cwru_excerpts()

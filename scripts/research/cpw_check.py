#!/usr/bin/env python3
"""Cepstral pre-whitening (Sawalhi & Randall, 2011: the real cepstrum zeroed but for its
zeroth quefrency, i.e. the spectrum's magnitude set to one and its phase kept) before the
verdict, on the CWRU signals of the evaluation set and, when ../shared is there, on their
whole recordings. A check of whether pre-whitening would rescue OR014 (docs/lab/cwru.md), not
part of the product. Dev script: needs numpy and a release build.

    cargo build --release && python3 scripts/research/cpw_check.py
"""
import json
import os
import subprocess
import tempfile

import numpy as np
from cwru_records import cwru_records

ROOT = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..")
BIN = os.environ.get("BEARING_SIM", os.path.join(ROOT, "target/release/bearing-sim"))


def whiten(x):
    x = x - x.mean()
    spec = np.fft.fft(x)
    return np.real(np.fft.ifft(spec / np.maximum(np.abs(spec), 1e-30)))


def verdict(path, sig):
    cmd = [BIN, "analyze", path, "--fs", str(sig["fs_hz"]), "--rpm", repr(sig["shaft_hz"] * 60),
           "--bearing", sig["bearing"]]
    v = json.loads(subprocess.run(cmd, capture_output=True, text=True, check=True).stdout)["verdict"]
    best = {e["fault"]: e["p_value"] for e in v["evidence"]}
    return v["faults"], best


def main():
    print("| signal | record | truth | verdict, pre-whitened | p outer / inner |")
    print("| --- | --- | --- | --- | --- |")
    with tempfile.TemporaryDirectory() as tmp:
        for sig, what, x in cwru_records():
            out = os.path.join(tmp, "w.f32le")
            whiten(x).astype("<f4").tofile(out)
            faults, p = verdict(out, sig)
            print(f"| {sig['id']} | {what} ({len(x) / sig['fs_hz']:.1f} s) | "
                  f"{', '.join(sig['truth'])} | {', '.join(faults) or 'none'} | "
                  f"{p['outer_race']:.1g} / {p['inner_race']:.1g} |")


if __name__ == "__main__":
    main()

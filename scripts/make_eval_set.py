#!/usr/bin/env python3
"""Build the diagnosis evaluation set in crates/bearing-core/tests/fixtures/eval/ (dev
script; its outputs are committed, building and testing never run it).

    cargo build --release
    python3 scripts/make_eval_set.py ../shared/data/cwru

Three kinds of signal, each with its truth in manifest.json:

- CWRU excerpts: the first 2 s of every recording of the shared CWRU set (drive end, 0 hp,
  12 and 48 kHz; normal, inner race, outer race, ball), float32 as recorded.
- Engine simulations: the H7005C preset (Table 1) with no fault, an inner-ring fault, an
  outer-ring fault and both, 0.5 s each; the vertical outer-ring acceleration over the run's
  steady window, float32. The shaft frequency is the run's mean shaft speed.
- A synthetic healthy machine: a 27-tooth gear mesh on the CWRU shaft, amplitude-modulated at
  the shaft rate with three mesh harmonics, a 2x-shaft imbalance line, a narrow-band resonance
  excited by white noise and broadband white noise; no bearing impulses. Seeded, so the file
  is reproducible.

Only numpy-free standard Python: the set must be rebuildable without a scientific stack.
"""
import json
import math
import os
import random
import struct
import subprocess
import sys
import tempfile

ROOT = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..")
OUT = os.path.join(ROOT, "crates/bearing-core/tests/fixtures/eval")
BIN = os.environ.get("BEARING_SIM", os.path.join(ROOT, "target/release/bearing-sim"))
EXCERPT_S = 2.0
TRUTH = {"normal": [], "inner_race": ["inner_race"], "outer_race": ["outer_race"], "ball": ["ball"]}


def write_f32(path, values):
    with open(path, "wb") as f:
        f.write(struct.pack(f"<{len(values)}f", *values))


def cwru(data_dir):
    man = json.load(open(os.path.join(data_dir, "manifest.json")))
    entries = []
    for rec in man["recordings"]:
        n = int(EXCERPT_S * rec["fs_hz"])
        raw = open(os.path.join(data_dir, rec["file"]), "rb").read()[: 4 * n]
        name = rec["id"] + ".f32le"
        open(os.path.join(OUT, name), "wb").write(raw)
        entries.append({
            "id": rec["id"], "file": name, "kind": "cwru", "fs_hz": rec["fs_hz"],
            "shaft_hz": rec["rpm"] / 60.0, "bearing": "cwru6205",
            "truth": TRUTH[rec["fault_type"]],
            "note": f"{rec['fault_type']} {rec['fault_diameter_in']:.3f} in; first {n} samples "
                    f"({EXCERPT_S} s) of {rec['source']['path']} {rec['source']['mat_variable']}",
        })
    return entries


def simulated():
    entries = []
    truth = {"none": [], "inner": ["inner_race"], "outer": ["outer_race"],
             "compound": ["inner_race", "outer_race"]}
    with tempfile.TemporaryDirectory() as tmp:
        for case, t in truth.items():
            out = os.path.join(tmp, case + ".json")
            subprocess.run([BIN, "run", "h7005c", "--fault", case, "--out", out], check=True,
                           stdout=subprocess.DEVNULL)
            r = json.load(open(out))
            ch = r["channels"]
            fs = ch["sample_rate"]
            y = next(c for c in ch["channels"] if c["name"] == "outer_ring_accel_y")["data"]
            s0, s1 = r["summary"]["steady_window"]
            i0 = round((s0 - ch["start_time"]) * fs)
            i1 = min(round((s1 - ch["start_time"]) * fs), len(y))
            name = f"sim_h7005c_{case}.f32le"
            write_f32(os.path.join(OUT, name), y[i0:i1])
            entries.append({
                "id": f"sim_h7005c_{case}", "file": name, "kind": "simulated", "fs_hz": fs,
                "shaft_hz": r["summary"]["mean_shaft_speed"] / (2 * math.pi), "bearing": "h7005c",
                "truth": t,
                "note": f"bearing-sim run h7005c --fault {case}: outer_ring_accel_y over the "
                        f"steady window [{s0}, {s1}] s",
            })
    return entries


def synthetic_healthy():
    fs, shaft, teeth, seconds = 12000.0, 1796 / 60.0, 27, 2.0
    rng = random.Random(20261123)
    n = int(fs * seconds)
    mesh = teeth * shaft
    # a lightly damped 2.8 kHz resonance driven by white noise (second-order recursion)
    f_res, zeta = 2800.0, 0.05
    r = math.exp(-zeta * 2 * math.pi * f_res / fs)
    a1, a2 = 2 * r * math.cos(2 * math.pi * f_res / fs), -r * r
    y1 = y2 = 0.0
    x = []
    for i in range(n):
        t = i / fs
        am = 1 + 0.3 * math.cos(2 * math.pi * shaft * t + 0.4)
        gear = am * sum(c * math.cos(2 * math.pi * h * mesh * t + h) for h, c in ((1, 1.0), (2, 0.4), (3, 0.15)))
        imbalance = 0.2 * math.cos(2 * math.pi * shaft * t) + 0.05 * math.cos(4 * math.pi * shaft * t + 1)
        y = a1 * y1 + a2 * y2 + rng.gauss(0, 1)
        y2, y1 = y1, y
        x.append(0.1 * gear + imbalance + 0.02 * y + 0.1 * rng.gauss(0, 1))
    name = "synthetic_gear_noise_12k.f32le"
    write_f32(os.path.join(OUT, name), x)
    return [{
        "id": "synthetic_gear_noise_12k", "file": name, "kind": "synthetic", "fs_hz": fs,
        "shaft_hz": shaft, "bearing": "cwru6205", "truth": [],
        "note": "healthy: 27-tooth gear mesh (3 harmonics, 30 % shaft-rate AM), shaft and 2x "
                "shaft lines, white-noise-driven 2.8 kHz resonance, white noise; seed 20261123",
    }]


def main():
    data_dir = sys.argv[1] if len(sys.argv) > 1 else os.path.join(ROOT, "../shared/data/cwru")
    os.makedirs(OUT, exist_ok=True)
    entries = cwru(data_dir) + simulated() + synthetic_healthy()
    with open(os.path.join(OUT, "manifest.json"), "w") as f:
        json.dump({"description": "Diagnosis evaluation set: signals (raw little-endian float32, "
                                  "one channel) and their true fault types. Built by "
                                  "scripts/make_eval_set.py.", "signals": entries}, f, indent=1)
        f.write("\n")


if __name__ == "__main__":
    main()

#!/usr/bin/env python3
"""Run `bearing-sim analyze` on every CWRU recording of the shared data set and print a
markdown table (used for docs/lab/cwru.md). Dev script only; needs a built binary.

    cargo build --release && python3 scripts/reports/cwru_report.py ../shared/data/cwru > /tmp/cwru.md
"""
import json
import os
import subprocess
import sys

DATA = sys.argv[1] if len(sys.argv) > 1 else "../shared/data/cwru"
BIN = os.environ.get("BEARING_SIM", os.path.join(os.path.dirname(__file__), "../../target/release/bearing-sim"))
EXPECT = {"inner_race": "BPFI", "outer_race": "BPFO", "ball": "2xBSF", "normal": None}
MANIFEST_KEY = {"BPFI": "BPFI", "BPFO": "BPFO", "2xBSF": "BSF_2x_rolling_element", "BSF": "BSF", "FTF": "FTF"}


def fund(ids, name):
    return next(i for i in ids if i["name"] == name and i["harmonic"] == 1)


def cell(i, expected):
    err = (i["identified_hz"] - expected) / expected * 100
    mark = "**yes**" if i["detected"] else "no"
    note = f", nearer {i['nearer_line']}" if i.get("nearer_line") else ""
    return f"{mark} {i['identified_hz']:.2f} Hz ({err:+.2f} %, {i['prominence_db']:.0f} dB{note})"


def main():
    man = json.load(open(os.path.join(DATA, "manifest.json")))
    rows = []
    for rec in man["recordings"]:
        path = os.path.join(DATA, rec["file"])
        out = subprocess.run([BIN, "analyze", path, "--fs", str(rec["fs_hz"]), "--rpm", str(rec["rpm"]),
                              "--bearing", "cwru6205"], capture_output=True, text=True, check=True)
        r = json.loads(out.stdout)
        exp = rec["expected_fault_frequencies_hz"]
        target = EXPECT[rec["fault_type"]]
        best, second = r["best_component"], r["runner_up_component"]
        detected = sorted({f"{i['name']}" for src in (r["raw"], best["identifications"], second["identifications"])
                           for i in src if i["detected"] and i["harmonic"] == 1})
        row = {
            "id": rec["id"], "fault": f"{rec['fault_type']} {rec['fault_diameter_in']:.3f} in",
            "kurt": f"{r['raw_kurtosis']:.2f}",
            "levels": f"L{best['level']} ({best['kurtosis']:.2f}), L{second['level']} ({second['kurtosis']:.2f})",
            "detected": ", ".join(detected) or "none",
        }
        for name in ("BPFI", "BPFO", "2xBSF"):
            e = exp[MANIFEST_KEY[name]]
            cands = [("raw", fund(r["raw"], name)), (f"L{best['level']}", fund(best["identifications"], name)),
                     (f"L{second['level']}", fund(second["identifications"], name))]
            det = [(w, i) for w, i in cands if i["detected"]]
            w, i = max(det or cands, key=lambda c: c[1]["prominence_db"])
            row[name] = f"{w}: {cell(i, e)}"
        row["verdict"] = ("-" if target is None else
                          ("found" if any(fund(src, target)["detected"] and
                                         abs(fund(src, target)["identified_hz"] / exp[MANIFEST_KEY[target]] - 1) < 0.01
                                         for src in (r["raw"], best["identifications"], second["identifications"]))
                           else "MISSED"))
        rows.append(row)
    print("| recording | fault | raw kurtosis | best, runner-up level (kurtosis) | BPFI | BPFO | 2xBSF | fundamentals detected | expected fault |")
    print("| --- | --- | --- | --- | --- | --- | --- | --- | --- |")
    for r in rows:
        print(f"| {r['id']} | {r['fault']} | {r['kurt']} | {r['levels']} | {r['BPFI']} | {r['BPFO']} | {r['2xBSF']} | {r['detected']} | {r['verdict']} |")


if __name__ == "__main__":
    main()

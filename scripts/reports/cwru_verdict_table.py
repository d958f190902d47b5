#!/usr/bin/env python3
"""The verdict of `bearing-sim analyze` on every whole CWRU recording of the shared data set
(default options; DTCWT and kurtogram band selection), as a markdown table for
docs/lab/cwru.md. Dev script only; needs a built binary.

    cargo build --release && python3 scripts/reports/cwru_verdict_table.py ../shared/data/cwru
"""
import json
import math
import os
import subprocess
import sys

DATA = sys.argv[1] if len(sys.argv) > 1 else "../shared/data/cwru"
BIN = os.environ.get("BEARING_SIM", os.path.join(os.path.dirname(__file__), "../../target/release/bearing-sim"))
TRUTH = {"inner_race": ["inner_race"], "outer_race": ["outer_race"], "ball": ["rolling_element"], "normal": []}


def verdict(rec, kurtogram):
    cmd = [BIN, "analyze", os.path.join(DATA, rec["file"]), "--fs", str(rec["fs_hz"]),
           "--rpm", str(rec["rpm"]), "--bearing", "cwru6205"]
    if kurtogram:
        # narrowest kurtogram band about 100 Hz, as in the evaluation set
        cmd += ["--kurtogram-levels", str(min(12, round(math.log2(rec["fs_hz"] / 200))))]
    out = subprocess.run(cmd, check=True, capture_output=True, text=True).stdout
    return json.loads(out)["verdict"]


def main():
    man = json.load(open(os.path.join(DATA, "manifest.json")))
    print("| recording | truth | verdict, DTCWT | verdict, kurtogram | exact | summary (DTCWT) |")
    print("| --- | --- | --- | --- | --- | --- |")
    for rec in man["recordings"]:
        truth = sorted(TRUTH[rec["fault_type"]])
        v = [verdict(rec, k) for k in (False, True)]
        named = [sorted(x["faults"]) for x in v]
        exact = "yes" if all(n == truth for n in named) else "**no**"
        show = lambda n: " + ".join(n) or "none"
        print(f"| {rec['id']} | {show(truth)} | {show(named[0])} | {show(named[1])} | {exact} | {v[0]['summary']} |")


if __name__ == "__main__":
    main()

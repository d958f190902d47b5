#!/usr/bin/env python3
"""Run the fault verdict on the committed evaluation set (crates/bearing-core/tests/fixtures/eval) with each
band-selection method and print, as markdown, one row per signal and a confusion table per
method (used for docs/lab/cwru.md). Dev script only; needs a release build, no packages.

    cargo build --release && python3 scripts/reports/eval_report.py > /tmp/eval.md

Methods: `dtcwt` = default options (the verdict reads the raw envelope spectrum and the two
DTCWT components of largest kurtosis); `kurtogram` = `--kurtogram-levels L` (raw spectrum,
the kurtogram's band and its runner-up; L = 6 at 12 kHz, 8 at 48 kHz, 9 at 102.4 kHz: the narrowest band about
100 Hz).
"""
import json
import math
import os
import subprocess
import sys

ROOT = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..")
EVAL = os.path.join(ROOT, "crates/bearing-core/tests/fixtures/eval")
BIN = os.environ.get("BEARING_SIM", os.path.join(ROOT, "target/release/bearing-sim"))
TYPES = ["outer_race", "inner_race", "rolling_element", "cage"]
TRUTH = {"outer_race": "outer_race", "inner_race": "inner_race", "ball": "rolling_element"}
SHORT = {"outer_race": "OR", "inner_race": "IR", "rolling_element": "ball", "cage": "cage"}


def kurtogram_levels(fs):
    return max(1, min(12, round(math.log2(fs / 2 / 100))))


def run(sig, method, verdict_harmonics=None):
    cmd = [BIN, "analyze", os.path.join(EVAL, sig["file"]), "--fs", str(sig["fs_hz"]),
           "--rpm", repr(sig["shaft_hz"] * 60), "--bearing", sig["bearing"]]
    if verdict_harmonics:
        cmd += ["--verdict-harmonics", str(verdict_harmonics)]
    if method == "kurtogram":
        cmd += ["--kurtogram-levels", str(kurtogram_levels(sig["fs_hz"]))]
    return json.loads(subprocess.run(cmd, capture_output=True, text=True, check=True).stdout)


def label(types):
    return " + ".join(SHORT[t] for t in types) or "none"


def main():
    signals = json.load(open(os.path.join(EVAL, "manifest.json")))["signals"]
    results = {m: [] for m in ("dtcwt", "kurtogram")}
    for sig in signals:
        truth = sorted(TRUTH[t] for t in sig["truth"])
        for method in results:
            v = run(sig, method)["verdict"]
            ev = {e["fault"]: e for e in v["evidence"]}
            results[method].append((sig, truth, v["faults"], ev))

    print("| signal | truth | verdict, DTCWT | verdict, kurtogram | strongest evidence (DTCWT): type, p, where, harmonics found, fundamental error |")
    print("| --- | --- | --- | --- | --- |")
    for (sig, truth, fd, ev), (_, _, fk, _) in zip(results["dtcwt"], results["kurtogram"]):
        mark = lambda f: label(f) + ("" if sorted(f) == truth else " **x**")
        best = min(ev.values(), key=lambda e: e["p_value"])
        err = f"{best['error_pct']:+.2f} %" if best.get("error_pct") is not None else "-"
        print(f"| {sig['id']} | {label(truth)} | {mark(fd)} | {mark(fk)} | {SHORT[best['fault']]}, "
              f"{best['p_value']:.0e}, {best['spectrum']}, {best['harmonics_found']}/{best['harmonics_searched']}, {err} |")

    for method, rows in results.items():
        print(f"\n**{method}**: rows = truth, columns = fault types named (a compound truth counts in "
              "both of its rows); `exact` = the verdict names the true types and no other.\n")
        classes = ["none"] + TYPES
        print("| truth \\ named | " + " | ".join(SHORT.get(c, c) for c in classes) + " | signals | exact |")
        print("| --- |" + " --- |" * (len(classes) + 2))
        for t in ["none", "outer_race", "inner_race", "rolling_element"]:
            sel = [r for r in rows if (t == "none" and not r[1]) or t in r[1]]
            if not sel:
                continue
            counts = [sum(1 for r in sel if (c == "none" and not r[2]) or c in r[2]) for c in classes]
            exact = sum(1 for r in sel if sorted(r[2]) == r[1])
            print(f"| {SHORT.get(t, t)} | " + " | ".join(map(str, counts)) + f" | {len(sel)} | {exact} |")

    # sensitivity to the one choice of the test, the number of harmonics N per family
    print("\n**Sensitivity to `verdict_harmonics` N** (DTCWT method; default 4): the verdict on "
          "each signal that any N gets wrong, and the number exactly right.\n")
    ns = list(range(3, 11))
    table = {n: [(sig, sorted(TRUTH[t] for t in sig["truth"]), run(sig, "dtcwt", n)["verdict"]["faults"])
                 for sig in signals] for n in ns}
    wrong = [i for i, sig in enumerate(signals)
             if any(sorted(table[n][i][2]) != table[n][i][1] for n in ns)]
    print("| signal | truth | " + " | ".join(f"N = {n}" for n in ns) + " |")
    print("| --- | --- |" + " --- |" * len(ns))
    for i in wrong:
        sig, truth, _ = table[ns[0]][i]
        cells = []
        for n in ns:
            f = table[n][i][2]
            cells.append(label(f) + ("" if sorted(f) == truth else " **x**"))
        print(f"| {sig['id']} | {label(truth)} | " + " | ".join(cells) + " |")
    print("| **exact** | | " + " | ".join(
        f"{sum(1 for sig, truth, f in table[n] if sorted(f) == truth)} / {len(signals)}" for n in ns) + " |")


if __name__ == "__main__":
    sys.exit(main())

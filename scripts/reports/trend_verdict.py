#!/usr/bin/env python3
"""The paper-trends verdict of docs/lab/paper-trends.md from a study's table.csv.

Usage: python3 scripts/reports/trend_verdict.py docs/lab/paper-trends/rheology/table.csv

Standard library only. Prints, for the outer fault (BPFO) and the inner fault (BPFI), the
error of the identified line against eq. 37 (raw envelope spectrum), the error implied by
the run's mean cage speed, and the split of that error into the loaded balls' contact angles
(eq. 37 at the load zone's angles against 15 deg) and the cage's slip against them, on each
line of the design (speed, axial load, radial load), and then the paper's four statements
with the figures that decide them.
"""
import csv
import sys


def pct(a, b):
    return 100.0 * (a / b - 1.0)


def main(path):
    rows = [r for r in csv.DictReader(open(path)) if r["state"] == "succeeded"]
    failed = [r for r in csv.DictReader(open(path)) if r["state"] != "succeeded"]
    by = {}
    for r in rows:
        key = (r["fault_case"], int(float(r["speed"])), int(float(r["axial_load"])),
               int(float(r["radial_load"])))
        by[key] = r

    def line(fault, r):
        f = "bpfo" if fault == "outer" else "bpfi"
        theory = float(r[f + "_theory_hz"])
        loaded = float(r[f + "_loaded_theory_hz"])
        cage = float(r[f + "_cage_hz"])
        raw = r[f + "_raw_error_pct"]
        raw = float(raw) if raw else float("nan")
        det = r[f + "_raw_detected"]
        return raw, det, pct(cage, theory), pct(loaded, theory), pct(cage, loaded)

    print("| fault | speed | Fa | Fr | spectrum error (%) | detected | cage error (%) | loaded angles vs 15 deg (%) | cage vs loaded rolling (%) | whirl |")
    print("| --- | --- | --- | --- | --- | --- | --- | --- | --- | --- |")
    for key in sorted(by):
        fault, n, fa, fr = key
        raw, det, cage, ang, slip = line(fault, by[key])
        print(f"| {fault} | {n} | {fa} | {fr} | {raw:+.3f} | {det} | {cage:+.3f} | {ang:+.3f} | {slip:+.3f} | {by[key]['cage_whirl']} |")
    for r in failed:
        print(f"| {r['fault_case']} | {r['speed']} | {r['axial_load']} | {r['radial_load']} | failed: {r['error']} |")

    def err(fault, n, fa, fr):
        r = by.get((fault, n, fa, fr))
        return line(fault, r)[0] if r else float("nan")

    print()
    o, i = err("outer", 10000, 100, 300), err("inner", 10000, 100, 300)
    print(f"1. paper's point: BPFO {o:+.3f} %, BPFI {i:+.3f} % -> {'yes' if o < 0 < i else 'no'}")
    so = [err("outer", n, 100, 300) for n in (4000, 10000, 12000)]
    si = [err("inner", n, 100, 300) for n in (4000, 10000, 12000)]
    grow = lambda v: abs(v[0]) < abs(v[1]) < abs(v[2])
    print(f"2. speed 4000/10000/12000: BPFO {so[0]:+.3f}/{so[1]:+.3f}/{so[2]:+.3f}, BPFI {si[0]:+.3f}/{si[1]:+.3f}/{si[2]:+.3f} -> {'yes' if grow(so) and grow(si) else 'no'} (|error| grows)")
    ao = [err("outer", 10000, fa, 300) for fa in (100, 200, 400)]
    ai = [err("inner", 10000, fa, 300) for fa in (100, 200, 400)]
    fall = lambda v: abs(v[0]) > abs(v[1]) > abs(v[2])
    print(f"3. axial 100/200/400 N: BPFO {ao[0]:+.3f}/{ao[1]:+.3f}/{ao[2]:+.3f}, BPFI {ai[0]:+.3f}/{ai[1]:+.3f}/{ai[2]:+.3f} -> {'yes' if fall(ao) and fall(ai) else 'no'} (|error| falls)")
    radial = [k for k in by if k[0] == "outer" and k[1] == 10000 and k[2] == 400]
    rv = [err("outer", 10000, 400, k[3]) for k in sorted(radial)]
    axial = [err("outer", 10000, fa, 300) for fa in (400, 600, 800)]
    spread = lambda v: max(v) - min(v) if v else float("nan")
    print(f"4. radial (Fa 400 N, Fr {sorted(k[3] for k in radial)}): BPFO spread {spread(rv):.3f} points; axial 400-800 N spread {spread(axial):.3f} -> {'yes' if spread(rv) < spread(axial) else 'no'}")


if __name__ == "__main__":
    main(sys.argv[1])

#!/usr/bin/env python3
"""Where a ball runs against its cage, per sector of its orbit, from a `bearing-sim run`
result recorded with `--ball-pocket K` (docs/reference/model.md, "Cage motion in the
summary"; the table in docs/lab/paper-trends.md, "where the two laws' cage slips differ").

Usage: python3 scripts/reports/ball_pocket_profile.py RESULT.json [T0 [SECTORS]]

Standard library only. Over the samples from T0 (s, default 0.2) it prints, per sector of
azimuth from +Z (the radial load's direction at radial_load_angle 0; default 12 sectors),
the mean of the ball's orbital speed less the cage's (rad/s) and the mean and range of its
offset in the pocket (um, + toward increasing azimuth), and the whole window's mean lead,
which a ball that stays in its pocket keeps near zero.
"""
import json
import math
import sys


def main(path, t0=0.2, sectors=12):
    result = json.load(open(path))
    channels = result["channels"]
    fs = channels["sample_rate"]
    data = {c["name"]: c["data"] for c in channels["channels"]}
    names = [n for n in data if n.endswith("_azimuth")]
    if not names:
        sys.exit(f"{path}: no ball{{k}}_azimuth channel; run with --ball-pocket K")
    ball = names[0][: -len("_azimuth")]
    start = int(round(t0 * fs))
    az = data[ball + "_azimuth"][start:]
    lead = data[ball + "_cage_lead"][start:]
    offset = data[ball + "_pocket_offset"][start:]
    if not az:
        sys.exit(f"{path}: no samples after {t0} s")
    acc = [[0, 0.0, 0.0, math.inf, -math.inf] for _ in range(sectors)]
    for a, l, o in zip(az, lead, offset):
        s = min(sectors - 1, int((a + math.pi) / (2 * math.pi) * sectors))
        b = acc[s]
        b[0] += 1
        b[1] += l
        b[2] += o
        b[3] = min(b[3], o)
        b[4] = max(b[4], o)
    width = 360.0 / sectors
    print(f"{path}: {ball}, {len(az)} samples from {t0} s; mean lead "
          f"{sum(lead) / len(lead):.4f} rad/s")
    print("azimuth (deg) | lead (rad/s) | offset (um) | offset range (um)")
    print("--- | --- | --- | ---")
    for i, (n, l, o, lo, hi) in enumerate(acc):
        centre = -180.0 + width * (i + 0.5)
        if n == 0:
            print(f"{centre:.0f} | - | - | -")
            continue
        print(f"{centre:.0f} | {l / n:+.3f} | {1e6 * o / n:+.1f} | {1e6 * lo:+.1f} to {1e6 * hi:+.1f}")


if __name__ == "__main__":
    if len(sys.argv) < 2:
        sys.exit(__doc__)
    main(sys.argv[1], *(float(a) for a in sys.argv[2:3]), *(int(a) for a in sys.argv[3:4]))

#!/usr/bin/env python3
"""Compare the band `bearing-sim analyze --kurtogram-levels L` chooses with the band a
published reference implementation of Antoni's fast kurtogram chooses, on the CWRU
recordings of the shared data set; print a markdown table (used for
docs/lab/kurtogram-reference.md). Dev script only, not a test; needs a built binary, numpy,
and the reference, which is NOT part of this repository (its code is not copied here):

  * --matlab PATH  J. Antoni's own Fast_kurtogram.m (MathWorks File Exchange 48912,
    "Fast Kurtogram", revision 12-2014, BSD licence), run unmodified in GNU Octave
    (`apt-get install octave octave-signal gnuplot-nox fonts-freefont-otf`). A GitHub
    mirror: github.com/yushi1006/Subband-averaging-kurtogram-with-dual-tree-complex-
    wavelet-packet, file Fast_kurtogram.m (commit 94a69b7d). Fast_kurtogram returns only
    the filtered signal, so this script puts a stub `imagesc.m` first on Octave's path
    that records the matrix Fast_kurtogram plots (its `Kwav`, already clipped at 0); the
    reference file itself is run as it is.
  * --port PATH    the Python port by D. Newman, kurtogram.py of
    github.com/danielnewman09/Kurtogram-Analysis (commit d419b1e6, BSD header of Antoni's
    code), imported from PATH; Kwav is the first value `fast_kurtogram` returns. It
    follows the MATLAB line by line, with scipy's firwin for fir1.

With both, the first (--matlab) is the one tabulated and the port is a cross-check (max
|dK| over the kurtogram, and whether it picks the same bands).

    python3 -m venv /tmp/kvenv && /tmp/kvenv/bin/pip install numpy scipy
    /tmp/kvenv/bin/python scripts/research/kurtogram_reference.py --binary target/release/bearing-sim \
        --matlab /tmp/kref/Fast_kurtogram.m --port /tmp/kref/kurtogram.py \
        --data ../shared/data/cwru [--harmonics 3] [--levels-12k 6] [--levels-48k 8]

How the comparison is made
--------------------------
* Same input: the raw float32 samples of each recording, whole length, as float64. Same
  number of levels for both (nlevel = 6 at 12 kHz; 8 at 48 kHz, which gives the same
  narrowest band, 93.75 Hz, and is within Antoni's limit log2(N) - 7).
* Same tree and level numbering: Antoni's rows are Level_w = 0, 1, 1+log2(3)-1, 2, ...,
  nlevel (printed 1.6, 2.6, ... = k + 0.585); ours (`level` in the JSON) is k + log2(3)-1
  too, so row r of Kwav is matched to our level by value. Level k has 2^k bands, level
  k + 0.585 has 3 * 2^(k-1), band j spanning [j, j+1] * fs / 2 / count (nominal edges;
  Kwav repeats each band's value over 3 * 2^nlevel / count columns, in increasing
  frequency, which was checked on a synthetic resonance). Our band index is
  round(low_hz / width).
* (a) the reference's argmax over the whole kurtogram, ties broken as Antoni's max_IJ
  (lowest frequency column, then lowest row). (b) its argmax among bands at least W wide,
  W = harmonics x max(BPFI, BPFO), BPFI/BPFO taken from the binary's own `theory` so the
  rule is exactly ours (`best_at_least`). (b') as (b) without level 0: see below.
* Ours: `bearing-sim analyze FILE --fs --rpm --bearing cwru6205 --kurtogram-levels L
  --harmonics H`, field `kurtogram`.
* "same": same level and band index ("yes"), or overlapping by >= 50 % of the narrower
  band ("yes, overlap" when the widths are within 2x; "yes, nested xR" when one band is R
  times wider, where the rule only says the narrow band lies inside the wide one, e.g.
  any band against level 0), else "no".
* Diagnostic table (--trim N, default 16): our kurtogram re-computed in numpy with N
  envelope samples dropped at each end of every band, to show which of our choices come
  from the circular FFT's wrap (the step between the record's last and first sample is a
  broadband impulse; in a band with almost no energy, e.g. next to Nyquist, it alone makes
  K huge). This is not what the binary does.
* SK values: "ref K @ ours" is the reference's Kwav at our band; "our K @ ref (b)" comes
  from a numpy re-computation of our ideal-filter kurtogram (the algorithm of
  crates/bearing-core/src/signal/kurtogram.rs, written again here); the script checks
  that re-computation picks the binary's band and kurtosis first ("replica" column).

Known differences between the two computations
----------------------------------------------
* Filters: Antoni uses short quasi-analytic FIR filters (h = fir1(16, 0.4) shifted to
  fs/8, its mirror g, and fir1(24, 0.267) for the 1/3 splits), applied with `filter`
  and decimated by 2 or 3 at each node. Their -3 dB band is about 1.4 times the nominal
  one (for h, -0.05 .. 0.30 fs against 0 .. 0.25 fs), so neighbouring bands overlap and
  a resonance near an edge leaks into both. Ours is an ideal rectangular band-pass of one
  circular FFT (no overlap, no transition band, circular wrap at the record's ends).
* Edges in time: Antoni drops the first length(h) = 17 samples of every band's output
  (filter transient) at each node; ours keeps every sample (circular).
* Estimator: both use <|c|^4> / <|c|^2>^2 - 2 on a complex band signal ('kurt2'), but
  Antoni subtracts the mean of c first and clips negative values to 0 (Kwav .* (Kwav >
  0)), and his level 0 is the kurtosis of the REAL signal minus 3, not of its analytic
  signal minus 2. For a narrow-band impulsive signal the real excess kurtosis is about
  1.5 times the complex one, so his level 0 is inflated relative to every other row and
  is often his argmax; ours takes level 0 as the analytic signal like every other band.
  Hence (b'), which leaves level 0 out.
* Octave's fir1 (signal 1.4.3) designs by frequency sampling (fir2), MATLAB's and scipy's
  firwin by windowed sinc: coefficients differ by up to ~4e-4, Kwav by up to ~0.02
  between --matlab under Octave and --port. MATLAB itself was not available.
* Band width for the W rule: reference bands use the nominal width; ours use the
  bin-rounded width high_hz - low_hz (below the nominal one by at most one bin).
"""
import argparse
import contextlib
import importlib.util
import io
import json
import math
import os
import subprocess
import sys
import tempfile

import numpy as np

LOG3 = math.log2(3) - 1  # 0.585: level k + LOG3 is the 1/3 level after level k


def level_w(nlevel):
    """Rows of Antoni's Kwav: 0, 1, 1.585, 2, ..., nlevel (2 * nlevel rows)."""
    out = [0.0]
    for k in range(1, nlevel + 1):
        out += [float(k), k + LOG3]
    return out[: 2 * nlevel]


def band_count(level):
    k = math.floor(level + 1e-9)
    if abs(level - k) < 1e-6:
        return 2 ** k
    return 3 * 2 ** (k - 1)


def label(level):
    return f"{level:.1f}"


# ---------------------------------------------------------------- reference back-ends
OCT_STUB = """function h = imagesc(varargin)
  % records the kurtogram Fast_kurtogram passes to imagesc(freq_w, rows, Kwav)
  global KREF_KWAV
  KREF_KWAV = varargin{3}; h = [];
end
"""

OCT_DRIVER = """graphics_toolkit('gnuplot'); set(0, 'defaultfigurevisible', 'off');
pkg load signal
addpath('%(ref)s'); addpath('%(stub)s');
global KREF_KWAV
fid = fopen('%(data)s', 'r', 'ieee-le'); x = fread(fid, Inf, 'float32=>double'); fclose(fid);
c = Fast_kurtogram(x, %(nlevel)d, %(fs)r);
fid = fopen('%(out)s', 'w'); fwrite(fid, KREF_KWAV', 'double'); fclose(fid);
close all;
"""


def kwav_octave(mfile, data, fs, nlevel):
    with tempfile.TemporaryDirectory() as tmp:
        stub = os.path.join(tmp, "stub")
        os.mkdir(stub)
        with open(os.path.join(stub, "imagesc.m"), "w") as f:
            f.write(OCT_STUB)
        out = os.path.join(tmp, "kwav.bin")
        drv = os.path.join(tmp, "driver.m")
        with open(drv, "w") as f:
            f.write(OCT_DRIVER % dict(ref=os.path.dirname(os.path.abspath(mfile)), stub=stub,
                                      data=os.path.abspath(data), nlevel=nlevel, fs=float(fs), out=out))
        p = subprocess.run(["octave-cli", "-q", "--no-gui", drv], capture_output=True, text=True, cwd=tmp)
        if not os.path.exists(out):
            sys.exit(f"octave failed on {data}:\n{p.stderr[-3000:]}")
        return np.fromfile(out, dtype=np.float64).reshape(2 * nlevel, 3 * 2 ** nlevel)


def load_port(path):
    spec = importlib.util.spec_from_file_location("kurtogram_port", path)
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    return mod


def kwav_port(mod, x, fs, nlevel):
    with contextlib.redirect_stdout(io.StringIO()):  # it prints its choice
        return np.asarray(mod.fast_kurtogram(x.copy(), float(fs), nlevel=nlevel)[0], dtype=float)


# ---------------------------------------------------------------- kurtogram as bands
def bands_of(kwav, fs, nlevel):
    """[(row, level, j, low, high, K)] from Kwav, checking each band's columns agree."""
    cols = 3 * 2 ** nlevel
    out = []
    for r, lev in enumerate(level_w(nlevel)):
        nb = band_count(lev)
        per = cols // nb
        w = fs / 2 / nb
        for j in range(nb):
            blk = kwav[r, j * per:(j + 1) * per]
            assert np.all(blk == blk[0]), (r, j)
            out.append((r, lev, j, j * w, (j + 1) * w, float(blk[0])))
    return out


def max_ij(kwav, allowed):
    """Antoni's max_IJ (max over rows per column, then first best column, first row)."""
    k = np.where(allowed, kwav, -np.inf)
    col_best = k.max(axis=0)
    j = int(np.argmax(col_best))
    i = int(np.argmax(k[:, j]))
    return i, j


def pick(kwav, fs, nlevel, min_w, skip_level0=False):
    cols = 3 * 2 ** nlevel
    allowed = np.zeros_like(kwav, dtype=bool)
    for r, lev in enumerate(level_w(nlevel)):
        allowed[r, :] = (fs / 2 / band_count(lev) >= min_w) and not (skip_level0 and r == 0)
    i, c = max_ij(kwav, allowed)
    lev = level_w(nlevel)[i]
    nb = band_count(lev)
    j = c // (cols // nb)
    w = fs / 2 / nb
    return dict(row=i, level=lev, j=j, low=j * w, high=(j + 1) * w, K=float(kwav[i, c]))


# ---------------------------------------------------------------- ours, re-computed
def ideal_kurtogram(x, fs, levels, trim=0):
    """The algorithm of kurtogram.rs: the record extended by its mirror image (no step at
    the FFT's wrap), ideal FFT band-pass per band, the first half of each band signal (the
    record), its mean removed, K = m4/m2^2 - 2.
    trim > 0 (diagnostic, not what the binary does): drop that many envelope samples at
    each end of every band before the moments."""
    n = len(x)
    y = x - x.mean()
    spec = np.fft.fft(np.concatenate([y, y[::-1]]))
    m = 2 * n
    half = m // 2
    out = []

    def split(parts, level):
        for i in range(parts):
            lo = i * half // parts
            hi = max((i + 1) * half // parts, lo + 1)
            c = np.fft.ifft(spec[lo:hi])
            c = c[: (len(c) + 1) // 2]
            c = c - c.mean()
            p = np.abs(c) ** 2
            if trim and len(p) > 4 * trim:
                p = p[trim:-trim]
            m2 = p.mean()
            k = 0.0 if m2 <= 0 else (p * p).mean() / m2 ** 2 - 2.0
            out.append((level, i, lo * fs / m, hi * fs / m, k))

    split(1, 0.0)
    for k in range(1, levels + 1):
        split(2 ** k, float(k))
        if k < levels:
            split(3 << (k - 1), k + LOG3)
    return out


def row_of(level, nlevel):
    lw = level_w(nlevel)
    r = min(range(len(lw)), key=lambda i: abs(lw[i] - level))
    assert abs(lw[r] - level) < 1e-6, level
    return r


def same_band(a, b):
    """'yes' (same level and index), 'yes, overlap' (>= 50 % of the narrower band, widths
    within 2x), 'yes, nested xR' (the same, but one band R > 2 times wider: the 50 % rule
    then only says the narrow band lies in the wide one, e.g. anything in level 0), 'no'."""
    if a["row"] == b["row"] and a["j"] == b["j"]:
        return "yes"
    wa, wb = a["high"] - a["low"], b["high"] - b["low"]
    ov = min(a["high"], b["high"]) - max(a["low"], b["low"])
    if ov < 0.5 * min(wa, wb):
        return "**no**"
    ratio = max(wa, wb) / min(wa, wb)
    return "yes, overlap" if ratio <= 2.0 + 1e-6 else f"yes, nested x{ratio:.0f}"


def fmt(b):
    return f"{label(b['level'])} / {b['low']:.0f}-{b['high']:.0f} / {b['K']:.2f}"


def main():
    here = os.path.dirname(os.path.abspath(__file__))
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--binary", default=os.path.join(here, "../../target/release/bearing-sim"))
    ap.add_argument("--data", default=os.path.join(here, "../../../shared/data/cwru"))
    ap.add_argument("--matlab", help="path of Antoni's Fast_kurtogram.m (run in octave-cli)")
    ap.add_argument("--port", help="path of kurtogram.py (danielnewman09/Kurtogram-Analysis)")
    ap.add_argument("--harmonics", type=int, default=3)
    ap.add_argument("--levels-12k", type=int, default=6)
    ap.add_argument("--levels-48k", type=int, default=8)
    ap.add_argument("--trim", type=int, default=16,
                    help="diagnostic table: our kurtogram re-computed with this many envelope samples "
                         "dropped at each end of every band (0: no such table)")
    ap.add_argument("--only", nargs="*", help="recording ids (default: all in the manifest)")
    a = ap.parse_args()
    if not (a.matlab or a.port):
        ap.error("give --matlab and/or --port")
    port = load_port(a.port) if a.port else None
    ref_name = "Fast_kurtogram.m (Octave)" if a.matlab else "kurtogram.py port"

    man = json.load(open(os.path.join(a.data, "manifest.json")))
    rows, checks, trimmed = [], [], []
    for rec in man["recordings"]:
        if a.only and rec["id"] not in a.only:
            continue
        path = os.path.join(a.data, rec["file"])
        fs = float(rec["fs_hz"])
        nlevel = a.levels_12k if fs < 24000 else a.levels_48k
        x = np.fromfile(path, dtype="<f4").astype(np.float64)

        r = json.loads(subprocess.run(
            [a.binary, "analyze", path, "--fs", str(rec["fs_hz"]), "--rpm", str(rec["rpm"]),
             "--bearing", "cwru6205", "--kurtogram-levels", str(nlevel), "--harmonics", str(a.harmonics)],
            capture_output=True, text=True, check=True).stdout)
        th = r["theory"]
        min_w = a.harmonics * max(th["bpfi"], th["bpfo"])
        kg = r["kurtogram"]
        orow = row_of(kg["level"], nlevel)
        nb = band_count(level_w(nlevel)[orow])
        oj = int(round(kg["band_hz"][0] / (fs / 2 / nb)))
        ours = dict(row=orow, level=kg["level"], j=oj, low=kg["band_hz"][0], high=kg["band_hz"][1],
                    K=kg["kurtosis"])

        kw_m = kwav_octave(a.matlab, path, fs, nlevel) if a.matlab else None
        kw_p = kwav_port(port, x, fs, nlevel) if port else None
        kw = kw_m if kw_m is not None else kw_p
        bands_of(kw, fs, nlevel)  # asserts the block structure
        ra = pick(kw, fs, nlevel, 0.0)
        rb = pick(kw, fs, nlevel, min_w)
        rb2 = pick(kw, fs, nlevel, min_w, skip_level0=True)
        cols = 3 * 2 ** nlevel
        ref_at_ours = float(kw[orow, oj * (cols // nb)])

        mine = ideal_kurtogram(x, fs, nlevel)
        wide = [m for m in mine if m[3] - m[2] >= min_w]
        rep = max(wide, key=lambda m: m[4])
        replica_ok = (row_of(rep[0], nlevel) == orow and rep[1] == oj and abs(rep[4] - ours["K"]) < 1e-6)
        ours_at = {(row_of(m[0], nlevel), m[1]): m[4] for m in mine}
        if a.trim:
            t = max((m for m in ideal_kurtogram(x, fs, nlevel, a.trim) if m[3] - m[2] >= min_w), key=lambda m: m[4])
            tb = dict(row=row_of(t[0], nlevel), level=t[0], j=t[1], low=t[2], high=t[3], K=t[4])
            trimmed.append([rec["id"], fmt(ours), fmt(tb), fmt(rb2), same_band(rb2, tb)])

        if kw_m is not None and kw_p is not None:
            pa, pb = pick(kw_p, fs, nlevel, 0.0), pick(kw_p, fs, nlevel, min_w)
            pb2 = pick(kw_p, fs, nlevel, min_w, skip_level0=True)
            checks.append((rec["id"], float(np.abs(kw_m - kw_p).max()),
                           all((p["row"], p["j"]) == (q["row"], q["j"]) for p, q in ((pa, ra), (pb, rb), (pb2, rb2)))))
        rows.append([
            rec["id"], rec["fault_type"], f"{fs / 1000:.0f}k/{nlevel}", f"{min_w:.0f}",
            fmt(ra), fmt(rb), fmt(rb2), fmt(ours),
            f"{ref_at_ours:.2f}", f"{ours_at[(rb['row'], rb['j'])]:.2f} / {ours_at[(rb2['row'], rb2['j'])]:.2f}",
            same_band(rb, ours), same_band(rb2, ours),
            "ok" if replica_ok else "MISMATCH",
        ])

    print(f"Reference: {ref_name}; harmonics = {a.harmonics}; bands as level / Hz / K "
          "(K = SK of the complex envelope, minus 2; reference level 0: real signal, minus 3)\n")
    head = ["recording", "fault", "fs/nlevel", "W Hz", "ref (a) argmax", "ref (b) >= W", "ref (b') >= W, no L0",
            "ours", "ref K @ ours", "our K @ ref (b) / (b')", "(b) = ours", "(b') = ours", "replica"]
    print("| " + " | ".join(head) + " |")
    print("|" + "---|" * len(head))
    for row in rows:
        print("| " + " | ".join(row) + " |")
    if trimmed:
        print(f"\nDiagnostic (not the binary): our kurtogram re-computed in numpy with {a.trim} envelope "
              "samples dropped at each end of every band, i.e. without the circular wrap's step:\n")
        print("| recording | ours (binary) | ours, ends trimmed | ref (b') | (b') = trimmed |")
        print("|---|---|---|---|---|")
        for row in trimmed:
            print("| " + " | ".join(row) + " |")
    if checks:
        print("\nCross-check, Python port vs Fast_kurtogram.m under Octave:\n")
        print("| recording | max abs dK over Kwav | same (a), (b), (b') picks |")
        print("|---|---|---|")
        for rid, d, same in checks:
            print(f"| {rid} | {d:.4f} | {'yes' if same else '**no**'} |")


if __name__ == "__main__":
    main()

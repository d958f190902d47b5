"""The CWRU signals of the evaluation set, each as its committed excerpt and, when ../shared
is there, as its whole recording: the inputs of the pre-processing checks
(scripts/research/cpw_check.py, scripts/research/ar_check.py). Dev helper: needs numpy."""
import json
import os

import numpy as np

ROOT = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..")
EVAL = os.path.join(ROOT, "crates/bearing-core/tests/fixtures/eval")
SHARED = os.path.join(ROOT, "../shared/data/cwru")


def cwru_records():
    """Yield (manifest entry, "excerpt" or "whole", samples as float64)."""
    signals = json.load(open(os.path.join(EVAL, "manifest.json")))["signals"]
    for sig in signals:
        if sig["kind"] != "cwru":
            continue
        sources = [("excerpt", os.path.join(EVAL, sig["file"]))]
        whole = os.path.join(SHARED, sig["file"])
        if os.path.exists(whole):
            sources.append(("whole", whole))
        for what, src in sources:
            yield sig, what, np.fromfile(src, dtype="<f4").astype(float)

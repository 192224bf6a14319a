#!/usr/bin/env python3
# SPDX-License-Identifier: MIT
"""Accuracy of the independent simulator (tests/python/indepsim) against
the exact step responses in tests/ref: the largest error over t in
[1 ms, 5 s], relative to the peak, per case and internal rate. Prints a
markdown table; never fails on the figures.

    .venv/bin/python bench/bench_indepsim_accuracy.py [--rates 8000,80000]
"""
from __future__ import annotations

import argparse
import os
import sys
import time
from pathlib import Path

for v in ("OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ.setdefault(v, "1")
ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "tests" / "python"))

from indepsim import reference  # noqa: E402


def main() -> int:
    ap = argparse.ArgumentParser()
    ap.add_argument("--rates", default="8000,80000", help="internal rates, Hz")
    a = ap.parse_args()
    try:
        rates = [float(r) for r in a.rates.split(",")]
        if not all(1000.0 <= r <= 1e6 for r in rates):
            raise ValueError
    except ValueError:
        print("bench_indepsim_accuracy: --rates: comma-separated rates in [1e3, 1e6] Hz",
              file=sys.stderr)
        return 2
    cases, exact = reference.load(ROOT / "tests" / "ref")
    print("| case | config | " + " | ".join(f"{r:.0f} Hz: error / peak (at t)" for r in rates)
          + " | time |")
    print("|---|---|" + "---|" * len(rates) + "---|")
    worst = {r: 0.0 for r in rates}
    for name, spec in cases.items():
        cells, t0 = [], time.monotonic()
        for r in rates:
            err, at = reference.step_error(spec, exact["t"], exact[name], r)
            worst[r] = max(worst[r], err)
            cells.append(f"{err:.1e} ({at * 1e3:.3g} ms)")
        print(f"| {name} | {spec['config']} | " + " | ".join(cells)
              + f" | {time.monotonic() - t0:.1f} s |")
    print()
    for r in rates:
        print(f"- worst at {r:.0f} Hz: {worst[r]:.1e} of peak")
    return 0


if __name__ == "__main__":
    sys.exit(main())

# SPDX-License-Identifier: MIT
"""python -m blindsim list | make NAME [NAME ...] --seed S [--noise KIND] --out DIR

`make` writes DIR/NAME-S.csv (the record), DIR/NAME-S.noise.csv (the noise
added to pc, one value per line) and DIR/NAME-S.json (its truth).
"""
from __future__ import annotations

import argparse
import fnmatch
import json
import os
import sys
from pathlib import Path

import numpy as np

from .catalogue import SCENARIOS, build
from .sensors import NOISE_KINDS


def write(name: str, seed: int, out: Path, noise: str | None = None) -> tuple[Path, Path]:
    cols, truth = build(name, seed, noise)
    names = truth["columns"]
    out.mkdir(parents=True, exist_ok=True)
    csv = out / f"{name}-{seed}.csv"
    js = out / f"{name}-{seed}.json"
    # Written under temporary names and renamed, the truth last: a reader
    # that finds the JSON finds the whole record.
    tmp = f".tmp{os.getpid()}"
    with open(str(csv) + tmp, "w") as f:
        f.write(f"# blindsim {name} seed {seed}\n")
        f.write(",".join(names) + "\n")
        for t, e, pc in zip(cols["t"], cols["e"], cols["pc"]):
            f.write(f"{t:.7f},{e:.9g},{pc:.9g}\n")
    os.replace(str(csv) + tmp, csv)
    noise_csv = out / f"{name}-{seed}.noise.csv"
    np.savetxt(str(noise_csv) + tmp, cols["noise"], fmt="%.10g")
    os.replace(str(noise_csv) + tmp, noise_csv)
    Path(str(js) + tmp).write_text(json.dumps(truth, indent=1) + "\n")
    os.replace(str(js) + tmp, js)
    return csv, js


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(prog="blindsim")
    sub = ap.add_subparsers(dest="cmd", required=True)
    sub.add_parser("list")
    mk = sub.add_parser("make")
    mk.add_argument("names", nargs="+", help="scenario names or shell patterns")
    mk.add_argument("--seed", type=int, default=1)
    mk.add_argument("--out", type=Path, required=True)
    mk.add_argument("--noise", choices=NOISE_KINDS, default=None,
                    help="replace the scenario's sensor noise (every other draw unchanged)")
    a = ap.parse_args(argv)
    if a.cmd == "list":
        for k, v in SCENARIOS.items():
            print(f"{k:34s} {v['cls']:8s} {v['config']:3s} {v['exc']:9s} {v['noise']:5s} "
                  f"{v['fs']:5d} Hz {v['dur']:4.0f} s {','.join(v['effects']) or 'none'}")
        return 0
    if a.seed < 0:
        print("blindsim: --seed must be >= 0", file=sys.stderr)
        return 2
    names = [k for k in SCENARIOS if any(fnmatch.fnmatchcase(k, p) for p in a.names)]
    if not names:
        print(f"blindsim: no scenario matches {' '.join(a.names)}", file=sys.stderr)
        return 2
    for n in names:
        csv, _ = write(n, a.seed, a.out, a.noise)
        print(csv)
    return 0


if __name__ == "__main__":
    sys.exit(main())

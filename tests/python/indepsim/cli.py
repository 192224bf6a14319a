# SPDX-License-Identifier: MIT
"""python -m indepsim list
python -m indepsim make SCENARIO --seed N --out DIR

make writes DIR/SCENARIO-N.csv (header t,e,pc) and DIR/SCENARIO-N.truth.json.
Bad arguments: one line on stderr, exit status 2."""
from __future__ import annotations

import argparse
import os
import sys

from .scenarios import CATALOGUE, SEED_MAX


class _Parser(argparse.ArgumentParser):
    def error(self, message: str) -> None:      # one line, no usage block
        print(f"indepsim: {message}", file=sys.stderr)
        raise SystemExit(2)


def _fail(msg: str) -> int:
    print(f"indepsim: {msg}", file=sys.stderr)
    return 2


def main(argv: list[str] | None = None) -> int:
    ap = _Parser(prog="indepsim", description=__doc__)
    sub = ap.add_subparsers(dest="cmd", required=True)
    sub.add_parser("list", help="list the scenarios")
    mk = sub.add_parser("make", help="write one record and its truth")
    mk.add_argument("scenario")
    mk.add_argument("--seed", required=True)
    mk.add_argument("--out", required=True)
    a = ap.parse_args(argv)
    if a.cmd == "list":
        for name, r in CATALOGUE.items():
            print(f"{name}\t{r.get('cls')}\t{r.get('expected')}\t{r.description}")
        return 0
    if a.scenario not in CATALOGUE:
        return _fail(f"unknown scenario '{a.scenario}' (python -m indepsim list)")
    try:
        seed = int(a.seed, 10)
    except ValueError:
        return _fail(f"seed '{a.seed}' is not an integer")
    if not 0 <= seed <= SEED_MAX:
        return _fail(f"seed {seed} outside [0, {SEED_MAX}]")
    try:
        os.makedirs(a.out, exist_ok=True)
    except OSError as exc:
        return _fail(f"cannot create output directory '{a.out}': {exc.strerror}")
    if not os.access(a.out, os.W_OK):
        return _fail(f"output directory '{a.out}' is not writable")
    from .make import make, write      # scipy: only once the arguments are good
    rec = make(a.scenario, seed)
    try:
        csv, js = write(rec, a.out, f"{a.scenario}-{seed}")
    except OSError as exc:
        return _fail(f"cannot write the record: {exc.strerror}")
    print(csv)
    print(js)
    return 0

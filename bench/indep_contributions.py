#!/usr/bin/env python3
# SPDX-License-Identifier: MIT
"""How much each true effect of an independent-simulator record moves its
sampled output on top of the others, in the part pneufrac-fit fits on and
in the part it validates on, over the noise sd: the split the tool used
(HELD_OUT, its JSON record.held_out, e.g. '[[1400, 2000], ...]'; the
tool chooses it from the record, data.split_for), or the tail
(pneufrac_fit.holdout.layout) when not given.

    PYTHONPATH=tests/python .venv/bin/python bench/indep_contributions.py NAME SEED [HELD_OUT]

Prints one JSON object: {effect: {"fit": rms/sd, "val": rms/sd}}. It
answers, for a record whose diagnosis misses one of two effects, whether
that effect is in the record where the guards look for it: an effect
absent from the held-out part cannot pass the held-out guard, whatever
the fit part shows. These are the effect switched off with every other
parameter as simulated, an upper bound on what a refitted model without
it can be shown to miss (the refit absorbs part of it).

The record is remade by indepsim's own make(); each call of its
simulator with effects on is repeated with each effect off, and the
sampling instants are those make() drew, so nothing here re-implements
the simulator or the acquisition.
"""
from __future__ import annotations

import dataclasses
import json
import math
import sys

import numpy as np

from indepsim import daq, make, simulate
from pneufrac_fit import holdout
from indepsim.scenarios import CATALOGUE, SEED_MAX

# Each effect's fields at "off" (indepsim.effects.Effects' defaults).
OFF = {"dead_time": {"dead_time": 0.0}, "lag": {"lag": 0.0},
       "saturation": {"sat_lo": -math.inf, "sat_hi": math.inf},
       "backlash": {"deadband": 0.0}, "nozzle": {"nozzle_xh": 0.0}}


def contributions(name: str, seed: int, held: list | None = None) -> dict:
    runs: dict[str, object] = {}
    times: list[np.ndarray] = []
    run, sample_times = simulate.run, daq.sample_times

    def run_each_off(config, p, fx, e, fs_int, **kw):
        out = run(config, p, fx, e, fs_int, **kw)
        if fx.names():
            runs["all"] = (out, fs_int)
            for c in fx.names():
                runs[c] = (run(config, p, dataclasses.replace(fx, **OFF[c]), e, fs_int, **kw),
                           fs_int)
        return out

    def keep_times(*a, **kw):
        t = sample_times(*a, **kw)
        times.append(t)
        return t

    simulate.run, daq.sample_times = run_each_off, keep_times
    try:
        rec = make.make(name, seed)
    finally:
        simulate.run, daq.sample_times = run, sample_times
    truth = rec.truth
    if "all" not in runs:
        return {}
    fs = truth["record"]["fs"]
    t_start = -truth["record"]["pre_roll"] - 2.0 / fs
    sd = truth["noise"]["sd"]
    t = times[0]
    split = holdout.layout(t.size) if held is None else split_of(held, t.size)
    fit_rows = np.concatenate([np.arange(s.start, s.stop) for s in split.fit_slices()])
    held_rows = np.concatenate([np.arange(s.start, s.stop) for s in split.held_slices()])
    full = daq.average(runs["all"][0].line, t_start, runs["all"][1], t, fs)
    out = {}
    for c in truth["causes"]:
        sim, fs_int = runs[c]
        d = full - daq.average(sim.line, t_start, fs_int, t, fs)
        out[c] = {part: float(np.sqrt(np.mean(x ** 2)) / sd) if sd > 0 else None
                  for part, x in (("fit", d[fit_rows]), ("val", d[held_rows]))}
    return out


def split_of(held: list, n: int) -> holdout.Split:
    """The tool's split from its held-out blocks ([[start, stop], ...], in
    samples of the record it read: the same n samples make() wrote, or the
    indices would not be this record's)."""
    blocks = tuple((int(a), int(b)) for a, b in held)
    if not blocks or any(not 0 <= a < b <= n for a, b in blocks):
        raise ValueError(f"held-out blocks {held} do not lie within the record's {n} samples")
    return holdout.Split(n, blocks)


def main(argv: list[str]) -> int:
    if len(argv) not in (2, 3) or argv[0] not in CATALOGUE or not argv[1].isdigit() \
            or not 0 <= int(argv[1]) <= SEED_MAX:
        print(f"usage: indep_contributions.py SCENARIO SEED [HELD_OUT] (seed 0..{SEED_MAX}; "
              "HELD_OUT: the tool's JSON record.held_out)", file=sys.stderr)
        return 2
    held = json.loads(argv[2]) if len(argv) == 3 else None
    print(json.dumps(contributions(argv[0], int(argv[1]), held)))
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))

# SPDX-License-Identifier: MIT
"""The reference's whole search (selection.confirm) starts from points that
name every parameter it moves, also when the reference is the model so far,
fitted while a group the test frees was still held (an independent dd
record with a dead band and clipping, indepsim two-backlash-saturation seed
5, ended in KeyError: 'L')."""
from types import SimpleNamespace

import numpy as np

from pneufrac_fit import fit, holdout, model, selection


def test_every_start_names_every_free_group():
    groups = dict(model.nominal_groups("dd"), e0=0.0)
    free = ["K", "L", "tau", "rho", "beta"]
    # the model so far: L held, so its values lack it
    current = SimpleNamespace(groups=groups, values={k: groups[k] for k in free if k != "L"})
    ext = SimpleNamespace(groups=groups, values={k: groups[k] for k in free})
    setup = model.Setup("dd", 1000.0, 3.0)
    pb = fit.Problem(np.zeros(10), np.zeros(10), setup,
                     {g: v for g, v in groups.items() if g not in free}, list(free), split=holdout.Split(10, ()))
    sp = fit.specs(pb, ())
    for label, st in selection.confirm_starts(ext, current, current):
        th = fit.to_theta(sp, st, pb)           # raised KeyError: 'L' before
        assert th.size == len(sp), label

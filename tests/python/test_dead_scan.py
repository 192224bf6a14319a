# SPDX-License-Identifier: MIT
"""The dead-time scan (candidates.scan_dead: one simulation, every delay
from sliding sums) gives the same cost as simulating each delay, with and
without a noise model, with the offset solved or given, with K solved or
carried by saturation."""
import numpy as np
import pytest

import cases
from pneufrac_fit import candidates, data, fit, model, noise


@pytest.mark.parametrize("coloured", [False, True])
@pytest.mark.parametrize("pc0", [None, 0.0])
@pytest.mark.parametrize("effects", [("dead_time",), ("dead_time", "saturation")])
def test_scan_equals_simulation(coloured, pc0, effects):
    ds = cases.make("dd", "dead_time", 3, n=2000)
    rec = data.make_record(ds.t, ds.e, ds.pc)
    pb = fit.Problem.from_record(rec, "dd", {}, 8, 2)
    pb.nm = noise.NoiseModel(np.array([1.0, -0.8, 0.15]), 1.0, 1.0, 100) if coloured else None
    pb.pc0 = pc0
    v = {**model.nominal_groups("dd"), "e0": 0.0}
    if "saturation" in effects:
        v.update(sat_lo=-1.0, sat_hi=1.0, K=0.009)
    scan = dict((d, c) for c, d in candidates.scan_dead(pb, effects, v, 30))
    assert set(scan) == set(range(31))
    for d in (0, 1, 5, 11, 30):
        assert scan[d] == pytest.approx(fit.start_cost(pb, effects, v, d), rel=1e-9)

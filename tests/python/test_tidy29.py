# SPDX-License-Identifier: MIT
"""Review leftovers (branch tidy29): one rule for a rate cut to a whole
factor (model.rate_multiple), used by the simulation's multiple and the
exploration copy's decimation; saturation's placements refined until the
best stays, a placement replacing another only when lower by
search.COST_RTOL."""
from types import SimpleNamespace

import numpy as np
import pytest

from pneufrac_fit import candidates, model, search
from test_speed10 import _problem


# ------------------------------------------ a rate cut to a whole factor
def test_a_10khz_record_on_a_slow_clock_is_explored_as_if_stamped_exactly():
    """A 10 kHz record whose clock runs 1 ppm slow (its stamps read about
    9999.99 Hz) is averaged by 10 to a 1 kHz exploration copy, the copy
    the same record stamped exactly gets; before, by 9 (a 1111 Hz copy)."""
    n = 80000
    exact = _problem(10000.0, n)
    slow = _problem(10000.0, n, t=np.arange(n) / (10000.0 * (1 - 1e-6)))
    assert slow.setup.fs < 10000.0          # the premise: the rate reads low
    qe, qs = search.explorer(exact), search.explorer(slow)
    assert qs.nsim == qe.nsim
    assert qs.setup.fs == pytest.approx(1000.0, rel=2e-6)
    assert qs.setup.oversample == qe.setup.oversample == 2
    assert np.array_equal(qs.y, slow.y[:10 * qs.nsim].reshape(-1, 10).mean(axis=1))


def test_one_rule_cuts_a_rate_either_way():
    """rate_multiple takes a ratio within FS_RTOL of a whole number to it,
    from either side, and leaves any other; both cuts read it."""
    r = model.rate_multiple
    assert r(10.0 * (1 - 1e-6)) == 10 and r(10.0 * (1 + 1e-6)) == 10
    assert r(10.0 * (1 - 1.1 * model.FS_RTOL)) < 10
    assert r(9.5) == 9.5 and r(0.5) == 0.5
    # the simulation's multiple rounds up what is left, the copy's
    # decimation down
    assert model.auto_oversample(2000.0 / 2.5) == 3
    assert model.auto_oversample(999.999) == 2 and model.auto_oversample(1000.001) == 2
    # where two whole factors are within the tolerance (below 15 Hz), the
    # nearer: 7 Hz takes 286 (2002 Hz), not 285 (1995 Hz, review_tidy28 2a)
    assert model.auto_oversample(7.0) == 286
    assert model.auto_oversample(1.0) == 2000 and model.auto_oversample(1.0 * (1 - 1e-5)) == 2000


# ------------------------------------------------ saturation's placements
def _fake(kind, cost, came_from):
    return SimpleNamespace(cost=cost, groups={}, values={"kind": kind, "from": came_from})


def _placements(costs, refined, monkeypatch):
    """fits of three placements at costs[kind], and search.refine replaced
    by refined[(kind, from kind)]: the cost a placement reaches from
    another's optimum (its own fit's cost where missing)."""
    calls = []

    def refine(pk, effects, starts, dead=0, **kw):
        (_, st), = starts
        calls.append((pk.kind, st["kind"]))
        return _fake(pk.kind, refined.get((pk.kind, st["kind"]), costs[pk.kind]), st["kind"])

    monkeypatch.setattr(search, "refine", refine)
    fits = [(_fake(k, c, None), SimpleNamespace(kind=k), k) for k, c in costs.items()]
    out = candidates._from_best_placement(fits, ("saturation",), SimpleNamespace(dead=0))
    return out, calls


def test_a_displaced_best_is_refined_from_the_new_best(monkeypatch):
    """"a" is best from its own search; "b" refined from it overtakes it;
    "a" refined from "b"'s optimum goes lower still and is the best. Before,
    one pass: "a" was never refined from "b" (review_blind5 section 1)."""
    out, calls = _placements({"a": 10.0, "b": 12.0, "c": 11.0},
                             {("b", "a"): 9.0, ("a", "b"): 8.5}, monkeypatch)
    assert ("a", "b") in calls and ("c", "b") in calls
    assert len(calls) == len(set(calls))            # each pair once
    assert [(f[2], f[0].cost) for f in out] == [("a", 8.5), ("b", 9.0), ("c", 11.0)]


def test_a_placement_lower_by_a_tie_does_not_replace_the_best(monkeypatch):
    """Where no limit binds every placement is the same model: the others,
    refined from the best's optimum, run longer and end a hair lower (1e-8
    relative). The best stays; the others keep the refined fit (no longer
    short of the best, so the record does not tell them apart). Before, the
    last refined took the name."""
    tie = 10.0 * (1 - 1e-8)
    out, _ = _placements({"a": 10.0, "b": 10.0, "c": 10.5},
                         {("b", "a"): tie, ("c", "a"): tie}, monkeypatch)
    assert out[0][2] == "a" and out[0][0].values["from"] is None
    assert {f[2]: f[0].values["from"] for f in out[1:]} == {"b": None, "c": "a"}

# SPDX-License-Identifier: MIT
"""A corner of the model without an effect does not decide where the model
with it is searched (issue 8, item 2; candidates.corner_freed): every
candidate also gets a start with the model so far's groups at a bound put
back inside, the others refitted; its gain is still measured against the
model without it refitted with the same freedoms, so a clean record whose
baseline sits in a corner still gives none.

The clean record: the own generator's clean id record of
test_hidden_effects (seed 120), whose baseline ends with w at its bound of
1. The record with an effect: the blind simulator's
two-backlash-lag-pid-5s seed 1 (pid, 5 s, a dead band and a 22 ms lag,
AR(1) noise), whose baseline ends with rho at its bound of 1e4; before
corner_freed its dead band's fit stayed there (cost 10.99, held-out NRMSE
0.42 against the reference's 0.34) and nothing was named; from the start
with rho, tau, q and nu put back inside it reaches cost 10.20 and
predicts the held-out part at 0.10 (docs/analysis-bench.md, "A corner
freed"). It checks the rule where it was traced, not a threshold: no
threshold depends on it.
(The lag is not named on top of the dead band: its fit is no better on
the held-out part.)"""
import copy
import pickle
import sys
import types
from pathlib import Path

import numpy as np
import pytest

import cases
from pneufrac_fit import baseline, candidates, data, diagnose, fit, model, selection
from pneufrac_fit import digest as pneufrac_digest

sys.path.insert(0, str(Path(__file__).resolve().parents[2] / "bench"))
from blindsim.__main__ import write  # noqa: E402


@pytest.fixture(scope="module")
def clean_corner():
    """The diagnosis, the corner-freed starts made (effects, label) and the
    inputs of every refit of the corner (corner_freed's fit.lm_fit), pickled."""
    made, refits = [], []
    orig, orig_lm = candidates.corner_start, fit.lm_fit

    def spy(pb, effects, base, size):
        r = orig(pb, effects, base, size)
        if r is not None:
            made.append((effects, r[0]))
        return r

    def lm_spy(pb, effects, start, dead=0, budget=400, label="", *a, **k):
        if label == candidates.CORNER:
            refits.append(pickle.dumps((pb, effects, start, dead)))
        return orig_lm(pb, effects, start, dead, budget, label, *a, **k)

    candidates.corner_start, fit.lm_fit = spy, lm_spy
    try:
        d = cases.run(cases.make("id", "none", 120), jobs=1)  # the spy sees one process
    finally:
        candidates.corner_start, fit.lm_fit = orig, orig_lm
    return d, made, refits


def test_clean_record_in_a_corner_gives_none(clean_corner):
    d, made, _ = clean_corner
    pbx = selection.problem_for(d.pb, ())
    edges = [e[0] for e in baseline.at_edges(pbx, {**d.baseline.groups, **d.baseline.values})]
    assert edges, "premise: the baseline has a group at a bound"
    tried = {fx[-1] for fx, _ in made if fx}    # round 1: the candidate is the only effect
    assert tried >= {"dead_time", "lag", "saturation", "backlash", "nozzle"}, tried
    assert d.causes == [], d.why


def test_corner_freed_moves_the_corner_groups_inside(clean_corner):
    d, _, _ = clean_corner
    pbx = selection.problem_for(d.pb, ())
    full = {**d.baseline.groups, **d.baseline.values}
    edges = {e[0] for e in baseline.at_edges(pbx, full)}
    start, moved = candidates.corner_freed(pbx, d.baseline)
    assert set(moved) == edges
    # no moved group is left at a bound
    assert not {e[0] for e in baseline.at_edges(pbx, start)} & edges
    # the others were refitted around the moved groups: not the corner's values
    others = [g for g in pbx.free if g in full and g not in moved and g != "e0"]
    assert any(not np.isclose(start[g], full[g], rtol=1e-6) for g in others)
    # a model with no group at a bound gets no such start
    inside = types.SimpleNamespace(groups={g: start[g] for g in d.baseline.groups},
                                   values={k: start[k] for k in d.baseline.values},
                                   effects=(), dead=0)
    assert candidates.corner_freed(pbx, inside) is None


def test_the_corner_is_refitted_once_per_problem(clean_corner):
    """corner_freed depends on the problem and the model so far alone: each
    pair is refitted once (before, every candidate of a round, and each
    confirmation, refitted the same corner again)."""
    _, _, refits = clean_corner
    assert refits, "premise: the corner was refitted"
    assert len(set(refits)) == len(refits), f"{len(refits) - len(set(refits))} repeated"


def test_the_corner_is_the_same_at_every_placement(clean_corner):
    """Without saturation in the model so far, no simulation reads
    saturation's placement: the corner made at the clip's is the one made
    at each other placement (saturation's test asks at all three). This
    record has no exploration copy, so the problem at the placement is
    itself the one simulated."""
    d, _, _ = clean_corner
    pbx = selection.problem_for(d.pb, ())
    assert pbx.setup.sat_kind == model.SAT_CLIP
    want = candidates.corner_freed(pbx, d.baseline)
    assert want is not None, "premise: a corner"
    for kind in (model.SAT_STOP, model.SAT_WIND):
        pk = candidates.with_kind(pbx, kind)
        assert candidates._corner_freed(pk, d.baseline) == want    # made at that placement
        assert candidates.corner_freed(pk, d.baseline) == want


def test_a_dead_band_behind_a_corner_is_found(tmp_path):
    csv, _ = write("two-backlash-lag-pid-5s", 1, tmp_path)    # as the CLI reads it
    d = diagnose.diagnose(data.read_csv(csv), "pid", jobs=2, progress=False)
    assert "rho" in d.corners, "premise: the baseline ends with rho at its bound"
    assert d.causes[:1] == ["backlash"], d.why
    assert set(d.causes) <= {"backlash", "lag"}, d.causes
    # found, not only named: the held-out error at least halfway from the
    # baseline's to the noise floor. (Which start wins, the corner-freed one
    # or the ordinary one, is not asserted: both reach this optimum, and the
    # last bits of the arithmetic decide between them; on a fresh venv,
    # numpy 2.4.6 and scipy 1.17.1, the ordinary start won at every commit
    # back to b4cb4e6, where the corner-freed one had won before.)
    before, after = d.baseline.nrmse_val, d.extended.nrmse_val
    assert before - after >= 0.5 * (before - d.noise_floor_val), (before, after, d.noise_floor_val)


def test_the_corner_key_is_the_same_in_a_worker(clean_corner):
    """A round's workers get the parent's problem and model so far pickled
    (selection.run_round, refit_rivals): the corner the parent made before
    they forked is theirs only if the key is the same on the unpickled
    copy (a digest of the pickle was not: its numpy scalars refer to a
    dtype object that the copy does not share). A problem that differs
    gets another key."""
    d, _, _ = clean_corner
    pbx = selection.problem_for(d.pb, ())
    key = candidates._corner_key(pbx, d.baseline)
    assert candidates._corner_key(*pickle.loads(pickle.dumps((pbx, d.baseline)))) == key
    later = copy.copy(pbx)
    later.burn += 1
    assert candidates._corner_key(later, d.baseline) != key


def test_the_corner_key_names_functions_and_stops_at_cycles():
    """Whatever a problem comes to hold, its digest is made: a function by
    its name (two functions, two digests), an object met inside itself as
    a back reference (no recursion without end)."""
    digest = pneufrac_digest.of

    loop = {"n": 1}
    loop["self"] = loop
    assert digest(loop) != digest({"n": 1, "self": {"n": 1}})
    assert digest({"f": len}) != digest({"f": abs})
    assert digest(np.arange(3.0)) != digest(np.arange(3))

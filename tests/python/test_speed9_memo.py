# SPDX-License-Identifier: MIT
"""Simulations not made twice (branch speed9): a fit's final point is not
simulated again by finish, a stage of the successive halving starts with
the Jacobian its run ended the last stage with, and a whole fit repeated on
equal data is answered from the first. Each must leave every fit bit for
bit as it was."""
import copy
import pickle

import numpy as np

import cases
from pneufrac_fit import data, fit, model, search


def _problem():
    ds = cases.make("p", "lag", 2, n=3000)
    rec = data.make_record(ds.t, ds.e, ds.pc)
    return fit.Problem.from_record(rec, "p", {"q": 0.0, "beta": 1.0}, 8, 2)


def _start(pb, **over):
    return {**model.nominal_groups("p"), "e0": pb.e0_default(), "lag": 0.01, **over}


def _same(a, b):
    assert a.cost == b.cost
    assert np.array_equal(a.theta, b.theta)
    assert a.values == b.values
    assert np.array_equal(a.start_coef, b.start_coef)


def _fresh(monkeypatch, keep=True):
    """keep=False: no whole fit answered from an earlier one at all (none
    from an earlier test in any case: conftest)."""
    if not keep:
        monkeypatch.setattr(fit, "FITS_KEPT", 0)


def _counting(monkeypatch):
    """Points (their values, and the rate multiple they were simulated at:
    a coarse Jacobian's points are another model's) simulated by
    model_output, in call order."""
    seen = []
    orig = fit.model_output

    def counted(pb, effects, vals, *a, **k):
        seen.append(tuple(sorted((k2, v) for k2, v in vals.items()
                                 if k2 not in ("sat_kind", "sat_kind_told")))
                    + (("oversample", k.get("oversample")),))
        return orig(pb, effects, vals, *a, **k)
    monkeypatch.setattr(fit, "model_output", counted)
    return seen


def test_a_fit_does_not_simulate_its_final_point_again(monkeypatch):
    pb = _problem()
    _fresh(monkeypatch)
    seen = _counting(monkeypatch)
    fr = fit.lm_fit(pb, ("lag",), _start(pb), 0, 60, "t")
    assert seen and len(seen) == len(set(seen)), "a point simulated twice"
    # finish from the search's simulation is finish from a fresh one
    sp = fit.specs(pb, ("lag",))
    again = fit.finish(pb, ("lag",), sp, fr.theta, 0, fr.cost, "t")
    _same(fr, again)


def test_halving_stages_reuse_the_last_jacobian(monkeypatch):
    pb = _problem()
    _fresh(monkeypatch, keep=False)
    starts = [("a", _start(pb)), ("b", _start(pb, lag=0.05)), ("c", _start(pb, lag=0.002))]
    seen = _counting(monkeypatch)
    got = search._halving(pb, ("lag",), starts, 0)
    n_memo = len(seen)
    orig = fit.lm_fit
    monkeypatch.setattr(fit, "lm_fit", lambda *a, memo=None, **k: orig(*a, **k))
    seen.clear()
    plain = search._halving(pb, ("lag",), starts, 0)
    _same(got, plain)
    # a run that converged within its stage ended with a Jacobian at its
    # final point, where its next stage starts: those p + 1 points are not
    # simulated again (a run that ran out of budget ended without one; a
    # run whose last Jacobian was made at half the rate, while it still
    # made headway, leaves only its base point: fit.COARSE_DEVIANCE)
    assert n_memo < len(seen)


def test_a_fit_repeated_on_equal_data_is_not_made_again(monkeypatch):
    pb = _problem()
    _fresh(monkeypatch)
    seen = _counting(monkeypatch)
    first = fit.lm_fit(pb, ("lag",), _start(pb), 0, 40, "a")
    n = len(seen)
    assert n > 0
    # an equal copy (as search.explorer makes one per search): no simulation
    again = fit.lm_fit(copy.deepcopy(pb), ("lag",), _start(pb), 0, 40, "b")
    assert len(seen) == n
    _same(first, again)
    assert again.start == "b" and first.start == "a"
    again.values["lag"] = -1.0                   # the caller's own copy
    assert fit.lm_fit(pb, ("lag",), _start(pb), 0, 40, "c").values == first.values
    # another start, budget or data: fitted
    fit.lm_fit(pb, ("lag",), _start(pb, lag=0.02), 0, 40, "d")
    assert len(seen) > n
    n = len(seen)
    fit.lm_fit(pb, ("lag",), _start(pb), 0, 41, "e")
    assert len(seen) > n
    n = len(seen)
    # a sample the fit counts (inside the fit part), a held group, the
    # first sample counted: anything the fit reads
    for change in (lambda q: q.y.__setitem__(q.nsim // 2, q.y[q.nsim // 2] + 1e-9),
                   lambda q: q.fixed.update({"beta": 0.9}),
                   lambda q: setattr(q, "burn", q.burn + 1)):
        other = copy.deepcopy(pb)
        other.y = other.y.copy()
        change(other)
        fit.lm_fit(other, ("lag",), _start(pb), 0, 40, "f")
        assert len(seen) > n
        n = len(seen)


def test_a_fit_made_before_a_worker_forked_is_its_answer_there(monkeypatch):
    """Workers get the problem pickled: the key is of its values, so the
    unpickled copy finds the fit the parent made (a digest of the pickle
    did not: its numpy scalars refer to a dtype object the copy lacks)."""
    pb = _problem()
    _fresh(monkeypatch)
    seen = _counting(monkeypatch)
    fit.lm_fit(pb, ("lag",), _start(pb), 0, 40, "a")
    n = len(seen)
    fit.lm_fit(pickle.loads(pickle.dumps(pb)), ("lag",), _start(pb), 0, 40, "b")
    assert len(seen) == n

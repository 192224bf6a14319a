# SPDX-License-Identifier: MIT
"""The best fit of the same effects among a round's references
(selection.best_same_fit, the baseline's rule): a reference replaces the
model when it fits the model's samples better (BIC); a reference
that is better only on the fewer samples it was fitted to (a dead band's
test does not count the samples before the input's first reversal) is
not (indepsim two-backlash-saturation seed 4: such a reference predicted
the held-out part better, 0.0228 against 0.0332, and fitted the model so
far's samples 15 % worse)."""
import copy
from types import SimpleNamespace

import numpy as np

import cases
from pneufrac_fit import data, fit, model, search, selection


def _problem(size=None):
    ds = cases.make("p", "lag", 3, n=3000, size=size)
    rec = data.make_record(ds.t, ds.e, ds.pc)
    pb = fit.Problem.from_record(rec, "p", {"q": 0.0, "beta": 1.0}, 8, 2)
    pb.burn = 30
    return pb


def _swung(pb, amp):
    """pb with a slow swing of amp times the output's span over the first
    half of its fit part: a disturbance no model of the controller follows."""
    k = np.arange(pb.split.n_fit // 2)
    pb.y = pb.y.copy()
    pb.y[k] += amp * np.ptp(pb.y) * np.sin(np.pi * k / k.size) ** 2
    return pb


def _fit(pb, effects, start, budget=400):
    r = fit.lm_fit(pb, effects, start, 0, budget, "test")
    fit.evaluate(pb, r)
    return r


def _start(pb, **kw):
    return {**model.nominal_groups("p"), "e0": pb.e0_default(), **kw}


def test_a_better_fit_of_the_same_effects_replaces_a_poor_one():
    """A poorly converged lag model, and a test whose reference (lag
    refitted) fits the same samples far better: that fit is returned."""
    pb = _problem()
    lag = model.canonical(("lag",))
    good = _fit(pb, lag, _start(pb, lag=0.01))
    poor = _fit(pb, lag, _start(pb, lag=0.2, L=1e3, rho=2.0, tau=0.2), budget=6)
    assert selection._bic(pb, poor) > selection._bic(pb, good) + 100   # the premise
    assert good.nrmse_val <= poor.nrmse_val
    test = SimpleNamespace(effect="nozzle", ref=good, pb=pb)
    kept, _, src = selection.best_same_fit([test], poor, pb)
    assert kept is not poor and kept.effects == lag and src == "nozzle"
    assert selection._bic(pb, kept) < selection._bic(pb, poor) - selection.SAME_FIT_DBIC


def test_a_fit_better_only_on_fewer_samples_is_not_kept():
    """The linear model fitted on the second half of the fit part beats the
    whole-part fit on that half by far, and loses on the whole part (the
    first half holds a disturbance, a slow swing no model of the
    controller follows, as the slow start of a sweep was where the model
    of the seed-4 record fitted worst): the whole-part fit is kept."""
    pb = _swung(_problem(), 0.2)
    whole = _fit(pb, (), _start(pb))
    late = copy.copy(pb)
    late.burn = pb.split.n_fit // 2
    half = _fit(late, (), {**whole.groups, **whole.values})
    # the premise: on its own samples it is the better fit, clearly
    assert selection._bic(late, half) < selection._bic(late, whole) - 10 * selection.SAME_FIT_DBIC
    test = SimpleNamespace(effect="backlash", ref=half, pb=late)
    kept, kept_pb, src = selection.best_same_fit([test], whole, pb)
    assert kept is whole and kept_pb is pb and src == ""


def test_only_references_of_the_same_effects_count():
    pb = _problem()
    whole = _fit(pb, (), _start(pb))
    other = _fit(pb, model.canonical(("lag",)), {**whole.groups, **whole.values, "lag": 0.01})
    test = SimpleNamespace(effect="nozzle", ref=other, pb=pb)
    assert selection.best_same_fit([test], whole, pb)[0] is whole


# A round's winner against the models without a new effect that the
# round found (selection.models_without, winner_on): each is compared with
# the winner fitted on the same samples. A dead band's test fits its
# reference without the samples before the input's first reversal; a fit
# that leaves out a stretch the model cannot follow predicts the rest of the
# record better for that reason alone, and was compared with the winner
# fitted on every sample (the independent simulator's two-nozzle-lag seed 5,
# nozzle 0.0137 against 0.0131, and two-backlash-saturation seed 1,
# saturation 0.0738 against 0.0703: docs/analysis-bench.md, "A second
# effect refused by a fit on fewer samples"). The record here is the own
# generator's lag record with a slow swing in the first half of its fit
# part.

def test_an_effect_is_compared_with_a_fit_on_fewer_samples_on_those_samples():
    """A lag record whose first half of the fit part holds a slow swing no
    model of the controller follows. The linear model fitted without that
    half (as a dead band's test fits its reference without the samples
    before the first reversal) predicts the held-out part better than the
    lag model fitted on every sample; refitted on the same samples, the
    lag model predicts better than it, and the lag is added."""
    # 0.04 of the span: at 0.035 the lag model's search (with Jacobians at
    # half the rate on its way, fit.COARSE_DEVIANCE) reached a lower cost
    # than it had and predicted the held-out part better than the late
    # half's fit (0.0459 against 0.0480), and the premise failed; at 0.04
    # it holds with a margin of 7 % on either side (0.0480 < 0.0514 <
    # 0.0556), and held with the full rate's Jacobians too
    pb = _swung(_problem(size=10), 0.04)
    whole = _fit(pb, (), {**model.nominal_groups("p"), "e0": pb.e0_default()})
    lag = _fit(pb, ("lag",), {**whole.groups, **whole.values, "lag": 0.01})
    late = copy.copy(pb)
    late.burn = pb.split.n_fit // 2
    half = _fit(late, (), {**whole.groups, **whole.values})
    # the premise: fitted on fewer samples, the model without the lag
    # predicts the held-out part better than the lag model fitted on all
    assert half.nrmse_val < lag.nrmse_val < whole.nrmse_val
    found = SimpleNamespace(effect="lag", passes=True, model=lag, ref=whole, pb=pb)
    play = SimpleNamespace(effect="backlash", passes=False, ref=half, pb=late,
                           model=SimpleNamespace(effects=("backlash",), nrmse_val=1.0))
    on_late = selection.winner_on(found, late.burn)
    assert on_late.effects == ("lag",) and on_late.nrmse_val < half.nrmse_val
    # samples the winner's own test left out stay out
    assert selection.winner_on(found, pb.burn) is lag
    # the whole selection: round 1 finds the two tests, round 2 nothing
    rounds = {"none": [found, play],
              "lag": [SimpleNamespace(effect="nozzle", passes=False, ref=lag, pb=pb,
                                      excludes=False, val_gain=-1.0, val_z=-3.0, reasons=["stub"],
                                      model=SimpleNamespace(effects=("lag", "nozzle"),
                                                            nrmse_val=1.0))]}
    found.excludes, found.val_gain, found.val_z = True, 0.5, 3.0
    play.excludes, play.val_gain, play.val_z = False, -1.0, -3.0
    final = _forward(pb, whole, rounds)
    assert final.effects == ("lag",)


def test_a_fit_on_fewer_samples_that_predicts_worse_is_no_rival(monkeypatch):
    """A reference fitted on fewer samples that predicts the held-out part
    no better than the model so far gained nothing from the samples it
    left out: the winner is not refitted without them and compared with it
    (on an independent record, lag-jitter-5, the lag refitted on fewer
    samples lost to such a reference and a 13 ms lag went unnamed); the
    model so far, fitted on every sample, is the rival."""
    pb = _problem(size=10)
    current = SimpleNamespace(effects=(), nrmse_val=0.07)
    late = copy.copy(pb)
    late.burn = pb.split.n_fit // 2
    worse_ref = SimpleNamespace(effects=(), nrmse_val=0.074)
    lag = SimpleNamespace(effects=("lag",), nrmse_val=0.063)
    found = SimpleNamespace(effect="lag", passes=True, model=lag, ref=current, pb=pb)
    play = SimpleNamespace(effect="backlash", passes=False, ref=worse_ref, pb=late,
                           model=SimpleNamespace(effects=("backlash",), nrmse_val=1.0))
    asked = []
    refit = SimpleNamespace(effects=("lag",), nrmse_val=0.078)   # worse on fewer samples
    monkeypatch.setattr(selection, "winner_on", lambda t, burn: (
        t.model if burn <= t.pb.burn else asked.append(burn) or refit))
    assert selection._passing([found, play], current, pb, 1, lambda m: None) == [found]
    assert late.burn not in asked
    # a reference on fewer samples that predicts better is still a rival
    # (significantly better: _rival_z, tests/python/test_passing33.py)
    play.ref = SimpleNamespace(effects=(), nrmse_val=0.065)
    monkeypatch.setattr(selection, "_rival_z", lambda t, r, w: 3.0)
    assert selection._passing([found, play], current, pb, 1, lambda m: None) == []
    assert late.burn in asked

def _forward(pb, base, rounds):
    """selection.forward with each round's tests given (by the model they
    are tried on), pairs and the backward check left out."""
    import pytest
    mp = pytest.MonkeyPatch()
    try:
        mp.setattr(selection, "run_round",
                   lambda pb, cur, eff, seed, jobs, say, prev: rounds[cur.effect])
        mp.setattr(selection, "refit_rivals", lambda pb, cur, tests, seed, say, jobs=1: tests)
        mp.setattr(selection, "refine_winner", lambda pb, cur, tests, seed, say: tests)
        mp.setattr(selection, "from_better", lambda pb, cur, tests, seed, say: tests)
        mp.setattr(selection, "pairs", lambda *a, **k: None)
        mp.setattr(selection, "pairs_instead", lambda *a, **k: None)
        return selection.forward(pb, base, 0, 1, lambda m: None)[0]
    finally:
        mp.undo()


def test_a_fit_the_library_refuses_fails_its_test(monkeypatch):
    """A candidate whose search reaches a parameter set the library cannot
    design fails its test with that reason; the round, and the diagnosis,
    go on (before, the refusal ended the diagnosis, or, raised in a worker,
    left the process pool waiting)."""
    from pneufrac_fit import candidates, lib
    pb = _problem()
    base = _fit(pb, (), _start(pb))

    def refused(*_a, **_k):
        raise lib.ModelError(1, "nozzle_bias", "refused: nozzle_bias")

    monkeypatch.setattr(candidates, "fit_extended", refused)
    t = selection.try_effect(pb, base, "nozzle", 7)
    assert not t.passes and t.model is base
    assert any("library refused" in r and "nozzle_bias" in r for r in t.reasons), t.reasons

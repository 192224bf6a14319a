# SPDX-License-Identifier: MIT
"""A round's references and winners searched as far as the round got
(branch twofx4): a test whose own fit a better model so far does not
improve still has its reference searched from that better model when the
reference stopped short of it (selection.from_better, _short_of), and
refinement follows the round's winner wherever the round moves it
(selection.refine_final)."""
from types import SimpleNamespace

import numpy as np

from pneufrac_fit import fit, guards, model, search, selection
from test_converge import _fit, _problem, _say, _start
from test_twofx3 import _fake


def _recording(monkeypatch, module, name, into):
    """module.name wrapped: each call's (args, kwargs, result) appended to into."""
    f = getattr(module, name)

    def rec(*a, **kw):
        r = f(*a, **kw)
        into.append((a, kw, r))
        return r
    monkeypatch.setattr(module, name, rec)


def test_a_reference_short_of_the_better_model_so_far_is_searched_from_it(monkeypatch):
    """The lag's own fit is at its optimum (a refit from the better linear
    fit finds nothing better), but its reference is the poorer linear fit:
    from_better tests the lag again, its reference refined from the better
    linear fit ("better prior"), so that the retest's reference fits the
    lag test's samples at least as well as the better linear fit does. The
    lag passes both ways: the retest, judged against the stronger
    reference, is kept, the old reference kept among the models without
    the lag (one-way, _referred_again), and a later retest searches from
    the better fit."""
    pb = _problem()
    poor_lin = _fit(pb, (), _start(pb, rho=3.0), budget=4)
    good_lin = _fit(pb, (), _start(pb))
    lag = _fit(pb, ("lag",), _start(pb, lag=0.05))
    fit.uncertainty(pb, lag)
    t = guards.test(pb, "lag", lag, poor_lin, so_far=poor_lin)
    t.pb = pb
    assert t.passes                     # the premise: from_better considers it
    other = SimpleNamespace(effect="nozzle", ref=good_lin, pb=pb, passes=False,
                            excludes=False, val_gain=0.0, val_z=0.0)
    # the lag's own fit is already at its optimum: the refit returns it
    monkeypatch.setattr(selection, "from_model", lambda pb_, cur, e, fr, src, own, lab: fr)
    refined, retests = [], []
    _recording(monkeypatch, search, "refine", refined)
    _recording(monkeypatch, selection, "try_effect", retests)
    lines = []
    out = selection.from_better(pb, poor_lin, [t, other], 1, _say(lines))
    assert any(lab == "better prior" for a, kw, r in refined for lab, _ in a[2])
    (_, kw, t2), = retests
    assert kw["better"] is not None and kw["better"].effects == ()
    good = fit.start_cost(pb, (), {**good_lin.groups, **good_lin.values})
    assert t2.ref.cost <= good * (1 + 1e-6)
    assert t2.passes and out[0] is t2 and t2.better is kw["better"]
    assert any(m is poor_lin for m in t2.also_without)
    assert any("referred to the better" in m for m in lines)


def _one_way(monkeypatch, t_passes, t2_passes, t2_ref):
    """_referred_again on a lag test whose reference is a poor linear fit,
    the retest faked: it passes or not, with reference t2_ref ("good": the
    better linear fit; "same": as poor as t's). Returns (t, the retest, the
    test after, the models without the effect after, the retests made)."""
    pb = _problem()
    poor_lin = _fit(pb, (), _start(pb, rho=3.0), budget=4)
    good_lin = _fit(pb, (), _start(pb))
    t = guards.Test(effect="lag", model=poor_lin, ref=poor_lin, passes=t_passes)
    t2 = guards.Test(effect="lag", model=poor_lin, passes=t2_passes,
                     ref={"good": good_lin, "same": poor_lin}[t2_ref],
                     reasons=[] if t2_passes else ["fails"])
    t.pb = t2.pb = pb
    made = []
    monkeypatch.setattr(selection, "try_effect", lambda *a, **kw: made.append(1) or t2)
    out = selection._referred_again(pb, poor_lin, [t], 0, good_lin, 1, lambda s: None)
    without = [m for m, _ in selection.models_without(out, poor_lin, pb)]
    return t, t2, out[0], without, made


def test_a_failed_test_is_not_retested(monkeypatch):
    """A test that failed against its reference stays failed, whatever a
    retest against a reference searched from the better model would say:
    the held-out gain and the guards on the fits' difference need not get
    stricter as the reference fits the fit part better."""
    t, t2, after, _, made = _one_way(monkeypatch, False, True, "good")
    assert after is t and not after.passes and not made


def test_a_retest_that_fails_refuses_the_effect(monkeypatch):
    """The effect passes only if it passes the retest too, whatever the
    retest's reference: a failed retest replaces the test, and the old
    reference stays among the models without the effect."""
    for ref in ("same", "good"):
        t, t2, after, without, _ = _one_way(monkeypatch, True, False, ref)
        assert after is t2 and not after.passes
        assert any(m is t.ref for m in without)


def test_a_passing_retest_is_judged_against_the_stronger_reference(monkeypatch):
    """Both pass: the test kept is the one whose reference fits the test's
    samples better (a retest whose reference is no lower keeps the old
    test), and the other reference stays among the models without the
    effect that the winner must beat."""
    t, t2, after, without, _ = _one_way(monkeypatch, True, True, "good")
    assert after is t2 and any(m is t.ref for m in without)
    t, t2, after, without, _ = _one_way(monkeypatch, True, True, "same")
    assert after is t and any(m is t2.ref for m in without)
    assert after.better is not None


def dead_time_fits(pb, start):
    """(the model so far, the better model so far, the effect's fit) with a
    dead time: the dead time fitted at delay 16 and at 4 samples, and a lag
    on top of the first at its delay."""
    def dfit(effects, st, dead):
        r = fit.lm_fit(pb, model.canonical(effects), st, dead, 400, "test")
        fit.evaluate(pb, r)
        return r
    cur = dfit(("dead_time",), start, 16)
    better = dfit(("dead_time",), start, 4)
    fr = dfit(("dead_time", "lag"), {**cur.groups, **cur.values, "lag": 0.01}, 16)
    return cur, better, fr


def test_a_reference_with_a_dead_time_reaches_the_better_model_so_far():
    """With a dead time in the model so far, the better model so far sits
    at another delay (4) than the effect's fit (16): the reference, and the
    confirmation search, refined from it at its own delay fit the samples
    at least as well as it does (at the effect's delay the search stopped
    at a local delay, about 30 % worse: the review of twofx4)."""
    pb = _problem()
    cur, better, fr = dead_time_fits(pb, _start(pb))
    assert better.cost < cur.cost       # the premise: better is better
    cb = fit.start_cost(pb, better.effects, {**better.groups, **better.values}, better.dead)
    ref = selection.reference(pb, ("dead_time",), fr, cur, better)
    assert ref.cost <= cb * (1 + 1e-6)
    fit.uncertainty(pb, fr)
    t = guards.test(pb, "lag", fr, cur, so_far=cur)
    t.pb = pb
    t2 = selection.confirm(pb, "lag", fr, t, cur, np.random.default_rng(1), better)
    assert t2.ref.cost <= cb * (1 + 1e-6)


def test_a_reference_as_good_as_the_better_model_is_left():
    """A reference that fits at least as well as the better model so far is
    not searched again (_short_of)."""
    pb = _problem()
    poor_lin = _fit(pb, (), _start(pb, rho=3.0), budget=4)
    good_lin = _fit(pb, (), _start(pb))
    t = SimpleNamespace(pb=pb, ref=good_lin)
    assert not selection._short_of(t, poor_lin)
    assert selection._short_of(SimpleNamespace(pb=pb, ref=poor_lin), good_lin)
    # fitted on other samples (a later start), its own cost is lower: it
    # is priced on t's samples, not by its own cost
    elsewhere = SimpleNamespace(effects=(), groups=poor_lin.groups, values=poor_lin.values,
                                dead=0, cost=0.0)
    assert not selection._short_of(t, elsewhere)


def _forward(monkeypatch, first, promoted, fails_after_refinement):
    """forward on a faked round: `first` from run_round, `promoted` from
    refit_rivals; refine_winner records the winner it refines and leaves
    it failing when its effect is in fails_after_refinement. Returns (the
    effects refined, in order, the final model)."""
    base = SimpleNamespace(effects=(), effect="none", nrmse_val=1.0)
    refined = []

    def refine_winner(pb, cur, tests, seed, say):
        w = selection._winner(tests)
        if w is None:
            return tests
        refined.append(w.effect)
        if w.effect in fails_after_refinement:
            w2 = _fake(w.effect, w.model.nrmse_val, passes=False)
            tests = [w2 if t is w else t for t in tests]
        return tests

    monkeypatch.setattr(selection, "run_round", lambda pb, cur, eff, seed, jobs, say, prev:
                        list(first) if cur is base else [])
    monkeypatch.setattr(selection, "from_better", lambda pb, cur, tests, seed, say: tests)
    monkeypatch.setattr(selection, "refine_winner", refine_winner)
    monkeypatch.setattr(selection, "refit_rivals", lambda pb, cur, tests, seed, say, jobs=1:
                        [promoted.get(t.effect, t) for t in tests])
    monkeypatch.setattr(selection, "_passing", lambda tests, cur, pb, n, say:
                        [t for t in tests if t.passes])
    monkeypatch.setattr(selection, "pairs", lambda *a: None)
    monkeypatch.setattr(selection, "pairs_instead", lambda *a: None)
    final, _, _, _ = selection.forward(SimpleNamespace(burn=0), base, 0, 1, lambda s: None)
    return refined, final


def test_a_winner_left_by_a_refined_winner_that_fails_is_refined(monkeypatch):
    """The nozzle wins, and refined it fails a guard: the lag, now the
    winner, is refined from its own optimum too before it is added."""
    noz, lag = _fake("nozzle", 0.02), _fake("lag", 0.03)
    refined, final = _forward(monkeypatch, [noz, lag], {}, {"nozzle"})
    assert refined == ["nozzle", "lag"]
    assert final is lag.model


def test_refinement_follows_the_winner_past_a_promoted_one(monkeypatch):
    """refit_rivals refits the lag and the dead time from the refined
    nozzle's optimum, and both now predict better than it; the lag, the
    winner, is refined and fails, and the dead time, never refined, is now
    the winner: it is refined too before it is added."""
    noz, lag, dt = _fake("nozzle", 0.02), _fake("lag", 0.03), _fake("dead_time", 0.025)
    lag2, dt2 = _fake("lag", 0.01), _fake("dead_time", 0.015)
    refined, final = _forward(monkeypatch, [noz, lag, dt], {"lag": lag2, "dead_time": dt2},
                              {"lag"})
    assert refined == ["nozzle", "lag", "dead_time"]
    assert final is dt2.model


def test_a_refined_winner_is_not_refined_again(monkeypatch):
    """The promoted lag fails once refined, and the round goes back to the
    nozzle, which refinement left: it is not refined again."""
    noz, lag = _fake("nozzle", 0.02), _fake("lag", 0.03)
    refined, final = _forward(monkeypatch, [noz, lag], {"lag": _fake("lag", 0.01)}, {"lag"})
    assert refined == ["nozzle", "lag"]
    assert final is noz.model


def test_a_winner_replaced_by_its_refinement_is_refined_once(monkeypatch):
    """Refinement replaces the winner with a test that still passes: that
    test is the one refinement left, and is not refined again (done holds
    the test after refinement, not the one before)."""
    noz = _fake("nozzle", 0.02)
    calls = []

    def refine_winner(pb, cur, tests, seed, say):
        w = selection._winner(tests)
        calls.append(w.effect)
        if w is not noz:        # a refined test: at its optimum, left as it is
            return tests
        w2 = _fake(w.effect, w.model.nrmse_val * 0.9)
        return [w2 if t is w else t for t in tests]
    monkeypatch.setattr(selection, "refine_winner", refine_winner)
    done = []
    out = selection.refine_final(None, None, [noz, _fake("lag", 0.03)], done, 1, lambda s: None)
    assert calls == ["nozzle"] and out[0] is not noz and done == [out[0]]


def test_a_retest_on_a_better_fit_keeps_the_old_reference_among_the_rivals(monkeypatch):
    """_test_again replaces a test by one on a better fit of its model
    (from_better's refit, refit_rivals, refine_winner): the old test's
    reference stays among the models without the effect that the winner
    must beat (models_without), with the references it had before; the
    retest's own reference joins them, none is dropped."""
    pb = _problem()
    poor_lin = _fit(pb, (), _start(pb, rho=3.0), budget=4)
    good_lin = _fit(pb, (), _start(pb))
    older = _fit(pb, (), _start(pb, rho=2.0), budget=4)
    lag = _fit(pb, ("lag",), _start(pb, lag=0.05))
    t = guards.Test(effect="lag", model=SimpleNamespace(cost=2 * lag.cost), ref=poor_lin,
                    passes=True)
    t.also_without = [older]
    t2 = guards.Test(effect="lag", model=lag, ref=good_lin, passes=True)
    t.pb = t2.pb = pb
    current = _fit(pb, (), _start(pb, rho=2.5), budget=4)    # the model so far
    monkeypatch.setattr(selection, "try_effect", lambda *a, **kw: t2)
    out = selection._test_again(pb, current, t, lag, 1)
    assert out is t2
    without = [m for m, _ in selection.models_without([out], current, pb)]
    assert without[0] is current
    for m in (good_lin, older, poor_lin):
        assert sum(w is m for w in without) == 1

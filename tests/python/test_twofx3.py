# SPDX-License-Identifier: MIT
"""A round's later fits searched as its first ones were (branch twofx3):
a winner that refit_rivals promotes is refined from its own optimum as the
first winner was (selection.refine_final), and an effect refitted from
a better fit of the model so far has its reference searched from that
better fit too (selection.from_better, try_effect's `better`)."""
from types import SimpleNamespace

from pneufrac_fit import guards, search, selection
from test_converge import _fit, _problem, _say, _start


def _fake(effect, nrmse, passes=True):
    m = SimpleNamespace(effects=(effect,), effect=effect, nrmse_val=nrmse)
    return SimpleNamespace(effect=effect, model=m, passes=passes, excludes=False,
                           val_gain=0.0, val_z=0.0, pb=SimpleNamespace(burn=0), ref=None)


def test_a_winner_promoted_by_refit_rivals_is_refined(monkeypatch):
    """Round 1: nozzle wins and is refined; refit_rivals then refits the lag
    from the nozzle's optimum and it predicts better: the lag, now the
    winner, is refined from its own optimum too before it is added."""
    noz, lag = _fake("nozzle", 0.02), _fake("lag", 0.03)
    lag2 = _fake("lag", 0.01)
    base = SimpleNamespace(effects=(), effect="none", nrmse_val=1.0)
    winners = []

    def refine_winner(pb, cur, tests, seed, say):
        ok = [t for t in tests if t.passes]
        if ok:
            winners.append(min(ok, key=lambda t: t.model.nrmse_val).effect)
        return tests

    monkeypatch.setattr(selection, "run_round", lambda pb, cur, eff, seed, jobs, say, prev:
                        [noz, lag] if cur is base else [])
    monkeypatch.setattr(selection, "from_better", lambda pb, cur, tests, seed, say: tests)
    monkeypatch.setattr(selection, "refine_winner", refine_winner)
    monkeypatch.setattr(selection, "refit_rivals", lambda pb, cur, tests, seed, say, jobs=1:
                        [noz, lag2])
    monkeypatch.setattr(selection, "_passing", lambda tests, cur, pb, n, say:
                        [t for t in tests if t.passes])
    monkeypatch.setattr(selection, "pairs", lambda *a: None)
    monkeypatch.setattr(selection, "pairs_instead", lambda *a: None)
    final, _, _, _ = selection.forward(SimpleNamespace(burn=0), base, 0, 1, lambda s: None)
    assert final is lag2.model
    assert winners == ["nozzle", "lag"]


def test_refine_final_refines_only_a_new_winner():
    """A passing lag fit that stopped short (a few iterations from a poor
    start) is refined when it is the winner and refine_winner did not leave
    it so; when it is the test refine_winner left, nothing is done."""
    pb = _problem()
    base = _fit(pb, (), _start(pb))
    poor = _fit(pb, ("lag",), _start(pb, lag=0.05), budget=12)
    t = selection.try_effect(pb, base, "lag", 1, fitted=poor)
    assert t.passes                           # the premise: a winner short of its optimum
    first = _fake("nozzle", 1.0)              # the first winner, now predicting worse
    lines = []
    out = selection.refine_final(pb, base, [first, t], [first], 1, _say(lines))
    assert out[0] is first and out[1] is not t
    assert out[1].model.cost < poor.cost * (1 - 1e-6)
    assert any("refined from its own optimum" in m for m in lines)
    same = [first, t]
    assert selection.refine_final(pb, base, same, [t], 1, _say([])) is same


def test_a_refit_from_a_better_model_so_far_is_referred_to_it(monkeypatch):
    """from_better refits the lag from a better linear fit than the model
    so far: the retest's reference is searched from that better fit too,
    so it fits the fit part at least as well as the better fit does (a
    reference left short of it would credit the lag with the better fit's
    gain)."""
    pb = _problem()
    poor_lin = _fit(pb, (), _start(pb, rho=3.0), budget=4)
    good_lin = _fit(pb, (), _start(pb))
    poor_lag = _fit(pb, ("lag",), {**poor_lin.groups, **poor_lin.values, "lag": 0.05},
                    budget=12)
    t = selection.try_effect(pb, poor_lin, "lag", 1, fitted=poor_lag)
    other = SimpleNamespace(effect="nozzle", ref=good_lin, pb=pb, passes=False,
                            excludes=False, val_gain=0.0, val_z=0.0)
    seen = []
    real = selection.reference

    def spy(pb_, effects, fr, prior, better=None):
        seen.append(better)
        return real(pb_, effects, fr, prior, better)

    monkeypatch.setattr(selection, "reference", spy)
    out = selection.from_better(pb, poor_lin, [t, other], 1, _say([]))
    assert out[0] is not t
    assert seen and all(m is not None and m.effects == () for m in seen)
    assert out[0].ref.cost <= seen[0].cost * (1 + 1e-9)
    assert out[0].better is seen[0]         # kept for the test's later retests


def test_a_retest_keeps_the_better_model_so_far(monkeypatch):
    """A test from_better made is tested again later (refine_winner,
    refit_rivals, refine_final) without being told the better model so
    far: its retest's reference is searched from it all the same."""
    better = SimpleNamespace(cost=0.1)
    t = guards.Test("lag", SimpleNamespace(cost=1.0), None, better=better)
    seen = []

    def try_effect(pb, cur, effect, seed, hint=None, fitted=None, better=None):
        seen.append(better)
        return SimpleNamespace(model=fitted, ref=None)     # as try_effect: a reference

    monkeypatch.setattr(selection, "try_effect", try_effect)
    assert selection._test_again(None, None, t, SimpleNamespace(cost=0.5), 1) is not None
    assert seen == [better]


def test_a_better_start_does_not_displace_a_deeper_optimum(monkeypatch):
    """The reference's search goes on from its best start by start cost
    only. A better model so far that starts lowest but ends in a shallower
    optimum than another start reaches must not leave the reference above
    what it was without it (that would favour the effect)."""
    start_cost = {"from extended": 3.0, "prior": 4.0, "better prior": 1.0}
    end_cost = {"from extended": 0.5, "prior": 0.7, "better prior": 0.9}

    def refine(pb, effects, starts, dead=0, iters=search.REFINE_ITER):
        lab = min(starts, key=lambda s: start_cost[s[0]])[0]
        return SimpleNamespace(cost=end_cost[lab], start=lab)

    monkeypatch.setattr(search, "refine", refine)
    fr = SimpleNamespace(dead=0, values={})
    prior = better = SimpleNamespace(groups={}, values={})
    r = selection.reference(None, (), fr, prior, better)
    assert r.cost == 0.5 and r.start == "from extended"

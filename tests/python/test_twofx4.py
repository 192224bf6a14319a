# SPDX-License-Identifier: MIT
"""A round's references and winners searched as far as the round got
(branch twofx4): a test whose own fit a better model so far does not
improve still has its reference searched from that better model when the
reference stopped short of it (selection.from_better, _short_of), and
refinement follows the round's winner wherever the round moves it
(selection.refine_final)."""
from types import SimpleNamespace

from pneufrac_fit import fit, guards, selection
from test_converge import _fit, _problem, _say, _start
from test_twofx3 import _fake


def test_a_reference_short_of_the_better_model_so_far_is_searched_from_it(monkeypatch):
    """The lag's own fit is at its optimum (a refit from the better linear
    fit finds nothing better), but its reference is the poorer linear fit:
    from_better tests the lag again, its reference searched from the better
    linear fit, so that the reference fits the lag test's samples at least
    as well as the better linear fit does."""
    pb = _problem()
    poor_lin = _fit(pb, (), _start(pb, rho=3.0), budget=4)
    good_lin = _fit(pb, (), _start(pb))
    lag = _fit(pb, ("lag",), _start(pb, lag=0.05))
    fit.uncertainty(pb, lag)
    t = guards.test(pb, "lag", lag, poor_lin, so_far=poor_lin)
    t.pb = pb
    assert selection.explains(t)        # the premise: from_better considers it
    other = SimpleNamespace(effect="nozzle", ref=good_lin, pb=pb, passes=False,
                            excludes=False, val_gain=0.0)
    # the lag's own fit is already at its optimum: the refit returns it
    monkeypatch.setattr(selection, "from_model", lambda pb_, cur, e, fr, src, own, lab: fr)
    lines = []
    out = selection.from_better(pb, poor_lin, [t, other], 1, _say(lines))
    assert out[0] is not t and out[0].model is lag
    good = fit.start_cost(pb, (), {**good_lin.groups, **good_lin.values})
    assert out[0].ref.cost <= good * (1 + 1e-6)
    assert out[0].better is not None and out[0].better.effects == ()
    assert any("referred to the better" in m for m in lines)


def test_a_reference_as_good_as_the_better_model_is_left():
    """A reference that fits at least as well as the better model so far is
    not searched again (_short_of)."""
    pb = _problem()
    poor_lin = _fit(pb, (), _start(pb, rho=3.0), budget=4)
    good_lin = _fit(pb, (), _start(pb))
    t = SimpleNamespace(pb=pb, ref=good_lin)
    assert not selection._short_of(t, poor_lin)
    assert selection._short_of(SimpleNamespace(pb=pb, ref=poor_lin), good_lin)


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

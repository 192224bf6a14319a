# SPDX-License-Identifier: MIT
"""Two effects that explain the same feature of a record equally well are
not named (selection.forward with guards.indistinguishable): the held-out
comparison itself, and the forward selection's decision on stub rounds (no
fits: the rule is about what is done with the guards' verdicts)."""
from types import SimpleNamespace

import numpy as np

from pneufrac_fit import guards, noise, selection

N_FIT, N_VAL = 400, 3000


def _test(effect, resid, passes=True, nrmse=0.1, k=9):
    """A guards.Test stand-in whose model has the given residual."""
    fr = SimpleNamespace(effects=(effect,), effect=effect, nrmse_val=nrmse, k=k,
                         residual=lambda pb, r=resid: r)
    return SimpleNamespace(effect=effect, model=fr, passes=passes,
                           nm=noise.fit(np.zeros(0)), pb=SimpleNamespace(nfit=N_FIT, burn=0))


def _residuals(scale_b, seed=1):
    rng = np.random.default_rng(seed)
    a = rng.normal(0.0, 1.0, N_FIT + N_VAL)
    return a, scale_b * rng.normal(0.0, 1.0, N_FIT + N_VAL)


def test_equal_errors_are_indistinguishable():
    ra, rb = _residuals(1.0)
    assert guards.indistinguishable(_test("nozzle", ra), _test("lag", rb))


def test_clearly_better_everywhere_is_distinguishable():
    ra, rb = _residuals(1.5)       # b's error 2.25x a's in variance, fit and held-out
    assert not guards.indistinguishable(_test("nozzle", ra), _test("lag", rb))


def test_better_on_the_fit_part_only_is_not_enough():
    ra, rb = _residuals(1.0)
    rb[:N_FIT] *= 1.5              # b worse on the fit part only
    rb[N_FIT:] = ra[N_FIT:] * 0.999   # and a hair better held-out
    assert guards.indistinguishable(_test("nozzle", ra), _test("lag", rb))


def test_extra_parameters_must_pay_for_themselves():
    ra, rb = _residuals(1.5)
    # fit part: b's whitened RSS 1.0404x a's, BIC -15.8 for a with equal
    # parameter counts; one more parameter costs log(400) = 6.0
    rb[:N_FIT] = ra[:N_FIT] * 1.02
    assert not guards.indistinguishable(_test("nozzle", ra, k=9), _test("lag", rb, k=9))
    assert guards.indistinguishable(_test("nozzle", ra, k=10), _test("lag", rb, k=9))


def _forward_with(scale_b, on_top, monkeypatch):
    """selection.forward over scripted rounds: round 1 on the baseline gives
    nozzle (residual a) and lag (residual b, scale_b times a's scale), both
    passing, nozzle the lower held-out NRMSE; `on_top` maps each later
    model's effect name to the tests a round on top of it gives."""
    ra, rb = _residuals(scale_b)
    first = [_test("lag", rb, nrmse=0.0184 * scale_b), _test("nozzle", ra, nrmse=0.0183)]
    rounds = {"none": first, **{k: f(ra) for k, f in on_top.items()}}
    monkeypatch.setattr(selection, "run_round",
                        lambda pb, cur, eff, seed, jobs, say, prev: rounds[cur.effect])
    monkeypatch.setattr(selection, "backward", lambda pb, fr, say: (fr, pb, []))
    base = SimpleNamespace(effects=(), effect="none")
    notes = []
    final, _, _, _ = selection.forward("pb", base, 0, 1, lambda s: None, notes)
    return final, notes


def _lag_fails_on_top(ra):
    return [_test("lag", ra, passes=False)]


def _lag_passes_on_top(ra):
    both = _test("lag", ra, nrmse=0.015)
    both.model.effects, both.model.effect = ("lag", "nozzle"), "lag+nozzle"
    return [both]


def test_rival_that_adds_nothing_on_top_leaves_neither_named(monkeypatch):
    final, notes = _forward_with(1.0, {"nozzle": _lag_fails_on_top}, monkeypatch)
    assert final.effect == "none"
    assert len(notes) == 1 and "nozzle" in notes[0] and "lag" in notes[0]


def test_rival_that_passes_on_top_keeps_both_in_play(monkeypatch):
    final, notes = _forward_with(1.0, {"nozzle": _lag_passes_on_top,
                                       "lag+nozzle": lambda ra: []}, monkeypatch)
    assert final.effects == ("lag", "nozzle") and notes == []


def test_clearly_better_winner_is_kept(monkeypatch):
    final, notes = _forward_with(1.5, {"nozzle": _lag_fails_on_top}, monkeypatch)
    assert final.effect == "nozzle" and notes == []

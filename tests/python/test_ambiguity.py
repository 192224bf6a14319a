# SPDX-License-Identifier: MIT
"""Two explanations the record cannot tell apart are not named
(selection.forward with guards.distinguishable): the comparison itself (the
J tests on the held-out part, and Vuong's log-likelihood-difference test
over the whole record, its long-run variance from Newey-West weights), their
calibration, the lack-of-fit test that
lets pairs be tried, and the forward selection's decision on stub rounds
(no fits: the rule is about what is done with the guards' verdicts)."""
import math
from types import SimpleNamespace

import numpy as np
import pytest
from scipy.signal import lfilter

from pneufrac_fit import guards, holdout, model, noise, selection

N_FIT, N_VAL = 2000, 3000
TAIL = holdout.Split(N_FIT + N_VAL, ((N_FIT, N_FIT + N_VAL),))   # fit, then held out


def _test(effect, resid, passes=True, nrmse=0.1, k=9, explains=True):
    """A guards.Test stand-in whose model has the given residual."""
    fr = SimpleNamespace(effects=(effect,), effect=effect, nrmse_val=nrmse, k=k,
                         residual=lambda pb, r=resid: r)
    ref = SimpleNamespace(effects=(), nrmse_val=1.0)      # the linear model, far worse
    return SimpleNamespace(effect=effect, model=fr, ref=ref, passes=passes, excludes=explains,
                           val_gain=0.1 if explains else -0.1, val_z=3.0 if explains else -3.0,
                           nm=noise.fit(np.zeros(0)), pb=SimpleNamespace(split=TAIL, burn=0))


def _residuals(scale_b, seed=1):
    rng = np.random.default_rng(seed)
    a = rng.normal(0.0, 1.0, N_FIT + N_VAL)
    return a, scale_b * rng.normal(0.0, 1.0, N_FIT + N_VAL)


def test_equal_errors_are_indistinguishable():
    ra, rb = _residuals(1.0)
    assert not guards.distinguishable(_test("nozzle", ra), _test("lag", rb))


def test_clearly_better_everywhere_is_distinguishable():
    ra, rb = _residuals(1.5)       # b's error 2.25x a's in variance, fit and held-out
    assert guards.distinguishable(_test("nozzle", ra), _test("lag", rb))
    assert not guards.distinguishable(_test("lag", rb), _test("nozzle", ra))


def test_better_on_the_fit_part_only_is_not_enough():
    """An advantage the fit bought on its own samples and loses held-out
    (overfitting) is no evidence: the whole record's sum cancels it."""
    ra, _ = _residuals(1.0)
    rb = ra.copy()
    rb[:N_FIT] *= 1.1              # b worse on the fit part, a as much worse held-out
    ra[N_FIT:] *= 1.1 ** (N_FIT / N_VAL)
    assert not guards.distinguishable(_test("nozzle", ra), _test("lag", rb))


def _half_t(ra, rb, part):
    """The t statistic on one part only (the rule before: each part on its own)."""
    a, b = ra.copy(), rb.copy()
    if part == "fit":
        b[N_FIT:] = a[N_FIT:]
    else:
        b[:N_FIT] = a[:N_FIT]
    return guards.better(_test("nozzle", a), _test("lag", b), noise.fit(np.zeros(0)))


def test_a_small_advantage_over_the_whole_record_is_evidence():
    """b's error a little larger everywhere: too little on either part alone,
    enough over the whole record (the one test pools both parts)."""
    ra, rb = _residuals(1.0, seed=3)
    rb = ra + 0.035 * rb
    assert _half_t(ra, rb, "fit") < guards.Z_DIFFERENT
    assert _half_t(ra, rb, "val") < guards.Z_DIFFERENT
    assert guards.distinguishable(_test("nozzle", ra), _test("lag", rb))


def test_an_advantage_in_one_stretch_is_one_piece_of_evidence():
    """Neither model explains the record (each misses a step's response,
    a by -2 and b by +8 noise sd, in one burst of 30 samples in each part:
    the J tests reject both): b's far larger misfit rests on one stretch,
    and Vuong's long-run variance says so. The same burst at every 100th
    sample is many pieces."""
    ra, _ = _residuals(1.0)
    rb = ra.copy()
    for k in (500, N_FIT + 500):
        rb[k:k + 30] += 8.0
        ra[k:k + 30] -= 2.0
    a, b = _test("nozzle", ra), _test("lag", rb)
    assert guards.rejects(a, b, a.nm) == (True, True)
    assert not guards.distinguishable(a, b)
    ra, _ = _residuals(1.0)
    rb = ra.copy()
    for k in range(0, N_FIT + N_VAL - 30, 100):
        rb[k:k + 3] += 8.0
        ra[k:k + 3] -= 2.0
    assert guards.distinguishable(_test("nozzle", ra), _test("lag", rb))


def test_extra_parameters_must_pay_for_themselves():
    """In Vuong's comparison, which counts the fit part (the J tests use
    the held-out part, where no parameter was fitted to the noise)."""
    ra, rb = _residuals(1.0)
    rb = ra * 1.02                 # a a little better everywhere
    nm = noise.fit(np.zeros(0))
    t = guards.better(_test("nozzle", ra, k=9), _test("lag", rb, k=9), nm)
    assert t > guards.Z_DIFFERENT
    # 40 more parameters cost 40 ln(2000)/2 = 152 log-likelihood units
    t49 = guards.better(_test("nozzle", ra, k=49), _test("lag", rb, k=9), nm)
    assert t49 < guards.Z_DIFFERENT < t


@pytest.mark.parametrize("pole", [0.0, 0.9])
def test_hac_t_holds_its_level_under_correlation(pole):
    """Under 'no difference' |t| of the long-run-variance t exceeds
    Z_DIFFERENT (two-sided 95 %) in about 5 % of records, white or strongly correlated (AR(1),
    pole 0.9: a naive iid variance would be 19x too small and the rate
    far above 5 %)."""
    rng = np.random.default_rng(7)
    hits = 0
    reps = 600
    for _ in range(reps):
        d = lfilter([1.0], [1.0, -pole], rng.normal(size=3000))
        hits += abs(guards.hac_t(d)) > guards.Z_DIFFERENT
    assert 0.02 < hits / reps < 0.09


def _events(rng, n, lo=-0.5, hi=2.5, count=25):
    """A misfit in the response to each of `count` input steps, of sizes
    log-uniform over 10^lo..10^hi (unequal events: a nozzle's curvature
    shows most at the largest excursions)."""
    out = np.zeros(n)
    decay = np.exp(-np.arange(150) / 30.0)
    for k, size in zip(range(50, n - 150, n // count), 10 ** rng.uniform(lo, hi, count)):
        out[k:k + 150] += size * decay
    return out


def test_a_model_at_the_noise_is_told_from_one_that_misses_every_event():
    """a's residual is the noise; b's misses the response to each of 25
    steps, by amounts that differ up to 1000x. Vuong's sum is dominated by
    the largest events and so is its long-run variance (it falls under
    1.96 on some of these records); the J test is not: b's residual lies
    along the difference of the two models, a's does not."""
    n = N_FIT + N_VAL
    weak = 0
    for seed in range(11, 21):
        rng = np.random.default_rng(seed)
        ra = rng.normal(size=n)
        rb = ra + _events(rng, n)
        a, b = _test("nozzle", ra), _test("lag", rb)
        weak += guards.better(a, b, a.nm) < guards.Z_DIFFERENT
        assert guards.distinguishable(a, b), seed
        assert not guards.distinguishable(b, a), seed
    assert weak >= 1        # the records where Vuong alone would not tell


@pytest.mark.parametrize("pole", [0.0, 0.5])
def test_the_j_test_holds_its_level(pole):
    """If b is the explanation its whitened residual is the noise, and the
    J test rejects it in favour of a wrong model a (b's residual plus a
    misfit at every step) in at most 2.5 % of records (one-sided), with
    white noise or noise the noise model left slightly coloured (AR(1),
    pole 0.5: the long-run variance covers it)."""
    rng = np.random.default_rng(3)
    n = N_FIT + N_VAL
    miss = _events(np.random.default_rng(4), n, -1.0, 0.5)
    hits, reps = 0, 600
    for _ in range(reps):
        rb = lfilter([1.0], [1.0, -pole], rng.normal(size=n)) * math.sqrt(1 - pole * pole)
        a, b = _test("nozzle", rb + miss), _test("lag", rb)
        hits += guards.rejects(a, b, a.nm)[0]
    assert 0.002 < hits / reps < 0.05


def test_when_both_are_rejected_vuong_decides():
    """Neither model alone explains the record (each misses what the other
    explains, at different steps: two effects at once): the J tests reject
    both, and a is named over b only if it explains the whole record
    significantly better (Vuong): not when their misses are alike, yes
    when a's are 0.4 of b's."""
    rng = np.random.default_rng(8)
    n = N_FIT + N_VAL
    noise_ = rng.normal(size=n)
    one = _events(np.random.default_rng(9), n, 0.0, 0.5)
    other = np.roll(_events(np.random.default_rng(10), n, 0.0, 0.5), 75)
    for scale, told in ((1.0, False), (0.4, True)):
        a, b = _test("nozzle", noise_ + scale * one), _test("lag", noise_ + other)
        assert guards.rejects(a, b, a.nm) == (True, True)
        assert guards.distinguishable(a, b) is told
        assert (guards.better(a, b, a.nm) > guards.Z_DIFFERENT) is told
        assert not guards.distinguishable(b, a)


def _lof_case(resid, e):
    pb = SimpleNamespace(nm=None, burn=10, fit_pieces=lambda r: [r[10:]], e_abs=e)
    return guards.inadequate(pb, SimpleNamespace(residual=lambda _pb: resid))


def test_lack_of_fit_needs_a_residual_that_depends_on_the_input():
    rng = np.random.default_rng(3)
    n = 5000
    e = np.repeat(rng.choice([-1.0, 1.0], n // 100), 100)    # steps every 0.1 s
    coloured = lfilter([1.0], [1.0, -0.95], rng.normal(0, 0.01, n))
    assert not _lof_case(coloured, e)[0]          # coloured noise alone: adequate
    missed = 0.1 * lfilter([0.1], [1.0, -0.9], np.diff(e, prepend=e[0]))
    assert _lof_case(coloured + missed, e)[0]     # a response to the input left over


def _forward_with(scale_b, on_top, monkeypatch, ref_lag=1.0):
    """selection.forward over scripted rounds: round 1 on the baseline gives
    nozzle (residual a) and lag (residual b, scale_b times a's scale), both
    passing, nozzle the lower held-out NRMSE; `on_top` maps each later
    model's effect name to the tests a round on top of it gives."""
    ra, rb = _residuals(scale_b)
    first = [_test("lag", rb, nrmse=0.0184 * scale_b), _test("nozzle", ra, nrmse=0.0183)]
    first[0].ref.nrmse_val = ref_lag
    rounds = {"none": first, **{k: f(ra) for k, f in on_top.items()}}
    script_rounds(monkeypatch, rounds)
    monkeypatch.setattr(selection, "pairs", lambda *a: None)
    monkeypatch.setattr(selection, "pairs_instead", lambda *a: None)
    base = SimpleNamespace(effects=(), effect="none", nrmse_val=1.0)
    notes = []
    # every scripted test counts the same samples as the model so far
    final, _, _, _ = selection.forward(SimpleNamespace(burn=0), base, 0, 1, lambda s: None,
                                       notes)
    return final, notes


def script_rounds(monkeypatch, rounds):
    """selection.forward over scripted rounds: rounds maps the model so
    far's effect name to its round's tests; the scripted fits are the
    rounds' last word (no backward step, no refit from a rival's optimum,
    no refinement of the winner)."""
    monkeypatch.setattr(selection, "run_round",
                        lambda pb, cur, eff, seed, jobs, say, prev: rounds[cur.effect])
    monkeypatch.setattr(selection, "backward", lambda pb, fr, say: (fr, pb, []))
    monkeypatch.setattr(selection, "refit_rivals", lambda pb, cur, tests, seed, say, jobs=1: tests)
    monkeypatch.setattr(selection, "refine_winner", lambda pb, cur, tests, seed, say: tests)
    monkeypatch.setattr(selection, "from_better", lambda pb, cur, tests, seed, say: tests)


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


def test_no_effect_when_the_model_without_one_predicts_as_well(monkeypatch):
    """A test's reference (no new effect, refitted with that test's
    freedoms) predicts the held-out part better than the winner,
    significantly (selection._rival_z; test_passing33): the winner's gain
    is the freedoms', and nothing is added."""
    monkeypatch.setattr(selection, "_rival_z", lambda t, r, w: 3.0)
    final, notes = _forward_with(1.5, {"nozzle": _lag_fails_on_top}, monkeypatch,
                                 ref_lag=0.015)
    assert final.effect == "none"


def _pairs_with(monkeypatch, inadequate, passing, scales, worse_alone=()):
    """selection.pairs over stub fits: three effects explain part of the
    residual; the pair fits' residuals are a common noise scaled by
    scales[pair]; members of the pairs in `passing` pass their guards."""
    rng = np.random.default_rng(5)
    noise_ = rng.normal(0.0, 1.0, N_FIT + N_VAL)
    tests = [_test(e, noise_) for e in ("dead_time", "lag", "saturation")]
    for t in tests:
        t.model.groups, t.model.values, t.model.dead = {}, {}, 0
        t.peak = 0.0
        if t.effect in worse_alone:      # significant, but predicts worse alone
            t.val_gain = -0.1
    monkeypatch.setattr(guards, "inadequate", lambda pb, fr: (inadequate, 9.0))
    monkeypatch.setattr(selection, "problem_for", lambda pb, eff: pb)
    monkeypatch.setattr(selection.fit, "uncertainty", lambda pb, fr: None)

    def extended(pb, base, new, rng_, hint=None):
        effects = model.canonical(base.effects + (new,))
        key = "+".join(effects)
        r = noise_ * scales[key] + rng.normal(0.0, 0.01, noise_.size)
        return SimpleNamespace(effects=effects, nrmse_val=scales[key], k=10, cost=scales[key],
                               residual=lambda _pb, r=r: r)

    def test(pb, effect, fr, ref, so_far=None):
        key = "+".join(fr.effects)
        t = _test(effect, fr.residual(pb), passes=key in passing)
        t.model, t.reasons = fr, [] if t.passes else ["stub: fails"]
        return t

    monkeypatch.setattr(selection.candidates, "fit_extended", extended)
    monkeypatch.setattr(selection, "reference", lambda pb, eff, fr, prior: prior)
    monkeypatch.setattr(guards, "test", test)
    current = SimpleNamespace(effects=(), effect="none", dead=0)
    notes, sets = [], []
    got = selection.pairs(SimpleNamespace(split=TAIL, burn=0), current, tests,
                          lambda s: None, notes, sets)
    return got, notes, sets


ALL_EQUAL = {"dead_time+lag": 1.0, "dead_time+saturation": 1.0, "lag+saturation": 1.0}


def test_pairs_only_when_the_model_is_inadequate(monkeypatch):
    got, _, _ = _pairs_with(monkeypatch, False, {"dead_time+saturation"}, ALL_EQUAL)
    assert got is None


def test_a_pair_whose_members_pass_and_that_stands_out_is_added(monkeypatch):
    scales = {"dead_time+lag": 1.5, "dead_time+saturation": 1.0, "lag+saturation": 1.5}
    got, notes, _ = _pairs_with(monkeypatch, True, {"dead_time+saturation"}, scales)
    assert got is not None and got[0].effects == ("dead_time", "saturation") and notes == []


def test_a_pair_the_record_cannot_tell_from_another_is_not_added(monkeypatch):
    got, notes, sets = _pairs_with(monkeypatch, True, {"dead_time+saturation"}, ALL_EQUAL)
    assert got is None
    assert sets and sets[0][0] == "dead_time+saturation" and "cannot tell" in notes[0]


def test_no_pair_whose_member_fails_is_added(monkeypatch):
    scales = {"dead_time+lag": 1.5, "dead_time+saturation": 1.0, "lag+saturation": 1.5}
    got, _, _ = _pairs_with(monkeypatch, True, set(), scales)
    assert got is None


def test_a_member_that_predicts_worse_alone_is_still_paired(monkeypatch):
    """Fitted alone, half of a pair imitates the other half and can predict
    the held-out part worse; significant on the fit part, it is still a
    member to try (its guards in the pair include the held-out one)."""
    scales = {"dead_time+lag": 1.5, "dead_time+saturation": 1.0, "lag+saturation": 1.5}
    got, notes, _ = _pairs_with(monkeypatch, True, {"dead_time+saturation"}, scales,
                                worse_alone=("dead_time",))
    assert got is not None and got[0].effects == ("dead_time", "saturation") and notes == []


def test_evidence_that_contradicts_itself_names_neither():
    """The held-out part rejects b and not a (a at the noise there, b
    missing a little), but over the whole record b is significantly more
    likely (a misses much more on the fit part): the record says
    opposite things, and neither is named over the other. Without the fit
    part's misses a is named (the J test alone decides then)."""
    rng = np.random.default_rng(11)
    n = N_FIT + N_VAL
    noise_ = rng.normal(size=n)
    held = np.zeros(n)
    held[N_FIT:] = 0.3 * _events(np.random.default_rng(12), n, 0.0, 0.3)[N_FIT:]
    fit_miss = np.zeros(n)
    fit_miss[:N_FIT] = 3.0 * _events(np.random.default_rng(13), n, 0.0, 0.3)[:N_FIT]
    b = _test("lag", noise_ + held)
    a_told = _test("dead_time", noise_)
    a = _test("dead_time", noise_ + fit_miss)
    assert guards.rejects(a, b, a.nm) == (True, False)
    assert guards.better(b, a, a.nm) > guards.Z_DIFFERENT
    assert not guards.distinguishable(a, b)
    assert not guards.distinguishable(b, a)
    assert guards.distinguishable(a_told, b)

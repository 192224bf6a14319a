# SPDX-License-Identifier: MIT
"""The held-out split that covers the input's levels as the default
(holdout.DEFAULT "cover"), what made it possible (the start at the paper's
values explored on its own beside a corner: candidates._apart), and the
coverage margin from the noise's level sd, not its sample-to-sample sd
(data.level_sd)."""
import numpy as np
import pytest
from scipy.signal import lfilter

import cases
from pneufrac_fit import candidates, data, holdout, signals

N, FS = 6000, 1000.0


def test_the_default_is_cover():
    """A record whose tail goes below every level of its first 70 % is
    validated on the held-out blocks without asking; one whose tail is
    covered keeps the tail, silently."""
    rng = np.random.default_rng(1)
    for levels, blocks in (([0, 1, -1, 0.5, -0.5, 1, 0, -2.0, -2.0, 0.5], True),
                           ([0, 1, -1, 0.5, -0.5, 1, 0, -1, 0.5, -0.5], False)):
        e = np.repeat(np.asarray(levels, float), N // len(levels))
        e = e + 1e-3 * rng.normal(size=N)
        pc = 0.1 + 0.02 * e + 1e-3 * rng.normal(size=N)
        rec = data.make_record(np.arange(N) / FS, e, pc, "default")
        split, why = data.split_for(rec)
        assert split == holdout.layout(N, "blocks" if blocks else "tail")
        assert (why is not None and "held-out tail refused" in why) == blocks


def _ar1(phi, n, seed, sd=1e-3):
    return lfilter([1.0], [1.0, -phi], sd * np.random.default_rng(seed).normal(size=n))


def test_level_sd_is_the_slow_noise_level_spread_not_its_sample_to_sample_sd():
    """AR(1) noise of pole 0.95 on constant levels: its process sd is 3.2x
    its innovations', its sample-to-sample sd (second differences) 0.6x:
    the level sd is the process sd (within 20 %); for white noise the two
    agree."""
    cuts = np.array([2000, 4000])
    lv = np.repeat([0.0, 1.0, -1.0], 2000)
    x = lv + _ar1(0.95, N, 4)
    proc = 1e-3 / np.sqrt(1 - 0.95 ** 2)
    sig = signals.noise_sd(x)
    assert sig < 0.3 * proc                                          # the premise
    assert abs(data.level_sd(x, data.rest_windows(x, cuts), sig) / proc - 1) < 0.2
    w = lv + 1e-3 * np.random.default_rng(5).normal(size=N)
    assert abs(data.level_sd(w, data.rest_windows(w, cuts), signals.noise_sd(w)) / 1e-3 - 1) < 0.1


def test_slow_noise_on_covered_levels_is_not_a_new_level():
    """Every tail level was held by the first 70 % (test_split29's
    levels-covered record); the input's noise is AR(1) of pole 0.995. Its
    wander puts 18 % of the tail's samples beyond the fit part's range by
    more than 5 of its sample-to-sample sd on this seed (the premise: the
    margin of split29 called it uncovered), none by 5 of its level sd: the
    tail is covered and kept. (Not every seed: noise slower than the
    window, holdout.MIN_HELD samples, still wanders further; the review of
    split29 found 6 of 40 seeds flagged at this pole, this rule 1.)"""
    levels = [0, 1, -1, 0.5, -0.5, 1, 0, -1, 0.5, -0.5]
    e = np.repeat(np.asarray(levels, float), N // len(levels)) + _ar1(0.995, N, 15)
    rng = np.random.default_rng(8)
    pc = 0.1 + 0.02 * np.convolve(e, np.full(30, 1 / 30))[:N] + 1e-3 * rng.normal(size=N)
    rec = data.make_record(np.arange(N) / FS, e, pc, "slow-noise")
    tail = holdout.layout(N, "tail")
    white = signals.REST_SIGMAS * rec.sig_e + rec.q_e
    assert holdout.outside_share(rec.e, tail, white) > data.MAX_OUTSIDE   # the premise
    assert data.uncovered(rec, tail) is None
    assert data.split_for(rec) == (tail, None)


@pytest.mark.xfail(strict=True, reason="known limit (review of level31, R4): no window "
                   "of an input whose noise is large next to 5 % of its span rests, so the "
                   "margin falls back to the sample-to-sample sd's")
def test_slow_noise_on_covered_levels_of_a_small_span_is_not_a_new_level():
    """The record above with its levels scaled by 0.1 (span 0.2): the
    noise's wander over a window is then about 20 % of the span, no window
    passes the 5 %-of-span rest test, the level sd falls back to the
    sample-to-sample sd and 18 % of the tail reads as outside: this test
    fails until the rest test is scaled to the noise."""
    levels = [0, 1, -1, 0.5, -0.5, 1, 0, -1, 0.5, -0.5]
    e = 0.1 * np.repeat(np.asarray(levels, float), N // len(levels)) + _ar1(0.995, N, 15)
    rng = np.random.default_rng(8)
    pc = 0.1 + 0.02 * np.convolve(e, np.full(30, 1 / 30))[:N] + 1e-3 * rng.normal(size=N)
    rec = data.make_record(np.arange(N) / FS, e, pc, "slow-noise-small")
    assert data.uncovered(rec, holdout.layout(N, "tail")) is None


def test_paper_start_apart_only_beside_a_corner():
    """Without a corner nothing is explored apart; beside one the paper
    start and the corner-freed start are also explored on their own (the
    halving still takes every start: its own winner is what it was)."""
    starts = [("warm0", {}), ("paper", {}), ("fresh0", {})]
    corner = ("corner freed (L)", {})
    assert candidates._apart(starts, None) == []
    assert [s[0] for s in candidates._apart(starts, corner)] == ["paper", "corner freed (L)"]


def test_pid_lag_in_the_baselines_corner_is_found_with_the_blocks():
    """The own generator's pid lag (seed 132, test_hidden_effects) with the
    held-out blocks: the baseline sits in a corner (L and rho near their
    upper bounds, tau at its lower, beta, tau, nu held), the warm starts
    begin at its optimum, and the halving cut the start at the paper's
    values after its first stage: the lag was fitted at 2.6 ms in the
    corner (truth 18.6 ms). Explored on its own, the paper start reaches
    the lag."""
    ds = cases.make("pid", "lag", 132)
    d = cases.run(ds, holdout="blocks")
    assert len(d.split.held) == 3
    bad = cases.check(ds, d)
    assert not bad, "; ".join(bad) + " | " + cases.explain(ds, d)

# SPDX-License-Identifier: MIT
"""Two effects at once (analysis-bench.md, branch two31).

1. With plain output-error fits (no noise model weights them), the guards
   judge the two models in the criterion the fits minimised: the
   likelihood ratio is the drop of the plain cost over the noise variance
   along the effect's contribution, and the held-out gain is the measured
   error's; a filter the fits did not minimise does not count.
2. The dead band's test also starts where the linear groups moved with the
   width: the groups refitted with the width held (fit.Problem.held)."""
import copy

import numpy as np
from scipy.signal import lfilter

from pneufrac_fit import candidates, fit, guards, model, noise, search
from test_converge import _problem


def _fit(pb, effects, **kw):
    r = fit.lm_fit(pb, model.canonical(effects),
                   {**model.nominal_groups("p"), "e0": pb.e0_default(), **kw}, 0, 400, "test")
    fit.evaluate(pb, r)
    return r


def _acov(nm, n):
    """The AR process's autocovariance at lags 0..n-1, from its impulse
    response (not guards' own computation)."""
    h = lfilter([1.0], nm.a, np.r_[1.0, np.zeros(4 * n - 1)])
    return nm.sigma2 * np.array([h[:h.size - k] @ h[k:] for k in range(n)])


def _plain(pb):
    q = copy.copy(pb)
    q.nm = None
    return q


def test_with_plain_fits_the_likelihood_ratio_is_the_plain_costs_drop_over_the_noise_along_it(
        monkeypatch):
    """The lag model against the linear one, both fitted as plain output
    error: LR = (rss0 - rss1) d'd / d'S d, S the noise model of the
    residual of the model with the effect (here computed from its
    autocovariance, a Toeplitz matrix), d the contribution less its mean.
    At the branch's base the LR was the log ratio of the two residuals
    whitened by that model. Since branch guards32 that noise model is an
    ARFIMA one (long memory); the scaling is checked here with the AR
    model alone in its place."""
    monkeypatch.setattr(noise, "fit_arfima", noise.fit)
    pb = _plain(_problem())
    base, lag = _fit(pb, ()), _fit(pb, ("lag",), lag=0.01)
    t = guards.test(pb, "lag", lag, base)
    r1, r0 = pb.fit_of(lag.residual(pb)), pb.fit_of(base.residual(pb))
    drop = float(r0 @ r0) - float(r1 @ r1)
    d = lag.sim - base.sim
    d = pb.fit_of(d) - float(np.mean(pb.fit_of(d)))
    g = _acov(noise.fit(pb.fit_of(lag.residual(pb))), d.size)
    dSd = g[0] * float(d @ d) + 2.0 * sum(g[k] * float(d[:-k] @ d[k:]) for k in range(1, d.size))
    want = drop * float(d @ d) / dSd
    # H H' (the process started at the part's first sample) against the
    # stationary covariance: they differ only over the noise's memory
    assert abs(t.lr - want) <= 0.05 * abs(want)
    m = pb.fit_white(lag.residual(pb), t.nm).size
    assert t.dbic == -t.lr + (lag.k - base.k) * np.log(m)


def test_a_nested_fit_whose_plain_cost_fell_is_never_judged_worse():
    """The sign of the evidence is the plain cost's: a model with one more
    freedom that fits better by the criterion both were fitted by has a
    positive likelihood ratio, whatever filter the comparison's noise model
    is (at the base, a filter the fits did not minimise could make it
    negative: blind seed 7's dead band, dBIC +860)."""
    pb = _plain(_problem())
    base, lag = _fit(pb, ()), _fit(pb, ("lag",), lag=0.01)
    r1, r0 = pb.fit_of(lag.residual(pb)), pb.fit_of(base.residual(pb))
    assert float(r0 @ r0) > float(r1 @ r1)          # the premise
    slow = noise.NoiseModel(np.array([1.0, -0.99]), 1.0, 50.0, 1000)
    fast = noise.NoiseModel(np.array([1.0, 0.9]), 1.0, 5.0, 1000)
    for nm in (slow, fast):
        assert guards._lr(pb, nm, lag.residual(pb), base.residual(pb),
                          lag.sim - base.sim - float(np.mean(pb.fit_of(lag.sim - base.sim)))) > 0


def test_with_plain_fits_the_held_out_gain_is_the_measured_errors(monkeypatch):
    """With plain fits the held-out gain is the measured error's alone;
    with fits weighted by the comparison's noise model too (branch
    satnoise32: the whitened criterion now gives the held-out improvement's
    significance, guards._held_z, not a share)."""
    pb = _plain(_problem())
    base, lag = _fit(pb, ()), _fit(pb, ("lag",), lag=0.01)
    t = guards.test(pb, "lag", lag, base)
    c1 = pb.split.centre_held(lag.residual(pb))
    c0 = pb.split.centre_held(base.residual(pb))
    p1, p0 = pb.held_of(c1), pb.held_of(c0)
    assert t.val_gain == 1.0 - float(p1 @ p1) / float(p0 @ p0)
    # the whitened gain with the same filter, smaller here: at the base it counted
    v1, v0 = pb.held_white(c1, t.nm), pb.held_white(c0, t.nm)
    assert 1.0 - float(v1 @ v1) / float(v0 @ v0) < t.val_gain
    w = copy.copy(pb)
    w.nm = t.nm
    monkeypatch.setattr(guards, "noise_for", lambda q, r1: q.nm)   # the rest model kept
    tw = guards.test(w, "lag", lag, base)
    assert tw.val_gain == t.val_gain
    raw = guards._raw_noise(pb, lag.residual(pb))
    assert tw.val_z == guards._held_z(w, tw.nm, c0, c1, True, raw)      # whitened
    assert t.val_z == guards._held_z(pb, t.nm, c0, c1, False, raw)      # as measured
    assert tw.val_z != t.val_z


def test_a_held_effect_parameter_is_simulated_and_not_fitted():
    """fit.Problem.held: the dead band's width held at its value while the
    groups are fitted, and simulated at it."""
    pb = _problem()
    q = copy.copy(pb)
    q.held = {"deadband": 0.05 * pb.span_e}
    names = [s[0] for s in fit.specs(q, ("backlash",))]
    assert "deadband" not in names and "deadband" in [s[0] for s in fit.specs(pb, ("backlash",))]
    st = {**model.nominal_groups("p"), "e0": pb.e0_default()}
    a = fit.simulate_raw(q, ("backlash",), st)
    b = fit.simulate_raw(pb, ("backlash",), {**st, **q.held})
    np.testing.assert_array_equal(a, b)
    r = fit.lm_fit(q, ("backlash",), {**st, **q.held}, 0, 60, "held")
    assert "deadband" not in r.values


def test_the_dead_band_test_takes_the_groups_moved_start(monkeypatch):
    """The dead band's extended fit is the better of the search and the
    joint fit from the groups refitted at its first size held, on the
    whole fit part (candidates._groups_moved)."""
    pb = _problem()
    base = _fit(pb, ())
    seen = []
    orig = fit.lm_fit

    def spy(q, effects, start, dead=0, budget=400, label="", **kw):
        if q.held:
            seen.append((q.nsim, dict(q.held)))
        return orig(q, effects, start, dead, budget, label, **kw)

    monkeypatch.setattr(fit, "lm_fit", spy)
    b = candidates.fit_extended(pb, base, "backlash", np.random.default_rng(0))
    first = candidates._sizes(pb, "backlash", base, None)[0]
    assert seen and all(n == pb.nsim and h == first for n, h in seen)
    assert "deadband" in b.values
    seen.clear()
    candidates.fit_extended(pb, base, "lag", np.random.default_rng(0))
    assert not seen

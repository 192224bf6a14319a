# SPDX-License-Identifier: MIT
"""A noise model measured at rest that took something other than noise for
noise (guards.noise_for). A rest stretch whose AR model claims
significantly more slow noise (long-run variance, beyond guards.LONG_RUN_Z
standard errors, longrun.py) than the residual of the model with the
effect holds (an output still settling in its opening stretch) does not
whiten the comparison; that residual's own model does, as for a record
without a rest stretch (analysis-bench.md, branches twofx5 and noise30)."""
import copy

import numpy as np
from scipy.signal import lfilter

from pneufrac_fit import fit, guards, longrun, model, noise
from test_converge import _problem
from test_noise30 import _stub

REST = 650


def _fit(pb, effects, **kw):
    r = fit.lm_fit(pb, model.canonical(effects),
                   {**model.nominal_groups("p"), "e0": pb.e0_default(), **kw}, 0, 400, "test")
    fit.evaluate(pb, r)
    return r


def _settling_rest(rng, sd, amplitude=5.0, tau=50.0):
    """A rest stretch of white noise (sd) whose output opens
    `amplitude` noise sd below its level and settles with time constant
    `tau` samples: what blind seed 5's two-lag-backlash-dd opens with."""
    k = np.arange(REST)
    return sd * (rng.standard_normal(REST) - amplitude * np.exp(-k / tau))


def _sd(pb, fr):
    """The noise sd of fr's residual: its AR model's innovations."""
    return float(np.sqrt(noise.fit(pb.fit_pieces(fr.residual(pb))).sigma2))


def _long_run(nm):
    """The AR model's spectrum at zero frequency (x 2 pi), computed here
    so that the premises hold without guards' own function."""
    return nm.sigma2 / float(np.sum(nm.a)) ** 2


def _significant(rest, own):
    """The premise: the rest model's long-run variance above own's by more
    than LONG_RUN_Z standard errors (and by 4x, the rule this one replaced)."""
    se = np.hypot(longrun.log_se(rest, rest.n), longrun.log_se(own, own.n))
    d = np.log(_long_run(rest) / _long_run(own))
    return d > guards.LONG_RUN_Z * se and d > np.log(4.0)


def _with_nm(pb, nm):
    q = copy.copy(pb)
    q.nm = nm
    return q


def test_a_rest_model_that_took_a_settling_output_for_noise_does_not_whiten_the_guards():
    """The lag test under a noise model measured on a settling rest stretch
    (AR, most of its variance slow): the guards whiten with the lag model's
    residual's own noise model, the one they use without a rest stretch,
    and the held-out gain is that one's. At the branch's base the rest
    model whitened them and the whitened gain came out smaller."""
    pb = _problem()
    base, lag = _fit(pb, ()), _fit(pb, ("lag",), lag=0.01)
    # this lag fit leaves a slow misfit (q and beta held): a large settling
    rest = noise.fit(_settling_rest(np.random.default_rng(5), _sd(pb, lag), 15.0, 150.0))
    assert rest.order >= 1                      # the premise: the settling taken for colour
    own = noise.fit(pb.fit_pieces(lag.residual(pb)))
    assert _significant(rest, own)              # the premise
    t = guards.test(_with_nm(pb, rest), "lag", lag, base)
    t0 = guards.test(_with_nm(pb, None), "lag", lag, base)
    assert t.nm is not rest
    np.testing.assert_allclose(t.nm.a, own.a)
    # (the likelihood ratio is the weighted criterion's since branch
    # guards32, the fits being weighted by the rest model: test_guards32)
    assert t.val_gain == t0.val_gain and t.snr == t0.snr


def test_a_rest_model_the_residual_agrees_with_is_kept():
    """A rest stretch that is the noise alone: its model whitens the guards,
    as before."""
    pb = _problem()
    base, lag = _fit(pb, ()), _fit(pb, ("lag",), lag=0.01)
    rest = noise.fit(_sd(pb, lag) * np.random.default_rng(6).standard_normal(REST))
    t = guards.test(_with_nm(pb, rest), "lag", lag, base)
    assert t.nm is rest


def test_lack_of_fit_reads_the_same_noise_model():
    """guards.inadequate (whether the pairs step runs) judges the residual
    under the same rule: with the settling rest model it gives what it gives
    without a rest stretch."""
    pb = _problem()
    lag = _fit(pb, ("lag",), lag=0.01)
    rest = noise.fit(_settling_rest(np.random.default_rng(7), _sd(pb, lag), 15.0, 150.0))
    own = noise.fit(pb.fit_pieces(lag.residual(pb)))
    assert _significant(rest, own)              # the premise
    assert guards.inadequate(_with_nm(pb, rest), lag) == guards.inadequate(_with_nm(pb, None),
                                                                              lag)


def test_a_coloured_rest_model_is_kept_in_these_draws():
    """No firing on a rest stretch that is the noise alone, AR(1) of pole
    0.95 and resonant AR(2), on the shortest rest stretch that gives a
    noise model (200 samples) and a long one, the residual the same noise
    over 14 000 samples (no misfit), 25 fixed draws each. A guard against
    over-firing, not a rate: the rate, on the slowest cases, is
    test_noise30's."""
    rng = np.random.default_rng(8)
    dens = {"ar1": [1.0, -0.95], "ar2": [1.0, -2 * 0.95 * np.cos(0.3), 0.95 ** 2]}
    for den in dens.values():
        for n_rest in (200, REST):
            for _ in range(25):
                x = lfilter([1.0], den, rng.standard_normal(n_rest + 14_500))[500:]
                rest = noise.fit(x[:n_rest])
                assert guards.noise_for(_stub(rest), x[:n_rest + 14_000]) is rest


def test_a_settling_rest_stretch_is_told_from_noise():
    """The other way: white noise whose rest stretch opens 3 sd or more off
    its level and settles over 50 samples or more is caught."""
    rng = np.random.default_rng(9)
    for amplitude, tau in ((3.0, 150.0), (5.0, 50.0)):
        for _ in range(10):
            opening = _settling_rest(rng, 1.0, amplitude, tau)
            rest = noise.fit(opening)
            resid = np.r_[opening, rng.standard_normal(14_000)]   # flat model: the settling too
            assert guards.noise_for(_stub(rest), resid) is not rest

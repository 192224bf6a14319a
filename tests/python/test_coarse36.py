# SPDX-License-Identifier: MIT
"""lm_fit's Jacobians at half the simulation rate while a search still
makes headway (fit._Objective._coarse_differences, fit.COARSE_PROGRESS):
they steer only; the cost, the best point and the stop are the residual's
own at the full rate."""
import numpy as np
import pytest

import cases
from pneufrac_fit import data, fit, model


def _problem(oversample=2):
    ds = cases.make("p", "lag", 2, n=3000)
    rec = data.make_record(ds.t, ds.e, ds.pc)
    return fit.Problem.from_record(rec, "p", {"q": 0.0, "beta": 1.0}, 8, oversample)


def _start(pb):
    return {**model.nominal_groups("p"), "e0": pb.e0_default(), "lag": 0.01}


def _objective(pb, effects=("lag",)):
    sp = fit.specs(pb, effects)
    return fit._Objective(pb, sp, effects, 0, 10_000), fit.to_theta(sp, _start(pb), pb)


def _steps(monkeypatch):
    """Simulated steps (samples x the rate multiple), by multiple."""
    got = {}
    orig = model.Setup.simulate

    def counted(self, g, e, effects=(), ev=None, oversample=None, internal=False):
        m = oversample or self.oversample
        got[m] = got.get(m, 0) + len(e) * m
        return orig(self, g, e, effects, ev, oversample, internal)
    monkeypatch.setattr(model.Setup, "simulate", counted)
    return got


@pytest.fixture(autouse=True)
def _one_thread():
    fit.set_threads(1)


def test_half_rate_jacobian_is_close_to_the_full_rates_and_is_simulated_at_half(monkeypatch):
    """Every column within 10 % (relative, in norm) of the full rate's:
    the two models differ in their fastest modes only. A sanity bound, not
    a tuned one: the search needs the directions, not the last digits."""
    pb = _problem()
    obj, th = _objective(pb)
    steps = _steps(monkeypatch)
    Jc = obj._coarse_differences(th)
    assert set(steps) == {1} and steps[1] == (th.size + 1) * pb.nsim
    obj.coarse = False
    Jf = obj.jac(th)
    assert Jc.shape == Jf.shape
    assert not np.array_equal(Jc, Jf)                 # another model's
    err = np.linalg.norm(Jc - Jf, axis=0) / np.linalg.norm(Jf, axis=0)
    assert np.all(err < 0.10), err


def test_half_rate_points_are_not_kept_as_the_residuals():
    pb = _problem()
    trail = {}
    sp = fit.specs(pb, ("lag",))
    obj = fit._Objective(pb, sp, ("lag",), 0, 10_000, trail=trail)
    th = fit.to_theta(sp, _start(pb), pb)
    f0 = obj(th)
    assert obj.coarse
    obj.jac(th, f0)
    assert obj.J_coarse
    assert len(trail) == 1                            # the base point only
    assert obj.best[0] == float(f0 @ f0)
    assert list(obj.last.values())[0] is f0 and len(obj.last) == 1
    assert obj.calls == 1 + th.size                   # counted as the p it stands in for


def test_no_half_rate_at_the_data_rate(monkeypatch):
    pb = _problem(oversample=1)
    obj, th = _objective(pb)
    assert not obj.coarse
    steps = _steps(monkeypatch)
    obj.jac(th)
    assert set(steps) == {1} and not obj.J_coarse


def test_a_step_that_saves_little_ends_the_half_rate_for_good():
    pb = _problem()
    obj, th = _objective(pb)
    f0 = obj(th)
    obj.jac(th, f0)
    assert obj.J_coarse
    obj.jac(th, f0)                                   # no headway at all
    assert not obj.coarse and not obj.J_coarse
    obj.jac(th, f0 * 0.5)                             # headway again: still the full rate
    assert not obj.J_coarse


@pytest.mark.parametrize("progress", [fit.COARSE_PROGRESS, 1e-300])
def test_a_fit_reaches_the_full_rates_cost_with_fewer_steps_and_stops_on_its_own_jacobian(
        monkeypatch, progress):
    """From the same start, with the half rate (as set; and with a gate that
    never closes, so that the search stops on a half-rate Jacobian and
    must go on with the full rate's) against without: a cost no worse by
    0.5 in deviance, in fewer simulated steps; and the fit's last Jacobian
    is the residual's own. 0.5: on this record's flat ridge between the lag
    and L the full rate's own search stops 0.4 apart in deviance from
    starts with lags 10-20 % apart (0.008-0.012: -0.33 to +0.07 around the
    start below; the half rate's, -0.33 to +0.13), and a guard resolves
    nothing under a BIC change of 10."""
    pb = _problem()
    made = []
    orig = fit._Objective

    class Kept(orig):
        def __init__(self, *a, **k):
            super().__init__(*a, **k)
            made.append(self)
    monkeypatch.setattr(fit, "_Objective", Kept)
    monkeypatch.setattr(fit, "FITS_KEPT", 0)
    steps = _steps(monkeypatch)

    def run(p):
        monkeypatch.setattr(fit, "COARSE_PROGRESS", p)
        steps.clear()
        fr = fit.lm_fit(pb, ("lag",), _start(pb), 0, budget=600)
        return fr, sum(steps.values()), made[-1]
    full, n_full, o_full = run(0.0)
    half, n_half, o_half = run(progress)
    assert not o_full.J_coarse and not o_half.J_coarse
    assert n_half < n_full
    assert pb.n_counted * np.log(half.cost / full.cost) < 0.5

# SPDX-License-Identifier: MIT
"""lm_fit's Jacobians at half the simulation rate while a search still
makes headway (fit._Objective.jac, _coarse_differences,
fit.COARSE_DEVIANCE): they steer only; the first Jacobian, the last ones,
the cost, the best point and the stop are the residual's own at the full
rate."""
import numpy as np
import pytest

import cases
from pneufrac_fit import data, fit, lib, model


def _problem(oversample=2):
    ds = cases.make("p", "lag", 2, n=3000)
    rec = data.make_record(ds.t, ds.e, ds.pc)
    return fit.Problem.from_record(rec, "p", {"q": 0.0, "beta": 1.0}, 8, oversample)


def _start(pb, **over):
    return {**model.nominal_groups("p"), "e0": pb.e0_default(), "lag": 0.01, **over}


def _objective(pb, effects=("lag",), dead=0, **kw):
    sp = fit.specs(pb, effects)
    return fit._Objective(pb, sp, effects, dead, 10_000, **kw), fit.to_theta(sp, _start(pb), pb)


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


def _headway(obj, th):
    """A point th2 near th whose residual is lower by far more than
    COARSE_DEVIANCE in deviance (a step down the full-rate gradient from a
    start far from the optimum), and its residual."""
    f0 = obj.eval(th)
    J = obj.jac(th, f0)
    g = J.T @ f0
    for s in (1e-1, 3e-2, 1e-2, 3e-3, 1e-3):
        th2 = th - s * g / np.linalg.norm(g)
        f2 = obj.eval(th2)
        if obj.n * np.log((f0 @ f0) / (f2 @ f2)) > 10 * fit.COARSE_DEVIANCE:
            return th2, f2
    raise AssertionError("no step with headway from the start")


@pytest.fixture(autouse=True)
def _one_thread():
    fit.set_threads(1)


def test_the_first_jacobian_is_the_full_rates_then_half_while_a_step_saves_much(monkeypatch):
    pb = _problem()
    obj, th = _objective(pb)
    steps = _steps(monkeypatch)
    th2, f2 = _headway(obj, th)
    assert set(steps) == {2}                          # the first: the full rate's
    steps.clear()
    obj.jac(th2, f2)
    assert obj.J_coarse and set(steps) == {1}
    assert steps[1] == (th.size + 1) * pb.nsim       # p + 1 points at half the rate


def test_half_rate_jacobian_is_close_to_the_full_rates():
    """Every column within 10 % (relative, in norm) of the full rate's:
    the two models differ in their fastest modes only. A sanity bound, not
    a tuned one: the search needs the directions, not the last digits."""
    pb = _problem()
    obj, th = _objective(pb)
    Jc = obj._coarse_differences(th)
    obj.coarse = False
    Jf = obj.jac(th)
    assert Jc.shape == Jf.shape
    assert not np.array_equal(Jc, Jf)                 # another model's
    err = np.linalg.norm(Jc - Jf, axis=0) / np.linalg.norm(Jf, axis=0)
    assert np.all(err < 0.10), err


def test_half_rate_points_are_not_kept_as_the_residuals():
    pb = _problem()
    trail = {}
    obj, th = _objective(pb, trail=trail)
    th2, f2 = _headway(obj, th)
    trail.clear()
    obj.memo.clear()
    obj.best = (np.inf, None, None)                  # any point noted would be the best
    obj.jac(th2, f2)
    assert obj.J_coarse
    assert trail == {} and obj.memo == {}
    assert obj.best[1] is None                       # no half-rate point noted
    assert len(obj.last) == 1 and list(obj.last.values())[0] is f2


def test_a_step_that_saves_little_ends_the_half_rate_for_good():
    pb = _problem()
    obj, th = _objective(pb)
    th2, f2 = _headway(obj, th)
    obj.jac(th2, f2)
    assert obj.J_coarse
    obj.jac(th2, f2)                                  # no headway at all
    assert not obj.coarse and not obj.J_coarse
    th3, f3 = _headway(obj, th2)                      # headway again: still the full rate
    obj.jac(th3, f3)
    assert not obj.J_coarse


@pytest.mark.parametrize("oversample, dead, half", [(1, 0, False), (3, 0, False), (2, 3, False),
                                                    (2, 4, True), (4, 2, True)])
def test_half_rate_only_where_the_rate_and_the_delay_halve_exactly(oversample, dead, half):
    """An odd delay at half the rate would be another delay (the library
    rounds it to whole samples): another model's Jacobian."""
    pb = _problem(oversample)
    effects = ("dead_time",) if dead else ("lag",)
    sp = fit.specs(pb, effects)
    obj = fit._Objective(pb, sp, effects, dead, 10_000)
    assert obj.coarse == half


def test_a_refused_half_rate_point_falls_back_once_counted(monkeypatch):
    pb = _problem()
    obj, th = _objective(pb)
    th2, f2 = _headway(obj, th)
    orig = fit._Objective._residual

    def refuse_half(self, vals, oversample=None):
        if oversample == 1:
            return np.full(self.n, 1e3), None
        return orig(self, vals, oversample)
    monkeypatch.setattr(fit._Objective, "_residual", refuse_half)
    calls = obj.calls
    obj.jac(th2, f2)
    assert not obj.J_coarse and not obj.coarse
    assert obj.calls == calls + th.size


@pytest.mark.parametrize("gate", [fit.COARSE_DEVIANCE, 1e-300])
def test_a_fit_is_no_worse_in_fewer_steps_and_stops_on_its_own_jacobian(monkeypatch, gate):
    """From the same start (far from the optimum), with the half rate (as
    set; and with a gate that never closes, so that the search stops on a
    half-rate Jacobian and must go on with the full rate's) against without:
    a cost no worse by 0.5 in deviance, in fewer simulated steps, ending on
    the full rate's Jacobian and reported at the full rate. 0.5: on this
    record's flat ridge between the lag and L the full rate's own search
    stops 0.4 apart in deviance from starts with lags 10-20 % apart (0.008
    to 0.012), and a guard resolves nothing under a BIC change of 10."""
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

    def run(g):
        monkeypatch.setattr(fit, "COARSE_DEVIANCE", g)
        steps.clear()
        fr = fit.lm_fit(pb, ("lag",), _start(pb), 0, budget=600)
        return fr, sum(steps.values()), made[-1], dict(steps)
    full, n_full, _, s_full = run(0.0)
    half, n_half, o_half, s_half = run(gate)
    assert set(s_full) == {2} and 1 in s_half        # the half rate was used
    assert not o_half.J_coarse
    assert n_half < n_full
    assert pb.n_counted * np.log(half.cost / full.cost) < 0.5
    # what the fit reports is the full rate's: evaluated afresh, the same
    sp = fit.specs(pb, ("lag",))
    again = fit.finish(pb, ("lag",), sp, half.theta, 0, half.cost, "x")
    assert again.values == half.values               # K and pc0 of a fresh full-rate run
    o = fit._Objective(pb, sp, ("lag",), 0, 10_000)
    r = o.eval(half.theta)
    assert float(r @ r) * o.scale ** 2 == pytest.approx(half.cost, rel=1e-12)

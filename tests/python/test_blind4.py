# SPDX-License-Identifier: MIT
"""Saturation with one limit nests saturation with two. A fit of two
limits one of which the fit part does not support (moved out of the
output's reach, the cost rises by less than BIC's price of a parameter)
is refined from the one-limit model too, and the better fit kept
(candidates._one_limit): a limit that binds at a few samples only stalls
a gradient search at its kink, and is no reason to stop the other
parameters short."""
import math

import numpy as np

import cases
from pneufrac_fit import baseline, candidates, data, excite, fit, generate, model, search


def _one_sided():
    """A p record whose relay meets one stop only (its lower limit; the
    upper one far above anything the output reaches), its problem with
    the limits clipping p_c, and its baseline."""
    rng = np.random.default_rng(3)
    params = generate.perturbed_params("p", rng)
    e = excite.make("steps", cases.N, cases.FS, rng, rest=0.1)
    y = generate.linear_output("p", e, cases.FS, params=params)
    fx = {"saturation": {"sat_lo": 0.6 * float(np.min(y)),
                         "sat_hi": 10.0 * float(np.ptp(y))}}
    ds = generate.generate("p", effects=fx, n=cases.N, fs=cases.FS, noise=cases.NOISE,
                           seed=11, e=e, params=params, **cases.PLANT)
    rec = data.make_record(ds.t, ds.e, ds.pc, "synthetic")
    pb = fit.Problem.from_record(rec, "p", None, 8, model.auto_oversample(rec.fs))
    base = baseline.fit_baseline(pb, np.random.default_rng(5), lambda m: None)[0]
    return pb, candidates.with_kind(pb, model.SAT_CLIP), base


def _unsupported(pk, b, k) -> bool:
    m = max(pk.n_counted, 1)
    full = {**b.groups, **b.values}
    c0 = fit.start_cost(pk, b.effects, full, b.dead)
    out = candidates.on_sim(pk, b, candidates.no_effect(pk, "saturation"))
    c = fit.start_cost(pk, b.effects, {**full, k: out[k]}, b.dead)
    return c != c0 and m * math.log(c / c0) < math.log(m)


def test_an_unsupported_upper_limit_is_refitted_out_of_reach():
    pb, pk, base = _one_sided()
    effects = ("saturation",)
    span = pb.y_hi - pb.y_lo
    lims = candidates.on_sim(pk, base, {"sat_lo": pb.y_lo + 0.02 * span,
                                        "sat_hi": pb.y_hi - 0.005 * span})
    st = {**base.groups, **base.values, **lims}
    st["rho"] *= 1.3
    # a fit stopped short (one iteration) with its upper limit binding at
    # the fit part's top, where the fit part does not support it
    b = search.refine(pk, effects, [("upper limit at the top", st)], dead=base.dead, iters=1)
    assert _unsupported(pk, b, "sat_hi")
    got = candidates._one_limit(pk, effects, b)
    assert got.cost < b.cost
    c = candidates._sat_shift(pk, got)
    assert got.values["sat_hi"] + c > pb.y_hi


def test_limits_the_fit_supports_are_left_alone():
    pb, pk, base = _one_sided()
    st = {**base.groups, **base.values,
          **candidates.on_sim(pk, base, candidates.no_effect(pk, "saturation"))}
    b = search.refine(pk, ("saturation",), [("limits out", st)], dead=base.dead, iters=2)
    # neither limit binds: nothing to refit
    assert candidates._one_limit(pk, ("saturation",), b) is b


def test_the_floor_without_rest_is_the_lower_of_the_two_parts_bounds():
    """Without an opening rest the floor is the final model's residual, an
    upper bound on each part; a model error only the fit part holds (there
    an effect the held-out part never reaches) must not raise it above
    what the held-out part shows (diagnose._floor)."""
    from types import SimpleNamespace
    from pneufrac_fit import diagnose
    rng = np.random.default_rng(1)
    n, n_fit = 4000, 2800
    y = np.sin(np.arange(n) / 50.0)
    resid = 0.01 * rng.standard_normal(n)
    resid[:n_fit] += 0.2 * np.sin(np.arange(n_fit) / 7.0)   # model error in the fit part
    pb = SimpleNamespace(y=y, fit_of=lambda x: x[:n_fit], held_of=lambda x: x[n_fit:])
    final = SimpleNamespace(residual=lambda _: resid)
    floor, src = diagnose._floor(SimpleNamespace(rest=0), pb, final)
    assert floor == np.std(resid[n_fit:]) / np.std(y[n_fit:])
    assert "held-out" in src

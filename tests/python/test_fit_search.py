# SPDX-License-Identifier: MIT
"""The search's machinery: a forked worker makes its own threads for the
Jacobian, and an effect at its no-effect values (where a lost extended fit
is refined again from) is the model without it."""
import multiprocessing as mp

import numpy as np
import pytest

import cases
from pneufrac_fit import candidates, data, fit, model


def _problem():
    ds = cases.make("p", "lag", 2, n=3000)
    rec = data.make_record(ds.t, ds.e, ds.pc)
    pb = fit.Problem.from_record(rec, "p", {"q": 0.0, "beta": 1.0}, 8, 2)
    return pb


def _jacobian_shape():
    pb = _problem()
    sp = fit.specs(pb, ())
    obj = fit._Objective(pb, sp, (), 0, 10_000)
    th = fit.to_theta(sp, {**model.nominal_groups("p"), "e0": pb.e0_default()}, pb)
    return obj.jac(th).shape


def _jac_in_child(q):
    fit.set_threads(2)                    # as selection.run_round's workers do
    q.put(_jacobian_shape())


def test_forked_worker_makes_its_own_threads():
    """A pool inherited through fork has no threads: a Jacobian run on it
    would wait for ever. The parent's pool has run work before the fork (its
    threads exist), as the baseline's Jacobians do in a diagnosis."""
    fit.set_threads(2)
    _jacobian_shape()
    ctx = mp.get_context("fork")
    q = ctx.Queue()
    p = ctx.Process(target=_jac_in_child, args=(q,))
    p.start()
    p.join(60)
    alive = p.is_alive()
    if alive:
        p.kill()
        p.join()
    fit.set_threads(1)
    assert not alive and p.exitcode == 0
    assert q.get(timeout=5)[1] == len(fit.specs(_problem(), ()))


@pytest.mark.parametrize("effect", ["lag", "saturation", "backlash", "nozzle"])
def test_no_effect_is_the_model_without_it(effect):
    pb = _problem()
    v = {**model.nominal_groups("p"), "e0": pb.e0_default()}
    plain, K, _, _ = fit.model_output(pb, (), v, 0, pb.nsim)
    w = {**v, **candidates.no_effect(pb, effect)}
    if effect == "saturation":            # K is searched, not solved, with it
        w["K"] = K
    with_it, _, _, _ = fit.model_output(pb, (effect,), w, 0, pb.nsim)
    span = np.ptp(plain)
    tol = 2e-3 if effect == "lag" else 1e-9   # the lag's bound is a fiftieth of a sample
    assert np.max(np.abs(with_it - plain)) <= tol * span

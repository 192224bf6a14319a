# SPDX-License-Identifier: MIT
"""Every model without a new effect is compared on the samples the model
so far was fitted on (selection.best_without): a round's winner is refused
when a refit of the model without it predicts the held-out part as well,
and a dead band's test refits that model without the samples before the
input's first reversal. A fit that leaves out a stretch the model cannot
follow predicts the rest better for that reason, and the stretch it left
out is the evidence for the effect.

Found on the independent simulator's two-nozzle-lag seed 5 (dd, PRBS; the
nozzle on top of the lag predicted the held-out part at 0.0137, the lag
model refitted by the dead band's test without its first samples at
0.0131: "no effect added") and two-backlash-saturation seed 1 (saturation
0.0738 against 0.0703). The record-level test takes the first: it was
chosen because it shows the cause, not drawn blind as the cases of
test_diagnose_indep.py were."""
import copy
from types import SimpleNamespace

import numpy as np

import cases
from indepsim.make import make
from pneufrac_fit import data, diagnose, fit, model, selection
from test_diagnose_indep import check


def _problem():
    ds = cases.make("p", "lag", 3, n=3000)
    rec = data.make_record(ds.t, ds.e, ds.pc)
    pb = fit.Problem.from_record(rec, "p", {"q": 0.0, "beta": 1.0}, 8, 2)
    pb.burn = 30
    return pb


def _fit(pb, start, budget=400):
    r = fit.lm_fit(pb, (), start, 0, budget, "test")
    fit.evaluate(pb, r)
    return r


def test_a_reference_fitted_on_fewer_samples_is_compared_on_the_model_so_fars():
    """The first half of the fit part holds a slow swing no model of the
    controller follows. The linear model fitted without it (as a dead
    band's reference leaves out the samples before the first reversal)
    predicts the held-out part better than the one fitted on every sample;
    an effect that predicts between the two is still added: refitted on
    the model so far's samples, that reference predicts no better than the
    model so far."""
    pb = _problem()
    k = np.arange(pb.split.n_fit // 2)
    pb.y = pb.y.copy()
    pb.y[k] += 0.2 * np.ptp(pb.y) * np.sin(np.pi * k / k.size) ** 2
    start = {**model.nominal_groups("p"), "e0": pb.e0_default()}
    whole = _fit(pb, start)
    late = copy.copy(pb)
    late.burn = pb.split.n_fit // 2
    half = _fit(late, {**whole.groups, **whole.values})
    # the premise: fitted on fewer samples, it predicts the held-out part better
    assert half.nrmse_val < 0.9 * whole.nrmse_val
    mid = 0.5 * (half.nrmse_val + whole.nrmse_val)
    effect = SimpleNamespace(effect="saturation", passes=True, ref=whole, pb=pb,
                             model=SimpleNamespace(effects=("saturation",), nrmse_val=mid))
    play = SimpleNamespace(effect="backlash", passes=False, ref=half, pb=late,
                           model=SimpleNamespace(effects=("backlash",), nrmse_val=1.0))
    without = selection.best_without([effect, play], whole, pb)
    assert without.nrmse_val > mid
    assert selection._passing([effect, play], whole, pb, 1, lambda m: None) == [effect]
    # the same reference fitted on the model so far's samples counts as it is
    play_all = SimpleNamespace(**{**vars(play), "ref": half, "pb": pb})
    assert selection.best_without([effect, play_all], whole, pb) is half


def test_nozzle_on_top_of_a_lag_is_named():
    """two-nozzle-lag seed 5 (dd, PRBS): lag 31 / 32 noise sd, nozzle 14 /
    15 (fit part / held out). Both are named, the lag's size and the
    held-out error as cases require. The nozzle's x_1/2 is not checked: a
    two-level input shows a static curve at two levels only, which many
    curves pass through (docs/analysis.md, Known limits; the fit gives
    0.30 against 3.47)."""
    rec = make("two-nozzle-lag", 5)
    r = data.make_record(rec.t, rec.e, rec.pc, "two-nozzle-lag-5")
    d = diagnose.diagnose(r, rec.truth["config"], jobs=2, progress=False)
    bad = [b for b in check(rec, d) if not b.startswith("nozzle_xh ")]
    assert not bad, "two-nozzle-lag-5: " + "; ".join(bad) + " | " + " ".join(d.why)
    assert set(d.causes) == {"lag", "nozzle"}

# SPDX-License-Identifier: MIT
"""Realistic records from the own generator with settings the fit does not
use (cases.PLANT): coloured noise, ADC steps, inputs that are not steps
(PRBS, ramps, a sine sweep that never rests), slow drift, two effects at
once, a 10 kHz record, an operating point away from zero. Clean records
must give none; effects must be found (cases.check)."""
import numpy as np
import pytest

import cases
from pneufrac_fit import data, diagnose, excite, fit, generate


@pytest.mark.parametrize("config,input_kind,kw", [
    ("dd", "prbs", {"noise_kind": "ar1"}),
    ("id", "sweep", {"noise_kind": "pink", "adc_bits": 12, "rest": 0.0}),
    ("pid", "ramps", {"drift": 0.03}),
    ("p", "steps", {"noise_kind": "pink", "drift": 0.02, "adc_bits": 10}),
])
def test_clean_record_gives_none(config, input_kind, kw):
    ds = cases.make(config, "none", 300 + len(config), input_kind=input_kind, **kw)
    d = cases.run(ds)
    assert d.causes == [], cases.explain(ds, d)


def test_two_effects_at_once():
    """A 30 ms line lag and a 1 % dead band: both named (the dead band used
    to be named alone), each with its own gain."""
    ds = cases.make("p", "none", 311)
    ds = generate.generate("p", effects={"lag": {"lag": 0.03}, "backlash": {"deadband": 0.02}},
                           n=cases.N, fs=cases.FS, noise=cases.NOISE, seed=318, e=ds.e,
                           params=ds.params, **cases.PLANT)
    d = cases.run(ds)
    assert not cases.check(ds, d), cases.explain(ds, d)
    by = {t.effect: t for t in d.checks}
    assert set(by) == {"lag", "backlash"}
    for t in by.values():           # each passes with the other in the model
        assert t.passes and t.model.nrmse_val < t.ref.nrmse_val


def test_dead_time_at_10_khz():
    ds = cases.make("dd", "dead_time", 320, n=20000, fs=10000.0, size_fs=1000.0)
    d = cases.run(ds)
    assert not cases.check(ds, d), cases.explain(ds, d)


def test_lag_in_a_sweep_at_an_operating_point():
    """No rest stretch anywhere: a sweep around e0 = 0.4 from the first
    sample, the output around pc0 = 3. The operating point is fitted and
    the lag found."""
    rng = np.random.default_rng(330)
    params = generate.perturbed_params("p", rng)
    e = excite.sweep(cases.N, cases.FS, rng, amp=0.8, f1=8.0, rest=0.0)
    ds = generate.generate("p", effects={"lag": {"lag": 0.012}}, n=cases.N, fs=cases.FS,
                           noise=cases.NOISE, seed=331, e=e, params=params, **cases.PLANT)
    rec = data.make_record(ds.t, ds.e + 0.4, ds.pc + 3.0)
    assert rec.e0 is None
    d = diagnose.diagnose(rec, "p", progress=False, jobs=2)
    assert d.causes == ["lag"], " ".join(d.why)
    assert abs(d.effect_params["lag"] / 0.012 - 1) < cases.REL_TOL
    # The operating point: the model, held at the true e0, settles at the
    # true pc0. (e0 and pc0 alone trade along the model's static line: with
    # the start's free response solved too, the opening transient no longer
    # pins e0 by itself.)
    assert abs(_settles_at(d, 0.4) - 3.0) < 0.05 * np.ptp(ds.pc)


def _settles_at(d, e_level: float) -> float:
    """The final model's output after a long constant input e_level."""
    import copy
    pb = copy.copy(d.pb)
    pb.e_abs = np.full(pb.e_abs.size, e_level)
    fr = d.extended
    v = dict(fr.values)
    if fr.K_solved:
        v["K"] = 1.0
    s = fit.simulate_raw(pb, fr.effects, v, fr.dead)
    return float((fr.values["K"] if fr.K_solved else 1.0) * s[-1] + fr.values["pc0"])

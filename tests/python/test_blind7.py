# SPDX-License-Identifier: MIT
"""Blind seed 7's two-effect misses (issue 8, branch blind7): a verdict that
names nothing on a record far above its noise floor says so, and says that
an effect large on the fit part was refused, not that nothing was material.
evidence.verdict is called on stand-in tests: the sentence depends only on
the tests' guard figures, the baseline's held-out NRMSE and the floor."""
from types import SimpleNamespace

from pneufrac_fit import evidence, guards

PB = SimpleNamespace(setup=SimpleNamespace(fs=1000.0, oversample=2, fs_int=1000))
BASE = SimpleNamespace(nrmse_val=0.2326)
EVB = {"ccf_out": 25}          # the baseline's whitened residual depends on the input


def _test(effect, val, lr, peak, snr, reasons):
    t = guards.Test(effect, SimpleNamespace(nrmse_val=val), SimpleNamespace(nrmse_val=0.2326))
    t.lr, t.excludes, t.peak, t.snr, t.reasons = lr, lr > guards.Z95 ** 2, peak, snr, reasons
    t.dbic = -lr
    return t


def _verdict(tests, floor=0.0264):
    return evidence.verdict([], BASE, BASE, tests, [], EVB, EVB, PB, floor)


def test_large_effect_refused_by_held_out_is_not_called_immaterial():
    # two-dead_time-saturation-p-7 with the held-out tail: the saturation is
    # 32 noise sd and significant on the fit part, refused only because it
    # predicts the tail (levels the fit part never reached) worse
    sat = _test("saturation", 0.3157, 17368.0, 32.5, 33173.0,
                ["the held-out error falls by -83.9 % (need > 5 %)"])
    small = _test("backlash", 0.2395, -16.0, 0.01, 1.4, ["its 95 % interval includes the "
                                                         "no-effect value"])
    last = _verdict([sat, small])[-1]
    assert "cannot name" in last
    assert "8.8x the noise floor" in last
    assert "saturation is significant and material" in last
    assert "backlash" not in last
    assert "materially" not in last


def test_only_small_effects_still_read_not_material():
    # every tested effect below the size guards: "not material" is true
    lag = _test("lag", 0.0558, 65.0, 5.1, 79.4, ["its contribution's energy is 79.4 noise "
                                                  "variances (need 100)"])
    last = _verdict([lag], floor=0.0125)[-1]
    assert "no catalogued cause explains it materially" in last
    assert "0.2326" in last and "18.6x the noise floor 0.0125" in last


def test_an_unnamed_effect_that_passes_is_not_called_refused():
    # the review of blind7: an effect that passes every guard but is left
    # unnamed (the record cannot tell it from an imitator, said first) is
    # not "refused by the held-out part or BIC"
    sat = _test("saturation", 0.0300, 17368.0, 32.5, 33173.0, [])
    sat.passes = True
    nozzle = _test("nozzle", 0.0310, 9000.0, 20.0, 800.0, [])
    nozzle.passes = True
    out = evidence.verdict([], BASE, BASE, [sat, nozzle], [], EVB, EVB, PB, 0.0264,
                           ["saturation or nozzle: the record cannot tell which."])
    last = out[-1]
    assert "saturation, nozzle pass every guard" in last
    assert "refused" not in last

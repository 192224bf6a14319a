# SPDX-License-Identifier: MIT
"""The input's timing (baseline.input_timing): a record whose converters
average each channel over the period before its stamp (an integrating ADC,
a DAQ's boxcar mean; the independent simulator's acquisition) of an input
whose edges fall anywhere within a period has its input taken half a
sample earlier; a record whose input changes at the stamps themselves (a
setpoint written on the recorder's clock; the own generator's records)
keeps its input as stamped.

The plant is the library at 16x the data rate, driven by a PRBS, for a dd
controller with a fast relay: its derivative action turns every edge into
a spike of the output, where the two conventions differ most. Before this
rule the independent simulator's nozzle-real seed 5 (dd, PRBS) missed the
true model by 2.8 noise sd rms at its edges, and its nozzle failed the
held-out guard."""
import numpy as np

from pneufrac_fit import baseline, data, diagnose, fit, lib, model

FS = 1000.0
M = 16          # plant steps per data sample
N = 5000


def _record(at_stamps: bool, seed: int = 3):
    rng = np.random.default_rng(seed)
    p = lib.default_params("dd")
    p.update(tau=1e-3, RC=0.02)
    # a PRBS of 15-35 ms bits after a 0.3 s rest, its edges at any fine
    # step, or at the data samples' stamps
    nf = N * M
    e_fine = np.zeros(nf)
    t = int(0.3 * FS * M)
    level = 1.0
    while t < nf:
        e_fine[t:] = level
        level = -level if rng.uniform() < 0.5 else level
        t += int(rng.integers(int(0.015 * FS * M), int(0.035 * FS * M)))
        if at_stamps:
            t = -(-t // M) * M
    y_fine = lib.Controller("dd", p, {}, FS * M).run(e_fine)
    if at_stamps:          # as the own generator samples: the stamp's instant
        e, y = e_fine[::M], y_fine[::M]
    else:                  # the mean over (t - 1/fs, t], both channels
        e = np.r_[e_fine[0], e_fine[1:1 + (N - 1) * M].reshape(N - 1, M).mean(axis=1)]
        y = np.r_[y_fine[0], y_fine[1:1 + (N - 1) * M].reshape(N - 1, M).mean(axis=1)]
    y = y + rng.normal(0.0, 0.005 * float(np.ptp(y)), y.size)
    return data.make_record(np.arange(N) / FS, e, y)


def _baseline(rec):
    split, _ = data.split_for(rec)
    pb = fit.Problem.from_record(rec, "dd", None, 8, model.auto_oversample(rec.fs), split)
    diagnose._noise_from_rest(rec, pb)
    e_stamped = pb.e_abs.copy()
    best, _, _, notes, _ = baseline.fit_baseline(pb, np.random.default_rng(0), lambda s: None)
    return pb, e_stamped, best, notes


def test_advanced_half_is_the_mean_of_a_sample_and_the_next():
    e = np.array([0.0, 1.0, 1.0, 3.0])
    assert np.array_equal(baseline.advanced_half(e), [0.5, 1.0, 2.0, 3.0])


def test_averaging_converters_take_the_input_half_a_sample_earlier():
    pb, e_stamped, best, notes = _baseline(_record(at_stamps=False))
    assert np.allclose(pb.e_abs, baseline.advanced_half(e_stamped))
    assert any("half a sample earlier" in s for s in notes), notes


def test_an_input_that_changes_at_the_stamps_is_kept_as_stamped():
    pb, e_stamped, best, notes = _baseline(_record(at_stamps=True))
    assert np.array_equal(pb.e_abs, e_stamped)
    assert not any("half a sample earlier" in s for s in notes), notes

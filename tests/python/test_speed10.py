# SPDX-License-Identifier: MIT
"""Slow records' exploration copy bounded by simulation steps (branch
speed10): a record below 1 kHz is simulated at many steps a sample
(model.F_SIM_MIN), and its copy was 6000 samples whatever that multiple;
the copy is now cut at search.EXPLORE_STEPS steps, never below a fit's
samples after the longest delay scanned. A copy of a record at 1 kHz or
faster stays exactly as it was."""
import numpy as np

from pneufrac_fit import candidates, data, excite, fit, generate, model, search


def _problem(fs, n):
    # steps held 5-20 samples at every rate (the generator's 0.06-0.4 s
    # are 1-4 samples at 10 Hz, which make_record reads as noise)
    rng = np.random.default_rng(3)
    e = excite.steps(n, fs, rng, hold=(5 / fs, 20 / fs), rest=10 / fs)
    ds = generate.generate("p", n=n, fs=fs, noise=0.005, seed=10, e=e,
                           oversample=model.auto_oversample(fs), order=5)
    rec = data.make_record(ds.t, ds.e, ds.pc)
    return fit.Problem.from_record(rec, "p", {"q": 0.0, "beta": 1.0}, 8,
                                   model.auto_oversample(rec.fs))


def _steps(q):
    return q.nsim * q.setup.oversample


def test_fast_records_copy_unchanged():
    # 1 kHz (2 steps a sample) and 10 kHz (averaged to 1 kHz): the first
    # N_EXPLORE samples of the copy's rate, as before the bound
    for fs, n in ((1000.0, 12000), (1500.0, 12000), (10000.0, 80000)):
        pb = _problem(fs, n)
        D = int(pb.setup.fs // search.F_EXPLORE)    # the stamps' rate: 9 or 10 at 10 kHz
        q = search.explorer(pb)
        assert q.nsim == search.N_EXPLORE
        assert np.array_equal(q.y, pb.y[:search.N_EXPLORE * D].reshape(-1, D).mean(axis=1))
        assert _steps(q) == 2 * search.N_EXPLORE


def test_slow_record_copy_bounded_by_steps():
    # 100 Hz, simulated at 20 steps a sample: 600 samples (6 s, as a 1 kHz
    # record's copy), not 6000 (120 000 steps)
    pb = _problem(100.0, 20000)
    q = search.explorer(pb)
    assert pb.setup.oversample == 20
    assert q.nsim == 600 and _steps(q) == 12000
    assert abs(q.setup.duration - 6.0) < 1e-9


def test_very_slow_record_copy_keeps_a_fits_samples():
    # 10 Hz, 200 steps a sample: 6 s is 60 samples, too few; the copy keeps
    # MIN_SAMPLES after the longest delay scanned (it was the whole record)
    pb = _problem(10.0, 3000)
    q = search.explorer(pb)
    assert q is not None
    floor = data.MIN_SAMPLES + candidates.dead_max(pb) // pb.setup.oversample
    assert q.nsim == floor < pb.nsim
    assert _steps(q) > 12000


def test_short_slow_record_has_no_copy():
    # within 1.3 x its copy's samples a record is explored whole
    pb = _problem(100.0, 1000)
    assert pb.nsim <= 1.3 * 600
    assert search.explorer(pb) is None

# SPDX-License-Identifier: MIT
"""Slow records' exploration copy bounded by time (branches speed10,
fixs10): a record below 1 kHz is simulated at many steps a sample
(model.F_SIM_MIN), and its copy was 6000 samples whatever that multiple;
it now counts the 6 s a 1 kHz record's copy spans (search.copy_samples),
after the whole fit's burn, never below a fit's samples after the longest
delay scanned. A copy of a record at 1 kHz or faster, or whose rate is
estimated a hair under 1 kHz, stays exactly as it was."""
import numpy as np

from pneufrac_fit import candidates, data, excite, fit, generate, model, search


def _problem(fs, n, t=None, rest=True):
    # steps held 5-20 samples at every rate (the generator's 0.06-0.4 s
    # are 1-4 samples at 10 Hz, which make_record reads as noise)
    rng = np.random.default_rng(3)
    e = excite.steps(n, fs, rng, hold=(5 / fs, 20 / fs), rest=10 / fs)
    ds = generate.generate("p", n=n, fs=fs, noise=0.005, seed=10, e=e,
                           oversample=model.auto_oversample(fs), order=5)
    k = 0 if rest else 200     # without its opening rest, the record has a burn
    rec = data.make_record(ds.t[k:] - ds.t[k] if t is None else t[:n - k],
                           ds.e[k:], ds.pc[k:])
    return fit.Problem.from_record(rec, "p", {"q": 0.0, "beta": 1.0}, 8,
                                   model.auto_oversample(rec.fs))


def _steps(q):
    return q.nsim * q.setup.oversample


def test_fast_records_copy_unchanged():
    # 1 kHz (2 steps a sample), 1.5 kHz and 10 kHz (averaged to 1 kHz), and
    # 1 kHz stamps whose estimated rate falls a hair short of 1 kHz (a clock
    # 1 ppm slow; stamps with jitter), simulated at 3 steps a sample: the
    # first N_EXPLORE samples of the copy's rate, as before the bound
    n = 12000
    rng = np.random.default_rng(5)
    slow_clock = np.arange(n) / 999.999
    jittered = np.arange(n) / 1000.0 + rng.normal(0, 1e-5, n)
    for fs, n, t in ((1000.0, n, None), (1500.0, n, None), (10000.0, 80000, None),
                     (1000.0, n, slow_clock), (1000.0, n, jittered)):
        pb = _problem(fs, n, t)
        D = max(1, int(pb.setup.fs // search.F_EXPLORE))   # 9 or 10 at 10 kHz
        q = search.explorer(pb)
        assert q.nsim == search.N_EXPLORE, (fs, pb.setup.fs)
        assert np.array_equal(q.y, pb.y[:search.N_EXPLORE * D].reshape(-1, D).mean(axis=1))
    # a rate read within what stamps can tell of 1 kHz (model.FS_RTOL) is
    # simulated at 1 kHz's 2 steps a sample since tidy28 (3 before)
    assert _problem(1000.0, n, slow_clock).setup.oversample == 2


def test_slow_record_copy_spans_a_fast_records_copy():
    # 100 Hz, simulated at 20 steps a sample: the copy counts 600 samples
    # (6 s, as a 1 kHz record's copy), after the whole fit's burn (the
    # start's free response: these records open without a rest long enough
    # to set the operating point), not 6000 (120 000 steps each)
    for rest in (True, False):
        pb = _problem(100.0, 20000, rest=rest)
        q = search.explorer(pb)
        assert pb.setup.oversample == 20 and pb.burn > 0
        assert q.burn == pb.burn              # it counts what the whole fit counts
        counted = q.nsim - q.burn
        assert counted >= 600 and (counted == 600 or q.nsim == 2 * q.burn)
        assert _steps(q) < search.N_EXPLORE * 20 / 2


def test_very_slow_record_copy_keeps_a_fits_samples():
    # 10 Hz, 200 steps a sample: 6 s is 60 samples, too few; the copy keeps
    # MIN_SAMPLES after the longest delay scanned (it was the whole record)
    pb = _problem(10.0, 3000)
    q = search.explorer(pb)
    assert q is not None
    assert q.nsim - q.burn - candidates.dead_max(pb) // pb.setup.oversample >= data.MIN_SAMPLES
    assert q.nsim < pb.nsim and _steps(q) > 12000


def test_short_slow_record_has_no_copy():
    # within 1.3 x its copy's samples a record is explored whole
    pb = _problem(100.0, 1000)
    assert pb.nsim <= 1.3 * 600
    assert search.explorer(pb) is None

# SPDX-License-Identifier: MIT
"""The exploration copy is counted in samples at every rate
(search.explorer): N_EXPLORE samples of the copy's rate, for a record at
1 kHz or faster, for one whose rate is estimated a hair under 1 kHz
(a slow clock, jittered stamps), and for a slow record simulated at many
steps a sample. Branches speed10/fixs10 cut a slow record's copy to the
6 s a 1 kHz copy spans; branch speed11 measured a 100 Hz pid record with
a 0.1 s lag whose right verdict that cut lost (its baseline's search
ended in a worse optimum), so the cut was taken back."""
import numpy as np

from pneufrac_fit import data, excite, fit, generate, model, search


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


def _first_samples(pb, q, D):
    assert q.nsim == search.N_EXPLORE, (pb.setup.fs, q.nsim)
    assert np.array_equal(q.y, pb.y[:search.N_EXPLORE * D].reshape(-1, D).mean(axis=1))


def test_fast_records_copy_its_first_samples():
    # 1 kHz (2 steps a sample), 1.5 kHz and 10 kHz (averaged by 10 to 1 kHz;
    # at this length its stamps read 10000.000000000002 Hz: a rate read a
    # hair low is test_tidy29's case), and
    # 1 kHz stamps whose estimated rate falls a hair short of 1 kHz (a clock
    # 1 ppm slow; stamps with jitter)
    n = 12000
    rng = np.random.default_rng(5)
    slow_clock = np.arange(n) / 999.999
    jittered = np.arange(n) / 1000.0 + rng.normal(0, 1e-5, n)
    for fs, n, t in ((1000.0, n, None), (1500.0, n, None), (10000.0, 100000, None),
                     (1000.0, n, slow_clock), (1000.0, n, jittered)):
        pb = _problem(fs, n, t)
        _first_samples(pb, search.explorer(pb), 10 if fs == 10000.0 else 1)


def test_slow_record_copy_holds_as_many_samples():
    # 100 Hz, simulated at 20 steps a sample, with and without an opening
    # rest: the copy holds N_EXPLORE samples, as a 1 kHz record's does, not
    # the 6 s (600 samples) a 1 kHz copy spans
    for rest in (True, False):
        pb = _problem(100.0, 20000, rest=rest)
        assert pb.setup.oversample == 20
        _first_samples(pb, search.explorer(pb), 1)


def test_short_slow_record_has_no_copy():
    # within 1.3 x N_EXPLORE samples a record is explored whole, at any rate
    pb = _problem(10.0, 3000)
    assert pb.nsim <= 1.3 * search.N_EXPLORE
    assert search.explorer(pb) is None

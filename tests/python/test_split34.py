# SPDX-License-Identifier: MIT
"""The held-out split's coverage of the input's frequencies (data.uncovered's
second test, holdout.band_outside_share): a tail whose input varies at
frequencies the fit part's input hardly had (the fast end of a sine sweep)
is an extrapolation in frequency, and `--holdout cover` takes the held-out
blocks; inputs whose two parts are alike in content (steps, PRBS, a sweep
that comes back down) keep the tail. The records are made here, by a
first-order response, not by the project's simulators."""
import numpy as np

from pneufrac_fit import data, holdout

N, FS = 20000, 1000.0
T = np.arange(N) / FS


def _record(e, name, seed=0, sd=2e-3):
    """A first-order response (time constant 20 ms) to e (any length, at
    FS), white noise of sd on both signals."""
    rng = np.random.default_rng(seed)
    n = e.size
    a = np.exp(-1.0 / (0.02 * FS))
    y = np.empty(n)
    acc = 0.0
    for k in range(n):
        acc = a * acc + (1.0 - a) * e[k]
        y[k] = acc
    return data.make_record(np.arange(n) / FS, e + sd * rng.normal(size=n),
                            0.2 + 0.05 * y + sd * rng.normal(size=n), name)


def _log_sweep(f0, f1, t, dur):
    """A sine sweep whose frequency goes from f0 to f1 geometrically over dur."""
    k = np.log(f1 / f0) / dur
    return np.sin(2 * np.pi * f0 * (np.exp(k * t) - 1.0) / k)


def _band(rec, mode):
    return holdout.band_outside_share(rec.e, holdout.layout(rec.n, mode), rec.sig_e ** 2,
                                      data.MAX_OUTSIDE / 2)


def _steps(rng, levels, n_steps):
    """Piecewise-constant input through levels at random instants; the first
    two steps visit the extremes, so the tail's levels are the fit part's."""
    cuts = np.sort(rng.choice(np.arange(200, N - 200), n_steps, replace=False))
    seq = np.r_[np.min(levels), np.max(levels), rng.choice(levels, n_steps - 1)]
    return seq[np.searchsorted(cuts, np.arange(N), side="right")]


def test_sweep_whose_tail_holds_the_fast_end_is_split_as_blocks():
    rec = _record(_log_sweep(0.1, 5.0, T, T[-1]), "sweep-up")
    tail = holdout.layout(N, "tail")
    assert data.outside(rec, tail)[0] <= data.MAX_OUTSIDE     # the levels are covered
    assert _band(rec, "tail") > 0.9                          # the frequencies are not
    assert _band(rec, "blocks") < data.MAX_BAND_OUTSIDE
    split, why = data.split_for(rec)
    assert split == holdout.layout(N, "blocks")
    assert "frequencies" in why and "held-out tail refused" in why


def test_sweep_whose_tail_holds_the_slow_end_is_split_as_blocks():
    rec = _record(_log_sweep(5.0, 0.1, T, T[-1]), "sweep-down")
    assert _band(rec, "tail") > data.MAX_BAND_OUTSIDE
    assert data.split_for(rec)[0] == holdout.layout(N, "blocks")


def test_sweep_asked_for_the_tail_keeps_it_and_says_it_extrapolates():
    rec = _record(_log_sweep(0.1, 5.0, T, T[-1]), "sweep-up")
    split, why = data.split_for(rec, "tail")
    assert split == holdout.layout(N, "tail")
    assert "frequencies" in why and "extrapolation" in why and "--holdout cover" in why


def test_sweep_whose_fit_part_covers_the_held_out_frequencies_keeps_the_tail():
    """Up from 0.1 to 5 Hz over the first half, back down over the second:
    the tail's frequencies (below those at 70 %) were all in the fit part."""
    half = T[-1] / 2
    up = _log_sweep(0.1, 5.0, T, half)
    k = np.log(50.0) / half
    phase_half = 2 * np.pi * 0.1 * (np.exp(k * half) - 1.0) / k
    down = np.sin(phase_half + 2 * np.pi * 5.0 * (1.0 - np.exp(-k * (T - half))) / k)
    rec = _record(np.where(T < half, up, down), "sweep-up-down")
    assert _band(rec, "tail") < data.MAX_BAND_OUTSIDE
    assert data.split_for(rec) == (holdout.layout(N, "tail"), None)


def test_random_steps_keep_the_tail():
    for seed in range(3):
        rng = np.random.default_rng(10 + seed)
        rec = _record(_steps(rng, np.linspace(-1, 1, 5), 30), f"steps-{seed}", seed)
        assert _band(rec, "tail") < data.MAX_BAND_OUTSIDE
        assert data.split_for(rec) == (holdout.layout(N, "tail"), None)


def test_prbs_keeps_the_tail():
    for seed in range(3):
        rng = np.random.default_rng(20 + seed)
        bits = rng.integers(0, 2, N // 50) * 2.0 - 1.0      # a new level every 50 ms
        bits[:2] = (-1.0, 1.0)
        rec = _record(np.repeat(bits, 50), f"prbs-{seed}", seed)
        assert _band(rec, "tail") < data.MAX_BAND_OUTSIDE
        assert data.split_for(rec) == (holdout.layout(N, "tail"), None)


def test_noise_alone_is_not_content():
    """A held-out part that only adds white noise on the same steps keeps
    its share: the noise is taken out before the content is compared."""
    rng = np.random.default_rng(3)
    e = _steps(rng, np.linspace(-1, 1, 5), 30)
    quiet = _record(e, "quiet", sd=1e-4)
    noisy = _record(e, "noisy", sd=2e-2)
    assert _band(noisy, "tail") < data.MAX_BAND_OUTSIDE
    assert abs(_band(noisy, "tail") - _band(quiet, "tail")) < 0.1


def test_a_side_with_only_noise_has_no_band():
    """White noise is not content: a signal of noise alone, or a tail where
    the input rests under its noise after a slow sine in the fit part, reads 0
    (holdout.CONTENT_FLOOR), where the noise bins left after the noise is
    taken off would put the held-out content at random frequencies."""
    split = holdout.layout(4000, "tail")
    rng = np.random.default_rng(0)
    assert holdout.band_outside_share(np.zeros(4000), split, 1.0, 0.025) == 0.0
    x = rng.normal(size=4000)
    assert holdout.band_outside_share(x, split, 1.0, 0.025) == 0.0
    x[:2800] += 20.0 * np.sin(2 * np.pi * np.arange(2800) / 800)   # the fit part only
    assert holdout.band_outside_share(x, split, 1.0, 0.025) == 0.0
    x[2800:] += 20.0 * np.sin(2 * np.pi * np.arange(1200) / 40)    # the tail 20x faster
    assert holdout.band_outside_share(x, split, 1.0, 0.025) > data.MAX_BAND_OUTSIDE


def _levels_then_tone():
    """Steps, but each held-out block of the blocks layout holds a fast tone
    alone, and the tail (outside every block) goes to a new level."""
    rng = np.random.default_rng(4)
    e = _steps(rng, [-1.0, -0.5, 0.0, 0.5, 1.0], 40)
    for start, stop in holdout.layout(N, "blocks").held:
        e[start:stop] = 0.5 * np.sin(2 * np.pi * 20.0 * T[start:stop])
    e[int(0.7 * N):int(0.9 * N)] = 1.8
    return _record(e, "levels-then-tone")


def test_no_switch_from_a_level_extrapolation_to_a_frequency_one():
    """The tail goes outside the fit part's levels; the blocks stay within
    their fit parts' levels but each held-out block holds a fast tone the
    fit parts never had. Step 4 weighs levels only, so it must not take
    the blocks (one extrapolation for another, unweighed): the tail stays,
    and its note says it extrapolates."""
    rec = _levels_then_tone()
    blocks = holdout.layout(N, "blocks")
    tail = holdout.layout(N, "tail")
    # the premise: the tail fails on levels, the blocks only on frequency
    assert data.outside(rec, tail)[0] > data.MAX_OUTSIDE
    assert data.outside(rec, tail)[0] - data.outside(rec, blocks)[0] > data.MAX_OUTSIDE
    assert _band(rec, "blocks") > data.MAX_BAND_OUTSIDE
    split, why = data.split_for(rec)
    assert split == tail
    assert "extrapolation" in why


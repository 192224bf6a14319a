# SPDX-License-Identifier: MIT
"""The held-out split's coverage of the levels (data.split_for,
data.uncovered, holdout.outside_share): a held-out part whose input or
output goes where its fit parts never went is an extrapolation; the report
says so, and `--holdout cover` takes the split whose held-out samples stay
at its fit parts' levels; computed from the record alone, before any fit."""
import numpy as np

from pneufrac_fit import data, holdout, signals

N, FS = 6000, 1000.0


def _record(levels, name, pc_extra=None, seed=0, sd=1e-3):
    """Input steps through `levels` (equal stretches), a first-order
    response as output, white noise of sd on both."""
    rng = np.random.default_rng(seed)
    e = np.repeat(np.asarray(levels, float), -(-N // len(levels)))[:N]
    e = e + sd * rng.normal(size=N)
    pc = 0.1 + 0.02 * np.convolve(e, np.full(30, 1 / 30))[:N] + sd * rng.normal(size=N)
    if pc_extra is not None:
        pc = pc + pc_extra
    return data.make_record(np.arange(N) / FS, e, pc, name)


def test_outside_share_counts_held_out_samples_beyond_the_fit_range():
    split = holdout.layout(10, "tail")                    # fit 0..6, held 7..9
    x = np.array([0, 1, 2, 3, 2, 1, 0, 3.05, 3.5, -1.0])
    assert holdout.outside_share(x, split, 0.1) == 2 / 3  # 3.05 is within the margin
    assert holdout.outside_share(x, split, 2.0) == 0.0


def test_tail_at_levels_the_fit_part_never_reached_takes_the_blocks_with_cover():
    """The blind simulator's two-dead_time-saturation-p-5 kind: steps in
    the last 30 % go below every level of the first 70 %. With --holdout
    cover the held-out blocks, whose last fit part holds that level
    (4200-5400) and whose last block (5400-6000) does not go beyond, are
    taken, and the note says why; with the default the tail stays and the
    note says that it extrapolates and that the blocks would not."""
    rec = _record([0, 1, -1, 0.5, -0.5, 1, 0, -2.0, -2.0, 0.5], "new-level-in-tail")
    assert data.uncovered(rec, holdout.layout(N, "tail")) is not None
    split, why = data.split_for(rec, "cover")
    assert split == holdout.layout(N, "blocks")
    assert "held-out tail refused" in why and "input e outside the range" in why
    assert "each third" in why
    split, why = data.split_for(rec, holdout.DEFAULT)
    assert split == holdout.layout(N, "tail")
    assert "input e outside the range" in why and "extrapolation" in why
    assert "--holdout cover" in why and "each third" in why


def test_output_beyond_the_fit_range_counts_too():
    """The input stays at visited levels, the output does not (a slow
    rise through the tail, 50 noise sd above anything the fit part saw)."""
    tail = holdout.layout(N, "tail")
    extra = np.zeros(N)
    a = tail.held[0][0]
    extra[a:] = np.linspace(0, 0.05, N - a)
    rec = _record([0, 1, -1, 0.5, -0.5, 1, 0, -1, 0.5, 0], "output-drifts-in-tail",
                  pc_extra=extra)
    assert "output pc outside the range" in data.uncovered(rec, tail)


def test_tail_within_the_fit_levels_is_kept_without_a_note():
    """Every held-out level was visited by the fit part: the default
    stands, silently; noise alone (the margin of REST_SIGMAS noise sd)
    does not refuse it."""
    rec = _record([0, 1, -1, 0.5, -0.5, 1, 0, -1, 0.5, -0.5], "levels-covered")
    for mode in ("tail", "cover"):
        assert data.split_for(rec, mode) == (holdout.layout(N, "tail"), None)
    assert signals.REST_SIGMAS >= 4        # the margin keeps noise out of the share


def test_no_split_covers_a_ramp_so_the_asked_one_stays_with_a_note():
    """A ramp rises through the whole record: every split's held-out part
    is above its fit part's levels, so none is better; the split asked
    for stays and the note says the held-out error includes an
    extrapolation."""
    rng = np.random.default_rng(3)
    e = np.linspace(0, 1, N) + 1e-3 * rng.normal(size=N)
    pc = 0.1 + 0.02 * e + 1e-3 * rng.normal(size=N)
    rec = data.make_record(np.arange(N) / FS, e, pc, "ramp")
    for mode in ("tail", "cover"):
        split, why = data.split_for(rec, mode)
        assert split == holdout.layout(N, "tail")
        assert "no other split" in why and "extrapolation" in why

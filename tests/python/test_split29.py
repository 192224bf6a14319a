# SPDX-License-Identifier: MIT
"""The held-out split's coverage of the levels (data.split_for,
data.uncovered, holdout.outside_share): a held-out part whose input or
output goes where its fit parts never went is an extrapolation; the report
says so, and `--holdout cover` takes the split whose held-out samples stay
at its fit parts' levels; computed from the record alone, before any fit."""
import numpy as np
import pytest

from pneufrac_fit import data, holdout

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
    cover the held-out blocks, whose held-out samples all lie within the
    levels of their fit parts (the last fit part, 4200-5400, holds -2), are
    taken, and the note says why; that is the default. Asked for the tail,
    the tail stays and the note says that it extrapolates and that the
    blocks would not."""
    rec = _record([0, 1, -1, 0.5, -0.5, 1, 0, -2.0, -2.0, 0.5], "new-level-in-tail")
    assert data.uncovered(rec, holdout.layout(N, "tail")) is not None
    split, why = data.split_for(rec, "cover")
    assert split == holdout.layout(N, "blocks")
    assert "held-out tail refused" in why and "input e outside the range" in why
    assert "each third" in why
    assert holdout.DEFAULT == "cover"
    split, why = data.split_for(rec, "tail")
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
    stands, silently."""
    rec = _record([0, 1, -1, 0.5, -0.5, 1, 0, -1, 0.5, -0.5], "levels-covered")
    for mode in ("tail", "cover"):
        assert data.split_for(rec, mode) == (holdout.layout(N, "tail"), None)


def test_no_split_covers_a_ramp_so_the_asked_one_stays_with_a_note():
    """A ramp rises through the whole record: every split's held-out part
    goes above its fit parts' levels; the split asked for stays and the
    note says the held-out error includes an extrapolation. Under
    --holdout cover the blocks are taken (extrap31): only their last block
    lies above their fit parts' levels (a third of their held-out samples,
    against all of the tail's), and their note still says they
    extrapolate."""
    rng = np.random.default_rng(3)
    e = np.linspace(0, 1, N) + 1e-3 * rng.normal(size=N)
    pc = 0.1 + 0.02 * e + 1e-3 * rng.normal(size=N)
    rec = data.make_record(np.arange(N) / FS, e, pc, "ramp")
    split, why = data.split_for(rec, "tail")
    assert split == holdout.layout(N, "tail")
    assert "does not keep them within its fit parts' levels and input frequencies either" in why
    assert "held-out blocks" in why and "extrapolation" in why
    split, why = data.split_for(rec, "cover")
    assert split == holdout.layout(N, "blocks")
    assert why.startswith("the held-out tail refused") and "extrapolation" in why


def _static(e, name, sd_e=1e-3, sd_pc=1e-3, seed=0):
    """A record of the input e (noise-free levels) with white noise of sd_e,
    and an output that follows it at once (pc = 0.1 + 0.02 e) with white
    noise of sd_pc: the output holds every level the input holds, however
    briefly."""
    rng = np.random.default_rng(seed)
    e = np.asarray(e, float)
    n = e.size
    pc = 0.1 + 0.02 * e + sd_pc * rng.normal(size=n)
    return data.make_record(np.arange(n) / FS, e + sd_e * rng.normal(size=n), pc, name)


def _steps(*stretches):
    """N samples of levels: (start, level) pairs, each held to the next."""
    e = np.zeros(N)
    for a, level in stretches:
        e[a:] = level
    return e


def test_noise_alone_does_not_make_a_level_the_fit_part_visited_briefly_uncovered():
    """The fit part reaches the top level for 3 samples only, the tail
    holds it for 900: the fit part's maximum there is that of 3 noise
    samples, which about half the tail's samples exceed. The margin
    (REST_SIGMAS noise sd plus one ADC step) is what keeps the tail
    covered: a level is the same level within the noise."""
    e = _steps((0, 0), (1000, -1), (2000, 1), (2003, 0.5), (3000, -0.5), (4200, 1), (5100, 0))
    rec = _static(e, "brief-top-in-fit-part")
    tail = holdout.layout(N, "tail")
    assert holdout.outside_share(rec.e, tail, 0.0) > data.MAX_OUTSIDE     # the premise
    assert data.uncovered(rec, tail) is None
    assert data.split_for(rec, "cover") == (tail, None)


def test_the_output_is_judged_with_its_own_noise():
    """The output's noise is 10x the input's; the tail's output sits 4 of
    its noise sd above the level the fit part held there: within the
    output's margin, far beyond the input's."""
    tail = holdout.layout(N, "tail")
    e = _steps((0, 0), (800, 1), (1600, -1), (2400, 0.5), (3200, 1), (4200, 0), (4400, 1))
    rec = _static(e, "output-noisier", sd_e=1e-3, sd_pc=1e-2)
    a = tail.held[0][0]
    pc = rec.pc.copy()
    pc[a:] += 0.04
    rec = data.make_record(rec.t, rec.e, pc, "output-noisier")
    assert rec.sig_pc > 5 * rec.sig_e
    assert holdout.outside_share(rec.pc, tail, 5 * rec.sig_e + rec.q_e) > data.MAX_OUTSIDE
    assert data.uncovered(rec, tail) is None


def test_a_held_out_block_at_a_level_only_a_later_fit_part_reached_is_covered():
    """The levels the blocks are judged against are those of all their fit
    parts: the first held-out block (1400-2000) goes to -2, which the
    first fit part never reaches and the second (2000-3400) does."""
    blocks = holdout.layout(N, "blocks")
    assert blocks.held[0] == (1400, 2000)
    e = _steps((0, 0), (500, 1), (1000, -1), (1500, -2), (1800, 0.5), (2200, -2),
               (2600, 0), (3000, 1), (3600, 0), (4300, 0.5), (4800, -1), (5600, 0))
    rec = _static(e, "later-fit-part")
    first = holdout.Split(N, ((1400, N),))                   # the first fit part's levels
    assert holdout.outside_share(rec.e, first, 0.1) > data.MAX_OUTSIDE
    assert data.uncovered(rec, blocks) is None


def test_a_level_one_adc_step_beyond_the_fit_range_is_covered():
    """A quantised input (steps of 1/64, nothing but the quantisation as
    noise: noise sd q/sqrt 12) ramps through its range in the fit part;
    the tail goes to 2 steps above the top code. The margin is 5 noise sd
    plus one step (2.44 steps): within it; without the step (1.44) not."""
    q = 1 / 64
    tail = holdout.layout(N, "tail")
    a = tail.held[0][0]
    x = np.concatenate([np.linspace(0, 1, a // 2), np.linspace(1, 0, a - a // 2)])
    x = np.concatenate([x, np.where(np.arange(N - a) % 600 < 300, 1 + 2 * q, 0.5)])
    rec = _static(np.round(x / q) * q, "adc-step-beyond", sd_e=0.0)
    assert rec.q_e == q
    assert holdout.outside_share(rec.e, tail, 5 * rec.sig_e) > data.MAX_OUTSIDE
    # the levels' test alone: the frequency test is not this test's subject.
    # It reads this tail's square wave 21 % outside its fit part's band
    # (under the half: covered), but only because the wave's fundamental,
    # 1.67 Hz, falls in the band's top bin (bins of 0.56 Hz); nothing pins that.
    assert data.outside(rec, tail)[0] <= data.MAX_OUTSIDE


def test_the_note_names_the_layout_used_and_every_mode():
    """On a record too short for held-out blocks (1500 samples, one
    section) asking for the blocks gives the tail, and the note names the
    tail and says that no other split exists; an unknown mode names every
    mode, cover too."""
    n = 1500
    e = np.repeat([0, 1, -1, 2.0], n // 4)
    rng = np.random.default_rng(5)
    rec = data.make_record(np.arange(n) / FS, e + 1e-3 * rng.normal(size=n),
                           0.1 + 0.02 * e + 1e-3 * rng.normal(size=n), "short")
    assert holdout.layout(n, "blocks") == holdout.layout(n, "tail")
    split, why = data.split_for(rec, "blocks")
    assert split == holdout.layout(n, "tail")
    assert why.startswith("the held-out tail: ") and "its fit part visited" in why
    assert "too short for another split" in why and "blocks" not in why
    with pytest.raises(ValueError, match="blocks, tail, cover"):
        data.split_for(rec, "x")

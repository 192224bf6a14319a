# SPDX-License-Identifier: MIT
"""When neither split covers its held-out levels, --holdout cover (the
default) takes the one whose held-out samples lie outside its fit parts'
levels by a clearly smaller share (data.split_for's step 4,
data._extrapolates_less); within MAX_OUTSIDE of each other the tail
stays."""
import numpy as np
from scipy.signal import lfilter

from pneufrac_fit import data, holdout, signals

N, FS = 6000, 1000.0
T = np.arange(N) / FS


def _record(levels, name):
    """A step record: levels is a list of (start, level) from which the
    input holds each level; the output follows it through a fast lag, both
    with white noise of sd 1e-3."""
    rng = np.random.default_rng(7)
    e = np.zeros(N)
    for (a, lev), (b, _) in zip(levels, levels[1:] + [(N, None)]):
        e[a:b] = lev
    e = e + 1e-3 * rng.normal(size=N)
    pc = 0.1 + lfilter([0.1], [1.0, -0.9], e) + 1e-3 * rng.normal(size=N)
    return data.make_record(T, e, pc, name)


# Before the tail (samples 4200 on), the input alternates between 0 and 1
# every 300 samples: every held-out block before the last sees only those.
_FIT = [(a, float((a // 300) % 2)) for a in range(0, 4200, 300)]


def _shares(rec):
    """Each layout's share of held-out samples beyond its fit parts' levels
    by the margin, the larger of the two signals' (data.outside), computed
    here from holdout.outside_share to state each test's premise."""
    return {m: max(holdout.outside_share(x, holdout.layout(N, m), signals.REST_SIGMAS * lsd + q)
                   for x, lsd, q in ((rec.e, rec.level_e, rec.q_e),
                                     (rec.pc, rec.level_pc, rec.q_pc)))
            for m in holdout.LAYOUTS}


def test_neither_covers_and_the_blocks_extrapolate_much_less():
    """Level 2 from 4200 to 5400 is in the blocks' last fit part (4000-5400)
    and beyond the tail's fit part; level 3 at 5400-5700 is new to both.
    The tail has 83 % of its held-out samples outside, the blocks 17 %:
    the blocks are taken, with the note that they still extrapolate."""
    rec = _record(_FIT + [(4200, 2.0), (5400, 3.0), (5700, 1.0)], "blocks-less")
    s = _shares(rec)
    assert s["tail"] > data.MAX_OUTSIDE and s["blocks"] > data.MAX_OUTSIDE   # neither covers
    assert s["tail"] - s["blocks"] > data.MAX_OUTSIDE
    split, why = data.split_for(rec, "cover")
    assert split == holdout.layout(N, "blocks")
    assert why.startswith("the held-out tail refused")
    assert "includes an extrapolation" in why
    # the explicit layouts are not switched
    assert data.split_for(rec, "tail")[0] == holdout.layout(N, "tail")


def test_neither_covers_and_the_shares_are_close_keeps_the_tail():
    """Level 2 at 5400-6000 is new to both splits; a short visit to -1 at
    4200-4220 (in the blocks' fit part, in the tail's held-out part) makes
    the tail's share 3-4 points larger than the blocks': within MAX_OUTSIDE,
    so the tail stays, with its note."""
    rec = _record(_FIT + [(4200, -1.0), (4220, 0.0), (4500, 1.0), (4800, 0.0),
                          (5100, 1.0), (5400, 2.0)], "close")
    s = _shares(rec)
    assert s["tail"] > data.MAX_OUTSIDE and s["blocks"] > data.MAX_OUTSIDE
    assert 0 < s["tail"] - s["blocks"] <= data.MAX_OUTSIDE
    split, why = data.split_for(rec, "cover")
    assert split == holdout.layout(N, "tail")
    assert "includes an extrapolation" in why and "either" in why

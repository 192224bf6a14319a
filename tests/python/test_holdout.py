# SPDX-License-Identifier: MIT
"""The split into fit parts and held-out blocks (holdout.py): its layout,
that no held-out output reaches the fit, and that whitening restarts at
every part."""
import numpy as np
import pytest

import cases
from indepsim.make import make
from pneufrac_fit import baseline, candidates, data, diagnose, fit, holdout, model, noise


@pytest.mark.parametrize("n", [200, 1000, 4999, 5000, 6000, 9999, 10000, 20000, 100003])
def test_layout(n):
    s = holdout.layout(n, "blocks")
    held = s.held_slices()
    fitp = s.fit_slices()
    # every sample is in exactly one part, in time order
    cover = np.zeros(n, int)
    for p in held + fitp:
        cover[p] += 1
    assert np.all(cover == 1)
    assert s.n_fit + s.n_held == n
    assert abs(s.n_held - (1 - holdout.FIT_FRACTION) * n) <= len(held)
    k = len(held)
    if k == 1:
        # too short for blocks: the tail split, unchanged
        assert s.held == ((int(holdout.FIT_FRACTION * n), n),)
        assert holdout.layout(n, "tail") == s
    else:
        assert all(b - a >= holdout.MIN_HELD for a, b in s.held)
        # one held-out block in each k-th of the record
        for j, (a, b) in enumerate(s.held):
            assert j * n // k <= a < b <= (j + 1) * n // k
    assert s.held[0][0] == s.first_end > 0
    assert holdout.layout(n).held == ((int(holdout.FIT_FRACTION * n), n),)   # layout's default: the tail


def test_layout_refuses_an_unknown_mode():
    with pytest.raises(ValueError):
        holdout.layout(1000, "middle")


def test_window_and_scaled_keep_held_samples_out():
    s = holdout.layout(20000, "blocks")
    w = s.window(12000)
    assert w.n == 12000 and all(b <= 12000 for _, b in w.held)
    d = 7
    q = s.scaled(d, 20000 // d)
    # an averaged sample that touches a held-out block is held out
    for a, b in s.held:
        for i in range(a // d, min((b - 1) // d + 1, q.n)):
            assert any(x <= i < y for x, y in q.held)


def test_each_held_out_block_is_centred_on_its_own_level():
    """centre_held removes each held-out block's own mean and leaves the
    fit parts alone; with the tail split that is the held-out part's mean."""
    rng = np.random.default_rng(4)
    n = 20000
    x = rng.normal(size=n)
    s = holdout.layout(n, "blocks")
    levels = x.copy()
    for j, (a, b) in enumerate(s.held):
        levels[a:b] += 10.0 * (j + 1)          # a different level per block
    c = s.centre_held(levels)
    for a, b in s.held:
        assert abs(np.mean(c[a:b])) < 1e-12
        assert np.allclose(c[a:b], x[a:b] - np.mean(x[a:b]))
    for f in s.fit_slices():
        assert np.array_equal(c[f], levels[f])
    t = holdout.layout(n, "tail")
    (a, b), = t.held
    assert np.allclose(t.centre_held(x)[a:b], x[a:b] - np.mean(x[a:b]))


def test_clean_record_with_slow_noise_names_nothing_with_blocks():
    """The independent simulator's clean-p-real seed 2 (p, 5 s of ramps,
    pink noise, 12-bit ADC): with the blocks, a dead band (and a lag, a
    delay, a nozzle) passed every guard on main at dfc86bb. Their held-out
    gain was the three blocks' levels: the pink noise's wander slower than
    a block, which the opening rest stretch (357 samples) does not show
    and which the fit parts on both sides of a block carry into it. With
    each block less its own level (holdout.Split.centre_held) the record
    gives `none`, as every clean record must."""
    rec = make("clean-p-real", 2)
    d = diagnose.diagnose(data.make_record(rec.t, rec.e, rec.pc, "indepsim"),
                          rec.truth["config"], jobs=2, progress=False, holdout="blocks")
    assert len(d.split.held) == 3
    assert d.causes == [], d.why


def test_whitening_restarts_at_every_part():
    rng = np.random.default_rng(2)
    x = rng.normal(size=3000)
    nm = noise.fit(np.cumsum(rng.normal(size=3000)) * 0.1 + rng.normal(size=3000))
    assert nm.order > 0
    parts = [slice(100, 1000), slice(1500, 2200)]
    w = noise.whiten_parts(nm, x, parts)
    assert w.size == sum(p.stop - p.start - nm.order for p in parts)
    y = x.copy()
    y[:100] += 5.0
    y[1000:1500] -= 7.0          # samples outside the parts: nothing changes
    y[2200:] *= 3.0
    assert np.array_equal(noise.whiten_parts(nm, y, parts), w)


def test_noise_model_of_pieces_pairs_no_samples_across_them():
    rng = np.random.default_rng(4)
    a, b = rng.normal(size=2000), rng.normal(size=2000)
    joined = noise.fit(np.r_[a, 50.0 + b])       # a jump between the pieces looks red
    pieces = noise.fit([a, b + 0.0])
    assert joined.order > 0
    assert pieces.order == 0


def _problem(pc, rec_like, split):
    rec = data.make_record(rec_like.t, rec_like.e, pc, "synthetic")
    return fit.Problem.from_record(rec, rec_like.config, None, 8, model.auto_oversample(rec.fs), split)


def test_held_out_outputs_never_reach_the_fit():
    """The model is output-error: simulated whole, counted on the fit
    parts. Corrupting every held-out output (an offset and noise ten times
    the record's) leaves the baseline and an extended fit unchanged to the
    last bit, while the held-out error sees the corruption."""
    ds = cases.make("p", "lag", 3, n=12000)
    split = holdout.layout(ds.e.size, "blocks")
    assert len(split.held) == 3
    bad = ds.pc.copy()
    rng = np.random.default_rng(11)
    for s in split.held_slices():
        bad[s] += 0.3 * np.ptp(ds.pc) + 10 * cases.NOISE * rng.normal(size=s.stop - s.start)
    fits = []
    for pc in (ds.pc, bad):
        pb = _problem(pc, ds, split)
        assert pb.split is split
        base = baseline.fit_baseline(pb, np.random.default_rng(5), lambda m: None)[0]
        ext = candidates.fit_extended(pb, base, "lag", np.random.default_rng(6))
        fits.append((base, ext))
    (b0, e0), (b1, e1) = fits
    assert b0.values == b1.values and b0.groups == b1.groups
    assert e0.values == e1.values and e0.dead == e1.dead
    assert b1.nrmse_val > 2 * b0.nrmse_val
    assert b1.nrmse_fit == b0.nrmse_fit


def test_sweep_second_effect_found_with_blocks():
    """A 0.1-5 Hz sine sweep (independent simulator, two-backlash-saturation
    seed 4: p, 5 s, AR(1) noise) holds saturation and a dead band. With
    the tail split (main at 63ab9f7) only saturation was named: the dead
    band on top of it predicted the held-out last 30 % no better than its
    reference. With held-out blocks in every third of the sweep both are
    named, with their sizes (test_diagnose_indep.check's tolerances)."""
    from test_diagnose_indep import check
    rec = make("two-backlash-saturation", 4)
    d = diagnose.diagnose(data.make_record(rec.t, rec.e, rec.pc, "indepsim"),
                          rec.truth["config"], jobs=2, progress=False, holdout="blocks")
    assert len(d.split.held) == 3
    assert not check(rec, d), check(rec, d)


def test_input_resting_in_every_held_out_block_falls_back_to_the_tail():
    """Steps only inside the fit parts: the held-out blocks would test
    nothing, so the record is validated on its last 30 % (where a step
    falls), and the report says so."""
    n, fs = 5000, 1000.0
    blocks = holdout.layout(n, "blocks")
    e = np.zeros(n)
    for k in (300, 800, 2000, 3600, 4000):      # all inside fit parts
        assert not any(a - 1 <= k < b for a, b in blocks.held)
        e[k:] += 1.0 if k % 400 else -0.7
    rng = np.random.default_rng(1)
    pc = np.convolve(e, np.full(20, 0.05))[:n] + 1e-3 * rng.normal(size=n)
    rec = data.make_record(np.arange(n) / fs, e, pc, "steps-in-fit-parts")
    split, why = data.split_for(rec, "blocks")
    assert split == holdout.layout(n, "tail")
    assert "held-out blocks refused" in why and "last 30 %" in why
    # The tail used goes to levels its first 70 % never reached: the note
    # says so, as when the tail is asked for (data.uncovered).
    assert "outside the range its fit part visited" in why and "extrapolation" in why
    # Asked for (or with cover), the tail stays: the blocks would keep their
    # held-out samples within their fit parts' levels, but their held-out
    # parts rest (data.check_parts), and the note says that is why.
    assert data.uncovered(rec, holdout.layout(n, "blocks")) is None
    for mode in ("tail", "cover"):
        tail, why = data.split_for(rec, mode)
        assert tail == split
        assert why.startswith("the held-out tail: ") and "outside the range" in why
        assert "the other split, held-out blocks, would keep them" in why
        assert "is refused (the input must move" in why


def test_input_resting_through_the_tail_falls_back_to_the_blocks():
    """A test that ends with a long rest: the last 30 % would test nothing,
    the held-out blocks do (a step falls in the first two), so the record
    is validated on them and the report says so; with neither, the
    refusal names the split asked for."""
    n, fs = 5000, 1000.0
    blocks, tail = holdout.layout(n, "blocks"), holdout.layout(n, "tail")
    e = np.zeros(n)
    for (a, b), k in zip(blocks.held[:2], (1, 2)):
        e[(a + b) // 2:] += 1.0 if k == 1 else -0.6
    for k in (200, 700, 1900):
        e[k:] += 0.4
    assert np.ptp(e[tail.held[0][0] - 1:]) == 0       # the premise: the tail rests
    rng = np.random.default_rng(2)
    pc = np.convolve(e, np.full(20, 0.05))[:n] + 1e-3 * rng.normal(size=n)
    rec = data.make_record(np.arange(n) / fs, e, pc, "rest-at-the-end")
    split, why = data.split_for(rec, "tail")
    assert split == blocks
    assert "held-out tail refused" in why and "each third" in why
    assert data.split_for(rec, "blocks") == (split, None)
    with pytest.raises(data.DataError, match="last 30 %") as refused:
        flat = data.make_record(np.arange(n) / fs, np.r_[e[:400], np.full(n - 400, e[400])],
                                pc, "moves-only-at-the-start")
        data.split_for(flat, "tail")
    # Both splits were tried: the refusal says so and asks for another
    # record, not for the split already tried.
    text = str(refused.value)
    assert "(nor in held-out blocks)" in text and "record whose input moves" in text
    assert "--holdout" not in text

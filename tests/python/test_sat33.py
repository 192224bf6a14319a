# SPDX-License-Identifier: MIT
"""A saturation limit that the fit part never reaches (issue 8, branch
sat33). The fit part's cost does not depend on such a limit, so a search
parks it where the flat stretch begins, at the fit part's highest (or
lowest) output, and the held-out part, which goes further, is then
clipped by a limit the fit part never showed. candidates._unseen_limits_out
puts a limit that no fit sample shows beyond the noise at no effect before
any held-out test; a limit the fit part does show is kept.

The records are made here: steps whose held-out levels go beyond the fit
part's on one side only, the library's plant with a lower (or upper) limit
that binds in both parts and no limit on the other side."""
import copy

import numpy as np
import pytest

from pneufrac_fit import baseline, candidates, data, fit, generate, holdout, model, search

FS = 1000.0
N = 6000


def _levels(n, split, fit_range, held_range, rng, hold=200, rest=300, top=0.0):
    """Steps held `hold` samples (cut at each part's end), from rest:
    levels drawn from fit_range in the fit parts and from held_range in the
    held-out blocks; a share `top` of the fit part's steps at fit_range's
    upper end."""
    e = np.zeros(n)
    for s, is_fit in split.parts(rest):
        lo, hi = fit_range if is_fit else held_range
        for i in range(s.start, s.stop, hold):
            at_top = is_fit and top > 0 and rng.uniform() < top
            e[i:min(i + hold, s.stop)] = hi if at_top else rng.uniform(lo, hi)
    return e


def _record(side: str, mode: str, seed: int = 3, both: bool = False):
    """A p record whose held-out output goes beyond the fit part's on
    `side` ("hi" or "lo"), with a limit on the other side that binds in
    the fit part, and no limit on `side` (both: one there too, binding in
    the fit part as well). Returns (problem at the clipping placement,
    baseline, the binding limit's name, the record)."""
    rng = np.random.default_rng(seed)
    split = holdout.layout(N, mode)
    # the output's sign against the input's (the held-out levels go
    # further on the input's side that moves the output to `side`)
    up = generate.linear_output("p", np.r_[np.zeros(100), np.ones(900)], FS)
    rises = (up[-1] > up[0]) == (side == "hi")
    wide = (0.9, 1.5) if rises else (-1.5, -0.9)
    e = _levels(N, split, (-0.6, 0.6), wide, rng)
    y = generate.linear_output("p", e, FS)
    bind = "sat_lo" if side == "hi" else "sat_hi"
    fit_y = np.concatenate([y[s] for s in split.fit_slices()])
    # binding in the fit part: 60 % of the way out to the fit part's extreme
    lim = 0.6 * (float(np.min(fit_y)) if bind == "sat_lo" else float(np.max(fit_y)))
    far = 1e3 * float(np.ptp(y))
    sat = {"sat_lo": lim, "sat_hi": far} if bind == "sat_lo" else {"sat_lo": -far, "sat_hi": lim}
    if both:
        other = "sat_hi" if bind == "sat_lo" else "sat_lo"
        sat[other] = 0.6 * (float(np.max(fit_y)) if other == "sat_hi" else float(np.min(fit_y)))
    ds = generate.generate("p", effects={"saturation": sat}, n=N, fs=FS, noise=0.005, seed=seed,
                           e=e, oversample=10, order=5)
    rec = data.make_record(ds.t, ds.e, ds.pc, "synthetic")
    pb = fit.Problem.from_record(rec, "p", None, 8, model.auto_oversample(rec.fs), split)
    base = baseline.fit_baseline(pb, np.random.default_rng(5), lambda m: None)[0]
    pk = candidates.with_kind(pb, model.SAT_CLIP)
    return pk, base, bind, ds


def _parked(pk, base, bind, lim_dev, inside: float):
    """(the saturation fit with the binding limit fitted from its truth and
    the other at no effect; the same with the other limit parked `inside`
    record units inside the model's extreme output on the fit part, where
    a search leaves a limit that no fit sample binds by more than that:
    the cost is flat beyond the outputs the fit part reaches; the parked
    limit's name)."""
    other = "sat_hi" if bind == "sat_lo" else "sat_lo"
    no = candidates.no_effect(pk, "saturation")[other]
    st = {**base.groups, **base.values, **candidates.on_sim(pk, base, {bind: lim_dev, other: no})}
    good = search.refine(pk, ("saturation",), [("other out", st)], dead=base.dead)
    # the simulated deviation (before the offset), where good's limits act
    y = pk.fit_of(good.sim) - good.values["pc0"]
    edge = float(np.max(y)) - inside if other == "sat_hi" else float(np.min(y)) + inside
    parked = copy.copy(good)
    parked.values = {**good.values, other: edge}
    fit.evaluate(pk, parked)
    return good, parked, other


@pytest.mark.parametrize("side,mode,inside", [("hi", "tail", 0.0), ("lo", "blocks", 0.0),
                                               ("hi", "tail", 0.5), ("lo", "blocks", 0.5)])
def test_a_limit_the_fit_part_never_reaches_is_put_out(side, mode, inside):
    """inside: the parked limit's distance inside the model's extreme
    output on the fit part, noise sd (0: it clips no fit sample and is
    moved alone; 0.5: it clips the model's highest outputs there by less
    than the noise, and the rest is refitted)."""
    pk, base, bind, ds = _record(side, mode)
    c0 = float(np.mean(ds.pc[:10]))          # the reference of on_sim (_sat_shift)
    sd = 0.005 * float(np.ptp(ds.clean))     # generate's noise: a share of the clean span
    good, parked, other = _parked(pk, base, bind, ds.effect_params[bind] - c0, inside * sd)
    span = pk.y_hi - pk.y_lo
    # the premise: the parked limit clips the held-out output, which goes
    # beyond the fit part's on that side, and predicts it far worse
    held_y = pk.held_of(pk.y - c0)
    assert (np.max(held_y) > pk.y_hi + 0.2 * span) if other == "sat_hi" else \
        (np.min(held_y) < pk.y_lo - 0.2 * span)
    assert parked.nrmse_val > 2 * good.nrmse_val, (parked.nrmse_val, good.nrmse_val)
    # and it clips the fit part's model output (by under the noise) or not at all
    d = candidates._limit_contribution(pk, ("saturation",), parked, other)
    clip = float(np.max(np.abs(pk.fit_of(d)))) / sd
    assert (0.1 < clip < 0.6) if inside > 0 else clip < 0.01, clip
    out = candidates._unseen_limits_out(pk, ("saturation",), parked)
    assert out is not parked
    co = candidates._sat_shift(pk, out)
    # the unseen limit is at no effect: beyond the fit part's range by far
    far = out.values[other] + co
    assert (far > pk.y_hi + 0.5 * span) if other == "sat_hi" else (far < pk.y_lo - 0.5 * span)
    # the limit the fit part shows is kept, at the fit's place
    assert abs(out.values[bind] - good.values[bind]) < 0.02 * span, (out.values, good.values)
    d = candidates._limit_contribution(pk, ("saturation",), out, bind)
    assert candidates.limit_seen(pk, out, d)
    # the held-out part predicted as without the parked clip
    assert out.nrmse_val < 1.1 * good.nrmse_val, (out.nrmse_val, good.nrmse_val)
    # the report says which limit was not seen, and only that one
    assert candidates.unseen_limits(pk, out) == [other]
    notes = candidates.limit_notes(pk, candidates.unseen_limits(pk, out))
    word = "upper" if other == "sat_hi" else "lower"
    assert len(notes) == 1 and f"no {word} limit is seen" in notes[0], notes


def test_limits_the_fit_part_shows_are_kept():
    """Both limits clipping the fit part: the fit is returned unchanged."""
    pk, base, bind, ds = _record("hi", "tail", both=True)
    c0 = float(np.mean(ds.pc[:10]))
    truth = {k: ds.effect_params[k] - c0 for k in ("sat_lo", "sat_hi")}
    st = {**base.groups, **base.values, **candidates.on_sim(pk, base, truth)}
    both = search.refine(pk, ("saturation",), [("both clip", st)], dead=base.dead)
    c = candidates._sat_shift(pk, both)
    span = pk.y_hi - pk.y_lo
    # the premise: both limits fitted at their truth (each clips the fit
    # part's output, which would reach 1/0.6 times as far without it)
    for k in ("sat_lo", "sat_hi"):
        assert abs(both.values[k] + c - truth[k]) < 0.05 * span, (k, both.values, truth)
    assert candidates._unseen_limits_out(pk, ("saturation",), both) is both
    assert candidates.unseen_limits(pk, both) == []
    assert candidates.limit_notes(pk, candidates.unseen_limits(pk, both)) == []


def test_a_true_limit_that_clips_the_fit_part_by_under_the_noise_is_kept():
    """The mirror of the parked limit: the true upper limit lies a little
    (0.7 noise sd) below the top of the fit part's linear output, which a
    third of its steps reach, and the held-out part goes far beyond it,
    where it clips hard. The fit part shows it (significant on many
    samples, though by under a noise sd at its peak): it stays, and the
    held-out part is predicted near the noise floor. A materiality cut
    (a noise sd somewhere) would put it out and leave the tail unclipped
    (review of sat33, stop 34)."""
    rng = np.random.default_rng(3)
    split = holdout.layout(N, "tail")
    up = generate.linear_output("p", np.r_[np.zeros(100), np.ones(900)], FS)
    sign = 1.0 if up[-1] > up[0] else -1.0     # the input's side that raises the output
    e = sign * _levels(N, split, (-0.6, 0.6), (0.9, 1.5), rng, top=0.35)
    y = generate.linear_output("p", e, FS)
    fit_y = np.concatenate([y[s] for s in split.fit_slices()])
    sat = {"sat_lo": 0.6 * float(np.min(fit_y)), "sat_hi": float(np.max(fit_y))}
    for _ in range(3):      # generate's noise sd is a share of the clipped output's span
        ds = generate.generate("p", effects={"saturation": sat}, n=N, fs=FS, noise=0.005,
                               seed=3, e=e, oversample=10, order=5)
        sd = 0.005 * float(np.ptp(ds.clean))
        sat = {**sat, "sat_hi": float(np.max(fit_y)) - 0.7 * sd}
    rec = data.make_record(ds.t, ds.e, ds.pc, "synthetic")
    pb = fit.Problem.from_record(rec, "p", None, 8, model.auto_oversample(rec.fs), split)
    base = baseline.fit_baseline(pb, np.random.default_rng(5), lambda m: None)[0]
    pk = candidates.with_kind(pb, model.SAT_CLIP)
    c0 = float(np.mean(ds.pc[:10]))
    truth = {k: ds.effect_params[k] - c0 for k in ("sat_lo", "sat_hi")}
    st = {**base.groups, **base.values, **candidates.on_sim(pk, base, truth)}
    both = search.refine(pk, ("saturation",), [("both clip", st)], dead=base.dead)
    d = candidates._limit_contribution(pk, ("saturation",), both, "sat_hi")
    # the premise: under a noise sd at its peak on the fit part, on many
    # samples, fitted at its truth, and the held-out part clipped hard
    assert float(np.max(np.abs(pk.fit_of(d)))) < sd
    assert int(np.sum(np.abs(pk.fit_of(d)) > 0.1 * sd)) > 50
    c = candidates._sat_shift(pk, both)
    assert abs(both.values["sat_hi"] + c - truth["sat_hi"]) < 0.5 * sd
    assert float(np.max(pk.held_of(y))) - ds.effect_params["sat_hi"] > 20 * sd
    assert candidates.limit_seen(pk, both, d)
    assert candidates._unseen_limits_out(pk, ("saturation",), both) is both
    assert candidates.unseen_limits(pk, both) == []
    assert candidates.limit_notes(pk, candidates.unseen_limits(pk, both)) == []
    floor = fit.nrmse(pk.held_of(ds.pc - ds.clean), pk.held_of(pk.y))
    assert both.nrmse_val < 1.5 * floor, (both.nrmse_val, floor)


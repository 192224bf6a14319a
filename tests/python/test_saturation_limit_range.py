# SPDX-License-Identifier: MIT
"""A saturation limit that a search leaves beyond the record's output
range never binds: the cost does not depend on it, so no refinement moves
it back, however much better a binding limit fits. The saturation test
puts such a limit back inside the range and refines from there
(candidates._limits_back_in_range), so that which side of the range a
start's path ends on does not decide the verdict."""
from types import SimpleNamespace

import numpy as np

import cases
from pneufrac_fit import baseline, candidates, data, fit, model, search, selection


def _fitted(n: int = cases.N):
    """A p record with saturation, its problem with the limits clipping
    p_c, and its baseline."""
    ds = cases.make("p", "saturation", 1, n=n)
    rec = data.make_record(ds.t, ds.e, ds.pc, "synthetic")
    pb = fit.Problem.from_record(rec, "p", None, 8, model.auto_oversample(rec.fs))
    base = baseline.fit_baseline(pb, np.random.default_rng(5), lambda m: None)[0]
    return ds, pb, candidates.with_kind(pb, model.SAT_CLIP), base


def test_a_limit_left_off_the_range_is_brought_back():
    ds, pb, pk, base = _fitted()
    effects = ("saturation",)
    span = pb.y_hi - pb.y_lo
    inner = candidates.effect_inits(pk, "saturation")[1]
    off = pb.y_lo - 0.5 * span                # the low limit far below the output
    st = {**base.groups, **base.values,
          **candidates.on_sim(pk, base, {"sat_lo": off, "sat_hi": inner["sat_hi"]})}
    stuck = search.refine(pk, effects, [("low limit off the range", st)], dead=base.dead)
    # the premise: off the range the low limit has no gradient and stays put
    assert stuck.values["sat_lo"] == st["sat_lo"]
    back = candidates._limits_back_in_range(pk, effects, base, stuck)
    assert back.cost < stuck.cost
    truth = ds.effects["saturation"]
    c = candidates._sat_shift(pk, base)
    rec_span = float(np.ptp(ds.pc))
    for k in ("sat_lo", "sat_hi"):
        assert abs(back.values[k] + c - truth[k]) <= cases.SAT_TOL * rec_span, (k, back.values)


def test_limits_inside_the_range_are_left_alone():
    _, pb, pk, base = _fitted(2000)
    st = {**base.groups, **base.values,
          **candidates.on_sim(pk, base, candidates.effect_inits(pk, "saturation")[1])}
    b = search.refine(pk, ("saturation",), [("inside", st)], dead=base.dead, iters=2)
    c = candidates._sat_shift(pk, base)
    assert pb.y_lo <= b.values["sat_lo"] + c and b.values["sat_hi"] + c <= pb.y_hi
    assert candidates._limits_back_in_range(pk, ("saturation",), base, b) is b


def test_the_model_so_far_keeps_its_limits_under_a_new_effect():
    """Limits fitted on top of base are on the simulated deviation already:
    a later round's starts keep them as fitted (moving them by the offset
    again would start every fit on top of a saturation model away from
    that model's own optimum), while sizes in the record's terms
    (effect_inits, no_effect) are moved once (candidates.on_sim)."""
    _, pb, pk, base = _fitted(2000)
    st = {**base.groups, **base.values,
          **candidates.on_sim(pk, base, candidates.effect_inits(pk, "saturation")[1])}
    sat = search.refine(pk, ("saturation",), [("inside", st)], dead=base.dead, iters=2)
    c = candidates._sat_shift(pk, sat)
    assert c != 0.0          # the premise: an offset that would move the limits
    effects = model.canonical(sat.effects + ("lag",))
    starts = candidates._starts(pk, effects, "lag", sat, np.random.default_rng(1))
    for label, s in starts:
        assert (s["sat_lo"], s["sat_hi"]) == (sat.values["sat_lo"], sat.values["sat_hi"]), label
    moved = candidates.on_sim(pk, sat, candidates.no_effect(pk, "saturation"))
    assert moved["sat_lo"] == candidates.no_effect(pk, "saturation")["sat_lo"] - c


def test_a_limit_fitted_in_an_earlier_round_keeps_its_place_on_the_record():
    """A size fitted in an earlier round starts the effect's next test
    (selection._hint): its limits are on that fit's simulated deviation,
    before that fit's offset, and the next fit's offset is its own model so
    far's. The start keeps the limit where the earlier fit put it on the
    record's output: the earlier limit plus its offset, less the new one."""
    _, pb, pk, base = _fitted(2000)
    st = {**base.groups, **base.values,
          **candidates.on_sim(pk, base, candidates.effect_inits(pk, "saturation")[1])}
    sat = search.refine(pk, ("saturation",), [("inside", st)], dead=base.dead, iters=2)
    earlier = SimpleNamespace(effect="saturation", model=sat, pb=pk, peak=10.0)
    later = SimpleNamespace(effects=("lag",), values={"pc0": sat.values["pc0"] + 0.01})
    hint = selection._hint(earlier)
    start = candidates._sizes(pk, "saturation", later, hint)[0]
    for k in ("sat_lo", "sat_hi"):
        assert np.isclose(start[k] + later.values["pc0"], sat.values[k] + sat.values["pc0"],
                          rtol=0, atol=1e-12), k

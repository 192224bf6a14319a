# SPDX-License-Identifier: MIT
"""Review findings left open (issue 8, branch revfix27): the whole-fit
cache keyed by the package's settings too, and answering a larger budget
with a fit that converged (a confirmation's refinement of the better model
so far repeats its reference's); the better model so far priced at its own
saturation placement."""
from types import SimpleNamespace

import numpy as np

import cases
from test_twofx4 import dead_time_fits
from pneufrac_fit import candidates, data, fit, guards, model, selection


def _problem(effects="lag", config="p"):
    ds = cases.make(config, effects, 2, n=3000)
    rec = data.make_record(ds.t, ds.e, ds.pc)
    return fit.Problem.from_record(rec, config, {"q": 0.0, "beta": 1.0}, 8, 2)


def _start(pb, **over):
    return {**model.nominal_groups("p"), "e0": pb.e0_default(), "lag": 0.01, **over}


def _fits_made(monkeypatch):
    """The labels of the fits lm_fit made (not answered from _FITS)."""
    made = []
    orig = fit._Objective

    class Counted(orig):
        def __init__(self, *a, **k):
            made.append(1)
            super().__init__(*a, **k)
    monkeypatch.setattr(fit, "_Objective", Counted)
    return made


def _same(a, b):
    assert a.cost == b.cost
    assert np.array_equal(a.theta, b.theta)
    assert a.values == b.values


def _last_converged() -> bool:
    """Whether the fit lm_fit stored last stopped at a tolerance."""
    return next(reversed(fit._FITS.values()))[1]


# ---------------------------------------------------- finding 3: settings
def test_a_setting_changed_at_run_time_is_not_answered_from_the_cache(monkeypatch):
    """A fit asked again after a setting it reads changed (fit.DIFF_STEP,
    the Jacobian's step) is fitted again, and is what a fresh fit under the
    new setting gives; a setting of another module of the package
    (model.F_SIM_MIN) also keys it. Before: the first fit's answer."""
    pb = _problem()
    made = _fits_made(monkeypatch)
    first = fit.lm_fit(pb, ("lag",), _start(pb), 0, 40, "a")
    assert len(made) == 1
    fit.lm_fit(pb, ("lag",), _start(pb), 0, 40, "a")
    assert len(made) == 1                       # unchanged: answered
    monkeypatch.setattr(fit, "DIFF_STEP", 3e-3)
    changed = fit.lm_fit(pb, ("lag",), _start(pb), 0, 40, "b")
    assert len(made) == 2
    fit._FITS.clear()
    _same(changed, fit.lm_fit(pb, ("lag",), _start(pb), 0, 40, "c"))
    assert changed.cost != first.cost or not np.array_equal(changed.theta, first.theta)
    monkeypatch.setattr(model, "F_SIM_MIN", model.F_SIM_MIN * 2)
    fit.lm_fit(pb, ("lag",), _start(pb), 0, 40, "d")
    assert len(made) == 4


def test_the_settings_digest_follows_every_module_of_the_package(monkeypatch):
    from pneufrac_fit import digest, holdout, search
    d0 = digest.settings("pneufrac_fit")
    assert digest.settings("pneufrac_fit") == d0
    for mod, name, v in ((search, "REFINE_ITER", search.REFINE_ITER + 1),
                         (holdout, "MIN_HELD", holdout.MIN_HELD + 1),
                         (model, "GROUPS", {**model.GROUPS, "extra": (0, 1, 2, 3)})):
        with monkeypatch.context() as m:
            m.setattr(mod, name, v)
            assert digest.settings("pneufrac_fit") != d0, name
    assert digest.settings("pneufrac_fit") == d0


def test_the_corner_cache_is_keyed_by_the_settings_too(monkeypatch):
    """The corner freed (candidates._CORNERS) is answered only under the
    settings it was made with, as the whole-fit cache (before: its key was
    the problem and the model so far alone)."""
    from pneufrac_fit import search
    pb = _problem()
    base = fit.lm_fit(pb, (), _start(pb), 0, 40, "base")
    k0 = candidates._corner_key(pb, base)
    assert candidates._corner_key(pb, base) == k0
    monkeypatch.setattr(search, "REFINE_ITER", search.REFINE_ITER + 1)
    assert candidates._corner_key(pb, base) != k0


# ------------------------------------------- finding 2: a larger budget
def test_a_converged_fit_answers_a_larger_budget_exactly(monkeypatch):
    """A fit that stopped at a tolerance answers the same fit with a larger
    budget (which only stops it later): no fit made, and bit for bit what a
    fresh fit with the larger budget gives. One stopped by its budget does
    not: the larger budget goes further."""
    pb = _problem()
    made = _fits_made(monkeypatch)
    st = _start(pb)
    small = fit.lm_fit(pb, ("lag",), st, 0, 400, "a")
    assert _last_converged()                              # the premise
    big = fit.lm_fit(pb, ("lag",), st, 0, 800, "b")
    assert len(made) == 1
    _same(small, big)
    fit._FITS.clear()
    _same(big, fit.lm_fit(pb, ("lag",), st, 0, 800, "c"))
    # a smaller budget than the run needed is not answered by its fit
    # (one it holds is: test_tidy28)
    calls = next(reversed(fit._FITS.values()))[1][0]
    fit.lm_fit(pb, ("lag",), st, 0, calls - 1, "d")
    assert len(made) == 3
    # stopped by its budget: fitted again with a larger one
    fit._FITS.clear()
    n = len(made)
    fit.lm_fit(pb, ("lag",), st, 0, 6, "e")
    assert not _last_converged()
    fit.lm_fit(pb, ("lag",), st, 0, 12, "f")
    assert len(made) == n + 2


def test_confirm_does_not_refit_the_better_start_its_reference_refined(monkeypatch):
    """confirm refines the better model so far at its own delay with twice
    the iterations reference() did, from the same start on the same
    problem: where the reference's refinement converged, the cache answers
    it (no fit made). Before: made again."""
    pb = _problem()
    cur, better, fr = dead_time_fits(pb, _start(pb))
    selection.reference(pb, ("dead_time",), fr, cur, better)
    # the premise: the reference's refinement of the better start at its
    # delay converged
    budget = selection.search._budget(pb, ("dead_time",), selection.search.REFINE_ITER)
    assert any(b == budget and conv and f.dead == better.dead and f.start == "better prior"
               for b, conv, f in fit._FITS.values())
    made, orig = [], selection.search.refine

    def refine(p, effects, starts, dead=0, iters=selection.search.REFINE_ITER):
        before = len(counted)
        r = orig(p, effects, starts, dead, iters)
        made.append((starts[0][0], dead, iters, len(counted) - before))
        return r
    counted = _fits_made(monkeypatch)
    monkeypatch.setattr(selection.search, "refine", refine)
    fit.uncertainty(pb, fr)
    t = guards.test(pb, "lag", fr, cur, so_far=cur)
    t.pb = pb
    selection.confirm(pb, "lag", fr, t, cur, np.random.default_rng(1), better)
    again = [m for m in made if m[0] == "better prior" and m[1] == better.dead]
    assert again and again[0][2] == 2 * selection.search.REFINE_ITER
    assert again[0][3] == 0, "the better start refined again"


# --------------------------------- finding 1: the better model's placement
def test_a_model_without_the_effect_is_priced_at_its_own_placement():
    """_cost_on prices a model with saturation on a test's problem at the
    placement the model was fitted with, not the test's (the same price as
    on the problem set up for the model: candidates.for_model)."""
    pb = _problem("saturation")
    sat = ("saturation",)
    # limits inside the output's range, so that where they act matters
    vals = {**model.nominal_groups("p"), "e0": pb.e0_default(),
            "sat_lo": pb.y_lo + 0.1 * (pb.y_hi - pb.y_lo),
            "sat_hi": pb.y_lo + 0.6 * (pb.y_hi - pb.y_lo),
            "sat_kind": model.SAT_WIND, "sat_kind_told": 1.0}
    m = SimpleNamespace(effects=sat, groups={}, values=vals, dead=0)
    at_wind = candidates.with_kind(pb, model.SAT_WIND, 1.0)
    at_clip = candidates.with_kind(pb, model.SAT_CLIP)
    own = fit.start_cost(at_wind, sat, vals, 0)
    assert selection._cost_on(SimpleNamespace(pb=at_clip), m) == own
    # the premise: the placement changes the price
    clip = {**vals, "sat_kind": model.SAT_CLIP}
    assert fit.start_cost(at_clip, sat, clip, 0) != own


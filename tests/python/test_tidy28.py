# SPDX-License-Identifier: MIT
"""Leftovers of stop 27 (issue 8, branch tidy28): the whole-fit cache
keeps a fit per budget; ..."""
import numpy as np

from test_revfix27 import _fits_made, _problem, _same, _start
from pneufrac_fit import fit


def _reach():
    """(simulations, least_squares evaluations) of the fit lm_fit stored
    last, None where its budget stopped it."""
    return next(reversed(fit._FITS.values()))[1]


# ------------------------------------------ the whole-fit cache's budgets
def test_a_fit_of_another_budget_does_not_drop_a_cached_one(monkeypatch):
    """A fit the cache cannot answer (its budget stops it sooner) is kept
    beside the one it could not use: the first budget asked again is
    answered. Before: one entry a key, replaced, so the repeat was fitted
    again."""
    pb = _problem()
    st = _start(pb)
    made = _fits_made(monkeypatch)
    first = fit.lm_fit(pb, ("lag",), st, 0, 400, "a")
    assert _reach()                                   # the premise: converged
    fit.lm_fit(pb, ("lag",), st, 0, 6, "b")
    assert not _reach() and len(made) == 2            # stopped by its budget
    _same(first, fit.lm_fit(pb, ("lag",), st, 0, 400, "c"))
    assert len(made) == 2, "the first budget's fit was dropped"


def test_a_converged_fit_answers_a_smaller_budget_that_holds_its_run(monkeypatch):
    """A converged fit answers a smaller budget that still allows every
    simulation and least_squares evaluation it made, bit for bit what a
    fresh fit with that budget gives; a budget one simulation short is
    fitted again. Before: a smaller budget was always fitted again."""
    pb = _problem()
    st = _start(pb)
    made = _fits_made(monkeypatch)
    fit.lm_fit(pb, ("lag",), st, 0, 800, "a")
    calls, nfev = _reach()
    p = len(fit.specs(pb, ("lag",)))
    least = next(b for b in range(calls, 800) if fit._max_nfev(b, p) >= nfev)
    assert least < 800                                # the premise
    answered = fit.lm_fit(pb, ("lag",), st, 0, least, "b")
    assert len(made) == 1
    fit._FITS.clear()
    _same(answered, fit.lm_fit(pb, ("lag",), st, 0, least, "c"))
    fit._FITS.clear()
    fit.lm_fit(pb, ("lag",), st, 0, 800, "d")
    n = len(made)
    fit.lm_fit(pb, ("lag",), st, 0, least - 1, "e")
    assert len(made) == n + 1

# SPDX-License-Identifier: MIT
"""Leftovers of stop 27 (issue 8, branch tidy28): the whole-fit cache
keeps a fit per budget and answers a smaller budget that holds a converged
run; numpy settings digested, every module's settings checked; a retest's
references through one helper; --json read off the parser that refused
the command line; the rate a record's stamps can tell."""
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


# ---------------------------------------------------- the settings digest
def test_an_array_setting_changed_in_place_changes_the_digest(monkeypatch):
    """A numpy array (or scalar) bound to a public upper-case name is a
    setting: changed in place, the digest changes. Before: left out, so a
    cached fit made under the old values answered."""
    from pneufrac_fit import digest
    monkeypatch.setattr(fit, "TABLE_T28", np.array([1.0, 2.0]), raising=False)
    monkeypatch.setattr(fit, "SCALAR_T28", np.float64(1.0), raising=False)
    d0 = digest.settings("pneufrac_fit")
    fit.TABLE_T28[0] = 3.0
    d1 = digest.settings("pneufrac_fit")
    assert d1 != d0
    monkeypatch.setattr(fit, "SCALAR_T28", np.float64(2.0))
    assert digest.settings("pneufrac_fit") != d1


def test_every_module_of_the_package_has_only_digested_settings():
    """Over every module of the package (imported here first: a module a
    test does not load, as plots or fleet, was not looked at; this replaces
    revfix27's check of the loaded modules only): each public upper-case value is a
    kind digest.settings digests, and pickles, or a module, class or
    function. A new kind fails here, not silently out of the digest."""
    import importlib
    import inspect
    import pickle
    import pkgutil
    import sys
    import pneufrac_fit
    from pneufrac_fit import digest
    names = [m.name for m in pkgutil.walk_packages(pneufrac_fit.__path__, "pneufrac_fit.")]
    for name in names:
        importlib.import_module(name)
    assert set(names) <= set(digest._modules_of("pneufrac_fit"))
    for name in names:
        for k, v in vars(sys.modules[name]).items():
            if not (k.isupper() and k[0] != "_"):
                continue
            if inspect.ismodule(v) or inspect.isclass(v) or callable(v):
                continue
            assert isinstance(v, digest._PLAIN), f"{name}.{k}: {type(v).__name__}"
            pickle.dumps(v)


# ------------------------------------------ the references a retest keeps
def test_a_retest_carries_earlier_references_but_not_the_model_so_far():
    """_test_again and _referred_again keep the replaced test's reference
    among the models without the effect (one helper), but never the model
    so far itself (in a forked worker a reference can be its copy: the
    identity guard of revfix27-review 8), nor the kept test's own one."""
    from types import SimpleNamespace as NS
    from pneufrac_fit import selection
    current, old, earlier, own = NS(), NS(), NS(), NS()
    t = NS(ref=old, also_without=[earlier])
    keep = NS(ref=own)
    selection._carry_refs(keep, t, old, current)
    assert keep.also_without == [earlier, old]
    for dropped in (current, own, None):
        selection._carry_refs(keep, t, dropped, current)
        assert keep.also_without == [earlier]
    selection._carry_refs(keep, t, current)          # _referred_again's: no model so far given
    assert keep.also_without == [earlier, current]
    selection._carry_refs(keep, NS(ref=old), old, current)    # a stand-in without the field
    assert keep.also_without == [old]
    # an earlier reference that is the model so far (a worker's copy that
    # an earlier retest carried) is left out too (the review of tidy28)
    selection._carry_refs(keep, NS(ref=old, also_without=[earlier, current]), old, current)
    assert keep.also_without == [earlier, old]


# ------------------------------------------------------- cli._wants_json
def test_a_refused_command_line_is_read_off_the_parser_that_refused_it(monkeypatch, capsys):
    """main answers --json on a refused command line from the parser it
    parsed with: one parser made, not a second on the error path."""
    import json
    import pytest
    from pneufrac_fit import cli
    made, orig = [], cli._parser

    def counted():
        made.append(1)
        return orig()
    monkeypatch.setattr(cli, "_parser", counted)
    with pytest.raises(SystemExit):
        cli.main(["diagnose", "--json", "--no-such-option"])
    assert "error" in json.loads(capsys.readouterr().out)
    assert len(made) == 1


# --------------------------------------------- the rate a record can tell
def test_a_rate_read_a_hair_low_is_simulated_at_the_round_rates_factor():
    """A 1 kHz record whose stamps read 999.9999 Hz (a clock slightly slow,
    or jitter) is simulated at 2 steps a sample, as at 1 kHz, not 3 (1.5x
    the cost); the tolerance is what stamps within timebase's jitter
    tolerance can tell of a rate (model.FS_RTOL), and a rate further off
    than that gets the next factor. Before: 3 (a tolerance of 1e-9)."""
    from pneufrac_fit import data, model
    assert model.auto_oversample(999.9999) == model.auto_oversample(1000.0) == 2
    assert model.auto_oversample(1000.0 * (1 - 0.9 * model.FS_RTOL)) == 2
    assert model.auto_oversample(1000.0 * (1 - 1.1 * model.FS_RTOL)) == 3
    assert model.auto_oversample(100.0 * (1 - 1e-6)) == 20
    # only the excess over a whole factor is forgiven: a slow round rate
    # keeps its factor, and a slightly slow one its round rate's
    assert model.auto_oversample(1.0) == 2000
    assert model.auto_oversample(1.0 * (1 - 1e-5)) == 2000
    assert model.auto_oversample(2000.0) == 1 and model.auto_oversample(1e6) == 1
    # through the record: stamps at 1 kHz with jitter, read as uniform
    rng = np.random.default_rng(3)
    n = 2000
    t = np.arange(n) * 1e-3 * (1 + 2e-7) + rng.uniform(-0.2e-3, 0.2e-3, n)
    e = np.where(np.arange(n) % 400 < 200, 0.5, -0.5) + 0.01 * rng.standard_normal(n)
    pc = np.cumsum(e) * 1e-3 + 0.01 * rng.standard_normal(n)
    rec = data.make_record(t, e, pc)
    assert rec.fs != 1000.0 and abs(rec.fs / 1000.0 - 1) < model.FS_RTOL
    assert data.check_cost(rec.n, rec.fs) == 2


def test_the_rate_tolerance_is_the_worst_slope_error_of_an_accepted_record():
    """FS_RTOL bounds the rate timebase reads: stamps of the shortest
    stretch it accepts, each as far off its grid point as it accepts (a
    quarter period, the sign that tilts the slope most), read a rate off
    by no more than FS_RTOL (and by about that much: the bound is tight)."""
    from pneufrac_fit import data, model, timebase
    n = data.MIN_SAMPLES
    k = np.arange(n)
    dev = 0.999 * timebase.JITTER_TOL * np.sign(k - (n - 1) / 2)
    tb = timebase.analyse((k + dev) * 1e-3)
    off = abs(tb.fs / 1000.0 - 1)
    assert off <= model.FS_RTOL
    assert off > 0.9 * model.FS_RTOL

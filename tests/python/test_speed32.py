# SPDX-License-Identifier: MIT
"""Work not done that nothing reads (branch speed32): a candidate's 95 %
intervals are made only for the model the selection ends with
(fit.uncertainty_later, fit.settle). Each shortcut must give what the long
way gives, bit for bit."""
import copy
import math

import numpy as np

import cases
from pneufrac_fit import data, diagnose, fit, model, selection
from test_converge import _fit, _problem, _start     # the same small lag record and fits


def _same_intervals(a, b):
    assert a.se.keys() == b.se.keys() and a.se
    for k in a.se:
        assert a.se[k] == b.se[k] or (math.isnan(a.se[k]) and math.isnan(b.se[k])), k
        assert a.ci[k] == b.ci[k], k
    assert np.array_equal(a.jac, b.jac)
    assert a.noise.describe() == b.noise.describe()


def test_a_candidates_intervals_are_owed_then_made_as_before():
    """try_effect leaves the candidate's intervals owed (none made); settle
    makes them on the test's problem, the same numbers as uncertainty
    called there at once; a second settle makes nothing again."""
    pb = _problem()
    base = _fit(pb, (), _start(pb))
    t = selection.try_effect(pb, base, "lag", 1)
    fr = t.model
    assert fr.owed is not None and not fr.se and not fr.ci and fr.jac is None
    at_once = copy.deepcopy(fr)
    at_once.owed = None
    fit.uncertainty(t.pb, at_once)
    fit.settle(fr, pb)
    assert fr.owed is None
    _same_intervals(fr, at_once)
    made = fr.se
    fit.settle(fr, pb)
    assert fr.se is made             # nothing owed: nothing made again
    fit.settle(None, pb)             # a model that is not there: nothing to do


def test_a_model_never_asked_for_intervals_gets_them_when_settled():
    """A model refitted after the rounds (backward's drop reports a
    reference(); _best_baseline a round-1 reference) owes nothing and has
    no intervals: settle makes them on the problem given, as uncertainty
    there would (review of speed32: the report showed none)."""
    pb = _problem()
    base = _fit(pb, (), _start(pb))
    pbx = selection.problem_for(pb, ("lag",))
    lag = _fit(pbx, ("lag",), _start(pb, lag=0.01))
    ref = selection.reference(pbx, (), lag, base)
    assert ref.owed is None and not ref.ci
    at_once = copy.deepcopy(ref)
    fit.uncertainty(pbx, at_once)
    fit.settle(ref, pbx)
    _same_intervals(ref, at_once)
    assert ref.ci and ref.noise is not None


def test_the_final_model_of_a_diagnosis_has_its_intervals():
    """diagnose settles the model it reports: its effect's interval is
    there (and the tests' models, read by nothing, owe theirs)."""
    ds = cases.make("p", "lag", 3, n=3000)
    rec = data.make_record(ds.t, ds.e, ds.pc)
    d = diagnose.diagnose(rec, "p", jobs=1, progress=False)
    assert d.extended.owed is None
    if "lag" in d.extended.effects:
        lo, hi = d.extended.ci["lag"]
        assert lo is not None and lo < d.extended.values["lag"] < hi
    assert d.extended.ci and d.extended.noise is not None


def test_param_used_kept_is_the_librarys_answer():
    """model._param_used (kept per configuration and name) answers what the
    library's table answers, for every configuration and parameter the
    model asks about, asked twice (the second from the cache)."""
    from pneufrac_fit import lib
    for _ in range(2):
        for config in model.CONFIG_GROUPS:
            for name in ("RC", "nu", "w", "RCd", "RCi", "tau", "beta", "q"):
                assert model._param_used(config, name) == lib.param_used(config, name)
    assert model._param_used.cache_info().hits > 0

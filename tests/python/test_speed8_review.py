# SPDX-License-Identifier: MIT
"""Review items of issue 8, item 8 (branch speed8), in the round's workers
and the rivals' refits:

- selection._workers gives the parent its Jacobian threads back
  (fit.set_threads) also when a fit in the pool raised: the restore is in a
  `finally`, so an error in one round cannot leave the next fits of the
  diagnosis (or of the next record in the same process, as `fleet` runs
  them) on another thread count.
- selection.rival_fit refits on the problem its test fitted (t.pb, which
  _try_effect made: the effect's own problem, saturation where the test's
  fit placed it), not on one made again from the record's problem."""
import types

import pytest

from pneufrac_fit import fit, selection


def test_workers_restore_threads_when_a_fit_raises(monkeypatch):
    calls = []
    monkeypatch.setattr(fit, "set_threads", lambda n: calls.append(n))
    with pytest.raises(RuntimeError):
        with selection._workers(2, 2) as pool:
            assert pool is not None
            raise RuntimeError("a fit failed in the pool")
    assert calls == [fit._threads]      # the parent's threads, set again


def test_rival_fit_fits_on_the_tests_problem(monkeypatch):
    seen = {}

    def from_rival(pb, current, effect, fr, rival):
        seen.update(pb=pb, effect=effect, fr=fr)
        return "refit"

    def made_again(*a, **k):
        raise AssertionError("the test's problem is made again")

    monkeypatch.setattr(selection, "from_rival", from_rival)
    monkeypatch.setattr(selection, "_problem_of", made_again)
    t = types.SimpleNamespace(pb=object(), effect="lag", model=object())
    assert selection.rival_fit(t, object(), object()) == "refit"
    assert seen == {"pb": t.pb, "effect": "lag", "fr": t.model}

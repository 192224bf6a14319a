# SPDX-License-Identifier: MIT
"""Work not done twice (branch speed31): the paper start's fit apart
(candidates._apart) begins on the path the halving's first stage from the
same start already took, and takes those points from it (fit.lm_fit's
trail). Each shortcut must return what the long way returns, bit for bit."""
import numpy as np

import cases
from pneufrac_fit import candidates, data, fit, search
from test_speed9_memo import _counting, _fresh, _problem, _same, _start


def test_a_longer_fit_from_the_same_start_follows_the_trail(monkeypatch):
    pb = _problem()
    _fresh(monkeypatch, keep=False)   # each fit below runs
    seen = _counting(monkeypatch)
    plain = fit.lm_fit(pb, ("lag",), _start(pb), 0, 90, "long")
    n_plain = len(seen)
    trail: dict = {}
    fit.lm_fit(pb, ("lag",), _start(pb), 0, 30, "short", trail=trail)
    assert trail
    seen.clear()
    got = fit.lm_fit(pb, ("lag",), _start(pb), 0, 90, "long", memo=trail)
    _same(got, plain)
    # the short fit's points came from its trail, not from a simulation
    assert len(seen) < n_plain


def _long_problem():
    """A record long enough for an exploration copy (search.explorer)."""
    ds = cases.make("p", "lag", 2, n=12000)
    rec = data.make_record(ds.t, ds.e, ds.pc)
    return fit.Problem.from_record(rec, "p", {"q": 0.0, "beta": 1.0}, 8, 2)


def test_the_paper_start_apart_takes_the_halvings_first_stage(monkeypatch):
    pb = _long_problem()
    assert search.explorer(pb) is not None        # the premise: a copy is explored
    _fresh(monkeypatch, keep=False)   # each fit below runs
    starts = [("warm0", _start(pb)), ("paper", _start(pb, lag=0.05)),
              ("fresh0", _start(pb, lag=0.002))]
    corner = (candidates.CORNER + " (lag)", _start(pb, lag=0.02))
    seen = _counting(monkeypatch)
    got = candidates._explore_corner(pb, ("lag",), starts, corner)
    n_got = len(seen)
    monkeypatch.setattr(candidates, "_trails", lambda apart: {})
    seen.clear()
    plain = candidates._explore_corner(pb, ("lag",), starts, corner)
    _same(got, plain)
    assert got.start == plain.start
    assert n_got < len(seen)


def test_trails_only_for_starts_the_halving_runs():
    starts = [("warm0", {}), ("paper", {}), ("fresh0", {})]
    corner = (candidates.CORNER + " (L)", {})
    assert candidates._trails(candidates._apart(starts, corner)) == {"paper": {}}
    assert candidates._trails(candidates._apart(starts, None)) == {}


def test_start_taus_kept_are_the_ones_computed(monkeypatch):
    """start_taus from its cache is what the computation gives, for the
    problem, its exploration copy and a window (other splits and burns),
    and a changed constant is not answered from the cache."""
    pb = _long_problem()
    assert pb.open_start                          # the premise: a start basis
    for q in (pb, search.explorer(pb), pb.window(5000)):
        want = fit._start_taus.__wrapped__(q.split, q.burn, fit.BURN, fit.START_STEP,
                                           fit.START_SPAN, fit.START_GONE)
        assert fit.start_taus(q) == want and want
        assert fit.start_taus(q) == want          # the second time, from the cache
    before = fit.start_taus(pb)
    monkeypatch.setattr(fit, "START_STEP", 2.0)
    assert fit.start_taus(pb) != before


def test_arfima_frequency_terms_kept_are_the_ones_computed():
    """fit_arfima's cosines, frequencies and fractional factor from the
    cache are the numbers computed for that n (odd and even), and a model
    fitted with them cached is the one fitted with the cache empty."""
    from scipy.signal import lfilter
    from pneufrac_fit import noise
    rng = np.random.default_rng(31)
    for n in (4001, 4000):
        x = lfilter([1.0], [1.0, -0.8], rng.normal(size=n))
        noise._kept_frequency_terms.cache_clear()
        cold = noise.fit_arfima(x)
        warm = noise.fit_arfima(x)                # the terms from the cache
        assert noise._kept_frequency_terms.cache_info().hits >= 1
        for f in ("a", "sigma2", "d", "d_sd", "var"):
            assert np.array_equal(getattr(cold, f), getattr(warm, f))
        assert len(cold.spread) == len(warm.spread)
        for p, q in zip(cold.spread, warm.spread):
            assert all(np.array_equal(u, v) for u, v in zip(p, q))
        I, lam, L, C = noise._whittle_terms(x, 7)
        assert I.size == lam.size == n // 2
        assert np.array_equal(lam, 2.0 * np.pi * np.arange(1, I.size + 1) / n)
        assert np.array_equal(L, 2.0 * np.log(2.0 * np.sin(lam / 2.0)))
        assert np.array_equal(C, np.cos(np.outer(np.arange(8), lam)))


def test_arfima_frequency_terms_past_the_cache_bound_are_made_not_kept(monkeypatch):
    """Above TERMS_CACHE_BYTES the terms are made per call (a 10^6-sample
    record's cosines are not kept after its diagnosis), read only, and
    equal to the kept ones."""
    from pneufrac_fit import noise
    noise._kept_frequency_terms.cache_clear()
    kept = noise._frequency_terms(4000, 7)
    monkeypatch.setattr(noise, "TERMS_CACHE_BYTES", 8 * 8 * 2000 - 1)
    made = noise._frequency_terms(4000, 7)
    assert noise._kept_frequency_terms.cache_info().currsize == 1
    assert made[2] is not kept[2]
    for u, v in zip(kept, made):
        assert np.array_equal(u, v) and not v.flags.writeable

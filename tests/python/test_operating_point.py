# SPDX-License-Identifier: MIT
"""Records at an operating point with noise on the input e: the opening rest
stretch must still be found (an input change is a step beyond 20x the noise
on e, data.change_points), and the verdict must not depend on it."""
import numpy as np
import pytest

from pneufrac_fit import baseline, data, diagnose, fit, generate, holdout, lib, model

E0, PC0, E_NOISE = 0.5, 9.0, 1e-4


def _record(effect, ep, n=3000):
    rng = np.random.default_rng(4)
    e = generate.bump_input(n, 1000.0, rng)
    ds = generate.generate("p", effect, ep, n=n, noise=0.002, seed=5, e=e)
    en = ds.e + E0 + E_NOISE * np.random.default_rng(9).standard_normal(n)
    return ds, data.make_record(ds.t, en, ds.pc + PC0, "noisy-e")


def test_change_points_ignore_input_noise():
    rng = np.random.default_rng(1)
    e = generate.bump_input(2000, 1000.0, rng)
    clean = data.change_points(e)
    noisy = data.change_points(e + 1e-4 * rng.standard_normal(e.size))
    assert clean.size > 5 and clean[0] == 100
    assert np.array_equal(clean, noisy)
    assert data.input_noise(e) == 0.0
    assert abs(data.input_noise(e + 1e-4 * rng.standard_normal(e.size)) / 1e-4 - 1) < 0.1


def test_noise_estimate_uses_the_same_changes():
    """Input noise is no input change: the output noise estimate must not
    lose every sample to 'near a change'."""
    rng = np.random.default_rng(2)
    e = generate.bump_input(3000, 1000.0, rng)
    y = np.repeat(rng.uniform(-1, 1, 30), 100)[:3000] + 1e-3 * rng.standard_normal(3000)
    sd_clean = diagnose.noise_estimate(y, e)
    sd_noisy = diagnose.noise_estimate(y, e + 1e-4 * rng.standard_normal(e.size))
    assert abs(sd_noisy / sd_clean - 1) < 0.05
    assert abs(sd_clean / 1e-3 - 1) < 0.2


def test_operating_point_found_with_noisy_input():
    _, rec = _record("none", {})
    assert abs(rec.e0 - E0) < 1e-4 and abs(rec.pc0 - PC0) < 0.01, rec.notes
    assert any("operating point from the first 100 samples" in s for s in rec.notes), rec.notes


def test_explicit_operating_point():
    _, rec = _record("none", {})
    data.set_operating_point(rec, 0.25, 7.0)
    assert (rec.e0, rec.pc0) == (0.25, 7.0)
    assert rec.notes[-1].startswith("operating point given")
    assert not any(s.startswith("operating point from") for s in rec.notes)
    with pytest.raises(data.DataError):
        data.set_operating_point(rec, float("nan"), 7.0)


@pytest.mark.parametrize("effect,ep", [("none", {}), ("lag", {"lag": 0.012})])
def test_verdict_at_operating_point_with_noisy_input(effect, ep):
    ds, rec = _record(effect, ep)
    d = diagnose.diagnose(rec, "p", progress=False, jobs=2)
    assert d.cause == effect, " ".join(d.why)
    assert d.baseline.nrmse_val < (0.2 if effect != "none" else 2 * ds.noise_floor)
    if effect == "lag":
        assert abs(d.effect_params["lag"] / 0.012 - 1) < 0.25


def test_pid_w_is_what_is_simulated():
    """pid: w = nu + (1 - nu) s, so no fitted point has w < nu and nothing
    is clamped between the fit and the library."""
    setup = model.Setup("pid", 1000.0, 3.0)
    pb = fit.Problem(np.zeros(10), np.zeros(10), setup, {},
                     list(model.CONFIG_GROUPS["pid"]), split=holdout.Split(10, ()))
    sp = fit.specs(pb, ())
    assert dict((n, tr) for n, tr, _, _ in sp)["w"] == "wnu"
    rng = np.random.default_rng(0)
    lo, hi = fit.bounds(sp)
    for _ in range(50):
        v = fit.from_theta(sp, rng.uniform(lo, hi), pb)
        assert v["nu"] <= v["w"] <= 1.0
        th = fit.to_theta(sp, v, pb)
        assert abs(fit.from_theta(sp, th, pb)["w"] - v["w"]) < 1e-12
    g = dict(model.nominal_groups("pid"), nu=0.9, w=0.8)
    p = model.physical_from_groups("pid", g)
    assert p["w"] == 0.8                        # not raised to nu behind the fit's back
    with pytest.raises(lib.ModelError):
        lib.Controller("pid", p, {}, 1000.0)
    # w held: nu is bounded by it
    pb2 = fit.Problem(np.zeros(10), np.zeros(10), setup, {"w": 0.7},
                      [g for g in model.CONFIG_GROUPS["pid"] if g != "w"], split=holdout.Split(10, ()))
    assert dict((n, h) for n, _, _, h in fit.specs(pb2, ()))["nu"] == 0.7


def test_pid_group_held_keeps_nu_below_w():
    """A group held by the identifiability test keeps nu <= w: nu held at
    its bound of 1 and then w at the paper's 0.94 crashed the library (an
    independent pid record, indepsim lag-steps seed 3)."""
    g = dict(model.nominal_groups("pid"), nu=1.0)
    w = baseline.keep_order("pid", "w", 0.94, g)
    assert w == 1.0
    lib.Controller("pid", model.physical_from_groups("pid", dict(g, w=w)), {}, 1000.0)
    assert baseline.keep_order("pid", "nu", 0.9, dict(g, w=0.8)) == 0.8
    assert baseline.keep_order("pid", "nu", 0.5, dict(g, w=0.8)) == 0.5
    assert baseline.keep_order("dd", "nu", 0.9, dict(g, w=0.8)) == 0.9

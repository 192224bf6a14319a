# SPDX-License-Identifier: MIT
"""The independent simulator (tests/python/indepsim) checked on its own:
against the exact step responses in tests/ref, against the paper's
transfer functions, and each effect, noise model and the ADC against its
definition. Nothing here imports pneufrac_fit or the C library."""
from __future__ import annotations

import json
import math
import os
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
from scipy.signal import welch

from indepsim import controller, daq, excitation, noise, reference, simulate
from indepsim.diffusive import frac_integrator, response
from indepsim.effects import U0_INFLECTION, Effects, nozzle
from indepsim.make import floor_over, make, true_floor_held
from indepsim.plant import PAPER

ROOT = Path(__file__).resolve().parents[2]
REF = ROOT / "tests" / "ref"
FS_INT = 8000.0          # the internal rate of a 1 kHz record
# Measured: 4.0e-8 of the peak at worst (ex4_beta0.6, t = 1.3 ms), limited by
# the cubic interpolation between internal samples, not by the model.
STEP_TOL = 1e-6


CASES, EXACT = reference.load(REF)


@pytest.mark.parametrize("case", list(CASES))
def test_step_response_matches_exact_reference(case):
    err, at = reference.step_error(CASES[case], EXACT["t"], EXACT[case], FS_INT)
    assert err <= STEP_TOL, f"{case}: {err:.2e} of peak at t = {at} s"


@pytest.mark.parametrize("alpha", [0.05, 0.3, 0.5, 0.8, 0.94, 0.99])
def test_diffusive_quadrature_matches_s_power(alpha):
    m = frac_integrator(alpha, 1e-4, 1e6)
    s = 1j * np.logspace(-1, 3, 200)       # well inside the band
    err = np.abs(response(m, s) * s ** alpha - 1.0)
    assert err.max() < 1e-6


def test_diffusive_integer_orders_are_exact():
    assert frac_integrator(0.0, 1e-3, 1e3).gain == 1.0
    m = frac_integrator(1.0, 1e-3, 1e3)
    assert np.allclose(response(m, np.array([2j, 5.0])), [1 / 2j, 1 / 5.0])


@pytest.mark.parametrize("config", controller.CONFIGS)
def test_closed_loop_matches_paper_transfer_function(config):
    """The block diagram closed by the netlist against eqs. 17/18/20 and
    docs/pid.md, for the paper's values and a loop gain large enough to
    matter (L x 1000)."""
    for scale in (1.0, 1000.0):
        p = dict(PAPER[config])
        p["A"] *= scale
        ss = controller.build(config, p, controller.band_for(1e5, 20.0))
        w = np.logspace(-1, 4, 60)
        got = np.array([(ss.C[2] @ np.linalg.solve(1j * wi * np.eye(ss.A.shape[0]) - ss.A, ss.B)
                         + ss.D[2])[0] for wi in w])
        want = controller.exact_tf(config, p, 1j * w)
        assert np.max(np.abs(got / want - 1.0)) < 1e-5


# A plant whose relay is static (pmin = pmax) and whose bellows loop is
# negligible (tiny A), so p_c = K/ce * (flapper after the effects): each
# effect can be read off the output against its definition.
STATIC = dict(PAPER["p"], pmax=1.0, A=1e-9)
K_STATIC = controller.groups("p", STATIC)["K"]


def _ramp_up_down(n_half: int) -> np.ndarray:
    up = np.linspace(-1.0, 1.0, n_half)
    return np.concatenate((up, up[::-1]))


def test_backlash_dead_band_width_in_input_units():
    width = 0.1
    e = _ramp_up_down(8000)
    run = simulate.run("p", STATIC, Effects(deadband=width), e, FS_INT)
    y = run.line / K_STATIC
    # rising branch: y = e - w/2; falling branch: y = e + w/2 (away from the ends)
    mid = slice(2000, 6000)
    assert np.allclose(e[mid] - y[mid], width / 2, atol=1e-6)
    mid2 = slice(10000, 14000)
    assert np.allclose(y[mid2] - e[mid2], width / 2, atol=1e-6)
    # right after the reversal the output holds while e travels the dead band
    top = 8000
    held = np.abs(y[top:top + 1000] - y[top]) < 1e-9
    travel = e[top] - e[top + int(np.argmin(held))]
    assert abs(travel - width) < 2 * abs(e[1] - e[0])


@pytest.mark.parametrize("u0", [U0_INFLECTION, 0.3, 1.1])
def test_nozzle_curve_and_unit_slope_at_bias(u0):
    xh = 0.8
    e = _ramp_up_down(8000)[:8000]
    run = simulate.run("p", STATIC, Effects(nozzle_xh=xh, nozzle_u0=u0), e, FS_INT)
    y = run.line / K_STATIC
    want = nozzle(e, xh, u0)
    assert np.max(np.abs(y - want)) < 1e-6
    i0 = int(np.argmin(np.abs(e)))
    slope = (y[i0 + 5] - y[i0 - 5]) / (e[i0 + 5] - e[i0 - 5])
    assert abs(slope - 1.0) < 1e-3
    # the curve compresses: at one end at least, the gain is well below 1
    assert min(abs(y[0] / e[0]), abs(y[-1] / e[-1])) < 0.9


def test_saturation_clips_inside_the_loop():
    p = PAPER["id"]
    e = np.zeros(16000)
    e[800:6000] = 1.0
    lin = simulate.run("id", p, Effects(), e, FS_INT)
    hi = 0.6 * lin.line.max()
    sat = simulate.run("id", p, Effects(sat_hi=hi), e, FS_INT)
    assert sat.line.max() <= hi + 1e-12
    assert np.sum(sat.line >= hi - 1e-12) > 100
    # the bellows saw the clipped pressure: after the release the response is
    # not the clipped linear one (the reset bellows charged less)
    after = slice(6100, 16000)
    diff = np.max(np.abs(sat.line[after] - np.minimum(lin.line[after], hi)))
    assert diff > 0.01 * lin.line.max()


def test_wound_on_stop_recovers_later_than_the_clip():
    """sat_wind: the relay's integral sees the held z, so while the output
    sits at the limit it winds on with p_b - pmin z_lim > 0 and the output
    leaves the limit later than the clip's, whose relay ran on."""
    p = PAPER["id"]
    e = np.zeros(16000)
    e[800:6000] = 1.0
    hi = 0.6 * simulate.run("id", p, Effects(), e, FS_INT).line.max()
    held = {}
    for w in (False, True):
        line = simulate.run("id", p, Effects(sat_hi=hi, sat_wind=w), e, FS_INT).line
        assert line.max() <= hi + 1e-12
        k = 6000
        while line[k] >= hi - 1e-12:
            k += 1
        held[w] = k - 6000
    assert held[True] > 2 * held[False] > 0


def test_lag_time_constant():
    T = 0.012
    e = np.ones(8000)
    run = simulate.run("p", STATIC, Effects(lag=T), e, FS_INT)
    t = np.arange(e.size) / FS_INT
    k = slice(40, 400)
    T_est = -t[k] / np.log(1.0 - run.line[k] / K_STATIC)
    assert np.max(np.abs(T_est / T - 1.0)) < 1e-6


def test_sub_sample_dead_time_survives_sampling():
    """0.37 data samples of dead time, seen through the DAQ at 1 kHz."""
    fs, D, f = 1000.0, 0.37e-3, 3.0
    t_int = np.arange(int(3.0 * FS_INT)) / FS_INT - 0.5
    e_int = np.where(t_int >= 0, np.sin(2 * math.pi * f * t_int), 0.0)
    run = simulate.run("p", STATIC, Effects(dead_time=D), e_int, FS_INT)
    t = np.arange(1000, 2400) / fs
    es = daq.average(e_int, t_int[0], FS_INT, t, fs)
    ps = daq.average(run.line, t_int[0], FS_INT, t, fs) / K_STATIC
    X = np.column_stack((np.sin(2 * math.pi * f * t), np.cos(2 * math.pi * f * t)))
    (a1, b1), (a2, b2) = (np.linalg.lstsq(X, v, rcond=None)[0] for v in (es, ps))
    lag = (math.atan2(b1, a1) - math.atan2(b2, a2)) / (2 * math.pi * f)
    assert abs(lag - D) < 0.01 * D


def test_ar1_noise_coefficient_and_level():
    x = noise.ar1(200000, 0.8, np.random.default_rng(1))
    assert abs(np.std(x) - 1.0) < 1e-12
    r1 = np.corrcoef(x[:-1], x[1:])[0, 1]
    assert abs(r1 - 0.8) < 0.01


@pytest.mark.parametrize("model,slope", [("white", 0.0), ("pink", -1.0)])
def test_noise_spectrum_slope(model, slope):
    x = noise.draw(model, 2 ** 17, np.random.default_rng(2))
    f, P = welch(x, fs=1.0, nperseg=4096)
    band = (f > 2e-3) & (f < 0.4)
    k = np.polyfit(np.log(f[band]), np.log(P[band]), 1)[0]
    assert abs(k - slope) < 0.1


def test_adc_is_12_bit():
    x = np.linspace(-3.0, 5.0, 100001)
    lo, hi = daq.adc_range(x, 0.5)
    q = daq.quantise(x, lo, hi)
    lsb = (hi - lo) / 4095
    codes = (q - lo) / lsb
    assert np.allclose(codes, np.round(codes), atol=1e-6)
    assert len(np.unique(np.round(codes))) <= 4096
    assert np.max(np.abs(q - x)) <= lsb / 2 * (1 + 1e-9)


def test_realistic_record_is_quantised_and_deterministic():
    a = make("clean-p-real", 5)
    b = make("clean-p-real", 5)
    assert np.array_equal(a.pc, b.pc) and np.array_equal(a.e, b.e)
    adc = a.truth["noise"]["adc"]
    for sig, rng_key, lsb_key in ((a.e, "e_range", "e_lsb"), (a.pc, "pc_range", "pc_lsb")):
        codes = (sig - adc[rng_key][0]) / adc[lsb_key]
        assert np.allclose(codes, np.round(codes), atol=1e-6)
        assert codes.min() >= -1e-6 and codes.max() <= 4095 + 1e-6
    assert a.truth["causes"] == []
    assert not np.array_equal(make("clean-p-real", 6).pc[:100], a.pc[:100])


def test_jittered_stamps():
    rng = np.random.default_rng(3)
    t = daq.stamps(daq.sample_times(20000, 1000.0, rng, 0.005))
    off = t - np.arange(t.size) / 1000.0
    assert np.all(np.diff(t) > 0)
    assert np.max(np.abs(off)) <= 3 * 0.005e-3 + 0.5e-6 + 1e-12
    assert np.std(off) > 0.003e-3
    assert np.allclose(t * 1e6, np.round(t * 1e6), atol=1e-6)


def test_prbs_is_maximal_length():
    bits = excitation._lfsr(7, 2 * 127, 5)
    assert np.array_equal(bits[:127], bits[127:])
    for period in range(1, 127):
        assert not np.array_equal(bits[:127], np.roll(bits[:127], period))


def _cli(*args, cwd=None):
    env = dict(os.environ, PYTHONPATH=str(Path(__file__).resolve().parent))
    return subprocess.run([sys.executable, "-m", "indepsim", *args], capture_output=True,
                          text=True, env=env, cwd=cwd, timeout=120)


def test_cli_list_and_make(tmp_path):
    r = _cli("list")
    assert r.returncode == 0
    names = [ln.split("\t")[0] for ln in r.stdout.splitlines()]
    assert "clean-pid-real" in names and "two-lag-backlash" in names
    r = _cli("make", "marginal-lag", "--seed", "3", "--out", str(tmp_path / "out"))
    assert r.returncode == 0, r.stderr
    csv = tmp_path / "out" / "marginal-lag-3.csv"
    truth = json.loads((tmp_path / "out" / "marginal-lag-3.truth.json").read_text())
    assert csv.read_text().splitlines()[0] == "t,e,pc"
    data = np.loadtxt(csv, delimiter=",", skiprows=1)
    assert data.shape == (20000, 3)
    assert truth["causes"] == ["lag"] and truth["effects"][0]["params"]["lag"] > 0
    # The noise written beside the record gives back the truth's floor over
    # the last 30 %, and another held-out part gives another floor.
    nz = np.loadtxt(tmp_path / "out" / "marginal-lag-3.noise.csv")
    assert nz.shape == (20000,) and 0 < np.std(nz) < np.std(data[:, 2])
    tail = [(20000 - 6000, 20000)]
    assert floor_over(data[:, 2], nz, tail) == pytest.approx(truth["noise"]["noise_floor_val"],
                                                             rel=1e-6)
    blocks = [(4667, 6667), (11333, 13333), (18000, 20000)]
    tail_floor = truth["noise"]["noise_floor_val"]
    assert true_floor_held(data[:, 2], nz, blocks, 20000, tail_floor) == floor_over(data[:, 2], nz,
                                                                                    blocks)
    assert floor_over(data[:, 2], nz, blocks) != floor_over(data[:, 2], nz, tail)
    # A tool record that does not line up sample for sample: the tail's floor.
    assert true_floor_held(data[:, 2], nz, blocks, 19999, tail_floor) == tail_floor
    for bad in ([(19000, 20001)], [(-5, 100)], []):
        with pytest.raises(ValueError):
            floor_over(data[:, 2], nz, bad)
    with pytest.raises(ValueError):   # an output that does not move has no floor
        floor_over(np.ones(100), np.zeros(100), [(0, 50)])


@pytest.mark.parametrize("args", [("make", "no-such", "--seed", "1", "--out", "x"),
                                  ("make", "lag-steps", "--seed", "one", "--out", "x"),
                                  ("make", "lag-steps", "--seed", "-4", "--out", "x"),
                                  ("make", "lag-steps", "--out", "x"),
                                  ("frobnicate",)])
def test_cli_bad_arguments(args, tmp_path):
    r = _cli(*args, cwd=tmp_path)
    assert r.returncode == 2
    assert len(r.stderr.strip().splitlines()) == 1 and "Traceback" not in r.stderr
    assert not (tmp_path / "x").exists()    # refused before any output

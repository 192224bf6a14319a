# SPDX-License-Identifier: MIT
"""pneufrac.simulate in double, float and Q15 is the C library's output bit
for bit: against `pneufrac simulate --arith ...`, and against the typed
runtimes a firmware links (pf_ctrl_run_f32, pf_ctrl_run_q15), sample for
sample."""
import shutil
import subprocess

import numpy as np
import pandas as pd
import pytest

import pneufrac
from conftest import BUILD, CLI, ROOT

FS = 20000.0
N = 8000
# (config, paper parameters, effects, in_fs, out_fs): every configuration,
# every effect block (backlash, nozzle curve, saturation, lag, dead time), and
# full scales that the input and output exceed now and then, so that the
# Q15 path saturates too.
CASES = [
    ("p", {}, {}, 1.0, 0.012),
    ("dd", {"tau": 0.002}, {"lag": 0.01, "dead_time": 0.0011}, 0.8, 0.01),
    ("id", {}, {"backlash": 0.02}, 1.0, 12.0),
    ("pid", {"q": 0.9}, {"backlash": 0.01, "lag": 0.004, "dead_time": 0.001}, 1.0, 16.0),
    ("dd", {}, {"sat_lo": -0.004, "sat_hi": 0.006}, 1.2, 0.01),
    ("dd", {}, {"nozzle_xh": 0.2, "backlash": 0.06}, 1.0, 0.012),
]


def excitation(n=N, seed=7):
    """Steps, a ramp, a sine and noise; peaks beyond 1.0 in both signs."""
    rng = np.random.default_rng(seed)
    t = np.arange(n) / FS
    steps = np.repeat(rng.uniform(-1.1, 1.1, n // 400 + 1), 400)[:n]
    return steps + 0.3 * np.sin(2 * np.pi * 7 * t) + 0.2 * (t / t[-1]) \
        + 0.01 * rng.standard_normal(n)


def cli_simulate(tmp_path, config, params, effects, e, arith, in_fs=None, out_fs=None):
    inp = tmp_path / "in.csv"
    t = np.arange(e.size) / FS
    inp.write_text("t,e\n" + "".join(f"{a!r},{b!r}\n" for a, b in zip(t.tolist(), e.tolist())))
    args = [str(CLI), "simulate", "--config", config, "--fs", repr(FS), "--duration",
            repr((e.size - 1) / FS), "--input", str(inp), "--arith", arith]
    for k, v in params.items():
        args += ["--set", f"{k}={v!r}"]
    for k, v in effects.items():
        if k == "backlash":
            args += ["--effect", f"backlash:width={v!r}"]
        elif k == "nozzle_xh":
            args += ["--effect", f"nozzle:xh={v!r}"]
        elif k == "lag":
            args += ["--effect", f"lag:tau={v!r}"]
        elif k == "dead_time":
            args += ["--effect", f"deadtime:t={v!r}"]
    if "sat_lo" in effects:
        args += ["--effect", f"saturation:lo={effects['sat_lo']!r},hi={effects['sat_hi']!r}"]
    if arith == "q15":
        args += ["--in-fs", repr(in_fs), "--out-fs", repr(out_fs)]
    r = subprocess.run(args, capture_output=True, text=True, timeout=120)
    assert r.returncode == 0, r.stderr
    out = tmp_path / "out.csv"
    out.write_text(r.stdout)
    return pd.read_csv(out, comment="#")


@pytest.mark.parametrize("arith", ["double", "float", "q15"])
@pytest.mark.parametrize("config,params,effects,in_fs,out_fs", CASES)
def test_simulate_is_pneufrac_simulate(tmp_path, arith, config, params, effects, in_fs,
                                       out_fs):
    e = excitation()
    d = pneufrac.design(config, FS, effects=effects, **params)
    scales = {"in_fs": in_fs, "out_fs": out_fs} if arith == "q15" else {}
    got = pneufrac.simulate(d, e, arith, **scales)
    want = cli_simulate(tmp_path, config, params, effects, e, arith, in_fs, out_fs)
    assert len(want) == e.size
    pc = want["pc"].to_numpy()
    if arith == "float":
        # The CLI writes a float run's output as the float it is (the
        # shortest text that reads back as that float).
        assert np.array_equal(got, got.astype(np.float32))
        pc = pc.astype(np.float32).astype(np.float64)
    assert np.array_equal(got, pc), np.max(np.abs(got - pc))
    if arith == "q15":
        raw = np.rint(got / out_fs * 32768.0)
        assert np.array_equal(raw, want["pc_q15"].to_numpy())
        assert np.ptp(raw) > 1000            # the output moves through the range


@pytest.fixture(scope="module")
def typed_runtime(tmp_path_factory):
    cc = shutil.which("cc")
    if cc is None:
        pytest.skip("no C compiler")
    exe = tmp_path_factory.mktemp("typed") / "typed_runtime"
    subprocess.run([cc, "-std=c99", "-O2", "-I", str(ROOT / "lib" / "include"),
                    str(ROOT / "tests" / "python" / "typed_runtime.c"),
                    str(BUILD / "lib" / "libpneufrac.a"), "-lm", "-o", str(exe)], check=True)
    return exe


def run_typed(exe, mode, config, params, effects, in_fs, out_fs, data: bytes) -> bytes:
    args = [str(exe), mode, config, repr(FS), repr(in_fs), repr(out_fs)]
    args += [f"{k}={float(v)!r}" for k, v in {**params, **effects}.items()]
    r = subprocess.run(args, input=data, capture_output=True, timeout=120)
    assert r.returncode == 0, r.stderr
    return r.stdout


@pytest.mark.parametrize("config,params,effects,in_fs,out_fs", CASES)
def test_float_is_the_typed_f32_runtime(typed_runtime, config, params, effects, in_fs,
                                        out_fs):
    e = excitation()
    want = np.frombuffer(run_typed(typed_runtime, "f32", config, params, effects, in_fs,
                                   out_fs, e.astype(np.float64).tobytes()), np.float32)
    d = pneufrac.design(config, FS, effects=effects, **params)
    got = pneufrac.simulate(d, e, "float")
    assert want.size == e.size
    assert np.array_equal(got, want.astype(np.float64))


@pytest.mark.parametrize("config,params,effects,in_fs,out_fs", CASES)
def test_q15_is_the_typed_q15_runtime(typed_runtime, config, params, effects, in_fs,
                                      out_fs):
    """Raw counts in, raw counts out, as firmware sees them; the whole int16
    range of the input, both ends included."""
    e = excitation()
    eq = np.clip(np.rint(e / in_fs * 32768.0), -32768, 32767).astype(np.int16)
    eq[:3] = [-32768, 32767, 0]
    want = np.frombuffer(run_typed(typed_runtime, "q15", config, params, effects, in_fs,
                                   out_fs, eq.tobytes()), np.int16)
    d = pneufrac.design(config, FS, effects=effects, **params)
    rt = d.runtime("q15", in_fs=in_fs, out_fs=out_fs)
    got = rt.run_q15(eq)
    assert got.dtype == np.int16 and np.array_equal(got, want)
    assert np.ptp(want.astype(int)) > 1000


def test_a_record_may_be_fed_in_pieces():
    e = excitation(3000)
    d = pneufrac.design("pid", FS, effects={"lag": 0.004, "dead_time": 0.001})
    for arith, sc in (("double", {}), ("float", {}), ("q15", {"in_fs": 1.0, "out_fs": 16.0})):
        whole = d.simulate(e, arith, **sc)
        rt = d.runtime(arith, **sc)
        parts = np.concatenate([rt.run(e[:1234]), rt.run(e[1234:1235]), rt.run(e[1235:])])
        assert np.array_equal(whole, parts)
        rt.reset()
        assert np.array_equal(rt.run(e), whole)


def test_bad_runtime_arguments():
    d = pneufrac.design("dd", FS)
    with pytest.raises(ValueError, match="arith"):
        d.simulate(np.ones(3), "fixed")
    with pytest.raises(ValueError, match="in_fs and out_fs"):
        d.simulate(np.ones(3), "q15")
    with pytest.raises(ValueError, match="in_fs"):
        d.simulate(np.ones(3), "q15", in_fs=-1.0, out_fs=1.0)
    with pytest.raises(ValueError, match="1-D"):
        d.simulate(np.ones((2, 3)))
    with pytest.raises(ValueError, match="run_q15"):
        d.runtime("double").run_q15(np.zeros(3, np.int16))
    rt = d.runtime("q15", in_fs=1.0, out_fs=0.01)
    with pytest.raises(ValueError, match="int16"):
        rt.run_q15(np.array([40000]))
    with pytest.raises(ValueError, match="integers"):
        rt.run_q15(np.array([0.5]))
    # The refined approximation is float/double only: the library says so.
    refined = pneufrac.design("dd", FS, approx="refined")
    with pytest.raises(pneufrac.ModelError):
        refined.simulate(np.ones(3), "q15", in_fs=1.0, out_fs=0.01)
    assert np.all(np.isfinite(refined.simulate(np.ones(3), "float")))
    # Extreme and NaN inputs: finite outputs, as the library promises.
    out = d.simulate(np.array([1e300, -1e300, np.nan, 0.0]))
    assert np.all(np.isfinite(out))
    assert d.simulate(np.array([])).size == 0

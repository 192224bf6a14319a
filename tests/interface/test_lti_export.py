# SPDX-License-Identifier: MIT
"""`pneufrac design --format ss|zpk|sos` in scipy's and python-control's
hands: each export's frequency response must be the design's own
(pf_ctrl_freqresp, as `pneufrac bode` prints it), and the state space run
by scipy.signal.dlsim must be `pneufrac simulate`, sample for sample."""
import io
import json

import control
import numpy as np
import pandas as pd
import pytest
import scipy.signal as sg

from conftest import run

# Designs: every configuration at the paper's rates, plus the output lag
# and plain Tustin (no held input), which change D and the state count.
CASES = [
    ("p", 20000, []),
    ("dd", 20000, []),
    ("id", 20000, []),
    ("pid", 20000, []),
    ("dd", 1000, []),
    ("pid", 5000, ["--effect", "lag:tau=0.002"]),
    ("id", 20000, ["--input-model", "linear", "--set", "q=0.5"]),
]
IDS = [f"{c}-{fs}{'-' + x[1] if x else ''}" for c, fs, x in CASES]


def design(fmt, config, fs, extra):
    return json.loads(run("design", "--config", config, "--fs", fs, "--format", fmt,
                          *extra).stdout)


def reference(config, fs, extra):
    """omega and the realised controller's response, from `pneufrac bode`."""
    csv = run("bode", "--config", config, "--fs", fs, "--points", 120, *extra).stdout
    b = pd.read_csv(io.StringIO(csv), comment="#")
    h = 10 ** (b["discrete_db"] / 20) * np.exp(1j * np.radians(b["discrete_deg"]))
    return b["omega"].to_numpy(), h.to_numpy()


def worst(h, ref):
    return float(np.max(np.abs(h / ref - 1)))


@pytest.mark.parametrize("config,fs,extra", CASES, ids=IDS)
def test_exports_have_the_design_response(config, fs, extra):
    w, ref = reference(config, fs, extra)
    ss, zpk, sos = (design(f, config, fs, extra) for f in ("ss", "zpk", "sos"))
    assert ss["dt"] == zpk["dt"] == sos["dt"] == 1 / fs

    # python-control, state space: no polynomial is formed.
    sys = control.ss(np.array(ss["A"]), np.array(ss["B"]), np.array(ss["C"]),
                     np.array(ss["D"]), ss["dt"])
    h_ss = np.array([complex(sys(np.exp(1j * x / fs))) for x in w])
    # scipy.signal, zeros/poles/gain and second-order sections.
    z = np.array(zpk["z"]) @ np.array([1, 1j])
    p = np.array(zpk["p"]) @ np.array([1, 1j])
    _, h_zpk = sg.freqz_zpk(z, p, zpk["k"], worN=w / fs)
    sos_a = np.array(sos["sos"])
    assert np.all(sos_a[:, 3] == 1.0), "a0 = 1 in every section"
    _, h_sos = sg.sosfreqz(sos_a, worN=w / fs)

    e_ss, e_zpk, e_sos = worst(h_ss, ref), worst(h_zpk, ref), worst(h_sos, ref)
    print(f"{config} {fs} {extra}: n = {len(ss['A'])}, relative error ss {e_ss:.1e}, "
          f"zpk {e_zpk:.1e}, sos {e_sos:.1e}")
    # ss is the runtime itself: rounding only. The roots come from
    # eigenvalues of matrices whose poles sit within 1e-7 of z = 1.
    assert e_ss < 1e-7
    assert e_zpk < 1e-5
    assert e_sos < 1e-5
    # scipy's conventions: zeros and poles are roots, inside the unit
    # circle or, for the integer parts' Tustin integrators, on it at z = 1;
    # conjugates in pairs.
    assert np.all(np.abs(p) <= 1 + 1e-12)
    for r in (z, p):
        assert np.allclose(np.sort_complex(r), np.sort_complex(r.conj()))


@pytest.mark.parametrize("config,fs,extra", CASES[:4] + CASES[5:], ids=IDS[:4] + IDS[5:])
def test_state_space_runs_like_simulate(config, fs, extra):
    ss = design("ss", config, fs, extra)
    n = int(0.05 * fs) + 1
    sim = pd.read_csv(io.StringIO(run("simulate", "--config", config, "--fs", fs,
                                      "--duration", 0.05, *extra).stdout), comment="#")
    _, y, _ = sg.dlsim((np.array(ss["A"]), np.array(ss["B"]), np.array(ss["C"]),
                        np.array(ss["D"]), ss["dt"]), np.ones(n))
    assert len(sim) == n
    err = np.max(np.abs(y[:, 0] - sim["pc"])) / np.max(np.abs(sim["pc"]))
    assert err < 1e-12, err


@pytest.mark.parametrize("fx", ["backlash:width=0.01", "nozzle:xh=0.5",
                                "saturation:lo=-1,hi=1", "deadtime:t=0.001"])
@pytest.mark.parametrize("fmt", ["ss", "zpk", "sos"])
def test_refused_without_a_transfer_function(fx, fmt):
    r = run("design", "--config", "dd", "--fs", 1000, "--format", fmt, "--effect", fx,
            check=False)
    assert r.returncode == 2 and r.stdout == ""
    assert r.stderr.count("\n") == 1 and r.stderr.startswith("pneufrac: design --format")


def test_no_arith_for_the_double_exports():
    r = run("design", "--config", "dd", "--fs", 1000, "--format", "ss", "--arith", "float",
            check=False)
    assert r.returncode == 2 and "takes no --arith" in r.stderr

# SPDX-License-Identifier: MIT
"""pneufrac.design and its exports against the C tool: the frequency
responses of `pneufrac bode`, the state space of `pneufrac design --format
ss`, and zeros/poles and sections that give the realised response."""
import json
import subprocess

import numpy as np
import pandas as pd
import pytest
import scipy.signal as sg

import pneufrac
from conftest import CLI

# (config, fs, paper parameters, effects): every configuration, a lag and a
# dead time on the output line, another rate and band.
CASES = [
    ("p", 20000.0, {}, {}),
    ("dd", 20000.0, {"tau": 0.002}, {"lag": 0.01}),
    ("id", 5000.0, {}, {"dead_time": 0.003}),
    ("pid", 20000.0, {"q": 0.9}, {"lag": 0.004, "dead_time": 0.0012}),
    ("dd", 1000.0, {"beta": 0.6, "q": 0.7}, {}),
]


def cli(*args):
    r = subprocess.run([str(CLI), *map(str, args)], capture_output=True, text=True,
                       timeout=120)
    assert r.returncode == 0, r.stderr
    return r.stdout


def cli_args(config, fs, params, effects):
    a = ["--config", config, "--fs", fs]
    for k, v in params.items():
        a += ["--set", f"{k}={v!r}"]
    if "lag" in effects:
        a += ["--effect", f"lag:tau={effects['lag']!r}"]
    if "dead_time" in effects:
        a += ["--effect", f"deadtime:t={effects['dead_time']!r}"]
    return a


@pytest.mark.parametrize("config,fs,params,effects", CASES)
def test_freqresp_is_pneufrac_bode(tmp_path, config, fs, params, effects):
    """Ideal (numpy here, pfh_ref_tf there) and realised (pf_ctrl_freqresp
    in both) magnitude and unwrapped phase, on the CLI's own grid."""
    f = tmp_path / "bode.csv"
    f.write_text(cli("bode", *cli_args(config, fs, params, effects)))
    want = pd.read_csv(f, comment="#")
    d = pneufrac.design(config, fs, effects=effects, **params)
    got = pneufrac.freqresp(d, want["omega"].to_numpy()).to_frame()
    for col in ("ideal_db", "ideal_deg", "discrete_db", "discrete_deg"):
        err = np.max(np.abs(got[col].to_numpy() - want[col].to_numpy()))
        assert err < 1e-9, (col, err)
    # The default grid is the CLI's too.
    assert np.allclose(pneufrac.freqresp(d).omega, want["omega"], rtol=1e-12, atol=0)


@pytest.mark.parametrize("config,fs,params,effects",
                         [c for c in CASES if "dead_time" not in c[3]])
def test_state_space_is_the_cli_export(config, fs, params, effects):
    want = json.loads(cli("design", *cli_args(config, fs, params, effects), "--format", "ss"))
    ss = pneufrac.design(config, fs, effects=effects, **params).ss()
    for k in "ABCD":
        assert np.array_equal(getattr(ss, k), np.array(want[k]).reshape(getattr(ss, k).shape))
    assert ss.dt == want["dt"]


@pytest.mark.parametrize("config,fs,params,effects",
                         [c for c in CASES if "dead_time" not in c[3]])
def test_zpk_and_sos_give_the_realised_response(config, fs, params, effects):
    """Against pf_ctrl_freqresp over the band, within the bound the control
    page states for the CLI's exports (4e-7), with as many sections as the
    CLI's (each is that close to the truth; the two roundings differ)."""
    d = pneufrac.design(config, fs, effects=effects, **params)
    w = np.logspace(np.log10(0.1 * d.options["wb"]), np.log10(0.99 * np.pi * fs), 120)
    h = d._buf.freqresp(w)
    z = d.zpk()
    sos = d.sos()
    _, hz = sg.freqz_zpk(z.z, z.p, z.k, worN=w * z.dt)
    _, hs = sg.sosfreqz(sos, worN=w / fs)
    assert np.max(np.abs(hz / h - 1)) < 4e-7
    assert np.max(np.abs(hs / h - 1)) < 4e-7
    assert np.all(sos[:, 3] == 1.0)
    # No section holds two real poles near z = 1 (the pairing's purpose).
    for b0, b1, b2, a0, a1, a2 in sos:
        r = np.roots([1.0, a1, a2])
        assert not (np.all(np.isreal(r)) and np.all(np.abs(1 - r.real) < 1e-4)), r
    want = np.array(json.loads(cli("design", *cli_args(config, fs, params, effects),
                                   "--format", "sos"))["sos"])
    assert want.shape == sos.shape


def test_design_reports_what_the_library_resolved():
    d = pneufrac.design("dd", 20000, tau=0.002, effects={"lag": 0.01, "dead_time": 0.001})
    assert d.config == "dd" and d.fs == 20000.0
    assert d.params["tau"] == 0.002 and d.params["beta"] == 0.8      # Example 6's
    assert d.effects == {"lag": 0.01, "dead_time": 0.001}
    assert d.delay == 20
    o = d.options
    assert o["wh"] == pytest.approx(np.pi * 20000) and o["order"] >= 1
    assert o["approx"] == "oustaloup" and o["input"] == "hold"
    s = pneufrac.design("p", 1000, effects={"sat_lo": -1, "sat_hi": 2})
    assert s.effects == {"sat_lo": -1.0, "sat_hi": 2.0} and not s.linear
    # the placement: the relay's diaphragm on its seat, kept as designed
    s = pneufrac.design("p", 1000, effects={"sat_lo": -1, "sat_hi": 2, "saturate": 2})
    assert s.effects == {"sat_lo": -1.0, "sat_hi": 2.0, "saturate": 2}
    assert "dd at 20000 Hz" in repr(d)


def test_parameters_are_the_library_table():
    rows = {r["name"]: r for r in pneufrac.parameters()}
    assert rows["beta"]["lo"] == 0.0 and rows["beta"]["lo_open"]
    assert rows["RC"]["configs"] == ["dd", "id"]
    assert rows["tau"]["unit"] == "s"
    assert {"dead_time", "lag", "in_fs", "fs"} <= set(rows)


@pytest.mark.parametrize("call,match", [
    (lambda: pneufrac.design("dd", 20000, tua=1.0), "unknown model parameter 'tua'"),
    (lambda: pneufrac.design("xx", 20000), "config"),
    (lambda: pneufrac.design("dd", float("nan")), "fs"),
    (lambda: pneufrac.design("dd", 20000, beta="x"), "beta"),
    (lambda: pneufrac.design("dd", 20000, effects={"backlash": float("inf")}), "backlash"),
    (lambda: pneufrac.design("dd", 20000, effects={"deadtime": 1}), "unknown effect"),
    (lambda: pneufrac.design("dd", 20000, effects={"sat_lo": 1}), "sat_hi"),
    (lambda: pneufrac.design("dd", 20000, effects={"saturate": 2}), "sat_lo"),
    (lambda: pneufrac.design("dd", 20000, effects={"sat_lo": -1, "sat_hi": 1,
                                                   "saturate": 1.5}), "whole number"),
    (lambda: pneufrac.design("dd", 20000, band=(1.0,)), "band"),
    (lambda: pneufrac.design("dd", 20000, order=2.5), "order"),
    (lambda: pneufrac.design("dd", 20000, order="many"), "order"),
    (lambda: pneufrac.design("dd", 20000, approx="best"), "approx"),
    (lambda: pneufrac.design("dd", 20000, input_model="zoh"), "input_model"),
])
def test_bad_arguments_are_value_errors(call, match):
    with pytest.raises(ValueError, match=match):
        call()


def test_the_library_names_the_parameter_it_refuses():
    with pytest.raises(pneufrac.ModelError) as e:
        pneufrac.design("dd", 20000, beta=1.5)
    assert e.value.param == "beta"
    with pytest.raises(pneufrac.ModelError) as e:
        pneufrac.design("dd", 20000, effects={"sat_lo": 2, "sat_hi": 1})
    assert e.value.param == "sat_hi"
    with pytest.raises(pneufrac.ModelError) as e:        # beyond the table's range
        pneufrac.design("dd", 20000, effects={"sat_lo": -1, "sat_hi": 1, "saturate": 4})
    assert e.value.param == "saturate"


def test_nonlinear_and_dead_time_have_no_transfer_function():
    nl = pneufrac.design("dd", 20000, effects={"backlash": 0.01})
    for call in (nl.ss, nl.zpk, nl.sos, nl.freqresp):
        with pytest.raises(ValueError, match="nonlinear"):
            call()
    dt = pneufrac.design("dd", 20000, effects={"dead_time": 0.001})
    with pytest.raises(ValueError, match="z\\^-D"):
        dt.ss()
    assert np.all(np.isfinite(dt.freqresp().discrete))     # the response has it
    with pytest.raises(ValueError, match="omega"):
        dt.freqresp([-1.0, 2.0])

# SPDX-License-Identifier: MIT
"""Records as they come: jittered time stamps, gaps, other column names,
ADC steps, inputs that never rest (data, timebase, signals)."""
import numpy as np
import pytest

from pneufrac_fit import cli, data, diagnose, excite, generate, signals, timebase


def _rec(n=3000, seed=0, **kw):
    ds = generate.generate("p", "none", {}, n=n, noise=0.005, seed=seed, **kw)
    return ds


def test_jitter_within_tolerance_is_accepted():
    ds = _rec()
    rng = np.random.default_rng(1)
    T = 1.0 / ds.fs
    t = ds.t + rng.uniform(-0.2, 0.2, ds.t.size) * T      # +-20 % of a period
    rec = data.make_record(t, ds.e, ds.pc)
    assert abs(rec.fs / ds.fs - 1) < 1e-3
    assert rec.n == ds.t.size
    assert any("jitter" in s for s in rec.notes)


def test_jitter_beyond_tolerance_is_refused():
    ds = _rec()
    rng = np.random.default_rng(2)
    t = ds.t + rng.uniform(-0.45, 0.45, ds.t.size) / ds.fs
    with pytest.raises(data.DataError, match="non-uniform sampling"):
        data.make_record(t, ds.e, ds.pc)


def test_gap_is_reported_and_the_longest_stretch_used():
    ds = _rec(n=4000)
    keep = np.r_[0:800, 850:4000]           # 50 samples lost at t = 0.8 s
    rec = data.make_record(ds.t[keep], ds.e[keep], ds.pc[keep])
    assert rec.n == 3150
    assert rec.t[0] == pytest.approx(0.85)
    notes = " ".join(rec.notes)
    assert "GAP in the record at t = 0.85 s" in notes and "50 sample(s) missing" in notes
    assert "longest stretch" in notes
    assert len(rec.gaps) == 1 and rec.gaps[0].missing == 50


def test_timebase_tolerance_is_a_quarter_period():
    assert timebase.JITTER_TOL == 0.25
    t = np.arange(1000) * 1e-3
    t[500] += 0.3e-3
    with pytest.raises(timebase.TimebaseError):
        timebase.analyse(t)


def test_other_column_names(tmp_path, capsys, monkeypatch):
    ds = _rec()
    p = tmp_path / "hist.csv"
    with open(p, "w") as f:
        f.write("Output,Time,Error,extra\n")
        for a, b, c in zip(ds.t, ds.e, ds.pc):
            f.write(f"{float(c)!r},{float(a)!r},{float(b)!r},1\n")
    got = {}

    def fake(rec, config, fixes=None, **kw):
        got["rec"] = rec
        raise cli.UsageError("stop here")
    monkeypatch.setattr(diagnose, "diagnose", fake)
    rc = cli.main(["diagnose", str(p), "--config", "p", "--columns", "t=time,e=error,pc=output"])
    assert rc == 2 and "stop here" in capsys.readouterr().err
    assert np.allclose(got["rec"].pc, ds.pc) and np.allclose(got["rec"].e, ds.e)
    rc = cli.main(["diagnose", str(p), "--config", "p"])
    err = capsys.readouterr().err
    assert rc == 2 and "missing column(s) t, e, pc" in err and "--columns" in err


@pytest.mark.parametrize("spec,msg", [("t=time,e", "expected t=NAME"),
                                      ("x=time", "expected t=NAME"),
                                      ("t=a,e=a", "three different columns")])
def test_bad_columns(spec, msg):
    with pytest.raises(data.DataError, match=msg):
        data.parse_columns(spec)


def test_adc_steps_recognised():
    rng = np.random.default_rng(3)
    x = np.sin(np.arange(5000) / 200.0) + 0.002 * rng.standard_normal(5000)
    q = 2.0 / 4095
    xq = np.round(x / q) * q
    assert signals.quantum(xq) == pytest.approx(q, rel=1e-6)
    assert signals.quantum(x) == 0.0
    # a few set levels are not a converter: steps, a PRBS
    assert signals.quantum(excite.steps(5000, 1000.0, rng)) == 0.0
    assert signals.quantum(excite.prbs(5000, 1000.0, rng)) == 0.0
    # the noise of a quantised signal includes its quantisation noise
    assert signals.noise_sd(np.round(np.zeros(100) / q) * q, q) == pytest.approx(q / np.sqrt(12))


def test_quantised_record_is_noted():
    ds = generate.generate("p", "none", {}, n=3000, noise=0.002, seed=2, adc_bits=10)
    rec = data.make_record(ds.t, ds.e, ds.pc)
    assert rec.q_pc > 0 and any("pc is quantised" in s for s in rec.notes)


def test_input_that_never_rests():
    """A sine sweep from the first sample has no opening rest stretch (it
    used to be taken whole as one): the operating point is fitted."""
    rng = np.random.default_rng(4)
    e = 0.3 + excite.sweep(4000, 1000.0, rng, amp=0.5, rest=0.0)
    ds = generate.generate("p", "none", {}, n=4000, noise=0.005, seed=5, e=e)
    rec = data.make_record(ds.t, ds.e, ds.pc + 2.0)
    assert rec.rest == 0 and rec.e0 is None
    assert any("does not open at rest" in s for s in rec.notes)
    assert signals.change_points(ds.e).size > 1000       # it changes all the time


def test_output_still_settling_is_no_rest():
    """Input at rest while the output still moves (an integrator running):
    not an operating point."""
    n = 2000
    e = np.r_[np.zeros(300), np.ones(n - 300)]
    pc = np.r_[np.linspace(0, 1, 300), np.ones(n - 300)]
    k, why = signals.opening_rest(e, pc, 0.0, 0.0, 1e-4, 0.0)
    assert k == 0 and "output" in why

# SPDX-License-Identifier: MIT
"""Every bad input gives one clear line on stderr and exit status 2."""
import os
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from pneufrac_fit import cli, diagnose, generate

ROOT = Path(__file__).resolve().parents[2]


def _write(path, t, e, pc, header="t,e,pc"):
    with open(path, "w") as f:
        f.write("# comment line\n" + header + "\n")
        for a, b, c in zip(t, e, pc):
            f.write(f"{float(a)!r},{float(b)!r},{float(c)!r}\n")
    return str(path)


def _good(n=1000):
    rng = np.random.default_rng(0)
    e = generate.bump_input(n, 1000.0, rng)
    t = np.arange(n) / 1000.0
    return t, e, 0.01 * e + 1e-4 * rng.standard_normal(n)


def _run(capsys, argv):
    rc = cli.main(argv)
    err = capsys.readouterr().err
    return rc, err


def _case(tmp_path, name):
    t, e, pc = _good()
    header = "t,e,pc"
    if name == "non-uniform":           # the second half at 1.3x the period
        t = t.copy(); t[500:] = t[500] + 1.3 * (t[500:] - t[500])
    elif name == "short-step":          # a stamp a tenth of a period after the last
        t = t.copy(); t[300] = t[299] + 0.0001
    elif name == "gaps-everywhere":     # a gap every 150 samples: no stretch of 200
        t = t.copy()
        for k in range(150, t.size, 150):
            t[k:] += 0.01
    elif name == "non-monotonic":
        t = t.copy(); t[300], t[301] = t[301], t[300]
    elif name == "repeated-time":
        t = t.copy(); t[300] = t[299]
    elif name == "nan":
        pc = pc.copy(); pc[42] = np.nan
    elif name == "nan-input":
        e = e.copy(); e[7] = np.nan
    elif name == "missing-column":
        header = "t,e,p"
    elif name == "too-few":
        t, e, pc = t[:50], e[:50], pc[:50]
    elif name == "flat":
        e = np.full_like(e, 0.3)
    elif name == "flat-noisy":
        e = 0.3 + 1e-4 * np.random.default_rng(1).standard_normal(e.size)
    elif name == "no-validation-excitation":
        e = e.copy(); e[650:] = e[650]
    elif name == "flat-output-tail":
        pc = pc.copy(); pc[700:] = pc[700]
    elif name == "flat-output-tail-rounding":
        pc = pc.copy(); pc[700:] = 0.1 + 1e-17 * (np.arange(pc.size - 700) % 3)
    return _write(tmp_path / f"{name}.csv", t, e, pc, header)


CASES = {
    "non-uniform": "non-uniform sampling",
    "short-step": "under half the typical step",
    "gaps-everywhere": "gaps in the record",
    "non-monotonic": "not strictly increasing",
    "repeated-time": "not strictly increasing",
    "nan": "NaN",
    "nan-input": "NaN",
    "missing-column": "missing column",
    "too-few": "too few samples",
    "flat": "flat",
    "flat-noisy": "flat",
    "no-validation-excitation": ("validation) of the record; the fit learns from one part "
                                 "and is judged on the other"),
    "flat-output-tail": "output pc does not move in the last 30 % (validation)",
    "flat-output-tail-rounding": "output pc does not move in the last 30 % (validation)",
}


@pytest.mark.parametrize("name", list(CASES))
def test_bad_record(tmp_path, capsys, name):
    path = _case(tmp_path, name)
    rc, err = _run(capsys, ["diagnose", path, "--config", "p", "--quiet"])
    assert rc == 2
    assert "Traceback" not in err
    assert err.count("\n") == 1 and err.startswith("pneufrac-fit: error:")
    assert CASES[name].lower() in err.lower(), err


def test_missing_file(tmp_path, capsys):
    rc, err = _run(capsys, ["diagnose", str(tmp_path / "nope.csv"), "--config", "p"])
    assert rc == 2 and "no such file" in err


def test_text_in_numbers(tmp_path, capsys):
    p = tmp_path / "x.csv"
    p.write_text("t,e,pc\n0,1,2\n0.001,abc,2\n")
    rc, err = _run(capsys, ["diagnose", str(p), "--config", "p"])
    assert rc == 2 and "not a number" in err


@pytest.mark.parametrize("fix,msg", [
    ("k1=2", "not identifiable on its own"),
    ("beta=1.5", "outside"),
    ("tau", "NAME=VALUE"),
    ("nu=0.5", "not a group of config p"),
])
def test_bad_fix(tmp_path, capsys, fix, msg):
    t, e, pc = _good()
    path = _write(tmp_path / "ok.csv", t, e, pc)
    rc, err = _run(capsys, ["diagnose", path, "--config", "p", "--fix", fix])
    assert rc == 2 and msg in err, err


def test_bad_config(tmp_path, capsys):
    with pytest.raises(SystemExit) as ex:
        cli.main(["diagnose", "x.csv", "--config", "pd"])
    assert ex.value.code == 2


def _one_line(rc, err, msg):
    assert rc == 2, err
    assert "Traceback" not in err
    assert err.count("\n") == 1 and err.startswith("pneufrac-fit: error:"), err
    assert msg.lower() in err.lower(), err


GEN = ["generate", "--config", "p", "--n", "300"]


@pytest.mark.parametrize("extra,msg", [
    (["--fs", "nan"], "--fs nan"),
    (["--fs", "inf"], "--fs inf"),
    (["--fs", "-5"], "--fs -5"),
    (["--fs", "1"], "shortest hold"),
    (["--fs", "1e9"], "--fs 1e+09"),
    (["--noise", "nan"], "--noise nan"),
    (["--noise", "-0.1"], "--noise -0.1"),
    (["--noise", "inf"], "--noise inf"),
    (["--n", "5"], "--n 5"),
    (["--oversample", "0"], "--oversample 0"),
    (["-o", "/nonexistent-dir/x.csv"], "-o /nonexistent-dir/x.csv: cannot write"),
    (["--rest", "-1"], "--rest -1"),
    (["--drift", "nan"], "--drift nan"),
    (["--adc-bits", "2"], "--adc-bits 2"),
    (["--order", "9"], "--order 9"),
    (["--effect", "lag:tau=0.01", "--effect", "lag:tau=0.02"], "lag given twice"),
    (["--effect", "nozzle:xh=1,bias=x"], "'x' is not a number"),
    (["--effect", "nozzle:xh=1,gap=1"], "nozzle takes xh=...[,bias=...]"),
])
def test_bad_generate(tmp_path, capsys, extra, msg):
    rc, err = _run(capsys, GEN + extra)
    _one_line(rc, err, msg)


def test_generate_output_is_a_directory(tmp_path, capsys):
    rc, err = _run(capsys, GEN + ["-o", str(tmp_path)])
    _one_line(rc, err, "cannot write")


def test_bump_input_terminates_at_low_rate():
    """A hold shorter than a sample is one sample (it used to loop forever)."""
    e = generate.bump_input(60, 1.0, np.random.default_rng(0))
    assert e.size == 60 and np.count_nonzero(np.diff(e)) >= 50


def _no_fit(monkeypatch, seen=None):
    def fake(rec, config, fixes=None, **kw):
        if seen is None:
            raise AssertionError("the fit ran")
        seen.update(kw)
        raise cli.UsageError("stop here")
    monkeypatch.setattr(diagnose, "diagnose", fake)


def test_out_not_a_directory_before_fit(tmp_path, capsys, monkeypatch):
    t, e, pc = _good()
    path = _write(tmp_path / "ok.csv", t, e, pc)
    f = tmp_path / "file"
    f.write_text("x")
    _no_fit(monkeypatch)
    rc, err = _run(capsys, ["diagnose", path, "--config", "p", "--out", str(f / "sub")])
    _one_line(rc, err, f"--out {f / 'sub'}: cannot create the directory")


def test_out_created_before_fit(tmp_path, capsys, monkeypatch):
    t, e, pc = _good()
    path = _write(tmp_path / "ok.csv", t, e, pc)
    seen = {}
    _no_fit(monkeypatch, seen)
    out = tmp_path / "a" / "b"
    rc, err = _run(capsys, ["diagnose", path, "--config", "p", "--out", str(out),
                            "--jobs", "99"])
    assert rc == 2 and "stop here" in err
    assert out.is_dir() and seen["jobs"] == 5          # created first; jobs clamped


@pytest.mark.parametrize("jobs,want", [("0", 1), ("-3", 1), ("3", 3)])
def test_jobs_clamped(tmp_path, capsys, monkeypatch, jobs, want):
    t, e, pc = _good()
    path = _write(tmp_path / "ok.csv", t, e, pc)
    seen = {}
    _no_fit(monkeypatch, seen)
    _run(capsys, ["diagnose", path, "--config", "p", "--jobs", jobs])
    assert seen["jobs"] == want


@pytest.mark.parametrize("extra,msg", [
    (["--e0", "0.5"], "--e0 and --pc0 go together"),
    (["--e0", "nan", "--pc0", "1"], "--e0 must be finite"),
    (["--e0", "0", "--pc0", "inf"], "--pc0 must be finite"),
])
def test_bad_operating_point(tmp_path, capsys, extra, msg):
    t, e, pc = _good()
    path = _write(tmp_path / "ok.csv", t, e, pc)
    rc, err = _run(capsys, ["diagnose", path, "--config", "p"] + extra)
    _one_line(rc, err, msg)


def test_operating_point_option_reaches_the_fit(tmp_path, capsys, monkeypatch):
    t, e, pc = _good()
    path = _write(tmp_path / "ok.csv", t, e, pc)
    got = {}

    def fake(rec, config, fixes=None, **kw):
        got["op"] = (rec.e0, rec.pc0)
        raise cli.UsageError("stop here")
    monkeypatch.setattr(diagnose, "diagnose", fake)
    _run(capsys, ["diagnose", path, "--config", "p", "--e0", "0.25", "--pc0", "3"])
    assert got["op"] == (0.25, 3.0)


def test_pid_fix_nu_above_w(tmp_path, capsys):
    t, e, pc = _good()
    path = _write(tmp_path / "ok.csv", t, e, pc)
    rc, err = _run(capsys, ["diagnose", path, "--config", "pid", "--fix", "nu=0.9",
                            "--fix", "w=0.8"])
    _one_line(rc, err, "needs nu <= w")


def _exe():
    p = Path(sys.executable).with_name("pneufrac-fit")
    return [str(p)] if p.exists() else [sys.executable, "-m", "pneufrac_fit.cli"]


def test_broken_pipe_is_quiet():
    """generate | head -1: no traceback, no complaint, status 0."""
    env = dict(os.environ)
    env.setdefault("PYTHONPATH", str(ROOT / "tools" / "python"))
    pr = subprocess.Popen(_exe() + ["generate", "--config", "p", "--n", "40000",
                                    "--oversample", "1"],
                          stdout=subprocess.PIPE, stderr=subprocess.PIPE, env=env)
    first = pr.stdout.readline()
    pr.stdout.close()
    err = pr.stderr.read().decode()
    rc = pr.wait(timeout=60)
    pr.stderr.close()
    assert first.startswith(b"#")
    assert rc == 0 and err == "", err


@pytest.mark.parametrize("cmd", ["generate", "diagnose"])
@pytest.mark.parametrize("seed,msg", [("-1", "-1 is outside"), ("1.5", "not an integer"),
                                      ("abc", "not an integer"),
                                      (str(2**64), "is outside")])
def test_bad_seed(tmp_path, capsys, monkeypatch, cmd, seed, msg):
    """Issue 12, F5: --seed -1 ended in a traceback from numpy."""
    _no_fit(monkeypatch)
    if cmd == "generate":
        argv = GEN + ["--seed", seed]
    else:
        t, e, pc = _good()
        argv = ["diagnose", _write(tmp_path / "ok.csv", t, e, pc), "--config", "p",
                "--seed", seed]
    with pytest.raises(SystemExit) as ex:
        cli.main(argv)
    err = capsys.readouterr().err
    assert ex.value.code == 2
    _one_line(2, err, "argument --seed:")
    assert msg in err, err


def test_largest_seed_is_accepted(capsys):
    rc = cli.main(GEN + ["--seed", str(cli.MAX_SEED)])
    out = capsys.readouterr().out
    assert rc == 0 and out.startswith("#")


def test_generate_two_effects_and_options(capsys):
    rc = cli.main(["generate", "--config", "dd", "--n", "400", "--effect", "lag:tau=0.01",
                   "--effect", "nozzle:xh=2,bias=0.5", "--input", "sweep", "--rest", "0",
                   "--noise-kind", "ar1", "--adc-bits", "12", "--drift", "0.02"])
    out = capsys.readouterr().out
    assert rc == 0
    assert "effect=lag+nozzle" in out.splitlines()[0]
    assert len(out.splitlines()) == 400 + 3

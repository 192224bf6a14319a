# SPDX-License-Identifier: MIT
"""Every bad input gives one clear line on stderr and exit status 2."""
import numpy as np
import pytest

from pneufrac_fit import cli, generate


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
    if name == "non-uniform":
        t = t.copy(); t[500:] += 0.0004
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
    return _write(tmp_path / f"{name}.csv", t, e, pc, header)


CASES = {
    "non-uniform": "non-uniform sampling",
    "non-monotonic": "not strictly increasing",
    "repeated-time": "not strictly increasing",
    "nan": "NaN",
    "nan-input": "NaN",
    "missing-column": "missing column",
    "too-few": "too few samples",
    "flat": "flat",
    "flat-noisy": "flat",
    "no-validation-excitation": "validation",
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

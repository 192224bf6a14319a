# SPDX-License-Identifier: MIT
"""Records as plant files come (branch attack26): a byte-order mark, CR or
CRLF line ends, quoted fields and comments in another code page are read
like the plain file; what cannot be read is refused in one line that names
the file, the line and what was expected; the time column's unit is
checked against the sample rates the fit can simulate."""
import json

import numpy as np
import pytest

from pneufrac_fit import cli, data
from test_bad_input import _good


def _text(t, e, pc, sep=",", nl="\n", quote=False, header="t,e,pc"):
    q = '"' if quote else ""
    rows = [sep.join(f"{q}{h}{q}" for h in header.split(","))]
    rows += [sep.join(f"{q}{float(x)!r}{q}" for x in r) for r in zip(t, e, pc)]
    return nl.join(rows) + nl


def _read(tmp_path, raw: bytes):
    p = tmp_path / "r.csv"
    p.write_bytes(raw)
    return data.read_csv(p)


def _refused(tmp_path, raw: bytes) -> str:
    with pytest.raises(data.DataError) as ex:
        _read(tmp_path, raw)
    msg = str(ex.value)
    assert "\n" not in msg and "r.csv" in msg, msg
    return msg


@pytest.mark.parametrize("kind", ["bom", "crlf", "cr", "quoted", "latin1-comment"])
def test_plant_file_variants_read_like_the_plain_file(tmp_path, kind):
    t, e, pc = _good()
    plain = _read(tmp_path, _text(t, e, pc).encode())
    raw = {"bom": "\ufeff" + _text(t, e, pc),
           "crlf": _text(t, e, pc, nl="\r\n"),
           "cr": _text(t, e, pc, nl="\r"),
           "quoted": _text(t, e, pc, quote=True)}.get(kind, "")
    raw = raw.encode() if raw else b"# Druck in \xb0C, Ventil 3\n" + _text(t, e, pc).encode()
    rec = _read(tmp_path, raw)
    for name in ("t", "e", "pc"):
        np.testing.assert_array_equal(getattr(rec, name), getattr(plain, name))


@pytest.mark.parametrize("kind,want", [
    ("utf16", "the file is UTF-16 text; save it as UTF-8"),
    ("latin1-data", ":3: character 7: byte 0xe9 is not UTF-8"),
    ("nul", ":1: NUL byte in the line"),
    ("semicolon", ":1: the header's fields are separated by ';', not commas"),
    ("tab", ":1: the header's fields are separated by '\\t', not commas"),
    ("duplicate", ":1: column e appears 2 times in the header (columns 2, 4)"),
    ("empty-cell", ":3: e is empty"),
    ("underscore", ":3: e is not a number: '1_0'"),
])
def test_unreadable_files_are_named(tmp_path, kind, want):
    t, e, pc = _good()
    text = _text(t, e, pc)
    lines = text.splitlines(keepends=True)
    if kind == "utf16":
        raw = text.encode("utf-16")
    elif kind == "latin1-data":
        raw = "".join(lines[:2]).encode() + b"0.001,\xe9,0\n" + "".join(lines[3:]).encode()
    elif kind == "nul":
        raw = ("t,e,pc\0\n" + "".join(lines[1:])).encode()
    elif kind == "semicolon":
        raw = _text(t, e, pc, sep=";").replace(".", ",").encode()
    elif kind == "tab":
        raw = _text(t, e, pc, sep="\t").encode()
    elif kind == "duplicate":
        raw = "".join(ln.rstrip("\n") + ",0\n" for ln in lines).replace(
            "t,e,pc,0", "t,e,pc,e", 1).encode()
    elif kind == "empty-cell":
        raw = ("".join(lines[:2]) + "0.001,,0\n" + "".join(lines[3:])).encode()
    else:
        raw = ("".join(lines[:2]) + "0.001,1_0,0\n" + "".join(lines[3:])).encode()
    msg = _refused(tmp_path, raw)
    assert want in msg, msg


def test_a_long_header_is_quoted_short(tmp_path):
    """A logger's header of a hundred channels: the message quotes its
    start, not the whole line."""
    t, e, pc = _good()
    header = ",".join(f"channel_{k:03d}" for k in range(100))
    body = "".join(",".join(["0"] * 100) + "\n" for _ in range(300))
    msg = _refused(tmp_path, (header + "\n" + body).encode())
    assert "missing column(s) t, e, pc" in msg and len(msg) < 400, msg


def test_text_with_cr_line_ends_is_read():
    """parse_csv (fleet, the Python API) reads CR line ends as the file
    reader does (before: the whole text was one header line)."""
    t, e, pc = _good()
    rec = data.parse_csv(_text(t, e, pc, nl="\r"), "r")
    np.testing.assert_array_equal(rec.pc, data.parse_csv(_text(t, e, pc), "r").pc)


@pytest.mark.parametrize("scale,rate,why", [
    (1000.0, "at 1 Hz", "t is not in seconds"),
    (1e-9, "sample rate of 1e+12 Hz", "t must be in seconds")])
def test_time_in_other_units_is_refused(tmp_path, capsys, scale, rate, why):
    """t in ms (3000 samples at 1 kHz read as 1 Hz: 2000 simulation steps
    per sample, beyond data.MAX_SIM_STEPS) or a rate above the library's
    (a traceback from the fit) is refused before the fit, naming the rate
    and the unit expected."""
    t, e, pc = _good(3000)
    p = tmp_path / "r.csv"
    p.write_text(_text(t * scale, e, pc))
    rc = cli.main(["diagnose", str(p), "--config", "p", "--quiet"])
    err = capsys.readouterr().err
    assert rc == 2 and err.count("\n") == 1, err
    assert rate in err and why in err, err


def test_every_generated_rate_is_read():
    """The fastest record generate writes is within the rates read (the
    slowest: test_fixattack's slow records)."""
    assert cli.MAX_FS <= data.max_rate()


@pytest.mark.parametrize("argv,want", [
    (["--fix", "tau=0.001", "--fix", "tau=0.002"], "--fix tau: given twice"),
    (["--columns", "t=t,t=time"], "--columns t=t,t=time: t given twice"),
])
def test_an_option_value_given_twice_is_refused(tmp_path, capsys, argv, want):
    t, e, pc = _good()
    p = tmp_path / "r.csv"
    p.write_text(_text(t, e, pc))
    rc = cli.main(["diagnose", str(p), "--config", "p", "--quiet", *argv])
    err = capsys.readouterr().err
    assert rc == 2 and want in err, err


@pytest.mark.parametrize("argv,want", [
    (["--set", "tau=0.001", "--set", "tau=0.002"], "--set tau: given twice"),
    (["--effect", "lag:tau=0.01,tau=0.02"], "--effect lag: tau: given twice"),
])
def test_a_generate_value_given_twice_is_refused(capsys, argv, want):
    rc = cli.main(["generate", "--config", "p", *argv])
    err = capsys.readouterr().err
    assert rc == 2 and want in err, err


@pytest.mark.parametrize("argv,want", [
    (["diagnose", "NOPE.csv", "--config", "p", "--json"], "NOPE.csv: no such file"),
    (["diagnose", "NOPE.csv", "--config", "pd", "--json"], "invalid choice: 'pd'"),
    (["diagnose", "--json"], "required"),
])
def test_json_errors_are_a_json_object(capsys, argv, want):
    """With --json a failure is one JSON object on stdout too (before:
    nothing, which a script's json.loads choked on)."""
    try:
        rc = cli.main(argv)
    except SystemExit as ex:        # argparse's errors end as argparse does
        rc = ex.code
    cap = capsys.readouterr()
    j = json.loads(cap.out)
    assert rc == 2 and j["status"] == 2 and want in j["error"], cap
    assert cap.err == f"pneufrac-fit: error: {j['error']}\n"


@pytest.mark.parametrize("scale,want", [(1e150, "beyond the library's range of levels"),
                                        (1e-300, "its squared deviations are lost")])
def test_values_in_units_the_fit_cannot_work_in_are_refused(scale, want):
    """Both ended in a traceback from the fit (SVD did not converge)."""
    t, e, pc = _good()
    with pytest.raises(data.DataError) as ex:
        data.parse_csv(_text(t, e * scale, pc * scale), "r")
    assert want in str(ex.value) and "rescale" in str(ex.value), ex.value


@pytest.mark.parametrize("scale", [1e6, 1e-12])
def test_values_in_large_or_small_units_are_read(scale):
    t, e, pc = _good()
    rec = data.parse_csv(_text(t, e * scale, pc * scale), "r")
    assert rec.n == t.size


def test_an_operating_point_beyond_the_levels_is_refused(tmp_path, capsys):
    """--e0 1e300 --pc0 1e300 ended in a traceback from the fit."""
    t, e, pc = _good()
    p = tmp_path / "r.csv"
    p.write_text(_text(t, e, pc))
    rc = cli.main(["diagnose", str(p), "--config", "p", "--quiet", "--e0", "1e300",
                   "--pc0", "1e300"])
    err = capsys.readouterr().err
    assert rc == 2 and "beyond the library's range of levels" in err, err


@pytest.mark.parametrize("seed", ["-1", str(2**64)])
def test_fleet_reads_the_seed_as_diagnose_does(tmp_path, capsys, seed):
    """fleet's --seed had its own rule (negative refused, 2**64 taken):
    now the one diagnose and generate use, before any cluster starts."""
    with pytest.raises(SystemExit) as ex:
        cli.main(["fleet", str(tmp_path), "--config", "p", "--seed", seed])
    err = capsys.readouterr().err
    assert ex.value.code == 2 and "argument --seed:" in err and "is outside" in err, err


def test_a_device_as_the_file_is_read_bounded(capsys):
    """/dev/zero was read until the memory ran out (fleet alone had a
    limit, by the file's size, which a device does not report)."""
    rc = cli.main(["diagnose", "/dev/zero", "--config", "p", "--quiet"])
    err = capsys.readouterr().err
    assert rc == 2 and "/dev/zero: larger than 256 MiB" in err, err


def test_json_error_when_stdout_itself_fails(tmp_path):
    """diagnose --json > /dev/full: the error object could not be written
    either, and that ended in a traceback (found on this branch's own
    change); now the one stderr line, status 2."""
    import subprocess
    import sys
    from pathlib import Path
    if not Path("/dev/full").exists():
        pytest.skip("no /dev/full")
    t, e, pc = _good(3000)
    p = tmp_path / "r.csv"
    p.write_text(_text(t * 1000.0, e, pc))      # refused for its cost: no fit
    with open("/dev/full", "w") as full:
        r = subprocess.run([sys.executable, "-c", "import sys; from pneufrac_fit.cli import "
                            "main; sys.exit(main())", "diagnose", str(p), "--config", "p",
                            "--json"], stdout=full, stderr=subprocess.PIPE, text=True,
                           timeout=120)
    assert r.returncode == 2 and "Traceback" not in r.stderr, r.stderr
    assert r.stderr.count("\n") == 1 and "samples at 1 Hz" in r.stderr, r.stderr

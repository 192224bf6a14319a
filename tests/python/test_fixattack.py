# SPDX-License-Identifier: MIT
"""After review of attack26 (branch fixattack): the record's cost, not its
sample rate, bounds what is read (slow historian exports are records);
every bound is accepted at itself; a short record at a high rate is
diagnosed; an unexpected failure is one line (and a JSON object); --json
is the parsed option; headers are read where they are used."""
import json

import numpy as np
import pytest

from pneufrac_fit import cli, data, fleet, lib
from test_attack26_csv import _text
from test_bad_input import _good


def _at(fs, n=1000, t0=0.0):
    """_good's signals at fs Hz from t0."""
    _, e, pc = _good(n)
    return t0 + np.arange(n) / fs, e, pc


@pytest.mark.parametrize("fs", [10.0, 20.0, 25.0, 30.0, 31.25, 1e4, 1e5])
def test_genuine_slow_and_fast_records_are_read(fs):
    """10, 20, 25 Hz are common historian and PLC export rates: refused
    before as "t must be in seconds" (the rate floor was 31.25 Hz, and
    31.25 Hz itself was refused as outside [31.25, ...])."""
    t, e, pc = _at(fs, 3000)
    rec = data.make_record(t, e, pc, "r")
    assert rec.n == t.size and rec.fs == pytest.approx(fs, rel=1e-9)


@pytest.mark.parametrize("t0", [1.7e9, -5.0])
def test_unix_time_and_negative_time_are_read(t0):
    t, e, pc = _at(1000.0, t0=t0)
    rec = data.parse_csv(_text(t, e, pc), "r")
    assert rec.n == t.size and rec.fs == pytest.approx(1000.0, rel=1e-6)


def test_the_cost_bound_is_accepted_at_itself_and_refused_beyond():
    """At 1 Hz every sample costs 2000 simulation steps (model.F_SIM_MIN):
    2000 samples are data.MAX_SIM_STEPS exactly, 2001 are beyond; the
    message names both causes (t in ms, a record too long) and the way out."""
    assert data.sim_steps(2000, 1.0) == data.MAX_SIM_STEPS
    t, e, pc = _at(1.0, 2000)
    assert data.make_record(t, e, pc, "r").n == 2000
    t, e, pc = _at(1.0, 2001)
    with pytest.raises(data.DataError) as ex:
        data.make_record(t, e, pc, "r")
    msg = str(ex.value)
    assert "2001 samples at 1 Hz" in msg and "t is not in seconds" in msg, msg
    assert "too long to fit at once" in msg and "cut it" in msg, msg


def test_the_top_rate_is_accepted_at_itself_and_refused_beyond():
    hi = lib.param_range("fs").hi
    t, e, pc = _at(hi)
    assert data.make_record(t, e, pc, "r").n == t.size
    t, e, pc = _at(hi * 1.001)
    with pytest.raises(data.DataError) as ex:
        data.make_record(t, e, pc, "r")
    assert f"above the {hi:g} Hz the library simulates" in str(ex.value), ex.value
    assert "minutes or hours" in str(ex.value), ex.value


def test_levels_at_the_bound_are_read_and_beyond_refused():
    big = data.max_level()
    assert big == 1e9
    t, e, pc = _good()
    rec = data.make_record(t, e / np.max(np.abs(e)) * big, pc, "r")
    assert np.max(np.abs(rec.e)) == big
    with pytest.raises(data.DataError):
        data.make_record(t, e / np.max(np.abs(e)) * big * (1 + 1e-9), pc, "r")


def _short(n, fs):
    k = np.arange(n)
    e = np.where((k // (n // 6)) % 2 == 0, 0.0, 1.0)
    e[:20] = 0.0
    pc = 0.01 * e + 1e-4 * np.random.default_rng(0).standard_normal(n)
    return k / fs, e, pc


@pytest.mark.parametrize("n,fs", [(250, 2e5), (3000, 3e6)])
def test_a_short_record_at_a_high_rate_is_diagnosed(tmp_path, capsys, n, fs):
    """The exploration copy averaged it down to one sample (or none) and
    the fit ended in a traceback, stdout empty under --json."""
    p = tmp_path / "r.csv"
    p.write_text(_text(*_short(n, fs)))
    rc = cli.main(["diagnose", str(p), "--config", "p", "--quiet", "--json", "--jobs", "1"])
    cap = capsys.readouterr()
    assert rc == 0 and json.loads(cap.out)["config"] == "p", cap.err


def test_an_unexpected_failure_is_one_line_and_a_json_object(tmp_path, capsys, monkeypatch):
    def boom(a):
        raise RuntimeError("something broke")
    monkeypatch.setattr(cli, "cmd_diagnose", boom)
    rc = cli.main(["diagnose", "r.csv", "--config", "p", "--json"])
    cap = capsys.readouterr()
    j = json.loads(cap.out)
    assert rc == 1 and j["status"] == 1 and "something broke" in j["error"], cap
    assert cap.err.count("\n") == 1 and "Traceback" not in cap.err, cap.err


def test_an_abbreviated_json_option_gives_the_json_error(tmp_path, capsys):
    rc = cli.main(["diagnose", str(tmp_path / "nope.csv"), "--config", "p", "--js"])
    cap = capsys.readouterr()
    assert rc == 2 and json.loads(cap.out)["status"] == 2, cap


@pytest.mark.parametrize("cmd", [["generate", "--config", "p"], ["fleet", ".", "--config", "p"]])
def test_commands_without_json_print_no_json(capsys, cmd):
    with pytest.raises(SystemExit) as ex:
        cli.main([*cmd, "--json"])
    cap = capsys.readouterr()
    assert ex.value.code == 2 and cap.out == "" and "--json" in cap.err, cap


def test_oversample_has_one_bound():
    """diagnose took at most 16, generate 64, the automatic choice 64."""
    assert cli.MAX_OVERSAMPLE == 64
    with pytest.raises(cli.UsageError) as ex:
        cli.cmd_diagnose(cli._parser().parse_args(
            ["diagnose", "r.csv", "--config", "p", "--oversample", "65"]))
    assert "[1, 64]" in str(ex.value)


def test_an_unused_columns_name_need_not_be_utf8(tmp_path):
    """Excel on Windows writes cp1252: a unit in an unused column's name
    refused the whole record."""
    t, e, pc = _good()
    text = "".join(ln + ",20\n" for ln in _text(t, e, pc).splitlines())
    raw = text.replace("t,e,pc,20", "t,e,pc,temp \xb0C", 1).encode("latin-1")
    p = tmp_path / "r.csv"
    p.write_bytes(raw)
    assert data.read_csv(p).n == t.size


def test_a_quoted_field_may_hold_commas():
    t, e, pc = _good()
    text = "".join(ln + ",1.5\n" for ln in _text(t, e, pc).splitlines())
    text = text.replace("t,e,pc,1.5", 't,e,pc,"p, bar"', 1)    # was: 5 fields, rows 4
    rec = data.parse_csv(text, "r")
    np.testing.assert_array_equal(rec.pc, data.parse_csv(_text(t, e, pc), "r").pc)


def test_a_non_ascii_cell_is_escaped_once():
    t, e, pc = _good()
    lines = _text(t, e, pc).splitlines(keepends=True)
    text = "".join(lines[:2]) + "0.001,\u22121,0\n" + "".join(lines[3:])
    with pytest.raises(data.DataError) as ex:
        data.parse_csv(text, "r")
    assert "'\\u22121'" in str(ex.value) and "\\\\" not in str(ex.value), ex.value


def test_fleet_names_the_path_once(tmp_path):
    p = tmp_path / "u16.csv"
    p.write_bytes("t,e,pc\n".encode("utf-16"))
    with pytest.raises(ValueError) as ex:
        fleet.read_record(p)
    msg = fleet.read_error(p, ex.value)
    assert msg.count("u16.csv") == 1 and "UTF-16" in msg, msg

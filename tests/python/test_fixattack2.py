# SPDX-License-Identifier: MIT
"""After the second review of attack26 (branch fixattack2): a rate within
the tolerance of the top is the top; one cost check (simulation rate and
steps) wherever the oversampling is known, an explicit smaller
--oversample rescuing a long slow record; a note on rates slower than a
controller's dynamics (t in ms?); integer step counts in messages."""
import json

import numpy as np
import pytest

from pneufrac_fit import cli, data, diagnose, lib
from test_fixattack import _at


def test_a_top_rate_record_not_starting_at_zero_is_at_the_top():
    """10 MHz from t0 = 0.5 (stamps %.8f as a logger writes them) read
    1e-12 above the top: accepted, then the library refused the fit's
    simulation rate ("invalid parameter 'fs'")."""
    hi = lib.param_range("fs").hi
    t, e, pc = _at(hi, 3000, t0=0.5)
    text = "t,e,pc\n" + "".join(f"{a:.8f},{b:.17g},{c:.17g}\n" for a, b, c in zip(t, e, pc))
    for rec in (data.make_record(t, e, pc, "r"), data.parse_csv(text, "r")):
        assert rec.fs <= hi and rec.fs == pytest.approx(hi, rel=1e-9), rec.fs


def _write(tmp_path, fs, n):
    t, e, pc = _at(fs, n)
    p = tmp_path / "r.csv"
    p.write_text("t,e,pc\n" + "".join(f"{a:.17g},{b:.17g},{c:.17g}\n" for a, b, c in zip(t, e, pc)))
    return p


def _diagnose(p, *more):
    return cli.main(["diagnose", str(p), "--config", "p", "--quiet", "--json", *more])


def test_oversample_beyond_the_top_rate_is_refused(tmp_path, capsys):
    """200 kHz x 64 = 12.8 MHz: "the library refused the model" before."""
    rc = _diagnose(_write(tmp_path, 2e5, 1000), "--oversample", "64")
    cap = capsys.readouterr()
    j = json.loads(cap.out)
    assert rc == 2 and "--oversample 64" in j["error"] and "use at most 50" in j["error"], j
    assert "refused the model" not in j["error"], j


def test_oversample_beyond_the_cost_is_refused(tmp_path, capsys):
    """100 000 samples at 64x: 6.4 M steps, over data.MAX_SIM_STEPS."""
    rc = _diagnose(_write(tmp_path, 1000.0, 100_000), "--oversample", "64")
    j = json.loads(capsys.readouterr().out)
    assert rc == 2 and "--oversample 64: 100000 samples need 6,400,000" in j["error"], j
    assert "at most 62,500 samples at 64x" in j["error"], j


def test_a_smaller_oversample_rescues_a_long_slow_record(tmp_path, capsys, monkeypatch):
    """2001 samples at 1 Hz are refused at the automatic 2000x, read at
    --oversample 1: the check waits for the option (it was refused before
    the option was looked at)."""
    p = _write(tmp_path, 1.0, 2001)
    assert _diagnose(p) == 2
    assert "too long to fit at once" in json.loads(capsys.readouterr().out)["error"]
    seen = {}

    def fake(rec, config, fixes, **kw):     # the record was read: stop before the fit
        seen.update(n=rec.n, m=kw["oversample"])
        raise KeyboardInterrupt
    monkeypatch.setattr(diagnose, "diagnose", fake)
    with pytest.raises(KeyboardInterrupt):
        _diagnose(p, "--oversample", "1")
    assert seen == {"n": 2001, "m": 1}


def test_the_python_api_checks_the_cost():
    t, e, pc = _at(2e5, 1000)
    rec = data.make_record(t, e, pc, "r")
    with pytest.raises(data.DataError) as ex:
        diagnose.diagnose(rec, "p", oversample=64, progress=False)
    assert "--oversample 64" in str(ex.value), ex.value


def test_the_cost_message_counts_in_integers():
    """2001 samples at 1 Hz said "need 4e+06 steps ... more than the 4e+06"."""
    t, e, pc = _at(1.0, 2001)
    with pytest.raises(data.DataError) as ex:
        data.make_record(t, e, pc, "r")
    msg = str(ex.value)
    assert "4,002,000 simulation steps" in msg and "the 4,000,000 a fit" in msg, msg
    assert "at most 2,000 samples at this rate" in msg, msg


@pytest.mark.parametrize("fs,slow", [(10.0, True), (31.0, True), (31.25, False), (1e4, False)])
def test_a_rate_slower_than_the_dynamics_has_a_note(fs, slow):
    """A 10 kHz record stamped in ms reads as 10 Hz: read with no word."""
    t, e, pc = _at(fs, 3000)
    notes = data.make_record(t, e, pc, "r").notes
    said = [n for n in notes if "if t is in ms" in n]
    assert bool(said) == slow, notes
    if slow:
        assert f"{fs:g} Hz" in said[0] and "more than 64 steps" in said[0], said
        assert f"a {fs * 1000:g} Hz record" in said[0], said


def test_a_line_the_csv_module_cannot_split_names_the_line():
    """A quoted field over the csv module's 128 KiB limit ended as
    "internal error", exit 1."""
    t, e, pc = _at(1000.0, 300)
    text = "t,e,pc,note\n" + "".join(f"{a:.17g},{b:.17g},{c:.17g},x\n"
                                     for a, b, c in zip(t, e, pc))
    lines = text.splitlines(keepends=True)
    lines[3] = lines[3].replace(",x\n", ',"' + "y" * 200_000 + '"\n')
    with pytest.raises(data.DataError) as ex:
        data.parse_csv("".join(lines), "r")
    assert str(ex.value).startswith("r:4: cannot split the line"), ex.value


def test_a_quoted_line_with_a_nul_is_not_text():
    """On Python 3.9 and 3.10 (requires-python >= 3.9) the csv module
    raises on a NUL, which ended as "internal error"; 3.11 and later split
    the line and the cell's check names the NUL, so this fails before the
    change on 3.9 and 3.10 only."""
    t, e, pc = _at(1000.0, 300)
    text = "t,e,pc\n" + "".join(f'"{a:.17g}",{b:.17g},{c:.17g}\n' for a, b, c in zip(t, e, pc))
    lines = text.splitlines(keepends=True)
    lines[2] = lines[2].replace('"', '"\x00', 1)
    with pytest.raises(data.DataError) as ex:
        data.parse_csv("".join(lines), "r")
    assert str(ex.value).startswith("r:3: NUL byte"), ex.value


def test_a_missing_column_in_another_code_page_says_utf8(tmp_path):
    """--columns pc=p°C on a Latin-1 header said only "missing column(s)"."""
    t, e, pc = _at(1000.0, 300)
    text = "t,e,p\xb0C\n" + "".join(f"{a:.17g},{b:.17g},{c:.17g}\n" for a, b, c in zip(t, e, pc))
    p = tmp_path / "r.csv"
    p.write_bytes(text.encode("latin-1"))
    with pytest.raises(data.DataError) as ex:
        data.read_csv(p, data.parse_columns("pc=p\xb0C"))
    assert "missing column(s) p\xb0C" in str(ex.value), ex.value
    assert "save the file as UTF-8" in str(ex.value), ex.value
    with pytest.raises(data.DataError) as ex:      # a UTF-8 header: no such hint
        data.parse_csv(text, "r", data.parse_columns("pc=pc"))
    assert "UTF-8" not in str(ex.value), ex.value


def _boom(exc):
    def run(a):
        raise exc
    return run


def test_an_internal_error_with_newlines_is_one_line(capsys, monkeypatch):
    monkeypatch.setattr(cli, "cmd_diagnose", _boom(RuntimeError("two\nlines\r\n")))
    monkeypatch.delenv("PNEUFRAC_FIT_DEBUG", raising=False)
    rc = cli.main(["diagnose", "r.csv", "--config", "p", "--json"])
    cap = capsys.readouterr()
    assert rc == 1 and cap.err.count("\n") == 1 and "two lines" in cap.err, cap.err
    assert "PNEUFRAC_FIT_DEBUG" in cap.err and "two lines" in json.loads(cap.out)["error"]


def test_the_debug_variable_prints_the_traceback(capsys, monkeypatch):
    monkeypatch.setattr(cli, "cmd_diagnose", _boom(RuntimeError("broke")))
    monkeypatch.setenv("PNEUFRAC_FIT_DEBUG", "1")
    rc = cli.main(["diagnose", "r.csv", "--config", "p"])
    err = capsys.readouterr().err
    assert rc == 1 and "Traceback" in err and "RuntimeError: broke" in err, err


def test_out_of_memory_is_not_a_bug(capsys, monkeypatch):
    monkeypatch.setattr(cli, "cmd_diagnose", _boom(MemoryError()))
    rc = cli.main(["diagnose", "r.csv", "--config", "p", "--json"])
    cap = capsys.readouterr()
    j = json.loads(cap.out)
    assert rc == 2 and j["status"] == 2 and "out of memory" in j["error"], cap
    assert "internal error" not in cap.err, cap.err


@pytest.mark.parametrize("opt,json_out", [("--js", True), ("--json", True), ("--j", False),
                                          ("--jo", False)])
def test_a_refused_command_line_gives_json_for_json_abbreviations_only(capsys, opt, json_out):
    """argparse refuses --order x; --js (only --json starts so) asks for
    the JSON error, --j and --jo do not (--jobs starts so too)."""
    with pytest.raises(SystemExit) as ex:
        cli.main(["diagnose", "r.csv", "--config", "p", "--order", "x", opt])
    out = capsys.readouterr().out
    assert ex.value.code == 2
    assert (json.loads(out)["status"] == 2) if json_out else out == "", out


def test_wants_json_reads_the_parser():
    """Commands without --json never want it; an abbreviation is one the
    command's options leave unambiguous."""
    p = cli._parser()
    assert not cli._wants_json(["generate", "--config", "p", "--js"], p)
    assert not cli._wants_json(["fleet", ".", "--json"], p)
    assert cli._wants_json(["diagnose", "--jso"], p)
    assert not cli._wants_json(["diagnose", "--", "--json"], p)

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

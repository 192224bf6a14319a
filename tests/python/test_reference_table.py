# SPDX-License-Identifier: MIT
"""The committed exact reference (tests/ref) is what make_reference.py makes.

test_reference (C) checks the C reference against the table; this checks the
table against its generator, so that neither can drift alone: the case file
must equal the script's case list, and a sample of points, recomputed with
mpmath (Talbot and de Hoog), must equal the committed values to the digits
written.
"""
import csv
import importlib.util
import json
from pathlib import Path

import pytest

REF = Path(__file__).resolve().parents[1] / "ref"


def _generator():
    spec = importlib.util.spec_from_file_location("make_reference", REF / "make_reference.py")
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    return mod


GEN = _generator()


def _table():
    with (REF / "paper_step_exact.csv").open(newline="") as f:
        rows = list(csv.reader(f))
    return rows[0], rows[1:]


def test_case_file_is_the_scripts_case_list():
    assert json.loads((REF / "paper_step_cases.json").read_text()) == GEN.CASES


def test_table_has_every_case_and_time():
    header, rows = _table()
    assert header == ["t"] + list(GEN.CASES)
    assert [float(r[0]) for r in rows] == GEN.times()


# One early, one steep and one late point for each kind of configuration.
@pytest.mark.parametrize("case,row", [("ex4_beta0.6", 0), ("ex6_q1.0", 22),
                                      ("ex7", 40), ("pid", 66)])
def test_sampled_points_recompute(case, row):
    header, rows = _table()
    t = float(rows[row][0])
    written = float(rows[row][header.index(case)])
    value, methods_diff = GEN.step(GEN.CASES[case]["config"], GEN.CASES[case]["params"], t)
    assert methods_diff <= GEN.METHODS_AGREE
    # 15 significant digits written: half a unit in the 15th digit.
    assert abs(float(value) - written) <= 5e-15 * abs(written)

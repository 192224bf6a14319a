# SPDX-License-Identifier: MIT
"""End to end through the console script: generate, diagnose --json --out."""
import json
import os
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]


def _exe():
    p = Path(sys.executable).with_name("pneufrac-fit")
    if p.exists():
        return [str(p)]
    return [sys.executable, "-m", "pneufrac_fit.cli"]


def test_generate_and_diagnose(tmp_path):
    env = dict(os.environ)
    env.setdefault("PYTHONPATH", str(ROOT / "tools" / "python"))
    csv = tmp_path / "bump.csv"
    subprocess.run(_exe() + ["generate", "--config", "p", "--effect", "backlash:width=0.06",
                             "--n", "4000", "--seed", "3", "-o", str(csv)],
                   check=True, env=env)
    out = tmp_path / "rep"
    r = subprocess.run(_exe() + ["diagnose", str(csv), "--config", "p", "--json",
                                 "--out", str(out)],
                       check=True, env=env, capture_output=True, text=True)
    j = json.loads(r.stdout)
    assert "round 1" in r.stderr              # progress on stderr
    for k in ("cause", "causes", "effect_params", "baseline", "extended", "gain",
              "candidates", "rounds", "evidence", "noise", "guards", "ambiguous"):
        assert k in j
    assert j["ambiguous"] == []               # one dead band: nothing to tell apart
    for m in ("baseline", "extended"):
        for k in ("params", "nrmse_fit", "nrmse_val", "bic"):
            assert k in j[m]
    assert set(j["gain"]) >= {"nrmse_val_before", "nrmse_val_after", "delta_bic"}
    assert {c["name"] for c in j["candidates"]} == {
        "dead_time", "lag", "saturation", "backlash", "nozzle"}
    assert all(set(c) >= {"name", "nrmse_val", "nrmse_val_without", "delta_bic", "params",
                          "passes_guards", "why_not"} for c in j["candidates"])
    assert j["cause"] == "backlash"
    assert [c["name"] for c in j["causes"]] == ["backlash"]
    c = j["causes"][0]
    assert abs(c["params"]["deadband"] / 0.06 - 1) < 0.25
    lo, hi = c["ci95"]["deadband"]
    assert lo < c["params"]["deadband"] < hi
    assert c["gain"]["nrmse_val_with"] < c["gain"]["nrmse_val_without"]
    assert abs(j["effect_params"]["deadband"] / 0.06 - 1) < 0.25
    assert all(isinstance(s, str) for s in j["evidence"])
    for f in ("report.md", "diagnosis.json", "overview.png", "residuals-baseline.png",
              "residuals-extended.png", "candidates.png"):
        assert (out / f).stat().st_size > 0
    text = (out / "report.md").read_text()
    assert "![overview](overview.png)" in text and "Verdict: backlash" in text
    # the round table gives the held-out z the guard asks, beside the gain
    cand = next(x for x in j["candidates"] if x["name"] == "backlash")
    row = next(l for l in text.splitlines() if l.startswith("| backlash |"))
    assert row.split("|")[-3].strip().strip("()") == f"{cand['val_z']:.3g}"


def test_operating_point_and_absolute_limits(tmp_path):
    """A record at an operating point (pc0 = 9, e0 = 0.5): saturation limits
    come back in absolute output units."""
    from pneufrac_fit import data, diagnose, generate, output
    import numpy as np
    rng = np.random.default_rng(4)
    e = generate.bump_input(4000, 1000.0, rng)
    ds = generate.generate("id", "saturation", {"sat_lo": -4.0, "sat_hi": 5.0}, n=4000,
                           noise=0.002, seed=5, e=e)
    rec = data.make_record(ds.t, ds.e + 0.5, ds.pc + 9.0)
    d = diagnose.diagnose(rec, "id", progress=False)
    j = output.to_dict(d)
    assert j["cause"] == "saturation"
    assert abs(j["effect_params"]["sat_hi"] - 14.0) < 0.5
    assert abs(j["effect_params"]["sat_lo"] - 5.0) < 0.5
    # both limits clip the fit part: both are the record's, and no note says otherwise
    assert j["causes"][0]["limits_not_seen"] == []
    assert not any("limit is seen" in n for n in j["fit_notes"])

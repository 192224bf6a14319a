# SPDX-License-Identifier: MIT
"""pneufrac.diagnose: the diagnosis of pneufrac-fit as a Python object, its
table (to_frame), and the plots as Figures that write nothing."""
import json
import subprocess
import sys
from pathlib import Path

import numpy as np
import pandas as pd
import pytest

import pneufrac


def fit_exe():
    p = Path(sys.executable).with_name("pneufrac-fit")
    return [str(p)] if p.exists() else [sys.executable, "-m", "pneufrac_fit.cli"]


@pytest.fixture(scope="module")
def record(tmp_path_factory):
    """A dd bump test with a 12 ms dead time hidden in it."""
    f = tmp_path_factory.mktemp("rec") / "loop.csv"
    subprocess.run(fit_exe() + ["generate", "--config", "dd", "--effect", "deadtime:t=0.012",
                                "--n", "3000", "--seed", "4", "-o", str(f)], check=True)
    return f


@pytest.fixture(scope="module")
def dx(record):
    return pneufrac.diagnose(record, "dd", jobs=1)


def test_the_diagnosis_names_the_cause(dx):
    assert dx.cause == "dead_time"
    assert [c["name"] for c in dx.causes] == ["dead_time"]
    c = dx.causes[0]
    assert c["params"]["dead_time"] == pytest.approx(0.012, abs=0.0011)
    assert dx.params["dead_time"] == c["params"]["dead_time"]
    for name, (lo, hi) in dx.intervals.items():
        assert lo <= dx.params[name] <= hi, name
    assert dx.verdict and dx.evidence
    assert "dead_time" in repr(dx)


def test_causes_from_either_json(dx):
    """causes_of reads a JSON with a causes list (most important first) as
    it stands, and one with a single cause as a list of that one; both the
    Diagnosis and the fleet's rows read causes through it."""
    from pneufrac.diagnosis import causes_of
    from pneufrac_fit import fleet_report
    j = json.loads(json.dumps(dx.to_dict()))
    single = {k: v for k, v in j.items() if k != "causes"}
    assert [c["name"] for c in causes_of(single)] == [single["cause"]]
    assert causes_of({**single, "cause": "none"}) == []
    two = [{"name": "lag", "place": "output", "params": {"lag": 0.02}, "ci95": {}},
           {"name": "dead_time", "place": "output", "params": {"dead_time": 0.01},
            "ci95": {}}]
    listed = {**single, "cause": "lag", "causes": two}
    assert causes_of(listed) == two
    row = fleet_report.flatten({"loop": "a", "status": "ok", "error": None,
                                "diagnosis": listed})
    assert row["causes"] == "lag+dead_time"
    assert row["lag"] == 0.02 and row["dead_time"] == 0.01


def test_to_dict_is_the_cli_json(dx, record, tmp_path):
    r = subprocess.run(fit_exe() + ["diagnose", str(record), "--config", "dd", "--json",
                                    "--jobs", "1", "--quiet"],
                       check=True, capture_output=True, text=True)
    cli = json.loads(r.stdout)
    ours = json.loads(json.dumps(dx.to_dict()))
    cli.pop("elapsed_s")
    ours.pop("elapsed_s")
    assert ours == cli          # the same diagnosis, seeded alike


def test_to_frame(dx, record):
    f = dx.to_frame()
    assert list(f.columns) == ["t", "measured", "baseline", "extended", "residual"]
    raw = pd.read_csv(record, comment="#")
    assert len(f) == len(raw)
    assert np.array_equal(f["t"], raw["t"])
    assert np.allclose(f["measured"], raw["pc"], rtol=0, atol=1e-12 * raw["pc"].abs().max())
    assert np.allclose(f["residual"], f["measured"] - f["extended"], rtol=0, atol=1e-15)
    # The extended model follows the record; the linear baseline cannot.
    held = dx.raw.split.held_slices()
    rms = lambda x: float(np.sqrt(np.mean(np.concatenate([x[s] for s in held]) ** 2)))  # noqa: E731
    assert rms(f["residual"]) < 0.5 * rms(f["measured"] - f["baseline"])


def test_data_forms(record, dx):
    raw = pd.read_csv(record, comment="#")
    renamed = raw.rename(columns={"t": "time", "e": "error", "pc": "output"})
    d2 = pneufrac.diagnose({k: renamed[k].to_numpy() for k in renamed}, "dd", jobs=1,
                           columns={"t": "time", "e": "error", "pc": "output"})
    assert d2.cause == dx.cause and d2.params == dx.params
    d3 = pneufrac.diagnose(raw, "dd", jobs=1)
    assert d3.params == dx.params


@pytest.mark.parametrize("kw,match", [
    ({"config": "xx"}, "config"),
    ({"config": "dd", "fixes": {"k1": 1.0}}, "fixes: k1"),
    ({"config": "dd", "fixes": {"tau": -1.0}}, "fixes: tau"),
    ({"config": "dd", "e0": 0.0}, "e0 and pc0"),
    ({"config": "dd", "holdout": "middle"}, "holdout: 'middle'"),
    ({"config": "dd", "holdout": None}, "holdout: None"),
])
def test_bad_options(record, kw, match):
    with pytest.raises(ValueError, match=match):
        pneufrac.diagnose(record, **kw)


def test_bad_data_is_a_value_error(tmp_path):
    with pytest.raises(ValueError, match="no column 'e'"):
        pneufrac.diagnose({"t": [0.0, 1.0]}, "dd")
    with pytest.raises(ValueError, match="too few"):
        pneufrac.diagnose({"t": np.arange(10.0), "e": np.ones(10), "pc": np.ones(10)}, "dd")
    with pytest.raises(ValueError, match="numeric"):
        pneufrac.diagnose({"t": ["a"] * 300, "e": np.ones(300), "pc": np.ones(300)}, "dd")
    with pytest.raises(ValueError, match="no such file"):
        pneufrac.diagnose(tmp_path / "missing.csv", "dd")


def test_write_report(dx, tmp_path):
    path = dx.write_report(tmp_path / "rep")
    assert path.name == "report.md" and path.exists()
    assert json.loads((tmp_path / "rep" / "diagnosis.json").read_text())["cause"] == "dead_time"


def test_diagnosis_figures_write_nothing(dx, tmp_path, monkeypatch):
    from matplotlib.figure import Figure
    monkeypatch.chdir(tmp_path)
    figs = dx.figures()
    assert sorted(figs) == ["after", "before", "candidates", "overview"]
    assert all(isinstance(f, Figure) and f.axes for f in figs.values())
    assert list(tmp_path.iterdir()) == []
    # The overview draws the measured record and both models on its top axes.
    labels = [ln.get_label() for ln in figs["overview"].axes[0].get_lines()]
    assert labels[:2] == ["measured", "baseline"] and labels[2].startswith("extended")


def test_plots_are_figures_and_write_nothing(tmp_path, monkeypatch):
    from matplotlib.figure import Figure
    monkeypatch.chdir(tmp_path)
    d = pneufrac.design("dd", 20000, effects={"lag": 0.01})
    fr = pneufrac.freqresp(d)
    figs = [pneufrac.plots.bode(fr), pneufrac.plots.bode(fr.to_frame(), "from a table"),
            pneufrac.plots.step(np.arange(100) / 20000, d.simulate(np.ones(100)))]
    assert all(isinstance(f, Figure) for f in figs)
    assert list(tmp_path.iterdir()) == []
    assert "matplotlib.pyplot" not in sys.modules or not __import__(
        "matplotlib.pyplot").pyplot.get_fignums()
    figs[0].savefig(tmp_path / "b.png")
    assert (tmp_path / "b.png").stat().st_size > 1000
    with pytest.raises(ValueError, match="ideal_db"):
        pneufrac.plots.bode(pd.DataFrame({"omega": [1.0]}))

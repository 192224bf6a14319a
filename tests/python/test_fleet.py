# SPDX-License-Identifier: MIT
"""pneufrac-fit fleet on a LocalCluster of two workers: generated records
with known effects, healthy ones and bad ones; the report's rows, order
and files; a running scheduler; bad arguments."""
import logging
import math
import os
import subprocess
import sys
from pathlib import Path

import numpy as np
import pandas as pd
import pytest

pytest.importorskip("dask.distributed")
from pneufrac_fit import fleet  # noqa: E402

from conftest import ROOT  # noqa: E402

# loop -> (generate arguments, the cause it must be given)
GOOD = {
    "tank_a": (["--effect", "deadtime:t=0.03", "--seed", "11"], "dead_time"),
    "tank_b": (["--effect", "deadtime:t=0.008", "--seed", "12"], "dead_time"),
    "valve_c": (["--seed", "13"], "none"),
}
BAD = {
    "empty": b"",
    "no_header": b"1,2,3\n4,5,6\n",
    "nan_pc": b"t,e,pc\n" + b"".join(b"%d,1,nan\n" % i for i in range(300)),
    # a Latin-1 byte in a cell (in a comment it is read: attack26)
    "latin1": "t,e,pc\n0,caf\xe9,1\n".encode("latin-1"),
    "utf16": "t,e,pc\n0,1,2\n".encode("utf-16"),     # Excel's "Unicode text"
}


def fit_exe():
    p = Path(sys.executable).with_name("pneufrac-fit")
    return [str(p)] if p.exists() else [sys.executable, "-m", "pneufrac_fit.cli"]


def fit(*args, **kw):
    return subprocess.run(fit_exe() + [str(a) for a in args], capture_output=True,
                          text=True, timeout=600, **kw)


@pytest.fixture(scope="module")
def records(tmp_path_factory):
    d = tmp_path_factory.mktemp("plant")
    for loop, (args, _) in GOOD.items():
        r = fit("generate", "--config", "dd", "--n", "3000", *args, "-o", d / f"{loop}.csv")
        assert r.returncode == 0, r.stderr
    for loop, data in BAD.items():
        (d / f"{loop}.csv").write_bytes(data)
    (d / "notes.txt").write_text("not a record\n")
    return d


@pytest.fixture(scope="module")
def report(records, tmp_path_factory):
    """docs/fleet.md's example, run as written (on two workers) from a
    folder that has the repository's .venv and the records in exports/."""
    doc = (ROOT / "docs" / "fleet.md").read_text()
    block = doc.split("<!-- fleet-example", 1)[1].split("```sh\n", 1)[1].split("```", 1)[0]
    assert "--workers 2" in block
    here = tmp_path_factory.mktemp("site")
    (here / ".venv").symlink_to(Path(sys.executable).parent.parent)
    (here / "exports").symlink_to(records)
    r = subprocess.run(["bash", "-euo", "pipefail", "-c", block], cwd=here,
                       capture_output=True, text=True, timeout=600)
    assert r.returncode == 0, r.stderr
    assert "tank_a" in r.stdout                      # the second line printed the table
    return here / "fleet-report", r


def test_every_record_has_its_row(report):
    out, r = report
    df = pd.read_csv(out / "fleet.csv", comment="#")
    assert sorted(df["loop"]) == sorted([*GOOD, *BAD])       # not notes.txt
    for loop, (_, cause) in GOOD.items():
        row = df[df["loop"] == loop].iloc[0]
        assert row["status"] == "ok" and row["causes"] == cause, row.to_dict()
    for loop in BAD:
        row = df[df["loop"] == loop].iloc[0]
        assert row["status"] == "error" and isinstance(row["error"], str) and row["error"]
    assert "byte 0xe9 is not UTF-8" in df[df["loop"] == "latin1"].iloc[0]["error"]
    err16 = df[df["loop"] == "utf16"].iloc[0]["error"]
    assert "UTF-16" in err16 and err16.count("utf16.csv") <= 1, err16
    assert f"{len(GOOD) + len(BAD)}/{len(GOOD) + len(BAD)}" in r.stderr


def test_rows_are_sorted_by_severity(report):
    out, _ = report
    df = pd.read_csv(out / "fleet.csv", comment="#")
    ok = df[df["status"] == "ok"]
    assert list(df["status"]) == ["ok"] * len(ok) + ["error"] * (len(df) - len(ok))
    assert list(ok["severity"]) == sorted(ok["severity"], reverse=True)
    # the larger dead time first; the healthy loop has none
    assert list(ok["loop"]) == ["tank_a", "tank_b", "valve_c"]
    assert ok.iloc[-1]["severity"] == 0.0
    a = ok.iloc[0]
    assert a["dead_time"] == pytest.approx(0.03, abs=0.0011)
    assert a["severity"] == pytest.approx(
        math.sqrt(a["nrmse_val_before"] ** 2 - a["nrmse_val_after"] ** 2))
    assert math.isnan(ok.iloc[-1]["dead_time"])


def test_report_files(report):
    out, _ = report
    csv = pd.read_csv(out / "fleet.csv", comment="#")
    pq = pd.read_parquet(out / "fleet.parquet")
    pd.testing.assert_frame_equal(csv, pq, check_dtype=False)
    units = (out / "fleet.csv").read_text().splitlines()[1]
    assert units.startswith("# units:") and "fraction of output sd" in units
    md = (out / "fleet.md").read_text()
    assert "| tank_a | dead_time |" in md and "could not be diagnosed" in md
    assert md.index("tank_a") < md.index("tank_b") < md.index("valve_c")
    assert (out / "fleet.png").stat().st_size > 5000
    assert sorted(p.stem for p in (out / "records").iterdir()) == sorted(GOOD)


def test_a_running_scheduler_and_a_glob(records, tmp_path):
    from dask.distributed import LocalCluster
    with LocalCluster(n_workers=2, threads_per_worker=1, host="127.0.0.1",
                      dashboard_address="127.0.0.1:0", silence_logs=logging.ERROR) as c:
        r = fit("fleet", records / "[tn]*.csv", "--config", "dd", "--scheduler",
                c.scheduler_address, "--out", tmp_path / "rep")
    assert r.returncode == 0, r.stderr
    df = pd.read_csv(tmp_path / "rep" / "fleet.csv", comment="#")
    assert sorted(df["loop"]) == ["nan_pc", "no_header", "tank_a", "tank_b"]
    assert c.scheduler_address in r.stderr


def test_the_local_cluster_listens_on_loopback_only():
    client, cluster = fleet._client(None, 2)
    try:
        pids = {os.getpid(), *client.run(os.getpid).values()}
        out = subprocess.run(["ss", "-ltnpH"], capture_output=True, text=True).stdout
    finally:
        client.close()
        cluster.close()
    mine = [ln for ln in out.splitlines() if any(f"pid={p}," in ln for p in pids)]
    assert len(mine) >= 3                         # scheduler and two workers
    assert all(ln.split()[3].startswith("127.0.0.1:") for ln in mine), mine


@pytest.mark.parametrize("args,match", [
    (["nowhere/*.csv"], "no file matches"),
    (["{records}", "--workers", "0"], "--workers 0"),
    (["{records}", "--workers", "2", "--scheduler", "tcp://127.0.0.1:9"], "--workers sizes"),
    (["{records}", "--scheduler", "nonsense://x"], "--scheduler nonsense://x"),
])
def test_bad_arguments(records, tmp_path, args, match):
    args = [a.format(records=records) for a in args]
    r = fit("fleet", *args, "--config", "dd", "--out", tmp_path / "o")
    assert r.returncode == 2 and match in r.stderr, r.stderr
    assert "Traceback" not in r.stderr


def test_names_stay_apart(tmp_path):
    (tmp_path / "a").mkdir()
    (tmp_path / "b").mkdir()
    files = [tmp_path / "a" / "x.csv", tmp_path / "b" / "x.csv", tmp_path / "a" / "y.csv"]
    assert fleet.loop_names(files) == ["a/x", "b/x", "a/y"]
    assert fleet.loop_names(files[1:]) == ["x", "y"]


def test_a_task_never_raises():
    flat = "t,e,pc\n" + "".join(f"{i / 1000},0,0\n" for i in range(300))
    row = fleet.diagnose_text("l", flat, "dd")
    assert row["status"] == "error" and "flat" in row["error"]
    row = fleet.diagnose_text("l", "t,e,pc\n", "nonsense")
    assert row["status"] == "error"
    assert np.isfinite(row["elapsed_s"])

# SPDX-License-Identifier: MIT
"""The fleet report: one row per loop, sorted by severity, as CSV, Parquet
and Markdown, with a summary figure and each loop's diagnosis as JSON.

Severity is the named effects' share of the loop's behaviour: the rms of
the output they account for on the held-out part, as a fraction of that
output's sd, sqrt(NRMSE_before^2 - NRMSE_after^2), where NRMSE_before is
the paper's linear model's held-out NRMSE and NRMSE_after the extended
model's. A 5 % severity means the effects move the output by 5 % of its
spread where the linear model cannot follow. It is 0 when no effect is
named, and undefined (the row sorts last) for a record that could not be
diagnosed.
"""
from __future__ import annotations

import json
import math
from pathlib import Path

import numpy as np

from pneufrac.diagnosis import causes_of

from . import model

# Units of the effect parameters, as model.EFFECT_PARAMS reports them.
EFFECT_UNITS = {"dead_time": "s", "lag": "s", "sat_lo": "output units",
                "sat_hi": "output units", "deadband": "input units",
                "nozzle_xh": "input units", "nozzle_bias": "x_1/2"}
COLUMNS = [("loop", ""), ("status", ""), ("severity", "fraction of output sd"),
           ("cause", ""), ("causes", ""),
           *[(p, EFFECT_UNITS.get(p, "")) for c in model.CAUSES
             for p in model.EFFECT_PARAMS[c]],
           ("nrmse_val_before", "fraction of output sd"),
           ("nrmse_val_after", "fraction of output sd"), ("delta_bic", ""),
           ("noise_floor_val", "fraction of output sd"), ("n", "samples"), ("fs", "Hz"),
           ("elapsed_s", "s"), ("cpu_s", "s"), ("error", "")]


def _num(v) -> float:
    return float(v) if v is not None and math.isfinite(float(v)) else math.nan


def severity(before: float, after: float, named: bool) -> float:
    if not named:
        return 0.0
    return math.sqrt(max(before * before - after * after, 0.0))


def flatten(row: dict) -> dict:
    """A task's row (fleet.diagnose_text) as one table row."""
    # Missing values are None or NaN, never "", so that the CSV (where an
    # empty field reads back as missing) and the Parquet file agree.
    out = {name: math.nan for name, _ in COLUMNS}
    out.update(loop=row["loop"], status=row["status"], error=row["error"] or None,
               cause=None, causes=None, elapsed_s=_num(row.get("elapsed_s")),
               cpu_s=_num(row.get("cpu_s")))
    j = row.get("diagnosis")
    if row["status"] != "ok" or j is None:
        return out
    causes = causes_of(j)
    g = j["gain"]
    out.update(cause=j["cause"], causes="+".join(c["name"] for c in causes) or "none",
               nrmse_val_before=_num(g["nrmse_val_before"]),
               nrmse_val_after=_num(g["nrmse_val_after"]), delta_bic=_num(g["delta_bic"]),
               noise_floor_val=_num(j["record"]["noise_floor_val"]),
               n=j["record"]["n"], fs=_num(j["record"]["fs"]))
    for c in causes:
        for k in model.EFFECT_PARAMS.get(c["name"], []):
            out[k] = _num(c["params"].get(k))
    out["severity"] = severity(out["nrmse_val_before"], out["nrmse_val_after"], bool(causes))
    return out


def table(rows: list[dict]):
    """pandas DataFrame, one row per loop: most severe first, then the
    healthy loops, then the records that could not be diagnosed."""
    import pandas as pd
    df = pd.DataFrame([flatten(r) for r in rows], columns=[c for c, _ in COLUMNS])
    df["n"] = df["n"].astype("Int64")
    key = np.where(df["status"] == "ok", -df["severity"].fillna(0.0), np.inf)
    order = np.lexsort((df["loop"].to_numpy(dtype=str), key))
    return df.iloc[order].reset_index(drop=True)


def _fmt(v, spec: str = ".4g") -> str:
    if isinstance(v, str):
        return v
    return "-" if v is None or (isinstance(v, float) and math.isnan(v)) else format(v, spec)


def markdown(df, config: str, figure: str, elapsed: float, workers: str) -> str:
    ok = df[df["status"] == "ok"]
    bad = df[df["status"] != "ok"]
    faulty = ok[ok["causes"] != "none"]
    L = [f"# pneufrac-fit fleet report: configuration `{config}`\n",
         f"{len(df)} records: {len(faulty)} with named effects, "
         f"{len(ok) - len(faulty)} healthy (no effect named), {len(bad)} could not be "
         f"diagnosed. {elapsed:.1f} s on {workers}.\n",
         "Severity: the rms of the output the named effects account for on the "
         "held-out part, as a fraction of that output's sd "
         "(sqrt(NRMSE_before² − NRMSE_after²)).\n",
         f"![summary]({figure})\n", "## Loops, most severe first\n"]
    params = [p for c in model.CAUSES for p in model.EFFECT_PARAMS[c]]
    shown = [p for p in params if ok[p].notna().any()]
    L.append("| loop | causes | severity | " + " | ".join(shown)
             + " | NRMSE before → after | ΔBIC |")
    L.append("|---|---|---|" + "---|" * len(shown) + "---|---|")
    for _, r in ok.iterrows():
        L.append(f"| {r['loop']} | {r['causes']} | {_fmt(r['severity'], '.3f')} | "
                 + " | ".join(_fmt(r[p]) for p in shown)
                 + f" | {_fmt(r['nrmse_val_before'])} → {_fmt(r['nrmse_val_after'])} | "
                 f"{_fmt(r['delta_bic'], '+.1f')} |")
    if len(bad):
        L += ["", "## Records that could not be diagnosed\n", "| loop | reason |", "|---|---|"]
        for _, r in bad.iterrows():
            L.append(f"| {r['loop']} | {r['error'].splitlines()[0].replace('|', '/')} |")
    return "\n".join(L) + "\n"


def write(rows: list[dict], out: Path, config: str, elapsed: float, workers: str) -> dict:
    """Write fleet.csv, fleet.parquet, fleet.md, fleet.png and
    records/LOOP.json into @out; returns the paths by kind."""
    from pneufrac import plots
    out = Path(out)
    (out / "records").mkdir(parents=True, exist_ok=True)
    df = table(rows)
    paths = {k: out / f"fleet.{k}" for k in ("csv", "parquet", "md", "png")}
    with open(paths["csv"], "w", encoding="utf-8", newline="") as f:
        f.write(",".join(c for c, _ in COLUMNS) + "\n")
        f.write("# units: " + ",".join(u for _, u in COLUMNS) + "\n")
        df.to_csv(f, index=False, header=False, float_format=None)
    df.to_parquet(paths["parquet"], index=False)
    plots.fleet_summary(df, f"fleet: configuration {config}").savefig(paths["png"], dpi=90)
    paths["md"].write_text(markdown(df, config, paths["png"].name, elapsed, workers),
                           encoding="utf-8")
    for r in rows:
        if r.get("diagnosis") is not None:
            name = r["loop"].replace("/", "__")
            (out / "records" / f"{name}.json").write_text(
                json.dumps(r["diagnosis"], indent=2, allow_nan=False) + "\n", encoding="utf-8")
    return paths

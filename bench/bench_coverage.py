#!/usr/bin/env python3
# SPDX-License-Identifier: MIT
"""Do the 95 % intervals hold? pneufrac-fit diagnose on records whose truth
is known, and how often each reported interval contains it. A benchmark: it
measures and prints, it never fails on the scores.

    .venv/bin/python bench/bench_coverage.py [--seeds 1-6] [--jobs 2]
        [--tool PATH] [--source gen|indep|both] [--indep-seeds 1-5]
        [--scenarios PATTERN[,PATTERN]] [--n 3000] [--plant fit|default]
        [--effects E,..] [--noise-kinds white,ar1,pink] [--keep DIR] [--timeout 900]

Two sources, reported apart:
  gen    the tool's own generator (`pneufrac-fit generate`) with the fit's
         discretisation (--plant fit: the fit's simulation rate and order;
         the clean outputs then differ by under 0.001 noise sd rms, against
         0.04-0.1 with the generator's own default, which at 3000 samples
         can bias a well-determined direction by several se): the model is
         exact (held groups at their true values), so what is measured is
         the statistics alone: the sandwich covariance under the noise
         model. One effect per record, well above the detection limit
         (docs/analysis-bench.md, "Detection limits"), noise white, AR(1)
         (the generator's pole, 0.95) and 1/f, several seeds per cell.
  indep  the independent simulator's one-effect scenarios
         (tests/python/indepsim, classes easy and realistic): model mismatch
         (another discretisation, effects placed physically) adds bias.

The true groups come from the library (pneufrac_fit.lib: set PNEUFRAC_LIBRARY
as for the tool).

For each named effect's parameter (and, on gen records whose named set is
the truth, each fitted group of the final model): whether the interval
contains the truth; z = (estimate - truth) / se on the scale the interval
is built on (fit.uncertainty: log for lag and the log groups, 1/x_1/2 for
the nozzle, linear otherwise; se = the half-width / 1.96, the wider side
when the report cut one side at a group's bound); the width (hi / lo on a
log scale, (hi - lo) / truth otherwise). Coverage is conditional on the
effect being named: the rows say how many records named it. Dead time has
no interval (a whole number of samples, tested by the likelihood ratio).
"""
from __future__ import annotations

import argparse
import concurrent.futures as cf
import inspect
import json
import math
import os
import shutil
import signal
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "tools" / "python"))
sys.path.insert(0, str(ROOT / "bench"))

import numpy as np  # noqa: E402

from bench_diagnose_indep import (Procs, _interrupt, _last_line, _num,  # noqa: E402
                                  pick_scenarios)
from indepsim.scenarios import CATALOGUE  # noqa: E402
from pneufrac_fit import fit, model  # noqa: E402
from pneufrac_fit.diagnose import diagnose as diagnose_api  # noqa: E402
from seedlist import seed_list  # noqa: E402


Z95 = 1.96                         # fit.uncertainty builds its intervals as +- 1.96 se
FS = 1000.0                        # the generator's default rate
NOISE = 0.005                      # sd over the output span, as the limits table
NOISE_KINDS = ["white", "ar1", "pink"]
# One effect per record, sized well above the detection limits measured at
# this noise (dead time 1.5-3 ms, lag 4 ms, dead band 0.018 in white noise):
# effect -> (config, --effect argument; saturation's limits are set per
# record from the output's range).
GEN_EFFECTS = {
    "lag": ("p", "lag:tau=0.01"),
    "dead_time": ("dd", "deadtime:t=0.006"),
    "backlash": ("dd", "backlash:width=0.08"),
    "nozzle": ("dd", "nozzle:xh=2"),
    "saturation": ("dd", None),
}
SAT_INSET = 0.15                   # limits this fraction of the span inside it
# the parameters whose intervals are scored, per effect (report names)
PARAMS = {"lag": ["lag"], "backlash": ["deadband"], "nozzle": ["nozzle_xh"],
          "saturation": ["sat_lo", "sat_hi"], "dead_time": []}


def scale_of(name: str):
    """The map to the coordinate the interval is symmetric in
    (fit.uncertainty): log for log-transformed parameters, 1/x_1/2 for the
    nozzle (fitted as the curvature nozzle_k), identity otherwise."""
    if name == "nozzle_xh":
        return lambda v: 1.0 / v
    if fit.transform_of(name) == "log":
        return math.log
    return lambda v: v


def score(name: str, est, ci, truth) -> dict | None:
    """Containment, z and width of one interval; None when it cannot be had."""
    est, truth = _num(est), _num(truth)
    if est is None or truth is None or not ci:
        return None
    lo, hi = _num(ci[0]), _num(ci[1])
    inside = (lo is None or lo <= truth) and (hi is None or truth <= hi)
    f = scale_of(name)
    try:
        ends = [f(x) for x in (lo, hi) if x is not None and (x > 0 or f(1.0) == 1.0)]
        fe, ft = f(est), f(truth)
    except (ValueError, ZeroDivisionError):
        return None
    half = max((abs(x - fe) for x in ends), default=None)
    if not half:
        return {"in": inside, "z": None, "width": math.inf}
    if lo is None or hi is None:
        width = math.inf                 # a side the sandwich could not bound
    elif f is math.log:
        width = hi / lo if lo > 0 else math.inf
    else:
        width = (hi - lo) / abs(truth) if truth else math.inf
    return {"in": inside, "z": (fe - ft) / (half / Z95), "width": width}


def cause_entry(js: dict, effect: str) -> dict | None:
    for c in js.get("causes") or []:
        if isinstance(c, dict) and c.get("name") == effect:
            return c
    return None


def named_of(js: dict) -> list[str]:
    return [c.get("name") for c in js.get("causes") or [] if isinstance(c, dict)]


def scores_of(js: dict, effect: str, truth_params: dict, groups: dict | None) -> list[dict]:
    """One score per scored parameter of the true effect (when named) and,
    given the true groups and a named set that is the truth, per fitted
    group of the final model."""
    out = []
    c = cause_entry(js, effect)
    if c is not None:
        for p in PARAMS[effect]:
            s = score(p, (c.get("params") or {}).get(p), (c.get("ci95") or {}).get(p),
                      truth_params.get(p))
            if s is not None:
                out.append(dict(s, param=p, kind="effect"))
    if groups and named_of(js) == [effect]:
        ext = js.get("extended") or {}
        held = js.get("held") or {}
        marked = ext.get("ci95_not_reliable") or {}
        for g, ci in (ext.get("ci95") or {}).items():
            if g in groups and g in model.GROUPS:
                s = score(g, (ext.get("params") or {}).get(g), ci, groups[g])
                if s is not None:
                    # a group the baseline held (not identified) and the
                    # extended fits freed again: its own class; marked: the
                    # report says its interval is not reliable
                    out.append(dict(s, param=g, kind="held group" if g in held else "group",
                                    marked=g in marked))
    return out


def diagnose(tool, csv, config, timeout, procs) -> tuple[dict | None, str]:
    # one worker per diagnosis (--jobs 1): --jobs of this bench is the
    # number of processes it runs at once
    rc, out, err = procs.run([tool, "diagnose", str(csv), "--config", config, "--json",
                              "--quiet", "--jobs", "1"], timeout)
    if rc != 0:
        return None, "timeout" if rc is None else f"exit {rc}: {_last_line(err)}"
    try:
        return json.loads(out), "ok"
    except json.JSONDecodeError:
        return None, "unreadable JSON"


def plant_args(plant: str) -> list[str]:
    """The generator's discretisation: its own default (4x the data rate, the
    library's default order), or the fit's (diagnose's default order, at
    model.auto_oversample's rate), so that nothing but the noise separates
    the record from the fitted model."""
    if plant == "default":
        return []
    order = inspect.signature(diagnose_api).parameters["order"].default
    return ["--oversample", str(model.auto_oversample(FS)), "--order", str(order)]


def gen_one(effect, kind, seed, a, keep, procs) -> dict:
    config, arg = GEN_EFFECTS[effect]
    row = {"source": "gen", "effect": effect, "cell": f"{effect} ({config}, {kind})", "noise": kind,
           "seed": seed, "named": None, "scores": []}
    stem = Path(keep) / f"gen-{effect}-{kind}-{seed}"
    base = [a.tool, "generate", "--config", config, "--n", str(a.n), "--noise", str(NOISE),
            "--noise-kind", kind, "--seed", str(seed)] + plant_args(a.plant)
    truth = {}
    if effect == "saturation":
        # limits inside the range the same record reaches without them
        rc, _, err = procs.run(base + ["-o", f"{stem}.none.csv"], a.timeout)
        if rc != 0:
            row["status"] = f"generate: {_last_line(err)}"
            return row
        with open(f"{stem}.none.csv") as fh:      # '#' comments, then a header
            y = np.loadtxt([ln for ln in fh if ln[:1] not in ("#", "t")], delimiter=",",
                           usecols=2)
        lo, hi = float(np.min(y)), float(np.max(y))
        truth = {"sat_lo": lo + SAT_INSET * (hi - lo), "sat_hi": hi - SAT_INSET * (hi - lo)}
        arg = f"saturation:lo={truth['sat_lo']:.9g},hi={truth['sat_hi']:.9g}"
    else:
        _, v = arg.split(":")[1].split("=")
        truth = {PARAMS[effect][0] if PARAMS[effect] else effect: float(v)}
    rc, _, err = procs.run(base + ["--effect", arg, "-o", f"{stem}.csv"], a.timeout)
    if rc != 0:
        row["status"] = f"generate: {_last_line(err)}"
        return row
    js, row["status"] = diagnose(a.tool, f"{stem}.csv", config, a.timeout, procs)
    if js is not None:
        row["named"] = named_of(js)
        row["scores"] = scores_of(js, effect, truth, model.nominal_groups(config))
    return row


def indep_one(name, seed, a, keep, procs) -> dict:
    row = {"source": "indep", "effect": None, "cell": name, "seed": seed, "named": None,
           "scores": []}
    env = dict(os.environ, PYTHONPATH=str(ROOT / "tests" / "python"))
    rc, _, err = procs.run([sys.executable, "-m", "indepsim", "make", name, "--seed", str(seed),
                            "--out", keep], a.timeout, env)
    if rc != 0:
        row["status"] = f"simulator: {_last_line(err)}"
        return row
    stem = Path(keep) / f"{name}-{seed}"
    truth = json.loads(stem.with_suffix(".truth.json").read_text())
    (eff,) = truth["effects"]
    row["effect"] = eff["cause"]
    row["noise"] = str((truth.get("noise") or {}).get("model", "-"))
    js, row["status"] = diagnose(a.tool, f"{stem}.csv", truth["config"], a.timeout, procs)
    if js is not None:
        row["named"] = named_of(js)
        row["scores"] = scores_of(js, eff["cause"], eff["params"], None)
    return row


def _guarded(f, *args) -> dict:
    """f's row; an error in one record is that record's status, not the
    sweep's end (the pool would otherwise wait for every record first)."""
    try:
        return f(*args)
    except Exception as exc:  # noqa: BLE001
        return {"source": "gen" if f is gen_one else "indep", "effect": args[0],
                "cell": " ".join(map(str, args[:-4])), "seed": args[-4], "named": None,
                "scores": [], "status": f"bench error: {exc!r}"[:160]}


def _med(xs, fmt="{:.2f}") -> str:
    xs = [x for x in xs if x is not None and math.isfinite(x)]
    return fmt.format(float(np.median(xs))) if xs else "-"


def pooled(rows: list[dict]) -> dict:
    """Scores pooled by the parameter's kind (the effect's own, a group the
    baseline identified, a group it held and the extended fits freed) and
    the noise (all noises too)."""
    out: dict[tuple, list] = {}
    for r in rows:
        for s in r["scores"]:
            for noise in (r.get("noise", "-"), "all"):
                out.setdefault((s["kind"], noise), []).append(s)
    order = ["effect", "group", "held group"]
    return dict(sorted(out.items(), key=lambda kv: (order.index(kv[0][0]), kv[0][1] == "all")))


def pooled_marked(rows: list[dict]) -> dict:
    """The groups' scores pooled by whether the report calls the interval a
    95 % one or marks it not reliable, and the noise (all noises too)."""
    out: dict[tuple, list] = {}
    for r in rows:
        for s in r["scores"]:
            if "marked" not in s:
                continue
            what = "marked not reliable" if s["marked"] else "reported 95 %"
            for noise in (r.get("noise", "-"), "all"):
                out.setdefault((what, noise), []).append(s)
    return dict(sorted(out.items(), key=lambda kv: (kv[0][0] != "reported 95 %", kv[0][1] == "all")))


def _pooled_rows(groups: dict) -> list[str]:
    """One table row per (what, noise) pool: intervals, how many contain the
    truth, median abs(z), how many abs(z) beyond the 95 % point."""
    rows = []
    for (what, noise), ss in groups.items():
        zs = [abs(s["z"]) for s in ss if s["z"] is not None]
        k = sum(s["in"] for s in ss)
        rows.append(f"| {what} | {noise} | {len(ss)} | {k} ({k / len(ss):.0%}) | {_med(zs)} | "
                    f"{sum(z > Z95 for z in zs)} of {len(zs)} |")
    return rows


def table(rows: list[dict], source: str) -> list[str]:
    """One line per (cell, parameter): records, named, coverage, median |z|,
    median width."""
    rs = [r for r in rows if r["source"] == source]
    cells: dict[str, list[dict]] = {}
    for r in rs:
        cells.setdefault(r["cell"], []).append(r)
    L = ["| cell | parameter | records | named | in 95 % interval | coverage | unbounded "
         "| median abs(z) | median z | median width |", "|---|---|---|---|---|---|---|---|---|---|"]
    for cell, cr in cells.items():
        done = [r for r in cr if r["named"] is not None]
        nam = sum(r["effect"] in r["named"] for r in done)
        params = []
        for r in cr:
            for s in r["scores"]:
                if s["param"] not in params:
                    params.append(s["param"])
        if not params:
            L.append(f"| {cell} | - | {len(done)} | {nam} | - | - | - | - | - | - |")
        for p in params:
            ss = [s for r in cr for s in r["scores"] if s["param"] == p]
            k = sum(s["in"] for s in ss)
            zs = [s["z"] for s in ss if s["z"] is not None]
            L.append(f"| {cell} | {p} | {len(done)} | {nam} | {k} / {len(ss)} | "
                     f"{k / len(ss):.0%} | {sum(not math.isfinite(s['width']) for s in ss)} | "
                     f"{_med([abs(z) for z in zs])} | "
                     f"{_med(zs, '{:+.2f}')} | {_med([s['width'] for s in ss], '{:.3g}')} |")
    L += ["", "| parameters | noise | intervals | contain the truth | median abs(z) | "
          "abs(z) > 1.96 |", "|---|---|---|---|---|---|"]
    L += _pooled_rows(pooled(rs))
    L += ["", "Groups' intervals by what the report says of them (ci95_not_reliable: at a "
          "bound, or held by the baseline and freed):", "",
          "| groups' intervals | noise | intervals | contain the truth | median abs(z) | "
          "abs(z) > 1.96 |", "|---|---|---|---|---|---|"]
    L += _pooled_rows(pooled_marked(rs))
    bad = [f"{r['cell']}-{r['seed']} ({r['status']})" for r in rs if r["named"] is None]
    if bad:
        L.append(f"- not diagnosed: {', '.join(bad)}")
    return L


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--seeds", default="1-6", help="generator seeds (default 1-6)")
    ap.add_argument("--indep-seeds", default="1-5", help="indepsim seeds (default 1-5)")
    ap.add_argument("--source", choices=["gen", "indep", "both"], default="both")
    ap.add_argument("--scenarios", default="*-steps,*-real,nozzle-offbias,dead_time-10khz,"
                    "lag-jitter,saturation-wind,lag-sweep",
                    help="indepsim scenarios (one-effect ones are kept)")
    ap.add_argument("--effects", default=",".join(GEN_EFFECTS))
    ap.add_argument("--noise-kinds", default=",".join(NOISE_KINDS))
    ap.add_argument("--plant", choices=["default", "fit"], default="fit",
                    help="the generator's discretisation: its default, or the fit's")
    ap.add_argument("--n", type=int, default=3000, help="generator record length")
    ap.add_argument("--jobs", type=int, default=2, help="records diagnosed at once")
    ap.add_argument("--timeout", type=float, default=900.0, help="per record, s")
    ap.add_argument("--tool", default=None, help="pneufrac-fit executable")
    ap.add_argument("--keep", default=None, help="write the records here (else a temp dir)")
    a = ap.parse_args()
    try:
        seeds, iseeds = seed_list(a.seeds, 10 ** 6), seed_list(a.indep_seeds, 10 ** 6)
        names = [n for n in pick_scenarios(a.scenarios) if len(CATALOGUE[n].effects) == 1]
        effects = [e for e in a.effects.split(",") if e]
        kinds = [k for k in a.noise_kinds.split(",") if k]
        assert set(effects) <= set(GEN_EFFECTS) and set(kinds) <= {"white", "ar1", "ar2", "pink"}
    except (ValueError, AssertionError):
        print("bench_coverage: bad --seeds, --scenarios, --effects or --noise-kinds",
              file=sys.stderr)
        return 2
    if not 1 <= a.jobs <= 2 * (os.cpu_count() or 1) or not 100 <= a.n <= 100000:
        print("bench_coverage: --jobs in 1..2x cores, --n in 100..100000", file=sys.stderr)
        return 2
    a.tool = a.tool or shutil.which("pneufrac-fit") or str(ROOT / ".venv" / "bin" / "pneufrac-fit")
    if not os.access(a.tool, os.X_OK):
        print(f"bench_coverage: no pneufrac-fit at {a.tool}", file=sys.stderr)
        return 2
    keep = a.keep or tempfile.mkdtemp(prefix="coverage-")
    os.makedirs(keep, exist_ok=True)
    procs = Procs()
    jobs = []
    if a.source in ("gen", "both"):
        jobs += [(gen_one, (e, k, s)) for e in effects for k in kinds for s in seeds]
    if a.source in ("indep", "both"):
        jobs += [(indep_one, (n, s)) for n in names for s in iseeds]
    t0 = time.monotonic()
    rows = []
    # Records are made and diagnosed in subprocesses; threads only wait on
    # them. An interrupt (Ctrl-C, SIGTERM) cancels what has not started and
    # kills what runs (the pool's own exit would wait for every record).
    signal.signal(signal.SIGTERM, _interrupt)
    ex = cf.ThreadPoolExecutor(max_workers=a.jobs)
    try:
        futs = [ex.submit(_guarded, f, *args, a, keep, procs) for f, args in jobs]
        for fu in futs:
            r = fu.result()
            rows.append(r)
            sc = "; ".join(f"{s['param']} {'in' if s['in'] else 'OUT'} z "
                           + ("-" if s["z"] is None else f"{s['z']:+.2f}")
                           + (" (marked)" if s.get("marked") else "")
                           for s in r["scores"])
            print(f"[coverage] {r['cell']}-{r['seed']}: named "
                  f"{'n/a' if r['named'] is None else (', '.join(r['named']) or 'none')} "
                  f"({r['status']}); {sc}", file=sys.stderr)
    except KeyboardInterrupt:
        ex.shutdown(wait=False, cancel_futures=True)
        procs.kill_all()
        print("bench_coverage: interrupted", file=sys.stderr)
        return 130
    finally:
        if not a.keep:
            shutil.rmtree(keep, ignore_errors=True)
    ex.shutdown()
    for src, title in (("gen", "The tool's own generator (the model exact)"),
                       ("indep", "The independent simulator, one effect (model mismatch)")):
        if any(r["source"] == src for r in rows):
            print(f"### {title}\n")
            print("\n".join(table(rows, src)))
            print()
    print(f"(wall time {time.monotonic() - t0:.0f} s, {a.jobs} records at once)")
    return 0


if __name__ == "__main__":
    sys.exit(main())

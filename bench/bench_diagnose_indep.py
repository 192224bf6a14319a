#!/usr/bin/env python3
# SPDX-License-Identifier: MIT
"""Scoreboard: pneufrac-fit diagnose on records from the independent
simulator (tests/python/indepsim), against their truth. A benchmark: it
measures and prints, it never fails on the scores or on time.

    .venv/bin/python bench/bench_diagnose_indep.py [--scenarios PATTERN[,PATTERN]]
        [--seeds 1|1-3|1,4] [--jobs 2] [--tool-jobs 1] [--timeout 900]
        [--tool PATH] [--keep DIR] [--holdout tail|blocks|cover]

Default: every scenario, seed 1, two records at a time (about 20 minutes on
the shared 2-core machine).

Prints a markdown table (one row per record) and summary lines. Right
means the set of named causes equals the set of true causes; partial, some
of them and nothing else; missed, none; wrong, a cause that is not in the
record (on a clean record: a false effect). Parameter
errors are relative to the true value; saturation limits relative to the
record's output range. "halfway" is the issue's criterion: the validation
NRMSE after is at most halfway from before to the true noise floor (over
the samples the tool held out, `--holdout` passed to it when given). The
effect size next to the true causes is the rms change the effects make to
the sampled output over the noise sd (an upper bound on what a fit can
attribute to them); with several effects, each one's on top of the others
in the fit part and in the held-out part of the split the tool used
(bench/indep_contributions.py:
an effect absent from the held-out part cannot pass the held-out guard).
"""
from __future__ import annotations

import argparse
import concurrent.futures as cf
import fnmatch
import json
import math
import os
import shutil
import signal
import subprocess
import sys
import tempfile
import threading
import time
from pathlib import Path

for v in ("OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ.setdefault(v, "1")
ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "tests" / "python"))

import numpy as np  # noqa: E402

from indepsim.make import load_noise, true_floor_held  # noqa: E402
from pneufrac_fit import holdout  # noqa: E402
from indepsim.scenarios import CATALOGUE, SEED_MAX  # noqa: E402
from seedlist import seed_list  # noqa: E402

PARAM_OF = {"dead_time": "dead_time", "lag": "lag", "backlash": "deadband",
            "nozzle": "nozzle_xh"}


def pick_scenarios(text: str | None) -> list[str]:
    if not text:
        return list(CATALOGUE)
    pats = [p.strip() for p in text.split(",") if p.strip()]
    out = [n for n in CATALOGUE if any(fnmatch.fnmatchcase(n, p) for p in pats)]
    if not out:
        raise ValueError(text)
    return out


def named_causes(js: dict) -> list[tuple[str, dict]]:
    """(cause, params) named by the tool, most important first: the
    `causes` list when there is one, else `cause` and `effect_params`."""
    out = []
    causes = js.get("causes")
    if isinstance(causes, list):
        for c in causes:
            if isinstance(c, str):
                name, params = c, {}
            elif isinstance(c, dict):
                name = c.get("cause") or c.get("name") or "?"
                params = c.get("effect_params") or c.get("params") or {}
            else:
                continue
            if name != "none":
                out.append((str(name), params if isinstance(params, dict) else {}))
        return out
    cause = js.get("cause", "none")
    if cause and cause != "none":
        out.append((str(cause), js.get("effect_params") or {}))
    return out


def _num(x) -> float | None:
    return float(x) if isinstance(x, (int, float)) and math.isfinite(x) else None


def param_errors(truth: dict, named: list[tuple[str, dict]], pc_range: float) -> list[str]:
    got = dict(named)
    out = []
    for eff in truth["effects"]:
        c, tp = eff["cause"], eff["params"]
        if c not in got:
            continue
        gp = got[c]
        if c == "saturation":
            for side in ("sat_lo", "sat_hi"):
                tv, gv = _num(tp.get(side)), _num(gp.get(side))
                if tv is None:
                    continue
                out.append(f"{side} {'?' if gv is None else f'{gv:.4g}'} vs {tv:.4g} "
                           f"({'-' if gv is None else f'{abs(gv - tv) / pc_range:.1%} of range'})")
            continue
        key = PARAM_OF[c]
        tv, gv = _num(tp.get(key)), _num(gp.get(key))
        note = "" if c != "nozzle" or tp.get("at_inflection") else f" (u0 {tp['nozzle_u0']:.2f})"
        if gv is None:
            out.append(f"{key} ? vs {tv:.4g}{note}")
        else:
            out.append(f"{key} {gv:.4g} vs {tv:.4g} ({(gv - tv) / tv:+.0%}){note}")
    return out


class Procs:
    """The subprocesses alive now, so that an interrupted sweep stops them."""

    def __init__(self) -> None:
        self.live: set[subprocess.Popen] = set()
        self.lock = threading.Lock()
        self.stopped = False

    def run(self, cmd: list[str], timeout: float, env=None) -> tuple[int | None, str, str]:
        """(status or None on timeout, stdout, stderr)."""
        with self.lock:
            if self.stopped:
                return None, "", "stopped"
            p = subprocess.Popen(cmd, stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                                 text=True, env=env)
            self.live.add(p)
        try:
            out, err = p.communicate(timeout=timeout)
            return p.returncode, out, err
        except subprocess.TimeoutExpired:
            p.kill()
            p.communicate()
            return None, "", ""
        finally:
            with self.lock:
                self.live.discard(p)

    def kill_all(self) -> None:
        with self.lock:
            self.stopped = True
            for p in self.live:
                p.kill()


def _last_line(err: str) -> str:
    return (err.strip().splitlines() or ["(no message)"])[-1][:160].replace("|", "/")


def one(name: str, seed: int, tool: str, tool_args: list[str], timeout: float, keep: str,
        procs: Procs) -> dict:
    row = {"scenario": name, "seed": seed, "class": CATALOGUE[name].get("cls"), "config": "?",
           "expected": CATALOGUE[name].get("expected"), "truth": [], "named": None,
           "status": "ok", "params": [], "nrmse": None, "floor": None, "noise": None,
           "halfway": None, "time": None, "size": None}
    env = dict(os.environ, PYTHONPATH=str(ROOT / "tests" / "python"))
    rc, _, err = procs.run([sys.executable, "-m", "indepsim", "make", name, "--seed", str(seed),
                            "--out", keep], timeout, env)
    if rc != 0:
        row["status"] = "simulator " + ("timeout" if rc is None else f"error: {_last_line(err)}")
        return row
    stem = Path(keep) / f"{name}-{seed}"
    truth = json.loads(stem.with_suffix(".truth.json").read_text())
    pc = np.loadtxt(f"{stem}.csv", delimiter=",", skiprows=1, usecols=2)
    row.update(config=truth["config"], truth=truth["causes"],
               size=truth["noise"]["effect_rms_over_sd"])
    cmd = [tool, "diagnose", f"{stem}.csv", "--config", truth["config"], "--json", "--quiet",
           *tool_args]
    t0 = time.monotonic()
    rc, out, err = procs.run(cmd, timeout)
    row["time"] = time.monotonic() - t0
    if rc is None:
        row["status"] = f"timeout after {timeout:.0f} s"
        return row
    if rc != 0:
        row["status"] = f"exit {rc}: {_last_line(err)}"
        return row
    try:
        js = json.loads(out)
    except json.JSONDecodeError:
        row["status"] = "unreadable JSON"
        return row
    named = named_causes(js)
    row["named"] = [c for c, _ in named]
    row["params"] = param_errors(truth, named, float(np.ptp(pc)) or 1.0)
    gain, recd = js.get("gain") or {}, js.get("record") or {}
    before, after = _num(gain.get("nrmse_val_before")), _num(gain.get("nrmse_val_after"))
    floor_true = true_floor(stem, pc, truth, recd)
    row["nrmse"] = (before, after)
    row["floor"] = (_num(recd.get("noise_floor_val")), floor_true)
    row["noise"] = (_num(recd.get("noise_sd")), truth["noise"]["realised_sd"])
    if before is not None and after is not None and truth["causes"]:
        row["halfway"] = after <= 0.5 * (before + floor_true)
    if len(truth["causes"]) >= 2:
        # on the split the tool validated on (it may be the held-out blocks)
        row["parts"] = parts_of(name, seed, recd.get("held_out"), timeout, env, procs)
    return row


def true_floor(stem: Path, pc: np.ndarray, truth: dict, recd: dict) -> float:
    """The true noise floor over the samples the tool held out (its JSON
    record.held_out)."""
    return true_floor_held(pc, load_noise(f"{stem}.noise.csv"), recd.get("held_out"), recd.get("n"),
                      truth["noise"]["noise_floor_val"])


def parts_of(name: str, seed: int, held, timeout: float, env: dict, procs: Procs) -> dict:
    """Each true effect's rms change to the sampled output on top of the
    others, over the noise sd, in the fit and the held-out parts of the
    tool's split (held: its JSON record.held_out; None: the tail)
    (bench/indep_contributions.py); {} when it cannot be had."""
    cmd = [sys.executable, str(ROOT / "bench" / "indep_contributions.py"), name, str(seed)]
    rc, out, _ = procs.run(cmd + ([json.dumps(held)] if held else []), timeout, env)
    try:
        return json.loads(out) if rc == 0 else {}
    except json.JSONDecodeError:
        return {}


def truth_cell(r: dict) -> str:
    """The true causes, the effects' rms over the noise sd, and for several
    effects each one's on top of the others as fit part / held-out part."""
    if not r["truth"]:
        return "none"
    parts = r.get("parts") or {}
    names = [c + (f" ({_f(parts[c]['fit'], '{:.2g}')}/{_f(parts[c]['val'], '{:.2g}')})"
                  if c in parts else "") for c in r["truth"]]
    return ", ".join(names) + ("" if r["size"] is None else f" ({r['size']:.2g})")


def _f(x, fmt="{:.3g}") -> str:
    return "-" if x is None else fmt.format(x)


def verdict(row: dict) -> str:
    if row["named"] is None:
        return "n/a"
    named, truth = set(row["named"]), set(row["truth"])
    if named == truth:
        return "right"
    if named - truth:
        return "wrong"      # a cause that is not in the record
    return "partial" if named else "missed"


def table(rows: list[dict]) -> list[str]:
    L = ["| scenario | seed | cfg | truth (effect rms / noise sd; with two, each on top of "
         "the other, fit / held-out part) | named | | "
         "parameters: tool vs truth | "
         "val NRMSE before -> after | floor tool / true | noise sd tool / true | time |",
         "|---|---|---|---|---|---|---|---|---|---|---|"]
    for r in rows:
        named = r["status"] if r["named"] is None else (", ".join(r["named"]) or "none")
        nr = "-" if not r["nrmse"] else f"{_f(r['nrmse'][0])} -> {_f(r['nrmse'][1])}" + (
            "" if r["halfway"] is None else (" (halfway)" if r["halfway"] else " (not halfway)"))
        fl = "-" if not r["floor"] else f"{_f(r['floor'][0])} / {_f(r['floor'][1])}"
        ns = "-" if not r["noise"] else f"{_f(r['noise'][0])} / {_f(r['noise'][1])}"
        L.append(f"| {r['scenario']} | {r['seed']} | {r['config']} | "
                 f"{truth_cell(r)} | {named} | {verdict(r)} | "
                 f"{'; '.join(r['params']) or '-'} | {nr} | {fl} | {ns} | "
                 f"{_f(r['time'], '{:.0f} s')} |")
    return L


def partial_missed(rows: list[dict]) -> str:
    """For records with several true causes: how many name only some of
    them, none, or a cause that is not there."""
    several = [r for r in rows if len(r["truth"]) >= 2 and r["named"] is not None]
    if not several:
        return ""
    n = {v: sum(verdict(r) == v for r in several) for v in ("partial", "missed", "wrong")}
    return f" ({n['partial']} partial, {n['missed']} missed, {n['wrong']} with a wrong cause)"


def summary(rows: list[dict]) -> list[str]:
    L = []
    classes = []
    for r in rows:
        if r["class"] not in classes:
            classes.append(r["class"])
    for c in classes:
        rs = [r for r in rows if r["class"] == c]
        right = sum(verdict(r) == "right" for r in rs)
        na = sum(verdict(r) == "n/a" for r in rs)
        lim = " (sized at the detection limit: none is defensible)" if c == "marginal" else ""
        L.append(f"- {c}: {right} / {len(rs)} right" + (f", {na} not diagnosed" if na else "")
                 + lim + partial_missed(rs))
    clean = [r for r in rows if not r["truth"] and r["named"] is not None]
    false = [r for r in clean if r["named"]]
    L.append(f"- false effects on clean records: {len(false)} of {len(clean)} diagnosed"
             + (": " + ", ".join(f"{r['scenario']}-{r['seed']} ({', '.join(r['named'])})"
                                 for r in false) if false else ""))
    eff = [r for r in rows if r["truth"] and r["named"] is not None]
    wrong = [r for r in eff if verdict(r) == "wrong"]
    L.append(f"- wrong causes (a cause named that is not there): {len(wrong)} of {len(eff)} "
             "records with effects" + (": " + ", ".join(
                 f"{r['scenario']}-{r['seed']} ({', '.join(r['named'])})" for r in wrong)
                 if wrong else ""))
    fair = [r for r in rows if r["expected"] == "fair"]
    L.append(f"- all fair records: {sum(verdict(r) == 'right' for r in fair)} / {len(fair)} right")
    hw = [r for r in rows if r["halfway"] is not None]
    if hw:
        L.append(f"- records with an effect whose validation NRMSE got halfway to the true "
                 f"floor: {sum(r['halfway'] for r in hw)} / {len(hw)}")
    ratios = [r["noise"][0] / r["noise"][1] for r in rows
              if r["noise"] and r["noise"][0] and r["noise"][1]]
    if ratios:
        L.append(f"- tool noise sd / true noise sd: median {np.median(ratios):.2f}, "
                 f"range {min(ratios):.2f}-{max(ratios):.2f}")
    times = [r["time"] for r in rows if r["time"] is not None]
    if times:
        L.append(f"- tool wall time: total {sum(times):.0f} s, median {np.median(times):.0f} s, "
                 f"max {max(times):.0f} s")
    return L


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--scenarios", help="comma-separated names or glob patterns (default: all)")
    ap.add_argument("--seeds", default="1", help="e.g. 1, 1-3, 1,4 (default 1)")
    ap.add_argument("--jobs", type=int, default=2, help="records diagnosed at once")
    ap.add_argument("--tool-jobs", type=int, default=1, help="pneufrac-fit --jobs")
    ap.add_argument("--timeout", type=float, default=900.0, help="per record, s")
    ap.add_argument("--tool", default=None, help="pneufrac-fit executable")
    ap.add_argument("--keep", default=None, help="write the records here (else a temp dir)")
    ap.add_argument("--holdout", choices=list(holdout.MODES), default=None,
                    help="pneufrac-fit --holdout (default: the tool's own default)")
    a = ap.parse_args()
    try:
        names = pick_scenarios(a.scenarios)
    except ValueError:
        print(f"bench_diagnose_indep: no scenario matches '{a.scenarios}'", file=sys.stderr)
        return 2
    try:
        seeds = seed_list(a.seeds, SEED_MAX)
    except ValueError:
        print(f"bench_diagnose_indep: --seeds '{a.seeds}': use N, N-M or N,M with seeds in "
              f"[0, {SEED_MAX}] (at most 10001 per range)", file=sys.stderr)
        return 2
    if not 1 <= a.jobs <= 64 or not 1 <= a.tool_jobs <= 64 or not a.timeout > 0:
        print("bench_diagnose_indep: --jobs, --tool-jobs in 1..64, --timeout > 0",
              file=sys.stderr)
        return 2
    tool = a.tool or shutil.which("pneufrac-fit") or str(ROOT / ".venv" / "bin" / "pneufrac-fit")
    if not os.access(tool, os.X_OK):
        print(f"bench_diagnose_indep: no pneufrac-fit at {tool} (run scripts/setup.sh)",
              file=sys.stderr)
        return 2
    keep = a.keep or tempfile.mkdtemp(prefix="indep-")
    try:
        return sweep(a, names, seeds, tool, keep)
    finally:
        if not a.keep:
            shutil.rmtree(keep, ignore_errors=True)


def _interrupt(*_) -> None:
    raise KeyboardInterrupt


def sweep(a, names: list[str], seeds: list[int], tool: str, keep: str) -> int:
    os.makedirs(keep, exist_ok=True)
    jobs = [(n, s) for s in seeds for n in names]
    t0 = time.monotonic()
    rows: dict[tuple[str, int], dict] = {}
    procs = Procs()
    # Records are made and diagnosed in subprocesses; threads only wait on
    # them, and an interrupted sweep kills what is still running.
    signal.signal(signal.SIGTERM, _interrupt)
    ex = cf.ThreadPoolExecutor(max_workers=a.jobs)
    try:
        tool_args = ["--jobs", str(a.tool_jobs)] + (["--holdout", a.holdout] if a.holdout else [])
        futs = {ex.submit(one, n, s, tool, tool_args, a.timeout, keep, procs): (n, s)
                for n, s in jobs}
        for f in cf.as_completed(futs):
            n, s = futs[f]
            r = rows[(n, s)] = f.result()
            named = "n/a" if r["named"] is None else (", ".join(r["named"]) or "none")
            print(f"[bench] {n}-{s}: {verdict(r)}: {named} ({r['status']}), "
                  f"{_f(r['time'], '{:.0f} s')}", file=sys.stderr)
    except KeyboardInterrupt:
        ex.shutdown(wait=False, cancel_futures=True)
        procs.kill_all()
        print("bench_diagnose_indep: interrupted; the records finished so far:", file=sys.stderr)
        done = [rows[j] for j in sorted(rows, key=lambda j: (names.index(j[0]), j[1]))]
        if done:
            print("\n".join(table(done)))
            print()
            print("\n".join(summary(done)))
        return 130
    ex.shutdown()
    ordered = [rows[j] for j in sorted(jobs, key=lambda j: (names.index(j[0]), j[1]))]
    print("\n".join(table(ordered)))
    print()
    print("\n".join(summary(ordered)))
    print(f"\n(sweep wall time {time.monotonic() - t0:.0f} s, {a.jobs} records at once"
          + (f"; records kept in {keep})" if a.keep else ")"))
    return 0


if __name__ == "__main__":
    sys.exit(main())

#!/usr/bin/env python3
# SPDX-License-Identifier: MIT
"""Cycles per sample of the controllers on Cortex-M0+ and Cortex-M4,
from the cross-built library run on an emulated core (tools/mcuemu).

Each figure comes from real calls of pf_ctrl_step_q15 / pf_ctrl_step_f32 in
a linked image: the executed instructions are counted block by block and
priced with the Arm TRMs' instruction timings at zero wait states
(tools/mcuemu/mcuemu/timing.py). Per configuration, the design at the
library's defaults (20 kHz, N = 8; dd is the paper's Example 6) and the
same at N = 1 give the cost of one section (the slope) and the fixed part
(the intercept). Writes a Markdown section to stdout (bench/run.sh puts it
into docs/benchmarks.md).
"""
from __future__ import annotations

import argparse
import re
import sys
import tempfile
from pathlib import Path

from mcuemu.images import Design, link_target
from mcuemu.runner import STEP, TargetRunner, step_costs
from mcuemu.target import Target

CONFIGS = ("p", "dd", "id", "pid")
OUT_FS = {"p": 0.02, "dd": 0.02, "id": 20.0, "pid": 20.0}
BUILDS = [("m0plus", "q15"), ("m4", "q15"), ("m4", "float")]
OPTS = ("-Os", "-O2")
CLOCKS_MHZ = (48, 168)
CORE_NAME = {"m0plus": "Cortex-M0+", "m4": "Cortex-M4"}
# The fewest sections that keep Example 6 within 0.1 % of the exact
# response at 20 kHz (bench_accuracy --orders: 0.035 %, N = 4 gives 0.12 %).
EX6_ORDER = 5
# The nozzle curve (x_1/2 = 0.2 of in_fs: the step drives x far into its
# compression) in Example 6, whose in-sample loop gain is too small to
# move x (the table's direct case), and in id, whose is not (the inverse).
NOZZLE = ("nozzle:xh=0.2",)
NOZZLE_CONFIGS = ("dd", "id")


def designs(core: str) -> list[Design]:
    ds = []
    for arith in ("q15", "float") if core == "m4" else ("q15",):
        for c in CONFIGS:
            for order in (None, 1) + ((EX6_ORDER,) if c == "dd" else ()):
                ds.append(Design(f"b_{c}_{arith}_{order or 'def'}", c, arith,
                                 out_fs=OUT_FS[c], order=order))
        for c in NOZZLE_CONFIGS:
            ds.append(Design(f"b_{c}_{arith}_nozzle", c, arith, out_fs=OUT_FS[c],
                             effects=NOZZLE))
    return ds


def key_config(d: Design) -> str:
    """The configuration's name in the results: dd+nozzle for the nozzle."""
    return d.config + ("+nozzle" if d.effects else "")


def sections(header: Path) -> int:
    return sum(int(n) for n in re.findall(r"\.n_sec = (\d+)", header.read_text()))


def measure(samples: int, work: Path) -> dict:
    """results[(core, arith, opt, config, order)] = dict of figures."""
    res = {}
    for core in ("m0plus", "m4"):
        ds = designs(core)
        for opt in OPTS:
            print(f"[mcu] {core} {opt}", file=sys.stderr)
            out = work / f"{core}{opt}"
            runner = TargetRunner(Target(str(link_target(core, opt, ds, out)), core))
            for arith in ("q15", "float"):
                mine = [d for d in ds if d.arith == arith]
                for index, d in enumerate(mine):
                    costs = step_costs(runner, arith, index, samples)
                    n = len(costs)
                    res[(core, arith, opt, key_config(d), d.order)] = {
                        "sections": sections(out / f"{d.name}.h"),
                        "instr": sum(c.instructions for c in costs) / n,
                        "cycles": sum(c.cycles for c in costs) / n,
                        "max_cycles": max(c.cycles for c in costs),
                        "by_function": _merge(c.by_function for c in costs),
                        "samples": n,
                    }
    return res


def _merge(parts) -> dict:
    total: dict[str, list[float]] = {}
    n = 0
    for p in parts:
        n += 1
        for k, (i, c) in p.items():
            t = total.setdefault(k, [0, 0])
            t[0] += i
            t[1] += c
    return {k: (i / n, c / n) for k, (i, c) in total.items()}


def split(res, core, arith, opt, config):
    """(per section, fixed) cycles from the default design and N = 1."""
    a, b = res[(core, arith, opt, config, None)], res[(core, arith, opt, config, 1)]
    per = (a["cycles"] - b["cycles"]) / (a["sections"] - b["sections"])
    return per, a["cycles"] - per * a["sections"]


def table(res, samples: int) -> str:
    lines = [
        "| core | arithmetic | build | config | sections | instructions/sample "
        "| cycles/sample (mean / max) | cycles per section | fixed cycles "
        + "".join(f"| max rate at {m} MHz " for m in CLOCKS_MHZ) + "|",
        "|---" * (9 + len(CLOCKS_MHZ)) + "|",
    ]
    for core, arith in BUILDS:
        for opt in OPTS:
            for c in CONFIGS:
                r = res[(core, arith, opt, c, None)]
                per, fixed = split(res, core, arith, opt, c)
                rates = "".join(f"| {m * 1e3 / r['max_cycles']:.1f} kHz " for m in CLOCKS_MHZ)
                lines.append(
                    f"| {CORE_NAME[core]} | {'Q15' if arith == 'q15' else 'float'} | {opt} | {c} "
                    f"| {r['sections']} | {r['instr']:,.0f} | {r['cycles']:,.0f} / {r['max_cycles']:,} "
                    f"| {per:.1f} | {fixed:,.0f} {rates}|")
    return "\n".join(lines)


def reduced(res) -> str:
    """Example 6 at the default order and at EX6_ORDER, every build."""
    lines = ["| core | arithmetic | build | N = 8 (51 sections) | "
             f"N = {EX6_ORDER} ({3 * (2 * EX6_ORDER + 1)} sections) "
             + "".join(f"| max rate at {m} MHz, N = {EX6_ORDER} " for m in CLOCKS_MHZ) + "|",
             "|---" * (5 + len(CLOCKS_MHZ)) + "|"]
    for core, arith in BUILDS:
        for opt in OPTS:
            a, b = res[(core, arith, opt, "dd", None)], res[(core, arith, opt, "dd", EX6_ORDER)]
            rates = "".join(f"| {m * 1e3 / b['max_cycles']:.1f} kHz " for m in CLOCKS_MHZ)
            lines.append(f"| {CORE_NAME[core]} | {'Q15' if arith == 'q15' else 'float'} | {opt} "
                         f"| {a['max_cycles']:,} | {b['max_cycles']:,} {rates}|")
    return "\n".join(lines)


def nozzle(res) -> str:
    """What the nozzle curve adds, every build."""
    lines = ["| core | arithmetic | build | config | cycles/sample (mean / max) "
             "| with the nozzle (mean / max) | the nozzle, max |", "|---" * 7 + "|"]
    for core, arith in BUILDS:
        for opt in OPTS:
            for c in NOZZLE_CONFIGS:
                a, b = res[(core, arith, opt, c, None)], res[(core, arith, opt, c + "+nozzle", None)]
                lines.append(f"| {CORE_NAME[core]} | {'Q15' if arith == 'q15' else 'float'} "
                             f"| {opt} | {c} | {a['cycles']:,.0f} / {a['max_cycles']:,} "
                             f"| {b['cycles']:,.0f} / {b['max_cycles']:,} "
                             f"| {b['max_cycles'] - a['max_cycles']:+,} |")
    return "\n".join(lines)


def breakdown(res) -> str:
    """Where Example 6's cycles go, per function, in each build."""
    lines = ["| core | arithmetic | build | function | cycles/sample | share |",
             "|---|---|---|---|---|---|"]
    for core, arith in BUILDS:
        for opt in OPTS:
            r = res[(core, arith, opt, "dd", None)]
            total = r["cycles"]
            top = sorted(r["by_function"].items(), key=lambda kv: -kv[1][1])
            for name, (_, cyc) in top[:6]:
                lines.append(f"| {CORE_NAME[core]} | {'Q15' if arith == 'q15' else 'float'} | {opt} "
                             f"| `{name}` | {cyc:,.0f} | {100 * cyc / total:.0f} % |")
            helpers = sum(c for k, (_, c) in r["by_function"].items() if k.startswith("__"))
            if helpers:
                lines.append(f"| {CORE_NAME[core]} | {'Q15' if arith == 'q15' else 'float'} | {opt} "
                             f"| all compiler helpers (libgcc) | {helpers:,.0f} "
                             f"| {100 * helpers / total:.0f} % |")
    return "\n".join(lines)


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--samples", type=int, default=200,
                    help="step calls measured per design (default 200)")
    args = ap.parse_args()
    with tempfile.TemporaryDirectory() as tmp:
        res = measure(args.samples, Path(tmp))
    print(f"Input: a step of {STEP['q15']} (Q15) or {STEP['float']} (float, in_fs = 1) "
          f"from rest, {args.samples} samples; mean and maximum over them.\n")
    print(table(res, args.samples))
    print(f"\nExample 6 (dd) at N = {EX6_ORDER}, the fewest sections that keep it within "
          "0.1 % of the exact response at 20 kHz (docs/accuracy.md), against the "
          "default N = 8; cycles per sample, maximum over the run:\n")
    print(reduced(res))
    print("\nThe nozzle curve (x_1/2 = 0.2 of in_fs). Q15: in dd the in-sample loop "
          "cannot move x, so one search and one cubic piece per sample; in id it can, "
          "so a search among the loop map's knots and two pieces (the inverse, then "
          "the curve). Float solves the loop by false position:\n")
    print(nozzle(res))
    print("\nWhere Example 6 (dd, default design) spends its cycles, by function "
          "(inlined code counts in its caller):\n")
    print(breakdown(res))
    return 0


if __name__ == "__main__":
    sys.exit(main())

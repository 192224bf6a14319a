#!/usr/bin/env python3
# SPDX-License-Identifier: MIT
"""Cycles per sample of the controllers on Cortex-M0+ and Cortex-M4,
from the cross-built library run on an emulated core (tools/mcuemu).

Each figure comes from real calls of pf_ctrl_step_q15 / pf_ctrl_step_f32
(the full controller) and pf_bank_step_q15 / pf_bank_step_f32 (its
reduced-order bank, made by pneufrac-reduce) in a linked image: the
executed instructions are counted block by block and priced with the Arm
TRMs' instruction timings at zero wait states
(tools/mcuemu/mcuemu/timing.py). Per configuration, the design at the
library's defaults (20 kHz, N = 8; dd is the paper's Example 6) and the
same at N = 1 give the cost of one section (the slope) and the fixed part
(the intercept); for the banks, Example 6's at the default tolerance and at
a loose one (fewer states) do the same. On the M0+ the banks run the
library's ARMv6-M assembly loop, and are measured with its portable C loop
too (the "C loop" rows: -DPNEUFRAC_BANK_ASM=OFF). Writes a Markdown section to stdout
(bench/run.sh puts it into docs/benchmarks.md).
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
# The banks have one build more: the M0+ library with the bank's portable C
# loop (-DPNEUFRAC_BANK_ASM=OFF) instead of its assembly one ("m0plus-c").
BANK_BUILDS = [("m0plus", "q15"), ("m0plus-c", "q15"), ("m4", "q15"), ("m4", "float")]
# Images measured: (label in the results, core, the bank's C loop).
IMAGES = [("m0plus", "m0plus", False), ("m0plus-c", "m0plus", True), ("m4", "m4", False)]
OPTS = ("-Os", "-O2")
CLOCKS_MHZ = (48, 168)
CORE_NAME = {"m0plus": "Cortex-M0+", "m0plus-c": "Cortex-M0+ (C loop)", "m4": "Cortex-M4"}
# The fewest sections that keep Example 6 within 0.1 % of the exact
# response at 20 kHz (bench_accuracy --orders: 0.035 %, N = 4 gives 0.12 %).
EX6_ORDER = 5
# A bank of Example 6 with fewer states than the default's (a loose
# tolerance), for the cost of one state.
LOOSE_TOL = "1e-2"
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
            ds.append(Design(f"r_{c}_{arith}", c, arith, out_fs=OUT_FS[c], kind="bank"))
        ds.append(Design(f"r_dd_{arith}_loose", "dd", arith, out_fs=OUT_FS["dd"], kind="bank",
                         reduce=("--tol", LOOSE_TOL)))
        for c in NOZZLE_CONFIGS:
            ds.append(Design(f"b_{c}_{arith}_nozzle", c, arith, out_fs=OUT_FS[c],
                             effects=NOZZLE))
    return ds


def sections(header: Path) -> int:
    """Sections of a full controller's header, states of a bank's."""
    text = header.read_text()
    if "pf_bank_coeffs" in text:
        return int(re.search(r"\.n_sec = (\d+)", text)[1]) + \
            2 * int(re.search(r"\.n_pair = (\d+)", text)[1])
    return sum(int(n) for n in re.findall(r"\.n_sec = (\d+)", text))


def key(d: Design):
    """results[...] key of a design: (kind, config, variant); the variant
    is the full controller's order or "nozzle", or a bank's "loose"."""
    if d.kind == "ctrl":
        variant = d.order or ("nozzle" if d.effects else None)
    else:
        variant = "loose" if d.reduce else None
    return d.kind, d.config, variant


def measure(samples: int, work: Path) -> dict:
    """results[(core, arith, opt) + key(design)] = dict of figures."""
    res = {}
    for label, core, bank_c in IMAGES:
        # the C loop's image: the banks only (the rest is the same code)
        ds = [d for d in designs(core) if d.kind == "bank" or not bank_c]
        for opt in OPTS:
            print(f"[mcu] {label} {opt}", file=sys.stderr)
            out = work / f"{label}{opt}"
            runner = TargetRunner(Target(str(link_target(core, opt, ds, out, bank_c)), core))
            for arith in ("q15", "float"):
                for kind in ("ctrl", "bank"):
                    mine = [d for d in ds if (d.arith, d.kind) == (arith, kind)]
                    for index, d in enumerate(mine):
                        costs = step_costs(runner, arith, index, samples, kind)
                        n = len(costs)
                        res[(label, arith, opt) + key(d)] = {
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


def _arith(a: str) -> str:
    return "Q15" if a == "q15" else "float"


def _rates(cycles: float) -> str:
    return "".join(f"| {m * 1e3 / cycles:.1f} kHz " for m in CLOCKS_MHZ)


def split(res, core, arith, opt, kind, config, small):
    """(per section or state, fixed) cycles from the default design and a
    smaller one (variant @small) of the same configuration."""
    a = res[(core, arith, opt, kind, config, None)]
    b = res[(core, arith, opt, kind, config, small)]
    per = (a["cycles"] - b["cycles"]) / (a["sections"] - b["sections"])
    return per, a["cycles"] - per * a["sections"]


def table(res, kind: str) -> str:
    """Every configuration and build of one family: the full controller
    (the cost of a section from each configuration's N = 1), or the banks
    (the cost of a state from Example 6's looser bank)."""
    unit, small = ("section", 1) if kind == "ctrl" else ("state", "loose")
    lines = [
        f"| core | arithmetic | build | config | {unit}s | instructions/sample "
        f"| cycles/sample (mean / max) | cycles per {unit} | fixed cycles "
        + "".join(f"| max rate at {m} MHz " for m in CLOCKS_MHZ) + "|",
        "|---" * (9 + len(CLOCKS_MHZ)) + "|",
    ]
    for core, arith in BUILDS if kind == "ctrl" else BANK_BUILDS:
        for opt in OPTS:
            for c in CONFIGS:
                r = res[(core, arith, opt, kind, c, None)]
                split_here = kind == "ctrl" or c == "dd"
                per, fixed = split(res, core, arith, opt, kind, c, small) if split_here else (0, 0)
                lines.append(
                    f"| {CORE_NAME[core]} | {_arith(arith)} | {opt} | {c} "
                    f"| {r['sections']} | {r['instr']:,.0f} | {r['cycles']:,.0f} / {r['max_cycles']:,} "
                    + (f"| {per:.1f} | {fixed:,.0f} " if split_here else "| | ")
                    + f"{_rates(r['max_cycles'])}|")
    return "\n".join(lines)


def before_after(res) -> str:
    """Example 6: the full controller at N = 8 and EX6_ORDER, and its bank."""
    lines = ["| core | arithmetic | build | full, N = 8 (51 sections) | "
             f"full, N = {EX6_ORDER} ({3 * (2 * EX6_ORDER + 1)} sections) | bank "
             + "".join(f"| bank's max rate at {m} MHz " for m in CLOCKS_MHZ) + "|",
             "|---" * (6 + len(CLOCKS_MHZ)) + "|"]
    for core, arith in BUILDS:
        for opt in OPTS:
            a = res[(core, arith, opt, "ctrl", "dd", None)]
            b = res[(core, arith, opt, "ctrl", "dd", EX6_ORDER)]
            k = res[(core, arith, opt, "bank", "dd", None)]
            c = res.get((core + "-c", arith, opt, "bank", "dd", None))
            c_loop = f"; C loop {c['max_cycles']:,}" if c else ""
            lines.append(f"| {CORE_NAME[core]} | {_arith(arith)} | {opt} "
                         f"| {a['max_cycles']:,} | {b['max_cycles']:,} "
                         f"| {k['max_cycles']:,} ({k['sections']} states{c_loop}) "
                         f"{_rates(k['max_cycles'])}|")
    return "\n".join(lines)


def nozzle(res) -> str:
    """What the nozzle curve adds to the full controller, every build."""
    lines = ["| core | arithmetic | build | config | cycles/sample (mean / max) "
             "| with the nozzle (mean / max) | the nozzle, max |", "|---" * 7 + "|"]
    for core, arith in BUILDS:
        for opt in OPTS:
            for c in NOZZLE_CONFIGS:
                a = res[(core, arith, opt, "ctrl", c, None)]
                b = res[(core, arith, opt, "ctrl", c, "nozzle")]
                lines.append(f"| {CORE_NAME[core]} | {_arith(arith)} "
                             f"| {opt} | {c} | {a['cycles']:,.0f} / {a['max_cycles']:,} "
                             f"| {b['cycles']:,.0f} / {b['max_cycles']:,} "
                             f"| {b['max_cycles'] - a['max_cycles']:+,} |")
    return "\n".join(lines)


def breakdown(res, kind: str) -> str:
    """Where Example 6's cycles go, per function, in each build."""
    lines = ["| core | arithmetic | build | function | cycles/sample | share |",
             "|---|---|---|---|---|---|"]
    for core, arith in BUILDS if kind == "ctrl" else BANK_BUILDS:
        for opt in OPTS:
            r = res[(core, arith, opt, kind, "dd", None)]
            total = r["cycles"]
            top = sorted(r["by_function"].items(), key=lambda kv: -kv[1][1])
            for name, (_, cyc) in top[:6]:
                lines.append(f"| {CORE_NAME[core]} | {_arith(arith)} | {opt} "
                             f"| `{name}` | {cyc:,.0f} | {100 * cyc / total:.0f} % |")
            helpers = sum(c for k, (_, c) in r["by_function"].items() if k.startswith("__"))
            if helpers:
                lines.append(f"| {CORE_NAME[core]} | {_arith(arith)} | {opt} "
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
    print("**Example 6, before and after.** Cycles per sample, maximum over the run: the "
          f"full controller at the default order and at N = {EX6_ORDER} (the fewest "
          "sections within 0.1 % of the exact response at 20 kHz, docs/accuracy.md), and "
          "its reduced-order bank (pneufrac-reduce's defaults: within 0.05 % of the full "
          "design's step response over [0, 10] s):\n")
    print(before_after(res))
    print("\n**The reduced-order banks** (`pf_bank_step_*`), every configuration; the cost "
          f"of a state and the fixed part from Example 6's bank and a looser one "
          f"(--tol {LOOSE_TOL}):\n")
    print(table(res, "bank"))
    print("\n**The full controller** (`pf_ctrl_step_*`), every configuration; the cost of a "
          "section from the default design and N = 1:\n")
    print(table(res, "ctrl"))
    print("\nThe nozzle curve (x_1/2 = 0.2 of in_fs) in the full controller. Q15: in dd "
          "the in-sample loop cannot move x, so one search and one cubic piece per sample; "
          "in id it can, so a search among the loop map's knots and two pieces (the "
          "inverse, then the curve). Float solves the loop by false position:\n")
    print(nozzle(res))
    print("\nWhere Example 6's cycles go, by function (inlined code counts in its caller), "
          "the full controller:\n")
    print(breakdown(res, "ctrl"))
    print("\nand its bank:\n")
    print(breakdown(res, "bank"))
    return 0


if __name__ == "__main__":
    sys.exit(main())

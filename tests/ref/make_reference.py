# SPDX-License-Identifier: MIT
"""Exact unit-step responses of the paper's controllers, for the test suite.

Writes, next to this script:
  paper_step_exact.csv   column t (seconds), then one column per case: p_c(t)
  paper_step_cases.json  each case's configuration and parameters (paper names)

How the numbers are made
------------------------
Each case's transfer function is the exact irrational one, with no Oustaloup
approximation: for p, dd and id the paper's own expanded forms (eq. 17, the
last line of eq. 18, eq. 20), for pid the block diagram of Remark 3
(docs/pid.md), which the paper does not expand. Every power is the principal
branch. The unit-step response p_c(t) = L^-1{H(s)/s}(t) is computed with
mpmath's `invertlaplace` at 30 significant digits, twice: on Talbot's contour
and by de Hoog's accelerated Fourier series. The two methods share nothing
but H, and the script refuses to write a value on which they differ by more
than 1e-20 relative (on the last run: at most 3.7e-31). Values are written
with 15 significant digits and the times as the exact binary doubles they
are (shortest round-trip form), so a reader in double sees the value of p_c
at exactly that t, correct to the last digit written.

This code is independent of the C library and of the C reference
(tools/host/pfh_ref.c, Talbot on Weideman's cotangent contour in double):
tests/unit/test_reference.c checks the C reference against this table, and
tests/python/test_reference_table.py checks that the table is what this
script makes.

Run from the project's venv (scripts/setup.sh installs mpmath):
    .venv/bin/python tests/ref/make_reference.py
"""
from __future__ import annotations

import csv
import json
import sys
from pathlib import Path

import mpmath as mp

DIGITS = 30          # working precision of mpmath
METHODS_AGREE = 1e-20  # largest relative Talbot/de Hoog difference accepted
WRITE_DIGITS = 15    # significant digits of p_c in the CSV
HERE = Path(__file__).resolve().parent
CSV_PATH = HERE / "paper_step_exact.csv"
JSON_PATH = HERE / "paper_step_cases.json"

# The paper's Example 4 (eq. 17): shared by Examples 6 and 7 unless overridden.
EXAMPLE4 = dict(b=9, a=1, k1=0.1, k2=0.1, A=2, ks=20, tau=0.001, pmin=1,
                pmax=10, beta=0.8, q=0.9)


def _case(config: str, **over) -> dict:
    return {"config": config, "params": {**EXAMPLE4, **over}}


# Example 4 with the q and beta values of its figures, Example 6 (FrDD) with
# its q values, Example 7 (FrID), and a pid with Example 7's gains, nu = w =
# 0.94 and a derivative restrictor ten times faster than the reset one (the
# library's pid default, docs/pid.md).
CASES = {
    "ex4_q0.9": _case("p", q=0.9),
    "ex4_q0.99": _case("p", q=0.99),
    "ex4_q1.0": _case("p", q=1.0),
    "ex4_beta0.6": _case("p", beta=0.6),
    "ex4_beta0.8": _case("p", beta=0.8),
    "ex4_beta1.0": _case("p", beta=1.0),
    "ex6_q0.9": _case("dd", q=0.9, nu=0.94, RC=0.1),
    "ex6_q0.99": _case("dd", q=0.99, nu=0.94, RC=0.1),
    "ex6_q1.0": _case("dd", q=1.0, nu=0.94, RC=0.1),
    "ex7": _case("id", k1=2, k2=5, q=0, w=0.94, RC=0.1),
    "pid": _case("pid", k1=2, k2=5, q=0, nu=0.94, w=0.94, RCd=0.01, RCi=0.1),
}


def times() -> list[float]:
    """Eight points per decade from 10 us to 10 s, plus every 0.5 s."""
    log_grid = [10.0 ** (k / 8) for k in range(-40, 9)]
    lin_grid = [0.5 * k for k in range(1, 21)]
    return sorted(set(log_grid) | set(lin_grid))


def transfer(config: str, p: dict):
    """H(s) = P_c(s)/E(s) of one case, as a function of an mpmath complex s."""
    p = {k: mp.mpf(v) for k, v in p.items()}
    K = p["k1"] * p["k2"] * p["ks"] * p["b"]
    kappa = p["ks"] * (p["a"] + p["b"])
    eta = p["k1"] * p["k2"] * p["a"] * p["A"]
    tb = p["tau"] ** p["beta"]

    def pw(s, e):
        # s^0 = 1 and s^1 = s exactly, so q = 0 and q = 1 are the rational
        # special cases and not exp(0 * log s).
        return 1 if e == 0 else s if e == 1 else s ** e

    def eq17(s):
        sq, sb = pw(s, p["q"]), pw(s, p["beta"])
        return K * sq * (1 + tb * sb) / (
            kappa * sq * (p["pmin"] + p["pmax"] * tb * sb) + eta * (1 + tb * sb))

    def eq18(s):  # the last line of eq. 18
        q, nu, be, RC = p["q"], p["nu"], p["beta"], p["RC"]
        num = (RC * tb * pw(s, q + nu + be) + RC * pw(s, q + nu) + pw(s, q)
               + tb * pw(s, q + be))
        den = kappa * (p["pmax"] * RC * tb * pw(s, q + nu + be)
                       + p["pmax"] * tb * pw(s, q + be)
                       + p["pmin"] * RC * pw(s, q + nu) + p["pmin"] * pw(s, q))
        return K * num / (den + eta + eta * tb * pw(s, be))

    def eq20(s):
        sq, sb = pw(s, p["q"]), pw(s, p["beta"])
        rw = p["RC"] * pw(s, p["w"])
        return K * sq * (rw + 1) * (1 + tb * sb) / (
            kappa * sq * (rw + 1) * (p["pmin"] + p["pmax"] * tb * sb)
            + eta * rw * (1 + tb * sb))

    def pid(s):
        # Block diagram (docs/pid.md): bellows fed by Rv p_c - Rw p_c.
        u = p["tau"] ** p["beta"] * pw(s, p["beta"])
        relay = (1 + u) / (p["pmin"] + p["pmax"] * u)
        bellows = p["A"] / p["ks"] / pw(s, p["q"])
        xd, xi = p["RCd"] * pw(s, p["nu"]), p["RCi"] * pw(s, p["w"])
        m = (xi - xd) / ((xd + 1) * (xi + 1))  # Rv - Rw over one denominator
        g = p["b"] * p["k1"] * p["k2"] / (p["a"] + p["b"])
        c = p["a"] * p["k1"] * p["k2"] / (p["a"] + p["b"])
        return g * relay / (1 + c * relay * bellows * m)

    return {"p": eq17, "dd": eq18, "id": eq20, "pid": pid}[config]


def step(config: str, params: dict, t: float) -> tuple[mp.mpf, float]:
    """p_c(t) by Talbot, and its relative difference from de Hoog's value."""
    h = transfer(config, params)
    f = lambda s: h(s) / s  # noqa: E731  (mpmath wants a callable)
    with mp.workdps(DIGITS):
        talbot = mp.invertlaplace(f, mp.mpf(t), method="talbot")
        dehoog = mp.invertlaplace(f, mp.mpf(t), method="dehoog")
        return talbot, float(abs(talbot - dehoog) / abs(talbot))


def main() -> int:
    ts = times()
    names = list(CASES)
    rows = [[repr(t)] for t in ts]
    worst = 0.0
    for name in names:
        case = CASES[name]
        for row, t in zip(rows, ts):
            value, diff = step(case["config"], case["params"], t)
            if not diff <= METHODS_AGREE:
                print(f"make_reference: {name} at t = {t}: Talbot and de Hoog "
                      f"differ by {diff:.2e}", file=sys.stderr)
                return 1
            worst = max(worst, diff)
            row.append(mp.nstr(value, WRITE_DIGITS, strip_zeros=False,
                               min_fixed=-4, max_fixed=4))
        print(f"{name}: done", file=sys.stderr)
    with CSV_PATH.open("w", newline="") as f:
        w = csv.writer(f, lineterminator="\n")
        w.writerow(["t"] + names)
        w.writerows(rows)
    JSON_PATH.write_text(json.dumps(CASES, indent=1) + "\n")
    print(f"wrote {CSV_PATH.name} ({len(ts)} times x {len(names)} cases) and "
          f"{JSON_PATH.name}; Talbot and de Hoog agree to {worst:.1e} "
          f"(relative, worst point)")
    return 0


if __name__ == "__main__":
    sys.exit(main())

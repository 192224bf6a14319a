# SPDX-License-Identifier: MIT
"""pneufrac-reduce: a reduced-order realisation of a linear pneufrac
controller for firmware, as a C header (lib pf_bank.h) or JSON.

    pneufrac-reduce --config {p,dd,id,pid} --fs HZ
                    [--set NAME=VALUE ...] [--effect lag:tau=S | deadtime:t=S ...]
                    [--order N] [--band WB:WH] [--t-slow S] [--input-model hold|linear]
                    [--tol F] [--horizon T0:T1] [--method residualise|truncate]
                    [--max-order R] [--format c|json] [--arith q15|float]
                    [--in-fs X --out-fs Y] [--name IDENT] [-o FILE]

The full design is the library's (the same options as `pneufrac design`);
the reduction keeps the fewest states whose unit-step response stays within
--tol (a fraction of its peak, default 5e-4) of the full design's at every
sample of --horizon (default 0:10 s: from the first sample on, so that the
fast response is kept too), and reports what it achieved.

Exit status: 0 written; 1 the output could not be written; 2 bad arguments
(one line on stderr); 3 libpneufrac is missing or does not match; 4 the
design cannot be reduced as asked (an effect inside the loop, an
integrating loop, no order within --max-order meets --tol, or the Q15
scales cannot hold it).
"""
from __future__ import annotations

import argparse
import re
import sys

from pneufrac._cli import UsageError, finite_number, parser_class

EXIT_OK, EXIT_IO, EXIT_USAGE, EXIT_LIBRARY, EXIT_CANNOT = 0, 1, 2, 3, 4
# Most samples of the horizon the rule simulates (the full design runs
# every one of them): 10 s at 1 MHz.
MAX_SAMPLES = 10_000_000
# --effect NAME:K=V: the output-line effects the bank runs, and the in-loop
# ones it refuses (accepted here so that the refusal names the reason).
EFFECTS = {"lag": ("lag", "tau"), "deadtime": ("dead_time", "t"),
           "backlash": ("backlash", "width"), "nozzle": ("nozzle_xh", "xh")}
IDENT = re.compile(r"[A-Za-z_][A-Za-z0-9_]*\Z")


_Parser = parser_class("pneufrac-reduce", EXIT_USAGE)


def _pair(text: str, what: str) -> tuple[float, float]:
    a, sep, b = text.partition(":")
    if not sep:
        raise UsageError(f"{what} '{text}': expected LOW:HIGH")
    return finite_number(a, what), finite_number(b, what)


def _parser() -> _Parser:
    from pneufrac import __version__   # one version for the Python tools

    p = _Parser(prog="pneufrac-reduce", description=__doc__.split("\n\n")[0],
                epilog=__doc__.split("\n\n")[-1], formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--version", action="version", version=f"pneufrac-reduce {__version__}")
    p.add_argument("--config", required=True, choices=["p", "dd", "id", "pid"])
    p.add_argument("--fs", required=True, help="sample rate, Hz")
    p.add_argument("--set", action="append", default=[], metavar="NAME=VALUE",
                   help="a paper parameter (default: the paper's examples)")
    p.add_argument("--effect", action="append", default=[], metavar="NAME:K=V",
                   help="lag:tau=S or deadtime:t=S (backlash, nozzle and saturation act "
                        "inside the loop: refused)")
    p.add_argument("--order", help="Oustaloup order N of the full design (default: the library's)")
    p.add_argument("--band", metavar="WB:WH", help="band of the full design, rad/s")
    p.add_argument("--t-slow", help="slowest time scale of the full design, s")
    p.add_argument("--input-model", choices=["hold", "linear"], default="hold")
    p.add_argument("--tol", default="5e-4",
                   help="largest step-response difference, fraction of its peak (default 5e-4)")
    p.add_argument("--horizon", default="0:10", metavar="T0:T1",
                   help="window of the comparison, s (default 0:10, from the first sample)")
    p.add_argument("--method", choices=["residualise", "truncate"], default="residualise",
                   help="residualise keeps the DC gain (default); truncate the high-frequency gain")
    p.add_argument("--max-order", help="most states (default and limit: the library's "
                                       "PF_BANK_MAX_ORDER)")
    p.add_argument("--format", choices=["c", "json"], default="c",
                   help="c: a header with the coefficient set for pf_bank.h (default); "
                        "json: the reduction and its figures")
    p.add_argument("--arith", choices=["q15", "float"], default="q15",
                   help="q15 (default; with --format c it needs --in-fs and --out-fs) "
                        "or float")
    p.add_argument("--in-fs", help="Q15: the input e that maps to full scale")
    p.add_argument("--out-fs", help="Q15: the output p_c that maps to full scale")
    p.add_argument("--name", default="pf_bank", help="C identifier (default pf_bank)")
    p.add_argument("-o", "--output", help="file (default stdout)")
    return p


def _request(a, lib) -> dict:
    """The validated request, every value a number."""
    r = {"config": a.config, "fs": finite_number(a.fs, "--fs")}
    if not 0 < r["fs"] <= 1e7:
        raise UsageError("--fs must be in (0, 1e7] Hz")
    params = {}
    for item in a.set:
        k, sep, v = item.partition("=")
        if not sep:
            raise UsageError(f"--set '{item}': expected NAME=VALUE")
        k = k.strip()
        try:
            lib.param_range(k)
        except KeyError:
            raise UsageError(f"--set {k}: no such parameter") from None
        if not lib.param_used(a.config, k):
            raise UsageError(f"--set {k}: configuration {a.config} does not use it")
        if k in params:
            raise UsageError(f"--set {k} given more than once")
        params[k] = finite_number(v, f"--set {k}")
    effects = {}
    for item in a.effect:
        name, _, rest = item.partition(":")
        if name == "saturation":
            k = dict(x.partition("=")[::2] for x in rest.split(",") if x)
            if sorted(k) != ["hi", "lo"]:
                raise UsageError(f"--effect {item}: saturation takes lo=...,hi=...")
            effects.update(saturate=1, sat_lo=finite_number(k["lo"], "--effect saturation lo"),
                           sat_hi=finite_number(k["hi"], "--effect saturation hi"))
            continue
        if name not in EFFECTS:
            raise UsageError(f"--effect {item}: unknown effect '{name}' (lag, deadtime, "
                             "backlash, nozzle, saturation)")
        field, key = EFFECTS[name]
        k, sep, v = rest.partition("=")
        if k != key or not sep:
            raise UsageError(f"--effect {item}: {name} takes {key}=...")
        if field in effects:
            raise UsageError(f"--effect {name} given more than once")
        effects[field] = finite_number(v, f"--effect {name}")
    opts = {"input_model": 0 if a.input_model == "hold" else 1}
    if a.order is not None:
        n = finite_number(a.order, "--order")
        if n != int(n) or not 1 <= n <= 99:
            raise UsageError("--order must be a whole number >= 1")
        opts["order"] = int(n)
    if a.band is not None:
        opts["wb"], opts["wh"] = _pair(a.band, "--band")
        if not 0 < opts["wb"] < opts["wh"]:
            raise UsageError(f"--band: need 0 < WB < WH, got '{a.band}'")
    if a.t_slow is not None:
        opts["t_slow"] = finite_number(a.t_slow, "--t-slow")
    tol = finite_number(a.tol, "--tol")
    if not 0 < tol < 1:
        raise UsageError("--tol must be in (0, 1): a fraction of the peak")
    t0, t1 = _pair(a.horizon, "--horizon")
    if not 0 <= t0 < t1:
        raise UsageError("--horizon T0:T1 needs 0 <= T0 < T1")
    if t1 * r["fs"] > MAX_SAMPLES:
        raise UsageError(f"--horizon: {t1:g} s at {r['fs']:g} Hz is more than "
                         f"{MAX_SAMPLES} samples")
    limit = lib.load().pf_bank_max_order()
    max_order = limit
    if a.max_order is not None:
        m = finite_number(a.max_order, "--max-order")
        if m != int(m) or not 1 <= m <= limit:
            raise UsageError(f"--max-order must be a whole number in 1..{limit}")
        max_order = int(m)
    if not IDENT.match(a.name):
        raise UsageError(f"--name '{a.name}' is not a C identifier")
    scales = None
    if a.arith == "q15":
        if (a.in_fs is None) != (a.out_fs is None) or (a.format == "c" and a.in_fs is None):
            raise UsageError("--arith q15 needs --in-fs and --out-fs")
        if a.in_fs is not None:
            scales = (finite_number(a.in_fs, "--in-fs"), finite_number(a.out_fs, "--out-fs"))
            if not (scales[0] > 0 and scales[1] > 0):
                raise UsageError("--in-fs and --out-fs must be > 0")
    elif a.in_fs is not None or a.out_fs is not None:
        raise UsageError("--in-fs and --out-fs are for --arith q15")
    r.update(params=params, effects=effects, design_opts=opts, tol=tol, horizon=[t0, t1],
             method=a.method, max_order=max_order, arith=a.arith, scales=scales)
    return r


def _summary(req: dict, red, ctrl) -> list[str]:
    b, o = red.bank, ctrl.head.opt
    lines = [f"config {req['config']}, fs = {req['fs']:g} Hz; full design: {red.full_order} states "
             f"(N = {o.order}, band [{o.wb:g}, {o.wh:g}] rad/s)",
             f"reduced: {b.order} states ({len(b.lam)} real, {len(b.alpha)} pairs) by "
             f"balanced {req['method'].replace('residualise', 'residualisation').replace('truncate', 'truncation')};",
             f"step response within {100 * red.error:.4f} % of the full design's peak over "
             f"[{req['horizon'][0]:g}, {req['horizon'][1]:g}] s (asked: {100 * req['tol']:g} %)"]
    if b.delay_len:
        lines.append(f"dead time: {b.delay_len} samples (the runtime needs a buffer that long)")
    if req["scales"]:
        lines.append(f"Q15: in_fs = {req['scales'][0]:g} (e), out_fs = {req['scales'][1]:g} (p_c)")
    return lines


def run(a) -> int:
    from pneufrac import binding as lib

    from . import export, fixed
    from .reduce import CannotReduce, design, design_buffer, reduce_design

    req = _request(a, lib)
    try:
        ctrl = design(req["config"], req["fs"], req["params"], req["effects"], **req["design_opts"])
        dl = design_buffer(req["config"], req["fs"], req["params"], req["effects"],
                           **req["design_opts"]).delay_len if "dead_time" in req["effects"] else 0
    except lib.ModelError as exc:
        raise UsageError(str(exc)) from None
    except CannotReduce as exc:
        print(f"pneufrac-reduce: cannot reduce: {exc}", file=sys.stderr)
        return EXIT_CANNOT
    try:
        red = reduce_design(ctrl, req["fs"], tuple(req["horizon"]), req["tol"], req["method"],
                            req["max_order"], dl)
        coeffs = None
        if a.arith == "float" or req["scales"]:
            coeffs = export.coefficient_set(red.bank, a.arith, *(req["scales"] or (1.0, 1.0)))
    except (CannotReduce, fixed.ScaleError) as exc:
        print(f"pneufrac-reduce: cannot reduce: {exc}", file=sys.stderr)
        return EXIT_CANNOT
    if a.format == "c":
        text = export.header(a.name, a.arith, coeffs, _summary(req, red, ctrl))
    else:
        text = export.record(red, {k: req[k] for k in ("config", "fs", "params", "effects",
                                                       "design_opts", "tol", "horizon",
                                                       "method")}, coeffs, a.arith)
    try:
        if a.output:
            with open(a.output, "w") as f:
                f.write(text)
        else:
            sys.stdout.write(text)
            sys.stdout.flush()
    except OSError as exc:
        print(f"pneufrac-reduce: cannot write {a.output or 'stdout'}: "
              f"{exc.strerror or exc}", file=sys.stderr)
        return EXIT_IO
    return EXIT_OK


def main(argv=None) -> int:
    a = _parser().parse_args(argv)
    try:
        return run(a)
    except UsageError as exc:
        print(f"pneufrac-reduce: error: {exc}", file=sys.stderr)
        return EXIT_USAGE
    except Exception as exc:  # noqa: BLE001 - the binding's own errors
        from pneufrac import binding
        if isinstance(exc, binding.LibraryError):
            print(f"pneufrac-reduce: {exc}", file=sys.stderr)
            return EXIT_LIBRARY
        raise


if __name__ == "__main__":
    sys.exit(main())

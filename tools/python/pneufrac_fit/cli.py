# SPDX-License-Identifier: MIT
"""pneufrac-fit: diagnose measured data against the paper's model.

    pneufrac-fit diagnose DATA.csv --config {p,dd,id,pid} [--fix NAME=VALUE ...]
                 [--columns t=NAME,e=NAME,pc=NAME] [--e0 E --pc0 P] [--out DIR] [--json]
    pneufrac-fit generate --config CFG [--effect NAME:K=V[,K=V]] [--n N] [--fs HZ]
                 [--noise F] [--seed S] [--set NAME=VALUE ...] [-o FILE.csv]
    pneufrac-fit fleet DIR|GLOB --config CFG [--scheduler ADDRESS] [--workers N]
                 [--out DIR]

Exit status: 0 success, 1 an internal error (a bug: one line on stderr;
PNEUFRAC_FIT_DEBUG=1 adds the traceback), 2 bad input or arguments or out
of memory (one line on stderr), 3 the shared library is missing or does not
match. A closed output pipe (`generate | head`) ends the command quietly with status 0.
"""
from __future__ import annotations

import argparse
import math
import os
import sys
from pathlib import Path

from pneufrac._cli import UsageError, finite_number, parser_class

from . import holdout, model, sensor

EXIT_INTERNAL = 1
EXIT_USAGE = 2
EXIT_LIBRARY = 3
MAX_JOBS = 5
# generate: the shortest hold of bump_input (0.06 s) must span 2 samples.
MIN_HOLD = 0.06
MIN_FS = 2.0 / MIN_HOLD
MAX_FS = 1e6
MAX_N = 10_000_000
MAX_NOISE = 1.0
MAX_SEED = 2**63 - 1   # numpy's generators take any non-negative integer
# The largest --oversample (diagnose and generate): 64 steps per sample
# reach the fit's 2 kHz from generate's slowest rate (MIN_FS); a record
# slower still gets more from model.auto_oversample, within the fit's cost
# bound (data.MAX_SIM_STEPS).
MAX_OVERSAMPLE = 64


class _ArgError(Exception):
    """argparse refused the command line (its message)."""


class _Parser(parser_class("pneufrac-fit", EXIT_USAGE)):
    """Argument errors come back to main(), which reports every error the
    same way (one line on stderr, and under --json an object on stdout)."""

    def error(self, message):
        raise _ArgError(message)


EXIT_HELP = (f"Exit status: 0 success; {EXIT_INTERNAL} an internal error; {EXIT_USAGE} bad "
             f"input or arguments (one line on stderr); {EXIT_LIBRARY} the shared library "
             "is missing or does not match.")


# The four configurations, as the paper names them (pneufrac simulate --help
# says the same), for each subcommand's --config.
CONFIG_HELP = ("{what} configuration: p (eq. 17), dd (FrDD, eq. 18), "
               "id (FrID, eq. 20) or pid (Remark 3)")


def seed_arg(text: str) -> int:
    """A seed for numpy's generators: a non-negative integer (a negative one
    used to end in a traceback from numpy)."""
    try:
        v = int(text, 10)
    except ValueError:
        raise argparse.ArgumentTypeError(f"'{text}' is not an integer") from None
    if not 0 <= v <= MAX_SEED:
        raise argparse.ArgumentTypeError(f"{v} is outside [0, {MAX_SEED}]")
    return v


def _parser():
    from . import __version__
    p = _Parser(prog="pneufrac-fit", description=__doc__.split("\n\n")[0], epilog=EXIT_HELP)
    p.add_argument("--version", action="version", version=f"pneufrac-fit {__version__}")
    sub = p.add_subparsers(dest="cmd", required=True, parser_class=_Parser)
    d = sub.add_parser("diagnose", help="fit, show what is wrong, name the cause, extend",
                       epilog=EXIT_HELP)
    d.add_argument("data", help="CSV with header t,e,pc (# comments allowed)")
    d.add_argument("--columns", default=None, metavar="t=NAME,e=NAME,pc=NAME",
                   help="header names of the time, input and output columns "
                        "(case-insensitive; default t,e,pc)")
    d.add_argument("--config", required=True, choices=["p", "dd", "id", "pid"],
                   help=CONFIG_HELP.format(what="the recorded controller's"))
    d.add_argument("--fix", action="append", default=[], metavar="NAME=VALUE",
                   help="hold a group at a value (K, L, tau, rho, beta, q, RC, nu, w, "
                        "RCd, RCi_ratio)")
    d.add_argument("--out", metavar="DIR", help="write report.md, diagnosis.json and PNGs")
    d.add_argument("--json", action="store_true", help="print one JSON object on stdout")
    d.add_argument("--e0", type=float, default=None,
                   help="operating point of the input (with --pc0; default: the "
                        "record's opening rest stretch, or estimated in the fit)")
    d.add_argument("--pc0", type=float, default=None,
                   help="operating point of the output (with --e0)")
    d.add_argument("--jobs", type=int, default=None,
                   help=f"worker processes, 1..{MAX_JOBS} (default 2)")
    d.add_argument("--oversample", type=int, default=None,
                   help="simulate at this multiple of the data rate (default: the "
                        f"whole multiple that reaches {model.F_SIM_MIN / 1e3:g} kHz, within the "
                        f"precision of a rate read off time stamps, {100 * model.FS_RTOL:g} %%: "
                        "999.9999 Hz is taken as 1 kHz, 2; below 15 Hz the nearest, "
                        "which can be one over the smallest)")
    d.add_argument("--order", type=int, default=8, help="Oustaloup order N (default 8)")
    d.add_argument("--seed", type=seed_arg, default=0,
                   help="seed of the fresh starts (a non-negative integer)")
    d.add_argument("--holdout", default=holdout.DEFAULT, choices=list(holdout.MODES),
                   help="what is held out for validation: 'cover' (default: the tail, "
                        "or the blocks when the tail goes to levels the first 70 %% never "
                        "reached and the blocks do not, or go there by a share at least "
                        "5 points smaller), 'tail' (the last 30 %% of the "
                        "record) or 'blocks' (the last 30 %% of each third of the record, "
                        "the whole record simulated)")
    d.add_argument("--quiet", action="store_true", help="no progress on stderr")
    g = sub.add_parser("generate", help="synthetic bump test with a hidden effect",
                       epilog=EXIT_HELP)
    g.add_argument("--config", required=True, choices=["p", "dd", "id", "pid"],
                   help=CONFIG_HELP.format(what="the simulated controller's"))
    g.add_argument("--effect", action="append", default=[],
                   help="repeatable: none | deadtime:t=S | lag:tau=S | backlash:width=W | "
                        "nozzle:xh=X[,bias=B] | saturation:lo=L,hi=H (W, X in input units; "
                        "B the nozzle's bias point above the inflection, units of x_1/2)")
    g.add_argument("--n", type=int, default=6000, help="samples (default 6000)")
    g.add_argument("--fs", type=float, default=1000.0,
                   help=f"output rate, Hz, {MIN_FS:.4g}..{MAX_FS:g} (default 1000)")
    g.add_argument("--noise", type=float, default=0.002,
                   help="noise sd as a fraction of the output span, 0..1 (default 0.002)")
    g.add_argument("--oversample", type=int, default=4,
                   help="internal rate multiple (default 4)")
    g.add_argument("--seed", type=seed_arg, default=1,
                   help="seed of the input and the noise (a non-negative integer)")
    g.add_argument("--set", action="append", default=[], metavar="NAME=VALUE",
                   help="paper parameter of the simulated plant (e.g. tau=0.002)")
    g.add_argument("--input", default="steps", choices=["steps", "prbs", "ramps", "sweep"],
                   help="excitation (default steps)")
    g.add_argument("--rest", type=float, default=0.1,
                   help="seconds at rest before the excitation, 0..10 (default 0.1)")
    g.add_argument("--noise-kind", default="white", choices=list(sensor.KINDS),
                   help="colour of the sensor noise (default white)")
    g.add_argument("--drift", type=float, default=0.0,
                   help="slow drift, peak-to-peak fraction of the output span, 0..1")
    g.add_argument("--adc-bits", type=int, default=0,
                   help="quantise e and pc with an ADC of this many bits, 4..24 (0: off)")
    g.add_argument("--order", type=int, default=0,
                   help="the plant's Oustaloup order, 1..8 (0: the library's default)")
    g.add_argument("-o", "--output", help="CSV file (default stdout)")
    from . import fleet_cli
    fleet_cli.add_arguments(sub.add_parser("fleet", help=fleet_cli.HELP, epilog=EXIT_HELP,
                                           description=fleet_cli.DESCRIPTION))
    return p


def _kv(text: str, what: str) -> tuple[str, float]:
    if "=" not in text:
        raise UsageError(f"{what} '{text}': expected NAME=VALUE")
    k, v = text.split("=", 1)
    return k.strip(), finite_number(v, f"{what} '{text}'")


def _kv_dict(items, what: str) -> dict:
    """NAME=VALUE items as a dict; a name given twice is refused (the later
    value silently winning would hide a typo in a script)."""
    out = {}
    for it in items:
        k, v = _kv(it, what)
        if k in out:
            raise UsageError(f"{what} {k}: given twice ({out[k]:g} and {v:g})")
        out[k] = v
    return out


def parse_fixes(items, config) -> dict:
    out = {}
    groups = model.CONFIG_GROUPS[config]
    for k, v in _kv_dict(items, "--fix").items():
        if k not in groups:
            hint = ""
            if k in ("k1", "k2", "a", "b", "A", "ks", "pmin", "pmax", "RCi"):
                hint = (" (not identifiable on its own: only groups reach the output; "
                        "k1, k2, a, b, A, ks, pmin enter through K and L, pmax through rho)")
            raise UsageError(f"--fix {k}: not a group of config {config}{hint}; "
                             f"groups: {', '.join(groups)}")
        lo, hi = model.group_bounds(k)
        if lo is not None and not lo <= v <= hi:
            raise UsageError(f"--fix {k}={v:g}: outside [{lo:g}, {hi:g}]")
        if lo is None and not v > 0:
            raise UsageError(f"--fix {k}={v:g}: must be > 0")
        out[k] = v
    if config == "pid" and "nu" in out and "w" in out and out["nu"] > out["w"]:
        raise UsageError(f"--fix nu={out['nu']:g} w={out['w']:g}: the pid configuration "
                         "needs nu <= w")
    if "RCi_ratio" in out and out["RCi_ratio"] <= 1:
        raise UsageError("--fix RCi_ratio must be > 1")
    return out


def parse_effect(text: str, fs: float) -> tuple[str, dict]:
    names = {"none": "none", "deadtime": "dead_time", "dead_time": "dead_time",
             "lag": "lag", "backlash": "backlash", "nozzle": "nozzle",
             "saturation": "saturation"}
    name, _, rest = text.partition(":")
    if name not in names:
        raise UsageError(f"--effect {text}: unknown effect '{name}'")
    eff = names[name]
    kv = _kv_dict([x for x in rest.split(",") if x], f"--effect {name}:")
    need = {"none": [], "dead_time": ["t"], "lag": ["tau"], "backlash": ["width"],
            "nozzle": ["xh"], "saturation": ["lo", "hi"]}[eff]
    optional = ["bias"] if eff == "nozzle" else []
    if not set(need) <= set(kv) <= set(need) | set(optional):
        raise UsageError(f"--effect {text}: {name} takes "
                         + (",".join(f"{k}=..." for k in need) or "no values")
                         + "".join(f"[,{k}=...]" for k in optional))
    if eff == "dead_time":
        return eff, {"dead_time": kv["t"]}
    if eff == "lag":
        return eff, {"lag": kv["tau"]}
    if eff == "backlash":
        return eff, {"deadband": kv["width"]}
    if eff == "nozzle":
        return eff, {"nozzle_xh": kv["xh"], "nozzle_bias": kv.get("bias", 0.0)}
    if eff == "saturation":
        if not kv["lo"] < kv["hi"]:
            raise UsageError("--effect saturation: lo must be below hi")
        return eff, {"sat_lo": kv["lo"], "sat_hi": kv["hi"]}
    return eff, {}


def _out_dir(path: str) -> Path:
    """Create (or check) the report directory before the long fit."""
    out = Path(path)
    try:
        out.mkdir(parents=True, exist_ok=True)
    except OSError as exc:
        raise UsageError(f"--out {path}: cannot create the directory: "
                         f"{exc.strerror or exc}") from None
    if not os.access(out, os.W_OK | os.X_OK):
        raise UsageError(f"--out {path}: the directory is not writable")
    return out


def cmd_diagnose(a) -> int:
    from . import data, diagnose, output
    fixes = parse_fixes(a.fix, a.config)
    if a.oversample is not None and not 1 <= a.oversample <= MAX_OVERSAMPLE:
        raise UsageError(f"--oversample {a.oversample}: must be in [1, {MAX_OVERSAMPLE}]")
    if not 1 <= a.order <= 8:
        raise UsageError("--order must be in [1, 8]")
    if (a.e0 is None) != (a.pc0 is None):
        raise UsageError("--e0 and --pc0 go together (the operating point of input "
                         "and output)")
    for name, v in (("--e0", a.e0), ("--pc0", a.pc0)):
        if v is not None and not math.isfinite(v):
            raise UsageError(f"{name} must be finite")
    jobs = None if a.jobs is None else min(max(a.jobs, 1), MAX_JOBS)
    cols = data.parse_columns(a.columns) if a.columns is not None else None
    rec = data.read_csv(a.data, cols, a.oversample)    # its cost at this --oversample
    if a.e0 is not None:
        data.set_operating_point(rec, a.e0, a.pc0)
    out = _out_dir(a.out) if a.out else None      # before the (long) fit
    d = diagnose.diagnose(rec, a.config, fixes, order=a.order, oversample=a.oversample,
                          jobs=jobs, progress=not a.quiet, seed=a.seed, holdout=a.holdout)
    if out is not None:
        try:
            path = output.write_report(d, out)
        except OSError as exc:
            raise UsageError(f"--out {a.out}: cannot write the report: "
                             f"{exc.strerror or exc}") from None
        if not a.quiet:
            print(f"[pneufrac-fit] report: {path}", file=sys.stderr)
    if a.json:
        print(output.to_json(d))
    elif out is None:
        print("causes: " + (", ".join(d.causes) if d.causes else "none"))
        for s in d.why:
            print(f"  {s}")
    return 0


def _check_generate(a) -> None:
    if not MIN_FS <= a.fs <= MAX_FS:      # NaN fails too
        why = (f" (the shortest hold, {MIN_HOLD:g} s, must span at least 2 samples)"
               if math.isfinite(a.fs) and 0 < a.fs < MIN_FS else "")
        raise UsageError(f"--fs {a.fs:g}: must be in [{MIN_FS:.4g}, {MAX_FS:g}] Hz{why}")
    if not 0.0 <= a.noise <= MAX_NOISE:   # NaN fails too
        raise UsageError(f"--noise {a.noise:g}: must be in [0, {MAX_NOISE:g}] "
                         "(a fraction of the output span)")
    if not 10 <= a.n <= MAX_N:
        raise UsageError(f"--n {a.n}: must be in [10, {MAX_N}]")
    if not 1 <= a.oversample <= MAX_OVERSAMPLE:
        raise UsageError(f"--oversample {a.oversample}: must be in [1, {MAX_OVERSAMPLE}]")
    lib_fs = model.lib.param_range("fs")    # the library's sample-rate range
    if not 0.0 <= a.rest <= 10.0:
        raise UsageError(f"--rest {a.rest:g}: must be in [0, 10] s")
    if not 0.0 <= a.drift <= 1.0:
        raise UsageError(f"--drift {a.drift:g}: must be in [0, 1]")
    if a.adc_bits and not 4 <= a.adc_bits <= 24:
        raise UsageError(f"--adc-bits {a.adc_bits}: must be 0 or in [4, 24]")
    if not 0 <= a.order <= 8:
        raise UsageError(f"--order {a.order}: must be in [0, 8]")
    if a.fs * a.oversample not in lib_fs:
        raise UsageError(f"--fs x --oversample = {a.fs * a.oversample:g} Hz: the plant is "
                         f"simulated at that rate, at most {lib_fs.hi:g} Hz")


def cmd_generate(a) -> int:
    from . import data, generate
    _check_generate(a)
    effects = {}
    for text in a.effect or ["none"]:
        eff, ep = parse_effect(text, a.fs)
        if eff in effects:
            raise UsageError(f"--effect {text}: {eff} given twice")
        if eff != "none":
            effects[eff] = ep
    params = _kv_dict(a.set, "--set")
    unknown = [k for k in params if k not in model.lib.default_params(a.config)]
    if unknown:
        raise UsageError(f"--set {unknown[0]}: not a paper parameter")
    try:
        ds = generate.generate(a.config, effects=effects, n=a.n, fs=a.fs, noise=a.noise,
                               oversample=a.oversample, seed=a.seed, params=params,
                               input_kind=a.input, rest=a.rest, noise_kind=a.noise_kind,
                               drift=a.drift, adc_bits=a.adc_bits, order=a.order)
    except model.lib.ModelError as exc:
        raise UsageError(str(exc)) from None
    if a.output:
        try:
            data.write_csv(a.output, ds.t, ds.e, ds.pc, ds.comments())
        except OSError as exc:
            raise UsageError(f"-o {a.output}: cannot write: {exc.strerror or exc}") from None
    else:
        data.write_csv(sys.stdout, ds.t, ds.e, ds.pc, ds.comments())
        sys.stdout.flush()
    return 0


def _quiet_broken_pipe() -> None:
    """The reader went away (generate | head): point stdout at /dev/null so
    that the interpreter's final flush does not complain either."""
    try:
        fd = sys.stdout.fileno()
    except (AttributeError, OSError, ValueError):
        return
    try:
        devnull = os.open(os.devnull, os.O_WRONLY)
        os.dup2(devnull, fd)
        os.close(devnull)
    except OSError:
        pass


def _fail(message: str, status: int, as_json: bool) -> int:
    """Report an error: one line on stderr; with --json also one object on
    stdout ({"error": ..., "status": ...}), so that a script that parses
    the output reads the failure instead of choking on an empty stream."""
    print(f"pneufrac-fit: error: {message}", file=sys.stderr)
    if as_json:
        import json
        try:
            print(json.dumps({"error": message, "status": status}), flush=True)
        except OSError:     # stdout itself failed (a full disk): the line above says so
            _quiet_broken_pipe()
    return status


def _wants_json(argv, parser: argparse.ArgumentParser) -> bool:
    """Whether a command line that argparse refused asked for JSON: its
    command takes --json and --json or an abbreviation argparse accepts
    (one no other option of the command starts with) is among its
    options, before a "--" that ends them. The commands and options are
    read off `parser`, the one that refused it (main's). A parsed command
    line says it itself (a.json)."""
    args = list(sys.argv[1:] if argv is None else argv)
    args = args[:args.index("--")] if "--" in args else args
    sub = next((x for x in parser._actions
                if isinstance(x, argparse._SubParsersAction)), None)
    cmd = sub.choices.get(args[0]) if sub is not None and args else None
    if cmd is None or "--json" not in cmd._option_string_actions:
        return False
    opts = [o for o in cmd._option_string_actions if o.startswith("--")]
    return any(x.startswith("--") and [o for o in opts if o.startswith(x)] == ["--json"]
               or x == "--json" for x in args[1:])


def main(argv=None) -> int:
    parser = _parser()
    try:
        a = parser.parse_args(argv)
    except _ArgError as exc:    # as argparse ends: SystemExit with the status
        raise SystemExit(_fail(str(exc), EXIT_USAGE, _wants_json(argv, parser))) from None
    as_json = bool(getattr(a, "json", False))
    from . import data, lib
    try:
        if a.cmd == "diagnose":
            return cmd_diagnose(a)
        if a.cmd == "fleet":
            from . import fleet_cli
            return fleet_cli.run(a, UsageError)
        return cmd_generate(a)
    except (UsageError, data.DataError) as exc:
        return _fail(str(exc), EXIT_USAGE, as_json)
    except lib.ModelError as exc:
        return _fail(f"the library refused the model: {exc}", EXIT_USAGE, as_json)
    except lib.LibraryError as exc:
        return _fail(str(exc), EXIT_LIBRARY, as_json)
    except BrokenPipeError:
        _quiet_broken_pipe()
        return 0
    except OSError as exc:
        where = f"{exc.filename}: " if getattr(exc, "filename", None) else ""
        return _fail(f"{where}{exc.strerror or exc}", EXIT_USAGE, as_json)
    except MemoryError:         # the record is too large for this machine: not a bug
        return _fail("out of memory (cut or decimate the record, or free memory)",
                     EXIT_USAGE, as_json)
    except Exception as exc:    # a bug: still one line, and the JSON object a script reads
        if os.environ.get("PNEUFRAC_FIT_DEBUG"):     # opt-in: the traceback to report
            import traceback
            traceback.print_exc()
        text = " ".join(str(exc).split())           # one line, whatever the message holds
        return _fail(f"internal error ({type(exc).__name__}: {text}); please report it "
                     "with the record (PNEUFRAC_FIT_DEBUG=1 prints the traceback)",
                     EXIT_INTERNAL, as_json)


if __name__ == "__main__":
    sys.exit(main())

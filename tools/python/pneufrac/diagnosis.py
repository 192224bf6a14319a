# SPDX-License-Identifier: MIT
"""diagnose(): pneufrac-fit's diagnosis of a measured record, as a Python
object. The diagnosis itself is pneufrac_fit's (pneufrac_fit.diagnose);
this module only takes the record in the forms Python has it and hands
back its result, the same one `pneufrac-fit diagnose --json` prints."""
from __future__ import annotations

import inspect
from pathlib import Path

import numpy as np


def _record(data, columns: dict | None):
    """A pneufrac_fit Record from a CSV path, a DataFrame or a mapping of
    arrays (t, e, pc; other names through @columns)."""
    from pneufrac_fit import data as data_mod
    names = {"t": "t", "e": "e", "pc": "pc", **(columns or {})}
    if isinstance(data, (str, Path)):
        if not columns:
            return data_mod.read_csv(data)
        if "columns" not in inspect.signature(data_mod.read_csv).parameters:
            raise ValueError("columns= names the columns of a DataFrame or arrays; this "
                             "pneufrac-fit reads CSV files with the header t,e,pc only")
        return data_mod.read_csv(data, columns=names)
    try:
        t, e, pc = (np.asarray(data[names[k]], dtype=float) for k in ("t", "e", "pc"))
    except KeyError as exc:
        raise data_mod.DataError(f"the data have no column {exc} (t, e and pc are needed; "
                                 "other names through columns=)") from None
    except (TypeError, ValueError) as exc:
        raise data_mod.DataError(f"t, e and pc must be numeric arrays ({exc})") from None
    return data_mod.make_record(t, e, pc, "<data>")


def diagnose(data, config: str, *, columns: dict | None = None, fixes: dict | None = None,
             e0: float | None = None, pc0: float | None = None, progress: bool = False,
             **options) -> "Diagnosis":
    """Diagnose a measured record against the paper's model of @config
    ("p", "dd", "id", "pid"), as `pneufrac-fit diagnose` does.

    data: a CSV file (header t,e,pc; '#' comments), a pandas DataFrame, or
        a mapping of 1-D arrays; columns: {"t": ..., "e": ..., "pc": ...}
        for other column names.
    fixes: {group: value}, groups held at a value (K, L, tau, rho, beta,
        q, RC, nu, w, RCd, RCi_ratio); e0, pc0: the operating point, both
        or neither (default: from the record); progress: progress lines on
        stderr; options: order, oversample, jobs, seed, holdout, as the CLI's
        options of those names (their defaults too).

    Raises pneufrac_fit.data.DataError (a ValueError) for a record that
    cannot be analysed, ValueError for bad options.
    """
    from pneufrac_fit import cli, data as data_mod, diagnose as diag_mod, holdout
    if (e0 is None) != (pc0 is None):
        raise ValueError("e0 and pc0 go together (the operating point of input and output)")
    fix_args = [f"{k}={float(v)!r}" for k, v in (fixes or {}).items()]
    try:
        fixed = cli.parse_fixes(fix_args, config) if config in ("p", "dd", "id", "pid") \
            else None
    except cli.UsageError as exc:
        raise ValueError(str(exc).replace("--fix ", "fixes: ")) from None
    if fixed is None:
        raise ValueError(f"config: '{config}' (known: p, dd, id, pid)")
    known = ("order", "oversample", "jobs", "seed", "holdout")
    bad = [k for k in options if k not in known]
    if bad:
        raise ValueError(f"unknown option '{bad[0]}' (options: {', '.join(known)})")
    # checked before the record is read, so that a typo is named as such
    if options.get("holdout", holdout.DEFAULT) not in holdout.MODES:
        raise ValueError(f"holdout: {options['holdout']!r} (known: {', '.join(holdout.MODES)})")
    rec = _record(data, columns)
    if e0 is not None:
        data_mod.set_operating_point(rec, float(e0), float(pc0))
    raw = diag_mod.diagnose(rec, config, fixed, progress=progress, **options)
    return Diagnosis(raw, rec)


def causes_of(j: dict) -> list[dict]:
    """The named effects of a diagnosis's JSON object @j, most important
    first, each {"name", "place", "params", "ci95"}: its "causes" list, or,
    from a pneufrac-fit whose JSON names one cause only, that cause."""
    if "causes" in j:
        return [dict(c) for c in j["causes"]]
    if j["cause"] == "none":
        return []
    names = j["effect_params"].keys()
    return [{"name": j["cause"], "place": j["place"], "params": dict(j["effect_params"]),
             "ci95": {k: v for k, v in j["extended"]["ci95"].items() if k in names}}]


class Diagnosis:
    """The result of diagnose().

    cause: the first named effect, or "none"; causes: the named effects,
    most important first, each {"name", "place", "params", "ci95"}; params:
    every parameter of the final (extended) model, groups and effects;
    intervals: their 95 % intervals, {name: [lo, hi]};
    intervals_not_reliable: {name: why} for the intervals that are no 95 %
    intervals (a group at a bound of its range, or held by the baseline and
    freed in this fit: the JSON's ci95_not_reliable); verdict and
    evidence: the report's sentences; raw: pneufrac_fit's own result.
    """

    def __init__(self, raw, record):
        from pneufrac_fit import output
        self.raw = raw
        self._record = record
        self._dict = output.to_dict(raw)
        j = self._dict
        self.config = j["config"]
        self.params = dict(j["extended"]["params"])
        self.intervals = {k: tuple(v) for k, v in j["extended"]["ci95"].items()}
        self.intervals_not_reliable = dict(j["extended"]["ci95_not_reliable"])
        self.causes = causes_of(j)
        self.cause = self.causes[0]["name"] if self.causes else "none"
        self.verdict = list(j["verdict"])
        self.evidence = list(j["evidence"])

    def __repr__(self) -> str:
        names = ", ".join(c["name"] for c in self.causes) or "none"
        g = self._dict["gain"]
        return (f"<pneufrac.Diagnosis {self.config}: {names}; held-out NRMSE "
                f"{g['nrmse_val_before']:.4g} -> {g['nrmse_val_after']:.4g}>")

    def to_dict(self) -> dict:
        """The JSON object of `pneufrac-fit diagnose --json`."""
        return self._dict

    def to_frame(self):
        """pandas DataFrame, one row per sample: t, measured (p_c),
        baseline (the paper's linear model), extended (with the named
        effects; the baseline when none is named) and residual (measured
        - extended)."""
        import pandas as pd
        d = self.raw
        measured = self._record.pc
        # The fits may work on deviations from an operating point: the
        # models' outputs in the record's units add back what the fit took
        # off the measured output.
        offset = measured - d.y
        extended = d.extended.sim + offset
        return pd.DataFrame({"t": self._record.t, "measured": measured,
                             "baseline": d.baseline.sim + offset, "extended": extended,
                             "residual": measured - extended})

    def figures(self) -> dict:
        """The report's figures as matplotlib Figures, written nowhere:
        {"overview": measured, baseline and extended model with their
        residuals; "before", "after": the residual evidence of the linear
        and the extended model; "candidates": the held-out NRMSE of every
        model tried}."""
        from pneufrac_fit import plots
        return plots.figures(self.raw)

    def write_report(self, out) -> Path:
        """report.md, diagnosis.json and the figures in folder @out, as
        `pneufrac-fit diagnose --out`; returns the report's path."""
        from pneufrac_fit import output
        return output.write_report(self.raw, Path(out))

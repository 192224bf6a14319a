# SPDX-License-Identifier: MIT
"""Measured records: CSV with a header naming t, e and pc (other names
through --columns), # comments; strict checks. Time stamps may jitter and
the record may have gaps (timebase); ADC steps, noise and the opening rest
stretch are read off the signals (signals)."""
from __future__ import annotations

import io
import math
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from . import holdout, signals, timebase

MIN_SAMPLES = 200


class DataError(ValueError):
    """The record cannot be analysed; the message says why, in one line."""


@dataclass
class Record:
    t: np.ndarray
    e: np.ndarray
    pc: np.ndarray
    fs: float
    source: str = ""
    e0: float | None = None  # operating point (opening rest, or given); None: fitted
    pc0: float | None = None
    notes: list = field(default_factory=list)
    gaps: list = field(default_factory=list)
    rest: int = 0            # samples of the opening rest stretch
    op_given: bool = False   # --e0/--pc0
    q_e: float = 0.0         # ADC steps (0: not quantised)
    q_pc: float = 0.0
    sig_e: float = 0.0       # sample-to-sample noise sd (signals.noise_sd)
    sig_pc: float = 0.0

    @property
    def n(self) -> int:
        return self.e.size


DEFAULT_COLUMNS = {"t": "t", "e": "e", "pc": "pc"}


def parse_columns(text: str) -> dict:
    """--columns t=time,e=error,pc=output: the header names of the record's
    t, e and pc columns (case-insensitive); any not given keep their name."""
    out = dict(DEFAULT_COLUMNS)
    for item in (x.strip() for x in text.split(",")):
        if not item:
            continue
        k, sep, v = item.partition("=")
        k, v = k.strip().lower(), v.strip()
        if not sep or k not in out or not v:
            raise DataError(f"--columns {text}: expected t=NAME,e=NAME,pc=NAME "
                            f"(got '{item}')")
        out[k] = v
    if len({v.lower() for v in out.values()}) != 3:
        raise DataError(f"--columns {text}: t, e and pc must be three different columns")
    return out


def read_csv(path: str | Path, columns: dict | None = None) -> Record:
    path = Path(path)
    try:
        text = path.read_text(encoding="utf-8", errors="strict")
    except FileNotFoundError:
        raise DataError(f"{path}: no such file") from None
    except (OSError, UnicodeDecodeError) as exc:
        raise DataError(f"{path}: cannot read: {exc}") from None
    return parse_csv(text, str(path), columns)


def parse_csv(text: str, source: str = "<csv>", columns: dict | None = None) -> Record:
    names = dict(columns or DEFAULT_COLUMNS)
    want = [names[k] for k in ("t", "e", "pc")]
    lines = [(i + 1, ln.strip()) for i, ln in enumerate(io.StringIO(text))]
    lines = [(i, ln) for i, ln in lines if ln and not ln.startswith("#")]
    if not lines:
        raise DataError(f"{source}: empty file (expected a header naming {','.join(want)})")
    hline, header = lines[0]
    cols = [c.strip().lower() for c in header.split(",")]
    missing = [c for c in want if c.lower() not in cols]
    if missing:
        raise DataError(
            f"{source}:{hline}: missing column(s) {', '.join(missing)}; the header "
            f"must name {','.join(want)} (found: {header}; other names: --columns "
            "t=NAME,e=NAME,pc=NAME)")
    idx = [cols.index(c.lower()) for c in want]
    rows = []
    for ln, s in lines[1:]:
        parts = [x.strip() for x in s.split(",")]
        if len(parts) != len(cols):
            raise DataError(f"{source}:{ln}: expected {len(cols)} fields, found {len(parts)}")
        vals = []
        for j, name in zip(idx, want):
            try:
                v = float(parts[j])
            except ValueError:
                raise DataError(f"{source}:{ln}: {name} is not a number: {parts[j]!r}") from None
            if not math.isfinite(v):
                raise DataError(f"{source}:{ln}: {name} is {parts[j]} (NaN or infinite "
                                "values are not allowed; cut the record instead)")
            vals.append(v)
        rows.append(vals)
    if len(rows) < MIN_SAMPLES:
        raise DataError(f"{source}: too few samples: {len(rows)} (need at least {MIN_SAMPLES})")
    a = np.asarray(rows, dtype=float)
    return make_record(a[:, 0], a[:, 1], a[:, 2], source)


def make_record(t, e, pc, source: str = "<data>") -> Record:
    t = np.asarray(t, float)
    e = np.asarray(e, float)
    pc = np.asarray(pc, float)
    if not (t.shape == e.shape == pc.shape) or t.ndim != 1:
        raise DataError(f"{source}: t, e and pc must be 1-D and of equal length")
    for name, v in (("t", t), ("e", e), ("pc", pc)):
        bad = np.flatnonzero(~np.isfinite(v))
        if bad.size:
            raise DataError(f"{source}: {name} is NaN or infinite at sample {bad[0]} "
                            f"(t index {bad[0]}); {bad.size} bad value(s)")
    if t.size < MIN_SAMPLES:
        raise DataError(f"{source}: too few samples: {t.size} (need at least {MIN_SAMPLES})")
    try:
        tb = timebase.analyse(t, source)
    except timebase.TimebaseError as exc:
        raise DataError(str(exc)) from None
    a, b = tb.start, tb.stop
    if b - a < MIN_SAMPLES:
        where = ", ".join(f"t = {g.t:.6g} s" for g in tb.gaps[:3])
        raise DataError(f"{source}: gaps in the record (at {where}{', ...' if len(tb.gaps) > 3 else ''}) "
                        f"leave at most {b - a} samples without a gap (need at least "
                        f"{MIN_SAMPLES})")
    # Own copies: the caller's arrays stay untouched and not aliased, and
    # the same record gives the same diagnosis to the last bit however its
    # arrays were laid out in memory (numpy's sums depend on alignment).
    rec = Record(np.array(t[a:b]), np.array(e[a:b]), np.array(pc[a:b]), tb.fs, source)
    rec.notes.extend(tb.notes(t.size))
    rec.gaps = tb.gaps
    _levels(rec)
    _operating_point(rec)
    _check_excitation(rec)
    split_for(rec)
    return rec


def _levels(rec: Record) -> None:
    """ADC steps and noise of both signals (signals.quantum, noise_sd)."""
    rec.q_e = signals.quantum(rec.e)
    rec.q_pc = signals.quantum(rec.pc)
    rec.sig_e = signals.noise_sd(rec.e, rec.q_e)
    rec.sig_pc = signals.noise_sd(rec.pc, rec.q_pc)
    for name, q, v in (("e", rec.q_e, rec.e), ("pc", rec.q_pc, rec.pc)):
        if q > 0:
            bits = math.log2(max(float(np.ptp(v)) / q, 1.0))
            rec.notes.append(f"{name} is quantised in steps of {q:.4g} ({bits:.1f} bits over "
                             f"its range: an ADC); its quantisation noise, sd "
                             f"{q / math.sqrt(12):.3g}, is part of the noise")


def input_noise(e: np.ndarray) -> float:
    """Robust sd of the noise on e (signals.noise_sd, with its ADC step)."""
    return signals.noise_sd(e, signals.quantum(e))


def change_points(e: np.ndarray, sigma: float | None = None) -> np.ndarray:
    """Indices where the input changes (signals.change_points)."""
    return signals.change_points(e, sigma)


def _operating_point(rec: Record) -> None:
    """The model is incremental from rest: if the record opens with both
    input and output at rest, that stretch is the operating point (e0, pc0
    are its means). Otherwise the diagnosis estimates the operating point
    as part of the fit (rec.e0 = None)."""
    k, why = signals.opening_rest(rec.e, rec.pc, rec.sig_e, rec.q_e, rec.sig_pc, rec.q_pc)
    rec.rest = k
    if k:
        rec.e0 = float(np.mean(rec.e[:k]))
        rec.pc0 = float(np.mean(rec.pc[:k]))
        rec.notes.append(f"operating point from the first {k} samples at rest: "
                         f"e0 = {rec.e0:.6g}, pc0 = {rec.pc0:.6g}")
    else:
        rec.e0 = None
        rec.pc0 = None
        rec.notes.append(f"the record does not open at rest ({why}): the operating point "
                         "(e0, pc0) is estimated as part of the fit, and so is the "
                         "controller's state at the start (a decaying free response)")


def set_operating_point(rec: Record, e0: float, pc0: float) -> None:
    """An operating point given by the user replaces the detected one."""
    if not (math.isfinite(e0) and math.isfinite(pc0)):
        raise DataError("the operating point e0, pc0 must be finite")
    rec.notes = [n for n in rec.notes if not n.startswith(("operating point from",
                                                           "the record does not open"))]
    rec.e0, rec.pc0 = float(e0), float(pc0)
    rec.op_given = True
    rec.notes.append(f"operating point given: e0 = {rec.e0:.6g}, pc0 = {rec.pc0:.6g}")


def _check_excitation(rec: Record) -> None:
    e = rec.e
    span = float(np.max(e) - np.min(e))
    scale = max(float(np.max(np.abs(e))), 1e-300)
    if span <= 1e-9 * scale or span == 0.0:
        raise DataError(f"{rec.source}: the input e is flat (constant {e[0]:.6g}): "
                        "it cannot excite the model; a bump test needs input steps")
    # Measurement noise on e is not excitation: compare the span with it.
    if span < signals.STEP_SIGMAS * rec.sig_e:
        raise DataError(f"{rec.source}: the input e is flat (span {span:.3g} is within "
                        f"{signals.STEP_SIGMAS:g}x its noise {rec.sig_e:.3g}): it cannot "
                        "excite the model")
    pc = rec.pc
    pspan = float(np.max(pc) - np.min(pc))
    if pspan <= 1e-12 * max(float(np.max(np.abs(pc))), 1e-300) or pspan == 0.0:
        raise DataError(f"{rec.source}: the output pc is constant: nothing to fit")


def split_for(rec: Record, mode: str = holdout.DEFAULT):
    """(split, note): the split of the record into fit parts and held-out
    blocks (holdout.layout) whose parts both see the input and the output
    move. Where the split asked for does not (an input that rests through
    the held-out part: a setpoint sequence whose moves all fall in the fit
    part, a test that ends with a long rest), the other split is used if
    its parts do, with a note saying so; DataError when neither does."""
    split = holdout.layout(rec.n, mode)
    try:
        check_parts(rec, split)
        return split, None
    except DataError as exc:
        other_mode = next(m for m in holdout.MODES if m != mode)
        other = holdout.layout(rec.n, other_mode)
        if other == split:
            raise
        try:
            check_parts(rec, other)
        except DataError:
            raise DataError(f"{exc} (nor in {_SPLIT_WORDS[other_mode][0]})") from None
        why = str(exc).split(": ", 1)[-1]
        return other, (f"{_SPLIT_WORDS[mode][0]} refused ({why}): validated on "
                       f"{_SPLIT_WORDS[other_mode][1]} instead")


# How the report names each split (holdout.MODES), and where it validates.
_SPLIT_WORDS = {"tail": ("the held-out tail", "the last 30 % of the record"),
                "blocks": ("held-out blocks", "the last 30 % of each third of the record")}


def check_parts(rec: Record, split) -> None:
    """The input and the output must move in both the fit part and the
    held-out part of the split (holdout.Split): a part where the input
    rests tests nothing, and a held-out part with a constant output has no
    spread to normalise the error by."""
    e, pc = rec.e, rec.pc
    span = float(np.max(e) - np.min(e))
    pspan = float(np.max(pc) - np.min(pc))
    tail = len(split.held) == 1 and split.held[0][1] == split.n
    fit_name = "the first 70 % (fit)" if tail else "the fit parts"
    held_name = "the last 30 % (validation)" if tail else "the held-out blocks (validation)"

    def moves(x, parts, edge):
        # the input's range over each part, from the sample before it (the
        # step into a part is a move of that part)
        return max((float(np.ptp(x[max(s.start - edge, 0):s.stop])) for s in parts),
                   default=0.0)
    if (moves(e, split.fit_slices(), 0) < 0.05 * span
            or moves(e, split.held_slices(), 1) < 0.05 * span):
        raise DataError(f"{rec.source}: the input must move in both {fit_name} and "
                        f"{held_name} of the record")
    for parts, name in ((split.fit_slices(), fit_name), (split.held_slices(), held_name)):
        rng = float(np.ptp(np.concatenate([pc[s] for s in parts])))
        if rng < 0.05 * pspan:
            raise DataError(f"{rec.source}: the output pc does not move in {name} of the "
                            f"record (range {rng:.3g}, under 5 % of its span "
                            f"{pspan:.3g}): it must respond in both parts")


def write_csv(path, t, e, pc, comments=()) -> None:
    """Write a record; path may be an open text stream (e.g. sys.stdout)."""
    if hasattr(path, "write"):
        _write_rows(path, t, e, pc, comments)
        return
    with open(path, "w", encoding="utf-8") as f:
        _write_rows(f, t, e, pc, comments)


def _write_rows(f, t, e, pc, comments) -> None:
    for c in comments:
        f.write(f"# {c}\n")
    f.write("t,e,pc\n")
    for a, b, c in zip(t, e, pc):
        f.write(f"{a:.9g},{b:.9g},{c:.9g}\n")

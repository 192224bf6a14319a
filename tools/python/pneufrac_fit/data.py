# SPDX-License-Identifier: MIT
"""Measured records: CSV t,e,pc with # comments; strict checks."""
from __future__ import annotations

import io
import math
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

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
    e0: float = 0.0          # operating point (first rest stretch)
    pc0: float = 0.0
    notes: list = field(default_factory=list)

    @property
    def n(self) -> int:
        return self.e.size


def read_csv(path: str | Path) -> Record:
    path = Path(path)
    try:
        text = path.read_text(encoding="utf-8", errors="strict")
    except FileNotFoundError:
        raise DataError(f"{path}: no such file") from None
    except (OSError, UnicodeDecodeError) as exc:
        raise DataError(f"{path}: cannot read: {exc}") from None
    return parse_csv(text, str(path))


def parse_csv(text: str, source: str = "<csv>") -> Record:
    lines = [(i + 1, ln.strip()) for i, ln in enumerate(io.StringIO(text))]
    lines = [(i, ln) for i, ln in lines if ln and not ln.startswith("#")]
    if not lines:
        raise DataError(f"{source}: empty file (expected a header t,e,pc)")
    hline, header = lines[0]
    cols = [c.strip().lower() for c in header.split(",")]
    missing = [c for c in ("t", "e", "pc") if c not in cols]
    if missing:
        raise DataError(
            f"{source}:{hline}: missing column(s) {', '.join(missing)}; the header "
            f"must name t,e,pc (found: {header})")
    idx = [cols.index(c) for c in ("t", "e", "pc")]
    rows = []
    for ln, s in lines[1:]:
        parts = [x.strip() for x in s.split(",")]
        if len(parts) != len(cols):
            raise DataError(f"{source}:{ln}: expected {len(cols)} fields, found {len(parts)}")
        vals = []
        for j, name in zip(idx, ("t", "e", "pc")):
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
    dt = np.diff(t)
    if np.any(dt <= 0):
        k = int(np.flatnonzero(dt <= 0)[0])
        raise DataError(f"{source}: t is not strictly increasing at sample {k + 1} "
                        f"(t = {t[k]:.9g} then {t[k + 1]:.9g})")
    T = (t[-1] - t[0]) / (t.size - 1)
    dev = np.abs(dt - T)
    tol = 1e-3 * T + 1e-9 * max(abs(t[0]), abs(t[-1]))
    if np.any(dev > tol):
        k = int(np.argmax(dev))
        raise DataError(
            f"{source}: non-uniform sampling: step {k + 1} is {dt[k]:.9g} s, the mean "
            f"step is {T:.9g} s (uniform sampling is required; resample first)")
    fs = 1.0 / T
    rec = Record(t, e, pc, fs, source)
    _operating_point(rec)
    _check_excitation(rec)
    return rec


def change_points(e: np.ndarray, rel: float = 1e-9) -> np.ndarray:
    """Indices n where e[n] != e[n-1] (beyond rounding)."""
    span = float(np.max(e) - np.min(e))
    d = np.abs(np.diff(e))
    return np.flatnonzero(d > rel * max(span, 1e-300)) + 1


def _operating_point(rec: Record) -> None:
    """The model is incremental from rest: if the record opens with a
    constant-input stretch, that stretch is the operating point."""
    cp = change_points(rec.e)
    first = int(cp[0]) if cp.size else rec.n
    if first >= 5:
        rec.e0 = float(rec.e[0])
        rec.pc0 = float(np.mean(rec.pc[:first]))
        rec.notes.append(f"operating point from the first {first} samples at rest: "
                         f"e0 = {rec.e0:.6g}, pc0 = {rec.pc0:.6g}")
    else:
        rec.notes.append("record does not open at rest: the model starts from "
                         "rest at e = 0, pc = 0")


def _check_excitation(rec: Record) -> None:
    e = rec.e
    span = float(np.max(e) - np.min(e))
    scale = max(float(np.max(np.abs(e))), 1e-300)
    if span <= 1e-9 * scale or span == 0.0:
        raise DataError(f"{rec.source}: the input e is flat (constant {e[0]:.6g}): "
                        "it cannot excite the model; a bump test needs input steps")
    # Measurement noise on e is not excitation: compare the span with it.
    d = np.diff(e)
    sig = 1.4826 * float(np.median(np.abs(d - np.median(d)))) / math.sqrt(2.0)
    if span < 20.0 * sig:
        raise DataError(f"{rec.source}: the input e is flat (span {span:.3g} is within "
                        f"20x its noise {sig:.3g}): it cannot excite the model")
    split = int(0.7 * rec.n)
    if np.ptp(e[:split]) < 0.05 * span or np.ptp(e[split - 1:]) < 0.05 * span:
        raise DataError(f"{rec.source}: the input must move in both the first 70 % (fit) "
                        "and the last 30 % (validation) of the record")
    pspan = float(np.max(rec.pc) - np.min(rec.pc))
    if pspan == 0.0:
        raise DataError(f"{rec.source}: the output pc is constant: nothing to fit")


def write_csv(path, t, e, pc, comments=()) -> None:
    with open(path, "w", encoding="utf-8") as f:
        for c in comments:
            f.write(f"# {c}\n")
        f.write("t,e,pc\n")
        for a, b, c in zip(t, e, pc):
            f.write(f"{a:.9g},{b:.9g},{c:.9g}\n")

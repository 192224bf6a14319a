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


# An input change is a step of e larger than STEP_SIGMAS times the noise on
# e (robust sd, input_noise) and larger than rounding (1e-9 of the span).
# The operating point, the noise estimate of the diagnosis and the flatness
# check all use this one definition.
STEP_SIGMAS = 20.0


def input_noise(e: np.ndarray) -> float:
    """Robust sd of the noise on e from first differences: 1.4826 MAD / sqrt 2.
    Steps are rare outliers of the differences, so a stepped input without
    noise gives 0."""
    d = np.diff(np.asarray(e, float))
    if d.size == 0:
        return 0.0
    return 1.4826 * float(np.median(np.abs(d - np.median(d)))) / math.sqrt(2.0)


def change_points(e: np.ndarray, sigma: float | None = None) -> np.ndarray:
    """Indices n where the input changes: |e[n] - e[n-1]| beyond STEP_SIGMAS
    times the noise on e (sigma; estimated by input_noise when None) and
    beyond rounding."""
    e = np.asarray(e, float)
    if e.size < 2:
        return np.zeros(0, int)
    if sigma is None:
        sigma = input_noise(e)
    span = float(np.max(e) - np.min(e))
    thr = max(STEP_SIGMAS * sigma, 1e-9 * max(span, 1e-300))
    return np.flatnonzero(np.abs(np.diff(e)) > thr) + 1


def _operating_point(rec: Record) -> None:
    """The model is incremental from rest: if the record opens with a
    constant-input stretch (no input change, noise allowed), that stretch
    is the operating point."""
    cp = change_points(rec.e)
    first = int(cp[0]) if cp.size else rec.n
    if first >= 5:
        rec.e0 = float(np.mean(rec.e[:first]))
        rec.pc0 = float(np.mean(rec.pc[:first]))
        rec.notes.append(f"operating point from the first {first} samples at rest: "
                         f"e0 = {rec.e0:.6g}, pc0 = {rec.pc0:.6g}")
    else:
        rec.notes.append("record does not open at rest: the model starts from "
                         "rest at e = 0, pc = 0 (give --e0 and --pc0 if the "
                         "operating point is known)")


def set_operating_point(rec: Record, e0: float, pc0: float) -> None:
    """An operating point given by the user replaces the detected one."""
    if not (math.isfinite(e0) and math.isfinite(pc0)):
        raise DataError("the operating point e0, pc0 must be finite")
    rec.notes = [n for n in rec.notes if not n.startswith(("operating point from",
                                                           "record does not open"))]
    rec.e0, rec.pc0 = float(e0), float(pc0)
    rec.notes.append(f"operating point given: e0 = {rec.e0:.6g}, pc0 = {rec.pc0:.6g}")


def _check_excitation(rec: Record) -> None:
    e = rec.e
    span = float(np.max(e) - np.min(e))
    scale = max(float(np.max(np.abs(e))), 1e-300)
    if span <= 1e-9 * scale or span == 0.0:
        raise DataError(f"{rec.source}: the input e is flat (constant {e[0]:.6g}): "
                        "it cannot excite the model; a bump test needs input steps")
    # Measurement noise on e is not excitation: compare the span with it.
    sig = input_noise(e)
    if span < STEP_SIGMAS * sig:
        raise DataError(f"{rec.source}: the input e is flat (span {span:.3g} is within "
                        f"{STEP_SIGMAS:g}x its noise {sig:.3g}): it cannot excite the model")
    split = int(0.7 * rec.n)
    if np.ptp(e[:split]) < 0.05 * span or np.ptp(e[split - 1:]) < 0.05 * span:
        raise DataError(f"{rec.source}: the input must move in both the first 70 % (fit) "
                        "and the last 30 % (validation) of the record")
    pc = rec.pc
    pspan = float(np.max(pc) - np.min(pc))
    if pspan <= 1e-12 * max(float(np.max(np.abs(pc))), 1e-300) or pspan == 0.0:
        raise DataError(f"{rec.source}: the output pc is constant: nothing to fit")
    # The output must move in both parts too: a validation part with a
    # constant output has no spread to normalise the error by.
    for part, name in ((pc[:split], "the first 70 % (fit)"),
                       (pc[split:], "the last 30 % (validation)")):
        if np.ptp(part) < 0.05 * pspan:
            raise DataError(f"{rec.source}: the output pc does not move in {name} of the "
                            f"record (range {np.ptp(part):.3g}, under 5 % of its span "
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

# SPDX-License-Identifier: MIT
"""Measured records: CSV with a header naming t, e and pc (other names
through --columns), # comments; strict checks. Time stamps may jitter and
the record may have gaps (timebase); ADC steps, noise and the opening rest
stretch are read off the signals (signals)."""
from __future__ import annotations

import csv
import math
import re
from dataclasses import dataclass, field
from functools import cached_property
from pathlib import Path

import numpy as np

from . import holdout, signals, timebase

MIN_SAMPLES = 200
# The longest simulation a record may need. A fit's cost is the number of
# simulation steps: the record's duration x the simulation rate, which is
# the smallest whole multiple of the record's rate at or above
# model.F_SIM_MIN (2 kHz), within the precision of a rate read off time
# stamps (model.auto_oversample, FS_RTOL), or the --oversample
# asked for (check_cost). The bound is a fixed multiple of the record of
# issue 8's time target (100 000 samples at 1 kHz, simulated at 2 kHz:
# under 30 s per diagnosis). The time per step is not the same for every
# record: every record is explored on a copy of at most 6000 samples
# (search.explorer), then refined on the whole record, and a slow
# record's samples are many steps each: at the bound (2000 samples at
# 1 Hz, 4e6 steps) a diagnosis took 1047 s with --jobs 1 (its copy is the
# whole record). The multiple, 20, admits every record a typical
# 256 MiB file (MAX_FILE_BYTES, about 3.5 M rows at one step each) holds at
# 2 kHz and faster: it bites only where a slow rate multiplies the steps
# per sample, a time column in ms read as seconds (1 kHz read as 1 Hz,
# 2000 steps per sample) or a slow record over 2000 s long. Slow records
# (10, 20, 25 Hz historian exports) within it are read.
TIME_TARGET_STEPS = 100_000 * 2    # 100 000 samples x auto_oversample(1 kHz) = 2
MAX_SIM_STEPS = 20 * TIME_TARGET_STEPS
# Relative tolerance of the top rate: timebase estimates the rate from the
# stamps, so a record at exactly the bound reads a few ulps off it (above
# it when the stamps do not start at 0); such a rate is taken as the bound.
RATE_RTOL = 1e-9
# Above this many simulation steps per sample a record's rate is far
# slower than the model's: the fit simulates at model.F_SIM_MIN at least
# (the rate the method was validated at, for the controller's fast terms),
# and beyond 64 steps a sample (under 31.25 Hz), the most --oversample
# takes, the samples are far apart for those terms. Such records are read
# (historian exports at 10-25 Hz), with a note: this slow a rate is also
# what a time column in ms gives (a 1-30 kHz record read as 1-30 Hz), whose
# fit would take 1000 times the time with time constants 1000 times off.
SLOW_STEPS_PER_SAMPLE = 64


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
    level_e: float = 0.0     # the noise's level sd (level_sd), for coverage
    level_pc: float = 0.0

    @property
    def n(self) -> int:
        return self.e.size


DEFAULT_COLUMNS = {"t": "t", "e": "e", "pc": "pc"}


def parse_columns(text: str) -> dict:
    """--columns t=time,e=error,pc=output: the header names of the record's
    t, e and pc columns (case-insensitive); any not given keep their name."""
    out = dict(DEFAULT_COLUMNS)
    given = set()
    for item in (x.strip() for x in text.split(",")):
        if not item:
            continue
        k, sep, v = item.partition("=")
        k, v = k.strip().lower(), v.strip()
        if not sep or k not in out or not v:
            raise DataError(f"--columns {text}: expected t=NAME,e=NAME,pc=NAME "
                            f"(got '{item}')")
        if k in given:
            raise DataError(f"--columns {text}: {k} given twice")
        given.add(k)
        out[k] = v
    if len({v.lower() for v in out.values()}) != 3:
        raise DataError(f"--columns {text}: t, e and pc must be three different columns")
    return out


# The largest record file read (fleet's limit before, now diagnose's too: a
# 10 kHz hour of t,e,pc is about 1 GB; a historian export per loop is far
# smaller): about 3.5 million rows, some 1.5 GB of memory while parsed.
# Read in one bounded call, so that
# a device given as the file (/dev/zero) or a file still growing does not
# fill the memory.
MAX_FILE_BYTES = 256 * 2**20


def read_bytes(path: str | Path) -> bytes:
    """A record file's bytes, at most MAX_FILE_BYTES (DataError beyond)."""
    with open(path, "rb") as f:
        raw = f.read(MAX_FILE_BYTES + 1)
    if len(raw) > MAX_FILE_BYTES:
        raise DataError(f"{path}: larger than {MAX_FILE_BYTES // 2**20} MiB, the most a "
                        "record file may hold; cut it or decimate it")
    return raw


def read_csv(path: str | Path, columns: dict | None = None,
             oversample: int | None = None) -> Record:
    path = Path(path)
    try:
        raw = read_bytes(path)
    except FileNotFoundError:
        raise DataError(f"{path}: no such file") from None
    except IsADirectoryError:
        raise DataError(f"{path}: is a directory, not a CSV file") from None
    except OSError as exc:
        raise DataError(f"{path}: cannot read: {exc.strerror or exc}") from None
    return parse_csv(decode(raw, str(path)), str(path), columns, oversample)


# Byte-order marks of the encodings a spreadsheet or logger may write
# instead of UTF-8 ("Unicode text" in Excel is UTF-16).
_WIDE_BOMS = ((b"\xff\xfe\x00\x00", "UTF-32"), (b"\x00\x00\xfe\xff", "UTF-32"),
              (b"\xff\xfe", "UTF-16"), (b"\xfe\xff", "UTF-16"))
_SHOW = 60      # characters of a line quoted in a message


def decode(raw: bytes, source: str) -> str:
    """The text of a record file. UTF-8, with or without a byte-order
    mark. Bytes that are not UTF-8 are kept as lone surrogates (Python's
    surrogateescape) so that a comment written in another code page (a
    unit's degree sign in Latin-1) does not refuse the record; parse_csv
    refuses them where they would be read: the cells of the rows (a unit in
    a column's name, as Excel writes it in cp1252, is not: the wanted
    columns' names match the names asked for, see _header)."""
    for bom, name in _WIDE_BOMS:
        if raw.startswith(bom):
            raise DataError(f"{source}: the file is {name} text; save it as UTF-8 (or "
                            "ASCII) CSV")
    return raw.decode("utf-8", errors="surrogateescape")


def _show(text: str) -> str:
    """A line as a message quotes it: invisible and undecodable characters
    escaped, and cut to _SHOW characters."""
    r = ascii(text)[1:-1]
    return r if len(r) <= _SHOW else r[:_SHOW] + "..."


def _undecoded(s: str) -> int | None:
    """The index of the first byte of s that decode() could not read as
    UTF-8 (kept as a lone surrogate, U+DC80-U+DCFF), or None."""
    return next((j for j, ch in enumerate(s) if "\udc80" <= ch <= "\udcff"), None)


def _check_line(source: str, ln: int, s: str, utf8: bool = True) -> None:
    """A header or data line must be text: no NUL (a binary file, or UTF-16
    without a mark) and, with utf8, only UTF-8 (a surrogate here is a byte
    decode() could not read)."""
    if "\x00" in s:
        raise DataError(f"{source}:{ln}: NUL byte in the line: not a text CSV (a binary "
                        "file, or UTF-16 without a byte-order mark?)")
    bad = _undecoded(s)
    if utf8 and bad is not None:
        raise DataError(f"{source}:{ln}: character {bad + 1}: byte "
                        f"0x{ord(s[bad]) - 0xdc00:02x} is not UTF-8; save the file as "
                        "UTF-8 (or ASCII) CSV")


def _fields(s: str) -> list[str]:
    """The comma-separated fields of a line, blanks around them removed and
    one pair of enclosing double quotes (as some exporters write every
    field) taken off. A quoted field may hold commas ("p, bar"): a line
    with a quote is split by the csv module (one line at a time, so that
    messages keep their line numbers; a quoted field cannot span lines)."""
    if '"' not in s:        # the common line: a plain split, without the csv module
        return [x.strip() for x in s.split(",")]
    try:
        row = next(csv.reader([s], skipinitialspace=True), [])
    except csv.Error as exc:    # a field over the csv module's limit, a NUL (3.9, 3.10)
        raise _LineError(str(exc)) from None
    return [x.strip() for x in row]


class _LineError(ValueError):
    """A line the csv module cannot split; the caller names the line."""


def _split(source: str, ln: int, s: str) -> list[str]:
    """_fields of line ln, a DataError naming it when it cannot be split."""
    try:
        return _fields(s)
    except _LineError as exc:
        _check_line(source, ln, s, utf8=False)
        raise DataError(f"{source}:{ln}: cannot split the line: {exc}") from None


def _lines(text: str) -> list[tuple[int, str]]:
    """(line number, text) of every line that is not blank or a comment.
    Lines end in LF, CRLF or a lone CR (old Mac and some loggers' files);
    a byte-order mark at the start is not part of the first line."""
    text = text[1:] if text.startswith("\ufeff") else text
    lines = enumerate(_NEWLINE.split(text), start=1)
    return [(i, ln.strip()) for i, ln in lines if ln.strip() and not ln.strip().startswith("#")]


_NEWLINE = re.compile(r"\r\n|\r|\n")


def _header(source: str, hline: int, header: str, want: list[str]) -> list[int]:
    """The indices of the wanted columns in the header line. The header
    is not checked for UTF-8: the wanted names match the names asked for,
    so a byte that is not UTF-8 can only be in an unused column's name (a
    unit in cp1252), which is not read."""
    _check_line(source, hline, header, utf8=False)
    cols = [c.lower() for c in _split(source, hline, header)]
    if len(cols) == 1:
        sep = next((c for c in (";", "\t", "|") if c in header), None)
        if sep is not None:
            raise DataError(f"{source}:{hline}: the header's fields are separated by "
                            f"{sep!r}, not commas (found: {_show(header)}); pneufrac-fit reads "
                            "comma-separated values with '.' as the decimal point: "
                            "export the record as such")
    missing = [c for c in want if c.lower() not in cols]
    if missing:
        # a name asked for in UTF-8 cannot match one written in another code
        # page (p\xb0C in Latin-1): say so rather than only "missing"
        hint = ("; the header has bytes that are not UTF-8: save the file as UTF-8"
                if _undecoded(header) is not None else "")
        raise DataError(
            f"{source}:{hline}: missing column(s) {', '.join(missing)}; the header "
            f"must name {','.join(want)} (found: {_show(header)}; other names: --columns "
            f"t=NAME,e=NAME,pc=NAME){hint}")
    for c in want:
        at = [j + 1 for j, x in enumerate(cols) if x == c.lower()]
        if len(at) > 1:
            raise DataError(f"{source}:{hline}: column {c} appears {len(at)} times in the "
                            f"header (columns {', '.join(map(str, at))}): which one is "
                            "meant is ambiguous; rename the others")
    return [cols.index(c.lower()) for c in want]


def parse_csv(text: str, source: str = "<csv>", columns: dict | None = None,
              oversample: int | None = None) -> Record:
    names = dict(columns or DEFAULT_COLUMNS)
    want = [names[k] for k in ("t", "e", "pc")]
    lines = _lines(text)
    if not lines:
        raise DataError(f"{source}: empty file (expected a header naming {','.join(want)})")
    hline, header = lines[0]
    idx = _header(source, hline, header, want)
    ncols = len(_split(source, hline, header))
    a = np.empty((len(lines) - 1, 3))    # not a list of lists: a third of the memory
    for i, (ln, s) in enumerate(lines[1:]):
        parts = _split(source, ln, s)
        if len(parts) != ncols:
            _check_line(source, ln, s)
            raise DataError(f"{source}:{ln}: expected {ncols} fields, found {len(parts)}")
        a[i] = [_number(source, ln, name, parts[j], s) for j, name in zip(idx, want)]
    if len(a) < MIN_SAMPLES:
        raise DataError(f"{source}: too few samples: {len(a)} (need at least {MIN_SAMPLES})")
    return make_record(a[:, 0], a[:, 1], a[:, 2], source, oversample)


def _number(source: str, ln: int, name: str, field: str, line: str) -> float:
    """One cell as a finite float, or a DataError naming line and column."""
    try:
        v = float(field)
    except ValueError:
        _check_line(source, ln, line)
        if not field:
            raise DataError(f"{source}:{ln}: {name} is empty (every row needs t, e and "
                            "pc; cut the record instead)") from None
        raise DataError(f"{source}:{ln}: {name} is not a number: '{_show(field)}'") from None
    if "_" in field:        # float() takes "1_000"; a CSV number never has it
        raise DataError(f"{source}:{ln}: {name} is not a number: '{_show(field)}'")
    if not math.isfinite(v):
        raise DataError(f"{source}:{ln}: {name} is {_show(field)} (NaN or infinite "
                        "values are not allowed; cut the record instead)")
    return v


def make_record(t, e, pc, source: str = "<data>", oversample: int | None = None) -> Record:
    """A checked Record. oversample: the simulation's multiple of the rate
    (None: model.auto_oversample), which sets the fit's cost (check_cost)."""
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
    _check_levels(e, pc, source)
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
    fs = _check_rate(tb.fs, source)
    check_cost(b - a, fs, oversample, source)
    # Own copies: the caller's arrays stay untouched and not aliased, and
    # the same record gives the same diagnosis to the last bit however its
    # arrays were laid out in memory (numpy's sums depend on alignment).
    rec = Record(np.array(t[a:b]), np.array(e[a:b]), np.array(pc[a:b]), fs, source)
    rec.notes.extend(tb.notes(t.size))
    if model_oversample(fs) > SLOW_STEPS_PER_SAMPLE:
        rec.notes.append(slow_note(fs))
    rec.gaps = tb.gaps
    _levels(rec)
    _operating_point(rec)
    _check_excitation(rec)
    split_for(rec)
    return rec


def max_rate() -> float:
    """The fastest sample rate (Hz) a record may have: the fastest the
    library simulates at all (a faster one ended in a traceback from the
    fit)."""
    from . import lib
    return lib.param_range("fs").hi


def sim_steps(n: int, fs: float) -> int:
    """The simulation steps of one fit of n samples at fs Hz (at the rate
    model.auto_oversample chooses)."""
    return int(n) * model_oversample(fs)


def model_oversample(fs: float) -> int:
    """model.auto_oversample (model imported late, as lib)."""
    from . import model
    return model.auto_oversample(fs)


def slow_note(fs: float) -> str:
    """The note of a record slower than SLOW_STEPS_PER_SAMPLE allows."""
    from . import model
    return (f"the record's rate is {fs:.6g} Hz: the fit simulates it at "
            f"{model.auto_oversample(fs)}x to reach the {model.F_SIM_MIN:g} Hz the model "
            f"needs, more than {SLOW_STEPS_PER_SAMPLE} steps a sample; if t is in ms "
            f"(a {fs * 1000:.6g} Hz record), convert it to seconds: read as it is, its "
            "time constants come out 1000 times too long")


# The smallest span of a signal: the fit works with squared deviations, and
# below the square root of the smallest normal double they are subnormal
# (precision lost, then zero: values of 1e-300 ended in a traceback).
MIN_SPAN = float(np.sqrt(np.finfo(float).tiny))


def max_level() -> float:
    """The largest magnitude of a record's value or operating point: the
    library's range of levels (its saturation limits)."""
    from . import lib
    return lib.param_range("sat_hi").hi


def _check_levels(e: np.ndarray, pc: np.ndarray, source: str) -> None:
    """The record's values in units the library can model: the levels its
    effects take (saturation limits in output units, dead band and nozzle
    widths in input units) are bounded by the library's range, so values
    beyond it cannot be modelled (1e150 ended in a traceback); and spans a
    fit can square."""
    big = max_level()
    for name, v in (("e", e), ("pc", pc)):
        k = int(np.argmax(np.abs(v)))
        if abs(v[k]) > big:
            raise DataError(f"{source}: {name} is {v[k]:.6g} at sample {k}: beyond the "
                            f"library's range of levels, +-{big:g}; rescale it (other units)")
        span = float(np.max(v) - np.min(v))
        if 0.0 < span < MIN_SPAN:
            raise DataError(f"{source}: {name} spans only {span:.3g}: below {MIN_SPAN:.3g}, "
                            "its squared deviations are lost in a double; rescale it (other "
                            "units)")


def _check_rate(fs: float, source: str) -> float:
    """The record's rate within what the library simulates: the rate, set
    to the top one when within RATE_RTOL of it (the fit simulates at the
    rate, and the library checks its top exactly)."""
    hi = max_rate()
    if fs > hi * (1 + RATE_RTOL):
        raise DataError(f"{source}: the time stamps give a sample rate of {fs:.6g} Hz, "
                        f"above the {hi:g} Hz the library simulates; t must be in seconds "
                        "(a time in minutes or hours reads 60 or 3600 times too fast)")
    return min(fs, hi)


def check_cost(n: int, fs: float, oversample: int | None = None,
               source: str = "<data>") -> int:
    """The simulation's multiple of the rate (oversample, or
    model.auto_oversample when None), checked: the simulation rate within
    the library's top rate, and the fit's simulation steps within
    MAX_SIM_STEPS. The one check of a fit's cost, wherever the multiple is
    known (make_record, diagnose.diagnose); DataError naming the likely
    causes on its side."""
    given = oversample is not None
    m = int(oversample) if given else model_oversample(fs)
    hi = max_rate()
    if given and fs * m > hi * (1 + RATE_RTOL):
        raise DataError(f"{source}: --oversample {m} simulates at {fs:g} x {m} = "
                        f"{fs * m:.6g} Hz, above the {hi:g} Hz the library simulates; use "
                        f"at most {max(int(hi * (1 + RATE_RTOL) // fs), 1)}")
    steps = int(n) * m
    if steps > MAX_SIM_STEPS:
        longest = MAX_SIM_STEPS // m
        if given:
            raise DataError(f"{source}: --oversample {m}: {n} samples need {steps:,} "
                            f"simulation steps, more than the {MAX_SIM_STEPS:,} a fit may "
                            f"take (at most {longest:,} samples at {m}x); use a smaller "
                            "one or cut the record")
        raise DataError(f"{source}: {n} samples at {fs:.6g} Hz ({n / fs:.6g} s) need "
                        f"{steps:,} simulation steps at {fs * m:.6g} Hz, more than the "
                        f"{MAX_SIM_STEPS:,} a fit may take (at most {longest:,} samples at "
                        "this rate); either t is not in seconds "
                        "(a time in ms or us reads 1000 or 1 000 000 times too slow: "
                        "convert it to seconds) or the record is too long to fit at once "
                        "(cut it into shorter records, or give a smaller --oversample)")
    return m


def _levels(rec: Record) -> None:
    """ADC steps and noise of both signals (signals.quantum, noise_sd)."""
    rec.q_e = signals.quantum(rec.e)
    rec.q_pc = signals.quantum(rec.pc)
    rec.sig_e = signals.noise_sd(rec.e, rec.q_e)
    rec.sig_pc = signals.noise_sd(rec.pc, rec.q_pc)
    # the levels' margins depend on the record alone, not on a split: made
    # once here, read by every split's coverage (uncovered)
    rests = rest_windows(rec.e, signals.change_points(rec.e, rec.sig_e, rec.q_e))
    rec.level_e = level_sd(rec.e, rests, rec.sig_e)
    rec.level_pc = level_sd(rec.pc, rests, rec.sig_pc)
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
    if max(abs(e0), abs(pc0)) > max_level():    # as the record's values (_check_levels)
        raise DataError(f"the operating point e0 = {e0:g}, pc0 = {pc0:g} is beyond the "
                        f"library's range of levels, +-{max_level():g}")
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
    blocks (holdout.layout), chosen from the record alone before any fit,
    in four steps:
    1. the split asked for ("cover": the tail) must have an input that moves
       and an output that responds in both its parts; where it does not,
       the other layout is used if its parts do (_fallback), DataError
       when neither does;
    2. its held-out samples should stay at levels its fit parts visited,
       and its held-out input's content mostly within their input's band
       of frequencies (uncovered); when they do, it is used without a note;
    3. when they do not, mode "cover" takes the other layout if that one
       is covered and its parts move (_other_refused names what stops it);
    4. when the other is uncovered too, mode "cover" takes it if its
       held-out samples lie outside its fit parts' levels by a clearly
       smaller share and its parts move (_extrapolates_less); the note
       then says that its held-out error includes an extrapolation;
       otherwise the split stays and the note says so, and why the other
       layout does not help."""
    if mode not in holdout.MODES:
        raise ValueError(f"holdout must be one of {', '.join(holdout.MODES)}")
    switch = mode == "cover"
    mode = "tail" if switch else mode
    split = holdout.layout(rec.n, mode)
    other = holdout.layout(rec.n, next(m for m in holdout.LAYOUTS if m != mode))
    rests = _rests(rec, split)
    if rests is not None:
        return _fallback(rec, split, other, rests)
    mine, theirs = _Coverage(rec, split), _Coverage(rec, other)
    why = mine.why
    if why is None:
        return split, None
    name, other_where = _split_words(split)[0], _split_words(other)[1]
    stop = _other_refused(rec, mine, theirs)
    if stop is None and switch:
        return other, (f"{name} refused ({why}: a prediction there would be an "
                       "extrapolation, and an effect acting only there cannot be fitted): "
                       f"validated on {other_where} instead, whose held-out samples stay "
                       "within the levels and the input's frequencies of its fit parts")
    if switch and stop is not None and _extrapolates_less(rec, theirs, mine):
        return other, (f"{name} refused ({why}): validated on {other_where} instead, "
                       f"whose held-out samples go less outside its fit parts' levels "
                       f"({theirs.why}), so {_EXTRAPOLATES}")
    if stop is None:
        stop = (f"validating on {other_where} would keep the held-out samples within the "
                "fit parts' levels and input frequencies (--holdout cover, the default, "
                "does so in that case)")
    return split, f"{name}: {why}, so {_EXTRAPOLATES}; {stop}"


# What an uncovered split's note ends with (split_for, _fallback).
_EXTRAPOLATES = ("the held-out error includes an extrapolation to those levels or "
                 "frequencies, where an effect acting only there cannot be fitted")


def _fallback(rec: Record, split, other, rests: str):
    """split_for's step 1: the split asked for has a part that rests (an
    input that rests through the held-out part: a setpoint sequence whose
    moves all fall in the fit part, a test that ends with a long rest):
    the other layout if its parts move, with a note saying so and whether
    it covers its held-out levels; DataError when neither moves."""
    if other == split:
        raise DataError(f"{rests}{_PARTS_HINT}")
    other_rests = _rests(rec, other)
    if other_rests is not None:
        raise DataError(f"{rests} (nor in {_split_words(other)[0]}){_PARTS_HINT}")
    note = (f"{_split_words(split)[0]} refused ({_reason(rests)}): validated on "
            f"{_split_words(other)[1]} instead")
    out = uncovered(rec, other)
    return other, note if out is None else f"{note}; {out}, so {_EXTRAPOLATES}"


def _other_refused(rec: Record, mine: "_Coverage", theirs: "_Coverage") -> str | None:
    """split_for's step 3: why the other layout (theirs) cannot replace an
    uncovered split (mine), a phrase for the note, or None when it can: the
    first that holds of: the record is too short for another layout; the
    other's held-out samples go beyond its fit parts' levels or input
    frequencies too; a part of the other rests."""
    other = theirs.split
    if other == mine.split:
        return "the record is too short for another split"
    other_name = _split_words(other)[0]
    out = theirs.why
    if out is not None:
        return (f"the other split, {other_name}, does not keep them within its fit parts' "
                f"levels and input frequencies either ({out})")
    rests = _rests(rec, other)
    if rests is not None:
        return (f"the other split, {other_name}, would keep them within its fit parts' "
                f"levels and input frequencies but is refused ({_reason(rests)})")
    return None


# When neither split covers, the other is taken only if its share of
# held-out samples outside its fit parts' levels (outside, below: the larger
# of the two signals') is smaller by more than MAX_OUTSIDE. A convention,
# not a measured resolution: MAX_OUTSIDE is the share at which coverage
# counts at all, and the margin behind the shares (5 level sd plus one ADC
# step) is estimated from the record's own noise, so its sampling error
# moves samples near a range's edge from one side to the other; shares
# that close are taken as alike (the shares' own sampling error was not
# measured: branch extrap31). Two splits within it extrapolate alike and
# the split asked for stays (the layout every earlier figure was measured
# with). The larger of the two signals' shares is compared: a split can be
# picked that goes further outside on one signal than the other split
# does on that signal, when it goes much less outside on the other. The
# argument is the same as for a covered other split: the held-out error
# judges the fit parts' model, and the less of it an effect can act on
# unseen, the less an extrapolation decides it.
def _extrapolates_less(rec: Record, theirs: "_Coverage", mine: "_Coverage") -> bool:
    """split_for's step 4: the other layout (theirs), uncovered like the
    split (mine), lies outside its fit parts' levels by a share smaller
    than the split's by more than MAX_OUTSIDE, is covered in frequency, and
    its parts move. Only levels are weighed here: a layout whose held-out
    input lies at frequencies its fit parts lack would trade one
    extrapolation for another, with nothing to say which is the smaller
    (review of split34)."""
    if theirs.split == mine.split:
        return False
    if mine.levels[0] - theirs.levels[0] <= MAX_OUTSIDE:
        return False
    return theirs.band <= MAX_BAND_OUTSIDE and _rests(rec, theirs.split) is None


def _reason(message: str) -> str:
    """A DataError's message without the record's name before it."""
    return message.split(": ", 1)[-1]


def _rests(rec: Record, split) -> str | None:
    """Why a part of the split does not see the input and the output move
    (check_parts' message), or None when both parts do."""
    try:
        check_parts(rec, split)
    except DataError as exc:
        return str(exc)
    return None


# Coverage: a held-out test asks the model fitted on the fit parts to
# predict samples like those it was fitted on. A held-out sample whose input
# or output lies outside the range the fit parts visited, by more than
# signals.REST_SIGMAS times the noise's level sd plus one ADC step (the
# margin within which the record is taken to hold a level at all), is at a
# level the fit never saw. The level sd (level_sd) is how far the noise
# alone moves a signal's level within a window of a held-out block's
# length, not the sample-to-sample sd: slow noise (AR(1) near 1, drift,
# pink) wanders several times further than its sample-to-sample sd says
# (AR(1) 0.95: 5x), and a margin from that sd alone called such wander a new
# level (review of split29: 6 covered records in 40 flagged at AR(1)
# 0.995). For white noise the two are the same and 5 sd is left with a
# probability under 1e-6 per sample. The level sd is a property of the
# noise, so it is measured only where the signal holds a level: in windows
# where the input rests (rest_windows), at the end of a stretch between
# input changes, where the output's response has settled. Where the input
# never rests (a sine, a multisine, a jitter, a wander) a window holds the
# excitation itself, and its spread measured the input's own motion as
# noise (review of cover30: 20-106x the noise sd on e, 9-60x on pc), so a
# tail at new levels read as covered; without a model nothing there tells
# the noise from the response, and the sample-to-sample sd is taken:
# exact for white noise, and for slow noise an error towards "uncovered",
# which costs the split asked for only where the other split is covered
# (split_for). An error towards "covered" comes from the range being
# max/min (one glitch in a fit part widens it) and from a level sd
# inflated by what moves within a resting window (a response not yet
# settled, an input's motion under WINDOW_REST_SHARE of its span, which
# counts as resting): both only keep the split asked for and drop its
# extrapolation note. A sample beyond the margin is at a level the fit never
# saw: an effect acting only there (a limit reached only in the tail, a
# nozzle's curve beyond the fitted range) is invisible to every fit and
# decides the held-out comparison alone. A split is uncovered when more
# than MAX_OUTSIDE of its held-out samples are such samples, on either
# signal: one held-out sample in twenty, the scale of the guards' smallest
# held-out gain counted as evidence (guards.MIN_VAL_GAIN). The share is of
# samples, not of error, so this is a convention at the guards' scale, not
# a bound; it is computed from the data alone before any fit, so no verdict
# can tune it.
MAX_OUTSIDE = 0.05
# A split's part excites the model (check_parts) when the input's range
# there reaches this share of its span over the record: an excitation
# floor, a part moving less tests too little to identify anything.
REST_SHARE = 0.05
# A window of level_sd rests when the input's range there is under this
# share of its span. The fact it stands for is another one: the input's
# motion in the window is what its own noise explains (as
# signals.rest_length decides rest, within REST_SIGMAS noise sd). That
# test on the sample-to-sample sd rejects every window of slow noise on the
# input (its wander over a window is several of its process sd), and
# cover30's slow-noise protection with it; no rule on the input alone tells
# slow noise from a slow excitation of the same size. So this share is not
# derived: it is check_parts's value, borrowed, and its cost is bounded,
# not nil. An input moving under 5 % of its span within windows between its
# changes (a small sine or PRBS after a set-point step) counts as resting;
# its own motion then sets the level sd, up to about 2 % of the span (a
# sine just under 5 % peak to peak: 2.2 %), so a tail may swing up to
# about 11 % of the input's span (REST_SIGMAS of that) beyond the fit
# parts' range and read as covered (review of level31, B1). And an input
# whose noise wanders by 5 % of its span within a window has no resting
# window: its margin is the sample-to-sample sd's, an error towards
# "uncovered" on slow noise (R4).
WINDOW_REST_SHARE = 0.05


def rest_windows(e: np.ndarray, cuts: np.ndarray) -> list:
    """Starts of the windows of holdout.MIN_HELD samples (a held-out block's
    shortest length) in which the input rests (its range under
    WINDOW_REST_SHARE of its span): laid from the end of each stretch
    between input changes (cuts: signals.change_points of e) backwards, so
    that none crosses a change and the last of each sits where the
    response has settled."""
    w = holdout.MIN_HELD
    tol = WINDOW_REST_SHARE * float(np.ptp(e))
    edges = np.r_[0, np.asarray(cuts, int), e.size]
    return [s for a, b in zip(edges[:-1], edges[1:]) for s in range(b - w, a - 1, -w)
            if float(np.ptp(e[s:s + w])) < tol]


def level_sd(x: np.ndarray, starts: list, sig: float) -> float:
    """The sd of x's noise as a level (Coverage, above): the robust sd
    (signals.mad_sd) of x less its straight line over the windows of
    holdout.MIN_HELD samples at starts (rest_windows); sig (the
    sample-to-sample sd) when it is larger or there is no such window. The
    line takes out a ramp and an integrator's drift; the robust sd
    discounts what remains of a response. Noise slower than the window
    (1/f at the longest scales) is not counted: the margin then stays that
    of the noise within a block."""
    if not starts:
        return sig
    w = holdout.MIN_HELD
    X = np.asarray([x[s:s + w] for s in starts], float)
    k = np.arange(w, dtype=float)
    A = np.c_[np.ones(w), k]
    resid = X - (X @ np.linalg.pinv(A).T) @ A.T
    return max(sig, signals.mad_sd(resid.ravel()))


def outside(rec: Record, split) -> tuple:
    """(share, signal's name): the larger of the input's and the output's
    shares of the split's held-out samples beyond its fit parts' levels by
    more than the margin (Coverage, above); the input's on a tie."""
    best = (-1.0, "")
    for name, x, lsd, q in (("input e", rec.e, rec.level_e, rec.q_e),
                            ("output pc", rec.pc, rec.level_pc, rec.q_pc)):
        share = holdout.outside_share(x, split, signals.REST_SIGMAS * lsd + q)
        if share > best[0]:
            best = (share, name)
    return best


# Coverage in frequency: a held-out test asks the fit parts' model to
# predict the response to an input like the one it was fitted on, in
# content as well as in level. A held-out input whose variation lies at
# frequencies the fit parts' input hardly had (the fast end of a sine
# sweep held out by the tail) asks for the response at frequencies the fit
# never saw: an extrapolation in frequency, as a level outside the fit
# parts' range is one in amplitude, and an effect that shows mainly there
# (a lag's or a dead time's phase, which grows with frequency) is
# invisible to every fit and decides the held-out comparison alone (branch
# trace34 traced two two-effect records to it, two-lag-backlash-5 and
# two-dead_time-saturation-5, but those are 5 s sweeps that this test
# leaves on the tail, 41 %; on seeds 4-5 it moves the 20 s sweeps to the
# blocks: clean-sweep-4/5, clean-dd-real-4, lag-sweep-4/5, lag-real-5,
# branch split34). The fit parts' band is the frequencies holding all but
# MAX_OUTSIDE / 2 of their input's content at each end (the level test's
# share, split between the two ends); the held-out share is of the
# held-out input's content, its power less its white noise
# (holdout.band_outside_share), so that noise, present at every frequency
# in both parts, does not count as content. For an input whose two parts
# are drawn alike from many moves (random steps, PRBS, a multisine) that
# share is near MAX_OUTSIDE, what the band leaves out of the fit parts'
# own content (measured, branch split34: at most 5 % on the independent
# simulator's records of seeds 4-5 other than sweeps, 16 % on 98 blind
# ones; review of split34: 2-5 % on multisines, 30 steps, PRBS, a random
# walk); with few moves it scatters widely (below). The tail counts as
# uncovered in frequency only when most of its content (over
# MAX_BAND_OUTSIDE) lies outside the band: then the held-out error judges
# the extrapolation more than what the fit learned. A majority, not the
# level test's one sample in twenty: the share is of power, and the power
# of a few random steps is spread over frequency unevenly enough to put
# far more than MAX_OUTSIDE outside the other part's band by chance (review
# of split34: of random 3- or 5-step sequences, 1 % over the half, up to
# 79 %, those looked at each with a tail step within 0.1-0.3 s of the
# tail's edge, which the taper makes a pulse: holdout's taper comment);
# and the held-out blocks of a 20 s sweep keep a third of their content
# just above their fit parts' band (the last block holds the sweep's end),
# a short extrapolation that the tail's is not (a wide 5 s sweep's blocks
# reach the half: review of split34). The test reads the record
# alone, before any fit.
MAX_BAND_OUTSIDE = 0.5


def _band_outside(rec: Record, split) -> float:
    """The share of the split's held-out input content outside its fit
    parts' band (holdout.band_outside_share; Coverage in frequency)."""
    return holdout.band_outside_share(rec.e, split, rec.sig_e ** 2, MAX_OUTSIDE / 2)


def uncovered(rec: Record, split) -> str | None:
    """Why the split's held-out part is not covered by its fit parts'
    levels (Coverage, above) or by their input's frequencies (Coverage in
    frequency), or None when it is."""
    return _Coverage(rec, split).why


class _Coverage:
    """One split's coverage of the record (uncovered): its level share
    (outside) and its frequency share (_band_outside), each computed when
    first read and then kept, since split_for reads the other layout's in
    its steps 3 and 4 and in its note. The frequency share is read only
    when the levels are covered, or by step 4."""

    def __init__(self, rec: Record, split):
        self.rec, self.split = rec, split

    @cached_property
    def levels(self) -> tuple:
        return outside(self.rec, self.split)

    @cached_property
    def band(self) -> float:
        return _band_outside(self.rec, self.split)

    @cached_property
    def why(self) -> str | None:
        parts = "its fit parts" if len(self.split.fit_slices()) > 1 else "its fit part"
        share, name = self.levels
        if share > MAX_OUTSIDE:
            return (f"{_percent(share, MAX_OUTSIDE)} % of its held-out samples have the "
                    f"{name} outside the range {parts} visited")
        if self.band > MAX_BAND_OUTSIDE:
            return (f"{_percent(self.band, MAX_BAND_OUTSIDE)} % of its held-out input's "
                    f"variation is at frequencies outside the band holding "
                    f"{100 * (1 - MAX_OUTSIDE):.0f} % of the input's variation in {parts}")
        return None


def _percent(share: float, limit: float) -> str:
    """A share over limit as a percentage for a note: whole percents, one
    decimal more at a time (up to four) while rounding would print it at or
    under limit's percentage (0.501 over a half reads "50.1", where "50"
    would say it is not over)."""
    for digits in range(5):
        text = f"{100 * share:.{digits}f}"
        if float(text) > 100 * limit:
            break
    return text


# What to do when no split has moves in both parts: every split was tried
# (split_for), so only another record helps.
_PARTS_HINT = ("; the fit learns from one part and is judged on the other, so give a "
               "record whose input moves, and output responds, all along it")

# How the report names a split (holdout.layout), and where it validates:
# from the layout itself, which on a short record has fewer blocks than
# the mode asked for.
_SECTION_WORDS = {2: "half", 3: "third"}


def _split_words(split) -> tuple:
    held = f"{100 * (1 - holdout.FIT_FRACTION):.0f} %"
    k = len(split.held)
    if k == 1:
        return "the held-out tail", f"the last {held} of the record"
    each = _SECTION_WORDS.get(k, f"of its {k} sections")
    return "held-out blocks", f"the last {held} of each {each} of the record"


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
    if (moves(e, split.fit_slices(), 0) < REST_SHARE * span
            or moves(e, split.held_slices(), 1) < REST_SHARE * span):
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

# SPDX-License-Identifier: MIT
"""CSV files of `pneufrac simulate`: units in a '#' line that pandas skips
with comment='#', and every number in its shortest round-trip form, the
same digits as Python's repr (an independent shortest-digit algorithm)."""
import io
import random
import struct

import numpy as np
import pandas as pd

from conftest import run


def repr_text(v: float) -> str:
    r = repr(v)
    return r[:-2] if r.endswith(".0") else r


def random_doubles(n, seed):
    """Normal doubles (the CLI refuses subnormal input as out of range;
    tests/unit/test_fmt.c covers those)."""
    rnd = random.Random(seed)
    out = []
    while len(out) < n:
        kind = len(out) % 3
        if kind == 0:   # any bit pattern: huge and tiny exponents
            v = struct.unpack("<d", struct.pack("<Q", rnd.getrandbits(64)))[0]
        elif kind == 1:  # ordinary magnitudes
            v = rnd.uniform(-1, 1) * 10.0 ** rnd.randint(-12, 12)
        else:           # powers of two: the lopsided rounding intervals
            v = rnd.choice([-1, 1]) * 2.0 ** rnd.randint(-1022, 1023)
        if np.isfinite(v) and abs(v) >= 2.2250738585072014e-308:
            out.append(v)
    return out


def test_units_line_and_pandas(tmp_path):
    text = run("simulate", "--config", "dd", "--fs", 1000, "--duration", 0.01,
               "--arith", "q15", "--in-fs", 1, "--out-fs", 0.02).stdout
    lines = text.splitlines()
    assert lines[0] == "t,e,pc,pc_q15"
    assert lines[1] == "# units: s,input units,output units,counts of out_fs/32768"
    df = pd.read_csv(io.StringIO(text), comment="#")
    assert list(df.columns) == ["t", "e", "pc", "pc_q15"] and len(df) == 11
    assert df["pc_q15"].dtype.kind == "i"


def test_every_number_is_the_shortest(tmp_path):
    fs = 1000
    e = random_doubles(30000, seed=11)
    src = tmp_path / "in.csv"
    src.write_text("t,e\n" + "".join(f"{repr(k / fs)},{repr(v)}\n" for k, v in enumerate(e)))
    text = run("simulate", "--config", "p", "--fs", fs, "--duration", (len(e) - 1) / fs,
               "--input", src).stdout
    rows = [ln.split(",") for ln in text.splitlines() if not ln.startswith("#")][1:]
    assert len(rows) == len(e)
    for k, (t, ev, pc) in enumerate(rows):
        assert t == repr_text(k / fs)
        assert ev == repr_text(e[k])
        assert pc == repr_text(float(pc))   # the output too, read back exactly


def test_float_output_is_the_shortest_float():
    text = run("simulate", "--config", "id", "--fs", 1000, "--duration", 2,
               "--arith", "float").stdout
    df = pd.read_csv(io.StringIO(text), comment="#", dtype=str)
    for s in df["pc"]:
        f = np.float32(s)
        assert np.float32(float(s)) == f
        # as many significant digits as numpy's shortest float32 text
        assert digits(s) == digits(np.format_float_scientific(f, unique=True))


def digits(s: str) -> str:
    return s.split("e")[0].replace("-", "").replace(".", "").strip("0")

# SPDX-License-Identifier: MIT
"""One interface to an instance on the host build and on an emulated core,
so that a test drives both the same way and compares.

new(arith, index, kind) binds coefficient set `index` of
fw_sets_<kind>_<arith>[] (kind "ctrl": the full controller, pf_ctrl_*;
"bank": the reduced-order bank, pf_bank_*) to a fresh instance (init) and
returns its Handle; step() and run() are the family's step and run;
reset() its reset. Q15 values are int16, float values float32.
"""
from __future__ import annotations

import ctypes as C
from pathlib import Path
from typing import NamedTuple

import numpy as np

from .images import C_TYPES, entry
from .target import Target

# Dead-time buffer given to every instance: at least the delay_len of any
# design used here (the library refuses a shorter one, PF_E_BUFFER).
DELAY_MAX = 1024
DTYPES = {"q15": np.int16, "float": np.float32}
SIZE_INDEX = {k: i for i, k in enumerate(C_TYPES)}


class Handle(NamedTuple):
    kind: str
    arith: str
    inst: object   # target address, or the host's ctypes buffer


class TargetRunner:
    def __init__(self, target: Target):
        self.t = target

    def _sets(self, kind: str, arith: str, index: int) -> int:
        return self.t.read_u32(self.t.symbols[f"fw_sets_{kind}_{arith}"] + 4 * index)

    def new(self, arith: str, index: int, kind: str = "ctrl") -> Handle:
        size = self.t.read_u32(self.t.symbols["fw_sizes"] + 4 * SIZE_INDEX[(kind, arith)])
        inst = self.t.alloc(size)
        dbuf = self.t.alloc(DELAY_MAX * np.dtype(DTYPES[arith]).itemsize)
        st, _ = self.t.call(entry(kind, "init", arith), inst, self._sets(kind, arith, index),
                            dbuf, DELAY_MAX)
        if st != 0:
            raise RuntimeError(f"{entry(kind, 'init', arith)} returned {st}")
        return Handle(kind, arith, inst)

    def step(self, h: Handle, e):
        if h.arith == "q15":
            # AAPCS: the caller sign-extends an int16 argument to 32 bits.
            r0, _ = self.t.call(entry(h.kind, "step", "q15"), h.inst, int(e))
            return np.int16(np.uint16(r0 & 0xFFFF).view(np.int16))
        _, s0 = self.t.call(entry(h.kind, "step", "float"), h.inst, s0=float(np.float32(e)))
        return np.float32(s0)

    def run(self, h: Handle, e: np.ndarray) -> np.ndarray:
        dt = DTYPES[h.arith]
        e = np.asarray(e, dtype=dt)
        buf = self.t.alloc(2 * e.nbytes)
        self.t.write_array(buf, e)
        self.t.call(entry(h.kind, "run", h.arith), h.inst, buf, buf + e.nbytes, len(e))
        out = self.t.read_array(buf + e.nbytes, len(e), dt)
        self.t.free_to(buf)
        return out

    def reset(self, h: Handle) -> None:
        self.t.call(entry(h.kind, "reset", h.arith), h.inst)


class HostRunner:
    def __init__(self, library: Path, sets: Path):
        self.lib = C.CDLL(str(library))
        self.sets = C.CDLL(str(sets))
        self._keep = []
        for kind, arith in C_TYPES:
            et = C.c_int16 if arith == "q15" else C.c_float
            init = getattr(self.lib, entry(kind, "init", arith))
            init.argtypes = [C.c_void_p, C.c_void_p, C.c_void_p, C.c_size_t]
            init.restype = C.c_int
            step = getattr(self.lib, entry(kind, "step", arith))
            step.argtypes = [C.c_void_p, et]
            step.restype = et
            run = getattr(self.lib, entry(kind, "run", arith))
            run.argtypes = [C.c_void_p, C.c_void_p, C.c_void_p, C.c_size_t]
            run.restype = None
            getattr(self.lib, entry(kind, "reset", arith)).argtypes = [C.c_void_p]

    def new(self, arith: str, index: int, kind: str = "ctrl") -> Handle:
        size = (C.c_uint32 * len(C_TYPES)).in_dll(self.sets, "fw_sizes")[SIZE_INDEX[(kind, arith)]]
        table = C.c_void_p.in_dll(self.sets, f"fw_sets_{kind}_{arith}")
        coeffs = C.cast(C.addressof(table) + index * C.sizeof(C.c_void_p),
                        C.POINTER(C.c_void_p)).contents.value
        inst = C.create_string_buffer(size)
        dbuf = C.create_string_buffer(DELAY_MAX * np.dtype(DTYPES[arith]).itemsize)
        self._keep += [inst, dbuf]
        st = getattr(self.lib, entry(kind, "init", arith))(inst, coeffs, dbuf, DELAY_MAX)
        if st != 0:
            raise RuntimeError(f"{entry(kind, 'init', arith)} returned {st}")
        return Handle(kind, arith, inst)

    def step(self, h: Handle, e):
        v = int(e) if h.arith == "q15" else float(e)
        return DTYPES[h.arith](getattr(self.lib, entry(h.kind, "step", h.arith))(h.inst, v))

    def run(self, h: Handle, e: np.ndarray) -> np.ndarray:
        e = np.ascontiguousarray(e, dtype=DTYPES[h.arith])
        out = np.empty_like(e)
        getattr(self.lib, entry(h.kind, "run", h.arith))(h.inst, e.ctypes.data,
                                                          out.ctypes.data, len(e))
        return out

    def reset(self, h: Handle) -> None:
        getattr(self.lib, entry(h.kind, "reset", h.arith))(h.inst)


# The input of a cost measurement: a half-scale step (Q15 16384; float
# 0.5, with in_fs = 1), the case the paper's figures show. Costs barely
# depend on the data: only saturations and a normalising shift branch.
STEP = {"q15": 16384, "float": 0.5}


def step_costs(runner: TargetRunner, arith: str, index: int, samples: int,
               kind: str = "ctrl") -> list:
    """Cost (instructions, cycles, ...) of each of `samples` calls of the
    step function on a fresh instance of set `index`, fed a step."""
    h = runner.new(arith, index, kind)
    out = []
    for _ in range(samples):
        profile = runner.t.start_counting()
        runner.step(h, STEP[arith])
        runner.t.stop_counting()
        out.append(runner.t.cost(profile))
    return out

# SPDX-License-Identifier: MIT
"""One interface to a controller instance on the host build and on an
emulated core, so that a test drives both the same way and compares.

new(arith, index) binds coefficient set `index` of fw_sets_<arith>[] to a
fresh instance (pf_ctrl_init_*); step() and run() are pf_ctrl_step_* and
pf_ctrl_run_*; reset() is pf_ctrl_reset_*. Q15 values are int16, float
values float32.
"""
from __future__ import annotations

import ctypes as C
from pathlib import Path

import numpy as np

from .images import C_TYPES
from .target import Target

# Dead-time buffer given to every instance: at least the delay_len of any
# design used here (the library refuses a shorter one, PF_E_BUFFER).
DELAY_MAX = 1024
DTYPES = {"q15": np.int16, "float": np.float32}
SIZE_INDEX = {a: i for i, a in enumerate(C_TYPES)}


class TargetRunner:
    def __init__(self, target: Target):
        self.t = target

    def _sets(self, arith: str, index: int) -> int:
        return self.t.read_u32(self.t.symbols[f"fw_sets_{arith}"] + 4 * index)

    def new(self, arith: str, index: int) -> tuple[str, int]:
        size = self.t.read_u32(self.t.symbols["fw_sizes"] + 4 * SIZE_INDEX[arith])
        inst = self.t.alloc(size)
        dbuf = self.t.alloc(DELAY_MAX * np.dtype(DTYPES[arith]).itemsize)
        st, _ = self.t.call(f"pf_ctrl_init_{_sfx(arith)}", inst, self._sets(arith, index), dbuf,
                            DELAY_MAX)
        if st != 0:
            raise RuntimeError(f"pf_ctrl_init_{_sfx(arith)} returned {st}")
        return arith, inst

    def step(self, h, e):
        arith, inst = h
        if arith == "q15":
            # AAPCS: the caller sign-extends an int16 argument to 32 bits.
            r0, _ = self.t.call("pf_ctrl_step_q15", inst, int(e))
            return np.int16(np.uint16(r0 & 0xFFFF).view(np.int16))
        _, s0 = self.t.call("pf_ctrl_step_f32", inst, s0=float(np.float32(e)))
        return np.float32(s0)

    def run(self, h, e: np.ndarray) -> np.ndarray:
        arith, inst = h
        dt = DTYPES[arith]
        e = np.asarray(e, dtype=dt)
        buf = self.t.alloc(2 * e.nbytes)
        self.t.write_array(buf, e)
        self.t.call(f"pf_ctrl_run_{_sfx(arith)}", inst, buf, buf + e.nbytes, len(e))
        out = self.t.read_array(buf + e.nbytes, len(e), dt)
        self.t.free_to(buf)
        return out

    def reset(self, h) -> None:
        self.t.call(f"pf_ctrl_reset_{_sfx(h[0])}", h[1])


class HostRunner:
    def __init__(self, library: Path, sets: Path):
        self.lib = C.CDLL(str(library))
        self.sets = C.CDLL(str(sets))
        self._keep = []
        for arith, sfx in (("q15", "q15"), ("float", "f32")):
            et = C.c_int16 if arith == "q15" else C.c_float
            init = getattr(self.lib, f"pf_ctrl_init_{sfx}")
            init.argtypes = [C.c_void_p, C.c_void_p, C.c_void_p, C.c_size_t]
            init.restype = C.c_int
            step = getattr(self.lib, f"pf_ctrl_step_{sfx}")
            step.argtypes = [C.c_void_p, et]
            step.restype = et
            run = getattr(self.lib, f"pf_ctrl_run_{sfx}")
            run.argtypes = [C.c_void_p, C.c_void_p, C.c_void_p, C.c_size_t]
            run.restype = None
            getattr(self.lib, f"pf_ctrl_reset_{sfx}").argtypes = [C.c_void_p]

    def new(self, arith: str, index: int):
        size = (C.c_uint32 * len(C_TYPES)).in_dll(self.sets, "fw_sizes")[SIZE_INDEX[arith]]
        table = C.c_void_p.in_dll(self.sets, f"fw_sets_{arith}")
        coeffs = C.cast(C.addressof(table) + index * C.sizeof(C.c_void_p),
                        C.POINTER(C.c_void_p)).contents.value
        inst = C.create_string_buffer(size)
        dbuf = C.create_string_buffer(DELAY_MAX * np.dtype(DTYPES[arith]).itemsize)
        self._keep += [inst, dbuf]
        st = getattr(self.lib, f"pf_ctrl_init_{_sfx(arith)}")(inst, coeffs, dbuf, DELAY_MAX)
        if st != 0:
            raise RuntimeError(f"pf_ctrl_init_{_sfx(arith)} returned {st}")
        return arith, inst

    def step(self, h, e):
        arith, inst = h
        v = int(e) if arith == "q15" else float(e)
        return DTYPES[arith](getattr(self.lib, f"pf_ctrl_step_{_sfx(arith)}")(inst, v))

    def run(self, h, e: np.ndarray) -> np.ndarray:
        arith, inst = h
        e = np.ascontiguousarray(e, dtype=DTYPES[arith])
        out = np.empty_like(e)
        getattr(self.lib, f"pf_ctrl_run_{_sfx(arith)}")(inst, e.ctypes.data, out.ctypes.data, len(e))
        return out

    def reset(self, h) -> None:
        getattr(self.lib, f"pf_ctrl_reset_{_sfx(h[0])}")(h[1])


def _sfx(arith: str) -> str:
    return "q15" if arith == "q15" else "f32"


# The input of a cost measurement: a half-scale step (Q15 16384; float
# 0.5, with in_fs = 1), the case the paper's figures show. Costs barely
# depend on the data: only saturations and a normalising shift branch.
STEP = {"q15": 16384, "float": 0.5}


def step_costs(runner: TargetRunner, arith: str, index: int, samples: int) -> list:
    """Cost (instructions, cycles, ...) of each of `samples` calls of
    pf_ctrl_step_* on a fresh instance of set `index`, fed a step."""
    h = runner.new(arith, index)
    out = []
    for _ in range(samples):
        profile = runner.t.start_counting()
        runner.step(h, STEP[arith])
        runner.t.stop_counting()
        out.append(runner.t.cost(profile))
    return out

# SPDX-License-Identifier: MIT
"""Running a design in double, float or Q15: the library's own runtimes
(pf_runtime), so that Python gives the firmware's numbers bit for bit."""
from __future__ import annotations

import numpy as np

from . import binding

ARITHMETICS = ("double", "float", "q15")
Q15_ONE = 32768.0      # Q15: the full scale is 2^15 counts


def _scale(name: str, v) -> float:
    if v is None:
        return 0.0
    x = float(v)
    if not np.isfinite(x) or x <= 0.0:
        raise ValueError(f"{name}: {v!r} must be a positive number")
    return x


class Runtime:
    """One instance of a design's runtime in arithmetic @arith, at rest.

    double: pf_ctrl_f64; float: pf_ctrl_f32 (the input is rounded to float,
    every output is a float's value); q15: pf_ctrl_q15, integer only, with
    the input quantised as pf_q15_quantize(e, in_fs) and the output scaled
    back as p_c = pc_q15 * out_fs / 32768. in_fs and out_fs, the values of
    e and p_c that map to Q15 +1.0, are required for q15.

    run() continues from the present state, so a record may be fed in
    pieces; reset() returns to rest.
    """

    def __init__(self, design, arith: str = "double", *, in_fs: float | None = None,
                 out_fs: float | None = None):
        if arith not in ARITHMETICS:
            raise ValueError(f"arith: '{arith}' (known: {', '.join(ARITHMETICS)})")
        if arith == "q15" and (in_fs is None or out_fs is None):
            raise ValueError("q15 needs in_fs and out_fs (the full scales of e and p_c)")
        self.design = design
        self.arith = arith
        self.in_fs = _scale("in_fs", in_fs)
        self.out_fs = _scale("out_fs", out_fs)
        self._rt = binding.Runtime(design._buf, arith, self.in_fs, self.out_fs)

    def reset(self) -> None:
        """Back to rest."""
        self._rt.reset()

    def run(self, e) -> np.ndarray:
        """p_c (float64, physical units) for the samples of e (1-D)."""
        e = np.asarray(e, dtype=np.float64)
        if e.ndim != 1:
            raise ValueError(f"e must be 1-D, not of shape {e.shape}")
        return self._rt.run(e)

    def run_q15(self, e_q15) -> np.ndarray:
        """q15 only: raw Q15 input (int16 counts of in_fs) in, raw Q15
        output (int16 counts of out_fs) out, as firmware sees them."""
        if self.arith != "q15":
            raise ValueError("run_q15 is for the q15 runtime")
        q = np.asarray(e_q15)
        if q.ndim != 1 or not (np.issubdtype(q.dtype, np.integer) or q.size == 0):
            raise ValueError("e_q15 must be a 1-D array of integers")
        if q.size and (q.min() < -32768 or q.max() > 32767):
            raise ValueError("e_q15 holds values outside int16")
        # Counts to physical and back are exact: |q| <= 2^15, so the two
        # roundings of q * in_fs / 32768 / in_fs * 32768 stay far below 1/2
        # and pf_q15_quantize returns q; likewise for the output.
        pc = self._rt.run(q.astype(np.float64) * self.in_fs / Q15_ONE)
        return np.rint(pc / self.out_fs * Q15_ONE).astype(np.int16)


def simulate(design, e, arith: str = "double", *, in_fs: float | None = None,
             out_fs: float | None = None) -> np.ndarray:
    """p_c of @design for input @e (1-D, physical units), from rest, in
    double, float or q15 (see Runtime): numpy in, numpy out."""
    return Runtime(design, arith, in_fs=in_fs, out_fs=out_fs).run(e)

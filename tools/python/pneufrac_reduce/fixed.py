# SPDX-License-Identifier: MIT
"""A bank (pneufrac_reduce.realise) normalised and quantised for the
runtimes of lib pf_bank.h: the formats are defined there, in
pf_bank_coeffs_q15 and pf_bank_coeffs_f32.

Normalisation: each mode's state is scaled so that it stays within 0.98
of the input's full scale for any input within it (|beta| times the l1
norm of the mode's impulse response, or for a pair the bound |b|/(1 - |z|)
on both components), with the output gain a power of two 2^-m: the sign
and the rest of the gain sit in beta. No state can overflow and the Q15
output sum is shifts and adds.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from .realise import Bank

STATE_BOUND = 0.98
# Q15 scaling (pf_bank.h): a state is s 2^28, an input gain beta 2^29, the
# output sum acc = y 2^(28 - E) within 2^30, with out_q = 13 - E.
STATE_BITS, BETA_BITS, ACC_BITS = 28, 29, 30
OUT_Q_MAX = 13
MANT_BITS, V_BASE = 16, 46


class ScaleError(ValueError):
    """The bank does not fit the Q15 formats at these full scales."""


@dataclass
class Scaled:
    """A bank at one gain (input full scale / output full scale): per mode
    the input gains and the output exponent m (output gain 2^-m)."""
    d: float
    beta: np.ndarray         # real modes
    m: np.ndarray
    beta_pair: np.ndarray    # pairs, (n, 2)
    m_pair: np.ndarray


def _l1_real(lam: np.ndarray) -> np.ndarray:
    """l1 norm of lam (1 - lam)^n, n >= 0: the state's bound per unit input
    of a unit-DC section."""
    return lam / (1.0 - np.abs(1.0 - lam))


def scale(bank: Bank, gain: float) -> Scaled:
    """Normalise @bank with its output multiplied by @gain (Q15:
    in_fs/out_fs; float: 1)."""
    g = bank.beta * gain
    with np.errstate(divide="ignore"):
        m = np.floor(np.log2(STATE_BOUND / (np.abs(g) * _l1_real(bank.lam))))
    b = bank.pair_input() * gain
    rho = np.hypot(1.0 - bank.alpha, bank.omega)
    mp = np.floor(np.log2(STATE_BOUND * (1.0 - rho) / np.hypot(b[:, 0], b[:, 1])))
    return Scaled(d=bank.d * gain, beta=g * 2.0 ** m, m=m.astype(int),
                  beta_pair=bank.beta_pair * gain * (2.0 ** mp)[:, None], m_pair=mp.astype(int))


def _mant(x: float) -> tuple[int, int]:
    """x = mant 2^(v - 46), mant in [2^15, 2^16): (mant, v); ScaleError if
    v leaves [1, 31] (pf_bank.h)."""
    f, e = math.frexp(x)                      # x = f 2^e, f in [1/2, 1)
    mant, sh = round(f * 2 ** MANT_BITS), MANT_BITS - e
    if mant == 2 ** MANT_BITS:
        mant, sh = mant // 2, sh - 1
    v = V_BASE - sh
    if not 1 <= v <= 31:
        raise ScaleError(f"a pole distance {x:.3g} has no Q15 leak format")
    return mant, v


def q15(bank: Bank, in_fs: float, out_fs: float) -> dict:
    """The pf_bank_coeffs_q15 fields, as Python integers."""
    s = scale(bank, in_fs / out_fs)
    ms = np.concatenate([s.m, s.m_pair])
    total = STATE_BOUND * np.sum(2.0 ** -ms) + abs(s.d)
    e = max(0, int(-ms.min()) if len(ms) else 0,
            math.ceil(math.log2(total)) - (ACC_BITS - STATE_BITS) if total > 0 else 0)
    if e > OUT_Q_MAX - 1:
        raise ScaleError(f"the modes' outputs sum to {total:.3g} output full scales "
                         "before they cancel: raise --out-fs")
    d_m = round(s.d * 2.0 ** (BETA_BITS - e))
    if abs(d_m) >= 2 ** 31:
        raise ScaleError("the feedthrough exceeds the output range: raise --out-fs")

    def shift(m):
        # A mode whose output shift would pass 31 adds less than 2^-4 units
        # of the sum (2^-17 LSB): zero.
        return min(int(m) + e, 31)

    sec = []
    for lam, beta, m in zip(bank.lam, s.beta, s.m):
        mant, v = _mant(lam)
        sec.append({"beta": round(beta * 2 ** BETA_BITS), "lam_m": mant, "lam_v": v,
                    "out_sh": shift(m)})
    pair = []
    for al, om, bt, m in zip(bank.alpha, bank.omega, s.beta_pair, s.m_pair):
        am, av = _mant(al)
        wm, wv = _mant(om)
        pair.append({"beta1": round(bt[0] * 2 ** BETA_BITS), "beta2": round(bt[1] * 2 ** BETA_BITS),
                     "alpha_m": am, "alpha_v": av, "omega_m": wm, "omega_v": wv,
                     "out_sh": shift(m)})
    return {"n_sec": len(sec), "n_pair": len(pair), "out_q": OUT_Q_MAX - e, "d_m": d_m,
            "delay_len": bank.delay_len, "sec": sec, "pair": pair}


def f32(bank: Bank) -> dict:
    """The pf_bank_coeffs_f32 fields (physical units), as float32 values."""
    s = scale(bank, 1.0)
    f = np.float32
    sec = [{"lam": f(lam), "beta": f(b), "c": f(2.0 ** -m)}
           for lam, b, m in zip(bank.lam, s.beta, s.m)]
    pair = [{"alpha": f(al), "omega": f(om), "beta1": f(bt[0]), "beta2": f(bt[1]),
             "c": f(2.0 ** -m)}
            for al, om, bt, m in zip(bank.alpha, bank.omega, s.beta_pair, s.m_pair)]
    return {"n_sec": len(sec), "n_pair": len(pair), "d": f(s.d), "delay_len": bank.delay_len,
            "sec": sec, "pair": pair}

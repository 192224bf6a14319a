# SPDX-License-Identifier: MIT
"""The reduction rule: the fewest states whose step response stays within a
requested accuracy of the full design's over a requested horizon.

The full design is the library's (through ctypes, pneufrac.binding): its
state space is read off the double runtime (pf_ctrl_state_space), and the
reference the reduced system is measured against is that runtime's own
step response (pf_ctrl_run_f64), not the state space, so an error in
either shows. For r = 1, 2, ... the balanced realisation is cut to r states
(pneufrac_reduce.balance), put into bank form (pneufrac_reduce.realise) and
its step response from rest compared with the full one at every sample in
[t0, t1]; the first r whose largest difference, relative to the largest
|response| in that window, is within the tolerance is the answer. Orders
whose bank form the runtimes cannot hold are passed over.

The dead time is not reduced: the bank delays its output by the same
number of samples, exactly. Backlash, the nozzle curve and saturation act
inside the loop, so a design with any of them is refused: it has no linear
system to reduce (run the full controller, pf_ctrl_*).
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from pneufrac import binding

from .balance import Balanced, NotStable
from .realise import LAM_MIN, Bank, NotRealisable, realise

# pf_effects members of the effects inside the loop, and their names
IN_LOOP = {"backlash": "backlash", "nozzle_xh": "the nozzle curve", "saturate": "saturation"}
CHUNK = 1 << 16


class CannotReduce(ValueError):
    """The design has no reduced bank as requested (one line for the user)."""


@dataclass
class Reduction:
    bank: Bank
    full_order: int        # states of the full linear system
    hsv: np.ndarray        # Hankel singular values of its minimal part
    error: float           # max |step difference| / peak over the horizon
    error_before: float    # the same before t0, relative to the same peak
    peak: float            # max |full step response| over the horizon
    t_worst: float         # where the error peaks, s
    tried: list            # (order, error or the reason it was passed over)


class FullDesign:
    """The library's design (binding.DesignBuffer): its options (head.opt),
    its step or any response from rest in double, its state space."""

    def __init__(self, buf: binding.DesignBuffer):
        self.buf = buf
        self.head = buf.head

    def run(self, e) -> np.ndarray:
        """The double runtime's response to e, from rest."""
        return binding.Runtime(self.buf, "double").run(e)

    def state_space(self):
        return self.buf.state_space()


def design_buffer(config: str, fs: float, params: dict, effects: dict,
                  **opts) -> binding.DesignBuffer:
    """pf_ctrl_design_make through the binding; opts as pneufrac-reduce's
    request names them (input_model is pf_design_opts' input)."""
    fields = {("input" if k == "input_model" else k): v for k, v in opts.items()}
    return binding.DesignBuffer(config, params, effects, {"fs": fs, **fields})


def design(config: str, fs: float, params: dict, effects: dict, **opts) -> FullDesign:
    """The full design, without its dead time; CannotReduce with an in-loop
    effect, binding.ModelError for a parameter the library refuses."""
    on = [name for k, name in IN_LOOP.items() if effects.get(k)]
    if on:
        raise CannotReduce(f"{' and '.join(on)} sit{'s' if len(on) == 1 else ''} inside the "
                           "loop: no linear system to reduce (run the full controller, pf_ctrl_*)")
    linear = {k: v for k, v in effects.items() if k != "dead_time"}
    return FullDesign(design_buffer(config, fs, params, linear, **opts))


def _step_error(bank: Bank, y_full: np.ndarray, n0: int) -> np.ndarray:
    """|bank step - full step| at samples 0..len(y_full)-1 (in chunks)."""
    out = np.empty_like(y_full)
    for a in range(0, len(y_full), CHUNK):
        n = np.arange(a, min(a + CHUNK, len(y_full)))
        out[a:n[-1] + 1] = np.abs(bank.step(n) - y_full[a:n[-1] + 1])
    return out


def reduce_design(ctrl: FullDesign, fs: float, horizon=(0.0, 10.0), tol=5e-4,
                  method="residualise", max_order=None, delay_len=0) -> Reduction:
    t0, t1 = horizon
    n0, n1 = math.ceil(t0 * fs - 1e-9), math.floor(t1 * fs + 1e-9)
    if not 0 <= n0 < n1:
        raise CannotReduce(f"the horizon [{t0:g}, {t1:g}] s holds no samples at {fs:g} Hz")
    y_full = ctrl.run(np.ones(n1 + 1))
    peak = float(np.max(np.abs(y_full[n0:])))
    if not peak > 0.0:
        raise CannotReduce("the step response is zero over the horizon")
    a, b, c, d = ctrl.state_space()
    radius = float(np.max(np.abs(np.linalg.eigvals(a))))
    if not radius < 1.0 - LAM_MIN:
        raise CannotReduce(f"a pole at |z| = {radius:.12g}, within 2^-30 of the unit circle "
                           "(an integrating or unstable loop): run the full controller")
    try:
        bal = Balanced(a, b, c, d)
    except NotStable as exc:
        raise CannotReduce(f"the design is not strictly stable ({exc}): an integrating "
                           "or unstable loop has no balanced reduction") from None
    top = bal.order if max_order is None else min(max_order, bal.order)
    tried = []
    for r in range(1, top + 1):
        try:
            bank = realise(*bal.reduce(r, method), fs)
        except NotRealisable as exc:
            tried.append((r, str(exc)))
            continue
        err = _step_error(bank, y_full, n0) / peak
        worst = n0 + int(np.argmax(err[n0:]))
        tried.append((r, float(err[worst])))
        if err[worst] <= tol:
            bank.delay_len = int(delay_len)
            return Reduction(bank, len(b), bal.hsv, float(err[worst]),
                             float(err[:n0].max()) if n0 else 0.0, peak, worst / fs, tried)
    best = min((e for _, e in tried if isinstance(e, float)), default=None)
    raise CannotReduce(
        f"no order up to {top} keeps the step response within {tol:g} of its peak over "
        f"[{t0:g}, {t1:g}] s" + (f" (best {best:.3g})" if best is not None else ""))

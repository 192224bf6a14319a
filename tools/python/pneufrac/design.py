# SPDX-License-Identifier: MIT
"""design(): one of the paper's controllers, realised by the library at a
sample rate, as a Python object."""
from __future__ import annotations

import math

import numpy as np

from . import binding, lti

# The library's enum values of pf_approx and pf_input_model, by the CLI's
# names (--approx, --input-model); the parameter table lists them too.
APPROX = {"oustaloup": 0, "refined": 1}
INPUT_MODELS = {"hold": 0, "linear": 1}
# Effects that have no transfer function (pf_ctrl_freqresp and
# pf_ctrl_state_space leave them out; the CLI refuses them there too).
NONLINEAR = ("backlash", "nozzle_xh", "saturate")


def model_parameters() -> list[str]:
    """The paper's parameter names the library takes (pf_params)."""
    return [n for n, _ in binding.Params._fields_ if n != "topology"]


def effect_parameters() -> list[str]:
    """Effect parameter names (pf_effects; saturation is sat_lo with sat_hi,
    and saturate its placement, pf_sat_kind)."""
    return [n for n, _ in binding.Effects._fields_]


def _check_number(what: str, v) -> float:
    try:
        x = float(v)
    except (TypeError, ValueError):
        raise ValueError(f"{what}: {v!r} is not a number") from None
    if not math.isfinite(x):
        raise ValueError(f"{what}: {v!r} is not finite")
    return x


def _effects(effects: dict | None) -> dict:
    fx = dict(effects or {})
    names = effect_parameters()
    bad = [k for k in fx if k not in names]
    if bad:
        raise ValueError(f"unknown effect parameter '{bad[0]}' (known: {', '.join(names)})")
    out = {k: _check_number(f"effect {k}", v) for k, v in fx.items()}
    if ("sat_lo" in out) != ("sat_hi" in out):
        raise ValueError("saturation needs both sat_lo and sat_hi")
    if "saturate" in out:
        # the placement (the library's range judges the value); only with limits
        k = out["saturate"]
        if isinstance(fx["saturate"], bool) or not binding.whole_number(k):
            raise ValueError(f"effect saturate: {fx['saturate']!r} is not a whole number")
        if "sat_lo" not in out:
            raise ValueError("saturate needs sat_lo and sat_hi")
        out["saturate"] = int(k)
    elif "sat_lo" in out:
        out["saturate"] = binding.PF_SAT_CLIP
    return out


def _options(fs, band, order, approx, prewarp, t_slow, input_model) -> dict:
    o = {"fs": _check_number("fs", fs)}
    if band is not None:
        try:
            wb, wh = band
        except (TypeError, ValueError):
            raise ValueError(f"band: expected (wb, wh) in rad/s, got {band!r}") from None
        o["wb"], o["wh"] = _check_number("band wb", wb), _check_number("band wh", wh)
    if order is not None:
        n = _check_number("order", order)
        if isinstance(order, bool) or n != int(n):
            raise ValueError(f"order: {order!r} is not a whole number")
        o["order"] = int(n)
    if approx not in APPROX:
        raise ValueError(f"approx: '{approx}' (known: {', '.join(APPROX)})")
    if input_model not in INPUT_MODELS:
        raise ValueError(f"input_model: '{input_model}' (known: {', '.join(INPUT_MODELS)})")
    o["approx"], o["input"] = APPROX[approx], INPUT_MODELS[input_model]
    if prewarp is not None:
        o["prewarp"] = _check_number("prewarp", prewarp)
    if t_slow is not None:
        o["t_slow"] = _check_number("t_slow", t_slow)
    return o


def design(config: str, fs: float, *, effects: dict | None = None,
           band: tuple[float, float] | None = None, order: int | None = None,
           approx: str = "oustaloup", prewarp: float | None = None,
           t_slow: float | None = None, input_model: str = "hold",
           **params: float) -> "Design":
    """Design one of the paper's controllers at sample rate @fs (Hz).

    config: "p" (eq. 17), "dd" (FrDD, eq. 18), "id" (FrID, eq. 20) or
        "pid" (Remark 3, docs/pid.md).
    params: model parameters by the paper's names (a, b, k1, k2, A, ks,
        tau, pmin, pmax, beta, q, nu, w, RC, RCd, RCi), over the paper's
        example for the configuration; ranges: ``pneufrac.parameters()``.
    effects: {name: value} of backlash (dead-band width on the flapper
        displacement x), nozzle_xh, sat_lo with sat_hi (limits on p_c;
        saturate: 1 clipped after the relay, the default, 2 the relay's
        diaphragm stops there, or 3 the relay's output stops while its
        memory winds on, pf_effects.h), dead_time (s) and lag (s);
        absent or 0 means off.
    band: (wb, wh), the Oustaloup band in rad/s (default: from t_slow up
        to pi fs); order: Oustaloup N (default: from the band);
        approx: "oustaloup" or "refined"; prewarp: Tustin prewarp
        frequency, rad/s; t_slow: slowest time scale of interest, s
        (default 10); input_model: "hold" (samples held, as by a DAC) or
        "linear" (plain Tustin).

    Raises ValueError for a malformed argument, and binding.ModelError
    (a ValueError; .param names the parameter) for a value the library
    refuses. The options are keyword-only, so further ones can follow.
    """
    known = model_parameters()
    bad = [k for k in params if k not in known]
    if bad:
        raise ValueError(f"unknown model parameter '{bad[0]}' (the paper's names: "
                         f"{', '.join(known)})")
    p = {k: _check_number(k, v) for k, v in params.items()}
    opts = _options(fs, band, order, approx, prewarp, t_slow, input_model)
    if config not in ("p", "dd", "id", "pid"):
        raise ValueError(f"config: '{config}' (known: p, dd, id, pid)")
    return Design(binding.DesignBuffer(config, p, _effects(effects), opts))


def _name_of(table: dict, value: int) -> str:
    return next((k for k, v in table.items() if v == value), str(value))


class Design:
    """A controller designed by the library (pf_ctrl_design_make).

    Attributes: config, fs, params (every model parameter, resolved),
    effects (those on, library names), options (the design options as
    resolved: fs, wb, wh, order, approx, prewarp, t_slow, input), delay
    (the dead time in samples), linear (no backlash, nozzle curve or
    saturation).
    """

    def __init__(self, buf: binding.DesignBuffer):
        self._buf = buf
        h = buf.head
        self.config = binding.load().pf_topology_name(h.p.topology).decode()
        self.params = {n: getattr(h.p, n) for n in model_parameters()}
        fx = {n: getattr(h.fx, n) for n, _ in binding.Effects._fields_}
        kind = fx.pop("saturate")
        if not kind:
            fx.pop("sat_lo")
            fx.pop("sat_hi")
        self.effects = {k: v for k, v in fx.items() if v != 0.0 or k.startswith("sat_")}
        if kind not in (binding.PF_SAT_OFF, binding.PF_SAT_CLIP):   # the placement, if not the default
            self.effects["saturate"] = kind
        o = {n: getattr(h.opt, n) for n, _ in binding.DesignOpts._fields_}
        o["approx"] = _name_of(APPROX, o["approx"])
        o["input"] = _name_of(INPUT_MODELS, o["input"])
        self.options = o
        self.fs = o["fs"]
        self.delay = buf.delay_len
        self.linear = not (h.fx.backlash or h.fx.nozzle_xh or h.fx.saturate)

    def __repr__(self) -> str:
        fx = ", ".join(f"{k}={v:g}" for k, v in self.effects.items())
        return (f"<pneufrac.Design {self.config} at {self.fs:g} Hz, band "
                f"[{self.options['wb']:g}, {self.options['wh']:g}] rad/s, N = "
                f"{self.options['order']}{', ' + fx if fx else ''}>")

    # -- the linear controller -------------------------------------------
    def _require_linear(self, what: str) -> None:
        if not self.linear:
            raise ValueError(f"{what}: backlash, the nozzle curve and saturation are "
                             "nonlinear: no transfer function")

    def ss(self) -> lti.StateSpace:
        """The realised controller (held input and lag included) as a
        discrete state space in the runtime's own coordinates, dt = 1/fs.
        A dead time of D samples would add D states: ValueError; design
        without it and append z^-D (``delay``)."""
        self._require_linear("ss")
        if self.delay:
            raise ValueError(f"ss: a dead time of {self.delay} samples adds as many "
                             "states: design without it and append z^-D")
        a, b, c, d = self._buf.state_space(with_lag=True)
        return lti.StateSpace(a, b, c, d, 1.0 / self.fs)

    def zpk(self) -> lti.ZerosPolesGain:
        """Zeros, poles (roots) and gain of ss()."""
        return lti.zpk(self.ss())

    def sos(self) -> np.ndarray:
        """Second-order sections of zpk(), rows [b0, b1, b2, 1, a1, a2]
        (``scipy.signal.sosfilt``, ``sosfreqz``)."""
        return lti.sos(self.zpk())

    def freqresp(self, omega=None, points: int | None = None):
        """Ideal and realised frequency responses: see pneufrac.freqresp."""
        from .freqresp import freqresp
        return freqresp(self, omega, points)

    # -- running it --------------------------------------------------------
    def runtime(self, arith: str = "double", *, in_fs: float | None = None,
                out_fs: float | None = None):
        """A runtime of this design at rest: see pneufrac.Runtime."""
        from .runtime import Runtime
        return Runtime(self, arith, in_fs=in_fs, out_fs=out_fs)

    def simulate(self, e, arith: str = "double", *, in_fs: float | None = None,
                 out_fs: float | None = None) -> np.ndarray:
        """p_c for input e from rest: see pneufrac.simulate."""
        return self.runtime(arith, in_fs=in_fs, out_fs=out_fs).run(e)

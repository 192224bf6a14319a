# SPDX-License-Identifier: MIT
"""ctypes binding to libpneufrac: the one implementation of the model.

The structures mirror lib/include/pneufrac/*.h field by field (enums are C
int on the platforms we support). ``check_layout`` verifies the mirror
against values the library itself derives, so a header change that is not
mirrored here fails loudly instead of corrupting memory; the design and the
instance are also placed in buffers with generous slack.
"""
from __future__ import annotations

import ctypes as C
import os
from pathlib import Path

import numpy as np

PF_MAX_ORDER = 8
PF_MAX_SEC = 2 * PF_MAX_ORDER + 3
PF_MAX_INT = 2



class ParamSpec(C.Structure):
    """pf_param_spec: one row of the library's parameter table."""
    _fields_ = [("name", C.c_char_p), ("unit", C.c_char_p), ("desc", C.c_char_p),
                ("lo", C.c_double), ("hi", C.c_double), ("flags", C.c_uint),
                ("topologies", C.c_uint)]


class Params(C.Structure):
    _fields_ = [("config", C.c_int)] + [
        (n, C.c_double)
        for n in ("a", "b", "k1", "k2", "A", "ks", "tau", "pmin", "pmax",
                  "beta", "q", "nu", "w", "RC", "RCd", "RCi")
    ]


class Effects(C.Structure):
    _fields_ = [
        ("backlash", C.c_double), ("nozzle_xh", C.c_double),
        ("saturate", C.c_int), ("sat_lo", C.c_double), ("sat_hi", C.c_double),
        ("dead_time", C.c_double), ("lag", C.c_double),
    ]


class DesignOpts(C.Structure):
    _fields_ = [
        ("fs", C.c_double), ("wb", C.c_double), ("wh", C.c_double),
        ("order", C.c_int), ("approx", C.c_int), ("prewarp", C.c_double),
        ("t_slow", C.c_double), ("input", C.c_int),
    ]


class DesignHead(C.Structure):
    """The leading members of pf_ctrl_design: what was asked, as resolved.
    The coefficient set that follows (pf_ctrl_coeffs_f64) is not mirrored:
    it is internal detail that changes with the library, and this binding
    only passes its address on. Its offset is that of the next 8-aligned
    member after opt."""
    _fields_ = [("p", Params), ("fx", Effects), ("opt", DesignOpts)]


RT_OFFSET = (C.sizeof(DesignHead) + 7) // 8 * 8
# Generous buffers for the design and the instance, whose sizes are the
# library's business: both are a few kB (PF_MAX_ORDER = 8).
DESIGN_BYTES = 1 << 16
INSTANCE_BYTES = 1 << 16
# The library sizes the dead-time buffer as floor(dead_time*fs + 0.5)
# samples; a few spare elements cost nothing.
DELAY_SPARE = 8


class LibraryError(RuntimeError):
    """The shared library is missing or does not match this binding."""


class ModelError(ValueError):
    """The library refused a parameter set; .param names it."""

    def __init__(self, status: int, param: str | None, msg: str):
        super().__init__(msg)
        self.status = status
        self.param = param


def _candidates():
    env = os.environ.get("PNEUFRAC_LIBRARY")
    if env:
        yield Path(env)
        return
    here = Path(__file__).resolve()
    for up in here.parents:
        p = up / "build" / "lib" / "libpneufrac.so"
        if p.exists():
            yield p
            return
    import ctypes.util
    name = ctypes.util.find_library("pneufrac")
    if name:
        yield Path(name)


_lib = None


def load():
    """Load libpneufrac once (PNEUFRAC_LIBRARY overrides the search)."""
    global _lib
    if _lib is not None:
        return _lib
    tried = []
    for path in _candidates():
        tried.append(str(path))
        try:
            lib = C.CDLL(str(path))
            break
        except OSError as exc:
            tried[-1] += f" ({exc})"
    else:
        raise LibraryError(
            "libpneufrac.so not found (tried: %s); run ./scripts/setup.sh or "
            "set PNEUFRAC_LIBRARY" % (", ".join(tried) or "nothing"))
    lib.pf_params_default.argtypes = [C.POINTER(Params), C.c_int]
    lib.pf_params_default.restype = None
    lib.pf_design_opts_default.argtypes = [C.POINTER(DesignOpts), C.c_double]
    lib.pf_design_opts_default.restype = None
    lib.pf_ctrl_design_make.argtypes = [C.c_void_p, C.POINTER(Params),
                                        C.POINTER(Effects), C.POINTER(DesignOpts)]
    lib.pf_ctrl_design_make.restype = C.c_int
    lib.pf_ctrl_init_f64.argtypes = [C.c_void_p, C.c_void_p,
                                     C.POINTER(C.c_double), C.c_size_t]
    lib.pf_ctrl_init_f64.restype = C.c_int
    lib.pf_ctrl_reset_f64.argtypes = [C.c_void_p]
    lib.pf_ctrl_reset_f64.restype = None
    lib.pf_ctrl_run_f64.argtypes = [C.c_void_p, C.POINTER(C.c_double),
                                    C.POINTER(C.c_double), C.c_size_t]
    lib.pf_ctrl_run_f64.restype = None
    lib.pf_status_param.argtypes = [C.c_int]
    lib.pf_status_param.restype = C.c_int
    lib.pf_param_name.argtypes = [C.c_int]
    lib.pf_param_name.restype = C.c_char_p
    lib.pf_status_str.argtypes = [C.c_int]
    lib.pf_status_str.restype = C.c_char_p
    lib.pf_nozzle.argtypes = [C.c_double, C.c_double]
    lib.pf_nozzle.restype = C.c_double
    lib.pf_play.argtypes = [C.c_double, C.c_double, C.c_double]
    lib.pf_play.restype = C.c_double
    lib.pf_param_info.argtypes = [C.c_int]
    lib.pf_param_info.restype = C.POINTER(ParamSpec)
    lib.pf_param_count.argtypes = []
    lib.pf_param_count.restype = C.c_int
    lib.pf_param_lookup.argtypes = [C.c_char_p]
    lib.pf_param_lookup.restype = C.c_int
    lib.pf_param_used.argtypes = [C.c_int, C.c_int]
    lib.pf_param_used.restype = C.c_int
    lib.pf_config_name.argtypes = [C.c_int]
    lib.pf_config_name.restype = C.c_char_p
    lib.pf_config_lookup.argtypes = [C.c_char_p]
    lib.pf_config_lookup.restype = C.c_int
    check_layout(lib)
    _lib = lib          # cached only once the mirror is known to match
    return lib


def _layout_request(lib):
    """A valid design request with a distinct value in every mirrored field,
    so that a field read back from the wrong offset shows."""
    p = Params()
    lib.pf_params_default(C.byref(p), lib.pf_config_lookup(b"dd"))
    names = [n for n, _ in Params._fields_[1:]]
    for i, n in enumerate(names):      # shrink each a little, differently
        setattr(p, n, getattr(p, n) * (1.0 - 0.001 * (i + 1)))
    fx = Effects(backlash=0.5, nozzle_xh=0.25, saturate=1, sat_lo=-1.0,
                 sat_hi=2.0, dead_time=0.003, lag=0.01)
    o = DesignOpts()
    lib.pf_design_opts_default(C.byref(o), 1000.0)
    o.wb, o.wh, o.order, o.prewarp, o.t_slow = 0.0125, 2500.0, 4, 150.0, 7.5
    return p, fx, o


def check_layout(lib) -> None:
    """Design a known controller, read back every field the library stored
    of the request, and run it: if the mirror's offsets were wrong these
    checks would see garbage."""
    p, fx, o = _layout_request(lib)
    buf = C.create_string_buffer(DESIGN_BYTES)
    st = lib.pf_ctrl_design_make(buf, C.byref(p), C.byref(fx), C.byref(o))
    if st != 0:
        raise LibraryError(f"layout self-check: design refused (status {st})")
    d = DesignHead.from_buffer(buf)
    bad = [f"pf_params.{n}" for n, _ in Params._fields_ if getattr(d.p, n) != getattr(p, n)]
    bad += [f"pf_effects.{n}" for n, _ in Effects._fields_
            if getattr(d.fx, n) != getattr(fx, n)]
    bad += [f"pf_design_opts.{n}" for n, _ in DesignOpts._fields_
            if getattr(d.opt, n) != getattr(o, n)]
    ok = not bad
    if ok:
        fx0 = Effects(saturate=1, sat_lo=-1.0, sat_hi=2.0, dead_time=0.003)
        st = lib.pf_ctrl_design_make(buf, C.byref(p), C.byref(fx0), C.byref(o))
        inst = C.create_string_buffer(INSTANCE_BYTES)
        dbuf = (C.c_double * (3 + DELAY_SPARE))()
        if st == 0:
            st = lib.pf_ctrl_init_f64(inst, C.c_void_p(C.addressof(buf) + RT_OFFSET),
                                      dbuf, len(dbuf))
        e = np.ones(6)
        out = np.empty(6)
        dp = C.POINTER(C.c_double)
        if st == 0:
            lib.pf_ctrl_run_f64(inst, e.ctypes.data_as(dp), out.ctypes.data_as(dp), 6)
        ok = st == 0 and np.all(out[:3] == 0.0) and np.all(out[3:] > 0.0)
        if not ok:
            bad.append("pf_ctrl_design.rt (the run gave garbage)")
    if not ok:
        raise LibraryError(
            "libpneufrac does not match the ctypes mirror in pneufrac_fit/lib.py "
            f"(mismatch at {', '.join(bad[:4])}; pf_params, pf_effects, "
            "pf_design_opts or pf_ctrl_design changed?)")


def status_message(lib, st: int) -> tuple[str | None, str]:
    pid = lib.pf_status_param(st)
    name = lib.pf_param_name(pid).decode() if pid < lib.pf_param_count() else None
    text = lib.pf_status_str(st).decode()
    return name, (f"invalid parameter '{name}'" if name else text)


class ParamRange:
    """A parameter's row of the library's table (pf_param_info.h)."""

    def __init__(self, spec: ParamSpec):
        self.name = spec.name.decode()
        self.unit = spec.unit.decode()
        self.desc = spec.desc.decode()
        self.lo, self.hi = spec.lo, spec.hi
        self.lo_open = bool(spec.flags & PF_PARAM_LO_OPEN)
        self.hi_open = bool(spec.flags & PF_PARAM_HI_OPEN)

    def __contains__(self, v: float) -> bool:
        above = v > self.lo if self.lo_open else v >= self.lo
        below = v < self.hi if self.hi_open else v <= self.hi
        return above and below


# pf_param_spec.flags (pf_param_info.h)
PF_PARAM_LO_OPEN = 0x1
PF_PARAM_HI_OPEN = 0x2


def param_range(name: str) -> ParamRange:
    """The range, unit and description of a library parameter by name."""
    lib = load()
    pid = lib.pf_param_lookup(name.encode())
    if pid >= lib.pf_param_count():
        raise KeyError(f"the library has no parameter '{name}'")
    return ParamRange(lib.pf_param_info(pid).contents)


def config_id(config: str) -> int:
    """The library's number of a configuration name ("p", "dd", ...)."""
    lib = load()
    cid = lib.pf_config_lookup(config.encode())
    if lib.pf_config_name(cid) != config.encode():
        raise KeyError(f"the library has no configuration '{config}'")
    return cid


def param_used(config: str, name: str) -> bool:
    """Whether configuration @config uses model parameter @name."""
    lib = load()
    return bool(lib.pf_param_used(config_id(config), lib.pf_param_lookup(name.encode())))


def default_params(config: str) -> dict:
    lib = load()
    p = Params()
    lib.pf_params_default(C.byref(p), config_id(config))
    return {n: getattr(p, n) for n, _ in Params._fields_[1:]}


class Controller:
    """A designed controller (double runtime) that runs whole records."""

    def __init__(self, config: str, params: dict, effects: dict | None, fs: float,
                 order: int = 0, t_slow: float = 0.0, wh: float = 0.0):
        lib = load()
        self._lib = lib
        p = Params()
        lib.pf_params_default(C.byref(p), config_id(config))
        for k, v in params.items():
            setattr(p, k, float(v))
        fx = Effects()
        for k, v in (effects or {}).items():
            setattr(fx, k, int(v) if k == "saturate" else float(v))
        o = DesignOpts()
        lib.pf_design_opts_default(C.byref(o), float(fs))
        o.order = int(order)
        o.t_slow = float(t_slow)
        o.wh = float(wh)
        self._design = C.create_string_buffer(DESIGN_BYTES)
        st = lib.pf_ctrl_design_make(self._design, C.byref(p), C.byref(fx),
                                     C.byref(o))
        if st != 0:
            name, msg = status_message(lib, st)
            raise ModelError(st, name, msg)
        self.head = DesignHead.from_buffer(self._design)
        n = int(np.floor(fx.dead_time * self.head.opt.fs + 0.5)) + DELAY_SPARE
        self._delay = (C.c_double * n)()
        self._inst = C.create_string_buffer(INSTANCE_BYTES)
        st = lib.pf_ctrl_init_f64(self._inst,
                                  C.c_void_p(C.addressof(self._design) + RT_OFFSET),
                                  self._delay, n)
        if st != 0:
            name, msg = status_message(lib, st)
            raise ModelError(st, name, msg)

    def run(self, e: np.ndarray) -> np.ndarray:
        """Simulate from rest: one library call for the whole record."""
        e = np.ascontiguousarray(e, dtype=np.float64)
        out = np.empty_like(e)
        self._lib.pf_ctrl_reset_f64(self._inst)
        dp = C.POINTER(C.c_double)
        self._lib.pf_ctrl_run_f64(self._inst, e.ctypes.data_as(dp),
                                  out.ctypes.data_as(dp), e.size)
        return out


def simulate(config, params, effects, fs, e, **opts) -> np.ndarray:
    return Controller(config, params, effects, fs, **opts).run(e)

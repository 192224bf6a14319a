# SPDX-License-Identifier: MIT
"""ctypes binding to libpneufrac: the one implementation of the model, for
both the public API (the pneufrac package) and pneufrac-fit.

Nothing about the C side is restated here. The input structs (pf_params,
pf_effects, pf_design_opts and the head of pf_ctrl_design) are built at
load time from the library's own description of them (pf_field_get: each
member's name, offset, size and kind), the design and the instance are
allocated with the sizes it reports (pf_sizeof), and parameter names,
ranges and which configuration uses which come from its parameter table
(pf_param_info). ``check_layout`` then designs and runs a known controller,
so a binding that still disagrees fails loudly instead of corrupting
memory. Only pf_param_spec, the struct the table is read through, is
mirrored by hand, and its size is checked too.
"""
from __future__ import annotations

import ctypes as C
from pathlib import Path
from types import SimpleNamespace

import numpy as np

from . import locate


class ParamSpec(C.Structure):
    """pf_param_spec (pf_param_info.h): one row of the parameter table."""
    _fields_ = [("name", C.c_char_p), ("unit", C.c_char_p), ("desc", C.c_char_p),
                ("lo", C.c_double), ("hi", C.c_double), ("flags", C.c_uint),
                ("topologies", C.c_uint)]


class Field(C.Structure):
    """pf_field (pf_layout.h): one member of a public struct."""
    _fields_ = [("name", C.c_char_p), ("offset", C.c_size_t), ("size", C.c_size_t),
                ("kind", C.c_int), ("type", C.c_int)]


# pf_field_kind and pf_param_spec.flags (pf_layout.h, pf_param_info.h)
PF_FIELD_DOUBLE, PF_FIELD_INT, PF_FIELD_STRUCT = 0, 1, 2
PF_PARAM_LO_OPEN = 0x1
PF_PARAM_HI_OPEN = 0x2
# pf_sat_kind (pf_effects.h): pf_effects.saturate, where the supply limits
# act; its range is the parameter "saturate" of the library's table.
PF_SAT_OFF, PF_SAT_CLIP, PF_SAT_STOP, PF_SAT_WIND = 0, 1, 2, 3


class LibraryError(RuntimeError):
    """The shared library is missing or does not match this binding."""


class ModelError(ValueError):
    """The library refused a parameter set; .param names it."""

    def __init__(self, status: int, param: str | None, msg: str):
        super().__init__(msg)
        self.status = status
        self.param = param

    def __reduce__(self):
        # Rebuilt from all three: the default pickles args, (msg,) alone, and
        # a worker process whose refusal its parent cannot unpickle kills the
        # pool's result thread, so the parent waits for ever (a diagnosis's
        # rounds run in a process pool).
        return (type(self), (self.status, self.param, str(self)))


_lib = None
_layout = None      # the mirrors and sizes built from the loaded library
_path = None        # where the loaded library is

# Module attributes that exist once the library is loaded (PEP 562).
_LAYOUT_NAMES = ("Params", "Effects", "DesignOpts", "DesignHead", "RT_OFFSET",
                 "DESIGN_BYTES", "INSTANCE_BYTES", "RUNTIME_BYTES", "MAX_STATES")


def __getattr__(name):
    if name in _LAYOUT_NAMES:
        load()
        return getattr(_layout, name)
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")


def _declare(lib) -> None:
    """Argument and result types of every function this binding calls."""
    vp, i, d, sz, cp = C.c_void_p, C.c_int, C.c_double, C.c_size_t, C.c_char_p
    for name, args, res in [
        ("pf_params_default", [vp, i], None),
        ("pf_design_opts_default", [vp, d], None),
        ("pf_ctrl_design_make", [vp, vp, vp, vp], i),
        ("pf_ctrl_design_delay_len", [vp], sz),
        ("pf_ctrl_init_f64", [vp, vp, C.POINTER(d), sz], i),
        ("pf_ctrl_reset_f64", [vp], None),
        ("pf_ctrl_run_f64", [vp, C.POINTER(d), C.POINTER(d), sz], None),
        ("pf_ctrl_limited_f64", [vp], C.c_uint32),
        ("pf_ctrl_freqresp", [vp, d, C.POINTER(d), C.POINTER(d)], None),
        ("pf_ctrl_state_space", [vp, i, C.POINTER(d), C.POINTER(d), C.POINTER(d),
                                 C.POINTER(d)], i),
        ("pf_runtime_init", [vp, vp, i, d, d, vp, sz], i),
        ("pf_runtime_reset", [vp], None),
        ("pf_runtime_run", [vp, C.POINTER(d), C.POINTER(d), sz], None),
        ("pf_arith_lookup", [cp], i),
        ("pf_arith_name", [i], cp),
        ("pf_arith_sample_size", [i], sz),
        ("pf_status_param", [i], i),
        ("pf_status_str", [i], cp),
        ("pf_param_name", [i], cp),
        ("pf_param_info", [i], C.POINTER(ParamSpec)),
        ("pf_param_count", [], i),
        ("pf_param_lookup", [cp], i),
        ("pf_param_used", [i, i], i),
        ("pf_topology_name", [i], cp),
        ("pf_topology_lookup", [cp], i),
        ("pf_nozzle", [d, d], d),
        ("pf_play", [d, d, d], d),
        ("pf_type_name", [i], cp),
        ("pf_sizeof", [i], sz),
        ("pf_field_get", [i, i, C.POINTER(Field)], i),
        ("pf_bank_max_order", [], i),
    ]:
        f = getattr(lib, name)
        f.argtypes = args
        f.restype = res


def _types(lib) -> dict:
    """pf_type numbers by C name ("pf_params" -> 0, ...)."""
    out, t = {}, 0
    while (name := lib.pf_type_name(t)) != b"?":
        out[name.decode()] = t
        t += 1
    return out


def _mirror(lib, types: dict, cname: str, built: dict, skip=()):
    """A ctypes Structure of C struct @cname from the library's member list;
    LibraryError if ctypes does not lay it out as the compiler did."""
    t = types[cname]
    fields, want, i, f = [], [], 0, Field()
    while lib.pf_field_get(t, i, C.byref(f)) == 0:
        i += 1
        name = f.name.decode()
        if name in skip:
            continue
        if f.kind == PF_FIELD_DOUBLE and f.size == C.sizeof(C.c_double):
            ctype = C.c_double
        elif f.kind == PF_FIELD_INT and f.size == C.sizeof(C.c_int):
            ctype = C.c_int
        elif f.kind == PF_FIELD_STRUCT and lib.pf_type_name(f.type).decode() in built:
            ctype = built[lib.pf_type_name(f.type).decode()]
        else:
            raise LibraryError(f"{cname}.{name}: a member this binding cannot mirror")
        fields.append((name, ctype))
        want.append((name, f.offset))
    cls = type(cname, (C.Structure,), {"_fields_": fields})
    bad = [n for n, off in want if getattr(cls, n).offset != off]
    if bad or not fields:
        raise LibraryError(f"{cname}: ctypes lays out {bad or 'nothing'} unlike the library")
    if not skip and C.sizeof(cls) != lib.pf_sizeof(t):
        raise LibraryError(f"{cname}: {C.sizeof(cls)} bytes in ctypes, "
                           f"{lib.pf_sizeof(t)} in the library")
    return cls


def _build_layout(lib) -> SimpleNamespace:
    types = _types(lib)
    if C.sizeof(ParamSpec) != lib.pf_sizeof(types["pf_param_spec"]):
        raise LibraryError("pf_param_spec: the hand mirror's size differs")
    built = {}
    for cname in ("pf_params", "pf_effects", "pf_design_opts"):
        built[cname] = _mirror(lib, types, cname, built)
    # The head of the design: what was asked, as resolved. The coefficient
    # set after it is the library's business; only its offset is used.
    head = _mirror(lib, types, "pf_ctrl_design", built, skip=("rt",))
    f, i, rt = Field(), 0, None
    while lib.pf_field_get(types["pf_ctrl_design"], i, C.byref(f)) == 0:
        rt = f.offset if f.name == b"rt" else rt
        i += 1
    if rt is None:
        raise LibraryError("pf_ctrl_design has no member rt")
    instance = lib.pf_sizeof(types["pf_ctrl_f64"])
    return SimpleNamespace(
        Params=built["pf_params"], Effects=built["pf_effects"],
        DesignOpts=built["pf_design_opts"], DesignHead=head, RT_OFFSET=rt,
        DESIGN_BYTES=lib.pf_sizeof(types["pf_ctrl_design"]),
        INSTANCE_BYTES=instance, RUNTIME_BYTES=lib.pf_sizeof(types["pf_runtime"]),
        # Every state of the linear runtime (pf_ctrl_state_space) is a double
        # of the double runtime's instance, so this bounds their number
        # without restating PF_CTRL_MAX_STATES.
        MAX_STATES=instance // C.sizeof(C.c_double))


def load():
    """Load libpneufrac once, from the first place of locate.candidates()
    where it loads; LibraryError if none, or if it does not match."""
    global _lib, _layout, _path
    if _lib is not None:
        return _lib
    tried = []
    for path in locate.candidates():
        tried.append(str(path))
        try:
            lib = C.CDLL(str(path))
            break
        except OSError as exc:
            tried[-1] += f" ({exc})"
    else:
        raise LibraryError(
            "libpneufrac.so not found (%s); run ./scripts/setup.sh, or set "
            "PNEUFRAC_PREFIX to the prefix of `cmake --install` or PNEUFRAC_LIBRARY "
            "to the file" % ("tried: " + ", ".join(tried) if tried
                             else "searched " + locate.searched()))
    try:
        _declare(lib)
    except AttributeError as exc:
        raise LibraryError(f"libpneufrac lacks a function this binding needs ({exc})")
    _layout = _build_layout(lib)
    check_layout(lib)
    _lib = lib          # cached only once the mirror is known to match
    _path = Path(path)
    return lib


def library_path() -> Path:
    """The file of the loaded library (loading it if needed)."""
    load()
    return _path


def _layout_request(lib):
    """A valid design request with a distinct value in every mirrored field,
    so that a field read back from the wrong offset shows."""
    m = _layout
    p = m.Params()
    lib.pf_params_default(C.byref(p), lib.pf_topology_lookup(b"dd"))
    names = [n for n, _ in m.Params._fields_[1:]]
    for i, n in enumerate(names):      # shrink each a little, differently
        setattr(p, n, getattr(p, n) * (1.0 - 0.001 * (i + 1)))
    fx = m.Effects(backlash=0.5, nozzle_xh=0.25, saturate=1, sat_lo=-1.0,
                   sat_hi=2.0, dead_time=0.003, lag=0.01)
    o = m.DesignOpts()
    lib.pf_design_opts_default(C.byref(o), 1000.0)
    o.wb, o.wh, o.order, o.prewarp, o.t_slow = 0.0125, 2500.0, 4, 150.0, 7.5
    return p, fx, o


def check_layout(lib) -> None:
    """Design a known controller, read back every field the library stored
    of the request, and run it: if the mirror's offsets were wrong these
    checks would see garbage."""
    m = _layout
    p, fx, o = _layout_request(lib)
    buf = C.create_string_buffer(m.DESIGN_BYTES)
    st = lib.pf_ctrl_design_make(buf, C.byref(p), C.byref(fx), C.byref(o))
    if st != 0:
        raise LibraryError(f"layout self-check: design refused (status {st})")
    d = m.DesignHead.from_buffer(buf)
    bad = [f"pf_params.{n}" for n, _ in m.Params._fields_ if getattr(d.p, n) != getattr(p, n)]
    bad += [f"pf_effects.{n}" for n, _ in m.Effects._fields_
            if getattr(d.fx, n) != getattr(fx, n)]
    bad += [f"pf_design_opts.{n}" for n, _ in m.DesignOpts._fields_
            if getattr(d.opt, n) != getattr(o, n)]
    ok = not bad
    if ok:
        fx0 = m.Effects(saturate=1, sat_lo=-1.0, sat_hi=2.0, dead_time=0.003)
        st = lib.pf_ctrl_design_make(buf, C.byref(p), C.byref(fx0), C.byref(o))
        inst = C.create_string_buffer(m.INSTANCE_BYTES)
        dlen = lib.pf_ctrl_design_delay_len(buf)
        dbuf = (C.c_double * max(dlen, 1))()
        if st == 0:
            st = lib.pf_ctrl_init_f64(inst, C.c_void_p(C.addressof(buf) + m.RT_OFFSET),
                                      dbuf, dlen)
        e = np.ones(6)
        out = np.empty(6)
        dp = C.POINTER(C.c_double)
        if st == 0:
            lib.pf_ctrl_run_f64(inst, e.ctypes.data_as(dp), out.ctypes.data_as(dp), 6)
        ok = st == 0 and dlen == 3 and np.all(out[:3] == 0.0) and np.all(out[3:] > 0.0)
        if not ok:
            bad.append("pf_ctrl_design.rt (the run gave garbage)")
    if not ok:
        raise LibraryError(
            "libpneufrac does not match the ctypes mirror in pneufrac/binding.py "
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



def param_range(name: str) -> ParamRange:
    """The range, unit and description of a library parameter by name."""
    lib = load()
    pid = lib.pf_param_lookup(name.encode())
    if pid >= lib.pf_param_count():
        raise KeyError(f"the library has no parameter '{name}'")
    return ParamRange(lib.pf_param_info(pid).contents)


def _enum_id(lookup, name_of, name: str, what: str) -> int:
    """The library's number of @name by its lookup function, checked by its
    name function (an unknown name looks up to the count, named "?")."""
    v = lookup(name.encode())
    if name_of(v) != name.encode():
        raise KeyError(f"the library has no {what} '{name}'")
    return v


def config_id(config: str) -> int:
    """The library's number of a configuration name ("p", "dd", ...)."""
    lib = load()
    v = _config_ids.get(config)
    if v is None:
        v = _config_ids[config] = _enum_id(lib.pf_topology_lookup, lib.pf_topology_name,
                                          config, "configuration")
    return v


# config_id's answers: the library's table of configurations is fixed once
# it is loaded, and every controller made asks (two ctypes calls and a
# comparison, about 1 % of a fit's Python side); a name it refuses is not
# kept, so it is refused again.
_config_ids: dict = {}


def param_used(config: str, name: str) -> bool:
    """Whether configuration @config uses model parameter @name."""
    lib = load()
    return bool(lib.pf_param_used(config_id(config), lib.pf_param_lookup(name.encode())))


def default_params(config: str) -> dict:
    lib = load()
    p = _layout.Params()
    lib.pf_params_default(C.byref(p), config_id(config))
    return {n: getattr(p, n) for n, _ in _layout.Params._fields_[1:]}


def _alloc(nbytes: int):
    """Zeroed memory for a library struct, aligned for doubles and pointers
    (pf_layout.h: none needs more than malloc's alignment)."""
    return (C.c_uint64 * max(1, (nbytes + 7) // 8))()


def whole_number(v) -> bool:
    """v is a number with no fractional part (not a bool or a string)."""
    if isinstance(v, (bool, str, bytes)):
        return False
    try:
        return float(v) == int(v)
    except (TypeError, ValueError, OverflowError):
        return False


def _field_types(cls) -> dict:
    """{member name: ctypes type} of a mirrored struct class, made once per
    class (a controller is made for every simulation of a fit, and each
    fills three structs)."""
    got = _FIELD_TYPES.get(cls)
    if got is None:
        got = _FIELD_TYPES[cls] = dict(cls._fields_)
    return got


_FIELD_TYPES: dict = {}


def _fill(struct, values: dict, what: str) -> None:
    """Set fields of a mirrored struct by name; a name it lacks is an
    error (ctypes would quietly add an attribute instead)."""
    types = _field_types(type(struct))
    for k, v in values.items():
        if k not in types:
            raise KeyError(f"{what} has no field '{k}'")
        if types[k] is C.c_int:
            # int() would truncate 2.5 to 2 and ctypes wrap an int that does
            # not fit round, both silently: a placement or an order asked
            # for must be the one the library gets.
            if not whole_number(v):
                raise ValueError(f"{what}.{k}: {v!r} is not a whole number")
            if not -2**31 <= int(v) < 2**31:
                raise ValueError(f"{what}.{k}: {v} does not fit an int")
            setattr(struct, k, int(v))
        else:
            setattr(struct, k, float(v))


class DesignBuffer:
    """A pf_ctrl_design the library made (pf_ctrl_design_make), in memory
    owned here: @params are pf_params fields by the paper's names (over the
    configuration's defaults), @effects pf_effects fields, @opts
    pf_design_opts fields (fs required; the rest over
    pf_design_opts_default). ModelError names a parameter it refuses."""

    def __init__(self, config: str, params: dict | None, effects: dict | None, opts: dict):
        lib = load()
        m = _layout
        self._lib = lib
        p = m.Params()
        lib.pf_params_default(C.byref(p), config_id(config))
        if "topology" in (params or {}):
            raise KeyError("the configuration is the config argument, not a parameter")
        _fill(p, params or {}, "pf_params")
        fx = m.Effects()
        _fill(fx, effects or {}, "pf_effects")
        o = m.DesignOpts()
        lib.pf_design_opts_default(C.byref(o), float(opts["fs"]))
        _fill(o, opts, "pf_design_opts")
        self._buf = _alloc(m.DESIGN_BYTES)
        st = lib.pf_ctrl_design_make(self._buf, C.byref(p), C.byref(fx), C.byref(o))
        if st != 0:
            name, msg = status_message(lib, st)
            raise ModelError(st, name, msg)
        self.head = m.DesignHead.from_buffer(self._buf)
        self.rt = C.c_void_p(C.addressof(self._buf) + m.RT_OFFSET)
        self.delay_len = int(lib.pf_ctrl_design_delay_len(self._buf))

    @property
    def ptr(self):
        return self._buf

    def freqresp(self, omega) -> np.ndarray:
        """P_c/E of the realised controller at z = exp(j omega/fs)
        (pf_ctrl_freqresp), omega in rad/s, any shape."""
        w = np.asarray(omega, dtype=float)
        out = np.empty(w.shape, dtype=complex)
        re, im = C.c_double(), C.c_double()
        for i, x in np.ndenumerate(w):
            self._lib.pf_ctrl_freqresp(self._buf, float(x), C.byref(re), C.byref(im))
            out[i] = complex(re.value, im.value)
        return out

    def state_space(self, with_lag: bool = True):
        """(A, B, C, D) of the linear runtime (pf_ctrl_state_space), as
        arrays of shapes (n, n), (n, 1), (1, n), (1, 1)."""
        nmax = _layout.MAX_STATES
        a = np.zeros(nmax * nmax)
        b, c, d = np.zeros(nmax), np.zeros(nmax), np.zeros(1)
        dp = C.POINTER(C.c_double)
        n = self._lib.pf_ctrl_state_space(self._buf, int(bool(with_lag)),
                                          a.ctypes.data_as(dp), b.ctypes.data_as(dp),
                                          c.ctypes.data_as(dp), d.ctypes.data_as(dp))
        if not 1 <= n <= nmax:
            raise LibraryError(f"pf_ctrl_state_space gave {n} states (room for {nmax})")
        return (a[:n * n].reshape(n, n).copy(), b[:n].reshape(n, 1).copy(),
                c[:n].reshape(1, n).copy(), d.reshape(1, 1))


def arith_id(name: str) -> int:
    """The library's number of an arithmetic ("double", "float", "q15")."""
    lib = load()
    return _enum_id(lib.pf_arith_lookup, lib.pf_arith_name, name, "arithmetic")


class Runtime:
    """A runtime of any arithmetic (pf_runtime) bound to a DesignBuffer, at
    rest. in_fs and out_fs are the Q15 full scales (required for q15)."""

    def __init__(self, design: DesignBuffer, arith: str = "double", in_fs: float = 0.0,
                 out_fs: float = 0.0):
        lib = load()
        self._lib = lib
        self.design = design            # the double runtime uses its coefficients
        self.arith = arith
        a = arith_id(arith)
        n = design.delay_len
        self._dbuf = _alloc(lib.pf_arith_sample_size(a) * n)
        self._S = _alloc(_layout.RUNTIME_BYTES)
        st = lib.pf_runtime_init(self._S, design.ptr, a, float(in_fs), float(out_fs),
                                 self._dbuf if n else None, n)
        if st != 0:
            name, msg = status_message(lib, st)
            raise ModelError(st, name, msg)

    def reset(self) -> None:
        self._lib.pf_runtime_reset(self._S)

    def run(self, e) -> np.ndarray:
        """p_c for input e (physical units), continuing from the present
        state: one library call for the block."""
        e = np.ascontiguousarray(e, dtype=np.float64)
        out = np.empty_like(e)
        dp = C.POINTER(C.c_double)
        self._lib.pf_runtime_run(self._S, e.ctypes.data_as(dp), out.ctypes.data_as(dp),
                                 e.size)
        return out


class Controller:
    """A designed controller (double runtime) that runs whole records."""

    def __init__(self, config: str, params: dict, effects: dict | None, fs: float,
                 order: int = 0, t_slow: float = 0.0, wh: float = 0.0):
        self.design = DesignBuffer(config, params, effects,
                                   {"fs": fs, "order": order, "t_slow": t_slow, "wh": wh})
        self.head = self.design.head
        self._lib = lib = self.design._lib
        n = self.design.delay_len
        self._delay = (C.c_double * max(n, 1))()
        self._inst = _alloc(_layout.INSTANCE_BYTES)
        st = lib.pf_ctrl_init_f64(self._inst, self.design.rt, self._delay, n)
        if st != 0:
            name, msg = status_message(lib, st)
            raise ModelError(st, name, msg)
        self.limited = 0

    def run(self, e: np.ndarray) -> np.ndarray:
        """Simulate from rest: one library call for the whole record (the
        typed double runtime, pf_ctrl_run_f64: the fits call this often).
        Afterwards `limited` is the number of samples on which the supply
        limits acted on the relay (pf_ctrl_f64.limited)."""
        e = np.ascontiguousarray(e, dtype=np.float64)
        out = np.empty_like(e)
        self._lib.pf_ctrl_reset_f64(self._inst)
        dp = C.POINTER(C.c_double)
        self._lib.pf_ctrl_run_f64(self._inst, e.ctypes.data_as(dp),
                                  out.ctypes.data_as(dp), e.size)
        self.limited = int(self._lib.pf_ctrl_limited_f64(self._inst))
        return out


def simulate(config, params, effects, fs, e, **opts) -> np.ndarray:
    return Controller(config, params, effects, fs, **opts).run(e)

# SPDX-License-Identifier: MIT
"""The library's parameter table (pf_param_info) as Python rows."""
from __future__ import annotations

from . import binding

CONFIGS = ("p", "dd", "id", "pid")


def parameters() -> list[dict]:
    """Every parameter the library knows, in its table's order: name, unit,
    lo, hi (with lo_open/hi_open), description, and for model parameters
    the configurations that use it. ``pandas.DataFrame(parameters())``
    shows them as a table."""
    lib = binding.load()
    rows = []
    for pid in range(lib.pf_param_count()):
        r = binding.ParamRange(lib.pf_param_info(pid).contents)
        used = [c for c in CONFIGS if lib.pf_param_used(binding.config_id(c), pid)]
        rows.append({"name": r.name, "unit": r.unit, "lo": r.lo, "hi": r.hi,
                     "lo_open": r.lo_open, "hi_open": r.hi_open,
                     "description": r.desc, "configs": used})
    return rows

# SPDX-License-Identifier: MIT
"""pneufrac: the paper's fractional-order pneumatic controllers in Python.

Every number comes from the C library (libpneufrac, through ctypes): the
design, the double, float and Q15 runtimes (bit for bit what firmware
computes), the realised frequency response and state space.

    import numpy as np, pneufrac
    d = pneufrac.design("dd", fs=20000, tau=0.002, effects={"lag": 0.01})
    pc = pneufrac.simulate(d, np.ones(2000))                   # double
    pq = pneufrac.simulate(d, np.ones(2000), "q15", in_fs=1, out_fs=20)
    fr = pneufrac.freqresp(d)          # ideal and realised; .to_frame()
    A, B, C, D, dt = d.ss()            # also d.zpk(), d.sos()
    dx = pneufrac.diagnose("record.csv", "dd")   # measured data; .to_frame()
    fig = pneufrac.plots.bode(fr)      # matplotlib Figures, never files

docs/python.md is the guide; each function's docstring its reference.
"""
__version__ = "0.1.0"

from .binding import LibraryError, ModelError, library_path  # noqa: E402
from .design import Design, design  # noqa: E402
from .freqresp import FreqResp, freqresp  # noqa: E402
from .lti import StateSpace, ZerosPolesGain  # noqa: E402
from .runtime import Runtime, simulate  # noqa: E402
from .table import parameters  # noqa: E402


def diagnose(data, config: str, **options):
    """Diagnose a measured record against the model: see
    pneufrac.diagnosis.diagnose (imported on first use: it brings the
    fitting machinery of pneufrac-fit)."""
    from .diagnosis import diagnose as _diagnose
    return _diagnose(data, config, **options)


def __getattr__(name):
    # Submodules with heavier imports (matplotlib, pneufrac-fit), loaded
    # when first used: pneufrac.plots, pneufrac.diagnosis.
    if name in ("plots", "diagnosis"):
        import importlib
        return importlib.import_module(f".{name}", __name__)
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")


__all__ = ["Design", "FreqResp", "LibraryError", "ModelError", "Runtime", "StateSpace",
           "ZerosPolesGain", "design", "diagnose", "freqresp", "library_path",
           "parameters", "simulate"]

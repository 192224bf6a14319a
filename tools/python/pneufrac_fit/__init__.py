# SPDX-License-Identifier: MIT
"""pneufrac-fit: compare measured controller data with the paper's model,
name what it gets wrong, extend it with the library's effect blocks."""
import os as _os
import sys as _sys

# The fits are many small least-squares problems: BLAS threads only fight
# each other (and the worker processes) for the cores. Set before numpy
# loads; an explicit setting by the user wins.
for _v in ("OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS", "MKL_NUM_THREADS"):
    _os.environ.setdefault(_v, "1")

# The ctypes binding is the pneufrac package's (one binding for both); it
# keeps its old name here, pneufrac_fit.lib, for the modules that use it.
from pneufrac import __version__  # noqa: E402
from pneufrac import binding as lib  # noqa: E402

_sys.modules[__name__ + ".lib"] = lib

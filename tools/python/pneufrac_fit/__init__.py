# SPDX-License-Identifier: MIT
"""pneufrac-fit: compare measured controller data with the paper's model,
name what it gets wrong, extend it with the library's effect blocks."""
import os as _os

# The fits are many small least-squares problems: BLAS threads only fight
# each other (and the worker processes) for the cores. Set before numpy
# loads; an explicit setting by the user wins.
for _v in ("OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS", "MKL_NUM_THREADS"):
    _os.environ.setdefault(_v, "1")

__version__ = "0.1.0"

# SPDX-License-Identifier: MIT
import os
import sys
from pathlib import Path

for v in ("OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ.setdefault(v, "1")
ROOT = Path(__file__).resolve().parents[2]
os.environ.setdefault("PNEUFRAC_LIBRARY", str(ROOT / "build" / "lib" / "libpneufrac.so"))
sys.path.insert(0, str(Path(__file__).resolve().parent))
try:
    import pneufrac_fit  # noqa: F401  (installed by scripts/setup.sh)
except ImportError:
    sys.path.insert(0, str(ROOT / "tools" / "python"))

# The build the tests check against (scripts/test.sh sets PNEUFRAC_BUILD_DIR).
BUILD = Path(os.environ.get("PNEUFRAC_BUILD_DIR", str(ROOT / "build")))
CLI = BUILD / "tools" / "pneufrac"


import pytest  # noqa: E402


@pytest.fixture(autouse=True)
def _no_answers_from_an_earlier_test():
    """The fit's caches (whole fits, freed corners) live for the process:
    each test starts without them, so that a test that patches the
    simulation or counts it is not answered from another test's fits."""
    try:
        from pneufrac_fit import candidates, fit
    except ImportError:          # a test of another package
        yield
        return
    fit._FITS.clear()
    candidates._CORNERS.clear()
    yield

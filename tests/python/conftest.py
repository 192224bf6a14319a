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

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


# Files whose tests share a session-scoped fixture, by the fixture: under
# pytest-xdist's --dist loadfile (scripts/test.sh) each file goes to one
# worker, and a session fixture is computed once per worker; the files
# named here go to one worker together, so it is computed once.
SHARED = {"lag_real_1": ("test_baseline_corner.py", "test_interval_notes.py")}


# optionalhook: a run without pytest-xdist (plain `pytest`, or `-p
# no:xdist`) does not know the hook, and would stop at collection
@pytest.hookimpl(optionalhook=True)
def pytest_xdist_make_scheduler(config, log):
    """--dist loadfile, with the files of one SHARED entry one unit of work
    (xdist's LoadFileScheduling takes a test's file as its unit, from the
    test's id). --dist loadgroup would say the same with marks, but with
    pytest 9 it no longer groups (xdist 3.8 renames the test ids through an
    attribute pytest 9 does not read), so the files are named here."""
    if config.getvalue("dist") != "loadfile":
        return None
    from xdist.scheduler import LoadFileScheduling
    unit = {name: fixture for fixture, names in SHARED.items() for name in names}

    class SharedFiles(LoadFileScheduling):
        def _split_scope(self, nodeid):
            path = nodeid.split("::", 1)[0]
            return unit.get(Path(path).name, path)
    return SharedFiles(config, log)


@pytest.fixture(scope="session")
def lag_real_1():
    """The diagnosis of the independent simulator's lag-real seed 1 (dd,
    two steps, AR(1) noise, a 24 ms lag; its baseline ends with rho, beta
    and q at bounds), for the files of SHARED["lag_real_1"]. Its tests only
    read it."""
    from indepsim.make import make
    from pneufrac_fit import data, diagnose
    rec = make("lag-real", 1)
    r = data.make_record(rec.t, rec.e, rec.pc, "lag-real-1")
    return diagnose.diagnose(r, rec.truth["config"], jobs=2, progress=False)

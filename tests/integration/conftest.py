# SPDX-License-Identifier: MIT
import sys
from pathlib import Path

import pytest

sys.path.insert(0, str(Path(__file__).resolve().parent))

from pfd import Daemon  # noqa: E402
from tlspki import make_pki  # noqa: E402


@pytest.fixture
def daemon(tmp_path):
    """daemon(*args) starts pneufracd; every one started is stopped with
    SIGTERM at teardown and must exit 0 (in the ASan/UBSan build that also
    means no sanitizer report and no leak)."""
    started = []

    def start(*args, **kw):
        d = Daemon(tmp_path, *args, **kw)
        started.append(d)
        return d

    yield start
    bad = []
    for d in started:
        if d.proc.returncode is None:
            rc = d.stop()
            if rc != 0:
                bad.append((d.args, rc, d.log()[-3000:]))
    assert not bad, bad


@pytest.fixture(scope="module")
def pki(tmp_path_factory):
    """The CA and certificates of the TLS tests (tlspki.make_pki())."""
    return make_pki(tmp_path_factory.mktemp("pki"))

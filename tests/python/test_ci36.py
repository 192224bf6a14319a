# SPDX-License-Identifier: MIT
"""The CI run's sharing of work (branch ci36): files that share a session
fixture go to one xdist worker under --dist loadfile (conftest.SHARED),
and the on-target images' exports are made once per design and process
(mcuemu.images)."""
import subprocess
from pathlib import Path

import pytest

from conftest import SHARED, pytest_xdist_make_scheduler

pytest.importorskip("xdist")
images = pytest.importorskip("mcuemu.images")

HERE = Path(__file__).resolve().parent


class _Config:
    """What xdist's schedulers read of the run's options."""
    def __init__(self, dist):
        self.values = {"dist": dist, "tx": ["2*popen"]}

    def getvalue(self, name):
        return self.values[name]


def test_shared_files_exist_and_take_their_fixture():
    """A file renamed or no longer using the fixture would leave SHARED
    naming nothing, and the fixture computed again on another worker."""
    for fixture, names in SHARED.items():
        assert len(names) >= 2, fixture
        for name in names:
            text = (HERE / name).read_text()
            assert f"({fixture})" in text or f"({fixture}," in text, (name, fixture)


def test_loadfile_puts_shared_files_in_one_unit_and_others_by_file():
    sched = pytest_xdist_make_scheduler(_Config("loadfile"), None)
    for fixture, names in SHARED.items():
        units = {sched._split_scope(f"tests/python/{n}::test_x[a]") for n in names}
        units |= {sched._split_scope(f"{n}::test_y") for n in names}
        assert len(units) == 1, units
    a = sched._split_scope("tests/python/test_record.py::test_x")
    b = sched._split_scope("tests/python/test_record.py::test_y[1]")
    c = sched._split_scope("tests/python/test_split29.py::test_x")
    assert a == b == "tests/python/test_record.py" and c != a


@pytest.mark.parametrize("dist", ["load", "loadscope", "worksteal", "no"])
def test_other_dist_modes_keep_xdists_scheduler(dist):
    assert pytest_xdist_make_scheduler(_Config(dist), None) is None


def _designs():
    return [images.Design("t_p_q15_ctrl", "p"),
            images.Design("t_dd_f32_bank", "dd", "float", kind="bank")]


def test_a_designs_header_is_exported_once_per_process(tmp_path, monkeypatch):
    calls = []

    def run(cmd, **kw):
        calls.append(cmd)
        return subprocess.CompletedProcess(cmd, 0, stdout=f"/* {' '.join(cmd)} */\n", stderr="")
    monkeypatch.setattr(images, "_HEADERS", {})
    monkeypatch.setattr(images.subprocess, "run", run)
    ds = _designs()
    images.write_sets(ds, tmp_path / "a")
    images.write_sets(ds + [images.Design("t_id_q15_ctrl", "id")], tmp_path / "b")
    assert len(calls) == 3                      # two designs, then one new
    for d in ds:
        h = (tmp_path / "a" / f"{d.name}.h").read_text()
        assert h == (tmp_path / "b" / f"{d.name}.h").read_text()
        assert h == f"/* {' '.join(d.exporter() + d.cli_args())} */\n"


def test_a_failed_export_is_not_kept(tmp_path, monkeypatch):
    results = iter([(1, "/* cut short"), (0, "/* h */\n")])

    def run(cmd, **kw):
        rc, out = next(results)
        return subprocess.CompletedProcess(cmd, rc, stdout=out, stderr="bad")
    monkeypatch.setattr(images, "_HEADERS", {})
    monkeypatch.setattr(images.subprocess, "run", run)
    d = _designs()[:1]
    with pytest.raises(RuntimeError, match="bad"):
        images.write_sets(d, tmp_path)
    images.write_sets(d, tmp_path)              # exported again, now it works
    assert (tmp_path / "t_p_q15_ctrl.h").read_text() == "/* h */\n"


def _slow_build(out):
    """A build that takes a while and counts itself in out's parent."""
    import time
    with open(out.parent / "count", "a") as f:
        f.write("x")
    time.sleep(0.5)
    (out / "image.elf").write_text("image")
    return out / "image.elf"


def _ask(out, q):
    q.put(str(images.built_once(out, _slow_build)))


def test_an_image_is_built_once_for_every_process(tmp_path):
    """Two processes ask for one image at once (two xdist workers): one
    builds it, the other waits and gets the same file; a later ask builds
    nothing."""
    import multiprocessing as mp
    ctx = mp.get_context("fork")
    q = ctx.Queue()
    ps = [ctx.Process(target=_ask, args=(tmp_path / "m0", q)) for _ in range(2)]
    for p in ps:
        p.start()
    for p in ps:
        p.join(30)
    assert [p.exitcode for p in ps] == [0, 0]
    got = {q.get(timeout=5) for _ in ps}
    assert got == {str(tmp_path / "m0" / "image.elf")}
    assert images.built_once(tmp_path / "m0", _slow_build) == tmp_path / "m0" / "image.elf"
    assert (tmp_path / "count").read_text() == "x"


def test_a_failed_build_records_nothing(tmp_path):
    def fails(out):
        raise RuntimeError("link failed")
    with pytest.raises(RuntimeError, match="link failed"):
        images.built_once(tmp_path / "m4", fails)
    assert images.built_once(tmp_path / "m4", _slow_build) == tmp_path / "m4" / "image.elf"
    assert (tmp_path / "count").read_text() == "x"

#!/usr/bin/env python3
# SPDX-License-Identifier: MIT
"""Check the systemd unit that `cmake --install` installs
(docs/pneufracd.service.in, its paths filled in), without a running systemd.

    check_unit.py [--no-namespace] BUILD_DIR

In a namespace of its own (sandbox.py), as root:
1. `cmake --install BUILD_DIR --prefix /usr/local` into an empty /usr/local;
2. `systemd-analyze verify` of the installed unit must print nothing and
   succeed: every directive known and valid, the ExecStart=/ExecStartPre=
   programs present, `man:pneufracd(8)` found by man;
3. every file:// of Documentation= is installed;
4. the unit's ExecStartPre= and ExecStart= run as written, as systemd
   would run them with DynamicUser= and StateDirectory=: as an
   unprivileged user that owns a fresh /var/lib/<StateDirectory>. The
   first must create the config file; the second must serve it and stop
   on SIGTERM with status 0; the first again must leave it alone.
Without the namespace (not root, or a container without the privilege)
step 2 runs against a temporary root (`systemd-analyze verify --root`, a
copy of the system's unit directory, --man=no and the man page checked as
a file) and step 4 is left out, saying so; --no-namespace takes that path
even where the namespace can be had, so that CI checks both. Without
systemd-analyze the check is skipped. Exit status: 0 passed, 1 failed, 77 skipped."""

import os
import re
import shutil
import subprocess
import sys
import tempfile
from pathlib import Path

import sandbox

UNIT = "lib/systemd/system/pneufracd.service"
# An unprivileged uid and gid, as DynamicUser= allocates them (61184-65519).
DYNAMIC_ID = 61234


def unit_values(text, key):
    return [m.group(1).strip() for m in re.finditer(rf"^{key}=(.*)$", text, re.M)]


def verify(*args):
    p = subprocess.run(["systemd-analyze", "verify", *args], capture_output=True, text=True,
                       timeout=120)
    said = (p.stdout + p.stderr).strip()
    if p.returncode != 0 or said:
        sandbox.fail(f"systemd-analyze verify {' '.join(args)} (status {p.returncode}): {said}")
    print(f"ok   systemd-analyze verify {' '.join(args)}: nothing to say")


def check_docs(prefix, text):
    docs = " ".join(unit_values(text, "Documentation")).split()
    if "man:pneufracd(8)" not in docs:
        sandbox.fail(f"Documentation= does not name man:pneufracd(8): {docs}")
    for d in docs:
        if d.startswith("file://"):
            path = Path(d[len("file://"):])
            local = prefix / path.relative_to("/usr/local")
            if not local.is_file():
                sandbox.fail(f"Documentation={d}: not installed")
            print(f"ok   Documentation={d}: installed")


def run_as_service(text, work):
    """ExecStartPre= and ExecStart= as written, as the dynamic user, from
    / (systemd's default WorkingDirectory=); their output in @p work."""
    state = unit_values(text, "StateDirectory")
    if state != ["pneufracd"]:
        sandbox.fail(f"StateDirectory= is {state}, not pneufracd")
    sandbox.mount_tmpfs("/var/lib")
    home = Path("/var/lib/pneufracd")
    home.mkdir(mode=0o750)
    subprocess.run(["chown", f"{DYNAMIC_ID}:{DYNAMIC_ID}", str(home)], check=True)
    conf = home / "pneufracd.conf"
    user = (DYNAMIC_ID, DYNAMIC_ID)
    pre, start = unit_values(text, "ExecStartPre"), unit_values(text, "ExecStart")
    if len(pre) != 1 or len(start) != 1:
        sandbox.fail(f"expected one ExecStartPre= and one ExecStart=, not {pre} {start}")

    rc, _ = sandbox.run_line(pre[0], "/", work / "pre.log", user=user)
    if rc != 0 or not conf.is_file():
        sandbox.fail(f"ExecStartPre={pre[0]}: status {rc}, {conf} "
                     f"{'made' if conf.is_file() else 'missing'}: {(work / 'pre.log').read_text()}")
    print(f"ok   ExecStartPre={pre[0]}: created {conf}")
    rc, served = sandbox.run_line(start[0], "/", work / "start.log", user=user)
    if rc != 0 or not served:
        sandbox.fail(f"ExecStart={start[0]}: status {rc}, served {served}: "
                     f"{(work / 'start.log').read_text()[-3000:]}")
    print(f"ok   ExecStart={start[0]}: served, stopped by SIGTERM with status 0")
    before = conf.read_bytes()
    rc, _ = sandbox.run_line(pre[0], "/", work / "pre2.log", user=user)
    if rc != 0 or conf.read_bytes() != before:
        sandbox.fail(f"ExecStartPre={pre[0]} again: status {rc}, file "
                     f"{'unchanged' if conf.read_bytes() == before else 'changed'}")
    print(f"ok   ExecStartPre={pre[0]} again: the file left as it was")


def without_namespace(build, reason):
    """Step 2 against a temporary root, steps 1 and 3 there too."""
    print(f"note: {reason}; verifying against a temporary root, without running the unit")
    root = Path(tempfile.mkdtemp(prefix="pneufrac-unit-"))
    try:
        # DESTDIR, not --prefix: the unit's paths are filled in from the
        # prefix at install time, and must read /usr/local as on a system.
        p = subprocess.run(["cmake", "--install", str(build), "--prefix", "/usr/local"],
                           capture_output=True, text=True, timeout=300,
                           env=dict(os.environ, DESTDIR=str(root)))
        if p.returncode != 0:
            sandbox.fail(f"cmake --install: {p.stdout}{p.stderr}")
        (root / "usr/lib/systemd").mkdir(parents=True)
        shutil.copytree("/usr/lib/systemd/system", root / "usr/lib/systemd/system",
                        symlinks=True)
        text = (root / "usr/local" / UNIT).read_text()
        verify("--root", str(root), "--man=no", "pneufracd.service")
        if not (root / "usr/local/share/man/man8/pneufracd.8").is_file():
            sandbox.fail("man:pneufracd(8): share/man/man8/pneufracd.8 not installed")
        check_docs(root / "usr/local", text)
    finally:
        shutil.rmtree(root)


def main():
    args = sys.argv[1:]
    forced = args[:1] == ["--no-namespace"]
    if forced:
        args = args[1:]
    if len(args) != 1:
        sandbox.fail("usage: check_unit.py [--no-namespace] BUILD_DIR")
    build = Path(args[0]).resolve()
    if shutil.which("systemd-analyze") is None:
        sandbox.skip("systemd-analyze is not installed (scripts/setup.sh installs systemd)")
    if forced:
        without_namespace(build, "--no-namespace")
        return
    if not sandbox.inside():
        reason = sandbox.why_not()
        if reason:
            without_namespace(build, reason)
            return
    sandbox.enter()

    sandbox.install(build)
    unit = Path("/usr/local") / UNIT
    verify(str(unit))
    text = unit.read_text()
    check_docs(Path("/usr/local"), text)
    work = Path(tempfile.mkdtemp(prefix="pneufrac-unit-"))
    try:
        run_as_service(text, work)
    finally:
        shutil.rmtree(work)


if __name__ == "__main__":
    main()

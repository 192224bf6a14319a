# SPDX-License-Identifier: MIT
"""A private machine for the checks in this directory, so that the
commands of the docs run exactly as written (`cmake --install build`,
`pneufracd` on 127.0.0.1:1502, files in /usr/local and /var/lib) without
touching the real one: the calling script is run again as root inside a
mount and network namespace of its own (unshare(1)), where

- /usr/local is an empty tmpfs, for `cmake --install`;
- the loopback is the namespace's own, so 127.0.0.1:1502 is always free
  and nothing else on the machine sees the daemons;
- mounts made inside vanish with the namespace.

Scripts exit with SKIP (77, ctest's SKIP_RETURN_CODE) and one line saying
why when this cannot be had (not root; a container without the privilege
to make namespaces; a tool missing)."""

import os
import shutil
import signal
import subprocess
import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
SKIP = 77
_INSIDE = "PNEUFRAC_SANDBOX"


def skip(reason):
    print(f"skipped: {reason}", flush=True)
    sys.exit(SKIP)


def fail(message):
    print(f"FAILED: {message}", flush=True)
    sys.exit(1)


def why_not():
    """Why the namespace cannot be made here, or None."""
    if os.geteuid() != 0:
        return "needs root, to make a mount and network namespace (unshare)"
    for tool in ("unshare", "mount", "ip"):
        if shutil.which(tool) is None:
            return f"{tool} is not installed (scripts/setup.sh installs it)"
    probe = subprocess.run(["unshare", "--mount", "--net", "true"], capture_output=True,
                           text=True, timeout=30)
    if probe.returncode != 0:
        return ("cannot make a mount and network namespace here (unshare: "
                f"{probe.stderr.strip() or probe.returncode}); a container needs the privilege")
    return None


def inside():
    return os.environ.get(_INSIDE) == "1"


def enter():
    """Run this script again inside the namespace and exit with its status;
    inside, set it up and return."""
    if inside():
        _setup()
        return
    env = dict(os.environ, **{_INSIDE: "1"})
    argv = ["unshare", "--mount", "--net", "--propagation", "private", "--",
            sys.executable, *sys.argv]
    sys.exit(subprocess.run(argv, env=env).returncode)


def _setup():
    subprocess.run(["ip", "link", "set", "lo", "up"], check=True)
    subprocess.run(["mount", "-t", "tmpfs", "-o", "mode=0755", "pneufrac-sandbox", "/usr/local"],
                   check=True)


def mount_tmpfs(path):
    """An empty tmpfs over @p path (inside the namespace only)."""
    subprocess.run(["mount", "-t", "tmpfs", "-o", "mode=0755", "pneufrac-sandbox", str(path)],
                   check=True)


def install(build):
    """`cmake --install BUILD` into the empty /usr/local."""
    p = subprocess.run(["cmake", "--install", str(build), "--prefix", "/usr/local"],
                       capture_output=True, text=True, timeout=300)
    if p.returncode != 0:
        fail(f"cmake --install {build}: {p.stdout}{p.stderr}")


def run_line(line, cwd, log, user=None, timeout_s=120):
    """Run one shell line in @p cwd, its output in @p log. A line that
    logs msg=listening is a server: it is stopped with SIGTERM once it
    does. Either must happen within @p timeout_s. @p user: (uid, gid) to
    run as. @return (status or what went wrong, whether it served)."""
    def as_user():
        os.setgid(user[1])
        os.setgroups([])
        os.setuid(user[0])

    with open(log, "w") as out:
        proc = subprocess.Popen(["bash", "-c", line], cwd=cwd, stdin=subprocess.DEVNULL,
                                stdout=out, stderr=subprocess.STDOUT,
                                preexec_fn=as_user if user else None, start_new_session=True)
    deadline = time.monotonic() + timeout_s
    while True:
        rc = proc.poll()
        if rc is not None:
            return rc, False
        if "msg=listening" in Path(log).read_text(errors="replace"):
            # bash runs a simple command in its own process (exec), so
            # this is the server itself.
            proc.send_signal(signal.SIGTERM)
            try:
                rc = proc.wait(timeout=20)
            except subprocess.TimeoutExpired:
                rc = "no stop within 20 s of SIGTERM"
            _kill_group(proc)
            return rc, True
        if time.monotonic() > deadline:
            _kill_group(proc)
            return f"neither finished nor served within {timeout_s} s", False
        time.sleep(0.05)


def _kill_group(proc):
    """Whatever the line left running."""
    try:
        os.killpg(proc.pid, signal.SIGKILL)
    except ProcessLookupError:
        pass
    proc.wait()

#!/usr/bin/env python3
# SPDX-License-Identifier: MIT
"""Run the command recipes of the docs as written, so that they cannot rot.

    run_recipes.py BUILD_DIR FILE.md...

Every fenced block right after a line `<!-- runnable -->` in each FILE is
run, in file order, one line at a time (a line ending in a backslash goes
on with the next; `#` starts a comment, as in the shell), with bash, in
one scratch working directory whose `build` is BUILD_DIR and whose `.venv`
is the project's (as in a checkout after scripts/setup.sh), as root in a
namespace of its own (sandbox.py: an empty /usr/local, a private
loopback). A line must finish with status 0, or, if it serves (it logs
msg=listening), stop on SIGTERM with status 0. A FILE without a runnable
block fails: a marker that went missing must not pass silently.
Exit status: 0 all ran, 1 a line failed, 77 skipped (the namespace cannot
be made here; the reason is printed)."""

import re
import shutil
import sys
import tempfile
from pathlib import Path

import sandbox

MARK = "<!-- runnable -->"
# A diagnosis with its plots is the slowest line (tens of seconds alone);
# the margin is for a CI machine running other tests beside it.
LINE_TIMEOUT_S = 400


def blocks(text):
    """The runnable blocks of @p text: (line number, [command lines])."""
    out = []
    lines = text.splitlines()
    for i, line in enumerate(lines):
        if line.strip() != MARK:
            continue
        if i + 1 >= len(lines) or not re.match(r"```(sh|bash)?\s*$", lines[i + 1]):
            sandbox.fail(f"line {i + 1}: {MARK} is not followed by a ```sh fence")
        body, j = [], i + 2
        while j < len(lines) and not lines[j].startswith("```"):
            body.append(lines[j])
            j += 1
        out.append((i + 3, commands(body)))
    return out


def commands(body):
    """Shell lines, continuations joined; blank and comment-only lines
    dropped."""
    out, cur = [], ""
    for line in body:
        if line.rstrip().endswith("\\"):
            cur += line.rstrip()[:-1] + " "
            continue
        cur += line
        if cur.strip() and not cur.strip().startswith("#"):
            out.append(cur.strip())
        cur = ""
    return out


def other_prefix(build):
    """Why `cmake --install build`, as the docs write it, would install
    outside the sandbox's /usr/local, or None."""
    cache = (build / "CMakeCache.txt").read_text(errors="replace")
    m = re.search(r"^CMAKE_INSTALL_PREFIX:PATH=(.*)$", cache, re.M)
    prefix = m.group(1) if m else None
    if prefix != "/usr/local":
        return f"{build} installs into {prefix}, and the docs' recipes into /usr/local"
    return None


def main():
    if len(sys.argv) < 3:
        sandbox.fail("usage: run_recipes.py BUILD_DIR FILE.md...")
    build = Path(sys.argv[1]).resolve()
    files = [Path(f).resolve() for f in sys.argv[2:]]
    found = {f: blocks(f.read_text()) for f in files}
    for f, bs in found.items():
        if not bs:
            sandbox.fail(f"{f}: no {MARK} block")
    if not sandbox.inside():
        reason = sandbox.why_not() or other_prefix(build)
        if reason:
            sandbox.skip(reason)
    sandbox.enter()

    work = Path(tempfile.mkdtemp(prefix="pneufrac-recipes-"))
    (work / "build").symlink_to(build)
    venv = sandbox.ROOT / ".venv"
    if venv.is_dir():
        (work / ".venv").symlink_to(venv)
    failed = 0
    for f, bs in found.items():
        for first, cmds in bs:
            for n, line in enumerate(cmds):
                log = work / f"line-{first}-{n}.log"
                rc, served = sandbox.run_line(line, work, log, timeout_s=LINE_TIMEOUT_S)
                ok = rc == 0
                print(f"{'ok  ' if ok else 'FAIL'} {f.name} block at line {first}: {line}"
                      f"{'  (served, stopped by SIGTERM)' if served else ''}", flush=True)
                if not ok:
                    failed = 1
                    print(f"     status {rc}; output:\n{log.read_text(errors='replace')[-3000:]}")
    shutil.rmtree(work)
    sys.exit(failed)


if __name__ == "__main__":
    main()

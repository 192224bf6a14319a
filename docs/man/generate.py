#!/usr/bin/env python3
# SPDX-License-Identifier: MIT
"""The OPTIONS of the man pages in docs/man are the programs' own --help
text, copied in between the lines

    .\\" generated: PROGRAM ARGS...
    .\\" end generated

so that an option is described in one place, the program. This script
rewrites those blocks (default) or checks them and groff's warnings
(--check: exit 1 and name the page; ctest runs it as man_pages). The programs are found in
the environment (PNEUFRAC_CLI, PNEUFRACD, PNEUFRAC_FIT, PNEUFRAC_REDUCE) or
the build tree.

    docs/man/generate.py [--check]
"""
import os
import re
import subprocess
import sys
from pathlib import Path

HERE = Path(__file__).resolve().parent
ROOT = HERE.parents[1]
PROGRAMS = {
    "pneufrac": os.environ.get("PNEUFRAC_CLI", str(ROOT / "build/tools/pneufrac")),
    "pneufracd": os.environ.get("PNEUFRACD", str(ROOT / "build/port/posix/pneufracd")),
    "pneufrac-fit": os.environ.get("PNEUFRAC_FIT", str(ROOT / ".venv/bin/pneufrac-fit")),
    "pneufrac-reduce": os.environ.get("PNEUFRAC_REDUCE", str(ROOT / ".venv/bin/pneufrac-reduce")),
}
BLOCK = re.compile(r'(\.\\" generated: ([^\n]+)\n)(.*?)(\.\\" end generated\n)', re.S)


def roff_escape(text: str) -> str:
    """Plain text as it must appear in a .nf block: backslashes and minus
    signs escaped (so options copy as ASCII hyphens), control characters at
    a line start neutralised."""
    out = []
    for line in text.splitlines():
        line = line.replace("\\", "\\e").replace("-", "\\-")
        if line.startswith((".", "'")):
            line = "\\&" + line
        out.append(line)
    return "\n".join(out) + "\n"


def help_block(cmd: str) -> str:
    prog, *args = cmd.split()
    # A fixed width: argparse wraps --help to the terminal's.
    env = dict(os.environ, COLUMNS="80")
    r = subprocess.run([PROGRAMS[prog], *args], capture_output=True, text=True,
                       timeout=60, env=env)
    if r.returncode != 0:
        sys.exit(f"generate.py: {cmd} failed ({r.returncode}): {r.stderr.strip()}")
    return ".nf\n" + roff_escape(r.stdout) + ".fi\n"


def main(argv) -> int:
    check = argv == ["--check"]
    if argv and not check:
        print(__doc__.strip(), file=sys.stderr)
        return 2
    stale = []
    for page in sorted([*HERE.glob("*.1"), *HERE.glob("*.8")]):
        text = page.read_text()
        new = BLOCK.sub(lambda m: m.group(1) + help_block(m.group(2)) + m.group(4), text)
        if new != text:
            stale.append(page)
            if not check:
                page.write_text(new)
    if check and stale:
        for p in stale:
            print(f"{p.relative_to(ROOT)} is out of date with the programs' --help; "
                  f"run docs/man/generate.py", file=sys.stderr)
        return 1
    if check:
        return lint()
    return 0


def lint() -> int:
    """groff's own warnings (-ww) about every page: none allowed."""
    bad = 0
    for page in sorted([*HERE.glob("*.1"), *HERE.glob("*.8")]):
        r = subprocess.run(["groff", "-man", "-ww", "-z", str(page)], capture_output=True,
                           text=True, timeout=60)
        if r.returncode != 0 or r.stderr:
            print(f"{page.relative_to(ROOT)}: groff: {r.stderr.strip()}", file=sys.stderr)
            bad = 1
    return bad


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))

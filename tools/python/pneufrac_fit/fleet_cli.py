# SPDX-License-Identifier: MIT
"""The `pneufrac-fit fleet` subcommand: its options and what it runs."""
from __future__ import annotations

import sys
import time
from pathlib import Path

from . import fleet

HELP = "diagnose one record per loop on dask.distributed; write the fleet report"
DESCRIPTION = """Diagnoses every record (one CSV per loop, header t,e,pc, as
`pneufrac-fit diagnose` reads it) of a folder or a glob pattern, each as a
task on dask.distributed: a local cluster of --workers processes by
default, or the running scheduler at --scheduler. Writes into --out:
fleet.csv, fleet.parquet and fleet.md (one row per loop: causes, effect
sizes, gain; most severe first), fleet.png (the summary figure) and
records/LOOP.json (each loop's diagnosis). A record that cannot be
diagnosed is reported in its row; the others go on."""
DEFAULT_OUT = "fleet-report"


def add_arguments(f) -> None:
    from .cli import seed_arg      # the seed's one rule, as diagnose and generate read it
    f.add_argument("records", metavar="DIR|GLOB",
                   help="a folder (its *.csv files) or a quoted glob pattern")
    f.add_argument("--config", required=True, choices=["p", "dd", "id", "pid"],
                   help="the loops' controller configuration")
    f.add_argument("--scheduler", metavar="ADDRESS", default=None,
                   help="a running dask scheduler (tcp://HOST:PORT); its workers need "
                        "pneufrac installed (default: a local cluster)")
    f.add_argument("--workers", type=int, default=None, metavar="N",
                   help=f"processes of the local cluster, 1..{fleet.MAX_WORKERS} "
                        "(default 2)")
    f.add_argument("--out", metavar="DIR", default=DEFAULT_OUT,
                   help=f"report folder (default {DEFAULT_OUT})")
    f.add_argument("--seed", type=seed_arg, default=0, metavar="S",
                   help="seed of the fits' fresh starts (a non-negative integer)")
    f.add_argument("--quiet", action="store_true", help="no progress on stderr")


def run(a, usage_error) -> int:
    """Run the subcommand; @usage_error(text) makes the CLI's usage error."""
    if a.scheduler and a.workers is not None:
        raise usage_error("--workers sizes the local cluster; with --scheduler the "
                          "cluster's own workers run the records")
    workers = 2 if a.workers is None else a.workers
    if not 1 <= workers <= fleet.MAX_WORKERS:
        raise usage_error(f"--workers {workers}: must be in [1, {fleet.MAX_WORKERS}]")
    try:
        files = fleet.find_records(a.records)
    except fleet.FleetError as exc:
        raise usage_error(str(exc)) from None
    out = Path(a.out)
    try:
        out.mkdir(parents=True, exist_ok=True)
    except OSError as exc:
        raise usage_error(f"--out {a.out}: cannot create the folder: "
                          f"{exc.strerror or exc}") from None

    def say(text: str) -> None:
        if not a.quiet:
            print(f"[pneufrac-fit fleet] {text}", file=sys.stderr, flush=True)

    where = a.scheduler or f"a local cluster of {workers} worker(s)"
    say(f"{len(files)} record(s), config {a.config}, on {where}")
    t0 = time.monotonic()
    try:
        rows = fleet.run(files, a.config, scheduler=a.scheduler, workers=workers,
                         seed=a.seed, say=say)
    except fleet.FleetError as exc:
        raise usage_error(str(exc)) from None
    from . import fleet_report
    paths = fleet_report.write(rows, out, a.config, time.monotonic() - t0, where)
    bad = sum(r["status"] != "ok" for r in rows)
    say(f"report: {paths['md']} ({len(rows) - bad} diagnosed, {bad} not)")
    return 0

#!/usr/bin/env python3
# SPDX-License-Identifier: MIT
"""Records per hour of `pneufrac-fit fleet` against the number of workers,
the scheduler's cost per task and the data each task moves; writes the
generated section of docs/fleet.md. A benchmark: it measures, it never
fails on the figures.

    .venv/bin/python bench/bench_fleet.py [--records 12] [--n 10000]
        [--workers 1,2] [--out docs/fleet.md]
"""
import argparse
import os
import pickle
import subprocess
import sys
import tempfile
import time
from datetime import datetime, timezone
from pathlib import Path

for v in ("OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ.setdefault(v, "1")
ROOT = Path(__file__).resolve().parents[1]

import numpy as np  # noqa: E402

from bench_fit import machine  # noqa: E402  (bench/, the script's folder)
from pneufrac_fit import fleet  # noqa: E402

BEGIN = "<!-- generated: bench/bench_fleet.py -->"
END = "<!-- end generated -->"
# The plant: loops of one configuration, a quarter each with a dead time, a
# lag, a dead band, and none.
KINDS = [["--effect", "deadtime:t=0.012"], ["--effect", "lag:tau=0.02"],
         ["--effect", "backlash:width=0.04"], []]
NOOP_TASKS = 2000


def make_records(folder: Path, k: int, n: int) -> list[Path]:
    exe = Path(sys.executable).with_name("pneufrac-fit")
    files = []
    for i in range(k):
        f = folder / f"loop{i:03d}.csv"
        subprocess.run([str(exe), "generate", "--config", "dd", "--n", str(n), "--seed",
                        str(100 + i), *KINDS[i % len(KINDS)], "-o", str(f)], check=True)
        files.append(f)
    return files


def startup(workers: int) -> float:
    t0 = time.monotonic()
    client, cluster = fleet._client(None, workers)
    client.wait_for_workers(workers)
    dt = time.monotonic() - t0
    client.close()
    cluster.close()
    return dt


def noop(x):
    return x


def scheduler_cost(workers: int) -> tuple[float, float]:
    """Seconds per task, for tasks that do nothing: the wall time of the
    whole dask round trip (submission, scheduling, the worker's call, the
    result), and the CPU time of this process, where the local cluster's
    scheduler runs beside the client."""
    client, cluster = fleet._client(None, workers)
    try:
        client.wait_for_workers(workers)
        client.gather(client.map(noop, range(50), pure=False))      # warm
        t0, c0 = time.monotonic(), time.process_time()
        client.gather(client.map(noop, range(NOOP_TASKS), pure=False))
        return ((time.monotonic() - t0) / NOOP_TASKS,
                (time.process_time() - c0) / NOOP_TASKS)
    finally:
        client.close()
        cluster.close()


def main() -> int:
    ap = argparse.ArgumentParser()
    ap.add_argument("--records", type=int, default=12)
    ap.add_argument("--n", type=int, default=10000)
    ap.add_argument("--workers", default="1,2")
    ap.add_argument("--out", default=str(ROOT / "docs" / "fleet.md"))
    a = ap.parse_args()
    counts = [int(x) for x in a.workers.split(",")]
    load0 = os.getloadavg()
    runs = []
    with tempfile.TemporaryDirectory() as tmp:
        files = make_records(Path(tmp), a.records, a.n)
        in_bytes = float(np.mean([f.stat().st_size for f in files]))
        for w in counts:
            up = startup(w)
            t0 = time.monotonic()
            rows = fleet.run(files, "dd", workers=w)
            wall = time.monotonic() - t0
            ok = [r for r in rows if r["status"] == "ok"]
            runs.append({"workers": w, "wall": wall, "startup": up, "ok": len(ok),
                         "task": float(np.median([r["elapsed_s"] for r in ok])),
                         "cpu": float(np.median([r["cpu_s"] for r in ok])),
                         "out_bytes": float(np.mean([len(pickle.dumps(r)) for r in rows]))})
            print(f"[bench_fleet] {w} worker(s): {wall:.1f} s for {len(rows)} records "
                  f"({len(ok)} diagnosed), startup {up:.1f} s", file=sys.stderr)
        per_task = scheduler_cost(max(counts))
    load1 = os.getloadavg()
    text = report(a, runs, in_bytes, per_task, load0, load1)
    out = Path(a.out)
    doc = out.read_text(encoding="utf-8")
    if BEGIN not in doc or END not in doc:
        print(text)
        print(f"[bench_fleet] {out} has no generated section; printed instead", file=sys.stderr)
        return 0
    head, rest = doc.split(BEGIN, 1)
    out.write_text(head + BEGIN + "\n" + text + END + rest.split(END, 1)[1],
                   encoding="utf-8")
    print(f"[bench_fleet] wrote {out}", file=sys.stderr)
    return 0


def report(a, runs, in_bytes, per_task, load0, load1) -> str:
    L = []
    w = L.append
    date = datetime.now(timezone.utc).strftime("%Y-%m-%d")
    w(f"Measured on {machine()}, {date}, by `.venv/bin/python bench/bench_fleet.py "
      f"--records {a.records} --n {a.n} --workers {a.workers}`. Load average "
      f"{load0[0]:.2f} at the start and {load1[0]:.2f} at the end (the machine is "
      "shared: other work competes for the same cores).\n")
    w(f"{a.records} generated dd records of {a.n} samples at 1 kHz, a quarter each with a "
      "dead time, a lag, a dead band and none; every record is diagnosed with "
      "pneufrac-fit's defaults (one process per record, `--jobs 1`).\n")
    w("| workers | wall time | of which cluster start | records/hour (wall) | "
      "records/hour (after start) | median per record: wall, CPU | "
      "records/hour if each worker had a core (from the CPU) |")
    w("|---|---|---|---|---|---|---|")
    for r in runs:
        rate = a.records * 3600 / r["wall"]
        steady = a.records * 3600 / max(r["wall"] - r["startup"], 1e-9)
        w(f"| {r['workers']} | {r['wall']:.1f} s | {r['startup']:.1f} s | {rate:.0f} | "
          f"{steady:.0f} | {r['task']:.1f} s, {r['cpu']:.1f} s | "
          f"{r['workers'] * 3600 / r['cpu']:.0f} |")
    w("")
    first, last = runs[0], runs[-1]
    speedup = first["wall"] / last["wall"]
    w("A record's wall time on its worker exceeds its CPU time by what the other work "
      "on the machine takes from its core; on a core of its own the two would agree. "
      f"From {first['workers']} to {last['workers']} workers the wall time fell by a "
      f"factor {speedup:.2f}: each worker got the share of a core that the machine's "
      "load left it, so that factor measures this shared machine, not dask. The last "
      "column is the rate the CPU time allows, workers × 3600 s / CPU per record: an "
      "estimate for idle cores, not a measurement, and on this 2-core machine the "
      "client and scheduler (below) would share the cores with the workers.\n")
    task = runs[0]["cpu"]
    out_b = runs[0]["out_bytes"]
    rt, cpu = per_task
    w(f"Each task carries its record's text to the worker ({in_bytes / 1e3:.0f} kB on "
      f"average here) and brings back the diagnosis's JSON object ({out_b / 1e3:.1f} kB "
      f"pickled). {NOOP_TASKS} tasks that do nothing, on a local cluster of "
      f"{runs[-1]['workers']}, took {rt * 1e6:.0f} µs each from submission to result, "
      f"and {cpu * 1e6:.0f} µs of CPU each in the process of the client and the "
      "scheduler.\n")
    w("**100 workers, on paper** (arithmetic on the figures above, not a measurement):\n")
    rate = 100 * 3600 / task
    tps = 100 / task
    w(f"- Throughput: with {task:.1f} s of CPU per record, 100 single-threaded "
      f"workers, each on a core of its own, finish 100 records every {task:.1f} s: about "
      f"{round(rate, -3):,.0f} records per hour once started.")
    w(f"- Scheduler: {tps:.1f} tasks per second. At {cpu * 1e6:.0f} µs of client and "
      f"scheduler CPU each, that is {100 * tps * cpu:.2f} % of one core; the scheduler "
      f"would saturate one core only when tasks got {task / (100 * cpu):.0f} times "
      f"shorter ({100 * cpu * 1e3:.0f} ms each at 100 workers).")
    w(f"- Data: {tps * in_bytes / 1e6:.2f} MB/s of records out of the client and "
      f"{tps * out_b / 1e6:.3f} MB/s of results back; the client reads one file per "
      f"finished task, and holds at most {fleet.IN_FLIGHT} records per worker thread "
      f"({fleet.IN_FLIGHT * 100 * in_bytes / 1e6:.0f} MB for 100 workers) in flight.")
    w("- Start: the local cluster's start above is per worker process (Python, numpy, "
      "scipy and the library imported once each); a real cluster's workers are started "
      "once and serve every fleet run, so only the client's connection remains.")
    w("- What does not scale: one record is one task on one core, so a fleet's wall "
      "time is at least its longest record's diagnosis, and a plant with fewer loops "
      "than workers leaves workers idle.\n")
    return "\n".join(L)


if __name__ == "__main__":
    sys.exit(main())

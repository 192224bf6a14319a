# SPDX-License-Identifier: MIT
"""pneufrac-fit fleet: diagnose one record per loop (a historian export) on
dask.distributed, a local cluster by default or a running scheduler.

Each record is one task. The client reads the file and sends its text
with the task, so workers need pneufrac installed but no view of the
client's files; the task returns the diagnosis as its JSON object (a few
kB). At most two tasks per worker thread are in flight, so a plant's
worth of records never sits in memory at once. A record that cannot be
diagnosed, for any reason, comes back as an error row: one bad record
never stops the fleet.
"""
from __future__ import annotations

import glob
import logging
import os
import time
from pathlib import Path

MAX_WORKERS = 256
# Tasks in flight per worker thread: one running, one queued beside it.
IN_FLIGHT = 2


class FleetError(Exception):
    """The fleet cannot start (no records, no scheduler); one line."""


def find_records(spec: str) -> list[Path]:
    """The records of DIR (its *.csv files) or of a glob pattern, sorted."""
    p = Path(spec)
    if p.is_dir():
        files = sorted(x for x in p.glob("*.csv") if x.is_file())
        if not files:
            raise FleetError(f"{spec}: no *.csv files in the folder")
        return files
    files = sorted(Path(x) for x in glob.glob(spec) if Path(x).is_file())
    if not files:
        raise FleetError(f"{spec}: no such folder, and no file matches it as a pattern")
    return files


def loop_names(files: list[Path]) -> list[str]:
    """A name per record: its file name without .csv, or its path relative
    to the records' common folder where two names would be equal."""
    stems = [f.stem for f in files]
    if len(set(stems)) == len(stems):
        return stems
    base = Path(os.path.commonpath([str(f.resolve().parent) for f in files]))
    return [str(f.resolve().relative_to(base).with_suffix("")) for f in files]


def error_row(loop: str, message: str, elapsed: float = 0.0, cpu: float = 0.0) -> dict:
    return {"loop": loop, "status": "error", "error": message, "diagnosis": None,
            "elapsed_s": elapsed, "cpu_s": cpu}


def diagnose_text(loop: str, text: str, config: str, seed: int = 0) -> dict:
    """One task: the record's CSV text in, its row out. Never raises.
    elapsed_s is the task's wall time, cpu_s its process's CPU time (the
    cost on a core of its own)."""
    from . import data, diagnose, lib, output
    t0, c0 = time.monotonic(), time.process_time()
    try:
        rec = data.parse_csv(text, loop)
        d = diagnose.diagnose(rec, config, {}, jobs=1, progress=False, seed=seed)
        j = output.to_dict(d)
    except (data.DataError, lib.ModelError) as exc:
        return error_row(loop, str(exc), time.monotonic() - t0, time.process_time() - c0)
    except Exception as exc:  # noqa: BLE001  a bug in one record must not stop the rest
        return error_row(loop, f"{type(exc).__name__}: {exc}", time.monotonic() - t0,
                         time.process_time() - c0)
    return {"loop": loop, "status": "ok", "error": "", "diagnosis": j,
            "elapsed_s": time.monotonic() - t0, "cpu_s": time.process_time() - c0}


def read_record(path: Path) -> str:
    """The record's text; OSError or ValueError with the reason."""
    from . import data
    return data.decode(data.read_bytes(path), str(path))    # as diagnose reads a file


def read_error(path: Path, exc: Exception) -> str:
    """The reason read_record failed, naming the path once (a DataError's
    message starts with it already)."""
    if isinstance(exc, OSError):
        return f"{path}: cannot read: {exc.strerror or exc}"
    return str(exc)


def _client(scheduler: str | None, workers: int):
    """(Client, the local cluster or None): a client of the scheduler at
    @scheduler, or of a new local cluster of @workers single-threaded
    processes on 127.0.0.1."""
    import dask
    from dask.distributed import Client, LocalCluster
    if scheduler:
        try:
            return Client(scheduler, timeout="20s"), None
        except (OSError, TimeoutError, ValueError) as exc:
            raise FleetError(f"--scheduler {scheduler}: cannot connect ({exc})") from None
    # A record that kills its worker (it should not) is not retried on the
    # others: it is reported in its row.
    dask.config.set({"distributed.scheduler.allowed-failures": 0})
    # Everything on the loopback interface, on free ports: the scheduler's
    # HTTP server starts even without a dashboard, on 8787 unless told (a
    # bare ":0" would listen on every interface).
    cluster = LocalCluster(n_workers=workers, threads_per_worker=1, processes=True,
                           host="127.0.0.1", dashboard_address="127.0.0.1:0",
                           silence_logs=logging.ERROR)
    return Client(cluster), cluster


def run(files: list[Path], config: str, *, scheduler: str | None = None,
        workers: int = 2, seed: int = 0, say=None) -> list[dict]:
    """Diagnose every record; rows in the order they finish. @say(text)
    hears of each."""
    names = loop_names(files)
    say = say or (lambda text: None)
    rows: list[dict] = []
    t0 = time.monotonic()
    client, cluster = _client(scheduler, workers)
    try:
        from dask.distributed import as_completed
        threads = sum(client.nthreads().values()) or 1
        todo = iter(zip(names, files))
        running = as_completed()
        loop_of = {}

        def submit_next() -> bool:
            for loop, path in todo:
                try:
                    text = read_record(path)
                except (OSError, ValueError) as exc:
                    rows.append(error_row(loop, read_error(path, exc)))
                    say(f"{len(rows)}/{len(files)} {loop}: cannot read")
                    continue
                fut = client.submit(diagnose_text, loop, text, config, seed, pure=False)
                loop_of[fut.key] = loop
                running.add(fut)
                return True
            return False

        for _ in range(IN_FLIGHT * threads):
            if not submit_next():
                break
        for fut in running:
            loop = loop_of.pop(fut.key)
            try:
                row = fut.result()
            except Exception as exc:  # noqa: BLE001  the worker died or was lost
                row = error_row(loop, f"the task failed: {type(exc).__name__}: {exc}")
            fut.release()
            rows.append(row)
            what = (row["diagnosis"]["cause"] if row["status"] == "ok"
                    else "error: " + row["error"].splitlines()[0][:120])
            say(f"{time.monotonic() - t0:7.1f}s {len(rows)}/{len(files)} {loop}: {what}")
            submit_next()
    finally:
        client.close()
        if cluster is not None:
            cluster.close()
    return rows

"""Running a study: each point independently, serially, on a local process pool
(:class:`concurrent.futures.ProcessPoolExecutor`, the default) or on a running
``dask.distributed`` cluster; rows stream into the table as points finish.

- **Deterministic.** A point's row depends on its inputs only (the study's definition fixes them,
  random samples included), so the same study gives the same bits serially, on the pool and on any
  Dask worker; the table is sorted by point when the study ends.
- **Streaming and resumable.** Each finished point is one line appended to a CSV journal and
  flushed to disk (for a ``.parquet`` table the journal is ``<table>.journal.csv``, converted when
  the study ends). A study run again on the same table computes only the points missing from it;
  the first line of the journal is the study's fingerprint, so a table of another study is refused.
- **Robust.** A point that raises is a row with status ``'failed'`` and the error; Ctrl-C stops
  the workers and leaves the journal with the finished points (a line cut short is dropped when
  it is read).
"""
from __future__ import annotations

import multiprocessing
import os
import sys
from concurrent.futures import ProcessPoolExecutor, as_completed
from concurrent.futures.process import BrokenProcessPool
from pathlib import Path
from typing import Any, Callable

from ..errors import ParameterError, WorkerError
from ..results.study import STATUS_COLUMNS, StudyTable, format_row, header_line, read_csv_rows
from .definition import Random, Study
from .point import evaluate_point
from .quantities import QUANTITIES

__all__ = ["run_study", "evaluate_point", "tasks"]


def tasks(study: Study) -> list[dict]:
    """The study's points as self-contained tasks (picklable: the model, the sweep and the point's
    parameters)."""
    w0, w1, n = study.omega
    return [dict(point=k, model=study.model, omega=(w0, w1, n), fixed=dict(study.fixed), varied=p,
                 direction=study.direction, method=study.method, harmonics=int(study.harmonics),
                 refine=bool(study.refine_peak))
            for k, p in enumerate(study.points())]


def _journal_path(table: Path) -> Path:
    return table if table.suffix == ".csv" else table.with_name(table.name + ".journal.csv")


def _done_rows(study: Study, table: Path, journal: Path, fingerprint: str, columns: tuple, n_points: int,
               restart: bool) -> list[dict]:
    """The rows already computed for this study (from its journal, or a finished Parquet table):
    whole rows of valid points, one per point."""
    if restart:
        for p in (journal, table):
            if p.exists():
                p.unlink()
        return []
    if journal.exists():
        fp, _, found, rows = read_csv_rows(journal)
        source = journal
    elif table.exists():
        done = StudyTable.read(table)
        fp, found, rows, source = done.fingerprint, list(done.columns), done.rows(), table
    else:
        return []
    if fp is None and not rows:  # stopped before its first line was written: a new journal
        return []
    if fp != fingerprint:
        raise ParameterError(f"table {str(source)!r} holds another study (fingerprint {fp}, this study's "
                             f"{fingerprint}): choose another table, or restart=True to overwrite it")
    if not rows:  # the column line missing or cut short: nothing to keep
        return []
    if tuple(found) != tuple(columns):
        raise ParameterError(f"table {str(source)!r} has the columns {found}, this study writes {list(columns)}: "
                             "choose another table, or restart=True to overwrite it")
    unique = {}
    for r in rows:  # one row per point of this study
        if isinstance(r.get("point"), int) and 0 <= r["point"] < n_points:
            unique.setdefault(r["point"], r)
    return [unique[k] for k in sorted(unique)]


def _write_journal(journal: Path, fingerprint: str, random: tuple, columns: tuple, rows: list[dict]) -> None:
    """The journal anew, atomically: its two header lines and the rows kept (a resumed study
    appends to whole lines only)."""
    tmp = journal.with_name(journal.name + ".tmp")
    with open(tmp, "w", newline="", encoding="utf-8") as f:
        f.write(header_line(fingerprint, random))
        f.write(format_row({c: c for c in columns}, columns))
        for r in rows:
            f.write(format_row(r, columns))
        f.flush()
        os.fsync(f.fileno())
    os.replace(tmp, journal)


def run_study(study: Study, table: str | os.PathLike | None = None, *, workers: int | None = None,
              scheduler: str | Any | None = None, progress: bool = False, restart: bool = False,
              on_row: Callable[[dict], None] | None = None) -> StudyTable:
    """Run ``study``, streaming its rows into ``table`` (module docstring).

    Parameters
    ----------
    study : Study
    table : str or os.PathLike, optional
        ``.csv`` or ``.parquet``; default ``study.table``.
    workers : int, optional
        Local processes (default the machine's cores); 1 runs the points in this process. Not
        with ``scheduler``.
    scheduler : str or distributed.Client, optional
        A running Dask scheduler's address (``tcp://host:port``) or a client: the points run on its
        workers (which need frictionjoint installed, and the model's files at the same paths).
    progress : bool
        Show a progress bar (points done, time left).
    restart : bool
        Discard the rows already in ``table`` (default: resume, computing only the missing points).
    on_row : callable, optional
        Called with each new row after it is written (in this process).

    Returns
    -------
    StudyTable
        Every point, sorted by point.
    """
    from tqdm import tqdm

    if not isinstance(study, Study):
        raise ParameterError(f"study must be a Study (frictionjoint.study.load_study), got {type(study).__name__}")
    table = Path(table if table is not None else (study.table or "study.csv"))
    if table.suffix not in (".csv", ".parquet"):
        raise ParameterError(f"table must end in .csv or .parquet, got {str(table)!r}")
    if workers is not None and (isinstance(workers, bool) or not isinstance(workers, int) or workers < 1):
        raise ParameterError(f"workers must be an integer >= 1, got {workers!r}")
    if workers is not None and scheduler is not None:
        raise ParameterError("workers is for the local pool; a Dask cluster has its own workers (scheduler)")
    all_tasks = tasks(study)
    fingerprint = study.fingerprint()
    columns = ("point", *study.varied, *QUANTITIES, *STATUS_COLUMNS)
    journal = _journal_path(table)
    done = _done_rows(study, table, journal, fingerprint, columns, len(all_tasks), restart)
    done_ids = {r["point"] for r in done}
    todo = [t for t in all_tasks if t["point"] not in done_ids]
    random = tuple(n for n, spec in study.vary.items() if isinstance(spec, Random))

    def finish(rows) -> StudyTable:
        out = StudyTable.from_rows(rows, columns, study.varied, random, fingerprint, table)
        if len(out) == len(all_tasks):  # complete: the table sorted by point (and as Parquet)
            out.write(table)
            if journal != table and journal.exists():
                journal.unlink()
        return out

    if not todo:
        return finish(done)
    # the journal anew with the rows kept: no line cut short, no half header, no duplicate
    _write_journal(journal, fingerprint, random, columns, done)
    rows = list(done)
    with open(journal, "a", newline="", encoding="utf-8") as f, \
            tqdm(total=len(all_tasks), initial=len(done_ids), desc="study", unit="pt", file=sys.stderr,
                 disable=not progress, leave=False) as bar:

        def record(row):
            f.write(format_row(row, columns))  # one line per row, flushed: a consistent journal
            f.flush()
            os.fsync(f.fileno())
            rows.append(row)
            bar.update()
            if on_row is not None:
                on_row(row)

        if scheduler is not None:
            _run_dask(todo, scheduler, record)
        elif workers == 1 or len(todo) == 1:
            for t in todo:
                record(evaluate_point(t))
        else:
            _run_pool(todo, workers or os.cpu_count() or 1, record)
    return finish(rows)


def _run_pool(todo: list[dict], workers: int, record) -> None:
    """The points on a local process pool (spawned workers: no state inherited from this
    process)."""
    pool = ProcessPoolExecutor(max_workers=min(workers, len(todo)), mp_context=multiprocessing.get_context("spawn"))
    try:
        futures = [pool.submit(evaluate_point, t) for t in todo]
        for fut in as_completed(futures):
            try:
                row = fut.result()
            except BrokenProcessPool as exc:
                raise WorkerError(f"a worker process died ({exc}); the finished points are in the table: "
                                  "run the study again to resume") from None
            record(row)
    except BaseException:
        pool.shutdown(wait=False, cancel_futures=True)
        raise
    pool.shutdown(wait=True)


def _run_dask(todo: list[dict], scheduler, record) -> None:
    """The points on a Dask cluster (a scheduler's address or a client)."""
    try:
        from distributed import Client, as_completed as dask_completed
    except ImportError:  # pragma: no cover - distributed is in the 'cluster' and 'test' extras
        raise ParameterError("scheduler: Dask's distributed is not installed (pip install 'frictionjoint[cluster]')") from None
    own = not isinstance(scheduler, Client)
    if own:
        if not isinstance(scheduler, str):
            raise ParameterError(f"scheduler must be an address (tcp://host:port) or a distributed.Client, got {scheduler!r}")
        try:
            client = Client(scheduler, timeout="10s")
        except (OSError, ValueError, TypeError) as exc:
            raise ParameterError(f"scheduler: no Dask scheduler at {scheduler!r} ({exc})") from None
    else:
        client = scheduler
    futures = client.map(evaluate_point, todo, pure=False)
    try:
        for fut in dask_completed(futures):
            try:
                row = fut.result()
            except Exception as exc:  # noqa: BLE001 - evaluate_point returns its errors: this is the worker's death
                raise WorkerError(f"a Dask worker failed ({type(exc).__name__}: {exc}); the finished points are "
                                  "in the table: run the study again to resume") from None
            record(row)
    except BaseException:
        client.cancel(futures)
        raise
    finally:
        if own:
            client.close()

"""Running a study: each point independently, serially, on a local process pool (the default)
or on a running ``dask.distributed`` cluster; rows stream into the table as points finish.

- **Deterministic.** A point's row depends on its inputs only (the study's definition fixes them,
  random samples included), so the same study gives the same bits serially, on the pool and on any
  Dask worker; the table is sorted by point when the study ends.
- **Streaming and resumable.** Each finished point is one line appended to a CSV journal and
  flushed to disk (for a ``.parquet`` table the journal is ``<table>.journal.csv``, converted when
  the study ends). A study run again on the same table computes only the points missing from it
  (and those that reached their time limit); the first line of the journal is the study's
  fingerprint, so a table of another study is refused, and so is a row whose parameters are not
  those of its point. A journal is never discarded silently: a byte-order mark or a lost column
  line is read through, anything else that is not a row is refused with its line number.
- **Preconditions first.** The table's folder writable, the table's rows this study's and, with a
  scheduler, the scheduler answering as one (:func:`connect`, within :data:`CONNECT_TIMEOUT`) are
  checked before the table is changed: even a restart replaces the finished rows only once the
  points can run.
- **Robust.** A point that raises is a row with status ``'failed'`` and the error; so is a point
  that reaches the study's ``time_limit`` (:mod:`.point`: raised in the point's thread, serially,
  on the pool and on Dask). The local pool's workers are processes of this runner's own: one that
  is still busy a grace period after the limit (stuck in one compiled call) is killed and replaced,
  and every worker ends when its parent does (``PR_SET_PDEATHSIG`` on Linux and a watchdog on its
  parent's pid: a runner killed by SIGTERM or SIGKILL leaves no worker behind). Ctrl-C stops the
  workers and leaves the journal with the finished points (a line cut short is dropped when it is
  read).
"""
from __future__ import annotations

import asyncio
import collections
import ctypes
import multiprocessing
import multiprocessing.connection
import os
import signal
import sys
import tempfile
import threading
import time
from pathlib import Path
from typing import Any, Callable

from ..errors import ParameterError, WorkerError
from ..results.study import STATUS_COLUMNS, StudyTable, format_row, header_line, read_csv_rows
from .definition import Random, Study
from .point import TIME_LIMIT_ERROR, evaluate_point, time_limit_row
from .quantities import QUANTITIES

__all__ = ["run_study", "evaluate_point", "tasks", "TableConflict", "SchedulerError", "connect", "CONNECT_TIMEOUT"]

#: Seconds a Dask scheduler has to answer as one (its handshake and its list of workers) before
#: :func:`connect` refuses its address: nothing listening, a host that does not answer, or a
#: service that is not a Dask scheduler.
CONNECT_TIMEOUT = 10.0


class TableConflict(ParameterError):
    """The table holds rows that are not this study's (another study's, other columns, a row whose
    parameters are not its point's): overwrite it only when asked."""

    def __init__(self, reason: str):
        self.reason = reason
        super().__init__(self.advice("restart=True"))

    def advice(self, restart: str) -> str:
        """The message with the way to overwrite the table of the caller's interface (``restart``:
        ``'restart=True'`` in Python, ``'--restart'`` on the command line)."""
        return f"{self.reason}: choose another table, or {restart} to overwrite it"


class SchedulerError(ParameterError):
    """No Dask scheduler answers at the study's ``scheduler`` address (why in :attr:`reason`)."""

    def __init__(self, reason: str):
        self.reason = reason
        super().__init__(f"scheduler: {reason}")


async def _handshake(address: str, timeout: float) -> None:
    """Reach the Dask scheduler at ``address`` and hear it answer as one, within ``timeout`` [s]
    (Dask's own connect bounds the TCP connection, not the handshake: a service that accepts and
    never answers would hold it forever)."""
    from distributed import Client

    client = Client(address, asynchronous=True, timeout=timeout, set_as_default=False)
    try:
        await asyncio.wait_for(client, timeout)
        await asyncio.wait_for(client.scheduler.identity(), timeout)
    finally:
        try:
            await asyncio.wait_for(client.close(), timeout)
        except Exception:  # noqa: BLE001 - closing a client that never connected: nothing to keep
            pass


def connect(scheduler: str, timeout: float | None = None):
    """A ``distributed.Client`` of the Dask scheduler at ``scheduler``, once it has answered as one.

    Parameters
    ----------
    scheduler : str
        The scheduler's address, ``tcp://host:port``.
    timeout : float, optional
        Seconds it has to answer (default :data:`CONNECT_TIMEOUT`).

    Returns
    -------
    distributed.Client

    Raises
    ------
    SchedulerError
        Nothing answers at the address within ``timeout``, or what answers is not a Dask scheduler
        (the reason, in one line); the handshake runs in a thread of its own, so that this returns
        within about three times ``timeout`` whatever answers.
    ParameterError
        ``scheduler`` is not an address, or Dask's distributed is not installed.
    """
    try:
        from distributed import Client
    except ImportError:  # pragma: no cover - distributed is in the 'cluster' and 'test' extras
        raise ParameterError("scheduler: Dask's distributed is not installed (pip install 'frictionjoint[cluster]')") from None
    if not isinstance(scheduler, str):
        raise ParameterError(f"scheduler must be an address (tcp://host:port) or a distributed.Client, got {scheduler!r}")
    limit = CONNECT_TIMEOUT if timeout is None else float(timeout)
    outcome: list = []

    def probe():
        try:
            asyncio.run(_handshake(scheduler, limit))
            outcome.append(None)
        except BaseException as exc:  # noqa: BLE001 - any failure to talk to it: the address is refused
            outcome.append(exc)
    thread = threading.Thread(target=probe, name="dask-handshake", daemon=True)
    thread.start()
    thread.join(3 * limit + 5.0)  # connect, identity and close, each bounded by the limit
    why = None
    if not outcome or isinstance(outcome[0], (asyncio.TimeoutError, TimeoutError)):
        why = f"no answer within {limit:g} s"
    elif outcome[0] is not None:
        exc = outcome[0]
        text = " ".join(str(exc).split())
        text = f"{type(exc).__name__}: {text[:200]}" if text else type(exc).__name__
        # an OSError is the connection's (refused, reset, closed); anything else, the answer's
        why = f"the connection failed: {text}" if isinstance(exc, OSError) else \
            f"what answers is not a Dask scheduler: {text}"
    if why is None:
        try:
            return Client(scheduler, timeout=limit, set_as_default=False)  # it answered: this connects at once
        except Exception as exc:  # noqa: BLE001 - gone since: refused as above
            why = f"{type(exc).__name__}: {exc}"
    raise SchedulerError(f"no Dask scheduler at {scheduler!r} ({why}); start one with 'dask scheduler', or check "
                         "the address")


def tasks(study: Study) -> list[dict]:
    """The study's points as self-contained tasks (picklable: the model, the sweep, the point's
    parameters and its time limit)."""
    kinds = {k: v for k, v in study.kinds.items() if v != "real"}
    return [dict(point=k, model=study.model, omega=study.omega, fixed=dict(study.fixed), varied=p,
                 direction=study.direction, method=study.method, harmonics=int(study.harmonics),
                 refine=bool(study.refine_peak), kinds=kinds, time_limit=float(study.time_limit),
                 mode_damping=study.mode_damping)
            for k, p in enumerate(study.points())]


def _journal_path(table: Path) -> Path:
    return table if table.suffix == ".csv" else table.with_name(table.name + ".journal.csv")


def _done_rows(table: Path, journal: Path, fingerprint: str, columns: tuple, all_tasks: list[dict]) -> list[dict]:
    """The rows already computed for this study (from its journal, or a finished Parquet table):
    whole rows, one per point, each with its point's parameters; not those that reached their time
    limit (computed again). Reads only: nothing is changed."""
    if journal.exists():
        fp, _, found, rows = read_csv_rows(journal, columns)
        source = journal
    elif table.exists():
        done = StudyTable.read(table)
        fp, found, rows, source = done.fingerprint, list(done.columns), done.rows(), table
    else:
        return []
    if fp is None and not rows:  # stopped before its first line was written: a new journal
        return []
    if fp is None:
        raise TableConflict(f"table {str(source)!r} has rows but not its first line (the study's fingerprint): "
                            "it cannot be told whose rows they are")
    if fp != fingerprint:
        raise TableConflict(f"table {str(source)!r} holds another study (fingerprint {fp}, this study's "
                            f"{fingerprint})")
    if not rows:  # the column line missing or cut short, no row: nothing to keep
        return []
    if tuple(found) != tuple(columns):
        raise TableConflict(f"table {str(source)!r} has the columns {found}, this study writes {list(columns)}")
    unique = {}
    for r in rows:  # one row per point of this study, with that point's parameters
        k = r.get("point")
        if not (isinstance(k, int) and 0 <= k < len(all_tasks)):
            raise TableConflict(f"table {str(source)!r} has a row of point {k!r}, this study's points are 0 to "
                                f"{len(all_tasks) - 1}")
        expected = all_tasks[k]["varied"]
        differ = {n: (r.get(n), v) for n, v in expected.items() if r.get(n) != v}
        if differ:
            shown = ", ".join(f"{n} = {got!r} (the study's {want!r})" for n, (got, want) in differ.items())
            raise TableConflict(f"table {str(source)!r}: the row of point {k} has {shown}: not this point's result")
        if str(r.get("error", "")).startswith(TIME_LIMIT_ERROR):
            continue  # the machine's, not the study's: computed again
        unique.setdefault(k, r)
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
        Compute every point again, replacing the rows already in ``table`` (default: resume,
        computing only the missing points).
    on_row : callable, optional
        Called with each new row after it is written (in this process).

    Returns
    -------
    StudyTable
        Every point, sorted by point; a point that raised or reached ``study.time_limit`` is a
        ``'failed'`` row with its error.

    Raises
    ------
    TableConflict
        ``table`` holds another study's rows, other columns, or a row whose parameters are not its
        point's (``restart=True`` overwrites it).
    SchedulerError
        No Dask scheduler answers at ``scheduler`` within :data:`CONNECT_TIMEOUT` (:func:`connect`).
    ParameterError
        A bad argument, a directory as ``table`` or a folder that cannot be written, or a table
        with a line that is not a row. Every refusal comes before the table is changed: the rows
        already in it, even with ``restart``, are replaced only once the points can run.
    WorkerError
        A pool or Dask worker died (the finished rows are kept: run again to resume).
    """
    # every precondition before anything finished is touched: the arguments, the table's folder
    # writable, the table read (another study's is refused), the scheduler answering as one
    table = _checked_arguments(study, table, workers, scheduler)
    all_tasks = tasks(study)
    fingerprint = study.fingerprint()
    columns = ("point", *study.varied, *QUANTITIES, *STATUS_COLUMNS)
    journal = _journal_path(table)
    done = [] if restart else _done_rows(table, journal, fingerprint, columns, all_tasks)
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

    client = connect(scheduler) if isinstance(scheduler, str) else scheduler
    try:
        if not todo:
            return finish(done)
        # the journal anew with the rows kept: no line cut short, no half header, no duplicate (on a
        # restart it replaces the old one here, atomically, once every precondition holds)
        _write_journal(journal, fingerprint, random, columns, done)
        if restart and journal != table and table.exists():
            table.unlink()  # the old Parquet table: its journal is the new one
        rows = list(done)
        _run_points(todo, journal, columns, rows, (len(done_ids), len(all_tasks)), progress, on_row,
                    client, workers, study.time_limit)
        return finish(rows)
    finally:
        if client is not scheduler:  # our own client, not the caller's
            client.close()


def _checked_arguments(study, table, workers, scheduler) -> Path:
    """The table's path, :func:`run_study`'s arguments checked (a Study; a ``.csv`` or ``.parquet``
    file, not a directory, in a folder that exists; ``workers`` an integer >= 1, not with a
    ``scheduler``)."""
    if not isinstance(study, Study):
        raise ParameterError(f"study must be a Study (frictionjoint.study.load_study), got {type(study).__name__}")
    table = Path(table if table is not None else (study.table or "study.csv"))
    if table.suffix not in (".csv", ".parquet"):
        raise ParameterError(f"table must end in .csv or .parquet, got {str(table)!r}")
    for p in (table, _journal_path(table)):
        if p.is_dir():
            raise ParameterError(f"table {str(p)!r} is a directory: give a file name ending in .csv or .parquet")
    folder = table.absolute().parent
    if not folder.is_dir():
        raise ParameterError(f"table: the folder of {str(table)!r} does not exist")
    try:  # writable (a read-only mount, permissions): tried, not guessed from the mode bits
        tempfile.TemporaryFile(dir=folder).close()
    except OSError as exc:
        raise ParameterError(f"table: cannot write in the folder of {str(table)!r} ({exc.strerror or exc})") from None
    if workers is not None and (isinstance(workers, bool) or not isinstance(workers, int) or workers < 1):
        raise ParameterError(f"workers must be an integer >= 1, got {workers!r}")
    if workers is not None and scheduler is not None:
        raise ParameterError("workers is for the local pool; a Dask cluster has its own workers (scheduler)")
    if scheduler is not None and not isinstance(scheduler, str):
        from distributed import Client

        if not isinstance(scheduler, Client):
            raise ParameterError(f"scheduler must be an address (tcp://host:port) or a distributed.Client, got "
                                 f"{scheduler!r}")
    return table


def _run_points(todo, journal: Path, columns, rows: list, done_of_total: tuple, progress: bool, on_row,
                client, workers, time_limit) -> None:
    """Evaluate the points ``todo`` (on the Dask cluster of ``client``, in this process or on the local pool),
    appending each row to ``journal`` as one flushed line (a consistent journal) and to ``rows``,
    with the progress bar and ``on_row``."""
    from tqdm import tqdm

    done, total = done_of_total
    with open(journal, "a", newline="", encoding="utf-8") as f, \
            tqdm(total=total, initial=done, desc="study", unit="pt", file=sys.stderr,
                 disable=not progress, leave=False) as bar:

        def record(row):
            f.write(format_row(row, columns))  # one line per row, flushed: a consistent journal
            f.flush()
            os.fsync(f.fileno())
            rows.append(row)
            bar.update()
            if on_row is not None:
                on_row(row)

        if client is not None:
            _run_dask(todo, client, record)
        elif workers == 1:
            for t in todo:
                record(evaluate_point(t))
        else:
            _run_pool(todo, workers or os.cpu_count() or 1, record, time_limit)


#: What a worker sends when it starts a point (the point's time limit runs from there).
_STARTED = "started"
#: Seconds a spawned worker may take to start a point it was sent (its interpreter, the package's
#: imports, numba's cache) before the runner counts it as stuck.
_STARTUP = 120.0


def _grace(limit: float) -> float:
    """How long after a point's time limit [s] the local pool kills a worker still busy with it (the
    point's own limit, raised in its thread, normally ends it first: this is for one stuck in a
    compiled call): 10 % of the limit, between 2 s and 60 s."""
    return min(60.0, max(2.0, 0.1 * limit))


def _end_with_parent(parent: int) -> None:
    """End this process when its parent ``parent`` dies: the kernel's parent-death signal on Linux
    (``prctl(PR_SET_PDEATHSIG, SIGKILL)``) and, everywhere, a thread that watches the parent's pid
    (an orphan is re-parented)."""
    if sys.platform.startswith("linux"):
        try:
            ctypes.CDLL(None, use_errno=True).prctl(1, int(signal.SIGKILL), 0, 0, 0)  # 1: PR_SET_PDEATHSIG
        except (OSError, AttributeError):  # pragma: no cover - no prctl: the watchdog alone
            pass
    if os.getppid() != parent:  # the parent died before the signal was asked for
        os._exit(1)

    def watch():
        while True:
            time.sleep(0.5)
            if os.getppid() != parent:
                os._exit(1)
    threading.Thread(target=watch, name="parent-watchdog", daemon=True).start()


def _worker_main(conn, parent: int) -> None:
    """A pool worker: points from ``conn`` until ``None`` (or the runner's end)."""
    _end_with_parent(parent)
    signal.signal(signal.SIGINT, signal.SIG_IGN)  # Ctrl-C is the runner's to handle: it ends the workers
    while True:
        try:
            task = conn.recv()
        except (EOFError, OSError):
            return
        if task is None:
            return
        conn.send(_STARTED)  # the runner's clock of this point starts here, not at its start-up
        row = evaluate_point(task)
        conn.send(row)
        if str(row.get("error") or "").startswith(TIME_LIMIT_ERROR):
            # the limit was raised asynchronously, at any bytecode (a cache update, an import, a
            # compilation): this process ends, the runner starts a fresh one
            return


class _Worker:
    """One spawned worker process of the local pool and the point it runs."""

    def __init__(self, ctx):
        self.conn, child = ctx.Pipe()
        self.process = ctx.Process(target=_worker_main, args=(child, os.getpid()), daemon=True,
                                   name="frictionjoint-study-worker")
        self.process.start()
        child.close()
        self.task = None
        self.deadline = None

    def send(self, task: dict, limit: float) -> None:
        self.task = task
        # until the worker says it started the point: its start-up (a spawned interpreter
        # importing the package, numba's cache) is not the point's time
        self.deadline = time.monotonic() + limit + _grace(limit) + _STARTUP
        try:
            self.conn.send(task)
        except OSError as exc:
            raise WorkerError(f"a worker process ended before it could take point {task['point']} ({exc}); the "
                              "finished points are in the table: run the study again to resume") from None

    def started(self, limit: float) -> None:
        self.deadline = time.monotonic() + limit + _grace(limit)

    def kill(self) -> None:
        if self.process.is_alive():
            self.process.kill()
        self.process.join(5.0)
        self.conn.close()


def _run_pool(todo: list[dict], workers: int, record, limit: float) -> None:
    """The points on a local pool of spawned worker processes (no state inherited from this
    process): a worker still busy a grace period after its point's time limit is killed, its row
    the time limit's, and replaced (module docstring)."""
    ctx = multiprocessing.get_context("spawn")
    pending = collections.deque(todo)
    pool = []
    try:
        for _ in range(min(workers, len(todo))):
            pool.append(_Worker(ctx))  # one at a time: a failed spawn leaves the others to end
        while pending or any(w.task is not None for w in pool):
            for w in pool:
                if w.task is None and pending:
                    w.send(pending.popleft(), limit)
            busy = [w for w in pool if w.task is not None]
            wait = max(0.0, min(w.deadline for w in busy) - time.monotonic())
            ready = set(multiprocessing.connection.wait([w.conn for w in busy] + [w.process.sentinel for w in busy],
                                                        timeout=wait))
            for i, w in enumerate(pool):
                if w.task is None:
                    continue
                if w.conn in ready or w.conn.poll():
                    try:
                        row = w.conn.recv()
                    except (EOFError, OSError):
                        row = None
                    if row == _STARTED:
                        w.started(limit)
                        continue
                    if row is not None:
                        w.task = None
                        record(row)
                        if str(row.get("error") or "").startswith(TIME_LIMIT_ERROR):
                            w.kill()  # it ends itself (_worker_main): replaced
                            pool[i] = _Worker(ctx)
                        continue
                if w.process.sentinel in ready or not w.process.is_alive():
                    raise WorkerError(f"a worker process died (exit code {w.process.exitcode}) running point "
                                      f"{w.task['point']}; the finished points are in the table: run the study "
                                      "again to resume")
                if time.monotonic() >= w.deadline:  # stuck past its limit: killed, replaced
                    task = w.task
                    w.kill()
                    pool[i] = _Worker(ctx)
                    record(time_limit_row(task, limit))
    finally:
        for w in pool:
            if w.task is None and w.process.is_alive():
                try:
                    w.conn.send(None)
                except OSError:
                    pass
        for w in pool:
            if w.task is not None:  # interrupted: not waited for
                w.process.kill()
            w.process.join(5.0)
            if w.process.is_alive():
                w.process.kill()
                w.process.join()
            w.conn.close()


def _run_dask(todo: list[dict], client, record) -> None:
    """The points on a Dask cluster (a connected ``distributed.Client``: :func:`connect`)."""
    from distributed import as_completed as dask_completed

    futures = client.map(evaluate_point, todo, pure=False)
    try:
        for fut in dask_completed(futures, loop=client.loop):  # this client's, not the default one
            try:
                row = fut.result()
            except Exception as exc:  # noqa: BLE001 - evaluate_point returns its errors: this is the worker's death
                raise WorkerError(f"a Dask worker failed ({type(exc).__name__}: {exc}); the finished points are "
                                  "in the table: run the study again to resume") from None
            record(row)
    except BaseException:
        client.cancel(futures)
        raise

"""The table of a design study (:class:`StudyTable`): one row per point, its varied parameters, its
quantities of interest (:mod:`frictionjoint.study.quantities`), its status and error; written as
CSV (a journal the runner appends to as points finish) or Parquet (pyarrow)."""
from __future__ import annotations

import csv
import io
import math
import os
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING, Optional

import numpy as np

from ..errors import ParameterError

if TYPE_CHECKING:  # pragma: no cover
    from matplotlib.axes import Axes
    from matplotlib.figure import Figure

__all__ = ["StudyTable", "STATUS_COLUMNS", "HEADER_PREFIX", "header_line"]

#: the last columns of every row: ``'ok'``, ``'partial'`` (some frequencies without a periodic
#: orbit: the peak may be among them), ``'no orbit'`` (none converged) or ``'failed'``, and the
#: error (or what is missing)
STATUS_COLUMNS = ("status", "error")
#: first line of a CSV study table: the study's fingerprint and its random parameters follow
HEADER_PREFIX = "# frictionjoint study "


def header_line(fingerprint: str, random) -> str:
    """The first line of a CSV study table (with its newline)."""
    return f"{HEADER_PREFIX}{fingerprint} random={','.join(random)}\n"
_BOOL = ("slipping_at_peak", "peak_at_edge")
_INT = ("point", "converged_points", "points")


def format_row(row: dict, columns: tuple) -> str:
    """One CSV line (with its newline) of ``row``: floats exactly (``repr``), booleans 1/0, unknown
    empty; line breaks in text (an error's) as `` / ``, so that a row is one physical line and a
    line cut short is recognised as such."""
    def cell(v):
        if v is None:
            return ""
        if isinstance(v, (bool, np.bool_)):
            return "1" if v else "0"
        if isinstance(v, (float, np.floating)):
            return "" if math.isnan(v) else repr(float(v))
        if isinstance(v, str):
            return " / ".join(part for part in v.replace("\r\n", "\n").replace("\r", "\n").split("\n"))
        return v
    buf = io.StringIO()
    csv.writer(buf, lineterminator="\n").writerow([cell(row.get(c)) for c in columns])
    return buf.getvalue()


def _parse(column: str, text: str):
    if column in STATUS_COLUMNS:
        return text
    if text == "":
        return None if column in _BOOL else math.nan
    if column in _BOOL:
        return text == "1"
    if column in _INT:
        return int(text)
    return float(text)


def read_csv_rows(path: str | os.PathLike, columns=None) -> tuple[str | None, list[str], list[str], list[dict]]:
    """``(fingerprint, random, columns, rows)`` of a CSV study table.

    A last line cut short (no newline: the runner was stopped while writing it) is dropped; a
    byte-order mark and Windows line ends (a file saved by a Windows editor) are read through.
    Anything else that is not a row is refused, never skipped: finished rows are not lost silently.

    Parameters
    ----------
    path : str or os.PathLike
    columns : sequence of str, optional
        The columns the table should have (the runner's): a table whose column line was lost is
        read with them.

    Raises
    ------
    ParameterError
        The file is not UTF-8, has no column line (and ``columns`` is not given), or holds a whole
        line that is not a row of the table (the message gives the line's number and why).
    """
    try:
        with open(path, newline="", encoding="utf-8-sig") as f:
            text = f.read().replace("\r\n", "\n")
    except UnicodeDecodeError as exc:
        raise ParameterError(f"study table {str(path)!r} is not UTF-8 text (offset {exc.start}): not a study "
                             "table") from None
    fingerprint, random, first = None, [], 1
    if text.startswith(HEADER_PREFIX):
        line, _, text = text.partition("\n")
        fingerprint, _, rest = line[len(HEADER_PREFIX):].strip().partition(" ")
        if rest.startswith("random="):
            random = [v for v in rest[len("random="):].split(",") if v]
        first = 2
    if text and not text.endswith("\n"):
        text = text[:text.rfind("\n") + 1]
    lines = text.split("\n")[:-1]  # whole lines only; a row is one line (format_row)
    numbered = [(first + i, line) for i, line in enumerate(lines) if line.strip()]
    if not numbered:
        return fingerprint, random, [], []
    head = next(csv.reader([numbered[0][1]]))
    if head and head[0] == "point":
        found, numbered = head, numbered[1:]
    elif columns is not None:  # the column line lost: the rows read with the table's columns
        found = list(columns)
    else:
        raise ParameterError(f"study table {str(path)!r}, line {numbered[0][0]}: no column line (point, ...) "
                             "before the rows")
    rows = []
    for number, line in numbered:
        fields = next(csv.reader([line]), [])
        why = None
        if len(fields) != len(found):
            why = f"{len(fields)} fields, the table has {len(found)} columns"
        else:
            try:
                rows.append({c: _parse(c, v) for c, v in zip(found, fields)})
            except ValueError as exc:
                why = f"a value is not of its column ({exc})"
        if why is not None:
            raise ParameterError(f"study table {str(path)!r}, line {number} is not a row of the table ({why}): "
                                 "repair or remove that line")
    return fingerprint, random, found, rows


@dataclass(eq=False)
class StudyTable:
    """A study's table, one row per point, sorted by point.

    Attributes
    ----------
    columns : dict
        ``{name: (n,) ndarray}``: ``point``, the varied parameters, the quantities of interest
        (:data:`frictionjoint.study.quantities.QUANTITIES`), ``status`` and ``error``.
    varied : tuple of str
        The varied parameters.
    random : tuple of str
        The random ones among them.
    fingerprint : str
        The study's (:meth:`frictionjoint.study.Study.fingerprint`).
    path : Path, optional
        Where it was read or written.
    """

    columns: dict
    varied: tuple
    random: tuple = ()
    fingerprint: str = ""
    path: Optional[Path] = None

    def __getitem__(self, name: str) -> np.ndarray:
        if name not in self.columns:
            raise ParameterError(f"no column {name!r}; columns: {list(self.columns)}")
        return self.columns[name]

    def __len__(self) -> int:
        return int(self.columns["point"].size) if "point" in self.columns else 0

    @property
    def ok(self) -> np.ndarray:
        """Rows whose sweep converged at every frequency."""
        return self.columns["status"] == "ok"

    @property
    def partial(self) -> np.ndarray:
        """Rows with a peak but some frequencies without a periodic orbit."""
        return self.columns["status"] == "partial"

    @property
    def success(self) -> bool:
        """Every point is in the table and gave a peak (the result contract)."""
        return bool(len(self) and np.all(self.ok))

    @property
    def status(self) -> str:
        """``'ok'`` (every point ok) or ``'incomplete'``."""
        return "ok" if self.success else "incomplete"

    @property
    def message(self) -> str:
        count = {s: int(np.count_nonzero(self.columns["status"] == s)) for s in ("ok", "partial", "no orbit", "failed")}
        return (f"{len(self)} points: {count['ok']} ok, {count['partial']} with some frequencies without a periodic "
                f"orbit, {count['no orbit']} without any, {count['failed']} failed")

    @classmethod
    def from_rows(cls, rows: list[dict], columns: tuple, varied, random=(), fingerprint="", path=None) -> "StudyTable":
        rows = sorted(rows, key=lambda r: r["point"])
        cols = {}
        for c in columns:
            vals = [r.get(c) for r in rows]
            if c in STATUS_COLUMNS or c in _BOOL:
                cols[c] = np.array(vals, dtype=object)
            elif c in _INT:
                cols[c] = np.array(vals, dtype=np.int64)
            else:
                cols[c] = np.array([math.nan if v is None else v for v in vals], dtype=float)
        return cls(cols, tuple(varied), tuple(random), fingerprint, None if path is None else Path(path))

    def rows(self) -> list[dict]:
        """The rows as dicts."""
        return [{c: (v[k].item() if hasattr(v[k], "item") else v[k]) for c, v in self.columns.items()}
                for k in range(len(self))]

    def to_csv(self, path: str | os.PathLike) -> None:
        """Write the table as CSV (the study's fingerprint on the first line, floats exactly),
        atomically: a reader never sees it half-written."""
        path = Path(path)
        cols = tuple(self.columns)
        tmp = path.with_name(path.name + ".tmp")
        with open(tmp, "w", newline="", encoding="utf-8") as f:
            f.write(header_line(self.fingerprint, self.random))
            f.write(format_row({c: c for c in cols}, cols))
            for row in self.rows():
                f.write(format_row(row, cols))
        os.replace(tmp, path)

    def to_parquet(self, path: str | os.PathLike) -> None:
        """Write the table as Parquet (pyarrow; the fingerprint and the varied and random
        parameters in the schema's metadata), atomically."""
        import pyarrow as pa
        import pyarrow.parquet as pq

        path = Path(path)
        arrays = {}
        for c, v in self.columns.items():
            if c in _BOOL:
                arrays[c] = pa.array(list(v), type=pa.bool_())
            elif c in STATUS_COLUMNS:
                arrays[c] = pa.array([str(x) for x in v], type=pa.string())
            else:
                arrays[c] = pa.array(v)
        meta = {b"frictionjoint.study": self.fingerprint.encode(), b"varied": ",".join(self.varied).encode(),
                b"random": ",".join(self.random).encode()}
        table = pa.table(arrays).replace_schema_metadata(meta)
        tmp = path.with_name(path.name + ".tmp")
        pq.write_table(table, tmp)
        os.replace(tmp, path)

    def write(self, path: str | os.PathLike) -> None:
        """Write as CSV or Parquet by the suffix (``.csv``, ``.parquet``)."""
        if Path(path).suffix == ".parquet":
            self.to_parquet(path)
        else:
            self.to_csv(path)

    @classmethod
    def read(cls, path: str | os.PathLike, varied=None, random=()) -> "StudyTable":
        """Read a study table written as CSV or Parquet.

        Parameters
        ----------
        path : str or os.PathLike
        varied, random : sequence of str, optional
            The varied and random parameters (a CSV table does not record them: default the
            columns between ``point`` and the quantities).
        """
        from ..study.quantities import QUANTITIES

        path = Path(path)
        if path.is_dir():
            raise ParameterError(f"study table {str(path)!r} is a directory, not a .csv or .parquet file")
        if not path.is_file():
            raise ParameterError(f"study table {str(path)!r} does not exist")
        if path.suffix == ".parquet":
            import pyarrow as pa
            import pyarrow.parquet as pq

            try:
                t = pq.read_table(path)
            except (OSError, pa.ArrowException) as exc:
                raise ParameterError(f"study table {str(path)!r} is not a readable Parquet file ({exc})") from None
            meta = t.schema.metadata or {}
            columns = t.column_names
            rows = t.to_pylist()
            fingerprint = meta.get(b"frictionjoint.study", b"").decode()
            if varied is None:
                varied = [v for v in meta.get(b"varied", b"").decode().split(",") if v]
                random = [v for v in meta.get(b"random", b"").decode().split(",") if v]
        else:
            fingerprint, found, columns, rows = read_csv_rows(path)
            random = random or found
        if rows and "point" not in columns:
            raise ParameterError(f"study table {str(path)!r} has no column 'point': not a study table")
        if varied is None:
            varied = [c for c in columns if c != "point" and c not in QUANTITIES and c not in STATUS_COLUMNS]
        return cls.from_rows(rows, tuple(columns), varied, random, fingerprint or "", path)

    def percentiles(self, column: str = "peak_amplitude", q=(5.0, 50.0, 95.0)) -> dict:
        """``{q: value}`` of a quantity over the rows that converged at every frequency."""
        v = np.asarray(self[column], float)[self.ok]
        v = v[np.isfinite(v)]
        if v.size == 0:
            return {float(p): math.nan for p in q}
        return {float(p): float(np.percentile(v, p)) for p in q}

    def plot(self, ax: Axes | None = None, path: str | os.PathLike | None = None,
             quantity: str = "peak_amplitude") -> Figure:
        """The plot that suits the study (:mod:`frictionjoint.plotting`): a Monte Carlo study
        (random parameters) its scatter against each random parameter and the histogram with
        percentiles; two grid parameters a contour of ``quantity``; one grid parameter the curve
        of ``quantity`` against it with its minimum marked (the damper curve).

        Parameters
        ----------
        ax : matplotlib Axes, optional
            Draw into these axes (curve and contour only).
        path : str or os.PathLike, optional
            Write the figure there.
        quantity : str
            A quantity column.
        """
        from ..plotting import plot_study_contour, plot_study_curve, plot_study_monte_carlo, plot_target

        ax, path = plot_target(ax, path)

        grid = [v for v in self.varied if v not in self.random]
        if self.random:
            return plot_study_monte_carlo(self, quantity, path=path)
        if len(grid) == 2:
            return plot_study_contour(self, grid[0], grid[1], quantity, ax=ax, path=path)
        return plot_study_curve(self, grid[0], quantity, ax=ax, path=path)

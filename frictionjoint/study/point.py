"""One study point: its frequency sweep, its peak refined between the sweep's points, and its row
of quantities (:mod:`.quantities`). Self-contained and picklable, for any worker.

A point has a time limit (the study's ``time_limit``): at the limit :class:`PointTimeLimit` is
raised in the thread that runs the point (``PyThreadState_SetAsyncExc``: it works in any thread,
the main one of a pool worker or of ``workers=1`` and a Dask worker's threads alike, where a signal
could not be used) and again every second until the point ends (a library's ``except
BaseException`` may swallow one). It is delivered between two Python bytecodes: a point inside one
long compiled call (a numba kernel, a LAPACK call) ends when that call returns; on the local pool
the runner also ends such a worker process a grace period after the limit
(:mod:`.execution`). The row of such a point is ``'failed'`` with an error that starts with
:data:`TIME_LIMIT_ERROR`.
"""
from __future__ import annotations

import ctypes
import math
import threading
from typing import TYPE_CHECKING

import numpy as np
import scipy.optimize

from ..errors import ParameterError
from ..threads import owns_blas_threads
from .definition import ModeDamping, _base_model
from .quantities import QUANTITIES, mode_amplitudes, quantities

if TYPE_CHECKING:  # pragma: no cover
    from ..system import FrictionSystem

__all__ = ["evaluate_point", "mode_quantities", "PointTimeLimit", "TIME_LIMIT_ERROR", "time_limit_row"]

#: relative tolerance of a refined peak's frequency
PEAK_XTOL = 1e-7
#: how the error of a point that reached its time limit starts (a resumed study computes it again)
TIME_LIMIT_ERROR = "TimeLimit:"


class PointTimeLimit(BaseException):
    """Raised in a point's thread at its time limit (a ``BaseException``, as ``KeyboardInterrupt``:
    the solvers' ``except Exception`` do not take it for a failure of their own)."""


def _raise_in(thread_id: int, exc) -> None:
    """Raise ``exc`` in the thread ``thread_id`` at its next bytecode (``None``: clear a pending one)."""
    ctypes.pythonapi.PyThreadState_SetAsyncExc(ctypes.c_ulong(thread_id),
                                               None if exc is None else ctypes.py_object(exc))


class _Deadline:
    """Raise :class:`PointTimeLimit` in this thread after ``seconds`` (module docstring), and every
    second after that, until the ``with`` block ends; nothing is raised after it has ended."""

    def __init__(self, seconds: float | None):
        self.seconds = seconds
        self._lock = threading.Lock()
        self._done = False
        self._fired = False
        self._timer = None

    def __enter__(self):
        self._thread = threading.get_ident()
        if self.seconds is not None:
            self._arm(self.seconds)
        return self

    def _arm(self, delay: float) -> None:
        self._timer = threading.Timer(delay, self._fire)
        self._timer.daemon = True
        self._timer.start()

    def _fire(self) -> None:
        with self._lock:
            if self._done:
                return
            self._fired = True
            _raise_in(self._thread, PointTimeLimit)
            self._arm(1.0)

    def _finish(self) -> None:
        with self._lock:
            self._done = True
            if self._timer is not None:
                self._timer.cancel()
            if self._fired:
                _raise_in(self._thread, None)  # one not yet delivered is dropped

    def __exit__(self, *exc_info) -> bool:
        while True:
            try:
                self._finish()
                return False
            except PointTimeLimit:  # delivered in here: finish again (after that, none is raised)
                continue


def _failed(row: dict, error: str) -> dict:
    row.update({q: math.nan for q in QUANTITIES})
    row.update(slipping_at_peak=None, peak_at_edge=None, converged_points=0, points=0, status="failed", error=error)
    return row


def time_limit_row(task: dict, seconds: float) -> dict:
    """The failed row of a point that did not finish within ``seconds``."""
    return _failed({"point": task["point"], **task["varied"]},
                   f"{TIME_LIMIT_ERROR} the point did not finish within {seconds:g} s (the study's time_limit; a "
                   "study run again computes it again)")


def _refined_peak(asm, fr, method: str, harmonics: int):
    """The peak between the sweep's points around its largest one: ``(omega, amplitude,
    dissipated, slipping)``, or None (no neighbours, or the refinement failed).

    Time domain: :meth:`BladeAssembly.peak <frictionjoint.structures.BladeAssembly.peak>` (exact
    steady states, bounded search) and the steady state at the peak. Harmonic balance: a bounded
    search of the balance's tip amplitude (same ``H``)."""
    from ..solvers.frequency_domain.hbm import harmonic_balance
    from ..solvers.steady_state import periodic_response

    ok = np.asarray(fr.converged, bool)
    w, a = np.asarray(fr.omega, float)[ok], np.asarray(fr.amplitude, float)[ok]
    if w.size < 2:
        return None
    i = int(np.argmax(a))
    nb = [w[j] for j in (i - 1, i + 1) if 0 <= j < w.size]
    lo, hi = min(nb + [w[i]]), max(nb + [w[i]])
    row = asm._row(fr.output)
    if method == "time":
        w_pk, a_pk = asm.peak(lo, hi, fr.output, n_grid=5, xtol=PEAK_XTOL)
        if not math.isfinite(a_pk):
            return None
        r = periodic_response(asm.system(w_pk), peaks=False)
        return (w_pk, a_pk, r.dissipated_per_cycle, not r.stuck) if r.converged else None

    def balance(om):
        return harmonic_balance(asm.system(float(om)), n_harmonics=harmonics)

    def neg(om):
        hb = balance(om)
        return -abs(hb.harmonics[1] @ row) if hb.converged else 0.0
    res = scipy.optimize.minimize_scalar(neg, bounds=(lo, hi), method="bounded", options={"xatol": PEAK_XTOL * hi})
    hb = balance(res.x)
    if not hb.converged:
        return None
    return float(res.x), float(abs(hb.harmonics[1] @ row)), hb.dissipated_per_cycle, not hb.stuck


def mode_quantities(system: FrictionSystem, mode: int, amplitude: float, n_harmonics: int,
                    dof: str | int | None) -> tuple[dict, str]:
    """The nonlinear mode's quantities (:data:`~.quantities.MODE_QUANTITIES`) of ``system`` at
    ``amplitude``: :func:`~frictionjoint.nonlinear_mode` over
    :func:`~.quantities.mode_amplitudes`, its last point.

    Parameters
    ----------
    system : FrictionSystem
        The point's system (its excitation is removed by the mode).
    mode : int
        The stuck system's mode, from 0.
    amplitude : float
        First-harmonic amplitude at ``dof`` [m], > 0.
    n_harmonics : int
        ``H`` >= 1.
    dof : str or int or None
        The DOF of the amplitude (None: the mode's default).

    Returns
    -------
    values : dict
        ``{name: value}`` of ``mode_frequency`` [rad/s] and ``mode_damping_ratio`` (NaN where the
        mode did not converge there).
    error : str
        Empty, or why the mode has no value at the amplitude.
    """
    from ..solvers.frequency_domain.nonlinear_mode import nonlinear_mode

    nm = nonlinear_mode(system, mode=mode, amplitudes=mode_amplitudes(amplitude), n_harmonics=n_harmonics, dof=dof)
    values = {"mode_frequency": float(nm.frequency[-1]), "mode_damping_ratio": float(nm.damping_ratio[-1])}
    return values, ("" if nm.converged[-1] else f"the nonlinear mode did not converge at {amplitude:g} m ({nm.message})")


def _mode_row(asm, omega: float, declared) -> tuple[dict, str]:
    """The nonlinear mode's quantities of a point's blade (:func:`mode_quantities`) for the
    declaration ``declared`` (a :class:`~.definition.ModeDamping` or its keys), at its DOF or the
    root's tangential DOF."""
    md = ModeDamping.from_table(declared)
    dof = md.dof if md.dof is not None else getattr(asm.joints[0], "tangential_dof", None) if asm.joints else None
    return mode_quantities(asm.system(omega), md.mode, md.amplitude, md.n_harmonics, dof)


@owns_blas_threads
def evaluate_point(task: dict) -> dict:
    """One point's row: its sweep (:func:`frictionjoint.sweep`; a blade's peak refined between the
    sweep's points) and quantities of interest; an exception, or the point's time limit, is the
    row's error (status ``'failed'``), not the study's.

    Parameters
    ----------
    task : dict
        ``point``, ``model``, ``omega`` (the frequencies [rad/s], any form of
        :mod:`frictionjoint.frequencies`), ``fixed``, ``varied``, ``direction``, ``method``,
        ``harmonics``, ``refine``, and optionally ``kinds`` (``{parameter: 'real' | 'int' |
        'bool'}``), ``time_limit`` [s] (:func:`frictionjoint.study.execution.tasks`) and
        ``mode_damping`` (a :class:`~.definition.ModeDamping`: the nonlinear mode's columns).

    Returns
    -------
    dict
        The row: ``point``, the varied parameters, :data:`~.quantities.QUANTITIES`, ``status``
        (``'ok'``; ``'partial'``: some frequencies without a periodic orbit, the peak may be among
        them, or no nonlinear mode at the declared amplitude; ``'no orbit'``; ``'failed'``) and
        ``error``.
    """
    from ..frequencies import check_omegas
    from ..sweep import blade_assembly, sweep

    row = {"point": task["point"], **task["varied"]}
    limit = task.get("time_limit")
    try:
        with _Deadline(limit):
            ws = np.sort(check_omegas("omega", task["omega"]))  # 'up': increasing, whatever the order given
            params = {**task["fixed"], **task["varied"]}
            for name, kind in dict(task.get("kinds") or {}).items():  # a switch or a count as such (1.0 -> True)
                if name in params and kind in ("bool", "int"):
                    params[name] = bool(params[name]) if kind == "bool" else int(params[name])
            model = task["model"]
            base = _base_model(model)
            refined = None
            if base is not None:  # a blade: swept in the library, its peak refined
                asm = blade_assembly(base, params)
                fr = asm.frequency_response(ws if task["direction"] == "up" else ws[::-1], method=task["method"],
                                            n_harmonics=task["harmonics"])
                if task.get("refine", True):
                    refined = _refined_peak(asm, fr, task["method"], task["harmonics"])
            else:
                fr = sweep(model, ws, params, direction=task["direction"], method=task["method"],
                           n_harmonics=task["harmonics"])
            row.update(quantities(fr.omega, fr.amplitude, fr.converged, fr.dissipated_per_cycle, fr.stuck, refined))
            mode_error = ""
            if task.get("mode_damping") is not None:
                if base is None:
                    raise ParameterError("quantities.mode_damping: the nonlinear mode needs the blade itself, not an FMU")
                try:  # a mode that fails leaves the sweep's columns: the row is partial, not failed
                    values, mode_error = _mode_row(asm, float(ws[0]), task["mode_damping"])
                    row.update(values)
                except Exception as exc:  # noqa: BLE001 - the mode's error is the row's, the sweep's columns stay
                    mode_error = f"quantities.mode_damping: {type(exc).__name__}: {exc}"
        n_ok, n_all = row["converged_points"], row["points"]
        # 'partial': frequencies without a periodic orbit, the peak may lie among them
        errors = [f"{n_all - n_ok} of {n_all} frequencies without a periodic orbit"] if n_ok < n_all else []
        row.update(status="ok" if n_ok == n_all and not mode_error else ("partial" if n_ok else "no orbit"),
                   error="; ".join(errors + ([mode_error] if mode_error else [])))
    except PointTimeLimit:
        return time_limit_row(task, limit)
    except Exception as exc:  # noqa: BLE001 - a failed point is a row of the table, the study goes on
        return _failed(row, f"{type(exc).__name__}: {exc}")
    return row

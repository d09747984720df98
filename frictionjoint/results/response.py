"""Result objects: time responses, periodic (steady-state) responses, co-simulation records.

The result contract, shared by every result of :mod:`frictionjoint.results`: ``success``
(bool), ``status`` (a word) and ``message`` (a sentence); a failed computation is a status of
its result, not an exception. Results of many points (sweeps, maps) also keep each point's
solver message in ``messages``.
"""
from __future__ import annotations

import os
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any, Optional

import numpy as np
from numpy.typing import ArrayLike

if TYPE_CHECKING:  # computing never imports matplotlib
    from matplotlib.axes import Axes

__all__ = ["TimeResponse", "PeriodicResponse", "CoSimulationResult", "STABILITY_MARGIN", "collection_status"]


@dataclass
class TimeResponse:
    """Response of a marched simulation at the requested times.

    Arrays hold only what was requested (``record``); the others are ``None``.

    Attributes
    ----------
    t : (n_t,) ndarray
        Times [s].
    x, v : (n_dof, n_t) ndarray or (n_t,) for single-DOF APIs
        Displacement [m] and velocity [m/s].
    friction_force : (n_elements, n_t) ndarray or (n_t,)
        Element forces [N], restoring convention (the structure feels ``-T d``).
    events : EventLog
        Every event: time, element, slider, kind.
    work, stored_energy, dissipated_friction, dissipated_viscous : (n_t,) ndarray
        Energy accounting [J] when ``'energy'`` was recorded: work of the applied forces since the
        start, stored (kinetic + elastic, incl. Jenkins springs) energy, energy dissipated by
        friction and by viscous damping since the start.
    success : bool
        False when the march failed (no consistent stick/slip status, chattering, a non-finite
        state): the outputs after the failure are NaN and ``message`` says what happened.
    message : str
    """

    t: np.ndarray
    x: Optional[np.ndarray] = None
    v: Optional[np.ndarray] = None
    friction_force: Optional[np.ndarray] = None
    events: object = None
    work: Optional[np.ndarray] = None
    stored_energy: Optional[np.ndarray] = None
    dissipated_friction: Optional[np.ndarray] = None
    dissipated_viscous: Optional[np.ndarray] = None
    success: bool = True
    message: str = "ok"
    final_state: object = field(default=None, repr=False)

    @property
    def status(self) -> str:
        """``'ok'`` or ``'failed'`` (the result contract's word for ``success``)."""
        return "ok" if self.success else "failed"

    def energy_residual(self) -> np.ndarray:
        """``work - (stored - stored[0]) - dissipated``: zero for an exact solution [J]."""
        if self.work is None:
            raise ValueError("energy was not recorded: simulate(..., record=(..., 'energy'))")
        return (self.work - (self.stored_energy - self.stored_energy[0])
                - self.dissipated_friction - self.dissipated_viscous)

    def plot(self, ax: Axes | None = None, path: str | os.PathLike | None = None, **kwargs: Any) -> Axes:
        """Plot displacement against time (see :func:`frictionjoint.plotting.plot_time_response`).

        Parameters
        ----------
        ax : matplotlib.axes.Axes, optional
            Draw into these axes (a new figure if omitted).
        path : str or os.PathLike, optional
            Write the figure there (format from the extension).
        **kwargs
            Passed to ``Axes.plot`` for the displacement lines.

        Returns
        -------
        matplotlib.axes.Axes
            The axes of the displacement.
        """
        from ..plotting import plot_target, plot_time_response

        ax, path = plot_target(ax, path)
        return plot_time_response(self, ax=ax, path=path, **kwargs)


@dataclass
class PeriodicResponse:
    """Periodic steady state over one excitation period.

    Attributes
    ----------
    omega : float
        Excitation angular frequency [rad/s].
    amplitude : float or (n_dof,) ndarray
        Max ``|x|`` over one steady period [m].
    phase : float or (n_dof,) ndarray
        Phase lag [rad] of the first harmonic of ``x`` behind ``cos(omega t)``.
    harmonic_amplitude : float or (n_dof,) ndarray
        Amplitude of the first harmonic of ``x`` [m].
    stops_per_cycle : int
        Stops of finite duration (slip -> stick) per period, over all sliders.
    stuck : bool
        True when nothing slips over the whole period (permanent stick): no slider's slip exceeds
        1e-12 of its displacement amplitude (a flank shaken down to its slip limit touches it
        every cycle, a slip of rounding size).
    converged : bool
        True when a periodic orbit was found to tolerance.
    unique : bool
        False when the orbit belongs to a family (period map with an eigenvalue 1).
    message : str
        What happened, in words.
    status : str
        ``'periodic'``, ``'unbounded'`` (grows without bound), ``'not converged'`` or ``'failed'``
        (the march itself failed: no consistent stick/slip status, chattering, a non-finite
        state; ``message`` says which). Failures are statuses, not exceptions.
    periods : float
        Number of excitation periods marched (all shooting iterations included).
    state : ndarray
        ``[x, v, w]`` at ``section_time`` on the orbit.
    section_time : float
        Time within the period [s] at which the orbit state is given.
    initial_state : ndarray
        ``[x, v, w]`` on the orbit at ``t = 0`` (a start that needs no transient).
    events : EventLog
        Events of the final period.
    dissipated_per_cycle : float
        Energy dissipated by friction over one period [J].
    floquet_multipliers : ndarray or None
        Eigenvalues of the period map's Jacobian (the monodromy matrix) at the orbit; None when no
        orbit was found. Exact (closed-form monodromy: the pieces' transition matrices times the
        saltation matrices of the events) for the library's models; from a finite-difference
        Jacobian (about 1e-7) for a stepping driver such as an FMU.
    stable : bool or None
        True when every multiplier lies inside the unit circle by more than
        :data:`STABILITY_MARGIN` (asymptotically stable orbit); None when no orbit was found.
    """

    omega: float
    amplitude: object
    phase: object
    harmonic_amplitude: object
    stops_per_cycle: int
    stuck: bool
    converged: bool
    unique: bool
    message: str
    periods: float
    status: str = "periodic"
    state: np.ndarray = field(repr=False, default=None)
    section_time: float = 0.0
    initial_state: np.ndarray = field(repr=False, default=None)
    events: object = field(repr=False, default=None)
    dissipated_per_cycle: float = float("nan")
    t: Optional[np.ndarray] = field(repr=False, default=None)
    x: Optional[np.ndarray] = field(repr=False, default=None)
    harmonics: Optional[dict] = field(repr=False, default=None)
    floquet_multipliers: Optional[np.ndarray] = field(repr=False, default=None)
    stable: Optional[bool] = None

    @property
    def success(self) -> bool:
        """True when a periodic orbit was found (``converged``; the result contract's name)."""
        return bool(self.converged)

    def set_multipliers(self, multipliers: ArrayLike) -> None:
        """Store the Floquet multipliers and the stability verdict they give.

        Sets :attr:`floquet_multipliers` and :attr:`stable` (True when every multiplier has
        modulus below ``1 - STABILITY_MARGIN``; True for an empty set).

        Parameters
        ----------
        multipliers : (n_state,) array_like of complex
            Eigenvalues of the monodromy matrix (the period map's Jacobian) at the orbit [-].
        """
        self.floquet_multipliers = np.asarray(multipliers)
        self.stable = bool(np.max(np.abs(self.floquet_multipliers), initial=0.0) < 1.0 - STABILITY_MARGIN)


#: an orbit is stable when every Floquet multiplier has modulus below 1 - STABILITY_MARGIN (the
#: finite-difference monodromy is good to about 1e-7; a neutral multiplier, e.g. of a family of
#: orbits, is not stability)
STABILITY_MARGIN = 1e-6


@dataclass
class CoSimulationResult:
    """Recorded outputs of a co-simulation at its communication points.

    Attributes
    ----------
    t : (n_t,) ndarray
        Communication points [s].
    values : dict
        ``"component.variable"`` -> (n_t,) ndarray of its values (units as the FMU declares).
    step : float
        Communication step [s].
    host : str
        Which master ran it (this library's, or a native host such as Ecos).
    success : bool
    message : str
    """

    t: np.ndarray
    values: dict
    step: float
    host: str = ""
    success: bool = True
    message: str = "ok"

    def __post_init__(self):
        failure = None if self.success else f"the co-simulation ({self.host or 'host'}) failed: {self.message}"
        self.values = RecordedOutputs(self.values, failure)

    @property
    def status(self) -> str:
        """``'ok'`` or ``'failed'`` (the result contract's word for ``success``)."""
        return "ok" if self.success else "failed"

    def __getitem__(self, name: str) -> np.ndarray:
        return self.values[name]


class OutputNotRecordedError(KeyError):
    """An output a :class:`CoSimulationResult` does not hold: the message says why (its run
    failed, with the reason, or the name was not among the recorded outputs)."""

    def __str__(self) -> str:  # KeyError's str is the repr of its argument
        return str(self.args[0]) if self.args else ""


class RecordedOutputs(dict):
    """``"component.variable"`` -> values; a name it does not hold raises
    :class:`OutputNotRecordedError` saying why, not a bare ``KeyError``.

    Parameters
    ----------
    values : mapping or iterable of pairs
        ``"component.variable"`` -> (n_t,) ndarray.
    failure : str, optional
        Why the run recorded nothing (None when it succeeded).
    """

    def __init__(self, values: Any = (), failure: Optional[str] = None):
        super().__init__(values)
        self.failure = failure

    def __missing__(self, name):
        if self.failure is not None:
            raise OutputNotRecordedError(f"no values of {name!r}: {self.failure}")
        raise OutputNotRecordedError(f"{name!r} was not recorded; the recorded outputs are {sorted(self)}")


def collection_status(converged: ArrayLike, noun: str = "points") -> tuple[str, str]:
    """``(status, message)`` of a result made of many points (a sweep, a map).

    Parameters
    ----------
    converged : array_like of bool
        Per point: its computation succeeded.
    noun : str
        What the points are called in the message.

    Returns
    -------
    status : str
        ``'ok'`` (every point), ``'partial'`` (some) or ``'failed'`` (none, or no points).
    message : str
        E.g. ``'97 of 100 points converged'``.
    """
    ok = np.asarray(converged, dtype=bool)
    n, k = int(ok.size), int(np.count_nonzero(ok))
    status = "ok" if n and k == n else ("partial" if k else "failed")
    return status, f"{k} of {n} {noun} converged"


class PointsContract:
    """The result contract of a result made of many points (a sweep, a map) with a ``converged``
    array: ``success`` (every point converged), ``status`` and ``message``
    (:func:`collection_status`); each point's solver message is in its ``messages``."""

    converged: np.ndarray

    @property
    def success(self) -> bool:
        """True when every point converged (and there is at least one)."""
        return self.status == "ok"

    @property
    def status(self) -> str:
        """``'ok'`` (every point converged), ``'partial'`` or ``'failed'`` (none, or no points)."""
        return collection_status(self.converged)[0]

    @property
    def message(self) -> str:
        """How many points converged (each point's solver message: ``messages``)."""
        return collection_status(self.converged)[1]

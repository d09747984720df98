"""The march's records: the event log and the state between events (:mod:`.events`)."""
from __future__ import annotations

import math

import numpy as np

__all__ = ["EventLog", "MarchState", "EVENT_KINDS"]

EVENT_KINDS = ("stick", "slip", "normal stop", "abnormal stop", "lift-off", "closure")


class EventLog:
    """Events in time order: ``time`` [s], ``element`` and ``slider`` indices, ``kind``.

    Kinds: ``'stick'`` (slip -> stick, a stop of finite duration begins), ``'slip'``
    (stick -> slip, start to slide), ``'normal stop'`` (zero-duration stop with reversal),
    ``'abnormal stop'`` (zero-duration stop, same direction), and with normal-load variation
    ``'lift-off'`` (the slider's contact opens) and ``'closure'`` (it closes again).
    """

    def __init__(self):
        self.time: list[float] = []
        self.element: list[int] = []
        self.slider: list[int] = []
        self.kind: list[str] = []

    def append(self, t: float, element: int, slider: int, kind: str) -> None:
        """Record one event.

        Parameters
        ----------
        t : float
            Event time [s].
        element : int
            Index of the element that owns the slider.
        slider : int
            Index of the slider (among the system's ``n_sliders``).
        kind : str
            One of :data:`EVENT_KINDS`: ``'stick'``, ``'slip'``, ``'normal stop'`` or
            ``'abnormal stop'``.
        """
        self.time.append(float(t))
        self.element.append(int(element))
        self.slider.append(int(slider))
        self.kind.append(kind)

    def __len__(self) -> int:
        return len(self.time)

    def __iter__(self):
        return iter(zip(self.time, self.element, self.slider, self.kind))

    def count(self, kind: str, t_start: float = -math.inf, t_stop: float = math.inf) -> int:
        """Number of events of ``kind`` with ``t_start <= time < t_stop``.

        Parameters
        ----------
        kind : str
            Event kind, one of :data:`EVENT_KINDS`.
        t_start : float, optional
            Start of the time window [s] (included); default: no lower bound.
        t_stop : float, optional
            End of the time window [s] (excluded); default: no upper bound.

        Returns
        -------
        int
            The number of such events.
        """
        return sum(1 for t, k in zip(self.time, self.kind) if k == kind and t_start <= t < t_stop)

    def __repr__(self) -> str:
        return f"EventLog({len(self)} events)"


class MarchState:
    """Complete state of a marched system (copyable; what FMU state save/restore captures).

    Attributes
    ----------
    t : float
        Time [s].
    x, v : (n_dof,) ndarray
        Displacement [m] and velocity [m/s].
    w : (n_sliders,) ndarray
        Slider positions [m] along each slider's direction (used by Jenkins sliders).
    status : (n_sliders,) int ndarray
        0 stuck, +1/-1 slipping in the positive/negative direction.
    v_scale : float or None
        The marcher's velocity scale (the zero band of the velocity events follows it), carried
        with the state so that a march restarted from a copy -- by any marcher of the same system
        -- continues bit for bit; None: the marcher's own (a state built by hand).
    """

    __slots__ = ("t", "x", "v", "w", "status", "v_scale")

    def __init__(self, t, x, v, w, status, v_scale=None):
        self.t = float(t)
        self.x = np.array(x, dtype=float)
        self.v = np.array(v, dtype=float)
        self.w = np.array(w, dtype=float)
        self.status = np.array(status, dtype=np.int8)
        self.v_scale = None if v_scale is None else float(v_scale)

    def copy(self) -> "MarchState":
        return MarchState(self.t, self.x, self.v, self.w, self.status, self.v_scale)

    def vector(self) -> np.ndarray:
        """``[x, v, w]`` as one vector."""
        return np.concatenate([self.x, self.v, self.w])

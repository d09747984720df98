"""The stick/slip pattern of a periodic orbit from its event log: which sliders stick, slip or are
open at every time of the period, exactly (the statuses change only at the events, whose times
the march located on the closed-form pieces).

A :class:`~frictionjoint.results.PeriodicResponse` keeps the events of one period from its section
time ``t_s`` (:attr:`~frictionjoint.results.PeriodicResponse.events`). Each event gives the
status of its slider after it:

======================================  ========================
event                                   status after it
======================================  ========================
``'stick'``, ``'closure'``              stuck
``'slip'``, ``'normal stop'``,          slipping (a stop of zero duration leaves it slipping,
``'abnormal stop'``                     reversed or not)
``'lift-off'``                          open
======================================  ========================

On a periodic orbit a slider's status at ``t_s`` is its status after its last event of the
period. A slider without events keeps one status over the period: it is open if its contact is
open at ``t_s`` (normal load ``<= 0``, :meth:`FrictionSystem.normal_loads
<frictionjoint.system.FrictionSystem.normal_loads>`), else stuck (a slider slipping over a whole
period without a stop would slip by a nonzero amount each period: no periodic orbit).
"""
from __future__ import annotations

import math

import numpy as np

from ...errors import ParameterError
from ...results.response import PeriodicResponse
from ...results.slip_pattern import OPEN, SLIPPING, STUCK, SlipPattern
from ...system import FrictionSystem

__all__ = ["slip_pattern", "STATUS_AFTER"]

#: the status of an event's slider after the event
STATUS_AFTER = {"stick": STUCK, "closure": STUCK, "slip": SLIPPING, "normal stop": SLIPPING,
                "abnormal stop": SLIPPING, "lift-off": OPEN}


def slip_pattern(response: PeriodicResponse, system: FrictionSystem) -> SlipPattern:
    """The status of every slider of ``system`` over one period of its periodic orbit ``response``
    (module docstring).

    Parameters
    ----------
    response : PeriodicResponse
        A converged steady state of ``system`` (its events of one period and its state).
    system : FrictionSystem
        The system it is a steady state of (e.g. ``BladeAssembly.system(omega)``): its sliders are
        the pattern's rows, in the system's order (for one
        :class:`~frictionjoint.elements.PatchDovetailRoot`, its nodes, right flank first).

    Returns
    -------
    SlipPattern
    """
    if not getattr(response, "converged", False) or response.events is None:
        raise ParameterError(f"response must be a converged periodic orbit with its events, got status "
                             f"{getattr(response, 'status', None)!r}")
    if not math.isclose(response.omega, system.omega, rel_tol=1e-12):
        raise ParameterError(f"response is at omega = {response.omega:g} rad/s, the system at {system.omega:g}")
    n = system.n_sliders
    period = 2.0 * math.pi / response.omega
    t_s = float(response.section_time)
    events = sorted((t, slider, kind) for t, _, slider, kind in response.events)
    if any(not t_s - 1e-9 * period <= t <= t_s + period * (1 + 1e-9) for t, _, _ in events):
        raise ParameterError("response.events must be one period's from its section time")
    if any(slider >= n for _, slider, _ in events):
        raise ParameterError(f"response has events of sliders the system does not have ({n} sliders)")
    status = _status_at_section(response, system, events)
    times, columns = [t_s], [status.copy()]
    for t, slider, kind in events:
        status[slider] = STATUS_AFTER[kind]
        times.append(t)
        columns.append(status.copy())
    times.append(t_s + period)
    bounds, pattern = _wrap(np.array(times), np.array(columns, dtype=np.int8).T, period)
    slips = int(np.count_nonzero((pattern == SLIPPING).any(axis=1)))
    opens = int(np.count_nonzero((pattern == OPEN).any(axis=1)))
    stuck = int(np.count_nonzero((pattern == STUCK).all(axis=1)))
    return SlipPattern(response.omega, bounds, pattern,
                       f"{n} sliders over one period, {len(events)} events: {slips} slip and {opens} open at some "
                       f"time, {stuck} stick throughout")


def _status_at_section(response, system, events) -> np.ndarray:
    """Each slider's status at the section time: after its last event of the period, or, without
    events, open where its contact is open there and stuck otherwise."""
    n = system.n_sliders
    status = np.full(n, STUCK, dtype=np.int8)
    if getattr(system, "n_contacts", 0):
        x = np.asarray(response.state, dtype=float)[:system.n_dof]
        loads = system.normal_loads(x)
        on = np.flatnonzero(system.slider_contact >= 0)
        status[on[loads[system.slider_contact[on]] <= 0.0]] = OPEN
    for _, slider, kind in events:  # in time order: the last one stays
        status[slider] = STATUS_AFTER[kind]
    return status


def _wrap(times: np.ndarray, pattern: np.ndarray, period: float) -> tuple[np.ndarray, np.ndarray]:
    """The pieces ``[times[k], times[k+1])`` of ``[t_s, t_s + period]`` moved to ``[0, period]``:
    those after ``period`` first (shifted back by a period), the piece across it split there."""
    times = np.clip(times, times[0], times[0] + period)
    k = int(np.searchsorted(times, period, side="left"))  # times[k - 1] < period <= times[k]
    if times[k] != period:  # split the piece across the period's end
        times = np.insert(times, k, period)
        pattern = np.insert(pattern, k - 1, pattern[:, k - 1], axis=1)
    bounds = np.concatenate([times[k:] - period, times[1:k + 1]])
    return np.maximum.accumulate(bounds), pattern[:, np.r_[k:pattern.shape[1], 0:k]]

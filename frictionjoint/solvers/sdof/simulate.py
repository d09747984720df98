"""Time response of the single-DOF Coulomb oscillator on the closed-form kernel.

:class:`~frictionjoint.solvers.sdof.SdofCoulomb` marches event to event with pure ``math`` on
floats; each piece is kept (start state, status, end) and the requested outputs are the closed form
of the piece that holds each output time: ``x``, ``v``, and the friction force (``s F`` while
slipping, the holding force ``P0 cos(wt) - k x`` while stuck). The event log is read off the chain
of pieces: a change of status between two pieces is an event of that kind at their junction.
The general marcher (:func:`frictionjoint.solvers.marcher.response.simulate`) stays the reference; the
energy accounting is computed there.
"""
from __future__ import annotations

import math

import numpy as np

from ...results import TimeResponse
from ..marcher import EventLog, MarchState
from .kernel import SdofCoulomb, event_kind

__all__ = ["sdof_simulate"]


def sdof_simulate(kernel: SdofCoulomb, t_end: float, x0: float, v0: float, t_eval: np.ndarray,
                  record: tuple) -> TimeResponse:
    """March the kernel from ``(0, x0, v0)`` to ``t_end`` and evaluate ``record`` at ``t_eval``.

    Parameters
    ----------
    kernel : SdofCoulomb
    t_end : float
        End time [s].
    x0, v0 : float
        Initial state at ``t = 0`` [m, m/s].
    t_eval : (n_t,) ndarray
        Output times in ``[0, t_end]``, ascending (checked by the caller).
    record : tuple of str
        Among ``'x'``, ``'v'``, ``'friction_force'``.

    Returns
    -------
    TimeResponse
        1-D arrays, the event log and the final state.

    Raises
    ------
    ConvergenceError
        Where the kernel's stick/slip rules find no consistent status (the caller falls back to
        the general marcher).
    """
    pieces = []
    res = kernel.march(0.0, x0, v0, t_end, on_piece=lambda *p: pieces.append(p))
    friction = kernel.slip_force > 0
    log = EventLog()
    if friction:
        if v0 == 0.0 and pieces and pieces[0][3] != 0:
            log.append(0.0, 0, 0, "slip")  # settled from rest into slip at the start
        for before, after in zip(pieces[:-1], pieces[1:]):
            log.append(before[4], 0, 0, event_kind(before[3], after[3]))
        if pieces and res.status != pieces[-1][3]:
            log.append(res.t, 0, 0, event_kind(pieces[-1][3], res.status))  # an event at t_end itself
    n_t = t_eval.size
    out = {name: np.empty(n_t) for name in record}
    starts = np.array([p[0] for p in pieces]) if pieces else np.zeros(1)
    which = np.clip(np.searchsorted(starts, t_eval, side="right") - 1, 0, max(len(pieces) - 1, 0))
    p0, k, w, f = kernel.force_amplitude, kernel.stiffness, kernel.omega, kernel.slip_force
    for i, t in enumerate(t_eval.tolist()):
        if not pieces:
            x, v, s = x0, v0, res.status
        else:
            ta, xa, va, s, tb = pieces[which[i]][:5]
            x, v = kernel.evaluate(s, ta, xa, va, min(t, tb))
        if t == res.t:  # the final state (after the rules at an event exactly at t_end)
            x, v, s = res.x, res.v, res.status
        if "x" in out:
            out["x"][i] = x
        if "v" in out:
            out["v"][i] = v
        if "friction_force" in out:
            out["friction_force"][i] = (0.0 if not friction else s * f if s != 0
                                        else p0 * math.cos(w * t) - k * x)
    # as the general marcher's: no slider without friction
    final = (MarchState(res.t, [res.x], [res.v], [res.x], [res.status]) if friction
             else MarchState(res.t, [res.x], [res.v], [], []))
    return TimeResponse(t=t_eval, x=out.get("x"), v=out.get("v"), friction_force=out.get("friction_force"),
                        events=log, final_state=final)

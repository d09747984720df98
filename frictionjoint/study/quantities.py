"""The quantities of interest of one study point, from its frequency sweep (physics only: no I/O).

From the swept first-harmonic amplitude ``|X(omega)|`` of the output (the converged points, in
sweep or branch order):

- ``peak_amplitude`` [m] and ``peak_omega`` [rad/s]: the largest amplitude and its frequency;
- ``damping_ratio``: the equivalent viscous damping ratio from the half-power bandwidth,
  ``(omega_2 - omega_1) / (2 omega_peak)``, ``omega_1,2`` where the amplitude falls to
  ``peak / sqrt(2)`` on either side of the peak (linear interpolation between sweep points; NaN if
  it does not fall that far inside the range, or the refined peak is so sharp that every sweep
  point is below that level). For a single mode with light viscous damping this
  is the modal damping ratio; for a friction-damped resonance it is the damping ratio of the
  linear oscillator with the same bandwidth;
- ``dissipated_at_peak`` [J]: the friction energy per cycle at the peak point;
- ``slipping_at_peak``: whether the joint slips at the peak point;
- ``peak_at_edge``: the peak is the first or last point of the sweep (widen the range);
- ``converged_points`` of ``points``.

With a nonlinear mode declared (:class:`~frictionjoint.study.definition.ModeDamping`: ``[quantities]
mode_damping`` in a study file), from the mode of the point's blade at the declared amplitude
(:func:`frictionjoint.study.point.mode_quantities`, over :func:`mode_amplitudes`; NaN without it):

- ``mode_frequency`` [rad/s] and ``mode_damping_ratio``: the mode's frequency and damping ratio
  (friction and the structure's dashpots together), the root damping at that vibration level.
"""
from __future__ import annotations

import math

import numpy as np

__all__ = ["QUANTITIES", "MODE_QUANTITIES", "quantities", "mode_amplitudes"]

#: the nonlinear mode's columns of a study table (NaN unless the study declares the mode)
MODE_QUANTITIES = ("mode_frequency", "mode_damping_ratio")
#: the quantity columns of a study table, in order
QUANTITIES = ("peak_amplitude", "peak_omega", "damping_ratio", "dissipated_at_peak", "slipping_at_peak",
              "peak_at_edge", "converged_points", "points", *MODE_QUANTITIES)
#: points of the ladder of amplitudes a study's mode is followed over, from a thousandth of the
#: declared amplitude (stuck, on a blade's root) to the amplitude itself
MODE_LADDER_POINTS = 13


def _crossing(w: np.ndarray, a: np.ndarray, i: int, level: float, step: int) -> float:
    """The frequency where ``a`` first falls below ``level`` walking from ``i`` by ``step``
    (linear interpolation between the two points); NaN if it does not."""
    j = i
    while 0 <= j + step < a.size:
        k = j + step
        if a[k] < level:
            return float(w[j] + (level - a[j]) * (w[k] - w[j]) / (a[k] - a[j]))
        j = k
    return math.nan


def quantities(omega, amplitude, converged, dissipated, stuck, peak: tuple | None = None) -> dict:
    """The quantities of interest (module docstring) of a sweep.

    Parameters
    ----------
    omega, amplitude : (n,) ndarray
        Frequencies [rad/s] and first-harmonic amplitudes [m] of the output, in sweep order.
    converged, stuck : (n,) bool ndarray
    dissipated : (n,) ndarray
        Friction energy per cycle [J].
    peak : (omega, amplitude, dissipated, slipping), optional
        The peak refined between the sweep's points (it replaces the largest point's values; the
        half-power level is taken from it).

    Returns
    -------
    dict
        ``{name: value}`` for :data:`QUANTITIES`.
    """
    ok = np.asarray(converged, bool)
    out = dict.fromkeys(QUANTITIES, math.nan)
    out.update(points=int(ok.size), converged_points=int(ok.sum()), slipping_at_peak=None, peak_at_edge=None)
    if not ok.any():
        return out
    w = np.asarray(omega, float)[ok]
    a = np.asarray(amplitude, float)[ok]
    i = int(np.argmax(a))
    w_pk, a_pk = float(w[i]), float(a[i])
    e_pk, slip_pk = float(np.asarray(dissipated, float)[ok][i]), bool(not np.asarray(stuck, bool)[ok][i])
    if peak is not None and peak[1] >= a_pk:
        w_pk, a_pk, e_pk, slip_pk = float(peak[0]), float(peak[1]), float(peak[2]), bool(peak[3])
    level = a_pk / math.sqrt(2.0)
    # a refined peak above sqrt 2 times every sample: the bandwidth is below the sweep's spacing
    w1, w2 = ((_crossing(w, a, i, level, -1), _crossing(w, a, i, level, +1)) if a[i] >= level
              else (math.nan, math.nan))
    out.update(peak_amplitude=a_pk, peak_omega=w_pk,
               damping_ratio=float(abs(w2 - w1) / (2.0 * w_pk)) if not (math.isnan(w1) or math.isnan(w2)) else math.nan,
               dissipated_at_peak=e_pk, slipping_at_peak=slip_pk, peak_at_edge=bool(i in (0, a.size - 1)))
    return out


def mode_amplitudes(amplitude: float) -> np.ndarray:
    """The amplitudes a study's nonlinear mode is followed over [m]: ``np.geomspace(amplitude /
    1000, amplitude, MODE_LADDER_POINTS)``, the last the declared one (a ladder, so that a fold of
    the branch on the way is passed by arc length, as :func:`~frictionjoint.nonlinear_mode` does
    between its amplitudes)."""
    return np.geomspace(amplitude / 1000.0, amplitude, MODE_LADDER_POINTS)


"""Forced-response sweeps: stepped sine, up and down, with the analytic answer beside it.

At each frequency the periodic steady state is found by shooting
(:meth:`frictionjoint.CoulombOscillator.steady_state`), started from the orbit of the previous
frequency (its state at ``t = 0``), so that a sweep follows one branch of the response as a
slowly stepped experiment would (DESIGN.md section 6). Where Den Hartog's closed form is the
motion (undamped, stop-free; DESIGN.md section 3) it is reported beside the simulated
answer with the relative error; elsewhere the regime word says why it does not apply.

:class:`FrequencyResponse` holds only arrays and words, so that other sweeps (e.g. through
FMUs) can return the same type; the analytic columns are then simply absent (all masked).
"""
from __future__ import annotations

import csv
import functools
import math
import os
import sys
import warnings
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Callable, Optional

import numpy as np
from numpy.typing import ArrayLike

from .errors import (ParameterError, check_count, check_grid, check_nonnegative, check_oscillator,
                     check_positive, check_system)
from .regime import classify
from .system import FrictionSystem

if TYPE_CHECKING:  # computing never imports matplotlib
    from matplotlib.figure import Figure

__all__ = ["FrequencyResponse", "SystemSweep", "oscillator_sweep", "system_sweep", "peak_response",
           "den_hartog_curve", "DIRECTIONS"]

#: Allowed values of ``direction``.
DIRECTIONS = ("up", "down", "both")

_MASKED_COLUMNS = ("analytic_amplitude", "analytic_phase", "amplitude_error", "phase_error")
_FIXED_COLUMNS = ("branch", "omega", "frequency_ratio", "amplitude", "phase", "harmonic_amplitude",
                  "stops_per_cycle", "stuck", "converged", "unique", "regime", "periods",
                  *_MASKED_COLUMNS, "analytic_regime", "message")
#: what ``FrequencyResponse.harmonics[output]`` holds per point
_HARMONIC_KEYS = ("amplitude", "phase", "peak")


def _masked(values) -> np.ma.MaskedArray:
    """Float masked array with NaN/None entries masked (and set to 0 underneath)."""
    vals = np.array([np.nan if v is None else v for v in values], dtype=float)
    bad = ~np.isfinite(vals)
    vals[bad] = 0.0
    return np.ma.MaskedArray(vals, mask=bad)


def _wrap(angle):
    """Angle wrapped into ``(-pi, pi]``."""
    return np.pi - np.mod(np.pi - angle, 2 * np.pi)


@dataclass(eq=False)
class FrequencyResponse:
    """Steady-state response at a sequence of excitation frequencies.

    One entry per computed point, in the order computed (the ``'up'`` branch in ascending,
    the ``'down'`` branch in descending ``omega``).

    Attributes
    ----------
    omega : (n,) ndarray
        Excitation angular frequency [rad/s].
    amplitude : (n,) ndarray
        Max ``|x|`` over one steady period [m] (for ``'unbounded'`` points: the value when
        the growth was recognised; meaningless as a steady amplitude).
    phase : (n,) ndarray
        Lag of the first harmonic of ``x`` behind the force ``cos(omega t)`` [rad].
    harmonic_amplitude : (n,) ndarray
        Amplitude of the first harmonic of ``x`` [m].
    stops_per_cycle : (n,) int ndarray
        Stops of finite duration per cycle.
    stuck, converged, unique : (n,) bool ndarray
        Permanent stick; periodic orbit found; orbit unique (not one of a family).
    regime : (n,) ndarray of str
        Simulated regime: ``'stop-free'``, ``'stops'``, ``'stuck'``, ``'unbounded'`` or
        ``'not converged'`` (:func:`frictionjoint.regime.classify`).
    branch : (n,) ndarray of str
        ``'up'`` or ``'down'``.
    periods : (n,) ndarray
        Excitation periods marched to reach the steady state.
    message : tuple of str
        The solver's message per point.
    analytic_amplitude, analytic_phase : (n,) masked ndarray
        Closed-form amplitude [m] and first-harmonic phase lag [rad]; masked where the closed
        form is not the motion.
    analytic_regime : (n,) ndarray of str
        Why the closed form applies or not: ``'stop-free'`` (applies), ``'stops'``,
        ``'unbounded'``, ``'stuck'``, ``'damped'`` (no closed form with viscous damping) or
        ``'none'`` (no analytic model).
    amplitude_error, phase_error : (n,) masked ndarray
        ``|amplitude - analytic| / analytic`` and ``|wrap(phase - analytic)| / |analytic|``
        [-]; masked where the closed form does not apply or the point did not converge.
    natural_frequency : float or None
        ``wn`` [rad/s] used for the frequency ratio ``r = omega/wn``.
    analytic_name : str
        Name of the analytic reference (``'Den Hartog'``).
    parameters : dict
        Model parameters of the sweep (for the record and the CSV header).
    reference : callable or None
        ``reference(omega) -> (amplitude, phase)`` masked arrays of the analytic answer at any
        frequencies (used to draw a dense analytic curve); ``None`` without an analytic model.
    """

    omega: np.ndarray
    amplitude: np.ndarray
    phase: np.ndarray
    harmonic_amplitude: np.ndarray
    stops_per_cycle: np.ndarray
    stuck: np.ndarray
    converged: np.ndarray
    unique: np.ndarray
    regime: np.ndarray
    branch: np.ndarray
    periods: np.ndarray
    message: tuple
    analytic_amplitude: np.ma.MaskedArray
    analytic_phase: np.ma.MaskedArray
    analytic_regime: np.ndarray
    amplitude_error: np.ma.MaskedArray
    phase_error: np.ma.MaskedArray
    natural_frequency: Optional[float] = None
    analytic_name: str = "Den Hartog"
    parameters: dict = field(default_factory=dict)
    reference: Optional[Callable] = field(default=None, repr=False, compare=False)
    harmonics: dict = field(default_factory=dict, repr=False, compare=False)

    # ------------------------------------------------------------ views
    def __len__(self) -> int:
        return int(self.omega.size)

    @property
    def frequency_ratio(self) -> Optional[np.ndarray]:
        """``r = omega / natural_frequency`` [-], or ``None`` if ``natural_frequency`` is unknown."""
        if self.natural_frequency is None:
            return None
        return self.omega / self.natural_frequency

    @property
    def success(self) -> bool:
        """True when every point converged to a periodic orbit."""
        return bool(np.all(self.converged))

    @property
    def applicable(self) -> np.ndarray:
        """(n,) bool ndarray: the closed form is the motion (not masked)."""
        return ~np.ma.getmaskarray(self.analytic_amplitude)

    def select(self, branch: str) -> "FrequencyResponse":
        """The points of one branch (``'up'`` or ``'down'``) as a new :class:`FrequencyResponse`.

        Parameters
        ----------
        branch : {'up', 'down'}
            The branch to keep.

        Returns
        -------
        FrequencyResponse
            The points with ``self.branch == branch``, in the order computed (per-point arrays,
            ``message`` and ``harmonics`` filtered; the other fields shared).

        Raises
        ------
        ParameterError
            If ``branch`` is neither ``'up'`` nor ``'down'``.
        """
        if branch not in ("up", "down"):
            raise ParameterError(f"branch must be 'up' or 'down', got {branch!r}")
        keep = self.branch == branch
        out = {}
        for name in self.__dataclass_fields__:
            value = getattr(self, name)
            if name == "message":
                value = tuple(m for m, k in zip(value, keep) if k)
            elif name == "harmonics":
                value = {out: {key: col[keep] for key, col in h.items()} for out, h in value.items()}
            elif isinstance(value, np.ndarray) and value.shape == keep.shape:
                value = value[keep]
            out[name] = value
        return FrequencyResponse(**out)

    def max_error(self) -> tuple[Optional[float], Optional[float]]:
        """Largest ``(amplitude_error, phase_error)`` over the applicable points (``None`` if none)."""
        res = []
        for err in (self.amplitude_error, self.phase_error):
            res.append(None if err.count() == 0 else float(err.max()))
        return res[0], res[1]

    # ------------------------------------------------------------ output
    def table(self, compare: bool = True) -> str:
        """Printed table of the sweep.

        With ``compare`` (the default): branch, omega, r, amplitude, analytic amplitude,
        relative error, stops per cycle. Where the closed form is not the motion the error
        column holds the regime word (``stops``, ``unbounded``, ``stuck``, ``damped``); where
        the simulation found no periodic orbit the amplitude column says ``unbounded`` or
        ``no conv.``; ``*`` marks an orbit that is one of a family (not unique). The table of
        :meth:`harmonics_table` follows when outputs other than ``x`` were recorded.

        Without ``compare``: only the simulated numbers (:meth:`harmonics_table`).

        Parameters
        ----------
        compare : bool
            Put the analytic answer and the relative error beside each point.

        Returns
        -------
        str
        """
        if not compare:
            return self.harmonics_table()
        text = self._compare_table()
        if set(self.harmonics) - {"x"}:
            text += "\n\n" + self.harmonics_table()
        return text

    def harmonics_table(self) -> str:
        """Simulated numbers only: per point and output, the peak ``max |y|``, the first-harmonic
        amplitude and its phase lag behind ``cos(omega t)`` [deg]; then stops per cycle, periods
        marched and the regime (``*``: not unique).

        Without recorded harmonics (library sweeps) the ``x`` columns come from ``amplitude``,
        ``harmonic_amplitude`` and ``phase``.

        Returns
        -------
        str
        """
        ratio = self.frequency_ratio
        outs = self.harmonics or {"x": {"peak": self.amplitude, "amplitude": self.harmonic_amplitude,
                                       "phase": self.phase}}
        head = f"{'branch':<6} {'omega [rad/s]':>13} {'r':>7}"
        for name in outs:
            head += f" {name + ' peak':>14} {name + ' H1':>14} {'phase [deg]':>11}"
        head += f" {'stops/cycle':>11} {'periods':>7}  regime"
        lines = [head, "-" * len(head)]
        for i in range(len(self)):
            row = f"{self.branch[i]:<6} {self.omega[i]:13.6g} "
            row += f"{ratio[i]:7.4f}" if ratio is not None else f"{'-':>7}"
            for name, h in outs.items():
                if self.converged[i]:
                    row += f" {h['peak'][i]:14.6e} {h['amplitude'][i]:14.6e} {math.degrees(h['phase'][i]):11.4f}"
                else:
                    row += f" {'-':>14} {'-':>14} {'-':>11}"
            stops = ("stuck" if self.regime[i] == "stuck" else str(int(self.stops_per_cycle[i]))) \
                if self.converged[i] else "-"
            row += f" {stops:>11} {self.periods[i]:7.0f}  {self.regime[i]}" + ("" if self.unique[i] else "*")
            lines.append(row)
        lines.append("-" * len(head))
        if not np.all(self.unique):
            lines.append("* not unique: one member of a family of periodic orbits")
        return "\n".join(lines)

    def _compare_table(self) -> str:
        ratio = self.frequency_ratio
        name = self.analytic_name
        head = (f"{'branch':<6} {'omega [rad/s]':>13} {'r':>7} {'amplitude [m]':>14} "
                f"{name + ' [m]':>15} {'rel. error':>11} {'stops/cycle':>11}")
        lines = [head, "-" * len(head)]
        for i in range(len(self)):
            r_txt = f"{ratio[i]:7.4f}" if ratio is not None else f"{'-':>7}"
            if self.converged[i]:
                amp_txt = f"{self.amplitude[i]:.6e}" + ("*" if not self.unique[i] else "")
                stops_txt = "stuck" if self.regime[i] == "stuck" else str(int(self.stops_per_cycle[i]))
            else:
                amp_txt = "unbounded" if self.regime[i] == "unbounded" else "no conv."
                stops_txt = "-"
            if np.ma.getmaskarray(self.analytic_amplitude)[i]:
                ref_txt = "-"
                err_txt = str(self.analytic_regime[i])
            else:
                ref_txt = f"{self.analytic_amplitude[i]:.6e}"
                err_txt = ("-" if np.ma.getmaskarray(self.amplitude_error)[i]
                           else f"{self.amplitude_error[i]:.1e}")
            lines.append(f"{self.branch[i]:<6} {self.omega[i]:13.6g} {r_txt} {amp_txt:>14} "
                         f"{ref_txt:>15} {err_txt:>11} {stops_txt:>11}")
        lines.append("-" * len(head))
        amp_err, ph_err = self.max_error()
        n_app = int(np.count_nonzero(~np.ma.getmaskarray(self.amplitude_error)))
        if amp_err is not None:
            lines.append(f"max rel. error vs {name} at {n_app} stop-free points: amplitude "
                         f"{amp_err:.1e}, phase {ph_err:.1e}")
        words = {"stops": "with stops", "stuck": "permanently stuck",
                 "unbounded": "growing without bound", "not converged": "not converged"}
        extra = []
        for word, text in words.items():
            n = int(np.count_nonzero(self.regime == word))
            if n:
                extra.append(f"{n} point{'' if n == 1 else 's'} {text}")
        if extra:
            lines.append(", ".join(extra) + " (simulation only: no closed form there)")
        if not np.all(self.unique):
            lines.append("* not unique: one member of a family of periodic orbits")
        return "\n".join(lines)

    def to_csv(self, path: str | os.PathLike) -> None:
        """Write one row per point; masked entries are empty cells, floats round-trip exactly.

        Leading ``# key = value`` lines record ``natural_frequency``, ``analytic_name`` and the
        model parameters (read with ``comment='#'`` in pandas or :meth:`from_csv`).

        Parameters
        ----------
        path : str or os.PathLike
            Output file.
        """
        ratio = self.frequency_ratio
        with open(path, "w", newline="", encoding="utf-8") as fh:
            fh.write(f"# natural_frequency = {self.natural_frequency!r}\n")
            fh.write(f"# analytic_name = {self.analytic_name}\n")
            for key, value in self.parameters.items():
                fh.write(f"# {key} = {value!r}\n")
            w = csv.writer(fh)
            w.writerow([*_FIXED_COLUMNS,
                        *[f"{out}_{key}" for out, h in self.harmonics.items() for key in h]])
            for i in range(len(self)):
                masked = []
                for name in _MASKED_COLUMNS:
                    col = getattr(self, name)
                    masked.append("" if np.ma.getmaskarray(col)[i] else repr(float(col[i])))
                w.writerow([self.branch[i], repr(float(self.omega[i])),
                            "" if ratio is None else repr(float(ratio[i])),
                            repr(float(self.amplitude[i])), repr(float(self.phase[i])),
                            repr(float(self.harmonic_amplitude[i])), int(self.stops_per_cycle[i]),
                            int(self.stuck[i]), int(self.converged[i]), int(self.unique[i]),
                            self.regime[i], repr(float(self.periods[i])), *masked,
                            self.analytic_regime[i], self.message[i],
                            *[repr(float(col[i])) for h in self.harmonics.values() for col in h.values()]])

    @classmethod
    def from_csv(cls, path: str | os.PathLike) -> "FrequencyResponse":
        """Read a file written by :meth:`to_csv` (the ``reference`` callable is not restored).

        Parameters
        ----------
        path : str or os.PathLike
            A CSV file written by :meth:`to_csv`.

        Returns
        -------
        FrequencyResponse
        """
        import ast

        meta = {}
        with open(path, newline="", encoding="utf-8") as fh:
            lines = fh.readlines()
        body = []
        for line in lines:
            if line.startswith("#"):
                key, _, value = line[1:].partition("=")
                meta[key.strip()] = value.strip()
            else:
                body.append(line)
        rows = list(csv.DictReader(body))
        wn = ast.literal_eval(meta.pop("natural_frequency", "None"))
        name = meta.pop("analytic_name", "Den Hartog")
        params = {k: ast.literal_eval(v) for k, v in meta.items()}

        def col(key, typ=float):
            return np.array([typ(r[key]) for r in rows])

        harmonics = {}
        for key in (rows[0].keys() if rows else ()):
            out, _, quantity = key.rpartition("_")
            if out and quantity in _HARMONIC_KEYS and key not in _FIXED_COLUMNS:
                harmonics.setdefault(out, {})[quantity] = col(key)

        return cls(
            omega=col("omega"), amplitude=col("amplitude"), phase=col("phase"),
            harmonic_amplitude=col("harmonic_amplitude"),
            stops_per_cycle=col("stops_per_cycle", int),
            stuck=col("stuck", int).astype(bool), converged=col("converged", int).astype(bool),
            unique=col("unique", int).astype(bool), regime=col("regime", str),
            branch=col("branch", str), periods=col("periods"),
            message=tuple(r["message"] for r in rows),
            **{k: _masked([float(r[k]) if r[k] != "" else None for r in rows]) for k in _MASKED_COLUMNS},
            analytic_regime=col("analytic_regime", str), natural_frequency=wn,
            analytic_name=name, parameters=params, harmonics=harmonics,
        )

    def plot(self, path: str | os.PathLike | None = None, phase: bool = True) -> Figure:
        """Amplitude (and phase) against frequency (see :func:`frictionjoint.plotting.plot_frequency_response`).

        Parameters
        ----------
        path : str or os.PathLike, optional
            Write the figure there (format from the extension, e.g. ``.png``).
        phase : bool
            Add a phase panel below the amplitude.

        Returns
        -------
        matplotlib.figure.Figure
        """
        from .plotting import plot_frequency_response

        return plot_frequency_response(self, path=path, phase=phase)


# --------------------------------------------------------------------------- analytic reference


def den_hartog_curve(omegas, mass: float, stiffness: float, slip_force: float,
                     force_amplitude: float, base_amplitude: float = 0.0):
    """Den Hartog's amplitude and phase at many frequencies, masked where it is not the motion.

    Parameters
    ----------
    omegas : (n,) array_like
        Angular frequencies [rad/s], > 0.
    mass, stiffness, slip_force, force_amplitude, base_amplitude : float
        As in :class:`frictionjoint.CoulombOscillator` [kg, N/m, N, N, m].

    Returns
    -------
    amplitude : (n,) masked ndarray
        Max ``|x|`` [m].
    phase : (n,) masked ndarray
        First-harmonic lag behind ``cos(omega t)`` [rad].
    regime : (n,) ndarray of str
        Regime word of :func:`frictionjoint.analytic.den_hartog`.
    """
    from .analytic import den_hartog_response

    amps, phases, regimes = [], [], []
    for w in np.atleast_1d(np.asarray(omegas, dtype=float)):
        dh = den_hartog_response(mass, stiffness, slip_force, force_amplitude, float(w),
                                 base_amplitude)
        ok = dh.applicable and math.isfinite(dh.amplitude)
        amps.append(dh.amplitude if ok else None)
        phases.append(dh.phase if ok else None)
        regimes.append(dh.regime)
    return _masked(amps), _masked(phases), np.array(regimes, dtype=str)


def _reference(params, omegas):
    amp, ph, _ = den_hartog_curve(omegas, **params)
    return amp, ph


# --------------------------------------------------------------------------- the sweep


def _steady_state(osc, state):
    """``osc.steady_state`` from ``state`` (or the default guess).

    A failed march (a status of the result) is retried from the default guess (with a
    warning), and if that fails too the point is reported as not converged (with a warning), so
    that one bad point does not lose a whole sweep.
    """
    starts = [state, None] if state is not None else [None]
    errors = []
    res = None
    for start in starts:
        x0, v0 = (None, None) if start is None else start
        res = osc.steady_state(x0=x0, v0=v0)
        if res.status != "failed":  # the march ran (converged or not)
            if errors:
                warnings.warn(f"omega = {osc.omega!r}: steady-state solver failed ({errors[0]}); "
                              "succeeded from the default estimate", RuntimeWarning, stacklevel=3)
            return res
        errors.append(res.message + ("" if start is None else f" (from x0={start[0]!r}, v0={start[1]!r})"))
    res.message = "steady-state solver failed: " + "; ".join(errors)
    res.status = "not converged"  # the regime of the point
    warnings.warn(f"omega = {osc.omega!r}: {res.message}", RuntimeWarning, stacklevel=3)
    return res


def oscillator_sweep(mass: float, stiffness: float, slip_force: float, force_amplitude: float,
                     omegas: ArrayLike, damping: float = 0.0, base_amplitude: float = 0.0,
                     direction: str = "up", progress: bool = False) -> FrequencyResponse:
    """Stepped-sine forced response of the single-DOF Coulomb oscillator.

    ``m x'' + c x' + k (x - Y cos(omega t)) + T = P cos(omega t)`` (see
    :class:`frictionjoint.CoulombOscillator`). The ``'up'`` branch visits ``omegas`` in
    ascending, the ``'down'`` branch in descending order; ``'both'`` runs up, then down,
    carrying the state over. Each point starts from the orbit of the previous one
    (``PeriodicResponse.initial_state``), or from the one-harmonic estimate after a point
    that did not converge. Den Hartog's closed form is evaluated at every point; it applies
    only without viscous damping and where the motion is stop-free.

    Parameters
    ----------
    mass : float
        Mass m [kg], > 0.
    stiffness : float
        Spring k [N/m], > 0.
    slip_force : float
        Friction limit F [N], >= 0.
    force_amplitude : float
        Force amplitude P [N].
    omegas : (n,) array_like
        Excitation angular frequencies [rad/s], each > 0 (any order; duplicates allowed).
    damping : float
        Viscous damping c [N s/m], >= 0.
    base_amplitude : float
        Base motion amplitude Y [m]; ``P + k Y`` must not be 0.
    direction : {'up', 'down', 'both'}
        Sweep direction.
    progress : bool
        Show a progress bar (tqdm, on stderr).

    Returns
    -------
    FrequencyResponse
        ``2 n`` points for ``'both'``, else ``n``.

    Raises
    ------
    ParameterError
        If an argument is out of range (the message names it).
    """
    from .oscillator import CoulombOscillator

    params, c, ws = _check_sweep(mass, stiffness, slip_force, force_amplitude, damping, base_amplitude,
                                 omegas, direction, progress)

    def solve(w, state):
        osc = CoulombOscillator(omega=float(w), damping=c, **params)
        return _steady_state(osc, state)

    return _run_sweep(params, c, ws, direction, progress, solve)


def _check_sweep(mass, stiffness, slip_force, force_amplitude, damping, base_amplitude, omegas, direction,
                 progress):
    """Validate the arguments every oscillator sweep takes; return ``(params, damping, omegas)``."""
    m, k, fr, p, y, _ = check_oscillator(mass, stiffness, slip_force, force_amplitude, base_amplitude)
    c = check_nonnegative("damping", damping)
    ws = check_grid("omegas", omegas, unit="rad/s")
    if direction not in DIRECTIONS:
        raise ParameterError(f"direction must be one of {DIRECTIONS}, got {direction!r}")
    if not isinstance(progress, (bool, np.bool_)):
        raise ParameterError(f"progress must be True or False, got {progress!r}")
    return dict(mass=m, stiffness=k, slip_force=fr, force_amplitude=p, base_amplitude=y), c, ws


def _run_sweep(params: dict, c: float, ws, direction: str, progress: bool, solve) -> FrequencyResponse:
    """The stepped-sine loop shared by every sweep: ``solve(omega, state)`` returns a
    :class:`~frictionjoint.results.PeriodicResponse` started from ``state`` (the previous orbit's
    ``(x0, v0)`` at ``t = 0``, or ``None``)."""
    m, k = params["mass"], params["stiffness"]
    up = np.sort(ws)
    plan = []
    if direction in ("up", "both"):
        plan += [("up", w) for w in up]
    if direction in ("down", "both"):
        plan += [("down", w) for w in up[::-1]]

    analytic = {}
    if c == 0.0:
        amp_ref, ph_ref, reg_ref = den_hartog_curve(up, **params)
        for i, w in enumerate(up):
            analytic[float(w)] = (None if amp_ref.mask[i] else float(amp_ref[i]),
                                  None if ph_ref.mask[i] else float(ph_ref[i]), str(reg_ref[i]))

    from tqdm import tqdm

    rows = []
    state = None
    wn = math.sqrt(k / m)
    with tqdm(total=len(plan), desc="sweep", unit="pt", file=sys.stderr, disable=not progress,
              leave=False) as bar:
        for branch, w in plan:
            ss = solve(float(w), state)
            ok = ss.converged and ss.initial_state is not None and np.all(np.isfinite(ss.initial_state[:2]))
            state = (float(ss.initial_state[0]), float(ss.initial_state[1])) if ok else None
            ref_amp, ref_ph, ref_reg = analytic.get(float(w), (None, None, "damped"))
            amp_err = ph_err = None
            if ref_amp is not None and ss.converged:
                amp_err = abs(ss.amplitude - ref_amp) / ref_amp
                ph_err = abs(float(_wrap(ss.phase - ref_ph))) / abs(ref_ph) if ref_ph != 0 else None
            rows.append((branch, float(w), ss, classify(ss), ref_amp, ref_ph,
                         ref_reg, amp_err, ph_err))
            bar.set_postfix_str(f"{branch} r={w / wn:.3f}", refresh=False)
            bar.update()

    def arr(fn, dtype=float):
        return np.array([fn(row) for row in rows], dtype=dtype)

    harmonics = {}
    for name in (rows[0][2].harmonics or {}) if rows else {}:
        harmonics[name] = {key: arr(lambda r, key=key: (r[2].harmonics or {}).get(name, {}).get(key, np.nan))
                           for key in _HARMONIC_KEYS}
    return FrequencyResponse(
        omega=arr(lambda r: r[1]),
        amplitude=arr(lambda r: r[2].amplitude),
        phase=arr(lambda r: r[2].phase),
        harmonic_amplitude=arr(lambda r: r[2].harmonic_amplitude),
        stops_per_cycle=arr(lambda r: r[2].stops_per_cycle, int),
        stuck=arr(lambda r: r[2].stuck, bool),
        converged=arr(lambda r: r[2].converged, bool),
        unique=arr(lambda r: r[2].unique, bool),
        regime=arr(lambda r: r[3], object).astype(str),
        branch=arr(lambda r: r[0], object).astype(str),
        periods=arr(lambda r: r[2].periods),
        message=tuple(r[2].message for r in rows),
        analytic_amplitude=_masked([r[4] for r in rows]),
        analytic_phase=_masked([r[5] for r in rows]),
        analytic_regime=arr(lambda r: r[6], object).astype(str),
        amplitude_error=_masked([r[7] for r in rows]),
        phase_error=_masked([r[8] for r in rows]),
        natural_frequency=wn,
        analytic_name="Den Hartog",
        parameters=dict(params, damping=c),
        reference=None if c > 0 else functools.partial(_reference, params),
        harmonics=harmonics,
    )


def sweep(model, omegas, parameters: dict | None = None, direction: str = "up", outputs=("x",),
          n_samples: int = 256, progress: bool = False) -> FrequencyResponse:
    """Stepped-sine sweep of the Coulomb oscillator through an FMU or directly in the library.

    The same algorithm drives both (:func:`frictionjoint.drivers.shoot` on a
    :class:`~frictionjoint.drivers.FMUDriver` or :class:`~frictionjoint.drivers.LibraryDriver`):
    shooting on ``(x0, v0)`` with one reused instance, the state carried from point to point,
    first harmonics from ``n_samples`` points per period, exact displacement peaks.

    Parameters
    ----------
    model : str or path
        A ``.fmu`` file with the variables of ``CoulombOscillator.fmu``, or ``"CoulombOscillator"``
        for the library model.
    omegas : (n,) array_like
        Angular frequencies [rad/s], > 0.
    parameters : dict, optional
        Oscillator parameters (``mass``, ``stiffness``, ``damping``, ``slip_force``,
        ``force_amplitude``, ``base_amplitude``); ``omega``, ``x0``, ``v0`` are set by the sweep.
    direction : {'up', 'down', 'both'}
    outputs : sequence of str
        Outputs whose first harmonic and peak are reported in ``FrequencyResponse.harmonics``.
    n_samples : int
        Samples per period for the first harmonics of outputs other than ``x`` and
        ``friction_force`` (those are integrated exactly, piece by piece), >= 16.
    progress : bool
        Show a progress bar (tqdm, on stderr).

    Returns
    -------
    FrequencyResponse
    """
    from pathlib import Path

    from .drivers import FMUDriver, LibraryDriver, shoot
    from .stepping import OSCILLATOR_OUTPUTS, OSCILLATOR_PARAMETERS

    library = str(model) == "CoulombOscillator"
    if not library and not (Path(model).suffix == ".fmu" and Path(model).is_file()):
        raise ParameterError(f"model must be 'CoulombOscillator' or an existing .fmu file, got {model!r}")
    params = dict(parameters or {})
    allowed = set(OSCILLATOR_PARAMETERS) - {"omega", "x0", "v0", "harmonics"}
    unknown = set(params) - allowed
    if unknown:
        raise ParameterError(f"parameters must be among {sorted(allowed)}, got {sorted(unknown)}")
    full = {k: v[0] for k, v in OSCILLATOR_PARAMETERS.items() if k in allowed}
    full.update(params)
    base, c, ws = _check_sweep(full["mass"], full["stiffness"], full["slip_force"], full["force_amplitude"],
                               full["damping"], full["base_amplitude"], omegas, direction, progress)
    outputs = tuple(outputs)
    bad = [o for o in outputs if o not in OSCILLATOR_OUTPUTS]
    if bad:
        raise ParameterError(f"outputs must be among {sorted(OSCILLATOR_OUTPUTS)}, got {bad}")
    if isinstance(n_samples, bool) or not isinstance(n_samples, (int, np.integer)) or n_samples < 16:
        raise ParameterError(f"n_samples must be an integer >= 16, got {n_samples!r}")
    driver = LibraryDriver() if library else FMUDriver(model)
    try:
        return _run_sweep(base, c, ws, direction, progress,
                          lambda w, st: shoot(driver, dict(base, damping=c, omega=w), st, outputs=outputs,
                                              n_samples=int(n_samples)))
    finally:
        driver.close()


@dataclass
class SystemSweep:
    """Stepped-sine steady states of a :class:`~frictionjoint.system.FrictionSystem` family.

    Attributes
    ----------
    omega : (n,) ndarray
        Excitation angular frequency [rad/s], in the order computed.
    amplitude, harmonic_amplitude, phase : (n, n_dof) ndarray
        Max ``|x|`` [m], first-harmonic amplitude [m] and its lag behind ``cos(omega t)`` [rad].
    dissipated_per_cycle : (n,) ndarray
        Friction energy per period [J].
    stuck, converged : (n,) bool ndarray
        Permanent stick; periodic orbit found.
    """

    omega: np.ndarray
    amplitude: np.ndarray
    harmonic_amplitude: np.ndarray
    phase: np.ndarray
    dissipated_per_cycle: np.ndarray
    stuck: np.ndarray
    converged: np.ndarray


def _check_build(build) -> None:
    if not callable(build):
        raise ParameterError(f"build must be a callable build(omega) -> FrictionSystem, got {build!r}")


def system_sweep(build: Callable, omegas: ArrayLike, progress: bool = False) -> SystemSweep:
    """Periodic steady state of ``build(omega)`` at each ``omega`` [rad/s], in the given order,
    each started from the previous orbit (its state at ``t = 0``).

    Parameters
    ----------
    build : callable
        ``build(omega) -> FrictionSystem`` with harmonic excitation at ``omega``.
    omegas : sequence of float
        Angular frequencies [rad/s], > 0.
    progress : bool
        Show a progress bar.

    Returns
    -------
    SystemSweep
        One row per frequency, in the order of ``omegas``.
    """
    from tqdm import tqdm

    from .solvers.steady import periodic_response

    _check_build(build)
    ws = check_grid("omegas", omegas, unit="rad/s")
    rows = []
    z = None
    for w in tqdm(ws, desc="sweep", unit="pt", file=sys.stderr, disable=not progress, leave=False):
        system = check_system("build(omega)", build(float(w)), FrictionSystem)
        n = system.n_dof
        if z is None or not np.all(np.isfinite(z)):
            r = periodic_response(system)
        else:
            r = periodic_response(system, z[:n], z[n:2 * n], z[2 * n:] if z.size > 2 * n else None)
        z = r.initial_state if r.converged else None
        rows.append(r)
    return SystemSweep(
        omega=ws, amplitude=np.array([r.amplitude for r in rows]),
        harmonic_amplitude=np.array([r.harmonic_amplitude for r in rows]),
        phase=np.array([r.phase for r in rows]),
        dissipated_per_cycle=np.array([r.dissipated_per_cycle for r in rows]),
        stuck=np.array([r.stuck for r in rows]), converged=np.array([r.converged for r in rows]))


def peak_response(build: Callable, omega_min: float, omega_max: float, dof: int = 0, n_grid: int = 25,
                  xtol: float = 1e-6) -> tuple[float, float, SystemSweep]:
    """Resonance peak of the first-harmonic amplitude of DOF ``dof`` over ``[omega_min, omega_max]``.

    A stepped sweep over ``n_grid`` frequencies brackets the largest amplitude, then a bounded
    scalar search (Brent) refines it to ``xtol`` relative in ``omega``.

    Parameters
    ----------
    build : callable
        ``build(omega) -> FrictionSystem`` with harmonic excitation at ``omega`` [rad/s].
    omega_min, omega_max : float
        Frequency interval [rad/s], ``0 < omega_min < omega_max``.
    dof : int
        Index of the DOF whose first-harmonic amplitude is maximised, in ``[0, n_dof)``.
    n_grid : int
        Equally spaced frequencies of the bracketing sweep, >= 3.
    xtol : float
        Tolerance of the search relative in ``omega`` [-], in ``(0, 1)``.

    Returns
    -------
    (omega_peak, amplitude_peak, sweep) : (float, float, SystemSweep)
    """
    import scipy.optimize

    lo = check_positive("omega_min", omega_min)
    hi = check_positive("omega_max", omega_max)
    if not hi > lo:
        raise ParameterError(f"omega_max must be > omega_min = {lo:g}, got {hi!r}")
    n_grid = check_count("n_grid", n_grid, 3)
    xtol = check_positive("xtol", xtol)
    if not xtol < 1:
        raise ParameterError(f"xtol must be in (0, 1) (relative in omega), got {xtol!r}")
    dof = check_count("dof", dof, 0)
    _check_build(build)
    n_dof = check_system("build(omega)", build(lo), FrictionSystem).n_dof
    if dof >= n_dof:
        raise ParameterError(f"dof must be in [0, {n_dof - 1}] (the system's DOFs), got {dof}")
    grid = np.linspace(lo, hi, n_grid)
    sw = system_sweep(build, grid)
    amps = sw.harmonic_amplitude[:, dof]
    i = int(np.argmax(amps))
    a, b = grid[max(i - 1, 0)], grid[min(i + 1, grid.size - 1)]

    def neg(w):
        return -float(system_sweep(build, [w]).harmonic_amplitude[0, dof])

    res = scipy.optimize.minimize_scalar(neg, bounds=(a, b), method="bounded",
                                         options={"xatol": xtol * b})
    if -res.fun >= amps[i]:
        return float(res.x), float(-res.fun), sw
    return float(grid[i]), float(amps[i]), sw

"""Frequency-response results: stepped-sine sweeps of the single-DOF oscillator
(:class:`FrequencyResponse`, with the analytic answer beside the simulated one), of multi-DOF
friction systems (:class:`SystemSweep`), and of one output of an assembly with its two linear
limits beside it (:class:`OutputSweep`, e.g. a blade's tip on its dovetail root).

Both hold only arrays, words and parameters (no functions), so a CSV round trip is lossless:
the dense analytic curve of a plot is computed from :attr:`FrequencyResponse.parameters`.
"""
from __future__ import annotations

import csv
import math
import os
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Optional

import numpy as np
from numpy.typing import ArrayLike

from ..errors import ParameterError
from .dof_names import dof_meaning
from .response import PointsContract

if TYPE_CHECKING:  # computing never imports matplotlib
    from matplotlib.axes import Axes
    from matplotlib.figure import Figure

__all__ = ["FrequencyResponse", "SystemSweep", "OutputSweep"]


_MASKED_COLUMNS = ("analytic_amplitude", "analytic_phase", "amplitude_error", "phase_error")
_FIXED_COLUMNS = ("branch", "omega", "frequency_ratio", "amplitude", "phase", "harmonic_amplitude",
                  "stops_per_cycle", "stuck", "converged", "unique", "regime", "periods",
                  *_MASKED_COLUMNS, "analytic_regime", "message")  # 'message': the point's (messages)
#: the parameters of Den Hartog's closed form (FrequencyResponse.analytic_curve)
_DEN_HARTOG_KEYS = ("mass", "stiffness", "slip_force", "force_amplitude", "base_amplitude")
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
class FrequencyResponse(PointsContract):
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
    messages : tuple of str
        The solver's message per point.
    analytic_amplitude, analytic_phase : (n,) masked ndarray
        Closed-form amplitude [m] and first-harmonic phase lag [rad]; masked where the closed
        form is not the motion: where it has no stop-free motion, and where the simulated orbit
        is not stop-free although it has one (the point's regime cannot be both).
    analytic_regime : (n,) ndarray of str
        Why the closed form applies or not: ``'stop-free'`` (applies), ``'stops'``,
        ``'unbounded'``, ``'stuck'``, ``'damped'`` (no closed form with viscous damping),
        ``'none'`` (no analytic model), ``'not unique'`` (a stop-free closed form exists, but the
        periodic orbit is one of a family, e.g. at ``r = 1/(2n)``, and the member found has stops)
        or ``'other orbit'`` (a stop-free closed form exists, but the orbit found, unique, is not
        stop-free).
    amplitude_error, phase_error : (n,) masked ndarray
        ``|amplitude - analytic| / analytic`` and ``|wrap(phase - analytic)| / |analytic|``
        [-]; masked where the closed form does not apply or the point did not converge.
    natural_frequency : float or None
        ``wn`` [rad/s] used for the frequency ratio ``r = omega/wn``.
    analytic_name : str
        Name of the analytic reference (``'Den Hartog'``).
    parameters : dict
        Model parameters of the sweep (for the record and the CSV header; a plot draws the
        dense analytic curve from them).
    success, status, message
        The result contract (:class:`~frictionjoint.results.response.PointsContract`).
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
    messages: tuple
    analytic_amplitude: np.ma.MaskedArray
    analytic_phase: np.ma.MaskedArray
    analytic_regime: np.ndarray
    amplitude_error: np.ma.MaskedArray
    phase_error: np.ma.MaskedArray
    natural_frequency: Optional[float] = None
    analytic_name: str = "Den Hartog"
    parameters: dict = field(default_factory=dict)
    harmonics: dict = field(default_factory=dict, repr=False, compare=False)

    def __post_init__(self):
        # The closed form is the motion only where the simulated orbit is stop-free too: where a
        # stop-free closed form exists but the orbit found has stops (at r = 1/(2n) the steady
        # state is a family, and a member with one stop per cycle is as periodic as Den Hartog's),
        # comparing the two measures the distance between two different orbits.
        other = (np.asarray(self.converged, bool) & (np.asarray(self.regime) != "stop-free")
                 & (np.asarray(self.analytic_regime) == "stop-free"))
        if np.any(other):
            for name in _MASKED_COLUMNS:
                col = np.ma.array(getattr(self, name), copy=True)
                col[other] = np.ma.masked
                setattr(self, name, col)
            words = np.asarray(self.analytic_regime).astype(object)
            words[other] = np.where(np.asarray(self.unique, bool)[other], "other orbit", "not unique")
            self.analytic_regime = words.astype(str)

    # ------------------------------------------------------------ views
    def __len__(self) -> int:
        return int(self.omega.size)

    @property
    def frequency_ratio(self) -> Optional[np.ndarray]:
        """``r = omega / natural_frequency`` [-], or ``None`` if ``natural_frequency`` is unknown."""
        if self.natural_frequency is None:
            return None
        return self.omega / self.natural_frequency


    def analytic_curve(self, omegas: ArrayLike) -> Optional[tuple[np.ma.MaskedArray, np.ma.MaskedArray]]:
        """The closed-form answer at any frequencies, from :attr:`parameters` (Den Hartog: the
        undamped oscillator); None without an analytic model (damped, or other parameters).

        Parameters
        ----------
        omegas : (n,) array_like
            Angular frequencies [rad/s], > 0.

        Returns
        -------
        (amplitude, phase) : masked ndarrays or None
            Max ``|x|`` [m] and first-harmonic lag [rad], masked where the closed form is not the
            motion (:func:`frictionjoint.analytic.den_hartog_curve`).
        """
        p = self.parameters
        if (self.analytic_name != "Den Hartog" or p.get("damping", 0.0) != 0.0
                or not all(k in p for k in _DEN_HARTOG_KEYS[:4])):
            return None
        from ..analytic import den_hartog_curve

        amp, ph, _ = den_hartog_curve(omegas, **{k: p[k] for k in _DEN_HARTOG_KEYS if k in p})
        return amp, ph

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
            ``messages`` and ``harmonics`` filtered; the other fields shared).

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
            if name == "messages":
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
        column holds the word of :attr:`analytic_regime` (``stops``, ``unbounded``, ``stuck``,
        ``damped``, ``not unique``, ...); where the simulation found no periodic orbit the
        amplitude column says ``unbounded`` or ``no conv.``; ``*`` marks an orbit that is one of a
        family (not unique). Below it, the largest errors over the compared points (stop-free in
        the closed form and in the simulation) and the points left out, counted by what the
        simulation found and why (each point once). The table of :meth:`harmonics_table` follows
        when outputs other than ``x`` were recorded.

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
            lines.append(f"max rel. error vs {name} at {n_app} of {len(self)} points (stop-free, where the "
                         f"closed form is the motion): amplitude {amp_err:.1e}, phase {ph_err:.1e}")
        left = self._left_out()
        if left:
            lines.append("left out: " + ", ".join(left))
        if not np.all(self.unique):
            lines.append("* not unique: one member of a family of periodic orbits")
        return "\n".join(lines)

    def _left_out(self) -> list[str]:
        """The points the compare table's headline leaves out, grouped by what the simulation found
        and why the closed form is not that motion: ``'2 points with stops (not unique: ...)'``;
        with the compared points they count every point once."""
        found = {"stop-free": "stop-free", "stops": "with stops", "stuck": "permanently stuck",
                 "unbounded": "growing without bound", "not converged": "not converged"}
        why = {"not unique": f"not unique: {self.analytic_name}'s stop-free motion is another member of the "
                             "family of periodic orbits",
               "other orbit": f"{self.analytic_name}'s stop-free motion is not the orbit found",
               "damped": "damped: no closed form", "none": "no analytic model"}
        groups: dict = {}
        for i in np.flatnonzero(np.ma.getmaskarray(self.amplitude_error)):
            sim, ana = str(self.regime[i]), str(self.analytic_regime[i])
            if ana in why:
                reason = why[ana]
            elif sim == "not converged":
                reason = "no orbit to compare"
            elif sim != "stop-free":
                reason = "simulation only: no closed form there"
            else:  # stop-free, but the closed form has none (at a boundary of its regime)
                reason = f"{self.analytic_name}: {ana}"
            key = (found.get(sim, sim), reason)
            groups[key] = groups.get(key, 0) + 1
        return [f"{n} point{'' if n == 1 else 's'} {text} ({reason})" for (text, reason), n in groups.items()]

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
                            self.analytic_regime[i], self.messages[i],
                            *[repr(float(col[i])) for h in self.harmonics.values() for col in h.values()]])

    @classmethod
    def from_csv(cls, path: str | os.PathLike) -> "FrequencyResponse":
        """Read a file written by :meth:`to_csv` (lossless: floats, words and parameters).

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
            messages=tuple(r["message"] for r in rows),
            **{k: _masked([float(r[k]) if r[k] != "" else None for r in rows]) for k in _MASKED_COLUMNS},
            analytic_regime=col("analytic_regime", str), natural_frequency=wn,
            analytic_name=name, parameters=params, harmonics=harmonics,
        )

    def plot(self, ax: Axes | tuple | None = None, path: str | os.PathLike | None = None,
             phase: bool = True) -> Figure:
        """Amplitude (and phase) against frequency (see :func:`frictionjoint.plotting.plot_frequency_response`).

        Parameters
        ----------
        ax : matplotlib Axes or (Axes, Axes), optional
            Draw the amplitude into ``ax`` (with ``phase``: a pair, amplitude and phase) instead
            of a new figure. A path given here (the former first argument) is taken as ``path``.
        path : str or os.PathLike, optional
            Write the figure there (format from the extension, e.g. ``.png``).
        phase : bool
            Add a phase panel below the amplitude.

        Returns
        -------
        matplotlib.figure.Figure
        """
        from ..plotting import plot_frequency_response, plot_target

        ax, path = plot_target(ax, path)
        return plot_frequency_response(self, path=path, phase=phase, ax=ax)


@dataclass
class SystemSweep(PointsContract):
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
    messages : tuple of str
        The solver's message per point.
    stable : (n,) object ndarray, optional
        Per point True/False from the orbit's Floquet multipliers
        (:func:`~frictionjoint.solvers.frequency_domain.hbm.lyapunov_stable`), None where no orbit was found.
    success, status, message
        The result contract (:func:`~frictionjoint.results.collection_status`).
    """

    omega: np.ndarray
    amplitude: np.ndarray
    harmonic_amplitude: np.ndarray
    phase: np.ndarray
    dissipated_per_cycle: np.ndarray
    stuck: np.ndarray
    converged: np.ndarray
    messages: tuple = ()
    stable: Optional[np.ndarray] = None

    @property
    def harmonics(self) -> np.ndarray:
        """First harmonics ``X = a e^{-i phase}`` of the DOFs, ``x = Re(X e^{i omega t})`` [m],
        (n, n_dof) complex."""
        return np.atleast_2d(self.harmonic_amplitude) * np.exp(-1j * np.atleast_2d(self.phase))





_OUTPUT_COLUMNS = ("omega", "amplitude", "phase", "stuck", "converged", "dissipated_per_cycle")


def _yes_no(value) -> str:
    """A table cell of a True/False/None verdict."""
    return "--" if value is None else ("yes" if value else "no")


@dataclass(eq=False)
class OutputSweep(PointsContract):
    """Stepped-sine steady states of one output (e.g. a blade's tip), with the output's linear
    frequency response in the limits of the joints (every slider stuck, every slider slipping).

    Attributes
    ----------
    omega : (n,) ndarray
        Excitation angular frequency [rad/s], in the order computed.
    output : str
        The output's name (a DOF of the full model).
    response : (n,) complex ndarray
        First harmonic ``X`` of the output, ``x = Re(X e^{i omega t})`` [m].
    limits : dict
        ``{name: (n,) complex ndarray}``: the output's first harmonic in each linear limit
        (``'stuck'``, ``'slipping'``), same load [m].
    stuck, converged : (n,) bool ndarray
        Permanent stick; periodic orbit found.
    dissipated_per_cycle : (n,) ndarray
        Friction energy per period [J].
    messages : tuple of str
        The solver's message per point.
    stable : (n,) object ndarray, optional
        Per point True/False from the Floquet multipliers of the exact orbit (of the point, or
        started from the harmonic-balance point), None where unknown; None when not judged.
    fold : (n,) bool ndarray, optional
        Turning points of a harmonic-balance branch (then the points are in branch order).
    truncation_error : (n,) ndarray, optional
        A harmonic-balance branch checked against the exact orbits: each point's first-harmonic
        error (:func:`~frictionjoint.solvers.frequency_domain.hbm.truncation_error`), NaN where unknown.
    """

    omega: np.ndarray
    output: str
    response: np.ndarray
    limits: dict
    stuck: np.ndarray
    converged: np.ndarray
    dissipated_per_cycle: np.ndarray
    messages: tuple = ()
    stable: Optional[np.ndarray] = None
    fold: Optional[np.ndarray] = None
    truncation_error: Optional[np.ndarray] = None

    @property
    def amplitude(self) -> np.ndarray:
        """First-harmonic amplitude ``|X|`` [m] (n,)."""
        return np.abs(self.response)

    @property
    def phase(self) -> np.ndarray:
        """Lag of the first harmonic behind ``cos(omega t)``, ``-arg X`` [rad] (n,)."""
        return -np.angle(self.response)

    def peak(self) -> tuple[float, float]:
        """``(omega, amplitude)`` of the largest converged amplitude [rad/s, m] (NaN if none)."""
        amp = np.where(self.converged, self.amplitude, -np.inf)
        if not np.any(self.converged):
            return math.nan, math.nan
        i = int(np.argmax(amp))
        return float(self.omega[i]), float(amp[i])

    def table(self) -> str:
        """The points as text: omega, amplitude and phase of the output, the linear limits'
        amplitudes, stuck/converged, and (when judged) stable and the branch's folds."""
        names = list(self.limits)
        head = f"{'omega [rad/s]':>14} {'|X| [m]':>12} {'phase [rad]':>11} " + \
            " ".join(f"{n + ' [m]':>13}" for n in names) + f" {'stuck':>5} {'ok':>3}" + \
            (f" {'stable':>6}" if self.stable is not None else "") + (f" {'fold':>4}" if self.fold is not None else "") + \
            (f" {'trunc. err':>10}" if self.truncation_error is not None else "")
        meaning = dof_meaning(self.output)
        lines = [f"output {self.output}" + (f" ({meaning})" if meaning else ""), head]
        for k, w in enumerate(self.omega):
            amp = f"{self.amplitude[k]:12.5e}" if self.converged[k] else f"{'--':>12}"
            lines.append(f"{w:14.6g} {amp} {self.phase[k]:11.5f} "
                         + " ".join(f"{abs(self.limits[n][k]):13.5e}" for n in names)
                         + f" {'yes' if self.stuck[k] else 'no':>5} {'yes' if self.converged[k] else 'no':>3}"
                         + (f" {_yes_no(self.stable[k]):>6}" if self.stable is not None else "")
                         + (f" {'<' if self.fold[k] else '':>4}" if self.fold is not None else "")
                         + (f" {self.truncation_error[k]:10.2e}" if self.truncation_error is not None else ""))
        w_p, a_p = self.peak()
        lines.append(f"peak {a_p:.6g} m at {w_p:.6g} rad/s; {self.message}")
        return "\n".join(lines)

    def to_csv(self, path: str | os.PathLike) -> None:
        """Write the points (and the limits' amplitudes and phases) as CSV.

        Parameters
        ----------
        path : str or os.PathLike
        """
        names = list(self.limits)
        with open(path, "w", newline="") as f:
            wr = csv.writer(f)
            wr.writerow([*_OUTPUT_COLUMNS, *[f"{n}_{q}" for n in names for q in ("amplitude", "phase")],
                         "stable", "fold", "truncation_error", "output", "message"])
            for k in range(self.omega.size):
                st = "" if self.stable is None or self.stable[k] is None else int(bool(self.stable[k]))
                wr.writerow([repr(float(self.omega[k])), repr(float(self.amplitude[k])), repr(float(self.phase[k])),
                             int(self.stuck[k]), int(self.converged[k]), repr(float(self.dissipated_per_cycle[k])),
                             *[repr(float(q)) for n in names for q in (abs(self.limits[n][k]),
                                                                         -np.angle(self.limits[n][k]))],
                             st, "" if self.fold is None else int(bool(self.fold[k])),
                             "" if self.truncation_error is None else repr(float(self.truncation_error[k])),
                             self.output, self.messages[k] if k < len(self.messages) else ""])

    @classmethod
    def from_csv(cls, path: str | os.PathLike) -> "OutputSweep":
        """Read a sweep written by :meth:`to_csv`.

        Parameters
        ----------
        path : str or os.PathLike

        Returns
        -------
        OutputSweep
        """
        with open(path, newline="") as f:
            rows = list(csv.DictReader(f))
        if not rows:
            raise ParameterError(f"{path}: no points")
        names = [c[:-len("_amplitude")] for c in rows[0] if c.endswith("_amplitude") and c != "amplitude"]

        def col(key, kind=float):
            return np.array([kind(r[key]) for r in rows])

        def harmonic(amp, ph):
            return col(amp) * np.exp(-1j * col(ph))

        def optional(key, kind):
            # written empty when not judged (the whole column) or unknown (one point)
            if not any(r.get(key) for r in rows):
                return None
            return np.array([kind(int(r[key])) if r.get(key) else None for r in rows], dtype=object)
        fold = optional("fold", bool)
        return cls(omega=col("omega"), output=rows[0]["output"], response=harmonic("amplitude", "phase"),
                   limits={n: harmonic(f"{n}_amplitude", f"{n}_phase") for n in names},
                   stuck=col("stuck", lambda v: bool(int(v))), converged=col("converged", lambda v: bool(int(v))),
                   dissipated_per_cycle=col("dissipated_per_cycle"), messages=tuple(r["message"] for r in rows),
                   stable=optional("stable", bool), fold=None if fold is None else fold.astype(bool),
                   truncation_error=(col("truncation_error") if any(r.get("truncation_error") for r in rows)
                                     else None))

    def plot(self, ax: Axes | None = None, path: str | os.PathLike | None = None) -> Figure:
        """The output's amplitude against frequency with its two linear limits
        (:func:`frictionjoint.plotting.plot_output_sweep`).

        Parameters
        ----------
        ax : matplotlib Axes, optional
            Draw into these axes instead of a new figure.
        path : str or os.PathLike, optional
            Write the figure there.

        Returns
        -------
        matplotlib.figure.Figure
        """
        from ..plotting import plot_output_sweep, plot_target

        ax, path = plot_target(ax, path)
        return plot_output_sweep(self, ax=ax, path=path)

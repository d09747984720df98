"""Dovetail blade root: two flanks inclined at ``gamma``, loaded by the centrifugal force.

Geometry and sign convention (DESIGN.md section 4). Root coordinates ``(X, Y)``: ``X``
tangential (in the plane of the dovetail, across the root), ``Y`` radial, positive outward; the
centrifugal force ``Fc`` pulls the blade in ``+Y``. The flank angle ``gamma`` is the angle
between each flank's normal and the radial axis. The disc pushes on the blade through the
*right* flank (at ``X > 0``) along ``n_R = (-sin g, -cos g)`` and through the *left* flank
along ``n_L = (+sin g, -cos g)`` (towards the centre line and inward). Each flank's tangent
points outward along the flank: ``t_R = (-cos g, sin g)``, ``t_L = (cos g, sin g)``. For a root
displacement ``u = (X, Y)`` the normal approach of a flank is ``-n . u`` and its tangential
displacement is ``s = t . u``. The flank force on the blade is ``N n - T t``: ``N >= 0`` the
normal force, ``T`` the friction force, positive when it acts radially inward on the blade,
i.e. against the outward slip of the blade during run-up.

Static (spun-up) state, both flanks alike, radial equilibrium ``Fc = 2 (N cos g + T sin g)``,
flanks elastic in the normal (``kn``) and tangential (``kt``) directions, ``Fc`` raised
monotonically from zero (radial root motion ``Y0``: approach ``Y0 cos g``, slip ``Y0 sin g``):

* frictionless: ``N = Fc/(2 cos g)``;
* stuck, when ``(kt/kn) tan g <= mu`` (the ratio ``T/N`` is then constant during run-up, so the
  flanks never slip): ``Y0 = Fc/(2 (kn cos^2 g + kt sin^2 g))``, ``N = kn Y0 cos g``,
  ``T = kt Y0 sin g``;
* slipping during run-up otherwise: ``N = Fc/(2 (cos g + mu sin g))``, ``T = mu N``,
  ``Y0 = N/(kn cos g)``.

Rocking (optional): with a ``rocking_dof`` and a ``flank_half_width`` ``a``, the root also turns.
The rocking coordinate ``theta`` is the blade's slope ``dX/dY`` at the root (a beam's rotation DOF;
a rigid turn of the root block by ``-theta``, clockwise for ``theta > 0``). Each flank's contact
point lies at ``X = +a`` (right) or ``-a`` (left) on the root's centre line and moves by ``u_i = (X,
Y - x_i theta)``: tipping the blade towards ``+X`` unloads the right flank and loads the left one.
The root coordinates are then ``(X, Y, theta)`` and every flank quantity goes through its own
contact point (:attr:`DovetailRoot.normal_rows`, :attr:`DovetailRoot.tangent_rows`).

Dynamics around the static state (the structure's coordinates are measured from it): each flank is
a joint element along its own tangent -- one Jenkins slider (``kt``, ``mu N0``) for a flat flank
with sharp edges, which sticks or slips as a whole, or the Iwan sliders of a microslip contact
(rounded edges) built by ``flank_contact``; the normal flank springs ``kn`` act along the
normals. In the marched model the slip limit uses the static normal load ``N0`` (frozen), or,
with ``normal_load_variation=True`` (flat flanks), follows the root motion, ``N = kn max(N0/kn -
n . u, 0)``, with lift-off, as in the displacement-driven :class:`DrivenDovetail`.

For purely tangential root motion ``X`` and a frozen ``N0``, the two flanks in steady cycles are
the equivalent Jenkins element of stiffness ``2 kt cos^2 g`` and slip force ``2 mu N0 cos g``
(slip onset ``X_s = mu N0/(kt cos g)``, dissipation ``8 mu N0 (X cos g - mu N0/kt)``) in parallel
with the linear spring ``2 kn sin^2 g``; from the preloaded static state the virgin loading
differs (one flank starts at ``T0``, the other at ``-T0`` relative to the motion), and without
preload (``T0 = 0``) the equivalence is exact along any path.
"""
from __future__ import annotations

from dataclasses import dataclass
import math
from typing import Any, Callable

import numpy as np
from numpy.typing import ArrayLike

from ..errors import ParameterError, check_bool, check_positive, check_real
from ..structure import LinearStructure
from .base import Attachment, Contact, Slider
from .driven import DrivenSliders
from .iwan import check_n_sliders
from .jenkins import Jenkins

__all__ = ["DovetailRoot", "DovetailStatic", "DrivenDovetail", "FLANK_OUTPUTS", "RESOLUTION"]

#: the largest error, relative to a flank's slip travel, that the rounding of a driven root's
#: displacement may cause (:class:`DrivenDovetail`)
RESOLUTION = 1e-6

#: the flanks' forces and slip states as the FMUs report them (DovetailRoot.fmu, BladeDovetail.fmu):
#: name -> (type, description with unit)
FLANK_OUTPUTS = {
    "normal_force_right": (float, "normal force of the right flank [N]"),
    "normal_force_left": (float, "normal force of the left flank [N]"),
    "friction_force_right": (float, "friction force of the right flank, positive radially inward on the blade [N]"),
    "friction_force_left": (float, "friction force of the left flank, positive radially inward on the blade [N]"),
    "slipping_right": (bool, "true while the right flank slips"),
    "slipping_left": (bool, "true while the left flank slips"),
}

def flank_directions(flank_angle: float) -> tuple[np.ndarray, np.ndarray]:
    """The flanks' normals ``n_R = (-sin g, -cos g)``, ``n_L = (sin g, -cos g)`` (force directions on
    the blade) and tangents ``t_R = (-cos g, sin g)``, ``t_L = (cos g, sin g)``: (2, 2) arrays, rows
    right/left, columns the root coordinates ``(X, Y)`` (the convention of the module docstring)."""
    c, s = math.cos(flank_angle), math.sin(flank_angle)
    return np.array([[-s, -c], [s, -c]]), np.array([[-c, s], [c, s]])


@dataclass(frozen=True)
class DovetailStatic:
    """Static state of the spun-up root (both flanks alike).

    Attributes
    ----------
    normal_force : float
        ``N0`` per flank [N].
    friction_force : float
        ``T0`` per flank [N], radially inward on the blade (>= 0).
    radial_displacement : float
        Outward root displacement ``Y0`` during run-up [m].
    regime : str
        ``'stuck'`` or ``'slipping'`` (the flanks during run-up).
    """

    normal_force: float
    friction_force: float
    radial_displacement: float
    regime: str


class DovetailRoot:
    """Dovetail blade-root damping element (two inclined flanks, centrifugal load).

    Parameters
    ----------
    centrifugal_force : float
        ``Fc`` [N], > 0 (or use :meth:`from_rotor`).
    flank_angle : float
        ``gamma`` [rad], angle between the flank normal and the radial axis, in [0, pi/2).
    friction_coefficient : float
        ``mu`` [-], > 0.
    normal_stiffness : float
        Normal contact stiffness ``kn`` of one flank [N/m], > 0.
    tangential_stiffness : float, optional
        Tangential stiffness ``kt`` of one flat flank [N/m], > 0. Required unless
        ``flank_contact`` is given (the contact's initial stiffness is then used).
    tangential_dof, radial_dof : str or int, optional
        Structure DOFs of the root's tangential and radial translation; at least one.
    rocking_dof : str or int, optional
        Structure DOF of the root's rocking ``theta`` (the blade's slope ``dX/dY`` at the root
        [rad]; module docstring); requires ``flank_half_width``.
    flank_half_width : float, optional
        Distance ``a`` [m], > 0, of each flank's contact point from the root's centre line (the
        rocking lever arm).
    normal_damping : float
        Viscous damping of each flank's normal contact [N s/m], >= 0: a dashpot along the flank
        normal beside ``kn`` (contact damping; without it the blade's rigid-body motions on its
        root are undamped). The displacement-driven :class:`DrivenDovetail` is rate-independent:
        it carries no dashpot.
    normal_load_variation : bool
        If true (flat flanks only), the slip limit of each flank follows its normal load in the
        marched dynamics, ``mu N`` with ``N = kn max(N0/kn - n . u, 0)``: the flank lifts off
        (no normal or friction force, the dashpot off too) where ``N`` reaches 0 and closes again
        (stuck, unstressed) where it comes back; the dynamics stay piecewise linear. Otherwise
        the slip limit is the static ``mu N0`` (frozen) and the normal springs are bilateral.
    flank_contact : callable, optional
        ``flank_contact(normal_load)`` -> a microslip contact (e.g.
        :class:`~frictionjoint.contact.MindlinContact` or a half-plane contact of a rounded
        flank) with ``slip_force == mu normal_load`` and ``to_iwan(n_sliders)``; each flank is
        then the discrete Iwan element of that contact at the static normal load.
    n_sliders : int
        Sliders per microslip flank, in ``[1, MAX_SLIDERS]`` (:data:`~frictionjoint.elements.iwan.MAX_SLIDERS`).
    """

    def __init__(self, centrifugal_force: float, flank_angle: float, friction_coefficient: float,
                 normal_stiffness: float, tangential_stiffness: float | None = None,
                 tangential_dof: str | int | None = None, radial_dof: str | int | None = None,
                 flank_contact: Callable[[float], Any] | None = None, n_sliders: int = 16,
                 rocking_dof: str | int | None = None, flank_half_width: float | None = None,
                 normal_damping: float = 0.0, normal_load_variation: bool = False):
        self._args = dict(centrifugal_force=centrifugal_force, flank_angle=flank_angle,
                          friction_coefficient=friction_coefficient, normal_stiffness=normal_stiffness,
                          tangential_stiffness=tangential_stiffness, tangential_dof=tangential_dof,
                          radial_dof=radial_dof, flank_contact=flank_contact, n_sliders=n_sliders,
                          rocking_dof=rocking_dof, flank_half_width=flank_half_width,
                          normal_damping=normal_damping, normal_load_variation=normal_load_variation)
        self.centrifugal_force = check_positive("centrifugal_force", centrifugal_force)
        g = check_real("flank_angle", flank_angle)
        if not 0.0 <= g < 0.5 * math.pi:
            raise ParameterError(f"flank_angle must be in [0, pi/2) rad, got {flank_angle!r}")
        self.flank_angle = g
        self.friction_coefficient = check_positive("friction_coefficient", friction_coefficient)
        self.normal_stiffness = check_positive("normal_stiffness", normal_stiffness)
        if tangential_dof is None and radial_dof is None:
            raise ParameterError("give tangential_dof, radial_dof or both (the root DOFs)")
        self.tangential_dof = tangential_dof
        self.radial_dof = radial_dof
        if (rocking_dof is None) != (flank_half_width is None):
            raise ParameterError("rocking_dof and flank_half_width go together (give both or neither)")
        self.rocking_dof = rocking_dof
        self.flank_half_width = None if flank_half_width is None else \
            check_positive("flank_half_width", flank_half_width)
        self.normal_damping = check_real("normal_damping", normal_damping)
        if self.normal_damping < 0:
            raise ParameterError(f"normal_damping must be >= 0 N s/m, got {normal_damping!r}")
        self.normal_load_variation = check_bool("normal_load_variation", normal_load_variation)
        if self.normal_load_variation and flank_contact is not None:
            raise ParameterError("normal_load_variation needs flat flanks (flank_contact is None)")
        self.flank_contact = flank_contact
        if flank_contact is None:
            if tangential_stiffness is None:
                raise ParameterError("tangential_stiffness is required for flat flanks "
                                     "(flank_contact is None)")
            self.tangential_stiffness = check_positive("tangential_stiffness", tangential_stiffness)
            self._table = None
        else:
            self.tangential_stiffness, self._table = self._microslip_flank(
                flank_contact, tangential_stiffness, n_sliders)
        self.static = self._static(self.tangential_stiffness)
        self._check_static_finite()
        #: flank normals (force directions on the blade) and tangents, rows right/left, (X, Y)
        self.normals, self.tangents = flank_directions(g)
        #: the same in the root coordinates, (X, Y) or with rocking (X, Y, theta): ``n_i . B_i``
        #: and ``t_i . B_i``, ``B_i`` the map to flank i's contact point (module docstring)
        self.normal_rows, self.tangent_rows = self._rows()

    def _microslip_flank(self, flank_contact, tangential_stiffness, n_sliders):
        """``(kt, iwan)``: a microslip flank's tangential stiffness and Iwan table, the contact
        ``flank_contact(N0)`` at the static normal load. The flank stiffness sets ``N0`` (stuck
        run-up) and the contact at ``N0`` sets the stiffness (unless ``tangential_stiffness`` is
        given): iterated to the fixed point (the stiffness grows only like ``N0^(1/3)``)."""
        if not callable(flank_contact):
            raise ParameterError("flank_contact must be a callable normal_load -> contact")
        n_sliders = check_n_sliders("n_sliders", n_sliders)
        kt = check_positive("tangential_stiffness", tangential_stiffness) \
            if tangential_stiffness is not None else None
        k_guess = kt if kt is not None else 1.0
        for _ in range(100):
            n0 = self._static(k_guess).normal_force
            contact = flank_contact(n0)
            iwan = contact.to_iwan(int(n_sliders))
            k_new = iwan.stiffness if kt is None else kt
            if abs(self._static(k_new).normal_force - n0) <= 1e-15 * n0:
                break
            k_guess = k_new
        else:
            raise ParameterError("flank_contact: the static normal load and the flank stiffness "
                                 "did not reach a fixed point in 100 iterations")
        fs = float(contact.slip_force)
        if not math.isclose(fs, self.friction_coefficient * n0, rel_tol=1e-9):
            raise ParameterError(
                f"flank_contact(N) must have slip_force = friction_coefficient * N "
                f"= {self.friction_coefficient * n0:g} N, got {fs:g} N")
        return k_new, iwan

    def _check_static_finite(self):
        """Refuses a static state whose slip limit ``mu N0`` or a spring force overflows: no finite
        answer would be right."""
        n0 = self.static.normal_force
        if not (math.isfinite(n0) and math.isfinite(self.friction_coefficient * n0)
                and math.isfinite(self.normal_stiffness * self.static.radial_displacement)):
            raise ParameterError(
                f"centrifugal_force = {self.centrifugal_force!r} N, friction_coefficient = "
                f"{self.friction_coefficient!r} and normal_stiffness = {self.normal_stiffness!r} N/m give a "
                f"static normal load N0 = {n0!r} N whose slip limit friction_coefficient * N0 or spring "
                "forces overflow the floating-point range (about 1.8e308)")

    def replace(self, **changes: Any) -> DovetailRoot:
        """The same root with some constructor arguments changed (e.g. ``centrifugal_force``,
        ``friction_coefficient``): the static state is computed anew.

        Parameters
        ----------
        **changes
            Constructor arguments, by keyword.

        Returns
        -------
        DovetailRoot
        """
        unknown = set(changes) - set(self._args)
        if unknown:
            raise ParameterError(f"not DovetailRoot arguments: {sorted(unknown)} (allowed: {sorted(self._args)})")
        return DovetailRoot(**{**self._args, **changes})

    def _rows(self) -> tuple[np.ndarray, np.ndarray]:
        if self.flank_half_width is None:
            return self.normals.copy(), self.tangents.copy()
        a = self.flank_half_width
        nr = np.zeros((2, 3))
        tr = np.zeros((2, 3))
        for i, x_i in enumerate((a, -a)):
            b = np.array([[1.0, 0.0, 0.0], [0.0, 1.0, -x_i]])  # (X, Y, theta) -> contact point (X, Y)
            nr[i] = self.normals[i] @ b
            tr[i] = self.tangents[i] @ b
        return nr, tr

    @property
    def root_coordinates(self) -> tuple[str, ...]:
        """Names of the root coordinates: ``('X', 'Y')`` or, rocking, ``('X', 'Y', 'theta')``."""
        return ("X", "Y") if self.flank_half_width is None else ("X", "Y", "theta")

    @classmethod
    def from_rotor(cls, rotor_speed: float, blade_mass: float, radius: float, **kwargs: Any) -> DovetailRoot:
        """Root with ``Fc = blade_mass * rotor_speed**2 * radius`` (rotor speed [rad/s], blade mass
        [kg], radius of the blade's centre of mass [m]); other arguments as the constructor.

        Parameters
        ----------
        rotor_speed : float
            Rotor angular speed [rad/s], > 0.
        blade_mass : float
            Blade mass [kg], > 0.
        radius : float
            Radius of the blade's centre of mass [m], > 0.
        **kwargs
            The other constructor arguments (``flank_angle``, ``friction_coefficient``,
            ``normal_stiffness``, ...), by keyword.

        Returns
        -------
        DovetailRoot
            The root with ``centrifugal_force = blade_mass * rotor_speed**2 * radius`` [N].
        """
        w = check_positive("rotor_speed", rotor_speed)
        m = check_positive("blade_mass", blade_mass)
        r = check_positive("radius", radius)
        return cls(m * w * w * r, **kwargs)

    # ----------------------------------------------------------------- statics
    def _static(self, kt: float) -> DovetailStatic:
        g, mu, kn, fc = self.flank_angle, self.friction_coefficient, self.normal_stiffness, \
            self.centrifugal_force
        c, s = math.cos(g), math.sin(g)
        if kt * s <= mu * kn * c:  # (kt/kn) tan g <= mu, written without dividing by cos g
            y0 = fc / (2.0 * (kn * c * c + kt * s * s))
            return DovetailStatic(kn * y0 * c, kt * y0 * s, y0, "stuck")
        n0 = fc / (2.0 * (c + mu * s))
        return DovetailStatic(n0, mu * n0, n0 / (kn * c), "slipping")

    @staticmethod
    def frictionless_normal_force(centrifugal_force: float, flank_angle: float) -> float:
        """``N = Fc/(2 cos g)`` [N] per flank without friction.

        Parameters
        ----------
        centrifugal_force : float
            ``Fc`` [N], > 0.
        flank_angle : float
            ``gamma`` [rad], angle between the flank normal and the radial axis.

        Returns
        -------
        float
            Normal force ``N`` of one flank [N].
        """
        return check_positive("centrifugal_force", centrifugal_force) / (
            2.0 * math.cos(check_real("flank_angle", flank_angle)))

    def root_force(self, normal_forces: ArrayLike, friction_forces: ArrayLike) -> np.ndarray:
        """Force ``sum_i (N_i n_i - T_i t_i)`` [N] of the flanks on the blade in the root
        coordinates: ``(X, Y)``, or with rocking ``(X, Y, theta)`` (the last a moment [N m]
        conjugate to ``theta``).

        Parameters
        ----------
        normal_forces : (2,) array_like
            Normal forces ``N_i`` of the right and left flanks [N].
        friction_forces : (2,) array_like
            Friction forces ``T_i`` of the right and left flanks [N], positive radially inward on
            the blade (sign convention of :mod:`~frictionjoint.elements.dovetail`).

        Returns
        -------
        (2,) or (3,) ndarray
            Generalised force of the flanks on the blade in :attr:`root_coordinates`.
        """
        n = np.asarray(normal_forces, dtype=float)
        t = np.asarray(friction_forces, dtype=float)
        return n @ self.normal_rows - t @ self.tangent_rows

    # ----------------------------------------------------------- flank sliders
    def flank_sliders(self) -> list[tuple[Slider, float]]:
        """One flank's sliders with their static preloads [N] (the same on both flanks).

        Flat flank: one Jenkins slider ``(kt, mu N0)`` carrying ``T0``. Microslip flank: the
        contact's Iwan sliders, preloaded as on monotonic tangential loading to ``T0`` at the
        constant load ``N0`` (an approximation: during run-up ``N`` grows with ``T``).
        """
        st = self.static
        if self._table is None:
            return [(Slider(self.friction_coefficient * st.normal_force, self.tangential_stiffness),
                     st.friction_force)]
        k, f, _ = self._table._table()
        if st.friction_force >= self._table.slip_force * (1 - 1e-12):
            pre = f.copy()
        else:
            u = self._table.displacement(st.friction_force)
            pre = np.minimum(k * u, f)
        return [(Slider(float(fi), float(ki)), float(p)) for ki, fi, p in zip(k, f, pre)]

    def stuck_stiffness(self) -> np.ndarray:
        """Root stiffness in :attr:`root_coordinates` with both flanks stuck, (2, 2) [N/m] or
        rocking (3, 3) [N/m, N/rad, N m/rad]: ``sum_i kn r_i r_i^T + kt q_i q_i^T`` over the flanks'
        normal and tangent rows; ``XX = 2 (kn sin^2 g + kt cos^2 g)``, rocking ``2 a^2 (kn cos^2
        g + kt sin^2 g)``."""
        return (self.normal_stiffness * self.normal_rows.T @ self.normal_rows
                + self.tangential_stiffness * self.tangent_rows.T @ self.tangent_rows)

    def equivalent_jenkins(self, dof: str | int | None = None,
                           direction: ArrayLike | None = None) -> tuple[Jenkins, float]:
        """Equivalent element for purely tangential root motion (frozen ``N0``).

        Returns ``(Jenkins(2 kt cos^2 g, 2 mu N0 cos g), 2 kn sin^2 g)``: the Jenkins element and
        the stiffness [N/m] of the linear spring in parallel with it (flat flanks only).

        Parameters
        ----------
        dof : str or int, optional
            DOF the returned Jenkins element connects to the ground (passed to :class:`Jenkins`).
        direction : (n_dof,) array_like, optional
            Direction vector instead of ``dof`` (passed to :class:`Jenkins`).

        Returns
        -------
        jenkins : Jenkins
            Stiffness ``2 kt cos^2 g`` [N/m], slip force ``2 mu N0 cos g`` [N].
        spring_stiffness : float
            Stiffness ``2 kn sin^2 g`` [N/m] of the linear spring in parallel.
        """
        if self._table is not None:
            raise ParameterError("equivalent_jenkins needs flat flanks (flank_contact is None)")
        c, s = math.cos(self.flank_angle), math.sin(self.flank_angle)
        jen = Jenkins(2.0 * self.tangential_stiffness * c * c,
                      2.0 * self.friction_coefficient * self.static.normal_force * c,
                      dof=dof, direction=direction)
        return jen, 2.0 * self.normal_stiffness * s * s

    # ---------------------------------------------------------- attachment
    def _root_map(self, structure) -> np.ndarray:
        """(k, n_dof) map from structure DOFs to the root coordinates (:attr:`root_coordinates`)."""
        dofs = (self.tangential_dof, self.radial_dof, self.rocking_dof)[:self.normal_rows.shape[1]]
        a = np.zeros((len(dofs), structure.n_dof))
        for row, dof in enumerate(dofs):
            if dof is not None:
                a[row, structure.dof_index(dof)] = 1.0
        return a

    def attach(self, structure: LinearStructure) -> Attachment:
        """Sliders along each flank tangent, normal springs and the centrifugal force, projected
        onto the structure's root DOFs (coordinates measured from the static state).

        Parameters
        ----------
        structure : LinearStructure
            Structure holding ``tangential_dof`` and ``radial_dof``.

        Returns
        -------
        Attachment
            Slider directions ``(k, n_dof)``, the ``k`` flank sliders and their static preloads [N],
            the normal springs' stiffness ``(n_dof, n_dof)`` [N/m] and the constant force
            ``(n_dof,)`` [N] (centrifugal force and normal preloads), and the normal dashpots'
            damping ``(n_dof, n_dof)`` [N s/m] (None without them).
        """
        a = self._root_map(structure)
        table = self.flank_sliders()
        directions, sliders, preload = [], [], []
        for i in range(2):
            d = self.tangent_rows[i] @ a
            if not np.any(d):  # a flank tangent normal to the attached DOFs moves nothing
                if self.normal_load_variation:
                    raise ParameterError("normal_load_variation needs both flank tangents to move the "
                                         "attached root DOFs (attach tangential_dof)")
                continue
            for sl, p in table:
                directions.append(d)
                sliders.append(sl)
                preload.append(p)
        nn = sum(np.outer(self.normal_rows[i] @ a, self.normal_rows[i] @ a) for i in range(2))
        kn = self.normal_stiffness * nn
        # x = 0 is the static state: Fc and the normal preloads N0 n_i (the linear normal springs
        # carry only the change) balance the preloaded sliders' -T0 t_i (their moments cancel)
        radial = np.zeros(a.shape[0])
        radial[1] = 1.0
        f_root = self.centrifugal_force * radial + self.static.normal_force * self.normal_rows.sum(axis=0)
        force = f_root @ a
        contacts, slider_contact = (), None
        if self.normal_load_variation:  # one flat slider per flank, on that flank's contact
            contacts = tuple(Contact(self.normal_rows[i] @ a, self.normal_stiffness, self.normal_damping,
                                     self.static.normal_force, self.friction_coefficient) for i in range(2))
            slider_contact = [0, 1]
        return Attachment(np.array(directions).reshape(len(directions), structure.n_dof), sliders,
                          np.array(preload), kn, force,
                          self.normal_damping * nn if self.normal_damping > 0 else None,
                          contacts, slider_contact)

    def driven(self, normal_load_variation: bool = False) -> "DrivenDovetail":
        """Displacement-driven flanks starting in the static state (:class:`DrivenDovetail`).

        Parameters
        ----------
        normal_load_variation : bool
            If true (flat flanks only), the normal loads follow the root motion with lift-off;
            otherwise the slip limits use the frozen static normal load ``N0``.

        Returns
        -------
        DrivenDovetail
        """
        return DrivenDovetail(self, normal_load_variation)

    def __repr__(self) -> str:
        rock = "" if self.flank_half_width is None else f", flank_half_width={self.flank_half_width:g}"
        return (f"DovetailRoot(centrifugal_force={self.centrifugal_force:g}, flank_angle="
                f"{self.flank_angle:g}, friction_coefficient={self.friction_coefficient:g}, "
                f"normal_stiffness={self.normal_stiffness:g}, tangential_stiffness="
                f"{self.tangential_stiffness:g}{rock})")


class DrivenDovetail:
    """Dovetail flanks driven by a prescribed root displacement ``u`` from the static state (the
    root coordinates ``(X, Y)``, or ``(X, Y, theta)`` of a rocking root), exact for paths linear
    between updates. Below, ``n . u`` and ``t . u`` stand for the flank's rows
    (:attr:`DovetailRoot.normal_rows`, :attr:`DovetailRoot.tangent_rows`) applied to ``u``.

    Per flank: normal force ``N = N0 - kn n . u`` and a slip limit from ``N0`` (frozen; flat or
    microslip flanks: each flank's sliders are the exact play operator
    :class:`~frictionjoint.elements.driven.DrivenSliders` along ``s = t . u``), or, with
    ``normal_load_variation=True`` (flat flanks), ``N = kn max(N0/kn - n . u, 0)`` with lift-off and
    the Jenkins friction ``T = kt (s - w)``, ``|T| <= mu N``. Along a linear path segment ``s`` and
    ``N`` are linear, so ``|T_trial| - mu N`` is linear: a flank stuck at both ends is stuck
    throughout, and one that reaches the limit slips to the end of the segment. The update is the
    return map at the segment end; the energy dissipated is ``mu (N(lambda*) + N(1))/2 |dw|``
    from the onset ``lambda*`` (trapezoid, exact). A segment that crosses lift-off is split there.

    Floating point resolves a flank's slip only while the rounding of its displacements stays
    far below its slip travel: :meth:`update` refuses a root motion that moves a flank by more than
    :attr:`max_flank_displacement` along or across it, or whose forces overflow.

    Attributes
    ----------
    u : (2,) or (3,) ndarray
        Current root coordinates [m, rad].
    max_flank_displacement : (2,) ndarray
        Largest ``|t . u|`` and ``|n . u|`` [m]: the rounding of a displacement (relative
        ``2.2e-16``) stays below :data:`RESOLUTION` of the smallest slider travel
        ``slip_force / stiffness`` (along) and of the static approach ``N0 / kn`` (across).
    normal_force, friction_force : (2,) ndarray
        Flank forces [N], right and left (sign convention of :mod:`~frictionjoint.elements.dovetail`).
    slipping : (2,) bool ndarray
        Flanks in gross slip (all their sliders slipping) at the end of the last update.
    dissipated_energy : float
        Energy dissipated since the start [J].
    """

    def __init__(self, root: DovetailRoot, normal_load_variation: bool = True):
        self.root = root
        self.vary = bool(normal_load_variation)
        st = root.static
        self.kn, self.mu = root.normal_stiffness, root.friction_coefficient
        self.gap0 = st.normal_force / self.kn  # static approach of each flank
        self.u = np.zeros(root.normal_rows.shape[1])
        if self.vary:
            if root._table is not None:
                raise ParameterError("normal_load_variation needs flat flanks (flank_contact is None)")
            self.kt = root.tangential_stiffness
            self.w = np.full(2, -st.friction_force / self.kt)
            self._flanks = None
        else:
            table = root.flank_sliders()
            k = [sl.stiffness for sl, _ in table]
            self._flanks = []
            for _ in range(2):
                d = DrivenSliders(k, [sl.slip_force for sl, _ in table])
                d.w = -np.array([p for _, p in table]) / np.array(k)  # preloaded: force T0 at s = 0
                self._flanks.append(d)
        self.slipping = np.zeros(2, dtype=bool)
        self._dissipated = 0.0
        travel = min(sl.slip_force / sl.stiffness for sl, _ in root.flank_sliders())
        eps = np.finfo(float).eps
        self.max_flank_displacement = np.array([travel, self.gap0]) * (RESOLUTION / eps)
        self._update_forces()

    @property
    def dissipated_energy(self) -> float:
        if self._flanks is None:
            return self._dissipated
        return self._flanks[0].dissipated_energy + self._flanks[1].dissipated_energy

    def _normal(self, u) -> np.ndarray:
        approach = self.gap0 - self.root.normal_rows @ u
        if self.vary:
            return self.kn * np.maximum(approach, 0.0)
        return self.kn * approach

    def _update_forces(self) -> None:
        self.normal_force = self._normal(self.u)
        if self._flanks is None:
            self.friction_force = self.kt * (self.root.tangent_rows @ self.u - self.w)
        else:
            self.friction_force = np.array([f.force for f in self._flanks])

    @property
    def root_force(self) -> np.ndarray:
        """Flank forces on the blade in the root coordinates [N, N m] (the static part balances
        ``Fc``)."""
        return self.root.root_force(self.normal_force, self.friction_force)

    def update(self, u) -> None:
        """Move the root linearly from the current ``u`` to ``u`` [m, rad]."""
        u = np.asarray(u, dtype=float).reshape(-1)
        names = ", ".join(self.root.root_coordinates)
        if u.shape != self.u.shape or not np.all(np.isfinite(u)):
            raise ParameterError(f"u must be finite root coordinates ({names}) [m, rad], got {u!r}")
        moves = np.abs([self.root.tangent_rows @ u, self.root.normal_rows @ u]).max(axis=1)
        if np.any(moves > self.max_flank_displacement):
            limit = self.max_flank_displacement
            raise ParameterError(
                f"u = {u!r} ({names}) moves a flank by {moves[0]:.3g} m along and {moves[1]:.3g} m across it; "
                f"allowed: at most {limit[0]:.3g} m along and {limit[1]:.3g} m across, where the rounding of a "
                f"displacement stays below {RESOLUTION:g} of the slip travel slip_force/stiffness and of the "
                "static approach N0/kn")
        saved = self.state()
        self._move(u)
        if not all(np.all(np.isfinite(a)) for a in (self.normal_force, self.friction_force, self.root_force,
                                                    self.dissipated_energy)):
            self.set_state(saved)
            raise ParameterError(f"u = {u!r} ({names}) gives flank forces beyond the floating-point range "
                                 "(stiffness times displacement overflows)")

    def _move(self, u) -> None:
        """:meth:`update` to the validated ``u``."""
        if self._flanks is not None:
            s = self.root.tangent_rows @ u
            for i, f in enumerate(self._flanks):
                f.update(float(s[i]))
                self.slipping[i] = bool(f.slipping.all())
        else:
            u0 = self.u
            cuts = [0.0, 1.0]
            a0 = self.gap0 - self.root.normal_rows @ u0
            a1 = self.gap0 - self.root.normal_rows @ u
            for x0, x1 in zip(a0, a1):  # split where a flank lifts off or closes
                if (x0 > 0) != (x1 > 0):
                    cuts.append(x0 / (x0 - x1))
            cuts = sorted(set(min(max(c, 0.0), 1.0) for c in cuts))
            for la, lb in zip(cuts[:-1], cuts[1:]):
                self._segment(u0 + la * (u - u0), u0 + lb * (u - u0))
        self.u = u.copy()
        self._update_forces()

    def _segment(self, ua, ub) -> None:
        t = self.root.tangent_rows
        sa, sb = t @ ua, t @ ub
        la, lb = self.mu * self._normal(ua), self.mu * self._normal(ub)
        trial = self.kt * (sb - self.w)
        slip = np.abs(trial) > lb
        for i in np.flatnonzero(slip):
            sig = math.copysign(1.0, trial[i])
            # onset: kt (s(l) - w) = sig mu N(l), both linear in l
            ga = self.kt * (sa[i] - self.w[i]) - sig * la[i]
            gb = trial[i] - sig * lb[i]
            lam = 0.0 if ga * sig >= 0 or gb == ga else ga / (ga - gb)
            lim_on = la[i] + lam * (lb[i] - la[i])
            w_new = sb[i] - sig * lb[i] / self.kt
            self._dissipated += 0.5 * (lim_on + lb[i]) * abs(w_new - self.w[i])
            self.w[i] = w_new
        self.slipping = slip

    def tangent_stiffness(self) -> np.ndarray:
        """Root tangent stiffness (k, k) in the root coordinates, ``-d(root force)/du`` in the current state: normal
        springs in contact, stuck sliders, and for slipping flanks with varying normal load the
        non-symmetric term ``-sig mu kn t n^T``."""
        n, t = self.root.normal_rows, self.root.tangent_rows
        k = np.zeros((self.u.size, self.u.size))
        for i in range(2):
            in_contact = self.normal_force[i] > 0 or not self.vary
            if in_contact:
                k += self.kn * np.outer(n[i], n[i])
            if self._flanks is not None:
                f = self._flanks[i]
                kt = float(f.stiffness[~f.slipping].sum())
                k += kt * np.outer(t[i], t[i])
            elif not self.slipping[i]:
                if in_contact:
                    k += self.kt * np.outer(t[i], t[i])
            elif in_contact:
                sig = math.copysign(1.0, self.friction_force[i])
                # T = sig mu kn (gap0 - n.u): force -T t, so -dF/du = -sig mu kn t n^T
                k += -sig * self.mu * self.kn * np.outer(t[i], n[i])
        return k

    def state(self):
        """Copy of the internal state (for FMU get/set state)."""
        if self._flanks is None:
            inner = (self.w.copy(), self._dissipated)
        else:
            inner = tuple(f.copy() for f in self._flanks)
        return (self.u.copy(), self.slipping.copy(), inner)

    def set_state(self, state) -> None:
        u, slipping, inner = state
        self.u, self.slipping = np.array(u, float), np.array(slipping, bool)
        if self._flanks is None:
            self.w, self._dissipated = np.array(inner[0], float), float(inner[1])
        else:
            self._flanks = [f.copy() for f in inner]
        self._update_forces()

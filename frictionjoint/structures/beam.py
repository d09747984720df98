"""A blade as a uniform Euler-Bernoulli beam: finite elements with rotation.

Frame and signs. The blade is a straight uniform beam of length ``L`` along the radial axis
``s`` (``s = 0`` at the root, at radius ``R`` = ``hub_radius`` from the rotation axis, ``s = L``
at the tip), rotating at ``rotor_speed`` ``Omega`` [rad/s] about an axis perpendicular to it.
Each node ``i`` (``s_i = i L / n_elements``) has three DOFs, named ``u{i}``, ``w{i}``, ``t{i}``:

- ``u``: axial (radial) displacement [m], positive outward;
- ``w``: transverse displacement [m] in the bending plane, ``bending="flapwise"``: out of the
  plane of rotation (along the rotation axis), ``"chordwise"``: in the plane of rotation;
- ``t``: the slope ``dw/ds`` [rad].

Elements: Hermite cubics for ``w`` (bending stiffness ``E I``, consistent mass), linear bars for
``u`` (``E A``). Rotation adds, in the frame that rotates with the blade,

- centrifugal stiffening of bending: the axial force ``T(s) = rho A Omega^2 [R (L - s) +
  (L^2 - s^2) / 2]`` gives ``K_G = int T N'^T N' ds`` (Gauss, exact for the quadratic ``T``);
- spin softening ``-Omega^2 M`` of the axial DOFs and, for chordwise bending, of ``w`` (the
  centrifugal force follows the in-plane displacement): in the continuous problem and in the
  discrete one alike, ``omega_chord^2 = omega_flap^2 - Omega^2``;
- Coriolis coupling of axial and chordwise motion is left out (a gyroscopic term; the tables of
  rotating cantilevers leave it out too), and so is the static elongation under ``T``.

The root node's DOFs are kept in :attr:`BeamBlade.structure` (for the root joints); the natural
frequencies are those with the root clamped. The rotating blade alone has negative stiffness
directions (spin softening of its free root): the joints that hold it make the assembly stable.
"""
from __future__ import annotations

import functools
import math

import numpy as np
import scipy.linalg

from ..errors import ParameterError, check_count, check_nonnegative, check_positive
from ..memory import check_fits
from ..structure import LinearStructure
from .scales import check_scales

__all__ = ["BeamBlade", "BENDING", "euler_bernoulli_cantilever"]

#: bending planes of :class:`BeamBlade`
BENDING = ("flapwise", "chordwise")

#: roots beta_n L of 1 + cos(x) cosh(x) = 0 (clamped-free Euler-Bernoulli beam)
_CANTILEVER_ROOTS = (1.8751040687119611, 4.6940911329741746, 7.8547574382376126, 10.995540734875467,
                     14.137168391046471)

# 4-point Gauss-Legendre rule on [0, 1]: exact for the polynomials of degree <= 7 of K_G
_GX, _GW = np.polynomial.legendre.leggauss(4)
_GX, _GW = 0.5 * (_GX + 1.0), 0.5 * _GW


def euler_bernoulli_cantilever(n: int, length: float, bending_stiffness: float, mass_per_length: float) -> np.ndarray:
    """Natural angular frequencies [rad/s] of a uniform non-rotating clamped-free Euler-Bernoulli
    beam: ``omega_k = (beta_k L)^2 sqrt(EI / (rho A L^4))`` with ``1 + cos(beta L) cosh(beta L) = 0``.

    Parameters
    ----------
    n : int
        Number of modes, 1 ... 5.
    length : float
        ``L`` [m], > 0.
    bending_stiffness : float
        ``E I`` [N m^2], > 0.
    mass_per_length : float
        ``rho A`` [kg/m], > 0.

    Returns
    -------
    (n,) ndarray
    """
    n = check_count("n", n, 1)
    if n > len(_CANTILEVER_ROOTS):
        raise ParameterError(f"n must be in [1, {len(_CANTILEVER_ROOTS)}], got {n}")
    scale = math.sqrt(check_positive("bending_stiffness", bending_stiffness)
                      / (check_positive("mass_per_length", mass_per_length) * check_positive("length", length) ** 4))
    return np.array(_CANTILEVER_ROOTS[:n]) ** 2 * scale


class BeamBlade:
    """A uniform rotating blade: Euler-Bernoulli beam finite elements with axial DOFs.

    Parameters
    ----------
    length : float
        ``L`` [m], > 0.
    width : float
        Chord ``b`` [m], > 0.
    thickness : float
        ``h`` [m], > 0.
    youngs_modulus : float
        ``E`` [Pa], > 0.
    density : float
        ``rho`` [kg/m^3], > 0.
    n_elements : int
        Beam elements, >= 1 (30: the first three bending frequencies within 3.3e-6 of the
        Euler-Bernoulli closed form; 20: 1.6e-5); the matrices are dense, and a number whose six
        ``3 (n + 1)``-square matrices would not fit in the available memory is refused. ``E``,
        ``rho`` and ``Omega`` must keep the matrices' entries and ``omega^2`` within ``[2.8e-103,
        5.6e102]`` (:mod:`~frictionjoint.structures.scales`).
    rotor_speed : float
        ``Omega`` [rad/s], >= 0.
    hub_radius : float
        ``R``: radius of the root from the rotation axis [m], >= 0.
    bending : {'flapwise', 'chordwise'}
        ``'flapwise'``: out of the plane of rotation, ``I = b h^3 / 12``; ``'chordwise'``: in the
        plane of rotation, ``I = h b^3 / 12``, with spin softening.
    rayleigh : (float, float)
        Viscous damping ``C = alpha M + beta K`` [1/s, s], ``K`` without the spin softening; both
        >= 0.
    """

    def __init__(self, length: float, width: float, thickness: float, youngs_modulus: float, density: float,
                 n_elements: int = 30, rotor_speed: float = 0.0, hub_radius: float = 0.0,
                 bending: str = "flapwise", rayleigh: tuple = (0.0, 0.0)) -> None:
        self.length = check_positive("length", length)
        self.width = check_positive("width", width)
        self.thickness = check_positive("thickness", thickness)
        self.youngs_modulus = check_positive("youngs_modulus", youngs_modulus)
        self.density = check_positive("density", density)
        self.n_elements = check_count("n_elements", n_elements, 1)
        self.rotor_speed = check_nonnegative("rotor_speed", rotor_speed)
        self.hub_radius = check_nonnegative("hub_radius", hub_radius)
        if bending not in BENDING:
            raise ParameterError(f"bending must be one of {BENDING}, got {bending!r}")
        self.bending = bending
        try:
            alpha, beta = (float(v) for v in rayleigh)
        except (TypeError, ValueError):
            raise ParameterError(f"rayleigh must be a pair (alpha, beta) of numbers >= 0, got {rayleigh!r}") from None
        self.rayleigh = (check_nonnegative("rayleigh alpha", alpha), check_nonnegative("rayleigh beta", beta))
        self.area = self.width * self.thickness
        b, h = self.width, self.thickness
        self.second_moment = b * h ** 3 / 12.0 if bending == "flapwise" else h * b ** 3 / 12.0
        check_scales(self._scales(), {"youngs_modulus": self.youngs_modulus, "density": self.density,
                                      "rotor_speed": self.rotor_speed})
        size = 3 * (self.n_elements + 1)  # dense: the assembly's mass, elastic and softening, the
        check_fits(6 * 8.0 * size ** 2, f"n_elements = {self.n_elements}",  # structure's K and C, eigh's copy
                   f"six dense {size} x {size} matrices: the assembly's three, the structure's and the eigensolver's")
        self._mass, self._elastic, self._softening = self._assemble()

    def _scales(self) -> dict:
        """The model's quantities as power laws in E, rho and Omega (log10, exponents, bounded below:
        :func:`~frictionjoint.structures.scales.check_scales`): the element's mass entries (``rho A
        l`` and ``rho A l^3``), its stiffness entries (``E A / l``, ``E I / l^3``, ``E I / l``), the
        highest and lowest ``omega^2`` and the rotation's terms."""
        lg = math.log10
        le = self.length / self.n_elements
        log_e, log_rho, log_a, log_i, log_l = lg(self.youngs_modulus), lg(self.density), lg(self.area), \
            lg(self.second_moment), lg(le)
        e, rho = {"youngs_modulus": 1}, {"density": 1}
        w2 = {"youngs_modulus": 1, "density": -1}
        scales = {"mass entries [kg]": (log_rho + log_a + log_l, rho, True),
                  "slope mass entries [kg m^2]": (log_rho + log_a + 3 * log_l, rho, True),
                  "axial stiffness entries [N/m]": (log_e + log_a - log_l, e, True),
                  "bending stiffness entries [N/m]": (log_e + log_i - 3 * log_l, e, True),
                  "slope stiffness entries [N m]": (log_e + log_i - log_l, e, True),
                  # the elements' highest (consistent mass): 12 E / (rho l^2) axial (linear bar),
                  # 8400 E I / (rho A l^4) bending (Hermite cubic); the assembled model's is below
                  "highest omega^2 [rad^2/s^2]": (log_e - log_rho + max(lg(12) - 2 * log_l,
                                                                        lg(8400) + log_i - log_a - 4 * log_l), w2, True),
                  "lowest omega^2 [rad^2/s^2]": (log_e + log_i - log_rho - log_a - 4 * lg(self.length), w2, True)}
        if self.rotor_speed > 0:
            log_om2 = 2 * lg(self.rotor_speed)
            om = {"rotor_speed": 2}
            scales["rotor_speed^2 [rad^2/s^2]"] = (log_om2, om, False)
            scales["spin softening entries [N/m]"] = (log_om2 + log_rho + log_a + log_l, {**om, **rho}, False)
            scales["geometric stiffness entries [N/m]"] = (
                log_om2 + log_rho + log_a + lg((self.hub_radius + self.length) * self.length) - log_l, {**om, **rho}, False)
        return scales

    # ------------------------------------------------------------------ assembly
    def axial_force(self, s) -> np.ndarray:
        """Centrifugal axial force ``T(s) = rho A Omega^2 [R (L - s) + (L^2 - s^2)/2]`` [N] at
        ``s`` [m] from the root (0 without rotation)."""
        s = np.asarray(s, dtype=float)
        L, R = self.length, self.hub_radius
        return self.density * self.area * self.rotor_speed ** 2 * (R * (L - s) + 0.5 * (L * L - s * s))

    @property
    def centrifugal_force(self) -> float:
        """The blade's centrifugal force on its root, ``T(0)`` [N]."""
        return float(self.axial_force(0.0))

    def _assemble(self):
        n, L = self.n_elements, self.length
        le = L / n
        rho_a = self.density * self.area
        ei, ea = self.youngs_modulus * self.second_moment, self.youngs_modulus * self.area
        size = 3 * (n + 1)
        m, k, soft = (np.zeros((size, size)) for _ in range(3))
        kb = ei / le ** 3 * np.array([[12, 6 * le, -12, 6 * le], [6 * le, 4 * le ** 2, -6 * le, 2 * le ** 2],
                                      [-12, -6 * le, 12, -6 * le], [6 * le, 2 * le ** 2, -6 * le, 4 * le ** 2]])
        mb = rho_a * le / 420 * np.array([[156, 22 * le, 54, -13 * le], [22 * le, 4 * le ** 2, 13 * le, -3 * le ** 2],
                                         [54, 13 * le, 156, -22 * le], [-13 * le, -3 * le ** 2, -22 * le, 4 * le ** 2]])
        ka = ea / le * np.array([[1.0, -1.0], [-1.0, 1.0]])
        ma = rho_a * le / 6 * np.array([[2.0, 1.0], [1.0, 2.0]])
        # slopes of the Hermite shape functions at the Gauss points (d/ds)
        x = _GX
        dn = np.stack([(-6 * x + 6 * x ** 2) / le, 1 - 4 * x + 3 * x ** 2, (6 * x - 6 * x ** 2) / le,
                       -2 * x + 3 * x ** 2], axis=1)
        om2 = self.rotor_speed ** 2
        for e in range(n):
            bend = [3 * e + 1, 3 * e + 2, 3 * e + 4, 3 * e + 5]
            axial = [3 * e, 3 * e + 3]
            kg = (dn.T * (_GW * self.axial_force(e * le + x * le) * le)) @ dn
            k[np.ix_(bend, bend)] += kb + kg
            m[np.ix_(bend, bend)] += mb
            k[np.ix_(axial, axial)] += ka
            m[np.ix_(axial, axial)] += ma
            soft[np.ix_(axial, axial)] += om2 * ma
            if self.bending == "chordwise":
                soft[np.ix_(bend, bend)] += om2 * mb
        return m, k, soft

    # ------------------------------------------------------------------ results
    @property
    def dof_names(self) -> tuple:
        """``u0, w0, t0, u1, ...``: axial, transverse and slope DOFs of each node, root first."""
        return tuple(f"{q}{i}" for i in range(self.n_elements + 1) for q in "uwt")

    @functools.cached_property
    def structure(self) -> LinearStructure:
        """The blade as a :class:`~frictionjoint.structure.LinearStructure` with every DOF, the
        root's included (for the root joints); stiffness = elastic + centrifugal stiffening -
        spin softening (indefinite under rotation until the joints hold the root)."""
        alpha, beta = self.rayleigh
        k = self._elastic - self._softening
        return LinearStructure(self._mass, k, alpha * self._mass + beta * self._elastic, dof_names=self.dof_names,
                               indefinite_stiffness=self.rotor_speed > 0)

    def _clamped(self, kind: str):
        free = [i for i, name in enumerate(self.dof_names) if name[0] in kind and name[1:] != "0"]
        k = (self._elastic - self._softening)[np.ix_(free, free)]
        return k, self._mass[np.ix_(free, free)]

    def natural_frequencies(self, n: int | None = None) -> np.ndarray:
        """Bending natural angular frequencies [rad/s] with the root clamped, ascending (the
        axial modes are uncoupled from bending and not included).

        Parameters
        ----------
        n : int, optional
            How many, >= 1 (all ``2 n_elements`` if omitted).

        Returns
        -------
        (n,) ndarray
        """
        k, m = self._clamped("wt")
        try:
            # the pencil inverted, M phi = mu K phi with mu = 1 / omega^2: the lowest frequencies are
            # then the largest mu, each good to eps of itself, where eigh(K, M) gives omega^2 to
            # eps * lambda_max / lambda_1 of its own value (1e8-1e9 on these meshes: LAPACK's drivers
            # disagreed by 3.4e-8 in omega at 120 elements, by 9e-16 inverted). Needs K positive
            # definite (a spun blade softened beyond it falls back to the direct pencil).
            lam = 1.0 / scipy.linalg.eigh(m, k, eigvals_only=True)[::-1]
        except np.linalg.LinAlgError:
            lam = scipy.linalg.eigh(k, m, eigvals_only=True)
        if n is not None:
            n = check_count("n", n, 1)
            if n > lam.size:
                raise ParameterError(f"n must be in [1, {lam.size}] ({self.n_elements} elements), got {n}")
            lam = lam[:n]
        if lam[0] < 0:
            raise ParameterError(f"the clamped blade is unstable at rotor_speed = {self.rotor_speed!r} rad/s "
                                 f"(omega^2 = {lam[0]:.3g})")
        return np.sqrt(lam)

    def dimensionless(self, omega) -> np.ndarray:
        """``omega L^2 sqrt(rho A / (E I))`` [-] of angular frequencies ``omega`` [rad/s] (the
        scale of the rotating-beam tables; the rotor speed's is :attr:`dimensionless_speed`)."""
        return np.asarray(omega, dtype=float) * self.length ** 2 * math.sqrt(
            self.density * self.area / (self.youngs_modulus * self.second_moment))

    @property
    def dimensionless_speed(self) -> float:
        """``nu = Omega L^2 sqrt(rho A / (E I))`` [-]."""
        return float(self.dimensionless(self.rotor_speed))

    def __repr__(self) -> str:
        return (f"BeamBlade(length={self.length!r}, n_elements={self.n_elements}, bending={self.bending!r}, "
                f"rotor_speed={self.rotor_speed!r}, hub_radius={self.hub_radius!r})")

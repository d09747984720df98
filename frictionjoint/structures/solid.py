"""A blade as a 3D elastic solid: quadratic hexahedra assembled sparse by scikit-fem (issue 30, part 2).

Frame and signs, as :class:`~frictionjoint.structures.BeamBlade`'s. ``x`` is the radial (span)
axis ``s``: the root face at ``x = 0`` sits at radius ``R`` = ``hub_radius`` from the rotation
axis, the tip face at ``x = L``. The rotation axis is parallel to ``z`` through ``(x, y) = (-R,
0)``; the blade spins at ``rotor_speed`` ``Omega`` [rad/s] about it. At the root the chord
(``width``) lies along ``y``, in the plane of rotation, and the thickness along ``z``, along the
rotation axis: BeamBlade's ``"flapwise"`` bending is bending in ``z`` (out of the plane of
rotation, ``I = b h^3 / 12``) and its ``"chordwise"`` bending is bending in ``y`` (in the plane
of rotation, ``I = h b^3 / 12``). The cross-section at ``s`` is the rectangle ``width c(s) x
thickness`` centred on the ``x`` axis, with ``c(s) = 1 + (taper - 1) s / L`` (``taper``: chord at
the tip / chord at the root; the thickness is uniform), turned about ``x`` by ``twist s / L``
(``twist`` [rad]: the tip's angle to the root's, positive from ``y`` towards ``z``).

Elements. Triquadratic 27-node Lagrange hexahedra (scikit-fem's ``ElementHex2``, full 3 x 3 x 3
Gauss integration) on a structured ``n_span x n_chord x n_thickness`` grid of trilinear
hexahedra. Why: a quadratic displacement field holds pure bending exactly, the anticlastic Poisson
terms included (``u = -kappa x z``, ``w = kappa (x^2 + nu (z^2 - y^2)) / 2``), so an element that is
long and thin carries a constant bending moment without the parasitic shear strain that locks
linear hexahedra, and one element through the thickness bends correctly (the transverse normal
strain is linear through it: no Poisson thickness locking either). Measured: the square plate
1 x 1 x h with 8 x 8 x 1 elements has its first five frequencies 0.96-2.4 % above the converged
Kirchhoff plate at a / h = 100 and 1.0-2.7 % at a / h = 1000 (16 x 16 x 1: 0.17-0.59 % and
0.35-0.83 %): the error does not grow as the blade thins. It falls at about second order in the
element size, not fourth: the edges of the clamped root face are singular lines of the 3D solution
(the Kirchhoff plate's clamped corners limit Argyris triangles likewise), and the frequencies
converge from above (tests/test_solid_blade.py: 2.4 %, 1.1 % and 0.6 % at 8, 12 and 16 elements a
side; a blade of L / h = 100, L / b = 20 with 40 x 2 x 1 is within 0.4 % of the Euler-Bernoulli
beam in flapwise bending, and within 1e-4 with nu = 0: the 0.4 % is the clamped root face holding
the Poisson contraction that the beam lets free, about 0.3 % converged, growing with b / L).
Full integration is kept on purpose: uniformly reduced 2 x 2 x 2 integration converges faster on
the plate (its first mode within 0.03 % at 8 x 8 x 1) but leaves 27 zero-energy modes per
element (33 zero eigenvalues in a free single element, 81 in a free 4 x 4 x 1 plate, measured),
and a blend of the two lets those modes down among the physical ones; a root whose contact patches carry the blade must not have them. The 20-node
serendipity element with reduced integration converges no faster here. Tetrahedra need several
layers through the thickness and many more DOFs for the same accuracy. The twist enters through
the trilinear element geometry (each element's edges are straight): the twist per element
should be small (the error is that of approximating the helicoid by bilinear patches).

Rotation, in the frame that rotates with the blade (as BeamBlade's):

- centrifugal stiffening: the steady stress ``sigma0`` of the clamped blade under its centrifugal
  body force ``rho Omega^2 (R + x, y, 0)`` (a linear elastic static solution, the blade's shape
  undeformed: BeamBlade's ``T(s)`` is its resultant) gives the geometric stiffness
  ``K_G = int sigma0_ij (d_i u_k)(d_j v_k) dV``;
- spin softening ``-Omega^2 M_s``, ``M_s = int rho (u_x v_x + u_y v_y) dV``: the mass of the
  motion in the plane of rotation;
- Coriolis coupling is left out (as in BeamBlade and the rotating-beam tables).

:attr:`SolidBlade.stiffness` is ``K_E + K_G - Omega^2 M_s``; the natural frequencies are those
with the root face clamped. The matrices are ``scipy.sparse`` CSR arrays, ordered node by node
(nodes sorted by ``x``, then ``y``, then ``z`` of the undeformed reference grid; directions x, y,
z), and :attr:`SolidBlade.fe_model` is the :class:`~frictionjoint.structures.FEModel` with the DOF
table and the node sets ``"root"`` and ``"tip"`` (the faces) and ``"tip_centre"``, as an FE code's
export would be.
"""
from __future__ import annotations

import functools
import math

import numpy as np
import scipy.sparse as sp
import scipy.sparse.linalg as spla

from ..errors import ParameterError, check_count, check_nonnegative, check_poisson_ratio, check_positive, check_real
from ..memory import check_fits
from ..structure import LinearStructure
from .fe_import import FEModel
from .scales import check_scales

__all__ = ["SolidBlade", "MAX_DENSE_DOF", "MAX_MODULUS_RATIO", "memory_estimate"]

#: largest number of DOFs :attr:`SolidBlade.structure` makes dense (LinearStructure checks its
#: matrices with dense eigenvalues: seconds at 2,000 DOFs); larger blades are reduced first
MAX_DENSE_DOF = 2000

# 3 x 3 x 3 Gauss points: scikit-fem's intorder 5 on hexahedra (exact for the mass on an affine element)
_INTORDER = 5


def _elements(n_elements, length, width):
    """``(n_span, n_chord, n_thickness)`` from an int (span; chord in proportion, >= 2; one layer
    through the thickness) or a triple."""
    if isinstance(n_elements, (int, np.integer)) and not isinstance(n_elements, (bool, np.bool_)):
        n = check_count("n_elements", n_elements, 1)
        return n, max(2, round(n * width / length)), 1
    try:
        counts = tuple(n_elements)
    except TypeError:
        counts = ()
    if len(counts) != 3:
        raise ParameterError(f"n_elements must be an integer >= 1 or a triple (n_span, n_chord, n_thickness), "
                             f"got {n_elements!r}")
    return tuple(check_count(f"n_elements[{i}]", c, 1) for i, c in enumerate(counts))


class SolidBlade:
    """A straight plate-like rotating blade as a 3D elastic solid (27-node hexahedra, sparse).

    Parameters
    ----------
    length : float
        Span ``L`` [m], > 0.
    width : float
        Chord ``b`` at the root [m], > 0.
    thickness : float
        ``h`` [m], > 0.
    youngs_modulus : float
        ``E`` [Pa], > 0.
    poisson_ratio : float
        ``nu`` [-], in [-0.9997, 0.499925]: closer to 0.5 (or -1) the bulk and shear moduli differ by
        more than :data:`MAX_MODULUS_RATIO` and the stiffness's rounding swamps the lowest modes.
        Above about 0.45 the fully integrated element also locks volumetrically in bending (a
        discretisation error, not rounding): the 8 x 8 x 1 square plate's first frequency
        parameter, against its value at nu = 0.3, was 2.3 %, 17 % and 78 % high at nu = 0.45, 0.49
        and 0.499 for a / h = 1000, and 1.9 %, 10 % and 19 % for a / h = 100 (measured).
    density : float
        ``rho`` [kg/m^3], > 0. ``E``, ``rho`` and ``Omega`` must keep the matrices' entries and
        ``omega^2`` within ``[2.8e-103, 5.6e102]`` (:mod:`~frictionjoint.structures.scales`; the
        refusal gives each one's range).
    twist : float
        Angle of the tip's cross-section to the root's [rad], linear over the span (positive from
        ``y`` towards ``z``), in (-pi, pi).
    taper : float
        Chord at the tip / chord at the root [-], > 0.
    n_elements : int or (int, int, int)
        Elements along the span, the chord and the thickness; an int ``n`` is ``(n, max(2,
        round(n b / L)), 1)``. One element through the thickness bends correctly (module
        docstring); the frequencies converge from above at about second order in the element
        size: the square plate (a / h = 100) with 16 x 16 x 1 is within 0.6 % of the converged
        Kirchhoff plate; keep the elements' span length within a few thicknesses. Torsion wants
        elements across the chord (the shear boundary layers at its edges): a strip of b / h = 5
        has its first torsion mode 3.7, 2.3, 1.9 and 1.3 % above Saint-Venant's with 2 x 1, 4 x 1,
        8 x 1 and 8 x 2 elements across the chord and the thickness. A mesh whose assembly and
        factor would not fit in the machine's available memory is refused before anything is
        allocated (:func:`memory_estimate`).
    rotor_speed : float
        ``Omega`` [rad/s], >= 0.
    hub_radius : float
        ``R``: radius of the root face from the rotation axis [m], >= 0.
    rayleigh : (float, float)
        Viscous damping ``C = alpha M + beta K_E`` [1/s, s] (``K_E`` the elastic stiffness), both
        >= 0.

    Attributes
    ----------
    mass, stiffness : (n_dof, n_dof) scipy.sparse.csr_array
        ``M`` [kg] and ``K_E + K_G - Omega^2 M_s`` [N/m], every node's DOFs (the root's included).
    elastic_stiffness, geometric_stiffness, softening : (n_dof, n_dof) scipy.sparse.csr_array
        ``K_E``, ``K_G`` and ``Omega^2 M_s`` [N/m] (the last two zero without rotation).
    nodes : (n_nodes, 3) ndarray
        Node coordinates [m], in the node order (node id = row + 1).
    centrifugal_load : (n_dof,) ndarray
        The consistent nodal forces of the centrifugal body force ``rho Omega^2 (R + x, y, 0)`` [N]
        (zero without rotation): the load the root carries, the root face's nodes' own share included.
    """

    def __init__(self, length: float, width: float, thickness: float, youngs_modulus: float,
                 poisson_ratio: float, density: float, *, twist: float = 0.0, taper: float = 1.0,
                 n_elements: int | tuple = 20, rotor_speed: float = 0.0, hub_radius: float = 0.0,
                 rayleigh: tuple = (0.0, 0.0)) -> None:
        self.length = check_positive("length", length)
        self.width = check_positive("width", width)
        self.thickness = check_positive("thickness", thickness)
        self.youngs_modulus = check_positive("youngs_modulus", youngs_modulus)
        self.poisson_ratio = check_poisson_ratio("poisson_ratio", poisson_ratio)
        self.density = check_positive("density", density)
        self.twist = check_real("twist", twist)
        if not abs(self.twist) < math.pi:
            raise ParameterError(f"twist must be in (-pi, pi) rad, got {twist!r}")
        self.taper = check_positive("taper", taper)
        self.n_elements = _elements(n_elements, self.length, self.width)
        self.rotor_speed = check_nonnegative("rotor_speed", rotor_speed)
        self.hub_radius = check_nonnegative("hub_radius", hub_radius)
        try:
            alpha, beta = (float(v) for v in rayleigh)
        except (TypeError, ValueError):
            raise ParameterError(f"rayleigh must be a pair (alpha, beta) of numbers >= 0, got {rayleigh!r}") from None
        self.rayleigh = (check_nonnegative("rayleigh alpha", alpha), check_nonnegative("rayleigh beta", beta))
        _check_poisson_conditioning(self.poisson_ratio)
        check_scales(self._scales(), {"youngs_modulus": self.youngs_modulus, "density": self.density,
                                      "rotor_speed": self.rotor_speed})
        estimate, what = memory_estimate(self.n_elements)
        given = "" if self.n_elements == n_elements else f" (a {' x '.join(map(str, self.n_elements))} mesh)"
        check_fits(estimate, f"n_elements = {n_elements!r}{given}", what)
        self._assemble()

    def _scales(self) -> dict:
        """The model's quantities as power laws in E, rho and Omega (log10, exponents, bounded below:
        :func:`~frictionjoint.structures.scales.check_scales`), from the smallest and largest element
        sides (the chord at its narrowest end)."""
        ns, nc, nt = self.n_elements
        sides = [self.length / ns, self.width * min(1.0, self.taper) / nc, self.thickness / nt]
        lg = math.log10
        log_v, log_dmin, log_dmax = sum(lg(d) for d in sides), lg(min(sides)), lg(max(sides))
        nu = self.poisson_ratio
        log_e, log_rho = lg(self.youngs_modulus), lg(self.density)
        # the P-wave modulus lambda + 2 mu over E; 120 sum 1/d^2: twice the 1D quadratic element's
        # highest eigenvalue 60 / d^2 per direction (the element's highest omega^2 bound)
        log_p = lg((1 - nu) / ((1 + nu) * (1 - 2 * nu)))
        depth = min(self.thickness, self.width * min(1.0, self.taper))
        scales = {
            "mass entries [kg]": (log_rho + log_v, {"density": 1}, True),
            "largest stiffness entries [N/m]": (log_e + log_p + log_v - 2 * log_dmin, {"youngs_modulus": 1}, True),
            "smallest stiffness entries [N/m]": (log_e + log_v - 2 * log_dmax, {"youngs_modulus": 1}, True),
            "highest omega^2 [rad^2/s^2]": (log_e + log_p - log_rho + lg(120) - 2 * log_dmin
                                            + lg(sum((min(sides) / d) ** 2 for d in sides)),
                                            {"youngs_modulus": 1, "density": -1}, True),
            "lowest omega^2 [rad^2/s^2]": (log_e + 2 * lg(depth) - log_rho - 4 * lg(self.length),
                                           {"youngs_modulus": 1, "density": -1}, True)}
        if self.rotor_speed > 0:
            log_om2 = 2 * lg(self.rotor_speed)
            scales["rotor_speed^2 [rad^2/s^2]"] = (log_om2, {"rotor_speed": 2}, False)
            scales["spin softening entries [N/m]"] = (log_om2 + log_rho + log_v, {"rotor_speed": 2, "density": 1}, False)
            scales["geometric stiffness entries [N/m]"] = (
                log_om2 + log_rho + lg((self.hub_radius + self.length) * self.length) + log_v - 2 * log_dmin,
                {"rotor_speed": 2, "density": 1}, False)
        return scales

    # ------------------------------------------------------------------ geometry and assembly
    def _mesh(self):
        from skfem import MeshHex

        ns, nc, nt = self.n_elements
        mesh = MeshHex.init_tensor(np.linspace(0.0, self.length, ns + 1),
                                   np.linspace(-0.5 * self.width, 0.5 * self.width, nc + 1),
                                   np.linspace(-0.5 * self.thickness, 0.5 * self.thickness, nt + 1))
        x, y, z = mesh.p
        y = y * (1.0 + (self.taper - 1.0) * x / self.length)
        angle = self.twist * x / self.length
        p = np.array([x, y * np.cos(angle) - z * np.sin(angle), y * np.sin(angle) + z * np.cos(angle)])
        return MeshHex(p, mesh.t)

    def _assemble(self):
        from skfem import Basis, BilinearForm, ElementHex2, LinearForm, asm
        from skfem.helpers import grad
        from skfem.models.elasticity import lame_parameters

        # the scalar quadratic element: a vector element's DOFs are (x, y, z) at each of its
        # nodes, and each matrix is made of the scalar blocks of components (c, e) (_vector)
        scalar = Basis(self._mesh(), ElementHex2(), intorder=_INTORDER)
        rho, om2, radius = self.density, self.rotor_speed ** 2, self.hub_radius
        lam, mu = lame_parameters(self.youngs_modulus, self.poisson_ratio)

        @BilinearForm
        def mass(u, v, w):
            return rho * u * v

        @LinearForm
        def radial_load(v, w):  # the centrifugal body force's x and y components per unit Omega^2
            return rho * (radius + w.x[0]) * v

        @LinearForm
        def chordwise_load(v, w):
            return rho * w.x[1] * v

        @BilinearForm
        def geometric(u, v, w):  # sigma0_ij (d_i u)(d_j v) of one component; sigma0 (3, 3, n_elements, n_points)
            du, dv = grad(u), grad(v)
            return sum(stress[i, j] * du[i] * dv[j] for i in range(3) for j in range(3))

        locs = scalar.doflocs
        grid = self._reference_grid(locs)
        order = np.lexsort(grid[::-1])  # nodes by x, then y, then z

        def arranged(a):  # a scalar matrix in the node order
            return sp.csr_array(sp.csr_array(a)[order][:, order])

        d = _derivative_pairs(scalar)
        m_s = arranged(asm(mass, scalar))
        m_s = sp.csr_array(0.5 * (m_s + m_s.T))
        self.mass = _vector({(c, c): m_s for c in range(3)})
        laplace = d[0, 0] + d[1, 1] + d[2, 2]
        k_e = _vector({(c, e): arranged(lam * d[c, e] + mu * d[e, c] + (mu * laplace if c == e else 0))
                       for c in range(3) for e in range(3)})
        self.elastic_stiffness = sp.csr_array(0.5 * (k_e + k_e.T))  # the sums of duplicates' rounding
        n_nodes = order.size
        inverse = np.empty_like(order)
        inverse[order] = np.arange(n_nodes)
        root, tip = np.abs(locs[0]) <= 1e-9 * self.length, np.abs(locs[0] - self.length) <= 1e-9 * self.length
        self._sets = {"root": np.sort(inverse[root]), "tip": np.sort(inverse[tip]),
                      "tip_centre": inverse[tip & (grid[1] == 0) & (grid[2] == 0)]}
        if om2 > 0.0:
            # the steady stress of the clamped, undeformed blade under its centrifugal load
            load = np.zeros((n_nodes, 3))
            load[:, 0], load[:, 1] = om2 * asm(radial_load, scalar)[order], om2 * asm(chordwise_load, scalar)[order]
            free = np.setdiff1d(np.arange(3 * n_nodes), self.dofs_of("root"))
            u = np.zeros(3 * n_nodes)
            u[free] = _factor(sp.csc_array(self.elastic_stiffness[free][:, free]))(load.ravel()[free])
            nodal = np.empty((n_nodes, 3))
            nodal[order] = u.reshape(-1, 3)  # back to scikit-fem's numbering
            du = np.array([scalar.interpolate(nodal[:, c]).grad for c in range(3)])  # du[c, i] = d_i u_c
            strain = 0.5 * (du + np.swapaxes(du, 0, 1))
            stress = 2.0 * mu * strain + lam * np.einsum("ii...", strain) * np.eye(3)[:, :, None, None]
            g = arranged(asm(geometric, scalar))
            g = sp.csr_array(0.5 * (g + g.T))
            self.geometric_stiffness = _vector({(c, c): g for c in range(3)})
            self.softening = _vector({(c, c): om2 * m_s for c in range(2)})
            self.centrifugal_load = load.ravel()
        else:
            self.geometric_stiffness = self.softening = sp.csr_array((3 * n_nodes, 3 * n_nodes))
            self.centrifugal_load = np.zeros(3 * n_nodes)
        self.centrifugal_load.setflags(write=False)
        self.stiffness = sp.csr_array(self.elastic_stiffness + self.geometric_stiffness - self.softening)
        self.nodes = locs[:, order].T.copy()
        self.nodes.setflags(write=False)

    def _reference_grid(self, locs):
        """Integer coordinates of the nodes ``locs`` (3, n_nodes) on the reference grid (before taper
        and twist), two units apart: the node order is the same for every twist and taper."""
        x = locs[0]
        angle = self.twist * x / self.length
        y = locs[1] * np.cos(angle) + locs[2] * np.sin(angle)
        z = -locs[1] * np.sin(angle) + locs[2] * np.cos(angle)
        y = y / (1.0 + (self.taper - 1.0) * x / self.length)
        scale = 4 * max(self.n_elements)
        return np.round(np.array([x / self.length, y / self.width, z / self.thickness]) * scale).astype(np.int64)

    # ------------------------------------------------------------------ the model
    @property
    def n_dof(self) -> int:
        """Number of DOFs, three per node (the root face's included)."""
        return self.mass.shape[0]

    @property
    def indefinite_stiffness(self) -> bool:
        """Whether the stiffness may have negative directions: under rotation, the spin softening
        of the free root (the joints hold it), as BeamBlade's structure."""
        return self.rotor_speed > 0

    @property
    def damping(self) -> sp.csr_array:
        """``C = alpha M + beta K_E`` [N s/m], sparse."""
        alpha, beta = self.rayleigh
        return sp.csr_array(alpha * self.mass + beta * self.elastic_stiffness)

    @property
    def dofs(self) -> np.ndarray:
        """``(n_dof, 2)`` DOF table: node id (1 ... n_nodes) and direction (1, 2, 3: x, y, z)."""
        n_nodes = self.n_dof // 3
        return np.column_stack([np.repeat(np.arange(1, n_nodes + 1), 3), np.tile([1, 2, 3], n_nodes)])

    @property
    def node_sets(self) -> dict:
        """Node ids of ``"root"``: the root face (``s = 0``, clamped for the natural frequencies);
        ``"tip"``: the tip face (``s = L``); ``"tip_centre"``: the node at the centre of the tip face
        (an excitation or response point)."""
        return {name: tuple(int(i) + 1 for i in nodes) for name, nodes in self._sets.items()}

    @functools.cached_property
    def fe_model(self) -> FEModel:
        """The blade as an :class:`~frictionjoint.structures.FEModel` (sparse mass, stiffness and
        damping, the DOF table, the node sets), checked as an imported model is (the mass's
        positive definiteness: about 3 s at 50,000 DOFs). Its DOF names are ``n<node>_u<d>``."""
        damping = self.damping if any(self.rayleigh) else None
        return FEModel(self.mass, self.stiffness, damping, dofs=self.dofs, node_sets=self.node_sets,
                       source=repr(self), indefinite_stiffness=self.indefinite_stiffness)

    @property
    def dof_names(self) -> tuple:
        """``n<node>_u<d>``: the names of :attr:`fe_model` (:func:`~frictionjoint.structures.dof_name`)."""
        from .fe_import import dof_name

        return tuple(dof_name(node, d) for node, d in self.dofs)

    def dofs_of(self, set_name: str) -> np.ndarray:
        """The matrix rows of a node set's DOFs (:attr:`node_sets`), node by node, x, y, z.

        Parameters
        ----------
        set_name : str
            ``"root"``, ``"tip"`` or ``"tip_centre"``.

        Returns
        -------
        (k,) ndarray of int
        """
        nodes = self._sets.get(set_name)
        if nodes is None:
            raise ParameterError(f"set_name must be one of {sorted(self._sets)}, got {set_name!r}")
        return (3 * nodes[:, None] + np.arange(3)).ravel()

    @functools.cached_property
    def structure(self) -> LinearStructure:
        """The blade as a dense :class:`~frictionjoint.structure.LinearStructure` with every DOF
        (the root face's included, for the root joints), for blades of at most
        :data:`MAX_DENSE_DOF` DOFs; stiffness ``K_E + K_G - Omega^2 M_s`` (indefinite under
        rotation until the joints hold the root). A larger blade is kept sparse: the blade itself
        is what :func:`~frictionjoint.structures.craig_bampton` reduces (sparse ``mass``,
        ``stiffness``, ``damping``, ``dof_names``), e.g. to its root face, ``craig_bampton(blade,
        blade.dofs_of("root"), n_modes=10)``."""
        if self.n_dof > MAX_DENSE_DOF:
            raise ParameterError(f"the blade has {self.n_dof} DOFs, more than {MAX_DENSE_DOF} for a dense "
                                 f"LinearStructure: reduce it first, e.g. craig_bampton(blade, "
                                 f"blade.dofs_of('root'), n_modes)")
        return LinearStructure(self.mass.toarray(), self.stiffness.toarray(), self.damping.toarray(),
                               dof_names=self.dof_names, indefinite_stiffness=self.indefinite_stiffness)

    # ------------------------------------------------------------------ modes
    def _clamped(self):
        free = np.setdiff1d(np.arange(self.n_dof), self.dofs_of("root"))
        return free, sp.csc_array(self.stiffness[free][:, free]), sp.csc_array(self.mass[free][:, free])

    def modes(self, n: int) -> tuple[np.ndarray, np.ndarray]:
        """The first ``n`` natural angular frequencies [rad/s] and mode shapes with the root face
        clamped: sparse shift-invert Lanczos (``scipy.sparse.linalg.eigsh``) about 0, one sparse
        factorisation of the clamped stiffness.

        Parameters
        ----------
        n : int
            How many, in ``[1, n_dof - root DOFs - 1]``.

        Returns
        -------
        omega : (n,) ndarray
            Ascending [rad/s].
        shapes : (n_dof, n) ndarray
            Mass-normalised mode shapes, zero at the root face.
        """
        free, k, m = self._clamped()
        n = check_count("n", n, 1)
        if n >= free.size:
            raise ParameterError(f"n must be in [1, {free.size - 1}], got {n}")
        solve = _factor(k)
        op = spla.LinearOperator(k.shape, matvec=solve, dtype=float)
        lam, vec = spla.eigsh(k, n, m, sigma=0.0, which="LM", OPinv=op)
        idx = np.argsort(lam)
        lam, vec = lam[idx], vec[:, idx]
        if lam[0] < 0:
            raise ParameterError(f"the clamped blade is unstable at rotor_speed = {self.rotor_speed!r} rad/s "
                                 f"(omega^2 = {lam[0]:.3g})")
        shapes = np.zeros((self.n_dof, n))
        shapes[free] = vec / np.sqrt(np.einsum("ij,ij->j", vec, m @ vec))
        return np.sqrt(lam), shapes

    def natural_frequencies(self, n: int = 6) -> np.ndarray:
        """The first ``n`` natural angular frequencies [rad/s] with the root face clamped, ascending
        (every kind: flapwise, chordwise, torsion, axial; :meth:`modes` gives the shapes).

        Parameters
        ----------
        n : int
            How many, >= 1.

        Returns
        -------
        (n,) ndarray
        """
        return self.modes(n)[0]

    def __repr__(self) -> str:
        return (f"SolidBlade(length={self.length!r}, width={self.width!r}, thickness={self.thickness!r}, "
                f"twist={self.twist!r}, taper={self.taper!r}, n_elements={self.n_elements}, "
                f"rotor_speed={self.rotor_speed!r}, hub_radius={self.hub_radius!r})")


#: largest ratio of the elastic moduli's extremes, max(3K / 2G, 2G / 3K) = max((1 + nu) / (1 - 2 nu),
#: (1 - 2 nu) / (1 + nu)), that SolidBlade accepts: the stiffness's rounding errors are eps times that
#: ratio times the mesh's own conditioning. Measured on the 10 x 2 x 1 Ti-6Al-4V blade: the first
#: frequency's rounding noise (its scatter from one nu to the next, against the smooth trend) was
#: 1.8e-3 at a ratio of 7.5e6 (nu = 0.4999999), 8 % at 7.5e8 and an unstable (negative) omega^2 at
#: 7.5e9 (nu = 0.4999999999); it grows in proportion, so 1e4 keeps it near 2e-6 on that mesh, 1e-5
#: on a mesh ten times worse conditioned. The range is nu in [-0.9997, 0.499925]
MAX_MODULUS_RATIO = 1e4


def _check_poisson_conditioning(nu: float) -> None:
    """Refuse a Poisson ratio so close to 0.5 (or -1) that the stiffness is ill-conditioned
    (:data:`MAX_MODULUS_RATIO`)."""
    bulk_over_shear = (1 + nu) / (1 - 2 * nu)  # 3K / 2G
    ratio = max(bulk_over_shear, 1 / bulk_over_shear)
    if ratio > MAX_MODULUS_RATIO:
        x = MAX_MODULUS_RATIO
        low, high = (1 - x) / (2 + x), (x - 1) / (1 + 2 * x)
        kind = ("nearly incompressible: its bulk modulus" if bulk_over_shear > 1 else
                "nearly rigid in shear: its shear modulus")
        raise ParameterError(
            f"poisson_ratio must be in [{low:.6g}, {high:.6g}] for the stiffness to be well-conditioned, got {nu!r}: "
            f"the solid is {kind} is {ratio:.3g} times the other (3K/2G = (1+nu)/(1-2nu)), and the "
            f"stiffness's rounding errors, eps times that ratio times the mesh's own conditioning, swamp "
            f"its lowest modes (allowed ratio {MAX_MODULUS_RATIO:.0e})")


#: bytes per stored entry of the blade's stiffness while it is assembled: measured 76-96 (the
#: larger rotating) on meshes of 40 x 2 x 1 to 160 x 8 x 1 (the peak resident memory over the
#: stiffness's entries: the mass, elastic, geometric, softening and total matrices and the
#: assembly's temporaries)
ASSEMBLY_BYTES_PER_ENTRY = 100
#: bytes per entry of the clamped stiffness's sparse LU factor (L and U, values and indices:
#: measured about 16)
FACTOR_BYTES_PER_ENTRY = 16


def memory_estimate(n_elements: tuple) -> tuple[float, str]:
    """Peak memory [bytes] to assemble a :class:`SolidBlade` of ``n_elements`` = ``(n_span, n_chord,
    n_thickness)`` and factor its clamped stiffness (its modes, its centrifugal stress and its
    reduction all need the factor), and how it was counted, from the mesh alone.

    A structured grid of 27-node hexahedra has ``prod(2 n_i + 1)`` nodes, three DOFs each; two
    nodes are coupled where they share an element, in each direction independently, so the
    scalar pattern has ``prod(8 n_i + 1)`` entries (1D: 9 per element, less one per shared
    vertex) and the stiffness 9 times that (:data:`ASSEMBLY_BYTES_PER_ENTRY` each). The factor
    is bounded by a band ordered along the longest direction: per DOF, both triangles of a band
    of the DOFs of two node layers across the two shorter directions, ``2 x 3 x 2 (2 a + 1) (2 b
    + 1)`` (SuperLU's minimum-degree ordering filled 1.3 to 4.6 times less, measured on slender
    blades, plates and blocks), :data:`FACTOR_BYTES_PER_ENTRY` each.

    Parameters
    ----------
    n_elements : (int, int, int)

    Returns
    -------
    bytes : float
    what : str
        The counts behind it, for a message.
    """
    counts = [int(n) for n in n_elements]
    nodes = math.prod(2 * n + 1 for n in counts)
    entries = 9 * math.prod(8 * n + 1 for n in counts)
    a, b = sorted(2 * n + 1 for n in counts)[:2]
    factor = 3 * nodes * 2 * 3 * 2 * a * b
    estimate = float(ASSEMBLY_BYTES_PER_ENTRY * entries + FACTOR_BYTES_PER_ENTRY * factor)
    what = (f"{nodes:.3g} nodes, {3 * nodes:.3g} DOFs, {entries:.3g} stiffness entries at "
            f"{ASSEMBLY_BYTES_PER_ENTRY} B while assembled, a factor of at most {factor:.3g} entries")
    return estimate, what


def _derivative_pairs(scalar) -> dict:
    """``D_pq[a, b] = int d_p phi_a d_q phi_b`` of the scalar basis, p, q = 0, 1, 2 (six assembled,
    ``D_qp = D_pq^T``). With ``u = phi_b e_e`` and ``v = phi_a e_c``, the isotropic elastic form
    ``lambda div u div v + mu (d_i u_k + d_k u_i) d_i v_k`` is ``lambda D_ce + mu D_ec + mu
    delta_ce sum_i D_ii``: nine times fewer element pairs than the vector form."""
    from skfem import BilinearForm, asm

    def pair(p, q):
        return BilinearForm(lambda u, v, w: v.grad[p] * u.grad[q])

    d = {}
    for p in range(3):
        for q in range(p, 3):
            d[p, q] = sp.csr_array(asm(pair(p, q), scalar))
            d[q, p] = d[p, q].T.tocsr()
    return d


def _vector(blocks: dict) -> sp.csr_array:
    """The vector matrix whose DOF ``3 a + c`` is node ``a``'s component ``c``, from the scalar
    blocks ``(c, e) -> (n, n)`` (the blocks not given are zero)."""
    rows, cols, vals = [], [], []
    for (c, e), block in blocks.items():
        coo = sp.coo_array(block)
        rows.append(3 * coo.row + c)
        cols.append(3 * coo.col + e)
        vals.append(coo.data)
    n = 3 * next(iter(blocks.values())).shape[0]
    out = sp.csr_array((np.concatenate(vals), (np.concatenate(rows), np.concatenate(cols))), shape=(n, n))
    out.sort_indices()
    return out


def _factor(a: sp.csc_array):
    """A solver ``b -> a^-1 b`` for a symmetric positive definite sparse ``a``: SuperLU in symmetric
    mode (diagonal pivots, minimum degree on ``a + a^T``), which a stiffness allows."""
    try:
        lu = spla.splu(a, permc_spec="MMD_AT_PLUS_A", diag_pivot_thresh=0.0, options={"SymmetricMode": True})
    except RuntimeError as exc:
        raise ParameterError(f"the clamped blade's stiffness is singular: {exc}") from None
    return lu.solve

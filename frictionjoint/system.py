"""A linear structure with joint elements and excitation: the model the solvers march."""
from __future__ import annotations

import copy
from typing import Sequence

import numpy as np
from numpy.typing import ArrayLike

from .errors import ParameterError, check_positive
from .excitation import ExternalForce, HarmonicBaseMotion, HarmonicForce
from .structure import LinearStructure

__all__ = ["FrictionSystem"]


class FrictionSystem:
    """Linear structure + joint elements + excitation at one angular frequency.

    Parameters
    ----------
    structure : LinearStructure
        The linear part.
    elements : sequence
        Joint elements (:class:`~frictionjoint.elements.CoulombSlider`,
        :class:`~frictionjoint.elements.Jenkins`, :class:`~frictionjoint.elements.Iwan`), each
        attached by its ``dof`` or ``direction``.
    omega : float, optional
        Angular frequency [rad/s] of all harmonic sources, > 0; required if there are any.
    excitation : sequence, optional
        :class:`HarmonicForce`, :class:`HarmonicBaseMotion` and :class:`ExternalForce` objects.
    """

    def __init__(self, structure: LinearStructure, elements: Sequence = (), omega: float | None = None,
                 excitation: Sequence = ()):
        if not isinstance(structure, LinearStructure):
            raise ParameterError(f"structure must be a LinearStructure, got {type(structure).__name__}")
        self.structure = structure
        self.elements = tuple(elements)
        self.excitation = tuple(excitation)
        harmonic = self._check_excitation(omega)
        k, c = self._harmonic_sources(harmonic)
        contacts = self._expand_elements(k, c)
        self._contact_arrays(contacts)

    def _check_excitation(self, omega) -> list:
        """Check the excitation items and ``omega``; set :attr:`omega` (0 without harmonic sources)
        and return the harmonic sources."""
        harmonic = [e for e in self.excitation if isinstance(e, (HarmonicForce, HarmonicBaseMotion))]
        for e in self.excitation:
            if not isinstance(e, (HarmonicForce, HarmonicBaseMotion, ExternalForce)):
                raise ParameterError(f"excitation items must be HarmonicForce, HarmonicBaseMotion or "
                                     f"ExternalForce, got {type(e).__name__}")
        if omega is None:
            if harmonic:
                raise ParameterError("omega is required when there is harmonic excitation")
            self.omega = 0.0
        else:
            self.omega = check_positive("omega", omega)
        return harmonic

    def _harmonic_sources(self, harmonic: list) -> tuple[np.ndarray, np.ndarray]:
        """The harmonic forces and base motions as one equivalent force (:attr:`force_cos`,
        :attr:`force_sin`), the held forces by DOF (:attr:`external`) and :attr:`mass`; return the
        structure's stiffness and damping with the base motions' springs and dashpots added."""
        structure = self.structure
        n = structure.n_dof
        k = np.array(structure.stiffness)
        c = np.array(structure.damping)
        fc = np.zeros(n)
        fs = np.zeros(n)
        w = self.omega
        for e in harmonic:
            i = structure.dof_index(e.dof)
            if isinstance(e, HarmonicForce):
                fc[i] += e.amplitude * np.cos(e.phase)
                fs[i] += e.amplitude * np.sin(e.phase)
            else:
                k[i, i] += e.stiffness
                c[i, i] += e.damping
                y = e.amplitude
                # k y + c y',  y = Y cos(wt - phase)
                fc[i] += e.stiffness * y * np.cos(e.phase) + e.damping * y * w * np.sin(e.phase)
                fs[i] += e.stiffness * y * np.sin(e.phase) - e.damping * y * w * np.cos(e.phase)
        self.mass = np.array(structure.mass)
        self.force_cos = fc
        self.force_sin = fs
        self.external = [(structure.dof_index(e.dof), e) for e in self.excitation
                         if isinstance(e, ExternalForce)]
        return k, c

    def _expand_elements(self, k: np.ndarray, c: np.ndarray) -> list:
        """Expand the joint elements into sliders (one row of each slider array per slider) and add
        their linear springs, dashpots and constant force to ``k``, ``c`` (:attr:`stiffness`,
        :attr:`damping`, :attr:`constant_force`); return the contacts with a varying normal load."""
        structure = self.structure
        n = structure.n_dof
        d_rows, fsl, ksl, owner, pre, on_contact, contacts = [], [], [], [], [], [], []
        self.constant_force = np.zeros(n)
        for ie, el in enumerate(self.elements):
            if hasattr(el, "attach"):
                # elements acting along several directions (DovetailRoot): sliders with their
                # own directions and preloads, plus linear springs and a constant force
                att = el.attach(structure)
                k = k + att.stiffness
                if att.damping is not None:
                    c = c + att.damping
                self.constant_force += att.force
                sc = att.slider_contact if att.slider_contact is not None else [-1] * len(att.sliders)
                for d, s, p, ic in zip(att.directions, att.sliders, att.preload, sc):
                    d_rows.append(d)
                    fsl.append(s.slip_force)
                    ksl.append(s.stiffness)
                    pre.append(p)
                    owner.append(ie)
                    if ic >= 0 and s.rigid:
                        raise ParameterError(f"elements[{ie}]: a slider on a contact with a varying normal "
                                             "load must have a finite stiffness (Jenkins)")
                    on_contact.append(ic + len(contacts) if ic >= 0 else -1)
                contacts += list(att.contacts)
                continue
            if not hasattr(el, "sliders"):
                raise ParameterError(f"elements[{ie}] is not a joint element: {el!r}")
            d = structure.direction(getattr(el, "dof", None), getattr(el, "direction", None))
            for s in el.sliders():
                d_rows.append(d)
                fsl.append(s.slip_force)
                ksl.append(s.stiffness)
                pre.append(0.0)
                owner.append(ie)
                on_contact.append(-1)
        self.stiffness = k  # structure + base springs + the elements' linear springs
        self.damping = c  # structure + base dashpots + the elements' dashpots
        self.slider_direction = np.array(d_rows, dtype=float).reshape(len(d_rows), n)
        self.slip_force = np.array(fsl, dtype=float)
        self.slider_stiffness = np.array(ksl, dtype=float)
        self.rigid = np.isinf(self.slider_stiffness)
        self.slider_owner = np.array(owner, dtype=int)
        #: Jenkins spring forces [N] in the initial state ``x = 0`` (static preload, e.g. of a
        #: dovetail flank after spin-up); the default initial slider positions carry them
        self.slider_preload = np.array(pre, dtype=float)
        #: normal-load variation: the contacts (normal over the DOFs, kn, dashpot, preload N0) and
        #: each slider's contact (-1: constant slip limit). A slider on contact c slips at
        #: ``slip_force + slip_gradient . x = mu (N0 - kn normal . x)`` while c is closed, and
        #: slips freely (status 2, no force) while c is open (lift-off, ``N0 - kn normal . x <= 0``)
        self.slider_contact = np.array(on_contact, dtype=np.intp)
        return contacts

    def _contact_arrays(self, contacts: list) -> None:
        """Normal-load variation: the contacts' arrays and each slider's slip-limit gradient."""
        n = self.structure.n_dof
        self.varying = self.slider_contact >= 0
        self.n_contacts = len(contacts)
        self.contact_normal = np.array([c.normal for c in contacts], dtype=float).reshape(len(contacts), n)
        self.contact_stiffness = np.array([c.stiffness for c in contacts], dtype=float)
        self.contact_damping = np.array([c.damping for c in contacts], dtype=float)
        self.contact_preload = np.array([c.preload for c in contacts], dtype=float)
        if self.n_contacts and np.any(np.bincount(self.slider_contact[self.varying], minlength=self.n_contacts) != 1):
            raise ParameterError("each contact with a varying normal load carries exactly one slider")
        self.slip_gradient = np.zeros((self.n_sliders, n))
        for i in np.flatnonzero(self.varying):
            c = contacts[self.slider_contact[i]]
            self.slip_gradient[i] = -c.friction_coefficient * c.stiffness * np.asarray(c.normal, float)
            if not np.isclose(self.slip_force[i], c.friction_coefficient * c.preload, rtol=1e-12, atol=0.0):
                raise ParameterError("a slider on a contact must slip at friction_coefficient * preload "
                                     f"= {c.friction_coefficient * c.preload:g} N at x = 0, got {self.slip_force[i]:g} N")

    def normal_loads(self, x: ArrayLike) -> np.ndarray:
        """Normal loads ``kn max(N0/kn - normal . x, 0)`` [N] of the contacts (normal-load
        variation; :class:`~frictionjoint.elements.base.Contact`).

        Parameters
        ----------
        x : (n_dof, ...) array_like
            Displacement(s) [m] from the static state.

        Returns
        -------
        (n_contacts, ...) ndarray
            Normal load of each contact [N], zero where it is open.
        """
        x = np.asarray(x, dtype=float)
        n = self.contact_preload.reshape((-1,) + (1,) * (x.ndim - 1)) - self.contact_stiffness.reshape(
            (-1,) + (1,) * (x.ndim - 1)) * np.tensordot(self.contact_normal, x, axes=(1, 0))
        return np.maximum(n, 0.0)

    def config_key(self, status: np.ndarray) -> bytes:
        """Key of the configuration of a stick/slip status: which sliders stick and, for sliders
        on contacts (their slip direction enters the stiffness), the status itself.

        Parameters
        ----------
        status : (n_sliders,) int8 ndarray
            0 stuck, +1/-1 slipping, 2 on an open contact.

        Returns
        -------
        bytes
        """
        if not self.n_contacts:
            return (status == 0).tobytes()
        key = (status != 0).astype(np.int8)
        key[self.varying] = status[self.varying] + 3
        return key.tobytes()
    def rigid_limit(self, ratio: float = 1e11) -> tuple["FrictionSystem", np.ndarray]:
        """This system with its Jenkins sliders far stiffer than the structure made rigid.

        A stuck Jenkins spring ``kt`` on ``s = d . x`` (``|d| = 1``) beside a structure whose
        stiffness along it is ``k_d = max(d^T K d, omega^2 d^T M d)`` holds ``s`` to within
        ``F/kt``: while it sticks it is a rigid constraint plus a stuck mode of rate
        ``sqrt(kt/m)``, which every stop sets ringing with a force of the order of the stop's
        inertial force, whatever ``kt`` (a stop leaves the state ``m a/kt`` off the stuck
        equilibrium), and which the structure's damping does not reach. Each of its periods
        brings the spring to its limit again while the load nears the slip force: a stick/slip
        chatter at the stuck mode's rate, ``sqrt(kt)`` events a period (416 at ``kt/k = 1e6``, 4e5
        at 1e12) that the rigid slider does not have. It moves the motion by ``O(k_d/kt)``: a
        unit oscillator with a Jenkins joint (F/P0 = 0.8, r = 1.2, zeta = 0.01) is within 7e-7,
        3e-7, 4e-7, 1.6e-8, 5e-8 of the rigid (Coulomb) one at ``kt/k = 1e7, 3e7, 1e8, 3e8, 1e9``:
        at most ``50 k/kt``. Where ``kt >= ratio k_d`` (default 1e11: ``5e-10`` by that
        measurement) the slider is marched as rigid. Sliders with a static preload or on a
        contact with a varying normal load keep their springs, and so does a slider whose direction
        depends on those of the rigid sliders (the stiffest taken first): the marcher's rigid
        constraints must be independent.

        Parameters
        ----------
        ratio : float
            Least ``kt/k_d`` of a slider made rigid, > 0.

        Returns
        -------
        (FrictionSystem, ndarray)
            The system (``self`` where no slider changes, else a copy sharing everything but the
            sliders' stiffness) and the indices of the sliders made rigid.
        """
        ratio = check_positive("ratio", ratio)
        k_ratio = self.stiffness_ratio()
        stiff = ((k_ratio >= ratio) & np.isfinite(self.slider_stiffness)
                 & (self.slider_preload == 0) & (self.slider_contact < 0))
        # the marcher's rigid sliders must constrain independent directions (two stuck rigid sliders
        # on one DOF are one constraint twice): the stiffest first, a parallel one keeps its spring
        rows = list(self.slider_direction[self.rigid])
        index = []
        for i in sorted(np.flatnonzero(stiff), key=lambda j: -k_ratio[j]):
            trial = np.array(rows + [self.slider_direction[i]])
            if np.linalg.matrix_rank(trial) == len(trial):
                rows.append(self.slider_direction[i])
                index.append(i)
        index = np.array(sorted(index), dtype=int)
        if not index.size:
            return self, index
        out = copy.copy(self)
        out.slider_stiffness = self.slider_stiffness.copy()
        out.slider_stiffness[index] = np.inf
        out.rigid = np.isinf(out.slider_stiffness)
        return out, index

    def stiffness_ratio(self) -> np.ndarray:
        """Each slider's stiffness over the structure's along it, ``kt |d|^4 / max(d^T K d,
        omega^2 d^T M d)`` (inf for a rigid slider or where the structure has neither along it).

        Returns
        -------
        (n_sliders,) ndarray
        """
        d = self.slider_direction
        dd = np.einsum("ij,ij->i", d, d)
        k_d = np.maximum(np.einsum("ij,jk,ik->i", d, self.stiffness, d),
                         self.omega ** 2 * np.einsum("ij,jk,ik->i", d, self.mass, d))
        with np.errstate(divide="ignore", over="ignore", invalid="ignore"):
            out = self.slider_stiffness * dd * dd / k_d
        return np.where(k_d > 0, out, np.inf)

    @property
    def n_dof(self) -> int:
        """Number of structural DOFs."""
        return self.structure.n_dof

    @property
    def n_sliders(self) -> int:
        """Number of sliders after expanding the elements."""
        return self.slip_force.size

    def external_force(self, t: float) -> np.ndarray:
        """Held external force vector (n_dof,) [N] at time ``t``, with the elements' constant force.

        Parameters
        ----------
        t : float
            Time [s].

        Returns
        -------
        (n_dof,) ndarray
            Sum of the held :class:`ExternalForce` values at ``t`` and the elements' constant force
            (e.g. a dovetail root's centrifugal load) [N].
        """
        f = self.constant_force.copy()
        for i, e in self.external:
            f[i] += e.value(t)
        return f

    def external_breaks(self) -> np.ndarray:
        """Sorted switching times [s] of the held external forces."""
        if not self.external:
            return np.empty(0)
        return np.unique(np.concatenate([e.times for _, e in self.external]))

    def harmonic_force(self, t: ArrayLike) -> np.ndarray:
        """Equivalent harmonic force (n_dof, ...) [N] at time(s) ``t``.

        Parameters
        ----------
        t : float or array_like
            Time or times [s].

        Returns
        -------
        (n_dof, ...) ndarray
            ``force_cos cos(omega t) + force_sin sin(omega t)`` [N] of the harmonic forces and base
            motions; the trailing axes are those of ``t``.
        """
        t = np.asarray(t, dtype=float)
        return (np.multiply.outer(self.force_cos, np.cos(self.omega * t))
                + np.multiply.outer(self.force_sin, np.sin(self.omega * t)))

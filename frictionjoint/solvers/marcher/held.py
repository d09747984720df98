"""Exact motion of a linear structure under harmonic force and port loads held over a step.

The structure ``M x'' + C x' + K x = p cos(omega t) + sum_j e_j f_j(t)`` is coupled at port DOFs
``j`` to joints (or any other subsystem) whose force is known at a communication point and held
over the step in the linearly implicit form

    f_j(t) = -(F_j + k_j (x_j(t) - r_j)),

``F_j`` the joint's restoring force evaluated at its displacement ``r_j`` and ``k_j`` its tangent
stiffness there (``k_j = 0``: the force is simply held, explicit coupling). The step is then a
linear time-invariant system with stiffness ``K + sum k_j e_j e_j^T`` and constant plus harmonic
forcing; with the state augmented by ``[cos(omega t), sin(omega t), 1]`` it is advanced exactly by
one matrix exponential (:func:`scipy.linalg.expm`), cached per step length and stiffness set.

While a joint sticks, ``F_j + k_j (u - r_j)`` *is* its force at ``u`` (a stuck Jenkins is a
linear spring): the coupling is then exact whatever the step and whatever the lag between
``r_j`` and the structure's own displacement (Jacobi and Gauss-Seidel masters alike). The only
coupling error comes from stick/slip changes inside a step (first order in the step).
"""
from __future__ import annotations

import math
from typing import Sequence

import numpy as np
import scipy.linalg

from ...errors import ParameterError, check_nonnegative, check_positive, check_real
from ...structure import LinearStructure

__all__ = ["HeldPortStructure"]


class HeldPortStructure:
    """A linear structure advanced exactly between communication points (see the module docstring).

    Parameters
    ----------
    structure : LinearStructure
        M, C, K with named DOFs.
    ports : sequence of str or int
        DOFs where joints act (each with force, stiffness and reference displacement held over a
        step).
    force_amplitude : (n_dof,) array_like, optional
        Amplitude ``p`` of the harmonic force ``p cos(omega t)`` [N]; zero if omitted.
    omega : float
        Excitation angular frequency [rad/s], > 0.
    x0, v0 : (n_dof,) array_like, optional
        State at ``t0`` [m], [m/s]; rest if omitted.
    t0 : float
        Start time [s].
    """

    def __init__(self, structure: LinearStructure, ports: Sequence = (), force_amplitude=None,
                 omega: float = 1.0, x0=None, v0=None, t0: float = 0.0):
        from ...errors import check_system, check_vector

        self.structure = check_system("structure", structure, LinearStructure)
        n = structure.n_dof
        self.ports = np.array([structure.dof_index(p) for p in ports], dtype=int)
        if len(set(self.ports.tolist())) != len(self.ports):
            raise ParameterError(f"ports must be distinct DOFs, got {list(ports)!r}")
        self.force_amplitude = (np.zeros(n) if force_amplitude is None
                                else check_vector("force_amplitude", force_amplitude, n))
        self.omega = check_positive("omega", omega)
        self.x = np.zeros(n) if x0 is None else check_vector("x0", x0, n)
        self.v = np.zeros(n) if v0 is None else check_vector("v0", v0, n)
        self.t = check_real("t0", t0)
        self._minv = np.linalg.inv(structure.mass)
        self._cache: dict = {}

    @property
    def n_ports(self) -> int:
        """Number of ports."""
        return len(self.ports)

    def _propagator(self, h: float, stiffness: tuple) -> np.ndarray:
        """``expm(A h)`` (rows of ``[x, v]``) of the augmented system ``[x, v, cos, sin, c]``, ``c``
        the constant force divided by the mass (``v' += c``); cached per step and stiffness set."""
        key = (h, stiffness)
        e = self._cache.get(key)
        if e is None:
            s = self.structure
            n = s.n_dof
            k = s.stiffness.copy()
            k[self.ports, self.ports] += np.asarray(stiffness, dtype=float)
            a = np.zeros((3 * n + 2, 3 * n + 2))
            a[:n, n:2 * n] = np.eye(n)
            a[n:2 * n, :n] = -self._minv @ k
            a[n:2 * n, n:2 * n] = -self._minv @ s.damping
            a[n:2 * n, 2 * n] = self._minv @ self.force_amplitude
            a[2 * n, 2 * n + 1] = -self.omega
            a[2 * n + 1, 2 * n] = self.omega
            a[n:2 * n, 2 * n + 2:] = np.eye(n)
            if len(self._cache) >= 64:  # stick/slip sets of many joints: keep the cache small
                self._cache.clear()
            e = self._cache[key] = scipy.linalg.expm(a * h)[:2 * n]
        return e

    def advance(self, step: float, force=(), stiffness=(), reference=()) -> None:
        """Advance by ``step`` with the port loads held (see the module docstring).

        Parameters
        ----------
        step : float
            Step length [s], > 0 (the propagator is cached per step length).
        force : (n_ports,) array_like
            Restoring force ``F_j`` of the joint at each port [N] (the structure feels ``-F_j``).
        stiffness : (n_ports,) array_like
            Tangent stiffness ``k_j`` of the joint at each port [N/m], >= 0 (0: force held).
        reference : (n_ports,) array_like
            Displacement ``r_j`` at which ``F_j`` and ``k_j`` were evaluated [m].
        """
        from ...errors import check_vector

        h = check_positive("step", step)
        p = self.n_ports
        force = check_vector("force", force, p) if p else np.zeros(0)
        stiffness = check_vector("stiffness", stiffness, p) if p else np.zeros(0)
        reference = check_vector("reference", reference, p) if p else np.zeros(0)
        for j, kj in enumerate(stiffness):
            check_nonnegative(f"stiffness[{j}]", kj)
        n = self.structure.n_dof
        e = self._propagator(h, tuple(stiffness.tolist()))
        b = np.zeros(n)
        np.add.at(b, self.ports, -force + stiffness * reference)
        wt = self.omega * self.t
        y = e @ np.concatenate([self.x, self.v, [math.cos(wt), math.sin(wt)], self._minv @ b])
        self.x, self.v = y[:n], y[n:]
        self.t += h


#!/usr/bin/env python
"""SolidBlade (frictionjoint.structures.SolidBlade): cost of a 50,000-DOF blade on this machine and
the converged references of tests/test_solid_blade.py.

1. Square cantilever plate (CFFF, nu = 0.3), lambda = omega a^2 sqrt(rho h / D): the Kirchhoff
   plate by Argyris triangles (C1 quintics, scikit-fem's ElementTriArgyris: a method that shares
   nothing with the solid blade's hexahedra), n x n squares split in two, for the converged
   values; Leissa (NASA SP-160, 1969) tabulates 3.492, 8.525, 21.43, 27.33, 31.11.
2. The solid blade's mesh convergence on that plate (a / h = 100, one element through the
   thickness).
3. A blade of about 50,000 DOFs (160 x 8 x 1 elements, twisted and tapered, rotating): assembly
   (elastic, mass, centrifugal static solution, geometric stiffness, softening), the first 10
   frequencies with the root clamped, and its Craig-Bampton reduction to the root face, timed.

pretwisted_beam() is the independent reference of the twisted, tapered blade in the tests.

Measured on this machine (2 cores shared with other work, load 3-5; the spread is the load's):
49,113 DOFs, nnz(K) 6.7e6; assembly 2.6-3.6 s at rest and 2.8-5.3 s at 1,000 rad/s (the
centrifugal static solution and the geometric stiffness included); first 10 frequencies 1.4-6 s;
Craig-Bampton to the 153 DOFs of the root face and 10 modes 13-45 s; peak memory 0.9-1.2 GB.

Usage: python benchmarks/solid_blade.py [--quick]   (one to two minutes; --quick skips 3)
"""
import sys
import time

import numpy as np

from frictionjoint.structures import SolidBlade, craig_bampton

LEISSA = (3.492, 8.525, 21.43, 27.33, 31.11)


def kirchhoff_square_cantilever(n: int, nu: float = 0.3, modes: int = 5) -> np.ndarray:
    """lambda of the clamped-free-free-free square Kirchhoff plate by Argyris triangles."""
    import scipy.sparse.linalg as spla
    from skfem import Basis, BilinearForm, ElementTriArgyris, MeshTri, asm
    from skfem.helpers import dd, ddot, trace

    @BilinearForm
    def bending(u, v, w):  # D = 1, a = 1
        return (1 - nu) * ddot(dd(u), dd(v)) + nu * trace(dd(u)) * trace(dd(v))

    @BilinearForm
    def mass(u, v, w):  # rho h = 1
        return u * v

    basis = Basis(MeshTri.init_tensor(np.linspace(0, 1, n + 1), np.linspace(0, 1, n + 1)), ElementTriArgyris())
    k, m = asm(bending, basis), asm(mass, basis)
    # clamped edge x = 0: w, its derivatives along the edge and the normal slope (w_xx stays free)
    held = basis.get_dofs(lambda x: np.isclose(x[0], 0.0)).all(["u", "u_x", "u_y", "u_xy", "u_yy", "u_n"])
    free = np.setdiff1d(np.arange(basis.N), held)
    lam = spla.eigsh(k[free][:, free], modes, m[free][:, free], sigma=0.0)[0]
    return np.sqrt(np.sort(lam))


def pretwisted_beam(length: float, width: float, thickness: float, youngs_modulus: float, density: float,
                    twist: float = 0.0, taper: float = 1.0, n_elements: int = 60, modes: int = 4) -> np.ndarray:
    """Natural angular frequencies [rad/s] of a clamped-free pretwisted, tapered Euler-Bernoulli
    beam bending in two planes: transverse displacements ``v`` (along y) and ``w`` (along z), the
    section's principal axes turned by ``theta(s) = twist s / L`` (chord along ``(cos, sin)``),
    bending stiffness ``E (I_c e_c e_c^T + I_f e_t e_t^T)`` with ``I_c = h b^3 / 12`` (bending along
    the chord), ``I_f = b h^3 / 12`` (along the thickness), ``b(s) = width (1 + (taper - 1) s /
    L)``, mass ``rho b h`` per length: the classical pretwisted-beam model (e.g. Carnegie, Proc. Inst.
    Mech. Eng. 173 (1959) 343), Hermite cubics with 5-point Gauss integration. The independent
    reference of SolidBlade's twist and taper (a slender blade bends as this beam)."""
    import scipy.linalg

    le = length / n_elements
    gx, gw = np.polynomial.legendre.leggauss(5)
    gx, gw = 0.5 * (gx + 1), 0.5 * gw
    size = 4 * (n_elements + 1)  # per node: v, v', w, w'
    k, m = np.zeros((size, size)), np.zeros((size, size))
    for e in range(n_elements):
        dofs = [4 * e + i for i in range(8)]
        for x, wt in zip(gx, gw):
            s = (e + x) * le
            n = np.array([1 - 3 * x ** 2 + 2 * x ** 3, le * (x - 2 * x ** 2 + x ** 3), 3 * x ** 2 - 2 * x ** 3,
                          le * (-x ** 2 + x ** 3)])
            b2 = np.array([-6 + 12 * x, le * (-4 + 6 * x), 6 - 12 * x, le * (-2 + 6 * x)]) / le ** 2
            nv, nw, bv, bw = (np.zeros((1, 8)) for _ in range(4))
            nv[0, [0, 1, 4, 5]], nw[0, [2, 3, 6, 7]] = n, n
            bv[0, [0, 1, 4, 5]], bw[0, [2, 3, 6, 7]] = b2, b2
            curvature = np.vstack([bv, bw])
            b = width * (1 + (taper - 1) * s / length)
            theta = twist * s / length
            chord, normal = np.array([np.cos(theta), np.sin(theta)]), np.array([-np.sin(theta), np.cos(theta)])
            ei = youngs_modulus * (thickness * b ** 3 / 12 * np.outer(chord, chord)
                                   + b * thickness ** 3 / 12 * np.outer(normal, normal))
            k[np.ix_(dofs, dofs)] += wt * le * curvature.T @ ei @ curvature
            m[np.ix_(dofs, dofs)] += wt * le * density * b * thickness * (nv.T @ nv + nw.T @ nw)
    free = slice(4, size)
    lam = scipy.linalg.eigh(k[free, free], m[free, free], eigvals_only=True, subset_by_index=[0, modes - 1])
    return np.sqrt(lam)


def solid_plate(n: int, nu: float = 0.3, ratio: float = 100.0) -> np.ndarray:
    e, rho, a = 200e9, 7800.0, 1.0
    h = a / ratio
    d = e * h ** 3 / (12 * (1 - nu ** 2))
    blade = SolidBlade(a, a, h, e, nu, rho, n_elements=(n, n, 1))
    return blade.natural_frequencies(5) * a ** 2 * np.sqrt(rho * h / d), blade.n_dof


def _peak_mb() -> float:
    import resource

    return resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024


def main(quick: bool = False) -> None:
    print("1. Kirchhoff square cantilever plate, Argyris triangles (lambda)")
    ref = None
    for n in (8, 16, 32):
        t = time.perf_counter()
        lam = kirchhoff_square_cantilever(n)
        print(f"   n = {n:2d}: {np.array2string(lam, precision=5)}  ({time.perf_counter() - t:.1f} s)")
        ref = lam
    print(f"   Leissa (1969) / converged - 1: {np.array2string(np.array(LEISSA) / ref - 1, precision=4)}")
    print("2. SolidBlade on the plate, a/h = 100, n x n x 1 (lambda, error against the Kirchhoff plate)")
    for n in (6, 8, 12, 16):
        t = time.perf_counter()
        lam, n_dof = solid_plate(n)
        print(f"   n = {n:2d} ({n_dof:5d} DOFs): {np.array2string(lam, precision=4)}  "
              f"err {np.array2string(lam / ref - 1, precision=4)}  ({time.perf_counter() - t:.1f} s)")
    if quick:
        return
    print("3. A blade of about 50,000 DOFs: L = 0.3 m, b = 0.06 m, h = 6 mm, twist 0.5 rad, taper 0.7,")
    print("   160 x 8 x 1 elements, 1,000 rad/s at R = 0.25 m")
    for speed in (0.0, 1000.0):
        t = time.perf_counter()
        blade = SolidBlade(0.3, 0.06, 0.006, 200e9, 0.3, 7800.0, twist=0.5, taper=0.7, n_elements=(160, 8, 1),
                           rotor_speed=speed, hub_radius=0.25)
        t_asm = time.perf_counter() - t
        t = time.perf_counter()
        omega = blade.natural_frequencies(10)
        t_eig = time.perf_counter() - t
        print(f"   Omega = {speed:6.0f} rad/s: {blade.n_dof} DOFs, nnz(K) = {blade.stiffness.nnz}, assembly "
              f"{t_asm:.1f} s, first 10 frequencies {t_eig:.1f} s")
        print(f"   f [Hz]: {np.array2string(omega / (2 * np.pi), precision=1)}")
        t = time.perf_counter()
        reduced = craig_bampton(blade, blade.dofs_of("root"), n_modes=10)
        t_cb = time.perf_counter() - t
        print(f"   Craig-Bampton to the root face ({blade.dofs_of('root').size} DOFs) and 10 modes: {t_cb:.1f} s, "
              f"{reduced.n_dof} DOFs; peak memory of the process {_peak_mb():.0f} MB")


if __name__ == "__main__":
    main(quick="--quick" in sys.argv)

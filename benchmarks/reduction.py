"""Reduction that scales (issue 30, part 4): sparse Craig-Bampton and interface reduction of a
solid blade of hexahedra, timed, with the reduced model's errors against the unreduced one.

The model (:func:`hex_blade`): a plate-like blade of 8-node hexahedra (trilinear, consistent
mass, 2 x 2 x 2 Gauss points), ``length`` along x (radial), chord ``width`` along y, ``thickness``
along z, titanium (E = 110 GPa, nu = 0.3, rho = 4430 kg/m^3), assembled with ``scipy.sparse``
from one element matrix (the elements are equal boxes); the root face ``x = 0`` is the
Craig-Bampton boundary, its outer node columns (a fifth of the chord each side) are the two
flanks (contact patches), the far corner is the tip. It stands in for
:class:`~frictionjoint.structures.SolidBlade` at the size that matters here: its element locks in
bending (this is a benchmark of the reduction, not of the blade).

Limits, as :mod:`frictionjoint.linear_limits` defines them for the root, the flanks being the
contact: ``stuck``, every flank DOF held to the ground by a spring ``k_s`` (normal x and both
tangential directions); ``slipping``, the normal springs only (the tangential directions free: the
contact slips and carries no tangential stiffness); ``free``, the blade free-free, reported as
the hardest case. The rest of the root face is free in each: it is in the Craig-Bampton
boundary because the FE export names the whole root surface, and the interface reduction reduces
it. Errors printed (reduced against unreduced, the same damping, tip load ``z``):

* interface reduction (:func:`~frictionjoint.structures.interface.interface_reduction`) against
  the unreduced interface (the Craig-Bampton model with every root DOF), stuck limit: its first
  ten frequencies and its static tip response, relative, with the flanks kept and with
  characteristic constraint modes, per number of interface modes;
* with ``--frequencies N``: the receptance at the tip (z) at ``N`` frequencies up to the cut-off,
  ``max |H_r - H| / max |H|`` (relative to the peak over the band: pointwise ratios are
  meaningless at the antiresonances), per limit, of the Craig-Bampton and of the
  interface-reduced model.

Cut-off: ``omega_c = omega_n / 3``, ``omega_n`` the highest fixed-interface mode kept
(``fixed_interface_frequencies[-1]``). Below it, with Rayleigh damping ``beta = 2e-6 s`` (1 % at
10^4 rad/s, the default ``--beta``) and 20 modes, the tip receptance is within 1e-3 of the peak in
every limit: 1,575 DOFs (``tests/test_reduction_sparse.py``) 9.6e-5 stuck, 8.1e-5 slipping,
3.5e-5 free; 7,644 DOFs (``--size 48,12,3 --frequencies 20``) 6.0e-5, 4.9e-5, 1.1e-5, the same
with the interface reduced (flanks kept, 20 interface modes). Near a resonance the error is the
mode's frequency error over its damping ratio: at 0.1 % (``--beta 2e-7``) it is 4e-3 to 1e-2 with
20 modes, and more modes (a higher ``omega_n`` for the same band) are the remedy.

Measured on this machine (2 cores shared with other jobs, load 3 to 5), the 50,925-DOF blade
(96 x 24 x 6 elements, 3.6 million stiffness entries; root face 525 DOFs, flanks 210):

=====================================================  ==============  ===========
step                                                   wall            peak memory
=====================================================  ==============  ===========
assemble + FEModel checks                              2.2-6.1 s       0.9 GB
craig_bampton, 20 modes + tip residual vector (546)    41-107 s        1.6 GB
  (CPU 52-58 s: factor 3.4-6.4 s, solves 29-50 s, eigsh 3-12 s, projections 3-5 s)
interface_reduction, flanks kept, 20 modes (251)       0.7-9.7 s       1.6 GB
one frequency of the full model (complex sparse LU)    11-139 s        2.2 GB
one frequency of a reduced model                       < 1 ms          --
=====================================================  ==============  ===========

and its tip receptance (``--frequencies 3``: 0.005, 0.5 and 1 times the cut-off, no resonance
among them, so a weaker check than the smaller models' 20 to 60 points) within 1.3e-5 (stuck),
8.9e-6 (slipping) and 2.8e-5 (free) of the largest, the same with the interface reduced.

Usage::

    python benchmarks/reduction.py                   # the 50,925-DOF blade: time and memory of each step
    python benchmarks/reduction.py --quick           # 1,575 DOFs
    python benchmarks/reduction.py --size 48,12,3 --frequencies 20   # with the receptance errors
"""
from __future__ import annotations

import argparse
import cProfile
import pstats
import resource
import sys
import time
from pathlib import Path

import numpy as np
import scipy.linalg
import scipy.sparse as sp
import scipy.sparse.linalg as spla

if __package__ in (None, ""):  # run as a script: the repository is not on the path
    sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from frictionjoint.structures import FEModel, craig_bampton  # noqa: E402
from frictionjoint.structures.interface import interface_reduction  # noqa: E402

TITANIUM = dict(youngs_modulus=110e9, poisson_ratio=0.3, density=4430.0)
CORNERS = np.array([[-1, -1, -1], [1, -1, -1], [1, 1, -1], [-1, 1, -1],
                    [-1, -1, 1], [1, -1, 1], [1, 1, 1], [-1, 1, 1]], dtype=float)
LIMITS = ("stuck", "slipping", "free")


def hex_element(a: float, b: float, c: float, youngs_modulus: float, poisson_ratio: float,
                density: float) -> tuple[np.ndarray, np.ndarray]:
    """Stiffness and consistent mass (24 x 24, DOFs node by node, x y z) of an 8-node brick of
    sides ``a, b, c`` [m], 2 x 2 x 2 Gauss points (exact for the mass, full integration)."""
    e, nu = youngs_modulus, poisson_ratio
    lam, mu = e * nu / ((1 + nu) * (1 - 2 * nu)), e / (2 * (1 + nu))
    d = np.zeros((6, 6))
    d[:3, :3] = lam
    d[range(3), range(3)] += 2 * mu
    d[range(3, 6), range(3, 6)] = mu
    half = np.array([a, b, c]) / 2
    det = np.prod(half)
    ke, me = np.zeros((24, 24)), np.zeros((24, 24))
    for point in CORNERS / np.sqrt(3):
        factors = 1 + CORNERS * point
        n = np.prod(factors, axis=1) / 8
        dn = np.stack([CORNERS[:, k] * np.prod(np.delete(factors, k, axis=1), axis=1) / 8 for k in range(3)],
                      axis=1) / half
        bmat = np.zeros((6, 24))
        for node, (bx, by, bz) in enumerate(dn):
            bmat[:, 3 * node:3 * node + 3] = [[bx, 0, 0], [0, by, 0], [0, 0, bz], [by, bx, 0], [0, bz, by], [bz, 0, bx]]
        ke += bmat.T @ d @ bmat * det
        shape = np.kron(n[None, :], np.eye(3))
        me += density * shape.T @ shape * det
    return ke, me


def hex_blade(n_length: int, n_chord: int, n_thickness: int, length: float = 0.2, width: float = 0.05,
              thickness: float = 0.01) -> FEModel:
    """The benchmark's blade (module docstring) as an :class:`FEModel`: node ids ``1 ...``,
    directions 1..3, node sets ``root``, ``flank_a``, ``flank_b``, ``rest`` (root face minus the
    flanks) and ``tip``; its node coordinates are ``model.coordinates`` (n_nodes, 3) [m]."""
    ke, me = hex_element(length / n_length, width / n_chord, thickness / n_thickness, **TITANIUM)
    node = np.arange((n_length + 1) * (n_chord + 1) * (n_thickness + 1)).reshape(
        n_length + 1, n_chord + 1, n_thickness + 1)
    conn = np.stack([node[i:i + n_length, j:j + n_chord, k:k + n_thickness].ravel()
                     for i, j, k in ((CORNERS + 1) // 2).astype(int)], axis=1)
    dofs = (3 * conn[:, :, None] + np.arange(3)).reshape(-1, 24)
    rows, cols = np.repeat(dofs, 24, axis=1).ravel(), np.tile(dofs, 24).ravel()
    n = 3 * node.size
    stiffness = sp.csr_array((np.tile(ke.ravel(), len(dofs)), (rows, cols)), shape=(n, n))
    mass = sp.csr_array((np.tile(me.ravel(), len(dofs)), (rows, cols)), shape=(n, n))
    table = np.stack([np.repeat(np.arange(1, node.size + 1), 3), np.tile([1, 2, 3], node.size)], axis=1)
    side = max(1, (n_chord + 1) // 5)
    root = node[0]
    sets = {"root": root.ravel() + 1, "flank_a": root[:side].ravel() + 1, "flank_b": root[-side:].ravel() + 1,
            "rest": root[side:-side].ravel() + 1, "tip": [int(node[-1, -1, -1]) + 1]}
    model = FEModel(mass, stiffness, dofs=table, node_sets={k: [int(v) for v in s] for k, s in sets.items()},
                    source=f"benchmarks/reduction.py hex_blade({n_length}, {n_chord}, {n_thickness})")
    grid = np.meshgrid(np.linspace(0, length, n_length + 1), np.linspace(0, width, n_chord + 1),
                       np.linspace(0, thickness, n_thickness + 1), indexing="ij")
    object.__setattr__(model, "coordinates", np.stack(grid, axis=-1).reshape(-1, 3))
    return model


def root_springs(model: FEModel, limit: str, spring: float) -> np.ndarray:
    """The springs [N/m] to the ground on each DOF of ``model`` in a limit (module docstring)."""
    if limit not in LIMITS:
        raise ValueError(f"limit must be one of {LIMITS}, got {limit!r}")
    k = np.zeros(model.n_dof)
    for patch in ("flank_a", "flank_b"):
        if limit == "stuck":
            k[model.dofs_of(patch)] = spring
        elif limit == "slipping":
            k[model.dofs_of(patch, [1])] = spring
    return k


def tip_receptance(model: FEModel, springs: np.ndarray, omegas: np.ndarray, rayleigh: tuple) -> np.ndarray:
    """Receptance tip z / tip z force [m/N] of the full model with ``springs`` [N/m] on its DOFs
    and damping ``alpha M + beta K`` (of the structure), one sparse LU per frequency [rad/s]."""
    alpha, beta = rayleigh
    tip = model.dof_index(model.node_sets["tip"][0], 3)
    k = sp.csc_array(model.stiffness + sp.diags_array(springs))
    c = alpha * model.mass + beta * model.stiffness
    f = np.zeros(model.n_dof, dtype=complex)
    f[tip] = 1.0
    # the dynamic stiffness is structurally symmetric: SuperLU's ordering of K + K^T and symmetric
    # mode (diagonal pivots preferred) fill as the real factor does; COLAMD's fill is several times it
    return np.array([spla.splu(sp.csc_array(k + 1j * w * c - w * w * model.mass), permc_spec="MMD_AT_PLUS_A",
                               diag_pivot_thresh=0.1, options={"SymmetricMode": True}).solve(f)[tip]
                     for w in omegas])


def reduced_tip_receptance(model: FEModel, reduced, springs: np.ndarray, omegas: np.ndarray) -> np.ndarray:
    """The same of a reduced model: the springs act on the rows of its transformation (the
    boundary DOFs' own coordinates for Craig-Bampton), its damping is its own."""
    tip = model.dof_index(model.node_sets["tip"][0], 3)
    t = reduced.transformation
    held = np.flatnonzero(springs)
    k = reduced.stiffness + t[held].T @ (springs[held, None] * t[held])  # x = T x_r at the springs
    return np.array([t[tip] @ np.linalg.solve(k + 1j * w * reduced.damping - w * w * reduced.mass, t[tip])
                     for w in omegas])


def interface_errors(model: FEModel, cb, flanks: list, modes: tuple = (5, 10, 20, 40), n_frequencies: int = 10,
                     spring: float = 2e7) -> list[str]:
    """Rows: interface reduction against the unreduced interface (the Craig-Bampton model ``cb``),
    stuck limit: the first ``n_frequencies`` frequencies and the static tip response, with the
    flanks kept and with nothing kept (characteristic constraint modes), per number of modes."""
    springs = root_springs(model, "stuck", spring)
    held = np.flatnonzero(springs)
    tip = model.dof_index(model.node_sets["tip"][0], 3)

    def stuck(red):
        t = red.transformation
        k = red.stiffness + t[held].T @ (springs[held, None] * t[held])
        w = np.sqrt(np.abs(scipy.linalg.eigh(k, red.mass, eigvals_only=True)[:n_frequencies]))
        return w, t[tip] @ np.linalg.solve(k, t[tip])

    w0, x0 = stuck(cb)
    rows = [f"interface reduction, stuck limit, against the unreduced interface ({cb.n_dof} DOFs): error of the "
            f"first {n_frequencies} frequencies, of the static tip response"]
    n_rest = len(cb.boundary_dofs) - len(flanks)
    for keep, label in ((flanks, f"flanks kept ({len(flanks)} DOFs)"), ((), "nothing kept (CC modes)")):
        for n in modes:
            if n > (n_rest if keep else len(cb.boundary_dofs)):
                continue
            red = interface_reduction(cb, n, keep=keep)
            w, x = stuck(red)
            rows.append(f"  {label:<26} {n:3d} modes, {red.n_dof:4d} DOFs: frequencies "
                        f"{np.max(np.abs(w / w0 - 1)):.1e}, static tip {abs(x / x0 - 1):.1e}")
    return rows


def _breakdown(profile: cProfile.Profile) -> str:
    """Seconds of craig_bampton's steps from its profile: the factorisation, the solves (constraint
    modes, ARPACK's shift-invert, residual vectors), eigsh as a whole, the projections."""
    stats = pstats.Stats(profile).stats
    total = {"factor": 0.0, "solves": 0.0, "eigsh": 0.0, "projections": 0.0}
    for (_, _, name), (_, calls, tottime, cumtime, _) in stats.items():
        if name == "gstrf" or name.endswith("gstrf>"):
            total["factor"] += tottime
        elif "method 'solve' of" in name:
            total["solves"] += tottime
        elif name == "eigsh":
            total["eigsh"] += cumtime
        elif name == "_project":
            total["projections"] += cumtime
    return ", ".join(f"{k} {v:.1f} s" for k, v in total.items())


def _rss() -> float:
    """Peak resident memory of this process so far [GB]."""
    return resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024 ** 2


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--quick", action="store_true", help="the 1,575-DOF blade (24 x 6 x 2)")
    parser.add_argument("--size", default=None, help="elements n_length,n_chord,n_thickness (default 96,24,6)")
    parser.add_argument("--modes", type=int, default=20, help="fixed-interface modes kept")
    parser.add_argument("--interface-modes", type=int, default=20, help="interface modes of the rest of the root")
    parser.add_argument("--beta", type=float, default=2e-6, help="Rayleigh beta [s] (zeta = beta omega / 2)")
    parser.add_argument("--frequencies", type=int, default=0,
                        help="receptance points per limit below the cut-off (one sparse LU each of the full model)")
    args = parser.parse_args(argv)
    size = tuple(int(a) for a in (args.size or ("24,6,2" if args.quick else "96,24,6")).split(","))
    rows = []

    def emit(step, seconds, extra=""):
        rows.append(f"{step:<44} {seconds:8.2f} s  {_rss():5.2f} GB  {extra}")
        print(rows[-1], flush=True)

    t0 = time.perf_counter()
    model = hex_blade(*size)
    emit(f"assemble + FEModel checks ({model.n_dof} DOFs)", time.perf_counter() - t0,
         f"nnz(K) = {model.stiffness.nnz}")
    root, tip = model.dofs_of("root"), model.dof_index(model.node_sets["tip"][0], 3)
    rayleigh = (0.0, args.beta)
    t0, c0 = time.perf_counter(), time.process_time()
    profile = cProfile.Profile()
    cb = profile.runcall(craig_bampton, model, root, args.modes, [tip], rayleigh=rayleigh)
    w_n = cb.fixed_interface_frequencies[-1]
    emit(f"craig_bampton ({len(root)} root DOFs, {args.modes} modes)", time.perf_counter() - t0,
         f"{cb.n_dof} DOFs; omega_1 {cb.fixed_interface_frequencies[0]:.0f}, omega_n {w_n:.0f} rad/s; "
         f"CPU {time.process_time() - c0:.1f} s")
    rows.append("  of which " + _breakdown(profile))
    print(rows[-1], flush=True)
    flanks = [model.dof_names[k] for s in ("flank_a", "flank_b") for k in model.dofs_of(s)]
    t0 = time.perf_counter()
    ir = interface_reduction(cb, args.interface_modes, keep=flanks)
    emit(f"interface_reduction (keep {len(flanks)} flank DOFs)", time.perf_counter() - t0, f"{ir.n_dof} DOFs")
    table = interface_errors(model, cb, flanks)
    rows.extend(table)
    print("\n".join(table), flush=True)
    if args.frequencies:
        omegas = np.linspace(0.005, 1.0, args.frequencies) * w_n / 3
        for limit in LIMITS:
            springs = root_springs(model, limit, 2e7)
            t0 = time.perf_counter()
            full = tip_receptance(model, springs, omegas, rayleigh)
            errors = []
            for label, red in (("craig_bampton", cb), ("interface", ir)):
                got = reduced_tip_receptance(model, red, springs, omegas)
                errors.append(f"{label} {np.max(np.abs(got - full)) / np.max(np.abs(full)):.1e}")
            emit(f"receptance {limit} ({args.frequencies} frequencies)", time.perf_counter() - t0,
                 "error / peak below omega_n / 3: " + ", ".join(errors))
    return 0


if __name__ == "__main__":
    sys.exit(main())

"""The solid blade on patch flanks (models/ti64_solid_blade.toml) against its unreduced model: the
tip receptance of the Craig-Bampton model that ``BladeAssembly.from_model`` builds, in the root's
two linear limits, against the full SolidBlade's, below the reduction's cut-off, for several
``n_modes`` (issue 30, part 5; tests/test_solid_blade_model.py checks the same numbers).

The unreduced model: the SolidBlade's sparse mass, stiffness (elastic, geometric and spin
softening at the rotor speed) and Rayleigh damping (4941 DOFs), the root face's chordwise ``u2``
clamped (the slot holds it, as :func:`~frictionjoint.structures.solid_root.solid_blade_on_patches`
does), and on every flank node the patch's springs in the node's ``(X, Y) = (u3, u1)``:

- stuck: ``kn_i n n^T + kt_i t t^T`` (every slider stuck: ``linear_limits``' stuck limit, whose
  slider springs are ``kt_i t t^T`` along each node's slip direction and whose structure already
  has the normal springs ``kn_i n n^T``);
- slipping (free slip): ``kn_i n n^T`` only;

with the normal dashpots ``cn_i n n^T`` in both (the attachment's damping). The reduced limits are
:func:`~frictionjoint.linear_limits.limit_structures` of the assembly's system, as
``BladeAssembly.frequency_response`` computes them; the tip force is ``T^T e_tip`` and the tip
displacement ``T[tip] x_r``.

Receptance of the unreduced model: one sparse LU per frequency (SuperLU, ``splu``) of ``K - w^2 M
+ i w C`` written as the real ``2n x 2n`` system ``[[A, -B], [B, A]]``, ``A = K - w^2 M``, ``B = w
C``: the same solution, and SuperLU's real path is 1.5-10 times faster here than its complex one
(0.25-1.5 s against 1.5-9.7 s per frequency on this shared machine, by its load).

Cut-off: ``omega_n / 3`` as benchmarks/reduction.py (the test's), and ``omega_n`` itself, with
``omega_n`` the highest kept fixed-interface mode's frequency (the flank nodes clamped), the
``fixed_interface_frequencies[-1]`` of the reduction, read here as the stiffness of the last modal
coordinate (unit modal mass): 14,221 rad/s with 5 modes, 42,041 with 10, 118,222 with 20.

Errors: ``max |H_r - H| / |H|`` over frequencies from 100 rad/s up to the cut-off (pointwise
relative, the full model's resonances included, where it is largest) and ``max |H_r - H| / max
|H|`` (relative to the largest receptance below the cut-off). Measured (60 frequencies and the
resonances, cut-off omega_n / 3; error / peak, pointwise in brackets):

=========  ===========================  ===========================  ===========================
limit      5 modes (4,740 rad/s)        10 modes (14,014 rad/s)      20 modes (39,407 rad/s)
=========  ===========================  ===========================  ===========================
stuck      1.4e-3 (7.6e-3 at 4,728)     7.8e-5 (4.7e-3 at 13,213)    4.8e-6 (3.8e-3 at 39,164)
slipping   2.4e-1 (2.4e-1 at 1,819)     1.5e-2 (2.3e-2 at 11,892)    9.0e-4 (1.3e-2 at 36,539)
=========  ===========================  ===========================  ===========================

Up to ``omega_n`` the error / peak is the same (the first resonance is the peak) and the pointwise
one 0.1-0.4, at the resonances near ``omega_n``. At a resonance the error is the mode's frequency
error over its damping ratio; the free-slip first mode (1819 rad/s), the blade swinging on its
flanks against the centrifugal stiffening, has a damping ratio of 7.8e-6 (Rayleigh damping acts on
the elastic stiffness only), so that its frequency error, 1.9e-6 with 5 modes, is 0.24 of its peak.

Run: ``python -m benchmarks.solid_blade_accuracy`` (some 2-5 minutes on this shared machine).

The partial-slip resonance, full size (``--resonance``; the tests run its onset only, 1880-1901
rad/s): the exact time-domain sweep over 1880-1940 rad/s (``fj.sweep``, as ``frictionjoint sweep
ti64_solid_blade`` runs it; its 1920 rad/s point alone took 154 s, which is why
``test_command_line_python_and_study_give_the_same_sweep`` stops at 1900), and the harmonic balance
sweep at ``H = 15`` with every branch point checked against its exact orbit (``check=True``), the
truncation error per point (measured before: 1.4e-3 to 1.5e-2 over 1902-1941 rad/s, 25 branch
points, 9 min on a loaded machine; a point whose exact orbit is not found prints NaN).
"""
from __future__ import annotations

import time

import numpy as np
import scipy.sparse as sp
import scipy.sparse.linalg as spla

from frictionjoint.linear_limits import limit_structures
from frictionjoint.structures import BladeAssembly, load_blade_model
from frictionjoint.structures.fe_import import dof_name

MODEL = "ti64_solid_blade"


def unreduced_limits(blade, root) -> tuple[dict, list]:
    """The unreduced blade on its flanks' springs, in both linear limits (module docstring).

    Parameters
    ----------
    blade : SolidBlade
    root : SolidBladeRoot or PatchDovetailRoot
        Its flank nodes (DOF names of ``blade``), normals, tangents and per-node stiffnesses.

    Returns
    -------
    limits : dict
        ``{"stuck": (M, K, C), "slipping": (M, K, C)}``, sparse, the root face's ``u2`` removed.
    names : list of str
        The DOF names of the rows.
    """
    names = list(blade.dof_names)
    index = {name: i for i, name in enumerate(names)}
    n = len(names)
    normal, tangent = root.normals[root.flank], root.tangents[root.flank]
    rows, cols, stuck, slipping, damping = [], [], [], [], []
    for j, node in enumerate(root.nodes):
        dofs = [index[node[0]], index[node[1]]]
        nn, tt = np.outer(normal[j], normal[j]), np.outer(tangent[j], tangent[j])
        for a in range(2):
            for b in range(2):
                rows.append(dofs[a])
                cols.append(dofs[b])
                slipping.append(root.normal_stiffness[j] * nn[a, b])
                stuck.append(root.normal_stiffness[j] * nn[a, b] + root.tangential_stiffness[j] * tt[a, b])
                damping.append(root.normal_damping[j] * nn[a, b])

    def springs(values):
        return sp.csr_array(sp.coo_array((values, (rows, cols)), shape=(n, n)))

    held = {index[dof_name(i + 1, 2)] for i in blade._sets["root"]}
    keep = np.array([i for i in range(n) if i not in held])

    def free(a):
        return sp.csr_array(sp.csr_array(a)[keep][:, keep])

    m, c = free(blade.mass), free(blade.damping + springs(damping))
    limits = {"stuck": (m, free(blade.stiffness + springs(stuck)), c),
              "slipping": (m, free(blade.stiffness + springs(slipping)), c)}
    return limits, [names[k] for k in keep]


def receptance(mass, stiffness, damping, dof: int, omega: float) -> complex:
    """``H = e^T (K - w^2 M + i w C)^-1 e`` of DOF ``dof`` [m/N] by one sparse LU (module docstring)."""
    a, b = stiffness - omega * omega * mass, omega * damping
    lu = spla.splu(sp.csc_array(sp.block_array([[a, -b], [b, a]])), permc_spec="MMD_AT_PLUS_A")
    n = stiffness.shape[0]
    e = np.zeros(2 * n)
    e[dof] = 1.0
    y = lu.solve(e)
    return complex(y[dof], y[n + dof])


def cut_off(assembly: BladeAssembly) -> float:
    """The highest kept fixed-interface mode's angular frequency [rad/s] (module docstring)."""
    s = assembly.structure
    last = [name for name in s.dof_names if name.startswith("q")][-1]
    k = s.dof_index(last)
    return float(np.sqrt(s.stiffness[k, k]))


def reduced_receptance(assembly: BladeAssembly, limit: str, omegas) -> np.ndarray:
    """The assembly's tip receptance in a linear limit (``"stuck"``/``"slipping"``) [m/N]."""
    row = assembly._row(assembly.tip)
    structure = limit_structures(assembly.system(1.0))[limit]
    return structure.harmonic_response(np.asarray(omegas, dtype=float), row) @ row


def main(n_modes=(5, 10, 20), n_grid: int = 60) -> None:
    model = load_blade_model(MODEL)
    blade = model.blade()
    assemblies = {n: BladeAssembly.from_model(model, n_modes=n) for n in n_modes}
    cuts = {n: cut_off(a) for n, a in assemblies.items()}
    first = assemblies[n_modes[0]]
    limits, names = unreduced_limits(blade, first.joints[0])
    tip = names.index(first.tip)
    print(f"{MODEL}: {blade.n_dof} DOFs unreduced; cut-offs " + ", ".join(f"{cuts[n]:.0f} rad/s ({n} modes)"
                                                                       for n in n_modes))
    print(f"{'limit':9s} {'n_modes':>7s} {'cut-off':>9s} {'max rel':>9s} {'at':>9s} {'max/peak':>9s}")
    for limit, (m, k, c) in limits.items():
        full = np.sort(np.sqrt(spla.eigsh(sp.csc_array(k), 12, sp.csc_array(m), sigma=0.0,
                                          return_eigenvectors=False)))
        top = max(cuts.values())
        omegas = np.unique(np.concatenate([np.geomspace(100.0, top, n_grid), full[full <= top]]))
        t0 = time.perf_counter()
        h = np.array([receptance(m, k, c, tip, w) for w in omegas])
        cost = (time.perf_counter() - t0) / omegas.size
        for n, assembly in assemblies.items():
            for cut in (cuts[n] / 3, cuts[n]):
                below = omegas <= cut
                err = np.abs(reduced_receptance(assembly, limit, omegas[below]) - h[below])
                rel = err / np.abs(h[below])
                print(f"{limit:9s} {n:7d} {cut:9.0f} {rel.max():9.2e} {omegas[below][rel.argmax()]:9.0f} "
                      f"{err.max() / np.abs(h[below]).max():9.2e}")
        print(f"  ({omegas.size} frequencies, {cost:.2f} s each unreduced; its first modes {np.round(full[:6])})")


def resonance(omega: str = "1880:1940:7", n_harmonics: int = 15) -> None:
    """The partial-slip resonance at full size (module docstring): the exact sweep, then the
    checked harmonic balance sweep, each timed."""
    import frictionjoint as fj

    t0 = time.perf_counter()
    exact = fj.sweep(MODEL, omega)
    print(f"exact sweep {omega} rad/s: {time.perf_counter() - t0:.0f} s")
    for w, a, stuck, ok in zip(exact.omega, exact.amplitude, exact.stuck, exact.converged):
        print(f"  {w:9.3f} {a:.6e} m stuck {stuck!s:5} converged {ok}")
    t0 = time.perf_counter()
    hb = fj.sweep(MODEL, omega, method="hbm", n_harmonics=n_harmonics, check=True)
    print(f"harmonic balance H = {n_harmonics}, every point checked: {time.perf_counter() - t0:.0f} s")
    for w, a, stuck, err in zip(hb.omega, hb.amplitude, hb.stuck, hb.truncation_error):
        print(f"  {w:9.3f} {a:.6e} m stuck {stuck!s:5} truncation error {err:.2e}")


if __name__ == "__main__":
    import sys

    resonance() if "--resonance" in sys.argv[1:] else main()

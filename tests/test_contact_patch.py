"""Dovetail flanks as contact patches (issue 30, part 3): :class:`frictionjoint.PatchDovetailRoot`.

References:
- the two-flank point model :class:`frictionjoint.DovetailRoot` (its closed-form statics, DESIGN.md
  section 4, and its exact march): a patch of N nodes on a rigid flank (every node on the root's
  DOFs) with uniform pressure (per node kn/N, kt/N) is that model, so its static node loads are the
  point model's flank loads shared equally and its steady state the point model's, to rounding;
- on an elastic root, the static state is checked as a solution of the contact problem (equilibrium
  of the structure, Coulomb's law at every node, slip in the direction of the force) and the
  partial slip over a cycle is read from the exact march's events;
- the energy balance of the march (work = stored + dissipated).
"""
import math

import numpy as np
import pytest
import skfem
from skfem.helpers import ddot, dot, sym_grad, trace

import frictionjoint as fj
from frictionjoint.errors import ParameterError
from frictionjoint.structures import FEModel, craig_bampton, dof_name

#: relative agreement of a rigid-flank patch with the point model (the issue's bound)
STEADY = 1e-9
#: static node loads against the point model's closed forms, relative (rounding of a 2 x 2 solve)
STATIC = 1e-14

G, MU, KN, FC = math.radians(40.0), 0.3, 1e6, 1000.0
#: tangential flank stiffness [N/m]: (kt/kn) tan g = 0.17 <= mu (stuck run-up), 0.67 > mu (slipping)
KT_STUCK, KT_SLIPPING = 2e5, 8e5


# ------------------------------------------------------------ rigid flank: the point model
def _root_block():
    """A root block (X, Y) on its flanks, no support of its own (the flanks hold it)."""
    return fj.LinearStructure(np.diag([0.2, 0.2]), np.zeros((2, 2)), np.diag([2.0, 2.0]), dof_names=["X", "Y"])


def _rigid_patch(n, kt, vary):
    """N nodes per flank, all on the root's DOFs, kn/N and kt/N each, loaded by Fc on Y."""
    def flank():
        return fj.FlankPatch([("X", "Y")] * n, KN / n, kt / n)
    return fj.PatchDovetailRoot(flank(), flank(), G, MU, {"Y": FC}, normal_load_variation=vary)


def _point(kt, vary):
    return fj.DovetailRoot(FC, G, MU, KN, kt, tangential_dof="X", radial_dof="Y", normal_load_variation=vary)


def _shaken(root):
    """Shaken hard enough to slip and, with varying normal loads, to lift off and close again."""
    return fj.FrictionSystem(_root_block(), [root], omega=2000.0,
                             excitation=[fj.HarmonicForce("X", 400.0), fj.HarmonicForce("Y", 200.0, phase=0.7)])


@pytest.mark.parametrize("kt, regime", [(KT_STUCK, "stuck"), (KT_SLIPPING, "slipping")])
@pytest.mark.parametrize("n", [1, 4, 16])
def test_rigid_flank_static_loads_are_the_point_models_split(n, kt, regime):
    point = _point(kt, False).static
    patch = _rigid_patch(n, kt, False)
    st = patch.static_state(_root_block())
    assert point.regime == st.regime == regime
    assert np.all(st.slipping == (regime == "slipping"))
    assert np.max(np.abs(st.normal_force * n / point.normal_force - 1)) <= STATIC
    assert np.max(np.abs(st.friction_force * n / point.friction_force - 1)) <= STATIC
    assert np.max(np.abs(st.flank_normal_force / point.normal_force - 1)) <= STATIC
    assert abs(st.displacement[1] / point.radial_displacement - 1) <= STATIC
    assert abs(st.displacement[0]) <= STATIC * point.radial_displacement
    # x = 0 is the static state: the constant force balances the preloaded sliders
    sysm = fj.FrictionSystem(_root_block(), [patch])
    assert np.max(np.abs(sysm.constant_force - sysm.slider_direction.T @ sysm.slider_preload)) <= 1e-13 * FC


def test_rigid_flank_with_mixed_nodes_slips_partially_during_run_up():
    """Nodes of two kinds on each rigid flank, (kt/kn) tan g below and above mu: the first stick,
    the second slip during run-up; the state balances Fc and satisfies Coulomb's law."""
    def flank():
        return fj.FlankPatch([("X", "Y")] * 4, KN / 4, [KT_STUCK / 4, KT_SLIPPING, KT_STUCK / 4, KT_SLIPPING])
    patch = fj.PatchDovetailRoot(flank(), flank(), G, MU, {"Y": FC})
    st = patch.static_state(_root_block())
    assert st.regime == "partial slip" and list(st.slipping) == [False, True] * 4
    ratio = st.friction_force / st.normal_force
    assert np.all(ratio[~st.slipping] < MU) and np.allclose(ratio[st.slipping], MU, rtol=1e-14)
    # radial equilibrium of the root: Fc = sum over the nodes of N cos g + T sin g
    radial = np.sum(st.normal_force * math.cos(G) + st.friction_force * math.sin(G))
    assert abs(radial / FC - 1) <= STATIC
    sysm = fj.FrictionSystem(_root_block(), [patch])
    assert np.max(np.abs(sysm.constant_force - sysm.slider_direction.T @ sysm.slider_preload)) <= 1e-13 * FC


@pytest.mark.parametrize("vary", [False, True], ids=["frozen", "varying"])
@pytest.mark.parametrize("kt", [KT_STUCK, KT_SLIPPING], ids=["stuck run-up", "slipping run-up"])
@pytest.mark.parametrize("n", [1, 4, 16])
def test_rigid_flank_patch_has_the_point_models_steady_state(n, kt, vary):
    """The exact steady state of a patch of N nodes per flank and of the two-flank point model with
    the same totals: amplitudes, first harmonics (amplitude and phase) and the energy per cycle to
    1e-9; every event of the point model's flanks happens to each of its N nodes."""
    a = fj.periodic_response(_shaken(_point(kt, vary)))
    b = fj.periodic_response(_shaken(_rigid_patch(n, kt, vary)))
    assert a.converged and b.converged
    err = max(np.max(np.abs(b.amplitude - a.amplitude)) / np.max(a.amplitude),
              np.max(np.abs(b.harmonic_amplitude - a.harmonic_amplitude)) / np.max(a.harmonic_amplitude),
              np.max(np.abs(b.phase - a.phase)),
              abs(b.dissipated_per_cycle - a.dissipated_per_cycle) / a.dissipated_per_cycle)
    print(f"N = {n}, kt = {kt:g}, {'varying' if vary else 'frozen'}: largest relative difference {err:.2e}")
    assert err <= STEADY
    assert a.events.count("slip") >= 2
    if vary:
        assert a.events.count("lift-off") >= 1
    for kind in ("slip", "stick", "lift-off", "closure"):
        assert b.events.count(kind) == n * a.events.count(kind), kind


# ------------------------------------------------------------ elastic root: partial slip
#: plane-stress dovetail root (trapezoid, its inclined sides the flanks) with a blade stub above:
#: steel, 10 mm deep, root 30 mm wide at the bottom, 10 mm at the neck, stub 40 mm high
E, NU, RHO, DEPTH = 2e11, 0.3, 7800.0, 0.01
WIDE, NECK, STUB = 0.03, 0.01, 0.04
HEIGHT = 0.5 * (WIDE - NECK) * math.tan(G)  # the sides make the flank angle
ROTOR_SPEED, RADIUS = 1000.0, 0.3  # [rad/s], [m] of the root's bottom
KN_FLANK, KT_RATIO = 5e8, 0.3  # per flank [N/m]; kt/kn per node


def _plate():
    """Bilinear quadrilaterals (scikit-fem), 4 across, 3 rows in the root and 5 in the stub: the
    full mass and stiffness, the DOF names (:func:`dof_name`, node ids from 1), the node
    coordinates and the flank nodes (right, left; bottom to neck) and the top right corner."""
    xi = np.linspace(-1.0, 1.0, 5)
    y = np.concatenate([np.linspace(0.0, HEIGHT, 4), np.linspace(HEIGHT, HEIGHT + STUB, 6)[1:]])
    mesh = skfem.MeshQuad.init_tensor(xi, y)
    p = mesh.p.copy()
    half = 0.5 * WIDE - 0.5 * (WIDE - NECK) * np.minimum(p[1] / HEIGHT, 1.0)
    p[0] *= half
    basis = skfem.Basis(skfem.MeshQuad(p, mesh.t), skfem.ElementVector(skfem.ElementQuad1()), intorder=3)
    shear, lame = E / (2 * (1 + NU)), E * NU / (1 - NU ** 2)  # plane stress

    @skfem.BilinearForm
    def stiffness(u, v, _):
        return DEPTH * (2 * shear * ddot(sym_grad(u), sym_grad(v)) + lame * trace(sym_grad(u)) * trace(sym_grad(v)))

    @skfem.BilinearForm
    def mass(u, v, _):
        return DEPTH * RHO * dot(u, v)

    k, m = stiffness.assemble(basis), mass.assemble(basis)
    nodal = basis.nodal_dofs
    names = [""] * k.shape[0]
    for i in range(p.shape[1]):
        names[nodal[0, i]], names[nodal[1, i]] = dof_name(i + 1, 1), dof_name(i + 1, 2)
    on_flank = np.isclose(np.abs(p[0]), half) & (p[1] <= HEIGHT * (1 + 1e-12))
    right = [i for i in np.flatnonzero(on_flank) if p[0, i] > 0]
    left = [i for i in np.flatnonzero(on_flank) if p[0, i] < 0]
    top = np.flatnonzero(np.isclose(p[1], HEIGHT + STUB))
    return m, k, names, p, (right, left), int(top[np.argmax(p[0, top])])


def _flank(nodes, kn=KN_FLANK):
    """A flank's nodes with trapezoid weights (half at the ends) of the flank's stiffness."""
    w = np.ones(len(nodes))
    w[[0, -1]] = 0.5
    w /= w.sum()
    return fj.FlankPatch([(dof_name(i + 1, 1), dof_name(i + 1, 2)) for i in nodes], kn * w, KT_RATIO * kn * w)


@pytest.fixture(scope="module")
def elastic():
    """The plate reduced by Craig-Bampton to its flank nodes and the tip's X (physical) and 4
    modes, Rayleigh damping; the centrifugal body force ``M (Omega^2 r)`` on the radial DOFs."""
    m, k, names, p, (right, left), tip = _plate()
    radius = np.zeros(k.shape[0])
    for i in range(p.shape[1]):
        radius[names.index(dof_name(i + 1, 2))] = RADIUS + p[1, i]
    load = ROTOR_SPEED ** 2 * (m @ radius)
    full = fj.LinearStructure(m.toarray(), k.toarray(), dof_names=names)
    boundary = [dof_name(i + 1, d) for i in right + left for d in (1, 2)] + [dof_name(tip + 1, 1)]
    reduced = craig_bampton(full, boundary, n_modes=4, rayleigh=(50.0, 1e-6))
    return dict(full=full, mass=m, stiffness=k, names=names, load=load, reduced=reduced,
                reduced_load=reduced.transformation.T @ load, right=right, left=left, tip=dof_name(tip + 1, 1))


def test_elastic_root_static_state_is_a_contact_solution(elastic):
    """On the elastic root the pressure is far from uniform: the nodes at the bottom of the flank
    carry less and slip during run-up, those towards the neck stick. The state balances the load on
    the full model and satisfies Coulomb's law node by node."""
    full, load = elastic["full"], elastic["load"]
    root = fj.PatchDovetailRoot(_flank(elastic["right"]), _flank(elastic["left"]), G, MU, load)
    st = root.static_state(full)
    print("static normal loads [N], right flank bottom to neck:", np.round(st.normal_force[:4], 1),
          "T0/N0:", np.round(st.friction_force[:4] / st.normal_force[:4], 4), st.regime)
    assert st.regime == "partial slip"
    assert list(st.slipping) == [True, True, False, False] * 2
    assert np.all(st.normal_force > 0) and st.normal_force.max() > 5 * st.normal_force.min()
    assert np.allclose(st.normal_force[:4], st.normal_force[4:], rtol=1e-9)  # symmetric root
    # Coulomb: |T| <= mu N where stuck, = mu N where slipping, the slip along the force
    ratio = st.friction_force / st.normal_force
    assert np.all(ratio[~st.slipping] < MU) and np.allclose(ratio[st.slipping], MU, rtol=1e-14)
    u = st.displacement[[[full.dof_index(d) for d in node] for node in root.nodes]]  # nodes' (X, Y)
    slip = np.einsum("ij,ij->i", root.tangents[root.flank], u) - st.friction_force / root.tangential_stiffness
    assert np.all(slip[st.slipping] * st.friction_force[st.slipping] > 0)
    assert np.all(np.abs(slip[~st.slipping]) <= 1e-12 * np.max(np.abs(u)))
    # equilibrium of the full structure: K x0 = f + sum_i (N0_i n_i - T0_i t_i)
    sysm = fj.FrictionSystem(full, [root])
    unbalanced = sysm.constant_force - sysm.slider_direction.T @ sysm.slider_preload
    assert np.max(np.abs(unbalanced)) <= 1e-12 * np.abs(load).sum()
    # the sparse path (an FEModel, the FE code's matrices) gives the same state
    dofs = [(int(s[1:s.index("_")]), int(s[-1])) for s in elastic["names"]]
    sparse = root.static_state(FEModel(elastic["mass"], elastic["stiffness"], dofs=dofs))
    assert np.max(np.abs(sparse.normal_force - st.normal_force)) <= 1e-10 * st.normal_force.max()
    assert np.array_equal(sparse.slipping, st.slipping)


def test_nodes_that_open_under_the_load(elastic):
    """Stiffer flanks (2e9 N/m each): the root bends and its bottom corners open under the
    centrifugal load. The static state says so; attach refuses them, and the patches without them
    have the same static state."""
    full, load, right, left = elastic["full"], elastic["load"], elastic["right"], elastic["left"]
    stiff = fj.PatchDovetailRoot(_flank(right, 2e9), _flank(left, 2e9), G, MU, load)
    st = stiff.static_state(full)
    assert list(st.separated) == [True, False, False, False] * 2
    assert np.all(st.normal_force[st.separated] == 0) and np.all(st.normal_force[~st.separated] > 0)
    with pytest.raises(ParameterError, match="open under the centrifugal load"):
        fj.FrictionSystem(full, [stiff])

    def without_corner(nodes):
        patch = _flank(nodes, 2e9)
        return fj.FlankPatch(patch.nodes[1:], patch.normal_stiffness[1:], patch.tangential_stiffness[1:])
    rest = fj.PatchDovetailRoot(without_corner(right), without_corner(left), G, MU, load).static_state(full)
    assert not rest.separated.any()
    assert np.max(np.abs(rest.displacement - st.displacement)) <= 1e-12 * np.max(np.abs(st.displacement))
    assert np.max(np.abs(rest.normal_force - st.normal_force[~st.separated])) <= 1e-12 * st.normal_force.max()


def _slip_fractions(r, n_sliders):
    """Fraction of the period each slider spends slipping on the orbit, from its events."""
    period = 2 * math.pi / r.omega
    frac = np.zeros(n_sliders)
    for j in range(n_sliders):
        ev = [(t, kind) for t, _, s, kind in r.events if s == j and kind in ("slip", "stick", "lift-off", "closure")]
        if not ev:
            continue
        slipping, t_prev = ev[0][1] == "stick", r.section_time  # the status before the first event
        for t, kind in ev:
            frac[j] += (t - t_prev) if slipping else 0.0
            slipping, t_prev = kind == "slip", t
        frac[j] += (r.section_time + period - t_prev) if slipping else 0.0
    return frac / period


@pytest.mark.parametrize("vary, force, slip_pattern", [(False, 1300.0, [True, True, False, False] * 2),
                                                       (True, 1600.0, [True, True, False, False] * 2)],
                         ids=["frozen", "varying"])
def test_elastic_root_slips_partially(elastic, vary, force, slip_pattern):
    """A tangential force at the blade tip: over the steady cycle the low-pressure nodes at the
    bottom of each flank slip while those towards the neck stick -- partial slip, which a point
    contact (one slider per flank, sticking or slipping as a whole) cannot show."""
    structure = elastic["reduced"]
    root = fj.PatchDovetailRoot(_flank(elastic["right"]), _flank(elastic["left"]), G, MU, elastic["reduced_load"],
                                normal_load_variation=vary)
    sysm = fj.FrictionSystem(structure, [root], omega=3000.0, excitation=[fj.HarmonicForce(elastic["tip"], force)])
    r = fj.periodic_response(sysm)
    assert r.converged
    frac = _slip_fractions(r, root.n_nodes)
    print(f"{'varying' if vary else 'frozen'} normal loads, tip force {force:g} N: fraction of the cycle "
          f"slipping, nodes bottom to neck: right {np.round(frac[:4], 3)}, left {np.round(frac[4:], 3)}")
    assert list(frac > 0) == slip_pattern
    assert frac.min() == 0.0 and frac.max() > 0.1


@pytest.fixture(scope="module")
def patch_march(elastic):
    """One march of the elastic root on its patches, normal loads varying, from the static state over
    one period (137 events: the run-up's slips and sticks), shared by the two tests below (each
    marched two periods of its own: 18 s and 27 s on a loaded machine, 45 s of the quick subset;
    the shared one period, 12 s): the result with its energy record, and per modal piece with
    friction work, its closed form (response.modal_varying_friction, exponential sums) beside the
    Gauss rule of 8 sub-intervals per period of the fastest mode (response.gauss_pieces)."""
    from frictionjoint.solvers.marcher import response

    root = fj.PatchDovetailRoot(_flank(elastic["right"]), _flank(elastic["left"]), G, MU, elastic["reduced_load"],
                                normal_load_variation=True)
    sysm = fj.FrictionSystem(elastic["reduced"], [root], omega=3000.0,
                             excitation=[fj.HarmonicForce(elastic["tip"], 1600.0)])
    pairs = []
    closed_form = response.modal_varying_friction

    def both(system, itv, a, b):  # the closed form, as the march uses it, and the Gauss rule beside it
        value = closed_form(system, itv, a, b)
        if value is not None and value != 0.0:
            nodes, wts = response.gauss_pieces(itv, a, b)
            xq, vq = itv.state(nodes)
            pairs.append((value, response.varying_friction(system, itv, wts, xq, vq)))
        return value

    response.modal_varying_friction = both
    try:
        r = fj.simulate(sysm, 2 * math.pi / sysm.omega, record=("x", "energy"))
    finally:
        response.modal_varying_friction = closed_form
    return r, np.array(pairs)


def test_energy_balance_of_a_patch(patch_march):
    """The march of the elastic root on its patches, normal loads varying: work = stored change +
    friction + viscous dissipation to 1e-9 of the work done."""
    r = patch_march[0]
    scale = float(np.max(np.abs(r.work)))
    assert r.dissipated_friction[-1] > 1e-3 * scale
    assert float(np.max(np.abs(r.energy_residual()))) <= 1e-9 * scale


# ------------------------------------------------------------ what is refused
def test_refused_static_states_and_bad_input(elastic):
    full, load = elastic["full"], elastic["load"]
    one_flank = fj.PatchDovetailRoot(_flank(elastic["right"]), fj.FlankPatch([("X", "Y")], KN, KT_STUCK),
                                     G, MU, {"Y": FC})
    free = fj.LinearStructure(np.eye(3), np.zeros((3, 3)), dof_names=["X", "Y", "Z"])
    with pytest.raises(ParameterError, match="singular"):
        _rigid_patch(2, KT_STUCK, False).static_state(free)  # Z: nothing holds it
    with pytest.raises(ParameterError, match="dof"):
        one_flank.static_state(_root_block())  # the right flank's nodes are not the block's DOFs
    with pytest.raises(ParameterError, match="two different DOFs"):
        fj.PatchDovetailRoot(fj.FlankPatch([("X", "X")], KN, KT_STUCK), fj.FlankPatch([("X", "Y")], KN, KT_STUCK),
                             G, MU, {"Y": FC}).static_state(_root_block())
    with pytest.raises(ParameterError, match="normal_stiffness"):
        fj.FlankPatch([("X", "Y")] * 2, [KN, -KN], KT_STUCK)
    with pytest.raises(ParameterError, match="at least one node"):
        fj.FlankPatch([], KN, KT_STUCK)
    with pytest.raises(ParameterError, match="centrifugal_load has 3 entries"):
        fj.PatchDovetailRoot(_flank(elastic["right"]), _flank(elastic["left"]), G, MU, [0.0, 1.0, 2.0]).static_state(full)
    with pytest.raises(ParameterError, match="flank_angle"):
        _rigid_patch(1, KT_STUCK, False).replace(flank_angle=2.0)
    assert _rigid_patch(2, KT_STUCK, False).replace(friction_coefficient=0.5).friction_coefficient == 0.5


def test_varying_friction_energy_closed_form_is_the_gauss_rules(patch_march):
    """The friction energy of sliders on contacts, per closed-form piece: the closed form of modal
    pieces (response.modal_varying_friction, exponential sums) against the Gauss rule of 8
    sub-intervals per period of the fastest mode (exact to rounding for such integrands), over
    the march of the elastic root on its patches with varying normal loads (patch_march)."""
    values = patch_march[1]
    assert len(values) > 10
    # closed form against Gauss quadrature, both exact: rounding (measured 8e-15 of the piece's
    # energy once, 1.3e-13 on another run); 1e-10 is over 100x
    assert np.max(np.abs(values[:, 0] - values[:, 1]) / np.abs(values[:, 1])) <= 1e-10

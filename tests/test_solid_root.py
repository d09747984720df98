"""A solid blade on its dovetail (frictionjoint.structures.solid_root) and its model definition
(models/ti64_solid_blade.toml): the root's geometry and loads, the reduced model's static contact
state against the full model's, the parameters a sweep or a study changes, and what is refused.

The accuracy of the dynamics on this model (harmonic balance against the exact steady state, the
reduced model against the unreduced one) is tests/test_solid_blade_model.py's.
"""
import math

import numpy as np
import pytest
import scipy.sparse as sp

from frictionjoint.errors import ParameterError
from frictionjoint.structures import BladeAssembly, FEModel, SolidBlade, load_blade_model
from frictionjoint.structures.solid_root import edge_weights, flank_edges, solid_blade_on_patches

TI64 = dict(youngs_modulus=114e9, poisson_ratio=0.342, density=4430.0)
ROOT = dict(flank_angle=math.radians(30.0), friction_coefficient=0.3, normal_stiffness=2e8,
            tangential_stiffness=1e8, normal_damping=400.0)


def _blade(twist=0.0, n=(10, 2, 1), speed=1000.0):
    return SolidBlade(0.15, 0.03, 0.003, **TI64, twist=twist, n_elements=n, rotor_speed=speed, hub_radius=0.25,
                      rayleigh=(0.0, 2e-6))


@pytest.mark.parametrize("twist", [0.0, 0.35])
def test_centrifugal_load_is_the_body_forces_resultant(twist):
    """The consistent nodal loads of rho Omega^2 (R + x, y, 0): their radial resultant is
    integral rho Omega^2 (R + x) dV, the mass matrix's 1^T M (R + x) (both Gauss rules on the same
    elements, and x is in the elements' space: only rounding differs); untwisted, it is
    m Omega^2 (R + L/2) in closed form (the elements' volume is exact). The chordwise resultant
    vanishes by symmetry; nothing acts along z."""
    b = _blade(twist)
    f = b.centrifugal_load.reshape(-1, 3)
    x = b.nodes[:, 0]
    moment = 1000.0 ** 2 * (b.mass[0::3][:, 0::3] @ (0.25 + x)).sum()
    mass = 4430.0 * 0.15 * 0.03 * 0.003
    expected = mass * 1000.0 ** 2 * (0.25 + 0.075) if twist == 0 else moment
    print(f"radial resultant {f[:, 0].sum():.12g} N, mass matrix's {moment:.12g} N, untwisted closed form "
          f"{mass * 1000.0 ** 2 * (0.25 + 0.075):.12g} N")
    assert abs(f[:, 0].sum() / expected - 1) <= 1e-12 and abs(moment / expected - 1) <= 1e-12
    assert abs(f[:, 1].sum()) <= 1e-12 * expected and np.all(f[:, 2] == 0.0)  # z: assigned zero
    assert np.all(_blade(twist, speed=0.0).centrifugal_load == 0.0)  # assigned zero without rotation


def test_flanks_are_the_root_faces_long_edges():
    b = _blade(0.35)
    right, left = flank_edges(b)
    assert right.size == left.size == 5  # 2 elements across the chord, quadratic: 5 nodes
    for edge, z in ((right, 0.0015), (left, -0.0015)):
        p = b.nodes[edge]
        assert np.allclose(p[:, 0], 0.0, atol=1e-15) and np.allclose(p[:, 2], z, rtol=1e-12)
        assert np.all(np.diff(p[:, 1]) > 0)
    w = edge_weights(5)
    assert np.allclose(w * 12, [1, 4, 2, 4, 1], rtol=1e-15) and abs(w.sum() - 1) <= 1e-15
    with pytest.raises(ParameterError, match="odd number"):
        edge_weights(4)


def test_reduced_static_state_is_the_full_models():
    """The static contact state on the Craig-Bampton model equals the full sparse model's (the
    constraint modes are the interior's static response; the reduced load is T^T f): node loads
    to 1e-9 of the largest, the same slipping set. The full model: the blade with its root face
    held along the chord (u2 removed), as the reduced one."""
    b = _blade(0.35)
    reduced, joint, _ = solid_blade_on_patches(b, ROOT, n_modes=4)
    st = joint.static_state(reduced)
    keep = np.setdiff1d(np.arange(b.n_dof), 3 * b._sets["root"] + 1)
    fe = b.fe_model
    full = FEModel(sp.csr_array(b.mass[keep][:, keep]), sp.csr_array(b.stiffness[keep][:, keep]),
                   dofs=fe.dofs[keep])
    ref = joint.patch_root.replace(centrifugal_load=b.centrifugal_load[keep]).static_state(full)
    err = np.max(np.abs(st.normal_force - ref.normal_force)) / ref.normal_force.max()
    print(f"{st.regime}; node normal loads reduced vs full: {err:.2e}")
    assert err <= 1e-9
    assert np.max(np.abs(st.friction_force - ref.friction_force)) <= 1e-9 * ref.normal_force.max()
    assert np.array_equal(st.slipping, ref.slipping)
    # the flanks carry the centrifugal load and the centrifugal force of the blade's static
    # displacement (the spin softening: K_E and K_G hold no resultant along x), to rounding
    g = ROOT["flank_angle"]
    carried = np.sum(ref.normal_force * math.cos(g) + ref.friction_force * math.sin(g))
    x_rows = np.flatnonzero(fe.dofs[keep][:, 1] == 1)
    expected = (b.centrifugal_load[keep] + b.softening[keep][:, keep] @ ref.displacement)[x_rows].sum()
    print(f"carried {carried:.9g} N = {expected:.9g} N ({b.centrifugal_load[0::3].sum():.9g} N without the "
          "displacement's share)")
    assert abs(carried / expected - 1) <= 1e-9


@pytest.fixture(scope="module")
def solid_model():
    model = load_blade_model("ti64_solid_blade")
    return model, BladeAssembly.from_model(model)


def test_definition_builds_the_blade_on_its_patches(solid_model):
    model, asm = solid_model
    assert model.kind == "solid" and asm.tip.endswith("_u3")
    joint = asm.joints[0]
    assert joint.n_nodes == 18 and asm.structure.n_dof == 2 * 18 + 5 + 1
    st = joint.static_state(asm.structure)
    assert abs(joint.centrifugal_force / model.blade().centrifugal_load[0::3].sum() - 1) <= 1e-15
    print(f"regime {st.regime}; flank normal loads {st.flank_normal_force} N")
    assert np.all(st.normal_force > 0) and abs(st.flank_normal_force[0] / st.flank_normal_force[1] - 1) < 0.1


def test_root_parameters_change_as_a_dovetails(solid_model):
    """with_root takes the point model's names: twice the centrifugal force doubles every node's
    static loads (the run-up's problem is linear and homogeneous for a fixed stick/slip set), a
    flank's stiffness is its nodes' sum, the distribution kept."""
    _, asm = solid_model
    joint = asm.joints[0]
    st = joint.static_state(asm.structure)
    double = asm.with_root(centrifugal_force=2 * joint.centrifugal_force).joints[0]
    st2 = double.static_state(asm.structure)
    assert np.max(np.abs(st2.normal_force - 2 * st.normal_force)) <= 1e-12 * st.normal_force.max()
    stiff = asm.with_root(normal_stiffness=5e8).joints[0]
    right = stiff.flank == 0
    assert abs(stiff.normal_stiffness[right].sum() / 5e8 - 1) <= 1e-14
    assert np.allclose(stiff.normal_stiffness / joint.normal_stiffness, 2.5, rtol=1e-14)
    assert asm.with_root(normal_load_variation=True).joints[0].normal_load_variation
    with pytest.raises(ParameterError, match="not SolidBladeRoot arguments"):
        asm.with_root(flank_half_width=0.005)


def test_bad_definitions_are_refused(tmp_path):
    base = (load_blade_model("ti64_solid_blade").path.read_text())
    cases = [(base.replace('kind = "solid"', 'kind = "shell"'), "kind must be one of"),
             (base.replace('kind = "solid"', 'kind = "solid"\nbending = "flapwise"'), "SolidBlade's arguments"),
             (base.replace("[root]", "[root]\nflank_half_width = 0.005"), "flank_half_width"),
             (base.replace('tip_point = "centre"', 'tip_point = "middle"'), "tip_point must be one of"),
             (base.replace("speed = 1000.0", "speed = 0.0"), "rotor_speed must be > 0")]
    for i, (text, words) in enumerate(cases):
        path = tmp_path / f"bad{i}.toml"
        path.write_text(text)
        with pytest.raises(ParameterError, match=words):
            BladeAssembly.from_model(load_blade_model(path))


def test_a_spinning_blades_exported_matrices_reduce_on_the_flanks():
    """A spinning blade's FE export (stress stiffening and spin softening in K) is indefinite
    until the root is held: FEModel(indefinite_stiffness=True) reduces on the flank nodes as the
    blade itself does (the same matrices: 1e-12) and the reduced structure carries the flag."""
    from frictionjoint.structures import craig_bampton, dof_name

    b = _blade(0.35)
    right, left = flank_edges(b)
    boundary = [dof_name(i + 1, d) for i in np.r_[right, left] for d in (3, 1)]
    boundary += [dof_name(i + 1, 2) for i in b._sets["root"]]  # the slot holds the face along the chord
    fe = b.fe_model
    assert fe.indefinite_stiffness
    a, r = craig_bampton(b, boundary, 4), craig_bampton(fe, boundary, 4)
    assert np.max(np.abs(r.stiffness - a.stiffness)) <= 1e-12 * np.max(np.abs(a.stiffness))
    assert r.indefinite_stiffness and not FEModel(fe.mass, fe.stiffness, dofs=fe.dofs).indefinite_stiffness
    with pytest.raises(ParameterError, match="indefinite_stiffness"):
        FEModel(fe.mass, fe.stiffness, dofs=fe.dofs, indefinite_stiffness=2.5)


@pytest.mark.parametrize("point, y_ref", [("centre", 0.0), ("leading_edge", 0.015), ("trailing_edge", -0.015)])
def test_the_excitation_point_on_the_twisted_tip(point, y_ref):
    """tip_point names a node of the tip face's middle line through the thickness, found on the
    untwisted reference grid: on a blade twisted 0.35 rad it is at (L, y cos t, y sin t) (the twist
    turns the tip face; its coordinates are rounded products of the same cosines: 1e-12)."""
    b = _blade(0.35)
    _, _, tip = solid_blade_on_patches(b, ROOT, n_modes=2, tip_point=point)
    node = int(tip[1:tip.index("_")]) - 1
    expected = [0.15, y_ref * math.cos(0.35), y_ref * math.sin(0.35)]
    assert tip.endswith("_u3") and np.allclose(b.nodes[node], expected, rtol=0, atol=1e-12)

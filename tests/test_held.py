"""HeldPortStructure: exact stepping of a linear structure under harmonic force and held port loads.

References: the stuck Jenkins springs folded into the stiffness matrix (a linear structure with
K + kt I) marched by the library's exact event-driven solver (no events), and the closed-form
undamped single-DOF response to a constant force.
"""
import math

import numpy as np
import pytest

import frictionjoint as fj
from frictionjoint.errors import ParameterError
from frictionjoint.solvers.marcher.held import HeldPortStructure

K = np.array([[2.0, -1.0], [-1.0, 1.0]])
STRUCTURE = fj.LinearStructure(np.eye(2), K, 0.02 * K, dof_names=["x1", "x2"])


@pytest.mark.parametrize("lag", [False, True])
def test_stuck_springs_are_exact_whatever_the_step_and_the_lag(lag):
    """Port loads of linear springs kt (unstressed at 0), evaluated at the current displacement
    or one step late (a Jacobi master): the same motion as K + kt I, to rounding."""
    kt, omega = 1e3, 1.2
    h = 2 * math.pi / omega / 7
    body = HeldPortStructure(STRUCTURE, ["x1", "x2"], [0.0, 1.0], omega=omega)
    ref_structure = fj.LinearStructure(np.eye(2), K + kt * np.eye(2), 0.02 * K, dof_names=["x1", "x2"])
    ref = fj.simulate(fj.FrictionSystem(ref_structure, [], omega=omega, excitation=[fj.HarmonicForce("x2", 1.0)]),
                      40 * h, t_eval=h * np.arange(41), record=("x",))
    r = body.x.copy()
    xs = [body.x.copy()]
    for _ in range(40):
        body.advance(h, kt * r, [kt, kt], r)
        xs.append(body.x.copy())
        r = xs[-2].copy() if lag else body.x.copy()
    err = np.max(np.abs(np.array(xs).T - ref.x)) / np.max(np.abs(ref.x))
    # rounding of 40 exact steps, each an exponential of a matrix of norm ~ sqrt(kt) h = 24, and of
    # the reference's march: measured 1e-11 on one machine, 3.1e-13 on another; 1e-9 is 100x the worst
    assert err < 1e-9


def test_constant_force_closed_form():
    """m x'' + k x = -F (held, no spring): x = -F/k (1 - cos(wn t))."""
    s = fj.LinearStructure(2.0, 8.0, dof_names=["x"])
    body = HeldPortStructure(s, ["x"], omega=1.0)
    for n in range(1, 11):
        body.advance(0.3, [0.5], [0.0], [0.0])
        t = 0.3 * n
        assert body.x[0] == pytest.approx(-0.5 / 8.0 * (1 - math.cos(2.0 * t)), rel=1e-13, abs=1e-16)
        assert body.t == pytest.approx(t, rel=1e-15)


def test_bad_input_names_the_parameter():
    body = HeldPortStructure(STRUCTURE, ["x2"])
    with pytest.raises(ParameterError, match="step"):
        body.advance(0.0, [0.0], [0.0], [0.0])
    with pytest.raises(ParameterError, match=r"stiffness\[0\]"):
        body.advance(0.1, [0.0], [-1.0], [0.0])
    with pytest.raises(ParameterError, match="force"):
        body.advance(0.1, [math.nan], [0.0], [0.0])
    with pytest.raises(ParameterError, match="ports must be distinct"):
        HeldPortStructure(STRUCTURE, ["x1", "x1"])
    with pytest.raises(ParameterError, match="omega"):
        HeldPortStructure(STRUCTURE, ["x1"], omega=0.0)

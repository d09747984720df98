"""The stuck and slipping linear limits (frictionjoint.linear_limits) against closed forms."""
import math

import control
import numpy as np
import pytest

import frictionjoint as fj
from frictionjoint.errors import ParameterError
from frictionjoint.linear_limits import limit_structures, linear_limits


def _frequencies(ss):
    wn, _, _ = control.damp(ss, doprint=False)
    return np.sort(wn)[::2]  # one per complex-conjugate pair of poles


def test_jenkins_oscillator():
    # m x'' + k x + Jenkins(kt): stuck sqrt((k + kt)/m), slipping sqrt(k/m)
    s = fj.FrictionSystem(fj.LinearStructure(2.0, 3.0), [fj.Jenkins(5.0, 0.1, dof=0)])
    lim = linear_limits(s)
    assert _frequencies(lim["stuck"]) == pytest.approx([2.0], rel=1e-12)
    assert _frequencies(lim["slipping"]) == pytest.approx([math.sqrt(1.5)], rel=1e-12)


def test_dovetail_root_stiffness():
    # a rigid blade of mass m on a dovetail (DESIGN section 4): tangentially
    # stuck 2 (kn sin^2 g + kt cos^2 g), slipping 2 kn sin^2 g; radially 2 (kn cos^2 g + kt sin^2 g)
    # and 2 kn cos^2 g
    g, kn, kt, m = math.radians(30.0), 2e8, 1e8, 0.5
    root = fj.DovetailRoot(1e4, g, 0.3, kn, kt, tangential_dof=0, radial_dof=1)
    st = limit_structures(fj.FrictionSystem(fj.LinearStructure(np.eye(2) * m, np.zeros((2, 2))), [root]))
    s, c = math.sin(g), math.cos(g)
    assert np.allclose(st["stuck"].stiffness, np.diag([2 * (kn * s * s + kt * c * c), 2 * (kn * c * c + kt * s * s)]),
                       rtol=1e-12, atol=1e-6)
    assert np.allclose(st["slipping"].stiffness, np.diag([2 * kn * s * s, 2 * kn * c * c]), rtol=1e-12, atol=1e-6)


def test_rigid_sliders_have_no_stuck_limit():
    s = fj.FrictionSystem(fj.LinearStructure(1.0, 1.0), [fj.CoulombSlider(0.1, dof=0)])
    with pytest.raises(ParameterError, match="rigid"):
        linear_limits(s)

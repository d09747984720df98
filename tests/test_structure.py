"""LinearStructure: validation, named DOFs, python-control state space."""
import numpy as np
import pytest

import frictionjoint as fj


def test_statespace_poles_match_natural_frequencies():
    m = np.diag([1.0, 2.0])
    k = np.array([[3.0, -1.0], [-1.0, 2.0]])
    s = fj.LinearStructure(m, k, dof_names=["root", "tip"])
    poles = np.sort(np.abs(s.to_statespace().poles().imag))
    wn = s.natural_frequencies()
    assert np.allclose(poles, np.repeat(wn, 2), rtol=1e-12)
    # generalised eigenproblem by hand: det(K - w^2 M) = 0
    for w in wn:
        assert abs(np.linalg.det(k - w**2 * m)) <= 1e-12 * np.linalg.norm(k) ** 2


def test_dof_names_and_directions():
    s = fj.LinearStructure(np.eye(3), np.eye(3), dof_names=["a", "b", "c"])
    assert s.dof_index("b") == 1
    assert np.array_equal(s.direction(dof="c"), [0.0, 0.0, 1.0])
    with pytest.raises(fj.ParameterError, match="dof"):
        s.dof_index("z")
    with pytest.raises(fj.ParameterError, match="dof_names"):
        fj.LinearStructure(np.eye(2), np.eye(2), dof_names=["a", "a"])


def test_symmetrised_and_read_only():
    s = fj.LinearStructure(np.eye(2), np.array([[2.0, -1.0], [-1.0, 2.0]]))
    with pytest.raises(ValueError):
        s.stiffness[0, 0] = 5.0

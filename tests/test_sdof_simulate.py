"""CoulombOscillator.simulate runs on the closed-form kernel: against the general n-DOF marcher
(the reference, response.simulate on the same system) -- outputs to 1e-12, the same events."""
import math

import numpy as np
import pytest

import frictionjoint as fj
from frictionjoint.solvers.marcher.response import simulate

CASES = [dict(slip_force=0.3, omega=0.8), dict(slip_force=0.5, omega=0.5, damping=0.1),
         dict(slip_force=0.6, omega=2.0, base_amplitude=0.2), dict(slip_force=0.2, omega=1.3),
         dict(slip_force=0.7, omega=0.3, damping=0.05), dict(slip_force=0.0, omega=1.2, damping=0.1),
         dict(slip_force=2.0, omega=1.0)]


@pytest.mark.parametrize("case", CASES)
@pytest.mark.parametrize("start", [(0.0, 0.0), (3.0, -1.0)])
def test_kernel_simulate_matches_the_general_marcher(case, start):
    osc = fj.CoulombOscillator(force_amplitude=1.0, **case)
    t_end = 6 * osc.period
    a = osc.simulate(t_end, *start)
    b = simulate(osc.system, t_end, start[0], start[1])
    scale = max(1.0, float(np.max(np.abs(b.x))))
    assert np.max(np.abs(a.x - b.x[0])) <= 1e-12 * scale
    assert np.max(np.abs(a.v - b.v[0])) <= 1e-12 * scale * max(1.0, osc.omega)
    assert np.max(np.abs(a.friction_force - b.friction_force[0])) <= 1e-12 * max(1.0, osc.slip_force)
    assert a.events.kind == b.events.kind
    assert np.max(np.abs(np.subtract(a.events.time, b.events.time)), initial=0.0) <= 1e-12 * t_end
    assert np.array_equal(a.final_state.status, b.final_state.status)


def test_energy_record_uses_the_reference_and_bad_input_is_refused():
    osc = fj.CoulombOscillator(slip_force=0.3, force_amplitude=1.0, omega=0.8)
    tr = osc.simulate(3 * osc.period, record=("x", "energy"))
    assert np.max(np.abs(tr.energy_residual())) <= 1e-10
    with pytest.raises(fj.ParameterError, match="t_eval"):
        osc.simulate(1.0, t_eval=[0.5, 2.0])
    with pytest.raises(fj.ParameterError, match="t_end"):
        osc.simulate(-1.0)


def test_kernel_simulate_is_faster():
    """Not a timing assertion: the kernel marches without building a configuration; recorded in
    benchmarks/. Here only that both give the same stop count over many periods."""
    osc = fj.CoulombOscillator(slip_force=0.5, force_amplitude=1.0, omega=0.5)
    a = osc.simulate(40 * osc.period, t_eval=[40 * osc.period])
    b = simulate(osc.system, 40 * osc.period, t_eval=[40 * osc.period])
    assert a.events.count("stick") == b.events.count("stick") > 0
    assert math.isclose(a.x[-1], b.x[0, -1], rel_tol=1e-11, abs_tol=1e-12)

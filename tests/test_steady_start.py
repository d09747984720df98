"""Where the exact steady-state search starts (frictionjoint.solvers.steady_state): the harmonic-balance
orbit for large structures, rest otherwise; the same orbit either way."""
import numpy as np
import pytest

import frictionjoint as fj
from benchmarks.chains import chain
from frictionjoint.solvers.steady_state import BALANCE_START_SIZE

BALANCED = "started from the harmonic-balance orbit"


def _close(a, b):
    """Largest amplitude difference relative to the largest amplitude."""
    return float(np.max(np.abs(a.amplitude - b.amplitude)) / np.max(b.amplitude))


def test_large_structure_starts_on_the_balance_and_finds_the_same_orbit():
    system = chain(40, 8)  # state 2 * 40 + 8 = 88 > BALANCE_START_SIZE
    assert 2 * system.n_dof + system.n_sliders > BALANCE_START_SIZE
    auto = fj.periodic_response(system)
    rest = fj.periodic_response(chain(40, 8), start="rest")
    assert auto.converged and rest.converged and auto.unique
    assert BALANCED in auto.message and BALANCED not in rest.message
    # the same orbit: both are fixed points of their own section's map to the tolerance 1e-12 (of
    # the largest displacement), which the map's contraction (0.93 per period) amplifies about 14
    # times; measured 2.2e-15 here, 1.4e-13 at (200, 40)
    assert _close(auto, rest) < 1e-11
    assert auto.periods < rest.periods  # no transient marched
    # the monodromy matrices of two sections of one orbit are similar: the same multipliers
    mu_a, mu_r = (np.max(np.abs(r.floquet_multipliers)) for r in (auto, rest))
    assert abs(mu_a - mu_r) < 1e-8 and auto.stable == rest.stable


def test_small_structure_starts_from_rest():
    system = chain(10, 2)
    assert 2 * system.n_dof + system.n_sliders <= BALANCE_START_SIZE
    res = fj.periodic_response(system)
    assert res.converged and BALANCED not in res.message
    forced = fj.periodic_response(chain(10, 2), start="harmonic_balance")
    assert BALANCED in forced.message and _close(forced, res) < 1e-11  # measured 5.9e-14


def test_a_guess_is_where_the_search_starts():
    system = chain(40, 8)
    ref = fj.periodic_response(system, start="rest")
    n = system.n_dof
    z = ref.initial_state
    again = fj.periodic_response(chain(40, 8), z[:n], z[n:2 * n], z[2 * n:])
    assert again.converged and BALANCED not in again.message and _close(again, ref) < 1e-11


def test_a_stuck_structure_keeps_the_closed_form_from_rest():
    # every joint far from slipping: the balance sticks all over, the stuck orbit from rest is
    # the closed form (its family member with the sliders where they started)
    system = chain(40, 8, slip_ratio=100.0)
    res = fj.periodic_response(system)
    assert res.converged and res.stuck and res.periods == 0.0 and BALANCED not in res.message


def test_bad_start_is_refused():
    system = chain(10, 2)
    with pytest.raises(fj.ParameterError, match="start"):
        fj.periodic_response(system, start="balance")
    with pytest.raises(fj.ParameterError, match="initial guess"):
        fj.periodic_response(system, np.ones(system.n_dof), start="harmonic_balance")

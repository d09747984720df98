"""The one frequency-grid convention (frictionjoint.frequencies) at every public function that takes
frequencies: ``"START:STOP:N"`` or the frequencies themselves; ``(start, stop, n)`` -- a list or
tuple of three numbers whose last is whole -- is refused as ambiguous, with both right forms shown.

References: the grid of ``"START:STOP:N"`` is ``np.linspace(START, STOP, N)`` (the convention's
definition, frictionjoint/frequencies.py); the refusals are the issue's cases (issue 25, section 3:
``sweep("CoulombOscillator", (0.5, 2.5, 60))`` swept 0.5, 2.5 and 60 rad/s, and
``hbm_sweep(system, (0.5, 3.0, 40))`` ran to 40 rad/s).
"""
import numpy as np
import pytest

import frictionjoint as fj
from frictionjoint.errors import ParameterError
from frictionjoint.sweep import oscillator_sweep, system_sweep

PARAMS = dict(mass=1.0, stiffness=1.0, slip_force=0.3, force_amplitude=1.0)
SDOF = fj.LinearStructure([[1.0]], [[1.0]], [[0.02]])


def _jenkins(omega):
    """The Jenkins SDOF of tests/test_hbm.py (m = k = 1, zeta = 1 %, kt = 5, Fs = 0.1, P = 0.2)."""
    return fj.FrictionSystem(SDOF, [fj.Jenkins(5.0, 0.1, dof=0)], omega=omega, excitation=[fj.HarmonicForce(0, 0.2)])


def _refused(call, *words):
    with pytest.raises(ParameterError) as exc:
        call()
    text = str(exc.value)
    assert all(w in text for w in words), text
    return text


def test_omega_range_is_exported_and_is_linspace():
    # the same float operations as np.linspace (the definition): equal bit for bit
    assert np.array_equal(fj.omega_range(0.5, 2.5, 41), np.linspace(0.5, 2.5, 41))
    assert "omega_range" in fj.__all__


@pytest.mark.parametrize("name, call", [
    ("sweep", lambda w: fj.sweep("CoulombOscillator", w, PARAMS)),
    ("oscillator_sweep", lambda w: oscillator_sweep(1.0, 1.0, 0.3, 1.0, w)),
    ("system_sweep", lambda w: system_sweep(_jenkins, w)),
    ("sweep(build)", lambda w: fj.sweep(_jenkins, w)),
    ("regime_map", lambda w: fj.regime_map([0.3], w)),
])
def test_a_three_number_tuple_is_refused_everywhere(name, call):
    """The issue's (0.5, 2.5, 60): three frequencies or 60 of them? Refused before any point runs,
    the message showing the range form and the array form."""
    _refused(lambda: call((0.5, 2.5, 60)), "'0.5:2.5:60'", "[0.5, 2.5, 60.0]")
    _refused(lambda: call([0.5, 2.5, 60]), "'0.5:2.5:60'")


def test_the_range_string_is_the_same_grid_as_its_array():
    by_text = fj.sweep("CoulombOscillator", "0.6:2.0:3", PARAMS)
    by_array = fj.sweep("CoulombOscillator", np.linspace(0.6, 2.0, 3), PARAMS)
    assert np.array_equal(by_text.omega, np.linspace(0.6, 2.0, 3))
    # the same grid, the same deterministic computation: equal bit for bit
    assert np.array_equal(by_text.amplitude, by_array.amplitude)
    sw = system_sweep(_jenkins, "0.8:1.2:3")
    assert np.array_equal(sw.omega, np.linspace(0.8, 1.2, 3))
    rm = fj.regime_map([0.3], "0.8:1.2:3")
    assert np.array_equal(rm.frequency_ratios, np.linspace(0.8, 1.2, 3))


def test_three_frequencies_as_an_array_or_with_a_fractional_last_are_frequencies():
    fr = fj.sweep("CoulombOscillator", np.array([0.6, 1.5, 2.0]), PARAMS)
    assert np.array_equal(fr.omega, [0.6, 1.5, 2.0])
    # a count is an integer: a last number written as a float is a frequency (a study file's
    # [1950.0, 2000.0, 2100.0] is three frequencies)
    fr = fj.sweep("CoulombOscillator", [0.6, 1.5, 2.0], PARAMS)
    assert np.array_equal(fr.omega, [0.6, 1.5, 2.0])
    fr = fj.sweep("CoulombOscillator", (0.6, 1.5, 2.5), PARAMS)  # 2.5 cannot be a count
    assert np.array_equal(fr.omega, [0.6, 1.5, 2.5])


@pytest.mark.parametrize("text, words", [
    ("-1:2.5:10", ["START", "> 0"]),
    ("0.5:2.5", ["START:STOP:N"]),
    ("0.5:2.5:10.5", ["whole number"]),
    ("0.5:2.5:0", ["N must be"]),
    ("0.5:nan:10", ["STOP"]),
])
def test_a_malformed_range_string_is_refused(text, words):
    _refused(lambda: fj.sweep("CoulombOscillator", text, PARAMS), "omegas", *words)


def test_hbm_sweep_refuses_the_ambiguous_tuple():
    """(0.5, 3.0, 40) ran the branch to 40 rad/s (it ended at 55.5)."""
    _refused(lambda: fj.hbm_sweep(_jenkins(1.0), (0.5, 3.0, 40), n_harmonics=1), "'0.5:3.0:40'")
    _refused(lambda: fj.hbm_sweep(_jenkins(1.0), "1.0:1.0:3", n_harmonics=1), "different")
    _refused(lambda: fj.hbm_sweep(_jenkins(1.0), "1.0:1.0:1", n_harmonics=1), "start and an end")


def test_hbm_sweep_takes_the_range_string():
    """'START:STOP:N' runs from START to STOP with n_points = N (the same branch as (START, STOP)
    with n_points=N: the same computation, equal bit for bit); n_points given wins."""
    by_text = fj.hbm_sweep(_jenkins(0.8), "0.8:1.6:15", n_harmonics=1)
    by_ends = fj.hbm_sweep(_jenkins(0.8), (0.8, 1.6), n_harmonics=1, n_points=15)
    assert by_text.omega[0] == 0.8 and by_text.omega[-1] >= 1.6 and by_text.message.startswith("reached")
    assert np.array_equal(by_text.omega, by_ends.omega)
    coarse = fj.hbm_sweep(_jenkins(0.8), "0.8:1.6:15", n_harmonics=1, n_points=4)
    assert coarse.omega.size < by_text.omega.size
    down = fj.hbm_sweep(_jenkins(1.6), "1.6:0.8:15", n_harmonics=1)
    assert down.omega[0] == 1.6 and down.omega[-1] <= 0.8


def test_blade_frequency_response_refuses_the_ambiguous_tuple():
    from frictionjoint.structures import BladeAssembly, load_blade_model

    asm = BladeAssembly.from_model(load_blade_model("ti64_compressor_blade"))
    _refused(lambda: asm.frequency_response((1950.0, 2100.0, 40), method="hbm"), "'1950.0:2100.0:40'")
    _refused(lambda: asm.frequency_response((1950.0, 2100.0, 40)), "'1950.0:2100.0:40'")
    _refused(lambda: fj.sweep("ti64_compressor_blade", (1950.0, 2100.0, 40)), "'1950.0:2100.0:40'")

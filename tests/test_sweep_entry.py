"""frictionjoint.sweep.sweep, the one sweep entry point: the library's oscillator by name, any
Driver, a build(omega) callable for multi-DOF systems; the same algorithm and numbers whatever
drives the oscillator."""

import numpy as np
import pytest

import frictionjoint as fj
from frictionjoint.drivers import Driver, LibraryDriver
from frictionjoint.errors import ParameterError
from frictionjoint.fmi.driver import FMUDriver
from frictionjoint.results import FrequencyResponse, SystemSweep

PARAMS = dict(mass=1.0, stiffness=1.0, slip_force=0.3, force_amplitude=1.0)
OMEGAS = np.array([0.6, 1.5, 2.0])  # an array: a list of three ending in a whole number is ambiguous


class _Counting(LibraryDriver):
    """A user's driver: the library's, counting its restarts and whether it was closed."""

    def __init__(self):
        super().__init__()
        self.starts = 0
        self.closed = False

    def start(self, parameters):
        self.starts += 1
        super().start(parameters)

    def close(self):
        self.closed = True


def test_drivers_satisfy_the_protocol():
    assert isinstance(LibraryDriver(), Driver)
    assert all(hasattr(FMUDriver, m) for m in ("start", "advance", "get", "save", "restore", "close"))


def test_a_driver_of_the_caller_gives_the_same_numbers_and_stays_open():
    by_name = fj.sweep("CoulombOscillator", OMEGAS, PARAMS)
    drv = _Counting()
    mine = fj.sweep(drv, OMEGAS, PARAMS)
    assert isinstance(mine, FrequencyResponse) and mine.status == "ok"
    assert np.array_equal(mine.amplitude, by_name.amplitude) and np.array_equal(mine.phase, by_name.phase)
    assert drv.starts >= len(OMEGAS) and not drv.closed


def test_same_points_as_oscillator_sweep():
    # Den Hartog's closed form is the reference of both (stop-free points): the two routes to the
    # steady state (driver with a period checked, CoulombOscillator.steady_state) agree with it
    a = fj.sweep("CoulombOscillator", OMEGAS, PARAMS)
    b = fj.oscillator_sweep(omegas=OMEGAS, **PARAMS)
    assert np.max(np.abs(a.amplitude - b.amplitude) / b.amplitude) <= 1e-11
    assert a.max_error()[0] <= 1e-11 and b.max_error()[0] <= 1e-11


def test_a_build_callable_sweeps_a_system():
    def build(omega):
        s = fj.LinearStructure.chain(2, damping=0.02)
        return fj.FrictionSystem(s, [fj.Jenkins(0.5, 0.002, dof=1)], omega=omega,
                                 excitation=[fj.HarmonicForce(1, 0.01)])

    out = fj.sweep(build, [0.5, 0.6])
    assert isinstance(out, SystemSweep) and out.success and out.status == "ok"
    assert out.amplitude.shape == (2, 2) and len(out.messages) == 2
    with pytest.raises(ParameterError, match="build"):
        fj.sweep(build, [0.5], PARAMS)


@pytest.mark.parametrize("kwargs, word", [
    (dict(method="hbm"), "method"),
    (dict(model="NoSuchModel"), "model"),
    (dict(model="missing.fmu"), "model"),
    (dict(model=LibraryDriver), "Driver instance"),  # the class passes the Protocol's hasattr check
])
def test_bad_input_names_the_parameter(kwargs, word):
    args = dict(model="CoulombOscillator", omegas=OMEGAS, parameters=PARAMS)
    args.update(kwargs)
    with pytest.raises(ParameterError, match=word):
        fj.sweep(**args)


def test_system_sweep_without_peaks_has_the_same_harmonics():
    """``peaks=False`` (what BladeAssembly.frequency_response and peak_response's refinement use)
    skips locating the displacement peaks: amplitude NaN (but on stuck orbits, whose closed form
    gives it for free), and every other number of the sweep bit for bit the same (harmonics,
    phases, dissipation, stuck, convergence)."""
    from frictionjoint.sweep import system_sweep

    st = fj.LinearStructure(np.diag([1.0, 0.5]), [[3.0, -1.0], [-1.0, 1.0]], 0.02 * np.eye(2))

    def build(w):
        return fj.FrictionSystem(st, [fj.Jenkins(2.0, 0.3, dof=1)], omega=w,
                                 excitation=[fj.HarmonicForce(0, 0.5)])
    ws = [0.5, 0.9, 1.2, 1.8]
    a = system_sweep(build, ws)
    b = system_sweep(build, ws, peaks=False)
    assert np.all(np.isfinite(a.amplitude)) and a.converged.all() and a.stuck.any() and not a.stuck.all()
    assert np.array_equal(a.amplitude[a.stuck], b.amplitude[a.stuck]) and np.all(np.isnan(b.amplitude[~a.stuck]))
    for name in ("harmonic_amplitude", "phase", "dissipated_per_cycle", "stuck", "converged"):
        assert np.array_equal(getattr(a, name), getattr(b, name)), name


@pytest.mark.parametrize("on, off", [(True, False), (1, 0), (1.0, 0.0), ("true", "false"), ("Yes", "no")])
def test_a_blade_switch_from_python_in_every_spelling(on, off):
    """normal_load_variation of a blade sweep's parameters (sweep(model, omegas, parameters) builds
    the blade with blade_assembly): every way of writing a switch (errors.check_bool) reaches the
    root as that switch; bool('false') was True, 1.0 from the CLI was refused."""
    from frictionjoint.sweep import blade_assembly

    assert blade_assembly("ti64_compressor_blade", {"normal_load_variation": on}).joints[0].normal_load_variation is True
    assert blade_assembly("ti64_compressor_blade", {"normal_load_variation": off}).joints[0].normal_load_variation is False


def test_a_blade_switch_that_is_no_switch_is_refused():
    from frictionjoint.sweep import blade_assembly

    for value in (0.5, 2, "maybe"):
        with pytest.raises(ParameterError, match="normal_load_variation"):
            blade_assembly("ti64_compressor_blade", {"normal_load_variation": value})


@pytest.mark.slow
def test_a_point_the_march_refuses_fails_alone_with_the_reason():
    """omega/omega_n = 1e-6: the exact motion sticks and slips about once per natural period (1e6
    events per excitation period), beyond the kernel's event budget and outside its quasi-static
    regime (bound ~1e-6 P0/k, not <= 1e-9 of the amplitude). The point fails with the reason and
    the sweep goes on (it ended in an EventBudgetError traceback after 11 s)."""
    fr = fj.sweep("CoulombOscillator", np.array([1e-6, 0.5]), {"force_amplitude": 1.0, "slip_force": 0.3})
    assert list(fr.converged) == [False, True] and fr.status == "partial"
    assert "too many to march event by event" in fr.messages[0]

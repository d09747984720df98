"""The slaves' declarations (frictionjoint.fmi.slaves): pythonfmu's wrapper constructs a slave anew
at every fmi2Reset, so a slave only records its variables; these tests run the slaves in this
process, without building an FMU."""
import gc
import weakref

import pytest

from frictionjoint.fmi.slaves import CoulombOscillatorSlave, JenkinsJointSlave
from frictionjoint.stepping import OSCILLATOR_OUTPUTS, OSCILLATOR_PARAMETERS

KW = dict(instance_name="test", resources="/nonexistent/resources", logger=0, visible=0)


def _refs(slave):
    return {v.name: v.value_reference for v in slave.vars.values()}


def test_variables_in_declaration_order_with_their_start_values():
    s = CoulombOscillatorSlave(**KW)
    names = list(_refs(s))
    assert names == [*OSCILLATOR_PARAMETERS, "force", *OSCILLATOR_OUTPUTS]
    assert list(_refs(s).values()) == list(range(len(names)))
    starts = {v.name: v.start for v in s.vars.values() if v.name in OSCILLATOR_PARAMETERS}
    assert starts == {k: type(d)(d) for k, (d, _) in OSCILLATOR_PARAMETERS.items()}
    # one table per class and declaration list, shared by every instance
    assert CoulombOscillatorSlave(**KW).vars is s.vars


def test_get_set_through_the_declarations():
    s = JenkinsJointSlave(**KW)
    vr = _refs(s)
    s.set_real([vr["stiffness"], vr["u"]], [250.0, 1e-3])
    assert s.stiffness == 250.0 and s.u == 1e-3
    assert s.get_real([vr["displacement"], vr["stiffness"]]) == [1e-3, 250.0]
    assert s.get_boolean([vr["slipping"]]) == [False]


@pytest.mark.parametrize("call", [
    lambda s, vr: s.get_real([vr["slipping"]]),            # a Boolean read as Real
    lambda s, vr: s.set_boolean([vr["u"]], [True]),        # a Real set as Boolean
    lambda s, vr: s.set_real([vr["force"]], [1.0]),        # an output
])
def test_wrong_type_or_causality_is_a_type_error(call):
    s = JenkinsJointSlave(**KW)
    with pytest.raises(TypeError):
        call(s, _refs(s))


def test_unknown_value_reference_is_a_key_error():
    s = JenkinsJointSlave(**KW)
    for vr in (len(s.vars), -1):  # -1: an unsigned reference >= 2^31 as the C wrapper passes it
        with pytest.raises(KeyError):
            s.get_real([vr])


def test_model_description_attributes():
    # FMI 2.0: parameters initial="exact" with a start; inputs a start, no initial; outputs neither
    import xml.etree.ElementTree as ET

    s = CoulombOscillatorSlave(**KW)
    for v in s.vars.values():
        attrib = ET.fromstring(ET.tostring(v.to_xml())).attrib
        if v.causality.name == "parameter":
            assert attrib.get("initial") == "exact" and v.start is not None, v.name
        elif v.causality.name == "input":
            assert "initial" not in attrib and v.start is not None, v.name
        else:
            assert "initial" not in attrib, v.name


def test_a_slave_is_freed_by_reference_counting():
    # no closures over the instance (pythonfmu's register_variable makes every slave a cycle):
    # the slave a reset replaces is freed at once, not at the next garbage collection
    enabled = gc.isenabled()
    gc.disable()
    try:
        s = CoulombOscillatorSlave(**KW)
        s.get_real([0])
        ref = weakref.ref(s)
        del s
        assert ref() is None
    finally:
        if enabled:
            gc.enable()


def test_a_long_step_skips_whole_periods_of_the_orbit_exactly():
    # The README's case (m = k = P0 = 1, F = 0.5, omega = 1.5: Den Hartog's stop-free motion) on
    # its orbit, one step of 1e7 s (1.6e6 periods; marched event by event it took ~80 s): the
    # state, the peak and the Fourier integrals against Den Hartog's closed form (1931), the
    # integrals by the trapezoid rule on 2^14 phases (spectrally accurate for a periodic, C^1
    # waveform: 1e-9 here)
    import math
    import time

    import numpy as np

    from frictionjoint.analytic import den_hartog

    s = CoulombOscillatorSlave(**KW)
    s.start_on_orbit = s.harmonics = True
    s.setup_experiment(0.0)
    s.exit_initialization_mode()
    w, t_end = 1.5, 1e7
    start = time.perf_counter()
    assert s.do_step(0.0, t_end)
    assert time.perf_counter() - start < 10.0
    dh = den_hartog(w, 0.5)
    phase = w * t_end  # exact in binary floating point; resolved to ulp(1.5e7) = 1.9e-9 rad
    assert abs(s._out("x") - dh.waveform(phase)) <= 1e-8
    assert abs(s._out("v") - dh.waveform(phase, 1)) <= 1e-8
    assert s._out("peak_x") == pytest.approx(dh.amplitude, rel=1e-9)

    def integral(lo, hi, n=2 ** 14):  # int x(t) e^{i w t} dt over the phases [lo, hi]
        phi = np.linspace(lo, hi, n + 1)
        g = dh.waveform(phi) * np.exp(1j * phi)
        return (hi - lo) / n * (g.sum() - 0.5 * (g[0] + g[-1])) / w

    periods = math.floor(phase / (2 * math.pi))
    ref = periods * integral(0.0, 2 * math.pi) + integral(2 * math.pi * periods, phase)
    assert s._out("x_cos_integral") == pytest.approx(ref.real, rel=1e-7, abs=1e-7 * abs(ref))
    assert s._out("x_sin_integral") == pytest.approx(ref.imag, rel=1e-7, abs=1e-7 * abs(ref))
    assert s._out("event_count") == pytest.approx(2 * periods, abs=4)  # two zero-duration stops per period

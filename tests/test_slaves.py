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

"""SSP (System Structure and Parameterization 1.0, Modelica Association) archives of an FMUSystem.

:func:`write_ssp` writes ``SystemStructure.ssd`` with one component per FMU component, the
connectors used by the connections, the connections, and the parameter values as one inline
parameter set (``ssv:ParameterSet``, named :data:`PARAMETER_SET`), and packs it with the FMUs
(``resources/``) into a ``.ssp`` zip archive. Ecos applies a parameter set only when it is
named on its command line (``--parameterSet initialValues``) or to ``EcosSimulation.init``.

The run's start and stop time go into the SSD's ``DefaultExperiment`` (SSP 1.0 has no step size:
OpenModelica's OMSimulator runs from 0 to 1 s without one). The communication step goes where
OMSimulator reads it, its vendor annotation of the system (``org.openmodelica``:
``oms:SimulationInformation`` / ``oms:FixedStepMaster``, its fixed-step master ``oms-ma``, as
OMSimulator 3.0 writes and reads it in ``SystemWC.cpp``); other hosts ignore annotations they do
not know.
"""
from __future__ import annotations

import math
import xml.etree.ElementTree as ET
import zipfile
from pathlib import Path

from ..errors import ParameterError
from .ports import split_port

__all__ = ["PARAMETER_SET", "write_ssp"]

PARAMETER_SET = "initialValues"
_NS = {"ssd": "http://ssp-standard.org/SSP1/SystemStructureDescription",
       "ssc": "http://ssp-standard.org/SSP1/SystemStructureCommon",
       "ssv": "http://ssp-standard.org/SSP1/SystemStructureParameterValues",
       "oms": "https://raw.githubusercontent.com/OpenModelica/OMSimulator/master/schema/oms.xsd"}
#: a model variable's type (fmpy: FMI 2's, or FMI 3's) -> the SSP 1.0 connector and parameter type
_TYPES = {"Real": "Real", "Integer": "Integer", "Boolean": "Boolean", "String": "String",
          "Float64": "Real", "Float32": "Real", "Int32": "Integer"}


def _el(parent, tag, **attrib):
    prefix, name = tag.split(":")
    return ET.SubElement(parent, f"{{{_NS[prefix]}}}{name}", {k: str(v) for k, v in attrib.items()})


def _value(kind: str, value) -> str:
    if kind == "Real":
        return repr(float(value))  # shortest round-trip form: the exact double
    if kind == "Integer":
        return str(int(value))
    if kind == "Boolean":
        return "true" if value else "false"
    return str(value)


def write_ssp(system, path, name: str = "system", start_time: float = 0.0, stop_time: float | None = None,
              step: float | None = None) -> Path:
    """Write ``system`` (:class:`~frictionjoint.fmi.cosim.FMUSystem`) as an SSP archive.

    Parameters
    ----------
    system : FMUSystem
    path : path
        The ``.ssp`` file to write.
    name : str
        Name of the system in the SSD.
    start_time, stop_time : float
        The default experiment [s] (``DefaultExperiment``); without ``stop_time`` a host picks its
        own (OMSimulator: 1 s).
    step : float, optional
        Communication step [s] > 0 for a fixed-step host (OMSimulator's annotation, see the module
        docstring).

    Returns
    -------
    Path
    """
    start_time = float(start_time)
    if not math.isfinite(start_time):
        raise ParameterError(f"start_time must be finite, got {start_time!r}")
    if stop_time is not None and not (math.isfinite(stop_time) and stop_time > start_time):
        raise ParameterError(f"stop_time must be finite and > start_time = {start_time}, got {stop_time!r}")
    if step is not None and not (math.isfinite(step) and step > 0):
        raise ParameterError(f"step must be finite and > 0 [s], got {step!r}")
    for prefix, uri in _NS.items():
        ET.register_namespace(prefix, uri)
    root = ET.Element(f"{{{_NS['ssd']}}}SystemStructureDescription", {"name": name, "version": "1.0"})
    sys_el = _el(root, "ssd:System", name=name)
    elements = _el(sys_el, "ssd:Elements")
    used = {}
    for source, target in system.connections:
        for port, kind in ((source, "output"), (target, "input")):
            comp, var = split_port(port)
            used.setdefault(comp, {})[var] = kind
    sources = {}  # FMU file -> its name in the archive (one copy however many components use it)
    for fmu in dict.fromkeys(p.resolve() for p in system.components.values()):
        arcname = f"resources/{fmu.name}"
        sources[fmu] = arcname if arcname not in sources.values() else f"resources/{len(sources)}_{fmu.name}"
    for comp, fmu in system.components.items():
        c = _el(elements, "ssd:Component", name=comp, source=sources[fmu.resolve()],
                type="application/x-fmu-sharedlibrary")
        if comp in used:
            connectors = _el(c, "ssd:Connectors")
            for var, kind in used[comp].items():
                con = _el(connectors, "ssd:Connector", name=var, kind=kind)
                _el(con, f"ssc:{_TYPES[system.variable(f'{comp}.{var}').type]}")
        values = system.parameters.get(comp)
        if values:
            binding = _el(_el(c, "ssd:ParameterBindings"), "ssd:ParameterBinding")
            pset = _el(_el(binding, "ssd:ParameterValues"), "ssv:ParameterSet", version="1.0", name=PARAMETER_SET)
            params = _el(pset, "ssv:Parameters")
            for var, value in values.items():
                kind = _TYPES[system.variable(f"{comp}.{var}").type]
                _el(_el(params, "ssv:Parameter", name=var), f"ssv:{kind}", value=_value(kind, value))
    if system.connections:
        conns = _el(sys_el, "ssd:Connections")
        for source, target in system.connections:
            (sc, sv), (tc, tv) = split_port(source), split_port(target)
            _el(conns, "ssd:Connection", startElement=sc, startConnector=sv, endElement=tc, endConnector=tv)
    if step is not None:  # OMSimulator's fixed-step master and its step
        note = _el(_el(sys_el, "ssd:Annotations"), "ssc:Annotation", type="org.openmodelica")
        info = _el(_el(note, "oms:Annotations"), "oms:SimulationInformation")
        _el(info, "oms:FixedStepMaster", description="oms-ma", stepSize=repr(float(step)), relativeTolerance="0.0001")
    experiment = {"startTime": repr(start_time)}
    if stop_time is not None:
        experiment["stopTime"] = repr(float(stop_time))
    _el(root, "ssd:DefaultExperiment", **experiment)
    ET.indent(root)
    path = Path(path)
    with zipfile.ZipFile(path, "w", zipfile.ZIP_DEFLATED) as z:
        z.writestr("SystemStructure.ssd", ET.tostring(root, encoding="UTF-8", xml_declaration=True))
        for fmu, arcname in sources.items():
            z.write(fmu, arcname)
    return path

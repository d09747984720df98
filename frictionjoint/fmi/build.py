"""Build the FMUs with pythonfmu (FMI 2.0) or pythonfmu3 (FMI 3.0), post-process their model
descriptions, validate with fmpy.

The library is bundled into each FMU's ``resources/`` under the name ``_frictionjoint_bundle`` (one
zip archive) with its identity, so an FMU needs only Python with numpy and scipy at run time and a host's own
``frictionjoint`` can neither shadow it nor be shadowed by it; where the host's installed
``frictionjoint`` is the very same library (the same identity), the FMU runs that one, with its
compiled kernels (:mod:`.bundle_loader`).

FMI 3.0 (``fmi_version=3``, :data:`FMUS3`): the oscillator and the displacement-driven joints as
``<name>Fmi3.fmu`` -- a model identifier of their own, so that an FMI 2 and an FMI 3 FMU of one model
can sit in one host (one shared library name per identifier on Windows, one name per component in
an SSP) -- and friction systems (``systems=``) as ``<system name>Fmi3.fmu`` (model identifier
``FrictionSystemFmi3``, as the FMI 2 ones' is ``FrictionSystem``), with early return at their stick/slip events (:mod:`.slaves3`). Early return needs
pythonfmu3's wrapper patched (``fmi3_wrapper/early_return.patch``); the package ships that binary for
x86_64-linux only (``fmi3_wrapper/build_wrapper.py`` rebuilds it). Such an FMU carries that binary
alone and declares ``mightReturnEarlyFromDoStep`` and ``hasEventMode``; with ``early_return=False`` it
carries pythonfmu3's stock binaries (x86_64-linux and x86_64-windows), declares neither and its
steps are whole.
"""
from __future__ import annotations

import contextlib
import shutil
import sys
import tempfile
import xml.etree.ElementTree as ET
import zipfile
from pathlib import Path

from .bundle_loader import ARCHIVE, BUNDLE, EXCLUDED, IDENTITY, identity

__all__ = ["FMUS", "FMUS3", "FMUS_ME", "FMUS_ME3", "INTERFACES", "FMI2_BINARIES", "FMI3_BINARIES", "BLADE_MODELS", "BLADE_SCRIPT", "BUNDLE_NAME", "STRUCTURE_SCRIPT", "SYSTEM_SCRIPT",
           "SYSTEM_SCRIPT3", "STRUCTURE_SCRIPT_ME", "SYSTEM_SCRIPT_ME",
           "STRUCTURE_SCRIPT_ME3", "SYSTEM_SCRIPT_ME3", "build_fmus", "postprocess",
           "validate", "default_source_dir"]

BUNDLE_NAME = BUNDLE  # the name the FMU scripts and their loader import
#: FMU name -> script in the FMU source folder (unique module names: see DESIGN.md 5)
FMUS = {
    "CoulombOscillator": "fj_coulomb_oscillator_fmu.py",
    "JenkinsJoint": "fj_jenkins_joint_fmu.py",
    "IwanJoint": "fj_iwan_joint_fmu.py",
    "MicroslipJoint": "fj_microslip_joint_fmu.py",
    "DovetailRoot": "fj_dovetail_root_fmu.py",
    "BladeDovetail": "fj_blade_dovetail_fmu.py",
}
#: FMI 3.0 FMUs (``fmi_version=3``): FMU name (as in :data:`FMUS`) -> script; built as ``<name>Fmi3.fmu``
FMUS3 = {
    "CoulombOscillator": "fj3_coulomb_oscillator_fmu.py",
    "JenkinsJoint": "fj3_jenkins_joint_fmu.py",
    "IwanJoint": "fj3_iwan_joint_fmu.py",
    "MicroslipJoint": "fj3_microslip_joint_fmu.py",
}
#: Model Exchange FMUs (``interface="model-exchange"`` or ``"both"``): FMU name -> script (FMI 2.0, on the
#: fixed wrapper: ``fmi2_wrapper/fix.patch``); built as ``<name>ME.fmu`` (model identifier ``<name>ME``),
#: with the structures and systems as ``<name>ME.fmu`` (:data:`STRUCTURE_SCRIPT_ME`, :data:`SYSTEM_SCRIPT_ME`)
FMUS_ME = {
    "CoulombOscillator": "fj_coulomb_oscillator_me_fmu.py",
    "JenkinsJoint": "fj_jenkins_joint_me_fmu.py",
    "IwanJoint": "fj_iwan_joint_me_fmu.py",
    "MicroslipJoint": "fj_microslip_joint_me_fmu.py",
}
#: FMI 3.0 Model Exchange FMUs (``fmi_version=3``): FMU name -> script; built as ``<name>MEFmi3.fmu``
FMUS_ME3 = {
    "CoulombOscillator": "fj3_coulomb_oscillator_me_fmu.py",
    "JenkinsJoint": "fj3_jenkins_joint_me_fmu.py",
    "IwanJoint": "fj3_iwan_joint_me_fmu.py",
    "MicroslipJoint": "fj3_microslip_joint_me_fmu.py",
}
#: the script of a Model Exchange structure FMU (model identifier ``LinearStructureME``; FMI 3.0:
#: ``..._ME3``, ``LinearStructureMEFmi3``)
STRUCTURE_SCRIPT_ME = "fj_linear_structure_me_fmu.py"
STRUCTURE_SCRIPT_ME3 = "fj3_linear_structure_me_fmu.py"
#: the script of a Model Exchange friction system FMU (model identifier ``FrictionSystemME``; FMI 3.0:
#: ``..._ME3``, ``FrictionSystemMEFmi3``)
SYSTEM_SCRIPT_ME = "fj_friction_system_me_fmu.py"
SYSTEM_SCRIPT_ME3 = "fj3_friction_system_me_fmu.py"
#: the interfaces :func:`build_fmus` builds: name -> (co-simulation, model exchange)
INTERFACES = {"co-simulation": (True, False), "model-exchange": (False, True), "both": (True, True)}
#: pythonfmu's wrapper with frictionjoint's fixes (``fmi2_wrapper/fix.patch``: never a NULL log category,
#: errors reported whatever the debug logging, a Python exception fmi2Error, reference counts):
#: FMI 2 platform -> binary; the other platforms keep pythonfmu's stock binary
FMI2_BINARIES = {"linux64": Path(__file__).resolve().parent / "fmi2_wrapper" / "binaries" / "x86_64-linux"
                 / "libpythonfmu-export.so"}
#: pythonfmu3's wrapper with early return (``fmi3_wrapper/early_return.patch``): FMI 3 platform -> binary
FMI3_BINARIES = {"x86_64-linux": Path(__file__).resolve().parent / "fmi3_wrapper" / "binaries" / "x86_64-linux"
                 / "libpythonfmu-export.so"}
#: FMUs that carry a blade model definition in their resources: FMU name -> the definition
#: (a name in the repository's ``models/``); ``build_fmus(blades=...)`` builds one such FMU per
#: definition, beam or solid (e.g. ``blades=["ti64_solid_blade"]``: ``Ti64SolidBlade.fmu``)
BLADE_MODELS = {"BladeDovetail": "ti64_compressor_blade"}
#: the FMU script of every blade FMU: one slave for every definition, which it reads from its resources
BLADE_SCRIPT = FMUS["BladeDovetail"]
#: the script of LinearStructure.fmu (one per structure definition, built by ``structures=``)
STRUCTURE_SCRIPT = "fj_linear_structure_fmu.py"
#: the script of a friction system FMU (one per system definition, built by ``systems=``)
SYSTEM_SCRIPT = "fj_friction_system_fmu.py"
#: the script of an FMI 3.0 friction system FMU (``systems=`` with ``fmi_version=3``)
SYSTEM_SCRIPT3 = "fj3_friction_system_fmu.py"


def default_source_dir() -> Path:
    """The repository's ``fmus/`` folder (next to the package)."""
    return Path(__file__).resolve().parents[2] / "fmus"


def _bundle(tmp: Path) -> list:
    """The project files every FMU carries: the library as the package :data:`BUNDLE_NAME` in one
    zip archive (:data:`.bundle_loader.ARCHIVE`, imported by ``zipimport``) with its identity
    (:func:`.bundle_loader.identity`, by which an FMU runs the installed library where that is the
    same) and its bytecode, and its loader (:mod:`.bundle_loader` as the top-level module
    ``_frictionjoint_loader``, which each FMU script asks for the library).

    One archive, not a folder of ~90 files: a host unpacks the FMU at every load and deletes the
    folder when it frees it, which cost 40-150 ms per load for the folder (and ~130 ms more to compile
    its sources at the import, where ``PYTHONDONTWRITEBYTECODE`` is set or the folder is read-only).
    The bytecode is checked-hash (valid where the source is byte for byte the same, whatever the
    unpacking's file times) for the building Python's version; another version compiles the sources.
    """
    import compileall
    import json
    import py_compile

    src = Path(__file__).resolve().parents[1]
    staged = tmp / "bundle" / BUNDLE_NAME
    shutil.copytree(src, staged, ignore=shutil.ignore_patterns(*EXCLUDED))
    (staged / IDENTITY).write_text(json.dumps(identity(str(staged))), encoding="utf-8")
    # zipimport reads a module's bytecode beside its source (module.pyc), not from __pycache__
    compileall.compile_dir(str(staged), quiet=2, legacy=True,
                           invalidation_mode=py_compile.PycInvalidationMode.CHECKED_HASH)
    archive = tmp / ARCHIVE
    with zipfile.ZipFile(archive, "w", zipfile.ZIP_DEFLATED) as z:
        for f in sorted(staged.rglob("*")):
            if f.is_file():
                z.write(f, arcname=f.relative_to(staged.parent).as_posix())
    loader = tmp / "_frictionjoint_loader.py"
    shutil.copyfile(Path(__file__).with_name("bundle_loader.py"), loader)
    return [archive, loader]


def postprocess(fmu: Path, description: str | None = None) -> None:
    """Add ``<InitialUnknowns>`` (the outputs, and a Model Exchange FMU's states and derivatives) to the
    model structure, which pythonfmu omits; make a Model Exchange FMU's description Model Exchange only
    (the builder's flags moved to ``ModelExchange``, ``CoSimulation`` dropped); keeping
    the outputs' ``dependencies`` the slave wrote; with ``description``, write it as the model's
    (pythonfmu writes the slave class's); put the fixed wrapper (:data:`FMI2_BINARIES`) in place of
    pythonfmu's x86_64-linux binary."""
    fmu = Path(fmu)
    with zipfile.ZipFile(fmu) as z:
        items = {name: z.read(name) for name in z.namelist()}
    root = ET.fromstring(items["modelDescription.xml"])
    if description is not None:
        root.set("description", description)
    variables = root.find("ModelVariables").findall("ScalarVariable")
    outputs = [i + 1 for i, v in enumerate(variables) if v.get("causality") == "output"]
    structure = root.find("ModelStructure")
    if structure is None:
        structure = ET.SubElement(root, "ModelStructure")
    # a Model Exchange FMU (frictionjoint.fmi.model_exchange): its states and their derivatives too
    derivatives = [int(u.get("index")) for u in structure.iterfind("Derivatives/Unknown")]
    states = [int(variables[i - 1].find("Real").get("derivative")) for i in derivatives]
    initial = sorted(set(outputs) | set(derivatives) | {i for i in states
                                                         if variables[i - 1].get("causality") == "local"})
    # each output's dependencies as the slave declared them (frictionjoint.fmi.slaves._Slave.to_xml)
    declared = {u.get("index"): u.get("dependencies") for u in structure.iterfind("Outputs/Unknown")}
    for tag in ("Outputs", "InitialUnknowns"):
        old = structure.find(tag)
        if old is not None:
            structure.remove(old)
    outs = ET.Element("Outputs")
    init = ET.Element("InitialUnknowns")
    for idx in outputs:
        unknown = ET.SubElement(outs, "Unknown", index=str(idx))
        if declared.get(str(idx)) is not None:
            unknown.set("dependencies", declared[str(idx)])
    for idx in initial:
        ET.SubElement(init, "Unknown", index=str(idx))
    structure.insert(0, outs)
    # Outputs, Derivatives, InitialUnknowns: keep the schema order
    structure.append(init)
    interface = root.find("CoSimulation")
    me = root.find("ModelExchange")
    if me is not None:  # Model Exchange only: the fixed wrapper alone has its functions (fix.patch, 6)
        for key in ("needsExecutionTool", "canBeInstantiatedOnlyOncePerProcess", "canNotUseMemoryManagementFunctions",
                    "canGetAndSetFMUstate", "canSerializeFMUstate", "providesDirectionalDerivative"):
            if interface.get(key) is not None:
                me.set(key, interface.get(key))
        root.remove(interface)
        interface = me
        items = {name: data for name, data in items.items() if not name.startswith("binaries/")}
    items["modelDescription.xml"] = ET.tostring(root, encoding="UTF-8", xml_declaration=True)
    ident = interface.get("modelIdentifier")
    for platform, binary in FMI2_BINARIES.items():  # the fixed wrapper in place of pythonfmu's
        if not binary.is_file():
            raise FileNotFoundError(f"the fixed FMI 2 wrapper {binary} is missing (see fmi2_wrapper/build_wrapper.py)")
        items[f"binaries/{platform}/{ident}.so"] = binary.read_bytes()
    _rewrite(fmu, items)


def postprocess3(fmu: Path, early_return: bool = True) -> None:
    """An FMI 3 FMU's capability flags (pythonfmu3 0.3.4 writes ``canHandleVariableCommunicationStepSize``
    with the value of the option before it), and with ``early_return`` the patched wrapper: its
    x86_64-linux binary (:data:`FMI3_BINARIES`) replaces pythonfmu3's binaries, ``sources/`` get the
    patch, and the FMU declares ``mightReturnEarlyFromDoStep`` and ``hasEventMode``; without, pythonfmu3's
    binaries stay and neither is declared. A Model Exchange FMU (its model description has a
    ``ModelExchange`` element: :mod:`.slaves3`'s ``*SlaveME3``) keeps that interface alone (pythonfmu3
    also writes ``CoSimulation`` for the base class) and always carries the patched wrapper."""
    from .fmi3_wrapper.build_wrapper import PATCH, apply_patch

    fmu = Path(fmu)
    with zipfile.ZipFile(fmu) as z:
        items = {name: z.read(name) for name in z.namelist()}
    root = ET.fromstring(items["modelDescription.xml"])
    cs = root.find("CoSimulation")
    flags = dict(needsExecutionTool="false", canBeInstantiatedOnlyOncePerProcess="false",
                 canGetAndSetFMUState="true", canSerializeFMUState="true")
    me = root.find("ModelExchange")
    if me is not None:
        root.remove(cs)
        cs, early_return = me, True
        flags["needsCompletedIntegratorStep"] = "false"
    else:
        flags.update(canHandleVariableCommunicationStepSize="true",
                     mightReturnEarlyFromDoStep=str(early_return).lower(), hasEventMode=str(early_return).lower())
    for key, value in flags.items():
        cs.set(key, value)
    items["modelDescription.xml"] = ET.tostring(root, encoding="UTF-8", xml_declaration=True)
    if early_return:
        ident = cs.get("modelIdentifier")
        items = {name: data for name, data in items.items() if not name.startswith("binaries/")}
        for platform, binary in FMI3_BINARIES.items():
            if not binary.is_file():
                raise FileNotFoundError(f"the patched FMI 3 wrapper {binary} is missing (see "
                                        "fmi3_wrapper/build_wrapper.py; early_return=False builds without it)")
            items[f"binaries/{platform}/{ident}.so"] = binary.read_bytes()
        with tempfile.TemporaryDirectory(prefix="frictionjoint_fmi3_src_") as tmpd:
            src = Path(tmpd)
            names = [n for n in items if n.startswith("sources/src/") and not n.endswith("/")]
            for name in names:
                (src / name).parent.mkdir(parents=True, exist_ok=True)
                (src / name).write_bytes(items[name])
            apply_patch(PATCH, src / "sources" / "src")
            for name in names:
                items[name] = (src / name).read_bytes()
    _rewrite(fmu, items)


def _rewrite(fmu: Path, items: dict) -> None:
    """Write ``items`` (archive name -> bytes) as the FMU ``fmu``, replacing it."""
    tmp = fmu.with_suffix(".tmp")
    with zipfile.ZipFile(tmp, "w", zipfile.ZIP_DEFLATED) as z:
        for name, data in items.items():
            z.writestr(name, data)
    tmp.replace(fmu)


def validate(fmu: Path) -> list[str]:
    """Problems reported by :func:`fmpy.validation.validate_fmu` (empty when valid)."""
    from fmpy.validation import validate_fmu

    return list(validate_fmu(str(fmu)))


def build_fmus(out_dir, names=None, source_dir=None, check: bool = True, structures=(), systems=(),
               fmi_version: int = 2, early_return: bool = True, blades=(),
               interface: str = "co-simulation") -> list[Path]:
    """Build, post-process and (optionally) validate the FMUs.

    Parameters
    ----------
    out_dir : path
        Folder for the ``.fmu`` files (created).
    names : sequence of str, optional
        Which of :data:`FMUS` to build; all by default, none when ``structures``, ``systems`` or
        ``blades`` are given.
    source_dir : path, optional
        Folder of the FMU scripts; the repository's ``fmus/`` by default.
    check : bool
        Validate each FMU and raise :class:`~frictionjoint.errors.FMUError` (a ``RuntimeError``)
        listing the problems.
    structures : sequence of path or StructureDefinition
        Structure definitions (:mod:`frictionjoint.structure_file`): each becomes
        ``<name>.fmu``, a ``LinearStructure`` FMU carrying the definition in its resources.
    systems : sequence of path or SystemDefinition
        System definitions (:mod:`frictionjoint.system_file`): each becomes ``<name>.fmu``, one FMU
        of the whole friction system (:mod:`frictionjoint.fmi.system_slave`) carrying the
        definition in its resources.
    fmi_version : {2, 3}
        3: the FMI 3.0 FMUs of :data:`FMUS3` (``names`` among them) and of ``systems``, as
        ``<name>Fmi3.fmu``; structures and blades are FMI 2 only.
    early_return : bool
        FMI 3: early return at events with the patched wrapper (x86_64-linux); False: pythonfmu3's stock
        binaries, whole steps (see the module docstring).
    blades : sequence of str or path
        Blade model definitions, beam or solid (:func:`~frictionjoint.structures.load_blade_model`):
        each becomes ``<name>.fmu``, the blade FMU (:data:`BLADE_SCRIPT`, model identifier
        ``BladeDovetail``) carrying it in its resources (:func:`_blade_jobs`).
    interface : {"co-simulation", "model-exchange", "both"}
        Which FMUs: co-simulation, Model Exchange (the FMUs of :data:`FMUS_ME`, the structures and the
        systems as ``<name>ME.fmu``, FMI 3.0: ``<name>MEFmi3.fmu``; :mod:`frictionjoint.fmi.model_exchange`;
        the blades and the dovetail root have no Model Exchange form), or both; each of ``fmi_version``.

    Returns
    -------
    list of Path
    """
    from ..structure_file import StructureDefinition, load_structure_definition

    out = Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)
    source = Path(source_dir) if source_dir is not None else default_source_dir()
    from ..system_file import SystemDefinition, load_system_definition

    if interface not in INTERFACES:
        raise ValueError(f"interface must be one of {sorted(INTERFACES)}, got {interface!r}")
    cosim, model_exchange = INTERFACES[interface]
    if blades and not cosim:
        raise ValueError("blades have no Model Exchange form: interface='co-simulation' or 'both'")
    structures = [s if isinstance(s, StructureDefinition) else load_structure_definition(s) for s in structures]
    systems = [s if isinstance(s, SystemDefinition) else load_system_definition(s) for s in systems]
    requested = names
    names = _names(names, [*structures, *blades], systems, fmi_version) if cosim else []
    names_me = _names_me(requested, structures, systems, strict=not cosim) if model_exchange else []
    built = []
    with tempfile.TemporaryDirectory(prefix="frictionjoint_fmu_") as tmpd, _builder_imports(Path(tmpd)) as tmp:
        bundle = _bundle(tmp)
        jobs = []
        if cosim:
            jobs += [(3, *j) for j in _jobs3(names, systems, out, tmp, bundle)] if fmi_version == 3 else [
                (2, *j) for j in _jobs(names, structures, systems, out, tmp, bundle)
                + _blade_jobs(blades, out, tmp, bundle)]
        jobs += [(fmi_version, *j) for j in _jobs_me(names_me, structures if model_exchange else (),
                                                     systems if model_exchange else (), out, tmp, bundle,
                                                     fmi_version)]
        for version, script_name, dest, project_files, *description in jobs:
            built.append(_build_one(source / script_name, dest, project_files, check, version, early_return,
                                    *description))
    return built


@contextlib.contextmanager
def _builder_imports(tmp: Path):
    """The builders' imports kept apart from this process's: ``tmp`` (the bundle's folder) on
    ``sys.path`` while they run. The builder imports each script, and so the bundle: a bundle this
    process has loaded from an FMU it runs (it may be another version, its folder may be gone) is
    set aside and given back afterwards, for those FMUs. pythonfmu's builder imports each FMU
    script as a top-level module (fj_*_fmu) and leaves it in ``sys.modules``: those are set aside
    too, and the builder's dropped afterwards, else an FMU loaded later in this process would reuse
    the build's script, bound to the removed build bundle."""
    def ours(m):
        return m == BUNDLE_NAME or m.startswith(BUNDLE_NAME + ".") or m in _SCRIPTS
    loaded = {m: sys.modules.pop(m) for m in list(sys.modules) if ours(m)}
    sys.path.insert(0, str(tmp))
    try:
        yield tmp
    finally:
        sys.path.remove(str(tmp))
        for mod in [m for m in sys.modules if ours(m)]:
            del sys.modules[mod]
        sys.modules.update(loaded)


#: the module names of the FMU scripts (pythonfmu's builder imports each as a top-level module)
_SCRIPTS = {Path(f).stem for f in (*FMUS.values(), *FMUS3.values(), *FMUS_ME.values(), *FMUS_ME3.values(),
                                   STRUCTURE_SCRIPT, SYSTEM_SCRIPT, SYSTEM_SCRIPT3, STRUCTURE_SCRIPT_ME,
                                   SYSTEM_SCRIPT_ME, STRUCTURE_SCRIPT_ME3, SYSTEM_SCRIPT_ME3)}


def _names(names, structures, systems, fmi_version: int) -> list:
    """The names of :data:`FMUS` (``fmi_version`` 3: :data:`FMUS3`) to build (see :func:`build_fmus`)."""
    if fmi_version not in (2, 3):
        raise ValueError(f"fmi_version must be 2 or 3, got {fmi_version!r}")
    if fmi_version == 3 and structures:
        raise ValueError("structures and blades are built as FMI 2.0 FMUs only (fmi_version=2)")
    table = FMUS3 if fmi_version == 3 else FMUS
    names = ([] if structures or systems else list(table)) if names is None else list(names)
    for n in names:
        if n not in table:
            raise ValueError(f"names must be among {sorted(table)} for fmi_version={fmi_version}, got {n!r}")
    return names


def _names_me(names, structures, systems, strict: bool) -> list:
    """The names of :data:`FMUS_ME` to build: all by default (none when ``structures`` or ``systems``
    are given); of ``names`` those in the table (``strict``: every one, else a ValueError)."""
    if names is None:
        return [] if structures or systems else list(FMUS_ME)
    if strict:
        for n in names:
            if n not in FMUS_ME:
                raise ValueError(f"names must be among {sorted(FMUS_ME)} for Model Exchange, got {n!r}")
    return [n for n in names if n in FMUS_ME]


def _fmi3_files(tmp: Path, bundle: list) -> list:
    """The bundle and pythonfmu's Python sources (the FMI 3 slaves bind the FMI 2 ones, which import
    pythonfmu; pythonfmu3 puts its own into every FMU, as pythonfmu does into the FMI 2 ones), so that
    an FMU needs no pythonfmu installed; copied into ``tmp`` once."""
    import pythonfmu

    pkg = tmp / "fmi3" / "pythonfmu"
    if not pkg.is_dir():
        pkg.mkdir(parents=True)
        for f in Path(pythonfmu.__file__).parent.glob("*.py"):
            shutil.copy2(f, pkg)
    return [*bundle, pkg]


def _jobs_me(names, structures, systems, out: Path, tmp: Path, bundle: list, fmi_version: int = 2) -> list:
    """The jobs of the Model Exchange FMUs: the named ones, one per structure definition and one per
    system definition, each ``<name>ME.fmu`` (FMI 3.0: ``<name>MEFmi3.fmu``)."""
    from .slaves import STRUCTURE_RESOURCE

    if fmi_version == 3:
        files, table, suffix = _fmi3_files(tmp, bundle), FMUS_ME3, "MEFmi3"
        structure_script, system_script = STRUCTURE_SCRIPT_ME3, SYSTEM_SCRIPT_ME3
    else:
        files, table, suffix = list(bundle), FMUS_ME, "ME"
        structure_script, system_script = STRUCTURE_SCRIPT_ME, SYSTEM_SCRIPT_ME
    jobs = [(table[n], out / f"{n}{suffix}.fmu", files) for n in names]
    for d in structures:
        data = tmp / ("structure_" + suffix + d.name) / STRUCTURE_RESOURCE
        data.parent.mkdir()
        d.to_json(data)
        jobs.append((structure_script, out / f"{d.name}{suffix}.fmu", [*files, data]))
    return jobs + _system_jobs(systems, system_script, suffix, out, tmp, files)


def _jobs3(names, systems, out: Path, tmp: Path, bundle: list) -> list:
    """``(script name, destination, project files)`` of each FMI 3 FMU (the named ones, then one per
    system definition): the bundle and pythonfmu's Python sources (the FMI 3 slaves bind the FMI 2 ones,
    which import pythonfmu; pythonfmu3 puts its own into every FMU, as pythonfmu does into the FMI 2
    ones), so that an FMU needs no pythonfmu installed."""
    files = _fmi3_files(tmp, bundle)
    return ([(FMUS3[n], out / f"{n}Fmi3.fmu", files) for n in names]
            + _system_jobs(systems, SYSTEM_SCRIPT3, "Fmi3", out, tmp, files))


def _system_jobs(systems, script: str, suffix: str, out: Path, tmp: Path, files: list) -> list:
    """The jobs of one friction system FMU per system definition (``script``, ``<name><suffix>.fmu``,
    ``files`` and the definition, written into ``tmp``)."""
    from .system_slave import SYSTEM_RESOURCE

    jobs = []
    for d in systems:
        data = tmp / ("system_" + d.name + suffix) / SYSTEM_RESOURCE
        data.parent.mkdir()
        d.to_json(data)
        jobs.append((script, out / f"{d.name}{suffix}.fmu", [*files, data]))
    return jobs


def _jobs(names, structures, systems, out: Path, tmp: Path, bundle: list) -> list:
    """``(script name, destination, project files)`` of each FMU to build: the named FMUs (with
    their blade model definition in the resources where :data:`BLADE_MODELS` gives one), one
    ``LinearStructure`` FMU per structure definition and one friction system FMU per system
    definition (the definitions written into ``tmp``)."""
    from .slaves import BLADE_RESOURCE, STRUCTURE_RESOURCE

    jobs = []
    for n in names:
        files = list(bundle)
        if n in BLADE_MODELS:  # the definition travels in the resources
            from ..structures import load_blade_model

            data = tmp / n / BLADE_RESOURCE
            data.parent.mkdir()
            shutil.copyfile(load_blade_model(BLADE_MODELS[n]).path, data)
            files.append(data)
        jobs.append((FMUS[n], out / f"{n}.fmu", files))
    for d in structures:
        data = tmp / d.name / STRUCTURE_RESOURCE
        data.parent.mkdir()
        d.to_json(data)
        jobs.append((STRUCTURE_SCRIPT, out / f"{d.name}.fmu", [*bundle, data]))
    return jobs + _system_jobs(systems, SYSTEM_SCRIPT, "", out, tmp, bundle)


def _blade_jobs(blades, out: Path, tmp: Path, bundle: list) -> list:
    """The jobs of one blade FMU per blade model definition (a name in ``models/`` or a ``.toml``
    path): :data:`BLADE_SCRIPT`, ``<name>.fmu`` (the definition's ``name``), the bundle and the
    definition's file, and the model description's ``description`` of a solid blade (whose FMU
    has the outputs of its contact patches, :func:`~frictionjoint.structures.blade_run.blade_outputs`)."""
    from ..structures import load_blade_model
    from .slaves import BLADE_RESOURCE, SOLID_BLADE_DESCRIPTION

    jobs = []
    for model in map(load_blade_model, blades):
        data = tmp / ("blade_" + model.name) / BLADE_RESOURCE
        data.parent.mkdir()
        shutil.copyfile(model.path, data)
        jobs.append((BLADE_SCRIPT, out / f"{model.name}.fmu", [*bundle, data],
                     SOLID_BLADE_DESCRIPTION if model.kind == "solid" else None))
    return jobs


def _build_one(script: Path, dest: Path, project_files, check: bool, fmi_version: int = 2,
               early_return: bool = True, description: str | None = None) -> Path:
    """Build one FMU from ``script`` to ``dest``, post-process it (``description``: the model
    description's, see :func:`postprocess`) and, with ``check``, validate it
    (:class:`~frictionjoint.errors.FMUError` listing the problems)."""
    from ..errors import FMUError

    if not script.is_file():
        raise FileNotFoundError(f"FMU script {script} not found (source_dir)")
    if fmi_version == 3:
        path = _pythonfmu3_build(script, dest, project_files)
        postprocess3(path, early_return)
    else:
        path = _pythonfmu_build(script, dest, project_files)
        postprocess(path, description)
    if check:
        problems = validate(path)
        if problems:
            raise FMUError(f"{path.name} does not validate: " + "; ".join(problems))
    return Path(path)


def _pythonfmu_build(script: Path, dest: Path, project_files) -> Path:
    """pythonfmu's builder with this project's capability flags."""
    from pythonfmu.builder import FmuBuilder

    return Path(FmuBuilder.build_FMU(script, dest=dest, project_files=project_files, needsExecutionTool="false",
                                     canGetAndSetFMUstate="true", canSerializeFMUstate="true",
                                     canHandleVariableCommunicationStepSize="true"))


def _pythonfmu3_build(script: Path, dest: Path, project_files) -> Path:
    """pythonfmu3's builder (it names the FMU after the script's class) to ``dest``; the capability
    flags are :func:`postprocess3`'s."""
    from pythonfmu3.builder import FmuBuilder

    path = Path(FmuBuilder.build_FMU(script, dest=dest.parent, project_files=project_files))
    if path != dest:
        path.replace(dest)
    return dest

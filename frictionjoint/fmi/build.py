"""Build the FMUs with pythonfmu, post-process their model descriptions, validate with fmpy.

The library is bundled into each FMU's ``resources/`` under the name ``_frictionjoint_bundle`` (one
zip archive) with its identity, so an FMU needs only Python with numpy and scipy at run time and a host's own
``frictionjoint`` can neither shadow it nor be shadowed by it; where the host's installed
``frictionjoint`` is the very same library (the same identity), the FMU runs that one, with its
compiled kernels (:mod:`.bundle_loader`).
"""
from __future__ import annotations

import shutil
import sys
import tempfile
import xml.etree.ElementTree as ET
import zipfile
from pathlib import Path

from .bundle_loader import ARCHIVE, BUNDLE, EXCLUDED, IDENTITY, identity

__all__ = ["FMUS", "BLADE_MODELS", "BUNDLE_NAME", "STRUCTURE_SCRIPT", "SYSTEM_SCRIPT", "build_fmus", "postprocess",
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
#: FMUs that carry a blade model definition in their resources: FMU name -> the definition
#: (a name in the repository's ``models/``)
BLADE_MODELS = {"BladeDovetail": "ti64_compressor_blade"}
#: the script of LinearStructure.fmu (one per structure definition, built by ``structures=``)
STRUCTURE_SCRIPT = "fj_linear_structure_fmu.py"
#: the script of a friction system FMU (one per system definition, built by ``systems=``)
SYSTEM_SCRIPT = "fj_friction_system_fmu.py"


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


def postprocess(fmu: Path) -> None:
    """Add ``<InitialUnknowns>`` (all outputs) to the model structure, which pythonfmu omits."""
    fmu = Path(fmu)
    with zipfile.ZipFile(fmu) as z:
        items = {name: z.read(name) for name in z.namelist()}
    root = ET.fromstring(items["modelDescription.xml"])
    variables = root.find("ModelVariables").findall("ScalarVariable")
    outputs = [i + 1 for i, v in enumerate(variables) if v.get("causality") == "output"]
    structure = root.find("ModelStructure")
    if structure is None:
        structure = ET.SubElement(root, "ModelStructure")
    for tag in ("Outputs", "InitialUnknowns"):
        old = structure.find(tag)
        if old is not None:
            structure.remove(old)
    outs = ET.Element("Outputs")
    init = ET.Element("InitialUnknowns")
    for idx in outputs:
        ET.SubElement(outs, "Unknown", index=str(idx))
        ET.SubElement(init, "Unknown", index=str(idx))
    structure.insert(0, outs)
    # Outputs, Derivatives, InitialUnknowns: keep the schema order
    structure.append(init)
    items["modelDescription.xml"] = ET.tostring(root, encoding="UTF-8", xml_declaration=True)
    tmp = fmu.with_suffix(".tmp")
    with zipfile.ZipFile(tmp, "w", zipfile.ZIP_DEFLATED) as z:
        for name, data in items.items():
            z.writestr(name, data)
    tmp.replace(fmu)


def validate(fmu: Path) -> list[str]:
    """Problems reported by :func:`fmpy.validation.validate_fmu` (empty when valid)."""
    from fmpy.validation import validate_fmu

    return list(validate_fmu(str(fmu)))


def build_fmus(out_dir, names=None, source_dir=None, check: bool = True, structures=(), systems=()) -> list[Path]:
    """Build, post-process and (optionally) validate the FMUs.

    Parameters
    ----------
    out_dir : path
        Folder for the ``.fmu`` files (created).
    names : sequence of str, optional
        Which of :data:`FMUS` to build; all by default, none when ``structures`` or ``systems`` are given.
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

    Returns
    -------
    list of Path
    """
    from ..structure_file import StructureDefinition, load_structure_definition

    out = Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)
    source = Path(source_dir) if source_dir is not None else default_source_dir()
    from ..system_file import SystemDefinition, load_system_definition

    structures = [s if isinstance(s, StructureDefinition) else load_structure_definition(s) for s in structures]
    systems = [s if isinstance(s, SystemDefinition) else load_system_definition(s) for s in systems]
    names = ([] if structures or systems else list(FMUS)) if names is None else list(names)
    for n in names:
        if n not in FMUS:
            raise ValueError(f"names must be among {sorted(FMUS)}, got {n!r}")
    built = []
    # the builder imports each script, and so the bundle: set aside a bundle this process has
    # loaded from an FMU it runs (it may be another version, its folder may be gone) and give
    # it back afterwards, for those FMUs
    # pythonfmu's builder imports each FMU script as a top-level module (fj_*_fmu) and leaves it in
    # sys.modules: set those aside too, and drop the builder's afterwards, else an FMU loaded
    # later in this process would reuse the build's script, bound to the removed build bundle
    scripts = {Path(f).stem for f in (*FMUS.values(), STRUCTURE_SCRIPT, SYSTEM_SCRIPT)}

    def ours(m):
        return m == BUNDLE_NAME or m.startswith(BUNDLE_NAME + ".") or m in scripts
    loaded = {m: sys.modules.pop(m) for m in list(sys.modules) if ours(m)}
    with tempfile.TemporaryDirectory(prefix="frictionjoint_fmu_") as tmpd:
        tmp = Path(tmpd)
        bundle = _bundle(tmp)
        sys.path.insert(0, str(tmp))
        try:
            for script_name, dest, project_files in _jobs(names, structures, systems, out, tmp, bundle):
                built.append(_build_one(source / script_name, dest, project_files, check))
        finally:
            sys.path.remove(str(tmp))
            for mod in [m for m in sys.modules if ours(m)]:
                del sys.modules[mod]
            sys.modules.update(loaded)
    return built


def _jobs(names, structures, systems, out: Path, tmp: Path, bundle: list) -> list:
    """``(script name, destination, project files)`` of each FMU to build: the named FMUs (with
    their blade model definition in the resources where :data:`BLADE_MODELS` gives one), one
    ``LinearStructure`` FMU per structure definition and one friction system FMU per system
    definition (the definitions written into ``tmp``)."""
    from .slaves import BLADE_RESOURCE, STRUCTURE_RESOURCE
    from .system_slave import SYSTEM_RESOURCE

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
    for d in systems:
        data = tmp / ("system_" + d.name) / SYSTEM_RESOURCE
        data.parent.mkdir()
        d.to_json(data)
        jobs.append((SYSTEM_SCRIPT, out / f"{d.name}.fmu", [*bundle, data]))
    return jobs


def _build_one(script: Path, dest: Path, project_files, check: bool) -> Path:
    """Build one FMU from ``script`` to ``dest``, post-process it and, with ``check``, validate it
    (:class:`~frictionjoint.errors.FMUError` listing the problems)."""
    from ..errors import FMUError

    if not script.is_file():
        raise FileNotFoundError(f"FMU script {script} not found (source_dir)")
    path = _pythonfmu_build(script, dest, project_files)
    postprocess(path)
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

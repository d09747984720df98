"""The user guide (docs/) builds with Sphinx, warnings as errors, and its API reference describes
every public name: each name of the ``__all__`` of ``frictionjoint``, of every subpackage whose face
defines ``__all__`` and of every module that ``frictionjoint.__all__`` names. Its Python examples
are run by tests/test_examples.py."""
import importlib
import pkgutil
import posixpath
import subprocess
import sys
import types
from pathlib import Path

import pytest

import frictionjoint

ROOT = Path(__file__).resolve().parents[1]
DOCS = ROOT / "docs"
TIMEOUT = 300  # seconds for the build (about 30-45 s on 2 shared cores)


def public_modules():
    """The public modules: the package, the modules its ``__all__`` names, every subpackage with
    ``__all__`` (found by walking the package, so a new face cannot be missed)."""
    modules = [frictionjoint]
    modules += [obj for obj in vars(frictionjoint).values()
                if isinstance(obj, types.ModuleType) and obj.__name__.split(".")[-1] in frictionjoint.__all__]
    for info in pkgutil.walk_packages(frictionjoint.__path__, "frictionjoint."):
        if info.ispkg:
            module = importlib.import_module(info.name)
            if hasattr(module, "__all__"):
                modules.append(module)
    return list({m.__name__: m for m in modules}.values())


@pytest.fixture(scope="module")
def html(tmp_path_factory):
    """The guide built from scratch (-E) into a temporary folder, warnings as errors; in a
    subprocess, so that Sphinx's and docutils' global registrations stay out of this process."""
    out = tmp_path_factory.mktemp("html")
    argv = [sys.executable, "-m", "sphinx", "-W", "--keep-going", "-E", "-b", "html", "-q",
            "-d", str(out / ".doctrees"), str(DOCS), str(out)]
    proc = subprocess.run(argv, capture_output=True, text=True, timeout=TIMEOUT, cwd=ROOT)
    return proc, out


@pytest.mark.slow  # about 30-45 s: the whole guide and its API reference
def test_guide_builds_with_warnings_as_errors(html):
    proc, out = html
    assert proc.returncode == 0, f"sphinx -W failed:\n{proc.stderr[-6000:]}"
    for page in ("index", "getting-started", "fmus", "cosimulation", "blades", "harmonic-balance", "studies",
                 "accuracy", "performance", "engines/index", "api/index", "api/frictionjoint"):
        assert (out / f"{page}.html").is_file(), page
    assert (out / "_images" / "work_precision.png").read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"


@pytest.mark.slow
def test_api_reference_has_every_public_name(html):
    """Every (module, name) of the public ``__all__`` lists is an object of the built reference
    (its inventory, objects.inv): described there, or an alias linked to where it is described."""
    from sphinx.util.inventory import InventoryFile

    proc, out = html
    assert proc.returncode == 0, proc.stderr[-3000:]
    with open(out / "objects.inv", "rb") as fh:
        inventory = InventoryFile.load(fh, "", posixpath.join)
    data = inventory.data if hasattr(inventory, "data") else inventory
    documented = {name for role, entries in data.items() if role.startswith("py:") for name in entries}
    modules = public_modules()
    assert {"frictionjoint", "frictionjoint.solvers.sdof", "frictionjoint.solvers.marcher",
            "frictionjoint.solvers.frequency_domain"} <= {m.__name__ for m in modules}
    missing = []
    for module in modules:
        assert module.__name__ in documented, f"no API page for {module.__name__}"
        for name in module.__all__:
            obj = getattr(module, name)
            target = obj.__name__ if isinstance(obj, types.ModuleType) else f"{module.__name__}.{name}"
            if target not in documented:
                missing.append(target)
    assert not missing, f"public names missing from the API reference: {missing}"

"""Sphinx configuration of the frictionjoint user guide.

Built by ``tests/test_docs.py`` with ``-W`` (warnings are errors) on every test run, so the guide
cannot rot: a page whose link, cross-reference or example goes stale fails the suite.

The pages are Markdown (MyST). The API reference is generated from the package: every public module
(``frictionjoint``, each subpackage whose face defines ``__all__``, each module named in
``frictionjoint.__all__``, and the few adapter modules of :data:`EXTRA_MODULES` the guide sends its
reader to) gets a page ``api/<module>.rst`` written here at the start of the build (those files are
not kept in git), listing exactly the names of its ``__all__``. A name is described once, where it
first appears (``frictionjoint`` first): later faces that re-export the same object show it as an
alias linked to that description, so every public name is in the index under every face that
exports it, without a duplicate description.
"""
from __future__ import annotations

import importlib
import inspect
import pkgutil
import sys
import types
from pathlib import Path

DOCS = Path(__file__).resolve().parent
ROOT = DOCS.parent
sys.path.insert(0, str(ROOT))

import frictionjoint  # noqa: E402

project = "frictionjoint"
author = "the frictionjoint developers"
copyright = "2026, the frictionjoint developers"
release = version = frictionjoint.__version__

extensions = [
    "myst_parser",
    "sphinx.ext.autodoc",
    "numpydoc",
]
source_suffix = {".rst": "restructuredtext", ".md": "markdown"}
root_doc = "index"
exclude_patterns = ["_build", ".gitignore"]
html_theme = "alabaster"
html_static_path = []
html_title = "frictionjoint user guide"

# Markdown: headings get anchors down to level 3, so pages may link to each other's sections
# (no MyST extensions: the pages write their formulas as text, and a `$` stays a `$`)
myst_heading_anchors = 3

# Every reference must resolve (nitpicky), in the guide's own pages. The API pages render the
# library's docstrings, which also name private helpers and modules the reference does not
# document (``frictionjoint.stepping.OscillatorRun``, ...): their unresolved references are
# dropped by ``_api_references`` below, nowhere else.
nitpicky = True


# autodoc: the docstrings (numpydoc) state the types with shapes and units; the signatures'
# annotations would only repeat them as unresolvable references (ArrayLike, os.PathLike, ...)
autodoc_typehints = "none"
autodoc_member_order = "bysource"
autodoc_default_options = {"members": True, "show-inheritance": False}
autodoc_preserve_defaults = True

# numpydoc: the docstrings are rendered, not validated here (tests/test_api_docs.py checks their
# sections and type hints); class member tables would need a stub page per member
numpydoc_show_class_members = False
numpydoc_class_members_toctree = False
numpydoc_xref_param_type = False
numpydoc_validation_checks = set()

#: adapter modules the guide names, documented beside the public faces
#: (not ``frictionjoint.sweep``: its name is the function ``frictionjoint.sweep``, described at the top)
EXTRA_MODULES = [
    "frictionjoint.drivers",
    "frictionjoint.fmi.cosim",
    "frictionjoint.fmi.ecos",
    "frictionjoint.fmi.me_master",
]


def public_modules() -> list[str]:
    """The modules of the API reference, ``frictionjoint`` first."""
    names = ["frictionjoint"]
    for name in frictionjoint.__all__:
        if isinstance(getattr(frictionjoint, name), types.ModuleType):
            names.append(f"frictionjoint.{name}")
    for info in pkgutil.walk_packages(frictionjoint.__path__, "frictionjoint."):
        if info.ispkg and hasattr(importlib.import_module(info.name), "__all__"):
            names.append(info.name)
    names += EXTRA_MODULES
    return list(dict.fromkeys(names[:1] + sorted(names[1:])))


def _kind(obj) -> str:
    if isinstance(obj, types.ModuleType):
        return "module"
    if inspect.isclass(obj):
        return "exception" if issubclass(obj, BaseException) else "class"
    if callable(obj):
        return "function"
    return "data"


def _module_page(module: str, first: dict) -> str:
    """The reST of one module's page; ``first`` maps ``id(obj)`` to the name it is described
    under (filled in here)."""
    mod = importlib.import_module(module)
    title = f"``{module}``"
    lines = [title, "=" * len(title), "", f".. automodule:: {module}", "   :no-members:", ""]
    for name in mod.__all__:
        obj = getattr(mod, name)
        kind = _kind(obj)
        full = f"{module}.{name}"
        if kind == "module":
            lines += [f".. rubric:: ``{name}``", "", f"The module :mod:`{obj.__name__}`.", ""]
            continue
        if kind != "data" and id(obj) in first:
            lines += [f".. py:{kind}:: {name}", f"   :module: {module}", "   :no-contents-entry:", "",
                      f"   The same as :py:{'func' if kind == 'function' else 'class'}:`{first[id(obj)]}`.", ""]
            continue
        if kind != "data":
            first[id(obj)] = full
        auto = {"class": "autoclass", "exception": "autoexception", "function": "autofunction",
                "data": "autodata"}[kind]
        lines += [f".. {auto}:: {full}", ""]
    return "\n".join(lines)


def write_api_pages(app) -> None:
    """``api/<module>.rst`` for every public module (rewritten only when its text changes)."""
    out = DOCS / "api"
    out.mkdir(exist_ok=True)
    first: dict = {}
    keep = set()
    for module in public_modules():
        path = out / f"{module}.rst"
        text = _module_page(module, first)
        keep.add(path.name)
        if not path.exists() or path.read_text() != text:
            path.write_text(text)
    for stale in out.glob("frictionjoint*.rst"):
        if stale.name not in keep:
            stale.unlink()


class _WorkPrecisionCSV:
    """``benchmarks/results/work_precision.csv`` read back as the little that
    :func:`frictionjoint.plotting.plot_work_precision` asks of a benchmark result."""

    def __init__(self, path: Path):
        import csv
        from collections import namedtuple
        from types import SimpleNamespace as NS

        case_type = namedtuple("Case", "label")  # a dict key, as the harness's Case

        text = path.read_text(encoding="utf-8").splitlines()
        refs = next(ln for ln in text if ln.startswith("# references: "))[len("# references: "):]
        names = dict(part.split(": ", 1) for part in refs.split("; "))
        cases, self.rows = {}, []
        for row in csv.DictReader(ln for ln in text if not ln.startswith("#")):
            label = row["case"]
            if label not in cases:
                cases[label] = case_type(label)
            error = float(row["relative_error"])
            self.rows.append(NS(case=cases[label], method=row["method"], time=float(row["time_s"]), error=error,
                                ok=row["status"] == "ok" and error == error and error != float("inf")))
        self.problems = {case: NS(reference_name=names[label],
                                  regime="stop-free" if names[label].startswith("Den Hartog") else "stops")
                         for label, case in cases.items()}

    def case_rows(self, case):
        return [r for r in self.rows if r.case is case]


def write_figures(app) -> None:
    """The guide's figures from the committed benchmark results (``_generated/``, not in git):
    the work-precision diagram from ``benchmarks/results/work_precision.csv``."""
    from frictionjoint.plotting import plot_work_precision

    out = DOCS / "_generated"
    out.mkdir(exist_ok=True)
    csv_path = ROOT / "benchmarks" / "results" / "work_precision.csv"
    png = out / "work_precision.png"
    if not png.exists() or png.stat().st_mtime < csv_path.stat().st_mtime:
        plot_work_precision(_WorkPrecisionCSV(csv_path), path=png)  # an Agg figure, no pyplot state


def _api_references(app, domain, node):
    """Keep quiet about unresolved references in the library's docstrings (API pages) only."""
    if node.get("refdoc", "").startswith("api/"):
        return True
    return None


def setup(app):
    app.connect("builder-inited", write_api_pages)
    app.connect("builder-inited", write_figures)
    app.connect("warn-missing-reference", _api_references)

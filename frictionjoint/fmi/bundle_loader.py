"""The first lines of every FMU script: the bundled library of *this* FMU, not of one already freed.

Each FMU carries the library as the package ``_frictionjoint_bundle`` in its resources; pythonfmu
appends the resources folder to ``sys.path`` and imports the FMU's script, and Python keeps the
first bundle it imported for the whole process. An importer deletes an FMU's extracted folder when
it frees the FMU (fmpy, this package's master), and a module of the bundle that had not been
imported by then (an FMU of another kind: the system FMU's slave after a joint FMU's) is then looked
for in a folder that is gone: ``ModuleNotFoundError``, and the FMU fails to instantiate.
:func:`fresh_bundle` forgets a bundle whose folder is gone, so that the script imports its own.
A bundle whose folder is still there (an FMU still loaded) is shared, as before.

Standard library only, and one function: the build copies this file into every FMU as the
top-level module ``_frictionjoint_loader``, which stays usable from a freed FMU's folder (it is
loaded whole and imports nothing later).
"""
import importlib
import os
import sys

BUNDLE = "_frictionjoint_bundle"  # the package name of the bundled library (build.BUNDLE_NAME is this)


def fresh_bundle(script: str) -> None:
    """Before ``script`` (an FMU script's ``__file__``) imports the bundle: drop a loaded bundle whose
    folder no longer exists, with all its modules, and make sure ``script``'s folder is searched."""
    loaded = sys.modules.get(BUNDLE)
    if loaded is not None and all(os.path.isdir(p) for p in getattr(loaded, "__path__", ())):
        return
    for name in [n for n in sys.modules if n == BUNDLE or n.startswith(BUNDLE + ".")]:
        del sys.modules[name]
    here = os.path.dirname(os.path.abspath(script))
    if here not in sys.path:
        sys.path.append(here)
    importlib.invalidate_caches()

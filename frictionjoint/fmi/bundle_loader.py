"""The first lines of every FMU script: which library runs the FMU, and the bundle of *this* FMU,
not of one already freed.

Each FMU carries the library as the package ``_frictionjoint_bundle`` in one zip archive in its
resources (:data:`ARCHIVE`, imported by ``zipimport``), with the library's identity
(``identity.json``: its version and a SHA-256 of its files, written by the build).
:func:`library` gives the FMU script the module it asks for:

- from the installed ``frictionjoint`` when that is the very same library (the same hash of the
  same files; :func:`identity`): it runs the compiled kernels (numba, compiled once at its
  installation and cached there), where the bundle runs their NumPy paths (numba would compile for
  seconds in every unpacked copy of the bundle); the numbers are the same library's;
- otherwise from the bundle: another version, an edited library or none installed is never used.
  The environment variable ``FRICTIONJOINT_FMU_BUNDLED=1`` forces the bundle.

pythonfmu adds the resources folder to ``sys.path`` and imports the FMU's script, and Python keeps
the first bundle it imported for the whole process. An importer deletes an FMU's extracted folder
when it frees the FMU (fmpy, this package's master), and a module of the bundle that had not been
imported by then (an FMU of another kind: the system FMU's slave after a joint FMU's) is then looked
for in an archive that is gone: ``ModuleNotFoundError``, and the FMU fails to instantiate.
:func:`fresh_bundle` forgets a bundle whose archive (or folder, an FMU built before the archive) is
gone, or that is another library than this FMU's (its identity differs), so that the script imports
its own. A bundle whose archive is still there and that is the same library (an FMU still loaded)
is shared, as before.

Standard library only: the build copies this file into every FMU as the top-level module
``_frictionjoint_loader``, which stays usable from a freed FMU's folder (it is loaded whole and
later imports nothing but the standard library's ``zipfile`` and ``zipimport``).
"""
import fnmatch
import hashlib
import importlib
import importlib.util
import json
import os
import sys

BUNDLE = "_frictionjoint_bundle"  # the package name of the bundled library (build.BUNDLE_NAME is this)
#: the zip archive, in an FMU's resources, that holds the package :data:`BUNDLE`
ARCHIVE = BUNDLE + ".zip"
INSTALLED = "frictionjoint"  # the package name of the installed library
#: the file, in the bundle's folder, that holds its identity (:func:`identity`)
IDENTITY = "identity.json"
#: what the bundle leaves out of the library's folder (at every depth), and :func:`identity` too
#: (``fmi3_wrapper``: the patched FMI 3 wrapper's binary and its build, for the build only)
EXCLUDED = ("__pycache__", "*.pyc", "cli.py", "__main__.py", "fmi3_wrapper")
#: set to 1: every FMU runs its bundled library, even where the installed one is the same
FORCE_BUNDLE = "FRICTIONJOINT_FMU_BUNDLED"


def _excluded(name: str) -> bool:
    return name == IDENTITY or any(fnmatch.fnmatch(name, p) for p in EXCLUDED)


def identity(folder: str) -> dict:
    """The identity of the library in ``folder`` (the installed package or a bundle): its version
    (``__version__`` as written in its ``__init__.py``) and the SHA-256 of its files but
    :data:`EXCLUDED` (each file's path relative to ``folder``, its size and its bytes, in sorted
    order): two folders with the same identity hold the same library, byte for byte."""
    digest = hashlib.sha256()
    version = ""
    for dirpath, dirnames, filenames in os.walk(folder):
        dirnames[:] = sorted(d for d in dirnames if not _excluded(d))
        for name in sorted(f for f in filenames if not _excluded(f)):
            path = os.path.join(dirpath, name)
            with open(path, "rb") as fh:
                data = fh.read()
            rel = os.path.relpath(path, folder).replace(os.sep, "/")
            if rel == "__init__.py":
                for line in data.decode("utf-8", "replace").splitlines():
                    if line.startswith("__version__"):
                        version = line.partition("=")[2].strip().strip("\"'")
            digest.update(f"{rel}\0{len(data)}\0".encode() + data)
    # the walk's order is fixed (sorted names, sorted folders), the same on every platform
    return {"version": version, "sha256": digest.hexdigest()}


def _read_identity(source: str):
    """The identity written in a bundle: ``source`` its archive or (an FMU built before the
    archive) its package folder; None if there is none."""
    try:
        if os.path.isfile(source):
            import zipfile

            with zipfile.ZipFile(source) as z:
                return json.loads(z.read(f"{BUNDLE}/{IDENTITY}").decode("utf-8"))
        with open(os.path.join(source, IDENTITY), encoding="utf-8") as fh:
            return json.load(fh)
    except (OSError, ValueError, KeyError):
        return None


def _loaded_source(module):
    """Where the loaded bundle ``module`` came from: its archive (``zipimport``) or its folder."""
    archive = getattr(getattr(module, "__loader__", None), "archive", None)
    if archive:
        return archive
    folders = list(getattr(module, "__path__", ()))
    return folders[0] if folders else None


def _archive(script: str) -> str:
    """The bundle archive of the FMU script ``script``: beside it (in the FMU's resources), else
    the first on ``sys.path`` (a folder that holds one, or one itself: the build imports the
    script from the FMU source folder, with the archive's folder on ``sys.path``)."""
    here = os.path.join(os.path.dirname(os.path.abspath(script)), ARCHIVE)
    if os.path.isfile(here):
        return here
    for entry in sys.path:
        if isinstance(entry, str) and entry:
            path = entry if entry.endswith(ARCHIVE) else os.path.join(entry, ARCHIVE)
            if os.path.isfile(path):
                return path
    return here


def _installed_folder():
    """The folder of the installed ``frictionjoint`` (the one this process has imported, else the
    one an import would find), or None."""
    module = sys.modules.get(INSTALLED)
    paths = list(getattr(module, "__path__", ())) if module is not None else None
    if paths is None:
        try:
            spec = importlib.util.find_spec(INSTALLED)
        except (ImportError, ValueError):
            return None
        paths = list(spec.submodule_search_locations or ()) if spec is not None else []
    return paths[0] if len(paths) == 1 and os.path.isdir(paths[0]) else None


def _process_start():
    """When this process started [s since the epoch], to about a second (Linux: ``/proc``), or None."""
    try:
        with open("/proc/self/stat", encoding="ascii") as fh:
            ticks = int(fh.read().rsplit(")", 1)[1].split()[19])  # field 22, starttime
        with open("/proc/stat", encoding="ascii") as fh:
            boot = next(int(line.split()[1]) for line in fh if line.startswith("btime "))
        return boot + ticks / os.sysconf("SC_CLK_TCK")
    except (OSError, ValueError, IndexError, StopIteration, AttributeError):
        return None


def _edited_since_start(folder: str) -> bool:
    """Whether a file of the library in ``folder`` may have changed since this process started (its
    modification time is later, to a 2 s margin); False where the start is not known."""
    start = _process_start()
    if start is None:
        return False
    for dirpath, dirnames, filenames in os.walk(folder):
        dirnames[:] = [d for d in dirnames if not _excluded(d)]
        for name in filenames:
            if not _excluded(name) and os.stat(os.path.join(dirpath, name)).st_mtime > start - 2.0:
                return True
    return False


def installed_is_bundle(script: str) -> bool:
    """Whether the installed ``frictionjoint`` is the very library bundled with the FMU of
    ``script`` (an FMU script's ``__file__``): same identity (:func:`identity`), and not
    :data:`FORCE_BUNDLE`. Where this process has imported it already, its files must also be
    older than the process (Linux): else the modules in memory may be older than the files the
    identity is computed from (a library edited while a session ran, and an FMU built from it)."""
    if os.environ.get(FORCE_BUNDLE, "").strip() not in ("", "0"):
        return False
    own = _read_identity(_archive(script))
    folder = _installed_folder()
    if own is None or folder is None:
        return False
    try:
        if INSTALLED in sys.modules and _edited_since_start(folder):
            return False
        return identity(folder) == own
    except OSError:
        return False


#: (script, module) -> the module :func:`library` gave that script's first execution
_CHOSEN: dict = {}


def library(script: str, module: str):
    """The library's module ``module`` (e.g. ``"fmi.slaves"``) for the FMU script ``script`` (its
    ``__file__``): from the installed ``frictionjoint`` where it is this FMU's library
    (:func:`installed_is_bundle`), else from this FMU's bundle (:func:`fresh_bundle` first).

    Once per script module: pythonfmu 0.7.0's wrapper imports the script at the first
    ``fmi2Instantiate`` of a process and, at every later one, executes its source again in the
    module's namespace (``__file__`` still the first one's, whose folder may be gone) but takes the
    slave class from the module, the first execution's; the same answer again costs nothing (it
    imported the whole bundle again, ~100-200 ms of each instantiation, for a class not used).
    """
    key = (os.path.abspath(script), module)
    chosen = _CHOSEN.get(key)
    if chosen is None:
        if installed_is_bundle(script):
            chosen = importlib.import_module(f"{INSTALLED}.{module}")
        else:
            fresh_bundle(script)
            chosen = importlib.import_module(f"{BUNDLE}.{module}")
        _CHOSEN[key] = chosen
    return chosen


def fresh_bundle(script: str) -> None:
    """Before ``script`` (an FMU script's ``__file__``) imports the bundle: drop a loaded bundle whose
    archive no longer exists or that is another library than this FMU's (another identity), with
    all its modules, and import the package from ``script``'s archive (its modules then come from
    there, by the package's ``__path__``: the archive is not put on ``sys.path``)."""
    archive = _archive(script)
    loaded = sys.modules.get(BUNDLE)
    if loaded is not None:
        source = _loaded_source(loaded)
        if source is not None and os.path.exists(source) and _read_identity(source) == _read_identity(archive):
            return
    for name in [n for n in sys.modules if n == BUNDLE or n.startswith(BUNDLE + ".")]:
        del sys.modules[name]
    importlib.invalidate_caches()
    if not os.path.isfile(archive):  # none to be found: the import says so
        return
    import zipimport

    spec = zipimport.zipimporter(archive).find_spec(BUNDLE)
    if spec is None:
        raise ImportError(f"{archive} holds no package {BUNDLE}", name=BUNDLE)
    module = importlib.util.module_from_spec(spec)
    sys.modules[BUNDLE] = module
    try:
        spec.loader.exec_module(module)
    except BaseException:
        del sys.modules[BUNDLE]
        raise

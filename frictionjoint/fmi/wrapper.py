"""What pythonfmu 0.7.0's native wrapper needs from a slave so that a host can hold many instances.

pythonfmu's binary (``src/pythonfmu/PySlaveInstance.cpp``, ``PyState.hpp``; 0.7.0 is the newest
release, and its master has the same code) has reference-counting and exit-order defects that
crash a host holding several instances of an FMU, or any native host at exit.
:class:`BalancedSlave` balances each of them once for every slave derived from it:

1. ``findClass`` ``Py_DECREF``s the borrowed ``__dict__`` of the FMU script's module at every
   instantiation (:func:`_balance_find_class`);
2. after a Python error ``handle_py_exception`` releases the slave class, instance and log queue,
   which the destructor or ``fmi2Reset`` release again (:func:`_lending_references`);
3. the static interpreter holder is released twice at unload/exit, and a native host's embedded
   interpreter is finalised after the C++ static destructors of extension modules
   (:func:`_finalize_before_exit`);
4. the FMU's resources folder is added to ``sys.path`` at every instantiation
   (:func:`_drop_repeated_path`).

frictionjoint's FMI 2 FMUs carry a fixed build of that wrapper for x86_64 Linux
(:mod:`frictionjoint.fmi.fmi2_wrapper`, ``fix.patch``), whose C++ source has none of the four defects
(items 4, 5, 7 and 8 of the patch): there (:data:`STOCK_WRAPPER` false) nothing is balanced here (a
surplus reference would leak the instance at every error). Elsewhere (Windows: pythonfmu's stock
binary) all four are.

Leaks of the wrapper (temporaries of ``PyUnicode_AsUTF8String``/``PyObject_Repr`` in
``findClass``, three attribute references per log message in ``clearLogBuffer``, the result of
``_set_fmu_state``) cost memory only and are left alone. A surplus reference here, should a
later pythonfmu fix a defect, only keeps alive what is alive anyway; a missing one is fatal.
"""
from __future__ import annotations

import ctypes
import functools
import os
import platform
import sys

from pythonfmu import Fmi2Slave

__all__ = ["BalancedSlave", "WRAPPER_CALLS"]

#: whether pythonfmu's stock binary runs this FMU: every platform but x86_64 Linux, whose FMI 2 FMUs carry
#: frictionjoint's fixed wrapper (``fmi2_wrapper/fix.patch``: the four defects fixed in its C++ source, so
#: that their balancing here goes)
STOCK_WRAPPER = not (sys.platform.startswith("linux") and platform.machine().lower() in ("x86_64", "amd64"))

_py_incref = ctypes.pythonapi.Py_IncRef
_py_incref.argtypes = [ctypes.py_object]
_py_incref.restype = None


def _balance_find_class(cls) -> None:
    """Give the FMU script module's ``__dict__`` the reference that pythonfmu takes from it.

    pythonfmu's native wrapper (0.7.0, ``src/pythonfmu/PySlaveInstance.cpp``, ``findClass``), once
    per ``fmi2Instantiate``: imports the script module, re-executes the script's source with the
    module's ``__dict__`` as globals (``PyEval_EvalCode``), picks the slave class, and at the end
    ``Py_DECREF``s ``PyModule_GetDict(module)`` -- a *borrowed* reference. Each instantiation
    thus releases one reference it never owned; a script whose module dict is held by nothing
    but the module (ours: one class, no functions) is freed by the first instantiation, and the
    second (or a cyclic GC pass) meets freed memory and crashes the host.

    The re-execution defines the script's slave class again, which calls
    ``BalancedSlave.__init_subclass__`` -- inside ``findClass``, before its ``Py_DECREF`` -- and that
    calls this: one ``Py_IncRef`` per instantiation balances it. (Compensating later, when the
    slave is constructed, is too late: the dict may be gone by then.) The surplus references (the
    script's first import, a pythonfmu that fixes the bug) only keep a module's dict alive that
    its module keeps alive anyway; a missing reference is fatal.
    """
    module = sys.modules.get(cls.__module__)
    if module is not None:
        _py_incref(vars(module))


#: FMU binary path -> its library handle, held to the end of the process (see _finalize_before_exit)
_HELD_BINARIES: dict = {}


def _finalize_before_exit(resources, model_identifier: str) -> None:
    """Have this FMU binary's Python holder released first thing at process exit.

    pythonfmu 0.7.0's binary keeps its interpreter holder in a static
    ``std::shared_ptr<PyState> pyState`` (``PySlaveInstance.cpp``) and releases it twice when the
    library is unloaded or the process exits: the static destructor frees it, then the ELF
    destructor ``onLibraryUnload`` assigns ``nullptr`` to the destroyed pointer and releases its
    freed control block again (heap corruption). In a non-Python host that destructor is also
    where the embedded interpreter is finalised -- after the C++ static destructors of the
    extension modules loaded meanwhile (SciPy's ``_uarray`` releases a type object from its own,
    which ``Py_Finalize`` releases again): the host's heap is corrupted at exit (Ecos: exit status
    139/134 after a complete run).

    Calling the binary's own ``finalizePythonInterpreter`` (exported, ``pyState = nullptr``) from a
    C ``atexit`` entry registered here -- after the library and the extension modules were loaded,
    so it runs before their static destructors -- releases the holder once, finalises the
    interpreter where the binary started it (as a Python host finalises before ``exit``), and
    leaves the static destructor and ``onLibraryUnload`` an empty pointer. The library is held
    open until then, so that the entry stays valid after a host unloads it (fmpy unloads the
    library when the last instance is freed, which would run the double release mid-process).
    Once per binary and process; Linux only (pythonfmu's Windows binary finalises from
    ``DllMain``).
    """
    if not sys.platform.startswith("linux") or not resources:
        return
    binary = os.path.join(os.path.dirname(os.path.abspath(resources)), "binaries", "linux64",
                          f"{model_identifier}.so")
    if binary in _HELD_BINARIES or not os.path.isfile(binary):  # e.g. the builder's dummy instance
        return
    try:
        lib = ctypes.CDLL(binary)
    except OSError:  # not loadable from here (the host loaded another copy): nothing to order
        return
    finalize = getattr(lib, "finalizePythonInterpreter", None)
    cxa_atexit = getattr(ctypes.CDLL(None), "__cxa_atexit", None)  # glibc (and most C libraries)
    if finalize is None or cxa_atexit is None:  # nothing to order, or no way to: hold it loaded
        _HELD_BINARIES[binary] = lib
        return
    cxa_atexit.argtypes = [ctypes.c_void_p, ctypes.c_void_p, ctypes.c_void_p]
    cxa_atexit.restype = ctypes.c_int
    if cxa_atexit(ctypes.cast(finalize, ctypes.c_void_p), None, None) == 0:
        _HELD_BINARIES[binary] = lib


def _drop_repeated_path(resources) -> None:
    """pythonfmu's wrapper inserts the FMU's resources folder at the front of ``sys.path`` at
    every instantiation (and leaks the string): keep the first copy only, so that a host with
    thousands of instantiations does not search one folder thousands of times per import."""
    if resources and sys.path.count(resources) > 1:
        first = sys.path.index(resources)
        sys.path[first + 1:] = [p for p in sys.path[first + 1:] if p != resources]


#: the slave methods pythonfmu's wrapper calls on the instance (see BalancedSlave._guard)
WRAPPER_CALLS = ("setup_experiment", "enter_initialization_mode", "exit_initialization_mode", "do_step",
                  "terminate", "get_integer", "get_real", "get_boolean", "get_string", "set_integer",
                  "set_real", "set_boolean", "set_string", "_get_fmu_state", "_set_fmu_state")


def _lending_references(method):
    """``method`` as called by pythonfmu's wrapper, with the references its error path takes.

    When a call into Python raises, pythonfmu 0.7.0's wrapper (``handle_py_exception``) logs the
    error, calls ``cleanPyObject`` -- ``Py_XDECREF`` of the slave class, the slave instance and
    its log queue, without clearing the pointers -- and returns ``fmi2Fatal``. The destructor
    (``fmi2FreeInstance``) and ``fmi2Reset`` release the same three objects again: the instance,
    held by nothing else, is freed twice and the host crashes. Before an exception leaves a
    wrapper-called method, one reference to each of the three is lent, so that the error path
    releases what it was given and the instance lives until the host frees it.
    """

    @functools.wraps(method)
    def call(self, *args):
        try:
            return method(self, *args)
        except BaseException:
            for obj in (type(self), self, self.log_queue):
                _py_incref(obj)
            raise

    call._lends_references = True
    return call


class BalancedSlave(Fmi2Slave):
    """A pythonfmu slave whose FMU a host may instantiate any number of times in one process,
    with its garbage collector on (see the module docstring)."""

    def __init_subclass__(cls, **kwargs):
        super().__init_subclass__(**kwargs)
        if not STOCK_WRAPPER:  # the fixed wrapper: nothing to balance (fmi2_wrapper/fix.patch, 4 and 5)
            return
        if "." not in cls.__module__:  # an FMU script's class: pythonfmu imports the script by file stem
            _balance_find_class(cls)
        cls._guard()

    @classmethod
    def _guard(cls, inherited: bool = False) -> None:
        """Wrap the wrapper-called methods this class defines, or (``inherited``) all of them
        (see :func:`_lending_references`)."""
        for name in WRAPPER_CALLS:
            method = getattr(cls, name) if inherited else cls.__dict__.get(name)
            if method is not None and not getattr(method, "_lends_references", False):
                setattr(cls, name, _lending_references(method))

    def __init__(self, **kwargs):
        super().__init__(**kwargs)
        # (also under the fixed FMI 2 wrapper, which puts the folder on sys.path once (fix.patch, 7): an
        # FMI 3 binding's slave is one of these too, and pythonfmu3's wrapper adds it at every instantiation)
        _drop_repeated_path(kwargs.get("resources"))
        if STOCK_WRAPPER:  # the fixed wrapper orders the exit itself (fix.patch, 8)
            _finalize_before_exit(kwargs.get("resources"), type(self).__name__)


if STOCK_WRAPPER:
    BalancedSlave._guard(inherited=True)

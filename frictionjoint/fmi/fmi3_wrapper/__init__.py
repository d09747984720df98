"""pythonfmu3's C++ wrapper with FMI 3 early return: ``early_return.patch`` (for pythonfmu3 0.3.4's
sources), :mod:`.build_wrapper` (rebuilds the binary with pip-only tools) and the binary it built,
``binaries/x86_64-linux/libpythonfmu-export.so``, which :mod:`frictionjoint.fmi.build` puts into the
FMI 3 FMUs (see docs/fmus.md, FMI 3.0)."""

"""pythonfmu's C++ wrapper (FMI 2.0 co-simulation) with frictionjoint's fixes: ``fix.patch`` (for
pythonfmu 0.7.0's sources, vendored in ``pythonfmu-export/`` with their MIT licence: its wheels and
sdist ship none), :mod:`.build_wrapper` (rebuilds the binary with pip-only tools) and the binary it
built, ``binaries/x86_64-linux/libpythonfmu-export.so``, which :mod:`frictionjoint.fmi.build` puts into
the FMI 2 FMUs (see docs/fmus.md, "The wrapper")."""

"""``python -m frictionjoint``: the ``frictionjoint`` command (see :mod:`frictionjoint.cli`)."""
import sys

from .cli import main

if __name__ == "__main__":
    sys.exit(main())

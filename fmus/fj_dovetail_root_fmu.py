"""FMU script: DovetailRoot.fmu (thin adapter; physics in frictionjoint)."""
from _frictionjoint_loader import library

# the installed frictionjoint where it is this FMU's library byte for byte, else the FMU's own bundle
# (frictionjoint.fmi.bundle_loader)
DovetailRootSlave = library(__file__, "fmi.slaves").DovetailRootSlave


class DovetailRoot(DovetailRootSlave):
    """Dovetail blade root driven by the root's tangential and radial displacement."""

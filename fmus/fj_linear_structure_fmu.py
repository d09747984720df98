"""FMU script: LinearStructure.fmu (thin adapter; the structure is data in the FMU's resources)."""
from _frictionjoint_loader import library

# the installed frictionjoint where it is this FMU's library byte for byte, else the FMU's own bundle
# (frictionjoint.fmi.bundle_loader)
LinearStructureSlave = library(__file__, "fmi.slaves").LinearStructureSlave


class LinearStructure(LinearStructureSlave):
    """Linear structure with joint ports, advanced exactly under held inputs."""

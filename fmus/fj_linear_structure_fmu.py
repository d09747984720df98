"""FMU script: LinearStructure.fmu (thin adapter; the structure is data in the FMU's resources)."""
from _frictionjoint_loader import fresh_bundle

fresh_bundle(__file__)  # this FMU's library, not a freed one's (frictionjoint.fmi.bundle_loader)
from _frictionjoint_bundle.fmi.slaves import LinearStructureSlave


class LinearStructure(LinearStructureSlave):
    """Linear structure with joint ports, advanced exactly under held inputs."""

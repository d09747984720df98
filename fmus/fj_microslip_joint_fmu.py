"""FMU script: MicroslipJoint.fmu (thin adapter; physics in frictionjoint)."""
from _frictionjoint_loader import library

# the installed frictionjoint where it is this FMU's library byte for byte, else the FMU's own bundle
# (frictionjoint.fmi.bundle_loader)
MicroslipJointSlave = library(__file__, "fmi.slaves").MicroslipJointSlave


class MicroslipJoint(MicroslipJointSlave):
    """Displacement-driven Iwan joint built from Cattaneo-Mindlin contact parameters."""

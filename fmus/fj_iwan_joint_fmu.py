"""FMU script: IwanJoint.fmu (thin adapter; physics in frictionjoint)."""
from _frictionjoint_loader import library

# the installed frictionjoint where it is this FMU's library byte for byte, else the FMU's own bundle
# (frictionjoint.fmi.bundle_loader)
IwanJointSlave = library(__file__, "fmi.slaves").IwanJointSlave


class IwanJoint(IwanJointSlave):
    """Displacement-driven Segalman 4-parameter Iwan joint."""

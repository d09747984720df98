"""FMU script: IwanJointFmi3.fmu, FMI 3.0 (thin adapter; physics in frictionjoint)."""
from _frictionjoint_loader import library

from pythonfmu3 import Fmi3Slave  # (pythonfmu3's builder and wrapper find the class by this base's name)

# the installed frictionjoint where it is this FMU's library byte for byte, else the FMU's own bundle
# (frictionjoint.fmi.bundle_loader)
IwanJointSlave3 = library(__file__, "fmi.slaves3").IwanJointSlave3


class IwanJointFmi3(IwanJointSlave3, Fmi3Slave):
    """Displacement-driven Iwan joint (FMI 3, early return at stick/slip events)."""

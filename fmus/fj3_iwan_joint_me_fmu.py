"""FMU script: IwanJointMEFmi3, FMI 3.0 Model Exchange (thin adapter; physics in frictionjoint)."""
from _frictionjoint_loader import library

from pythonfmu3 import Fmi3SlaveBase  # (pythonfmu3's builder and wrapper find the class by this base's name)

# the installed frictionjoint where it is this FMU's library byte for byte, else the FMU's own bundle
# (frictionjoint.fmi.bundle_loader)
IwanJointSlaveME3 = library(__file__, "fmi.slaves3").IwanJointSlaveME3


class IwanJointMEFmi3(IwanJointSlaveME3, Fmi3SlaveBase):
    """Displacement-driven Iwan joint: Model Exchange, event indicators for its stick/slip events."""

"""FMU script: FrictionSystemMEFmi3, FMI 3.0 Model Exchange (thin adapter; physics in frictionjoint)."""
from _frictionjoint_loader import library

from pythonfmu3 import Fmi3SlaveBase  # (pythonfmu3's builder and wrapper find the class by this base's name)

# the installed frictionjoint where it is this FMU's library byte for byte, else the FMU's own bundle
# (frictionjoint.fmi.bundle_loader)
SystemSlaveME3 = library(__file__, "fmi.slaves3").SystemSlaveME3


class FrictionSystemMEFmi3(SystemSlaveME3, Fmi3SlaveBase):
    """Linear structure with Jenkins-type joints (the system is data in the FMU's resources): Model Exchange, event indicators for its stick/slip events."""

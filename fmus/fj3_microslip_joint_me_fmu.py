"""FMU script: MicroslipJointMEFmi3, FMI 3.0 Model Exchange (thin adapter; physics in frictionjoint)."""
from _frictionjoint_loader import library

from pythonfmu3 import Fmi3SlaveBase  # (pythonfmu3's builder and wrapper find the class by this base's name)

# the installed frictionjoint where it is this FMU's library byte for byte, else the FMU's own bundle
# (frictionjoint.fmi.bundle_loader)
MicroslipJointSlaveME3 = library(__file__, "fmi.slaves3").MicroslipJointSlaveME3


class MicroslipJointMEFmi3(MicroslipJointSlaveME3, Fmi3SlaveBase):
    """Displacement-driven microslip joint: Model Exchange, event indicators for its stick/slip events."""

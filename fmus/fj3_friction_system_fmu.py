"""FMU script: a friction system FMU, FMI 3.0 (thin adapter; the system is data in the FMU's resources)."""
from _frictionjoint_loader import library

from pythonfmu3 import Fmi3Slave  # (pythonfmu3's builder and wrapper find the class by this base's name)

# the installed frictionjoint where it is this FMU's library byte for byte, else the FMU's own bundle
# (frictionjoint.fmi.bundle_loader)
SystemSlave3 = library(__file__, "fmi.slaves3").SystemSlave3


class FrictionSystemFmi3(SystemSlave3, Fmi3Slave):
    """Linear structure with friction joints, exact stick/slip inside do_step (FMI 3, early return at each event)."""

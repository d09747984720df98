"""FMU script: a friction system FMU, FMI 3.0 (thin adapter; the system is data in the FMU's resources)."""
from _frictionjoint_loader import fresh_bundle

fresh_bundle(__file__)  # this FMU's library, not a freed one's (frictionjoint.fmi.bundle_loader)
from pythonfmu3 import Fmi3Slave  # (pythonfmu3's builder and wrapper find the class by this base's name)
from _frictionjoint_bundle.fmi.slaves3 import SystemSlave3


class FrictionSystemFmi3(SystemSlave3, Fmi3Slave):
    """Linear structure with friction joints, exact stick/slip inside do_step (FMI 3, early return at each event)."""

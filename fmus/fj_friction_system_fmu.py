"""FMU script: a friction system FMU (thin adapter; the system is data in the FMU's resources)."""
from _frictionjoint_loader import fresh_bundle

fresh_bundle(__file__)  # this FMU's library, not a freed one's (frictionjoint.fmi.bundle_loader)
from _frictionjoint_bundle.fmi.system_slave import SystemSlave


class FrictionSystem(SystemSlave):
    """Linear structure with friction joints, exact stick/slip inside do_step."""

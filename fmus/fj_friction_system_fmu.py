"""FMU script: a friction system FMU (thin adapter; the system is data in the FMU's resources)."""
from _frictionjoint_bundle.fmi.system_slave import SystemSlave


class FrictionSystem(SystemSlave):
    """Linear structure with friction joints, exact stick/slip inside do_step."""

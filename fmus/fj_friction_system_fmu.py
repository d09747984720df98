"""FMU script: a friction system FMU (thin adapter; the system is data in the FMU's resources)."""
from _frictionjoint_loader import library

# the installed frictionjoint where it is this FMU's library byte for byte, else the FMU's own bundle
# (frictionjoint.fmi.bundle_loader)
SystemSlave = library(__file__, "fmi.system_slave").SystemSlave


class FrictionSystem(SystemSlave):
    """Linear structure with friction joints, exact stick/slip inside do_step."""

"""FMU script: MicroslipJointFmi3.fmu, FMI 3.0 (thin adapter; physics in the bundled frictionjoint)."""
from _frictionjoint_loader import fresh_bundle

fresh_bundle(__file__)  # this FMU's library, not a freed one's (frictionjoint.fmi.bundle_loader)
from pythonfmu3 import Fmi3Slave  # (pythonfmu3's builder and wrapper find the class by this base's name)
from _frictionjoint_bundle.fmi.slaves3 import MicroslipJointSlave3


class MicroslipJointFmi3(MicroslipJointSlave3, Fmi3Slave):
    """Displacement-driven microslip joint (FMI 3, early return at stick/slip events)."""

"""FMU script: MicroslipJoint.fmu (thin adapter; physics in the bundled frictionjoint)."""
from _frictionjoint_bundle.fmi.slaves import MicroslipJointSlave


class MicroslipJoint(MicroslipJointSlave):
    """Displacement-driven Iwan joint built from Cattaneo-Mindlin contact parameters."""

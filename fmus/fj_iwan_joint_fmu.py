"""FMU script: IwanJoint.fmu (thin adapter; physics in the bundled frictionjoint)."""
from _frictionjoint_bundle.fmi.slaves import IwanJointSlave


class IwanJoint(IwanJointSlave):
    """Displacement-driven Segalman 4-parameter Iwan joint."""

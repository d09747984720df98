"""FMU script: JenkinsJoint.fmu (thin adapter; physics in the bundled frictionjoint)."""
from _frictionjoint_bundle.fmi.slaves import JenkinsJointSlave


class JenkinsJoint(JenkinsJointSlave):
    """Displacement-driven Jenkins joint."""

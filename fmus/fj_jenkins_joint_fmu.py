"""FMU script: JenkinsJoint.fmu (thin adapter; physics in the bundled frictionjoint)."""
from _frictionjoint_loader import fresh_bundle

fresh_bundle(__file__)  # this FMU's library, not a freed one's (frictionjoint.fmi.bundle_loader)
from _frictionjoint_bundle.fmi.slaves import JenkinsJointSlave


class JenkinsJoint(JenkinsJointSlave):
    """Displacement-driven Jenkins joint."""

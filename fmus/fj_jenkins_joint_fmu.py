"""FMU script: JenkinsJoint.fmu (thin adapter; physics in frictionjoint)."""
from _frictionjoint_loader import library

# the installed frictionjoint where it is this FMU's library byte for byte, else the FMU's own bundle
# (frictionjoint.fmi.bundle_loader)
JenkinsJointSlave = library(__file__, "fmi.slaves").JenkinsJointSlave


class JenkinsJoint(JenkinsJointSlave):
    """Displacement-driven Jenkins joint."""

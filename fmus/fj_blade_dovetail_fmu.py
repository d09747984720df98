"""FMU script: BladeDovetail.fmu (thin adapter; physics in frictionjoint)."""
from _frictionjoint_loader import library

# the installed frictionjoint where it is this FMU's library byte for byte, else the FMU's own bundle
# (frictionjoint.fmi.bundle_loader)
BladeDovetailSlave = library(__file__, "fmi.slaves").BladeDovetailSlave


class BladeDovetail(BladeDovetailSlave):
    """Craig-Bampton blade on its dovetail root, harmonic tip force, exact stick/slip inside do_step."""

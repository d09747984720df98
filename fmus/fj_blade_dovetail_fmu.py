"""FMU script: BladeDovetail.fmu (thin adapter; physics in the bundled frictionjoint)."""
from _frictionjoint_loader import fresh_bundle

fresh_bundle(__file__)  # this FMU's library, not a freed one's (frictionjoint.fmi.bundle_loader)
from _frictionjoint_bundle.fmi.slaves import BladeDovetailSlave


class BladeDovetail(BladeDovetailSlave):
    """Craig-Bampton blade on its dovetail root, harmonic tip force, exact stick/slip inside do_step."""

"""FMU script: CoulombOscillator.fmu (thin adapter; physics in frictionjoint)."""
from _frictionjoint_loader import library

# the installed frictionjoint where it is this FMU's library byte for byte, else the FMU's own bundle
# (frictionjoint.fmi.bundle_loader)
CoulombOscillatorSlave = library(__file__, "fmi.slaves").CoulombOscillatorSlave


class CoulombOscillator(CoulombOscillatorSlave):
    """Single-DOF mass on a Coulomb friction surface, spring to a moving base."""

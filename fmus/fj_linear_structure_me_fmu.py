"""FMU script: LinearStructureME, FMI 2.0 Model Exchange (thin adapter; physics in frictionjoint)."""
from _frictionjoint_loader import library

# the installed frictionjoint where it is this FMU's library byte for byte, else the FMU's own bundle
# (frictionjoint.fmi.bundle_loader)
Model = library(__file__, "fmi.model_exchange").LinearStructureME


class LinearStructureME(Model):
    """Linear structure with joint ports (the structure is data in the FMU's resources): Model Exchange, event indicators for its stick/slip events."""

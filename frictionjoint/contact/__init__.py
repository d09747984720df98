"""Contact mechanics that gives joint parameters: Cattaneo-Mindlin microslip (DESIGN.md section 4)."""
from .halfplane import HalfPlaneContact
from .mindlin import MindlinContact
from .profiles import HertzCylinder, Profile, RoundedFlatPunch, Wedge

__all__ = ["HalfPlaneContact", "HertzCylinder", "MindlinContact", "Profile", "RoundedFlatPunch", "Wedge"]

"""Joint elements with exact stick/slip."""
from .coulomb import CoulombSlider
from .dovetail import DovetailRoot
from .iwan import Iwan
from .jenkins import Jenkins
from .patch import FlankPatch, PatchDovetailRoot

__all__ = ["CoulombSlider", "DovetailRoot", "Jenkins", "Iwan", "FlankPatch", "PatchDovetailRoot"]

"""Joint elements with exact stick/slip."""
from .coulomb import CoulombSlider
from .iwan import Iwan
from .jenkins import Jenkins

__all__ = ["CoulombSlider", "Jenkins", "Iwan"]

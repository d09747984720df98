"""Blade models: structures with their root DOFs kept for the root joints, their reduction, and
the model definitions of ``models/``."""
from .assembly import BladeAssembly
from .beam import BENDING, BeamBlade, euler_bernoulli_cantilever
from .lumped import lumped_blade
from .models import MODELS_DIR, BladeModel, load_blade_model
from .reduction import craig_bampton

__all__ = ["BladeAssembly", "BeamBlade", "BENDING", "euler_bernoulli_cantilever", "craig_bampton", "BladeModel", "load_blade_model",
           "MODELS_DIR", "lumped_blade"]

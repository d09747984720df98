"""Blade models: structures with their root DOFs kept for the root joints, and their reduction."""
from .beam import BENDING, BeamBlade, euler_bernoulli_cantilever
from .reduction import craig_bampton

__all__ = ["BeamBlade", "BENDING", "euler_bernoulli_cantilever", "craig_bampton"]

"""Blade models: structures with their root DOFs kept for the root joints, their reduction, the
model definitions of ``models/``, and structures read from the matrices an FE code exports."""
from .assembly import BladeAssembly
from .beam import BENDING, BeamBlade, euler_bernoulli_cantilever
from .fe_import import (FE_FORMATS, FEModel, dof_name, read_dof_table, read_fe_model,
                        read_node_sets)
from .interface import interface_reduction
from .lumped import lumped_blade
from .models import MODELS_DIR, BladeModel, load_blade_model
from .reduction import craig_bampton
from .solid import SolidBlade

__all__ = ["BladeAssembly", "BeamBlade", "BENDING", "euler_bernoulli_cantilever", "craig_bampton", "BladeModel", "load_blade_model",
           "MODELS_DIR", "lumped_blade", "FEModel", "read_fe_model", "read_dof_table", "read_node_sets",
           "FE_FORMATS", "dof_name", "SolidBlade", "interface_reduction"]

"""Design studies: many sweeps of one model over grids, lists and random samples of its
parameters, run on local processes or a Dask cluster (:mod:`.definition`, :mod:`.quantities`,
:mod:`.point`, :mod:`.execution`)."""
from .definition import Grid, ModeDamping, Random, Study, Values, load_study
from .execution import run_study
from .point import evaluate_point
from .quantities import QUANTITIES, quantities

__all__ = ["Grid", "Values", "Random", "Study", "load_study", "run_study", "evaluate_point", "QUANTITIES",
           "quantities", "ModeDamping"]

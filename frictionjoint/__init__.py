"""frictionjoint: exact event-driven dynamics of frictional joints.

Linear structures with Coulomb sliders, Jenkins and Iwan elements, marched exactly from event to
event (no time step, no regularisation), periodic steady states by shooting, and the analytic
single-DOF Coulomb oscillator (Den Hartog 1931; Hong & Liu 2000) they are checked against.
"""
from . import analytic, contact, shakedown
from .elements import CoulombSlider, DovetailRoot, FlankPatch, Iwan, Jenkins, PatchDovetailRoot
from .elements.masing import ContinuousIwan
from .errors import ConvergenceError, FMUError, NoSolutionError, ParameterError
from .excitation import ExternalForce, HarmonicBaseMotion, HarmonicForce
from .frequencies import omega_range
from .oscillator import CoulombOscillator
from .results import PeriodicResponse, TimeResponse
from .solvers.marcher.events import EventLog, Marcher
from .solvers.frequency_domain.continuation import hbm_sweep
from .solvers.frequency_domain.hbm import harmonic_balance
from .solvers.frequency_domain.nonlinear_mode import nonlinear_mode
from .solvers.frequency_domain.mode_synthesis import mode_synthesis
from .campbell import campbell
from .solvers.marcher.response import simulate
from .solvers.marcher.slip_pattern import slip_pattern
from .solvers.sdof.kernel import SdofCoulomb
from .solvers.steady_state import periodic_response
from .regime import RegimeMap, regime_map
from .shakedown import QuasiStaticFrictionSystem, PeriodicLoad, melan_check, shakedown_check
from .structure import LinearStructure
from .study import Study, load_study, run_study
from .sweep import FrequencyResponse, SystemSweep, oscillator_sweep, peak_response, sweep, system_sweep
from .threads import blas_threads, set_blas_threads
from .system import FrictionSystem

__version__ = "0.1.0"

__all__ = [
    "analytic",
    "Study",
    "load_study",
    "run_study",
    "ContinuousIwan",
    "CoulombOscillator",
    "CoulombSlider",
    "DovetailRoot",
    "FlankPatch",
    "PatchDovetailRoot",
    "ConvergenceError",
    "EventLog",
    "FMUError",
    "NoSolutionError",
    "ExternalForce",
    "FrequencyResponse",
    "FrictionSystem",
    "HarmonicBaseMotion",
    "HarmonicForce",
    "harmonic_balance",
    "hbm_sweep",
    "nonlinear_mode",
    "mode_synthesis",
    "slip_pattern",
    "campbell",
    "Iwan",
    "Jenkins",
    "LinearStructure",
    "Marcher",
    "SdofCoulomb",
    "ParameterError",
    "PeriodicResponse",
    "RegimeMap",
    "TimeResponse",
    "contact",
    "shakedown",
    "QuasiStaticFrictionSystem",
    "PeriodicLoad",
    "melan_check",
    "shakedown_check",
    "omega_range",
    "blas_threads",
    "set_blas_threads",
    "oscillator_sweep",
    "periodic_response",
    "regime_map",
    "simulate",
    "SystemSweep",
    "system_sweep",
    "sweep",
    "peak_response",
]

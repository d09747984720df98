"""Result types, one module per family; all of them importable from here.

The result contract: every result has ``success`` (bool), ``status`` (a word) and ``message``
(a sentence), and a failed computation is a status of its result, not an exception; results
of many points (sweeps, maps) keep each point's solver message in ``messages``. Results hold
data only (arrays, words, parameters), so CSV round trips are lossless, and plot with
``plot(ax=None, path=None)``.

- :mod:`.response`: :class:`TimeResponse`, :class:`PeriodicResponse`, :class:`CoSimulationResult`;
- :mod:`.frequency`: :class:`FrequencyResponse`, :class:`SystemSweep`, :class:`OutputSweep`;
- :mod:`.harmonic`: :class:`HarmonicBalance`, :class:`HarmonicBalanceSweep`;
- :mod:`.nonlinear_mode`: :class:`NonlinearMode`, :class:`ModeOrbit`;
- :mod:`.mode_synthesis`: :class:`SynthesisedResponse`;
- :mod:`.campbell`: :class:`CampbellDiagram`;
- :mod:`.slip_pattern`: :class:`SlipPattern`;
- :mod:`.regime_map`: :class:`RegimeMap`;
- :mod:`.shakedown`: :class:`CycleResult`, :class:`MelanResult`, :class:`ShakedownResult`,
  :class:`CriticalLoadFactors`.
"""
from .frequency import FrequencyResponse, OutputSweep, SystemSweep
from .harmonic import HarmonicBalance, HarmonicBalanceSweep
from .nonlinear_mode import ModeOrbit, NonlinearMode
from .mode_synthesis import SynthesisedResponse
from .campbell import CampbellDiagram
from .slip_pattern import SlipPattern
from .regime_map import RegimeMap
from .response import STABILITY_MARGIN, CoSimulationResult, PeriodicResponse, TimeResponse, collection_status
from .shakedown import CriticalLoadFactors, CycleResult, MelanResult, ShakedownResult
from .study import StudyTable

__all__ = ["TimeResponse", "PeriodicResponse", "HarmonicBalance", "HarmonicBalanceSweep", "CoSimulationResult", "FrequencyResponse", "SystemSweep", "OutputSweep",
           "RegimeMap", "CycleResult", "MelanResult", "ShakedownResult", "CriticalLoadFactors", "STABILITY_MARGIN",
           "collection_status", "StudyTable", "NonlinearMode",
           "SynthesisedResponse", "CampbellDiagram", "ModeOrbit", "SlipPattern"]

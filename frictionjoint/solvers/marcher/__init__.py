"""The multi-DOF event-driven marcher: a linear structure with friction joints marched exactly,
closed-form piece by piece between stick/slip/contact events (DESIGN.md, "event-driven marcher").

Modules: :mod:`.propagator` (one configuration's closed-form pieces), :mod:`.patterns` and
:mod:`.consistency` (which configuration follows an event), :mod:`.search` and
:mod:`.piece_kernels` (the compiled event search and piece coefficients), :mod:`.events` (the
:class:`Marcher`), :mod:`.eventlog`, :mod:`.monodromy` (the period map's Jacobian),
:mod:`.steady` (steady states by shooting), :mod:`.response` (time histories and the steady
state's observables), :mod:`.held` (a structure held at its ports, for co-simulation), :mod:`.autonomous` (the
extended periodic motion concept's orbit solved exactly).
"""
from .autonomous import mode_branch, mode_orbit, mode_orbits
from .eventlog import EVENT_KINDS, EventLog, MarchState
from .events import Marcher
from .held import HeldPortStructure
from .monodromy import march_jacobian
from .response import gauss_nodes, simulate
from .slip_pattern import slip_pattern
from .steady import SECTION_MARGIN, failed_response, periodic_response

__all__ = ["Marcher", "EventLog", "MarchState", "EVENT_KINDS", "periodic_response", "simulate",
           "march_jacobian", "failed_response", "HeldPortStructure", "SECTION_MARGIN", "gauss_nodes",
           "mode_orbit", "mode_orbits", "mode_branch", "slip_pattern"]

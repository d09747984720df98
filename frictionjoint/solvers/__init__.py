"""The three engines, each a package with its face in its ``__init__``:

- :mod:`.sdof` -- the single-DOF Coulomb oscillator in closed form (Hong & Liu's stop rules,
  exact stick/slip, its steady state, simulation and monodromy);
- :mod:`.marcher` -- the multi-DOF event-driven marcher: closed-form pieces between events of a
  linear structure with friction joints, the event search, the period map and its Jacobian, the
  steady state by shooting, time histories;
- :mod:`.frequency_domain` -- harmonic balance with exact hysteresis, condensed to the joint
  coordinates, and its continuation over frequency.

Below them, shared: :mod:`.shooting` (Newton on a period map, whichever engine supplies it) and
:mod:`.jit` (the compiled kernels' switch). Imports point down: ``sdof`` uses the marcher's event
log and steady-state helpers through its face, ``frequency_domain`` asks the marcher for the
exact orbit it checks against; the marcher imports neither.
"""

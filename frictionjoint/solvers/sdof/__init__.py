"""The single-DOF Coulomb oscillator in closed form: :class:`SdofCoulomb` (exact stick/slip with
Hong & Liu's stop rules), its steady state (:func:`sdof_periodic_response`, closed-form monodromy)
and simulation (:func:`sdof_simulate`). Uses the marcher's event log and steady-state helpers
through :mod:`..marcher`'s face."""
from .kernel import EVENT_KINDS, EventBudgetError, QUASI_STATIC_TOL, SdofCoulomb, SdofResult, event_kind
from .simulate import sdof_simulate
from .steady import exp_integral, quasi_static_response, sdof_orbit, sdof_periodic_response, sdof_piece_fourier

__all__ = ["SdofCoulomb", "SdofResult", "EventBudgetError", "event_kind", "EVENT_KINDS", "QUASI_STATIC_TOL",
           "sdof_simulate", "sdof_periodic_response", "sdof_orbit", "sdof_piece_fourier", "exp_integral",
           "quasi_static_response"]

"""The periodic steady state users call: the marcher's exact shooting, started where it is cheapest.

The exact steady state is the fixed point of the marcher's period map
(:func:`frictionjoint.solvers.marcher.periodic_response`); where Newton starts decides its cost,
not its answer. From rest it first marches the transient (a period, then Newton steps far from
the orbit, whose Jacobians cost ``pieces x n^2 x (2n + sliders)`` each and whose periods meet
configurations the orbit never visits). A structure large enough for that to dominate is started
instead on the harmonic-balance orbit (:func:`frictionjoint.solvers.frequency_domain.harmonic_balance`,
``H = 7``: the joint coordinates' balance, a fraction of one period's march), within about 1e-4
of the exact orbit; Newton then converges in two Jacobians.

The answer is the marcher's either way, to its tolerance. Only where more than one orbit exists
could the start choose another: a balance start that ends on an orbit that is not unique (a
family, e.g. of stuck orbits with different rest positions) or does not converge is discarded
and the search starts from rest as before, so that such cases keep the member they had.
"""
from __future__ import annotations

from numpy.typing import ArrayLike
import numpy as np

from ..errors import ParameterError
from ..results import PeriodicResponse
from ..system import FrictionSystem
from ..threads import owns_blas_threads
from .frequency_domain import balanced_state, harmonic_balance
from .marcher import periodic_response as march_to_orbit

__all__ = ["periodic_response", "STARTS", "BALANCE_START_SIZE", "BALANCE_START_HARMONICS"]

#: where the search starts: ``'auto'`` (the balance for large structures, else rest), ``'rest'``,
#: ``'harmonic_balance'``
STARTS = ("auto", "rest", "harmonic_balance")
#: ``'auto'`` starts on the balanced orbit where the state ``2 n + sliders`` is larger than this
#: (the marcher's chord-iteration size: where a Jacobian costs more than periods)
BALANCE_START_SIZE = 64
#: harmonics of the starting balance (its error, about 1e-4 of the orbit on the benchmark chains,
#: leaves two Newton steps; more harmonics cost more than the step they save)
BALANCE_START_HARMONICS = 7


@owns_blas_threads
def periodic_response(system: FrictionSystem, x0: ArrayLike = 0.0, v0: ArrayLike = 0.0,
                      w0: ArrayLike | None = None, *, start: str = "auto", **options) -> PeriodicResponse:
    """Periodic steady state of a harmonically excited :class:`~frictionjoint.system.FrictionSystem`,
    exact (the marcher's shooting, :func:`frictionjoint.solvers.marcher.periodic_response`).

    Parameters
    ----------
    system : FrictionSystem
        Must have harmonic excitation (``omega > 0``).
    x0, v0, w0 :
        Initial guess (state at ``t = 0``) [m, m/s, m]; given, the search starts there.
    start : {'auto', 'rest', 'harmonic_balance'}
        Without an initial guess: from the harmonic-balance orbit (``H = 7``) or from rest.
        ``'auto'`` takes the balance where the state (``2 n_dof + n_sliders``) is larger than
        :data:`BALANCE_START_SIZE` and the balance applies (no held external force, no marcher with
        a held force), and goes back to rest where the orbit found from the balance is not unique
        or was not found (the answer a start from rest gives where orbits coexist).
    **options :
        ``marcher``, ``tol``, ``max_newton``, ``max_periods``, ``n_samples``, ``jacobian``,
        ``peaks``: as :func:`frictionjoint.solvers.marcher.periodic_response`.

    Returns
    -------
    PeriodicResponse
        Its ``message`` says where a balance start was taken.
    """
    if start not in STARTS:
        raise ParameterError(f"start must be one of {STARTS}, got {start!r}")
    guessed = w0 is not None or np.any(np.asarray(x0) != 0) or np.any(np.asarray(v0) != 0)
    if start == "harmonic_balance" and guessed:
        raise ParameterError("start='harmonic_balance' takes no initial guess x0, v0, w0 (the balance is the guess)")
    if start == "harmonic_balance" or (start == "auto" and not guessed and _balance_pays(system, options)):
        found = _from_balance(system, options, strict=start == "harmonic_balance")
        if found is not None:
            return found
    return march_to_orbit(system, x0, v0, w0, **options)


def _balance_pays(system, options) -> bool:
    """``'auto'``: a structure large enough for the transient's Jacobians to dominate, a system the
    balance takes (sliders, harmonic excitation, no held external force, no held port force)."""
    if not isinstance(system, FrictionSystem) or system.omega <= 0 or system.n_sliders == 0 or system.external:
        return False
    marcher = options.get("marcher")
    if marcher is not None and marcher.held_force is not None:
        return False
    return 2 * system.n_dof + system.n_sliders > BALANCE_START_SIZE


def _from_balance(system, options, strict: bool) -> PeriodicResponse | None:
    """The exact orbit from the balanced one; None (start from rest) where ``'auto'`` should not keep
    it: the balance refuses the system or did not converge, it sticks all over (the stuck orbit
    from rest is a closed form), or the orbit found is not unique or not found."""
    try:
        hb = harmonic_balance(system, n_harmonics=BALANCE_START_HARMONICS, peaks=False)
    except ParameterError:
        if strict:
            raise
        return None  # e.g. the linear part singular at a harmonic: rest decides
    if not strict and (not hb.converged or hb.stuck):
        return None
    x0, v0, w0 = balanced_state(system, hb.harmonics, hb.slider_positions)
    res = march_to_orbit(system, x0, v0, w0, **options)
    if not strict and not (res.converged and res.unique):
        return None
    res.message += f"; started from the harmonic-balance orbit (H = {BALANCE_START_HARMONICS})"
    return res

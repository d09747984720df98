"""The frequency domain: multi-harmonic balance with exact hysteresis, condensed to the joint
coordinates (:func:`harmonic_balance`), its continuation over frequency (:func:`hbm_sweep`), the
hysteresis loops of the joint elements (:mod:`.hysteresis`, compiled kernels in
:mod:`.loop_kernels`). Asks the marcher (:mod:`..marcher`) for the exact orbit it checks against."""
from .continuation import hbm_sweep
from .hbm import Condensed, balanced_state, exact_orbit, harmonic_balance, hill_exponents, lyapunov_stable, truncation_error

__all__ = ["harmonic_balance", "hbm_sweep", "Condensed", "balanced_state", "exact_orbit", "lyapunov_stable", "truncation_error",
           "hill_exponents"]

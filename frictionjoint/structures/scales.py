"""The range of floating-point numbers a blade model's matrices must stay within (issue 39).

A blade's mass and stiffness entries and its squared frequencies are products of its parameters
(``rho V``, ``E V / d^2``, ``E / (rho d^2)``, ``rho Omega^2 R L V / d^2``, ...). The eigensolvers
form products of up to three such quantities (ARPACK's mass inner products of shift-inverted
vectors, ``v^T M v`` with ``v ~ K^-1 M v``; LAPACK's scaled reductions), so each quantity must lie
within the cube root of the normal floating-point range, ``[2.8e-103, 5.6e102]``: beyond, the
products underflow or overflow and the solvers fail (ARPACK error -9, "starting vector is zero", at
a density of 1e-300 or a Young's modulus of 1e300) or, worse, return a wrong answer without a word
(a solid blade of E 1e-180 times titanium's gave its first frequency 4 to 7 times too high, on
meshes of 3 to 10 elements along the span). Measured on a 6 x 2 x 1 solid blade: the frequencies
follow their exact scaling ``sqrt(E / rho)`` to 1e-8 for E from 1e-160 to 1e140 and rho from 1e-100
to 1e140 times titanium's; inside the window they do, with tens of decades to spare.

The rotor speed's terms only have an upper bound: a slow rotor's ``Omega^2`` that underflows to 0
is the right answer to rounding (its stiffening is below the elastic stiffness's last digit).

:func:`check_scales` names the parameter that takes a quantity out of the window and the range it
may take with the others as given.
"""
from __future__ import annotations

import math

from ..errors import ParameterError

__all__ = ["LOG_LOW", "LOG_HIGH", "check_scales"]

#: log10 of the window's ends: the cube roots of the smallest normal and the largest float
LOG_LOW = math.log10(2.2250738585072014e-308) / 3
LOG_HIGH = math.log10(1.7976931348623157e308) / 3


def check_scales(scales: dict, parameters: dict) -> None:
    """Refuse a model whose quantities leave the window ``[10^LOG_LOW, 10^LOG_HIGH]``.

    Parameters
    ----------
    scales : dict
        ``name -> (log10 of the quantity, {parameter: exponent}, bounded_below)``: each quantity
        as a power law in the named parameters (the others' contribution in the constant).
    parameters : dict
        ``name -> value`` of the parameters the power laws name (> 0).

    Raises
    ------
    ParameterError
        Naming the parameter furthest outside its allowed range (given the others), that range,
        and the quantity it takes out of the window.
    """
    bad = [(name, log) for name, (log, _, below) in scales.items()
           if log > LOG_HIGH or (below and log < LOG_LOW)]
    if not bad:
        return
    outside = []  # (decades outside, parameter, value, log10 range) of each parameter outside a range it could be in
    for p, value in parameters.items():
        if not value > 0:
            continue
        lo, hi = -math.inf, math.inf
        logp = math.log10(value)
        for log, exps, below in scales.values():
            a = exps.get(p, 0)
            if a == 0:
                continue
            rest = log - a * logp
            ends = [(LOG_HIGH - rest) / a, (LOG_LOW - rest) / a if below else (-math.inf if a > 0 else math.inf)]
            lo, hi = max(lo, min(ends)), min(hi, max(ends))
        out = max(lo - logp, logp - hi)
        if lo <= hi and out > 0:
            outside.append((out, p, value, lo, hi))
    name, log = max(bad, key=lambda b: max(b[1] - LOG_HIGH, LOG_LOW - b[1]))
    what = (f"its {name} would be about 1e{log:.0f}, outside [{10 ** LOG_LOW:.2g}, {10 ** LOG_HIGH:.2g}], the range "
            f"in which the eigensolvers' products of such numbers stay finite and normal")
    if not outside:
        raise ParameterError(f"the blade's dimensions and material ({', '.join(f'{k} = {v!r}' for k, v in parameters.items())}) "
                             f"are out of range together: {what}")

    def allowed(p, value, lo, hi):
        span = f"[{10 ** lo:.3g}, {10 ** hi:.3g}]" if lo > -math.inf else f"[0, {10 ** hi:.3g}]"
        return f"{p} must be in {span} with the blade's other parameters as given, got {value!r}"

    outside.sort(reverse=True)
    others = "".join(f" (or {allowed(*o[1:])})" for o in outside[1:])
    raise ParameterError(f"{allowed(*outside[0][1:])}{others}: {what}")

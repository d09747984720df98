"""Segalman's 4-parameter Iwan element as a continuous backbone (ContinuousIwan.segalman).

Reference: Segalman (2005), "A four-parameter Iwan model for lap-type joints", J. Appl. Mech. 72:
density ``R phi**chi`` on ``(0, phi_max)`` plus ``S delta(phi - phi_max)``. The closed forms below
(DESIGN.md section 4, and the one beyond phi_max derived here) were checked with sympy:
``F = K_T u - R u**(chi+2)/((chi+1)(chi+2))`` for ``u <= phi_max`` and ``F_S`` beyond;
``D = 4 R u0**(chi+3)/((chi+2)(chi+3))`` for ``u0 <= phi_max``; beyond it every slider slips and
``D = 4 R phi_max**(chi+3)/((chi+2)(chi+3)) + 4 F_S (u0 - phi_max)``.
"""
import math

import numpy as np
import pytest

import frictionjoint as fj
from frictionjoint.elements.masing import ContinuousIwan

CLOSED = 1e-10   # relative, continuous element vs closed form
FS, KT = 2.0, 1e5
PARAMS = [(-0.5, 0.3), (-0.9, 0.0), (-0.1, 2.0), (0.0, 0.5), (-0.3, 0.0)]


def segalman(chi, beta):
    """phi_max, R, S from Segalman's parameters (his eqs., written out independently here)."""
    c = (chi + 1) / (chi + 2)
    phi_max = FS * (1 + beta) / (KT * (beta + c))
    r = FS * (chi + 1) / (phi_max ** (chi + 2) * (beta + c))
    s = FS * beta / (phi_max * (beta + c))
    return phi_max, r, s


def closed_dissipation(chi, beta, u0):
    phi_max, r, _ = segalman(chi, beta)
    d = 4 * r * min(u0, phi_max) ** (chi + 3) / ((chi + 2) * (chi + 3))
    return d + 4 * FS * max(u0 - phi_max, 0.0)


@pytest.mark.parametrize("chi,beta", PARAMS)
def test_dissipation_closed_form(chi, beta):
    """Below phi_max (down to 1e-4 phi_max) and beyond it, <= 1e-10 relative."""
    iw = ContinuousIwan.segalman(FS, KT, chi, beta)
    phi_max = segalman(chi, beta)[0]
    assert abs(iw.slip_displacement / phi_max - 1) <= 1e-15
    for frac in (1e-4, 1e-2, 0.3, 0.999, 1.0, 1.001, 2.0, 10.0):
        exact = closed_dissipation(chi, beta, frac * phi_max)
        assert abs(iw.dissipation_per_displacement_cycle(frac * phi_max) / exact - 1) <= CLOSED, frac


@pytest.mark.parametrize("chi,beta", PARAMS)
def test_masing_with_the_closed_form_primitive(chi, beta):
    """Masing's ``8 int F - 4 u* F(u*)`` from the backbone by quadrature (no density, no point
    slider) gives the same dissipation: the delta's share is in the backbone's slope jump."""
    iw = ContinuousIwan.segalman(FS, KT, chi, beta)
    phi_max = iw.slip_displacement
    plain = ContinuousIwan(iw.backbone, KT, FS, phi_max)
    for frac in (0.3, 0.999, 1.5):
        exact = closed_dissipation(chi, beta, frac * phi_max)
        assert abs(plain.dissipation_per_displacement_cycle(frac * phi_max) / exact - 1) <= CLOSED


@pytest.mark.parametrize("chi,beta", PARAMS)
def test_backbone_stiffness_slip_force_and_continuity(chi, beta):
    iw = ContinuousIwan.segalman(FS, KT, chi, beta)
    phi_max, r, s = segalman(chi, beta)
    assert iw.stiffness == KT and iw.slip_force == FS
    # K_T and F_S are the integrals of the density (Segalman's normalisation)
    assert abs(r * phi_max ** (chi + 1) / (chi + 1) + s - KT) <= 1e-12 * KT
    assert abs(r * phi_max ** (chi + 2) / (chi + 2) + s * phi_max - FS) <= 1e-12 * FS
    # continuous at phi_max with F = F_S, constant beyond, odd
    below, at, above = iw.backbone([phi_max * (1 - 1e-12), phi_max, phi_max * 1.5])
    assert abs(below - FS) <= 1e-10 * FS and abs(at - FS) <= 1e-14 * FS and above == at
    assert iw.backbone(-0.5 * phi_max) == -iw.backbone(0.5 * phi_max)
    # slopes: K_T at 0, S just below phi_max (the delta's sliders), 0 beyond
    h = 1e-6 * phi_max
    deficit = [1 - iw.backbone(u) / (KT * u) for u in (h, h / 100)]  # R u^(chi+1)/(K_T (chi+1)(chi+2))
    assert deficit[0] < 0.5 and abs(deficit[0] / deficit[1] / 100 ** (chi + 1) - 1) <= 1e-6
    slope = (iw.backbone(phi_max) - iw.backbone(phi_max - h)) / h
    assert abs(slope - s) <= 1e-5 * KT


@pytest.mark.parametrize("chi,beta", [(-0.5, 0.3), (-0.2, 0.0)])
def test_force_inverse_and_dissipation_per_force_cycle(chi, beta):
    """No closed-form inverse: Brent's method to rounding (regression: its rtol was below scipy's
    floor 4 eps and raised ValueError)."""
    iw = ContinuousIwan.segalman(FS, KT, chi, beta)
    for q in (1e-6, 0.3, 1.0, 1.9):
        u = iw.displacement(q)
        assert abs(iw.backbone(u) / q - 1) <= 4e-15
        assert abs(iw.dissipation_per_cycle(q) / closed_dissipation(chi, beta, u) - 1) <= CLOSED


def test_discrete_iwan_converges_second_order():
    """Iwan.segalman(n_sliders=N) -> the continuous element: dissipation error O(N^-2) (each
    slider sits at its interval's centroid), backbone sup error O(N^-(chi+2)) (first interval)."""
    chi, beta = -0.5, 0.3
    cont = ContinuousIwan.segalman(FS, KT, chi, beta)
    phi_max = cont.slip_displacement
    ns = (20, 40, 80, 160)
    for frac in (0.5, 0.9, 1.3):
        exact = cont.dissipation_per_displacement_cycle(frac * phi_max)
        err = [abs(fj.Iwan.segalman(FS, KT, chi, beta, n_sliders=n).dissipation_per_displacement_cycle(
            frac * phi_max) / exact - 1) for n in ns]
        rates = np.log2(np.array(err[:-1]) / np.array(err[1:]))
        assert np.all((rates > 1.9) & (rates < 2.1)), rates  # measured 2.00-2.01
        assert err[-1] <= 1e-4                                 # measured 9.8e-5, 3.0e-5, 1.0e-5
    sup = []
    for n in ns:  # the largest error is near the first slider, u ~ phi_max / N
        u = np.concatenate([np.linspace(0.0, 4 * phi_max / n, 4001), np.linspace(0.0, 1.2 * phi_max, 2001)])
        sup.append(np.max(np.abs(fj.Iwan.segalman(FS, KT, chi, beta, n_sliders=n).backbone(u) - cont.backbone(u))))
    rates = np.log2(np.array(sup[:-1]) / np.array(sup[1:]))
    assert np.all(np.abs(rates - (chi + 2)) < 0.05), rates


def test_force_power_law_only_asymptotic():
    """D vs the power law ``4 R (F0/K_T)**(chi+3)/((chi+2)(chi+3))``: the relative excess tends to
    ``(chi+3) eps``, ``eps = R (F0/K_T)**(chi+1) / (K_T (chi+1)(chi+2))`` (from u = (F0/K_T)(1 + eps
    + ...)), and at moderate amplitude it is large: +88 % at F0 = 0.3 F_S, +147 % at 0.5 F_S
    (chi = -0.5, beta = 0.3)."""
    chi, beta = -0.5, 0.3
    iw = ContinuousIwan.segalman(FS, KT, chi, beta)
    _, r, _ = segalman(chi, beta)

    def excess(f0):
        return iw.dissipation_per_cycle(f0) / (4 * r * (f0 / KT) ** (chi + 3) / ((chi + 2) * (chi + 3))) - 1

    for f0 in (1e-6 * FS, 1e-5 * FS):
        eps = r * (f0 / KT) ** (chi + 1) / (KT * (chi + 1) * (chi + 2))
        assert abs(excess(f0) / ((chi + 3) * eps) - 1) <= 10 * eps
    assert abs(excess(0.1 * FS) - 0.3793) <= 1e-3
    assert abs(excess(0.3 * FS) - 0.8750) <= 1e-3
    assert abs(excess(0.5 * FS) - 1.4674) <= 1e-3


@pytest.mark.parametrize("kwargs,match", [
    (dict(chi=-1.0), "chi"), (dict(chi=0.2), "chi"), (dict(chi=math.nan), "chi"),
    (dict(beta=-0.1), "beta"), (dict(slip_force=0.0), "slip_force"), (dict(stiffness=-1.0), "stiffness"),
])
def test_invalid(kwargs, match):
    args = dict(slip_force=FS, stiffness=KT, chi=-0.5, beta=0.3)
    args.update(kwargs)
    with pytest.raises(fj.ParameterError, match=match):
        ContinuousIwan.segalman(**args)


def test_invalid_point_sliders():
    with pytest.raises(fj.ParameterError, match="point_sliders"):
        ContinuousIwan(lambda u: u, 1.0, 1.0, 1.0, point_sliders=[(1.0, -1.0)])
    with pytest.raises(fj.ParameterError, match="point_sliders"):
        ContinuousIwan(lambda u: u, 1.0, 1.0, 1.0, point_sliders=[1.0])

"""The Craig-Bampton Ti-6Al-4V blade on its rocking dovetail root (models/ti64_compressor_blade.toml):
the nonlinear resonance between the root's two linear limits and the friction-damper curve."""
import numpy as np
import pytest
import scipy.optimize

from frictionjoint.linear_limits import limit_structures
from frictionjoint.structures import BladeAssembly, load_blade_model

pytestmark = pytest.mark.slow


@pytest.fixture(scope="module")
def blade():
    return BladeAssembly.from_model(load_blade_model("ti64_compressor_blade"))


def _linear_peak(asm, limit):
    """Peak of the tip receptance of a linear limit (LinearStructure.harmonic_response, Brent)."""
    st = limit_structures(asm.system(1000.0))[limit]
    row = asm._row("w30")
    f = asm._force

    def neg(w):
        return -abs(st.harmonic_response([w], f)[0] @ row)
    w_n = float(np.min(st.natural_frequencies()[st.natural_frequencies() > 100.0]))
    res = scipy.optimize.minimize_scalar(neg, bounds=(0.9 * w_n, 1.1 * w_n), method="bounded",
                                         options={"xatol": 1e-9 * w_n})
    return float(res.x), -float(res.fun)


def test_damper_curve_has_a_minimum_between_the_linear_limits(blade):
    """Peak tip amplitude for 1 N at the tip against the root's centrifugal load Fc (the blade's own,
    19.4 kN at 9550 rpm, scaled): at full load the root sticks and the peak is the stuck-root
    linear peak (to 1e-9); at 19 N the flanks slip freely and the peak sits at the free-slip
    limit's first frequency (the root rolling on its flanks, 1707 rad/s); in between friction
    damps the resonance, with a minimum 20x below either end (measured: 2.23 mm at 19 N, 0.106
    mm at 42 N, 0.117 mm at 90 N, 2.00 mm at 1.9 kN, 3.72 mm at 19 kN)."""
    w_stuck, a_stuck = _linear_peak(blade, "stuck")
    w_slip, a_slip = _linear_peak(blade, "slipping")
    assert 2030 < w_stuck < 2040 and 1700 < w_slip < 1715  # the rocking root's two limits
    fc0 = blade.joints[0].centrifugal_force
    curve = {}
    for scale in (1e-3, 2.154e-3, 4.642e-3, 0.1, 1.0):
        # one resonance in 1600-2200 rad/s: 13 grid points bracket it (the same peaks as 41 to 3e-11 in
        # amplitude); xtol 1e-7 for the 1e-9 check at full load, 1e-5 elsewhere (a flat top: amplitudes
        # the same to 4e-11, peaks within 4e-6 in omega against the 1e-3 bounds): 20 -> 8 s
        w, amp = blade.with_root(centrifugal_force=scale * fc0).peak(1600.0, 2200.0, "w30", n_grid=13,
                                                                     xtol=1e-7 if scale == 1.0 else 1e-5)
        curve[scale] = (w, amp)
        assert w_slip * (1 - 1e-3) <= w <= w_stuck * (1 + 1e-3)  # between the limits
    assert curve[1.0][1] == pytest.approx(a_stuck, rel=1e-9)
    assert curve[1.0][0] == pytest.approx(w_stuck, rel=1e-5)
    assert curve[1e-3][0] == pytest.approx(w_slip, rel=2e-3)
    amps = np.array([a for _, a in curve.values()])
    k = int(np.argmin(amps))
    assert 0 < k < amps.size - 1  # an interior minimum: the friction-damper optimum
    assert amps[k] < amps[0] / 20 and amps[k] < amps[-1] / 20

"""Tests of frictionjoint.sweep (stepped-sine sweeps) and of the forced-response plots.

Reference values: Den Hartog's closed form (frictionjoint.analytic.den_hartog_response;
DESIGN.md section 3), which is the exact steady motion of the undamped oscillator wherever it
is stop-free. The exact simulation must agree with it to RTOL.
"""
import csv
import math
import warnings

import numpy as np
import pytest

import frictionjoint
from frictionjoint.analytic import den_hartog_response
from frictionjoint.errors import ParameterError
from frictionjoint.sweep import FrequencyResponse, den_hartog_curve, oscillator_sweep, sweep

RTOL = 1e-9  # relative amplitude and phase error against Den Hartog at stop-free points
PNG_MAGIC = b"\x89PNG\r\n\x1a\n"

# m = k = P0 = 1, F/P0 = 0.3: stop-free at all these r (Den Hartog's boundary is above 0.3)
RATIOS = [0.8, 0.9, 1.1, 1.5, 2.0]


@pytest.fixture(scope="module")
def both():
    return oscillator_sweep(1.0, 1.0, 0.3, 1.0, RATIOS, direction="both")


@pytest.fixture(scope="module")
def with_stops():
    # r = 0.45, F/P0 = 0.5: two stops per cycle (Hong & Liu); r = 1.5: stop-free
    return oscillator_sweep(1.0, 1.0, 0.5, 1.0, [0.45, 1.5], direction="up")


def test_stop_free_points_agree_with_den_hartog(both):
    assert len(both) == 2 * len(RATIOS)
    assert both.success
    assert np.all(both.regime == "stop-free")
    assert np.all(both.analytic_regime == "stop-free")
    assert both.applicable.all()
    assert both.amplitude_error.count() == len(both)
    assert float(both.amplitude_error.max()) <= RTOL
    assert float(both.phase_error.max()) <= RTOL
    # independently of the stored columns
    for w, amp, ph in zip(both.omega, both.amplitude, both.phase):
        dh = den_hartog_response(1.0, 1.0, 0.3, 1.0, float(w))
        assert dh.applicable
        assert abs(amp - dh.amplitude) <= RTOL * dh.amplitude
        assert abs(ph - dh.phase) <= RTOL * abs(dh.phase)
    amp_err, ph_err = both.max_error()
    assert amp_err <= RTOL and ph_err <= RTOL


def test_branch_order_and_labels(both):
    up, down = both.select("up"), both.select("down")
    assert list(both.branch) == ["up"] * 5 + ["down"] * 5
    assert np.all(np.diff(up.omega) > 0)
    assert np.all(np.diff(down.omega) < 0)
    assert len(up.messages) == len(up) == 5
    with pytest.raises(ParameterError, match="branch"):
        both.select("sideways")
    only_down = oscillator_sweep(1.0, 1.0, 0.3, 1.0, [2.0, 0.8, 1.5], direction="down")
    assert list(only_down.branch) == ["down"] * 3
    np.testing.assert_array_equal(only_down.omega, [2.0, 1.5, 0.8])


def test_up_and_down_branches_agree_where_unique(both):
    up, down = both.select("up"), both.select("down")
    order = np.argsort(down.omega)
    np.testing.assert_array_equal(up.omega, down.omega[order])
    unique = up.unique & down.unique[order]
    assert unique.all()
    np.testing.assert_allclose(down.amplitude[order][unique], up.amplitude[unique], rtol=RTOL, atol=0)
    np.testing.assert_allclose(down.phase[order][unique], up.phase[unique], rtol=RTOL, atol=0)


def test_frequency_ratio_scales_with_natural_frequency():
    # m = 4, k = 9: wn = 1.5 rad/s; r = omega/wn
    fr = oscillator_sweep(4.0, 9.0, 0.3 * 2.0, 2.0, [1.2, 2.25], direction="up")
    assert fr.natural_frequency == pytest.approx(1.5)
    np.testing.assert_allclose(fr.frequency_ratio, [0.8, 1.5])
    assert float(fr.amplitude_error.max()) <= RTOL


def test_state_is_carried_from_point_to_point(monkeypatch):
    calls = []
    original = frictionjoint.CoulombOscillator.steady_state

    def spy(self, x0=None, v0=None, **kwargs):
        res = original(self, x0=x0, v0=v0, **kwargs)
        calls.append((self.omega, x0, v0, res))
        return res

    monkeypatch.setattr(frictionjoint.CoulombOscillator, "steady_state", spy)
    oscillator_sweep(1.0, 1.0, 0.3, 1.0, [1.5, 1.6, 1.7], direction="both")
    assert [c[0] for c in calls] == [1.5, 1.6, 1.7, 1.7, 1.6, 1.5]
    assert calls[0][1] is None and calls[0][2] is None  # the first point starts from the estimate
    for prev, cur in zip(calls, calls[1:]):
        assert cur[1] == prev[3].initial_state[0]
        assert cur[2] == prev[3].initial_state[1]


def test_stop_regime_points_are_marked(with_stops):
    fr = with_stops
    assert list(fr.regime) == ["stops", "stop-free"]
    assert fr.stops_per_cycle[0] == 2
    assert list(fr.analytic_regime) == ["stops", "stop-free"]
    mask = np.ma.getmaskarray(fr.analytic_amplitude)
    assert list(mask) == [True, False]
    assert list(np.ma.getmaskarray(fr.amplitude_error)) == [True, False]
    # NaN-free: masked entries hold finite filler values
    for name in ("analytic_amplitude", "analytic_phase", "amplitude_error", "phase_error"):
        assert np.all(np.isfinite(getattr(fr, name).data)), name
    assert float(fr.amplitude_error[1]) <= RTOL
    lines = fr.table().splitlines()
    row = [ln for ln in lines if ln.startswith("up") and " 0.4500 " in ln]
    assert len(row) == 1
    cells = row[0].split()
    assert cells[-2:] == ["stops", "2"]   # regime word instead of the error, then stops/cycle
    assert cells[-3] == "-"               # no Den Hartog amplitude
    assert "1 point with stops" in fr.table()


def test_unbounded_resonance_is_reported():
    fr = oscillator_sweep(1.0, 1.0, 0.3, 1.0, [1.0], direction="up")
    assert fr.regime[0] == "unbounded"
    assert not fr.converged[0] and not fr.success
    assert fr.analytic_regime[0] == "unbounded"
    assert np.ma.getmaskarray(fr.amplitude_error)[0]
    row = fr.table().splitlines()[2].split()
    assert row[3] == "unbounded" and row[5] == "unbounded"


def test_damped_sweep_has_no_closed_form():
    fr = oscillator_sweep(1.0, 1.0, 0.3, 1.0, [1.5], damping=0.05)
    assert fr.analytic_regime[0] == "damped"
    assert np.ma.getmaskarray(fr.analytic_amplitude).all()
    assert fr.analytic_curve([1.5]) is None
    assert "damped" in fr.table()
    assert fr.parameters["damping"] == 0.05


def test_base_excitation_matches_den_hartog():
    # P = 0.4 N plus base motion Y = 0.6 m through k = 1: P0 = 1 N
    fr = oscillator_sweep(1.0, 1.0, 0.3, 0.4, [0.9, 1.5], base_amplitude=0.6)
    assert float(fr.amplitude_error.max()) <= RTOL
    assert float(fr.phase_error.max()) <= RTOL


def test_den_hartog_curve_masks_where_not_applicable():
    amp, ph, regime = den_hartog_curve([0.45, 1.0, 1.5], 1.0, 1.0, 0.5, 1.0)
    assert list(np.ma.getmaskarray(amp)) == [True, True, False]
    assert list(regime) == ["stops", "unbounded", "stop-free"]
    assert amp[2] == pytest.approx(den_hartog_response(1, 1, 0.5, 1, 1.5).amplitude, rel=1e-15)


def test_csv_round_trip(both, with_stops, tmp_path):
    for fr, name in ((both, "both.csv"), (with_stops, "stops.csv")):
        path = tmp_path / name
        fr.to_csv(path)
        back = FrequencyResponse.from_csv(path)
        for field in ("omega", "amplitude", "phase", "harmonic_amplitude", "periods",
                      "stops_per_cycle", "stuck", "converged", "unique", "regime", "branch",
                      "analytic_regime"):
            np.testing.assert_array_equal(getattr(back, field), getattr(fr, field), err_msg=field)
        for field in ("analytic_amplitude", "analytic_phase", "amplitude_error", "phase_error"):
            np.testing.assert_array_equal(np.ma.getmaskarray(getattr(back, field)),
                                          np.ma.getmaskarray(getattr(fr, field)), err_msg=field)
            np.testing.assert_array_equal(getattr(back, field).compressed(),
                                          getattr(fr, field).compressed(), err_msg=field)
        assert back.message == fr.message
        assert back.natural_frequency == fr.natural_frequency
        assert back.parameters == fr.parameters
        assert back.table() == fr.table()
    # plain CSV readers see one header and one row per point (comment lines first)
    with open(tmp_path / "stops.csv", newline="") as fh:
        rows = [r for r in csv.reader(line for line in fh if not line.startswith("#"))]
    assert rows[0][:3] == ["branch", "omega", "frequency_ratio"]
    assert len(rows) == 1 + len(with_stops)
    assert rows[1][rows[0].index("analytic_amplitude")] == ""


def test_plot_writes_png(both, with_stops, tmp_path):
    for fr, name in ((both, "both.png"), (with_stops, "stops.png")):
        path = tmp_path / name
        fig = fr.plot(path)
        assert path.read_bytes()[:8] == PNG_MAGIC
        assert len(fig.axes) == 2
    path = tmp_path / "amp_only.png"
    fig = both.plot(path, phase=False)
    assert len(fig.axes) == 1 and path.read_bytes()[:8] == PNG_MAGIC


def test_plot_without_analytic_reference(with_stops, tmp_path):
    # a generic response (e.g. read back from CSV): no reference curve, no natural frequency
    path = tmp_path / "r.csv"
    with_stops.to_csv(path)
    fr = FrequencyResponse.from_csv(path)
    fr.natural_frequency = None
    assert fr.frequency_ratio is None
    fr.plot(tmp_path / "generic.png")
    assert (tmp_path / "generic.png").read_bytes()[:8] == PNG_MAGIC
    assert " - " in fr.table().splitlines()[2]


def test_time_response_plot(tmp_path):
    osc = frictionjoint.CoulombOscillator(1.0, 1.0, 0.5, 1.0, 0.45)
    tr = osc.simulate(30.0)
    ax = tr.plot()
    assert ax.get_xlabel() == "time [s]"
    ax.figure.savefig(tmp_path / "tr.png")
    assert (tmp_path / "tr.png").read_bytes()[:8] == PNG_MAGIC


def test_progress_bar_goes_to_stderr(capsys):
    oscillator_sweep(1.0, 1.0, 0.3, 1.0, [1.5], progress=True)
    captured = capsys.readouterr()
    assert captured.out == ""
    assert "sweep" in captured.err


def test_solver_failure_is_retried_then_reported(monkeypatch):
    """A failed march is a status of the steady state ('failed'), not an exception: the sweep
    retries from the default estimate, then reports the point as not converged."""
    from frictionjoint.solvers.marcher.steady import failed_response

    original = frictionjoint.CoulombOscillator.steady_state
    failures = {"n": 0}

    def failed(self, message):
        res = failed_response(self.omega, 1, f"the march failed: {message}")
        res.amplitude = res.phase = res.harmonic_amplitude = math.nan
        return res

    def flaky(self, x0=None, v0=None, **kwargs):
        if x0 is not None:  # fails from a carried state, works from the default estimate
            failures["n"] += 1
            return failed(self, "no consistent stick/slip configuration")
        return original(self, x0=x0, v0=v0, **kwargs)

    monkeypatch.setattr(frictionjoint.CoulombOscillator, "steady_state", flaky)
    with pytest.warns(RuntimeWarning, match="default estimate"):
        fr = oscillator_sweep(1.0, 1.0, 0.3, 1.0, [1.5, 1.6])
    assert failures["n"] == 1 and fr.success

    def broken(self, x0=None, v0=None, **kwargs):
        return failed(self, "broken solver")

    monkeypatch.setattr(frictionjoint.CoulombOscillator, "steady_state", broken)
    with pytest.warns(RuntimeWarning, match="broken solver"):
        fr = oscillator_sweep(1.0, 1.0, 0.3, 1.0, [1.5])
    assert fr.regime[0] == "not converged" and not fr.converged[0]
    assert "broken solver" in fr.messages[0]
    assert "no conv." in fr.table()


@pytest.mark.parametrize("kwargs, name", [
    (dict(mass=0.0), "mass"),
    (dict(stiffness=-1.0), "stiffness"),
    (dict(slip_force=-0.1), "slip_force"),
    (dict(slip_force=math.nan), "slip_force"),
    (dict(force_amplitude=math.inf), "force_amplitude"),
    (dict(damping=-1.0), "damping"),
    (dict(base_amplitude="1"), "base_amplitude"),
    (dict(omegas=[]), "omegas"),
    (dict(omegas=[[1.0, 2.0]]), "omegas"),
    (dict(omegas=[1.0, -2.0]), r"omegas\[1\]"),
    (dict(omegas=[1.0, math.inf]), r"omegas\[1\]"),
    (dict(omegas="fast"), "omegas"),
    (dict(direction="sideways"), "direction"),
    (dict(progress="yes"), "progress"),
    (dict(force_amplitude=0.0), "force_amplitude"),
])
def test_invalid_input_names_the_parameter(kwargs, name):
    args = dict(mass=1.0, stiffness=1.0, slip_force=0.3, force_amplitude=1.0, omegas=[1.5])
    args.update(kwargs)
    with pytest.raises(ParameterError, match=name):
        oscillator_sweep(**args)


def test_no_warnings_on_a_clean_sweep():
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        oscillator_sweep(1.0, 1.0, 0.3, 1.0, [1.5, 2.0])


def test_fmu_sweep_harmonics_are_exact(fmus):
    """x and the friction force through the FMU come from its exact Fourier integrals (one
    communication step per period, no sampling): against Den Hartog (stop-free orbits), the first
    harmonic of x in phase, and the friction force F sgn(v) -- a square wave whose first harmonic
    is 4F/pi, lagging the displacement maximum by -pi/2 -- in amplitude and phase."""
    from frictionjoint.analytic import den_hartog

    f, ws = 0.3, [0.8, 1.3, 1.5, 2.0]
    fr = sweep(fmus["CoulombOscillator"], ws, dict(force_amplitude=1.0, slip_force=f), outputs=("x", "friction_force"))
    ff = fr.harmonics["friction_force"]
    for i, w in enumerate(ws):
        sol = den_hartog(w, f)
        assert abs(fr.phase[i] - sol.harmonic_phase) <= 1e-10  # measured <= 6e-13 (was ~5e-8 with 256 samples)
        assert fr.amplitude[i] == pytest.approx(sol.amplitude, rel=1e-10)
        assert ff["amplitude"][i] == pytest.approx(4 * f / math.pi, rel=1e-12)
        lag = (ff["phase"][i] - (sol.peak_phase - math.pi / 2) + math.pi) % (2 * math.pi) - math.pi
        assert abs(lag) <= 1e-10  # measured <= 6e-13 (was quantised to 1.4 deg)
        assert ff["peak"][i] == f

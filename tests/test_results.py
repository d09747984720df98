"""The result contract (frictionjoint.results): every result type has success, status and
message; every plot takes (ax=None, path=None); results are data, so a CSV round trip keeps
what a plot needs (the analytic curve is recomputed from the stored parameters)."""
import dataclasses
import inspect

import numpy as np
import pytest

import frictionjoint.results as results
from frictionjoint import oscillator_sweep, sweep
from frictionjoint.results import FrequencyResponse, collection_status

RESULT_TYPES = [getattr(results, n) for n in results.__all__ if inspect.isclass(getattr(results, n))]


def _has(cls, name):
    fields = {f.name for f in dataclasses.fields(cls)} if dataclasses.is_dataclass(cls) else set()
    return name in fields or hasattr(cls, name)


@pytest.mark.parametrize("cls", RESULT_TYPES, ids=lambda c: c.__name__)
def test_every_result_has_success_status_message(cls):
    for name in ("success", "status", "message"):
        assert _has(cls, name), f"{cls.__name__} lacks {name}"


@pytest.mark.parametrize("cls", [c for c in RESULT_TYPES if hasattr(c, "plot")], ids=lambda c: c.__name__)
def test_plot_signature(cls):
    params = list(inspect.signature(cls.plot).parameters)
    assert params[:3] == ["self", "ax", "path"]
    sig = inspect.signature(cls.plot).parameters
    assert sig["ax"].default is None and sig["path"].default is None


def test_collection_status():
    assert collection_status([True, True]) == ("ok", "2 of 2 points converged")
    assert collection_status([True, False], "cells")[0] == "partial"
    assert collection_status([False])[0] == "failed"
    assert collection_status([])[0] == "failed"


def test_csv_round_trip_keeps_the_analytic_curve(tmp_path):
    fr = oscillator_sweep(1.0, 1.0, 0.3, 1.0, np.array([0.6, 1.5, 2.0]))  # three frequencies, not a range
    assert fr.status == "ok" and fr.success and fr.message == "3 of 3 points converged"
    path = tmp_path / "fr.csv"
    fr.to_csv(path)
    back = FrequencyResponse.from_csv(path)
    dense = np.linspace(0.5, 2.5, 41)
    a, b = fr.analytic_curve(dense), back.analytic_curve(dense)
    assert np.array_equal(np.ma.getmaskarray(a[0]), np.ma.getmaskarray(b[0]))
    assert np.array_equal(a[0].filled(0.0), b[0].filled(0.0)) and np.array_equal(a[1].filled(0.0), b[1].filled(0.0))
    assert back.messages == fr.messages and back.status == fr.status


def test_plot_takes_the_former_positional_path(tmp_path):
    fr = oscillator_sweep(1.0, 1.0, 0.3, 1.0, [1.5])
    fig = fr.plot(tmp_path / "a.png")
    assert (tmp_path / "a.png").exists() and len(fig.axes) == 2
    fig2 = fr.plot(ax=fig.axes, path=tmp_path / "b.png")
    assert fig2 is fig and (tmp_path / "b.png").exists()
    with pytest.raises(TypeError, match="path"):
        fr.plot(tmp_path / "c.png", path=tmp_path / "d.png")


def test_no_points_is_no_success():
    fr = oscillator_sweep(1.0, 1.0, 0.3, 1.0, [1.5]).select("down")  # an up sweep has no down points
    assert len(fr) == 0 and not fr.success and fr.status == "failed"


def test_closed_form_is_compared_only_where_it_is_the_motion():
    """Den Hartog (1931) at r = 1/2, f = 0.3: U = tan(pi/(2r))/r = 0, so X = V P0/k = 4/3 m, a
    stop-free motion that is one member of a family of periodic orbits. From rest (the up
    branch) the kernel's orbit is Den Hartog's member (it pins the family's mean offset by the
    antisymmetric orbit, solvers/sdof.py): compared, to rounding, flagged not unique. From the
    r = 0.8 orbit (the down branch) it is another orbit, with one stop per cycle (Hong & Liu 2000):
    left out of the headline, which once counted such a point both as stop-free (error 2.5e-2)
    and as a point with stops; r = 0.8 is unique and stop-free."""
    from frictionjoint.analytic import den_hartog

    dh = den_hartog(0.5, 0.3)
    assert dh.regime == "stop-free" and not dh.unique and abs(dh.amplitude - 4.0 / 3.0) <= 1e-12
    fr = sweep("CoulombOscillator", np.array([0.5, 0.8]), {"force_amplitude": 1.0, "slip_force": 0.3},
               direction="both")
    assert list(fr.regime) == ["stop-free"] * 3 + ["stops"] and fr.stops_per_cycle[3] == 1
    assert abs(fr.amplitude[0] - 4.0 / 3.0) <= 1e-12 and abs(fr.amplitude[3] - 4.0 / 3.0) >= 1e-2
    assert list(fr.applicable) == [True, True, True, False]
    # the down branch's orbit with stops is left out as another orbit, unique or not: the general
    # marcher's exact monodromy there has the multiplier 1 - 1.6e-7 (1 - 1.1e-7 before issue 26's
    # classical modes: within UNIT_EIGENVALUE_TOL of 1 both times, a family member), but the sweep's
    # start check takes uniqueness from the kernel's Jacobian where it has one and defaults to unique
    # at a grazing start, which rounding decides here
    assert list(fr.analytic_regime[:3]) == ["stop-free"] * 3
    assert fr.analytic_regime[3] in ("other orbit", "not unique")
    for name in ("analytic_amplitude", "analytic_phase", "amplitude_error", "phase_error"):
        assert list(np.ma.getmaskarray(getattr(fr, name))) == [False, False, False, True]
    assert fr.max_error()[0] <= 1e-9
    last = fr.table().splitlines()
    assert "at 3 of 4 points (stop-free" in last[-3]
    assert last[-2].startswith("left out: 1 point with stops")


def test_every_point_is_compared_or_left_out_once(tmp_path):
    """A point cannot be both stop-free and with stops: whatever the builder put in the error
    columns, a converged orbit that is not stop-free is not compared with a stop-free closed form
    ('not unique' for a family member, 'other orbit' for a unique orbit), and the headline's
    compared and left-out points add up to all points; a CSV round trip keeps it."""
    n = 5
    err = np.ma.MaskedArray(np.full(n, 0.1), mask=[False, False, False, True, True])
    fr = FrequencyResponse(
        omega=np.arange(1.0, n + 1), amplitude=np.ones(n), phase=np.ones(n), harmonic_amplitude=np.ones(n),
        stops_per_cycle=np.array([0, 1, 2, 0, 0]), stuck=np.zeros(n, bool),
        converged=np.array([True, True, True, True, False]), unique=np.array([True, False, True, True, True]),
        regime=np.array(["stop-free", "stops", "stops", "stop-free", "not converged"]),
        branch=np.array(["up"] * n), periods=np.ones(n), messages=("",) * n,
        analytic_amplitude=err.copy(), analytic_phase=err.copy(),
        analytic_regime=np.array(["stop-free", "stop-free", "stop-free", "damped", "stop-free"]),
        amplitude_error=err.copy(), phase_error=err.copy(), natural_frequency=1.0)
    assert list(fr.applicable) == [True, False, False, False, False]
    assert list(fr.analytic_regime[:3]) == ["stop-free", "not unique", "other orbit"]
    left = fr._left_out()
    assert sum(int(t.split()[0]) for t in left) == n - 1 == n - fr.amplitude_error.count()
    assert left == ["1 point with stops (not unique: Den Hartog's stop-free motion is another member of the "
                    "family of periodic orbits)",
                    "1 point with stops (Den Hartog's stop-free motion is not the orbit found)",
                    "1 point stop-free (damped: no closed form)",
                    "1 point not converged (no orbit to compare)"]
    fr.to_csv(tmp_path / "fr.csv")
    back = FrequencyResponse.from_csv(tmp_path / "fr.csv")
    assert list(back.analytic_regime) == list(fr.analytic_regime) and back._left_out() == left


# ---------------------------------------------------------------- issue 39 §6: plots say what they draw


def _legend_texts(ax):
    legend = ax.get_legend()
    return [t.get_text() for t in legend.get_texts()] if legend is not None else []


def _bands(ax, min_width):
    """The axes' vertical bands (axvspan) at least ``min_width`` wide in data units."""
    from matplotlib.patches import Polygon, Rectangle

    widths = []
    for p in ax.patches:
        if isinstance(p, Rectangle):
            widths.append(p.get_width())
        elif isinstance(p, Polygon):
            x = p.get_xy()[:, 0]
            widths.append(x.max() - x.min())
    return [w for w in widths if w >= min_width]


@pytest.mark.parametrize("slip_force", [0.3, 0.9])
def test_the_legend_lists_only_what_is_drawn(slip_force):
    # F/P0 = 0.3: the closed form is invalid only at r = 1 itself (unbounded): before, a band two
    # dense samples wide (0.27 % of the axis) hidden under the resonance's line was listed; F/P0 =
    # 0.9: the closed form is nowhere the motion (stops everywhere): before, "Den Hartog (closed
    # form)" was listed with no curve drawn
    fr = oscillator_sweep(1.0, 1.0, slip_force, 1.0, [0.8, 1.2])  # the dense closed form crosses r = 1
    fig = fr.plot()
    ax = fig.axes[0]
    texts = _legend_texts(ax)
    band = any("not valid" in t for t in texts)
    assert band == bool(_bands(ax, 0.01 * np.ptp(ax.get_xlim())))
    closed = any("closed form" in t for t in texts)
    drawn = [ln for ln in ax.get_lines() if ln.get_color() == "k" and np.isfinite(np.asarray(ln.get_ydata(), float)).any()]
    assert closed == bool(drawn)
    assert closed == (slip_force == 0.3) and band == (slip_force == 0.9)


def test_other_outputs_reach_the_plot():
    # sweep(..., outputs=("x", "friction_force")), the command line's --output friction_force:
    # before, recorded and printed but never drawn
    fr = sweep("CoulombOscillator", [0.6, 0.7], outputs=("x", "friction_force"))
    fig = fr.plot()
    assert len(fig.axes) == 3
    ax = fig.axes[2]
    assert ax.get_ylabel() == "friction_force, first harmonic [N]"
    y = np.concatenate([np.asarray(ln.get_ydata(), float) for ln in ax.get_lines()])
    assert np.allclose(np.sort(y), np.sort(fr.harmonics["friction_force"]["amplitude"]), rtol=0, atol=0)


def test_an_output_sweep_has_a_title_that_says_what_its_output_is():
    # tip.png (frictionjoint sweep ti64_compressor_blade ... --plot tip.png): before, no title and
    # the output named only "w30"
    from frictionjoint.results.dof_names import dof_meaning
    from frictionjoint.results import OutputSweep

    n = 3
    sw = OutputSweep(omega=np.array([1.0, 2.0, 3.0]), output="w30", response=np.full(n, 1e-4 + 0j),
                     limits={"stuck": np.full(n, 1e-4 + 0j)}, stuck=np.ones(n, bool), converged=np.ones(n, bool),
                     dissipated_per_cycle=np.zeros(n))
    title = sw.plot().axes[0].get_title()
    assert "w30" in title and "transverse" in title and "node 30" in title
    assert dof_meaning("n1634_u3") == "the z displacement of node 1634" and dof_meaning("x") == ""


def test_monte_carlo_percentiles_are_named_without_overlap():
    # mc.png: before, P5 and P50 were texts beside their lines, overlapping where the percentiles are
    # close; now a legend names each line with its value
    from frictionjoint.results.study import StudyTable

    rng = np.random.default_rng(0)
    n = 40
    peak = np.concatenate([np.full(n - 4, 1e-4), 1e-4 + rng.uniform(0, 1e-4, 4)])
    table = StudyTable(columns={"point": np.arange(n), "friction_coefficient": rng.uniform(0.2, 0.4, n),
                                "peak_amplitude": peak, "status": np.array(["ok"] * n, dtype=object)},
                       varied=("friction_coefficient",), random=("friction_coefficient",))
    fig = table.plot()
    ax = fig.axes[-1]
    q = table.percentiles()
    assert _legend_texts(ax) == [f"P{k:g} = {v:.4g}" for k, v in q.items()]
    assert not ax.texts  # no labels beside the lines to overlap


def test_a_non_unique_orbit_is_marked_and_explained_in_the_plot():
    # r = 1/2, F/P0 = 0.05: the stop-free orbit is one of a family (Den Hartog's U = 0); the tables
    # mark it '*' with a footnote, and the plot now rings it with a legend entry saying why
    fr = oscillator_sweep(1.0, 1.0, 0.05, 1.0, [0.45, 0.5])
    assert list(fr.unique) == [True, False]
    ax = fr.plot().axes[0]
    assert "not unique: one member of a family of orbits" in _legend_texts(ax)
    assert "* not unique: one member of a family of periodic orbits" in fr.table()

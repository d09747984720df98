"""frictionjoint.campbell: the Campbell diagram of a blade model on its friction root.

References: the linear limits are the assembly's (BladeAssembly.from_model at each speed, then
linear_limits.limit_structures), and independently the unreduced beam blade on the same dovetail;
a crossing is checked by recomputing the mode at the crossing's speed from scratch.
"""
import sys
from pathlib import Path

import numpy as np
import pytest

import frictionjoint as fj
from frictionjoint.campbell import campbell
from frictionjoint.elements import DovetailRoot
from frictionjoint.errors import ParameterError
from frictionjoint.linear_limits import limit_structures
from frictionjoint.structures import BladeAssembly, load_blade_model

ROOT = Path(__file__).resolve().parents[1]
MODEL = ROOT / "models" / "ti64_compressor_blade.toml"
#: a crossing on its mode's curve and on its engine-order line, relative (root finding exact)
CROSSING_TOL = 1e-9
#: the nonlinear modes' crossings: their frequency is solved to Newton's tolerance (1e-11)
NONLINEAR_TOL = 1e-9
#: Craig-Bampton with 2 n_modes + 2 modes (n_modes = 3) against the unreduced blade, stuck and
#: free slip (measured at 1000 rad/s: 3.2e-7 and 4.9e-5)
REDUCTION_TOL = {"stuck": 1e-6, "slipping": 1e-4}


@pytest.fixture(scope="module")
def diagram():
    """Ti-64 blade, 8 speeds, 3 modes, engine orders 1-8, the nonlinear band at 2e-5 m (about 2 s)."""
    return campbell("ti64_compressor_blade", "200:1500:8", engine_orders=range(1, 9), n_modes=3, amplitude=2e-5)


def _limits(speed, n_modes=3):
    model = load_blade_model(MODEL)
    system = BladeAssembly.from_model(model, 2 * n_modes + 2, rotor_speed=speed).system(1.0)
    return {name: st.natural_frequencies()[:n_modes] for name, st in limit_structures(system).items()}


def test_lowest_speed_is_the_assembly_s_linear_limits(diagram):
    """At the lowest speed (the root carries no load at rest, so speeds are > 0) the stuck and
    free-slip frequencies are the BladeAssembly's linear limits at that speed, to rounding."""
    ref = _limits(diagram.speed[0])
    np.testing.assert_allclose(diagram.stuck_frequency[0], ref["stuck"], rtol=1e-13)
    np.testing.assert_allclose(diagram.slipping_frequency[0], ref["slipping"], rtol=1e-13)


def test_at_rest_the_stuck_frequencies_are_the_assembly_s():
    """Speed to zero: the BladeAssembly of the blade at rest (built here by hand, as from_model
    builds it but on the non-rotating blade; the stuck limit does not depend on the root's load,
    so a nominal 1 N carries it) has the stuck frequencies the diagram finds at 1e-3 rad/s, to the
    centrifugal stiffening there (about 1e-11). Its free slip has a mechanism: 0 rad/s, to the
    eigenvalues' rounding (sqrt(eps |K| / |M|), a few 1e-3 rad/s), and so does the diagram's at
    1e-3 rad/s."""
    from frictionjoint.structures import craig_bampton

    model = load_blade_model(MODEL)
    cd = campbell(model, [1e-3], engine_orders=[1], n_modes=3)
    blade = model.blade(rotor_speed=0.0)
    reduced = craig_bampton(blade.structure, ["u0", "w0", "t0"], 8, loaded_dofs=["w30"])
    root = DovetailRoot(1.0, tangential_dof="w0", radial_dof="u0", rocking_dof="t0", **model.root)
    limits = limit_structures(BladeAssembly(reduced, [root]).system(1.0))
    at_rest = limits["stuck"].natural_frequencies()[:3]
    err = np.max(np.abs(cd.stuck_frequency[0] / at_rest - 1))
    print(f"stuck at 1e-3 rad/s against the assembly at rest: {err:.1e}")
    assert err <= 1e-10
    slip = limits["slipping"].natural_frequencies()[:3]
    assert slip[0] < 0.1 and cd.slipping_frequency[0, 0] < 0.1
    np.testing.assert_allclose(cd.slipping_frequency[0, 1:], slip[1:], rtol=1e-10)


def test_limits_against_the_unreduced_blade_on_its_dovetail():
    """Independently: the full beam blade (93 DOFs) on the same flat-flank dovetail, rocking on
    its flanks, at the centrifugal force of the speed."""
    model = load_blade_model(MODEL)
    speed = 1000.0
    cd = campbell(model, [speed], engine_orders=[1], n_modes=3)
    blade = model.blade(rotor_speed=speed)
    root = DovetailRoot(blade.centrifugal_force, tangential_dof="w0", radial_dof="u0", rocking_dof="t0", **model.root)
    full = limit_structures(fj.FrictionSystem(blade.structure, [root]))
    for name, got in (("stuck", cd.stuck_frequency[0]), ("slipping", cd.slipping_frequency[0])):
        ref = full[name].natural_frequencies()[:3]
        err = np.max(np.abs(got / ref - 1))
        print(f"{name}: Craig-Bampton against the unreduced blade {err:.2e}")
        assert err <= REDUCTION_TOL[name]


def test_crossings_lie_on_their_line_and_their_mode(diagram):
    """Each crossing's speed, recomputed from scratch: the mode's frequency there equals the
    engine order times the speed and the crossing's frequency."""
    assert {"stuck", "slipping", "nonlinear"} <= set(diagram.crossings["limit"])
    worst = {}
    for row in diagram.crossings:
        limit, eo, mode, speed, freq = (row[k] for k in ("limit", "engine_order", "mode", "speed", "frequency"))
        if limit == "nonlinear":
            system = BladeAssembly.from_model(load_blade_model(MODEL), 8, rotor_speed=speed).system(1.0)
            w = fj.nonlinear_mode(system, mode=int(mode), amplitudes=[diagram.amplitude],
                                  n_harmonics=diagram.n_harmonics, dof="w0").frequency[0]
        else:
            w = _limits(speed)[str(limit)][mode]
        on_line, on_curve = abs(w - eo * speed) / w, abs(w - freq) / w
        worst[str(limit)] = max(worst.get(str(limit), 0.0), on_line, on_curve)
        assert on_line <= (NONLINEAR_TOL if limit == "nonlinear" else CROSSING_TOL)
        assert on_curve <= (NONLINEAR_TOL if limit == "nonlinear" else CROSSING_TOL)
        # inside the sample interval where the curve changed sides of the line
        i = np.searchsorted(diagram.speed, speed)
        assert 0 < i < diagram.speed.size
    print("largest relative distance of a crossing from its line and its curve:", worst)


def test_every_sign_change_is_a_crossing(diagram):
    """As many crossings per curve, mode and engine order as sign changes of omega - EO Omega
    between the samples."""
    curves = {"stuck": diagram.stuck_frequency, "slipping": diagram.slipping_frequency,
              "nonlinear": diagram.nonlinear_frequency}
    for limit, omega in curves.items():
        for eo in diagram.engine_orders:
            g = omega - eo * diagram.speed[:, None]
            changes = np.sum(g[:-1] * g[1:] < 0, axis=0)
            for mode in range(diagram.n_modes):
                found = diagram.crossings[(diagram.crossings["limit"] == limit)
                                          & (diagram.crossings["engine_order"] == eo)
                                          & (diagram.crossings["mode"] == mode)]
                assert found.size == changes[mode]


def test_free_slip_below_stuck_and_the_nonlinear_modes_between(diagram):
    assert np.all(diagram.slipping_frequency < diagram.stuck_frequency)
    assert np.all(np.diff(diagram.stuck_frequency, axis=1) > 0)
    ok = diagram.nonlinear_converged
    assert ok.sum() >= ok.size - 1
    w = diagram.nonlinear_frequency[ok]
    # the EPMC's stuck limit is the damped mode's (Rayleigh damping and the root's dashpots, not
    # proportional): above the undamped frequency, in the second order of the damping ratio
    zeta = diagram.nonlinear_damping_ratio[ok]
    excess = w / diagram.stuck_frequency[ok] - 1
    print(f"nonlinear above the undamped stuck frequency by at most {excess.max():.2e} (zeta^2 {zeta.max() ** 2:.1e})")
    assert np.all(excess <= zeta ** 2)
    assert np.all(w >= diagram.slipping_frequency[ok])
    assert np.all(diagram.nonlinear_damping_ratio[ok] > 0)
    # the root's load grows like Omega^2: at 2e-5 m the root slips at 200 rad/s, sticks at 1500
    assert diagram.nonlinear_frequency[0, 0] < 0.99 * diagram.stuck_frequency[0, 0]
    assert diagram.nonlinear_frequency[-1, 0] == pytest.approx(diagram.stuck_frequency[-1, 0], rel=1e-5)


def _read_csv(path):
    import csv

    with open(path, encoding="utf-8") as fh:
        return list(csv.DictReader(line for line in fh if not line.startswith("#")))


def test_result_contract_table_csv_and_plot(diagram, tmp_path):
    assert diagram.status in ("ok", "partial") and diagram.message
    text = diagram.table()
    assert len(text.splitlines()) == 1 + diagram.crossings.size
    md = diagram.table(markdown=True)
    assert md.startswith("| curve | EO | mode |") and md.count("\n") == 1 + diagram.crossings.size
    diagram.to_csv(tmp_path / "x.csv")
    back = _read_csv(tmp_path / "x.csv")
    assert [r["limit"] for r in back] == list(diagram.crossings["limit"])
    np.testing.assert_array_equal([float(r["speed"]) for r in back], diagram.crossings["speed"])  # exact
    diagram.to_csv(tmp_path / "curves.csv", curves=True)
    curves = _read_csv(tmp_path / "curves.csv")
    np.testing.assert_array_equal([float(r["stuck_2"]) for r in curves], diagram.stuck_frequency[:, 2])
    np.testing.assert_array_equal([float(r["nonlinear_0"]) for r in curves], diagram.nonlinear_frequency[:, 0])
    fig = diagram.plot(path=tmp_path / "c.png")
    assert (tmp_path / "c.png").read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    assert len(fig.axes) == 2  # the frequencies, and the nonlinear modes' damping ratios
    assert len(diagram.plot(ax=fig.axes[0]).axes) == 2  # into given axes: the frequencies only


def test_no_crossing_is_a_table_that_says_so():
    cd = campbell("ti64_compressor_blade", "900:1000:2", engine_orders=[1], n_modes=1)
    assert cd.crossings.size == 0 and cd.success
    assert "no crossing" in cd.table()
    assert len(cd.plot().axes) == 1  # no nonlinear modes: no damping panel


@pytest.mark.parametrize("kwargs,name", [
    (dict(speeds="0:1000:5"), "speeds"), (dict(speeds=[-100.0, 200.0]), "speeds"),
    (dict(speeds=[100.0, float("nan")]), "speeds"), (dict(speeds=[300.0, 200.0]), "speeds"),
    (dict(speeds=[200.0, 200.0]), "speeds"), (dict(speeds=[]), "speeds"), (dict(speeds=(100, 200, 3)), "speeds"),
    (dict(speeds="100:200"), "speeds"), (dict(engine_orders=[0]), "engine_orders"),
    (dict(engine_orders=[-1, 2]), "engine_orders"), (dict(engine_orders=[1, float("inf")]), "engine_orders"),
    (dict(engine_orders=[2, 2]), "engine_orders"), (dict(engine_orders="1,2"), "engine_orders"),
    (dict(engine_orders=[]), "engine_orders"), (dict(n_modes=0), "n_modes"), (dict(n_modes=2.5), "n_modes"),
    (dict(amplitude=-1e-5), "amplitude"), (dict(amplitude=float("nan")), "amplitude"),
    (dict(n_harmonics=0), "n_harmonics"), (dict(reduction_modes=-1), "reduction_modes"),
    (dict(n_modes=50), "n_modes"), (dict(model=3.0), "model"), (dict(model="no_such_blade"), "not found"),
])
def test_bad_input_names_the_parameter(kwargs, name):
    args = dict(model="ti64_compressor_blade", speeds=[500.0, 600.0], engine_orders=[1])
    args.update(kwargs)
    with pytest.raises(ParameterError, match=name):
        campbell(args.pop("model"), args.pop("speeds"), **args)


@pytest.mark.slow  # about 2-5 s: two Campbell diagrams and a plot
def test_cli_on_the_ti64_model_file(tmp_path, monkeypatch, capsys):
    """The command on the model file, in this process (``python -m frictionjoint`` in a subprocess:
    tests/test_cli.py; 3.0 -> 1.9 s here): the library's table, the plot and the CSV."""
    from frictionjoint.cli import main

    monkeypatch.chdir(tmp_path)
    assert main(["campbell", str(MODEL), "--speed", "200:1500:5", "--engine-orders", "1,2,3,4,5,6,7,8", "--modes", "2",
                 "--plot", "c.png", "--csv", "c.csv", "--no-progress"]) == 0
    out = capsys.readouterr().out
    cd = campbell(MODEL, "200:1500:5", engine_orders=range(1, 9), n_modes=2)
    assert cd.table() in out and "crossings" in out
    assert (tmp_path / "c.png").read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    rows = [ln for ln in (tmp_path / "c.csv").read_text().splitlines() if not ln.startswith("#")]
    assert len(rows) == 1 + cd.crossings.size


def test_cli_in_process_with_the_nonlinear_band(tmp_path, capsys):
    from frictionjoint.cli import main

    assert main(["campbell", str(MODEL), "--speed", "1100:1200:2", "--engine-orders", "2", "--modes", "1",
                 "--amplitude", "2e-5", "--csv", str(tmp_path / "c.csv"), "--no-progress"]) == 0
    out = capsys.readouterr().out
    assert "nonlinear modes at 2e-05 m (w0, H = 1): 2 of 2 converged" in out
    rows = _read_csv(tmp_path / "c.csv")
    assert sorted(r["limit"] for r in rows) == ["nonlinear", "stuck"]  # the first mode crosses EO 2 at 1164 rad/s


@pytest.mark.slow  # about 2-5 s: one assembly of the solid blade (sparse Craig-Bampton)
def test_a_solid_blade_model():
    """The solid blade's definition works the same way (BladeAssembly.from_model's solid path)."""
    cd = campbell("ti64_solid_blade", [1000.0], engine_orders=[1], n_modes=2)
    assert np.all(cd.slipping_frequency < cd.stuck_frequency) and cd.crossings.size == 0
    assert cd.stuck_frequency[0, 0] == pytest.approx(1976.5, rel=1e-3)  # BladeAssembly's, measured


@pytest.mark.parametrize("argv,words", [
    (["--speed", "0:1500:5"], "> 0"), (["--speed", "-5:1500:5"], "> 0"), (["--speed", "100:1500"], "START:STOP:N"),
    (["--speed", "100:100:3"], "speeds must increase"), (["--speed", "100:200:3", "--engine-orders", "1,0"], "> 0"),
    (["--speed", "100:200:3", "--engine-orders", "1,x"], "commas"),
    (["--speed", "100:200:3", "--engine-orders", "2,2"], "repeat"),
    (["--speed", "100:200:3", "--modes", "0"], ">= 1"), (["--speed", "100:200:3", "--amplitude", "-1"], "> 0"),
])
def test_cli_bad_arguments(argv, words, capsys):
    from frictionjoint.cli import main

    with pytest.raises(SystemExit) as exc:
        main(["campbell", "ti64_compressor_blade", *argv, "--no-progress"])
    assert exc.value.code == 2
    assert words in capsys.readouterr().err


def test_cli_misspelt_model_prints_nothing(capsys):
    from frictionjoint.cli import main

    with pytest.raises(SystemExit):
        main(["campbell", "ti64_compressor_blad", "--speed", "100:200:3"])
    out = capsys.readouterr()
    assert out.out == "" and "not found" in out.err


def test_guide_example_runs(tmp_path, monkeypatch):
    """The Python example of docs/campbell.md."""
    import re

    text = (ROOT / "docs" / "campbell.md").read_text()
    blocks = [b for b in re.findall(r"^```python\n(.*?)^```", text, re.S | re.M) if "cd = fj.campbell(" in b]
    assert len(blocks) == 1
    monkeypatch.chdir(tmp_path)
    namespace = {"__name__": "guide"}
    exec(compile(blocks[0], "docs/campbell.md:python-example", "exec"), namespace)
    cd = namespace["cd"]
    assert cd.success and cd.nonlinear_frequency.shape == (8, 3)
    assert {"stuck", "slipping", "nonlinear"} <= set(cd.crossings["limit"])
    assert (tmp_path / "campbell.png").read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"


def test_a_crossing_the_nonlinear_mode_cannot_reach_is_counted_not_invented(monkeypatch):
    """Where the nonlinear mode does not converge at a trial speed between two samples, the sign
    change is not located: no row, and the message counts it."""
    module = sys.modules["frictionjoint.campbell"]  # the package's attribute is the function

    samples = (1100.0, 1200.0)
    solve = module._Blade.nonlinear
    monkeypatch.setattr(module._Blade, "nonlinear",
                        lambda self, speed, mode: solve(self, speed, mode) if speed in samples else (np.nan, np.nan))
    cd = campbell(MODEL, list(samples), engine_orders=[2], n_modes=1, amplitude=2e-5)
    assert list(cd.crossings["limit"]) == ["stuck"] and cd.success
    assert "1 sign changes of the nonlinear curves not located" in cd.message


@pytest.mark.slow  # about 2-5 s: the example's Campbell diagram with its nonlinear modes
def test_example_script_draws_the_readme_diagram(tmp_path, monkeypatch, capsys):
    """examples/campbell_diagram.py (which draws docs/campbell_ti64.png) on 2 speeds (its own argument),
    its main in this process (was 4 speeds in a subprocess: 5.2 -> 2.7 s here)."""
    import runpy

    monkeypatch.chdir(tmp_path)
    example = runpy.run_path(str(ROOT / "examples" / "campbell_diagram.py"), run_name="example")
    assert example["main"](["campbell_diagram.py", "c.png", "2"]) == 0
    out = capsys.readouterr().out
    assert out.startswith("| curve | EO | mode |") and "2 speeds in" in out
    assert (tmp_path / "c.png").read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"


@pytest.mark.parametrize("amplitude", [1e12, 1e300])
def test_deep_slip_nonlinear_mode_is_the_free_slip_limit(amplitude):
    """Issue 39: at 1000 rad/s the root's slip reach is below 1e-3 m, so from 0.1 m on the nonlinear
    mode is the free-slip limit (1707.28 rad/s) to the joint's force over the springs' (< 1e-10 from
    1e8 m; the free-slip frequency is the same eigenproblem's, to rounding: bound 1e-9). At 1e12 m it
    gave the stuck limit 2034.78 (the joint's loop held its spring once its reach was below the
    rounding of the motion), at 1e300 m NaN (k u overflowed) with no message."""
    c = campbell("ti64_compressor_blade", "1000:1000:1", engine_orders=[1], n_modes=1, amplitude=amplitude)
    assert c.nonlinear_converged.all(), c.message
    assert abs(c.nonlinear_frequency[0, 0] / c.slipping_frequency[0, 0] - 1) <= 1e-9


def test_too_many_modes_quote_what_was_given():
    """n_modes = 1000 asks the Craig-Bampton reduction for 2 n_modes + 2 = 2002 modes: the refusal
    names n_modes, its range for this blade (90 interior DOFs, one kept for the tip's residual
    vector: 2 n + 2 <= 89) and 1000 (it quoted 2002 under the name n_modes)."""
    with pytest.raises(ParameterError, match=r"n_modes must be in \[1, 43\].*got 1000$"):
        campbell("ti64_compressor_blade", "500:2000:3", n_modes=1000)
    with pytest.raises(ParameterError, match=r"reduction_modes must be in \[0, 89\].*got 500$"):
        campbell("ti64_compressor_blade", "500:2000:3", n_modes=2, reduction_modes=500)
    campbell("ti64_compressor_blade", "500:2000:2", n_modes=43)  # the largest runs


def test_speeds_are_capped_before_any_assembly():
    """10^6 speeds (frequencies' own cap) would take about 14 hours on the beam blade: refused at
    campbell.MAX_SPEEDS, naming speeds, before the first assembly (well within a second)."""
    import time

    from frictionjoint.campbell import MAX_SPEEDS

    t0 = time.perf_counter()
    with pytest.raises(ParameterError, match=rf"speeds must hold at most {MAX_SPEEDS} rotor speeds, got 1000000"):
        campbell("ti64_compressor_blade", "500:2000:1000000", n_modes=1)
    assert time.perf_counter() - t0 < 30.0  # measured 0.2 s; an assembly per speed would be hours

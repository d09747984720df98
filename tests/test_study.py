"""Design studies (frictionjoint.study): definition, quantities, execution serially, on the local
process pool and on a Dask LocalCluster (bit-identical tables), resume after an interruption, failed
points as rows, the CLI and the plots.

References: the half-power bandwidth of a linear oscillator in closed form (the equivalent damping
ratio); the blade's steady states themselves (the study's rows equal a direct sweep of the same
point)."""
import math

import numpy as np
import pytest

import frictionjoint as fj
from frictionjoint.errors import ParameterError
from frictionjoint.results import StudyTable
from frictionjoint.study import Grid, Random, Study, Values, evaluate_point, load_study, quantities, run_study

# a small study: the blade at two root loads x two random friction coefficients, a short sweep. The
# root loads are cheap ones (the four points serially 2.5 s against 12.8 s at 109 and 259 N, measured
# at load 5): the execution (pool, Dask, journal, resume) is the same whatever the points cost, and
# the points still have slipping and stuck frequencies (615 N: stuck at 1990 and 2060 rad/s)
SMALL = dict(model="ti64_compressor_blade", omega="1990:2060:4",
             vary={"centrifugal_force": Values((615.0, 1458.0)),
                   "friction_coefficient": Random("uniform", (("loc", 0.25), ("scale", 0.1)))},
             n_samples=2, seed=5, refine_peak=False)


BLADE = "ti64_compressor_blade"


def test_points_product_and_seeded_samples():
    """Grids and lists form a Cartesian product (first parameter slowest), random parameters are
    n draws from default_rng(seed), the same for every grid point; another seed other draws."""
    st = Study(model=BLADE, omega="1:2:3",
               vary={"centrifugal_force": Grid(1.0, 100.0, 3, "log"), "flank_angle": Values((0.5, 0.6)),
                     "friction_coefficient": Random("norm", (("loc", 0.3), ("scale", 0.01)))}, n_samples=4, seed=11)
    pts = st.points()
    assert len(pts) == 3 * 2 * 4 == st.n_points
    assert list(pts[0]) == ["centrifugal_force", "flank_angle", "friction_coefficient"]
    assert [p["centrifugal_force"] for p in pts[::8]] == pytest.approx([1.0, 10.0, 100.0])
    draws = 0.3 + 0.01 * np.random.default_rng(11).standard_normal(4)
    assert [p["friction_coefficient"] for p in pts[:4]] == pytest.approx(list(draws), rel=1e-15)
    assert [p["friction_coefficient"] for p in pts[:4]] == [p["friction_coefficient"] for p in pts[4:8]]
    again = dict(vars(st), omega="1:2:3")
    assert Study(**{**again, "seed": 12}).points()[0]["friction_coefficient"] != pts[0]["friction_coefficient"]
    assert st.fingerprint() == Study(**again).fingerprint() != Study(**{**again, "seed": 12}).fingerprint()
    # the same frequencies written as a range or listed are the same study
    assert Study(**{**again, "omega": np.linspace(1.0, 2.0, 3)}).fingerprint() == st.fingerprint()


def test_bad_definitions_name_the_parameter(tmp_path):
    one = {"centrifugal_force": Values((100.0,))}
    with pytest.raises(ParameterError, match="vary.x.num"):
        Study(model=BLADE, omega="1:2:3", vary={"x": Grid(1.0, 2.0, 0)})
    with pytest.raises(ParameterError, match="vary.friction_coefficient.distribution"):
        Study(model=BLADE, omega="1:2:3", vary={"friction_coefficient": Random("gaussian")})
    with pytest.raises(ParameterError, match="vary.friction_coefficient: bad parameters"):
        Study(model=BLADE, omega="1:2:3", vary={"friction_coefficient": Random("uniform", (("width", 1.0),))})
    with pytest.raises(ParameterError, match="omega"):
        Study(model=BLADE, omega="0:2:3", vary=one)
    with pytest.raises(ParameterError, match="log grid"):
        Study(model=BLADE, omega="1:2:3", vary={"centrifugal_force": Grid(-1.0, 2.0, 3, "log")})
    bad = tmp_path / "bad.toml"
    bad.write_text(f'model = "{BLADE}"\n[sweep]\nomega = "1:2:3"\n[vary.x]\nstart = 1.0\n')
    with pytest.raises(ParameterError, match="vary.x needs"):
        load_study(bad)
    bad.write_text(f'model = "{BLADE}"\nfoo = 1\n')
    with pytest.raises(ParameterError, match="unknown keys"):
        load_study(bad)
    for text, name in ((f'model = "{BLADE}"\nfixed = 3\n', r"\[fixed\]"), (f'model = "{BLADE}"\ntable = 5\n', "table"),
                       (f'model = "{BLADE}"\n[sweep]\nomega = "a:2:3"\n', "omega"),
                       (f'model = "{BLADE}"\n[sweep]\nomega = [1990.0, 2060.0, 4]\n', "'1990.0:2060.0:4'"),
                       (f'model = "{BLADE}"\n[sweep]\nomega = "1:2:3"\n[vary.x]\nvalues = 2\n', "vary.x.values")):
        bad.write_text(text)
        with pytest.raises(ParameterError, match=name):
            load_study(bad)
    with pytest.raises(ParameterError, match="vary.friction_coefficient: parameters"):
        Study(model=BLADE, omega="1:2:3", vary={"friction_coefficient": Random("uniform", (("scale", -1.0),))})
    with pytest.raises(ParameterError, match="omega"):
        Study(model=BLADE, omega=(1.0, 2.0, 3.7, 0.0), vary=one)
    with pytest.raises(ParameterError, match="column"):
        Study(model=BLADE, omega="1:2:3", vary={"status": Values((1.0,))})
    with pytest.raises(ParameterError, match="scheduler"):
        run_study(Study(model=BLADE, omega="1:2:3", vary=one), tmp_path / "t.csv", scheduler="notanaddress")


def test_half_power_damping_ratio_of_a_linear_oscillator():
    """|X| = 1 / sqrt((1 - w^2)^2 + (2 zeta w)^2): the half-power points solve w^4 - 2 (1 - 2
    zeta^2) w^2 + 1 - 8 zeta^2 (1 - zeta^2)... in closed form w^2 = 1 - 2 zeta^2 -+ 2 zeta sqrt(1 -
    zeta^2) (level peak/sqrt 2); the quantity equals (w2 - w1)/(2 w_peak) of the closed form to
    1e-6 on a fine sweep (linear interpolation between points)."""
    for zeta in (0.01, 0.05):
        w = np.linspace(0.8, 1.2, 40001)
        a = 1.0 / np.sqrt((1 - w ** 2) ** 2 + (2 * zeta * w) ** 2)
        q = quantities(w, a, np.ones(w.size, bool), np.zeros(w.size), np.zeros(w.size, bool))
        w_pk = math.sqrt(1 - 2 * zeta ** 2)
        a_pk = 1.0 / (2 * zeta * math.sqrt(1 - zeta ** 2))
        # the level is the sampled peak's / sqrt 2: solve |X|^2 = a_max^2 / 2 in closed form
        level2 = (q["peak_amplitude"] / math.sqrt(2)) ** -2
        # (1 - w^2)^2 + 4 zeta^2 w^2 = level2: w^4 - (2 - 4 zeta^2) w^2 + 1 - level2 = 0
        b = 2 - 4 * zeta ** 2
        disc = math.sqrt(b * b - 4 * (1 - level2))
        w1, w2 = math.sqrt((b - disc) / 2), math.sqrt((b + disc) / 2)
        assert abs(q["peak_amplitude"] / a_pk - 1) <= 1e-8 and abs(q["peak_omega"] - w_pk) <= 1e-5
        assert abs(q["damping_ratio"] / ((w2 - w1) / (2 * q["peak_omega"])) - 1) <= 1e-6
        assert abs(q["damping_ratio"] / zeta - 1) <= 2e-3 * (zeta / 0.01)  # ~ zeta for light damping
    # a refined peak above sqrt 2 times every sample: the bandwidth is below the spacing (NaN)
    ws = np.array([0.97, 0.985, 1.015, 1.03])
    aw = 1.0 / np.sqrt((1 - ws ** 2) ** 2 + (0.02 * ws) ** 2)
    q = quantities(ws, aw, np.ones(4, bool), np.zeros(4), np.zeros(4, bool), peak=(1.0, 50.0, 0.0, False))
    assert q["peak_amplitude"] == 50.0 and math.isnan(q["damping_ratio"])
    # the peak at the end of the range, no half-power points inside it
    q = quantities(w[:100], a[:100], np.ones(100, bool), np.zeros(100), np.zeros(100, bool))
    assert q["peak_at_edge"] and math.isnan(q["damping_ratio"])


@pytest.mark.slow
def test_row_equals_a_direct_sweep_and_refined_peak():
    """A point's row comes from the blade's own sweep (the same numbers as fj.sweep of the same
    parameters), and the refined peak is the assembly's peak between the sweep's points."""
    from frictionjoint.sweep import blade_assembly

    task = dict(point=0, model="ti64_compressor_blade", omega="1990:2060:5", fixed={"tip_force_amplitude": 1.0},
                varied={"centrifugal_force": 1458.0}, direction="up", method="time", harmonics=7, refine=True)
    row = evaluate_point(task)
    fr = fj.sweep("ti64_compressor_blade", np.linspace(1990.0, 2060.0, 5), {"centrifugal_force": 1458.0})
    assert row["status"] == "ok" and row["points"] == 5 and row["slipping_at_peak"] is True
    assert row["peak_amplitude"] >= fr.amplitude.max()
    asm = blade_assembly("ti64_compressor_blade", {"centrifugal_force": 1458.0})
    i = int(np.argmax(fr.amplitude))
    w_pk, a_pk = asm.peak(fr.omega[i - 1], fr.omega[i + 1], asm.tip, n_grid=5, xtol=1e-7)
    assert row["peak_amplitude"] == a_pk and row["peak_omega"] == w_pk


def test_failed_point_is_a_row_and_the_study_finishes(tmp_path):
    """A parameter outside its range fails its point only: the row says why."""
    st = Study(model="ti64_compressor_blade", omega="1990:2060:4",
               vary={"centrifugal_force": Values((1458.0, -5.0))}, refine_peak=False)
    tab = run_study(st, tmp_path / "t.csv", workers=1)
    assert list(tab["status"]) == ["ok", "failed"]
    assert "centrifugal_force" in tab["error"][1] and "ParameterError" in tab["error"][1]
    assert math.isnan(tab["peak_amplitude"][1]) and tab["peak_amplitude"][0] > 0
    assert "1 failed" in tab.message


@pytest.mark.slow
def test_serial_pool_and_dask_give_bit_identical_tables(tmp_path):
    """The same study serially, on the local process pool (2 workers) and on a Dask LocalCluster
    with 2 worker processes: byte-identical CSV tables (floats written exactly), and the Parquet
    table reads back to the same rows."""
    distributed = pytest.importorskip("distributed")
    st = Study(**SMALL)
    run_study(st, tmp_path / "serial.csv", workers=1)
    run_study(st, tmp_path / "pool.csv", workers=2)
    with distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=True, dashboard_address=None) as cl:
        dask_tab = run_study(st, tmp_path / "dask.parquet", scheduler=cl.scheduler_address)
    dask_tab.to_csv(tmp_path / "dask.csv")
    serial = (tmp_path / "serial.csv").read_bytes()
    assert serial == (tmp_path / "pool.csv").read_bytes() == (tmp_path / "dask.csv").read_bytes()
    assert len(dask_tab) == 4 and np.all(dask_tab.ok)
    back = StudyTable.read(tmp_path / "dask.parquet")
    assert back.fingerprint == st.fingerprint() and back.random == ("friction_coefficient",)
    back.to_csv(tmp_path / "back.csv")
    assert (tmp_path / "back.csv").read_bytes() == serial


@pytest.mark.slow
def test_interrupted_study_resumes_without_computing_a_point_twice(tmp_path):
    """Ctrl-C (KeyboardInterrupt) after two of four points: the journal holds those two; run
    again, the study computes only the other two, and the final table is byte-identical to an
    uninterrupted run's. A table of another study is refused."""
    st = Study(**SMALL)
    full = tmp_path / "full.csv"
    run_study(st, full, workers=1)
    first, second = [], []

    def stop_after_two(row):
        first.append(row["point"])
        if len(first) == 2:
            raise KeyboardInterrupt

    part = tmp_path / "part.csv"
    with pytest.raises(KeyboardInterrupt):
        run_study(st, part, workers=1, on_row=stop_after_two)
    assert len(StudyTable.read(part)) == 2
    tab = run_study(st, part, workers=2, on_row=lambda row: second.append(row["point"]))
    assert sorted(first + second) == [0, 1, 2, 3] and not set(first) & set(second)
    assert part.read_bytes() == full.read_bytes() and len(tab) == 4
    other = Study(**{**SMALL, "seed": 6})
    with pytest.raises(ParameterError, match="another study"):
        run_study(other, part, workers=1)


@pytest.mark.slow
def test_journal_cut_short_resumes_to_the_full_table(tmp_path):
    """A journal cut anywhere (in a row, in the column line, after the first line) resumes to the
    table of an uninterrupted run: the fragment is not a row, and new rows are not appended to it.
    A row is one line: an error's line breaks are written as ' / '."""
    from frictionjoint.results.study import format_row

    st = Study(**{**SMALL, "n_samples": 1})
    full = tmp_path / "full.csv"
    run_study(st, full, workers=1)
    text = full.read_text()
    lines = text.splitlines(keepends=True)
    for cut in (lines[0] + lines[1] + lines[2][:17],  # in the first row
                lines[0] + lines[1][:20],              # in the column line
                lines[0]):                             # after the fingerprint
        path = tmp_path / "cut.csv"
        path.write_text(cut)
        assert len(StudyTable.read(path)) == 0
        run_study(st, path, workers=1)
        assert path.read_bytes() == full.read_bytes()
    assert format_row({"a": 1.0, "error": "ValueError: one\ntwo\r\nthree"}, ("a", "error")) == \
        "1.0,ValueError: one / two / three\n"


@pytest.mark.slow
def test_cli_study_and_plots(tmp_path, monkeypatch):
    """frictionjoint study FILE: the table, the summary and the plot; a Monte Carlo table's plot
    (scatter and histogram with percentiles) and a two-parameter contour."""
    from frictionjoint.cli import main

    monkeypatch.chdir(tmp_path)  # the table curve.csv is written in the working directory

    f = tmp_path / "curve.toml"
    f.write_text('model = "ti64_compressor_blade"\ntable = "curve.csv"\n[vary.centrifugal_force]\nvalues = [615.0, 1458.0]\n'
                 '[sweep]\nomega = "1990:2060:4"\nrefine_peak = false\n')
    assert main(["study", str(f), "--workers", "1", "--plot", str(tmp_path / "curve.png"), "--no-progress"]) == 0
    tab = StudyTable.read(tmp_path / "curve.csv")
    assert len(tab) == 2 and np.all(tab.ok)
    assert (tmp_path / "curve.png").read_bytes()[:4] == b"\x89PNG"
    mc = run_study(Study(**SMALL), tmp_path / "mc.csv", workers=1)
    fig = mc.plot(path=tmp_path / "mc.png")
    assert len(fig.axes) == 2 and (tmp_path / "mc.png").exists()
    q = mc.percentiles()
    assert q[5.0] <= q[50.0] <= q[95.0]
    again = StudyTable.read(tmp_path / "mc.csv")  # the CSV's first line keeps the random parameters
    assert again.random == ("friction_coefficient",) and len(again.plot().axes) == 2
    grid = Study(model="ti64_compressor_blade", omega="1990:2060:4", refine_peak=False,
                 vary={"centrifugal_force": Values((615.0, 1458.0)), "friction_coefficient": Values((0.25, 0.35))})
    fig = run_study(grid, tmp_path / "grid.csv", workers=1).plot(path=tmp_path / "grid.png")
    assert fig.axes[0].get_xlabel() == "centrifugal_force" and fig.axes[0].get_ylabel() == "friction_coefficient"
    with pytest.raises(SystemExit):
        main(["study", str(f), "--workers", "1", "--scheduler", "tcp://127.0.0.1:1"])


def test_study_of_the_blade_fmu_equals_the_library_study(tmp_path, fmus):
    """The model may be an FMU: a study of BladeDovetail.fmu (through fmpy) gives the rows of the
    same study of the library's blade definition (peaks taken at the sweep's points, as an FMU's
    cannot be refined in the library) to 1e-8."""
    common = dict(omega="2000:2040:2", refine_peak=False,
                  vary={"centrifugal_force": Values((615.0, 1458.0))})
    fmu = run_study(Study(model=str(fmus["BladeDovetail"]), **common), tmp_path / "fmu.csv", workers=2)
    lib = run_study(Study(model="ti64_compressor_blade", **common), tmp_path / "lib.csv", workers=1)
    assert np.all(fmu.ok) and np.all(lib.ok)
    for q in ("peak_amplitude", "dissipated_at_peak"):
        assert np.max(np.abs(fmu[q] / lib[q] - 1)) <= 1e-8, q
    np.testing.assert_array_equal(fmu["peak_omega"], lib["peak_omega"])


@pytest.mark.slow
def test_ctrl_c_on_the_command_leaves_a_table_that_resumes(tmp_path):
    """SIGINT to `frictionjoint study` running on the local pool: exit status 130, the table holds
    whole rows of the finished points only, and the same command finishes the others."""
    import os
    import signal
    import subprocess
    import sys
    import time

    f = tmp_path / "s.toml"
    # points of some seconds each (100-1000 N, 6 frequencies: the uninterrupted command 20.5 s at
    # load 4, 9.5 s quiet), so that points remain when the signal comes after the first row
    f.write_text('model = "ti64_compressor_blade"\n[vary.centrifugal_force]\nstart = 100.0\nstop = 1000.0\nnum = 8\n'
                 '[sweep]\nomega = "1990:2060:6"\nrefine_peak = false\n')
    table = tmp_path / "s.csv"
    cmd = [sys.executable, "-m", "frictionjoint", "study", str(f), "--workers", "2", "--no-progress"]
    # Ctrl-C as in a terminal: SIGINT at its default in the command (a shell without job control
    # starts background jobs with SIGINT ignored, which a child inherits and Python then keeps:
    # run so, e.g. from a CI script started with '&', the command never saw the signal)
    proc = subprocess.Popen(cmd, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, cwd=tmp_path,
                            preexec_fn=lambda: signal.signal(signal.SIGINT, signal.SIG_DFL))
    deadline = time.monotonic() + 120
    while time.monotonic() < deadline and (not table.exists() or table.read_text().count("\n") < 3):
        time.sleep(0.1)  # header lines, then the first row
    proc.send_signal(signal.SIGINT)
    out, err = proc.communicate(timeout=120)
    assert proc.returncode == 130, (out, err)
    assert "run again to resume" in err
    done = StudyTable.read(table)
    assert 1 <= len(done) < 8 and np.all(done.ok)
    again = subprocess.run(cmd, capture_output=True, text=True, timeout=300, env=dict(os.environ), cwd=tmp_path)
    assert again.returncode == 0, again.stderr
    final = StudyTable.read(table)
    assert len(final) == 8 and list(final["point"]) == list(range(8)) and np.all(final.ok)
    for k, p in enumerate(done["point"]):  # the rows written before the interruption are kept as they were
        assert final["peak_amplitude"][p] == done["peak_amplitude"][k]


@pytest.mark.slow
def test_harmonic_balance_point_refines_its_peak_on_the_balance():
    """method = 'hbm': the point's sweep is the harmonic-balance branch, and its refined peak is
    the balance's own maximum: at least the branch's largest point, and a balance at the refined
    frequency gives the same amplitude."""
    from frictionjoint.sweep import blade_assembly

    task = dict(point=0, model="ti64_compressor_blade", omega="1990:2060:10", fixed={},
                varied={"centrifugal_force": 259.0}, direction="up", method="hbm", harmonics=5, refine=True)
    row = evaluate_point(task)
    assert row["status"] == "ok" and row["slipping_at_peak"] is True
    asm = blade_assembly("ti64_compressor_blade", {"centrifugal_force": 259.0})
    fr = asm.frequency_response(np.linspace(1990.0, 2060.0, 10), method="hbm", n_harmonics=5)
    assert row["peak_amplitude"] >= fr.amplitude.max() and row["points"] == fr.omega.size
    hb = fj.harmonic_balance(asm.system(row["peak_omega"]), n_harmonics=5)
    assert abs(abs(hb.harmonics[1] @ asm._row(asm.tip)) / row["peak_amplitude"] - 1) <= 1e-9


def test_mode_damping_column_equals_the_nonlinear_mode_run_directly(tmp_path):
    """[quantities] mode_damping (issue 31, part 5): each point's mode_frequency and
    mode_damping_ratio equal fj.nonlinear_mode run directly on the point's blade, over
    mode_amplitudes(amplitude) at the same H and DOF, to 1e-12 (here bit for bit: the same
    computation); the sweep's columns are those of the study without it."""
    from frictionjoint.study.definition import ModeDamping
    from frictionjoint.study.execution import tasks
    from frictionjoint.study.quantities import MODE_QUANTITIES, mode_amplitudes
    from frictionjoint.sweep import blade_assembly

    declared = ModeDamping(amplitude=3e-6, n_harmonics=3, dof="w0")
    st = Study(model=BLADE, omega="1990:2060:4", vary={"centrifugal_force": Values((109.0, 259.0, 2000.0))},
               refine_peak=False, mode_damping={"amplitude": 3e-6, "n_harmonics": 3, "dof": "w0"})
    assert st.mode_damping == declared
    plain = Study(model=BLADE, omega="1990:2060:4", vary={"centrifugal_force": Values((109.0, 259.0, 2000.0))},
                  refine_peak=False)
    assert st.fingerprint() != plain.fingerprint()
    path = tmp_path / "root_damping.toml"
    path.write_text(f'model = "{BLADE}"\n[vary.centrifugal_force]\nvalues = [109.0, 259.0, 2000.0]\n[sweep]\n'
                    'omega = "1990:2060:4"\nrefine_peak = false\n[quantities]\n'
                    'mode_damping = {amplitude = 3e-6, n_harmonics = 3, dof = "w0"}\n')
    assert load_study(path).mode_damping == declared and load_study(path).fingerprint() == st.fingerprint()
    # the declaration travels with each task (execution.tasks: run_study and the CLI use them)
    assert all(t["mode_damping"] == declared for t in tasks(st))
    rows = [evaluate_point(t) for t in tasks(st)]
    for row, p in zip(rows, st.points()):
        assert row["status"] == "ok", row["error"]
        nm = fj.nonlinear_mode(blade_assembly(BLADE, p).system(1990.0), mode=0, amplitudes=mode_amplitudes(3e-6),
                               n_harmonics=3, dof="w0")
        assert abs(row["mode_damping_ratio"] - nm.damping_ratio[-1]) <= 1e-12 * nm.damping_ratio[-1]
        assert abs(row["mode_frequency"] - nm.frequency[-1]) <= 1e-12 * nm.frequency[-1]
    zeta = [r["mode_damping_ratio"] for r in rows]
    print("root damping at 3e-6 m of w0 (H = 3) against the centrifugal force 109, 259, 2000 N:",
          ", ".join(f"{z:.4f}" for z in zeta))
    assert zeta[0] > zeta[-1]  # the lightly loaded root slips at this amplitude, the heavily loaded one sticks
    without = evaluate_point(tasks(plain)[0])
    assert all(math.isnan(without[q]) for q in MODE_QUANTITIES)
    assert {q: without[q] for q in ("peak_amplitude", "peak_omega")} == {q: rows[0][q] for q in ("peak_amplitude", "peak_omega")}


@pytest.mark.parametrize("entry, match", [
    ("mode_damping = {amplitude = -1e-5}", "quantities.mode_damping.amplitude"),
    ("mode_damping = {amplitude = 1e-5, mode = -1}", "quantities.mode_damping.mode"),
    ("mode_damping = {amplitude = 1e-5, n_harmonics = 0}", "quantities.mode_damping.n_harmonics"),
    ("mode_damping = {amplitude = 1e-5, harmonics = 3}", "unknown keys \\['harmonics'\\]"),
    ("mode_damping = {mode = 0}", "amplitude is missing"),
    ("mode_damping = 1e-5", "must be a table"),
    ("root_damping = {amplitude = 1e-5}", "unknown keys in \\[quantities\\]"),
])
def test_bad_mode_damping_declaration_is_refused(tmp_path, entry, match):
    """A bad [quantities] declaration is a ParameterError naming the key and what it takes, when the
    file is loaded (before any point runs)."""
    path = tmp_path / "study.toml"
    path.write_text(f'model = "{BLADE}"\n[vary.centrifugal_force]\nvalues = [100.0]\n[sweep]\nomega = "1990:2060:4"\n'
                    f"[quantities]\n{entry}\n")
    with pytest.raises(ParameterError, match=match):
        load_study(path)

"""Tests of the benchmark harness (benchmarks/harness.py) and `frictionjoint bench`: the pieces of the quick variant on one
case (r = 0.8, F/P0 = 0.3). Errors only -- timings belong to the benchmark, not to tests.

The quick `bench` command runs once (in-process, its cases narrowed to the one case, the FMU built
into a temporary folder); its CSV is then checked: columns, machine header, the marcher's error, the
floor of the regularised baselines, the describing function's error.
"""
import contextlib
import csv
import io
import math

import pytest

from benchmarks import harness as bm  # the harness of the source tree (pytest pythonpath: ".")
from frictionjoint.cli import main

# tolerances, stated once
MARCHER_ERROR = 1e-10          # the brief's bar for the exact marcher (it gets ~1e-15)
STOP_AGREEMENT = 1e-12         # event-driven DOP853 at rtol 2.3e-14 against the exact stop orbit
REGULARISED_FLOOR = 1e-9       # no tanh setting of the quick grid (eps >= 1e-6) gets below this
FLOOR_PER_WIDTH = 0.01         # ... nor below 0.01 eps (its error at tight rtol is ~0.03 eps)
CASE = bm.Case(0.8, 0.3)
PNG_MAGIC = b"\x89PNG\r\n\x1a\n"


@pytest.fixture(scope="module")
def bench(tmp_path_factory):
    """`frictionjoint bench --quick` on one case: (stdout, header lines, CSV rows, out folder)."""
    out = tmp_path_factory.mktemp("bench")
    buf = io.StringIO()
    with pytest.MonkeyPatch.context() as mp, contextlib.redirect_stdout(buf):
        mp.setattr(bm, "CASES", (CASE,))
        status = main(["bench", "--quick", "--repeat", "1", "--out", str(out), "--no-progress"])
    assert status == 0
    text = (out / "work_precision.csv").read_text()
    header = [ln[2:] for ln in text.splitlines() if ln.startswith("#")]
    rows = list(csv.DictReader(ln for ln in text.splitlines() if not ln.startswith("#")))
    return buf.getvalue(), header, rows, out


def _rows(rows, method):
    return [r for r in rows if r["method"] == method]


def test_csv_has_the_columns_and_the_machine(bench):
    _, header, rows, out = bench
    assert tuple(rows[0].keys()) == bm.COLUMNS
    machine = " ".join(header)
    for word in ("CPU", "cores", "python", "numpy", "scipy", "date", "task:"):
        assert word in machine
    methods = {r["method"] for r in rows}
    assert methods == {"exact marcher", "exact SDOF kernel", "steady_state", "FMU sweep", "describing function", "tanh RK45",
                       "tanh LSODA", "tanh Radau", "events DOP853", "harmonic balance"}
    assert {r["case"] for r in rows} == {CASE.label}
    assert all(r["status"] == "ok" for r in rows)
    assert (out / "work_precision.png").read_bytes()[:8] == PNG_MAGIC


def test_marcher_reaches_rounding(bench):
    stdout, _, rows, _ = bench
    (marcher,) = _rows(rows, "exact marcher")
    (kernel,) = _rows(rows, "exact SDOF kernel")
    assert float(marcher["relative_error"]) <= MARCHER_ERROR
    assert float(kernel["relative_error"]) <= MARCHER_ERROR
    assert float(marcher["ratio_to_marcher"]) == 1.0
    assert "fastest exact: exact" in stdout and "x the time" in stdout


def test_amplitudes_are_plain_floats(bench):
    _, _, rows, _ = bench
    for r in rows:
        float(r["amplitude"]), float(r["reference"])   # 'np.float64(...)' would not parse
        assert "np." not in r["amplitude"]


def test_exact_methods_agree_with_den_hartog(bench):
    _, _, rows, _ = bench
    for method in ("steady_state", "FMU sweep", "events DOP853"):
        best = min(float(r["relative_error"]) for r in _rows(rows, method))
        assert best <= 1e-11, method


def test_regularised_baselines_have_a_floor(bench):
    _, _, rows, _ = bench
    tanh = [r for r in rows if r["method"].startswith("tanh")]
    assert len(tanh) == 10
    by_width = {}
    for r in tanh:
        eps = float(r["setting"].split(",")[0].split("=")[1])
        err = float(r["relative_error"])
        assert err >= max(REGULARISED_FLOOR, FLOOR_PER_WIDTH * eps), (r["method"], r["setting"], err)
        by_width.setdefault(eps, []).append(err)
    # the floor is set by the width, not the tolerance: at eps = 1e-3 every setting is within 30 %
    errs = by_width[1e-3]
    assert max(errs) <= 1.3 * min(errs)


def test_describing_function_error(bench):
    _, _, rows, _ = bench
    (df,) = _rows(rows, "describing function")
    # Den Hartog (DESIGN.md section 3) and the one-harmonic balance, written out independently
    r, f = CASE.frequency_ratio, CASE.friction_ratio
    v, u = 1 / (1 - r * r), math.tan(math.pi / (2 * r)) / r
    x_dh = math.sqrt(v * v - f * f * u * u)
    x_hb = math.sqrt(1 - (4 * f / math.pi) ** 2) / abs(1 - r * r)
    assert float(df["relative_error"]) == pytest.approx(abs(x_hb / x_dh - 1), rel=1e-3)
    assert 1e-2 < float(df["relative_error"]) < 5e-2  # 2.2e-2: a few per cent, as expected


def test_harmonic_balance_rows(bench):
    """H = 1 is the describing function (to 1e-10); H = 7 is closer to Den Hartog (the stop-free
    motion is continuous sliding, which the balance represents; the force's jumps make its
    harmonics decay like 1/h, so the truncation error falls slowly)."""
    _, _, rows, _ = bench
    (df,) = _rows(rows, "describing function")
    hbm = {r["setting"]: r for r in _rows(rows, "harmonic balance")}
    assert set(hbm) == {"H=1", "H=7"}
    assert float(hbm["H=1"]["amplitude"]) == pytest.approx(float(df["amplitude"]), rel=1e-10)
    assert float(hbm["H=7"]["relative_error"]) < 0.5 * float(hbm["H=1"]["relative_error"])  # 5.0e-3 against 2.2e-2


def test_stop_case_reference_is_confirmed_independently():
    p = bm.make_problem(bm.Case(2.0, 0.6))
    assert p.regime != "stop-free" and p.reference_name.startswith("exact orbit")
    assert p.error(bm.event_driven_amplitude(p, bm.RTOL_MIN)) <= STOP_AGREEMENT
    assert p.error(bm.marcher_amplitude(p)) <= MARCHER_ERROR
    assert p.error(bm.sdof_amplitude(p)) <= MARCHER_ERROR


def test_headline_matched_and_unmatched():
    p = bm.make_problem(CASE)
    rows = [bm.Row(CASE, "exact marcher", "", 1.0, 1e-15, 0.01, 1, ratio=1.0),
            bm.Row(CASE, "events DOP853", "a", 1.0, 1e-13, 0.02, 1),
            bm.Row(CASE, "tanh RK45", "b", 1.0, 1e-6, 0.005, 1),
            bm.Row(CASE, "steady_state", "c", 1.0, 1e-16, 0.001, 1)]
    h = bm.WorkPrecision(rows, {CASE: p}).headline(CASE)
    assert not h["matched"] and h["baseline"].setting == "a" and h["ratio"] == pytest.approx(2.0)
    assert h["at_threshold"].setting == "a" and h["best_regularised"].setting == "b"
    rows.append(bm.Row(CASE, "tanh LSODA", "d", 1.0, 1e-15, 0.5, 1))
    rows.append(bm.Row(CASE, "tanh Radau", "e", 1.0, 1e-16, 0.3, 1))
    h = bm.WorkPrecision(rows, {CASE: p}).headline(CASE)
    assert h["matched"] and h["baseline"].setting == "e" and h["ratio"] == pytest.approx(30.0)
    # the fastest exact row is the headline's denominator, whichever it is
    rows.append(bm.Row(CASE, "exact SDOF kernel", "", 1.0, 1e-16, 0.001, 1))
    wp = bm.WorkPrecision(rows, {CASE: p})
    h = wp.headline(CASE)
    assert h["marcher"].method == "exact SDOF kernel"
    assert h["matched"] and h["baseline"].setting == "e" and h["ratio"] == pytest.approx(300.0)
    assert h["ratio_at_threshold"] == pytest.approx(20.0)   # 'a' (1e-13, 0.02 s)
    assert "fastest exact: exact SDOF kernel" in wp.summary()
    rows[-1] = bm.Row(CASE, "exact SDOF kernel", "", 1.0, 1e-16, 0.05, 1)
    assert bm.WorkPrecision(rows, {CASE: p}).headline(CASE)["marcher"].method == "exact marcher"


def test_bad_repeat_is_an_argument_error(capsys):
    with pytest.raises(SystemExit) as exc:
        main(["bench", "--repeat", "0"])
    assert exc.value.code == 2
    assert "--repeat" in capsys.readouterr().err


def test_stop_case_reference_agrees_with_the_bruteforce_reference():
    """The benchmark's stop-case reference (the exact orbit) against the one brute-force
    reference of tests and benchmarks (benchmarks/bruteforce.py: solve_ivp DOP853 rtol 1e-12,
    plain period-by-period marching from the orbit's start): 1e-10 relative, the brute force's
    own accuracy (README: 3.3e-12 on the stop cases)."""
    from benchmarks import bruteforce as bf

    p = bm.make_problem(bm.Case(2.0, 0.6))
    ref = bf.coulomb_steady_state(p.mass, p.stiffness, 0.0, p.slip_force, p.force_amplitude, 0.0, p.omega,
                                  x0=p.x0, v0=p.v0)
    assert ref.converged and p.error(ref.amplitude) <= 1e-10

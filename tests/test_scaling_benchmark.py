"""Tests of benchmarks/scaling.py (issue 26's cost-growth table): the script runs on the smallest
chain and prints its table; the growth fit, the time limit and the check's verdicts on made-up rows.
No speed is asserted: timings belong to the benchmark, machines are noisy."""
import math

import numpy as np
import pytest

from benchmarks import scaling  # the benchmark of the source tree (pytest pythonpath: ".")

SAME = scaling.SAME_ORBIT  # amplitudes of the same orbit, relative to the largest (the script's own bar)


@pytest.mark.slow
def test_smallest_chain_prints_the_table(tmp_path, capsys):
    out, amps = tmp_path / "table.txt", tmp_path / "amplitudes.npz"
    status = scaling.main(["--sizes", "20:5", "--limit", "120", "--out", str(out), "--amplitudes", str(amps)])
    assert status == 0
    printed = capsys.readouterr().out
    text = out.read_text()
    for word in ("DOP853", "rtol=1e-06, atol=1e-09", "rtol=1e-10, atol=1e-12", "cold", "warm", "HBM7", "HBM15",
                 "growth exponents"):
        assert word in text
    row = next(line for line in text.splitlines() if line.split()[:2] == ["20", "5"])
    assert "periodic" in row and "limit" not in row and "error" not in row
    assert row in printed  # the table is printed too
    assert "note:" not in text  # HBM converged, warm found the cold orbit, the worker ended cleanly
    with np.load(amps) as f:
        assert f.files == ["20_5"] and f["20_5"].shape == (20,)


def test_linear_stuck_is_the_chain_with_its_joints_stuck():
    system = scaling.chain(6, 2)
    a, g_cos, g_sin = scaling.linear_stuck(system)
    k = system.structure.stiffness.copy()
    for e in system.elements:
        k[e.dof, e.dof] += e.tangential_stiffness
    n = system.n_dof
    assert np.allclose(a[n:, :n], -k, rtol=0, atol=1e-15)  # unit masses
    assert np.allclose(a[n:, n:], -system.structure.damping, rtol=0, atol=1e-15)
    assert g_cos[-1] == 0.01 and not g_cos[:-1].any() and not g_sin.any()


def test_growth_is_the_slope_over_the_finished_rows():
    rows = [{"n": n, "cold": 1e-3 * n ** 2.0} for n in (20, 50, 100)] + [{"n": 200, "limit": True}]
    p, count = scaling.growth(rows, "cold")
    assert count == 3 and p == pytest.approx(2.0, rel=1e-12)
    assert math.isnan(scaling.growth(rows[:1], "cold")[0])
    rows[0]["cold"] *= 10  # a fixed cost at the smallest size: the last two sizes do not see it
    p, count = scaling.growth(rows, "cold", last=2)
    assert count == 2 and p == pytest.approx(2.0, rel=1e-12)


def test_check_names_each_missed_target():
    amp = np.ones(100)
    rows = [{"n": 100, "joints": 20, "dop853": 1.0, "cold": 0.4, "status": "periodic", "amplitude": amp},
            {"n": 200, "joints": 40, "dop853": 2.0, "cold": 1.5, "hbm7": 0.05, "status": "periodic"}]
    failures = scaling.check(rows, None)
    assert len(failures) == 1 and "(200, 40) cold" in failures[0]
    rows[1]["cold"], rows[1]["hbm7"] = 0.9, 0.2
    assert [f.split(":")[0] for f in scaling.check(rows, None)] == ["(200, 40) hbm7"]
    rows[1]["hbm7"] = 0.09
    assert scaling.check(rows, None) == []
    assert scaling.check(rows, {"100_20": amp * (1 + 0.5 * SAME)}) == []
    assert "amplitudes differ" in scaling.check(rows, {"100_20": amp * (1 + 4 * SAME)})[0]
    # relative to the largest amplitude: a DOF that moves 1/100 of the largest may differ by 100 SAME of its own
    small = amp.copy()
    small[0] = 0.01
    off = small.copy()
    off[0] *= 1 + 50 * SAME
    rows[0]["amplitude"] = off
    assert scaling.check(rows, {"100_20": small}) == []
    rows[0]["amplitude"] = amp
    del rows[1]["hbm7"]
    assert "not measured" in scaling.check(rows, None)[0]


def test_a_size_past_its_limit_reads_limit():
    row = scaling.run_size(20, 5, 0.05)  # the worker has not even imported the library
    assert row["limit"] and "cold" not in row
    assert "> limit" in scaling.row_lines(row, None)[0]


@pytest.mark.slow
def test_a_size_past_its_memory_reads_memory():
    row = scaling.run_size(20, 5, 120, memory=0.02)  # NumPy alone takes more
    assert row["memory"] and row["rss"] > 0.02 and "cold" not in row
    lines = scaling.row_lines(row, None)
    assert "> memory" in lines[0] and "memory limit" in lines[1]

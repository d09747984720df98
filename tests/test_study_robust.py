"""Design studies under a careless user and a hostile host (issue 25): one frequency convention, a
definition refused whole when it is loaded (before any point runs), switches from a study file,
journals that are never discarded silently, one-line errors and a non-zero exit status, a per-point
time limit serially, on the local pool and on Dask, and pool workers that end with their runner.

References: the study's rows against direct sweeps of the same parameters (frictionjoint.sweep);
the frequency grid against numpy.linspace; everything else is a behaviour asserted directly (an
error, an exit status, a process that is or is not alive)."""
import math
import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
import pytest

import frictionjoint as fj
from frictionjoint.cli import main
from frictionjoint.errors import ParameterError
from frictionjoint.results.study import StudyTable, format_row, header_line
from frictionjoint.structures import BladeAssembly
from frictionjoint.study import Study, Values, load_study, run_study
from frictionjoint.study.execution import TableConflict, tasks
from frictionjoint.study.quantities import QUANTITIES

BLADE = "ti64_compressor_blade"
TWO = {"centrifugal_force": Values((109.0, 259.0))}


def _toml(tmp_path, text: str, name: str = "s.toml") -> Path:
    f = tmp_path / name
    f.write_text(f'model = "{BLADE}"\n' + text)
    return f


# -- frequencies ------------------------------------------------------------------------------

def test_omega_takes_the_one_convention_and_refuses_the_old_triple():
    """'START:STOP:N' is numpy.linspace(START, STOP, N); the frequencies themselves are kept; the
    old (start, stop, N) could mean three frequencies and is refused with both right forms."""
    st = Study(model=BLADE, omega="1950:2100:40", vary=TWO)
    np.testing.assert_array_equal(st.omega, np.linspace(1950.0, 2100.0, 40))
    np.testing.assert_array_equal(Study(model=BLADE, omega=[2000.0, 1990.0], vary=TWO).omega, [2000.0, 1990.0])
    with pytest.raises(ParameterError, match=r"'1950.0:2100.0:40'.*\[1950.0, 2100.0, 40.0\]"):
        Study(model=BLADE, omega=(1950.0, 2100.0, 40), vary=TWO)
    # a count is an integer: three frequencies whose last is written as a float are frequencies
    np.testing.assert_array_equal(Study(model=BLADE, omega=[1950.0, 2000.0, 2100.0], vary=TWO).omega,
                                  [1950.0, 2000.0, 2100.0])
    with pytest.raises(ParameterError, match="harmonic-balance branch needs two frequencies"):
        Study(model=BLADE, omega=[2000.0], vary=TWO, method="hbm")


@pytest.mark.slow
def test_a_point_sweeps_the_frequencies_of_the_convention():
    """A task's omega in either form gives the same row (the grid is the frequencies)."""
    from frictionjoint.study import evaluate_point

    base = dict(point=0, model=BLADE, fixed={}, varied={"centrifugal_force": 259.0}, direction="up",
                method="time", harmonics=7, refine=False)
    a = evaluate_point(dict(base, omega="1990:2060:3"))
    b = evaluate_point(dict(base, omega=np.array([2060.0, 2025.0, 1990.0])))  # any order: swept upwards
    assert a["status"] == "ok" and a["points"] == 3
    assert {k: a[k] for k in QUANTITIES} == {k: b[k] for k in QUANTITIES}


# -- switches ---------------------------------------------------------------------------------

@pytest.mark.slow
@pytest.mark.parametrize("value", ["true", "1"])
def test_switch_from_a_study_file_runs_the_point(tmp_path, value):
    """[fixed] normal_load_variation = true (or 1) is the switch: the point's row is the direct
    sweep's with normal_load_variation=True (refine_peak off: the peak is the sweep's largest)."""
    f = _toml(tmp_path, f"[fixed]\nnormal_load_variation = {value}\n[vary.centrifugal_force]\nvalues = [259.0]\n"
                        '[sweep]\nomega = "1990:2060:3"\nrefine_peak = false\n')
    st = load_study(f)
    assert st.fixed == {"normal_load_variation": True}
    tab = run_study(st, tmp_path / "t.csv", workers=1)
    fr = fj.sweep(BLADE, np.linspace(1990.0, 2060.0, 3), {"centrifugal_force": 259.0, "normal_load_variation": True})
    assert tab["status"][0] == "ok"
    assert tab["peak_amplitude"][0] == np.max(fr.amplitude)  # same computation, same bits


# -- a definition refused when it is loaded ---------------------------------------------------

BAD = [
    ("model misspelt", 'model = "ti64_compresor_blade"\n[vary.centrifugal_force]\nvalues = [1.0]\n'
                       '[sweep]\nomega = "1:2:3"\n', ["ti64_compresor_blade", "not found", "'ti64_compressor_blade'"]),
    ("fmu missing", 'model = "nowhere/Blade.fmu"\n[vary.centrifugal_force]\nvalues = [1.0]\n[sweep]\nomega = "1:2:3"\n',
     ["Blade.fmu", "not found"]),
    ("varied misspelt", '[vary.centrifugal_forse]\nvalues = [1.0]\n[sweep]\nomega = "1:2:3"\n',
     ["vary.centrifugal_forse", "'centrifugal_force'", "'friction_coefficient'"]),
    ("fixed misspelt", '[fixed]\nfriction_coeficient = 0.3\n[vary.centrifugal_force]\nvalues = [1.0]\n'
                       '[sweep]\nomega = "1:2:3"\n', ["fixed.friction_coeficient", "'friction_coefficient'"]),
    ("fixed nan", '[fixed]\nfriction_coefficient = nan\n[vary.centrifugal_force]\nvalues = [1.0]\n'
                  '[sweep]\nomega = "1:2:3"\n', ["fixed.friction_coefficient", "finite"]),
    ("fixed inf", '[fixed]\nnormal_stiffness = inf\n[vary.centrifugal_force]\nvalues = [1.0]\n'
                  '[sweep]\nomega = "1:2:3"\n', ["fixed.normal_stiffness", "finite"]),
    ("switch not 0 or 1", '[fixed]\nnormal_load_variation = 2\n[vary.centrifugal_force]\nvalues = [1.0]\n'
                          '[sweep]\nomega = "1:2:3"\n', ["fixed.normal_load_variation", "True or False"]),
    ("three grids of 1000", "".join(f"[vary.{n}]\nstart = 1.0\nstop = 2.0\nnum = 1000\n" for n in
                                    ("centrifugal_force", "friction_coefficient", "normal_stiffness"))
     + '[sweep]\nomega = "1:2:3"\n', ["1000000000 points", "vary.normal_stiffness", "100000"]),
    ("num 1e9", '[vary.centrifugal_force]\nstart = 1.0\nstop = 2.0\nnum = 1000000000\n[sweep]\nomega = "1:2:3"\n',
     ["vary.centrifugal_force.num", "100000"]),
    ("num a float", '[vary.centrifugal_force]\nstart = 1.0\nstop = 2.0\nnum = 1e9\n[sweep]\nomega = "1:2:3"\n',
     ["vary.centrifugal_force.num", "integer"]),
    ("old omega triple", '[vary.centrifugal_force]\nvalues = [1.0]\n[sweep]\nomega = [1950.0, 2100.0, 40]\n',
     ["'1950.0:2100.0:40'"]),
    ("time limit", '[vary.centrifugal_force]\nvalues = [1.0]\n[sweep]\nomega = "1:2:3"\ntime_limit = 0\n',
     ["time_limit", "> 0"]),
]


@pytest.mark.parametrize("label, text, names", BAD, ids=[b[0] for b in BAD])
def test_bad_definition_is_refused_when_loaded(tmp_path, monkeypatch, label, text, names):
    """Each is a ParameterError of load_study naming the key (and the allowed names); the command
    exits with status 2 before any point runs (no table written)."""
    monkeypatch.chdir(tmp_path)  # where the table would go
    f = tmp_path / "s.toml"
    f.write_text(text if text.startswith("model") else f'model = "{BLADE}"\n' + text)
    with pytest.raises(ParameterError) as info:
        load_study(f)
    for name in names:
        assert name in str(info.value), (name, str(info.value))
    with pytest.raises(SystemExit) as code:
        main(["study", str(f), "--workers", "1", "--no-progress"])
    assert code.value.code == 2 and not (tmp_path / "s.csv").exists()


def test_study_file_not_utf8_is_one_line(tmp_path, capsys):
    f = tmp_path / "s.toml"
    f.write_bytes(b'model = "ti64_compressor_blade"  # \xe9t\xe9 (Latin-1)\n')
    with pytest.raises(ParameterError, match="not UTF-8"):
        load_study(f)
    with pytest.raises(SystemExit) as code:
        main(["study", str(f)])
    err = capsys.readouterr().err
    assert code.value.code == 2 and "not UTF-8" in err and "Traceback" not in err


# -- the table: refusals and journals ---------------------------------------------------------

def _journal(st: Study, rows: int = 2, columns_line: bool = True, changed=None) -> str:
    """A journal of ``st`` as the runner writes it, with made-up quantities (status 'ok')."""
    columns = ("point", *st.varied, *QUANTITIES, "status", "error")
    text = header_line(st.fingerprint(), ())
    if columns_line:
        text += format_row({c: c for c in columns}, columns)
    for t in tasks(st)[:rows]:
        row = {"point": t["point"], **t["varied"], **{q: 1e-4 * (t["point"] + 1) for q in QUANTITIES},
               "slipping_at_peak": True, "peak_at_edge": False, "converged_points": 3, "points": 3,
               "status": "ok", "error": ""}
        row.update((changed or {}).get(t["point"], {}))
        text += format_row(row, columns)
    return text


def _never(row):
    raise AssertionError(f"point {row['point']} was computed")


@pytest.mark.parametrize("how", ["column line lost", "Windows editor"])
def test_journal_of_finished_rows_is_read_not_discarded(tmp_path, how):
    """A journal whose column line was lost, or saved by a Windows editor (a byte-order mark and CR
    LF line ends): its finished rows are the study's; nothing is computed again and the table
    keeps them."""
    st = Study(model=BLADE, omega="1990:2060:3", vary=TWO, refine_peak=False)
    text = _journal(st, columns_line=how != "column line lost")
    path = tmp_path / "t.csv"
    if how == "Windows editor":
        path.write_bytes(b"\xef\xbb\xbf" + text.replace("\n", "\r\n").encode())
    else:
        path.write_text(text)
    tab = run_study(st, path, workers=1, on_row=_never)
    assert list(tab["point"]) == [0, 1] and list(tab["peak_amplitude"]) == [1e-4, 2e-4]
    assert path.read_text() == _journal(st)  # rewritten whole, as the runner writes it


def test_journal_rows_that_are_not_the_studys_are_refused(tmp_path, monkeypatch, capsys):
    """A row whose parameters differ from its point's, and a line that is not a row, are refused
    with the reason (never taken, never dropped); another study's table names restart=True in
    Python and --restart on the command line."""
    monkeypatch.chdir(tmp_path)  # the command's table t.csv is the one written here
    st = Study(model=BLADE, omega="1990:2060:3", vary=TWO, refine_peak=False)
    path = tmp_path / "t.csv"
    path.write_text(_journal(st, changed={1: {"centrifugal_force": 999.0}}))
    with pytest.raises(TableConflict, match=r"point 1 has centrifugal_force = 999.0 \(the study's 259.0\)"):
        run_study(st, path, workers=1, on_row=_never)
    lines = _journal(st).splitlines(keepends=True)
    path.write_text(lines[0] + lines[1] + "garbage,1\n" + lines[2])
    with pytest.raises(ParameterError, match="line 3 is not a row"):
        run_study(st, path, workers=1, on_row=_never)
    assert path.read_text() == lines[0] + lines[1] + "garbage,1\n" + lines[2]  # left as it was
    other = Study(model=BLADE, omega="1990:2060:4", vary=TWO, refine_peak=False)
    path.write_text(_journal(other))
    with pytest.raises(TableConflict, match="another study.*restart=True"):
        run_study(st, path, workers=1, on_row=_never)
    f = _toml(tmp_path, '[vary.centrifugal_force]\nvalues = [109.0, 259.0]\n[sweep]\nomega = "1990:2060:3"\n'
                        "refine_peak = false\n", name="t.toml")
    capsys.readouterr()
    with pytest.raises(SystemExit) as code:
        main(["study", str(f), "--workers", "1"])
    err = capsys.readouterr().err
    assert code.value.code == 2 and "--restart" in err and "restart=True" not in err, err


@pytest.mark.parametrize("kind", ["garbage parquet", "directory"])
def test_bad_table_is_one_line(tmp_path, kind, capsys):
    """A --table that is not a Parquet file, or a directory: a ParameterError, the command's error
    line (status 2, no traceback)."""
    f = _toml(tmp_path, '[vary.centrifugal_force]\nvalues = [259.0]\n[sweep]\nomega = "1990:2060:3"\n')
    if kind == "directory":
        table = tmp_path / "t.csv"
        table.mkdir()
    else:
        table = tmp_path / "t.parquet"
        table.write_bytes(os.urandom(200))
    with pytest.raises(ParameterError, match="directory" if kind == "directory" else "not a readable Parquet"):
        run_study(load_study(f), table, workers=1, on_row=_never)
    capsys.readouterr()
    with pytest.raises(SystemExit) as code:
        main(["study", str(f), "--table", str(table)])
    err = capsys.readouterr().err
    assert code.value.code == 2 and err.strip().splitlines()[-1].startswith("frictionjoint study: error: "), err


@pytest.mark.slow
def test_failed_point_gives_exit_status_1_and_a_last_line(tmp_path, monkeypatch, capsys):
    monkeypatch.chdir(tmp_path)  # the table s.csv goes here
    f = _toml(tmp_path, '[vary.centrifugal_force]\nvalues = [259.0, -5.0]\n[sweep]\nomega = "1990:2060:3"\n'
                        "refine_peak = false\n")
    assert main(["study", str(f), "--workers", "1", "--no-progress"]) == 1
    out = capsys.readouterr().out.strip().splitlines()
    assert out[-1].startswith("1 of 2 points failed")


# -- the time limit of a point ----------------------------------------------------------------

class SlowRoot(BladeAssembly):
    """A blade whose root takes ``SECONDS`` to change: in Python steps of 10 ms (a Python-level
    loop, which the point's own limit interrupts), or in one uninterruptible call if made
    ``stuck`` (time.sleep in C: only the pool's kill ends it)."""

    SECONDS = 60.0

    def with_root(self, **changes):
        if self.__dict__.get("stuck"):
            time.sleep(self.SECONDS)
        else:
            end = time.monotonic() + self.SECONDS
            while time.monotonic() < end:
                time.sleep(0.01)
        return BladeAssembly.with_root(self, **changes)


def _slow_blade(stuck: bool = False) -> SlowRoot:
    asm = BladeAssembly.from_model(fj.structures.load_blade_model(BLADE))
    slow = SlowRoot.__new__(SlowRoot)
    slow.__dict__.update(asm.__dict__, stuck=stuck)  # pickled with the instance, to the pool's workers
    return slow


@pytest.mark.slow
def test_time_limit_serially_and_a_resumed_study_computes_those_points_again(tmp_path, monkeypatch):
    """workers=1: a point still running at its limit is a failed row saying so, within about the
    limit; run again (the model fast, a longer limit: the same study), those points are computed."""
    slow = _slow_blade()
    # cheap root loads (test_study.SMALL's): the run again computes both points, 4 s less than at TWO's
    cheap = {"centrifugal_force": Values((615.0, 1458.0))}
    st = Study(model=slow, omega="1990:2060:3", vary=cheap, refine_peak=False, time_limit=0.5)
    t0 = time.monotonic()
    tab = run_study(st, tmp_path / "t.csv", workers=1)
    assert time.monotonic() - t0 < 10.0
    assert list(tab["status"]) == ["failed", "failed"]
    assert all(e.startswith("TimeLimit: the point did not finish within 0.5 s") for e in tab["error"])
    monkeypatch.setattr(SlowRoot, "SECONDS", 0.0)
    again = []
    st = Study(model=slow, omega="1990:2060:3", vary=cheap, refine_peak=False, time_limit=60.0)
    tab = run_study(st, tmp_path / "t.csv", workers=1, on_row=lambda r: again.append(r["point"]))
    assert again == [0, 1] and list(tab["status"]) == ["ok", "ok"]


@pytest.mark.slow
def test_time_limit_on_the_pool_kills_a_point_stuck_in_one_call(tmp_path):
    """On the local pool a point stuck in one call that its thread cannot leave (a compiled loop;
    here time.sleep) ends a grace period after the limit: its worker is killed and replaced."""
    st = Study(model=_slow_blade(stuck=True), omega="1990:2060:3", vary=TWO, refine_peak=False, time_limit=0.5)
    t0 = time.monotonic()
    tab = run_study(st, tmp_path / "t.csv", workers=2)
    assert time.monotonic() - t0 < 45.0  # not the 60 s of the stuck call (2.5 s and the workers' start)
    assert list(tab["status"]) == ["failed", "failed"] and all(e.startswith("TimeLimit:") for e in tab["error"])


@pytest.mark.slow
def test_time_limit_of_a_last_remaining_point_is_the_pools(tmp_path):
    """The one point left of a study (a resumed study whose last point hit its limit) runs on the
    pool too: stuck in one call, it is killed after its limit (it ran in the runner's own thread
    once, where nothing could stop it)."""
    st = Study(model=_slow_blade(stuck=True), omega="1990:2060:3", vary={"centrifugal_force": Values((259.0,))},
               refine_peak=False, time_limit=0.5)
    t0 = time.monotonic()
    tab = run_study(st, tmp_path / "t.csv", workers=2)
    assert time.monotonic() - t0 < 45.0  # not the 60 s of the stuck call
    assert list(tab["status"]) == ["failed"] and tab["error"][0].startswith("TimeLimit:")


@pytest.mark.slow
def test_time_limit_on_dask_worker_threads(tmp_path):
    """A Dask worker runs points in threads (no signals there): the limit is still raised in the
    point's thread."""
    distributed = pytest.importorskip("distributed")
    st = Study(model=_slow_blade(), omega="1990:2060:3", vary=TWO, refine_peak=False, time_limit=0.5)
    with distributed.LocalCluster(n_workers=1, threads_per_worker=2, processes=False, dashboard_address=None) as cl:
        t0 = time.monotonic()
        tab = run_study(st, tmp_path / "t.csv", scheduler=cl.scheduler_address)
        assert time.monotonic() - t0 < 20.0
    assert list(tab["status"]) == ["failed", "failed"] and all(e.startswith("TimeLimit:") for e in tab["error"])


# -- workers end with their runner ------------------------------------------------------------

def _children(pid: int) -> set[int]:
    """The live processes whose parent is ``pid`` (from /proc)."""
    out = set()
    for entry in os.listdir("/proc"):
        if entry.isdigit():
            try:
                stat = Path(f"/proc/{entry}/stat").read_text()
            except OSError:
                continue
            fields = stat[stat.rfind(")") + 2:].split()
            if int(fields[1]) == pid and fields[0] != "Z":
                out.add(int(entry))
    return out


def _alive(pid: int) -> bool:
    try:
        stat = Path(f"/proc/{pid}/stat").read_text()
    except OSError:
        return False
    return stat[stat.rfind(")") + 2:].split()[0] != "Z"  # a zombie has ended


@pytest.mark.slow
@pytest.mark.skipif(not Path("/proc/self/stat").exists(), reason="reads /proc")
@pytest.mark.parametrize("sig", [signal.SIGKILL, signal.SIGTERM], ids=["SIGKILL", "SIGTERM"])
def test_workers_and_resource_tracker_end_when_the_runner_is_killed(tmp_path, sig):
    """`frictionjoint study --workers 2` killed while its workers compute: within seconds no worker
    and no resource tracker of it is left (they would block forever on their parent's pipe)."""
    f = _toml(tmp_path, '[vary.centrifugal_force]\nstart = 100.0\nstop = 1000.0\nnum = 8\n'
                        '[sweep]\nomega = "1990:2060:6"\n')
    proc = subprocess.Popen([sys.executable, "-m", "frictionjoint", "study", str(f), "--workers", "2", "--no-progress"],
                            stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL, cwd=tmp_path)
    family = set()
    try:
        deadline = time.monotonic() + 120
        while time.monotonic() < deadline and len(_children(proc.pid)) < 3:  # two workers, one tracker
            time.sleep(0.2)
        family = _children(proc.pid)
        assert len(family) >= 3, family
        time.sleep(1.0)  # the workers inside their first point
        proc.send_signal(sig)
        proc.wait(30)
        deadline = time.monotonic() + 15
        while time.monotonic() < deadline and any(_alive(p) for p in family):
            time.sleep(0.2)
        assert not [p for p in family if _alive(p)]
    finally:
        for p in family | {proc.pid}:
            if _alive(p):
                os.kill(p, signal.SIGKILL)


# -- preconditions before anything finished is touched (issue 39, section 5) -------------------

#: a scheduler address where nothing listens (port 1: refused at once on this host)
NOWHERE = "tcp://127.0.0.1:1"
#: the connect timeout the tests give the runner [s] (execution.CONNECT_TIMEOUT, 10 s by default):
#: short, so that a service that never answers is refused quickly
SHORT = 0.5
#: the most a refused scheduler may take [s]: the timeout, Dask's import (~1.3 s measured) and its
#: retries' back-off, with 10x margin for a loaded 2-core machine
BOUNDED = 10 * (SHORT + 1.5)


def _finished(tmp_path, name: str = "t") -> tuple[Path, Path, str]:
    """A study file (two points) and its finished table (rows as the runner writes them)."""
    f = _toml(tmp_path, f'table = "{name}.csv"\n[vary.centrifugal_force]\nvalues = [109.0, 259.0]\n'
                        '[sweep]\nomega = "1990:2060:3"\nrefine_peak = false\n', name=f"{name}.toml")
    text = _journal(load_study(f))
    table = tmp_path / f"{name}.csv"
    table.write_text(text)
    return f, table, text


@pytest.mark.parametrize("restart", [True, False], ids=["--restart", "finished"])
def test_unreachable_scheduler_is_refused_before_the_table_is_touched(tmp_path, monkeypatch, capsys, restart):
    """`study FILE --scheduler ADDR [--restart]` with no scheduler at ADDR: one error line naming
    --scheduler (status 2), and the finished rows are still there, byte for byte (before: --restart
    deleted them before the scheduler was contacted; on a finished table the command reported
    success 'on the Dask cluster at ...' without contacting it). The same from Python."""
    from frictionjoint.study import execution

    monkeypatch.setattr(execution, "CONNECT_TIMEOUT", SHORT)
    monkeypatch.chdir(tmp_path)
    f, table, text = _finished(tmp_path)
    capsys.readouterr()
    start = time.monotonic()
    with pytest.raises(SystemExit) as code:
        main(["study", str(f), "--scheduler", NOWHERE, "--no-progress"] + ["--restart"] * restart)
    err = capsys.readouterr().err
    assert time.monotonic() - start <= BOUNDED
    assert code.value.code == 2 and err.strip().splitlines()[-1].startswith("frictionjoint study: error: --scheduler: ")
    assert "Traceback" not in err and NOWHERE in err, err
    assert table.read_text() == text
    with pytest.raises(ParameterError, match="scheduler"):
        run_study(load_study(f), table, scheduler=NOWHERE, restart=restart, on_row=_never)
    assert table.read_text() == text


def test_folder_that_cannot_be_written_is_refused_before_the_table_is_touched(tmp_path, monkeypatch):
    """A table in a folder that cannot be written (a read-only mount: tried by creating a file
    there, which the mode bits cannot tell for root) is refused, naming the table, before the
    finished rows are touched, even with restart (made read-only here by the file creation failing
    as on such a mount)."""
    import errno

    from frictionjoint.study import execution

    f, table, text = _finished(tmp_path)

    def read_only(*args, **kwargs):
        raise OSError(errno.EROFS, "Read-only file system")

    monkeypatch.setattr(execution.tempfile, "TemporaryFile", read_only)
    with pytest.raises(ParameterError, match="table: cannot write in the folder of .*Read-only file system"):
        run_study(load_study(f), table, workers=1, restart=True, on_row=_never)
    assert table.read_text() == text


def test_finished_table_says_nothing_was_computed(tmp_path, monkeypatch, capsys):
    """A study run again on its finished table computes nothing and says so (not that it ran)."""
    monkeypatch.chdir(tmp_path)
    f, table, text = _finished(tmp_path)
    capsys.readouterr()
    assert main(["study", str(f), "--workers", "1", "--no-progress"]) == 0
    out = capsys.readouterr().out
    assert "nothing computed: the 2 points were already in" in out, out
    assert table.read_text() == text


def test_live_scheduler_is_named_with_its_workers_and_a_finished_table_computes_nothing(tmp_path, monkeypatch, capsys):
    """On a live Dask scheduler (an in-process LocalCluster, one worker thread): the command names
    it with its workers, computes the points there; run again it says that nothing was computed;
    with --restart it computes them again (the same rows, bit for bit)."""
    distributed = pytest.importorskip("distributed")
    monkeypatch.chdir(tmp_path)
    # 2000 and 19400 N: the root sticks, the cheapest sweeps (0.05 s a point)
    f = _toml(tmp_path, '[vary.centrifugal_force]\nvalues = [2000.0, 19400.0]\n[sweep]\nomega = "1990:2060:2"\n'
                        "refine_peak = false\n")
    with distributed.LocalCluster(n_workers=1, threads_per_worker=1, processes=False, dashboard_address=None) as cl:
        address = cl.scheduler_address
        runs = []
        for extra in ([], [], ["--restart"]):
            capsys.readouterr()
            assert main(["study", str(f), "--scheduler", address, "--no-progress", *extra]) == 0
            runs.append(capsys.readouterr().out)
            if not extra:
                first = (tmp_path / "s.csv").read_bytes() if len(runs) == 1 else first
    assert f"on the Dask cluster at {address} (1 worker now)" in runs[0], runs[0]
    assert "nothing computed" not in runs[0] and "nothing computed" not in runs[2]
    assert "nothing computed: the 2 points were already in" in runs[1], runs[1]
    assert (tmp_path / "s.csv").read_bytes() == first
    assert list(StudyTable.read(tmp_path / "s.csv")["status"]) == ["ok", "ok"]


class _NotDask:
    """A TCP service on 127.0.0.1 that is not a Dask scheduler: it answers ``garbage`` (an HTTP
    reply, whose first bytes Dask reads as a frame length of exabytes), nothing (``silent``) or
    closes the connection (``close``)."""

    def __init__(self, how: str):
        import socket
        import threading

        self.how, self.sock = how, socket.create_server(("127.0.0.1", 0))
        self.address = f"tcp://127.0.0.1:{self.sock.getsockname()[1]}"
        self.open = []
        threading.Thread(target=self._serve, daemon=True).start()

    def _serve(self):
        while True:
            try:
                conn, _ = self.sock.accept()
            except OSError:
                return
            if self.how == "close":
                conn.close()
                continue
            self.open.append(conn)
            if self.how == "garbage":
                try:
                    conn.sendall(b"HTTP/1.0 200 OK\r\nContent-Type: text/plain\r\n\r\nhello\r\n" * 50)
                except OSError:
                    pass

    def close(self):
        for c in self.open:
            c.close()
        self.sock.close()


@pytest.mark.parametrize("how", ["garbage", "silent", "close"])
def test_scheduler_that_is_not_dask_is_one_line_in_bounded_time(tmp_path, monkeypatch, capsys, how):
    """--scheduler at a TCP service that is not a Dask scheduler: one error line naming
    --scheduler, status 2, within the connect timeout (before: garbage gave a MemoryError traceback
    of a 3 EiB frame, silence hung forever)."""
    from frictionjoint.study import execution

    monkeypatch.setattr(execution, "CONNECT_TIMEOUT", SHORT)
    f, table, text = _finished(tmp_path)
    service = _NotDask(how)
    try:
        capsys.readouterr()
        start = time.monotonic()
        with pytest.raises(SystemExit) as code:
            main(["study", str(f), "--scheduler", service.address, "--restart", "--no-progress"])
        elapsed = time.monotonic() - start
        err = capsys.readouterr().err
    finally:
        service.close()
    assert code.value.code == 2 and "Traceback" not in err, err
    assert err.strip().splitlines()[-1].startswith(f"frictionjoint study: error: --scheduler: "), err
    assert service.address in err and elapsed <= BOUNDED, (elapsed, err)
    assert table.read_text() == text


# -- the nonlinear mode's declaration checked at load, its failure a partial row -----------------

@pytest.mark.parametrize("entry, match", [
    ("{amplitude = 1e-5, mode = 99}", r"quantities.mode_damping.mode must be < 9 \(the blade's 9 DOFs"),
    ("{amplitude = 1e-5, mode = 9}", r"quantities.mode_damping.mode must be < 9"),
    ("{amplitude = 1e-5, dof = 'nope'}", r"quantities.mode_damping.dof: 'nope' is not a DOF of the blade.*'w0'"),
])
def test_mode_damping_is_checked_against_the_blade_when_loaded(tmp_path, entry, match):
    """[quantities] mode_damping's mode must be one of the blade's (9 DOFs, hence 9 stuck modes,
    0 to 8) and its dof one of the blade's DOFs: refused when the file is loaded, before any point
    runs (before: every point ran its sweep and then failed)."""
    f = _toml(tmp_path, '[vary.centrifugal_force]\nvalues = [259.0]\n[sweep]\nomega = "1990:2060:3"\n'
                        f"[quantities]\nmode_damping = {entry}\n")
    with pytest.raises(ParameterError, match=match) as exc:
        load_study(f)
    assert str(f) in str(exc.value)
    assert BladeAssembly.from_model(fj.structures.load_blade_model(BLADE)).structure.n_dof == 9
    ok = _toml(tmp_path, '[vary.centrifugal_force]\nvalues = [259.0]\n[sweep]\nomega = "1990:2060:3"\n'
                         "[quantities]\nmode_damping = {amplitude = 1e-5, mode = 8, dof = 'w0'}\n", name="ok.toml")
    assert load_study(ok).mode_damping.mode == 8


def test_mode_that_fails_at_a_point_keeps_the_sweeps_columns(monkeypatch):
    """A nonlinear mode that raises at a point (here made to) leaves the row 'partial' with the
    sweep's own columns, equal to the row without the declaration, the mode's columns empty and
    the mode's error (docs/studies.md; before: a 'failed' row without the sweep's columns)."""
    from frictionjoint.study import point

    def broken(*args, **kwargs):
        raise ParameterError("nonlinear_mode: the stuck linear mode 0 has a node at dof 1")

    # 2000 N: the root sticks, the cheapest sweep (0.06 s; 1.8 s at 259 N where it slips)
    kw = dict(model=BLADE, omega="1990:2060:2", vary={"centrifugal_force": Values((2000.0,))}, refine_peak=False)
    plain = point.evaluate_point(tasks(Study(**kw))[0])
    monkeypatch.setattr(point, "mode_quantities", broken)
    row = point.evaluate_point(tasks(Study(**kw, mode_damping={"amplitude": 1e-5}))[0])
    assert plain["status"] == "ok" and row["status"] == "partial", row
    assert "mode_damping" in row["error"] and "has a node at dof 1" in row["error"], row["error"]
    for q in QUANTITIES:
        if q in ("mode_frequency", "mode_damping_ratio"):
            assert math.isnan(row[q])
        else:
            assert row[q] == plain[q] or (math.isnan(row[q]) and math.isnan(plain[q])), q


# -- where the table goes, and the file's errors ----------------------------------------------

def test_table_is_written_in_the_working_directory(tmp_path, monkeypatch):
    """A study's table (its file's 'table', or the file's name with .csv) is relative to the
    working directory, not to the study file: running an example does not write into the source
    tree. The model's path stays relative to the file."""
    src, work = tmp_path / "src", tmp_path / "work"
    src.mkdir()
    work.mkdir()
    monkeypatch.chdir(work)
    named = _toml(src, 'table = "curve.csv"\n[vary.centrifugal_force]\nvalues = [259.0]\n[sweep]\nomega = "1990:2060:3"\n')
    assert Path(load_study(named).table).resolve() == work / "curve.csv"
    plain = _toml(src, '[vary.centrifugal_force]\nvalues = [259.0]\n[sweep]\nomega = "1990:2060:3"\n', name="p.toml")
    assert Path(load_study(plain).table).resolve() == work / "p.csv"
    for example in Path(__file__).parents[1].joinpath("examples", "studies").glob("*.toml"):
        assert Path(load_study(example).table).resolve().parent == work, example


def test_toml_syntax_error_names_the_study_file(tmp_path, capsys):
    """A TOML syntax error is a ParameterError naming the study file and the line (one line on the
    command line)."""
    f = tmp_path / "broken.toml"
    f.write_text(f'model = "{BLADE}"\n[sweep\nomega = "1990:2060:3"\n')
    with pytest.raises(ParameterError, match=r"broken.toml: not valid TOML: .*line 2"):
        load_study(f)
    capsys.readouterr()
    with pytest.raises(SystemExit) as code:
        main(["study", str(f)])
    err = capsys.readouterr().err
    assert code.value.code == 2 and "broken.toml" in err.strip().splitlines()[-1] and "Traceback" not in err

"""Tests of the ``frictionjoint`` command (frictionjoint.cli, ``python -m frictionjoint``).

The real command runs in a subprocess with this interpreter; argument errors are also checked
in-process through ``main(argv)``.
"""
import subprocess
import sys
from pathlib import Path

import pytest

from frictionjoint.cli import main

PNG_MAGIC = b"\x89PNG\r\n\x1a\n"
TIMEOUT = 120  # seconds per subprocess


def run(*args, cwd=None):
    return subprocess.run([sys.executable, "-m", "frictionjoint", *args], capture_output=True,
                          text=True, timeout=TIMEOUT, cwd=cwd)


def test_demo_writes_table_png_and_csv(tmp_path):
    png, table = tmp_path / "fr.png", tmp_path / "fr.csv"
    proc = run("demo", "--points", "4", "--out", str(png), "--csv", str(table))
    assert proc.returncode == 0, proc.stderr
    out = proc.stdout
    assert "Den Hartog [m]" in out and "rel. error" in out and "stops/cycle" in out
    # r = 0.5 at F/P0 = 0.5 has stops: the regime word stands in the error column
    rows = [ln.split() for ln in out.splitlines() if ln.startswith(("up ", "down "))]
    assert len(rows) == 8
    assert rows[0][:3] == ["up", "0.5", "0.5000"] and rows[0][-2:] == ["stops", "2"]
    assert all(float(row[-2]) <= 1e-9 for row in rows if row[-2] != "stops")
    assert f"wrote {png}" in out
    assert png.read_bytes()[:8] == PNG_MAGIC
    assert table.read_text().count("\n") > 8
    assert "sweep" in proc.stderr  # the progress bar goes to stderr


def test_demo_default_output_name(tmp_path):
    proc = run("demo", "--points", "2", "--ratio", "1.5:2.0", "--slip-force", "0.3",
               "--direction", "up", "--no-progress", cwd=tmp_path)
    assert proc.returncode == 0, proc.stderr
    assert (tmp_path / "forced_response.png").read_bytes()[:8] == PNG_MAGIC
    assert proc.stderr == ""


def test_map_writes_png(tmp_path):
    png, table = tmp_path / "map.png", tmp_path / "map.csv"
    proc = run("map", "--out", str(png), "--friction", "0.3:1.2:2", "--ratio", "0.45:1.5:2",
               "--jobs", "1", "--table", "--csv", str(table), "--no-progress")
    assert proc.returncode == 0, proc.stderr
    assert png.read_bytes()[:8] == PNG_MAGIC
    assert "points per category" in proc.stdout
    assert "S permanent stick" in proc.stdout  # the text map
    assert len(table.read_text().splitlines()) == 1 + 4


def test_bad_arguments_exit_nonzero_in_a_subprocess(tmp_path):
    proc = run("demo", "--points", "zero", cwd=tmp_path)
    assert proc.returncode != 0
    assert "--points" in proc.stderr and "integer" in proc.stderr
    assert not (tmp_path / "forced_response.png").exists()


@pytest.mark.parametrize("argv, words", [
    ([], "required"),
    (["sweep"], "invalid choice"),
    (["demo", "--bogus"], "unrecognized arguments"),
    (["demo", "--poin", "5"], "unrecognized arguments"),  # no silent abbreviations
    (["demo", "--points", "0"], "--points"),
    (["demo", "--points", "2.5"], "--points"),
    (["demo", "--slip-force", "-1"], "--slip-force"),
    (["demo", "--mass", "nan"], "--mass"),
    (["demo", "--ratio", "2.5:0.5"], "--ratio"),
    (["demo", "--ratio", "0:2"], "--ratio"),
    (["demo", "--ratio", "0.5:2:10"], "--ratio"),
    (["demo", "--direction", "sideways"], "--direction"),
    (["demo", "--out", "/nonexistent-dir/x.png"], "does not exist"),
    (["map", "--friction", "0:1"], "--friction"),
    (["map", "--friction", "-0.1:1:3"], "--friction"),
    (["map", "--ratio", "0.5:1.5:0"], "--ratio"),
    (["map", "--ratio", "0.5:1.5:x"], "--ratio"),
    (["map", "--jobs", "0"], "--jobs"),
])
def test_bad_arguments_give_a_clear_error(argv, words, capsys):
    with pytest.raises(SystemExit) as exc:
        main(argv)
    assert exc.value.code == 2
    err = capsys.readouterr().err
    assert words in err
    assert "usage:" in err


def test_help_and_version(capsys):
    with pytest.raises(SystemExit) as exc:
        main(["--version"])
    assert exc.value.code == 0
    assert capsys.readouterr().out.startswith("frictionjoint ")
    for sub in ("demo", "map"):
        with pytest.raises(SystemExit) as exc:
            main([sub, "--help"])
        assert exc.value.code == 0
        assert "--out" in capsys.readouterr().out


def test_console_script_is_installed():
    script = Path(sys.executable).with_name("frictionjoint")
    if not script.exists():
        pytest.skip("console script not installed next to this interpreter")
    proc = subprocess.run([str(script), "--version"], capture_output=True, text=True, timeout=TIMEOUT)
    assert proc.returncode == 0 and proc.stdout.startswith("frictionjoint ")

"""Tests of frictionjoint.regime: Hong & Liu's map of stops per cycle over (F/P0, r).

Known facts (DESIGN.md section 3; Den Hartog 1931; Hong & Liu 2000), m = k = P0 = 1:
- r = 1.5, F/P0 = 0.3 and 0.5: stop-free (above r = 1/2, Den Hartog's boundary is exact and
  lies at F/P0 ~ 0.62 for r = 1.5);
- r = 0.45, F/P0 = 0.5: two stops per cycle;
- F/P0 >= 1: permanent stick (friction can hold the full force);
- r = 1, F/P0 < pi/4: unbounded growth; r = 1, F/P0 > pi/4: bounded motion with stops.
"""
from types import SimpleNamespace

import numpy as np
import pytest

from frictionjoint.errors import ParameterError
from frictionjoint.regime import REGIMES, RegimeMap, classify, regime_map

PNG_MAGIC = b"\x89PNG\r\n\x1a\n"


@pytest.fixture(scope="module")
def small_map():
    return regime_map([0.3, 0.5, 1.0, 1.2], [0.45, 1.5])


def test_known_points(small_map):
    rm = small_map
    assert rm.shape == (4, 2)
    assert rm.at(0.3, 1.5) == ("stop-free", 0)
    assert rm.at(0.5, 1.5) == ("stop-free", 0)
    assert rm.at(0.5, 0.45) == ("stops", 2)
    for f in (1.0, 1.2):
        for r in (0.45, 1.5):
            assert rm.at(f, r) == ("stuck", -1)
    assert rm.converged.all()


def test_resonance():
    rm = regime_map([0.3, 0.9], [1.0])
    assert rm.at(0.3, 1.0) == ("unbounded", -1)
    assert not rm.converged[0, 0]
    regime, stops = rm.at(0.9, 1.0)
    assert regime == "stops" and stops >= 2


def test_category_table_and_csv(small_map, tmp_path):
    cat = small_map.category()
    assert cat[0, 1] == "0 stops" and cat[1, 0] == "2 stops" and cat[3, 0] == "stuck"
    text = small_map.table()
    lines = text.splitlines()
    assert lines[1].split()[1:] == ["S", "S"]      # largest friction ratio first
    assert lines[-2].split()[1:] == ["2", "0"]     # F/P0 = 0.3
    path = tmp_path / "map.csv"
    small_map.to_csv(path)
    rows = path.read_text().splitlines()
    assert rows[0].startswith("friction_ratio,frequency_ratio,regime,stops_per_cycle")
    assert len(rows) == 1 + 8


def test_plot_writes_png(small_map, tmp_path):
    path = tmp_path / "map.png"
    fig = small_map.plot(path)
    assert path.read_bytes()[:8] == PNG_MAGIC
    labels = [t.get_text() for t in fig.axes[0].get_legend().get_texts()]
    assert "permanent stick" in labels and "2 stops" in labels


def test_plot_all_categories(tmp_path):
    # a synthetic map with every category, odd counts and a non-unique orbit
    regime = np.array([["stop-free", "stops", "stops", "stops"],
                       ["stops", "stuck", "unbounded", "not converged"]])
    stops = np.array([[0, 1, 3, 8], [2, -1, -1, -1]])
    unique = np.array([[False, True, True, True], [True, False, True, True]])
    rm = RegimeMap(np.array([0.1, 0.2]), np.array([0.5, 1.0, 1.5, 2.0]), regime, stops,
                   converged=regime != "not converged", unique=unique,
                   periods=np.ones((2, 4)), messages=np.full((2, 4), "m"))
    assert list(rm.category()[0]) == ["0 stops", "1 stop", "3 stops", "8 stops"]
    fig = rm.plot(tmp_path / "all.png")
    labels = [t.get_text() for t in fig.axes[0].get_legend().get_texts()]
    for word in ("1 stop", "3 stops", "8 stops", "permanent stick", "unbounded (resonance)",
                 "not converged", "not unique (family of orbits)"):
        assert word in labels
    text = rm.table()
    assert "0*" in text and "?" in text and "U" in text and "S*" not in text


def test_parallel_jobs_give_the_same_map(small_map):
    rm = regime_map([0.3, 0.5, 1.0, 1.2], [0.45, 1.5], jobs=2)
    np.testing.assert_array_equal(rm.regime, small_map.regime)
    np.testing.assert_array_equal(rm.stops_per_cycle, small_map.stops_per_cycle)


def test_classify():
    def resp(**kw):
        base = dict(converged=True, stuck=False, stops_per_cycle=0, message="ok", status="periodic")
        base.update(kw)
        return SimpleNamespace(**base)

    assert classify(resp()) == "stop-free"
    assert classify(resp(stops_per_cycle=3)) == "stops"
    assert classify(resp(stuck=True)) == "stuck"
    assert classify(resp(converged=False, status="unbounded")) == "unbounded"
    assert classify(resp(converged=False, status="not converged")) == "not converged"
    assert classify(resp(converged=False, status="failed")) == "not converged"  # a failed march
    assert set(REGIMES) == {"stop-free", "stops", "stuck", "unbounded", "not converged"}


@pytest.mark.parametrize("args, name", [
    (([-0.1], [1.0]), r"friction_ratios\[0\]"),
    (([0.3], [0.0]), r"frequency_ratios\[0\]"),
    (([0.3], [1.0, np.nan]), r"frequency_ratios\[1\]"),
    (([], [1.0]), "friction_ratios"),
    (([[0.3]], [1.0]), "friction_ratios"),
    (([0.3], "r"), "frequency_ratios"),
])
def test_invalid_grid_names_the_parameter(args, name):
    with pytest.raises(ParameterError, match=name):
        regime_map(*args)


def test_invalid_options():
    with pytest.raises(ParameterError, match="jobs"):
        regime_map([0.3], [1.5], jobs=0)
    with pytest.raises(ParameterError, match="progress"):
        regime_map([0.3], [1.5], progress=1)

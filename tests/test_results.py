"""The result contract (frictionjoint.results): every result type has success, status and
message; every plot takes (ax=None, path=None); results are data, so a CSV round trip keeps
what a plot needs (the analytic curve is recomputed from the stored parameters)."""
import dataclasses
import inspect

import numpy as np
import pytest

import frictionjoint.results as results
from frictionjoint import oscillator_sweep
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
    fr = oscillator_sweep(1.0, 1.0, 0.3, 1.0, [0.6, 1.5, 2.0])
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

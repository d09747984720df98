"""Structure definition files (TOML/JSON) and LinearStructure.fmu built from them."""
import json
from pathlib import Path

import numpy as np
import pytest

from frictionjoint.errors import ParameterError
from frictionjoint.structure_file import StructureDefinition, load_structure_definition

ROOT = Path(__file__).resolve().parents[1]


def test_toml_json_round_trip(tmp_path):
    d = load_structure_definition(ROOT / "models" / "two_dof_chain.toml")
    assert d.name == "TwoDofChain" and d.structure.dof_names == ("x1", "x2")
    assert np.array_equal(d.structure.damping, 0.02 * d.structure.stiffness)
    again = load_structure_definition(d.to_json(tmp_path / "chain.json"))
    assert again.to_dict() == d.to_dict()


@pytest.mark.parametrize("change,text", [
    ({"mass": [[1.0, 0.0], [0.0, -1.0]]}, "mass"),
    ({"ports": ["x3"]}, "dof must be one of"),
    ({"ports": ["x1", "x1"]}, "distinct"),
    ({"dofs": ["x 1", "x2"]}, "identifiers"),
    ({"excitation": {"omega": -1.0}}, "omega"),
    ({"excitation": {"phase": 1.0}}, "unknown keys"),
    ({"color": "red"}, "unknown keys"),
])
def test_bad_definitions_name_the_key(tmp_path, change, text):
    data = load_structure_definition(ROOT / "models" / "two_dof_chain.toml").to_dict()
    data.update(change)
    path = tmp_path / "bad.json"
    path.write_text(json.dumps(data))
    with pytest.raises(ParameterError, match=text):
        load_structure_definition(path)


def test_missing_or_wrong_file(tmp_path):
    with pytest.raises(ParameterError, match="not found"):
        load_structure_definition(tmp_path / "none.toml")
    (tmp_path / "a.txt").write_text("")
    with pytest.raises(ParameterError, match=".toml or .json"):
        load_structure_definition(tmp_path / "a.txt")
    with pytest.raises(ParameterError, match="needs 'stiffness'"):
        StructureDefinition.from_dict({"dofs": ["a"], "mass": [[1.0]]})


def test_structure_fmu_variables(tmp_path):
    from fmpy import read_model_description

    from frictionjoint.fmi.build import build_fmus, validate

    (path,) = build_fmus(tmp_path, structures=[ROOT / "models" / "two_dof_chain.toml"])
    assert path.name == "TwoDofChain.fmu" and validate(path) == []
    md = read_model_description(str(path))
    by = {v.name: v for v in md.modelVariables}
    assert float(by["omega"].start) == 1.2 and float(by["force_amplitude_x2"].start) == 1.0
    for dof in ("x1", "x2"):
        assert by[f"x_{dof}"].causality == "output"
        for kind in ("force", "stiffness", "displacement"):
            assert by[f"joint_{kind}_{dof}"].causality == "input"

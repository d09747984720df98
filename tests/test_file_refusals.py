"""Definition files that are not what they claim (issue 39 §4): one line naming the file and why.

Structure definitions (frictionjoint.structure_file), system definitions (frictionjoint.system_file)
and blade model definitions (frictionjoint.structures.models) are read by one function,
``read_definition_file``; before issue 39 binary garbage gave a UnicodeDecodeError (a full
traceback from ``build-fmus --system``), and a TOML syntax error in a structure definition a raw
TOMLDecodeError that named no file. The FE matrix files' refusals are in test_fe_import.py.
"""
import numpy as np
import pytest

from frictionjoint.errors import ParameterError
from frictionjoint.structure_file import load_structure_definition
from frictionjoint.structures.models import load_blade_model
from frictionjoint.system_file import load_system_definition

LOADERS = {"structure definition": load_structure_definition, "system definition": load_system_definition,
           "blade model": load_blade_model}
# (file name, content, words of the refusal)
BAD_FILES = {
    "binary garbage": ("g.toml", np.random.default_rng(39).integers(0, 256, 3000, dtype=np.uint8).tobytes(),
                       "file: byte 0x"),
    "a TOML syntax error": ("s.toml", b"name = \n", "file is not valid TOML: Invalid value (at line 1, column 8)"),
    "a JSON syntax error": ("s.json", b'{"name": }', "file is not valid JSON: Expecting value: line 1 column 10"),
    "a JSON array": ("a.json", b"[1, 2]", "file holds a table, got list"),
}


@pytest.mark.parametrize("what", list(LOADERS))
@pytest.mark.parametrize("case", list(BAD_FILES))
def test_a_bad_definition_file_gives_one_line_naming_it(case, what, tmp_path):
    name, content, words = BAD_FILES[case]
    path = tmp_path / name
    path.write_bytes(content)
    with pytest.raises(ParameterError) as info:
        LOADERS[what](path)
    message = str(info.value)
    assert "\n" not in message and message.startswith(f"{path}: ") and words in message, message


def test_build_fmus_with_a_garbage_system_file_prints_one_error_line(tmp_path, capsys):
    """``frictionjoint build-fmus --system FILE``: a usage error naming the file, no traceback,
    before anything is built."""
    from frictionjoint.cli import main

    path = tmp_path / "system.toml"
    path.write_bytes(BAD_FILES["binary garbage"][1])
    with pytest.raises(SystemExit) as info:
        main(["build-fmus", "--system", str(path), "--out", str(tmp_path / "out")])
    assert info.value.code == 2
    err = capsys.readouterr().err
    assert f"error: {path}: not a system definition file: byte 0x" in err and "Traceback" not in err, err
    assert not list(tmp_path.rglob("*.fmu"))

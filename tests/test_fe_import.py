"""Structures from FE-code exports (frictionjoint.structures.fe_import, issue 30 part 1).

The files of tests/data/fe_import are written by its make_files.py from known matrices (a lattice
of masses and bars, 16 nodes, 48 DOFs; README.md there): read back in each format, the model has
the same DOF table and the same natural frequencies as the matrices it was written from, to RTOL.
Every wrong file gives a one-line ParameterError that names the file and what is wrong.
"""
import sys
from pathlib import Path

import numpy as np
import pytest
import scipy.linalg
import scipy.sparse as sp

from frictionjoint import LinearStructure
from frictionjoint.errors import ParameterError
from frictionjoint.structure_file import StructureDefinition, load_structure_definition
from frictionjoint.structures.fe_import import FEModel, dof_name, read_dof_table, read_fe_model, read_node_sets

DATA = Path(__file__).resolve().parent / "data" / "fe_import"
sys.path.insert(0, str(DATA))
import make_files  # noqa: E402  (the script that wrote the files)

RTOL = 1e-10  # natural frequencies of the file against those of the matrices it was written from
SHAPE = (4, 2, 2)
DOFS = DATA / "lattice.dofs.csv"


def _frequencies(mass, stiffness):
    return np.sqrt(scipy.linalg.eigh(stiffness.toarray(), mass.toarray(), eigvals_only=True))


@pytest.fixture(scope="module")
def reference():
    """The known matrices: (mass, stiffness, dofs, frequencies) for exact=False and exact=True."""
    out = {}
    for exact in (False, True):
        m, k, dofs = make_files.lattice(*SHAPE, exact=exact)
        out[exact] = (m, k, dofs, _frequencies(m, k))
    return out


# (keyword arguments of read_fe_model, written from the exact-decimal matrices)
CASES = {
    "matrix_market": (dict(mass="lattice_M.mtx", stiffness="lattice_K.mtx", dofs=DOFS), False),
    "harwell_boeing": (dict(mass="lattice_M.rsa", stiffness="lattice_K.rua", dofs=DOFS), False),
    "dmig_small_field": (dict(mass=("lattice_small.pch", "MAAX"), stiffness=("lattice_small.pch", "KAAX")), True),
    "dmig_large_field": (dict(mass=("lattice_large.pch", "MAAX"), stiffness=("lattice_large.pch", "kaax")), True),
    "dmig_free_field": (dict(mass=("lattice_free.bdf", "MAAX"), stiffness=("lattice_free.bdf", "KAAX")), False),
    "abaqus_matrix_input": (dict(mass="lattice_MASS2.mtx", stiffness="lattice_STIF2.mtx"), False),
    "op4": (dict(mass=("lattice.op4", "MAA"), stiffness=("lattice.op4", "KAA"), dofs=DOFS), False),
}


def _in_data(kwargs):
    def place(v):
        if isinstance(v, tuple):
            return (DATA / v[0], v[1])
        return v if isinstance(v, Path) else DATA / v
    return {key: place(v) for key, v in kwargs.items()}


@pytest.mark.parametrize("case", list(CASES))
def test_each_format_gives_the_frequencies_of_its_matrices(case, reference):
    if case == "op4":
        pytest.importorskip("pyyeti.nastran.op4")
    kwargs, exact = CASES[case]
    m, k, dofs, w_ref = reference[exact]
    model = read_fe_model(**_in_data(kwargs), node_sets=DATA / "lattice.sets.csv")
    assert sp.issparse(model.mass) and sp.issparse(model.stiffness)
    np.testing.assert_array_equal(model.dofs, dofs)
    w = _frequencies(model.mass, model.stiffness)
    error = np.max(np.abs(w - w_ref) / w_ref)
    print(f"{case}: {model.n_dof} DOFs, largest relative frequency error {error:.1e}")
    assert error <= RTOL
    assert np.max(np.abs(model.to_structure().natural_frequencies() - w_ref) / w_ref) <= RTOL


def test_files_are_what_make_files_writes(tmp_path):
    """The test data are reproducible: make_files.py writes the same bytes again."""
    m, k, dofs = make_files.write_all(tmp_path, *SHAPE)
    make_files.write_bad(tmp_path, m, k, dofs)
    written = sorted(p.name for p in tmp_path.iterdir())
    assert written, "nothing written"
    for name in written:
        assert (tmp_path / name).read_bytes() == (DATA / name).read_bytes(), name


def test_dof_table_node_sets_and_names():
    model = read_fe_model(**_in_data(CASES["matrix_market"][0]), node_sets=DATA / "lattice.sets.csv")
    assert model.n_dof == 48 and model.dof_names[:4] == ("n101_u1", "n101_u2", "n101_u3", "n103_u1")
    assert model.dof_index(131, 3) == 47
    assert model.node_sets == {"root": (101, 103, 105, 107), "tip": (131,), "flank": (101, 103)}
    np.testing.assert_array_equal(model.dofs_of("flank"), [0, 1, 2, 3, 4, 5])
    np.testing.assert_array_equal(model.dofs_of("root", directions=[1]), [0, 3, 6, 9])
    assert dof_name(7, 6) == "n7_r3" and dof_name(12, 1) == "n12_u1"
    s = model.to_structure()
    assert isinstance(s, LinearStructure) and s.dof_names == model.dof_names
    with pytest.raises(ParameterError, match="no DOF"):
        model.dof_index(131, 4)
    with pytest.raises(ParameterError, match="set_name"):
        model.dofs_of("hub")
    with pytest.raises(ParameterError, match="max_dof=10"):
        model.to_structure(max_dof=10)


def test_fe_model_from_arrays_is_checked_the_same_way(reference):
    m, k, dofs, _ = reference[False]
    model = FEModel(m.toarray(), k, None, dofs, {"tip": [131]})
    assert sp.issparse(model.mass) and model.damping is None
    with pytest.raises(ParameterError, match="^mass is not positive definite"):
        FEModel(-m, k, None, dofs)


# (file or keyword arguments, words the one-line message must hold)
BAD = {
    "unsymmetric": (dict(mass="lattice_M.mtx", stiffness="bad_unsymmetric_K.mtx", dofs=DOFS),
                    ["bad_unsymmetric_K.mtx: stiffness is not symmetric", "(n101_u1, n101_u2)"]),
    "indefinite_mass": (dict(mass="bad_indefinite_M.mtx", stiffness="lattice_K.mtx", dofs=DOFS),
                        ["bad_indefinite_M.mtx: mass is not positive definite", "pivot"]),
    "sizes_differ": (dict(mass="lattice_M.mtx", stiffness="bad_size_K.mtx", dofs=DOFS),
                     ["bad_size_K.mtx: the header declares a 45 x 45 matrix, the DOF table (",
                      "lattice.dofs.csv) has 48 rows"]),
    "short_dof_table": (dict(mass="lattice_M.mtx", stiffness="lattice_K.mtx", dofs=DATA / "bad_short.dofs.csv"),
                        ["lattice_M.mtx: the header declares a 48 x 48 matrix, the DOF table (",
                         "bad_short.dofs.csv) has 47 rows"]),
    "unknown_node_in_set": (dict(mass="lattice_M.mtx", stiffness="lattice_K.mtx", dofs=DOFS,
                                 node_sets=DATA / "bad.sets.csv"),
                            ["bad.sets.csv: node_sets: set 'flank' names node 99999, which is not in the DOF table"]),
    "no_dof_table": (dict(mass="lattice_M.mtx", stiffness="lattice_K.mtx"),
                     ["lattice_M.mtx: a matrix_market file has no DOF table"]),
    "which_matrix": (dict(mass="lattice_small.pch", stiffness=("lattice_small.pch", "KAAX")),
                     ["lattice_small.pch holds the matrices ['KAAX', 'MAAX']: name the one"]),
    "no_such_matrix": (dict(mass=("lattice_small.pch", "MGG"), stiffness=("lattice_small.pch", "KAAX")),
                       ["lattice_small.pch has no matrix 'MGG'"]),
}


@pytest.mark.parametrize("case", list(BAD))
def test_bad_files_give_one_line_naming_the_file(case):
    kwargs, words = BAD[case]
    with pytest.raises(ParameterError) as info:
        read_fe_model(**_in_data(kwargs))
    message = str(info.value)
    print(f"{case}: {message}")
    assert "\n" not in message
    for w in words:
        assert w in message


def _dmig(tmp_path, text, name="m.pch"):
    path = tmp_path / name
    path.write_text(text)
    return path


def _small(*fields):
    """A small-field line: each field in 8 columns."""
    return "".join(f.ljust(8) for f in fields).rstrip() + "\n"


HEADER6 = _small("DMIG", "M", "0", "6", "2", "2")
DMIG_BAD = {
    "both triangles in form 6": (HEADER6 + _small("DMIG", "M", "1", "1", "", "1", "1", "1.")
                                 + _small("+", "1", "2", ".5")
                                 + _small("DMIG", "M", "1", "2", "", "1", "1", ".5"), "and its mirror"),
    "an entry twice": (HEADER6 + _small("DMIG", "M", "1", "1", "", "1", "1", "1.") + _small("+", "1", "1", "1."),
                       "is given twice"),
    "a complex matrix": (_small("DMIG", "M", "0", "6", "3", "3"), "complex"),
    "a rectangular form": (_small("DMIG", "M", "0", "2", "2", "2"), "form IFO=2"),
    "a scalar point": (HEADER6 + _small("DMIG", "M", "1", "0", "", "1", "0", "1."), "scalar points"),
    "a point id below 1": (HEADER6 + _small("DMIG", "M", "1", "1", "", "-1", "1", "1."), "point id -1 is not"),
    "an integer for a real": (HEADER6 + _small("DMIG", "M", "1", "1", "", "1", "1", "1"), "not a real number"),
    "a column before its header": (_small("DMIG", "M", "1", "1", "", "1", "1", "1."), "before its header"),
    "a stray continuation": (_small("+", "1", "1", "1."), "no entry before it"),
    "an INCLUDE": ("INCLUDE 'other.pch'\n", "INCLUDE is not followed"),
}


@pytest.mark.parametrize("case", list(DMIG_BAD))
def test_dmig_reader_is_strict(case, tmp_path):
    text, words = DMIG_BAD[case]
    path = _dmig(tmp_path, text)
    with pytest.raises(ParameterError) as info:
        read_fe_model(path, path)
    message = str(info.value)
    assert "\n" not in message and str(path) in message and words in message, message


def test_dmig_fields_and_number_forms(tmp_path):
    """Small, large and free field in one file, exponents as E, D and a bare sign, comments,
    other entries skipped: a 2-DOF symmetric mass and stiffness."""
    text = ("$ a comment\nBEGIN BULK\n" + _small("GRID", "1", "", "0.", "0.", "0.")
            + _small("DMIG", "MAA", "0", "6", "2", "2") + "$ a comment line between\n"
            + _small("DMIG", "MAA", "5", "1", "", "5", "1", "2.+0", "") + _small("+", "5", "2", "1.-1")
            + "DMIG*   MAA                           5               2\n"
            "*                      5               2 3.000000000D+00\n"
            "DMIG,KAA,0,6,2,2\nDMIG,KAA,5,1,,5,1,4.0E+02,\n,5,2,-1.E2\nDMIG,KAA,5,2,,5,2,.3e3\nENDDATA\n")
    path = _dmig(tmp_path, text)
    model = read_fe_model((path, "MAA"), (path, "KAA"))
    np.testing.assert_array_equal(model.dofs, [[5, 1], [5, 2]])
    np.testing.assert_array_equal(model.mass.toarray(), [[2.0, 0.1], [0.1, 3.0]])
    np.testing.assert_array_equal(model.stiffness.toarray(), [[400.0, -100.0], [-100.0, 300.0]])


def test_abaqus_both_triangles_and_dof_limits(tmp_path, reference):
    m, k, dofs, _ = reference[False]
    full = tmp_path / "m.mtx"
    coo = sp.coo_matrix(m)
    full.write_text("** whole matrix\n" + "".join(f"{dofs[r, 0]},{dofs[r, 1]},{dofs[c, 0]},{dofs[c, 1]},{float(v)!r}\n"
                                                  for r, c, v in zip(coo.row, coo.col, coo.data)))
    model = read_fe_model(full, DATA / "lattice_STIF2.mtx", format="abaqus_matrix_input")
    assert (model.mass != m).nnz == 0
    bad = tmp_path / "t.mtx"
    bad.write_text("1,1,1,1,1.0\n1,11,1,11,1.0\n")
    with pytest.raises(ParameterError, match="t.mtx: data line 2 has a DOF outside 1..6"):
        read_fe_model(bad, bad)


def test_symmetry_tolerance_is_relative_to_the_rows_scale(reference):
    """Rounding-size asymmetry passes; 1e-6 of sqrt(k_ii k_jj) does not, even in a row whose scale
    is 1e-6 of the largest entry (a rotation's, say)."""
    m, k, dofs, _ = reference[False]
    k = k.tolil()
    scale = np.full(48, 1.0)
    scale[-3:] = 1e-3  # the last node's DOFs in other units: its rows and columns scaled
    s = sp.diags_array(scale)
    k, m = (s @ k.tocsr() @ s).tolil(), (s @ m @ s).tocsr()
    i, j = 46, 47
    ok = k.copy()
    ok[i, j] = k[i, j] * (1 + 1e-12)
    FEModel(m, ok.tocsr(), None, dofs)
    bad = k.copy()
    bad[i, j] = k[i, j] + 1e-6 * np.sqrt(k[i, i] * k[j, j])
    with pytest.raises(ParameterError, match=r"stiffness is not symmetric: entry \(n131_u2, n131_u3\)"):
        FEModel(m, bad.tocsr(), None, dofs)


def test_sidecar_files_are_checked(tmp_path):
    path = tmp_path / "d.csv"
    path.write_text("node,dir\n1,1\n")
    with pytest.raises(ParameterError, match="the first line must be the header node,direction"):
        read_dof_table(path)
    path.write_text("node,direction\n1,1\n1,7\n")
    with pytest.raises(ParameterError, match=r"direction 7 of node 1 \(row 2\) is not in 1..6"):
        FEModel(np.eye(2), np.eye(2), None, read_dof_table(path), files={"dofs": path})
    path.write_text("node,direction\n1,1\n-2,1\n")
    with pytest.raises(ParameterError, match=r"node id -2 \(row 2\) is not in 1..2147483647"):
        FEModel(np.eye(2), np.eye(2), None, read_dof_table(path))
    path.write_text("node,direction\n1,1\n1,1\n")
    with pytest.raises(ParameterError, match=r"\(node 1, direction 1\) appears more than once"):
        FEModel(np.eye(2), np.eye(2), None, read_dof_table(path))
    sets = tmp_path / "s.csv"
    sets.write_text("set,node\ntip,3,4\n")
    with pytest.raises(ParameterError, match="data row 1 has 3 fields"):
        read_node_sets(sets)


def test_structure_definition_names_the_files():
    """tests/data/fe_import/lattice.toml: an [fe] definition loads the structure of the files, with
    its Rayleigh damping, ports and excitation on the DOF names."""
    d = load_structure_definition(DATA / "lattice.toml")
    model = read_fe_model(DATA / "lattice_M.mtx", DATA / "lattice_K.mtx", dofs=DOFS)
    s = model.to_structure()
    assert d.structure.dof_names == s.dof_names
    np.testing.assert_array_equal(d.structure.mass, s.mass)
    np.testing.assert_array_equal(d.structure.stiffness, s.stiffness)
    np.testing.assert_array_equal(d.structure.damping, 1e-5 * s.stiffness)
    assert d.ports == ("n101_u1", "n101_u2") and d.force_amplitude == {"n131_u3": 1.0}
    again = StructureDefinition.from_dict(d.to_dict())  # the normalised form an FMU carries
    np.testing.assert_array_equal(again.structure.stiffness, s.stiffness)


def test_structure_definition_fe_errors(tmp_path):
    base = {"fe": {"mass": "lattice_M.mtx", "stiffness": "lattice_K.mtx", "dofs": "lattice.dofs.csv"}}
    with pytest.raises(ParameterError, match=r"remove \['mass'\]"):
        StructureDefinition.from_dict({**base, "mass": [[1.0]]}, folder=DATA)
    with pytest.raises(ParameterError, match=r"unknown keys \['mas'\] in \[fe\]"):
        StructureDefinition.from_dict({"fe": {"mas": "x", **base["fe"]}}, folder=DATA)
    with pytest.raises(ParameterError, match="damping or rayleigh"):
        StructureDefinition.from_dict({"fe": {**base["fe"], "damping": "a.mtx", "rayleigh": [0.0, 1.0]}}, folder=DATA)
    with pytest.raises(ParameterError, match="mass file .*not found"):
        StructureDefinition.from_dict(base, folder=tmp_path)
    dmig = {"fe": {"mass": ["lattice_small.pch", "MAAX"], "stiffness": ["lattice_small.pch", "KAAX"]}}
    assert StructureDefinition.from_dict(dmig, folder=DATA).structure.n_dof == 48


def test_unreadable_and_complex_files_give_one_line(tmp_path):
    import scipy.io

    scipy.io.mmwrite(str(tmp_path / "c.mtx"), sp.coo_matrix(np.array([[1 + 1j, 0], [0, 1]])))
    (tmp_path / "p.mtx").write_text("%%MatrixMarket matrix coordinate pattern general\n2 2 2\n1 1\n2 2\n")
    (tmp_path / "short.mtx").write_text("%%MatrixMarket matrix coordinate real general\n2 2 3\n1 1 1.0\n")
    (tmp_path / "k.matrix").write_text("not\na Harwell-Boeing file\n")
    (tmp_path / "d.csv").write_text("node,direction\n1,1\n1,2\n")
    cases = {"c.mtx": "a Matrix Market file of complex entries", "p.mtx": "of pattern entries",
             "short.mtx": "not a readable matrix_market file", "k.matrix": "not a readable harwell_boeing file"}
    for name, words in cases.items():
        with pytest.raises(ParameterError) as info:
            read_fe_model(tmp_path / name, tmp_path / name, dofs=tmp_path / "d.csv")
        message = str(info.value)
        assert "\n" not in message and message.startswith(str(tmp_path / name)) and words in message, message
    with pytest.raises(ParameterError, match="mass must be a matrix of real numbers"):
        FEModel(np.eye(2) * (1 + 1j), np.eye(2), None, [[1, 1], [1, 2]])


def test_symmetric_harwell_boeing_with_both_triangles_is_refused(tmp_path, reference):
    """A symmetric (RSA) file stores one triangle; both (as an old ANSYS defect wrote) would double."""
    m, k, dofs, _ = reference[False]
    make_files.write_harwell_boeing(tmp_path / "k.rua", k, symmetric=False)
    text = (tmp_path / "k.rua").read_text().splitlines(keepends=True)
    text[2] = "RSA" + text[2][3:]
    (tmp_path / "k.rsa").write_text("".join(text))
    with pytest.raises(ParameterError, match=r"k.rsa: a symmetric \(RSA\) file stores one triangle"):
        read_fe_model(DATA / "lattice_M.rsa", tmp_path / "k.rsa", dofs=DOFS)


def test_system_definition_with_an_inline_fe_structure():
    """A system definition whose inline [structure] names FE files: the paths are the system
    definition's folder's, and the structure is the files'."""
    from frictionjoint.system_file import SystemDefinition

    data = {"structure": {"fe": {"format": "matrix_market", "mass": "lattice_M.mtx", "stiffness": "lattice_K.mtx",
                                 "dofs": "lattice.dofs.csv"}},
            "joints": [{"name": "j", "type": "jenkins", "dof": "n101_u1", "tangential_stiffness": 1e3,
                        "slip_force": 1.0}],
            "excitation": {"omega": 50.0, "force_amplitude": {"n131_u3": 1.0}}}
    d = SystemDefinition.from_dict(data, folder=DATA)
    s = read_fe_model(DATA / "lattice_M.mtx", DATA / "lattice_K.mtx", dofs=DOFS).to_structure()
    np.testing.assert_array_equal(d.structure.stiffness, s.stiffness)
    assert d.structure.dof_names == s.dof_names


# Files that end early (issue 39 §2): each format's files cut at lines and inside lines, read
# with the other matrix whole. (keyword arguments, the file to cut)
WHOLE_AND_CUT = {
    "matrix_market": (dict(mass="lattice_M.mtx", dofs=DOFS), "stiffness", "lattice_K.mtx"),
    "harwell_boeing": (dict(mass="lattice_M.rsa", dofs=DOFS), "stiffness", "lattice_K.rua"),
    "dmig_small_field": (dict(), "both", "lattice_small.pch"),
    "dmig_large_field": (dict(), "both", "lattice_large.pch"),
    "dmig_free_field": (dict(), "both", "lattice_free.bdf"),
    "abaqus_stiffness": (dict(mass="lattice_MASS2.mtx"), "stiffness", "lattice_STIF2.mtx"),
    "abaqus_mass": (dict(stiffness="lattice_STIF2.mtx"), "mass", "lattice_MASS2.mtx"),
    "op4": (dict(dofs=DOFS), "op4", "lattice.op4"),
}


def _read_cut(case, path):
    kwargs, role, _ = WHOLE_AND_CUT[case]
    kwargs = _in_data(kwargs)
    if role == "both":
        return read_fe_model((path, "MAAX"), (path, "KAAX"))
    if role == "op4":
        return read_fe_model((path, "MAA"), (path, "KAA"), **kwargs)
    return read_fe_model(**{**kwargs, role: path})


@pytest.mark.parametrize("case", list(WHOLE_AND_CUT))
def test_a_file_cut_short_is_refused(case, tmp_path):
    """Cut after 12 line ends and at 12 places inside lines spread over the file (the last just
    before its final newline), every cut file is refused by name. Before issue 39 a DMIG or Abaqus
    file cut between columns read with the entries it had (the DMIG file cut before its last KAAX
    column gave a first frequency 0), and a cut inside a number read the number's first digits."""
    if case == "op4":
        pytest.importorskip("pyyeti.nastran.op4")
    name = WHOLE_AND_CUT[case][2]
    data = (DATA / name).read_bytes()
    ends = [k + 1 for k in range(len(data)) if data[k:k + 1] == b"\n"]
    cuts = ends[:-1][::max(1, len(ends) // 12)][1:] + [int(f * len(data)) for f in np.linspace(0.05, 0.95, 11)]
    cuts.append(len(data) - 1)
    path = tmp_path / name
    for cut in cuts:
        path.write_bytes(data[:cut])
        with pytest.raises(ParameterError) as info:
            _read_cut(case, path)
        message = str(info.value)
        assert "\n" not in message and str(path) in message, (cut, message)
    path.write_bytes(data)
    _read_cut(case, path)  # the whole file reads


def test_dmig_cut_before_its_last_column_names_the_missing_diagonal(tmp_path):
    """The issue's file: lattice_small.pch cut before the last DMIG KAAX column (n131_u3)."""
    lines = (DATA / "lattice_small.pch").read_text().splitlines(keepends=True)
    last = max(k for k, line in enumerate(lines) if line.startswith("DMIG") and "KAAX" in line)
    path = _dmig(tmp_path, "".join(lines[:last]))
    with pytest.raises(ParameterError, match=r"m.pch: stiffness has no diagonal entry at n131_u3 \(1 of the 48 "
                                             r"DOFs the files name have none\): the file seems cut short"):
        read_fe_model((path, "MAAX"), (path, "KAAX"))


def test_a_dof_without_stiffness_written_as_zero_reads(tmp_path):
    """An explicit 0.0 diagonal is a DOF without stiffness (a mass that only the joints hold)."""
    path = _dmig(tmp_path, HEADER6 + _small("DMIG", "M", "1", "1", "", "1", "1", "1.") + _small("+", "1", "2", "0.")
                 + _small("DMIG", "M", "1", "2", "", "1", "2", "2.") + _small("DMIG", "K", "0", "6", "2", "2")
                 + _small("DMIG", "K", "1", "1", "", "1", "1", "5.") + _small("DMIG", "K", "1", "2", "", "1", "2", "0."))
    model = read_fe_model((path, "M"), (path, "K"))
    np.testing.assert_array_equal(model.stiffness.toarray(), [[5.0, 0.0], [0.0, 0.0]])


SIX_DOFS = "node,direction\n1,1\n1,2\n1,3\n2,1\n2,2\n2,3\n"
# (a Matrix Market header and its one entry, words of the refusal): the sizes of issue 39 §3
HUGE_HEADERS = {
    "1e8 rows": ("coordinate real general\n100000000 100000000 1\n1 1 1.0\n",
                 "declares a 100000000 x 100000000 matrix, the DOF table ("),
    "3e9 rows": ("coordinate real general\n3000000000 3000000000 1\n1 1 1.0\n",
                 "declares a 3000000000 x 3000000000 matrix"),
    "dense 1e5 x 1e5": ("array real general\n100000 100000\n1.0\n", "declares a 100000 x 100000 matrix"),
    "1e8 entries": ("coordinate real general\n6 6 100000000\n1 1 1.0\n",
                    "declares 100000000 entries, more than a file of 68 bytes holds"),
    "a short dense file": ("array real symmetric\n6 6\n1.0\n", "declares 21 values, the file has 1: it ends early"),
}


@pytest.mark.parametrize("case", list(HUGE_HEADERS))
def test_declared_sizes_are_refused_before_anything_is_allocated(case, tmp_path):
    """Before issue 39 the 1e8-row header allocated 0.9 GB before the DOF table's 6 rows refused
    it, and 3e9 rows or a dense 1e5 x 1e5 header failed with a MemoryError (or the process was
    killed). Python-side allocations during the refusal stay below 20 MB (tracemalloc sees numpy's
    and scipy's arrays; the file's text is 100 bytes)."""
    import tracemalloc

    text, words = HUGE_HEADERS[case]
    path = tmp_path / "k.mtx"
    path.write_text("%%MatrixMarket matrix " + text)
    (tmp_path / "d.csv").write_text(SIX_DOFS)
    tracemalloc.start()
    try:
        with pytest.raises(ParameterError) as info:
            read_fe_model(path, path, dofs=tmp_path / "d.csv")
        peak = tracemalloc.get_traced_memory()[1]
    finally:
        tracemalloc.stop()
    message = str(info.value)
    assert "\n" not in message and message.startswith(str(path)) and words in message, message
    assert peak < 20e6, peak


def test_harwell_boeing_header_is_checked_against_the_dof_table_and_the_file(tmp_path):
    lines = (DATA / "lattice_K.rua").read_text().splitlines(keepends=True)
    (tmp_path / "d.csv").write_text(SIX_DOFS)
    with pytest.raises(ParameterError, match=r"k.rua: the header declares a 48 x 48 matrix, the DOF table \(.*d.csv\) "
                                             r"has 6 rows"):
        read_fe_model(_dmig(tmp_path, "".join(lines), "k.rua"), DATA / "lattice_K.rua", dofs=tmp_path / "d.csv")
    with pytest.raises(ParameterError, match=r"k.rua: the header declares 173 lines of data, the file has 100: "
                                             r"it ends early"):
        read_fe_model(DATA / "lattice_M.rsa", _dmig(tmp_path, "".join(lines[:104]), "k.rua"), dofs=DOFS)


def test_files_that_are_no_text_empty_or_out_of_range_give_one_line(tmp_path):
    """Issue 39 §4: random bytes as a DMIG file (was a UnicodeDecodeError), an empty .mtx (was 'the
    matrices' files must have one format'), a node id of 1e20 in a DOF table, a DMIG file and an
    Abaqus file (was an OverflowError, or a wrapped id)."""
    rng = np.random.default_rng(39)
    garbage = _dmig(tmp_path, "", "g.pch")
    garbage.write_bytes(rng.integers(0, 256, 4000, dtype=np.uint8).tobytes())
    (tmp_path / "empty.mtx").write_text("")
    (tmp_path / "big.dofs.csv").write_text("node,direction\n100000000000000000000,1\n")
    (tmp_path / "d.csv").write_text("node,direction\n1,1\n")
    big_dmig = _dmig(tmp_path, "DMIG,M,0,6,2,2\nDMIG,M,100000000000000000000,1,,100000000000000000000,1,1.\n",
                     "big.bdf")
    (tmp_path / "big_abaqus.mtx").write_text("100000000000000000000,1,100000000000000000000,1,1.0\n")
    (tmp_path / "comments.pch").write_text("$ nothing but a comment\n")
    cases = {  # (read_fe_model arguments, the file named, words)
        "random bytes": ((garbage, garbage), {}, garbage, "is not text: not a file of the nastran_dmig format"),
        "empty": ((tmp_path / "empty.mtx", DATA / "lattice_K.mtx"), dict(dofs=DOFS), tmp_path / "empty.mtx",
                  "is empty"),
        "node id in a DOF table": ((DATA / "lattice_M.mtx", DATA / "lattice_K.mtx"),
                                   dict(dofs=tmp_path / "big.dofs.csv"), tmp_path / "big.dofs.csv",
                                   "data row 1 (100000000000000000000, 1): node ids are 1..2147483647"),
        "node id in a DMIG file": (((big_dmig, "M"), (big_dmig, "M")), {}, big_dmig,
                                   "point id 100000000000000000000 is larger than 2147483647"),
        "node id in an Abaqus file": ((tmp_path / "big_abaqus.mtx",) * 2, {}, tmp_path / "big_abaqus.mtx",
                                      "data line 1 has a node id outside 1..2147483647"),
        "no DMIG entries": ((tmp_path / "comments.pch",) * 2, {}, tmp_path / "comments.pch", "no DMIG entries"),
    }
    for case, (args, kwargs, named, words) in cases.items():
        with pytest.raises(ParameterError) as info:
            read_fe_model(*args, **kwargs)
        message = str(info.value)
        assert "\n" not in message and str(named) in message and words in message, (case, message)
    with pytest.raises(ParameterError, match=r"node id 100000000000000000000 \(row 1\) is not in 1..2147483647"):
        FEModel(np.eye(1), np.eye(1), None, [[10**20, 1]])


def test_a_symmetric_dense_matrix_market_file_that_ends_early_is_refused(tmp_path):
    """scipy 1.17 reads a symmetric "array" file with values missing as zeros: the values are
    counted here (6 of a 3 x 3 symmetric matrix's lower triangle; 5 given)."""
    (tmp_path / "d.csv").write_text("node,direction\n1,1\n1,2\n1,3\n")
    path = tmp_path / "m.mtx"
    path.write_text("%%MatrixMarket matrix array real symmetric\n%\n3 3\n2.0\n0.5\n0.0\n2.0\n0.5\n")
    with pytest.raises(ParameterError, match="m.mtx: the header declares 6 values, the file has 5: it ends early"):
        read_fe_model(path, path, dofs=tmp_path / "d.csv")
    path.write_text(path.read_text() + "2.0\n")
    model = read_fe_model(path, path, dofs=tmp_path / "d.csv")
    np.testing.assert_array_equal(model.mass.toarray(), [[2.0, 0.5, 0.0], [0.5, 2.0, 0.5], [0.0, 0.5, 2.0]])

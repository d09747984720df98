"""Write the FE-import test files of this folder from known matrices (see README.md here).

The model is a lattice of point masses and bars: nodes on an ``nx x ny x nz`` grid of unit
spacing, three translations per node, the layer ``x = 0`` clamped (it is the ground and has no
DOFs). Bars join each node to its neighbours along the axes and along both diagonals of each face
(a rigid truss); a bar along the unit vector ``e`` has stiffness ``k e e^T`` and, along the axes,
the consistent mass ``(m/6) [[2, 1], [1, 2]]`` per direction; each node also carries a point
mass. With ``exact=True`` every entry is a multiple of 1/2 below 1e5 (written exactly in eight
characters, so the small- and large-field DMIG files are exact); otherwise the matrices are
scaled by 1.2345678901234567e6 (stiffness) and 0.7310585786300049 (mass), numbers no short
decimal writes exactly, for the formats that carry 17 digits.

    python tests/data/fe_import/make_files.py            # the test files, into this folder
    python tests/data/fe_import/make_files.py /tmp/big 167 10 10   # 50,100 DOFs, for timing
    python tests/data/fe_import/make_files.py --time /tmp/big     # read them: seconds per step
"""
from __future__ import annotations

import sys
from pathlib import Path

import numpy as np
import scipy.io
import scipy.sparse as sp

HERE = Path(__file__).resolve().parent
AXES = [(1, 0, 0), (0, 1, 0), (0, 0, 1)]
DIAGONALS = [(1, 1, 0), (1, -1, 0), (1, 0, 1), (1, 0, -1), (0, 1, 1), (0, 1, -1)]
STIFFNESS_SCALE, MASS_SCALE = 1.2345678901234567e6, 0.7310585786300049


def node_id(index):
    """Node ids are not the matrix rows: 101, 103, 105, ..."""
    return 101 + 2 * np.asarray(index)


def lattice(nx: int, ny: int, nz: int, exact: bool = True):
    """``(mass, stiffness, dofs)`` of the lattice: sparse CSR matrices and the (n, 2) DOF table."""
    i, j, k = np.meshgrid(np.arange(nx + 1), np.arange(ny), np.arange(nz), indexing="ij")
    i, j, k = i.ravel(), j.ravel(), k.ravel()
    free = i >= 1
    index = np.where(free, ((i - 1) * ny + j) * nz + k, -1)  # -1: the clamped layer
    n_nodes = nx * ny * nz
    lookup = {(a, b, c): idx for a, b, c, idx in zip(i, j, k, index)}
    rows, cols, kval, mval = [], [], [], []
    for bond, offset in enumerate(AXES + DIAGONALS):
        o = np.array(offset, dtype=float)
        stiff = (1000.0 + 500.0 * bond) * np.outer(o, o) / (o @ o)  # e e^T exactly: entries 1, 1/2
        for a, b, c, p in zip(i, j, k, index):
            q = lookup.get((a + offset[0], b + offset[1], c + offset[2]))
            if q is None or (p < 0 and q < 0):
                continue
            consistent = bond < 3
            for (r, s, sign) in ((p, p, 1.0), (q, q, 1.0), (p, q, -1.0), (q, p, -1.0)):
                if r < 0 or s < 0:
                    continue
                for d1 in range(3):
                    for d2 in range(3):
                        if stiff[d1, d2]:
                            rows.append(3 * r + d1), cols.append(3 * s + d2)
                            kval.append(sign * stiff[d1, d2]), mval.append(0.0)
                    if consistent:  # (m/6) [[2, 1], [1, 2]] with m = 3
                        rows.append(3 * r + d1), cols.append(3 * s + d1)
                        kval.append(0.0), mval.append(1.0 if r == s else 0.5)
    n = 3 * n_nodes
    rows.extend(range(n)), cols.extend(range(n)), kval.extend([0.0] * n), mval.extend([2.0] * n)
    stiffness = sp.csr_array((kval, (rows, cols)), shape=(n, n))
    mass = sp.csr_array((mval, (rows, cols)), shape=(n, n))
    stiffness.eliminate_zeros(), mass.eliminate_zeros()
    if not exact:
        stiffness, mass = stiffness * STIFFNESS_SCALE, mass * MASS_SCALE
    dofs = np.stack([np.repeat(node_id(np.arange(n_nodes)), 3), np.tile([1, 2, 3], n_nodes)], axis=1)
    return mass, stiffness, dofs


def node_sets(nx: int, ny: int, nz: int) -> dict:
    """The root layer (x = 1), the tip node (far corner) and a 'flank' (the root layer's y = 0 row)."""
    idx = np.arange(nx * ny * nz).reshape(nx, ny, nz)
    return {"root": node_id(idx[0].ravel()).tolist(), "tip": [int(node_id(idx[-1, -1, -1]))],
            "flank": node_id(idx[0, 0, :]).tolist()}


def write_dofs(path, dofs):
    with open(path, "w") as fh:
        fh.write("node,direction\n")
        fh.writelines(f"{a},{b}\n" for a, b in dofs)


def write_sets(path, sets):
    with open(path, "w") as fh:
        fh.write("# node sets of the lattice model (make_files.py)\nset,node\n")
        fh.writelines(f"{name},{node}\n" for name, nodes in sets.items() for node in nodes)


def write_harwell_boeing(path, a, symmetric: bool):
    """scipy writes unsymmetric (RUA) files; a symmetric one (RSA, as ANSYS writes) is the lower
    triangle in the same layout with the type changed."""
    a = sp.csc_matrix(sp.tril(a) if symmetric else a)
    scipy.io.hb_write(str(path), a, hb_info=None)
    if symmetric:
        lines = Path(path).read_text().splitlines(keepends=True)
        lines[2] = "RSA" + lines[2][3:]
        Path(path).write_text("".join(lines))


def _small(v: float) -> str:
    """Eight characters at most and a decimal point: positional (2000.5) or with a bare-sign
    exponent (2.+3) where that is shorter; both are the shortest digits that give ``v`` back."""
    text = np.format_float_positional(v, trim=".")
    mantissa, exponent = np.format_float_scientific(v, trim=".", exp_digits=1).split("e")
    alt = mantissa + exponent
    best = alt if len(alt) < len(text) else text
    if len(best) > 8:
        raise ValueError(f"{v} does not fit a small field exactly")
    return best


def _cards(fields, field: str):
    """Lines of one entry: fields[0] is the name (DMIG), then its data fields."""
    name, data = fields[0], fields[1:]
    if field == "free":
        per, lines = 8, []
        for start in range(0, len(data), per):
            lines.append((name if start == 0 else "") + "," + ",".join(data[start:start + per]))
        return lines
    width, per = (16, 4) if field == "large" else (8, 8)
    lines = []
    for start in range(0, len(data), per):
        head = (name + ("*" if field == "large" else "")) if start == 0 else ("*" if field == "large" else "+")
        lines.append(head.ljust(8) + "".join(f.rjust(width) for f in data[start:start + per]).rstrip())
    return lines


def write_dmig(path, matrices: dict, dofs, field: str):
    """DMIG entries (symmetric form 6, upper triangle: column j, rows i <= j) in small, large or
    free field; values: exact short decimals (small), 10-digit D exponents (large), 17 digits (free)."""
    fmt = {"small": _small, "large": lambda v: f"{v:.9E}".replace("E", "D"), "free": lambda v: f"{v:.17E}"}[field]
    out = [f"$ DMIG matrices of the lattice model, {field} field (tests/data/fe_import/make_files.py)"]
    for name, a in matrices.items():
        upper = sp.csc_matrix(sp.triu(a))
        out += _cards(["DMIG", name, "0", "6", "2", "2", "", "", ""], field)
        for jcol in range(a.shape[0]):
            lo, hi = upper.indptr[jcol], upper.indptr[jcol + 1]
            data = [name, str(dofs[jcol, 0]), str(dofs[jcol, 1]), ""]
            for r, v in zip(upper.indices[lo:hi], upper.data[lo:hi]):
                data += [str(dofs[r, 0]), str(dofs[r, 1]), fmt(v), ""]
            out += _cards(["DMIG"] + data, field)
    Path(path).write_text("\n".join(out) + "\n")


def write_abaqus(path, a, dofs):
    """Abaqus matrix-input lines, lower triangle: row node, row DOF, column node, column DOF, value."""
    low = sp.coo_matrix(sp.tril(a))
    with open(path, "w") as fh:
        fh.writelines(f"{dofs[r, 0]},{dofs[r, 1]}, {dofs[c, 0]},{dofs[c, 1]}, {v:.16e}\n"
                      for r, c, v in sorted(zip(low.row, low.col, low.data)))


def write_all(folder: Path, nx: int, ny: int, nz: int):
    folder.mkdir(parents=True, exist_ok=True)
    m_exact, k_exact, dofs = lattice(nx, ny, nz, exact=True)
    m, k, _ = lattice(nx, ny, nz, exact=False)
    write_dofs(folder / "lattice.dofs.csv", dofs)
    write_sets(folder / "lattice.sets.csv", node_sets(nx, ny, nz))
    scipy.io.mmwrite(str(folder / "lattice_M.mtx"), sp.coo_matrix(m), symmetry="symmetric", precision=17)
    scipy.io.mmwrite(str(folder / "lattice_K.mtx"), sp.coo_matrix(k), symmetry="general", precision=17)
    write_harwell_boeing(folder / "lattice_M.rsa", m, symmetric=True)
    write_harwell_boeing(folder / "lattice_K.rua", k, symmetric=False)
    write_dmig(folder / "lattice_small.pch", {"MAAX": m_exact, "KAAX": k_exact}, dofs, "small")
    write_dmig(folder / "lattice_large.pch", {"MAAX": m_exact, "KAAX": k_exact}, dofs, "large")
    write_dmig(folder / "lattice_free.bdf", {"MAAX": m, "KAAX": k}, dofs, "free")
    write_abaqus(folder / "lattice_MASS2.mtx", m, dofs)
    write_abaqus(folder / "lattice_STIF2.mtx", k, dofs)
    try:
        from pyyeti.nastran import op4
    except ImportError:
        print("pyyeti not installed: no OP4 file written")
    else:
        op4.write(str(folder / "lattice.op4"), {"MAA": (sp.coo_matrix(m), 6), "KAA": (sp.coo_matrix(k), 6)},
                  binary=False, digits=16, sparse="bigmat")
    return m, k, dofs


def write_bad(folder: Path, m, k, dofs):
    """One wrong file per check (tests/test_fe_import.py expects each one's message)."""
    n = m.shape[0]
    kk = k.tolil()
    kk[0, 1] = k[0, 1] + 1e-3 * np.sqrt(k[0, 0] * k[1, 1])  # (0, 1) no longer equals (1, 0)
    scipy.io.mmwrite(str(folder / "bad_unsymmetric_K.mtx"), sp.coo_matrix(kk.tocsr()), symmetry="general",
                     precision=17)
    mm = m.tolil()
    mm[0, 3] = mm[3, 0] = 1.5 * np.sqrt(m[0, 0] * m[3, 3])  # a 2x2 minor with a negative determinant
    scipy.io.mmwrite(str(folder / "bad_indefinite_M.mtx"), sp.coo_matrix(mm.tocsr()), symmetry="symmetric",
                     precision=17)
    scipy.io.mmwrite(str(folder / "bad_size_K.mtx"), sp.coo_matrix(k[: n - 3, : n - 3]), symmetry="symmetric",
                     precision=17)
    write_dofs(folder / "bad_short.dofs.csv", dofs[:-1])
    write_sets(folder / "bad.sets.csv", {"flank": [int(dofs[0, 0]), 99999]})


def time_reads(folder: Path):
    """Seconds to parse each format's files, to check the model (symmetry and the mass's
    L D L^T), and the whole read_fe_model (best of ``repeat``), printed as a table."""
    import time

    from frictionjoint.structures import fe_import as fe

    def best(call, repeat=3):
        times = []
        for _ in range(repeat):
            t0 = time.perf_counter()
            out = call()
            times.append(time.perf_counter() - t0)
        return min(times), out

    dofs, sets = folder / "lattice.dofs.csv", folder / "lattice.sets.csv"
    cases = {"matrix_market": (folder / "lattice_M.mtx", folder / "lattice_K.mtx", dofs),
             "harwell_boeing": (folder / "lattice_M.rsa", folder / "lattice_K.rua", dofs),
             "nastran_dmig (small field)": ((folder / "lattice_small.pch", "MAAX"),
                                            (folder / "lattice_small.pch", "KAAX"), None),
             "nastran_dmig (large field)": ((folder / "lattice_large.pch", "MAAX"),
                                            (folder / "lattice_large.pch", "KAAX"), None),
             "nastran_dmig (free field)": ((folder / "lattice_free.bdf", "MAAX"), (folder / "lattice_free.bdf", "KAAX"),
                                           None),
             "nastran_op4 (ASCII, sparse)": ((folder / "lattice.op4", "MAA"), (folder / "lattice.op4", "KAA"), dofs),
             "abaqus_matrix_input": (folder / "lattice_MASS2.mtx", folder / "lattice_STIF2.mtx", None)}
    print(f"{'format':30s} {'read_fe_model [s]':>18s}")
    for name, (mass, stiffness, table) in cases.items():
        seconds, model = best(lambda: fe.read_fe_model(mass, stiffness, dofs=table, node_sets=sets), repeat=1)
        print(f"{name:30s} {seconds:18.2f}")
    m, k, names = model.mass, model.stiffness, model.dof_names
    t_sym, _ = best(lambda: (fe._check_symmetric("mass", m, names), fe._check_symmetric("stiffness", k, names)))
    t_pd, _ = best(lambda: fe._check_positive_definite("mass", m, names))
    t_csv, _ = best(lambda: fe.read_dof_table(dofs))
    # a mass with the stiffness's pattern, as a solid mesh's consistent mass has, and node ids in
    # no particular order: K + 0.1 diag(K), its DOFs shuffled
    shuffle = np.random.default_rng(1).permutation(k.shape[0])
    solid = (k + sp.diags_array(0.1 * k.diagonal())).tocsr()[shuffle][:, shuffle]
    t_solid, _ = best(lambda: fe._check_positive_definite("mass", solid, names), repeat=1)
    t_all, _ = best(lambda: fe.FEModel(m, k, None, model.dofs, model.node_sets))
    print(f"{model.n_dof} DOFs, {k.nnz} stiffness and {m.nnz} mass entries; checks (best of 3): symmetry of both "
          f"{t_sym:.2f} s, mass L D L^T {t_pd:.2f} s, all checks of FEModel {t_all:.2f} s; DOF table CSV {t_csv:.2f} s; "
          f"L D L^T of a mass with the stiffness's pattern, DOFs shuffled: {t_solid:.2f} s")


if __name__ == "__main__":
    if len(sys.argv) == 3 and sys.argv[1] == "--time":
        time_reads(Path(sys.argv[2]))
        sys.exit()
    if len(sys.argv) > 1:  # a big model for timing: folder nx ny nz
        folder, nx, ny, nz = Path(sys.argv[1]), *map(int, sys.argv[2:5])
    else:
        folder, nx, ny, nz = HERE, 4, 2, 2
    m, k, dofs = write_all(folder, nx, ny, nz)
    if len(sys.argv) == 1:
        write_bad(folder, m, k, dofs)
    print(f"wrote {folder}: {m.shape[0]} DOFs, {k.nnz} stiffness and {m.nnz} mass entries")

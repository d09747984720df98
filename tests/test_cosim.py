"""A system of FMUs: LinearStructure.fmu (two-DOF chain) with two JenkinsJoint.fmu instances,
through this library's master and, as SSP, through Ecos; errors against the library's exact
MDOF solution (FrictionSystem + simulate: event-driven, no time step).

The case (models/two_dof_chain.toml, JenkinsJoint.fmu defaults): unit masses and springs,
C = 0.02 K, Jenkins kt = 100 N/m, Fs = 0.8 N from each mass to the ground, 1 N cos(1.2 t) on
DOF 2, from rest, four periods. Joint 1 never slips in the exact solution (its force stays
below 0.2 N); joint 2 slips near every displacement peak.
"""
import math

import numpy as np
import pytest

import frictionjoint as fj
from frictionjoint.errors import ParameterError
from frictionjoint.fmi.cosim import FMUSystem, joint_connections
from frictionjoint.structure_file import load_structure_definition

MODEL = "models/two_dof_chain.toml"
OMEGA = 1.2
T = 2 * math.pi / OMEGA
PERIODS = 4
DIVISIONS = (50, 100, 200, 400)  # communication steps T/50 ... T/400
OUTPUTS = ["chain.x_x1", "chain.x_x2", "j1.dissipated_energy"]


@pytest.fixture(scope="module")
def chain_fmus(tmp_path_factory, fmus):
    from pathlib import Path

    from frictionjoint.fmi.build import build_fmus

    root = Path(__file__).resolve().parents[1]
    (structure,) = build_fmus(tmp_path_factory.mktemp("structure"), structures=[root / MODEL])
    return {"chain": structure, "joint": fmus["JenkinsJoint"], "definition": load_structure_definition(root / MODEL)}


def system(chain_fmus, coupling):
    return FMUSystem({"chain": chain_fmus["chain"], "j1": chain_fmus["joint"], "j2": chain_fmus["joint"]},
                     joint_connections("chain", "j1", "x1", coupling, events=False)
                     + joint_connections("chain", "j2", "x2", coupling, events=False))


def exact(definition, division):
    """The library's exact solution at the communication points t = n T/division."""
    kt, fs = 100.0, 0.8  # JenkinsJoint.fmu defaults
    sysl = fj.FrictionSystem(definition.structure, [fj.Jenkins(kt, fs, dof="x1"), fj.Jenkins(kt, fs, dof="x2")],
                             omega=OMEGA, excitation=[fj.HarmonicForce("x2", 1.0)])
    t = T / division * np.arange(division * PERIODS + 1)
    return fj.simulate(sysl, t[-1], t_eval=t, record=("x", "friction_force", "energy"))


def errors(result, ref):
    """Max error over the communication points, per DOF, relative to that DOF's amplitude."""
    x = np.vstack([result["chain.x_x1"], result["chain.x_x2"]])
    return np.max(np.abs(x - ref.x), axis=1) / np.max(np.abs(ref.x), axis=1)


@pytest.fixture(scope="module")
def references(chain_fmus):
    return {d: exact(chain_fmus["definition"], d) for d in DIVISIONS}


def observed_order(errs):
    """Least-squares slope of log(error) against log(step)."""
    return float(np.polyfit(np.log(1.0 / np.array(DIVISIONS, dtype=float)), np.log(errs), 1)[0])


def test_definition_and_fmu_defaults_are_the_case(chain_fmus, references):
    d = chain_fmus["definition"]
    assert d.ports == ("x1", "x2") and d.omega == OMEGA and d.force_amplitude == {"x2": 1.0}
    # joint 1 never slips in the exact solution: its force stays below the slip force
    ref = references[400]
    assert np.max(np.abs(ref.friction_force[0])) < 0.3 * 0.8
    assert np.max(np.abs(ref.friction_force[1])) == pytest.approx(0.8, rel=1e-12)


def test_semi_implicit_master_converges_to_the_exact_solution(chain_fmus, references):
    sys_ = system(chain_fmus, "semi-implicit")
    errs = []
    for d in DIVISIONS:
        r = sys_.simulate(PERIODS * T, T / d, OUTPUTS)
        assert np.allclose(r.t, T / d * np.arange(d * PERIODS + 1), rtol=0, atol=1e-13)
        errs.append(errors(r, references[d]).max())
        assert r["j1.dissipated_energy"][-1] == 0.0  # joint 1 sticks, as in the exact solution
    # measured: 2.7e-1, 3.5e-2, 1.7e-2, 2.8e-3 (orders 2.9, 1.1, 2.6; fit 2.1)
    assert errs[-1] < 5e-3
    assert errs[0] / errs[-1] > 30
    assert observed_order(errs) > 1.5


def test_explicit_coupling_diverges_where_semi_implicit_is_stable(chain_fmus, references):
    """Force held over the step (no tangent stiffness): the stuck joint's spring (omega_t = 10
    rad/s) is integrated by zero-order hold, which amplifies every step (|lambda|^2 = 1 + (omega_t
    h)^2 / 2): joint 1's oscillation grows until it slips, which it never does in the exact
    solution, at every step size."""
    sys_ = system(chain_fmus, "explicit")
    for d in DIVISIONS:
        r = sys_.simulate(PERIODS * T, T / d, OUTPUTS)
        e1 = errors(r, references[d])[0]
        assert e1 > 3.0  # measured 35, 17, 11, 7.2 times joint 1's true amplitude
        assert r["j1.dissipated_energy"][-1] > 0.0  # spurious slip


def test_jacobi_transfer_lags_and_stays_stable(chain_fmus, references):
    """Jacobi transfer (Ecos's algorithm): the joint force lags a step; the semi-implicit form
    stays exact while joints stick, so the coupling is stable and converges, with a larger error."""
    sys_ = system(chain_fmus, "semi-implicit")
    errs = [errors(sys_.simulate(PERIODS * T, T / d, OUTPUTS, transfer="jacobi"), references[d]).max()
            for d in DIVISIONS]
    # measured: 1.35, 0.28, 0.093, 0.021
    assert errs[-1] < 0.05 and observed_order(errs) > 1.5


def guide_rows():
    """The fixed-step rows of docs/cosimulation.md's coupling table that this master ran: (transfer,
    coupling, velocity connected, the five printed errors at T/20 ... T/400)."""
    from pathlib import Path

    page = (Path(__file__).resolve().parents[1] / "docs" / "cosimulation.md").read_text()
    rows = []
    for line in page.splitlines():
        cells = [c.strip() for c in line.strip().strip("|").split("|")]
        if len(cells) < 7 or "fixed step" not in cells[0]:
            continue
        coupling = cells[1].split(",")[0]
        velocity = [v for v in (False, True) if ("velocity connected" in cells[1]) == v
                    or "connected or not" in cells[1]]
        transfers = ([t for t in ("sequential", "jacobi") if t in cells[0].lower()]
                     or ["sequential", "jacobi"])  # "any of the four": a range over both
        rows += [(cells[0], coupling, tuple(transfers), v, tuple(cells[2:7])) for v in velocity]
    return rows


def printed(text):
    """``(low, high)`` of a printed number or range ``"89 … 308"``: each to half a unit in its
    last printed digit (the rounding of the page)."""
    from decimal import Decimal

    def bounds(number):
        d = Decimal(number.strip())
        half = Decimal(5) * Decimal(10) ** (d.as_tuple().exponent - 1)
        return float(d - half), float(d + half)

    parts = [bounds(n) for n in text.split("…")]
    return parts[0], parts[-1]


def test_the_guide_table_has_its_rows():
    """The rows test_the_guide_table_rows reruns are on the page (an empty parametrisation would
    only skip): sequential and Jacobi with the velocity connected or not, explicit with either."""
    rows = guide_rows()
    assert len(rows) == 6
    assert {(r[1], r[2], r[3]) for r in rows} == {
        ("semi-implicit", ("sequential",), False), ("semi-implicit", ("sequential",), True),
        ("semi-implicit", ("jacobi",), False), ("semi-implicit", ("jacobi",), True),
        ("explicit", ("sequential", "jacobi"), False), ("explicit", ("sequential", "jacobi"), True)}


@pytest.mark.parametrize("row", guide_rows(), ids=lambda r: f"{r[0]}-{r[1]}-{'v' if r[3] else 'no-v'}")
def test_the_guide_table_rows(chain_fmus, row):
    """docs/cosimulation.md's fixed-step rows of this master, rerun as each row says: the error at
    T/20 ... T/400 to the page's printed digits (a range row: its ends are the least and largest
    error over the transfers). These are coupling errors of 1e-3 or more, in which rounding
    (1e-14) cannot move a printed digit."""
    label, coupling, transfers, velocity, cells = row
    s = FMUSystem({"chain": chain_fmus["chain"], "j1": chain_fmus["joint"], "j2": chain_fmus["joint"]},
                  joint_connections("chain", "j1", "x1", coupling, events=velocity)
                  + joint_connections("chain", "j2", "x2", coupling, events=velocity))
    for division, cell in zip((20, 50, 100, 200, 400), cells):
        ref = exact(chain_fmus["definition"], division)
        errs = [errors(s.simulate(PERIODS * T, T / division, OUTPUTS, transfer=t, locate_events=False), ref).max()
                for t in transfers]
        (lo_ok, hi_ok) = printed(cell)
        assert lo_ok[0] <= min(errs) <= lo_ok[1], (label, division, errs)
        assert hi_ok[0] <= max(errs) <= hi_ok[1], (label, division, errs)


def test_bad_systems_are_rejected(chain_fmus):
    comps = {"chain": chain_fmus["chain"], "j1": chain_fmus["joint"]}
    with pytest.raises(ParameterError, match="has no output 'nope'"):
        FMUSystem(comps, [("j1.nope", "chain.joint_force_x1")])
    with pytest.raises(ParameterError, match="has no input 'x_x1'"):
        FMUSystem(comps, [("j1.force", "chain.x_x1")])
    with pytest.raises(ParameterError, match="one connection only"):
        FMUSystem(comps, [("j1.force", "chain.joint_force_x1"), ("j1.tangent_stiffness", "chain.joint_force_x1")])
    with pytest.raises(ParameterError, match="no parameter 'mass'"):
        FMUSystem(comps, [], {"j1": {"mass": 1.0}})
    with pytest.raises(ParameterError, match="not found"):
        FMUSystem({"a": "no-such.fmu"})
    with pytest.raises(ParameterError, match="coupling must be"):
        joint_connections("chain", "j1", "x1", "implicit")
    s = FMUSystem(comps, joint_connections("chain", "j1", "x1"))
    with pytest.raises(ParameterError, match="step"):
        s.simulate(1.0, -0.1, ["chain.x_x1"])
    with pytest.raises(ParameterError, match="transfer must be"):
        s.simulate(1.0, 0.1, ["chain.x_x1"], transfer="gauss")
    with pytest.raises(ParameterError, match="no variable"):
        s.simulate(1.0, 0.1, ["chain.y"])


def test_parameters_are_converted_to_their_variable_type_never_silently(fmus):
    """A Boolean takes any way of writing a switch, an Integer only a whole number, a Real only a
    finite number: ``int(5.5)``, ``bool(0.5)`` and NaN were passed on silently before."""
    from frictionjoint.fmi.master import FMUInstance

    inst = FMUInstance(fmus["IwanJoint"], "iwan")
    try:
        assert inst.convert("n_sliders", 8.0) == 8 and isinstance(inst.convert("n_sliders", 8.0), int)
        with pytest.raises(ParameterError, match="n_sliders must be a whole number"):
            inst.convert("n_sliders", 5.5)
        with pytest.raises(ParameterError, match="must be finite"):
            inst.convert("slip_force", float("nan"))
        with pytest.raises(ParameterError, match="n_sliders must be a whole number"):
            inst.initialize({"n_sliders": 5.5})
    finally:
        inst.close()
    blade = FMUInstance(fmus["BladeDovetail"], "blade")
    try:
        assert blade.convert("normal_load_variation", "true") is True and blade.convert("normal_load_variation", 0) is False
        with pytest.raises(ParameterError, match="normal_load_variation must be True or False"):
            blade.convert("normal_load_variation", 0.5)
    finally:
        blade.close()


def test_a_system_keeps_its_fmus_between_runs_and_frees_them(chain_fmus):
    """The components are loaded at the first run and kept (the next run resets them: the same
    numbers, bit for bit, as the reset FMU starts from the same state); close() frees them; a run
    that fails frees them, and the next run loads them again."""
    from frictionjoint.errors import FMUError

    s = system(chain_fmus, "semi-implicit")
    first = s.simulate(PERIODS * T, T / 20, ["chain.x_x2"])
    loaded = dict(s._pool)
    again = s.simulate(PERIODS * T, T / 20, ["chain.x_x2"])
    assert len(loaded) == 3 and all(s._pool[k] is v for k, v in loaded.items())
    np.testing.assert_array_equal(first["chain.x_x2"], again["chain.x_x2"])
    s.close()
    assert not s._pool and all(v._freed for v in loaded.values())
    bad = FMUSystem(s.components, s.connections, {"j1": {"slip_force": -1.0}})
    with pytest.raises(FMUError, match="slip_force"):
        bad.simulate(PERIODS * T, T / 20, ["chain.x_x2"])
    assert not bad._pool
    with FMUSystem(s.components, s.connections) as fresh:
        np.testing.assert_array_equal(fresh.simulate(PERIODS * T, T / 20, ["chain.x_x2"])["chain.x_x2"],
                                      first["chain.x_x2"])
    assert not fresh._pool


def test_a_run_that_cannot_fit_is_refused_before_anything_is_loaded(chain_fmus, monkeypatch):
    """Issue 39: ``stop_time=1e9`` allocated a 28.5 GiB grid and died with a raw MemoryError,
    ``step=1e-300`` with numpy's "Maximum allowed dimension exceeded". Both are refused, naming the
    parameter, with the estimate, before any FMU is loaded (the system's pool stays empty)."""
    from frictionjoint.fmi import cosim

    s = system(chain_fmus, "semi-implicit")
    # a machine with 16 GiB free: 1e9 s at T/20 is 3.8e9 steps, 3 columns of float64 = 85 GiB
    monkeypatch.setattr(cosim, "available_memory", lambda: 16 * 2 ** 30)
    with pytest.raises(ParameterError, match=r"stop_time = 1000000000.0 s .* 3.82e\+09 communication steps.*85.4 GiB.*16 GiB"):
        s.simulate(1e9, T / 20, ["chain.x_x1", "chain.x_x2"])
    for stop, h in ((1.0, 1e-300), (1e300, 1.0), (1e9, 1e-9), (1.0, 5e-324)):  # t0 + h == t0, or stop + h == stop
        with pytest.raises(ParameterError, match="step must be above the rounding of the times"):
            s.simulate(stop, h, ["chain.x_x1"])
    assert not s._pool


def test_a_long_run_shows_its_progress_on_stderr(chain_fmus, monkeypatch, capsys):
    """Issue 39: 10**6 steps ran for minutes with no progress bar and no estimate. By default the bar
    (tqdm, with the time left) appears once the run has lasted PROGRESS_DELAY seconds: here 0 s."""
    from frictionjoint.fmi import cosim

    s = system(chain_fmus, "semi-implicit")
    s.simulate(T, T / 20, ["chain.x_x1"])
    assert "co-simulation" not in capsys.readouterr().err  # a short run: no bar
    monkeypatch.setattr(cosim, "PROGRESS_DELAY", 0.0)
    s.simulate(T, T / 20, ["chain.x_x1"])
    assert "co-simulation" in capsys.readouterr().err
    s.simulate(T, T / 20, ["chain.x_x1"], progress=False)
    assert "co-simulation" not in capsys.readouterr().err
    with pytest.raises(ParameterError, match="progress must be True, False or None"):
        s.simulate(T, T / 20, ["chain.x_x1"], progress="yes")
    s.close()

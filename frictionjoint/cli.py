"""The ``frictionjoint`` command (also ``python -m frictionjoint``).

Subcommands::

    frictionjoint demo [--slip-force F] [--points N] [--out forced_response.png] [--csv FILE]
    frictionjoint map  [--out map.png] [--friction START:STOP:N] [--ratio START:STOP:N]
    frictionjoint sweep FMU_OR_MODEL --omega START:STOP:N [--set NAME=VALUE ...]
                        [--direction up|down|both] [--output NAME ...] [--compare analytic]
                        [--csv FILE] [--plot PNG]
    frictionjoint campbell MODEL --speed START:STOP:N [--engine-orders 1,2,3] [--modes N]
                           [--amplitude A] [--harmonics H] [--plot PNG] [--csv FILE]
    frictionjoint build-fmus [--out DIR] [--only NAME ...] [--structure FILE ...] [--system FILE ...]
                             [--blade MODEL ...] [--fmi-version {2,3}] [--no-early-return]
                             [--interface {cs,me,both}]
    frictionjoint host-env [COMMAND ...]
    frictionjoint bench [--quick] [--repeat N] [--out DIR]

``demo`` sweeps the single-DOF Coulomb oscillator across resonance (stepped sine, up and down,
exact periodic steady state at every frequency), prints the table beside Den Hartog's closed
form and writes the plot; ``map`` draws Hong & Liu's map of stops per cycle; ``sweep`` runs the
same stepped sine through an FMU (fmpy) or the library model; ``build-fmus`` builds the FMUs
(``LinearStructure`` FMUs from structure definitions, one FMU per friction system definition; FMI 3.0
FMUs with early return at stick/slip events with ``--fmi-version 3``, friction systems included;
Model Exchange FMUs, ``<name>ME.fmu``, with ``--interface me`` or ``both``);
``campbell`` computes a blade model's Campbell diagram (its frequencies on the stuck and on the
slipping root against rotor speed, the engine-order crossings, with ``--amplitude`` the nonlinear
modes between them); ``host-env`` runs a non-Python host (Ecos, a C/C++ master) with the environment it needs to run them, in
that process only (without a command, it prints that environment);
``bench`` runs the work-precision benchmark of the source tree (``benchmarks/harness.py``) and writes its CSV
and plot. Progress bars go to stderr, results to stdout; invalid options exit with status 2 and a
message.
"""
from __future__ import annotations

import argparse
import math
import os
import sys
from collections import Counter

import numpy as np

from . import __version__
from .errors import ParameterError, check_bool
from .fmi.build import FMUS, FMUS3, FMUS_ME
from .frequencies import omega_range, parse_range
from .stepping import OSCILLATOR_OUTPUTS
from .sweep import BLADE_SETTINGS

#: build-fmus --interface -> build_fmus(interface=...)
_INTERFACES = {"cs": "co-simulation", "me": "model-exchange", "both": "both"}

__all__ = ["main", "build_parser"]

PROG = "frictionjoint"


def _number(kind: str):
    """argparse type: a finite float, ``kind`` in {'real', 'positive', 'nonnegative'}."""
    accept = {"real": (lambda v: True, ""), "positive": (lambda v: v > 0, " > 0"),
              "nonnegative": (lambda v: v >= 0, " >= 0")}[kind]

    def convert(text: str) -> float:
        try:
            value = float(text)
        except ValueError:
            raise argparse.ArgumentTypeError(f"expected a number, got {text!r}") from None
        if not (math.isfinite(value) and accept[0](value)):
            raise argparse.ArgumentTypeError(f"expected a finite number{accept[1]}, got {text!r}")
        return value
    return convert


_positive_float = _number("positive")
_nonnegative_float = _number("nonnegative")
_real = _number("real")


def _count(minimum: int):
    def parse(text: str) -> int:
        try:
            value = int(text)
        except ValueError:
            raise argparse.ArgumentTypeError(f"expected an integer, got {text!r}") from None
        if value < minimum:
            raise argparse.ArgumentTypeError(f"expected an integer >= {minimum}, got {text!r}")
        return value
    return parse


def _range(lower: float, strict: bool, with_count: bool):
    """Parser of ``START:STOP:N`` (or ``START:STOP`` when ``with_count`` is False)."""
    form = "START:STOP:N" if with_count else "START:STOP"

    def parse(text: str):
        parts = text.split(":")
        if len(parts) != (3 if with_count else 2):
            raise argparse.ArgumentTypeError(f"expected {form}, got {text!r}")
        try:
            start, stop = float(parts[0]), float(parts[1])
            n = int(parts[2]) if with_count else None
        except ValueError:
            raise argparse.ArgumentTypeError(f"expected {form} with numbers, got {text!r}") from None
        bad = [v for v in (start, stop) if not math.isfinite(v) or v < lower or (strict and v == lower)]
        if bad:
            rel = ">" if strict else ">="
            raise argparse.ArgumentTypeError(f"START and STOP must be finite and {rel} {lower:g}, got {text!r}")
        if stop < start:
            raise argparse.ArgumentTypeError(f"STOP must be >= START, got {text!r}")
        if with_count:
            if n < 1:
                raise argparse.ArgumentTypeError(f"N must be >= 1, got {text!r}")
            if n == 1 and stop != start:
                raise argparse.ArgumentTypeError(f"N = 1 needs START == STOP, got {text!r}")
            return start, stop, n
        return start, stop
    return parse


def _omega(text: str):
    """argparse type of ``--omega START:STOP:N``: the package's one frequency-range convention
    (:func:`frictionjoint.frequencies.parse_range`, with its messages); ``(start, stop, n)``."""
    try:
        return parse_range("omega", text)
    except ParameterError as exc:
        raise argparse.ArgumentTypeError(str(exc)) from None


def _setting(text: str):
    """argparse type of ``--set NAME=VALUE``: a name and a finite float, or a switch written
    ``true``/``false`` (also ``yes``/``no``, ``on``/``off``, any case; :func:`~frictionjoint.errors.check_bool`),
    which becomes ``True``/``False`` (``1``/``0`` stay numbers: a Boolean parameter takes them too)."""
    name, sep, value = text.partition("=")
    name = name.strip()
    if not sep or not name:
        raise argparse.ArgumentTypeError(f"expected NAME=VALUE, got {text!r}")
    try:
        return name, _real(value.strip())
    except argparse.ArgumentTypeError:
        try:
            return name, check_bool(name, value.strip())
        except ParameterError:
            raise argparse.ArgumentTypeError(f"{name}: expected a finite number or true/false, got "
                                             f"{value.strip()!r}") from None


def _add_csv_and_progress(parser, what: str) -> None:
    parser.add_argument("--csv", default=None, metavar="FILE", help=f"also write the {what} as CSV")
    parser.add_argument("--no-progress", action="store_true", help="no progress bar on stderr")


def _command(sub, name: str, func, *, help: str, description: str, **defaults) -> argparse.ArgumentParser:
    """The parser of the subcommand ``name``: abbreviated options refused (a misspelt option is an
    error, not a guess), ``func(args, parser)`` with this parser (for its errors) as what
    :func:`main` runs, and the parser-level ``defaults``."""
    parser = sub.add_parser(name, allow_abbrev=False, help=help, description=description)
    parser.set_defaults(func=func, subparser=parser, **defaults)
    return parser


def build_parser() -> argparse.ArgumentParser:
    """The argument parser of the ``frictionjoint`` command.

    Returns
    -------
    argparse.ArgumentParser
    """
    parser = argparse.ArgumentParser(
        prog=PROG,
        description="Exact event-driven dynamics of frictional joints: forced-response sweeps "
                    "and stop-regime maps of the Coulomb oscillator.",
        allow_abbrev=False)
    parser.add_argument("--version", action="version", version=f"%(prog)s {__version__}")
    sub = parser.add_subparsers(dest="command", metavar="{demo,map,sweep,study,campbell,build-fmus,host-env,bench}")
    sub.required = True
    _add_demo(sub)
    _add_map(sub)
    _add_sweep(sub)
    _add_study(sub)
    _add_campbell(sub)
    _add_tools(sub)
    return parser


def _add_study(sub) -> None:
    st = _command(
        sub, "study", _study, csv=None,
        help="run a design study (a TOML file): many sweeps over parameter grids and random samples",
        description="Run a design study defined in a TOML file (frictionjoint.study.definition): one "
                    "frequency sweep per point over grids, lists and random samples of the model's "
                    "parameters, with the peak amplitude and frequency, the equivalent damping ratio, the "
                    "energy dissipated per cycle and the slip state at the peak. Without --scheduler the "
                    "points run on a local process pool; with it, on a running Dask cluster. Rows stream "
                    "into the table as points finish; run again to resume an interrupted study. A point "
                    "that runs longer than the study's time_limit ([sweep], default 600 s) is a failed row; "
                    "the exit status is 1 when any point failed, the last line says how many.")
    st.add_argument("file", metavar="FILE", help="the study definition (.toml)")
    st.add_argument("--workers", type=_count(1), default=None, metavar="N",
                    help="local worker processes (default: the machine's cores; 1: in this process)")
    st.add_argument("--scheduler", default=None, metavar="ADDRESS",
                    help="a running Dask scheduler, e.g. tcp://host:8786 (start one with 'dask scheduler' and "
                         "workers with 'dask worker tcp://host:8786'); contacted first, before the table is touched: "
                         "it must answer as a Dask scheduler within 10 s")
    st.add_argument("--table", default=None, metavar="FILE",
                    help="the table, .csv or .parquet (default: the study's 'table', or FILE's name with .csv, in "
                         "the working directory)")
    st.add_argument("--restart", action="store_true",
                    help="compute every point again (the rows already in the table are replaced once the points "
                         "can run)")
    st.add_argument("--plot", dest="out", default=None, metavar="PNG",
                    help="write the study's plot (damper curve, contour or Monte Carlo scatter and histogram)")
    st.add_argument("--no-progress", action="store_true", help="no progress bar on stderr")


def _study(args, parser) -> int:
    """Run the study; exit status 0 when every point has a row that did not fail, 1 when some
    failed (the last line says how many) or a worker died, 2 for a bad definition or table."""
    from .errors import WorkerError
    from .study import load_study, run_study
    from .study.execution import SchedulerError, TableConflict, connect

    if args.workers is not None and args.scheduler is not None:
        parser.error("--workers is for the local pool; a Dask cluster has its own workers")
    study = load_study(args.file)  # the whole definition checked, before anything runs or is written
    table = args.table if args.table is not None else study.table
    _check_writable(parser, "--table", table)
    client = None
    if args.scheduler is not None:  # reached, and answering as a Dask scheduler, before the table is touched
        try:
            client = connect(args.scheduler)
        except SchedulerError as exc:
            parser.error(f"--scheduler: {exc.reason}")
        n = len(client.nthreads())
        where = f"the Dask cluster at {args.scheduler} ({n} worker{'s' * (n != 1)} now" + \
            ("; the points wait for workers to join)" if n == 0 else ")")
    else:
        where = "this process" if args.workers == 1 else f"{args.workers or os.cpu_count()} local processes"
    print(f"study {args.file}: {study.n_points} points of {study.model} ({', '.join(study.varied)}), "
          f"{study.omega.size} frequencies {study.omega.min():g}-{study.omega.max():g} rad/s ({study.method}), "
          f"at most {study.time_limit:g} s per point, on {where}; table {os.path.abspath(table)}", flush=True)
    computed = []
    try:
        out = run_study(study, table, workers=args.workers, scheduler=client, progress=not args.no_progress,
                        restart=args.restart, on_row=computed.append)
    except KeyboardInterrupt:
        print(f"{PROG}: interrupted; the finished points are in {table} (run again to resume)", file=sys.stderr)
        return 130
    except TableConflict as exc:
        parser.error(exc.advice("--restart"))
    except (WorkerError, OSError) as exc:
        print(f"{PROG}: {exc}", file=sys.stderr)
        return 1
    finally:
        if client is not None:
            client.close()
    if not computed:
        print(f"nothing computed: the {len(out)} points were already in {table} (--restart computes them again)")
    print(out.message)
    q = out.percentiles()
    if out.random:
        print("peak amplitude percentiles: " + ", ".join(f"P{p:g} {v:.6g} m" for p, v in q.items()))
    elif out.ok.any():
        k = int(np.nanargmin(np.where(out.ok, out["peak_amplitude"], np.nan)))
        print("lowest peak amplitude {:.6g} m at ".format(out["peak_amplitude"][k])
              + ", ".join(f"{n} = {out[n][k]:.6g}" for n in out.varied))
    failed = [row for row in out.rows() if row["status"] == "failed"]
    for row in failed:
        print(f"point {row['point']} failed: {row['error']}")
    if args.out:
        out.plot(path=args.out)
        print(f"wrote {args.out}")
    if failed:
        print(f"{len(failed)} of {len(out)} points failed (their rows in {table}, the errors above)")
        return 1
    return 0


def _add_demo(sub) -> None:
    demo = _command(
        sub, "demo", _demo,
        help="forced response of the Coulomb oscillator across resonance vs Den Hartog",
        description="Stepped-sine sweep of m x'' + k x + F sgn(x') = P cos(omega t) across "
                    "resonance, up and down, with the exact periodic steady state at every "
                    "frequency; prints the table beside Den Hartog's closed form (with the "
                    "relative error, or the regime where the closed form does not apply) and "
                    "writes the plot.")
    demo.add_argument("--mass", type=_positive_float, default=1.0, help="mass m [kg] (default 1)")
    demo.add_argument("--stiffness", type=_positive_float, default=1.0,
                      help="spring stiffness k [N/m] (default 1)")
    demo.add_argument("--force-amplitude", type=_positive_float, default=1.0,
                      help="force amplitude P [N] (default 1)")
    demo.add_argument("--slip-force", type=_nonnegative_float, default=0.5,
                      help="friction limit F [N] (default 0.5, i.e. F/P = 0.5)")
    demo.add_argument("--damping", type=_nonnegative_float, default=0.0,
                      help="viscous damping c [N s/m] (default 0; Den Hartog's form needs 0)")
    demo.add_argument("--ratio", type=_range(0.0, True, False), default=(0.5, 2.5),
                      metavar="START:STOP",
                      help="range of the frequency ratio r = omega/omega_n (default 0.5:2.5)")
    demo.add_argument("--points", type=_count(1), default=60,
                      help="number of frequencies per branch (default 60)")
    demo.add_argument("--direction", choices=("up", "down", "both"), default="both",
                      help="sweep direction (default both)")
    demo.add_argument("--out", default="forced_response.png", metavar="PNG",
                      help="plot file (default forced_response.png)")
    _add_csv_and_progress(demo, "table")


def _add_map(sub) -> None:
    mp = _command(
        sub, "map", _map,
        help="Hong & Liu's map of stops per cycle over (F/P0, r)",
        description="Number of stops per cycle of the steady motion of the Coulomb oscillator "
                    "(m = k = P0 = 1) over a grid of friction ratio F/P0 and frequency ratio r, "
                    "drawn as a categorical map (0, 1, 2, 4, ... stops, permanent stick, "
                    "unbounded, not converged).")
    mp.add_argument("--out", default="map.png", metavar="PNG", help="plot file (default map.png)")
    mp.add_argument("--friction", type=_range(0.0, False, True), default=(0.05, 1.2, 24),
                    metavar="START:STOP:N", help="friction ratios F/P0 (default 0.05:1.2:24)")
    mp.add_argument("--ratio", type=_range(0.0, True, True), default=(0.1, 2.0, 39),
                    metavar="START:STOP:N", help="frequency ratios r (default 0.1:2.0:39)")
    mp.add_argument("--jobs", type=_count(1), default=os.cpu_count() or 1,
                    help="worker processes (default: the number of CPUs)")
    mp.add_argument("--table", action="store_true", help="print the map as text")
    _add_csv_and_progress(mp, "map")


def _add_sweep(sub) -> None:
    sw = _command(
        sub, "sweep", _sweep,
        help="stepped-sine forced-response sweep through an FMU (fmpy), the library model or a blade model",
        description="Stepped-sine sweep of CoulombOscillator.fmu (or any FMU with its variables), "
                    "driven through fmpy, or of the library model 'CoulombOscillator' without the FMU "
                    "layer (frictionjoint.sweep): the periodic steady state at every frequency (the "
                    "model starts on it, one period checked), the state carried from point to point. "
                    "Prints the table (peak, "
                    "first-harmonic amplitude and phase of each output) and writes the plot; with "
                    "--compare analytic, Den Hartog's amplitude and the relative error beside each "
                    "point, or why the closed form does not apply there (stops, damping, resonance). "
                    "A blade model definition (a name in models/, e.g. ti64_compressor_blade, or a "
                    ".toml file) sweeps the Craig-Bampton blade on its dovetail root: the tip's first "
                    "harmonic with the root's two linear limits (stuck, free slip) beside it; --set "
                    "takes the root's parameters (centrifugal_force, friction_coefficient, ...) and "
                    "tip_force_amplitude, --output a DOF of the blade (default the tip).")
    sw.add_argument("model", metavar="FMU_OR_MODEL",
                    help="a .fmu file (e.g. fmus/build/CoulombOscillator.fmu), 'CoulombOscillator' or a "
                         "blade model (e.g. ti64_compressor_blade)")
    sw.add_argument("--set", dest="settings", action="append", default=[], type=_setting,
                    metavar="NAME=VALUE",
                    help="parameter value (a number, or true/false for a switch), repeatable: mass, stiffness, "
                         "damping, slip_force, force_amplitude, base_amplitude for the oscillator (SI units; the "
                         "FMU's defaults otherwise); for a blade model " + ", ".join(BLADE_SETTINGS)
                         + "; for a blade FMU its parameters")
    sw.add_argument("--omega", type=_omega, required=True, metavar="START:STOP:N",
                    help="excitation angular frequencies [rad/s]: N equally spaced from START to STOP (both > 0; "
                         "--direction sets the order they are swept in)")
    sw.add_argument("--direction", choices=("up", "down", "both"), default="up",
                    help="sweep direction (default up)")
    sw.add_argument("--output", dest="outputs", action="append", default=None, metavar="NAME",
                    help="output to report (peak, first harmonic), repeatable (default x): "
                         + ", ".join(OSCILLATOR_OUTPUTS))
    sw.add_argument("--samples", type=_count(16), default=256,
                    help="samples per period for the first harmonics of outputs other than x and "
                         "friction_force, which are integrated exactly (default 256)")
    sw.add_argument("--compare", choices=("analytic",), default=None,
                    help="put Den Hartog's closed form and the relative error beside each point")
    sw.add_argument("--plot", dest="out", default=None, metavar="PNG",
                    help="write the plot (amplitude and phase against omega) to this file")
    sw.add_argument("--method", choices=("time", "hbm"), default="time",
                    help="time: the exact steady state at each frequency (default); hbm: the harmonic-balance "
                         "branch from START to STOP by continuation, about N points (blade models)")
    sw.add_argument("--harmonics", type=_count(1), default=7, metavar="H",
                    help="harmonics of --method hbm (default 7)")
    sw.add_argument("--check", action="store_true",
                    help="--method hbm: check each branch point against the exact orbit started from it, its "
                         "truncation error and stability (one shooting per point; --method time is exact and "
                         "judges every orbit's stability anyway)")
    _add_csv_and_progress(sw, "table")


def _engine_orders(text: str):
    """argparse type of ``--engine-orders 1,2,3``: numbers > 0, comma-separated."""
    try:
        orders = [float(part) for part in text.split(",")]
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected numbers separated by commas (e.g. 1,2,3), got {text!r}") from None
    if not all(math.isfinite(e) and e > 0 for e in orders):
        raise argparse.ArgumentTypeError(f"engine orders must be finite and > 0, got {text!r}")
    if len(set(orders)) != len(orders):
        raise argparse.ArgumentTypeError(f"engine orders must not repeat, got {text!r}")
    return orders


def _add_campbell(sub) -> None:
    cb = _command(
        sub, "campbell", _campbell,
        help="Campbell diagram of a blade model: frequencies on the stuck and slipping root against rotor speed",
        description="The Campbell diagram of a blade model definition (a name in models/, e.g. "
                    "ti64_compressor_blade, or a .toml file; frictionjoint.campbell): at each rotor speed the "
                    "Craig-Bampton blade on its dovetail root, its centrifugal stiffening and the root's normal "
                    "load following the speed, with the natural frequencies of the lowest modes with the root "
                    "stuck and with it slipping freely; the engine-order lines omega = EO * speed and their "
                    "crossings with each mode, located by root finding between the speeds. Prints the crossings "
                    "(curve, engine order, mode, speed, frequency). With --amplitude, the nonlinear mode (EPMC, "
                    "exact hysteresis) of each stuck mode at that first-harmonic amplitude of the root's "
                    "tangential DOF, at every speed: its frequency between the two limits, its damping ratio, "
                    "and its crossings.")
    cb.add_argument("model", metavar="MODEL", help="a blade model (e.g. ti64_compressor_blade) or a .toml file")
    cb.add_argument("--speed", type=_range(0.0, True, True), required=True, metavar="START:STOP:N",
                    help="rotor speeds [rad/s]: N equally spaced from START to STOP (both > 0: the root carries "
                         "no load at rest)")
    cb.add_argument("--engine-orders", type=_engine_orders, default=[1.0, 2.0, 3.0, 4.0], metavar="EO,EO,...",
                    help="engine orders, comma-separated (default 1,2,3,4)")
    cb.add_argument("--modes", type=_count(1), default=3, metavar="N", help="modes per limit, the lowest (default 3)")
    cb.add_argument("--amplitude", type=_positive_float, default=None, metavar="A",
                    help="first-harmonic amplitude [m] at the root's tangential DOF of the nonlinear modes drawn "
                         "between the limits (default: none)")
    cb.add_argument("--harmonics", type=_count(1), default=1, metavar="H",
                    help="harmonics of the nonlinear modes (default 1, the describing function's balance)")
    cb.add_argument("--plot", dest="out", default=None, metavar="PNG", help="write the diagram to this file")
    _add_csv_and_progress(cb, "crossings")


def _campbell(args, parser) -> int:
    from .campbell import campbell
    from .structures.models import load_blade_model

    model = load_blade_model(args.model)  # a misspelt name is refused before anything is printed
    start, stop, n = args.speed
    print(f"Campbell diagram of {model.name} ({model.path}): {n} rotor speeds {start:g} ... {stop:g} rad/s, {args.modes} modes, "
          f"engine orders {', '.join(f'{e:g}' for e in args.engine_orders)}"
          + (f", nonlinear modes at {args.amplitude:g} m (H = {args.harmonics})" if args.amplitude else ""),
          flush=True)
    cd = campbell(model, np.linspace(start, stop, n), args.engine_orders, n_modes=args.modes,
                  amplitude=args.amplitude, n_harmonics=args.harmonics, progress=not args.no_progress)
    print(cd.table())
    print(cd.message)
    return _write(cd, args)


def _add_tools(sub) -> None:
    """build-fmus, host-env and bench."""
    bf = _command(
        sub, "build-fmus", _build_fmus, csv=None,
        help="build the FMUs (pythonfmu), post-process and validate them",
        description="Build " + ", ".join(f"{name}.fmu" for name in FMUS) + " from the scripts in "
                    "fmus/, with the library bundled inside, and check each with fmpy's validate_fmu.")
    bf.add_argument("--out", default=None, metavar="DIR",
                    help="output folder (default: fmus/build next to the package)")
    bf.add_argument("--only", nargs="+", default=None, metavar="NAME", help="build only these FMUs")
    bf.add_argument("--structure", nargs="+", default=[], metavar="FILE",
                    help="also build a LinearStructure FMU from each structure definition (.toml or .json, "
                         "see frictionjoint.structure_file; e.g. models/two_dof_chain.toml), named after its "
                         "'name'; with --structure and no --only, only the structure FMUs are built")
    bf.add_argument("--system", nargs="+", default=[], metavar="FILE",
                    help="also build one FMU of a whole friction system from each system definition (.toml "
                         "or .json, see frictionjoint.system_file; e.g. models/two_dof_chain_system.toml), "
                         "named after its 'name'; with --system and no --only, only these FMUs are built")
    bf.add_argument("--blade", nargs="+", default=[], metavar="MODEL",
                    help="also build a blade FMU (BladeDovetail's slave) from each blade model definition (a "
                         "name in models/ or a .toml file; beam or solid, e.g. ti64_solid_blade), named after "
                         "its 'name'; with --blade and no --only, only these FMUs are built")
    bf.add_argument("--fmi-version", type=int, choices=(2, 3), default=2,
                    help="3: FMI 3.0 co-simulation FMUs of " + ", ".join(FMUS3) + " (and of each --system) as "
                         "<name>Fmi3.fmu (pythonfmu3), returning early at each stick/slip event where the host "
                         "allows it (x86_64-linux binary)")
    bf.add_argument("--no-early-return", action="store_true",
                    help="--fmi-version 3: pythonfmu3's stock binaries (Linux and Windows x86_64), no early return "
                         "or event mode declared")
    bf.add_argument("--interface", choices=tuple(_INTERFACES), default="cs",
                    help="cs: co-simulation FMUs; me: Model Exchange FMUs of " + ", ".join(FMUS_ME)
                         + ", of each --structure and each --system, as <name>ME.fmu (--fmi-version 3: "
                         "<name>MEFmi3.fmu; their host integrates them with its own solver and locates their "
                         "stick/slip events from their event indicators; x86_64 Linux); both: the two")

    he = _command(
        sub, "host-env", _host_env, csv=None, out=None,
        help="run a non-Python FMU host (Ecos, a C/C++ master) with the environment it needs: "
             "frictionjoint host-env ecos simulate ...",
        description="Run COMMAND with the environment a host that is not Python (Ecos, a C/C++ master) needs "
                    "to run these FMUs with this Python, in that command's process only: LD_PRELOAD of this "
                    "interpreter's libpython (the FMUs' binary leaves the Python symbols to the process), "
                    "PYTHONPATH to this environment's site-packages (numpy, scipy), LD_LIBRARY_PATH with the "
                    "tbb wheel's folder (Ecos needs its libtbb.so.12), and ECOS, the path of an executable "
                    "ecos, checked to start; a COMMAND named 'ecos' is that executable. The exit status is "
                    "COMMAND's. Without COMMAND, prints the shell exports instead, for a subshell: "
                    "( eval \"$(frictionjoint host-env)\"; \"$ECOS\" ... ) -- evaluated in a login shell "
                    "they would preload libpython into every later command. Where Ecos cannot run it runs "
                    "and prints nothing, says why on stderr and exits with status 1.")
    he.add_argument("run", nargs=argparse.REMAINDER, metavar="COMMAND ...",
                    help="the command and its arguments ('ecos' for the ecospy wheel's executable; put '--' "
                         "before a command that starts with '-')")

    be = _command(
        sub, "bench", _bench, csv=None,
        help="work-precision benchmark: run time against error, exact marcher vs scipy baselines",
        description="Amplitude of the periodic steady state of the Coulomb oscillator (r = 0.8 and "
                    "1.5 at F/P0 = 0.3 against Den Hartog; r = 2, F/P0 = 0.6 with stops against the "
                    "converged exact orbit) by the exact marcher, steady_state, the FMU sweep, the "
                    "one-harmonic describing function and scipy solve_ivp baselines (tanh-regularised "
                    "RK45/LSODA/Radau, event-driven DOP853) at several settings, timed in this process. "
                    "Prints the table and the headline ratios; writes work_precision.csv (machine in "
                    "the header) and work_precision.png to --out.")
    be.add_argument("--quick", action="store_true", help="the short version (under 30 s)")
    be.add_argument("--repeat", type=_count(1), default=None,
                    help="best of N runs per setting (default 5, with --quick 2)")
    be.add_argument("--out", default=".", metavar="DIR",
                    help="folder for work_precision.csv and work_precision.png (default: .)")
    be.add_argument("--no-progress", action="store_true", help="no progress bar on stderr")


def _check_writable(parser, option: str, path) -> None:
    if path is None:
        return
    folder = os.path.dirname(os.path.abspath(path)) or "."
    if not os.path.isdir(folder):
        parser.error(f"{option}: directory {folder!r} does not exist")


def _demo(args, parser) -> int:
    from .sweep import sweep

    wn = math.sqrt(args.stiffness / args.mass)
    r0, r1 = args.ratio
    ratios = np.linspace(r0, r1, args.points)
    print(f"Coulomb oscillator: m = {args.mass:g} kg, k = {args.stiffness:g} N/m, "
          f"P = {args.force_amplitude:g} N, F = {args.slip_force:g} N "
          f"(F/P = {args.slip_force / args.force_amplitude:.4g}), c = {args.damping:g} N s/m, "
          f"omega_n = {wn:.6g} rad/s")
    print(f"stepped sine {args.direction}, {ratios.size} frequencies per branch, "
          f"r = {ratios[0]:g} ... {ratios[-1]:g}; exact steady state at each\n", flush=True)
    params = dict(mass=args.mass, stiffness=args.stiffness, slip_force=args.slip_force,
                  force_amplitude=args.force_amplitude, damping=args.damping)
    fr = sweep("CoulombOscillator", ratios * wn, params, direction=args.direction,
               progress=not args.no_progress)
    print(fr.table())
    return _write(fr, args)


def _map(args, parser) -> int:
    from .regime import regime_map

    fs = np.linspace(*args.friction)
    rs = np.linspace(*args.ratio)
    print(f"Hong & Liu map: {fs.size} friction ratios F/P0 = {fs[0]:g} ... {fs[-1]:g}, "
          f"{rs.size} frequency ratios r = {rs[0]:g} ... {rs[-1]:g} "
          f"({fs.size * rs.size} steady states, {args.jobs} job(s))", flush=True)
    rm = regime_map(fs, rs, progress=not args.no_progress, jobs=args.jobs)
    if args.table:
        print(rm.table())
    counts = Counter(rm.category().ravel().tolist())
    print("points per category: " + ", ".join(f"{k}: {v}" for k, v in sorted(counts.items())))
    return _write(rm, args)


def _sweep(args, parser) -> int:
    from pathlib import Path

    from .sweep import _blade_definition, _is_blade_fmu, model_not_found, sweep

    params = {}
    for name, value in args.settings:
        if name in params:
            parser.error(f"--set: {name} given twice")
        params[name] = value
    w0, w1, n = args.omega
    omegas = omega_range(w0, w1, n)
    definition = _blade_definition(args.model)
    if definition is None and args.model != "CoulombOscillator" and not (
            Path(args.model).suffix == ".fmu" and Path(args.model).is_file()):
        parser.error(str(model_not_found(args.model)))  # before anything is printed
    if definition is not None:  # a blade model definition: the blade on its root
        if args.compare:
            parser.error("--compare analytic is for the single-DOF oscillator, not a blade model")
        unknown = sorted(set(params) - set(BLADE_SETTINGS))
        if unknown:
            parser.error(f"--set: {unknown} not parameters of the blade model {definition.name}; --set takes "
                         f"{', '.join(BLADE_SETTINGS)}")
        outputs = tuple(args.outputs or ["x"])
        how = (f"harmonic balance (H = {args.harmonics}), the branch from {w0:g} to {w1:g} rad/s by continuation"
               if args.method == "hbm" else f"{n} frequencies, omega = {w0:g} ... {w1:g} rad/s")
        print(f"sweep of the blade model {definition.name} ({definition.path}) on its dovetail root, in the "
              f"library: {how}, direction {args.direction}", flush=True)
        fr = sweep(args.model, omegas, params, direction=args.direction, outputs=outputs,
                   progress=not args.no_progress, method=args.method, n_harmonics=args.harmonics,
                   check=args.check)
        print(fr.table())
        return _write(fr, args)
    if args.method != "time" or args.check:
        parser.error("--method hbm and --check are for blade model definitions (e.g. ti64_compressor_blade)")
    if _is_blade_fmu(args.model):  # BladeDovetail.fmu: the blade on its root through fmpy
        if args.compare or args.outputs:
            parser.error("--compare and --outputs are for the single-DOF oscillator, not a blade FMU")
        print(f"sweep of the blade FMU {args.model} through fmpy: {n} frequencies, omega = {w0:g} ... {w1:g} "
              f"rad/s, direction {args.direction}", flush=True)
        fr = sweep(args.model, omegas, params, direction=args.direction, progress=not args.no_progress)
        print(fr.table())
        return _write(fr, args)
    outputs = tuple(dict.fromkeys(["x"] + (args.outputs or [])))
    via = "the library (no FMU layer)" if args.model == "CoulombOscillator" else "fmpy"
    print(f"sweep of {args.model} through {via}: {n} frequencies, omega = {w0:g} ... {w1:g} rad/s, "
          f"direction {args.direction}", flush=True)
    fr = sweep(args.model, omegas, params, direction=args.direction, outputs=outputs,
               n_samples=args.samples, progress=not args.no_progress)
    p = fr.parameters
    print(", ".join(f"{k} = {v:g}" for k, v in p.items())
          + f", omega_n = {fr.natural_frequency:.6g} rad/s\n")
    print(fr.table(compare=args.compare == "analytic"))
    return _write(fr, args)


def _write(result, args) -> int:
    """Write the result's CSV (if asked) and its plot (if asked); say so."""
    if args.csv:
        result.to_csv(args.csv)
        print(f"wrote {args.csv}")
    if args.out:
        result.plot(path=args.out)
        print(f"wrote {args.out}")
    return 0


def _build_fmus(args, parser) -> int:
    from .fmi.build import build_fmus, default_source_dir

    out = args.out or str(default_source_dir() / "build")
    interface = _INTERFACES[args.interface]
    cosim = interface != "model-exchange"
    table = dict(FMUS3 if args.fmi_version == 3 else FMUS) if cosim else {}
    if interface != "co-simulation":
        table.update(FMUS_ME)
    if args.only:
        unknown = [n for n in args.only if n not in table]
        if unknown:
            parser.error(f"--only: unknown FMU(s) {unknown} for --fmi-version {args.fmi_version} --interface "
                         f"{args.interface}; choose from {sorted(table)}")
    if cosim and args.fmi_version == 3 and (args.structure or args.blade):
        parser.error("--structure and --blade build FMI 2.0 co-simulation FMUs only (--fmi-version 2)")
    if not cosim and args.blade:
        parser.error("--blade: a blade FMU has no Model Exchange form (--interface cs)")
    for path in build_fmus(out, names=args.only, structures=args.structure, systems=args.system,
                           fmi_version=args.fmi_version, early_return=not args.no_early_return,
                           blades=args.blade, interface=interface):
        print(f"built and validated {path}")
    return 0


def _host_env(args, parser) -> int:
    """Everything is computed, and ecos started once, before anything runs or is printed: where
    Ecos cannot run, nothing runs, stdout stays empty (``eval`` applies nothing) and stderr says why
    (status 1). With a command, the environment is that command's alone (its process and its
    children), never the caller's shell's."""
    import shlex
    import subprocess

    from .errors import FMUError
    from .fmi.ecos import ecos_environment

    try:
        env = ecos_environment()
    except FMUError as exc:
        parser.exit(1, f"{PROG} host-env: {exc}\n")
    command = list(args.run)
    if command[:1] == ["--"]:
        command = command[1:]
    if not command:
        print("\n".join(f"export {name}={shlex.quote(value)}" for name, value in env.items()))
        return 0
    if command[0] == "ecos":
        command[0] = env["ECOS"]
    try:
        return subprocess.call(command, env=dict(os.environ, **env))
    except OSError as exc:
        parser.exit(127, f"{PROG} host-env: cannot run {command[0]!r}: {exc}\n")


def _benchmark_harness():
    """The work-precision harness of the source tree, ``benchmarks/harness.py`` beside the package
    (the package itself does not carry the scipy baselines)."""
    import importlib.util
    from pathlib import Path

    path = Path(__file__).resolve().parents[1] / "benchmarks" / "harness.py"
    if not path.is_file():
        raise FileNotFoundError(f"frictionjoint bench runs the benchmark harness of the source tree, "
                                f"{path} (not installed with the package): run it from a checkout")
    for name in ("benchmarks.harness", "frictionjoint_benchmark_harness"):  # imported already (tests)
        module = sys.modules.get(name)
        if module is not None and Path(module.__file__).resolve() == path:
            return module
    name = "frictionjoint_benchmark_harness"
    module = sys.modules.get(name)
    if module is None:
        spec = importlib.util.spec_from_file_location(name, path)
        module = importlib.util.module_from_spec(spec)
        sys.modules[name] = module  # the dataclasses there look their module up
        spec.loader.exec_module(module)
    return module


def _bench(args, parser) -> int:
    try:
        run_benchmark = _benchmark_harness().run_benchmark
    except FileNotFoundError as exc:
        print(f"error: {exc}", file=sys.stderr)
        return 2

    os.makedirs(args.out, exist_ok=True)
    print(f"work-precision benchmark{' (quick)' if args.quick else ''}: amplitude of the periodic "
          "steady state of the Coulomb oscillator, every method in this process", flush=True)
    wp = run_benchmark(quick=args.quick, repeat=args.repeat, progress=not args.no_progress)
    print("\n".join("# " + line for line in wp.header_lines()))
    print(wp.table())
    print()
    print(wp.summary())
    csv_path = os.path.join(args.out, "work_precision.csv")
    png_path = os.path.join(args.out, "work_precision.png")
    wp.to_csv(csv_path)
    wp.plot(path=png_path)
    print(f"wrote {csv_path}\nwrote {png_path}")
    return 0


#: options whose value is a range START:STOP[:N] (see _attach_range_values)
_RANGE_OPTIONS = ("--omega", "--ratio", "--friction", "--speed")


def _attach_range_values(argv: list) -> list:
    """``--omega -1:2.5:10`` as ``--omega=-1:2.5:10``.

    argparse takes a word that starts with ``-`` for an option unless it is a plain negative
    number, so a range with a negative START never reached the range's own check (the message was
    "expected one argument"). A value that starts with ``-`` and a digit or a point is never one of
    this command's options: it is attached to the range option before it, and the range's check
    says what is wrong with it. Nothing after ``--`` is touched.
    """
    out = []
    i = 0
    while i < len(argv):
        word = str(argv[i])
        if word == "--":
            out.extend(argv[i:])
            break
        value = str(argv[i + 1]) if i + 1 < len(argv) else ""
        if word in _RANGE_OPTIONS and len(value) > 1 and value[0] == "-" and (value[1].isdigit() or value[1] == "."):
            out.append(f"{word}={value}")
            i += 2
            continue
        out.append(argv[i])
        i += 1
    return out


def main(argv=None) -> int:
    """Run the ``frictionjoint`` command.

    Parameters
    ----------
    argv : sequence of str, optional
        Arguments without the program name; ``sys.argv[1:]`` if omitted.

    Returns
    -------
    int
        Exit status: 0 on success, 2 on invalid arguments.
    """
    parser = build_parser()
    args = parser.parse_args(_attach_range_values(sys.argv[1:] if argv is None else list(argv)))
    sub = args.subparser
    if args.command not in ("build-fmus", "host-env"):
        _check_writable(sub, "--plot" if args.command in ("sweep", "study", "campbell") else "--out", args.out)
    _check_writable(sub, "--csv", args.csv)
    try:
        return args.func(args, sub)
    except ParameterError as exc:
        sub.error(str(exc))
    except KeyboardInterrupt:
        print(f"{PROG}: interrupted", file=sys.stderr)
        return 130


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())

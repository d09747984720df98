"""Bad input at every public entry point: each invalid value (negative, zero where not allowed,
NaN, inf, wrong type or shape, non-symmetric or non-positive-definite M, K, C) raises
ParameterError (a ValueError) whose message names the offending argument. The FMU parameters
are checked the same way through fmpy, one subprocess per FMU
(tests/stress/fmu_stress_checks.py: the FMU is re-initialised, i.e. reset, for each bad value).

"""
import json
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

import frictionjoint as fj
from frictionjoint.study import Grid, Values
from frictionjoint.contact import HalfPlaneContact, HertzCylinder, MindlinContact, Profile, RoundedFlatPunch, Wedge
from frictionjoint.shakedown import PeriodicLoad, QuasiStaticFrictionSystem, melan_check, shakedown_check
from frictionjoint.sweep import oscillator_sweep

HERE = Path(__file__).parent
NAN, INF = float("nan"), float("inf")


def _s2():
    return fj.LinearStructure(np.diag([1.0, 2.0]), [[2.0, -1.0], [-1.0, 1.0]])


def _forced(elements=()):
    return fj.FrictionSystem(_s2(), list(elements), omega=1.0, excitation=[fj.HarmonicForce(0, 1.0)])


def _mode():
    return fj.nonlinear_mode(_free_jenkins(), amplitudes=[0.01, 1.0], n_harmonics=1)


def _synth_system():
    return _forced([fj.Jenkins(1.0, 0.1, dof=0)])


def _free_jenkins():
    return fj.FrictionSystem(_s2(), [fj.Jenkins(1.0, 0.1, dof=0)])


def _patch():
    return fj.FlankPatch([(0, 1)], 1.0, 1.0)


def _no_build(omega):
    """A build that must never be called: the arguments are checked first."""
    raise AssertionError("build called before the arguments were checked")


def _osc():
    return fj.CoulombOscillator(slip_force=0.3, force_amplitude=1.0)


def _qs(n=1):
    return QuasiStaticFrictionSystem(np.eye(n), [0.3] * n)


def _load(tangential=((0.0,), (1.0,)), normal=((1.0,), (1.0,)), times=(0.0, 0.5), period=1.0):
    return PeriodicLoad(list(times), [list(r) for r in tangential], [list(r) for r in normal], period)


def _mindlin(n):
    return MindlinContact(n, 0.3, 0.02, 210e9, 0.3)


def _dovetail(**kw):
    args = dict(centrifugal_force=1e4, flank_angle=0.5, friction_coefficient=0.3, normal_stiffness=1e8,
                tangential_stiffness=1e8, tangential_dof=0)
    args.update(kw)
    return fj.DovetailRoot(**args)


# (label, call, name the message must contain)
BLADE = "ti64_compressor_blade"
MU = {"friction_coefficient": Values((0.3,))}

CASES = [
    # LinearStructure: M, K, C, names
    ("M non-symmetric", lambda: fj.LinearStructure([[1, 0.5], [0, 1]], np.eye(2)), "mass"),
    ("M indefinite", lambda: fj.LinearStructure([[1, 0], [0, -1]], np.eye(2)), "mass"),
    ("M singular", lambda: fj.LinearStructure([[1, 1], [1, 1]], np.eye(2)), "mass"),
    ("M zero", lambda: fj.LinearStructure(0.0, 1.0), "mass"),
    ("M negative", lambda: fj.LinearStructure(-1.0, 1.0), "mass"),
    ("M nan", lambda: fj.LinearStructure(NAN, 1.0), "mass"),
    ("M inf", lambda: fj.LinearStructure(INF, 1.0), "mass"),
    ("M string", lambda: fj.LinearStructure("x", 1.0), "mass"),
    ("M 3-D", lambda: fj.LinearStructure(np.ones((2, 2, 2)), np.eye(2)), "mass"),
    ("M non-square", lambda: fj.LinearStructure(np.ones((2, 3)), np.eye(2)), "mass"),
    ("K non-symmetric", lambda: fj.LinearStructure(np.eye(2), [[1, 0.5], [0, 1]]), "stiffness"),
    ("K indefinite", lambda: fj.LinearStructure(np.eye(2), [[1, 0], [0, -1]]), "stiffness"),
    ("K inf", lambda: fj.LinearStructure(1.0, INF), "stiffness"),
    ("K nan", lambda: fj.LinearStructure(1.0, NAN), "stiffness"),
    ("K wrong shape", lambda: fj.LinearStructure(np.eye(2), np.eye(3)), "stiffness"),
    ("C non-symmetric", lambda: fj.LinearStructure(np.eye(2), np.eye(2), [[1, 0.5], [0, 1]]), "damping"),
    ("C negative", lambda: fj.LinearStructure(1.0, 1.0, -1.0), "damping"),
    ("C nan", lambda: fj.LinearStructure(1.0, 1.0, NAN), "damping"),
    ("C wrong shape", lambda: fj.LinearStructure(np.eye(2), np.eye(2), np.eye(3)), "damping"),
    ("dof_names short", lambda: fj.LinearStructure(np.eye(2), np.eye(2), dof_names=["a"]), "dof_names"),
    ("dof_names duplicate", lambda: fj.LinearStructure(np.eye(2), np.eye(2), dof_names=["a", "a"]), "dof_names"),
    # elements
    ("Jenkins kt zero", lambda: fj.Jenkins(0.0, 1.0, dof=0), "tangential_stiffness"),
    ("Jenkins kt nan", lambda: fj.Jenkins(NAN, 1.0, dof=0), "tangential_stiffness"),
    ("Jenkins kt inf", lambda: fj.Jenkins(INF, 1.0, dof=0), "tangential_stiffness"),
    ("Jenkins fs negative", lambda: fj.Jenkins(1.0, -1.0, dof=0), "slip_force"),
    ("Jenkins fs inf", lambda: fj.Jenkins(1.0, INF, dof=0), "slip_force"),
    ("Jenkins direction nan", lambda: fj.FrictionSystem(_s2(), [fj.Jenkins(1.0, 1.0, direction=[NAN, 1])]),
     "direction"),
    ("Jenkins direction zero", lambda: fj.FrictionSystem(_s2(), [fj.Jenkins(1.0, 1.0, direction=[0, 0])]),
     "direction"),
    ("Jenkins direction length", lambda: fj.FrictionSystem(_s2(), [fj.Jenkins(1.0, 1.0, direction=[1, 0, 0])]),
     "direction"),
    ("Jenkins direction string", lambda: fj.FrictionSystem(_s2(), [fj.Jenkins(1.0, 1.0, direction="ab")]),
     "direction"),
    ("Jenkins dof out of range", lambda: fj.FrictionSystem(_s2(), [fj.Jenkins(1.0, 1.0, dof=5)]), "dof"),
    ("Jenkins dof negative", lambda: fj.FrictionSystem(_s2(), [fj.Jenkins(1.0, 1.0, dof=-1)]), "dof"),
    ("CoulombSlider fs negative", lambda: fj.CoulombSlider(-1.0, dof=0), "slip_force"),
    ("CoulombSlider fs nan", lambda: fj.CoulombSlider(NAN, dof=0), "slip_force"),
    ("Iwan empty", lambda: fj.Iwan([], dof=0), "sliders"),
    ("Iwan negative stiffness", lambda: fj.Iwan([(-1.0, 1.0)], dof=0), "stiffness"),
    ("Iwan nan slip force", lambda: fj.Iwan([(1.0, NAN)], dof=0), "slip_force"),
    ("Iwan triple", lambda: fj.Iwan([(1.0, 1.0, 1.0)], dof=0), "sliders"),
    ("Segalman chi > 0", lambda: fj.Iwan.segalman(1, 1, 0.5, 0.1, dof=0), "chi"),
    ("Segalman chi = -1", lambda: fj.Iwan.segalman(1, 1, -1.0, 0.1, dof=0), "chi"),
    ("Segalman beta < 0", lambda: fj.Iwan.segalman(1, 1, -0.5, -0.1, dof=0), "beta"),
    ("Segalman n_sliders 0", lambda: fj.Iwan.segalman(1, 1, -0.5, 0.1, n_sliders=0, dof=0), "n_sliders"),
    ("Segalman n_sliders 2.5", lambda: fj.Iwan.segalman(1, 1, -0.5, 0.1, n_sliders=2.5, dof=0), "n_sliders"),
    ("Segalman slip_force nan", lambda: fj.Iwan.segalman(NAN, 1, -0.5, 0.1, dof=0), "slip_force"),
    ("Segalman stiffness 0", lambda: fj.Iwan.segalman(1, 0, -0.5, 0.1, dof=0), "stiffness"),
    ("ContinuousIwan stiffness 0", lambda: fj.ContinuousIwan(lambda u: u, 0.0, 1.0, 1.0), "stiffness"),
    ("ContinuousIwan slip_force nan", lambda: fj.ContinuousIwan(lambda u: u, 1.0, NAN, 1.0), "slip_force"),
    ("ContinuousIwan slip_displacement < 0", lambda: fj.ContinuousIwan(lambda u: u, 1.0, 1.0, -1.0),
     "slip_displacement"),
    ("ContinuousIwan slip_displacement inf", lambda: fj.ContinuousIwan(lambda u: u, 1.0, 1.0, INF),
     "slip_displacement"),
    ("ContinuousIwan backbone not callable", lambda: fj.ContinuousIwan(3.0, 1.0, 1.0, 1.0), "backbone"),
    ("ContinuousIwan inverse not callable", lambda: fj.ContinuousIwan(lambda u: u, 1.0, 1.0, 1.0, inverse=2.0),
     "inverse"),
    # DovetailRoot
    ("Dovetail Fc zero", lambda: _dovetail(centrifugal_force=0.0), "centrifugal_force"),
    ("Dovetail Fc nan", lambda: _dovetail(centrifugal_force=NAN), "centrifugal_force"),
    ("Dovetail angle pi/2", lambda: _dovetail(flank_angle=np.pi / 2), "flank_angle"),
    ("Dovetail angle negative", lambda: _dovetail(flank_angle=-0.1), "flank_angle"),
    ("Dovetail angle nan", lambda: _dovetail(flank_angle=NAN), "flank_angle"),
    ("Dovetail mu zero", lambda: _dovetail(friction_coefficient=0.0), "friction_coefficient"),
    ("Dovetail kn zero", lambda: _dovetail(normal_stiffness=0.0), "normal_stiffness"),
    ("Dovetail kn inf", lambda: _dovetail(normal_stiffness=INF), "normal_stiffness"),
    ("Dovetail kt nan", lambda: _dovetail(tangential_stiffness=NAN), "tangential_stiffness"),
    ("Dovetail kt missing", lambda: _dovetail(tangential_stiffness=None), "tangential_stiffness"),
    ("Dovetail n_sliders 0", lambda: _dovetail(tangential_stiffness=None, flank_contact=_mindlin, n_sliders=0),
     "n_sliders"),
    ("Dovetail rotor speed < 0", lambda: fj.DovetailRoot.from_rotor(
        -1.0, 1.0, 0.1, flank_angle=0.5, friction_coefficient=0.3, normal_stiffness=1e8,
        tangential_stiffness=1e8, tangential_dof=0), "rotor_speed"),
    ("Dovetail radial dof", lambda: fj.FrictionSystem(_s2(), [_dovetail(radial_dof=5)]), "dof"),
    # excitation and system
    ("HarmonicForce amplitude nan", lambda: fj.HarmonicForce(0, NAN), "amplitude"),
    ("HarmonicForce phase inf", lambda: fj.HarmonicForce(0, 1.0, INF), "phase"),
    ("HarmonicBaseMotion stiffness < 0", lambda: fj.HarmonicBaseMotion(0, -1.0, 1.0), "stiffness"),
    ("HarmonicBaseMotion damping < 0", lambda: fj.HarmonicBaseMotion(0, 1.0, 1.0, -1.0), "damping"),
    ("HarmonicBaseMotion amplitude nan", lambda: fj.HarmonicBaseMotion(0, 1.0, NAN), "amplitude"),
    ("ExternalForce times decreasing", lambda: fj.ExternalForce(0, [0, 2, 1], [1, 2]), "times"),
    ("ExternalForce values length", lambda: fj.ExternalForce(0, [0, 1, 2], [1, 2, 3]), "values"),
    ("ExternalForce values nan", lambda: fj.ExternalForce(0, [0, 1, 2], [1, NAN]), "values"),
    ("ExternalForce times nan", lambda: fj.ExternalForce(0, [0, NAN, 2], [1, 1]), "times"),
    ("ExternalForce empty", lambda: fj.ExternalForce(0, [], []), "times"),
    ("FrictionSystem omega 0", lambda: fj.FrictionSystem(_s2(), [], omega=0.0,
                                                          excitation=[fj.HarmonicForce(0, 1.0)]), "omega"),
    ("FrictionSystem omega nan", lambda: fj.FrictionSystem(_s2(), [], omega=NAN), "omega"),
    ("FrictionSystem omega < 0", lambda: fj.FrictionSystem(_s2(), [], omega=-1.0), "omega"),
    ("FrictionSystem omega inf", lambda: fj.FrictionSystem(_s2(), [], omega=INF), "omega"),
    ("FrictionSystem excitation dof", lambda: fj.FrictionSystem(_s2(), [], omega=1.0,
                                                                 excitation=[fj.HarmonicForce(7, 1.0)]), "dof"),
    ("FrictionSystem excitation name", lambda: fj.FrictionSystem(_s2(), [], omega=1.0,
                                                                  excitation=[fj.HarmonicForce("zz", 1.0)]), "zz"),
    ("FrictionSystem harmonic without omega", lambda: fj.FrictionSystem(_s2(), [],
                                                                         excitation=[fj.HarmonicForce(0, 1.0)]),
     "omega"),
    ("FrictionSystem structure", lambda: fj.FrictionSystem(np.eye(2), []), "structure"),
    ("FrictionSystem element", lambda: fj.FrictionSystem(_s2(), [3.0]), "element"),
    # CoulombOscillator and its methods
    ("oscillator mass 0", lambda: fj.CoulombOscillator(mass=0.0), "mass"),
    ("oscillator mass nan", lambda: fj.CoulombOscillator(mass=NAN), "mass"),
    ("oscillator stiffness < 0", lambda: fj.CoulombOscillator(stiffness=-1.0), "stiffness"),
    ("oscillator slip_force < 0", lambda: fj.CoulombOscillator(slip_force=-1.0), "slip_force"),
    ("oscillator slip_force inf", lambda: fj.CoulombOscillator(slip_force=INF), "slip_force"),
    ("oscillator force_amplitude nan", lambda: fj.CoulombOscillator(force_amplitude=NAN), "force_amplitude"),
    ("oscillator omega 0", lambda: fj.CoulombOscillator(omega=0.0), "omega"),
    ("oscillator omega inf", lambda: fj.CoulombOscillator(omega=INF), "omega"),
    ("oscillator damping < 0", lambda: fj.CoulombOscillator(damping=-1.0), "damping"),
    ("oscillator base_amplitude inf", lambda: fj.CoulombOscillator(base_amplitude=INF), "base_amplitude"),
    ("oscillator.simulate t_end < 0", lambda: _osc().simulate(-1.0), "t_end"),
    ("oscillator.simulate t_end nan", lambda: _osc().simulate(NAN), "t_end"),
    ("oscillator.simulate t_end inf", lambda: _osc().simulate(INF), "t_end"),
    ("oscillator.simulate x0 nan", lambda: _osc().simulate(1.0, x0=NAN), "x0"),
    ("oscillator.simulate v0 inf", lambda: _osc().simulate(1.0, v0=INF), "v0"),
    ("oscillator.simulate t_eval nan", lambda: _osc().simulate(1.0, t_eval=[0, NAN]), "t_eval"),
    ("oscillator.simulate t_eval beyond", lambda: _osc().simulate(1.0, t_eval=[0, 2.0]), "t_eval"),
    ("oscillator.simulate t_eval decreasing", lambda: _osc().simulate(1.0, t_eval=[0.5, 0.1]), "t_eval"),
    ("oscillator.simulate record", lambda: _osc().simulate(1.0, record=("zz",)), "record"),
    ("oscillator.steady_state tol < 0", lambda: _osc().steady_state(tol=-1.0), "tol"),
    ("oscillator.steady_state tol nan", lambda: _osc().steady_state(tol=NAN), "tol"),
    ("oscillator.steady_state max_periods < 0", lambda: _osc().steady_state(max_periods=-1), "max_periods"),
    ("oscillator.steady_state n_samples < 0", lambda: _osc().steady_state(n_samples=-1), "n_samples"),
    ("oscillator.steady_state x0 nan", lambda: _osc().steady_state(x0=NAN), "x0"),
    # simulate / periodic_response
    ("simulate t_end < 0", lambda: fj.simulate(_forced(), -1.0), "t_end"),
    ("simulate t_end nan", lambda: fj.simulate(_forced(), NAN), "t_end"),
    ("simulate x0 nan", lambda: fj.simulate(_forced(), 1.0, x0=[1, NAN]), "x0"),
    ("simulate v0 inf", lambda: fj.simulate(_forced(), 1.0, v0=[INF, 0]), "v0"),
    ("simulate t0 nan", lambda: fj.simulate(_forced(), 1.0, t0=NAN), "t0"),
    ("simulate t0 > t_end", lambda: fj.simulate(_forced(), 1.0, t0=2.0), "t_end"),
    ("simulate w0 nan", lambda: fj.simulate(_forced([fj.Jenkins(1, 1, dof=0)]), 1.0, w0=[NAN]), "w0"),
    ("simulate t_eval nan", lambda: fj.simulate(_forced(), 1.0, t_eval=[NAN]), "t_eval"),
    ("simulate record", lambda: fj.simulate(_forced(), 1.0, record=("bogus",)), "record"),
    ("periodic_response without omega", lambda: fj.periodic_response(fj.FrictionSystem(_s2(), [])), "omega"),
    ("simulate not a system", lambda: fj.simulate("system", 1.0), "system"),
    ("simulate x0 wrong length", lambda: fj.simulate(_forced(), 1.0, x0=[1.0, 2.0, 3.0]), "x0"),
    ("simulate v0 wrong shape", lambda: fj.simulate(_forced(), 1.0, v0=np.zeros((2, 2))), "v0"),
    ("simulate x0 string", lambda: fj.simulate(_forced(), 1.0, x0="a"), "x0"),
    ("simulate w0 wrong length", lambda: fj.simulate(_forced([fj.Jenkins(1, 1, dof=0)]), 1.0, w0=[0.0, 0.0]), "w0"),
    ("Marcher not a system", lambda: fj.Marcher(None), "system"),
    ("SdofCoulomb mass 0", lambda: fj.SdofCoulomb(0.0, 1.0, 0.3, 1.0, 1.0), "mass"),
    ("SdofCoulomb omega nan", lambda: fj.SdofCoulomb(1.0, 1.0, 0.3, 1.0, NAN), "omega"),
    ("SdofCoulomb slip_force < 0", lambda: fj.SdofCoulomb(1.0, 1.0, -0.3, 1.0, 1.0), "slip_force"),
    ("SdofCoulomb.march t_end < t0", lambda: fj.SdofCoulomb(1.0, 1.0, 0.3, 1.0, 1.0).march(1.0, 0.0, 0.0, 0.5), "t_end"),
    ("SdofCoulomb.march x0 inf", lambda: fj.SdofCoulomb(1.0, 1.0, 0.3, 1.0, 1.0).march(0.0, INF, 0.0, 1.0), "x0"),
    ("Marcher.initial_state x0 wrong length", lambda: fj.Marcher(_forced()).initial_state([0.0] * 3, 0.0), "x0"),
    ("periodic_response not a system", lambda: fj.periodic_response(_s2()), "system"),
    ("periodic_response max_newton 0", lambda: fj.periodic_response(_forced(), max_newton=0), "max_newton"),
    ("periodic_response max_periods -1", lambda: fj.periodic_response(_forced(), max_periods=-1), "max_periods"),
    ("periodic_response n_samples -2", lambda: fj.periodic_response(_forced(), n_samples=-2), "n_samples"),
    ("periodic_response n_samples float", lambda: fj.periodic_response(_forced(), n_samples=2.5), "n_samples"),
    ("periodic_response v0 wrong length", lambda: fj.periodic_response(_forced(), v0=[0.0] * 3), "v0"),
    ("periodic_response tol 0", lambda: fj.periodic_response(_forced(), tol=0.0), "tol"),
    ("periodic_response tol nan", lambda: fj.periodic_response(_forced(), tol=NAN), "tol"),
    ("periodic_response x0 nan", lambda: fj.periodic_response(_forced(), x0=[NAN, 0]), "x0"),
    # sweeps and maps
    ("oscillator_sweep omegas < 0", lambda: oscillator_sweep(1, 1, 0.3, 1, [-1.0, 1.0]), "omega"),
    ("oscillator_sweep omegas nan", lambda: oscillator_sweep(1, 1, 0.3, 1, [NAN]), "omega"),
    ("oscillator_sweep omegas empty", lambda: oscillator_sweep(1, 1, 0.3, 1, []), "omega"),
    ("oscillator_sweep direction", lambda: oscillator_sweep(1, 1, 0.3, 1, [1.0], direction="sideways"),
     "direction"),
    ("oscillator_sweep mass 0", lambda: oscillator_sweep(0, 1, 0.3, 1, [1.0]), "mass"),
    ("oscillator_sweep no excitation", lambda: oscillator_sweep(1, 1, 0.3, 0, [1.0]), "force_amplitude"),
    ("oscillator_sweep damping < 0", lambda: oscillator_sweep(1, 1, 0.3, 1, [1.0], damping=-1), "damping"),
    ("system_sweep omegas nan", lambda: fj.system_sweep(lambda w: _forced(), [NAN]), "omega"),
    ("peak_response reversed range", lambda: fj.peak_response(lambda w: _forced(), 2.0, 1.0), "omega"),
    ("peak_response nan", lambda: fj.peak_response(lambda w: _forced(), NAN, 1.0), "omega_min"),
    ("peak_response n_grid 1", lambda: fj.peak_response(lambda w: _forced(), 1.0, 2.0, n_grid=1), "n_grid"),
    ("system_sweep build not callable", lambda: fj.system_sweep(_forced(), [1.0]), "build"),
    ("nonlinear_mode amplitude nan", lambda: fj.nonlinear_mode(_free_jenkins(), amplitudes=[NAN]), "amplitudes"),
    ("nonlinear_mode n_harmonics 0", lambda: fj.nonlinear_mode(_free_jenkins(), n_harmonics=0), "n_harmonics"),
    ("nonlinear_mode mode beyond", lambda: fj.nonlinear_mode(_free_jenkins(), mode=5), "mode"),
    ("nonlinear_mode tol 0", lambda: fj.nonlinear_mode(_free_jenkins(), tol=0.0), "tol"),
    ("mode_synthesis omegas nan", lambda: fj.mode_synthesis(_mode(), _synth_system(), [NAN, 2.0]), "omegas"),
    ("mode_synthesis omegas < 0", lambda: fj.mode_synthesis(_mode(), _synth_system(), "-1:2:5"), "omegas"),
    ("mode_synthesis tol 0", lambda: fj.mode_synthesis(_mode(), _synth_system(), [1.0, 2.0], tol=0.0), "tol"),
    ("mode_synthesis max_iter 0", lambda: fj.mode_synthesis(_mode(), _synth_system(), [1.0, 2.0], max_iter=0),
     "max_iter"),
    ("mode_synthesis output 7", lambda: fj.mode_synthesis(_mode(), _synth_system(), [1.0, 2.0], output=7), "output"),
    ("slip_pattern of a system at another omega",
     lambda: fj.slip_pattern(fj.periodic_response(_forced([fj.Jenkins(1.0, 0.1, dof=0)])),
                             fj.FrictionSystem(_forced().structure, [fj.Jenkins(1.0, 0.1, dof=0)], omega=3.0)), "omega"),
    ("campbell speeds 0", lambda: fj.campbell("ti64_compressor_blade", "0:1000:5"), "speeds"),
    ("campbell speeds decreasing", lambda: fj.campbell("ti64_compressor_blade", [300.0, 200.0]), "speeds"),
    ("campbell speeds nan", lambda: fj.campbell("ti64_compressor_blade", [100.0, NAN]), "speeds"),
    ("campbell engine order 0", lambda: fj.campbell("ti64_compressor_blade", [500.0], engine_orders=[0]), "engine_orders"),
    ("campbell engine order inf", lambda: fj.campbell("ti64_compressor_blade", [500.0], engine_orders=[1, INF]),
     "engine_orders"),
    ("campbell engine orders repeated", lambda: fj.campbell("ti64_compressor_blade", [500.0], engine_orders=[2, 2]),
     "engine_orders"),
    ("campbell n_modes 0", lambda: fj.campbell("ti64_compressor_blade", [500.0], n_modes=0), "n_modes"),
    ("campbell amplitude < 0", lambda: fj.campbell("ti64_compressor_blade", [500.0], amplitude=-1e-5), "amplitude"),
    ("campbell n_harmonics 0", lambda: fj.campbell("ti64_compressor_blade", [500.0], amplitude=1e-5, n_harmonics=0),
     "n_harmonics"),
    ("FlankPatch normal_stiffness < 0", lambda: fj.FlankPatch([(0, 1)], -1.0, 1.0), "normal_stiffness"),
    ("FlankPatch tangential_stiffness nan", lambda: fj.FlankPatch([(0, 1)], 1.0, NAN), "tangential_stiffness"),
    ("FlankPatch no node", lambda: fj.FlankPatch([], 1.0, 1.0), "nodes"),
    ("PatchDovetailRoot flank_angle pi/2", lambda: fj.PatchDovetailRoot(_patch(), _patch(), 2.0, 0.3, {1: 1.0}),
     "flank_angle"),
    ("PatchDovetailRoot mu < 0", lambda: fj.PatchDovetailRoot(_patch(), _patch(), 0.5, -0.3, {1: 1.0}),
     "friction_coefficient"),
    ("PatchDovetailRoot load nan", lambda: fj.PatchDovetailRoot(_patch(), _patch(), 0.5, 0.3, {1: NAN}),
     "centrifugal_load"),
    ("harmonic_balance n_harmonics 0", lambda: fj.harmonic_balance(_forced(), n_harmonics=0), "n_harmonics"),
    ("harmonic_balance omega nan", lambda: fj.harmonic_balance(_forced(), omega=NAN), "omega"),
    ("harmonic_balance tol 0", lambda: fj.harmonic_balance(_forced(), tol=0.0), "tol"),
    ("harmonic_balance guess shape", lambda: fj.harmonic_balance(_forced([fj.Jenkins(1.0, 0.1, dof=0)]),
                                                                 guess=np.zeros((2, 7))), "guess"),
    ("harmonic_balance no joint", lambda: fj.harmonic_balance(_forced()), "sliders"),
    ("hbm_sweep omega_range one value", lambda: fj.hbm_sweep(_forced(), (1.0,)), "omega_range"),
    ("hbm_sweep omega_range nan", lambda: fj.hbm_sweep(_forced(), (NAN, 2.0)), "omega_range"),
    ("hbm_sweep n_points 1", lambda: fj.hbm_sweep(_forced(), (1.0, 2.0), n_points=1), "n_points"),
    ("system_sweep build returns no system", lambda: fj.system_sweep(lambda w: _s2(), [1.0]), "build"),
    ("peak_response xtol 0", lambda: fj.peak_response(_no_build, 1.0, 2.0, xtol=0.0), "xtol"),
    ("peak_response xtol nan", lambda: fj.peak_response(_no_build, 1.0, 2.0, xtol=NAN), "xtol"),
    ("peak_response dof -1", lambda: fj.peak_response(_no_build, 1.0, 2.0, dof=-1), "dof"),
    ("peak_response dof beyond", lambda: fj.peak_response(lambda w: _forced(), 1.0, 2.0, dof=2), "dof"),
    ("peak_response build not callable", lambda: fj.peak_response(_forced(), 1.0, 2.0), "build"),
    ("regime_map friction nan", lambda: fj.regime_map([NAN], [1.0]), "friction_ratios"),
    ("regime_map frequency < 0", lambda: fj.regime_map([0.5], [-1.0]), "frequency_ratios"),
    ("regime_map jobs 0", lambda: fj.regime_map([0.5], [1.0], jobs=0), "jobs"),
    # contact
    ("Mindlin load 0", lambda: MindlinContact(0.0, 0.3, 0.02, 210e9, 0.3), "normal_load"),
    ("Mindlin mu nan", lambda: MindlinContact(1.0, NAN, 0.02, 210e9, 0.3), "friction_coefficient"),
    ("Mindlin radius < 0", lambda: MindlinContact(1.0, 0.3, -0.02, 210e9, 0.3), "radius"),
    ("Mindlin E inf", lambda: MindlinContact(1.0, 0.3, 0.02, INF, 0.3), "youngs_modulus"),
    ("Mindlin nu 0.5", lambda: MindlinContact(1.0, 0.3, 0.02, 210e9, 0.5), "poisson_ratio"),
    ("Mindlin to_iwan 0", lambda: MindlinContact(1.0, 0.3, 0.02, 210e9, 0.3).to_iwan(0), "n_sliders"),
    # beyond elements.iwan.MAX_SLIDERS: refused before the slider table is allocated (1e9 would
    # need 8 GB per array, then Iwan refused it)
    ("Mindlin to_iwan 1e9", lambda: MindlinContact(1.0, 0.3, 0.02, 210e9, 0.3).to_iwan(10 ** 9), "n_sliders"),
    ("HertzCylinder radius 0", lambda: HertzCylinder(0.0), "radius"),
    ("Wedge angle < 0", lambda: Wedge(-0.1), "angle"),
    ("Wedge angle nan", lambda: Wedge(NAN), "angle"),
    ("RoundedFlatPunch width < 0", lambda: RoundedFlatPunch(-1e-3, 1e-3), "flat_half_width"),
    ("RoundedFlatPunch radius nan", lambda: RoundedFlatPunch(1e-3, NAN), "corner_radius"),
    ("Profile not callable", lambda: Profile(3.0), "h"),
    ("HalfPlane load 0", lambda: HalfPlaneContact(RoundedFlatPunch(2e-3, 5e-3), 0.0, 0.3, 210e9, 0.3, 0.01),
     "normal_load"),
    ("HalfPlane mu < 0", lambda: HalfPlaneContact(RoundedFlatPunch(2e-3, 5e-3), 100.0, -0.3, 210e9, 0.3, 0.01),
     "friction_coefficient"),
    ("HalfPlane E nan", lambda: HalfPlaneContact(RoundedFlatPunch(2e-3, 5e-3), 100.0, 0.3, NAN, 0.3, 0.01),
     "youngs_modulus"),
    ("HalfPlane nu 0.7", lambda: HalfPlaneContact(RoundedFlatPunch(2e-3, 5e-3), 100.0, 0.3, 210e9, 0.7, 0.01),
     "poisson_ratio"),
    ("HalfPlane depth < 0", lambda: HalfPlaneContact(RoundedFlatPunch(2e-3, 5e-3), 100.0, 0.3, 210e9, 0.3, -0.01),
     "reference_depth"),
    ("HalfPlane length 0", lambda: HalfPlaneContact(RoundedFlatPunch(2e-3, 5e-3), 100.0, 0.3, 210e9, 0.3, 0.01,
                                                    length=0.0), "length"),
    ("HalfPlane n_nodes 1", lambda: HalfPlaneContact(RoundedFlatPunch(2e-3, 5e-3), 100.0, 0.3, 210e9, 0.3, 0.01,
                                                     n_nodes=1), "n_nodes"),
    ("HalfPlane tilt nan", lambda: HalfPlaneContact(RoundedFlatPunch(2e-3, 5e-3), 100.0, 0.3, 210e9, 0.3, 0.01,
                                                    tilt=NAN), "tilt"),
    ("HalfPlane profile", lambda: HalfPlaneContact(3.0, 100.0, 0.3, 210e9, 0.3, 0.01), "profile"),
    # shakedown
    ("QuasiStatic K non-symmetric", lambda: QuasiStaticFrictionSystem([[1, 0.5], [0, 1]], [0.3, 0.3]), "stiffness"),
    ("QuasiStatic K indefinite", lambda: QuasiStaticFrictionSystem([[1, 0], [0, -1]], [0.3, 0.3]), "stiffness"),
    ("QuasiStatic K nan", lambda: QuasiStaticFrictionSystem([[NAN]], [0.3]), "stiffness"),
    ("QuasiStatic mu < 0", lambda: QuasiStaticFrictionSystem(np.eye(2), [0.3, -0.3]), "friction_coefficient"),
    ("QuasiStatic mu shape", lambda: QuasiStaticFrictionSystem(np.eye(2), [0.3]), "friction_coefficient"),
    ("PeriodicLoad period 0", lambda: _load(period=0.0), "period"),
    ("PeriodicLoad period <= last time", lambda: _load(period=0.5), "period"),
    ("PeriodicLoad tangential nan", lambda: _load(tangential=((0.0,), (NAN,))), "tangential"),
    ("PeriodicLoad tangential rows", lambda: _load(tangential=((0.0,),)), "tangential"),
    ("PeriodicLoad normal < 0", lambda: _load(normal=((-1.0,), (1.0,))), "normal"),
    ("PeriodicLoad times decreasing", lambda: _load(times=(0.0, 0.7, 0.5), tangential=((0,), (1,), (0,)),
                                                    normal=((1,), (1,), (1,))), "times"),
    ("shakedown_check n_cycles 0", lambda: shakedown_check(_qs(), _load(), n_cycles=0), "n_cycles"),
    ("shakedown_check rtol nan", lambda: shakedown_check(_qs(), _load(), rtol=NAN), "rtol"),
    ("shakedown_check initial_slip shape", lambda: shakedown_check(_qs(), _load(), initial_slip=[1, 2]),
     "initial_slip"),
    ("shakedown_check size mismatch", lambda: shakedown_check(_qs(2), _load()), "load"),
    ("melan_check size mismatch", lambda: melan_check(_qs(2), _load()), "load"),
    # design studies (a real model and parameter, so that only the named value is wrong)
    ("Study omega nan", lambda: fj.Study(model=BLADE, omega=(NAN, 2.0, 3.5), vary=MU), "omega"),
    ("Study omega count 1", lambda: fj.Study(model=BLADE, omega="1:2:1", vary=MU), "omega"),
    ("Study omega ambiguous", lambda: fj.Study(model=BLADE, omega=(1.0, 2.0, 3), vary=MU), "omega"),
    ("Study n_samples 0", lambda: fj.Study(model=BLADE, omega="1:2:3", vary=MU, n_samples=0), "n_samples"),
    ("Study seed < 0", lambda: fj.Study(model=BLADE, omega="1:2:3", vary=MU, seed=-1), "seed"),
    ("Study fixed text", lambda: fj.Study(model=BLADE, omega="1:2:3", vary=MU,
                                          fixed={"centrifugal_force": "a"}), "fixed.centrifugal_force"),
    ("Study fixed nan", lambda: fj.Study(model=BLADE, omega="1:2:3", vary=MU,
                                         fixed={"centrifugal_force": NAN}), "fixed.centrifugal_force"),
    ("Study values inf", lambda: fj.Study(model=BLADE, omega="1:2:3",
                                          vary={"friction_coefficient": Values((INF,))}).points(),
     "vary.friction_coefficient"),
    ("Study grid start nan", lambda: fj.Study(model=BLADE, omega="1:2:3",
                                              vary={"friction_coefficient": Grid(NAN, 1.0, 3)}).points(),
     "vary.friction_coefficient"),
    ("load_study missing", lambda: fj.load_study("/nonexistent/study.toml"), "study file"),
    # BLAS threads (blas_threads takes no argument); a refused value leaves the choice as it was
    ("set_blas_threads 0", lambda: fj.set_blas_threads(0), "n must be None or an integer >= 1"),
    ("run_study workers 0", lambda: fj.run_study(fj.Study(model=BLADE, omega="1:2:3", vary=MU), "t.csv", workers=0),
     "workers"),
    ("run_study table suffix", lambda: fj.run_study(fj.Study(model=BLADE, omega="1:2:3", vary=MU), "t.txt"), "table"),
]


@pytest.mark.parametrize("label, call, name", CASES, ids=[c[0] for c in CASES])
def test_bad_value_raises_parameter_error_naming_it(label, call, name):
    with pytest.raises(fj.ParameterError) as info:
        call()
    assert isinstance(info.value, ValueError)
    assert name in str(info.value), f"{label}: message does not name {name!r}: {info.value}"


def test_every_public_callable_with_numbers_is_covered():
    """Each name in fj.__all__ that takes numbers appears in a label or a call above."""
    import inspect

    text = inspect.getsource(sys.modules[__name__])
    takes_numbers = [n for n in fj.__all__ if n not in (
        "ConvergenceError", "ParameterError", "FMUError", "NoSolutionError", "EventLog", "PeriodicResponse",
        "TimeResponse", "FrequencyResponse", "RegimeMap", "SystemSweep", "analytic", "contact", "shakedown",
        "Marcher", "blas_threads")]
    missing = [n for n in takes_numbers if n not in text]
    assert not missing


# ------------------------------------------------------------------------------------------ FMUs
#: FMU -> [(parameters set at initialisation, name the FMU's error message must contain)]
FMU_CASES = {
    "CoulombOscillator": [({"mass": v}, "mass") for v in (0.0, -1.0, NAN, INF)]
    + [({"stiffness": v}, "stiffness") for v in (0.0, NAN)]
    + [({"damping": v}, "damping") for v in (-1.0, NAN)]
    + [({"slip_force": v}, "slip_force") for v in (-1.0, INF)]
    + [({"omega": v, "force_amplitude": 1.0}, "omega") for v in (0.0, -1.0, NAN)]
    + [({"force_amplitude": v}, "force_amplitude") for v in (NAN, INF)]
    + [({"base_amplitude": INF}, "base_amplitude"), ({"x0": NAN}, "x0"), ({"v0": INF}, "v0")],
    "JenkinsJoint": [({"stiffness": v}, "stiffness") for v in (0.0, -1.0, NAN, INF)]
    + [({"slip_force": v}, "slip_force") for v in (0.0, NAN, INF)],
    "IwanJoint": [({"stiffness": v}, "stiffness") for v in (0.0, NAN)]
    + [({"slip_force": v}, "slip_force") for v in (-1.0, INF)]
    + [({"chi": v}, "chi") for v in (0.5, -1.0, NAN)]
    + [({"beta": v}, "beta") for v in (-0.1, NAN)]
    + [({"n_sliders": v}, "n_sliders") for v in (0, -3)],
    "MicroslipJoint": [({"normal_load": v}, "normal_load") for v in (0.0, NAN)]
    + [({"friction_coefficient": v}, "friction_coefficient") for v in (0.0, INF)]
    + [({"radius": -1.0}, "radius"), ({"youngs_modulus": NAN}, "youngs_modulus")]
    + [({"poisson_ratio": v}, "poisson_ratio") for v in (0.5, -1.0, NAN)]
    + [({"n_sliders": 0}, "n_sliders")],
    "DovetailRoot": [({"centrifugal_force": v}, "centrifugal_force") for v in (0.0, NAN)]
    + [({"flank_angle": v}, "flank_angle") for v in (-0.1, np.pi / 2, NAN)]
    + [({"friction_coefficient": 0.0}, "friction_coefficient")]
    + [({"normal_stiffness": v}, "normal_stiffness") for v in (0.0, INF)]
    + [({"tangential_stiffness": v}, "tangential_stiffness") for v in (0.0, NAN)]
    + [({"flank_profile": v}, "flank_profile") for v in (7, -1)]
    + [({"flank_profile": 1, "flank_radius": 0.0}, "radius"),
       ({"flank_profile": 1, "youngs_modulus": NAN}, "youngs_modulus"),
       ({"flank_profile": 1, "poisson_ratio": 0.5}, "poisson_ratio"),
       ({"flank_profile": 1, "n_sliders": 0}, "n_sliders"),
       ({"flank_profile": 2, "flat_half_width": -1.0}, "flat_half_width"),
       ({"flank_profile": 2, "corner_radius": 0.0}, "corner_radius"),
       ({"flank_profile": 2, "flank_length": 0.0}, "length"),
       ({"flank_profile": 2, "reference_depth": 0.0}, "reference_depth")],
}


@pytest.mark.parametrize("fmu", sorted(FMU_CASES))
def test_fmu_rejects_bad_parameters_naming_them(fmus, fmu):
    """One subprocess per FMU; the instance is re-initialised (reset) for each bad value and,
    at the end, once more with its defaults, which must still work."""
    cases = [p for p, _ in FMU_CASES[fmu]]  # json writes NaN and Infinity
    proc = subprocess.run([sys.executable, str(HERE / "fmu_stress_checks.py"), "bad_parameters", str(fmus[fmu]),
                           json.dumps(cases)], capture_output=True, text=True, timeout=120)
    assert proc.returncode == 0, proc.stderr[-3000:]
    res = json.loads(proc.stdout.strip().splitlines()[-1])
    failures = []
    for (params, name), got in zip(FMU_CASES[fmu], res["cases"]):
        if got["raised"] is None or not any(name in m for m in got["messages"]):
            failures.append((params, name, got))
    assert not failures
    assert res["defaults_ok"], res

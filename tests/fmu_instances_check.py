"""Many instances of one FMU in one fmpy process, the cyclic GC on (run by test_fmu_instances.py).

    python fmu_instances_check.py FMU N_INSTANCES N_ROUNDS

For each instance index i the inputs and one parameter differ (:data:`CASES`); every instance
runs the same schedule: set parameters, initialise, step with its inputs, save the state (and
serialise it) half-way, step on, restore the saved state, step to the end again. The outputs
of every step are recorded.

1. ``lone``: each i alone in the process (instantiate, run, free), one after another;
2. ``rounds``: N_ROUNDS times, all N_INSTANCES instantiated together, stepped interleaved
   (each step of the schedule for every instance in turn, state calls included), freed in a
   shuffled order, with garbage collections between the calls; in each round one more
   instance is given a bad parameter (:data:`BAD`): its ``exitInitializationMode`` must fail
   with the parameter named in the log, and the instance is freed at once.

Prints one JSON line: the number of instantiations; per round, the indices whose record
differs from the lone run's (bit for bit); what the bad instances logged; the reference counts
of the script's module dict and slave class after the lone runs and at the end (equal when
nothing is over-released or leaked); the copies of the resources folder on ``sys.path``. The process ends normally (interpreter teardown
included): a crash is a non-zero exit status.
"""
import gc
import json
import math
import random
import sys

from fmpy import extract, read_model_description
from fmpy.fmi2 import FMU2Slave

#: FMU -> a parameter value that exitInitializationMode rejects
BAD = {"CoulombOscillator": ("mass", -1.0), "JenkinsJoint": ("slip_force", -1.0), "IwanJoint": ("chi", 2.0),
       "MicroslipJoint": ("radius", 0.0), "DovetailRoot": ("flank_angle", 2.0),
       "BladeDovetail": ("friction_coefficient", 0.0)}
#: FMU -> (parameter varied per instance: name -> value for instance i; input signals: name -> u(i, t))
CASES = {
    "CoulombOscillator": ({"slip_force": lambda i: 0.1 + 0.05 * i},
                          {"force": lambda i, t: 0.2 * math.sin(0.7 * t + i)}),
    "JenkinsJoint": ({"slip_force": lambda i: 0.5 + 0.1 * i},
                     {"u": lambda i, t: (1 + 0.1 * i) * 2e-4 * math.sin(1.3 * t) * (1 + 0.3 * math.sin(0.4 * t))}),
    "IwanJoint": ({"slip_force": lambda i: 1.0 + 0.2 * i},
                  {"u": lambda i, t: (2 + i) * 1e-4 * math.sin(t) + 5e-5 * math.sin(3.1 * t)}),
    "MicroslipJoint": ({"normal_load": lambda i: 100.0 + 10 * i},
                       {"u": lambda i, t: (1 + 0.2 * i) * 1e-6 * math.sin(t)}),
    "DovetailRoot": ({"centrifugal_force": lambda i: 1e4 * (1 + 0.1 * i)},
                     {"u_tangential": lambda i, t: (1 + 0.1 * i) * 3e-5 * math.sin(t),
                      "u_radial": lambda i, t: 1e-5 * math.sin(0.5 * t + i)}),
    # the root stuck (full centrifugal load, twice the model's friction: far from slip even at the
    # start), so that 6 s of a 2000 rad/s response stay cheap
    "BladeDovetail": ({"centrifugal_force": lambda i: 2e4 * (1 + 0.1 * i), "friction_coefficient": lambda i: 0.6},
                      {"tip_force": lambda i, t: 0.2 * math.sin(0.7 * t + i)}),
}
N_STEPS = 24  # communication steps of H; the state is saved at SAVE and restored at RESTORE
H = 0.25
SAVE, RESTORE = 8, 16


class Run:
    """One instance and its schedule, advanced one call at a time."""

    def __init__(self, md, unzipdir, name, i):
        self.md, self.i = md, i
        self.params, self.inputs = CASES[name]
        self.vr = {v.name: v for v in md.modelVariables}
        self.outputs = [v for v in md.modelVariables if v.causality == "output"]
        self.fmu = FMU2Slave(guid=md.guid, unzipDirectory=unzipdir,
                             modelIdentifier=md.coSimulation.modelIdentifier, instanceName=f"{name}{i}")
        self.record = []

    def calls(self):
        """The schedule as a generator: each ``next`` makes one or a few FMI calls."""
        f = self.fmu
        f.instantiate(loggingOn=True)
        yield
        f.setupExperiment(startTime=0.0)
        f.enterInitializationMode()
        for p, value in self.params.items():
            f.setReal([self.vr[p].valueReference], [value(self.i)])
        self._set_inputs(0.0)
        f.exitInitializationMode()
        yield
        saved = None
        k = 0
        while k < N_STEPS:
            t = k * H
            self._set_inputs(t)
            f.doStep(currentCommunicationPoint=t, communicationStepSize=H)
            self._read()
            k += 1
            if k == SAVE and saved is None:
                state = f.getFMUstate()
                saved = bytes(f.serializeFMUstate(state))
                f.freeFMUstate(state)
            elif k == RESTORE and saved is not False:
                state = f.deSerializeFMUstate(saved)
                f.setFMUstate(state)
                f.freeFMUstate(state)
                saved, k = False, SAVE
                self.record.append("restored")
            yield
        f.terminate()
        f.freeInstance()
        yield

    def _set_inputs(self, t):
        for name, u in self.inputs.items():
            self.fmu.setReal([self.vr[name].valueReference], [u(self.i, t)])

    def _read(self):
        row = []
        for v in self.outputs:
            if v.type == "Real":
                row.append(self.fmu.getReal([v.valueReference])[0])
            elif v.type == "Integer":
                row.append(self.fmu.getInteger([v.valueReference])[0])
            else:
                row.append(bool(self.fmu.getBoolean([v.valueReference])[0]))
        self.record.append(row)


def main(path, n_instances, n_rounds):
    gc.enable()
    md = read_model_description(path)
    name = md.coSimulation.modelIdentifier
    unzipdir = extract(path)
    lone = {}
    count = 0
    for i in range(n_instances):
        run = Run(md, unzipdir, name, i)
        for _ in run.calls():
            pass
        count += 1
        lone[i] = run.record
        gc.collect()
    refs_before = _references(md)
    rng = random.Random(1)
    bad, rejected = [], []
    for _ in range(n_rounds):
        runs = [Run(md, unzipdir, name, i) for i in range(n_instances)]
        steps = [r.calls() for r in runs]
        steps.insert(rng.randrange(len(steps) + 1), _bad_instance(md, unzipdir, name, rejected))
        done = set()
        while len(done) < len(steps):
            order = [j for j in range(len(steps)) if j not in done]
            rng.shuffle(order)  # a different interleaving at every call
            for j in order:
                try:
                    next(steps[j])
                except StopIteration:
                    done.add(j)
            gc.collect(1)  # the young generations at every pass, everything once a round
        gc.collect()
        count += n_instances + 1
        bad.append([r.i for r in runs if r.record != lone[r.i]])
    print(json.dumps({"instantiations": count, "differ": bad, "records": len(lone[0]), "rejected": rejected,
                      "references": [refs_before, _references(md)], "sys_path": _path_copies(unzipdir)}))


def _references(md):
    """Reference counts of the FMU script's module dict and slave class (the FMU's Python runs
    in this interpreter): pythonfmu's wrapper over-releases both unless balanced."""
    gc.collect()
    module = sys.modules[_script_module(md)]
    cls = getattr(module, md.coSimulation.modelIdentifier)
    return [sys.getrefcount(vars(module)), sys.getrefcount(cls)]


def _script_module(md):
    return next(name for name, m in sys.modules.items()
                if getattr(m, "__file__", None) and "resources" in m.__file__ and name.startswith("fj_"))


def _path_copies(unzipdir):
    """How often the FMU's resources folder is on sys.path (pythonfmu inserts it per instance)."""
    return sum(1 for p in sys.path if p.startswith(str(unzipdir)))


def _bad_instance(md, unzipdir, name, rejected):
    """An instance whose exitInitializationMode fails; appends what happened to ``rejected``."""
    messages = []

    def logger(component, instance, status, category, message):
        messages.append(message.decode(errors="replace"))

    f = FMU2Slave(guid=md.guid, unzipDirectory=unzipdir, modelIdentifier=md.coSimulation.modelIdentifier,
                  instanceName="bad")
    f.instantiate(loggingOn=True, callbacks=_callbacks(logger))
    yield
    param, value = BAD[name]
    vr = {v.name: v.valueReference for v in md.modelVariables}
    f.setupExperiment(startTime=0.0)
    f.enterInitializationMode()
    f.setReal([vr[param]], [value])
    try:
        f.exitInitializationMode()
        rejected.append("accepted")
    except Exception:  # noqa: BLE001 -- fmpy raises on the error status
        rejected.append(param if any(param in m for m in messages) else "no message")
    yield
    f.freeInstance()


def _callbacks(logger):
    from fmpy import fmi2

    cb = fmi2.fmi2CallbackFunctions()
    cb.logger = fmi2.fmi2CallbackLoggerTYPE(logger)
    cb.allocateMemory = fmi2.defaultCallbacks.allocateMemory
    cb.freeMemory = fmi2.defaultCallbacks.freeMemory
    _callbacks.keep.append(cb)  # alive as long as the process (the FMU holds the pointer)
    return cb


_callbacks.keep = []


if __name__ == "__main__":
    main(sys.argv[1], int(sys.argv[2]), int(sys.argv[3]))
